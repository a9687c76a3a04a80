"""The add-on's operators: import / export a clothbake scene, Bake (the
clothbake program in the background, with progress, cancellable with Esc),
Apply (a lookup onto meshes) and Compare (Cycles against clothbake's
reference renderer).

Every refused input is a ClothbakeError, reported as an ERROR with the
program's or the reader's message ("file: field: message") and the
operator cancelled: never a traceback.
"""
import json
import os
import queue
import re
import shutil
import subprocess
import threading
import time

import bpy
from bpy_extras.io_utils import ExportHelper, ImportHelper

from ..core import scene_export
from ..core.defaults import folder_siblings
from ..core.errors import ClothbakeError
from ..core.scene import load_scene
from . import prefs
from .apply import apply_lookup
from .props import read_cloth_file
from .scene_export_bpy import build_model, cloth_objects, export_scene, scene_file_for_bake
from .scene_import import import_scene, set_render_settings

_PROGRESS = re.compile(r"^(?:bake|render|material)\s+(\d+)%")
_ERROR_PREFIX = "clothbake: error: "


def _program(context):
    program = prefs.program_path(context)
    if program is None:
        raise ClothbakeError("the clothbake program was not found; set its path in the add-on's "
                             "preferences (Edit > Preferences > Add-ons > clothbake)")
    return program


def _program_error(stderr_lines, command, code):
    """The program's own error message, else its last lines."""
    for line in reversed(stderr_lines):
        if line.startswith(_ERROR_PREFIX):
            return line[len(_ERROR_PREFIX):].strip()
    tail = " | ".join(l.strip() for l in stderr_lines[-3:] if l.strip())
    return f"clothbake {command} failed (exit status {code})" + (f": {tail}" if tail else "")


def _run(args, command):
    """Runs the program to its end; returns stdout. Raises ClothbakeError
    with the program's message when it fails."""
    try:
        run = subprocess.run(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                             stdin=subprocess.DEVNULL)
    except OSError as e:
        raise ClothbakeError(f"cannot run the clothbake program: {e.strerror}", args[0]) from None
    if run.returncode != 0:
        raise ClothbakeError(_program_error(run.stderr.splitlines(), command, run.returncode))
    return run.stdout


def _redraw(context):
    wm = context.window_manager
    for window in wm.windows:
        for area in window.screen.areas:
            area.tag_redraw()


# -- import / export -----------------------------------------------------------

class CLOTHBAKE_OT_import_scene(bpy.types.Operator, ImportHelper):
    """Import a clothbake scene (camera, lights, cloth meshes and settings)"""
    bl_idname = "clothbake.import_scene"
    bl_label = "Import clothbake scene"
    bl_options = {"REGISTER", "UNDO"}

    filename_ext = ".json"
    filter_glob: bpy.props.StringProperty(default="*.json", options={"HIDDEN"})
    clear: bpy.props.BoolProperty(name="Replace scene objects", default=True,
                                  description="Remove the scene's objects before importing")

    def execute(self, context):
        try:
            model = load_scene(self.filepath)
            for o in model["objects"]:  # every cloth spec readable before anything changes
                if "cloth_path" in o:
                    read_cloth_file(o["cloth_path"])
            settings = context.scene.clothbake
            objects = import_scene(self.filepath, clear=self.clear,
                                   samples=settings.compare_samples)
        except ClothbakeError as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        settings.scene_path = model["path"]
        settings.load_render(model["json"].get("render"))
        settings.bake_status = ""
        settings.compare_status = ""
        if objects:
            for obj in context.scene.objects:
                if obj.name in context.view_layer.objects:
                    obj.select_set(obj in objects)
            context.view_layer.objects.active = objects[0]
        self.report({"INFO"}, f"Imported {len(objects)} cloth object(s) from {model['path']}")
        return {"FINISHED"}


class CLOTHBAKE_OT_export_scene(bpy.types.Operator, ExportHelper):
    """Export the scene as a clothbake scene (scene JSON and one OBJ per cloth object)"""
    bl_idname = "clothbake.export_scene"
    bl_label = "Export clothbake scene"

    filename_ext = ".json"
    filter_glob: bpy.props.StringProperty(default="*.json", options={"HIDDEN"})

    def execute(self, context):
        try:
            path = export_scene(context.scene, self.filepath)
        except ClothbakeError as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        self.report({"INFO"}, f"Exported {path}")
        return {"FINISHED"}


# -- bake ----------------------------------------------------------------------

def _bake_command(context):
    """(argv, bake folder, scene file) of the bake. Raises ClothbakeError."""
    settings = context.scene.clothbake
    program = _program(context)
    scene_path, _ = scene_file_for_bake(context.scene)
    bake_dir = settings.bake_folder()
    args = [program, "bake", scene_path, "-o", bake_dir, "--direction-map", "hemi-octahedral",
            "--directions", str(settings.directions), "--texels", str(settings.texels),
            "--spp", str(settings.bake_spp), "--threads", str(prefs.threads(context))]
    if settings.adaptive:
        args += ["--adaptive", "--texels-per-pixel", "%g" % settings.texels_per_pixel]
    return args, bake_dir, scene_path


def _duration(seconds):
    if seconds < 90:
        return f"{seconds:.0f} s"
    if seconds < 5400:
        return f"{seconds / 60:.0f} min"
    return f"{seconds / 3600:.1f} h"


def estimate_bake(context):
    """Runs `clothbake bake ... --estimate` for the bake the panel would
    start: the program plans it and times a small probe of the real work,
    before any bake. Stores the summary in scene.clothbake.bake_estimate
    (with the command it is for) and returns (seconds, bytes).
    Raises ClothbakeError."""
    args, _, _ = _bake_command(context)
    report = json.loads(_run(args + ["--estimate"], "bake"))
    seconds = float(report["seconds_estimated"]) + float(report.get("setup_seconds", 0.0))
    size = int(report["bytes_uncompressed"])
    settings = context.scene.clothbake
    # Short: the panel is narrow (the tooltip of the button has the rest).
    settings.bake_estimate = f"about {_duration(seconds)}, {max(1, round(size / 2**20))} MiB"
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


# A bake estimated to take longer than this asks before it starts.
CONFIRM_SECONDS = 60.0


def _clean_after_kill(bake_dir, pid):
    """What a killed bake may leave (docs/lookup-format.md "Folder layout"):
    its temporary folder, or an old folder half swapped out."""
    temp, old = folder_siblings(bake_dir, pid)
    shutil.rmtree(temp, ignore_errors=True)
    if os.path.isdir(old):
        if os.path.isdir(bake_dir):
            shutil.rmtree(old, ignore_errors=True)
        else:
            os.replace(old, bake_dir)


def kill_job(proc, out_dir):
    """Ends a running bake (lookup or material) and removes what it left:
    SIGTERM (its output is only ever written atomically), SIGKILL after 10 s."""
    proc.terminate()
    try:
        proc.wait(timeout=10)
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.wait()
    _clean_after_kill(out_dir, proc.pid)


def _bake_summary(bake_dir):
    try:
        with open(os.path.join(bake_dir, "manifest.json"), encoding="utf-8") as f:
            stats = json.load(f).get("statistics", {})
        return f"baked in {stats['bake_seconds']:.1f} s, {stats['direction_tiles']} direction " \
               f"tiles, {stats['texels']} texels: {bake_dir}"
    except (OSError, ValueError, KeyError, TypeError):
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


class _ProgramJob:
    """The program run in the background for an operator (Bake, Bake
    material): modal, progress from its stderr lines ("bake NN%", "material
    NN%"), Esc kills it and removes what it left half-written; an estimate
    first, and a confirmation dialog when it is over CONFIRM_SECONDS.
    Synchronous in background mode and scripts. One job at a time, whichever
    kind (the machine's cores are the job's).

    A subclass states `_kind` (the settings' prefix: bake_running,
    bake_progress, bake_status; material_...), `_verb`, and implements
    _command(context) -> (argv, output folder), _estimate(context) ->
    seconds, _succeeded(scene, folder) -> status text, _dialog_lines."""
    _running = False  # one job at a time: set on _ProgramJob itself
    _kind = "bake"
    _verb = "baking"

    def _set(self, scene, name, value):
        setattr(scene.clothbake, f"{self._kind}_{name}", value)

    def _get(self, scene, name):
        return getattr(scene.clothbake, f"{self._kind}_{name}")

    def _start_report(self, scene, out_dir):
        self._set(scene, "running", True)
        self._set(scene, "progress", 0.0)
        self._set(scene, "status", f"{self._verb} into {out_dir}")

    def _finish(self, scene, code, stderr_lines, out_dir):
        self._set(scene, "running", False)
        if code == 0:
            self._set(scene, "progress", 1.0)
            try:
                return self._succeeded(scene, out_dir)
            except ClothbakeError as e:  # baked, but not applied
                self._set(scene, "status", f"baked into {out_dir}, not applied: {e}")
                _report_error(self, e)
                return {"CANCELLED"}
        message = _program_error(stderr_lines, self._kind, code)
        self._set(scene, "status", "failed: " + message)
        self.report({"ERROR"}, message)
        return {"CANCELLED"}

    def execute(self, context):
        """Background mode and scripts: the program runs to its end here. In
        the UI (after invoke, or its confirmation), it starts in the
        background (modal)."""
        if _ProgramJob._running:
            self.report({"ERROR"}, "a bake is running already")
            return {"CANCELLED"}
        if not bpy.app.background and context.window is not None:
            return self._start_modal(context)
        try:
            args, out_dir = self._command(context)
        except ClothbakeError as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        self._start_report(context.scene, out_dir)
        env = dict(os.environ, CLOTHBAKE_PROGRESS="lines")
        try:
            run = subprocess.run(args, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                                 stdin=subprocess.DEVNULL, text=True, env=env)
        except OSError as e:
            self._set(context.scene, "running", False)
            self.report({"ERROR"}, f"{args[0]}: cannot run the clothbake program: {e.strerror}")
            return {"CANCELLED"}
        return self._finish(context.scene, run.returncode, run.stderr.splitlines(), out_dir)

    def invoke(self, context, event):
        if bpy.app.background:
            return self.execute(context)
        if _ProgramJob._running:
            self.report({"ERROR"}, "a bake is running already")
            return {"CANCELLED"}
        # The estimate first (a second or two): a long bake asks before it
        # starts, with its seconds and bytes (issue 13: a first full bake ran
        # past 10 minutes with no word beforehand).
        try:
            seconds = self._estimate(context)
        except ClothbakeError as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        if seconds > CONFIRM_SECONDS:
            return context.window_manager.invoke_props_dialog(self, width=420)
        return self._start_modal(context)

    def draw(self, context):
        col = self.layout.column()
        for i, line in enumerate(self._dialog_lines(context)):
            col.label(text=line, icon="TIME" if i == 0 else "NONE")

    def _start_modal(self, context):
        try:
            args, self._out_dir = self._command(context)
            self._proc = subprocess.Popen(
                args, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, stdin=subprocess.DEVNULL,
                text=True, env=dict(os.environ, CLOTHBAKE_PROGRESS="lines"))
        except ClothbakeError as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        except OSError as e:
            self.report({"ERROR"}, f"cannot run the clothbake program: {e.strerror}")
            return {"CANCELLED"}
        _ProgramJob._running = True
        self._lines = []
        self._queue = queue.Queue()
        self._reader = threading.Thread(target=self._read, args=(self._proc.stderr, self._queue),
                                         daemon=True)
        self._reader.start()
        self._scene = context.scene  # the baked scene, whichever is shown later
        self._start_report(self._scene, self._out_dir)
        wm = context.window_manager
        wm.progress_begin(0, 100)
        self._timer = wm.event_timer_add(0.2, window=context.window)
        wm.modal_handler_add(self)
        context.workspace.status_text_set(f"clothbake: {self._verb} 0% (Esc to cancel)")
        return {"RUNNING_MODAL"}

    @staticmethod
    def _read(stream, out):
        for line in stream:
            out.put(line.rstrip("\n"))
        out.put(None)

    def _drain(self, context):
        done = False
        while True:
            try:
                line = self._queue.get_nowait()
            except queue.Empty:
                break
            if line is None:
                done = True
                continue
            self._lines.append(line)
            m = _PROGRESS.match(line)
            if m:
                self._set(self._scene, "progress", int(m.group(1)) / 100.0)
        percent = int(round(self._get(self._scene, "progress") * 100))
        context.window_manager.progress_update(percent)
        context.workspace.status_text_set(f"clothbake: {self._verb} {percent}% (Esc to cancel)")
        return done

    def _end_modal(self, context):
        wm = context.window_manager
        wm.event_timer_remove(self._timer)
        wm.progress_end()
        context.workspace.status_text_set(None)
        _ProgramJob._running = False
        _redraw(context)

    def _cancel(self, context):
        """Esc: the program killed, what it left half-written removed."""
        kill_job(self._proc, self._out_dir)
        self._end_modal(context)
        self._set(self._scene, "running", False)
        self._set(self._scene, "status", f"cancelled; the previous {self._thing} (if any) is "
                  "unchanged")
        self.report({"WARNING"}, f"clothbake {self._kind} cancelled")
        return {"CANCELLED"}

    def modal(self, context, event):
        if event.type == "ESC" and event.value == "PRESS":
            return self._cancel(context)
        if event.type != "TIMER":
            return {"PASS_THROUGH"}
        reader_done = self._drain(context)
        _redraw(context)
        code = self._proc.poll()
        if code is None or not reader_done:
            return {"RUNNING_MODAL"}
        self._end_modal(context)
        return self._finish(self._scene, code, self._lines, self._out_dir)


class CLOTHBAKE_OT_bake(_ProgramJob, bpy.types.Operator):
    """Bake the scene's cloth into a lookup with the clothbake program (Esc cancels)"""
    bl_idname = "clothbake.bake"
    bl_label = "Bake"
    _kind = "bake"
    _verb = "baking"
    _thing = "lookup"

    def _command(self, context):
        args, bake_dir, _ = _bake_command(context)
        return args, bake_dir

    def _estimate(self, context):
        return estimate_bake(context)[0]

    def _succeeded(self, scene, bake_dir):
        settings = scene.clothbake
        settings.bake_status = _bake_summary(bake_dir)
        self.report({"INFO"}, "clothbake " + settings.bake_status)
        _reapply(self, scene, bake_dir)
        return {"FINISHED"}

    def _dialog_lines(self, context):
        return [f"This bake takes {context.scene.clothbake.bake_estimate}.",
                "Esc cancels it once started. Lower Texels or Samples, or tick",
                "Adaptive, for a quicker bake. Start it?"]


class CLOTHBAKE_OT_estimate(bpy.types.Operator):
    """Estimate the seconds and bytes of the bake these settings would start (the program plans it and times a small sample of the work)"""
    bl_idname = "clothbake.estimate"
    bl_label = "Estimate"

    def execute(self, context):
        try:
            estimate_bake(context)
        except ClothbakeError as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        self.report({"INFO"}, "clothbake bake: " + context.scene.clothbake.bake_estimate)
        return {"FINISHED"}


# -- apply ---------------------------------------------------------------------

def _targets(context):
    objs = [o for o in context.selected_objects if o.type == "MESH"]
    active = context.active_object
    if not objs and active is not None and active.type == "MESH":
        objs = [active]
    return objs


class CLOTHBAKE_OT_apply(bpy.types.Operator):
    """Apply the baked lookup to the selected meshes (a material of plain Cycles nodes)"""
    bl_idname = "clothbake.apply"
    bl_label = "Apply"
    bl_options = {"REGISTER", "UNDO"}

    def execute(self, context):
        objs = _targets(context)
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


# -- the cloth material ----------------------------------------------------------

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
    was (the material folder's default is named after it)."""
    model = build_model(scene)
    settings = scene.clothbake
    current = os.path.abspath(bpy.path.abspath(settings.scene_path)) if settings.scene_path \
        else ""
    if current and scene_export.scene_matches_file(model, current):
        return current
    return scene_export.write_scene(model, os.path.join(folder + ".scene", "scene.json"))


def _material_command(context):
    """(argv, material folder) of the material bake. Raises ClothbakeError."""
    settings = context.scene.clothbake
    program = _program(context)
    texels = settings.material_texels
    if texels & (texels - 1):
        raise ClothbakeError(f"must be a power of 2 (8, 16, 32, 64, ...), got {texels}", "",
                             "material Texels")
    _, index = _material_target(context)
    folder = settings.material_folder()
    if not folder:
        raise ClothbakeError("set a material folder (or save the .blend file, or export the "
                             "scene first)", "", "material folder")
    scene_path = _material_scene_file(context.scene, folder)
    if not settings.material_dir:
        settings.material_dir = folder  # kept when the scene file changes
    args = [program, "material", scene_path, "--object", str(index), "-o", folder,
            "--texels", str(texels), "--directions", str(settings.material_directions),
            "--light-directions", str(settings.material_light_directions),
            "--spp", str(settings.material_spp), "--max-error", "%g" % settings.material_max_error,
            "--threads", str(prefs.threads(context))]
    return args, folder


def _material_key(context):
    """What a material estimate depends on: the settings, object and scene."""
    s = context.scene.clothbake
    obj = context.active_object
    return json.dumps([s.scene_path, s.material_folder(), obj.name if obj else "",
                       s.material_texels, s.material_directions, s.material_light_directions,
                       s.material_spp, round(s.material_max_error, 6), prefs.threads(context)])


def material_estimate_is_current(context):
    s = context.scene.clothbake
    return bool(s.material_estimate) and s.material_estimate_for == _material_key(context)


def estimate_material(context):
    """Runs `clothbake material ... --estimate` for the bake the panel would
    start (the program times a probe of the real work and writes nothing).
    Stores the summary in scene.clothbake.material_estimate and returns
    (seconds, bytes of the table at full rank, an upper bound). Raises
    ClothbakeError."""
    args, _ = _material_command(context)
    report = json.loads(_run(args + ["--estimate"], "material"))
    seconds = float(report["seconds"])
    size = int(report["max_bytes"])
    settings = context.scene.clothbake
    settings.material_estimate = f"about {_duration(seconds)}, up to " \
                                 f"{max(1, round(size / 2**20))} MiB"
    settings.material_estimate_for = _material_key(context)
    return seconds, size


def _material_targets(context):
    objs = list(context.selected_objects)
    active = context.active_object
    if not objs and active is not None:
        objs = [active]
    return objs


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
        raise _Refused(refused)
    applied = []
    for obj in objs:
        _, notes = apply_material(obj, folder, route=route)
        applied.append(obj.name)
        for note in notes:
            op.report({"WARNING"}, f"{obj.name}: {note}")
    return applied


class _Refused(ClothbakeError):
    """Several objects refused at once: one report each."""

    def __init__(self, errors):
        super().__init__("; ".join(str(e) for e in errors))
        self.errors = errors


def _report_error(op, e):
    for err in getattr(e, "errors", [e]):
        op.report({"ERROR"}, str(err))


def _material_summary(folder):
    try:
        with open(os.path.join(folder, "manifest.json"), encoding="utf-8") as f:
            m = json.load(f)
        return f"baked: {m['texels']} texels, {m['directions']} view and " \
               f"{m['light_directions']} light directions, rank up to {m['max_rank']}: {folder}"
    except (OSError, ValueError, KeyError, TypeError):
        return f"baked: {folder}"


class CLOTHBAKE_OT_bake_material(_ProgramJob, bpy.types.Operator):
    """Bake the active cloth object's cloth into a material (every view, light and distance) with the clothbake program, then apply it to the selected meshes (Esc cancels)"""
    bl_idname = "clothbake.bake_material"
    bl_label = "Bake material"
    _kind = "material"
    _verb = "baking material"
    _thing = "material"

    def _command(self, context):
        return _material_command(context)

    def _estimate(self, context):
        return estimate_material(context)[0]

    def _succeeded(self, scene, folder):
        settings = scene.clothbake
        settings.material_status = _material_summary(folder)
        objs = [o for o in bpy.context.selected_objects if o.name in scene.objects]
        if not objs and bpy.context.active_object is not None:
            objs = [bpy.context.active_object]
        applied = apply_material_to(self, objs, folder, settings.material_route)
        self.report({"INFO"}, f"clothbake material {settings.material_status}; applied to "
                    f"{', '.join(applied)}")
        return {"FINISHED"}

    def _dialog_lines(self, context):
        return [f"This material bake takes {context.scene.clothbake.material_estimate}.",
                "Esc cancels it once started. Lower Texels, View or Light",
                "directions, or Samples, for a quicker bake. Start it?"]


class CLOTHBAKE_OT_material_estimate(bpy.types.Operator):
    """Estimate the seconds and size of the material bake these settings would start (the program times a small probe of the real work and writes nothing)"""
    bl_idname = "clothbake.material_estimate"
    bl_label = "Estimate"

    def execute(self, context):
        try:
            estimate_material(context)
        except ClothbakeError as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        self.report({"INFO"}, "clothbake material: " + context.scene.clothbake.material_estimate)
        return {"FINISHED"}


class CLOTHBAKE_OT_apply_material(bpy.types.Operator):
    """Put the baked cloth material on the selected meshes (any mesh with a UV map), lit live by the scene's lights"""
    bl_idname = "clothbake.apply_material"
    bl_label = "Apply material"
    bl_options = {"REGISTER", "UNDO"}

    def execute(self, context):
        settings = context.scene.clothbake
        try:
            applied = apply_material_to(self, _material_targets(context),
                                        settings.material_folder(), settings.material_route)
        except ClothbakeError as e:
            _report_error(self, e)
            return {"CANCELLED"}
        except ImportError as e:
            self.report({"ERROR"}, f"this add-on cannot build materials here: {e}")
            return {"CANCELLED"}
        self.report({"INFO"}, f"Applied the cloth material ({settings.material_route}) to "
                    f"{', '.join(applied)}")
        return {"FINISHED"}


# -- compare -------------------------------------------------------------------

def _scene_key(path):
    st = os.stat(path)
    return {"scene": os.path.abspath(path), "mtime_ns": st.st_mtime_ns, "size": st.st_size}


def _reference(context, program, scene_path, folder):
    """FOLDER/reference.exr rendered by clothbake from the scene file, reused
    while the scene file is unchanged (path, mtime and size)."""
    ref = os.path.join(folder, "reference.exr")
    key_path = os.path.join(folder, "reference.json")
    key = _scene_key(scene_path)
    try:
        with open(key_path, encoding="utf-8") as f:
            if json.load(f) == key and os.path.isfile(ref):
                return ref, True
    except (OSError, ValueError):
        pass
    _run([program, "render", scene_path, "-o", ref, "--quiet",
          "--threads", str(prefs.threads(context))], "render")
    with open(key_path + ".tmp", "w", encoding="utf-8") as f:
        json.dump(key, f)
    os.replace(key_path + ".tmp", key_path)
    return ref, False


def _save_render(scene, path):
    tmp = f"{path}.tmp-{os.getpid()}.exr"
    bpy.data.images["Render Result"].save_render(tmp, scene=scene)
    os.replace(tmp, path)


def _load_image(name, path):
    image = bpy.data.images.get(name)
    if image is not None and os.path.abspath(bpy.path.abspath(image.filepath)) == path:
        image.reload()
        return image
    if image is not None:
        bpy.data.images.remove(image)
    image = bpy.data.images.load(path)
    image.name = name
    return image


def _show(context, image):
    """Shows the image in an Image Editor: an open one, else a new window."""
    for window in context.window_manager.windows:
        for area in window.screen.areas:
            if area.type == "IMAGE_EDITOR":
                area.spaces.active.image = image
                return True
    try:
        bpy.ops.render.view_show("INVOKE_DEFAULT")
    except RuntimeError:
        return False
    for window in context.window_manager.windows:
        for area in window.screen.areas:
            if area.type == "IMAGE_EDITOR":
                area.spaces.active.image = image
                return True
    return False


class CLOTHBAKE_OT_compare(bpy.types.Operator):
    """Render the scene with Cycles and compare it with clothbake's reference render"""
    bl_idname = "clothbake.compare"
    bl_label = "Compare"

    def execute(self, context):
        scene = context.scene
        settings = scene.clothbake
        try:
            program = _program(context)
            if not any(o.get("clothbake_lookup") for o in cloth_objects(scene)):
                raise ClothbakeError("no cloth object has a lookup: Bake and Apply first")
            scene_path, _ = scene_file_for_bake(scene)
            model = load_scene(scene_path)
            folder = settings.bake_folder() + "_compare"
            os.makedirs(folder, exist_ok=True)
            ref, cached = _reference(context, program, scene_path, folder)
            # Cycles set up as clothbake's renderer (box filter, no bounces, ...).
            set_render_settings(scene, model["camera"], model["background"],
                                samples=settings.compare_samples,
                                seed=int(model["render"].get("seed", 1)) & 0x7FFFFFFF)
            start = time.perf_counter()
            bpy.ops.render.render(write_still=False)
            seconds = time.perf_counter() - start
            cycles = os.path.join(folder, "cycles.exr")
            _save_render(scene, cycles)
            heat = os.path.join(folder, "difference.png")
            sheet = os.path.join(folder, "sheet.png")
            metrics = json.loads(_run([program, "compare", ref, cycles, "--heatmap", heat,
                                       "--sheet", sheet, "--json"], "compare"))
        except ClothbakeError as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        except OSError as e:
            self.report({"ERROR"}, f"{e.filename}: {e.strerror}")
            return {"CANCELLED"}
        settings.compare_status = (f"PSNR {metrics['psnr']:.2f} dB, relative RMSE "
                                   f"{metrics['relative_rmse']:.4f} (Cycles {seconds:.1f} s at "
                                   f"{settings.compare_samples} samples"
                                   f"{', cached reference' if cached else ''})")
        if not bpy.app.background:
            images = [_load_image(n, p) for n, p in (("clothbake reference", ref),
                                                      ("clothbake cycles", cycles),
                                                      ("clothbake difference", heat),
                                                      ("clothbake comparison", sheet))]
            _show(context, images[-1])
        self.report({"INFO"}, f"clothbake compare: {settings.compare_status}; files in {folder}")
        return {"FINISHED"}


# -- Cycles without a denoiser ---------------------------------------------------

def denoiser_missing(scene):
    """True when F12 would fail: Cycles renders with denoising on, and this
    Blender was built without OpenImageDenoise (Debian's 3.4 is), so the
    render stops with "Build without OpenImageDenoiser"."""
    if scene.render.engine != "CYCLES" or not scene.cycles.use_denoising:
        return False
    try:
        import _cycles
    except ImportError:
        return False
    return not getattr(_cycles, "with_openimagedenoise", True)


class CLOTHBAKE_OT_denoising_off(bpy.types.Operator):
    """Turn Cycles' render denoising off: this Blender has no denoiser, so F12 fails with it on"""
    bl_idname = "clothbake.denoising_off"
    bl_label = "Turn render denoising off"
    bl_options = {"REGISTER", "UNDO"}

    def execute(self, context):
        context.scene.cycles.use_denoising = False
        self.report({"INFO"}, "Cycles render denoising is off (this Blender has no denoiser)")
        return {"FINISHED"}


CLASSES = (CLOTHBAKE_OT_import_scene, CLOTHBAKE_OT_export_scene, CLOTHBAKE_OT_bake,
           CLOTHBAKE_OT_estimate, CLOTHBAKE_OT_apply, CLOTHBAKE_OT_compare,
           CLOTHBAKE_OT_denoising_off, CLOTHBAKE_OT_bake_material,
           CLOTHBAKE_OT_material_estimate, CLOTHBAKE_OT_apply_material)
