#include "bench/suites.hpp"

namespace splatcl::bench {

const std::vector<Suite>& suites() {
  static const std::vector<Suite> all = {
      {"primitives",
       "Scan, compaction and radix sort (both kernel shapes) against the native reference, std and Boost.Compute, "
       "plus streaming-copy bandwidth",
       run_primitives_suite, true, nullptr},
      {"cluster",
       "Clustered-shading stages on a 1920x1080 frame (keys, compaction variants, bounds, light assignment for 1k, "
       "16k and 256k lights) against the native reference, std and Boost.Compute, plus streaming-copy bandwidth",
       run_cluster_suite, false, nullptr},
      {"splats", "Splat stage per phase and end to end (the thesis's method and the two-sided default) on stanford-bunny, ogre, the bunny split to 139k vertices (two-sided only) and a flat 100x100 grid, device fit beside the native reference", run_splats_suite, false, check_splats_models},
      {"csm",
       "Coherent shadow maps on stanford-bunny: capture rays/s (native reference, Embree), compression samples/s, "
       "visibility queries/s and AO samples/s against the native reference",
       run_csm_suite, false, check_csm_model},
  };
  return all;
}

}  // namespace splatcl::bench
