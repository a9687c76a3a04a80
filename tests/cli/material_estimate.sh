#!/usr/bin/env bash
# `clothbake material --estimate`: one JSON object with the counts, the
# memory figures and a timed estimate, exit 0, nothing written (no -o folder,
# an existing material left as it was); its counts are the real bake's; what a
# bake refuses, the estimate refuses. The seconds must fall within 0.33x..3x
# of a real small bake's own "seconds" (the bake's report): generous, because
# the machine may be shared, but a probe that measured the wrong work (views
# or light nodes all at the horizon, scattered rays) is off by more.
#   material_estimate.sh EXE ROOT
set -u
exe=$1 root=$2
paper=$root/testscenes/paper/scene.json
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
small=(--texels 8 --directions 4 --light-directions 4 --spp 1 --quiet)

"$exe" material "$paper" -o "$tmp/est" --estimate "${small[@]}" >"$tmp/est.json" 2>"$tmp/est.err" \
  || fail "--estimate exited $?: $(cat "$tmp/est.err")"
[[ -e $tmp/est ]] && fail "--estimate wrote the folder"
compgen -G "$tmp/est.*-*" && fail "--estimate left a temporary folder"
echo "ok   --estimate writes nothing: $(tr -d ' \n' <"$tmp/est.json")"
# Texels per thread: the paper's 2-thread repeat at R 8 has 4, no warning;
# a real WIF whose weave spans 62 threads (wi_32twill) at R 8 has 0.13, and
# the estimate says so and names a --texels that resolves it.
python3 -c "import json,sys; e=json.load(open(sys.argv[1])); assert e['texels_per_thread'] == 4.0 and 'texels_advised' not in e, e" \
  "$tmp/est.json" || fail "the paper at R 8: texels_per_thread"
[[ -s $tmp/est.err ]] && fail "the paper at R 8 warned: $(cat "$tmp/est.err")"
printf '{"weave": {"wif": "%s"}, "resolution": {"cells_per_thread": 1, "layers": 4}}\n' \
  "$root/testscenes/wif/real/wi_32twill.wif" >"$tmp/twill.json"
"$exe" material "$tmp/twill.json" -o "$tmp/twill" --estimate --address repeat "${small[@]}" \
  >"$tmp/twill.out" 2>"$tmp/twill.err" || fail "estimate of wi_32twill: $(cat "$tmp/twill.err")"
grep -qF "warning: --texels 8 spans 62 x 62 threads per repeat: 0.13 texels per thread" \
  "$tmp/twill.err" || fail "wi_32twill at R 8: $(cat "$tmp/twill.err")"
grep -qE -- "--texels 256 gives 4.1 \(the bake holds about [0-9]+ MiB\)" "$tmp/twill.err" ||
  fail "the advice: $(cat "$tmp/twill.err")"
python3 -c "import json,sys; e=json.load(open(sys.argv[1])); assert e['texels_advised'] == 256, e" \
  "$tmp/twill.out" || fail "wi_32twill: texels_advised in the estimate"
echo "ok   few texels per thread warned (--address repeat): $(cat "$tmp/twill.err")"
# The address left to the bake: the paper keeps its whole repeat; the twill,
# 0.13 texels a thread over its repeat, is addressed per crossing (at the
# texels given), with no warning, and the plan says why.
python3 -c "import json,sys; e=json.load(open(sys.argv[1])); assert e['plan'].startswith('the whole repeat at 8 texels: 4.0 texels a thread'), e['plan']" \
  "$tmp/est.json" || fail "the paper's plan"
"$exe" material "$tmp/twill.json" -o "$tmp/twill" --estimate "${small[@]}" >"$tmp/auto.out" \
  2>"$tmp/auto.err" || fail "estimate of wi_32twill, address auto: $(cat "$tmp/auto.err")"
[[ -s $tmp/auto.err ]] && fail "wi_32twill, address auto, warned: $(cat "$tmp/auto.err")"
python3 -c "import json,sys; e=json.load(open(sys.argv[1])); p=e['plan']; assert p.startswith('per crossing at 8 texels (') and 'blocks): the whole repeat spans 62 threads: 0.13 texels a thread at 8, below 2' in p, p; assert 'texels_advised' not in e, e" \
  "$tmp/auto.out" || fail "wi_32twill: the plan"
echo "ok   the address chosen: $(python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['plan'])" "$tmp/auto.out")"

"$exe" material "$paper" -o "$tmp/real" "${small[@]}" >"$tmp/real.json" || fail "the real bake"
/usr/bin/python3 - "$tmp/est.json" "$tmp/real.json" <<'PY' || fail "estimate JSON against the bake"
import json, sys
e = json.load(open(sys.argv[1]))
b = json.load(open(sys.argv[2]))
for key in ("seconds", "light_field_bytes", "max_bytes", "fixed_bytes", "view_nodes", "light_nodes",
            "texels", "spp", "rays", "threads", "probe_seconds", "probe_rays", "fields_seconds",
            "marches_seconds", "factorise_seconds", "mips_seconds"):
    assert key in e, f"missing {key}"
# The counts are the bake's.
assert (e["view_nodes"], e["light_nodes"], e["texels"], e["rays"]) == \
    (b["view_nodes"], b["light_nodes"], b["texels"], b["rays"]) == (32, 32, 8, 32 * 64), (e, b)
assert e["threads"] == b["threads"] >= 1
# The fields' bytes are the bake's (it reports MiB); the full-rank table
# bounds the real one (rank 32 at most here).
assert abs(e["light_field_bytes"] / 2**20 - b["light_field_mib"]) < 1e-6, (e, b)
assert e["max_bytes"] > 0 and b["max_rank"] <= e["light_nodes"]
assert e["fixed_bytes"] >= e["light_field_bytes"]
ratio = e["seconds"] / b["seconds"]
print(f"ok   estimate {e['seconds']:.2f} s (probe {e['probe_seconds']:.2f} s), "
      f"bake {b['seconds']:.2f} s: ratio {ratio:.2f}")
assert 0.33 <= ratio <= 3.0, f"estimate {e['seconds']} s against the bake's {b['seconds']} s"
PY

# Onto an existing material folder: left as it was.
before=$(cd "$tmp/real" && sha256sum ./*)
"$exe" material "$paper" -o "$tmp/real" --estimate "${small[@]}" >/dev/null || fail "estimate over a material"
[[ $(cd "$tmp/real" && sha256sum ./*) == "$before" ]] || fail "--estimate changed the material"
compgen -G "$tmp/real.*-*" && fail "--estimate left a temporary folder"
echo "ok   an existing material is left as it was"

# What the bake refuses in step 1, the estimate refuses, with no output.
"$exe" material "$paper" -o "$tmp/bad" --estimate --texels 12 --quiet >"$tmp/bad.out" 2>"$tmp/bad.err" \
  && fail "--estimate with --texels 12 succeeded"
grep -qF -- "--texels" "$tmp/bad.err" || fail "texels 12: $(cat "$tmp/bad.err")"
[[ ! -s $tmp/bad.out && ! -e $tmp/bad ]] || fail "texels 12: output"
"$exe" material "$paper" -o "$tmp/bad" --estimate --object nobody --quiet >"$tmp/bad.out" 2>"$tmp/bad.err" \
  && fail "--estimate with --object nobody succeeded"
grep -qF -- "--object" "$tmp/bad.err" || fail "object: $(cat "$tmp/bad.err")"
[[ ! -e $tmp/bad ]] || fail "object: output"
echo "ok   refused: $(head -1 "$tmp/bad.err")"
# --object by index: the first object is index 0.
"$exe" material "$paper" -o "$tmp/idx" --estimate --object 0 "${small[@]}" >/dev/null || fail "--object 0"
echo "ok   --object 0"
