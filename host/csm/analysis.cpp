#include "csm/analysis.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <numeric>
#include <random>

#include "runtime/error.hpp"
#include "runtime/profiling.hpp"
#include "core/parallel.hpp"

namespace splatcl::csm {
namespace {

constexpr const char* kModeNames[] = {"per-pixel", "per-map", "hilbert-3d", "hilbert-4d"};
constexpr const char* kCurveNames[] = {"hilbert", "zigzag-h", "zigzag-v"};

std::uint32_t ceil_log2(std::uint64_t v) { return v <= 1 ? 0 : static_cast<std::uint32_t>(std::bit_width(v - 1)); }

// The stored depth of `position` in segments [first, last) of `s` (lower bound on the end index).
float decode(const Segments& s, std::size_t first, std::size_t last, std::uint64_t position) {
  const auto begin = s.end.begin() + static_cast<std::ptrdiff_t>(first), stop = s.end.begin() + static_cast<std::ptrdiff_t>(last);
  const auto it = std::lower_bound(begin, stop, position, [](std::uint32_t e, std::uint64_t v) { return e < v; });
  if (it == stop) return NAN;  // past the list: counted as a violation
  const auto k = static_cast<std::size_t>(it - s.end.begin());
  return segment_depth(s.lo[k], s.hi[k]);
}

// Appends `part`'s segments to the counts of `result`.
void account(ModeResult& result, const Segments& part, std::uint64_t lists) {
  result.lists += lists;
  result.segments += part.size();
}

struct PixelCurveTable {
  std::vector<std::uint32_t> pixel_at, index_of;  // curve position → pixel, pixel → curve position
  PixelCurveTable(PixelCurve curve, std::uint32_t m) : pixel_at(std::size_t{m} * m), index_of(pixel_at.size()) {
    for (std::uint32_t y = 0; y < m; ++y)
      for (std::uint32_t x = 0; x < m; ++x) {
        const std::uint32_t d = pixel_curve_index(curve, m, x, y);
        index_of[y * m + x] = d;
        pixel_at[d] = y * m + x;
      }
  }
};

// Compresses maps [first, first + count) (z1, z2 laid out [k][pixel]) in `mode` and checks them.
class ModeCompressor {
 public:
  ModeCompressor(const ModeOptions& options, std::uint32_t maps, std::uint32_t resolution, std::uint32_t grid_cols)
      : options_(options), maps_(maps), m_(resolution), cols_(grid_cols) {
    if (options.mode == CompressionMode::PerPixel) throw Error("per-pixel compression is build_csm's; the mode compressor takes the alternatives");
    if (maps == 0 || resolution == 0) throw Error("mode compression needs at least one map and one pixel");
    if (options.mode == CompressionMode::PerMap) {
      if (options.pixel_curve == PixelCurve::Hilbert && !std::has_single_bit(resolution))
        throw Error(fmt::format("per-map compression along a Hilbert curve needs a power-of-two resolution, not {}", resolution));
      curve_ = std::make_unique<PixelCurveTable>(options.pixel_curve, resolution);
    } else if (options.mode == CompressionMode::Hilbert3d) {
      bits_ = ceil_log2(resolution);
    } else {
      if (grid_cols == 0) throw Error("4-D Hilbert compression needs the grid's column count");
      rows_ = (maps + grid_cols - 1) / grid_cols;
      bits_ = ceil_log2(std::max({std::uint64_t{rows_}, std::uint64_t{grid_cols}, std::uint64_t{resolution}}));
      if (4 * bits_ > 32) throw Error(fmt::format("4-D Hilbert compression: a hypercube of side 2^{} has more than 2^32 cells", bits_));
    }
  }

  // Maps per call: per-map any, 3-D Hilbert whole blocks of M maps, 4-D Hilbert all maps.
  std::uint32_t block_maps() const {
    return options_.mode == CompressionMode::Hilbert3d ? m_ : options_.mode == CompressionMode::Hilbert4d ? maps_ : 0;
  }

  void add(const std::vector<float>& z1, const std::vector<float>& z2, std::uint32_t first, std::uint32_t count, ModeResult& result) {
    const std::size_t pixels = std::size_t{m_} * m_;
    if (options_.mode == CompressionMode::PerMap) {
      std::vector<Segments> per_map(count);
      std::vector<std::uint64_t> violations(count, 0);
      parallel_for(count, 4, [&](std::size_t k, std::size_t) {
        Segments& s = per_map[k];
        s.end.clear();
        s.offsets.clear();
        ScanSegmenter scan(s);
        const float* a = z1.data() + k * pixels;
        const float* b = z2.data() + k * pixels;
        for (std::uint32_t d = 0; d < pixels; ++d) scan.add(a[curve_->pixel_at[d]], b[curve_->pixel_at[d]], d);
        scan.close();
        for (std::size_t p = 0; p < pixels; ++p) {
          const std::uint32_t d = pixel_curve_index(options_.pixel_curve, m_, static_cast<std::uint32_t>(p % m_), static_cast<std::uint32_t>(p / m_));
          violations[k] += !lossless(decode(s, 0, s.size(), d), a[p], b[p]);
        }
      });
      for (std::uint32_t k = 0; k < count; ++k) {
        account(result, per_map[k], 1);
        result.violations += violations[k];
      }
      result.samples += std::uint64_t{count} * pixels;
      return;
    }
    Segments s;
    s.offsets.clear();
    ScanSegmenter scan(s);
    std::uint32_t c[4];
    if (options_.mode == CompressionMode::Hilbert3d) {
      const std::uint64_t cells = std::uint64_t{1} << (3 * bits_);
      for (std::uint64_t h = 0; h < cells; ++h) {
        hilbert_point(h, 3, bits_, c);
        if (c[0] < m_ && c[1] < m_ && c[2] < count) {
          const std::size_t at = std::size_t{c[2]} * pixels + std::size_t{c[1]} * m_ + c[0];
          scan.add(z1[at], z2[at], h);
        }
      }
    } else {
      const std::uint64_t cells = std::uint64_t{1} << (4 * bits_);
      for (std::uint64_t h = 0; h < cells; ++h) {
        hilbert_point(h, 4, bits_, c);
        const std::uint64_t i = std::uint64_t{c[0]} * cols_ + c[1];
        if (c[0] < rows_ && c[1] < cols_ && i < maps_ && c[2] < m_ && c[3] < m_) {
          const std::size_t at = static_cast<std::size_t>(i) * pixels + std::size_t{c[3]} * m_ + c[2];
          scan.add(z1[at], z2[at], h);
        }
      }
    }
    scan.close();
    account(result, s, 1);
    std::vector<std::uint64_t> violations(worker_count(count, 1), 0);
    parallel_for(count, 1, [&](std::size_t k, std::size_t w) {
      std::uint32_t q[4];
      for (std::size_t p = 0; p < pixels; ++p) {
        std::uint64_t h = 0;
        if (options_.mode == CompressionMode::Hilbert3d) {
          q[0] = static_cast<std::uint32_t>(p % m_);
          q[1] = static_cast<std::uint32_t>(p / m_);
          q[2] = static_cast<std::uint32_t>(k);
          h = hilbert_index(q, 3, bits_);
        } else {
          const std::uint64_t i = first + k;
          q[0] = static_cast<std::uint32_t>(i / cols_);
          q[1] = static_cast<std::uint32_t>(i % cols_);
          q[2] = static_cast<std::uint32_t>(p % m_);
          q[3] = static_cast<std::uint32_t>(p / m_);
          h = hilbert_index(q, 4, bits_);
        }
        violations[w] += !lossless(decode(s, 0, s.size(), h), z1[k * pixels + p], z2[k * pixels + p]);
      }
    });
    for (std::uint64_t v : violations) result.violations += v;
    result.samples += std::uint64_t{count} * pixels;
  }

 private:
  ModeOptions options_;
  std::uint32_t maps_, m_, cols_, rows_ = 0, bits_ = 0;
  std::unique_ptr<PixelCurveTable> curve_;
};

// The build's grid and scene with the one host capture path (HostMapCapture), by the build's
// capture method, so that every mode compresses the maps a per-pixel build would.
class MapSource {
 public:
  MapSource(const Mesh& mesh, const BuildOptions& b, Runtime* runtime, std::uint32_t batch_maps)
      : grid_(b.distribution, b.order, b.pole, b.maps),
        scene_(mesh, bounding_sphere(mesh), b.resolution, b.single_hit, b.hit_epsilon),
        capture_(mesh, grid_, scene_, b.capture, runtime, batch_maps) {}
  std::size_t pixels() const { return scene_.pixels(); }
  void get(std::uint32_t first, std::uint32_t count, std::vector<float>& z1, std::vector<float>& z2) { capture_.get(first, count, z1, z2); }

 private:
  SphereGrid grid_;
  CaptureScene scene_;
  HostMapCapture capture_;
};

}  // namespace

const char* to_string(CompressionMode value) { return kModeNames[static_cast<std::uint32_t>(value)]; }
const char* to_string(PixelCurve value) { return kCurveNames[static_cast<std::uint32_t>(value)]; }

CompressionMode parse_compression_mode(const std::string& text) {
  for (std::uint32_t i = 0; i < std::size(kModeNames); ++i)
    if (text == kModeNames[i]) return static_cast<CompressionMode>(i);
  throw Error("unknown compression mode '" + text + "' (one of: per-pixel, per-map, hilbert-3d, hilbert-4d)");
}

PixelCurve parse_pixel_curve(const std::string& text) {
  for (std::uint32_t i = 0; i < std::size(kCurveNames); ++i)
    if (text == kCurveNames[i]) return static_cast<PixelCurve>(i);
  throw Error("unknown pixel order '" + text + "' (one of: hilbert, zigzag-h, zigzag-v)");
}

// Skilling, "Programming the Hilbert curve" (AIP Conf. Proc. 707, 2004): coordinates ↔ the
// "transposed" index (its bits dealt round-robin over the dims, most significant first).
void hilbert_point(std::uint64_t index, std::uint32_t dims, std::uint32_t bits, std::uint32_t* x) {
  for (std::uint32_t i = 0; i < dims; ++i) x[i] = 0;
  if (bits == 0) return;
  std::uint32_t bit = dims * bits;
  for (std::uint32_t level = bits; level-- > 0;)
    for (std::uint32_t i = 0; i < dims; ++i) x[i] |= static_cast<std::uint32_t>((index >> --bit) & 1u) << level;
  const std::uint32_t n = 2u << (bits - 1);
  std::uint32_t t = x[dims - 1] >> 1;
  for (std::uint32_t i = dims - 1; i > 0; --i) x[i] ^= x[i - 1];
  x[0] ^= t;
  for (std::uint32_t q = 2; q != n; q <<= 1) {
    const std::uint32_t p = q - 1;
    for (std::uint32_t i = dims; i-- > 0;) {
      if (x[i] & q) {
        x[0] ^= p;
      } else {
        t = (x[0] ^ x[i]) & p;
        x[0] ^= t;
        x[i] ^= t;
      }
    }
  }
}

std::uint64_t hilbert_index(const std::uint32_t* coords, std::uint32_t dims, std::uint32_t bits) {
  if (bits == 0) return 0;
  std::uint32_t x[4];
  for (std::uint32_t i = 0; i < dims; ++i) x[i] = coords[i];
  const std::uint32_t m = 1u << (bits - 1);
  for (std::uint32_t q = m; q > 1; q >>= 1) {
    const std::uint32_t p = q - 1;
    for (std::uint32_t i = 0; i < dims; ++i) {
      if (x[i] & q) {
        x[0] ^= p;
      } else {
        const std::uint32_t t = (x[0] ^ x[i]) & p;
        x[0] ^= t;
        x[i] ^= t;
      }
    }
  }
  for (std::uint32_t i = 1; i < dims; ++i) x[i] ^= x[i - 1];
  std::uint32_t t = 0;
  for (std::uint32_t q = m; q > 1; q >>= 1)
    if (x[dims - 1] & q) t ^= q - 1;
  for (std::uint32_t i = 0; i < dims; ++i) x[i] ^= t;
  std::uint64_t index = 0;
  for (std::uint32_t level = bits; level-- > 0;)
    for (std::uint32_t i = 0; i < dims; ++i) index = (index << 1) | ((x[i] >> level) & 1u);
  return index;
}

std::uint32_t pixel_curve_index(PixelCurve curve, std::uint32_t m, std::uint32_t x, std::uint32_t y) {
  switch (curve) {
    case PixelCurve::ZigzagH: return y * m + (y % 2 ? m - 1 - x : x);
    case PixelCurve::ZigzagV: return x * m + (x % 2 ? m - 1 - y : y);
    case PixelCurve::Hilbert: break;
  }
  const std::uint32_t c[2] = {x, y};
  return static_cast<std::uint32_t>(hilbert_index(c, 2, ceil_log2(m)));
}

void ScanSegmenter::add(float z1, float z2, std::uint64_t position) {
  if (open_) {
    const float nlo = std::fmax(lo_, z1), nhi = std::fmin(hi_, z2);
    if (nlo < nhi) {
      lo_ = nlo;
      hi_ = nhi;
      last_ = position;
      return;
    }
    close();
  }
  open_ = true;
  lo_ = z1;
  hi_ = z2;
  last_ = position;
}

void ScanSegmenter::close() {
  if (!open_) return;
  out_.lo.push_back(lo_);
  out_.hi.push_back(hi_);
  out_.end.push_back(static_cast<std::uint32_t>(last_));
  open_ = false;
}

ModeResult compress_in_mode(const std::vector<float>& z1, const std::vector<float>& z2, std::uint32_t maps, std::uint32_t resolution,
                            std::uint32_t grid_cols, const ModeOptions& options) {
  const std::size_t pixels = std::size_t{resolution} * resolution;
  if (z1.size() != pixels * maps || z2.size() != z1.size()) throw Error("compress_in_mode: depth arrays do not hold maps x pixels values");
  ModeCompressor compressor(options, maps, resolution, grid_cols);
  ModeResult result;
  const std::uint32_t block = compressor.block_maps() ? compressor.block_maps() : maps;
  std::vector<float> a, b;
  for (std::uint32_t first = 0; first < maps; first += block) {
    const std::uint32_t count = std::min(block, maps - first);
    a.assign(z1.begin() + static_cast<std::ptrdiff_t>(first * pixels), z1.begin() + static_cast<std::ptrdiff_t>((first + count) * pixels));
    b.assign(z2.begin() + static_cast<std::ptrdiff_t>(first * pixels), z2.begin() + static_cast<std::ptrdiff_t>((first + count) * pixels));
    compressor.add(a, b, first, count, result);
  }
  return result;
}

void capture_all_maps(const Mesh& mesh, const BuildOptions& build, Runtime* runtime, std::vector<float>& z1,
                      std::vector<float>& z2, std::uint64_t max_bytes, const BuildProgress& progress) {
  const std::uint64_t bytes = 8ull * build.maps * build.resolution * build.resolution;
  if (bytes > max_bytes)
    throw Error(fmt::format("keeping all {} maps of {}x{} in memory needs {:.0f} MiB, above the limit of {:.0f} MiB", build.maps,
                            build.resolution, build.resolution, static_cast<double>(bytes) / 1048576.0,
                            static_cast<double>(max_bytes) / 1048576.0));
  const std::uint32_t batch = build.batch_maps ? std::min(build.batch_maps, build.maps) : default_batch_maps(build.resolution, build.maps);
  MapSource source(mesh, build, runtime, batch);
  const std::size_t pixels = source.pixels();
  z1.resize(std::size_t{build.maps} * pixels);
  z2.resize(z1.size());
  std::vector<float> a, b;
  for (std::uint32_t first = 0; first < build.maps; first += batch) {
    const std::uint32_t count = std::min(batch, build.maps - first);
    source.get(first, count, a, b);
    std::copy(a.begin(), a.end(), z1.begin() + static_cast<std::ptrdiff_t>(first * pixels));
    std::copy(b.begin(), b.end(), z2.begin() + static_cast<std::ptrdiff_t>(first * pixels));
    if (progress) progress(first + count, build.maps);
  }
}

ModeResult compress_in_mode(const Mesh& mesh, const BuildOptions& build, const ModeOptions& options, Runtime* runtime,
                            const BuildProgress& progress) {
  const SphereGrid grid(build.distribution, build.order, build.pole, build.maps);
  if (build.resolution == 0) throw Error("mode compression needs a resolution of at least 1");
  ModeCompressor compressor(options, build.maps, build.resolution, grid.cols());
  ModeResult result;
  std::vector<float> z1, z2;
  if (options.mode == CompressionMode::Hilbert4d) {
    Stopwatch clock;
    capture_all_maps(mesh, build, runtime, z1, z2, options.max_memory_bytes, progress);
    result.capture_ms = clock.elapsed_ms();
    Stopwatch compress_clock;
    compressor.add(z1, z2, 0, build.maps, result);
    result.compress_ms = compress_clock.elapsed_ms();
    return result;
  }
  const std::uint32_t batch = compressor.block_maps() ? compressor.block_maps()
                              : build.batch_maps      ? std::min(build.batch_maps, build.maps)
                                                      : default_batch_maps(build.resolution, build.maps);
  MapSource source(mesh, build, runtime, batch);
  for (std::uint32_t first = 0; first < build.maps; first += batch) {
    const std::uint32_t count = std::min(batch, build.maps - first);
    Stopwatch clock;
    source.get(first, count, z1, z2);
    result.capture_ms += clock.elapsed_ms();
    Stopwatch compress_clock;
    compressor.add(z1, z2, first, count, result);
    result.compress_ms += compress_clock.elapsed_ms();
    if (progress) progress(first + count, build.maps);
  }
  return result;
}

std::vector<KMeansResult> kmeans_analysis(const std::vector<float>& z1, const std::vector<float>& z2, std::uint32_t maps,
                                          std::size_t pixels, const std::vector<std::uint32_t>& ks, std::uint32_t seed,
                                          std::uint32_t max_iterations) {
  if (z1.size() != pixels * maps || z2.size() != z1.size()) throw Error("kmeans_analysis: depth arrays do not hold maps x pixels values");
  if (max_iterations == 0) throw Error("k-means: at least one iteration assigns the maps to clusters");
  // Depths lie in [0, 1] (a sphere exit may round a hair above 1): 2 stands for the empty pixels' +∞.
  const auto feature2 = [](float v) { return std::fmin(v, 2.0f); };
  std::vector<KMeansResult> results;
  for (const std::uint32_t k : ks) {
    if (k == 0 || k > maps) throw Error(fmt::format("k-means: k = {} must be between 1 and the map count {}", k, maps));
    std::vector<std::uint32_t> order(maps);
    std::iota(order.begin(), order.end(), 0u);
    std::mt19937 rng(seed);
    std::shuffle(order.begin(), order.end(), rng);
    std::vector<float> c1(std::size_t{k} * pixels), c2(c1.size());
    for (std::uint32_t j = 0; j < k; ++j)
      for (std::size_t p = 0; p < pixels; ++p) {
        c1[j * pixels + p] = z1[order[j] * pixels + p];
        c2[j * pixels + p] = feature2(z2[order[j] * pixels + p]);
      }
    std::vector<std::uint32_t> cluster(maps, UINT32_MAX);
    KMeansResult r;
    r.k = k;
    for (r.iterations = 0; r.iterations < max_iterations;) {
      ++r.iterations;
      std::vector<std::uint8_t> changed(maps, 0);
      parallel_for(maps, 4, [&](std::size_t m, std::size_t) {
        double best = INFINITY;
        std::uint32_t best_j = 0;
        for (std::uint32_t j = 0; j < k; ++j) {
          double d = 0;
          for (std::size_t p = 0; p < pixels && d < best; ++p) {
            const double a = z1[m * pixels + p] - c1[j * pixels + p], b = feature2(z2[m * pixels + p]) - c2[j * pixels + p];
            d += a * a + b * b;
          }
          if (d < best) {
            best = d;
            best_j = j;
          }
        }
        changed[m] = cluster[m] != best_j;
        cluster[m] = best_j;
      });
      if (std::none_of(changed.begin(), changed.end(), [](std::uint8_t v) { return v != 0; })) break;
      std::vector<double> s1(c1.size(), 0), s2(c1.size(), 0);
      std::vector<std::uint32_t> members(k, 0);
      for (std::uint32_t m = 0; m < maps; ++m) {
        ++members[cluster[m]];
        for (std::size_t p = 0; p < pixels; ++p) {
          s1[cluster[m] * pixels + p] += z1[m * pixels + p];
          s2[cluster[m] * pixels + p] += feature2(z2[m * pixels + p]);
        }
      }
      for (std::uint32_t j = 0; j < k; ++j)
        if (members[j])
          for (std::size_t p = 0; p < pixels; ++p) {
            c1[j * pixels + p] = static_cast<float>(s1[j * pixels + p] / members[j]);
            c2[j * pixels + p] = static_cast<float>(s2[j * pixels + p] / members[j]);
          }
    }
    // Mean maps: z2 = +∞ where every member is empty there.
    std::vector<std::uint8_t> all_empty(c1.size(), 1);
    for (std::uint32_t m = 0; m < maps; ++m)
      for (std::size_t p = 0; p < pixels; ++p)
        if (z2[m * pixels + p] != INFINITY) all_empty[cluster[m] * pixels + p] = 0;
    std::vector<float> m1(z1.size()), m2(z1.size());
    for (std::uint32_t m = 0; m < maps; ++m)
      for (std::size_t p = 0; p < pixels; ++p) {
        const std::size_t c = cluster[m] * pixels + p;
        m1[m * pixels + p] = c1[c];
        m2[m * pixels + p] = all_empty[c] ? INFINITY : c2[c];
      }
    const Segments s = compress_reference(m1, m2, pixels, maps);
    r.segments = s.size();
    r.plain_bytes = 256 + 4 * (pixels + 1) + 8 * s.size();
    r.samples = std::uint64_t{maps} * pixels;
    std::vector<std::uint64_t> wrong(worker_count(pixels, 64), 0);
    parallel_for(pixels, 64, [&](std::size_t p, std::size_t w) {
      std::size_t at = s.offsets[p];
      for (std::uint32_t m = 0; m < maps; ++m) {
        while (s.end[at] < m) ++at;
        wrong[w] += !lossless(segment_depth(s.lo[at], s.hi[at]), z1[m * pixels + p], z2[m * pixels + p]);
      }
    });
    for (std::uint64_t v : wrong) r.wrong_samples += v;
    results.push_back(r);
  }
  return results;
}

void require_wavelet_resolution(std::uint32_t resolution) {
  if (!std::has_single_bit(resolution))
    throw Error(fmt::format("the Haar-wavelet analysis needs a power-of-two resolution (--res), not {}", resolution));
}

WaveletResult wavelet_analysis(const Csm& csm) {
  const std::uint32_t m = csm.info.resolution;
  require_wavelet_resolution(m);
  const std::size_t pixels = std::size_t{m} * m;
  if (csm.pixels() != pixels) throw Error("wavelet_analysis: the CSM's pixel count does not match its resolution");
  WaveletResult result;
  for (std::size_t p = 0; p < pixels; ++p) result.layers = std::max(result.layers, csm.offsets[p + 1] - csm.offsets[p]);
  const std::uint32_t layer_images = 2 * result.layers;
  std::vector<std::uint64_t> zeros(worker_count(layer_images, 1), 0);
  parallel_for(layer_images, 1, [&](std::size_t image, std::size_t w) {
    const std::uint32_t layer = static_cast<std::uint32_t>(image / 2);
    const bool ends = image % 2 == 1;
    std::vector<float> v(pixels), scratch(m);
    for (std::size_t p = 0; p < pixels; ++p) {
      const std::uint32_t k = csm.offsets[p] + layer;
      if (k >= csm.offsets[p + 1]) v[p] = 0;
      else if (ends) v[p] = static_cast<float>(csm.end[k]);
      else v[p] = csm.depth[k] == INFINITY ? 2.0f : csm.depth[k];
    }
    // Full 1-D Haar transform of `count` values at stride `stride`: averages first, details after.
    const auto haar = [&](float* base, std::size_t stride) {
      for (std::uint32_t len = m; len > 1; len /= 2) {
        for (std::uint32_t i = 0; i < len / 2; ++i) {
          const float a = base[2 * i * stride], b = base[(2 * i + 1) * stride];
          scratch[i] = (a + b) * 0.5f;
          scratch[len / 2 + i] = (a - b) * 0.5f;
        }
        for (std::uint32_t i = 0; i < len; ++i) base[i * stride] = scratch[i];
      }
    };
    for (std::uint32_t y = 0; y < m; ++y) haar(v.data() + std::size_t{y} * m, 1);
    for (std::uint32_t x = 0; x < m; ++x) haar(v.data() + x, m);
    for (float c : v) zeros[w] += c == 0.0f;
  });
  result.coefficients = std::uint64_t{layer_images} * pixels;
  for (std::uint64_t z : zeros) result.zeros += z;
  return result;
}

}  // namespace splatcl::csm
