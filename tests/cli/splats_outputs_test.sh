#!/usr/bin/env bash
# splats_outputs_test.sh MODE SPLATCL WORKDIR EXPECT_ERROR: `splatcl splats` leaves nothing at
# -o (nor at --stats, nor staged leftovers) when another output fails, and an -o file from an
# earlier run stays as it was.
#   stats:  --stats into a missing directory: refused before any work, with one line naming it;
#   render: --render to an image format that does not exist: refused before any work (until
#           2026-12-07 it failed after the splats were computed, and then too left nothing).
set -u
mode=$1 splatcl=$2 work=$3 expect_error=$4
fail() { echo "FAIL: $*"; exit 1; }
rm -rf "$work" && mkdir -p "$work"
out=$work/out.ply
quad=$work/quad.obj  # tiny, so the run that fails late takes seconds
printf 'v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n' >"$quad"
run() {  # PATTERN EXTRA_OPTIONS...
  local pattern=$1; shift
  "$expect_error" "$pattern" "$splatcl" splats "$quad" --samples grid:2 --reference -o "$out" "$@" ||
    fail "the run did not fail as expected"
}
case $mode in
  stats)
    run "cannot write --stats .*no-such-dir/stats.json: directory .*no-such-dir does not exist" --stats "$work/no-such-dir/stats.json"
    [ -e "$out" ] && fail "-o $out was written although --stats cannot be" ;;
  render)
    run "--render $work/picture.nosuchformat: the file must end in .png or .exr" --stats "$work/stats.json" --render "$work/picture.nosuchformat"
    [ -e "$out" ] && fail "-o $out was written although --render failed"
    [ -e "$work/stats.json" ] && fail "--stats was written although --render failed"
    # An earlier result stays untouched.
    echo "earlier result" >"$out"
    run "--render $work/picture.nosuchformat: the file must end in .png or .exr" --render "$work/picture.nosuchformat"
    [ "$(cat "$out")" = "earlier result" ] || fail "-o $out was replaced although --render failed" ;;
  *) fail "unknown mode $mode" ;;
esac
leftovers=$(find "$work" -name '*partial*' -o -name '*tmp*')
[ -z "$leftovers" ] || fail "staged files left behind: $leftovers"
echo "ok: $mode"
