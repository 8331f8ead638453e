// The head both splat vertex shaders share. Per-splat attributes are pulled from buffer textures
// by splat index (gl_VertexID: 3 per splat, 1 for points): llvmpipe runs an instanced draw as one
// small vertex batch per instance, a plain draw shades its vertices 8 at a time, and it gathers a
// texel fetch across those 8 where it loads from a storage buffer one vertex at a time.
// Static rows (SPLAT_ROW_TEXELS texels, model space) and lighting rows (LIGHTING_ROW_VEC4S texels,
// world space) as layout.h lays them out.
// splat_head gives the world centre c, normal n and model rotation m, sets the flat outputs, and
// tells whether the splat is drawn (its plane faces the eye and, with LOD on, the eye distance puts its
// error in its interval: the point-rendering thesis's sequential point tree test, §5.3.1). The
// ambient term is evaluated per splat, where the AO is known: irradiance of the sky around the bent
// normal times AO (u_ambient 0), around the normal without AO (1), or the AO itself as grey (2,
// the AO view).
#include "layout.h"
#include "sh_irradiance.glsl"
layout(binding = UNIT_SPLAT_ROWS) uniform samplerBuffer u_splat_rows;
layout(binding = UNIT_SPLAT_LIGHTING) uniform samplerBuffer u_splat_lighting;
uniform mat4 u_model, u_view, u_proj;
uniform vec3 u_eye;
uniform float u_scale;
uniform float u_lod;  // LOD error per model unit of eye distance; 0 = off
// A two-sided object's offset from each splat to its mirrored copy (SplatDraw::mirror), 0 = none:
// where the splat faces away, its copy, which faces the eye, is drawn in its place.
uniform uint u_mirror;
// Whether splat_head took the mirrored copy.
bool a_back_copy = false;
uniform int u_ambient;
flat out vec3 v_albedo;
flat out vec3 v_normal;
flat out vec3 v_ambient;
flat out vec4 v_shadow;
flat out uint v_id;
vec3 a_major, a_minor, a_clip, a_clip2;
// The splat's static row; the field offsets are constants, so row_float and static3 pick lanes of
// the fetched texels.
vec4 a_row[SPLAT_ROW_TEXELS];
float row_float(uint i) { return a_row[i / 4u][i % 4u]; }
vec3 static3(uint i) { return vec3(row_float(i), row_float(i + 1u), row_float(i + 2u)); }
void fetch_row(uint s) {
  for (int t = 0; t < SPLAT_ROW_TEXELS; ++t) a_row[t] = texelFetch(u_splat_rows, SPLAT_ROW_TEXELS * int(s) + t);
}
// Faces the eye by its plane (major × minor on the normal's side), not by its shading normal: the
// Phong splat's normal field leaves the row's normal a little off the plane, and which splats are
// drawn is the geometry's business (a splat file's flat splats and the mesh's give the same depth).
bool faces_eye(mat3 m, vec3 c) {
  vec3 plane = cross(static3(SPLAT_MAJOR), static3(SPLAT_MINOR));
  return dot(m * (dot(plane, static3(SPLAT_NORMAL)) < 0.0 ? -plane : plane), u_eye - c) > 0.0;
}
bool splat_head(uint s, out vec3 c, out vec3 n, out mat3 m) {
  fetch_row(s);
  m = mat3(u_model);
  c = (u_model * vec4(static3(SPLAT_CENTER), 1.0)).xyz;
  if (u_mirror != 0u && !faces_eye(m, c)) {  // the copy lies where the splat does
    s += u_mirror;
    fetch_row(s);
    a_back_copy = true;
  }
  n = normalize(m * static3(SPLAT_NORMAL));
  a_major = static3(SPLAT_MAJOR);
  a_minor = static3(SPLAT_MINOR);
  a_clip = static3(SPLAT_CLIP);
  a_clip2 = static3(SPLAT_CLIP2);
  v_albedo = static3(SPLAT_ALBEDO);
  v_normal = n;
#ifdef VISIBILITY_PASS
  // The visibility pass reads no lighting rows: they may still be in the making (Presenter::render).
  v_ambient = vec3(0.0);
  v_shadow = vec4(1.0);
#else
  vec4 ao = texelFetch(u_splat_lighting, int(LIGHTING_ROW_VEC4S * s + LIGHTING_AO));
  vec3 bent = length(ao.xyz) > 0.0 ? normalize(ao.xyz) : n;
  v_ambient = u_ambient == 2 ? vec3(ao.w)
            : u_ambient == 1 ? max(sh_irradiance(n), vec3(0.0)) / 3.14159265
                             : max(sh_irradiance(bent), vec3(0.0)) / 3.14159265 * ao.w;
  v_shadow = texelFetch(u_splat_lighting, int(LIGHTING_ROW_VEC4S * s + LIGHTING_SHADOW));
#endif
  v_id = s;
  if (u_lod > 0.0) {
    float e = length(u_eye - c) * u_lod;
    if (e < row_float(SPLAT_LOD_MIN) || e >= row_float(SPLAT_LOD_MAX)) return false;
  }
  return faces_eye(m, c);
}
