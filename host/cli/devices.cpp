#include <fmt/format.h>

#include <cstdlib>
#include <thread>

#include "cli/commands.hpp"
#include "io/cpu_set.hpp"
#include "runtime/runtime.hpp"

namespace splatcl::cli {

Action register_devices(CLI::App& app) {
  auto* sub = app.add_subcommand("devices", "List every OpenCL platform and device, and the one chosen by default or by --device");
  auto options = std::make_shared<DeviceOptions>();
  add_device_option(*sub, *options);
  return [options] {
    const auto devices = list_devices();
    const auto chosen = choose_device(options->device);
    for (const auto& d : devices) {
      fmt::print("{} [{}] {} / {}\n", d.index == chosen.index ? "*" : " ", d.index, d.platform, d.name);
      fmt::print("      type {}, {} compute units, {:.1f} GiB global, {} KiB local, max alloc {:.1f} GiB\n", d.type,
                 d.compute_units, static_cast<double>(d.global_mem_bytes) / (1 << 30), d.local_mem_bytes / 1024,
                 static_cast<double>(d.max_alloc_bytes) / (1 << 30));
      fmt::print("      {}, {}, max work-group {}, preferred work-group multiple {}\n", d.version, d.opencl_c_version,
                 d.max_work_group_size, d.preferred_work_group_multiple);
    }
    const char* pocl_threads = std::getenv("POCL_MAX_PTHREAD_COUNT");
    fmt::print("host threads {} (the process's CPU affinity mask, of {} on the machine); POCL_MAX_PTHREAD_COUNT {}\n", usable_cpus(),
               std::thread::hardware_concurrency(), pocl_threads ? pocl_threads : "unset (PoCL uses every core)");
    fmt::print("* = chosen ({})\n", options->device.empty() ? "default: $SPLATCL_DEVICE, else GPU, else PoCL, else CPU; simulators only when named" : "--device " + options->device);
    return 0;
  };
}

}  // namespace splatcl::cli
