"""The clothbake panel (Properties > Object > clothbake) and the File >
Import / Export menu entries."""
import os
import textwrap

import bpy

from ..core import wif_cloth
from ..core.cloth_fields import DRAFT, WIF
from . import wif_preview
from ..core.material_settings import MATERIAL_SETTINGS
from .operators_lookup import (CLOTHBAKE_OT_apply, CLOTHBAKE_OT_bake, CLOTHBAKE_OT_estimate,
                             estimate_is_current)
from .operators_compare import CLOTHBAKE_OT_compare, CLOTHBAKE_OT_denoising_off, denoiser_missing
from .operators_job import ProgramJob
from .operators_material import (CLOTHBAKE_OT_apply_material, CLOTHBAKE_OT_bake_material,
                                 CLOTHBAKE_OT_material_estimate, material_estimate_is_current)
from .operators_scene import CLOTHBAKE_OT_export_scene, CLOTHBAKE_OT_import_scene


class _ObjectPanel:
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "object"

    @classmethod
    def poll(cls, context):
        return context.object is not None and context.object.type == "MESH"


class CLOTHBAKE_PT_object(_ObjectPanel, bpy.types.Panel):
    bl_label = "clothbake"

    def draw_header(self, context):
        self.layout.prop(context.object.clothbake, "is_cloth", text="")

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        cloth = context.object.clothbake
        if not cloth.is_cloth:
            layout.label(text="Tick the box to make this quad mesh a clothbake cloth",
                         icon="INFO")
            return
        col = layout.column()
        col.prop(cloth, "repeats_per_uv")
        col.prop(cloth, "thickness_world")
        col.prop(cloth, "extinction_per_mm")
        col.prop(cloth, "lookup_dir")


class CLOTHBAKE_PT_cloth(_ObjectPanel, bpy.types.Panel):
    bl_label = "Cloth"
    bl_parent_id = "CLOTHBAKE_PT_object"

    @classmethod
    def poll(cls, context):
        return super().poll(context) and context.object.clothbake.is_cloth

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        cloth = context.object.clothbake
        row = layout.row(align=True)
        path = row.row(align=True)
        path.enabled = False  # set by Load cloth file, which reads the file
        path.prop(cloth, "cloth_path")
        row.operator("clothbake.load_cloth", text="", icon="FILEBROWSER")
        if cloth.cloth_path:
            layout.label(text="Edited: exported inline" if cloth.cloth_edited
                         else "Exported as a reference to the file",
                         icon="GREASEPENCIL" if cloth.cloth_edited else "LINKED")
        layout.prop(cloth, "volume_path")
        if cloth.volume_path:
            layout.label(text="Texture read from the VDB; the spec gives the fibre model",
                         icon="INFO")
        layout.prop(cloth, "weave")
        if cloth.weave == DRAFT:
            layout.label(text="Draft from the spec file", icon="INFO")
        draft = None
        if cloth.weave == WIF:
            draft = _draw_wif(layout, context, context.object, cloth)
        for family in ("warp", "weft"):
            col = layout.column(heading=family.capitalize(), align=True)
            if draft is None:  # a WIF cloth's colours are its palette's
                col.prop(cloth, f"{family}_color", text=f"{family.capitalize()} colour")
            mean = draft is not None and (wif_cloth.varies(draft.get(f"{family}_spacing_mm")) or
                                          wif_cloth.varies(draft.get(f"{family}_width_mm")))
            col.prop(cloth, f"{family}_spacing_mm",
                     text="Spacing (mm, mean)" if mean else "Spacing (mm)")
            col.prop(cloth, f"{family}_width_mm", text="Width (mm, mean)" if mean else "Width (mm)")
            col.prop(cloth, f"{family}_thickness_mm", text="Thickness (mm)")
            col.prop(cloth, f"{family}_twist_deg", text="Ply twist (deg)")
            col.prop(cloth, f"{family}_ply_pitch_mm", text="Ply pitch (mm)")
        col = layout.column(align=True)
        col.prop(cloth, "crimp")
        col.prop(cloth, "angle_spread_deg")
        col.prop(cloth, "seed")
        col = layout.column(heading="Cells", align=True)
        col.prop(cloth, "cells_x", text="X")
        col.prop(cloth, "cells_y", text="Y")
        col.prop(cloth, "layers")
        col.prop(cloth, "supersample")
        if context.scene.clothbake.shading == "isotropic":
            layout.prop(cloth, "isotropic_albedo")


def _draw_wif(layout, context, obj, cloth):
    """The WIF draft: its name and size, the drawdown in the palette as
    edited, and one colour field per distinct colour. Returns the compact
    draft (None when it could not be read)."""
    box = layout.box()
    if cloth.wif_status:
        col = box.column()
        col.alert = True
        col.label(text="The WIF file could not be read:", icon="ERROR")
        for part in textwrap.wrap(cloth.wif_status, 48):
            col.label(text=part)
    draft = wif_preview.draft(cloth)
    if draft is None:
        if not cloth.wif_status:
            box.label(text="Pick a .wif (or a spec naming one) as the cloth file", icon="INFO")
        return None
    box.label(text=os.path.basename(cloth.wif_path) or "WIF", icon="TEXTURE")
    box.label(text=f"{draft['ends']} ends x {draft['picks']} picks, "
                   f"{len(cloth.wif_palette)} colours")
    program = wif_cloth.source_program(draft)
    if program:
        box.label(text=f"Made with {program}")
    prev = wif_preview.preview(cloth)
    # The icon is drawn in a square of scale x 20 px (UI units), as wide as
    # the panel allows.
    width = context.region.width / max(context.preferences.view.ui_scale, 0.1) if context.region \
        else 300
    scale = max(4.0, min(16.0, (width - 50) / 20.0))
    box.template_icon(icon_value=prev.icon_id, scale=scale)
    wif_preview.drawn[obj.name_full] = {"icon_id": prev.icon_id,
                                        "image_size": tuple(prev.image_size),
                                        "block": wif_cloth.drawdown_block(draft["ends"],
                                                                          draft["picks"]),
                                        "scale": scale}
    col = box.column(align=True)
    col.label(text="Palette")
    for i, item in enumerate(cloth.wif_palette):
        counts = ", ".join(t for t in (f"{item.ends} ends" if item.ends else "",
                                      f"{item.picks} picks" if item.picks else "") if t)
        row = col.split(factor=0.62, align=True)
        row.label(text=f"{i + 1}: {counts}")
        row.prop(item, "color", text="")
    return draft


def _split_column(layout):
    """A column of labelled fields (label left, value right), as Blender's
    own property panels draw them."""
    col = layout.column()
    col.use_property_split = True
    col.use_property_decorate = False
    return col


def _wrap(context, text, less=0):
    """`text` in lines that fit the panel's width less `less` characters (a
    label is cut with an ellipsis where it overflows)."""
    chars = max(24, int(context.region.width / (7 * context.preferences.view.ui_scale)) - less)
    return textwrap.wrap(text, chars) or [""]


def _wrapped(col, context, text, icon):
    """`text` as labels wrapped to the panel's width, `icon` on the first."""
    for i, line in enumerate(_wrap(context, text)):
        col.label(text=line, icon=icon if i == 0 else "BLANK1")


def _estimate_row(col, context, current, estimate, operator):
    """What a bake would cost, before it starts: the program's estimate for
    exactly these settings, else the button that makes one."""
    row = col.row(align=True)
    if current:
        # The notes after "; " (what the bake chose and why, a texels
        # warning: program.plan_note, texels_note) wrapped below: the panel
        # is narrow.
        text, _, notes = estimate.partition("; ")
        first, *rest = _wrap(context, text, less=4)  # the refresh button beside it
        row.label(text=first, icon="TIME")
        row.operator(operator.bl_idname, text="", icon="FILE_REFRESH")
        for line in rest:
            col.label(text=line, icon="BLANK1")
        if notes:
            _wrapped(col.column(align=True), context, notes, "INFO")
    else:
        row.operator(operator.bl_idname, text="Estimate time and size", icon="TIME")


def _job_row(layout, bake, apply):
    """The big row: the bake (greyed while any job of the program runs) and
    its Apply. Returns (row, whether a job runs)."""
    row = layout.row(align=True)
    row.scale_y = 1.4
    sub = row.row(align=True)
    running = ProgramJob._running  # not the saved flag: a .blend may keep it
    sub.enabled = not running
    sub.operator(bake.bl_idname, icon="RENDER_STILL")
    row.operator(apply.bl_idname, icon="MATERIAL")
    return row, running


class CLOTHBAKE_PT_bake(_ObjectPanel, bpy.types.Panel):
    bl_label = "Bake"
    bl_parent_id = "CLOTHBAKE_PT_object"

    def draw(self, context):
        layout = self.layout
        settings = context.scene.clothbake
        col = _split_column(layout)
        col.prop(settings, "scene_path")
        col.prop(settings, "bake_dir")
        col.prop(settings, "adaptive")
        col.prop(settings, "directions")
        if settings.adaptive:
            col.prop(settings, "texels_per_pixel")
        else:
            col.prop(settings, "texels")
        col.prop(settings, "bake_spp")
        _estimate_row(col, context, estimate_is_current(context), settings.bake_estimate,
                      CLOTHBAKE_OT_estimate)
        col.prop(settings, "compare_samples")
        row, running = _job_row(layout, CLOTHBAKE_OT_bake, CLOTHBAKE_OT_apply)
        row.operator(CLOTHBAKE_OT_compare.bl_idname, icon="IMAGE_REFERENCE")
        if running and settings.bake_running:
            layout.prop(settings, "bake_progress", text="Baking (Esc cancels)", slider=True)
        if denoiser_missing(context.scene):
            # The first F12 after Apply would fail, and look like our fault;
            # said here, under Apply, where the user is.
            box = layout.box()
            box.alert = True
            box.label(text="No denoiser here: F12 fails",
                      icon="ERROR")
            box.operator(CLOTHBAKE_OT_denoising_off.bl_idname, icon="CHECKMARK")
        if settings.bake_status:
            layout.label(text="Bake: " + settings.bake_status)
        if settings.compare_status:
            layout.label(text="Compare: " + settings.compare_status)


class CLOTHBAKE_PT_material(_ObjectPanel, bpy.types.Panel):
    """The cloth material: baked once from the active cloth object's cloth
    (every view, light and distance), put on any mesh with a UV map."""
    bl_label = "Material"
    bl_parent_id = "CLOTHBAKE_PT_object"

    def draw(self, context):
        layout = self.layout
        settings = context.scene.clothbake
        col = _split_column(layout)
        col.prop(settings, "material_dir")
        col.prop(settings, "material_address")
        for setting in MATERIAL_SETTINGS:
            col.prop(settings, setting.prop)
        col.prop(settings, "material_route")
        _estimate_row(col, context, material_estimate_is_current(context),
                      settings.material_estimate, CLOTHBAKE_OT_material_estimate)
        _, running = _job_row(layout, CLOTHBAKE_OT_bake_material, CLOTHBAKE_OT_apply_material)
        if running and settings.material_running:
            layout.prop(settings, "material_progress", text="Baking material (Esc cancels)",
                        slider=True)
        if settings.material_status:
            layout.label(text="Material: " + settings.material_status)


class CLOTHBAKE_PT_reference(_ObjectPanel, bpy.types.Panel):
    bl_label = "Reference render settings"
    bl_parent_id = "CLOTHBAKE_PT_object"
    bl_options = {"DEFAULT_CLOSED"}

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        settings = context.scene.clothbake
        for prop in ("render_spp", "step_cells", "fiber_model", "fiber_samples", "transmittance",
                     "shading", "cutoff", "render_seed"):
            layout.prop(settings, prop)


def _menu_import(self, context):
    self.layout.operator(CLOTHBAKE_OT_import_scene.bl_idname, text="clothbake scene (.json)")


def _menu_export(self, context):
    self.layout.operator(CLOTHBAKE_OT_export_scene.bl_idname, text="clothbake scene (.json)")


CLASSES = (CLOTHBAKE_PT_object, CLOTHBAKE_PT_cloth, CLOTHBAKE_PT_bake, CLOTHBAKE_PT_material,
           CLOTHBAKE_PT_reference)


def register_extra():
    bpy.types.TOPBAR_MT_file_import.append(_menu_import)
    bpy.types.TOPBAR_MT_file_export.append(_menu_export)


def unregister_extra():
    bpy.types.TOPBAR_MT_file_export.remove(_menu_export)
    bpy.types.TOPBAR_MT_file_import.remove(_menu_import)
