"""The cloth settings an artist edits in the add-on's panel, as a flat set of
named fields, and their mapping to and from a cloth spec (docs/formats/cloth-spec.md).

Only part of a cloth spec is exposed (weave, yarns, crimp, fibre spread,
seed, resolution); everything else (density, shading, an explicit draft) is
kept from the spec the object came from (`base`) and written back
unchanged, so editing a field never loses the rest of a spec.
"""
import copy
import struct

from .errors import ClothbakeError

# Named drafts of baker/core/weave/weave.cpp, plus "uniform" (a homogeneous slab,
# for analytic checks), "draft" (an explicit weave.draft matrix, which the
# panel cannot edit: it comes from the spec file) and "wif" (a weaving draft
# file, weave.wif: its drawdown and colours, core/wif_cloth.py).
WEAVES = ("plain", "twill_2_1", "twill_2_2", "satin_5", "satin_8", "basket_2x2", "uniform")
DRAFT = "draft"
WIF = "wif"

_YARN = (  # key, default warp, default weft (baker/core/weave/cloth_spec.h)
    ("spacing_mm", 0.5, 0.5),
    ("width_mm", 0.44, 0.44),
    ("thickness_mm", 0.18, 0.18),
    ("color", (0.60, 0.09, 0.08), (0.55, 0.42, 0.10)),
    ("twist_deg", 28.0, 28.0),
    ("ply_pitch_mm", 1.0, 1.0),
)

# flat name -> (path in the spec, default)
FIELDS = {}
for _key, _warp, _weft in _YARN:
    FIELDS[f"warp_{_key}"] = (("warp", _key), _warp)
    FIELDS[f"weft_{_key}"] = (("weft", _key), _weft)
FIELDS.update({
    "crimp": (("crimp",), 1.0),
    "angle_spread_deg": (("angle_spread_deg",), 6.0),
    "seed": (("seed",), 1),
    "cells_x": (("resolution", "cells_x"), 64),
    "cells_y": (("resolution", "cells_y"), 64),
    "layers": (("resolution", "layers"), 16),
    "supersample": (("resolution", "supersample"), 2),
})
COLOR_FIELDS = ("warp_color", "weft_color")
INT_FIELDS = ("seed", "cells_x", "cells_y", "layers", "supersample")


def short_float(value):
    """`value` as the shortest decimal that is the same float32, when it is a
    float32 (Blender stores float properties as float32: 0.44 comes back as
    0.4399999976158142, and is written as 0.44); other values unchanged."""
    value = float(value)
    try:
        as32 = struct.unpack("f", struct.pack("f", value))[0]
    except OverflowError:
        return value
    if as32 != value:
        return value
    for digits in range(6, 10):
        text = float(f"%.{digits}g" % value)
        if struct.unpack("f", struct.pack("f", text))[0] == as32:
            return text
    return value


def _get(spec, path):
    node = spec
    for key in path:
        if not isinstance(node, dict) or key not in node:
            return None
        node = node[key]
    return node


def default_fields():
    """Every field at the cloth spec's default, weave plain."""
    fields = {"weave": "plain"}
    for name, (_, default) in FIELDS.items():
        fields[name] = list(default) if name in COLOR_FIELDS else default
    return fields


def fields_from_spec(spec, path=""):
    """The flat fields of a cloth spec dict (defaults where a key is absent).
    Raises ClothbakeError (naming `path` and the field) for a value of the
    wrong type or an unknown weave name."""
    if not isinstance(spec, dict):
        raise ClothbakeError("a cloth spec must be a JSON object", path)
    fields = default_fields()
    weave = spec.get("weave", {})
    if not isinstance(weave, dict):
        raise ClothbakeError("must be an object", path, "weave")
    given = [k for k in ("pattern", "draft", "wif") if weave.get(k) is not None]
    if len(given) > 1:  # as the program's reader (io/cloth_spec_json.cpp)
        raise ClothbakeError("give one of pattern, draft or wif", path, "weave")
    if "wif" in weave:
        if not isinstance(weave["wif"], str) or not weave["wif"]:
            raise ClothbakeError("must be the path of a WIF file", path, "weave.wif")
        fields["weave"] = WIF
    elif weave.get("draft") is not None:
        fields["weave"] = DRAFT
    elif "pattern" in weave:
        if weave["pattern"] not in WEAVES:
            raise ClothbakeError(f"unknown weave '{weave['pattern']}'; expected one of: "
                                 + ", ".join(WEAVES), path, "weave.pattern")
        fields["weave"] = weave["pattern"]
    for name, (keys, default) in FIELDS.items():
        value = _get(spec, keys)
        if value is None:
            continue
        field = ".".join(keys)
        if name in COLOR_FIELDS:
            numbers = all(isinstance(c, (int, float)) and not isinstance(c, bool)
                          for c in value) if isinstance(value, list) else False
            if not numbers or len(value) != 3:
                raise ClothbakeError("must be an array of 3 numbers", path, field)
            fields[name] = [float(c) for c in value]
        elif name in INT_FIELDS:
            if not isinstance(value, int) or isinstance(value, bool):
                raise ClothbakeError("must be an integer", path, field)
            fields[name] = value
        else:
            if not isinstance(value, (int, float)) or isinstance(value, bool):
                raise ClothbakeError("must be a number", path, field)
            fields[name] = float(value)
    return fields


def spec_from_fields(fields, base=None):
    """A cloth spec dict: `base` (the spec the object came from, or none)
    with every field of `fields` written over it. Raises ClothbakeError when
    the weave is "draft" (or "wif") but `base` holds no draft (no weave.wif).
    A WIF cloth's edits are written by wif_cloth.inline_spec, which writes
    only the fields that changed."""
    spec = copy.deepcopy(base) if isinstance(base, dict) else {}
    weave = fields.get("weave", "plain")
    if weave == DRAFT:
        if _get(spec, ("weave", "draft")) is None:
            raise ClothbakeError("the weave is an explicit draft, but the cloth spec holds no "
                                 "weave.draft; pick a named weave", "", "weave")
    elif weave == WIF:
        if _get(spec, ("weave", "wif")) is None:
            raise ClothbakeError("the weave is a WIF draft, but the cloth spec names no WIF file "
                                 "(weave.wif); pick a cloth file or a named weave", "", "weave")
    elif weave in WEAVES:
        spec["weave"] = {"pattern": weave}
    else:
        raise ClothbakeError(f"unknown weave '{weave}'; expected one of: " + ", ".join(WEAVES),
                             "", "weave")
    for name, (keys, _) in FIELDS.items():
        if name not in fields:
            continue
        node = spec
        for key in keys[:-1]:
            if not isinstance(node.get(key), dict):
                node[key] = {}
            node = node[key]
        value = fields[name]
        if name in COLOR_FIELDS:
            value = [short_float(c) for c in value]
        elif name in INT_FIELDS:
            value = int(value)
        else:
            value = short_float(value)
        node[keys[-1]] = value
    return spec
