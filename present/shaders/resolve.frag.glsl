// Silhouette anti-aliasing of the tone-mapped image: the splat passes give each pixel one surface
// (or none), so an object's outline is a staircase. Where a pixel's coverage differs from one of its
// 4 neighbours' or the view depth jumps between them (one object in front of another), the pixel is
// the mean of itself (weight 2) and its 4 neighbours: a tent filter across the outline only, so the
// surfaces' own detail stays sharp.
#include "layout.h"
layout(binding = UNIT_DISPLAY) uniform sampler2D u_display;
layout(binding = UNIT_WEIGHT_ALBEDO) uniform sampler2D g_weight_albedo;
layout(binding = UNIT_Z_NORMAL) uniform sampler2D g_z_normal;
uniform float u_depth_jump;  // a relative view-depth change between neighbours that makes an outline
layout(location = 0) out vec4 o_display;

float depth(ivec2 p) {
  float w = texelFetch(g_weight_albedo, p, 0).x;
  return w > 0.0 ? -texelFetch(g_z_normal, p, 0).x / w : -1.0;  // -1: no splat
}

void main() {
  ivec2 p = ivec2(gl_FragCoord.xy), last = textureSize(u_display, 0) - 1;
  float d = depth(p);
  vec3 sum = 2.0 * texelFetch(u_display, p, 0).rgb;
  bool outline = false;
  const ivec2 steps[4] = ivec2[4](ivec2(1, 0), ivec2(-1, 0), ivec2(0, 1), ivec2(0, -1));
  for (int i = 0; i < 4; ++i) {
    ivec2 q = clamp(p + steps[i], ivec2(0), last);
    float e = depth(q);
    outline = outline || (e < 0.0) != (d < 0.0) || abs(e - d) > u_depth_jump * max(d, e);
    sum += texelFetch(u_display, q, 0).rgb;
  }
  o_display = vec4(outline ? sum / 6.0 : texelFetch(u_display, p, 0).rgb, 1.0);
}
