#!/usr/bin/env bash
# One entry point for a fresh Debian 12 machine: install what is missing, build, then
#   scripts/setup.sh run    run the main job on the embedded default in data/
#   scripts/setup.sh test   run the whole test suite with ctest (ASan+UBSan, Release where it must)
#   scripts/setup.sh build  only install and build
# Beside PoCL it installs two more OpenCL implementations for the cross-implementation tests and
# benchmarks: Oclgrind (Debian) and Intel's OpenCL CPU runtime (PyPI wheels unpacked into .opencl/,
# which git ignores). `. .opencl/env` points the ICD loader at all of them (docs/portability.md).
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(
  build-essential cmake pkg-config
  pocl-opencl-icd ocl-icd-opencl-dev opencl-headers opencl-clhpp-headers clinfo oclgrind python3-pip unzip
  libglfw3-dev libglm-dev libegl-dev libgl-dev libopengl-dev libegl-mesa0 libgl1-mesa-dri xvfb xauth
  libimgui-dev xdotool  # the viewer's panel (Dear ImGui with its GLFW and OpenGL 3 backends); X input for its test
  libopenmesh-dev libopenimageio-dev libflann-dev liblz4-dev
  libcli11-dev nlohmann-json3-dev libspdlog-dev libfmt-dev
  libboost-dev libgtest-dev libgmock-dev libbenchmark-dev
  libembree-dev gnuplot-nox
  slurm-wlm munge strace  # tests/batch/cli_slurm_test.sh (a single-node Slurm), the batch start-up test (strace)
  clang libclang-rt-14-dev  # libFuzzer for scripts/fuzz.sh (the suite replays the fuzz corpus with the default compiler)
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}"
  sudo_cmd=""; [ "$(id -u)" -ne 0 ] && sudo_cmd="sudo"
  $sudo_cmd apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

# Intel's OpenCL CPU runtime, with the libraries it loads, from PyPI (wheel, version).
intel_wheels=(intel-opencl-rt==2026.2.0 tbb==2023.2.0 intel-cmplr-lib-rt==2026.2.0 tcmlib==1.6.0)
opencl_dir=$PWD/.opencl

# .opencl/vendors: the system's ICD files, Oclgrind's and Intel's; .opencl/env names it for the ICD
# loader (ocl-icd reads OCL_ICD_VENDORS instead of /etc/OpenCL/vendors). Without PyPI, PoCL and
# Oclgrind only: the tests skip the missing implementation with a message.
setup_opencl_implementations() {
  local vendors=$opencl_dir/vendors intel=$opencl_dir/intel stamp="${intel_wheels[*]}"
  rm -rf "$vendors" && mkdir -p "$vendors"
  cp /etc/OpenCL/vendors/*.icd "$vendors"/ 2>/dev/null || true
  [ -f /usr/lib/oclgrind/liboclgrind-rt-icd.so ] && echo /usr/lib/oclgrind/liboclgrind-rt-icd.so > "$vendors/oclgrind.icd"
  if [ "$(cat "$intel/stamp" 2>/dev/null)" != "$stamp" ]; then
    echo "setup: downloading Intel's OpenCL CPU runtime from PyPI (${intel_wheels[*]})"
    rm -rf "$intel" "$opencl_dir/wheels"
    if timeout 900 python3 -m pip download -q --no-deps --only-binary=:all: --disable-pip-version-check --timeout 30 --retries 2 \
        -d "$opencl_dir/wheels" "${intel_wheels[@]}"; then
      mkdir -p "$intel/lib"
      for wheel in "$opencl_dir"/wheels/*.whl; do unzip -q -o -j "$wheel" '*.data/data/lib/*' -d "$intel/lib"; done
      # The wheel's own ICD loader would shadow the system's (ocl-icd) on LD_LIBRARY_PATH.
      rm -f "$intel"/lib/libOpenCL.so*
      echo "$stamp" > "$intel/stamp"
      rm -rf "$opencl_dir/wheels"
    else
      echo "setup: could not download from PyPI (no network, or no pip): Intel's OpenCL CPU runtime is not installed; PoCL and Oclgrind only" >&2
      rm -rf "$intel" "$opencl_dir/wheels"
    fi
  fi
  [ -f "$intel/lib/libintelocl.so" ] && echo "$intel/lib/libintelocl.so" > "$vendors/intel-cpu.icd"
  cat > "$opencl_dir/env" <<ENV
# Written by scripts/setup.sh: every OpenCL implementation it installed (. .opencl/env).
export OCL_ICD_VENDORS="$vendors"
export LD_LIBRARY_PATH="$intel/lib\${LD_LIBRARY_PATH:+:\$LD_LIBRARY_PATH}"
ENV
}
setup_opencl_implementations

jobs=$(nproc)
build_config() {  # build_config DIR CMAKE_ARGS...
  local dir=$1; shift
  cmake -S . -B "$dir" -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
  cmake --build "$dir" -j "$jobs"
}

# Warnings are errors in the test builds (CI), not when a user only builds or runs.
werror=OFF; [ "${1:-build}" = test ] && werror=ON
build_config build -DSPLATCL_WERROR=$werror
case "${1:-build}" in
  build) ;;
  run)
    # The presenter offscreen (EGL, no display needed) on the embedded default scene: per-stage timings,
    # the last frame and the timings as JSON in out/presenter/; assets cached in out/cache/.
    mkdir -p out/presenter && build/splatcl render --frames 10 --cache out/cache -o out/presenter/frame.png \
      --json out/presenter/timings.json
    ;;
  test)
    # Every test runs once: under ASan+UBSan below, but for those that need the Release build: the
    # devices.* reruns of the kernel tests on every device that is not the default, with every
    # implementation visible (tests/devices/on_devices.sh; $SPLATCL_TEST_DEVICES narrows the list),
    # the package tests (they build a consumer of the installed and of the embedded library), the AO
    # check against Embree ray casting (the sanitizer build has no Embree), and the
    # runs that take minutes under the sanitizers: the shared models, the batch runs of several
    # processes (shards, resume, a Slurm cluster) and the radix sorts of a million keys. Their code
    # also runs under the sanitizers on smaller inputs.
    release_only='^(devices|package)\.|HoldsOnTheSharedModels|render_scans_scene|batch_slurm|batch_shards|batch_resume|_n1048579_|AmbientOcclusionMatchesRayCast'
    (. "$opencl_dir/env" && ctest --test-dir build --output-on-failure -j "$jobs" -R "$release_only")
    # ASan+UBSan: PoCL only (the system's ICD files). LeakSanitizer on, with the third-party
    # libraries' leaks in tests/lsan.supp. intercept_tls_get_addr=0: the leak check's tracer crashes
    # on a bogus dynamic TLS range after some PoCL runs (GCC 12's runtime); glibc's dynamic TLS blocks
    # are heap blocks reached from each thread's DTV, so they are still scanned.
    build_config build-asan -DSPLATCL_SANITIZE=ON -DSPLATCL_BUILD_BENCH_PEERS=OFF -DSPLATCL_DEVICE_TESTS=OFF
    ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:intercept_tls_get_addr=0 UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 \
      LSAN_OPTIONS=suppressions=$PWD/tests/lsan.supp:print_suppressions=0 ctest --test-dir build-asan --output-on-failure -j "$jobs" \
      -E "$release_only"
    # ThreadSanitizer on the threaded tests only: the presenter's lighting worker beside its
    # visibility pass and the thread pools that build its assets. A third build, of the presenter's
    # test program alone; it reuses the ASan pass's asset cache. Mesa's own races: tests/tsan.supp.
    threaded_present_tests=(PresenterTest.OverlappedLightingEqualsSerialLighting PresenterTest.MovingAnOccluderMovesItsAmbientOcclusion
      PresenterTest.IncrementalSplatLightingEqualsFullRecomputation PresenterTest.LightingSettingsChangeTheRowsWithoutMotion
      PresenterTest.UnreadableCacheEntriesAreRebuilt)
    cmake -S . -B build-tsan -DCMAKE_BUILD_TYPE=Release -DSPLATCL_SANITIZE_THREAD=ON -DSPLATCL_WERROR=ON \
      -DSPLATCL_BUILD_BENCH_PEERS=OFF -DSPLATCL_DEVICE_TESTS=OFF >/dev/null
    cmake --build build-tsan -j "$jobs" --target splatcl_tests_present
    rm -rf build-tsan/tests/present-cache && cp -r build-asan/tests/present-cache build-tsan/tests/present-cache
    TSAN_OPTIONS="halt_on_error=1 suppressions=$PWD/tests/tsan.supp" build-tsan/tests/splatcl_tests_present \
      --gtest_filter="$(IFS=:; echo "${threaded_present_tests[*]}")"
    ;;
  *) echo "usage: scripts/setup.sh [build|run|test]" >&2; exit 2 ;;
esac
