#pragma once
// Reading a whole input file (a scene, a manifest, a summary, a CSV) with errors that name the
// real cause: a directory is "it is a directory", a missing file "No such file or directory".
#include <string>
#include <string_view>

namespace splatcl {

// The bytes of `path`. Throws Error "cannot read WHAT PATH: CAUSE" (what: "scene", "manifest", ...;
// empty: "cannot read PATH: CAUSE").
std::string read_text_file(const std::string& path, const std::string& what);

// Whether `text` is well-formed UTF-8 (no overlong forms, surrogates or code points beyond
// U+10FFFF), as the JSON reader requires of JSON text: the CSV readers refuse what it would.
bool is_utf8(std::string_view text);

}  // namespace splatcl
