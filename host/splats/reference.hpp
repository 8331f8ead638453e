#pragma once
// Native C++ reference of the splat fit kernels (kernels/splat_fit.cl): the same algorithm and the
// same float operations in the same order, multithreaded over samples.
#include <vector>

#include "splats/fit.hpp"

namespace splatcl::splats::reference {

// crease_degrees: FitOptions::crease_degrees.
std::vector<Frame> fit_frames(const Samples& samples, const Neighborhoods& neighbors, float crease_degrees);

// Grows every splat from the given frames; FitResult::frames is set to `frames`.
FitResult grow_splats(const Samples& samples, const Neighborhoods& neighbors, const std::vector<Frame>& frames,
                      const FitOptions& options);

// The colour test of the growth (the splat thesis §2.3.2; kernels/splat_fit.h's): every channel within
// `tolerance`. Also the colour rule of the surface fit's splats (splats/surface_fit.cpp).
bool color_similar(Rgba8 a, Rgba8 b, int tolerance);

// Sets kOnHullBit on the entries of q (sample indices, start point first, bits clear) whose
// projection on the plane through c spanned by fu, fv lies on the convex hull of the projected
// set, for |q| > 3; the start point is never marked (the splat thesis §2.2.3). The growth's own rule.
void mark_hull_points(const Samples& samples, Vec3 c, Vec3 fu, Vec3 fv, std::vector<std::uint32_t>& q);

// Frames then growth.
FitResult fit_splats(const Samples& samples, const Neighborhoods& neighbors, const FitOptions& options);

}  // namespace splatcl::splats::reference
