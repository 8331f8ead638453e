/* The layouts the presenter's host code and its shaders share: included by the presenter's C++ as
   a header and by the GLSL sources beside this file (whose #include lines the presenter resolves),
   so a row's size or a field's offset is written once. Only preprocessor lines and comments
   outside the __cplusplus block, which GLSL reads too. */
#ifndef SPLATCL_PRESENT_SHADER_LAYOUT_H
#define SPLATCL_PRESENT_SHADER_LAYOUT_H

/* Static splat row (floats, model space): centre, normal, the major and minor semi-axis vectors,
   linear albedo, the LOD interval [e_min, e_max) in model units, two clip lines (unit direction in
   the (major, minor) frame and the line's distance from the centre along it; FLT_MAX: none; the
   second one only where one line cannot keep the splat on the surface: a convex corner, a narrow
   face), and the Phong splat's normal field (splats::NormalField): the shading normal at
   centre + x·major + y·minor is normal + x·normal_du + y·normal_dv (zero: flat). */
#define SPLAT_CENTER 0u
#define SPLAT_NORMAL 3u
#define SPLAT_MAJOR 6u
#define SPLAT_MINOR 9u
#define SPLAT_ALBEDO 12u
#define SPLAT_LOD_MIN 15u
#define SPLAT_LOD_MAX 16u
#define SPLAT_CLIP 17u
#define SPLAT_CLIP2 20u
#define SPLAT_NORMAL_DU 23u
#define SPLAT_NORMAL_DV 26u
#define SPLAT_ROW_FLOATS 32u  /* 29 used, padded to whole RGBA32F texels */
#define SPLAT_ROW_TEXELS 8

/* Lighting row (world space), the per-splat CL results: vec4 bent normal xyz + AO, then vec4
   visibility of key lights 0-3. */
#define LIGHTING_AO 0u
#define LIGHTING_SHADOW 1u
#define LIGHTING_ROW_VEC4S 2u
#define MAX_KEY_LIGHTS 4

/* Point light row: vec4 view-space centre + 1/r², vec4 colour (w unused). */
#define LIGHT_ROW_VEC4S 2u

/* A pixel's light-list index where no list covers it (cluster::kNoCluster). */
#define NO_LIGHT_LIST 0xFFFFFFFFu

/* Storage buffer binding points. */
#define BINDING_RESOLVE_TILES 6  /* the silhouette resolve's screen rectangles */

/* Texture units of the shading pass: the G-buffer's four targets, then the per-pixel inputs. */
#define UNIT_WEIGHT_ALBEDO 0
#define UNIT_Z_NORMAL 1
#define UNIT_SHADOW_AMBIENT 2
#define UNIT_SHADOWS 3
#define UNIT_DISPLAY 4  /* the silhouette resolve's input: the tone-mapped image */
#define UNIT_PIXEL_LIST 5
#define UNIT_PIXEL_SHADOW 6
#define UNIT_PIXEL_AO 7
#define UNIT_FLOOR_AO 8      /* the floor's lattice: bent normal, AO (bilinear) */
#define UNIT_FLOOR_SHADOW 9  /* the floor's lattice: key-light visibility 0-3 (bilinear) */
#define UNIT_LIGHT_ROWS 10    /* the point lights' rows (samplerBuffer, RGBA32F, two texels per light) */
#define UNIT_LIST_OFFSETS 11  /* the light lists (usamplerBuffer, R32UI): first index of list l */
#define UNIT_LIST_COUNTS 12   /* number of lights in list l */
#define UNIT_LIST_INDICES 13  /* the lights' indices */
#define SHADING_UNITS 14
/* Texture units of the splat passes' vertex shaders (buffer textures, RGBA32F), past the shading's. */
#define UNIT_SPLAT_ROWS 14     /* the static rows, SPLAT_ROW_TEXELS texels per splat */
#define UNIT_SPLAT_LIGHTING 15 /* the lighting rows, LIGHTING_ROW_VEC4S texels per splat */

/* The floor's lighting lattice: a node every FLOOR_LATTICE_STEP pixels in x and y (node (i, j) is
   pixel (i, j) * FLOOR_LATTICE_STEP), interpolated to the floor's pixels by the shading. */
#define FLOOR_LATTICE_STEP 4

#ifdef __cplusplus
#include <cstddef>

namespace splatcl::present::layout {

struct SplatRow {
  float center[3], normal[3], major[3], minor[3], albedo[3], lod[2], clip[3], clip2[3], normal_du[3], normal_dv[3];
  float padding[3];
};
static_assert(sizeof(SplatRow) == SPLAT_ROW_FLOATS * sizeof(float));
static_assert(SPLAT_ROW_FLOATS == 4 * SPLAT_ROW_TEXELS);
static_assert(offsetof(SplatRow, center) == SPLAT_CENTER * sizeof(float));
static_assert(offsetof(SplatRow, normal) == SPLAT_NORMAL * sizeof(float));
static_assert(offsetof(SplatRow, major) == SPLAT_MAJOR * sizeof(float));
static_assert(offsetof(SplatRow, minor) == SPLAT_MINOR * sizeof(float));
static_assert(offsetof(SplatRow, albedo) == SPLAT_ALBEDO * sizeof(float));
static_assert(offsetof(SplatRow, lod) == SPLAT_LOD_MIN * sizeof(float));
static_assert(SPLAT_LOD_MAX == SPLAT_LOD_MIN + 1u);
static_assert(offsetof(SplatRow, clip) == SPLAT_CLIP * sizeof(float));
static_assert(offsetof(SplatRow, clip2) == SPLAT_CLIP2 * sizeof(float));
static_assert(offsetof(SplatRow, normal_du) == SPLAT_NORMAL_DU * sizeof(float));
static_assert(offsetof(SplatRow, normal_dv) == SPLAT_NORMAL_DV * sizeof(float));

struct LightingRow {
  float bent_ao[4];     // bent normal xyz, AO
  float visibility[MAX_KEY_LIGHTS];  // key lights 0-3
};
static_assert(sizeof(LightingRow) == LIGHTING_ROW_VEC4S * 4 * sizeof(float));
static_assert(offsetof(LightingRow, bent_ao) == LIGHTING_AO * 4 * sizeof(float));
static_assert(offsetof(LightingRow, visibility) == LIGHTING_SHADOW * 4 * sizeof(float));
constexpr std::size_t kLightingRowFloats = sizeof(LightingRow) / sizeof(float);

struct LightRow {
  float center_inv_r2[4];  // view-space centre, 1/r²
  float color[4];          // w unused
};
static_assert(sizeof(LightRow) == LIGHT_ROW_VEC4S * 4 * sizeof(float));
constexpr std::size_t kLightRowFloats = sizeof(LightRow) / sizeof(float);

}  // namespace splatcl::present::layout
#endif

#endif
