"""The settings of a cloth object (`obj.clothbake`: the cloth and how it
sits on the mesh). Properties only: loading a cloth file and reading a WIF
draft with the program are operators_cloth.py's.

Cloth spec files. An object imported from a scene whose cloth is a file
keeps that path (`cloth_path`) and shows the file's values in the fields.
Export refers to the file as long as no field is edited; once one is
(`cloth_edited`), export writes the cloth inline: the file's spec with the
fields written over it, so what the panel does not show (density, shading,
an explicit draft) is kept. Loading another file reloads the fields from it.

WIF drafts, so a weaver's own draft file is the cloth. The cloth file may
be a .wif, or a JSON spec whose weave.wif names one. The program reads it
(`clothbake draft`, into a folder of Blender's session temp) and the object
keeps its reading (`wif_draft`: the drawdown and each thread's index into
the palette), the palette as editable colours (`wif_palette`) and the
fields as loaded (`wif_loaded`). Editing a palette colour recolours every
thread that uses it; once anything is edited, export writes the cloth
inline: {"weave": {"wif": ABSOLUTE_PATH}, "warp": {"colors": per end},
"weft": {"colors": per pick}} and only the fields that changed
(core/wif_cloth.py), so the file's per-thread spacings and widths stay
unless their field is edited.
"""
import json
import os
from contextlib import contextmanager

import bpy

from ..core import cloth_fields, wif_cloth
from ..core.errors import ClothbakeError

_loading = False  # true while fields are filled from a spec: not an edit


@contextmanager
def loading():
    """Fields set inside are filled from a spec, not edits."""
    global _loading
    _loading = True
    try:
        yield
    finally:
        _loading = False


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
            name="Cloth spec file", subtype="FILE_PATH",
            description="Cloth spec JSON this cloth came from, or a WIF weaving draft (.wif), "
                        "as Load cloth file read it; export refers to it until a field below "
                        "is edited, then writes the cloth inline"),
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
        fields = cloth_fields.fields_from_spec(spec, path)
        with loading():
            self.weave = fields["weave"]
            for name in cloth_fields.FIELDS:
                setattr(self, name, fields[name])
            self.cloth_base = json.dumps(spec)
            self.cloth_edited = False
        _recolour(self.id_data)

    # -- WIF drafts -------------------------------------------------------------
    def clear_wif(self):
        with loading():
            self.wif_path = self.wif_draft = self.wif_loaded = self.wif_status = ""
            self.wif_palette.clear()

    def set_wif_draft(self, draft, spec):
        """Fills the palette and the fields from the program's reading of the
        draft (operators_cloth.load_wif); not an edit."""
        fields = wif_cloth.fields_for_draft(self.fields(), draft, spec)
        with loading():
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
        _recolour(self.id_data)

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
