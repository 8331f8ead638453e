// Stable stream compaction of uint32 values: keep_flagged (flags[i] != 0) or unique (the first of
// each run of equal adjacent values), chosen by `unique_mode` (0 or 1). Count, then scatter from
// scanned counts; no global atomics, so the output order is the input order.
#include "common.h"
#include "primitives_group.h"

// Whether element i is kept. In unique mode `flags` is not read.
inline uint is_kept(__global const uint* values, __global const uint* flags, size_t i, uint unique_mode) {
  if (unique_mode) return i == 0 || values[i] != values[i - 1];
  return flags[i] != 0u;
}

// ---- CPU shape: one work-item per contiguous chunk, serial loops, no barriers.

// counts[c] = elements kept in chunk c.
__kernel void compact_count_cpu(__global const uint* values, __global const uint* flags, __global uint* counts,
                                ulong n_items, uint chunks, uint unique_mode) {
  const size_t n = (size_t)n_items;
  const size_t c = get_global_id(0);
  const size_t end = chunk_begin(n, chunks, c + 1);
  size_t i = chunk_begin(n, chunks, c);
  uint count = 0;
  // Loops specialised per mode so that they vectorize.
  if (unique_mode) {
    if (i == 0 && end > 0) count = 1, i = 1;  // element 0 has no predecessor: always kept
    for (; i < end; ++i) count += values[i] != values[i - 1];
  } else {
    for (; i < end; ++i) count += flags[i] != 0u;
  }
  counts[c] = count;
}

// Copies the kept elements of chunk c after those of the chunks before it; the last chunk writes
// the total kept to counts[chunks]. With one chunk, counts[0] is not read.
__kernel void compact_scatter_cpu(__global const uint* values, __global const uint* flags, __global uint* out,
                                  __global uint* counts, ulong n_items, uint chunks, uint unique_mode) {
  const size_t n = (size_t)n_items;
  const size_t c = get_global_id(0);
  size_t position = 0;
  for (size_t k = 0; k < c; ++k) position += counts[k];
  const size_t begin = chunk_begin(n, chunks, c);
  size_t last_kept = chunk_begin(n, chunks, c + 1);
  while (last_kept > begin && !is_kept(values, flags, last_kept - 1, unique_mode)) --last_kept;
  // Branch-free: every element is written and the position advances only when it is kept. A dropped
  // element's write is overwritten by the next kept one, which exists up to last_kept, so no write
  // leaves this chunk's output range.
  if (unique_mode) {
    // Element 0 has no predecessor; comparing it with its own complement keeps it.
    uint previous = begin == 0 ? ~values[0] : values[begin - 1];
    for (size_t i = begin; i < last_kept; ++i) {
      const uint value = values[i];
      out[position] = value;
      position += value != previous;
      previous = value;
    }
  } else {
    for (size_t i = begin; i < last_kept; ++i) {
      out[position] = values[i];
      position += flags[i] != 0u;
    }
  }
  if (c == chunks - 1) counts[chunks] = (uint)position;
}

// ---- GPU shape: work-groups of GROUP_SIZE; a block is COMPACT_ROUNDS rounds of GROUP_SIZE
// consecutive elements, one element per work-item per round (COMPACT_ROUNDS: a build option, from
// the device's tuning record).

#ifndef COMPACT_ROUNDS
#error "COMPACT_ROUNDS must be given as a build option"
#endif
#define COMPACT_BLOCK (GROUP_SIZE * COMPACT_ROUNDS)

// block_counts[group] = elements kept in the block.
__kernel __attribute__((reqd_work_group_size(GROUP_SIZE, 1, 1)))
void compact_count_gpu(__global const uint* values, __global const uint* flags, __global uint* block_counts,
                       ulong n_items, uint unique_mode) {
  __local uint scratch[GROUP_SCAN_SCRATCH];
  const size_t n = (size_t)n_items;
  const size_t base = get_group_id(0) * (size_t)COMPACT_BLOCK + get_local_id(0);
  uint count = 0;
  for (size_t k = 0; k < COMPACT_ROUNDS; ++k) {
    const size_t i = base + k * GROUP_SIZE;
    if (i < n) count += is_kept(values, flags, i, unique_mode);
  }
  uint block_total;
  group_exclusive_scan(count, scratch, &block_total);
  if (get_local_id(0) == 0) block_counts[get_group_id(0)] = block_total;
}

// Writes the block's kept elements from its scanned offset, ranked by a group scan per round.
__kernel __attribute__((reqd_work_group_size(GROUP_SIZE, 1, 1)))
void compact_scatter_gpu(__global const uint* values, __global const uint* flags, __global uint* out,
                         __global const uint* block_offsets, ulong n_items, uint unique_mode) {
  __local uint scratch[GROUP_SCAN_SCRATCH];
  const size_t n = (size_t)n_items;
  const size_t base = get_group_id(0) * (size_t)COMPACT_BLOCK + get_local_id(0);
  size_t offset = block_offsets[get_group_id(0)];
  for (size_t k = 0; k < COMPACT_ROUNDS; ++k) {
    const size_t i = base + k * GROUP_SIZE;
    const uint kept = i < n && is_kept(values, flags, i, unique_mode);
    uint round_total;
    const uint rank = group_exclusive_scan(kept, scratch, &round_total);
    if (kept) out[offset + rank] = values[i];
    offset += round_total;
  }
}
