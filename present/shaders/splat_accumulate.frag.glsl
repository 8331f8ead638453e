// Pass 2: Gaussian-weighted attribute sums into the G-buffer.
#include "accumulation_targets.glsl"
in vec2 v_local;
in vec3 v_view_pos;
flat in vec3 v_clip, v_clip2;
in vec3 v_shading_normal;
uniform float u_beta;
void main() {
  float r2 = dot(v_local, v_local);
  if (r2 > 1.0 || dot(v_local, v_clip.xy) > v_clip.z || dot(v_local, v_clip2.xy) > v_clip2.z) discard;
  write_splat(exp(-u_beta * r2), v_view_pos.z, normalize(v_shading_normal));
}
