// Coherent shadow maps, ambient occlusion: one work-item per receiver, `samples` directions of the
// receiver's pattern through every occluder instance (Müller §5.3). The per-receiver work lives
// in csm_query.h, shared with the native reference (host/csm/ao.cpp).
#include "csm_query.h"

kernel void csm_ambient_occlusion_receivers(global const float4* positions, global const float4* normals,
                                            global const uint* pattern_of, uint count, global const float4* patterns,
                                            uint samples, global const CsmInstance* instances, uint instance_count,
                                            global const CsmOccluder* occluders, global const CsmCell* cells,
                                            global const uint* offsets, global const uint* ends,
                                            global const float* depths, global const float* bounds, uint ground,
                                            float bias, global float4* out) {
  const size_t r = get_global_id(0);
  if (r >= count) return;
  const CsmScene scene = {instances, instance_count, occluders, cells, offsets, ends, depths, bounds};
  const float4 p = positions[r], n = normals[r];
  float result[4];
  csm_ambient_occlusion(&scene, (global const float*)(patterns + (size_t)pattern_of[r] * samples), samples, p.x, p.y, p.z,
                        n.x, n.y, n.z, ground, bias, result);
  out[r] = (float4)(result[0], result[1], result[2], result[3]);
}
