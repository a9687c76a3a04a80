"""The drawdown of a WIF cloth as an icon for the panel: one ImagePreview per
object in a bpy.utils.previews collection, its pixels written directly from
the draft and the palette as edited (core/wif_cloth.drawdown_pixels), and
remade when either changes.

Measured in Blender 3.4.1: a preview's pixels are 8-bit and drawn with no
colour management (so they are display sRGB values), row 0 at the bottom;
`template_icon(icon_value=..., scale=s)` draws it in a square of s x 20 px,
keeping its aspect; `icon_id` is 0 in background mode (no icons without a
window), so the panel is checked under Xvfb (tests/blender/ui_wif_panel.py).
"""
import json

import bpy
import bpy.utils.previews

from ..core import wif_cloth

_collection = None
_made = {}       # object name -> (key of what the preview shows, preview name)
_parsed = {}     # hash of a compact draft string -> (string, draft, warp_up rows)
_serial = [0]
# What the panel drew last, per object name: {"icon_id", "image_size", "block"}
# (read by the tests: the panel's draw has no other output).
drawn = {}


def _parse(draft_text):
    """(compact draft dict, warp_up rows) of a wif_draft string, parsed once:
    the panel redraws often, and a 641 x 641 draft's text is 460 kB (17 ms
    to parse)."""
    key = hash(draft_text)
    hit = _parsed.get(key)
    if hit is None or hit[0] != draft_text:
        d = json.loads(draft_text)
        hit = (draft_text, d, wif_cloth.warp_up_rows(d))
        _parsed.clear()  # the active object's draft is the one drawn
        _parsed[key] = hit
    return hit[1], hit[2]


def draft(settings):
    """The compact draft of `settings` (obj.clothbake), or None; parsed once."""
    return _parse(settings.wif_draft)[0] if settings.wif_draft else None


def preview(settings):
    """The ImagePreview of `settings` (obj.clothbake)'s drawdown in its
    current palette, or None when it has no draft."""
    global _collection
    if not settings.wif_draft:
        return None
    if _collection is None:
        _collection = bpy.utils.previews.new()
    palette = [tuple(c.color) for c in settings.wif_palette]
    key = (hash(settings.wif_draft), tuple(palette))
    name = settings.id_data.name_full
    made = _made.get(name)
    if made is not None and made[0] == key and made[1] in _collection:
        return _collection[made[1]]
    d, rows = _parse(settings.wif_draft)
    warp = wif_cloth.thread_colors(palette, d["warp_color_index"])
    weft = wif_cloth.thread_colors(palette, d["weft_color_index"])
    block = wif_cloth.drawdown_block(d["ends"], d["picks"])
    width, height, pixels = wif_cloth.drawdown_pixels(rows, warp, weft, block)
    # A new preview per change: an icon's GPU texture is made once, so
    # rewriting a drawn preview's pixels would not show.
    if made is not None and made[1] in _collection:
        del _collection[made[1]]
    _serial[0] += 1
    pname = f"{name}#{_serial[0]}"
    prev = _collection.new(pname)
    prev.image_size = (width, height)
    prev.image_pixels_float = pixels
    _made[name] = (key, pname)
    return prev


CLASSES = ()


def unregister_extra():
    global _collection
    if _collection is not None:
        bpy.utils.previews.remove(_collection)
    _collection = None
    _made.clear()
    _parsed.clear()
    drawn.clear()
