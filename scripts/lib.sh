# Shared by scripts/demo.sh and scripts/test.sh: install what is missing,
# configure and build. Source it; do not run it.
set -euo pipefail

CLOTHBAKE_ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
CLOTHBAKE_BUILD=${CLOTHBAKE_BUILD:-$CLOTHBAKE_ROOT/build}

log() { printf '\033[1m[clothbake]\033[0m %s\n' "$*" >&2; }

# Installs the packages of scripts/packages.txt that are not installed yet
# (apt, idempotent: a second run installs nothing and touches no index).
install_packages() {
  local wanted missing=()
  mapfile -t wanted < <(grep -v '^\s*#' "$CLOTHBAKE_ROOT/scripts/packages.txt" | grep -v '^\s*$')
  for pkg in "${wanted[@]}"; do
    dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q 'install ok installed' || missing+=("$pkg")
  done
  if ((${#missing[@]} == 0)); then
    log "all ${#wanted[@]} packages present"
    return
  fi
  log "installing ${#missing[@]} missing packages: ${missing[*]}"
  local sudo=()
  [[ $(id -u) -eq 0 ]] || sudo=(sudo)
  export DEBIAN_FRONTEND=noninteractive
  "${sudo[@]}" apt-get update -qq
  "${sudo[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
  log "packages installed"
}

# The compiler flags of the sanitised build (scripts/test.sh --sanitize):
# AddressSanitizer and UBSan, any UB fatal (no recovering past it).
CLOTHBAKE_SANITIZE_FLAGS="-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=all"

# Configures (Release, Ninja) and builds everything: library, CLI, tests, benchmarks.
# With CLOTHBAKE_SANITIZE=1: RelWithDebInfo (stack traces with lines) built with
# CLOTHBAKE_SANITIZE_FLAGS, no benchmarks.
build_all() {
  local args=(-DCMAKE_BUILD_TYPE=Release)
  if [[ ${CLOTHBAKE_SANITIZE:-0} == 1 ]]; then
    args=(-DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_CXX_FLAGS=$CLOTHBAKE_SANITIZE_FLAGS"
      "-DCMAKE_EXE_LINKER_FLAGS=-fsanitize=address,undefined" -DCLOTHBAKE_BUILD_BENCHMARKS=OFF)
  fi
  log "configuring $CLOTHBAKE_BUILD"
  cmake -S "$CLOTHBAKE_ROOT" -B "$CLOTHBAKE_BUILD" -G Ninja "${args[@]}" \
    ${CLOTHBAKE_CMAKE_ARGS:-} >/dev/null
  log "building"
  cmake --build "$CLOTHBAKE_BUILD" -j "$(nproc)"
}
