#include "csm/sphere_grid.hpp"

#include "core/bvh.hpp"

#include <cmath>
#include <numbers>

#include "runtime/error.hpp"

namespace splatcl::csm {
namespace {

constexpr const char* kDistributionNames[] = {"uniform", "regular", "ao"};
constexpr const char* kOrderNames[] = {"zigzag-h", "zigzag-v", "linear-h", "linear-v", "hilbert", "morton"};
constexpr const char* kPoleNames[] = {"y", "z", "x", "y180", "z180", "x180"};

template <class Enum, std::size_t N>
Enum parse_name(const std::string& text, const char* const (&names)[N], const char* what) {
  std::string accepted;
  for (std::size_t i = 0; i < N; ++i) {
    if (text == names[i]) return static_cast<Enum>(i);
    accepted += (i ? ", " : "") + std::string(names[i]);
  }
  throw Error("unknown " + std::string(what) + " '" + text + "' (one of: " + accepted + ")");
}

bool is_power_of_two(std::uint32_t n) { return n != 0 && (n & (n - 1)) == 0; }

std::uint32_t compact_even_bits(std::uint32_t x) {
  x &= 0x55555555u;
  x = (x | (x >> 1)) & 0x33333333u;
  x = (x | (x >> 2)) & 0x0f0f0f0fu;
  x = (x | (x >> 4)) & 0x00ff00ffu;
  x = (x | (x >> 8)) & 0x0000ffffu;
  return x;
}

Vec3 to_object(const std::array<Vec3, 3>& frame, double x, double y, double z) {
  Vec3 out;
  out.x = static_cast<float>(x * frame[0].x + y * frame[1].x + z * frame[2].x);
  out.y = static_cast<float>(x * frame[0].y + y * frame[1].y + z * frame[2].y);
  out.z = static_cast<float>(x * frame[0].z + y * frame[1].z + z * frame[2].z);
  return out;
}

}  // namespace

const char* to_string(Distribution value) { return kDistributionNames[static_cast<std::uint32_t>(value)]; }
const char* to_string(Order value) { return kOrderNames[static_cast<std::uint32_t>(value)]; }
const char* to_string(PoleAxis value) { return kPoleNames[static_cast<std::uint32_t>(value)]; }
Distribution parse_distribution(const std::string& text) { return parse_name<Distribution>(text, kDistributionNames, "distribution"); }
Order parse_order(const std::string& text) { return parse_name<Order>(text, kOrderNames, "map order"); }
PoleAxis parse_pole_axis(const std::string& text) { return parse_name<PoleAxis>(text, kPoleNames, "pole axis"); }

std::array<Vec3, 3> pole_frame(PoleAxis pole) {
  // Right-handed frames (ex × ey = ez) with the pole ey on the chosen object axis.
  std::array<Vec3, 3> frame;
  switch (pole) {
    case PoleAxis::Y:
    case PoleAxis::Y180: frame = {Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, 0, 1}}; break;
    case PoleAxis::Z:
    case PoleAxis::Z180: frame = {Vec3{0, 1, 0}, Vec3{0, 0, 1}, Vec3{1, 0, 0}}; break;
    case PoleAxis::X:
    case PoleAxis::X180: frame = {Vec3{0, 0, 1}, Vec3{1, 0, 0}, Vec3{0, 1, 0}}; break;
  }
  if (pole == PoleAxis::Y180 || pole == PoleAxis::Z180 || pole == PoleAxis::X180) {
    frame[0] = -1.0f * frame[0];
    frame[1] = -1.0f * frame[1];
  }
  return frame;
}

std::array<std::uint32_t, 2> grid_shape(Distribution distribution, std::uint32_t maps) {
  if (maps == 0) throw Error("0 maps: the number of maps must be positive");
  if (distribution == Distribution::ThesisAo) {
    const auto t = static_cast<std::uint32_t>(std::llround(std::sqrt(maps / 2.0)));
    if (2ull * t * t != maps)
      throw Error(std::to_string(maps) + " does not fit the ao distribution's T x 2T grid (use 2T², e.g. 8192)");
    return {t, 2 * t};
  }
  const auto g = static_cast<std::uint32_t>(std::llround(std::sqrt(static_cast<double>(maps))));
  if (std::uint64_t{g} * g != maps)
    throw Error(std::to_string(maps) + " is not a perfect square, as the " + to_string(distribution) +
                " G x G grid needs (e.g. 4096 or 16384)");
  return {g, g};
}

void hilbert_d2xy(std::uint32_t n, std::uint32_t d, std::uint32_t& x, std::uint32_t& y) {
  std::uint32_t t = d;
  x = y = 0;
  for (std::uint32_t s = 1; s < n; s *= 2) {
    const std::uint32_t rx = 1 & (t / 2);
    const std::uint32_t ry = 1 & (t ^ rx);
    if (ry == 0) {
      if (rx == 1) {
        x = s - 1 - x;
        y = s - 1 - y;
      }
      std::swap(x, y);
    }
    x += s * rx;
    y += s * ry;
    t /= 4;
  }
}

std::array<std::uint32_t, 2> grid_shape(Distribution distribution, Order order, std::uint32_t maps) {
  const auto shape = grid_shape(distribution, maps);
  if ((order == Order::Hilbert || order == Order::Morton) && !(shape[0] == shape[1] && is_power_of_two(shape[0])))
    throw Error(std::string("the ") + to_string(order) + " order needs a square power-of-two grid (maps = 4^k with a G x G distribution)");
  return shape;
}

SphereGrid::SphereGrid(Distribution distribution, Order order, PoleAxis pole, std::uint32_t maps)
    : distribution_(distribution), order_(order), pole_(pole), frame_(pole_frame(pole)) {
  const auto shape = grid_shape(distribution, order, maps);
  rows_ = shape[0];
  cols_ = shape[1];
  cell_of_sequence_.resize(maps);
  sequence_of_cell_.resize(maps);
  for (std::uint32_t i = 0; i < maps; ++i) {
    std::uint32_t a = 0, b = 0;
    switch (order) {
      case Order::ZigzagH:
        b = i / rows_;
        a = (b % 2 == 0) ? i % rows_ : rows_ - 1 - i % rows_;
        break;
      case Order::LinearH:
        b = i / rows_;
        a = i % rows_;
        break;
      case Order::ZigzagV:
        a = i / cols_;
        b = (a % 2 == 0) ? i % cols_ : cols_ - 1 - i % cols_;
        break;
      case Order::LinearV:
        a = i / cols_;
        b = i % cols_;
        break;
      case Order::Hilbert: hilbert_d2xy(rows_, i, a, b); break;
      case Order::Morton:
        a = compact_even_bits(i);
        b = compact_even_bits(i >> 1);
        break;
    }
    cell_of_sequence_[i] = a * cols_ + b;
    sequence_of_cell_[a * cols_ + b] = i;
  }
}

Cell SphereGrid::cell_of(std::uint32_t sequence) const {
  const std::uint32_t c = cell_of_sequence_.at(sequence);
  return {c / cols_, c % cols_};
}

void SphereGrid::angles(Cell cell, double& theta, double& phi) const {
  const double pi = std::numbers::pi;
  if (distribution_ == Distribution::ThesisAo) {
    theta = pi * cell.a / rows_;
    phi = 2 * pi * cell.b / cols_;
    return;
  }
  const double s = (cell.a + 0.5) / rows_, t = (cell.b + 0.5) / cols_;
  theta = distribution_ == Distribution::Uniform ? std::acos(1 - 2 * s) : pi * s;
  phi = 2 * pi * t;
}

Camera SphereGrid::camera(std::uint32_t sequence) const {
  double theta = 0, phi = 0;
  angles(cell_of(sequence), theta, phi);
  const double st = std::sin(theta), ct = std::cos(theta), sp = std::sin(phi), cp = std::cos(phi);
  const double d[3] = {st * sp, ct, st * cp};
  // The φ-tangent varies continuously with the direction; on the pole itself it is undefined, and
  // a fixed axis makes every pole map identical (Müller §5.2.1).
  const double u[3] = {st > 0 ? cp : 1.0, 0.0, st > 0 ? -sp : 0.0};
  const double v[3] = {d[1] * u[2] - d[2] * u[1], d[2] * u[0] - d[0] * u[2], d[0] * u[1] - d[1] * u[0]};
  const Vec3 od = to_object(frame_, d[0], d[1], d[2]), ou = to_object(frame_, u[0], u[1], u[2]),
             ov = to_object(frame_, v[0], v[1], v[2]);
  Camera camera{};
  const Vec3* vectors[3] = {&od, &ou, &ov};
  float* targets[3] = {camera.d, camera.u, camera.v};
  for (int k = 0; k < 3; ++k) {
    targets[k][0] = vectors[k]->x;
    targets[k][1] = vectors[k]->y;
    targets[k][2] = vectors[k]->z;
  }
  for (int k = 0; k < 3; ++k) camera.inv[k] = inverse_direction(-camera.d[k]);
  return camera;
}

Cell SphereGrid::nearest_cell(Vec3 w) const {
  const float x = dot(w, frame_[0]), y = dot(w, frame_[1]), z = dot(w, frame_[2]);
  const float len = std::sqrt(x * x + y * y + z * z);
  const float cos_theta = std::fmin(1.0f, std::fmax(-1.0f, y / len));
  const float two_pi = 2.0f * std::numbers::pi_v<float>;
  float phi = std::atan2(x, z);
  if (phi < 0) phi += two_pi;
  const float t = phi / two_pi;
  const float rows = static_cast<float>(rows_), cols = static_cast<float>(cols_);
  std::uint32_t a = 0, b = 0;
  if (distribution_ == Distribution::ThesisAo) {
    const float s = std::acos(cos_theta) / std::numbers::pi_v<float>;
    a = static_cast<std::uint32_t>(std::fmin(rows - 1, std::floor(s * rows + 0.5f)));
    b = static_cast<std::uint32_t>(std::floor(t * cols + 0.5f)) % cols_;
  } else {
    const float s = distribution_ == Distribution::Uniform ? (1.0f - cos_theta) * 0.5f : std::acos(cos_theta) / std::numbers::pi_v<float>;
    a = static_cast<std::uint32_t>(std::fmin(rows - 1, std::floor(s * rows)));
    b = static_cast<std::uint32_t>(std::floor(t * cols)) % cols_;
  }
  return {a, b};
}

}  // namespace splatcl::csm
