// Low-quality mode: the nearest point's attributes with weight 1, into the accumulation targets.
#include "accumulation_targets.glsl"
in float v_view_z;
void main() { write_splat(1.0, v_view_z, v_normal); }
