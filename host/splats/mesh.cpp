#include "splats/mesh.hpp"

// GCC reports a false -Wmaybe-uninitialized inside OpenMesh's property vectors when sanitizers are on.
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"

#include <fmt/format.h>

#include <filesystem>
#include <fstream>

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/System/omstream.hh>

#include "runtime/error.hpp"

namespace splatcl::splats {
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

Mesh convert(OmMesh& om, bool file_normals, bool halfedge_texcoords, bool vertex_texcoords, const std::string& source) {
  if (!file_normals) {
    om.request_face_normals();
    om.update_normals();
  }
  Mesh mesh;
  mesh.source = source;
  // Unused vertices carry no surface, and as samples they would sit far from every splat.
  std::vector<std::uint32_t> remap(om.n_vertices(), UINT32_MAX);
  for (const auto v : om.vertices()) {
    if (om.is_isolated(v)) continue;
    const auto& p = om.point(v);
    const Vec3 position{p[0], p[1], p[2]};
    if (!finite(position))
      throw Error(fmt::format("{}: vertex {} has a non-finite coordinate", source, v.idx() + 1));
    const auto& n = om.normal(v);
    Vec3 normal{n[0], n[1], n[2]};
    normal = finite(normal) ? normalized(normal) : Vec3{};
    remap[static_cast<std::size_t>(v.idx())] = static_cast<std::uint32_t>(mesh.vertices.size());
    mesh.vertices.push_back(position);
    mesh.normals.push_back(normal);
  }
  const bool texcoords = halfedge_texcoords || vertex_texcoords;
  for (const auto f : om.faces()) {
    for (const auto h : om.fh_range(f)) {
      const auto v = om.to_vertex_handle(h);
      mesh.corners.push_back(remap[static_cast<std::size_t>(v.idx())]);
      if (texcoords) {
        const auto t = halfedge_texcoords ? om.texcoord2D(h) : om.texcoord2D(v);
        mesh.corner_texcoords.push_back({t[0], t[1]});
      }
    }
    mesh.face_offsets.push_back(static_cast<std::uint32_t>(mesh.corners.size()));
  }
  // OpenMesh's readers drop a vertex they cannot parse (such as a "nan" or out-of-range coordinate)
  // and then every face using it, so say so: the file may well list faces.
  if (mesh.face_count() == 0)
    throw Error(source + ": the mesh has no faces (none listed, or every face uses a vertex OpenMesh could not read, "
                         "such as a non-finite coordinate)");
  return mesh;
}

}  // namespace

Box Mesh::bounds() const {
  Box box;
  for (const Vec3& p : vertices) box.add(p);
  return box;
}

Mesh load_mesh(const std::string& path) {
  silence_openmesh();
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw Error("cannot read mesh " + path + ": no such file");
  if (!std::ifstream(path)) throw Error("cannot read mesh " + path + ": not readable");
  OmMesh om;
  om.request_vertex_normals();
  om.request_vertex_texcoords2D();
  om.request_halfedge_texcoords2D();
  OpenMesh::IO::Options options = OpenMesh::IO::Options::VertexNormal | OpenMesh::IO::Options::FaceTexCoord |
                                  OpenMesh::IO::Options::VertexTexCoord;
  bool ok = false;
  try {
    ok = OpenMesh::IO::read_mesh(om, path, options);
  } catch (const std::exception& e) {
    throw Error("cannot read mesh " + path + ": " + e.what());
  }
  if (!ok) throw Error("cannot read mesh " + path + ": not an OBJ, PLY, OFF or STL file OpenMesh can parse");
  return convert(om, options.check(OpenMesh::IO::Options::VertexNormal),
                 options.check(OpenMesh::IO::Options::FaceTexCoord),
                 options.check(OpenMesh::IO::Options::VertexTexCoord), path);
}

Mesh make_mesh(const std::vector<Vec3>& vertices, const std::vector<std::vector<std::uint32_t>>& faces,
               const std::string& description) {
  silence_openmesh();
  OmMesh om;
  om.request_vertex_normals();
  std::vector<OmMesh::VertexHandle> handles;
  handles.reserve(vertices.size());
  for (const Vec3& p : vertices) handles.push_back(om.add_vertex(OmMesh::Point(p.x, p.y, p.z)));
  for (const auto& face : faces) {
    std::vector<OmMesh::VertexHandle> corners;
    for (const std::uint32_t i : face) {
      if (i >= handles.size()) throw Error(fmt::format("{}: face refers to vertex {} of {}", description, i, handles.size()));
      corners.push_back(handles[i]);
    }
    om.add_face(corners);  // a non-manifold or repeated-corner face is rejected by OpenMesh and skipped
  }
  return convert(om, false, false, false, description);
}

}  // namespace splatcl::splats
