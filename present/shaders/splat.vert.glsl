// The splat passes' vertex shader: one triangle around each splat's ellipse. Compiled with
// VISIBILITY_PASS defined for pass 1, which reads no lighting rows.
#include "splat_head.glsl"
// The ellipse coordinate times the visibility pass's w scale (splat_local.glsl).
out vec3 v_local_scaled;
out vec3 v_view_pos;
// The clip lines in ellipse coordinates: a pixel is kept where dot(coordinate, xy) <= z for both.
flat out vec3 v_clip, v_clip2;
// The Phong splat's shading normal (world space, not normalised): linear in the ellipse coordinates,
// so the rasteriser's perspective-correct interpolation over the splat's plane is exact.
out vec3 v_shading_normal;
uniform float u_depth_offset;  // ε of the visibility pass, 0 in the accumulation pass
// A back copy's extra push in both passes (SplatFrame::back_offset): at a fold, where the surface
// turns away, the splats beyond the fold face away and their back copies, lying in tangent planes,
// stand in front of the surface there, within ε of the front side's splats; pushed back by 2ε, they
// show only where they stand ε in front of any front side (among back copies alone, inside a bowl,
// nothing changes). Only grazing ones (the eye within ~78° of their plane, fully within ~72°):
// seen more steeply, a back side is a surface like any other, and a sheet lying on the floor, seen
// from its back, blends with the floor within ε as before instead of vanishing under it.
uniform float u_back_offset;
void main() {
  vec3 c, n;
  mat3 m;
  // Culled splats (back-facing, or outside their LOD interval) are moved outside the clip volume.
  // The splat passes cost per primitive on llvmpipe more than per pixel: one triangle circumscribing
  // the ellipse (inradius 1 in ellipse coordinates) is cheaper than a quad of two.
  if (!splat_head(uint(gl_VertexID) / 3u, c, n, m)) {
    gl_Position = vec4(0.0, 0.0, 2.0, 1.0);
    gl_ClipDistance[0] = -1.0;
    v_local_scaled = vec3(2.0, 2.0, 1.0); v_view_pos = vec3(0.0); v_shading_normal = vec3(0.0);
    return;
  }
  // The clip line is where the surface ends (a sharp edge), so it stays put when k scales the splat.
  v_clip = vec3(a_clip.x * length(a_major), a_clip.y * length(a_minor), a_clip.z / u_scale);
  v_clip2 = vec3(a_clip2.x * length(a_major), a_clip2.y * length(a_minor), a_clip2.z / u_scale);
  int j = gl_VertexID % 3;
  // 1 % beyond the triangle circumscribing the unit disk, so the ellipse does not touch its edges,
  // where the two passes' rasterisation of the pushed and un-pushed corners could round apart.
  vec2 corner = 1.01 * (j == 0 ? vec2(0.0, 2.0) : vec2(j == 1 ? -1.7320508 : 1.7320508, -1.0));
  // The triangle lies in the splat's plane, so the rasterised depth is the ray-cast depth of that plane
  // at every pixel (perspective correct), and the interpolated corner is the pixel's ellipse coordinate.
  vec3 p = c + u_scale * (corner.x * (m * a_major) + corner.y * (m * a_minor));
#ifdef VISIBILITY_PASS
  v_shading_normal = vec3(0.0);  // the visibility pass writes depth only
#else
  v_shading_normal = m * (static3(SPLAT_NORMAL) + u_scale * (corner.x * static3(SPLAT_NORMAL_DU) + corner.y * static3(SPLAT_NORMAL_DV)));
#endif
  v_view_pos = (u_view * vec4(p, 1.0)).xyz;
  // The visibility pass pushes each corner back by ε along its view ray (a perspective projection:
  // w is proportional to the view z, which splat_local.glsl's argument needs). Done per vertex rather than
  // per pixel, the fragment shader writes no depth and llvmpipe keeps its early depth test; across
  // a splat the offset differs from ε by a second-order amount in the splat's angular size.
  float back_push = 0.0;
  if (a_back_copy) {
    float facing = abs(dot(normalize(m * cross(a_major, a_minor)), normalize(u_eye - c)));
    back_push = u_back_offset * clamp((0.5 - facing) / 0.3, 0.0, 1.0);
  }
  float push = 1.0 + (u_depth_offset + back_push) / length(v_view_pos);
  gl_Position = u_proj * vec4(v_view_pos * push, 1.0);
  v_local_scaled = vec3(corner, 1.0) * push;
  // The near plane where the un-pushed splat crosses it, in both passes (GL_CLIP_DISTANCE0): the
  // pushed triangle lies ε farther and its own near clip kept pixels pass 2 clipped, a black band
  // where the near plane cuts a surface. The distance w - z of the un-pushed clip position (reversed
  // depth: the near plane is z = w), times
  // push, is zero along the pushed triangle's edges where the un-pushed one's is (the same argument
  // as for v_local_scaled: x, y and w scale by push, the screen position stays).
  vec4 unpushed = u_proj * vec4(v_view_pos, 1.0);
  gl_ClipDistance[0] = push * (unpushed.w - unpushed.z);
}
