#include "splats/fit.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <numbers>

#include "primitives/launch.hpp"
#include "runtime/error.hpp"

namespace splatcl::splats {
namespace {

using primitives::detail::set_args;

// First growth capacity (accepted samples per splat) and the factor for each relaunch of the splats
// that outgrew it; the per-splat output (and, in the GPU shape, the per-splat scratch) of one launch
// stays under kScratchBudget bytes by batching splats.
constexpr std::uint32_t kFirstCapacity = 128;
constexpr std::uint32_t kCapacityGrowth = 8;
constexpr std::size_t kScratchBudget = std::size_t{16} << 20;
// CPU shape: items a worker takes from the shared counter at a time (few enough atomics, small tail).
constexpr std::uint32_t kCpuBlock = 16;

std::string build_options(const Runtime& runtime, const FitOptions& options) {
  std::string text = fmt::format("-DLITERAL_LAMBDA={} -DRETEST_VIOLATOR={} -DCLIP={} -DON_HULL_BIT={}u -DSIZE_AT_ACCEPTED={}",
                                 options.literal_lambda ? 1 : 0, options.retest_violator ? 1 : 0, options.clip ? 1 : 0, kOnHullBit,
                                 options.size_at_accepted ? 1 : 0);
  // The reference's std::sqrt and division are correctly rounded; ask the device for the same.
  return text + runtime.exact_divide_option();
}

}  // namespace

void set_rows(const std::vector<std::vector<std::uint32_t>>& sets, FitResult& result) {
  result.covered = Rows{};
  result.safe = Rows{};
  for (const auto& set : sets) {
    for (const std::uint32_t entry : set) {
      result.covered.items.push_back(entry & ~kOnHullBit);
      if (!(entry & kOnHullBit)) result.safe.items.push_back(entry);
    }
    result.covered.offsets.push_back(static_cast<std::uint32_t>(result.covered.items.size()));
    result.safe.offsets.push_back(static_cast<std::uint32_t>(result.safe.items.size()));
  }
}

std::uint32_t budget_growth_cap(std::size_t samples, std::uint32_t requested, std::size_t budget) {
  const std::size_t share = budget / std::max<std::size_t>(samples, 1);
  return static_cast<std::uint32_t>(std::min<std::size_t>(requested, std::max<std::size_t>(kMinBudgetCap, share)));
}

void validate(const FitOptions& options) {
  if (!(std::isfinite(options.eps) && options.eps > 0))
    throw Error(fmt::format("--eps must be a positive length, not {}", options.eps));
  if (options.max_covered < 4 || options.max_covered > kMaxCoveredLimit)
    throw Error(fmt::format("--max-covered must be in 4..{}, not {}", kMaxCoveredLimit, options.max_covered));
  if (options.color_tolerance < 0 || options.color_tolerance > 255)
    throw Error(fmt::format("--color-tol must be in 0..255, not {}", options.color_tolerance));
  if (!(options.crease_degrees > 0 && options.crease_degrees <= 180))
    throw Error(fmt::format("--crease-angle must be in (0, 180] degrees, not {}", options.crease_degrees));
}

float crease_cosine(float crease_degrees) {
  return crease_degrees >= 180.0f ? -2.0f : static_cast<float>(std::cos(static_cast<double>(crease_degrees) * std::numbers::pi / 180.0));
}

FitResult fit_splats(Runtime& runtime, const Samples& samples, const Neighborhoods& neighbors, const FitOptions& options,
                     const std::vector<Frame>* frames, FitTimings* timings, Profiler* profiler) {
  validate(options);
  const std::size_t n = samples.size();
  if (frames && frames->size() != n) throw Error("splat fit: frame count differs from the sample count");
  FitResult result;
  result.splats.resize(n);
  result.clips.resize(n);
  if (n == 0) return result;
  FitTimings local_timings;
  FitTimings& t = timings ? *timings : local_timings;
  const std::uint32_t k = neighbors.k;
  const std::string build = build_options(runtime, options);
  auto& queue = runtime.queue();
  try {
    Stopwatch transfer;
    const cl::Buffer positions = upload(runtime, samples.positions, "splat sample positions", CL_MEM_READ_ONLY);
    const cl::Buffer normals = upload(runtime, samples.normals, "splat sample normals", CL_MEM_READ_ONLY);
    const cl::Buffer colors = upload(runtime, samples.colors, "splat sample colours", CL_MEM_READ_ONLY);
    const cl::Buffer neighbor_buffer = upload(runtime, neighbors.indices, "splat neighbour lists", CL_MEM_READ_ONLY);
    const cl::Buffer kth = upload(runtime, neighbors.kth_distance, "splat neighbour distances", CL_MEM_READ_ONLY);
    cl::Buffer frame_buffer = runtime.buffer(CL_MEM_READ_WRITE, n * sizeof(Frame), "splat frames");
    t.transfer_ms += transfer.elapsed_ms();
    if (frames) {
      queue.enqueueWriteBuffer(frame_buffer, CL_TRUE, 0, n * sizeof(Frame), frames->data());
      result.frames = *frames;
    } else {
      cl::Kernel kernel = runtime.kernel("splat_fit.cl", "splat_frames", build);
      set_args(kernel, positions, normals, neighbor_buffer, k, kth, crease_cosine(options.crease_degrees), static_cast<cl_uint>(n),
               frame_buffer);
      t.frames_ms += event_ms(enqueue_1d(queue, kernel, n, 0, profiler, "splat frames"));
      result.frames.resize(n);
      queue.enqueueReadBuffer(frame_buffer, CL_TRUE, 0, n * sizeof(Frame), result.frames.data());
    }

    cl::Buffer splat_buffer = runtime.buffer(CL_MEM_READ_WRITE, n * sizeof(SplatShape), "splat shapes");
    cl::Buffer clip_buffer = runtime.buffer(CL_MEM_READ_WRITE, n * sizeof(Vec4), "splat clip lines");
    cl::Kernel grow = runtime.kernel("splat_fit.cl", "splat_grow", build);
    // CPU shape: a few workers pull blocks of consecutive items, each reusing its scratch; GPU
    // shape: one work-item and one scratch per item.
    const bool cpu_shape = runtime.resolve(options.shape) == Shape::Cpu;
    std::vector<std::vector<std::uint32_t>> sets(n);
    std::vector<std::uint32_t> pending(n);
    for (std::size_t i = 0; i < n; ++i) pending[i] = static_cast<std::uint32_t>(i);
    std::uint32_t capacity = static_cast<std::uint32_t>(std::min<std::size_t>(kFirstCapacity, n));
    cl::Buffer items, q_slots, seen_slots, ring_slots, aux_slots, hash_slots, counts;
    cl::Buffer next_block = runtime.buffer(CL_MEM_READ_WRITE, sizeof(std::uint32_t), "splat growth block counter");
    for (bool first = true; !pending.empty(); first = false) {
      if (!first) ++t.relaunches;
      // Every seen sample is the start, one of its k neighbours, or a neighbour of an accepted one.
      const std::size_t seen_capacity = std::min<std::size_t>(n, std::size_t{k} * capacity + 1);
      const std::size_t hash_size = std::bit_ceil(2 * seen_capacity);
      const std::size_t per_worker = seen_capacity * (2 * sizeof(std::uint32_t) + sizeof(cl_ulong)) + hash_size * sizeof(std::uint32_t);
      const std::size_t per_item = (capacity + 1) * sizeof(std::uint32_t);
      const std::size_t batch = std::clamp<std::size_t>(kScratchBudget / (per_item + (cpu_shape ? 0 : per_worker)), 1, pending.size());
      const std::size_t workers = cpu_shape ? std::min(batch, runtime.cpu_chunks()) : batch;
      items = runtime.buffer(CL_MEM_READ_ONLY, batch * sizeof(std::uint32_t), "splat growth items");
      q_slots = runtime.buffer(CL_MEM_READ_WRITE, batch * capacity * sizeof(std::uint32_t), "splat growth sets");
      counts = runtime.buffer(CL_MEM_READ_WRITE, batch * sizeof(std::uint32_t), "splat growth counts");
      seen_slots = runtime.buffer(CL_MEM_READ_WRITE, workers * seen_capacity * sizeof(std::uint32_t), "splat growth seen lists");
      ring_slots = runtime.buffer(CL_MEM_READ_WRITE, workers * seen_capacity * sizeof(cl_ulong), "splat growth ring keys");
      aux_slots = runtime.buffer(CL_MEM_READ_WRITE, workers * seen_capacity * sizeof(std::uint32_t), "splat growth hull scratch");
      hash_slots = runtime.buffer(CL_MEM_READ_WRITE, workers * hash_size * sizeof(std::uint32_t), "splat growth seen sets");
      // Zeroed once: every splat leaves its worker's set empty for the next one.
      queue.enqueueFillBuffer(hash_slots, std::uint32_t{0}, 0, workers * hash_size * sizeof(std::uint32_t));
      std::vector<std::uint32_t> overflow, batch_counts(batch), batch_sets(batch * capacity);
      for (std::size_t begin = 0; begin < pending.size(); begin += batch) {
        const std::size_t count = std::min(batch, pending.size() - begin);
        queue.enqueueWriteBuffer(items, CL_FALSE, 0, count * sizeof(std::uint32_t), pending.data() + begin);
        queue.enqueueFillBuffer(next_block, std::uint32_t{0}, 0, sizeof(std::uint32_t));
        set_args(grow, positions, normals, colors, neighbor_buffer, k, frame_buffer, crease_cosine(options.crease_degrees), options.eps,
                 static_cast<cl_int>(options.color_tolerance), static_cast<cl_uint>(options.max_covered), items, static_cast<cl_uint>(count), capacity,
                 static_cast<cl_uint>(seen_capacity), static_cast<cl_uint>(hash_size - 1),
                 static_cast<cl_uint>(cpu_shape ? kCpuBlock : 0), next_block, q_slots, seen_slots, ring_slots,
                 aux_slots, hash_slots, counts, splat_buffer, clip_buffer);
        const std::size_t launched = cpu_shape ? std::min(workers, count) : count;
        t.grow_ms += event_ms(enqueue_1d(queue, grow, launched, cpu_shape ? 1 : 8, profiler, "splat grow"));
        Stopwatch read;
        queue.enqueueReadBuffer(counts, CL_TRUE, 0, count * sizeof(std::uint32_t), batch_counts.data());
        queue.enqueueReadBuffer(q_slots, CL_TRUE, 0, count * capacity * sizeof(std::uint32_t), batch_sets.data());
        t.transfer_ms += read.elapsed_ms();
        for (std::size_t s = 0; s < count; ++s) {
          const std::uint32_t i = pending[begin + s];
          if (batch_counts[s] > capacity) {
            overflow.push_back(i);
            continue;
          }
          const auto* first_entry = batch_sets.data() + s * capacity;
          sets[i].assign(first_entry, first_entry + batch_counts[s]);
        }
      }
      pending = std::move(overflow);
      capacity = static_cast<std::uint32_t>(std::min<std::size_t>({std::size_t{capacity} * kCapacityGrowth, n, options.max_covered}));
    }
    Stopwatch read;
    queue.enqueueReadBuffer(splat_buffer, CL_TRUE, 0, n * sizeof(SplatShape), result.splats.data());
    queue.enqueueReadBuffer(clip_buffer, CL_TRUE, 0, n * sizeof(Vec4), result.clips.data());
    t.transfer_ms += read.elapsed_ms();
    set_rows(sets, result);
  } catch (const Error&) {
    throw;
  } catch (...) {
    rethrow_as_error(fmt::format("splat fit of {} samples", n));
  }
  return result;
}

}  // namespace splatcl::splats
