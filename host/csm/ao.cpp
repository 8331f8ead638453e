#include "csm/ao.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>
#include <random>

#include "primitives/launch.hpp"
#include "runtime/error.hpp"
#include "core/parallel.hpp"

namespace splatcl::csm {
namespace {

// Receivers per work-item of the AO kernel, one per vector component (csm_query.h, CSM_AO_LANES).
constexpr std::uint32_t kAoLanes = 8;

constexpr const char* kPatternNames[] = {"monte-carlo", "stratified", "latin-hypercube", "halton-cp", "hammersley-cp", "hammersley-scrambled"};

double uniform01(std::mt19937& rng) { return static_cast<double>(rng()) / 4294967296.0; }

double radical_inverse(std::uint32_t k, std::uint32_t base) {
  double f = 1.0 / base, r = 0;
  for (; k; k /= base, f /= base) r += (k % base) * f;
  return r;
}

double wrap01(double v) { return v - std::floor(v); }

// Random digit scrambling (Kollig & Keller): XOR the 32-bit fixed-point value with a random word.
// u = 1 (Hammersley's k = N) is clamped below 2^32 first (Müller §5.3.1).
double scramble(double u, std::uint32_t word) {
  const double fixed = std::min(u * 4294967296.0, 4294967295.0);
  return static_cast<double>(static_cast<std::uint32_t>(fixed) ^ word) / 4294967296.0;
}

Vec4 cosine_direction(double xi1, double xi2) {
  const double r = std::sqrt(xi1), phi = 2 * std::numbers::pi * xi2;
  return {static_cast<float>(r * std::cos(phi)), static_cast<float>(std::sqrt(std::max(0.0, 1 - xi1))),
          static_cast<float>(r * std::sin(phi)), 0.0f};
}

}  // namespace

const char* to_string(PatternSet value) { return kPatternNames[static_cast<std::uint32_t>(value)]; }

PatternSet parse_pattern_set(const std::string& text) {
  // Short names of the `splatcl ao --pattern` option.
  if (text == "mc") return PatternSet::MonteCarlo;
  if (text == "lhs") return PatternSet::LatinHypercube;
  if (text == "halton") return PatternSet::HaltonRotated;
  std::string accepted = "mc, lhs, halton, ";
  for (std::uint32_t i = 0; i < std::size(kPatternNames); ++i) {
    if (text == kPatternNames[i]) return static_cast<PatternSet>(i);
    accepted += (i ? ", " : "") + std::string(kPatternNames[i]);
  }
  throw Error("unknown pattern set '" + text + "' (one of: " + accepted + ")");
}

std::vector<Vec4> make_patterns(PatternSet set, std::uint32_t patterns, std::uint32_t samples, std::uint32_t seed) {
  if (patterns == 0 || samples == 0) throw Error("AO patterns need at least one pattern and one sample");
  const auto strata = static_cast<std::uint32_t>(std::lround(std::sqrt(static_cast<double>(samples))));
  if (set == PatternSet::Stratified && strata * strata != samples)
    throw Error(fmt::format("stratified AO patterns need a square sample count, not {}", samples));
  std::mt19937 rng(seed);
  std::vector<Vec4> out;
  out.reserve(std::size_t{patterns} * samples);
  std::vector<std::uint32_t> permutation(samples);
  for (std::uint32_t j = 0; j < patterns; ++j) {
    const double shift1 = uniform01(rng), shift2 = uniform01(rng);
    const auto word1 = static_cast<std::uint32_t>(rng()), word2 = static_cast<std::uint32_t>(rng());
    std::iota(permutation.begin(), permutation.end(), 0u);
    for (std::uint32_t k = samples; k > 1; --k) std::swap(permutation[k - 1], permutation[static_cast<std::uint32_t>(rng() % k)]);
    for (std::uint32_t k = 0; k < samples; ++k) {
      double xi1 = 0, xi2 = 0;
      const double n = samples;
      switch (set) {
        case PatternSet::MonteCarlo:
          xi1 = uniform01(rng);
          xi2 = uniform01(rng);
          break;
        case PatternSet::Stratified:
          xi1 = (k / strata + uniform01(rng)) / strata;
          xi2 = (k % strata + uniform01(rng)) / strata;
          break;
        case PatternSet::LatinHypercube:
          xi1 = (k + uniform01(rng)) / n;
          xi2 = (permutation[k] + uniform01(rng)) / n;
          break;
        case PatternSet::HaltonRotated:
          xi1 = wrap01(radical_inverse(k + 1, 2) + shift1);
          xi2 = wrap01(radical_inverse(k + 1, 3) + shift2);
          break;
        case PatternSet::HammersleyRotated:
          xi1 = wrap01((k + 1) / n + shift1);
          xi2 = wrap01(radical_inverse(k + 1, 2) + shift2);
          break;
        case PatternSet::HammersleyScrambled:
          xi1 = scramble((k + 1) / n, word1);
          xi2 = scramble(radical_inverse(k + 1, 2), word2);
          break;
      }
      out.push_back(cosine_direction(xi1, xi2));
    }
  }
  return out;
}

std::vector<std::uint32_t> choose_patterns(std::size_t receivers, std::uint32_t patterns, std::uint32_t seed) {
  std::mt19937 rng(seed ^ 0x9e3779b9u);
  std::vector<std::uint32_t> out(receivers);
  for (auto& j : out) j = static_cast<std::uint32_t>(uniform01(rng) * patterns);
  return out;
}

void AoRequest::validate() const {
  if (normals.size() != positions.size() || pattern_of.size() != positions.size())
    throw Error("AO needs one normal and one pattern choice per receiver");
  if (samples == 0 || patterns.size() % samples != 0 || patterns.empty()) throw Error("AO patterns do not hold whole patterns of the sample count");
  const std::size_t count = patterns.size() / samples;
  for (std::uint32_t j : pattern_of)
    if (j >= count) throw Error(fmt::format("AO pattern choice {} out of {} patterns", j, count));
}

void ambient_occlusion_reference(const VisibilityScene& scene, const AoRequest& request, std::vector<Vec4>& out) {
  request.validate();
  out.resize(request.positions.size());
  const device::CsmScene view = scene.view();
  parallel_for(out.size(), 64, [&](std::size_t r, std::size_t) {
    const Vec4 p = request.positions[r], n = request.normals[r];
    float result[4];
    device::csm_ambient_occlusion(&view, &request.patterns[0].x, request.pattern_of[r] * 4 * request.samples, request.samples, p.x,
                                  p.y, p.z, n.x, n.y, n.z, request.own_instance, p.w, 1, request.ground ? 1 : 0, request.bias, result);
    out[r] = {result[0], result[1], result[2], result[3]};
  });
}

AmbientOcclusion::AmbientOcclusion(Runtime& runtime, const VisibilityScene& scene)
    : runtime_(runtime),
      scene_(runtime, scene),
      kernel_(runtime.kernel("csm_ao.cl", "csm_ambient_occlusion_receivers",
                                   fmt::format("-DCSM_AO_LANES={}", kAoLanes) + runtime.exact_divide_option())),
      positions_(runtime, "AO receivers"),
      normals_(runtime, "AO normals"),
      choice_(runtime, "AO pattern choice"),
      patterns_(runtime, "AO patterns"),
      result_(runtime, "AO output") {}

std::vector<Vec4> AmbientOcclusion::run(const AoRequest& request, Profiler* profiler) {
  request.validate();
  const std::size_t n = request.positions.size();
  if (n == 0) return {};
  if (n > UINT32_MAX) throw Error("more than 2^32 AO receivers in one batch");
  // Buffers grow as needed and are reused by later calls (no allocation per batch).
  // The last write blocks (the queue is in order): every upload is done before anything below can
  // throw and let the caller free the request.
  positions_.assign(request.positions, false);
  normals_.assign(request.normals, false);
  choice_.assign(request.pattern_of, false);
  patterns_.assign(request.patterns, true);
  result_.resize(n);
  kernel_.setArg(0, positions_.buffer());
  kernel_.setArg(1, normals_.buffer());
  kernel_.setArg(2, choice_.buffer());
  kernel_.setArg(3, static_cast<cl_uint>(n));
  kernel_.setArg(4, patterns_.buffer());
  kernel_.setArg(5, static_cast<cl_uint>(request.samples));
  scene_.bind_scene(kernel_, 6);
  kernel_.setArg(14, static_cast<cl_uint>(request.ground ? 1 : 0));
  kernel_.setArg(15, request.bias);
  kernel_.setArg(16, static_cast<cl_uint>(request.own_instance));
  kernel_.setArg(17, result_.buffer());
  enqueue_1d(runtime_.queue(), kernel_, (n + kAoLanes - 1) / kAoLanes, 0, profiler, "csm ambient occlusion");
  return result_.read();
}

}  // namespace splatcl::csm
