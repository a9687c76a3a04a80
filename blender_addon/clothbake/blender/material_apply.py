"""Apply material: a cloth material (docs/formats/material.md) on any mesh
with a UV map, lit live by the scene's sun, point, spot and area lights. The node group
is the material_nodes package's, the lights and camera reach it through
material_drivers.py; this module reads what the group needs from the mesh
and the scene, and makes the object's material around the group.
"""
import math
import os

import bpy
import numpy as np

from ..core.defaults import DEPTH_SCALE_TOLERANCE
from ..core.errors import ClothbakeError
from ..core.light_units import unsupported_light_setting
from ..core.material_manifest import SWF
from ..core.material_pack import pack_material, read_material
from ..core.svm_budget import stack_note
from . import material_colours
from . import lookup_patch_nodes
from .lookup_apply import load_data_image
from .material_drivers import drive_camera, drive_light, drive_world
from .material_nodes import (FRAME_SCALE_ATTRIBUTE, STRETCH_ATTRIBUTE, build_group,
                             layout_suffix, light_kinds)

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


def _triangles(mesh, matrix_world, layer):
    """The mesh's loop triangles: world positions p (n x 3 x 3), UVs t
    (n x 3 x 2) on `layer`, and each triangle's face index. The one read of
    a mesh that the scale and the frame factors below share."""
    mesh.calc_loop_triangles()
    n = len(mesh.loop_triangles)
    co = np.empty(len(mesh.vertices) * 3)
    mesh.vertices.foreach_get("co", co)
    m = np.array(matrix_world)
    co = co.reshape(-1, 3) @ m[:3, :3].T + m[:3, 3]
    tri_v = np.empty(n * 3, np.int64)
    mesh.loop_triangles.foreach_get("vertices", tri_v)
    tri_l = np.empty(n * 3, np.int64)
    mesh.loop_triangles.foreach_get("loops", tri_l)
    face = np.empty(n, np.int64)
    mesh.loop_triangles.foreach_get("polygon_index", face)
    uv = np.empty(len(mesh.loops) * 2)
    layer.data.foreach_get("uv", uv)
    return co[tri_v.reshape(-1, 3)], uv.reshape(-1, 2)[tri_l.reshape(-1, 3)], face


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
        layer = mesh.uv_layers.get(uv_name) or mesh.uv_layers.active
        if layer is None:
            raise ClothbakeError(f"mesh '{obj.name}' has no UV map after its modifiers")
        p, t, _ = _triangles(mesh, ob_eval.matrix_world, layer)
        area_w = 0.5 * np.linalg.norm(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), axis=1).sum()
        e1, e2 = t[:, 1] - t[:, 0], t[:, 2] - t[:, 0]
        area_uv = 0.5 * np.abs(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]).sum()
    finally:
        ob_eval.to_mesh_clear()
    if not area_uv > 0:
        raise ClothbakeError(f"mesh '{obj.name}': its UV map '{uv_name}' has no area "
                             "(every face maps to a point or a line); unwrap it (UV > Unwrap)")
    return math.sqrt(area_w / area_uv)




def write_face_world_per_uv(obj, uv_name):
    """The UV map's local scale per face, sqrt(world area / UV area) of the
    face (world space through the object's matrix), stored on the ORIGINAL
    mesh as the FACE float attribute STRETCH_ATTRIBUTE, which the group's
    level reads (material_nodes.level). Modifiers after it carry it on
    (a Subdivision Surface copies each face's value onto its sub-faces, a
    Mirror onto the mirrored copy); a face whose UVs have no area gets 0,
    where the group falls back to its World per UV input (the mean). A
    mesh or UV edit after Apply needs Apply again. Returns the number of
    faces without a value."""
    mesh = obj.data
    layer = mesh.uv_layers.get(uv_name)
    n_faces = len(mesh.polygons)
    values = np.zeros(n_faces)
    mesh.calc_loop_triangles()
    n = len(mesh.loop_triangles)
    if n and layer is not None:
        p, t, face = _triangles(mesh, obj.matrix_world, layer)
        a_w = 0.5 * np.linalg.norm(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), axis=1)
        e1, e2 = t[:, 1] - t[:, 0], t[:, 2] - t[:, 0]
        a_uv = 0.5 * np.abs(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0])
        area_w = np.bincount(face, a_w, n_faces)
        area_uv = np.bincount(face, a_uv, n_faces)
        ok = area_uv > 1e-12 * np.maximum(area_w, 1e-30)
        values[ok] = np.sqrt(area_w[ok] / area_uv[ok])
    attr = mesh.attributes.get(STRETCH_ATTRIBUTE)
    if attr is not None and (attr.domain != "FACE" or attr.data_type != "FLOAT"):
        mesh.attributes.remove(attr)
        attr = None
    if attr is None:
        attr = mesh.attributes.new(STRETCH_ATTRIBUTE, "FLOAT", "FACE")
    attr.data.foreach_set("value", values.astype(np.float32))
    mesh.update()
    return int((values == 0).sum())


def write_face_frame_scale(obj, uv_name, info, repeats, thickness):
    """The factors that carry a direction in the UV frame (d.T, d.B, d.N)
    into the material's frame as lookup-render does it (texture mm per world
    unit along each axis, surface_frame.h, then z over the material's depth
    scale): per face (e, 1 / e, depth_here / depth_material), e =
    sqrt(mm_per_world.x / mm_per_world.y), from the UV map's Jacobian
    (|dP/du|, |dP/dv|, area-weighted over the face's triangles). Stored on the
    original mesh as the FACE vector attribute FRAME_SCALE_ATTRIBUTE (`repeats`:
    the material's repeats per UV along u and along v); where
    the UV map runs square and at the material's depth it is (1, 1, 1). A
    face without UV area gets (0, 0, 0), read by the group as (1, 1, 1)."""
    mesh = obj.data
    layer = mesh.uv_layers.get(uv_name)
    n_faces = len(mesh.polygons)
    values = np.zeros((n_faces, 3))
    mesh.calc_loop_triangles()
    n = len(mesh.loop_triangles)
    rx, ry, rz = info.repeat_mm
    rep_u, rep_v = repeats
    if n and layer is not None and thickness > 0 and info.depth_scale > 0:
        p, t, face = _triangles(mesh, obj.matrix_world, layer)
        e = np.stack([p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]], axis=2)        # 3 x 2 world
        d = np.stack([t[:, 1] - t[:, 0], t[:, 2] - t[:, 0]], axis=2)        # 2 x 2 UV
        det = d[:, 0, 0] * d[:, 1, 1] - d[:, 0, 1] * d[:, 1, 0]
        ok = np.abs(det) > 1e-14
        inv = np.zeros_like(d)
        inv[ok, 0, 0], inv[ok, 1, 1] = d[ok, 1, 1] / det[ok], d[ok, 0, 0] / det[ok]
        inv[ok, 0, 1], inv[ok, 1, 0] = -d[ok, 0, 1] / det[ok], -d[ok, 1, 0] / det[ok]
        jac = e @ inv                                                       # dP/du, dP/dv
        w = 0.5 * np.abs(det) * ok
        a_u = np.bincount(face, w * np.linalg.norm(jac[:, :, 0], axis=1), n_faces)
        a_v = np.bincount(face, w * np.linalg.norm(jac[:, :, 1], axis=1), n_faces)
        good = (a_u > 0) & (a_v > 0)
        mx = rx * rep_u / np.where(good, a_u, 1.0) * np.bincount(face, w, n_faces)
        my = ry * rep_v / np.where(good, a_v, 1.0) * np.bincount(face, w, n_faces)
        mz = rz / thickness
        ex = np.sqrt(np.where(good, mx / np.where(good, my, 1.0), 1.0))
        depth = mz / np.sqrt(np.where(good, mx * my, 1.0))
        values[good] = np.stack([ex, 1.0 / ex, depth / info.depth_scale], axis=1)[good]
    attr = mesh.attributes.get(FRAME_SCALE_ATTRIBUTE)
    if attr is not None and (attr.domain != "FACE" or attr.data_type != "FLOAT_VECTOR"):
        mesh.attributes.remove(attr)
        attr = None
    if attr is None:
        attr = mesh.attributes.new(FRAME_SCALE_ATTRIBUTE, "FLOAT_VECTOR", "FACE")
    attr.data.foreach_set("vector", values.astype(np.float32).ravel())
    mesh.update()


def scene_lights(scene):
    """(the light objects the material is lit by, notes about the others).
    Sun, point, spot and area lights light it; an area light whose Spread
    is not 180 degrees is left out (clothbake's area lights emit into the
    whole half-space, and a narrower spread is up to 1.7 x brighter under
    it: measured), with a note, and so is one whose colour temperature or
    Normalize off (Blender 5.x) clothbake does not model; a spot scaled
    unevenly is lit as its round cone, as Cycles 3.4 draws it (Eevee draws
    an ellipse), with a note."""
    lights, notes = [], []
    for obj in scene.objects:
        if obj.type != "LIGHT":
            continue
        data = obj.data
        if data.type == "AREA" and abs(getattr(data, "spread", math.pi) - math.pi) > 1e-5:
            notes.append(f"light '{obj.name}': its spread is "
                         f"{math.degrees(data.spread):.4g} degrees: the material is not lit by "
                         "it (clothbake's area lights have Spread 180 degrees)")
            continue
        why = unsupported_light_setting(getattr(data, "use_temperature", False),
                                        getattr(data, "normalize", True))
        if why is not None and data.type in ("SUN", "POINT", "SPOT", "AREA"):
            notes.append(f"light '{obj.name}': {why}: the material is not lit by it")
            continue
        if data.type == "SPOT":
            sx, sy = obj.matrix_world.col[0].length, obj.matrix_world.col[1].length
            if abs(sx - sy) > 1e-4 * max(sx, sy):
                notes.append(f"light '{obj.name}': its X and Y scale differ: the material is "
                             "lit by its round cone as Cycles draws it (Eevee draws an "
                             "ellipse), and export refuses it")
        if data.type in ("SUN", "POINT", "SPOT", "AREA"):
            lights.append(obj)
        else:
            kind = data.type.lower()
            notes.append(f"light '{obj.name}' is {'an' if kind[0] in 'aeiou' else 'a'} {kind} "
                         "light: the material is not lit by it (it reads sun, point, spot and "
                         "area lights)")
    lights.sort(key=lambda o: o.name)
    return lights, notes


def _cloth_settings(obj):
    s = getattr(obj, "clothbake", None)
    if s is not None and hasattr(s, "repeats_per_uv"):
        return float(s.repeats_per_uv), float(s.thickness_world)
    return float(obj.get("clothbake_repeats_per_uv", 40.0)), \
        float(obj.get("clothbake_thickness_world", 0.01))


# --- Apply --------------------------------------------------------------------

def _uv_map_to_use(obj, route):
    """The UV map the material reads; refuses a non-mesh, an unknown route
    or a mesh with no UV map."""
    if obj is None or obj.type != "MESH":
        what = "nothing" if obj is None else f"object '{obj.name}' ({obj.type.lower()})"
        raise ClothbakeError(f"{what} is not a mesh; select a mesh object with a UV map")
    if route not in ROUTES:
        raise ClothbakeError(f"must be one of {', '.join(ROUTES)}", "", "route")
    uv_name = uv_map_name(obj)
    if uv_name is None:
        raise ClothbakeError(f"object '{obj.name}': its mesh has no UV map; add one (Edit Mode, "
                             "UV > Unwrap) so the weave has a place on it")
    return uv_name


def _fill_material_tree(tree, group, uv_name, written=(1.0, 1.0)):
    """The material's own nodes: the group fed the UV map, its tangent and
    its signed bitangent (a Normal Map node in tangent space fed
    (0.5, 1, 0.5): the tangent space's sign, live under modifiers and
    animation), into the Material Output. Returns the group node."""
    if tree.animation_data:
        tree.animation_data_clear()
    tree.nodes.clear()
    uv = tree.nodes.new("ShaderNodeUVMap")
    uv.uv_map = uv_name
    uv.location = (-300, 100)
    tangent = tree.nodes.new("ShaderNodeTangent")
    tangent.direction_type = "UV_MAP"
    tangent.uv_map = uv_name
    tangent.location = (-300, -100)
    bitangent = tree.nodes.new("ShaderNodeNormalMap")
    bitangent.space = "TANGENT"
    bitangent.uv_map = uv_name
    bitangent.label = "signed bitangent"
    bitangent.inputs["Color"].default_value = (0.5, 1.0, 0.5, 1.0)
    bitangent.location = (-300, -300)
    uv_out = uv.outputs["UV"]
    if written[0] != written[1]:
        # The material holds a repeat of the weave; the object's repeats per
        # UV count its draft as written (a WIF's whole threading), kx x ky
        # material repeats: the group's Repeats per UV takes k = sqrt(kx ky)
        # (apply_material), this node the rest, kx / k along u and ky / k
        # along v.
        k = (written[0] * written[1]) ** 0.5
        scale_uv = tree.nodes.new("ShaderNodeVectorMath")
        scale_uv.operation = "MULTIPLY"
        scale_uv.label = "written draft to material repeats"
        scale_uv.inputs[1].default_value = (written[0] / k, written[1] / k, 1.0)
        scale_uv.location = (-150, 250)
        tree.links.new(uv_out, scale_uv.inputs[0])
        uv_out = scale_uv.outputs["Vector"]
    # The group node after its feeds: Cycles compiles in creation order
    # (graph.Graph.converted), and a group node made first would wait a
    # pass for them.
    node = tree.nodes.new("ShaderNodeGroup")
    node.node_tree = group
    node.location = (0, 0)
    tree.links.new(uv_out, node.inputs["UV"])
    tree.links.new(tangent.outputs["Tangent"], node.inputs["Tangent"])
    tree.links.new(bitangent.outputs["Normal"], node.inputs["Bitangent"])
    return node


def _depth_note(obj, info, repeats, thickness, scale):
    """The weave's depth in the material against this object's
    (docs/formats/material.md): a note when they differ by more than the
    program's tolerance, else None."""
    # `repeats`: the material's (along u, along v); the geometric mean of
    # the two axes, as object_optics (C++) takes it.
    rep_u, rep_v = repeats
    mm_along = (info.repeat_mm[0] * rep_u * info.repeat_mm[1] * rep_v) ** 0.5 / scale
    if not (thickness > 0 and mm_along > 0):
        return None
    object_depth = info.repeat_mm[2] / thickness / mm_along
    if not abs(object_depth / info.depth_scale - 1.0) > DEPTH_SCALE_TOLERANCE:
        return None
    return (f"object '{obj.name}': its depth scale {object_depth:.3g} (thickness "
            f"{thickness:g}, {rep_u:g} x {rep_v:g} material repeats per UV, {scale:.3g} "
            "world units per "
            f"UV) differs from the material's {info.depth_scale:.3g} by more than "
            f"{DEPTH_SCALE_TOLERANCE:.0%}: the weave is shaded as the material's thickness")


def apply_material(obj, folder, route="exact", rank=None, scene=None, depsgraph=None):
    """Puts the material in `folder` on mesh object `obj`. Returns (material,
    notes). Raises ClothbakeError (no traceback) for a non-mesh, a mesh with
    no UV map, or a broken material folder, before changing anything."""
    uv_name = _uv_map_to_use(obj, route)
    scene = scene or bpy.context.scene
    depsgraph = depsgraph or bpy.context.evaluated_depsgraph_get()
    info = read_material(folder)
    scale = world_per_uv(obj, uv_name, depsgraph)
    unmeasured = write_face_world_per_uv(obj, uv_name)
    pack = pack_material(info, rank)
    coeff = load_data_image(pack.coefficients, half=True)
    lights_img = load_data_image(pack.light_factors, half=False)
    lights, notes = scene_lights(scene)
    if not lights:
        notes.append("the scene has no light: the cloth renders black until one is added "
                     "and the material applied again" if route != "cycles-lit" else
                     "the scene has no light: the cloth is lit by the world alone until one "
                     "is added and the material applied again")

    key = os.path.basename(pack.folder)
    kinds = light_kinds(lights)
    stack = stack_note(kinds, info.parts == SWF, route, tuple(bpy.app.version))
    if stack:
        notes.append(stack)
    # A colour-free material's group holds the object's own colour strips:
    # one group per object.
    strips, strips_json = material_colours.make_strips(obj, info) if info.parts == SWF else \
        (None, None)
    owner = f" for {obj.name}" if strips is not None else ""
    next_img = load_data_image(pack.next_coefficients, half=True) if strips is not None \
        else None
    index_img = load_data_image(pack.crossings, half=False) if pack.crossings else None
    span_img = load_data_image(pack.spans, half=False) if pack.spans else None
    group = build_group(f"clothbake material {info.name or 'cloth'} {key} {len(lights)}L"
                        f"{layout_suffix(kinds)} {route}{owner}", info, pack, coeff, lights_img,
                        kinds, route, strips, next_img, index_img, span_img)

    name = f"clothbake material {obj.name}"
    material = bpy.data.materials.get(name) or bpy.data.materials.new(name)
    material.use_nodes = True
    tree = material.node_tree
    written = tuple(info.written_repeats)
    node = _fill_material_tree(tree, group, uv_name, written)
    repeats, thickness = _cloth_settings(obj)
    per_uv = (repeats * written[0], repeats * written[1])   # material repeats along u, v
    write_face_frame_scale(obj, uv_name, info, per_uv, thickness)
    node.inputs["Repeats per UV"].default_value = repeats * (written[0] * written[1]) ** 0.5
    node.inputs["World per UV"].default_value = scale
    out = tree.nodes.new("ShaderNodeOutputMaterial")
    out.location = (300, 0)
    tree.links.new(node.outputs["Shader"], out.inputs["Surface"])
    drive_camera(node, scene)
    for l, light in enumerate(lights):
        drive_light(node, l, light)
    notes += drive_world(node, scene)
    material.blend_method = "HASHED"        # Eevee: stochastic alpha, converges with samples
    if hasattr(material, "shadow_method"):
        material.shadow_method = "HASHED" if route == "cycles-lit" else "NONE"
    material.use_backface_culling = False
    material["clothbake_material"] = info.folder
    material["clothbake_route"] = route
    if strips is not None:
        material[material_colours.STRIPS_KEY] = strips_json
    elif material_colours.STRIPS_KEY in material:
        del material[material_colours.STRIPS_KEY]

    obj.data.materials.clear()
    obj.data.materials.append(material)
    obj["clothbake_material"] = info.folder
    if strips is not None:
        notes += material_colours.refresh_material(material, obj)
        cloth = getattr(obj, "clothbake", None)
        if cloth is None or not cloth.is_cloth:
            notes.append(f"'{obj.name}' is no cloth object: its colour-free material takes "
                         "the colours it was baked with")
    # A per-scene lookup's patch modifier (lookup_apply.py) means nothing to a
    # material, and its geometry-nodes output left Eevee's viewport without
    # the UV map's tangents: a black plane in Material Preview.
    lookup_patch_nodes.detach(obj)

    if unmeasured:
        notes.append(f"{unmeasured} face(s) of '{obj.name}' have no UV area: their weave's "
                     "level follows the mesh's mean scale")
    depth = _depth_note(obj, info, per_uv, thickness, scale)
    if depth:
        notes.append(depth)
    if pack.rank < max(info.ranks):
        notes.append(f"{pack.rank} of up to {max(info.ranks)} components evaluated")
    return material, notes
