#include "io/json_keys.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <string_view>
#include <vector>

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

namespace {

// A SAX pass over the text that only looks for a key given twice in one object; the DOM is parsed
// after it. nlohmann's callback parser (Json::parse with a callback) scans the enclosing container
// for discarded values at the end of every object, so a scene listing 80,000 lights took 12.8 s to
// read (quadratic; 2^20 of them about 30 minutes); this pass and a plain parse are linear.
template <class Json>
struct OncePerKey : nlohmann::json_sax<Json> {
  using Number = typename Json::number_integer_t;
  using Unsigned = typename Json::number_unsigned_t;
  using Float = typename Json::number_float_t;
  using String = typename Json::string_t;
  using Binary = typename Json::binary_t;

  OncePerKey(const std::string& document, std::string (*to_canonical)(const std::string&)) : name(document), canonical(to_canonical) {}

  // The open containers: an object's keys so far (and its latest, which names the value being
  // parsed), an array's count of elements begun; they name where a repeated key lies.
  struct Open {
    bool array = false;
    std::size_t elements = 0;
    std::string key;
    std::vector<std::string> keys;
  };
  const std::string& name;
  std::string (*canonical)(const std::string&);
  std::vector<Open> open;

  std::string where() const {
    std::string path;
    for (std::size_t i = 0; i + 1 < open.size(); ++i) {
      if (open[i].array) {
        path += fmt::format("[{}]", open[i].elements - 1);
      } else {
        if (!path.empty()) path += '.';
        path += printable(open[i].key);
      }
    }
    return path.empty() ? name : fmt::format("{}: {}", name, path);
  }
  bool element() {
    if (!open.empty() && open.back().array) ++open.back().elements;
    return true;
  }
  bool start(bool array) {
    element();
    open.push_back({array, 0, {}, {}});
    return true;
  }
  bool end() {
    if (!open.empty()) open.pop_back();
    return true;
  }
  bool null() override { return element(); }
  bool boolean(bool) override { return element(); }
  bool number_integer(Number) override { return element(); }
  bool number_unsigned(Unsigned) override { return element(); }
  bool number_float(Float, const String&) override { return element(); }
  bool string(String&) override { return element(); }
  bool binary(Binary&) override { return element(); }
  bool start_object(std::size_t) override { return start(false); }
  bool start_array(std::size_t) override { return start(true); }
  bool end_object() override { return end(); }
  bool end_array() override { return end(); }
  bool key(String& key) override {
    if (open.empty()) return true;
    const auto same = [&](const std::string& a, const std::string& b) { return canonical ? canonical(a) == canonical(b) : a == b; };
    for (const std::string& earlier : open.back().keys)
      if (same(earlier, key))
        throw Error(earlier == key ? fmt::format("{}: key '{}' appears twice in one object", where(), printable(key))
                                   : fmt::format("{}: keys '{}' and '{}' in one object name the same parameter", where(), printable(earlier),
                                                 printable(key)));
    open.back().keys.push_back(key);
    open.back().key = key;
    return true;
  }
  // The plain parse below throws the library's error for it.
  bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception&) override { return false; }
};

}  // namespace

template <class Json>
Json parse_json_once_per_key(std::string_view text, const std::string& name, std::string (*canonical)(const std::string&)) {
  OncePerKey<Json> keys(name, canonical);
  Json::sax_parse(text, &keys);
  return Json::parse(text);
}

template nlohmann::json parse_json_once_per_key<nlohmann::json>(std::string_view, const std::string&, std::string (*)(const std::string&));
template nlohmann::ordered_json parse_json_once_per_key<nlohmann::ordered_json>(std::string_view, const std::string&,
                                                                                std::string (*)(const std::string&));

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
