#pragma once
// Appending plain values to a byte string in the machine's (little-endian) layout, for the binary
// PLY writers.
#include <cstring>
#include <string>
#include <type_traits>

namespace splatcl {

template <class T>
void append_bytes(std::string& out, T value) {
  static_assert(std::is_trivially_copyable_v<T>);
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  out.append(bytes, sizeof(T));
}

}  // namespace splatcl
