// Coherent shadow maps, visibility queries through one occluder instance, chunked: each work-item
// runs a contiguous chunk of (receiver, light) queries in order, reusing the previous query's map
// choice, walk start, and stored depths where they repeat (csm_instance_visibility_cached in
// csm_query.h, shared with the native reference host/csm/visibility.cpp). The host launches it once
// per instance: the first launch writes the visibility, later ones multiply into it, in instance
// order, as csm_visibility does (its early exit at 0 changes nothing: 0 times a fraction is 0).
// Light: xyz = point (w = 1) or direction towards the light (w = 0), so the light vector is
// light.xyz − light.w · receiver.xyz. Output: lit fraction (0 or 1 without PCF).
#include "csm_query.h"

kernel void csm_visibility_chunks(global const float4* receivers, global const float4* lights, uint count, uint chunk,
                                  global const CsmInstance* instances, uint instance, global const CsmOccluder* occluders,
                                  global const CsmCell* cells, global const uint* offsets, global const uint* ends,
                                  global const float* depths, global const float* bounds, uint filter, float bias,
                                  uint multiply, global float* out) {
  const size_t begin = get_global_id(0) * (size_t)chunk;
  if (begin >= count) return;
  const size_t end = min(begin + chunk, (size_t)count);
  const CsmScene scene = {instances, 0u, occluders, cells, offsets, ends, depths, bounds};
  CsmQueryCache cache;
  csm_cache_reset(&cache);
  for (size_t q = begin; q < end; ++q) {
    const float4 p = receivers[q], l = lights[q];
    const float wx = l.x - l.w * p.x, wy = l.y - l.w * p.y, wz = l.z - l.w * p.z;
    const float v = csm_instance_visibility_cached(&scene, instance, p.x, p.y, p.z, wx, wy, wz, filter, bias, &cache);
    out[q] = multiply ? out[q] * v : v;
  }
}
