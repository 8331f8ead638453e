#include "io/json_keys.hpp"

#include <algorithm>
#include <string_view>

namespace splatcl {

std::optional<std::string> unknown_key(const nlohmann::json& object, std::initializer_list<const char*> known) {
  if (!object.is_object()) return std::nullopt;
  for (const auto& item : object.items())
    if (std::none_of(known.begin(), known.end(), [&](const char* k) { return item.key() == std::string_view(k); })) return item.key();
  return std::nullopt;
}

std::string key_list(std::initializer_list<const char*> known) {
  std::string list;
  for (const char* k : known) list += (list.empty() ? "" : ", ") + std::string(k);
  return list;
}

}  // namespace splatcl
