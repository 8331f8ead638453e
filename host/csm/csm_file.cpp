#include "csm/csm_file.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "io/atomic_file.hpp"
#include "io/checksum.hpp"
#include "runtime/error.hpp"

namespace splatcl::csm {
namespace {

static_assert(std::endian::native == std::endian::little, "the .csm format is little-endian");

constexpr char kMagic[8] = {'S', 'P', 'L', 'A', 'T', 'C', 'S', 'M'};
constexpr std::size_t kChecksumOffset = 204, kCaptureOffset = 212, kSourceOffset = 216, kSourceBytes = kCsmHeaderBytes - kSourceOffset;
constexpr std::uint32_t kMaxResolution = 8192;
// Compact depth codes: 0..kCodeScale is depth code / kCodeScale; two codes are reserved.
constexpr std::uint16_t kCodeScale = 65533, kCodeExact = 65534, kCodeInfinity = 65535;


template <class T>
void put(std::string& out, std::size_t at, const T& value) {
  std::memcpy(out.data() + at, &value, sizeof(T));
}
template <class T>
T get(const std::string& in, std::size_t at) {
  T value;
  std::memcpy(&value, in.data() + at, sizeof(T));
  return value;
}
template <class T>
void append(std::string& out, const std::vector<T>& values) {
  out.append(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T));
}
template <class T>
std::vector<T> section(const std::string& in, std::size_t at, std::size_t count) {
  std::vector<T> values(count);
  if (count) std::memcpy(values.data(), in.data() + at, count * sizeof(T));
  return values;
}

float decode_code(std::uint16_t q) {
  if (q == kCodeInfinity) return INFINITY;
  return static_cast<float>(q) / static_cast<float>(kCodeScale);
}

// A code whose depth keeps every test of the run unchanged (lo <= g < hi, or g == lo when lo == hi),
// or kCodeExact when none does. Of the codes that fit, the one nearest the plain encoding's depth
// (segment_depth, the interval's midpoint): both encodings are lossless, and the midpoint keeps the
// margin to both surfaces that an unbiased shadow test needs (the lowest fitting code sat on max z1
// and shadowed lit receivers there).
std::uint16_t choose_code(float lo, float hi) {
  if (hi == INFINITY) return lo <= 1.0f ? kCodeInfinity : kCodeExact;
  if (!(lo >= 0.0f) || !(hi <= 1.0f)) return kCodeExact;
  const auto fits = [&](float g) { return lo <= g && (g < hi || (lo == hi && g == lo)); };
  const float middle = segment_depth(lo, hi);
  // The nearest codes to the middle are its rounding and the neighbours float rounding may shift it to.
  const long nearest = std::lround(static_cast<double>(middle) * kCodeScale);
  std::uint16_t best = kCodeExact;
  double best_distance = INFINITY;
  for (long q = std::max(0L, nearest - 1); q <= std::min<long>(kCodeScale, nearest + 1); ++q) {
    const float g = decode_code(static_cast<std::uint16_t>(q));
    const double distance = std::abs(static_cast<double>(g) - middle);
    if (fits(g) && distance < best_distance) best = static_cast<std::uint16_t>(q), best_distance = distance;
  }
  return best;
}

void put_varint(std::string& out, std::uint32_t value) {
  while (value >= 0x80) {
    out.push_back(static_cast<char>((value & 0x7f) | 0x80));
    value >>= 7;
  }
  out.push_back(static_cast<char>(value));
}

std::string header(const Csm& csm, Encoding encoding, const std::array<std::uint64_t, 3>& sections) {
  const CsmInfo& info = csm.info;
  std::string h(kCsmHeaderBytes, '\0');
  std::memcpy(h.data(), kMagic, 8);
  const SphereGrid grid(info.distribution, info.order, info.pole, info.maps);
  const std::uint32_t fields[] = {kCsmVersion,
                                  static_cast<std::uint32_t>(encoding),
                                  info.resolution,
                                  info.maps,
                                  grid.rows(),
                                  grid.cols(),
                                  static_cast<std::uint32_t>(info.distribution),
                                  static_cast<std::uint32_t>(info.order),
                                  static_cast<std::uint32_t>(info.pole),
                                  static_cast<std::uint32_t>(info.single_hit),
                                  info.triangles};
  for (std::size_t i = 0; i < std::size(fields); ++i) put(h, 8 + 4 * i, fields[i]);
  put(h, 52, info.hit_epsilon);
  put(h, 56, info.sphere.centre.x);
  put(h, 60, info.sphere.centre.y);
  put(h, 64, info.sphere.centre.z);
  put(h, 68, info.sphere.radius);
  const auto frame = pole_frame(info.pole);
  for (int k = 0; k < 3; ++k) {
    put(h, 72 + 12 * static_cast<std::size_t>(k), frame[static_cast<std::size_t>(k)].x);
    put(h, 76 + 12 * static_cast<std::size_t>(k), frame[static_cast<std::size_t>(k)].y);
    put(h, 80 + 12 * static_cast<std::size_t>(k), frame[static_cast<std::size_t>(k)].z);
  }
  for (std::size_t k = 0; k < 16; ++k) put(h, 108 + 4 * k, info.object_transform[k]);
  put(h, 172, static_cast<std::uint64_t>(csm.segments()));
  for (std::size_t k = 0; k < 3; ++k) put(h, 180 + 8 * k, sections[k]);
  put(h, kCaptureOffset, static_cast<std::uint32_t>(info.capture));
  std::memcpy(h.data() + kSourceOffset, info.source.data(), std::min(info.source.size(), kSourceBytes - 1));
  return h;
}

}  // namespace

const char* to_string(Encoding value) { return value == Encoding::Compact ? "compact" : "plain"; }

Encoding parse_encoding(const std::string& text) {
  if (text == "plain") return Encoding::Plain;
  if (text == "compact") return Encoding::Compact;
  throw Error("unknown encoding '" + text + "' (one of: plain, compact)");
}

float Csm::lookup(std::size_t pixel, std::uint32_t sequence) const {
  const auto first = end.begin() + offsets[pixel], last = end.begin() + offsets[pixel + 1];
  const auto it = std::lower_bound(first, last, sequence);
  return depth[static_cast<std::size_t>(it == last ? (last - end.begin()) - 1 : it - end.begin())];
}

Csm make_csm(const CsmInfo& info, const Segments& segments) {
  Csm csm;
  csm.info = info;
  csm.offsets = segments.offsets;
  csm.end = segments.end;
  csm.depth.resize(segments.size());
  for (std::size_t k = 0; k < segments.size(); ++k) csm.depth[k] = segment_depth(segments.lo[k], segments.hi[k]);
  return csm;
}

std::string encode_csm(const Csm& csm, Encoding encoding, const Segments* intervals) {
  if (intervals && intervals->size() != csm.segments()) throw Error("encode_csm: the intervals do not match the segments");
  std::string payload;
  std::array<std::uint64_t, 3> sections{};
  if (encoding == Encoding::Plain) {
    append(payload, csm.offsets);
    append(payload, csm.depth);
    append(payload, csm.end);
    sections = {csm.offsets.size() * 4, csm.depth.size() * 4, csm.end.size() * 4};
  } else {
    std::vector<std::uint16_t> codes(csm.segments());
    std::vector<float> exact;
    std::string runs;
    for (std::size_t p = 0; p < csm.pixels(); ++p) {
      std::uint32_t previous_end = 0;
      for (std::uint32_t k = csm.offsets[p]; k < csm.offsets[p + 1]; ++k) {
        const float g = csm.depth[k];
        const float lo = intervals ? intervals->lo[k] : g;
        const float hi = intervals ? intervals->hi[k] : (g == INFINITY ? g : std::nextafter(g, INFINITY));
        codes[k] = g == INFINITY ? kCodeInfinity : choose_code(lo, hi);
        if (codes[k] == kCodeExact) exact.push_back(g);
        // Run length − 1: the first run of a pixel starts at map 0.
        put_varint(runs, k == csm.offsets[p] ? csm.end[k] : csm.end[k] - previous_end - 1);
        previous_end = csm.end[k];
      }
    }
    append(payload, codes);
    payload += runs;
    append(payload, exact);
    sections = {codes.size() * 2, runs.size(), exact.size() * 4};
  }
  std::string out = header(csm, encoding, sections);
  std::uint64_t hash = fnv1a64({out.data(), out.size()});
  hash = fnv1a64({payload.data(), payload.size()}, hash);
  put(out, kChecksumOffset, hash);
  return out + payload;
}

void write_csm(const std::string& path, const Csm& csm, Encoding encoding, const Segments* intervals) {
  write_file_atomically(path, encode_csm(csm, encoding, intervals));
}

Csm decode_csm(const std::string& bytes, const std::string& name, Encoding* encoding_out) {
  const auto fail = [&](const std::string& why) -> Error { return Error(name + ": " + why); };
  if (bytes.size() < kCsmHeaderBytes) throw fail(fmt::format("not a .csm file (only {} bytes, the header alone has 256)", bytes.size()));
  if (std::memcmp(bytes.data(), kMagic, 8) != 0) throw fail("not a .csm file (bad magic)");
  const auto version = get<std::uint32_t>(bytes, 8);
  if (version != kCsmVersion)
    throw fail(fmt::format("not a splatcl .csm file of version {} (it has version {}; rebuild it with splatcl csm build)", kCsmVersion,
                           version));
  const auto encoding_value = get<std::uint32_t>(bytes, 12);
  if (encoding_value > 1) throw fail(fmt::format("unknown encoding {}", encoding_value));
  const auto encoding = static_cast<Encoding>(encoding_value);
  Csm csm;
  CsmInfo& info = csm.info;
  info.resolution = get<std::uint32_t>(bytes, 16);
  info.maps = get<std::uint32_t>(bytes, 20);
  const auto rows = get<std::uint32_t>(bytes, 24), cols = get<std::uint32_t>(bytes, 28);
  const std::uint32_t enums[4] = {get<std::uint32_t>(bytes, 32), get<std::uint32_t>(bytes, 36), get<std::uint32_t>(bytes, 40),
                                  get<std::uint32_t>(bytes, 44)};
  if (info.resolution == 0 || info.resolution > kMaxResolution) throw fail(fmt::format("bad resolution {}", info.resolution));
  if (enums[0] > 2 || enums[1] > 5 || enums[2] > 5 || (enums[3] > 1 && enums[3] != static_cast<std::uint32_t>(SingleHit::Thin)))
    throw fail("unknown distribution, order, pole axis or single-hit rule");
  info.distribution = static_cast<Distribution>(enums[0]);
  info.order = static_cast<Order>(enums[1]);
  info.pole = static_cast<PoleAxis>(enums[2]);
  info.single_hit = static_cast<SingleHit>(enums[3]);
  const auto capture = get<std::uint32_t>(bytes, kCaptureOffset);
  if (capture > 1) throw fail(fmt::format("unknown capture method {}", capture));
  info.capture = static_cast<CaptureMethod>(capture);
  info.triangles = get<std::uint32_t>(bytes, 48);
  info.hit_epsilon = get<float>(bytes, 52);
  info.sphere.centre = {get<float>(bytes, 56), get<float>(bytes, 60), get<float>(bytes, 64)};
  info.sphere.radius = get<float>(bytes, 68);
  if (!finite(info.sphere.centre) || !(info.sphere.radius >= kMinSphereRadius && info.sphere.radius <= kMaxSphereRadius) ||
      !(info.hit_epsilon >= 0) || !std::isfinite(info.hit_epsilon))
    throw fail("bad bounding sphere or hit epsilon");
  for (std::size_t k = 0; k < 16; ++k) {
    info.object_transform[k] = get<float>(bytes, 108 + 4 * k);
    if (!std::isfinite(info.object_transform[k])) throw fail("non-finite object transform");
  }
  // The object transform is an invertible affine map (row-major, last row 0 0 0 1): a singular one
  // would send every query to one point and make AO silently 1.
  const auto& t = info.object_transform;
  if (t[12] != 0 || t[13] != 0 || t[14] != 0 || t[15] != 1) throw fail("the object transform is not affine (its last row is not 0 0 0 1)");
  {
    const double det = double{t[0]} * (double{t[5]} * t[10] - double{t[6]} * t[9]) - double{t[1]} * (double{t[4]} * t[10] - double{t[6]} * t[8]) +
                       double{t[2]} * (double{t[4]} * t[9] - double{t[5]} * t[8]);
    double rows_norm = 1;
    for (int r = 0; r < 3; ++r) rows_norm *= std::sqrt(double{t[4 * r]} * t[4 * r] + double{t[4 * r + 1]} * t[4 * r + 1] + double{t[4 * r + 2]} * t[4 * r + 2]);
    if (!(std::abs(det) > 1e-6 * rows_norm)) throw fail(fmt::format("the object transform is singular (determinant {:g})", det));
  }
  // The pole frame is stored for other readers; it must be the frame of the stored pole axis.
  const auto frame = pole_frame(info.pole);
  for (std::size_t k = 0; k < 3; ++k)
    for (std::size_t c = 0; c < 3; ++c) {
      const float stored = get<float>(bytes, 72 + 12 * k + 4 * c);
      const float expected = c == 0 ? frame[k].x : c == 1 ? frame[k].y : frame[k].z;
      if (!(stored == expected)) throw fail(fmt::format("the pole frame does not match pole axis {} (zero, NaN or edited)", to_string(info.pole)));
    }
  const char* source = bytes.data() + kSourceOffset;
  info.source.assign(source, strnlen(source, kSourceBytes));
  const auto segments = get<std::uint64_t>(bytes, 172);
  std::array<std::uint64_t, 3> sections;
  for (std::size_t k = 0; k < 3; ++k) sections[k] = get<std::uint64_t>(bytes, 180 + 8 * k);
  const std::uint64_t pixels = std::uint64_t{info.resolution} * info.resolution;
  const std::uint64_t payload = bytes.size() - kCsmHeaderBytes;
  if (segments < pixels || segments > pixels * info.maps || segments > UINT32_MAX) throw fail(fmt::format("bad segment count {}", segments));
  if (sections[0] > payload || sections[1] > payload || sections[2] > payload ||
      sections[0] + sections[1] + sections[2] != payload)
    throw fail(fmt::format("file size {} does not match its sections (truncated or padded)", bytes.size()));
  std::string copy = bytes.substr(0, kCsmHeaderBytes);
  put(copy, kChecksumOffset, std::uint64_t{0});
  std::uint64_t hash = fnv1a64({copy.data(), copy.size()});
  hash = fnv1a64({bytes.data() + kCsmHeaderBytes, payload}, hash);
  if (hash != get<std::uint64_t>(bytes, kChecksumOffset)) throw fail("checksum mismatch (the file is corrupted)");
  // The grid is sized from the map count only now, and within the stated limit: a crafted count
  // allocates nothing before the checksum, and a resealed one nothing beyond the limit.
  if (info.maps == 0 || info.maps > kMaxMaps) throw fail(fmt::format("its map count {} is not in 1..{}", info.maps, kMaxMaps));
  try {
    const auto shape = grid_shape(info.distribution, info.order, info.maps);
    if (shape[0] != rows || shape[1] != cols) throw fail(fmt::format("grid {}x{} does not match {} maps", rows, cols, info.maps));
  } catch (const Error& e) {
    if (std::string(e.what()).rfind(name, 0) == 0) throw;
    // The grid's own message speaks of a requested count; here the count comes from the file.
    throw fail(fmt::format("its {} maps do not fit the {} distribution's grid", info.maps, to_string(info.distribution)));
  }

  const std::size_t at = kCsmHeaderBytes;
  if (encoding == Encoding::Plain) {
    if (sections[0] != (pixels + 1) * 4 || sections[1] != segments * 4 || sections[2] != segments * 4)
      throw fail("section sizes do not match the resolution and segment count");
    csm.offsets = section<std::uint32_t>(bytes, at, pixels + 1);
    csm.depth = section<float>(bytes, at + sections[0], segments);
    csm.end = section<std::uint32_t>(bytes, at + sections[0] + sections[1], segments);
  } else {
    if (sections[0] != segments * 2 || sections[2] % 4 != 0) throw fail("section sizes do not match the segment count");
    const std::vector<std::uint16_t> codes = section<std::uint16_t>(bytes, at, segments);
    const std::vector<float> exact = section<float>(bytes, at + sections[0] + sections[1], sections[2] / 4);
    const unsigned char* runs = reinterpret_cast<const unsigned char*>(bytes.data() + at + sections[0]);
    const std::size_t run_bytes = sections[1];
    std::size_t r = 0, e = 0;
    csm.offsets.assign(pixels + 1, 0);
    csm.depth.resize(segments);
    csm.end.resize(segments);
    std::size_t k = 0;
    for (std::uint64_t p = 0; p < pixels; ++p) {
      std::uint64_t next = 0;  // first map of the next run
      while (next < info.maps) {
        if (k >= segments) throw fail("more runs than segments");
        std::uint64_t value = 0;
        for (int shift = 0;; shift += 7) {
          if (r >= run_bytes || shift > 28) throw fail("corrupt run lengths");
          const unsigned char byte = runs[r++];
          value |= std::uint64_t{byte & 0x7fu} << shift;
          if (!(byte & 0x80)) break;
        }
        next += value + 1;
        if (next > info.maps) throw fail(fmt::format("pixel {}: runs exceed {} maps", p, info.maps));
        csm.end[k] = static_cast<std::uint32_t>(next - 1);
        if (codes[k] == kCodeExact) {
          if (e >= exact.size()) throw fail("fewer exact depths than escaped codes");
          csm.depth[k] = exact[e++];
        } else {
          csm.depth[k] = decode_code(codes[k]);
        }
        ++k;
      }
      csm.offsets[p + 1] = static_cast<std::uint32_t>(k);
    }
    if (k != segments || r != run_bytes || e != exact.size()) throw fail("sections hold more data than the segments use");
  }
  // Plain: offsets and end indices must describe N maps per pixel with increasing ends.
  if (csm.offsets[0] != 0 || csm.offsets[pixels] != segments) throw fail("offset table does not span the segments");
  for (std::uint64_t p = 0; p < pixels; ++p) {
    const std::uint32_t first = csm.offsets[p], last = csm.offsets[p + 1];
    if (last <= first || last > segments) throw fail(fmt::format("pixel {} has a bad segment range", p));
    for (std::uint32_t k = first; k < last; ++k) {
      if (k > first && csm.end[k] <= csm.end[k - 1]) throw fail(fmt::format("pixel {}: end indices not increasing", p));
      // Depth units: 0 on the camera plane, 1 at the sphere's far side; +inf for an empty run.
      const float d = csm.depth[k];
      if (!(d == INFINITY || (d >= -1e-3f && d <= 1.001f))) throw fail(fmt::format("pixel {}: depth {} outside [0, 1] (or +inf)", p, d));
    }
    if (csm.end[last - 1] != info.maps - 1) throw fail(fmt::format("pixel {}: segments do not end at map {}", p, info.maps - 1));
  }
  if (encoding_out) *encoding_out = encoding;
  return csm;
}

Csm read_csm(const std::string& path, Encoding* encoding, std::size_t* file_bytes) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw Error("cannot read " + path + ": it is a directory");
  if (!std::filesystem::is_regular_file(path, ec)) throw Error("cannot read " + path + ": no such file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot read " + path + ": not readable");
  const auto size = std::filesystem::file_size(path, ec);
  if (ec) throw Error("cannot read " + path + ": " + ec.message());
  std::string bytes(size, '\0');
  if (!in.read(bytes.data(), static_cast<std::streamsize>(size))) throw Error("cannot read " + path + ": read failed");
  if (file_bytes) *file_bytes = size;
  return decode_csm(bytes, path, encoding);
}

}  // namespace splatcl::csm
