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

#include "csm/build_options.hpp"
#include "splats/pipeline_options.hpp"

namespace splatcl::batch {

// A model's parameters: those of `splatcl splats` and `splatcl csm build`, with the same names
// (manifest key eps_diag = option --eps-diag), defaults and meaning, from the stages' own lists.
struct ModelParams {
  splats::SplatParameters splats;
  csm::CsmParameters csm;
  bool want_splats = true, want_csm = true;  // the "outputs" key
};

// The parameter keys accepted in manifests (and as CSV columns): every splat parameter, every CSM
// parameter, and outputs.
const std::vector<std::string>& parameter_keys();

// Sets one parameter from a JSON value (a CSV cell or a command-line option arrives as a string
// and is converted by the parameter's type). `name` may be spelled eps_diag, eps-diag or --eps-diag.
// A relative path value (texture) is resolved against `folder` (the manifest's; empty: as given).
// Throws Error "'NAME' ..." or "unknown parameter 'NAME' (known: ...)"; callers prefix the location.
void apply_parameter(ModelParams& params, const std::string& name, const nlohmann::json& value, const std::string& folder = {});

// Checks the parameters of the wanted outputs (sampling spec, colour field, map count fitting the
// distribution and order, ...). Throws Error describing the first problem.
void validate(const ModelParams& params);

struct ModelEntry {
  std::string id;      // unique; names the outputs: OUTDIR/ID.splats.ply, OUTDIR/ID.csm, ...
  std::string input;   // mesh path (relative paths resolved against the manifest's folder)
  std::string origin;  // where it was declared, for messages: "list.csv:4", "m.json: models[2]"
  // The origin with the model's id, as error messages name a model: "m.json: models[2] (bunny)".
  std::string where() const { return origin + " (" + id + ")"; }
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

// Ids that differ only in letter case ("Chair" and "chair"), as pairs: on a case-insensitive file
// system (macOS, Windows, an SMB share) their outputs are the same files.
std::vector<std::pair<std::string, std::string>> ids_differing_in_case_only(const std::vector<ModelEntry>& models);

// A checksum of the whole model list (ids, inputs, parameters): shards of one run share it, so
// `splatcl batch merge` can tell summaries of different runs apart.
std::string manifest_checksum(const std::vector<ModelEntry>& models);

}  // namespace splatcl::batch
