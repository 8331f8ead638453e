#include "present/lod.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <numeric>

#include <glm/glm.hpp>

#include "present/cache_blob.hpp"
#include "runtime/error.hpp"

namespace splatcl::present {
namespace {

glm::vec3 g3(const Vec3& v) { return {v.x, v.y, v.z}; }
Vec3 s3(glm::vec3 v) { return {v.x, v.y, v.z}; }

// A disk or ellipse: centre, unit normal, the two semi-axis vectors; colour as floats.
struct Disk {
  glm::vec3 center, normal, major, minor, color;
  float radius() const { return std::max(glm::length(major), glm::length(minor)); }
};

Disk disk_of(const splats::SplatRecord& s) {
  return {g3(s.center), glm::normalize(g3(s.normal)), g3(s.major), g3(s.minor),
          glm::vec3(s.color.r, s.color.g, s.color.b)};
}

// Two unit vectors spanning the plane normal to n.
std::pair<glm::vec3, glm::vec3> tangents(glm::vec3 n) {
  const glm::vec3 helper = std::abs(n.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
  const glm::vec3 t1 = glm::normalize(glm::cross(helper, n));
  return {t1, glm::cross(n, t1)};
}

struct Builder {
  const std::vector<splats::SplatRecord>& splats;
  const LodOptions& options;
  SplatTree& tree;
  std::vector<Disk> node_disks;
  std::vector<float> node_error;                  // e_min before the interval pass
  std::vector<std::vector<std::uint32_t>> kids;  // per node: child nodes (inner) …
  std::vector<bool> leaf;                          // … or, for a leaf, its splats in order[begin, end)

  // The share of the parent disk's area not covered by the children's ellipses projected along the
  // parent normal, on a grid × grid raster of the disk's bounding square.
  float uncovered_share(const Disk& parent, const std::vector<Disk>& children) const {
    const auto [t1, t2] = tangents(parent.normal);
    const float r = parent.radius();
    struct Ellipse {
      glm::vec2 center;
      glm::mat2 inverse;  // plane point − centre → ellipse coordinates
    };
    std::vector<Ellipse> ellipses;
    for (const Disk& c : children) {
      const glm::vec2 a(glm::dot(c.major, t1), glm::dot(c.major, t2)), b(glm::dot(c.minor, t1), glm::dot(c.minor, t2));
      const glm::mat2 axes(a, b);
      const float det = glm::determinant(axes);
      if (!(std::abs(det) > 1e-12f * r * r)) continue;  // seen edge-on: covers nothing
      const glm::vec3 d = c.center - parent.center;
      ellipses.push_back({{glm::dot(d, t1), glm::dot(d, t2)}, glm::inverse(axes)});
    }
    const std::uint32_t g = options.grid;
    std::uint32_t inside = 0, uncovered = 0;
    for (std::uint32_t y = 0; y < g; ++y)
      for (std::uint32_t x = 0; x < g; ++x) {
        const glm::vec2 unit((2.0f * static_cast<float>(x) + 1.0f) / static_cast<float>(g) - 1.0f,
                             (2.0f * static_cast<float>(y) + 1.0f) / static_cast<float>(g) - 1.0f);
        if (glm::dot(unit, unit) > 1.0f) continue;
        ++inside;
        const glm::vec2 p = r * unit;
        bool covered = false;
        for (const Ellipse& e : ellipses) {
          const glm::vec2 q = e.inverse * (p - e.center);
          if (glm::dot(q, q) <= 1.0f) {
            covered = true;
            break;
          }
        }
        uncovered += covered ? 0 : 1;
      }
    return inside ? static_cast<float>(uncovered) / static_cast<float>(inside) : 0.0f;
  }

  // Node over order[begin, end): splits at the mean centre, recurses, then computes its disk and
  // error from its direct children. Returns the node index.
  std::uint32_t build(std::uint32_t begin, std::uint32_t end, int depth) {
    const auto index = static_cast<std::uint32_t>(node_disks.size());
    node_disks.emplace_back();
    node_error.push_back(0);
    kids.emplace_back();
    leaf.push_back(true);
    tree.node_begin.push_back(begin);
    tree.node_end.push_back(end);
    std::vector<Disk> children;
    if (end - begin >= options.leaf_splats && depth < 24) {
      glm::dvec3 sum(0.0);
      for (std::uint32_t i = begin; i < end; ++i) sum += glm::dvec3(g3(splats[tree.order[i]].center));
      const glm::vec3 mean(sum / static_cast<double>(end - begin));
      // Octant bits: x > mean, y > mean, z > mean (ties go to the "<" side).
      const auto octant = [&](std::uint32_t s) {
        const glm::vec3 p = g3(splats[s].center);
        return (p.x > mean.x ? 4 : 0) | (p.y > mean.y ? 2 : 0) | (p.z > mean.z ? 1 : 0);
      };
      std::stable_sort(tree.order.begin() + begin, tree.order.begin() + end,
                       [&](std::uint32_t a, std::uint32_t b) { return octant(a) < octant(b); });
      std::array<std::uint32_t, 9> bounds{};
      bounds[0] = begin;
      for (int o = 0; o < 8; ++o) {
        std::uint32_t k = bounds[static_cast<std::size_t>(o)];
        while (k < end && octant(tree.order[k]) == o) ++k;
        bounds[static_cast<std::size_t>(o) + 1] = k;
      }
      int occupied = 0;
      for (std::size_t o = 0; o < 8; ++o) occupied += bounds[o + 1] > bounds[o] ? 1 : 0;
      if (occupied >= 2) {  // all in one octant (coincident centres): a leaf
        leaf[index] = false;
        for (std::size_t o = 0; o < 8; ++o)
          if (bounds[o + 1] > bounds[o]) {
            const std::uint32_t child = build(bounds[o], bounds[o + 1], depth + 1);
            kids[index].push_back(child);
            children.push_back(node_disks[child]);
          }
      }
    }
    if (leaf[index])
      for (std::uint32_t i = begin; i < end; ++i) children.push_back(disk_of(splats[tree.order[i]]));

    Disk node{glm::vec3(0.0f), glm::vec3(0.0f), glm::vec3(0.0f), glm::vec3(0.0f), glm::vec3(0.0f)};
    glm::vec3 normal_sum(0.0f);
    for (const Disk& c : children) {
      node.center += c.center;
      normal_sum += c.normal;
      node.color += c.color;
    }
    node.center /= static_cast<float>(children.size());
    node.color /= static_cast<float>(children.size());
    node.normal = glm::length(normal_sum) > 1e-6f ? glm::normalize(normal_sum) : children.front().normal;
    float radius = 0, top = -FLT_MAX, bottom = FLT_MAX;
    for (const Disk& c : children) {
      radius = std::max(radius, c.radius() + glm::length(c.center - node.center));
      // Half-extent of the child's ellipse along the node normal.
      const float d = std::sqrt(std::pow(glm::dot(c.major, node.normal), 2.0f) + std::pow(glm::dot(c.minor, node.normal), 2.0f));
      const float h = glm::dot(node.normal, c.center - node.center);
      top = std::max(top, h + d);
      bottom = std::min(bottom, h - d);
    }
    const auto [t1, t2] = tangents(node.normal);
    node.major = radius * t1;
    node.minor = radius * t2;
    const float perpendicular = top - bottom;
    const float tangential = radius * uncovered_share(node, children);
    node_error[index] = std::min(radius, std::sqrt(perpendicular * perpendicular + tangential * tangential));
    node_disks[index] = node;
    return index;
  }
};

constexpr CacheMagic kMagic = {'S', 'P', 'L', 'A', 'T', 'S', 'P', 'T'};
constexpr std::uint32_t kVersion = 1;  // counts: splats, nodes, entries

}  // namespace

std::size_t SplatTree::prefix(float error) const {
  // error_max is descending: the first entry with error_max <= error ends the prefix.
  return static_cast<std::size_t>(std::partition_point(error_max.begin(), error_max.end(), [&](float e) { return e > error; }) -
                                  error_max.begin());
}

SplatTree build_splat_tree(const std::vector<splats::SplatRecord>& splats, const LodOptions& options) {
  SplatTree tree;
  tree.splat_count = static_cast<std::uint32_t>(splats.size());
  if (splats.empty()) return tree;
  tree.order.resize(splats.size());
  std::iota(tree.order.begin(), tree.order.end(), 0u);
  Builder b{splats, options, tree, {}, {}, {}, {}};
  b.build(0, tree.splat_count, 0);
  const std::size_t nodes = b.node_disks.size();

  // Bounds decrease from the root to the leaves: a node's e_min is at least its children's.
  for (std::size_t i = nodes; i-- > 0;)
    for (const std::uint32_t c : b.kids[i]) b.node_error[i] = std::max(b.node_error[i], b.node_error[c]);
  std::vector<float> node_max(nodes, FLT_MAX), splat_max(splats.size(), FLT_MAX);
  for (std::size_t i = 0; i < nodes; ++i) {
    const float child_max = b.node_error[i] * (1.0f + options.overlap);
    for (const std::uint32_t c : b.kids[i]) node_max[c] = child_max;
    if (b.leaf[i])
      for (std::uint32_t k = tree.node_begin[i]; k < tree.node_end[i]; ++k) splat_max[tree.order[k]] = child_max;
  }

  for (const Disk& d : b.node_disks) {
    splats::SplatRecord r;
    r.center = s3(d.center);
    r.normal = s3(d.normal);
    r.major = s3(d.major);
    r.minor = s3(d.minor);
    r.color = {static_cast<std::uint8_t>(std::lround(d.color.x)), static_cast<std::uint8_t>(std::lround(d.color.y)),
               static_cast<std::uint8_t>(std::lround(d.color.z)), 255};
    tree.nodes.push_back(r);
  }
  std::vector<std::uint32_t> entries(splats.size() + nodes);
  std::iota(entries.begin(), entries.end(), 0u);
  const auto max_of = [&](std::uint32_t e) { return e < tree.splat_count ? splat_max[e] : node_max[e - tree.splat_count]; };
  std::stable_sort(entries.begin(), entries.end(), [&](std::uint32_t a, std::uint32_t c) { return max_of(a) > max_of(c); });
  for (const std::uint32_t e : entries) {
    tree.source.push_back(e);
    tree.error_min.push_back(e < tree.splat_count ? 0.0f : b.node_error[e - tree.splat_count]);
    tree.error_max.push_back(max_of(e));
  }
  return tree;
}

std::vector<float> gather_tree_rows(const SplatTree& tree, const float* splat_rows, std::size_t width) {
  std::vector<float> out(tree.size() * width, 0.0f);
  // Prefix sums over the octree order make every node's mean one subtraction.
  std::vector<double> prefix((tree.order.size() + 1) * width, 0.0);
  for (std::size_t k = 0; k < tree.order.size(); ++k)
    for (std::size_t c = 0; c < width; ++c)
      prefix[(k + 1) * width + c] = prefix[k * width + c] + static_cast<double>(splat_rows[tree.order[k] * width + c]);
  for (std::size_t e = 0; e < tree.size(); ++e) {
    const std::uint32_t s = tree.source[e];
    if (s < tree.splat_count) {
      std::copy_n(splat_rows + std::size_t{s} * width, width, out.begin() + static_cast<std::ptrdiff_t>(e * width));
      continue;
    }
    const std::size_t node = s - tree.splat_count, begin = tree.node_begin[node], end = tree.node_end[node];
    for (std::size_t c = 0; c < width; ++c)
      out[e * width + c] = static_cast<float>((prefix[end * width + c] - prefix[begin * width + c]) / static_cast<double>(end - begin));
  }
  return out;
}

void write_splat_tree(const std::string& path, const SplatTree& tree) {
  std::string body;
  put_array(body, tree.nodes);
  put_array(body, tree.order);
  put_array(body, tree.node_begin);
  put_array(body, tree.node_end);
  put_array(body, tree.source);
  put_array(body, tree.error_min);
  put_array(body, tree.error_max);
  write_cache_blob(path, kMagic, kVersion,
                   {tree.splat_count, static_cast<std::uint32_t>(tree.nodes.size()), static_cast<std::uint32_t>(tree.source.size())},
                   body);
}

SplatTree read_splat_tree(const std::string& path, std::uint32_t splat_count) {
  CacheBlob blob = read_cache_blob(path, kMagic, kVersion, 3, "splat tree");
  const auto fail = [&](const std::string& why) -> Error { return Error(path + ": " + why); };
  SplatTree tree;
  tree.splat_count = blob.counts[0];
  const std::size_t nodes = blob.counts[1], entries = blob.counts[2];
  if (tree.splat_count != splat_count) throw fail(fmt::format("tree of {} splats, the splat file has {}", tree.splat_count, splat_count));
  if (entries != std::size_t{splat_count} + nodes) throw fail("entry count does not match");
  blob.take(tree.nodes, nodes);
  blob.take(tree.order, splat_count);
  blob.take(tree.node_begin, nodes);
  blob.take(tree.node_end, nodes);
  blob.take(tree.source, entries);
  blob.take(tree.error_min, entries);
  blob.take(tree.error_max, entries);
  blob.expect_consumed();
  for (std::size_t i = 0; i < nodes; ++i)
    if (tree.node_begin[i] >= tree.node_end[i] || tree.node_end[i] > splat_count) throw fail("node range out of bounds");
  for (const std::uint32_t s : tree.order)
    if (s >= splat_count) throw fail("splat index out of bounds");
  for (std::size_t e = 0; e < entries; ++e)
    if (tree.source[e] >= entries || (e > 0 && tree.error_max[e] > tree.error_max[e - 1])) throw fail("sequence out of order");
  return tree;
}

}  // namespace splatcl::present
