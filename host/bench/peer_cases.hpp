#pragma once
// The libraries people would otherwise use, measured beside our kernels on the same keys:
// std::sort and std::unique on the host, Boost.Compute sort and unique on the session's device
// (when splatcl was built with the Boost.Compute peer).
#include <cstdint>
#include <vector>

#include "bench/session.hpp"

namespace splatcl::bench {

// The C++ standard library, single-threaded on the host.
inline constexpr const char* kImplStd = "std";

// Sort, remove adjacent duplicates, or both in turn.
enum class PeerWork { Sort, Unique, SortUnique };

// Adds one record per peer under c.name (c.impl and c.on_device are set per peer) for `work` on
// `keys`. Each peer's output must equal `expected`.
void measure_sort_peers(Session& session, Case c, PeerWork work, const std::vector<std::uint32_t>& keys,
                        const std::vector<std::uint32_t>& expected);

}  // namespace splatcl::bench
