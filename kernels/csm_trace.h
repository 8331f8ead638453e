// Coherent shadow maps: BVH traversal for the ray-cast capture (csm_capture.cl) and the host's
// exact visibility and scene ray caster. Written once, in the common subset of OpenCL C and C++
// (scalar floats, + − × ÷ and comparisons, no contraction), so the kernel and the native traversal
// (host/core/bvh.cpp, which includes this file inside a namespace) walk the same nodes in the same
// order and return the same floats.
#ifndef SPLATCL_CSM_TRACE_H
#define SPLATCL_CSM_TRACE_H

#ifdef __OPENCL_C_VERSION__
#pragma OPENCL FP_CONTRACT OFF
#define CSM_TGLOBAL global
#define csm_tfmin fmin
#define csm_tfmax fmax
#define csm_tsqrt sqrt
#define CSM_TINF INFINITY
#define csm_tnext_up(v) nextafter(v, INFINITY)
#else
#define CSM_TGLOBAL
#define csm_tfmin std::fmin
#define csm_tfmax std::fmax
#define csm_tsqrt std::sqrt
#define CSM_TINF INFINITY
#define csm_tnext_up(v) std::nextafter(v, INFINITY)
#endif

#include "csm_inline.h"

// A pixel's stored depths from its first two hits t1, t2 (depth units, +inf where there is none),
// by the single-hit rule (csm::single_hit_code: 0 sphere-exit, 1 exact, 2 thin); written once for
// both capture methods and their references. Empty: z1 = 1, z2 = +inf. A second hit is z2, except
// under thin, where every hit pixel takes z2 = z1 (an open mesh that encloses air has nothing solid
// between its hits). A single hit takes z2 = where the ray through (x, y) leaves the bounding
// sphere (sphere-exit, then kept above z1) or z2 = z1, a value that merges with nothing.
CSM_INLINE void csm_pixel_depths(float t1, float t2, float x, float y, float radius, float depth_scale, uint rule, float* z1,
                                 float* z2) {
  float a = 1.0f, b = CSM_TINF;
  if (t1 != CSM_TINF) {
    a = t1;
    if (t2 != CSM_TINF && rule != 2u) {
      b = t2;
    } else if (rule != 0u) {
      b = a;
    } else {
      b = (radius + csm_tsqrt(csm_tfmax(radius * radius - (x * x + y * y), 0.0f))) * depth_scale;
    }
    if (!(b >= a)) b = a;
    if (rule == 0u && !(b > a)) b = csm_tnext_up(a);
  }
  *z1 = a;
  *z2 = b;
}

// The deepest BVH the builder makes; the traversal stack has this many entries.
#define CSM_MAX_DEPTH 64

// Internal node: count == 0, children at (this + 1) and `index`. Leaf: triangles [index, index + count).
typedef struct {
  float lo[3];
  uint index;
  float hi[3];
  uint count;
} CsmNode;

// A triangle as vertex 0 and the two edges from it, precomputed once on the host.
typedef struct {
  float v0[3], e1[3], e2[3];
} CsmTriangle;

typedef struct {
  float d[3], u[3], v[3], inv[3];
} CsmCamera;

// Plain comparisons rather than fmin/fmax: inverse directions are finite (1e30 stands in for 1/0).
CSM_INLINE float csm_min(float a, float b) { return a < b ? a : b; }
CSM_INLINE float csm_max(float a, float b) { return a > b ? a : b; }

// Entry distance of the ray into the node's box, or INFINITY when it misses or enters beyond `limit`.
CSM_INLINE float csm_box_entry(CSM_TGLOBAL const CsmNode* n, const float* o, const float* inv, float limit) {
  const float ax = (n->lo[0] - o[0]) * inv[0], bx = (n->hi[0] - o[0]) * inv[0];
  const float ay = (n->lo[1] - o[1]) * inv[1], by = (n->hi[1] - o[1]) * inv[1];
  const float az = (n->lo[2] - o[2]) * inv[2], bz = (n->hi[2] - o[2]) * inv[2];
  const float tmin = csm_max(csm_max(csm_min(ax, bx), csm_min(ay, by)), csm_min(az, bz));
  const float tmax = csm_min(csm_min(csm_max(ax, bx), csm_max(ay, by)), csm_max(az, bz));
  return (tmin <= tmax && tmax >= 0.0f && tmin <= limit) ? tmin : INFINITY;
}

// Ray-triangle distance (Möller–Trumbore), INFINITY on a miss, with the barycentric bounds
// widened by `edge_tolerance`: 0 is the capture's test (edges inclusive); a small positive
// value closes the cracks that float rounding leaves along edges shared by two triangles, which a
// primary ray through such an edge sees as a hole (the scene ray caster's test).
CSM_INLINE float csm_triangle_hit_within(CSM_TGLOBAL const CsmTriangle* tri, const float* o, const float* dir,
                                         float edge_tolerance) {
  const float e1x = tri->e1[0], e1y = tri->e1[1], e1z = tri->e1[2];
  const float e2x = tri->e2[0], e2y = tri->e2[1], e2z = tri->e2[2];
  const float px = dir[1] * e2z - dir[2] * e2y, py = dir[2] * e2x - dir[0] * e2z, pz = dir[0] * e2y - dir[1] * e2x;
  const float det = e1x * px + e1y * py + e1z * pz;
  if (det == 0.0f) return INFINITY;
  const float inv_det = 1.0f / det;
  const float tx = o[0] - tri->v0[0], ty = o[1] - tri->v0[1], tz = o[2] - tri->v0[2];
  const float u = (tx * px + ty * py + tz * pz) * inv_det;
  if (u < -edge_tolerance || u > 1.0f + edge_tolerance) return INFINITY;
  const float qx = ty * e1z - tz * e1y, qy = tz * e1x - tx * e1z, qz = tx * e1y - ty * e1x;
  const float v = (dir[0] * qx + dir[1] * qy + dir[2] * qz) * inv_det;
  if (v < -edge_tolerance || u + v > 1.0f + edge_tolerance) return INFINITY;
  const float t = (e2x * qx + e2y * qy + e2z * qz) * inv_det;
  return t > 0.0f ? t : INFINITY;
}

// The capture's ray-triangle distance: edges inclusive.
CSM_INLINE float csm_triangle_hit(CSM_TGLOBAL const CsmTriangle* tri, const float* o, const float* dir) {
  return csm_triangle_hit_within(tri, o, dir, 0.0f);
}

typedef struct {
  float t1, t2;
} CsmHits;

// What csm_trace looks for.
#define CSM_TRACE_FIRST_TWO 0  // the nearest hit t1 and the next distinct one t2 (> t1 + eps)
#define CSM_TRACE_ANY 1        // any hit before t_max: t1 = the first found (not the nearest)

// Depth-first walk along o + t·dir (t > 0), nearer child first, skipping nodes entered beyond the
// current limit (t2 for CSM_TRACE_FIRST_TWO, t_max for CSM_TRACE_ANY). Hits within `eps` of t1
// count as the same surface (shared edges and vertices). INFINITY where there is none.
CSM_INLINE CsmHits csm_trace(CSM_TGLOBAL const CsmNode* nodes, CSM_TGLOBAL const CsmTriangle* tris, const float* o,
                         const float* dir, const float* inv, float eps, int mode, float t_max) {
  CsmHits hits;
  hits.t1 = INFINITY;
  hits.t2 = INFINITY;
  if (csm_box_entry(nodes, o, inv, mode == CSM_TRACE_ANY ? t_max : hits.t2) == INFINITY) return hits;
  uint stack_node[CSM_MAX_DEPTH];
  float stack_entry[CSM_MAX_DEPTH];
  int sp = 0;
  uint node = 0;
  for (;;) {
    CSM_TGLOBAL const CsmNode* n = nodes + node;
    bool descend = false;
    if (n->count > 0) {
      const uint end = n->index + n->count;
      for (uint k = n->index; k < end; ++k) {
        const float t = csm_triangle_hit(tris + k, o, dir);
        if (mode == CSM_TRACE_ANY) {
          if (t < t_max) {
            hits.t1 = t;
            return hits;
          }
        } else if (t < hits.t1 - eps) {
          hits.t2 = hits.t1;
          hits.t1 = t;
        } else if (t <= hits.t1 + eps) {
          hits.t1 = csm_tfmin(hits.t1, t);
        } else if (t < hits.t2) {
          hits.t2 = t;
        }
      }
    } else {
      const float limit = mode == CSM_TRACE_ANY ? t_max : hits.t2;
      const uint left = node + 1, right = n->index;
      const float el = csm_box_entry(nodes + left, o, inv, limit), er = csm_box_entry(nodes + right, o, inv, limit);
      if (el != INFINITY && er != INFINITY) {
        const bool left_first = el <= er;
        stack_node[sp] = left_first ? right : left;
        stack_entry[sp] = left_first ? er : el;
        ++sp;
        node = left_first ? left : right;
        descend = true;
      } else if (el != INFINITY) {
        node = left;
        descend = true;
      } else if (er != INFINITY) {
        node = right;
        descend = true;
      }
    }
    if (descend) continue;
    bool found = false;
    while (sp > 0) {
      --sp;
      if (stack_entry[sp] <= (mode == CSM_TRACE_ANY ? t_max : hits.t2)) {
        node = stack_node[sp];
        found = true;
        break;
      }
    }
    if (!found) break;
  }
  return hits;
}

#endif  // SPLATCL_CSM_TRACE_H
