// Map distributions and orders: every order is a permutation, zigzag and Hilbert step to a grid
// neighbour, and the query-side inverse finds every camera's own cell.
#include <cmath>
#include <set>

#include "csm/sphere_grid.hpp"
#include "csm_test_support.hpp"
#include "runtime/error.hpp"

namespace splatcl::csm {
namespace {

TEST(CsmSphereGrid, OrdersArePermutationsAndCurvesStepToNeighbours) {
  for (const Order order : {Order::ZigzagH, Order::ZigzagV, Order::LinearH, Order::LinearV, Order::Hilbert, Order::Morton}) {
    const SphereGrid grid(Distribution::Uniform, order, PoleAxis::Y, 256);
    std::set<std::uint32_t> seen;
    for (std::uint32_t i = 0; i < grid.size(); ++i) {
      const Cell c = grid.cell_of(i);
      seen.insert(c.a * grid.cols() + c.b);
      EXPECT_EQ(grid.sequence_of(c), i);
      if (i > 0 && (order == Order::ZigzagH || order == Order::ZigzagV || order == Order::Hilbert)) {
        const Cell p = grid.cell_of(i - 1);
        EXPECT_EQ(std::abs(int(c.a) - int(p.a)) + std::abs(int(c.b) - int(p.b)), 1) << to_string(order) << " step " << i;
      }
    }
    EXPECT_EQ(seen.size(), 256u);
  }
  // Horizontal curves walk θ (a) fastest.
  const SphereGrid h(Distribution::Uniform, Order::ZigzagH, PoleAxis::Y, 16);
  EXPECT_EQ(h.cell_of(1).a, 1u);
  EXPECT_EQ(h.cell_of(4).b, 1u);
  EXPECT_EQ(h.cell_of(4).a, 3u);
}

TEST(CsmSphereGrid, NearestCellInvertsEveryCamera) {
  for (const Distribution dist : {Distribution::Uniform, Distribution::Regular, Distribution::ThesisAo})
    for (const PoleAxis pole : {PoleAxis::Y, PoleAxis::Z, PoleAxis::X, PoleAxis::Y180, PoleAxis::Z180, PoleAxis::X180}) {
      const SphereGrid grid(dist, Order::ZigzagH, pole, dist == Distribution::ThesisAo ? 512 : 1024);
      for (std::uint32_t i = 0; i < grid.size(); ++i) {
        const Camera cam = grid.camera(i);
        const Cell c = grid.nearest_cell({cam.d[0], cam.d[1], cam.d[2]});
        const Cell want = grid.cell_of(i);
        // The AO grid's pole row is one direction for every φ.
        if (dist == Distribution::ThesisAo && want.a == 0) {
          EXPECT_EQ(c.a, 0u);
          continue;
        }
        ASSERT_TRUE(c.a == want.a && c.b == want.b) << to_string(dist) << " pole " << to_string(pole) << " map " << i;
        // Orthonormal, right-handed basis: d × u = v.
        const Vec3 d{cam.d[0], cam.d[1], cam.d[2]}, u{cam.u[0], cam.u[1], cam.u[2]}, v{cam.v[0], cam.v[1], cam.v[2]};
        EXPECT_NEAR(dot(d, u), 0.0f, 1e-6f);
        EXPECT_NEAR(length(cross(d, u) - v), 0.0f, 1e-6f);
      }
    }
}

TEST(CsmSphereGrid, MapCountsThatDoNotFitAreErrors) {
  EXPECT_THROW(SphereGrid(Distribution::Uniform, Order::ZigzagH, PoleAxis::Y, 1000), Error);
  EXPECT_THROW(SphereGrid(Distribution::ThesisAo, Order::ZigzagV, PoleAxis::Y, 4096), Error);
  EXPECT_THROW(SphereGrid(Distribution::Uniform, Order::Hilbert, PoleAxis::Y, 36 * 36), Error);
  EXPECT_THROW(SphereGrid(Distribution::Uniform, Order::ZigzagH, PoleAxis::Y, 0), Error);
  EXPECT_NO_THROW(SphereGrid(Distribution::ThesisAo, Order::ZigzagV, PoleAxis::Y, 8192));
  EXPECT_THROW(parse_order("spiral"), Error);
  EXPECT_EQ(parse_order("zigzag-h"), Order::ZigzagH);
}

}  // namespace
}  // namespace splatcl::csm
