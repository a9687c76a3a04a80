#!/usr/bin/env bash
# The material's size on disk as `clothbake material --estimate` puts it
# (bytes_on_disk), for the paper cloth and each real draft at the defaults: the
# left column of docs/design/material.md's "Size on disk". The written sizes
# beside them are the bakes' (real_drafts.py's results, the guide's table).
# A probe each: about 10 to 60 s on 2 cores.
#   disk_estimate.sh EXE
set -euo pipefail
exe=$1
root=$(cd "$(dirname "$0")/../.." && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
estimate() { # estimate NAME INPUT
  "$exe" material "$2" -o "$tmp/$1.mat" --estimate --quiet >"$tmp/$1.json"
  /usr/bin/python3 -c "import json, sys; e = json.load(open(sys.argv[1]))
print(f'{sys.argv[2]}: {e[\"bytes_on_disk\"] / 1e6:.1f} MB at mean rank {e[\"expected_mean_rank\"]:.1f}')" \
    "$tmp/$1.json" "$1"
}
estimate paper "$root/testscenes/paper/scene.json"
for wif in d2w_zeros dbw_schort fw_hearts3 hw_34779 hw_55116 hw_8452 tw_honeysuckle wi_32twill; do
  printf '{"name": "%s", "weave": {"wif": "%s"}, "seed": 1}\n' "$wif" \
    "$root/testscenes/wif/real/$wif.wif" >"$tmp/$wif.cloth.json"
  estimate "$wif" "$tmp/$wif.cloth.json"
done
