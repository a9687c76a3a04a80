"""Headless Blender 3.4 test of the cloth material under the lights artists
use (beside the sun and the point light): a spot light and an area light,
then the area light moved (no re-bake, no re-apply), and the world per
route.

Tried as a new user would: Blender's default scene (--factory-startup), the
cube and the default point light deleted, a plane added (subdivided, 64
quads, scaled 2 x in Object Mode) and made a cloth with the panel's
defaults, a spot light and a rectangular area light added and aimed at
it; Bake material (small: texels 16, 12 view and 8 light directions, 1
sample; with 8 and 6 directions the material itself erred 8.1 % on the
second set-up, the back-lit disk) and Apply material (route exact). The render is set up as Compare
does (box filter, no bounces, the scene's resolution at 10 %). For each
light set-up the scene is exported with the add-on's exporter and
rendered by clothbake's reference renderer (`clothbake render`) and by
`lookup-render` from the same material (64 spp each, as the issue's
table); relative RMSE against the
reference must be at most 8 % for lookup-render and at most 1.25 x
lookup-render's + 1 % for Cycles (64 samples; the issue's bound). The
second set-up moves the area light to the far side, makes it a disk
(Blender's Shape, read live by a driver) and scales it unevenly (an ellipse
1.875 x 1.2, as the export writes it). Before each, the group's light
inputs are read back through the drivers and held to the lights' settings.

The world per route: the spot and area lights hidden, a sun added, the
world's Camera ray visibility off (so the world lights the cloth but never
shows), Apply material again. Exact route: the renders with a black world
and with a uniform world colour W are the same bit for bit (the world's
light is ignored, as clothbake's renderers ignore it). Cycles-lit: the
world alone (the sun hidden) against lookup-render of the same material
under 96 suns of equal solid angle standing in for the uniform world
(mean within 3 %; relative RMSE within 3 x the render's two-seed noise +
2 %, the 96 suns' own quadrature error included: on testscenes/flat the
world alone measured 0.9987 of them in the mean, 4.2 % per pixel at a
noise of 4.0 %); beside the sun the world adds what it gives alone
(mean within 3 %: the Diffuse closure's colour over E cos + pi W); and
with the sky above blocked by a plane hidden from the camera, what is left
is the light through the cloth from the world below (mean within 10 % of
lookup-render under the 48 suns below; measured 1.04, a part of 3.7 % of
the whole): the viewer's hemisphere goes
through the shadowed closure, the other through the Emission.

The light rig: the spot and the area light shown again, beside the sun, a
second area light (a square) and two point lights: 8 light terms (an area
light is read at two points), past where Cycles' 255-float SVM stack ran out
before (docs/design/material.md, "Lights and the SVM stack": black cloth under 3
point lights on cycles-lit, 5 on exact). Exact route, world black, 4
samples, one seed: the rig's render equals the sum of the six renders of one
light each (the others hidden: the drivers zero a hidden light) within float
rounding: at most 1 pixel in 1000 differs by more than 1e-4 x the image's
peak, none by more than 1e-2 x. (Measured with the view parallax of
--view-parallax: 1 pixel of 20736 at 3.4e-4 x the peak, in G and B only;
the same configuration rendered twice is bit-identical, so the hidden
lights' constants change how Cycles compiles the group, and one sample's
texel pick flips at a boundary; not isolated further. Before it: max
1.8e-6 x. A missing or doubled light term differs by 1e-2 x and more over
most of the cloth.) Cycles-lit: the cloth
is lit, and its mean within 3 x the two-seed noise + 2 % of the exact
route's (Cycles samples the lights itself; the material's two-point area
light is its only other difference).

    blender -b --factory-startup --python-exit-code 1 -P material_lights.py -- \
        CLOTHBAKE_EXE SOURCE_DIR WORK_DIR
"""
import json
import math
import os
import sys
import time

import bpy
import numpy as np
from mathutils import Vector

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from lib import program  # noqa: E402
from lib.checks import check, run_checks  # noqa: E402
from lib.headless import TMP, enable_addon  # noqa: E402
from lib.images import pixels, rel_rmse, render_still  # noqa: E402

SPP = 64                # Cycles, the exact-route samples
REF_SPP = 64            # clothbake render and lookup-render (the table)
PERCENT = 10            # of the default scene's 1920 x 1080
THREADS = "2"
WORLD = 0.4             # the uniform world's radiance, the world check
SUN = 2.0               # its sun's strength (irradiance)
WORLD_SUNS = 96         # suns standing in for the uniform world in lookup-render
T0 = time.time()


def run(args):
    return program.run(args + ["--threads", THREADS, "--quiet"])


def rgb(image):
    """An image's RGB in float64."""
    return image[..., :3].astype(np.float64)


def aim(obj, target):
    """Points the light's -Z at `target` (what an artist does with R or a
    Track To constraint), its Y up."""
    direction = Vector(target) - obj.location
    obj.rotation_mode = "QUATERNION"
    obj.rotation_quaternion = direction.to_track_quat("-Z", "Y")


def new_user_scene():
    """The default scene, the cube and the point light deleted, a plane made a
    cloth with the panel's defaults, a spot and an area light added."""
    for name in ("Cube", "Light"):
        bpy.data.objects.remove(bpy.data.objects[name])
    bpy.ops.mesh.primitive_plane_add(size=2)
    plane = bpy.context.active_object
    plane.name = "Cloth plane"
    bpy.ops.object.mode_set(mode="EDIT")
    bpy.ops.mesh.subdivide(number_cuts=7)
    bpy.ops.object.mode_set(mode="OBJECT")
    plane.scale = (2.0, 2.0, 1.0)
    plane.clothbake.is_cloth = True
    bpy.ops.object.light_add(type="SPOT", location=(-2.0, -2.5, 3.5))
    spot = bpy.context.active_object
    spot.data.energy = 600.0
    spot.data.spot_size = math.radians(50.0)
    spot.data.spot_blend = 0.25
    aim(spot, (0.3, 0.2, 0.0))
    bpy.ops.object.light_add(type="AREA", location=(2.5, -1.0, 2.0))
    area = bpy.context.active_object
    area.data.energy = 80.0
    area.data.shape = "RECTANGLE"
    area.data.size, area.data.size_y = 2.0, 0.8
    aim(area, (0.0, 0.0, 0.0))
    return plane, spot, area


# An area light's radiance per watt: P / (4 A) up to Blender 3.x, P / (pi A)
# from 4.0 (measured on a white plane in 3.4.1, 4.3.2 and 5.2.2:
# docs/design/blender-nodes.md), so clothbake's intensity per watt.
AREA_INTENSITY_PER_WATT = 0.25 if bpy.app.version < (4, 0, 0) else 1.0 / math.pi


def check_drivers(what, plane, area, spot):
    """The group's light inputs as the drivers evaluate them, against the
    lights' own settings and world matrices (lights in name order: the
    area light is light 0, the spot light 1)."""
    dg = bpy.context.evaluated_depsgraph_get()
    dg.update()
    node = plane.active_material.evaluated_get(dg).node_tree.nodes["Group"]
    got = {i.name: np.array(i.default_value[:] if hasattr(i.default_value, "__len__")
                            else [i.default_value]) for i in node.inputs if i.name[:6] == "Light "}
    m = area.matrix_world
    d = area.data
    size_y = d.size_y if d.shape in ("RECTANGLE", "ELLIPSE") else d.size
    want = {"Light 0 vector": m.translation, "Light 0 axis": -m.col[2].xyz.normalized(),
            "Light 0 side u": m.col[0].xyz * d.size, "Light 0 side v": m.col[1].xyz * size_y,
            "Light 0 ellipse": [1.0 if d.shape in ("DISK", "ELLIPSE") else 0.0],
            "Light 0 irradiance": Vector(d.color) * d.energy * AREA_INTENSITY_PER_WATT}
    m, d = spot.matrix_world, spot.data
    c = math.cos(d.spot_size / 2)
    want.update({"Light 1 vector": m.translation, "Light 1 axis": -m.col[2].xyz.normalized(),
                 "Light 1 cos half angle": [c], "Light 1 smooth": [(1 - c) * d.spot_blend],
                 "Light 1 irradiance": Vector(d.color) * d.energy / (4 * math.pi)})
    worst = max(float(np.abs(got[k] - np.array(v)).max() / max(1.0, np.abs(np.array(v)).max()))
                for k, v in want.items())
    check(worst < 1e-5, f"{what}: the drivers give the lights' settings (worst relative "
                        f"difference {worst:.1e} over {len(want)} inputs)")


def compare_case(what, tag, scene, material, export_scene):
    """Cycles (exact route) against clothbake's reference of the exported
    scene, and lookup-render of the same material against it."""
    t = time.time()
    cycles = rgb(render_still(os.path.join(TMP, f"{tag}_cycles.exr")))
    t_cycles = time.time() - t
    path = export_scene(scene, os.path.join(TMP, tag, "scene.json"))
    t = time.time()
    run(["render", path, "-o", os.path.join(TMP, f"{tag}_ref.exr"), "--spp", str(REF_SPP)])
    t_ref = time.time() - t
    run(["lookup-render", path, material, "-o", os.path.join(TMP, f"{tag}_lr.exr"),
         "--spp", str(REF_SPP)])
    ref = rgb(pixels(os.path.join(TMP, f"{tag}_ref.exr")))
    lr = rgb(pixels(os.path.join(TMP, f"{tag}_lr.exr")))
    e_cycles, e_lr, e_pair = rel_rmse(ref, cycles), rel_rmse(ref, lr), rel_rmse(lr, cycles)
    print(f"{what}: Cycles {e_cycles:.4f}, lookup-render {e_lr:.4f} against the reference; "
          f"Cycles against lookup-render {e_pair:.4f} (Cycles {t_cycles:.1f} s, reference "
          f"{t_ref:.1f} s)", flush=True)
    check(e_lr <= 0.08, f"{what}: lookup-render's relative RMSE {e_lr:.4f} <= 0.08")
    bound = 1.25 * e_lr + 0.01
    check(e_cycles <= bound, f"{what}: Cycles' relative RMSE {e_cycles:.4f} <= 1.25 x "
                             f"{e_lr:.4f} + 0.01 = {bound:.4f}")
    check(cycles[ref.mean(axis=2) > 0.1].mean() > 0.1, f"{what}: the cloth is lit")
    return path


def world_per_route(scene, plane, spot, area, apply_material, material, export_scene):
    """The world per route (module docstring)."""
    spot.hide_render = area.hide_render = True
    bpy.ops.object.light_add(type="SUN", location=(0.0, 0.0, 4.0))
    sun = bpy.context.active_object
    sun.data.energy = SUN
    sun.data.angle = 0.0
    aim(sun, (0.35, -0.45, -3.0))
    bpy.context.view_layer.update()
    world = scene.world
    world.cycles_visibility.camera = False
    background = world.node_tree.nodes["Background"]
    background.inputs["Strength"].default_value = 1.0
    images = {}
    for route in ("exact", "cycles-lit"):
        apply_material(plane, material, route=route)
        for w in (0.0, WORLD):
            background.inputs["Color"].default_value = (w, w, w, 1.0)
            images[route, w] = rgb(render_still(os.path.join(TMP, f"world_{route}_{w}.exr")))
    check(np.array_equal(images["exact", 0.0], images["exact", WORLD]),
          f"exact route: a uniform world of {WORLD} changes no pixel (bit for bit)")
    # Cycles-lit, the world alone (the sun hidden: no front light at all),
    # two seeds; against lookup-render of the material lit by WORLD_SUNS
    # suns of equal solid angle over the whole sphere (a Fibonacci lattice,
    # each of irradiance W 4 pi / N), WORLD_SUNS / 8 scenes of 8 summed.
    sun.hide_render = True
    alone = [rgb(render_still(os.path.join(TMP, f"world_alone_{seed}.exr"), seed=seed)) for seed in (1, 2)]
    sun.hide_render = False
    path = export_scene(scene, os.path.join(TMP, "world", "scene.json"))
    with open(path) as f:
        exported = json.load(f)
    golden = math.pi * (3.0 - math.sqrt(5.0))
    suns = []
    for n in range(WORLD_SUNS):
        z = 1.0 - 2.0 * (n + 0.5) / WORLD_SUNS
        r = math.sqrt(1.0 - z * z)
        suns.append({"type": "directional", "color": [1.0, 1.0, 1.0],
                     "intensity": WORLD * 4.0 * math.pi / WORLD_SUNS,
                     "direction": [-r * math.cos(n * golden), -r * math.sin(n * golden), -z]})
    summed, below = 0.0, 0.0
    for b in range(0, WORLD_SUNS, 8):
        batch = dict(exported, lights=suns[b:b + 8], background=[0.0, 0.0, 0.0])
        batch_path = os.path.join(TMP, "world", f"suns_{b}.json")
        with open(batch_path, "w") as f:
            json.dump(batch, f)
        out = os.path.join(TMP, "world", f"suns_{b}.exr")
        run(["lookup-render", batch_path, material, "-o", out, "--spp", "16"])
        summed = summed + rgb(pixels(out))
        if b >= WORLD_SUNS // 2:   # the lattice runs from z = 1 down: these suns are below
            below = below + rgb(pixels(out))
    cloth = summed.mean(axis=2) > 0.02 * summed.mean(axis=2).max()
    noise = rel_rmse(alone[0][cloth], alone[1][cloth]) / math.sqrt(2.0)
    ratio = float(alone[0][cloth].mean() / summed[cloth].mean())
    err = rel_rmse(summed[cloth], alone[0][cloth])
    bound = 3.0 * noise + 0.02
    print(f"world alone: cycles-lit {alone[0][cloth].mean():.4f}, lookup-render under "
          f"{WORLD_SUNS} suns {summed[cloth].mean():.4f}: ratio {ratio:.4f}, relative RMSE "
          f"{err:.4f} (noise {noise:.4f})", flush=True)
    check(abs(ratio - 1.0) <= 0.03, f"cycles-lit, the world alone: the mean is the material's "
                                    f"response to it ({ratio:.4f} of it, within 3 %)")
    check(err <= bound, f"cycles-lit, the world alone: relative RMSE {err:.4f} against "
                        f"{WORLD_SUNS} suns <= 3 x noise + 2 % = {bound:.4f}")
    # With the sun: the world adds the same (the closure's colour carries
    # both, over E cos + pi W).
    gain = images["cycles-lit", WORLD] - images["cycles-lit", 0.0]
    ratio = float(gain[cloth].mean() / alone[0][cloth].mean())
    print(f"world beside the sun: gain {gain[cloth].mean():.4f} against the world alone "
          f"{alone[0][cloth].mean():.4f} (ratio {ratio:.4f})", flush=True)
    if bpy.app.version >= (5, 0, 0):
        # A sun and the world overflow 5.x's SVM stack on this group (the
        # caution is checked with the rig below).
        print("world beside the sun: not checked in Blender 5.x (cycles-lit overflows "
              "Cycles' SVM stack there)", flush=True)
    else:
        check(abs(ratio - 1.0) <= 0.03, f"cycles-lit: the world adds beside a sun what it "
                                        f"gives alone ({ratio:.4f}, within 3 %)")
    # The world above the cloth blocked (a plane hidden from the camera):
    # what is left is the light through the cloth from the world below, the
    # group's Emission part (the other hemisphere's factors); the viewer's
    # hemisphere went through the closure, which Cycles now shadows.
    sun.hide_render = True
    bpy.ops.mesh.primitive_plane_add(size=200.0, location=(0.0, 0.0, 0.5))
    lid = bpy.context.active_object
    lid.visible_camera = False
    covered = rgb(render_still(os.path.join(TMP, "world_covered.exr")))
    bpy.data.objects.remove(lid)
    sun.hide_render = False
    ratio = float(covered[cloth].mean() / below[cloth].mean())
    print(f"world, the sky above blocked: cycles-lit {covered[cloth].mean():.4f}, lookup-render "
          f"under the {WORLD_SUNS // 2} suns below {below[cloth].mean():.4f} (ratio "
          f"{ratio:.4f}; all {WORLD_SUNS}: {summed[cloth].mean():.4f})", flush=True)
    # The part below is a few per cent of the whole (measured 0.0039 of
    # 0.1068), so 10 %: the 48 suns' quadrature of a small transmitted part
    # and the lid's gap at the horizon (0.3 degrees). Routed the wrong way
    # round (the viewer's hemisphere as Emission) it would be about 27 x.
    check(abs(ratio - 1.0) <= 0.10, f"cycles-lit, the sky above blocked: the light through the "
                                    f"cloth from the world below is left ({ratio:.4f} of it, "
                                    f"within 10 %)")
    # An HDRI: its image's mean over the sphere (cos-latitude weighted) x
    # the live strength; upper half (2, 0, 0), lower half (0, 0, 1): mean
    # (1, 0, 0.5).
    image = bpy.data.images.new("clothbake test sky", 64, 32, float_buffer=True)
    sky = np.zeros((32, 64, 4), np.float32)
    sky[..., 3] = 1.0
    sky[16:, :, 0], sky[:16, :, 2] = 2.0, 1.0
    image.pixels.foreach_set(sky.ravel())
    env = world.node_tree.nodes.new("ShaderNodeTexEnvironment")
    env.image = image
    world.node_tree.links.new(env.outputs["Color"], background.inputs["Color"])
    background.inputs["Strength"].default_value = 0.5
    _, notes = apply_material(plane, material, route="cycles-lit")
    dg = bpy.context.evaluated_depsgraph_get()
    dg.update()
    got = np.array(plane.active_material.evaluated_get(dg).node_tree.nodes["Group"]
                   .inputs["World radiance"].default_value[:])
    check(np.allclose(got, [0.5, 0.0, 0.25], atol=1e-5) and any("mean colour" in n for n in notes),
          f"an HDRI: its mean x strength drives World radiance ({got}), noted {notes}")
    world.node_tree.links.remove(background.inputs["Color"].links[0])
    world.node_tree.nodes.remove(env)
    background.inputs["Strength"].default_value = 1.0


def light_rig(scene, plane, lights, apply_material, material):
    """The light rig (module docstring). `lights`: the scene's lights so far."""
    background = scene.world.node_tree.nodes["Background"]
    background.inputs["Color"].default_value = (0.0, 0.0, 0.0, 1.0)
    for obj in lights:
        obj.hide_render = False
    bpy.ops.object.light_add(type="AREA", location=(-2.5, 1.5, 2.5))
    square = bpy.context.active_object
    square.data.energy, square.data.shape, square.data.size = 60.0, "SQUARE", 1.2
    aim(square, (0.0, 0.0, 0.0))
    for x, y, z, w in ((1.5, 2.0, 1.5, 150.0), (-0.5, -2.0, 1.2, 80.0)):
        bpy.ops.object.light_add(type="POINT", location=(x, y, z))
        bpy.context.active_object.data.energy = w
        bpy.context.active_object.data.shadow_soft_size = 0.0
    rig = [o for o in scene.objects if o.type == "LIGHT"]
    terms = sum(2 if o.data.type == "AREA" else 1 for o in rig)
    kinds = sorted(o.data.type.lower() for o in rig)
    samples = scene.cycles.samples
    scene.cycles.samples = 4
    apply_material(plane, material, route="exact")
    full = rgb(render_still(os.path.join(TMP, "rig_exact.exr")))
    total = np.zeros_like(full)
    for obj in rig:
        for other in rig:
            other.hide_render = other is not obj
        total += rgb(render_still(os.path.join(TMP, f"rig_exact_{obj.name}.exr")))
    for obj in rig:
        obj.hide_render = False
    diff = float(np.abs(full - total).max())
    over = float((np.abs(full - total).max(axis=2) > 1e-4 * full.max()).mean())
    cloth = full.mean(axis=2) > 0.02
    print(f"light rig ({len(rig)} lights, {terms} terms: {', '.join(kinds)}): exact route mean "
          f"{full[cloth].mean():.4f}, against the sum of the single lights max difference "
          f"{diff:.2e} (peak {full.max():.4f}); pixels over 1e-4 x the peak: {over:.2e}",
          flush=True)
    check(cloth.mean() > 0.2 and full[cloth].mean() > 0.05,
          f"the rig's exact route lights the cloth ({cloth.mean():.2f} of the pixels)")
    check(over <= 1e-3 and diff <= 1e-2 * full.max(),
          f"exact route: the rig's render is the sum of its {len(rig)} single-light renders "
          f"(share of pixels over 1e-4 x the peak {over:.2e} <= 1e-3; max {diff:.2e} <= "
          f"1e-2 x {full.max():.4f})")
    if bpy.app.version >= (5, 0, 0):
        # Blender 5.x's Cycles overflows its SVM stack on cycles-lit groups of
        # this size (docs/design/material.md, "Lights and Cycles' SVM stack"):
        # what is checked there is that Apply material says so.
        _, notes = apply_material(plane, material, route="cycles-lit")
        check(any("overflows Cycles' shader stack" in n for n in notes),
              f"cycles-lit in Blender {bpy.app.version_string}: Apply material cautions that "
              f"the route overflows Cycles' SVM stack ({notes})")
        return
    scene.cycles.samples = 16
    exact = rgb(render_still(os.path.join(TMP, "rig_exact16.exr")))
    apply_material(plane, material, route="cycles-lit")
    lit = [rgb(render_still(os.path.join(TMP, f"rig_lit_{seed}.exr"), seed=seed)) for seed in (1, 2)]
    scene.cycles.samples = samples
    means = [float(x[cloth].mean()) for x in lit]
    noise = abs(means[0] - means[1]) / math.sqrt(2.0) / float(exact[cloth].mean())
    ratio = means[0] / float(exact[cloth].mean())
    print(f"light rig, cycles-lit: cloth mean {means[0]:.4f} (seed 2: {means[1]:.4f}), exact "
          f"route {exact[cloth].mean():.4f}: ratio {ratio:.4f}, noise {noise:.4f}", flush=True)
    check(min(means) > 0.5 * float(exact[cloth].mean()),
          f"cycles-lit: the rig lights the cloth (not black: {min(means):.4f})")
    check(abs(ratio - 1.0) <= 3.0 * noise + 0.02,
          f"cycles-lit: the rig's cloth mean against the exact route's {ratio:.4f} within "
          f"3 x {noise:.4f} + 0.02")


def main():
    enable_addon().threads = int(THREADS)      # the program's; Cycles' below
    from clothbake.blender.material_apply import apply_material
    from clothbake.blender.scene_export_bpy import export_scene
    from clothbake.blender.scene_import import set_render_settings

    scene = bpy.context.scene
    plane, spot, area = new_user_scene()
    world_colour = list(scene.world.node_tree.nodes["Background"].inputs["Color"]
                        .default_value[:3])
    scene.render.resolution_percentage = PERCENT
    set_render_settings(scene, {"resolution": [1920 * PERCENT // 100, 1080 * PERCENT // 100]},
                        world_colour, samples=SPP)
    scene.render.threads_mode = "FIXED"
    scene.render.threads = int(THREADS)
    settings = scene.clothbake
    settings.material_dir = os.path.join(TMP, "material")
    settings.material_texels, settings.material_directions = 16, 12
    settings.material_light_directions, settings.material_spp = 8, 1
    for obj in scene.objects:
        obj.select_set(obj == plane)
    bpy.context.view_layer.objects.active = plane
    t = time.time()
    check(bpy.ops.clothbake.bake_material() == {"FINISHED"},
          f"Bake material in a scene lit by a spot and an area light ({settings.material_status})")
    print(f"Bake material: {time.time() - t:.1f} s", flush=True)
    material = settings.material_folder()
    check(bpy.ops.clothbake.apply_material() == {"FINISHED"}, "Apply material")
    _, notes = apply_material(plane, material, route="exact")
    check(not any("not lit" in n for n in notes), f"Apply material's notes: {notes}")
    group = plane.active_material.node_tree.nodes["Group"]
    check(all(f"Light {l} axis" in group.inputs for l in (0, 1)) and
          "Light 0 side u" in group.inputs and "Light 1 smooth" in group.inputs,
          "the group has the area light's (0) and the spot's (1) inputs")

    check_drivers("spot + rectangle", plane, area, spot)
    compare_case("spot + rectangle area light", "lights", scene, material, export_scene)
    area.location = (-1.5, 2.0, 1.8)
    aim(area, (0.2, -0.2, 0.0))
    area.data.shape = "DISK"
    area.data.size = 1.5
    area.scale = (1.25, 0.8, 1.0)    # a disk scaled unevenly: an ellipse 1.875 x 1.2
    check_drivers("moved, a disk scaled unevenly", plane, area, spot)
    path = compare_case("the area light moved, made a disk and scaled (no re-bake, no "
                        "re-apply)", "moved", scene, material, export_scene)
    with open(path) as f:
        exported = {l["type"]: l for l in json.load(f)["lights"]}
    check(sorted(exported) == ["area", "spot"] and exported["area"]["shape"] == "ellipse" and
          np.allclose(exported["area"]["size"], [1.875, 1.2], rtol=1e-6),
          f"the export holds the spot and the ellipse ({exported.get('area')})")
    world_per_route(scene, plane, spot, area, apply_material, material, export_scene)
    light_rig(scene, plane, [spot, area], apply_material, material)
    print(f"material_lights: {time.time() - T0:.0f} s", flush=True)


run_checks(main)
