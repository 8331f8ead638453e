// Constants of the GPU-shaped primitive kernels that the host's launch checks and local-memory
// sizes depend on (host/primitives/tuning.cpp and radix_sort.cpp include this file): the group
// scan's rakes and scratch size, the GPU radix sort's digit width and its packed per-way count
// fields. Plain macros, valid in OpenCL C and in C++, written only here.
#ifndef SPLATCL_PRIMITIVES_LAYOUT_H
#define SPLATCL_PRIMITIVES_LAYOUT_H

// Raking scan over a work-group of `group` items (a multiple of GROUP_SCAN_RAKES): the rakes each
// scan group / GROUP_SCAN_RAKES consecutive values, segments padded by one entry so that the
// rakes' strided accesses fall in distinct local memory banks on GPUs. Scratch elements: padded
// values, rake sums, the total.
#define GROUP_SCAN_RAKES 16
#define GROUP_SCAN_PADDED_IN(group, i) ((i) + (i) / ((group) / GROUP_SCAN_RAKES))
#define GROUP_SCAN_SCRATCH_IN(group) (GROUP_SCAN_PADDED_IN(group, group) + GROUP_SCAN_RAKES + 1)

// GPU radix sort: digits of GPU_DIGIT_BITS bits per pass; a block's per-way counts are packed in
// SPLIT_FIELD_BITS-bit fields, so a block holds fewer than 2^SPLIT_FIELD_BITS keys.
#define GPU_DIGIT_BITS 4
#define GPU_RADIX (1 << GPU_DIGIT_BITS)
#define SPLIT_FIELD_BITS 16

#endif  // SPLATCL_PRIMITIVES_LAYOUT_H
