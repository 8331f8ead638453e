#include "bench/runner.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <thread>

#include "bench/compare.hpp"
#include "io/in_flight.hpp"
#include "runtime/error.hpp"

extern char** environ;

namespace splatcl::bench {
namespace {

// Runs `program arguments` with POCL_MAX_PTHREAD_COUNT=threads and stdout discarded (the child's
// table is merged into the parent's); stderr is shared, so progress and errors show. Returns the exit
// status.
int run_child(const std::string& program, const std::vector<std::string>& arguments, int threads) {
  std::vector<std::string> env_strings;
  for (char** e = environ; *e; ++e)
    if (std::strncmp(*e, "POCL_MAX_PTHREAD_COUNT=", 23) != 0 && std::strncmp(*e, kBenchParentVariable, std::strlen(kBenchParentVariable)) != 0)
      env_strings.emplace_back(*e);
  env_strings.push_back(fmt::format("POCL_MAX_PTHREAD_COUNT={}", threads));
  env_strings.push_back(fmt::format("{}={}", kBenchParentVariable, ::getpid()));
  std::vector<char*> env;
  for (auto& s : env_strings) env.push_back(s.data());
  env.push_back(nullptr);
  std::vector<std::string> argv_strings{"splatcl"};
  argv_strings.insert(argv_strings.end(), arguments.begin(), arguments.end());
  std::vector<char*> argv;
  for (auto& s : argv_strings) argv.push_back(s.data());
  argv.push_back(nullptr);

  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
  pid_t pid = 0;
  const int started = ::posix_spawn(&pid, program.c_str(), &actions, nullptr, argv.data(), env.data());
  posix_spawn_file_actions_destroy(&actions);
  if (started != 0) throw Error("cannot run " + program + " for thread scaling: " + std::strerror(started));
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) throw Error("waiting for the thread-scaling run failed");
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
}

Results run_thread_scaling(const RunOptions& options) {
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  Results merged;
  for (unsigned threads = 1; threads <= cores; ++threads) {
    const std::filesystem::path json =
        std::filesystem::temp_directory_path() / fmt::format("splatcl-bench-{}-threads-{}.json", ::getpid(), threads);
    std::vector<std::string> arguments = options.arguments;
    arguments.push_back("--json");
    arguments.push_back(json.string());
    // Removed by a terminating signal while the child may write it (the child ends with us: end_with_parent).
    const int slot = register_in_flight(json.string());
    const int status = run_child(options.program, arguments, static_cast<int>(threads));
    unregister_in_flight(slot);
    if (status != 0) {
      std::error_code ignored;
      std::filesystem::remove(json, ignored);
      throw Error(fmt::format("the run with POCL_MAX_PTHREAD_COUNT={} failed (exit status {})", threads, status));
    }
    Results part = read_results(json.string());
    std::error_code ignored;
    std::filesystem::remove(json, ignored);
    if (merged.machine.empty()) {
      merged.machine = part.machine;
      merged.machine.erase("pocl_max_pthread_count");
      merged.machine["pocl_thread_counts"] = fmt::format("1..{}", cores);
      merged.machine["command"] = command_line();  // the child's names a temporary --json
    }
    for (auto& record : part.records) {
      record.extra["pocl_threads"] = threads;
      merged.records.push_back(std::move(record));
    }
  }
  return merged;
}

}  // namespace

void end_with_parent() {
  const char* parent = std::getenv(kBenchParentVariable);
  if (!parent) return;
  // SIGTERM when the parent dies; and now if it already has (it is no longer our parent).
  ::prctl(PR_SET_PDEATHSIG, SIGTERM);
  if (std::to_string(::getppid()) != parent) ::raise(SIGTERM);
}

Scaling parse_scaling(const std::string& text) {
  if (text == "none") return Scaling::None;
  if (text == "size") return Scaling::Size;
  if (text == "threads") return Scaling::Threads;
  throw Error("unknown scaling '" + text + "' (one of: none, size, threads)");
}

std::vector<DeviceInfo> bench_devices(const std::vector<std::string>& selectors) {
  if (selectors.empty()) return default_devices();  // simulators only when named
  std::vector<DeviceInfo> chosen;
  auto add = [&](DeviceInfo info) {
    if (std::none_of(chosen.begin(), chosen.end(), [&](const DeviceInfo& d) { return d.index == info.index; }))
      chosen.push_back(std::move(info));
  };
  for (const auto& selector : selectors) {
    if (selector == "all") {
      for (DeviceInfo& info : default_devices()) add(std::move(info));
    } else {
      add(choose_device(selector));
    }
  }
  return chosen;
}

std::vector<std::string> own_arguments() {
  std::vector<std::string> arguments = command_words();
  if (!arguments.empty()) arguments.erase(arguments.begin());
  return arguments;
}

std::vector<std::string> child_arguments(const std::vector<std::string>& arguments) {
  static const char* const parent_options[] = {"--scaling", "--json", "--csv", "--compare", "--threshold", "--plot"};
  std::vector<std::string> kept;
  for (std::size_t k = 0; k < arguments.size(); ++k) {
    const std::string& a = arguments[k];
    bool dropped = false;
    for (const char* option : parent_options) {
      const std::string name = option;
      if (a == name) {
        ++k;  // and its value
        dropped = true;
      } else if (a.rfind(name + "=", 0) == 0) {
        dropped = true;
      }
      if (dropped) break;
    }
    if (!dropped) kept.push_back(a);
  }
  return kept;
}

Results run_benchmarks(const std::vector<const Suite*>& suites, const RunOptions& options) {
  if (options.scaling == Scaling::Threads) return run_thread_scaling(options);
  if (options.size_steps < 1) throw Error("--steps must be at least 1");

  const std::vector<DeviceInfo> devices = bench_devices(options.devices);
  Results results;
  // A case at its smallest size already is not made smaller by a further step: the step's rows
  // repeat the earlier step's (same case, impl, device and size), and report, compare and plot
  // could not tell them apart (three "1024 rays" rows with speedups 1.00x, 1.49x and 0.20x; compare
  // of a file with itself found regressions). The first of them is kept.
  for (std::size_t d = 0; d < devices.size(); ++d) {
    std::set<std::string> recorded;  // per device: two devices of one model are two sets of rows
    // Two devices of one name (two GPUs of one model) are told apart by their index in the rows,
    // which compare and report match by device name.
    const bool name_shared = std::count_if(devices.begin(), devices.end(), [&](const DeviceInfo& other) { return other.name == devices[d].name; }) > 1;
    for (const Suite* suite : suites) {
      const int steps = options.scaling == Scaling::Size ? options.size_steps : 1;
      for (int step = steps - 1; step >= 0; --step) {
        SessionOptions session_options = options.session;
        session_options.device = std::to_string(devices[d].index);
        session_options.json_path.clear();
        session_options.measure_host = d == 0;
        session_options.scale = options.session.scale / std::ldexp(1.0, step);
        session_options.measure_bandwidth = options.session.measure_bandwidth && step == 0;
        Session session(suite->name, session_options);
        suite->run(session);
        Results part = session.results();
        if (results.machine.empty()) results.machine = part.machine;
        for (Record& record : part.records) {
          if (name_shared && record.device == devices[d].name) record.device += fmt::format(" [{}]", devices[d].index);
          if (recorded.insert(comparison_key(record)).second) results.records.push_back(std::move(record));
        }
      }
    }
  }
  if (devices.size() > 1) {
    // Each device's platform, version and tuning too: the machine block's opencl_* and tuning
    // fields are the first's.
    Json described = Json::array();
    for (const auto& device : devices)
      described.push_back({{"name", device.name}, {"platform", device.platform}, {"type", device.type}, {"version", device.version},
                           {"tuning", tuning_used(device)}});
    results.machine["opencl_devices"] = described;
  }
  return results;
}

}  // namespace splatcl::bench
