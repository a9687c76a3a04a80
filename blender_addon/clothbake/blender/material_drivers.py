"""The drivers that bring the scene into the cloth material's node group
(the material_nodes package): each light's direction (or position), irradiance and
render visibility, a spot's axis and cone, an area light's axis, sides and
shape, and the camera's pixel angle and Cycles' samples.

They read each light object's world transform, colour, power (and
Exposure where the light has one: 5.x) and render visibility (BLENDER_NOTES.md: simple expressions, no script
auto-run needed). A Texture Coordinate node set to an empty would need one
empty per light kept aligned with it; drivers read the light itself.
"""
from .running_units import RUNNING_UNITS as UNITS


def _driver(socket, index, expression, variables):
    """variables: (name, kind, target id, id_type, data_path or transform)."""
    fc = socket.driver_add("default_value", index) if index is not None else \
        socket.driver_add("default_value")
    drv = fc.driver
    drv.type = "SCRIPTED"
    for v in list(drv.variables):
        drv.variables.remove(v)
    for name, kind, target_id, id_type, what in variables:
        var = drv.variables.new()
        var.name = name
        if kind == "TRANSFORMS":
            var.type = "TRANSFORMS"
            t = var.targets[0]
            t.id = target_id
            t.transform_type = what
            t.transform_space = "WORLD_SPACE"
            t.rotation_mode = "QUATERNION"
        else:
            var.type = "SINGLE_PROP"
            t = var.targets[0]
            t.id_type = id_type
            t.id = target_id
            t.data_path = what
    drv.expression = expression
    return fc


# The light object's world rotation as a quaternion (w, x, y, z): the
# columns of its rotation matrix, each as three simple expressions.
_X_AXIS = ("1-2*(y*y+z*z)", "2*(x*y+w*z)", "2*(x*z-w*y)")
_Y_AXIS = ("2*(x*y-w*z)", "1-2*(x*x+z*z)", "2*(y*z+w*x)")
_Z_AXIS = ("2*(x*z+w*y)", "2*(y*z-w*x)", "1-2*(x*x+y*y)")
# Blender's area light shapes as a driver reads data.shape (the enum's
# values: SQUARE 0, RECTANGLE 1, DISK 4, ELLIPSE 5; checked in Blender 3.4).
_USES_SIZE_Y = "(s == 1 or s == 5)"
_IS_ELLIPSE = "1.0 if s >= 4 else 0.0"

def _rotation(light_obj):
    return [(c, "TRANSFORMS", light_obj, None, f"ROT_{c.upper()}") for c in "wxyz"]


def drive_light(node, l, light_obj):
    """Light l's group inputs driven by the light object: a sun's direction
    toward it, otherwise its world position (an area light's centre); its
    irradiance (colour x power x the watts' factor x (1 - hide_render)); a
    spot's axis and cone (cos(size / 2), (1 - cos(size / 2)) x blend), an
    area light's axis, its sides (size, or size_y for a rectangle or an
    ellipse, times the object's world scale, along its X and Y) and its
    ellipse flag: every one live, the shape included."""
    kind = light_obj.data.type
    vector = node.inputs[f"Light {l} vector"]
    if kind == "SUN":
        rot = _rotation(light_obj)
        for axis, expr in enumerate(("2*(x*z+w*y)", "2*(y*z-w*x)", "1-2*(x*x+y*y)")):
            _driver(vector, axis, expr, rot)
        per = 1.0
    else:
        for axis, c in enumerate("XYZ"):
            _driver(vector, axis, "p", [("p", "TRANSFORMS", light_obj, None, f"LOC_{c}")])
        per = 1.0 / UNITS.watts_per_intensity(kind if kind in ("SPOT", "AREA") else "POINT")
    node.inputs[f"Light {l} point"].default_value = 0.0 if light_obj.data.type == "SUN" else 1.0
    irr = node.inputs[f"Light {l} irradiance"]
    exposure = hasattr(light_obj.data, "exposure")      # 5.x (not 4.3): watts x 2^x
    for axis in range(3):
        _driver(irr, axis, f"c*e*{float(per)!r}*(1-h)" + ("*pow(2,x)" if exposure else ""),
                [("c", "SINGLE_PROP", light_obj, "OBJECT", f"data.color[{axis}]"),
                 ("e", "SINGLE_PROP", light_obj, "OBJECT", "data.energy"),
                 ("h", "SINGLE_PROP", light_obj, "OBJECT", "hide_render")] +
                ([("x", "SINGLE_PROP", light_obj, "OBJECT", "data.exposure")] if exposure else []))
    if kind in ("SPOT", "AREA") and f"Light {l} axis" in node.inputs:
        rot = _rotation(light_obj)
        for axis, expr in enumerate(_Z_AXIS):    # the way it shines: its -Z
            _driver(node.inputs[f"Light {l} axis"], axis, f"-({expr})", rot)
    if kind == "SPOT" and f"Light {l} smooth" in node.inputs:
        size = ("s", "SINGLE_PROP", light_obj, "OBJECT", "data.spot_size")
        _driver(node.inputs[f"Light {l} cos half angle"], None, "cos(s/2)", [size])
        _driver(node.inputs[f"Light {l} smooth"], None, "(1-cos(s/2))*b",
                [size, ("b", "SINGLE_PROP", light_obj, "OBJECT", "data.spot_blend")])
    if kind == "AREA" and f"Light {l} side u" in node.inputs:
        rot = _rotation(light_obj)
        a = ("a", "SINGLE_PROP", light_obj, "OBJECT", "data.size")
        b = ("b", "SINGLE_PROP", light_obj, "OBJECT", "data.size_y")
        shape = ("s", "SINGLE_PROP", light_obj, "OBJECT", "data.shape")
        for axis, expr in enumerate(_X_AXIS):
            _driver(node.inputs[f"Light {l} side u"], axis, f"({expr})*a*k",
                    rot + [a, ("k", "TRANSFORMS", light_obj, None, "SCALE_X")])
        for axis, expr in enumerate(_Y_AXIS):
            _driver(node.inputs[f"Light {l} side v"], axis,
                    f"({expr})*k*(b if {_USES_SIZE_Y} else a)",
                    rot + [a, b, shape, ("k", "TRANSFORMS", light_obj, None, "SCALE_Y")])
        _driver(node.inputs[f"Light {l} ellipse"], None, _IS_ELLIPSE, [shape])


def drive_camera(node, scene):
    _driver(node.inputs["Pixel angle"], None, "w/f/(x*p/100)",
            [("w", "SINGLE_PROP", scene, "SCENE", "camera.data.sensor_width"),
             ("f", "SINGLE_PROP", scene, "SCENE", "camera.data.lens"),
             ("x", "SINGLE_PROP", scene, "SCENE", "render.resolution_x"),
             ("p", "SINGLE_PROP", scene, "SCENE", "render.resolution_percentage")])
    _driver(node.inputs["Samples"], None, "s",
            [("s", "SINGLE_PROP", scene, "SCENE", "cycles.samples")])


def _environment_mean(node):
    """The mean radiance of an Environment Texture's image over the sphere
    (equirectangular rows weighted by cos(latitude)), RGB, or None when it
    holds no pixels."""
    import numpy as np
    image = getattr(node, "image", None)
    if image is None or image.size[0] == 0 or image.size[1] == 0:
        return None
    w, h = image.size
    px = np.empty(w * h * image.channels, np.float32)
    image.pixels.foreach_get(px)
    px = px.reshape(h, w, image.channels)[..., :3].astype(np.float64)
    lat = (np.arange(h) + 0.5) / h * np.pi - 0.5 * np.pi      # bottom row first
    weight = np.cos(lat)[:, None, None]
    return tuple((px * weight).sum((0, 1)) / (weight.sum() * w))


def drive_world(node, scene):
    """The group's World radiance (cycles-lit route, material_nodes.lights.world_terms):
    the scene world's Background colour x strength, a live driver through
    scene.world (so another world assigned later is followed too). Where
    the colour is linked: an Environment Texture's image is averaged over
    the sphere now (its mean x the live strength; painting the image or
    swapping it needs Apply again), anything else (a sky, a gradient)
    counts as its Background node's unlinked colour. Returns the notes."""
    socket = node.inputs.get("World radiance")
    if socket is None:
        return []
    world = scene.world
    if world is None:
        socket.default_value = (0.0, 0.0, 0.0)
        return []
    if not world.use_nodes or world.node_tree is None:
        for axis in range(3):
            _driver(socket, axis, "c", [("c", "SINGLE_PROP", scene, "SCENE",
                                         f"world.color[{axis}]")])
        return []
    background = next((n for n in world.node_tree.nodes if n.type == "BACKGROUND"
                       and any(l.to_node.type == "OUTPUT_WORLD" for l in n.outputs[0].links)),
                      None)
    if background is None:
        socket.default_value = (0.0, 0.0, 0.0)
        return [f"the world '{world.name}' has no Background node into its output: the "
                "cloth material takes no light from it"]
    path = f'world.node_tree.nodes["{background.name}"].inputs'
    strength = ("s", "SINGLE_PROP", scene, "SCENE", f"{path}[1].default_value")
    colour_in = background.inputs[0]
    notes = []
    mean = None
    if colour_in.is_linked:
        source = colour_in.links[0].from_node
        if source.type == "TEX_ENVIRONMENT":
            mean = _environment_mean(source)
        if mean is None:
            notes.append(f"world '{world.name}': its colour comes from a "
                         f"'{source.bl_label}' node; the cloth material takes the Background "
                         "node's own colour as the world's light instead")
        else:
            notes.append(f"world '{world.name}': its image is taken as its mean colour "
                         f"({mean[0]:.3g}, {mean[1]:.3g}, {mean[2]:.3g}) x strength: apply the "
                         "material again after changing the image")
    for axis in range(3):
        if mean is not None:
            _driver(socket, axis, f"{float(mean[axis])!r}*s", [strength])
        else:
            _driver(socket, axis, "c*s", [("c", "SINGLE_PROP", scene, "SCENE",
                                           f"{path}[0].default_value[{axis}]"), strength])
    return notes
