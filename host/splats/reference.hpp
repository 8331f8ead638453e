#pragma once
// Native C++ reference of the splat fit kernels (kernels/splat_fit.cl): the same algorithm and the
// same float operations in the same order, multithreaded over samples.
#include <vector>

#include "splats/fit.hpp"

namespace splatcl::splats::reference {

std::vector<Frame> fit_frames(const Samples& samples, const Neighborhoods& neighbors);

// Grows every splat from the given frames; FitResult::frames is set to `frames`.
FitResult grow_splats(const Samples& samples, const Neighborhoods& neighbors, const std::vector<Frame>& frames,
                      const FitOptions& options);

// Frames then growth.
FitResult fit_splats(const Samples& samples, const Neighborhoods& neighbors, const FitOptions& options);

}  // namespace splatcl::splats::reference
