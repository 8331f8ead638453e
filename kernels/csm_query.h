// Coherent shadow maps, queries: map selection, projection, segment search, depth test, PCF and
// ambient occlusion for a set of occluder instances. Written once, in the common subset of OpenCL C
// and C++ (scalar floats, + − × ÷ √ and comparisons only, no contraction), so the kernels
// (csm_visibility.cl, csm_ao.cl) and the native references (host/csm/visibility.cpp, ao.cpp, which
// include this file inside a namespace) execute the same float operations and agree exactly.
//
// Conventions: docs/formats.md (.csm geometry) and Talpe §4.3–§4.4.1; Müller §5.3 with
// our resolutions where it is ambiguous (nearest camera by rounding with φ wrap, d = 2(h·s)h − s, lower-bound
// segment search, never-occluding +∞ for empty runs). The nearest camera is found by exact tests
// against the cell boundaries (csm_walk_cell): same cells as rounding the continuous grid
// coordinates up to float rounding at a boundary, but with no atan2 and, for coherent queries
// walking from the previous query's cell, no root or division either.
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

#include "csm_inline.h"

// Light vectors whose squared length is below the smallest normal float (|w| < 1.1e-19) are lit,
// like a zero one: a device that flushes denormals reads that square as 0, the host does not.
#define CSM_MIN_LEN2 1.17549435e-38f

#define CSM_FILTER_NONE 0u
#define CSM_FILTER_SAME_MAP 1u   // 4 × 4 texels of the selected map (16 taps)
#define CSM_FILTER_CROSS_MAP 2u  // 2 × 2 texels in each of the 4 nearest maps (16 taps)
#define CSM_FILTER_MARCH 3u      // the true light ray through the 4 nearest maps' texels (csm_march_vote)
// csm_march_taps: a step between neighbouring texels' stored depths that a ray passes from behind
// to in front by at most this many texels counts as the inside of a solid, a larger one as a
// silhouette. The depth a two-hit texel stores lies anywhere between its first and second hit
// (the run's common interval, Talpe §5.2), so neighbouring texels of one solid step by up to its
// thickness, and so do a steep surface's; 4 and 8 gave the fewest wrong answers against ray
// casting, larger values more false shadows past silhouettes, and 4 left lit holes in the middle of
// a cube's floor shadow, 8 few (docs/results/csm.md, *Filter march*).
#define CSM_MARCH_JUMP_TEXELS 8.0f

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
  float texel_depth;  // 1 / M: one texel's width in depth units (a query's bias is in texels)
  uint resolution, rows, cols;
  uint centred;    // 1: cell-centred samples (uniform, regular); 0: corner samples (ao grid)
  uint uniform;    // 1: s = (1 − cosθ)/2; 0: s = θ/π
  uint cell_base;  // first entry of this map's cells, row-major over (θ cell, φ cell)
  uint pixel_base; // first entry of this map's offsets (M² + 1 of them, segment indices global)
  // Cell boundaries for the map choice (csm_select_cell), from bounds[bound_base]: rows − 1 θ
  // boundaries between rows k − 1 and k (k = 1 … rows − 1), then the φ boundaries β_1 … β_K in
  // increasing φ (K = col_bounds: cols − 1 on cell-centred grids, cols on the ao grid, whose
  // column 0 straddles φ = 0). Each is stored as the signed square c·|c| of its cosine (cosθ_k;
  // cosβ_k), so the tests need no root. The first half_cols φ boundaries lie in [0, π].
  uint bound_base, col_bounds, half_cols;
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
  CSM_GLOBAL const float* bounds;  // every occluder's cell boundaries (CsmOccluder::bound_base)
} CsmScene;

// floor() for |v| well inside the int range.
CSM_INLINE int csm_floor(float v) {
  const int i = (int)v;
  return v < (float)i ? i - 1 : i;
}

// atan2 from basic operations only (Cephes atanf after reduction to [0, tan π/8]); about 1e-7 rad.
CSM_INLINE float csm_atan2(float y, float x) {
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

// Continuous grid coordinates of a sphere-frame direction (Talpe §4.3, the inverse
// of the distribution): sr = s·rows, tc = t·cols with t = φ/2π ∈ [0, 1). Returns 0 for a zero or
// non-finite direction (a light at the receiver), which the callers treat as lit.
CSM_INLINE int csm_grid_coords(CSM_GLOBAL const CsmOccluder* oc, float x, float y, float z, float* sr, float* tc) {
  const float rho2 = x * x + z * z, len2 = rho2 + y * y;
  if (!(len2 >= CSM_MIN_LEN2) || !(len2 < INFINITY)) return 0;
  const float s = oc->uniform ? (1.0f - y / csm_sqrt(len2)) * 0.5f : csm_atan2(csm_sqrt(rho2), y) * 0.318309886f;
  float t = csm_atan2(x, z) * 0.159154943f;
  if (t < 0.0f) t += 1.0f;
  *sr = s * (float)oc->rows;
  *tc = t * (float)oc->cols;
  return 1;
}

CSM_INLINE uint csm_clamp_row(CSM_GLOBAL const CsmOccluder* oc, int a) {
  return a < 0 ? 0u : (a >= (int)oc->rows ? oc->rows - 1u : (uint)a);
}

// Column b of a φ grid coordinate in [−1, cols + 1] (t ∈ [0, 1] rounded, ± one cell), wrapped to
// [0, cols); a comparison instead of an integer division.
CSM_INLINE uint csm_wrap_col(CSM_GLOBAL const CsmOccluder* oc, int b) {
  const int cols = (int)oc->cols;
  return (uint)(b < 0 ? b + cols : (b >= cols ? b - cols : b));
}

// The 4 maps around continuous grid coordinates (sr, tc) (csm_grid_coords): rows a0, a0 + 1 and
// columns b0, b0 + 1 (wrapped) of the samples around them (s·rows − 0.5 on a cell-centred grid,
// s·rows on the ao grid's corners), as cell indices. Cross-map PCF clamps the rows, so near a pole
// both rows are the edge row; `distinct` keeps two different rows there (the march's vote of 2 must
// be over 4 different maps, not 2 counted twice), and on the ao grid, whose row 0 is one map (the
// pole) repeated, rows from 1 on (with at least 3 rows; fewer maps than that repeat some).
CSM_INLINE void csm_near_cells(CSM_GLOBAL const CsmOccluder* oc, float sr, float tc, int distinct, uint* out) {
  const float corner_shift = oc->centred ? 0.5f : 0.0f;
  int a0 = csm_floor(sr - corner_shift);
  const int b0 = csm_floor(tc - corner_shift);
  if (distinct && oc->rows >= 2u) {
    const int lowest = !oc->centred && oc->rows >= 3u ? 1 : 0;
    a0 = a0 < lowest ? lowest : (a0 > (int)oc->rows - 2 ? (int)oc->rows - 2 : a0);
  }
  for (int da = 0; da < 2; ++da)
    for (int db = 0; db < 2; ++db) out[2 * da + db] = oc->cell_base + csm_clamp_row(oc, a0 + da) * oc->cols + csm_wrap_col(oc, b0 + db);
}

// Is y ≤ c·sqrt(len2), given sc = c·|c|? Compared squared, so no root is taken. For fixed (y, len2)
// it is monotone in sc (float rounding is monotone): true for one sc, true for every larger one. So
// over a sorted list of boundaries it flips once, and the cell found by walking along the list does
// not depend on where the walk starts (csm_walk_cell).
CSM_INLINE int csm_at_most(float y, float len2, float sc) {
  if (sc > 0.0f) return y <= 0.0f || y * y <= sc * len2;
  if (sc < 0.0f) return y < 0.0f && y * y >= -sc * len2;
  return y <= 0.0f;
}

// Is y < c·sqrt(len2)? The same form and the same monotony.
CSM_INLINE int csm_below(float y, float len2, float sc) {
  if (sc > 0.0f) return y < 0.0f || y * y < sc * len2;
  if (sc < 0.0f) return y < 0.0f && y * y > -sc * len2;
  return y < 0.0f;
}

// Squared lengths of a sphere-frame direction: rho2 = x² + z², len2 = rho2 + y². 0 for a zero or
// non-finite direction (a light at the receiver), which the callers treat as lit.
CSM_INLINE int csm_direction(float x, float y, float z, float* rho2, float* len2) {
  *rho2 = x * x + z * z;
  *len2 = *rho2 + y * y;
  return *len2 >= CSM_MIN_LEN2 && *len2 < INFINITY;
}

// The nearest map's cell by exact boundary tests: row a = the number of θ boundaries θ_k ≤ θ
// (cosθ = y/|w| ≤ cosθ_k), column b = the number of φ boundaries β_k ≤ φ = atan2(x, z) ∈ [0, 2π):
// for x ≥ 0 (φ ∈ [0, π]) among β_k ≤ π by z/ρ ≤ cosβ_k, for x < 0 (φ ∈ (π, 2π)) among the others by
// z/ρ ≥ cosβ_k. No root, division or atan2: each test is a product and a comparison. *a and *b are
// the walk's start on entry and the cell on return; b is unwrapped (the ao grid's b = cols is
// column 0), so the next coherent query starts next to it. A direction on the pole axis (ρ² = 0)
// takes column 0. Requires csm_direction(x, y, z) to hold.
CSM_INLINE void csm_walk_cell(CSM_GLOBAL const CsmOccluder* oc, CSM_GLOBAL const float* bounds, float x, float y, float z,
                          float rho2, float len2, uint* a, uint* b) {
  CSM_GLOBAL const float* row_bounds = bounds + oc->bound_base;            // θ_k at [k − 1]
  CSM_GLOBAL const float* col_bounds = row_bounds + (oc->rows - 1u);      // β_k at [k − 1]
  uint row = *a < oc->rows ? *a : oc->rows - 1u;
  while (row > 0u && !csm_at_most(y, len2, row_bounds[row - 1u])) --row;
  while (row + 1u < oc->rows && csm_at_most(y, len2, row_bounds[row])) ++row;
  *a = row;
  const uint mid = oc->half_cols, top = oc->col_bounds;
  uint col = *b < top ? *b : top;
  if (!(rho2 > 0.0f)) {
    col = 0u;
  } else if (!(x < 0.0f)) {
    if (col > mid) col = col - mid > (top - mid) / 2u ? 0u : mid;  // from across the φ = 0 seam: start at 0
    while (col > 0u && !csm_at_most(z, rho2, col_bounds[col - 1u])) --col;
    while (col < mid && csm_at_most(z, rho2, col_bounds[col])) ++col;
  } else {
    if (col < mid) col = col < mid / 2u ? top : mid;  // from across the seam: start at the top boundary
    while (col > mid && csm_below(z, rho2, col_bounds[col - 1u])) --col;
    while (col < top && !csm_below(z, rho2, col_bounds[col])) ++col;
  }
  *b = col;
}

// Grid entry (a·cols + b) of the cell found by csm_walk_cell.
CSM_INLINE uint csm_cell_entry(CSM_GLOBAL const CsmOccluder* oc, uint a, uint b) {
  return a * oc->cols + (b < oc->cols ? b : 0u);
}

// The nearest map's grid entry for a sphere-frame direction: csm_walk_cell started at the rounded
// continuous coordinates (which are within a cell of the answer). Returns 0 when csm_direction fails.
CSM_INLINE int csm_select_cell(CSM_GLOBAL const CsmOccluder* oc, CSM_GLOBAL const float* bounds, float x, float y, float z,
                           uint* entry) {
  float rho2 = 0.0f, len2 = 0.0f, sr = 0.0f, tc = 0.0f;
  if (!csm_direction(x, y, z, &rho2, &len2) || !csm_grid_coords(oc, x, y, z, &sr, &tc)) return 0;
  const float corner_shift = oc->centred ? 0.5f : 0.0f;
  uint a = csm_clamp_row(oc, csm_floor(sr + (0.5f - corner_shift)));
  const int b0 = csm_floor(tc + (0.5f - corner_shift));
  uint b = b0 < 0 ? 0u : (uint)b0;
  csm_walk_cell(oc, bounds, x, y, z, rho2, len2, &a, &b);
  *entry = csm_cell_entry(oc, a, b);
  return 1;
}

// Stored depth of (pixel, map at `sequence`): the first segment whose inclusive end is >= sequence.
CSM_INLINE float csm_fetch(const CsmScene* scene, uint pixel_entry, uint sequence) {
  uint lo = scene->offsets[pixel_entry], hi = scene->offsets[pixel_entry + 1u] - 1u;
  while (lo < hi) {
    const uint mid = (lo + hi) >> 1;
    if (scene->ends[mid] >= sequence) hi = mid;
    else lo = mid + 1u;
  }
  return scene->depths[lo];
}

// Projection of the receiver (rx, ry, rz relative to the sphere centre) into one map for a
// width × width window of taps: the window's first texel (*i0, *j0) and the depth limit (receiver
// depth − bias texels) below which a stored depth occludes. width 1: the texel containing the receiver;
// width 2 or 4: the texels whose centres surround it.
CSM_INLINE float csm_window(CSM_GLOBAL const CsmOccluder* oc, CSM_GLOBAL const CsmCell* cell, float rx, float ry, float rz, int width,
                        float bias, int* i0, int* j0) {
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
  *i0 = width == 1 ? csm_floor(fx) : csm_floor(fx - 0.5f) - (width / 2 - 1);
  *j0 = width == 1 ? csm_floor(fy) : csm_floor(fy - 0.5f) - (width / 2 - 1);
  return depth - bias * oc->texel_depth;
}

// Lit taps among the width × width window of one map around the receiver. Texels outside the map
// are lit (the occluder cannot block there).
CSM_INLINE float csm_map_taps(const CsmScene* scene, CSM_GLOBAL const CsmOccluder* oc, CSM_GLOBAL const CsmCell* cell,
                          float rx, float ry, float rz, int width, float bias) {
  int i0 = 0, j0 = 0;
  const float limit = csm_window(oc, cell, rx, ry, rz, width, bias, &i0, &j0);
  const int res = (int)oc->resolution;
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

// The limits of τ ≥ 0 where f + τ·k lies in [0, m) (one axis of the map's texels), narrowed into
// [*lo, *hi]; an empty range leaves *lo ≥ *hi or NaN.
CSM_INLINE void csm_march_clip(float f, float k, float m, float* lo, float* hi) {
  if (k == 0.0f) {
    if (!(f >= 0.0f && f < m)) *hi = -1.0f;
    return;
  }
  float a = (0.0f - f) / k, b = (m - f) / k;
  if (k < 0.0f) {
    const float t = a;
    a = b;
    b = t;
  }
  if (a > *lo) *lo = a;
  if (!(b >= *hi)) *hi = b;
}

// The light ray's boundary τ of texel column i along one axis (f + τ·k leaves [i, i + 1)); +∞ when
// the ray does not move along it.
CSM_INLINE float csm_march_boundary(float f, float k, int i) {
  if (k > 0.0f) return ((float)(i + 1) - f) / k;
  if (k < 0.0f) return ((float)i - f) / k;
  return INFINITY;
}

// Filter march: the true light ray in one map (csm_march_vote asks 4). A map's direction d differs
// from the light vector w (object space: wx, wy, wz) by up to a grid cell, and the single-texel test
// answers along d, which moves a shadow edge by the occluder's distance times that angle. Here the
// ray from the receiver along w is followed through the map's texel columns toward the capture
// plane (its depth falls by τ while it moves τ·k texels sideways), and it is blocked where, within
// one column, its depth passes that texel's stored depth (a surface, or on a two-hit texel a depth
// inside the solid, lies across it), or where it passes from behind one column's depth to at most
// CSM_MARCH_JUMP_TEXELS in front of the next one's (a step of the stored depths inside a solid). A
// ray that leaves the shadow of a silhouette sideways, farther in front of the next column's depth,
// is not stopped there: that is where the single-texel test errs. As with it, depths are biased by
// `bias` texels, texels outside the map are empty, and the ray is followed to the capture plane
// whatever the light's distance. Each column costs a segment search: at most about
// 2M · tan(angle) + 1 of them (the ray from depth 2 to 0; about 5 for a receiver on the sphere at
// 64² and 1024 maps). 0 or 1.
CSM_INLINE float csm_march_taps(const CsmScene* scene, CSM_GLOBAL const CsmOccluder* oc, CSM_GLOBAL const CsmCell* cell, float rx,
                                float ry, float rz, float wx, float wy, float wz, float bias) {
  const float wd = wx * cell->d[0] + wy * cell->d[1] + wz * cell->d[2];
  // A light vector 90° or more from the map's direction never reaches its capture plane: such a
  // map (on grids of a few maps) sees nothing of the ray and votes lit.
  if (!(wd > 0.0f)) return 1.0f;
  const float x = rx * cell->u[0] + ry * cell->u[1] + rz * cell->u[2];
  const float y = rx * cell->v[0] + ry * cell->v[1] + rz * cell->v[2];
  const float limit = (oc->radius - (rx * cell->d[0] + ry * cell->d[1] + rz * cell->d[2])) * oc->depth_scale - bias * oc->texel_depth;
  const float fx = (x + oc->radius) * oc->pixel_scale, fy = (y + oc->radius) * oc->pixel_scale;
  // Texels sideways per unit of depth toward the capture plane.
  const float per_depth = oc->pixel_scale / (wd * oc->depth_scale);
  const float kx = (wx * cell->u[0] + wy * cell->u[1] + wz * cell->u[2]) * per_depth;
  const float ky = (wx * cell->v[0] + wy * cell->v[1] + wz * cell->v[2]) * per_depth;
  // The part of the ray over the map, down to depth 0 (the biased depth is limit − τ).
  const float m = (float)oc->resolution;
  float enter = 0.0f, end = limit;
  csm_march_clip(fx, kx, m, &enter, &end);
  csm_march_clip(fy, ky, m, &enter, &end);
  // Stored depths lie in [0, 1] (in the bounding sphere): while the ray's depth is above 2 nothing
  // stops it, nor can the step rule fire at the first column it enters below that. A receiver far
  // behind the sphere starts there instead of walking every column in between (the same answers
  // for receivers within about 2^22 diameters of the map; farther, float rounding decides both).
  if (limit - 2.0f > enter) enter = limit - 2.0f;
  if (!(enter < end)) return 1.0f;
  const int res = (int)oc->resolution, step_i = kx > 0.0f ? 1 : -1, step_j = ky > 0.0f ? 1 : -1;
  // The clip puts the start in [0, M] up to rounding, which grows with |fx|: clamp before the int.
  float start_x = fx + enter * kx, start_y = fy + enter * ky;
  start_x = start_x > 0.0f ? (start_x < m ? start_x : m) : 0.0f;
  start_y = start_y > 0.0f ? (start_y < m ? start_y : m) : 0.0f;
  int i = csm_floor(start_x), j = csm_floor(start_y);
  i = i >= res ? res - 1 : i;
  j = j >= res ? res - 1 : j;
  int behind = 0;  // the ray left the previous column behind its stored depth
  const float jump = CSM_MARCH_JUMP_TEXELS * oc->texel_depth;
  for (;;) {  // each pass moves one texel in a fixed direction: at most 2M passes
    const float bx = csm_march_boundary(fx, kx, i), by = csm_march_boundary(fy, ky, j);
    float leave = bx < by ? bx : by;
    if (!(leave < end)) leave = end;
    if (leave < enter) leave = enter;  // rounding at a corner: an empty stretch
    const float g = csm_fetch(scene, oc->pixel_base + (uint)j * oc->resolution + (uint)i, cell->sequence);
    if (g < limit - enter && g >= limit - leave) return 0.0f;  // crosses the depth in this column
    if (behind && !(g < limit - enter) && g - (limit - enter) <= jump) return 0.0f;  // a step inside a solid
    behind = g < limit - leave;
    if (!(leave < end)) return 1.0f;
    if (bx < by) i += step_i;
    else j += step_j;
    if (i < 0 || i >= res || j < 0 || j >= res) return 1.0f;
    enter = leave;
  }
}

// Filter march over the 4 maps nearest the light vector (the cross-map filter's cells; wx, wy, wz
// in object space): occluded (0) when the ray is blocked in at least 2 of them, else lit (1). One
// map alone is fooled where its stored depths step inside a solid by more than
// CSM_MARCH_JUMP_TEXELS; the maps store different depths there, so a vote of the four removes most
// of those false lights (docs/results/csm.md, *Filter march*).
CSM_INLINE float csm_march_vote(const CsmScene* scene, CSM_GLOBAL const CsmOccluder* oc, const uint* cells, float rx, float ry, float rz,
                                float wx, float wy, float wz, float bias) {
  int blocked = 0;
  for (int t = 0; t < 4; ++t) {
    blocked += csm_march_taps(scene, oc, scene->cells + cells[t], rx, ry, rz, wx, wy, wz, bias) == 0.0f;
    if (blocked == 2) return 0.0f;
    if (blocked + (3 - t) < 2) return 1.0f;  // 2 can no longer be reached
  }
  return 1.0f;
}

// The stored depths of one map's tap window, kept while coherent queries stay in it: a chunk of
// screen-neighbouring receivers mostly falls into the same window, so its 4 or 16 segment searches
// become comparisons. Texels outside the map hold +∞, which tests lit exactly like csm_map_taps.
typedef struct {
  uint cell;  // cells index of the map; UINT_MAX: empty
  int i0, j0;
  float g[16];
} CsmWindow;

// csm_map_taps(scene, oc, scene->cells + cell, ...), exactly, through `window`.
CSM_INLINE float csm_window_taps(const CsmScene* scene, CSM_GLOBAL const CsmOccluder* oc, uint cell, float rx, float ry, float rz,
                             int width, float bias, CsmWindow* window) {
  CSM_GLOBAL const CsmCell* c = scene->cells + cell;
  int i0 = 0, j0 = 0;
  const float limit = csm_window(oc, c, rx, ry, rz, width, bias, &i0, &j0);
  if (window->cell != cell || window->i0 != i0 || window->j0 != j0) {
    // A window shifted by a texel or two within the same map keeps the texels it still covers.
    const int res = (int)oc->resolution, same_map = window->cell == cell;
    float g[16];
    for (int j = 0; j < width; ++j)
      for (int i = 0; i < width; ++i) {
        const int ti = i0 + i, tj = j0 + j, oi = ti - window->i0, oj = tj - window->j0;
        if (same_map && oi >= 0 && oi < width && oj >= 0 && oj < width) g[j * width + i] = window->g[oj * width + oi];
        else if (ti < 0 || ti >= res || tj < 0 || tj >= res) g[j * width + i] = INFINITY;
        else g[j * width + i] = csm_fetch(scene, oc->pixel_base + (uint)tj * oc->resolution + (uint)ti, c->sequence);
      }
    for (int t = 0; t < width * width; ++t) window->g[t] = g[t];
    window->cell = cell;
    window->i0 = i0;
    window->j0 = j0;
  }
  float lit = 0.0f;
  for (int t = 0; t < width * width; ++t) lit += window->g[t] < limit ? 0.0f : 1.0f;
  return lit;
}

// Fraction of lit taps for one instance: receiver p (world), light vector w = q − p (world).
CSM_INLINE float csm_instance_visibility(const CsmScene* scene, uint k, float px, float py, float pz, float wx, float wy,
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
  CSM_GLOBAL const CsmCell* cells = scene->cells + oc->cell_base;
  if (filter == CSM_FILTER_CROSS_MAP || filter == CSM_FILTER_MARCH) {
    float sr = 0.0f, tc = 0.0f;
    if (!csm_grid_coords(oc, fx, fy, fz, &sr, &tc)) return 1.0f;
    uint near[4];
    csm_near_cells(oc, sr, tc, filter == CSM_FILTER_MARCH, near);
    if (filter == CSM_FILTER_MARCH)
      return csm_march_vote(scene, oc, near, rx, ry, rz, m[0] * wx + m[1] * wy + m[2] * wz, m[4] * wx + m[5] * wy + m[6] * wz,
                            m[8] * wx + m[9] * wy + m[10] * wz, bias);
    float lit = 0.0f;
    for (int t = 0; t < 4; ++t) lit += csm_map_taps(scene, oc, scene->cells + near[t], rx, ry, rz, 2, bias);
    return lit * 0.0625f;
  }
  uint entry = 0u;
  if (!csm_select_cell(oc, scene->bounds, fx, fy, fz, &entry)) return 1.0f;
  if (filter == CSM_FILTER_SAME_MAP) return csm_map_taps(scene, oc, cells + entry, rx, ry, rz, 4, bias) * 0.0625f;
  return csm_map_taps(scene, oc, cells + entry, rx, ry, rz, 1, bias);
}

// Visibility of light vector w from receiver p through every instance: the product of the
// instances' lit fractions (Talpe §4.3: lit only if every test passes; with PCF each
// instance contributes its fraction). Stops at the first fully occluding instance.
CSM_INLINE float csm_visibility(const CsmScene* scene, float px, float py, float pz, float wx, float wy, float wz, uint filter,
                            float bias) {
  float lit = 1.0f;
  for (uint k = 0; k < scene->instance_count && lit > 0.0f; ++k)
    lit *= csm_instance_visibility(scene, k, px, py, pz, wx, wy, wz, filter, bias);
  return lit;
}

// What a run of queries through one instance can reuse from the query before: the map choice for
// the same light vector; the cell to start the next map choice's walk from (for a new light vector,
// e.g. a point light seen from the next receiver, the walk usually just confirms it); the stored
// depth of the same (pixel, map), or with PCF the tap windows (CsmWindow). Coherent batches (a
// screen of receivers, one light or a small area light) hit them most of the time.
typedef struct {
  float wx, wy, wz;  // light vector of the cached map choice
  int valid;         // 1: wx, wy, wz hold a light vector whose choice is cached
  int lit;           // 1: that light vector is zero or non-finite (always lit)
  int placed;        // 1: row, col hold an earlier query's cell (the walk's start)
  uint row, col;     // that cell (col unwrapped, as csm_walk_cell returns it)
  uint cell;         // cells index of the chosen map
  uint cross[4];     // CSM_FILTER_CROSS_MAP and MARCH: cells indices of the 4 nearest maps
  uint entry, sequence;  // filter none: cached (pixel entry, map) ...
  float g;               // ... and its stored depth (entry == UINT_MAX: none)
  CsmWindow windows[4];  // PCF: the tap windows (same map: windows[0]; cross map: one per map)
} CsmQueryCache;

CSM_INLINE void csm_cache_reset(CsmQueryCache* cache) {
  cache->valid = 0;
  cache->placed = 0;
  cache->row = 0u;
  cache->col = 0u;
  cache->entry = 0xffffffffu;
  for (int t = 0; t < 4; ++t) cache->windows[t].cell = 0xffffffffu;
}

// Is light vector w within about 18° of the cached one (cos² ≥ 0.9)? Then the walk from the cached
// cell takes a few steps; otherwise (the AO kernel's directions, one receiver's 16 after another)
// it could cross the whole grid, one boundary test per row and column, and csm_select_cell's start
// from the rounded coordinates is cheaper. Either start finds the same cell (csm_walk_cell).
CSM_INLINE int csm_near_previous(const CsmQueryCache* cache, float wx, float wy, float wz) {
  const float dot = wx * cache->wx + wy * cache->wy + wz * cache->wz;
  const float len2 = wx * wx + wy * wy + wz * wz, cached2 = cache->wx * cache->wx + cache->wy * cache->wy + cache->wz * cache->wz;
  return dot > 0.0f && dot * dot >= 0.9f * len2 * cached2;
}

// The map choice of csm_instance_visibility for light vector w (world), into `cache`.
CSM_INLINE void csm_cache_choose(const CsmScene* scene, CSM_GLOBAL const CsmInstance* in, CSM_GLOBAL const CsmOccluder* oc, float wx,
                             float wy, float wz, uint filter, CsmQueryCache* cache) {
  if (cache->valid && wx == cache->wx && wy == cache->wy && wz == cache->wz) return;
  CSM_GLOBAL const float* f = in->to_frame;
  const float fx = f[0] * wx + f[1] * wy + f[2] * wz;
  const float fy = f[3] * wx + f[4] * wy + f[5] * wz;
  const float fz = f[6] * wx + f[7] * wy + f[8] * wz;
  float rho2 = 0.0f, len2 = 0.0f;
  cache->lit = !csm_direction(fx, fy, fz, &rho2, &len2);
  if (cache->lit) {
  } else if (filter == CSM_FILTER_CROSS_MAP || filter == CSM_FILTER_MARCH) {
    float sr = 0.0f, tc = 0.0f;
    csm_grid_coords(oc, fx, fy, fz, &sr, &tc);
    csm_near_cells(oc, sr, tc, filter == CSM_FILTER_MARCH, cache->cross);
  } else if (cache->placed && csm_near_previous(cache, wx, wy, wz)) {
    csm_walk_cell(oc, scene->bounds, fx, fy, fz, rho2, len2, &cache->row, &cache->col);
    cache->cell = oc->cell_base + csm_cell_entry(oc, cache->row, cache->col);
  } else {
    uint entry = 0u;
    csm_select_cell(oc, scene->bounds, fx, fy, fz, &entry);
    cache->cell = oc->cell_base + entry;
    cache->row = entry / oc->cols;
    cache->col = entry % oc->cols;
    cache->placed = 1;
  }
  cache->wx = wx;
  cache->wy = wy;
  cache->wz = wz;
  // NaN never equals itself: such a vector is recomputed each time (and is lit).
  cache->valid = 1;
}

// csm_instance_visibility(scene, k, p, w, filter, bias), exactly, reusing `cache` (one cache per
// instance and filter: a run of queries through the same instance with the same filter).
CSM_INLINE float csm_instance_visibility_cached(const CsmScene* scene, uint k, float px, float py, float pz, float wx, float wy,
                                            float wz, uint filter, float bias, CsmQueryCache* cache) {
  CSM_GLOBAL const CsmInstance* in = scene->instances + k;
  CSM_GLOBAL const CsmOccluder* oc = scene->occluders + in->occluder;
  csm_cache_choose(scene, in, oc, wx, wy, wz, filter, cache);
  if (cache->lit) return 1.0f;
  CSM_GLOBAL const float* m = in->to_object;
  const float rx = m[0] * px + m[1] * py + m[2] * pz + m[3] - oc->centre[0];
  const float ry = m[4] * px + m[5] * py + m[6] * pz + m[7] - oc->centre[1];
  const float rz = m[8] * px + m[9] * py + m[10] * pz + m[11] - oc->centre[2];
  if (filter == CSM_FILTER_SAME_MAP) return csm_window_taps(scene, oc, cache->cell, rx, ry, rz, 4, bias, cache->windows) * 0.0625f;
  if (filter == CSM_FILTER_MARCH)
    return csm_march_vote(scene, oc, cache->cross, rx, ry, rz, m[0] * wx + m[1] * wy + m[2] * wz, m[4] * wx + m[5] * wy + m[6] * wz,
                          m[8] * wx + m[9] * wy + m[10] * wz, bias);
  if (filter == CSM_FILTER_CROSS_MAP) {
    float lit = 0.0f;
    for (int t = 0; t < 4; ++t) lit += csm_window_taps(scene, oc, cache->cross[t], rx, ry, rz, 2, bias, cache->windows + t);
    return lit * 0.0625f;
  }
  // Filter none: csm_map_taps with width 1, caching the one stored depth.
  CSM_GLOBAL const CsmCell* cell = scene->cells + cache->cell;
  int i = 0, j = 0;
  const float limit = csm_window(oc, cell, rx, ry, rz, 1, bias, &i, &j);
  const int res = (int)oc->resolution;
  if (i < 0 || i >= res || j < 0 || j >= res) return 1.0f;
  const uint entry = oc->pixel_base + (uint)j * oc->resolution + (uint)i;
  if (entry != cache->entry || cell->sequence != cache->sequence) {
    cache->g = csm_fetch(scene, entry, cell->sequence);
    cache->entry = entry;
    cache->sequence = cell->sequence;
  }
  return cache->g < limit ? 0.0f : 1.0f;
}

// Lanes: the ambient occlusion below runs CSM_AO_LANES receivers side by side in the OpenCL kernel
// (csm_vfloat = floatN, one receiver per component: PoCL vectorises a work-group only across
// work-items whose body has no inner loop, and the per-receiver walk, segment search and direction
// loop are such loops, so the lanes are explicit) and one receiver in the C++ reference, where
// csm_vfloat is float. Each lane executes the scalar query's float operations in the same order;
// branches become selects (both sides computed, one kept) and loops run while any lane still
// steps, a lane that stopped holding its value. Masks: comparisons, combined with & | !
// (−1/0 per component in OpenCL C, 1/0 in C++).
#ifdef __OPENCL_C_VERSION__
#ifndef CSM_AO_LANES
#define CSM_AO_LANES 8
#endif
#define CSM_VJOIN_(a, b) a##b
#define CSM_VJOIN(a, b) CSM_VJOIN_(a, b)
typedef CSM_VJOIN(float, CSM_AO_LANES) csm_vfloat;
typedef CSM_VJOIN(int, CSM_AO_LANES) csm_vint;
typedef CSM_VJOIN(uint, CSM_AO_LANES) csm_vuint;
#define csm_vsel(c, t, f) select((f), (t), (c))
#define csm_vany(m) any(m)
#define csm_vto_int(v) CSM_VJOIN(convert_int, CSM_AO_LANES)(v)
#define csm_vto_uint(v) CSM_VJOIN(convert_uint, CSM_AO_LANES)(v)
#define csm_vto_float(v) CSM_VJOIN(convert_float, CSM_AO_LANES)(v)
// One load per lane: P[I.sK] F for each component K of the index vector I (F: a member, or nothing).
#if CSM_AO_LANES == 8
#define CSM_VGATHER(T, P, I, F) \
  ((T)((P)[(I).s0] F, (P)[(I).s1] F, (P)[(I).s2] F, (P)[(I).s3] F, (P)[(I).s4] F, (P)[(I).s5] F, (P)[(I).s6] F, (P)[(I).s7] F))
#define CSM_VLANE_IDS ((csm_vuint)(0u, 1u, 2u, 3u, 4u, 5u, 6u, 7u))
#elif CSM_AO_LANES == 16
#define CSM_VGATHER(T, P, I, F)                                                                                              \
  ((T)((P)[(I).s0] F, (P)[(I).s1] F, (P)[(I).s2] F, (P)[(I).s3] F, (P)[(I).s4] F, (P)[(I).s5] F, (P)[(I).s6] F, (P)[(I).s7] F, \
       (P)[(I).s8] F, (P)[(I).s9] F, (P)[(I).sa] F, (P)[(I).sb] F, (P)[(I).sc] F, (P)[(I).sd] F, (P)[(I).se] F, (P)[(I).sf] F))
#define CSM_VLANE_IDS ((csm_vuint)(0u, 1u, 2u, 3u, 4u, 5u, 6u, 7u, 8u, 9u, 10u, 11u, 12u, 13u, 14u, 15u))
#else
#error "CSM_AO_LANES must be 8 or 16"
#endif
#else
typedef float csm_vfloat;
typedef int csm_vint;
typedef uint csm_vuint;
#define csm_vsel(c, t, f) ((c) ? (t) : (f))
#define csm_vany(m) (m)
#define csm_vto_int(v) static_cast<int>(v)
#define csm_vto_uint(v) static_cast<uint>(v)
#define csm_vto_float(v) static_cast<float>(v)
#define CSM_VGATHER(T, P, I, F) ((P)[I] F)
#endif
#define csm_vf(v) ((csm_vfloat)(v))
#define csm_vu(v) ((csm_vuint)(v))

// csm_floor, per lane.
CSM_INLINE csm_vint csm_vfloor(csm_vfloat v) {
  const csm_vint i = csm_vto_int(v);
  return csm_vsel(v < csm_vto_float(i), i - 1, i);
}

// csm_atan2, per lane.
CSM_INLINE csm_vfloat csm_vatan2(csm_vfloat y, csm_vfloat x) {
  const csm_vfloat ax = csm_vsel(x < 0.0f, -x, x), ay = csm_vsel(y < 0.0f, -y, y);
  const csm_vint zero = (ax == 0.0f) & (ay == 0.0f), swapped = ay > ax;
  const csm_vfloat q = csm_vsel(swapped, ax / ay, ay / ax);
  const csm_vint reduced = q > 0.41421356f;
  const csm_vfloat base = csm_vsel(reduced, csm_vf(0.78539816f), csm_vf(0.0f));
  const csm_vfloat r = csm_vsel(reduced, (q - 1.0f) / (q + 1.0f), q);
  const csm_vfloat z = r * r;
  csm_vfloat a = base + ((((8.05374449538e-2f * z - 1.38776856032e-1f) * z + 1.99777106478e-1f) * z - 3.33329491539e-1f) * z * r + r);
  a = csm_vsel(swapped, 1.57079633f - a, a);
  a = csm_vsel(x < 0.0f, 3.14159265f - a, a);
  return csm_vsel(zero, csm_vf(0.0f), csm_vsel(y < 0.0f, -a, a));
}

// csm_at_most and csm_below, per lane.
CSM_INLINE csm_vint csm_vat_most(csm_vfloat y, csm_vfloat len2, csm_vfloat sc) {
  const csm_vint positive = (y <= 0.0f) | (y * y <= sc * len2), negative = (y < 0.0f) & (y * y >= -sc * len2);
  return csm_vsel(sc > 0.0f, positive, csm_vsel(sc < 0.0f, negative, y <= 0.0f));
}
CSM_INLINE csm_vint csm_vbelow(csm_vfloat y, csm_vfloat len2, csm_vfloat sc) {
  const csm_vint positive = (y < 0.0f) | (y * y < sc * len2), negative = (y < 0.0f) & (y * y > -sc * len2);
  return csm_vsel(sc > 0.0f, positive, csm_vsel(sc < 0.0f, negative, y < 0.0f));
}

// csm_select_cell's grid entry, per lane, for the lanes of `run` (whose directions pass
// csm_direction; rho2 and len2 as it computes them). The walks of csm_walk_cell step the lanes
// that still step; the eastern (x ≥ 0) and western lanes of a column walk share its iterations.
CSM_INLINE csm_vuint csm_vselect_cell(CSM_GLOBAL const CsmOccluder* oc, CSM_GLOBAL const float* bounds, csm_vfloat x, csm_vfloat y,
                                      csm_vfloat z, csm_vfloat rho2, csm_vfloat len2, csm_vint run) {
  // csm_grid_coords.
  const csm_vfloat s = oc->uniform ? (1.0f - y / csm_sqrt(len2)) * 0.5f : csm_vatan2(csm_sqrt(rho2), y) * 0.318309886f;
  csm_vfloat t = csm_vatan2(x, z) * 0.159154943f;
  t = csm_vsel(t < 0.0f, t + 1.0f, t);
  const csm_vfloat sr = s * (float)oc->rows, tc = t * (float)oc->cols;
  const float corner_shift = oc->centred ? 0.5f : 0.0f;
  const csm_vint a0 = csm_vfloor(sr + (0.5f - corner_shift)), b0 = csm_vfloor(tc + (0.5f - corner_shift));
  const uint rows = oc->rows;
  // csm_clamp_row, then csm_walk_cell's clamp of its start (a no-op after csm_clamp_row).
  csm_vuint row = csm_vsel(a0 < 0, csm_vu(0u), csm_vsel(a0 >= (int)rows, csm_vu(rows - 1u), csm_vto_uint(a0)));
  csm_vuint col = csm_vsel(b0 < 0, csm_vu(0u), csm_vto_uint(b0));
  CSM_GLOBAL const float* row_bounds = bounds + oc->bound_base;
  CSM_GLOBAL const float* col_bounds = row_bounds + (rows - 1u);
  for (;;) {
    const csm_vint m = run & (row > 0u);
    if (!csm_vany(m)) break;
    const csm_vint step = m & !csm_vat_most(y, len2, CSM_VGATHER(csm_vfloat, row_bounds, csm_vsel(m, row - 1u, csm_vu(0u)), ));
    if (!csm_vany(step)) break;
    row = csm_vsel(step, row - 1u, row);
  }
  for (;;) {
    const csm_vint m = run & (row + 1u < rows);
    if (!csm_vany(m)) break;
    const csm_vint step = m & csm_vat_most(y, len2, CSM_VGATHER(csm_vfloat, row_bounds, csm_vsel(m, row, csm_vu(0u)), ));
    if (!csm_vany(step)) break;
    row = csm_vsel(step, row + 1u, row);
  }
  const uint mid = oc->half_cols, top = oc->col_bounds;
  col = csm_vsel(col < top, col, csm_vu(top));
  const csm_vint pole = !(rho2 > 0.0f), east = run & !pole & !(x < 0.0f), west = run & !pole & (x < 0.0f);
  col = csm_vsel(east & (col > mid), csm_vsel(col - mid > (top - mid) / 2u, csm_vu(0u), csm_vu(mid)), col);
  col = csm_vsel(west & (col < mid), csm_vsel(col < mid / 2u, csm_vu(top), csm_vu(mid)), col);
  for (;;) {
    const csm_vint me = east & (col > 0u), mw = west & (col > mid);
    if (!csm_vany(me | mw)) break;
    const csm_vfloat sc = CSM_VGATHER(csm_vfloat, col_bounds, csm_vsel(me | mw, col - 1u, csm_vu(0u)), );
    const csm_vint step = (me & !csm_vat_most(z, rho2, sc)) | (mw & csm_vbelow(z, rho2, sc));
    if (!csm_vany(step)) break;
    col = csm_vsel(step, col - 1u, col);
  }
  for (;;) {
    const csm_vint me = east & (col < mid), mw = west & (col < top);
    if (!csm_vany(me | mw)) break;
    const csm_vfloat sc = CSM_VGATHER(csm_vfloat, col_bounds, csm_vsel(me | mw, col, csm_vu(0u)), );
    const csm_vint step = (me & csm_vat_most(z, rho2, sc)) | (mw & !csm_vbelow(z, rho2, sc));
    if (!csm_vany(step)) break;
    col = csm_vsel(step, col + 1u, col);
  }
  col = csm_vsel(pole, csm_vu(0u), col);
  // csm_cell_entry.
  return row * oc->cols + csm_vsel(col < oc->cols, col, csm_vu(0u));
}

// csm_fetch, per lane, for the lanes of `run` (the others search nothing and read pixel_entry's first segment).
CSM_INLINE csm_vfloat csm_vfetch(const CsmScene* scene, csm_vuint pixel_entry, csm_vuint sequence, csm_vint run) {
  csm_vuint lo = CSM_VGATHER(csm_vuint, scene->offsets, pixel_entry, );
  csm_vuint hi = CSM_VGATHER(csm_vuint, scene->offsets, pixel_entry + 1u, ) - 1u;
  for (;;) {
    const csm_vint m = run & (lo < hi);
    if (!csm_vany(m)) break;
    const csm_vuint mid = (lo + hi) >> 1;
    const csm_vint later = CSM_VGATHER(csm_vuint, scene->ends, csm_vsel(m, mid, lo), ) >= sequence;
    hi = csm_vsel(m & later, mid, hi);
    lo = csm_vsel(m & !later, mid + 1u, lo);
  }
  return CSM_VGATHER(csm_vfloat, scene->depths, lo, );
}

// csm_instance_visibility(scene, k, p, w, CSM_FILTER_NONE, bias) == 1 per lane (it is 0 or 1), for
// the lanes of `run` (the others: true).
CSM_INLINE csm_vint csm_vinstance_lit(const CsmScene* scene, uint k, csm_vfloat px, csm_vfloat py, csm_vfloat pz, csm_vfloat wx,
                                      csm_vfloat wy, csm_vfloat wz, float bias, csm_vint run) {
  CSM_GLOBAL const CsmInstance* in = scene->instances + k;
  CSM_GLOBAL const CsmOccluder* oc = scene->occluders + in->occluder;
  CSM_GLOBAL const float* f = in->to_frame;
  CSM_GLOBAL const float* o = in->to_object;
  const csm_vfloat rx = o[0] * px + o[1] * py + o[2] * pz + o[3] - oc->centre[0];
  const csm_vfloat ry = o[4] * px + o[5] * py + o[6] * pz + o[7] - oc->centre[1];
  const csm_vfloat rz = o[8] * px + o[9] * py + o[10] * pz + o[11] - oc->centre[2];
  const csm_vfloat fx = f[0] * wx + f[1] * wy + f[2] * wz;
  const csm_vfloat fy = f[3] * wx + f[4] * wy + f[5] * wz;
  const csm_vfloat fz = f[6] * wx + f[7] * wy + f[8] * wz;
  const csm_vfloat rho2 = fx * fx + fz * fz, len2 = rho2 + fy * fy;
  const csm_vint test = run & (len2 >= CSM_MIN_LEN2) & (len2 < INFINITY);  // csm_direction; the others are lit
  if (!csm_vany(test)) return !test;
  // Lanes not tested walk from the pole, a valid direction, and keep no result.
  const csm_vuint entry = csm_vselect_cell(oc, scene->bounds, csm_vsel(test, fx, csm_vf(0.0f)), csm_vsel(test, fy, csm_vf(1.0f)),
                                           csm_vsel(test, fz, csm_vf(0.0f)), csm_vsel(test, rho2, csm_vf(0.0f)),
                                           csm_vsel(test, len2, csm_vf(1.0f)), test);
  // csm_map_taps with width 1 (csm_window).
  CSM_GLOBAL const CsmCell* cells = scene->cells + oc->cell_base;
  const csm_vfloat x = rx * CSM_VGATHER(csm_vfloat, cells, entry, .u[0]) + ry * CSM_VGATHER(csm_vfloat, cells, entry, .u[1]) +
                       rz * CSM_VGATHER(csm_vfloat, cells, entry, .u[2]);
  const csm_vfloat y = rx * CSM_VGATHER(csm_vfloat, cells, entry, .v[0]) + ry * CSM_VGATHER(csm_vfloat, cells, entry, .v[1]) +
                       rz * CSM_VGATHER(csm_vfloat, cells, entry, .v[2]);
  const csm_vfloat depth = (oc->radius - (rx * CSM_VGATHER(csm_vfloat, cells, entry, .d[0]) +
                                          ry * CSM_VGATHER(csm_vfloat, cells, entry, .d[1]) +
                                          rz * CSM_VGATHER(csm_vfloat, cells, entry, .d[2]))) *
                           oc->depth_scale;
  const float m = (float)oc->resolution;
  csm_vfloat tx = (x + oc->radius) * oc->pixel_scale, ty = (y + oc->radius) * oc->pixel_scale;
  tx = csm_vsel(!(tx >= -8.0f), csm_vf(-8.0f), tx);
  tx = csm_vsel(!(tx <= m + 8.0f), csm_vf(m + 8.0f), tx);
  ty = csm_vsel(!(ty >= -8.0f), csm_vf(-8.0f), ty);
  ty = csm_vsel(!(ty <= m + 8.0f), csm_vf(m + 8.0f), ty);
  const csm_vint i = csm_vfloor(tx), j = csm_vfloor(ty);
  const int res = (int)oc->resolution;
  const csm_vint inside = test & (i >= 0) & (i < res) & (j >= 0) & (j < res);
  const csm_vuint pixel = csm_vsel(inside, csm_vto_uint(j) * oc->resolution + csm_vto_uint(i), csm_vu(0u));
  const csm_vfloat g = csm_vfetch(scene, oc->pixel_base + pixel, CSM_VGATHER(csm_vuint, cells, entry, .sequence), inside);
  return !inside | !(g < depth - bias * oc->texel_depth);
}

// csm_visibility(scene, p, w, CSM_FILTER_NONE, bias) > 0 per lane, for the lanes of `run` (the
// others: false): lit through every instance, stopping where every lane is occluded. Instance `own`
// (none: any index past the instances) is queried from q instead of p: the receiver lifted off its
// own surface, which only that instance's maps can shadow it on.
CSM_INLINE csm_vint csm_vlit(const CsmScene* scene, csm_vfloat px, csm_vfloat py, csm_vfloat pz, uint own, csm_vfloat qx,
                             csm_vfloat qy, csm_vfloat qz, csm_vfloat wx, csm_vfloat wy, csm_vfloat wz, float bias, csm_vint run) {
  csm_vint lit = run;
  for (uint k = 0; k < scene->instance_count && csm_vany(lit); ++k)
    lit = lit & (k == own ? csm_vinstance_lit(scene, k, qx, qy, qz, wx, wy, wz, bias, lit)
                          : csm_vinstance_lit(scene, k, px, py, pz, wx, wy, wz, bias, lit));
  return lit;
}

// Ambient occlusion of one receiver (Müller §5.3): `samples` cosine-weighted directions of one
// pattern (+y hemisphere, xyz of 4 floats each) rotated into the normal's hemisphere by the 180°
// rotation about h = normalize(n + o), o = +y (d = 2(h·s)h − s, our reading of Müller §5.3.1; h = (1, 0, 0) when
// n = −o). With `ground`, directions below the world floor (d.y < 0) are occluded without a test.
// out = (bent normal xyz, AO = lit fraction, with `ground` as csm_ao_finish says); the bent normal
// is n when nothing is lit.
// The rotation's axis h = normalize(n + o), o = +y; h = (1, 0, 0) when n = −o. Also used by the
// presenter's incremental AO, which must produce bit-identical directions.
CSM_INLINE void csm_ao_rotation_axis(csm_vfloat nx, csm_vfloat ny, csm_vfloat nz, csm_vfloat* h) {
  const csm_vfloat hy = ny + 1.0f;
  const csm_vfloat hlen = csm_sqrt(nx * nx + hy * hy + nz * nz);
  const csm_vint normal = hlen > 1e-6f;
  h[0] = csm_vsel(normal, nx / hlen, csm_vf(1.0f));
  h[1] = csm_vsel(normal, hy / hlen, csm_vf(0.0f));
  h[2] = csm_vsel(normal, nz / hlen, csm_vf(0.0f));
}

// Pattern direction s rotated about h: d = 2(h·s)h − s.
CSM_INLINE void csm_ao_rotate(const csm_vfloat* h, csm_vfloat sx, csm_vfloat sy, csm_vfloat sz, csm_vfloat* d) {
  const csm_vfloat twice = 2.0f * (h[0] * sx + h[1] * sy + h[2] * sz);
  d[0] = twice * h[0] - sx;
  d[1] = twice * h[1] - sy;
  d[2] = twice * h[2] - sz;
}

// The AO of a receiver from its lit directions: sum = (lit count, Σ dx, Σ dy, Σ dz), starting at 0 and
// adding the lit directions in pattern order (csm_ao_add); out as csm_ambient_occlusion. Shared with
// the presenter's incremental AO, which knows the lit directions without running the kernel.
CSM_INLINE void csm_ao_add_where(csm_vfloat* sum, csm_vfloat dx, csm_vfloat dy, csm_vfloat dz, csm_vint lit) {
  sum[0] = csm_vsel(lit, sum[0] + 1.0f, sum[0]);
  sum[1] = csm_vsel(lit, sum[1] + dx, sum[1]);
  sum[2] = csm_vsel(lit, sum[2] + dy, sum[2]);
  sum[3] = csm_vsel(lit, sum[3] + dz, sum[3]);
}
#ifndef __OPENCL_C_VERSION__
CSM_INLINE void csm_ao_add(float* sum, float dx, float dy, float dz) { csm_ao_add_where(sum, dx, dy, dz, 1); }
#endif

// `above`: the directions not below the floor (all `samples` without `ground`). With `ground` the
// AO is the lit share of those times the exact cosine-weighted share of the hemisphere above the
// floor, (1 + n.y) / 2, instead of lit / samples: the count of directions that fall below the
// horizon varies from receiver to receiver (a pattern each), which mottled convex surfaces whose
// only occluder is the floor; this ratio estimator is exact there and keeps the mean elsewhere.
CSM_INLINE void csm_ao_finish(const csm_vfloat* sum, csm_vfloat nx, csm_vfloat ny, csm_vfloat nz, uint samples, csm_vuint above,
                              uint ground, csm_vfloat* out) {
  const csm_vfloat lit = sum[0], bx = sum[1], by = sum[2], bz = sum[3];
  const csm_vfloat blen = csm_sqrt(bx * bx + by * by + bz * bz);
  const csm_vint bent = (lit > 0.0f) & (blen > 0.0f);
  out[0] = csm_vsel(bent, bx / blen, nx);
  out[1] = csm_vsel(bent, by / blen, ny);
  out[2] = csm_vsel(bent, bz / blen, nz);
  if (!ground) out[3] = lit / (float)samples;
  else out[3] = csm_vsel(above > 0u, lit / csm_vto_float(above) * (0.5f + 0.5f * ny), csm_vf(0.0f));
}

// The AO of each lane's receiver (p, n; `valid` lanes only, the others compute garbage): its
// pattern's directions start at patterns[first] (4 floats each). Instance `own` (none: an index
// past the instances) sees the receiver lifted by `lift` along n (csm_vlit). The C++ reference runs
// it per receiver, the kernel per CSM_AO_LANES receivers.
CSM_INLINE void csm_ambient_occlusion(const CsmScene* scene, CSM_GLOBAL const float* patterns, csm_vuint first, uint samples,
                                      csm_vfloat px, csm_vfloat py, csm_vfloat pz, csm_vfloat nx, csm_vfloat ny, csm_vfloat nz,
                                      uint own, csm_vfloat lift, csm_vint valid, uint ground, float bias, csm_vfloat* out) {
  const csm_vfloat qx = px + nx * lift, qy = py + ny * lift, qz = pz + nz * lift;
  csm_vfloat h[3];
  csm_ao_rotation_axis(nx, ny, nz, h);
  csm_vfloat sum[4] = {csm_vf(0.0f), csm_vf(0.0f), csm_vf(0.0f), csm_vf(0.0f)};
  csm_vuint above = csm_vu(0u);
  for (uint k = 0; k < samples; ++k) {
    const csm_vuint s = first + 4u * k;
    csm_vfloat d[3];
    csm_ao_rotate(h, CSM_VGATHER(csm_vfloat, patterns, s, ), CSM_VGATHER(csm_vfloat, patterns, s + 1u, ),
                  CSM_VGATHER(csm_vfloat, patterns, s + 2u, ), d);
    const csm_vint test = ground ? valid & !(d[1] < 0.0f) : valid;
    above = csm_vsel(test, above + 1u, above);
    csm_ao_add_where(sum, d[0], d[1], d[2], csm_vlit(scene, px, py, pz, own, qx, qy, qz, d[0], d[1], d[2], bias, test));
  }
  csm_ao_finish(sum, nx, ny, nz, samples, above, ground, out);
}

#endif  // SPLATCL_CSM_QUERY_H
