"""clothbake.core.cloth_fields: the panel's cloth fields read from and
written to cloth specs without losing what the panel does not show."""
import json
import os
import sys

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "blender_addon"))

from clothbake.core import cloth_fields as cf  # noqa: E402
from clothbake.core.errors import ClothbakeError  # noqa: E402


def test_defaults_are_the_cloth_specs():
    # docs/formats/cloth-spec.md / baker/core/weave/cloth_spec.h
    d = cf.default_fields()
    assert d["weave"] == "plain"
    assert d["warp_color"] == [0.60, 0.09, 0.08] and d["weft_color"] == [0.55, 0.42, 0.10]
    assert (d["warp_spacing_mm"], d["warp_width_mm"], d["warp_thickness_mm"]) == (0.5, 0.44, 0.18)
    assert (d["cells_x"], d["cells_y"], d["layers"], d["supersample"]) == (64, 64, 16, 2)
    assert (d["crimp"], d["angle_spread_deg"], d["seed"]) == (1.0, 6.0, 1)


def test_paper_spec_round_trip_is_exact():
    spec = json.load(open(os.path.join(ROOT, "testscenes", "paper", "cloth.json")))
    fields = cf.fields_from_spec(spec)
    assert fields["weave"] == "plain" and fields["warp_twist_deg"] == 28.0
    assert cf.spec_from_fields(fields, spec) == spec


def test_edit_keeps_the_fields_the_panel_does_not_show():
    spec = json.load(open(os.path.join(ROOT, "testscenes", "slab", "cloth.json")))
    fields = cf.fields_from_spec(spec)
    assert fields["weave"] == "uniform" and fields["cells_x"] == 8
    fields["weave"] = "twill_2_2"
    fields["warp_width_mm"] = 0.3
    out = cf.spec_from_fields(fields, spec)
    assert out["weave"] == {"pattern": "twill_2_2"}
    assert out["warp"]["width_mm"] == 0.3
    assert out["density"] == spec["density"] and out["description"] == spec["description"]


def test_explicit_draft_is_kept_and_needs_a_base():
    spec = {"weave": {"draft": [[1, 0], [0, 1]]}}
    fields = cf.fields_from_spec(spec)
    assert fields["weave"] == cf.DRAFT
    assert cf.spec_from_fields(fields, spec)["weave"] == spec["weave"]
    with pytest.raises(ClothbakeError, match="weave: the weave is an explicit draft"):
        cf.spec_from_fields(fields, None)


def test_bad_spec_values_name_the_field():
    with pytest.raises(ClothbakeError, match="c.json: warp.color: must be an array of 3"):
        cf.fields_from_spec({"warp": {"color": [1, 2]}}, "c.json")
    with pytest.raises(ClothbakeError, match="c.json: weave.pattern: unknown weave 'satin_7'"):
        cf.fields_from_spec({"weave": {"pattern": "satin_7"}}, "c.json")
    with pytest.raises(ClothbakeError, match="resolution.layers: must be an integer"):
        cf.fields_from_spec({"resolution": {"layers": 2.5}}, "c.json")


def test_float32_values_are_written_short():
    import struct
    f32 = struct.unpack("f", struct.pack("f", 0.44))[0]
    assert f32 != 0.44 and cf.short_float(f32) == 0.44
    assert cf.short_float(0.1) == 0.1  # a double that is no float32: unchanged
    assert cf.short_float(1e300) == 1e300
