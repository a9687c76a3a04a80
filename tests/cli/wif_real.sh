#!/usr/bin/env bash
# cli.wif_real: every real WIF file in testscenes/wif/real (written by
# Handweaving.net, TempoWeave, Fiberworks PCW, Mac WeaveIt, DB-WEAVE, ...;
# testscenes/wif/real/PROVENANCE.md) read by `clothbake draft` and woven by
# `clothbake volume` must agree, crossing by crossing, with an independent
# reading (tests/lib/wif_reference.py). The comparison is
# tests/cli/wif_real_check.py; it checks itself first (a flipped cell must be
# caught).  Usage: wif_real.sh CLOTHBAKE REPO_ROOT [--no-volume] [--only FILE]...
set -euo pipefail
exe=$1
root=$2
shift 2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
/usr/bin/python3 "$root/tests/cli/wif_real_check.py" \
  --clothbake "$exe" --repo "$root" --tmp "$tmp" "$@"
