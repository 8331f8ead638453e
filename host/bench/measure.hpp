#pragma once
// Timing of one benchmark case: warm-up runs, then timed runs summarised by median, min and max.
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "runtime/profiling.hpp"

namespace splatcl::bench {

struct Summary {
  double median_ms = 0;
  double min_ms = 0;
  double max_ms = 0;
};

// Median (mean of the middle two for an even count), min and max. Throws Error when empty.
Summary summarize(std::vector<double> samples_ms);

struct MeasureOptions {
  int warmup = 1;  // untimed runs first: kernel builds, caches, page faults
  int runs = 7;
};

struct Timing {
  std::vector<double> wall_ms;  // one per timed run
  // Median over the timed runs of each profiled kernel label's device time, in first-seen order;
  // empty without a profiler.
  std::vector<std::pair<std::string, double>> device_ms;
  double device_total_ms = 0;  // median over the runs of their summed device time
};

// Runs setup() then run() warmup + runs times. Only run() is timed, on the host wall clock, so run()
// must return once its work has finished (e.g. after queue.finish()). When a profiler is given it is
// cleared before each run and the drivers' kernel events in it give the device times.
// on_run(i, total) is called before each run, for progress display.
Timing measure_runs(const MeasureOptions& options, const std::function<void()>& setup, const std::function<void()>& run,
                    Profiler* profiler = nullptr, const std::function<void(int, int)>& on_run = {});

// Resets the process's peak resident set size so the next peak_rss_mb() covers only what follows.
// Returns false where the kernel does not allow it (the peak then covers the whole process so far).
bool reset_peak_rss();
// Peak resident set size of this process in MiB (VmHWM, else getrusage).
double peak_rss_mb();

}  // namespace splatcl::bench
