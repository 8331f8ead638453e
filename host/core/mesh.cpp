#include "core/mesh.hpp"

// GCC reports a false -Wmaybe-uninitialized inside OpenMesh's property vectors when sanitizers are on.
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/System/omstream.hh>

#include "runtime/error.hpp"
#include "core/mesh_readers.hpp"

namespace splatcl {
namespace {

using OmMesh = OpenMesh::PolyMesh_ArrayKernelT<>;

// OpenMesh reports problems on its own streams; our callers get one Error line instead.
void silence_openmesh() {
  static const bool silenced = [] {
    omerr().disable();
    omlog().disable();
    omout().disable();
    return true;
  }();
  (void)silenced;
}

std::string plural(std::size_t n, const char* one, const char* many) { return fmt::format("{} {}", n, n == 1 ? one : many); }

// The faces assemble() keeps: corner vertex indices into the raw mesh, and texcoords per corner.
struct Faces {
  std::vector<std::uint32_t> offsets{0}, corners;
  std::vector<std::array<float, 2>> texcoords;
  std::size_t count() const { return offsets.size() - 1; }
};

// Drops, and counts, faces with an index out of range, a bad vertex, or fewer than 3 distinct
// corners. A corner repeated next to itself (`f 1 2 3 3`) is merged first.
Faces usable_faces(const mesh_io::RawMesh& raw, MeshProblems& problems) {
  Faces faces;
  const bool texcoords = !raw.corner_texcoords.empty();
  const auto vertex_count = static_cast<std::int64_t>(raw.positions.size());
  std::vector<std::uint32_t> face, sorted;
  std::vector<std::array<float, 2>> face_texcoords;
  for (std::size_t f = 0; f < raw.face_count(); ++f) {
    const std::size_t begin = raw.face_offsets[f], end = raw.face_offsets[f + 1];
    bool bad_index = false, bad_vertex = false;
    for (std::size_t c = begin; c < end; ++c) {
      const std::int64_t v = raw.corners[c];
      if (v < 0 || v >= vertex_count)
        bad_index = true;
      else if (raw.bad_vertex[static_cast<std::size_t>(v)])
        bad_vertex = true;
    }
    if (bad_index) {
      ++problems.bad_index_faces;
      continue;
    }
    if (bad_vertex) {
      ++problems.bad_vertex_faces;
      continue;
    }
    face.clear();
    face_texcoords.clear();
    for (std::size_t c = begin; c < end; ++c) {
      const auto v = static_cast<std::uint32_t>(raw.corners[c]);
      if (!face.empty() && face.back() == v) continue;
      face.push_back(v);
      if (texcoords) face_texcoords.push_back(raw.corner_texcoords[c]);
    }
    while (face.size() > 1 && face.front() == face.back()) {
      face.pop_back();
      if (texcoords) face_texcoords.pop_back();
    }
    sorted = face;
    std::sort(sorted.begin(), sorted.end());
    if (face.size() < 3 || std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end()) {
      ++problems.degenerate_faces;
      continue;
    }
    faces.corners.insert(faces.corners.end(), face.begin(), face.end());
    faces.texcoords.insert(faces.texcoords.end(), face_texcoords.begin(), face_texcoords.end());
    faces.offsets.push_back(static_cast<std::uint32_t>(faces.corners.size()));
  }
  return faces;
}

struct Components {
  std::vector<std::uint32_t> parent;
  explicit Components(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0u); }
  std::uint32_t find(std::uint32_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  }
  void unite(std::uint32_t a, std::uint32_t b) { parent[find(a)] = find(b); }
};

// Zero-area faces, edges two faces use in the same direction, and whether the closed parts of the
// surface (components whose every edge two faces share in opposite directions) enclose negative
// volume. In double, about the bounding box's centre, so any float coordinates give finite sums.
void check_surface(const std::vector<Vec3>& positions, const Faces& faces, MeshProblems& problems) {
  using D3 = std::array<double, 3>;
  D3 lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
  for (const std::uint32_t v : faces.corners) {
    const Vec3 p = positions[v];
    const D3 q{p.x, p.y, p.z};
    for (int i = 0; i < 3; ++i) lo[i] = std::min(lo[i], q[i]), hi[i] = std::max(hi[i], q[i]);
  }
  const D3 centre{(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2};
  const auto raw_at = [&](std::uint32_t v) {
    const Vec3 p = positions[v];
    return D3{p.x, p.y, p.z};
  };
  const auto at = [&](std::uint32_t v) {
    const D3 p = raw_at(v);
    return D3{p[0] - centre[0], p[1] - centre[1], p[2] - centre[2]};
  };
  const auto sub = [](const D3& a, const D3& b) { return D3{a[0] - b[0], a[1] - b[1], a[2] - b[2]}; };
  const auto cross3 = [](const D3& a, const D3& b) {
    return D3{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
  };
  const auto key = [](std::uint32_t from, std::uint32_t to) { return std::uint64_t{from} << 32 | to; };
  const std::size_t n = faces.count();
  std::vector<double> volume(n);
  std::vector<std::pair<std::uint64_t, std::uint32_t>> edges;  // directed edge, face
  edges.reserve(faces.corners.size());
  for (std::size_t f = 0; f < n; ++f) {
    const std::uint32_t begin = faces.offsets[f], end = faces.offsets[f + 1];
    // The area from the face's own coordinates (a difference of two floats is exact in double
    // unless their magnitudes are ~2^29 apart, so collinear corners give exactly zero); the volume
    // about the common centre.
    const D3 q0 = raw_at(faces.corners[begin]), p0 = at(faces.corners[begin]);
    D3 area{0, 0, 0};
    double v = 0;
    for (std::uint32_t c = begin + 1; c + 1 < end; ++c) {
      const D3 a = cross3(sub(raw_at(faces.corners[c]), q0), sub(raw_at(faces.corners[c + 1]), q0));
      const D3 b = cross3(at(faces.corners[c]), at(faces.corners[c + 1]));
      for (int i = 0; i < 3; ++i) area[i] += a[i];
      v += p0[0] * b[0] + p0[1] * b[1] + p0[2] * b[2];
    }
    if (area[0] == 0 && area[1] == 0 && area[2] == 0) ++problems.zero_area_faces;
    volume[f] = v / 6;
    for (std::uint32_t c = begin; c < end; ++c)
      edges.emplace_back(key(faces.corners[c], faces.corners[c + 1 == end ? begin : c + 1]), static_cast<std::uint32_t>(f));
  }
  std::sort(edges.begin(), edges.end());
  Components components(n);
  std::vector<std::uint8_t> open(n, 0);
  std::vector<std::uint64_t> twice;  // undirected edges (low index first) used twice in one direction
  const auto run_end = [&](std::size_t i) {
    std::size_t j = i;
    while (j < edges.size() && edges[j].first == edges[i].first) ++j;
    return j;
  };
  for (std::size_t i = 0; i < edges.size();) {
    const std::size_t j = run_end(i);
    const auto from = static_cast<std::uint32_t>(edges[i].first >> 32), to = static_cast<std::uint32_t>(edges[i].first);
    const auto reverse = std::lower_bound(edges.begin(), edges.end(), std::pair{key(to, from), std::uint32_t{0}});
    const std::size_t ri = static_cast<std::size_t>(reverse - edges.begin()), rj = ri < edges.size() && reverse->first == key(to, from) ? run_end(ri) : ri;
    for (std::size_t k = i + 1; k < j; ++k) components.unite(edges[i].second, edges[k].second);
    if (rj > ri) components.unite(edges[i].second, edges[ri].second);
    if (j - i >= 2) twice.push_back(key(std::min(from, to), std::max(from, to)));
    if (j - i != 1 || rj - ri != 1) {
      for (std::size_t k = i; k < j; ++k) open[edges[k].second] = 1;
      for (std::size_t k = ri; k < rj; ++k) open[edges[k].second] = 1;
    }
    i = j;
  }
  std::sort(twice.begin(), twice.end());
  problems.inconsistent_edges += static_cast<std::size_t>(std::unique(twice.begin(), twice.end()) - twice.begin());
  std::vector<std::uint8_t> open_component(n, 0);
  for (std::uint32_t f = 0; f < n; ++f)
    if (open[f]) open_component[components.find(f)] = 1;
  double closed_volume = 0, closed_magnitude = 0;
  for (std::uint32_t f = 0; f < n; ++f)
    if (!open_component[components.find(f)]) closed_volume += volume[f], closed_magnitude += std::fabs(volume[f]);
  problems.inward = closed_volume < 0 && -closed_volume > 1e-6 * closed_magnitude;
}

// OpenMesh's face-normal average, on a copy scaled by a power of two (exact) when the coordinates
// are so large or small that its float cross products would over- or underflow.
void update_normals(OmMesh& om) {
  om.request_face_normals();
  float largest = 0;
  for (const auto v : om.vertices())
    if (!om.is_isolated(v))
      for (int i = 0; i < 3; ++i) largest = std::max(largest, std::fabs(om.point(v)[i]));
  if (largest > 0 && (largest > 0x1p32f || largest < 0x1p-32f)) {
    int exponent = 0;
    std::frexp(largest, &exponent);
    const float scale = std::ldexp(1.0f, -exponent);
    std::vector<OmMesh::Point> points;
    points.reserve(om.n_vertices());
    for (const auto v : om.vertices()) {
      points.push_back(om.point(v));
      om.set_point(v, om.point(v) * scale);
    }
    om.update_normals();
    for (const auto v : om.vertices()) om.set_point(v, points[static_cast<std::size_t>(v.idx())]);
  } else {
    om.update_normals();
  }
  om.release_face_normals();
}

// The checked faces into OpenMesh, then the Mesh: unused vertices dropped, normals from the file
// where it gives them, else computed.
Mesh assemble(const mesh_io::RawMesh& raw, const std::string& source) {
  silence_openmesh();
  MeshProblems problems = raw.problems;
  problems.faces_listed = raw.face_count();
  const Faces faces = usable_faces(raw, problems);
  check_surface(raw.positions, faces, problems);
  const bool texcoords = !raw.corner_texcoords.empty();

  OmMesh om;
  om.request_vertex_normals();
  if (texcoords) om.request_halfedge_texcoords2D();
  std::vector<OmMesh::VertexHandle> handles;
  handles.reserve(raw.positions.size());
  for (const Vec3& p : raw.positions) handles.push_back(om.add_vertex(OmMesh::Point(p.x, p.y, p.z)));
  std::vector<std::uint32_t> origin(raw.positions.size());  // per OpenMesh vertex: the raw vertex it copies
  std::iota(origin.begin(), origin.end(), 0u);
  std::vector<OmMesh::VertexHandle> corners;
  for (std::size_t f = 0; f < faces.count(); ++f) {
    const std::uint32_t begin = faces.offsets[f], end = faces.offsets[f + 1];
    corners.clear();
    for (std::uint32_t c = begin; c < end; ++c) corners.push_back(handles[faces.corners[c]]);
    auto face = om.add_face(corners);
    if (!face.is_valid()) {
      // OpenMesh cannot fit it into its half-edge structure (a non-manifold edge or vertex, or
      // wound against a neighbour): keep its surface on copies of its vertices, as its importer does.
      ++problems.complex_faces;
      for (std::uint32_t c = begin; c < end; ++c) {
        const OmMesh::Point p = om.point(corners[c - begin]);
        corners[c - begin] = om.add_vertex(p);
        origin.push_back(faces.corners[c]);
      }
      face = om.add_face(corners);
    }
    if (texcoords)
      for (const auto h : om.fh_range(face)) {
        const auto k = static_cast<std::size_t>(std::find(corners.begin(), corners.end(), om.to_vertex_handle(h)) - corners.begin());
        om.set_texcoord2D(h, OmMesh::TexCoord2D(faces.texcoords[begin + k][0], faces.texcoords[begin + k][1]));
      }
  }
  const auto file_normal = [&](OmMesh::VertexHandle v) { return !raw.has_normal.empty() && raw.has_normal[origin[static_cast<std::size_t>(v.idx())]]; };
  bool all_file_normals = true;
  for (const auto v : om.vertices()) all_file_normals = all_file_normals && (om.is_isolated(v) || file_normal(v));
  if (!all_file_normals) update_normals(om);

  Mesh mesh;
  mesh.source = source;
  // Unused vertices carry no surface, and as samples they would sit far from every splat.
  std::vector<std::uint32_t> remap(om.n_vertices(), UINT32_MAX);
  for (const auto v : om.vertices()) {
    if (om.is_isolated(v)) continue;
    const auto& p = om.point(v);
    Vec3 normal;
    if (file_normal(v)) {
      normal = raw.normals[origin[static_cast<std::size_t>(v.idx())]];
    } else {
      const auto& n = om.normal(v);
      normal = {n[0], n[1], n[2]};
    }
    normal = finite(normal) ? normalized(normal) : Vec3{};
    remap[static_cast<std::size_t>(v.idx())] = static_cast<std::uint32_t>(mesh.vertices.size());
    mesh.vertices.push_back({p[0], p[1], p[2]});
    mesh.normals.push_back(normal);
    mesh.file_vertex.push_back(origin[static_cast<std::size_t>(v.idx())]);
  }
  for (const auto f : om.faces()) {
    for (const auto h : om.fh_range(f)) {
      mesh.corners.push_back(remap[static_cast<std::size_t>(om.to_vertex_handle(h).idx())]);
      if (texcoords) {
        const auto t = om.texcoord2D(h);
        mesh.corner_texcoords.push_back({t[0], t[1]});
      }
    }
    mesh.face_offsets.push_back(static_cast<std::uint32_t>(mesh.corners.size()));
  }
  mesh.problems = problems;
  if (mesh.face_count() == 0) {
    if (problems.faces_listed == 0) throw Error(source + ": the mesh has no faces");
    throw Error(fmt::format("{}: the mesh has no faces left: {} dropped ({})", source,
                            problems.faces_listed == 1 ? "its one face was" : fmt::format("all {} faces were", problems.faces_listed),
                            problems.summary()));
  }
  return mesh;
}

}  // namespace

bool MeshProblems::any() const {
  return non_finite_vertices + unreadable_vertices + bad_vertex_faces + bad_index_faces + degenerate_faces + zero_area_faces +
             complex_faces + inconsistent_edges > 0 ||
         inward;
}

std::string MeshProblems::summary() const {
  std::vector<std::string> parts;
  if (non_finite_vertices > 0) parts.push_back(plural(non_finite_vertices, "vertex", "vertices") + " with a non-finite coordinate (nan, inf or beyond float range)");
  if (unreadable_vertices > 0) parts.push_back(plural(unreadable_vertices, "unreadable vertex", "unreadable vertices") + " (not three numbers)");
  if (bad_vertex_faces > 0) parts.push_back(plural(bad_vertex_faces, "face", "faces") + " using such vertices dropped");
  if (bad_index_faces > 0) parts.push_back(plural(bad_index_faces, "face", "faces") + " with an index out of range dropped");
  if (degenerate_faces > 0) parts.push_back(plural(degenerate_faces, "degenerate face", "degenerate faces") + " (fewer than 3 distinct corners) dropped");
  if (zero_area_faces > 0) parts.push_back(plural(zero_area_faces, "zero-area face", "zero-area faces"));
  if (complex_faces > 0) parts.push_back(plural(complex_faces, "non-manifold or oppositely wound face", "non-manifold or oppositely wound faces") + " kept detached");
  if (inconsistent_edges > 0)
    parts.push_back(plural(inconsistent_edges, "edge", "edges") + " with inconsistent orientation (two faces use it in the same direction)");
  if (inward) parts.push_back("faces point inward (the closed surface encloses negative volume)");
  std::string line;
  for (const std::string& part : parts) line += (line.empty() ? "" : ", ") + part;
  return line;
}

Box Mesh::bounds() const {
  Box box;
  for (const Vec3& p : vertices) box.add(p);
  return box;
}

Mesh load_mesh(const std::string& path) {
  silence_openmesh();
  return assemble(mesh_io::read_mesh_file(path), path);
}

Mesh parse_mesh(const std::string& path, std::string_view bytes) {
  silence_openmesh();
  return assemble(mesh_io::parse_mesh_file(path, bytes), path);
}

Mesh make_mesh(const std::vector<Vec3>& vertices, const std::vector<std::vector<std::uint32_t>>& faces,
               const std::string& description) {
  mesh_io::RawMesh raw;
  raw.positions.reserve(vertices.size());
  for (const Vec3& p : vertices) {
    if (!finite(p)) ++raw.problems.non_finite_vertices;
    raw.add_vertex(p, !finite(p));
  }
  for (const auto& face : faces) {
    for (const std::uint32_t i : face) raw.corners.push_back(i);
    raw.end_face();
  }
  return assemble(raw, description);
}

}  // namespace splatcl
