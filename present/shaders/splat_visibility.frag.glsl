// Pass 1: the ellipse and clip-line test; the depth is pushed back by ε in the vertex shader.
#include "splat_local.glsl"
void main() {
  if (outside_splat(splat_local())) discard;
}
