#pragma once
// Ambient occlusion with coherent shadow maps (Müller §5.3): per receiver, the N directions of
// one precomputed cosine-weighted pattern (chosen per receiver) rotated into the normal's
// hemisphere, each tested against every occluder instance; AO = fraction unoccluded (no cosine
// factor: the density carries it; with a ground plane the lit share of the directions above it
// times (1 + n.y) / 2, csm_ao_finish) and the bent normal = normalised sum of the unoccluded directions.
// The per-receiver code is kernels/csm_query.h, shared by the kernel (AmbientOcclusion) and the
// native reference (ambient_occlusion_reference), which agree exactly.
#include <cstdint>
#include <string>
#include <vector>

#include "core/device_vector.hpp"
#include "csm/visibility.hpp"

namespace splatcl::csm {

// The thesis's six strategies (Müller §5.3.1, Fig. 5.7 a–f).
enum class PatternSet : std::uint32_t {
  MonteCarlo = 0,
  Stratified = 1,          // √N × √N strata, one jittered sample each (N a perfect square)
  LatinHypercube = 2,      // (k + u)/N, (π(k) + u')/N
  HaltonRotated = 3,       // (Φ2(k), Φ3(k)), k = 1…N, Cranley–Patterson shift per pattern
  HammersleyRotated = 4,   // (k/N, Φ2(k)), k = 1…N, Cranley–Patterson shift per pattern
  HammersleyScrambled = 5  // (k/N, Φ2(k)), k = 1…N, random digit (XOR) scrambling per pattern
};
const char* to_string(PatternSet value);
PatternSet parse_pattern_set(const std::string& text);

inline constexpr std::uint32_t kDefaultPatterns = 256, kDefaultSamples = 36;
// Stated limits (docs/reliability.md): directions per pattern and patterns per set, so the pattern
// table (patterns x samples x 16 bytes) stays under 256 MiB; more is refused before allocating.
inline constexpr std::uint32_t kMaxSamples = 4096, kMaxPatterns = 4096;

// patterns × samples directions on the +y hemisphere with density cosθ/π (Shirley's map,
// Müller Eq. 5.9), xyz with w = 0, pattern-major. Deterministic for a seed. Throws Error for zero sizes or a
// stratified set whose sample count is not a perfect square.
std::vector<Vec4> make_patterns(PatternSet set, std::uint32_t patterns, std::uint32_t samples, std::uint32_t seed);

// The pattern each receiver uses: floor(u · patterns) of a fixed per-receiver uniform u.
std::vector<std::uint32_t> choose_patterns(std::size_t receivers, std::uint32_t patterns, std::uint32_t seed);

inline constexpr std::uint32_t kNoInstance = UINT32_MAX;
struct AoRequest {
  // World space; unit normals. positions[r].w: how far receiver r is lifted along its normal, world
  // units, where instance own_instance is queried (off its own surface); ignored without one.
  std::vector<Vec4> positions, normals;
  std::uint32_t own_instance = kNoInstance;
  std::vector<Vec4> patterns;            // from make_patterns
  std::uint32_t samples = kDefaultSamples;
  std::vector<std::uint32_t> pattern_of;  // per receiver
  bool ground = false;                    // directions below the world floor (d.y < 0) are occluded
  float bias = 0;
  void validate() const;  // throws Error on inconsistent sizes or pattern indices
};

// out[r] = (bent normal xyz, AO). Multithreaded over receivers.
void ambient_occlusion_reference(const VisibilityScene& scene, const AoRequest& request, std::vector<Vec4>& out);

class AmbientOcclusion {
 public:
  AmbientOcclusion(Runtime& runtime, const VisibilityScene& scene);
  std::vector<Vec4> run(const AoRequest& request, Profiler* profiler = nullptr);
  // Other instances of the scene's CSMs; the CSM tables stay on the device (VisibilityQueries::place).
  void place(const std::vector<Instance>& placed) { scene_.place(placed); }
  // The scene tables on the device, placed as the last place() left them: visibility queries through
  // the same instances (key-light shadows) need no second copy of the tables.
  VisibilityQueries& queries() { return scene_; }

 private:
  Runtime& runtime_;
  VisibilityQueries scene_;
  cl::Kernel kernel_;
  DeviceVector<Vec4> positions_, normals_;
  DeviceVector<std::uint32_t> choice_;
  DeviceVector<Vec4> patterns_, result_;
};

}  // namespace splatcl::csm
