#include "io/image_codec.hpp"

#include <dlfcn.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <cstdio>
#include <filesystem>
#include <mutex>
#include <system_error>

#include "io/oiio/oiio_module.h"
#include "runtime/error.hpp"

namespace splatcl {
namespace {

constexpr const char* kModuleName = "libsplatcl_oiio.so";

struct Module {
  decltype(&splatcl_oiio_encode_rgb) encode = nullptr;
  decltype(&splatcl_oiio_decode_u8) decode = nullptr;
  std::string failure;  // why it could not be loaded
};

std::filesystem::path executable_directory() {
  std::error_code error;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", error);
  return error ? std::filesystem::path() : self.parent_path();
}

Module load_module() {
  Module module;
  std::vector<std::string> candidates;
  if (const char* named = std::getenv("SPLATCL_OIIO_MODULE"); named && *named) {
    candidates.push_back(named);
  } else {
    const std::filesystem::path here = executable_directory();
    if (!here.empty()) {
      candidates.push_back((here / kModuleName).string());                            // the build tree
      candidates.push_back((here / ".." / kModuleName).string());                     // its tests/
      candidates.push_back((here / ".." / "lib" / "splatcl" / kModuleName).string());  // an install
    }
    candidates.push_back(kModuleName);  // the library search path
  }
  void* handle = nullptr;
  for (const std::string& path : candidates) {
    if (path.find('/') != std::string::npos && access(path.c_str(), R_OK) != 0) {
      if (candidates.size() == 1) module.failure = path + ": no such file";
      continue;
    }
    if ((handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL))) break;
    module.failure = dlerror();
  }
  if (!handle) {
    // Appended, not `std::string(kModuleName) + "..."`: GCC 12 warns falsely (-Warray-bounds) on that.
    if (module.failure.empty()) (module.failure = kModuleName) += " not found beside the executable or in ../lib/splatcl";
    module.failure = "the image module is missing (" + module.failure + "; set SPLATCL_OIIO_MODULE to its path)";
    return module;
  }
  module.encode = reinterpret_cast<decltype(module.encode)>(dlsym(handle, "splatcl_oiio_encode_rgb"));
  module.decode = reinterpret_cast<decltype(module.decode)>(dlsym(handle, "splatcl_oiio_decode_u8"));
  if (!module.encode || !module.decode) module.failure = "the image module lacks its entry points";
  return module;
}

const Module& module() {
  static std::once_flag once;
  static Module loaded;
  std::call_once(once, [] { loaded = load_module(); });
  return loaded;
}

}  // namespace

void check_image_module(const std::string& path, const std::string& prefix) {
  std::string extension = std::filesystem::path(path).extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  static constexpr std::array<const char*, 8> kImages = {".png", ".exr", ".hdr", ".jpg", ".jpeg", ".tif", ".tiff", ".bmp"};
  if (std::none_of(kImages.begin(), kImages.end(), [&](const char* e) { return extension == e; })) return;
  if (const Module& m = module(); !m.failure.empty()) throw Error(prefix + m.failure);
}

std::vector<unsigned char> encode_image_rgb(const std::string& path, int width, int height, const std::vector<float>& rgb) {
  const Module& m = module();
  if (!m.failure.empty()) throw Error("cannot write " + path + ": " + m.failure);
  std::vector<unsigned char> encoded;
  std::array<char, 512> error{};
  const auto append = [](void* sink, const unsigned char* bytes, size_t size) {
    auto& out = *static_cast<std::vector<unsigned char>*>(sink);
    out.insert(out.end(), bytes, bytes + size);
  };
  if (m.encode(path.c_str(), width, height, rgb.data(), &encoded, append, error.data(), error.size()) != 0)
    throw Error("cannot write " + path + ": " + error.data());
  return encoded;
}

DecodedImage decode_image_u8(const std::string& path, const std::string& what) {
  const Module& m = module();
  if (!m.failure.empty()) throw Error("cannot read " + what + " " + path + ": " + m.failure);
  // The file's own cause first: the module's reader called a folder "no format reader for it".
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw Error("cannot read " + what + " " + path + ": it is a directory");
  if (std::FILE* file = std::fopen(path.c_str(), "rb")) {
    std::fclose(file);
  } else {
    const int cause = errno;  // at once, and by the thread-safe category (batch decodes in parallel)
    throw Error("cannot read " + what + " " + path + ": " + std::generic_category().message(cause));
  }
  DecodedImage image;
  std::array<char, 512> error{};
  const auto allocate = [](void* sink, int width, int height, int channels) {
    auto& out = *static_cast<DecodedImage*>(sink);
    out.width = width, out.height = height, out.channels = channels;
    out.pixels.resize(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * static_cast<std::size_t>(channels));
    return out.pixels.data();
  };
  if (m.decode(path.c_str(), &image, allocate, error.data(), error.size()) != 0)
    throw Error("cannot read " + what + " " + path + ": " + error.data());
  return image;
}

}  // namespace splatcl
