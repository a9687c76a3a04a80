#!/usr/bin/env bash
# Fuzzes every reader clothbake writes itself (tests/fuzz/: scene, cloth_spec,
# manifest, obj, cli_args, wif) with libFuzzer + AddressSanitizer + UBSan, each for
# a bounded time, and prints executions, corpus size and crashes per target.
#   scripts/fuzz.sh [SECONDS_PER_TARGET] [TARGET...]   (default 60 s, all targets)
# Build: build-fuzz/ (clang, -DCLOTHBAKE_FUZZ=ON). Corpora grow across runs in
# build-fuzz/corpus/<target>/, seeded each run from testscenes/ and tests/cli/;
# crashing inputs land in build-fuzz/crashes/<target>/. A crash, once fixed,
# belongs in tests/fuzz/regressions/<target>/ (ctest replays those).
# Exit status 1 if any target crashed.
source "$(dirname "$0")/lib.sh"
seconds=${1:-60}
shift || true
targets=("$@")
((${#targets[@]})) || targets=(scene cloth_spec manifest obj cli_args wif)
build=${CLOTHBAKE_FUZZ_BUILD:-$CLOTHBAKE_ROOT/build-fuzz}
src=$CLOTHBAKE_ROOT

install_packages
log "configuring $build (clang, libFuzzer, ASan, UBSan)"
CC=clang CXX=clang++ cmake -S "$src" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCLOTHBAKE_FUZZ=ON -DCLOTHBAKE_BUILD_TESTS=OFF -DCLOTHBAKE_BUILD_BENCHMARKS=OFF >/dev/null
log "building"
cmake --build "$build" -j "$(nproc)" --target "${targets[@]/#/clothbake_fuzz_}"

# Seeds per target: the shipped inputs and the bad inputs of the CLI tests.
seeds() {
  case $1 in
    scene) ls "$src"/testscenes/*/scene.json "$src"/tests/fuzz/seeds/scene/* \
      "$src"/tests/cli/bad_scenes/*.json ;;
    cloth_spec) ls "$src"/testscenes/*/cloth.json "$src"/testscenes/*/scene.json \
      "$src"/tests/cli/bad_specs/*.json ;;
    obj) ls "$src"/testscenes/*/*.obj "$src"/tests/cli/bad_scenes/meshes/*.obj ;;
    manifest) ls "$src"/tests/fuzz/files/lookup/manifest.json ;;
    cli_args) ls "$src"/tests/fuzz/seeds/cli_args/* ;;
    wif) find "$src"/testscenes/wif "$src"/tests/cli/bad_wifs -iname '*.wif' ;;
  esac
}
dict() {
  case $1 in
    scene | cloth_spec | manifest) echo "$src/tests/fuzz/json.dict" ;;
    *) echo "$src/tests/fuzz/$1.dict" ;;
  esac
}

export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
summary=()
any_crash=0
for t in "${targets[@]}"; do
  corpus=$build/corpus/$t crashes=$build/crashes/$t
  mkdir -p "$corpus" "$crashes"
  seeds "$t" | while read -r f; do cp "$f" "$corpus/seed_$(basename "$(dirname "$f")")_$(basename "$f")"; done
  before=$(find "$crashes" -type f | wc -l)
  log "fuzzing $t for $seconds s"
  # One input may take at most 10 s and 2 GiB; -max_len fits the largest seed mesh.
  "$build/tests/fuzz/clothbake_fuzz_$t" "$corpus" "$src/tests/fuzz/regressions/$t" \
    -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -max_len=16384 \
    -dict="$(dict "$t")" -artifact_prefix="$crashes/" -print_final_stats=1 \
    >"$build/fuzz_$t.log" 2>&1
  rc=$?
  execs=$(grep -o 'stat::number_of_executed_units: [0-9]*' "$build/fuzz_$t.log" | tail -1 | awk '{print $2}')
  # Coverage and the in-memory corpus from libFuzzer's last status line.
  done_line=$(grep -E '^#[0-9]+.*(DONE|cov:)' "$build/fuzz_$t.log" | tail -1)
  cov=$(grep -oE 'cov: [0-9]+' <<<"$done_line" | awk '{print $2}')
  corp=$(grep -oE 'corp: [0-9]+' <<<"$done_line" | awk '{print $2}')
  new=$(($(find "$crashes" -type f | wc -l) - before))
  ((new > 0 || rc != 0)) && any_crash=1
  summary+=("$(printf '%-11s %6s s %10s execs  cov %5s  corpus %5s (%6s files)  %3s new crash files (exit %s)' \
    "$t" "$seconds" "${execs:-?}" "${cov:-?}" "${corp:-?}" "$(find "$corpus" -type f | wc -l)" "$new" "$rc")")
  if ((rc != 0)); then
    grep -m1 -E '^==[0-9]+==ERROR|runtime error|deadly signal|uncaught|terminate' "$build/fuzz_$t.log" >&2 || true
    log "$t: see $build/fuzz_$t.log and $crashes/"
  fi
done
log "summary (per target: seconds, executions, coverage edges, corpus kept (files on disk), crashes)"
printf '%s\n' "${summary[@]}"
exit "$any_crash"
