// Splat fit, the parts the kernel (splat_fit.cl) and the native reference (host/splats/reference.cpp,
// which includes this file inside a namespace) must compute bit for bit alike: the PCA frame with
// its orientation test, the growth's size rule and sort key, the colour test, and the convex-hull
// test of the safe points. Written once, in the common subset of OpenCL C and C++ (scalar floats,
// no contraction). The walk over the rings stays twice, on purpose: the kernel's in-place ring, hash
// set and capacity relaunch are checked against the reference's plain vectors and std::sort.
#ifndef SPLATCL_SPLAT_FIT_H
#define SPLATCL_SPLAT_FIT_H

#ifdef __OPENCL_C_VERSION__
#pragma OPENCL FP_CONTRACT OFF
#define SPLAT_GLOBAL global
#define splat_sqrt sqrt
#define splat_fabs fabs
#define splat_exp exp
#define splat_fmin fmin
#define splat_fmax fmax
#define splat_abs abs
#else
#define SPLAT_GLOBAL
#define splat_sqrt std::sqrt
#define splat_fabs std::fabs
#define splat_exp std::exp
#define splat_fmin std::fmin
#define splat_fmax std::fmax
#define splat_abs std::abs
#endif

// What ended a growth phase (the reference's Stop has the same values).
#define STOP_NONE 0
#define STOP_GEOMETRY 1
#define STOP_COLOR 2

// Sign convention: the largest-magnitude component (first on ties) is positive.
inline void splat_canonical_sign(float* a) {
  float m = a[0];
  if (splat_fabs(a[1]) > splat_fabs(m)) m = a[1];
  if (splat_fabs(a[2]) > splat_fabs(m)) m = a[2];
  if (m < 0.0f) a[0] = -a[0], a[1] = -a[1], a[2] = -a[2];
}

// The frame of sample i (the splat thesis §2.2.2, "directions"): PCA of {p_i} ∪ N_k(p_i),
// mean-centred, in coordinates scaled by 1/d_i (scale-free), cyclic Jacobi; eigenvectors by
// descending eigenvalue → u, v; n = u × v; then all three flipped when the distance-weighted mean
// of the sample normals (weight exp(−3 |p_j − p_i| / d_i)) points away from n.
// positions, normals: xyzw per sample; row: the k neighbours of i; d_i = kth_distance.
inline void splat_frame(SPLAT_GLOBAL const float* positions, SPLAT_GLOBAL const float* normals,
                        SPLAT_GLOBAL const uint* row, uint k, float kth_distance, uint i, float* u, float* v,
                        float* n) {
  SPLAT_GLOBAL const float* p0 = positions + 4 * (size_t)i;
  const float scale = kth_distance > 0.0f ? 1.0f / kth_distance : 1.0f;
  // Mean of the scaled offsets from p0 (p0 itself contributes zero).
  float mx = 0.0f, my = 0.0f, mz = 0.0f;
  for (uint r = 0; r < k; ++r) {
    SPLAT_GLOBAL const float* p = positions + 4 * (size_t)row[r];
    mx += (p[0] - p0[0]) * scale, my += (p[1] - p0[1]) * scale, mz += (p[2] - p0[2]) * scale;
  }
  const float inv = 1.0f / (float)(k + 1);
  mx *= inv, my *= inv, mz *= inv;
  float a[3][3];
  {
    float xx = mx * mx, xy = mx * my, xz = mx * mz, yy = my * my, yz = my * mz, zz = mz * mz;  // p0's term
    for (uint r = 0; r < k; ++r) {
      SPLAT_GLOBAL const float* p = positions + 4 * (size_t)row[r];
      const float x = (p[0] - p0[0]) * scale - mx, y = (p[1] - p0[1]) * scale - my, z = (p[2] - p0[2]) * scale - mz;
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
      float t = 1.0f / (splat_fabs(theta) + splat_sqrt(theta * theta + 1.0f));
      if (theta < 0.0f) t = -t;
      const float c = 1.0f / splat_sqrt(t * t + 1.0f), s = t * c;
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
  for (int r = 0; r < 3; ++r) u[r] = e[r][order[0]], v[r] = e[r][order[1]];
  splat_canonical_sign(u);
  splat_canonical_sign(v);
  n[0] = u[1] * v[2] - u[2] * v[1], n[1] = u[2] * v[0] - u[0] * v[2], n[2] = u[0] * v[1] - u[1] * v[0];
  SPLAT_GLOBAL const float* n0 = normals + 4 * (size_t)i;
  float m[3] = {n0[0], n0[1], n0[2]};
  for (uint r = 0; r < k; ++r) {
    SPLAT_GLOBAL const float* p = positions + 4 * (size_t)row[r];
    const float wx = p[0] - p0[0], wy = p[1] - p0[1], wz = p[2] - p0[2];
    const float d = splat_sqrt(wx * wx + wy * wy + wz * wz);
    const float weight = splat_exp(-3.0f * d * scale);
    SPLAT_GLOBAL const float* nj = normals + 4 * (size_t)row[r];
    m[0] += nj[0] * weight, m[1] += nj[1] * weight, m[2] += nj[2] * weight;
  }
  if (m[0] * n[0] + m[1] * n[1] + m[2] * n[2] < 0.0f)
    for (int r = 0; r < 3; ++r) u[r] = -u[r], v[r] = -v[r], n[r] = -n[r];
}

// Colours within the tolerance φ on every channel (the splat thesis §2.3.2).
inline bool splat_color_similar(int ar, int ag, int ab, int br, int bg, int bb, int tolerance) {
  return splat_abs(ar - br) <= tolerance && splat_abs(ag - bg) <= tolerance && splat_abs(ab - bb) <= tolerance;
}

// Size rule for one phase (the splat thesis §4.1.1–§4.1.2): geometric max(e1, e2), colour
// extrapolation 2 e2 − e1, e1 with no violator (or with at_accepted).
inline float splat_size_rule(float e1, float e2, int stop, bool at_accepted) {
  if (at_accepted || stop == STOP_NONE || e2 < e1) return e1;
  return stop == STOP_COLOR ? e2 + (e2 - e1) : e2;
}

// Sort key of a candidate at in-plane offset (x, y): its distance (circle phase) or
// λ = x²/(b² − y²) (ellipse phase with minor axis b), −1 when unusable.
inline float splat_growth_key(bool ellipse, float x, float y, float b) {
  if (!ellipse) return splat_sqrt(x * x + y * y);
  const float den = b * b - y * y;
  return den > 0.0f ? x * x / den : -1.0f;
}

// Safe points (the splat thesis §2.2.3): the accepted set's projections (xs, ys), sorted by
// (x, y, local index), whose local indices are order[]; every point on their convex hull (vertices
// and edges, within 1e-6 of the extent; monotone chain) but the start point (local index 0) gets
// on_hull_bit in q[local index]. extent: the larger side of the points' bounding box. hull: scratch
// for 2·qn indices. Needs qn > 3.
inline void splat_mark_hull(SPLAT_GLOBAL const float* xs, SPLAT_GLOBAL const float* ys, SPLAT_GLOBAL const uint* order,
                            uint qn, float extent, SPLAT_GLOBAL uint* hull, SPLAT_GLOBAL uint* q, uint on_hull_bit) {
  uint hn = 0;
  for (uint r = 0; r < qn; ++r) {
    while (hn >= 2 && (xs[hull[hn - 1]] - xs[hull[hn - 2]]) * (ys[r] - ys[hull[hn - 2]]) -
                              (ys[hull[hn - 1]] - ys[hull[hn - 2]]) * (xs[r] - xs[hull[hn - 2]]) <= 0.0f)
      --hn;
    hull[hn++] = r;
  }
  const uint lower = hn + 1u;
  for (uint r = qn - 1u; r-- > 0;) {
    while (hn >= lower && (xs[hull[hn - 1]] - xs[hull[hn - 2]]) * (ys[r] - ys[hull[hn - 2]]) -
                                 (ys[hull[hn - 1]] - ys[hull[hn - 2]]) * (xs[r] - xs[hull[hn - 2]]) <= 0.0f)
      --hn;
    hull[hn++] = r;
  }
  const float tolerance = 1e-6f * extent;
  const float tolerance2 = tolerance * tolerance;
  for (uint r = 0; r < qn; ++r) {
    bool on_hull = false;
    for (uint e = 0; e + 1u < hn && !on_hull; ++e) {
      const float ax = xs[hull[e]], ay = ys[hull[e]];
      const float ex = xs[hull[e + 1u]] - ax, ey = ys[hull[e + 1u]] - ay;
      const float wx = xs[r] - ax, wy = ys[r] - ay;
      const float ee = ex * ex + ey * ey;
      float t = ee > 0.0f ? (wx * ex + wy * ey) / ee : 0.0f;
      t = splat_fmin(splat_fmax(t, 0.0f), 1.0f);
      const float dx = wx - t * ex, dy = wy - t * ey;
      on_hull = dx * dx + dy * dy <= tolerance2;
    }
    if (on_hull && order[r] != 0u) q[order[r]] |= on_hull_bit;
  }
}

#endif  // SPLATCL_SPLAT_FIT_H
