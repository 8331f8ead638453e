#include "present/shaders.hpp"

#include <set>

#include "runtime/embedded.hpp"
#include "runtime/error.hpp"

namespace splatcl::present::shaders {
namespace {

std::string_view embedded(std::string_view file) {
  const auto& table = embedded_shaders();
  const auto found = table.find(file);
  if (found == table.end()) throw Error("no embedded shader '" + std::string(file) + "'");
  return found->second;
}

void expand(std::string_view file, std::set<std::string_view>& included, std::string& out) {
  if (!included.insert(file).second) return;
  const std::string_view text = embedded(file);
  constexpr std::string_view kInclude = "#include \"";
  std::size_t at = 0;
  while (at < text.size()) {
    std::size_t end = text.find('\n', at);
    end = end == std::string_view::npos ? text.size() : end + 1;
    const std::string_view line = text.substr(at, end - at);
    if (line.starts_with(kInclude)) {
      const std::size_t close = line.find('"', kInclude.size());
      if (close == std::string_view::npos) throw Error("shader '" + std::string(file) + "': unterminated #include");
      expand(line.substr(kInclude.size(), close - kInclude.size()), included, out);
    } else {
      out += line;
    }
    at = end;
  }
}

}  // namespace

std::string source(std::string_view file, std::string_view defines) {
  std::string out = "#version 450 core\n";
  out += defines;
  std::set<std::string_view> included;
  expand(file, included, out);
  return out;
}

}  // namespace splatcl::present::shaders
