// The accumulation targets, also the G-buffer the shading reads (present/gbuffer.hpp): it divides
// by Σw itself, so no normalisation pass writes a second set of full-screen targets. Σw and Σw·z
// lead their targets, so the light-list stage reads them back as single channels. With the flat
// inputs of splat_head.
flat in vec3 v_albedo;
flat in vec3 v_normal;
flat in vec3 v_ambient;
flat in vec4 v_shadow;
flat in uint v_id;
uniform int u_footprints;

layout(location = 0) out vec4 o_weight_albedo;   // Σw, Σw·albedo
layout(location = 1) out vec4 o_z_normal;        // Σw·z_view, Σw·n (world)
layout(location = 2) out vec4 o_shadow_ambient;  // Σw·visibility of key light 0, Σw·ambient
layout(location = 3) out vec4 o_shadows;         // Σw·visibility of key lights 1-3 (bound with 2+ key lights)
vec3 hash_color(uint id) {
  uint h = id * 2654435761u; h ^= h >> 15; h *= 2246822519u; h ^= h >> 13;
  return vec3(float(h & 255u), float((h >> 8) & 255u), float((h >> 16) & 255u)) / 255.0;
}
// normal: the world shading normal at the pixel (unit).
void write_splat(float w, float view_z, vec3 normal) {
  o_weight_albedo = vec4(w, w * (u_footprints != 0 ? hash_color(v_id) : v_albedo));
  o_z_normal = vec4(w * view_z, w * normal);
  o_shadow_ambient = vec4(w * v_shadow.x, w * v_ambient);
  o_shadows = vec4(w * v_shadow.yzw, 0.0);
}
