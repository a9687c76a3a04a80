"""The material bake's settings table (clothbake.core.material_settings):
one row per default the program has, options the program takes, and the
command line and estimate key made from it."""
import subprocess

import pytest

from clothbake.core import defaults
from clothbake.core import material_settings as ms
from clothbake.core.errors import ClothbakeError


class Settings:
    """Stands in for scene.clothbake: material_<name> fields."""

    def __init__(self, **values):
        for s in ms.MATERIAL_SETTINGS:
            setattr(self, s.prop, values.get(s.name, s.default))


def test_one_row_per_program_default():
    assert [s.name for s in ms.MATERIAL_SETTINGS] == list(defaults.MATERIAL_DEFAULTS)
    for s in ms.MATERIAL_SETTINGS:
        lo, hi = s.value_range
        assert lo <= s.default <= hi, s.name
        assert isinstance(s.default, s.kind), s.name


def test_command_line_and_key():
    values = ms.material_values(Settings(texels=8, max_error=0.1234567))
    assert ms.material_arguments(values) == [
        "--texels", "8", "--directions", "16", "--light-directions", "10", "--spp", "2",
        "--max-error", "0.123457"]
    assert ms.material_key(values) == [8, 16, 10, 2, 0.123457]


def test_texels_must_be_a_power_of_2():
    ms.check_material_values({"texels": 64})
    with pytest.raises(ClothbakeError, match=r"material Texels: must be a power of 2.*got 12"):
        ms.check_material_values({"texels": 12})


def test_the_program_takes_every_option(clothbake_bin):
    help_text = subprocess.run([clothbake_bin, "material", "--help"], capture_output=True,
                               text=True).stdout
    for s in ms.MATERIAL_SETTINGS:
        assert s.flag in help_text, s.flag
