#pragma once
// Shared by the presenter tests: one headless GL context (EGL surfaceless on Mesa llvmpipe) and one
// Runtime (PoCL) per test program, a small default scene, and the splats' coverage of the mesh.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

#include "present/assets.hpp"
#include "present/context.hpp"
#include "present/presenter.hpp"
#include "core/scene.hpp"
#include "runtime/error.hpp"
#include "runtime/runtime.hpp"

namespace splatcl::present::testing {

class PresenterTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    runtime_ = Runtime::create("");
    context_ = GlContext::offscreen();
  }
  static void TearDownTestSuite() {
    context_.reset();
    runtime_.reset();
  }
  inline static std::shared_ptr<Runtime> runtime_;
  inline static std::unique_ptr<GlContext> context_;
};

// Small and quick: the default scene with its quality, fewer floor splats.
inline Scene test_scene() {
  Scene scene = default_scene();
  scene.floor.splats_per_side = 48;
  return scene;
}

// The last render's splat coverage against the triangle meshes rendered with the same camera:
// covered share of the mesh pixels, and splat pixels outside the mesh relative to the mesh's.
struct Coverage {
  std::size_t mesh = 0;
  double covered = 0, spill = 0;
};
inline Coverage silhouette_coverage(Presenter& presenter, float time) {
  const auto splat_mask = presenter.read_coverage();
  const auto mesh_mask = presenter.render_mesh_mask(time);
  std::size_t covered = 0, outside = 0;
  Coverage c;
  for (std::size_t i = 0; i < mesh_mask.size(); ++i) {
    c.mesh += mesh_mask[i];
    covered += mesh_mask[i] & splat_mask[i];
    outside += splat_mask[i] & (1 - mesh_mask[i]);
  }
  c.covered = static_cast<double>(covered) / static_cast<double>(std::max<std::size_t>(c.mesh, 1));
  c.spill = static_cast<double>(outside) / static_cast<double>(std::max<std::size_t>(c.mesh, 1));
  return c;
}

}  // namespace splatcl::present::testing
