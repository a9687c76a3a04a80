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

from ..core.defaults import folder_siblings
from ..core.errors import ClothbakeError
from ..core.scene import load_scene
from . import prefs
from .apply import apply_lookup
from .props import read_cloth_file
from .scene_export_bpy import cloth_objects, export_scene, scene_file_for_bake
from .scene_import import import_scene, set_render_settings

_PROGRESS = re.compile(r"^(?:bake|render)\s+(\d+)%")
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


class CLOTHBAKE_OT_bake(bpy.types.Operator):
    """Bake the scene's cloth into a lookup with the clothbake program (Esc cancels)"""
    bl_idname = "clothbake.bake"
    bl_label = "Bake"

    _running = False  # one bake at a time

    def _start_report(self, scene, bake_dir):
        settings = scene.clothbake
        settings.bake_running = True
        settings.bake_progress = 0.0
        settings.bake_status = f"baking into {bake_dir}"

    def _finish(self, scene, code, stderr_lines, bake_dir):
        settings = scene.clothbake
        settings.bake_running = False
        if code == 0:
            settings.bake_progress = 1.0
            settings.bake_status = _bake_summary(bake_dir)
            self.report({"INFO"}, "clothbake " + settings.bake_status)
            _reapply(self, scene, bake_dir)
            return {"FINISHED"}
        message = _program_error(stderr_lines, "bake", code)
        settings.bake_status = "failed: " + message
        self.report({"ERROR"}, message)
        return {"CANCELLED"}

    def execute(self, context):
        """Background mode and scripts: the bake runs to its end here. In
        the UI (after invoke, or its confirmation), it starts in the
        background (modal)."""
        if CLOTHBAKE_OT_bake._running:
            self.report({"ERROR"}, "a bake is running already")
            return {"CANCELLED"}
        if not bpy.app.background and context.window is not None:
            return self._start_modal(context)
        try:
            args, bake_dir, _ = _bake_command(context)
        except ClothbakeError as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        self._start_report(context.scene, bake_dir)
        env = dict(os.environ, CLOTHBAKE_PROGRESS="lines")
        try:
            run = subprocess.run(args, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                                 stdin=subprocess.DEVNULL, text=True, env=env)
        except OSError as e:
            context.scene.clothbake.bake_running = False
            self.report({"ERROR"}, f"{args[0]}: cannot run the clothbake program: {e.strerror}")
            return {"CANCELLED"}
        return self._finish(context.scene, run.returncode, run.stderr.splitlines(), bake_dir)

    def invoke(self, context, event):
        if bpy.app.background:
            return self.execute(context)
        if CLOTHBAKE_OT_bake._running:
            self.report({"ERROR"}, "a bake is running already")
            return {"CANCELLED"}
        # The estimate first (a second or two): a long bake asks before it
        # starts, with its seconds and bytes (issue 13: a first full bake ran
        # past 10 minutes with no word beforehand).
        try:
            seconds, _ = estimate_bake(context)
        except ClothbakeError as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        if seconds > CONFIRM_SECONDS:
            return context.window_manager.invoke_props_dialog(self, width=420)
        return self._start_modal(context)

    def draw(self, context):
        settings = context.scene.clothbake
        col = self.layout.column()
        col.label(text=f"This bake takes {settings.bake_estimate}.", icon="TIME")
        col.label(text="Esc cancels it once started. Lower Texels or Samples, or tick")
        col.label(text="Adaptive, for a quicker bake. Start it?")

    def _start_modal(self, context):
        try:
            args, self._bake_dir, _ = _bake_command(context)
            self._proc = subprocess.Popen(
                args, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, stdin=subprocess.DEVNULL,
                text=True, env=dict(os.environ, CLOTHBAKE_PROGRESS="lines"))
        except ClothbakeError as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        except OSError as e:
            self.report({"ERROR"}, f"cannot run the clothbake program: {e.strerror}")
            return {"CANCELLED"}
        CLOTHBAKE_OT_bake._running = True
        self._lines = []
        self._queue = queue.Queue()
        self._reader = threading.Thread(target=self._read, args=(self._proc.stderr, self._queue),
                                         daemon=True)
        self._reader.start()
        self._scene = context.scene  # the baked scene, whichever is shown later
        self._start_report(self._scene, self._bake_dir)
        wm = context.window_manager
        wm.progress_begin(0, 100)
        self._timer = wm.event_timer_add(0.2, window=context.window)
        wm.modal_handler_add(self)
        context.workspace.status_text_set("clothbake: baking 0% (Esc to cancel)")
        return {"RUNNING_MODAL"}

    @staticmethod
    def _read(stream, out):
        for line in stream:
            out.put(line.rstrip("\n"))
        out.put(None)

    def _drain(self, context):
        settings = self._scene.clothbake
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
                settings.bake_progress = int(m.group(1)) / 100.0
        percent = int(round(settings.bake_progress * 100))
        context.window_manager.progress_update(percent)
        context.workspace.status_text_set(f"clothbake: baking {percent}% (Esc to cancel)")
        return done

    def _end_modal(self, context):
        wm = context.window_manager
        wm.event_timer_remove(self._timer)
        wm.progress_end()
        context.workspace.status_text_set(None)
        CLOTHBAKE_OT_bake._running = False
        _redraw(context)

    def modal(self, context, event):
        if event.type == "ESC" and event.value == "PRESS":
            self._proc.terminate()  # SIGTERM: the output is only ever written atomically
            try:
                self._proc.wait(timeout=10)
            except subprocess.TimeoutExpired:
                self._proc.kill()
                self._proc.wait()
            _clean_after_kill(self._bake_dir, self._proc.pid)
            self._end_modal(context)
            settings = self._scene.clothbake
            settings.bake_running = False
            settings.bake_status = "cancelled; the previous lookup (if any) is unchanged"
            self.report({"WARNING"}, "clothbake bake cancelled")
            return {"CANCELLED"}
        if event.type != "TIMER":
            return {"PASS_THROUGH"}
        reader_done = self._drain(context)
        _redraw(context)
        code = self._proc.poll()
        if code is None or not reader_done:
            return {"RUNNING_MODAL"}
        self._end_modal(context)
        return self._finish(self._scene, code, self._lines, self._bake_dir)


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
           CLOTHBAKE_OT_denoising_off)
