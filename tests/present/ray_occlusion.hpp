#pragma once
// An ambient-occlusion oracle independent of the CSMs: rays cast with Embree on the scene objects'
// triangle meshes at their placements. Available where the build found Embree (the benchmark
// peers, SPLATCL_BUILD_BENCH_PEERS); SPLATCL_TEST_EMBREE says so.
#ifdef SPLATCL_TEST_EMBREE
#include <embree3/rtcore.h>

#include <cmath>
#include <numbers>
#include <optional>
#include <vector>

#include <glm/glm.hpp>

#include "present/presenter.hpp"
#include "runtime/error.hpp"

namespace splatcl::present::testing {

class RayOcclusion {
 public:
  // The occluder objects of `presenter`'s scene, placed at `time`.
  RayOcclusion(Presenter& presenter, float time) {
    device_ = rtcNewDevice(nullptr);
    if (!device_) throw Error("Embree: cannot create a device");
    scene_ = rtcNewScene(device_);
    const Scene& scene = presenter.scene();
    for (std::size_t i = 0; i < scene.objects.size(); ++i) {
      if (!scene.objects[i].occluder) continue;
      const Mesh& mesh = presenter.assets(i).mesh;
      const glm::mat4 m = scene.objects[i].placement(time);
      std::vector<glm::vec3> corners;
      for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        const std::uint32_t begin = mesh.face_offsets[f], end = mesh.face_offsets[f + 1];
        for (std::uint32_t c = begin + 1; c + 1 < end; ++c)
          for (const std::uint32_t corner : {begin, c, c + 1}) {
            const Vec3 p = mesh.vertices[mesh.corners[corner]];
            corners.push_back(glm::vec3(m * glm::vec4(p.x, p.y, p.z, 1.0f)));
          }
      }
      const std::size_t triangles = corners.size() / 3;
      RTCGeometry geometry = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
      auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                                   3 * sizeof(float), corners.size()));
      auto* indices = static_cast<unsigned*>(
          rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), triangles));
      for (std::size_t k = 0; k < corners.size(); ++k) {
        vertices[3 * k] = corners[k].x, vertices[3 * k + 1] = corners[k].y, vertices[3 * k + 2] = corners[k].z;
        indices[k] = static_cast<unsigned>(k);
      }
      rtcCommitGeometry(geometry);
      rtcAttachGeometry(scene_, geometry);
      rtcReleaseGeometry(geometry);
    }
    rtcCommitScene(scene_);
    if (rtcGetDeviceError(device_) != RTC_ERROR_NONE) throw Error("Embree: building the scene failed");
  }
  ~RayOcclusion() {
    rtcReleaseScene(scene_);
    rtcReleaseDevice(device_);
  }
  RayOcclusion(const RayOcclusion&) = delete;
  RayOcclusion& operator=(const RayOcclusion&) = delete;

  // Does the ray from `origin` along unit `direction` hit a mesh beyond `t_near`?
  bool occluded(glm::vec3 origin, glm::vec3 direction, float t_near) const {
    RTCRay ray{};
    ray.org_x = origin.x, ray.org_y = origin.y, ray.org_z = origin.z;
    ray.dir_x = direction.x, ray.dir_y = direction.y, ray.dir_z = direction.z;
    ray.tnear = t_near;
    ray.tfar = INFINITY;
    ray.mask = ~0u;
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    rtcOccluded1(scene_, &context, &ray);
    return ray.tfar < 0.0f;  // Embree sets tfar to −∞ on a hit
  }

  struct Hit {
    glm::vec3 position, normal;  // the unit geometric normal, facing the ray's origin
  };
  // The nearest mesh surface along the ray.
  std::optional<Hit> nearest(glm::vec3 origin, glm::vec3 direction) const {
    RTCRayHit hit{};
    hit.ray.org_x = origin.x, hit.ray.org_y = origin.y, hit.ray.org_z = origin.z;
    hit.ray.dir_x = direction.x, hit.ray.dir_y = direction.y, hit.ray.dir_z = direction.z;
    hit.ray.tnear = 0.0f;
    hit.ray.tfar = INFINITY;
    hit.ray.mask = ~0u;
    hit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    rtcIntersect1(scene_, &context, &hit);
    if (hit.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;
    glm::vec3 n = glm::normalize(glm::vec3(hit.hit.Ng_x, hit.hit.Ng_y, hit.hit.Ng_z));
    if (glm::dot(n, direction) > 0.0f) n = -n;
    return Hit{origin + hit.ray.tfar * direction, n};
  }

  // The presenter's AO definition at a surface point with unit normal n, integrated finely: the
  // cosine-weighted share of n's hemisphere whose rays leave every mesh (self-occlusion included)
  // and, with `ground`, point up (an infinite floor takes every downward direction). strata² rays
  // on a stratified, jittered cosine-weighted grid (Shirley's concentric map would do as well).
  float ambient_occlusion(glm::vec3 p, glm::vec3 n, bool ground, int strata, std::uint32_t seed) const {
    const glm::vec3 a = std::abs(n.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
    const glm::vec3 t = glm::normalize(glm::cross(n, a)), b = glm::cross(n, t);
    std::uint32_t state = seed * 747796405u + 2891336453u;
    const auto uniform = [&] {
      state = state * 1664525u + 1013904223u;
      return static_cast<float>(state >> 8) / 16777216.0f;
    };
    // Off the surface by a hair, far below any feature of the meshes, so the start triangle is not hit.
    const glm::vec3 origin = p + 1e-4f * n;
    int lit = 0;
    for (int i = 0; i < strata; ++i)
      for (int k = 0; k < strata; ++k) {
        const float u = (static_cast<float>(i) + uniform()) / static_cast<float>(strata);
        const float v = (static_cast<float>(k) + uniform()) / static_cast<float>(strata);
        const float r = std::sqrt(u), phi = 2.0f * std::numbers::pi_v<float> * v;
        const glm::vec3 d = glm::normalize(r * std::cos(phi) * t + r * std::sin(phi) * b + std::sqrt(std::max(0.0f, 1.0f - u)) * n);
        if (ground && d.y < 0.0f) continue;
        lit += !occluded(origin, d, 0.0f);
      }
    return static_cast<float>(lit) / static_cast<float>(strata * strata);
  }

 private:
  RTCDevice device_ = nullptr;
  RTCScene scene_ = nullptr;
};

}  // namespace splatcl::present::testing
#endif
