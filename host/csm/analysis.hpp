#pragma once
// The compression thesis's alternatives to per-pixel compression (Talpe §5.4–§5.7), for
// comparison with it:
// - per-map: each map segmented on its own along a 2-D pixel curve; n = the pixel's curve index;
// - 3-D Hilbert: the map sequence cut into blocks of M maps, each an M × M × M cube (x, y, map in
//   block) segmented along a 3-D Hilbert curve; n = the Hilbert index;
// - 4-D Hilbert: one list over (i / W, i mod W, x, y), i = sequence index, W = the grid's φ cells
//   (our reading of Talpe §5.6.2); n = the Hilbert index.
// All use the per-pixel merge rule (max z1 < min z2, midpoint), so all are exactly lossless; each
// build decodes every (map, pixel) through the mode's own lookup (index from coordinates, binary
// search) and counts the samples whose test would change. Sizes use the plain accounting: 256 B
// header, 4 B per list offset, 8 B per segment.
// Offline analyses (Talpe §5.5, §5.7): k-means clustering of maps before per-pixel compression
// (lossy; errors and correction cost counted) and the Haar-wavelet layer re-layout (zero count).
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "csm/build.hpp"

namespace splatcl::csm {

enum class CompressionMode : std::uint32_t { PerPixel = 0, PerMap = 1, Hilbert3d = 2, Hilbert4d = 3 };
enum class PixelCurve : std::uint32_t { Hilbert = 0, ZigzagH = 1, ZigzagV = 2 };
const char* to_string(CompressionMode value);
const char* to_string(PixelCurve value);
CompressionMode parse_compression_mode(const std::string& text);
PixelCurve parse_pixel_curve(const std::string& text);

// n-dimensional Hilbert curve (Skilling 2004) on a cube of side 2^bits: index ↔ coordinates.
// dims ≤ 4, dims · bits ≤ 64.
void hilbert_point(std::uint64_t index, std::uint32_t dims, std::uint32_t bits, std::uint32_t* coords);
std::uint64_t hilbert_index(const std::uint32_t* coords, std::uint32_t dims, std::uint32_t bits);

// Position of pixel (x, y) along the per-map curve on an M × M map (Hilbert needs M a power of 2).
std::uint32_t pixel_curve_index(PixelCurve curve, std::uint32_t resolution, std::uint32_t x, std::uint32_t y);

// Greedy segmentation of one scan: samples (z1, z2) at increasing positions; segments appended as
// (lo, hi, inclusive end position). Shared by every mode.
class ScanSegmenter {
 public:
  explicit ScanSegmenter(Segments& out) : out_(out) {}
  void add(float z1, float z2, std::uint64_t position);
  void close();  // ends the open run (call once per list)

 private:
  Segments& out_;
  bool open_ = false;
  float lo_ = 0, hi_ = 0;
  std::uint64_t last_ = 0;
};

struct ModeOptions {
  CompressionMode mode = CompressionMode::PerMap;
  PixelCurve pixel_curve = PixelCurve::Hilbert;  // per-map only
  std::uint64_t max_memory_bytes = std::uint64_t{6} << 30;  // 4-D Hilbert keeps every map in memory
};

struct ModeResult {
  std::uint64_t lists = 0, segments = 0, samples = 0, violations = 0;
  std::uint64_t plain_bytes() const { return 256 + 4 * (lists + 1) + 8 * segments; }
  double capture_ms = 0, compress_ms = 0;
};

// Captures the maps of `build` (on `runtime`, or the native reference when null) and compresses
// them in `mode` (not PerPixel: build_csm does that), checking every sample. Throws Error for
// settings the mode cannot take (Hilbert curves need powers of two; 4-D above the memory limit).
ModeResult compress_in_mode(const Mesh& mesh, const BuildOptions& build, const ModeOptions& options, Runtime* runtime,
                            const BuildProgress& progress = {});
// The same on depths already in memory, laid out [map][pixel] in sequence order (tests).
ModeResult compress_in_mode(const std::vector<float>& z1, const std::vector<float>& z2, std::uint32_t maps,
                            std::uint32_t resolution, std::uint32_t grid_cols, const ModeOptions& options);

// k-means (Lloyd) over maps, each a point of 2·M² values (z1, and z2 with the empty pixels' +∞
// taken as 2), Euclidean distance; k maps picked by a seeded shuffle start it. Every map is then
// replaced by its cluster's mean map (z2 = +∞ where every member is empty), the sequence is
// compressed per pixel, and each (map, pixel) is checked against its own (z1, z2).
struct KMeansResult {
  std::uint32_t k = 0, iterations = 0;
  std::uint64_t segments = 0, plain_bytes = 0, wrong_samples = 0, samples = 0;
  // Lossless again: every wrong sample stored beside the segments as (f32 depth, u32 position).
  std::uint64_t corrected_bytes() const { return plain_bytes + 8 * wrong_samples; }
};
std::vector<KMeansResult> kmeans_analysis(const std::vector<float>& z1, const std::vector<float>& z2, std::uint32_t maps,
                                          std::size_t pixels, const std::vector<std::uint32_t>& ks, std::uint32_t seed,
                                          std::uint32_t max_iterations = 20);

// Haar-wavelet re-layout of per-pixel segments: L = the longest list; layer l holds every pixel's
// l-th stored depth (+∞ as 2, missing entries 0) and a second set its l-th end index; each layer
// gets a standard 2-D Haar transform (rows, then columns; M a power of two) and the exactly zero
// coefficients are counted. Estimated size = 2·L·M²·4 B × (1 − zero fraction) (Talpe §5.7).
struct WaveletResult {
  std::uint32_t layers = 0;
  std::uint64_t coefficients = 0, zeros = 0;
  std::uint64_t transformed_bytes() const { return 4 * coefficients; }
  double estimated_bytes() const {
    return coefficients ? static_cast<double>(transformed_bytes()) * (1.0 - static_cast<double>(zeros) / static_cast<double>(coefficients)) : 0;
  }
};
WaveletResult wavelet_analysis(const Csm& csm);
// Throws Error unless wavelet_analysis can take this map resolution (a power of two): a command
// checks it before it captures anything.
void require_wavelet_resolution(std::uint32_t resolution);

// Captures all maps of `build` into memory ([map][pixel]); throws Error above `max_bytes`.
void capture_all_maps(const Mesh& mesh, const BuildOptions& build, Runtime* runtime, std::vector<float>& z1,
                      std::vector<float>& z2, std::uint64_t max_bytes, const BuildProgress& progress = {});

}  // namespace splatcl::csm
