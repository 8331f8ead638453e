// Shared by every kernel file: index type and small helpers. Also compiled as C++ by the native
// references of the primitives (host/primitives/reference.cpp includes it inside a namespace).
#ifndef SPLATCL_COMMON_H
#define SPLATCL_COMMON_H

#ifdef __OPENCL_C_VERSION__
#define splatcl_min min
#else
#define splatcl_min std::min
#endif

// [first, last) of chunk c when n items are split into `chunks` nearly equal contiguous chunks.
inline size_t chunk_begin(size_t n, size_t chunks, size_t c) { return n / chunks * c + splatcl_min(c, n % chunks); }

#endif  // SPLATCL_COMMON_H

#ifdef SPLATCL_FORCE_BUILD_ERROR
// Lets the runtime tests check that a build failure reports this file and line.
this_is_a_deliberate_syntax_error
#endif
