// The pixel's ellipse coordinate and the splat test, shared by both splat passes so that they keep
// the same pixels. The visibility pass pushes each corner back by ε along its view ray, scaling its
// clip w by s = 1 + ε/|corner|, which changes the rasteriser's perspective-correct interpolation: a
// pixel at the rim kept by pass 1 (its depth hides what lies behind) but dropped by pass 2 was a
// black single-pixel hole in close-ups (41 in a 640×480 grazing view of the torus). The vertex
// shader hands over (ellipse coordinate, 1) · s, whose perspective-correct interpolation divided
// by its last component is the coordinate interpolated over the un-pushed w, in either pass.
in vec3 v_local_scaled;
flat in vec3 v_clip, v_clip2;
vec2 splat_local() { return v_local_scaled.xy / v_local_scaled.z; }
bool outside_splat(vec2 local) {
  return dot(local, local) > 1.0 || dot(local, v_clip.xy) > v_clip.z || dot(local, v_clip2.xy) > v_clip2.z;
}
