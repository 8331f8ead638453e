#pragma once
// Per-splat lighting through every occluder's CSM: ambient occlusion with the bent normal (as the
// AO kernel computes it) and the visibility (Settings::filter) of up to 4 key lights, as rows of 8 floats per
// splat (bent normal xyz, AO, visibility of key lights 0-3).
//
// Full update: every splat's AO directions and key-light points through each occluder instance,
// only where its Cone may reach (csm/query_reach.hpp). Incremental (some occluders moved since the
// last update, the same settings): the moved objects' splats as in the full update; every other
// splat from its cached visibility through the static occluders and new queries through the moved
// ones where those can answer "occluded"; a splat whose set of lit AO directions changed gets its
// row from that set (csm_ao_finish, as the AO kernel does); a receiver whose position, normal or
// pattern changed since it was last cached (pixels that move, or come into view) is queried through
// the static occluders again, on its own. Both give the same rows bit for bit,
// and the same as the AO kernel and one visibility batch through all instances
// (key_light_visibility). Cross-map PCF and a negative bias always take the full update.
// An object's splats are lifted off its surface (query_reach.hpp) for its own CSM's queries only:
// their AO rows are the AO kernel's with the object as own_instance, `splatcl ao`'s rule.
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "csm/ao.hpp"
#include "csm/query_reach.hpp"
#include "runtime/runtime.hpp"

namespace splatcl::csm {

class SplatLighting {
 public:
  static constexpr std::size_t kRowFloats = 8;    // per splat
  static constexpr std::size_t kVisibilityAt = 4;  // first key light's visibility in a row
  static constexpr std::size_t kMaxKeyLights = kRowFloats - kVisibilityAt;

  struct Settings {
    bool ao = true;       // off: AO 1 and the bent normal = the normal
    bool shadows = true;  // off: every key light visible
    Filter filter = Filter::March;  // of the shadow queries (AO queries use Filter::None)
    std::uint32_t ao_samples = 16, shadow_samples = 4;
    float bias = 0.5f;    // CSM depth bias in texels of each occluder's CSM
    float lift = 0.02f;   // shadow receivers are lifted by it (world units) along their normal
    bool ground = true;   // AO directions below y = 0 count as occluded (a floor)
    std::vector<KeyLightShape> key_lights;  // at most kMaxKeyLights
  };
  struct Object {
    std::size_t first = 0, count = 0;  // its splats among the receivers
    bool occluder = true;              // casts AO and shadows through its CSM
  };
  struct Receivers {
    std::vector<Vec4> positions, normals;  // world space, per splat
    std::vector<Object> objects;                   // the objects with a CSM; other splats (a floor) belong to none
    // Per receiver its AO pattern; empty: the constructor's.
    std::vector<std::uint32_t> pattern_of;
    // Per receiver whether it is lit in this update (empty: all). An inactive receiver is not queried
    // and its row is left unspecified; its slot keeps a place for it (a pixel hidden this frame).
    std::vector<std::uint8_t> active;
  };
  struct Update {
    std::vector<std::pair<std::string, double>> stages;  // name, ms
    std::uint32_t receivers = 0;  // splats whose AO and shadows were recomputed
  };

  // `csms`: per object its CSM (occluder or not); `patterns` (samples per pattern, Vec4 each) and
  // `pattern_of` (per splat): the AO kernel's sample patterns.
  SplatLighting(Runtime& runtime, std::vector<const Csm*> csms, std::vector<Vec4> patterns,
                std::vector<std::uint32_t> pattern_of);

  // Recomputes the rows for the objects placed at `placements` (one per object, model → world).
  // `allow_incremental` false: the full update every time.
  Update update(const Receivers& input, const std::vector<Transform>& placements, const Settings& settings,
                bool allow_incremental);
  const std::vector<float>& rows() const { return rows_; }

  // Every object's CSM on the CL device, uploaded on first use; each query run places the instances
  // it goes through, which uploads only the instance table. Also for per-pixel queries.
  AmbientOcclusion& device();

 private:
  bool same_settings(const Settings& settings) const;
  float slack_of(std::size_t object);  // map_slack of the object's CSM, computed once

  Runtime& runtime_;
  std::vector<const Csm*> csms_;
  std::vector<Vec4> patterns_;
  std::vector<std::uint32_t> pattern_of_;
  std::unique_ptr<AmbientOcclusion> device_;
  std::map<std::size_t, float> slacks_;
  // The last update's rows, settings and placements: the incremental update starts from them.
  std::vector<float> rows_;
  Settings settings_;
  bool valid_ = false;
  std::vector<Transform> lit_placements_;
  // The incremental update's cache, for the objects marked in cached_movers_ as moving: per splat,
  // the AO directions lit through the static occluders and through all of them at the last update
  // (bit masks), and per splat, key light and light point the PCF visibility through the static ones.
  std::vector<char> cached_movers_;
  std::vector<std::uint64_t> static_lit_, lit_mask_;
  std::vector<float> static_shadow_;
  std::vector<Vec4> static_directions_;  // per splat and sample: its AO direction, w = |d| (0: below the floor)
  // Per splat the input its cache entries were made for (cached_: they hold it), so that a receiver
  // that changed is queried through the static occluders again.
  std::vector<char> cached_;
  std::vector<Vec4> cached_positions_, cached_normals_;
  std::vector<std::uint32_t> cached_patterns_;
};

}  // namespace splatcl::csm
