// Pass 1: the ellipse and clip-line test; the depth is pushed back by ε in the vertex shader. The
// object target (GBuffer) keeps the nearest splat's object; the pass writes it only where a frame
// asks for it (its draw buffer is GL_NONE otherwise).
#include "splat_local.glsl"
uniform uint u_object;
layout(location = 0) out uint o_object;
void main() {
  if (outside_splat(splat_local())) discard;
  o_object = u_object;
}
