#pragma once
// Polygon meshes for the splat stage, read through OpenMesh (OBJ, PLY, OFF, STL). Vertices that no
// face uses are dropped (the Stanford bunny's scan has 1,113 of them); vertex normals come from the
// file or, when it has none, from OpenMesh's face-normal average.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "splats/geometry.hpp"

namespace splatcl::splats {

struct Mesh {
  std::string source;                 // file name or a description of a generated mesh
  std::vector<Vec3> vertices;
  std::vector<Vec3> normals;          // one unit normal per vertex (zero where undefined)
  std::vector<std::uint32_t> face_offsets{0};  // face f = corners [face_offsets[f], face_offsets[f+1])
  std::vector<std::uint32_t> corners;          // vertex index per face corner
  std::vector<std::array<float, 2>> corner_texcoords;  // per face corner; empty when the file has none

  std::size_t face_count() const { return face_offsets.size() - 1; }
  bool has_texcoords() const { return !corner_texcoords.empty(); }
  Box bounds() const;
};

// Reads `path`. Throws Error naming the file when it is missing, unreadable, not a mesh OpenMesh
// understands, has no faces, or has a non-finite coordinate.
Mesh load_mesh(const std::string& path);

// Builds a mesh from polygons (vertex index lists) through the same OpenMesh path as load_mesh, so
// tests and generated models get the same normals and cleaning. Throws Error like load_mesh.
Mesh make_mesh(const std::vector<Vec3>& vertices, const std::vector<std::vector<std::uint32_t>>& faces,
               const std::string& description);

}  // namespace splatcl::splats
