// The silhouette resolve's quads: two triangles per screen rectangle (pixels x0, y0, x1, y1), the
// rectangles that may hold an outline; the rest of the image is copied as it is.
#include "layout.h"
layout(std430, binding = BINDING_RESOLVE_TILES) readonly buffer Tiles { ivec4 tiles[]; };
uniform vec2 u_viewport;

void main() {
  const ivec2 corners[6] = ivec2[6](ivec2(0, 0), ivec2(1, 0), ivec2(0, 1), ivec2(0, 1), ivec2(1, 0), ivec2(1, 1));
  ivec4 t = tiles[gl_VertexID / 6];
  vec2 p = mix(vec2(t.xy), vec2(t.zw), vec2(corners[gl_VertexID % 6]));
  gl_Position = vec4(p / u_viewport * 2.0 - 1.0, 0.0, 1.0);
}
