// Ambient occlusion: pattern sets (cosine density, stratification properties), the OpenCL kernel
// against the native reference (identical), analytic cases (open sky, ground plane, a receiver
// under a slab), the hemisphere rotation and several instances sharing one CSM.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <numbers>
#include <cstring>
#include <random>

#include "csm/ao.hpp"
#include "csm/build.hpp"
#include "csm/csm_file.hpp"
#include "csm_test_support.hpp"
#include "runtime/error.hpp"

namespace splatcl::csm {
namespace {

using namespace testing;

const Csm& slab_csm() {
  // A thin wide slab above the origin: receivers under it are occluded upwards.
  static const Csm csm = [] {
    BuildOptions options;
    options.maps = 1024;
    options.resolution = 64;
    return build_csm(boxes_mesh({{{-1, 0.5f, -1}, {1, 0.6f, 1}}}, "slab"), options, &runtime()).csm;
  }();
  return csm;
}

constexpr PatternSet kAllSets[] = {PatternSet::MonteCarlo,        PatternSet::Stratified,        PatternSet::LatinHypercube,
                                   PatternSet::HaltonRotated,     PatternSet::HammersleyRotated, PatternSet::HammersleyScrambled};

TEST(CsmAo, PatternsAreCosineWeightedUnitDirections) {
  for (PatternSet set : kAllSets) {
    const std::vector<Vec4> p = make_patterns(set, 256, 36, 1);
    ASSERT_EQ(p.size(), 256u * 36u);
    double mean_cos = 0;
    for (const Vec4& d : p) {
      EXPECT_NEAR(d.x * d.x + d.y * d.y + d.z * d.z, 1.0f, 1e-5f);
      EXPECT_GE(d.y, 0.0f);
      mean_cos += d.y;
    }
    // E[cosθ] under the density cosθ/π is 2/3.
    EXPECT_NEAR(mean_cos / static_cast<double>(p.size()), 2.0 / 3.0, 0.01) << to_string(set);
    EXPECT_EQ(std::memcmp(p.data(), make_patterns(set, 256, 36, 1).data(), p.size() * sizeof(Vec4)), 0) << "deterministic";
  }
  EXPECT_THROW(make_patterns(PatternSet::Stratified, 4, 35, 1), Error);
  EXPECT_THROW(make_patterns(PatternSet::MonteCarlo, 0, 36, 1), Error);
  EXPECT_EQ(parse_pattern_set("hammersley-scrambled"), PatternSet::HammersleyScrambled);
  EXPECT_THROW(parse_pattern_set("sobol"), Error);
}

TEST(CsmAo, StratifiedAndLatinHypercubeFillTheirCells) {
  // ξ1 = 1 − y², so the strata in ξ1 are visible through cosθ.
  for (PatternSet set : {PatternSet::Stratified, PatternSet::LatinHypercube}) {
    const std::vector<Vec4> p = make_patterns(set, 8, 36, 2);
    for (std::uint32_t j = 0; j < 8; ++j) {
      std::vector<int> rows(set == PatternSet::Stratified ? 6 : 36, 0);
      for (std::uint32_t k = 0; k < 36; ++k) {
        const float y = p[j * 36 + k].y;
        const auto row = std::min<std::size_t>(rows.size() - 1, static_cast<std::size_t>((1 - y * y) * static_cast<float>(rows.size())));
        ++rows[row];
      }
      for (int count : rows) EXPECT_EQ(count, set == PatternSet::Stratified ? 6 : 1) << to_string(set);
    }
  }
}

AoRequest request_for(const std::vector<Vec4>& positions, const std::vector<Vec4>& normals, PatternSet set, bool ground) {
  AoRequest r;
  r.positions = positions;
  r.normals = normals;
  r.patterns = make_patterns(set, 64, 36, 3);
  r.pattern_of = choose_patterns(positions.size(), 64, 3);
  r.ground = ground;
  return r;
}

// Random receivers around the slab; every 100th normal is −o or +o (the rotation's degenerate cases).
void random_receivers(unsigned seed, int count, std::vector<Vec4>& positions, std::vector<Vec4>& normals) {
  std::mt19937 rng(seed);
  const auto u = [&] { return static_cast<float>(rng() >> 8) / 16777216.0f * 2 - 1; };
  for (int k = 0; k < count; ++k) {
    positions.push_back({2 * u(), 1.5f * u(), 2 * u(), 1});
    Vec3 n{u(), u(), u()};
    if (k % 100 == 0) n = {0, -1, 0};
    if (k % 100 == 1) n = {0, 1, 0};
    n = normalized(n);
    normals.push_back({n.x, n.y, n.z, 0});
  }
}

// The kernel against the reference on a CSM built on the host (64 maps of 16²) and 40 receivers:
// small enough for Oclgrind (devices.csm), with two instances and the ground plane.
TEST(CsmAo, KernelMatchesReferenceOnASmallHostBuiltCsm) {
  BuildOptions options;
  options.maps = 64;
  options.resolution = 16;
  const Csm small = build_csm(boxes_mesh({{{-1, 0.5f, -1}, {1, 0.6f, 1}}}, "slab"), options, nullptr).csm;
  std::vector<Vec4> positions, normals;
  random_receivers(5, 40, positions, normals);
  const Instance moved{0, {0, 0, 1, 0.5, 0, 1, 0, -0.9, -1, 0, 0, 0.25, 0, 0, 0, 1}};
  const VisibilityScene scene({&small}, {{}, moved});
  AmbientOcclusion ao(runtime(), scene);
  for (PatternSet set : {PatternSet::MonteCarlo, PatternSet::HammersleyScrambled}) {
    const AoRequest request = request_for(positions, normals, set, set == PatternSet::HammersleyScrambled);
    std::vector<Vec4> ref;
    ambient_occlusion_reference(scene, request, ref);
    const std::vector<Vec4> cl = ao.run(request);
    ASSERT_EQ(cl.size(), ref.size());
    EXPECT_EQ(std::memcmp(cl.data(), ref.data(), ref.size() * sizeof(Vec4)), 0) << to_string(set);
  }
}

TEST(CsmAo, KernelMatchesReferenceForEveryPatternSetAndInstances) {
  std::vector<Vec4> positions, normals;
  random_receivers(4, 1000, positions, normals);
  const Instance moved{0, {0, 0, 1, 0.5, 0, 1, 0, -0.9, -1, 0, 0, 0.25, 0, 0, 0, 1}};
  const VisibilityScene scene({&slab_csm()}, {{}, moved});
  AmbientOcclusion ao(runtime(), scene);
  for (PatternSet set : kAllSets) {
    const bool ground = set == PatternSet::Stratified || set == PatternSet::HammersleyScrambled;
    {
      const AoRequest request = request_for(positions, normals, set, ground);
      std::vector<Vec4> ref;
      ambient_occlusion_reference(scene, request, ref);
      const std::vector<Vec4> cl = ao.run(request);
      ASSERT_EQ(cl.size(), ref.size());
      EXPECT_EQ(std::memcmp(cl.data(), ref.data(), ref.size() * sizeof(Vec4)), 0) << to_string(set) << " ground " << ground;
    }
  }
  // The first `count` receivers through `driver`: a smaller batch reuses its buffers, a larger one
  // grows them.
  const auto check_prefix = [&](AmbientOcclusion& driver, std::size_t count, PatternSet set, bool ground) {
    const auto end = static_cast<std::ptrdiff_t>(count);
    const AoRequest request = request_for({positions.begin(), positions.begin() + end}, {normals.begin(), normals.begin() + end}, set, ground);
    std::vector<Vec4> ref;
    ambient_occlusion_reference(scene, request, ref);
    const std::vector<Vec4> cl = driver.run(request);
    ASSERT_EQ(cl.size(), count);
    EXPECT_EQ(std::memcmp(cl.data(), ref.data(), ref.size() * sizeof(Vec4)), 0) << count;
  };
  check_prefix(ao, 37, PatternSet::HaltonRotated, false);
  AmbientOcclusion fresh(runtime(), scene);
  check_prefix(fresh, 37, PatternSet::MonteCarlo, true);
  check_prefix(fresh, positions.size(), PatternSet::MonteCarlo, true);
  AoRequest bad = request_for(positions, normals, PatternSet::MonteCarlo, false);
  bad.pattern_of[5] = 64;
  EXPECT_THROW(ao.run(bad), Error);
  EXPECT_TRUE(ao.run(request_for({}, {}, PatternSet::MonteCarlo, false)).empty());
}

// A driver placed anew (the presenter's moving occluders) answers like one built for the new
// instances, and its queries() go through the same instances.
TEST(CsmAo, PlacingNewInstancesEqualsAFreshDriver) {
  std::vector<Vec4> positions, normals;
  random_receivers(5, 300, positions, normals);
  const AoRequest request = request_for(positions, normals, PatternSet::HammersleyScrambled, false);
  const Instance moved{0, {0, 0, 1, 0.5, 0, 1, 0, -0.9, -1, 0, 0, 0.25, 0, 0, 0, 1}};
  AmbientOcclusion ao(runtime(), VisibilityScene({&slab_csm()}, {{}}));
  const std::vector<Vec4> lights(positions.size(), Vec4{0.3f, 1, 0.2f, 0});
  for (const auto& instances : {std::vector<Instance>{moved, {}}, std::vector<Instance>{}, std::vector<Instance>{moved}}) {
    ao.place(instances);
    const VisibilityScene fresh({&slab_csm()}, instances);
    std::vector<Vec4> ref;
    ambient_occlusion_reference(fresh, request, ref);
    const std::vector<Vec4> cl = ao.run(request);
    ASSERT_EQ(cl.size(), ref.size());
    EXPECT_EQ(std::memcmp(cl.data(), ref.data(), ref.size() * sizeof(Vec4)), 0) << instances.size() << " instances";
    std::vector<float> visible;
    visibility_reference(fresh, positions, lights, Filter::SameMap, 0.0f, visible);
    const std::vector<float> through = ao.queries().run(positions, lights, Filter::SameMap, 0.0f);
    EXPECT_EQ(std::memcmp(through.data(), visible.data(), visible.size() * sizeof(float)), 0) << instances.size() << " instances";
    std::size_t open = 0;
    for (const Vec4& r : ref) open += r.w == 1.0f;
    if (instances.empty()) {
      EXPECT_EQ(open, ref.size());
    } else {
      EXPECT_LT(open, ref.size());
    }
  }
}

TEST(CsmAo, AnalyticCases) {
  const VisibilityScene scene({&slab_csm()}, {{}});
  // Far from the slab, facing away: open sky, AO 1, bent normal ≈ the normal.
  // Under the slab's middle facing up: the slab covers θ < atan(1 / 0.5) at least, so only the
  // cosine-weighted fraction beyond it, cos²(63.4°) = 0.2 (less towards the corners), is open.
  // Under it facing down with the ground plane on: the whole hemisphere is below the floor.
  const std::vector<Vec4> positions{{0, -1.2f, 0, 1}, {0, 0, 0, 1}, {0, 0, 0, 1}, {0, 2, 0, 1}};
  const std::vector<Vec4> normals{{0, -1, 0, 0}, {0, 1, 0, 0}, {0, -1, 0, 0}, {1, 0, 0, 0}};
  std::vector<Vec4> out;
  ambient_occlusion_reference(scene, request_for(positions, normals, PatternSet::HammersleyScrambled, false), out);
  EXPECT_EQ(out[0].w, 1.0f);
  EXPECT_NEAR(out[0].y, -1.0f, 0.15f);  // the mean of cosine samples is cos ≈ 0.87 off-axis at most
  EXPECT_NEAR(out[1].w, 0.2f, 0.1f);
  EXPECT_EQ(out[2].w, 1.0f);
  EXPECT_GT(out[3].w, 0.8f);  // above the slab facing sideways: only steep downward samples hit it
  EXPECT_GT(out[3].x, 0.6f);
  ambient_occlusion_reference(scene, request_for(positions, normals, PatternSet::HammersleyScrambled, true), out);
  EXPECT_EQ(out[2].w, 0.0f);
  EXPECT_EQ(out[2].y, -1.0f);  // nothing lit: the bent normal is the normal
  EXPECT_NEAR(out[3].w, 0.5f, 0.2f);  // a side-facing receiver loses the lower half
}

// The cosine-weighted share of a receiver's upward hemisphere that a rectangle [x0, x1] × [z0, z1]
// parallel to it, at height h above it, covers: the analytic form factor (a differential area to a
// parallel rectangle, by corner rectangles with signs), independent of any capture or query.
double parallel_rectangle_form_factor(double x0, double x1, double z0, double z1, double h) {
  const auto corner = [&](double x, double z) {
    const double X = x / h, Z = z / h, sx = std::sqrt(1 + X * X), sz = std::sqrt(1 + Z * Z);
    return (X / sx * std::atan(Z / sx) + Z / sz * std::atan(X / sz)) / (2 * std::numbers::pi);
  };
  return corner(x1, z1) - corner(x0, z1) - corner(x1, z0) + corner(x0, z0);
}

// AO of receivers under one CSM at its own placement, by the native reference with 1,024
// directions per receiver.
std::vector<Vec4> reference_ao(const Csm& csm, const std::vector<Vec4>& positions, const std::vector<Vec4>& normals) {
  const VisibilityScene scene({&csm}, {{}});
  AoRequest request;
  request.positions = positions;
  request.normals = normals;
  request.samples = 1024;
  request.patterns = make_patterns(PatternSet::HammersleyScrambled, 4, request.samples, 3);
  request.pattern_of = choose_patterns(positions.size(), 4, 3);
  std::vector<Vec4> out;
  ambient_occlusion_reference(scene, request, out);
  return out;
}

// A single-sided sheet (an open mesh: the build's default rule takes z2 = z1 for it) occludes
// receivers under it as much as the form factor says. With the sphere-exit rule every receiver in
// the first half of the span from the sheet to the bounding sphere's exit counted as lit: AO 1
// under the sheet's middle where 0.17 is right.
TEST(CsmAo, OpenSheetOccludesAsItsFormFactorSays) {
  std::vector<Vec3> vertices;
  std::vector<std::vector<std::uint32_t>> faces;
  constexpr std::uint32_t n = 8;  // quads per side of the 4 × 4 sheet at y = 1, facing up
  for (std::uint32_t i = 0; i <= n; ++i)
    for (std::uint32_t k = 0; k <= n; ++k) vertices.push_back({-2.0f + 0.5f * static_cast<float>(i), 1.0f, -2.0f + 0.5f * static_cast<float>(k)});
  for (std::uint32_t i = 0; i < n; ++i)
    for (std::uint32_t k = 0; k < n; ++k) faces.push_back({i * (n + 1) + k, i * (n + 1) + k + 1, (i + 1) * (n + 1) + k + 1, (i + 1) * (n + 1) + k});
  const Mesh sheet = make_mesh(vertices, faces, "sheet");
  ASSERT_FALSE(sheet.closed());
  BuildOptions options;
  options.maps = 1024;
  options.resolution = 64;
  const Csm csm = build_csm(sheet, options, &runtime()).csm;
  EXPECT_EQ(csm.info.single_hit, SingleHit::Exact);
  std::vector<Vec4> positions, normals;
  for (const float x : {0.0f, 1.0f, 1.9f, 2.5f, 3.5f})
    for (const float z : {0.0f, 1.5f}) positions.push_back({x, 0.0f, z, 1}), normals.push_back({0, 1, 0, 0});
  const std::vector<Vec4> out = reference_ao(csm, positions, normals);
  for (std::size_t r = 0; r < positions.size(); ++r) {
    const double x = positions[r].x, z = positions[r].z;
    const double open = 1 - parallel_rectangle_form_factor(-2 - x, 2 - x, -2 - z, 2 - z, 1.0);
    EXPECT_NEAR(out[r].w, open, 0.04) << "receiver at x " << x << ", z " << z;
  }
  // A closed mesh keeps the sphere-exit rule.
  EXPECT_EQ(build_csm(cube_mesh(), options, &runtime()).csm.info.single_hit, SingleHit::SphereExit);
}

// Two single-sided sheets, 4 × 4 at y = 1 and y = 2 (an open mesh that encloses air, as a roof
// over a floor does): a receiver between them facing up is occluded by the upper one as the form
// factor says. The default rule for an open mesh (exact) keeps the span between a ray's two hits as
// solid, and receivers in it read as lit (a ball in a bowl: AO 0.67 against 0.24 ray-cast); the
// thin rule takes z2 = z1 on every pixel. Its capture kernels match their references
// (CsmCapture / CsmRasterCapture KernelMatchesReference), and its rule survives the file.
TEST(CsmAo, ThinRuleLeavesTheAirBetweenTwoSheetsOpen) {
  std::vector<Vec3> vertices;
  std::vector<std::vector<std::uint32_t>> faces;
  constexpr std::uint32_t n = 8;
  for (const float y : {1.0f, 2.0f}) {
    const auto first = static_cast<std::uint32_t>(vertices.size());
    for (std::uint32_t i = 0; i <= n; ++i)
      for (std::uint32_t k = 0; k <= n; ++k) vertices.push_back({-2.0f + 0.5f * static_cast<float>(i), y, -2.0f + 0.5f * static_cast<float>(k)});
    for (std::uint32_t i = 0; i < n; ++i)
      for (std::uint32_t k = 0; k < n; ++k)
        faces.push_back({first + i * (n + 1) + k, first + i * (n + 1) + k + 1, first + (i + 1) * (n + 1) + k + 1, first + (i + 1) * (n + 1) + k});
  }
  const Mesh sheets = make_mesh(vertices, faces, "two sheets");
  ASSERT_FALSE(sheets.closed());
  std::vector<Vec4> positions, normals;
  for (const float x : {0.0f, 1.0f, 1.5f})
    for (const float z : {0.0f, 1.0f}) positions.push_back({x, 1.5f, z, 1}), normals.push_back({0, 1, 0, 0});
  const auto mean_error = [&](SingleHit rule) {
    BuildOptions options;
    options.maps = 1024;
    options.resolution = 64;
    options.single_hit = rule;
    Csm csm = build_csm(sheets, options, &runtime()).csm;
    if (rule == SingleHit::Thin) {
      const std::string path = (std::filesystem::temp_directory_path() / "splatcl-thin-rule.csm").string();
      write_csm(path, csm, Encoding::Compact);
      csm = read_csm(path);
      EXPECT_EQ(csm.info.single_hit, SingleHit::Thin);
      std::filesystem::remove(path);
    }
    const std::vector<Vec4> out = reference_ao(csm, positions, normals);
    double sum = 0;
    for (std::size_t r = 0; r < positions.size(); ++r) {
      const double x = positions[r].x, z = positions[r].z;
      const double open = 1 - parallel_rectangle_form_factor(-2 - x, 2 - x, -2 - z, 2 - z, 0.5);
      if (rule == SingleHit::Thin) {
        EXPECT_NEAR(out[r].w, open, 0.04) << "receiver at x " << x << ", z " << z;
      }
      sum += std::fabs(out[r].w - open);
    }
    return sum / static_cast<double>(positions.size());
  };
  const double thin = mean_error(SingleHit::Thin), exact = mean_error(SingleHit::Auto);
  std::printf("two sheets, receivers between them: mean |AO - form factor| %.4f thin, %.4f auto (exact)\n", thin, exact);
  EXPECT_GT(exact, 0.1) << "the span between the sheets read as solid";
}

}  // namespace
}  // namespace splatcl::csm
