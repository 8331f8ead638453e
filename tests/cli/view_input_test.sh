#!/usr/bin/env bash
# view_input_test.sh SPLATCL CACHE: the real window under Xvfb, driven by X input events (xdotool,
# through the XTEST extension, as a keyboard and mouse would): a click where the box's centre is
# drawn (at 200x150, time 0: pixel 129, 65; the torus lies in front of it there), ten quick taps of C
# and four of Tab as soon as the window is there (they all reach the first frame), then, while
# frames run, nine more taps of C and three wheel steps up 25 ms apart, then Esc. Every tap and
# wheel step must arrive exactly once, whatever the frame time: shading 19 steps on (clustered ->
# tiled), the click picks the nearest object (torus), four Tabs on from it select the sphere, the
# distance is 0.85^3 of the start. Skips (77) without xdotool.
set -u
splatcl=$1 cache=$2
command -v xdotool >/dev/null || { echo "skip: xdotool is not installed"; exit 77; }
log=$(mktemp) || exit 1
trap 'rm -f "$log"' EXIT
xvfb-run -a -s "-screen 0 640x480x24" bash -c '
  "$0" view --size 200x150 --no-panel --paused --seconds 120 --cache "$1" > "$2" 2>&1 & pid=$!
  wid=$(timeout 120 xdotool search --sync --name "^splatcl view" | head -n 1)
  [ -n "$wid" ] || { kill $pid; exit 1; }
  # No window manager: the keyboard follows the pointer.
  xdotool mousemove --window "$wid" 129 65
  xdotool click 1
  xdotool key --delay 2 c c c c c c c c c c Tab Tab Tab Tab
  sleep 3
  xdotool key --delay 25 c c c c c c c c c
  xdotool click --repeat 3 --delay 25 4
  xdotool key Escape
  wait $pid' "$splatcl" "$cache" "$log"
status=$?
fail() { echo "FAIL: $*"; cat "$log"; exit 1; }
[ "$status" -eq 0 ] || fail "exit status $status"
line=$(grep "^view: state " "$log") || fail "no state line"
[[ $line == *"shading tiled,"* ]] || fail "19 taps of C did not give 19 steps: $line"
[[ $line == *"last pick: picked torus" ]] || fail "the click did not pick the torus in front of the box: $line"
[[ $line == *"selected sphere,"* ]] || fail "four taps of Tab after the torus did not select the sphere: $line"
read -r distance start < <(sed -E 's/.*distance ([0-9.]+) \(start ([0-9.]+)\).*/\1 \2/' <<< "$line")
awk -v d="$distance" -v s="$start" 'BEGIN { e = s * 0.85 ^ 3; exit !(d > e - 1e-3 && d < e + 1e-3) }' ||
  fail "three wheel steps: distance $distance, not 0.85^3 of $start"
frames=$(grep -oE "^view: [0-9]+ frames" "$log")
echo "ok: $line ($frames)"
