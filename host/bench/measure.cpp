#include "bench/measure.hpp"

#include <sys/resource.h>

#include <algorithm>
#include <fstream>
#include <string>

#include "io/memory.hpp"
#include "runtime/error.hpp"

namespace splatcl::bench {

Summary summarize(std::vector<double> samples_ms) {
  if (samples_ms.empty()) throw Error("cannot summarize a benchmark with no timed runs");
  std::sort(samples_ms.begin(), samples_ms.end());
  const std::size_t n = samples_ms.size();
  const double median = n % 2 == 1 ? samples_ms[n / 2] : (samples_ms[n / 2 - 1] + samples_ms[n / 2]) / 2.0;
  return {median, samples_ms.front(), samples_ms.back()};
}

Timing measure_runs(const MeasureOptions& options, const std::function<void()>& setup, const std::function<void()>& run,
                    Profiler* profiler, const std::function<void(int, int)>& on_run) {
  if (options.runs < 1) throw Error("benchmark needs at least one timed run");
  const int total = std::max(options.warmup, 0) + options.runs;
  Timing timing;
  std::vector<std::pair<std::string, std::vector<double>>> device_samples;
  std::vector<double> device_totals;
  for (int i = 0; i < total; ++i) {
    if (on_run) on_run(i, total);
    if (setup) setup();
    if (profiler) profiler->clear();
    Stopwatch stopwatch;
    run();
    const double elapsed = stopwatch.elapsed_ms();
    if (i < total - options.runs) continue;
    timing.wall_ms.push_back(elapsed);
    if (!profiler) continue;
    double run_total = 0;
    for (const auto& [label, ms] : profiler->per_label_ms()) {
      auto it = std::find_if(device_samples.begin(), device_samples.end(), [&](const auto& s) { return s.first == label; });
      if (it == device_samples.end()) it = device_samples.insert(device_samples.end(), {label, {}});
      it->second.push_back(ms);
      run_total += ms;
    }
    device_totals.push_back(run_total);
  }
  for (const auto& [label, samples] : device_samples) timing.device_ms.emplace_back(label, summarize(samples).median_ms);
  if (!device_totals.empty()) timing.device_total_ms = summarize(device_totals).median_ms;
  return timing;
}

bool reset_peak_rss() {
  // Writing 5 to clear_refs resets VmHWM to the current RSS (Linux 4.0 and later).
  std::ofstream clear("/proc/self/clear_refs");
  if (!clear) return false;
  clear << "5";
  clear.close();
  return static_cast<bool>(clear);
}

double peak_rss_mb() {
  if (const auto peak = proc_kib("/proc/self/status", "VmHWM")) return static_cast<double>(*peak) / (1024.0 * 1024.0);
  rusage usage{};
  ::getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;  // ru_maxrss is in KiB on Linux
}

}  // namespace splatcl::bench
