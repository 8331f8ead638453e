#include "present/shaders.hpp"

#include <string>

namespace splatcl::present::shaders {
namespace {

// Irradiance from the sky's 9 SH coefficients (Ramamoorthi & Hanrahan 2001, Eq. 13), for the
// per-splat ambient term and the per-pixel one of the pixel-AO mode.
const char* const kShIrradiance = R"(
uniform vec3 u_sh[9];  // irradiance SH of the sky
vec3 sh_irradiance(vec3 n) {
  const float c1 = 0.429043, c2 = 0.511664, c3 = 0.743125, c4 = 0.886227, c5 = 0.247708;
  return c1 * u_sh[8] * (n.x * n.x - n.y * n.y) + c3 * u_sh[6] * n.z * n.z + c4 * u_sh[0] - c5 * u_sh[6]
       + 2.0 * c1 * (u_sh[4] * n.x * n.y + u_sh[7] * n.x * n.z + u_sh[5] * n.y * n.z)
       + 2.0 * c2 * (u_sh[3] * n.x + u_sh[1] * n.y + u_sh[2] * n.z);
}
)";

// The head both splat vertex shaders share. Per-splat attributes are pulled from storage buffers
// by splat index (gl_VertexID: 3 per splat, 1 for points): llvmpipe runs an instanced draw as one
// small vertex batch per instance, a plain draw shades its vertices 8 at a time.
// Static rows (17 floats, model space): centre, normal, the two semi-axis vectors, colour, the LOD
// interval [e_min, e_max) (model units). Lighting rows (2 vec4, world space): the per-splat CL
// results, bent normal + AO and key-light visibility.
// splat_head gives the world centre c, normal n and model rotation m, sets the flat outputs, and
// tells whether the splat is drawn (it faces the eye and, with LOD on, the eye distance puts its
// error in its interval: the point-rendering thesis's sequential point tree test, §5.3.1). The ambient term is evaluated
// per splat, where the AO is known: irradiance of the sky around the bent normal times AO
// (u_ambient 0), around the normal without AO (1), or the AO itself as grey (2, the AO view).
const std::string kSplatHead = std::string(kShIrradiance) + R"(
layout(std430, binding = 4) readonly buffer SplatStatics { float splat_statics[]; };
layout(std430, binding = 5) readonly buffer SplatLighting { vec4 splat_lighting[]; };
uniform mat4 u_model, u_view, u_proj;
uniform vec3 u_eye;
uniform float u_scale;
uniform float u_lod;  // LOD error per model unit of eye distance; 0 = off
uniform int u_ambient;
flat out vec3 v_albedo;
flat out vec3 v_normal;
flat out vec3 v_ambient;
flat out vec4 v_shadow;
flat out uint v_id;
vec3 a_major, a_minor;
vec3 static3(uint o) { return vec3(splat_statics[o], splat_statics[o + 1u], splat_statics[o + 2u]); }
bool splat_head(uint s, out vec3 c, out vec3 n, out mat3 m) {
  uint o = 17u * s;
  m = mat3(u_model);
  c = (u_model * vec4(static3(o), 1.0)).xyz;
  n = normalize(m * static3(o + 3u));
  a_major = static3(o + 6u);
  a_minor = static3(o + 9u);
  v_albedo = static3(o + 12u);
  v_normal = n;
#ifdef VISIBILITY_PASS
  // The visibility pass reads no lighting rows: they may still be in the making (Presenter::render).
  v_ambient = vec3(0.0);
  v_shadow = vec4(1.0);
#else
  vec4 ao = splat_lighting[2u * s];
  vec3 bent = length(ao.xyz) > 0.0 ? normalize(ao.xyz) : n;
  v_ambient = u_ambient == 2 ? vec3(ao.w)
            : u_ambient == 1 ? max(sh_irradiance(n), vec3(0.0)) / 3.14159265
                             : max(sh_irradiance(bent), vec3(0.0)) / 3.14159265 * ao.w;
  v_shadow = splat_lighting[2u * s + 1u];
#endif
  v_id = s;
  if (u_lod > 0.0) {
    float e = length(u_eye - c) * u_lod;
    if (e < splat_statics[o + 15u] || e >= splat_statics[o + 16u]) return false;
  }
  return dot(n, u_eye - c) > 0.0;
}
)";

const char* const kSplatVertexMain = R"(
out vec2 v_local;
out vec3 v_view_pos;
uniform float u_depth_offset;  // ε of the visibility pass, 0 in the accumulation pass
void main() {
  vec3 c, n;
  mat3 m;
  // Culled splats (back-facing, or outside their LOD interval) are moved outside the clip volume.
  // The splat passes cost per primitive on llvmpipe more than per pixel: one triangle circumscribing
  // the ellipse (inradius 1 in ellipse coordinates) is cheaper than a quad of two.
  if (!splat_head(uint(gl_VertexID) / 3u, c, n, m)) { gl_Position = vec4(0.0, 0.0, 2.0, 1.0); v_local = vec2(2.0); v_view_pos = vec3(0.0); return; }
  int j = gl_VertexID % 3;
  vec2 corner = j == 0 ? vec2(0.0, 2.0) : vec2(j == 1 ? -1.7320508 : 1.7320508, -1.0);
  // The triangle lies in the splat's plane, so the rasterised depth is the ray-cast depth of that plane
  // at every pixel (perspective correct), and v_local is the pixel's ellipse coordinate.
  vec3 p = c + u_scale * (corner.x * (m * a_major) + corner.y * (m * a_minor));
  v_local = corner;
  v_view_pos = (u_view * vec4(p, 1.0)).xyz;
  // The visibility pass pushes each corner back by ε along its view ray. Done per vertex rather than
  // per pixel, the fragment shader writes no depth and llvmpipe keeps its early depth test; across
  // a splat the offset differs from ε by a second-order amount in the splat's angular size.
  gl_Position = u_proj * vec4(v_view_pos * (1.0 + u_depth_offset / length(v_view_pos)), 1.0);
}
)";
}  // namespace

const std::string kSplatVertex = std::string("#version 450 core\n") + kSplatHead + kSplatVertexMain;
const std::string kSplatVisibilityVertex =
    std::string("#version 450 core\n#define VISIBILITY_PASS 1\n") + kSplatHead + kSplatVertexMain;

const char* const kSplatVisibility = R"(#version 450 core
in vec2 v_local;
void main() {
  if (dot(v_local, v_local) > 1.0) discard;
}
)";

namespace {
// The accumulation targets, also the G-buffer the shading reads (it divides by Σw itself, so no
// normalisation pass writes a second set of full-screen targets). Σw and Σw·z lead their targets,
// so the cluster stage reads them back as single channels.
const char* const kAccumulationTargets = R"(
layout(location = 0) out vec4 o_weight_albedo;   // Σw, Σw·albedo
layout(location = 1) out vec4 o_z_normal;        // Σw·z_view, Σw·n (world)
layout(location = 2) out vec4 o_shadow_ambient;  // Σw·visibility of key light 0, Σw·ambient
layout(location = 3) out vec4 o_shadows;         // Σw·visibility of key lights 1-3 (bound with 2+ key lights)
vec3 hash_color(uint id) {
  uint h = id * 2654435761u; h ^= h >> 15; h *= 2246822519u; h ^= h >> 13;
  return vec3(float(h & 255u), float((h >> 8) & 255u), float((h >> 16) & 255u)) / 255.0;
}
void write_splat(float w, float view_z) {
  o_weight_albedo = vec4(w, w * (u_footprints != 0 ? hash_color(v_id) : v_albedo));
  o_z_normal = vec4(w * view_z, w * v_normal);
  o_shadow_ambient = vec4(w * v_shadow.x, w * v_ambient);
  o_shadows = vec4(w * v_shadow.yzw, 0.0);
}
)";

const char* const kSplatFlatInputs = R"(
flat in vec3 v_albedo;
flat in vec3 v_normal;
flat in vec3 v_ambient;
flat in vec4 v_shadow;
flat in uint v_id;
uniform int u_footprints;
)";

}  // namespace

const std::string kSplatAccumulate = std::string("#version 450 core\n") + kSplatFlatInputs + kAccumulationTargets + R"(
in vec2 v_local;
in vec3 v_view_pos;
uniform float u_beta;
void main() {
  float r2 = dot(v_local, v_local);
  if (r2 > 1.0) discard;
  write_splat(exp(-u_beta * r2), v_view_pos.z);
}
)";

const std::string kPointVertex = std::string("#version 450 core\n") + kSplatHead + R"(
uniform float u_viewport_height;
out float v_view_z;
void main() {
  vec3 c, n;
  mat3 m;
  bool drawn = splat_head(uint(gl_VertexID), c, n, m);
  vec4 view = u_view * vec4(c, 1.0);
  v_view_z = view.z;
  if (!drawn) { gl_Position = vec4(0.0, 0.0, 2.0, 1.0); gl_PointSize = 1.0; return; }
  gl_Position = u_proj * view;
  // Projected diameter of the splat's major axis (the point-rendering thesis: r·n/z·h/(t−b), ×2 for the diameter).
  float radius = u_scale * length(m * a_major);
  gl_PointSize = max(1.0, 2.0 * radius * u_proj[1][1] * 0.5 * u_viewport_height / max(-view.z, 1e-3));
}
)";

// The nearest point's attributes with weight 1, into the accumulation targets.
const std::string kPointFragment = std::string("#version 450 core\n") + kSplatFlatInputs + kAccumulationTargets + R"(
in float v_view_z;
void main() { write_splat(1.0, v_view_z); }
)";

const char* const kFullscreenVertex = R"(#version 450 core
void main() {
  vec2 p = vec2((gl_VertexID == 1) ? 3.0 : -1.0, (gl_VertexID == 2) ? 3.0 : -1.0);
  gl_Position = vec4(p, 0.0, 1.0);
}
)";

// Compiled once per variant: the presenter prepends "#version 450 core" and the defines DEBUG_VIEW
// (0 final, 1 albedo, 2 normals, 3 AO, 4 lights per cluster, 5 shadows, 6 depth), BRUTE_FORCE,
// PIXEL_SHADOWS, PIXEL_AO, KEY_COUNT, SPECULAR and HDR_OUTPUT. On llvmpipe every branch on a uniform
// runs both sides under a mask, so the modes are constants and the dead paths are compiled out.
// The G-buffer is the accumulation targets: every attribute is a Σw-weighted sum divided here.
const std::string kShade = std::string(kShIrradiance) + R"(
// center_inv_r2: view-space centre and 1/r² (the falloff needs (d/r)² only, so no root per light).
struct Light { vec4 center_inv_r2; vec4 color; };
layout(std430, binding = 0) readonly buffer Lights { Light lights[]; };
layout(std430, binding = 1) readonly buffer Offsets { uint list_offsets[]; };
layout(std430, binding = 2) readonly buffer Counts { uint list_counts[]; };
layout(std430, binding = 3) readonly buffer Indices { uint list_indices[]; };
layout(binding = 0) uniform sampler2D g_weight_albedo;
layout(binding = 1) uniform sampler2D g_z_normal;
layout(binding = 2) uniform sampler2D g_shadow_ambient;
layout(binding = 3) uniform sampler2D g_shadows;
layout(binding = 5) uniform usampler2D u_pixel_list;
layout(binding = 6) uniform sampler2D u_pixel_shadow;
layout(binding = 7) uniform sampler2D u_pixel_ao_texture;
uniform mat4 u_view;
uniform vec2 u_tan_half;       // tan of half the field of view, x and y
uniform vec2 u_viewport;
uniform int u_light_count;
uniform vec4 u_key_center[4];  // view space, 1/r² in w
uniform vec3 u_key_color[4];
uniform float u_heat_max;
uniform float u_specular;      // Blinn-Phong: white highlight strength (SPECULAR only)
uniform float u_shininess;     // Blinn-Phong exponent (SPECULAR only)
#if HDR_OUTPUT
layout(location = 0) out vec4 o_hdr;
layout(location = 1) out vec4 o_display;
#else
layout(location = 0) out vec4 o_display;
#endif

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

// Key-light visibility per key light, from the splats or per pixel.
vec4 key_visibility(ivec2 p, float inv_weight) {
#if PIXEL_SHADOWS
  return texelFetch(u_pixel_shadow, p, 0);
#elif KEY_COUNT > 1
  return vec4(texelFetch(g_shadow_ambient, p, 0).x, texelFetch(g_shadows, p, 0).xyz) * inv_weight;
#else
  return vec4(texelFetch(g_shadow_ambient, p, 0).x * inv_weight, 1.0, 1.0, 1.0);
#endif
}

vec4 shade(ivec2 p) {
  vec4 weight_albedo = texelFetch(g_weight_albedo, p, 0);
  if (weight_albedo.x <= 0.0) return vec4(DEBUG_VIEW == 0 ? sh_irradiance(vec3(0.0, 0.3, 1.0)) / 3.14159265 * 0.6 : vec3(0.0), 1.0);
  float inv_weight = 1.0 / weight_albedo.x;
  vec3 albedo = weight_albedo.yzw * inv_weight;
  vec4 z_normal = texelFetch(g_z_normal, p, 0);
  vec3 n_world = normalize(z_normal.yzw);
#if DEBUG_VIEW == 1
  return vec4(albedo, 1.0);
#elif DEBUG_VIEW == 2
  return vec4(0.5 * n_world + 0.5, 1.0);
#elif DEBUG_VIEW == 3
  // The splat passes carry the AO itself in the ambient channels for this view.
  return vec4(vec3(PIXEL_AO != 0 ? texelFetch(u_pixel_ao_texture, p, 0).w : texelFetch(g_shadow_ambient, p, 0).y * inv_weight), 1.0);
#elif DEBUG_VIEW == 4
  uint list = texelFetch(u_pixel_list, p, 0).x;
  float count = BRUTE_FORCE != 0 ? float(u_light_count) : (list == 0xFFFFFFFFu ? 0.0 : float(list_counts[list]));
  return vec4(heat(count / u_heat_max), 1.0);
#elif DEBUG_VIEW == 5
  vec4 shadow = key_visibility(p, inv_weight);
  float v = 1.0;  // the darkest key light's visibility
  for (int k = 0; k < KEY_COUNT; ++k) v = min(v, shadow[k]);
  return vec4(vec3(v), 1.0);
#elif DEBUG_VIEW == 6
  return vec4(vec3(-z_normal.x * inv_weight / 20.0), 1.0);
#else
  // Same reconstruction as cluster::pixel_view_position, from the same Σw·z / Σw as the cluster stage.
  float d = -(z_normal.x / weight_albedo.x);
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
  vec4 shadow = key_visibility(p, inv_weight);
  for (int k = 0; k < KEY_COUNT; ++k)
    add_light(u_key_center[k], u_key_color[k], position, n, to_eye, shadow[k], diffuse, specular);
#endif
  // Ambient: sky irradiance around the bent normal times AO (albedo/π · E), evaluated per splat by
  // the splat passes, or per pixel in the pixel-AO mode.
#if PIXEL_AO
  vec4 ao = texelFetch(u_pixel_ao_texture, p, 0);
  vec3 ambient = max(sh_irradiance(ao.xyz), vec3(0.0)) / 3.14159265 * ao.w;
#else
  vec3 ambient = texelFetch(g_shadow_ambient, p, 0).yzw * inv_weight;
#endif
  return vec4(albedo * (diffuse + ambient) + u_specular * specular, 1.0);
#endif
}

void main() {
  vec4 color = shade(ivec2(gl_FragCoord.xy));
#if HDR_OUTPUT
  o_hdr = color;
#endif
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
