"""The cloth material's operators: Bake material (the clothbake program in
the background, from the active cloth object), its Estimate, and Apply
material (onto any mesh with a UV map)."""
import json
import os

import bpy

from ..core import program as runner
from ..core import scene_export, scene_match
from ..core.defaults import MATERIAL_DEFAULTS
from ..core.errors import ClothbakeError
from ..core.material_manifest import read_material
from ..core.material_settings import (check_material_values, material_arguments, material_key,
                                      material_values)
from . import prefs
from .operators_job import EstimateJob, ProgramJob, Refused, program_path, report_error
from .scene_export_bpy import build_model, cloth_objects, scene_file_for_estimate
from .targets import selected_else_active


def _material_target(context):
    """(object, index among the scene's cloth objects, as the export writes
    them) of the cloth the material is baked from: the active object."""
    obj = context.active_object
    if obj is None or obj.type != "MESH":
        raise ClothbakeError("make the cloth object active (a mesh with 'Cloth' ticked in its "
                             "clothbake panel): the material is baked from its cloth")
    if not obj.clothbake.is_cloth:
        raise ClothbakeError(f"object '{obj.name}' is not a cloth: tick 'Cloth' in its clothbake "
                             "panel (Object properties) and pick a weave; the material is baked "
                             "from its cloth")
    return obj, cloth_objects(context.scene).index(obj)


def _material_scene_file(scene, folder):
    """The scene file the material bake reads (the cloth object's optics):
    the scene file while it still describes the Blender scene, else a fresh
    export to FOLDER.scene/scene.json. The scene file setting is left as it
    was (the material folder's default is named after it). A light the
    export would refuse (an area light's Spread below 180 degrees, a spot
    scaled unevenly) is left out: a material bake needs no lights."""
    model = build_model(scene, supported_lights_only=True)
    settings = scene.clothbake
    current = os.path.abspath(bpy.path.abspath(settings.scene_path)) if settings.scene_path \
        else ""
    if current and scene_match.scene_matches_file(model, current):
        return current
    return scene_export.write_scene(model, os.path.join(folder + ".scene", "scene.json"))


def _material_job(context):
    """(program, object index, material folder) of the material bake, each
    checked. Raises ClothbakeError."""
    settings = context.scene.clothbake
    program = program_path(context)
    check_material_values(material_values(settings))
    _, index = _material_target(context)
    folder = settings.material_folder()
    if not folder:
        raise ClothbakeError("set a material folder (or save the .blend file, or export the "
                             "scene first)", "", "material folder")
    return program, index, folder


def _material_arguments(context, program, scene_path, index, folder):
    settings = context.scene.clothbake
    # --parts auto: a fibre-shaded cloth bakes colour-free, so the panel's
    # colours recolour the applied material with no bake (docs/design/material.md).
    # Automatic with Texels at its default: the program chooses the texels
    # with the address (32 over the whole repeat, 8 per crossing); Texels
    # the user set are kept whichever address it takes.
    args = material_arguments(material_values(settings))
    if settings.material_address == "auto" and \
            settings.material_texels == MATERIAL_DEFAULTS["texels"]:
        i = args.index("--texels")
        del args[i:i + 2]
    return [program, "material", scene_path, "--object", str(index), "-o", folder, *args,
            "--address", settings.material_address, "--parts", "auto", "--threads",
            str(prefs.threads(context))]


def material_command(context):
    """(argv, material folder) of the material bake: the scene file
    exported when it no longer describes the scene, and the folder kept in
    material_dir. Raises ClothbakeError."""
    program, index, folder = _material_job(context)
    scene_path = _material_scene_file(context.scene, folder)
    settings = context.scene.clothbake
    if not settings.material_dir:
        settings.material_dir = folder  # kept when the scene file changes
    return _material_arguments(context, program, scene_path, index, folder), folder


def _estimate_key(context):
    """What a material estimate depends on: the settings, object and scene."""
    s = context.scene.clothbake
    obj = context.active_object
    return json.dumps([s.scene_path, s.material_folder(), obj.name if obj else "",
                       *material_key(material_values(s)), s.material_address,
                       prefs.threads(context)])


def material_estimate_is_current(context):
    s = context.scene.clothbake
    return bool(s.material_estimate) and s.material_estimate_for == _estimate_key(context)


def estimate_material(context):
    """Runs `clothbake material ... --estimate` for the bake the panel would
    start (the program times a probe of the real work and writes nothing).
    Nor does the add-on: no setting changes, and a scene that changed since
    its scene file is exported to a temporary folder, removed afterwards.
    Stores the summary in scene.clothbake.material_estimate and returns
    (seconds, the bake's peak memory in bytes: the program's estimate,
    within 10 % of the real peak on the real drafts). Raises
    ClothbakeError."""
    program, index, folder = _material_job(context)
    with scene_file_for_estimate(context.scene, supported_lights_only=True) as scene_path:
        args = _material_arguments(context, program, scene_path, index, folder)
        report = json.loads(runner.run(args + ["--estimate"], "material"))
    seconds = float(report["seconds"])
    size = int(report.get("peak_bytes", report["max_bytes"]))
    settings = context.scene.clothbake
    notes = [n for n in (runner.plan_note(report), runner.texels_note(report)) if n]
    estimate = runner.estimate_text(seconds, size, what="peak memory",
                                    disk=report.get("bytes_on_disk"))
    settings.material_estimate = "; ".join([estimate] + notes)
    settings.material_estimate_for = _estimate_key(context)
    return seconds, size


def apply_material_to(op, objs, folder, route):
    """Puts the material in `folder` on every object of `objs`; returns the
    names applied. Refuses (ClothbakeError per object, reported by the
    caller) a non-mesh or a mesh without a UV map before changing anything."""
    from .material_apply import apply_material, uv_map_name  # the material's node builder
    if not objs:
        raise ClothbakeError("select the meshes to put the material on (any mesh with a UV map)")
    if not folder or not os.path.isfile(os.path.join(folder, "manifest.json")):
        raise ClothbakeError(f"no material in {folder or 'the material folder'}: Bake material "
                             "first, or set the material folder", "", "material folder")
    refused = []
    for obj in objs:
        if obj.type != "MESH":
            refused.append(ClothbakeError(
                f"object '{obj.name}' is a {obj.type.lower()}, not a mesh; the material goes "
                "on meshes with a UV map"))
        elif uv_map_name(obj) is None:
            refused.append(ClothbakeError(
                f"object '{obj.name}': mesh has no UV map; add one (UV > Unwrap in Edit Mode) "
                "so the weave has a place on it"))
    if refused:
        raise Refused(refused)
    applied = []
    for obj in objs:
        _, notes = apply_material(obj, folder, route=route)
        applied.append(obj.name)
        for note in notes:
            op.report({"WARNING"}, f"{obj.name}: {note}")
    return applied


def _material_summary(folder):
    try:
        info = read_material(folder)
        texels = f"{info.texels} texels" if info.address != "crossings" else \
            f"{info.blocks} blocks of {info.texels} x {info.texels} texels over " \
            f"{info.ends} x {info.picks} crossings"
        return f"baked: {texels}, {info.k} view and {info.kl} light directions, " \
               f"rank up to {info.max_rank}: {folder}"
    except ClothbakeError:
        return f"baked: {folder}"


class CLOTHBAKE_OT_bake_material(ProgramJob, bpy.types.Operator):
    """Bake the active cloth object's cloth into a material (every view, light and distance) with the clothbake program, then apply it to the selected meshes (Esc cancels)"""
    bl_idname = "clothbake.bake_material"
    bl_label = "Bake material"
    _kind = "material"
    _verb = "baking material"
    _thing = "material"
    _job = "material bake"
    _advice = ("Esc cancels it once started. Lower Texels, View or Light",
               "directions, or Samples, for a quicker bake. Start it?")
    _estimator = staticmethod(estimate_material)

    def _command(self, context):
        return material_command(context)

    def _succeeded(self, scene, folder):
        settings = scene.clothbake
        settings.material_status = _material_summary(folder)
        # bpy.context: the modal job ends in a later event, whose context is
        # the one shown now; only objects of the baked scene.
        objs = selected_else_active(bpy.context, lambda o: o.name in scene.objects)
        applied = apply_material_to(self, objs, folder, settings.material_route)
        self.report({"INFO"}, f"clothbake material {settings.material_status}; applied to "
                    f"{', '.join(applied)}")
        return {"FINISHED"}


class CLOTHBAKE_OT_material_estimate(EstimateJob, bpy.types.Operator):
    """Estimate the seconds and size of the material bake these settings would start (the program times a small probe of the real work and writes nothing)"""
    bl_idname = "clothbake.material_estimate"
    bl_label = "Estimate"
    _kind = "material"
    _estimator = staticmethod(estimate_material)


class CLOTHBAKE_OT_apply_material(bpy.types.Operator):
    """Put the baked cloth material on the selected meshes (any mesh with a UV map), lit live by the scene's lights"""
    bl_idname = "clothbake.apply_material"
    bl_label = "Apply material"
    bl_options = {"REGISTER", "UNDO"}

    def execute(self, context):
        settings = context.scene.clothbake
        try:
            applied = apply_material_to(self, selected_else_active(context),
                                        settings.material_folder(), settings.material_route)
        except ClothbakeError as e:
            report_error(self, e)
            return {"CANCELLED"}
        except ImportError as e:
            self.report({"ERROR"}, f"this add-on cannot build materials here: {e}")
            return {"CANCELLED"}
        self.report({"INFO"}, f"Applied the cloth material ({settings.material_route}) to "
                    f"{', '.join(applied)}")
        return {"FINISHED"}


CLASSES = (CLOTHBAKE_OT_bake_material, CLOTHBAKE_OT_material_estimate,
           CLOTHBAKE_OT_apply_material)
