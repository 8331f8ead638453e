#include "csm/ao_receivers.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <cstring>
#include <fstream>
#include <memory>
#include <numbers>
#include <optional>
#include <sstream>

#include "csm/query_reach.hpp"
#include "core/bvh.hpp"
#include "csm/build.hpp"
#include "csm/capture.hpp"
#include "io/atomic_file.hpp"
#include "runtime/error.hpp"
#include "core/parallel.hpp"

namespace splatcl::csm {

Transform parse_placement(const std::string& text) {
  std::vector<double> values;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    std::size_t used = 0;
    double v = 0;
    try {
      v = std::stod(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    // Placements are applied in float: beyond its range (1e39) they would turn inf.
    if (used == 0 || item.find_first_not_of(" \t", used) != std::string::npos || !std::isfinite(v) ||
        std::fabs(v) > std::numeric_limits<float>::max())
      throw Error("bad occluder transform '" + text + "': '" + item + "' is not a finite number in float range");
    values.push_back(v);
  }
  if (values.size() == 16) {
    Transform m;
    std::copy(values.begin(), values.end(), m.begin());
    if (m[12] != 0 || m[13] != 0 || m[14] != 0 || m[15] != 1) throw Error("bad occluder transform '" + text + "': the last row must be 0,0,0,1");
    try {  // named here: the queries' inversion failed later without naming the placement
      invert_affine(m);
    } catch (const Error& e) {
      throw Error("bad occluder transform '" + text + "': " + e.what());
    }
    return m;
  }
  if (values.size() != 3 && values.size() != 6)
    throw Error("bad occluder transform '" + text + "': give tx,ty,tz or tx,ty,tz,rx,ry,rz (degrees) or 16 numbers");
  double rx = 0, ry = 0, rz = 0;
  // 1e30 degrees turned the occluder at random; a sweep over a few turns is fine.
  for (std::size_t i = 3; i < values.size(); ++i)
    if (std::fabs(values[i]) > 36000)
      throw Error(fmt::format("bad occluder transform '{}': rotation {:g} is beyond 100 turns (degrees in -36000..36000)", text, values[i]));
  if (values.size() == 6) {
    const double k = std::numbers::pi / 180;
    rx = values[3] * k;
    ry = values[4] * k;
    rz = values[5] * k;
  }
  // R = Rz · Ry · Rx: x first, then y, then z.
  const double cx = std::cos(rx), sx = std::sin(rx), cy = std::cos(ry), sy = std::sin(ry), cz = std::cos(rz), sz = std::sin(rz);
  return {cz * cy, cz * sy * sx - sz * cx, cz * sy * cx + sz * sx, values[0],
          sz * cy, sz * sy * sx + cz * cx, sz * sy * cx - cz * sx, values[1],
          -sy,     cy * sx,                cy * cx,                values[2],
          0,       0,                      0,                      1};
}

namespace {

// Vertex v's normal, or +y where it has none (only degenerate faces around it).
Vec3 receiver_normal(const Mesh& receiver, std::size_t v) {
  const Vec3 nrm = v < receiver.normals.size() ? receiver.normals[v] : Vec3{0, 0, 0};
  return nrm.x * nrm.x + nrm.y * nrm.y + nrm.z * nrm.z > 0.5f ? nrm : Vec3{0, 1, 0};
}

}  // namespace

std::vector<Vec4> receiver_ambient_occlusion(const Mesh& receiver, const VisibilityScene& scene,
                                             const ReceiverAoOptions& options, Runtime* runtime,
                                             const std::function<void(std::size_t, std::size_t)>& progress) {
  const std::size_t n = receiver.vertices.size();
  if (n == 0) throw Error(receiver.source + ": the receiver mesh has no vertices");
  if (options.batch == 0) throw Error("AO batch size must be positive");
  AoRequest request;
  request.patterns = make_patterns(options.pattern_set, options.patterns, options.samples, options.seed);
  request.samples = options.samples;
  request.ground = options.ground;
  request.bias = options.bias;
  request.own_instance = options.lift.own_instance;
  const std::vector<std::uint32_t> choice = choose_patterns(n, options.patterns, options.seed);
  std::unique_ptr<AmbientOcclusion> device;
  if (runtime) device = std::make_unique<AmbientOcclusion>(*runtime, scene);
  std::vector<Vec4> out(n), part;
  for (std::size_t first = 0; first < n; first += options.batch) {
    const std::size_t count = std::min(options.batch, n - first);
    request.positions.resize(count);
    request.normals.resize(count);
    request.pattern_of.assign(choice.begin() + static_cast<std::ptrdiff_t>(first),
                              choice.begin() + static_cast<std::ptrdiff_t>(first + count));
    for (std::size_t k = 0; k < count; ++k) {
      const Vec3 nrm = receiver_normal(receiver, first + k);
      const float lift = options.lift.lifts.empty() ? 0.0f : options.lift.lifts.at(first + k);
      if (options.lift.own_instance == kNoInstance) {
        const Vec3 p = receiver.vertices[first + k] + nrm * lift;
        request.positions[k] = {p.x, p.y, p.z, 0};
      } else {
        const Vec3 p = receiver.vertices[first + k];
        request.positions[k] = {p.x, p.y, p.z, lift};
      }
      request.normals[k] = {nrm.x, nrm.y, nrm.z, 0};
    }
    if (device) part = device->run(request);
    else ambient_occlusion_reference(scene, request, part);
    std::copy(part.begin(), part.end(), out.begin() + static_cast<std::ptrdiff_t>(first));
    if (progress) progress(first + count, n);
  }
  return out;
}

std::optional<std::size_t> receiver_instance(const Mesh& receiver, const std::vector<const Csm*>& csms,
                                             const std::vector<Instance>& instances) {
  const Box box = receiver.bounds();
  const glm::vec3 box_centre(0.5f * (box.lo.x + box.hi.x), 0.5f * (box.lo.y + box.hi.y), 0.5f * (box.lo.z + box.hi.z));
  const double half_diagonal = 0.5 * box.exact_diagonal();
  for (std::size_t i = 0; i < instances.size(); ++i) {
    if (instances[i].occluder >= csms.size()) continue;
    const Csm& csm = *csms[instances[i].occluder];
    // A quick look first: the placed bounding sphere about where the receiver's box is, and as large.
    const MovedReach placed = moved_reach(csm.info, instances[i].placement, 0.0f);
    if (!(glm::distance(placed.centre, box_centre) <= placed.radius && half_diagonal >= 0.5 * placed.radius &&
          half_diagonal <= 2.0 * placed.radius))
      continue;
    // Then the receiver taken into the CSM's object space, where its bounding sphere and casting
    // triangles are compared as csm verify compares a model (require_built_from): a world-space
    // sphere does not turn with the mesh, so a receiver rotated into place did not match.
    Mesh moved = receiver;
    const Transform to_object = world_to_object(csm.info, instances[i].placement);
    for (Vec3& v : moved.vertices) v = transform_point(to_object, v);
    try {
      require_built_from(csm, moved);
      return i;
    } catch (const Error&) {
    }
  }
  return std::nullopt;
}

ReceiverLifts receiver_lifts(const Mesh& receiver, const std::vector<const Csm*>& csms, const std::vector<Instance>& instances,
                             float texels) {
  ReceiverLifts out;
  if (const std::optional<std::size_t> own = receiver_instance(receiver, csms, instances)) {
    out.own_instance = static_cast<std::uint32_t>(*own);
    out.lifts.assign(receiver.vertices.size(), texels * placed_texel(csms[instances[*own].occluder]->info, instances[*own].placement));
    return out;
  }
  return out;  // no occluder's own surface: not lifted
}

std::vector<float> raycast_ambient_occlusion(const Mesh& receiver, const Mesh& occluder, const ReceiverAoOptions& options) {
  const std::size_t n = receiver.vertices.size();
  if (n == 0) throw Error(receiver.source + ": the receiver mesh has no vertices");
  const std::vector<Vec4> patterns = make_patterns(options.pattern_set, options.patterns, options.samples, options.seed);
  const std::vector<std::uint32_t> choice = choose_patterns(n, options.patterns, options.seed);
  const Sphere sphere = bounding_sphere(occluder);
  const Vec3 c = sphere.centre;
  const float unit = trace_unit(sphere.radius);  // traced in these units, as the CSM capture is
  const Bvh bvh = build_bvh(mesh_triangles(occluder, c, unit));
  const float eps = 1e-4f * (sphere.radius / unit);
  std::vector<float> out(n);
  parallel_for(n, 64, [&](std::size_t v, std::size_t) {
    const Vec3 p = receiver.vertices[v], nrm = receiver_normal(receiver, v);
    float h[3];
    device::csm_ao_rotation_axis(nrm.x, nrm.y, nrm.z, h);
    const Vec4* pattern = patterns.data() + std::size_t{choice[v]} * options.samples;
    std::uint32_t lit = 0;
    for (std::uint32_t k = 0; k < options.samples; ++k) {
      float d[3];
      device::csm_ao_rotate(h, pattern[k].x, pattern[k].y, pattern[k].z, d);
      if (options.ground && d[1] < 0.0f) continue;
      const float o[3] = {(p.x - c.x) / unit + eps * d[0], (p.y - c.y) / unit + eps * d[1], (p.z - c.z) / unit + eps * d[2]};
      lit += !any_hit(bvh, o, d, INFINITY);
    }
    out[v] = static_cast<float>(lit) / static_cast<float>(options.samples);
  });
  return out;
}

void write_ao_ply(const std::string& path, const Mesh& receiver, const std::vector<Vec4>& ao) {
  const std::size_t n = receiver.vertices.size();
  if (ao.size() != n) throw Error("write_ao_ply: one AO value per vertex needed");
  std::string out = fmt::format(
      "ply\nformat binary_little_endian 1.0\ncomment splatcl ao: ambient occlusion per vertex (grey = AO, 1 = unoccluded)\n"
      "element vertex {}\nproperty float x\nproperty float y\nproperty float z\nproperty float nx\nproperty float ny\n"
      "property float nz\nproperty uchar red\nproperty uchar green\nproperty uchar blue\nproperty float ao\n"
      "property float bent_nx\nproperty float bent_ny\nproperty float bent_nz\nproperty uint file_vertex\nelement face {}\n"
      "property list uchar int vertex_indices\nend_header\n",
      n, receiver.face_count());
  const auto put = [&out](const auto& value) { out.append(reinterpret_cast<const char*>(&value), sizeof(value)); };
  for (std::size_t v = 0; v < n; ++v) {
    const Vec3 p = receiver.vertices[v];
    const Vec3 nrm = v < receiver.normals.size() ? receiver.normals[v] : Vec3{0, 0, 0};
    for (float f : {p.x, p.y, p.z, nrm.x, nrm.y, nrm.z}) put(f);
    const auto grey = static_cast<std::uint8_t>(std::lround(std::clamp(ao[v].w, 0.0f, 1.0f) * 255.0f));
    for (int c = 0; c < 3; ++c) put(grey);
    for (float f : {ao[v].w, ao[v].x, ao[v].y, ao[v].z}) put(f);
    put(static_cast<std::uint32_t>(v < receiver.file_vertex.size() ? receiver.file_vertex[v] : v));
  }
  for (std::size_t f = 0; f < receiver.face_count(); ++f) {
    const std::uint32_t first = receiver.face_offsets[f], last = receiver.face_offsets[f + 1];
    if (last - first > 255) throw Error(fmt::format("{}: face {} has {} corners (a PLY face lists at most 255)", receiver.source, f, last - first));
    put(static_cast<std::uint8_t>(last - first));
    for (std::uint32_t k = first; k < last; ++k) put(static_cast<std::int32_t>(receiver.corners[k]));
  }
  write_file_atomically(path, out);
}

}  // namespace splatcl::csm
