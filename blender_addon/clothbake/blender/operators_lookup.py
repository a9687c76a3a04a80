"""Bake (a per-scene lookup, the clothbake program in the background), its
Estimate, and Apply (a lookup onto meshes)."""
import json

import bpy

from ..core import program as runner
from ..core.errors import ClothbakeError
from ..core.lookup_manifest import read_manifest
from . import prefs
from .lookup_apply import apply_lookup
from .operators_job import EstimateJob, ProgramJob, program_path
from .scene_export_bpy import scene_file_for_bake, scene_file_for_estimate
from .targets import is_mesh, selected_else_active


def bake_command(context):
    """(argv, bake folder, scene file) of the bake: the scene file exported
    when it no longer describes the scene. Raises ClothbakeError."""
    program = program_path(context)
    scene_path, _ = scene_file_for_bake(context.scene)
    bake_dir = context.scene.clothbake.bake_folder()
    return _bake_arguments(context, program, scene_path, bake_dir), bake_dir, scene_path


def _bake_arguments(context, program, scene_path, bake_dir):
    settings = context.scene.clothbake
    args = [program, "bake", scene_path, "-o", bake_dir, "--direction-map", "hemi-octahedral",
            "--directions", str(settings.directions), "--texels", str(settings.texels),
            "--spp", str(settings.bake_spp), "--threads", str(prefs.threads(context))]
    if settings.adaptive:
        args += ["--adaptive", "--texels-per-pixel", "%g" % settings.texels_per_pixel]
    return args


def estimate_bake(context):
    """Runs `clothbake bake ... --estimate` for the bake the panel would
    start: the program plans it and times a small probe of the real work,
    before any bake. Writes no file and changes no setting: a scene that
    changed since its scene file is exported to a temporary folder. Stores
    the summary in scene.clothbake.bake_estimate (with the command it is
    for) and returns (seconds, bytes). Raises ClothbakeError."""
    program = program_path(context)
    bake_dir = context.scene.clothbake.bake_folder()
    if not bake_dir:
        raise ClothbakeError("set a bake folder (or export the scene first)", "", "bake folder")
    with scene_file_for_estimate(context.scene) as scene_path:
        args = _bake_arguments(context, program, scene_path, bake_dir)
        report = json.loads(runner.run(args + ["--estimate"], "bake"))
    seconds = float(report["seconds_estimated"]) + float(report.get("setup_seconds", 0.0))
    size = int(report["bytes_uncompressed"])
    settings = context.scene.clothbake
    settings.bake_estimate = runner.estimate_text(seconds, size)
    settings.bake_estimate_for = _settings_key(context)
    return seconds, size


def _settings_key(context):
    """What an estimate depends on: the bake settings and the scene file."""
    s = context.scene.clothbake
    return json.dumps([s.scene_path, s.adaptive, s.directions, s.texels, s.bake_spp,
                       round(s.texels_per_pixel, 6), prefs.threads(context)])


def estimate_is_current(context):
    s = context.scene.clothbake
    return bool(s.bake_estimate) and s.bake_estimate_for == _settings_key(context)


def _bake_summary(bake_dir):
    try:
        stats = read_manifest(bake_dir).statistics
        return f"baked in {stats['bake_seconds']:.1f} s, {stats['direction_tiles']} direction " \
               f"tiles, {stats['texels']} texels: {bake_dir}"
    except (ClothbakeError, KeyError, TypeError, ValueError):
        return f"baked: {bake_dir}"


def _reapply(op, scene, bake_dir):
    """Objects showing this folder's previous lookup get the new one (its
    layout may differ, so the mesh layers are written again)."""
    for obj in scene.objects:
        if obj.type == "MESH" and obj.get("clothbake_lookup") == bake_dir:
            try:
                apply_lookup(obj, bake_dir)
            except ClothbakeError as e:
                op.report({"WARNING"}, f"{obj.name}: the new lookup was not applied: {e}")


class CLOTHBAKE_OT_bake(ProgramJob, bpy.types.Operator):
    """Bake the scene's cloth into a lookup with the clothbake program (Esc cancels)"""
    bl_idname = "clothbake.bake"
    bl_label = "Bake"
    _kind = "bake"
    _verb = "baking"
    _thing = "lookup"
    _advice = ("Esc cancels it once started. Lower Texels or Samples, or tick",
               "Adaptive, for a quicker bake. Start it?")
    _estimator = staticmethod(estimate_bake)

    def _command(self, context):
        args, bake_dir, _ = bake_command(context)
        return args, bake_dir

    def _succeeded(self, scene, bake_dir):
        settings = scene.clothbake
        settings.bake_status = _bake_summary(bake_dir)
        self.report({"INFO"}, "clothbake " + settings.bake_status)
        _reapply(self, scene, bake_dir)
        return {"FINISHED"}


class CLOTHBAKE_OT_estimate(EstimateJob, bpy.types.Operator):
    """Estimate the seconds and bytes of the bake these settings would start (the program plans it and times a small sample of the work)"""
    bl_idname = "clothbake.estimate"
    bl_label = "Estimate"
    _kind = "bake"
    _estimator = staticmethod(estimate_bake)


class CLOTHBAKE_OT_apply(bpy.types.Operator):
    """Apply the baked lookup to the selected meshes (a material of plain Cycles nodes)"""
    bl_idname = "clothbake.apply"
    bl_label = "Apply"
    bl_options = {"REGISTER", "UNDO"}

    def execute(self, context):
        objs = selected_else_active(context, is_mesh)
        if not objs:
            self.report({"ERROR"}, "select the cloth meshes to apply a lookup to")
            return {"CANCELLED"}
        default = context.scene.clothbake.bake_folder()
        applied, failed = [], 0
        for obj in objs:
            folder = bpy.path.abspath(obj.clothbake.lookup_dir) if obj.clothbake.lookup_dir \
                else default
            try:
                if not folder:
                    raise ClothbakeError("no lookup folder: set the bake folder or bake first")
                _, notes = apply_lookup(obj, folder)
            except ClothbakeError as e:
                failed += 1
                self.report({"ERROR"}, f"{obj.name}: {e}")
                continue
            applied.append(obj.name)
            for note in notes:
                self.report({"WARNING"}, f"{obj.name}: {note}")
        if not applied:
            return {"CANCELLED"}
        self.report({"INFO"}, f"Applied the lookup to {', '.join(applied)}"
                    + (f" ({failed} failed)" if failed else ""))
        return {"FINISHED"}


CLASSES = (CLOTHBAKE_OT_bake, CLOTHBAKE_OT_estimate, CLOTHBAKE_OT_apply)
