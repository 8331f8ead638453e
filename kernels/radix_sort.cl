// Stable LSD radix sort of KEY_T keys (uint or ulong), carrying uint values when WITH_VALUES is 1.
// Each pass sorts by one digit: (key >> shift) masked to the pass's width. Per-pass histograms are
// stored digit-major (table[digit * parts + part]), so an exclusive scan of the whole table gives
// every (digit, part) its first output position, and parts keep their input order: stable.
// The value arguments are always present; without WITH_VALUES they are not read.
#include "common.h"
#include "primitives_cpu.h"
#include "primitives_group.h"

#ifndef KEY_T
#error "KEY_T must be given as a build option (uint or ulong)"
#endif
#ifndef WITH_VALUES
#define WITH_VALUES 0
#endif

// ---- CPU shape: one work-item per contiguous chunk, serial loops, no barriers. CPU_RADIX_BITS (a
// build option, from the device's tuning record) bounds the digit width of a pass.

#ifndef CPU_RADIX_BITS
#error "CPU_RADIX_BITS must be given as a build option"
#endif
#define CPU_RADIX (1 << CPU_RADIX_BITS)

inline uint cpu_digit(KEY_T key, uint shift, uint radix) { return (uint)(key >> shift) & (radix - 1u); }

// table[d * chunks + c] = keys of chunk c with digit d, for the pass's `radix` digits.
__kernel void radix_histogram_cpu(__global const KEY_T* keys, __global uint* table, ulong n_items, uint chunks,
                                  uint shift, uint radix) {
  const size_t n = (size_t)n_items;
  const size_t c = get_global_id(0);
  // Four interleaved count arrays: runs of equal digits would otherwise chain every increment
  // through the same counter in memory.
  uint counts[4][CPU_RADIX];
  for (uint d = 0; d < radix; ++d) counts[0][d] = counts[1][d] = counts[2][d] = counts[3][d] = 0;
  size_t i = chunk_begin(n, chunks, c);
  const size_t end = chunk_begin(n, chunks, c + 1);
  for (; i + 4 <= end; i += 4) {
    ++counts[0][cpu_digit(keys[i], shift, radix)];
    ++counts[1][cpu_digit(keys[i + 1], shift, radix)];
    ++counts[2][cpu_digit(keys[i + 2], shift, radix)];
    ++counts[3][cpu_digit(keys[i + 3], shift, radix)];
  }
  for (; i < end; ++i) ++counts[0][cpu_digit(keys[i], shift, radix)];
  for (uint d = 0; d < radix; ++d) table[d * chunks + c] = counts[0][d] + counts[1][d] + counts[2][d] + counts[3][d];
}

// Write combining: a digit's elements are staged per aligned run of WC_SLOTS output positions
// and a full run leaves as streaming vector stores (whole cache lines, no read for ownership),
// instead of 256 digits x 2 arrays of element stores competing for cache lines and TLB entries.
// A run is 128 bytes of keys (two cache lines): the flush branch, mispredicted once per run, cost
// more than the larger staging area with 64-byte runs of uint keys (radix sort of 2M 20-bit keys
// on PoCL and Intel, docs/benchmarks.md); ulong keys keep 16 slots and their staging area's size.
// The staging area is private: 128 bytes per digit and array, 128 KiB each with 10-bit digits.
#define WC_SLOTS (128 / (int)sizeof(KEY_T))
#define KEY_VEC SPLATCL_CONCAT(KEY_T, 16)

// Stores staged output positions [from, to) of digit d element by element (partial runs).
inline void flush_staged(__global KEY_T* keys_out, __global uint* values_out, const KEY_T* staged_keys,
                         const uint* staged_values, uint d, uint from, uint to) {
  for (uint position = from; position < to; ++position) {
    const uint slot = d * WC_SLOTS + (position & (WC_SLOTS - 1u));
    keys_out[position] = staged_keys[slot];
#if WITH_VALUES
    values_out[position] = staged_values[slot];
#endif
  }
}

// Moves chunk c's elements to their sorted positions, in input order within each digit. Each
// work-item scans the (small) table itself for its own offsets, which saves a launch per pass.
__kernel void radix_scatter_cpu(__global const KEY_T* keys_in, __global KEY_T* keys_out, __global const uint* values_in,
                                __global uint* values_out, __global const uint* table, ulong n_items, uint chunks,
                                uint shift, uint radix) {
  const size_t n = (size_t)n_items;
  const size_t c = get_global_id(0);
  uint next[CPU_RADIX];   // next output position per digit
  uint first[CPU_RADIX];  // this chunk's first output position per digit
  KEY_T staged_keys[CPU_RADIX * WC_SLOTS];
  uint staged_values[WITH_VALUES ? CPU_RADIX * WC_SLOTS : 1];
  uint running = 0;
  for (uint d = 0; d < radix; ++d) {
    for (uint k = 0; k < chunks; ++k) {
      if (k == c) next[d] = first[d] = running;
      running += table[d * chunks + k];
    }
  }
  const size_t end = chunk_begin(n, chunks, c + 1);
  for (size_t i = chunk_begin(n, chunks, c); i < end; ++i) {
    const KEY_T key = keys_in[i];
    const uint d = cpu_digit(key, shift, radix);
    const uint position = next[d]++;
    const uint slot = position & (WC_SLOTS - 1u);
    staged_keys[d * WC_SLOTS + slot] = key;
#if WITH_VALUES
    staged_values[d * WC_SLOTS + slot] = values_in[i];
#endif
    if (slot == WC_SLOTS - 1u) {
      const uint run = position - (WC_SLOTS - 1u);
      if (run >= first[d]) {
        for (uint j = 0; j < WC_SLOTS / 16; ++j)
          STREAM_STORE(vload16(j, staged_keys + d * WC_SLOTS), (__global KEY_VEC*)(keys_out + run) + j);
#if WITH_VALUES
        for (uint j = 0; j < WC_SLOTS / 16; ++j)
          STREAM_STORE(vload16(j, staged_values + d * WC_SLOTS), (__global uint16*)(values_out + run) + j);
#endif
      } else {
        // The run starts before this chunk's share of the digit: store only the chunk's own part.
        flush_staged(keys_out, values_out, staged_keys, staged_values, d, first[d], position + 1);
      }
    }
  }
  for (uint d = 0; d < radix; ++d)
    flush_staged(keys_out, values_out, staged_keys, staged_values, d, max(first[d], next[d] & ~(WC_SLOTS - 1u)),
                 next[d]);
  STREAM_STORES_DONE();
}

// ---- GPU shape: blocks of GPU_BLOCK keys, GPU_ITEM_KEYS consecutive keys per work-item, 4-bit
// digits. A block is sorted by its digit in local memory with stable splits (Satish et al. split
// on one bit per group scan; four per-way counters packed in a ulong let one scan split two bits),
// its digit counts go to the table, and once the table is scanned every key goes to its digit's
// table offset plus its rank among the block's keys of that digit.

// GPU_DIGIT_BITS, GPU_RADIX and SPLIT_FIELD_BITS: primitives_layout.h (the host sizes the digit
// tables and limits the block from them).
#ifndef GPU_ITEM_KEYS
#error "GPU_ITEM_KEYS must be given as a build option"
#endif
#define GPU_BLOCK (GROUP_SIZE * GPU_ITEM_KEYS)
#define SPLIT_BITS 2
#define SPLIT_WAYS (1 << SPLIT_BITS)
#if GPU_BLOCK >= (1 << SPLIT_FIELD_BITS)
#error "a block's per-way counts must fit the packed 16-bit fields"
#endif

inline uint split_way(uint digit, uint bit) { return (digit >> bit) & (SPLIT_WAYS - 1u); }
inline ulong split_one(uint way) { return 1ul << (SPLIT_FIELD_BITS * way); }
inline uint split_field(ulong packed, uint way) {
  return (uint)(packed >> (SPLIT_FIELD_BITS * way)) & ((1u << SPLIT_FIELD_BITS) - 1u);
}

// Sorts each block by the digit (key >> shift) & digit_mask into sorted_keys/values and writes its
// digit counts to table[d * blocks + block]. Positions past n carry the largest digit and come
// after every real key of the block, so after the splits they sit at its end and are dropped.
__kernel __attribute__((reqd_work_group_size(GROUP_SIZE, 1, 1)))
void radix_block_sort_gpu(__global const KEY_T* keys, __global const uint* values, __global KEY_T* sorted_keys,
                          __global uint* sorted_values, __global uint* table, ulong n_items, uint blocks, uint shift,
                          uint digit_mask) {
  __local KEY_T local_keys[GPU_BLOCK];
#if WITH_VALUES
  __local uint local_values[GPU_BLOCK];
#endif
  __local uint local_digits[GPU_BLOCK];
  __local ulong scratch[GROUP_SCAN_SCRATCH];
  __local uint digit_begin[GPU_RADIX];
  __local uint digit_end[GPU_RADIX];
  const uint lid = (uint)get_local_id(0);
  const size_t group = get_group_id(0);
  const size_t base = group * GPU_BLOCK;
  const uint valid_count = (uint)min((size_t)GPU_BLOCK, (size_t)n_items - base);
  KEY_T key[GPU_ITEM_KEYS];
  uint value[GPU_ITEM_KEYS];
  uint digit[GPU_ITEM_KEYS];
#pragma unroll
  for (uint j = 0; j < GPU_ITEM_KEYS; ++j) {
    const uint p = lid * GPU_ITEM_KEYS + j;
    key[j] = p < valid_count ? keys[base + p] : (KEY_T)0;
    value[j] = WITH_VALUES && p < valid_count ? values[base + p] : 0u;
    digit[j] = p < valid_count ? (uint)(key[j] >> shift) & digit_mask : GPU_RADIX - 1u;
  }
  // Fixed trip counts: every work-item reaches every barrier. Bits above digit_mask are 0 for every
  // real key, so their splits keep the order.
#pragma unroll
  for (uint bit = 0; bit < GPU_DIGIT_BITS; bit += SPLIT_BITS) {
    ulong item_counts = 0;
#pragma unroll
    for (uint j = 0; j < GPU_ITEM_KEYS; ++j) item_counts += split_one(split_way(digit[j], bit));
    ulong way_totals;
    ulong ahead = group_exclusive_scan_ulong(item_counts, scratch, &way_totals);
#pragma unroll
    for (uint j = 0; j < GPU_ITEM_KEYS; ++j) {
      const uint way = split_way(digit[j], bit);
      uint destination = split_field(ahead, way);
      for (uint w = 0; w < way; ++w) destination += split_field(way_totals, w);
      ahead += split_one(way);
      local_keys[destination] = key[j];
#if WITH_VALUES
      local_values[destination] = value[j];
#endif
      local_digits[destination] = digit[j];
    }
    barrier(CLK_LOCAL_MEM_FENCE);
#pragma unroll
    for (uint j = 0; j < GPU_ITEM_KEYS; ++j) {
      const uint p = lid * GPU_ITEM_KEYS + j;
      key[j] = local_keys[p];
#if WITH_VALUES
      value[j] = local_values[p];
#endif
      digit[j] = local_digits[p];
    }
    barrier(CLK_LOCAL_MEM_FENCE);
  }
  if (lid < GPU_RADIX) {
    digit_begin[lid] = 0;
    digit_end[lid] = 0;
  }
  barrier(CLK_LOCAL_MEM_FENCE);
#pragma unroll
  for (uint j = 0; j < GPU_ITEM_KEYS; ++j) {
    const uint p = lid * GPU_ITEM_KEYS + j;
    if (p < valid_count) {
      if (p == 0 || local_digits[p - 1] != digit[j]) digit_begin[digit[j]] = p;
      if (p == valid_count - 1 || local_digits[p + 1] != digit[j]) digit_end[digit[j]] = p + 1;
      sorted_keys[base + p] = key[j];
#if WITH_VALUES
      sorted_values[base + p] = value[j];
#endif
    }
  }
  barrier(CLK_LOCAL_MEM_FENCE);
  if (lid < GPU_RADIX) table[lid * blocks + group] = digit_end[lid] - digit_begin[lid];
}

// Moves each key of a block-sorted run to offsets[digit * blocks + block] + its rank among the
// block's keys of that digit.
__kernel __attribute__((reqd_work_group_size(GROUP_SIZE, 1, 1)))
void radix_scatter_gpu(__global const KEY_T* sorted_keys, __global const uint* sorted_values, __global KEY_T* keys_out,
                       __global uint* values_out, __global const uint* offsets, ulong n_items, uint blocks, uint shift,
                       uint digit_mask) {
  __local uint local_digits[GPU_BLOCK];
  __local uint digit_begin[GPU_RADIX];
  const uint lid = (uint)get_local_id(0);
  const size_t group = get_group_id(0);
  const size_t base = group * GPU_BLOCK;
  const uint valid_count = (uint)min((size_t)GPU_BLOCK, (size_t)n_items - base);
  KEY_T key[GPU_ITEM_KEYS];
  uint digit[GPU_ITEM_KEYS];
#pragma unroll
  for (uint j = 0; j < GPU_ITEM_KEYS; ++j) {
    const uint p = lid * GPU_ITEM_KEYS + j;
    key[j] = p < valid_count ? sorted_keys[base + p] : (KEY_T)0;
    // GPU_RADIX matches no real digit, so the last real run ends where the padding starts.
    digit[j] = p < valid_count ? (uint)(key[j] >> shift) & digit_mask : GPU_RADIX;
    local_digits[p] = digit[j];
  }
  barrier(CLK_LOCAL_MEM_FENCE);
#pragma unroll
  for (uint j = 0; j < GPU_ITEM_KEYS; ++j) {
    const uint p = lid * GPU_ITEM_KEYS + j;
    if (p < valid_count && (p == 0 || local_digits[p - 1] != digit[j])) digit_begin[digit[j]] = p;
  }
  barrier(CLK_LOCAL_MEM_FENCE);
#pragma unroll
  for (uint j = 0; j < GPU_ITEM_KEYS; ++j) {
    const uint p = lid * GPU_ITEM_KEYS + j;
    if (p < valid_count) {
      const uint position = offsets[digit[j] * blocks + group] + p - digit_begin[digit[j]];
      keys_out[position] = key[j];
#if WITH_VALUES
      values_out[position] = sorted_values[base + p];
#endif
    }
  }
}
