#include "splats/sampling.hpp"

#include <fmt/format.h>


#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>
#include <numeric>

#include "io/image_codec.hpp"
#include "runtime/error.hpp"

namespace splatcl::splats {
namespace {

std::uint8_t channel(float value) { return static_cast<std::uint8_t>(std::clamp(std::lround(value * 255.0f), 0L, 255L)); }

// splitmix64's finaliser: a well-mixed, platform-independent hash step.
std::uint64_t mix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

// Fully saturated HSV colour: hue in [0, 1), value in [0, 1]; continuous in hue, also across 1 → 0.
Rgba8 hue_color(float hue, float value) {
  const float sector = hue * 6.0f;
  const float ramp = sector - std::floor(sector);
  const auto up = channel(value * ramp), down = channel(value * (1.0f - ramp)), full = channel(value);
  switch (static_cast<int>(sector) % 6) {
    case 0: return {full, up, 0, 255};
    case 1: return {down, full, 0, 255};
    case 2: return {0, full, up, 255};
    case 3: return {0, down, full, 255};
    case 4: return {up, 0, full, 255};
    default: return {full, 0, down, 255};
  }
}

Rgba8 field_color(ColorField field, const Box& bounds, Vec3 p) {
  const Vec3 extent = bounds.hi - bounds.lo;
  if (field == ColorField::Soft) {
    // Longest axis; t = 0 red, t = 1 white, so the red channel is 255 everywhere as in Fig. 3.8.
    int axis = extent.y > extent.x ? 1 : 0;
    if (extent.z > (axis == 0 ? extent.x : extent.y)) axis = 2;
    const float lo = axis == 0 ? bounds.lo.x : axis == 1 ? bounds.lo.y : bounds.lo.z;
    const float size = axis == 0 ? extent.x : axis == 1 ? extent.y : extent.z;
    const float value = axis == 0 ? p.x : axis == 1 ? p.y : p.z;
    const float t = size > 0 ? std::clamp((value - lo) / size, 0.0f, 1.0f) : 0.0f;
    return {255, channel(t), channel(t), 255};
  }
  // Eight cells along the diagonal's length (both the checker and the rainbow).
  const float cell = bounds.diagonal() / 8.0f;
  if (!(cell > 0)) return {};
  const auto index = [&](float v, float lo) { return static_cast<std::int64_t>(std::floor((v - lo) / cell)); };
  const std::int64_t cx = index(p.x, bounds.lo.x), cy = index(p.y, bounds.lo.y), cz = index(p.z, bounds.lo.z);
  if (field == ColorField::Rainbow) {
    // Hue runs along a direction picked per cell, so colours vary continuously inside a cell (the
    // hue circle wraps without a jump); a cell's hue offset, direction and frequency come from a hash
    // of the cell, and face-adjacent cells differ in brightness (value 1 vs 1/2), so every cell face
    // is a hard edge whatever the hues. Frequencies 1/4 … 4 hue cycles per cell, log-uniform, give
    // both gentle and steep places, as a rainbow texture mapped onto a model would.
    const std::uint64_t h = mix64(mix64(mix64(static_cast<std::uint64_t>(cx)) ^ static_cast<std::uint64_t>(cy)) ^
                                  static_cast<std::uint64_t>(cz));
    const auto uniform = [&](int slot) { return static_cast<float>((h >> (16 * slot)) & 0xffff) / 65536.0f; };
    const float z = 2.0f * uniform(0) - 1.0f, azimuth = 6.2831853f * uniform(1), r = std::sqrt(1.0f - z * z);
    const Vec3 direction{r * std::cos(azimuth), r * std::sin(azimuth), z};
    const float cycles_per_cell = std::exp2(4.0f * uniform(2) - 2.0f);
    const Vec3 corner{bounds.lo.x + static_cast<float>(cx) * cell, bounds.lo.y + static_cast<float>(cy) * cell,
                      bounds.lo.z + static_cast<float>(cz) * cell};
    const float along = dot(p - corner, direction) / cell;
    const float hue = uniform(3) + cycles_per_cell * along;
    return hue_color(hue - std::floor(hue), ((cx + cy + cz) & 1) == 0 ? 1.0f : 0.5f);
  }
  static constexpr Rgba8 palette[] = {{230, 25, 75, 255},  {60, 180, 75, 255},  {255, 225, 25, 255},
                                      {0, 130, 200, 255},  {245, 130, 48, 255}, {145, 30, 180, 255},
                                      {70, 240, 240, 255}, {20, 20, 20, 255}};
  const std::uint64_t h = static_cast<std::uint64_t>(cx * 73856093 ^ cy * 19349663 ^ cz * 83492791);
  return palette[h % 8];
}

// Newell normal of a polygon given by corner indices (robust for any planar polygon; zero for a
// degenerate one).
Vec3 polygon_normal(const Mesh& mesh, const std::uint32_t* ids, std::uint32_t count) {
  Vec3 n{};
  for (std::uint32_t c = 0; c < count; ++c) {
    const Vec3 a = mesh.vertices[mesh.corners[ids[c]]];
    const Vec3 b = mesh.vertices[mesh.corners[ids[c + 1 == count ? 0 : c + 1]]];
    n = n + Vec3{(a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y)};
  }
  return normalized(n);
}

// Whether a polygon's corners lie in one plane (within 1e-6 of its extent): a non-planar polygon
// is sampled as its fan triangles, the surface the checks measure against (splats/surface.hpp).
bool planar(const Mesh& mesh, const std::uint32_t* ids, std::uint32_t count) {
  if (count <= 3) return true;
  const Vec3 normal = polygon_normal(mesh, ids, count);
  const Vec3 origin = mesh.vertices[mesh.corners[ids[0]]];
  float extent = 0, off = 0;
  for (std::uint32_t c = 1; c < count; ++c) {
    const Vec3 r = mesh.vertices[mesh.corners[ids[c]]] - origin;
    extent = std::max(extent, length(r));
    off = std::max(off, std::fabs(dot(r, normal)));
  }
  return off <= 1e-6f * extent;
}

float shortest_edge(const Mesh& mesh) {
  float shortest = INFINITY;
  for (std::size_t f = 0; f < mesh.face_count(); ++f) {
    const std::uint32_t begin = mesh.face_offsets[f], end = mesh.face_offsets[f + 1];
    for (std::uint32_t c = begin; c < end; ++c) {
      const float l = length(mesh.vertices[mesh.corners[c + 1 == end ? begin : c + 1]] - mesh.vertices[mesh.corners[c]]);
      if (l > 0) shortest = std::min(shortest, l);  // zero-length edges of degenerate faces say nothing about spacing
    }
  }
  return shortest;
}

struct SampleBuilder {
  Samples samples;
  void add(Vec3 p, Vec3 n, Rgba8 c) {
    samples.positions.push_back(to_vec4(p));
    samples.normals.push_back(to_vec4(n));
    samples.colors.push_back(c);
  }
};

// The grid of one face (the splat thesis §2.1.1, Fig. 2.4): the face's bounding rectangle in its
// own plane, x along its first edge, walked row by row from the rectangle's lower corner with spacing
// d; the points strictly inside the (convex) polygon are kept. Points on the boundary are left out:
// they lie on an edge shared with the neighbouring face or on a vertex, which the vertex samples
// already hold, and keeping them puts long rows of near-duplicates along the edges (this reading gives
// the thesis's 110,174 samples on the bunny at n = 0.3 within 0.3 %). Colour and normal come from the
// fan triangle (corner 0, c, c + 1) holding the point, by barycentric interpolation.
//
// `ids` are the polygon's corner indices (into Mesh::corners); `first_edge` picks the corner that
// starts the rectangle's x axis (the thesis's rule is corner 0; the spacing mode takes the start of
// the longest edge, so a sliver's rectangle hugs it instead of spanning its long edge squared).
// `fan_cos`: for a fan triangle of a non-planar polygon, a corner normal (smoothed against the
// polygon's Newell normal, not this triangle's plane) less than this cosine from the triangle's own
// normal is replaced by it, as a triangle mesh's crease would; below -1: corner normals as they are.
void sample_face(const Mesh& mesh, const std::vector<Vec3>& normal_at_corner, const std::uint32_t* input_ids, std::uint32_t count,
                 std::uint32_t first_edge, double d, const ColorSource& colors, SampleBuilder& out, float fan_cos = -2.0f) {
  if (count < 3) return;
  std::vector<std::uint32_t> rotated(count);
  for (std::uint32_t c = 0; c < count; ++c) rotated[c] = input_ids[(c + first_edge) % count];
  const std::uint32_t* ids = rotated.data();
  const Vec3 normal = polygon_normal(mesh, ids, count);
  const Vec3 origin = mesh.vertices[mesh.corners[ids[0]]];
  const Vec3 ex = normalized(mesh.vertices[mesh.corners[ids[1]]] - origin);
  if (length(normal) == 0 || length(ex) == 0) return;  // degenerate face: no area to sample
  const Vec3 ey = cross(normal, ex);
  std::vector<Vec3> corner_normal(count);
  for (std::uint32_t c = 0; c < count; ++c) {
    corner_normal[c] = normal_at_corner[ids[c]];
    if (!(dot(corner_normal[c], normal) >= fan_cos)) corner_normal[c] = normal;
  }
  std::vector<double> xs(count), ys(count);
  double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
  for (std::uint32_t c = 0; c < count; ++c) {
    const Vec3 r = mesh.vertices[mesh.corners[ids[c]]] - origin;
    xs[c] = dot(r, ex);
    ys[c] = dot(r, ey);
    x0 = std::min(x0, xs[c]), x1 = std::max(x1, xs[c]), y0 = std::min(y0, ys[c]), y1 = std::max(y1, ys[c]);
  }
  // Signed area orients the inside test. A point closer than `margin` to an edge counts as on it:
  // float positions cannot tell such a point from the edge's.
  double area2 = 0;
  for (std::uint32_t c = 0; c < count; ++c) area2 += xs[c] * ys[(c + 1) % count] - xs[(c + 1) % count] * ys[c];
  if (area2 == 0) return;
  const double sign = area2 > 0 ? 1.0 : -1.0;
  const double margin = kFaceSampleMargin * std::max(x1 - x0, y1 - y0);
  const auto edge_side = [&](std::uint32_t c, double x, double y) {
    const std::uint32_t e = (c + 1) % count;
    const double ex_ = xs[e] - xs[c], ey_ = ys[e] - ys[c];
    return sign * (ex_ * (y - ys[c]) - ey_ * (x - xs[c])) / std::hypot(ex_, ey_);
  };
  for (double j = 0; y0 + j * d <= y1; j += 1) {
    for (double i = 0; x0 + i * d <= x1; i += 1) {
      const double x = x0 + i * d, y = y0 + j * d;
      bool inside = true;
      for (std::uint32_t c = 0; c < count && inside; ++c) inside = edge_side(c, x, y) > margin;
      if (!inside) continue;
      // Fan triangle (0, c, c+1) holding the point; barycentric weights in it.
      double w0 = 1, w1 = 0, w2 = 0;
      std::uint32_t tri = 1;
      for (std::uint32_t c = 1; c + 1 < count; ++c) {
        const double ax = xs[c] - xs[0], ay = ys[c] - ys[0], bx = xs[c + 1] - xs[0], by = ys[c + 1] - ys[0];
        const double det = ax * by - ay * bx;
        if (det == 0) continue;
        const double px = x - xs[0], py = y - ys[0];
        const double s = (px * by - py * bx) / det, t = (ax * py - ay * px) / det;
        if (s >= -1e-9 && t >= -1e-9 && s + t <= 1 + 1e-9) {
          w0 = 1 - s - t, w1 = s, w2 = t, tri = c;
          break;
        }
      }
      const std::uint32_t i0 = ids[0], i1 = ids[tri], i2 = ids[tri + 1];
      const Vec3 p = origin + static_cast<float>(x) * ex + static_cast<float>(y) * ey;
      const Vec3 n = normalized(static_cast<float>(w0) * corner_normal[0] + static_cast<float>(w1) * corner_normal[tri] +
                                static_cast<float>(w2) * corner_normal[tri + 1]);
      float uv[2] = {0, 0};
      if (mesh.has_texcoords()) {
        for (int k = 0; k < 2; ++k)
          uv[k] = static_cast<float>(w0 * mesh.corner_texcoords[i0][k] + w1 * mesh.corner_texcoords[i1][k] +
                                     w2 * mesh.corner_texcoords[i2][k]);
      }
      out.add(p, length(n) > 0 ? n : normal, colors.at(p, mesh.has_texcoords() ? uv : nullptr));
    }
  }
}

}  // namespace

// Per face corner, the normal its face's samples interpolate: the vertex normal, unless the faces
// around the vertex meet at a crease (two of them more than crease_degrees apart); then the mean
// normal of those within crease_degrees of this corner's face (auto-smooth), so that the samples
// beside a sharp edge keep their face's normal instead of the edge's average. 180: vertex normals.
std::vector<Vec3> corner_normals(const Mesh& mesh, float crease_degrees) {
  std::vector<Vec3> normals(mesh.corners.size());
  for (std::size_t c = 0; c < mesh.corners.size(); ++c) normals[c] = mesh.normals[mesh.corners[c]];
  if (crease_degrees >= 180) return normals;
  const float cos_crease = static_cast<float>(std::cos(static_cast<double>(crease_degrees) * std::numbers::pi / 180.0));
  const std::size_t faces = mesh.face_count();
  std::vector<Vec3> face_normal(faces);
  std::vector<std::uint32_t> face_of_corner(mesh.corners.size());
  for (std::size_t f = 0; f < faces; ++f) {
    const std::uint32_t begin = mesh.face_offsets[f], end = mesh.face_offsets[f + 1];
    std::vector<std::uint32_t> ids(end - begin);
    std::iota(ids.begin(), ids.end(), begin);
    // A zero-area face's normal is rounding noise: it neither takes part nor marks a crease.
    if (!mesh.zero_area_face(f)) face_normal[f] = polygon_normal(mesh, ids.data(), end - begin);
    for (std::uint32_t c = begin; c < end; ++c) face_of_corner[c] = static_cast<std::uint32_t>(f);
  }
  // The corners at each vertex (compressed rows).
  std::vector<std::uint32_t> first(mesh.vertices.size() + 1, 0), at_vertex(mesh.corners.size());
  for (const std::uint32_t v : mesh.corners) ++first[v + 1];
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) first[v + 1] += first[v];
  std::vector<std::uint32_t> fill(first.begin(), first.end() - 1);
  for (std::size_t c = 0; c < mesh.corners.size(); ++c) at_vertex[fill[mesh.corners[c]]++] = static_cast<std::uint32_t>(c);
  for (std::size_t c = 0; c < mesh.corners.size(); ++c) {
    const Vec3 own = face_normal[face_of_corner[c]];
    if (length(own) == 0) continue;
    const std::uint32_t v = mesh.corners[c];
    Vec3 sum{};
    bool crease = false;
    for (std::uint32_t r = first[v]; r < first[v + 1]; ++r) {
      const Vec3 other = face_normal[face_of_corner[at_vertex[r]]];
      if (length(other) == 0) continue;
      if (dot(own, other) >= cos_crease)
        sum = sum + other;
      else
        crease = true;
    }
    if (crease) normals[c] = normalized(sum);
  }
  return normals;
}

namespace {

// Keeps the first sample at each exact position, in order.
void drop_duplicates(Samples& samples) {
  const std::size_t n = samples.size();
  std::vector<std::uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  const auto key = [&](std::uint32_t i) {
    const Vec4& p = samples.positions[i];
    return std::tuple(p.x, p.y, p.z, i);
  };
  std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return key(a) < key(b); });
  std::vector<bool> keep(n, true);
  for (std::size_t r = 1; r < n; ++r) {
    const Vec4 &a = samples.positions[order[r - 1]], &b = samples.positions[order[r]];
    if (a.x == b.x && a.y == b.y && a.z == b.z) keep[order[r]] = false;  // order[r - 1] is earlier
  }
  std::size_t out = 0, kept_vertices = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!keep[i]) continue;
    if (i < samples.vertex_samples) ++kept_vertices;
    samples.positions[out] = samples.positions[i];
    samples.normals[out] = samples.normals[i];
    samples.colors[out] = samples.colors[i];
    ++out;
  }
  samples.duplicates_dropped = n - out;
  samples.vertex_samples = kept_vertices;
  samples.positions.resize(out);
  samples.normals.resize(out);
  samples.colors.resize(out);
}

}  // namespace

Texture load_texture(const std::string& path) {
  const DecodedImage image = decode_image_u8(path, "texture");
  const std::size_t texels = static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height);
  Texture texture{image.width, image.height, std::vector<std::uint8_t>(texels * 3)};
  for (std::size_t p = 0; p < texels; ++p)
    for (int c = 0; c < 3; ++c) texture.rgb[3 * p + c] = image.pixels[p * image.channels + std::min(c, image.channels - 1)];
  return texture;
}

const char* to_string(ColorField field) {
  switch (field) {
    case ColorField::Soft: return "soft";
    case ColorField::Hard: return "hard";
    case ColorField::Rainbow: return "rainbow";
    default: return "grey";
  }
}

ColorField parse_color_field(const std::string& text) {
  if (text == "grey" || text == "gray") return ColorField::Grey;
  if (text == "soft") return ColorField::Soft;
  if (text == "hard") return ColorField::Hard;
  if (text == "rainbow") return ColorField::Rainbow;
  throw Error("colour field '" + text + "' is not grey, soft, hard or rainbow");
}

Rgba8 ColorSource::at(Vec3 position, const float* texcoord) const {
  if (texture && texcoord) {
    // Nearest texel, repeating outside [0, 1]; texture v runs upwards, image rows downwards. 1 is
    // the last texel's edge, not the first's: a sample on a UV shell's u = 1 or v = 1 border took
    // the opposite edge's colour (wrong-coloured splats along every such seam).
    const auto texel = [](float t, int size) {
      const float wrapped = t >= 0.0f && t <= 1.0f ? t : t - std::floor(t);
      return std::min(static_cast<int>(wrapped * static_cast<float>(size)), size - 1);
    };
    const int x = texel(texcoord[0], texture->width), y = texture->height - 1 - texel(texcoord[1], texture->height);
    const std::uint8_t* p = &texture->rgb[3 * (static_cast<std::size_t>(y) * texture->width + x)];
    return {p[0], p[1], p[2], 255};
  }
  if (field != ColorField::Grey) return field_color(field, bounds, position);
  return {};
}

SamplingOptions parse_sampling(const std::string& text) {
  SamplingOptions options;
  if (text == "vertices") return options;
  if (text == "auto") {
    options.mode = SampleMode::Spacing;
    return options;
  }
  const auto number_after = [&](const char* prefix, double& out) {
    const std::size_t length = std::char_traits<char>::length(prefix);
    if (text.rfind(prefix, 0) != 0) return false;
    char* end = nullptr;
    const std::string number = text.substr(length);
    out = std::strtod(number.c_str(), &end);
    return !number.empty() && end && *end == '\0' && std::isfinite(out) && out > 0;
  };
  if (number_after("grid:", options.per_shortest_edge)) {
    options.mode = SampleMode::FaceGrid;
    return options;
  }
  if (number_after("spacing:", options.spacing)) {
    options.mode = SampleMode::Spacing;
    return options;
  }
  throw Error("'" + text + "' is not 'auto', 'vertices', 'grid:N' or 'spacing:D' with N, D > 0");
}

std::string to_string(const SamplingOptions& options) {
  switch (options.mode) {
    case SampleMode::Vertices: return "vertices";
    case SampleMode::FaceGrid: return fmt::format("grid:{}", options.per_shortest_edge);
    default: return options.spacing > 0 ? fmt::format("spacing:{}", options.spacing) : "auto";
  }
}

double auto_spacing(double eps, double diagonal) { return 0.5 * std::sqrt(eps * diagonal); }

namespace {

// The polygons a face is sampled as: itself when planar, else its fan triangles (corner 0, c, c+1).
template <class Visit>
void for_each_sampled_polygon(const Mesh& mesh, std::size_t f, Visit&& visit) {
  const std::uint32_t begin = mesh.face_offsets[f], end = mesh.face_offsets[f + 1];
  std::vector<std::uint32_t> ids(end - begin);
  for (std::uint32_t c = begin; c < end; ++c) ids[c - begin] = c;
  if (planar(mesh, ids.data(), end - begin)) {
    visit(ids.data(), end - begin);
    return;
  }
  for (std::uint32_t c = 1; c + 1 < end - begin; ++c) {
    const std::uint32_t triangle[3] = {ids[0], ids[c], ids[c + 1]};
    visit(triangle, 3u);
  }
}

// The corner that starts a polygon's longest edge.
std::uint32_t longest_edge_start(const Mesh& mesh, const std::uint32_t* ids, std::uint32_t count) {
  std::uint32_t best = 0;
  float longest = -1;
  for (std::uint32_t c = 0; c < count; ++c) {
    const float l = length(mesh.vertices[mesh.corners[ids[(c + 1) % count]]] - mesh.vertices[mesh.corners[ids[c]]]);
    if (l > longest) longest = l, best = c;
  }
  return best;
}

// An upper estimate of the grid points strictly inside all sampled polygons at spacing d (area / d²
// + perimeter / d + 1 each), computed before any sample is made so a budget can refuse or coarsen.
double grid_estimate(const Mesh& mesh, double d) {
  double total = 0;
  for (std::size_t f = 0; f < mesh.face_count(); ++f) {
    for_each_sampled_polygon(mesh, f, [&](const std::uint32_t* ids, std::uint32_t count) {
      const Vec3 a = mesh.vertices[mesh.corners[ids[0]]];
      double area = 0, perimeter = 0;
      for (std::uint32_t c = 0; c < count; ++c) {
        const Vec3 p = mesh.vertices[mesh.corners[ids[c]]], q = mesh.vertices[mesh.corners[ids[(c + 1) % count]]];
        perimeter += length(q - p);
        if (c >= 1 && c + 1 < count) area += 0.5 * length(cross(p - a, q - a));
      }
      total += area / (d * d) + perimeter / d + 1;
    });
  }
  return total;
}

}  // namespace

Samples sample_mesh(const Mesh& mesh, const SamplingOptions& options, const ColorSource& colors) {
  SampleBuilder builder;
  if (mesh.vertices.size() > options.max_samples)
    throw Error(fmt::format("{}: its {} vertices alone exceed the sample budget of {} (--max-samples)", mesh.source,
                            mesh.vertices.size(), options.max_samples));
  // A vertex's texture coordinate is that of its first face corner.
  std::vector<const float*> vertex_uv(mesh.vertices.size(), nullptr);
  if (mesh.has_texcoords())
    for (std::size_t c = mesh.corners.size(); c-- > 0;) vertex_uv[mesh.corners[c]] = mesh.corner_texcoords[c].data();
  // A vertex sample on a crease takes the normal of its first face corner's side, of a face that
  // has area: a zero-area face listed first gave its corner's vertex sample a noise normal.
  const std::vector<Vec3> normal_at_corner = corner_normals(mesh, options.crease_degrees);
  std::vector<Vec3> vertex_normal = mesh.normals;
  for (std::size_t f = mesh.face_count(); f-- > 0;) {
    if (mesh.zero_area_face(f)) continue;
    for (std::uint32_t c = mesh.face_offsets[f + 1]; c-- > mesh.face_offsets[f];) vertex_normal[mesh.corners[c]] = normal_at_corner[c];
  }
  builder.samples.positions.reserve(mesh.vertices.size());
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v)
    builder.add(mesh.vertices[v], vertex_normal[v], colors.at(mesh.vertices[v], vertex_uv[v]));
  builder.samples.vertex_samples = mesh.vertices.size();
  if (options.mode != SampleMode::Vertices) {
    double d = 0;
    if (options.mode == SampleMode::FaceGrid) {
      const float l_min = shortest_edge(mesh);
      if (!std::isfinite(l_min)) throw Error(mesh.source + ": every edge has zero length; nothing to sample");
      d = static_cast<double>(l_min) / options.per_shortest_edge;
    } else {
      d = options.spacing;
      if (!(d > 0 && std::isfinite(d))) throw Error(mesh.source + ": the sample spacing is not resolved (auto needs eps)");
    }
    const double room = static_cast<double>(options.max_samples - mesh.vertices.size());
    double estimate = grid_estimate(mesh, d);
    if (estimate > room) {
      if (!options.coarsen)
        throw Error(fmt::format("{}: sampling '{}' at spacing {:.4g} would make about {:.0f} samples, more than the budget of {} "
                                "(--max-samples); use a coarser sampling or raise the budget",
                                mesh.source, to_string(options), d, estimate + static_cast<double>(mesh.vertices.size()),
                                options.max_samples));
      const double requested = d;
      for (int step = 0; step < 64 && estimate > room; ++step) {
        d *= std::max(1.05, std::sqrt(estimate / std::max(room, 1.0)));
        estimate = grid_estimate(mesh, d);
      }
      builder.samples.note = fmt::format("sample spacing coarsened from {:.4g} to {:.4g} to stay within the budget of {} samples (--max-samples)",
                                         requested, d, options.max_samples);
    }
    builder.samples.grid_spacing = d;
    builder.samples.positions.reserve(mesh.vertices.size() + static_cast<std::size_t>(std::min(estimate, room)));
    // A non-planar polygon's fan triangles can stand far from its Newell normal (a crown's cap): their
    // samples' normals are kept within the crease angle of the triangle they lie on (at crease 180,
    // plain vertex normals as the thesis's method uses, at least facing its way), since the fit
    // orients each splat by them.
    const float fan_cos = options.crease_degrees >= 180
                              ? 0.0f
                              : static_cast<float>(std::cos(static_cast<double>(options.crease_degrees) * std::numbers::pi / 180.0));
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
      if (mesh.zero_area_face(f)) continue;  // no surface, and a normal of rounding noise
      const std::uint32_t corners = mesh.face_offsets[f + 1] - mesh.face_offsets[f];
      for_each_sampled_polygon(mesh, f, [&](const std::uint32_t* ids, std::uint32_t count) {
        const std::uint32_t first = options.mode == SampleMode::FaceGrid ? 0 : longest_edge_start(mesh, ids, count);
        sample_face(mesh, normal_at_corner, ids, count, first, d, colors, builder, count < corners ? fan_cos : -2.0f);
      });
    }
  }
  drop_duplicates(builder.samples);
  if (builder.samples.size() == 0) throw Error(mesh.source + ": the mesh yields no samples");
  if (builder.samples.size() >= (std::size_t{1} << 31)) throw Error(mesh.source + ": too many samples");
  return std::move(builder.samples);
}

}  // namespace splatcl::splats
