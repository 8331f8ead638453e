// Coherent shadow maps: BVH traversal shared by the capture and query kernels. The operations and
// their order match host/csm/bvh.cpp exactly (no contraction), so kernel and native reference
// return the same floats.
#ifndef SPLATCL_CSM_TRACE_H
#define SPLATCL_CSM_TRACE_H

#pragma OPENCL FP_CONTRACT OFF

#define CSM_MAX_DEPTH 64

typedef struct {
  float lo[3];
  uint index;  // internal: right child (left is the next node); leaf: first triangle
  float hi[3];
  uint count;  // 0 for internal nodes
} CsmNode;

typedef struct {
  float v0[3], e1[3], e2[3];
} CsmTriangle;

typedef struct {
  float d[3], u[3], v[3], inv[3];
} CsmCamera;

// Plain comparisons rather than fmin/fmax: inverse directions are finite (1e30 stands in for 1/0).
inline float csm_min(float a, float b) { return a < b ? a : b; }
inline float csm_max(float a, float b) { return a > b ? a : b; }

inline float csm_box_entry(global const CsmNode* n, float3 o, float3 inv, float limit) {
  const float ax = (n->lo[0] - o.x) * inv.x, bx = (n->hi[0] - o.x) * inv.x;
  const float ay = (n->lo[1] - o.y) * inv.y, by = (n->hi[1] - o.y) * inv.y;
  const float az = (n->lo[2] - o.z) * inv.z, bz = (n->hi[2] - o.z) * inv.z;
  const float tmin = csm_max(csm_max(csm_min(ax, bx), csm_min(ay, by)), csm_min(az, bz));
  const float tmax = csm_min(csm_min(csm_max(ax, bx), csm_max(ay, by)), csm_max(az, bz));
  return (tmin <= tmax && tmax >= 0.0f && tmin <= limit) ? tmin : INFINITY;
}

inline float csm_triangle_hit(global const CsmTriangle* tri, float3 o, float3 dir) {
  const float e1x = tri->e1[0], e1y = tri->e1[1], e1z = tri->e1[2];
  const float e2x = tri->e2[0], e2y = tri->e2[1], e2z = tri->e2[2];
  const float px = dir.y * e2z - dir.z * e2y, py = dir.z * e2x - dir.x * e2z, pz = dir.x * e2y - dir.y * e2x;
  const float det = e1x * px + e1y * py + e1z * pz;
  if (det == 0.0f) return INFINITY;
  const float inv_det = 1.0f / det;
  const float tx = o.x - tri->v0[0], ty = o.y - tri->v0[1], tz = o.z - tri->v0[2];
  const float u = (tx * px + ty * py + tz * pz) * inv_det;
  if (u < 0.0f || u > 1.0f) return INFINITY;
  const float qx = ty * e1z - tz * e1y, qy = tz * e1x - tx * e1z, qz = tx * e1y - ty * e1x;
  const float v = (dir.x * qx + dir.y * qy + dir.z * qz) * inv_det;
  if (v < 0.0f || u + v > 1.0f) return INFINITY;
  const float t = (e2x * qx + e2y * qy + e2z * qz) * inv_det;
  return t > 0.0f ? t : INFINITY;
}

// Nearest hit t1 and next distinct hit t2 (> t1 + eps) along o + t·dir; INFINITY where none.
// Nearer child first; nodes entered beyond the current t2 are skipped.
inline float2 csm_first_two_hits(global const CsmNode* nodes, global const CsmTriangle* tris, float3 o, float3 dir,
                                 float3 inv, float eps) {
  float t1 = INFINITY, t2 = INFINITY;
  if (csm_box_entry(nodes, o, inv, t2) == INFINITY) return (float2)(t1, t2);
  uint stack_node[CSM_MAX_DEPTH];
  float stack_entry[CSM_MAX_DEPTH];
  int sp = 0;
  uint node = 0;
  for (;;) {
    global const CsmNode* n = nodes + node;
    bool descend = false;
    if (n->count > 0) {
      const uint end = n->index + n->count;
      for (uint k = n->index; k < end; ++k) {
        const float t = csm_triangle_hit(tris + k, o, dir);
        if (t < t1 - eps) {
          t2 = t1;
          t1 = t;
        } else if (t <= t1 + eps) {
          t1 = fmin(t1, t);
        } else if (t < t2) {
          t2 = t;
        }
      }
    } else {
      const uint left = node + 1, right = n->index;
      const float el = csm_box_entry(nodes + left, o, inv, t2), er = csm_box_entry(nodes + right, o, inv, t2);
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
      if (stack_entry[sp] <= t2) {
        node = stack_node[sp];
        found = true;
        break;
      }
    }
    if (!found) break;
  }
  return (float2)(t1, t2);
}

#endif  // SPLATCL_CSM_TRACE_H
