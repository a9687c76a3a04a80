"""Headless Blender 3.4 test of a colour-free material (docs/formats/material.md,
"Colour-free parts") in Blender: the paper scene's cloth baked once with
--parts specular-warp-weft, rendered in Cycles in the scene's own colours and
in a recolouring (weft recoloured, a 4-end warp stripe), each against
`clothbake lookup-render` of that scene with the same material, within the
bound blender.material_routes uses (3 standard deviations of the two
renders' noise, from two seeds each, plus 0.01 systematic); then the weft
colour changed in the panel's property: the applied material follows with
no re-apply (the render changes, and matches lookup-render of a scene in
that colour), and the update's time for a 48-thread warp stripe and a
480-thread weft sequence; then a real WIF written over its colour repeat,
baked over its weave's (written_over_its_colours); a material addressed
per crossing of a real WIF, and its palette edited (addressed_per_crossing),
and one of a WIF whose threads have their own spacings (addressed_uneven).

    blender -b --factory-startup --python-exit-code 1 -P material_colour_free.py -- \\
        CLOTHBAKE_EXE SOURCE_DIR WORK_DIR [MATERIAL_DIR]
"""
import json
import os
import shutil
import sys
import time

import bpy
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from lib.checks import check, run_checks  # noqa: E402
from lib.headless import SOURCE, TMP, argv, enable_addon  # noqa: E402
from lib.images import pixels, rel_rmse, render_still, save_png  # noqa: E402
from lib.noise import Noisy, blocks, within_noise  # noqa: E402
from lib.program import run  # noqa: E402

SPP = 32
SYS = 0.01      # blender.material_routes' systematic part
PAPER = os.path.join(SOURCE, "testscenes", "paper")


def pair(name):
    """A render and its noise (two seeds)."""
    t = time.perf_counter()
    a = render_still(os.path.join(TMP, f"{name}_s1.exr"), 1)
    b = render_still(os.path.join(TMP, f"{name}_s2.exr"), 2)
    print(f"{name}: two renders in {time.perf_counter() - t:.1f} s")
    return Noisy(a, b)


def applied(path, material):
    """The scene imported (SPP samples, no denoising), its cloth on bilinear
    patches, the material applied on the exact route: (the cloth, Apply's
    notes)."""
    from clothbake.blender.headless import bilinear_patches
    from clothbake.blender.material_apply import apply_material
    from clothbake.blender.scene_import import import_scene
    (obj,) = import_scene(path, clear=True, samples=SPP)
    bpy.context.scene.cycles.use_denoising = False
    bilinear_patches(obj)
    _, notes = apply_material(obj, material, route="exact")
    return obj, notes


def compare(what, noisy, reference):
    """within_noise(), with blender.material_routes' systematic part."""
    within_noise(what, noisy, reference, SYS)


def scene_with(name, warp=None, weft=None):
    """The paper scene in its folder's copy, the cloth's colours replaced."""
    folder = os.path.join(TMP, name)
    os.makedirs(folder, exist_ok=True)
    for f in ("scene.json", "cloth.obj"):
        shutil.copy(os.path.join(PAPER, f), folder)
    with open(os.path.join(PAPER, "cloth.json")) as f:
        cloth = json.load(f)
    for family, value in (("warp", warp), ("weft", weft)):
        if value is None:
            continue
        yarn = cloth.setdefault(family, {})
        if isinstance(value[0], list):
            yarn["colors"] = value
        else:
            yarn["color"] = value
    with open(os.path.join(folder, "cloth.json"), "w") as f:
        json.dump(cloth, f, indent=1)
    return os.path.join(folder, "scene.json")


def reference(scene_path, material, name):
    out = os.path.join(TMP, f"ref_{name}.exr")
    run(["lookup-render", scene_path, material, "-o", out, "--spp", "64", "--quiet"])
    return pixels(out)


def main():
    enable_addon()
    from clothbake.blender import material_colours
    from clothbake.blender.headless import bilinear_patches
    from clothbake.blender.material_apply import apply_material
    from clothbake.blender.scene_import import import_scene
    from clothbake.core.material_pack import read_material

    material = argv[3] if len(argv) > 3 else os.path.join(TMP, "material")
    if len(argv) <= 3:
        run(["material", os.path.join(PAPER, "scene.json"), "-o", material, "--texels", "16",
             "--directions", "8", "--light-directions", "6", "--spp", "2",
             "--parts", "specular-warp-weft", "--quiet"])
    info = read_material(material)
    check(info.parts == "specular-warp-weft", f"the material is colour-free ({info.parts})")

    stripe = [[0.7, 0.1, 0.1], [0.7, 0.1, 0.1], [0.1, 0.5, 0.1], [0.9, 0.8, 0.2]]
    cases = [("own", scene_with("own")),
             ("recoloured", scene_with("recoloured", warp=stripe, weft=[0.1, 0.2, 0.6]))]
    sheet = []
    for name, path in cases:
        ref = reference(path, material, name)
        obj, notes = applied(path, material)
        print(name, "notes:", notes)
        got = pair(name)
        compare(f"Cycles, {name} colours, against lookup-render", got, ref)
        save_png([got.image], os.path.join(TMP, f"{name}.png"))
        save_png([ref], os.path.join(TMP, f"ref_{name}.png"))
        sheet += [ref, got.image]

    # The weft colour changed in the panel, no re-apply: the render follows.
    before = sheet[-1]
    obj.clothbake.weft_color = (0.6, 0.5, 0.1)
    print(f"weft colour update: {material_colours.last_refresh['seconds'] * 1e3:.2f} ms")
    ref = reference(scene_with("weft_changed", warp=stripe, weft=[0.6, 0.5, 0.1]), material,
                    "weft_changed")
    got = pair("weft_changed")
    change = rel_rmse(before, got.image)
    check(change > 10 * got.sigma, f"the weft colour's change changes the render (relative "
                                f"{change:.4f}, noise {got.sigma:.4f})")
    compare("Cycles after the weft colour changed, against lookup-render", got, ref)
    save_png([got.image], os.path.join(TMP, "weft_changed.png"))
    sheet += [ref, got.image]

    # Eevee (the GPU textures of the strips and the inputs) follows too.
    from clothbake.blender.render_engines import use_eevee
    scene = bpy.context.scene
    use_eevee(scene, 16)
    e1 = render_still(os.path.join(TMP, "eevee_before.exr"), 1)
    obj.clothbake.weft_color = (0.1, 0.2, 0.6)
    e2 = render_still(os.path.join(TMP, "eevee_after.exr"), 1)
    e_ref = sheet[2]       # lookup-render in weft (0.1, 0.2, 0.6)
    moved = rel_rmse(e1, e2)
    check(moved > 0.3, f"Eevee: the weft colour's change changes the render ({moved:.4f})")
    err = rel_rmse(blocks(e_ref), blocks(e2))
    check(err < 0.05, f"Eevee after the change against lookup-render in that colour, 4x4 "
                      f"blocks: {err:.4f} < 0.05")
    save_png([e1, e2], os.path.join(TMP, "eevee_change.png"))
    scene.render.engine = "CYCLES"
    save_png(sheet, os.path.join(os.environ.get("CLOTHBAKE_SHEET_DIR", TMP),
                                 "material_colour_free.png"))

    # The update's cost: a 48-thread warp stripe, a 480-thread weft sequence.
    rng = np.random.default_rng(1)
    for label, family, n in (("48-thread warp stripe", "warp", 48),
                             ("480-thread weft sequence", "weft", 480)):
        base = json.loads(obj.clothbake.cloth_base)
        for f in ("warp", "weft"):
            base.get(f, {}).pop("colors", None)
        base.setdefault(family, {})["colors"] = rng.uniform(0, 1, (n, 3)).round(3).tolist()
        obj.clothbake.cloth_base = json.dumps(base)
        apply_material(obj, material, route="exact")      # a new length: q changes
        times = []
        for i in range(5):
            obj.clothbake.warp_color = (0.1 * i, 0.3, 0.2)
            times.append(material_colours.last_refresh["seconds"])
        print(f"update for a {label}: {1e3 * min(times):.2f} ms (min of 5), "
              f"{1e3 * max(times):.2f} ms max")
        check(max(times) < 0.1, f"the update for a {label} takes under 100 ms")

    written_over_its_colours(import_scene, bilinear_patches, apply_material, read_material)
    addressed_per_crossing(import_scene, bilinear_patches, apply_material, read_material,
                           material_colours)
    addressed_uneven(import_scene, bilinear_patches, apply_material, read_material)


def paper_scene_with(name, cloth, repeats_per_uv):
    """TMP/name/scene.json: the paper scene's folds, camera and lights with
    `cloth` (a cloth spec, written beside it) at `repeats_per_uv`. Returns
    (folder, the scene as a dict, its path)."""
    folder = os.path.join(TMP, name)
    os.makedirs(folder, exist_ok=True)
    with open(os.path.join(folder, "cloth.json"), "w") as f:
        json.dump(cloth, f)
    with open(os.path.join(PAPER, "scene.json")) as f:
        scene = json.load(f)
    scene["objects"][0].update(mesh=os.path.join(PAPER, "cloth.obj"), cloth="cloth.json",
                               repeats_per_uv=repeats_per_uv)
    path = os.path.join(folder, "scene.json")
    with open(path, "w") as f:
        json.dump(scene, f)
    return folder, scene, path


def written_over_its_colours(import_scene, bilinear_patches, apply_material, read_material):
    """A real WIF written over its colour repeat (Handweaving.net 8452: 84
    ends and 100 picks whose lifts repeat every 28 and 50) bakes the weave's
    repeat, 3 x 2 of them per repeat of the draft as written; the scene's
    repeats_per_uv counts the draft as written (84 ends per UV here), and the
    add-on reads the material at 3 x 2 times it (an anisotropic UV scale):
    Cycles against lookup-render, which maps by the scene's own cloth."""
    cloth = {"name": "hw_8452",
             "weave": {"wif": os.path.join(SOURCE, "testscenes", "wif", "real", "hw_8452.wif")},
             "resolution": {"cells_per_thread": 2}}
    folder, _, path = paper_scene_with("wif", cloth, 1)
    material = os.path.join(folder, "material")
    run(["material", path, "-o", material, "--texels", "16", "--directions", "8",
         "--light-directions", "6", "--spp", "2", "--field-supersample", "1",
         "--parts", "specular-warp-weft", "--quiet"])
    info = read_material(material)
    check(info.written_repeats == (3.0, 2.0),
          f"hw_8452 bakes its weave's repeat, 3 x 2 per draft as written ({info.written_repeats})")
    ref = reference(path, material, "wif")
    obj, notes = applied(path, material)
    print("wif notes:", notes)
    check(not any("depth scale" in n for n in notes), f"no depth-scale note ({notes})")
    got = pair("wif")
    compare("Cycles, a WIF written over its colour repeat, against lookup-render", got, ref)
    save_png([ref, got.image],
             os.path.join(os.environ.get("CLOTHBAKE_SHEET_DIR", TMP), "material_wif_written.png"))


def addressed_per_crossing(import_scene, bilinear_patches, apply_material, read_material,
                           material_colours):
    """A material addressed per crossing (--address crossings) of a real WIF
    (Mac WeaveIt's 62 x 62 twill: 30 classes of crossings, 62 ends per UV
    on the paper scene's folds): Cycles against lookup-render in the draft's
    colours; then a palette colour edited in the panel, no re-apply: the
    render follows, against lookup-render of the object's cloth as edited."""
    wif = os.path.join(SOURCE, "testscenes", "wif", "real", "wi_32twill.wif")
    folder, scene, path = paper_scene_with(
        "addressed", {"name": "wi_32twill", "weave": {"wif": wif}}, 1)
    material = os.path.join(folder, "material")
    run(["material", path, "-o", material, "--address", "crossings", "--texels", "4",
         "--directions", "6", "--light-directions", "6", "--spp", "1", "--context", "1",
         "--quiet"])
    info = read_material(material)
    check(info.address == "crossings" and info.blocks == 30,
          f"the twill is addressed per crossing, 30 blocks ({info.address}, {info.blocks})")
    ref = reference(path, material, "addressed")
    obj, notes = applied(path, material)
    print("addressed notes:", notes)
    got = pair("addressed")
    compare("Cycles, a material addressed per crossing, against lookup-render", got, ref)
    sheet = [ref, got.image]

    # The palette's first colour (a quarter of the ends, a quarter of the
    # picks) turned orange in the panel: the strips follow, no re-apply.
    s = obj.clothbake
    s.wif_palette[0].color = (0.8, 0.35, 0.05)
    print(f"addressed palette update: {material_colours.last_refresh['seconds'] * 1e3:.2f} ms")
    with open(os.path.join(folder, "cloth_edited.json"), "w") as f:
        json.dump(s.wif_inline_spec(), f)
    scene["objects"][0]["cloth"] = "cloth_edited.json"
    edited = os.path.join(folder, "scene_edited.json")
    with open(edited, "w") as f:
        json.dump(scene, f)
    ref2 = reference(edited, material, "addressed_edited")
    got2 = pair("addressed_edited")
    change = rel_rmse(got.image, got2.image)
    check(change > 10 * got2.sigma, f"the palette's change changes the render (relative "
                                 f"{change:.4f}, noise {got2.sigma:.4f})")
    compare("Cycles after a palette colour changed, against lookup-render", got2, ref2)
    sheet += [ref2, got2.image]
    # Eevee reads the same images (its GPU textures: the index and the
    # blocks' grid within its limits).
    from clothbake.blender.render_engines import use_eevee
    scene_bpy = bpy.context.scene
    use_eevee(scene_bpy, 16)
    eevee = render_still(os.path.join(TMP, "addressed_eevee.exr"), 1)
    scene_bpy.render.engine = "CYCLES"
    err = rel_rmse(blocks(ref2), blocks(eevee))
    check(err < 0.05, f"Eevee, the addressed material after the palette edit, against "
                      f"lookup-render, 4x4 blocks: {err:.4f} < 0.05")
    sheet.append(eevee)
    save_png(sheet,
             os.path.join(os.environ.get("CLOTHBAKE_SHEET_DIR", TMP), "material_addressed.png"))


def addressed_uneven(import_scene, bilinear_patches, apply_material, read_material):
    """A material addressed per crossing of a real WIF whose threads have
    their own spacings (d2w_zeros.wif: 5 ends in 4 spacings, 6 picks in 6):
    the nodes place a point among them through the pack's span image;
    Cycles against lookup-render."""
    wif = os.path.join(SOURCE, "testscenes", "wif", "real", "d2w_zeros.wif")
    folder, _, path = paper_scene_with(
        "uneven", {"name": "d2w_zeros", "weave": {"wif": wif}}, 4)
    material = os.path.join(folder, "material")
    t = time.perf_counter()
    run(["material", path, "-o", material, "--address", "crossings", "--texels", "2",
         "--directions", "4", "--light-directions", "4", "--spp", "1", "--context", "1",
         "--quiet"])
    print(f"uneven: material baked in {time.perf_counter() - t:.1f} s")
    info = read_material(material)
    check(info.even == (False, False), f"d2w_zeros's ends and picks are unevenly spaced "
                                       f"({info.even})")
    ref = reference(path, material, "uneven")
    applied(path, material)
    got = pair("uneven")
    compare("Cycles, addressed on unevenly spaced threads, against lookup-render", got, ref)
    save_png([ref, got.image],
             os.path.join(os.environ.get("CLOTHBAKE_SHEET_DIR", TMP), "material_uneven.png"))


run_checks(main)
