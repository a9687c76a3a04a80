"""What the add-on shares with the clothbake program, stated once on this
side: the reference renderer's default settings, the ranges of the bake
settings, the material bake's defaults and ranges, the depth-scale tolerance
and the names of a folder output's temporary siblings. Each is stated once on
the C++ side too (baker/core/scene/scene.h RenderSettings,
baker/core/bake/bake_settings.h, baker/core/material/material_settings.h,
material_shader.h, baker/io/atomic_file.h), and tests/addon/test_defaults.py
and test_material_defaults.py read those headers and hold these to them.
"""

# RenderSettings (baker/core/scene/scene.h), as a scene's "render" block
# spells them. light_roulette is not exported: the program's default holds.
RENDER_DEFAULTS = {"spp": 4, "step_cells": 0.5, "fiber_model": "table", "fiber_samples": 64,
                   "transmittance": "cached", "shading": "fiber", "cutoff": 0.001, "seed": 1}

# Bake settings' ranges (baker/core/bake/bake_settings.h).
DIRECTIONS_RANGE = (2, 64)        # K
TEXELS_RANGE = (1, 4096)          # R, texels per quad side
BAKE_SPP_RANGE = (1, 4096)        # samples per texel
TEXELS_PER_PIXEL_MAX = 64.0       # adaptive, in (0, this]

# The material bake's settings (baker/core/material/material_settings.h,
# MaterialSettings and its ranges), by the add-on's names; texels is a
# power of 2.
MATERIAL_DEFAULTS = {"texels": 32, "directions": 16, "light_directions": 10, "spp": 2,
                     "max_error": 0.05}
MATERIAL_TEXELS_RANGE = (1, 1024)
MATERIAL_DIRECTIONS_RANGE = (2, 32)   # view and light directions
MATERIAL_SPP_RANGE = (1, 1024)
MATERIAL_ERROR_RANGE = (0.0, 1.0)
# How far an object's depth scale may stray from the material's before the
# weave is shaded at the material's thickness (k_depth_scale_tolerance,
# baker/core/material/material_shader.h): a relative difference.
DEPTH_SCALE_TOLERANCE = 0.05

# A folder output (a bake) is written as NAME.tmp-PID and the folder it
# replaces set aside as NAME.old-PID (baker/io/atomic_file.h).
FOLDER_TEMP_TAG = ".tmp-"
FOLDER_OLD_TAG = ".old-"


def folder_siblings(folder, pid):
    """(temporary, set-aside) names the program `pid` uses for `folder`."""
    return f"{folder}{FOLDER_TEMP_TAG}{pid}", f"{folder}{FOLDER_OLD_TAG}{pid}"
