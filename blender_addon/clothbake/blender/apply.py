"""Apply: put a baked lookup on a mesh with plain Cycles nodes (no OSL).

What it writes onto the mesh: per face, world-space vectors describing the
face's bilinear patch, its UV Jacobian and its square in the atlas
(clothbake.core.layout.face_attributes). A material whose node group does,
per shading point (the arithmetic of layout.patch_parameters and
layout.frame_from_attributes, which the tests check in plain Python):
  1. the patch parameters (s, t) where the view ray through the hit point
     meets the quad's bilinear patch, exactly as clothbake's renderer
     intersects it (Blender's two triangles per quad parameterise a
     non-parallelogram differently, which would shift the weave);
  2. the local frame there: N along dP/ds x dP/dt, T along dP/du of the
     weave's UV map in the tangent plane, B = N x T, and the view direction
     d = (I.T, I.B, I.N), I the Incoming vector (toward the camera). N is the
     patch's, never flipped toward the viewer, so back faces read side 1;
  3. side = d.z < 0; the hemi-octahedral (u, v) of d; grid position
     (u, v)(K - 1); the four nodes i0..i0+1, j0..j0+1 and weights fx, fy;
  4. per side, four Image Texture reads of the atlas at tile (i, j):
     ((i + u_tile) / K, (K - 1 - j + v_tile) / K), blended bilinearly
     (colour and alpha alike); the side picked by `side`;
  5. Emission(RGB) + Transparent(1 - A): the lookup's RGB is premultiplied,
     so this is exactly "RGB + (1 - A) x behind", the same as Emission of
     RGB / A mixed with Transparent by A, without dividing by A.
Linear filtering reads at most half a texel outside a face's square, which
the one-texel gutter holds (copies of edge texels), so directions never
bleed into each other.
"""
import os

import bpy

from ..core import directions
from ..core.errors import ClothbakeError
from ..core.layout import corner_frames, face_attributes
from ..core.manifest import read_manifest
from .graph import Graph

ATTR_PREFIX = "clothbake_"
FACE_ATTRS = ("p0", "e", "f", "g", "ue", "uf", "ug", "square")


def _weave_uv_layer(mesh):
    """The UV map the weave (and so the frame) follows: the render-active one."""
    for layer in mesh.uv_layers:
        if layer.active_render:
            return layer
    return mesh.uv_layers[0] if len(mesh.uv_layers) else None


def _count(n, noun):
    return f"{n} {noun}" + ("" if n == 1 else "s")


def pick_lookup_object(lookup, obj):
    """The lookup object for a Blender object: by the index stored on import,
    else by name, else the only one."""
    index = obj.get("clothbake_object_index")
    if isinstance(index, int) and 0 <= index < len(lookup.objects):
        return lookup.objects[index]
    named = lookup.object_named(obj.get("clothbake_name", obj.name))
    if named is not None:
        return named
    if len(lookup.objects) == 1:
        return lookup.objects[0]
    names = ", ".join(f"'{o.name}'" for o in lookup.objects)
    raise ClothbakeError(f"object '{obj.name}' matches none of the lookup's objects ({names})",
                         os.path.join(lookup.folder, "manifest.json"), "objects")


def write_mesh_layers(obj, lookup, lookup_object):
    """Writes the per-face attributes the shader reads (clothbake.core.layout
    face_attributes, world space). Refuses meshes that do not match the
    lookup (face count, non-quads, no UVs) before changing anything."""
    mesh = obj.data
    manifest = os.path.join(lookup.folder, "manifest.json")
    if len(mesh.polygons) != lookup_object.quads:
        raise ClothbakeError(f"mesh '{obj.name}' has {_count(len(mesh.polygons), 'face')}; the "
                             f"lookup's object '{lookup_object.name}' has "
                             f"{_count(lookup_object.quads, 'quad')} "
                             "(was it baked from another mesh?)", manifest,
                             f"objects[{lookup_object.index}].quads")
    bad = [p.index for p in mesh.polygons if p.loop_total != 4]
    if bad:
        raise ClothbakeError(f"mesh '{obj.name}' has {_count(len(bad), 'face')} that are not quads "
                             f"(first: face {bad[0]}, {mesh.polygons[bad[0]].loop_total} corners)")
    weave = _weave_uv_layer(mesh)
    if weave is None:
        raise ClothbakeError(f"mesh '{obj.name}' has no UV map; the weave follows the UVs")

    to_world = obj.matrix_world
    tw, th = lookup_object.tile_width, lookup_object.tile_height
    values = {name: [] for name in FACE_ATTRS}
    degenerate = 0
    for poly in mesh.polygons:
        loops = list(poly.loop_indices)
        corners = [tuple(to_world @ mesh.vertices[mesh.loops[li].vertex_index].co)
                   for li in loops]
        uvs = [tuple(weave.data[li].uv) for li in loops]
        rect = lookup_object.rects[poly.index]
        if corner_frames(corners, uvs) is None:
            degenerate += 1
            rect = (0, 0, 0)  # reads the zero texel at the tile's corner: transparent
        attrs = face_attributes(corners, uvs, rect, tw, th)
        for name in FACE_ATTRS:
            values[name].extend(attrs[name])
    for name in FACE_ATTRS:
        full = ATTR_PREFIX + name
        if full in mesh.attributes:
            mesh.attributes.remove(mesh.attributes[full])
        mesh.attributes.new(full, "FLOAT_VECTOR", "FACE").data.foreach_set("vector", values[name])
    mesh.update()
    return degenerate


def _load_image(path):
    """Loads an atlas as raw linear data; half precision in Cycles (the file
    is half already), alpha kept as a separate channel."""
    for image in bpy.data.images:
        if image.filepath and bpy.path.abspath(image.filepath) == path:
            image.reload()
            return image
    image = bpy.data.images.load(path, check_existing=False)
    image.colorspace_settings.name = "Non-Color"
    image.alpha_mode = "CHANNEL_PACKED"
    if hasattr(image, "use_half_precision"):
        image.use_half_precision = True
    return image


def build_group(name, k, aspect, images):
    """The node group: Shader output of the lookup for atlases
    images = {"front": Image or None, "back": Image or None}; aspect =
    tile_width / tile_height."""
    group = bpy.data.node_groups.get(name)
    if group is not None:
        bpy.data.node_groups.remove(group)
    group = bpy.data.node_groups.new(name, "ShaderNodeTree")
    group.outputs.new("NodeSocketShader", "Shader")
    group.outputs.new("NodeSocketColor", "Color")
    group.outputs.new("NodeSocketFloat", "Alpha")
    g = Graph(group)

    # 0. Inputs: the shading point, the unit direction toward the camera and
    # the face's patch (world space).
    geometry = g.node("ShaderNodeNewGeometry", 0)
    point = geometry.outputs["Position"]
    incoming = geometry.outputs["Incoming"]
    attr = {name: g.node("ShaderNodeAttribute", 0, attribute_name=ATTR_PREFIX + name,
                         attribute_type="GEOMETRY", label=name).outputs["Vector"]
            for name in FACE_ATTRS}
    e, f, gt = attr["e"], attr["f"], attr["g"]

    # 1. Patch parameters (s, t) where the view ray meets the bilinear patch
    # (clothbake.core.layout.patch_parameters, step for step).
    def cross_along(a, b, column):
        return g.vmath("DOT_PRODUCT", g.vmath("CROSS_PRODUCT", a, b, column=column), incoming,
                       column=column)

    h = g.vmath("SUBTRACT", point, attr["p0"], column=1)
    k2 = cross_along(gt, f, 1)
    k1 = g.math("ADD", cross_along(e, f, 1), cross_along(h, gt, 1), column=2)
    k0 = cross_along(h, e, 1)
    disc = g.math("MULTIPLY_ADD", k1, k1, g.math("MULTIPLY", -4.0, g.math("MULTIPLY", k0, k2,
                                                                          column=2), column=2),
                  column=2)
    root = g.math("SQRT", g.math("MAXIMUM", disc, 0.0, column=2), column=2)
    # sign(k1) with sign(0) = -1, as the Python mirror has it
    sign = g.math("MULTIPLY_ADD", g.math("GREATER_THAN", k1, 0.0, column=3), 2.0, -1.0, column=3)
    q = g.math("MULTIPLY", -0.5, g.math("MULTIPLY_ADD", sign, root, k1, column=3), column=3)
    t_near = g.math("DIVIDE", k0, q, column=3)
    t_far = g.math("DIVIDE", q, k2, column=3)
    near_ok = g.math("LESS_THAN", g.math("ABSOLUTE", g.math("SUBTRACT", t_near, 0.5, column=4),
                                         column=4), 0.5 + 1e-3, column=4)
    t = g.math("ADD", g.math("MULTIPLY", near_ok, g.math("SUBTRACT", t_near, t_far, column=4),
                             column=4), t_far, column=4, clamp=True)

    def perp(v, column):
        along = g.vmath("DOT_PRODUCT", v, incoming, column=column)
        return g.vmath("SUBTRACT", v, g.scale(incoming, along, column),
                       column=column)

    ps = g.vmath("ADD", e, g.scale(gt, t, 5), column=5)           # dP/ds at t
    d1 = perp(g.vmath("SUBTRACT", h, g.scale(f, t, 5), column=5), 6)
    d2 = perp(ps, 6)
    s = g.math("DIVIDE", g.vmath("DOT_PRODUCT", d1, d2, column=7),
               g.vmath("DOT_PRODUCT", d2, d2, column=7), column=7, clamp=True)

    # 2. The local frame at (s, t) (layout.frame_from_attributes) and the
    # view direction in it.
    pt = g.vmath("ADD", f, g.scale(gt, s, 8), column=8)           # dP/dt at s
    normal = g.vmath("NORMALIZE", g.vmath("CROSS_PRODUCT", ps, pt, column=8), column=8)
    us_x, us_y, _ = g.separate(g.vmath("ADD", attr["ue"], g.scale(attr["ug"], t, 8), column=8), 9)
    ut_x, ut_y, _ = g.separate(g.vmath("ADD", attr["uf"], g.scale(attr["ug"], s, 8), column=8), 9)
    det = g.math("SUBTRACT", g.math("MULTIPLY", us_x, ut_y, column=9),
                 g.math("MULTIPLY", ut_x, us_y, column=9), column=9)
    dp_du = g.scale(g.vmath("SUBTRACT", g.scale(ps, ut_y, 10), g.scale(pt, us_y, 10), column=10),
                   det, 10)
    along_n = g.vmath("DOT_PRODUCT", dp_du, normal, column=11)
    tangent = g.vmath("NORMALIZE", g.vmath("SUBTRACT", dp_du, g.scale(normal, along_n, 11),
                                           column=11), column=11)
    bitangent = g.vmath("CROSS_PRODUCT", normal, tangent, column=12)
    x = g.vmath("DOT_PRODUCT", incoming, tangent, column=12)
    y = g.vmath("DOT_PRODUCT", incoming, bitangent, column=12)
    z = g.vmath("DOT_PRODUCT", incoming, normal, column=12)
    side = g.math("LESS_THAN", z, 0.0, column=13)

    # 3. Hemi-octahedral (u, v), grid position, nodes and weights.
    l1 = g.math("ADD", g.math("ADD", g.math("ABSOLUTE", x, column=13),
                              g.math("ABSOLUTE", y, column=13), column=13),
                g.math("ABSOLUTE", z, column=13), column=13)
    l1 = g.math("MAXIMUM", l1, 1e-20, column=13)
    px = g.math("DIVIDE", x, l1, column=14)
    py = g.math("DIVIDE", y, l1, column=14)
    u = g.math("MULTIPLY_ADD", g.math("ADD", px, py, column=14), 0.5, 0.5, column=15, clamp=True)
    v = g.math("MULTIPLY_ADD", g.math("SUBTRACT", px, py, column=14), 0.5, 0.5, column=15,
               clamp=True)

    def node_and_weight(coord):
        grid = g.math("MULTIPLY", coord, float(k - 1), column=16)
        first = g.math("MINIMUM", g.math("FLOOR", grid, column=16), float(k - 2), column=16)
        weight = g.math("SUBTRACT", grid, first, column=17, clamp=True)
        return first, weight

    i0, fx = node_and_weight(u)
    j0, fy = node_and_weight(v)

    # 4. Atlas coordinates of the four tiles: the face's square in tile
    # units (u_tile = x0 + s w, v_tile = y0 + t w aspect), then tile (i, j)
    # at ((i + u_tile) / K, (K - 1 - j + v_tile) / K), rows counted from the top.
    sq_x, sq_y, sq_w = g.separate(attr["square"], column=16)
    u_tile = g.math("MULTIPLY_ADD", s, sq_w, sq_x, column=17)
    v_tile = g.math("MULTIPLY_ADD", t, g.math("MULTIPLY", sq_w, aspect, column=17), sq_y,
                    column=17)
    inv_k = 1.0 / k
    atlas_uv = {}
    for di in (0, 1):
        for dj in (0, 1):
            col = g.math("ADD", g.math("ADD", i0, float(di), column=18), u_tile, column=18)
            row = g.math("ADD", g.math("SUBTRACT", float(k - 1 - dj), j0, column=18), v_tile,
                         column=18)
            atlas_uv[di, dj] = g.combine(g.math("MULTIPLY", col, inv_k, column=19),
                                         g.math("MULTIPLY", row, inv_k, column=19), column=19)

    def side_value(image, column):
        if image is None:
            return (0.0, 0.0, 0.0, 1.0), 0.0
        reads = {}
        for key, vec in atlas_uv.items():
            tex = g.node("ShaderNodeTexImage", column, image=image, interpolation="Linear",
                         extension="EXTEND")
            g.feed(tex.inputs["Vector"], vec)
            reads[key] = tex
        c0 = g.mix_color(reads[0, 0].outputs["Color"], reads[1, 0].outputs["Color"], fx, column + 1)
        c1 = g.mix_color(reads[0, 1].outputs["Color"], reads[1, 1].outputs["Color"], fx, column + 1)
        a0 = g.lerp(reads[0, 0].outputs["Alpha"], reads[1, 0].outputs["Alpha"], fx, column + 1)
        a1 = g.lerp(reads[0, 1].outputs["Alpha"], reads[1, 1].outputs["Alpha"], fx, column + 1)
        return g.mix_color(c0, c1, fy, column + 2), g.lerp(a0, a1, fy, column + 2)

    front_c, front_a = side_value(images.get("front"), 20)
    back_c, back_a = side_value(images.get("back"), 23)
    color = g.mix_color(front_c, back_c, side, 26)
    alpha = g.lerp(front_a, back_a, side, 26)

    # 4. Premultiplied radiance over what is behind.
    emission = g.node("ShaderNodeEmission", 27)
    g.feed(emission.inputs["Color"], color)
    emission.inputs["Strength"].default_value = 1.0
    transparent = g.node("ShaderNodeBsdfTransparent", 27)
    g.feed(transparent.inputs["Color"], g.math("SUBTRACT", 1.0, alpha, column=27, clamp=True))
    add = g.node("ShaderNodeAddShader", 28)
    g.links.new(emission.outputs[0], add.inputs[0])
    g.links.new(transparent.outputs[0], add.inputs[1])
    out = g.node("NodeGroupOutput", 29)
    g.links.new(add.outputs[0], out.inputs["Shader"])
    g.links.new(color, out.inputs["Color"])
    g.links.new(alpha, out.inputs["Alpha"])
    return group


def apply_lookup(obj, folder):
    """Applies the lookup in `folder` to mesh object `obj`: mesh layers, the
    node group and a material. Returns (material, notes); raises
    ClothbakeError for a missing folder, a broken manifest or a mismatched
    mesh, before touching the object."""
    if obj is None or obj.type != "MESH":
        raise ClothbakeError("select a mesh object to apply a lookup to")
    lookup = read_manifest(folder)
    if lookup.direction_map != directions.HEMI_OCTAHEDRAL:
        raise ClothbakeError(f"the add-on applies hemi-octahedral lookups; this one is "
                             f"{lookup.direction_map} (bake with --direction-map hemi-octahedral)",
                             os.path.join(lookup.folder, "manifest.json"), "direction_map.type")
    lobj = pick_lookup_object(lookup, obj)
    degenerate = write_mesh_layers(obj, lookup, lobj)
    images = {side: (_load_image(path) if path else None) for side, path in lobj.files.items()}
    group = build_group(f"clothbake {obj.name}", lookup.k, lobj.tile_width / lobj.tile_height,
                        images)

    material = bpy.data.materials.get(f"clothbake {obj.name}") or \
        bpy.data.materials.new(f"clothbake {obj.name}")
    material.use_nodes = True
    tree = material.node_tree
    tree.nodes.clear()
    node = tree.nodes.new("ShaderNodeGroup")
    node.node_tree = group
    out = tree.nodes.new("ShaderNodeOutputMaterial")
    out.location = (300, 0)
    tree.links.new(node.outputs["Shader"], out.inputs["Surface"])
    material.blend_method = "BLEND"  # EEVEE viewport: honour the transparency
    if hasattr(material, "shadow_method"):
        material.shadow_method = "NONE"
    material["clothbake_lookup"] = lookup.folder
    obj.data.materials.clear()
    obj.data.materials.append(material)
    obj["clothbake_lookup"] = lookup.folder
    notes = []
    if degenerate:
        notes.append(f"{degenerate} degenerate faces left transparent")
    return material, notes
