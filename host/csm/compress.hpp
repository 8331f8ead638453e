#pragma once
// Per-pixel greedy segmentation (Talpe §5.2): for every pixel, the maps in
// sequence order are cut into maximal runs with max z1 < min z2; each run stores its interval
// [lo = max z1, hi = min z2] and its inclusive end index. The stored depth is segment_depth(lo, hi).
//
// StreamingCompressor runs kernels/csm_compress.cl batch by batch, so memory holds one batch of
// maps plus the segments, never all N maps; compress_reference is the batch algorithm on all maps.
// Both produce identical segments (max, min and comparisons only: no rounding).
#include <cstdint>
#include <vector>

#include "core/device_vector.hpp"
#include "runtime/profiling.hpp"
#include "runtime/runtime.hpp"

namespace splatcl::csm {

// Pixel p's segments are [offsets[p], offsets[p + 1]).
struct Segments {
  std::uint32_t maps = 0;
  std::vector<std::uint32_t> offsets{0};
  std::vector<float> lo, hi;
  std::vector<std::uint32_t> end;
  std::size_t pixels() const { return offsets.size() - 1; }
  std::size_t size() const { return end.size(); }
};

// The thesis's midpoint in float, kept strictly below hi when lo and hi are adjacent floats
// (Talpe §5.2); +inf for a run of empty pixels; lo itself when lo == hi.
float segment_depth(float lo, float hi);

// Whether stored depth g gives every depth test the same answer as the pixel's own (z1, z2):
// z1 <= g < z2, or g == z1 when z1 == z2 (a single-surface pixel kept exactly), or g == +inf for
// an empty pixel (z1 = 1, z2 = +inf).
bool lossless(float g, float z1, float z2);

// Reference: z1, z2 laid out [map][pixel] for all `maps` maps in sequence order.
Segments compress_reference(const std::vector<float>& z1, const std::vector<float>& z2, std::size_t pixels,
                            std::uint32_t maps);

class StreamingCompressor {
 public:
  StreamingCompressor(Runtime& runtime, std::size_t pixels, std::uint32_t maps);
  // Folds the next `count` maps (device buffers laid out [map][pixel]) into the open runs.
  void add(const cl::Buffer& z1, const cl::Buffer& z2, std::uint32_t count, Profiler* profiler = nullptr);
  std::uint32_t maps_done() const { return done_; }
  // Bytes of the segments closed so far, with their per-pixel offsets.
  std::uint64_t held_bytes() const;
  // After all maps were added: the segments, pixel by pixel.
  Segments finish();

 private:
  // The segments a run of batches closed, pixel by pixel; each holds a full offsets array, so they
  // are folded into one (merge_chunks) once those arrays pass a quarter of the segments: at 1024² and 16,384
  // maps (8 maps a batch) the 2,048 arrays alone took 8 GiB.
  struct Chunk {
    std::vector<std::uint32_t> offsets;
    std::vector<float> lo, hi;
    std::vector<std::uint32_t> end;
  };
  void merge_chunks();
  Runtime& runtime_;
  std::size_t pixels_;
  std::uint32_t maps_, done_ = 0;
  cl::Buffer state_lo_, state_hi_, counts_, offsets_;
  DeviceVector<float> out_lo_, out_hi_;
  DeviceVector<cl_uint> out_end_;
  cl::Kernel count_, emit_;
  std::vector<Chunk> chunks_;
};

}  // namespace splatcl::csm
