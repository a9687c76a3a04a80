"""Load cloth file: a cloth spec (JSON) or a WIF draft onto a cloth object,
its fields filled from it. A WIF is read by the program (`clothbake
draft`), so loading is an operator's work, never a property's: the scene
import (operators_scene.py) loads its objects' cloths through here too."""
import json
import os
import tempfile

import bpy
from bpy_extras.io_utils import ImportHelper

from ..core import cloth_fields, wif_cloth
from ..core.errors import ClothbakeError
from . import prefs
from .props_cloth import loading


def read_cloth_file(path):
    """The spec dict of a cloth spec file (a .wif stands for {"weave": {"wif":
    PATH}}); raises ClothbakeError."""
    if wif_cloth.is_wif_path(path):
        return wif_cloth.wif_spec_of_file(path)
    try:
        with open(path, encoding="utf-8") as f:
            spec = json.load(f)
    except OSError as e:
        raise ClothbakeError(f"cannot read the cloth spec: {e.strerror}", path) from None
    except UnicodeDecodeError as e:
        raise ClothbakeError(f"not UTF-8 text (byte {e.start}); a cloth spec is a JSON file",
                             path) from None
    except json.JSONDecodeError as e:
        raise ClothbakeError(f"invalid JSON: {e.msg}", path, f"line {e.lineno}") from None
    cloth_fields.fields_from_spec(spec, path)  # checks what the fields need
    return spec


def draft_cache_root():
    """Where `clothbake draft` writes: Blender's temp folder of this session."""
    return bpy.app.tempdir or tempfile.gettempdir()


def load_cloth_file(settings, path):
    """Fills `settings` (an obj.clothbake) from the cloth file at `path` and
    keeps the path; a WIF draft it is or names is read by the program.
    Returns the program's message when it refused the draft, else "".
    Raises ClothbakeError for a file that cannot be read."""
    full = os.path.abspath(bpy.path.abspath(path))
    spec = read_cloth_file(full)
    settings.set_fields_from_spec(spec, path)
    with loading():
        settings.cloth_path = path
    wif = wif_cloth.absolute_wif(spec, os.path.dirname(full))
    if wif:
        return load_wif(settings, spec, wif, full)
    settings.clear_wif()
    return ""


def load_wif(settings, spec, wif_path, input_path=None):
    """Runs `clothbake draft` on `input_path` (the .wif or the spec file;
    None: `spec` is inline, written to the cache with `wif_path`) and fills
    the palette and the fields from its reading; not an edit. Returns the
    program's message when it refused (also kept in wif_status, which the
    panel shows), else ""."""
    settings.clear_wif()
    with loading():
        settings.wif_path = wif_path
    try:
        program = prefs.program_path(bpy.context)
        if program is None:
            raise ClothbakeError("the clothbake program was not found; set its path in the "
                                 "add-on's preferences (it reads the WIF file)")
        root = draft_cache_root()
        if input_path is None:
            input_path = wif_cloth.write_spec_for_draft(spec, wif_path, root,
                                                        settings.id_data.name)
        draft, _ = wif_cloth.run_draft(program, input_path, root)
    except (ClothbakeError, OSError) as e:
        with loading():
            settings.wif_status = str(e)
        return settings.wif_status
    settings.set_wif_draft(draft, spec)
    return ""


def load_from_scene_object(settings, o):
    """Takes an object of a loaded scene (clothbake.core.scene.load_scene)
    into `settings`: its cloth (file or inline) and its settings. Raises
    ClothbakeError for a cloth spec file that cannot be read."""
    if "cloth_path" in o:
        load_cloth_file(settings, o["cloth_path"])
    else:
        settings.set_fields_from_spec(o["cloth"])
        with loading():
            settings.cloth_path = ""
        if "cloth_wif_path" in o:
            load_wif(settings, o["cloth"], o["cloth_wif_path"])
        else:
            settings.clear_wif()
    settings.is_cloth = True
    settings.repeats_per_uv = o["repeats_per_uv"]
    settings.thickness_world = o["thickness_world"]
    settings.extinction_per_mm = o["extinction_per_mm"]
    settings.isotropic_albedo = o.get("isotropic_albedo", (0.8, 0.8, 0.8))
    settings.volume_path = o.get("volume_path", "")


class CLOTHBAKE_OT_load_cloth(bpy.types.Operator, ImportHelper):
    """Load a cloth spec (JSON) or a WIF weaving draft onto the cloth object: its fields show the file's values, and export refers to the file until one is edited"""
    bl_idname = "clothbake.load_cloth"
    bl_label = "Load cloth file"
    bl_options = {"REGISTER", "UNDO"}

    filter_glob: bpy.props.StringProperty(default="*.json;*.wif", options={"HIDDEN"})
    object_name: bpy.props.StringProperty(
        name="Object", options={"HIDDEN"},
        description="The cloth object to load onto (empty: the active object)")

    def execute(self, context):
        obj = bpy.data.objects.get(self.object_name) if self.object_name else context.object
        if obj is None or obj.type != "MESH":
            self.report({"ERROR"}, "make the cloth object active (a mesh) to load its cloth file")
            return {"CANCELLED"}
        settings = obj.clothbake
        try:
            refused = load_cloth_file(settings, self.filepath)
        except ClothbakeError as e:
            # Kept, as a path typed in would be: export refers to it, and
            # the program names the problem when it reads it.
            with loading():
                settings.cloth_path = self.filepath
            self.report({"WARNING"}, str(e))
            return {"FINISHED"}
        if refused:
            self.report({"WARNING"}, refused)
        else:
            self.report({"INFO"}, f"Loaded {self.filepath} onto '{obj.name}'")
        return {"FINISHED"}


CLASSES = (CLOTHBAKE_OT_load_cloth,)
