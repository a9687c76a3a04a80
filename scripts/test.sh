#!/usr/bin/env bash
# Installs what is missing, builds, and runs every test through ctest
# (unit tests, CLI checks, the headless Blender check). Ends with ctest's summary.
source "$(dirname "$0")/lib.sh"
install_packages
build_all
log "running tests"
cd "$CLOTHBAKE_BUILD"
ctest --output-on-failure -j "$(nproc)" "$@"
