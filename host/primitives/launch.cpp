#include "primitives/launch.hpp"

#include <algorithm>

#include "runtime/error.hpp"
#include "runtime/tuning.hpp"

namespace splatcl::primitives::detail {

LaunchParameters launch_parameters(const Runtime& runtime, Primitive primitive, Shape shape,
                                   const std::optional<LaunchParameters>& given, std::size_t key_bytes, bool with_values) {
  if (given) {
    validate(*given, primitive, shape, runtime.info(), key_bytes, with_values);
    return *given;
  }
  const LaunchParameters parameters = tuned_parameters(runtime, primitive, shape);
  try {
    validate(parameters, primitive, shape, runtime.info(), key_bytes, with_values);
  } catch (const Error& e) {
    throw Error(TuningDatabase::active()->source() + ": " + e.what());
  }
  return parameters;
}

std::size_t cpu_chunk_count(const Runtime& runtime, std::size_t n, const LaunchParameters& parameters) {
  const auto per_unit = static_cast<std::size_t>(parameters.chunks_per_compute_unit);
  const std::size_t most = std::max<std::size_t>(1, std::size_t{runtime.info().compute_units} * per_unit);
  return std::clamp<std::size_t>(n / static_cast<std::size_t>(parameters.min_chunk_items), 1, most);
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
