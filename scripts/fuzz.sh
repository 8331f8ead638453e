#!/usr/bin/env bash
# Fuzz one reader with libFuzzer (ASan + UBSan):
#   scripts/fuzz.sh NAME SECONDS [LIBFUZZER OPTIONS...]   e.g. scripts/fuzz.sh mesh_ply 600 -runs=1000000
#   scripts/fuzz.sh list                                    the names (tests/fuzz/corpus/NAME holds each seed corpus)
# Builds the harness with clang (-DSPLATCL_FUZZ=ON) in $SPLATCL_FUZZ_BUILD (default build-fuzz/clang),
# starts from the seeds in the repository and keeps what it finds in $SPLATCL_FUZZ_BUILD/corpus/NAME
# (the repository's seeds are only read). An input over 1 s (-timeout=1), over 2 GiB of memory, a
# crash, a sanitizer report or a harness check (tests/fuzz/fuzz_reader.hpp) ends the run with a
# non-zero exit and the input in $SPLATCL_FUZZ_BUILD/findings/NAME/; add it to the corpus as
# regression-*.EXT once fixed. Runs one job on one core (-jobs, -workers after the options give more).
set -euo pipefail
cd "$(dirname "$0")/.."
corpus_root=tests/fuzz/corpus
if [ "${1:-}" = list ]; then
  find "$corpus_root" -mindepth 1 -maxdepth 1 -type d -printf '%f\n' | sort
  exit 0
fi
if [ $# -lt 2 ] || [ ! -d "$corpus_root/$1" ] || ! [[ "$2" =~ ^[0-9]+$ ]]; then
  echo "usage: scripts/fuzz.sh NAME SECONDS [LIBFUZZER OPTIONS...] (NAME: one of scripts/fuzz.sh list)" >&2
  exit 2
fi
name=$1 seconds=$2
shift 2
if ! command -v clang++ >/dev/null; then
  echo "fuzz.sh: clang++ not found: install clang and libclang-rt-14-dev (scripts/setup.sh does)" >&2
  exit 1
fi
build=${SPLATCL_FUZZ_BUILD:-build-fuzz/clang}
if [ ! -f "$build/CMakeCache.txt" ]; then
  cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER=clang++ -DSPLATCL_FUZZ=ON -DSPLATCL_BUILD_TESTS=OFF \
    -DSPLATCL_BUILD_BENCH_PEERS=OFF -DSPLATCL_DEVICE_TESTS=OFF >/dev/null
fi
cmake --build "$build" -j "$(nproc)" --target "splatcl_fuzz_$name"
mkdir -p "$build/corpus/$name" "$build/findings/$name"
dictionary=()  # the keys and values of a text format (corpus/NAME.dict), which random bytes rarely spell
[ -f "$corpus_root/$name.dict" ] && dictionary=(-dict="$corpus_root/$name.dict")
exec "$build/tests/fuzz/splatcl_fuzz_$name" -max_total_time="$seconds" -timeout=1 -rss_limit_mb=2048 -print_final_stats=1 \
  -artifact_prefix="$build/findings/$name/" "${dictionary[@]}" "$@" "$build/corpus/$name" "$corpus_root/$name"
