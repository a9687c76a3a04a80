"""Headless Blender 3.4 test of the cloth material in Blender:
every route against clothbake's own lookup of the same material.

A flat 2 x 2 cloth of the paper weave (8 x 8 quads, made here) and one
small material baked from it (`clothbake material`, R 16, K 8, KL 6). Each
Blender render is compared with `clothbake lookup-render` of the matching
scene JSON and the same material:

  exact         Cycles, Emission + Transparent
  moved light   the lights moved, recoloured and re-powered in Blender after
                Apply (drivers; no re-apply), against the scene with them there
  moved camera  likewise the camera
  deformed      a shape key bends the cloth (frame 2), against the bent OBJ
  eevee         Eevee, the same node group
  cycles-lit    the Diffuse route, nothing in the way: the same expectation
  shadow        a sphere between the sun and the cloth: on the cycles-lit
                route the sun's part is gone inside the shadow (computed
                here by ray casting), kept outside it; on the exact route
                the cloth ignores the sphere
  refusals      a mesh with no UV map, a camera, a missing folder: one
                ClothbakeError each, never a traceback
  paper         the paper scene with a small material of its cloth: Eevee
                against Cycles

Bounds are derived from the samples used: every Blender render is made with
two seeds, and their relative RMSE d gives the render's own noise
sigma = d / sqrt(2); lookup-render's 64 stratified samples per pixel carry
at most as much (it has no stochastic picks). A comparison passes when its
relative RMSE is at most 3 sqrt(2) sigma (three standard deviations of the
difference of two such images) plus the systematic part stated by each
check (the dense light grid against clothbake's Catmull-Rom, the rank kept,
Eevee's own filtering), measured in docs/design/material.md.

    blender -b --factory-startup --python-exit-code 1 -P material_routes.py -- \
        CLOTHBAKE_EXE SOURCE_DIR WORK_DIR
"""
import json
import math
import os
import sys

import bpy
import numpy as np
from mathutils import Matrix, Vector

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from lib.checks import check, run_checks  # noqa: E402
from lib.headless import SOURCE, TMP, enable_addon  # noqa: E402
from lib.images import pixels, render_still, save_png  # noqa: E402
from lib.noise import Noisy, within_noise  # noqa: E402
from lib.program import run  # noqa: E402
from lib.scene import lit_flat_scene  # noqa: E402

SPP = 64
N = 8  # quads a side
# Systematic parts (docs/design/material.md, "Blender"): the resampled light grid
# and the rank kept against lookup-render's Catmull-Rom over all components;
# on the bent cloth, Blender's subdivided triangles against clothbake's
# bilinear patches; Eevee's hashed transparency and float16 textures.
SYS = 0.01
SYS_BENT = 0.015
SYS_EEVEE = 0.015

BASE = lit_flat_scene(SPP)


def plane(z_of=lambda x, y: 0.0):
    """Vertices, UVs and quads of the 2 x 2 cloth, z = z_of(x, y)."""
    verts, uvs, quads = [], [], []
    for j in range(N + 1):
        for i in range(N + 1):
            x, y = -1.0 + 2.0 * i / N, -1.0 + 2.0 * j / N
            verts.append((x, y, z_of(x, y)))
            uvs.append((i / N, j / N))
    for j in range(N):
        for i in range(N):
            a = j * (N + 1) + i
            quads.append((a, a + 1, a + N + 2, a + N + 1))
    return verts, uvs, quads


def bend(x, y):
    return 0.35 * (1.0 - x * x) * (0.5 + 0.25 * y)


def write_obj(path, verts, uvs, quads):
    with open(path, "w") as f:
        for v in verts:
            f.write("v %.7f %.7f %.7f\n" % v)
        for t in uvs:
            f.write("vt %.7f %.7f\n" % t)
        for q in quads:
            f.write("f " + " ".join(f"{i + 1}/{i + 1}" for i in q) + "\n")


def write_scene(name, obj_path, changes=None):
    scene = json.loads(json.dumps(BASE))
    scene["name"] = name
    scene["objects"] = [{"name": "cloth", "mesh": obj_path,
                         "cloth": os.path.join(SOURCE, "testscenes", "paper", "cloth.json"),
                         "repeats_per_uv": 12, "thickness_world": 0.06,
                         "extinction_per_mm": 40}]
    for key, value in (changes or {}).items():
        scene[key] = value
    path = os.path.join(TMP, name + ".json")
    with open(path, "w") as f:
        json.dump(scene, f, indent=1)
    return path


def pair(name, seeds=(1, 2)):
    a = render_still(os.path.join(TMP, f"{name}_s{seeds[0]}.exr"), seeds[0])
    b = render_still(os.path.join(TMP, f"{name}_s{seeds[1]}.exr"), seeds[1])
    return Noisy(a, b)


def eevee_pair(name, use_eevee):
    """An Eevee render at SPP samples and its noise. Eevee has no seed: the
    noise comes from SPP against 2 SPP samples (the difference has variance
    sigma^2 (1 + 1/2), so sigma = d / sqrt(1.5)). Leaves Eevee on."""
    scene = bpy.context.scene
    use_eevee(scene, SPP)
    a = render_still(os.path.join(TMP, f"{name}.exr"), 1)
    use_eevee(scene, 2 * SPP)
    b = render_still(os.path.join(TMP, f"{name}2.exr"), 1)
    return Noisy(a, b, spread=math.sqrt(1.5))


def main():
    enable_addon()
    from clothbake.blender.material_apply import apply_material
    from clothbake.blender.headless import bilinear_patches
    from clothbake.blender.render_engines import use_eevee
    from clothbake.blender.scene_import import import_scene
    from clothbake.core.errors import ClothbakeError

    flat_obj = os.path.join(TMP, "flat.obj")
    bent_obj = os.path.join(TMP, "bent.obj")
    write_obj(flat_obj, *plane())
    write_obj(bent_obj, *plane(bend))
    base = write_scene("base", flat_obj)
    moved_lights = [
        {"type": "directional", "direction": [-0.7, 0.1, -0.45], "color": [0.7, 0.8, 1.0],
         "intensity": 4.0},
        {"type": "point", "position": [1.2, -1.4, 0.7], "color": [1.0, 0.6, 0.4],
         "intensity": 1.5},
    ]
    moved_camera = dict(BASE["camera"], position=[1.9, -1.2, 2.2])
    lights_scene = write_scene("lights", flat_obj, {"lights": moved_lights})
    camera_scene = write_scene("camera", flat_obj, {"camera": moved_camera})
    bent_scene = write_scene("bent", bent_obj)

    material = os.path.join(TMP, "material")
    run(["material", base, "-o", material, "--parts", "rgb", "--texels", "16", "--directions", "8",
         "--light-directions", "6", "--spp", "1", "--quiet"])
    refs = {}
    for name, path in (("base", base), ("lights", lights_scene), ("camera", camera_scene),
                       ("bent", bent_scene)):
        out = os.path.join(TMP, f"ref_{name}.exr")
        run(["lookup-render", path, material, "-o", out, "--spp", str(SPP), "--quiet"])
        refs[name] = pixels(out)

    # Exact route, then lights and camera moved in Blender with no re-apply.
    (obj,) = import_scene(base, clear=True, samples=SPP)
    bilinear_patches(obj)
    _, notes = apply_material(obj, material, route="exact")
    print("notes:", notes)
    exact_n = pair("exact")
    exact = exact_n.image
    within_noise("Cycles, exact route", exact_n, refs["base"], SYS)

    scene = bpy.context.scene
    lights = sorted((o for o in scene.objects if o.type == "LIGHT"), key=lambda o: o.name)
    from clothbake.core.light_units import light_units
    from clothbake.core.scene import blender_light
    units = light_units(bpy.app.version)
    for o, spec in zip(lights, moved_lights):
        s = blender_light(spec, units)
        o.matrix_world = Matrix(s["matrix"])
        o.data.color = s["color"]
        o.data.energy = s["energy"]
    within_noise("lights moved, recoloured, re-powered after Apply", pair("lights"), refs["lights"],
            SYS)
    for o, spec in zip(lights, BASE["lights"]):
        s = blender_light(spec, units)
        o.matrix_world = Matrix(s["matrix"])
        o.data.color = s["color"]
        o.data.energy = s["energy"]

    from clothbake.core.scene import blender_camera
    cam = scene.camera
    cam.matrix_world = Matrix(blender_camera(moved_camera)["matrix"])
    within_noise("camera moved after Apply", pair("camera"), refs["camera"], SYS)
    cam.matrix_world = Matrix(blender_camera(BASE["camera"])["matrix"])

    # A shape key bends the cloth at frame 2; the material stays as applied.
    verts, _, _ = plane(bend)
    obj.shape_key_add(name="Basis")
    key = obj.shape_key_add(name="bent")
    for i, v in enumerate(verts):
        key.data[i].co = v
    key.value = 0.0
    key.keyframe_insert("value", frame=1)
    key.value = 1.0
    key.keyframe_insert("value", frame=2)
    scene.frame_set(2)
    within_noise("shape key, frame 2, against the bent OBJ", pair("bent"), refs["bent"], SYS_BENT)
    scene.frame_set(1)
    within_noise("shape key back at frame 1, against the flat OBJ", pair("frame1", (3, 4)),
            refs["base"], SYS)

    # Eevee, the same node group.
    eevee_n = eevee_pair("eevee", use_eevee)
    eevee = eevee_n.image
    within_noise("Eevee against lookup-render", eevee_n, refs["base"], SYS_EEVEE)
    within_noise("Eevee against Cycles", eevee_n, exact, SYS_EEVEE,
            ref_sigma=(exact_n.sigma, exact_n.sigma4))
    scene.render.engine = "CYCLES"

    # cycles-lit, nothing in the way: the same expectation as exact.
    apply_material(obj, material, route="cycles-lit")
    lit_n = pair("lit")
    lit = lit_n.image
    within_noise("cycles-lit against exact, unshadowed", lit_n, exact, 0.0,
            ref_sigma=(exact_n.sigma, exact_n.sigma4))

    # A sphere between the sun and the cloth.
    to_sun = -Vector(BASE["lights"][0]["direction"]).normalized()
    centre = Vector((0.15, 0.05, 0.0)) + 0.8 * to_sun
    radius = 0.3
    bpy.ops.mesh.primitive_uv_sphere_add(radius=radius, location=centre, segments=48,
                                         ring_count=24)
    sphere = bpy.context.active_object
    sphere.visible_camera = False   # the shadow only: the cloth stays in view
    lit_s = pair("lit_sphere").image
    mask = shadow_mask(centre, radius, to_sun)
    point = np.array(BASE["lights"][1]["position"], float)
    either = mask | shadow_mask(centre, radius, None, point)
    alpha = exact[..., 3] > 0.99
    inside, outside = mask & alpha, ~either & alpha
    check(inside.sum() > 50, f"the sphere's shadow covers {int(inside.sum())} cloth pixels")
    ratio_in = float(lit_s[inside][:, :3].mean() / exact[inside][:, :3].mean())
    ratio_out = float(lit_s[outside][:, :3].mean() / exact[outside][:, :3].mean())
    # The sun gives most of the light here; inside the shadow only the
    # point light is left.
    check(ratio_in < 0.6, f"cycles-lit: the sphere's shadow darkens the cloth to {ratio_in:.3f} "
                          "of the exact route (< 0.6)")
    # The mean over n pixels: the ratio's noise is about sigma / sqrt(n).
    tol = 3.0 * math.hypot(lit_n.sigma, exact_n.sigma) / math.sqrt(outside.sum())
    check(abs(ratio_out - 1.0) < tol + 0.01,
          f"cycles-lit: outside any shadow the cloth keeps {ratio_out:.4f} of the exact route "
          f"(within {tol:.4f} + 0.01 for the sphere's bounce-free occlusion of the sky)")
    apply_material(obj, material, route="exact")
    ex_s = render_still(os.path.join(TMP, "exact_sphere.exr"), 1)
    ratio_ex = float(ex_s[inside][:, :3].mean() / exact[inside][:, :3].mean())
    check(abs(ratio_ex - 1.0) < 0.05, f"exact route: the sphere casts no shadow on the cloth "
                                      f"({ratio_ex:.4f} of the unshadowed render)")
    save_sheet([refs["base"], exact, eevee, lit, lit_s],
               os.path.join(os.environ.get("CLOTHBAKE_SHEET_DIR", TMP), "material_routes.png"))

    # A second object with the same material keeps the first one's working
    # (the group is shared, never removed under it).
    twin = obj.copy()
    twin.data = obj.data.copy()
    scene.collection.objects.link(twin)
    apply_material(twin, material, route="exact")
    apply_material(obj, material, route="exact")
    for o in (obj, twin):
        group = next(n for n in o.active_material.node_tree.nodes if n.type == "GROUP")
        check(group.node_tree is not None and len(group.inputs) > 10,
              f"'{o.name}' keeps its node group after the other object's Apply "
              f"({len(group.inputs)} inputs)")

    # Refusals: no UV map, not a mesh, no material folder.
    mesh = bpy.data.meshes.new("no uv")
    mesh.from_pydata([(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)], [], [(0, 1, 2, 3)])
    bare = bpy.data.objects.new("bare", mesh)
    scene.collection.objects.link(bare)
    for target, folder, text, what in (
            (bare, material, "no UV map", "a mesh with no UV map"),
            (scene.camera, material, "is not a mesh", "a camera"),
            (obj, os.path.join(TMP, "nowhere"), "nowhere", "a missing material folder")):
        try:
            apply_material(target, folder)
            check(False, f"{what}: refused")
        except ClothbakeError as e:
            check(text in str(e), f"{what}: refused with '{e}'")
    check(len(bare.data.materials) == 0, "the refused mesh was left as it was")

    # The paper scene (folded quads, fibre shading, y up): Eevee against
    # Cycles there, with a small material of the paper cloth.
    paper = os.path.join(SOURCE, "testscenes", "paper", "scene.json")
    paper_material = os.path.join(TMP, "paper_material")
    run(["material", paper, "-o", paper_material, "--parts", "rgb", "--texels", "16", "--directions", "8",
         "--light-directions", "6", "--spp", "1", "--quiet"])
    (cloth,) = import_scene(paper, clear=True, samples=SPP)
    bilinear_patches(cloth)
    apply_material(cloth, paper_material, route="exact")
    cycles_paper = pair("paper_cycles")
    within_noise("paper scene: Eevee against Cycles", eevee_pair("paper_eevee", use_eevee), cycles_paper.image, SYS_EEVEE,
            ref_sigma=(cycles_paper.sigma, cycles_paper.sigma4))
    scene.render.engine = "CYCLES"


def shadow_mask(centre, radius, to_sun, light_at=None):
    """Cloth pixels whose point on the plane z = 0 sees the sphere toward the
    sun (or toward the point light at `light_at`): ray casting through
    clothbake's pinhole camera, pixel centres."""
    cam = BASE["camera"]
    w, h = cam["resolution"]
    eye = np.array(cam["position"], float)
    forward = np.array(cam["look_at"], float) - eye
    forward /= np.linalg.norm(forward)
    right = np.cross(forward, cam["up"])
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    half = math.tan(math.radians(cam["fov_deg"]) / 2.0)
    xs = ((np.arange(w) + 0.5) / w * 2.0 - 1.0) * half
    ys = (1.0 - (np.arange(h) + 0.5) / h * 2.0) * half * h / w
    X, Y = np.meshgrid(xs, ys)
    d = forward + X[..., None] * right + Y[..., None] * up
    t = -eye[2] / d[..., 2]
    p = eye + t[..., None] * d
    c = np.array(centre, float)
    if light_at is None:
        s = np.broadcast_to(np.array(to_sun, float), p.shape)
        reach = np.full(p.shape[:2], np.inf)
    else:
        s = light_at - p
        reach = np.linalg.norm(s, axis=-1)
        s = s / reach[..., None]
    oc = p - c
    b = (oc * s).sum(-1)
    disc = b * b - ((oc * oc).sum(-1) - radius * radius)
    far = -b + np.sqrt(np.maximum(disc, 0))
    return (disc > 0) & (far > 0) & (-b - np.sqrt(np.maximum(disc, 0)) < reach) & (t > 0)


def save_sheet(images, path):
    save_png(images, path)
    print("sheet:", path)


run_checks(main)
