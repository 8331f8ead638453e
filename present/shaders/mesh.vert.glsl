// Triangle mesh, for the coverage test.
layout(location = 0) in vec3 a_position;
uniform mat4 u_model, u_view, u_proj;
out float v_view_z;
void main() {
  vec4 view = u_view * u_model * vec4(a_position, 1.0);
  v_view_z = view.z;
  gl_Position = u_proj * view;
}
