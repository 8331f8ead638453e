#pragma once
// The CSM build's parameters, one list for `splatcl csm build` (options --NAME) and `splatcl batch`
// (manifest keys NAME): their defaults, parsing and validation, and their translation into
// BuildOptions and the file encoding.
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "csm/build.hpp"
#include "csm/csm_file.hpp"
#include "io/parameters.hpp"

namespace splatcl::csm {

struct CsmParameters {
  std::uint32_t maps = 4096, res = 128;
  std::string dist = "uniform", order = "zigzag-h", pole = "y", single_hit = "auto";
  std::string capture = to_string(kDefaultCaptureMethod);
  std::string encoding = "plain";
  std::uint32_t batch = 0;  // maps per capture batch; 0: about 8 M samples. Memory only, same file.
  // Hits closer than hit_eps x the bounding sphere's diameter count as one surface (shared edges).
  float hit_eps = kDefaultHitEpsilon;
};
inline constexpr float kMinHitEpsilon = 1e-7f, kMaxHitEpsilon = 1e-2f;

// Every parameter, in the order of `splatcl csm build --help`.
const std::vector<ParameterInfo>& csm_parameters();
// Whether `name` (any spelling, see parameter_key) is one of them.
bool is_csm_parameter(const std::string& name);
// Sets the parameter `name` from a JSON value or text. Throws Error naming it as given for an
// unknown name or a value out of range.
void set_parameter(CsmParameters& params, const std::string& name, const nlohmann::json& value);
// Checks every name and the combination (a map count that fits the distribution and order).
// Throws Error "'KEY': ..." (or "'--KEY': ..." for Spelling::Option) for the first problem.
void validate(const CsmParameters& params, Spelling spelling = Spelling::Key);
// The parameters that determine the .csm file's bytes (all but batch), by key: a run's record,
// and what its parameters checksum is computed from.
nlohmann::json to_json(const CsmParameters& params);

// Validates, then translates.
BuildOptions to_build_options(const CsmParameters& params);
Encoding file_encoding(const CsmParameters& params);

}  // namespace splatcl::csm
