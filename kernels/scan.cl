// Scan (exclusive or inclusive prefix sum) of uint32, sums wrapping modulo 2^32.
// Reduce-then-scan in separate launches: work-groups have no forward-progress guarantee, so no
// chained single-pass scan. `inclusive` is 0 or 1; in and out may be the same buffer.
#include "common.h"
#include "primitives_group.h"

// ---- CPU shape: one work-item per contiguous chunk, serial loops, no barriers.

// chunk_sums[c] = sum of chunk c.
__kernel void scan_chunk_sums_cpu(__global const uint* in, __global uint* chunk_sums, ulong n_items, uint chunks) {
  const size_t n = (size_t)n_items;
  const size_t c = get_global_id(0);
  const size_t end = chunk_begin(n, chunks, c + 1);
  uint sum = 0;
  for (size_t i = chunk_begin(n, chunks, c); i < end; ++i) sum += in[i];
  chunk_sums[c] = sum;
}

// Scans chunk c starting from the sum of the chunks before it (few chunks, so each work-item adds
// them up itself instead of a separate launch). The last chunk writes the grand total. With one
// chunk, chunk_sums is not read.
__kernel void scan_chunks_cpu(__global const uint* in, __global uint* out, __global const uint* chunk_sums,
                              __global uint* total, ulong n_items, uint chunks, uint inclusive) {
  const size_t n = (size_t)n_items;
  const size_t c = get_global_id(0);
  uint running = 0;
  for (size_t k = 0; k < c; ++k) running += chunk_sums[k];
  const uint own_mask = inclusive ? 0xFFFFFFFFu : 0u;
  const size_t begin = chunk_begin(n, chunks, c);
  const size_t end = chunk_begin(n, chunks, c + 1);
  // Serial head up to an 8-aligned index, 8-wide body (in-register log-step scan), serial tail.
  const size_t body_begin = min(end, (begin + 7) & ~(size_t)7);
  const size_t body_end = max(body_begin, end & ~(size_t)7);
  for (size_t i = begin; i < body_begin; ++i) {
    const uint value = in[i];
    out[i] = running + (value & own_mask);
    running += value;
  }
  const uint8 own_mask8 = (uint8)(own_mask);
  for (size_t i = body_begin; i < body_end; i += 8) {
    const uint8 value = vload8(0, in + i);
    uint8 sums = value;
    sums += (uint8)(0u, sums.s012, sums.s3456);
    sums += (uint8)(0u, 0u, sums.s01, sums.s2345);
    sums += (uint8)((uint4)(0u), sums.lo);
    // sums is the inclusive scan within the 8; subtract the value for the exclusive one.
    vstore8((uint8)(running) + sums - (value & ~own_mask8), 0, out + i);
    running += sums.s7;
  }
  for (size_t i = body_end; i < end; ++i) {
    const uint value = in[i];
    out[i] = running + (value & own_mask);
    running += value;
  }
  if (c == chunks - 1) *total = running;
}

// ---- GPU shape: work-groups of GROUP_SIZE, SCAN_ITEMS consecutive values per work-item (both
// build options: the device's tuning record, host/primitives/tuning.hpp).

#ifndef SCAN_ITEMS
#error "SCAN_ITEMS must be given as a build option"
#endif
#define SCAN_BLOCK (GROUP_SIZE * SCAN_ITEMS)

// Scans each block of SCAN_BLOCK values locally; block_sums[group] = the block's sum. The block is
// staged through local memory so that global loads and stores stay coalesced. Out-of-range items
// load 0 (the grid is padded to whole groups, never partial ones).
__kernel __attribute__((reqd_work_group_size(GROUP_SIZE, 1, 1)))
void scan_blocks_gpu(__global const uint* in, __global uint* out, __global uint* block_sums, ulong n_items,
                     uint inclusive) {
  __local uint tile[SCAN_BLOCK];
  __local uint scratch[GROUP_SCAN_SCRATCH];
  const size_t n = (size_t)n_items;
  const size_t lid = get_local_id(0);
  const size_t base = get_group_id(0) * (size_t)SCAN_BLOCK;
  for (size_t k = 0; k < SCAN_ITEMS; ++k) {
    const size_t i = base + k * GROUP_SIZE + lid;
    tile[k * GROUP_SIZE + lid] = i < n ? in[i] : 0u;
  }
  barrier(CLK_LOCAL_MEM_FENCE);
  const uint own_mask = inclusive ? 0xFFFFFFFFu : 0u;
  uint running = 0;
  for (size_t k = 0; k < SCAN_ITEMS; ++k) {
    const uint value = tile[lid * SCAN_ITEMS + k];
    tile[lid * SCAN_ITEMS + k] = running + (value & own_mask);
    running += value;
  }
  uint block_total;
  const uint prefix = group_exclusive_scan(running, scratch, &block_total);
  for (size_t k = 0; k < SCAN_ITEMS; ++k) tile[lid * SCAN_ITEMS + k] += prefix;
  barrier(CLK_LOCAL_MEM_FENCE);
  for (size_t k = 0; k < SCAN_ITEMS; ++k) {
    const size_t i = base + k * GROUP_SIZE + lid;
    if (i < n) out[i] = tile[k * GROUP_SIZE + lid];
  }
  if (lid == 0) block_sums[get_group_id(0)] = block_total;
}

// out[i] += block_offsets[block of i] (the scanned block sums).
__kernel __attribute__((reqd_work_group_size(GROUP_SIZE, 1, 1)))
void scan_add_offsets_gpu(__global uint* out, __global const uint* block_offsets, ulong n_items) {
  const size_t i = get_global_id(0);
  if (i < (size_t)n_items) out[i] += block_offsets[i / SCAN_BLOCK];
}
