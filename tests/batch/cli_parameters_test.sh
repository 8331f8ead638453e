#!/usr/bin/env bash
# Manifest parameters are the build options of `splatcl splats` and `splatcl csm build`: the same
# names (both directions), the same outputs byte for byte; a per-model texture resolved against the
# manifest's folder and part of the resume checksum; an unknown parameter names the model and the
# parameter; a bad command line exits 1.
. "$(dirname "$0")/cli_common.sh" "$1" "$2"

# The options of a --help text, one per line.
options_of() { "$splatcl" "$@" --help | grep -oE '^ +(-[a-z], ?)?--[a-z0-9-]+' | grep -oE -- '--[a-z0-9-]+' | sort -u; }
batch_options=$(options_of batch)
# Every build option of each command is a batch option (and so a manifest key) ...
for option in $(options_of splats | grep -vxE -- '--(help|output|stats|render|reference|device|format|strict|no-check)'); do
  grep -qx -- "$option" <<< "$batch_options" || fail "splats option $option is not a batch parameter"
done
for option in $(options_of csm build | grep -vxE -- '--(help|output|mode|pixel-order|coherence|reference|device)'); do
  grep -qx -- "$option" <<< "$batch_options" || fail "csm build option $option is not a batch parameter"
done
# ... and every batch parameter is an option of one of them.
stage_options=$( (options_of splats; options_of csm build) | sort -u)
for option in $(grep -vxE -- '--(help|output|device|shard|jobs|summary|force|list|reference|outputs)' <<< "$batch_options"); do
  grep -qx -- "$option" <<< "$stage_options" || fail "batch option $option is neither a splats nor a csm build option"
done

# The same parameters give the same files as the single-model commands.
printf '%s\n' "$textured_cube" > "$work/meshes/box.obj"
mkdir -p "$work/textures"
printf 'P3\n2 2\n255\n255 0 0 255 0 0 255 0 0 255 0 0\n' > "$work/textures/red.ppm"
box=$(cd "$work/meshes" && pwd)/box.obj
"$splatcl" splats "$box" -o "$work/single.ply" --k 6 --eps-diag 0.02 --clip --texture "$work/textures/red.ppm" > /dev/null ||
  fail "splatcl splats failed"
"$splatcl" csm build "$box" -o "$work/single.csm" --maps 64 --res 16 --capture raycast --single-hit exact > /dev/null ||
  fail "splatcl csm build failed"
cat > "$work/set.json" <<JSON
{"defaults": {"k": 6, "eps-diag": 0.02, "clip": true, "maps": 64, "res": 16, "capture": "raycast", "single_hit": "exact"},
 "models": [{"path": "$box", "id": "box", "texture": "textures/red.ppm"}]}
JSON
# Run from another folder: the texture is found beside the manifest, not in the working directory.
(cd / && "$splatcl" batch "$work/set.json" -o "$work/out" > "$work/first.log") || fail "batch run failed: $(cat "$work/first.log")"
cmp -s "$work/single.csm" "$work/out/box.csm" || fail "batch and csm build give different .csm files"
cmp -s "$work/single.ply" "$work/out/box.splats.ply" || fail "batch and splats give different splat files"
grep -qa "texture:$work/textures/red.ppm" "$work/out/box.splats.ply" || fail "the splat file does not name the texture beside the manifest"
grep -q '"color_source": "texture:' "$work/out/box.splats.json" || fail "the statistics do not name the texture"

# The texture is part of the resume checksum: edited in place, the splats are rebuilt, the CSM reused.
"$splatcl" batch "$work/set.json" -o "$work/out" > "$work/second.log" || fail "second run failed"
grep -q '^reused  box' "$work/second.log" || fail "unchanged model not reused: $(cat "$work/second.log")"
printf 'P3\n2 2\n255\n0 0 255 0 0 255 0 0 255 0 0 255\n' > "$work/textures/red.ppm"
"$splatcl" batch "$work/set.json" -o "$work/out" > "$work/third.log" || fail "third run failed"
grep -q '^ok      box (splats built in .* s, csm reused)' "$work/third.log" || fail "texture edit did not rebuild just the splats: $(cat "$work/third.log")"

# An unknown parameter: one line naming the file, the entry, the model and the parameter; status 1.
printf '{"models": [{"path": "meshes/box.obj", "id": "crate", "resolution": 64}]}\n' > "$work/unknown.json"
"$splatcl" batch "$work/unknown.json" -o "$work/out2" > /dev/null 2> "$work/unknown.err"
status=$?
[ "$status" -eq 1 ] || fail "unknown parameter: expected exit status 1, got $status"
[ "$(wc -l < "$work/unknown.err")" -eq 1 ] || fail "unknown parameter: expected one line: $(cat "$work/unknown.err")"
grep -q "unknown.json: models\[0\] (crate): unknown parameter 'resolution' (known: id, path, eps," "$work/unknown.err" ||
  fail "unknown parameter message: $(cat "$work/unknown.err")"

# A bad command line is an error like the others: status 1.
"$splatcl" batch "$work/set.json" -o "$work/out3" --no-such-option > /dev/null 2>&1
status=$?
[ "$status" -eq 1 ] || fail "unknown option: expected exit status 1, got $status"
echo "ok: batch parameters are the build options; texture resolved and checksummed; clear errors"
