#!/usr/bin/env bash
# Packs the Blender add-on for Edit > Preferences > Add-ons > Install:
# a zip holding the clothbake/ package folder (no __pycache__ or .pyc).
#
#   scripts/package-addon.sh [-o OUT.zip]      (default: dist/clothbake-addon.zip)
#
# The zip is reproducible: files in sorted order with a fixed date, so the
# same sources give the same bytes. Written to a temporary name and renamed.
set -euo pipefail

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
out="$root/dist/clothbake-addon.zip"
if [ $# -eq 2 ] && [ "$1" = "-o" ]; then
  out=$2
elif [ $# -ne 0 ]; then
  echo "usage: scripts/package-addon.sh [-o OUT.zip]" >&2
  exit 2
fi
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
