// Streaming per-pixel compression: kernel against the batch reference (identical segments) for
// every batch split, edge cases, and exhaustive losslessness of small builds.
#include <cmath>
#include <random>

#include "csm/build.hpp"
#include "csm/compress.hpp"
#include "csm_test_support.hpp"

namespace splatcl::csm {
namespace {

using namespace testing;

void expect_same(const Segments& a, const Segments& b) {
  ASSERT_EQ(a.offsets, b.offsets);
  ASSERT_EQ(a.end, b.end);
  for (std::size_t k = 0; k < a.size(); ++k) {
    ASSERT_EQ(a.lo[k], b.lo[k]) << k;
    ASSERT_EQ(a.hi[k], b.hi[k]) << k;
  }
}

Segments compress_on_device(const std::vector<float>& z1, const std::vector<float>& z2, std::size_t pixels, std::uint32_t maps,
                            std::uint32_t batch) {
  Runtime& rt = runtime();
  StreamingCompressor compressor(rt, pixels, maps);
  const std::size_t bytes = std::size_t{batch} * pixels * sizeof(float);
  cl::Buffer b1 = rt.buffer(CL_MEM_READ_WRITE, bytes, "z1"), b2 = rt.buffer(CL_MEM_READ_WRITE, bytes, "z2");
  for (std::uint32_t first = 0; first < maps; first += batch) {
    const std::uint32_t count = std::min(batch, maps - first);
    rt.queue().enqueueWriteBuffer(b1, CL_TRUE, 0, count * pixels * sizeof(float), z1.data() + first * pixels);
    rt.queue().enqueueWriteBuffer(b2, CL_TRUE, 0, count * pixels * sizeof(float), z2.data() + first * pixels);
    compressor.add(b1, b2, count);
  }
  return compressor.finish();
}

// Depth pairs drawn from a few surfaces so runs form, with empty and single-surface pixels.
void random_depths(std::mt19937& rng, std::size_t n, std::vector<float>& z1, std::vector<float>& z2) {
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  z1.resize(n);
  z2.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    const float kind = u(rng);
    if (kind < 0.1f) {
      z1[k] = 1.0f;
      z2[k] = INFINITY;
    } else if (kind < 0.15f) {
      z1[k] = z2[k] = 0.5f;
    } else {
      z1[k] = 0.3f + 0.1f * u(rng);
      z2[k] = z1[k] + 0.02f + 0.2f * u(rng);
    }
  }
}

TEST(CsmCompress, StreamingKernelMatchesReferenceForEveryBatchSplit) {
  std::mt19937 rng(3);
  for (const auto& [pixels, maps] : {std::pair<std::size_t, std::uint32_t>{1, 1}, {1, 37}, {13, 1}, {100, 64}, {257, 50}}) {
    std::vector<float> z1, z2;
    random_depths(rng, pixels * maps, z1, z2);
    const Segments reference = compress_reference(z1, z2, pixels, maps);
    EXPECT_EQ(reference.offsets.back(), reference.size());
    for (const std::uint32_t batch : {1u, 3u, 16u, maps}) {
      SCOPED_TRACE(::testing::Message() << pixels << " pixels, " << maps << " maps, batch " << batch);
      expect_same(compress_on_device(z1, z2, pixels, maps, batch), reference);
    }
  }
}

// Each batch's segments come with a full offsets array: they are folded into one as they come, so
// that many small batches (8192² maps one a batch) do not hold an array each (at 2048² and 1024
// maps, 2 a batch, peak memory 13.1 -> 7.3 GB). Coherent maps (few segments) fold most often.
TEST(CsmCompress, ManySmallBatchesAreFoldedAndGiveTheReferencesSegments) {
  std::mt19937 rng(5);
  constexpr std::size_t pixels = 300;
  constexpr std::uint32_t maps = 120;
  std::vector<float> z1(pixels * maps), z2(z1.size()), r1, r2;
  random_depths(rng, pixels * 6, r1, r2);
  // Each pixel sees 6 surfaces in turn, 20 maps each: at most one segment closes per pixel every 20 maps.
  for (std::size_t m = 0; m < maps; ++m)
    for (std::size_t p = 0; p < pixels; ++p) z1[m * pixels + p] = r1[(m / 20) * pixels + p], z2[m * pixels + p] = r2[(m / 20) * pixels + p];
  Runtime& rt = runtime();
  StreamingCompressor compressor(rt, pixels, maps);
  const std::size_t bytes = pixels * sizeof(float);
  cl::Buffer b1 = rt.buffer(CL_MEM_READ_WRITE, bytes, "z1"), b2 = rt.buffer(CL_MEM_READ_WRITE, bytes, "z2");
  const std::uint64_t offsets_bytes = (pixels + 1) * sizeof(std::uint32_t);
  for (std::uint32_t m = 0; m < maps; ++m) {
    rt.queue().enqueueWriteBuffer(b1, CL_TRUE, 0, bytes, z1.data() + m * pixels);
    rt.queue().enqueueWriteBuffer(b2, CL_TRUE, 0, bytes, z2.data() + m * pixels);
    compressor.add(b1, b2, 1);
    // The segments, and offsets arrays of at most a quarter of their bytes or 9 arrays, however many
    // batches came (unfolded: 120 arrays, 144 KB, at the end).
    const std::uint64_t segment_bytes = 12 * pixels * (m / 20 + 1);
    EXPECT_LE(compressor.held_bytes(), segment_bytes + segment_bytes / 4 + 10 * offsets_bytes) << "after map " << m;
  }
  expect_same(compressor.finish(), compress_reference(z1, z2, pixels, maps));
}

TEST(CsmCompress, MergeRuleEdgeCases) {
  // Empty pixels merge into one +inf run; single-surface pixels (z1 == z2) never merge; identical
  // pairs merge; touching intervals (max z1 == min z2) do not (strict rule).
  const std::vector<float> z1 = {1, 1, 1, 0.5f, 0.5f, 0.2f, 0.2f, 0.4f, 0.45f};
  const std::vector<float> z2 = {INFINITY, INFINITY, INFINITY, 0.5f, 0.5f, 0.4f, 0.4f, 0.5f, 0.6f};
  const Segments s = compress_reference(z1, z2, 1, 9);
  ASSERT_EQ(s.end, (std::vector<std::uint32_t>{2, 3, 4, 6, 8}));
  EXPECT_EQ(segment_depth(s.lo[0], s.hi[0]), INFINITY);
  EXPECT_EQ(segment_depth(s.lo[1], s.hi[1]), 0.5f);
  EXPECT_FLOAT_EQ(segment_depth(s.lo[3], s.hi[3]), 0.3f);
  expect_same(compress_on_device(z1, z2, 1, 9, 2), s);
}

TEST(CsmCompress, MidpointStaysBelowAdjacentUpperBound) {
  const float lo = 0.25f, hi = std::nextafter(lo, 1.0f);
  const float g = segment_depth(lo, hi);
  EXPECT_TRUE(lossless(g, lo, hi));
  EXPECT_LT(g, hi);
}

TEST(CsmCompress, SmallBuildsAreLosslessForEveryMapAndPixel) {
  // Device build against reference build, then an exhaustive check of every (map, pixel).
  struct Case {
    Mesh mesh;
    BuildOptions options;
  };
  std::vector<Case> cases;
  BuildOptions a;
  a.maps = 256;
  a.resolution = 24;
  a.batch_maps = 37;
  cases.push_back({scene_mesh(), a});
  BuildOptions b = a;
  b.distribution = Distribution::ThesisAo;
  b.order = Order::ZigzagV;
  b.maps = 128;
  b.single_hit = SingleHit::Exact;
  cases.push_back({square_mesh(), b});
  BuildOptions c = a;
  c.order = Order::Hilbert;
  c.pole = PoleAxis::X180;
  c.distribution = Distribution::Regular;
  cases.push_back({sphere_mesh(10, 20), c});
  for (const Case& t : cases) {
    SCOPED_TRACE(t.mesh.source);
    const BuildResult device = build_csm(t.mesh, t.options, &runtime());
    BuildOptions whole = t.options;
    whole.batch_maps = 0;
    expect_same(build_csm(t.mesh, whole, nullptr).segments, device.segments);
    const BuildResult reference = build_csm(t.mesh, t.options, nullptr);
    expect_same(device.segments, reference.segments);
    EXPECT_LT(device.csm.segments(), std::size_t{t.options.maps} * device.csm.pixels());
    const LosslessReport report = check_lossless(device.csm, t.mesh, &runtime());
    EXPECT_EQ(report.samples, std::uint64_t{t.options.maps} * device.csm.pixels());
    EXPECT_EQ(report.violations, 0u) << "first at map " << report.first_map << " pixel " << report.first_pixel;
  }
}

TEST(CsmCompress, LosslessCheckFindsAWrongDepth) {
  BuildOptions o;
  o.maps = 16;
  o.resolution = 16;
  const Mesh mesh = cube_mesh();
  BuildResult result = build_csm(mesh, o, nullptr);
  // Put a surface-pixel's run in front of its first surface: points on it would then be shadowed.
  const std::size_t pixel = 8 * 16 + 8;
  result.csm.depth[result.csm.offsets[pixel]] = 0.0f;
  EXPECT_GT(check_lossless(result.csm, mesh, nullptr).violations, 0u);
}

}  // namespace
}  // namespace splatcl::csm
