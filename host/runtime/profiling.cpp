#include "runtime/profiling.hpp"

#include <algorithm>
#include <cstdlib>
#include <string>

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

namespace {

// Rethrows a failed launch as Error; when the work-group did not fit, the message says what the
// kernel allows on this device (CL_KERNEL_WORK_GROUP_SIZE, local memory) against what was asked.
[[noreturn]] void rethrow_launch_error(cl::CommandQueue& queue, cl::Kernel& kernel, std::size_t group_items,
                                       const char* label) {
  std::string what = std::string("launching kernel ") + label;
  try {
    throw;
  } catch (const cl::Error& e) {
    if (e.err() == CL_INVALID_WORK_GROUP_SIZE || e.err() == CL_OUT_OF_RESOURCES || e.err() == CL_INVALID_WORK_ITEM_SIZE) {
      try {
        const cl::Device device = queue.getInfo<CL_QUEUE_DEVICE>();
        what += " with " + std::to_string(group_items) + " work-items per group (the kernel allows " +
                std::to_string(kernel.getWorkGroupInfo<CL_KERNEL_WORK_GROUP_SIZE>(device)) + " and uses " +
                std::to_string(kernel.getWorkGroupInfo<CL_KERNEL_LOCAL_MEM_SIZE>(device)) + " B of the device's " +
                std::to_string(device.getInfo<CL_DEVICE_LOCAL_MEM_SIZE>()) + " B local memory on '" +
                device.getInfo<CL_DEVICE_NAME>().c_str() + "')";
      } catch (const cl::Error&) {
        // the limits could not be read: the plain message below still names the kernel
      }
    }
  } catch (...) {
  }
  rethrow_as_error(what);
}

// Test hook ($SPLATCL_TEST_SKIP_KERNEL, read once): a launch of the kernel of that name enqueues a
// marker instead, so a test can check that the result checks catch a kernel that writes nothing.
bool skipped_by_test(cl::CommandQueue& queue, cl::Kernel& kernel, cl::Event& event) {
  static const std::string skipped = [] {
    const char* name = std::getenv(kSkipKernelVariable);
    return std::string(name ? name : "");
  }();
  if (skipped.empty()) return false;
  std::string name = kernel.getInfo<CL_KERNEL_FUNCTION_NAME>();
  while (!name.empty() && name.back() == '\0') name.pop_back();
  if (name != skipped) return false;
  queue.enqueueMarkerWithWaitList(nullptr, &event);
  return true;
}

}  // namespace

cl::Event enqueue_1d(cl::CommandQueue& queue, cl::Kernel& kernel, std::size_t global, std::size_t local,
                     Profiler* profiler, const char* label) {
  cl::Event event;
  if (global == 0) return event;
  try {
    if (skipped_by_test(queue, kernel, event)) {
      if (profiler) profiler->add(label, event);
      return event;
    }
    if (local > 0) {
      queue.enqueueNDRangeKernel(kernel, cl::NullRange, cl::NDRange(round_up(global, local)), cl::NDRange(local), nullptr, &event);
    } else {
      queue.enqueueNDRangeKernel(kernel, cl::NullRange, cl::NDRange(global), cl::NullRange, nullptr, &event);
    }
  } catch (...) {
    rethrow_launch_error(queue, kernel, local, label);
  }
  if (profiler) profiler->add(label, event);
  return event;
}

cl::Event enqueue_2d(cl::CommandQueue& queue, cl::Kernel& kernel, std::size_t width, std::size_t height,
                     std::size_t group_width, std::size_t group_height, Profiler* profiler, const char* label) {
  cl::Event event;
  if (width == 0 || height == 0) return event;
  try {
    if (skipped_by_test(queue, kernel, event)) {
      if (profiler) profiler->add(label, event);
      return event;
    }
    queue.enqueueNDRangeKernel(kernel, cl::NullRange,
                               cl::NDRange(round_up(width, group_width), round_up(height, group_height)),
                               cl::NDRange(group_width, group_height), nullptr, &event);
  } catch (...) {
    rethrow_launch_error(queue, kernel, group_width * group_height, label);
  }
  if (profiler) profiler->add(label, event);
  return event;
}

}  // namespace splatcl
