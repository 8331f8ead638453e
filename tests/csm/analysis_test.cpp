// The compression thesis's alternative modes (per-map, 3-D and 4-D Hilbert) and analyses (k-means,
// Haar wavelet): the n-D Hilbert curve is a unit-step bijection, every mode is exactly lossless on
// small builds (each (map, pixel) decoded through the mode's own lookup), segment counts match a
// brute-force segmentation, and the analyses give their exact values on constructed inputs.
#include <algorithm>
#include <cmath>
#include <random>

#include "csm/analysis.hpp"
#include "csm_test_support.hpp"
#include "runtime/error.hpp"

namespace splatcl::csm {
namespace {

using namespace testing;

TEST(CsmAnalysis, HilbertCurveIsAUnitStepBijection) {
  for (std::uint32_t dims = 2; dims <= 4; ++dims)
    for (std::uint32_t bits = 1; bits <= 3; ++bits) {
      const std::uint64_t cells = std::uint64_t{1} << (dims * bits);
      std::vector<std::uint8_t> seen(cells, 0);
      std::uint32_t previous[4] = {}, x[4] = {};
      for (std::uint64_t h = 0; h < cells; ++h) {
        hilbert_point(h, dims, bits, x);
        std::uint64_t flat = 0;
        for (std::uint32_t i = 0; i < dims; ++i) {
          ASSERT_LT(x[i], 1u << bits);
          flat = (flat << bits) | x[i];
        }
        EXPECT_FALSE(seen[flat]) << "dims " << dims << " bits " << bits << " index " << h;
        seen[flat] = 1;
        EXPECT_EQ(hilbert_index(x, dims, bits), h);
        if (h > 0) {
          std::uint32_t step = 0;
          for (std::uint32_t i = 0; i < dims; ++i) step += x[i] > previous[i] ? x[i] - previous[i] : previous[i] - x[i];
          EXPECT_EQ(step, 1u) << "dims " << dims << " bits " << bits << " index " << h;
        }
        std::copy(x, x + dims, previous);
      }
    }
  std::uint32_t origin[4];
  hilbert_point(0, 3, 0, origin);
  EXPECT_EQ(origin[0], 0u);
}

TEST(CsmAnalysis, PixelCurvesAreBijections) {
  for (PixelCurve curve : {PixelCurve::Hilbert, PixelCurve::ZigzagH, PixelCurve::ZigzagV})
    for (std::uint32_t m : {1u, 2u, 8u, 6u}) {
      if (curve == PixelCurve::Hilbert && m == 6) continue;
      std::vector<int> seen(m * m, 0);
      for (std::uint32_t y = 0; y < m; ++y)
        for (std::uint32_t x = 0; x < m; ++x) ++seen.at(pixel_curve_index(curve, m, x, y));
      EXPECT_TRUE(std::all_of(seen.begin(), seen.end(), [](int v) { return v == 1; })) << to_string(curve) << " " << m;
    }
  EXPECT_EQ(parse_compression_mode("hilbert-4d"), CompressionMode::Hilbert4d);
  EXPECT_THROW(parse_compression_mode("octree"), Error);
  EXPECT_THROW(parse_pixel_curve("spiral"), Error);
}

// Random dual depths with empty pixels (1, +inf) and exact single hits (z1 = z2).
void random_depths(std::uint32_t maps, std::size_t pixels, std::uint32_t seed, std::vector<float>& z1, std::vector<float>& z2) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  z1.resize(maps * pixels);
  z2.resize(z1.size());
  for (std::size_t k = 0; k < z1.size(); ++k) {
    const float kind = u(rng);
    if (kind < 0.2f) {
      z1[k] = 1.0f;
      z2[k] = INFINITY;
    } else if (kind < 0.25f) {
      z1[k] = z2[k] = u(rng);
    } else {
      z1[k] = 0.3f + 0.1f * u(rng);
      z2[k] = 0.45f + 0.5f * u(rng);
    }
  }
}

// Brute force: the samples sorted by their mode position, then the greedy rule; the segment count.
std::uint64_t brute_force_segments(const std::vector<float>& z1, const std::vector<float>& z2, std::uint32_t maps,
                                   std::uint32_t m, std::uint32_t cols, const ModeOptions& o) {
  struct Sample {
    std::uint64_t list, position;
    float a, b;
  };
  std::vector<Sample> samples;
  const std::size_t pixels = std::size_t{m} * m;
  std::uint32_t bits = 0;
  while ((1u << bits) < (o.mode == CompressionMode::Hilbert4d ? std::max({(maps + cols - 1) / cols, cols, m}) : m)) ++bits;
  for (std::uint32_t i = 0; i < maps; ++i)
    for (std::uint32_t y = 0; y < m; ++y)
      for (std::uint32_t x = 0; x < m; ++x) {
        Sample s{0, 0, z1[i * pixels + y * m + x], z2[i * pixels + y * m + x]};
        if (o.mode == CompressionMode::PerMap) {
          s.list = i;
          s.position = pixel_curve_index(o.pixel_curve, m, x, y);
        } else if (o.mode == CompressionMode::Hilbert3d) {
          const std::uint32_t c[3] = {x, y, i % m};
          s.list = i / m;
          s.position = hilbert_index(c, 3, bits);
        } else {
          const std::uint32_t c[4] = {i / cols, i % cols, x, y};
          s.position = hilbert_index(c, 4, bits);
        }
        samples.push_back(s);
      }
  std::sort(samples.begin(), samples.end(), [](const Sample& l, const Sample& r) {
    return l.list != r.list ? l.list < r.list : l.position < r.position;
  });
  std::uint64_t segments = 0;
  float lo = 0, hi = 0;
  for (std::size_t k = 0; k < samples.size(); ++k) {
    const Sample& s = samples[k];
    const float nlo = std::fmax(lo, s.a), nhi = std::fmin(hi, s.b);
    if (k > 0 && samples[k - 1].list == s.list && nlo < nhi) {
      lo = nlo;
      hi = nhi;
    } else {
      ++segments;
      lo = s.a;
      hi = s.b;
    }
  }
  return segments;
}

TEST(CsmAnalysis, EveryModeIsLosslessOnRandomDepthsAndMatchesBruteForce) {
  struct Case {
    std::uint32_t maps, m, cols;
  };
  // 3-D: N a multiple of M, N not a multiple of M, N < M. 4-D: square grid and a T x 2T grid.
  for (const Case c : {Case{64, 8, 8}, Case{36, 8, 6}, Case{4, 8, 2}, Case{32, 4, 8}})
    for (ModeOptions o : {ModeOptions{CompressionMode::PerMap, PixelCurve::Hilbert}, ModeOptions{CompressionMode::PerMap, PixelCurve::ZigzagH},
                          ModeOptions{CompressionMode::PerMap, PixelCurve::ZigzagV}, ModeOptions{CompressionMode::Hilbert3d},
                          ModeOptions{CompressionMode::Hilbert4d}}) {
      std::vector<float> z1, z2;
      random_depths(c.maps, std::size_t{c.m} * c.m, c.maps + c.m, z1, z2);
      const ModeResult r = compress_in_mode(z1, z2, c.maps, c.m, c.cols, o);
      const std::string what = std::string(to_string(o.mode)) + "/" + to_string(o.pixel_curve) + " maps " + std::to_string(c.maps);
      EXPECT_EQ(r.samples, std::uint64_t{c.maps} * c.m * c.m) << what;
      EXPECT_EQ(r.violations, 0u) << what;
      EXPECT_EQ(r.segments, brute_force_segments(z1, z2, c.maps, c.m, c.cols, o)) << what;
      EXPECT_GT(r.segments, 0u);
      EXPECT_LE(r.segments, r.samples);
    }
}

TEST(CsmAnalysis, EveryModeIsExactlyLosslessOnSmallBuilds) {
  const Mesh mesh = scene_mesh();
  for (std::uint32_t maps : {64u, 36u}) {
    BuildOptions build;
    build.maps = maps;
    build.resolution = 16;
    build.order = maps == 64 ? Order::Hilbert : Order::ZigzagH;
    for (CompressionMode mode : {CompressionMode::PerMap, CompressionMode::Hilbert3d, CompressionMode::Hilbert4d}) {
      ModeOptions o;
      o.mode = mode;
      const ModeResult device = compress_in_mode(mesh, build, o, &runtime());
      EXPECT_EQ(device.samples, std::uint64_t{maps} * 256) << to_string(mode);
      EXPECT_EQ(device.violations, 0u) << to_string(mode);
      // Streaming on the device and the reference capture give the same segments.
      const ModeResult reference = compress_in_mode(mesh, build, o, nullptr);
      EXPECT_EQ(reference.segments, device.segments) << to_string(mode);
      EXPECT_EQ(reference.violations, 0u);
      std::vector<float> z1, z2;
      capture_all_maps(mesh, build, nullptr, z1, z2, std::uint64_t{1} << 30);
      const SphereGrid grid(build.distribution, build.order, build.pole, maps);
      EXPECT_EQ(compress_in_mode(z1, z2, maps, 16, grid.cols(), o).segments, device.segments) << to_string(mode);
    }
  }
}

TEST(CsmAnalysis, ModesAndAnalysesCaptureWithTheBuildsMethod) {
  // The modes and analyses take their maps from the build's capture path: per-pixel compression
  // of those maps gives exactly the streaming build's segments, for either method, and every mode
  // stays lossless on rasterized (the default) and ray-cast maps.
  const Mesh mesh = sphere_mesh(9, 14);
  for (CaptureMethod method : {CaptureMethod::Raster, CaptureMethod::Raycast}) {
    BuildOptions build;
    build.maps = 64;
    build.resolution = 16;
    build.capture = method;
    const BuildResult streamed = build_csm(mesh, build, &runtime());
    EXPECT_EQ(streamed.csm.info.capture, method);
    for (Runtime* rt : {&runtime(), static_cast<Runtime*>(nullptr)}) {
      std::vector<float> z1, z2;
      capture_all_maps(mesh, build, rt, z1, z2, std::uint64_t{1} << 30);
      const Segments segments = compress_reference(z1, z2, 256, 64);
      EXPECT_EQ(segments.offsets, streamed.segments.offsets) << to_string(method);
      EXPECT_EQ(segments.end, streamed.segments.end) << to_string(method);
      EXPECT_EQ(segments.lo, streamed.segments.lo) << to_string(method);
      EXPECT_EQ(segments.hi, streamed.segments.hi) << to_string(method);
    }
    for (CompressionMode mode : {CompressionMode::PerMap, CompressionMode::Hilbert3d, CompressionMode::Hilbert4d}) {
      ModeOptions o;
      o.mode = mode;
      const ModeResult device = compress_in_mode(mesh, build, o, &runtime());
      EXPECT_EQ(device.samples, std::uint64_t{64} * 256) << to_string(mode) << " " << to_string(method);
      EXPECT_EQ(device.violations, 0u) << to_string(mode) << " " << to_string(method);
      EXPECT_EQ(compress_in_mode(mesh, build, o, nullptr).segments, device.segments) << to_string(mode) << " " << to_string(method);
    }
  }
}

TEST(CsmAnalysis, ModesRejectWhatTheyCannotTake) {
  const Mesh mesh = cube_mesh();
  BuildOptions build;
  build.maps = 16;
  build.resolution = 12;
  ModeOptions o;
  o.mode = CompressionMode::PerMap;
  EXPECT_THROW(compress_in_mode(mesh, build, o, nullptr), Error);  // Hilbert pixel curve on 12 x 12
  o.pixel_curve = PixelCurve::ZigzagH;
  EXPECT_EQ(compress_in_mode(mesh, build, o, nullptr).violations, 0u);
  o.mode = CompressionMode::Hilbert4d;
  o.max_memory_bytes = 1000;
  EXPECT_THROW(compress_in_mode(mesh, build, o, nullptr), Error);
  o.mode = CompressionMode::PerPixel;
  EXPECT_THROW(compress_in_mode(mesh, build, o, nullptr), Error);
}

TEST(CsmAnalysis, KMeansWithKEqualToNIsPerPixelAndFewerClustersCostErrors) {
  const std::uint32_t maps = 16;
  const std::size_t pixels = 25;
  std::vector<float> z1, z2;
  random_depths(maps, pixels, 7, z1, z2);
  const Segments exact = compress_reference(z1, z2, pixels, maps);
  const std::vector<KMeansResult> r = kmeans_analysis(z1, z2, maps, pixels, {maps, 1, 4}, 3);
  ASSERT_EQ(r.size(), 3u);
  EXPECT_EQ(r[0].segments, exact.size());
  EXPECT_EQ(r[0].wrong_samples, 0u);
  EXPECT_EQ(r[0].corrected_bytes(), r[0].plain_bytes);
  EXPECT_EQ(r[1].segments, pixels);  // one mean map repeated: one segment per pixel
  EXPECT_GT(r[1].wrong_samples, 0u);
  EXPECT_EQ(r[1].corrected_bytes(), r[1].plain_bytes + 8 * r[1].wrong_samples);
  EXPECT_GE(r[2].segments, pixels);
  for (const KMeansResult& k : r) EXPECT_EQ(k.samples, std::uint64_t{maps} * pixels);
  EXPECT_THROW(kmeans_analysis(z1, z2, maps, pixels, {0}, 1), Error);
  EXPECT_THROW(kmeans_analysis(z1, z2, maps, pixels, {maps + 1}, 1), Error);
  EXPECT_THROW(kmeans_analysis(z1, z2, maps, pixels, {4}, 1, 0), Error);  // no iteration: no map had a cluster (a crash)
}

TEST(CsmAnalysis, KMeansWithKEqualToNReproducesPerPixelOnABuild) {
  // Real captures: empty pixels, sphere exits a hair above 1; k = N must change nothing.
  BuildOptions build;
  build.maps = 64;
  build.resolution = 16;
  std::vector<float> z1, z2;
  capture_all_maps(scene_mesh(), build, &runtime(), z1, z2, std::uint64_t{1} << 30);
  const KMeansResult r = kmeans_analysis(z1, z2, 64, 256, {64}, 1).at(0);
  EXPECT_EQ(r.segments, compress_reference(z1, z2, 256, 64).size());
  EXPECT_EQ(r.wrong_samples, 0u);
}

TEST(CsmAnalysis, WaveletCountsZerosExactly) {
  Csm csm;
  csm.info.resolution = 8;
  csm.info.maps = 10;
  csm.offsets.resize(65);
  for (std::uint32_t p = 0; p <= 64; ++p) csm.offsets[p] = p;
  csm.depth.assign(64, 0.375f);
  csm.end.assign(64, 9);
  WaveletResult w = wavelet_analysis(csm);
  EXPECT_EQ(w.layers, 1u);
  EXPECT_EQ(w.coefficients, 128u);
  EXPECT_EQ(w.zeros, 126u);  // a constant layer keeps only its average
  EXPECT_DOUBLE_EQ(w.estimated_bytes(), 8.0);
  // Pixel 0 gets a second segment: two layers, the second zero but for one value.
  csm.offsets.assign(65, 0);
  for (std::uint32_t p = 1; p <= 64; ++p) csm.offsets[p] = p + 1;
  csm.depth.insert(csm.depth.begin(), INFINITY);
  csm.end.insert(csm.end.begin(), 4);
  w = wavelet_analysis(csm);
  EXPECT_EQ(w.layers, 2u);
  EXPECT_EQ(w.coefficients, 256u);
  EXPECT_LT(w.zeros, 256u);
  EXPECT_GT(w.zeros, 128u);
  csm.info.resolution = 6;
  EXPECT_THROW(wavelet_analysis(csm), Error);
}

}  // namespace
}  // namespace splatcl::csm
