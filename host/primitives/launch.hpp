#pragma once
// Shared by the primitive drivers: GPU-shape group size, chunk counts for the CPU shape, kernel
// arguments and scratch buffers.
#include <cstddef>
#include <string>

#include "runtime/opencl.hpp"
#include "runtime/profiling.hpp"
#include "runtime/runtime.hpp"

namespace splatcl::primitives::detail {

// Work-group size of every GPU-shaped primitive kernel (a multiple of 8, fits any OpenCL device).
inline constexpr std::size_t kGroupSize = 256;

// Build options shared by every primitive kernel file.
inline std::string group_options() { return "-DGROUP_SIZE=" + std::to_string(kGroupSize); }

using splatcl::set_args;

// Chunks for a CPU-shaped launch over n items: up to runtime.cpu_chunks(), but none smaller than
// min_chunk items (a tiny chunk costs more to launch than to process). At least 1.
std::size_t cpu_chunk_count(const Runtime& runtime, std::size_t n, std::size_t min_chunk);

// Size of a buffer in bytes; 0 for a buffer that was never allocated.
std::size_t buffer_bytes(const cl::Buffer& buffer);

// Reallocates `buffer` (contents not kept) when it holds fewer than `bytes`.
void ensure_bytes(Runtime& runtime, cl::Buffer& buffer, std::size_t bytes, const char* what);

// Throws Error naming `what` when `buffer` holds fewer than `bytes`.
void require_bytes(const cl::Buffer& buffer, std::size_t bytes, const char* what);

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
