"""Apply: put a baked lookup on a mesh with plain Cycles nodes (no OSL).

What it writes onto the mesh: per face, world-space vectors describing the
face's bilinear patch, its UV Jacobian and its square in the atlas
(clothbake.core.lookup_layout.face_attributes). A material whose node group does,
per shading point (the arithmetic of lookup_layout.patch_parameters and
lookup_layout.frame_from_attributes, which the tests check in plain Python):
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
  4. per side and node, the square's origin in the packed atlas from the
     side's index image (pixel (node, quad), Closest; lookup_layout.index_pixels),
     then the atlas at origin + (s, t) x size / (W, H), Linear; texels of
     unbaked pairs multiplied by 0; the four blended bilinearly (colour and
     alpha alike); the side picked by `side`;
  5. Emission(RGB) + Transparent(1 - A): the lookup's RGB is premultiplied,
     so this is exactly "RGB + (1 - A) x behind", the same as Emission of
     RGB / A mixed with Transparent by A, without dividing by A.
Linear filtering reads at most half a texel outside a face's square, which
the one-texel gutter holds (copies of edge texels), so directions never
bleed into each other.
"""
import os

import bpy

from ..core import directions, lookup_mesh_summary
from ..core.errors import ClothbakeError
from ..core.lookup_layout import corner_frames, index_pixels
from ..core.lookup_manifest import read_manifest
from . import evaluated_mesh, lookup_patch_nodes
from .graph import Graph
from .node_compat import new_group_socket
from .lookup_patch_nodes import ATTR_PREFIX, FACE_ATTRS

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


def check_mesh(obj, lookup, lookup_object):
    """Refuses a mesh that cannot show the lookup: its render mesh (after
    modifiers, evaluated_mesh) must be quads with UVs, as many as the
    lookup's object has, and match the baked mesh's summary. Returns the
    RenderMesh. Changes nothing."""
    manifest = os.path.join(lookup.folder, "manifest.json")
    rm = evaluated_mesh.render_mesh(obj)
    # Non-quads first: whatever lookup is chosen, such a mesh cannot carry one.
    bad = evaluated_mesh.non_quads(rm)
    if bad:
        what = "1 face that is not a quad" if len(bad) == 1 else \
            f"{len(bad)} faces that are not quads"
        raise ClothbakeError(f"mesh '{obj.name}' has {what} (first: face {bad[0]}, "
                             f"{len(rm.faces[bad[0]])} corners){evaluated_mesh.blame(obj, rm)}; "
                             "clothbake needs quads (4 corners)")
    if len(rm.faces) != lookup_object.quads:
        mods = evaluated_mesh.modifier_list(obj)
        after = f" after its modifiers ({mods})" if mods else ""
        raise ClothbakeError(f"mesh '{obj.name}' has {_count(len(rm.faces), 'face')}{after}; "
                             f"the lookup's object '{lookup_object.name}' has "
                             f"{_count(lookup_object.quads, 'quad')} "
                             "(was it baked from another mesh?)",
                             manifest, f"objects[{lookup_object.index}].quads")
    if rm.face_uvs is None:
        raise ClothbakeError(f"mesh '{obj.name}' has no UV map{evaluated_mesh.blame(obj, rm)}; "
                             "the weave follows the UVs")
    if lookup_object.mesh is not None:
        differs = lookup_mesh_summary.difference(lookup_object.mesh, lookup_mesh_summary.summarize(rm.quads()))
        if differs:
            raise ClothbakeError(f"mesh '{obj.name}' is not the mesh the lookup's object "
                                 f"'{lookup_object.name}' was baked from: {differs} (was it "
                                 "baked from another mesh, or has this one moved since? bake "
                                 "again)", manifest, f"objects[{lookup_object.index}].mesh")
    return rm


def load_data_image(path, half=True):
    """Loads an image of data (an atlas) as raw linear values, alpha kept as
    a separate channel; half precision in Cycles when `half` (the file is
    half already), else float. Reloaded when already loaded."""
    for image in bpy.data.images:
        if image.filepath and bpy.path.abspath(image.filepath) == path:
            image.reload()
            return image
    image = bpy.data.images.load(path, check_existing=False)
    image.colorspace_settings.name = "Non-Color"
    image.alpha_mode = "CHANNEL_PACKED"
    if hasattr(image, "use_half_precision"):
        image.use_half_precision = half
    return image


def _index_image(name, lookup_object, side, k, hidden=()):
    """The side's index image (lookup_layout.index_pixels), made in memory and
    packed into the .blend so a saved file keeps it. Float32, Closest: it
    holds addresses, not colours."""
    image = bpy.data.images.get(name)
    if image is not None:
        bpy.data.images.remove(image)
    image = bpy.data.images.new(name, width=k * k, height=max(1, lookup_object.quads), alpha=True,
                                float_buffer=True, is_data=True)
    image.colorspace_settings.name = "Non-Color"
    image.alpha_mode = "CHANNEL_PACKED"
    if hasattr(image, "use_half_precision"):
        image.use_half_precision = False
    image.pixels.foreach_set(index_pixels(lookup_object, side, k, hidden))
    image.update()
    image.pack()
    return image


def _transform(g, vector, kind, source, target, column):
    n = g.node("ShaderNodeVectorTransform", column, vector_type=kind, convert_from=source,
               convert_to=target)
    g.feed(n.inputs["Vector"], vector)
    return n.outputs["Vector"]


def _clamp(g, value, lo, hi, column):
    return g.math("MAXIMUM", g.math("MINIMUM", value, hi, column=column), lo, column=column)


def _new_group(name):
    group = bpy.data.node_groups.get(name)
    if group is not None:
        bpy.data.node_groups.remove(group)
    group = bpy.data.node_groups.new(name, "ShaderNodeTree")
    for socket_type, socket_name in (("NodeSocketShader", "Shader"),
                                     ("NodeSocketColor", "Color"), ("NodeSocketFloat", "Alpha")):
        new_group_socket(group, "OUTPUT", socket_type, socket_name)
    return group


def _patch_inputs(g):
    """Step 0, the inputs: (the shading point and the unit direction toward
    the camera in object space, that direction in world space, the face's
    patch attributes by name). The patch is in object space (lookup_patch_nodes),
    so the point and the direction move there for step 1; an affine map
    keeps the ray's crossing with the patch at the same (s, t)."""
    geometry = g.node("ShaderNodeNewGeometry", 0)
    point = _transform(g, geometry.outputs["Position"], "POINT", "WORLD", "OBJECT", 0)
    incoming_world = geometry.outputs["Incoming"]
    incoming = g.vmath("NORMALIZE", _transform(g, incoming_world, "VECTOR", "WORLD", "OBJECT", 0),
                       column=0)
    attr = {name: g.node("ShaderNodeAttribute", 0, attribute_name=ATTR_PREFIX + name,
                         attribute_type="GEOMETRY", label=name).outputs["Vector"]
            for name in FACE_ATTRS}
    return point, incoming, incoming_world, attr


def _patch_parameters(g, point, incoming, attr):
    """Step 1: the patch parameters (s, t) where the view ray meets the
    bilinear patch (clothbake.core.lookup_layout.patch_parameters, step for step),
    and dP/ds at t."""
    e, f, gt = attr["e"], attr["f"], attr["g"]

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
    # Both roots clamped to [-1, 2] before the select below: it is a blend
    # near_ok t_near + (1 - near_ok) t_far, and on a parallelogram (g = 0 up
    # to rounding) k2 is tiny and t_far huge, so unclamped the blend lost
    # t_near to float cancellation and t came out 0 or 1 on whole quads
    # (the patchwork of stripes a plane made in Blender showed). The select
    # only ever keeps a root in [-1e-3, 1 + 1e-3], which the clamp leaves as
    # it is.
    t_near = _clamp(g, t_near, -1.0, 2.0, 3)
    t_far = _clamp(g, g.math("DIVIDE", q, k2, column=3), -1.0, 2.0, 3)
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
    return s, t, ps


def _view_in_frame(g, attr, s, t, ps, incoming_world):
    """Step 2: the local frame at (s, t) (lookup_layout.frame_from_attributes) and
    the view direction (x, y, z) in it, and its side. In world space: the
    patch's derivatives move back there (angles are not kept by a
    non-uniform scale)."""
    f, gt = attr["f"], attr["g"]
    pt = _transform(g, g.vmath("ADD", f, g.scale(gt, s, 8), column=8), "VECTOR", "OBJECT",
                    "WORLD", 8)                                   # dP/dt at s
    ps = _transform(g, ps, "VECTOR", "OBJECT", "WORLD", 8)
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
    x = g.vmath("DOT_PRODUCT", incoming_world, tangent, column=12)
    y = g.vmath("DOT_PRODUCT", incoming_world, bitangent, column=12)
    z = g.vmath("DOT_PRODUCT", incoming_world, normal, column=12)
    side = g.math("LESS_THAN", z, 0.0, column=13)
    return x, y, z, side


def _direction_nodes(g, k, x, y, z):
    """Step 3: the hemi-octahedral (u, v), grid position, and (i0, fx, j0,
    fy), the lower nodes and the weights of i0 + 1, j0 + 1."""
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
    return i0, fx, j0, fy


def _index_addresses(g, attr, k, quads, i0, j0):
    """Step 4's index-image addresses, {(di, dj): uv of pixel (node, quad)}:
    per side and node, the square's origin is read there (Closest), then
    the atlas at origin + (s, t) size / (W, H) (_side_value)."""
    quad, _, _ = g.separate(attr["face"], column=16)
    index_v = g.math("MULTIPLY", g.math("ADD", quad, 0.5, column=17), 1.0 / max(1, quads),
                     column=17)
    index_uv = {}
    for di in (0, 1):
        for dj in (0, 1):
            node = g.math("ADD", g.math("MULTIPLY_ADD", g.math("ADD", j0, float(dj), column=18),
                                        float(k), i0, column=18), float(di) + 0.5, column=18)
            index_uv[di, dj] = g.combine(g.math("MULTIPLY", node, 1.0 / (k * k), column=19),
                                         index_v, column=19)
    return index_uv


def _side_value(g, entry, index_uv, s, t, fx, fy, column):
    """Step 4 for one side: (colour, alpha) of its four nodes blended
    bilinearly; transparent black when the side was not baked."""
    if entry is None:
        return (0.0, 0.0, 0.0, 1.0), 0.0
    atlas, index, width, height = entry
    colors, alphas = {}, {}
    for key, vec in index_uv.items():
        where = g.node("ShaderNodeTexImage", column, image=index, interpolation="Closest",
                       extension="EXTEND", label="square origin")
        g.feed(where.inputs["Vector"], vec)
        x0, y0, size = g.separate(where.outputs["Color"], column=column + 1)
        baked = g.math("GREATER_THAN", size, 0.5, column=column + 1)
        uv = g.combine(
            g.math("MULTIPLY_ADD", s, g.math("MULTIPLY", size, 1.0 / width, column=column + 1),
                   x0, column=column + 1),
            g.math("MULTIPLY_ADD", t, g.math("MULTIPLY", size, 1.0 / height,
                                             column=column + 1), y0, column=column + 1),
            column=column + 1)
        tex = g.node("ShaderNodeTexImage", column + 2, image=atlas, interpolation="Linear",
                     extension="EXTEND")
        g.feed(tex.inputs["Vector"], uv)
        colors[key] = g.scale(tex.outputs["Color"], baked, column + 3)
        alphas[key] = g.math("MULTIPLY", tex.outputs["Alpha"], baked, column=column + 3)
    c0 = g.mix_color(colors[0, 0], colors[1, 0], fx, column + 4)
    c1 = g.mix_color(colors[0, 1], colors[1, 1], fx, column + 4)
    a0 = g.lerp(alphas[0, 0], alphas[1, 0], fx, column + 4)
    a1 = g.lerp(alphas[0, 1], alphas[1, 1], fx, column + 4)
    return g.mix_color(c0, c1, fy, column + 5), g.lerp(a0, a1, fy, column + 5)


def _shader(g, color, alpha):
    """Step 5: premultiplied radiance over what is behind."""
    emission = g.node("ShaderNodeEmission", 33)
    g.feed(emission.inputs["Color"], color)
    emission.inputs["Strength"].default_value = 1.0
    transparent = g.node("ShaderNodeBsdfTransparent", 33)
    g.feed(transparent.inputs["Color"], g.math("SUBTRACT", 1.0, alpha, column=33, clamp=True))
    add = g.node("ShaderNodeAddShader", 34)
    g.links.new(emission.outputs[0], add.inputs[0])
    g.links.new(transparent.outputs[0], add.inputs[1])
    out = g.node("NodeGroupOutput", 35)
    g.links.new(add.outputs[0], out.inputs["Shader"])
    g.links.new(color, out.inputs["Color"])
    g.links.new(alpha, out.inputs["Alpha"])


def build_group(name, k, quads, sides):
    """The node group: Shader output of the lookup, the steps of the module
    docstring in order. sides = {"front": (atlas Image, index Image, width,
    height) or None, "back": ...}."""
    group = _new_group(name)
    g = Graph(group)
    point, incoming, incoming_world, attr = _patch_inputs(g)
    s, t, ps = _patch_parameters(g, point, incoming, attr)
    x, y, z, side = _view_in_frame(g, attr, s, t, ps, incoming_world)
    i0, fx, j0, fy = _direction_nodes(g, k, x, y, z)
    index_uv = _index_addresses(g, attr, k, quads, i0, j0)
    front_c, front_a = _side_value(g, sides.get("front"), index_uv, s, t, fx, fy, 20)
    back_c, back_a = _side_value(g, sides.get("back"), index_uv, s, t, fx, fy, 26)
    color = g.mix_color(front_c, back_c, side, 32)
    alpha = g.lerp(front_a, back_a, side, 32)
    _shader(g, color, alpha)
    return group


def apply_lookup(obj, folder):
    """Applies the lookup in `folder` to mesh object `obj`: the patch
    modifier (lookup_patch_nodes), the node group and a material. Returns (material, notes); raises
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
    rm = check_mesh(obj, lookup, lobj)
    # Faces Blender finds degenerate stay transparent, whatever was baked.
    degenerate = {q for q, (corners, uvs) in enumerate(rm.quads())
                  if corner_frames(corners, uvs) is None}
    sides = {}
    for side, key in enumerate(("front", "back")):
        atlas = lobj.sides[key]
        sides[key] = None if atlas is None else (
            load_data_image(atlas.path),
            _index_image(f"clothbake {obj.name} {key} index", lobj, side, lookup.k, degenerate),
            atlas.width, atlas.height)
    group = build_group(f"clothbake {obj.name}", lookup.k, lobj.quads, sides)

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
    # Attributes an older add-on wrote onto the base mesh would be copied
    # onto other faces by modifiers; the patch modifier writes them now.
    for name in FACE_ATTRS + ("square",):
        if ATTR_PREFIX + name in obj.data.attributes:
            obj.data.attributes.remove(obj.data.attributes[ATTR_PREFIX + name])
    lookup_patch_nodes.attach(obj, rm.uv_name)
    obj.data.materials.clear()
    obj.data.materials.append(material)
    obj["clothbake_lookup"] = lookup.folder
    notes = []
    if degenerate:
        notes.append(f"{len(degenerate)} degenerate faces left transparent")
    return material, notes
