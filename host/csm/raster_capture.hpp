#pragma once
// Dual-depth capture by rasterization: the same maps, pixels and depth rules as the ray-cast capture
// (capture.hpp), computed by rasterizing every triangle into each map's two-layer depth buffer
// instead of casting one ray per pixel. RasterCapture runs kernels/csm_raster.cl (one work-item per
// map); raster_capture_reference runs the same per-map code (kernels/csm_raster.h) natively, so the
// two agree bit for bit. Against the ray caster the depths agree to float rounding and coverage
// differs only for pixel centres on triangle edges (the raster's edge rule is exact and watertight,
// the ray caster's edge tests are inclusive floats). Described in docs/formats.md.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "csm/capture.hpp"

namespace splatcl::csm {

// How maps are captured; both give the same values up to float rounding and triangle-edge pixels,
// so a .csm must be verified with the method that built it.
enum class CaptureMethod : std::uint32_t { Raycast = 0, Raster = 1 };
const char* to_string(CaptureMethod value);
CaptureMethod parse_capture_method(const std::string& text);
// The faster on PoCL's CPU device (docs/results/csm.md, "Capture and visibility performance").
inline constexpr CaptureMethod kDefaultCaptureMethod = CaptureMethod::Raster;

// The mesh as indexed triangles relative to the sphere centre: fan-triangulated faces without the
// zero-area triangles (the ray caster's set), sorted along a Morton curve of their centroids and
// vertices renumbered by first use, so consecutive triangles touch nearby pixels and vertices.
struct RasterMesh {
  std::vector<float> vertices;           // xyz per vertex
  std::vector<std::uint32_t> triangles;  // 3 vertex indices per triangle
  std::uint32_t vertex_count() const { return static_cast<std::uint32_t>(vertices.size() / 3); }
  std::uint32_t triangle_count() const { return static_cast<std::uint32_t>(triangles.size() / 3); }
};
// Throws Error naming the mesh when no triangle with a positive area remains.
RasterMesh raster_mesh(const Mesh& mesh, Vec3 origin);

// Native reference: maps [first, first + count) in sequence order, laid out [map][pixel],
// multithreaded over maps.
void raster_capture_reference(const CaptureScene& scene, const RasterMesh& mesh, const SphereGrid& grid,
                              std::uint32_t first, std::uint32_t count, std::vector<float>& z1, std::vector<float>& z2);

// The raster kernel's driver; owns the mesh, camera and projected-vertex buffers on the device.
class RasterCapture {
 public:
  // max_slots (0: no limit) caps the maps per launch below what the scratch budget allows.
  RasterCapture(Runtime& runtime, const CaptureScene& scene, const RasterMesh& mesh, std::uint32_t max_slots = 0);
  // Captures maps [first, first + count) into z1 and z2 (each at least count·M² floats), laid out
  // [map][pixel]; enqueued on the runtime's queue (in launches of at most slots() maps); returns
  // the last launch's event.
  cl::Event capture(const SphereGrid& grid, std::uint32_t first, std::uint32_t count, cl::Buffer& z1, cl::Buffer& z2,
                    Profiler* profiler = nullptr);
  // Maps per launch: scratch for projected vertices is held for this many maps at once.
  std::uint32_t slots() const { return slots_; }

 private:
  Runtime& runtime_;
  const CaptureScene& scene_;
  std::uint32_t vertex_count_, triangle_count_, slots_;
  cl::Buffer vertices_, triangles_;
  DeviceVector<Camera> cameras_;
  cl::Buffer scratch_;
  cl::Kernel kernel_;
};

// Either capture method on a device, behind one call (what the build and the losslessness check use).
class MapCapture {
 public:
  MapCapture(Runtime& runtime, const CaptureScene& scene, const Mesh& mesh, CaptureMethod method);
  ~MapCapture();
  cl::Event capture(const SphereGrid& grid, std::uint32_t first, std::uint32_t count, cl::Buffer& z1, cl::Buffer& z2,
                    Profiler* profiler = nullptr);
  CaptureMethod method() const { return method_; }

 private:
  CaptureMethod method_;
  RasterMesh mesh_;
  std::unique_ptr<DepthCapture> raycast_;
  std::unique_ptr<RasterCapture> raster_;
};

// Native reference of either method (the raster needs the mesh; the ray caster uses scene.bvh).
void capture_reference(const CaptureScene& scene, const Mesh& mesh, CaptureMethod method, const SphereGrid& grid,
                       std::uint32_t first, std::uint32_t count, std::vector<float>& z1, std::vector<float>& z2);

}  // namespace splatcl::csm
