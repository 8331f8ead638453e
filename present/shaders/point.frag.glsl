// Low-quality mode: the nearest point's attributes with weight 1, into the accumulation targets,
// and its object into the object target where the frame binds it (GBuffer::kObjectAttachment).
#include "accumulation_targets.glsl"
in float v_view_z;
uniform uint u_object;
layout(location = 4) out uint o_object;
void main() {
  write_splat(1.0, v_view_z, v_normal);
  o_object = u_object;
}
