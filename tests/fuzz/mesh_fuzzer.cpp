// OBJ, PLY, OFF and STL meshes (SPLATCL_FUZZ_MESH_NAME gives the file name, whose extension picks
// the format) through the loader every command uses: our readers, the checks and counts, OpenMesh's
// half-edge structure and normals (core/mesh.hpp); then what the CLI prints of the problems.
#include "fuzz_reader.hpp"
#include "core/mesh.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  splatcl::fuzz::check_reader(data, size, SPLATCL_FUZZ_MESH_NAME, [](const std::string& bytes) {
    const splatcl::Mesh mesh = splatcl::parse_mesh(SPLATCL_FUZZ_MESH_NAME, bytes);
    (void)mesh.problems.summary();
    // What the stages rely on: every corner indexes a vertex, one normal per vertex.
    if (mesh.normals.size() != mesh.vertices.size()) splatcl::fuzz::finding("a normal count differs from the vertex count");
    if (mesh.face_offsets.back() != mesh.corners.size()) splatcl::fuzz::finding("face offsets do not end at the corner count");
    for (const std::uint32_t c : mesh.corners)
      if (c >= mesh.vertices.size()) splatcl::fuzz::finding("a corner indexes no vertex");
    for (const splatcl::Vec3& p : mesh.vertices)
      if (!splatcl::finite(p)) splatcl::fuzz::finding("a non-finite vertex was kept");
  });
  return 0;
}
