#include "runtime/runtime.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>

#include <unistd.h>

#include "runtime/embedded.hpp"
#include "runtime/error.hpp"

namespace splatcl {
namespace {

std::string lower(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return text;
}

// A device that claims more than one of CPU, GPU and accelerator is a simulator of them all
// (Oclgrind: ACCELERATOR|GPU|CPU); so is any device of a known simulator platform.
bool is_simulator(cl_device_type type, const std::string& platform) {
  const cl_device_type kinds = type & (CL_DEVICE_TYPE_CPU | CL_DEVICE_TYPE_GPU | CL_DEVICE_TYPE_ACCELERATOR);
  return (kinds & (kinds - 1)) != 0 || lower(platform).find("oclgrind") != std::string::npos;
}

std::string device_type_name(cl_device_type type) {
  if (type & CL_DEVICE_TYPE_GPU) return "gpu";
  if (type & CL_DEVICE_TYPE_CPU) return "cpu";
  if (type & CL_DEVICE_TYPE_ACCELERATOR) return "accelerator";
  return "other";
}

// The one line of a failed kernel build: the file, the device, the options and the log's first
// error (its "file:line"), and where the whole log was written (the error was the whole log with
// its newlines, printed as one line of "\n"s).
std::string build_failure(const std::string& file, const std::string& device, const std::string& options, const std::string& log) {
  std::string first, line;
  std::istringstream lines(log);
  while (std::getline(lines, line)) {
    if (first.empty() && line.find_first_not_of(" \t\r") != std::string::npos) first = line;
    if (lower(line).find("error") != std::string::npos) {
      first = line;
      break;
    }
  }
  std::string saved;
  try {
    // Per process, file and options (the variants of one file are built with other options).
    std::string name = fmt::format("splatcl-kernel-build-{}-{}-{:016x}.log", ::getpid(), file, std::hash<std::string>{}(options));
    for (char& c : name)
      if (!std::isalnum(static_cast<unsigned char>(c)) && c != '.' && c != '-' && c != '_') c = '_';
    const std::filesystem::path path = std::filesystem::temp_directory_path() / name;
    std::ofstream out(path, std::ios::binary);
    out << log << "\n";
    out.close();  // a short log is still buffered: a full disk shows only here
    saved = !out.fail() ? "; the whole log: " + path.string() : "; the log could not be written to " + path.string();
  } catch (const std::exception& e) {
    saved = std::string("; the log could not be written: ") + e.what();
  }
  return "kernel build of " + file + " failed on '" + device + "'" + (options.empty() ? "" : " with options '" + options + "'") + ": " +
         (first.empty() ? "(the device gave no log)" : first) + saved;
}

std::string trim(std::string text) {
  while (!text.empty() && (text.back() == '\0' || std::isspace(static_cast<unsigned char>(text.back())))) text.pop_back();
  return text;
}

// PoCL fills CL_KERNEL_PREFERRED_WORK_GROUP_SIZE_MULTIPLE per kernel only; ask it on a tiny kernel.
std::size_t query_preferred_multiple(const cl::Device& device) {
  try {
    cl::Context context(device);
    cl::Program program(context, "__kernel void probe(__global int* a) { a[get_global_id(0)] = 0; }");
    program.build({device});
    cl::Kernel kernel(program, "probe");
    return kernel.getWorkGroupInfo<CL_KERNEL_PREFERRED_WORK_GROUP_SIZE_MULTIPLE>(device);
  } catch (...) {
    return 0;
  }
}

// The file name of a `#include "name"` line, or empty for any other line.
std::string quoted_include(const std::string& line) {
  std::size_t pos = line.find_first_not_of(" \t");
  if (pos == std::string::npos || line[pos] != '#') return {};
  pos = line.find_first_not_of(" \t", pos + 1);
  if (pos == std::string::npos || line.compare(pos, 7, "include") != 0) return {};
  const std::size_t open = line.find('"', pos + 7);
  if (open == std::string::npos) return {};
  const std::size_t close = line.find('"', open + 1);
  if (close == std::string::npos) return {};
  return line.substr(open + 1, close - open - 1);
}

}  // namespace

const char* cl_error_name(cl_int code) {
  switch (code) {
#define SPLATCL_CASE(x) case x: return #x;
    SPLATCL_CASE(CL_DEVICE_NOT_FOUND) SPLATCL_CASE(CL_DEVICE_NOT_AVAILABLE) SPLATCL_CASE(CL_COMPILER_NOT_AVAILABLE)
    SPLATCL_CASE(CL_MEM_OBJECT_ALLOCATION_FAILURE) SPLATCL_CASE(CL_OUT_OF_RESOURCES) SPLATCL_CASE(CL_OUT_OF_HOST_MEMORY)
    SPLATCL_CASE(CL_BUILD_PROGRAM_FAILURE) SPLATCL_CASE(CL_INVALID_VALUE) SPLATCL_CASE(CL_INVALID_DEVICE)
    SPLATCL_CASE(CL_INVALID_BUFFER_SIZE) SPLATCL_CASE(CL_INVALID_KERNEL_NAME) SPLATCL_CASE(CL_INVALID_KERNEL_ARGS)
    SPLATCL_CASE(CL_INVALID_ARG_INDEX) SPLATCL_CASE(CL_INVALID_ARG_VALUE) SPLATCL_CASE(CL_INVALID_ARG_SIZE)
    SPLATCL_CASE(CL_INVALID_WORK_GROUP_SIZE) SPLATCL_CASE(CL_INVALID_WORK_ITEM_SIZE) SPLATCL_CASE(CL_INVALID_GLOBAL_OFFSET)
    SPLATCL_CASE(CL_INVALID_GLOBAL_WORK_SIZE) SPLATCL_CASE(CL_INVALID_MEM_OBJECT) SPLATCL_CASE(CL_INVALID_PLATFORM)
    SPLATCL_CASE(CL_PLATFORM_NOT_FOUND_KHR) SPLATCL_CASE(CL_INVALID_OPERATION) SPLATCL_CASE(CL_INVALID_BUILD_OPTIONS)
    SPLATCL_CASE(CL_INVALID_PROGRAM_EXECUTABLE) SPLATCL_CASE(CL_INVALID_COMMAND_QUEUE)
#undef SPLATCL_CASE
    default: return "unknown OpenCL error";
  }
}

void rethrow_as_error(const std::string& what) {
  try {
    throw;
  } catch (const Error&) {
    throw;
  } catch (const cl::Error& e) {
    throw Error(what + ": " + e.what() + " failed with " + cl_error_name(e.err()) + " (" + std::to_string(e.err()) + ")");
  } catch (const std::bad_alloc&) {
    throw Error(what + ": out of host memory");
  } catch (const std::exception& e) {
    throw Error(what + ": " + e.what());
  }
}

std::vector<DeviceInfo> list_devices() {
  std::vector<cl::Platform> platforms;
  try {
    cl::Platform::get(&platforms);
  } catch (const cl::Error& e) {
    if (e.err() != CL_PLATFORM_NOT_FOUND_KHR) rethrow_as_error("listing OpenCL platforms");
  }
  if (platforms.empty())
    throw Error("no OpenCL platform found: install an OpenCL driver (on CPU-only Debian: pocl-opencl-icd)");
  std::vector<DeviceInfo> result;
  for (const auto& platform : platforms) {
    std::vector<cl::Device> devices;
    try {
      platform.getDevices(CL_DEVICE_TYPE_ALL, &devices);
    } catch (const cl::Error&) {
      continue;  // a platform without devices is not an error while another has some
    }
    for (const auto& device : devices) {
      DeviceInfo info;
      info.index = result.size();
      info.platform = trim(platform.getInfo<CL_PLATFORM_NAME>());
      info.platform_vendor = trim(platform.getInfo<CL_PLATFORM_VENDOR>());
      info.vendor = trim(device.getInfo<CL_DEVICE_VENDOR>());
      info.name = trim(device.getInfo<CL_DEVICE_NAME>());
      const cl_device_type type = device.getInfo<CL_DEVICE_TYPE>();
      info.type = is_simulator(type, info.platform) ? "simulator" : device_type_name(type);
      info.version = trim(device.getInfo<CL_DEVICE_VERSION>());
      info.opencl_c_version = trim(device.getInfo<CL_DEVICE_OPENCL_C_VERSION>());
      info.compute_units = device.getInfo<CL_DEVICE_MAX_COMPUTE_UNITS>();
      info.global_mem_bytes = device.getInfo<CL_DEVICE_GLOBAL_MEM_SIZE>();
      info.local_mem_bytes = device.getInfo<CL_DEVICE_LOCAL_MEM_SIZE>();
      info.max_alloc_bytes = device.getInfo<CL_DEVICE_MAX_MEM_ALLOC_SIZE>();
      info.max_work_group_size = device.getInfo<CL_DEVICE_MAX_WORK_GROUP_SIZE>();
      info.preferred_work_group_multiple = query_preferred_multiple(device);
      info.device = device;
      result.push_back(std::move(info));
    }
  }
  if (result.empty()) throw Error("no OpenCL device found on any platform");
  return result;
}

std::vector<DeviceInfo> default_devices() {
  std::vector<DeviceInfo> devices = list_devices();
  std::erase_if(devices, [](const DeviceInfo& d) { return d.type == "simulator"; });
  if (devices.empty())
    throw Error("only simulator OpenCL devices found (Oclgrind checks kernels, slowly): name one with --device or $" +
                std::string(kDeviceEnvVar));
  return devices;
}

DeviceInfo match_device(const std::vector<DeviceInfo>& devices, const std::string& selector, const std::string& origin) {
  const std::string wanted = lower(selector);
  if (std::all_of(wanted.begin(), wanted.end(), [](unsigned char c) { return std::isdigit(c); })) {
    const auto index = std::stoul(wanted);
    if (index >= devices.size())
      throw Error("device index " + wanted + origin + " out of range: " + std::to_string(devices.size()) +
                  " device(s) found (see 'splatcl devices', or list_devices())");
    return devices[index];
  }
  for (const auto& d : devices)
    if (d.type == wanted) return d;
  // A name substring: the platform's name or vendor first, so that 'intel' is Intel's runtime and
  // not PoCL on an Intel CPU (whose device name says Intel), and 'pocl' is PoCL; then the device's
  // name. More than one device either way is refused, not guessed.
  const auto has = [&](const std::string& text) { return lower(text).find(wanted) != std::string::npos; };
  for (const bool by_platform : {true, false}) {
    std::vector<std::size_t> matches;
    for (std::size_t i = 0; i < devices.size(); ++i)
      if (by_platform ? has(devices[i].platform) || has(devices[i].platform_vendor) : has(devices[i].name)) matches.push_back(i);
    if (matches.size() == 1) return devices[matches[0]];
    if (matches.size() > 1) {
      std::string listed;
      for (const std::size_t i : matches)
        listed += (listed.empty() ? "" : ", ") + fmt::format("[{}] {} / {}", devices[i].index, devices[i].platform, devices[i].name);
      throw Error(fmt::format("'{}'{} matches {} OpenCL devices by {}: {}; give its index or more of its name (see 'splatcl devices', or list_devices())",
                              selector, origin, matches.size(), by_platform ? "platform name or vendor" : "device name", listed));
    }
  }
  throw Error("no OpenCL device matches '" + selector + "'" + origin + " (see 'splatcl devices', or list_devices())");
}

DeviceInfo choose_device(const std::string& selector_in) {
  std::string selector = selector_in;
  std::string origin;  // names the variable where the selector came from it, not from --device
  if (selector.empty()) {
    if (const char* env = std::getenv(kDeviceEnvVar)) selector = env, origin = std::string(" (from $") + kDeviceEnvVar + ")";
  }
  if (selector.empty()) {
    const auto devices = default_devices();
    const auto first = [&](auto&& accept) { return std::find_if(devices.begin(), devices.end(), accept); };
    auto it = first([](const DeviceInfo& d) { return d.type == "gpu"; });
    if (it == devices.end())  // the CPU kernels are tuned on PoCL: it stays the default beside other CPU runtimes
      it = first([](const DeviceInfo& d) { return d.type == "cpu" && lower(d.platform).find("portable computing") != std::string::npos; });
    if (it == devices.end()) it = first([](const DeviceInfo& d) { return d.type == "cpu"; });
    return it == devices.end() ? devices.front() : *it;
  }
  return match_device(list_devices(), selector, origin);
}

const char* to_string(Shape shape) {
  switch (shape) {
    case Shape::Cpu: return "cpu";
    case Shape::Gpu: return "gpu";
    default: return "auto";
  }
}

Shape parse_shape(const std::string& text) {
  if (text == "cpu") return Shape::Cpu;
  if (text == "gpu") return Shape::Gpu;
  if (text == "auto" || text.empty()) return Shape::Auto;
  throw Error("unknown kernel shape '" + text + "' (expected auto, cpu or gpu)");
}

Runtime::Runtime(const DeviceInfo& info) : info_(info) {
  try {
    context_ = cl::Context(info_.device);
    queue_ = cl::CommandQueue(context_, info_.device, CL_QUEUE_PROFILING_ENABLE);
  } catch (...) {
    rethrow_as_error("creating an OpenCL context on '" + info_.name + "'");
  }
}

Runtime::~Runtime() {
  try {
    if (queue_()) queue_.finish();
  } catch (...) {  // a failed command already reported its error; nothing is left to wait for
  }
}

std::shared_ptr<Runtime> Runtime::create(const std::string& selector) {
  return std::make_shared<Runtime>(choose_device(selector));
}

Shape Runtime::resolve(Shape shape) const {
  if (shape != Shape::Auto) return shape;
  return is_cpu() ? Shape::Cpu : Shape::Gpu;
}

std::size_t Runtime::cpu_chunks() const {
  // A few chunks per compute unit balances uneven chunks without many partial results.
  return std::max<std::size_t>(1, std::size_t{info_.compute_units} * 4);
}

std::string expand_kernel_source(const std::string& file) {
  const auto& table = embedded_kernels();
  const auto it = table.find(file);
  if (it == table.end()) throw Error("kernel source '" + file + "' is not embedded in this binary");
  std::istringstream in{std::string(it->second)};
  std::ostringstream out;
  out << "#line 1 \"" << file << "\"\n";
  std::string line;
  int line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    if (const std::string header = quoted_include(line); !header.empty()) {
      out << expand_kernel_source(header) << "\n#line " << (line_number + 1) << " \"" << file << "\"\n";
    } else {
      out << line << '\n';
    }
  }
  return out.str();
}

cl::Program Runtime::program(const std::string& file, const std::string& options) {
  std::lock_guard lock(mutex_);
  const auto key = std::make_pair(file, options);
  if (auto it = programs_.find(key); it != programs_.end()) return it->second;
  const std::string source = expand_kernel_source(file);
  cl::Program program;
  try {
    program = cl::Program(context_, source);
  } catch (...) {
    rethrow_as_error("creating program " + file);
  }
  try {
    program.build({info_.device}, (options + " -cl-std=CL1.2").c_str());
  } catch (const cl::BuildError& e) {
    std::string log;
    for (const auto& entry : e.getBuildLog()) log += entry.second;
    throw Error(build_failure(file, info_.name, options, trim(log)));
  } catch (...) {
    rethrow_as_error("building " + file);
  }
  programs_.emplace(key, program);
  return program;
}

std::string Runtime::exact_divide_option() const {
  const cl_device_fp_config config = device().getInfo<CL_DEVICE_SINGLE_FP_CONFIG>();
  return (config & CL_FP_CORRECTLY_ROUNDED_DIVIDE_SQRT) ? " -cl-fp32-correctly-rounded-divide-sqrt" : "";
}

cl::Kernel Runtime::kernel(const std::string& file, const std::string& name, const std::string& options) {
  cl::Program built = program(file, options);
  try {
    return cl::Kernel(built, name.c_str());
  } catch (...) {
    rethrow_as_error("creating kernel " + name + " from " + file);
  }
}

cl::Buffer Runtime::buffer(cl_mem_flags flags, std::size_t bytes, const char* what) {
  try {
    // A zero-size buffer is invalid in OpenCL; size-0 inputs get a minimal allocation instead.
    return cl::Buffer(context_, flags, std::max<std::size_t>(bytes, 16));
  } catch (...) {
    rethrow_as_error(std::string("allocating ") + std::to_string(bytes) + " bytes for " + what + " on '" + info_.name + "'");
  }
}

}  // namespace splatcl
