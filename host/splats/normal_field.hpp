#pragma once
// Phong splats (Botsch, Spernat and Kobbelt, "Phong Splatting", 2004): a splat carries a linear
// normal field over its ellipse, so that neighbouring flat splats shade as one smooth surface
// instead of showing the facets of a low-poly mesh or the splats' own tilts as dashes. With a mesh,
// the field is fitted to the mesh's own smooth normals (its crease-aware corner normals interpolated
// over each triangle), so a sharp edge stays sharp; without one (a splat file), to the neighbouring
// splats' normals.
#include <vector>

#include "math/vec3.hpp"
#include "splats/surface.hpp"
#include "splats/surface_fit.hpp"

namespace splatcl::splats {

// The shading normal at ellipse coordinates (x, y), the point centre + x·major + y·minor (before the
// presenter's splat scale k), is centre + x·du + y·dv, normalised. A flat field: centre = the
// splat's normal, du = dv = 0.
struct NormalField {
  Vec3 centre, du, dv;
};

struct NormalFieldStats {
  std::size_t fitted = 0, flat = 0;  // flat: too few surface points on the splat's side of a crease
};

// One field per splat: least squares over 19 points of the ellipse (its centre and two rings, those
// the splat's clip lines keep, `second_lines` as clip_to_surface gives them, or empty), each taking
// the smooth normal of its nearest surface point; points whose normal is more than crease_degrees
// from the splat's (the other side of a sharp edge) or whose surface point lies farther than the
// minor semi-axis plus a quarter of the major (a hole or a gap under the splat) are left out.
// Normals on the splat's back side are turned to its front. Fewer than 6 points: flat.
std::vector<NormalField> fit_normal_fields(const Mesh& mesh, const Surface& surface, const std::vector<SplatRecord>& splats,
                                           const std::vector<ClipLine>& second_lines, float crease_degrees,
                                           NormalFieldStats* stats = nullptr);

// For splats with no mesh (a splat file): the field of each splat fitted to its own normal at its
// centre and to the normals of its nearest splats (up to 12, centres within two major semi-axes),
// at their centres' ellipse coordinates, as the Phong splatting paper does; neighbours more than
// crease_degrees off (turned to the splat's side first) or farther off its plane than its major
// semi-axis (another sheet) are left out; with fewer than 3 neighbours the splat stays flat.
std::vector<NormalField> fit_normal_fields_from_splats(const std::vector<SplatRecord>& splats, float crease_degrees,
                                                       NormalFieldStats* stats = nullptr);

// The same for other splats over them (the LOD tree's nodes of a splat file): each target's field
// from the normals of the nearest 64 splats whose centres lie within two of its major semi-axes.
std::vector<NormalField> fit_normal_fields_from_splats(const std::vector<SplatRecord>& targets, const std::vector<SplatRecord>& splats,
                                                       float crease_degrees, NormalFieldStats* stats = nullptr);

}  // namespace splatcl::splats
