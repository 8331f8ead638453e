#!/usr/bin/env bash
# view_panel_test.sh SPLATCL CACHE WORKDIR: splatcl view under Xvfb, paused, shot at exit with the
# panel shown and hidden. The panel never reaches the presenter's image: the image with the panel
# equals the image without it bit for bit; the window without the panel equals the image, the
# window with it does not; the panel drew on every frame and its cost is printed.
set -u
splatcl=$1 cache=$2 work=$3
rm -rf "$work" && mkdir -p "$work/panel" "$work/hidden" || exit 1
fail() { echo "FAIL: $*"; exit 1; }
run() {  # run DIR EXTRA...
  local dir=$1; shift
  xvfb-run -a "$splatcl" view --size 200x150 --seconds 3 --paused --screenshot-on-exit --screenshots "$dir" --cache "$cache" "$@" \
    > "$dir/log" 2>&1 || { cat "$dir/log"; fail "splatcl view $* exited non-zero"; }
}
run "$work/panel"
run "$work/hidden" --no-panel
grep -qE "^view: [1-9][0-9]* frames, [0-9.]+ ms per frame; panel on [1-9][0-9]* frames, [0-9.]+ ms per frame$" "$work/panel/log" ||
  { cat "$work/panel/log"; fail "no panel line in the log"; }
grep -qE "^view: [1-9][0-9]* frames, .*; panel hidden$" "$work/hidden/log" || { cat "$work/hidden/log"; fail "the panel was not hidden"; }
for d in panel hidden; do
  for f in splatcl-view-000.png splatcl-view-window-000.png; do
    [ "$(head -c 8 "$work/$d/$f" 2>/dev/null | od -An -tx1 | tr -d ' \n')" = "89504e470d0a1a0a" ] || fail "$d/$f is not a PNG"
  done
done
cmp -s "$work/panel/splatcl-view-000.png" "$work/hidden/splatcl-view-000.png" || fail "the panel changed the presenter's image"
cmp -s "$work/hidden/splatcl-view-000.png" "$work/hidden/splatcl-view-window-000.png" || fail "without the panel the window differs from the image"
! cmp -s "$work/panel/splatcl-view-000.png" "$work/panel/splatcl-view-window-000.png" || fail "the panel is not in the window"
echo "ok: panel in the window only ($(grep -o 'panel on .*' "$work/panel/log"))"
