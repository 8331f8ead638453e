#include "present/shaders.hpp"

namespace splatcl::present::shaders {

// Per-splat attributes shared by the splat vertex shaders. Model space: centre, normal, the two
// semi-axis vectors; then the colour and the per-splat CL results (bent normal + AO, key-light
// visibility), both already in world space.
#define SPLAT_INPUTS                                                                              \
  "layout(location = 0) in vec3 a_center;\n"                                                      \
  "layout(location = 1) in vec3 a_normal;\n"                                                      \
  "layout(location = 2) in vec3 a_major;\n"                                                       \
  "layout(location = 3) in vec3 a_minor;\n"                                                       \
  "layout(location = 4) in vec3 a_albedo;\n"                                                      \
  "layout(location = 5) in vec4 a_ao;\n"                                                          \
  "layout(location = 6) in vec4 a_shadow;\n"                                                      \
  "uniform mat4 u_model, u_view, u_proj;\n"                                                       \
  "uniform vec3 u_eye;\n"                                                                         \
  "uniform float u_scale;\n"                                                                      \
  "uniform int u_base;  // first instance of the draw: gl_BaseInstance needs GL 4.6\n"                                                                      \
  "flat out vec3 v_albedo;\n"                                                                     \
  "flat out vec3 v_normal;\n"                                                                     \
  "flat out vec4 v_ao;\n"                                                                         \
  "flat out vec4 v_shadow;\n"                                                                     \
  "flat out uint v_id;\n"

const char* const kSplatVertex = "#version 450 core\n" SPLAT_INPUTS R"(
out vec2 v_local;
out vec3 v_view_pos;
void main() {
  mat3 m = mat3(u_model);
  vec3 c = (u_model * vec4(a_center, 1.0)).xyz;
  vec3 n = normalize(m * a_normal);
  v_albedo = a_albedo; v_normal = n; v_ao = a_ao; v_shadow = a_shadow; v_id = uint(gl_InstanceID + u_base);
  // Back-face culling: splats facing away from the eye are moved outside the clip volume.
  if (dot(n, u_eye - c) <= 0.0) { gl_Position = vec4(0.0, 0.0, 2.0, 1.0); v_local = vec2(2.0); v_view_pos = vec3(0.0); return; }
  vec2 corner = vec2((gl_VertexID & 1) != 0 ? 1.0 : -1.0, (gl_VertexID & 2) != 0 ? 1.0 : -1.0);
  // The quad lies in the splat's plane, so the rasterised depth is the ray-cast depth of that plane
  // at every pixel (perspective correct), and v_local is the pixel's ellipse coordinate.
  vec3 p = c + u_scale * (corner.x * (m * a_major) + corner.y * (m * a_minor));
  v_local = corner;
  v_view_pos = (u_view * vec4(p, 1.0)).xyz;
  gl_Position = u_proj * vec4(v_view_pos, 1.0);
}
)";

const char* const kSplatVisibility = R"(#version 450 core
in vec2 v_local;
in vec3 v_view_pos;
uniform mat4 u_proj;
uniform float u_depth_offset;
void main() {
  if (dot(v_local, v_local) > 1.0) discard;
  // Push the surface back by ε along the view ray, so pass 2 blends every splat within ε of the front.
  vec3 p = v_view_pos * (1.0 + u_depth_offset / length(v_view_pos));
  vec4 clip = u_proj * vec4(p, 1.0);
  gl_FragDepth = 0.5 * clip.z / clip.w + 0.5;
}
)";

const char* const kSplatAccumulate = R"(#version 450 core
in vec2 v_local;
in vec3 v_view_pos;
flat in vec3 v_albedo;
flat in vec3 v_normal;
flat in vec4 v_ao;
flat in vec4 v_shadow;
flat in uint v_id;
uniform float u_beta;
uniform int u_footprints;
layout(location = 0) out vec4 o_albedo;   // Σ w·albedo, Σ w
layout(location = 1) out vec4 o_normal;   // Σ w·n, Σ w·z_view
layout(location = 2) out vec4 o_ao;       // Σ w·bent, Σ w·AO
layout(location = 3) out vec4 o_shadow;   // Σ w·visibility per key light
vec3 hash_color(uint id) {
  uint h = id * 2654435761u; h ^= h >> 15; h *= 2246822519u; h ^= h >> 13;
  return vec3(float(h & 255u), float((h >> 8) & 255u), float((h >> 16) & 255u)) / 255.0;
}
void main() {
  float r2 = dot(v_local, v_local);
  if (r2 > 1.0) discard;
  float w = exp(-u_beta * r2);
  o_albedo = vec4(w * (u_footprints != 0 ? hash_color(v_id) : v_albedo), w);
  o_normal = vec4(w * v_normal, w * v_view_pos.z);
  o_ao = w * v_ao;
  o_shadow = w * v_shadow;
}
)";

const char* const kPointVertex = "#version 450 core\n" SPLAT_INPUTS R"(
uniform float u_viewport_height;
out float v_view_z;
void main() {
  mat3 m = mat3(u_model);
  vec3 c = (u_model * vec4(a_center, 1.0)).xyz;
  vec3 n = normalize(m * a_normal);
  v_albedo = a_albedo; v_normal = n; v_ao = a_ao; v_shadow = a_shadow; v_id = uint(gl_InstanceID + u_base);
  vec4 view = u_view * vec4(c, 1.0);
  v_view_z = view.z;
  if (dot(n, u_eye - c) <= 0.0) { gl_Position = vec4(0.0, 0.0, 2.0, 1.0); gl_PointSize = 1.0; return; }
  gl_Position = u_proj * view;
  // Projected diameter of the splat's major axis (digest: r·n/z·h/(t−b), ×2 for the diameter).
  float radius = u_scale * length(m * a_major);
  gl_PointSize = max(1.0, 2.0 * radius * u_proj[1][1] * 0.5 * u_viewport_height / max(-view.z, 1e-3));
}
)";

const char* const kPointFragment = R"(#version 450 core
flat in vec3 v_albedo;
flat in vec3 v_normal;
flat in vec4 v_ao;
flat in vec4 v_shadow;
flat in uint v_id;
in float v_view_z;
uniform int u_footprints;
layout(location = 0) out vec4 g_albedo;
layout(location = 1) out vec4 g_normal;
layout(location = 2) out float g_view_z;
layout(location = 3) out vec4 g_ao;
layout(location = 4) out vec4 g_shadow;
vec3 hash_color(uint id) {
  uint h = id * 2654435761u; h ^= h >> 15; h *= 2246822519u; h ^= h >> 13;
  return vec3(float(h & 255u), float((h >> 8) & 255u), float((h >> 16) & 255u)) / 255.0;
}
void main() {
  g_albedo = vec4(u_footprints != 0 ? hash_color(v_id) : v_albedo, 1.0);
  g_normal = vec4(v_normal, 0.0);
  g_view_z = v_view_z;
  g_ao = vec4(normalize(v_ao.xyz + vec3(0.0, 1e-6, 0.0)), v_ao.w);
  g_shadow = v_shadow;
}
)";

const char* const kFullscreenVertex = R"(#version 450 core
void main() {
  vec2 p = vec2((gl_VertexID == 1) ? 3.0 : -1.0, (gl_VertexID == 2) ? 3.0 : -1.0);
  gl_Position = vec4(p, 0.0, 1.0);
}
)";

const char* const kNormalize = R"(#version 450 core
layout(binding = 0) uniform sampler2D u_albedo;
layout(binding = 1) uniform sampler2D u_normal;
layout(binding = 2) uniform sampler2D u_ao;
layout(binding = 3) uniform sampler2D u_shadow;
layout(location = 0) out vec4 g_albedo;
layout(location = 1) out vec4 g_normal;
layout(location = 2) out float g_view_z;
layout(location = 3) out vec4 g_ao;
layout(location = 4) out vec4 g_shadow;
void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  vec4 a = texelFetch(u_albedo, p, 0);
  if (a.w <= 0.0) { g_albedo = vec4(0.0); g_normal = vec4(0.0); g_view_z = 0.0; g_ao = vec4(0.0, 1.0, 0.0, 1.0); g_shadow = vec4(1.0); return; }
  float inv = 1.0 / a.w;
  vec4 n = texelFetch(u_normal, p, 0);
  vec4 ao = texelFetch(u_ao, p, 0) * inv;
  g_albedo = vec4(a.rgb * inv, 1.0);
  g_normal = vec4(normalize(n.xyz), 0.0);
  g_view_z = n.w * inv;
  g_ao = vec4(length(ao.xyz) > 0.0 ? normalize(ao.xyz) : g_normal.xyz, ao.w);
  g_shadow = texelFetch(u_shadow, p, 0) * inv;
}
)";

const char* const kShade = R"(#version 450 core
struct Light { vec4 center_radius; vec4 color; };
layout(std430, binding = 0) readonly buffer Lights { Light lights[]; };
layout(std430, binding = 1) readonly buffer Offsets { uint list_offsets[]; };
layout(std430, binding = 2) readonly buffer Counts { uint list_counts[]; };
layout(std430, binding = 3) readonly buffer Indices { uint list_indices[]; };
layout(binding = 0) uniform sampler2D g_albedo;
layout(binding = 1) uniform sampler2D g_normal;
layout(binding = 2) uniform sampler2D g_view_z;
layout(binding = 3) uniform sampler2D g_ao;
layout(binding = 4) uniform sampler2D g_shadow;
layout(binding = 5) uniform usampler2D u_pixel_list;
layout(binding = 6) uniform sampler2D u_pixel_shadow;
layout(binding = 7) uniform sampler2D u_pixel_ao_texture;
uniform mat4 u_view;
uniform vec2 u_tan_half;       // tan of half the field of view, x and y
uniform vec2 u_viewport;
uniform int u_brute_force;     // 1: every light at every pixel; 0: the pixel's list
uniform int u_light_count;
uniform int u_key_count;
uniform vec4 u_key_center[4];  // view space, radius in w
uniform vec3 u_key_color[4];
uniform int u_pixel_shadows;   // 1: key-light visibility per pixel, 0: per splat (G-buffer)
uniform vec3 u_sh[9];          // irradiance SH of the sky
uniform int u_debug;           // 0 final, 1 albedo, 2 normals, 3 AO, 4 lights per cluster, 5 shadows, 6 depth
uniform int u_use_ao;
uniform int u_pixel_ao;        // 1: AO and bent normal per pixel (quality mode), 0: per splat (G-buffer)
uniform float u_heat_max;
uniform int u_tone_map;
layout(location = 0) out vec4 o_hdr;
layout(location = 1) out vec4 o_display;
vec4 o_color;

float falloff(float d, float r) { float q = d / r; return clamp(1.0 - q * q, 0.0, 1.0); }

vec3 sh_irradiance(vec3 n) {  // Ramamoorthi & Hanrahan 2001, Eq. 13
  const float c1 = 0.429043, c2 = 0.511664, c3 = 0.743125, c4 = 0.886227, c5 = 0.247708;
  return c1 * u_sh[8] * (n.x * n.x - n.y * n.y) + c3 * u_sh[6] * n.z * n.z + c4 * u_sh[0] - c5 * u_sh[6]
       + 2.0 * c1 * (u_sh[4] * n.x * n.y + u_sh[7] * n.x * n.z + u_sh[5] * n.y * n.z)
       + 2.0 * c2 * (u_sh[3] * n.x + u_sh[1] * n.y + u_sh[2] * n.z);
}

vec3 heat(float t) {
  t = clamp(t, 0.0, 1.0);
  return clamp(vec3(1.5 * t - 0.25, 1.5 - abs(2.0 * t - 1.0) * 1.5, 1.25 - 1.5 * t), 0.0, 1.0) * vec3(1.0, 1.0, 1.0);
}

void shade(ivec2 p);
void main() {
  shade(ivec2(gl_FragCoord.xy));
  o_hdr = o_color;
  vec3 c = u_tone_map != 0 ? vec3(1.0) - exp(-o_color.rgb) : o_color.rgb;  // exposure curve keeps many lights in range
  o_display = vec4(pow(clamp(c, 0.0, 1.0), vec3(1.0 / 2.2)), 1.0);
}
void shade(ivec2 p) {
  vec4 albedo = texelFetch(g_albedo, p, 0);
  if (albedo.w <= 0.0) { o_color = vec4(u_debug == 0 ? sh_irradiance(vec3(0.0, 0.3, 1.0)) / 3.14159265 * 0.6 : vec3(0.0), 1.0); return; }
  vec3 n_world = texelFetch(g_normal, p, 0).xyz;
  float view_z = texelFetch(g_view_z, p, 0).x;
  vec4 ao = u_pixel_ao != 0 ? texelFetch(u_pixel_ao_texture, p, 0) : texelFetch(g_ao, p, 0);
  vec4 shadow = u_pixel_shadows != 0 ? texelFetch(u_pixel_shadow, p, 0) : texelFetch(g_shadow, p, 0);
  uint list = texelFetch(u_pixel_list, p, 0).x;
  if (u_debug == 1) { o_color = vec4(albedo.rgb, 1.0); return; }
  if (u_debug == 2) { o_color = vec4(0.5 * n_world + 0.5, 1.0); return; }
  if (u_debug == 3) { o_color = vec4(vec3(ao.w), 1.0); return; }
  if (u_debug == 4) {
    float count = u_brute_force != 0 ? float(u_light_count) : (list == 0xFFFFFFFFu ? 0.0 : float(list_counts[list]));
    o_color = vec4(heat(count / u_heat_max), 1.0);
    return;
  }
  if (u_debug == 5) {  // the darkest key light's visibility
    float v = 1.0;
    for (int k = 0; k < u_key_count; ++k) v = min(v, shadow[k]);
    o_color = vec4(vec3(v), 1.0);
    return;
  }
  if (u_debug == 6) { o_color = vec4(vec3(-view_z / 20.0), 1.0); return; }
  // Same reconstruction as cluster::pixel_view_position.
  float d = -view_z;
  vec2 ndc = (vec2(p) + 0.5) * 2.0 / u_viewport - 1.0;
  vec3 position = vec3(ndc * d * u_tan_half, -d);
  vec3 n = normalize(mat3(u_view) * n_world);
  vec3 sum = vec3(0.0);
  if (u_brute_force != 0) {
    for (int i = 0; i < u_light_count; ++i) {
      vec3 to_light = lights[i].center_radius.xyz - position;
      float dist = length(to_light);
      float f = falloff(dist, lights[i].center_radius.w);
      if (f <= 0.0 || dist <= 0.0) continue;
      sum += lights[i].color.rgb * (f * max(0.0, dot(n, to_light / dist)));
    }
  } else if (list != 0xFFFFFFFFu) {
    uint begin = list_offsets[list], end = begin + list_counts[list];
    for (uint k = begin; k < end; ++k) {
      Light light = lights[list_indices[k]];
      vec3 to_light = light.center_radius.xyz - position;
      float dist = length(to_light);
      float f = falloff(dist, light.center_radius.w);
      if (f <= 0.0 || dist <= 0.0) continue;
      sum += light.color.rgb * (f * max(0.0, dot(n, to_light / dist)));
    }
  }
  for (int k = 0; k < u_key_count; ++k) {
    vec3 to_light = u_key_center[k].xyz - position;
    float dist = length(to_light);
    float f = falloff(dist, u_key_center[k].w);
    if (f > 0.0 && dist > 0.0) sum += u_key_color[k] * (f * max(0.0, dot(n, to_light / dist)) * shadow[k]);
  }
  // Ambient: sky irradiance in the bent normal's direction, times AO (albedo/π · E).
  vec3 bent = u_use_ao != 0 ? ao.xyz : n_world;
  float occlusion = u_use_ao != 0 ? ao.w : 1.0;
  vec3 ambient = max(sh_irradiance(bent), vec3(0.0)) / 3.14159265 * occlusion;
  o_color = vec4(albedo.rgb * (sum + ambient), 1.0);
}
)";

const char* const kMeshVertex = R"(#version 450 core
layout(location = 0) in vec3 a_position;
uniform mat4 u_model, u_view, u_proj;
void main() { gl_Position = u_proj * u_view * u_model * vec4(a_position, 1.0); }
)";

const char* const kMeshFragment = R"(#version 450 core
layout(location = 0) out vec4 o_mask;
void main() { o_mask = vec4(1.0); }
)";

}  // namespace splatcl::present::shaders
