#pragma once
// Visibility sampling with coherent shadow maps (Talpe §4.3–§4.4.1, Müller §5.3): for a
// batch of (receiver, light) queries, the fraction of the light that every placed occluder lets
// through; 0 or 1 without filtering, a multiple of 1/16 with PCF. The per-query code is
// kernels/csm_query.h, compiled both into the OpenCL kernel (VisibilityQueries) and into the native
// multithreaded reference (visibility_reference), so the two agree exactly.
//
// Spaces: a .csm's maps live in its object space (its header's object transform applied to the model
// file). An instance places the model in the world with `placement` (model file → world, any
// invertible affine; rigid in practice); queries are in world coordinates.
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "core/device_vector.hpp"
#include "csm/csm_file.hpp"
#include "runtime/profiling.hpp"
#include "runtime/runtime.hpp"
#include "core/geometry.hpp"

namespace splatcl::csm {

namespace device {
using uint = std::uint32_t;
#include "../../kernels/csm_query.h"
}  // namespace device


enum class Filter : std::uint32_t {
  None = CSM_FILTER_NONE,          // one texel of the nearest map
  SameMap = CSM_FILTER_SAME_MAP,   // 4 × 4 texels of the nearest map (16 taps)
  CrossMap = CSM_FILTER_CROSS_MAP, // 2 × 2 texels in each of the 4 nearest maps (16 taps)
  March = CSM_FILTER_MARCH         // the true light ray through 4 maps' texels, blocked in 2 (0 or 1)
};
// The filters' names, in Filter's order (scene files, command lines, the viewer's panel).
inline constexpr std::array<const char*, 4> kFilterNames = {"none", "same-map", "cross-map", "march"};
const char* to_string(Filter value);
Filter parse_filter(const std::string& text);

using Transform = std::array<double, 16>;  // row-major 4 × 4 affine
inline constexpr Transform kIdentity{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};

struct Instance {
  std::uint32_t occluder = 0;  // index into the scene's CSMs
  Transform placement = kIdentity;
};

// The packed tables every query reads: occluder types, instances, per-cell cameras, and all CSMs'
// segment lists concatenated (segment indices made global).
class VisibilityScene {
 public:
  // Copies the CSMs' data. Throws Error for an instance naming a
  // missing CSM, a singular placement, or more than 2^32 segments in all.
  VisibilityScene(const std::vector<const Csm*>& csms, const std::vector<Instance>& instances);

  // Other instances of the same CSMs (new placements, another subset, none): only `instances`
  // changes. Throws Error like the constructor.
  void place(const std::vector<Instance>& placed);

  std::vector<CsmInfo> infos;  // each CSM's header: what placing an instance of it needs
  std::vector<device::CsmOccluder> occluders;
  std::vector<device::CsmInstance> instances;
  std::vector<device::CsmCell> cells;
  std::vector<std::uint32_t> offsets, ends;
  std::vector<float> depths;
  std::vector<float> bounds;  // every occluder's cell boundaries for the map choice (csm_walk_cell)

  device::CsmScene view() const;
};

// An occluder's grid fields (rows, cols, centred, uniform, and the cell boundaries that the map
// choice csm_walk_cell tests, appended to `bounds`); the caller fills in the rest.
device::CsmOccluder grid_occluder(const SphereGrid& grid, std::vector<float>& bounds);

// The world → object transform of an instance of `csm` (object transform · placement⁻¹).
Transform world_to_object(const CsmInfo& info, const Transform& placement);
// Point p through the row-major affine t (a placement, or a CSM's float object transform), in
// double, rounded to float once.
template <class T>
Vec3 transform_point(const std::array<T, 16>& t, Vec3 p) {
  const double x = p.x, y = p.y, z = p.z;
  const auto row = [&](int r) { return static_cast<float>(double{t[4 * r]} * x + double{t[4 * r + 1]} * y + double{t[4 * r + 2]} * z + double{t[4 * r + 3]}); };
  return {row(0), row(1), row(2)};
}
// The inverse of an affine placement; throws Error "an occluder placement is not invertible" when
// its 3 x 3 part's determinant is 0, below 1e-12 of the product of its rows' lengths (nearly
// singular at any scale) or not finite.
Transform invert_affine(const Transform& m);

// The instance table of `placed` instances of the CSMs whose headers are `infos` (computed in
// double, stored as float). Throws Error for an instance naming a missing CSM or a singular placement.
std::vector<device::CsmInstance> place_instances(const std::vector<CsmInfo>& infos, const std::vector<Instance>& placed);

// The depth bias of a query (`bias`) is in texels of each occluder's maps: at most this many (a
// negative one shadowed every receiver by its own surface).
inline constexpr float kMaxBiasTexels = 1000;
// "" for a bias in 0..kMaxBiasTexels, else "--bias B is not a texel count in 0..1000".
std::string bias_error(float bias);

// Light vector of a query: light.xyz − light.w · receiver.xyz (w = 1 point light, w = 0 direction).
// Native reference, multithreaded over queries.
void visibility_reference(const VisibilityScene& scene, const std::vector<Vec4>& receivers, const std::vector<Vec4>& lights,
                          Filter filter, float bias, std::vector<float>& out);

// The kernel's driver; owns the scene's tables on the device.
class VisibilityQueries {
 public:
  VisibilityQueries(Runtime& runtime, const VisibilityScene& scene);
  // Other instances of the scene's CSMs (as VisibilityScene::place): uploads only the instance table,
  // so moving occluders reuse the CSM tables the constructor uploaded. Throws Error like place_instances.
  void place(const std::vector<Instance>& placed);
  std::size_t instance_count() const { return instance_count_; }

  // Device buffers of `count` float4 receivers and lights → `out` (count floats).
  cl::Event run(const cl::Buffer& receivers, const cl::Buffer& lights, std::size_t count, Filter filter, float bias,
                const cl::Buffer& out, Profiler* profiler = nullptr);
  // Host vectors in and out (uploads, runs, reads back).
  std::vector<float> run(const std::vector<Vec4>& receivers, const std::vector<Vec4>& lights, Filter filter, float bias,
                         Profiler* profiler = nullptr);

  // Binds the scene tables as arguments first, first + 1, ... (instances, count, occluders, cells,
  // offsets, ends, depths, bounds): shared with the AO driver.
  void bind_scene(cl::Kernel& kernel, cl_uint first) const;

 private:
  Runtime& runtime_;
  std::vector<CsmInfo> infos_;
  cl_uint instance_count_;
  // Chunks of consecutive queries per work-item, one launch per instance.
  cl::Kernel chunk_kernel_;
  DeviceVector<device::CsmInstance> instances_;
  cl::Buffer occluders_, cells_, offsets_, ends_, depths_, bounds_;
  DeviceVector<Vec4> receivers_, lights_;
  DeviceVector<float> out_;
};

}  // namespace splatcl::csm
