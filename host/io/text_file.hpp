#pragma once
// Reading a whole input file (a scene, a manifest, a summary, a CSV) with errors that name the
// real cause: a directory is "it is a directory", a missing file "No such file or directory".
#include <string>

namespace splatcl {

// The bytes of `path`. Throws Error "cannot read WHAT PATH: CAUSE" (what: "scene", "manifest", ...;
// empty: "cannot read PATH: CAUSE").
std::string read_text_file(const std::string& path, const std::string& what);

}  // namespace splatcl
