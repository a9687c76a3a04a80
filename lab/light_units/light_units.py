"""Measures how Blender 3.4 Cycles' light settings map to irradiance, with a
tiny diffuse-plane render (no assumptions taken from memory).

  blender -b --factory-startup --python-exit-code 1 -P light_units.py -- OUT.json

A white Lambertian plane (Diffuse BSDF, colour 1) in z = 0, seen straight
down by an orthographic camera (8 x 8 pixels, box filter). Its radiance is
L = E / pi for irradiance E, so E = pi L:
  1. a Sun of strength 1 (angle 0) shining straight down: E_sun per unit strength;
  2. a Point light of power 1 W (radius 0) at height 1 above the plane's
     centre: E at 1 unit per watt, i.e. the light's radiant intensity per watt
     (W/sr per W); 1/(4 pi) would be a physical isotropic 1-W emitter.
Writes {"sun_irradiance_per_strength": .., "point_irradiance_at_1_per_watt": ..,
"point_radiant_intensity_per_watt_times_4pi2": ..} and prints them.
"""
import json
import math
import sys

import bpy
import numpy as np

out_path = sys.argv[sys.argv.index("--") + 1]
RES = 8


def reset():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    sc = bpy.context.scene
    sc.render.engine = "CYCLES"
    sc.cycles.device = "CPU"
    sc.cycles.samples = 16
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
    bpy.ops.mesh.primitive_plane_add(size=0.02)  # 0.02 x 0.02: the point light's distance is 1 everywhere to 1e-4
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
    cam.data.ortho_scale = 0.01
    cam.location = (0, 0, 0.5)  # between the plane and the point light: it casts no shadow
    sc.collection.objects.link(cam)
    sc.camera = cam
    return sc


def mean_radiance(sc):
    bpy.ops.render.render()
    img = bpy.data.images["Render Result"]
    path = bpy.app.tempdir + "light_units.exr"
    sc.render.image_settings.file_format = "OPEN_EXR"
    sc.render.image_settings.color_depth = "32"
    img.save_render(path)
    loaded = bpy.data.images.load(path)
    px = np.array(loaded.pixels[:], dtype=np.float64).reshape(RES, RES, 4)
    return float(px[..., :3].mean()), float(px[..., :3].std())


sc = reset()
sun = bpy.data.objects.new("sun", bpy.data.lights.new("sun", "SUN"))
sun.data.energy = 1.0
sun.data.angle = 0.0
sc.collection.objects.link(sun)  # default orientation shines down -z
l_sun, s_sun = mean_radiance(sc)

sc = reset()
pt = bpy.data.objects.new("point", bpy.data.lights.new("point", "POINT"))
pt.data.energy = 1.0
pt.data.shadow_soft_size = 0.0
pt.location = (0, 0, 1.0)
sc.collection.objects.link(pt)
l_pt, s_pt = mean_radiance(sc)

res = {
    "sun_radiance_on_white_plane": l_sun,
    "sun_irradiance_per_strength": math.pi * l_sun,
    "point_radiance_on_white_plane": l_pt,
    "point_irradiance_at_1_per_watt": math.pi * l_pt,
    "point_radiant_intensity_per_watt_times_4pi2": math.pi * l_pt * 4 * math.pi ** 2,
    "pixel_std": [s_sun, s_pt],
}
print("light_units: " + json.dumps(res))
with open(out_path, "w") as f:
    json.dump(res, f, indent=2)
