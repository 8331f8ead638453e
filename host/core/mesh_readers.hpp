#pragma once
// The file readers behind load_mesh (core/mesh.hpp): OBJ, OFF, PLY and STL parsed into a polygon
// soup exactly as listed, so that the loader can count what is wrong instead of OpenMesh's readers
// misreading it. Internal to mesh.cpp, the 3D Gaussian Splatting reader and their tests.
#include <array>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

#include "core/mesh.hpp"
#include "math/dvec3.hpp"

namespace splatcl::mesh_io {

struct RawMesh {
  std::vector<Vec3> positions;
  std::vector<DVec3> exact_positions;        // per vertex as the file has it, in double (positions: rounded)
  std::vector<std::uint8_t> bad_vertex;      // per vertex: 1 where its coordinates are not three finite floats
  std::vector<Vec3> normals;                 // per vertex from the file; empty when it has none
  std::vector<std::uint8_t> has_normal;      // per vertex, beside normals
  std::vector<std::int64_t> corners;         // 0-based vertex index per face corner as listed; may be out of range
  std::vector<std::size_t> face_offsets{0};  // face f = corners [face_offsets[f], face_offsets[f+1])
  std::vector<std::array<float, 2>> corner_texcoords;  // per corner; empty when the file has none
  MeshProblems problems;                     // what the reader counted (the vertex kinds)
  // The format stores coordinates as 32-bit floats (binary STL, binary PLY with float x, y or z):
  // far from the origin, detail finer than their step there was lost in the file itself.
  bool float_coordinates = false;

  std::size_t face_count() const { return face_offsets.size() - 1; }
  void add_vertex(Vec3 p, bool bad) { add_vertex(bad ? DVec3{} : DVec3(p), p, bad); }
  // `exact`: the file's coordinates before they were rounded to `p`.
  void add_vertex(DVec3 exact, Vec3 p, bool bad) {
    positions.push_back(bad ? Vec3{} : p);
    exact_positions.push_back(bad ? DVec3{} : exact);
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

// ---- PLY, shared by the mesh reader and the 3D Gaussian Splatting reader (splats/gaussian_file.hpp)

enum class PlyType : std::uint8_t { I8, U8, I16, U16, I32, U32, F32, F64 };

bool ply_type(std::string_view name, PlyType& type);

std::size_t size_of(PlyType t);

struct PlyProperty {
  std::string name;
  bool list = false;
  PlyType count_type = PlyType::U8, type = PlyType::F32;
};

struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::vector<PlyProperty> properties;
  int find(std::string_view n) const {
    for (std::size_t i = 0; i < properties.size(); ++i)
      if (properties[i].name == n) return static_cast<int>(i);
    return -1;
  }
};

enum class PlyFormat { Ascii, BinaryLittle, BinaryBig };

// The values after end_header, one at a time in the file's encoding.
class PlyBody {
 public:
  enum Result { Ok, Malformed, End };
  PlyBody(std::string_view body, PlyFormat format) : body_(body), format_(format) {}

  Result next(PlyType type, double& value);
  // After a record: in ASCII, the rest of its line must be blank (Malformed otherwise), and the next
  // record starts on the next line. Read as one stream of values, a line with a value too many or too
  // few shifted every later record: a 3DGS file with two extra values on one line drew a spindle
  // with exit 0. Binary records have no lines: always Ok.
  Result end_record();
  // A list property's length: Malformed when it is not a count (negative, fractional, unreadable),
  // End when the rest of the body cannot hold that many values of `type` (so a float count beyond
  // any integer allocates nothing).
  Result next_count(PlyType count_type, PlyType type, std::uint64_t& count);
  // Reads a list property's length and values, keeping nothing (a property no reader uses).
  Result skip_list(PlyType count_type, PlyType type);
  std::size_t remaining() const { return body_.size() - pos_; }
  bool binary() const { return format_ != PlyFormat::Ascii; }

 private:
  static double decode(PlyType type, const unsigned char* b) {
    switch (type) {
      case PlyType::I8: return static_cast<std::int8_t>(b[0]);
      case PlyType::U8: return b[0];
      case PlyType::I16: return copy<std::int16_t>(b);
      case PlyType::U16: return copy<std::uint16_t>(b);
      case PlyType::I32: return copy<std::int32_t>(b);
      case PlyType::U32: return copy<std::uint32_t>(b);
      case PlyType::F32: return copy<float>(b);
      case PlyType::F64: return copy<double>(b);
    }
    return 0;
  }
  template <typename T>
  static T copy(const unsigned char* b) {
    T v;
    std::memcpy(&v, b, sizeof v);
    return v;
  }
  std::string_view body_;
  PlyFormat format_;
  std::size_t pos_ = 0;
};

// A PLY header: format, elements with their properties, and the bytes after end_header.
struct PlyHeader {
  PlyFormat format = PlyFormat::Ascii;
  std::vector<PlyElement> elements;
  std::string_view body;  // into the text given to parse_ply_header
};

// Parses the header of the PLY `text`, refusing a missing end_header, an unknown format or type,
// and element counts the bytes after end_header cannot hold. Errors read "cannot read WHAT PATH: ...".
PlyHeader parse_ply_header(const std::string& path, std::string_view text, const char* what);

// The number in all of `token` ("1.5", "-2e3", "+4", "nan", "inf"); false when it is not one.
// Values beyond double range become ±inf (or 0 when too small), as strtod gives them.
bool parse_number(std::string_view token, double& value);

}  // namespace splatcl::mesh_io
