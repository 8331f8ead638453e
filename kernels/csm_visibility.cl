// Coherent shadow maps, visibility queries: one work-item per (receiver, light) query, through every
// occluder instance. The query itself lives in csm_query.h, shared with the native reference
// (host/csm/visibility.cpp). Light: xyz = point (w = 1) or direction towards the light (w = 0), so
// the light vector is light.xyz − light.w · receiver.xyz. Output: lit fraction (0 or 1 without PCF).
#include "csm_query.h"

kernel void csm_visibility_queries(global const float4* receivers, global const float4* lights, uint count,
                                   global const CsmInstance* instances, uint instance_count,
                                   global const CsmOccluder* occluders, global const CsmCell* cells,
                                   global const uint* offsets, global const uint* ends, global const float* depths,
                                   uint filter, float bias, global float* out) {
  const size_t q = get_global_id(0);
  if (q >= count) return;
  const CsmScene scene = {instances, instance_count, occluders, cells, offsets, ends, depths};
  const float4 p = receivers[q], l = lights[q];
  const float wx = l.x - l.w * p.x, wy = l.y - l.w * p.y, wz = l.z - l.w * p.z;
  out[q] = csm_visibility(&scene, p.x, p.y, p.z, wx, wy, wz, filter, bias);
}
