// Coherent shadow maps, raster capture: one orthographic map rasterized into a two-layer depth
// buffer. Written once, in the common subset of OpenCL C and C++ (scalar floats, + − × ÷ and
// comparisons, no contraction), so the kernel (csm_raster.cl) and the native reference
// (host/csm/raster_capture.cpp, which includes this file inside a namespace) agree bit for bit.
//
// Per pixel it keeps exactly what the ray-cast capture (csm_trace.h) keeps along the pixel-centre
// ray: the nearest depth z1 and the nearest depth z2 > z1 + eps, hits within eps of z1 counting as
// the same surface, updated triangle by triangle with the same rule.
//
// Pixel coordinates: pixel (i, j) has its centre at (i, j); a vertex at (x, y) on the camera plane
// sits at ((x + R)·M/2R − 0.5, (y + R)·M/2R − 0.5). Coverage: a pixel centre is inside a triangle
// when it is strictly inside every edge; a centre exactly on an edge belongs to the side the point
// centre + (ε, ε·δ) (0 < δ ≪ 1) lies on. Every edge function is evaluated in one canonical
// direction (lower vertex index first), so two triangles sharing an edge compute the same float and
// exactly one of them owns a centre on it: no pixel is hit twice or missed on a shared edge.
// Depth: the plane through the three vertices' depths, interpolated with the edge functions.
#ifndef SPLATCL_CSM_RASTER_H
#define SPLATCL_CSM_RASTER_H

#ifdef __OPENCL_C_VERSION__
#pragma OPENCL FP_CONTRACT OFF
#define CSM_RGLOBAL global
#define CSM_RINF INFINITY
#else
#define CSM_RGLOBAL
#define CSM_RINF (std::numeric_limits<float>::infinity())
#endif

#include "csm_inline.h"
// csm_pixel_depths comes from csm_trace.h: the kernel includes it first, a host includer brings it
// into the namespace it includes this file in.

// One map's camera as the raster needs it (the sphere-grid camera without the inverse direction).
typedef struct {
  float dx, dy, dz, ux, uy, uz, vx, vy, vz;
} CsmRasterCamera;

typedef struct {
  uint resolution;
  float radius;       // R
  float pixel_scale;  // M / 2R
  float half_pixel;   // R / M
  float depth_scale;  // 1 / 2R
  float eps;          // hit tolerance in depth units
  uint single_hit_rule;  // 0 sphere-exit, 1 exact, 2 thin (csm::single_hit_code)
} CsmRasterParams;

// Vertices (relative to the sphere centre, xyz) → pixel coordinates and depth (x, y, z, unused).
CSM_INLINE void csm_raster_project(CSM_RGLOBAL const float* vertices, uint count, CsmRasterCamera c, CsmRasterParams p,
                               CSM_RGLOBAL float* out) {
  for (uint k = 0; k < count; ++k) {
    const float x = vertices[3u * k], y = vertices[3u * k + 1u], z = vertices[3u * k + 2u];
    out[4u * k] = (x * c.ux + y * c.uy + z * c.uz + p.radius) * p.pixel_scale - 0.5f;
    out[4u * k + 1u] = (x * c.vx + y * c.vy + z * c.vz + p.radius) * p.pixel_scale - 0.5f;
    out[4u * k + 2u] = (p.radius - (x * c.dx + y * c.dy + z * c.dz)) * p.depth_scale;
    out[4u * k + 3u] = 0.0f;
  }
}

CSM_INLINE float csm_rmin(float a, float b) { return a < b ? a : b; }
CSM_INLINE float csm_rmax(float a, float b) { return a > b ? a : b; }

// Smallest integer >= v and largest integer <= v for 0 <= v < 2^23.
CSM_INLINE int csm_rceil(float v) {
  const int i = (int)v;
  return (float)i < v ? i + 1 : i;
}

// Canonical edge from vertex index ia to ib: origin (ox, oy) and direction (ex, ey) of the lower
// index's vertex to the higher's; sign = +1 when that is a → b, −1 when b → a.
typedef struct {
  float ox, oy, ex, ey, sign, tie;
} CsmEdge;

CSM_INLINE CsmEdge csm_edge(uint ia, uint ib, CSM_RGLOBAL const float* a, CSM_RGLOBAL const float* b) {
  CsmEdge e;
  const int forward = ia < ib;
  CSM_RGLOBAL const float* lo = forward ? a : b;
  CSM_RGLOBAL const float* hi = forward ? b : a;
  e.ox = lo[0];
  e.oy = lo[1];
  e.ex = hi[0] - lo[0];
  e.ey = hi[1] - lo[1];
  e.sign = forward ? 1.0f : -1.0f;
  // Sign of the edge function's change along (1, δ): −ey, or ex when the edge is horizontal.
  e.tie = e.ey != 0.0f ? -e.ey : e.ex;
  return e;
}

CSM_INLINE float csm_edge_value(CsmEdge e, float px, float py) { return e.ex * (py - e.oy) - e.ey * (px - e.ox); }

// Whether the centre is on the triangle's side of the edge (orientation = ±1, the triangle's
// winding sign); `value` is the canonical edge function at the centre.
CSM_INLINE int csm_edge_inside(CsmEdge e, float value, float orientation) {
  const float side = e.sign * orientation;
  return value * side > 0.0f || (value == 0.0f && e.tie * side > 0.0f);
}

// The two-layer update of the ray-cast capture (csm_first_two_hits) in depth units.
CSM_INLINE void csm_raster_keep(CSM_RGLOBAL float* z1, CSM_RGLOBAL float* z2, float z, float eps) {
  const float t1 = *z1;
  if (z < t1 - eps) {
    *z2 = t1;
    *z1 = z;
  } else if (z <= t1 + eps) {
    *z1 = csm_rmin(t1, z);
  } else if (z < *z2) {
    *z2 = z;
  }
}

// Rasterizes triangles (vertex index triples) with projected vertices `proj` (csm_raster_project)
// into z1/z2 (M² each, cleared to +inf beforehand).
CSM_INLINE void csm_raster_triangles(CSM_RGLOBAL const uint* tris, uint count, CSM_RGLOBAL const float* proj, CsmRasterParams p,
                                 CSM_RGLOBAL float* z1, CSM_RGLOBAL float* z2) {
  const float top = (float)p.resolution - 1.0f;
  for (uint t = 0; t < count; ++t) {
    const uint ia = tris[3u * t], ib = tris[3u * t + 1u], ic = tris[3u * t + 2u];
    CSM_RGLOBAL const float* a = proj + 4u * ia;
    CSM_RGLOBAL const float* b = proj + 4u * ib;
    CSM_RGLOBAL const float* c = proj + 4u * ic;
    // Pixel centres inside the bounding box (most triangles of a dense mesh contain none).
    const float minx = csm_rmax(csm_rmin(csm_rmin(a[0], b[0]), c[0]), 0.0f);
    const float maxx = csm_rmin(csm_rmax(csm_rmax(a[0], b[0]), c[0]), top);
    const float miny = csm_rmax(csm_rmin(csm_rmin(a[1], b[1]), c[1]), 0.0f);
    const float maxy = csm_rmin(csm_rmax(csm_rmax(a[1], b[1]), c[1]), top);
    if (!(minx <= maxx) || !(miny <= maxy)) continue;
    const int x0 = csm_rceil(minx), x1 = (int)maxx, y0 = csm_rceil(miny), y1 = (int)maxy;
    if (x0 > x1 || y0 > y1) continue;
    const CsmEdge bc = csm_edge(ib, ic, b, c), ca = csm_edge(ic, ia, c, a), ab = csm_edge(ia, ib, a, b);
    // Twice the signed area, as the a → b edge function at c.
    const float area = ab.sign * csm_edge_value(ab, c[0], c[1]);
    if (area == 0.0f) continue;
    const float orientation = area > 0.0f ? 1.0f : -1.0f;
    const float inv_area = 1.0f / area;
    const float za = a[2], dzb = b[2] - a[2], dzc = c[2] - a[2];
    for (int j = y0; j <= y1; ++j) {
      const float py = (float)j;
      for (int i = x0; i <= x1; ++i) {
        const float px = (float)i;
        const float wa = csm_edge_value(bc, px, py), wb = csm_edge_value(ca, px, py), wc = csm_edge_value(ab, px, py);
        if (!csm_edge_inside(bc, wa, orientation) || !csm_edge_inside(ca, wb, orientation) ||
            !csm_edge_inside(ab, wc, orientation))
          continue;
        // Barycentric weights of b and c: the oriented edge functions opposite them over the area.
        const float z = za + (ca.sign * wb * dzb + ab.sign * wc * dzc) * inv_area;
        const uint pixel = (uint)j * p.resolution + (uint)i;
        csm_raster_keep(z1 + pixel, z2 + pixel, z, p.eps);
      }
    }
  }
}

CSM_INLINE void csm_raster_clear(CSM_RGLOBAL float* z1, CSM_RGLOBAL float* z2, uint pixels) {
  for (uint k = 0; k < pixels; ++k) {
    z1[k] = CSM_RINF;
    z2[k] = CSM_RINF;
  }
}

// The ray-cast capture's rules for empty and single-surface pixels (csm_pixel_depths, csm_trace.h).
CSM_INLINE void csm_raster_finish(CSM_RGLOBAL float* z1, CSM_RGLOBAL float* z2, CsmRasterParams p) {
  for (uint j = 0; j < p.resolution; ++j) {
    const float y = (float)(2u * j + 1u) * p.half_pixel - p.radius;
    for (uint i = 0; i < p.resolution; ++i) {
      const uint pixel = j * p.resolution + i;
      const float x = (float)(2u * i + 1u) * p.half_pixel - p.radius;
      float a, b;
      csm_pixel_depths(z1[pixel], z2[pixel], x, y, p.radius, p.depth_scale, p.single_hit_rule, &a, &b);
      z1[pixel] = a;
      z2[pixel] = b;
    }
  }
}

#endif  // SPLATCL_CSM_RASTER_H
