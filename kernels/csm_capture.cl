// Coherent shadow maps, capture: two depths per pixel (first and next distinct surface) for a batch
// of orthographic maps, by ray casting against the host-built BVH. CPU shape: one work-item per
// (map, pixel row), a serial loop over the row, no barriers. Native reference: host/csm/capture.cpp.
#include "csm_trace.h"

// Depth is linear, 0 at the camera plane and 1 at distance 2R (Talpe §4.2); empty and
// single-surface pixels by single_hit_rule (csm_pixel_depths in csm_trace.h).
kernel void csm_capture(global const CsmNode* nodes, global const CsmTriangle* tris, global const CsmCamera* cameras,
                        uint resolution, uint rows_total, float radius, float half_pixel, float depth_scale, float eps,
                        uint single_hit_rule, global float* z1_out, global float* z2_out) {
  const size_t item = get_global_id(0);
  if (item >= rows_total) return;
  const size_t map = item / resolution;
  const uint row = (uint)(item % resolution);
  global const CsmCamera* cam = cameras + map;
  const float3 d = (float3)(cam->d[0], cam->d[1], cam->d[2]);
  const float3 u = (float3)(cam->u[0], cam->u[1], cam->u[2]);
  const float3 v = (float3)(cam->v[0], cam->v[1], cam->v[2]);
  const float3 inv = (float3)(cam->inv[0], cam->inv[1], cam->inv[2]);
  const float3 dir = -d;
  const float y = (float)(2 * row + 1) * half_pixel - radius;
  const size_t base = map * (size_t)resolution * resolution + (size_t)row * resolution;
  for (uint i = 0; i < resolution; ++i) {
    const float x = (float)(2 * i + 1) * half_pixel - radius;
    const float3 o = (float3)(radius * d.x + x * u.x + y * v.x, radius * d.y + x * u.y + y * v.y,
                              radius * d.z + x * u.z + y * v.z);
    const float o3[3] = {o.x, o.y, o.z}, dir3[3] = {dir.x, dir.y, dir.z}, inv3[3] = {inv.x, inv.y, inv.z};
    const CsmHits hits = csm_trace(nodes, tris, o3, dir3, inv3, eps, CSM_TRACE_FIRST_TWO, INFINITY);
    float z1, z2;
    csm_pixel_depths(hits.t1 * depth_scale, hits.t2 * depth_scale, x, y, radius, depth_scale, single_hit_rule, &z1, &z2);
    z1_out[base + i] = z1;
    z2_out[base + i] = z2;
  }
}
