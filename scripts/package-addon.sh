#!/usr/bin/env bash
# Packs the Blender add-on for both of Blender's add-on systems:
#
#   scripts/package-addon.sh [-o OUT.zip] [--extension DIR] [--blender BIN]
#
# -o OUT.zip      the legacy add-on zip (default dist/clothbake-addon.zip): the
#                 clothbake/ package folder, installed with Preferences > Add-ons >
#                 Install (3.4 to 4.1) or Install from Disk (4.2 and newer).
# --extension DIR also the extension (4.2 and newer: blender_addon/blender_manifest.toml
#                 beside the package), built into DIR and validated by Blender's own
#                 `blender --command extension build` / `validate`. That command
#                 exists from 4.2: pass such a Blender with --blender, or run this
#                 script in a Debian root (scripts/debian-root.sh trixie run ...).
#
# The zip is reproducible: files in sorted order with a fixed date, so the
# same sources give the same bytes. Written to a temporary name and renamed.
set -euo pipefail

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
out="$root/dist/clothbake-addon.zip"
ext_dir=""
blender=${BLENDER:-blender}
usage() {
  echo "usage: scripts/package-addon.sh [-o OUT.zip] [--extension DIR] [--blender BIN]" >&2
  exit 2
}
while (($#)); do
  case $1 in
    -o) (($# >= 2)) || usage; out=$2; shift 2 ;;
    --extension) (($# >= 2)) || usage; ext_dir=$2; shift 2 ;;
    --blender) (($# >= 2)) || usage; blender=$2; shift 2 ;;
    *) usage ;;
  esac
done
mkdir -p "$(dirname "$out")"

/usr/bin/python3 - "$root/blender_addon" "$out" <<'PY'
import os
import sys
import zipfile

src, out = sys.argv[1], os.path.abspath(sys.argv[2])
files = []
for folder, dirs, names in os.walk(os.path.join(src, "clothbake")):
    dirs[:] = sorted(d for d in dirs if d != "__pycache__" and not d.startswith("."))
    files += [os.path.join(folder, n) for n in names
              if not n.endswith((".pyc", ".pyo")) and not n.startswith(".")]
tmp = f"{out}.tmp-{os.getpid()}"
try:
    with zipfile.ZipFile(tmp, "w", zipfile.ZIP_DEFLATED) as z:
        for path in sorted(files):
            info = zipfile.ZipInfo(os.path.relpath(path, src), date_time=(2020, 1, 1, 0, 0, 0))
            info.compress_type = zipfile.ZIP_DEFLATED
            info.external_attr = 0o644 << 16
            with open(path, "rb") as f:
                z.writestr(info, f.read())
    os.replace(tmp, out)
finally:
    if os.path.exists(tmp):
        os.remove(tmp)
print(f"{out}: {len(files)} files")
PY

[[ -n $ext_dir ]] || exit 0

# The extension: Blender builds it from a staged copy (the package without
# caches, the manifest at its top), and validates what it built.
version=$("$blender" --version 2>/dev/null | sed -n 's/^Blender \([0-9][0-9.]*\).*/\1/p' | head -1)
if [[ -z $version ]]; then
  echo "package-addon.sh: error: --extension: '$blender' did not run (--blender BIN names a Blender 4.2 or newer)" >&2
  exit 1
fi
if [[ $(printf '%s\n4.2\n' "$version" | sort -V | head -1) != 4.2 ]]; then
  echo "package-addon.sh: error: --extension: Blender $version has no 'extension build' (it came in 4.2);" \
    "pass --blender with a newer one, or run: scripts/debian-root.sh trixie run scripts/package-addon.sh --extension $ext_dir" >&2
  exit 1
fi
stage=$(mktemp -d)
trap 'rm -rf "$stage"' EXIT
mkdir -p "$stage/clothbake" "$ext_dir"
(cd "$root/blender_addon/clothbake" && find . -name __pycache__ -prune -o -type f ! -name '*.py[co]' -print |
  while read -r f; do mkdir -p "$stage/clothbake/$(dirname "$f")"; cp "$f" "$stage/clothbake/$f"; done)
cp "$root/blender_addon/blender_manifest.toml" "$stage/clothbake/"
"$blender" --factory-startup --command extension build --source-dir "$stage/clothbake" \
  --output-dir "$stage" >"$stage/build.log" 2>&1 || { cat "$stage/build.log" >&2; exit 1; }
built=$(ls "$stage"/clothbake-*.zip)
"$blender" --factory-startup --command extension validate "$built" >"$stage/validate.log" 2>&1 ||
  { cat "$stage/validate.log" >&2; exit 1; }
mv "$built" "$ext_dir/"
echo "$ext_dir/$(basename "$built"): extension for Blender 4.2+ (built and validated by Blender $version)"
