#include "io/json_keys.hpp"

#include <algorithm>
#include <cmath>
#include <string_view>

#include "runtime/error.hpp"

namespace splatcl {

std::string json_text(const nlohmann::json& document, int indent) {
  return document.dump(indent, ' ', false, nlohmann::json::error_handler_t::replace);
}

std::string json_text(const nlohmann::ordered_json& document, int indent) {
  return document.dump(indent, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
}

std::string printable(std::string_view text) {
  static constexpr char kHex[] = "0123456789abcdef";
  std::string out;
  for (const char ch : text) {
    const auto c = static_cast<unsigned char>(ch);
    if (c == '\n') out += "\\n";
    else if (c == '\t') out += "\\t";
    else if (c == '\r') out += "\\r";
    else if (c < 0x20 || c == 0x7f) out += std::string("\\x") + kHex[c >> 4] + kHex[c & 15];
    else out += ch;
  }
  return out;
}

std::optional<std::string> unknown_key(const nlohmann::json& object, std::initializer_list<const char*> known) {
  if (!object.is_object()) return std::nullopt;
  for (const auto& item : object.items())
    if (std::none_of(known.begin(), known.end(), [&](const char* k) { return item.key() == std::string_view(k); })) return printable(item.key());
  return std::nullopt;
}

std::string key_list(std::initializer_list<const char*> known) {
  std::string list;
  for (const char* k : known) list += (list.empty() ? "" : ", ") + std::string(k);
  return list;
}

void JsonFields::fail(const std::string& message) const { throw Error(prefix + message); }

const nlohmann::json& JsonFields::field(const nlohmann::json& object, const char* name, const std::string& path) const {
  if (!object.is_object()) fail(path + " must be an object");
  const auto it = object.find(name);
  if (it == object.end()) fail(path + " is missing '" + name + "'");
  return *it;
}

bool json_float(const nlohmann::json& value, float& out) {
  if (!value.is_number()) return false;
  out = value.get<float>();
  return std::isfinite(out);
}

float JsonFields::number(const nlohmann::json& value, const std::string& path) const {
  if (!value.is_number()) fail(path + " must be a number");
  float v = 0;
  if (!json_float(value, v))
    fail(path + (std::isfinite(value.get<double>()) ? " is beyond float range (at most 3.4e38)" : " must be finite"));
  return v;
}

float JsonFields::number_or(const nlohmann::json& object, const char* name, float fallback, const std::string& path) const {
  return object.contains(name) ? number(object[name], path + "." + name) : fallback;
}

Vec3 JsonFields::vec3(const nlohmann::json& value, const std::string& path) const {
  if (!value.is_array() || value.size() != 3) fail(path + " must be an array of 3 numbers");
  return {number(value[0], path + "[0]"), number(value[1], path + "[1]"), number(value[2], path + "[2]")};
}

void JsonFields::known_keys(const nlohmann::json& object, const std::string& path,
                            std::initializer_list<const char*> known) const {
  if (const auto key = unknown_key(object, known)) fail("unknown key '" + *key + "' in " + path + " (known: " + key_list(known) + ")");
}

}  // namespace splatcl
