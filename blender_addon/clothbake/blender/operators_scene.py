"""Import and export of a clothbake scene (File > Import / Export)."""
import bpy
from bpy_extras.io_utils import ExportHelper, ImportHelper

from ..core.errors import ClothbakeError
from ..core.scene import load_scene
from .operators_cloth import read_cloth_file
from .scene_export_bpy import export_scene
from .scene_import import import_scene


class CLOTHBAKE_OT_import_scene(bpy.types.Operator, ImportHelper):
    """Import a clothbake scene (camera, lights, cloth meshes and settings)"""
    bl_idname = "clothbake.import_scene"
    bl_label = "Import clothbake scene"
    bl_options = {"REGISTER", "UNDO"}

    filename_ext = ".json"
    filter_glob: bpy.props.StringProperty(default="*.json", options={"HIDDEN"})
    clear: bpy.props.BoolProperty(name="Replace scene objects", default=True,
                                  description="Remove the scene's objects before importing")

    def execute(self, context):
        try:
            model = load_scene(self.filepath)
            for o in model["objects"]:  # every cloth spec readable before anything changes
                if "cloth_path" in o:
                    read_cloth_file(o["cloth_path"])
            settings = context.scene.clothbake
            objects = import_scene(self.filepath, clear=self.clear,
                                   samples=settings.compare_samples)
        except ClothbakeError as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        settings.scene_path = model["path"]
        settings.load_render(model["json"].get("render"))
        settings.bake_status = ""
        settings.compare_status = ""
        if objects:
            for obj in context.scene.objects:
                if obj.name in context.view_layer.objects:
                    obj.select_set(obj in objects)
            context.view_layer.objects.active = objects[0]
        self.report({"INFO"}, f"Imported {len(objects)} cloth object(s) from {model['path']}")
        return {"FINISHED"}


class CLOTHBAKE_OT_export_scene(bpy.types.Operator, ExportHelper):
    """Export the scene as a clothbake scene (scene JSON and one OBJ per cloth object)"""
    bl_idname = "clothbake.export_scene"
    bl_label = "Export clothbake scene"

    filename_ext = ".json"
    filter_glob: bpy.props.StringProperty(default="*.json", options={"HIDDEN"})

    def execute(self, context):
        try:
            path = export_scene(context.scene, self.filepath)
        except ClothbakeError as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        self.report({"INFO"}, f"Exported {path}")
        return {"FINISHED"}


CLASSES = (CLOTHBAKE_OT_import_scene, CLOTHBAKE_OT_export_scene)
