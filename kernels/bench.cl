// Kernels used only by `splatcl bench`.

// Streaming copy, the memory-bandwidth ceiling of the other kernels: one uint4 per work-item, so
// consecutive work-items touch consecutive memory and PoCL vectorizes across them.
__kernel void copy_uint4(__global const uint4* restrict src, __global uint4* restrict dst) {
  const size_t i = get_global_id(0);
  dst[i] = src[i];
}
