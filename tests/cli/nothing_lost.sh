#!/usr/bin/env bash
# Nothing lost (docs/design/hardening.md): a render, bake or volume that is interrupted, runs
# out of disk or meets a read-only folder leaves the previous output byte for
# byte as it was, no half-written file under the final name and no temporary
# file; a re-run completes and gives the whole output.
#   nothing_lost.sh EXE ROOT
set -u
exe=$1 root=$2
slab=$root/testscenes/slab/scene.json
# Two cloth specs with different volumes (the paper cloth, seeds 1 and 2): the
# interrupted `volume` runs make the other one, so a file of theirs published
# by mistake would show.
paper_cloth=$root/testscenes/paper/cloth.json
tmp=$(mktemp -d)
trap 'chmod -R u+rwX "$tmp" 2>/dev/null; rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
other_cloth=$tmp/paper_seed2.json
sed 's/"seed": 1/"seed": 2/' "$paper_cloth" >"$other_cloth"
cmp -s "$paper_cloth" "$other_cloth" && fail "could not make a second cloth spec"
small=(--directions 3 --texels 4 --spp 1 --quiet)
out=$tmp/out

# The previous outputs every case must leave as they are, and their digests.
mkdir -p "$out"
"$exe" render "$slab" -o "$out/r.exr" --png "$out/r.png" --quiet || fail "first render"
"$exe" bake "$slab" -o "$out/b" "${small[@]}" >/dev/null || fail "first bake"
"$exe" volume "$paper_cloth" -o "$out/v" >/dev/null || fail "first volume"
digest() { (cd "$out" && find . -type f | LC_ALL=C sort | xargs sha256sum); }
digest >"$tmp/before"
intact() {  # case name: the previous outputs are intact and nothing else is there
  digest | cmp -s - "$tmp/before" || { diff <(digest) "$tmp/before"; fail "$1: previous output changed"; }
  local extra
  extra=$(ls -A "$out" | grep -v -x -e r.exr -e r.png -e b -e v)
  [[ -z $extra ]] || fail "$1: left behind in the output folder: $extra"
  extra=$(ls -A "$out/v" | grep -v -x -e volume.vdb -e volume.json -e top.png -e tangents.png \
    -e section_warp.png -e section_weft.png -e drawdown.png -e crossings.exr)
  [[ -z $extra ]] || fail "$1: left behind in the volume folder: $extra"
}
# Waits until FILE has a line matching PATTERN (up to 120 s) while PID runs.
wait_for() {
  local file=$1 pattern=$2 pid=$3
  for _ in $(seq 1200); do
    grep -q -- "$pattern" "$file" 2>/dev/null && return 0
    kill -0 "$pid" 2>/dev/null || return 1
    sleep 0.1
  done
  return 1
}
# Runs a command in the background, sends SIGTERM once PATTERN shows on its
# stderr, and checks exit status 143, the message and the previous outputs.
interrupted() {  # name, pattern, env assignments..., -- command...
  local name=$1 pattern=$2; shift 2
  local env=()
  while [[ $1 != -- ]]; do env+=("$1"); shift; done
  shift
  env "${env[@]}" CLOTHBAKE_PROGRESS=lines "$@" >/dev/null 2>"$tmp/$name.err" &
  local pid=$!
  wait_for "$tmp/$name.err" "$pattern" $pid || { wait $pid; fail "$name: '$pattern' never showed ($(tail -2 "$tmp/$name.err"))"; }
  local pending
  pending=$(ls -A "$out" | grep -c -e '\.tmp')
  kill -TERM $pid
  wait $pid
  local rc=$?
  [[ $rc -eq 143 ]] || fail "$name: exit status $rc, expected 143 ($(tail -1 "$tmp/$name.err"))"
  grep -q "clothbake: interrupted by SIGTERM: stopped;" "$tmp/$name.err" ||
    fail "$name: no interrupt message: $(tail -1 "$tmp/$name.err")"
  intact "$name"
  echo "ok   $name: killed at '$pattern' with $pending temporary output(s) pending: $(tail -1 "$tmp/$name.err")"
}

# --- (a) SIGTERM half-way ------------------------------------------------------
# Mid-computation: at the first percent shown of a render / bake that takes
# far longer to finish (tens of seconds).
interrupted render_mid_run "render  *[1-9][0-9]*%" -- \
  "$exe" render "$slab" -o "$out/r.exr" --png "$out/r.png" --spp 1024 --threads 1
interrupted bake_mid_run "bake  *[1-9][0-9]*%" -- \
  "$exe" bake "$slab" -o "$out/b" --directions 8 --texels 32 --spp 16 --threads 1
# Mid-publication: every file is written under its temporary name and the
# writer waits (CLOTHBAKE_TEST_HOLD_UNFINISHED) before renaming it into place.
interrupted render_before_rename "holding unfinished .*r.tmp.*png" CLOTHBAKE_TEST_HOLD_UNFINISHED=60 -- \
  "$exe" render "$slab" -o "$out/r.exr" --png "$out/r.png" --spp 2
grep -q "2 unfinished outputs removed" "$tmp/render_before_rename.err" || fail "render_before_rename: temporaries not reported removed"
interrupted bake_before_rename "holding unfinished .*b.tmp-" CLOTHBAKE_TEST_HOLD_UNFINISHED=60 -- \
  "$exe" bake "$slab" -o "$out/b" --directions 3 --texels 4 --spp 2
grep -q "1 unfinished output removed" "$tmp/bake_before_rename.err" || fail "bake_before_rename: temporary folder not reported removed"
# `volume` writes eight files (VDB, crossings, five previews, summary) and publishes them
# together: held before the renames, none may have replaced its old version.
interrupted volume_before_rename "holding unfinished .*volume.tmp.*json" CLOTHBAKE_TEST_HOLD_UNFINISHED=60 -- \
  "$exe" volume "$other_cloth" -o "$out/v"
grep -q "8 unfinished outputs removed" "$tmp/volume_before_rename.err" || fail "volume_before_rename: temporaries not reported removed"

# --- (b) a full disk: a file size limit (RLIMIT_FSIZE), writes fail with EFBIG --
refused() {  # name, expected message, command... : exit 1, message, previous intact
  local name=$1 expect=$2; shift 2
  "$@" >/dev/null 2>"$tmp/$name.err"
  local rc=$?
  [[ $rc -eq 1 ]] || fail "$name: exit status $rc, expected 1 ($(cat "$tmp/$name.err"))"
  grep -qF -- "$expect" "$tmp/$name.err" || fail "$name: expected '$expect', got: $(cat "$tmp/$name.err")"
  intact "$name"
  echo "ok   $name: $(head -1 "$tmp/$name.err")"
}
limited() { (trap '' XFSZ; ulimit -f "$1"; shift; exec "$@"); }  # KiB, command...
refused render_disk_full "$out/r.exr: cannot write image: " \
  limited 8 "$exe" render "$slab" -o "$out/r.exr" --png "$out/r.png" --spp 2 --quiet
refused bake_disk_full "$out/b: cannot write manifest.json: File too large; nothing under this name was changed" \
  limited 2 "$exe" bake "$slab" -o "$out/b" --directions 3 --texels 4 --spp 2 --quiet
refused volume_disk_full "$out/v/volume.vdb: cannot write the file: File too large" \
  limited 8 "$exe" volume "$other_cloth" -o "$out/v"
refused material_disk_full "$out/m: cannot write level_0.exr: " \
  limited 2 "$exe" material "$slab" -o "$out/m" --texels 16 --directions 3 --light-directions 3 \
  --spp 1 --field-supersample 1 --quiet

# --- (c) a read-only output folder ----------------------------------------------
# chmod 555 does not stop root: root runs the command without CAP_DAC_OVERRIDE
# (setpriv, util-linux); failing that the folder is made immutable (chattr +i).
ro_prefix=()
chmod 555 "$out"
ro_how="chmod 555"
if [[ $(id -u) -eq 0 ]]; then
  if setpriv --bounding-set=-dac_override,-dac_read_search -- test ! -w "$out" 2>/dev/null; then
    ro_prefix=(setpriv --bounding-set=-dac_override,-dac_read_search --)
    ro_how="chmod 555, run without CAP_DAC_OVERRIDE (root)"
  elif chattr +i "$out" 2>/dev/null; then
    ro_how="chattr +i (root)"
  else
    ro_how=""
  fi
fi
if [[ -n $ro_how ]]; then
  refused render_read_only "$out/r.exr: -o: cannot write in the folder $out: " \
    "${ro_prefix[@]}" "$exe" render "$slab" -o "$out/r.exr" --png "$out/r.png" --spp 2 --quiet
  refused bake_read_only "$out/b: cannot write in the folder $out: " \
    "${ro_prefix[@]}" "$exe" bake "$slab" -o "$out/b" --directions 3 --texels 4 --spp 2 --quiet
  echo "     (read-only by $ro_how)"
else
  echo "skip render_read_only, bake_read_only: running as root, and neither setpriv nor chattr +i can make a folder read-only here"
fi
chattr -i "$out" 2>/dev/null
chmod 755 "$out"

# --- a re-run completes, whole -----------------------------------------------------
"$exe" render "$slab" -o "$out/r.exr" --png "$out/r.png" --spp 2 --quiet || fail "re-run render"
"$exe" render "$slab" -o "$tmp/fresh.exr" --png "$tmp/fresh.png" --spp 2 --quiet || fail "fresh render"
cmp -s "$out/r.exr" "$tmp/fresh.exr" && cmp -s "$out/r.png" "$tmp/fresh.png" ||
  fail "the re-run render differs from an uninterrupted one"
"$exe" bake "$slab" -o "$out/b" --directions 3 --texels 4 --spp 2 --quiet >/dev/null || fail "re-run bake"
"$exe" bake "$slab" -o "$tmp/fresh_b" --directions 3 --texels 4 --spp 2 --quiet >/dev/null || fail "fresh bake"
for f in "$tmp/fresh_b"/*.exr; do
  cmp -s "$f" "$out/b/$(basename "$f")" || fail "re-run bake: $(basename "$f") differs from an uninterrupted bake"
done
cmp -s <(python3 "$root/tests/cli/manifest_without_times.py" "$out/b/manifest.json") \
  <(python3 "$root/tests/cli/manifest_without_times.py" "$tmp/fresh_b/manifest.json") ||
  fail "re-run bake: manifest differs from an uninterrupted bake (times aside)"
"$exe" lookup-render "$slab" "$out/b" -o "$tmp/lookup.exr" --quiet || fail "lookup-render of the re-run bake"
"$exe" volume "$other_cloth" -o "$out/v" >/dev/null || fail "re-run volume"
"$exe" volume "$other_cloth" -o "$tmp/fresh_v" >/dev/null || fail "fresh volume"
# (A VDB file carries a random UUID: its cells are compared by their hash.)
for f in top.png tangents.png section_warp.png section_weft.png; do
  cmp -s "$out/v/$f" "$tmp/fresh_v/$f" || fail "re-run volume: $f differs from an uninterrupted run"
done
cells_hash() { grep -o '"cells_hash": "[0-9a-f]*"' "$1"; }
[[ -n $(cells_hash "$out/v/volume.json") && $(cells_hash "$out/v/volume.json") == "$(cells_hash "$tmp/fresh_v/volume.json")" ]] ||
  fail "re-run volume: cells hash differs from an uninterrupted run"
extra=$(ls -A "$out" | grep -v -x -e r.exr -e r.png -e b -e v)
[[ -z $extra ]] || fail "re-run: left behind: $extra"
echo "ok   re-run: render, bake and volume complete, byte-identical to uninterrupted runs, lookup-render reads the bake"
