#include "io/parameters.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cstdlib>

#include "io/json_keys.hpp"
#include "runtime/error.hpp"

namespace splatcl {

std::string parameter_key(const std::string& name) {
  std::string key = name.substr(std::min(name.find_first_not_of('-'), name.size()));
  std::replace(key.begin(), key.end(), '-', '_');
  return key;
}

std::string option_name(const std::string& key) {
  std::string option = "--" + key;
  std::replace(option.begin(), option.end(), '_', '-');
  return option;
}

std::string spelled(const std::string& key, Spelling spelling) {
  return "'" + (spelling == Spelling::Option ? option_name(key) : key) + "'";
}

std::string shown_value(const nlohmann::json& value) {
  return value.is_string() ? fmt::format("'{}'", printable(value.get<std::string>())) : value.dump();
}

double number_parameter(const std::string& name, const nlohmann::json& value) {
  if (value.is_number()) return value.get<double>();
  if (value.is_string()) {
    const std::string text = value.get<std::string>();
    char* end = nullptr;
    errno = 0;
    const double parsed = std::strtod(text.c_str(), &end);
    if (!text.empty() && end == text.c_str() + text.size() && errno == 0) return parsed;
  }
  throw Error(fmt::format("'{}' must be a number, got {}", name, shown_value(value)));
}

long long integer_parameter(const std::string& name, const nlohmann::json& value, long long low, long long high) {
  long long parsed = 0;
  bool ok = false;
  if (value.is_number_integer()) {
    parsed = value.get<long long>();
    ok = true;
  } else if (value.is_string()) {
    const std::string text = value.get<std::string>();
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), parsed);
    ok = !text.empty() && ec == std::errc() && end == text.data() + text.size();
  }
  if (!ok || parsed < low || parsed > high)
    throw Error(fmt::format("'{}' must be an integer from {} to {}, got {}", name, low, high, shown_value(value)));
  return parsed;
}

std::string string_parameter(const std::string& name, const nlohmann::json& value) {
  if (!value.is_string() || value.get<std::string>().empty())
    throw Error(fmt::format("'{}' must be a non-empty string, got {}", name, shown_value(value)));
  return value.get<std::string>();
}

bool bool_parameter(const std::string& name, const nlohmann::json& value) {
  if (value.is_boolean()) return value.get<bool>();
  if (value.is_string()) {
    std::string text = value.get<std::string>();
    std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (text == "true" || text == "yes" || text == "1") return true;
    if (text == "false" || text == "no" || text == "0") return false;
  }
  throw Error(fmt::format("'{}' must be true or false, got {}", name, shown_value(value)));
}

}  // namespace splatcl
