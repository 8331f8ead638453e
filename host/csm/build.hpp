#pragma once
// Building a coherent shadow map: bounding sphere, BVH, then maps captured in batches in sequence
// order and folded into the per-pixel runs (StreamingCompressor), so memory holds one batch of
// maps, never all N. With no runtime the native references do the same work (all maps of a batch
// captured on the host, then the batch algorithm over the whole sequence: for small builds and
// tests only).
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "csm/capture.hpp"
#include "csm/compress.hpp"
#include "csm/csm_file.hpp"
#include "csm/raster_capture.hpp"
#include "csm/sphere_grid.hpp"
#include "runtime/runtime.hpp"
#include "core/mesh.hpp"

namespace splatcl::csm {

struct BuildOptions {
  std::uint32_t maps = 4096, resolution = 128;
  Distribution distribution = Distribution::Uniform;
  Order order = Order::ZigzagH;
  PoleAxis pole = PoleAxis::Y;
  SingleHit single_hit = SingleHit::Auto;  // resolved per mesh (resolve_single_hit)
  float hit_epsilon = kDefaultHitEpsilon;
  // Capture by rasterization or by ray casting (same values up to rounding and edge pixels).
  CaptureMethod capture = kDefaultCaptureMethod;
  // Maps per batch; 0 picks about 8 M samples per batch (64 MiB of depths).
  std::uint32_t batch_maps = 0;
  // What BuildResult::thin_part_warning tells the user to do, in the caller's spelling; empty: no
  // check (a caller that checks on its own, for reused CSMs too).
  std::string thin_part_remedy = "lower the hit epsilon, or capture with the single-hit rule exact";
};

struct BuildResult {
  Csm csm;
  Segments segments;  // the runs' intervals, for the compact encoding
  double setup_ms = 0, capture_ms = 0, compress_ms = 0, total_ms = 0;
  std::uint32_t batch_maps = 0;
  // thin_part_warning of the capture (csm/capture.hpp) with BuildOptions::thin_part_remedy; empty when none.
  std::string thin_part_warning;
};

// Called after each batch with (maps done, maps total).
using BuildProgress = std::function<void(std::uint32_t, std::uint32_t)>;

// Throws Error for bad options (maps not fitting the distribution or order, resolution 0).
BuildResult build_csm(const Mesh& mesh, const BuildOptions& options, Runtime* runtime,
                      const BuildProgress& progress = {});

std::uint32_t default_batch_maps(std::uint32_t resolution, std::uint32_t maps);

// Maps of a grid captured batch by batch into host memory ([map][pixel]) with one capture method:
// on the device (MapCapture, read back) or, with no runtime, the native reference. The one capture
// path of everything that needs the maps on the host (losslessness check, compression modes,
// analyses); build_csm streams the same MapCapture's output to the compressor on the device.
class HostMapCapture {
 public:
  HostMapCapture(const Mesh& mesh, const SphereGrid& grid, const CaptureScene& scene, CaptureMethod method, Runtime* runtime,
                 std::uint32_t batch_maps);
  ~HostMapCapture();
  // Maps [first, first + count), count ≤ batch_maps.
  void get(std::uint32_t first, std::uint32_t count, std::vector<float>& z1, std::vector<float>& z2);

 private:
  const Mesh& mesh_;
  const SphereGrid& grid_;
  const CaptureScene& scene_;
  CaptureMethod method_;
  Runtime* runtime_;
  std::uint32_t batch_maps_;
  std::unique_ptr<MapCapture> capture_;
  cl::Buffer d1_, d2_;
};

// Losslessness check (Talpe §5.1.1): every (map, pixel) of `csm` recaptured from `mesh`
// and its stored depth tested with lossless(). Captures in batches on `runtime` (native reference
// when null) with the method recorded in the CSM, or `method` when given (a cross-check against
// the other method, which may report violations at triangle-edge pixels).
// Throws Error naming `mesh` (in the CSM's object space) unless the CSM's capture has its bounding
// sphere (to 1e-4 R; bounding_sphere is deterministic) and its count of casting triangles: a CSM of
// another model gives meaningless answers (csm verify reported it as not lossless, blaming the file).
void require_built_from(const Csm& csm, const Mesh& mesh);

inline constexpr std::uint64_t kMostEdgeSamples = 200;  // 0.5 %
struct LosslessReport {
  std::uint64_t samples = 0, violations = 0;
  // Cross-checks only (tolerance > 0): samples one capture method hits and the other misses (a ray
  // grazing a triangle's edge), not counted as violations while they are at most 1 / kMostEdgeSamples
  // of the samples; beyond, they are violations.
  std::uint64_t edge_disagreements = 0;
  std::uint32_t first_map = 0;
  std::size_t first_pixel = 0;
  float first_depth = 0, first_z1 = 0, first_z2 = 0;
  float tolerance = 0;  // depth units: twice the hit epsilon when recaptured by another method than the file's, else 0
};
// The model file's mesh is moved into object space by the CSM's stored object transform first.
// Throws Error (require_built_from) for a CSM of another model.
LosslessReport check_lossless(const Csm& csm, const Mesh& mesh, Runtime* runtime, const BuildProgress& progress = {},
                              std::optional<CaptureMethod> method = std::nullopt);

}  // namespace splatcl::csm
