#pragma once
// The ceilings the kernels are measured against. Streaming copy bandwidth, the physical limit of
// memory-bound kernels: a STREAM-style copy on the host over all cores and the same copy as an
// OpenCL kernel on the session's device; throughput is bytes read plus bytes written per second, as
// STREAM counts it. Peak arithmetic, the limit of compute-bound ones: independent single-precision
// FMA chains on the device, in flop/s (an FMA counts 2).
#include <cstddef>

#include "bench/session.hpp"

namespace splatcl::bench {

// Large enough that no cache holds it.
inline constexpr std::size_t kStreamArrayBytes = std::size_t{256} << 20;
// --quick runs: still larger than the caches of small machines, but fast.
inline constexpr std::size_t kQuickStreamArrayBytes = std::size_t{32} << 20;
// On a simulated device (Oclgrind) the device copy only checks the kernel.
inline constexpr std::size_t kSimulatorStreamArrayBytes = std::size_t{1} << 20;

inline constexpr const char* kCaseStreamCopy = "stream-copy";
// Element loop with ordinary stores, as kernels write memory.
inline constexpr const char* kImplHostCopyLoop = "std::thread copy loop";
// memcpy, which switches to non-temporal stores for large copies and so skips the read-for-ownership
// of the destination: the ceiling for code that can use them.
inline constexpr const char* kImplHostMemcpy = "std::thread memcpy";

inline constexpr const char* kCasePeakFma = "peak-fma";

// Measures the host loop, host memcpy and OpenCL copy of `array_bytes` (rounded down to 16 bytes),
// adding one record each under case "stream-copy" with size = bytes read + bytes written per run,
// and the device's FMA throughput (case "peak-fma", size in flop; smaller with --quick). Does
// nothing when the session's options say the ceilings are measured at another size step.
void measure_ceilings(Session& session, std::size_t array_bytes = kStreamArrayBytes);

}  // namespace splatcl::bench
