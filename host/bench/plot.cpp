#include "bench/plot.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>

#include "bench/report.hpp"
#include "io/atomic_file.hpp"
#include "runtime/error.hpp"

namespace splatcl::bench {
namespace {

namespace fs = std::filesystem;

// A gnuplot double-quoted string.
std::string quote(const std::string& text) {
  std::string out = "\"";
  for (char c : text) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

// Tab-separated data cells must not hold tabs or line breaks.
std::string cell(std::string text) {
  std::replace_if(text.begin(), text.end(), [](char c) { return c == '\t' || c == '\n' || c == '\r'; }, ' ');
  return text;
}

int threads_of(const Record& record) {
  const auto it = record.extra.find("pocl_threads");
  return it != record.extra.end() && it->is_number_integer() ? it->get<int>() : 0;
}

// A file-name-safe suite name.
std::string slug(const std::string& text) {
  std::string out;
  for (char c : text) out += std::isalnum(static_cast<unsigned char>(c)) ? c : '-';
  return out;
}

// The implementation, with the device when the results hold several, without the thread count (the
// x axis of thread scaling).
std::string series_label(const Record& record, bool with_device) {
  Record unthreaded = record;
  unthreaded.extra.erase("pocl_threads");
  return impl_label(unthreaded) + (with_device && record.device != kHostDevice ? " on " + record.device : "");
}

// 16 distinguishable colours, so no two series of a plot share one.
std::string terminal(int width, int height) {
  static const char* const colours[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2", "#7f7f7f",
                                        "#bcbd22", "#17becf", "#393b79", "#e7ba52", "#637939", "#ad494a", "#7b4173", "#000000"};
  std::string text = fmt::format("set terminal pngcairo size {},{} noenhanced font \",9\"\n", width, height);
  for (std::size_t k = 0; k < std::size(colours); ++k) text += fmt::format("set linetype {} lc rgb \"{}\" lw 2 pt {}\n", k + 1, colours[k], k % 7 + 1);
  return text + "set linetype cycle 16\n";
}

// Device names go into the series labels only when the records come from several devices; the
// single device is named in the title.
bool several_devices(const std::vector<const Record*>& records, std::string& only_device) {
  std::vector<std::string> devices;
  for (const Record* r : records)
    if (r->device != kHostDevice && std::find(devices.begin(), devices.end(), r->device) == devices.end()) devices.push_back(r->device);
  only_device = devices.size() == 1 ? devices.front() : "";
  return devices.size() > 1;
}

struct Plot {
  std::string png;     // final path
  std::string script;  // gnuplot commands
};

// Bars: x = case (with its unit), one bar per implementation and device.
void throughput_plot(const std::string& suite, const std::vector<const Record*>& records, const fs::path& dir,
                     std::vector<Plot>& plots) {
  // Largest size and thread count of each case/series.
  std::string device;
  const bool with_device = several_devices(records, device);
  std::map<std::pair<std::string, std::string>, const Record*> chosen;
  std::vector<std::string> cases, series;
  for (const Record* r : records) {
    if (!r->throughput) continue;
    const std::string row = case_label(*r) + " [" + r->throughput_unit + "]";
    const std::string column = series_label(*r, with_device);
    if (std::find(cases.begin(), cases.end(), row) == cases.end()) cases.push_back(row);
    if (std::find(series.begin(), series.end(), column) == series.end()) series.push_back(column);
    const Record*& slot = chosen[{row, column}];
    if (!slot || r->size.value_or(0) > slot->size.value_or(0) ||
        (r->size == slot->size && threads_of(*r) > threads_of(*slot)))
      slot = r;
  }
  if (cases.empty()) return;
  std::string data = "case";
  for (const auto& s : series) {
    data += '\t';
    data += cell(s);
  }
  data += "\n";
  for (const auto& row : cases) {
    data += cell(row);
    for (const auto& column : series) {
      const auto it = chosen.find({row, column});
      data += it == chosen.end() ? "\t?" : fmt::format("\t{:.6g}", *it->second->throughput);
    }
    data += "\n";
  }
  const fs::path data_path = dir / ("throughput-" + slug(suite) + ".dat");
  write_file_atomically(data_path.string(), data);
  const fs::path png = dir / ("throughput-" + slug(suite) + ".png");
  const int width = 700 + 12 * static_cast<int>(cases.size() * series.size());
  std::string script = terminal(std::clamp(width, 1100, 1800), 800);
  script += "set output " + quote(png.string() + ".part") + "\n";
  script += "set title " + quote("bench " + suite + ": throughput per case and implementation, higher is better") +
            (device.empty() ? "" : " . \"\\n\" . " + quote("OpenCL device " + device)) + "\n";
  script += "set datafile separator \"\\t\"\nset datafile missing \"?\"\n";
  script += "set style data histograms\nset style histogram clustered gap 1\nset style fill solid 0.85 border -1\n";
  script += "set logscale y\nset ylabel \"throughput (units per second, log scale)\"\nset grid ytics\n";
  script += "set xtics rotate by 30 right\nset bmargin 17\nset lmargin 40\nset key outside right top\n";
  script += fmt::format("plot for [i=2:{}] {} using i:xtic(1) title columnhead(i)\n", series.size() + 1, quote(data_path.string()));
  plots.push_back({png.string(), script});
}

// Lines: one per (case, implementation, device) with at least two points.
void scaling_plot(const std::string& suite, const std::vector<const Record*>& records, const fs::path& dir, bool threads,
                  std::vector<Plot>& plots) {
  std::map<std::string, std::map<double, double>> lines;  // label → x → y
  std::vector<std::string> order;
  std::map<std::string, double> one_thread_ms;
  std::string device;
  const bool with_device = several_devices(records, device);
  const auto label_of = [&](const Record& r) { return series_label(r, with_device); };
  if (threads)
    for (const Record* r : records)
      if (threads_of(*r) == 1) one_thread_ms[case_label(*r) + " " + label_of(*r) + fmt::format(" {}", r->size.value_or(0))] = r->median_ms;
  for (const Record* r : records) {
    double x = 0, y = 0;
    std::string label = case_label(*r) + ": " + label_of(*r);
    if (threads) {
      if (threads_of(*r) == 0 || r->median_ms <= 0) continue;
      const auto base = one_thread_ms.find(case_label(*r) + " " + label_of(*r) + fmt::format(" {}", r->size.value_or(0)));
      if (base == one_thread_ms.end()) continue;
      x = threads_of(*r);
      y = base->second / r->median_ms;
      if (r->size) label += fmt::format(" ({} {})", *r->size, r->size_unit);
    } else {
      if (!r->size || !r->throughput || threads_of(*r) > 0) continue;
      x = static_cast<double>(*r->size);
      y = *r->throughput;
      label += " [" + r->throughput_unit + "]";
    }
    if (!lines.count(label)) order.push_back(label);
    lines[label][x] = y;
  }
  std::erase_if(order, [&](const std::string& label) { return lines[label].size() < 2; });
  if (order.empty()) return;
  const std::string name = (threads ? "scaling-threads-" : "scaling-size-") + slug(suite);
  std::string data;
  for (const auto& label : order) {
    for (const auto& [x, y] : lines[label]) data += fmt::format("{:.6g}\t{:.6g}\n", x, y);
    data += "\n\n";
  }
  const fs::path data_path = dir / (name + ".dat");
  write_file_atomically(data_path.string(), data);
  const fs::path png = dir / (name + ".png");
  std::string script = terminal(1200, 700 + 14 * static_cast<int>(order.size()));
  script += "set output " + quote(png.string() + ".part") + "\n";
  script += "set datafile separator \"\\t\"\nset grid\nset key outside below\n";
  if (threads) {
    script += "set title " + quote("bench " + suite + ": speedup over one thread (POCL_MAX_PTHREAD_COUNT)") +
              (device.empty() ? "" : " . \"\\n\" . " + quote("OpenCL device " + device)) + "\n";
    script += "set xlabel \"threads\"\nset ylabel \"speedup over 1 thread\"\nset xtics 1\n";
  } else {
    script += "set title " + quote("bench " + suite + ": throughput against problem size (x2 steps)") +
              (device.empty() ? "" : " . \"\\n\" . " + quote("OpenCL device " + device)) + "\n";
    script += "set logscale xy 2\nset xlabel \"problem size\"\nset ylabel \"throughput (units per second)\"\nset format y \"%.3g\"\n";
  }
  script += "plot ";
  for (std::size_t k = 0; k < order.size(); ++k)
    script += fmt::format("{}{} index {} using 1:2 with linespoints title {}", k ? ", \\\n     " : "", quote(data_path.string()), k,
                          quote(order[k]));
  script += "\n";
  plots.push_back({png.string(), script});
}

}  // namespace

std::string find_gnuplot() {
  const char* path = std::getenv("PATH");
  std::stringstream dirs(path ? path : "");
  std::string entry;
  while (std::getline(dirs, entry, ':')) {
    if (entry.empty()) continue;
    const fs::path candidate = fs::path(entry) / "gnuplot";
    if (::access(candidate.c_str(), X_OK) == 0) return candidate.string();
  }
  return {};
}

std::vector<std::string> write_plots(const Results& results, const std::string& dir_name) {
  const fs::path dir(dir_name);
  std::error_code error;
  fs::create_directories(dir, error);
  if (!fs::is_directory(dir))
    throw Error("cannot create plot directory " + dir_name + ": " +
                (fs::exists(dir) ? std::string("a file of that name is there") : error ? error.message() : std::string("no such directory")));

  std::vector<std::string> suites;
  for (const auto& r : results.records)
    if (std::find(suites.begin(), suites.end(), r.suite) == suites.end()) suites.push_back(r.suite);
  std::vector<Plot> plots;
  for (const auto& suite : suites) {
    std::vector<const Record*> records;
    for (const auto& r : results.records)
      if (r.suite == suite) records.push_back(&r);
    throughput_plot(suite, records, dir, plots);
    scaling_plot(suite, records, dir, false, plots);
    scaling_plot(suite, records, dir, true, plots);
  }
  if (plots.empty()) throw Error("nothing to plot: no record has a throughput");

  std::string script = "# Written by 'splatcl bench plot'; rerun with: gnuplot " + (dir / "plots.gp").string() + "\n";
  for (const auto& plot : plots) script += "\n" + plot.script + "unset output\nreset\n";
  // gnuplot draws into PNAME.png.part here (renamed when every plot is complete); the kept script
  // names the PNGs themselves, so that rerunning it redraws them (it wrote only *.png.part files).
  std::string kept = script;
  for (const auto& plot : plots)
    for (std::size_t at = 0; (at = kept.find(quote(plot.png + ".part"), at)) != std::string::npos;)
      kept.replace(at, quote(plot.png + ".part").size(), quote(plot.png));
  write_file_atomically((dir / "plots.gp").string(), kept);
  const fs::path script_path = dir / "plots.gp.part";
  write_file_atomically(script_path.string(), script);
  struct RemoveScript {
    fs::path path;
    ~RemoveScript() {
      std::error_code ignored;
      fs::remove(path, ignored);
    }
  } remove_script{script_path};

  const std::string gnuplot = find_gnuplot();
  if (gnuplot.empty())
    // The kept script, which names the PNGs (the .part one is removed on the way out).
    throw Error("gnuplot not found on PATH: install gnuplot-nox (scripts/setup.sh does), then run gnuplot " + (dir / "plots.gp").string());
  const pid_t child = ::fork();
  if (child < 0) throw Error("cannot start gnuplot: fork failed");
  if (child == 0) {
    ::execl(gnuplot.c_str(), "gnuplot", script_path.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  int status = 0;
  while (::waitpid(child, &status, 0) < 0) {
    if (errno != EINTR) throw Error("waiting for gnuplot failed");
  }
  std::vector<std::string> written;
  for (const auto& plot : plots) {
    const std::string part = plot.png + ".part";
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || !fs::exists(part)) {
      for (const auto& p : plots) fs::remove(p.png + ".part", error);
      throw Error("gnuplot failed on " + (dir / "plots.gp").string() + " (exit status " +
                  std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) + ")");
    }
  }
  for (const auto& plot : plots) {
    fs::rename(plot.png + ".part", plot.png, error);
    if (error) throw Error("cannot write " + plot.png + ": " + error.message());
    written.push_back(plot.png);
  }
  return written;
}

}  // namespace splatcl::bench
