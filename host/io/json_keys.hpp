#pragma once
// Closed JSON objects: a key the reader does not know (a typo such as "colour" or "positon") is an
// error naming it, not a silently ignored field that leaves a default in place.
#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "math/vec3.hpp"

namespace splatcl {

// The text of a JSON document splatcl writes or checksums: `indent` spaces per level (-1: one
// line), a byte of a string that is not UTF-8 written as U+FFFD. A file name in another encoding
// (a Latin-1 "café.obj") failed every writer with the library's "invalid UTF-8 byte" message.
std::string json_text(const nlohmann::json& document, int indent = 2);
std::string json_text(const nlohmann::ordered_json& document, int indent = 2);  // keys in their order

// `text` for a one-line error message: control characters (a newline in a JSON key or value)
// written as escapes (\n, \t, \xNN), the rest as it is.
std::string printable(std::string_view text);

// JSON (nlohmann::json or ordered_json) parsed from `text`, refusing a key that appears twice in
// one object: Error "NAME: PATH: key 'K' appears twice in one object" (PATH as "models[2].eps"),
// where the library kept the later value silently. `canonical` maps a key to what it names (batch
// manifests: a parameter's spellings); two keys naming the same give "keys 'A' and 'B' in one object
// name the same parameter". The library's parse errors propagate as its exceptions.
template <class Json>
Json parse_json_once_per_key(std::string_view text, const std::string& name, std::string (*canonical)(const std::string&) = nullptr);

// The first key of `object` that is not one of `known`, printable(); nullopt when every key is
// known or `object` is not an object.
std::optional<std::string> unknown_key(const nlohmann::json& object, std::initializer_list<const char*> known);

// "a, b, c": the known keys for an error message.
std::string key_list(std::initializer_list<const char*> known);

// A JSON number that is finite as a float (1e39 is finite as a double and becomes inf): its value
// in `out`, else false.
bool json_float(const nlohmann::json& value, float& out);

// Field access for a reader of closed JSON objects: every error is one line, `prefix` then the
// field's path and what is wrong ("scene: camera.eye must be an array of 3 numbers").
struct JsonFields {
  std::string prefix;
  [[noreturn]] void fail(const std::string& message) const;
  // object[name]; an error when `object` (at `path`) is not an object or has no such key.
  const nlohmann::json& field(const nlohmann::json& object, const char* name, const std::string& path) const;
  // A finite number.
  float number(const nlohmann::json& value, const std::string& path) const;
  float number_or(const nlohmann::json& object, const char* name, float fallback, const std::string& path) const;
  // An array of 3 finite numbers.
  Vec3 vec3(const nlohmann::json& value, const std::string& path) const;
  // Every key of `object` (at `path`) is one of `known`: a typo names itself, not a silent default.
  void known_keys(const nlohmann::json& object, const std::string& path, std::initializer_list<const char*> known) const;
};

}  // namespace splatcl
