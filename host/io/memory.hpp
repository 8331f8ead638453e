#pragma once
// How much memory this process may still allocate, so that work whose size grows with its input
// (a CSM's compressed maps) stops with an error naming what it needed instead of being killed by
// the kernel's out-of-memory killer (which ended a whole batch run, and every resume of it).
#include <cstdint>
#include <optional>
#include <string>

namespace splatcl {

// Value of a "key: value" line of a /proc file ("" when absent).
std::string proc_field(const char* file, const std::string& key);

// A "key: N kB" line of a /proc file in bytes (nullopt when absent).
std::optional<std::uint64_t> proc_kib(const char* file, const std::string& key);

// The memory still available: /proc/meminfo's MemAvailable, less where a cgroup this process is in
// (v2 memory.max, v1 memory.limit_in_bytes or its hierarchical limit; a Slurm job's or a
// container's) leaves less after its inactive page cache, and at most $SPLATCL_MEMORY_LIMIT less
// what the process holds now (its resident set). nullopt when none of these can be read.
std::optional<std::uint64_t> available_memory();

// The tightest room the cgroups in `self_cgroup` (/proc/self/cgroup's text: v2 "0::/path", its
// folder under `mount` and each parent's; v1 "N:...memory...:/path" under mount/memory, with its
// hierarchical limit) leave after their inactive page cache, which the kernel reclaims before it
// kills. A folder that is not visible (a container with its own cgroup namespace) is read at the
// mount's root. nullopt where no limit is set.
std::optional<std::uint64_t> cgroup_memory_room(const std::string& self_cgroup, const std::string& mount);

// The limit $SPLATCL_MEMORY_LIMIT names: bytes, or with a K, M, G or T suffix (powers of 1024).
// Throws Error for a value that is none of these. nullopt when unset or empty.
std::optional<std::uint64_t> memory_limit_from_environment();

// "1.25 GiB", "340 MiB", "12 KiB", "512 bytes": for messages.
std::string memory_size(std::uint64_t bytes);

// Throws Error "WHAT needs about X GiB more memory, and Y GiB is available: REMEDY" when `bytes`
// exceed available_memory(); nothing when they fit or it is unknown.
void require_memory(std::uint64_t bytes, const std::string& what, const std::string& remedy);

}  // namespace splatcl
