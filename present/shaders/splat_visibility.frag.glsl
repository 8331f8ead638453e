// Pass 1: the ellipse and clip-line test; the depth is pushed back by ε in the vertex shader.
in vec2 v_local;
flat in vec3 v_clip, v_clip2;
void main() {
  if (dot(v_local, v_local) > 1.0 || dot(v_local, v_clip.xy) > v_clip.z || dot(v_local, v_clip2.xy) > v_clip2.z) discard;
}
