"""Renders a flat clothbake scene in Blender 3.4 Cycles as a real volume: the
tiled volume texture (lab/common/tile_volume.py) placed where clothbake's map
puts it, with the scene's camera, lights and background.

  blender -b --factory-startup --python-exit-code 1 -P volume_render.py -- \
      SCENE.json VOLUME_DIR TILED.vdb LIGHT_UNITS.json OUT_DIR \
      --samples 1,4,16 [--seed S[,S2..]] [--color albedo|grid] [--voxel-shift 0.5] \
      [--step-rate 1] [--interpolation LINEAR|CUBIC] [--tag volume]

Writes OUT_DIR/TAG_sN_seedS.exr (linear RGBA float) per sample count and
seed, and per seed OUT_DIR/TAG_seedS_timing.json: load seconds (scene set-up and loading the
VDB's grids) and, per sample count, the wall seconds of
bpy.ops.render.render() alone (Cycles' scene sync, volume upload and
sampling; saving the EXR is excluded) and the CPU seconds (user + system,
all threads) Blender spent in it.

Physics (docs/formats/scene.md; clothbake's `isotropic` shading):
- Principled Volume, Density = extinction_per_mm x mm per world unit times the
  `density` grid, Color = the object's isotropic_albedo (--color albedo, the
  default, as clothbake's isotropic mode) or the `diffuse` grid through an
  Attribute node (--color grid), Absorption Color black (so extinction =
  density, scattering = Color x density), anisotropy 0 (isotropic phase).
- volume_bounces 0: single scattering with shadowed direct light (see
  ../shared/BLENDER_NOTES.md), the same as clothbake's march.
- Volume precision FULL, step rate 1 (one voxel; --step-rate r: r voxels),
  trilinear lookup (--interpolation CUBIC: the material's cubic lookup).
- Lights: Sun strength and point power from the measured LIGHT_UNITS.json
  (lab/light_units/light_units.py): strength = intensity / (irradiance per
  unit strength), power = intensity / (irradiance at 1 unit per watt).
  Both hard (sun angle 0, point radius 0).
- Density in WORLD space (vol.render.space): with OBJECT space Cycles reads
  the Density as extinction per *object* unit, here per texture mm, so the
  per-world value above would be multiplied by the object's scale in mm per
  world unit (measured on testscenes/slab: OBJECT gave alpha 0.9999 where the
  slab's exp(-1.8) see-through needs 0.8347; WORLD gives 0.8350).
- Background: a transparent film (alpha = 1 - transmittance, as clothbake's
  alpha) with a black world that lights nothing (clothbake's background
  lights nothing), then composited here as RGB + (1 - alpha) x background,
  which is what clothbake writes. Why not a world that shows the background
  to camera rays only (Light Path: Is Camera Ray): a camera ray that has
  crossed a volume object is no longer a camera ray there, so the background
  seen through the cloth came out black; and a world shown to every ray
  lights the volume (measured on the slab: +0.036 on a 0.059 pixel).
- Camera: pinhole at the scene's position, looking at look_at with its up;
  sensor fit along fov_axis, the field of view fov_deg; pixel filter BOX
  width 1 (clothbake averages over the pixel square); adaptive sampling and
  denoising off.
- --voxel-shift s moves the object by -s voxel on every axis: Cycles shows
  voxel i's value centred at index position i + 0.5 from the grid's own
  placement (BLENDER_NOTES.md), i.e. half a voxel off clothbake's cell
  centre; s = 0.5 (the default) puts it back.
"""
import argparse
import json
import math
import os
import resource
import sys
import time

import bpy
from mathutils import Matrix, Vector

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import flat_volume  # noqa: E402


def cpu_seconds():
    r = resource.getrusage(resource.RUSAGE_SELF)
    return r.ru_utime + r.ru_stime


def composite_background(path, background):
    """Rewrites the EXR at path (transparent film: premultiplied RGB, alpha
    = 1 - transmittance) as RGB + (1 - alpha) x background, alpha kept."""
    import numpy as np
    import OpenImageIO as oiio
    buf = oiio.ImageBuf(path)
    px = buf.get_pixels(oiio.FLOAT)
    px[..., :3] += (1.0 - px[..., 3:4]) * np.asarray(background, np.float32)
    spec = oiio.ImageSpec(buf.spec().width, buf.spec().height, 4, oiio.FLOAT)
    out = oiio.ImageOutput.create(path)
    if out is None or not out.open(path, spec) or not out.write_image(px) or not out.close():
        raise SystemExit("cannot rewrite %s: %s" % (path, oiio.geterror()))


def parse():
    ap = argparse.ArgumentParser(prog="volume_render.py", description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    for name in ("scene", "volume_dir", "tiled_vdb", "light_units", "out_dir"):
        ap.add_argument(name)
    ap.add_argument("--samples", default="1", help="comma-separated sample counts")
    ap.add_argument("--seed", default="1", help="comma-separated seeds")
    ap.add_argument("--color", default="albedo", choices=("albedo", "grid"))
    ap.add_argument("--voxel-shift", type=float, default=0.5)
    ap.add_argument("--tag", default="volume")
    ap.add_argument("--threads", type=int, default=0, help="0: Cycles' own choice")
    ap.add_argument("--step-rate", type=float, default=1.0)
    ap.add_argument("--interpolation", default="LINEAR", choices=("LINEAR", "CUBIC"))
    return ap.parse_args(sys.argv[sys.argv.index("--") + 1:])


def main():
    t_start = time.perf_counter()
    opt = parse()
    scene_path, vdir, tiled, units_path, out_dir = (opt.scene, opt.volume_dir, opt.tiled_vdb,
                                                    opt.light_units, opt.out_dir)
    samples = [int(s) for s in opt.samples.split(",")]
    seeds = [int(s) for s in opt.seed.split(",")]
    shift = opt.voxel_shift
    with open(os.path.join(vdir, "volume.json")) as f:
        vmeta = json.load(f)
    with open(units_path) as f:
        units = json.load(f)
    lay = flat_volume.layout(scene_path, vmeta["size_mm"])
    cells, size = vmeta["cells"], vmeta["size_mm"]
    voxel_mm = [s / n for s, n in zip(size, cells)]

    bpy.ops.wm.read_factory_settings(use_empty=True)
    sc = bpy.context.scene

    # The volume object: texture mm -> world (flat_volume.py), then -shift voxel.
    vol = bpy.data.volumes.new("cloth")
    vol.filepath = os.path.abspath(tiled)
    if not vol.grids.load():
        raise SystemExit("cannot load %s: %s" % (tiled, vol.grids.error_message))
    for g in vol.grids:
        g.load()
    vol.render.precision = "FULL"
    vol.render.space = "WORLD"  # density per world unit (see the top)
    vol.render.step_size = 0.0
    ob = bpy.data.objects.new("cloth", vol)
    sc.collection.objects.link(ob)
    u, v, n = Vector(lay["u_vec"]), Vector(lay["v_vec"]), Vector(lay["normal"])
    wpm = lay["world_per_mm"]
    ax = [u.normalized() * wpm[0], v.normalized() * wpm[1], n * wpm[2]]
    origin = Vector(lay["origin"]) - n * lay["thickness_world"]
    origin -= sum((ax[a] * (shift * voxel_mm[a]) for a in range(3)), Vector())
    m = Matrix.Identity(4)
    for a in range(3):
        for r in range(3):
            m[r][a] = ax[a][r]
        m[a][3] = origin[a]
    ob.matrix_world = m

    mat = bpy.data.materials.new("cloth_volume")
    mat.use_nodes = True
    nt = mat.node_tree
    nt.nodes.clear()
    pv = nt.nodes.new("ShaderNodeVolumePrincipled")
    pv.inputs["Density"].default_value = lay["extinction_per_world"]
    pv.inputs["Density Attribute"].default_value = "density"
    pv.inputs["Anisotropy"].default_value = 0.0
    pv.inputs["Absorption Color"].default_value = (0, 0, 0, 1)
    pv.inputs["Emission Strength"].default_value = 0.0
    pv.inputs["Blackbody Intensity"].default_value = 0.0
    if opt.color == "grid":
        attr = nt.nodes.new("ShaderNodeAttribute")
        attr.attribute_name = "diffuse"
        nt.links.new(attr.outputs["Color"], pv.inputs["Color"])
    else:
        pv.inputs["Color"].default_value = tuple(lay["albedo"]) + (1.0,)
    outn = nt.nodes.new("ShaderNodeOutputMaterial")
    nt.links.new(pv.outputs["Volume"], outn.inputs["Volume"])
    mat.cycles.volume_interpolation = opt.interpolation
    ob.data.materials.append(mat)

    # Lights.
    for i, L in enumerate(lay["lights"]):
        color = L.get("color", [1, 1, 1])
        inten = L.get("intensity", 1.0)
        if L["type"] == "directional":
            ld = bpy.data.lights.new("light%d" % i, "SUN")
            ld.energy = inten / units["sun_irradiance_per_strength"]
            ld.angle = 0.0
            lo = bpy.data.objects.new("light%d" % i, ld)
            d = Vector(L["direction"]).normalized()
            lo.rotation_euler = d.to_track_quat("-Z", "Y").to_euler()
        else:
            ld = bpy.data.lights.new("light%d" % i, "POINT")
            ld.energy = inten / units["point_irradiance_at_1_per_watt"]
            ld.shadow_soft_size = 0.0
            lo = bpy.data.objects.new("light%d" % i, ld)
            lo.location = L["position"]
        ld.color = color
        sc.collection.objects.link(lo)

    # World: black, lights nothing; the background is composited after the
    # render (see the top).
    world = bpy.data.worlds.new("black")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Color"].default_value = (0, 0, 0, 1)
    world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.0
    world.cycles.sampling_method = "NONE"
    sc.world = world

    # Camera.
    cam = lay["camera"]
    cd = bpy.data.cameras.new("camera")
    cd.type = "PERSP"
    fov = math.radians(cam.get("fov_deg", 40))
    if cam.get("fov_axis", "horizontal") == "horizontal":
        cd.sensor_fit = "HORIZONTAL"
        cd.angle_x = fov
    else:
        cd.sensor_fit = "VERTICAL"
        cd.angle_y = fov
    cd.clip_start = 1e-3
    cd.clip_end = 1e4
    co = bpy.data.objects.new("camera", cd)
    pos = Vector(cam.get("position", [0, 0, 5]))
    fwd = (Vector(cam.get("look_at", [0, 0, 0])) - pos).normalized()
    right = fwd.cross(Vector(cam.get("up", [0, 1, 0]))).normalized()
    up = right.cross(fwd)
    cm = Matrix.Identity(4)
    for r in range(3):
        cm[r][0], cm[r][1], cm[r][2], cm[r][3] = right[r], up[r], -fwd[r], pos[r]
    co.matrix_world = cm
    sc.collection.objects.link(co)
    sc.camera = co

    res = cam.get("resolution", [426, 266])
    r = sc.render
    r.engine = "CYCLES"
    r.resolution_x, r.resolution_y = res
    r.resolution_percentage = 100
    r.film_transparent = True
    r.threads_mode = "AUTO" if opt.threads <= 0 else "FIXED"
    if opt.threads > 0:
        r.threads = opt.threads
    cy = sc.cycles
    cy.device = "CPU"
    cy.use_adaptive_sampling = False
    cy.use_denoising = False
    cy.pixel_filter_type = "BOX"
    cy.filter_width = 1.0
    cy.max_bounces = 1024  # volume_bounces 0 is what limits the paths
    cy.volume_bounces = 0
    cy.diffuse_bounces = cy.glossy_bounces = cy.transmission_bounces = 0
    cy.transparent_max_bounces = 64
    cy.volume_step_rate = opt.step_rate
    cy.volume_max_steps = 1024
    cy.sample_clamp_direct = cy.sample_clamp_indirect = 0.0
    cy.use_auto_tile = False
    r.image_settings.file_format = "OPEN_EXR"
    r.image_settings.color_mode = "RGBA"
    r.image_settings.color_depth = "32"
    sc.view_settings.view_transform = "Standard"

    load_s = time.perf_counter() - t_start
    os.makedirs(out_dir, exist_ok=True)
    tag = opt.tag
    for seed in seeds:
        cy.seed = seed
        runs = []
        for ns in samples:
            cy.samples = ns
            c0, t0 = cpu_seconds(), time.perf_counter()
            bpy.ops.render.render()
            dt, dc = time.perf_counter() - t0, cpu_seconds() - c0
            path = os.path.join(out_dir, "%s_s%d_seed%d.exr" % (tag, ns, seed))
            bpy.data.images["Render Result"].save_render(path)
            composite_background(path, lay["background"])
            runs.append({"samples": ns, "seed": seed, "render_seconds": dt, "cpu_seconds": dc,
                         "exr": path})
            print("volume_render: %s %d samples, seed %d: %.3f s" % (tag, ns, seed, dt), flush=True)
        info = {"tag": tag, "load_seconds": load_s, "color": opt.color, "voxel_shift": shift,
                "step_rate": cy.volume_step_rate, "interpolation": opt.interpolation,
                "density_per_world": lay["extinction_per_world"],
                "object_matrix": [list(row) for row in m], "runs": runs}
        with open(os.path.join(out_dir, "%s_seed%d_timing.json" % (tag, seed)), "w") as f:
            json.dump(info, f, indent=2)


main()
