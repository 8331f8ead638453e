#include "csm/compress.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "primitives/launch.hpp"
#include "runtime/error.hpp"
#include "core/parallel.hpp"

namespace splatcl::csm {

using primitives::detail::set_args;

float segment_depth(float lo, float hi) {
  if (hi == INFINITY) return INFINITY;  // a run of empty pixels: always lit
  const float g = 0.5f * (lo + hi);
  return g < hi ? g : lo;
}

bool lossless(float g, float z1, float z2) {
  if (z2 == INFINITY) return g == INFINITY;
  if (z1 == z2) return g == z1;
  return z1 <= g && g < z2;
}

Segments compress_reference(const std::vector<float>& z1, const std::vector<float>& z2, std::size_t pixels, std::uint32_t maps) {
  if (z1.size() != pixels * maps || z2.size() != pixels * maps) throw Error("compress_reference: depth arrays do not hold maps x pixels values");
  std::vector<Segments> per_pixel(pixels);
  parallel_for(pixels, 256, [&](std::size_t p, std::size_t) {
    Segments& s = per_pixel[p];
    std::uint32_t k = 0;
    while (k < maps) {
      float lo = z1[k * pixels + p], hi = z2[k * pixels + p];
      std::uint32_t j = k + 1;
      for (; j < maps; ++j) {
        const float nlo = std::fmax(lo, z1[j * pixels + p]), nhi = std::fmin(hi, z2[j * pixels + p]);
        if (!(nlo < nhi)) break;
        lo = nlo;
        hi = nhi;
      }
      s.lo.push_back(lo);
      s.hi.push_back(hi);
      s.end.push_back(j - 1);
      k = j;
    }
  });
  Segments out;
  out.maps = maps;
  out.offsets.resize(pixels + 1, 0);
  for (std::size_t p = 0; p < pixels; ++p) out.offsets[p + 1] = out.offsets[p] + static_cast<std::uint32_t>(per_pixel[p].size());
  for (const Segments& s : per_pixel) {
    out.lo.insert(out.lo.end(), s.lo.begin(), s.lo.end());
    out.hi.insert(out.hi.end(), s.hi.begin(), s.hi.end());
    out.end.insert(out.end.end(), s.end.begin(), s.end.end());
  }
  return out;
}

StreamingCompressor::StreamingCompressor(Runtime& runtime, std::size_t pixels, std::uint32_t maps)
    : runtime_(runtime),
      pixels_(pixels),
      maps_(maps),
      out_lo_(runtime, "CSM segments"),
      out_hi_(runtime, "CSM segments"),
      out_end_(runtime, "CSM segments") {
  if (pixels == 0 || maps == 0) throw Error("CSM compression needs at least one pixel and one map");
  state_lo_ = runtime.buffer(CL_MEM_READ_WRITE, pixels * sizeof(float), "CSM open runs");
  state_hi_ = runtime.buffer(CL_MEM_READ_WRITE, pixels * sizeof(float), "CSM open runs");
  counts_ = runtime.buffer(CL_MEM_READ_WRITE, pixels * sizeof(cl_uint), "CSM segment counts");
  offsets_ = runtime.buffer(CL_MEM_READ_ONLY, pixels * sizeof(cl_uint), "CSM segment offsets");
  auto& queue = runtime.queue();
  queue.enqueueFillBuffer(state_lo_, -INFINITY, 0, pixels * sizeof(float));
  queue.enqueueFillBuffer(state_hi_, INFINITY, 0, pixels * sizeof(float));
  count_ = runtime.kernel("csm_compress.cl", "csm_segment_count");
  emit_ = runtime.kernel("csm_compress.cl", "csm_segment_emit");
}

void StreamingCompressor::add(const cl::Buffer& z1, const cl::Buffer& z2, std::uint32_t count, Profiler* profiler) {
  if (count == 0) return;
  if (done_ + count > maps_) throw Error("CSM compression was given more maps than announced");
  require_bytes(z1, count * pixels_ * sizeof(float), "CSM compression z1");
  require_bytes(z2, count * pixels_ * sizeof(float), "CSM compression z2");
  auto& queue = runtime_.queue();
  const cl_uint close = done_ + count == maps_ ? 1 : 0;
  const auto pixels = static_cast<cl_uint>(pixels_);
  set_args(count_, z1, z2, pixels, static_cast<cl_uint>(count), static_cast<cl_uint>(done_), close, state_lo_, state_hi_, counts_);
  enqueue_1d(queue, count_, pixels_, 0, profiler, "csm segment count");
  Chunk chunk;
  chunk.offsets.resize(pixels_ + 1);
  queue.enqueueReadBuffer(counts_, CL_TRUE, 0, pixels_ * sizeof(cl_uint), chunk.offsets.data() + 1);
  chunk.offsets[0] = 0;
  std::uint64_t total = 0;
  for (std::size_t p = 1; p <= pixels_; ++p) {
    total += chunk.offsets[p];
    if (total > UINT32_MAX) throw Error("CSM compression: more than 2^32 segments in one batch");
    chunk.offsets[p] = static_cast<std::uint32_t>(total);
  }
  // With no run closing the emit pass still advances the open runs; it then writes no segment.
  const std::size_t slots = std::max<std::uint64_t>(total, 1);
  queue.enqueueWriteBuffer(offsets_, CL_TRUE, 0, pixels_ * sizeof(cl_uint), chunk.offsets.data());
  out_lo_.resize(slots);
  out_hi_.resize(slots);
  out_end_.resize(slots);
  set_args(emit_, z1, z2, pixels, static_cast<cl_uint>(count), static_cast<cl_uint>(done_), close, state_lo_, state_hi_,
           offsets_, out_lo_.buffer(), out_hi_.buffer(), out_end_.buffer());
  enqueue_1d(queue, emit_, pixels_, 0, profiler, "csm segment emit");
  chunk.lo.resize(total);
  chunk.hi.resize(total);
  chunk.end.resize(total);
  if (total > 0) {
    queue.enqueueReadBuffer(out_lo_.buffer(), CL_FALSE, 0, total * sizeof(float), chunk.lo.data());
    queue.enqueueReadBuffer(out_hi_.buffer(), CL_FALSE, 0, total * sizeof(float), chunk.hi.data());
    queue.enqueueReadBuffer(out_end_.buffer(), CL_TRUE, 0, total * sizeof(cl_uint), chunk.end.data());
  }
  done_ += count;
  chunks_.push_back(std::move(chunk));
  // Folded once the offsets arrays pass a quarter of the segments' bytes (and 8 of them are held):
  // each fold copies what is held, and the next comes only when a quarter as many bytes of offsets
  // have come again, so the copying stays within 4 times the batches' offsets.
  const std::uint64_t offsets_bytes = chunks_.size() * (pixels_ + 1) * sizeof(std::uint32_t);
  if (chunks_.size() >= 8 && 4 * offsets_bytes > held_bytes() - offsets_bytes) merge_chunks();
}

std::uint64_t StreamingCompressor::held_bytes() const {
  std::uint64_t bytes = 0;
  for (const Chunk& c : chunks_) bytes += c.offsets.size() * sizeof(std::uint32_t) + c.end.size() * (2 * sizeof(float) + sizeof(std::uint32_t));
  return bytes;
}

void StreamingCompressor::merge_chunks() {
  if (chunks_.size() < 2) return;
  Chunk out;
  out.offsets.assign(pixels_ + 1, 0);
  for (std::size_t p = 0; p < pixels_; ++p) {
    std::uint64_t n = out.offsets[p];
    for (const Chunk& c : chunks_) n += c.offsets[p + 1] - c.offsets[p];
    if (n > UINT32_MAX) throw Error("CSM compression: more than 2^32 segments");
    out.offsets[p + 1] = static_cast<std::uint32_t>(n);
  }
  const std::size_t total = out.offsets[pixels_];
  out.lo.resize(total);
  out.hi.resize(total);
  out.end.resize(total);
  parallel_for(pixels_, 512, [&](std::size_t p, std::size_t) {
    std::size_t at = out.offsets[p];
    for (const Chunk& c : chunks_)
      for (std::uint32_t k = c.offsets[p]; k < c.offsets[p + 1]; ++k, ++at) {
        out.lo[at] = c.lo[k];
        out.hi[at] = c.hi[k];
        out.end[at] = c.end[k];
      }
  });
  chunks_.clear();
  chunks_.push_back(std::move(out));
}

Segments StreamingCompressor::finish() {
  if (done_ != maps_) throw Error("CSM compression finished after " + std::to_string(done_) + " of " + std::to_string(maps_) + " maps");
  merge_chunks();
  Segments out;
  out.maps = maps_;
  if (chunks_.empty()) return out;
  Chunk& all = chunks_.front();
  out.offsets = std::move(all.offsets);
  out.lo = std::move(all.lo);
  out.hi = std::move(all.hi);
  out.end = std::move(all.end);
  chunks_.clear();
  return out;
}

}  // namespace splatcl::csm
