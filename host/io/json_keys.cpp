#include "io/json_keys.hpp"

#include <algorithm>
#include <string_view>

namespace splatcl {

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

}  // namespace splatcl
