// Coherent shadow maps, ambient occlusion: one work-item per CSM_AO_LANES receivers (set by the
// host), `samples` directions of each receiver's pattern through every occluder instance (Müller
// §5.3), the receivers side by side in the components of vectors. The per-receiver work lives in
// csm_query.h, shared with the native reference (host/csm/ao.cpp), which runs it one receiver at a time.
#include "csm_query.h"

kernel void csm_ambient_occlusion_receivers(global const float4* positions, global const float4* normals,
                                            global const uint* pattern_of, uint count, global const float4* patterns,
                                            uint samples, global const CsmInstance* instances, uint instance_count,
                                            global const CsmOccluder* occluders, global const CsmCell* cells,
                                            global const uint* offsets, global const uint* ends,
                                            global const float* depths, global const float* bounds, uint ground,
                                            float bias, uint own_instance, global float4* out) {
  const size_t first = get_global_id(0) * CSM_AO_LANES;
  if (first >= count) return;
  const CsmScene scene = {instances, instance_count, occluders, cells, offsets, ends, depths, bounds};
  // Lanes past the end repeat the last receiver and store nothing.
  const csm_vuint lane = (uint)first + CSM_VLANE_IDS;
  const csm_vint valid = lane < count;
  const csm_vuint r = csm_vsel(valid, lane, csm_vu(count - 1u));
  csm_vfloat result[4];
  csm_ambient_occlusion(&scene, (global const float*)patterns, CSM_VGATHER(csm_vuint, pattern_of, r, ) * (4u * samples), samples,
                        CSM_VGATHER(csm_vfloat, positions, r, .x), CSM_VGATHER(csm_vfloat, positions, r, .y),
                        CSM_VGATHER(csm_vfloat, positions, r, .z), CSM_VGATHER(csm_vfloat, normals, r, .x),
                        CSM_VGATHER(csm_vfloat, normals, r, .y), CSM_VGATHER(csm_vfloat, normals, r, .z), own_instance,
                        CSM_VGATHER(csm_vfloat, positions, r, .w), valid, ground, bias, result);
  float x[CSM_AO_LANES], y[CSM_AO_LANES], z[CSM_AO_LANES], w[CSM_AO_LANES];
  CSM_VJOIN(vstore, CSM_AO_LANES)(result[0], 0, x);
  CSM_VJOIN(vstore, CSM_AO_LANES)(result[1], 0, y);
  CSM_VJOIN(vstore, CSM_AO_LANES)(result[2], 0, z);
  CSM_VJOIN(vstore, CSM_AO_LANES)(result[3], 0, w);
  const uint lanes = count - (uint)first < CSM_AO_LANES ? count - (uint)first : CSM_AO_LANES;
  for (uint l = 0; l < lanes; ++l) out[first + l] = (float4)(x[l], y[l], z[l], w[l]);
}
