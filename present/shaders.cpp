#include "present/shaders.hpp"

namespace splatcl::present::shaders {

// Per-splat attributes shared by the splat vertex shaders. Model space: centre, normal, the two
// semi-axis vectors; then the colour, the per-splat CL results (bent normal + AO, key-light
// visibility), both already in world space, and the LOD interval [e_min, e_max) (model units).
#define SPLAT_INPUTS                                                                              \
  "layout(location = 0) in vec3 a_center;\n"                                                      \
  "layout(location = 1) in vec3 a_normal;\n"                                                      \
  "layout(location = 2) in vec3 a_major;\n"                                                       \
  "layout(location = 3) in vec3 a_minor;\n"                                                       \
  "layout(location = 4) in vec3 a_albedo;\n"                                                      \
  "layout(location = 5) in vec4 a_ao;\n"                                                          \
  "layout(location = 6) in vec4 a_shadow;\n"                                                      \
  "layout(location = 7) in vec2 a_lod;\n"                                                         \
  "uniform mat4 u_model, u_view, u_proj;\n"                                                       \
  "uniform vec3 u_eye;\n"                                                                         \
  "uniform float u_scale;\n"                                                                      \
  "uniform float u_lod;  // LOD error per model unit of eye distance; 0 = off\n"                  \
  "uniform int u_base;  // first instance of the draw: gl_BaseInstance needs GL 4.6\n"            \
  "flat out vec3 v_albedo;\n"                                                                     \
  "flat out vec3 v_normal;\n"                                                                     \
  "flat out vec4 v_ao;\n"                                                                         \
  "flat out vec4 v_shadow;\n"                                                                     \
  "flat out uint v_id;\n"

// The head both splat vertex shaders share: world centre c, normal n and model rotation m, the
// flat outputs, and whether the splat is drawn (it faces the eye and, with LOD on, the eye distance
// puts its error in its interval: the digest's sequential point tree test).
#define SPLAT_HEAD                                                                                \
  "#version 450 core\n" SPLAT_INPUTS                                                              \
  "bool splat_head(out vec3 c, out vec3 n, out mat3 m) {\n"                                       \
  "  m = mat3(u_model);\n"                                                                        \
  "  c = (u_model * vec4(a_center, 1.0)).xyz;\n"                                                  \
  "  n = normalize(m * a_normal);\n"                                                              \
  "  v_albedo = a_albedo; v_normal = n; v_ao = a_ao; v_shadow = a_shadow;\n"                      \
  "  v_id = uint(gl_InstanceID + u_base);\n"                                                      \
  "  if (u_lod > 0.0) {\n"                                                                        \
  "    float e = length(u_eye - c) * u_lod;\n"                                                    \
  "    if (e < a_lod.x || e >= a_lod.y) return false;\n"                                         \
  "  }\n"                                                                                         \
  "  return dot(n, u_eye - c) > 0.0;\n"                                                           \
  "}\n"

const char* const kSplatVertex = SPLAT_HEAD R"(
out vec2 v_local;
out vec3 v_view_pos;
void main() {
  vec3 c, n;
  mat3 m;
  // Culled splats (back-facing, or outside their LOD interval) are moved outside the clip volume.
  if (!splat_head(c, n, m)) { gl_Position = vec4(0.0, 0.0, 2.0, 1.0); v_local = vec2(2.0); v_view_pos = vec3(0.0); return; }
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

const char* const kPointVertex = SPLAT_HEAD R"(
uniform float u_viewport_height;
out float v_view_z;
void main() {
  vec3 c, n;
  mat3 m;
  bool drawn = splat_head(c, n, m);
  vec4 view = u_view * vec4(c, 1.0);
  v_view_z = view.z;
  if (!drawn) { gl_Position = vec4(0.0, 0.0, 2.0, 1.0); gl_PointSize = 1.0; return; }
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

// Compiled once per variant: the presenter prepends "#version 450 core" and the defines DEBUG_VIEW
// (0 final, 1 albedo, 2 normals, 3 AO, 4 lights per cluster, 5 shadows, 6 depth), BRUTE_FORCE,
// PIXEL_SHADOWS, PIXEL_AO, USE_AO, KEY_COUNT and SPECULAR. On llvmpipe every branch on a uniform
// runs both sides under a mask, so the modes are constants and the dead paths are compiled out.
const char* const kShade = R"(
// center_inv_r2: view-space centre and 1/r² (the falloff needs (d/r)² only, so no root per light).
struct Light { vec4 center_inv_r2; vec4 color; };
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
uniform int u_light_count;
uniform vec4 u_key_center[4];  // view space, 1/r² in w
uniform vec3 u_key_color[4];
uniform vec3 u_sh[9];          // irradiance SH of the sky
uniform float u_heat_max;
uniform float u_specular;      // Blinn-Phong: white highlight strength (SPECULAR only)
uniform float u_shininess;     // Blinn-Phong exponent (SPECULAR only)
layout(location = 0) out vec4 o_hdr;
layout(location = 1) out vec4 o_display;

vec3 sh_irradiance(vec3 n) {  // Ramamoorthi & Hanrahan 2001, Eq. 13
  const float c1 = 0.429043, c2 = 0.511664, c3 = 0.743125, c4 = 0.886227, c5 = 0.247708;
  return c1 * u_sh[8] * (n.x * n.x - n.y * n.y) + c3 * u_sh[6] * n.z * n.z + c4 * u_sh[0] - c5 * u_sh[6]
       + 2.0 * c1 * (u_sh[4] * n.x * n.y + u_sh[7] * n.x * n.z + u_sh[5] * n.y * n.z)
       + 2.0 * c2 * (u_sh[3] * n.x + u_sh[1] * n.y + u_sh[2] * n.z);
}

vec3 heat(float t) {
  t = clamp(t, 0.0, 1.0);
  return clamp(vec3(1.5 * t - 0.25, 1.5 - abs(2.0 * t - 1.0) * 1.5, 1.25 - 1.5 * t), 0.0, 1.0);
}

// One light: c · f(d) · max(0, n·l) with the corrected falloff f(d) = clamp(1 − (d/r)², 0, 1), and
// with SPECULAR also c · f · max(0, n·l) · max(0, n·h)^s (Blinn-Phong, h the half vector).
// Branch-free: a light out of range has f = 0; d = 0 gives n·l = 0.
void add_light(vec4 center_inv_r2, vec3 color, vec3 position, vec3 n, vec3 to_eye, float visibility,
               inout vec3 diffuse, inout vec3 specular) {
  vec3 to_light = center_inv_r2.xyz - position;
  float d2 = dot(to_light, to_light);
  float inv_d = inversesqrt(max(d2, 1e-30));
  float f = clamp(1.0 - d2 * center_inv_r2.w, 0.0, 1.0) * visibility;
  float n_dot_l = max(0.0, dot(n, to_light) * inv_d);
  diffuse += color * (f * n_dot_l);
#if SPECULAR
  vec3 h = normalize(to_light * inv_d + to_eye);
  specular += color * (f * n_dot_l * pow(max(0.0, dot(n, h)), u_shininess));
#endif
}

vec4 shade(ivec2 p) {
  vec4 albedo = texelFetch(g_albedo, p, 0);
  if (albedo.w <= 0.0) return vec4(DEBUG_VIEW == 0 ? sh_irradiance(vec3(0.0, 0.3, 1.0)) / 3.14159265 * 0.6 : vec3(0.0), 1.0);
#if DEBUG_VIEW == 1
  return vec4(albedo.rgb, 1.0);
#elif DEBUG_VIEW == 2
  return vec4(0.5 * texelFetch(g_normal, p, 0).xyz + 0.5, 1.0);
#elif DEBUG_VIEW == 3
  return vec4(vec3(PIXEL_AO != 0 ? texelFetch(u_pixel_ao_texture, p, 0).w : texelFetch(g_ao, p, 0).w), 1.0);
#elif DEBUG_VIEW == 4
  uint list = texelFetch(u_pixel_list, p, 0).x;
  float count = BRUTE_FORCE != 0 ? float(u_light_count) : (list == 0xFFFFFFFFu ? 0.0 : float(list_counts[list]));
  return vec4(heat(count / u_heat_max), 1.0);
#elif DEBUG_VIEW == 5
  vec4 shadow = PIXEL_SHADOWS != 0 ? texelFetch(u_pixel_shadow, p, 0) : texelFetch(g_shadow, p, 0);
  float v = 1.0;  // the darkest key light's visibility
  for (int k = 0; k < KEY_COUNT; ++k) v = min(v, shadow[k]);
  return vec4(vec3(v), 1.0);
#elif DEBUG_VIEW == 6
  return vec4(vec3(-texelFetch(g_view_z, p, 0).x / 20.0), 1.0);
#else
  vec3 n_world = texelFetch(g_normal, p, 0).xyz;
  // Same reconstruction as cluster::pixel_view_position.
  float d = -texelFetch(g_view_z, p, 0).x;
  vec2 ndc = (vec2(p) + 0.5) * 2.0 / u_viewport - 1.0;
  vec3 position = vec3(ndc * d * u_tan_half, -d);
  vec3 n = normalize(mat3(u_view) * n_world);
  vec3 to_eye = normalize(-position);
  vec3 diffuse = vec3(0.0), specular = vec3(0.0);
#if BRUTE_FORCE
  for (int i = 0; i < u_light_count; ++i)
    add_light(lights[i].center_inv_r2, lights[i].color.rgb, position, n, to_eye, 1.0, diffuse, specular);
#else
  uint list = texelFetch(u_pixel_list, p, 0).x;
  if (list != 0xFFFFFFFFu) {
    uint begin = list_offsets[list], end = begin + list_counts[list];
    for (uint k = begin; k < end; ++k) {
      uint i = list_indices[k];
      add_light(lights[i].center_inv_r2, lights[i].color.rgb, position, n, to_eye, 1.0, diffuse, specular);
    }
  }
#endif
#if KEY_COUNT > 0
  vec4 shadow = PIXEL_SHADOWS != 0 ? texelFetch(u_pixel_shadow, p, 0) : texelFetch(g_shadow, p, 0);
  for (int k = 0; k < KEY_COUNT; ++k)
    add_light(u_key_center[k], u_key_color[k], position, n, to_eye, shadow[k], diffuse, specular);
#endif
  // Ambient: sky irradiance in the bent normal's direction, times AO (albedo/π · E).
#if USE_AO
  vec4 ao = PIXEL_AO != 0 ? texelFetch(u_pixel_ao_texture, p, 0) : texelFetch(g_ao, p, 0);
  vec3 ambient = max(sh_irradiance(ao.xyz), vec3(0.0)) / 3.14159265 * ao.w;
#else
  vec3 ambient = max(sh_irradiance(n_world), vec3(0.0)) / 3.14159265;
#endif
  return vec4(albedo.rgb * (diffuse + ambient) + u_specular * specular, 1.0);
#endif
}

void main() {
  vec4 color = shade(ivec2(gl_FragCoord.xy));
  o_hdr = color;
  vec3 c = DEBUG_VIEW == 0 ? vec3(1.0) - exp(-color.rgb) : color.rgb;  // exposure curve keeps many lights in range
  o_display = vec4(pow(clamp(c, 0.0, 1.0), vec3(1.0 / 2.2)), 1.0);
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
