// The fit kernels (kernels/splat_fit.cl) against the native reference, and the growth rules on
// meshes whose answer is known.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>

#include "runtime/error.hpp"
#include "splats/fit.hpp"
#include "splats/pipeline.hpp"
#include "splats/reference.hpp"
#include "splats_test_support.hpp"

namespace splatcl::splats {
namespace {

using namespace testing;

struct Input {
  Samples samples;
  Neighborhoods neighbors;
};

Input prepare(const Mesh& mesh, const std::string& sampling = "vertices", ColorField field = ColorField::Grey, unsigned k = 10) {
  ColorSource colors;
  colors.field = field;
  colors.bounds = mesh.bounds();
  Input in;
  in.samples = sample_mesh(mesh, parse_sampling(sampling), colors);
  in.neighbors = find_neighbors(in.samples.positions, k);
  return in;
}

// Integer outputs exact; the shapes too (same float operations, correctly rounded on PoCL).
void expect_same(const FitResult& device, const FitResult& reference) {
  ASSERT_EQ(device.splats.size(), reference.splats.size());
  EXPECT_EQ(device.covered.offsets, reference.covered.offsets);
  EXPECT_EQ(device.covered.items, reference.covered.items);
  EXPECT_EQ(device.safe.offsets, reference.safe.offsets);
  EXPECT_EQ(device.safe.items, reference.safe.items);
  for (std::size_t i = 0; i < device.splats.size(); ++i) {
    const auto& a = device.splats[i];
    const auto& b = reference.splats[i];
    const float* pa = &a.center.x;
    const float* pb = &b.center.x;
    for (int c = 0; c < 16; ++c) ASSERT_EQ(pa[c], pb[c]) << "splat " << i << " component " << c;
    const float* ca = &device.clips[i].x;
    const float* cb = &reference.clips[i].x;
    for (int c = 0; c < 4; ++c) ASSERT_EQ(ca[c], cb[c]) << "clip of splat " << i << " component " << c;
  }
}

// Frames: the kernel's exp may differ from std::exp in the last bit, which can flip an
// orientation only where the weighted normal is orthogonal to the PCA normal; everything else is
// the same float arithmetic. Tolerance: 1e-5 per component, on every frame.
void expect_frames_close(const std::vector<Frame>& device, const std::vector<Frame>& reference) {
  ASSERT_EQ(device.size(), reference.size());
  for (std::size_t i = 0; i < device.size(); ++i) {
    const float* a = &device[i].u.x;
    const float* b = &reference[i].u.x;
    for (int c = 0; c < 12; ++c) ASSERT_NEAR(a[c], b[c], 1e-5f) << "frame " << i << " component " << c;
  }
}

void compare(const Input& in, const FitOptions& options) {
  const std::vector<Frame> frames = reference::fit_frames(in.samples, in.neighbors, options.crease_degrees);
  FitTimings timings;
  const FitResult device = fit_splats(runtime(), in.samples, in.neighbors, options, nullptr, &timings);
  expect_frames_close(device.frames, frames);
  // Growth from identical frames must agree exactly, in both kernel shapes.
  const FitResult expected = reference::grow_splats(in.samples, in.neighbors, frames, options);
  for (const Shape shape : {Shape::Cpu, Shape::Gpu}) {
    SCOPED_TRACE(to_string(shape));
    FitOptions shaped = options;
    shaped.shape = shape;
    expect_same(fit_splats(runtime(), in.samples, in.neighbors, shaped, &frames), expected);
  }
}

FitOptions geometry(float eps) {
  FitOptions options;
  options.eps = eps;
  return options;
}

TEST(SplatFit, KernelMatchesReferenceOnSphere) { compare(prepare(sphere_mesh(40, 60)), geometry(2e-3f)); }

TEST(SplatFit, KernelMatchesReferenceOnCubeGridWithColour) {
  FitOptions options = geometry(1e-3f);
  options.color_tolerance = 20;
  compare(prepare(cube_mesh(), "grid:12", ColorField::Hard), options);
}

TEST(SplatFit, KernelMatchesReferenceWithEverySwitch) {
  FitOptions options = geometry(2e-3f);
  options.literal_lambda = true;
  options.retest_violator = true;
  options.color_tolerance = 30;
  compare(prepare(sphere_mesh(30, 40), "vertices", ColorField::Soft), options);
}

TEST(SplatFit, KernelMatchesReferenceOnBunnySubset) {
  const std::string path = model_path("stanford-bunny.obj");
  if (path.empty()) GTEST_SKIP() << "stanford-bunny.obj not found in " << SPLATCL_MODELS_DIR;
  Input in = prepare(load_mesh(path));
  compare(in, geometry(3e-4f));
}

TEST(SplatFit, KernelMatchesReferenceWithClipping) {
  FitOptions options = geometry(1e-3f);
  options.clip = true;
  options.color_tolerance = 20;
  compare(prepare(cube_mesh(), "grid:12", ColorField::Hard), options);
  options.color_tolerance = 255;
  compare(prepare(sphere_mesh(30, 40)), options);
}

// The whole fit as `bench splats` checks it: the device's own frames (not the reference's), then the
// growth from them, bit for bit against reference::fit_splats, in both kernel shapes. Frames first
// (their bytes), so a difference names the first frame that differs rather than a covered index.
void expect_same_whole_fit(const Input& in, const FitOptions& options) {
  const FitResult expected = reference::fit_splats(in.samples, in.neighbors, options);
  for (const Shape shape : {Shape::Cpu, Shape::Gpu}) {
    SCOPED_TRACE(to_string(shape));
    FitOptions shaped = options;
    shaped.shape = shape;
    const FitResult device = fit_splats(runtime(), in.samples, in.neighbors, shaped);
    ASSERT_EQ(device.frames.size(), expected.frames.size());
    for (std::size_t i = 0; i < device.frames.size(); ++i) {
      const float* a = &device.frames[i].u.x;
      const float* b = &expected.frames[i].u.x;
      for (int c = 0; c < 12; ++c)  // xyz of u, v and n (w is padding: the kernel's negation makes it -0)
        if (c % 4 != 3) {
          ASSERT_EQ(std::bit_cast<std::uint32_t>(a[c]), std::bit_cast<std::uint32_t>(b[c])) << "frame " << i << " component " << c;
        }
    }
    expect_same(device, expected);
  }
}

// The size `splatcl bench splats` fits (stanford-bunny, the pipeline's sampling and k, ε = 0.0003:
// 34,834 samples, about a million covered entries): where Intel's runtime once gave other frames
// (docs/portability.md, "Splat fit on Intel's runtime"). Run on every device by devices.splats.
TEST(SplatFit, WholeFitMatchesReferenceBitForBitAtBenchSize) {
  const std::string path = model_path("stanford-bunny.obj");
  if (path.empty()) GTEST_SKIP() << "stanford-bunny.obj not found in " << SPLATCL_MODELS_DIR;
  const Mesh mesh = load_mesh(path);
  const PipelineOptions pipeline;
  ColorSource colors;
  colors.bounds = mesh.bounds();
  Input in;
  in.samples = sample_mesh(mesh, pipeline.sampling, colors);
  in.neighbors = find_neighbors(in.samples.positions, pipeline.k, &in.samples.normals, crease_cosine(pipeline.fit.crease_degrees));
  ASSERT_GT(in.samples.size(), 30000u);
  expect_same_whole_fit(in, geometry(3e-4f));
}

// The cube with hard colour edges: its frames' orientation test meets weighted normals orthogonal
// to the PCA normal (on the edges), where a one-ulp difference in a weight flips a frame.
TEST(SplatFit, WholeFitMatchesReferenceBitForBitOnCubeEdges) {
  FitOptions options = geometry(1e-3f);
  options.color_tolerance = 20;
  expect_same_whole_fit(prepare(cube_mesh(), "grid:12", ColorField::Hard), options);
}

TEST(SplatFit, ClippedSplatsKeepTheirSamplesAndCutTheRest) {
  FitOptions options = geometry(1e-3f);
  options.color_tolerance = 20;
  const Input in = prepare(cube_mesh(), "grid:12", ColorField::Hard);
  const FitResult plain = fit_splats(runtime(), in.samples, in.neighbors, options);
  options.clip = true;
  const FitResult fit = fit_splats(runtime(), in.samples, in.neighbors, options);
  std::size_t clipped = 0, larger = 0;
  for (std::size_t j = 0; j < fit.covered.size(); ++j) {
    const Vec4& clip = fit.clips[j];
    if (!std::isfinite(clip.z)) {
      ASSERT_EQ(fit.covered.row_size(j), plain.covered.row_size(j)) << "an unclipped splat grows as without clipping";
      continue;
    }
    ++clipped;
    larger += fit.covered.row_size(j) > plain.covered.row_size(j) ? 1 : 0;
    ASSERT_NEAR(clip.x * clip.x + clip.y * clip.y, 1.0f, 1e-5f);
    const SplatShape& s = fit.splats[j];
    for (const std::uint32_t* m = fit.covered.begin(j); m != fit.covered.end(j); ++m) {
      const Vec3 w = xyz(in.samples.positions[*m]) - xyz(s.center);
      const float x = dot(xyz(s.major), w) / s.major.w, y = dot(xyz(s.minor), w) / s.minor.w;
      ASSERT_LE(x * clip.x + y * clip.y, clip.z + 1e-5f) << "splat " << j << " cuts off its own sample " << *m;
    }
  }
  // Colour boundaries run through the cube's faces: many splats are clipped, and skipping violators
  // on one side lets many of them grow past where the unclipped walk stopped.
  EXPECT_GT(clipped, fit.covered.size() / 10);
  EXPECT_GT(larger, clipped / 4);
}

TEST(SplatFit, FlatPlaneGrowsPastTheFirstCapacity) {
  // 41 × 41 vertices in a plane: every splat can cover every sample, far more than the kernel's
  // first scratch capacity, so the growth is relaunched with more and must not truncate.
  const Input in = prepare(plane_mesh(40));
  FitTimings timings;
  const FitResult device = fit_splats(runtime(), in.samples, in.neighbors, geometry(1e-4f), nullptr, &timings);
  EXPECT_GE(timings.relaunches, 1u);
  for (std::size_t i = 0; i < device.covered.size(); ++i) ASSERT_EQ(device.covered.row_size(i), in.samples.size()) << i;
  expect_same(device, reference::fit_splats(in.samples, in.neighbors, geometry(1e-4f)));
  // Interior points are safe, hull points not; the start point always is.
  for (std::size_t i = 0; i < device.safe.size(); ++i) {
    ASSERT_EQ(device.safe.begin(i)[0], i);
    ASSERT_EQ(device.safe.row_size(i), in.samples.size() - 160 + (i % 41 == 0 || i % 41 == 40 || i < 41 || i >= 41 * 40 ? 1 : 0));
  }
}

TEST(SplatFit, CoveredSamplesLieWithinEpsAndInsideTheEllipse) {
  const Input in = prepare(sphere_mesh(40, 60));
  const float eps = 2e-3f;
  const FitResult fit = fit_splats(runtime(), in.samples, in.neighbors, geometry(eps));
  for (std::size_t j = 0; j < fit.covered.size(); ++j) {
    const SplatShape& s = fit.splats[j];
    ASSERT_EQ(fit.covered.begin(j)[0], j);
    ASSERT_GE(s.major.w, s.minor.w);
    for (const std::uint32_t* m = fit.covered.begin(j); m != fit.covered.end(j); ++m) {
      const Vec3 w = xyz(in.samples.positions[*m]) - xyz(s.center);
      ASSERT_LE(std::fabs(dot(xyz(s.normal), w)), eps * (1 + 1e-4f));
      const float x = dot(xyz(s.major), w) / s.major.w, y = dot(xyz(s.minor), w) / s.minor.w;
      ASSERT_LE(x * x / (s.major.w * s.major.w) + y * y / (s.minor.w * s.minor.w), 1.0f + 1e-4f) << "splat " << j;
    }
  }
}

TEST(SplatFit, ZeroColourToleranceStopsAtEveryColourChange) {
  FitOptions options = geometry(1.0f);  // geometry never stops: only colour does
  options.color_tolerance = 0;
  const Input in = prepare(cube_mesh(), "grid:10", ColorField::Hard);
  const FitResult fit = fit_splats(runtime(), in.samples, in.neighbors, options);
  for (std::size_t j = 0; j < fit.covered.size(); ++j)
    for (const std::uint32_t* m = fit.covered.begin(j); m != fit.covered.end(j); ++m)
      ASSERT_TRUE(in.samples.colors[*m] == in.samples.colors[j]);
  // φ = 255 equals the geometry-only fit on the same samples.
  FitOptions all = geometry(1e-3f);
  Input grey = prepare(cube_mesh(), "grid:10");
  const FitResult a = fit_splats(runtime(), in.samples, in.neighbors, all);
  const FitResult b = fit_splats(runtime(), grey.samples, grey.neighbors, all);
  EXPECT_EQ(a.covered.items, b.covered.items);
  EXPECT_EQ(a.safe.items, b.safe.items);
}

TEST(SplatFit, TinyInputs) {
  // One sample: no neighbours, a zero-size splat covering itself.
  Samples one;
  one.positions = {{1, 2, 3, 0}};
  one.normals = {{0, 0, 1, 0}};
  one.colors = {Rgba8{}};
  const Neighborhoods none = find_neighbors(one.positions, 10);
  const FitResult fit = fit_splats(runtime(), one, none, geometry(0.1f));
  ASSERT_EQ(fit.covered.items, std::vector<std::uint32_t>{0});
  ASSERT_EQ(fit.safe.items, std::vector<std::uint32_t>{0});
  expect_same(fit, reference::fit_splats(one, none, geometry(0.1f)));
  // A single triangle: three samples, k = 2.
  const Input tri = prepare(make_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}}, "triangle"));
  expect_same(fit_splats(runtime(), tri.samples, tri.neighbors, geometry(0.1f)), reference::fit_splats(tri.samples, tri.neighbors, geometry(0.1f)));
}

TEST(SplatFit, RejectsBadOptions) {
  const Input in = prepare(cube_mesh());
  EXPECT_THROW(fit_splats(runtime(), in.samples, in.neighbors, geometry(0.0f)), Error);
  EXPECT_THROW(fit_splats(runtime(), in.samples, in.neighbors, geometry(NAN)), Error);
  FitOptions bad = geometry(0.1f);
  bad.color_tolerance = 256;
  EXPECT_THROW(reference::fit_splats(in.samples, in.neighbors, bad), Error);
}

}  // namespace
}  // namespace splatcl::splats
