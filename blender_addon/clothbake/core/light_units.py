"""Blender's light watts as clothbake's intensities, per Blender version.

Cycles changed what a watt of a spot or area light gives in Blender 4.0
(its release notes: spot lights became sphere lights like point lights, and
the lights' normalisation with them). Measured on a white diffuse plane, 64
samples, in 3.4.1, 4.3.2 and 5.2.2 (lab/light_units/):

- point and sun: the same in every version. A point light of P watts has
  radiant intensity P / (4 pi) W/sr, so clothbake's point intensity I
  (irradiance at distance 1) is P / (4 pi). Sun strength is irradiance.
- spot: that point light masked by its cone. In 3.x the mask holds one more
  cosine of the angle off the axis (a x smoothstep); from 4.0 it is the
  smoothstep alone. clothbake's spot says which with `axis_cosine`.
- area: radiance P / (4 A) in 3.x, P / (pi A) from 4.0 (4 / pi = 1.273 x
  brighter for the same watts). clothbake's area intensity is radiance x
  area, so I = P / 4 or P / pi.

From 5.0 (not in 4.3.2) a light also has Exposure (watts x 2^exposure:
effective_watts), and a Temperature and a Normalize switch, which clothbake
does not model: see unsupported_light_setting.
"""
import math
from dataclasses import dataclass

POINT_WATTS_PER_IRRADIANCE = 4.0 * math.pi


@dataclass(frozen=True)
class LightUnits:
    """How one Blender version's light watts become clothbake intensities."""
    name: str                          # "3.x" or "4.0+", for notes and group keys
    spot_watts_per_intensity: float
    area_watts_per_intensity: float
    spot_axis_cosine: bool             # the spot's mask holds cos(off the axis)

    point_watts_per_irradiance: float = POINT_WATTS_PER_IRRADIANCE

    def watts_per_intensity(self, blender_type):
        """The watts one unit of clothbake intensity takes, for a POINT, SPOT
        or AREA light (a SUN's strength is its irradiance: 1)."""
        return {"SUN": 1.0, "POINT": self.point_watts_per_irradiance,
                "SPOT": self.spot_watts_per_intensity,
                "AREA": self.area_watts_per_intensity}[blender_type]


BLENDER_3 = LightUnits("3.x", POINT_WATTS_PER_IRRADIANCE, 4.0, True)
BLENDER_4 = LightUnits("4.0+", POINT_WATTS_PER_IRRADIANCE, math.pi, False)


def light_units(version):
    """The units of Blender `version` (a tuple such as bpy.app.version)."""
    return BLENDER_3 if tuple(version[:2]) < (4, 0) else BLENDER_4


def effective_watts(energy, exposure=0.0):
    """A light's watts with its Exposure (5.x; 0 before) applied."""
    return float(energy) * 2.0 ** float(exposure)


def unsupported_light_setting(use_temperature=False, normalize=True):
    """Why clothbake cannot light a scene as this light does (None when it
    can): a colour temperature (Blender 5.x multiplies the colour by a
    black body's, which clothbake does not model) or Normalize off (the
    power then grows with the light's size)."""
    if use_temperature:
        return ("Temperature is on: clothbake reads the light's Color only; turn "
                "Temperature off and set the colour")
    if not normalize:
        return "Normalize is off: clothbake's lights keep their power at any size; turn it on"
    return None
