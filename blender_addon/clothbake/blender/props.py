"""The settings an artist edits: per object (`obj.clothbake`: the cloth and
how it sits on the mesh) and per scene (`scene.clothbake`: files, bake,
comparison and the reference renderer's settings).

Cloth spec files. An object imported from a scene whose cloth is a file
keeps that path (`cloth_path`) and shows the file's values in the fields.
Export refers to the file as long as no field is edited; once one is
(`cloth_edited`), export writes the cloth inline: the file's spec with the
fields written over it, so what the panel does not show (density, shading,
an explicit draft) is kept. Picking another file reloads the fields from it.

WIF drafts (issue 23). The cloth file may be a .wif, or a JSON spec whose
weave.wif names one. The program reads it (`clothbake draft`, into a folder
of Blender's session temp) and the object keeps its reading (`wif_draft`: the
drawdown and each thread's index into the palette), the palette as editable
colours (`wif_palette`) and the fields as loaded (`wif_loaded`). Editing a
palette colour recolours every thread that uses it; once anything is edited,
export writes the cloth inline: {"weave": {"wif": ABSOLUTE_PATH}, "warp":
{"colors": per end}, "weft": {"colors": per pick}} and only the fields that
changed (core/wif_cloth.py), so the file's per-thread spacings and widths stay
unless their field is edited.
"""
import json
import os
import tempfile

import bpy

from ..core import cloth_fields, wif_cloth
from ..core.errors import ClothbakeError
from ..core.defaults import (BAKE_SPP_RANGE, DIRECTIONS_RANGE, RENDER_DEFAULTS,
                             TEXELS_PER_PIXEL_MAX, TEXELS_RANGE)
from ..core.material_settings import MATERIAL_SETTINGS
from ..core.scene_export import FIBER_MODELS, SHADINGS, TRANSMITTANCES
from . import prefs

_loading = False  # true while fields are filled from a spec: not an edit


def _mark_edited(self, context):
    if not _loading:
        self.cloth_edited = True


def _palette_changed(self, context):
    if not _loading:
        self.id_data.clothbake.cloth_edited = True
        _recolour(self.id_data)


def _colour_changed(self, context):
    if not _loading:
        self.cloth_edited = True
        _recolour(self.id_data)


def _recolour(obj):
    """An applied colour-free material follows the cloth's colours at once
    (material_colours.refresh: strip pixels and group inputs, no program
    run). A colour field's update must not raise: a failure is printed."""
    from . import material_colours
    try:
        material_colours.refresh(obj)
    except Exception as e:  # noqa: BLE001 (an update callback has no one to raise to)
        print(f"clothbake: the material of '{obj.name}' could not be recoloured: {e}")


def _cloth_path_changed(self, context):
    if _loading or not self.cloth_path:
        return
    try:
        self.load_cloth_file(self.cloth_path)
    except ClothbakeError:
        pass  # export refers to the path; clothbake names the problem when it reads it


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


_WEAVE_ITEMS = [
    ("plain", "Plain", "Plain weave (1 up, 1 down)"),
    ("twill_2_1", "Twill 2/1", "Twill, 2 up 1 down"),
    ("twill_2_2", "Twill 2/2", "Twill, 2 up 2 down"),
    ("satin_5", "Satin 5", "5-harness satin"),
    ("satin_8", "Satin 8", "8-harness satin"),
    ("basket_2x2", "Basket 2x2", "Basket weave, pairs of yarns"),
    ("uniform", "Uniform slab", "A homogeneous slab (for analytic checks)"),
    (cloth_fields.DRAFT, "Explicit draft", "The draft matrix of the cloth spec file"),
    (cloth_fields.WIF, "WIF draft", "The drawdown, colours and sizes of the WIF file the cloth "
     "file is or names"),
]


def draft_cache_root():
    """Where `clothbake draft` writes: Blender's temp folder of this session."""
    return bpy.app.tempdir or tempfile.gettempdir()


class ClothbakeWifColor(bpy.types.PropertyGroup):
    """One distinct colour of a WIF cloth's palette (obj.clothbake.wif_palette)."""
    __annotations__ = {
        "color": bpy.props.FloatVectorProperty(
            name="Colour", subtype="COLOR", size=3, min=0.0, max=1.0, update=_palette_changed,
            description="Diffuse albedo (linear RGB) of every thread of this colour; an applied "
                        "colour-free material follows at once"),
        "loaded": bpy.props.FloatVectorProperty(
            name="Loaded colour", size=3, options={"HIDDEN"},
            description="The colour as the draft gave it"),
        "ends": bpy.props.IntProperty(name="Ends", options={"HIDDEN"},
                                      description="Warp ends of this colour"),
        "picks": bpy.props.IntProperty(name="Picks", options={"HIDDEN"},
                                       description="Weft picks of this colour"),
    }


def _float(name, default, lo, hi, desc, step=1, precision=3):
    return bpy.props.FloatProperty(name=name, default=default, min=lo, max=hi, description=desc,
                                   update=_mark_edited, step=step, precision=precision)


def _yarn(family, default_color):
    F = family.capitalize()
    return {
        f"{family}_spacing_mm": _float(f"{F} spacing (mm)", 0.5, 1e-4, 100.0,
                                       "Distance between neighbouring yarn centres"),
        f"{family}_width_mm": _float(f"{F} width (mm)", 0.44, 1e-4, 200.0,
                                     "Full width of the yarn's cross-section "
                                     "(at most 2 x spacing)"),
        f"{family}_thickness_mm": _float(f"{F} thickness (mm)", 0.18, 1e-4, 100.0,
                                         "Full height of the yarn's cross-section"),
        f"{family}_color": bpy.props.FloatVectorProperty(
            name=f"{F} colour", subtype="COLOR", size=3, min=0.0, max=1.0,
            default=default_color, update=_colour_changed,
            description="Diffuse albedo of the fibres, linear RGB; an applied colour-free "
                        "material follows at once"),
        f"{family}_twist_deg": _float(f"{F} ply twist (deg)", 28.0, 0.0, 89.0,
                                      "Angle of the fibres to the yarn axis",
                                      step=100, precision=1),
        f"{family}_ply_pitch_mm": _float(f"{F} ply pitch (mm)", 1.0, 1e-4, 1000.0,
                                         "Yarn length of one full turn of the two bundles"),
    }


class ClothbakeObjectSettings(bpy.types.PropertyGroup):
    """obj.clothbake: one cloth object of a clothbake scene."""
    __annotations__ = {
        "is_cloth": bpy.props.BoolProperty(
            name="Cloth", default=False,
            description="Export this mesh as a clothbake cloth object (quads with UVs)"),
        "cloth_path": bpy.props.StringProperty(
            name="Cloth spec file", subtype="FILE_PATH", update=_cloth_path_changed,
            description="Cloth spec JSON this cloth came from, or a WIF weaving draft (.wif); "
                        "export refers to it until a field below is edited, then writes the "
                        "cloth inline"),
        "cloth_base": bpy.props.StringProperty(
            name="Base spec", options={"HIDDEN"},
            description="JSON of the spec the fields came from (kept for the keys the panel "
                        "does not show)"),
        "cloth_edited": bpy.props.BoolProperty(
            name="Edited", default=False,
            description="A field differs from the cloth spec file: export writes the cloth "
                        "inline"),
        "weave": bpy.props.EnumProperty(name="Weave", items=_WEAVE_ITEMS, default="plain",
                                        update=_mark_edited),
        "wif_path": bpy.props.StringProperty(
            name="WIF file", options={"HIDDEN"},
            description="Absolute path of the WIF file whose draft the panel shows"),
        "wif_draft": bpy.props.StringProperty(
            name="WIF draft", options={"HIDDEN"},
            description="The program's reading of the draft (JSON: drawdown, palette, the "
                        "threads' palette indices)"),
        "wif_loaded": bpy.props.StringProperty(
            name="Fields as loaded", options={"HIDDEN"},
            description="JSON of the fields as the draft was loaded (edits are what differs)"),
        "wif_status": bpy.props.StringProperty(
            name="WIF status", description="Why the draft could not be read, if it could not"),
        "wif_palette": bpy.props.CollectionProperty(type=ClothbakeWifColor, name="Palette"),
        **_yarn("warp", (0.60, 0.09, 0.08)),
        **_yarn("weft", (0.55, 0.42, 0.10)),
        "crimp": _float("Crimp", 1.0, 0.0, 2.0,
                        "Over/under amplitude; 1 = the yarns just touch at crossings, 0 = flat"),
        "angle_spread_deg": _float("Fibre spread (deg)", 6.0, 0.0, 45.0,
                                   "Standard deviation of the random fibre-direction "
                                   "perturbation", step=100, precision=1),
        "seed": bpy.props.IntProperty(name="Seed", default=1, min=0, update=_mark_edited,
                                      description="Seeds every random choice of the volume"),
        "cells_x": bpy.props.IntProperty(name="Cells x", default=64, min=1, soft_max=512,
                                         update=_mark_edited,
                                         description="Cells across one repeat along x (weft)"),
        "cells_y": bpy.props.IntProperty(name="Cells y", default=64, min=1, soft_max=512,
                                         update=_mark_edited,
                                         description="Cells across one repeat along y (warp)"),
        "layers": bpy.props.IntProperty(name="Layers", default=16, min=1, soft_max=128,
                                        update=_mark_edited,
                                        description="Cells through the cloth's thickness"),
        "supersample": bpy.props.IntProperty(name="Supersample", default=2, min=1, max=8,
                                             update=_mark_edited,
                                             description="Density averages s^3 sub-cell points"),
        "repeats_per_uv": bpy.props.FloatProperty(
            name="Repeats per UV", default=40.0, min=1e-6,
            description="Weave repeats per unit of UV, in u and in v"),
        "thickness_world": bpy.props.FloatProperty(
            name="Thickness", default=0.01, min=1e-9, precision=4, subtype="DISTANCE",
            description="Depth of the cloth volume behind the surface, in world units"),
        "extinction_per_mm": bpy.props.FloatProperty(
            name="Extinction (1/mm)", default=40.0, min=0.0,
            description="Extinction of fibre at density 1 per millimetre of texture space"),
        "isotropic_albedo": bpy.props.FloatVectorProperty(
            name="Isotropic albedo", subtype="COLOR", size=3, min=0.0, max=1.0,
            default=(0.8, 0.8, 0.8),
            description="Scattering albedo when the reference renderer's shading is isotropic"),
        "volume_path": bpy.props.StringProperty(
            name="Volume VDB", subtype="FILE_PATH",
            description="VDB whose volume texture replaces the one generated from the cloth "
                        "spec (the spec still gives the fibre model); empty = generate"),
        "lookup_dir": bpy.props.StringProperty(
            name="Lookup folder", subtype="DIR_PATH",
            description="Lookup to apply to this object; empty = the scene's bake folder"),
    }

    # -- cloth spec <-> fields ------------------------------------------------
    def fields(self):
        out = {"weave": self.weave}
        for name in cloth_fields.FIELDS:
            value = getattr(self, name)
            out[name] = list(value) if name in cloth_fields.COLOR_FIELDS else value
        return out

    def set_fields_from_spec(self, spec, path=""):
        """Fills the fields from a spec dict and makes it the base; not an edit."""
        global _loading
        fields = cloth_fields.fields_from_spec(spec, path)
        _loading = True
        try:
            self.weave = fields["weave"]
            for name in cloth_fields.FIELDS:
                setattr(self, name, fields[name])
            self.cloth_base = json.dumps(spec)
            self.cloth_edited = False
        finally:
            _loading = False
        _recolour(self.id_data)

    def load_cloth_file(self, path):
        global _loading
        full = os.path.abspath(bpy.path.abspath(path))
        spec = read_cloth_file(full)
        self.set_fields_from_spec(spec, path)
        _loading = True
        try:
            self.cloth_path = path
        finally:
            _loading = False
        wif = wif_cloth.absolute_wif(spec, os.path.dirname(full))
        if wif:
            self.load_wif(spec, wif, full)
        else:
            self.clear_wif()

    # -- WIF drafts -------------------------------------------------------------
    def clear_wif(self):
        global _loading
        _loading = True
        try:
            self.wif_path = self.wif_draft = self.wif_loaded = self.wif_status = ""
            self.wif_palette.clear()
        finally:
            _loading = False

    def load_wif(self, spec, wif_path, input_path=None):
        """Runs `clothbake draft` on `input_path` (the .wif or the spec file;
        None: `spec` is inline, written to the cache with `wif_path`) and
        fills the palette and the fields from its reading; not an edit.
        Returns the program's message when it refused (also kept in
        wif_status, which the panel shows), else ""."""
        global _loading
        self.clear_wif()
        _loading = True
        try:
            self.wif_path = wif_path
        finally:
            _loading = False
        try:
            program = prefs.program_path(bpy.context)
            if program is None:
                raise ClothbakeError("the clothbake program was not found; set its path in the "
                                     "add-on's preferences (it reads the WIF file)")
            root = draft_cache_root()
            if input_path is None:
                input_path = wif_cloth.write_spec_for_draft(spec, wif_path, root,
                                                            self.id_data.name)
            draft, _ = wif_cloth.run_draft(program, input_path, root)
        except (ClothbakeError, OSError) as e:
            _loading = True
            try:
                self.wif_status = str(e)
            finally:
                _loading = False
            return self.wif_status
        fields = wif_cloth.fields_for_draft(self.fields(), draft, spec)
        _loading = True
        try:
            for name in cloth_fields.FIELDS:
                setattr(self, name, fields[name])
            for i, rgb in enumerate(draft["palette"]):
                item = self.wif_palette.add()
                item.name = f"Colour {i + 1}"
                item.color = rgb
                item.loaded = rgb
                item.ends = draft["warp_color_index"].count(i)
                item.picks = draft["weft_color_index"].count(i)
            self.wif_draft = json.dumps(wif_cloth.compact_draft(draft), separators=(",", ":"))
            self.wif_loaded = json.dumps(self.fields())
        finally:
            _loading = False
        _recolour(self.id_data)
        return ""

    def draft(self):
        """The compact draft (core/wif_cloth.compact_draft), or None."""
        return json.loads(self.wif_draft) if self.wif_draft else None

    def palette(self):
        return [list(c.color) for c in self.wif_palette]

    def thread_colors(self):
        """(per-end, per-pick) colours in the palette as edited."""
        d = self.draft()
        palette = self.palette()
        return (wif_cloth.thread_colors(palette, d["warp_color_index"]),
                wif_cloth.thread_colors(palette, d["weft_color_index"]))

    def wif_inline_spec(self):
        """The inline spec of an edited WIF cloth (core/wif_cloth.inline_spec)."""
        if not self.wif_path:
            raise ClothbakeError(f"object '{self.id_data.name}': the weave is a WIF draft, but no "
                                 "WIF file is loaded; pick a .wif as the cloth spec file, or a "
                                 "named weave")
        if not self.wif_draft:  # the program refused the file: its message, once
            if self.wif_status:
                raise ClothbakeError(f"{self.wif_status}; fix the file and pick it again")
            raise ClothbakeError("the WIF draft could not be read; pick the cloth file again",
                                 self.wif_path)
        base = json.loads(self.cloth_base) if self.cloth_base else {}
        changed = wif_cloth.changed_fields(self.fields(), json.loads(self.wif_loaded))
        warp = weft = None
        if wif_cloth.palette_edited(self.palette(), [list(c.loaded) for c in self.wif_palette]):
            warp, weft = self.thread_colors()
        return wif_cloth.inline_spec(base, self.wif_path, changed, warp, weft)

    def load_from_scene_object(self, o):
        """Takes an object of a loaded scene (clothbake.core.scene.load_scene):
        its cloth (file or inline) and its settings. Raises ClothbakeError for
        a cloth spec file that cannot be read."""
        global _loading
        if "cloth_path" in o:
            self.load_cloth_file(o["cloth_path"])
        else:
            self.set_fields_from_spec(o["cloth"])
            _loading = True
            try:
                self.cloth_path = ""
            finally:
                _loading = False
            if "cloth_wif_path" in o:
                self.load_wif(o["cloth"], o["cloth_wif_path"])
            else:
                self.clear_wif()
        self.is_cloth = True
        self.repeats_per_uv = o["repeats_per_uv"]
        self.thickness_world = o["thickness_world"]
        self.extinction_per_mm = o["extinction_per_mm"]
        self.isotropic_albedo = o.get("isotropic_albedo", (0.8, 0.8, 0.8))
        self.volume_path = o.get("volume_path", "")

    def cloth(self):
        """What export writes as the object's cloth: the spec file's absolute
        path while unedited, else the spec dict."""
        if self.cloth_path and not self.cloth_edited:
            return os.path.abspath(bpy.path.abspath(self.cloth_path))
        if self.weave == cloth_fields.WIF:
            return self.wif_inline_spec()
        base = json.loads(self.cloth_base) if self.cloth_base else None
        return cloth_fields.spec_from_fields(self.fields(), base)

    def to_scene_object(self):
        """The object's entry for clothbake.core.scene_export.build_scene,
        without its mesh. Raises ClothbakeError."""
        out = {"name": self.id_data.name, "cloth": self.cloth(),
               "repeats_per_uv": self.repeats_per_uv, "thickness_world": self.thickness_world,
               "extinction_per_mm": self.extinction_per_mm,
               "isotropic_albedo": list(self.isotropic_albedo)}
        if self.volume_path:
            out["volume"] = os.path.abspath(bpy.path.abspath(self.volume_path))
        return out


def _items(names):
    return [(n, n, "") for n in names]


def _material_properties():
    """{material_<name>: property} of core/material_settings.py's table."""
    props = {}
    for s in MATERIAL_SETTINGS:
        lo, hi = s.value_range
        kwargs = dict(name=s.label, default=s.default, min=lo, max=hi, description=s.description)
        if s.kind is int:
            props[s.prop] = bpy.props.IntProperty(**kwargs)
        else:
            props[s.prop] = bpy.props.FloatProperty(**kwargs, precision=s.precision, step=s.step)
    return props


class ClothbakeSceneSettings(bpy.types.PropertyGroup):
    """scene.clothbake: the scene file, the bake and the comparison."""
    scene_path: bpy.props.StringProperty(
        name="Scene file", subtype="FILE_PATH",
        description="clothbake scene this Blender scene was imported from or last exported to; "
                    "Bake uses it as long as it still describes the Blender scene")
    bake_dir: bpy.props.StringProperty(
        name="Bake folder", subtype="DIR_PATH",
        description="Lookup folder Bake writes and Apply reads (empty: SCENE_bake beside the "
                    "scene file)")
    adaptive: bpy.props.BoolProperty(
        name="Adaptive", default=True,
        description="Bake only what the scene's camera sees, at the resolution it sees it "
                    "(otherwise every quad and direction at the texels below)")
    directions: bpy.props.IntProperty(name="Directions (K)", default=8, min=DIRECTIONS_RANGE[0],
                                      max=DIRECTIONS_RANGE[1],
                                      description="Direction nodes per side of each hemisphere")
    # Defaults for a first bake of about a minute (issue 13): a full bake of
    # a 64-quad plane at K = 8 took 8 to 10 minutes at 64 texels and 4
    # samples; at 32 texels (what docs/results.md recommends for full bakes)
    # and 2 samples it takes 58 s on the idle 2-core machine (estimate: 60 s).
    texels: bpy.props.IntProperty(name="Texels", default=32, min=TEXELS_RANGE[0],
                                  max=TEXELS_RANGE[1],
                                  description="Texels per quad side (full bake)")
    bake_spp: bpy.props.IntProperty(name="Samples per texel", default=2, min=BAKE_SPP_RANGE[0],
                                    max=BAKE_SPP_RANGE[1],
                                    description="Jittered sub-texel samples per texel")
    texels_per_pixel: bpy.props.FloatProperty(
        name="Texels per pixel", default=1.5, min=0.01, max=TEXELS_PER_PIXEL_MAX,
        description="Adaptive: texels per projected pixel along a quad edge")
    compare_samples: bpy.props.IntProperty(name="Compare samples", default=16, min=1,
                                           max=65536,
                                           description="Cycles samples of the Compare render")
    # The reference renderer's settings, written to the scene's "render" block.
    render_spp: bpy.props.IntProperty(name="Reference samples", default=RENDER_DEFAULTS["spp"],
                                      min=1, max=65536,
                                      description="Samples per pixel of clothbake render")
    step_cells: bpy.props.FloatProperty(name="Step (cells)", default=RENDER_DEFAULTS["step_cells"],
                                        min=1e-4, max=16.0,
                                        description="March step, fraction of a cell edge")
    fiber_model: bpy.props.EnumProperty(name="Fibre model", items=_items(FIBER_MODELS),
                                        default=RENDER_DEFAULTS["fiber_model"])
    fiber_samples: bpy.props.IntProperty(name="Fibre samples",
                                         default=RENDER_DEFAULTS["fiber_samples"], min=1,
                                         max=65536)
    transmittance: bpy.props.EnumProperty(name="Transmittance", items=_items(TRANSMITTANCES),
                                          default=RENDER_DEFAULTS["transmittance"])
    shading: bpy.props.EnumProperty(name="Shading", items=_items(SHADINGS),
                                    default=RENDER_DEFAULTS["shading"])
    cutoff: bpy.props.FloatProperty(name="Cutoff", default=RENDER_DEFAULTS["cutoff"], min=0.0,
                                    max=0.999,
                                    precision=4)
    render_seed: bpy.props.IntProperty(name="Seed", default=RENDER_DEFAULTS["seed"], min=0)
    # Status of the last bake / comparison, for the panel.
    bake_running: bpy.props.BoolProperty(default=False)
    bake_progress: bpy.props.FloatProperty(default=0.0, min=0.0, max=1.0, subtype="FACTOR")
    bake_status: bpy.props.StringProperty(name="Last bake")
    bake_estimate: bpy.props.StringProperty(name="Estimate")
    bake_estimate_for: bpy.props.StringProperty(options={"HIDDEN"})
    compare_status: bpy.props.StringProperty(name="Last comparison")
    # The cloth material (docs/material-format.md): one weave repeat for every
    # view, light and distance, baked from the active cloth object's cloth and
    # applied to any mesh with a UV map. Defaults: the program's.
    material_dir: bpy.props.StringProperty(
        name="Material folder", subtype="DIR_PATH",
        description="Material folder Bake material writes and Apply material reads (empty: "
                    "SCENE_material beside the scene file, else BLEND_material beside the "
                    ".blend file)")
    # texels, directions, light_directions, spp, max_error: from the one table.
    __annotations__.update(_material_properties())
    material_address: bpy.props.EnumProperty(
        name="Address", default="repeat",
        items=[("repeat", "Whole repeat", "Texels cover the weave's whole repeat (Texels per "
                "repeat side): every crossing its own, the size grows with the repeat"),
               ("crossings", "Per crossing", "One block per distinct crossing neighbourhood, "
                "addressed per crossing (Texels per crossing side): the size follows the "
                "weave's variety, not its repeat; for a large draft (a WIF of 48 threads "
                "and more)")],
        description="What the material's texels cover (clothbake material --address)")
    material_route: bpy.props.EnumProperty(
        name="Route", default="exact",
        items=[("exact", "Exact", "The reference renderer's sum: emission and transparency, "
                "lit by the scene's suns and point lights through drivers (no shadows from "
                "other objects)"),
               ("cycles-lit", "Cycles-lit", "Lights in front through a Diffuse closure, so "
                "Cycles or Eevee add shadows from other objects")],
        description="How Apply material builds the material's nodes")
    material_running: bpy.props.BoolProperty(default=False)
    material_progress: bpy.props.FloatProperty(default=0.0, min=0.0, max=1.0,
                                               subtype="FACTOR")
    material_status: bpy.props.StringProperty(name="Last material bake")
    material_estimate: bpy.props.StringProperty(name="Material estimate")
    material_estimate_for: bpy.props.StringProperty(options={"HIDDEN"})

    _RENDER_KEYS = {"spp": "render_spp", "step_cells": "step_cells",
                    "fiber_model": "fiber_model", "fiber_samples": "fiber_samples",
                    "transmittance": "transmittance", "shading": "shading", "cutoff": "cutoff",
                    "seed": "render_seed"}

    def load_render(self, render):
        """Takes a scene's "render" block (defaults where a key is absent)."""
        values = dict(RENDER_DEFAULTS)
        values.update({k: v for k, v in (render or {}).items() if k in self._RENDER_KEYS})
        for key, prop in self._RENDER_KEYS.items():
            setattr(self, prop, values[key])

    def render_dict(self):
        return {key: getattr(self, prop) for key, prop in self._RENDER_KEYS.items()}

    def bake_folder(self):
        """The absolute bake folder ("" when neither it nor a scene file is set)."""
        if self.bake_dir:
            return os.path.abspath(bpy.path.abspath(self.bake_dir)).rstrip(os.sep)
        if self.scene_path:
            return os.path.splitext(os.path.abspath(bpy.path.abspath(self.scene_path)))[0] + \
                "_bake"
        return ""

    def material_folder(self):
        """The absolute material folder: material_dir, else SCENE_material
        beside the scene file, else BLEND_material beside the saved .blend
        ("" when none is set)."""
        if self.material_dir:
            return os.path.abspath(bpy.path.abspath(self.material_dir)).rstrip(os.sep)
        base = self.scene_path and bpy.path.abspath(self.scene_path) or bpy.data.filepath
        if base:
            return os.path.splitext(os.path.abspath(base))[0] + "_material"
        return ""


CLASSES = (ClothbakeWifColor, ClothbakeObjectSettings, ClothbakeSceneSettings)


def register_extra():
    bpy.types.Object.clothbake = bpy.props.PointerProperty(type=ClothbakeObjectSettings)
    bpy.types.Scene.clothbake = bpy.props.PointerProperty(type=ClothbakeSceneSettings)


def unregister_extra():
    del bpy.types.Scene.clothbake
    del bpy.types.Object.clothbake
