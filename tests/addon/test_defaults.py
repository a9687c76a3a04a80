"""The add-on's copy of what it shares with the program
(clothbake.core.defaults) against the program's own headers, where each is
stated once: a new render setting, a changed range or a renamed temporary
folder fails here instead of drifting apart."""
import os
import re

from clothbake.core import defaults, lookup_manifest, scene, scene_export

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")


def header(path):
    with open(os.path.join(ROOT, path), encoding="utf-8") as f:
        return f.read()


def struct_fields(text, name):
    """{field: default text} of `struct name { ... };` (one field a line)."""
    body = re.search(r"struct %s \{(.*?)\n\};" % name, text, re.S).group(1)
    fields = {}
    for line in body.splitlines():
        m = re.match(r"\s*[\w:<>]+ (\w+) = ([^;]+);", line)
        if m:
            fields[m.group(1)] = m.group(2).strip()
    return fields


def test_render_defaults_are_the_programs():
    cpp = struct_fields(header("baker/core/scene/scene.h"), "RenderSettings")
    enum_names = {"FiberModelKind::Table": "table", "FiberModelKind::Ellipsoid": "ellipsoid",
                  "TransmittanceMode::Cached": "cached",
                  "TransmittanceMode::ShadowMarch": "shadow-march",
                  "ShadingMode::Fiber": "fiber", "ShadingMode::Isotropic": "isotropic"}

    def value(text):
        if text in enum_names:
            return enum_names[text]
        return float(text.rstrip("f")) if re.search(r"[.e]", text) else int(text)

    program = {k: value(v) for k, v in cpp.items()}
    # Every setting the program has, the add-on has (light_roulette is left
    # to the program on purpose: export never writes it).
    assert set(program) - {"light_roulette"} == set(defaults.RENDER_DEFAULTS)
    for key, want in defaults.RENDER_DEFAULTS.items():
        assert program[key] == want, key
    # The modules that state render defaults take them from here.
    assert scene_export.RENDER_DEFAULTS is defaults.RENDER_DEFAULTS
    assert scene.RENDER_DEFAULTS is defaults.RENDER_DEFAULTS


def test_bake_ranges_are_the_programs():
    text = header("baker/core/bake/bake_settings.h")

    def const(name):
        return float(re.search(r"\b%s = ([0-9.]+)f?" % name, text).group(1))

    assert defaults.DIRECTIONS_RANGE == (const("k_min_directions"), const("k_max_directions"))
    assert defaults.TEXELS_RANGE == (const("k_min_texels"), const("k_max_texels"))
    assert defaults.BAKE_SPP_RANGE == (const("k_min_bake_spp"), const("k_max_bake_spp"))
    assert defaults.TEXELS_PER_PIXEL_MAX == const("k_max_texels_per_pixel")
    assert lookup_manifest.K_RANGE == defaults.DIRECTIONS_RANGE


def test_folder_tags_are_the_programs():
    text = header("baker/io/atomic_file.h")
    temp = re.search(r'k_folder_temp_tag = "([^"]+)"', text).group(1)
    old = re.search(r'k_folder_old_tag = "([^"]+)"', text).group(1)
    assert (defaults.FOLDER_TEMP_TAG, defaults.FOLDER_OLD_TAG) == (temp, old)
    assert defaults.folder_siblings("/a/bake", 12) == ("/a/bake.tmp-12", "/a/bake.old-12")


def test_depth_scale_tolerance_is_the_programs():
    """Wherever the program's header states it (found by name, as the
    baker's files may move)."""
    found = []
    for folder, _, files in os.walk(os.path.join(ROOT, "baker")):
        for name in files:
            if name.endswith(".h"):
                with open(os.path.join(folder, name), encoding="utf-8") as f:
                    m = re.search(r"\bk_depth_scale_tolerance = ([0-9.]+)f?;", f.read())
                if m:
                    found.append(float(m.group(1)))
    assert found == [defaults.DEPTH_SCALE_TOLERANCE]
