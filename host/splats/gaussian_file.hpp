#pragma once
// Export of a splat set as the de-facto 3D Gaussian Splatting PLY (`splatcl splats --format 3dgs`),
// which 3DGS viewers and tools read: binary little-endian, one "vertex" per splat with the float
// properties x y z, nx ny nz, f_dc_0 f_dc_1 f_dc_2, opacity, scale_0 scale_1 scale_2, rot_0 rot_1
// rot_2 rot_3, in that order. One flat Gaussian per splat (docs/formats.md):
// - σ along the major and minor axes = semi-axis / 2, so the ellipse's edge is the 2σ contour and
//   the Gaussian is the presenter's splat weight exp(−β r²) with its default β = 2
//   (present/scene.hpp Quality::gaussian); σ along the normal = 10⁻³ of the minor σ. scale_i = ln σ_i
//   (every σ at least kGaussianMinSigma, so the logs are finite);
// - rot = unit quaternion (w x y z, w ≥ 0) of the rotation whose columns are the splat's unit major
//   axis u, v = n × u and its unit normal n (the Gaussian's local x, y, z). v is ± the splat's minor
//   axis: the fit's orientation test can leave (u, v, n) left-handed, and the Gaussian is symmetric;
// - f_dc = (rgb / 255 − 0.5) / C0 (degree-0 spherical harmonic, C0 = 0.28209479177387814);
// - opacity = logit(kGaussianAlpha), the same for every splat.
// 3DGS has no clip lines: clipped splats are written as their whole ellipse.
#include <cstddef>
#include <string>
#include <vector>

#include "splats/splat_file.hpp"

namespace splatcl::splats {

inline constexpr double kGaussianSigmaPerSemiAxis = 0.5;  // σ_u = major / 2, σ_v = minor / 2
inline constexpr double kGaussianNormalSigma = 1e-3;      // σ_n = kGaussianNormalSigma · σ_v
inline constexpr double kGaussianMinSigma = 1e-30;        // floor of every σ (degenerate splats)
inline constexpr double kGaussianAlpha = 0.99;            // peak opacity; 1 would be logit = +inf
inline constexpr double kShC0 = 0.28209479177387814;      // degree-0 SH basis constant 1 / (2√π)

// The property names, in file order.
const std::vector<std::string>& gaussian_properties();

struct Gaussian {
  float position[3], normal[3], f_dc[3], opacity, scale[3], rotation[4];  // rotation: w, x, y, z
};

// The Gaussian of one splat (its clip line, if any, ignored).
Gaussian to_gaussian(const SplatRecord& splat);

// Unit quaternion (w, x, y, z), w ≥ 0, of the rotation matrix with columns c0, c1, c2 (orthonormal,
// right-handed), by Shepperd's method: stable for every rotation, w near 0 included.
void rotation_quaternion(const double c0[3], const double c1[3], const double c2[3], double q[4]);

// Writes the file atomically. Returns how many of the splats were clipped (clip_offset finite) and
// were written unclipped. A non-zero `origin` (the splats' positions are relative to it, SplatFileInfo)
// is written as a header comment `comment splatcl_origin X Y Z`, which 3DGS readers skip.
std::size_t write_gaussian_file(const std::string& path, const std::vector<SplatRecord>& splats, const DVec3& origin = {0, 0, 0});

// Gaussians fainter than this peak opacity are dropped on reading: in a trained 3DGS scene they are
// the faint floaters and fill-in that an opaque splat would turn into clutter.
inline constexpr double kGaussianMinReadAlpha = 0.1;

// The splats of a 3DGS PLY's bytes (ours, or any tool's: any property order and scalar types,
// f_rest_* and other properties ignored; x y z, scale_0..2 and rot_0..3 required, f_dc_0..2 and
// opacity optional). Each Gaussian becomes the flat splat of its two largest axes: semi-axes
// σ / kGaussianSigmaPerSemiAxis, normal the axis of the smallest σ (turned to the file's nx ny nz
// where those are given and non-zero), colour 0.5 + C0 · f_dc (grey without it). Inverts
// write_gaussian_file up to float rounding (and the sign of v). Throws Error naming `name` and the
// record for a missing property, a list property, a zero or non-finite quaternion or scale.
std::vector<SplatRecord> decode_gaussian_file(const std::string& bytes, const std::string& name);
// The origin splatcl's export records in the header (`comment splatcl_origin X Y Z`, written where
// the splats are relative to one); zero when the header has none (any other tool's file). Throws
// Error naming `name` for such a line that is not three finite numbers.
DVec3 gaussian_file_origin(const std::string& bytes, const std::string& name);

}  // namespace splatcl::splats
