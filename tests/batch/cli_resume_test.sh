#!/usr/bin/env bash
# An interrupted batch run (SIGKILL after the first model, through the test hook, and once more
# at a random moment) resumes to the same result as an uninterrupted run: byte-identical splat
# PLYs and .csm files, the same statuses, no temporaries left, finished models reused. The
# uninterrupted run uses --jobs 2, so this also checks that parallel jobs give the same bytes.
. "$(dirname "$0")/cli_common.sh" "$1" "$2"
for name in a-cube b-wedge c-cube d-wedge; do
  case $name in *cube) printf '%s\n' "$cube" ;; *) printf '%s\n' "$wedge" ;; esac > "$work/meshes/$name.obj"
done
printf '# a tall cube, so c differs from a\n' >> "$work/meshes/c-cube.obj"
cat > "$work/set.json" <<'JSON'
{"defaults": {"maps": 64, "res": 32, "k": 8},
 "models": ["meshes/a-cube.obj", "meshes/b-wedge.obj", {"path": "meshes/c-cube.obj", "samples": "grid:2"},
            {"path": "meshes/d-wedge.obj", "dist": "regular", "encoding": "compact"}]}
JSON

"$splatcl" batch "$work/set.json" -o "$work/whole" --jobs 2 > "$work/whole.log" || fail "uninterrupted run failed: $(cat "$work/whole.log")"

# Killed by the hook after the 7th file write: model a complete (5 files), b half-written.
SPLATCL_BATCH_KILL_AFTER_WRITES=7 "$splatcl" batch "$work/set.json" -o "$work/killed" > "$work/killed.log" 2>&1
status=$?
[ "$status" -eq 137 ] || fail "expected the hook to kill the run (status 137), got $status: $(cat "$work/killed.log")"
[ -f "$work/killed/a-cube.batch.json" ] || fail "model a has no record after the kill"
[ -f "$work/killed/b-wedge.splats.ply" ] || fail "model b's splats were not written before the kill"
[ ! -f "$work/killed/b-wedge.batch.json" ] || fail "model b has a record although the kill came before it"
[ ! -f "$work/killed/summary.json" ] || fail "a killed run left a summary"
# Something half-written in the meantime (a kill inside a write leaves a temporary).
printf 'half' > "$work/killed/b-wedge.csm.tmp12345"

"$splatcl" batch "$work/set.json" -o "$work/killed" > "$work/resumed.log" || fail "resumed run failed: $(cat "$work/resumed.log")"
grep -q '^reused  a-cube' "$work/resumed.log" || fail "model a was not reused: $(cat "$work/resumed.log")"
grep -q '^ok      b-wedge (splats built' "$work/resumed.log" || fail "model b was not rebuilt: $(cat "$work/resumed.log")"

# A second interruption at an arbitrary moment, then resume.
"$splatcl" batch "$work/set.json" -o "$work/random" > /dev/null 2>&1 &
pid=$!
sleep 0.7
kill -KILL "$pid" 2> /dev/null
wait "$pid" 2> /dev/null
"$splatcl" batch "$work/set.json" -o "$work/random" > "$work/random.log" || fail "resume after a random kill failed: $(cat "$work/random.log")"

for run in killed random; do
  for model in a-cube b-wedge c-cube d-wedge; do
    for file in "$model.splats.ply" "$model.csm"; do
      cmp -s "$work/whole/$file" "$work/$run/$file" || fail "$run/$file differs from the uninterrupted run"
    done
  done
  [ "$(statuses "$work/whole/summary.json")" = "$(statuses "$work/$run/summary.json")" ] || fail "$run: statuses differ"
  leftovers=$(find "$work/$run" -name '*.tmp*')
  [ -z "$leftovers" ] || fail "$run: temporaries left: $leftovers"
done
[ "$(grep -c '"status": "ok"' "$work/whole/summary.json")" -eq 4 ] || fail "not every model ok"

# A third run reuses everything and still writes the same statuses.
"$splatcl" batch "$work/set.json" -o "$work/killed" > "$work/again.log" || fail "third run failed"
[ "$(grep -c '^reused' "$work/again.log")" -eq 4 ] || fail "a complete run was not fully reused: $(cat "$work/again.log")"

# A run killed while it rewrites outputs leaves no summary: the earlier one named the files as they
# were before it (an interrupted --k 9 run left the k 8 summary beside k 9 splats).
SPLATCL_BATCH_KILL_AFTER_WRITES=1 "$splatcl" batch "$work/set.json" -o "$work/killed" --k 9 > /dev/null 2>&1
[ $? -eq 137 ] || fail "expected the hook to kill the --k 9 run"
[ ! -f "$work/killed/summary.json" ] || fail "a run killed while rewriting outputs left the earlier summary"
"$splatcl" batch "$work/set.json" -o "$work/killed" > /dev/null || fail "the run after the --k 9 kill failed"
# A run refused before any work (no such device) leaves the earlier summary alone.
"$splatcl" batch "$work/set.json" -o "$work/killed" --device no-such-device > /dev/null 2>&1 && fail "a run on no device was not refused"
[ -f "$work/killed/summary.json" ] || fail "a run refused for its device removed the earlier summary"

# The native reference does not pass off the OpenCL run's files as its own: it rebuilds them.
"$splatcl" batch "$work/set.json" -o "$work/killed" --reference > "$work/reference.log" || fail "reference run failed: $(cat "$work/reference.log")"
! grep -q '^reused' "$work/reference.log" || fail "--reference reused an OpenCL run's outputs: $(cat "$work/reference.log")"
grep -q '"made_by": "reference"' "$work/killed/a-cube.batch.json" || fail "the record does not say the reference made the outputs"
echo "ok: interrupted runs resume to the uninterrupted result"
