// Clustered shading: cluster keys, the three compaction variants, cluster bounds.
// Build options: TILE_W, TILE_H (tile size), NORMAL_BITS (0 or 6), BACKGROUND (the key of a pixel
// with no geometry, also its cluster index), MAX_SORT_TILE_PIXELS, MAX_BITMASK_LOW_BITS (limits of
// the per-tile variants), and for the GPU-shaped tile sort SORT_N (power of two ≥ TILE_W·TILE_H)
// and SORT_GROUP (its work-group size).
// Per-pixel buffers are row-major with row 0 at the bottom (OpenGL window coordinates).
// Distances, normal cells and cluster boxes: cluster_layout.h, shared with the native reference
// (host/cluster/layout.cpp).
#pragma OPENCL FP_CONTRACT OFF
#include "common.h"
#include "cluster_layout.h"

#ifndef BACKGROUND
#error "BACKGROUND must be given as a build option"
#endif
#define TILE_PIXELS (TILE_W * TILE_H)

// ---- keys

// Natural log for x ≥ FLT_MIN to about 1e-7 absolute: x = m·2^e with m in [√½, √2), then
// ln m = 2·atanh(s), s = (m−1)/(m+1), by its series. The builtin log is not vectorized by PoCL.
inline float fast_ln(float x) {
  const uint bits = as_uint(x);
  int e = (int)(bits >> 23) - 127;
  float m = as_float((bits & 0x7FFFFFu) | 0x3F800000u);
  const int halve = m > 1.41421356f;
  m = halve ? m * 0.5f : m;
  e += halve;
  const float s = (m - 1.0f) / (m + 1.0f);
  const float s2 = s * s;
  return s * (2.0f + s2 * (0.666666667f + s2 * (0.4f + s2 * 0.285714286f))) + (float)e * 0.693147181f;
}

// k = floor(ln(d/near)/ln q), exactly as the largest k < S_z with d_k ≤ d in the boundary table
// d_k = near·q^k. fast_ln is within 0.2 slices for every layout ClusterLayout::make accepts, so
// the guess lowered by half a slice is k or k − 1, and one table lookup settles it.
// Branch-free, one gather: PoCL vectorizes it.
inline uint slice_of_distance(float distance, __global const float* boundaries, int slices, float ln_near,
                              float inv_ln_q) {
  int k = (int)fmax((fast_ln(distance) - ln_near) * inv_ln_q - 0.5f, 0.0f);
  k = min(k, slices - 1);
  return (uint)min(k + (int)(distance >= boundaries[k + 1]), slices - 1);
}

inline uint pixel_key(float distance, uint x, uint y, size_t p, __global const float* normals,
                      __global const float* boundaries, uint tiles_x, uint low_bits, int slices, float near_plane,
                      float ln_near, float inv_ln_q) {
  const uint tile = y / TILE_H * tiles_x + x / TILE_W;
  const uint slice = slice_of_distance(fmax(distance, near_plane), boundaries, slices, ln_near, inv_ln_q);
  uint key = (tile << low_bits) | (slice << NORMAL_BITS);
#if NORMAL_BITS > 0
  const float3 normal = vload3(p, normals);
  key |= cluster_normal_cell(normal.x, normal.y, normal.z);
#endif
  return distance < 0.0f ? BACKGROUND : key;
}

// One work-item per pixel over a 2-D range, one kernel per depth format (a runtime branch would
// make PoCL evaluate both). `normals` (3 floats per pixel) is read only when NORMAL_BITS > 0.
__kernel void cluster_keys_view(__global const float* view_z, __global const float* normals,
                                __global const float* boundaries, __global uint* keys, uint width, uint height,
                                uint tiles_x, uint low_bits, int slices, float near_plane, float far_plane,
                                float ln_near, float inv_ln_q) {
  const uint x = get_global_id(0), y = get_global_id(1);
  if (x >= width || y >= height) return;
  const size_t p = (size_t)y * width + x;
  const float distance = cluster_view_distance(view_z[p], near_plane, far_plane);
  keys[p] = pixel_key(distance, x, y, p, normals, boundaries, tiles_x, low_bits, slices, near_plane, ln_near, inv_ln_q);
}

__kernel void cluster_keys_window(__global const float* depth, __global const float* normals,
                                  __global const float* boundaries, __global uint* keys, uint width, uint height,
                                  uint tiles_x, uint low_bits, int slices, float near_plane, float far_plane,
                                  float ln_near, float inv_ln_q, float near_over_far, float far_share) {
  const uint x = get_global_id(0), y = get_global_id(1);
  if (x >= width || y >= height) return;
  const size_t p = (size_t)y * width + x;
  const float distance = cluster_window_distance(depth[p], near_plane, far_plane, near_over_far, far_share);
  keys[p] = pixel_key(distance, x, y, p, normals, boundaries, tiles_x, low_bits, slices, near_plane, ln_near, inv_ln_q);
}

// ---- compaction (a): global radix sort of (key, pixel), then run flags, scan, scatter

__kernel void cluster_sort_init(__global const uint* keys, __global uint* sort_keys, __global uint* sort_pixels,
                                uint n) {
  const uint i = get_global_id(0);
  if (i >= n) return;
  sort_keys[i] = keys[i];
  sort_pixels[i] = i;
}

// run_starts[i] = 1 where a run of equal valid keys starts in the sorted keys.
__kernel void cluster_run_starts(__global const uint* sort_keys, __global uint* run_starts, uint n) {
  const uint i = get_global_id(0);
  if (i >= n) return;
  const uint key = sort_keys[i];
  run_starts[i] = key != BACKGROUND && (i == 0 || key != sort_keys[i - 1]) ? 1u : 0u;
}

// run_ends = inclusive scan of run_starts: element i belongs to unique cluster run_ends[i] − 1.
__kernel void cluster_sorted_scatter(__global const uint* sort_keys, __global const uint* sort_pixels,
                                     __global const uint* run_ends, __global uint* unique_keys,
                                     __global uint* pixel_cluster, uint n) {
  const uint i = get_global_id(0);
  if (i >= n) return;
  const uint key = sort_keys[i];
  const uint pixel = sort_pixels[i];
  if (key == BACKGROUND) {
    pixel_cluster[pixel] = BACKGROUND;
    return;
  }
  const uint cluster = run_ends[i] - 1u;
  pixel_cluster[pixel] = cluster;
  if (i == 0 || key != sort_keys[i - 1]) unique_keys[cluster] = key;
}

// ---- compaction (b): per tile, the tile's unique keys go to staging[tile·TILE_PIXELS ...], its
// count to tile_counts[tile], and each pixel gets its tile-local cluster index; after a scan of the
// counts, cluster_tile_scatter makes them global.

inline void tile_origin(uint tile, uint tiles_x, uint width, uint height, uint* x0, uint* y0, uint* w, uint* h) {
  *x0 = tile % tiles_x * TILE_W;
  *y0 = tile / tiles_x * TILE_H;
  *w = min((uint)TILE_W, width - *x0);
  *h = min((uint)TILE_H, height - *y0);
}

#define COUNT_BINS 1024u

// Stable counting sort of n values in [lo, lo + COUNT_BINS) with their pixel offsets. Equal values
// come in runs (neighbouring pixels share a cluster), so counts and slots are carried in registers
// along a run instead of a load-increment-store chain through hist[] per pixel.
inline void counting_sort(const uint* value, const ushort* where, uint n, uint lo, uint hi, uint* hist,
                          uint* sorted_value, ushort* sorted_where) {
  const uint bins = hi - lo + 1u;
  for (uint b = 0; b < bins; ++b) hist[b] = 0;
  uint current = value[0], run = 0;
  for (uint t = 0; t < n; ++t) {
    if (value[t] != current) {
      hist[current - lo] += run;
      current = value[t];
      run = 0;
    }
    ++run;
  }
  hist[current - lo] += run;
  uint running = 0;
  for (uint b = 0; b < bins; ++b) {
    const uint count = hist[b];
    hist[b] = running;
    running += count;
  }
  current = value[0];
  uint slot = hist[current - lo];
  for (uint t = 0; t < n; ++t) {
    if (value[t] != current) {
      hist[current - lo] = slot;
      current = value[t];
      slot = hist[current - lo];
    }
    sorted_value[slot] = current;
    sorted_where[slot] = where[t];
    ++slot;
  }
}

// Stable LSD radix sort, 8-bit digits of (value − lo), for value ranges too wide for counting_sort.
// Ping-pongs between the two array pairs; the result lands in sorted_value / sorted_where.
inline void radix_sort(uint* value, ushort* where, uint n, uint lo, uint hi, uint* hist, uint* sorted_value,
                       ushort* sorted_where) {
  const uint span_bits = 32u - clz(hi - lo);
  const uint passes = (span_bits + 7u) / 8u;
  uint* src_value = value;
  ushort* src_where = where;
  uint* dst_value = sorted_value;
  ushort* dst_where = sorted_where;
  for (uint pass = 0; pass < passes; ++pass) {
    const uint shift = pass * 8u;
    for (uint b = 0; b < 256u; ++b) hist[b] = 0;
    for (uint t = 0; t < n; ++t) ++hist[((src_value[t] - lo) >> shift) & 0xFFu];
    uint running = 0;
    for (uint b = 0; b < 256u; ++b) {
      const uint count = hist[b];
      hist[b] = running;
      running += count;
    }
    for (uint t = 0; t < n; ++t) {
      const uint slot = hist[((src_value[t] - lo) >> shift) & 0xFFu]++;
      dst_value[slot] = src_value[t];
      dst_where[slot] = src_where[t];
    }
    uint* swap_value = src_value;
    src_value = dst_value;
    dst_value = swap_value;
    ushort* swap_where = src_where;
    src_where = dst_where;
    dst_where = swap_where;
  }
  if (passes % 2u == 0u) {
    for (uint t = 0; t < n; ++t) {
      sorted_value[t] = value[t];
      sorted_where[t] = where[t];
    }
  }
}

// (b) CPU shape: one work-item per tile, serial sort of the tile's keys on their low (slice,
// normal) bits — counting sort when the tile's value range is narrow, else radix sort — then the
// runs of equal values are the tile's clusters. No barriers, no local memory. Built only for tiles
// small enough for its private arrays.
#if TILE_PIXELS <= MAX_SORT_TILE_PIXELS
__kernel void cluster_tile_sort_cpu(__global const uint* keys, __global uint* pixel_cluster, __global uint* staging,
                                    __global uint* tile_counts, uint width, uint height, uint tiles_x,
                                    uint tile_count, uint low_bits) {
  const uint tile = get_global_id(0);
  if (tile >= tile_count) return;
  uint x0, y0, w, h;
  tile_origin(tile, tiles_x, width, height, &x0, &y0, &w, &h);
  const uint low_mask = (1u << low_bits) - 1u;

  uint value[TILE_PIXELS], sorted_value[TILE_PIXELS], hist[COUNT_BINS];
  ushort where[TILE_PIXELS], sorted_where[TILE_PIXELS];
  uint n = 0, lo = 0xFFFFFFFFu, hi = 0;
  for (uint ly = 0; ly < h; ++ly) {
    const size_t row = (size_t)(y0 + ly) * width + x0;
    for (uint lx = 0; lx < w; ++lx) {
      const uint key = keys[row + lx];
      if (key == BACKGROUND) {
        pixel_cluster[row + lx] = BACKGROUND;
        continue;
      }
      const uint v = key & low_mask;
      value[n] = v;
      where[n] = (ushort)(ly * TILE_W + lx);
      lo = min(lo, v);
      hi = max(hi, v);
      ++n;
    }
  }
  if (n == 0) {
    tile_counts[tile] = 0;
    return;
  }
  if (hi - lo < COUNT_BINS) {
    counting_sort(value, where, n, lo, hi, hist, sorted_value, sorted_where);
  } else {
    radix_sort(value, where, n, lo, hi, hist, sorted_value, sorted_where);
  }

  const uint tile_high = tile << low_bits;
  __global uint* tile_staging = staging + (size_t)tile * TILE_PIXELS;
  uint run = 0;
  tile_staging[0] = tile_high | sorted_value[0];
  for (uint t = 0; t < n; ++t) {
    if (t > 0 && sorted_value[t] != sorted_value[t - 1]) tile_staging[++run] = tile_high | sorted_value[t];
    const uint offset = sorted_where[t];
    pixel_cluster[(size_t)(y0 + offset / TILE_W) * width + x0 + offset % TILE_W] = run;
  }
  tile_counts[tile] = run + 1u;
}
#endif

// (b) GPU shape: one work-group per tile; bitonic sort of the tile's (key, pixel offset) pairs in
// local memory (padded with background keys), then run flags and a work-group scan.
#ifdef SORT_N
#define SORT_ITEMS (SORT_N / SORT_GROUP)

// Inclusive scan of one value per work-item over the work-group (Hillis–Steele in local memory).
inline uint group_inclusive_scan(uint value, __local uint* scratch, uint* total) {
  const uint lid = get_local_id(0);
  scratch[lid] = value;
  barrier(CLK_LOCAL_MEM_FENCE);
  for (uint offset = 1; offset < SORT_GROUP; offset <<= 1) {
    const uint add = lid >= offset ? scratch[lid - offset] : 0u;
    barrier(CLK_LOCAL_MEM_FENCE);
    scratch[lid] += add;
    barrier(CLK_LOCAL_MEM_FENCE);
  }
  const uint result = scratch[lid];
  *total = scratch[SORT_GROUP - 1];
  barrier(CLK_LOCAL_MEM_FENCE);
  return result;
}

__kernel __attribute__((reqd_work_group_size(SORT_GROUP, 1, 1)))
void cluster_tile_sort_gpu(__global const uint* keys, __global uint* pixel_cluster, __global uint* staging,
                           __global uint* tile_counts, uint width, uint height, uint tiles_x) {
  __local uint sort_key[SORT_N];
  __local uint sort_where[SORT_N];
  __local uint scratch[SORT_GROUP];
  const uint tile = get_group_id(0);
  const uint lid = get_local_id(0);
  uint x0, y0, w, h;
  tile_origin(tile, tiles_x, width, height, &x0, &y0, &w, &h);

  for (uint t = lid; t < SORT_N; t += SORT_GROUP) {
    const uint lx = t % TILE_W, ly = t / TILE_W;
    uint key = BACKGROUND;
    if (t < TILE_PIXELS && lx < w && ly < h) {
      const size_t p = (size_t)(y0 + ly) * width + x0 + lx;
      key = keys[p];
      if (key == BACKGROUND) pixel_cluster[p] = BACKGROUND;
    }
    sort_key[t] = key;
    sort_where[t] = t;
  }
  barrier(CLK_LOCAL_MEM_FENCE);

  for (uint size = 2; size <= SORT_N; size <<= 1) {
    for (uint stride = size >> 1; stride > 0; stride >>= 1) {
      for (uint t = lid; t < SORT_N / 2; t += SORT_GROUP) {
        const uint i = 2u * t - (t & (stride - 1u));
        const uint j = i + stride;
        const uint a = sort_key[i], b = sort_key[j];
        const int ascending = (i & size) == 0;
        if ((a > b) == ascending) {
          sort_key[i] = b;
          sort_key[j] = a;
          const uint where_i = sort_where[i];
          sort_where[i] = sort_where[j];
          sort_where[j] = where_i;
        }
      }
      barrier(CLK_LOCAL_MEM_FENCE);
    }
  }

  // Each work-item owns SORT_ITEMS consecutive sorted elements.
  const uint first = lid * SORT_ITEMS;
  uint starts = 0;
  for (uint t = first; t < first + SORT_ITEMS; ++t)
    starts += sort_key[t] != BACKGROUND && (t == 0 || sort_key[t] != sort_key[t - 1]) ? 1u : 0u;
  uint total;
  uint run = group_inclusive_scan(starts, scratch, &total) - starts;  // runs started before my elements
  __global uint* tile_staging = staging + (size_t)tile * TILE_PIXELS;
  for (uint t = first; t < first + SORT_ITEMS; ++t) {
    const uint key = sort_key[t];
    if (key == BACKGROUND) break;
    if (t == 0 || key != sort_key[t - 1]) tile_staging[run++] = key;
    const uint offset = sort_where[t];
    pixel_cluster[(size_t)(y0 + offset / TILE_W) * width + x0 + offset % TILE_W] = run - 1u;
  }
  if (lid == 0) tile_counts[tile] = total;
}
#endif

// Tile-local results to global ones: tile t's clusters start at tile_offsets[t]. One work-group
// per tile; its work-items stride over the tile (one work-item on CPU, a group on GPU).
__kernel void cluster_tile_scatter(__global const uint* staging, __global const uint* tile_counts,
                                   __global const uint* tile_offsets, __global uint* unique_keys,
                                   __global uint* pixel_cluster, uint width, uint height, uint tiles_x) {
  const uint tile = get_group_id(0);
  const uint lid = get_local_id(0), group = get_local_size(0);
  const uint offset = tile_offsets[tile], count = tile_counts[tile];
  __global const uint* tile_staging = staging + (size_t)tile * TILE_PIXELS;
  for (uint i = lid; i < count; i += group) unique_keys[offset + i] = tile_staging[i];
  if (count == 0) return;
  uint x0, y0, w, h;
  tile_origin(tile, tiles_x, width, height, &x0, &y0, &w, &h);
  for (uint ly = 0; ly < h; ++ly) {
    const size_t row = (size_t)(y0 + ly) * width + x0;
    for (uint lx = lid; lx < w; lx += group) {
      const uint local_index = pixel_cluster[row + lx];
      pixel_cluster[row + lx] = local_index == BACKGROUND ? BACKGROUND : local_index + offset;
    }
  }
}

// (c) per tile, a bit mask over the tile's (slice, normal) values; popcounts give each value's
// rank, so no sort. Two kernels around the scan of the tile counts (one work-item per tile each):
// cluster_tile_mask stores the mask and counts its bits; cluster_tile_mask_write then writes the
// unique keys and the global cluster index of every pixel. Only the mask words between the tile's
// lowest and highest value are cleared and scanned (the range grows as values arrive); the host
// guarantees that the value space fits MASK_WORDS words. Neighbouring pixels mostly share a key,
// so the pixel passes look at 16 keys at once and do per-pixel work only where a chunk holds a new
// key.
#define MASK_WORDS (1u << (MAX_BITMASK_LOW_BITS - 5))
#define CHUNK 16

// Bitwise or of the 16 lanes: 0 iff every lane is 0. Cheaper on PoCL than all()/any(), which it
// lowers to a chain of shuffles.
inline uint or_reduce(uint16 v) {
  const uint8 a = v.lo | v.hi;
  const uint4 b = a.lo | a.hi;
  const uint2 c = b.lo | b.hi;
  return c.x | c.y;
}

// Sets the mask bit of `key` (not background), growing the cleared word range as needed.
inline void mark_value(uint key, uint low_mask, uint* mask, uint* first_word, uint* last_word) {
  const uint v = key & low_mask, word = v >> 5;
  if (*first_word > *last_word) {
    *first_word = *last_word = word;
    mask[word] = 0;
  } else if (word < *first_word) {
    for (uint i = word; i < *first_word; ++i) mask[i] = 0;
    *first_word = word;
  } else if (word > *last_word) {
    for (uint i = *last_word + 1u; i <= word; ++i) mask[i] = 0;
    *last_word = word;
  }
  mask[word] |= 1u << (v & 31u);
}

// masks[tile·words_per_tile + w] for w in [first, last] = mask_ranges[tile] (first > last: empty).
__kernel void cluster_tile_mask(__global const uint* restrict keys, __global uint* restrict masks,
                                __global uint2* restrict mask_ranges, __global uint* restrict tile_counts,
                                uint width, uint height, uint tiles_x, uint tile_count, uint low_bits,
                                uint words_per_tile) {
  const uint tile = get_global_id(0);
  if (tile >= tile_count) return;
  uint x0, y0, w, h;
  tile_origin(tile, tiles_x, width, height, &x0, &y0, &w, &h);
  const uint low_mask = (1u << low_bits) - 1u;

  uint mask[MASK_WORDS];
  uint first_word = MASK_WORDS, last_word = 0;  // cleared words: [first_word, last_word]
  uint previous = BACKGROUND;
  for (uint ly = 0; ly < h; ++ly) {
    __global const uint* row = keys + (size_t)(y0 + ly) * width + x0;
    uint lx = 0;
    for (; lx + CHUNK <= w; lx += CHUNK) {
      const uint16 chunk = vload16(0, row + lx);
      if (or_reduce((chunk ^ previous) & as_uint16(chunk != BACKGROUND)) == 0) continue;
      for (uint i = lx; i < lx + CHUNK; ++i) {
        const uint key = row[i];
        if (key == previous || key == BACKGROUND) continue;
        previous = key;
        mark_value(key, low_mask, mask, &first_word, &last_word);
      }
    }
    for (; lx < w; ++lx) {
      const uint key = row[lx];
      if (key == previous || key == BACKGROUND) continue;
      previous = key;
      mark_value(key, low_mask, mask, &first_word, &last_word);
    }
  }
  __global uint* tile_mask = masks + (size_t)tile * words_per_tile;
  uint count = 0;
  for (uint i = first_word; i <= last_word && first_word <= last_word; ++i) {
    tile_mask[i] = mask[i];
    count += popcount(mask[i]);
  }
  mask_ranges[tile] = (uint2)(first_word, last_word);
  tile_counts[tile] = count;
}

inline uint rank_of(uint key, uint low_mask, const uint* mask, const uint* below) {
  const uint v = key & low_mask, word = v >> 5;
  return key == BACKGROUND ? BACKGROUND : below[word] + popcount(mask[word] & ((1u << (v & 31u)) - 1u));
}

__kernel void cluster_tile_mask_write(__global const uint* restrict keys, __global const uint* restrict masks,
                                      __global const uint2* restrict mask_ranges,
                                      __global const uint* restrict tile_offsets, __global uint* restrict unique_keys,
                                      __global uint* restrict pixel_cluster, uint width, uint height, uint tiles_x,
                                      uint tile_count, uint low_bits, uint words_per_tile) {
  const uint tile = get_global_id(0);
  if (tile >= tile_count) return;
  uint x0, y0, w, h;
  tile_origin(tile, tiles_x, width, height, &x0, &y0, &w, &h);
  const uint low_mask = (1u << low_bits) - 1u;

  // below[word] = global index of the first cluster in that word; the unique keys in bit order.
  uint mask[MASK_WORDS], below[MASK_WORDS];
  const uint2 range = mask_ranges[tile];
  __global const uint* tile_mask = masks + (size_t)tile * words_per_tile;
  const uint tile_high = tile << low_bits;
  uint next = tile_offsets[tile];
  for (uint i = range.x; i <= range.y && range.x <= range.y; ++i) {
    mask[i] = tile_mask[i];
    below[i] = next;
    for (uint bits = mask[i]; bits != 0; bits &= bits - 1u)
      unique_keys[next++] = tile_high | (i << 5) | (31u - clz(bits & (0u - bits)));
  }

  uint previous = BACKGROUND, rank = BACKGROUND;  // the last key ranked, and its rank
  for (uint ly = 0; ly < h; ++ly) {
    const size_t row = (size_t)(y0 + ly) * width + x0;
    uint lx = 0;
    for (; lx + CHUNK <= w; lx += CHUNK) {
      const uint16 chunk = vload16(0, keys + row + lx);
      if (or_reduce(chunk ^ previous) == 0) {
        vstore16((uint16)rank, 0, pixel_cluster + row + lx);
        continue;
      }
      for (uint i = lx; i < lx + CHUNK; ++i) {
        const uint key = keys[row + i];
        if (key != previous) {
          previous = key;
          rank = rank_of(key, low_mask, mask, below);
        }
        pixel_cluster[row + i] = rank;
      }
    }
    for (; lx < w; ++lx) {
      const uint key = keys[row + lx];
      if (key != previous) {
        previous = key;
        rank = rank_of(key, low_mask, mask, below);
      }
      pixel_cluster[row + lx] = rank;
    }
  }
}

// ---- bounds: one work-item per unique cluster; bounds[2c] = min, bounds[2c + 1] = max (w unused).

__kernel void cluster_bounds(__global const uint* unique_keys, __global const float* boundaries,
                             __global float4* bounds, uint clusters, uint width, uint height, uint tiles_x,
                             uint low_bits, uint slice_mask, float two_over_width, float two_over_height,
                             float tan_half_x, float tan_half_y, float padding_scale) {
  const uint c = get_global_id(0);
  if (c >= clusters) return;
  const ClusterGrid grid = {width, height, TILE_W, TILE_H, tiles_x, low_bits, NORMAL_BITS, slice_mask,
                            two_over_width, two_over_height, tan_half_x, tan_half_y, padding_scale};
  float lo[3], hi[3];
  cluster_key_box(grid, unique_keys[c], boundaries, lo, hi);
  bounds[2 * (size_t)c] = (float4)(lo[0], lo[1], lo[2], 0.0f);
  bounds[2 * (size_t)c + 1] = (float4)(hi[0], hi[1], hi[2], 0.0f);
}
