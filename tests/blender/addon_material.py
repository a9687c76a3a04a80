"""Headless Blender 3.4 test of the panel's Material section:
the settings' defaults are the program's, Estimate writes nothing, Bake
material (small: texels 8, 4 view and 4 light directions, 1 sample) writes
a "clothbake-material" folder with those settings and puts the material on
the selection, Apply material on several meshes and routes, the refusals
(a mesh with no UV map, a camera, a non-cloth active object, texels not a
power of 2, no material yet), and a bake killed half-way (what Esc does)
leaving no folder and an earlier material untouched; a scene with a spot
and an area light (Bake material, Apply and a per-scene export take both;
an area light's Spread other than 180 degrees is refused or noted).

    blender -b --factory-startup --python-exit-code 1 -P addon_material.py -- \
        CLOTHBAKE_EXE SOURCE_DIR TMP_DIR

Run by run_addon_script.sh addon_material.
"""
import hashlib
import json
import math
import os
import subprocess
import sys
import time

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from lib.checks import check, run_checks  # noqa: E402
from lib.errors import expect_error  # noqa: E402
from lib.headless import TMP, enable_addon  # noqa: E402
from lib.scene import select  # noqa: E402


def folder_hash(folder):
    h = hashlib.sha256()
    for name in sorted(os.listdir(folder)):  # the program's files (not Apply's packed images)
        if not os.path.isfile(os.path.join(folder, name)):
            continue
        with open(os.path.join(folder, name), "rb") as f:
            h.update(name.encode() + f.read())
    return h.hexdigest()


def main():
    enable_addon()
    for op in ("bake_material", "apply_material", "material_estimate"):
        check(hasattr(bpy.types, f"CLOTHBAKE_OT_{op}"), f"operator clothbake.{op} registered")
    check(hasattr(bpy.types, "CLOTHBAKE_PT_material"), "Material panel registered")
    from clothbake.core.defaults import MATERIAL_DEFAULTS
    from clothbake.blender import operators_material
    from clothbake.core import program
    scene = bpy.context.scene
    settings = scene.clothbake
    got = {"texels": settings.material_texels, "directions": settings.material_directions,
           "light_directions": settings.material_light_directions, "spp": settings.material_spp,
           "max_error": round(settings.material_max_error, 6)}
    check(got == MATERIAL_DEFAULTS and settings.material_route == "exact",
          f"Material defaults are the program's: {got}, route {settings.material_route}")
    m = program.PROGRESS.match("material  42% 1.3s")
    check(m is not None and m.group(1) == "42", "material progress line parsed")

    # A new user's scene: the default cube, a plane made a cloth (twill).
    bpy.ops.mesh.primitive_plane_add(size=2, location=(0, 0, 1.5))
    plane = bpy.context.active_object
    plane.name = "Cloth plane"
    bpy.ops.object.mode_set(mode="EDIT")
    bpy.ops.mesh.subdivide(number_cuts=3)
    bpy.ops.object.mode_set(mode="OBJECT")
    plane.clothbake.is_cloth = True
    plane.clothbake.weave = "twill_2_1"
    cube = scene.objects["Cube"]
    bpy.ops.mesh.primitive_plane_add(size=1, location=(3, 0, 0))
    bare = bpy.context.active_object
    bare.name = "Bare"
    while bare.data.uv_layers:
        bare.data.uv_layers.remove(bare.data.uv_layers[0])
    folder = os.path.join(TMP, "twill_material")
    settings.material_dir = folder
    settings.material_texels, settings.material_directions = 8, 4
    settings.material_light_directions, settings.material_spp = 4, 1

    # No material yet: Apply material says so.
    select([cube], cube)
    expect_error(bpy.ops.clothbake.apply_material, ["no material in", "Bake material first"],
                 "Apply material before any bake")

    # Refusals before any work.
    select([cube], cube)
    expect_error(bpy.ops.clothbake.bake_material, ["'Cube' is not a cloth", "tick 'Cloth'"],
                 "Bake material with a non-cloth active object")
    select([plane], plane)
    settings.material_texels = 12
    expect_error(bpy.ops.clothbake.bake_material, ["power of 2", "12"],
                 "Bake material at texels 12")
    settings.material_texels = 8
    check(not os.path.exists(folder), "refusals wrote nothing")

    # Estimate: the program's probe, nothing written.
    t0 = time.perf_counter()
    result = bpy.ops.clothbake.material_estimate()
    seconds = time.perf_counter() - t0
    check(result == {"FINISHED"} and settings.material_estimate.startswith("about ") and
          "MiB" in settings.material_estimate and "MB on disk" in settings.material_estimate and
          operators_material.material_estimate_is_current(bpy.context) and
          not os.path.exists(folder),
          f"Estimate shows '{settings.material_estimate}' in {seconds:.1f} s and writes no "
          "material")

    # Bake material: small, synchronous here; applied to the selection.
    select([plane], plane)
    t0 = time.perf_counter()
    result = bpy.ops.clothbake.bake_material()
    seconds = time.perf_counter() - t0
    manifest_path = os.path.join(folder, "manifest.json")
    check(result == {"FINISHED"} and os.path.isfile(manifest_path),
          f"Bake material wrote the folder in {seconds:.1f} s ({settings.material_status})")
    manifest = json.load(open(manifest_path))
    check(manifest["format"] == "clothbake-material" and manifest["texels"] == 8 and
          manifest["directions"] == 4 and manifest["light_directions"] == 4 and
          manifest["spp"] == 1 and abs(manifest["max_error"] - 0.05) < 1e-6,
          "the manifest is a clothbake-material with the panel's settings")
    check(settings.material_status.startswith("baked") and not settings.material_running and
          abs(settings.material_progress - 1.0) < 1e-6, "the panel shows the bake finished")
    mat = plane.active_material
    check(mat is not None and mat.get("clothbake_material") == folder and
          mat.get("clothbake_route") == "exact",
          "Bake material put the material on the selected plane (route exact)")

    # Apply material: the cube and the plane, the other route.
    settings.material_route = "cycles-lit"
    select([plane, cube], cube)
    result = bpy.ops.clothbake.apply_material()
    check(result == {"FINISHED"} and all(
        o.active_material is not None and o.active_material.get("clothbake_route") == "cycles-lit"
        and o.active_material.get("clothbake_material") == folder for o in (plane, cube)),
        "Apply material put the cycles-lit material on the cube and the plane")

    # Refused: a mesh with no UV map among the selection; nothing changes.
    settings.material_route = "exact"
    select([plane, bare], plane)
    expect_error(bpy.ops.clothbake.apply_material,
                 ["object 'Bare': mesh has no UV map", "UV > Unwrap"],
                 "Apply material with a UV-less mesh selected")
    check(plane.active_material.get("clothbake_route") == "cycles-lit" and
          bare.active_material is None, "the refusal changed no object")
    camera = scene.objects["Camera"]
    select([camera], camera)
    expect_error(bpy.ops.clothbake.apply_material, ["'Camera' is a camera, not a mesh"],
                 "Apply material on a camera")

    # A bake killed half-way (what Esc does): no folder, no temporary
    # sibling; an earlier material in the same folder untouched.
    select([plane], plane)
    settings.material_texels, settings.material_directions = 32, 8
    settings.material_light_directions, settings.material_spp = 6, 2
    for target, existing in ((os.path.join(TMP, "killed_material"), False), (folder, True)):
        settings.material_dir = target
        before = folder_hash(target) if existing else None
        args, out = operators_material.material_command(bpy.context)
        proc = subprocess.Popen(args, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                                stdin=subprocess.DEVNULL, text=True,
                                env=dict(os.environ, CLOTHBAKE_PROGRESS="lines"))
        seen = ""
        for line in proc.stderr:
            m = program.PROGRESS.match(line)
            if m and int(m.group(1)) >= 5:
                seen = line.strip()
                break
        program.kill_job(proc, out)
        parent = os.path.dirname(target)
        left = [n for n in os.listdir(parent)
                if n.startswith(os.path.basename(target) + ".") and not n.endswith(".scene")]
        if existing:
            check(bool(seen) and folder_hash(target) == before and not left,
                  f"killed at '{seen}': the earlier material is unchanged, nothing left beside it")
        else:
            check(bool(seen) and not os.path.exists(target) and not left,
                  f"killed at '{seen}': no material folder, nothing left beside it ({left})")


    spot_and_area_lights(plane, folder)


def spot_and_area_lights(plane, folder):
    """A scene with a spot and an area light (the lights artists use most
    beside the sun and the point light). Estimate
    and Bake material run; Apply lights the material with both (no note);
    a per-scene export writes them. An area light whose Spread is not 180
    degrees is refused by the export (naming the light and the setting),
    left out of the material bake's scene, and noted by Apply."""
    from clothbake.blender.scene_export_bpy import build_model, export_scene
    scene = bpy.context.scene
    settings = scene.clothbake
    for kind in ("SPOT", "AREA"):
        bpy.ops.object.light_add(type=kind, location=(1.0, -1.0, 3.0))
        bpy.context.active_object.name = f"{kind.title()} lamp"
    target = os.path.join(TMP, "spot_material")
    settings.material_dir = target
    settings.material_texels, settings.material_directions = 8, 4
    settings.material_light_directions, settings.material_spp = 4, 1
    settings.material_route = "exact"
    select([plane], plane)
    result = bpy.ops.clothbake.material_estimate()
    check(result == {"FINISHED"} and settings.material_estimate.startswith("about "),
          f"Estimate with a spot and an area light: '{settings.material_estimate}'")
    result = bpy.ops.clothbake.bake_material()
    check(result == {"FINISHED"} and os.path.isfile(os.path.join(target, "manifest.json")),
          f"Bake material with a spot and an area light ({settings.material_status})")
    from clothbake.blender.material_apply import apply_material
    _, notes = apply_material(plane, target)
    check(not any("lamp" in n for n in notes), f"Apply lights the material with both: {notes}")
    group = plane.active_material.node_tree.nodes["Group"]
    check("Light 0 side u" in group.inputs and any(
        i.name.endswith("cos half angle") for i in group.inputs),
        "the group has the area light's and the spot's inputs")
    select([plane], plane)
    result = bpy.ops.clothbake.apply_material()
    check(result == {"FINISHED"} and plane.active_material.get("clothbake_material") == target,
          "Apply material with a spot and an area light")
    from clothbake.core.errors import ClothbakeError
    path = export_scene(scene, os.path.join(TMP, "spot_scene", "scene.json"))
    with open(path) as f:
        kinds = sorted(l["type"] for l in json.load(f)["lights"])
    check("spot" in kinds and "area" in kinds, f"a per-scene export writes both: {kinds}")
    area = bpy.data.objects["Area lamp"]
    area.data.spread = 1.5707963
    try:
        export_scene(scene, os.path.join(TMP, "spread_scene", "scene.json"))
        check(False, "a per-scene export of an area light with Spread 90 degrees refuses")
    except ClothbakeError as e:
        check(str(e) == "light 'Area lamp': spread: 90 degrees; clothbake's area lights emit "
              "into the whole half-space in front of them (Spread 180 degrees)",
              f"a per-scene export refuses Spread 90: '{e}'")
    model = build_model(scene, supported_lights_only=True)
    check(len(model["lights"]) == len(kinds) - 1,
          "the material bake's scene leaves that light out")
    _, notes = apply_material(plane, target)
    check(any("'Area lamp': its spread is 90 degrees: the material is not lit by it" in n
              for n in notes), f"Apply's note on the spread: {notes}")
    area.data.spread = math.pi


run_checks(main)
