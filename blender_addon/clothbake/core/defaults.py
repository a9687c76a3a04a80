"""What the add-on shares with the clothbake program, stated once on this
side: the reference renderer's default settings, the ranges of the bake
settings, and the names of a folder output's temporary siblings. Each is
stated once on the C++ side too (baker/core/scene/scene.h RenderSettings,
baker/core/bake/bake_settings.h, baker/io/atomic_file.h), and
tests/addon/test_defaults.py reads those headers and holds these to them.
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

# A folder output (a bake) is written as NAME.tmp-PID and the folder it
# replaces set aside as NAME.old-PID (baker/io/atomic_file.h).
FOLDER_TEMP_TAG = ".tmp-"
FOLDER_OLD_TAG = ".old-"


def folder_siblings(folder, pid):
    """(temporary, set-aside) names the program `pid` uses for `folder`."""
    return f"{folder}{FOLDER_TEMP_TAG}{pid}", f"{folder}{FOLDER_OLD_TAG}{pid}"
