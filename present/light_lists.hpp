#pragma once
// Where the shading finds each pixel's point lights: the light-list stage of a frame, one
// interchangeable implementation per quality.shading.
//   ClusteredLightLists: clusters of the frame's depth on the CL device (cluster::ClusterPipeline:
//     keys → compaction → bounds → light assignment), one list per occupied cluster
//   TiledLightLists: one list per screen tile over its depth range, on the host (cluster/tiled.hpp)
//   BruteForceLights: no lists; the shading loops over every light
#include <cstdint>
#include <memory>
#include <vector>

#include "cluster/cluster.hpp"
#include "present/presenter.hpp"

namespace splatcl::present {

struct FrameLightLists {
  std::vector<std::uint32_t> pixel_list;  // per pixel its list, cluster::kNoCluster for none
  cluster::LightLists lists;
  std::uint32_t clusters = 0, light_indices = 0;  // lists made and indices in them (FrameStats)
};

class LightListBuilder {
 public:
  virtual ~LightListBuilder() = default;
  // True when the shading loops over every light instead of reading lists.
  virtual bool brute_force() const { return false; }
  // Lists for the frame's view-space z per pixel (0 = background) and view-space lights; appends
  // the time of each of its stages.
  virtual FrameLightLists build(const std::vector<float>& view_z, const std::vector<cluster::PointLight>& lights,
                                std::vector<StageTime>& stages) = 0;
  // The screen layout of the lists (tiles and depth slices).
  virtual const cluster::ClusterLayout& layout() const = 0;
};

class ClusteredLightLists final : public LightListBuilder {
 public:
  ClusteredLightLists(Runtime& runtime, const cluster::ClusterConfig& config);
  FrameLightLists build(const std::vector<float>& view_z, const std::vector<cluster::PointLight>& lights,
                        std::vector<StageTime>& stages) override;
  const cluster::ClusterLayout& layout() const override { return pipeline_.layout(); }

 private:
  cluster::ClusterPipeline pipeline_;
};

class TiledLightLists final : public LightListBuilder {
 public:
  explicit TiledLightLists(const cluster::ClusterLayout& layout) : layout_(layout) {}
  FrameLightLists build(const std::vector<float>& view_z, const std::vector<cluster::PointLight>& lights,
                        std::vector<StageTime>& stages) override;
  const cluster::ClusterLayout& layout() const override { return layout_; }

 private:
  cluster::ClusterLayout layout_;
};

class BruteForceLights final : public LightListBuilder {
 public:
  explicit BruteForceLights(const cluster::ClusterLayout& layout) : layout_(layout) {}
  bool brute_force() const override { return true; }
  FrameLightLists build(const std::vector<float>& view_z, const std::vector<cluster::PointLight>& lights,
                        std::vector<StageTime>& stages) override;
  const cluster::ClusterLayout& layout() const override { return layout_; }

 private:
  cluster::ClusterLayout layout_;
};

}  // namespace splatcl::present
