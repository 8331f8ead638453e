// The 3DGS export (splats/gaussian_file.hpp), read back by a minimal binary-PLY parser written here
// from the PLY format alone, knowing nothing of splatcl's writer: header lines, the property list,
// then the floats. Each Gaussian is checked against its splat: position, normal, σ per axis, unit
// quaternion whose rotation maps x, y, z onto the splat's u, ±v, n, colour and opacity.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <numbers>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "runtime/error.hpp"
#include "splats/gaussian_file.hpp"
#include "splats/pipeline.hpp"
#include "splats_test_support.hpp"

namespace splatcl::splats {
namespace {

using testing::temp_path;

// ---- An independent binary little-endian PLY reader (float properties of one element) ----

struct Ply {
  std::string format;
  std::string element;
  std::size_t count = 0;
  std::vector<std::string> types, names;
  std::vector<float> values;  // count × names.size()
  float at(std::size_t row, const std::string& name) const {
    for (std::size_t p = 0; p < names.size(); ++p)
      if (names[p] == name) return values[row * names.size() + p];
    ADD_FAILURE() << "no property " << name;
    return NAN;
  }
};

Ply read_ply(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  EXPECT_TRUE(in) << path;
  const std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  Ply ply;
  std::size_t pos = 0;
  auto next_line = [&] {
    const std::size_t end = data.find('\n', pos);
    if (end == std::string::npos) throw std::runtime_error("header not terminated");
    std::string line = data.substr(pos, end - pos);
    pos = end + 1;
    return line;
  };
  if (next_line() != "ply") throw std::runtime_error("no ply magic");
  for (std::string line; (line = next_line()) != "end_header";) {
    std::istringstream words(line);
    std::string keyword;
    words >> keyword;
    if (keyword == "format") {
      std::string version;
      words >> ply.format >> version;
      if (version != "1.0") throw std::runtime_error("format version " + version);
    } else if (keyword == "element") {
      if (!ply.element.empty()) throw std::runtime_error("more than one element");
      words >> ply.element >> ply.count;
    } else if (keyword == "property") {
      std::string type, name;
      words >> type >> name;
      ply.types.push_back(type);
      ply.names.push_back(name);
    } else if (keyword != "comment" && keyword != "obj_info") {
      throw std::runtime_error("unknown header line: " + line);
    }
  }
  for (const std::string& type : ply.types)
    if (type != "float" && type != "float32") throw std::runtime_error("property type " + type);
  const std::size_t floats = ply.count * ply.names.size();
  if (data.size() - pos != floats * 4) throw std::runtime_error("body is " + std::to_string(data.size() - pos) + " bytes");
  ply.values.resize(floats);
  for (std::size_t i = 0; i < floats; ++i) {
    const auto* b = reinterpret_cast<const unsigned char*>(data.data() + pos + 4 * i);
    const std::uint32_t bits = std::uint32_t{b[0]} | std::uint32_t{b[1]} << 8 | std::uint32_t{b[2]} << 16 | std::uint32_t{b[3]} << 24;
    std::memcpy(&ply.values[i], &bits, 4);
  }
  return ply;
}

// ---- Helpers in double ----

struct V {
  double x, y, z;
};
V v(Vec3 a) { return {a.x, a.y, a.z}; }
double dot3(V a, V b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
V cross3(V a, V b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
V unit(V a) {
  const double l = std::sqrt(dot3(a, a));
  return {a.x / l, a.y / l, a.z / l};
}
Vec3 f3(V a) { return {static_cast<float>(a.x), static_cast<float>(a.y), static_cast<float>(a.z)}; }
double distance3(V a, V b) { return std::sqrt(dot3({a.x - b.x, a.y - b.y, a.z - b.z}, {a.x - b.x, a.y - b.y, a.z - b.z})); }

// p' = p + 2w (q × p) + 2 q × (q × p), q = (w, x, y, z) a unit quaternion.
V rotate(const double q[4], V p) {
  const V r{q[1], q[2], q[3]};
  const V t = cross3(r, p);
  const V t2 = cross3(r, t);
  return {p.x + 2 * q[0] * t.x + 2 * t2.x, p.y + 2 * q[0] * t.y + 2 * t2.y, p.z + 2 * q[0] * t.z + 2 * t2.z};
}

const std::vector<std::string> kExpectedNames = {"x",       "y",       "z",       "nx",      "ny",      "nz",
                                                 "f_dc_0",  "f_dc_1",  "f_dc_2",  "opacity", "scale_0", "scale_1",
                                                 "scale_2", "rot_0",   "rot_1",   "rot_2",   "rot_3"};

// Every property of row i against splat s.
void check_gaussian(const Ply& ply, std::size_t i, const SplatRecord& s) {
  SCOPED_TRACE("splat " + std::to_string(i));
  EXPECT_EQ(ply.at(i, "x"), s.center.x);
  EXPECT_EQ(ply.at(i, "y"), s.center.y);
  EXPECT_EQ(ply.at(i, "z"), s.center.z);
  const V n = unit(v(s.normal)), u = unit(v(s.major)), minor = unit(v(s.minor));
  const V file_n{ply.at(i, "nx"), ply.at(i, "ny"), ply.at(i, "nz")};
  EXPECT_LT(distance3(file_n, n), 1e-6);

  // σ_u = major / 2, σ_v = minor / 2, σ_n = 10⁻³ σ_v.
  const double major_len = std::sqrt(dot3(v(s.major), v(s.major))), minor_len = std::sqrt(dot3(v(s.minor), v(s.minor)));
  const double s0 = std::exp(double{ply.at(i, "scale_0")}), s1 = std::exp(double{ply.at(i, "scale_1")}),
               s2 = std::exp(double{ply.at(i, "scale_2")});
  // Relative 1e-5: a float ln σ is exact to |ln σ| · 2⁻²⁴ (σ_n ≈ 1e-9 here: 1.2e-6).
  EXPECT_NEAR(s0, major_len / 2, 1e-5 * major_len / 2);
  EXPECT_NEAR(s1, minor_len / 2, 1e-5 * minor_len / 2);
  EXPECT_NEAR(s2, 1e-3 * minor_len / 2, 1e-5 * 1e-3 * minor_len / 2);
  EXPECT_GT(s2, 0.0);

  double q[4] = {ply.at(i, "rot_0"), ply.at(i, "rot_1"), ply.at(i, "rot_2"), ply.at(i, "rot_3")};
  EXPECT_NEAR(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3], 1.0, 1e-6);
  EXPECT_GE(q[0], 0.0);
  const V rx = rotate(q, {1, 0, 0}), ry = rotate(q, {0, 1, 0}), rz = rotate(q, {0, 0, 1});
  EXPECT_LT(distance3(rx, u), 1e-5) << "x ↦ u";
  EXPECT_LT(distance3(rz, n), 1e-5) << "z ↦ n";
  // y ↦ ±v: (u, v, n) may be left-handed (the fit's orientation test), a rotation cannot be, and
  // the Gaussian is the same either way; the file's y axis is n × u.
  EXPECT_LT(distance3(ry, cross3(n, u)), 1e-5) << "y ↦ n × u";
  EXPECT_LT(std::fabs(std::fabs(dot3(ry, minor)) - 1.0), 1e-5) << "y ↦ ±v";

  // Colour: rgb = 0.5 + C0 f_dc, as viewers decode it.
  const double C0 = 0.28209479177387814;
  const std::uint8_t rgb[3] = {s.color.r, s.color.g, s.color.b};
  for (int c = 0; c < 3; ++c) {
    const double decoded = 255.0 * (0.5 + C0 * ply.at(i, "f_dc_" + std::to_string(c)));
    EXPECT_NEAR(decoded, rgb[c], 1.0 / 255.0) << "channel " << c;
  }
  // Opacity: sigmoid(stored) = α = 0.99.
  EXPECT_NEAR(1.0 / (1.0 + std::exp(-double{ply.at(i, "opacity")})), 0.99, 1e-6);
}

void write_and_check(const std::vector<SplatRecord>& splats, const std::string& name) {
  const std::string path = temp_path(name);
  write_gaussian_file(path, splats);
  const Ply ply = read_ply(path);
  EXPECT_EQ(ply.format, "binary_little_endian");
  EXPECT_EQ(ply.element, "vertex");
  EXPECT_EQ(ply.names, kExpectedNames);
  ASSERT_EQ(ply.count, splats.size());
  for (std::size_t i = 0; i < splats.size(); ++i) check_gaussian(ply, i, splats[i]);
  std::filesystem::remove(path);
}

// A splat with unit axes u, v (v ⟂ u), normal n, semi-axes a ≥ b.
SplatRecord splat(V center, V u, V vv, V n, double a, double b, Rgba8 color = {}) {
  SplatRecord s;
  s.center = f3(center);
  s.normal = f3(n);
  s.major = f3({u.x * a, u.y * a, u.z * a});
  s.minor = f3({vv.x * b, vv.y * b, vv.z * b});
  s.color = color;
  return s;
}

// The frame of the rotation by `angle` about the unit `axis` (Rodrigues), optionally left-handed.
SplatRecord rotated_splat(V axis, double angle, bool left_handed, double a = 0.5, double b = 0.25) {
  auto rot = [&](V p) {
    const double c = std::cos(angle), s = std::sin(angle);
    const V k = cross3(axis, p);
    const double d = dot3(axis, p);
    return V{p.x * c + k.x * s + axis.x * d * (1 - c), p.y * c + k.y * s + axis.y * d * (1 - c), p.z * c + k.z * s + axis.z * d * (1 - c)};
  };
  V vv = rot({0, 1, 0});
  if (left_handed) vv = {-vv.x, -vv.y, -vv.z};
  return splat({1, 2, 3}, rot({1, 0, 0}), vv, rot({0, 0, 1}), a, b, {10, 200, 77, 255});
}

TEST(GaussianFile, PropertiesInTheDeFactoOrder) { EXPECT_EQ(gaussian_properties(), kExpectedNames); }

std::vector<SplatRecord> random_splats() {
  std::mt19937 rng(20240611);
  std::normal_distribution<double> gauss;
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::uniform_int_distribution<int> byte(0, 255);
  std::vector<SplatRecord> splats;
  for (int i = 0; i < 2000; ++i) {
    const V n = unit({gauss(rng), gauss(rng), gauss(rng)});
    const V u = unit(cross3(n, {gauss(rng), gauss(rng), gauss(rng)}));
    V vv = cross3(n, u);
    if (i % 2) vv = {-vv.x, -vv.y, -vv.z};  // left-handed, as the orientation test leaves half the frames
    const double a = std::exp(std::log(1e-4) + uniform(rng) * std::log(1e5)), b = a * (0.05 + 0.95 * uniform(rng));
    splats.push_back(splat({10 * gauss(rng), 10 * gauss(rng), 10 * gauss(rng)}, u, vv, n, a, b,
                           {static_cast<std::uint8_t>(byte(rng)), static_cast<std::uint8_t>(byte(rng)),
                            static_cast<std::uint8_t>(byte(rng)), 255}));
  }
  return splats;
}

TEST(GaussianFile, RandomFramesReadBackByAnIndependentParser) { write_and_check(random_splats(), "random.ply"); }

std::string file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Reading our export back gives the splats: the same centre and colour, the normal, and each
// semi-axis up to its sign (v = n × u) and float rounding of ln σ and the quaternion.
TEST(GaussianFile, ReadingInvertsTheExport) {
  const std::vector<SplatRecord> splats = random_splats();
  const std::string path = temp_path("round-trip.ply");
  write_gaussian_file(path, splats);
  const std::vector<SplatRecord> read = decode_gaussian_file(file_bytes(path), path);
  std::filesystem::remove(path);
  ASSERT_EQ(read.size(), splats.size());
  const auto parallel_same_length = [](Vec3 a, Vec3 b) {
    const double la = std::sqrt(dot3(v(a), v(a))), lb = std::sqrt(dot3(v(b), v(b)));
    EXPECT_NEAR(la / lb, 1.0, 2e-6);
    EXPECT_NEAR(std::abs(dot3(v(a), v(b))) / (la * lb), 1.0, 2e-6);
  };
  for (std::size_t i = 0; i < splats.size(); ++i) {
    SCOPED_TRACE(i);
    EXPECT_EQ(read[i].center, splats[i].center);
    EXPECT_TRUE(read[i].color == splats[i].color);
    EXPECT_NEAR(dot3(v(read[i].normal), v(splats[i].normal)), 1.0, 1e-6);
    parallel_same_length(read[i].major, splats[i].major);
    parallel_same_length(read[i].minor, splats[i].minor);
  }
}

// A non-zero origin (positions relative to it, SplatFileInfo::origin) is kept as a header comment
// that 3DGS readers skip: the body is that of the file without it, and it reads back the same;
// gaussian_file_origin reads it (the presenter places the splats by it), zero for a file without.
TEST(GaussianFile, OriginIsAHeaderComment) {
  const std::vector<SplatRecord> splats = random_splats();
  const std::string plain = temp_path("no-origin.ply"), far = temp_path("origin.ply");
  write_gaussian_file(plain, splats);
  write_gaussian_file(far, splats, DVec3{512345.5, 5412345.25, -0.125});
  const std::string a = file_bytes(plain), b = file_bytes(far);
  EXPECT_EQ(a.find("splatcl_origin"), std::string::npos);
  EXPECT_NE(b.find("\ncomment splatcl_origin 512345.5 5412345.25 -0.125\n"), std::string::npos);
  EXPECT_EQ(a.substr(a.find("end_header\n")), b.substr(b.find("end_header\n")));
  EXPECT_EQ(read_ply(far).values, read_ply(plain).values);
  const std::vector<SplatRecord> read = decode_gaussian_file(b, far);
  ASSERT_EQ(read.size(), splats.size());
  for (std::size_t i = 0; i < splats.size(); ++i) EXPECT_EQ(read[i].center, splats[i].center);
  const DVec3 origin = gaussian_file_origin(b, far), none = gaussian_file_origin(a, plain);
  EXPECT_EQ(origin.x, 512345.5);
  EXPECT_EQ(origin.y, 5412345.25);
  EXPECT_EQ(origin.z, -0.125);
  EXPECT_EQ(none.x, 0.0);
  std::string damaged = b;
  damaged.replace(damaged.find("5412345.25"), 10, "nan");
  EXPECT_THROW(gaussian_file_origin(damaged, far), Error);
  std::filesystem::remove(plain);
  std::filesystem::remove(far);
}

// A file as 3DGS training tools write it, by hand: other property order, doubles, f_rest_* and a
// faint Gaussian; and the same in ASCII. Gaussian 0: identity rotation, σ = (0.1, 0.2, 0.001), so
// the major axis is y (0.2 / 0.5 = 0.4 long), the minor x (0.2), the normal z. Gaussian 1: a quarter
// turn about z (x → y, y → −x), σ = (0.3, 0.05, 0.01): major along y, 0.6 long. Gaussian 2: opacity
// logit −5 (α 0.007), dropped.
TEST(GaussianFile, FilesOfOtherToolsInAnyOrderTypeAndEncoding) {
  const double s2 = std::sqrt(0.5);
  const std::vector<std::vector<double>> rows = {
      // opacity, rot_0..3, scale_0..2, x, y, z, f_dc_0..2, f_rest_0
      {4.0, 1, 0, 0, 0, std::log(0.1), std::log(0.2), std::log(0.001), 1, 2, 3, 0, 0, 0, 0.3},
      {4.0, 2 * s2, 0, 0, 2 * s2, std::log(0.3), std::log(0.05), std::log(0.01), -1, 0, 0.5, 1.0, -1.0, 0.2, 0.3},
      {-5.0, 1, 0, 0, 0, std::log(0.1), std::log(0.2), std::log(0.001), 9, 9, 9, 0, 0, 0, 0.3}};
  const char* names[] = {"opacity", "rot_0", "rot_1", "rot_2", "rot_3", "scale_0", "scale_1", "scale_2",
                         "x", "y", "z", "f_dc_0", "f_dc_1", "f_dc_2", "f_rest_0"};
  for (const bool ascii : {false, true}) {
    SCOPED_TRACE(ascii ? "ascii" : "binary doubles");
    std::string text = std::string("ply\nformat ") + (ascii ? "ascii" : "binary_little_endian") + " 1.0\nelement vertex 3\n";
    for (const char* name : names) text += std::string("property double ") + name + "\n";
    text += "end_header\n";
    for (const auto& row : rows) {
      for (const double x : row) {
        if (ascii) {
          text += std::to_string(x) + " ";
        } else {
          char bytes[8];
          std::memcpy(bytes, &x, 8);
          text.append(bytes, 8);
        }
      }
      if (ascii) text += "\n";
    }
    const std::vector<SplatRecord> read = decode_gaussian_file(text, "trained.ply");
    ASSERT_EQ(read.size(), 2u) << "the faint Gaussian is dropped";
    const auto near = [](Vec3 a, V b, double tolerance) {
      EXPECT_NEAR(a.x, b.x, tolerance);
      EXPECT_NEAR(a.y, b.y, tolerance);
      EXPECT_NEAR(a.z, b.z, tolerance);
    };
    near(read[0].center, {1, 2, 3}, 1e-6);
    near(read[0].major, {0, 0.4, 0}, 1e-5);
    near(read[0].minor, {0.2, 0, 0}, 1e-5);
    near(read[0].normal, {0, 0, 1}, 1e-6);
    EXPECT_EQ(read[0].color.r, 128);  // 0.5 + C0 · 0 = 0.5
    near(read[1].center, {-1, 0, 0.5}, 1e-6);
    near(read[1].major, {0, 0.6, 0}, 1e-5);  // local x (σ 0.3) turned onto y
    near(read[1].minor, {-0.1, 0, 0}, 1e-5);
    EXPECT_EQ(read[1].color.r, static_cast<int>(std::lround(255 * (0.5 + 0.28209479177387814))));
    EXPECT_EQ(read[1].color.g, static_cast<int>(std::lround(255 * (0.5 - 0.28209479177387814))));
  }
}

TEST(GaussianFile, ReadingRefusesWhatIsNotAGaussianFile) {
  const auto refused = [](const std::string& text, const std::string& expected) {
    try {
      decode_gaussian_file(text, "g.ply");
      ADD_FAILURE() << "accepted: " << text;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("g.ply"), std::string::npos) << e.what();
    }
  };
  const std::string head = "ply\nformat ascii 1.0\nelement vertex 1\n";
  std::string all;
  for (const char* p : {"x", "y", "z", "scale_0", "scale_1", "scale_2", "rot_0", "rot_1", "rot_2"}) all += std::string("property float ") + p + "\n";
  refused(head + all + "end_header\n0 0 0 0 0 0 1 0 0\n", "no 'rot_3' property");
  all += "property float rot_3\n";
  refused(head + all + "end_header\n0 0 0 0 0 0 0 0 0 0\n", "quaternion is zero");
  refused(head + all + "end_header\n0.0000 0.0000 0.0000 0.0000 0.0000 0.0000 1.0000 0.0000 0.0000\n", "truncated");
  refused("ply\nformat binary_little_endian 1.0\nelement vertex 1\n" + all + "end_header\n" + std::string(36, '\0'),
          "more than the 36 bytes after end_header can hold");
  refused(head + all + "end_header\n0 0 0 800 0 0 1 0 0 0\n", "scale_0 is not finite");
  refused(head + all + "end_header\n0 0 x 0 0 0 1 0 0 0\n", "'z' is not a number");
  // exp(100) is finite as a double and an axis of 2.7e43 is not a float: accepted as inf before.
  refused(head + all + "end_header\n0 0 0 100 0 0 1 0 0 0\n", "Gaussian 1: its scale makes an axis beyond float range");
  // NaN colour, opacity or normal: kept silently before (a NaN opacity passed the faintness test).
  std::string extra = all;
  for (const char* p : {"nx", "ny", "nz", "f_dc_0", "f_dc_1", "f_dc_2", "opacity"}) extra += std::string("property float ") + p + "\n";
  refused(head + extra + "end_header\n0 0 0 0 0 0 1 0 0 0 0 0 1 0.1 0.2 0.3 nan\n", "Gaussian 1: 'opacity' is not a number");
  refused(head + extra + "end_header\n0 0 0 0 0 0 1 0 0 0 0 0 1 nan 0.2 0.3 2\n", "Gaussian 1: 'f_dc_0' is not a number");
  refused(head + extra + "end_header\n0 0 0 0 0 0 1 0 0 0 0 nan 1 0.1 0.2 0.3 2\n", "Gaussian 1: 'ny' is not a number");
  refused(head + extra + "end_header\n0 0 0 0 0 0 1 0 0 0 0 0 inf 0.1 0.2 0.3 2\n", "Gaussian 1: 'nz' is not finite");
  // One Gaussian per line: two values too many on a line drew a spindle with exit 0; one too few
  // was "truncated" at the last Gaussian.
  const std::string two = "ply\nformat ascii 1.0\nelement vertex 2\n" + all + "end_header\n";
  refused(two + "0 0 0 0 0 0 1 0 0 0 7 8\n1 0 0 0 0 0 1 0 0 0\n", "Gaussian 1: its line holds more or fewer values than the vertex element's 10 properties");
  refused(two + "0 0 0 0 0 0 1 0 0\n1.0000 0.0000 0.0000 0.0000 0.0000 0.0000 1.0000 0.0000 0.0000 0.0000\n",
          "Gaussian 1: its line holds more or fewer values");
  refused("ply\nformat ascii 1.0\nelement vertex 0\n" + all + "end_header\n", "no Gaussians");
  refused("ply\nformat ascii 1.0\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n3 0 1 2\n", "no vertex element");
  refused("not a ply", "not a PLY file");
}

// A list property in the vertex element is none of the used ones: skipped whole, in either encoding
// (read as one value, it shifted the rest: "'opacity' is not a number" at a later Gaussian).
TEST(GaussianFile, ListPropertiesAreSkipped) {
  for (const bool ascii : {true, false}) {
    SCOPED_TRACE(ascii ? "ascii" : "binary");
    std::string text = std::string("ply\nformat ") + (ascii ? "ascii" : "binary_little_endian") + " 1.0\nelement vertex 2\n";
    text += "property list uchar int idx\n";
    for (const char* p : {"x", "y", "z", "scale_0", "scale_1", "scale_2", "rot_0", "rot_1", "rot_2", "rot_3"}) text += std::string("property float ") + p + "\n";
    text += "end_header\n";
    const std::vector<std::vector<int>> lists = {{5, 6}, {}};
    const float rows[2][10] = {{1, 2, 3, -2, -3, -7, 1, 0, 0, 0}, {4, 5, 6, -2, -3, -7, 1, 0, 0, 0}};
    for (int r = 0; r < 2; ++r) {
      if (ascii) {
        text += fmt::format("{}", lists[r].size());
        for (const int i : lists[r]) text += fmt::format(" {}", i);
        for (const float v : rows[r]) text += fmt::format(" {}", v);
        text += "\n";
      } else {
        text += static_cast<char>(lists[r].size());
        for (const int i : lists[r]) text.append(reinterpret_cast<const char*>(&i), 4);
        text.append(reinterpret_cast<const char*>(rows[r]), sizeof rows[r]);
      }
    }
    const std::vector<SplatRecord> read = decode_gaussian_file(text, "lists.ply");
    ASSERT_EQ(read.size(), 2u);
    EXPECT_EQ(read[0].center.x, 1.0f);
    EXPECT_EQ(read[1].center.z, 6.0f);
  }
}

TEST(GaussianFile, ZeroSplats) {
  const std::string path = temp_path("empty.ply");
  EXPECT_EQ(write_gaussian_file(path, {}), 0u);
  const Ply ply = read_ply(path);
  EXPECT_EQ(ply.count, 0u);
  EXPECT_EQ(ply.names, kExpectedNames);
  EXPECT_TRUE(ply.values.empty());
  std::filesystem::remove(path);
}

TEST(GaussianFile, AxisAlignedFramesAndHalfTurns) {
  // u = x exactly (identity, and its left-handed twin), and the three half turns about x, y, z
  // (w = 0 exactly), where a trace-only conversion would divide by zero.
  std::vector<SplatRecord> splats = {
      splat({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, 1, 1),    splat({0, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 0, 1}, 2, 1),
      splat({0, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 0, -1}, 1, 0.5), splat({0, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, 0, -1}, 1, 0.5),
      splat({0, 0, 0}, {-1, 0, 0}, {0, -1, 0}, {0, 0, 1}, 1, 0.5), splat({0, 0, 0}, {0, 0, 1}, {1, 0, 0}, {0, 1, 0}, 3, 0.1),
      splat({0, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 0}, 3, 0.1)};
  write_and_check(splats, "axes.ply");
  const Gaussian identity = to_gaussian(splats[0]);
  EXPECT_EQ(identity.rotation[0], 1.0f);
  EXPECT_EQ(identity.rotation[1], 0.0f);
  EXPECT_EQ(identity.rotation[2], 0.0f);
  EXPECT_EQ(identity.rotation[3], 0.0f);
  const Gaussian half_x = to_gaussian(splats[2]);
  EXPECT_EQ(half_x.rotation[0], 0.0f);
  EXPECT_EQ(std::fabs(half_x.rotation[1]), 1.0f);
}

TEST(GaussianFile, RotationsNearAHalfTurn) {
  // w = cos(angle / 2) near 0: angles within 1e-7 … 1e-2 of π about random axes, both handednesses.
  std::mt19937 rng(7);
  std::normal_distribution<double> gauss;
  std::vector<SplatRecord> splats;
  for (const double gap : {0.0, 1e-7, 1e-5, 1e-3, 1e-2})
    for (int i = 0; i < 20; ++i)
      splats.push_back(rotated_splat(unit({gauss(rng), gauss(rng), gauss(rng)}), std::numbers::pi - (i % 2 ? gap : -gap), i % 4 >= 2));
  write_and_check(splats, "half-turns.ply");
}

TEST(GaussianFile, ClippedSplatsAreCountedAndWrittenWhole) {
  std::vector<SplatRecord> splats = {rotated_splat(unit({1, 2, 3}), 0.3, false), rotated_splat(unit({3, 2, 1}), 1.3, true),
                                     rotated_splat(unit({0, 1, 0}), 2.0, false)};
  splats[1].clip_x = 1, splats[1].clip_y = 0, splats[1].clip_offset = 0.1f;
  splats[2].clip_x = 0, splats[2].clip_y = -1, splats[2].clip_offset = 0.0f;
  const std::string path = temp_path("gaussian-clipped.ply");
  EXPECT_EQ(write_gaussian_file(path, splats), 2u);
  const Ply ply = read_ply(path);
  ASSERT_EQ(ply.count, 3u);
  for (std::size_t i = 0; i < 3; ++i) check_gaussian(ply, i, splats[i]);
  std::filesystem::remove(path);
}

TEST(GaussianFile, DegenerateSplatsHaveFiniteScales) {
  // Zero minor axis, zero major axis, zero normal: every value finite, the quaternion a unit one.
  std::vector<SplatRecord> splats(3);
  splats[0] = splat({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, 1, 0);
  splats[1] = splat({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, 0, 0);
  splats[2] = splat({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 0}, 1, 1);
  for (const SplatRecord& s : splats) {
    const Gaussian g = to_gaussian(s);
    for (const float x : g.scale) EXPECT_TRUE(std::isfinite(x));
    for (const float x : g.normal) EXPECT_TRUE(std::isfinite(x));
    double len = 0;
    for (const float x : g.rotation) {
      EXPECT_TRUE(std::isfinite(x));
      len += double{x} * x;
    }
    EXPECT_NEAR(len, 1.0, 1e-6);
  }
}

TEST(GaussianFile, SplatsOfARealMesh) {
  // The fit's own frames (half of them left-handed after the orientation test), through the native reference.
  const Mesh mesh = testing::sphere_mesh(16, 32);
  PipelineOptions options;
  options.fit.eps = 0.01f;
  options.fit.color_tolerance = 255;
  const SplatRun run = generate_splats(mesh, ColorSource{}, options, nullptr);
  const std::vector<SplatRecord> records = run.records();
  ASSERT_GT(records.size(), 10u);
  std::size_t left_handed = 0;
  for (const SplatRecord& s : records) left_handed += dot3(cross3(v(s.major), v(s.minor)), v(s.normal)) < 0;
  EXPECT_GT(left_handed, 0u);
  write_and_check(records, "sphere.ply");
}

}  // namespace
}  // namespace splatcl::splats
