// Work-group building blocks for the GPU-shaped primitives (OpenCL C 1.2 has no work_group_scan).
// Every work-item of the group must call these (they contain barriers); GROUP_SIZE is a build option.
#ifndef SPLATCL_PRIMITIVES_GROUP_H
#define SPLATCL_PRIMITIVES_GROUP_H

#ifndef GROUP_SIZE
#error "GROUP_SIZE must be given as a build option"
#endif

#include "primitives_layout.h"

// Raking scan layout (primitives_layout.h): GROUP_SCAN_RAKES work-items each scan
// GROUP_SCAN_SEGMENT consecutive values of the padded scratch.
#define GROUP_SCAN_SEGMENT (GROUP_SIZE / GROUP_SCAN_RAKES)
#if GROUP_SCAN_SEGMENT * GROUP_SCAN_RAKES != GROUP_SIZE
#error "GROUP_SIZE must be a multiple of GROUP_SCAN_RAKES"
#endif
#define GROUP_SCAN_PADDED(i) GROUP_SCAN_PADDED_IN(GROUP_SIZE, i)
// Local elements the caller provides for a group scan.
#define GROUP_SCAN_SCRATCH GROUP_SCAN_SCRATCH_IN(GROUP_SIZE)

// Defines T NAME(T value, __local T* scratch, T* total): the exclusive prefix sum of `value` over
// the work-group, and the group's sum in *total. A raking scan: 4 barriers instead of the
// 2 log2(GROUP_SIZE) of a Hillis-Steele scan, which matters on CPUs (each barrier is a loop over the
// work-items) and costs little on GPUs. Every branch and loop has a uniform trip count, so every
// work-item reaches every barrier.
#define DEFINE_GROUP_EXCLUSIVE_SCAN(NAME, T)                                     \
  inline T NAME(T value, __local T* scratch, T* total) {                         \
    __local T* rake_sums = scratch + GROUP_SCAN_PADDED(GROUP_SIZE);              \
    const uint lid = (uint)get_local_id(0);                                      \
    scratch[GROUP_SCAN_PADDED(lid)] = value;                                     \
    barrier(CLK_LOCAL_MEM_FENCE);                                                \
    if (lid < GROUP_SCAN_RAKES) {                                                \
      T sum = 0;                                                                 \
      for (uint k = 0; k < GROUP_SCAN_SEGMENT; ++k) {                            \
        const uint index = GROUP_SCAN_PADDED(lid * GROUP_SCAN_SEGMENT + k);      \
        const T v = scratch[index];                                              \
        scratch[index] = sum;                                                    \
        sum += v;                                                                \
      }                                                                          \
      rake_sums[lid] = sum;                                                      \
    }                                                                            \
    barrier(CLK_LOCAL_MEM_FENCE);                                                \
    if (lid == 0) {                                                              \
      T sum = 0;                                                                 \
      for (uint r = 0; r < GROUP_SCAN_RAKES; ++r) {                              \
        const T v = rake_sums[r];                                                \
        rake_sums[r] = sum;                                                      \
        sum += v;                                                                \
      }                                                                          \
      rake_sums[GROUP_SCAN_RAKES] = sum;                                         \
    }                                                                            \
    barrier(CLK_LOCAL_MEM_FENCE);                                                \
    const T prefix = scratch[GROUP_SCAN_PADDED(lid)] + rake_sums[lid / GROUP_SCAN_SEGMENT]; \
    *total = rake_sums[GROUP_SCAN_RAKES];                                        \
    /* The caller may reuse scratch right away. */                               \
    barrier(CLK_LOCAL_MEM_FENCE);                                                \
    return prefix;                                                               \
  }

DEFINE_GROUP_EXCLUSIVE_SCAN(group_exclusive_scan, uint)
DEFINE_GROUP_EXCLUSIVE_SCAN(group_exclusive_scan_ulong, ulong)

#endif  // SPLATCL_PRIMITIVES_GROUP_H
