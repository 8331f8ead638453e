#pragma once
// The test models: the folder SPLATCL_MODELS_DIR, which the test program defines (data/models by
// default, or the models' folder CI keeps beside the checkout). Tests that need one skip when it is
// absent.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "core/mesh.hpp"

namespace splatcl::testing {

// The path of the test model `name` ("stanford-bunny.obj"), or "" when it is absent.
inline std::string model_path(const std::string& name) {
  // Joined as a path: GCC 12 warns falsely (-Warray-bounds) on `std::string(...) + "/" + name` once
  // it is inlined into a unity batch of tests.
  const std::string path = (std::filesystem::path(SPLATCL_MODELS_DIR) / name).string();
  return std::filesystem::exists(path) ? path : std::string();
}

// The faces of `mesh` as corner lists, make_mesh's input.
inline std::vector<std::vector<std::uint32_t>> face_lists(const Mesh& mesh) {
  std::vector<std::vector<std::uint32_t>> faces;
  for (std::size_t f = 0; f < mesh.face_count(); ++f)
    faces.emplace_back(mesh.corners.begin() + mesh.face_offsets[f], mesh.corners.begin() + mesh.face_offsets[f + 1]);
  return faces;
}

// `mesh` with every vertex p at move(p), made again as a new mesh named `name` (normals, problems
// and closedness found anew).
template <class Move>
Mesh moved_mesh(const Mesh& mesh, const Move& move, const std::string& name) {
  std::vector<Vec3> vertices = mesh.vertices;
  for (Vec3& p : vertices) p = move(p);
  return make_mesh(vertices, face_lists(mesh), name);
}

}  // namespace splatcl::testing
