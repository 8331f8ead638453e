#pragma once
// The models of a batch run and their parameters, from a manifest (JSON or CSV) or a directory of
// meshes. Parameters resolve in layers: built-in defaults (those of `splatcl splats` and
// `splatcl csm build`) < the manifest's "defaults" < options given on the command line < the
// model's own keys. Every value is validated when the manifest is read, so a bad entry stops the
// run before any work with one line naming the file, the entry and the key.
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace splatcl::batch {

// Same names and defaults as `splatcl splats`.
struct SplatParams {
  double eps = 0;             // absolute; 0 = eps_diag times the bounding-box diagonal
  double eps_diag = 0.001;
  unsigned k = 10;
  std::string samples = "vertices";
  int color_tol = 255;
  std::string color_field = "grey";
  unsigned rounds = 5;
  bool clip = false;
};

// Same names and defaults as `splatcl csm build`.
struct CsmParams {
  std::uint32_t maps = 4096, res = 128;
  std::string dist = "uniform", order = "zigzag-h", pole = "y", single_hit = "sphere-exit", encoding = "plain";
};

struct ModelParams {
  SplatParams splats;
  CsmParams csm;
  bool want_splats = true, want_csm = true;  // the "outputs" key
};

// Canonical JSON of the parameters that determine each output (keys sorted, every field present):
// what the parameters checksum of a resumable run is computed from.
nlohmann::json to_json(const SplatParams& params);
nlohmann::json to_json(const CsmParams& params);

// The parameter keys accepted in manifests (and as CSV columns): eps, eps_diag, k, samples,
// color_tol, color_field, rounds, clip, maps, res, dist, order, pole, single_hit, encoding, outputs.
const std::vector<std::string>& parameter_keys();

// Sets one key from a JSON value (a CSV cell arrives as a string and is converted by the key's
// type). Throws Error "'KEY' ..." for an unknown key or a bad value; callers prefix the location.
void apply_parameter(ModelParams& params, const std::string& key, const nlohmann::json& value);

// Checks that the combination is valid (sampling spec, colour field, map count fitting the
// distribution and order, ...). Throws Error describing the first problem.
void validate(const ModelParams& params);

struct ModelEntry {
  std::string id;      // unique; names the outputs: OUTDIR/ID.splats.ply, OUTDIR/ID.csm, ...
  std::string input;   // mesh path (relative paths resolved against the manifest's folder)
  std::string origin;  // where it was declared, for messages: "list.csv:4", "m.json: models[2]"
  ModelParams params;
};

// Reads a manifest: JSON when the name ends in .json, CSV when it ends in .csv. `base` holds the
// built-in defaults; `overrides` (an object of parameter keys) holds the options given on the
// command line. Returns the models sorted by id. Throws Error with one line naming the file (and
// line or entry) for anything wrong.
std::vector<ModelEntry> load_manifest(const std::string& path, const nlohmann::json& overrides = nlohmann::json::object(),
                                      const ModelParams& base = {});
std::vector<ModelEntry> parse_json_manifest(const std::string& text, const std::string& name, const std::string& folder,
                                            const nlohmann::json& overrides = nlohmann::json::object(), const ModelParams& base = {});
std::vector<ModelEntry> parse_csv_manifest(const std::string& text, const std::string& name, const std::string& folder,
                                           const nlohmann::json& overrides = nlohmann::json::object(), const ModelParams& base = {});

// Every OBJ/PLY/OFF/STL file under `folder` (recursively, skipping hidden entries and the folder
// `exclude`, usually the output directory); the id is the relative path without its extension.
std::vector<ModelEntry> scan_directory(const std::string& folder, const std::string& exclude = {},
                                       const nlohmann::json& overrides = nlohmann::json::object(), const ModelParams& base = {});

// Throws Error unless `id` is a usable relative output name: segments of [A-Za-z0-9._-] separated
// by '/', none empty, "." or "..", none starting with '.'.
void check_model_id(const std::string& id);

// A checksum of the whole model list (ids, inputs, parameters): shards of one run share it, so
// `splatcl batch merge` can tell summaries of different runs apart.
std::string manifest_checksum(const std::vector<ModelEntry>& models);

}  // namespace splatcl::batch
