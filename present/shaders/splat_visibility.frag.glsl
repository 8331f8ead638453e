// Pass 1: the ellipse test; the depth is pushed back by ε in the vertex shader.
in vec2 v_local;
void main() {
  if (dot(v_local, v_local) > 1.0) discard;
}
