// Final shading and debug views: HDR and tone-mapped 8-bit. Compiled once per variant: the
// presenter puts the defines DEBUG_VIEW (0 final, 1 albedo, 2 normals, 3 AO, 4 lights per cluster,
// 5 shadows, 6 depth), BRUTE_FORCE, PIXEL_SHADOWS, PIXEL_AO, FLOOR_AO, FLOOR_SHADOWS, KEY_COUNT,
// SPECULAR and HDR_OUTPUT after the version line. On llvmpipe every branch on a uniform runs both sides under a mask, so
// the modes are constants and the dead paths are compiled out. The G-buffer is the accumulation
// targets: every attribute is a Σw-weighted sum divided here.
#include "layout.h"
#include "sh_irradiance.glsl"
// Light i is texels 2i (view-space centre and 1/r²: the falloff needs (d/r)² only, so no root per
// light) and 2i + 1 (colour) of u_light_rows.
layout(binding = UNIT_LIGHT_ROWS) uniform samplerBuffer u_light_rows;
layout(binding = UNIT_LIST_INDICES) uniform usamplerBuffer u_list_indices;
layout(binding = UNIT_LIST_OFFSETS) uniform usamplerBuffer u_list_offsets;
layout(binding = UNIT_LIST_COUNTS) uniform usamplerBuffer u_list_counts;
layout(binding = UNIT_WEIGHT_ALBEDO) uniform sampler2D g_weight_albedo;
layout(binding = UNIT_Z_NORMAL) uniform sampler2D g_z_normal;
layout(binding = UNIT_SHADOW_AMBIENT) uniform sampler2D g_shadow_ambient;
layout(binding = UNIT_SHADOWS) uniform sampler2D g_shadows;
layout(binding = UNIT_PIXEL_LIST) uniform usampler2D u_pixel_list;
layout(binding = UNIT_PIXEL_SHADOW) uniform sampler2D u_pixel_shadow;
layout(binding = UNIT_PIXEL_AO) uniform sampler2D u_pixel_ao_texture;
layout(binding = UNIT_FLOOR_AO) uniform sampler2D u_floor_ao;
layout(binding = UNIT_FLOOR_SHADOW) uniform sampler2D u_floor_shadow;
uniform vec4 u_floor_plane;      // view space: dot(xyz, p) + w = height above the floor
uniform float u_floor_tolerance;
uniform mat4 u_view;
uniform vec2 u_tan_half;       // tan of half the field of view, x and y
uniform vec2 u_viewport;
uniform int u_light_count;
uniform vec4 u_key_center[MAX_KEY_LIGHTS];  // view space, 1/r² in w
uniform vec3 u_key_color[MAX_KEY_LIGHTS];
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

// A pixel on the floor: on its plane to the tolerance and facing up (objects and the floor blended
// at a contact keep the splats' values).
bool on_floor(vec3 position, vec3 n_world) {
  return abs(dot(u_floor_plane.xyz, position) + u_floor_plane.w) <= u_floor_tolerance && n_world.y > 0.999;
}

// The floor's lattice at pixel p: the bilinear filter between the four nodes around it (the host
// gave a node that does not show floor its floor neighbours' mean, and a large negative value
// where it has none: a negative result means no floor node is near, and the pixel, a sliver of
// floor between objects, keeps the splats' values).
vec2 floor_lattice_point(ivec2 p) {
  return (vec2(p) / float(FLOOR_LATTICE_STEP) + 0.5) / vec2(textureSize(u_floor_ao, 0));
}

// The floor's AO and bent normal (renormalised) at the lattice point uv, or false.
bool floor_ao(vec2 uv, bool is_floor, out vec4 ao) {
  ao = vec4(0.0);
#if FLOOR_AO
  if (is_floor) {
    ao = texture(u_floor_ao, uv);
    if (ao.w < 0.0) return false;
    if (dot(ao.xyz, ao.xyz) > 0.0) ao.xyz = normalize(ao.xyz);
    return true;
  }
#endif
  return false;
}

// Key-light visibility per key light, from the splats, per pixel or from the floor's lattice.
vec4 key_visibility(ivec2 p, float inv_weight, vec2 lattice_uv, bool is_floor) {
#if FLOOR_SHADOWS
  if (is_floor) {
    vec4 lattice = texture(u_floor_shadow, lattice_uv);
    if (lattice.x >= 0.0) return lattice;
  }
#endif
#if PIXEL_SHADOWS
  // Negative where not computed: the splats' value.
  vec4 pixel_shadow = texelFetch(u_pixel_shadow, p, 0);
  if (pixel_shadow.x >= 0.0) return pixel_shadow;
#endif
#if KEY_COUNT > 1
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
  // Same reconstruction as cluster::pixel_view_position, from the same Σw·z / Σw as the cluster stage.
  float d = -(z_normal.x / weight_albedo.x);
  vec2 ndc = (vec2(p) + 0.5) * 2.0 / u_viewport - 1.0;
  vec3 position = vec3(ndc * d * u_tan_half, -d);
  bool is_floor = (FLOOR_AO != 0 || FLOOR_SHADOWS != 0) && on_floor(position, n_world);
  vec2 lattice_uv = floor_lattice_point(p);
#if DEBUG_VIEW == 1
  return vec4(albedo, 1.0);
#elif DEBUG_VIEW == 2
  return vec4(0.5 * n_world + 0.5, 1.0);
#elif DEBUG_VIEW == 3
  // The splat passes carry the AO itself in the ambient channels for this view; per-pixel AO where
  // computed (w ≥ 0), or the floor's lattice.
  vec4 lattice_ao;
  if (floor_ao(lattice_uv, is_floor, lattice_ao)) return vec4(vec3(lattice_ao.w), 1.0);
#if PIXEL_AO
  float pixel_ao = texelFetch(u_pixel_ao_texture, p, 0).w;
  if (pixel_ao >= 0.0) return vec4(vec3(pixel_ao), 1.0);
#endif
  return vec4(vec3(texelFetch(g_shadow_ambient, p, 0).y * inv_weight), 1.0);
#elif DEBUG_VIEW == 4
  uint list = texelFetch(u_pixel_list, p, 0).x;
  float count = BRUTE_FORCE != 0 ? float(u_light_count) : (list == NO_LIGHT_LIST ? 0.0 : float(texelFetch(u_list_counts, int(list)).x));
  return vec4(heat(count / u_heat_max), 1.0);
#elif DEBUG_VIEW == 5
  vec4 shadow = key_visibility(p, inv_weight, lattice_uv, is_floor);
  float v = 1.0;  // the darkest key light's visibility
  for (int k = 0; k < KEY_COUNT; ++k) v = min(v, shadow[k]);
  return vec4(vec3(v), 1.0);
#elif DEBUG_VIEW == 6
  return vec4(vec3(-z_normal.x * inv_weight / 20.0), 1.0);
#else
  vec3 n = normalize(mat3(u_view) * n_world);
  vec3 to_eye = normalize(-position);
  vec3 diffuse = vec3(0.0), specular = vec3(0.0);
#if BRUTE_FORCE
  for (int i = 0; i < u_light_count; ++i)
    add_light(texelFetch(u_light_rows, 2 * i), texelFetch(u_light_rows, 2 * i + 1).rgb, position, n, to_eye, 1.0,
              diffuse, specular);
#else
  uint list = texelFetch(u_pixel_list, p, 0).x;
  if (list != NO_LIGHT_LIST) {
    int begin = int(texelFetch(u_list_offsets, int(list)).x);
    int end = begin + int(texelFetch(u_list_counts, int(list)).x);
    for (int k = begin; k < end; ++k) {
      int i = int(texelFetch(u_list_indices, k).x);
      add_light(texelFetch(u_light_rows, 2 * i), texelFetch(u_light_rows, 2 * i + 1).rgb, position, n, to_eye, 1.0,
                diffuse, specular);
    }
  }
#endif
#if KEY_COUNT > 0
  vec4 shadow = key_visibility(p, inv_weight, lattice_uv, is_floor);
  for (int k = 0; k < KEY_COUNT; ++k)
    add_light(u_key_center[k], u_key_color[k], position, n, to_eye, shadow[k], diffuse, specular);
#endif
  // Ambient: sky irradiance around the bent normal times AO (albedo/π · E), evaluated per splat by
  // the splat passes, or on the floor from its lattice, or per pixel where that was computed (w ≥ 0:
  // the pixel-AO mode).
  // The lattice first, as in the AO view.
  vec3 ambient = texelFetch(g_shadow_ambient, p, 0).yzw * inv_weight;
  vec4 lattice_ao;
  if (floor_ao(lattice_uv, is_floor, lattice_ao)) {
    ambient = max(sh_irradiance(lattice_ao.xyz), vec3(0.0)) / 3.14159265 * lattice_ao.w;
  } else {
#if PIXEL_AO
    vec4 ao = texelFetch(u_pixel_ao_texture, p, 0);
    if (ao.w >= 0.0) ambient = max(sh_irradiance(ao.xyz), vec3(0.0)) / 3.14159265 * ao.w;
#endif
  }
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
