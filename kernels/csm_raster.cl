// Coherent shadow maps, raster capture: the same two depths per pixel as the ray-cast capture
// (csm_capture.cl), by rasterizing every triangle of the mesh into each map's two-layer depth
// buffer. CPU shape: one work-item (and work-group) per map, a serial loop over vertices and
// triangles, the map's own rows of z1/z2 as its depth buffer: no atomics, no barriers. The
// per-map code is csm_raster.h, shared with the native reference (host/csm/raster_capture.cpp).
#include "csm_trace.h"
#include "csm_raster.h"

// Maps [map_first, map_first + maps) of the camera table; work-item k uses scratch slot k
// (4 floats per vertex) for its projected vertices and writes map (map_first + k) of z1/z2.
kernel void csm_raster_capture(global const float* vertices, uint vertex_count, global const uint* tris, uint tri_count,
                               global const CsmCamera* cameras, uint map_first, uint maps, uint resolution, float radius,
                               float pixel_scale, float half_pixel, float depth_scale, float eps, uint single_hit_rule,
                               global float* scratch, global float* z1_out, global float* z2_out) {
  const size_t slot = get_global_id(0);
  if (slot >= maps) return;
  const size_t map = map_first + slot;
  global const CsmCamera* cam = cameras + map;
  const CsmRasterCamera c = {cam->d[0], cam->d[1], cam->d[2], cam->u[0], cam->u[1], cam->u[2], cam->v[0], cam->v[1], cam->v[2]};
  const CsmRasterParams p = {resolution, radius, pixel_scale, half_pixel, depth_scale, eps, single_hit_rule};
  const size_t pixels = (size_t)resolution * resolution;
  global float* proj = scratch + slot * 4 * (size_t)vertex_count;
  global float* z1 = z1_out + map * pixels;
  global float* z2 = z2_out + map * pixels;
  csm_raster_project(vertices, vertex_count, c, p, proj);
  csm_raster_clear(z1, z2, (uint)pixels);
  csm_raster_triangles(tris, tri_count, proj, p, z1, z2);
  csm_raster_finish(z1, z2, p);
}
