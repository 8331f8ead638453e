#pragma once
// Closed JSON objects: a key the reader does not know (a typo such as "colour" or "positon") is an
// error naming it, not a silently ignored field that leaves a default in place.
#include <initializer_list>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

namespace splatcl {

// The first key of `object` that is not one of `known`; nullopt when every key is known or
// `object` is not an object.
std::optional<std::string> unknown_key(const nlohmann::json& object, std::initializer_list<const char*> known);

// "a, b, c": the known keys for an error message.
std::string key_list(std::initializer_list<const char*> known);

}  // namespace splatcl
