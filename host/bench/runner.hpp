#pragma once
// A whole `splatcl bench` run: the chosen suites on every chosen OpenCL device, optionally at
// several problem sizes (x2 steps) or thread counts, merged into one Results.
#include <string>
#include <vector>

#include "bench/record.hpp"
#include "bench/session.hpp"
#include "bench/suites.hpp"

namespace splatcl::bench {

enum class Scaling { None, Size, Threads };
Scaling parse_scaling(const std::string& text);  // "none", "size", "threads"; throws Error otherwise

struct RunOptions {
  SessionOptions session;            // sizes, runs, --quick; device and json_path are ignored
  std::vector<std::string> devices;  // selectors as for choose_device; empty = every device present but simulators
  Scaling scaling = Scaling::None;
  // Size scaling: every suite at scales 2^-(steps-1), ..., 1/2, 1 of their standard sizes.
  int size_steps = 4;
  // Thread scaling: the program to re-execute (default /proc/self/exe) and its arguments, without
  // the options the parent handles (see child_arguments).
  std::string program = "/proc/self/exe";
  std::vector<std::string> arguments;
};

// The devices the selectors name, each once, in order; "all" (or no selector) names every device but
// simulators (Oclgrind), which run only when named.
std::vector<DeviceInfo> bench_devices(const std::vector<std::string>& selectors);

// This process's command-line arguments (after the program name), from /proc/self/cmdline.
std::vector<std::string> own_arguments();

// A thread-scaling child run (run_child sets kBenchParentVariable to the parent's pid) ends when
// its parent does: a SIGTERM to the parent left the child running and writing its results into
// the temporary directory. Called first by the bench command; does nothing in other runs.
inline constexpr const char* kBenchParentVariable = "SPLATCL_BENCH_PARENT_PID";
void end_with_parent();
// `arguments` without the options a thread-scaling parent handles itself (--scaling, --json,
// --csv, --compare, --threshold, --plot, each with its value, as "--x V" or "--x=V").
std::vector<std::string> child_arguments(const std::vector<std::string>& arguments);

// Runs the suites; host rows (references, std, Embree) are measured with the first device only.
// Thread scaling re-executes options.program once per thread count 1..logical cores with
// POCL_MAX_PTHREAD_COUNT set (PoCL reads it once, at initialisation) and merges the children's
// records, each tagged "pocl_threads".
Results run_benchmarks(const std::vector<const Suite*>& suites, const RunOptions& options);

}  // namespace splatcl::bench
