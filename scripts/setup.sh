#!/usr/bin/env bash
# One entry point for a fresh Debian 12 machine: install what is missing, build, then
#   scripts/setup.sh run    run the main job on the embedded default in data/
#   scripts/setup.sh test   run the whole test suite (Release, then ASan+UBSan) with ctest
#   scripts/setup.sh build  only install and build
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(
  build-essential cmake pkg-config
  pocl-opencl-icd ocl-icd-opencl-dev opencl-headers opencl-clhpp-headers clinfo
  libglfw3-dev libglm-dev libegl-dev libgl-dev libopengl-dev libegl-mesa0 libgl1-mesa-dri xvfb xauth
  libopenmesh-dev libopenimageio-dev libflann-dev liblz4-dev
  libcli11-dev nlohmann-json3-dev libspdlog-dev libfmt-dev
  libboost-dev libgtest-dev libgmock-dev libbenchmark-dev
  libembree-dev gnuplot-nox
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

jobs=$(nproc)
build_config() {  # build_config DIR CMAKE_ARGS...
  local dir=$1; shift
  cmake -S . -B "$dir" -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
  cmake --build "$dir" -j "$jobs"
}

build_config build
case "${1:-build}" in
  build) ;;
  run)
    # The presenter offscreen (EGL, no display needed) on the embedded default scene: per-stage timings,
    # the last frame and the timings as JSON in out/presenter/; assets cached in out/cache/.
    mkdir -p out/presenter && build/splatcl render --frames 10 --cache out/cache -o out/presenter/frame.png \
      --json out/presenter/timings.json
    ;;
  test)
    ctest --test-dir build --output-on-failure -j "$jobs"
    build_config build-asan -DSPLATCL_SANITIZE=ON -DSPLATCL_BUILD_BENCH_PEERS=OFF
    ASAN_OPTIONS=detect_leaks=0:abort_on_error=1 UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 \
      ctest --test-dir build-asan --output-on-failure -j "$jobs"
    ;;
  *) echo "usage: scripts/setup.sh [build|run|test]" >&2; exit 2 ;;
esac
