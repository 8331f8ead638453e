#pragma once
// The presenter's GLSL 4.50 sources: present/shaders/*.glsl, embedded in the binary at build time
// (cmake/embed_files.cmake) so it needs no source tree. They share present/shaders/layout.h with
// the C++.
#include <string>
#include <string_view>

namespace splatcl::present::shaders {

// The compilable text of `file` (a name in present/shaders): "#version 450 core", then `defines`
// (lines of "#define NAME VALUE"), then the file with its `#include "NAME"` lines replaced by those
// files (each at most once per source). Error for an unknown file.
std::string source(std::string_view file, std::string_view defines = {});

}  // namespace splatcl::present::shaders
