#!/usr/bin/env bash
# Failing models (missing, empty, non-finite, degenerate) are reported with their reason, the rest
# complete, and the exit status is 2 with one line on stderr.
. "$(dirname "$0")/cli_common.sh" "$1" "$2"
printf '%s\n' "$cube" > "$work/meshes/cube.obj"
printf 'v 0 0 0\n' > "$work/meshes/empty.obj"
printf 'v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n' > "$work/meshes/nan.obj"
printf 'v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n' > "$work/meshes/flat.obj"
printf 'path\nmeshes/missing.obj\nmeshes/cube.obj\nmeshes/empty.obj\nmeshes/nan.obj\nmeshes/flat.obj\n' > "$work/set.csv"
"$splatcl" batch "$work/set.csv" -o "$work/out" --maps 64 --res 32 > "$work/out.log" 2> "$work/err.log"
status=$?
[ "$status" -eq 2 ] || fail "expected exit status 2, got $status"
[ "$(wc -l < "$work/err.log")" -eq 1 ] || fail "expected one line on stderr: $(cat "$work/err.log")"
grep -q "batch: 4 of 5 models failed (reasons in $work/out/summary.json)" "$work/err.log" || fail "stderr: $(cat "$work/err.log")"
grep -q '^ok      cube' "$work/out.log" || fail "the good model did not complete: $(cat "$work/out.log")"
for model in missing empty nan flat; do
  grep -q "^FAILED  $model: .*$model.obj\|^FAILED  $model: .*degenerate" "$work/out.log" || fail "no reason for $model: $(cat "$work/out.log")"
done
[ -f "$work/out/cube.splats.ply" ] && [ -f "$work/out/cube.csm" ] || fail "the good model's outputs are missing"
[ "$(grep -c '"reason": ' "$work/out/summary.json")" -eq 4 ] || fail "the summary does not give 4 reasons"
echo "ok: failures reported, the rest complete, exit status 2"
