#pragma once
// Closed JSON objects: a key the reader does not know (a typo such as "colour" or "positon") is an
// error naming it, not a silently ignored field that leaves a default in place.
#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

namespace splatcl {

// `text` for a one-line error message: control characters (a newline in a JSON key or value)
// written as escapes (\n, \t, \xNN), the rest as it is.
std::string printable(std::string_view text);

// The first key of `object` that is not one of `known`, printable(); nullopt when every key is
// known or `object` is not an object.
std::optional<std::string> unknown_key(const nlohmann::json& object, std::initializer_list<const char*> known);

// "a, b, c": the known keys for an error message.
std::string key_list(std::initializer_list<const char*> known);

}  // namespace splatcl
