#include "bench/csv.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <fstream>
#include <sstream>
#include <string_view>

#include "io/atomic_file.hpp"
#include "io/json_keys.hpp"
#include "io/text_file.hpp"
#include "runtime/error.hpp"

namespace splatcl::bench {
namespace {

const char* const kColumns[] = {"suite",     "case",       "impl",       "device",     "size",           "size_unit",  "runs",
                                "median_ms", "min_ms",     "max_ms",     "throughput", "throughput_unit", "peak_rss_mb"};

std::string quoted(const std::string& cell) {
  if (cell.find_first_of(",\"\r\n") == std::string::npos) return cell;
  std::string out = "\"";
  for (char c : cell) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + "\"";
}

// Shortest text that reads back as the same double.
std::string number(double value) { return fmt::format("{}", value); }

std::string extra_cell(const Json& value) { return value.is_string() ? value.get<std::string>() : value.dump(); }

// RFC 4180 rows; quoted cells may hold line breaks.
std::vector<std::vector<std::string>> parse_rows(const std::string& text) {
  std::vector<std::vector<std::string>> rows;
  std::vector<std::string> row;
  std::string cell;
  bool in_quotes = false, row_started = false;
  std::size_t line = 1;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_quotes) {
      if (c == '"' && i + 1 < text.size() && text[i + 1] == '"') {
        cell += '"';
        ++i;
      } else if (c == '"') {
        in_quotes = false;
      } else {
        if (c == '\n') ++line;
        cell += c;
      }
      continue;
    }
    if (c == '"') {
      if (!cell.empty()) throw Error("line " + std::to_string(line) + ": quote inside an unquoted cell");
      in_quotes = true;
      row_started = true;
    } else if (c == ',') {
      row.push_back(std::move(cell));
      cell.clear();
      row_started = true;
    } else if (c == '\n' || c == '\r') {
      if (c == '\r' && i + 1 < text.size() && text[i + 1] == '\n') ++i;
      if (row_started || !cell.empty()) {
        row.push_back(std::move(cell));
        rows.push_back(std::move(row));
      }
      row.clear();
      cell.clear();
      row_started = false;
      ++line;
    } else {
      cell += c;
      row_started = true;
    }
  }
  if (in_quotes) throw Error("line " + std::to_string(line) + ": unterminated quoted cell");
  if (row_started || !cell.empty()) {
    row.push_back(std::move(cell));
    rows.push_back(std::move(row));
  }
  return rows;
}

Json extra_value(const std::string& cell) {
  try {
    Json value = Json::parse(cell);
    if (!value.is_string() && !value.is_null()) return value;
  } catch (const nlohmann::json::exception&) {
    // Not JSON: the text itself.
  }
  return cell;
}

}  // namespace

std::string to_csv(const Results& results) {
  std::vector<std::string> extras;
  for (const auto& record : results.records)
    for (const auto& [key, value] : record.extra.items())
      if (std::find(extras.begin(), extras.end(), key) == extras.end()) extras.push_back(key);

  std::string text;
  auto append_row = [&](const std::vector<std::string>& cells) {
    for (std::size_t k = 0; k < cells.size(); ++k) {
      if (k) text += ',';
      text += quoted(cells[k]);
    }
    text += "\n";
  };
  std::vector<std::string> header(std::begin(kColumns), std::end(kColumns));
  header.insert(header.end(), extras.begin(), extras.end());
  append_row(header);
  for (const auto& r : results.records) {
    std::vector<std::string> cells = {r.suite,
                                      r.case_name,
                                      r.impl,
                                      r.device,
                                      r.size ? std::to_string(*r.size) : "",
                                      r.size ? r.size_unit : "",
                                      std::to_string(r.runs),
                                      number(r.median_ms),
                                      number(r.min_ms),
                                      number(r.max_ms),
                                      r.throughput ? number(*r.throughput) : "",
                                      r.throughput ? r.throughput_unit : "",
                                      r.peak_rss_mb ? number(*r.peak_rss_mb) : ""};
    for (const auto& key : extras) {
      const auto it = r.extra.find(key);
      cells.push_back(it == r.extra.end() ? "" : extra_cell(*it));
    }
    append_row(cells);
  }
  return text;
}

Results results_from_csv(const std::string& text) {
  // As JSON results must be (and --json could not write it otherwise).
  if (!is_utf8(text)) throw Error("not UTF-8 text");
  // A spreadsheet's UTF-8 byte-order mark before the header read as "not a benchmark CSV".
  const std::string_view body = std::string_view(text).starts_with("\xEF\xBB\xBF") ? std::string_view(text).substr(3) : std::string_view(text);
  const auto rows = parse_rows(std::string(body));
  if (rows.empty()) throw Error("empty CSV: expected a header row");
  const auto& header = rows.front();
  const std::size_t fixed = std::size(kColumns);
  if (header.size() < fixed || !std::equal(std::begin(kColumns), std::end(kColumns), header.begin()))
    throw Error("not a benchmark CSV: the header must start with suite,case,impl,device,...");
  // A column named twice: the later cell won (it read as "times must be finite..." when a fixed
  // column repeated).
  for (std::size_t c = 0; c < header.size(); ++c)
    for (std::size_t d = 0; d < c; ++d)
      if (header[c] == header[d]) throw Error(fmt::format("column '{}' appears twice in the header", printable(header[c])));
  Results results;
  for (std::size_t r = 1; r < rows.size(); ++r) {
    const auto& row = rows[r];
    if (row.size() != header.size())
      throw Error("row " + std::to_string(r + 1) + ": " + std::to_string(row.size()) + " cells, the header has " +
                  std::to_string(header.size()));
    // Through the JSON record reader, so both formats validate the same way.
    Json json = Json::object();
    for (std::size_t c = 0; c < fixed; ++c) {
      const std::string& cell = row[c];
      if (cell.empty()) continue;
      const std::string key = header[c];
      const bool text_field = key == "suite" || key == "case" || key == "impl" || key == "device" || key == "size_unit" ||
                              key == "throughput_unit";
      if (text_field) {
        json[key] = cell;
        continue;
      }
      try {
        std::size_t used = 0;
        if (key == "size" || key == "runs") {
          const unsigned long long value = std::stoull(cell, &used);
          if (used != cell.size()) throw std::invalid_argument(cell);
          json[key] = static_cast<std::uint64_t>(value);
        } else {
          const double value = std::stod(cell, &used);
          if (used != cell.size()) throw std::invalid_argument(cell);
          json[key] = value;
        }
      } catch (const std::exception&) {
        throw Error("row " + std::to_string(r + 1) + ": field '" + key + "' is not a number: '" + cell + "'");
      }
    }
    for (std::size_t c = fixed; c < header.size(); ++c)
      if (!row[c].empty()) json[header[c]] = extra_value(row[c]);
    try {
      results.records.push_back(record_from_json(json));
    } catch (const Error& e) {
      throw Error("row " + std::to_string(r + 1) + ": " + e.what());
    }
  }
  return results;
}

void write_csv(const std::string& path, const Results& results) { write_file_atomically(path, to_csv(results)); }

Results read_csv(const std::string& path) {
  const std::string text = read_text_file(path, "results");
  try {
    return results_from_csv(text);
  } catch (const Error& e) {
    throw Error(path + ": " + e.what());
  }
}

}  // namespace splatcl::bench
