#!/usr/bin/env bash
# Installs what is missing, builds, and runs every test through ctest
# (unit tests, CLI checks, the Blender suite), then the same in each Debian
# root of the add-on's newer Blenders. Ends with a summary of every place.
#   scripts/test.sh [CTEST_ARGS...]             Release build in build/, then the roots
#   scripts/test.sh --sanitize [CTEST_ARGS...]  the same suite built with
#       AddressSanitizer + UBSan (any report fails the test) in build-asan/;
#       e.g. --sanitize -LE slow to leave out the slow scene and Blender tests
#       (docs/design/hardening.md, "Sanitisers"). No roots.
#
# The roots (scripts/debian-root.sh; docs/guide/blender.md, "Blender versions"):
# CLOTHBAKE_ROOT_SUITES (default "trixie sid"; empty for none) are made while
# the host builds and tests, then clothbake is built in each and there run
# the fast tests (-LE "slow|farm": the unit tests and the CLI checks, with
# that suite's compiler and libraries) and the Blender tests labelled
# "roots" (both material routes, UV layouts, every light type, colour-free
# recolouring and addressed materials, installing both packages, the new
# user and the WIF panel in the real window). CTEST_ARGS apply to the host.
set -uo pipefail
sanitize=0
if [[ ${1:-} == --sanitize ]]; then
  shift
  sanitize=1
  export CLOTHBAKE_SANITIZE=1
  export CLOTHBAKE_BUILD=${CLOTHBAKE_BUILD_ASAN:-$(cd "$(dirname "$0")/.." && pwd)/build-asan}
  # Leaks are errors; UBSan prints where. Python (pytest, Blender) runs the
  # sanitised clothbake as a child process, so nothing needs preloading.
  export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1:strict_string_checks=1}
  export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
fi
source "$(dirname "$0")/lib.sh"
set +e
install_packages || exit 1
suites=()
((sanitize)) || read -r -a suites <<<"${CLOTHBAKE_ROOT_SUITES-trixie sid}"
roots_log=$CLOTHBAKE_ROOT/build-roots/setup.log
mkdir -p "$(dirname "$roots_log")"
start=$SECONDS

# The roots are made (debootstrap, apt: the network and the disk, little CPU)
# while the host builds and tests.
if ((${#suites[@]})); then
  log "making the Debian roots (${suites[*]}) in the background: $roots_log"
  (for s in "${suites[@]}"; do
    CLOTHBAKE_ROOT_BUILD=0 bash "$CLOTHBAKE_ROOT/scripts/debian-root.sh" "$s" run true || exit 1
  done) >"$roots_log" 2>&1 &
  roots_pid=$!
fi

build_all || exit 1
log "running tests"
(cd "$CLOTHBAKE_BUILD" && ctest --output-on-failure -j "$(nproc)" "$@")
host_rc=$?
summary=("host ($(blender --version 2>/dev/null | head -1)): ctest exit $host_rc")
failed=$((host_rc != 0))

if ((${#suites[@]})); then
  log "waiting for the Debian roots"
  if ! wait "$roots_pid"; then
    cat "$roots_log" >&2
    log "making the Debian roots failed"
    exit 1
  fi
  for s in "${suites[@]}"; do
    t=$SECONDS
    log "Debian root $s: building clothbake and running the fast tests and the roots' Blender tests"
    bash "$CLOTHBAKE_ROOT/scripts/debian-root.sh" "$s" setup || { failed=1; summary+=("$s: build failed"); continue; }
    bash "$CLOTHBAKE_ROOT/scripts/debian-root.sh" "$s" run bash -c \
      'ctest --test-dir "$1" --output-on-failure -j "$(nproc)" -LE "slow|farm" &&
       ctest --test-dir "$1" --output-on-failure -j "$(nproc)" -L roots' bash "$CLOTHBAKE_ROOT/build-$s"
    rc=$?
    failed=$((failed || rc != 0))
    summary+=("$s ($(CLOTHBAKE_ROOT_BUILD=0 bash "$CLOTHBAKE_ROOT/scripts/debian-root.sh" "$s" run blender --version 2>/dev/null | head -1)): exit $rc in $((SECONDS - t)) s")
  done
fi

log "summary after $((SECONDS - start)) s:"
for line in "${summary[@]}"; do log "  $line"; done
exit "$failed"
