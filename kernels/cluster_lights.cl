// Light assignment to cluster boxes: brute force, and a light hierarchy (a BVH over the lights
// sorted by Morton code, fanout 8, built bottom-up one level per launch).
// Build options: LANES (lights per block and children per node: 8, the float8 of the code below),
// BVH_MAX_LEVELS, BVH_STACK, RANK_SORT_MAX.
//
// Work is explicitly 8 or 16 wide (vector types), because PoCL does not vectorize loops inside a
// work-item:
// - lights are stored SoA in four blocks of `stride` floats (x | y | z | radius), stride a multiple
//   of 8; padding lights sit at +infinity with radius 0 and touch nothing;
// - a BVH node stores the boxes of its 8 children SoA (min x, y, z, max x, y, z: six float8);
//   leaves are the 8-light blocks of the sorted lights, so they need no storage of their own.
// Cluster boxes are float4 pairs (min, max). Light lists hold original light indices, ascending.
// The sphere–box test is cluster_layout.h's, shared with the native reference
// (host/cluster/layout.cpp).
#pragma OPENCL FP_CONTRACT OFF
#include "common.h"
#include "cluster_layout.h"

#if LANES != 8
#error "LANES must be given as a build option, and be 8: the light blocks and nodes are float8"
#endif
#define NODE_FLOATS (6 * LANES)

// Bit i set where lane i of the comparison mask is true.
inline uint lane_bits(int8 mask) {
  const int8 weighted = mask & (int8)(1, 2, 4, 8, 16, 32, 64, 128);
  const int4 pairs = weighted.lo | weighted.hi;
  const int2 quads = pairs.lo | pairs.hi;
  return (uint)(quads.x | quads.y);
}

inline uint lowest_bit(uint bits) { return 31u - clz(bits & (0u - bits)); }

DEFINE_CLUSTER_SPHERE_TOUCHES_BOX(spheres_touch_box8, float8, int8)

// Sphere–box overlap of the 8 lights of block `block`.
inline uint touching_lights(float4 lo, float4 hi, __global const float* restrict lights, uint stride, uint block) {
  const size_t i = (size_t)block * LANES;
  const float8 x = vload8(0, lights + i);
  const float8 y = vload8(0, lights + stride + i);
  const float8 z = vload8(0, lights + 2 * (size_t)stride + i);
  const float8 r = vload8(0, lights + 3 * (size_t)stride + i);
  return lane_bits(spheres_touch_box8(lo.x, lo.y, lo.z, hi.x, hi.y, hi.z, x, y, z, r));
}

// ---- brute force: one work-item per cluster, every 8-light block; count, then (after a scan) fill.

__kernel void assign_brute_count(__global const float4* restrict bounds, __global const float* restrict lights,
                                 __global uint* restrict counts, uint clusters, uint stride) {
  const uint c = get_global_id(0);
  if (c >= clusters) return;
  const float4 lo = bounds[2 * (size_t)c], hi = bounds[2 * (size_t)c + 1];
  uint count = 0;
  for (uint block = 0; block < stride / LANES; ++block)
    count += popcount(touching_lights(lo, hi, lights, stride, block));
  counts[c] = count;
}

__kernel void assign_brute_fill(__global const float4* restrict bounds, __global const float* restrict lights,
                                __global const uint* restrict offsets, __global uint* restrict indices, uint clusters,
                                uint stride) {
  const uint c = get_global_id(0);
  if (c >= clusters) return;
  const float4 lo = bounds[2 * (size_t)c], hi = bounds[2 * (size_t)c + 1];
  __global uint* out = indices + offsets[c];
  for (uint block = 0; block < stride / LANES; ++block)
    for (uint bits = touching_lights(lo, hi, lights, stride, block); bits != 0; bits &= bits - 1u)
      *out++ = block * LANES + lowest_bit(bits);
}

// ---- light hierarchy: build

// Interleaves the low 10 bits of v with two zero bits after each.
inline uint spread_bits(uint v) {
  v &= 0x3FFu;
  v = (v | (v << 16)) & 0x030000FFu;
  v = (v | (v << 8)) & 0x0300F00Fu;
  v = (v | (v << 4)) & 0x030C30C3u;
  v = (v | (v << 2)) & 0x09249249u;
  return v;
}

// 30-bit Morton code of each light centre, quantised to 1024 cells per axis of the centres' box.
__kernel void lights_morton(__global const float* restrict lights, __global uint* restrict codes,
                            __global uint* restrict order, uint light_count, uint stride, float4 origin,
                            float4 scale) {
  const uint i = get_global_id(0);
  if (i >= light_count) return;
  const float4 centre = (float4)(lights[i], lights[stride + i], lights[2 * (size_t)stride + i], 0.0f);
  const float4 cell = clamp((centre - origin) * scale, 0.0f, 1023.0f);
  codes[i] = (spread_bits((uint)cell.x) << 2) | (spread_bits((uint)cell.y) << 1) | spread_bits((uint)cell.z);
  order[i] = i;
}

// Sorted SoA lights: slot i holds light order[i]; slots past light_count are padding.
__kernel void bvh_gather(__global const float* restrict lights, __global const uint* restrict order,
                         __global float* restrict sorted_lights, uint light_count, uint stride) {
  const uint i = get_global_id(0);
  if (i >= stride) return;
  const int real = i < light_count;
  const uint l = real ? order[i] : 0u;
  sorted_lights[i] = real ? lights[l] : INFINITY;
  sorted_lights[stride + i] = real ? lights[stride + l] : INFINITY;
  sorted_lights[2 * (size_t)stride + i] = real ? lights[2 * (size_t)stride + l] : INFINITY;
  sorted_lights[3 * (size_t)stride + i] = real ? lights[3 * (size_t)stride + l] : 0.0f;
}

// Stores `lo`/`hi` as child `slot` of a node.
inline void store_child_box(__global float* node, uint slot, float4 lo, float4 hi) {
  node[0 * LANES + slot] = lo.x;
  node[1 * LANES + slot] = lo.y;
  node[2 * LANES + slot] = lo.z;
  node[3 * LANES + slot] = hi.x;
  node[4 * LANES + slot] = hi.y;
  node[5 * LANES + slot] = hi.z;
}

// Relative growth of leaf boxes beyond the float-rounded sphere bounds, so that a box never culls
// a light that touching_lights would accept.
#define BOX_PADDING 1e-5f

// Leaf n (sorted lights [8n, 8n + 8)) → its box, stored as child n % 8 of level-1 node n / 8.
// Work-items past the last leaf store empty boxes into the remaining slots.
__kernel void bvh_leaf_boxes(__global const float* restrict sorted_lights, __global float* restrict nodes,
                             uint light_count, uint stride, uint leaf_count) {
  const uint leaf = get_global_id(0);
  float4 lo = (float4)(INFINITY), hi = (float4)(-INFINITY);
  if (leaf < leaf_count) {
    const uint first = leaf * LANES, last = min(first + LANES, light_count);
    for (uint i = first; i < last; ++i) {
      const float4 centre =
          (float4)(sorted_lights[i], sorted_lights[stride + i], sorted_lights[2 * (size_t)stride + i], 0.0f);
      const float radius = sorted_lights[3 * (size_t)stride + i];
      const float4 reach = (float4)(radius, radius, radius, 0.0f) + (fabs(centre) + radius) * BOX_PADDING;
      lo = fmin(lo, centre - reach);
      hi = fmax(hi, centre + reach);
    }
  }
  store_child_box(nodes + (size_t)(leaf / LANES) * NODE_FLOATS, leaf % LANES, lo, hi);
}

// Node n of a level (its 8 children's boxes at node_first + n) → its own box, stored as child
// n % 8 of node n / 8 of the level above (at parent_first).
__kernel void bvh_node_boxes(__global float* nodes, uint node_first, uint node_count, uint parent_first) {
  const uint node = get_global_id(0);
  float4 lo = (float4)(INFINITY), hi = (float4)(-INFINITY);
  if (node < node_count) {
    __global const float* children = nodes + (size_t)(node_first + node) * NODE_FLOATS;
    for (uint k = 0; k < LANES; ++k) {
      lo = fmin(lo, (float4)(children[0 * LANES + k], children[1 * LANES + k], children[2 * LANES + k], 0.0f));
      hi = fmax(hi, (float4)(children[3 * LANES + k], children[4 * LANES + k], children[5 * LANES + k], 0.0f));
    }
  }
  store_child_box(nodes + (size_t)(parent_first + node / LANES) * NODE_FLOATS, node % LANES, lo, hi);
}

// ---- light hierarchy: traversal, one work-item per cluster

inline uint overlapping_children(float4 lo, float4 hi, __global const float* restrict node) {
  const float8 min_x = vload8(0, node), min_y = vload8(1, node), min_z = vload8(2, node);
  const float8 max_x = vload8(3, node), max_y = vload8(4, node), max_z = vload8(5, node);
  return lane_bits((min_x <= hi.x) & (max_x >= lo.x) & (min_y <= hi.y) & (max_y >= lo.y) & (min_z <= hi.z) &
                   (max_z >= lo.z));
}

#define LEVEL_SHIFT 27u
#define NODE_MASK ((1u << LEVEL_SHIFT) - 1u)

// Depth-first traversal with a small stack of (level, node); level 0 = leaves (8-light blocks).
// Returns the number of lights that touch the box and writes the original indices of the first
// `limit` of them to out[0 .. limit), in sorted-light order. A leaf's hits are written 8 at once:
// compaction[bits] lists the set lanes of `bits` first (so `order` is read for `stride` lights).
inline uint bvh_traverse(float4 lo, float4 hi, __global const float* restrict nodes,
                         __global const float* restrict sorted_lights, __global const uint* restrict order,
                         __constant uchar8* compaction, uint stride, uint level_count, uint limit,
                         __global uint* restrict out) {
  uint level_first[BVH_MAX_LEVELS];  // node storage exists for levels ≥ 1
  uint size = stride / LANES;
  level_first[1] = 0;
  for (uint l = 1; l + 1 < level_count; ++l) {
    size = (size + LANES - 1) / LANES;
    level_first[l + 1] = level_first[l] + size;
  }
  uint stack[BVH_STACK];
  uint top = 0;
  stack[top++] = (level_count - 1u) << LEVEL_SHIFT;
  uint found = 0;
  while (top > 0) {
    const uint entry = stack[--top];
    const uint level = entry >> LEVEL_SHIFT, node = entry & NODE_MASK;
    if (level == 0) {
      uint bits = touching_lights(lo, hi, sorted_lights, stride, node);
      if (bits != 0 && found + LANES <= limit) {
        vstore8(shuffle(vload8(node, order), convert_uint8(compaction[bits])), 0, out + found);
        found += popcount(bits);
        continue;
      }
      for (; bits != 0 && found < limit; bits &= bits - 1u) out[found++] = order[node * LANES + lowest_bit(bits)];
      found += popcount(bits);
    } else {
      // Pushed highest first, so children are visited in ascending order.
      for (uint bits = overlapping_children(lo, hi, nodes + (size_t)(level_first[level] + node) * NODE_FLOATS);
           bits != 0;) {
        const uint child = 31u - clz(bits);
        bits &= ~(1u << child);
        stack[top++] = ((level - 1u) << LEVEL_SHIFT) | (node * LANES + child);
      }
    }
  }
  return found;
}

// Sorts a short list of n ≤ RANK_SORT_MAX distinct light indices ascending (the traversal finds
// them in Morton order): each value goes to the slot given by the number of smaller values,
// computed for 16 values at once against every value. Branch-free and vectorized, unlike a
// comparison sort's scalar loop on PoCL; O(n²), so longer lists use radix_sort_light_list.
inline void rank_sort_light_list(__global uint* restrict a, uint n) {
  uint list[RANK_SORT_MAX], slots[16];
  for (uint i = 0; i < n; ++i) list[i] = a[i];
  for (uint first = 0; first < n; first += 16u) {
    const uint16 values = vload16(0, list + first);  // lanes past n hold garbage and are not stored
    int16 rank = 0;                                   // −1 per smaller value
    for (uint j = 0; j < n; ++j) rank += list[j] < values;
    vstore16(as_uint16(-rank), 0, slots);
    for (uint k = 0; k < 16u && first + k < n; ++k) a[slots[k]] = list[first + k];
  }
}

// One traversal per cluster: counts[c] = number of lights; lists of up to `slot` lights are also
// stored in scratch[c·slot ...] for assign_bvh_place, sorted when short.
__kernel void assign_bvh_collect(__global const float4* restrict bounds, __global const float* restrict nodes,
                                 __global const float* restrict sorted_lights, __global const uint* restrict order,
                                 __constant uchar8* compaction, __global uint* restrict counts,
                                 __global uint* restrict scratch, uint clusters, uint stride, uint level_count,
                                 uint slot) {
  const uint c = get_global_id(0);
  if (c >= clusters) return;
  __global uint* list = scratch + (size_t)c * slot;
  const uint found = bvh_traverse(bounds[2 * (size_t)c], bounds[2 * (size_t)c + 1], nodes, sorted_lights, order,
                                  compaction, stride, level_count, slot, list);
  if (found <= min(slot, (uint)RANK_SORT_MAX)) rank_sort_light_list(list, found);
  counts[c] = found;
}

#define RADIX_DIGIT_BITS_MAX 11

// Sorts a long list of light indices below 2^index_bits ascending: stable LSD radix sort in two
// (or more) passes of at most RADIX_DIGIT_BITS_MAX bits, ping-ponging between a and temp (n
// entries each). O(n + buckets) per pass, where a comparison sort would be O(n log n) with
// PoCL's slow scalar loops.
inline void radix_sort_light_list(__global uint* a, __global uint* temp, uint n, uint index_bits) {
  const uint digit_bits = clamp((index_bits + 1u) / 2u, 1u, (uint)RADIX_DIGIT_BITS_MAX);
  const uint passes = (index_bits + digit_bits - 1u) / digit_bits, buckets = 1u << digit_bits;
  uint hist[1u << RADIX_DIGIT_BITS_MAX];
  __global uint* src = a;
  __global uint* dst = temp;
  for (uint pass = 0; pass < passes; ++pass) {
    const uint shift = pass * digit_bits;
    for (uint b = 0; b < buckets; ++b) hist[b] = 0;
    for (uint i = 0; i < n; ++i) ++hist[(src[i] >> shift) & (buckets - 1u)];
    uint running = 0;
    for (uint b = 0; b < buckets; ++b) {
      const uint count = hist[b];
      hist[b] = running;
      running += count;
    }
    for (uint i = 0; i < n; ++i) dst[hist[(src[i] >> shift) & (buckets - 1u)]++] = src[i];
    __global uint* swap = src;
    src = dst;
    dst = swap;
  }
  if (src != a)
    for (uint i = 0; i < n; ++i) a[i] = src[i];
}

// After the scan of the counts, each list goes to indices[offsets[c] ...]: copied from its scratch
// slot, or found again when it did not fit there; lists longer than RANK_SORT_MAX are then
// radix-sorted in place (with sort_scratch, laid out like indices).
__kernel void assign_bvh_place(__global const float4* restrict bounds, __global const float* restrict nodes,
                               __global const float* restrict sorted_lights, __global const uint* restrict order,
                               __constant uchar8* compaction, __global const uint* restrict counts,
                               __global const uint* restrict offsets, __global const uint* restrict scratch,
                               __global uint* restrict indices, __global uint* restrict sort_scratch,
                               uint clusters, uint stride, uint level_count, uint slot, uint index_bits) {
  const uint c = get_global_id(0);
  if (c >= clusters) return;
  const uint count = counts[c];
  __global uint* out = indices + offsets[c];
  if (count > slot) {
    bvh_traverse(bounds[2 * (size_t)c], bounds[2 * (size_t)c + 1], nodes, sorted_lights, order, compaction, stride,
                 level_count, count, out);
  } else {
    __global const uint* list = scratch + (size_t)c * slot;
    uint i = 0;
    for (; i + 16u <= count; i += 16u) vstore16(vload16(0, list + i), 0, out + i);
    for (; i < count; ++i) out[i] = list[i];
  }
  if (count > RANK_SORT_MAX) radix_sort_light_list(out, sort_scratch + offsets[c], count, index_bits);
}
