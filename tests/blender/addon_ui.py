"""Headless Blender 3.4 test of the add-on's artist-facing half: register,
import (paper, slab) through the operator, export and check clothbake
accepts the export with the same camera, lights and objects, Bake
(synchronously, tiny), Apply, Compare, the edited-cloth export, error
reports (non-quad mesh on export and on apply, missing bake folder, missing
program), and a clean unregister.

    blender -b --factory-startup --python-exit-code 1 -P addon_ui.py -- \
        CLOTHBAKE_EXE SOURCE_DIR TMP_DIR

Run by run_addon_script.sh addon_ui. Exit status 0 when every check passes.
"""
import json
import os
import subprocess
import sys

import addon_utils
import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from lib.checks import check, run_checks  # noqa: E402
from lib.errors import expect_error  # noqa: E402
from lib.headless import CLOTHBAKE, PAPER, SLAB, SOURCE, TMP, enable_addon  # noqa: E402
from lib.scene import select  # noqa: E402


def close(a, b, tol=1e-5):
    if isinstance(a, (list, tuple)):
        return len(a) == len(b) and all(close(x, y, tol) for x, y in zip(a, b))
    if isinstance(a, (int, float)) and isinstance(b, (int, float)):
        return abs(a - b) <= tol * max(1.0, abs(a), abs(b))
    return a == b


def main():
    # -- register ------------------------------------------------------------
    prefs = enable_addon()
    for op in ("import_scene", "export_scene", "bake", "apply", "compare"):
        check(hasattr(bpy.types, f"CLOTHBAKE_OT_{op}"), f"operator clothbake.{op} registered")
    check(hasattr(bpy.types, "CLOTHBAKE_PT_object"), "panel registered")
    check(hasattr(bpy.types.Object, "clothbake") and hasattr(bpy.types.Scene, "clothbake"),
          "object and scene settings registered")
    from clothbake.blender import panels
    from clothbake.core import program
    check(panels._menu_import in bpy.types.TOPBAR_MT_file_import.draw._draw_funcs and
          panels._menu_export in bpy.types.TOPBAR_MT_file_export.draw._draw_funcs,
          "File > Import / Export entries")
    m = program.PROGRESS.match("bake  42% 1.3s")
    check(m is not None and m.group(1) == "42", "progress line parsed")
    check(program.program_error(["bake  10% 0.1s", "clothbake: error: a.json: b: bad"],
                                "bake", 1) == "a.json: b: bad", "program error message kept")

    from clothbake.core import scene_export
    from clothbake.core.obj import read_obj
    from clothbake.core.scene import load_scene

    # -- import / export: the paper scene --------------------------------------
    bpy.ops.clothbake.import_scene(filepath=PAPER)
    scene = bpy.context.scene
    cloths = [o for o in scene.objects if o.type == "MESH" and o.clothbake.is_cloth]
    check(len(cloths) == 1 and cloths[0].name == "cloth", "paper: one cloth object imported")
    cloth = cloths[0].clothbake
    check(cloth.cloth_path == os.path.join(SOURCE, "testscenes", "paper", "cloth.json") and
          not cloth.cloth_edited, "paper: cloth spec file kept, not edited")
    check(close(list(cloth.warp_color), [0.60, 0.09, 0.08]) and cloth.weave == "plain",
          "paper: cloth fields loaded from the spec file")
    check(scene.clothbake.transmittance == "shadow-march" and scene.clothbake.render_spp == 4,
          "paper: render settings loaded")

    out = os.path.join(TMP, "paper_export", "scene.json")
    bpy.ops.clothbake.export_scene(filepath=out)
    check(os.path.isfile(out) and os.path.isfile(os.path.join(TMP, "paper_export", "cloth.obj")),
          "paper: export wrote scene.json and cloth.obj")
    exported, original = load_scene(out), load_scene(PAPER)
    cam_a, cam_b = exported["camera"], original["camera"]
    check(all(close(cam_a[k], cam_b[k]) for k in cam_b), "paper: exported camera equals the "
          f"original within 1e-5 ({cam_a} vs {cam_b})")
    check(len(exported["lights"]) == len(original["lights"]) and all(
        a.keys() == b.keys() and all(close(a[k], b[k]) for k in b)
        for a, b in zip(exported["lights"], original["lights"])),
        "paper: exported lights equal the original's within 1e-5")
    ok = len(exported["objects"]) == len(original["objects"])
    for a, b in zip(exported["objects"], original["objects"]):
        ok = ok and all(close(a[k], b[k]) for k in ("name", "repeats_per_uv", "thickness_world",
                                                     "extinction_per_mm", "isotropic_albedo",
                                                     "cloth_path"))
        ma, mb = read_obj(a["mesh_path"]), read_obj(b["mesh_path"])
        ok = ok and len(ma.quads) == len(mb.quads) and all(
            close(list(ma.positions[pa[i]]), list(mb.positions[pb[i]])) and
            close(list(ma.uvs[ta[i]]), list(mb.uvs[tb[i]]))
            for (pa, ta), (pb, tb) in zip(ma.quads, mb.quads) for i in range(4))
    check(ok, "paper: exported objects and meshes equal the original's within 1e-5")
    check(close(exported["background"], original["background"]) and
          exported["json"]["render"] == dict(scene_export.RENDER_DEFAULTS,
                                             **original["json"]["render"]),
          "paper: background and render settings exported")
    check(scene.clothbake.scene_path == out, "paper: the export became the scene file")
    run = subprocess.run([CLOTHBAKE, "render", out, "-o", os.path.join(TMP, "paper.exr"),
                          "--spp", "1", "--threads", "1", "--quiet"], capture_output=True,
                         text=True)
    check(run.returncode == 0, f"paper: clothbake render accepts the export {run.stderr.strip()}")

    # An edited field: the cloth is exported inline, the spec's other keys kept.
    cloth.warp_width_mm = 0.3
    check(cloth.cloth_edited, "paper: editing a field marks the cloth edited")
    out2 = os.path.join(TMP, "paper_edited", "scene.json")
    bpy.ops.clothbake.export_scene(filepath=out2)
    inline = json.load(open(out2))["objects"][0]["cloth"]
    check(isinstance(inline, dict) and inline["warp"]["width_mm"] == 0.3 and
          inline["density"]["edge"] == 0.45, "paper: edited cloth exported inline, rest kept")

    # -- bake, apply, compare: the slab scene -----------------------------------
    bpy.ops.clothbake.import_scene(filepath=SLAB)
    settings = scene.clothbake
    check(settings.scene_path == SLAB and settings.shading == "isotropic", "slab: imported")
    bake_dir = os.path.join(TMP, "slab_bake")
    settings.bake_dir = bake_dir
    settings.adaptive = False
    settings.directions, settings.texels, settings.bake_spp = 2, 4, 1
    # Estimate before the bake (a new user cannot guess a bake's time): the
    # program's plan for exactly these settings, shown in the panel; its
    # march samples are the bake's.
    from clothbake.blender.operators_lookup import estimate_is_current
    check(not estimate_is_current(bpy.context), "slab: no estimate yet")
    result = bpy.ops.clothbake.estimate()
    check(result == {"FINISHED"} and settings.bake_estimate.startswith("about ") and
          "MiB" in settings.bake_estimate and estimate_is_current(bpy.context) and
          not os.path.exists(bake_dir),
          f"slab: Estimate shows '{settings.bake_estimate}' and writes no bake")
    est = json.loads(subprocess.run(
        [CLOTHBAKE, "bake", SLAB, "-o", bake_dir, "--direction-map", "hemi-octahedral",
         "--directions", "2", "--texels", "4", "--spp", "1", "--estimate"],
        capture_output=True, text=True).stdout)
    settings.texels = 5
    check(not estimate_is_current(bpy.context), "slab: an estimate goes stale when a setting changes")
    settings.texels = 4
    result = bpy.ops.clothbake.bake()
    check(result == {"FINISHED"} and os.path.isfile(os.path.join(bake_dir, "manifest.json")),
          f"slab: Bake wrote the lookup ({settings.bake_status})")
    check(settings.scene_path == SLAB and not os.path.exists(bake_dir + ".scene"),
          "slab: the unchanged scene was baked from its own file (no export)")
    manifest = json.load(open(os.path.join(bake_dir, "manifest.json")))
    check(manifest["direction_map"] == dict(manifest["direction_map"], k=2,
                                             type="hemi-octahedral") and
          manifest["settings"]["texels"] == 4 and manifest["settings"]["spp"] == 1 and
          not manifest["settings"]["adaptive"], "slab: bake settings passed (K 2, R 4, 1 spp)")
    check(manifest["statistics"]["march_samples"] == est["march_samples"],
          f"slab: the estimate planned the bake's {est['march_samples']} march samples")
    slab = bpy.data.objects["slab"]
    select(slab)
    result = bpy.ops.clothbake.apply()
    check(result == {"FINISHED"} and slab.active_material is not None and
          slab.active_material.name == "clothbake slab", "slab: Apply put the lookup material on")
    settings.compare_samples = 2
    result = bpy.ops.clothbake.compare()
    folder = bake_dir + "_compare"
    check(result == {"FINISHED"} and "PSNR" in settings.compare_status and all(
        os.path.isfile(os.path.join(folder, f)) for f in ("reference.exr", "cycles.exr",
                                                          "difference.png", "sheet.png")),
        f"slab: Compare wrote reference, Cycles render and heat map ({settings.compare_status})")
    # Cycles through the applied lookup draws what clothbake's lookup-render
    # draws from the same bake (the comparison's PSNR itself is low at K = 2).
    lookup_exr = os.path.join(TMP, "slab_lookup.exr")
    run = subprocess.run([CLOTHBAKE, "lookup-render", SLAB, bake_dir, "-o", lookup_exr,
                          "--quiet"], capture_output=True, text=True)
    metrics = subprocess.run([CLOTHBAKE, "compare", lookup_exr, os.path.join(folder, "cycles.exr"),
                              "--json"], capture_output=True, text=True)
    psnr = json.loads(metrics.stdout)["psnr"] if metrics.returncode == 0 else 0.0
    check(run.returncode == 0 and psnr > 60.0,
          f"slab: Compare's Cycles render equals clothbake lookup-render ({psnr:.1f} dB > 60)")
    bpy.ops.clothbake.compare()
    check("cached reference" in settings.compare_status, "slab: reference reused for the same "
          "scene file")

    # A moved camera: Bake exports the scene beside the bake folder first.
    scene.camera.location.x += 0.01
    settings.texels = 2
    result = bpy.ops.clothbake.bake()
    check(result == {"FINISHED"} and settings.scene_path == os.path.join(
        bake_dir + ".scene", "scene.json"), "slab: a changed scene is exported, then baked")
    scene.camera.location.x -= 0.01

    # -- errors are reports ----------------------------------------------------
    mesh = bpy.data.meshes.new("bad")
    mesh.from_pydata([(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (2, 0, 0)], [],
                     [(0, 1, 2, 3), (1, 4, 2)])
    mesh.uv_layers.new(name="UVMap")
    bad = bpy.data.objects.new("bad", mesh)
    scene.collection.objects.link(bad)
    bad.clothbake.is_cloth = True
    expect_error(bpy.ops.clothbake.export_scene, ["object 'bad'", "face 1 has 3 corners"],
                 "export of a non-quad mesh", filepath=os.path.join(TMP, "bad", "scene.json"))
    check(not os.path.exists(os.path.join(TMP, "bad")), "failed export wrote nothing")
    bpy.data.objects.remove(bad)
    # One triangle: as many faces as the slab's lookup has quads, so Apply
    # gets as far as the quad check.
    mesh = bpy.data.meshes.new("triangle")
    mesh.from_pydata([(0, 0, 0), (1, 0, 0), (1, 1, 0)], [], [(0, 1, 2)])
    mesh.uv_layers.new(name="UVMap")
    tri = bpy.data.objects.new("triangle", mesh)
    scene.collection.objects.link(tri)
    select(tri)
    tri["clothbake_object_index"] = 0
    expect_error(bpy.ops.clothbake.apply, ["triangle", "not a quad", "3 corners"],
                 "apply to a non-quad mesh")
    check(tri.active_material is None, "failed apply left the mesh alone")
    bpy.data.objects.remove(tri)

    select(slab)
    settings.bake_dir = os.path.join(TMP, "no_such_bake")
    expect_error(bpy.ops.clothbake.apply, ["no_such_bake", "no such lookup folder"],
                 "apply from a missing bake folder")
    prefs.program = os.path.join(TMP, "no_such_program")
    expect_error(bpy.ops.clothbake.bake, ["clothbake program was not found"],
                 "bake without the program")
    prefs.program = CLOTHBAKE
    settings.bake_dir = os.path.join(TMP, "not_a_lookup")
    os.makedirs(settings.bake_dir)
    open(os.path.join(settings.bake_dir, "keep.txt"), "w").close()
    expect_error(bpy.ops.clothbake.bake, ["not_a_lookup"], "bake refused by the program")
    expect_error(bpy.ops.clothbake.import_scene, ["nope.json", "cannot read the scene"],
                 "import of a missing scene", filepath=os.path.join(TMP, "nope.json"))

    # -- no denoiser (a Blender built without OpenImageDenoise fails F12 with
    # denoising on): the panel's warning and its button ----------------------
    from clothbake.blender.operators_compare import denoiser_missing
    import _cycles
    scene = bpy.context.scene
    scene.render.engine = "CYCLES"
    scene.cycles.use_denoising = True
    scene.cycles.samples = 1
    scene.render.resolution_percentage = 10
    if not _cycles.with_openimagedenoise:
        check(denoiser_missing(scene), "no denoiser: the panel's warning is shown")
        try:
            bpy.ops.render.render()
            failed = ""
        except RuntimeError as e:
            failed = str(e)
        check("OpenImageDenoise" in failed, f"no denoiser: F12 with denoising on fails ({failed})")
        check(bpy.ops.clothbake.denoising_off() == {"FINISHED"} and
              not scene.cycles.use_denoising and not denoiser_missing(scene),
              "no denoiser: the button turns render denoising off and the warning goes")
        check(bpy.ops.render.render() == {"FINISHED"}, "no denoiser: F12 then renders")
    else:
        check(not denoiser_missing(scene), "with a denoiser no warning is shown")
    scene.render.resolution_percentage = 100

    # -- unregister --------------------------------------------------------------
    addon_utils.disable("clothbake", default_set=True, handle_error=None)
    check(not hasattr(bpy.types, "CLOTHBAKE_PT_object") and
          not hasattr(bpy.types, "CLOTHBAKE_OT_bake") and
          not hasattr(bpy.types.Object, "clothbake") and
          panels._menu_import not in bpy.types.TOPBAR_MT_file_import.draw._draw_funcs,
          "unregistered cleanly")


run_checks(main)
