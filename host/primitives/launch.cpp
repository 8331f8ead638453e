#include "primitives/launch.hpp"

#include <algorithm>

#include "runtime/error.hpp"

namespace splatcl::primitives::detail {

std::size_t cpu_chunk_count(const Runtime& runtime, std::size_t n, std::size_t min_chunk) {
  return std::clamp<std::size_t>(n / min_chunk, 1, runtime.cpu_chunks());
}

std::size_t buffer_bytes(const cl::Buffer& buffer) { return buffer() ? buffer.getInfo<CL_MEM_SIZE>() : 0; }

void ensure_bytes(Runtime& runtime, cl::Buffer& buffer, std::size_t bytes, const char* what) {
  if (buffer_bytes(buffer) < bytes) buffer = runtime.buffer(CL_MEM_READ_WRITE, bytes, what);
}

void require_bytes(const cl::Buffer& buffer, std::size_t bytes, const char* what) {
  const std::size_t held = buffer_bytes(buffer);
  if (held < bytes)
    throw Error(std::string(what) + ": buffer holds " + std::to_string(held) + " bytes, " + std::to_string(bytes) +
                " needed");
}

}  // namespace splatcl::primitives::detail
