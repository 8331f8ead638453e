#!/usr/bin/env bash
# Shards 0..N-1 of a directory of meshes cover every model exactly once (by --list and by the
# summaries they write into one output directory), and `batch merge` combines their summaries.
. "$(dirname "$0")/cli_common.sh" "$1" "$2"
for i in 1 2 3 4 5; do
  mkdir -p "$work/meshes/set$((i % 2))"
  { printf '%s\n' "$cube"; echo "# copy $i"; } > "$work/meshes/set$((i % 2))/model$i.obj"
done
args=(--maps 64 --res 32 --k 8 --reference)
"$splatcl" batch "$work/meshes" --list > "$work/all.txt" || fail "--list failed"
[ "$(wc -l < "$work/all.txt")" -eq 5 ] || fail "expected 5 models: $(cat "$work/all.txt")"
: > "$work/listed.txt"
: > "$work/ran.txt"
for shard in 0 1 2; do
  "$splatcl" batch "$work/meshes" --shard $shard/3 --list >> "$work/listed.txt" || fail "--list of shard $shard failed"
  "$splatcl" batch "$work/meshes" -o "$work/out" --shard $shard/3 "${args[@]}" > "$work/shard$shard.log" || fail "shard $shard failed"
  [ -f "$work/out/summary-$shard-of-3.json" ] || fail "shard $shard wrote no summary"
  grep -o '"id": "[^"]*"' "$work/out/summary-$shard-of-3.json" >> "$work/ran.txt"
done
[ "$(sort "$work/listed.txt")" = "$(sort "$work/all.txt")" ] || fail "listed shards do not cover the models exactly once"
[ "$(sort "$work/ran.txt" | uniq -d)" = "" ] || fail "a model ran in two shards"
[ "$(sort -u "$work/ran.txt" | wc -l)" -eq 5 ] || fail "the shards ran $(sort -u "$work/ran.txt" | wc -l) of 5 models"
"$splatcl" batch merge "$work"/out/summary-*-of-3.json -o "$work/merged.json" > "$work/merge.log" || fail "merge failed: $(cat "$work/merge.log")"
[ "$(grep -c '"status": "ok"' "$work/merged.json")" -eq 5 ] || fail "merged summary does not hold 5 ok models"
# -o naming a model's mesh or one of its outputs is refused and leaves the file as it was (merge
# wrote its summary over it without a word).
splat_file=$(ls "$work"/out/*/*.splats.ply | head -1)
for target in "$work/meshes/set1/model1.obj" "$splat_file"; do
  before=$(cksum < "$target")
  if "$splatcl" batch merge "$work"/out/summary-*-of-3.json -o "$target" > "$work/merge-over.log" 2>&1; then fail "merge -o $target was accepted"; fi
  grep -q "would overwrite the \(input\|output\) of model" "$work/merge-over.log" || fail "merge -o $target: $(cat "$work/merge-over.log")"
  [ "$(cksum < "$target")" = "$before" ] || fail "merge -o $target changed it"
done
# Nor the run's manifest (merged over it, the next run failed on the summary's keys), also when
# merge runs in another directory than the run (relative paths are the run's: merged from
# elsewhere, the guard refused unrelated files and let the run's own be overwritten).
printf '{"models": ["%s"]}\n' "meshes/set1/model1.obj" > "$work/set.json"
(cd "$work" && "$splatcl" batch set.json -o out-set "${args[@]}") > "$work/set.log" || fail "the manifest's run failed: $(cat "$work/set.log")"
before=$(cksum < "$work/set.json")
mkdir -p "$work/elsewhere"
for target in ../set.json ../meshes/set1/model1.obj; do
  if (cd "$work/elsewhere" && "$splatcl" batch merge ../out-set/summary.json -o "$target") > "$work/merge-over.log" 2>&1; then
    fail "merge -o $target from another directory was accepted"
  fi
  grep -q "would overwrite the \(manifest of the run\|input of model\)" "$work/merge-over.log" || fail "merge -o $target: $(cat "$work/merge-over.log")"
done
[ "$(cksum < "$work/set.json")" = "$before" ] || fail "merge -o the manifest changed it"
(cd "$work/elsewhere" && "$splatcl" batch merge ../out-set/summary.json -o set.json) > "$work/merge-elsewhere.log" 2>&1 ||
  fail "merge -o an unrelated set.json was refused: $(cat "$work/merge-elsewhere.log")"
grep -q '"status": "ok"' "$work/elsewhere/set.json" || fail "merge wrote no summary to elsewhere/set.json"
# The whole run in one go finds every shard's outputs and reuses them.
"$splatcl" batch "$work/meshes" -o "$work/out" "${args[@]}" > "$work/whole.log" || fail "whole run failed"
[ "$(grep -c '^reused' "$work/whole.log")" -eq 5 ] || fail "the whole run did not reuse the shards' outputs: $(cat "$work/whole.log")"
# Shards run with other parameters, or on another device, do not merge (they merged silently when
# only the manifest's own keys differed): one line naming the summary.
expect_error=$(dirname "$0")/../cli/expect_error.sh
"$splatcl" batch "$work/meshes" -o "$work/mixed" --shard 0/2 "${args[@]}" > /dev/null || fail "shard 0/2 failed"
"$splatcl" batch "$work/meshes" -o "$work/mixed" --shard 1/2 --maps 64 --res 16 --k 8 --reference > /dev/null || fail "shard 1/2 at --res 16 failed"
"$expect_error" "summary-1-of-2.json: from a different run than .*summary-0-of-2.json: other models, inputs or parameters" \
  "$splatcl" batch merge "$work/mixed/summary-0-of-2.json" "$work/mixed/summary-1-of-2.json" -o "$work/mixed.json" >/dev/null ||
  fail "shards of other parameters merged"
"$splatcl" batch "$work/meshes" -o "$work/mixed" --shard 1/2 --maps 64 --res 32 --k 8 > /dev/null || fail "shard 1/2 on the device failed"
"$expect_error" "summary-1-of-2.json: ran on device '.+', .*summary-0-of-2.json on 'reference'; rerun the shards on one device" \
  "$splatcl" batch merge "$work/mixed/summary-0-of-2.json" "$work/mixed/summary-1-of-2.json" -o "$work/mixed.json" >/dev/null ||
  fail "shards of two devices merged"
[ -e "$work/mixed.json" ] && fail "a refused merge wrote its output"
echo "ok: 3 shards cover 5 models exactly once; shards of other parameters or devices are not merged; merge -o spares the run's files"
