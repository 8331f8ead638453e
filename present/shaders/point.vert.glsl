// Low-quality mode: one square point per splat.
#include "splat_head.glsl"
uniform float u_viewport_height;
out float v_view_z;
void main() {
  vec3 c, n;
  mat3 m;
  bool drawn = splat_head(uint(gl_VertexID), c, n, m);
  vec4 view = u_view * vec4(c, 1.0);
  v_view_z = view.z;
  if (!drawn) { gl_Position = vec4(0.0, 0.0, 2.0, 1.0); gl_PointSize = 1.0; return; }
  gl_Position = u_proj * view;
  // Projected diameter of the splat's major axis (the point-rendering thesis: r·n/z·h/(t−b), ×2 for the diameter).
  float radius = u_scale * length(m * a_major);
  gl_PointSize = max(1.0, 2.0 * radius * u_proj[1][1] * 0.5 * u_viewport_height / max(-view.z, 1e-3));
}
