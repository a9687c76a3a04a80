"""Measures Blender 3.4 Cycles' spot and area lights on a white Lambertian
plane (issue 22, item 3): what a spot's cone and blend do to the light, and
what an area light of P watts and a given size radiates. No assumption taken
from memory: each case is compared with candidate formulas.

  blender -b --factory-startup --python-exit-code 1 -P spot_area_units.py -- OUT.json [--threads N]

A white Diffuse BSDF plane (colour 1) in z = 0, seen straight down by an
orthographic camera at z = 0.05 (below every light: cameras cast no shadow,
and an area light's back is never in view), 64 x 64 pixels over
[-W/2, W/2]^2, box filter 1 px, no denoiser. Radiance L = E / pi for
irradiance E. Each pixel's prediction is the mean of 4 x 4 sub-pixel
points, the formulas evaluated in numpy:

  spot (at height h, pointing down, Size s, Blend b, power P):
    E = P / (4 pi) cos_inc / d^2 * att,  c0 = cos(s / 2), smooth = (1 - c0) b,
    a = cos(angle to the axis); att = 0 if a <= c0, else
    "with cos":    att = a * smoothstep(t / smooth)  (t = a - c0 < smooth; else a)
    "without cos": att = smoothstep(t / smooth)      (else 1)
  area (one-sided, emitting along its -Z): E = L_e * integral over the
    shape of cos_light cos_plane / d^2 dA; candidates L_e = P / (pi A) and
    P / (4 A). Integrated on a 256 x 256 grid over the shape.

Writes each case's fitted scale (measured / predicted, mean over lit pixels
weighted by the prediction) and relative RMSE against each candidate.
"""
import json
import math
import os
import sys

import bpy
import numpy as np

argv = sys.argv[sys.argv.index("--") + 1:]
OUT = argv[0]
THREADS = int(argv[argv.index("--threads") + 1]) if "--threads" in argv else 2
RES = 64
SPP = 256


def reset(width):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    sc = bpy.context.scene
    sc.render.engine = "CYCLES"
    sc.cycles.device = "CPU"
    sc.render.threads_mode = "FIXED"
    sc.render.threads = THREADS
    sc.cycles.samples = SPP
    sc.cycles.use_adaptive_sampling = False
    sc.cycles.use_denoising = False
    sc.cycles.max_bounces = 1
    sc.cycles.pixel_filter_type = "BOX"
    sc.cycles.filter_width = 1.0
    sc.render.resolution_x = sc.render.resolution_y = RES
    sc.render.resolution_percentage = 100
    world = bpy.data.worlds.new("black")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Color"].default_value = (0, 0, 0, 1)
    sc.world = world
    bpy.ops.mesh.primitive_plane_add(size=4.0 * width)
    plane = bpy.context.active_object
    mat = bpy.data.materials.new("white")
    mat.use_nodes = True
    nt = mat.node_tree
    nt.nodes.clear()
    d = nt.nodes.new("ShaderNodeBsdfDiffuse")
    d.inputs["Color"].default_value = (1, 1, 1, 1)
    o = nt.nodes.new("ShaderNodeOutputMaterial")
    nt.links.new(d.outputs["BSDF"], o.inputs["Surface"])
    plane.data.materials.append(mat)
    cam = bpy.data.objects.new("cam", bpy.data.cameras.new("cam"))
    cam.data.type = "ORTHO"
    cam.data.ortho_scale = width
    cam.data.clip_start = 0.01
    cam.location = (0, 0, 0.05)
    sc.collection.objects.link(cam)
    sc.camera = cam
    return sc


def render(sc, tag):
    bpy.ops.render.render()
    path = os.path.join(bpy.app.tempdir, f"spot_area_{tag}.exr")
    sc.render.image_settings.file_format = "OPEN_EXR"
    sc.render.image_settings.color_depth = "32"
    bpy.data.images["Render Result"].save_render(path)
    img = bpy.data.images.load(path)
    px = np.array(img.pixels[:], dtype=np.float64).reshape(RES, RES, 4)  # rows bottom-up
    bpy.data.images.remove(img)
    return px[..., :3].mean(axis=2)


def points(width, sub=4):
    """World (x, y) of sub x sub points per pixel: arrays (RES, RES, sub*sub)."""
    k = (np.arange(RES * sub) + 0.5) / (RES * sub) * width - width / 2
    x, y = np.meshgrid(k, k)   # row index = y (bottom-up, as Blender's pixels)
    x = x.reshape(RES, sub, RES, sub).transpose(0, 2, 1, 3).reshape(RES, RES, -1)
    y = y.reshape(RES, sub, RES, sub).transpose(0, 2, 1, 3).reshape(RES, RES, -1)
    return x, y


def smoothstep(t):
    t = np.clip(t, 0.0, 1.0)
    return t * t * (3.0 - 2.0 * t)


def spot_prediction(width, h, size, blend, power, with_cos):
    x, y = points(width)
    d2 = x * x + y * y + h * h
    d = np.sqrt(d2)
    a = h / d                       # cos(angle to the axis) = cos(incidence) here
    c0 = math.cos(size / 2)
    smooth = (1 - c0) * blend
    t = a - c0
    fade = np.where(t < smooth, smoothstep(t / smooth) if smooth > 0 else 1.0, 1.0)
    att = np.where(a <= c0, 0.0, fade * (a if with_cos else 1.0))
    e = power / (4 * math.pi) * a / d2 * att
    return (e / math.pi).mean(axis=2)


def area_prediction(width, centre, rot, shape, sx, sy, power, n=256):
    """Radiance of the white plane for L_e = power / (pi A) (the caller
    rescales for other candidates). rot: 3x3 world matrix columns (X, Y, Z)
    of the light (emitting along -Z)."""
    u = (np.arange(n) + 0.5) / n - 0.5
    gu, gv = np.meshgrid(u * sx, u * sy)
    gu, gv = gu.ravel(), gv.ravel()
    if shape in ("DISK", "ELLIPSE"):
        keep = (gu / (sx / 2)) ** 2 + (gv / (sy / 2)) ** 2 <= 1.0
        gu, gv = gu[keep], gv[keep]
        area = math.pi * sx * sy / 4
    else:
        area = sx * sy
    dA = area / len(gu)
    X, Y, Z = rot[:, 0], rot[:, 1], rot[:, 2]
    ys = centre[None, :] + gu[:, None] * X[None, :] + gv[:, None] * Y[None, :]   # (m, 3)
    normal = -Z
    le = power / (math.pi * area)
    x, y = points(width, sub=2)
    P = np.stack([x, y, np.zeros_like(x)], axis=-1).reshape(-1, 3)          # (p, 3)
    out = np.zeros(len(P))
    for i0 in range(0, len(P), 256):
        p = P[i0:i0 + 256]
        v = p[:, None, :] - ys[None, :, :]                                     # light -> point
        d2 = (v * v).sum(-1)
        dn = np.sqrt(d2)
        cos_l = (v @ normal) / dn
        cos_p = (-v[..., 2]) / dn       # plane normal +z; the light above
        e = le * np.clip(cos_l, 0, None) * np.clip(cos_p, 0, None) / d2 * dA
        out[i0:i0 + 256] = e.sum(1)
    return (out / math.pi).reshape(RES, RES, -1).mean(axis=2), area


def fit(measured, predicted):
    lit = predicted > 0.02 * predicted.max()
    scale = float((measured[lit] * predicted[lit]).sum() / (predicted[lit] ** 2).sum())
    rel = float(np.sqrt(((measured - predicted) ** 2).mean()) / measured.mean())
    return {"fitted_scale": scale, "rel_rmse": rel,
            "dark_outside": float(measured[predicted == 0].max()) if (predicted == 0).any()
            else None}


results = {}


def spot_case(tag, h=1.0, size_deg=90.0, blend=0.5, power=100.0, scale=(1, 1, 1), radius=0.0,
              width=3.0):
    sc = reset(width)
    data = bpy.data.lights.new("spot", "SPOT")
    data.energy = power
    data.spot_size = math.radians(size_deg)
    data.spot_blend = blend
    data.shadow_soft_size = radius
    obj = bpy.data.objects.new("spot", data)
    obj.location = (0, 0, h)
    obj.scale = scale
    sc.collection.objects.link(obj)
    m = render(sc, tag)
    r = {"setup": {"height": h, "spot_size_deg": size_deg, "blend": blend, "power_w": power,
                   "scale": list(scale), "radius": radius}}
    for label, with_cos in (("with_cos", True), ("without_cos", False)):
        r[label] = fit(m, spot_prediction(width, h, math.radians(size_deg), blend, power,
                                          with_cos))
    # on the axis: the centre 2 x 2 pixels against P / (4 pi) / h^2 / pi
    c = RES // 2
    r["axis_radiance"] = float(m[c - 1:c + 1, c - 1:c + 1].mean())
    r["axis_expected_P_over_4pi_h2_pi"] = power / (4 * math.pi) / h ** 2 / math.pi
    # radial profile: measured / each prediction in rings
    results[tag] = r
    print(tag, json.dumps(r), flush=True)
    return m


def area_case(tag, shape="RECTANGLE", size=1.0, size_y=0.5, h=0.5, power=100.0,
              scale=(1, 1, 1), tilt_deg=0.0, spread_deg=180.0, width=3.0):
    sc = reset(width)
    data = bpy.data.lights.new("area", "AREA")
    data.energy = power
    data.shape = shape
    data.size = size
    data.size_y = size_y
    data.spread = math.radians(spread_deg)
    obj = bpy.data.objects.new("area", data)
    obj.location = (0, 0, h)
    obj.rotation_euler = (math.radians(tilt_deg), 0, 0)
    obj.scale = scale
    sc.collection.objects.link(obj)
    bpy.context.view_layer.update()
    m = render(sc, tag)
    mw = np.array(obj.matrix_world)
    rot = mw[:3, :3] / np.linalg.norm(mw[:3, :3], axis=0)
    sx = size * np.linalg.norm(mw[:3, 0])
    sy = (size_y if shape in ("RECTANGLE", "ELLIPSE") else size) * np.linalg.norm(mw[:3, 1])
    pred, area = area_prediction(width, mw[:3, 3], rot, shape, sx, sy, power)
    r = {"setup": {"shape": shape, "size": size, "size_y": size_y, "height": h,
                   "power_w": power, "scale": list(scale), "tilt_deg": tilt_deg,
                   "spread_deg": spread_deg, "world_size": [sx, sy], "area": area}}
    r["Le_P_over_pi_A"] = fit(m, pred)
    r["Le_P_over_4A"] = fit(m, pred * math.pi / 4)
    c = RES // 2
    r["centre_radiance"] = float(m[c - 1:c + 1, c - 1:c + 1].mean())
    if shape == "DISK" and tilt_deg == 0:
        rr = sx / 2
        r["centre_closed_form_P_over_piA"] = power / (math.pi * area) * rr * rr / (rr * rr + h * h)
    if shape == "RECTANGLE" and tilt_deg == 0:
        def corner(a, b):  # E / L of a point under the corner of an a x b rectangle
            A, B = a / h, b / h
            return 0.5 * (A / math.hypot(1, A) * math.atan(B / math.hypot(1, A))
                          + B / math.hypot(1, B) * math.atan(A / math.hypot(1, B)))
        r["centre_closed_form_P_over_piA"] = power / (math.pi * area) * 4 * corner(sx / 2, sy / 2) / math.pi
    results[tag] = r
    print(tag, json.dumps(r), flush=True)
    return m


spot_case("spot_90_blend_0.5")
spot_case("spot_60_blend_0", size_deg=60.0, blend=0.0)
spot_case("spot_120_blend_1", size_deg=120.0, blend=1.0, h=0.8)
spot_case("spot_90_scale_2_1_1", scale=(2.0, 1.0, 1.0))
spot_case("spot_90_scale_2_2_2", scale=(2.0, 2.0, 2.0))
spot_case("spot_90_radius_0.25", radius=0.25)
area_case("rect_1x0.5")
area_case("rect_0.5x0.25_scaled_2", size=0.5, size_y=0.25, scale=(2.0, 2.0, 1.0))
area_case("square_0.8", shape="SQUARE", size=0.8, size_y=3.0)
area_case("disk_1", shape="DISK", size=1.0, size_y=3.0)
area_case("ellipse_1x0.4", shape="ELLIPSE", size=1.0, size_y=0.4)
area_case("rect_tilted_40", tilt_deg=40.0, h=0.4)
area_case("rect_spread_90", spread_deg=90.0)
with open(OUT, "w") as f:
    json.dump(results, f, indent=2)
