#!/usr/bin/env bash
# hostile_outputs_test.sh MODE SPLATCL WORKDIR EXPECT_ERROR: outputs under hostile conditions.
# Each mode reproduces one failure and asserts the exit status, the one
# error line and what is (not) on disk afterwards.
#   full-disk-*: a file system that fills up under each PNG writer: RLIMIT_FSIZE with SIGXFSZ
#     ignored (writes past the limit fail with EFBIG, as they would with ENOSPC), or a small tmpfs;
#   batch-*: batch runs whose outputs would replace their inputs, an unwritable output directory,
#     and two runs on one output directory at once;
#   batch-same-shard-twice, batch-scan-own-folders: two copies of one shard at once; start-up
#     clean-up only in the folders of the shard's own outputs (strace);
#   threads-follow-affinity: host threads and PoCL's count follow the CPU affinity mask (taskset);
#   csm-leftover: a killed `csm build` left F.csm.tmpPID; the next run removes it;
#   sigterm-*: SIGTERM (scancel, a time limit) while a temporary is on disk removes it; status 143.
set -u
mode=$1 splatcl=$2 work=$3 expect_error=$4
fail() { echo "FAIL: $*"; exit 1; }
rm -rf "$work" && mkdir -p "$work"
cube=$work/cube.obj
printf 'v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\nf 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 3 4 8 7\nf 2 3 7 6\nf 1 5 8 4\n' >"$cube"
no_leftovers() {  # DIR: no temporary or staged file of any output left behind
  local left
  left=$(find "$1" -name '*.tmp[0-9]*' -o -name '*.partial[0-9]*' -o -name '.splatcl-write-test*')
  [ -z "$left" ] || fail "temporaries left behind: $left"
}
full_disk() {  # KIB PATTERN COMMAND...: fails with one "write failed" line when files may not exceed KIB KiB
  local kib=$1 pattern=$2; shift 2
  (trap '' XFSZ; ulimit -f "$kib"; "$expect_error" "$pattern" "$@") || fail "the write on a full disk did not fail as expected"
}

# A real full disk: a KIB KiB tmpfs at $work/full in a private mount namespace (root only; skipped
# otherwise). PoCL writes files of its own on every run and dies under RLIMIT_FSIZE, so the OpenCL
# commands need this. What is left on it is checked inside the namespace, before it goes.
full_tmpfs_empty() {  # KIB PATTERN COMMAND...: fails unless the command fails so and leaves nothing on the disk
  local kib=$1 pattern=$2; shift 2
  mkdir -p "$work/full"
  unshare -m true 2>/dev/null || { echo "no private mount namespace (needs root): skipped"; exit 77; }
  unshare -m sh -c 'mount -t tmpfs -o size="$0"k tmpfs "$1" && dir=$1 && shift && "$@" && left=$(find "$dir" -mindepth 1 -type f) && [ -z "$left" ] || { echo "left on the full disk: $left"; exit 1; }' \
    "$kib" "$work/full" "$expect_error" "$pattern" "$@" || fail "the write on a full disk did not fail as expected, or left files"
}

case $mode in
  full-disk-coherence)  # the coherence PNG of a 128x128 map is several KiB; the .csm exists already
    "$splatcl" csm build "$cube" -o "$work/cube.csm" --maps 64 --res 128 --reference >/dev/null || fail "csm build failed"
    full_disk 1 "cannot write $work/coherence.png: write failed \\(disk full\\?\\)$" \
      "$splatcl" csm info "$work/cube.csm" --coherence "$work/coherence.png"
    [ -e "$work/coherence.png" ] && fail "a coherence image was left at the target" ;;
  full-disk-coherence-build)  # csm build -o and --coherence are one unit: neither is left
    full_disk 1 "cannot write .*: write failed \\(disk full\\?\\)$" \
      "$splatcl" csm build "$cube" -o "$work/cube.csm" --maps 64 --res 128 --reference --coherence "$work/coherence.png"
    [ -e "$work/coherence.png" ] || [ -e "$work/cube.csm" ] && fail "an output was left at the target" ;;
  full-disk-splats-render)  # the PLY (about 22 KiB) fits under 64 KiB, the rendered PNG (about 100 KiB) does not
    full_disk 64 "cannot write $work/render.png: write failed \\(disk full\\?\\)$" \
      "$splatcl" splats "$cube" --samples grid:4 --reference -o "$work/out.ply" --render "$work/render.png"
    [ -e "$work/render.png" ] || [ -e "$work/out.ply" ] && fail "an output was left at the target" ;;
  full-disk-cluster)  # a real full disk (8 KiB): the four outputs of a 320x180 frame need about 48 KiB
    full_tmpfs_empty 8 "cannot write $work/full/cl/.*: write failed \\(disk full\\?\\)$" "$splatcl" cluster --size 320x180 -o "$work/full/cl" ;;
  full-disk-render)  # a real full disk (8 KiB); a 160x120 frame is about 16 KiB; the asset cache was filled beforehand
    "$splatcl" render --size 160x120 --cache "$work/cache" >/dev/null || fail "the warm-up render failed"
    full_tmpfs_empty 8 "cannot write $work/full/frame.png: write failed \\(disk full\\?\\)$" \
      "$splatcl" render --size 160x120 --cache "$work/cache" -o "$work/full/frame.png" --json "$work/full/frame.json" ;;

  render-cache-read-only)  # a read-only asset cache: refused before a missing asset is built; one that holds every asset serves
    unshare -m true 2>/dev/null || { echo "no private mount namespace (needs root): skipped"; exit 77; }
    printf '{"objects": [{"name": "b", "mesh": {"procedural": "box", "rings": 3}}]}\n' >"$work/scene.json"
    mkdir -p "$work/empty" "$work/warm"
    unshare -m sh -c 'mount --bind "$0" "$0" && mount -o remount,bind,ro "$0" && "$@"' "$work/empty" \
      "$expect_error" "objects\\[0\\] 'b': cannot write the asset cache: directory $work/empty is not writable \\(Read-only file system\\)$" \
      "$splatcl" render "$work/scene.json" --size 64x48 --cache "$work/empty" || fail "an empty read-only cache was not refused as such"
    "$splatcl" render "$work/scene.json" --size 64x48 --cache "$work/warm" >/dev/null || fail "the warm-up render failed"
    unshare -m sh -c 'mount --bind "$0" "$0" && mount -o remount,bind,ro "$0" && "$@" >/dev/null' "$work/warm" \
      "$splatcl" render "$work/scene.json" --size 64x48 --cache "$work/warm" -o "$work/frame.png" || fail "a full read-only cache did not serve"
    [ -s "$work/frame.png" ] || fail "no frame from the full read-only cache" ;;
  batch-summary-is-manifest)
    printf 'path\n%s\n' "$cube" >"$work/set.csv"
    cp "$work/set.csv" "$work/set.csv.orig"
    "$expect_error" "batch: --summary $work/set.csv is the manifest $work/set.csv$" \
      "$splatcl" batch "$work/set.csv" -o "$work/out" --summary "$work/set.csv" || fail "not refused"
    cmp -s "$work/set.csv" "$work/set.csv.orig" || fail "the manifest was changed" ;;
  batch-summary-is-output)
    printf 'path\n%s\n' "$cube" >"$work/set.csv"
    "$expect_error" "batch: --summary $work/out/cube.splats.ply is the output cube.splats.ply of model 'cube'$" \
      "$splatcl" batch "$work/set.csv" -o "$work/out" --summary "$work/out/cube.splats.ply" || fail "not refused"
    [ -e "$work/out/cube.splats.ply" ] && fail "the model was built although the run was refused" ;;
  batch-summary-is-lock)  # written over, the lock file no longer kept a second run off these models
    printf 'path\n%s\n' "$cube" >"$work/set.csv"
    "$expect_error" "batch: --summary $work/out/.splatcl-batch.lock is the output directory's lock file$" \
      "$splatcl" batch "$work/set.csv" -o "$work/out" --summary "$work/out/.splatcl-batch.lock" || fail "not refused"
    [ -e "$work/out/cube.splats.ply" ] && fail "the model was built although the run was refused" ;;
  batch-input-is-lock)  # read and closed, the lock file dropped this run's locks: a second run built the same models at once
    mkdir -p "$work/out" && : >"$work/out/.splatcl-batch.lock"
    printf '{"models": [{"path": "%s", "id": "a"}, {"path": "out/.splatcl-batch.lock", "id": "x"}]}' "$cube" >"$work/set.json"
    "$expect_error" "batch: the input of model 'x' \\(.*\\) is the output directory's lock file$" \
      "$splatcl" batch "$work/set.json" -o "$work/out" || fail "an input naming the lock file was not refused"
    printf '{"models": [{"path": "%s", "id": "a", "texture": "out/.splatcl-batch.lock"}]}' "$cube" >"$work/set.json"
    "$expect_error" "batch: the texture of model 'a' \\(.*\\) is the output directory's lock file$" \
      "$splatcl" batch "$work/set.json" -o "$work/out" || fail "a texture naming the lock file was not refused"
    [ -e "$work/out/a.splats.ply" ] && fail "the model was built although the run was refused" ;;
  batch-summary-folder-missing)  # the output directory and its lock file were made before the summary was refused
    printf 'path\n%s\n' "$cube" >"$work/set.csv"
    "$expect_error" "cannot write --summary $work/nodir/s.json: directory $work/nodir does not exist$" \
      "$splatcl" batch "$work/set.csv" -o "$work/out" --summary "$work/nodir/s.json" || fail "not refused"
    [ -e "$work/out" ] && fail "the output directory was made although the run was refused" ;;
  batch-output-in-output)  # model 'a' writes the file a.csm; 'a.csm/b' would need it as a folder (it failed at run time, every run)
    printf '{"models": [{"path": "%s", "id": "a"}, {"path": "%s", "id": "a.csm/b"}]}' "$cube" "$cube" >"$work/set.json"
    "$expect_error" "batch: the output a.csm/b.batch.json of model 'a.csm/b' lies in a.csm, the output of model 'a'$" \
      "$splatcl" batch "$work/set.json" -o "$work/out" || fail "not refused"
    [ -e "$work/out/a.csm" ] && fail "a model was built although the run was refused" ;;
  batch-fifo-input)  # a FIFO named like a mesh: reading it waited forever for a writer
    mkdir -p "$work/in"
    cp "$cube" "$work/in/cube.obj"
    mkfifo "$work/in/pipe.obj" || { echo "mkfifo failed: skipped"; exit 77; }
    timeout 60 "$splatcl" batch "$work/in" -o "$work/out" --reference --maps 64 --res 16 >"$work/log" 2>&1 || fail "the directory run failed: $(cat "$work/log")"
    [ -e "$work/out/cube.splats.ply" ] || fail "the mesh beside the FIFO was not built"
    [ -e "$work/out/pipe.batch.json" ] && fail "the FIFO was taken as a model"
    printf 'path\n%s\n' "$work/in/pipe.obj" >"$work/set.csv"
    timeout 60 "$expect_error" "^splatcl: batch: 1 of 1 models failed" "$splatcl" batch "$work/set.csv" -o "$work/out2" --reference --maps 64 --res 16 \
      || fail "a manifest naming the FIFO did not fail at once"
    grep -q "not a regular file" "$work/out2/summary.json" || fail "the summary does not say why: $(cat "$work/out2/summary.json")" ;;
  batch-output-is-input | batch-output-inside-input | batch-output-contains-input)
    mkdir -p "$work/in/sub"
    cp "$cube" "$work/in/sub/cube.obj"
    case $mode in
      batch-output-is-input) input=$work/in/sub out=$work/in/sub/. pattern="is the input directory" ;;
      batch-output-inside-input) input=$work/in out=$work/in/sub/out pattern="is inside the input directory $work/in:" ;;
      *) input=$work/in/sub out=$work/in pattern="contains the input directory $work/in/sub:" ;;
    esac
    "$expect_error" "batch: the output directory $out $pattern" "$splatcl" batch "$input" -o "$out" || fail "not refused"
    [ -z "$(find "$work/in" -name '*.splats.*' -o -name '*.csm*' -o -name 'summary*')" ] || fail "outputs were written into the input" ;;
  batch-unwritable)  # refused before any model is computed, whoever runs it (root ignores permissions)
    printf 'path\n%s\n' "$cube" >"$work/set.csv"
    mkdir -p "$work/locked"
    chmod 555 "$work/locked"
    as_user=()
    if [ "$(id -u)" -eq 0 ]; then
      command -v setpriv >/dev/null || { echo "setpriv missing: cannot drop root"; exit 77; }
      chmod 755 "$work" && chmod o+rx "$(dirname "$splatcl")" "$splatcl" 2>/dev/null
      as_user=(setpriv --reuid=65534 --regid=65534 --clear-groups)
      "${as_user[@]}" test -x "$splatcl" || { echo "the unprivileged user cannot run $splatcl: skipped"; exit 77; }
    fi
    out=$("${as_user[@]}" "$expect_error" "cannot write output directory $work/locked: directory $work/locked is not writable \\(Permission denied\\)$" \
      "$splatcl" batch "$work/set.csv" -o "$work/locked" --reference) || fail "not refused: $out"
    chmod 755 "$work/locked"
    [ -z "$(ls -A "$work/locked")" ] || fail "something was written: $(ls -A "$work/locked")" ;;
  batch-concurrent)  # the first run holds its model locks for 3 s; a second run on the same models is refused
    printf 'path\n%s\n' "$cube" >"$work/set.csv"
    SPLATCL_BATCH_HOLD_LOCKS_MS=3000 "$splatcl" batch "$work/set.csv" -o "$work/out" --reference --maps 64 --res 16 \
      >"$work/first.log" 2>&1 &
    first=$!
    for _ in $(seq 100); do [ -e "$work/out/.splatcl-batch.lock" ] && break; sleep 0.05; done
    sleep 0.5
    "$expect_error" "batch: model 'cube' in $work/out is being built by another batch run \\(pid $first\\); run one batch per model and output directory at a time" \
      "$splatcl" batch "$work/set.csv" -o "$work/out" --reference --maps 64 --res 16 || fail "the second run was not refused"
    wait "$first" || fail "the first run failed: $(cat "$work/first.log")"
    grep -q '^ok      cube' "$work/first.log" || fail "the first run did not build the model: $(cat "$work/first.log")"
    # Once it is done, the same run goes through and reuses its outputs.
    "$splatcl" batch "$work/set.csv" -o "$work/out" --reference --maps 64 --res 16 >"$work/third.log" || fail "a later run failed"
    grep -q '^reused  cube' "$work/third.log" || fail "a later run did not reuse: $(cat "$work/third.log")" ;;

  batch-concurrent-summary)  # two runs into different output directories naming one --summary
    printf 'path\n%s\n' "$cube" >"$work/set.csv"
    printf 'path\n%s\n' "$work/wedge.obj" >"$work/other.csv"
    printf 'v 0 0 0\nv 2 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n' >"$work/wedge.obj"
    mkdir -p "$work/summaries"
    SPLATCL_BATCH_HOLD_LOCKS_MS=3000 "$splatcl" batch "$work/set.csv" -o "$work/outA" --summary "$work/summaries/s.json" --reference \
      --maps 64 --res 16 >"$work/first.log" 2>&1 &
    first=$!
    for _ in $(seq 100); do [ -e "$work/summaries/.splatcl-batch.lock" ] && break; sleep 0.05; done
    sleep 0.5
    "$expect_error" "batch: the summary $work/summaries/s.json is being written by another batch run \\(pid $first\\); run one batch per summary at a time" \
      "$splatcl" batch "$work/other.csv" -o "$work/outB" --summary "$work/summaries/s.json" --reference --maps 64 --res 16 ||
      fail "the second run was not refused"
    # Refused before it made its output directory (it left an empty one with a lock file).
    [ -e "$work/outB" ] && fail "the refused run made its output directory"
    wait "$first" || fail "the first run failed: $(cat "$work/first.log")"
    grep -q '"id": "cube"' "$work/summaries/s.json" || fail "the summary is not the first run's: $(cat "$work/summaries/s.json")" ;;

  batch-same-shard-twice)  # two copies of one shard (a requeued Slurm task while the first still runs)
    # Copy A pauses 1.5 s before each rename, so it has a temporary on disk. summary-0-of-2.json.tmpDEAD
    # stands for a summary temporary of a copy on another node: its pid does not exist on this one.
    printf 'path\n%s\n%s\n' "$cube" "$work/wedge.obj" >"$work/set.csv"
    printf 'v 0 0 0\nv 2 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n' >"$work/wedge.obj"
    args=(batch "$work/set.csv" -o "$work/out" --shard 0/2 --reference --outputs csm --maps 64 --res 16)
    SPLATCL_TEST_PAUSE_BEFORE_RENAME_MS=1500 "$splatcl" "${args[@]}" >"$work/first.log" 2>&1 &
    first=$!
    for _ in $(seq 200); do [ -n "$(find "$work/out" -name '*.tmp[0-9]*' 2>/dev/null)" ] && break; sleep 0.05; done
    temporary=$(find "$work/out" -name '*.tmp[0-9]*')
    [ -n "$temporary" ] || fail "the first copy wrote no temporary"
    sh -c 'exit 0' & dead=$!
    wait "$dead"
    echo elsewhere >"$work/out/summary-0-of-2.json.tmp$dead"
    "$expect_error" "is being built by another batch run \\(pid $first\\)" "$splatcl" "${args[@]}" || fail "the second copy was not refused"
    [ -e "$work/out/summary-0-of-2.json.tmp$dead" ] || fail "the second copy removed a summary temporary before it was refused"
    # Had the second copy removed the first one's temporary, the first one's rename would fail.
    wait "$first" || fail "the first copy failed: $(cat "$work/first.log")"
    "$splatcl" csm verify "$work/out/cube.csm" >/dev/null || fail "the first copy's output does not verify"
    grep -q '^ok      cube' "$work/first.log" || fail "the first copy did not build its model: $(cat "$work/first.log")"
    rm "$work/out/summary-0-of-2.json.tmp$dead" ;;
  batch-scan-own-folders)  # start-up clean-up lists only the folders of the shard's own outputs
    command -v strace >/dev/null || { echo "strace missing (Debian package strace): skipped"; exit 77; }
    strace -f -o /dev/null true 2>/dev/null || { echo "strace cannot trace here (ptrace refused): skipped"; exit 77; }
    mkdir -p "$work/out/others/deep/er" && echo x >"$work/out/others/deep/er/model.csm"
    printf 'path\n%s\n' "$cube" >"$work/set.csv"
    # LeakSanitizer cannot run under ptrace: off for the traced run in the sanitizer pass.
    ASAN_OPTIONS=${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0 strace -f -e trace=openat,open -o "$work/trace" "$splatcl" batch "$work/set.csv" -o "$work/out" --reference --maps 64 --res 16 \
      >"$work/run.log" 2>&1 || fail "the run failed: $(cat "$work/run.log")"
    # Opened by full path or relative to its parent's descriptor (libstdc++'s recursive iterator).
    grep -q 'others"' "$work/trace" && fail "the run opened another shard's folder: $(grep 'others"' "$work/trace" | head -n 2)"
    [ -e "$work/out/others/deep/er/model.csm" ] || fail "another model's file was removed" ;;
  threads-follow-affinity)  # one CPU in the affinity mask: one host thread, and PoCL told so
    command -v taskset >/dev/null || { echo "taskset missing: skipped"; exit 77; }
    out=$(env -u POCL_MAX_PTHREAD_COUNT taskset -c 0 "$splatcl" devices) || fail "devices failed under taskset"
    grep -q '^host threads 1 ' <<<"$out" || fail "the host threads do not follow the affinity mask: $(grep '^host' <<<"$out")"
    if [ "$(nproc --all)" -gt 1 ]; then
      grep -q 'POCL_MAX_PTHREAD_COUNT 1$' <<<"$out" || fail "PoCL's thread count was not set from the mask: $(grep '^host' <<<"$out")"
      grep -A1 'Portable Computing Language' <<<"$out" | grep -q ', 1 compute units' || fail "PoCL does not use one thread: $out"
    fi
    # A value the user set is kept.
    POCL_MAX_PTHREAD_COUNT=2 taskset -c 0 "$splatcl" devices | grep -q 'POCL_MAX_PTHREAD_COUNT 2$' || fail "the user's POCL_MAX_PTHREAD_COUNT was replaced" ;;
  csm-leftover)  # what a SIGKILL during the write leaves: F.csm.tmpPID of a process that is gone
    sh -c 'exit 0' & dead=$!
    wait "$dead"
    echo partial >"$work/cube.csm.tmp$dead"
    "$splatcl" csm build "$cube" -o "$work/cube.csm" --maps 64 --res 16 --reference >/dev/null || fail "csm build failed"
    [ -e "$work/cube.csm.tmp$dead" ] && fail "the dead run's temporary is still there"
    "$splatcl" csm verify "$work/cube.csm" >/dev/null || fail "the rebuilt file does not verify" ;;
  sigterm-csm-build | sigterm-batch)  # SIGTERM while a temporary is on disk (each write pauses 5 s before its rename)
    if [ "$mode" = sigterm-csm-build ]; then
      SPLATCL_TEST_PAUSE_BEFORE_RENAME_MS=5000 "$splatcl" csm build "$cube" -o "$work/cube.csm" --maps 64 --res 16 --reference \
        --coherence "$work/coherence.png" >/dev/null 2>&1 &
    else
      printf 'path\n%s\n' "$cube" >"$work/set.csv"
      SPLATCL_TEST_PAUSE_BEFORE_RENAME_MS=5000 "$splatcl" batch "$work/set.csv" -o "$work/out" --reference --maps 64 --res 16 \
        >/dev/null 2>&1 &
    fi
    pid=$!
    for _ in $(seq 200); do [ -n "$(find "$work" -name '*.tmp[0-9]*')" ] && break; sleep 0.05; done
    [ -n "$(find "$work" -name '*.tmp[0-9]*')" ] || fail "no temporary appeared"
    kill -TERM "$pid"
    wait "$pid"
    status=$?
    [ "$status" -eq 143 ] || fail "expected the status of a SIGTERM (143), got $status"
    [ -e "$work/cube.csm" ] || [ -e "$work/coherence.png" ] && fail "an output was left at the target"
    no_leftovers "$work"
    if [ "$mode" = sigterm-batch ]; then  # and the run resumes
      "$splatcl" batch "$work/set.csv" -o "$work/out" --reference --maps 64 --res 16 >"$work/again.log" || fail "the rerun failed"
      grep -q '^ok      cube' "$work/again.log" || fail "the rerun did not build the model: $(cat "$work/again.log")"
    fi ;;
  sigterm-cluster)  # SIGTERM while a staged output is on disk: no file, and no folder -o made (it stayed)
    "$splatcl" devices >/dev/null 2>&1 || { echo "skipped: no OpenCL device"; exit 77; }
    SPLATCL_TEST_PAUSE_BEFORE_RENAME_MS=5000 "$splatcl" cluster --size 64x48 -o "$work/made/cl" >/dev/null 2>&1 &
    pid=$!
    # Up to 60 s: a cold kernel compile under a parallel ctest comes first.
    for _ in $(seq 1200); do [ -n "$(find "$work/made" -type f 2>/dev/null)" ] && break; sleep 0.05; done
    [ -n "$(find "$work/made" -type f 2>/dev/null)" ] || fail "no staged output appeared"
    kill -TERM "$pid"
    wait "$pid"
    status=$?
    [ "$status" -eq 143 ] || fail "expected the status of a SIGTERM (143), got $status"
    [ ! -e "$work/made" ] || fail "the folders -o made are still there: $(find "$work/made")" ;;
  *) fail "unknown mode $mode" ;;
esac
no_leftovers "$work"
echo "ok: $mode"
