#!/usr/bin/env bash
# Issue 15's figures for the cloth material (lab/material_accuracy/measure.py):
# install, build, then bake the paper cloth's material once and render it in
# four scenes against converged references. About 45 minutes on 2 cores the
# first time (the four references), 10 after. Results in out/material/.
source "$(dirname "$0")/../../scripts/lib.sh"
install_packages
build_all
/usr/bin/python3 "$CLOTHBAKE_ROOT/lab/material_accuracy/measure.py" --exe "$CLOTHBAKE_BUILD/baker/clothbake" "$@"
