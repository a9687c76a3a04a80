"""Headless Blender 3.4 test of the add-on's error reports: every
refused input, met through the operators as an artist invokes them, ends in
an ERROR report naming what is wrong and a cancelled operator, never a
Python traceback (run_addon_script.sh also fails on any "Traceback" in
Blender's output).

    blender -b --factory-startup --python-exit-code 1 -P addon_errors.py -- \
        CLOTHBAKE_EXE SOURCE_DIR TMP_DIR

Cases (docs/design/blender-nodes.md, "The add-on's errors"):
  a. export / bake / apply on a mesh with a triangle or an n-gon;
  b. apply with a missing bake folder, a folder without manifest.json, a
     malformed manifest, a manifest of another format version;
  c. apply with a bake of another mesh (quad count, object name, the mesh
     summary: the slab moved since its bake);
  d. import of a scene with a missing OBJ, a malformed field, a broken OBJ,
     malformed JSON.
"""
import json
import os
import shutil
import subprocess
import sys

import addon_utils
import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from lib.checks import check, run_checks  # noqa: E402
from lib.errors import Reports, expect_report as expect  # noqa: E402
from lib.headless import CLOTHBAKE, PAPER, SLAB, SOURCE, TMP, enable_addon  # noqa: E402
from lib.scene import select  # noqa: E402


def grid_mesh(name, faces, cloth=True):
    """A mesh object on a 3 x 2 grid of vertices with a UV map, linked to the
    scene, selected and active."""
    verts = [(x, y, 0.0) for y in range(2) for x in range(3)] + [(1.5, 2.0, 0.0)]
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(verts, [], faces)
    mesh.uv_layers.new(name="UVMap")
    obj = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(obj)
    obj.clothbake.is_cloth = cloth
    select(obj)
    return obj


def write(path, text):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w", encoding="utf-8") as f:
        f.write(text)
    return path


def main():
    enable_addon()
    scene = bpy.context.scene
    settings = scene.clothbake

    # A real lookup of the slab (one quad), baked by the program.
    slab_bake = os.path.join(TMP, "slab_bake")
    run = subprocess.run([CLOTHBAKE, "bake", SLAB, "-o", slab_bake, "--direction-map",
                          "hemi-octahedral", "--directions", "2", "--texels", "4", "--spp", "1",
                          "--threads", "1", "--quiet"], capture_output=True, text=True)
    check(run.returncode == 0, f"slab baked for the apply cases {run.stderr.strip()}")
    manifest_text = open(os.path.join(slab_bake, "manifest.json"), encoding="utf-8").read()

    # -- a. non-quad faces: export, bake, apply --------------------------------
    bpy.ops.clothbake.import_scene(filepath=SLAB)
    slab = bpy.data.objects["slab"]
    slab.clothbake.is_cloth = False  # the bad meshes below are the scene's only cloth
    triangle = grid_mesh("triangles", [(0, 1, 4, 3), (1, 2, 5)])
    export_dir = os.path.join(TMP, "export_triangle")
    expect(bpy.ops.clothbake.export_scene,
           "object 'triangles': face 1 has 3 corners; clothbake needs quads (4 corners)",
           "a. export of a mesh with a triangle",
           filepath=os.path.join(export_dir, "scene.json"))
    check(not os.path.exists(export_dir), "a. the refused export wrote nothing")
    settings.bake_dir = os.path.join(TMP, "bake_triangle")
    expect(bpy.ops.clothbake.bake,
           "object 'triangles': face 1 has 3 corners; clothbake needs quads (4 corners)",
           "a. bake of a mesh with a triangle")
    check(not os.path.exists(settings.bake_dir) and
          not os.path.exists(settings.bake_dir + ".scene"), "a. the refused bake wrote nothing")
    settings.bake_dir = slab_bake
    expect(bpy.ops.clothbake.apply,
           "triangles: mesh 'triangles' has 1 face that is not a quad (first: face 1, 3 "
           "corners); clothbake needs quads (4 corners)", "a. apply to a mesh with a triangle")
    check(triangle.active_material is None and "clothbake_p0" not in triangle.data.attributes,
          "a. the refused apply left the mesh alone")
    bpy.data.objects.remove(triangle)

    ngon = grid_mesh("ngon", [(0, 1, 4, 3), (1, 2, 5, 6, 4)])
    expect(bpy.ops.clothbake.export_scene,
           "object 'ngon': face 1 has 5 corners; clothbake needs quads (4 corners)",
           "a. export of a mesh with an n-gon", filepath=os.path.join(TMP, "ngon", "scene.json"))
    settings.bake_dir = os.path.join(TMP, "bake_ngon")
    expect(bpy.ops.clothbake.bake,
           "object 'ngon': face 1 has 5 corners; clothbake needs quads (4 corners)",
           "a. bake of a mesh with an n-gon")
    settings.bake_dir = slab_bake
    expect(bpy.ops.clothbake.apply,
           "ngon: mesh 'ngon' has 1 face that is not a quad (first: face 1, 5 corners); "
           "clothbake needs quads (4 corners)", "a. apply to a mesh with an n-gon")
    bpy.data.objects.remove(ngon)
    two_bad = grid_mesh("two_bad", [(0, 1, 3), (1, 2, 5, 6, 4)])
    expect(bpy.ops.clothbake.export_scene,
           "object 'two_bad': face 0 has 3 corners (2 of 2 faces are not quads); clothbake "
           "needs quads (4 corners)", "a. export of a mesh with two bad faces",
           filepath=os.path.join(TMP, "two_bad", "scene.json"))
    expect(bpy.ops.clothbake.apply,
           "two_bad: mesh 'two_bad' has 2 faces that are not quads (first: face 0, 3 corners); "
           "clothbake needs quads (4 corners)", "a. apply to a mesh with two bad faces")
    bpy.data.objects.remove(two_bad)
    # A quad mesh whose modifier makes triangles (bake and apply take the
    # mesh Cycles renders, modifiers applied): the refusal names the modifier.
    tri_mod = grid_mesh("tri_mod", [(0, 1, 4, 3), (1, 2, 5, 4)])
    tri_mod.modifiers.new("Triangulate", "TRIANGULATE")
    settings.bake_dir = os.path.join(TMP, "bake_tri_mod")
    expect(bpy.ops.clothbake.bake,
           "object 'tri_mod': face 0 has 3 corners (4 of 4 faces are not quads); the Triangulate "
           "modifier 'Triangulate' makes them; clothbake needs quads (4 corners)",
           "a. bake of a quad mesh under a Triangulate modifier")
    check(not os.path.exists(settings.bake_dir), "a. the refused bake wrote nothing")
    settings.bake_dir = slab_bake
    expect(bpy.ops.clothbake.apply,
           "tri_mod: mesh 'tri_mod' has 4 faces that are not quads (first: face 0, 3 corners); "
           "the Triangulate modifier 'Triangulate' makes them; clothbake needs quads "
           "(4 corners)", "a. apply to a quad mesh under a Triangulate modifier")
    check([m.name for m in tri_mod.modifiers] == ["Triangulate"] and
          tri_mod.modifiers[0].show_viewport, "a. the refused apply left the modifiers as they were")
    bpy.data.objects.remove(tri_mod)
    slab.clothbake.is_cloth = True

    # -- b. the bake folder and its manifest ------------------------------------
    select(slab)
    missing = os.path.join(TMP, "no_such_bake")
    settings.bake_dir = missing
    expect(bpy.ops.clothbake.apply, f"slab: {missing}: no such lookup folder",
           "b. apply from a missing bake folder")
    empty = os.path.join(TMP, "empty_bake")
    os.makedirs(empty)
    settings.bake_dir = empty
    expect(bpy.ops.clothbake.apply,
           f"slab: {empty}: no manifest.json in this folder; it is not a clothbake lookup "
           "(bake into it first)", "b. apply from a folder without manifest.json")
    broken = os.path.join(TMP, "broken_manifest")
    shutil.copytree(slab_bake, broken)
    write(os.path.join(broken, "manifest.json"), manifest_text[: len(manifest_text) // 2])
    settings.bake_dir = broken
    r = Reports(bpy.ops.clothbake.apply)
    prefix = f"Error: slab: {os.path.join(broken, 'manifest.json')}: line "
    check(r.error.startswith(prefix) and ": invalid JSON: " in r.error and
          "Traceback" not in r.error, f"b. apply with a truncated manifest: {r.describe()}")
    write(os.path.join(broken, "manifest.json"), "[1, 2, 3]\n")
    expect(bpy.ops.clothbake.apply,
           f"slab: {os.path.join(broken, 'manifest.json')}: must be a JSON object",
           "b. apply with a manifest that is not an object")
    manifest = json.loads(manifest_text)
    manifest["objects"][0]["quads"] = "one"
    write(os.path.join(broken, "manifest.json"), json.dumps(manifest))
    expect(bpy.ops.clothbake.apply,
           f"slab: {os.path.join(broken, 'manifest.json')}: objects[0].quads: must be int, "
           "got str", "b. apply with a manifest field of the wrong type")
    for version in (1, 3):
        manifest = json.loads(manifest_text)
        manifest["version"] = version
        write(os.path.join(broken, "manifest.json"), json.dumps(manifest))
        expect(bpy.ops.clothbake.apply,
               f"slab: {os.path.join(broken, 'manifest.json')}: version: this lookup has format "
               f"version {version}; this add-on reads version 2",
               f"b. apply with a manifest of format version {version}")
    manifest = json.loads(manifest_text)
    manifest["format"] = "something-else"
    write(os.path.join(broken, "manifest.json"), json.dumps(manifest))
    expect(bpy.ops.clothbake.apply,
           f"slab: {os.path.join(broken, 'manifest.json')}: format: not a clothbake lookup "
           "(format 'something-else', expected 'clothbake-lookup')",
           "b. apply with a manifest of another format")
    write(os.path.join(broken, "manifest.json"), "")
    with open(os.path.join(broken, "manifest.json"), "wb") as f:
        f.write(b"\xff\xfe{not text")
    expect(bpy.ops.clothbake.apply,
           f"slab: {os.path.join(broken, 'manifest.json')}: not UTF-8 text (byte 0); a manifest "
           "is a JSON file", "b. apply with a binary manifest")
    # The atlas a manifest names: truncated (Blender 3.4 hangs loading it), or
    # of another size than the manifest says.
    write(os.path.join(broken, "manifest.json"), manifest_text)
    atlas = os.path.join(broken, "object0_side0.exr")
    data = open(os.path.join(slab_bake, "object0_side0.exr"), "rb").read()
    with open(atlas, "wb") as f:
        f.write(data[: len(data) - 10])
    r = Reports(bpy.ops.clothbake.apply)
    check(r.error.startswith(f"Error: slab: {atlas}: the lookup image is damaged or truncated (") and
          r.error.endswith("); bake again"), f"b. apply with a truncated atlas: {r.describe()}")
    shutil.copy(os.path.join(slab_bake, "object0_side0.exr"), atlas)
    manifest = json.loads(manifest_text)
    width, height = manifest["objects"][0]["sides"]["front"]["size"]
    manifest["objects"][0]["sides"]["front"]["size"] = [width * 2, height * 2]
    write(os.path.join(broken, "manifest.json"), json.dumps(manifest))
    expect(bpy.ops.clothbake.apply,
           f"slab: {atlas}: the image is {width} x {height} pixels; the manifest says "
           f"{width * 2} x {height * 2}", "b. apply with an atlas of another size")
    check(slab.active_material is None or not slab.active_material.name.startswith("clothbake"),
          "b. no refused apply put a material on")

    # -- c. a bake of another mesh -----------------------------------------------
    # The slab itself, moved since its bake: same name, same quad count, but
    # the lookup's mesh summary (objects[0].mesh) no longer matches.
    select(slab)
    settings.bake_dir = slab_bake
    slab.location.x += 0.5
    bpy.context.view_layer.update()
    r = Reports(bpy.ops.clothbake.apply)
    check(r.error.startswith(
        f"Error: slab: {os.path.join(slab_bake, 'manifest.json')}: objects[0].mesh: mesh 'slab' "
        "is not the mesh the lookup's object 'slab' was baked from: its lower bounds are (") and
        r.error.endswith("(was it baked from another mesh, or has this one moved since? bake "
                         "again)") and "Traceback" not in r.error,
        f"c. apply a bake to its mesh moved since: {r.describe()}")
    check(slab.active_material is None or not slab.active_material.name.startswith("clothbake"),
          "c. the refused apply left the moved slab alone")
    slab.location.x -= 0.5
    bpy.context.view_layer.update()
    r = Reports(bpy.ops.clothbake.apply)
    check(not r.error and slab.active_material is not None and
          slab.active_material.name.startswith("clothbake"),
          f"c. the same bake applies once the slab is back: {r.describe()}")
    bpy.ops.clothbake.import_scene(filepath=PAPER)
    cloth = bpy.data.objects["cloth"]
    select(cloth)
    settings.bake_dir = slab_bake
    expect(bpy.ops.clothbake.apply,
           f"cloth: {os.path.join(slab_bake, 'manifest.json')}: objects[0].quads: mesh 'cloth' "
           "has 64 faces; the lookup's object 'slab' has 1 quad (was it baked from another "
           "mesh?)", "c. apply a one-quad bake to the 64-quad paper cloth")
    check(cloth.active_material is None and "clothbake_p0" not in cloth.data.attributes,
          "c. the refused apply left the mesh alone")
    # A mesh of the same face count whose name and scene index match nothing.
    stranger = grid_mesh("stranger", [(0, 1, 4, 3)], cloth=False)
    two = json.loads(manifest_text)
    second = json.loads(json.dumps(two["objects"][0]))
    second["name"] = "other"
    two["objects"].append(second)
    two_dir = os.path.join(TMP, "two_objects")
    shutil.copytree(slab_bake, two_dir)
    write(os.path.join(two_dir, "manifest.json"), json.dumps(two))
    settings.bake_dir = two_dir
    expect(bpy.ops.clothbake.apply,
           f"stranger: {os.path.join(two_dir, 'manifest.json')}: objects: object 'stranger' "
           "matches none of the lookup's objects ('slab', 'other')",
           "c. apply a lookup whose objects are other meshes")
    bpy.data.objects.remove(stranger)

    # -- d. import of a broken scene ---------------------------------------------
    paper = json.load(open(PAPER, encoding="utf-8"))
    paper_dir = os.path.dirname(PAPER)

    def scene_file(name, edit):
        data = json.loads(json.dumps(paper))
        data["objects"][0]["cloth"] = os.path.join(paper_dir, "cloth.json")
        data["objects"][0]["mesh"] = os.path.join(paper_dir, "cloth.obj")
        edit(data)
        return write(os.path.join(TMP, "scenes", name + ".json"), json.dumps(data, indent=1))

    before = sorted(o.name for o in scene.objects)
    # Each case: its scene file's name, the edit, the report ("{path}": the
    # scene file's), and what is refused.
    malformed = "d. import of a scene with a malformed field"
    cases = [
        ("missing_obj", lambda d: d["objects"][0].update(mesh="nowhere/cloth.obj"),
         f"{os.path.join(TMP, 'scenes', 'nowhere', 'cloth.obj')}: cannot read the mesh: "
         "No such file or directory", "d. import of a scene whose OBJ is missing"),
        ("fov_text", lambda d: d["camera"].update(fov_deg="wide"),
         "{path}: camera.fov_deg: must be a finite number", f"{malformed} (camera.fov_deg)"),
        ("direction_short", lambda d: d["lights"][0].update(direction=[0, -1]),
         "{path}: lights[0].direction: must be an array of 3 numbers",
         f"{malformed} (lights[0].direction)"),
        ("thickness_text", lambda d: d["objects"][0].update(thickness_world="thin"),
         "{path}: objects[0].thickness_world: must be a finite number",
         f"{malformed} (objects[0].thickness_world)"),
        ("cloth_number", lambda d: d["objects"][0].update(cloth=7),
         "{path}: objects[0].cloth: must be a cloth spec object or the path of one",
         f"{malformed} (objects[0].cloth)"),
        ("missing_cloth_file", lambda d: d["objects"][0].update(cloth="nowhere/cloth.json"),
         f"{os.path.join(TMP, 'scenes', 'nowhere', 'cloth.json')}: cannot read the cloth "
         "spec: No such file or directory", "d. import of a scene whose cloth spec is missing"),
        ("inline_cloth", lambda d: d["objects"][0].update(cloth={"warp": {"width_mm": "wide"}}),
         "{path}: objects[0].cloth.warp.width_mm: must be a number",
         f"{malformed} (objects[0].cloth.warp.width_mm)"),
        ("name_number", lambda d: d["objects"][0].update(name=5),
         "{path}: objects[0].name: must be a non-empty string", f"{malformed} (objects[0].name)"),
        ("albedo_short", lambda d: d["objects"][0].update(isotropic_albedo=[1, 1]),
         "{path}: objects[0].isotropic_albedo: must be an array of 3 numbers",
         f"{malformed} (objects[0].isotropic_albedo)"),
        ("render_enum", lambda d: d["render"].update(fiber_model="fancy"),
         "{path}: render.fiber_model: unknown value \"fancy\"; expected one of: ellipsoid, "
         "table, kajiya-kay", f"{malformed} (render.fiber_model)"),
        ("render_spp", lambda d: d["render"].update(spp="many"),
         "{path}: render.spp: must be an integer", f"{malformed} (render.spp)"),
        ("render_seed", lambda d: d["render"].update(seed=2**40),
         "{path}: render.seed: must be in [0, 2147483647], got " + str(2**40),
         "d. import of a scene with a seed Blender cannot hold (render.seed)"),
        ("render_number", lambda d: d.update(render=5),
         "{path}: render: must be an object", f"{malformed} (render)"),
    ]
    for name, edit, report, what in cases:
        path = scene_file(name, edit)
        expect(bpy.ops.clothbake.import_scene, report.replace("{path}", path), what,
               filepath=path)
    path = os.path.join(TMP, "scenes", "binary.json")
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n")
    expect(bpy.ops.clothbake.import_scene,
           f"{path}: not UTF-8 text (byte 0); a scene is a JSON file",
           "d. import of a binary file", filepath=path)
    triangle_obj = os.path.join(SOURCE, "tests", "cli", "bad_scenes", "meshes", "triangle.obj")
    path = scene_file("triangle_obj", lambda d: d["objects"][0].update(mesh=triangle_obj))
    r = Reports(bpy.ops.clothbake.import_scene, filepath=path)
    check(r.error.startswith(f"Error: {triangle_obj}: line ") and
          r.error.endswith(": face has 3 corners; clothbake needs quads (4 corners)"),
          f"d. import of a scene whose OBJ has a triangle: {r.describe()}")
    text = json.dumps(paper, indent=1)
    path = write(os.path.join(TMP, "scenes", "truncated.json"), text[: len(text) // 2])
    try:
        json.loads(text[: len(text) // 2])
    except json.JSONDecodeError as e:
        expect(bpy.ops.clothbake.import_scene, f"{path}: line {e.lineno}: invalid JSON: {e.msg}",
               "d. import of truncated JSON", filepath=path)
    path = scene_file("volume_number", lambda d: d["objects"][0].update(volume=7))
    expect(bpy.ops.clothbake.import_scene,
           f"{path}: objects[0].volume: must be the path of a VDB file",
           "d. import of a scene whose object's volume is not a path", filepath=path)
    check(sorted(o.name for o in scene.objects) == before,
          "d. refused imports left the Blender scene unchanged")

    # -- e. a scene whose cloth reads its texture from a VDB: imported, and
    # exported with the VDB (relative to the new scene file) ---------------------
    run = subprocess.run([CLOTHBAKE, "volume", os.path.join(paper_dir, "cloth.json"), "-o",
                          os.path.join(TMP, "vdb"), "--threads", "1"], capture_output=True,
                         text=True)
    check(run.returncode == 0, f"e. a VDB of the paper cloth made {run.stderr.strip()}")
    vdb = os.path.join(TMP, "vdb", "volume.vdb")
    path = scene_file("volume", lambda d: d["objects"][0].update(volume=vdb))
    r = Reports(bpy.ops.clothbake.import_scene, filepath=path)
    cloth = bpy.data.objects.get("cloth")
    check(not r.error and cloth is not None and
          os.path.abspath(bpy.path.abspath(cloth.clothbake.volume_path)) == vdb,
          f"e. import keeps the object's VDB: {r.describe()}")
    exported = os.path.join(TMP, "exported_volume", "scene.json")
    r = Reports(bpy.ops.clothbake.export_scene, filepath=exported)
    written = json.load(open(exported, encoding="utf-8")) if os.path.exists(exported) else {}
    volumes = [o.get("volume") for o in written.get("objects", [])]
    check(not r.error and volumes == [os.path.relpath(vdb, os.path.dirname(exported))],
          f"e. export writes the VDB relative to the scene file: {volumes} {r.describe()}")

    addon_utils.disable("clothbake", default_set=True, handle_error=None)


run_checks(main)
