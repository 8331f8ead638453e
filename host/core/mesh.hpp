#pragma once
// Polygon meshes, as every stage reads them: OBJ, PLY, OFF and STL files, held and cleaned by OpenMesh.
// Vertices that no face uses are dropped (the Stanford bunny's scan has 1,113 of them); vertex
// normals come from the file where it gives them, else from OpenMesh's face-normal average.
//
// What is read, counted, dropped and refused (docs/formats.md, "Mesh input"). The files are parsed
// here (mesh_readers.cpp), not by OpenMesh's readers, which misread damaged files silently (a "nan"
// vertex shifts the indices of every later one, `v 1.2.3 -3 1.8` reads as (1.2, 0.3, -3), a
// truncated OFF repeats its last face, a PLY without end_header hangs).
// - Counted in Mesh::problems and dropped, the rest of the mesh loads: vertices whose coordinates
//   are not three finite floats (nan, inf, beyond ±3.4e38 such as 1e39, unreadable text), and the
//   faces using them; faces with a vertex index out of range (OBJ: 0, or a negative relative index
//   before the first vertex); faces with fewer than 3 distinct corners (a corner repeated next to
//   itself is merged first, so `f 1 2 3 3` is a triangle).
// - Counted and kept: zero-area faces (collinear corners; they add no samples); faces OpenMesh
//   cannot add to its half-edge structure (a non-manifold edge or vertex, or a winding opposite to a
//   neighbour's), which are kept detached on copies of their vertices as OpenMesh's own importer
//   does; edges two faces use in the same direction (inconsistent orientation); a closed part that
//   encloses negative volume and lies in no other (faces point inward).
// - Refused with one Error line naming the file: a missing or unreadable file, an unknown format, a
//   truncated file (an OFF or PLY with fewer records than its header declares, a binary STL whose
//   size does not match its triangle count), a PLY header without end_header (in the first MiB) or
//   declaring more records than the file can hold, and a mesh with no face left.
// PLY triangle strips (element tristrips, -1 restarts a strip) are read as triangles of
// alternating winding. Coordinates keep their float values at any scale (1e-30 or 1e30 load
// exactly; normals are computed on a power-of-two rescaled copy so they do not under- or overflow).
#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "core/geometry.hpp"
#include "math/dvec3.hpp"

namespace splatcl {

// What loading found wrong with a mesh, by kind (all zero / false for a clean one).
struct MeshProblems {
  std::size_t faces_listed = 0;          // faces (polygons, or strip triangles) the input lists
  std::size_t non_finite_vertices = 0;   // vertices with a coordinate that is nan, inf or beyond float range
  std::size_t unreadable_vertices = 0;   // vertex records that are not three numbers (e.g. `v 1.2.3 -3 1.8`)
  std::size_t bad_vertex_faces = 0;      // dropped: a corner is a non-finite or unreadable vertex
  std::size_t bad_index_faces = 0;       // dropped: a vertex (OBJ: or texture/normal) index out of range or unreadable
  std::size_t degenerate_faces = 0;      // dropped: fewer than 3 distinct corners (or a corner repeated apart)
  std::size_t zero_area_faces = 0;       // kept: corners collinear (or coincident) up to their float rounding (Mesh::zero_area_face)
  std::size_t complex_faces = 0;         // kept detached: OpenMesh refused the face (non-manifold, or wound against a neighbour)
  std::size_t inconsistent_edges = 0;    // undirected edges that two faces use in the same direction
  bool inward = false;                   // a closed part faces inward: one that encloses negative volume and lies in no other closed part
  std::size_t turned_faces = 0;          // Winding::Orient: faces whose corners were reversed (see there)
  // Not a problem (any() ignores it): polygons a fan from their first corner would not triangulate
  // inside their outline (concave, or non-planar with a folding fan), split into triangles by ear
  // clipping in the plane of their Newell normal, and polygons whose fan triangles stand more than
  // 30° off that normal, split into their fan; convex, nearly planar polygons are kept whole.
  std::size_t split_polygons = 0;

  std::size_t dropped_faces() const { return bad_vertex_faces + bad_index_faces + degenerate_faces; }
  // Whether Winding::Orient could turn faces of a mesh loaded as given with these problems.
  bool winding_disagrees() const { return inconsistent_edges > 0 || inward || complex_faces > 0; }
  bool any() const;
  // One line listing the non-zero kinds ("2 faces with an index out of range or unreadable dropped, faces
  // point inward"); empty when there are none.
  std::string summary() const;
};

struct Mesh;
// Vertices are floats: far from the origin for its size a mesh loses its detail on reading (a unit
// sphere at 1e7 became a handful of points 1 apart). Where the float spacing at the mesh's reach
// exceeds kFloatStepWarning of its diagonal, the warning that every command reading a model gives
// (no file name: "coordinates reach ..., where floats step by ..."); empty otherwise.
inline constexpr double kFloatStepWarning = 1e-4;
std::string float_step_warning(const Mesh& mesh);
// The spacing of floats at magnitude `reach` (0 for 0 or a non-finite reach).
double float_step_at(double reach);
// The float spacing where coordinates reach `reach`, against a shape `size` across: the one test
// and wording of every far-placement warning (meshes, presenter objects, ao's placements).
struct FloatStep {
  double step = 0, size = 0, share = 0;  // share = step / size (0 for no size)
  bool coarse() const { return share > kFloatStepWarning; }
  // "floats step by 0.0625 (5.2 % of its 1.2 size)", owner "its" and noun "size".
  std::string clause(std::string_view owner, std::string_view noun) const;
};
FloatStep float_step(double reach, double size);

struct Mesh {
  std::string source;                 // file name or a description of a generated mesh
  std::vector<Vec3> vertices;
  std::vector<Vec3> normals;          // one unit normal per vertex (zero where undefined)
  // Per vertex: its index among the file's vertices (STL: equal positions in order of appearance).
  // Vertices no face uses are dropped, and the copies a non-manifold face gets share its index.
  std::vector<std::uint32_t> file_vertex;
  std::vector<std::uint32_t> face_offsets{0};  // face f = corners [face_offsets[f], face_offsets[f+1])
  std::vector<std::uint32_t> corners;          // vertex index per face corner
  std::vector<std::array<float, 2>> corner_texcoords;  // per face corner; empty when the file has none
  MeshProblems problems;                               // what load_mesh / make_mesh counted (see above)
  // The file's coordinates are origin + vertices, the sum in double: zero unless the mesh was loaded
  // about an origin (load_mesh_about, load_mesh_recentred), which keeps the detail of a mesh far from
  // the origin for its size. Outputs that hold positions record it (the splat file's splatcl_origin).
  DVec3 origin{0, 0, 0};
  // The file's format stores floats (binary STL, a binary PLY with float x, y or z): far from the
  // origin, detail finer than the float step there was lost in the file itself.
  bool float_file = false;
  // The box of the vertices the kept faces use, in the file's coordinates (double, whatever the
  // origin): what recentring_wanted decides by.
  DVec3 file_lo{INFINITY, INFINITY, INFINITY}, file_hi{-INFINITY, -INFINITY, -INFINITY};
  // Of that box: the largest |coordinate| (floats there step by 2^-23 of it), and the diagonal.
  double file_reach() const;
  double file_diagonal() const { return length(file_hi - file_lo); }

  std::size_t face_count() const { return face_offsets.size() - 1; }
  bool has_texcoords() const { return !corner_texcoords.empty(); }
  Box bounds() const;
  // Every edge is shared by exactly two faces (no border, no non-manifold edge): a surface that
  // encloses a solid. Edges are matched by index where two faces share one, else by their corners'
  // positions (files repeat vertices at seams; faces kept detached on copies are matched so too);
  // also closed when it is without its (nearly) zero-area faces (docs/formats.md, "Closed and
  // connected by position").
  bool closed() const;
  // Whether face f's area is within the float rounding of its own corners of zero (one float step
  // of its coordinates times its longest edge): its normal is noise, so it adds no samples, no
  // surface triangles and nothing to its vertices' normals.
  bool zero_area_face(std::size_t f) const;
};

// Reads `path`, counting and dropping bad faces into Mesh::problems (see above). Throws Error naming
// the file when it is missing, unreadable, not one of the four formats, truncated or otherwise
// refused, or has no face left (the message then says what was dropped).
// How load_mesh takes the faces' winding: as the file gives it (the splat stage and batch report
// problems and leave the mesh as it is), or oriented: faces turned so that neighbours across each
// edge two faces share agree (each open connected part keeping the winding most of its area had), and
// the closed parts turned outward when they enclose negative volume (counted in turned_faces; the
// other counts are of the oriented faces). The presenter's and cluster scenes orient.
enum class Winding { AsGiven, Orient };
Mesh load_mesh(const std::string& path, Winding winding = Winding::AsGiven);
// load_mesh with the file's coordinates less `origin`, subtracted in double before they are rounded
// to float (Mesh::origin holds it): `splatcl splats verify` reads a mesh about the origin its splat
// file records.
Mesh load_mesh_about(const std::string& path, Winding winding, const DVec3& origin);
// load_mesh about the centre of the box of the vertices the kept faces use (in double): for callers
// that place a mesh by its bounds (a scene object's `fit`), so that a mesh far from the origin keeps
// its detail (a unit sphere at 1e5, read to float first, had its vertices moved by up to 0.0039, and
// its splats' outline was lumpy). With `when`, only where it holds for the box's reach (largest
// |coordinate|) and diagonal, as the file gives them or as floats (else the origin stays zero): for
// outputs that record the origin (splats, which recentre where floats are coarse for the mesh or for
// its eps).
using RecentreTest = std::function<bool(double reach, double diagonal)>;
Mesh load_mesh_recentred(const std::string& path, Winding winding, const RecentreTest& when = {});
// Whether load_mesh_recentred would recentre the file that `mesh` was read from, by its file box
// (Mesh::file_lo, file_hi): one decision for callers that read it as given first (batch).
bool recentring_wanted(const Mesh& mesh, const RecentreTest& when);
// float_step_warning's test: floats where the coordinates reach step by more than kFloatStepWarning
// of the diagonal.
bool coarse_for_floats(double reach, double diagonal);
// The same for a file's bytes already in memory (the format by the extension of `path`, which
// errors name): load_mesh is the file checks and one read, then this (the fuzz harnesses' entry).
Mesh parse_mesh(const std::string& path, std::string_view bytes);

// Builds a mesh from polygons (vertex index lists) through the same checks and OpenMesh path as
// load_mesh, so tests and generated models get the same normals, cleaning and problem counts.
// Throws Error like load_mesh when no face is left.
Mesh make_mesh(const std::vector<Vec3>& vertices, const std::vector<std::vector<std::uint32_t>>& faces,
               const std::string& description);

}  // namespace splatcl
