// Mesh hygiene on input: what load_mesh and make_mesh count, drop, keep and refuse (core/mesh.hpp).
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <bit>
#include <chrono>
#include <cmath>
#include <cstring>
#include <fstream>
#include <future>
#include <numbers>
#include <thread>

#include "runtime/error.hpp"
#include "splats_test_support.hpp"

namespace splatcl::splats {
namespace {

using namespace testing;

// The Error load_mesh throws for `path`: one line naming the file and containing `text`.
void expect_refused(const std::string& path, const std::string& text) {
  try {
    load_mesh(path);
    ADD_FAILURE() << path << ": no error";
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(path), std::string::npos) << what;
    EXPECT_NE(what.find(text), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << "one line: " << what;
  }
}

// Corner positions of face f.
std::vector<Vec3> face_positions(const Mesh& mesh, std::size_t f) {
  std::vector<Vec3> out;
  for (std::uint32_t c = mesh.face_offsets[f]; c < mesh.face_offsets[f + 1]; ++c) out.push_back(mesh.vertices[mesh.corners[c]]);
  return out;
}

// Whether face f has the corners `expected`, in this cyclic order (from any start).
bool face_is(const Mesh& mesh, std::size_t f, const std::vector<Vec3>& expected) {
  const std::vector<Vec3> p = face_positions(mesh, f);
  if (p.size() != expected.size()) return false;
  for (std::size_t r = 0; r < p.size(); ++r) {
    bool same = true;
    for (std::size_t i = 0; i < p.size(); ++i) same = same && p[(i + r) % p.size()] == expected[i];
    if (same) return true;
  }
  return false;
}

Vec3 face_normal(const Mesh& mesh, std::size_t f) {
  const std::vector<Vec3> p = face_positions(mesh, f);
  Vec3 n{};
  for (std::size_t i = 1; i + 1 < p.size(); ++i) n = n + cross(p[i] - p[0], p[i + 1] - p[0]);
  return n;
}

// Every count zero except those named.
void expect_only(const MeshProblems& p, std::size_t non_finite, std::size_t unreadable, std::size_t bad_vertex_faces,
                 std::size_t bad_index_faces, std::size_t degenerate = 0, std::size_t zero_area = 0) {
  EXPECT_EQ(p.non_finite_vertices, non_finite);
  EXPECT_EQ(p.unreadable_vertices, unreadable);
  EXPECT_EQ(p.bad_vertex_faces, bad_vertex_faces);
  EXPECT_EQ(p.bad_index_faces, bad_index_faces);
  EXPECT_EQ(p.degenerate_faces, degenerate);
  EXPECT_EQ(p.zero_area_faces, zero_area);
  EXPECT_EQ(p.complex_faces, 0u);
  EXPECT_EQ(p.inconsistent_edges, 0u);
  EXPECT_FALSE(p.inward);
}

// The unit cube `v`, `outward` with a half-size cube inside it facing into the cavity.
std::pair<std::vector<Vec3>, std::vector<std::vector<std::uint32_t>>> hollow_cube(const std::vector<Vec3>& v,
                                                                                 const std::vector<std::vector<std::uint32_t>>& outward) {
  std::vector<Vec3> hollow = v;
  auto shell = outward;
  for (const Vec3& p : v) hollow.push_back(0.5f * p + Vec3{0.25f, 0.25f, 0.25f});
  for (auto f : outward) {
    std::reverse(f.begin(), f.end());
    for (auto& i : f) i += 8;
    shell.push_back(f);
  }
  return {hollow, shell};
}

const char* const kQuadVertices = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n";

TEST(MeshHygiene, ObjIndexOutOfRangeDropsThatFaceOnly) {
  const Mesh mesh = load_mesh(temp_file("range.obj", std::string(kQuadVertices) + "f 1 2 3\nf 1 3 9\nf 0 1 2\nf 1 3 x\n"));
  EXPECT_EQ(mesh.face_count(), 1u);
  EXPECT_EQ(mesh.vertices.size(), 3u);
  EXPECT_EQ(mesh.problems.faces_listed, 4u);
  expect_only(mesh.problems, 0, 0, 0, 3);
  EXPECT_TRUE(mesh.problems.any());
  EXPECT_EQ(mesh.problems.summary(), "3 faces with an index out of range or unreadable dropped");
}

TEST(MeshHygiene, ObjNegativeIndicesCountBackFromTheLastVertexSoFar) {
  // -1 is the last vertex defined before the face line; -5 after four vertices is before the first.
  const Mesh mesh = load_mesh(temp_file("relative.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nf -3 -2 -1\nv 0 1 0\nf -4 -2 -1\nf -1 -2 -5\n"));
  ASSERT_EQ(mesh.face_count(), 2u);
  expect_only(mesh.problems, 0, 0, 0, 1);
  EXPECT_TRUE(face_is(mesh, 1, {{0, 0, 0}, {1, 1, 0}, {0, 1, 0}}));
}

TEST(MeshHygiene, ObjVertexThatIsNotThreeNumbersIsNotMisread) {
  // OpenMesh's reader takes `v 1.2.3 -3 1.8` as (1.2, 0.3, -3).
  const Mesh mesh = load_mesh(temp_file("dots.obj", std::string(kQuadVertices) + "v 1.2.3 -3 1.8\nv 2 2\nf 1 2 3\nf 1 3 4\nf 2 5 3\nf 1 6 2\n"));
  EXPECT_EQ(mesh.face_count(), 2u);
  EXPECT_EQ(mesh.vertices.size(), 4u);
  expect_only(mesh.problems, 0, 2, 2, 0);
  for (const Vec3& p : mesh.vertices) EXPECT_TRUE(p.x == 0 || p.x == 1) << p.x;
}

TEST(MeshHygiene, ObjNonFiniteVertexDropsItsFacesAndShiftsNoIndex) {
  // OpenMesh's reader drops the nan vertex and shifts every later index by one.
  const Mesh mesh = load_mesh(temp_file("hygiene-nan.obj", "v 0 0 0\nv nan 1 0\nv 1 0 0\nv 0 1 0\nv 1e39 0 0\nv 1 1 inf\n"
                                                   "f 1 3 4\nf 1 2 3\nf 3 5 4\nf 3 6 4\n"));
  ASSERT_EQ(mesh.face_count(), 1u);
  expect_only(mesh.problems, 3, 0, 3, 0);
  EXPECT_TRUE(face_is(mesh, 0, {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}));
  EXPECT_NE(mesh.problems.summary().find("3 vertices with a non-finite coordinate"), std::string::npos) << mesh.problems.summary();
  // Every face on a bad vertex: an error saying why.
  expect_refused(temp_file("all-nan.obj", "v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n"), "no faces left: its one face was dropped (1 vertex with a non-finite");
}

TEST(MeshHygiene, FarFromOneCoordinatesLoadExactly) {
  for (const float scale : {1e-30f, 1e-20f, 1e20f, 1e30f, 3e38f}) {
    const std::string text = fmt::format("v 0 0 0\nv {:.9g} 0 0\nv 0 {:.9g} 0\nv 0 0 {:.9g}\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n", scale, scale, scale);
    const Mesh mesh = load_mesh(temp_file("far.obj", text));
    ASSERT_EQ(mesh.face_count(), 4u) << scale;
    EXPECT_FALSE(mesh.problems.any()) << scale << ": " << mesh.problems.summary();
    for (const Vec3& p : mesh.vertices) {
      EXPECT_TRUE(p.x == 0 || p.x == scale) << scale;
      EXPECT_TRUE(finite(p));
    }
    for (const Vec3& n : mesh.normals) EXPECT_NEAR(length(n), 1.0f, 1e-5f) << scale;
    // The bounding-box diagonal (the splat stage's ε is relative to it) is √3 × the scale, not an
    // overflow or underflow of float squares; 3e38 × √3 is beyond float, so inf there.
    if (scale < 1e38f) {
      EXPECT_NEAR(mesh.bounds().diagonal() / scale, std::sqrt(3.0f), 1e-6f) << scale;
    }
  }
}

// Read about the centre of its box (with the test coarse_for_floats) only where the file's coordinates are too
// coarse as floats for the mesh's size: then each vertex is its file position less that centre,
// subtracted in double and rounded once (the tetrahedron's corners 0.001 apart at 1e6, 16 float
// steps of 0.0625 there, were one point). Near the origin the mesh is the one load_mesh reads.
// load_mesh_about takes a given origin the same way.
TEST(MeshHygiene, CoarseCoordinatesAreReadAboutTheBoxCentre) {
  const std::string far = temp_file("tetra-far.obj", "v 1000000 -2000000 5\nv 1000000.001 -2000000 5\nv 1000000 -1999999.999 5\n"
                                                     "v 1000000 -2000000 5.001\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n");
  const Mesh recentred = load_mesh_recentred(far, Winding::Orient, coarse_for_floats);
  const DVec3 centre{0.5 * 1000000 + 0.5 * 1000000.001, 0.5 * -2000000 + 0.5 * -1999999.999, 0.5 * 5 + 0.5 * 5.001};
  EXPECT_EQ(recentred.origin.x, centre.x);
  EXPECT_EQ(recentred.origin.y, centre.y);
  EXPECT_EQ(recentred.origin.z, centre.z);
  const DVec3 file[4] = {{1000000, -2000000, 5}, {1000000.001, -2000000, 5}, {1000000, -1999999.999, 5}, {1000000, -2000000, 5.001}};
  ASSERT_EQ(recentred.vertices.size(), 4u);
  for (std::size_t v = 0; v < 4; ++v) {
    const Vec3 want = to_float(file[recentred.file_vertex[v]] - centre);
    EXPECT_EQ(recentred.vertices[v].x, want.x);
    EXPECT_EQ(recentred.vertices[v].y, want.y);
    EXPECT_EQ(recentred.vertices[v].z, want.z);
  }
  EXPECT_NEAR(recentred.bounds().exact_diagonal(), 0.001 * std::sqrt(3.0), 1e-9);
  EXPECT_TRUE(float_step_warning(recentred).empty()) << float_step_warning(recentred);
  EXPECT_FALSE(float_step_warning(load_mesh(far)).empty());  // as given, it collapses
  const Mesh about = load_mesh_about(far, Winding::Orient, DVec3{1000000, -2000000, 5});
  EXPECT_EQ(about.origin.x, 1000000.0);
  EXPECT_EQ(about.vertices[0].x, 0.0f);
  EXPECT_NEAR(about.bounds().exact_diagonal(), 0.001 * std::sqrt(3.0), 1e-9);

  // The same tetrahedron as ASCII STL: its corners are merged as read, in double (merged as floats
  // they were one point before the mesh could be recentred), so it reads the same; it is no float file.
  std::string stl = "solid t\n";
  for (const auto& face : std::vector<std::array<int, 3>>{{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}}) {
    stl += " facet normal 0 0 0\n  outer loop\n";
    for (const int c : face) stl += fmt::format("   vertex {:.17g} {:.17g} {:.17g}\n", file[c].x, file[c].y, file[c].z);
    stl += "  endloop\n endfacet\n";
  }
  const Mesh from_stl = load_mesh_recentred(temp_file("tetra-far.stl", stl + "endsolid t\n"), Winding::Orient, coarse_for_floats);
  ASSERT_EQ(from_stl.vertices.size(), 4u);
  EXPECT_EQ(from_stl.face_count(), 4u);
  EXPECT_FALSE(from_stl.problems.any()) << from_stl.problems.summary();
  EXPECT_NEAR(from_stl.bounds().exact_diagonal(), 0.001 * std::sqrt(3.0), 1e-9);
  EXPECT_FALSE(from_stl.float_file);
  EXPECT_FALSE(recentred.float_file);
  // A binary STL stores floats: the detail finer than their step was lost in the file itself, which
  // the splats' warning says (not of an OBJ whose values happen to be floats).
  const DVec3 unit_far[4] = {{1000000, 0, 0}, {1000001, 0, 0}, {1000000, 1, 0}, {1000000, 0, 1}};
  std::string binary(80, ' ');
  const auto put = [&](auto value) { binary.append(reinterpret_cast<const char*>(&value), sizeof value); };
  put(std::uint32_t{4});
  for (const auto& face : std::vector<std::array<int, 3>>{{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}}) {
    for (int k = 0; k < 3; ++k) put(0.0f);
    for (const int c : face) put(static_cast<float>(unit_far[c].x)), put(static_cast<float>(unit_far[c].y)), put(static_cast<float>(unit_far[c].z));
    put(std::uint16_t{0});
  }
  EXPECT_TRUE(load_mesh_recentred(temp_file("tetra-far-binary.stl", binary), Winding::Orient, coarse_for_floats).float_file);
  const std::string integers = temp_file("box-far-integers.obj", "v 1000000 0 0\nv 1000001 0 0\nv 1000000 1 0\nv 1000000 0 1\n"
                                                                  "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n");
  EXPECT_FALSE(load_mesh_recentred(integers, Winding::Orient, coarse_for_floats).float_file);

  const std::string near = temp_file("tetra-near-origin.obj", "v 1000 0 0\nv 1001 0 0\nv 1000 1 0\nv 1000 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n");
  const Mesh kept = load_mesh_recentred(near, Winding::Orient, coarse_for_floats), plain = load_mesh(near, Winding::Orient);
  EXPECT_EQ(kept.origin.x, 0.0);
  EXPECT_EQ(kept.origin.y, 0.0);
  EXPECT_EQ(kept.origin.z, 0.0);
  ASSERT_EQ(kept.vertices.size(), plain.vertices.size());
  for (std::size_t v = 0; v < kept.vertices.size(); ++v) EXPECT_TRUE(kept.vertices[v] == plain.vertices[v]) << v;
  EXPECT_NE(load_mesh_recentred(near, Winding::Orient).origin.x, 0.0);  // no test: always
}

TEST(MeshHygiene, OffTruncatedIsRefused) {
  const std::string whole = "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n";
  EXPECT_EQ(load_mesh(temp_file("whole.off", whole)).face_count(), 2u);
  // OpenMesh reads the first as two faces (its last face repeated) and the second as four points at one place.
  expect_refused(temp_file("cut-face.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n"),
                 "truncated OFF: the header declares 4 vertices and 2 faces, the file ends after 4 vertices and 1 face");
  expect_refused(temp_file("cut-vertex.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n"), "the file ends after 3 vertices and 0 faces");
  expect_refused(temp_file("cut-inside.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2"), "truncated OFF");
  expect_refused(temp_file("huge.off", "OFF\n1000000000000 1 0\n0 0 0\n"), "truncated OFF");
  // A bad record in the middle is counted, not refused; a nan vertex shifts nothing.
  const Mesh mesh = load_mesh(temp_file("bad.off", "OFF\n5 3 0\n0 0 0\nnan 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 2 3\n3 0 1 2\n3 0 3 7\n"));
  ASSERT_EQ(mesh.face_count(), 1u);
  expect_only(mesh.problems, 1, 0, 1, 1);
  EXPECT_TRUE(face_is(mesh, 0, {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}}));
}

std::string ply_header(const std::string& format, int vertices, const std::string& faces) {
  return fmt::format("ply\nformat {} 1.0\nelement vertex {}\nproperty float x\nproperty float y\nproperty float z\n{}end_header\n", format, vertices, faces);
}

// 32-bit words in the given byte order: binary OFF's counts (integers) and values (floats).
std::string off_words(const std::vector<double>& values, bool big_endian, std::size_t integers) {
  std::string out;
  for (std::size_t i = 0; i < values.size(); ++i) {
    std::uint32_t word = i < integers ? static_cast<std::uint32_t>(static_cast<std::int32_t>(values[i]))
                                      : std::bit_cast<std::uint32_t>(static_cast<float>(values[i]));
    if (big_endian == (std::endian::native == std::endian::little)) word = __builtin_bswap32(word);
    out.append(reinterpret_cast<const char*>(&word), 4);
  }
  return out;
}

// Binary, 4D (homogeneous) and nOFF files, once OpenMesh's (it reserved 3 GB for a bare "4OFF",
// a fuzz finding: tests/fuzz/corpus/mesh_off/regression-4off-no-counts.off), now ours.
TEST(MeshHygiene, OffBinaryHomogeneousAndNDimensionalVariants) {
  const std::vector<Vec3> triangle{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  const auto expect_triangle = [&](const std::string& name, const std::string& contents) {
    const Mesh mesh = load_mesh(temp_file(name, contents));
    ASSERT_EQ(mesh.face_count(), 1u) << name;
    EXPECT_TRUE(face_is(mesh, 0, triangle)) << name;
    expect_only(mesh.problems, 0, 0, 0, 0);
  };
  expect_triangle("homogeneous.off", "4OFF\n3 1 0\n0 0 0 1\n2 0 0 2\n0 -3 0 -3\n3 0 1 2\n");
  expect_triangle("dimension.off", "nOFF\n3\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  // Face: 3 corners, then a colour count of 1 with its float.
  const std::vector<double> body{3, 1, 0, 0, 0, 0, 1, 0, 0, 0, 1, 0};
  const std::vector<double> face{3, 0, 1, 2, 1, 0.5};
  for (const bool big : {true, false})
    expect_triangle(big ? "big.off" : "little.off", "OFF BINARY\n" + off_words(body, big, 3) + off_words(face, big, 5));
  const Mesh w0 = load_mesh(temp_file("w0.off", "4OFF\n4 2 0\n0 0 0 1\n1 0 0 1\n0 1 0 1\n1 1 0 0\n3 0 1 2\n3 1 3 2\n"));
  expect_only(w0.problems, 1, 0, 1, 0);
  expect_refused(temp_file("bare-4off.off", "4OFF"), "no vertex and face counts");
  expect_refused(temp_file("dimension-4.off", "nOFF 4 3 1 0\n"), "nOFF of dimension '4': only 3-dimensional meshes are read");
  expect_refused(temp_file("binary-huge.off", "OFF BINARY\n" + off_words({1e9, 1, 0}, true, 3) + std::string(64, '\0')),
                 "binary OFF header declares 1000000000 vertices and 1 face, more than the 64 bytes after it can hold");
  expect_refused(temp_file("binary-cut.off", "OFF BINARY\n" + off_words(body, true, 3) + off_words({3, 0, 1}, true, 3)),
                 "truncated binary OFF: the file ends in face 1 of 1");
}

// A PLY list length stored as a float beyond any integer (UB in the cast before; a fuzz finding:
// tests/fuzz/corpus/mesh_ply/regression-float-list-count.ply) is a truncated file.
TEST(MeshHygiene, PlyListLengthBeyondTheFileIsTruncation) {
  std::string file = ply_header("binary_little_endian", 3, "element face 1\nproperty list float int vertex_indices\n");
  const float values[10] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 7e31f};
  file.append(reinterpret_cast<const char*>(values), sizeof values);
  expect_refused(temp_file("float-count.ply", file), "truncated PLY: the file ends in face record 1 of 1");
}

TEST(MeshHygiene, PlyWithoutEndHeaderIsRefusedAtOnce) {
  const std::string small = temp_file("no-end.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n0\n1\n2\n");
  std::string big = "ply\nformat binary_little_endian 1.0\n";
  while (big.size() < (3u << 20)) big += "comment a header that never ends\n";
  const std::string large = temp_file("no-end-large.ply", big);
  // OpenMesh's reader never returns on these: guard the test with a deadline.
  const auto start = std::chrono::steady_clock::now();
  std::packaged_task<void()> task([small, large] {
    expect_refused(small, "PLY header has no end_header");
    expect_refused(large, "PLY header has no end_header in its first MiB");
  });
  std::future<void> done = task.get_future();
  std::thread(std::move(task)).detach();
  ASSERT_EQ(done.wait_for(std::chrono::seconds(5)), std::future_status::ready) << "load_mesh hangs on a PLY without end_header";
  done.get();
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 1.0);
}

TEST(MeshHygiene, PlyHeaderCountsBeyondTheFileAreRefused) {
  const std::string body = "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  expect_refused(temp_file("faces.ply", ply_header("ascii", 3, "element face 1000000000000\nproperty list uchar int vertex_indices\n") + body),
                 "PLY header declares 1000000000000 face records, more than the 26 bytes after end_header can hold");
  expect_refused(temp_file("vertices.ply", ply_header("binary_little_endian", 2000000000, "") + std::string(36, '\0')),
                 "PLY header declares 2000000000 vertex records");
  // Fewer records than declared, but within what the size allows: truncated.
  expect_refused(temp_file("hygiene-short.ply", ply_header("ascii", 3, "element face 2\nproperty list uchar int vertex_indices\n") + body),
                 "truncated PLY: the file ends in face record 2 of 2");
  std::string binary = ply_header("binary_little_endian", 3, "");
  const float xyz[8] = {0, 0, 0, 1, 0, 0, 0, 1};
  binary.append(reinterpret_cast<const char*>(xyz), sizeof xyz);  // 8 floats of 9
  expect_refused(temp_file("short-binary.ply", binary), "PLY header declares 3 vertex records");
}

// ASCII records are one per line: a vertex line with a value too many shifted every later record
// (the mesh read as other vertices and faces, without a word); one too few likewise.
TEST(MeshHygiene, PlyAsciiRecordsEndTheirLines) {
  const std::string faces = "element face 1\nproperty list uchar int vertex_indices\n";
  expect_refused(temp_file("extra-value.ply", ply_header("ascii", 3, faces) + "0 0 0\n1 0 0 7\n0 1 0\n3 0 1 2\n"),
                 "PLY vertex record 2: its line holds more or fewer values than its properties");
  expect_refused(temp_file("short-line.ply", ply_header("ascii", 3, faces) + "0 0 0\n1 0\n0 1 0\n3 0 1 2\n"),
                 "PLY vertex record 2: its line holds more or fewer values than its properties");
  // Blank space at line ends, CRLF, blank lines between records and no newline at the end are fine.
  const Mesh mesh = load_mesh(temp_file("loose.ply", ply_header("ascii", 3, faces) + "0 0 0 \r\n\n1 0 0\t\n0 1 0\n3 0 1 2"));
  EXPECT_EQ(mesh.face_count(), 1u);
}

TEST(MeshHygiene, PlyNonFiniteVertexDropsItsFaceOnly) {
  // OpenMesh's reader turns every vertex of this file into (0, 0, 0).
  const Mesh mesh = load_mesh(temp_file("nan.ply", ply_header("ascii", 5, "element face 2\nproperty list uchar int vertex_indices\n") +
                                                        "0 0 0\nnan 0 0\n1 0 0\n0 1 0\n1 1 1e39\n3 0 2 3\n3 0 1 2\n"));
  ASSERT_EQ(mesh.face_count(), 1u);
  expect_only(mesh.problems, 2, 0, 1, 0);
  EXPECT_TRUE(face_is(mesh, 0, {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}));
}

// Two rows of four vertices in z = 0 (a strip zig-zagging along x), and two above the first column.
const char* const kStripVertices = "0 0 0\n0 1 0\n1 0 0\n1 1 0\n2 0 0\n2 1 0\n3 0 0\n3 1 0\n0 2 0\n1 2 0\n";
void expect_strip_triangles(const Mesh& mesh) {
  ASSERT_EQ(mesh.face_count(), 8u);
  EXPECT_FALSE(mesh.problems.any()) << mesh.problems.summary();
  EXPECT_EQ(mesh.problems.faces_listed, 8u);
  for (std::size_t f = 0; f < mesh.face_count(); ++f) {
    ASSERT_EQ(mesh.face_offsets[f + 1] - mesh.face_offsets[f], 3u);
    // The first triangle (0, 1, 2) winds clockwise seen from +z; alternation keeps every one so.
    EXPECT_EQ(face_normal(mesh, f).z, -1.0f) << "triangle " << f;
  }
  EXPECT_TRUE(face_is(mesh, 0, {{0, 0, 0}, {0, 1, 0}, {1, 0, 0}}));
  EXPECT_TRUE(face_is(mesh, 1, {{1, 0, 0}, {0, 1, 0}, {1, 1, 0}}));  // (2 1 3): the second triangle swapped
  EXPECT_TRUE(face_is(mesh, 6, {{0, 1, 0}, {0, 2, 0}, {1, 1, 0}}));  // (1 8 3): after the restart, unswapped
}

TEST(MeshHygiene, PlyTriangleStripsAreReadWithAlternatingWinding) {
  // Strip 1: 0 1 2 3 4 5 6 7 (6 triangles); -1 restarts; strip 2: 1 8 3 9 (2 triangles).
  const std::string strips = "element tristrips 1\nproperty list int int vertex_indices\n";
  expect_strip_triangles(load_mesh(temp_file("strips.ply", ply_header("ascii", 10, strips) + kStripVertices + "13 0 1 2 3 4 5 6 7 -1 1 8 3 9\n")));
  // The same in binary little-endian, the list length a uchar.
  std::string binary = ply_header("binary_little_endian", 10, "element tristrips 1\nproperty list uchar int vertex_indices\n");
  const float v[30] = {0, 0, 0, 0, 1, 0, 1, 0, 0, 1, 1, 0, 2, 0, 0, 2, 1, 0, 3, 0, 0, 3, 1, 0, 0, 2, 0, 1, 2, 0};
  binary.append(reinterpret_cast<const char*>(v), sizeof v);
  const std::int32_t list[13] = {0, 1, 2, 3, 4, 5, 6, 7, -1, 1, 8, 3, 9};
  binary.push_back(13);
  binary.append(reinterpret_cast<const char*>(list), sizeof list);
  expect_strip_triangles(load_mesh(temp_file("strips-binary.ply", binary)));
}

TEST(MeshHygiene, PlyStripJoinsThroughRepeatedIndicesAddNoFace) {
  // 0 1 2 3 | 3 4 (a join of two degenerate triangles) ... as one strip 0 1 2 3 3 4 4 5 6 7.
  // Triangles: (0 1 2) (2 1 3) (2 3 3)x (3 3 4)x (3 4 4)x (4 4 5)x (4 5 6) (6 5 7): 4 faces, all
  // wound alike because the joins keep the parity.
  const Mesh mesh = load_mesh(temp_file("strip-join.ply", ply_header("ascii", 10, "element tristrips 1\nproperty list int int vertex_indices\n") +
                                                              kStripVertices + "10 0 1 2 3 3 4 4 5 6 7\n"));
  ASSERT_EQ(mesh.face_count(), 4u);
  EXPECT_FALSE(mesh.problems.any()) << mesh.problems.summary();
  for (std::size_t f = 0; f < mesh.face_count(); ++f) EXPECT_EQ(face_normal(mesh, f).z, -1.0f) << "triangle " << f;
}

TEST(MeshHygiene, StlNonFiniteVertexAndTruncatedBinary) {
  const std::string facet = "facet normal 0 0 1\nouter loop\nvertex {}\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\n";
  const Mesh mesh = load_mesh(temp_file("nan.stl", "solid t\n" + fmt::format(fmt::runtime(facet), "0 0 0") + fmt::format(fmt::runtime(facet), "nan 0 0") +
                                                       fmt::format(fmt::runtime(facet), "1.2.3 0 0") + "endsolid t\n"));
  EXPECT_EQ(mesh.face_count(), 1u);
  expect_only(mesh.problems, 1, 1, 2, 0);
  std::string binary(80, ' ');
  const std::uint32_t triangles = 2;
  binary.append(reinterpret_cast<const char*>(&triangles), 4);
  binary.append(50, '\0');
  expect_refused(temp_file("short.stl", binary), "binary STL of 134 bytes, but its header declares 2 triangles (184 bytes)");
  expect_refused(temp_file("cut.stl", "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n"), "truncated STL");
}

TEST(MeshHygiene, InconsistentOrientationIsCountedAndTheFacesKept) {
  // Two triangles sharing the edge 1-2, both using it from 1 to 2.
  const Mesh flipped = make_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}}, {{0, 1, 2}, {1, 2, 3}}, "flipped");
  EXPECT_EQ(flipped.face_count(), 2u);
  EXPECT_EQ(flipped.problems.inconsistent_edges, 1u);
  EXPECT_EQ(flipped.problems.complex_faces, 1u);  // OpenMesh cannot link it: kept on copies of its vertices
  EXPECT_EQ(flipped.problems.dropped_faces(), 0u);
  EXPECT_FALSE(flipped.problems.inward);
  // A cube with one face turned: all four of its edges, and OpenMesh detaches the face.
  const std::vector<Vec3> v{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  const Mesh cube = make_mesh(v, {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {2, 3, 7, 6}, {1, 2, 6, 5}, {0, 3, 7, 4}}, "turned");
  EXPECT_EQ(cube.face_count(), 6u);
  EXPECT_EQ(cube.problems.inconsistent_edges, 4u);
  EXPECT_EQ(cube.problems.complex_faces, 1u);
  EXPECT_FALSE(cube.problems.inward) << "not a consistently closed surface";
  EXPECT_NE(cube.problems.summary().find("4 edges with inconsistent orientation"), std::string::npos) << cube.problems.summary();
  // The same through a file.
  const Mesh file = load_mesh(temp_file("flipped.obj", std::string(kQuadVertices) + "f 1 2 4\nf 2 4 3\n"));
  EXPECT_EQ(file.problems.inconsistent_edges, 1u);
  EXPECT_EQ(file.face_count(), 2u);
}

// Two outward cubes touching along one edge: four faces share it, two each way. Nothing is wound
// wrong, yet it was warned "1 edge with inconsistent orientation" (a helper's audit).
TEST(MeshHygiene, AnEdgeFourFacesShareTwoEachWayIsConsistent) {
  std::vector<Vec3> v;
  std::vector<std::vector<std::uint32_t>> f;
  for (const float o : {0.0f, 1.0f}) {  // the unit cube at (o, o, 0), outward quads
    const auto base = static_cast<std::uint32_t>(v.size());
    for (int k = 0; k < 8; ++k) v.push_back({o + static_cast<float>(k & 1), o + static_cast<float>((k >> 1) & 1), static_cast<float>((k >> 2) & 1)});
    for (const auto& q : {std::array{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}})
      f.push_back({base + q[0], base + q[1], base + q[2], base + q[3]});
  }
  const Mesh cubes = make_mesh(v, f, "two cubes");
  EXPECT_EQ(cubes.problems.inconsistent_edges, 0u) << cubes.problems.summary();
  EXPECT_EQ(cubes.problems.summary().find("inconsistent orientation"), std::string::npos) << cubes.problems.summary();
  EXPECT_EQ(cubes.face_count(), 12u);
}

TEST(MeshHygiene, InsideOutClosedMeshIsWarned) {
  const std::vector<Vec3> v{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  std::vector<std::vector<std::uint32_t>> outward{{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {2, 3, 7, 6}, {1, 2, 6, 5}, {0, 4, 7, 3}};
  EXPECT_FALSE(make_mesh(v, outward, "cube").problems.any()) << make_mesh(v, outward, "cube").problems.summary();
  EXPECT_FALSE(cube_mesh().problems.any());
  EXPECT_FALSE(sphere_mesh(12, 16).problems.any()) << sphere_mesh(12, 16).problems.summary();
  auto inward = outward;
  for (auto& f : inward) std::reverse(f.begin(), f.end());
  const Mesh inside_out = make_mesh(v, inward, "inside-out cube");
  EXPECT_TRUE(inside_out.problems.inward);
  EXPECT_EQ(inside_out.problems.inconsistent_edges, 0u);
  EXPECT_EQ(inside_out.problems.summary(), "faces point inward (a closed surface encloses negative volume)");
  // Far from the origin and at any scale, the same.
  std::vector<Vec3> far = v;
  for (Vec3& p : far) p = 1e30f * p + Vec3{3e30f, -2e30f, 1e30f};
  EXPECT_TRUE(make_mesh(far, inward, "far inside-out cube").problems.inward);
  EXPECT_FALSE(make_mesh(far, outward, "far cube").problems.inward);
  // Open, the volume means nothing: no warning.
  inward.pop_back();
  EXPECT_FALSE(make_mesh(v, inward, "open inside-out cube").problems.inward);
  // An open part beside a closed inside-out one: the closed part is judged.
  auto both = outward;
  for (auto& f : both) std::reverse(f.begin(), f.end());
  std::vector<Vec3> with_plane = v;
  for (const Vec3 p : {Vec3{5, 0, 0}, Vec3{6, 0, 0}, Vec3{6, 1, 0}}) with_plane.push_back(p);
  both.push_back({8, 9, 10});
  EXPECT_TRUE(make_mesh(with_plane, both, "cube and triangle").problems.inward);
  // A hollow shell (an inner cube facing into the cavity) encloses positive volume: no warning.
  const auto [hollow, shell] = hollow_cube(v, outward);
  EXPECT_FALSE(make_mesh(hollow, shell, "hollow cube").problems.any());
  // Through a file: the inside-out cube as OBJ.
  const Mesh file = load_mesh(temp_file("inside-out.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
                                                          "f 2 3 4 1\nf 8 7 6 5\nf 5 6 2 1\nf 7 8 4 3\nf 6 7 3 2\nf 4 8 5 1\n"));
  EXPECT_TRUE(file.problems.inward);
}

// `faces` (0-based corners) over `vertices` as OBJ text.
std::string obj_text(const std::vector<Vec3>& vertices, const std::vector<std::vector<std::uint32_t>>& faces) {
  std::string text;
  for (const Vec3& p : vertices) text += fmt::format("v {} {} {}\n", p.x, p.y, p.z);
  for (const auto& f : faces) {
    text += "f";
    for (const std::uint32_t i : f) text += fmt::format(" {}", i + 1);
    text += "\n";
  }
  return text;
}

// Winding::Orient (the scenes' meshes): faces turned to agree across shared edges and outward,
// checked by the geometry (each face's normal against the direction from the solid's centre), not
// by the counts alone; the mesh as given otherwise.
TEST(MeshHygiene, OrientTurnsFacesToAgreeAndFaceOutward) {
  const std::vector<Vec3> v{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  const std::vector<std::vector<std::uint32_t>> outward{{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {2, 3, 7, 6}, {1, 2, 6, 5}, {0, 4, 7, 3}};
  const auto all_outward = [](const Mesh& mesh, Vec3 centre) {
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
      const std::vector<Vec3> p = face_positions(mesh, f);
      Vec3 mid{};
      for (const Vec3& q : p) mid = mid + q;
      if (!(dot(face_normal(mesh, f), mid * (1.0f / static_cast<float>(p.size())) - centre) > 0)) return false;
    }
    return true;
  };
  const auto clean_after = [](const MeshProblems& p) {
    EXPECT_EQ(p.inconsistent_edges, 0u);
    EXPECT_EQ(p.complex_faces, 0u);
    EXPECT_FALSE(p.inward);
  };
  // Inside out: every face turned.
  auto inward = outward;
  for (auto& f : inward) std::reverse(f.begin(), f.end());
  const std::string inside_out = temp_file("orient-inside-out.obj", obj_text(v, inward));
  EXPECT_TRUE(load_mesh(inside_out).problems.inward) << "as given by default";
  const Mesh turned = load_mesh(inside_out, Winding::Orient);
  EXPECT_EQ(turned.problems.turned_faces, 6u);
  clean_after(turned.problems);
  EXPECT_TRUE(all_outward(turned, {0.5f, 0.5f, 0.5f}));
  EXPECT_NE(turned.problems.summary().find("6 faces turned"), std::string::npos) << turned.problems.summary();
  // One face turned against its neighbours: that one back.
  auto one = outward;
  std::reverse(one[3].begin(), one[3].end());
  const Mesh fixed = load_mesh(temp_file("orient-one.obj", obj_text(v, one)), Winding::Orient);
  EXPECT_EQ(fixed.problems.turned_faces, 1u);
  clean_after(fixed.problems);
  EXPECT_TRUE(all_outward(fixed, {0.5f, 0.5f, 0.5f}));
  // A hollow shell (the inner cube faces into the cavity): nothing turned.
  const auto [hollow, shell] = hollow_cube(v, outward);
  EXPECT_EQ(load_mesh(temp_file("orient-hollow.obj", obj_text(hollow, shell)), Winding::Orient).problems.turned_faces, 0u);
  // An open strip of three quads, the middle one turned: it follows the majority (+z).
  const std::vector<Vec3> strip{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}, {0, 1, 0}, {1, 1, 0}, {2, 1, 0}, {3, 1, 0}};
  const Mesh open = load_mesh(temp_file("orient-strip.obj", obj_text(strip, {{0, 1, 5, 4}, {1, 5, 6, 2}, {2, 3, 7, 6}})), Winding::Orient);
  EXPECT_EQ(open.problems.turned_faces, 1u);
  clean_after(open.problems);
  for (std::size_t f = 0; f < open.face_count(); ++f) EXPECT_GT(face_normal(open, f).z, 0.0f) << f;
  // A sphere with a third of its faces turned at random, far from the origin: all outward again.
  const Mesh sphere = sphere_mesh(12, 16);
  std::vector<Vec3> far;
  for (const Vec3& p : sphere.vertices) far.push_back(p + Vec3{1e4f, -2e4f, 3e4f});
  std::vector<std::vector<std::uint32_t>> faces = splatcl::testing::face_lists(sphere);
  std::size_t reversed = 0;
  for (std::size_t f = 0; f < faces.size(); ++f)
    if ((f * 2654435761u) % 3 == 0) std::reverse(faces[f].begin(), faces[f].end()), ++reversed;
  const Mesh mixed = load_mesh(temp_file("orient-mixed.obj", obj_text(far, faces)), Winding::Orient);
  EXPECT_EQ(mixed.problems.turned_faces, reversed);
  clean_after(mixed.problems);
  EXPECT_TRUE(all_outward(mixed, {1e4f, -2e4f, 3e4f}));
}

// An open part keeps the winding of most of its area: a 10 x 10 plate wound +z beside a strip of
// four 1 x 2.5 quads wound -z (sharing the plate's edge, split at the quads' corners). By face count
// (the rule until 2026-12-08) the plate was turned to face -z with the strip.
TEST(MeshHygiene, OrientOpenPartKeepsTheWindingOfMostOfItsArea) {
  const std::vector<Vec3> v{{0, 0, 0},   {10, 0, 0},   {10, 2.5f, 0}, {10, 5, 0},   {10, 7.5f, 0},  {10, 10, 0}, {0, 10, 0},
                            {11, 0, 0},  {11, 2.5f, 0}, {11, 5, 0},   {11, 7.5f, 0}, {11, 10, 0}};
  const std::vector<std::vector<std::uint32_t>> faces{
      {0, 1, 2, 3, 4, 5, 6},                                       // the plate, counter-clockwise seen from +z
      {1, 2, 8, 7}, {2, 3, 9, 8}, {3, 4, 10, 9}, {4, 5, 11, 10}};  // the strip, clockwise
  const Mesh mesh = load_mesh(temp_file("orient-area.obj", obj_text(v, faces)), Winding::Orient);
  EXPECT_EQ(mesh.problems.turned_faces, 4u);
  EXPECT_EQ(mesh.problems.inconsistent_edges, 0u);
  for (std::size_t f = 0; f < mesh.face_count(); ++f) EXPECT_GT(face_normal(mesh, f).z, 0.0f) << f;
}

// A closed part that lies inside no other closed part faces outward, whatever the others enclose:
// an inside-out cube beside a larger outward one kept its inward faces (their volumes summed
// positive), so its splats faced into it. One inside another keeps the file's side (a cavity, or
// parts that overlap), and a hollow shell turned inside out as a whole is turned as a whole.
TEST(MeshHygiene, OrientTurnsAnInsideOutPartThatLiesInsideNoOther) {
  const std::vector<Vec3> v{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  const std::vector<std::vector<std::uint32_t>> outward{{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {2, 3, 7, 6}, {1, 2, 6, 5}, {0, 4, 7, 3}};
  // Cube `scale` · v + offset, facing out or in, appended.
  const auto add_cube = [&](std::vector<Vec3>& vertices, std::vector<std::vector<std::uint32_t>>& faces, float scale, Vec3 offset,
                            bool inside_out) {
    const auto base = static_cast<std::uint32_t>(vertices.size());
    for (const Vec3& p : v) vertices.push_back(scale * p + offset);
    for (auto f : outward) {
      if (inside_out) std::reverse(f.begin(), f.end());
      for (auto& i : f) i += base;
      faces.push_back(f);
    }
  };
  // Whether each face of cube `cube` (6 faces each, in order) points away from that cube's centre.
  const auto faces_out = [](const Mesh& mesh, std::size_t cube, Vec3 centre) {
    for (std::size_t f = 6 * cube; f < 6 * cube + 6; ++f) {
      const std::vector<Vec3> p = face_positions(mesh, f);
      if (!(dot(face_normal(mesh, f), p[0] + p[2] - 2.0f * centre) > 0)) return false;
    }
    return true;
  };
  const auto load = [&](const char* name, const std::vector<Vec3>& vertices, const std::vector<std::vector<std::uint32_t>>& faces) {
    return load_mesh(temp_file(name, obj_text(vertices, faces)), Winding::Orient);
  };
  {  // beside: the small one is turned
    std::vector<Vec3> vertices;
    std::vector<std::vector<std::uint32_t>> faces;
    add_cube(vertices, faces, 2, {0, 0, 0}, false);
    add_cube(vertices, faces, 1, {5, 0, 0}, true);
    const Mesh mesh = load("orient-beside.obj", vertices, faces);
    // Loaded as given it is warned, by the same rule (batch orients the faces only when warned).
    EXPECT_TRUE(make_mesh(vertices, faces, "beside").problems.inward);
    EXPECT_EQ(mesh.problems.turned_faces, 6u);
    EXPECT_TRUE(faces_out(mesh, 0, {1, 1, 1}));
    EXPECT_TRUE(faces_out(mesh, 1, {5.5f, 0.5f, 0.5f}));
  }
  {  // inside: a cavity's wall, kept facing into the cavity
    std::vector<Vec3> vertices;
    std::vector<std::vector<std::uint32_t>> faces;
    add_cube(vertices, faces, 4, {0, 0, 0}, false);
    add_cube(vertices, faces, 1, {1.3f, 1.2f, 1.1f}, true);
    const Mesh mesh = load("orient-cavity.obj", vertices, faces);
    EXPECT_FALSE(make_mesh(vertices, faces, "cavity").problems.any());
    EXPECT_EQ(mesh.problems.turned_faces, 0u);
    EXPECT_FALSE(faces_out(mesh, 1, {1.8f, 1.7f, 1.6f}));
  }
  {  // a cavity whose top lies in the outer cube's top face (separate vertices): kept, and not warned
    std::vector<Vec3> vertices;
    std::vector<std::vector<std::uint32_t>> faces;
    add_cube(vertices, faces, 4, {0, 0, 0}, false);
    add_cube(vertices, faces, 2, {1, 1, 2}, true);
    EXPECT_FALSE(make_mesh(vertices, faces, "touching cavity").problems.any()) << make_mesh(vertices, faces, "touching cavity").problems.summary();
    EXPECT_EQ(load("orient-touching-cavity.obj", vertices, faces).problems.turned_faces, 0u);
  }
  {  // a correct hollow cube beside a larger inside-out cube: only the inside-out one is turned (all
     // three parts' volumes together are negative; turning them all left the cavity facing out)
    const auto [hollow, shell] = hollow_cube(v, outward);
    std::vector<Vec3> vertices = hollow;
    std::vector<std::vector<std::uint32_t>> faces = shell;
    add_cube(vertices, faces, 3, {5, 0, 0}, true);
    const Mesh mesh = load("orient-hollow-beside.obj", vertices, faces);
    EXPECT_EQ(mesh.problems.turned_faces, 6u);
    EXPECT_TRUE(faces_out(mesh, 0, {0.5f, 0.5f, 0.5f}));
    EXPECT_FALSE(faces_out(mesh, 1, {0.5f, 0.5f, 0.5f}));
    EXPECT_TRUE(faces_out(mesh, 2, {6.5f, 1.5f, 1.5f}));
  }
  {  // an inside-out tetrahedron alone (few faces: its test points beside distinct faces)
    const std::vector<Vec3> corners{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    const Mesh mesh = load("orient-tetrahedron.obj", corners, {{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 3, 2}});
    EXPECT_EQ(mesh.problems.turned_faces, 4u);
  }
  {  // the hollow cube inside out as a whole: both shells turned, the cavity's wall faces into it again
    const auto [hollow, shell] = hollow_cube(v, outward);
    auto reversed = shell;
    for (auto& f : reversed) std::reverse(f.begin(), f.end());
    const Mesh mesh = load("orient-hollow-inverted.obj", hollow, reversed);
    EXPECT_EQ(mesh.problems.turned_faces, 12u);
    EXPECT_TRUE(faces_out(mesh, 0, {0.5f, 0.5f, 0.5f}));
    EXPECT_FALSE(faces_out(mesh, 1, {0.5f, 0.5f, 0.5f}));
  }
}

// Polygons every consumer fans from their first corner: a concave one is split by ear clipping, so
// its triangles cover exactly its area (a fan of the L covered the notch: 165 of 872 splats stood
// there, up to 175 ε off the surface), with the polygon's winding; convex ones stay whole.
TEST(MeshHygiene, ConcavePolygonsAreSplitInsideTheirOutline) {
  const auto area_and_facing = [](const Mesh& mesh) {
    double area = 0;
    bool up = true;
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
      const Vec3 n = face_normal(mesh, f);
      area += 0.5 * std::sqrt(double{dot(n, n)});
      up = up && n.z > 0;
    }
    return std::pair{area, up};
  };
  // The L: (0,0)-(2,0)-(2,1)-(1,1)-(1,2)-(0,2), area 3, listed from a reflex corner's neighbour.
  const std::vector<Vec3> l{{2, 1, 0}, {1, 1, 0}, {1, 2, 0}, {0, 2, 0}, {0, 0, 0}, {2, 0, 0}};
  const Mesh ell = make_mesh(l, {{0, 1, 2, 3, 4, 5}}, "L");
  EXPECT_EQ(ell.problems.split_polygons, 1u);
  EXPECT_FALSE(ell.problems.any());
  EXPECT_EQ(ell.face_count(), 4u);
  const auto [ell_area, ell_up] = area_and_facing(ell);
  EXPECT_NEAR(ell_area, 3.0, 1e-6);
  EXPECT_TRUE(ell_up);
  for (std::size_t f = 0; f < ell.face_count(); ++f) {
    Vec3 mid{};
    for (const Vec3& p : face_positions(ell, f)) mid = mid + p * (1.0f / 3.0f);
    EXPECT_FALSE(mid.x > 1 && mid.y > 1) << "triangle " << f << " in the notch";
  }
  // A five-pointed star as one 10-gon, through a file: area of the star, every triangle facing +z.
  std::vector<Vec3> star;
  for (int k = 0; k < 10; ++k) {
    const double angle = std::numbers::pi * k / 5, r = k % 2 ? 0.4 : 1.0;
    star.push_back({static_cast<float>(r * std::cos(angle)), static_cast<float>(r * std::sin(angle)), 0.0f});
  }
  const Mesh star_mesh = load_mesh(temp_file("star.obj", obj_text(star, {{0, 1, 2, 3, 4, 5, 6, 7, 8, 9}})));
  EXPECT_EQ(star_mesh.problems.split_polygons, 1u);
  EXPECT_EQ(star_mesh.face_count(), 8u);
  double star_area = 0;
  for (int k = 0; k < 10; ++k) star_area += 0.5 * std::fabs(double{star[k].x} * star[(k + 1) % 10].y - double{star[(k + 1) % 10].x} * star[k].y);
  const auto [area, up] = area_and_facing(star_mesh);
  EXPECT_NEAR(area, star_area, 1e-5);
  EXPECT_TRUE(up);
  // Convex polygons (and a convex one with a corner on an edge) stay one face.
  const Mesh quad = make_mesh({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {2, 1, 0}, {0, 1, 0}}, {{0, 1, 2, 3, 4}}, "pentagon");
  EXPECT_EQ(quad.problems.split_polygons, 0u);
  EXPECT_EQ(quad.face_count(), 1u);
}

// A convex quad whose corners alternate in height is two triangles folded along the fan's
// diagonal, and every stage fans it: split into that fan when a triangle stands more than 30° off
// the quad's normal, so its normals are the triangles' (the crease angle keeps a sharp fold sharp).
// Kept whole, a grid of them was shaded flat with the quad's normal: its corner normals all lay 60°
// off the surface. A nearly planar quad stays whole.
TEST(MeshHygiene, StronglyNonPlanarPolygonsAreSplitIntoTheirFan) {
  const Mesh folded = make_mesh({{0, 0, 0}, {1, 0, 1}, {1, 1, 0}, {0, 1, 1}}, {{0, 1, 2, 3}}, "folded quad");
  EXPECT_EQ(folded.problems.split_polygons, 1u);
  EXPECT_FALSE(folded.problems.any());
  ASSERT_EQ(folded.face_count(), 2u);
  const std::vector<Vec3> first = face_positions(folded, 0), second = face_positions(folded, 1);
  EXPECT_EQ(first, (std::vector<Vec3>{{0, 0, 0}, {1, 0, 1}, {1, 1, 0}}));  // the fan (0 1 2), (0 2 3)
  EXPECT_EQ(second, (std::vector<Vec3>{{0, 0, 0}, {1, 1, 0}, {0, 1, 1}}));
  const Mesh nearly = make_mesh({{0, 0, 0}, {1, 0, 0.1f}, {1, 1, 0}, {0, 1, 0.1f}}, {{0, 1, 2, 3}}, "nearly planar quad");
  EXPECT_EQ(nearly.problems.split_polygons, 0u);
  EXPECT_EQ(nearly.face_count(), 1u);
  // The grid: every corner normal (what samples and Phong splats interpolate) against its
  // triangle's own normal.
  const Mesh grid = non_planar_quads_mesh(8, 0.3f);
  const std::vector<Vec3> corner = corner_normals(grid, 60.0f);
  double worst = 0, sum = 0;
  std::size_t count = 0;
  for (std::size_t f = 0; f < grid.face_count(); ++f) {
    const std::vector<Vec3> p = face_positions(grid, f);
    ASSERT_EQ(p.size(), 3u) << "face " << f << " kept whole";
    const Vec3 own = normalized(cross(p[1] - p[0], p[2] - p[0]));
    for (std::uint32_t c = grid.face_offsets[f]; c < grid.face_offsets[f + 1]; ++c) {
      const double angle = std::acos(std::clamp(double{dot(normalized(corner[c]), own)}, -1.0, 1.0)) * 180 / std::numbers::pi;
      worst = std::max(worst, angle), sum += angle, ++count;
    }
  }
  fmt::print("folded quads: corner normals {:.1f}° off their triangle on average, {:.1f}° at most\n", sum / static_cast<double>(count), worst);
  EXPECT_LT(sum / static_cast<double>(count), 20.0);
  EXPECT_LT(worst, 45.0);
}

// A self-intersecting polygon whose halves turn opposite ways has no Newell normal, but its fan
// has area: it was kept whole and called zero-area, and got no splats (a helper's audit: half of
// the surface uncovered while both checks passed). Flat and twisted, it is split into its fan.
TEST(MeshHygiene, BowtiePolygonsAreSplitIntoTheirFan) {
  const Mesh flat = make_mesh({{1, 0, 0}, {2, 0, 0}, {1, 1, 0}, {2, 1, 0}}, {{0, 1, 2, 3}}, "bowtie");
  EXPECT_EQ(flat.problems.zero_area_faces, 0u);
  EXPECT_EQ(flat.problems.split_polygons, 1u);
  ASSERT_EQ(flat.face_count(), 2u);
  EXPECT_EQ(face_positions(flat, 0), (std::vector<Vec3>{{1, 0, 0}, {2, 0, 0}, {1, 1, 0}}));
  EXPECT_EQ(face_positions(flat, 1), (std::vector<Vec3>{{1, 0, 0}, {1, 1, 0}, {2, 1, 0}}));
  const Mesh twisted = make_mesh({{0, 0, 0}, {1, 1, 0.3f}, {1, 0, 0}, {0, 1, 0.3f}}, {{0, 1, 2, 3}}, "twisted bowtie");
  EXPECT_EQ(twisted.problems.zero_area_faces, 0u);
  EXPECT_EQ(twisted.face_count(), 2u);
  // A polygon whose fan has no area either stays one zero-area face.
  const Mesh line = make_mesh({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}}, {{0, 1, 2, 3}}, "collinear");
  EXPECT_EQ(line.problems.zero_area_faces, 1u);
  EXPECT_EQ(line.face_count(), 1u);
}

TEST(MeshHygiene, MakeMeshCountsDegenerateAndZeroAreaFaces) {
  const std::vector<Vec3> v{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {2, 0, 0}, {5, 5, 5}, {NAN, 0, 0}};
  const Mesh mesh = make_mesh(v,
                              {{0, 1, 2},        // good
                               {0, 1, 1},        // two distinct corners: dropped
                               {0, 1},           // two corners: dropped
                               {0, 1, 0, 2},     // a corner repeated apart: dropped
                               {1, 3, 4, 4, 1},  // repeats next to each other (cyclically) merged: the triangle 1 3 4
                               {3, 1, 0},        // collinear: zero area, kept
                               {0, 2, 7},        // out of range: dropped
                               {0, 5, 2}},       // non-finite vertex: dropped
                              "degenerate");
  EXPECT_EQ(mesh.face_count(), 3u);
  expect_only(mesh.problems, 1, 0, 1, 1, 3, 1);
  EXPECT_EQ(mesh.problems.faces_listed, 8u);
  EXPECT_EQ(mesh.problems.dropped_faces(), 5u);
  EXPECT_EQ(face_positions(mesh, 1).size(), 3u);
  EXPECT_EQ(mesh.problems.summary(),
            "1 vertex with a non-finite coordinate (nan, inf or beyond float range), 1 face using such vertices dropped, 1 face with an "
            "index out of range or unreadable dropped, 3 degenerate faces (fewer than 3 distinct corners) dropped, 1 zero-area face kept (no surface to sample)");
  // Nothing usable left: one line saying why.
  try {
    make_mesh({{0, 0, 0}, {1, 0, 0}}, {{0, 1, 1}, {0, 1, 2}}, "hopeless");
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(),
                 "hopeless: the mesh has no faces left: all 2 faces were dropped (1 face with an index out of range or unreadable dropped, 1 degenerate "
                 "face (fewer than 3 distinct corners) dropped)");
  }
}

// A box whose six faces are each meshed on their own, into grids of different sizes with their own
// vertices (a CAD part exported face by face): along the box's edges the vertices of one face lie on
// the other face's edges (T-junctions), so no edge is shared, yet the surface is closed. It was taken
// as open (drawn two-sided at twice the cost, with specks of the inside along its outline, and its
// CSM with the open meshes' rule). Without a face, or with one face's grid short of an edge, it is
// open.
TEST(MeshHygiene, FacesMeshedOnTheirOwnCloseAlongTJunctions) {
  const auto box = [](int skip_face, float shrink) {
    std::vector<Vec3> vertices;
    std::vector<std::vector<std::uint32_t>> faces;
    // Face f: an n × n grid on a side of the unit cube, outward.
    const Vec3 origins[6] = {{0, 0, 0}, {0, 0, 1}, {0, 0, 0}, {0, 1, 0}, {0, 0, 0}, {1, 0, 0}};
    const Vec3 us[6] = {{0, 1, 0}, {1, 0, 0}, {1, 0, 0}, {0, 0, 1}, {0, 0, 1}, {0, 1, 0}};
    const Vec3 vs[6] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (int f = 0; f < 6; ++f) {
      if (f == skip_face) continue;
      const int n = 2 + f;  // 2 to 7 cells a side: the grids meet at T-junctions
      const auto first = static_cast<std::uint32_t>(vertices.size());
      for (int i = 0; i <= n; ++i)
        for (int k = 0; k <= n; ++k) {
          const float u = static_cast<float>(i) / static_cast<float>(n), v = static_cast<float>(k) / static_cast<float>(n) * (f == 0 ? shrink : 1.0f);
          vertices.push_back(origins[f] + us[f] * u + vs[f] * v);
        }
      for (int i = 0; i < n; ++i)
        for (int k = 0; k < n; ++k) {
          const auto at = [&](int a, int b) { return first + static_cast<std::uint32_t>(a * (n + 1) + b); };
          faces.push_back({at(i, k), at(i + 1, k), at(i + 1, k + 1), at(i, k + 1)});
        }
    }
    return make_mesh(vertices, faces, "box of separate faces");
  };
  const Mesh whole = box(-1, 1.0f);
  EXPECT_TRUE(whole.closed());
  Mesh moved = whole;
  for (Vec3& p : moved.vertices) p = p * 0.3719f + Vec3{1234.5678f, -0.1f, 7.77f};
  EXPECT_TRUE(moved.closed()) << "T-junction corners moved off their edges by float rounding";
  EXPECT_FALSE(box(3, 1.0f).closed()) << "a face missing";
  EXPECT_FALSE(box(-1, 0.99f).closed()) << "a face short of its edge by 1 %";
  EXPECT_FALSE(box(-1, 0.99999f).closed()) << "a face short of its edge by 1e-5";
  // A part 1000 large, closed along its T-junctions, and a separate small open triangle: open (a
  // tolerance from the largest coordinate anywhere let the triangle's short edges pass; an audit).
  {
    std::vector<Vec3> vertices = moved.vertices;
    for (Vec3& p : vertices) p = p * 1000.0f;
    std::vector<std::vector<std::uint32_t>> faces = splatcl::testing::face_lists(moved);
    const auto first = static_cast<std::uint32_t>(vertices.size());
    vertices.insert(vertices.end(), {{1, 1, 1}, {1.0009f, 1, 1}, {1, 1.0009f, 1}});
    faces.push_back({first, first + 1, first + 2});
    EXPECT_FALSE(make_mesh(vertices, faces, "part and a stray triangle").closed());
  }
  // A slanted edge of a tetrahedron split into 48 pieces on one side only: closed (a piece's own
  // direction, off by its rounding over its short length, missed the long edge's far end; an audit).
  const Vec3 a{0, 0, 0}, b{3, 1, 0.7f}, c{0.2f, 3, 0.1f}, d{0.1f, 0.3f, 3};
  std::vector<Vec3> tetra{a, b, c, d};
  std::vector<std::vector<std::uint32_t>> fan{{0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  for (int k = 1; k < 48; ++k) tetra.push_back(a + (b - a) * (static_cast<float>(k) / 48.0f));
  for (std::uint32_t k = 0; k < 48; ++k) fan.push_back({2, k == 0 ? 0u : 3 + k, k == 47 ? 1u : 4 + k});
  EXPECT_TRUE(make_mesh(tetra, fan, "tetrahedron with a split edge").closed());
  // The same scaled by 1000 beside a small open triangle (0.01 long, 0.004 high, not zero-area) lying
  // 2e-3 from its split edge's line: open (1e-6 of the long edge's length, 3.2e-3, let the
  // triangle's edges lie "along" it; a review).
  {
    std::vector<Vec3> vertices = tetra;
    for (Vec3& p : vertices) p = p * 1000.0f;
    const Vec3 along = (b - a) * (1.0f / length(b - a)), across = Vec3{1, -3, 0} * (1.0f / std::sqrt(10.0f));
    const Vec3 on_line = (a + (b - a) * 0.4f) * 1000.0f;
    const auto first = static_cast<std::uint32_t>(vertices.size());
    vertices.insert(vertices.end(), {on_line - across * 2e-3f, on_line + along * 0.01f - across * 2e-3f, on_line + along * 0.005f + across * 2e-3f});
    auto faces = fan;
    faces.push_back({first, first + 1, first + 2});
    EXPECT_TRUE(make_mesh(std::vector<Vec3>(vertices.begin(), vertices.begin() + first), fan, "large split tetrahedron").closed());
    const Mesh beside = make_mesh(vertices, faces, "large split tetrahedron and a small triangle by its edge");
    EXPECT_EQ(beside.problems.zero_area_faces, 0u);
    EXPECT_FALSE(beside.closed());
  }
  fan.pop_back();
  EXPECT_FALSE(make_mesh(tetra, fan, "tetrahedron with a split edge and a piece missing").closed());
  // A face listing one position twice (A, B, C, C' with C' at C) leaves only a zero-length border
  // edge: no crack, closed (it was open unless a T-junction elsewhere came with it).
  std::vector<Vec3> quad_tetra{a, b, c, d, c};
  EXPECT_TRUE(make_mesh(quad_tetra, {{0, 1, 2, 4}, {0, 3, 1}, {1, 3, 2}, {0, 2, 3}}, "tetrahedron with a doubled corner").closed());
}

// Faces that meet at one position are neighbours whether or not the file gives them one vertex
// index there (triangle soups, UV and normal splits): a soup sphere is closed (the presenter drew
// it two-sided, twice the splats), and orienting a soup with turned faces turns them back. A
// zero-area face laid along an edge of a closed mesh leaves it closed, also after a float
// transform has moved its collinear corners off their line (the scene's fit); one filling a crack
// is needed to close it. Parts that touch, each with its own vertices, stay closed parts.
TEST(MeshHygiene, ClosedAndOrientedByPositionWhereFilesRepeatVertices) {
  const Mesh sphere = sphere_mesh(12, 16);
  ASSERT_TRUE(sphere.closed());
  std::vector<Vec3> soup;
  std::vector<std::vector<std::uint32_t>> soup_faces, turned_faces;
  std::size_t reversed = 0;
  for (std::size_t f = 0; f < sphere.face_count(); ++f) {
    std::vector<std::uint32_t> face;
    for (std::uint32_t c = sphere.face_offsets[f]; c < sphere.face_offsets[f + 1]; ++c) {
      face.push_back(static_cast<std::uint32_t>(soup.size()));
      soup.push_back(sphere.vertices[sphere.corners[c]]);
    }
    soup_faces.push_back(face);
    if ((f * 2654435761u) % 3 == 0) std::reverse(face.begin(), face.end()), ++reversed;
    turned_faces.push_back(face);
  }
  EXPECT_TRUE(make_mesh(soup, soup_faces, "soup").closed());
  auto open_faces = soup_faces;
  open_faces.pop_back();
  EXPECT_FALSE(make_mesh(soup, open_faces, "soup with a hole").closed());
  const Mesh oriented = load_mesh(temp_file("orient-soup.obj", obj_text(soup, turned_faces)), Winding::Orient);
  EXPECT_EQ(oriented.problems.turned_faces, reversed);
  EXPECT_EQ(oriented.problems.inconsistent_edges, 0u);
  for (std::size_t f = 0; f < oriented.face_count(); ++f) {
    Vec3 mid{};
    for (const Vec3& p : face_positions(oriented, f)) mid = mid + p;
    EXPECT_GT(dot(face_normal(oriented, f), mid), 0.0f) << f;
  }

  // The unit cube as triangles, then a zero-area triangle on its edge 0-1 through the midpoint 8.
  std::vector<Vec3> cube{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}, {0.5f, 0, 0}};
  std::vector<std::vector<std::uint32_t>> triangles{{0, 3, 2}, {0, 2, 1}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                                                    {2, 3, 7}, {2, 7, 6}, {1, 2, 6}, {1, 6, 5}, {0, 4, 7}, {0, 7, 3}};
  ASSERT_TRUE(make_mesh(cube, triangles, "cube").closed());
  auto sliver = triangles;
  sliver.push_back({0, 1, 8});
  const Mesh with_sliver = make_mesh(cube, sliver, "cube and a sliver");
  EXPECT_EQ(with_sliver.problems.zero_area_faces, 1u);
  EXPECT_TRUE(with_sliver.closed());
  Mesh moved = with_sliver;
  for (Vec3& p : moved.vertices) p = p * 0.3719f + Vec3{1234.5678f, -0.1f, 7.77f};
  EXPECT_TRUE(moved.closed()) << "collinear corners moved by float rounding";
  // The bottom's edge 0-1 split at 8 on one side only (a T-junction): closed, with the zero-area
  // face 0 8 1 filling the crack or without it (the edges 0-8 and 8-1 cover the edge 0-1).
  auto crack = triangles;
  crack[1] = {0, 2, 8};
  crack.push_back({8, 2, 1});
  EXPECT_TRUE(make_mesh(cube, crack, "cube with a T-junction").closed());
  crack.push_back({0, 8, 1});
  EXPECT_TRUE(make_mesh(cube, crack, "cube with a filled crack").closed());

  // Two cubes, each with its own vertices, stacked (touching along a face) or touching along an
  // edge: matched by position alone, the touching edges had four uses, so the pair was open, warned
  // of inconsistent edges, and an inside-out one was not turned. Edges two faces share by index stay
  // matched by index.
  for (const Vec3 offset : {Vec3{0, 0, 1}, Vec3{1, 0, 1}}) {
    std::vector<Vec3> two(cube.begin(), cube.begin() + 8);
    for (std::size_t k = 0; k < 8; ++k) two.push_back(cube[k] + offset);
    auto both = triangles;
    for (auto face : triangles) {
      for (auto& i : face) i += 8;
      both.push_back(face);
    }
    const Mesh touching = make_mesh(two, both, "touching cubes");
    EXPECT_TRUE(touching.closed()) << offset.x;
    EXPECT_EQ(touching.problems.inconsistent_edges, 0u) << offset.x;
    EXPECT_FALSE(touching.problems.any()) << touching.problems.summary();
    auto inside_out = both;
    for (std::size_t f = 0; f < triangles.size(); ++f) std::reverse(inside_out[f].begin(), inside_out[f].end());
    const Mesh turned = load_mesh(temp_file("orient-touching.obj", obj_text(two, inside_out)), Winding::Orient);
    EXPECT_EQ(turned.problems.turned_faces, triangles.size()) << offset.x;
    EXPECT_EQ(turned.problems.complex_faces, 0u) << offset.x;
  }
}

TEST(MeshHygiene, SharedModelsAreClean) {
  for (const char* name : {"stanford-bunny.obj", "spot.obj", "fandisk.obj"}) {
    const std::string path = model_path(name);
    if (path.empty()) GTEST_SKIP() << "test models not found in " << SPLATCL_MODELS_DIR;
    const Mesh mesh = load_mesh(path);
    EXPECT_FALSE(mesh.problems.any()) << name << ": " << mesh.problems.summary();
  }
  const std::string ogre = model_path("ogre.obj");
  if (!ogre.empty()) {
    EXPECT_EQ(load_mesh(ogre).problems.summary(), "4 zero-area faces kept (no surface to sample)");
  }
}

}  // namespace
}  // namespace splatcl::splats
