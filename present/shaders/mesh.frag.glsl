// The mask's value is the view distance along −z (> 0 where the mesh covers the pixel).
in float v_view_z;
layout(location = 0) out vec4 o_mask;
void main() { o_mask = vec4(-v_view_z); }
