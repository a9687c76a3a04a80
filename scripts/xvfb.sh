# Blender's real window needs an X display: sourced by the scripts and tests
# that open it (tests/blender/ui_new_user.sh, ui_wif_panel.sh,
# lab/material_preview/material_preview.sh).
#
# start_xvfb LOG_DIR [FIRST]: starts Xvfb (1600 x 1000 x 24) on the first free
# display from :FIRST (default 90) on, sets xvfb_pid and display; on failure
# prints why (LOG_DIR/xvfb.log) and returns 1. The caller's cleanup kills
# $xvfb_pid. Tests that may run side by side start from different FIRSTs only
# for speed: a display in use is skipped by its lock file, and Xvfb refuses
# one taken meanwhile, whereupon the next is tried.
start_xvfb() {
  local log=$1/xvfb.log first=${2:-90} n
  command -v Xvfb >/dev/null || { echo "FAIL: Xvfb not installed (scripts/packages.txt: xvfb)"; return 1; }
  for n in $(seq "$first" $((first + 40))); do
    [[ -e /tmp/.X$n-lock ]] && continue
    Xvfb ":$n" -screen 0 1600x1000x24 -nolisten tcp >"$log" 2>&1 &
    xvfb_pid=$!
    sleep 1
    if kill -0 "$xvfb_pid" 2>/dev/null; then display=:$n; return 0; fi
    xvfb_pid=
  done
  cat "$log"
  echo "FAIL: no Xvfb display"
  return 1
}
