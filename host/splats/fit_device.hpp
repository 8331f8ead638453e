#pragma once
// kernels/splat_fit.h compiled as C++: the parts of the splat fit that the kernels and the host must
// compute bit for bit alike (the reference's growth, the kNN graph's sheet test).
#include <cmath>    // splat_fit.h's std::sqrt, fmin, fmax, fabs (it is included inside the namespace below)
#include <cstddef>
#include <cstdint>
#include <cstdlib>  // its std::abs

namespace splatcl::splats::device {
using uint = std::uint32_t;
using std::size_t;
#include "../../kernels/splat_fit.h"
}  // namespace splatcl::splats::device
