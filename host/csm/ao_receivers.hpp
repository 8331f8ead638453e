#pragma once
// Ambient occlusion for the vertices of a receiver mesh under placed occluders (Müller §5.3):
// each vertex is a receiver with its vertex normal; occluder instances may share one CSM. The result
// is written as a vertex-coloured binary PLY (grey = AO) carrying the AO value and the bent normal
// as extra vertex properties, and the mesh's faces so common viewers show it shaded.
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "csm/ao.hpp"
#include "core/mesh.hpp"

namespace splatcl::csm {

// How far each receiver vertex is lifted along its normal before it is queried, world units
// (empty: not lifted): off a surface that is its own occluder's, where a texel's single stored depth
// (an open mesh's exact single-hit rule) lies in front of half the surface it covers.
struct ReceiverLifts {
  std::vector<float> lifts;
  // The instance whose maps alone see the receivers lifted (the receiver's own: receiver_instance);
  // kNoInstance: every instance does. Lifted for all, receivers in contact with another occluder
  // were lifted through its surface: under a sphere resting on a thin plate a vertex read AO 1
  // off ray casting.
  std::uint32_t own_instance = kNoInstance;
};

struct ReceiverAoOptions {
  PatternSet pattern_set = PatternSet::HammersleyScrambled;
  std::uint32_t patterns = kDefaultPatterns, samples = kDefaultSamples, seed = 1;
  bool ground = false;
  float bias = 0;
  ReceiverLifts lift;  // receiver_lifts
  std::size_t batch = 1u << 16;  // receivers per kernel launch (progress granularity)
};

// The default lift in texels (`splatcl ao --lift`): receivers on an open mesh's own surface got AO
// 0.74 where ray casting gives 1 (a flat fan of 500 triangles; 1.00 lifted), the bunny's self-AO
// error against ray casting fell from 0.0202 to 0.0159 (4096 maps of 128²).
inline constexpr float kDefaultLiftTexels = 1, kMaxLiftTexels = 1000;
// Each vertex's lift for `splatcl ao --lift`, in world units. A receiver that is one of the
// occluder instances (receiver_instance) is lifted by `texels` texels (csm/query_reach.hpp
// placed_texel) of that instance, for that instance's queries only (as the presenter lifts an
// object's splats: csm/splat_lighting.cpp). Lifted by the coarsest occluder around it, a sphere
// resting on a large plate's CSM was lifted by the plate's texel, 11 of its own, which erased its
// contact AO (mean |AO − ray-cast| 0.196; 0.0285 now, 0.0288 unlifted). Any other receiver is
// not lifted: none of the CSMs holds its surface. Lifted by the coarsest occluder around it (until
// 2026-12-07), a floor under a box resting on it went into the box: AO up to 0.137 where it is 0.
ReceiverLifts receiver_lifts(const Mesh& receiver, const std::vector<const Csm*>& csms, const std::vector<Instance>& instances,
                                  float texels);

// The first instance whose CSM was built from `receiver` as it lies in the world: the receiver
// taken into the CSM's object space (placement and object transform undone) passes
// require_built_from (bounding sphere to 1e-4 R, count of casting triangles). None for a receiver
// that no occluder is.
std::optional<std::size_t> receiver_instance(const Mesh& receiver, const std::vector<const Csm*>& csms,
                                             const std::vector<Instance>& instances);

// Parses a placement: "tx,ty,tz" (translation), "tx,ty,tz,rx,ry,rz" (then rotations in degrees,
// applied about x, then y, then z, before the translation) or 16 numbers (row-major 4 × 4 affine).
// Throws Error naming the text.
Transform parse_placement(const std::string& text);

// out[v] = (bent normal xyz, AO) for every vertex of `receiver`. Vertices without a normal (zero:
// only degenerate faces around them) use +y. Runs on `runtime`, or the native reference when null.
// progress(done, total) after each batch. Throws Error for a mesh without vertices.
std::vector<Vec4> receiver_ambient_occlusion(const Mesh& receiver, const VisibilityScene& scene,
                                             const ReceiverAoOptions& options, Runtime* runtime,
                                             const std::function<void(std::size_t, std::size_t)>& progress = {});

// The AO of the same receivers and directions as receiver_ambient_occlusion, by exact ray casting
// against `occluder` (in world coordinates) instead of CSM queries: out[v] = lit fraction. A ray
// leaves the vertex 1e-4 bounding radii along its direction, so its own faces do not occlude it. The
// ground truth the CSM's AO error is measured against (docs/results/csm.md).
std::vector<float> raycast_ambient_occlusion(const Mesh& receiver, const Mesh& occluder, const ReceiverAoOptions& options);

// Binary little-endian PLY: vertex x y z nx ny nz red green blue ao bent_nx bent_ny bent_nz
// file_vertex, and face vertex_indices. The vertices are the mesh's as loaded: the file's in its
// order but those no face uses, then the copies of split non-manifold vertices; file_vertex is each
// one's index in the receiver file (Mesh::file_vertex). Written atomically.
void write_ao_ply(const std::string& path, const Mesh& receiver, const std::vector<Vec4>& ao);

}  // namespace splatcl::csm
