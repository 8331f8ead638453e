// Splat fit (the splat thesis §2.2.2–§2.2.3), one work-item per sample. Native reference: host/splats/reference.cpp,
// which performs the same float operations in the same order; the size rule, sort key, colour
// test and hull test are one source with it (splat_fit.h); contraction into fused
// multiply-adds is off so both round identically.
//
// Build options: LITERAL_LAMBDA (0/1), RETEST_VIOLATOR (0/1), CLIP (0/1), SIZE_AT_ACCEPTED (0/1),
// ON_HULL_BIT (uint). The growth cap is an argument (max_covered): the thesis's depends on the
// sample count, and a build option would compile the program again for every model.
#pragma OPENCL FP_CONTRACT OFF
#include "splat_fit.h"

typedef struct {
  float4 u, v, n;
} Frame;

inline float dot3(float4 a, float4 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

inline float4 cross3(float4 a, float4 b) {
  return (float4)(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x, 0.0f);
}

// Sign convention: the largest-magnitude component (first on ties) is positive.
inline float4 canonical_sign(float4 a) {
  float m = a.x;
  if (fabs(a.y) > fabs(m)) m = a.y;
  if (fabs(a.z) > fabs(m)) m = a.z;
  return m < 0.0f ? -a : a;
}

__kernel void splat_frames(__global const float4* positions, __global const float4* normals,
                           __global const uint* neighbors, uint k, __global const float* kth_distance,
                           float crease_cos, uint count, __global Frame* frames) {
  const size_t i = get_global_id(0);
  if (i >= count) return;
  const float4 p0 = positions[i];
  const float di = kth_distance[i];
  const float scale = di > 0.0f ? 1.0f / di : 1.0f;
  __global const uint* row = neighbors + i * (size_t)k;
  // The neighbours on the sample's side of a crease; with fewer than two there is no plane, and
  // every neighbour is taken.
  const float4 n0 = normals[i];
  uint taken = 0;
  for (uint r = 0; r < k; ++r) {
    const float4 nr = normals[row[r]];
    taken += splat_same_side_of_crease(n0.x, n0.y, n0.z, nr.x, nr.y, nr.z, crease_cos) ? 1u : 0u;
  }
  const bool take_all = taken < 2u || taken == k;
#define SPLAT_TAKEN(r) (take_all || splat_same_side_of_crease(n0.x, n0.y, n0.z, normals[row[r]].x, normals[row[r]].y, normals[row[r]].z, crease_cos))
  // Mean of the scaled offsets from p0 (p0 itself contributes zero).
  float mx = 0.0f, my = 0.0f, mz = 0.0f;
  for (uint r = 0; r < k; ++r) {
    if (!SPLAT_TAKEN(r)) continue;
    const float4 w = (positions[row[r]] - p0) * scale;
    mx += w.x, my += w.y, mz += w.z;
  }
  const float inv = 1.0f / (float)((take_all ? k : taken) + 1);
  mx *= inv, my *= inv, mz *= inv;
  float a[3][3];
  {
    float xx = mx * mx, xy = mx * my, xz = mx * mz, yy = my * my, yz = my * mz, zz = mz * mz;  // p0's term
    for (uint r = 0; r < k; ++r) {
      if (!SPLAT_TAKEN(r)) continue;
      const float4 w = (positions[row[r]] - p0) * scale;
      const float x = w.x - mx, y = w.y - my, z = w.z - mz;
      xx += x * x, xy += x * y, xz += x * z, yy += y * y, yz += y * z, zz += z * z;
    }
    a[0][0] = xx * inv, a[0][1] = xy * inv, a[0][2] = xz * inv;
    a[1][0] = xy * inv, a[1][1] = yy * inv, a[1][2] = yz * inv;
    a[2][0] = xz * inv, a[2][1] = yz * inv, a[2][2] = zz * inv;
  }
  float e[3][3] = {{1.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, {0.0f, 0.0f, 1.0f}};
  for (int sweep = 0; sweep < 10; ++sweep) {
    if (a[0][1] == 0.0f && a[0][2] == 0.0f && a[1][2] == 0.0f) break;
    for (int pair = 0; pair < 3; ++pair) {
      const int p = pair == 2 ? 1 : 0, q = pair == 0 ? 1 : 2;
      const float apq = a[p][q];
      if (apq == 0.0f) continue;
      const float theta = (a[q][q] - a[p][p]) / (2.0f * apq);
      float t = 1.0f / (fabs(theta) + sqrt(theta * theta + 1.0f));
      if (theta < 0.0f) t = -t;
      const float c = 1.0f / sqrt(t * t + 1.0f), s = t * c;
      for (int r = 0; r < 3; ++r) {
        const float arp = a[r][p], arq = a[r][q];
        a[r][p] = c * arp - s * arq;
        a[r][q] = s * arp + c * arq;
      }
      for (int r = 0; r < 3; ++r) {
        const float apr = a[p][r], aqr = a[q][r];
        a[p][r] = c * apr - s * aqr;
        a[q][r] = s * apr + c * aqr;
      }
      for (int r = 0; r < 3; ++r) {
        const float erp = e[r][p], erq = e[r][q];
        e[r][p] = c * erp - s * erq;
        e[r][q] = s * erp + c * erq;
      }
    }
  }
  // Order by descending eigenvalue, ties by column.
  int order[3] = {0, 1, 2};
  for (int x = 1; x < 3; ++x)
    for (int y = x; y > 0 && a[order[y]][order[y]] > a[order[y - 1]][order[y - 1]]; --y) {
      const int swap = order[y];
      order[y] = order[y - 1];
      order[y - 1] = swap;
    }
  float4 u = canonical_sign((float4)(e[0][order[0]], e[1][order[0]], e[2][order[0]], 0.0f));
  float4 v = canonical_sign((float4)(e[0][order[1]], e[1][order[1]], e[2][order[1]], 0.0f));
  float4 n = cross3(u, v);
  // Orientation: distance-weighted mean of the sample normals (weight exp(-3 |p_j - p_i| / d_i)) of
  // the neighbours in the frame: across a thin plate the other side's normals outweighed the
  // sample's own and turned its splat inside out.
  float4 m = normals[i];
  for (uint r = 0; r < k; ++r) {
    if (!SPLAT_TAKEN(r)) continue;
    const float4 w = positions[row[r]] - p0;
    const float d = sqrt(dot3(w, w));
    m += normals[row[r]] * exp(-3.0f * d * scale);
  }
#undef SPLAT_TAKEN
  {
    float fu[3] = {u.x, u.y, u.z}, fv[3] = {v.x, v.y, v.z}, fn[3] = {n.x, n.y, n.z};
    splat_frame_facing(fu, fv, fn, n0.x, n0.y, n0.z, crease_cos);
    u = (float4)(fu[0], fu[1], fu[2], 0.0f), v = (float4)(fv[0], fv[1], fv[2], 0.0f), n = (float4)(fn[0], fn[1], fn[2], 0.0f);
  }
  if (dot3(m, n) < 0.0f) u = -u, v = -v, n = -n;
  frames[i].u = u;
  frames[i].v = v;
  frames[i].n = n;
}

// ---------------------------------------------------------------------------------------------
// Growth. Scratch belongs to a worker (one work-item): seen and aux (seen_capacity entries each),
// ring keys (seen_capacity ulongs) and a hash set of seen samples (hash_mask + 1 entries); each
// grown splat (item s) writes its accepted set to q_slots[s * capacity ...] and its size to
// counts[s]. `seen` lists the samples in the order they were first seen, which is the walk's ring
// order: ring r and the next ring being collected are adjacent ranges of it, so no ring is ever
// copied. The hash set starts zeroed (the host fills it once) and is left zeroed, by removing
// exactly the listed samples: clearing the whole table per splat cost more than the walk on small
// splats. A splat that would accept more than `capacity` samples stops and reports capacity + 1;
// the host relaunches it with more.
//
// Two shapes (design.md): CPU (block > 0), a few workers each taking blocks of `block` consecutive
// items from a shared counter until none is left, so a worker's scratch stays in its core's cache
// from one splat to the next; GPU (block == 0), one item per work-item with its own scratch.

// A ring entry: the sort key (never -0 or NaN) in the high half, mapped so that unsigned order is
// float order, and the sample index in the low half: sorting the ulongs sorts by (key, index), the
// order of the reference's std::pair<float, uint32_t>.
inline ulong pack_key(float key, uint j) {
  const uint bits = as_uint(key + 0.0f);  // -0 → +0
  const uint ordered = (bits & 0x80000000u) ? ~bits : (bits | 0x80000000u);
  return ((ulong)ordered << 32) | (ulong)j;
}

inline float unpack_key(ulong packed) {
  const uint ordered = (uint)(packed >> 32);
  return as_float((ordered & 0x80000000u) ? (ordered & 0x7fffffffu) : ~ordered);
}

// Shell sort gaps (Ciura's, extended by ×2.25), largest first.
__constant uint kGaps[] = {1035711u, 460316u, 204585u, 90927u, 40412u, 17961u, 7983u, 3548u, 1577u,
                           701u,     301u,    132u,    57u,    23u,    10u,    4u,    1u};

// Sorts a[0..n) ascending: shell sort, in place, no recursion.
void sort_packed(__global ulong* a, uint n) {
  for (uint g = 0; g < sizeof(kGaps) / sizeof(kGaps[0]); ++g) {
    const uint gap = kGaps[g];
    if (gap >= n) continue;
    for (uint x = gap; x < n; ++x) {
      const ulong value = a[x];
      uint y = x;
      for (; y >= gap && a[y - gap] > value; y -= gap) a[y] = a[y - gap];
      a[y] = value;
    }
  }
}

// Sorts (xs, ys, idx)[0..n) by (x, y, idx) ascending, as the reference's std::tuple sort: shell sort.
inline bool point_less(float ax, float ay, uint ai, float bx, float by, uint bi) {
  if (ax != bx) return ax < bx;
  if (ay != by) return ay < by;
  return ai < bi;
}

void sort_points(__global float* xs, __global float* ys, __global uint* idx, uint n) {
  for (uint g = 0; g < sizeof(kGaps) / sizeof(kGaps[0]); ++g) {
    const uint gap = kGaps[g];
    if (gap >= n) continue;
    for (uint x = gap; x < n; ++x) {
      const float vx = xs[x], vy = ys[x];
      const uint vi = idx[x];
      uint y = x;
      for (; y >= gap && point_less(vx, vy, vi, xs[y - gap], ys[y - gap], idx[y - gap]); y -= gap) {
        xs[y] = xs[y - gap], ys[y] = ys[y - gap], idx[y] = idx[y - gap];
      }
      xs[y] = vx, ys[y] = vy, idx[y] = vi;
    }
  }
}

// Inserts sample j into the open-addressing set; true when it was not there yet.
inline bool seen_insert(__global uint* table, uint mask, uint j) {
  uint h = (j * 2654435761u) & mask;
  for (;;) {
    const uint entry = table[h];
    if (entry == 0u) {
      table[h] = j + 1u;
      return true;
    }
    if (entry == j + 1u) return false;
    h = (h + 1u) & mask;
  }
}

// Empties the set by removing `list`. A removal can break the probe chain of a later entry, so
// each lookup scans on past empty slots until it meets its entry (which is always there).
void seen_clear(__global uint* table, uint mask, __global const uint* list, uint count) {
  for (uint r = count; r-- > 0;) {
    uint h = (list[r] * 2654435761u) & mask;
    while (table[h] != list[r] + 1u) h = (h + 1u) & mask;
    table[h] = 0u;
  }
}

// Grows the splat of item s (sample items[s]) with one worker's scratch.
void grow_one(__global const float4* positions, __global const float4* normals, __global const uchar4* colors,
              __global const uint* neighbors, uint k, __global const Frame* frames, float crease_cos, float eps,
              int color_tolerance, uint max_covered, uint i, uint capacity, uint hash_mask,
              __global uint* q, __global uint* seen, __global ulong* ring, __global uint* aux, __global uint* table,
              __global uint* count_out, __global float4* splats, __global float4* clips) {
  __global uint* rejected = aux;  // clipped splats: the skipped violators
  const float4 p0 = positions[i];
  const float4 n0 = normals[i];
  const uchar4 c0 = colors[i];
  const Frame f = frames[i];
  const float two_eps = 2.0f * eps;
  float hmin = 0.0f, hmax = 0.0f;
  uint qn = 0;
  q[qn++] = i;
  seen_insert(table, hash_mask, i);
  seen[0] = i;
  // The ring is seen[ring_begin, ring_end); the next ring collects in seen[ring_end, seen_len).
  uint ring_begin = 1, ring_end = 1, seen_len = 1, pos = 0;
  for (uint r = 0; r < k; ++r) {
    const uint j = neighbors[(size_t)i * k + r];
    if (seen_insert(table, hash_mask, j)) seen[seen_len++] = j;
  }
  ring_end = seen_len;

  // Per phase: the largest accepted key (d1, λ1), the violator's key (d2, λ2) and what stopped it.
  float circle_extent1 = 0.0f, circle_extent2 = -1.0f;
  int circle_stop = STOP_NONE;
  float extent1 = 0.0f, extent2 = -1.0f;
  int stop = STOP_NONE;
  float b = 0.0f;
  float clip_x = 0.0f, clip_y = 0.0f;  // sum of the unit in-plane directions to the skipped violators
  uint rejected_count = 0;
  bool full = false;  // Q reached max_covered: both phases end as if no violator was met
  for (int ellipse = 0; ellipse < 2; ++ellipse) {
    if (ellipse) {
      circle_extent1 = extent1, circle_extent2 = extent2, circle_stop = stop;
      extent1 = 1.0f, extent2 = -1.0f, stop = STOP_NONE;
      // Continue with the untested rest of the circle's last ring and the collected next ring.
      b = RETEST_VIOLATOR ? circle_extent1 : splat_size_rule(circle_extent1, circle_extent2, circle_stop, SIZE_AT_ACCEPTED);
      ring_begin = circle_stop != STOP_NONE ? (RETEST_VIOLATOR ? pos : pos + 1u) : seen_len;
      ring_end = seen_len;
      if (full) break;
    }
    for (;;) {
      for (uint r = ring_begin; r < ring_end; ++r) {
        const uint j = seen[r];
        const float4 w = positions[j] - p0;
        ring[r] = pack_key(splat_growth_key(ellipse, dot3(f.u, w), dot3(f.v, w), b), j);
      }
      sort_packed(ring + ring_begin, ring_end - ring_begin);
      for (uint r = ring_begin; r < ring_end; ++r) seen[r] = (uint)ring[r];
      bool stopped = false;
      for (pos = ring_begin; pos < ring_end; ++pos) {
        const float key = unpack_key(ring[pos]);
        if (ellipse && key < 1.0f) continue;  // λ < 1: neither tested, accepted nor expanded
        const uint j = seen[pos];
        const float4 w = positions[j] - p0;
        const float h = dot3(f.n, w);
        const float4 nj = normals[j];
        if (splat_other_sheet(n0.x, n0.y, n0.z, nj.x, nj.y, nj.z, h, crease_cos)) continue;
        const float lo = fmin(hmin, h), hi = fmax(hmax, h);
        const uchar4 cj = colors[j];
        const int violation = !splat_color_similar(cj.x, cj.y, cj.z, c0.x, c0.y, c0.z, color_tolerance) ? STOP_COLOR
                              : hi - lo > two_eps                             ? STOP_GEOMETRY
                                                                              : STOP_NONE;
        if (violation != STOP_NONE) {
#if CLIP
          // §3.13: a violator within 90° of the mean rejected direction is skipped and growth goes on.
          const float wx = dot3(f.u, w), wy = dot3(f.v, w);
          const float len = sqrt(wx * wx + wy * wy);
          if (len > 0.0f && (rejected_count == 0 || wx * clip_x + wy * clip_y > 0.0f)) {
            clip_x += wx / len, clip_y += wy / len;
            rejected[rejected_count++] = j;
            continue;
          }
#endif
          stop = violation, extent2 = key, stopped = true;
          break;
        }
        if (qn == max_covered) {
          full = true;
          break;
        }
        if (qn == capacity) {
          seen_clear(table, hash_mask, seen, seen_len);
          *count_out = capacity + 1u;
          return;
        }
        hmin = lo, hmax = hi;
        q[qn++] = j;
        extent1 = fmax(extent1, key);
        __global const uint* row = neighbors + (size_t)j * k;
        for (uint r = 0; r < k; ++r)
          if (seen_insert(table, hash_mask, row[r])) seen[seen_len++] = row[r];
      }
      if (stopped || full || seen_len == ring_end) break;
      ring_begin = ring_end, ring_end = seen_len;
    }
  }
  seen_clear(table, hash_mask, seen, seen_len);

  const float minor = splat_size_rule(circle_extent1, circle_extent2, circle_stop, SIZE_AT_ACCEPTED);
#if LITERAL_LAMBDA
  const float ratio = splat_size_rule(extent1, extent2, stop, SIZE_AT_ACCEPTED);
#else
  const float ratio = splat_size_rule(sqrt(extent1), extent2 >= 0.0f ? sqrt(extent2) : -1.0f, stop, SIZE_AT_ACCEPTED);
#endif
  const float major = ratio * minor;
  const float4 c = p0 + f.n * (0.5f * (hmin + hmax));
  splats[4 * (size_t)i + 0] = (float4)(c.xyz, (float)circle_stop);
  splats[4 * (size_t)i + 1] = (float4)(f.n.xyz, (float)stop);
  splats[4 * (size_t)i + 2] = (float4)((f.u * major).xyz, major);
  splats[4 * (size_t)i + 3] = (float4)((f.v * minor).xyz, minor);
  float4 clip = (float4)(0.0f, 0.0f, INFINITY, 0.0f);
#if CLIP
  // Clip line perpendicular to the mean rejected direction, halfway between the farthest accepted
  // and the nearest skipped sample along it (never cutting off an accepted one).
  const float clip_len = sqrt(clip_x * clip_x + clip_y * clip_y);
  if (rejected_count > 0 && clip_len > 0.0f) {
    const float dx = clip_x / clip_len, dy = clip_y / clip_len;
    float accepted_reach = -INFINITY, rejected_reach = INFINITY;
    for (uint r = 0; r < qn; ++r) {
      const float4 w = positions[q[r]] - c;
      accepted_reach = fmax(accepted_reach, dx * dot3(f.u, w) + dy * dot3(f.v, w));
    }
    for (uint r = 0; r < rejected_count; ++r) {
      const float4 w = positions[rejected[r]] - c;
      rejected_reach = fmin(rejected_reach, dx * dot3(f.u, w) + dy * dot3(f.v, w));
    }
    const float offset = rejected_reach > accepted_reach ? accepted_reach + 0.5f * (rejected_reach - accepted_reach) : accepted_reach;
    clip = (float4)(dx, dy, offset, 0.0f);
  }
#endif
  clips[i] = clip;

  // Safe points: the projections of Q sorted, then splat_mark_hull; |Q| <= 3 stays unmarked.
  if (qn > 3) {
    __global float* xs = (__global float*)ring;
    __global float* ys = (__global float*)aux;
    __global uint* order = seen;
    __global uint* hull = table;  // empty now; cleared again below
    float lo_x = INFINITY, hi_x = -INFINITY, lo_y = INFINITY, hi_y = -INFINITY;
    for (uint r = 0; r < qn; ++r) {
      const float4 w = positions[q[r]] - c;
      xs[r] = dot3(f.u, w), ys[r] = dot3(f.v, w), order[r] = r;
      lo_x = fmin(lo_x, xs[r]), hi_x = fmax(hi_x, xs[r]), lo_y = fmin(lo_y, ys[r]), hi_y = fmax(hi_y, ys[r]);
    }
    sort_points(xs, ys, order, qn);
    splat_mark_hull(xs, ys, order, qn, fmax(hi_x - lo_x, hi_y - lo_y), hull, q, ON_HULL_BIT);
    // The chain pushes at most 2 qn entries before its pops; empty every slot it may have written.
    for (uint r = 0; r < min(2u * qn, hash_mask + 1u); ++r) hull[r] = 0u;
  }
  *count_out = qn;
}

__kernel void splat_grow(__global const float4* positions, __global const float4* normals,
                         __global const uchar4* colors, __global const uint* neighbors, uint k,
                         __global const Frame* frames, float crease_cos, float eps,
                         int color_tolerance, uint max_covered, __global const uint* items, uint item_count, uint capacity,
                         uint seen_capacity, uint hash_mask, uint block, __global uint* next_block,
                         __global uint* q_slots, __global uint* seen_slots, __global ulong* ring_slots,
                         __global uint* aux_slots, __global uint* hash_slots, __global uint* counts,
                         __global float4* splats, __global float4* clips) {
  const size_t w = get_global_id(0);
  __global uint* seen = seen_slots + w * seen_capacity;
  __global ulong* ring = ring_slots + w * seen_capacity;
  __global uint* aux = aux_slots + w * seen_capacity;
  __global uint* table = hash_slots + w * (hash_mask + 1u);
  if (block == 0u) {
    if (w < item_count)
      grow_one(positions, normals, colors, neighbors, k, frames, crease_cos, eps, color_tolerance, max_covered, items[w], capacity, hash_mask,
               q_slots + w * capacity, seen, ring, aux, table, counts + w, splats, clips);
    return;
  }
  for (;;) {
    const uint begin = atomic_add(next_block, block);
    if (begin >= item_count) return;
    const uint end = min(item_count, begin + block);
    for (uint s = begin; s < end; ++s)
      grow_one(positions, normals, colors, neighbors, k, frames, crease_cos, eps, color_tolerance, max_covered, items[s], capacity, hash_mask,
               q_slots + (size_t)s * capacity, seen, ring, aux, table, counts + s, splats, clips);
  }
}
