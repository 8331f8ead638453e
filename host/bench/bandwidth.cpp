#include "bench/bandwidth.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <memory>
#include <thread>
#include <vector>

#include "runtime/error.hpp"

namespace splatcl::bench {
namespace {

unsigned host_threads() { return std::max(1u, std::thread::hardware_concurrency()); }

// Runs body(begin, end) on one contiguous chunk of [0, n) per thread, all threads in parallel.
void parallel_chunks(std::size_t n, unsigned threads, const std::function<void(std::size_t, std::size_t)>& body) {
  std::vector<std::thread> workers;
  workers.reserve(threads);
  for (unsigned t = 0; t < threads; ++t)
    workers.emplace_back(body, n * t / threads, n * (t + 1) / threads);
  for (auto& worker : workers) worker.join();
}

// Zero, read where the compiler cannot see it: the copy loop below stays a loop of ordinary stores
// instead of being recognised as memcpy.
volatile std::uint64_t runtime_zero = 0;

void copy_loop(const std::uint64_t* __restrict src, std::uint64_t* __restrict dst, std::size_t n, std::uint64_t mask) {
  for (std::size_t i = 0; i < n; ++i) dst[i] = src[i] ^ mask;
}

void measure_host_copies(Session& session, std::size_t array_bytes) {
  const std::size_t n = array_bytes / sizeof(std::uint64_t);
  const unsigned threads = host_threads();
  std::unique_ptr<std::uint64_t[]> src(new std::uint64_t[n]);
  std::unique_ptr<std::uint64_t[]> dst(new std::uint64_t[n]);
  // First touch by the threads that copy, so pages are mapped before timing.
  parallel_chunks(n, threads, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      src[i] = i * 0x9E3779B97F4A7C15ull;
      dst[i] = 0;
    }
  });
  Case c{kCaseStreamCopy, kImplHostCopyLoop, false, 2 * n * sizeof(std::uint64_t), "bytes",
         Json{{"threads", threads}}};
  const std::uint64_t mask = runtime_zero;
  session.measure(c, {}, [&] {
    parallel_chunks(n, threads, [&](std::size_t begin, std::size_t end) { copy_loop(&src[begin], &dst[begin], end - begin, mask); });
  });
  if (std::memcmp(src.get(), dst.get(), n * sizeof(std::uint64_t)) != 0)
    throw Error("bench stream-copy: host copy loop output differs from its input");

  std::fill_n(dst.get(), n, std::uint64_t{0});
  c.impl = kImplHostMemcpy;
  session.measure(c, {}, [&] {
    parallel_chunks(n, threads, [&](std::size_t begin, std::size_t end) {
      std::memcpy(&dst[begin], &src[begin], (end - begin) * sizeof(std::uint64_t));
    });
  });
  if (std::memcmp(src.get(), dst.get(), n * sizeof(std::uint64_t)) != 0)
    throw Error("bench stream-copy: host memcpy output differs from its input");
}

void measure_device_copy(Session& session, std::size_t array_bytes) {
  Runtime& runtime = session.runtime();
  // A simulator interprets every load and store (a 32 MiB copy took minutes on Oclgrind): a token
  // array there, only to check the kernel, as measure_peak_fma does.
  if (runtime.info().type == "simulator") array_bytes = std::min(array_bytes, kSimulatorStreamArrayBytes);
  const std::size_t vectors = array_bytes / sizeof(cl_uint4);
  const std::size_t bytes = vectors * sizeof(cl_uint4);
  cl::Buffer src = runtime.buffer(CL_MEM_READ_ONLY, bytes, "stream-copy source");
  cl::Buffer dst = runtime.buffer(CL_MEM_WRITE_ONLY, bytes, "stream-copy destination");
  const cl_uint4 pattern = {{0x01234567u, 0x89ABCDEFu, 0xDEADBEEFu, 0x0F1E2D3Cu}};
  try {
    runtime.queue().enqueueFillBuffer(src, pattern, 0, bytes);
    runtime.queue().enqueueFillBuffer(dst, cl_uint{0}, 0, bytes);
    runtime.queue().finish();
  } catch (...) {
    rethrow_as_error("filling the stream-copy buffers");
  }
  cl::Kernel kernel = runtime.kernel("bench.cl", "copy_uint4");
  kernel.setArg(0, src);
  kernel.setArg(1, dst);
  Profiler profiler;
  const Case c{kCaseStreamCopy, kImplOpenCL, true, 2 * bytes, "bytes"};
  session.measure(
      c, {},
      [&] {
        enqueue_1d(runtime.queue(), kernel, vectors, 0, &profiler, "copy_uint4");
        runtime.queue().finish();
      },
      &profiler);
  std::vector<cl_uint4> copied(vectors);
  try {
    runtime.queue().enqueueReadBuffer(dst, CL_TRUE, 0, bytes, copied.data());
  } catch (...) {
    rethrow_as_error("reading back the stream-copy destination");
  }
  const bool intact = std::all_of(copied.begin(), copied.end(), [&](const cl_uint4& v) {
    return std::equal(std::begin(v.s), std::end(v.s), std::begin(pattern.s));
  });
  if (!intact) throw Error("bench stream-copy: OpenCL copy output differs from its input");
}

// The host's value of fma_peak's output for work-item i (kernels/bench.cl): fma is correctly rounded
// on both sides, and the sums run in the kernel's order.
float fma_peak_expected(std::size_t i, unsigned steps, float a, float b) {
  float x[8], y[8];
  const float lanes[8] = {0.0f, 0.1f, 0.2f, 0.3f, 0.4f, 0.5f, 0.6f, 0.7f};
  for (int k = 0; k < 8; ++k) {
    x[k] = static_cast<float>(i & 1023u) * 1e-4f + lanes[k];
    y[k] = x[k] + 0.05f;
  }
  for (unsigned s = 0; s < steps; ++s)
    for (int k = 0; k < 8; ++k) {
      x[k] = std::fma(x[k], a, b);
      y[k] = std::fma(y[k], a, b);
    }
  float sum[8], half[4];
  for (int k = 0; k < 8; ++k) sum[k] = x[k] + y[k];
  for (int k = 0; k < 4; ++k) half[k] = sum[k] + sum[k + 4];
  return half[0] + half[1] + half[2] + half[3];
}

void measure_peak_fma(Session& session) {
  Runtime& runtime = session.runtime();
  // A simulator (Oclgrind) interprets every operation: a token problem there, only to check the kernel.
  const bool simulator = runtime.info().type == "simulator";
  const bool small = session.options().quick || simulator;
  const std::size_t items = simulator ? std::size_t{1} << 10 : small ? std::size_t{1} << 16 : std::size_t{1} << 20;
  const cl_uint steps = simulator ? 16u : small ? 256u : 512u;
  const float a = 0.9999f, b = 1e-4f;
  cl::Buffer out = runtime.buffer(CL_MEM_WRITE_ONLY, items * sizeof(float), "peak-fma output");
  cl::Kernel kernel = runtime.kernel("bench.cl", "fma_peak");
  set_args(kernel, out, steps, a, b);
  Profiler profiler;
  const Case c{kCasePeakFma, kImplOpenCL, true, std::uint64_t{64} * steps * items, "flop"};
  session.measure(
      c, {},
      [&] {
        enqueue_1d(runtime.queue(), kernel, items, 0, &profiler, "fma_peak");
        finish(runtime);
      },
      &profiler);
  const auto result = download<float>(runtime, out, items, "peak-fma output");
  for (const std::size_t i : {std::size_t{0}, std::size_t{1}, std::size_t{777}, items - 1})
    if (result[i] != fma_peak_expected(i, steps, a, b))
      throw Error("bench peak-fma: OpenCL output differs from the host's FMA chains at work-item " + std::to_string(i));
}

}  // namespace

void measure_ceilings(Session& session, std::size_t array_bytes) {
  if (!session.options().measure_bandwidth) return;
  measure_host_copies(session, array_bytes);
  measure_device_copy(session, array_bytes);
  measure_peak_fma(session);
}

}  // namespace splatcl::bench
