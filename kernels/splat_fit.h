// Splat fit, the parts the kernel (splat_fit.cl) and the native reference (host/splats/reference.cpp,
// which includes this file inside a namespace) must compute bit for bit alike: the growth's size
// rule and sort key, the colour test, and the convex-hull test of the safe points. Written once, in
// the common subset of OpenCL C and C++ (scalar floats, no contraction). Twice, on purpose: the walk
// over the rings (the kernel's in-place ring, hash set and capacity relaunch are checked against the
// reference's plain vectors and std::sort). Twice, for now: the PCA frame, whose scalar form here
// gave frames that differ from the reference on Intel's OpenCL CPU runtime (its float4 form in
// splat_fit.cl agrees with the reference on PoCL and on Intel's runtime).
#ifndef SPLATCL_SPLAT_FIT_H
#define SPLATCL_SPLAT_FIT_H

#ifdef __OPENCL_C_VERSION__
#pragma OPENCL FP_CONTRACT OFF
#define SPLAT_GLOBAL global
#define splat_sqrt sqrt
#define splat_fmin fmin
#define splat_fmax fmax
#define splat_abs abs
#define splat_fabs fabs
#else
#define SPLAT_GLOBAL
#define splat_sqrt std::sqrt
#define splat_fmin std::fmin
#define splat_fmax std::fmax
#define splat_abs std::abs
#define splat_fabs std::fabs
#endif

// What ended a growth phase (the reference's Stop has the same values).
#define STOP_NONE 0
#define STOP_GEOMETRY 1
#define STOP_COLOR 2

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

// An undefined normal (a sample whose mesh gave none).
inline bool splat_zero_normal(float x, float y, float z) { return x == 0.0f && y == 0.0f && z == 0.0f; }

// Whether neighbour normal (bx, by, bz) takes part in the PCA frame of a sample with normal
// (ax, ay, az): within the crease angle (crease_cos = its cosine; -1 or less takes every neighbour,
// as the thesis does). An undefined (zero) normal on either side is taken. An extension: the
// thesis's frame averages across a sharp edge, which tilts the splats there (bevels) off both faces.
inline bool splat_same_side_of_crease(float ax, float ay, float az, float bx, float by, float bz, float crease_cos) {
  if (crease_cos <= -1.0f) return true;
  if (splat_zero_normal(ax, ay, az) || splat_zero_normal(bx, by, bz)) return true;
  return ax * bx + ay * by + az * bz >= crease_cos;
}

// The PCA frame (u, v, n) of a sample whose neighbours lie on a line, as along a finely divided rim
// (a circle of 400 vertices, where only the rim's own vertices are near): its second axis is noise,
// and the normal u × v lay in the cap's plane while the samples face the side, turned by the sign
// test into the solid for half of them (a helper's audit: 400 of a 400-sided cylinder's 1,679
// splats faced 90° off every face near them, 200 into the solid). Where n stands more than 30°
// off the sample's own normal m, the frame takes m's direction as its normal and u made orthogonal
// to it. (Not the neighbourhood's weighted mean normal, which the sign test uses: its exp weights
// differ in the last bits between OpenCL and C++, and as a normal that changed the growth.) Off at
// crease_cos <= -1 (the thesis's frames), for a zero m, and where u lies within 6° of m.
inline void splat_frame_facing(float* u, float* v, float* n, float mx, float my, float mz, float crease_cos) {
  if (crease_cos <= -1.0f) return;
  const float ml = splat_sqrt(mx * mx + my * my + mz * mz);
  if (!(ml > 0.0f)) return;
  const float ax = mx / ml, ay = my / ml, az = mz / ml;
  if (splat_fabs(n[0] * ax + n[1] * ay + n[2] * az) >= 0.8660254f) return;
  const float along = u[0] * ax + u[1] * ay + u[2] * az;
  const float wx = u[0] - along * ax, wy = u[1] - along * ay, wz = u[2] - along * az;
  const float wl = splat_sqrt(wx * wx + wy * wy + wz * wz);
  if (!(wl > 0.1f)) return;
  u[0] = wx / wl, u[1] = wy / wl, u[2] = wz / wl;
  n[0] = ax, n[1] = ay, n[2] = az;
  v[0] = n[1] * u[2] - n[2] * u[1];
  v[1] = n[2] * u[0] - n[0] * u[2];
  v[2] = n[0] * u[1] - n[1] * u[0];
}

// Whether two sample normals lie on opposed sheets of the surface: facing apart beyond 180° minus
// the crease angle (the two sides of a thin plate or of a knife edge). Never at crease_cos <= -1 (the
// thesis), nor for an undefined (zero) normal, which a crease angle over 90° would otherwise oppose
// to everything. The kNN graph (host/splats/neighbors.cpp) passes over such neighbours too.
inline bool splat_opposed_sheets(float ax, float ay, float az, float bx, float by, float bz, float crease_cos) {
  if (crease_cos <= -1.0f) return false;
  if (splat_zero_normal(ax, ay, az) || splat_zero_normal(bx, by, bz)) return false;
  return ax * bx + ay * by + az * bz < -crease_cos;
}

// Whether a candidate at height h above the splat's plane, with sample normal (bx, by, bz), lies on
// another sheet of the surface than the splat's sample (normal (ax, ay, az)): behind the plane and
// facing away from it beyond 180° minus the crease angle (the other side of a thin plate or a
// knife edge). Growth neither tests, accepts nor expands such a candidate: its depth below the plane
// says nothing about the sheet the splat lies on, and as a violator it stopped the splats of a plate
// thinner than about 2 ε at the sample under their start (every one shrank to nothing, and gap
// filling had to cover the whole part). Off at crease_cos <= -1 (the thesis's growth).
inline bool splat_other_sheet(float ax, float ay, float az, float bx, float by, float bz, float h, float crease_cos) {
  return h < 0.0f && splat_opposed_sheets(ax, ay, az, bx, by, bz, crease_cos);
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
