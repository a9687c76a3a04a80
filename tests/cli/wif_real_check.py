#!/usr/bin/python3
"""cli.wif_real: clothbake's reading of real WIF files against an independent one.

For every testscenes/wif/real/*.wif (any case of the extension):
  1. `clothbake draft FILE -o TMP/draft_X`: draft.json's ends, picks, warp_up
     (exact), warp/weft colours (1e-6), the palette indices (palette[index]
     = the thread's colour) and, where the file states them, spacing and
     width in mm (relative 1e-6) must equal tests/lib/wif_reference.py's.
  2. `clothbake volume SPEC -o TMP/vol_X` on a small spec naming the file:
     crossings.exr (ends x picks, row 0 = pick 1) must say, at every
     crossing, family A = 1 where the reference has the warp up and 2 where
     the weft is up, and RGB = that thread's linear colour (relative 1e-5).
Before any of that, self-checks: the comparisons must catch one flipped
cell, one nudged colour and one flipped crossing, and the reference reader
must pass a few facts known by hand; otherwise the test fails rather than
passing blind.

Use: wif_real_check.py --clothbake BIN --repo ROOT --tmp DIR [--no-volume]
"""

import argparse
import json
import os
import subprocess
import sys

import numpy as np

COLOUR_ABS = 1e-6     # draft.json colours
EXR_REL = 1e-5        # crossings.exr RGB, relative
EXR_ABS = 1e-7        # floor for colours near 0
SIZE_REL = 1e-6
LARGE = 200           # above this many ends or picks: cells_per_thread 2


def load_reference(repo):
    sys.path.insert(0, os.path.join(repo, "tests", "lib"))
    import wif_reference  # noqa: E402
    return wif_reference


# ---------------------------------------------------------------- comparisons

def compare_draft(ref, dj, note):
    """Mismatch messages between the reference reading and a draft.json dict."""
    bad = []
    if dj.get("ends") != ref["ends"] or dj.get("picks") != ref["picks"]:
        bad.append("size %sx%s, reference %dx%d" % (dj.get("ends"), dj.get("picks"), ref["ends"], ref["picks"]))
        return bad
    E, P = ref["ends"], ref["picks"]
    try:
        up = np.array(dj["warp_up"], dtype=np.int64)
    except Exception as e:  # ragged or missing
        bad.append("warp_up unreadable: %s" % e)
        return bad
    if up.shape != (P, E):
        bad.append("warp_up shape %s, reference %s" % (up.shape, (P, E)))
        return bad
    diff = np.argwhere(up.astype(bool) != ref["warp_up"])
    if len(diff):
        p, e = diff[0]
        bad.append("warp_up differs at %d crossings; first pick %d end %d: clothbake %s, reference %s"
                   % (len(diff), p + 1, e + 1, "warp" if up[p, e] else "weft",
                      "warp" if ref["warp_up"][p, e] else "weft"))
    for fam, n in (("warp", E), ("weft", P)):
        key = fam + "_colors"
        try:
            got = np.array(dj[key], dtype=np.float64)
        except Exception as e:
            bad.append("%s unreadable: %s" % (key, e))
            continue
        want = np.array(ref[key], dtype=np.float64)
        if got.shape != want.shape:
            bad.append("%s shape %s, reference %s" % (key, got.shape, want.shape))
            continue
        d = np.abs(got - want).max(axis=1)
        wrong = np.nonzero(d > COLOUR_ABS)[0]
        if len(wrong):
            i = wrong[0]
            bad.append("%s differ at %d threads; first %s %d: clothbake %s, reference %s"
                       % (key, len(wrong), fam, i + 1, got[i].tolist(), want[i].tolist()))
        # palette + index must reproduce the per-thread colours
        pal = dj.get("palette")
        idx = dj.get(fam + "_color_index")
        if pal is None or idx is None:
            bad.append("%s: palette or %s_color_index missing" % (note, fam))
        else:
            pal = np.array(pal, dtype=np.float64)
            idx = np.array(idx, dtype=np.int64)
            if idx.shape != (n,) or (idx < 0).any() or (len(idx) and idx.max() >= len(pal)):
                bad.append("%s_color_index out of the palette" % fam)
            else:
                d2 = np.abs(pal[idx] - got).max(axis=1) if len(idx) else np.zeros(0)
                if (d2 > COLOUR_ABS).any():
                    i = int(np.nonzero(d2 > COLOUR_ABS)[0][0])
                    bad.append("palette[%s_color_index[%d]] is not %s %d's colour" % (fam, i, fam, i + 1))
    for key in ("warp_spacing_mm", "weft_spacing_mm", "warp_width_mm", "weft_width_mm"):
        want = ref[key]
        if all(v is None for v in want):
            continue  # the file says nothing; clothbake's default is not under test here
        got = dj.get(key)
        if got is None or len(got) != len(want):
            bad.append("%s missing or of length %s, reference %d" % (key, None if got is None else len(got), len(want)))
            continue
        wrong = [i for i, (g, w) in enumerate(zip(got, want))
                 if w is not None and (g is None or abs(g - w) > SIZE_REL * max(abs(w), 1e-12))]
        if wrong:
            i = wrong[0]
            bad.append("%s differs at %d threads; first %d: clothbake %s, reference %s"
                       % (key, len(wrong), i + 1, got[i], want[i]))
    return bad


def read_crossings(path):
    import OpenImageIO as oiio
    inp = oiio.ImageInput.open(path)
    if inp is None:
        raise RuntimeError("cannot open %s: %s" % (path, oiio.geterror()))
    spec = inp.spec()
    px = inp.read_image(0, 0, 0, spec.nchannels, "float")
    inp.close()
    if px is None:
        raise RuntimeError("cannot read %s" % path)
    px = np.asarray(px, dtype=np.float64).reshape(spec.height, spec.width, spec.nchannels)
    names = list(spec.channelnames)
    return px, names


def compare_crossings(ref, px, names):
    """(crossings checked, mismatch messages)."""
    E, P = ref["ends"], ref["picks"]
    bad = []
    if px.shape[0] != P or px.shape[1] != E:
        return 0, ["crossings.exr is %dx%d (w x h), reference %d ends x %d picks" % (px.shape[1], px.shape[0], E, P)]
    try:
        ci = [names.index(c) for c in ("R", "G", "B", "A")]
    except ValueError:
        return 0, ["crossings.exr channels %s, want R,G,B,A" % names]
    rgb = px[:, :, ci[:3]]
    fam = px[:, :, ci[3]]
    up = ref["warp_up"]
    want_fam = np.where(up, 1.0, 2.0)
    warp = np.array(ref["warp_colors"], dtype=np.float64)   # E x 3
    weft = np.array(ref["weft_colors"], dtype=np.float64)   # P x 3
    want_rgb = np.where(up[:, :, None], warp[None, :, :], weft[:, None, :])
    fam_bad = fam != want_fam
    tol = np.maximum(EXR_REL * np.abs(want_rgb), EXR_ABS)
    rgb_bad = (np.abs(rgb - want_rgb) > tol).any(axis=2)
    n_bad = int(np.sum(fam_bad | rgb_bad))
    if n_bad:
        where = np.argwhere(fam_bad | rgb_bad)
        p, e = where[0]
        bad.append("%d of %d crossings differ (family %d, colour %d); first pick %d end %d: "
                   "A=%g RGB=%s, reference A=%g RGB=%s"
                   % (n_bad, E * P, int(fam_bad.sum()), int(rgb_bad.sum()), p + 1, e + 1,
                      fam[p, e], rgb[p, e].tolist(), want_fam[p, e], want_rgb[p, e].tolist()))
    return E * P, bad


# ------------------------------------------------------------------ self-checks

def self_checks(W, real_dir):
    """Facts about the reference and the comparisons that must hold, or the
    test would be measuring nothing. Returns failure messages."""
    fails = []
    # sRGB transfer end points and the knee.
    if abs(W.srgb_eotf(1.0) - 1.0) > 1e-12 or W.srgb_eotf(0.0) != 0.0:
        fails.append("srgb_eotf end points")
    if abs(W.srgb_eotf(0.5) - 0.21404114048223255) > 1e-12:
        fails.append("srgb_eotf(0.5)")

    def path(name):
        return os.path.join(real_dir, name)

    # Twins: TempoWeave's treadled and liftplan Honeysuckle, WeaveIt's single
    # treadled and liftplan 641 x 641 weave the same cloth.
    for a, b in (("tw_honeysuckle.wif", "tw_honeysuckle_lp.wif"),
                 ("wi_641_single.wif", "wi_641_liftplan.wif")):
        if os.path.exists(path(a)) and os.path.exists(path(b)):
            A, B = W.read_wif(path(a)), W.read_wif(path(b))
            if not np.array_equal(A["warp_up"], B["warp_up"]):
                fails.append("reference: twins %s / %s differ" % (a, b))
    # Fiberworks hearts: treadle 23 has no tie-up row, so its 5 picks lift
    # nothing and float the weft over every end (rising shed).
    if os.path.exists(path("fw_hearts3.wif")):
        H = W.read_wif(path("fw_hearts3.wif"))
        rows = [p for p in range(H["picks"]) if H["treadling"][p] == [23]]
        if len(rows) != 5 or H["warp_up"][rows].any():
            fails.append("reference: fw_hearts3 treadle-23 picks should be 5 weft floats")
        # Range 0,999: colour 9 = 999,999,999? whatever it is, (v-0)/999 is the rule:
        if H["range"] != [0, 999]:
            fails.append("reference: fw_hearts3 Range should be 0,999")
    # dtx_to_wif zeros: end 4 has no threading line -> never up.
    if os.path.exists(path("d2w_zeros.wif")):
        Z = W.read_wif(path("d2w_zeros.wif"))
        if Z["warp_up"][:, 3].any() or not Z["warp_up"][:, [0, 1, 2, 4]].any():
            fails.append("reference: d2w_zeros end 4 (unthreaded) must never be up")
        # pick 4 = treadles 0,1,4 -> shafts {1,3} | {2} = {1,2,3}: ends 1(2),2(3),5(1) up, 3(4) down
        if Z["warp_up"][3].tolist() != [True, True, False, False, True]:
            fails.append("reference: d2w_zeros pick 4 row %s" % Z["warp_up"][3].tolist())

    # The comparisons must see a single changed cell / colour / crossing.
    name = "d2w_zeros.wif" if os.path.exists(path("d2w_zeros.wif")) else None
    if name is None:
        cands = sorted(f for f in os.listdir(real_dir) if f.lower().endswith(".wif"))
        name = cands[0] if cands else None
    if name is None:
        fails.append("no real WIF files to test")
        return fails
    R = W.read_wif(path(name))
    dj = W.to_json(R)
    if compare_draft(R, dj, "self"):
        fails.append("self-check: the reference does not match its own draft.json: %s" % compare_draft(R, dj, "self"))
    flipped = json.loads(json.dumps(dj))
    flipped["warp_up"][0][0] = 1 - flipped["warp_up"][0][0]
    if not compare_draft(R, flipped, "self"):
        fails.append("self-check: a flipped warp_up cell went unnoticed")
    nudged = json.loads(json.dumps(dj))
    nudged["weft_colors"][-1][1] += 1e-4
    if not compare_draft(R, nudged, "self"):
        fails.append("self-check: a weft colour nudged by 1e-4 went unnoticed")
    short = json.loads(json.dumps(dj))
    short["warp_up"] = short["warp_up"][:-1]
    if not compare_draft(R, short, "self"):
        fails.append("self-check: a missing pick row went unnoticed")
    # A synthetic crossings image built from the reference passes; one flip fails.
    up = R["warp_up"]
    warp = np.array(R["warp_colors"])
    weft = np.array(R["weft_colors"])
    img = np.zeros((R["picks"], R["ends"], 4))
    img[:, :, :3] = np.where(up[:, :, None], warp[None], weft[:, None])
    img[:, :, 3] = np.where(up, 1.0, 2.0)
    n, b = compare_crossings(R, img, ["R", "G", "B", "A"])
    if b or n != R["ends"] * R["picks"]:
        fails.append("self-check: the reference's own crossings fail: %s" % b)
    img2 = img.copy()
    img2[0, 0, 3] = 3.0 - img2[0, 0, 3]
    if not compare_crossings(R, img2, ["R", "G", "B", "A"])[1]:
        fails.append("self-check: a flipped crossing family went unnoticed")
    img3 = img.copy()
    img3[-1, -1, 0] *= (1 + 1e-3)
    img3[-1, -1, 0] += 1e-3
    if not compare_crossings(R, img3, ["R", "G", "B", "A"])[1]:
        fails.append("self-check: a crossing colour off by 1e-3 went unnoticed")
    if not compare_crossings(R, img[::-1].copy(), ["R", "G", "B", "A"])[1] and not np.array_equal(up, up[::-1]):
        fails.append("self-check: crossings upside down went unnoticed")
    return fails


# ------------------------------------------------------------------------ main

def run(cmd, log):
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    with open(log, "w") as f:
        f.write(" ".join(cmd) + "\n" + p.stdout)
    return p.returncode, p.stdout


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--clothbake", required=True)
    ap.add_argument("--repo", required=True)
    ap.add_argument("--tmp", required=True)
    ap.add_argument("--no-volume", action="store_true", help="skip the crossings.exr step")
    ap.add_argument("--only", action="append", help="test only these file names")
    a = ap.parse_args()
    W = load_reference(a.repo)
    real_dir = os.path.join(a.repo, "testscenes", "wif", "real")

    fails = self_checks(W, real_dir)
    if fails:
        for f in fails:
            print("FAIL %s" % f)
        return 1
    print("self-checks: ok (flipped cell, nudged colour, missing row, flipped crossing, "
          "crossing colour, upside-down image all detected; reference twins and hand facts hold)")

    files = sorted(f for f in os.listdir(real_dir) if f.lower().endswith(".wif"))
    if a.only:
        files = [f for f in files if f in a.only]
    if not files:
        print("FAIL no files in %s" % real_dir)
        return 1
    total_bad = 0
    for name in files:
        src = os.path.abspath(os.path.join(real_dir, name))
        stem = os.path.splitext(name)[0]
        msgs = []
        try:
            ref = W.read_wif(src)
        except W.WifError as e:
            print("FAIL %s: the reference refuses it: %s" % (name, e))
            total_bad += 1
            continue
        ddir = os.path.join(a.tmp, "draft_" + stem)
        rc, out = run([a.clothbake, "draft", src, "-o", ddir], os.path.join(a.tmp, "draft_%s.log" % stem))
        dpath = os.path.join(ddir, "draft.json")
        if rc != 0 or not os.path.exists(dpath):
            msgs.append("clothbake draft failed (rc %d): %s" % (rc, out.strip().splitlines()[-1] if out.strip() else ""))
        else:
            with open(dpath) as f:
                dj = json.load(f)
            msgs += ["draft: " + m for m in compare_draft(ref, dj, name)]
            if dj.get("source_program", ref["source_program"]) != ref["source_program"]:
                print("  note %s: source_program %r, reference %r" % (name, dj.get("source_program"), ref["source_program"]))
        checked = 0
        vol_note = ""
        if not a.no_volume:
            cpt = 2 if (ref["ends"] > LARGE or ref["picks"] > LARGE) else 4
            vol_note = " cells_per_thread %d" % cpt
            spec = {"weave": {"wif": src},
                    "shading": {"variation": 0, "diffuse_top": 1, "diffuse_bottom": 1},
                    "density": {"noise_amplitude": 0},
                    "resolution": {"cells_per_thread": cpt, "layers": 8, "supersample": 1}}
            spath = os.path.join(a.tmp, "spec_%s.json" % stem)
            with open(spath, "w") as f:
                json.dump(spec, f, indent=1)
            vdir = os.path.join(a.tmp, "vol_" + stem)
            rc, out = run([a.clothbake, "volume", spath, "-o", vdir], os.path.join(a.tmp, "vol_%s.log" % stem))
            epath = os.path.join(vdir, "crossings.exr")
            if rc != 0 or not os.path.exists(epath):
                msgs.append("clothbake volume failed (rc %d): %s" % (rc, out.strip().splitlines()[-1] if out.strip() else ""))
            else:
                try:
                    px, names = read_crossings(epath)
                    checked, b = compare_crossings(ref, px, names)
                    msgs += ["crossings: " + m for m in b]
                except Exception as e:
                    msgs.append("crossings.exr unreadable: %s" % e)
        print("%-22s %-30s %4d x %-4d crossings checked %7d  mismatches %d%s"
              % (name, ref["source_program"][:30], ref["ends"], ref["picks"], checked, len(msgs), vol_note))
        for m in msgs:
            print("    " + m)
        total_bad += len(msgs)
    if total_bad:
        print("FAIL: %d mismatch(es) over %d files" % (total_bad, len(files)))
        return 1
    print("ok: %d real WIF files agree with the reference reading" % len(files))
    return 0


if __name__ == "__main__":
    sys.exit(main())
