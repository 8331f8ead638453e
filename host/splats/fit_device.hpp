#pragma once
// kernels/splat_fit.h compiled as C++: the parts of the splat fit that the kernels and the host must
// compute bit for bit alike (the reference's growth, the kNN graph's sheet test).
#include <cstddef>
#include <cstdint>

namespace splatcl::splats::device {
using uint = std::uint32_t;
using std::size_t;
#include "../../kernels/splat_fit.h"
}  // namespace splatcl::splats::device
