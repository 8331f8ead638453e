#pragma once
// Files embedded at build time by cmake/embed_files.cmake.
#include <map>
#include <string_view>

namespace splatcl {

// kernels/*.cl and kernels/*.h by file name.
const std::map<std::string_view, std::string_view>& embedded_kernels();
// data/*.json by file name.
const std::map<std::string_view, std::string_view>& embedded_data();
// present/shaders/*.glsl and present/shaders/layout.h by file name.
const std::map<std::string_view, std::string_view>& embedded_shaders();

}  // namespace splatcl
