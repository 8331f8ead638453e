// Clustered shading, the arithmetic that the kernels (cluster.cl, cluster_lights.cl) and the native
// reference (host/cluster/layout.cpp, which includes this file inside a namespace) must compute bit
// for bit alike: the view distance of a depth sample, the normal cell, a cluster's view-space box
// and the sphere–box test of the light assignment. Written once, in the common subset of OpenCL C
// and C++ (scalar floats, no contraction; the sphere–box test also for float vectors). Twice, on
// purpose: the depth slice of a distance (the kernel's fast first guess and one lookup is checked
// against the reference's binary search over the same boundary table).
#ifndef SPLATCL_CLUSTER_LAYOUT_H
#define SPLATCL_CLUSTER_LAYOUT_H

#ifdef __OPENCL_C_VERSION__
#pragma OPENCL FP_CONTRACT OFF
#define CLUSTER_GLOBAL global
#define cluster_fabs fabs
#define cluster_fmin fmin
#define cluster_fmax fmax
#define cluster_umin min
#else
#define CLUSTER_GLOBAL
#define cluster_fabs std::fabs
#define cluster_umin std::min
// fmin and fmax as OpenCL C defines them (a NaN operand gives the other one), inline: std::fmin
// and std::fmax are library calls.
inline float cluster_fmin(float a, float b) { return b < a || a != a ? b : a; }
inline float cluster_fmax(float a, float b) { return a < b || a != a ? b : a; }
#endif

// View distance (−z_view) of a view-space z, or −1 outside [near, far] (NaN included).
inline float cluster_view_distance(float view_z, float near_plane, float far_plane) {
  const float distance = -view_z;
  return (distance >= near_plane && distance <= far_plane) ? distance : -1.0f;
}

// View distance of a reversed window depth (near 1, far 0: the presenter's depth buffer, glClipControl
// ZERO_TO_ONE) under the perspective projection of (near, far): near·far / (near + depth·(far − near)),
// computed as near / (near/far + depth·(1 − near/far)): near·far overflowed for far planes beyond
// 3.4e38 / near, which put every pixel on the far plane.
// Reversed, the float depth keeps its precision out to the far plane: the conventional depth (near 0,
// far 1) read 1.0 for every pixel at near 1e-7 and far 500, and 0.62 off brute-force shading at 1e-6.
inline float cluster_window_to_distance(float depth, float near_plane, float near_over_far, float far_share) {
  return near_plane / (near_over_far + depth * far_share);
}

// The same clamped into [near, far], or −1 for a depth outside (0, 1] (background: the clear value 0).
inline float cluster_window_distance(float depth, float near_plane, float far_plane, float near_over_far,
                                     float far_share) {
  const float distance = cluster_fmin(
      cluster_fmax(cluster_window_to_distance(depth, near_plane, near_over_far, far_share), near_plane),
      far_plane);
  return (depth > 0.0f && depth <= 1.0f) ? distance : -1.0f;
}

// Cube-map cell 0..53 of a view-space normal: face = 2·axis + (major < 0), then the two other
// components (in x, y, z order) divided by |major| fall into thirds of [−1, 1]. Branch-free.
inline uint cluster_normal_cell(float x, float y, float z) {
  const float ax = cluster_fabs(x), ay = cluster_fabs(y), az = cluster_fabs(z);
  const int x_major = ax >= ay && ax >= az;
  const int y_major = !x_major && ay >= az;
  const uint axis = x_major ? 0u : (y_major ? 1u : 2u);
  const float major = x_major ? x : (y_major ? y : z);
  const float u = x_major ? y : x;
  const float v = x_major || y_major ? z : y;
  const float m = cluster_fabs(major);
  const uint face = 2u * axis + (major < 0.0f ? 1u : 0u);
  const uint cell_u = (3.0f * u >= -m ? 1u : 0u) + (3.0f * u >= m ? 1u : 0u);
  const uint cell_v = (3.0f * v >= -m ? 1u : 0u) + (3.0f * v >= m ? 1u : 0u);
  return face * 9u + cell_v * 3u + cell_u;
}

// What a cluster's box depends on: the frame and tile size, the key's field layout (tile id above
// low_bits, slice above normal_bits, masked by slice_mask) and the projection (ClusterLayout).
typedef struct {
  uint width, height, tile_w, tile_h, tiles_x;
  uint low_bits, normal_bits, slice_mask;
  float two_over_width, two_over_height, tan_half_x, tan_half_y;
  float padding_scale;  // box padding per unit of far distance
} ClusterGrid;

// View-space box of the cluster with key `key`: its tile's sub-frustum between the boundaries of
// its depth slice (boundaries[slice], boundaries[slice + 1]), padded by far distance ×
// padding_scale. lo, hi: x, y, z of the box's corners.
inline void cluster_key_box(ClusterGrid grid, uint key, CLUSTER_GLOBAL const float* boundaries, float* lo,
                            float* hi) {
  const uint tile = key >> grid.low_bits;
  const uint slice = (key >> grid.normal_bits) & grid.slice_mask;
  const uint i = tile % grid.tiles_x, j = tile / grid.tiles_x;
  const float near_d = boundaries[slice], far_d = boundaries[slice + 1u];
  const float x0 = (float)(i * grid.tile_w) * grid.two_over_width - 1.0f;
  const float x1 = (float)cluster_umin((i + 1u) * grid.tile_w, grid.width) * grid.two_over_width - 1.0f;
  const float y0 = (float)(j * grid.tile_h) * grid.two_over_height - 1.0f;
  const float y1 = (float)cluster_umin((j + 1u) * grid.tile_h, grid.height) * grid.two_over_height - 1.0f;
  const float pad = far_d * grid.padding_scale;
  lo[0] = cluster_fmin(x0 * near_d, x0 * far_d) * grid.tan_half_x - pad;
  lo[1] = cluster_fmin(y0 * near_d, y0 * far_d) * grid.tan_half_y - pad;
  lo[2] = -far_d - pad;
  hi[0] = cluster_fmax(x1 * near_d, x1 * far_d) * grid.tan_half_x + pad;
  hi[1] = cluster_fmax(y1 * near_d, y1 * far_d) * grid.tan_half_y + pad;
  hi[2] = -near_d + pad;
}

// Defines MASK NAME(lo_x, lo_y, lo_z, hi_x, hi_y, hi_z, x, y, z, r): whether spheres (centre
// (x, y, z), radius r, of the float type T: a scalar, or a vector for a block of lights) touch the
// box [lo, hi], as squared distance from the centre to the box ≤ r².
#define DEFINE_CLUSTER_SPHERE_TOUCHES_BOX(NAME, T, MASK)                                                       \
  inline MASK NAME(float lo_x, float lo_y, float lo_z, float hi_x, float hi_y, float hi_z, T x, T y, T z, T r) { \
    const T dx = cluster_fmax(cluster_fmax(lo_x - x, x - hi_x), 0.0f);                                       \
    const T dy = cluster_fmax(cluster_fmax(lo_y - y, y - hi_y), 0.0f);                                       \
    const T dz = cluster_fmax(cluster_fmax(lo_z - z, z - hi_z), 0.0f);                                       \
    return dx * dx + dy * dy + dz * dz <= r * r;                                                             \
  }

#endif  // SPLATCL_CLUSTER_LAYOUT_H
