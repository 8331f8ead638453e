#!/usr/bin/env bash
# Reruns one kernel test program on other OpenCL devices: by default every device present but the
# default one (the plain test run covers that), or the devices $SPLATCL_TEST_DEVICES names
# (comma-separated selectors as for --device: "intel,oclgrind", "1", "all"). A named device that is
# missing is skipped with a message. Simulators (Oclgrind) run the small-size filter with their
# bounds, barrier-divergence, data-race and API checks on, at most 256 work-items per group and
# 32 KiB of local memory; any finding in their log fails the test. Oclgrind 21.10's uninitialised-
# value check loses track of memory once earlier buffers are released (a finding that depends on
# which tests ran before, on data the kernel wrote itself: docs/portability.md), so it is on only
# with SPLATCL_OCLGRIND_UNINITIALIZED=1, for one test at a time.
#   on_devices.sh SPLATCL TEST_PROGRAM FILTER SIMULATOR_FILTER
# Exit 0 when every device run passed, 77 (skipped) when there was no device to run on, else 1.
set -uo pipefail
splatcl=$1 program=$2 filter=$3 simulator_filter=$4
name=$(basename "$program")

# "index<TAB>type<TAB>platform / name" of the starred (chosen) device in `splatcl devices` output.
chosen_device() {
  env -u SPLATCL_DEVICE "$splatcl" devices "$@" | awk '
    /^[* ] \[[0-9]+\]/ { chosen = ($1 == "*"); match($0, /\[[0-9]+\]/); index_ = substr($0, RSTART + 1, RLENGTH - 2);
                         label = substr($0, RSTART + RLENGTH + 1) }
    /^ +type / { type = $2; sub(",", "", type); if (chosen) print index_ "\t" type "\t" label }'
}
every_device() {
  env -u SPLATCL_DEVICE "$splatcl" devices | awk '/^[* ] \[[0-9]+\]/ { match($0, /\[[0-9]+\]/); print substr($0, RSTART + 1, RLENGTH - 2) }'
}

if ! env -u SPLATCL_DEVICE "$splatcl" devices > /dev/null; then
  echo "$name: 'splatcl devices' failed: no device list"
  exit 1
fi
selectors=${SPLATCL_TEST_DEVICES:-all}
devices=()  # "index<TAB>type<TAB>label"
if [ "$selectors" = all ]; then
  default_index=$(chosen_device | cut -f1)
  for index in $(every_device); do
    [ "$index" = "$default_index" ] && continue
    devices+=("$(chosen_device --device "$index")")
  done
  if [ ${#devices[@]} -eq 0 ]; then
    echo "$name: skipped: only the default device is present (scripts/setup.sh installs Oclgrind and Intel's runtime; . .opencl/env)"
    exit 77
  fi
else
  IFS=, read -ra wanted <<< "$selectors"
  for selector in "${wanted[@]}"; do
    if line=$(chosen_device --device "$selector" 2>/dev/null) && [ -n "$line" ]; then
      devices+=("$line")
    else
      echo "$name: skipped device '$selector': not present (splatcl devices lists what is)"
    fi
  done
  [ ${#devices[@]} -eq 0 ] && exit 77
fi

failed=0
log_dir=$(mktemp -d) && trap 'rm -rf "$log_dir"' EXIT
for line in "${devices[@]}"; do
  IFS=$'\t' read -r index type label <<< "$line"
  start=$SECONDS
  if [ "$type" = simulator ]; then
    log=$log_dir/oclgrind-$index.log
    OCLGRIND_DATA_RACES=1 OCLGRIND_UNINITIALIZED=${SPLATCL_OCLGRIND_UNINITIALIZED:-0} OCLGRIND_CHECK_API=1 OCLGRIND_MAX_WGSIZE=256 \
      OCLGRIND_LOG=$log SPLATCL_DEVICE=$index "$program" --gtest_filter="$simulator_filter" --gtest_brief=1
    status=$?
    if [ -s "$log" ]; then
      echo "$name on [$index] $label: Oclgrind reported:"
      head -n 60 "$log"
      status=1
    fi
  else
    SPLATCL_DEVICE=$index "$program" --gtest_filter="$filter" --gtest_brief=1
    status=$?
  fi
  if [ "$status" -eq 0 ]; then
    echo "$name on [$index] $label ($type): passed in $((SECONDS - start)) s"
  else
    echo "$name on [$index] $label ($type): FAILED (exit $status)"
    failed=1
  fi
done
exit "$failed"
