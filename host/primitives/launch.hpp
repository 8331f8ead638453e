#pragma once
// Shared by the primitive drivers: build options and chunk counts from the launch parameters,
// kernel arguments.
#include <cstddef>
#include <optional>
#include <string>

#include "core/device_vector.hpp"
#include "primitives/tuning.hpp"
#include "runtime/opencl.hpp"
#include "runtime/profiling.hpp"
#include "runtime/runtime.hpp"

namespace splatcl::primitives::detail {

// Build options shared by every primitive kernel file: the GPU shape's group size.
inline std::string group_options(const LaunchParameters& parameters) {
  return "-DGROUP_SIZE=" + std::to_string(parameters.group_size);
}

// The parameters a driver runs with: `given`, else the device's tuning record over the defaults;
// validated against the device (Error naming the parameter and the limit otherwise).
LaunchParameters launch_parameters(const Runtime& runtime, Primitive primitive, Shape shape,
                                   const std::optional<LaunchParameters>& given, std::size_t key_bytes = 4,
                                   bool with_values = false);

using splatcl::set_args;

// Chunks for a CPU-shaped launch over n items: up to compute units x chunks_per_compute_unit, but
// none smaller than min_chunk_items (a tiny chunk costs more to launch than to process). At least 1.
std::size_t cpu_chunk_count(const Runtime& runtime, std::size_t n, const LaunchParameters& parameters);

// Where LSD radix pass `pass` of `passes` writes. Each pass reads what the one before wrote; the
// last of several passes writes the caller's buffer, so no copy back is needed: even pass counts go
// caller -> scratch -> caller ..., odd ones caller -> scratch -> spare -> scratch ... -> caller.
// A single pass writes the scratch and the caller copies it back.
enum class RadixTarget { Caller, Scratch, Spare };
constexpr RadixTarget radix_pass_target(unsigned pass, unsigned passes) {
  if (passes > 1 && pass + 1 == passes) return RadixTarget::Caller;
  if (pass % 2 == 0) return RadixTarget::Scratch;
  return passes % 2 == 1 ? RadixTarget::Spare : RadixTarget::Caller;
}

}  // namespace splatcl::primitives::detail
