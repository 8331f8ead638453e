#pragma once
// Level of detail for one object's splats: a sequential point tree (the point-rendering thesis §5.2.3–§5.2.4,
// Dachsbacher et al. 2003 as the thesis builds it).
//   - A temporary octree split at the mean point (children by the per-axis comparison of the
//     thesis's table, ties to the "<" side) down to fewer than `leaf_splats` splats per leaf.
//   - Every octree node becomes one extra round splat: position and normal the mean of its direct
//     children, radius max(r_i + |p_i − p|), colour the mean colour.
//   - Its geometric error e_g = sqrt(e_p² + e_t²): e_p the thickness of the slab along the node
//     normal enclosing the children's disks, e_t = radius × the share of the node's disk not covered
//     by its children, counted on a grid × grid raster in the node's plane (our OpenCL
//     stand-in for the thesis's render-and-read-back).
//   - Interval [e_min, e_max): node e_min = min(radius, e_g), raised to its children's e_min so the
//     bounds decrease from the root to the leaves (a cut exists at every threshold); a child's
//     e_max = its parent's e_min × (1 + overlap) (the thesis's "small value against holes"); the
//     root's e_max = FLT_MAX; the original splats have e_min = 0.
//   - Originals and nodes in one array sorted by e_max, descending (the "sequential" form).
// Selection per frame: an entry is drawn when e_min ≤ e < e_max, e = (distance from the eye to the
// entry in model units) × (angle of `lod_error` pixels); the CPU sends the prefix of entries whose
// e_max exceeds the smallest e over the object's bounding sphere, the vertex shader tests each entry.
#include <cstdint>
#include <string>
#include <vector>

#include "splats/splat_file.hpp"

namespace splatcl::present {

struct LodOptions {
  std::uint32_t leaf_splats = 16;  // an octree node with fewer splats is a leaf
  std::uint32_t grid = 32;         // e_t raster side
  float overlap = 0.1f;            // child e_max = parent e_min × (1 + overlap)
};

struct SplatTree {
  std::uint32_t splat_count = 0;            // original splats (sources 0 .. splat_count − 1)
  std::vector<splats::SplatRecord> nodes;   // the octree nodes' round splats (sources splat_count + i)
  std::vector<std::uint32_t> order;         // original splats in octree order
  std::vector<std::uint32_t> node_begin, node_end;  // node i covers order[node_begin[i] .. node_end[i])
  std::vector<std::uint32_t> source;        // sequence entry → original splat or splat_count + node
  std::vector<float> error_min, error_max;  // per sequence entry, model units; sorted by error_max, descending

  std::size_t size() const { return source.size(); }
  // Number of leading entries with error_max > error (the entries that can be drawn when every
  // entry's e is at least `error`).
  std::size_t prefix(float error) const;
};

SplatTree build_splat_tree(const std::vector<splats::SplatRecord>& splats, const LodOptions& options = {});

// Rows of `width` floats per sequence entry from rows per original splat: an original copies its
// row, a node takes the mean of the rows of the splats under it.
std::vector<float> gather_tree_rows(const SplatTree& tree, const float* splat_rows, std::size_t width);

// Binary cache file (magic SPLATSPT, version, sizes, FNV-1a checksum), written atomically. The reader
// validates everything and that the tree is over `splat_count` splats; Error names the file.
void write_splat_tree(const std::string& path, const SplatTree& tree);
SplatTree read_splat_tree(const std::string& path, std::uint32_t splat_count);

}  // namespace splatcl::present
