#include "csm/visibility.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <iterator>
#include <numbers>

#include "primitives/launch.hpp"
#include "runtime/error.hpp"
#include "core/parallel.hpp"

namespace splatcl::csm {

using primitives::detail::set_args;

// Queries per work-item of the chunked kernel: long enough runs for the reuse of map choices and
// stored depths, and still thousands of work-items per million queries.
constexpr std::size_t kQueryChunk = 256;

static_assert(sizeof(device::CsmCell) == 40 && sizeof(device::CsmOccluder) == 68 && sizeof(device::CsmInstance) == 88,
              "the query tables must match kernels/csm_query.h byte for byte");

namespace {


Transform multiply(const Transform& a, const Transform& b) {
  Transform c{};
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      for (int k = 0; k < 4; ++k) c[4 * i + j] += a[4 * i + k] * b[4 * k + j];
  return c;
}


}  // namespace

Transform invert_affine(const Transform& m) {
  const double a = m[0], b = m[1], c = m[2], d = m[4], e = m[5], f = m[6], g = m[8], h = m[9], i = m[10];
  const double det = a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g);
  // Relative to the rows' lengths (|det| <= their product), so that a uniform scale of any size
  // passes: an absolute 1e-30 refused a scene object of scale 1e-11 (det 1e-33).
  const double rows = std::hypot(a, b, c) * std::hypot(d, e, f) * std::hypot(g, h, i);
  if (!(std::abs(det) > 1e-12 * rows) || !std::isfinite(det) || !std::isfinite(rows))
    throw Error("an occluder placement is not invertible");
  const double r[9] = {(e * i - f * h) / det, (c * h - b * i) / det, (b * f - c * e) / det,
                       (f * g - d * i) / det, (a * i - c * g) / det, (c * d - a * f) / det,
                       (d * h - e * g) / det, (b * g - a * h) / det, (a * e - b * d) / det};
  Transform out = kIdentity;
  for (int row = 0; row < 3; ++row) {
    for (int col = 0; col < 3; ++col) out[4 * row + col] = r[3 * row + col];
    out[4 * row + 3] = -(r[3 * row] * m[3] + r[3 * row + 1] * m[7] + r[3 * row + 2] * m[11]);
  }
  return out;
}

const char* to_string(Filter value) { return kFilterNames[static_cast<std::uint32_t>(value)]; }

Filter parse_filter(const std::string& text) {
  for (std::uint32_t i = 0; i < std::size(kFilterNames); ++i)
    if (text == kFilterNames[i]) return static_cast<Filter>(i);
  throw Error("unknown filter '" + text + "' (one of: none, same-map, cross-map, march)");
}

Transform world_to_object(const CsmInfo& info, const Transform& placement) {
  Transform object{};
  for (std::size_t k = 0; k < 16; ++k) object[k] = info.object_transform[k];
  return multiply(object, invert_affine(placement));
}

// Boundaries as signed squared cosines (c·|c|, computed in double). θ boundaries sit halfway
// between sample rows in s (uniform: cosθ = 1 − 2s; regular and ao: θ = πs), φ boundaries halfway
// between sample columns in t (φ = 2πt). Cosines of exact quarter turns are stored as 0, so that
// the test there is the sign of x or z.
device::CsmOccluder grid_occluder(const SphereGrid& grid, std::vector<float>& bounds) {
  const double pi = std::numbers::pi;
  device::CsmOccluder oc{};
  oc.rows = grid.rows();
  oc.cols = grid.cols();
  oc.centred = grid.distribution() == Distribution::ThesisAo ? 0 : 1;
  oc.uniform = grid.distribution() == Distribution::Uniform ? 1 : 0;
  const bool centred = oc.centred == 1;
  const auto signed_square = [](double c) { return std::abs(c) < 1e-12 ? 0.0f : static_cast<float>(c * std::abs(c)); };
  oc.bound_base = static_cast<std::uint32_t>(bounds.size());
  const double rows = grid.rows(), cols = grid.cols();
  for (std::uint32_t k = 1; k < grid.rows(); ++k) {
    // Sample rows at s = (a + 0.5)/rows (centred) or a/rows (ao): boundaries at k/rows or (k − 0.5)/rows.
    const double s = centred ? k / rows : (k - 0.5) / rows;
    bounds.push_back(signed_square(grid.distribution() == Distribution::Uniform ? 1 - 2 * s : std::cos(pi * s)));
  }
  oc.col_bounds = centred ? grid.cols() - 1 : grid.cols();
  oc.half_cols = 0;
  for (std::uint32_t k = 1; k <= oc.col_bounds; ++k) {
    // β_k = π · twice_t / cols (twice_t = 2t · cols), so twice_t ≤ cols means β_k ≤ π.
    const double twice_t = centred ? 2.0 * k : 2.0 * k - 1;
    if (twice_t <= cols) oc.half_cols = k;
    bounds.push_back(signed_square(std::cos(pi * twice_t / cols)));
  }
  return oc;
}

VisibilityScene::VisibilityScene(const std::vector<const Csm*>& csms, const std::vector<Instance>& placed) {
  std::uint64_t segment_base = 0;
  for (const Csm* csm : csms) {
    const CsmInfo& info = csm->info;
    infos.push_back(info);
    const SphereGrid grid(info.distribution, info.order, info.pole, info.maps);
    device::CsmOccluder oc = grid_occluder(grid, bounds);
    oc.centre[0] = info.sphere.centre.x;
    oc.centre[1] = info.sphere.centre.y;
    oc.centre[2] = info.sphere.centre.z;
    oc.radius = info.sphere.radius;
    oc.pixel_scale = static_cast<float>(info.resolution) / (2.0f * info.sphere.radius);
    oc.depth_scale = 1.0f / (2.0f * info.sphere.radius);
    oc.texel_depth = static_cast<float>(1.0 / info.resolution);
    oc.resolution = info.resolution;
    oc.cell_base = static_cast<std::uint32_t>(cells.size());
    oc.pixel_base = static_cast<std::uint32_t>(offsets.size());
    occluders.push_back(oc);
    for (std::uint32_t a = 0; a < grid.rows(); ++a)
      for (std::uint32_t b = 0; b < grid.cols(); ++b) {
        const std::uint32_t sequence = grid.sequence_of({a, b});
        const Camera camera = grid.camera(sequence);
        device::CsmCell cell{};
        std::copy(camera.d, camera.d + 3, cell.d);
        std::copy(camera.u, camera.u + 3, cell.u);
        std::copy(camera.v, camera.v + 3, cell.v);
        cell.sequence = sequence;
        cells.push_back(cell);
      }
    if (segment_base + csm->segments() > UINT32_MAX) throw Error("the occluders' CSMs hold more than 2^32 segments in all");
    for (std::uint32_t offset : csm->offsets) offsets.push_back(static_cast<std::uint32_t>(segment_base + offset));
    ends.insert(ends.end(), csm->end.begin(), csm->end.end());
    depths.insert(depths.end(), csm->depth.begin(), csm->depth.end());
    segment_base += csm->segments();
  }
  place(placed);
}

std::string bias_error(float bias) {
  return bias >= 0 && bias <= kMaxBiasTexels ? std::string{} : fmt::format("--bias {} is not a texel count in 0..{}", bias, kMaxBiasTexels);
}

void VisibilityScene::place(const std::vector<Instance>& placed) { instances = place_instances(infos, placed); }

std::vector<device::CsmInstance> place_instances(const std::vector<CsmInfo>& infos, const std::vector<Instance>& placed) {
  std::vector<device::CsmInstance> instances;
  instances.reserve(placed.size());
  for (const Instance& instance : placed) {
    if (instance.occluder >= infos.size())
      throw Error(fmt::format("occluder instance names CSM {} of {}", instance.occluder, infos.size()));
    const CsmInfo& info = infos[instance.occluder];
    const Transform m = world_to_object(info, instance.placement);
    const auto frame = pole_frame(info.pole);
    device::CsmInstance in{};
    for (int row = 0; row < 3; ++row)
      for (int col = 0; col < 4; ++col) in.to_object[4 * row + col] = static_cast<float>(m[4 * row + col]);
    for (int row = 0; row < 3; ++row) {
      const Vec3 axis = frame[static_cast<std::size_t>(row)];
      for (int col = 0; col < 3; ++col)
        in.to_frame[3 * row + col] = static_cast<float>(axis.x * m[col] + axis.y * m[4 + col] + axis.z * m[8 + col]);
    }
    in.occluder = instance.occluder;
    instances.push_back(in);
  }
  return instances;
}

device::CsmScene VisibilityScene::view() const {
  return {instances.data(), static_cast<std::uint32_t>(instances.size()), occluders.data(), cells.data(), offsets.data(),
          ends.data(),      depths.data(), bounds.data()};
}

void visibility_reference(const VisibilityScene& scene, const std::vector<Vec4>& receivers, const std::vector<Vec4>& lights,
                          Filter filter, float bias, std::vector<float>& out) {
  if (receivers.size() != lights.size()) throw Error("visibility queries need one light per receiver");
  out.resize(receivers.size());
  const device::CsmScene view = scene.view();
  parallel_for(receivers.size(), 4096, [&](std::size_t q, std::size_t) {
    const Vec4 p = receivers[q], l = lights[q];
    const float wx = l.x - l.w * p.x, wy = l.y - l.w * p.y, wz = l.z - l.w * p.z;
    out[q] = device::csm_visibility(&view, p.x, p.y, p.z, wx, wy, wz, static_cast<std::uint32_t>(filter), bias);
  });
}

VisibilityQueries::VisibilityQueries(Runtime& runtime, const VisibilityScene& scene)
    : runtime_(runtime),
      infos_(scene.infos),
      instance_count_(static_cast<cl_uint>(scene.instances.size())),
      instances_(runtime, "CSM instances", CL_MEM_READ_ONLY),
      receivers_(runtime, "CSM query receivers"),
      lights_(runtime, "CSM query lights"),
      out_(runtime, "CSM query output") {
  instances_.assign(scene.instances);
  occluders_ = upload(runtime, scene.occluders, "CSM occluders", CL_MEM_READ_ONLY);
  cells_ = upload(runtime, scene.cells, "CSM cameras", CL_MEM_READ_ONLY);
  offsets_ = upload(runtime, scene.offsets, "CSM offsets", CL_MEM_READ_ONLY);
  ends_ = upload(runtime, scene.ends, "CSM segment ends", CL_MEM_READ_ONLY);
  depths_ = upload(runtime, scene.depths, "CSM segment depths", CL_MEM_READ_ONLY);
  bounds_ = upload(runtime, scene.bounds, "CSM cell boundaries", CL_MEM_READ_ONLY);
  // The map choice (csm_atan2, square roots) and the march divide; the answers must match the
  // reference's bit for bit.
  chunk_kernel_ = runtime.kernel("csm_visibility.cl", "csm_visibility_chunks", runtime.exact_divide_option());
}

void VisibilityQueries::place(const std::vector<Instance>& placed) {
  const std::vector<device::CsmInstance> instances = place_instances(infos_, placed);
  if (instances.size() > UINT32_MAX) throw Error("more than 2^32 occluder instances");
  // Blocking (the queue is in order: earlier launches have read the old table by then), so the
  // host table may go right after.
  // No instances until the new table is in place: a failed upload leaves none, not a stale count.
  instance_count_ = 0;
  instances_.assign(instances);
  instance_count_ = static_cast<cl_uint>(instances.size());
}

void VisibilityQueries::bind_scene(cl::Kernel& kernel, cl_uint first) const {
  kernel.setArg(first, instances_.buffer());
  kernel.setArg(first + 1, instance_count_);
  kernel.setArg(first + 2, occluders_);
  kernel.setArg(first + 3, cells_);
  kernel.setArg(first + 4, offsets_);
  kernel.setArg(first + 5, ends_);
  kernel.setArg(first + 6, depths_);
  kernel.setArg(first + 7, bounds_);
}

cl::Event VisibilityQueries::run(const cl::Buffer& receivers, const cl::Buffer& lights, std::size_t count, Filter filter,
                                 float bias, const cl::Buffer& out, Profiler* profiler) {
  if (count == 0) return {};
  if (count > UINT32_MAX) throw Error("more than 2^32 visibility queries in one batch");
  require_bytes(receivers, count * sizeof(Vec4), "CSM query receivers");
  require_bytes(lights, count * sizeof(Vec4), "CSM query lights");
  require_bytes(out, count * sizeof(float), "CSM query output");
  // One launch per instance, multiplying into `out`; no instance: everything is lit.
  if (instance_count_ == 0) {
    cl::Event event;
    runtime_.queue().enqueueFillBuffer(out, 1.0f, 0, count * sizeof(float), nullptr, &event);
    return event;
  }
  const std::size_t items = (count + kQueryChunk - 1) / kQueryChunk;
  // CPU: one work-item (a chunk) per work-group. Left to itself PoCL makes one work-group of the
  // few dozen items a batch of thousands of queries has, run by one thread; and it compiles the
  // kernel once per work-group size, which is now fixed.
  const std::size_t local = runtime_.is_cpu() ? 1 : 0;
  cl::Event last;
  for (cl_uint k = 0; k < instance_count_; ++k) {
    set_args(chunk_kernel_, receivers, lights, static_cast<cl_uint>(count), static_cast<cl_uint>(kQueryChunk), instances_.buffer(), k,
             occluders_, cells_, offsets_, ends_, depths_, bounds_, static_cast<cl_uint>(filter), bias,
             static_cast<cl_uint>(k > 0 ? 1 : 0), out);
    last = enqueue_1d(runtime_.queue(), chunk_kernel_, items, local, profiler, "csm visibility");
  }
  return last;
}

std::vector<float> VisibilityQueries::run(const std::vector<Vec4>& receivers, const std::vector<Vec4>& lights, Filter filter,
                                          float bias, Profiler* profiler) {
  if (receivers.size() != lights.size()) throw Error("visibility queries need one light per receiver");
  if (receivers.empty()) return {};
  const std::size_t n = receivers.size();
  // The second write blocks (the queue is in order): both uploads are done before anything below
  // can throw and let the caller free the vectors.
  receivers_.assign(receivers, false);
  lights_.assign(lights, true);
  out_.resize(n);
  run(receivers_.buffer(), lights_.buffer(), n, filter, bias, out_.buffer(), profiler);
  return out_.read();
}

}  // namespace splatcl::csm
