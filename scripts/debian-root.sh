#!/usr/bin/env bash
# Real Debian roots for the add-on's Blenders: a debootstrap root per suite in
# which clothbake is built and Debian's own Blender runs.
#
#   scripts/debian-root.sh SUITE setup          make the root (first use only) and build
#   scripts/debian-root.sh SUITE run CMD...     run CMD in the root as root
#   scripts/debian-root.sh SUITE status         root, Blender, Python, build state, pins
#   scripts/debian-root.sh SUITE purge          remove the root (unmounting first)
#
# SUITE: trixie (Debian 13: Blender 4.3, Python 3.13, GCC 14, OpenImageIO 2.5,
# oneTBB 2022) or sid (Debian unstable: Blender 5.x, Python 3.14).
#
# The root is made once, in ${CLOTHBAKE_ROOTS:-/var/cache/clothbake-roots}/SUITE,
# from the Debian mirror the host's apt uses (CLOTHBAKE_DEBIAN_MIRROR overrides):
# debootstrap --variant=minbase, then Blender, python3-numpy, Xvfb, fonts and
# the build dependencies of scripts/packages.txt that exist in the suite, with
# --no-install-recommends. The downloaded .debs are kept in
# CLOTHBAKE_ROOTS/debs-SUITE, so a purge and a new setup download nothing again.
# A second setup changes nothing; setup and purge hold an exclusive flock on
# CLOTHBAKE_ROOTS/SUITE.lock, run a shared one (runs side by side are fine).
#
# clothbake is built inside the root into build-SUITE/ of this checkout
# (cmake -G Ninja, Release, nice -n 15, -j${CLOTHBAKE_ROOT_JOBS:-2}; every
# target, or CLOTHBAKE_ROOT_TARGETS); `run` brings that build up to date first
# (CLOTHBAKE_ROOT_BUILD=0 skips it) and puts it and the root's blender on the PATH.
#
# Mounts: every command in the root runs in a private mount namespace
# (unshare -m), where the checkout and /tmp are bind-mounted at their own paths
# (a path means the same inside and out) with /proc, /dev and /sys. The mounts
# exist only in that namespace: they vanish with its last process, however it
# ends (Ctrl-C, kill -9), and are never seen by the host, so nothing is left
# mounted and purge cannot remove through a live bind mount of the checkout.
#
# CLOTHBAKE_ROOT_NO_NUMPY=1 runs CMD as on a system without python3-numpy
# (numpy's package is covered in that run's namespace by one that fails to
# import), for the add-on's message on a Blender without numpy.
#
# Pins: the root is made once and never updated by this script, so it stays at
# the versions it got. Those versions and the date of the mirror's Release file
# are written to /etc/clothbake-root in the root and printed by setup and
# status. CLOTHBAKE_BLENDER_VERSION=VERSION installs exactly that blender (a
# new root; apt fails if the mirror no longer has it); blender is held
# (apt-mark hold). Unstable's Release file on the mirror has expired, so apt in
# the sid root runs with Acquire::Check-Valid-Until=false.
set -euo pipefail

CHECKOUT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd -P)
SELF=$CHECKOUT/scripts/debian-root.sh
ROOTS=${CLOTHBAKE_ROOTS:-/var/cache/clothbake-roots}
JOBS=${CLOTHBAKE_ROOT_JOBS:-2}

log() { printf '\033[1m[debian-root %s]\033[0m %s\n' "${SUITE:-}" "$*" >&2; }
die() { log "ERROR: $*"; exit 1; }
usage() {
  sed -n '2,12p' "$SELF" | sed 's/^# \{0,1\}//' >&2
  exit 2
}

(($# >= 2)) || usage
SUITE=$1 ACTION=$2
shift 2
case $SUITE in trixie | sid) ;; *) usage ;; esac
ROOT=$ROOTS/$SUITE
BUILD=$CHECKOUT/build-$SUITE
DEBS=$ROOTS/debs-$SUITE
STAMP=etc/clothbake-root # in the root: written last by setup, with the pins

# Packages of scripts/packages.txt that a root does not get: the farm's daemons
# (Slurm, munge), the fuzzer's clang, the profiler and debootstrap stay on the host.
SKIP_PACKAGES=${CLOTHBAKE_ROOT_SKIP:-"slurm-wlm munge clang libclang-rt-dev debootstrap linux-perf"}
# Wanted beyond packages.txt: Debian's Blender 5.x cannot register its
# extensions system (bl_pkg) without cattrs (python3-cattr) and requests
# (python3-requests), both only recommended; xvfb-run needs xauth. Names a
# suite does not have are skipped.
EXTRA_PACKAGES="python3-cattr python3-cattrs python3-requests xauth fonts-dejavu-core ca-certificates"

# The Debian mirror of the host's apt (deb822 URIs or one-line deb entries),
# not its security archive.
host_mirror() {
  [[ -n ${CLOTHBAKE_DEBIAN_MIRROR:-} ]] && { echo "$CLOTHBAKE_DEBIAN_MIRROR"; return; }
  local url
  url=$({
    grep -hsE '^\s*URIs:' /etc/apt/sources.list.d/*.sources 2>/dev/null |
      sed -E 's/^\s*URIs:\s*//' | tr ' ' '\n'
    grep -hsE '^\s*deb\s' /etc/apt/sources.list /etc/apt/sources.list.d/*.list 2>/dev/null |
      sed -E 's/^\s*deb\s+(\[[^]]*\]\s+)?//' | awk '{print $1}'
  } | grep -E '^(https?|file)://.*/debian/?$' | head -1)
  echo "${url:-http://deb.debian.org/debian}"
}

# --- the namespace side: mounts, then chroot ---------------------------------
# `debian-root.sh SUITE __enter ROOTDIR CWD CMD...` runs inside unshare -m.
if [[ $ACTION == __enter ]]; then
  target=$1 cwd=$2
  shift 2
  mount --make-rprivate /
  mount -t proc proc "$target/proc"
  mount --rbind /dev "$target/dev"
  mount --rbind /sys "$target/sys"
  mkdir -p "$target/tmp"
  mount --bind /tmp "$target/tmp"
  case $CHECKOUT/ in
    /tmp/*) ;; # already there through /tmp
    *) mkdir -p "$target$CHECKOUT" && mount --bind "$CHECKOUT" "$target$CHECKOUT" ;;
  esac
  if [[ -n ${CLOTHBAKE_ROOT_DEBS:-} ]]; then # setup: apt's archive is the shared cache
    mkdir -p "$target/var/cache/apt/archives"
    mount --bind "$CLOTHBAKE_ROOT_DEBS" "$target/var/cache/apt/archives"
  fi
  if [[ ${CLOTHBAKE_ROOT_NO_NUMPY:-0} == 1 && -d $target/usr/lib/python3/dist-packages/numpy ]]; then
    # As if python3-numpy were not installed: its package is covered, in
    # this namespace only, by one that fails to import as a missing one does.
    stub=$target/var/lib/clothbake-root/no-numpy
    mkdir -p "$stub"
    echo 'raise ModuleNotFoundError("No module named '"'numpy'"'", name="numpy")' >"$stub/__init__.py"
    mount --bind "$stub" "$target/usr/lib/python3/dist-packages/numpy"
  fi
  cp -L /etc/resolv.conf "$target/etc/resolv.conf" 2>/dev/null || true
  # Blender lists the mounted file systems through /etc/mtab, which minbase lacks.
  [[ -e $target/etc/mtab ]] || ln -sf ../proc/self/mounts "$target/etc/mtab"
  path=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin
  [[ -d $BUILD/baker ]] && path=$BUILD/baker:$path
  envs=(HOME=/root PATH="$path" LANG=C.UTF-8 TERM="${TERM:-dumb}" DEBIAN_FRONTEND=noninteractive
    CLOTHBAKE_DEBIAN_ROOT="$SUITE")
  # Passed through: the project's own settings, a display, CI.
  while IFS='=' read -r name _; do
    case $name in CLOTHBAKE_* | DISPLAY | XAUTHORITY | CI | BLENDER_* | PYTHON*) envs+=("$name=${!name}") ;; esac
  done < <(env)
  exec chroot "$target" /usr/bin/env -i "${envs[@]}" /bin/bash -c 'cd "$1" 2>/dev/null || cd /; shift; exec "$@"' \
    bash "$cwd" "$@"
fi

# in_root ROOTDIR CWD CMD...: CMD in ROOTDIR through a private mount namespace.
in_root() {
  # The locks stay with this script, not with what the root leaves running.
  unshare -m --propagation private "$SELF" "$SUITE" __enter "$@" 8>&- 9>&-
}

# Mount points under DIR seen by this namespace (there should be none).
mounts_under() {
  awk -v d="$1" '{ p = $5; gsub(/\\040/, " ", p); if (p == d || index(p, d "/") == 1) print p }' /proc/self/mountinfo
}

apt_opts() {
  local o=(-o APT::Install-Recommends=false -o Acquire::Languages=none)
  [[ $SUITE == sid ]] && o+=(-o Acquire::Check-Valid-Until=false)
  echo "${o[@]}"
}

lock() { # lock -x|-s: on fd 9
  mkdir -p "$ROOTS"
  exec 9>"$ROOTS/$SUITE.lock"
  flock "$1" 9
}

ready() { [[ -f $ROOT/$STAMP ]]; }

# Makes ROOT (once): debootstrap into ROOT.partial, configure apt, install,
# write the pins, then rename. An interrupted setup leaves only ROOT.partial,
# which the next setup removes and starts again.
make_root() {
  local part=$ROOT.partial mirror start
  mirror=$(host_mirror)
  start=$SECONDS
  command -v debootstrap >/dev/null || die "debootstrap is not installed (apt-get install debootstrap)"
  if [[ -e $part ]]; then
    [[ -z $(mounts_under "$part") ]] || die "$part has mounts ($(mounts_under "$part" | tr '\n' ' ')); not removing"
    log "removing an interrupted $part"
    rm -rf --one-file-system "$part"
  fi
  mkdir -p "$DEBS"
  log "debootstrap $SUITE from $mirror into $part"
  # In a private mount namespace too: the /proc and /sys that debootstrap
  # mounts in the target go away with it whatever happens.
  unshare -m --propagation private debootstrap --variant=minbase --include=apt-utils,ca-certificates \
    --cache-dir="$DEBS" "$SUITE" "$part" "$mirror" >"$ROOTS/$SUITE.debootstrap.log" 2>&1 ||
    { tail -20 "$ROOTS/$SUITE.debootstrap.log" >&2; die "debootstrap failed (log: $ROOTS/$SUITE.debootstrap.log)"; }
  log "debootstrap done in $((SECONDS - start)) s"

  echo "deb $mirror $SUITE main" >"$part/etc/apt/sources.list"
  rm -f "$part"/etc/apt/sources.list.d/*
  {
    echo 'APT::Install-Recommends "false";'
    echo 'APT::Install-Suggests "false";'
    echo 'Acquire::Languages "none";'
    echo 'Binary::apt::APT::Keep-Downloaded-Packages "true";'
    [[ $SUITE == sid ]] && echo 'Acquire::Check-Valid-Until "false";'
  } >"$part/etc/apt/apt.conf.d/90clothbake"
  rm -f "$part/etc/apt/apt.conf.d/docker-clean"
  # No services start in the root.
  printf '#!/bin/sh\nexit 101\n' >"$part/usr/sbin/policy-rc.d"
  chmod +x "$part/usr/sbin/policy-rc.d"

  local t=$SECONDS
  CLOTHBAKE_ROOT_DEBS=$DEBS in_root "$part" / apt-get update -qq ||
    die "apt-get update in the root failed"
  # The wanted names that this suite has (apt-cache in the root decides).
  local wanted=() have=() missing=() pkg
  mapfile -t wanted < <({ grep -v '^\s*#' "$CHECKOUT/scripts/packages.txt" | grep -v '^\s*$'; tr ' ' '\n' <<<"$EXTRA_PACKAGES"; } |
    awk 'NF' | sort -u)
  local skip=" $SKIP_PACKAGES "
  for pkg in "${wanted[@]}"; do [[ $skip == *" $pkg "* ]] && continue; have+=("$pkg"); done
  mapfile -t missing < <(in_root "$part" / bash -c 'for p; do [ -n "$(apt-cache policy "$p" 2>/dev/null | sed -n "s/^ *Candidate: //p" | grep -v "(none)")" ] || echo "$p"; done' \
    bash "${have[@]}")
  local install=()
  for pkg in "${have[@]}"; do
    [[ " ${missing[*]} " == *" $pkg "* ]] && continue
    if [[ $pkg == blender && -n ${CLOTHBAKE_BLENDER_VERSION:-} ]]; then pkg=blender=$CLOTHBAKE_BLENDER_VERSION; fi
    install+=("$pkg")
  done
  ((${#missing[@]} == 0)) || log "not in $SUITE, skipped: ${missing[*]}"
  log "installing ${#install[@]} packages (and their dependencies)"
  CLOTHBAKE_ROOT_DEBS=$DEBS in_root "$part" / apt-get install -y -q --no-install-recommends "${install[@]}" \
    >"$ROOTS/$SUITE.apt.log" 2>&1 ||
    { tail -30 "$ROOTS/$SUITE.apt.log" >&2; die "apt-get install failed (log: $ROOTS/$SUITE.apt.log)"; }
  in_root "$part" / apt-mark hold blender >/dev/null
  log "packages installed in $((SECONDS - t)) s"

  # The pins: the mirror's Release date and the versions that matter.
  local release_date
  release_date=$(sed -n 's/^Date: //p' "$part"/var/lib/apt/lists/*_dists_"${SUITE}"_*Release 2>/dev/null | head -1)
  {
    echo "suite=$SUITE"
    echo "mirror=$mirror"
    echo "release_date=$release_date"
    echo "made_in_seconds=$((SECONDS - start))"
    in_root "$part" / dpkg-query -W -f='pkg ${Package}=${Version}\n' blender python3 python3-numpy python3-cattr \
      g++ cmake ninja-build libopenimageio-dev libtbb-dev libopenvdb-dev libopenexr-dev libeigen3-dev xvfb 2>/dev/null || true
  } >"$part/$STAMP.new"
  mv "$part/$STAMP.new" "$part/$STAMP"
  mv "$part" "$ROOT"
  log "root ready in $((SECONDS - start)) s: $ROOT"
}

print_pins() {
  log "pinned (made once, never updated; $ROOT/$STAMP):"
  sed 's/^pkg /  /; s/^/  /' "$ROOT/$STAMP" >&2
}

# Configures (once) and brings build-SUITE up to date, in the root.
# Two builders of one build folder would trample each other: the build holds
# an exclusive flock on BUILD/.root-build.lock (fd 8), apart from the root's.
build() {
  local t=$SECONDS
  mkdir -p "$BUILD"
  exec 8>"$BUILD/.root-build.lock"
  flock -x 8
  if [[ ! -f $BUILD/build.ninja ]]; then
    log "configuring $BUILD (Release, Ninja)"
    in_root "$ROOT" "$CHECKOUT" cmake -S "$CHECKOUT" -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=Release \
      ${CLOTHBAKE_CMAKE_ARGS:-} >"$BUILD/root-configure.log" 2>&1 ||
      { cat "$BUILD/root-configure.log" >&2; die "cmake configure failed in the $SUITE root"; }
  fi
  local targets=()
  read -r -a targets <<<"${CLOTHBAKE_ROOT_TARGETS:-}"
  if in_root "$ROOT" "$CHECKOUT" ninja -C "$BUILD" -n "${targets[@]}" 2>/dev/null | grep -q 'no work to do'; then
    exec 8>&-
    return 0
  fi
  log "building $BUILD in the root (nice -n 15, -j$JOBS; log: $BUILD/root-build.log)"
  if ! in_root "$ROOT" "$CHECKOUT" nice -n 15 cmake --build "$BUILD" -j "$JOBS" ${targets[@]:+--target "${targets[@]}"} >"$BUILD/root-build.log" 2>&1; then
    grep -E 'error|Error|FAILED' "$BUILD/root-build.log" | head -40 >&2
    die "the build failed in the $SUITE root (log: $BUILD/root-build.log)"
  fi
  log "built in $((SECONDS - t)) s"
  exec 8>&-
}

case $ACTION in
  setup)
    lock -x
    if ready; then
      log "root present: $ROOT"
    else
      make_root
    fi
    print_pins
    flock -s 9 # the root is made: runs may start beside the build
    build
    ;;
  run)
    (($# >= 1)) || usage
    lock -s # other runs may go on beside this one; making the root and purge wait
    if ! ready; then
      flock -x 9
      ready || make_root
      flock -s 9
    fi
    [[ ${CLOTHBAKE_ROOT_BUILD:-1} == 0 ]] || build
    cwd=$PWD
    case $cwd/ in "$CHECKOUT"/* | /tmp/*) ;; *) cwd=$CHECKOUT ;; esac
    set +e
    in_root "$ROOT" "$cwd" "$@"
    exit $?
    ;;
  status)
    if ! ready; then
      echo "$SUITE: no root at $ROOT"
      if [[ -e $ROOT.partial ]]; then
        mkdir -p "$ROOTS"
        exec 9>"$ROOTS/$SUITE.lock"
        if flock -n -x 9; then
          echo "$SUITE: an interrupted setup left $ROOT.partial (the next setup starts again)"
        else
          echo "$SUITE: being made now in $ROOT.partial"
        fi
      fi
      exit 1
    fi
    lock -s
    echo "$SUITE: root $ROOT ($(du -sh --one-file-system "$ROOT" 2>/dev/null | cut -f1))"
    sed -n 's/^\(mirror\|release_date\)=/  \1: /p' "$ROOT/$STAMP"
    echo "  blender: $(in_root "$ROOT" / blender --version 2>/dev/null | head -1)"
    echo "  python: $(in_root "$ROOT" / python3 --version 2>&1)"
    if [[ ! -f $BUILD/build.ninja ]]; then
      echo "  build: none ($BUILD)"
    elif ! (exec 8>"$BUILD/.root-build.lock" && flock -n -x 8); then
      echo "  build: being built now ($BUILD)"
    elif in_root "$ROOT" "$CHECKOUT" ninja -C "$BUILD" -n 2>/dev/null | grep -q 'no work to do'; then
      echo "  build: current ($BUILD)"
    else
      echo "  build: out of date ($BUILD; setup or run rebuilds it)"
    fi
    echo "  pinned:"
    sed -n 's/^pkg /    /p' "$ROOT/$STAMP"
    ;;
  purge)
    lock -x # waits for runs in progress
    for dir in "$ROOT" "$ROOT.partial"; do
      [[ -e $dir ]] || continue
      # Mounts live only in the runs' private namespaces; should any be seen
      # here (made by hand), unmount them and refuse if one stays.
      if [[ -n $(mounts_under "$dir") ]]; then
        log "unmounting under $dir"
        mounts_under "$dir" | sort -r | while read -r m; do umount -R "$m" 2>/dev/null || umount -l "$m" || true; done
      fi
      [[ -z $(mounts_under "$dir") ]] || die "$dir still has mounts: $(mounts_under "$dir" | tr '\n' ' ')"
      # The checkout's mount point must be an empty directory of the root.
      if [[ -d $dir$CHECKOUT ]] && [[ -n $(ls -A "$dir$CHECKOUT") ]]; then
        die "$dir$CHECKOUT is not empty: not removing $dir"
      fi
      log "removing $dir"
      rm -rf --one-file-system "$dir"
    done
    rm -f "$ROOTS/$SUITE".*.log
    log "purged $SUITE (downloaded packages stay in $DEBS; build-$SUITE/ stays in the checkout)"
    ;;
  *) usage ;;
esac
