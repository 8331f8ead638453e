// Pass 2: Gaussian-weighted attribute sums into the G-buffer.
#include "accumulation_targets.glsl"
#include "splat_local.glsl"
in vec3 v_view_pos;
in vec3 v_shading_normal;
uniform float u_beta;
void main() {
  vec2 local = splat_local();
  if (outside_splat(local)) discard;
  float r2 = dot(local, local);
  write_splat(exp(-u_beta * r2), v_view_pos.z, normalize(v_shading_normal));
}
