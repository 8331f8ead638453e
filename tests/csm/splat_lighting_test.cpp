// Per-splat lighting through the CSMs (csm/splat_lighting.hpp): the full update gives the AO
// kernel's rows and key_light_visibility's shadows through every instance, and an incremental
// update after one occluder moved gives the full update's rows bit for bit with fewer receivers.
#include <cstring>
#include <iterator>

#include "csm/ao_receivers.hpp"
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
    // Splats of the slab (its underside and top) and of the block (two sides): lifted off their own
    // surface for their own object's queries only.
    const std::size_t floor_count = f.receivers.positions.size();
    for (int i = 0; i < 8; ++i)
      for (int k = 0; k < 8; ++k)
        for (const float y : {0.8f, 0.9f}) {
          f.receivers.positions.push_back({-0.875f + 0.25f * static_cast<float>(i), y, -0.875f + 0.25f * static_cast<float>(k), 0});
          f.receivers.normals.push_back({0, y < 0.85f ? -1.0f : 1.0f, 0, 0});
        }
    const std::size_t slab_count = f.receivers.positions.size() - floor_count;
    for (int i = 0; i < 4; ++i)
      for (int k = 0; k < 4; ++k)
        for (const float x : {-0.3f, 0.3f}) {
          f.receivers.positions.push_back({x, 0.05f + 0.125f * static_cast<float>(i), -0.225f + 0.15f * static_cast<float>(k), 0});
          f.receivers.normals.push_back({x < 0 ? -1.0f : 1.0f, 0, 0, 0});
        }
    f.receivers.objects = {{floor_count, slab_count, true}, {floor_count + slab_count, f.receivers.positions.size() - floor_count - slab_count, true}};
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

// The same for each shadow filter: the queries skip instances out of reach (Cone) with same-map
// PCF and march (the default; bias 0.5 texels, and 6, where march's cone reach grows with the
// bias), every query runs with cross-map; the AO's queries are culled with each (they use filter
// none).
TEST(CsmSplatLighting, FullUpdateEqualsTheAoKernelAndOneVisibilityBatch) {
  const std::pair<Filter, float> cases[] = {
      {Filter::SameMap, 0.5f}, {Filter::CrossMap, 0.5f}, {Filter::March, 0.5f}, {Filter::March, 6.0f}};
  for (const auto& [filter, bias] : cases) {
    SCOPED_TRACE(fmt::format("{} bias {}", to_string(filter), bias));
    Fixture f = fixture();
    f.settings.filter = filter;
    f.settings.bias = bias;
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
    std::vector<Vec4> ao = device.run(request);
    // An object's splats: the AO kernel with the object as own instance, lifted by its own texel.
    const Csm* csms[] = {&f.slab, &f.block};
    for (std::uint32_t object = 0; object < 2; ++object) {
      const SplatLighting::Object& o = f.receivers.objects[object];
      AoRequest own = request;
      own.own_instance = object;
      own.positions.assign(f.receivers.positions.begin() + static_cast<std::ptrdiff_t>(o.first),
                           f.receivers.positions.begin() + static_cast<std::ptrdiff_t>(o.first + o.count));
      for (Vec4& p : own.positions) p.w = kAoLiftTexels * placed_texel(csms[object]->info, placements[object]);
      own.normals.assign(f.receivers.normals.begin() + static_cast<std::ptrdiff_t>(o.first),
                         f.receivers.normals.begin() + static_cast<std::ptrdiff_t>(o.first + o.count));
      own.pattern_of.assign(f.pattern_of.begin() + static_cast<std::ptrdiff_t>(o.first),
                            f.pattern_of.begin() + static_cast<std::ptrdiff_t>(o.first + o.count));
      const std::vector<Vec4> part = device.run(own);
      std::copy(part.begin(), part.end(), ao.begin() + static_cast<std::ptrdiff_t>(o.first));
    }
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
      for (std::size_t s = 0; s < f.receivers.objects[0].first; ++s) {  // the floor's splats, of no object
        EXPECT_EQ(rows[SplatLighting::kRowFloats * s + SplatLighting::kVisibilityAt + k], visible[s]) << "splat " << s;
        shadowed += visible[s] < 1.0f;
      }
    }
    EXPECT_GT(shadowed, 0u);
    // The slab's top sees the key light above it (no acne through its own maps), its underside does
    // not (PCF lets up to 3 of 32 taps through near the slab's rim) unless the bias exceeds the
    // slab's thickness (0.1, about a texel of these maps: 6 texels lets the underside see through).
    const SplatLighting::Object& slab = f.receivers.objects[0];
    for (std::size_t s = slab.first; s < slab.first + slab.count; ++s) {
      const float visible = rows[SplatLighting::kRowFloats * s + SplatLighting::kVisibilityAt];
      if (f.receivers.normals[s].y > 0) {
        EXPECT_EQ(visible, 1.0f) << "slab splat " << s;
      } else if (bias < 1.0f) {
        EXPECT_LE(visible, 0.1f) << "slab splat " << s;
      }
    }
    for (std::size_t s = 0; s < n; ++s)  // no third or fourth key light: visible
      for (std::size_t k = f.settings.key_lights.size(); k < SplatLighting::kMaxKeyLights; ++k)
        EXPECT_EQ(rows[SplatLighting::kRowFloats * s + SplatLighting::kVisibilityAt + k], 1.0f);
  }
}

// Also with a bias beyond the default reach: march's cone grows with the bias (cone_reach_texels),
// so the incremental update stays on.
TEST(CsmSplatLighting, IncrementalUpdateAfterAMoveEqualsTheFullUpdate) {
  for (const float bias : {0.5f, 6.0f}) {
    SCOPED_TRACE(bias);
    Fixture f = fixture();
    f.settings.bias = bias;
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

// Several objects with splats: two static occluders, one or two moving, and an object that casts
// nothing (occluder false), so that the queries through several static instances at once group
// the receivers by their own instance. Every step's incremental rows are the full update's.
TEST(CsmSplatLighting, IncrementalUpdateWithSeveralOwnersEqualsTheFullUpdate) {
  const Fixture& f = fixture();
  BuildOptions options;
  options.maps = 256;
  options.resolution = 32;
  static const Csm post = build_csm(boxes_mesh({{{1.5f, 0.0f, -0.2f}, {1.8f, 1.2f, 0.1f}}}, "post"), options, &runtime()).csm;
  SplatLighting::Receivers receivers = f.receivers;
  const auto add_object = [&](float x, bool occluder) {
    const std::size_t first = receivers.positions.size();
    for (int i = 0; i < 6; ++i)
      for (const float side : {-1.0f, 1.0f}) {
        receivers.positions.push_back({x + 0.15f * side, 0.1f + 0.2f * static_cast<float>(i), -0.05f, 0});
        receivers.normals.push_back({side, 0, 0, 0});
      }
    receivers.objects.push_back({first, receivers.positions.size() - first, occluder});
  };
  add_object(1.65f, true);    // the post's sides
  add_object(-2.0f, false);   // an object that casts nothing
  const std::size_t n = receivers.positions.size();
  const std::vector<Vec4> patterns = f.patterns;
  const std::vector<std::uint32_t> pattern_of = choose_patterns(n, 64, 1);
  const auto lighting = [&] { return SplatLighting(runtime(), {&f.slab, &f.block, &post, &f.block}, patterns, pattern_of); };
  SplatLighting incremental = lighting();
  const std::vector<std::vector<Transform>> steps = {
      {kIdentity, translation(1.2, 0, 0), kIdentity, kIdentity},
      {kIdentity, translation(0.9, 0, 0.4), kIdentity, kIdentity},           // the block moves
      {kIdentity, translation(0.6, 0, 0.5), translation(-0.3, 0, 0), kIdentity},  // the block and the post
      {kIdentity, translation(0.6, 0, 0.5), translation(-0.5, 0, 0.1), kIdentity},  // the post
      {kIdentity, translation(0.6, 0, 0.5), translation(-0.5, 0, 0.1), translation(0.1, 0, 0)},  // the non-occluder
      {kIdentity, translation(0.6, 0, 0.5), translation(-0.5, 0, 0.1), translation(0.1, 0, 0)},  // nothing
  };
  for (std::size_t step = 0; step < steps.size(); ++step) {
    incremental.update(receivers, steps[step], f.settings, true);
    SplatLighting full = lighting();
    full.update(receivers, steps[step], f.settings, false);
    ASSERT_EQ(incremental.rows().size(), n * SplatLighting::kRowFloats);
    std::size_t differ = 0;
    for (std::size_t s = 0; s < n; ++s)
      differ += std::memcmp(&incremental.rows()[SplatLighting::kRowFloats * s], &full.rows()[SplatLighting::kRowFloats * s],
                            SplatLighting::kRowFloats * sizeof(float)) != 0;
    EXPECT_EQ(differ, 0u) << "step " << step;
  }
}

// A splat's own object lifts it off its own surface for its own CSM's queries only, as `splatcl ao`
// lifts a receiver that is an occluder (csm/ao_receivers.hpp): a unit sphere's splats resting on a
// thin plate, both occluders. Lifted by the sphere's texel through every instance, the splats under
// the sphere went through the plate and read AO up to 1 off ray casting. Now the rows' AO is the
// `ao` command's on the same receivers and patterns (the AO kernel with the sphere as own instance).
TEST(CsmSplatLighting, SplatsAreLiftedForTheirOwnObjectsMapsOnly) {
  const BallOnPlate& setup = ball_on_plate();
  const Mesh& ball = setup.ball;
  const Csm &ball_csm = setup.ball_csm, &plate_csm = setup.plate_csm;
  ReceiverAoOptions options;
  const std::size_t n = ball.vertices.size();
  SplatLighting::Receivers receivers;
  for (std::size_t v = 0; v < n; ++v) {
    receivers.positions.push_back({ball.vertices[v].x, ball.vertices[v].y, ball.vertices[v].z, 0});
    receivers.normals.push_back({ball.normals[v].x, ball.normals[v].y, ball.normals[v].z, 0});
  }
  receivers.objects = {{0, n, true}, {n, 0, true}};
  SplatLighting lighting(runtime(), {&ball_csm, &plate_csm}, make_patterns(options.pattern_set, options.patterns, options.samples, options.seed),
                         choose_patterns(n, options.patterns, options.seed));
  SplatLighting::Settings settings;
  settings.ao_samples = options.samples;
  settings.bias = options.bias;
  settings.ground = options.ground;
  settings.shadows = false;
  lighting.update(receivers, {kIdentity, kIdentity}, settings, false);

  const std::vector<const Csm*> csms{&ball_csm, &plate_csm};
  const std::vector<Instance> instances{{0, kIdentity}, {1, kIdentity}};
  options.lift = receiver_lifts(ball, csms, instances, kAoLiftTexels);
  ASSERT_EQ(options.lift.own_instance, 0u);
  const std::vector<Vec4> ao = receiver_ambient_occlusion(ball, VisibilityScene(csms, instances), options, &runtime());
  const std::vector<float> truth = raycast_ambient_occlusion(ball, setup.both, options);
  double error = 0, worst = 0, from_ao = 0;
  for (std::size_t v = 0; v < n; ++v) {
    const float row_ao = lighting.rows()[SplatLighting::kRowFloats * v + 3];
    error += std::abs(row_ao - truth[v]);
    worst = std::max(worst, static_cast<double>(std::abs(row_ao - truth[v])));
    from_ao = std::max(from_ao, static_cast<double>(std::abs(row_ao - ao[v].w)));
  }
  std::printf("ball on a plate, splat rows: mean |AO - ray-cast| %.4f (largest %.3f); largest |AO - splatcl ao| %.2g\n",
              error / static_cast<double>(n), worst, from_ao);
  EXPECT_LT(worst, 0.35);
  EXPECT_LE(from_ao, 1e-6);
}

}  // namespace
}  // namespace splatcl::csm
