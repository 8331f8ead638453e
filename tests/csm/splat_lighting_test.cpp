// Per-splat lighting through the CSMs (csm/splat_lighting.hpp): the full update gives the AO
// kernel's rows and key_light_visibility's shadows through every instance, and an incremental
// update after one occluder moved gives the full update's rows bit for bit with fewer receivers.
#include <cstring>
#include <iterator>

#include "csm/build.hpp"
#include "csm/splat_lighting.hpp"
#include "csm_test_support.hpp"

namespace splatcl::csm {
namespace {

using namespace testing;

struct Fixture {
  Csm slab, block;
  SplatLighting::Receivers receivers;
  SplatLighting::Settings settings;
  std::vector<Vec4> patterns;
  std::vector<std::uint32_t> pattern_of;
};

const Fixture& fixture() {
  static const Fixture built = [] {
    Fixture f;
    BuildOptions options;
    options.maps = 256;
    options.resolution = 32;
    f.slab = build_csm(boxes_mesh({{{-1, 0.8f, -1}, {1, 0.9f, 1}}}, "slab"), options, &runtime()).csm;
    f.block = build_csm(boxes_mesh({{{-0.3f, 0.0f, -0.3f}, {0.3f, 0.5f, 0.3f}}}, "block"), options, &runtime()).csm;
    // A floor of receivers (no object's splats) under and around the occluders.
    for (int i = 0; i < 24; ++i)
      for (int k = 0; k < 24; ++k) {
        f.receivers.positions.push_back({-3.0f + 0.25f * static_cast<float>(i), 0.0f, -3.0f + 0.25f * static_cast<float>(k), 0});
        f.receivers.normals.push_back({0, 1, 0, 0});
      }
    f.receivers.objects = {{0, 0, true}, {0, 0, true}};
    f.settings.ao_samples = 16;
    f.settings.lift = 0.035f;  // not the bias: the two are separate settings
    f.settings.key_lights = {{{0.5f, 4.0f, 0.2f}, 0.3f}, {{-2.0f, 3.0f, 1.0f}, 0.0f}};
    f.patterns = make_patterns(PatternSet::HammersleyScrambled, 64, f.settings.ao_samples, 1);
    f.pattern_of = choose_patterns(f.receivers.positions.size(), 64, 1);
    return f;
  }();
  return built;
}

SplatLighting make_lighting(const Fixture& f) { return SplatLighting(runtime(), {&f.slab, &f.block}, f.patterns, f.pattern_of); }

TEST(CsmSplatLighting, FullUpdateEqualsTheAoKernelAndOneVisibilityBatch) {
  const Fixture& f = fixture();
  SplatLighting lighting = make_lighting(f);
  const std::vector<Transform> placements = {kIdentity, translation(1.2, 0, 0)};
  const SplatLighting::Update update = lighting.update(f.receivers, placements, f.settings, false);
  const std::size_t n = f.receivers.positions.size();
  EXPECT_EQ(update.receivers, n);
  const std::vector<float>& rows = lighting.rows();
  ASSERT_EQ(rows.size(), n * SplatLighting::kRowFloats);

  AoRequest request;
  request.positions = f.receivers.positions;
  request.normals = f.receivers.normals;
  request.patterns = f.patterns;
  request.samples = f.settings.ao_samples;
  request.pattern_of = f.pattern_of;
  request.ground = f.settings.ground;
  request.bias = f.settings.bias;
  AmbientOcclusion& device = lighting.device();
  device.place({{0, placements[0]}, {1, placements[1]}});
  const std::vector<Vec4> ao = device.run(request);
  std::size_t occluded = 0;
  for (std::size_t s = 0; s < n; ++s) {
    EXPECT_EQ(std::memcmp(&rows[SplatLighting::kRowFloats * s], &ao[s], sizeof(Vec4)), 0) << "splat " << s;
    occluded += ao[s].w < 1.0f;
  }
  EXPECT_GT(occluded, n / 10);  // the slab and the block shade part of the floor

  std::vector<Vec4> lifted;
  for (std::size_t s = 0; s < n; ++s) {
    const Vec4& p = f.receivers.positions[s];
    lifted.push_back({p.x, p.y + f.settings.lift, p.z, 1.0f});
  }
  std::size_t shadowed = 0;
  for (std::size_t k = 0; k < f.settings.key_lights.size(); ++k) {
    const std::vector<float> visible = key_light_visibility(device.queries(), lifted, f.settings.key_lights[k],
                                                            f.settings.shadow_samples, f.settings.filter, f.settings.bias);
    for (std::size_t s = 0; s < n; ++s) {
      EXPECT_EQ(rows[SplatLighting::kRowFloats * s + SplatLighting::kVisibilityAt + k], visible[s]) << "splat " << s;
      shadowed += visible[s] < 1.0f;
    }
  }
  EXPECT_GT(shadowed, 0u);
  for (std::size_t s = 0; s < n; ++s)  // no third or fourth key light: visible
    for (std::size_t k = f.settings.key_lights.size(); k < SplatLighting::kMaxKeyLights; ++k)
      EXPECT_EQ(rows[SplatLighting::kRowFloats * s + SplatLighting::kVisibilityAt + k], 1.0f);
}

TEST(CsmSplatLighting, IncrementalUpdateAfterAMoveEqualsTheFullUpdate) {
  const Fixture& f = fixture();
  SplatLighting incremental = make_lighting(f);
  const std::size_t n = f.receivers.positions.size();
  incremental.update(f.receivers, {kIdentity, translation(1.2, 0, 0)}, f.settings, true);
  int step = 0;
  for (const Transform& moved : {translation(0.9, 0, 0.4), translation(-1.5, 0, 0.1), translation(-1.2, 0, 0.3)}) {
    const std::vector<Transform> placements = {kIdentity, moved};
    const SplatLighting::Update update = incremental.update(f.receivers, placements, f.settings, true);
    // The first move builds the cache of the static occluder; later moves of the same object
    // recompute only the splats whose lit directions changed.
    if (step++ > 0) {
      EXPECT_LT(update.receivers, n);
    }
    SplatLighting full = make_lighting(f);
    full.update(f.receivers, placements, f.settings, false);
    ASSERT_EQ(incremental.rows().size(), full.rows().size());
    EXPECT_EQ(std::memcmp(incremental.rows().data(), full.rows().data(), full.rows().size() * sizeof(float)), 0);
  }
  // Changed settings take the full update.
  SplatLighting::Settings no_shadows = f.settings;
  no_shadows.shadows = false;
  EXPECT_EQ(incremental.update(f.receivers, {kIdentity, translation(0.2, 0, 0)}, no_shadows, true).receivers, n);
  for (std::size_t s = 0; s < n; ++s)
    EXPECT_EQ(incremental.rows()[SplatLighting::kRowFloats * s + SplatLighting::kVisibilityAt], 1.0f);
}

// Receivers that change between updates (pixels: some hidden, some showing another point) with
// an occluder moving: the incremental update re-caches only the changed receivers and gives the
// full update's rows bit for bit on every active receiver.
TEST(CsmSplatLighting, IncrementalUpdateWithChangingReceiversEqualsTheFullUpdate) {
  const Fixture& f = fixture();
  const std::size_t n = f.receivers.positions.size();
  SplatLighting incremental = make_lighting(f);
  SplatLighting::Receivers receivers = f.receivers;
  receivers.active.assign(n, 1);
  receivers.pattern_of = f.pattern_of;
  incremental.update(receivers, {kIdentity, translation(1.2, 0, 0)}, f.settings, true);
  const Transform moves[] = {translation(0.9, 0, 0.4), translation(0.6, 0, 0.5), translation(-1.5, 0, 0.1),
                             translation(-1.2, 0, 0.3), translation(-1.0, 0, 0.3)};
  std::size_t partial = 0;
  for (std::size_t step = 0; step < std::size(moves); ++step) {
    // A band of receivers hidden (every third step none), a few shifted to another point, one
    // given another pattern; a receiver hidden in the step before comes back where it was.
    for (std::size_t s = 0; s < n; ++s) receivers.active[s] = step % 3 == 2 || (s + 7 * step) % 11 != 0;
    for (std::size_t s = step; s < n; s += 37) receivers.positions[s].x += 0.01f;
    for (std::size_t s = step; s < n; s += 53) receivers.normals[s] = {0.0f, 0.8f, 0.6f, 0.0f};
    receivers.pattern_of[step] = (receivers.pattern_of[step] + 1) % 64;
    const std::vector<Transform> placements = {kIdentity, moves[step]};
    const SplatLighting::Update update = incremental.update(receivers, placements, f.settings, true);
    if (step > 0) partial += update.receivers < n / 2;
    SplatLighting full = make_lighting(f);
    full.update(receivers, placements, f.settings, false);
    std::size_t differ = 0, active = 0;
    for (std::size_t s = 0; s < n; ++s) {
      if (!receivers.active[s]) continue;
      ++active;
      differ += std::memcmp(&incremental.rows()[SplatLighting::kRowFloats * s], &full.rows()[SplatLighting::kRowFloats * s],
                            SplatLighting::kRowFloats * sizeof(float)) != 0;
    }
    EXPECT_GT(active, n / 2);
    EXPECT_EQ(differ, 0u) << "step " << step;
  }
  EXPECT_GE(partial, 3u);  // the cache served most receivers after the first move
  // The occluder stops: the cache of the static occluders is made again (now both), and then with
  // nothing moved and nothing changed no row is recomputed, and the rows stay.
  const std::vector<Transform> still = {kIdentity, moves[std::size(moves) - 1]};
  incremental.update(receivers, still, f.settings, true);
  const std::vector<float> rows = incremental.rows();
  EXPECT_EQ(incremental.update(receivers, still, f.settings, true).receivers, 0u);
  EXPECT_EQ(incremental.rows(), rows);
}

}  // namespace
}  // namespace splatcl::csm
