#pragma once
// Embree 3 as the capture peer of `splatcl bench csm`: the same first- and second-hit rays as the
// CSM capture (one orthographic ray per pixel of every map; where it hits, a second ray from just
// beyond the first hit, so a hit within `eps` of the first is the same surface), cast in packets of
// 16 with rtcIntersect16 on every core. The interface includes no Embree header, like the
// Boost.Compute peer, so only splatcl_peers needs Embree.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

namespace splatcl::bench {

inline constexpr const char* kImplEmbree = "embree";

// An orthographic camera as the capture defines it: rays start on the plane through radius·d
// spanned by u and v, and travel along −d.
struct EmbreeCamera {
  float d[3], u[3], v[3];
};

class EmbreeCapturePeer {
 public:
  // `corners` holds 9 floats per triangle (three xyz corners), relative to the sphere centre.
  // Throws Error when Embree cannot create its device or build the scene.
  explicit EmbreeCapturePeer(const std::vector<float>& corners);
  ~EmbreeCapturePeer();
  EmbreeCapturePeer(const EmbreeCapturePeer&) = delete;
  EmbreeCapturePeer& operator=(const EmbreeCapturePeer&) = delete;

  struct Result {
    std::uint64_t rays = 0;          // Embree rays cast: first rays plus second rays
    std::uint64_t first_hits = 0;    // pixels with a first hit
    std::uint64_t second_hits = 0;   // pixels with a second, distinct hit
  };
  // For every camera, resolution² pixels (pixel (i, j) at x = (2i + 1)·R/M − R along u, y likewise
  // along v, index j·M + i): the first and second hit distances (INFINITY where none) written to
  // t1 and t2 laid out [camera][pixel]. Multithreaded over pixel rows.
  Result capture(const std::vector<EmbreeCamera>& cameras, std::uint32_t resolution, float radius, float eps,
                 float* t1, float* t2) const;

  // Embree's version string, for records.
  static const char* version();

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace splatcl::bench
