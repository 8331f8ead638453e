#pragma once
// Clustered-shading back end on OpenCL (Tegelaers §3.3): per-pixel cluster keys,
// sort/compaction to the unique clusters with a per-pixel cluster index, cluster bounds, and light
// lists per cluster. Kernels: kernels/cluster.cl, kernels/cluster_lights.cl. Native reference:
// cluster/reference.hpp.
//
// ClusterPipeline keeps every buffer on the device across stages and frames; each stage can be
// called on its own and records its kernels in an optional Profiler (pass a fresh one per stage to
// time stages). The only host reads are the cluster count and the light-index count, which size
// the following launches.
#include <cstdint>
#include <string>
#include <vector>

#include "cluster/layout.hpp"
#include "cluster/types.hpp"
#include "primitives/primitives.hpp"
#include "runtime/profiling.hpp"
#include "runtime/runtime.hpp"

namespace splatcl::cluster {

// How the unique clusters are found; all three give identical results.
enum class Compaction {
  // Radix sort of (key, pixel) over the whole frame on key_bits bits, then run flags, scan, scatter.
  GlobalSort,
  // The thesis's per-tile sort, then a scan of the tile counts and a scatter. CPU shape: one
  // work-item per tile, serial counting/radix sort; GPU shape: one work-group per tile, bitonic
  // sort in local memory and a work-group scan. Tiles of at most max_sort_tile_pixels(): the GPU
  // shape's local memory grows with the tile and must fit the device's.
  TileSort,
  // Per tile, a bit mask over the (slice, normal) values; popcounts rank them, no sort. Mask and
  // count kernel, scan of the tile counts, write kernel. At most kMaxBitmaskLowBits low key bits.
  // The fastest on CPUs.
  TileBitmask,
};

// How lights are assigned to clusters; both give identical lists (light indices ascending).
enum class Assignment {
  // Every cluster tests every light (8 at a time): count, scan, fill.
  BruteForce,
  // A BVH over the lights sorted by Morton code (fanout kBvhFanout), rebuilt on every call. One
  // traversal per cluster counts its lights and leaves lists of up to 256 sorted in a per-cluster
  // slot; after the scan a second kernel copies them into place (longer lists are found again and
  // radix-sorted there).
  Hierarchy,
};

// Fanout of the light hierarchy and lights per leaf: the kernels test 8 boxes or lights at once.
inline constexpr std::uint32_t kBvhFanout = 8;

const char* to_string(Compaction compaction);
const char* to_string(Assignment assignment);
// "global-sort", "tile-sort", "bitmask"; "brute", "bvh". Throws Error for anything else.
Compaction parse_compaction(const std::string& text);
Assignment parse_assignment(const std::string& text);

// Work-group size of the GPU-shaped tile sort for tiles of `tile_pixels`: half the padded tile, at
// most 256 and at most the device's work-group limit (a power of two: the sort splits evenly).
std::size_t tile_sort_group(const DeviceInfo& device, std::uint32_t tile_pixels);
// Local memory of the GPU-shaped tile sort: a (key, pixel) pair per padded tile pixel and a scan slot
// per work-item.
std::size_t tile_sort_local_bytes(const DeviceInfo& device, std::uint32_t tile_pixels);
// Largest tile (pixels) the tile-sort compaction accepts in `shape` on `device`: kMaxSortTilePixels,
// or for the GPU shape the largest power of two whose local memory fits the device (64×64 tiles need
// 33,792 B: 32 KiB devices sort up to 2048 pixels).
std::uint32_t max_sort_tile_pixels(const DeviceInfo& device, Shape shape);

class ClusterPipeline {
 public:
  // Validates the config (see ClusterLayout::make) and allocates the per-pixel buffers. `shape`
  // chooses the per-tile sort kernel and the shapes of the scan and radix sort.
  ClusterPipeline(Runtime& runtime, const ClusterConfig& config, Shape shape = Shape::Auto);
  ClusterPipeline(const ClusterPipeline&) = delete;  // owns device buffers
  ClusterPipeline& operator=(const ClusterPipeline&) = delete;

  const ClusterLayout& layout() const { return layout_; }
  Shape shape() const { return shape_; }

  // ---- inputs (row 0 = bottom; sizes must match the frame)
  void upload_depth(const std::vector<float>& depth, DepthFormat format);
  // View-space unit normals, one per pixel; needed only when the config asks for normal bits.
  void upload_normals(const std::vector<Vec3>& normals);
  // View-space lights. Throws Error for a non-finite centre or a negative or non-finite radius.
  void upload_lights(const std::vector<PointLight>& lights);

  // ---- stages, in this order; each needs the previous one (Error otherwise)
  void compute_keys(Profiler* profiler = nullptr);
  // Returns the number of unique clusters.
  std::uint32_t compact(Compaction compaction, Profiler* profiler = nullptr);
  void compute_bounds(Profiler* profiler = nullptr);
  // Returns the total length of the light-index list.
  std::uint32_t assign_lights(Assignment assignment, Profiler* profiler = nullptr);
  // Waits until every queued stage has finished (for wall-clock timing).
  void finish();

  std::uint32_t cluster_count() const { return cluster_count_; }
  std::uint32_t light_index_count() const { return light_index_count_; }
  std::uint32_t light_count() const { return light_count_; }

  // ---- device results, valid after their stage (for the presenter; sizes as documented)
  const cl::Buffer& keys_buffer() const { return keys_; }                    // uint per pixel
  const cl::Buffer& pixel_cluster_buffer() const { return pixel_cluster_; }  // uint per pixel
  const cl::Buffer& unique_keys_buffer() const { return unique_keys_; }      // uint per cluster
  const cl::Buffer& bounds_buffer() const { return bounds_; }                // float4 (min, max) per cluster
  const cl::Buffer& light_offsets_buffer() const { return light_offsets_; }  // uint per cluster
  const cl::Buffer& light_counts_buffer() const { return light_counts_; }    // uint per cluster
  const cl::Buffer& light_indices_buffer() const { return light_indices_; }  // uint per list entry

  // ---- downloads (blocking)
  std::vector<std::uint32_t> download_keys();
  ClusterList download_clusters();
  std::vector<ClusterBox> download_bounds();
  LightLists download_light_lists();

 private:
  enum class Stage { None, Input, Keys, Compacted, Bounded, Assigned };
  void require(Stage stage, const char* what) const;
  void ensure_capacity(cl::Buffer& buffer, std::size_t& capacity, std::size_t bytes, const char* what);
  void compact_global_sort(Profiler* profiler);
  void compact_tiles(Compaction compaction, Profiler* profiler);
  void build_light_hierarchy(Profiler* profiler);

  Runtime& runtime_;
  ClusterLayout layout_;
  Shape shape_;
  Stage stage_ = Stage::None;
  bool window_depth_ = false;
  bool have_normals_ = false;
  std::uint32_t cluster_count_ = 0;
  std::uint32_t light_count_ = 0;
  std::uint32_t light_index_count_ = 0;
  std::uint32_t light_stride_ = 0;  // light count rounded up to kBvhFanout (SoA block length)
  std::uint32_t bvh_levels_ = 0;
  float morton_origin_[4] = {};
  float morton_scale_[4] = {};

  primitives::Scanner scanner_;
  primitives::RadixSorter pair_sorter_;  // (key, pixel) of the frame and (Morton code, light)

  cl::Kernel keys_view_kernel_, keys_window_kernel_, sort_init_kernel_, run_starts_kernel_, sorted_scatter_kernel_;
  cl::Kernel tile_sort_kernel_, tile_scatter_kernel_, tile_mask_kernel_, tile_mask_write_kernel_, bounds_kernel_;
  cl::Kernel brute_count_kernel_, brute_fill_kernel_, morton_kernel_, gather_kernel_, leaf_boxes_kernel_,
      node_boxes_kernel_;
  cl::Kernel bvh_collect_kernel_, bvh_place_kernel_;
  std::size_t tile_sort_group_ = 1;  // work-group size of the tile sort (GPU shape) / tile scatter

  // Per pixel.
  cl::Buffer depth_, normals_, keys_, pixel_cluster_;
  cl::Buffer sort_keys_, sort_pixels_, run_ends_;  // global-sort scratch, allocated on first use
  // Per tile.
  cl::Buffer slice_boundaries_, tile_counts_, tile_offsets_;
  cl::Buffer staging_;                   // tile sort, allocated on first use
  cl::Buffer tile_masks_, mask_ranges_;  // bitmask compaction, allocated on first use
  // Per cluster (capacity grows).
  cl::Buffer unique_keys_, bounds_, light_counts_, light_offsets_;
  std::size_t bounds_capacity_ = 0, light_counts_capacity_ = 0, light_offsets_capacity_ = 0;
  // Per light (capacity grows); lights are SoA: x | y | z | radius blocks of light_stride_ floats.
  cl::Buffer lights_, morton_codes_, light_order_, sorted_lights_, bvh_nodes_, light_indices_;
  std::size_t lights_capacity_ = 0, morton_capacity_ = 0, order_capacity_ = 0, sorted_lights_capacity_ = 0;
  std::size_t nodes_capacity_ = 0, indices_capacity_ = 0;
  // Per-cluster slots where the hierarchy traversal leaves sorted lists for the placing pass, and
  // the scratch of the radix sort of lists too long for them.
  cl::Buffer list_scratch_, list_sort_scratch_;
  std::size_t list_sort_scratch_capacity_ = 0;
  cl::Buffer lane_compaction_;  // 256 uchar8: the set lanes of each 8-bit mask first
  std::size_t list_scratch_capacity_ = 0;
};

}  // namespace splatcl::cluster
