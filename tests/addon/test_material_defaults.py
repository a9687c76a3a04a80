"""The add-on's material-bake defaults and ranges (clothbake.core.defaults)
against the program's MaterialSettings (baker/core/material/material_settings.h),
where they are stated once."""
import os
import re

from clothbake.core import defaults

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")


def _header():
    with open(os.path.join(ROOT, "baker/core/material/material_settings.h"),
              encoding="utf-8") as f:
        return f.read()


def test_material_defaults_are_the_programs():
    text = _header()
    body = re.search(r"struct MaterialSettings \{(.*?)\n\};", text, re.S).group(1)
    cpp = {}
    for line in body.splitlines():
        m = re.match(r"\s*[\w:]+ (\w+) = ([0-9.]+)f?;", line)
        if m:
            cpp[m.group(1)] = float(m.group(2))
    for key, want in defaults.MATERIAL_DEFAULTS.items():
        assert cpp[key] == want, key
    texels = defaults.MATERIAL_DEFAULTS["texels"]
    assert texels & (texels - 1) == 0


def test_material_ranges_are_the_programs():
    text = _header()

    def const(name):
        return float(re.search(r"\b%s = ([0-9.]+)f?" % name, text).group(1))

    assert defaults.MATERIAL_TEXELS_RANGE == (const("k_min_material_texels"),
                                              const("k_max_material_texels"))
    assert defaults.MATERIAL_DIRECTIONS_RANGE == (const("k_min_material_directions"),
                                                  const("k_max_material_directions"))
    assert defaults.MATERIAL_SPP_RANGE == (const("k_min_material_spp"),
                                           const("k_max_material_spp"))
    assert defaults.MATERIAL_ERROR_RANGE == (const("k_min_material_error"),
                                             const("k_max_material_error"))
