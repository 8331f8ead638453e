#pragma once
// Extensions of the thesis's method that make its splats keep the two-sided bound on any mesh
// (docs/results/splats.md, "The two-sided bound"):
//  - growth within ±0.9 ε: the height band of the growth rule is the surface bound's test limit;
//  - bound by the surface: before selection, a grown splat whose test points leave the mesh surface
//    by more than 0.9 ε is scaled down (then its major axis extended back as far as it passes),
//    and its covered and safe sets are recomputed from the samples still inside it; a test point
//    counts as on the surface only near a triangle that faces within 60° of the splat (no fins
//    standing across a face within ε of it);
//  - certification: after selection, every splat is certified by subdividing the ellipse (a
//    rectangle passes when its centre's distance plus its radius is at most ε, the distance being
//    1-Lipschitz, or when one triangle lies within ε of its four corners, the distance to one
//    triangle being convex) and made smaller until it passes;
//  - gap filling: after selection, the surface is checked cell by cell (each triangle subdivided
//    where needed): a cell is covered when one splat covers its three corners (what a splat covers
//    is convex, so it then covers the whole cell); below ε/16 a cell covered only by several splats
//    together is checked at its corners, edge midpoints and centre. At each uncovered point a splat
//    is added (an ellipse in the triangle's plane, as large as the surface bound allows, oriented
//    along the direction that allows the longest one), until nothing is left uncovered.
// The thesis's growth bounds a splat only by the heights of the samples it meets; the size
// corrections and the ellipse phase extrapolate beyond them, and selection guarantees coverage only
// at the samples. The extensions measure against the mesh itself (splats/surface.hpp).
#include <cmath>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "math/dvec3.hpp"
#include "splats/fit.hpp"
#include "splats/neighbors.hpp"
#include "splats/sampling.hpp"
#include "splats/splat_file.hpp"
#include "splats/surface.hpp"

namespace splatcl::splats {

// A splat as the checks see it: unit axes, semi-axis lengths, the clip line (offset +inf: none)
// and a second one (a corner, clip_to_surface; only the coverage tests read it).
struct Ellipse {
  DVec3 center, normal, u, v;
  double a = 0, b = 0;
  double clip_x = 0, clip_y = 0, clip_offset = INFINITY;
  double clip2_x = 0, clip2_y = 0, clip2_offset = INFINITY;
};
Ellipse ellipse_of(const SplatRecord& splat);
// A grown splat, its axes from its frame (so a splat of zero size still has directions).
Ellipse ellipse_of(const SplatShape& shape, const Vec4& clip, const Frame& frame);

// The points the surface bound is tested at: the centre, an inner ring and the rim (spaced at
// most 2ε apart, 24..128 points), the clip chord when clipped; points cut off by the clip are left out.
void ellipse_test_points(const Ellipse& e, double eps, std::vector<DVec3>& out);

// Whether every test point of `e` lies within `eps` of a surface triangle that faces within 60° of
// it. `recent`, kept across the tests of one splat at several sizes, only speeds the queries up.
bool within_surface(const Surface& surface, const Ellipse& e, double eps, std::vector<DVec3>& scratch,
                    Surface::Recent* recent = nullptr);

// Whether every point of `e` lies within `eps` of the surface, by a subdivision of the ellipse
// whose cells are certified by the distance at their centre plus their radius (the distance is
// 1-Lipschitz), down to ε/16; false also when the subdivision outgrows its budget.
bool certified_within_surface(const Surface& surface, const Ellipse& e, double eps);

// Makes `e` smaller until certified_within_surface holds (both axes by 0.85 at a time); false when
// even a tiny splat fails (e then has zero size).
bool shrink_until_certified(const Surface& surface, Ellipse& e, double eps);

struct SurfaceFitStats {
  std::size_t shrunk = 0;         // grown splats the surface bound made smaller
  std::size_t recertified = 0;    // selected splats made smaller again by the final certification
  std::size_t gap_splats = 0;     // splats added where the surface was not covered
  std::size_t gap_rounds = 0;     // check-and-fill rounds
  std::size_t cells_checked = 0;  // surface cells tested for coverage
  std::size_t uncovered_cells = 0;  // cells still uncovered after the last round (0 unless a round limit was hit)
  // certify_ms and gap_search_ms: the parts of cover_ms spent certifying the selected splats and
  // looking for gaps (the rest places gap splats)
  double bound_ms = 0, cover_ms = 0, certify_ms = 0, gap_search_ms = 0;
};

// The height band that growth keeps under the two-sided bound: ±(the surface bound's test limit)
// instead of the thesis's ±ε, so that most grown splats pass the bound's first test unshrunk.
float growth_eps(float eps);

// Shrinks the splats of `fit` that leave the surface by more than ε and drops the samples outside
// the shrunk ellipses from their covered and safe sets (the start point always stays).
// `neighbors` give a first guess of the scale (the nearest off-plane neighbour of the covered samples).
void bound_by_surface(const Surface& surface, const Samples& samples, const Neighborhoods& neighbors, FitResult& fit,
                      float eps, SurfaceFitStats& stats);

// Certifies every splat of `selected` against the surface (shrinking, or dropping, the splats that
// fail), then returns the splats to add so that every point of the surface lies within ε of a splat that
// contains its projection and faces its way. Colours come from `colors` at the gap (through the
// mesh's texture coordinates when it has them); with a colour tolerance below 255 and colours that
// vary, an added splat is also kept to where the surface's colour lies within the tolerance of its
// own, up to `margin` from its rim (checked at the rim and three inner rings of the ellipse shrunk
// by the margin). The margin is the colour variant's resolution, about half the sample spacing: a
// grown splat's colour edge lies somewhere between two samples too, and without it the gaps along a
// colour edge got ever smaller splats.
struct GapColour {
  int tolerance = 255;
  double margin = 0;
};
// progress(text) at the start and every 1024 gaps of a round.
std::vector<SplatRecord> fill_gaps(const Surface& surface, const Mesh& mesh, const ColorSource& colors, const GapColour& colour,
                                   std::vector<SplatRecord>& selected, float eps, SurfaceFitStats& stats,
                                   const std::function<void(const std::string&)>& progress = {});

// Fits every unclipped splat to where the surface is, for drawing the thesis's splats, whose size
// corrections reach past the last accepted sample, as drawn with both axes times `scale` (the splat
// scale k): along 16 directions of the ellipse, then 64 where
// it leaves the surface, the reach up to which its points lie within `tolerance` of the surface.
// Where the splat leaves the surface in one run of directions, the ends of the reaches trace where
// the surface ends: on one line (a sharp edge or a boundary) the splat gets a clip line there, on
// two (a convex corner) a second one as well, in `second_lines` (one per splat; offset +inf: none),
// the lines fitted by least squares and moved to the innermost end. Where it leaves it in several
// runs or all round (a curved surface under an elongated splat, seen edge-on as a fin past the
// silhouette), its major semi-axis is shortened to the reach along it, never below the minor.
// Where neither fits (the ends on no two lines, a line behind the centre, or the kept part's rim
// or chords off the surface), both axes are shrunk to its shortest reach (`shrunk`).
struct ClipLine {
  float x = 0, y = 0, offset = INFINITY;  // as SplatRecord's clip line
};
struct SurfaceClipStats {
  std::size_t clipped = 0, shortened = 0, cornered = 0, shrunk = 0;  // cornered: clipped with two lines
};
SurfaceClipStats clip_to_surface(const Surface& surface, std::vector<SplatRecord>& splats, double tolerance, double scale,
                                 std::vector<ClipLine>& second_lines);

// After clip_to_surface: the splats to add so that every point of the surface lies within
// `tolerance` of a splat (both clip lines) that contains its projection and faces its way: the gap
// filling above, over the fitted splats. The thesis's splats leave gaps between them (their
// selection covers the samples, not the surface), and the fit makes more where it shortens or
// shrinks a splat. Coverage is checked at the splats' own size, so the splat scale k they are
// drawn at is the overlap that keeps a view at an angle from seeing between two splats at
// different heights. An added splat is as large as the surface allows with every point of it, as
// drawn at `scale` (k), certified within `tolerance`; it is unclipped (clip_to_surface then cuts it
// at a sharp edge) and takes the colour of the nearest same-facing splat's centre within 8 of its
// sizes (plus 8 × the tolerance), else of the nearest splat (a grey 128 when there is none).
std::vector<SplatRecord> cover_drawn_gaps(const Surface& surface, const std::vector<SplatRecord>& splats,
                                          const std::vector<ClipLine>& second_lines, double tolerance, double scale,
                                          SurfaceFitStats& stats);

}  // namespace splatcl::splats
