#include "bench/peers/embree.hpp"

#include <embree3/rtcore.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <string>
#include <thread>

#include "runtime/error.hpp"

namespace splatcl::bench {
namespace {

constexpr int kPacket = 16;

std::string device_error(RTCDevice device, const char* what) {
  const RTCError code = rtcGetDeviceError(device);
  return std::string("Embree: ") + what + " failed (error " + std::to_string(static_cast<int>(code)) + ")";
}

}  // namespace

struct EmbreeCapturePeer::State {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  ~State() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

EmbreeCapturePeer::EmbreeCapturePeer(const std::vector<float>& corners) : state_(std::make_unique<State>()) {
  if (corners.empty() || corners.size() % 9 != 0) throw Error("Embree peer: expected 9 floats per triangle");
  state_->device = rtcNewDevice(nullptr);
  if (!state_->device) throw Error("Embree: cannot create a device");
  RTCDevice device = state_->device;
  state_->scene = rtcNewScene(device);
  if (!state_->scene) throw Error(device_error(device, "rtcNewScene"));
  rtcSetSceneBuildQuality(state_->scene, RTC_BUILD_QUALITY_HIGH);

  const std::size_t triangles = corners.size() / 9;
  RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* vertices = static_cast<float*>(
      rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), 3 * triangles));
  auto* indices = static_cast<unsigned*>(
      rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), triangles));
  if (!vertices || !indices) {
    rtcReleaseGeometry(geometry);
    throw Error(device_error(device, "allocating the triangle buffers"));
  }
  std::copy(corners.begin(), corners.end(), vertices);
  for (std::size_t k = 0; k < 3 * triangles; ++k) indices[k] = static_cast<unsigned>(k);
  rtcCommitGeometry(geometry);
  rtcAttachGeometry(state_->scene, geometry);
  rtcReleaseGeometry(geometry);
  rtcCommitScene(state_->scene);
  if (rtcGetDeviceError(device) != RTC_ERROR_NONE) throw Error(device_error(device, "building the scene"));
}

EmbreeCapturePeer::~EmbreeCapturePeer() = default;

const char* EmbreeCapturePeer::version() { return RTC_VERSION_STRING; }

EmbreeCapturePeer::Result EmbreeCapturePeer::capture(const std::vector<EmbreeCamera>& cameras, std::uint32_t resolution,
                                                     float radius, float eps, float* t1, float* t2) const {
  const std::size_t m = resolution, rows = cameras.size() * m, pixels = m * m;
  const float half_pixel = radius / static_cast<float>(resolution);
  std::atomic<std::size_t> next_row{0};
  std::atomic<std::uint64_t> rays{0}, first_hits{0}, second_hits{0};
  RTCScene scene = state_->scene;

  auto worker = [&] {
    alignas(64) RTCRayHit16 packet;
    alignas(64) int valid[kPacket];
    RTCIntersectContext context;
    std::uint64_t my_rays = 0, my_first = 0, my_second = 0;
    for (std::size_t item = next_row++; item < rows; item = next_row++) {
      const EmbreeCamera& cam = cameras[item / m];
      const std::size_t row = item % m;
      const float y = static_cast<float>(2 * row + 1) * half_pixel - radius;
      float* row_t1 = t1 + (item / m) * pixels + row * m;
      float* row_t2 = t2 + (item / m) * pixels + row * m;
      for (std::size_t first = 0; first < m; first += kPacket) {
        const std::size_t lanes = std::min<std::size_t>(kPacket, m - first);
        // First rays: a coherent packet of neighbouring pixels of one row.
        for (int lane = 0; lane < kPacket; ++lane) {
          valid[lane] = static_cast<std::size_t>(lane) < lanes ? -1 : 0;
          const float x = static_cast<float>(2 * (first + static_cast<std::size_t>(lane)) + 1) * half_pixel - radius;
          packet.ray.org_x[lane] = radius * cam.d[0] + x * cam.u[0] + y * cam.v[0];
          packet.ray.org_y[lane] = radius * cam.d[1] + x * cam.u[1] + y * cam.v[1];
          packet.ray.org_z[lane] = radius * cam.d[2] + x * cam.u[2] + y * cam.v[2];
          packet.ray.dir_x[lane] = -cam.d[0];
          packet.ray.dir_y[lane] = -cam.d[1];
          packet.ray.dir_z[lane] = -cam.d[2];
          packet.ray.tnear[lane] = 0.0f;
          packet.ray.tfar[lane] = INFINITY;
          packet.ray.time[lane] = 0.0f;
          packet.ray.mask[lane] = ~0u;
          packet.ray.id[lane] = static_cast<unsigned>(lane);
          packet.ray.flags[lane] = 0;
          packet.hit.geomID[lane] = RTC_INVALID_GEOMETRY_ID;
        }
        rtcInitIntersectContext(&context);
        context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
        rtcIntersect16(valid, scene, &context, &packet);
        my_rays += lanes;
        // Second rays: the lanes that hit, restarted just beyond their first hit.
        bool any = false;
        for (std::size_t lane = 0; lane < lanes; ++lane) {
          const bool hit = packet.hit.geomID[lane] != RTC_INVALID_GEOMETRY_ID;
          row_t1[first + lane] = hit ? packet.ray.tfar[lane] : INFINITY;
          row_t2[first + lane] = INFINITY;
          if (!hit) {
            valid[lane] = 0;
            continue;
          }
          ++my_first;
          any = true;
          packet.ray.tnear[lane] = packet.ray.tfar[lane] + eps;
          packet.ray.tfar[lane] = INFINITY;
          packet.hit.geomID[lane] = RTC_INVALID_GEOMETRY_ID;
        }
        if (!any) continue;
        rtcInitIntersectContext(&context);
        context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
        rtcIntersect16(valid, scene, &context, &packet);
        for (std::size_t lane = 0; lane < lanes; ++lane) {
          if (!valid[lane]) continue;
          ++my_rays;
          if (packet.hit.geomID[lane] == RTC_INVALID_GEOMETRY_ID) continue;
          row_t2[first + lane] = packet.ray.tfar[lane];
          ++my_second;
        }
      }
    }
    rays += my_rays;
    first_hits += my_first;
    second_hits += my_second;
  };

  const unsigned threads = std::max(1u, std::thread::hardware_concurrency());
  std::vector<std::thread> pool;
  for (unsigned k = 1; k < threads; ++k) pool.emplace_back(worker);
  worker();
  for (auto& thread : pool) thread.join();
  if (rtcGetDeviceError(state_->device) != RTC_ERROR_NONE) throw Error(device_error(state_->device, "rtcIntersect16"));
  return {rays.load(), first_hits.load(), second_hits.load()};
}

}  // namespace splatcl::bench
