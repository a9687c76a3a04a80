"""Compare (Cycles against clothbake's reference renderer) and the check
for a Blender built without a denoiser."""
import json
import os
import time

import bpy

from ..core import program as runner
from ..core.errors import ClothbakeError
from ..core.scene import load_scene
from . import prefs
from .operators_job import program_path
from .scene_export_bpy import cloth_objects, scene_file_for_bake
from .scene_import import set_render_settings


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
    runner.run([program, "render", scene_path, "-o", ref, "--quiet",
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
            program = program_path(context)
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
            metrics = json.loads(runner.run([program, "compare", ref, cycles, "--heatmap", heat,
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


CLASSES = (CLOTHBAKE_OT_compare, CLOTHBAKE_OT_denoising_off)
