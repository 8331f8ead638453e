#include "csm/splat_lighting.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "runtime/profiling.hpp"

namespace splatcl::csm {
namespace {

// A batch of (receiver, light) visibility queries and, per query, where its answer goes. The
// receiver is an index: where it is queried depends on the instance (ReceiverPlaces).
struct QueryBatch {
  std::vector<std::size_t> receivers;
  std::vector<Vec4> lights;
  std::vector<std::size_t> where;
  void add(std::size_t receiver, const Vec4& light, std::size_t at) {
    receivers.push_back(receiver);
    lights.push_back(light);
    where.push_back(at);
  }
};

inline constexpr std::uint32_t kNoOwner = UINT32_MAX;

// Where each receiver is queried: through its own object's CSM lifted off that surface (`own`),
// through every other CSM at `other`, as `splatcl ao` lifts a receiver that is an occluder
// (csm/ao_receivers.hpp). Lifted through every instance, splats under a sphere resting on a thin
// plate went through the plate and read AO 1 where ray casting gives about 0.
struct ReceiverPlaces {
  const std::vector<Vec4>& own;
  const std::vector<Vec4>& other;
  const std::vector<std::uint32_t>& owner;  // per receiver its object, kNoOwner for none (a floor)
  const Vec4& at(std::size_t receiver, std::uint32_t occluder) const {
    return owner[receiver] == occluder ? own[receiver] : other[receiver];
  }
};

}  // namespace

SplatLighting::SplatLighting(Runtime& runtime, std::vector<const Csm*> csms, std::vector<Vec4> patterns,
                             std::vector<std::uint32_t> pattern_of)
    : runtime_(runtime), csms_(std::move(csms)), patterns_(std::move(patterns)), pattern_of_(std::move(pattern_of)) {}

AmbientOcclusion& SplatLighting::device() {
  if (!device_) device_ = std::make_unique<AmbientOcclusion>(runtime_, VisibilityScene(csms_, {}));
  return *device_;
}

float SplatLighting::slack_of(std::size_t object) {
  const auto found = slacks_.find(object);
  if (found != slacks_.end()) return found->second;
  return slacks_[object] = map_slack(csms_[object]->info);
}

bool SplatLighting::same_settings(const Settings& s) const {
  const Settings& t = settings_;
  return s.ao == t.ao && s.shadows == t.shadows && s.filter == t.filter && s.ao_samples == t.ao_samples &&
         s.shadow_samples == t.shadow_samples && s.bias == t.bias && s.lift == t.lift && s.ground == t.ground &&
         s.key_lights.size() == t.key_lights.size();
}

SplatLighting::Update SplatLighting::update(const Receivers& input, const std::vector<Transform>& placements,
                                            const Settings& settings, bool allow_incremental) {
  Update update;
  const std::size_t n = input.positions.size();
  const std::vector<Vec4>& positions = input.positions;
  const std::vector<Vec4>& normals = input.normals;
  const auto active = [&](std::size_t s) { return input.active.empty() || input.active[s] != 0; };
  std::vector<Instance> instances;
  for (std::size_t i = 0; i < input.objects.size(); ++i)
    if (input.objects[i].occluder) instances.push_back({static_cast<std::uint32_t>(i), placements[i]});
  const Filter filter = settings.filter;
  // Receivers lifted off their own surface along the normal, so that a splat's own CSM does not
  // shadow it: by kAoLiftTexels / kShadowLiftTexels texels of that CSM (query_reach.hpp), for that
  // CSM's queries only (ReceiverPlaces); shadow receivers by the lift as well, for every CSM.
  std::vector<float> own_texel(n, 0.0f);
  std::vector<std::uint32_t> owner(n, kNoOwner);
  for (std::size_t i = 0; i < input.objects.size(); ++i) {
    const auto first = static_cast<std::ptrdiff_t>(input.objects[i].first), end = first + static_cast<std::ptrdiff_t>(input.objects[i].count);
    std::fill(own_texel.begin() + first, own_texel.begin() + end, placed_texel(csms_[i]->info, placements[i]));
    std::fill(owner.begin() + first, owner.begin() + end, static_cast<std::uint32_t>(i));
  }
  const auto lifted_by = [&](std::size_t s, float by, float w) {
    return Vec4{positions[s].x + by * normals[s].x, positions[s].y + by * normals[s].y, positions[s].z + by * normals[s].z, w};
  };
  std::vector<Vec4> shadow_own(n), shadow_other(n), ao_own(n);
  for (std::size_t s = 0; s < n; ++s) {
    shadow_own[s] = lifted_by(s, settings.lift + kShadowLiftTexels * own_texel[s], 1.0f);
    shadow_other[s] = lifted_by(s, settings.lift, 1.0f);
    ao_own[s] = lifted_by(s, kAoLiftTexels * own_texel[s], positions[s].w);
  }
  const ReceiverPlaces ao_at{ao_own, positions, owner}, shadow_at{shadow_own, shadow_other, owner};
  const bool do_ao = settings.ao, do_shadows = settings.shadows && !settings.key_lights.empty();
  std::vector<std::vector<glm::vec3>> light_points;  // per key light
  for (const KeyLightShape& light : settings.key_lights) light_points.push_back(key_light_points(light, settings.shadow_samples));

  // Full update: every splat's AO directions and key-light points through each occluder instance,
  // where its Cone may reach. Incremental (occluders moved since the last update, same settings):
  // the moved objects' splats as in the full update; every other splat from its cached visibility
  // through the static occluders and new queries through the moved ones, only where those can
  // answer "occluded" (Cone); a splat whose set of lit AO directions changed gets its row from that
  // set (csm_ao_finish, as the AO kernel does). Both give the same rows bit for bit, and the same as
  // the AO kernel and one visibility batch through all instances (key_light_visibility).
  const bool incremental = allow_incremental && valid_ && rows_.size() == n * kRowFloats && same_settings(settings) &&
                           lit_placements_.size() == placements.size() && cone_reach_texels(filter, settings.bias).has_value();
  // Set again when the update completes: one that fails half way forces a full update next time.
  valid_ = false;
  std::vector<char> moved(input.objects.size(), 1), kernel_receiver(n, 1);
  if (incremental) {
    for (std::size_t i = 0; i < moved.size(); ++i) moved[i] = placements[i] != lit_placements_[i];
    std::fill(kernel_receiver.begin(), kernel_receiver.end(), 0);
    for (std::size_t i = 0; i < moved.size(); ++i)
      if (moved[i])
        std::fill(kernel_receiver.begin() + static_cast<std::ptrdiff_t>(input.objects[i].first),
                  kernel_receiver.begin() + static_cast<std::ptrdiff_t>(input.objects[i].first + input.objects[i].count), 1);
  }
  std::vector<float> dynamic = incremental ? rows_ : std::vector<float>(n * kRowFloats, 1.0f);
  std::vector<std::uint32_t> ao_subset, shadow_subset;
  for (std::size_t s = 0; s < n; ++s)
    if (kernel_receiver[s] && active(s)) ao_subset.push_back(static_cast<std::uint32_t>(s)), shadow_subset.push_back(static_cast<std::uint32_t>(s));

  // Runs the batch's queries through every instance of `through` (the CSM tables stay on the device,
  // only the instances are placed): per query the product of the instances' answers (0 or 1 with
  // Filter::None; PCF fractions are multiples of 1/16, so products are exact in any order); no
  // instances: all lit. A receiver whose own object is among them is queried through the others at
  // places.other and then, where still lit, through its own at places.own. Batches of any size: the
  // chunked kernel's work-group size is fixed on the CPU, so PoCL compiles it once, not once per
  // batch size.
  const auto run_queries = [&](const std::vector<Instance>& through, const QueryBatch& batch, const ReceiverPlaces& places,
                               Filter f) {
    std::vector<float> answer(batch.receivers.size(), 1.0f);
    if (through.empty() || batch.receivers.empty()) return answer;
    const auto run_through = [&](const std::vector<Instance>& part, const std::vector<Vec4>& receivers, const std::vector<Vec4>& lights) {
      VisibilityQueries& queries_device = device().queries();
      queries_device.place(part);
      return queries_device.run(receivers, lights, f, settings.bias);
    };
    // Through `part` at `place(receiver)`, the queries still lit.
    const auto run_part = [&](const std::vector<Instance>& part, const std::vector<std::size_t>& queries, auto&& place) {
      std::vector<Vec4> receivers, lights;
      std::vector<std::size_t> asked;
      for (const std::size_t q : queries) {
        if (answer[q] == 0.0f) continue;
        receivers.push_back(place(batch.receivers[q]));
        lights.push_back(batch.lights[q]);
        asked.push_back(q);
      }
      if (part.empty() || receivers.empty()) return;
      const std::vector<float> visible = run_through(part, receivers, lights);
      for (std::size_t k = 0; k < asked.size(); ++k) answer[asked[k]] *= visible[k];
    };
    const auto own = [&](std::size_t r) { return places.own[r]; };
    const auto other = [&](std::size_t r) { return places.other[r]; };
    // One instance, or no receiver owned by any of them (a floor): one launch of the whole batch,
    // each receiver where it is queried through them.
    const bool owned = std::any_of(batch.receivers.begin(), batch.receivers.end(), [&](std::size_t r) {
      return std::any_of(through.begin(), through.end(), [&](const Instance& i) { return i.occluder == places.owner[r]; });
    });
    if (through.size() == 1 || !owned) {
      std::vector<Vec4> receivers;
      receivers.reserve(batch.receivers.size());
      for (const std::size_t r : batch.receivers) receivers.push_back(through.size() == 1 ? places.at(r, through[0].occluder) : places.other[r]);
      return run_through(through, receivers, batch.lights);
    }
    // The queries by their receiver's own instance among `through` (the entry at through.size():
    // none of them).
    std::vector<std::vector<std::size_t>> by_own(through.size() + 1);
    for (std::size_t q = 0; q < batch.receivers.size(); ++q) {
      const std::uint32_t object = places.owner[batch.receivers[q]];
      std::size_t k = 0;
      while (k < through.size() && through[k].occluder != object) ++k;
      by_own[k].push_back(q);
    }
    for (std::size_t k = 0; k <= through.size(); ++k) {
      if (by_own[k].empty()) continue;
      std::vector<Instance> others = through;
      if (k < through.size()) others.erase(others.begin() + static_cast<std::ptrdiff_t>(k));
      run_part(others, by_own[k], other);
      if (k < through.size()) run_part({through[k]}, by_own[k], own);
    }
    return answer;
  };
  // Where the queries through an instance may answer "occluded" (Cone, with the reach the shadow
  // filter needs; cone_reach_texels). The AO's queries use Filter::None, which a larger reach bounds too.
  const std::optional<double> shadow_reach = cone_reach_texels(filter, settings.bias);
  const bool cull_shadows = shadow_reach.has_value(), cull_ao = cone_reach_texels(Filter::None, settings.bias).has_value();
  std::vector<MovedReach> instance_reaches;  // per entry of `instances`
  for (const Instance& instance : instances) {
    const CsmInfo& info = csms_[instance.occluder]->info;
    instance_reaches.push_back(moved_reach(info, placements[instance.occluder], slack_of(instance.occluder),
                                           shadow_reach.value_or(kReachTexels)));
  }

  // The AO kernel's directions for splat s into out[0 .. samples) (ao_directions).
  const std::uint32_t samples = settings.ao_samples;
  const auto pattern_at = [&](std::size_t s) { return input.pattern_of.empty() ? pattern_of_[s] : input.pattern_of[s]; };
  const auto directions_of = [&](std::size_t s, Vec4* out) {
    ao_directions(normals[s], &patterns_[std::size_t{pattern_at(s)} * samples], samples, settings.ground, out);
  };

  if (incremental) {
    Stopwatch clock;
    const std::uint32_t words = (samples + 63) / 64;
    // Slots per key light: its points (a light of size 0 has one, others shadow_samples).
    std::size_t points = 0;
    for (const auto& p : light_points) points = std::max(points, p.size());
    const std::size_t keys = light_points.size();
    std::vector<Instance> static_instances, moving_instances;
    std::vector<MovedReach> reaches;
    for (std::size_t k = 0; k < instances.size(); ++k) {
      const bool moving = moved[instances[k].occluder];
      (moving ? moving_instances : static_instances).push_back(instances[k]);
      if (moving) reaches.push_back(instance_reaches[k]);
    }
    // The cache of visibility through the static occluders, rebuilt when the moving set changes, and
    // per receiver when its input differs from the one its entries were made for (bit for bit), or
    // it was inactive since (its entries are dropped then).
    const bool rebuild = cached_movers_ != moved;
    if (rebuild) {
      static_lit_.assign(do_ao ? n * words : 0, 0);
      lit_mask_.assign(static_lit_.size(), 0);
      static_shadow_.assign(do_shadows ? n * keys * points : 0, 1.0f);
      static_directions_.assign(do_ao ? n * samples : 0, Vec4{});
      cached_.assign(n, 0);
      cached_positions_.assign(n, Vec4{});
      cached_normals_.assign(n, Vec4{});
      cached_patterns_.assign(n, 0);
    }
    std::vector<char> stale(n, 0);
    for (std::size_t s = 0; s < n; ++s) {
      if (kernel_receiver[s]) continue;
      if (!active(s)) {
        cached_[s] = 0;
        continue;
      }
      const std::uint32_t pattern = do_ao ? pattern_at(s) : 0;
      stale[s] = !cached_[s] || std::memcmp(&cached_positions_[s], &positions[s], sizeof(Vec4)) != 0 ||
                 std::memcmp(&cached_normals_[s], &normals[s], sizeof(Vec4)) != 0 || cached_patterns_[s] != pattern;
      if (!stale[s]) continue;
      cached_[s] = 1;
      cached_positions_[s] = positions[s];
      cached_normals_[s] = normals[s];
      cached_patterns_[s] = pattern;
      if (do_ao) std::fill_n(static_lit_.begin() + static_cast<std::ptrdiff_t>(s * words), words, std::uint64_t{0});
      if (do_shadows) std::fill_n(static_shadow_.begin() + static_cast<std::ptrdiff_t>(s * keys * points), keys * points, 1.0f);
    }
    {
      QueryBatch ao_batch;
      for (std::size_t s = 0; s < n && do_ao; ++s) {
        if (!stale[s]) continue;
        Vec4* d = &static_directions_[s * samples];
        directions_of(s, d);
        for (std::uint32_t j = 0; j < samples; ++j)
          if (d[j].w != 0) ao_batch.add(s, {d[j].x, d[j].y, d[j].z, 0.0f}, s * words * 64 + j);
      }
      const std::vector<float> lit = run_queries(static_instances, ao_batch, ao_at, Filter::None);
      for (std::size_t k = 0; k < ao_batch.where.size(); ++k) {
        const std::size_t bit = ao_batch.where[k];
        if (lit[k] > 0.0f) static_lit_[bit / 64] |= std::uint64_t{1} << (bit % 64);
      }
      QueryBatch shadow_batch;
      for (std::size_t s = 0; s < n && do_shadows; ++s) {
        if (!stale[s]) continue;
        for (std::size_t k = 0; k < keys; ++k)
          for (std::size_t j = 0; j < light_points[k].size(); ++j)
            shadow_batch.add(s, {light_points[k][j].x, light_points[k][j].y, light_points[k][j].z, 1.0f}, (s * keys + k) * points + j);
      }
      const std::vector<float> visible = run_queries(static_instances, shadow_batch, shadow_at, filter);
      for (std::size_t k = 0; k < shadow_batch.where.size(); ++k) static_shadow_[shadow_batch.where[k]] = visible[k];
      cached_movers_ = moved;
    }
    // Queries through the moved occluders where they may answer "occluded".
    std::vector<std::uint64_t> mask = static_lit_;
    // Per moved instance the Cone from where receiver s is queried through it.
    const auto cones_from = [&](std::size_t s, const ReceiverPlaces& places, std::vector<Cone>& cones) {
      cones.clear();
      for (std::size_t k = 0; k < reaches.size(); ++k) {
        const Vec4& p = places.at(s, moving_instances[k].occluder);
        cones.push_back(reaches[k].cone_from({p.x, p.y, p.z}));
      }
    };
    const auto reached = [](const std::vector<Cone>& cones, glm::vec3 w, float length) {
      return std::any_of(cones.begin(), cones.end(), [&](const Cone& c) { return c.may_reach(w, length); });
    };
    QueryBatch ao_batch;
    std::vector<Cone> cones;
    for (std::size_t s = 0; s < n && do_ao && !reaches.empty(); ++s) {
      if (kernel_receiver[s] || !active(s)) continue;
      // No lit direction left to test (all occluded by the static occluders or below the floor).
      if (std::all_of(mask.begin() + static_cast<std::ptrdiff_t>(s * words),
                      mask.begin() + static_cast<std::ptrdiff_t>((s + 1) * words), [](std::uint64_t w) { return w == 0; }))
        continue;
      cones_from(s, ao_at, cones);
      const Vec4* d = &static_directions_[s * samples];
      for (std::uint32_t j = 0; j < samples; ++j) {
        const std::size_t bit = s * words * 64 + j;
        if ((mask[bit / 64] >> (bit % 64) & 1) && reached(cones, {d[j].x, d[j].y, d[j].z}, d[j].w))
          ao_batch.add(s, {d[j].x, d[j].y, d[j].z, 0.0f}, bit);
      }
    }
    const std::vector<float> lit = run_queries(moving_instances, ao_batch, ao_at, Filter::None);
    for (std::size_t k = 0; k < ao_batch.where.size(); ++k) {
      const std::size_t bit = ao_batch.where[k];
      if (!(lit[k] > 0.0f)) mask[bit / 64] &= ~(std::uint64_t{1} << (bit % 64));
    }
    for (std::size_t s = 0; s < n && do_ao; ++s) {
      if (kernel_receiver[s] || !active(s)) continue;
      const bool changed = stale[s] || !std::equal(mask.begin() + static_cast<std::ptrdiff_t>(s * words),
                                                  mask.begin() + static_cast<std::ptrdiff_t>((s + 1) * words),
                                                  lit_mask_.begin() + static_cast<std::ptrdiff_t>(s * words));
      if (!changed) continue;
      if (instances.empty()) {
        ao_subset.push_back(static_cast<std::uint32_t>(s));  // no occluder: the row of the full update
        continue;
      }
      // The mask holds the kernel's answer for every direction: its row without the kernel.
      const Vec4* d = &static_directions_[s * samples];
      float sum[4] = {0.0f, 0.0f, 0.0f, 0.0f};
      std::uint32_t above = 0;
      for (std::uint32_t j = 0; j < samples; ++j) {
        const std::size_t bit = s * words * 64 + j;
        above += d[j].w != 0;
        if (mask[bit / 64] >> (bit % 64) & 1) device::csm_ao_add(sum, d[j].x, d[j].y, d[j].z);
      }
      device::csm_ao_finish(sum, normals[s].x, normals[s].y, normals[s].z, samples, above, settings.ground,
                            &dynamic[kRowFloats * s]);
      ++update.receivers;
    }
    lit_mask_ = std::move(mask);
    // Key-light visibility: per light point the product of the instances' PCF fractions, which are
    // multiples of 1/16, so static × moved is exact; then the mean over the points as in
    // key_light_visibility.
    std::vector<float> shadow = static_shadow_;
    QueryBatch shadow_batch;
    for (std::size_t s = 0; s < n && do_shadows && !reaches.empty(); ++s) {
      if (kernel_receiver[s] || !active(s)) continue;
      cones_from(s, shadow_at, cones);
      // Whether a moved instance's Cone may reach the light point from where s is queried through it.
      const auto may_shade = [&](glm::vec3 light) {
        for (std::size_t c = 0; c < cones.size(); ++c) {
          const Vec4& p = shadow_at.at(s, moving_instances[c].occluder);
          const glm::vec3 w = light - glm::vec3(p.x, p.y, p.z);
          if (cones[c].may_reach(w, glm::length(w))) return true;
        }
        return false;
      };
      for (std::size_t k = 0; k < keys; ++k)
        for (std::size_t j = 0; j < light_points[k].size(); ++j) {
          const std::size_t at = (s * keys + k) * points + j;
          if (shadow[at] != 0.0f && may_shade(light_points[k][j]))
            shadow_batch.add(s, {light_points[k][j].x, light_points[k][j].y, light_points[k][j].z, 1.0f}, at);
        }
    }
    const std::vector<float> visible = run_queries(moving_instances, shadow_batch, shadow_at, filter);
    for (std::size_t k = 0; k < shadow_batch.where.size(); ++k) shadow[shadow_batch.where[k]] *= visible[k];
    for (std::size_t s = 0; s < n && do_shadows; ++s) {
      if (kernel_receiver[s] || !active(s)) continue;
      for (std::size_t k = 0; k < keys; ++k) {
        float sum = 0.0f;
        for (std::size_t j = 0; j < light_points[k].size(); ++j) sum += shadow[(s * keys + k) * points + j];
        dynamic[kRowFloats * s + kVisibilityAt + k] = sum / static_cast<float>(light_points[k].size());
      }
    }
    update.stages.push_back({rebuild ? "cl: static occluder cache" : "cl: moved occluder queries", clock.elapsed_ms()});
  }
  update.receivers += static_cast<std::uint32_t>(ao_subset.size());
  // Rows to recompute start as "unoccluded": bent normal = normal, AO 1, every key light visible.
  for (const std::uint32_t s : ao_subset) {
    float* row = &dynamic[kRowFloats * std::size_t{s}];
    row[0] = normals[s].x, row[1] = normals[s].y, row[2] = normals[s].z, row[3] = 1.0f;
  }
  for (const std::uint32_t s : shadow_subset) std::fill(&dynamic[kRowFloats * std::size_t{s} + kVisibilityAt], &dynamic[kRowFloats * (std::size_t{s} + 1)], 1.0f);

  if (!instances.empty() && ((do_ao && !ao_subset.empty()) || (do_shadows && !shadow_subset.empty()))) {
    if (do_ao && !ao_subset.empty()) {
      Stopwatch clock;
      // Per (receiver, direction) the lit flag through every instance (Filter::None: 0 or 1, as the AO
      // kernel's csm_visibility), each instance queried only where its Cone may reach and the
      // direction is still lit; then the rows from the lit directions as the AO kernel makes them.
      const std::size_t m = ao_subset.size();
      std::vector<Vec4> receiver_directions(m * samples);
      std::vector<char> unblocked(m * samples);  // direction above the floor and lit so far
      for (std::size_t r = 0; r < m; ++r) {
        directions_of(ao_subset[r], &receiver_directions[r * samples]);
        for (std::uint32_t j = 0; j < samples; ++j) unblocked[r * samples + j] = receiver_directions[r * samples + j].w != 0;
      }
      for (std::size_t i = 0; i < instances.size(); ++i) {
        QueryBatch batch;
        for (std::size_t r = 0; r < m; ++r) {
          const Vec4& p = ao_at.at(ao_subset[r], instances[i].occluder);
          const Cone cone = cull_ao ? instance_reaches[i].cone_from({p.x, p.y, p.z}) : Cone{true};
          for (std::uint32_t j = 0; j < samples; ++j) {
            const std::size_t at = r * samples + j;
            const Vec4& d = receiver_directions[at];
            if (unblocked[at] && cone.may_reach({d.x, d.y, d.z}, d.w)) batch.add(ao_subset[r], {d.x, d.y, d.z, 0.0f}, at);
          }
        }
        const std::vector<float> visible = run_queries({instances[i]}, batch, ao_at, Filter::None);
        for (std::size_t x = 0; x < batch.where.size(); ++x)
          if (!(visible[x] > 0.0f)) unblocked[batch.where[x]] = 0;
      }
      for (std::size_t r = 0; r < m; ++r) {
        const Vec4& nrm = normals[ao_subset[r]];
        float sum[4] = {0.0f, 0.0f, 0.0f, 0.0f};
        std::uint32_t above = 0;
        for (std::uint32_t j = 0; j < samples; ++j) {
          const Vec4& d = receiver_directions[r * samples + j];
          above += d.w != 0;
          if (unblocked[r * samples + j]) device::csm_ao_add(sum, d.x, d.y, d.z);
        }
        device::csm_ao_finish(sum, nrm.x, nrm.y, nrm.z, samples, above, settings.ground,
                              &dynamic[kRowFloats * std::size_t{ao_subset[r]}]);
      }
      update.stages.push_back({"cl: splat AO", clock.elapsed_ms()});
    }
    if (do_shadows && !shadow_subset.empty()) {
      Stopwatch clock;
      // Per (key light, point, receiver), point-major as in key_light_visibility, the product of the
      // instances' PCF fractions; each instance is queried only where its Cone may reach and the
      // product is not 0 yet: a skipped answer is 1 or meets a 0, and products of multiples of 1/16
      // are exact in any order. Then, as there, the mean over each light's points.
      const std::size_t m = shadow_subset.size();
      std::vector<std::size_t> light_base{0};  // first entry of each key light's points
      for (const auto& p : light_points) light_base.push_back(light_base.back() + p.size() * m);
      std::vector<float> product(light_base.back(), 1.0f);
      std::vector<Cone> cones(m);
      for (std::size_t i = 0; i < instances.size(); ++i) {
        // Where receiver r is queried through instance i.
        const auto lift = [&](std::size_t r) {
          const Vec4& p = shadow_at.at(shadow_subset[r], instances[i].occluder);
          return glm::vec3(p.x, p.y, p.z);
        };
        for (std::size_t r = 0; r < m; ++r) cones[r] = cull_shadows ? instance_reaches[i].cone_from(lift(r)) : Cone{true};
        QueryBatch batch;
        for (std::size_t k = 0; k < light_points.size(); ++k)
          for (std::size_t j = 0; j < light_points[k].size(); ++j) {
            const Vec4 point{light_points[k][j].x, light_points[k][j].y, light_points[k][j].z, 1.0f};
            for (std::size_t r = 0; r < m; ++r) {
              const std::size_t at = light_base[k] + j * m + r;
              const glm::vec3 w = light_points[k][j] - lift(r);
              if (product[at] != 0.0f && cones[r].may_reach(w, glm::length(w))) batch.add(shadow_subset[r], point, at);
            }
          }
        const std::vector<float> visible = run_queries({instances[i]}, batch, shadow_at, filter);
        for (std::size_t x = 0; x < batch.where.size(); ++x) product[batch.where[x]] *= visible[x];
      }
      for (std::size_t r = 0; r < m; ++r)
        for (std::size_t k = 0; k < light_points.size(); ++k) {
          float sum = 0.0f;
          for (std::size_t j = 0; j < light_points[k].size(); ++j) sum += product[light_base[k] + j * m + r];
          dynamic[kRowFloats * std::size_t{shadow_subset[r]} + kVisibilityAt + k] = sum / static_cast<float>(light_points[k].size());
        }
      update.stages.push_back({"cl: splat shadows", clock.elapsed_ms()});
    }
  }
  rows_ = std::move(dynamic);
  settings_ = settings;
  valid_ = true;
  lit_placements_ = placements;
  if (!incremental) cached_movers_.clear();
  return update;
}

}  // namespace splatcl::csm
