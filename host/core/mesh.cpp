#include "core/mesh.hpp"

// GCC reports a false -Wmaybe-uninitialized inside OpenMesh's property vectors when sanitizers are on.
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"

#include <fmt/format.h>

#include <algorithm>
#include <limits>
#include <bit>
#include <cmath>
#include <numbers>
#include <numeric>

#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/System/omstream.hh>

#include "runtime/error.hpp"
#include "core/mesh_readers.hpp"

namespace splatcl {
namespace {

using OmMesh = OpenMesh::PolyMesh_ArrayKernelT<>;

// OpenMesh reports problems on its own streams; our callers get one Error line instead.
void silence_openmesh() {
  static const bool silenced = [] {
    omerr().disable();
    omlog().disable();
    omout().disable();
    return true;
  }();
  (void)silenced;
}

std::string plural(std::size_t n, const char* one, const char* many) { return fmt::format("{} {}", n, n == 1 ? one : many); }

// The faces assemble() keeps: corner vertex indices into the raw mesh, and texcoords per corner.
struct Faces {
  std::vector<std::uint32_t> offsets{0}, corners;
  std::vector<std::array<float, 2>> texcoords;
  std::size_t count() const { return offsets.size() - 1; }
};

// Drops, and counts, faces with an index out of range, a bad vertex, or fewer than 3 distinct
// corners. A corner repeated next to itself (`f 1 2 3 3`) is merged first.
Faces usable_faces(const mesh_io::RawMesh& raw, MeshProblems& problems) {
  Faces faces;
  const bool texcoords = !raw.corner_texcoords.empty();
  const auto vertex_count = static_cast<std::int64_t>(raw.positions.size());
  std::vector<std::uint32_t> face, sorted;
  std::vector<std::array<float, 2>> face_texcoords;
  for (std::size_t f = 0; f < raw.face_count(); ++f) {
    const std::size_t begin = raw.face_offsets[f], end = raw.face_offsets[f + 1];
    bool bad_index = false, bad_vertex = false;
    for (std::size_t c = begin; c < end; ++c) {
      const std::int64_t v = raw.corners[c];
      if (v < 0 || v >= vertex_count)
        bad_index = true;
      else if (raw.bad_vertex[static_cast<std::size_t>(v)])
        bad_vertex = true;
    }
    if (bad_index) {
      ++problems.bad_index_faces;
      continue;
    }
    if (bad_vertex) {
      ++problems.bad_vertex_faces;
      continue;
    }
    face.clear();
    face_texcoords.clear();
    for (std::size_t c = begin; c < end; ++c) {
      const auto v = static_cast<std::uint32_t>(raw.corners[c]);
      if (!face.empty() && face.back() == v) continue;
      face.push_back(v);
      if (texcoords) face_texcoords.push_back(raw.corner_texcoords[c]);
    }
    while (face.size() > 1 && face.front() == face.back()) {
      face.pop_back();
      if (texcoords) face_texcoords.pop_back();
    }
    sorted = face;
    std::sort(sorted.begin(), sorted.end());
    if (face.size() < 3 || std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end()) {
      ++problems.degenerate_faces;
      continue;
    }
    faces.corners.insert(faces.corners.end(), face.begin(), face.end());
    faces.texcoords.insert(faces.texcoords.end(), face_texcoords.begin(), face_texcoords.end());
    faces.offsets.push_back(static_cast<std::uint32_t>(faces.corners.size()));
  }
  return faces;
}

struct Components {
  std::vector<std::uint32_t> parent;
  explicit Components(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0u); }
  std::uint32_t find(std::uint32_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  }
  void unite(std::uint32_t a, std::uint32_t b) { parent[find(a)] = find(b); }
};

// Calls edge(face, from, to) for every edge of every face, in winding order (the last corner back to
// the first): the one walk the surface checks, orientation and Mesh::closed share.
template <typename Edge>
void for_each_edge(const std::vector<std::uint32_t>& offsets, const std::vector<std::uint32_t>& corners, Edge&& edge) {
  for (std::size_t f = 0; f + 1 < offsets.size(); ++f)
    for (std::uint32_t c = offsets[f]; c < offsets[f + 1]; ++c)
      edge(static_cast<std::uint32_t>(f), corners[c], corners[c + 1 == offsets[f + 1] ? offsets[f] : c + 1]);
}

// An undirected edge as one key: low vertex << 32 | high vertex.
std::uint64_t undirected_edge(std::uint32_t a, std::uint32_t b) { return std::uint64_t{std::min(a, b)} << 32 | std::max(a, b); }

// Per vertex, the first vertex at the same position (+0 and -0 are one).
std::vector<std::uint32_t> position_ids(const std::vector<Vec3>& positions) {
  const auto key = [&](std::uint32_t v) {
    const Vec3& p = positions[v];
    return std::array{std::bit_cast<std::uint32_t>(p.x + 0.0f), std::bit_cast<std::uint32_t>(p.y + 0.0f),
                      std::bit_cast<std::uint32_t>(p.z + 0.0f), v};
  };
  std::vector<std::uint32_t> order(positions.size());
  std::iota(order.begin(), order.end(), 0u);
  std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return key(a) < key(b); });
  std::vector<std::uint32_t> ids(positions.size());
  for (std::size_t i = 0, first = 0; i < order.size(); ++i) {
    const auto k = key(order[i]), f = key(order[first]);
    if (k[0] != f[0] || k[1] != f[1] || k[2] != f[2]) first = i;
    ids[order[i]] = order[first];
  }
  return ids;
}

// Per face corner c, the ends (from, to) of the edge from c to the next corner, as the surface's
// connectivity matches it: by vertex index where exactly two uses share the edge by index, else by
// position (ids offset by the vertex count, so the two kinds never meet). Files repeat a vertex
// where faces meet without sharing it by index (triangle soups, UV or normal splits), and by index
// such a closed surface was open (the presenter drew it two-sided at twice the cost); by position
// alone, two parts that touch along an edge (stacked boxes, each with its own vertices) gave that
// edge four uses and were open instead.
std::vector<std::array<std::uint32_t, 2>> matched_edges(const std::vector<Vec3>& positions, const std::vector<std::uint32_t>& offsets,
                                                        const std::vector<std::uint32_t>& corners) {
  if (positions.size() >= (std::size_t{1} << 31)) throw Error("a mesh of 2^31 vertices or more");
  std::vector<std::uint64_t> by_index;
  by_index.reserve(corners.size());
  for_each_edge(offsets, corners, [&](std::uint32_t, std::uint32_t a, std::uint32_t b) { by_index.push_back(undirected_edge(a, b)); });
  std::sort(by_index.begin(), by_index.end());
  const std::vector<std::uint32_t> at = position_ids(positions);
  const auto shift = static_cast<std::uint32_t>(positions.size());
  std::vector<std::array<std::uint32_t, 2>> ends;
  ends.reserve(corners.size());
  for_each_edge(offsets, corners, [&](std::uint32_t, std::uint32_t a, std::uint32_t b) {
    const auto [lo, hi] = std::equal_range(by_index.begin(), by_index.end(), undirected_edge(a, b));
    if (hi - lo == 2)
      ends.push_back({a, b});
    else
      ends.push_back({shift + at[a], shift + at[b]});
  });
  return ends;
}

using D3 = std::array<double, 3>;
D3 sub(const D3& a, const D3& b) { return D3{a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
D3 cross3(const D3& a, const D3& b) { return D3{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]}; }
D3 to_double(const Vec3& p) { return D3{p.x, p.y, p.z}; }

// Twice face f's vector area (a fan from its first corner), from its own coordinates in double (a
// difference of two floats is exact in double unless their magnitudes are ~2^29 apart, so
// collinear corners give exactly zero).
D3 fan_area(const std::vector<Vec3>& positions, const std::vector<std::uint32_t>& offsets, const std::vector<std::uint32_t>& corners,
            std::size_t f) {
  const std::uint32_t begin = offsets[f], end = offsets[f + 1];
  const D3 q0 = to_double(positions[corners[begin]]);
  D3 area{0, 0, 0};
  for (std::uint32_t c = begin + 1; c + 1 < end; ++c) {
    const D3 a = cross3(sub(to_double(positions[corners[c]]), q0), sub(to_double(positions[corners[c + 1]]), q0));
    for (int i = 0; i < 3; ++i) area[i] += a[i];
  }
  return area;
}

// Per face, the signed volume of the cone from the bounding box's centre over it (a fan from its
// first corner), in double about that centre, so any float coordinates give finite sums: their sum
// over a closed surface is the volume it encloses, negative when its faces point inward.
std::vector<double> face_volumes(const std::vector<Vec3>& positions, const Faces& faces) {
  D3 lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
  for (const std::uint32_t v : faces.corners) {
    const D3 q = to_double(positions[v]);
    for (int i = 0; i < 3; ++i) lo[i] = std::min(lo[i], q[i]), hi[i] = std::max(hi[i], q[i]);
  }
  const D3 centre{(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2};
  const auto at = [&](std::uint32_t v) { return sub(to_double(positions[v]), centre); };
  std::vector<double> volume(faces.count());
  for (std::size_t f = 0; f < faces.count(); ++f) {
    const std::uint32_t begin = faces.offsets[f], end = faces.offsets[f + 1];
    const D3 p0 = at(faces.corners[begin]);
    double v = 0;
    for (std::uint32_t c = begin + 1; c + 1 < end; ++c) {
      const D3 b = cross3(at(faces.corners[c]), at(faces.corners[c + 1]));
      v += p0[0] * b[0] + p0[1] * b[1] + p0[2] * b[2];
    }
    volume[f] = v / 6;
  }
  return volume;
}

double dot3(const D3& a, const D3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

// Whether face f's area is within float rounding of zero: at most `steps` float steps of its
// coordinates' magnitude times its longest edge, so its height is at most twice that.
// kCollinearSteps: corners collinear but for the rounding of their own coordinates (a midpoint
// rounded to float lies within one step of its edge); the face's normal is noise. Not more: at 8
// steps a radius-1 UV sphere (20 x 30) moved to x = 3e5, whose faces are a few steps high there,
// had 304 of its 600 faces zero-area and 230 of its 572 vertices without a normal. kTransformedSteps, for closedness only: collinear corners moved by a float transform (the
// scene's fit), each rounded again.
constexpr double kCollinearSteps = 1, kTransformedSteps = 8;
// The largest |cross product| (twice an area) face f may have and still count as zero-area.
double rounding_area(const std::vector<Vec3>& positions, const std::vector<std::uint32_t>& offsets,
                     const std::vector<std::uint32_t>& corners, std::size_t f, double steps) {
  const std::uint32_t begin = offsets[f], end = offsets[f + 1];
  double magnitude = 0, longest = 0;
  for (std::uint32_t c = begin; c < end; ++c) {
    const D3 p = to_double(positions[corners[c]]), e = sub(to_double(positions[corners[c + 1 == end ? begin : c + 1]]), p);
    magnitude = std::max({magnitude, std::fabs(p[0]), std::fabs(p[1]), std::fabs(p[2])});
    longest = std::max(longest, std::sqrt(dot3(e, e)));
  }
  return steps * std::ldexp(magnitude, -23) * longest;
}
bool rounded_zero_area(const std::vector<Vec3>& positions, const std::vector<std::uint32_t>& offsets,
                       const std::vector<std::uint32_t>& corners, std::size_t f, double steps) {
  const D3 area = fan_area(positions, offsets, corners, f);
  return std::sqrt(dot3(area, area)) <= rounding_area(positions, offsets, corners, f, steps);
}

D3 unit3(const D3& a) {
  const double length = std::sqrt(dot3(a, a));
  return {a[0] / length, a[1] / length, a[2] / length};
}

// The parity rays' direction, oblique to the axes and their diagonals (CAD meshes are full of
// both), and a basis of the plane across it.
struct ParityFrame {
  D3 dir, u, v;
};
const ParityFrame& parity_frame() {
  static const ParityFrame frame = [] {
    const D3 dir = unit3({0.3713906763541037, 0.5570860145311556, 0.7427813527082074});
    const D3 u = unit3(cross3(dir, {1, 0, 0}));
    return ParityFrame{dir, u, cross3(dir, u)};
  }();
  return frame;
}

// A closed part's fan triangles, bucketed by their projection along one oblique direction, so that
// the parity of the ray from a point along it tests only the triangles over that point.
class ParityIndex {
 public:
  ParityIndex(const std::vector<Vec3>& positions, const Faces& faces, const std::vector<std::uint32_t>& part) {
    for (const std::uint32_t f : part)
      for (std::uint32_t c = faces.offsets[f] + 1; c + 1 < faces.offsets[f + 1]; ++c)
        triangles_.push_back({to_double(positions[faces.corners[faces.offsets[f]]]), to_double(positions[faces.corners[c]]),
                              to_double(positions[faces.corners[c + 1]])});
    for (const auto& t : triangles_)
      for (const D3& q : t) {
        const double uv[2] = {dot3(q, frame_.u), dot3(q, frame_.v)};
        for (int i = 0; i < 2; ++i) lo_[i] = std::min(lo_[i], uv[i]), hi_[i] = std::max(hi_[i], uv[i]);
      }
    side_ = std::clamp<std::size_t>(static_cast<std::size_t>(std::sqrt(static_cast<double>(triangles_.size()))), 1, 1024);
    cells_.resize(side_ * side_);
    for (std::size_t t = 0; t < triangles_.size(); ++t) {
      double tlo[2] = {INFINITY, INFINITY}, thi[2] = {-INFINITY, -INFINITY};
      for (const D3& q : triangles_[t]) {
        const double uv[2] = {dot3(q, frame_.u), dot3(q, frame_.v)};
        for (int i = 0; i < 2; ++i) tlo[i] = std::min(tlo[i], uv[i]), thi[i] = std::max(thi[i], uv[i]);
      }
      // A hair wider, so that rounding in the projections cannot put a crossing's point in the next cell.
      for (int i = 0; i < 2; ++i) {
        const double pad = 1e-9 * (hi_[i] - lo_[i]);
        tlo[i] -= pad, thi[i] += pad;
      }
      for (std::size_t y = cell(tlo[1], 1); y <= cell(thi[1], 1); ++y)
        for (std::size_t x = cell(tlo[0], 0); x <= cell(thi[0], 0); ++x) cells_[y * side_ + x].push_back(static_cast<std::uint32_t>(t));
    }
  }
  // Whether the ray from p along the frame's direction crosses the part an odd number of times: p inside it.
  bool contains(const D3& p) const {
    const double u = dot3(p, frame_.u), v = dot3(p, frame_.v);
    if (!(u >= lo_[0] && u <= hi_[0] && v >= lo_[1] && v <= hi_[1])) return false;
    int crossings = 0;
    for (const std::uint32_t t : cells_[cell(v, 1) * side_ + cell(u, 0)]) {
      const auto& [a, b, c] = triangles_[t];
      const D3 e1 = sub(b, a), e2 = sub(c, a), h = cross3(frame_.dir, e2);
      const double det = dot3(e1, h);
      if (det == 0) continue;
      const D3 s = sub(p, a), q = cross3(s, e1);
      const double bu = dot3(s, h) / det, bv = dot3(frame_.dir, q) / det;
      if (bu < 0 || bv < 0 || bu + bv > 1) continue;
      if (dot3(e2, q) / det > 0) ++crossings;
    }
    return crossings % 2 == 1;
  }

 private:
  const ParityFrame& frame_ = parity_frame();
  std::size_t cell(double value, int axis) const {
    const double extent = hi_[axis] - lo_[axis];
    if (!(extent > 0)) return 0;
    return std::min(side_ - 1, static_cast<std::size_t>(std::max(0.0, (value - lo_[axis]) / extent * static_cast<double>(side_))));
  }
  std::vector<std::array<D3, 3>> triangles_;
  double lo_[2] = {INFINITY, INFINITY}, hi_[2] = {-INFINITY, -INFINITY};
  std::size_t side_ = 1;
  std::vector<std::vector<std::uint32_t>> cells_;
};

// Which closed parts (each a list of consistently wound faces, with its faces' volumes) to turn:
// each that encloses negative volume yet lies in no other closed part (an inside-out part, or the
// outer shell of an inside-out nest), together with every part that lies in it, so that a cavity
// inside it keeps facing into the cavity. A part that lies in another and is not turned with it
// keeps the file's side: a cavity's wall, or parts that overlap. P lies in Q when two of three
// points just inside P, beside three of its faces, are inside Q (ray parity): points on P's own
// surface decided nothing where a cavity touched the outer wall.
std::vector<std::uint8_t> parts_to_turn(const std::vector<Vec3>& positions, const Faces& faces, const std::vector<double>& volume,
                                        const std::vector<std::vector<std::uint32_t>>& parts) {
  const std::size_t count = parts.size();
  std::vector<double> part_volume(count, 0), magnitude(count, 0);
  for (std::size_t id = 0; id < count; ++id)
    for (const std::uint32_t f : parts[id]) part_volume[id] += volume[f], magnitude[id] += std::fabs(volume[f]);
  const auto inverted = [&](std::size_t id) { return part_volume[id] < 0 && -part_volume[id] > 1e-6 * magnitude[id]; };
  std::vector<std::uint8_t> turn(count, 0);
  bool any_inverted = false;
  for (std::size_t id = 0; id < count; ++id) any_inverted = any_inverted || inverted(id);
  if (!any_inverted) return turn;  // every load comes here: the boxes and tests below only when needed
  std::vector<std::array<D3, 2>> box(count, {D3{INFINITY, INFINITY, INFINITY}, D3{-INFINITY, -INFINITY, -INFINITY}});
  for (std::size_t id = 0; id < count; ++id)
    for (const std::uint32_t f : parts[id])
      for (std::uint32_t c = faces.offsets[f]; c < faces.offsets[f + 1]; ++c) {
        const D3 q = to_double(positions[faces.corners[c]]);
        for (int i = 0; i < 3; ++i) box[id][0][i] = std::min(box[id][0][i], q[i]), box[id][1][i] = std::max(box[id][1][i], q[i]);
      }
  const auto box_within = [&](std::size_t inner, std::size_t outer) {
    for (int i = 0; i < 3; ++i)
      if (box[inner][0][i] < box[outer][0][i] || box[inner][1][i] > box[outer][1][i]) return false;
    return true;
  };
  // Three points just inside each part (on the side its volume's sign puts inside), beside faces
  // spread over its list; fewer where its faces have no area.
  const auto voters = [&](std::size_t id) {
    std::vector<D3> points;
    const std::vector<std::uint32_t>& own = parts[id];
    const double inward = part_volume[id] >= 0 ? -1.0 : 1.0;
    for (std::size_t k = 0; k < 3; ++k)
      for (std::size_t i = k * own.size() / 3; i < own.size(); ++i) {
        const std::uint32_t f = own[i], begin = faces.offsets[f];
        const D3 a = to_double(positions[faces.corners[begin]]), b = to_double(positions[faces.corners[begin + 1]]),
                 c = to_double(positions[faces.corners[begin + 2]]);
        const D3 n = cross3(sub(b, a), sub(c, a));
        const double length = std::sqrt(dot3(n, n));
        if (!(length > 0)) continue;
        const double offset = inward * 1e-3 * std::sqrt(length / 2) / length;
        points.push_back({(a[0] + b[0] + c[0]) / 3 + offset * n[0], (a[1] + b[1] + c[1]) / 3 + offset * n[1], (a[2] + b[2] + c[2]) / 3 + offset * n[2]});
        break;
      }
    return points;
  };
  std::vector<std::optional<ParityIndex>> index(count);
  const auto lies_in = [&](std::size_t inner, std::size_t outer) {
    if (inner == outer || !box_within(inner, outer)) return false;
    if (!index[outer]) index[outer].emplace(positions, faces, parts[outer]);
    const std::vector<D3> points = voters(inner);
    std::size_t inside = 0;
    for (const D3& p : points) inside += index[outer]->contains(p) ? 1 : 0;
    return 2 * inside > points.size();
  };
  for (std::size_t id = 0; id < count; ++id) {
    if (!inverted(id)) continue;
    bool nested = false;
    for (std::size_t other = 0; other < count && !nested; ++other) nested = lies_in(id, other);
    if (nested) continue;
    turn[id] = 1;
    for (std::size_t inner = 0; inner < count; ++inner)
      if (lies_in(inner, id)) turn[inner] = 1;
  }
  return turn;
}

// Faces turned (their corners reversed) so that each edge two faces share is used in opposite
// directions, spread face to face across such edges from the first face of each connected part;
// an open part keeps the winding most of its faces had in the file; then the closed parts (every
// edge shared by exactly two faces) that parts_to_turn picks are turned: an inside-out part that
// lies in no other, with the parts inside it (a shell facing into a cavity inside an outward one
// stays; an inside-out part beside an outward one kept its inward faces while only the parts'
// volumes together were judged).
// Returns how many faces end up turned.
std::size_t orient_faces(const std::vector<Vec3>& positions, Faces& faces) {
  const std::size_t n = faces.count();
  struct Use {
    std::uint64_t edge;  // low end << 32 | high end (matched_edges)
    std::uint32_t face;
    bool forward;        // the face runs low → high
    bool operator<(const Use& o) const { return edge < o.edge || (edge == o.edge && face < o.face); }
  };
  std::vector<Use> uses;
  uses.reserve(faces.corners.size());
  const std::vector<std::array<std::uint32_t, 2>> ends = matched_edges(positions, faces.offsets, faces.corners);
  for_each_edge(faces.offsets, faces.corners, [&](std::uint32_t f, std::uint32_t, std::uint32_t) {
    const auto [a, b] = ends[uses.size()];
    uses.push_back({undirected_edge(a, b), f, a < b});
  });
  std::sort(uses.begin(), uses.end());
  // Edges of exactly two faces link them; `same` when the two run it the same way (one must turn).
  struct Link {
    std::uint32_t to;
    bool same;
  };
  std::vector<std::vector<Link>> links(n);
  std::vector<std::uint8_t> closed(n, 1);  // every edge of the face shared by exactly two faces
  for (std::size_t i = 0; i < uses.size();) {
    std::size_t j = i;
    while (j < uses.size() && uses[j].edge == uses[i].edge) ++j;
    if (j - i == 2 && uses[i].face != uses[i + 1].face) {
      const bool same = uses[i].forward == uses[i + 1].forward;
      links[uses[i].face].push_back({uses[i + 1].face, same});
      links[uses[i + 1].face].push_back({uses[i].face, same});
    } else {
      for (std::size_t k = i; k < j; ++k) closed[uses[k].face] = 0;
    }
    i = j;
  }
  std::vector<std::int8_t> turn(n, -1);  // -1: not reached yet
  std::vector<std::uint32_t> part(n), queue;
  std::vector<std::pair<std::size_t, std::size_t>> part_turned;  // per part: faces, faces turned
  std::vector<std::pair<double, double>> part_area;              // per part: area kept, area turned
  std::vector<std::uint8_t> part_closed;
  for (std::uint32_t seed = 0; seed < n; ++seed) {
    if (turn[seed] >= 0) continue;
    const auto id = static_cast<std::uint32_t>(part_turned.size());
    part_turned.push_back({0, 0});
    part_area.push_back({0, 0});
    part_closed.push_back(1);
    turn[seed] = 0;
    queue.assign(1, seed);
    for (std::size_t q = 0; q < queue.size(); ++q) {
      const std::uint32_t f = queue[q];
      part[f] = id;
      ++part_turned[id].first;
      part_turned[id].second += static_cast<std::size_t>(turn[f]);
      const D3 twice_area = fan_area(positions, faces.offsets, faces.corners, f);
      const double area = std::sqrt(dot3(twice_area, twice_area));
      (turn[f] ? part_area[id].second : part_area[id].first) += area;
      part_closed[id] &= closed[f];
      for (const Link& l : links[f])
        if (turn[l.to] < 0) {
          turn[l.to] = static_cast<std::int8_t>(turn[f] ^ static_cast<int>(l.same));
          queue.push_back(l.to);
        }
    }
  }
  // An open part keeps the winding of most of its area in the file (a few large faces outweigh many
  // slivers wound the other way); on a tie of areas, of most of its faces; on a tie of both, the
  // first face's.
  std::vector<std::uint8_t> keep_turned(part_turned.size());
  for (std::size_t id = 0; id < part_turned.size(); ++id) {
    const auto [area_kept, area_turned] = part_area[id];
    const auto [count, count_turned] = part_turned[id];
    // Equal areas summed in another order may differ in their last bits.
    const bool area_tie = std::fabs(area_turned - area_kept) <= 1e-9 * (area_turned + area_kept);
    keep_turned[id] = area_tie ? 2 * count_turned > count : area_turned > area_kept;
  }
  for (std::uint32_t f = 0; f < n; ++f)
    if (keep_turned[part[f]]) turn[f] ^= 1;
  const auto reverse = [&](std::uint32_t f) {
    std::reverse(faces.corners.begin() + faces.offsets[f], faces.corners.begin() + faces.offsets[f + 1]);
    if (!faces.texcoords.empty())
      std::reverse(faces.texcoords.begin() + faces.offsets[f], faces.texcoords.begin() + faces.offsets[f + 1]);
  };
  for (std::uint32_t f = 0; f < n; ++f)
    if (turn[f]) reverse(f);
  // Turning changes no edge's face count: a closed part stays closed.
  const std::vector<double> volume = face_volumes(positions, faces);
  std::vector<std::vector<std::uint32_t>> closed_parts(part_turned.size());
  for (std::uint32_t f = 0; f < n; ++f)
    if (part_closed[part[f]]) closed_parts[part[f]].push_back(f);
  const std::vector<std::uint8_t> turn_part = parts_to_turn(positions, faces, volume, closed_parts);
  for (std::size_t id = 0; id < closed_parts.size(); ++id)
    if (turn_part[id])
      for (const std::uint32_t f : closed_parts[id]) {
        reverse(f);
        turn[f] ^= 1;
      }
  return static_cast<std::size_t>(std::count(turn.begin(), turn.end(), 1));
}

// How far a fan triangle may stand off its polygon's Newell normal before the polygon is split into
// its fan: half the default crease angle (splats::kDefaultCreaseAngle, 60°), so two fan triangles
// tilted apart by more can meet at a crease.
constexpr double kMaxFanTilt = 30;

// Polygons of more than three corners that a fan from their first corner would not triangulate
// inside their outline (every consumer fans: sampling, the shadow casters, the surface checks) are
// replaced by an ear-clipping triangulation in the plane of their Newell normal: concave ones (an
// L-shaped CAD face), and non-planar ones whose fan folds (a fan triangle facing against the
// normal). Polygons whose fan triangles stand more than kMaxFanTilt off that normal are replaced by
// the fan itself (the same surface): their normals then come from the triangles, and a fold
// sharper than the crease angle stays sharp (a quad whose corners alternate in height, its fan
// triangles 60° off the quad's normal, was shaded flat with the quad's normal). Convex polygons
// that are nearly planar stay whole. Returns how many were split.
std::size_t split_unfannable_faces(const std::vector<Vec3>& positions, Faces& faces) {
  Faces out;
  std::size_t split = 0;
  std::vector<std::array<double, 2>> flat;
  std::vector<std::uint32_t> left;
  const auto keep = [&](std::uint32_t f) {
    out.corners.insert(out.corners.end(), faces.corners.begin() + faces.offsets[f], faces.corners.begin() + faces.offsets[f + 1]);
    if (!faces.texcoords.empty())
      out.texcoords.insert(out.texcoords.end(), faces.texcoords.begin() + faces.offsets[f], faces.texcoords.begin() + faces.offsets[f + 1]);
    out.offsets.push_back(static_cast<std::uint32_t>(out.corners.size()));
  };
  for (std::uint32_t f = 0; f < faces.count(); ++f) {
    const std::uint32_t begin = faces.offsets[f], n = faces.offsets[f + 1] - begin;
    if (n <= 3) {
      keep(f);
      continue;
    }
    const auto at = [&](std::uint32_t i) { return to_double(positions[faces.corners[begin + i]]); };
    const auto emit = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
      for (const std::uint32_t i : {a, b, c}) {
        out.corners.push_back(faces.corners[begin + i]);
        if (!faces.texcoords.empty()) out.texcoords.push_back(faces.texcoords[begin + i]);
      }
      out.offsets.push_back(static_cast<std::uint32_t>(out.corners.size()));
    };
    // Newell's normal, and the fan's triangles against it.
    D3 normal{0, 0, 0};
    const D3 origin = at(0);
    for (std::uint32_t i = 0; i < n; ++i) {
      const D3 a = sub(at(i), origin), b = sub(at((i + 1) % n), origin);
      const D3 c = cross3(a, b);
      for (int k = 0; k < 3; ++k) normal[k] += c[k];
    }
    const double length = std::sqrt(normal[0] * normal[0] + normal[1] * normal[1] + normal[2] * normal[2]);
    if (!(length > 0)) {
      // No Newell normal, yet its fan may have area: a self-intersecting "bowtie" whose two halves
      // turn opposite ways (kept whole, it was called zero-area and got no splats, though its
      // fan, which every consumer takes, covers a surface). Replaced by that fan.
      // Area beyond float rounding, by rounded_zero_area's measure, in one of its triangles.
      const double rounding = rounding_area(positions, faces.offsets, faces.corners, f, kCollinearSteps);
      bool area = false;
      for (std::uint32_t i = 1; i + 1 < n && !area; ++i) {
        const D3 c = cross3(sub(at(i), origin), sub(at(i + 1), origin));
        area = std::sqrt(dot3(c, c)) > rounding;
      }
      if (!area) {
        keep(f);
        continue;
      }
      for (std::uint32_t i = 1; i + 1 < n; ++i) emit(0, i, i + 1);
      ++split;
      continue;
    }
    // A frame of the Newell plane; corners projected into it (counter-clockwise about the normal).
    const D3 w{normal[0] / length, normal[1] / length, normal[2] / length};
    const D3 helper = std::fabs(w[0]) < 0.9 ? D3{1, 0, 0} : D3{0, 1, 0};
    D3 u = cross3(helper, w);
    const double ul = std::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    for (double& x : u) x /= ul;
    const D3 v = cross3(w, u);
    flat.resize(n);
    for (std::uint32_t i = 0; i < n; ++i) {
      const D3 p = sub(at(i), origin);
      flat[i] = {p[0] * u[0] + p[1] * u[1] + p[2] * u[2], p[0] * v[0] + p[1] * v[1] + p[2] * v[2]};
    }
    const auto turn = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
      return (flat[b][0] - flat[a][0]) * (flat[c][1] - flat[a][1]) - (flat[b][1] - flat[a][1]) * (flat[c][0] - flat[a][0]);
    };
    bool fans = true;
    for (std::uint32_t i = 0; i < n && fans; ++i) fans = turn((i + n - 1) % n, i, (i + 1) % n) >= 0;  // convex outline
    for (std::uint32_t i = 1; i + 1 < n && fans; ++i) {
      const D3 c = cross3(sub(at(i), origin), sub(at(i + 1), origin));
      fans = c[0] * w[0] + c[1] * w[1] + c[2] * w[2] >= 0;  // no fan triangle folded back
    }
    if (fans) {
      bool tilted = false;
      const double cos_tilt = std::cos(kMaxFanTilt * std::numbers::pi / 180);
      for (std::uint32_t i = 1; i + 1 < n && !tilted; ++i) {
        const D3 c = cross3(sub(at(i), origin), sub(at(i + 1), origin));
        const double cl = std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
        tilted = cl > 0 && c[0] * w[0] + c[1] * w[1] + c[2] * w[2] < cos_tilt * cl;
      }
      if (!tilted) {
        keep(f);
        continue;
      }
      for (std::uint32_t i = 1; i + 1 < n; ++i) emit(0, i, i + 1);
      ++split;
      continue;
    }
    // Ear clipping: cut a convex corner whose triangle holds no other remaining corner.
    left.resize(n);
    std::iota(left.begin(), left.end(), 0u);
    const auto inside = [&](std::uint32_t p, std::uint32_t a, std::uint32_t b, std::uint32_t c) {
      return turn(a, b, p) >= 0 && turn(b, c, p) >= 0 && turn(c, a, p) >= 0;
    };
    while (left.size() > 3) {
      const std::size_t m = left.size();
      std::size_t ear = m;
      for (std::size_t i = 0; i < m && ear == m; ++i) {
        const std::uint32_t a = left[(i + m - 1) % m], b = left[i], c = left[(i + 1) % m];
        if (!(turn(a, b, c) > 0)) continue;
        bool empty = true;
        for (std::size_t k = 0; k < m && empty; ++k) {
          const std::uint32_t p = left[k];
          if (p != a && p != b && p != c && flat[p] != flat[a] && flat[p] != flat[b] && flat[p] != flat[c]) empty = !inside(p, a, b, c);
        }
        if (empty) ear = i;
      }
      if (ear == m) ear = 0;  // self-intersecting or degenerate outline: cut anywhere, it still ends
      emit(left[(ear + m - 1) % m], left[ear], left[(ear + 1) % m]);
      left.erase(left.begin() + static_cast<std::ptrdiff_t>(ear));
    }
    emit(left[0], left[1], left[2]);
    ++split;
  }
  faces = std::move(out);
  return split;
}

// Zero-area faces, edges two faces use in the same direction, and whether a closed part of the
// surface (a component whose every edge two faces share in opposite directions) faces inward: one
// parts_to_turn picks. In double, about the bounding box's centre, so any float coordinates give
// finite sums.
void check_surface(const std::vector<Vec3>& positions, const Faces& faces, MeshProblems& problems) {
  const auto key = [](std::uint32_t from, std::uint32_t to) { return std::uint64_t{from} << 32 | to; };
  const std::size_t n = faces.count();
  const std::vector<double> volume = face_volumes(positions, faces);
  std::vector<std::pair<std::uint64_t, std::uint32_t>> edges;  // directed edge, face
  edges.reserve(faces.corners.size());
  for (std::size_t f = 0; f < n; ++f)
    if (rounded_zero_area(positions, faces.offsets, faces.corners, f, kCollinearSteps)) ++problems.zero_area_faces;
  const std::vector<std::array<std::uint32_t, 2>> ends = matched_edges(positions, faces.offsets, faces.corners);
  for_each_edge(faces.offsets, faces.corners, [&](std::uint32_t f, std::uint32_t, std::uint32_t) {
    const auto [a, b] = ends[edges.size()];
    edges.emplace_back(key(a, b), f);
  });
  std::sort(edges.begin(), edges.end());
  Components components(n);
  std::vector<std::uint8_t> open(n, 0);
  std::vector<std::uint64_t> twice;  // undirected edges (low end first, matched_edges) used twice in one direction, unpaired
  const auto run_end = [&](std::size_t i) {
    std::size_t j = i;
    while (j < edges.size() && edges[j].first == edges[i].first) ++j;
    return j;
  };
  for (std::size_t i = 0; i < edges.size();) {
    const std::size_t j = run_end(i);
    const auto from = static_cast<std::uint32_t>(edges[i].first >> 32), to = static_cast<std::uint32_t>(edges[i].first);
    const auto reverse = std::lower_bound(edges.begin(), edges.end(), std::pair{key(to, from), std::uint32_t{0}});
    const std::size_t ri = static_cast<std::size_t>(reverse - edges.begin()), rj = ri < edges.size() && reverse->first == key(to, from) ? run_end(ri) : ri;
    for (std::size_t k = i + 1; k < j; ++k) components.unite(edges[i].second, edges[k].second);
    if (rj > ri) components.unite(edges[i].second, edges[ri].second);
    // An edge four faces share, two each way (two cubes touching along an edge), pairs up: only
    // uses that cannot pair (two one way, none or one the other) make it inconsistent.
    if (j - i >= 2 && j - i != rj - ri) twice.push_back(key(std::min(from, to), std::max(from, to)));
    if (j - i != 1 || rj - ri != 1) {
      for (std::size_t k = i; k < j; ++k) open[edges[k].second] = 1;
      for (std::size_t k = ri; k < rj; ++k) open[edges[k].second] = 1;
    }
    i = j;
  }
  std::sort(twice.begin(), twice.end());
  problems.inconsistent_edges += static_cast<std::size_t>(std::unique(twice.begin(), twice.end()) - twice.begin());
  std::vector<std::uint8_t> open_component(n, 0);
  for (std::uint32_t f = 0; f < n; ++f)
    if (open[f]) open_component[components.find(f)] = 1;
  // Closed parts by compact id (one list per component, not per face).
  std::vector<std::uint32_t> part_of_root(n, UINT32_MAX);
  std::vector<std::vector<std::uint32_t>> closed_parts;
  double closed_volume = 0, closed_magnitude = 0;
  for (std::uint32_t f = 0; f < n; ++f) {
    const std::uint32_t root = components.find(f);
    if (open_component[root]) continue;
    closed_volume += volume[f], closed_magnitude += std::fabs(volume[f]);
    if (part_of_root[root] == UINT32_MAX) part_of_root[root] = static_cast<std::uint32_t>(closed_parts.size()), closed_parts.emplace_back();
    closed_parts[part_of_root[root]].push_back(f);
  }
  // Warned exactly where orient_faces would turn a closed part (its parts agree across every edge
  // then); with faces that disagree, by the closed parts' volume together.
  if (problems.inconsistent_edges == 0) {
    const std::vector<std::uint8_t> turn = parts_to_turn(positions, faces, volume, closed_parts);
    problems.inward = std::find(turn.begin(), turn.end(), 1) != turn.end();
  } else {
    problems.inward = closed_volume < 0 && -closed_volume > 1e-6 * closed_magnitude;
  }
}

// The vertex normals of the vertices of faces whose area is within float rounding of zero
// (`noise`), without those faces: OpenMesh averages unit face normals, and such a face's is
// rounding noise as heavy as any real face's (a helper's audit: faces laid along a sphere's edges,
// collinear only to float rounding, turned the splats at their corners 90–121° off the surface).
// A vertex of such faces only keeps a zero normal, as one of exactly collinear faces does.
void drop_noise_normals(OmMesh& om, const std::vector<std::uint8_t>& noise) {
  for (const auto f : om.faces()) {
    if (!noise[static_cast<std::size_t>(f.idx())]) continue;
    for (const auto v : om.fv_range(f)) {
      OmMesh::Normal sum(0, 0, 0);
      for (const auto g : om.vf_range(v))
        if (!noise[static_cast<std::size_t>(g.idx())]) sum += om.normal(g);
      const float length = sum.norm();
      om.set_normal(v, length > 0 ? sum / length : OmMesh::Normal(0, 0, 0));
    }
  }
}

// OpenMesh's face-normal average, on a copy scaled by a power of two (exact) when the coordinates
// are so large or small that its float cross products would over- or underflow; without the faces
// that `noise` marks (drop_noise_normals).
void update_normals(OmMesh& om, const std::vector<std::uint8_t>& noise) {
  om.request_face_normals();
  float largest = 0;
  for (const auto v : om.vertices())
    if (!om.is_isolated(v))
      for (int i = 0; i < 3; ++i) largest = std::max(largest, std::fabs(om.point(v)[i]));
  if (largest > 0 && (largest > 0x1p32f || largest < 0x1p-32f)) {
    int exponent = 0;
    std::frexp(largest, &exponent);
    const float scale = std::ldexp(1.0f, -exponent);
    std::vector<OmMesh::Point> points;
    points.reserve(om.n_vertices());
    for (const auto v : om.vertices()) {
      points.push_back(om.point(v));
      om.set_point(v, om.point(v) * scale);
    }
    om.update_normals();
    drop_noise_normals(om, noise);
    for (const auto v : om.vertices()) om.set_point(v, points[static_cast<std::size_t>(v.idx())]);
  } else {
    om.update_normals();
    drop_noise_normals(om, noise);
  }
  om.release_face_normals();
}

// The checked faces into OpenMesh, then the Mesh: unused vertices dropped, normals from the file
// where it gives them, else computed.
// The box of the vertices `faces` use, as the file gives them (double): a stray unused vertex far
// out must not move a recentred mesh's centre.
std::pair<DVec3, DVec3> file_box(const mesh_io::RawMesh& raw, const Faces& faces) {
  DVec3 lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
  for (const std::uint32_t v : faces.corners) {
    const DVec3& p = raw.exact_positions[v];
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  }
  return {lo, hi};
}

Mesh assemble(const mesh_io::RawMesh& raw, const std::string& source, Winding winding) {
  silence_openmesh();
  MeshProblems problems = raw.problems;
  problems.faces_listed = raw.face_count();
  Faces faces = usable_faces(raw, problems);
  const auto [file_lo, file_hi] = file_box(raw, faces);
  if (winding == Winding::Orient) problems.turned_faces = orient_faces(raw.positions, faces);
  problems.split_polygons = split_unfannable_faces(raw.positions, faces);
  check_surface(raw.positions, faces, problems);
  const bool texcoords = !raw.corner_texcoords.empty();

  OmMesh om;
  om.request_vertex_normals();
  if (texcoords) om.request_halfedge_texcoords2D();
  std::vector<OmMesh::VertexHandle> handles;
  handles.reserve(raw.positions.size());
  for (const Vec3& p : raw.positions) handles.push_back(om.add_vertex(OmMesh::Point(p.x, p.y, p.z)));
  std::vector<std::uint32_t> origin(raw.positions.size());  // per OpenMesh vertex: the raw vertex it copies
  std::iota(origin.begin(), origin.end(), 0u);
  std::vector<OmMesh::VertexHandle> corners;
  for (std::size_t f = 0; f < faces.count(); ++f) {
    const std::uint32_t begin = faces.offsets[f], end = faces.offsets[f + 1];
    corners.clear();
    for (std::uint32_t c = begin; c < end; ++c) corners.push_back(handles[faces.corners[c]]);
    auto face = om.add_face(corners);
    if (!face.is_valid()) {
      // OpenMesh cannot fit it into its half-edge structure (a non-manifold edge or vertex, or
      // wound against a neighbour): keep its surface on copies of its vertices, as its importer does.
      ++problems.complex_faces;
      for (std::uint32_t c = begin; c < end; ++c) {
        const OmMesh::Point p = om.point(corners[c - begin]);
        corners[c - begin] = om.add_vertex(p);
        origin.push_back(faces.corners[c]);
      }
      face = om.add_face(corners);
    }
    if (texcoords)
      for (const auto h : om.fh_range(face)) {
        const auto k = static_cast<std::size_t>(std::find(corners.begin(), corners.end(), om.to_vertex_handle(h)) - corners.begin());
        om.set_texcoord2D(h, OmMesh::TexCoord2D(faces.texcoords[begin + k][0], faces.texcoords[begin + k][1]));
      }
  }
  const auto file_normal = [&](OmMesh::VertexHandle v) { return !raw.has_normal.empty() && raw.has_normal[origin[static_cast<std::size_t>(v.idx())]]; };
  bool all_file_normals = true;
  for (const auto v : om.vertices()) all_file_normals = all_file_normals && (om.is_isolated(v) || file_normal(v));
  if (!all_file_normals) {
    std::vector<std::uint8_t> noise(faces.count());  // OpenMesh's faces are `faces`, in order
    for (std::size_t f = 0; f < faces.count(); ++f) noise[f] = rounded_zero_area(raw.positions, faces.offsets, faces.corners, f, kCollinearSteps);
    update_normals(om, noise);
  }

  Mesh mesh;
  mesh.source = source;
  // Unused vertices carry no surface, and as samples they would sit far from every splat.
  std::vector<std::uint32_t> remap(om.n_vertices(), UINT32_MAX);
  for (const auto v : om.vertices()) {
    if (om.is_isolated(v)) continue;
    const auto& p = om.point(v);
    Vec3 normal;
    if (file_normal(v)) {
      normal = raw.normals[origin[static_cast<std::size_t>(v.idx())]];
    } else {
      const auto& n = om.normal(v);
      normal = {n[0], n[1], n[2]};
    }
    normal = finite(normal) ? normalized(normal) : Vec3{};
    remap[static_cast<std::size_t>(v.idx())] = static_cast<std::uint32_t>(mesh.vertices.size());
    mesh.vertices.push_back({p[0], p[1], p[2]});
    mesh.normals.push_back(normal);
    mesh.file_vertex.push_back(origin[static_cast<std::size_t>(v.idx())]);
  }
  for (const auto f : om.faces()) {
    for (const auto h : om.fh_range(f)) {
      mesh.corners.push_back(remap[static_cast<std::size_t>(om.to_vertex_handle(h).idx())]);
      if (texcoords) {
        const auto t = om.texcoord2D(h);
        mesh.corner_texcoords.push_back({t[0], t[1]});
      }
    }
    mesh.face_offsets.push_back(static_cast<std::uint32_t>(mesh.corners.size()));
  }
  mesh.problems = problems;
  mesh.file_lo = file_lo, mesh.file_hi = file_hi;
  mesh.float_file = raw.float_coordinates;
  if (mesh.face_count() == 0) {
    if (problems.faces_listed == 0) throw Error(source + ": the mesh has no faces");
    throw Error(fmt::format("{}: the mesh has no faces left: {} dropped ({})", source,
                            problems.faces_listed == 1 ? "its one face was" : fmt::format("all {} faces were", problems.faces_listed),
                            problems.summary()));
  }
  return mesh;
}

// Whether every border edge (used by one face; vertex indices) is covered by other border edges
// lying along it: T-junctions, where a closed surface's edge is split on one side only (a vertex of
// one face lies on another face's edge, as in CAD parts meshed face by face), leave the long edge and
// the short ones each used once. Such a surface is closed up to cracks of float rounding. A border
// of a hole or a sheet's rim is covered by nothing, so open meshes stay open (the first edge found
// uncovered ends the search).
bool border_is_cracks(const std::vector<Vec3>& positions, const std::vector<std::array<std::uint32_t, 2>>& border) {
  struct Edge {
    D3 a, b, d;  // ends, b - a
    double length, rounding;  // rounding: 4 float steps of its own coordinates
    int level;                // of the grid it is walked in: cells of at least half its length
  };
  std::vector<Edge> edges;
  edges.reserve(border.size());
  std::vector<double> lengths;
  D3 lo{INFINITY, INFINITY, INFINITY};
  for (const auto& [from, to] : border) {
    const D3 a = to_double(positions[from]), b = to_double(positions[to]), d = sub(b, a);
    const double length = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    if (!std::isfinite(length)) return false;
    // A T-junction's vertex is rounded off the line by half a float step, the line's ends by as much.
    const double magnitude = std::max({std::fabs(a[0]), std::fabs(a[1]), std::fabs(a[2]), std::fabs(b[0]), std::fabs(b[1]), std::fabs(b[2])});
    edges.push_back({a, b, d, length, std::ldexp(magnitude, -21), 0});
    if (length > 0) lengths.push_back(length);
    for (int k = 0; k < 3; ++k) lo[k] = std::min({lo[k], a[k], b[k]});
  }
  if (lengths.empty()) return true;  // only edges between two corners at one position: no crack
  // Grids of cells of the median length times 2^level; an edge is walked in the grid whose cells
  // are at least half its length (a few cells), so one long edge among many short ones costs no
  // more than they do.
  std::nth_element(lengths.begin(), lengths.begin() + static_cast<std::ptrdiff_t>(lengths.size() / 2), lengths.end());
  const double cell0 = lengths[lengths.size() / 2];
  std::vector<int> levels;
  for (Edge& e : edges) {
    e.level = e.length > cell0 ? std::min(60, static_cast<int>(std::ceil(std::log2(e.length / cell0)))) : 0;
    levels.push_back(e.level);
  }
  std::sort(levels.begin(), levels.end());
  levels.erase(std::unique(levels.begin(), levels.end()), levels.end());
  // Cell coordinates from the border's lowest corner, clamped (no overflow far out: the hash only
  // gathers candidates, and the exact test below decides).
  const auto cell_of = [&](const D3& p, int level) {
    const double size = std::ldexp(cell0, level);
    std::array<std::int64_t, 3> c{};
    for (int k = 0; k < 3; ++k) c[k] = static_cast<std::int64_t>(std::clamp(std::floor((p[k] - lo[k]) / size), -1e15, 1e15));
    return c;
  };
  const auto key = [](int level, const std::array<std::int64_t, 3>& c, std::int64_t x, std::int64_t y, std::int64_t z) {
    return static_cast<std::uint64_t>(c[0] + x) * 0x9E3779B97F4A7C15ull ^ static_cast<std::uint64_t>(c[1] + y) * 0xC2B2AE3D27D4EB4Full ^
           static_cast<std::uint64_t>(c[2] + z) * 0x165667B19E3779F9ull ^ static_cast<std::uint64_t>(level) * 0x27D4EB2F165667C5ull;
  };
  const auto walk = [&](const Edge& e, auto&& visit) {
    const auto steps = static_cast<std::int64_t>(std::ceil(2.0 * e.length / std::ldexp(cell0, e.level)));
    for (std::int64_t k = 0; k <= steps; ++k) {
      const double t = steps == 0 ? 0.0 : static_cast<double>(k) / static_cast<double>(steps);
      visit(cell_of({e.a[0] + t * e.d[0], e.a[1] + t * e.d[1], e.a[2] + t * e.d[2]}, e.level));
    }
  };
  // Per grid level the cells of every edge's endpoints, and the cells each edge passes in its own.
  std::vector<std::pair<std::uint64_t, std::uint32_t>> ends, passes;
  for (std::uint32_t i = 0; i < edges.size(); ++i) {
    walk(edges[i], [&](const std::array<std::int64_t, 3>& c) { passes.push_back({key(edges[i].level, c, 0, 0, 0), i}); });
    for (const int level : levels)
      for (const D3& p : {edges[i].a, edges[i].b}) ends.push_back({key(level, cell_of(p, level), 0, 0, 0), i});
  }
  std::sort(passes.begin(), passes.end());
  passes.erase(std::unique(passes.begin(), passes.end()), passes.end());
  std::sort(ends.begin(), ends.end());
  const auto gather_around = [&](const std::vector<std::pair<std::uint64_t, std::uint32_t>>& index, int level,
                                 const std::array<std::int64_t, 3>& c, std::vector<std::uint32_t>& out) {
    for (std::int64_t x = -1; x <= 1; ++x)
      for (std::int64_t y = -1; y <= 1; ++y)
        for (std::int64_t z = -1; z <= 1; ++z) {
          const std::uint64_t k = key(level, c, x, y, z);
          for (auto it = std::lower_bound(index.begin(), index.end(), std::pair<std::uint64_t, std::uint32_t>{k, 0});
               it != index.end() && it->first == k; ++it)
            out.push_back(it->second);
        }
  };
  // Whether point p lies on the line of edge l within `tolerance`.
  const auto on_line = [](const Edge& l, const D3& p, double tolerance) {
    const D3 c = cross3(l.d, sub(p, l.a));
    return std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]) <= tolerance * l.length;
  };
  std::vector<std::uint32_t> candidates;
  std::vector<std::pair<double, double>> spans;
  for (std::uint32_t i = 0; i < edges.size(); ++i) {
    const Edge& e = edges[i];
    if (e.length == 0) continue;  // two corners at one position: no crack
    // The edges with an endpoint near e (in e's grid), and those that pass near e's endpoints (in
    // theirs).
    candidates.clear();
    walk(e, [&](const std::array<std::int64_t, 3>& c) { gather_around(ends, e.level, c, candidates); });
    for (const int level : levels)
      for (const D3& p : {e.a, e.b}) gather_around(passes, level, cell_of(p, level), candidates);
    std::sort(candidates.begin(), candidates.end());
    candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
    // Their parameter intervals along e, where they lie on one line: the shorter's ends on the
    // longer's line (a short piece's own direction is off by its rounding over its short length),
    // within the longer's rounding and 1e-6 of the shorter's length (of the longer's, a small open
    // triangle beside a long edge passed).
    spans.clear();
    const double length2 = e.length * e.length;
    for (const std::uint32_t o : candidates) {
      if (o == i || edges[o].length == 0) continue;
      const Edge& other = edges[o];
      const Edge &longer = other.length > e.length ? other : e, &shorter = other.length > e.length ? e : other;
      const double tolerance = longer.rounding + 1e-6 * shorter.length;
      if (!on_line(longer, shorter.a, tolerance) || !on_line(longer, shorter.b, tolerance)) continue;
      const D3 wa = sub(other.a, e.a), wb = sub(other.b, e.a);
      const double ta = (wa[0] * e.d[0] + wa[1] * e.d[1] + wa[2] * e.d[2]) / length2, tb = (wb[0] * e.d[0] + wb[1] * e.d[1] + wb[2] * e.d[2]) / length2;
      spans.push_back({std::min(ta, tb), std::max(ta, tb)});
    }
    // Covered from 0 to 1 but for gaps of the tolerance (never a quarter of the edge or more).
    const double gap = std::min((e.rounding + 1e-6 * e.length) / e.length, 0.25);
    std::sort(spans.begin(), spans.end());
    double covered = 0;
    for (const auto& [from, to] : spans) {
      if (from > covered + gap) break;
      covered = std::max(covered, to);
    }
    if (covered < 1 - gap) return false;
  }
  return true;
}

}  // namespace

bool MeshProblems::any() const {
  return non_finite_vertices + unreadable_vertices + bad_vertex_faces + bad_index_faces + degenerate_faces + zero_area_faces +
             complex_faces + inconsistent_edges + turned_faces > 0 ||
         inward;
}

std::string MeshProblems::summary() const {
  std::vector<std::string> parts;
  if (non_finite_vertices > 0) parts.push_back(plural(non_finite_vertices, "vertex", "vertices") + " with a non-finite coordinate (nan, inf or beyond float range)");
  if (unreadable_vertices > 0) parts.push_back(plural(unreadable_vertices, "unreadable vertex", "unreadable vertices") + " (not three numbers)");
  if (bad_vertex_faces > 0) parts.push_back(plural(bad_vertex_faces, "face", "faces") + " using such vertices dropped");
  if (bad_index_faces > 0) parts.push_back(plural(bad_index_faces, "face", "faces") + " with an index out of range or unreadable dropped");
  if (degenerate_faces > 0) parts.push_back(plural(degenerate_faces, "degenerate face", "degenerate faces") + " (fewer than 3 distinct corners) dropped");
  if (zero_area_faces > 0) parts.push_back(plural(zero_area_faces, "zero-area face", "zero-area faces") + " kept (no surface to sample)");
  if (complex_faces > 0) parts.push_back(plural(complex_faces, "non-manifold or oppositely wound face", "non-manifold or oppositely wound faces") + " kept detached");
  if (inconsistent_edges > 0)
    parts.push_back(plural(inconsistent_edges, "edge", "edges") + " with inconsistent orientation (two faces use it in the same direction)");
  if (inward) parts.push_back("faces point inward (a closed surface encloses negative volume)");
  if (turned_faces > 0)
    parts.push_back(plural(turned_faces, "face", "faces") +
                    " turned to agree with their neighbours' winding (closed parts outward)");
  std::string line;
  for (const std::string& part : parts) line += (line.empty() ? "" : ", ") + part;
  return line;
}

double float_step_at(double reach) {
  return reach > 0 && std::isfinite(reach) ? std::ldexp(1.0, std::max(std::ilogb(reach), -126) - 23) : 0.0;
}

FloatStep float_step(double reach, double size) {
  const double step = float_step_at(reach);
  return {step, size, size > 0 ? step / size : 0.0};
}

std::string FloatStep::clause(std::string_view owner, std::string_view noun) const {
  return fmt::format("floats step by {:.3g} ({:.2g} % of {} {:.4g} {})", step, 100 * share, owner, size, noun);
}

std::string float_step_warning(const Mesh& mesh) {
  const Box box = mesh.bounds();
  // The spacing of floats where the mesh reaches (|x| 2^-24, half of it at most, was printed as the step).
  const FloatStep far = float_step(box.reach(), box.exact_diagonal());
  // Collapsed whole (a tiny part far out: every vertex read as one point), there is no diagonal to
  // compare with, and the warning was missing where it mattered most. The file's own coordinates are
  // gone by now: a mesh whose vertices coincide there reads the same, so the text allows both.
  if (mesh.vertices.size() > 1 && !(box.exact_diagonal() > 0) && far.step > 0)
    return fmt::format("coordinates reach {:.7g}, where floats step by {:.3g}: every vertex reads as the same point (the mesh has "
                       "no extent, or one finer than that step; if its vertices differ in the file, translate it nearer the origin)",
                       box.reach(), far.step);
  if (!far.coarse()) return {};
  return fmt::format("coordinates reach {:.7g}, where {}: detail finer than that was lost on reading; translate the mesh "
                     "nearer the origin",
                     box.reach(), far.clause("the mesh's", "diagonal"));
}

Box Mesh::bounds() const {
  Box box;
  for (const Vec3& p : vertices) box.add(p);
  return box;
}

bool Mesh::zero_area_face(std::size_t f) const { return rounded_zero_area(vertices, face_offsets, corners, f, kCollinearSteps); }

// Closed with every face, or without the (nearly) zero-area ones: they hold no surface, and one
// laid along an edge of a closed mesh made that edge non-manifold; but where zero-area faces fill a
// crack (an edge split on one side only) the mesh is closed only with them.
bool Mesh::closed() const {
  const auto closed_with = [&](bool zero_area_faces) {
    std::vector<std::uint32_t> offsets{0}, kept;
    for (std::size_t f = 0; f < face_count(); ++f) {
      if (!zero_area_faces && rounded_zero_area(vertices, face_offsets, corners, f, kTransformedSteps)) continue;
      kept.insert(kept.end(), corners.begin() + face_offsets[f], corners.begin() + face_offsets[f + 1]);
      offsets.push_back(static_cast<std::uint32_t>(kept.size()));
    }
    std::vector<std::uint64_t> edges;
    edges.reserve(kept.size());
    for (const auto& [a, b] : matched_edges(vertices, offsets, kept)) edges.push_back(undirected_edge(a, b));
    std::sort(edges.begin(), edges.end());
    if (edges.empty()) return false;
    // Every edge used by two faces; or by one face, where other such edges along it close the crack.
    const auto shift = static_cast<std::uint32_t>(vertices.size());
    std::vector<std::array<std::uint32_t, 2>> border;
    for (std::size_t i = 0, j = 0; i < edges.size(); i = j) {
      while (j < edges.size() && edges[j] == edges[i]) ++j;
      if (j - i > 2) return false;
      const auto vertex = [&](std::uint64_t id) { return static_cast<std::uint32_t>(id >= shift ? id - shift : id); };
      if (j - i == 1) border.push_back({vertex(edges[i] >> 32), vertex(edges[i] & 0xffffffffu)});
    }
    return border.empty() || border_is_cracks(vertices, border);
  };
  bool any_zero_area = false;
  for (std::size_t f = 0; f < face_count() && !any_zero_area; ++f) any_zero_area = rounded_zero_area(vertices, face_offsets, corners, f, kTransformedSteps);
  return closed_with(true) || (any_zero_area && closed_with(false));
}

Mesh load_mesh(const std::string& path, Winding winding) {
  silence_openmesh();
  return assemble(mesh_io::read_mesh_file(path), path, winding);
}

namespace {

// The file's positions less `origin`, in double, rounded to float afterwards; a vertex that leaves
// float range so (a crafted origin of 1e300) is a non-finite vertex, its faces dropped.
Mesh assemble_about(mesh_io::RawMesh raw, const std::string& source, Winding winding, const DVec3& origin) {
  for (std::size_t v = 0; v < raw.exact_positions.size(); ++v) {
    if (raw.bad_vertex[v]) continue;
    const DVec3 local = raw.exact_positions[v] - origin;
    const double largest = std::max({std::fabs(local.x), std::fabs(local.y), std::fabs(local.z)});
    if (largest <= std::numeric_limits<float>::max()) {
      raw.positions[v] = to_float(local);
    } else {
      raw.bad_vertex[v] = 1, raw.positions[v] = Vec3{};
      ++raw.problems.non_finite_vertices;
    }
  }
  Mesh mesh = assemble(raw, source, winding);
  mesh.origin = origin;
  return mesh;
}

// Whether `when` holds for the box [lo, hi] as the file gives it or as floats (the float box decides
// float_step_warning, which must not warn of a mesh left as it is; the exact one sees a mesh that
// collapses as floats).
double reach_of(const DVec3& lo, const DVec3& hi) {
  return std::max({std::fabs(lo.x), std::fabs(lo.y), std::fabs(lo.z), std::fabs(hi.x), std::fabs(hi.y), std::fabs(hi.z)});
}

bool wants_recentring(const DVec3& lo, const DVec3& hi, const RecentreTest& when) {
  if (!(lo.x <= hi.x)) return false;
  if (!when) return true;
  const double reach = reach_of(lo, hi);
  Box rounded;
  rounded.add(to_float(lo)), rounded.add(to_float(hi));
  return when(reach, length(hi - lo)) || when(rounded.reach(), rounded.exact_diagonal());
}

}  // namespace

Mesh load_mesh_about(const std::string& path, Winding winding, const DVec3& origin) {
  silence_openmesh();
  return assemble_about(mesh_io::read_mesh_file(path), path, winding, origin);
}

bool coarse_for_floats(double reach, double diagonal) { return float_step(reach, diagonal).coarse(); }

double Mesh::file_reach() const { return file_lo.x <= file_hi.x ? reach_of(file_lo, file_hi) : 0.0; }

bool recentring_wanted(const Mesh& mesh, const RecentreTest& when) { return wants_recentring(mesh.file_lo, mesh.file_hi, when); }

Mesh load_mesh_recentred(const std::string& path, Winding winding, const RecentreTest& when) {
  silence_openmesh();
  mesh_io::RawMesh raw = mesh_io::read_mesh_file(path);
  // The box of the vertices the kept faces use: a stray unused vertex far out moved the centre, and
  // the used ones were rounded at its magnitude.
  MeshProblems ignored;
  const auto [lo, hi] = file_box(raw, usable_faces(raw, ignored));
  if (!wants_recentring(lo, hi, when)) return assemble(raw, path, winding);
  return assemble_about(std::move(raw), path, winding, 0.5 * lo + 0.5 * hi);  // halves first: no overflow near the double range
}

Mesh parse_mesh(const std::string& path, std::string_view bytes) {
  silence_openmesh();
  return assemble(mesh_io::parse_mesh_file(path, bytes), path, Winding::AsGiven);
}

Mesh make_mesh(const std::vector<Vec3>& vertices, const std::vector<std::vector<std::uint32_t>>& faces,
               const std::string& description) {
  mesh_io::RawMesh raw;
  raw.positions.reserve(vertices.size());
  for (const Vec3& p : vertices) {
    if (!finite(p)) ++raw.problems.non_finite_vertices;
    raw.add_vertex(p, !finite(p));
  }
  for (const auto& face : faces) {
    for (const std::uint32_t i : face) raw.corners.push_back(i);
    raw.end_face();
  }
  return assemble(raw, description, Winding::AsGiven);
}

}  // namespace splatcl
