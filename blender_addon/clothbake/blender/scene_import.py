"""Import a clothbake scene JSON into Blender: meshes (face and corner order
kept, so face q is the lookup's quad q), camera, lights (sun, point, spot,
area), background and
Cycles settings that reproduce clothbake's reference renderer.

Coordinates are taken as they are (no axis conversion): clothbake's world
and Blender's are both right-handed, and a scene exported back must give
the same numbers, so the scene's "up" stays whatever axis it was (the paper
scene is y-up).
"""
import math

import bpy
from mathutils import Matrix

from ..core.obj import read_obj
from .running_units import RUNNING_UNITS
from ..core.scene import blender_camera, blender_light, load_scene
from .operators_cloth import load_from_scene_object

CLOTH_KEYS = ("repeats_per_uv", "thickness_world", "extinction_per_mm")


def mesh_from_obj(name, data):
    """A Blender mesh of an OBJ's quads: vertex i = OBJ vertex i, face q =
    OBJ face q with its corners in file order, UVs in map "UVMap". Flat
    shaded: the lookup's frame is the patch's, not a smoothed normal."""
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata([tuple(p) for p in data.positions], [], [list(ps) for ps, _ in data.quads])
    uv = mesh.uv_layers.new(name="UVMap")
    for poly, (_, ts) in zip(mesh.polygons, data.quads):
        for li, t in zip(poly.loop_indices, ts):
            uv.data[li].uv = data.uvs[t]
    mesh.validate(clean_customdata=False)
    mesh.update()
    return mesh


def clear_scene(scene):
    for obj in list(scene.objects):
        bpy.data.objects.remove(obj, do_unlink=True)


def set_render_settings(scene, cam, background, samples=16, seed=1):
    """Cycles set up to be compared pixel for pixel with `clothbake render`:
    box pixel filter one pixel wide (clothbake's stratified box), no
    denoiser, no adaptive sampling, background as a constant world colour,
    enough transparent bounces for folded cloth, nothing else bouncing (the
    lookup is emission)."""
    scene.render.engine = "CYCLES"
    scene.render.resolution_x, scene.render.resolution_y = cam["resolution"]
    scene.render.resolution_percentage = 100
    scene.render.pixel_aspect_x = scene.render.pixel_aspect_y = 1.0
    scene.render.film_transparent = False
    scene.render.filter_size = 1.0  # Cycles reads cycles.filter_width; EEVEE this
    scene.render.use_persistent_data = False
    c = scene.cycles
    c.device = "CPU"
    c.samples = samples
    c.use_adaptive_sampling = False
    c.use_denoising = False
    c.seed = seed
    c.pixel_filter_type = "BOX"
    c.filter_width = 1.0
    c.max_bounces = 0
    c.diffuse_bounces = c.glossy_bounces = c.transmission_bounces = c.volume_bounces = 0
    c.transparent_max_bounces = 64
    c.caustics_reflective = c.caustics_refractive = False
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.image_settings.color_mode = "RGBA"
    scene.render.image_settings.color_depth = "32"
    world = scene.world or bpy.data.worlds.new("clothbake background")
    scene.world = world
    world.use_nodes = True
    bg = world.node_tree.nodes.get("Background") or world.node_tree.nodes.new("ShaderNodeBackground")
    bg.inputs["Color"].default_value = (*background, 1.0)
    bg.inputs["Strength"].default_value = 1.0


def import_scene(path, clear=True, samples=16):
    """Builds the scene in the current Blender scene; returns the cloth
    objects in scene order. Raises ClothbakeError for a bad scene or mesh."""
    model = load_scene(path)
    meshes = [read_obj(o["mesh_path"]) for o in model["objects"]]  # all errors before any change
    scene = bpy.context.scene
    if clear:
        clear_scene(scene)
    scene["clothbake_scene"] = model["path"]

    cam_settings = blender_camera(model["camera"])
    cam_data = bpy.data.cameras.new("clothbake camera")
    cam_data.type = "PERSP"
    cam_data.sensor_fit = cam_settings["sensor_fit"]
    cam_data.sensor_width = cam_settings["sensor_width"]
    cam_data.sensor_height = cam_settings["sensor_height"]
    cam_data.lens = cam_settings["lens"]
    cam_data.clip_start = 1e-3
    cam_data.clip_end = 1e4
    cam_obj = bpy.data.objects.new("clothbake camera", cam_data)
    cam_obj.matrix_world = Matrix(cam_settings["matrix"])
    scene.collection.objects.link(cam_obj)
    scene.camera = cam_obj

    for i, light in enumerate(model["lights"]):
        settings = blender_light(light, RUNNING_UNITS)
        if "mask" in settings:
            print(f"clothbake: warning: {path}: lights[{i}]: {settings['mask']}")
        data = bpy.data.lights.new(f"clothbake light {i}", settings["type"])
        data.color = settings["color"]
        data.energy = settings["energy"]
        if settings["type"] == "SUN":
            data.angle = 0.0
        elif settings["type"] == "AREA":
            data.shape = settings["shape"]
            data.size = settings["size"]
            data.size_y = settings["size_y"]
            data.spread = math.pi       # clothbake's area lights: the whole half-space
        else:
            data.shadow_soft_size = 0.0
            if settings["type"] == "SPOT":
                data.spot_size = settings["spot_size"]
                data.spot_blend = settings["spot_blend"]
        light_obj = bpy.data.objects.new(f"clothbake light {i}", data)
        light_obj.matrix_world = Matrix(settings["matrix"])
        scene.collection.objects.link(light_obj)

    objects = []
    for i, (o, data) in enumerate(zip(model["objects"], meshes)):
        mesh = mesh_from_obj(o["name"], data)
        obj = bpy.data.objects.new(o["name"], mesh)
        scene.collection.objects.link(obj)
        obj["clothbake_object_index"] = i
        obj["clothbake_name"] = o["name"]
        settings = obj.clothbake if hasattr(obj, "clothbake") else None
        if settings is not None:
            load_from_scene_object(settings, o)
        else:
            for key in CLOTH_KEYS:
                obj[f"clothbake_{key}"] = o[key]
        objects.append(obj)

    render = model["render"]
    set_render_settings(scene, model["camera"], model["background"], samples=samples,
                        seed=int(render.get("seed", 1)) & 0x7FFFFFFF)
    return objects
