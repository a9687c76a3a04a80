"""A colour-free material's yarn colours in Blender (docs/formats/material.md,
"Colour-free parts"): the object's cloth colours into its node group, live.

Per object the material has two strip images (one per family, its own,
owner + 1 and owner - 1 strips: core/yarn_colours.py's layout) inside its own node group, and the group node's
colour inputs (Warp colour, Weft colour, Warp / Weft per thread). The colours
are the object's cloth settings (obj.clothbake): the family colours, and the
per-thread colours of a WIF cloth (its palette as edited) or of a cloth spec
with warp.colors / weft.colors; an object that is no cloth takes the
material's baked-with colours (manifest cloth.colors).

`refresh(obj)` rewrites the strips' pixels and the inputs' values, in numpy
and with no program run: the panel's colour fields call it on every change
(props_cloth.py), so an applied material follows at once in Cycles, Eevee and
Material Preview. What the strips are made from (thread centres, repeat,
texels, levels, q) is kept on the material (STRIPS_KEY, JSON), so a refresh
reads no file. A sequence of another length changes q: the strip is then left
as it was, with a note, until Apply material again.
"""
import json
import time

import bpy
import numpy as np

from ..core import wif_cloth, yarn_colours
from ..core.cloth_fields import WIF
from ..core.errors import ClothbakeError
from ..core.material_manifest import CROSSINGS, FAMILIES
from .material_nodes import Strips

STRIPS_KEY = "clothbake_strips"   # on the material: JSON of what its strips are made from
last_refresh = {}                 # the last refresh's timing (seconds) and notes, for tests


def object_colours(obj, baked):
    """{family: (colour, per-thread colours or [])} of `obj`'s cloth settings,
    or the material's baked-with colours `baked` (MaterialInfo.colors) when
    obj is no cloth object."""
    s = getattr(obj, "clothbake", None)
    if s is None or not s.is_cloth:
        return {f: (list(baked[f]["color"]), [list(c) for c in baked[f]["colors"]])
                for f in FAMILIES}
    if s.weave == WIF and s.wif_draft:
        from . import wif_preview   # its parse of the draft, cached
        d = wif_preview.draft(s)
        palette = [list(c.color) for c in s.wif_palette]
        return {"warp": (list(s.warp_color), wif_cloth.thread_colors(palette,
                                                                     d["warp_color_index"])),
                "weft": (list(s.weft_color), wif_cloth.thread_colors(palette,
                                                                     d["weft_color_index"]))}
    try:
        base = json.loads(s.cloth_base) if s.cloth_base else {}
    except ValueError:
        base = {}
    out = {}
    for f in FAMILIES:
        yarn = base.get(f) if isinstance(base, dict) and isinstance(base.get(f), dict) else {}
        seq = yarn.get("colors") if isinstance(yarn.get("colors"), list) else []
        out[f] = (list(getattr(s, f"{f}_color")), [list(c) for c in seq])
    return out


def _strip_image(name, width, height):
    """A float RGBA image of data (no colour transform), made or resized."""
    image = bpy.data.images.get(name)
    if image is not None and tuple(image.size) != (width, height):
        bpy.data.images.remove(image)
        image = None
    if image is None:
        image = bpy.data.images.new(name, width=width, height=height, alpha=True,
                                    float_buffer=True, is_data=True)
        image.colorspace_settings.name = "Non-Color"
        image.alpha_mode = "CHANNEL_PACKED"
        if hasattr(image, "use_half_precision"):
            image.use_half_precision = False
    return image


def make_strips(obj, info):
    """The strips of `obj` for the colour-free material `info` (MaterialInfo,
    parts SWF): images sized for its colours (filled by refresh), and the
    JSON the material keeps (STRIPS_KEY). Returns (Strips, json text).
    Raises ClothbakeError when a strip would not fit an image."""
    colours = object_colours(obj, info.colors)
    keep = {"texels": info.texels, "levels": info.levels, "baked": info.colors}
    made = {}
    for axis, f in enumerate(FAMILIES):
        colour, seq = colours[f]
        centres = info.centres_mm[f]
        texels, levels = info.texels, info.levels
        if info.address == CROSSINGS:
            # A tap lies in one crossing and takes its threads' colours:
            # one column a thread (material_nodes.address.crossing_address counts
            # the taps' crossings, whatever the threads' spacings: column c
            # is thread c of the colours' repeat), and one level.
            n = len(centres)
            texels, levels = n, 1
            centres = [(i + 0.5) * info.repeat_mm[axis] / n for i in range(n)]
        q = yarn_colours.strip_repeats(len(centres), len(seq) or 1)
        width, rows, height = yarn_colours.strip_layout(q, texels, levels)
        if height > 16384:
            raise ClothbakeError(f"{f} colours: {len(seq)} per-thread colours over "
                                 f"{len(centres)} threads repeat every {q} material repeats, "
                                 f"a colour strip of {q * texels} texels: too large for "
                                 "Blender's images; bake the material at fewer texels")
        image = _strip_image(f"clothbake {f} colours {obj.name}", width, height)
        made[f] = (image, q, rows)
        keep[f] = {"centres_mm": centres, "repeat_mm": info.repeat_mm[axis], "q": q,
                   "sequence": len(seq), "width": width, "rows": rows, "image": image.name,
                   "texels": texels, "levels": levels}
    strips = Strips(made["warp"][0], made["weft"][0], made["warp"][1], made["weft"][1],
                    made["warp"][2], made["weft"][2])
    return strips, json.dumps(keep)


def _group_node(material):
    if material is None or not material.use_nodes:
        return None
    return next((n for n in material.node_tree.nodes if n.type == "GROUP" and n.node_tree and
                 "Warp colour" in n.inputs), None)


def refresh_material(material, obj, baked=None):
    """Writes `obj`'s colours into `material`'s strips and group inputs.
    Returns notes (a sequence whose length no longer fits the strip)."""
    keep = json.loads(material[STRIPS_KEY])
    if baked is None:
        baked = keep.get("baked")
    colours = object_colours(obj, baked)
    node = _group_node(material)
    notes = []
    for f in FAMILIES:
        colour, seq = colours[f]
        k = keep[f]
        q = yarn_colours.strip_repeats(len(k["centres_mm"]), len(seq) or 1)
        if node is not None:
            node.inputs[f"{f.capitalize()} colour"].default_value = tuple(colour) + (1.0,)
            node.inputs[f"{f.capitalize()} per thread"].default_value = 1.0 if seq else 0.0
        image = bpy.data.images.get(k["image"])
        if image is None or q != k["q"]:
            if seq:
                notes.append(f"'{obj.name}': its {f} colour sequence ({len(seq)} colours) "
                             f"repeats otherwise than when the material was applied: apply "
                             "the material again")
            continue
        strips = yarn_colours.family_strips(k["centres_mm"], k["repeat_mm"],
                                            yarn_colours.family_colours(colour, seq),
                                            k.get("texels", keep["texels"]),
                                            k.get("levels", keep["levels"]))
        px = yarn_colours.strip_pixels(strips, k["width"], k["rows"])
        image.pixels.foreach_set(px.ravel())
        image.update()
    if node is not None:
        # The inputs' new values reach Cycles and Eevee through the depsgraph.
        material.node_tree.update_tag()
    return notes


def refresh(obj):
    """Every colour-free material on `obj` follows its cloth colours. Timed
    (last_refresh["seconds"])."""
    start = time.perf_counter()
    notes = []
    data = getattr(obj, "data", None)
    for material in getattr(data, "materials", ()) or ():
        if material is not None and STRIPS_KEY in material:
            notes += refresh_material(material, obj)
    last_refresh.update(seconds=time.perf_counter() - start, notes=notes, object=obj.name)
    return notes


def pack_strips(materials=None):
    """Packs every colour strip into the .blend (save_pre: generated pixels
    are not saved otherwise)."""
    for material in materials or bpy.data.materials:
        if STRIPS_KEY not in material:
            continue
        keep = json.loads(material[STRIPS_KEY])
        for f in FAMILIES:
            image = bpy.data.images.get(keep[f]["image"])
            if image is not None and (image.is_dirty or not image.packed_file):
                image.pack()


def strips_pixels(material):
    """The strips' pixels as numpy arrays (height, W, 4), for the tests."""
    keep = json.loads(material[STRIPS_KEY])
    out = {}
    for f in FAMILIES:
        image = bpy.data.images[keep[f]["image"]]
        w, h = image.size
        px = np.empty(w * h * 4, np.float32)
        image.pixels.foreach_get(px)
        out[f] = px.reshape(h, w, 4)
    return out


@bpy.app.handlers.persistent
def _save_pre(*_):
    pack_strips()


def register_extra():
    if _save_pre not in bpy.app.handlers.save_pre:
        bpy.app.handlers.save_pre.append(_save_pre)


def unregister_extra():
    if _save_pre in bpy.app.handlers.save_pre:
        bpy.app.handlers.save_pre.remove(_save_pre)


CLASSES = ()
