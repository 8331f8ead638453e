#pragma once
// Sampling a mesh into the dense point set P of the splat thesis (§2.1): the vertices (mode A), or
// the vertices plus a per-face grid of spacing d = L_min / n (mode B). Each sample has a position, a
// unit normal and an RGB colour (texture, procedural colour field, or grey).
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/geometry.hpp"
#include "core/mesh.hpp"

namespace splatcl::splats {

// An RGB image read through OpenImageIO, row 0 = top of the file.
struct Texture {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;
};
// Throws Error naming the file when it cannot be read.
Texture load_texture(const std::string& path);

// A colour for samples of models without a texture file, so the colour variant can be exercised on
// any mesh. Soft: red → white along the bounding box's longest axis (the thesis's Fig. 3.8
// gradient). Hard: 3-D checker cells of saturated colours with sharp boundaries, constant inside a
// cell. Rainbow (like Fig. 3.9's rainbow texture): the same cells, each with hue varying continuously
// along a direction at its own frequency, and a brightness jump across every cell face.
enum class ColorField { Grey, Soft, Hard, Rainbow };
const char* to_string(ColorField field);
ColorField parse_color_field(const std::string& text);  // "grey", "soft", "hard", "rainbow"; Error otherwise

// Where sample colours come from: a texture (through the mesh's texture coordinates, nearest texel,
// wrapping), else a colour field over the mesh bounds, else grey (128, 128, 128).
struct ColorSource {
  std::optional<Texture> texture;
  ColorField field = ColorField::Grey;
  Box bounds;
  Rgba8 at(Vec3 position, const float* texcoord) const;
};

// Vertices: mode A. FaceGrid: mode B with the thesis's spacing d = L_min / n. Spacing (an
// extension): the vertices plus a per-face grid of a spacing d given, or derived from ε and the
// mesh ("auto": d = ½·√(ε · bounding-box diagonal), the scale at which a splat of tolerance ε on a
// surface curved like the whole model spans a few samples), independent of the shortest edge, so
// one sliver does not set the density of the whole mesh; the grid is aligned with each polygon's
// longest edge.
enum class SampleMode { Vertices, FaceGrid, Spacing };

inline constexpr std::size_t kDefaultMaxSamples = 2'000'000;

struct SamplingOptions {
  SampleMode mode = SampleMode::Vertices;
  double per_shortest_edge = 1.0;  // n: grid samples along the shortest mesh edge (FaceGrid mode)
  double spacing = 0;              // d (Spacing mode); 0 = auto, resolved by the caller with auto_spacing
  // The sample budget: sampling whose estimated count exceeds it is refused before any sample is
  // made, or, for the automatic spacing (coarsen), made at a coarser spacing with a note.
  std::size_t max_samples = kDefaultMaxSamples;
  bool coarsen = false;
  // Samples beside an edge whose faces meet at more than this angle take their own face's normal,
  // not the vertex normals' average across the edge (see FitOptions::crease_degrees); 180: the
  // mesh's vertex normals everywhere, as the thesis does.
  float crease_degrees = 180.0f;
};

// Parses "auto", "vertices", "grid:N" or "spacing:D" (N, D > 0, fractional allowed). Throws Error otherwise.
SamplingOptions parse_sampling(const std::string& text);
std::string to_string(const SamplingOptions& options);
// The automatic spacing of mode Spacing for a tolerance ε on a mesh of bounding-box diagonal `diagonal`.
double auto_spacing(double eps, double diagonal);

struct Samples {
  std::vector<Vec4> positions;  // xyz, w = 0
  std::vector<Vec4> normals;    // unit, or zero where the mesh has no defined normal
  std::vector<Rgba8> colors;
  std::size_t vertex_samples = 0;      // kept samples that are mesh vertices (they come first)
  std::size_t duplicates_dropped = 0;  // samples at the exact position of an earlier sample
  double grid_spacing = 0;             // d (FaceGrid and Spacing modes)
  std::string note;                    // what the budget changed, for the user (empty: nothing)
  std::size_t size() const { return positions.size(); }
};

// Mode B keeps a face's grid points only when they lie farther than this fraction of the face's
// extent inside every edge: boundary points belong to the vertices and the neighbouring faces.
inline constexpr double kFaceSampleMargin = 1e-6;

// Samples `mesh`: the vertices first, then (modes B and Spacing) each face's grid, row by row from
// the lower corner of its bounding rectangle in its own plane (x along its first edge, or its longest
// in mode Spacing), strictly inside the face; a non-planar face is sampled as its fan triangles.
// Samples at exactly the same position as an earlier one are dropped (duplicate vertices;
// zero-distance neighbours make d_i and the PCA degenerate). Throws Error when the mesh yields no
// sample, or more than the budget allows (see SamplingOptions::max_samples).
Samples sample_mesh(const Mesh& mesh, const SamplingOptions& options, const ColorSource& colors);

// Per face corner (Mesh::corners), the crease-aware normal the face's samples interpolate: the
// vertex normal, or where the faces around the vertex meet at more than crease_degrees, the mean
// normal of those within crease_degrees of the corner's face (auto-smooth). 180: vertex normals.
std::vector<Vec3> corner_normals(const Mesh& mesh, float crease_degrees);

}  // namespace splatcl::splats
