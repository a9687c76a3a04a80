#!/usr/bin/python3
"""An independent reading of a WIF (Weaving Information File 1.1) draft.

This is the test suite's reference for clothbake's C++ WIF reader. It follows
the reading rules of clothbake's WIF contract (restated below) and the
WIF 1.1 specification (Ravi Nielsen, April 20 1997); it shares no code with
the C++ reader. Debian python3 and numpy only.

Reading rules (the contract):
- INI-like: [SECTION] headers and key=value lines. Section and key names are
  case-insensitive; spaces around '=' and around values are ignored; ';'
  starts a comment (a whole line, or after a value); blank lines are ignored;
  booleans yes/true/1/on and no/false/0/off. Sections other than the ones
  read here (private sections, [NOTES], ...) are ignored.
- [WARP] Threads = ends, [WEFT] Threads = picks; both required.
- [WEAVING] Shafts, Treadles; Rising Shed defaults to yes when absent.
- [THREADING] end=shaft[,shaft...]; 0 or empty lifts nothing; an end with no
  line is on no shaft.
- [TIEUP] treadle=shaft[,shaft...]; a treadle with no line ties nothing.
- [TREADLING] pick=treadle[,treadle...]; 0/empty = no treadle.
- [LIFTPLAN] pick=shaft[,shaft...]; if the section exists it is used and
  [TREADLING]/[TIEUP] are ignored.
- The shafts listed for a pick: the union of its treadles' tie-up rows, or
  its liftplan row.
- Rising shed: end e is up at pick p iff e is on at least one listed shaft.
  Sinking shed: the listed shafts sink; e is up iff e is on at least one
  shaft and none of its shafts is listed. An end on no shaft is never up.
- Colours: [COLOR PALETTE] Range=lo,hi (default 0,255); [COLOR TABLE]
  index=r,g,b; v -> (v-lo)/(hi-lo) -> sRGB EOTF -> linear. Thread colour:
  [WARP COLORS] end=index, else [WARP] Color=index, else clothbake's default
  (warp linear 0.60,0.09,0.08; weft 0.55,0.42,0.10).
  (WIF 1.1: [WARP] Color holds "1 or 4 integers" (index[,R,G,B]) and a
  [WARP COLORS] line may be "index,R,G,B" whose RGB "should be ignored";
  only the first integer is read.)
- Sizes: [WARP] Units = centimeters|inches|decipoints (default centimeters);
  Spacing, Thickness; per thread [WARP SPACING], [WARP THICKNESS].

Errors (WifError, naming file, section and line): a shaft above Shafts, a
treadle above Treadles, a colour index missing from the table, a missing
Threads, a non-numeric entry.

Use:  python3 wif_reference.py FILE.wif --json OUT.json [--features]
"""

import json
import math
import re
import sys

import numpy as np

DEFAULT_WARP_LINEAR = (0.60, 0.09, 0.08)
DEFAULT_WEFT_LINEAR = (0.55, 0.42, 0.10)

MM_PER_UNIT = {
    "centimeters": 10.0,
    "inches": 25.4,
    "decipoints": 25.4 / 720.0,
}

TRUE_WORDS = {"yes", "true", "1", "on"}
FALSE_WORDS = {"no", "false", "0", "off"}


class WifError(Exception):
    pass


def srgb_eotf(c):
    """IEC 61966-2-1 electro-optical transfer: display value in [0,1] -> linear."""
    if c <= 0.04045:
        return c / 12.92
    return ((c + 0.055) / 1.055) ** 2.4


class Entry:
    __slots__ = ("value", "line")

    def __init__(self, value, line):
        self.value = value
        self.line = line


class WifFile:
    """The sections of a WIF file: {SECTION: {KEY: Entry}} (upper-cased names).

    A duplicated key keeps its first value (the WIF spec calls duplicates an
    error that readers must survive; which one wins is not specified), and
    each duplicate is recorded in self.duplicates."""

    def __init__(self, path):
        self.path = path
        self.sections = {}
        self.section_line = {}
        self.duplicates = []
        with open(path, "rb") as f:
            raw = f.read()
        text = raw.decode("latin-1")
        current = None
        for lineno, line in enumerate(text.splitlines(), start=1):
            s = line.strip()
            if not s or s.startswith(";"):
                continue
            if s.startswith("["):
                end = s.find("]")
                if end < 0:
                    current = None
                    continue
                name = " ".join(s[1:end].split()).upper()
                current = name
                if name not in self.sections:
                    self.sections[name] = {}
                    self.section_line[name] = lineno
                continue
            if current is None:
                continue  # text before the first section
            eq = s.find("=")
            if eq < 0:
                continue  # not a key line
            key = " ".join(s[:eq].split()).upper()
            value = s[eq + 1:]
            semi = value.find(";")
            if semi >= 0:
                value = value[:semi]
            value = value.strip()
            sec = self.sections[current]
            if key in sec:
                self.duplicates.append((current, key, lineno))
                continue
            sec[key] = Entry(value, lineno)

    def has(self, section):
        return section in self.sections

    def get(self, section, key):
        return self.sections.get(section, {}).get(key.upper())

    def where(self, section, entry):
        return "%s: [%s] line %d" % (self.path, section, entry.line)


def _int(wif, section, entry, text=None):
    t = entry.value if text is None else text
    t = t.strip()
    if not re.fullmatch(r"[+-]?\d+", t):
        raise WifError("%s: non-numeric entry %r" % (wif.where(section, entry), t))
    return int(t)


def _float(wif, section, entry):
    t = entry.value.strip()
    try:
        v = float(t)
    except ValueError:
        raise WifError("%s: non-numeric entry %r" % (wif.where(section, entry), t))
    if not math.isfinite(v):
        raise WifError("%s: non-finite entry %r" % (wif.where(section, entry), t))
    return v


def _int_list(wif, section, entry):
    """'1,5' -> [1, 5]; '' -> []; zeros are dropped (they lift nothing)."""
    out = []
    t = entry.value.strip()
    if t == "":
        return out
    for part in t.split(","):
        part = part.strip()
        if part == "":
            continue
        v = _int(wif, section, entry, part)
        if v < 0:
            raise WifError("%s: negative entry %d" % (wif.where(section, entry), v))
        if v != 0:
            out.append(v)
    return out


def _bool(wif, section, entry):
    t = entry.value.strip().lower()
    if t in TRUE_WORDS:
        return True
    if t in FALSE_WORDS:
        return False
    raise WifError("%s: not a boolean %r" % (wif.where(section, entry), entry.value))


def _thread_index(wif, section, key, entry, count):
    """The thread / treadle number of a data-section key, or None if beyond count."""
    if not re.fullmatch(r"\d+", key):
        raise WifError("%s: key %r is not a number" % (wif.where(section, entry), key))
    n = int(key)
    if n < 1:
        raise WifError("%s: key %d below 1" % (wif.where(section, entry), n))
    return n


def read_wif(path):
    wif = WifFile(path)
    r = {"source": path, "duplicates": list(wif.duplicates), "ignored": []}

    prog = wif.get("WIF", "Source Program")
    r["source_program"] = prog.value if prog is not None else ""

    def threads(section):
        e = wif.get(section, "Threads")
        if e is None:
            raise WifError("%s: [%s] has no Threads" % (path, section))
        n = _int(wif, section, e)
        if n < 1:
            raise WifError("%s: Threads=%d" % (wif.where(section, e), n))
        return n

    ends = threads("WARP")
    picks = threads("WEFT")

    def weaving_int(key):
        e = wif.get("WEAVING", key)
        if e is None or e.value == "":
            return None
        return _int(wif, "WEAVING", e)

    shafts = weaving_int("Shafts")
    treadles = weaving_int("Treadles")
    shed_e = wif.get("WEAVING", "Rising Shed")
    rising = True if shed_e is None or shed_e.value == "" else _bool(wif, "WEAVING", shed_e)

    def check_shaft(section, entry, s):
        if shafts is not None and s > shafts:
            raise WifError("%s: shaft %d above Shafts=%d" % (wif.where(section, entry), s, shafts))

    def check_treadle(section, entry, t):
        if treadles is not None and t > treadles:
            raise WifError("%s: treadle %d above Treadles=%d" % (wif.where(section, entry), t, treadles))

    # Threading: per end the set of its shafts.
    threading = [set() for _ in range(ends)]
    for key, e in wif.sections.get("THREADING", {}).items():
        n = _thread_index(wif, "THREADING", key, e, ends)
        lst = _int_list(wif, "THREADING", e)
        for s in lst:
            check_shaft("THREADING", e, s)
        if n > ends:
            r["ignored"].append("[THREADING] %d beyond Threads=%d" % (n, ends))
            continue
        threading[n - 1].update(lst)

    # The shafts listed for every pick.
    lifted = [set() for _ in range(picks)]
    use_liftplan = wif.has("LIFTPLAN")
    if use_liftplan:
        for key, e in wif.sections["LIFTPLAN"].items():
            n = _thread_index(wif, "LIFTPLAN", key, e, picks)
            lst = _int_list(wif, "LIFTPLAN", e)
            for s in lst:
                check_shaft("LIFTPLAN", e, s)
            if n > picks:
                r["ignored"].append("[LIFTPLAN] %d beyond Threads=%d" % (n, picks))
                continue
            lifted[n - 1].update(lst)
        tieup = {}
        treadling = None
    else:
        tieup = {}
        for key, e in wif.sections.get("TIEUP", {}).items():
            t = _thread_index(wif, "TIEUP", key, e, None)
            lst = _int_list(wif, "TIEUP", e)
            for s in lst:
                check_shaft("TIEUP", e, s)
            if treadles is not None and t > treadles:
                # Fiberworks PCW 4.2 writes tie-up rows for treadles beyond
                # Treadles (its tabby treadles); no pick can name them (that
                # is refused below), so the row is unused, not an error.
                r["ignored"].append("[TIEUP] %d beyond Treadles=%d" % (t, treadles))
                continue
            tieup[t] = set(lst)
        treadling = [[] for _ in range(picks)]
        for key, e in wif.sections.get("TREADLING", {}).items():
            n = _thread_index(wif, "TREADLING", key, e, picks)
            lst = _int_list(wif, "TREADLING", e)
            for t in lst:
                check_treadle("TREADLING", e, t)
            if n > picks:
                r["ignored"].append("[TREADLING] %d beyond Threads=%d" % (n, picks))
                continue
            treadling[n - 1] = lst
            for t in lst:
                lifted[n - 1] |= tieup.get(t, set())

    # The drawdown.
    up = np.zeros((picks, ends), dtype=bool)
    for p in range(picks):
        listed = lifted[p]
        for e in range(ends):
            on = threading[e]
            if not on:
                continue
            if rising:
                up[p, e] = bool(on & listed)
            else:
                up[p, e] = not (on & listed)

    # Colours.
    lo, hi = 0, 255
    rng = wif.get("COLOR PALETTE", "Range")
    if rng is not None and rng.value != "":
        parts = [x.strip() for x in rng.value.split(",")]
        if len(parts) != 2:
            raise WifError("%s: Range needs two values, got %r" % (wif.where("COLOR PALETTE", rng), rng.value))
        lo = _int(wif, "COLOR PALETTE", rng, parts[0])
        hi = _int(wif, "COLOR PALETTE", rng, parts[1])
        if hi <= lo:
            raise WifError("%s: Range %d,%d is empty" % (wif.where("COLOR PALETTE", rng), lo, hi))
    table = {}
    for key, e in wif.sections.get("COLOR TABLE", {}).items():
        idx = _thread_index(wif, "COLOR TABLE", key, e, None)
        parts = [x.strip() for x in e.value.split(",")]
        if len(parts) != 3:
            raise WifError("%s: colour needs r,g,b, got %r" % (wif.where("COLOR TABLE", e), e.value))
        rgb = []
        for x in parts:
            v = _int(wif, "COLOR TABLE", e, x)
            c = (v - lo) / float(hi - lo)
            rgb.append(srgb_eotf(c))
        table[idx] = (tuple(int(x) for x in parts), tuple(rgb))

    def first_int(section, e):
        t = e.value.split(",")[0].strip()
        return _int(wif, section, e, t)

    def lookup(section, e, idx):
        if idx not in table:
            raise WifError("%s: colour index %d missing from [COLOR TABLE]" % (wif.where(section, e), idx))
        return table[idx]

    def family_colours(family, count, default_linear):
        base = wif.get(family, "Color")
        if base is not None and base.value != "":
            bidx = first_int(family, base)
            bcol = lookup(family, base, bidx)[1]
            bsrc = ("table", bidx)
        else:
            bcol = default_linear
            bsrc = ("default", None)
        cols = [bcol] * count
        srcs = [bsrc] * count
        sec = family + " COLORS"
        for key, e in wif.sections.get(sec, {}).items():
            n = _thread_index(wif, sec, key, e, count)
            if e.value == "":
                continue  # an empty line keeps the default
            idx = first_int(sec, e)
            col = lookup(sec, e, idx)[1]
            if n > count:
                r["ignored"].append("[%s] %d beyond Threads=%d" % (sec, n, count))
                continue
            cols[n - 1] = col
            srcs[n - 1] = ("table", idx)
        return cols, srcs

    warp_cols, warp_src = family_colours("WARP", ends, DEFAULT_WARP_LINEAR)
    weft_cols, weft_src = family_colours("WEFT", picks, DEFAULT_WEFT_LINEAR)

    palette = []
    pal_index = {}

    def pidx(c):
        if c not in pal_index:
            pal_index[c] = len(palette)
            palette.append(c)
        return pal_index[c]

    warp_ci = [pidx(c) for c in warp_cols]
    weft_ci = [pidx(c) for c in weft_cols]

    # Sizes (mm). None where the file says nothing.
    def family_sizes(family, count, key, section):
        units_e = wif.get(family, "Units")
        units = "centimeters"
        if units_e is not None and units_e.value != "":
            units = units_e.value.strip().lower()
            if units not in MM_PER_UNIT:
                raise WifError("%s: unknown Units %r" % (wif.where(family, units_e), units_e.value))
        k = MM_PER_UNIT[units]
        base_e = wif.get(family, key)
        base = None
        if base_e is not None and base_e.value != "":
            base = _float(wif, family, base_e) * k
        vals = [base] * count
        for tkey, e in wif.sections.get(section, {}).items():
            n = _thread_index(wif, section, tkey, e, count)
            if e.value == "":
                continue
            v = _float(wif, section, e) * k
            if n > count:
                continue
            vals[n - 1] = v
        return vals

    r.update({
        "ends": ends,
        "picks": picks,
        "shafts": shafts,
        "treadles": treadles,
        "rising_shed": rising,
        "rising_shed_given": shed_e is not None,
        "uses_liftplan": use_liftplan,
        "range": [lo, hi],
        "warp_up": up,
        "warp_colors": warp_cols,
        "weft_colors": weft_cols,
        "warp_color_source": warp_src,
        "weft_color_source": weft_src,
        "palette": palette,
        "warp_color_index": warp_ci,
        "weft_color_index": weft_ci,
        "warp_spacing_mm": family_sizes("WARP", ends, "Spacing", "WARP SPACING"),
        "weft_spacing_mm": family_sizes("WEFT", picks, "Spacing", "WEFT SPACING"),
        "warp_width_mm": family_sizes("WARP", ends, "Thickness", "WARP THICKNESS"),
        "weft_width_mm": family_sizes("WEFT", picks, "Thickness", "WEFT THICKNESS"),
        "threading": threading,
        "lifted": lifted,
        "tieup": tieup,
        "treadling": treadling,
        "has_warp_colors_section": wif.has("WARP COLORS"),
        "has_weft_colors_section": wif.has("WEFT COLORS"),
        "has_per_thread_spacing": wif.has("WARP SPACING") or wif.has("WEFT SPACING"),
        "has_per_thread_thickness": wif.has("WARP THICKNESS") or wif.has("WEFT THICKNESS"),
    })
    return r


def features(r):
    """What a draft exercises, for PROVENANCE.md and the test's log."""
    up = r["warp_up"]
    f = {}
    f["ends"] = r["ends"]
    f["picks"] = r["picks"]
    f["shafts"] = r["shafts"]
    f["treadles"] = r["treadles"]
    f["mode"] = "liftplan" if r["uses_liftplan"] else "treadling"
    f["shed"] = ("rising" if r["rising_shed"] else "sinking") + ("" if r["rising_shed_given"] else " (key absent)")
    f["range"] = "%d-%d" % tuple(r["range"])
    f["multi_shaft_ends"] = sum(1 for t in r["threading"] if len(t) > 1)
    f["unthreaded_ends"] = sum(1 for t in r["threading"] if len(t) == 0)
    f["empty_picks"] = sum(1 for l in r["lifted"] if len(l) == 0)
    if r["treadling"] is not None:
        f["multi_treadle_picks"] = sum(1 for t in r["treadling"] if len(t) > 1)
        used = set(t for row in r["treadling"] for t in row)
        f["treadles_without_tieup"] = sorted(t for t in used if not r["tieup"].get(t))
    f["picks_all_warp_up"] = int(np.sum(up.all(axis=1)))
    f["picks_all_weft_up"] = int(np.sum((~up).all(axis=1)))
    f["ends_all_up"] = int(np.sum(up.all(axis=0)))
    f["ends_all_down"] = int(np.sum((~up).all(axis=0)))
    f["warp_colours"] = len(set(r["warp_colors"]))
    f["weft_colours"] = len(set(r["weft_colors"]))
    f["warp_colors_section"] = r["has_warp_colors_section"]
    f["weft_colors_section"] = r["has_weft_colors_section"]
    f["per_thread_spacing"] = r["has_per_thread_spacing"]
    f["per_thread_thickness"] = r["has_per_thread_thickness"]
    f["default_colour_used"] = any(s[0] == "default" for s in r["warp_color_source"] + r["weft_color_source"])
    f["duplicates"] = len(r["duplicates"])
    f["ignored"] = r["ignored"][:5]
    return f


def to_json(r):
    return {
        "ends": r["ends"],
        "picks": r["picks"],
        "warp_up": [[int(v) for v in row] for row in r["warp_up"]],
        "warp_colors": [list(c) for c in r["warp_colors"]],
        "weft_colors": [list(c) for c in r["weft_colors"]],
        "palette": [list(c) for c in r["palette"]],
        "warp_color_index": r["warp_color_index"],
        "weft_color_index": r["weft_color_index"],
        "warp_spacing_mm": r["warp_spacing_mm"],
        "weft_spacing_mm": r["weft_spacing_mm"],
        "warp_width_mm": r["warp_width_mm"],
        "weft_width_mm": r["weft_width_mm"],
        "source": r["source"],
        "source_program": r["source_program"],
    }


def main(argv):
    import argparse
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("wif")
    ap.add_argument("--json", help="write draft.json-shaped output here")
    ap.add_argument("--features", action="store_true", help="print what the draft exercises")
    a = ap.parse_args(argv)
    try:
        r = read_wif(a.wif)
    except WifError as e:
        print("error: %s" % e, file=sys.stderr)
        return 1
    if a.json:
        with open(a.json, "w") as f:
            json.dump(to_json(r), f)
    if a.features or not a.json:
        print(json.dumps({"file": a.wif, "program": r["source_program"], **features(r)}))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
