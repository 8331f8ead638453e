#include "cluster/cluster.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

#include "runtime/error.hpp"

namespace splatcl::cluster {
namespace {

constexpr const char* kClusterKernels = "cluster.cl";
constexpr const char* kLightKernels = "cluster_lights.cl";

// Launch shapes. Per-pixel kernels: 32×8 blocks (PoCL vectorizes along x; measured fastest on
// PoCL 3.1 against 64×1, 64×4, 128×8 and 16×8). Per-tile CPU-shaped kernels: a few tiles per
// work-group, one work-item each. GPU-shaped tile kernels: a work-group per tile.
constexpr std::size_t kPixelGroupWidth = 32;
constexpr std::size_t kPixelGroupHeight = 8;
constexpr std::size_t kCpuTileGroup = 8;
constexpr std::size_t kGpuTileScatterGroup = 64;
constexpr std::size_t kGpuSortGroupMax = 256;
constexpr std::size_t kItemGroup = 64;  // per-element and per-cluster kernels

constexpr std::uint32_t kBvhMaxLevels = 16;
constexpr std::uint32_t kBvhStack = 80;
constexpr std::uint32_t kMaxLights = 1u << 26;
constexpr unsigned kMortonBits = 30;
// Light-list slots of the hierarchy traversal: up to kListSlotMax entries per cluster (a multiple
// of 16), within kListScratchEntries in total. Lists of up to kRankSortMax lights are sorted by
// rank (O(n²), vectorized), longer ones by radix.
constexpr std::size_t kListSlotMax = 256;
constexpr std::size_t kRankSortMax = 64;
constexpr std::size_t kListScratchEntries = std::size_t{16} << 20;

// The kernels write their background key (the BACKGROUND build option) as the cluster index of a
// background pixel too.
static_assert(kNoCluster == kBackgroundKey, "a background pixel's key and cluster index are one value");

cl_uint to_uint(std::size_t value) { return static_cast<cl_uint>(value); }

// Bytes of one float4 pair (min, max) per cluster.
constexpr std::size_t kBoxBytes = 8 * sizeof(float);
// Bytes of one hierarchy node: its children's boxes, six float8.
constexpr std::size_t kNodeBytes = 6 * kBvhFanout * sizeof(float);

// Level sizes of the light hierarchy: level 0 = leaves (8-light blocks), the last level is the
// single root.
std::vector<std::uint32_t> bvh_level_sizes(std::uint32_t leaf_count) {
  std::vector<std::uint32_t> sizes{leaf_count};
  while (sizes.back() > 1) sizes.push_back((sizes.back() + kBvhFanout - 1) / kBvhFanout);
  return sizes;
}

std::uint32_t sort_padded(std::uint32_t tile_pixels) { return std::max<std::uint32_t>(2, std::bit_ceil(tile_pixels)); }

std::string cluster_build_options(const Runtime& runtime, const ClusterLayout& layout, Shape shape,
                                  std::size_t sort_group) {
  const ClusterConfig& c = layout.config;
  std::string options = "-DTILE_W=" + std::to_string(c.tile_width) + " -DTILE_H=" + std::to_string(c.tile_height) +
                        " -DNORMAL_BITS=" + std::to_string(layout.normal_bits) +
                        " -DBACKGROUND=" + std::to_string(kBackgroundKey) + "u" +
                        " -DMAX_BITMASK_LOW_BITS=" + std::to_string(kMaxBitmaskLowBits) +
                        " -DMAX_SORT_TILE_PIXELS=" + std::to_string(kMaxSortTilePixels);
  const std::uint32_t tile_pixels = c.tile_width * c.tile_height;
  if (shape == Shape::Gpu && tile_pixels <= max_sort_tile_pixels(runtime.info(), shape))
    options += " -DSORT_N=" + std::to_string(sort_padded(tile_pixels)) + " -DSORT_GROUP=" + std::to_string(sort_group);
  // The window-depth conversion divides; keys must match the host reference bit for bit.
  return options + runtime.exact_divide_option();
}

}  // namespace

std::size_t tile_sort_group(const DeviceInfo& device, std::uint32_t tile_pixels) {
  const std::size_t device_limit = std::bit_floor(std::max<std::size_t>(1, device.max_work_group_size));
  return std::min({kGpuSortGroupMax, std::size_t{sort_padded(tile_pixels)} / 2, device_limit});
}

std::size_t tile_sort_local_bytes(const DeviceInfo& device, std::uint32_t tile_pixels) {
  return (2 * std::size_t{sort_padded(tile_pixels)} + tile_sort_group(device, tile_pixels)) * sizeof(std::uint32_t);
}

std::uint32_t max_sort_tile_pixels(const DeviceInfo& device, Shape shape) {
  if (shape == Shape::Auto) shape = device.type == "cpu" ? Shape::Cpu : Shape::Gpu;  // as Runtime::resolve
  if (shape != Shape::Gpu) return kMaxSortTilePixels;
  std::uint32_t pixels = kMaxSortTilePixels;
  while (pixels > 2 && tile_sort_local_bytes(device, pixels) > device.local_mem_bytes) pixels /= 2;
  return tile_sort_local_bytes(device, pixels) <= device.local_mem_bytes ? pixels : 0;
}

const char* to_string(Compaction compaction) {
  switch (compaction) {
    case Compaction::GlobalSort: return "global-sort";
    case Compaction::TileSort: return "tile-sort";
    default: return "bitmask";
  }
}

const char* to_string(Assignment assignment) { return assignment == Assignment::BruteForce ? "brute" : "bvh"; }

Compaction parse_compaction(const std::string& text) {
  for (auto c : {Compaction::GlobalSort, Compaction::TileSort, Compaction::TileBitmask})
    if (text == to_string(c)) return c;
  throw Error("unknown compaction '" + text + "' (expected global-sort, tile-sort or bitmask)");
}

Assignment parse_assignment(const std::string& text) {
  for (auto a : {Assignment::BruteForce, Assignment::Hierarchy})
    if (text == to_string(a)) return a;
  throw Error("unknown light assignment '" + text + "' (expected brute or bvh)");
}

ClusterPipeline::ClusterPipeline(Runtime& runtime, const ClusterConfig& config, Shape shape)
    : runtime_(runtime),
      layout_(ClusterLayout::make(config)),
      shape_(runtime.resolve(shape)),
      scanner_(runtime, shape_),
      pair_sorter_(runtime, primitives::KeyType::U32, true, shape_) {
  const std::uint32_t tile_pixels = config.tile_width * config.tile_height;
  tile_sort_group_ = shape_ == Shape::Gpu ? tile_sort_group(runtime.info(), tile_pixels) : 1;
  const std::string options = cluster_build_options(runtime, layout_, shape_, tile_sort_group_);
  const std::string light_options = "-DLANES=" + std::to_string(kBvhFanout) +
                                    " -DBVH_MAX_LEVELS=" + std::to_string(kBvhMaxLevels) +
                                    " -DBVH_STACK=" + std::to_string(kBvhStack) +
                                    " -DRANK_SORT_MAX=" + std::to_string(kRankSortMax);
  keys_view_kernel_ = runtime.kernel(kClusterKernels, "cluster_keys_view", options);
  keys_window_kernel_ = runtime.kernel(kClusterKernels, "cluster_keys_window", options);
  sort_init_kernel_ = runtime.kernel(kClusterKernels, "cluster_sort_init", options);
  run_starts_kernel_ = runtime.kernel(kClusterKernels, "cluster_run_starts", options);
  sorted_scatter_kernel_ = runtime.kernel(kClusterKernels, "cluster_sorted_scatter", options);
  tile_scatter_kernel_ = runtime.kernel(kClusterKernels, "cluster_tile_scatter", options);
  tile_mask_kernel_ = runtime.kernel(kClusterKernels, "cluster_tile_mask", options);
  tile_mask_write_kernel_ = runtime.kernel(kClusterKernels, "cluster_tile_mask_write", options);
  bounds_kernel_ = runtime.kernel(kClusterKernels, "cluster_bounds", options);
  if (tile_pixels <= max_sort_tile_pixels(runtime.info(), shape_))
    tile_sort_kernel_ = runtime.kernel(
        kClusterKernels, shape_ == Shape::Gpu ? "cluster_tile_sort_gpu" : "cluster_tile_sort_cpu", options);
  brute_count_kernel_ = runtime.kernel(kLightKernels, "assign_brute_count", light_options);
  brute_fill_kernel_ = runtime.kernel(kLightKernels, "assign_brute_fill", light_options);
  morton_kernel_ = runtime.kernel(kLightKernels, "lights_morton", light_options);
  gather_kernel_ = runtime.kernel(kLightKernels, "bvh_gather", light_options);
  leaf_boxes_kernel_ = runtime.kernel(kLightKernels, "bvh_leaf_boxes", light_options);
  node_boxes_kernel_ = runtime.kernel(kLightKernels, "bvh_node_boxes", light_options);
  bvh_collect_kernel_ = runtime.kernel(kLightKernels, "assign_bvh_collect", light_options);
  bvh_place_kernel_ = runtime.kernel(kLightKernels, "assign_bvh_place", light_options);

  const std::size_t pixels = layout_.pixel_count();
  const std::size_t tiles = layout_.tile_count;
  depth_ = runtime.buffer(CL_MEM_READ_ONLY, pixels * sizeof(float), "the depth buffer");
  keys_ = runtime.buffer(CL_MEM_READ_WRITE, pixels * sizeof(std::uint32_t), "cluster keys");
  pixel_cluster_ = runtime.buffer(CL_MEM_READ_WRITE, pixels * sizeof(std::uint32_t), "the pixel cluster index");
  unique_keys_ = runtime.buffer(CL_MEM_READ_WRITE, pixels * sizeof(std::uint32_t), "unique cluster keys");
  tile_counts_ = runtime.buffer(CL_MEM_READ_WRITE, tiles * sizeof(std::uint32_t), "tile cluster counts");
  tile_offsets_ = runtime.buffer(CL_MEM_READ_WRITE, tiles * sizeof(std::uint32_t), "tile cluster offsets");
  slice_boundaries_ = runtime.buffer(CL_MEM_READ_ONLY, layout_.slice_boundaries.size() * sizeof(float),
                                     "depth slice boundaries");
  // Lane order per 8-bit hit mask with the set lanes first, for 8-wide writes of a leaf's hits.
  std::vector<cl_uchar> compaction(256 * kBvhFanout, 0);
  for (unsigned bits = 0; bits < 256; ++bits) {
    unsigned next = 0;
    for (unsigned lane = 0; lane < kBvhFanout; ++lane)
      if (bits & (1u << lane)) compaction[bits * kBvhFanout + next++] = static_cast<cl_uchar>(lane);
  }
  lane_compaction_ = runtime.buffer(CL_MEM_READ_ONLY, compaction.size(), "the lane compaction table");
  try {
    runtime.queue().enqueueWriteBuffer(slice_boundaries_, CL_TRUE, 0, layout_.slice_boundaries.size() * sizeof(float),
                                       layout_.slice_boundaries.data());
    runtime.queue().enqueueWriteBuffer(lane_compaction_, CL_TRUE, 0, compaction.size(), compaction.data());
  } catch (...) {
    rethrow_as_error("uploading cluster lookup tables");
  }
}

void ClusterPipeline::require(Stage stage, const char* what) const {
  if (stage_ >= stage) return;
  static const char* const needs[] = {"", "upload_depth()", "compute_keys()", "compact()", "compute_bounds()",
                                      "assign_lights()"};
  throw Error(std::string("ClusterPipeline: ") + what + " needs " + needs[static_cast<int>(stage)] + " first");
}

void ClusterPipeline::ensure_capacity(cl::Buffer& buffer, std::size_t& capacity, std::size_t bytes, const char* what) {
  if (bytes <= capacity) return;
  const std::size_t grown = std::max({bytes, capacity + capacity / 2, std::size_t{16}});
  buffer = runtime_.buffer(CL_MEM_READ_WRITE, grown, what);
  capacity = grown;
}

void ClusterPipeline::upload_depth(const std::vector<float>& depth, DepthFormat format) {
  if (depth.size() != layout_.pixel_count())
    throw Error("depth buffer has " + std::to_string(depth.size()) + " values; the " +
                std::to_string(layout_.config.width) + "x" + std::to_string(layout_.config.height) + " frame needs " +
                std::to_string(layout_.pixel_count()));
  try {
    runtime_.queue().enqueueWriteBuffer(depth_, CL_TRUE, 0, depth.size() * sizeof(float), depth.data());
  } catch (...) {
    rethrow_as_error("uploading the depth buffer");
  }
  window_depth_ = format == DepthFormat::Window;
  stage_ = Stage::Input;
}

void ClusterPipeline::upload_normals(const std::vector<Vec3>& normals) {
  static_assert(sizeof(Vec3) == 3 * sizeof(float), "normals are uploaded as packed float triples");
  if (normals.size() != layout_.pixel_count())
    throw Error("normal buffer has " + std::to_string(normals.size()) + " values; the frame needs " +
                std::to_string(layout_.pixel_count()));
  if (!have_normals_)
    normals_ = runtime_.buffer(CL_MEM_READ_ONLY, normals.size() * sizeof(Vec3), "the normal buffer");
  try {
    runtime_.queue().enqueueWriteBuffer(normals_, CL_TRUE, 0, normals.size() * sizeof(Vec3), normals.data());
  } catch (...) {
    rethrow_as_error("uploading the normal buffer");
  }
  have_normals_ = true;
  stage_ = std::min(stage_, Stage::Input);
}

void ClusterPipeline::upload_lights(const std::vector<PointLight>& lights) {
  if (lights.size() > kMaxLights)
    throw Error("too many lights: " + std::to_string(lights.size()) + " (at most " + std::to_string(kMaxLights) + ")");
  const std::size_t stride = round_up(lights.size(), kBvhFanout);
  // SoA blocks x | y | z | radius; padding lights at +infinity with radius 0 touch nothing.
  std::vector<float> packed(4 * stride, std::numeric_limits<float>::infinity());
  std::fill(packed.begin() + static_cast<std::ptrdiff_t>(3 * stride), packed.end(), 0.0f);
  constexpr float kHuge = std::numeric_limits<float>::max();
  float lo[3] = {kHuge, kHuge, kHuge}, hi[3] = {-kHuge, -kHuge, -kHuge};
  for (std::size_t i = 0; i < lights.size(); ++i) {
    const PointLight& light = lights[i];
    const float centre[3] = {light.center.x, light.center.y, light.center.z};
    for (std::size_t a = 0; a < 3; ++a) {
      if (!std::isfinite(centre[a])) throw Error("light " + std::to_string(i) + " has a non-finite centre");
      lo[a] = std::min(lo[a], centre[a]);
      hi[a] = std::max(hi[a], centre[a]);
      packed[a * stride + i] = centre[a];
    }
    if (!(std::isfinite(light.radius) && light.radius >= 0))
      throw Error("light " + std::to_string(i) + " has radius " + std::to_string(light.radius) +
                  "; expected a finite value >= 0");
    packed[3 * stride + i] = light.radius;
  }
  for (int a = 0; a < 3; ++a) {
    const float extent = hi[a] - lo[a];
    morton_origin_[a] = lights.empty() ? 0.0f : lo[a];
    morton_scale_[a] = extent > 0 ? 1023.0f / extent : 0.0f;
  }
  light_count_ = static_cast<std::uint32_t>(lights.size());
  light_stride_ = static_cast<std::uint32_t>(stride);
  if (!lights.empty()) {
    ensure_capacity(lights_, lights_capacity_, packed.size() * sizeof(float), "lights");
    try {
      runtime_.queue().enqueueWriteBuffer(lights_, CL_TRUE, 0, packed.size() * sizeof(float), packed.data());
    } catch (...) {
      rethrow_as_error("uploading lights");
    }
  }
  stage_ = std::min(stage_, Stage::Bounded);
}

void ClusterPipeline::compute_keys(Profiler* profiler) {
  require(Stage::Input, "compute_keys()");
  if (layout_.normal_bits > 0 && !have_normals_)
    throw Error("ClusterPipeline: normal-bit keys need upload_normals() first");
  const ClusterConfig& c = layout_.config;
  cl::Kernel& kernel = window_depth_ ? keys_window_kernel_ : keys_view_kernel_;
  set_args(kernel, depth_, have_normals_ ? normals_ : depth_, slice_boundaries_, keys_, c.width, c.height,
           layout_.tiles_x, cl_uint{layout_.low_bits()}, static_cast<cl_int>(layout_.slice_count), c.near_plane,
           c.far_plane, layout_.ln_near, layout_.inv_ln_q);
  if (window_depth_) {
    kernel.setArg(13, layout_.near_over_far);
    kernel.setArg(14, layout_.far_share);
  }
  enqueue_2d(runtime_.queue(), kernel, c.width, c.height, kPixelGroupWidth, kPixelGroupHeight, profiler, "cluster-keys");
  stage_ = Stage::Keys;
}

std::uint32_t ClusterPipeline::compact(Compaction compaction, Profiler* profiler) {
  require(Stage::Keys, "compact()");
  if (compaction == Compaction::GlobalSort) {
    compact_global_sort(profiler);
  } else {
    compact_tiles(compaction, profiler);
  }
  stage_ = Stage::Compacted;
  return cluster_count_;
}

void ClusterPipeline::compact_global_sort(Profiler* profiler) {
  const std::size_t n = layout_.pixel_count();
  if (!sort_keys_()) {
    sort_keys_ = runtime_.buffer(CL_MEM_READ_WRITE, n * sizeof(std::uint32_t), "sorted cluster keys");
    sort_pixels_ = runtime_.buffer(CL_MEM_READ_WRITE, n * sizeof(std::uint32_t), "sorted pixel ids");
    run_ends_ = runtime_.buffer(CL_MEM_READ_WRITE, n * sizeof(std::uint32_t), "cluster run ends");
  }
  auto& queue = runtime_.queue();
  set_args(sort_init_kernel_, keys_, sort_keys_, sort_pixels_, to_uint(n));
  enqueue_1d(queue, sort_init_kernel_, n, kItemGroup, profiler, "cluster-sort-init");
  pair_sorter_.sort(sort_keys_, &sort_pixels_, n, layout_.key_bits, profiler);
  set_args(run_starts_kernel_, sort_keys_, run_ends_, to_uint(n));
  enqueue_1d(queue, run_starts_kernel_, n, kItemGroup, profiler, "cluster-run-starts");
  cluster_count_ = scanner_.run(run_ends_, run_ends_, n, primitives::ScanKind::Inclusive, true, profiler);
  set_args(sorted_scatter_kernel_, sort_keys_, sort_pixels_, run_ends_, unique_keys_, pixel_cluster_, to_uint(n));
  enqueue_1d(queue, sorted_scatter_kernel_, n, kItemGroup, profiler, "cluster-sorted-scatter");
}

void ClusterPipeline::compact_tiles(Compaction compaction, Profiler* profiler) {
  const ClusterConfig& c = layout_.config;
  const std::uint32_t tiles = layout_.tile_count;
  const cl_uint low_bits = layout_.low_bits();
  auto& queue = runtime_.queue();
  if (compaction == Compaction::TileBitmask) {
    if (low_bits > kMaxBitmaskLowBits)
      throw Error("bitmask compaction supports at most " + std::to_string(kMaxBitmaskLowBits) +
                  " slice and normal bits per tile; this layout has " + std::to_string(low_bits));
    const cl_uint words_per_tile = std::max(1u, (1u << low_bits) / 32u);
    if (!tile_masks_()) {
      tile_masks_ = runtime_.buffer(CL_MEM_READ_WRITE, std::size_t{tiles} * words_per_tile * sizeof(std::uint32_t),
                                    "tile cluster masks");
      mask_ranges_ = runtime_.buffer(CL_MEM_READ_WRITE, std::size_t{tiles} * 2 * sizeof(std::uint32_t),
                                     "tile cluster mask ranges");
    }
    set_args(tile_mask_kernel_, keys_, tile_masks_, mask_ranges_, tile_counts_, c.width, c.height, layout_.tiles_x,
             tiles, low_bits, words_per_tile);
    enqueue_1d(queue, tile_mask_kernel_, tiles, kCpuTileGroup, profiler, "cluster-tile-mask");
    cluster_count_ = scanner_.run(tile_counts_, tile_offsets_, tiles, primitives::ScanKind::Exclusive, true, profiler);
    set_args(tile_mask_write_kernel_, keys_, tile_masks_, mask_ranges_, tile_offsets_, unique_keys_, pixel_cluster_,
             c.width, c.height, layout_.tiles_x, tiles, low_bits, words_per_tile);
    enqueue_1d(queue, tile_mask_write_kernel_, tiles, kCpuTileGroup, profiler, "cluster-tile-mask-write");
    return;
  }

  if (!tile_sort_kernel_())
    throw Error("tile-sort compaction (" + std::string(to_string(shape_)) + " shape) supports tiles of at most " +
                std::to_string(max_sort_tile_pixels(runtime_.info(), shape_)) + " pixels on '" + runtime_.info().name +
                "' (" + std::to_string(runtime_.info().local_mem_bytes / 1024) + " KiB local memory); tile " +
                std::to_string(c.tile_width) + "x" + std::to_string(c.tile_height) + " is larger");
  if (!staging_())
    staging_ = runtime_.buffer(CL_MEM_READ_WRITE,
                               std::size_t{tiles} * c.tile_width * c.tile_height * sizeof(std::uint32_t),
                               "per-tile cluster keys");
  if (shape_ == Shape::Gpu) {
    set_args(tile_sort_kernel_, keys_, pixel_cluster_, staging_, tile_counts_, c.width, c.height, layout_.tiles_x);
    enqueue_1d(queue, tile_sort_kernel_, std::size_t{tiles} * tile_sort_group_, tile_sort_group_, profiler,
               "cluster-tile-sort");
  } else {
    set_args(tile_sort_kernel_, keys_, pixel_cluster_, staging_, tile_counts_, c.width, c.height, layout_.tiles_x,
             tiles, low_bits);
    enqueue_1d(queue, tile_sort_kernel_, tiles, kCpuTileGroup, profiler, "cluster-tile-sort");
  }
  cluster_count_ = scanner_.run(tile_counts_, tile_offsets_, tiles, primitives::ScanKind::Exclusive, true, profiler);
  const std::size_t scatter_group = shape_ == Shape::Gpu ? kGpuTileScatterGroup : 1;
  set_args(tile_scatter_kernel_, staging_, tile_counts_, tile_offsets_, unique_keys_, pixel_cluster_, c.width, c.height,
           layout_.tiles_x);
  enqueue_1d(queue, tile_scatter_kernel_, std::size_t{tiles} * scatter_group, scatter_group, profiler,
             "cluster-tile-scatter");
}

void ClusterPipeline::compute_bounds(Profiler* profiler) {
  require(Stage::Compacted, "compute_bounds()");
  const ClusterConfig& c = layout_.config;
  ensure_capacity(bounds_, bounds_capacity_, std::size_t{cluster_count_} * kBoxBytes, "cluster bounds");
  set_args(bounds_kernel_, unique_keys_, slice_boundaries_, bounds_, cluster_count_, c.width, c.height, layout_.tiles_x,
           cl_uint{layout_.low_bits()}, cl_uint{(1u << layout_.slice_bits) - 1u}, layout_.two_over_width,
           layout_.two_over_height, layout_.tan_half_x, layout_.tan_half_y, layout_.padding_scale);
  enqueue_1d(runtime_.queue(), bounds_kernel_, cluster_count_, kItemGroup, profiler, "cluster-bounds");
  stage_ = Stage::Bounded;
}

void ClusterPipeline::build_light_hierarchy(Profiler* profiler) {
  const std::uint32_t n = light_count_, stride = light_stride_;
  const auto sizes = bvh_level_sizes(stride / kBvhFanout);
  if (sizes.size() > kBvhMaxLevels || (sizes.size() - 1) * (kBvhFanout - 1) + 1 > kBvhStack)
    throw Error("light hierarchy over " + std::to_string(n) + " lights is deeper than its traversal stack");
  // Node storage for levels 1 .. top, each level after the one below.
  std::vector<std::uint32_t> level_first(sizes.size() + 1, 0);
  for (std::size_t level = 1; level < sizes.size(); ++level) level_first[level + 1] = level_first[level] + sizes[level];
  ensure_capacity(morton_codes_, morton_capacity_, std::size_t{n} * sizeof(std::uint32_t), "light Morton codes");
  ensure_capacity(light_order_, order_capacity_, std::size_t{stride} * sizeof(std::uint32_t), "light order");
  ensure_capacity(sorted_lights_, sorted_lights_capacity_, std::size_t{stride} * 4 * sizeof(float), "sorted lights");
  ensure_capacity(bvh_nodes_, nodes_capacity_, std::size_t{level_first[sizes.size()]} * kNodeBytes,
                  "light hierarchy nodes");

  auto& queue = runtime_.queue();
  const cl_float4 origin = {{morton_origin_[0], morton_origin_[1], morton_origin_[2], 0.0f}};
  const cl_float4 scale = {{morton_scale_[0], morton_scale_[1], morton_scale_[2], 0.0f}};
  set_args(morton_kernel_, lights_, morton_codes_, light_order_, n, stride, origin, scale);
  enqueue_1d(queue, morton_kernel_, n, kItemGroup, profiler, "bvh-morton");
  pair_sorter_.sort(morton_codes_, &light_order_, n, kMortonBits, profiler);
  set_args(gather_kernel_, lights_, light_order_, sorted_lights_, n, stride);
  enqueue_1d(queue, gather_kernel_, stride, kItemGroup, profiler, "bvh-gather");
  if (sizes.size() > 1) {
    set_args(leaf_boxes_kernel_, sorted_lights_, bvh_nodes_, n, stride, sizes[0]);
    enqueue_1d(queue, leaf_boxes_kernel_, round_up(sizes[0], kBvhFanout), kBvhFanout, profiler, "bvh-leaf-boxes");
  }
  for (std::size_t level = 1; level + 1 < sizes.size(); ++level) {
    set_args(node_boxes_kernel_, bvh_nodes_, level_first[level], sizes[level], level_first[level + 1]);
    enqueue_1d(queue, node_boxes_kernel_, round_up(sizes[level], kBvhFanout), kBvhFanout, profiler, "bvh-node-boxes");
  }
  bvh_levels_ = static_cast<std::uint32_t>(sizes.size());
}

std::uint32_t ClusterPipeline::assign_lights(Assignment assignment, Profiler* profiler) {
  require(Stage::Bounded, "assign_lights()");
  auto& queue = runtime_.queue();
  const std::uint32_t clusters = cluster_count_;
  ensure_capacity(light_counts_, light_counts_capacity_, std::size_t{clusters} * sizeof(std::uint32_t),
                  "light counts per cluster");
  ensure_capacity(light_offsets_, light_offsets_capacity_, std::size_t{clusters} * sizeof(std::uint32_t),
                  "light offsets per cluster");
  light_index_count_ = 0;
  stage_ = Stage::Assigned;
  if (clusters == 0) return 0;
  if (light_count_ == 0) {
    try {
      queue.enqueueFillBuffer(light_counts_, cl_uint{0}, 0, std::size_t{clusters} * sizeof(std::uint32_t));
      queue.enqueueFillBuffer(light_offsets_, cl_uint{0}, 0, std::size_t{clusters} * sizeof(std::uint32_t));
    } catch (...) {
      rethrow_as_error("clearing light lists");
    }
    return 0;
  }

  const auto scan_counts = [&] {
    light_index_count_ =
        scanner_.run(light_counts_, light_offsets_, clusters, primitives::ScanKind::Exclusive, true, profiler);
    ensure_capacity(light_indices_, indices_capacity_, std::size_t{light_index_count_} * sizeof(std::uint32_t),
                    "light indices");
  };
  if (assignment == Assignment::BruteForce) {
    set_args(brute_count_kernel_, bounds_, lights_, light_counts_, clusters, light_stride_);
    enqueue_1d(queue, brute_count_kernel_, clusters, kItemGroup, profiler, "assign-brute-count");
    scan_counts();
    set_args(brute_fill_kernel_, bounds_, lights_, light_offsets_, light_indices_, clusters, light_stride_);
    enqueue_1d(queue, brute_fill_kernel_, clusters, kItemGroup, profiler, "assign-brute-fill");
    return light_index_count_;
  }
  build_light_hierarchy(profiler);
  // Slot size: a multiple of 16 (the copy is 16 wide); 0 sends every cluster to a second traversal.
  const cl_uint slot = static_cast<cl_uint>(std::min(kListSlotMax, kListScratchEntries / clusters) / 16 * 16);
  ensure_capacity(list_scratch_, list_scratch_capacity_, std::size_t{clusters} * slot * sizeof(std::uint32_t),
                  "light list slots");
  set_args(bvh_collect_kernel_, bounds_, bvh_nodes_, sorted_lights_, light_order_, lane_compaction_, light_counts_,
           list_scratch_, clusters, light_stride_, bvh_levels_, slot);
  enqueue_1d(queue, bvh_collect_kernel_, clusters, kItemGroup, profiler, "assign-bvh-collect");
  scan_counts();
  // Long lists are radix-sorted in place, with a scratch laid out like the indices.
  ensure_capacity(list_sort_scratch_, list_sort_scratch_capacity_,
                  std::size_t{light_index_count_} * sizeof(std::uint32_t), "light list sort scratch");
  const cl_uint index_bits = std::max(1u, static_cast<cl_uint>(std::bit_width(light_count_ - 1)));
  set_args(bvh_place_kernel_, bounds_, bvh_nodes_, sorted_lights_, light_order_, lane_compaction_, light_counts_,
           light_offsets_, list_scratch_, light_indices_, list_sort_scratch_, clusters, light_stride_, bvh_levels_, slot,
           index_bits);
  enqueue_1d(queue, bvh_place_kernel_, clusters, kItemGroup, profiler, "assign-bvh-place");
  return light_index_count_;
}

void ClusterPipeline::finish() {
  try {
    runtime_.queue().finish();
  } catch (...) {
    rethrow_as_error("waiting for the cluster pipeline");
  }
}

namespace {

template <class T>
std::vector<T> read_buffer(cl::CommandQueue& queue, const cl::Buffer& buffer, std::size_t count, const char* what) {
  std::vector<T> result(count);
  if (count == 0) return result;
  try {
    queue.enqueueReadBuffer(buffer, CL_TRUE, 0, count * sizeof(T), result.data());
  } catch (...) {
    rethrow_as_error(std::string("downloading ") + what);
  }
  return result;
}

}  // namespace

std::vector<std::uint32_t> ClusterPipeline::download_keys() {
  require(Stage::Keys, "download_keys()");
  return read_buffer<std::uint32_t>(runtime_.queue(), keys_, layout_.pixel_count(), "cluster keys");
}

ClusterList ClusterPipeline::download_clusters() {
  require(Stage::Compacted, "download_clusters()");
  ClusterList list;
  list.unique_keys = read_buffer<std::uint32_t>(runtime_.queue(), unique_keys_, cluster_count_, "unique cluster keys");
  list.pixel_cluster =
      read_buffer<std::uint32_t>(runtime_.queue(), pixel_cluster_, layout_.pixel_count(), "the pixel cluster index");
  return list;
}

std::vector<ClusterBox> ClusterPipeline::download_bounds() {
  require(Stage::Bounded, "download_bounds()");
  const auto raw = read_buffer<float>(runtime_.queue(), bounds_, std::size_t{cluster_count_} * 8, "cluster bounds");
  std::vector<ClusterBox> boxes(cluster_count_);
  for (std::size_t c = 0; c < boxes.size(); ++c) {
    const float* v = raw.data() + 8 * c;
    boxes[c] = {{v[0], v[1], v[2]}, {v[4], v[5], v[6]}};
  }
  return boxes;
}

LightLists ClusterPipeline::download_light_lists() {
  require(Stage::Assigned, "download_light_lists()");
  LightLists lists;
  lists.offsets = read_buffer<std::uint32_t>(runtime_.queue(), light_offsets_, cluster_count_, "light offsets");
  lists.counts = read_buffer<std::uint32_t>(runtime_.queue(), light_counts_, cluster_count_, "light counts");
  lists.indices = read_buffer<std::uint32_t>(runtime_.queue(), light_indices_, light_index_count_, "light indices");
  return lists;
}

}  // namespace splatcl::cluster
