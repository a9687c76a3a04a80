#!/usr/bin/env bash
# Installs what is missing, builds, and runs every test through ctest
# (unit tests, CLI checks, the headless Blender check). Ends with ctest's summary.
#   scripts/test.sh [CTEST_ARGS...]             Release build in build/
#   scripts/test.sh --sanitize [CTEST_ARGS...]  the same suite built with
#       AddressSanitizer + UBSan (any report fails the test) in build-asan/;
#       e.g. --sanitize -LE slow to leave out the slow scene and Blender tests
#       (docs/design/hardening.md, "Sanitisers").
if [[ ${1:-} == --sanitize ]]; then
  shift
  export CLOTHBAKE_SANITIZE=1
  export CLOTHBAKE_BUILD=${CLOTHBAKE_BUILD_ASAN:-$(cd "$(dirname "$0")/.." && pwd)/build-asan}
  # Leaks are errors; UBSan prints where. Python (pytest, Blender) runs the
  # sanitised clothbake as a child process, so nothing needs preloading.
  export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1:strict_string_checks=1}
  export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
fi
source "$(dirname "$0")/lib.sh"
install_packages
build_all
log "running tests"
cd "$CLOTHBAKE_BUILD"
ctest --output-on-failure -j "$(nproc)" "$@"
