"""Apply material: a cloth material (docs/material-format.md) on any mesh
with a UV map, lit live by the scene's sun and point lights, with plain
nodes that Cycles, Eevee and the viewport's Material Preview all run.

Nothing is stored per face. Per shading point the node group computes:
  1. the frame: N the true normal (Geometry's, unflipped with Backfacing),
     T the UV map's tangent made orthogonal to N, B = N x T; the directions
     toward the eye and toward each light in that frame;
  2. where in the repeat: the UV map x repeats per UV, its fraction;
  3. the level from the pixel's footprint (below);
  4. the view node, level and texel, each picked at random with the
     probabilities of clothbake's bilinear / trilinear weights (a White
     Noise of the position: every sample of a pixel hits another point), so
     that one read of the Blender images (clothbake.core.material_pack)
     per component replaces 4 views x 2 levels x 4 texels; the pixel's
     samples average the blend ("stochastic texture filtering"). Every
     image is read with Closest: nothing bleeds between tiles, and Eevee's
     GPU mip-maps (which an atlas cannot use) never come into play;
  5. per light, its direction's light factors (resampled densely in the
     pack, so a stochastic bilinear read stands in for clothbake's
     Catmull-Rom), times its irradiance: W_k = sum_l E_l F_k(v, l);
  6. L = max(0, sum_k C_k W_k), alpha A.
Route "exact": Emission(L) + Transparent(1 - A), the reference renderer's
sum (no shadows from other objects, no cloth-on-cloth shadowing).
Route "cycles-lit": lights on the viewer's side of the surface go through
a Diffuse closure whose colour is pi L_front / sum_l E_l cos_l, so that
Cycles (or Eevee) adds its own shadows and the light's live power; lights
behind the surface (light through the cloth) stay Emission.

The lights reach the nodes by drivers on the group node's inputs, reading
each light object's world transform, colour, power and render visibility
(BLENDER_NOTES.md: simple expressions, no script auto-run needed). A
Texture Coordinate node set to an empty would need one empty per light
kept aligned with it; drivers read the light itself.

The footprint: the distance to the camera (the point in camera space) x
the camera's pixel angle (sensor width / lens / pixels, a driver on the
scene's camera and resolution), stretched by 1 / sqrt(cos) of the view's
tilt, in level-0 texels through the object's world units per UV (the mean
over its evaluated mesh, measured on Apply: where the UV map stretches the
weave locally, the level follows the mean), divided by sqrt(samples)
(Cycles' samples: each sample prefilters its stratum of the pixel).
"""
import math
import os

import bpy
import numpy as np

from ..core.errors import ClothbakeError
from ..core.material_pack import HORIZON, pack_material, read_material
from . import patch_nodes
from .apply import load_data_image
from .graph import Graph

ROUTES = ("exact", "cycles-lit")


# --- what the material reads from the mesh ---------------------------------

def uv_map_name(obj):
    """The UV map a render reads (active for render, else active); None."""
    layers = obj.data.uv_layers
    if not len(layers):
        return None
    for layer in layers:
        if layer.active_render:
            return layer.name
    return layers.active.name if layers.active else layers[0].name


def world_per_uv(obj, uv_name, depsgraph):
    """World units per UV unit over the evaluated mesh: sqrt(world area /
    UV area). Raises ClothbakeError when the UV map has no area."""
    ob_eval = obj.evaluated_get(depsgraph)
    mesh = ob_eval.to_mesh()
    try:
        mesh.calc_loop_triangles()
        n = len(mesh.loop_triangles)
        if n == 0:
            raise ClothbakeError(f"mesh '{obj.name}' has no faces after its modifiers")
        co = np.empty(len(mesh.vertices) * 3)
        mesh.vertices.foreach_get("co", co)
        co = co.reshape(-1, 3)
        m = np.array(ob_eval.matrix_world)
        co = co @ m[:3, :3].T + m[:3, 3]
        tri_v = np.empty(n * 3, np.int64)
        mesh.loop_triangles.foreach_get("vertices", tri_v)
        tri_l = np.empty(n * 3, np.int64)
        mesh.loop_triangles.foreach_get("loops", tri_l)
        layer = mesh.uv_layers.get(uv_name) or mesh.uv_layers.active
        if layer is None:
            raise ClothbakeError(f"mesh '{obj.name}' has no UV map after its modifiers")
        uv = np.empty(len(mesh.loops) * 2)
        layer.data.foreach_get("uv", uv)
        uv = uv.reshape(-1, 2)
        p = co[tri_v.reshape(-1, 3)]
        t = uv[tri_l.reshape(-1, 3)]
        area_w = 0.5 * np.linalg.norm(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), axis=1).sum()
        e1, e2 = t[:, 1] - t[:, 0], t[:, 2] - t[:, 0]
        area_uv = 0.5 * np.abs(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]).sum()
    finally:
        ob_eval.to_mesh_clear()
    if not area_uv > 0:
        raise ClothbakeError(f"mesh '{obj.name}': its UV map '{uv_name}' has no area "
                             "(every face maps to a point or a line); unwrap it (UV > Unwrap)")
    return math.sqrt(area_w / area_uv)


def scene_lights(scene):
    """(sun and point light objects, notes about the others)."""
    lights, notes = [], []
    for obj in scene.objects:
        if obj.type != "LIGHT":
            continue
        if obj.data.type in ("SUN", "POINT"):
            lights.append(obj)
        else:
            notes.append(f"light '{obj.name}' is a {obj.data.type.lower()} light; the material "
                         "reads sun and point lights only")
    lights.sort(key=lambda o: o.name)
    return lights, notes


def _cloth_settings(obj):
    s = getattr(obj, "clothbake", None)
    if s is not None and hasattr(s, "repeats_per_uv"):
        return float(s.repeats_per_uv), float(s.thickness_world)
    return float(obj.get("clothbake_repeats_per_uv", 40.0)), \
        float(obj.get("clothbake_thickness_world", 0.01))


# --- the node group ----------------------------------------------------------

def _inputs(group, n_lights):
    new = group.inputs.new
    new("NodeSocketVector", "UV")
    new("NodeSocketVector", "Tangent")
    for name, value in (("Repeats per UV", 40.0), ("World per UV", 1.0),
                        ("Pixel angle", 1e-3), ("Samples", 16.0), ("Footprint scale", 1.0)):
        new("NodeSocketFloat", name).default_value = value
    for l in range(n_lights):
        new("NodeSocketVector", f"Light {l} vector")
        new("NodeSocketVector", f"Light {l} irradiance")
        new("NodeSocketFloat", f"Light {l} point")


GROUP_VERSION = 1


def build_group(name, info, pack, coeff_image, light_image, n_lights, route):
    """The node group, reused when one of this name was built from the same
    pack; else built anew and every material of the old one moved onto it
    (removing it would leave other objects' group nodes empty: a black
    plane once the sphere beside it was applied)."""
    key = f"{GROUP_VERSION} {pack.folder} {pack.rank} {pack.dense} {n_lights} {route} " \
          f"{pack.width}x{pack.height}"
    old = bpy.data.node_groups.get(name)
    if old is not None and old.get("clothbake_key") == key:
        return old
    group = bpy.data.node_groups.new(name, "ShaderNodeTree")
    group["clothbake_key"] = key
    _inputs(group, n_lights)
    group.outputs.new("NodeSocketShader", "Shader")
    group.outputs.new("NodeSocketColor", "Color")
    group.outputs.new("NodeSocketFloat", "Alpha")
    g = Graph(group)
    gin = g.node("NodeGroupInput", 0).outputs
    K, R, M = info.k, info.texels, pack.dense
    Q = M + 2

    # 1. Frame and directions.
    geo = g.node("ShaderNodeNewGeometry", 0)
    facing = geo.outputs["Normal"]                      # toward the viewer (Cycles flips it)
    flip = g.math("MULTIPLY_ADD", geo.outputs["Backfacing"], -2.0, 1.0, column=1)
    normal = g.scale(facing, flip, 1)                   # the mesh's own side
    t_in = gin["Tangent"]
    tangent = g.vmath("NORMALIZE", g.vmath("SUBTRACT", t_in, g.scale(
        normal, g.vmath("DOT_PRODUCT", normal, t_in, column=1), 1), column=1), column=1)
    bitangent = g.vmath("CROSS_PRODUCT", normal, tangent, column=2)

    def local(d, column):
        return (g.vmath("DOT_PRODUCT", d, tangent, column=column),
                g.vmath("DOT_PRODUCT", d, bitangent, column=column),
                g.vmath("DOT_PRODUCT", d, normal, column=column))

    def horizon(u, v, column):
        """The horizon warp of the material's light map (material_pack):
        the diamond's radius rho goes to 1 - sqrt(1 - rho)."""
        a = g.math("MULTIPLY_ADD", u, 2.0, -1.0, column=column)
        b = g.math("MULTIPLY_ADD", v, 2.0, -1.0, column=column)
        px = g.math("MULTIPLY", g.math("ADD", a, b, column=column), 0.5, column=column)
        py = g.math("MULTIPLY", g.math("SUBTRACT", a, b, column=column), 0.5, column=column)
        rho = g.math("ADD", g.math("ABSOLUTE", px, column=column),
                     g.math("ABSOLUTE", py, column=column), column=column)
        warped = g.math("SUBTRACT", 1.0, g.math("SQRT", g.math("SUBTRACT", 1.0, g.math(
            "MINIMUM", rho, 1.0, column=column), column=column, clamp=True), column=column),
            column=column)
        scale = g.math("DIVIDE", warped, g.math("MAXIMUM", rho, 1e-12, column=column),
                       column=column + 1)
        px = g.math("MULTIPLY", px, scale, column=column + 1)
        py = g.math("MULTIPLY", py, scale, column=column + 1)
        return (g.math("MULTIPLY_ADD", g.math("ADD", px, py, column=column + 1), 0.5, 0.5,
                       column=column + 1, clamp=True),
                g.math("MULTIPLY_ADD", g.math("SUBTRACT", px, py, column=column + 1), 0.5, 0.5,
                       column=column + 1, clamp=True))

    def hemi(x, y, z, column):
        l1 = g.math("MAXIMUM", g.math("ADD", g.math("ADD", g.math("ABSOLUTE", x, column=column),
                                                    g.math("ABSOLUTE", y, column=column),
                                                    column=column),
                                      g.math("ABSOLUTE", z, column=column), column=column),
                    1e-20, column=column)
        px = g.math("DIVIDE", x, l1, column=column + 1)
        py = g.math("DIVIDE", y, l1, column=column + 1)
        u = g.math("MULTIPLY_ADD", g.math("ADD", px, py, column=column + 1), 0.5, 0.5,
                   column=column + 1, clamp=True)
        v = g.math("MULTIPLY_ADD", g.math("SUBTRACT", px, py, column=column + 1), 0.5, 0.5,
                   column=column + 1, clamp=True)
        return u, v

    position = geo.outputs["Position"]
    vx, vy, vz = local(geo.outputs["Incoming"], 2)
    view_side = g.math("LESS_THAN", vz, 0.0, column=3)
    vu, vv = hemi(vx, vy, vz, 3)

    # Random numbers per shading point (two White Noise nodes, 6 channels).
    def noise(offset, column):
        n = g.node("ShaderNodeTexWhiteNoise", column, noise_dimensions="3D")
        g.feed(n.inputs["Vector"], g.vmath("ADD", position, offset, column=column))
        return g.separate(n.outputs["Color"], column=column) + (n.outputs["Value"],)

    xi1, xi2, xi3, xi7 = noise((0.0, 0.0, 0.0), 4)
    xi4, xi5, xi6, _ = noise((17.13, -3.71, 9.29), 4)

    def pick(coord, nodes, xi, column):
        """Node floor(coord (nodes - 1) + xi), at most nodes - 1: node i0 + 1
        with probability frac, the bilinear weight."""
        return g.math("MINIMUM", g.math("FLOOR", g.math("MULTIPLY_ADD", coord, float(nodes - 1),
                                                        xi, column=column), column=column),
                      float(nodes - 1), column=column)

    vi = pick(vu, K, xi1, 5)
    vj = pick(vv, K, xi2, 5)
    view_row = g.math("MULTIPLY_ADD", view_side, float(K), vj, column=6)   # side K + j

    # 3. Level from the footprint.
    cam_point = g.node("ShaderNodeVectorTransform", 4, vector_type="POINT",
                       convert_from="WORLD", convert_to="CAMERA")
    g.feed(cam_point.inputs["Vector"], position)
    distance = g.vmath("LENGTH", cam_point.outputs["Vector"], column=5)
    cos_view = g.math("MAXIMUM", g.math("ABSOLUTE", vz, column=5), 0.02, column=5)
    texels_per_world = g.math("DIVIDE", g.math("MULTIPLY", gin["Repeats per UV"], float(R),
                                               column=5), gin["World per UV"], column=5)
    footprint = g.math("MULTIPLY", g.math("MULTIPLY", distance, gin["Pixel angle"], column=6),
                       texels_per_world, column=6)
    footprint = g.math("DIVIDE", footprint, g.math("SQRT", cos_view, column=6), column=6)
    footprint = g.math("DIVIDE", footprint, g.math("SQRT", g.math("MAXIMUM", gin["Samples"], 1.0,
                                                                  column=6), column=6), column=6)
    footprint = g.math("MULTIPLY", footprint, gin["Footprint scale"], column=7)
    level = g.math("MINIMUM", g.math("LOGARITHM", g.math("MAXIMUM", footprint, 1.0, column=7), 2.0,
                                     column=7), float(info.levels - 1), column=7)
    level = g.math("MINIMUM", g.math("FLOOR", g.math("ADD", level, xi3, column=8), column=8),
                   float(info.levels - 1), column=8)
    half_pow = g.math("POWER", 0.5, level, column=8)
    side_texels = g.math("MULTIPLY", half_pow, float(R), column=9)           # S_L
    pitch = g.math("ADD", side_texels, 2.0, column=9)                        # P_L
    y_level = g.math("MULTIPLY", g.math("ADD", g.math("MULTIPLY", g.math(
        "SUBTRACT", 1.0, half_pow, column=9), 2.0 * R, column=9), g.math(
        "MULTIPLY", level, 2.0, column=9), column=9), 2.0 * K, column=10)   # Y_L

    # 2 + 4. The texel (periodic, stochastic bilinear) and the component-0 address.
    ux, uy, _ = g.separate(g.scale(gin["UV"], gin["Repeats per UV"], 6), 7)

    def texel(coord, xi, column):
        t = g.math("MULTIPLY", g.math("FRACT", coord, column=column), side_texels, column=column)
        # pixel centre of texel floor(t - 0.5 + xi), one past the gutter
        return g.math("ADD", g.math("FLOOR", g.math("ADD", t, g.math("SUBTRACT", xi, 0.5,
                                                                     column=column),
                                                    column=column), column=column), 1.5,
                      column=column)

    tx = texel(ux, xi4, 10)
    ty = texel(uy, xi5, 10)
    px0 = g.math("MULTIPLY_ADD", vi, pitch, tx, column=11)
    py0 = g.math("ADD", g.math("MULTIPLY_ADD", view_row, pitch, ty, column=11), y_level, column=11)
    uv0 = g.combine(g.math("DIVIDE", px0, float(pack.width), column=12),
                    g.math("DIVIDE", py0, float(pack.height), column=12), 0.0, column=12)
    # component k at + (k % per_row) K P_L across and (k // per_row) bands up
    step = g.combine(g.math("MULTIPLY", pitch, float(K) / pack.width, column=12),
                     float(pack.band) / pack.height, 0.0, column=12)

    # 5. Lights: direction, irradiance and the light-factor address, per light.
    lit = route == "cycles-lit"
    rank = pack.rank
    per_light = []   # (light-factor uv, [(irradiance, accumulator index)])
    denom = None
    col = 13
    for l in range(n_lights):
        vec, irr, is_point = (gin[f"Light {l} vector"], gin[f"Light {l} irradiance"],
                              gin[f"Light {l} point"])
        to_point = g.vmath("SUBTRACT", vec, position, column=col)
        direction = g.vmath("NORMALIZE", g.vmath("ADD", vec, g.scale(g.vmath(
            "SUBTRACT", to_point, vec, column=col), is_point, col), column=col), column=col)
        r2 = g.math("MAXIMUM", g.vmath("DOT_PRODUCT", to_point, to_point, column=col), 1e-12,
                    column=col)
        atten = g.math("ADD", g.math("MULTIPLY", is_point, g.math("SUBTRACT", g.math(
            "DIVIDE", 1.0, r2, column=col), 1.0, column=col), column=col), 1.0, column=col)
        irradiance = _mix(g, "ADD", BLACK, irr, atten, col)
        lx, ly, lz = local(direction, col + 1)
        light_side = g.math("LESS_THAN", lz, 0.0, column=col + 1)
        lu, lv = hemi(lx, ly, lz, col + 1)
        if info.light_map == HORIZON:
            lu, lv = horizon(lu, lv, col + 2)
        la = pick(lu, M, xi6, col + 3)
        lb = pick(lv, M, xi7, col + 3)
        # tile of (view_side, i, j), group 0, light side; pixel centre of (a, b)
        lpx = g.math("ADD", g.math("MULTIPLY", g.math("MULTIPLY_ADD", vi, 2.0, light_side,
                                                      column=col + 4), float(Q), column=col + 4),
                     g.math("ADD", la, 1.5, column=col + 4), column=col + 4)
        lpy = g.math("ADD", g.math("MULTIPLY", view_row, float(Q), column=col + 4),
                     g.math("ADD", lb, 1.5, column=col + 4), column=col + 4)
        luv = g.combine(g.math("DIVIDE", lpx, float(pack.light_width), column=col + 5),
                        g.math("DIVIDE", lpy, float(pack.light_height), column=col + 5), 0.0,
                        column=col + 5)
        if lit:
            cos_l = g.vmath("DOT_PRODUCT", direction, facing, column=col + 5)
            front = g.math("GREATER_THAN", cos_l, 0.0, column=col + 5)
            e_front = _mix(g, "ADD", BLACK, irradiance, front, col + 5)
            e_back = _mix(g, "SUBTRACT", irradiance, e_front, 1.0, col + 5)
            term = _mix(g, "ADD", BLACK, e_front, g.math("MAXIMUM", cos_l, 0.0, column=col + 5),
                        col + 5)
            denom = term if denom is None else _mix(g, "ADD", denom, term, 1.0, col + 6)
            per_light.append((luv, [(e_front, 0), (e_back, 1)]))
        else:
            per_light.append((luv, [(irradiance, 0)]))
        col += 7

    # 6. Per group of four components: each light's factors, then the four
    # coefficients, summed at once. Nodes are made in this order because
    # Cycles compiles them in creation order and keeps a value on its SVM
    # stack (255 floats) until its last user: all W_k first, then all C_k,
    # overflowed the stack at rank 24 on the cycles-lit route ("out of SVM
    # stack space": a black cloth).
    sums = [None, None]        # radiance (front when lit), radiance from behind
    alpha = None
    for gi in range(pack.groups):
        factors = []
        for l, (luv, _) in enumerate(per_light):
            tex = g.node("ShaderNodeTexImage", col, image=light_image,
                         interpolation="Closest", extension="EXTEND",
                         label=f"light {l} factors {4 * gi}..{4 * gi + 3}")
            g.feed(tex.inputs["Vector"], g.vmath("ADD", luv, (gi * 2.0 * K * Q / pack.light_width,
                                                              0.0, 0.0), column=col))
            r, gg, b = g.separate(tex.outputs["Color"], column=col + 1)
            factors.append((r, gg, b, tex.outputs["Alpha"]))
        for c in range(4):
            kk = 4 * gi + c
            if kk >= rank:
                break
            where = uv0
            if kk:
                n = g.node("ShaderNodeVectorMath", col + 2, operation="MULTIPLY_ADD")
                g.feed(n.inputs[0], step)
                g.feed(n.inputs[1], (float(kk % pack.per_row), float(kk // pack.per_row), 0.0))
                g.feed(n.inputs[2], uv0)
                where = n.outputs["Vector"]
            tex = g.node("ShaderNodeTexImage", col + 3, image=coeff_image,
                         interpolation="Closest", extension="EXTEND", label=f"component {kk}")
            g.feed(tex.inputs["Vector"], where)
            if kk == 0:
                alpha = tex.outputs["Alpha"]
            weights = [None, None]
            for (luv, parts), f in zip(per_light, factors):
                for e, which in parts:
                    weights[which] = _mix(g, "ADD", weights[which] or BLACK, e, f[c], col + 4)
            for which in (0, 1):
                if weights[which] is not None:
                    term = _mix(g, "MULTIPLY", tex.outputs["Color"], weights[which], 1.0, col + 5)
                    sums[which] = term if sums[which] is None else \
                        _mix(g, "ADD", sums[which], term, 1.0, col + 5)
        col += 6
    radiance, radiance_back = sums
    zero = (0.0, 0.0, 0.0)
    radiance = g.vmath("MAXIMUM", radiance if radiance is not None else zero, zero,
                       column=col + 4)

    out = g.node("NodeGroupOutput", col + 8)
    transparent = g.node("ShaderNodeBsdfTransparent", col + 6)
    g.feed(transparent.inputs["Color"], g.math("SUBTRACT", 1.0, alpha, column=col + 5,
                                               clamp=True))
    if lit:
        radiance_back = g.vmath("MAXIMUM", radiance_back if radiance_back is not None else zero,
                                zero, column=col + 4)
        safe = g.vmath("MAXIMUM", denom if denom is not None else zero, (1e-6,) * 3,
                       column=col + 4)
        colour = g.scale(g.vmath("DIVIDE", radiance, safe, column=col + 5), math.pi, col + 5)
        diffuse = g.node("ShaderNodeBsdfDiffuse", col + 6)
        g.feed(diffuse.inputs["Color"], colour)
        emission = g.node("ShaderNodeEmission", col + 6)
        g.feed(emission.inputs["Color"], radiance_back)
        add1 = g.node("ShaderNodeAddShader", col + 7)
        g.links.new(diffuse.outputs[0], add1.inputs[0])
        g.links.new(emission.outputs[0], add1.inputs[1])
        color_out = g.vmath("ADD", radiance, radiance_back, column=col + 5)
    else:
        emission = g.node("ShaderNodeEmission", col + 6)
        g.feed(emission.inputs["Color"], radiance)
        add1 = emission
        color_out = radiance
    add = g.node("ShaderNodeAddShader", col + 7)
    g.links.new(add1.outputs[0], add.inputs[0])
    g.links.new(transparent.outputs[0], add.inputs[1])
    g.links.new(add.outputs[0], out.inputs["Shader"])
    g.links.new(color_out, out.inputs["Color"])
    g.links.new(alpha, out.inputs["Alpha"])
    old = bpy.data.node_groups.get(name)
    if old is not None and old != group:
        old.user_remap(group)
        bpy.data.node_groups.remove(old)
        group.name = name
    return group


BLACK = (0.0, 0.0, 0.0, 1.0)


def _mix(g, blend, a, b, fac, column):
    """Colour a (blend) b by fac, factor and result unclamped (Blender 3.4's
    Mix node; the legacy MixRGB clamps fac in Eevee). Colours throughout:
    a float or vector into a colour socket makes Cycles insert a conversion
    node after all others, which delays its users to a later compile pass
    while every ready texture read is compiled and held on the 255-float SVM
    stack ("out of SVM stack space": a black cloth at rank 24)."""
    n = g.node("ShaderNodeMix", column, data_type="RGBA", blend_type=blend,
               clamp_factor=False, clamp_result=False)
    g.feed(n.inputs[0], fac)
    g.feed(n.inputs[6], a)
    g.feed(n.inputs[7], b)
    return n.outputs[2]


# --- drivers -----------------------------------------------------------------

def _driver(socket, index, expression, variables):
    """variables: (name, kind, target id, id_type, data_path or transform)."""
    fc = socket.driver_add("default_value", index) if index is not None else \
        socket.driver_add("default_value")
    drv = fc.driver
    drv.type = "SCRIPTED"
    for v in list(drv.variables):
        drv.variables.remove(v)
    for name, kind, target_id, id_type, what in variables:
        var = drv.variables.new()
        var.name = name
        if kind == "TRANSFORMS":
            var.type = "TRANSFORMS"
            t = var.targets[0]
            t.id = target_id
            t.transform_type = what
            t.transform_space = "WORLD_SPACE"
            t.rotation_mode = "QUATERNION"
        else:
            var.type = "SINGLE_PROP"
            t = var.targets[0]
            t.id_type = id_type
            t.id = target_id
            t.data_path = what
    drv.expression = expression
    return fc


def _drive_light(node, l, light_obj):
    vector = node.inputs[f"Light {l} vector"]
    if light_obj.data.type == "SUN":
        rot = [(c, "TRANSFORMS", light_obj, None, f"ROT_{c.upper()}") for c in "wxyz"]
        for axis, expr in enumerate(("2*(x*z+w*y)", "2*(y*z-w*x)", "1-2*(x*x+y*y)")):
            _driver(vector, axis, expr, rot)
        per = 1.0
    else:
        for axis, c in enumerate("XYZ"):
            _driver(vector, axis, "p", [("p", "TRANSFORMS", light_obj, None, f"LOC_{c}")])
        per = 1.0 / (4.0 * math.pi)  # Blender's point watts -> irradiance at 1 unit (scene.py)
    node.inputs[f"Light {l} point"].default_value = 0.0 if light_obj.data.type == "SUN" else 1.0
    irr = node.inputs[f"Light {l} irradiance"]
    for axis in range(3):
        _driver(irr, axis, f"c*e*{per!r}*(1-h)",
                [("c", "SINGLE_PROP", light_obj, "OBJECT", f"data.color[{axis}]"),
                 ("e", "SINGLE_PROP", light_obj, "OBJECT", "data.energy"),
                 ("h", "SINGLE_PROP", light_obj, "OBJECT", "hide_render")])


def _drive_camera(node, scene):
    _driver(node.inputs["Pixel angle"], None, "w/f/(x*p/100)",
            [("w", "SINGLE_PROP", scene, "SCENE", "camera.data.sensor_width"),
             ("f", "SINGLE_PROP", scene, "SCENE", "camera.data.lens"),
             ("x", "SINGLE_PROP", scene, "SCENE", "render.resolution_x"),
             ("p", "SINGLE_PROP", scene, "SCENE", "render.resolution_percentage")])
    _driver(node.inputs["Samples"], None, "s",
            [("s", "SINGLE_PROP", scene, "SCENE", "cycles.samples")])


# --- Apply --------------------------------------------------------------------

def apply_material(obj, folder, route="exact", rank=None, scene=None, depsgraph=None):
    """Puts the material in `folder` on mesh object `obj`. Returns (material,
    notes). Raises ClothbakeError (no traceback) for a non-mesh, a mesh with
    no UV map, or a broken material folder, before changing anything."""
    if obj is None or obj.type != "MESH":
        what = "nothing" if obj is None else f"object '{obj.name}' ({obj.type.lower()})"
        raise ClothbakeError(f"{what} is not a mesh; select a mesh object with a UV map")
    if route not in ROUTES:
        raise ClothbakeError(f"must be one of {', '.join(ROUTES)}", "", "route")
    uv_name = uv_map_name(obj)
    if uv_name is None:
        raise ClothbakeError(f"object '{obj.name}': its mesh has no UV map; add one (Edit Mode, "
                             "UV > Unwrap) so the weave has a place on it")
    scene = scene or bpy.context.scene
    depsgraph = depsgraph or bpy.context.evaluated_depsgraph_get()
    info = read_material(folder)
    scale = world_per_uv(obj, uv_name, depsgraph)
    pack = pack_material(info, rank)
    coeff = load_data_image(pack.coefficients, half=True)
    lights_img = load_data_image(pack.light_factors, half=False)
    lights, notes = scene_lights(scene)
    if not lights:
        notes.append("the scene has no sun or point light: the cloth renders black until one "
                     "is added and the material applied again")

    key = os.path.basename(pack.folder)
    group = build_group(f"clothbake material {info.name or 'cloth'} {key} {len(lights)}L {route}",
                        info, pack, coeff, lights_img, len(lights), route)

    name = f"clothbake material {obj.name}"
    material = bpy.data.materials.get(name) or bpy.data.materials.new(name)
    material.use_nodes = True
    tree = material.node_tree
    if tree.animation_data:
        tree.animation_data_clear()
    tree.nodes.clear()
    node = tree.nodes.new("ShaderNodeGroup")
    node.node_tree = group
    node.location = (0, 0)
    uv = tree.nodes.new("ShaderNodeUVMap")
    uv.uv_map = uv_name
    uv.location = (-300, 100)
    tangent = tree.nodes.new("ShaderNodeTangent")
    tangent.direction_type = "UV_MAP"
    tangent.uv_map = uv_name
    tangent.location = (-300, -100)
    tree.links.new(uv.outputs["UV"], node.inputs["UV"])
    tree.links.new(tangent.outputs["Tangent"], node.inputs["Tangent"])
    repeats, thickness = _cloth_settings(obj)
    node.inputs["Repeats per UV"].default_value = repeats
    node.inputs["World per UV"].default_value = scale
    out = tree.nodes.new("ShaderNodeOutputMaterial")
    out.location = (300, 0)
    tree.links.new(node.outputs["Shader"], out.inputs["Surface"])
    _drive_camera(node, scene)
    for l, light in enumerate(lights):
        _drive_light(node, l, light)
    material.blend_method = "HASHED"        # Eevee: stochastic alpha, converges with samples
    if hasattr(material, "shadow_method"):
        material.shadow_method = "HASHED" if route == "cycles-lit" else "NONE"
    material.use_backface_culling = False
    material["clothbake_material"] = info.folder
    material["clothbake_route"] = route

    obj.data.materials.clear()
    obj.data.materials.append(material)
    obj["clothbake_material"] = info.folder
    # A per-scene lookup's patch modifier (apply.py) means nothing to a
    # material, and its geometry-nodes output left Eevee's viewport without
    # the UV map's tangents: a black plane in Material Preview.
    patch_nodes.detach(obj)

    # The weave's depth in the material against this object's (docs/material-format.md).
    mm_along = info.repeat_mm[0] * repeats / scale
    if thickness > 0 and mm_along > 0:
        object_depth = info.repeat_mm[2] / thickness / mm_along
        if abs(object_depth / info.depth_scale - 1.0) > 0.05:
            notes.append(f"object '{obj.name}': its depth scale {object_depth:.3g} (thickness "
                         f"{thickness:g}, {repeats:g} repeats per UV, {scale:.3g} world units per "
                         f"UV) differs from the material's {info.depth_scale:.3g} by more than 5%: "
                         "the weave is shaded as the material's thickness")
    if pack.rank < max(info.ranks):
        notes.append(f"{pack.rank} of up to {max(info.ranks)} components evaluated")
    return material, notes
