"""The material bake's settings, listed once: each one's name, label,
description and the `clothbake material` option that takes it. The panel's
properties (blender/props_scene.py), its rows (blender/panels.py), the command
line and the estimate's cache key (blender/operators_material.py) are all
made from this table; the defaults and ranges are the program's
(core/defaults.py, held to baker/core/material/material_settings.h).
"""
from dataclasses import dataclass

from .defaults import (MATERIAL_DEFAULTS, MATERIAL_DIRECTIONS_RANGE, MATERIAL_ERROR_RANGE,
                       MATERIAL_SPP_RANGE, MATERIAL_TEXELS_RANGE)
from .errors import ClothbakeError


@dataclass(frozen=True)
class MaterialSetting:
    name: str                 # key of MATERIAL_DEFAULTS; the property is material_<name>
    flag: str                 # the option of `clothbake material`
    kind: type                # int or float
    value_range: tuple        # (min, max), the program's
    label: str
    description: str
    precision: int = None     # float fields: digits shown
    step: int = None          # float fields: drag step, in 1/100 units

    @property
    def prop(self):
        return f"material_{self.name}"

    @property
    def default(self):
        return MATERIAL_DEFAULTS[self.name]

    def argument(self, value):
        """The option's value as the command line spells it."""
        return str(value) if self.kind is int else "%g" % value

    def key(self, value):
        """The value as an estimate's cache key holds it (floats rounded, so
        a value the panel shows unchanged keeps its estimate)."""
        return value if self.kind is int else round(value, 6)


MATERIAL_SETTINGS = (
    MaterialSetting("texels", "--texels", int, MATERIAL_TEXELS_RANGE, "Texels",
                    "Texels per side of one weave repeat (a power of 2)"),
    MaterialSetting("directions", "--directions", int, MATERIAL_DIRECTIONS_RANGE,
                    "View directions", "View nodes per side of each hemisphere's grid"),
    MaterialSetting("light_directions", "--light-directions", int, MATERIAL_DIRECTIONS_RANGE,
                    "Light directions", "Light nodes per side of each hemisphere's grid"),
    MaterialSetting("spp", "--spp", int, MATERIAL_SPP_RANGE, "Samples per texel",
                    "Jittered marches per texel and view direction"),
    MaterialSetting("max_error", "--max-error", float, MATERIAL_ERROR_RANGE, "Max error",
                    "Relative error the compression may leave per view direction (0 = exact)",
                    precision=3, step=1),
)


def material_values(settings):
    """{name: value} of the table's settings, read from `settings` (the
    scene's clothbake settings, or anything with material_<name> fields)."""
    return {s.name: getattr(settings, s.prop) for s in MATERIAL_SETTINGS}


def check_material_values(values):
    """Refuses what the properties' ranges cannot: texels not a power of 2."""
    texels = values["texels"]
    if texels & (texels - 1):
        raise ClothbakeError(f"must be a power of 2 (8, 16, 32, 64, ...), got {texels}", "",
                             "material Texels")


def material_arguments(values):
    """The table's options of `clothbake material`, in table order."""
    args = []
    for s in MATERIAL_SETTINGS:
        args += [s.flag, s.argument(values[s.name])]
    return args


def material_key(values):
    """The settings' part of a material estimate's cache key."""
    return [s.key(values[s.name]) for s in MATERIAL_SETTINGS]
