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

# Configures (Release, Ninja) and builds everything: library, CLI, tests, benchmarks.
build_all() {
  log "configuring $CLOTHBAKE_BUILD"
  cmake -S "$CLOTHBAKE_ROOT" -B "$CLOTHBAKE_BUILD" -G Ninja -DCMAKE_BUILD_TYPE=Release \
    ${CLOTHBAKE_CMAKE_ARGS:-} >/dev/null
  log "building"
  cmake --build "$CLOTHBAKE_BUILD" -j "$(nproc)"
}
