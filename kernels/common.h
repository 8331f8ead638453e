// Shared by every kernel file: index type and small helpers.
#ifndef SPLATCL_COMMON_H
#define SPLATCL_COMMON_H

// [first, last) of chunk c when n items are split into `chunks` nearly equal contiguous chunks.
inline size_t chunk_begin(size_t n, size_t chunks, size_t c) { return n / chunks * c + min(c, n % chunks); }

#endif  // SPLATCL_COMMON_H

#ifdef SPLATCL_FORCE_BUILD_ERROR
// Lets the runtime tests check that a build failure reports this file and line.
this_is_a_deliberate_syntax_error
#endif
