#pragma once
// Named build parameters, given as JSON values (batch manifests) or as text (CSV cells, command-line
// options). Each stage lists its parameters once (splats/pipeline_options.hpp,
// csm/build_options.hpp); `splatcl splats`, `splatcl csm build` and `splatcl batch` all parse them
// with these converters, so a parameter has one name, one range and one meaning everywhere.
#include <string>

#include <nlohmann/json.hpp>

namespace splatcl {

struct ParameterInfo {
  const char* key;     // manifest key and CSV column, "eps_diag"; the option is "--eps-diag"
  const char* help;    // one line, for --help
  bool flag = false;   // true/false; a flag without a value on the command line
  bool path = false;   // a file path: a manifest's relative paths are resolved against its folder
  bool number = false; // a number: a JSON manifest must give it as one ("k": 10, not "k": "10")
};

// The key of a parameter named in any spelling: "--eps-diag", "eps-diag" and "eps_diag" all give
// "eps_diag".
std::string parameter_key(const std::string& name);
// "eps_diag" → "--eps-diag".
std::string option_name(const std::string& key);

// How a message names a parameter, quoted as set_parameter's errors name it as given: as a manifest
// names it ('eps_diag') or as the command line does ('--eps-diag').
enum class Spelling { Key, Option };
std::string spelled(const std::string& key, Spelling spelling);

// A value as a manifest would spell it, for messages: 'text' or the JSON.
std::string shown_value(const nlohmann::json& value);

// Conversions of one parameter's value; strings are parsed by the parameter's type. Errors name the
// parameter as it was given: "'k' must be an integer from 1 to 1024, got 'zero'".
double number_parameter(const std::string& name, const nlohmann::json& value);
long long integer_parameter(const std::string& name, const nlohmann::json& value, long long low, long long high);
std::string string_parameter(const std::string& name, const nlohmann::json& value);  // non-empty
bool bool_parameter(const std::string& name, const nlohmann::json& value);           // true/false, yes/no, 1/0

}  // namespace splatcl
