#!/usr/bin/env bash
# A scene object's "volume" (docs/formats/scene.md) through the CLI:
# 1. round trip: `clothbake volume` writes volume.vdb; a render whose object
#    reads it ("volume", with and without its "cloth") gives the same EXR
#    bytes as the render that generates the texture from the spec;
# 2. bad VDBs (tests/cli/make_bad_vdbs.py, pyopenvdb): exit 1, a message
#    naming the scene, the VDB and the grid, and no output (bad_inputs.sh).
#
#   vdb_cli.sh EXE SOURCE_DIR
set -u
exe=$1 source=$2
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

paper=$source/testscenes/paper
"$exe" volume "$paper/cloth.json" -o "$tmp/vol" >/dev/null || fail "clothbake volume"
[[ -f $tmp/vol/volume.vdb ]] || fail "no volume.vdb"

# The paper scene, smaller and with cached transmittance to keep the test short.
/usr/bin/python3 - "$paper" "$tmp" <<'EOF' || fail "writing the scenes"
import json, os, sys
paper, tmp = sys.argv[1:3]
scene = json.load(open(os.path.join(paper, "scene.json")))
scene["camera"]["resolution"] = [160, 100]
scene["render"]["transmittance"] = "cached"
obj = scene["objects"][0]
obj["mesh"] = os.path.join(paper, obj["mesh"])
obj["cloth"] = os.path.join(paper, obj["cloth"])
json.dump(scene, open(os.path.join(tmp, "spec.json"), "w"), indent=1)
obj["volume"] = os.path.join(tmp, "vol", "volume.vdb")
json.dump(scene, open(os.path.join(tmp, "spec_and_volume.json"), "w"), indent=1)
del obj["cloth"]  # the paper cloth's fibre model is the default one
json.dump(scene, open(os.path.join(tmp, "volume_only.json"), "w"), indent=1)
EOF

for name in spec spec_and_volume volume_only; do
  "$exe" render "$tmp/$name.json" -o "$tmp/$name.exr" --spp 1 --quiet || fail "render $name"
done
cmp "$tmp/spec.exr" "$tmp/spec_and_volume.exr" || fail "render with \"volume\" differs from the spec's"
cmp "$tmp/spec.exr" "$tmp/volume_only.exr" || fail "render with \"volume\" only differs from the spec's"
echo "ok   round trip: renders from the spec and from volume.vdb are byte-identical"

/usr/bin/python3 "$here/make_bad_vdbs.py" "$tmp/vol/volume.vdb" "$paper/scene.json" "$tmp/bad" ||
  fail "make_bad_vdbs.py"
bash "$here/bad_inputs.sh" "$exe" "$tmp/bad" render || fail "bad VDB inputs"
