#include "runtime/profiling.hpp"

#include <algorithm>

#include "runtime/runtime.hpp"

namespace splatcl {

double event_ms(const cl::Event& event) {
  event.wait();
  const auto start = event.getProfilingInfo<CL_PROFILING_COMMAND_START>();
  const auto end = event.getProfilingInfo<CL_PROFILING_COMMAND_END>();
  return static_cast<double>(end - start) * 1e-6;
}

double Profiler::total_device_ms() const {
  double total = 0;
  for (const auto& e : entries_) total += event_ms(e.event);
  return total;
}

std::vector<std::pair<std::string, double>> Profiler::per_label_ms() const {
  std::vector<std::pair<std::string, double>> result;
  for (const auto& e : entries_) {
    auto it = std::find_if(result.begin(), result.end(), [&](const auto& r) { return r.first == e.label; });
    if (it == result.end()) {
      result.emplace_back(e.label, event_ms(e.event));
    } else {
      it->second += event_ms(e.event);
    }
  }
  return result;
}

cl::Event enqueue_1d(cl::CommandQueue& queue, cl::Kernel& kernel, std::size_t global, std::size_t local,
                     Profiler* profiler, const char* label) {
  cl::Event event;
  if (global == 0) return event;
  try {
    if (local > 0) {
      queue.enqueueNDRangeKernel(kernel, cl::NullRange, cl::NDRange(round_up(global, local)), cl::NDRange(local), nullptr, &event);
    } else {
      queue.enqueueNDRangeKernel(kernel, cl::NullRange, cl::NDRange(global), cl::NullRange, nullptr, &event);
    }
  } catch (...) {
    rethrow_as_error(std::string("launching kernel ") + label);
  }
  if (profiler) profiler->add(label, event);
  return event;
}

cl::Event enqueue_2d(cl::CommandQueue& queue, cl::Kernel& kernel, std::size_t width, std::size_t height,
                     std::size_t group_width, std::size_t group_height, Profiler* profiler, const char* label) {
  cl::Event event;
  if (width == 0 || height == 0) return event;
  try {
    queue.enqueueNDRangeKernel(kernel, cl::NullRange,
                               cl::NDRange(round_up(width, group_width), round_up(height, group_height)),
                               cl::NDRange(group_width, group_height), nullptr, &event);
  } catch (...) {
    rethrow_as_error(std::string("launching kernel ") + label);
  }
  if (profiler) profiler->add(label, event);
  return event;
}

}  // namespace splatcl
