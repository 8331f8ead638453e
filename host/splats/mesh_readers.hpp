#pragma once
// The file readers behind load_mesh (splats/mesh.hpp): OBJ, OFF, PLY and STL parsed into a polygon
// soup exactly as listed, so that the loader can count what is wrong instead of OpenMesh's readers
// misreading it. Internal to mesh.cpp and its tests.
#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "splats/mesh.hpp"

namespace splatcl::splats::detail {

struct RawMesh {
  std::vector<Vec3> positions;
  std::vector<std::uint8_t> bad_vertex;      // per vertex: 1 where its coordinates are not three finite floats
  std::vector<Vec3> normals;                 // per vertex from the file; empty when it has none
  std::vector<std::uint8_t> has_normal;      // per vertex, beside normals
  std::vector<std::int64_t> corners;         // 0-based vertex index per face corner as listed; may be out of range
  std::vector<std::size_t> face_offsets{0};  // face f = corners [face_offsets[f], face_offsets[f+1])
  std::vector<std::array<float, 2>> corner_texcoords;  // per corner; empty when the file has none
  MeshProblems problems;                     // what the reader counted (the vertex kinds)

  std::size_t face_count() const { return face_offsets.size() - 1; }
  void add_vertex(Vec3 p, bool bad) {
    positions.push_back(bad ? Vec3{} : p);
    bad_vertex.push_back(bad ? 1 : 0);
  }
  void end_face() { face_offsets.push_back(corners.size()); }
};

// Reads `path` by its extension (any case). Throws Error "cannot read mesh PATH: ..." when it is
// missing, unreadable, of an unknown format, truncated, or its header is refused (mesh.hpp).
RawMesh read_mesh_file(const std::string& path);
// The same for a file's bytes already in memory: the format by the extension of `path`, which
// errors name. read_mesh_file is the file checks and one read, then this.
RawMesh parse_mesh_file(const std::string& path, std::string_view bytes);

// The number in all of `token` ("1.5", "-2e3", "+4", "nan", "inf"); false when it is not one.
// Values beyond double range become ±inf (or 0 when too small), as strtod gives them.
bool parse_number(std::string_view token, double& value);

}  // namespace splatcl::splats::detail
