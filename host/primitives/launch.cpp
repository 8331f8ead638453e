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

}  // namespace splatcl::primitives::detail
