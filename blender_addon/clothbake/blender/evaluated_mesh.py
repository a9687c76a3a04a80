"""The mesh Cycles renders: an object's mesh after its modifiers (Subdivision
Surface, Cloth, deform modifiers, shape keys), evaluated with the
modifiers' *render* settings, in world space. Bake exports it and Apply
checks the lookup against it, so both work on what F12 shows rather than on
the base mesh.

Blender 3.4 gives Python the viewport evaluation only, so while the mesh is
read each modifier is switched to its render settings (shown if shown in
renders; a Subdivision Surface's or Multires's render levels), then put back.
The apply modifier itself (lookup_patch_nodes) only adds attributes and is left
out.

Where the result cannot carry a lookup (a face that is not a quad, no UV
map) the error names the modifier that made it so.
"""
from dataclasses import dataclass

import bpy

from . import lookup_patch_nodes


@dataclass
class RenderMesh:
    """World corners and UVs of each face, in Blender's face and corner order."""
    positions: list      # world positions per vertex
    faces: list          # vertex indices per face
    face_uvs: list       # per face, (u, v) per corner; None without a UV map
    uv_name: str         # the UV map the weave follows ("" without one)

    def quads(self):
        """(world corners, uvs) per face, for lookup_mesh_summary and the checks."""
        return [([self.positions[v] for v in face], uvs)
                for face, uvs in zip(self.faces, self.face_uvs)]


def _render_settings(obj, upto=None):
    """Switches obj's modifiers to their render settings (modifiers past
    index `upto`, and the apply modifier, off); returns what to restore."""
    saved = []
    for i, mod in enumerate(obj.modifiers):
        state = {"show_viewport": mod.show_viewport}
        show = mod.show_render and mod.name != lookup_patch_nodes.MODIFIER_NAME and \
            (upto is None or i <= upto)
        if hasattr(mod, "render_levels") and hasattr(mod, "levels"):
            state["levels"] = mod.levels
            if mod.levels != mod.render_levels:
                mod.levels = mod.render_levels
        if mod.show_viewport != show:
            mod.show_viewport = show
        saved.append((mod, state))
    return saved


def _restore(saved):
    for mod, state in saved:
        for key, value in state.items():
            if getattr(mod, key) != value:
                setattr(mod, key, value)


def _weave_uv_layer(mesh):
    """The UV map the weave (and so the frame) follows: the render-active one."""
    for layer in mesh.uv_layers:
        if layer.active_render:
            return layer
    return mesh.uv_layers[0] if len(mesh.uv_layers) else None


def _read(obj, upto=None):
    """RenderMesh of obj with modifiers up to `upto` (all when None)."""
    if obj.mode == "EDIT":
        obj.update_from_editmode()
    saved = _render_settings(obj, upto)
    try:
        depsgraph = bpy.context.evaluated_depsgraph_get()
        depsgraph.update()
        evaluated = obj.evaluated_get(depsgraph)
        mesh = evaluated.to_mesh()
        try:
            matrix = evaluated.matrix_world.copy()
            positions = [tuple(matrix @ v.co) for v in mesh.vertices]
            faces = [tuple(p.vertices) for p in mesh.polygons]
            layer = _weave_uv_layer(mesh)
            face_uvs = None if layer is None else \
                [[tuple(layer.data[li].uv) for li in p.loop_indices] for p in mesh.polygons]
            uv_name = layer.name if layer is not None else ""
        finally:
            evaluated.to_mesh_clear()
    finally:
        _restore(saved)
        if saved:
            bpy.context.evaluated_depsgraph_get().update()
    return RenderMesh(positions, faces, face_uvs, uv_name)


def _active_modifiers(obj):
    return [m for m in obj.modifiers
            if m.show_render and m.name != lookup_patch_nodes.MODIFIER_NAME]


def modifier_list(obj):
    """'Subdivision' (Subdivision Surface), ... of obj's render modifiers."""
    return ", ".join(f"'{m.name}' ({_type_name(m)})" for m in _active_modifiers(obj))


def _type_name(mod):
    return mod.bl_rna.properties["type"].enum_items[mod.type].name


def _culprit(obj, bad):
    """The first render modifier after which bad(RenderMesh) holds, or None
    when the base mesh already has the problem."""
    if bad(_read(obj, upto=-1)):
        return None
    for i, mod in enumerate(obj.modifiers):
        if mod.show_render and mod.name != lookup_patch_nodes.MODIFIER_NAME and bad(_read(obj, upto=i)):
            return mod
    return None


def non_quads(rm):
    """Indices of the faces that are not quads."""
    return [i for i, f in enumerate(rm.faces) if len(f) != 4]


def blame(obj, rm):
    """Why rm cannot carry a lookup, as the end of a sentence naming the
    modifier that made it so ("; the Triangulate modifier 'T' makes them"),
    or "" when the base mesh is that way already or nothing is wrong."""
    if non_quads(rm):
        mod = _culprit(obj, lambda m: bool(non_quads(m)))
        return f"; the {_type_name(mod)} modifier '{mod.name}' makes them" if mod else ""
    if rm.face_uvs is None:
        mod = _culprit(obj, lambda m: m.face_uvs is None)
        return f" (after the {_type_name(mod)} modifier '{mod.name}')" if mod else ""
    return ""


def render_mesh(obj):
    """The RenderMesh of obj (checked by the caller: non_quads, blame)."""
    return _read(obj)
