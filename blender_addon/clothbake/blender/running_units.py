"""The light units of the Blender this add-on runs in (core/light_units.py):
the one place that reads the running version for them, so export, import,
the exact route's drivers and its spot mask always agree."""
import bpy

from ..core.light_units import light_units

RUNNING_UNITS = light_units(bpy.app.version)
