#!/usr/bin/env bash
# view_input_test.sh SPLATCL CACHE: the real window under Xvfb, driven by X input events (xdotool,
# through the XTEST extension, as a keyboard and mouse would); each run checks the state `view`
# prints on exit. Skips (77) without xdotool.
# 1. The scene (--no-panel, 200x150): a click where the box's centre is drawn (at time 0: pixel
#    129, 65; the torus lies in front of it there), ten quick taps of C and four of Tab as soon as
#    the window is there (they all reach the first frame), then, while frames run, nine more taps
#    of C and three wheel steps up 25 ms apart, then Esc. Every tap and wheel step must arrive
#    exactly once, whatever the frame time: shading 19 steps on (clustered -> tiled), the click
#    picks the nearest object (torus), four Tabs on from it select the sphere, the distance is
#    0.85^3 of the start.
# 2. The panel (640x480, started hidden): a wheel step over the scene, F1, a move off the panel,
#    then a move onto its "tiled" radio button (pixel 205, 118: the panel's first section, below
#    three lines of readouts) and a click at once (before any frame sees the move), two wheel
#    steps over the panel, Esc: the first step zooms; the panel's button sets
#    tiled shading, and its click picks nothing and its wheel steps zoom nothing.
set -u
splatcl=$1 cache=$2
command -v xdotool >/dev/null || { echo "skip: xdotool is not installed"; exit 77; }
log=$(mktemp) || exit 1
trap 'rm -f "$log"' EXIT
fail() { echo "FAIL: $*"; cat "$log"; exit 1; }
# run_view SIZE XDOTOOL-SCRIPT VIEW-OPTIONS...: the state line of a run ($wid is the window).
run_view() {
  local size=$1 actions=$2; shift 2
  xvfb-run -a -s "-screen 0 800x600x24" bash -c '
    log=$1 actions=$2; shift 2
    "$@" > "$log" 2>&1 & pid=$!
    wid=$(timeout 120 xdotool search --sync --name "^splatcl view" | head -n 1)
    [ -n "$wid" ] || { kill $pid; exit 1; }
    eval "$actions"
    wait $pid' run "$log" "$actions" "$splatcl" view --size "$size" --paused --seconds 120 --cache "$cache" "$@"
  local status=$?
  [ "$status" -eq 0 ] || fail "exit status $status"
  grep "^view: state " "$log" || fail "no state line"
}
distance_is() {  # distance_is LINE FACTOR: the distance is FACTOR times the start
  local distance start
  read -r distance start < <(sed -E 's/.*distance ([0-9.]+) \(start ([0-9.]+)\).*/\1 \2/' <<< "$1")
  awk -v d="$distance" -v s="$start" -v f="$2" 'BEGIN { e = s * f; exit !(d > e - 1e-3 && d < e + 1e-3) }'
}

# No window manager: the keyboard follows the pointer.
line=$(run_view 200x150 '
  xdotool mousemove --window "$wid" 129 65
  xdotool click 1
  xdotool key --delay 2 c c c c c c c c c c Tab Tab Tab Tab
  sleep 3
  xdotool key --delay 25 c c c c c c c c c
  xdotool click --repeat 3 --delay 25 4
  xdotool key Escape' --no-panel) || exit 1
[[ $line == *"shading tiled,"* ]] || fail "19 taps of C did not give 19 steps: $line"
[[ $line == *"last pick: picked torus" ]] || fail "the click did not pick the torus in front of the box: $line"
[[ $line == *"selected sphere,"* ]] || fail "four taps of Tab after the torus did not select the sphere: $line"
distance_is "$line" 0.614125 || fail "three wheel steps did not zoom by 0.85^3: $line"
echo "ok: $line"

line=$(run_view 640x480 '
  sleep 2
  xdotool mousemove --window "$wid" 205 118 click 4
  sleep 0.5
  xdotool key F1
  xdotool mousemove --window "$wid" 600 50
  sleep 1.5
  xdotool mousemove --window "$wid" 205 118 click 1
  sleep 1.5
  xdotool click --repeat 2 --delay 25 4
  sleep 1
  xdotool key Escape' --no-panel) || exit 1
[[ $line == *"shading tiled,"* ]] || fail "the panel's tiled button did not set tiled shading: $line"
[[ $line == *"panel on,"* ]] || fail "F1 did not show the panel: $line"
[[ $line == *"last pick: -" ]] || fail "the click on the panel was taken for a click on the scene: $line"
distance_is "$line" 0.85 || fail "the wheel over the scene did not zoom, or the one over the panel did: $line"
echo "ok: $line"
