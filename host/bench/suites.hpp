#pragma once
// The benchmark suites behind `splatcl bench <suite>`. A suite is one function that measures its
// cases through the Session; adding one means writing that function and listing it in suites().
// Every suite honours size scaling: it multiplies its problem sizes by SessionOptions::scale.
#include <string>
#include <vector>

#include "bench/session.hpp"

namespace splatcl::bench {

struct Suite {
  const char* name;
  const char* description;
  void (*run)(Session& session);
  bool takes_size;  // whether --size applies (else the suite's standard inputs have a fixed size)
  // Checks the suite's inputs (its models) before any suite runs; throws Error naming what is missing.
  void (*check_inputs)() = nullptr;
};

// Every suite, in the order `splatcl bench --help` lists them.
const std::vector<Suite>& suites();

// Scan, compaction (flagged, unique), radix sort (32-bit keys on 20 and 32 bits, key-value, 64-bit
// keys) in both kernel shapes against the native references, sort + unique against std and
// Boost.Compute, and the streaming-copy bandwidth.
void run_primitives_suite(Session& session);

// The clustered-shading stages on a ray-cast 1920×1080 frame with 32×32 tiles: keys, every
// compaction variant (with std and Boost.Compute sort + unique as peers), bounds, and both light
// assignments for 1k, 16k and 256k lights, each in both kernel shapes against the native reference;
// plus the streaming-copy bandwidth. Size scaling scales the frame's pixel count (both sides by the
// square root of the factor).
void run_cluster_suite(Session& session);

// The splat stage phase by phase and end to end (fit on the device beside the native reference) on
// stanford-bunny (ε = 0.0003) and ogre (ε = 0.001 × diagonal) from splats_models_dir(), and the
// default two-sided variant end to end on both and on a generated flat 100×100 grid; the models come
// from splats_models_dir(), which
// `--models` sets (default: data/models, SPLATCL_MODELS_DIR at configure time). Size scaling keeps every
// 1/scale-th vertex of each model (ε stays that of the whole model), so every phase sees that share of
// the samples.
void run_splats_suite(Session& session);
void check_splats_models();
std::string& splats_models_dir();

// The coherent-shadow-map kernels on stanford-bunny (from splats_models_dir()): capture rays/s
// beside the native reference and Embree (same first/second-hit rays), streaming compression
// samples/s, visibility queries/s on a coherent floor grid and AO samples/s, each beside the native
// reference. Under a minute at the standard sizes; --quick shrinks them for tests.
void run_csm_suite(Session& session);
void check_csm_model();

}  // namespace splatcl::bench
