#!/usr/bin/env bash
# Installs what is missing, builds, and runs every test through ctest
# (unit tests, CLI checks, the Blender suite), and when asked the same in each
# Debian root of the add-on's newer Blenders. Ends with a summary of every place.
#   scripts/test.sh [CTEST_ARGS...]              Release build in build/, then the
#       roots (CLOTHBAKE_ROOT_SUITES, "trixie sid" unless set; empty: none)
#   scripts/test.sh --sanitize [CTEST_ARGS...]   the same suite built with
#       AddressSanitizer + UBSan (any report fails the test) in build-asan/;
#       e.g. --sanitize -LE slow to leave out the slow scene and Blender tests
#       (docs/design/hardening.md, "Sanitisers"). No roots.
#   scripts/test.sh --roots-only                 the roots alone (trixie and sid unless
#       CLOTHBAKE_ROOT_SUITES says otherwise)
#
# The roots (scripts/debian-root.sh; docs/guide/blender.md, "Blender versions"):
# for each of CLOTHBAKE_ROOT_SUITES the root is made (first use only) while
# the host builds and tests, clothbake and its unit tests are built in it
# with that suite's compiler and libraries, and there run the unit tests and
# the Blender tests labelled "roots" (both material routes, UV layouts, every
# light type, colour-free recolouring and addressed materials, installing
# both packages, the lookup route, the new user and the WIF panel in the
# real window). CLOTHBAKE_ROOT_UNIT=0 builds clothbake alone there and runs
# the "roots" tests only (CI's subset: .ci/run). CTEST_ARGS apply to the
# host. With CLOTHBAKE_TEST_DEADLINE (seconds since the epoch), a root whose
# run would start with less than CLOTHBAKE_ROOT_MINUTES (23) minutes left is
# not started, and the summary says so.
set -uo pipefail
sanitize=0 host=1
if [[ ${1:-} == --sanitize ]]; then
  shift
  sanitize=1
  export CLOTHBAKE_SANITIZE=1
  export CLOTHBAKE_BUILD=${CLOTHBAKE_BUILD_ASAN:-$(cd "$(dirname "$0")/.." && pwd)/build-asan}
  # Leaks are errors; UBSan prints where. Python (pytest, Blender) runs the
  # sanitised clothbake as a child process, so nothing needs preloading.
  export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1:strict_string_checks=1}
  export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
elif [[ ${1:-} == --roots-only ]]; then
  shift
  host=0
fi
source "$(dirname "$0")/lib.sh"
set +e
install_packages || exit 1
suites=()
default_suites="trixie sid"
((sanitize)) || read -r -a suites <<<"${CLOTHBAKE_ROOT_SUITES-$default_suites}"
root_script=$CLOTHBAKE_ROOT/scripts/debian-root.sh
roots_log=$CLOTHBAKE_ROOT/build-roots/make.log
mkdir -p "$(dirname "$roots_log")"
start=$SECONDS
# A root's build and Blender tests took 12 and 17 minutes on 2 cores, made
# once (11.5 of them the tests); the margin is for a slower machine.
root_minutes=${CLOTHBAKE_ROOT_MINUTES:-23}
summary=()
failed=0

# Made (debootstrap, apt: mostly the network and the disk) while the host
# builds and tests.
if ((${#suites[@]})); then
  log "making the Debian roots (${suites[*]}) in the background: $roots_log"
  (for s in "${suites[@]}"; do
    CLOTHBAKE_ROOT_BUILD=0 bash "$root_script" "$s" run true || exit 1
  done) >"$roots_log" 2>&1 &
  roots_pid=$!
fi

if ((host)); then
  build_all || exit 1
  log "running tests"
  (cd "$CLOTHBAKE_BUILD" && ctest --output-on-failure -j "$(nproc)" "$@")
  rc=$?
  summary+=("host, $(blender --version 2>/dev/null | head -1): ctest exit $rc")
  failed=$((rc != 0))
fi

if ((${#suites[@]})); then
  log "waiting for the Debian roots to be made"
  if ! wait "$roots_pid"; then
    cat "$roots_log" >&2
    log "making the Debian roots failed"
    exit 1
  fi
  for s in "${suites[@]}"; do
    if [[ -n ${CLOTHBAKE_TEST_DEADLINE:-} ]] && (($(date +%s) + 60 * root_minutes > CLOTHBAKE_TEST_DEADLINE)); then
      summary+=("$s: NOT RUN, less than $root_minutes minutes left before CLOTHBAKE_TEST_DEADLINE")
      continue
    fi
    t=$SECONDS
    if [[ ${CLOTHBAKE_ROOT_UNIT:-1} == 0 ]]; then
      targets="clothbake" what="the 'roots' Blender tests"
    else
      targets="clothbake clothbake_tests" what="the unit tests and the 'roots' Blender tests"
    fi
    log "Debian root $s: building $targets, then $what"
    if ! CLOTHBAKE_ROOT_TARGETS="$targets" bash "$root_script" "$s" setup; then
      failed=1
      summary+=("$s: the build failed")
      continue
    fi
    CLOTHBAKE_ROOT_TARGETS="$targets" bash "$root_script" "$s" run bash -c \
      'if [[ $2 != clothbake ]]; then
         ctest --test-dir "$1" --output-on-failure -j "$(nproc)" -E "^(cli|scene|addon|farm|blender)\." || exit
       fi
       ctest --test-dir "$1" --output-on-failure -j "$(nproc)" -L roots' bash \
      "$CLOTHBAKE_ROOT/build-$s" "$targets"
    rc=$?
    failed=$((failed || rc != 0))
    version=$(CLOTHBAKE_ROOT_BUILD=0 bash "$root_script" "$s" run blender --version 2>/dev/null | head -1)
    summary+=("$s, $version ($what): ctest exit $rc after $((SECONDS - t)) s")
  done
fi

log "summary after $((SECONDS - start)) s:"
for line in "${summary[@]}"; do log "  $line"; done
exit "$failed"
