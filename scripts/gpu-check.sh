#!/usr/bin/env bash
# The kernels on an NVIDIA GPU's OpenCL (the ICD the driver installs): builds splatcl, then
#   devices.txt          splatcl devices (what the ICD loader sees)
#   kernel-tests.log     every kernel-vs-reference test on the GPU (ctest -L devices, both shapes)
#   bench-quick.{md,json} splatcl bench --quick on the GPU
#   tuning.json          splatcl bench tune --quick on the GPU (records for data/tuning.json)
#   summary.txt          one line per step: passed / FAILED, and the seconds it took
# written into OUTDIR. Exit 0 when every step passed, 1 when one failed, 2 when it could not start
# (no NVIDIA ICD or GPU, bad arguments). Without a GPU, --dry-run DEVICE runs the same steps on
# another device (e.g. pocl) to check the script itself; its results say so.
#
#   scripts/gpu-check.sh OUTDIR [--dry-run DEVICE] [--build-dir DIR] [--no-build]
#                        [--steps devices,tests,bench,tune] [--suite SUITE] [--tune-kernel KERNEL] [--tune-shape SHAPE]
# --suite, --tune-kernel and --tune-shape narrow `bench` and `bench tune` (default: everything).
set -uo pipefail
cd "$(dirname "$0")/.."

usage() { echo "usage: scripts/gpu-check.sh OUTDIR [--dry-run DEVICE] [--build-dir DIR] [--no-build] [--steps LIST] [--suite SUITE] [--tune-kernel KERNEL] [--tune-shape SHAPE]" >&2; }
fail_start() { echo "gpu-check: $*" >&2; exit 2; }

out="" dry_run="" build_dir=build-gpu build=1 steps=devices,tests,bench,tune suite="" tune_kernel="" tune_shape=""
while [ $# -gt 0 ]; do
  case "$1" in
    --dry-run) [ $# -ge 2 ] || { usage; exit 2; }; dry_run=$2; shift 2 ;;
    --build-dir) [ $# -ge 2 ] || { usage; exit 2; }; build_dir=$2; shift 2 ;;
    --no-build) build=0; shift ;;
    --steps) [ $# -ge 2 ] || { usage; exit 2; }; steps=$2; shift 2 ;;
    --suite) [ $# -ge 2 ] || { usage; exit 2; }; suite=$2; shift 2 ;;
    --tune-kernel) [ $# -ge 2 ] || { usage; exit 2; }; tune_kernel=$2; shift 2 ;;
    --tune-shape) [ $# -ge 2 ] || { usage; exit 2; }; tune_shape=$2; shift 2 ;;
    -h|--help) usage; exit 0 ;;
    -*) usage; fail_start "unknown option '$1'" ;;
    *) [ -z "$out" ] || { usage; fail_start "one OUTDIR only, got '$out' and '$1'"; }; out=$1; shift ;;
  esac
done
[ -n "$out" ] || { usage; fail_start "no OUTDIR given"; }
for step in ${steps//,/ }; do
  case "$step" in devices|tests|bench|tune) ;; *) fail_start "unknown step '$step' (steps: devices, tests, bench, tune)" ;; esac
done

# Intel's CPU runtime and Oclgrind beside the driver's ICD when setup.sh installed them (its
# .opencl/vendors copies /etc/OpenCL/vendors, the driver's ICD with it), unless the caller chose.
[ -z "${OCL_ICD_VENDORS:-}" ] && [ -f .opencl/env ] && . .opencl/env
vendors=${OCL_ICD_VENDORS:-/etc/OpenCL/vendors}

if [ -z "$dry_run" ]; then
  # The driver's ICD file names libnvidia-opencl.so.1 (Debian: nvidia-opencl-icd; NVIDIA's .run
  # installer: /etc/OpenCL/vendors/nvidia.icd).
  nvidia_icd=$(grep -l 'libnvidia-opencl' "$vendors"/*.icd 2>/dev/null | head -n 1)
  [ -n "$nvidia_icd" ] || fail_start "no NVIDIA OpenCL ICD in $vendors (no file there names libnvidia-opencl.so; install the driver's OpenCL part, e.g. Debian's nvidia-opencl-icd); nothing run. Without a GPU: --dry-run DEVICE"
  library=$(head -n 1 "$nvidia_icd")
  if [[ "$library" == /* ]]; then found=$([ -e "$library" ] && echo yes); else found=$(ldconfig -p 2>/dev/null | grep -F -m 1 "$library"); fi
  [ -n "$found" ] || fail_start "$nvidia_icd names $library, which is not installed (ldconfig -p does not list it); nothing run"
fi

mkdir -p "$out" || fail_start "cannot create $out"
out=$(cd "$out" && pwd)

if [ "$build" = 1 ]; then
  echo "gpu-check: building into $build_dir"
  { cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release && cmake --build "$build_dir" -j "$(nproc)"; } > "$out/build.log" 2>&1 ||
    { tail -n 20 "$out/build.log" >&2; fail_start "the build failed (the whole log: $out/build.log)"; }
fi
splatcl=$build_dir/splatcl
[ -x "$splatcl" ] || fail_start "$splatcl does not exist (build first, or drop --no-build)"

# The device: the first NVIDIA GPU, or the --dry-run one, as its index in `splatcl devices`.
selector=${dry_run:-nvidia}
index=$(env -u SPLATCL_DEVICE "$splatcl" devices --device "$selector" 2>/dev/null |
        awk '/^\* \[[0-9]+\]/ { match($0, /\[[0-9]+\]/); print substr($0, RSTART + 1, RLENGTH - 2) }')
[ -n "$index" ] || fail_start "no OpenCL device matches '$selector' ($splatcl devices lists what the ICD loader sees)"
type=$(env -u SPLATCL_DEVICE "$splatcl" devices --device "$index" | awk '/^\* / { chosen = 1 } chosen && /^ +type / { t = $2; sub(",", "", t); print t; exit }')
if [ -z "$dry_run" ] && [ "$type" != gpu ]; then
  fail_start "device [$index] matching 'nvidia' is of type '$type', not a GPU; nothing run"
fi

summary=$out/summary.txt
{
  echo "# scripts/gpu-check.sh on $(hostname), $(date -u +%Y-%m-%dT%H:%M:%SZ), commit $(git rev-parse --short HEAD 2>/dev/null || echo unknown)"
  [ -n "$dry_run" ] && echo "# DRY RUN on '$dry_run' (device [$index], type $type): not a GPU result"
} > "$summary"
failed=0
# run_step NAME LOG COMMAND...: the command's output to LOG, one summary line.
run_step() {
  local name=$1 log=$2 start=$SECONDS status
  shift 2
  echo "gpu-check: $name"
  "$@" > "$log" 2>&1
  status=$?
  if [ "$status" -eq 0 ]; then
    echo "$name: passed in $((SECONDS - start)) s" >> "$summary"
  else
    echo "$name: FAILED (exit $status, $log) in $((SECONDS - start)) s" >> "$summary"
    failed=1
  fi
}
has_step() { [[ ",$steps," == *",$1,"* ]]; }

has_step devices && run_step devices "$out/devices.txt" env -u SPLATCL_DEVICE "$splatcl" devices --device "$index"
# The devices.* tests rerun the kernel tests on the devices SPLATCL_TEST_DEVICES names.
has_step tests && run_step kernel-tests "$out/kernel-tests.log" \
  env SPLATCL_TEST_DEVICES="$index" ctest --test-dir "$build_dir" -L devices --output-on-failure
has_step bench && run_step "bench --quick" "$out/bench-quick.log" \
  "$splatcl" bench $suite --quick --device "$index" --json "$out/bench-quick.json"
has_step bench && [ -f "$out/bench-quick.json" ] && "$splatcl" bench report "$out/bench-quick.json" > "$out/bench-quick.md"
has_step tune && run_step "bench tune --quick" "$out/tune.log" \
  "$splatcl" bench tune --quick --device "$index" ${tune_kernel:+--kernel "$tune_kernel"} ${tune_shape:+--shape "$tune_shape"} -o "$out/tuning.json"

cat "$summary"
exit "$failed"
