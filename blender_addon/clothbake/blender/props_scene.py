"""The settings of a scene (`scene.clothbake`): the scene file, the lookup
bake, the comparison, the reference renderer's settings and the cloth
material's."""
import os

import bpy

from ..core.defaults import (BAKE_SPP_RANGE, DIRECTIONS_RANGE, RENDER_DEFAULTS,
                             TEXELS_PER_PIXEL_MAX, TEXELS_RANGE)
from ..core.material_settings import MATERIAL_SETTINGS
from ..core.scene_export import FIBER_MODELS, SHADINGS, TRANSMITTANCES


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


class _SceneSettingsMethods:
    """What scene.clothbake computes from its properties."""

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


# Built with type(): Python 3.14 defers a class body's annotations, so the
# material table's properties cannot be added to them inside the body.
ClothbakeSceneSettings = type("ClothbakeSceneSettings", (_SceneSettingsMethods,
                                                         bpy.types.PropertyGroup), {
    "__doc__": "scene.clothbake: the scene file, the bake and the comparison.",
    "__module__": __name__,
    "__annotations__": {
        "scene_path": bpy.props.StringProperty(
            name="Scene file", subtype="FILE_PATH",
            description="clothbake scene this Blender scene was imported from or last exported to; "
                        "Bake uses it as long as it still describes the Blender scene"),
        "bake_dir": bpy.props.StringProperty(
            name="Bake folder", subtype="DIR_PATH",
            description="Lookup folder Bake writes and Apply reads (empty: SCENE_bake beside the "
                        "scene file)"),
        "adaptive": bpy.props.BoolProperty(
            name="Adaptive", default=True,
            description="Bake only what the scene's camera sees, at the resolution it sees it "
                        "(otherwise every quad and direction at the texels below)"),
        "directions": bpy.props.IntProperty(
            name="Directions (K)", default=8, min=DIRECTIONS_RANGE[0], max=DIRECTIONS_RANGE[1],
            description="Direction nodes per side of each hemisphere"),
        # Defaults for a first bake of about a minute, so a new user is not
        # left waiting with no word: a full bake of a 64-quad plane at K = 8
        # took 8 to 10 minutes at 64 texels and 4 samples; at 32 texels and 2
        # samples it takes 58 s on an idle 2-core machine (estimate: 60 s).
        "texels": bpy.props.IntProperty(
            name="Texels", default=32, min=TEXELS_RANGE[0], max=TEXELS_RANGE[1],
            description="Texels per quad side (full bake)"),
        "bake_spp": bpy.props.IntProperty(
            name="Samples per texel", default=2, min=BAKE_SPP_RANGE[0], max=BAKE_SPP_RANGE[1],
            description="Jittered sub-texel samples per texel"),
        "texels_per_pixel": bpy.props.FloatProperty(
            name="Texels per pixel", default=1.5, min=0.01, max=TEXELS_PER_PIXEL_MAX,
            description="Adaptive: texels per projected pixel along a quad edge"),
        "compare_samples": bpy.props.IntProperty(
            name="Compare samples", default=16, min=1, max=65536,
            description="Cycles samples of the Compare render"),
        # The reference renderer's settings, written to the scene's "render" block.
        "render_spp": bpy.props.IntProperty(
            name="Reference samples", default=RENDER_DEFAULTS["spp"], min=1, max=65536,
            description="Samples per pixel of clothbake render"),
        "step_cells": bpy.props.FloatProperty(
            name="Step (cells)", default=RENDER_DEFAULTS["step_cells"], min=1e-4, max=16.0,
            description="March step, fraction of a cell edge"),
        "fiber_model": bpy.props.EnumProperty(name="Fibre model", items=_items(FIBER_MODELS),
                                              default=RENDER_DEFAULTS["fiber_model"]),
        "fiber_samples": bpy.props.IntProperty(name="Fibre samples",
                                               default=RENDER_DEFAULTS["fiber_samples"], min=1,
                                               max=65536),
        "transmittance": bpy.props.EnumProperty(name="Transmittance",
                                                items=_items(TRANSMITTANCES),
                                                default=RENDER_DEFAULTS["transmittance"]),
        "shading": bpy.props.EnumProperty(name="Shading", items=_items(SHADINGS),
                                          default=RENDER_DEFAULTS["shading"]),
        "cutoff": bpy.props.FloatProperty(name="Cutoff", default=RENDER_DEFAULTS["cutoff"],
                                          min=0.0, max=0.999, precision=4),
        "render_seed": bpy.props.IntProperty(name="Seed", default=RENDER_DEFAULTS["seed"], min=0),
        # Status of the last bake / comparison, for the panel.
        "bake_running": bpy.props.BoolProperty(default=False),
        "bake_progress": bpy.props.FloatProperty(default=0.0, min=0.0, max=1.0,
                                                 subtype="FACTOR"),
        "bake_status": bpy.props.StringProperty(name="Last bake"),
        "bake_estimate": bpy.props.StringProperty(name="Estimate"),
        "bake_estimate_for": bpy.props.StringProperty(options={"HIDDEN"}),
        "compare_status": bpy.props.StringProperty(name="Last comparison"),
        # The cloth material (docs/formats/material.md): one weave repeat for
        # every view, light and distance, baked from the active cloth object's
        # cloth and applied to any mesh with a UV map. Defaults: the program's.
        "material_dir": bpy.props.StringProperty(
            name="Material folder", subtype="DIR_PATH",
            description="Material folder Bake material writes and Apply material reads (empty: "
                        "SCENE_material beside the scene file, else BLEND_material beside the "
                        ".blend file)"),
        # texels, directions, light_directions, spp, max_error: the one table.
        **_material_properties(),
        "material_address": bpy.props.EnumProperty(
            name="Address", default="auto",
            items=[("auto", "Automatic", "The whole repeat where its texels resolve the threads "
                    "(2 a thread) and the bake fits the memory, else per crossing (at 8 texels "
                    "while Texels is at its default): the estimate says which and why"),
                   ("repeat", "Whole repeat", "Texels cover the weave's whole repeat (Texels per "
                    "repeat side): every crossing its own, the size grows with the repeat"),
                   ("crossings", "Per crossing", "One block per distinct crossing neighbourhood, "
                    "addressed per crossing (Texels per crossing side): the size follows the "
                    "weave's variety, not its repeat; for a large draft (a WIF of 48 threads "
                    "and more)")],
            description="What the material's texels cover (clothbake material --address)"),
        "material_route": bpy.props.EnumProperty(
            name="Route", default="exact",
            items=[("exact", "Exact", "The reference renderer's sum: emission and transparency, "
                    "lit by the scene's sun, point, spot and area lights through drivers (no shadows from "
                    "other objects)"),
                   ("cycles-lit", "Cycles-lit", "Lights in front through a Diffuse closure, so "
                    "Cycles or Eevee add shadows from other objects")],
            description="How Apply material builds the material's nodes"),
        "material_running": bpy.props.BoolProperty(default=False),
        "material_progress": bpy.props.FloatProperty(default=0.0, min=0.0, max=1.0,
                                                     subtype="FACTOR"),
        "material_status": bpy.props.StringProperty(name="Last material bake"),
        "material_estimate": bpy.props.StringProperty(name="Material estimate"),
        "material_estimate_for": bpy.props.StringProperty(options={"HIDDEN"}),
    },
})
