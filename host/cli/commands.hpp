#pragma once
// Each subcommand registers itself on the CLI11 app and returns the action to run when chosen.
#include <functional>

#include <CLI/CLI.hpp>

namespace splatcl::cli {

using Action = std::function<int()>;

// Options shared by every command that runs kernels.
struct DeviceOptions {
  std::string device;  // index, type or name substring; empty = $SPLATCL_DEVICE or default
};
void add_device_option(CLI::App& app, DeviceOptions& options);
// The check every --device option takes: an empty value is refused (bench took it as the default).
std::string empty_device_value(const std::string& value);

Action register_devices(CLI::App& app);
Action register_cluster(CLI::App& app);
Action register_bench(CLI::App& app);
Action register_splats(CLI::App& app);
Action register_csm(CLI::App& app);
Action register_ao(CLI::App& app);
Action register_batch(CLI::App& app);
Action register_render(CLI::App& app);
Action register_view(CLI::App& app);

}  // namespace splatcl::cli
