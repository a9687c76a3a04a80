"""A new user's scenes, made in Blender rather than imported (the meshes an
artist makes, which the imported test scenes never are):
Blender's default scene, the cube deleted, a plane added and shaped as the
case says, 'Cloth' ticked, the panel's defaults kept, Bake, Apply, Compare.
Leaves in WORK: the bake folder (bake/), its exported scene
(bake.scene/scene.json) and Compare's Cycles render (bake_compare/cycles.exr),
which new_user_render.sh compares with `clothbake lookup-render` of the same
bake.

    blender -b --factory-startup --python-exit-code 1 -P new_user.py -- \
        CLOTHBAKE_EXE SOURCE_DIR WORK_DIR CASE

Cases (each a manifest shape, or a route, the older tests never produced):
  plane        64 quads, object rotated and scaled; the camera sees the
               front only (sides.back null)
  plane_back   the same plane turned over: the back only (sides.front null)
  single_quad  one quad
  two_objects  two cloth objects of different quad counts
  subsurf      a bumped 16-quad plane under a Subdivision Surface modifier
               (viewport level 1, render level 2: the bake must take the
               render mesh, 256 quads)
  bend         a Simple Deform bend curling the plane so that the camera sees
               some faces from the front and some from behind
"""
import json
import math
import os
import sys

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from lib.checks import check, run_checks  # noqa: E402
from lib.headless import TMP, enable_addon  # noqa: E402

CASE = sys.argv[sys.argv.index("--") + 4]


def plane(cuts, location=(0, 0, 0), rotation=(0.9, 0.0, 0.3), scale=(1.25, 0.8, 1.0)):
    bpy.ops.object.select_all(action="DESELECT")
    bpy.ops.mesh.primitive_plane_add(size=2, location=location, rotation=rotation)
    obj = bpy.context.active_object
    obj.scale = scale
    if cuts:
        bpy.ops.object.mode_set(mode="EDIT")
        bpy.ops.mesh.subdivide(number_cuts=cuts)
        bpy.ops.object.mode_set(mode="OBJECT")
    obj.clothbake.is_cloth = True
    return obj


def build(case):
    if case == "plane":
        return [plane(7)]
    if case == "plane_back":
        return [plane(7, rotation=(0.9 + math.pi, 0.0, 0.3))]
    if case == "single_quad":
        return [plane(0)]
    if case == "two_objects":
        return [plane(7, location=(-0.8, 0.8, 0)), plane(3, location=(1.2, -0.9, 0),
                                                         rotation=(0.4, 0.2, 1.1),
                                                         scale=(1, 1, 1))]
    if case == "subsurf":
        obj = plane(3, rotation=(0.6, 0.0, 0.3), scale=(1, 1, 1))
        for v in obj.data.vertices:  # a bump, so the subdivided surface curves
            v.co.z = 0.5 * math.exp(-4.0 * (v.co.x ** 2 + v.co.y ** 2))
        obj.modifiers.new("Subdivision", "SUBSURF")
        return [obj]
    if case == "bend":
        obj = plane(7, rotation=(0.3, 0.0, 0.3), scale=(1, 1, 1))
        bend = obj.modifiers.new("Bend", "SIMPLE_DEFORM")
        bend.deform_method = "BEND"
        bend.deform_axis = "X"
        bend.angle = math.radians(300)
        return [obj]
    raise SystemExit(f"unknown case {case}")


def main():
    enable_addon()
    bpy.data.objects.remove(bpy.data.objects["Cube"])
    scene = bpy.context.scene
    scene.render.resolution_x, scene.render.resolution_y = 480, 270
    objects = build(CASE)
    settings = scene.clothbake
    settings.bake_dir = os.path.join(TMP, "bake")
    check(bpy.ops.clothbake.bake() == {"FINISHED"}, f"{CASE}: Bake with the panel's defaults")
    for obj in scene.objects:
        obj.select_set(obj in objects)
    bpy.context.view_layer.objects.active = objects[0]
    check(bpy.ops.clothbake.apply() == {"FINISHED"}, f"{CASE}: Apply")
    for obj in objects:
        check(obj.modifiers[-1].name == "clothbake patch",
              f"{CASE}: '{obj.name}' has the patch modifier last "
              f"({[m.name for m in obj.modifiers]})")
    check(bpy.ops.clothbake.compare() == {"FINISHED"}, f"{CASE}: Compare")
    print(f"{CASE}: {settings.compare_status}")
    with open(os.path.join(settings.bake_folder(), "manifest.json")) as f:
        manifest = json.load(f)
    sides = [{k: v is not None for k, v in o["sides"].items()} for o in manifest["objects"]]
    print(f"{CASE}: quads {[o['quads'] for o in manifest['objects']]}, sides {sides}")
    want = {"plane": [{"front": True, "back": False}],
            "plane_back": [{"front": False, "back": True}],
            "bend": [{"front": True, "back": True}]}.get(CASE)
    if want is not None:
        check(sides == want, f"{CASE}: the bake's sides are {want}")
    if CASE == "subsurf":
        check(manifest["objects"][0]["quads"] == 256,
              "subsurf: the bake took the render mesh (level 2: 256 quads), not the viewport's")
    if CASE == "two_objects":
        check([o["quads"] for o in manifest["objects"]] == [64, 16], "two objects baked")


run_checks(main)
