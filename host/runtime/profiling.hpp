#pragma once
// Event profiling used by every driver and benchmark: device time per kernel (from the queue's
// profiling events) and host wall time.
#include <chrono>
#include <string>
#include <vector>

#include "runtime/opencl.hpp"

namespace splatcl {

// Device execution time of a completed event (END - START), in milliseconds.
double event_ms(const cl::Event& event);

// Collects labelled kernel events; drivers add to it when a caller passes one.
class Profiler {
 public:
  struct Entry {
    std::string label;
    cl::Event event;
  };
  void add(std::string label, const cl::Event& event) { entries_.push_back({std::move(label), event}); }
  void clear() { entries_.clear(); }
  const std::vector<Entry>& entries() const { return entries_; }
  // Sum of device time over all entries (waits for them).
  double total_device_ms() const;
  // Device time per distinct label, in first-seen order.
  std::vector<std::pair<std::string, double>> per_label_ms() const;

 private:
  std::vector<Entry> entries_;
};

// Host wall clock.
class Stopwatch {
 public:
  Stopwatch() : start_(std::chrono::steady_clock::now()) {}
  void restart() { start_ = std::chrono::steady_clock::now(); }
  double elapsed_ms() const {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start_).count();
  }

 private:
  std::chrono::steady_clock::time_point start_;
};

// Test hook: a launch of the kernel named by this environment variable (through enqueue_1d or
// enqueue_2d) enqueues a marker instead, so a test can check that a result check catches a kernel
// that writes nothing.
inline constexpr const char* kSkipKernelVariable = "SPLATCL_TEST_SKIP_KERNEL";

// Enqueues a kernel over a 1-D range (global rounded up to a multiple of local when local > 0) and
// records its event in `profiler` under `label` when a profiler is given.
cl::Event enqueue_1d(cl::CommandQueue& queue, cl::Kernel& kernel, std::size_t global, std::size_t local,
                     Profiler* profiler, const char* label);

// Enqueues a kernel over width x height work-items in group_width x group_height groups (the range is
// rounded up to whole groups; kernels check bounds); recorded in `profiler` like enqueue_1d.
cl::Event enqueue_2d(cl::CommandQueue& queue, cl::Kernel& kernel, std::size_t width, std::size_t height,
                     std::size_t group_width, std::size_t group_height, Profiler* profiler, const char* label);

// Sets every argument of `kernel` in order.
template <class... Args>
void set_args(cl::Kernel& kernel, const Args&... args) {
  cl_uint index = 0;
  (kernel.setArg(index++, args), ...);
}

// Rounds n up to a multiple of m (m > 0).
constexpr std::size_t round_up(std::size_t n, std::size_t m) { return (n + m - 1) / m * m; }
constexpr std::size_t div_up(std::size_t n, std::size_t m) { return (n + m - 1) / m; }

}  // namespace splatcl
