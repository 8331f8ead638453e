// Coherent shadow maps, queries: map selection, projection, segment search, depth test, PCF and
// ambient occlusion for a set of occluder instances. Written once, in the common subset of OpenCL C
// and C++ (scalar floats, + − × ÷ √ and comparisons only, no contraction), so the kernels
// (csm_visibility.cl, csm_ao.cl) and the native references (host/csm/visibility.cpp, ao.cpp, which
// include this file inside a namespace) execute the same float operations and agree exactly.
//
// Conventions: docs/formats.md (.csm geometry) and compression digest §5; AO digest §5.2–§5.8 with
// its errata resolutions (nearest camera by rounding with φ wrap, d = 2(h·s)h − s, lower-bound
// segment search, never-occluding +∞ for empty runs).
#ifndef SPLATCL_CSM_QUERY_H
#define SPLATCL_CSM_QUERY_H

#ifdef __OPENCL_C_VERSION__
#pragma OPENCL FP_CONTRACT OFF
#define CSM_GLOBAL global
#define csm_sqrt sqrt
#else
#define CSM_GLOBAL
#define csm_sqrt std::sqrt
#endif

#define CSM_FILTER_NONE 0u
#define CSM_FILTER_SAME_MAP 1u   // 4 × 4 texels of the selected map (16 taps)
#define CSM_FILTER_CROSS_MAP 2u  // 2 × 2 texels in each of the 4 nearest maps (16 taps)

// One grid cell's camera (object space) and its position in the map sequence.
typedef struct {
  float d[3], u[3], v[3];
  uint sequence;
} CsmCell;

// One coherent shadow map (an occluder type), shared by all its instances.
typedef struct {
  float centre[3], radius;
  float pixel_scale;  // M / 2R: object units → pixels
  float depth_scale;  // 1 / 2R: object units → depth
  uint resolution, rows, cols;
  uint centred;    // 1: cell-centred samples (uniform, regular); 0: corner samples (ao grid)
  uint uniform;    // 1: s = (1 − cosθ)/2; 0: s = θ/π
  uint cell_base;  // first entry of this map's cells, row-major over (θ cell, φ cell)
  uint pixel_base; // first entry of this map's offsets (M² + 1 of them, segment indices global)
} CsmOccluder;

// One placed occluder: world point → object space (row-major 3 × 4) and world direction → sphere
// frame (3 × 3, the pole frame times the linear part), both computed on the host in double.
typedef struct {
  float to_object[12];
  float to_frame[9];
  uint occluder;
} CsmInstance;

typedef struct {
  CSM_GLOBAL const CsmInstance* instances;
  uint instance_count;
  CSM_GLOBAL const CsmOccluder* occluders;
  CSM_GLOBAL const CsmCell* cells;
  CSM_GLOBAL const uint* offsets;
  CSM_GLOBAL const uint* ends;
  CSM_GLOBAL const float* depths;
} CsmScene;

// floor() for |v| well inside the int range.
inline int csm_floor(float v) {
  const int i = (int)v;
  return v < (float)i ? i - 1 : i;
}

// atan2 from basic operations only (Cephes atanf after reduction to [0, tan π/8]); about 1e-7 rad.
inline float csm_atan2(float y, float x) {
  const float ax = x < 0.0f ? -x : x, ay = y < 0.0f ? -y : y;
  if (ax == 0.0f && ay == 0.0f) return 0.0f;
  const int swapped = ay > ax;
  const float q = swapped ? ax / ay : ay / ax;
  float base = 0.0f, r = q;
  if (q > 0.41421356f) {
    base = 0.78539816f;
    r = (q - 1.0f) / (q + 1.0f);
  }
  const float z = r * r;
  float a = base + ((((8.05374449538e-2f * z - 1.38776856032e-1f) * z + 1.99777106478e-1f) * z - 3.33329491539e-1f) * z * r + r);
  if (swapped) a = 1.57079633f - a;
  if (x < 0.0f) a = 3.14159265f - a;
  return y < 0.0f ? -a : a;
}

// Continuous grid coordinates of a sphere-frame direction (compression digest §5.1, the inverse
// of the distribution): sr = s·rows, tc = t·cols with t = φ/2π ∈ [0, 1). Returns 0 for a zero or
// non-finite direction (a light at the receiver), which the callers treat as lit.
inline int csm_grid_coords(CSM_GLOBAL const CsmOccluder* oc, float x, float y, float z, float* sr, float* tc) {
  const float rho2 = x * x + z * z, len2 = rho2 + y * y;
  if (!(len2 > 0.0f) || !(len2 < INFINITY)) return 0;
  const float s = oc->uniform ? (1.0f - y / csm_sqrt(len2)) * 0.5f : csm_atan2(csm_sqrt(rho2), y) * 0.318309886f;
  float t = csm_atan2(x, z) * 0.159154943f;
  if (t < 0.0f) t += 1.0f;
  *sr = s * (float)oc->rows;
  *tc = t * (float)oc->cols;
  return 1;
}

inline uint csm_clamp_row(CSM_GLOBAL const CsmOccluder* oc, int a) {
  return a < 0 ? 0u : (a >= (int)oc->rows ? oc->rows - 1u : (uint)a);
}

inline uint csm_wrap_col(CSM_GLOBAL const CsmOccluder* oc, int b) {
  const int cols = (int)oc->cols;
  return (uint)(((b % cols) + cols) % cols);
}

// Stored depth of (pixel, map at `sequence`): the first segment whose inclusive end is >= sequence.
inline float csm_fetch(const CsmScene* scene, uint pixel_entry, uint sequence) {
  uint lo = scene->offsets[pixel_entry], hi = scene->offsets[pixel_entry + 1u] - 1u;
  while (lo < hi) {
    const uint mid = (lo + hi) >> 1;
    if (scene->ends[mid] >= sequence) hi = mid;
    else lo = mid + 1u;
  }
  return scene->depths[lo];
}

// Lit taps among width × width texels of one map around the receiver (rx, ry, rz relative to the
// sphere centre). width 1: the texel containing the receiver; width 2 or 4: the texels whose centres
// surround it. Texels outside the map are lit (the occluder cannot block there).
inline float csm_map_taps(const CsmScene* scene, CSM_GLOBAL const CsmOccluder* oc, CSM_GLOBAL const CsmCell* cell,
                          float rx, float ry, float rz, int width, float bias) {
  const float x = rx * cell->u[0] + ry * cell->u[1] + rz * cell->u[2];
  const float y = rx * cell->v[0] + ry * cell->v[1] + rz * cell->v[2];
  const float depth = (oc->radius - (rx * cell->d[0] + ry * cell->d[1] + rz * cell->d[2])) * oc->depth_scale;
  const float m = (float)oc->resolution;
  float fx = (x + oc->radius) * oc->pixel_scale, fy = (y + oc->radius) * oc->pixel_scale;
  // Far outside (or NaN): clamp before converting to int; every tap is then outside, hence lit.
  if (!(fx >= -8.0f)) fx = -8.0f;
  if (!(fx <= m + 8.0f)) fx = m + 8.0f;
  if (!(fy >= -8.0f)) fy = -8.0f;
  if (!(fy <= m + 8.0f)) fy = m + 8.0f;
  const int i0 = width == 1 ? csm_floor(fx) : csm_floor(fx - 0.5f) - (width / 2 - 1);
  const int j0 = width == 1 ? csm_floor(fy) : csm_floor(fy - 0.5f) - (width / 2 - 1);
  const int res = (int)oc->resolution;
  const float limit = depth - bias;
  float lit = 0.0f;
  for (int j = j0; j < j0 + width; ++j)
    for (int i = i0; i < i0 + width; ++i) {
      if (i < 0 || i >= res || j < 0 || j >= res) {
        lit += 1.0f;
        continue;
      }
      const float g = csm_fetch(scene, oc->pixel_base + (uint)j * oc->resolution + (uint)i, cell->sequence);
      lit += g < limit ? 0.0f : 1.0f;
    }
  return lit;
}

// Fraction of lit taps for one instance: receiver p (world), light vector w = q − p (world).
inline float csm_instance_visibility(const CsmScene* scene, uint k, float px, float py, float pz, float wx, float wy,
                                     float wz, uint filter, float bias) {
  CSM_GLOBAL const CsmInstance* in = scene->instances + k;
  CSM_GLOBAL const CsmOccluder* oc = scene->occluders + in->occluder;
  CSM_GLOBAL const float* m = in->to_object;
  CSM_GLOBAL const float* f = in->to_frame;
  const float rx = m[0] * px + m[1] * py + m[2] * pz + m[3] - oc->centre[0];
  const float ry = m[4] * px + m[5] * py + m[6] * pz + m[7] - oc->centre[1];
  const float rz = m[8] * px + m[9] * py + m[10] * pz + m[11] - oc->centre[2];
  const float fx = f[0] * wx + f[1] * wy + f[2] * wz;
  const float fy = f[3] * wx + f[4] * wy + f[5] * wz;
  const float fz = f[6] * wx + f[7] * wy + f[8] * wz;
  float sr = 0.0f, tc = 0.0f;
  if (!csm_grid_coords(oc, fx, fy, fz, &sr, &tc)) return 1.0f;
  CSM_GLOBAL const CsmCell* cells = scene->cells + oc->cell_base;
  // Sample positions: s·rows − 0.5 on a cell-centred grid, s·rows on the ao grid's corners.
  const float corner_shift = oc->centred ? 0.5f : 0.0f;
  if (filter == CSM_FILTER_CROSS_MAP) {
    const int a0 = csm_floor(sr - corner_shift), b0 = csm_floor(tc - corner_shift);
    float lit = 0.0f;
    for (int da = 0; da < 2; ++da)
      for (int db = 0; db < 2; ++db)
        lit += csm_map_taps(scene, oc, cells + csm_clamp_row(oc, a0 + da) * oc->cols + csm_wrap_col(oc, b0 + db), rx, ry, rz, 2,
                            bias);
    return lit * 0.0625f;
  }
  const uint a = csm_clamp_row(oc, csm_floor(sr + (0.5f - corner_shift)));
  const uint b = csm_wrap_col(oc, csm_floor(tc + (0.5f - corner_shift)));
  if (filter == CSM_FILTER_SAME_MAP) return csm_map_taps(scene, oc, cells + a * oc->cols + b, rx, ry, rz, 4, bias) * 0.0625f;
  return csm_map_taps(scene, oc, cells + a * oc->cols + b, rx, ry, rz, 1, bias);
}

// Visibility of light vector w from receiver p through every instance: the product of the
// instances' lit fractions (compression digest §5.5: lit only if every test passes; with PCF each
// instance contributes its fraction). Stops at the first fully occluding instance.
inline float csm_visibility(const CsmScene* scene, float px, float py, float pz, float wx, float wy, float wz, uint filter,
                            float bias) {
  float lit = 1.0f;
  for (uint k = 0; k < scene->instance_count && lit > 0.0f; ++k)
    lit *= csm_instance_visibility(scene, k, px, py, pz, wx, wy, wz, filter, bias);
  return lit;
}

// What a run of filter-free queries through one instance can reuse from the query before: the map
// chosen for the same light vector, and the stored depth of the same (pixel, map). Coherent batches
// (a screen of receivers, one light or a small area light) hit both most of the time.
typedef struct {
  float wx, wy, wz;  // light vector of the cached map choice
  int valid;         // 1: wx, wy, wz hold a light vector whose choice is cached
  int lit;           // 1: that light vector is zero or non-finite (always lit)
  uint cell;         // cells index of the chosen map
  uint entry, sequence;  // cached (pixel entry, map) ...
  float g;               // ... and its stored depth (entry == UINT_MAX: none)
} CsmQueryCache;

inline void csm_cache_reset(CsmQueryCache* cache) {
  cache->valid = 0;
  cache->entry = 0xffffffffu;
}

// csm_instance_visibility(scene, k, p, w, CSM_FILTER_NONE, bias), exactly, reusing `cache`.
inline float csm_instance_visibility_cached(const CsmScene* scene, uint k, float px, float py, float pz, float wx, float wy,
                                            float wz, float bias, CsmQueryCache* cache) {
  CSM_GLOBAL const CsmInstance* in = scene->instances + k;
  CSM_GLOBAL const CsmOccluder* oc = scene->occluders + in->occluder;
  if (!(cache->valid && wx == cache->wx && wy == cache->wy && wz == cache->wz)) {
    CSM_GLOBAL const float* f = in->to_frame;
    const float fx = f[0] * wx + f[1] * wy + f[2] * wz;
    const float fy = f[3] * wx + f[4] * wy + f[5] * wz;
    const float fz = f[6] * wx + f[7] * wy + f[8] * wz;
    float sr = 0.0f, tc = 0.0f;
    cache->lit = !csm_grid_coords(oc, fx, fy, fz, &sr, &tc);
    const float corner_shift = oc->centred ? 0.5f : 0.0f;
    const uint a = csm_clamp_row(oc, csm_floor(sr + (0.5f - corner_shift)));
    const uint b = csm_wrap_col(oc, csm_floor(tc + (0.5f - corner_shift)));
    cache->cell = oc->cell_base + a * oc->cols + b;
    cache->wx = wx;
    cache->wy = wy;
    cache->wz = wz;
    // NaN never equals itself: such a vector is recomputed each time (and is lit).
    cache->valid = 1;
  }
  if (cache->lit) return 1.0f;
  CSM_GLOBAL const float* m = in->to_object;
  const float rx = m[0] * px + m[1] * py + m[2] * pz + m[3] - oc->centre[0];
  const float ry = m[4] * px + m[5] * py + m[6] * pz + m[7] - oc->centre[1];
  const float rz = m[8] * px + m[9] * py + m[10] * pz + m[11] - oc->centre[2];
  CSM_GLOBAL const CsmCell* cell = scene->cells + cache->cell;
  // csm_map_taps with width 1.
  const float x = rx * cell->u[0] + ry * cell->u[1] + rz * cell->u[2];
  const float y = rx * cell->v[0] + ry * cell->v[1] + rz * cell->v[2];
  const float depth = (oc->radius - (rx * cell->d[0] + ry * cell->d[1] + rz * cell->d[2])) * oc->depth_scale;
  const float mres = (float)oc->resolution;
  float tx = (x + oc->radius) * oc->pixel_scale, ty = (y + oc->radius) * oc->pixel_scale;
  if (!(tx >= -8.0f)) tx = -8.0f;
  if (!(tx <= mres + 8.0f)) tx = mres + 8.0f;
  if (!(ty >= -8.0f)) ty = -8.0f;
  if (!(ty <= mres + 8.0f)) ty = mres + 8.0f;
  const int i = csm_floor(tx), j = csm_floor(ty), res = (int)oc->resolution;
  if (i < 0 || i >= res || j < 0 || j >= res) return 1.0f;
  const uint entry = oc->pixel_base + (uint)j * oc->resolution + (uint)i;
  if (entry != cache->entry || cell->sequence != cache->sequence) {
    cache->g = csm_fetch(scene, entry, cell->sequence);
    cache->entry = entry;
    cache->sequence = cell->sequence;
  }
  return cache->g < depth - bias ? 0.0f : 1.0f;
}

// Ambient occlusion of one receiver (AO digest §5.2): `samples` cosine-weighted directions of one
// pattern (+y hemisphere, xyz of 4 floats each) rotated into the normal's hemisphere by the 180°
// rotation about h = normalize(n + o), o = +y (d = 2(h·s)h − s, digest §16 #2; h = (1, 0, 0) when
// n = −o). With `ground`, directions below the world floor (d.y < 0) are occluded without a test.
// out = (bent normal xyz, AO = lit fraction); the bent normal is n when nothing is lit.
inline void csm_ambient_occlusion(const CsmScene* scene, CSM_GLOBAL const float* pattern, uint samples, float px, float py,
                                  float pz, float nx, float ny, float nz, uint ground, float bias, float* out) {
  float hx = nx, hy = ny + 1.0f, hz = nz;
  const float hlen = csm_sqrt(hx * hx + hy * hy + hz * hz);
  if (hlen > 1e-6f) {
    hx = hx / hlen;
    hy = hy / hlen;
    hz = hz / hlen;
  } else {
    hx = 1.0f;
    hy = 0.0f;
    hz = 0.0f;
  }
  float lit = 0.0f, bx = 0.0f, by = 0.0f, bz = 0.0f;
  for (uint k = 0; k < samples; ++k) {
    const float sx = pattern[4u * k], sy = pattern[4u * k + 1u], sz = pattern[4u * k + 2u];
    const float twice = 2.0f * (hx * sx + hy * sy + hz * sz);
    const float dx = twice * hx - sx, dy = twice * hy - sy, dz = twice * hz - sz;
    if (ground && dy < 0.0f) continue;
    if (csm_visibility(scene, px, py, pz, dx, dy, dz, CSM_FILTER_NONE, bias) > 0.0f) {
      lit += 1.0f;
      bx += dx;
      by += dy;
      bz += dz;
    }
  }
  const float blen = csm_sqrt(bx * bx + by * by + bz * bz);
  if (lit > 0.0f && blen > 0.0f) {
    out[0] = bx / blen;
    out[1] = by / blen;
    out[2] = bz / blen;
  } else {
    out[0] = nx;
    out[1] = ny;
    out[2] = nz;
  }
  out[3] = lit / (float)samples;
}

#endif  // SPLATCL_CSM_QUERY_H
