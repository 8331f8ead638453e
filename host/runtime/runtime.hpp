#pragma once
// OpenCL runtime layer: device discovery and choice, one context and profiling queue per device,
// programs built from the embedded kernel sources once per (file, options) and cached.
#include <cstddef>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "runtime/opencl.hpp"

namespace splatcl {

// Environment variable that chooses the device when --device is not given.
inline constexpr const char* kDeviceEnvVar = "SPLATCL_DEVICE";

struct DeviceInfo {
  std::size_t index = 0;  // position in the flat list over all platforms
  std::string platform;
  std::string platform_vendor;  // CL_PLATFORM_VENDOR ("The pocl project", "Intel(R) Corporation")
  std::string vendor;  // CL_DEVICE_VENDOR (for a CPU device, the CPU's maker)
  std::string name;
  // "cpu", "gpu", "accelerator", "other", or "simulator": a device that checks kernels rather than
  // runs them fast (Oclgrind, which reports itself as ACCELERATOR|GPU|CPU). Simulators are never a
  // default: only a selector that names one (index, "simulator" or name) chooses it.
  std::string type;
  std::string version;
  std::string opencl_c_version;
  unsigned compute_units = 0;
  unsigned long long global_mem_bytes = 0;
  unsigned long long local_mem_bytes = 0;
  unsigned long long max_alloc_bytes = 0;
  std::size_t max_work_group_size = 0;
  std::size_t preferred_work_group_multiple = 0;
  cl::Device device;
};

// Every device of every platform. Throws Error when there is no platform or no device.
std::vector<DeviceInfo> list_devices();

// The devices a run over "every device" uses (bench without --device): all but simulators.
// Throws Error when there are none.
std::vector<DeviceInfo> default_devices();

// Chooses a device: selector is an index ("0"), a type ("cpu", "gpu", "simulator") or a
// case-insensitive substring of the platform's name or vendor, else of the device's name, that
// names one device (several are an Error that lists them). Empty selector: $SPLATCL_DEVICE, else
// the first GPU, else the first PoCL CPU device, else the first CPU, else the first device that is
// not a simulator.
DeviceInfo choose_device(const std::string& selector = "");
// The non-empty selector's device among `devices`, as choose_device; `origin` is appended to the
// selector in errors (" (from $SPLATCL_DEVICE)").
DeviceInfo match_device(const std::vector<DeviceInfo>& devices, const std::string& selector, const std::string& origin = "");

// Kernel shape: CPU-shaped (one work-item per contiguous chunk, no barriers) or GPU-shaped
// (work-groups with local memory). Auto picks by CL_DEVICE_TYPE.
enum class Shape { Auto, Cpu, Gpu };
const char* to_string(Shape shape);
Shape parse_shape(const std::string& text);

class Runtime {
 public:
  explicit Runtime(const DeviceInfo& info);
  // Waits for every command still queued: a kernel left behind by a stage that threw would
  // otherwise still be compiling (PoCL builds lazily, on a worker thread) while the process exits.
  ~Runtime();
  Runtime(const Runtime&) = delete;
  Runtime& operator=(const Runtime&) = delete;
  // Convenience: choose_device(selector) then construct.
  static std::shared_ptr<Runtime> create(const std::string& selector = "");

  const DeviceInfo& info() const { return info_; }
  cl::Context& context() { return context_; }
  cl::CommandQueue& queue() { return queue_; }
  const cl::Device& device() const { return info_.device; }
  bool is_cpu() const { return info_.type == "cpu"; }
  // Auto resolved against the device type.
  Shape resolve(Shape shape) const;
  // Work-items that keep every compute unit busy for CPU-shaped kernels.
  std::size_t cpu_chunks() const;

  // " -cl-fp32-correctly-rounded-divide-sqrt" where the device offers it, else "": for kernels that
  // must match a host reference (whose division and std::sqrt are correctly rounded) bit for bit.
  // OpenCL 1.2 lets a device round single-precision division to 2.5 ulp and sqrt to 3 without it.
  std::string exact_divide_option() const;

  // Builds (once) the embedded kernel file `file` with `options` and returns a fresh kernel object.
  // Build failures throw Error: one line with the build log's first error (file name and line) and
  // the path of the whole log, written to the temporary directory.
  cl::Kernel kernel(const std::string& file, const std::string& name, const std::string& options = "");
  cl::Program program(const std::string& file, const std::string& options = "");

  // Buffer allocation with a clear error on failure (size named).
  cl::Buffer buffer(cl_mem_flags flags, std::size_t bytes, const char* what);

 private:
  DeviceInfo info_;
  cl::Context context_;
  cl::CommandQueue queue_;
  std::mutex mutex_;
  std::map<std::pair<std::string, std::string>, cl::Program> programs_;
};

// Expands `#include "x.h"` against the embedded kernel headers, with #line markers so that build
// logs name the original file and line. Throws Error for an unknown file.
std::string expand_kernel_source(const std::string& file);

// Text for an OpenCL error code ("CL_OUT_OF_RESOURCES").
const char* cl_error_name(cl_int code);

// Rethrows a cl::Error (or anything else) as splatcl::Error with `what` prefixed.
[[noreturn]] void rethrow_as_error(const std::string& what);

// Blocking copy of `data` into a new buffer named `what` in errors. An empty vector gets a
// one-element buffer: OpenCL has no zero-sized buffers.
template <class T>
cl::Buffer upload(Runtime& runtime, const std::vector<T>& data, const char* what,
                  cl_mem_flags flags = CL_MEM_READ_WRITE) {
  cl::Buffer buffer = runtime.buffer(flags, (data.empty() ? 1 : data.size()) * sizeof(T), what);
  try {
    if (!data.empty()) runtime.queue().enqueueWriteBuffer(buffer, CL_TRUE, 0, data.size() * sizeof(T), data.data());
  } catch (...) {
    rethrow_as_error(std::string("uploading ") + what);
  }
  return buffer;
}

// Blocking read of the first n elements of `buffer`.
template <class T>
std::vector<T> download(Runtime& runtime, const cl::Buffer& buffer, std::size_t n, const char* what = "device results") {
  std::vector<T> data(n);
  try {
    if (n > 0) runtime.queue().enqueueReadBuffer(buffer, CL_TRUE, 0, n * sizeof(T), data.data());
  } catch (...) {
    rethrow_as_error(std::string("reading back ") + what);
  }
  return data;
}

}  // namespace splatcl
