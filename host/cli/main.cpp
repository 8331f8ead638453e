// splatcl: one program, subcommands. Every failure is one line on stderr and a non-zero exit.
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <new>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "cli/commands.hpp"
#include "cli/model_input.hpp"
#include "cli/progress.hpp"
#include "io/cpu_set.hpp"
#include "io/memory.hpp"
#include "io/in_flight.hpp"
#include "runtime/error.hpp"
#include "io/json_keys.hpp"
#include "runtime/runtime.hpp"

namespace splatcl::cli {

std::string empty_device_value(const std::string& value) {
  return value.empty() ? std::string("empty: give an index, a type (cpu, gpu, simulator) or a name substring") : std::string();
}

void add_device_option(CLI::App& app, DeviceOptions& options) {
  app.add_option("--device", options.device,
                 "OpenCL device: index, type (cpu, gpu, simulator) or name substring; default $SPLATCL_DEVICE, else a GPU, else PoCL, else a CPU (a simulator only when named)")
      ->check(empty_device_value);
}

// CLI11's "Could not convert: --samples = -5" as what the option takes: "--samples -5: not a whole
// number 0 or more". The option is looked up in the command tree by name for its type.
std::string conversion_message(const CLI::App& app, const std::string& message) {
  const std::string prefix = "Could not convert: ", separator = " = ";
  const std::size_t at = message.find(separator);
  if (message.rfind(prefix, 0) != 0 || at == std::string::npos) return message;
  const std::string name = message.substr(prefix.size(), at - prefix.size()), value = message.substr(at + separator.size());
  std::vector<const CLI::App*> apps{&app};
  for (std::size_t i = 0; i < apps.size(); ++i)
    for (const CLI::App* sub : apps[i]->get_subcommands({})) apps.push_back(sub);
  for (const CLI::App* a : apps)
    if (const CLI::Option* option = a->get_option_no_throw(name)) {
      const std::string type = option->get_type_name();
      const char* wanted = type == "UINT" ? "a whole number 0 or more"
                           : type == "COUNT" ? "a whole number 1 or more"
                           : type == "INT"   ? "a whole number"
                           : type == "FLOAT" ? "a number"
                                             : nullptr;
      // A whole number too large for the option's type (--frames 99999999999) is one, just out of range.
      const bool digits = !value.empty() && value.find_first_not_of("0123456789") == std::string::npos;
      if (wanted && digits && (type == "UINT" || type == "COUNT" || type == "INT")) return fmt::format("{} {}: too large", name, value);
      if (wanted) return fmt::format("{} {}: not {}", name, value, wanted);
    }
  return message;
}

}  // namespace splatcl::cli

int main(int argc, char** argv) {
  // SIGTERM (scancel, time limits, preemption), SIGINT and SIGHUP remove half-written files first.
  splatcl::remove_in_flight_files_on_termination();
  // A task's CPU set (Slurm --cpus-per-task, taskset) bounds PoCL's threads as it bounds ours.
  splatcl::limit_opencl_threads_to_cpu_set();
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
  // CLI11 reports an unknown command word as "A subcommand is required"; name it instead, at the
  // top level and in a command whose own subcommand is required (csm build|info|...).
  const auto unknown_word = [](const CLI::App& parent, const char* word, const std::string& what) {
    std::string known;
    for (const CLI::App* sub : parent.get_subcommands({})) {
      if (sub->get_name() == word) return false;
      known += (known.empty() ? "" : ", ") + sub->get_name();
    }
    std::fprintf(stderr, "splatcl: unknown %s '%s' (%s: %s)\n", what.c_str(), word, what == "command" ? "commands" : "known", known.c_str());
    return true;
  };
  // An unknown option before any command word: CLI11 said only "A subcommand is required". One
  // that a command takes is named as misplaced.
  if (const std::string first = argc > 1 ? argv[1] : ""; first.size() > 1 && first[0] == '-' && !app.get_option_no_throw(first.substr(0, first.find('=')))) {
    bool commands_take_it = false;
    std::vector<const CLI::App*> commands{&app};
    for (std::size_t i = 0; i < commands.size(); ++i)
      for (const CLI::App* sub : commands[i]->get_subcommands({})) {
        commands.push_back(sub);
        commands_take_it = commands_take_it || sub->get_option_no_throw(first.substr(0, first.find('=')));
      }
    std::fprintf(stderr, commands_take_it ? "splatcl: option '%s' goes after the command (splatcl COMMAND %s ...; see --help)\n"
                                          : "splatcl: unknown option '%s' before the command (see --help)\n",
                 splatcl::printable(first).c_str(), splatcl::printable(first).c_str());
    return 1;
  }
  if (argc > 1 && argv[1][0] != '-') {
    if (unknown_word(app, argv[1], "command")) return 1;
    const CLI::App* chosen = app.get_subcommand(argv[1]);
    if (chosen->get_require_subcommand_min() > 0 && argc > 2 && argv[2][0] != '-' &&
        unknown_word(*chosen, argv[2], std::string(argv[1]) + " command"))
      return 1;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version exit 0; a bad command line is an error like any other: one line and
    // status 1 (runtime/error.hpp), not CLI11's two lines and its own codes (105-127).
    if (e.get_exit_code() == 0) return app.exit(e);
    std::string message = dynamic_cast<const CLI::ConversionError*>(&e) ? splatcl::cli::conversion_message(app, e.what()) : e.what();
    // An option given twice: CLI11 says "--res: At Most 1 required but received 2".
    if (const std::size_t at = message.find(": At Most 1 required but received "); at != std::string::npos)
      message = fmt::format("{} given {} times: give it once", message.substr(0, at), message.substr(at + 34));
    // A CLI::Range check: "--kmeans: Value 4x not in range 1 to 4294967295" (also for no number).
    // (Parsed by hand: std::regex drew -Wmaybe-uninitialized from libstdc++ in the sanitizer build.)
    if (const std::size_t value = message.find(": Value "), range = message.find(" not in range "), to = message.rfind(" to ");
        value != std::string::npos && range != std::string::npos && to != std::string::npos && value < range && range < to)
      message = fmt::format("{}: '{}' is not in {}..{}", message.substr(0, value), message.substr(value + 8, range - value - 8),
                            message.substr(range + 14, to - range - 14), message.substr(to + 4));
    std::fprintf(stderr, "splatcl: %s (see --help)\n", splatcl::printable(message).c_str());
    return 1;
  }
  // --reference runs the native references on no OpenCL device: a --device beside it was ignored
  // without a word (the summary said "reference").
  for (const CLI::App* a : app.get_subcommands({})) {
    std::vector<const CLI::App*> chosen{a};
    for (std::size_t i = 0; i < chosen.size(); ++i)
      for (const CLI::App* sub : chosen[i]->get_subcommands({})) chosen.push_back(sub);
    for (const CLI::App* c : chosen) {
      const CLI::Option* device = c->get_option_no_throw("--device");
      const CLI::Option* reference = c->get_option_no_throw("--reference");
      if (c->parsed() && device && reference && device->count() > 0 && reference->count() > 0 && reference->as<bool>()) {
        std::fprintf(stderr, "splatcl: --device and --reference contradict: --reference uses no OpenCL device (see --help)\n");
        return 1;
      }
      // A simulator interprets every operation: said before minutes of silence (a CSM build at its
      // defaults took about 20 minutes on Oclgrind, with no word why). Only a named device can be
      // one (no default is); one the selector does not name is left to the command's own error.
      if (c->parsed() && device && a->get_name() != "devices" && !(reference && reference->count() > 0 && reference->as<bool>())) {
        std::vector<std::string> selectors = device->count() > 0 ? device->results() : std::vector<std::string>{};
        if (const char* variable = std::getenv("SPLATCL_DEVICE"); selectors.empty() && variable && *variable) selectors.emplace_back(variable);
        try {
          const std::vector<splatcl::DeviceInfo> devices = selectors.empty() ? std::vector<splatcl::DeviceInfo>{} : splatcl::list_devices();
          for (const std::string& selector : selectors) {
            bool simulated = false;
            try {
              simulated = splatcl::match_device(devices, selector).type == "simulator";
            } catch (const splatcl::Error&) {
            }
            if (simulated) {
              std::fprintf(stderr, "splatcl: note: a simulated device interprets every operation: expect minutes for what takes "
                                   "seconds on PoCL (docs/portability.md)\n");
              break;
            }
          }
        } catch (const std::exception&) {  // no platform: the command says so
        }
      }
    }
  }
  try {
    // A bad $SPLATCL_MEMORY_LIMIT is named now, not when a build first asks for memory (after a
    // batch run's first model had built its splats).
    (void)splatcl::memory_limit_from_environment();
    (void)splatcl::cli::log_interval_seconds();  // and a bad $SPLATCL_PROGRESS_SECONDS (it was ignored)
    for (auto& [sub, action] : actions)
      if (sub->parsed()) {
        const int status = action();
        splatcl::cli::print_model_warnings();  // after the work, so a failing command prints one line only
        return status;
      }
  } catch (const splatcl::Error& e) {
    // One line, whatever a file or object name holds (a newline in a path split the message).
    std::fprintf(stderr, "splatcl: %s\n", splatcl::printable(e.what()).c_str());
    return 1;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "splatcl: out of memory: the input or the options ask for more memory than this machine has\n");
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "splatcl: %s\n", splatcl::printable(e.what()).c_str());
    return 1;
  }
  return 0;
}
