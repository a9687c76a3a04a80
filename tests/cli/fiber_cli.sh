#!/usr/bin/env bash
# `clothbake fiber` prints one JSON object whose diffuse matches the Lambert-
# sphere phase law at aspect 1 (tolerance 4 sigma / sqrt(N), sigma <= 0.5);
# bad vectors and values exit 1 naming the option, with nothing on stdout.
set -u
exe=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

"$exe" fiber --aspect 1 --tangent 1,0,0 --light 0,0,1 --view 0,0.5,0.8660254 --samples 4096 \
  --plot "$tmp/lobe.png" >"$tmp/out.json" || fail "fiber exited $?"
/usr/bin/python3 - "$tmp/out.json" <<'PY' || fail "JSON check"
import json, math, sys
d = json.load(open(sys.argv[1]))
for key in ("diffuse", "specular", "model", "aspect", "samples", "exponent"):
    assert key in d, f"missing {key}"
a = math.radians(30.0)
exact = 2 / (3 * math.pi) * (math.sin(a) + (math.pi - a) * math.cos(a))
tol = 4 * 0.5 / math.sqrt(4096)
assert abs(d["diffuse"] - exact) < tol, (d["diffuse"], exact, tol)
assert 0.0 <= d["specular"] <= 1.0
print(f"ok: diffuse {d['diffuse']:.5f} vs exact {exact:.5f} (tol {tol:.4f})")
PY
[[ -s $tmp/lobe.png ]] || fail "no plot written"

for model in table kajiya-kay; do
  "$exe" fiber --model $model --aspect 8 --tangent 1,0,0 --light 0,0.6,0.8 --view 0,-0.6,0.8 \
    >"$tmp/$model.json" || fail "$model exited $?"
  /usr/bin/python3 -c "import json,sys,math; d=json.load(open('$tmp/$model.json')); assert all(math.isfinite(d[k]) for k in ('diffuse','specular'))" \
    || fail "$model JSON"
done

bad() {  # expected option, args...
  local opt=$1; shift
  "$exe" fiber "$@" >"$tmp/stdout" 2>"$tmp/stderr"
  local rc=$?
  [[ $rc -eq 1 ]] || fail "$* exited $rc, expected 1"
  grep -q -- "error: $opt" "$tmp/stderr" || fail "$* did not name $opt: $(cat "$tmp/stderr")"
  [[ ! -s $tmp/stdout ]] || fail "$* printed to stdout"
  echo "ok: $(cat "$tmp/stderr")"
}
bad --tangent --tangent 1,0 --light 0,0,1 --view 0,0,1
bad --light --tangent 1,0,0 --light 0,0,0 --view 0,0,1
bad --view --tangent 1,0,0 --light 0,0,1 --view a,b,c
bad --aspect --aspect 0.5 --tangent 1,0,0 --light 0,0,1 --view 0,0,1
bad --samples --samples 0 --tangent 1,0,0 --light 0,0,1 --view 0,0,1
bad --exponent --exponent -2 --tangent 1,0,0 --light 0,0,1 --view 0,0,1
echo "all fiber CLI checks passed"
