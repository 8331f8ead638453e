#!/usr/bin/env bash
# scripts/gpu-check.sh on a machine without a GPU: without an NVIDIA ICD, or with one naming a
# library that is not installed, it stops before any work (exit 2, one line, no OUTDIR); a dry run
# on PoCL runs its steps and writes every result file, marked as a dry run.
#   gpu_check_test.sh SCRIPT BUILD_DIR WORK_DIR
set -uo pipefail
script=$1 build=$2 work=$3
fail() { echo "gpu_check_test: $*" >&2; exit 1; }
rm -rf "$work" && mkdir -p "$work/no-vendors" "$work/fake-vendors" || fail "cannot create $work"

# expect_start_failure VENDORS PATTERN: exit 2, exactly one line on stderr matching PATTERN, no OUTDIR.
expect_start_failure() {
  local vendors=$1 pattern=$2 message status
  message=$(OCL_ICD_VENDORS=$vendors "$script" "$work/out-refused" --no-build --build-dir "$build" 2>&1 >/dev/null)
  status=$?
  [ "$status" -eq 2 ] || fail "exit status $status, not 2, with OCL_ICD_VENDORS=$vendors: $message"
  [ "$(printf '%s\n' "$message" | wc -l)" -eq 1 ] || fail "more than one line: $message"
  [[ "$message" =~ $pattern ]] || fail "message '$message' does not match '$pattern'"
  [ ! -e "$work/out-refused" ] || fail "OUTDIR was created although nothing ran"
}
expect_start_failure "$work/no-vendors" "^gpu-check: no NVIDIA OpenCL ICD in $work/no-vendors .*nothing run"
echo libnvidia-opencl-not-installed.so.1 > "$work/fake-vendors/nvidia.icd"
expect_start_failure "$work/fake-vendors" "^gpu-check: $work/fake-vendors/nvidia.icd names libnvidia-opencl-not-installed.so.1, which is not installed"

out=$work/out
"$script" "$out" --dry-run portable --no-build --build-dir "$build" --steps devices,bench,tune --suite csm \
  --tune-kernel scan --tune-shape cpu > "$work/dry-run.log" 2>&1 || { cat "$work/dry-run.log"; fail "the dry run failed"; }
grep -q '^# DRY RUN on .portable. (device \[[0-9]*\], type cpu): not a GPU result$' "$out/summary.txt" || fail "summary.txt does not say DRY RUN"
for step in devices "bench --quick" "bench tune --quick"; do
  grep -q "^$step: passed in [0-9]* s$" "$out/summary.txt" || fail "summary.txt has no passed line for '$step'"
done
[ "$(grep -c 'passed in' "$out/summary.txt")" -eq 3 ] || fail "summary.txt lists other steps than the three asked for"
grep -q '^\* \[[0-9]*\] Portable Computing Language' "$out/devices.txt" || fail "devices.txt does not show PoCL chosen"
grep -q '"suite": "csm"' "$out/bench-quick.json" || fail "bench-quick.json has no csm record"
grep -q '^### csm$' "$out/bench-quick.md" || fail "bench-quick.md has no csm table"
grep -q '"kernel": "scan"' "$out/tuning.json" || fail "tuning.json has no scan record"
grep -q '"shape": "cpu"' "$out/tuning.json" || fail "tuning.json has no cpu-shape record"
[ ! -e "$out/kernel-tests.log" ] || fail "the tests step ran although not asked for"
echo "gpu_check_test: passed"
