#include "batch/manifest.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "io/checksum.hpp"
#include "io/json_keys.hpp"
#include "io/output_files.hpp"
#include "io/text_file.hpp"
#include "runtime/error.hpp"

namespace splatcl::batch {
namespace {

namespace fs = std::filesystem;

std::string lower(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return text;
}

std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

void set_outputs(ModelParams& params, const nlohmann::json& value) {
  std::vector<std::string> names;
  if (value.is_array()) {
    for (const auto& item : value) {
      if (!item.is_string()) throw Error(fmt::format("'outputs' entries must be \"splats\" or \"csm\", got {}", item.dump()));
      names.push_back(item.get<std::string>());
    }
  } else if (value.is_string()) {
    // Every name between the '+'s, a trailing empty one too (getline dropped it: "splats+" passed).
    const std::string list = value.get<std::string>();
    for (std::size_t from = 0;;) {
      const std::size_t plus = list.find('+', from);
      names.push_back(list.substr(from, plus == std::string::npos ? std::string::npos : plus - from));
      if (plus == std::string::npos) break;
      from = plus + 1;
    }
  } else {
    throw Error(fmt::format("'outputs' must be a list of \"splats\" and \"csm\" (CSV: splats+csm), got {}", value.dump()));
  }
  bool splats = false, csm = false;
  for (const auto& name : names) {
    bool& wanted = name == "splats" ? splats : csm;
    if (name != "splats" && name != "csm") throw Error(fmt::format("'outputs' has unknown output '{}' (one of: splats, csm)", name));
    if (wanted) throw Error(fmt::format("'outputs' names '{}' twice", name));
    wanted = true;
  }
  if (!splats && !csm) throw Error("'outputs' must name at least one of splats, csm");
  params.want_splats = splats;
  params.want_csm = csm;
}

void apply_overrides(ModelParams& params, const nlohmann::json& overrides, const std::string& where) {
  for (const auto& [key, value] : overrides.items()) {
    try {
      apply_parameter(params, key, value);
    } catch (const Error& e) {
      throw Error(where + ": " + e.what());
    }
  }
}

std::string resolve(const std::string& folder, const std::string& path) {
  const fs::path p(path);
  if (p.is_absolute() || folder.empty()) return p.lexically_normal().string();
  return (fs::path(folder) / p).lexically_normal().string();
}

std::string stem_id(const std::string& path) { return fs::path(path).stem().string(); }

// Sorted by id; a repeated id is an error naming both declarations.
std::vector<ModelEntry> finish(std::vector<ModelEntry> models, const std::string& name,
                               const char* remedy = "give one an \"id\"") {
  if (models.empty()) throw Error(name + ": no models");
  std::sort(models.begin(), models.end(), [](const ModelEntry& a, const ModelEntry& b) { return a.id < b.id; });
  for (std::size_t i = 1; i < models.size(); ++i)
    if (models[i].id == models[i - 1].id)
      throw Error(fmt::format("{}: model id '{}' is used twice ({} and {}); {}", models[i].origin, models[i].id, models[i - 1].origin,
                              models[i].origin, remedy));
  return models;
}

ModelEntry checked_entry(ModelEntry entry) {
  try {
    check_model_id(entry.id);
    validate(entry.params);
  } catch (const Error& e) {
    throw Error(fmt::format("{}: {}", entry.where(), e.what()));
  }
  return entry;
}

// One CSV record (RFC 4180 quoting: "a, b" and "" for a quote inside quotes).
std::vector<std::string> csv_fields(const std::string& line, const std::string& where) {
  std::vector<std::string> fields(1);
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') fields.back() += '"', ++i;
      else if (c == '"') quoted = false;
      else fields.back() += c;
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      fields.emplace_back();
    } else {
      fields.back() += c;
    }
  }
  if (quoted) throw Error(where + ": unterminated quote");
  for (auto& f : fields) {
    const auto first = f.find_first_not_of(" \t"), last = f.find_last_not_of(" \t");
    f = first == std::string::npos ? std::string() : f.substr(first, last - first + 1);
  }
  return fields;
}

}  // namespace

const std::vector<std::string>& parameter_keys() {
  static const std::vector<std::string> keys = [] {
    std::vector<std::string> all;
    for (const ParameterInfo& p : splats::splat_parameters()) all.push_back(p.key);
    for (const ParameterInfo& p : csm::csm_parameters()) all.push_back(p.key);
    all.push_back("outputs");
    return all;
  }();
  return keys;
}

void apply_parameter(ModelParams& params, const std::string& name, const nlohmann::json& value, const std::string& folder) {
  const std::string key = parameter_key(name);
  if (key == "outputs") {
    set_outputs(params, value);
  } else if (splats::is_splat_parameter(key)) {
    splats::set_parameter(params.splats, name, value);
    if (key == "texture") params.splats.texture = resolve(folder, params.splats.texture);
  } else if (csm::is_csm_parameter(key)) {
    csm::set_parameter(params.csm, name, value);
  } else {
    throw Error(fmt::format("unknown parameter '{}' (known: id, path, {})", name, joined(parameter_keys())));
  }
}

namespace {

// A JSON manifest spells a boolean parameter true or false and a number as a number: the strings
// "yes", "no", "1" or "10" that a CSV cell or a command-line option may hold are refused there, as
// a typo would be.
void apply_json_parameter(ModelParams& params, const std::string& name, const nlohmann::json& value, const std::string& folder) {
  const std::string key = parameter_key(name);
  for (const auto* list : {&splats::splat_parameters(), &csm::csm_parameters()})
    for (const ParameterInfo& p : *list) {
      if (key != p.key) continue;
      if (p.flag && !value.is_boolean()) throw Error(fmt::format("'{}' must be true or false, got {}", name, shown_value(value)));
      if (p.number && !value.is_number()) throw Error(fmt::format("'{}' must be a number, got {}", name, shown_value(value)));
    }
  apply_parameter(params, name, value, folder);
}

}  // namespace

void validate(const ModelParams& params) {
  if (params.want_splats) splats::validate(params.splats);
  if (params.want_csm) csm::validate(params.csm);
}

namespace {
// The characters of an id's path segments.
bool id_character(char ch) { return std::isalnum(static_cast<unsigned char>(ch)) || ch == '.' || ch == '_' || ch == '-'; }
}  // namespace

void check_model_id(const std::string& id) {
  auto fail = [&](const std::string& why) { throw Error(fmt::format("model id '{}' {}", id, why)); };
  if (id.empty()) fail("is empty");
  std::stringstream parts(id);
  for (std::string part; std::getline(parts, part, '/');) {
    if (part.empty()) fail("has an empty path segment");
    if (part.front() == '.') fail("has a segment starting with '.'");
    for (const char ch : part)
      if (!id_character(ch))
        fail(fmt::format("has the character '{}' (use letters, digits, '.', '_', '-' and '/')",
                         static_cast<unsigned char>(ch) < 0x80 ? printable(std::string(1, ch)) : fmt::format("\\x{:02X}", static_cast<unsigned char>(ch))));
  }
  if (id.back() == '/') fail("ends with '/'");
}

std::vector<ModelEntry> parse_json_manifest(const std::string& text, const std::string& name, const std::string& folder,
                                            const nlohmann::json& overrides, const ModelParams& base) {
  nlohmann::json doc;
  // nlohmann keeps the last of two equal keys in an object: a key given twice, or a parameter under
  // two spellings (eps_diag, eps-diag), is refused instead of one value winning silently.
  try {
    doc = parse_json_once_per_key<nlohmann::json>(text, name, parameter_key);
  } catch (const nlohmann::json::exception& e) {  // parse_error, or out_of_range for a number beyond double
    std::string what = e.what();
    if (const auto at = what.find("] "); what.rfind("[json.exception", 0) == 0 && at != std::string::npos) what = what.substr(at + 2);
    throw Error(fmt::format("{}: not valid JSON: {}", name, what));
  }
  if (!doc.is_object()) throw Error(name + ": expected an object with \"models\" (and optional \"defaults\")");
  for (const auto& [key, value] : doc.items())
    if (key != "models" && key != "defaults") throw Error(fmt::format("{}: unknown top-level key '{}' (known: defaults, models)", name, key));
  if (!doc.contains("models") || !doc["models"].is_array()) throw Error(name + ": \"models\" must be a list");

  ModelParams defaults = base;
  if (doc.contains("defaults")) {
    const auto& d = doc["defaults"];
    if (!d.is_object()) throw Error(name + ": \"defaults\" must be an object");
    for (const auto& [key, value] : d.items()) {
      // A model's own keys: the unknown-parameter message lists them as known, so say why here.
      if (key == "id" || key == "path")
        throw Error(fmt::format("{}: defaults: '{}' names one model; give it in each model's entry, not in the defaults", name, key));
      try {
        apply_json_parameter(defaults, key, value, folder);
      } catch (const Error& e) {
        throw Error(fmt::format("{}: defaults: {}", name, e.what()));
      }
    }
  }
  apply_overrides(defaults, overrides, "command line");

  std::vector<ModelEntry> models;
  const auto& list = doc["models"];
  for (std::size_t i = 0; i < list.size(); ++i) {
    const auto& item = list[i];
    ModelEntry entry;
    entry.origin = fmt::format("{}: models[{}]", name, i);
    entry.params = defaults;
    if (item.is_string()) {
      if (item.get<std::string>().empty()) throw Error(entry.origin + ": empty path");
      entry.input = resolve(folder, item.get<std::string>());
      entry.id = stem_id(entry.input);
    } else if (item.is_object()) {
      // Path and id first, so every later message names the model.
      try {
        if (!item.contains("path")) throw Error("missing \"path\"");
        entry.input = resolve(folder, string_parameter("path", item["path"]));
        entry.id = item.contains("id") ? string_parameter("id", item["id"]) : stem_id(entry.input);
      } catch (const Error& e) {
        throw Error(fmt::format("{}: {}", entry.origin, e.what()));
      }
      for (const auto& [key, value] : item.items()) {
        if (key == "path" || key == "id") continue;
        try {
          apply_json_parameter(entry.params, key, value, folder);
        } catch (const Error& e) {
          throw Error(fmt::format("{}: {}", entry.where(), e.what()));
        }
      }
    } else {
      throw Error(fmt::format("{}: expected a path or an object with \"path\", got {}", entry.origin, item.dump()));
    }
    models.push_back(checked_entry(std::move(entry)));
  }
  return finish(std::move(models), name);
}

std::vector<ModelEntry> parse_csv_manifest(const std::string& text, const std::string& name, const std::string& folder,
                                           const nlohmann::json& overrides, const ModelParams& base) {
  ModelParams defaults = base;
  apply_overrides(defaults, overrides, "command line");
  std::vector<std::string> header;
  std::vector<ModelEntry> models;
  // A UTF-8 byte order mark (spreadsheets write one) is not part of the first column's name.
  std::stringstream lines(text.rfind("\xEF\xBB\xBF", 0) == 0 ? text.substr(3) : text);
  std::size_t number = 0;
  for (std::string line; std::getline(lines, line);) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.find_first_not_of(" \t") == std::string::npos || line[line.find_first_not_of(" \t")] == '#') continue;
    const std::string where = fmt::format("{}:{}", name, number);
    // As a JSON manifest must be: its paths and ids go into the summary's JSON.
    if (!is_utf8(line)) throw Error(where + ": not UTF-8 text");
    auto fields = csv_fields(line, where);
    if (header.empty()) {
      header = std::move(fields);
      bool has_path = false;
      for (std::size_t i = 0; i < header.size(); ++i) {
        const auto& column = header[i];
        if (column == "path") has_path = true;
        else if (column != "id" &&
                 std::find(parameter_keys().begin(), parameter_keys().end(), parameter_key(column)) == parameter_keys().end())
          throw Error(fmt::format("{}: unknown column '{}' (known: id, path, {})", where, column, joined(parameter_keys())));
        // eps_diag and eps-diag name one parameter: the later column used to win silently.
        for (std::size_t j = 0; j < i; ++j)
          if (parameter_key(header[j]) == parameter_key(column))
            throw Error(header[j] == column ? fmt::format("{}: column '{}' appears twice", where, column)
                                            : fmt::format("{}: columns '{}' and '{}' name the same parameter", where, header[j], column));
      }
      if (!has_path) throw Error(where + ": the header has no 'path' column");
      continue;
    }
    if (fields.size() != header.size())
      throw Error(fmt::format("{}: {} fields, but the header has {}", where, fields.size(), header.size()));
    ModelEntry entry;
    entry.origin = where;
    entry.params = defaults;
    // Path and id first, so every later message names the model.
    for (std::size_t i = 0; i < header.size(); ++i) {
      if (header[i] == "path") {
        if (fields[i].empty()) throw Error(where + ": empty path");
        entry.input = resolve(folder, fields[i]);
      } else if (header[i] == "id") {
        entry.id = fields[i];
      }
    }
    if (entry.id.empty()) entry.id = stem_id(entry.input);
    for (std::size_t i = 0; i < header.size(); ++i) {
      if (header[i] == "path" || header[i] == "id" || fields[i].empty()) continue;  // empty cell: the default
      try {
        apply_parameter(entry.params, header[i], fields[i], folder);
      } catch (const Error& e) {
        throw Error(fmt::format("{}: {}", entry.where(), e.what()));
      }
    }
    models.push_back(checked_entry(std::move(entry)));
  }
  if (header.empty()) throw Error(name + ": empty (expected a header line with a 'path' column)");
  return finish(std::move(models), name);
}

std::vector<ModelEntry> load_manifest(const std::string& path, const nlohmann::json& overrides, const ModelParams& base) {
  const std::string extension = lower(fs::path(path).extension().string());
  std::error_code ec;
  if (!fs::exists(path, ec)) throw Error(fmt::format("cannot read manifest {}: No such file or directory", path));
  if (extension != ".json" && extension != ".csv")
    throw Error(fmt::format("cannot tell the manifest format of {}: name it .json or .csv (or pass a directory of meshes)", path));
  const std::string text = read_text_file(path, "manifest");
  const std::string folder = fs::path(path).parent_path().string();
  return extension == ".json" ? parse_json_manifest(text, path, folder, overrides, base)
                              : parse_csv_manifest(text, path, folder, overrides, base);
}

std::vector<ModelEntry> scan_directory(const std::string& folder, const std::string& exclude, const nlohmann::json& overrides,
                                       const ModelParams& base) {
  std::error_code ec;
  if (!fs::is_directory(folder, ec)) throw Error("cannot read directory " + folder + ": it does not exist");
  ModelParams defaults = base;
  apply_overrides(defaults, overrides, "command line");
  // Every model of a directory takes these: a bad combination is the command line's, not the first
  // model's ("../m/cube.obj (cube): 'maps': 1000 is not a perfect square").
  try {
    validate(defaults);
  } catch (const Error& e) {
    throw Error(std::string("command line: ") + e.what());
  }
  const fs::path excluded = exclude.empty() ? fs::path() : fs::weakly_canonical(exclude, ec);
  std::vector<ModelEntry> models;
  fs::recursive_directory_iterator it(folder, fs::directory_options::skip_permission_denied, ec), end;
  if (ec) throw Error("cannot read directory " + folder + ": " + ec.message());
  for (; it != end; it.increment(ec)) {
    if (ec) throw Error("cannot read directory " + folder + ": " + ec.message());
    const fs::path& p = it->path();
    const bool hidden = p.filename().string().front() == '.';
    if (it->is_directory(ec)) {
      if (hidden || (!excluded.empty() && fs::weakly_canonical(p, ec) == excluded)) it.disable_recursion_pending();
      continue;
    }
    const std::string extension = lower(p.extension().string());
    if (hidden || (extension != ".obj" && extension != ".ply" && extension != ".off" && extension != ".stl")) continue;
    // A FIFO or device named like a mesh is no mesh: reading one waited forever, holding the locks.
    if (!it->is_regular_file(ec)) continue;
    ModelEntry entry;
    entry.input = p.lexically_normal().string();
    // A file name's other characters (a space, an accent's bytes) become '_' in its id: "Chair 01.obj"
    // refused the whole directory run.
    entry.id = fs::path(p.lexically_relative(folder)).replace_extension().generic_string();
    for (char& ch : entry.id)
      if (ch != '/' && !id_character(ch)) ch = '_';
    entry.origin = entry.input;
    entry.params = defaults;
    models.push_back(checked_entry(std::move(entry)));
  }
  if (models.empty()) throw Error("no meshes (.obj, .ply, .off, .stl) in " + folder);
  return finish(std::move(models), folder, "list them in a manifest with distinct ids");
}

std::vector<std::pair<std::string, std::string>> ids_differing_in_case_only(const std::vector<ModelEntry>& models) {
  std::map<std::string, std::string> first_of;  // case-folded id -> the first id that folds to it
  std::vector<std::pair<std::string, std::string>> pairs;
  for (const ModelEntry& m : models) {
    std::string folded = m.id;
    std::transform(folded.begin(), folded.end(), folded.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    const auto [it, fresh] = first_of.emplace(folded, m.id);
    if (!fresh) pairs.emplace_back(it->second, m.id);
  }
  return pairs;
}

std::string manifest_checksum(const std::vector<ModelEntry>& models) {
  // Paths as the files they name: resolved against the manifest's folder as it was typed, the same
  // manifest run as man/set.json in one shard and as /abs/man/set.json (or from another working
  // directory) in another gave other checksums, and merge refused the shards of one run.
  const auto as_file = [](const std::string& path) { return path.empty() ? path : comparable_path(path).string(); };
  std::vector<const ModelEntry*> sorted;
  for (const auto& m : models) sorted.push_back(&m);
  std::sort(sorted.begin(), sorted.end(), [](const ModelEntry* a, const ModelEntry* b) { return a->id < b->id; });
  nlohmann::json all = nlohmann::json::array();
  for (const ModelEntry* m : sorted) {
    splats::SplatParameters splat_params = m->params.splats;
    splat_params.texture = as_file(splat_params.texture);
    all.push_back({m->id, as_file(m->input), m->params.want_splats ? splats::to_json(splat_params) : nlohmann::json(),
                   m->params.want_csm ? csm::to_json(m->params.csm) : nlohmann::json()});
  }
  return checksum_of(json_text(all, -1));
}

}  // namespace splatcl::batch
