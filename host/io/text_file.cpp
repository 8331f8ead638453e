#include "io/text_file.hpp"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "runtime/error.hpp"

namespace splatcl {

std::string read_text_file(const std::string& path, const std::string& what) {
  const std::string name = "cannot read " + (what.empty() ? "" : what + " ") + path + ": ";
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw Error(name + "it is a directory");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(name + std::strerror(errno));
  std::stringstream text;
  text << in.rdbuf();
  if (in.bad()) throw Error(name + "read failed");
  return text.str();
}

}  // namespace splatcl
