"""Step 3: the level from the pixel's footprint (see the package's
docstring), picked stochastically between the two around it."""
from .common import STRETCH_ATTRIBUTE


def footprint_level(g, gin, info, position, vz, xi):
    """Step 3: the level from the footprint, picked stochastically between
    the two around it; returns (S_L, P_L across, Y_L, L, P_L up) of the
    pack's layout (the pitches differ for a material addressed per
    crossing: its tiles hold bx x by blocks)."""
    k, r = info.k, info.texels
    bx, by = info.block_grid
    per_repeat = r * info.threads_per_repeat[0]   # level-0 texels per repeat along x
    cam_point = g.node("ShaderNodeVectorTransform", 4, vector_type="POINT",
                       convert_from="WORLD", convert_to="CAMERA")
    g.feed(cam_point.inputs["Vector"], position)
    distance = g.vmath("LENGTH", cam_point.outputs["Vector"], column=5)
    cos_view = g.math("MAXIMUM", g.math("ABSOLUTE", vz, column=5), 0.02, column=5)
    # World units per UV here: the face's own (the mesh attribute Apply
    # writes), else (0: no attribute, or a face without UV area) the input.
    local = g.node("ShaderNodeAttribute", 4, attribute_type="GEOMETRY",
                   attribute_name=STRETCH_ATTRIBUTE, label="world per UV, per face")
    missing = g.math("LESS_THAN", local.outputs["Fac"], 1e-12, column=5)
    world_per_uv = g.math("MULTIPLY_ADD", missing, gin["World per UV"], local.outputs["Fac"],
                          column=5)
    texels_per_world = g.math("DIVIDE", g.math("MULTIPLY", gin["Repeats per UV"],
                                               float(per_repeat), column=5), world_per_uv,
                              column=5)
    footprint = g.math("MULTIPLY", g.math("MULTIPLY", distance, gin["Pixel angle"], column=6),
                       texels_per_world, column=6)
    footprint = g.math("DIVIDE", footprint, g.math("SQRT", cos_view, column=6), column=6)
    footprint = g.math("DIVIDE", footprint, g.math("SQRT", g.math("MAXIMUM", gin["Samples"], 1.0,
                                                                  column=6), column=6), column=6)
    footprint = g.math("MULTIPLY", footprint, gin["Footprint scale"], column=7)
    level = g.math("MINIMUM", g.math("LOGARITHM", g.math("MAXIMUM", footprint, 1.0, column=7), 2.0,
                                     column=7), float(info.levels - 1), column=7)
    level = g.math("MINIMUM", g.math("FLOOR", g.math("ADD", level, xi, column=8), column=8),
                   float(info.levels - 1), column=8)
    half_pow = g.math("POWER", 0.5, level, column=8)
    side_texels = g.math("MULTIPLY", half_pow, float(r), column=9)           # S_L
    pitch = g.math("ADD", side_texels, 2.0, column=9) if bx == 1 else \
        g.math("MULTIPLY_ADD", side_texels, float(bx), 2.0, column=9)        # P_L across
    pitch_up = pitch if by == bx else \
        g.math("MULTIPLY_ADD", side_texels, float(by), 2.0, column=9)        # P_L up
    y_level = g.math("MULTIPLY", g.math("ADD", g.math("MULTIPLY", g.math(
        "SUBTRACT", 1.0, half_pow, column=9), 2.0 * r * by, column=9), g.math(
        "MULTIPLY", level, 2.0, column=9), column=9), 2.0 * k, column=10)   # Y_L
    return side_texels, pitch, y_level, level, pitch_up
