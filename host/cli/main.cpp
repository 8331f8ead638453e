// splatcl: one program, subcommands. Every failure is one line on stderr and a non-zero exit.
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "cli/commands.hpp"
#include "runtime/error.hpp"
#include "runtime/runtime.hpp"

namespace splatcl::cli {

void add_device_option(CLI::App& app, DeviceOptions& options) {
  app.add_option("--device", options.device,
                 "OpenCL device: index, type (cpu, gpu) or name substring; default $SPLATCL_DEVICE, else a GPU, else the CPU");
}

}  // namespace splatcl::cli

int main(int argc, char** argv) {
  CLI::App app{"splatcl: point-based rendering with coherent shadow maps and many lights, on OpenCL"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "splatcl 0.1.0");
  std::vector<std::pair<CLI::App*, splatcl::cli::Action>> actions;
  auto add = [&](splatcl::cli::Action (*registrar)(CLI::App&)) {
    const std::size_t before = app.get_subcommands({}).size();
    auto action = registrar(app);
    actions.emplace_back(app.get_subcommands({}).at(before), std::move(action));
  };
  add(splatcl::cli::register_devices);
  add(splatcl::cli::register_cluster);
  add(splatcl::cli::register_bench);
  add(splatcl::cli::register_splats);
  add(splatcl::cli::register_csm);
  add(splatcl::cli::register_ao);
  add(splatcl::cli::register_batch);
  add(splatcl::cli::register_render);
  add(splatcl::cli::register_view);
  // CLI11 reports an unknown command word as "A subcommand is required"; name it instead.
  if (argc > 1 && argv[1][0] != '-') {
    std::string known;
    bool found = false;
    for (const CLI::App* sub : app.get_subcommands({})) {
      found = found || sub->get_name() == argv[1];
      known += (known.empty() ? "" : ", ") + sub->get_name();
    }
    if (!found) {
      std::fprintf(stderr, "splatcl: unknown command '%s' (commands: %s)\n", argv[1], known.c_str());
      return 1;
    }
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version exit 0; a bad command line is an error like any other: status 1
    // (runtime/error.hpp), not CLI11's own codes (105-127).
    return app.exit(e) == 0 ? 0 : 1;
  }
  try {
    for (auto& [sub, action] : actions)
      if (sub->parsed()) return action();
  } catch (const splatcl::Error& e) {
    std::fprintf(stderr, "splatcl: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "splatcl: %s\n", e.what());
    return 1;
  }
  return 0;
}
