"""The drivers that bring the scene into the cloth material's node group
(material_nodes.py): each light's direction (or position), irradiance and
render visibility, and the camera's pixel angle and Cycles' samples.

They read each light object's world transform, colour, power and
render visibility (BLENDER_NOTES.md: simple expressions, no script
auto-run needed). A Texture Coordinate node set to an empty would need one
empty per light kept aligned with it; drivers read the light itself.
"""
import math


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


def drive_light(node, l, light_obj):
    vector = node.inputs[f"Light {l} vector"]
    if light_obj.data.type == "SUN":
        rot = [(c, "TRANSFORMS", light_obj, None, f"ROT_{c.upper()}") for c in "wxyz"]
        for axis, expr in enumerate(("2*(x*z+w*y)", "2*(y*z-w*x)", "1-2*(x*x+y*y)")):
            _driver(vector, axis, expr, rot)
        per = 1.0
    else:
        for axis, c in enumerate("XYZ"):
            _driver(vector, axis, "p", [("p", "TRANSFORMS", light_obj, None, f"LOC_{c}")])
        per = 1.0 / (4.0 * math.pi)  # Blender's point watts -> irradiance at 1 unit (scene.py)
    node.inputs[f"Light {l} point"].default_value = 0.0 if light_obj.data.type == "SUN" else 1.0
    irr = node.inputs[f"Light {l} irradiance"]
    for axis in range(3):
        _driver(irr, axis, f"c*e*{per!r}*(1-h)",
                [("c", "SINGLE_PROP", light_obj, "OBJECT", f"data.color[{axis}]"),
                 ("e", "SINGLE_PROP", light_obj, "OBJECT", "data.energy"),
                 ("h", "SINGLE_PROP", light_obj, "OBJECT", "hide_render")])


def drive_camera(node, scene):
    _driver(node.inputs["Pixel angle"], None, "w/f/(x*p/100)",
            [("w", "SINGLE_PROP", scene, "SCENE", "camera.data.sensor_width"),
             ("f", "SINGLE_PROP", scene, "SCENE", "camera.data.lens"),
             ("x", "SINGLE_PROP", scene, "SCENE", "render.resolution_x"),
             ("p", "SINGLE_PROP", scene, "SCENE", "render.resolution_percentage")])
    _driver(node.inputs["Samples"], None, "s",
            [("s", "SINGLE_PROP", scene, "SCENE", "cycles.samples")])
