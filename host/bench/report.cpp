#include "bench/report.hpp"

#include <algorithm>
#include <iterator>
#include <optional>

#include <fmt/format.h>
#include <fmt/ranges.h>

namespace splatcl::bench {
namespace {

std::string scalar_text(const Json& value) { return value.is_string() ? value.get<std::string>() : value.dump(); }

// "bits=20 lights=16384": the scalar extra fields that make a variant of the problem.
std::string problem_label(const Record& record) {
  std::string label;
  for (const auto& [key, value] : record.extra.items()) {
    if (describes_implementation(key) || value.is_structured()) continue;
    label += (label.empty() ? "" : " ") + key + "=" + scalar_text(value);
  }
  return label;
}

std::string group_key(const Record& record) {
  return record.suite + '\n' + record.case_name + '\n' + (record.size ? std::to_string(*record.size) : "") + '\n' +
         record.size_unit + '\n' + problem_label(record);
}

std::string format_ms(double ms) {
  if (ms < 1) return fmt::format("{:.3f}", ms);
  if (ms < 100) return fmt::format("{:.2f}", ms);
  return fmt::format("{:.1f}", ms);
}

// 20.1 GB/s, 1.52 G keys/s.
std::string format_throughput(double value, const std::string& unit) {
  static const char* const prefixes[] = {"", "k", "M", "G", "T", "P"};
  std::size_t prefix = 0;
  while (value >= 1000 && prefix + 1 < std::size(prefixes)) {
    value /= 1000;
    ++prefix;
  }
  const std::string number = value < 10 ? fmt::format("{:.2f}", value) : fmt::format("{:.1f}", value);
  if (unit.rfind("bytes", 0) == 0) return number + " " + prefixes[prefix] + "B" + unit.substr(5);
  return number + " " + prefixes[prefix] + (prefix == 0 ? "" : " ") + unit;
}

// Display width of UTF-8 text: code points, which is right for the symbols used here.
std::size_t display_width(const std::string& text) {
  return static_cast<std::size_t>(
      std::count_if(text.begin(), text.end(), [](char c) { return (static_cast<unsigned char>(c) & 0xC0) != 0x80; }));
}

std::string render(const std::vector<std::string>& header, const std::vector<bool>& right_aligned,
                   const std::vector<std::vector<std::string>>& rows) {
  std::vector<std::size_t> widths(header.size(), 3);
  for (std::size_t c = 0; c < header.size(); ++c) {
    widths[c] = std::max(widths[c], display_width(header[c]));
    for (const auto& row : rows) widths[c] = std::max(widths[c], display_width(row[c]));
  }
  auto line = [&](const std::vector<std::string>& cells) {
    std::string text = "|";
    for (std::size_t c = 0; c < cells.size(); ++c) {
      const std::size_t pad = widths[c] - display_width(cells[c]);
      text.push_back(' ');
      if (right_aligned[c]) text.append(pad, ' ');
      text += cells[c];
      if (!right_aligned[c]) text.append(pad, ' ');
      text += " |";
    }
    text.push_back('\n');
    return text;
  };
  std::string text = line(header);
  text += "|";
  for (std::size_t c = 0; c < header.size(); ++c) {
    text.push_back(' ');
    text.append(right_aligned[c] ? widths[c] - 1 : widths[c], '-');
    text += right_aligned[c] ? ": |" : " |";
  }
  text.push_back('\n');
  for (const auto& row : rows) text += line(row);
  return text;
}

}  // namespace

std::string case_label(const Record& record) {
  const std::string variant = problem_label(record);
  return variant.empty() ? record.case_name : record.case_name + " " + variant;
}

std::string impl_label(const Record& record) {
  std::string label = record.impl;
  if (const auto variant = record.extra.find("variant"); variant != record.extra.end())
    label += fmt::format(" {}", scalar_text(*variant));
  if (const auto shape = record.extra.find("shape"); shape != record.extra.end())
    label += fmt::format(" ({} shape)", scalar_text(*shape));
  if (const auto threads = record.extra.find("pocl_threads"); threads != record.extra.end())
    label += fmt::format(" [{} threads]", scalar_text(*threads));
  return label;
}

std::string machine_line(const Json& machine) {
  auto field = [&](const char* key) -> std::string {
    const auto it = machine.find(key);
    return it == machine.end() ? std::string{} : scalar_text(*it);
  };
  std::vector<std::string> parts;
  if (const auto cpu = field("cpu_model"); !cpu.empty()) {
    std::string text = cpu;
    std::vector<std::string> details;
    if (const auto cores = field("logical_cores"); !cores.empty()) details.push_back(cores + " logical cores");
    if (const auto memory = field("memory_gib"); !memory.empty()) details.push_back(memory + " GiB");
    if (!details.empty()) text += " (" + fmt::format("{}", fmt::join(details, ", ")) + ")";
    parts.push_back(text);
  }
  if (const auto os = field("os"); !os.empty()) parts.push_back(os);
  if (const auto device = field("opencl_device"); !device.empty()) {
    std::string text = "OpenCL device " + device;
    std::vector<std::string> versions;
    if (const auto version = field("opencl_device_version"); !version.empty()) versions.push_back(version);
    if (const auto driver = field("opencl_driver_version"); !driver.empty()) versions.push_back("driver " + driver);
    if (!versions.empty()) text += " (" + fmt::format("{}", fmt::join(versions, ", ")) + ")";
    parts.push_back(text);
  }
  if (const auto threads = field("pocl_max_pthread_count"); !threads.empty())
    parts.push_back("POCL_MAX_PTHREAD_COUNT=" + threads);
  if (const auto compiler = field("compiler"); !compiler.empty()) {
    const auto build = field("build");
    parts.push_back(build.empty() ? compiler : compiler + ", " + build);
  }
  if (const auto date = field("date"); !date.empty()) parts.push_back(date);
  return "**Machine:** " + (parts.empty() ? std::string("not recorded") : fmt::format("{}", fmt::join(parts, "; "))) + "\n";
}

std::string markdown_table(const std::vector<Record>& records, const std::vector<Record>& context) {
  // The baseline of each comparison group: the reference, else the first peer; and the first peer.
  struct Group {
    std::string key;
    const Record* baseline = nullptr;
    const Record* peer = nullptr;
  };
  std::vector<Group> groups;
  for (const auto& record : records) {
    const std::string key = group_key(record);
    auto it = std::find_if(groups.begin(), groups.end(), [&](const Group& g) { return g.key == key; });
    if (it == groups.end()) it = groups.insert(groups.end(), Group{key});
    const bool is_reference = record.impl == kImplReference;
    const bool is_peer = !is_reference && record.impl != kImplOpenCL;
    if (is_reference && (!it->baseline || it->baseline->impl != kImplReference)) it->baseline = &record;
    if (is_peer && !it->baseline) it->baseline = &record;
    if (is_peer && !it->peer) it->peer = &record;
  }
  // A ceiling row's throughput on the record's device: the one its own suite measured, else any
  // suite's. In a run of several suites each measures its own, and the first of any suite put the
  // cluster rows against the primitives suite's FMA peak (25 % where their own said 40 %).
  auto ceiling = [&](const Record& record, const char* case_name, const std::string& impl) -> std::optional<double> {
    for (const bool same_suite : {true, false})
      for (const auto& r : context)
        if (r.case_name == case_name && r.impl == impl && r.device == record.device && r.throughput && (!same_suite || r.suite == record.suite))
          return r.throughput;
    return std::nullopt;
  };
  // Streaming-copy bandwidth per device: the OpenCL copy on a device, the host copy loop on the host.
  auto stream_bandwidth = [&](const Record& record) {
    return ceiling(record, "stream-copy", record.device == kHostDevice ? "std::thread copy loop" : kImplOpenCL);
  };
  // Peak arithmetic per device: the FMA chains of the peak-fma rows (device rows only).
  auto peak_flops = [&](const Record& record) { return ceiling(record, "peak-fma", kImplOpenCL); };
  // `field` per run / median time as a percentage of `ceiling`, or "—".
  auto share = [](const Record& record, const char* field, const std::optional<double>& top) -> std::string {
    const auto value = record.extra.find(field);
    if (value == record.extra.end() || !value->is_number() || record.median_ms <= 0 || !top || *top <= 0) return "—";
    return fmt::format("{:.0f} %", value->get<double>() / (record.median_ms * 1e-3) / *top * 100.0);
  };
  std::vector<std::string> devices;
  for (const auto& record : records)
    if (record.device != kHostDevice && std::find(devices.begin(), devices.end(), record.device) == devices.end())
      devices.push_back(record.device);
  const bool show_device = devices.size() > 1;
  bool show_peer = false, show_bandwidth = false, show_arithmetic = false;
  for (const auto& g : groups) show_peer = show_peer || g.peer;
  for (const auto& record : records) show_bandwidth = show_bandwidth || record.extra.contains("bytes");
  for (const auto& record : records) show_arithmetic = show_arithmetic || record.extra.contains("flops");

  std::vector<std::vector<std::string>> rows;
  for (const auto& record : records) {
    const std::string key = group_key(record);
    const Group& group = *std::find_if(groups.begin(), groups.end(), [&](const Group& g) { return g.key == key; });
    std::string speedup = "—", versus_peer = "—";
    if (group.baseline && record.median_ms > 0) speedup = fmt::format("{:.2f}×", group.baseline->median_ms / record.median_ms);
    if (group.peer && record.median_ms > 0) versus_peer = fmt::format("{:.2f}×", group.peer->median_ms / record.median_ms);
    const std::string bandwidth = share(record, "bytes", stream_bandwidth(record));
    const std::string arithmetic = share(record, "flops", peak_flops(record));
    std::vector<std::string> row{case_label(record), impl_label(record)};
    if (show_device) row.push_back(record.device);
    row.insert(row.end(), {record.size ? fmt::format("{} {}", *record.size, record.size_unit) : "—", format_ms(record.median_ms),
                           format_ms(record.min_ms), format_ms(record.max_ms),
                           record.throughput ? format_throughput(*record.throughput, record.throughput_unit) : "—", speedup});
    if (show_peer) row.push_back(versus_peer);
    if (show_bandwidth) row.push_back(bandwidth);
    if (show_arithmetic) row.push_back(arithmetic);
    row.push_back(record.peak_rss_mb ? fmt::format("{:.0f}", *record.peak_rss_mb) : "—");
    rows.push_back(std::move(row));
  }
  std::vector<std::string> header{"case", "impl"};
  std::vector<bool> right{false, false};
  if (show_device) header.push_back("device"), right.push_back(false);
  for (const char* column : {"size", "median ms", "min ms", "max ms", "throughput", "speedup"}) header.push_back(column), right.push_back(true);
  if (show_peer) header.push_back("vs peer"), right.push_back(true);
  if (show_bandwidth) header.push_back("of stream BW"), right.push_back(true);
  if (show_arithmetic) header.push_back("of peak FLOP/s"), right.push_back(true);
  header.push_back("peak RSS MiB");
  right.push_back(true);
  return render(header, right, rows);
}

std::string markdown_table(const std::vector<Record>& records) { return markdown_table(records, records); }

std::string markdown_report(const Results& results) {
  std::string text = machine_line(results.machine);
  std::vector<std::string> suites;
  for (const auto& record : results.records)
    if (std::find(suites.begin(), suites.end(), record.suite) == suites.end()) suites.push_back(record.suite);
  for (const auto& suite : suites) {
    std::vector<Record> records;
    std::copy_if(results.records.begin(), results.records.end(), std::back_inserter(records),
                 [&](const Record& r) { return r.suite == suite; });
    text += "\n### " + suite + "\n\n" + markdown_table(records, results.records);
  }
  text += "\nspeedup = baseline median / median, where the baseline of a case is its reference, else its first peer; "
          "vs peer = the first peer's median / median; of stream BW = bytes the case must move per run / median time, "
          "as a share of the same device's streaming-copy bandwidth (stream-copy rows); of peak FLOP/s = floating-point "
          "operations the case counts per run / median time, as a share of the same device's FMA throughput (peak-fma "
          "rows, an FMA counting 2).\n";
  return text;
}

}  // namespace splatcl::bench
