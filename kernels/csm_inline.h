// CSM_INLINE, for the functions of the headers shared by the CSM kernels and their native references
// (csm_query.h, csm_trace.h, csm_raster.h). On the OpenCL side it forces inlining: PoCL's inliner
// otherwise keeps the larger query, traversal and raster functions as calls ("too costly to inline")
// inside the work-group function's work-item loop. In the C++ references it is plain inline.
#ifndef SPLATCL_CSM_INLINE_H
#define SPLATCL_CSM_INLINE_H

#ifdef __OPENCL_C_VERSION__
#define CSM_INLINE inline __attribute__((always_inline))
#else
#define CSM_INLINE inline
#endif

#endif  // SPLATCL_CSM_INLINE_H
