#pragma once
// The directions of a coherent shadow map's N orthographic cameras on the bounding sphere, their
// coherent sequence order, and the inverse (direction → nearest map) used by queries.
//
// Conventions (Talpe §4.2, §5.2, §5.3.2; Müller §5.2.1):
// - Sphere frame: pole on +y; x = sinθ sinφ, y = cosθ, z = sinθ cosφ. A pole-axis choice maps the
//   sphere frame into object space (frame(): object = x·ex + y·ey + z·ez).
// - A grid cell is (a, b): a walks θ (the s axis, "horizontal"), b walks φ (the t axis, "vertical").
//   Uniform and regular grids are G × G with cell-centred samples; the AO thesis's grid is T × 2T
//   with corner samples θ = π a / T, φ = 2π b / 2T (its first row sits on the pole).
// - Camera basis: u = the φ-tangent (cosφ, 0, −sinφ), or (1, 0, 0) on the pole; v = d × u.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/geometry.hpp"

namespace splatcl::csm {


enum class Distribution : std::uint32_t {
  Uniform = 0,  // G × G, θ = acos(1 − 2s), φ = 2πt (area-preserving)
  Regular = 1,  // G × G, θ = πs, φ = 2πt
  ThesisAo = 2  // T × 2T, θ = πa/T, φ = 2πb/2T (AO thesis §5.2.1)
};

// Map orders over the grid. "h" curves walk θ fastest, "v" curves walk φ fastest (Talpe §5.3.2).
enum class Order : std::uint32_t {
  ZigzagH = 0,
  ZigzagV = 1,
  LinearH = 2,
  LinearV = 3,
  Hilbert = 4,  // 2-D Hilbert over (x = a, y = b); needs a square power-of-two grid
  Morton = 5    // Z-order (extension, not in the theses); same requirement
};

// Which object axis the sphere's pole is on; the *180 variants swap the poles (rotation by 180°
// about the sphere frame's z axis).
enum class PoleAxis : std::uint32_t { Y = 0, Z = 1, X = 2, Y180 = 3, Z180 = 4, X180 = 5 };

const char* to_string(Distribution value);
const char* to_string(Order value);
const char* to_string(PoleAxis value);
// Parse the names printed by to_string; throw Error listing the accepted names.
Distribution parse_distribution(const std::string& text);
Order parse_order(const std::string& text);
PoleAxis parse_pole_axis(const std::string& text);

// Object-space unit vectors of the sphere frame's x, y (pole) and z axes.
std::array<Vec3, 3> pole_frame(PoleAxis pole);

struct Cell {
  std::uint32_t a = 0, b = 0;  // θ index, φ index
};

// One map's orthographic camera: d points from the sphere centre to the camera (the light
// direction it stands for); rays travel along −d. inv = 1 / (−d) per component, for box tests.
struct Camera {
  float d[3], u[3], v[3], inv[3];
};

// Stated limit of the map count N (docs/reliability.md): the grid's tables take 8 B per map, and
// `csm build --maps` and .csm headers beyond it are refused before anything is sized from them.
inline constexpr std::uint32_t kMaxMaps = 1u << 24;

class SphereGrid {
 public:
  // Throws Error when `maps` does not fit the distribution (G × G needs a perfect square, T × 2T
  // needs 2T²) or the order (Hilbert and Morton need a square power-of-two grid).
  SphereGrid(Distribution distribution, Order order, PoleAxis pole, std::uint32_t maps);

  Distribution distribution() const { return distribution_; }
  Order order() const { return order_; }
  PoleAxis pole() const { return pole_; }
  std::uint32_t rows() const { return rows_; }  // θ cells
  std::uint32_t cols() const { return cols_; }  // φ cells
  std::uint32_t size() const { return rows_ * cols_; }

  Cell cell_of(std::uint32_t sequence) const;
  std::uint32_t sequence_of(Cell cell) const { return sequence_of_cell_[cell.a * cols_ + cell.b]; }
  // Grid cell → position in the sequence, row-major over (a, b); what queries look up.
  const std::vector<std::uint32_t>& sequence_table() const { return sequence_of_cell_; }

  // Spherical angles of a cell's camera.
  void angles(Cell cell, double& theta, double& phi) const;
  // The camera of the map at `sequence`, in object space (computed in double, stored as float).
  Camera camera(std::uint32_t sequence) const;
  // The cell whose direction is nearest to the object-space direction `w` (Talpe §4.3), in float.
  Cell nearest_cell(Vec3 w) const;

 private:
  Distribution distribution_;
  Order order_;
  PoleAxis pole_;
  std::uint32_t rows_ = 0, cols_ = 0;
  std::array<Vec3, 3> frame_;
  std::vector<std::uint32_t> cell_of_sequence_;  // a * cols + b
  std::vector<std::uint32_t> sequence_of_cell_;
};

// Grid (rows, cols) for `maps` under `distribution`, or throws Error.
std::array<std::uint32_t, 2> grid_shape(Distribution distribution, std::uint32_t maps);
// The same, also checked against the order as SphereGrid's constructor checks it, without building
// the grid's tables (a .csm header's map count is checked this way: 2^24 maps take seconds to build).
std::array<std::uint32_t, 2> grid_shape(Distribution distribution, Order order, std::uint32_t maps);

// 2-D Hilbert index → (x, y) on an n × n grid, n a power of two (Talpe §2.4).
void hilbert_d2xy(std::uint32_t n, std::uint32_t d, std::uint32_t& x, std::uint32_t& y);

}  // namespace splatcl::csm
