// Kernels used only by `splatcl bench`.

// Streaming copy, the memory-bandwidth ceiling of the other kernels: one uint4 per work-item, so
// consecutive work-items touch consecutive memory and PoCL vectorizes across them.
__kernel void copy_uint4(__global const uint4* restrict src, __global uint4* restrict dst) {
  const size_t i = get_global_id(0);
  dst[i] = src[i];
}

// Peak single-precision arithmetic, the ceiling of compute-bound kernels: 16 independent chains
// (two float8) of `steps` dependent FMAs per work-item, enough to hide the FMA latency once PoCL
// or a GPU runs work-items side by side in vector lanes. 64 flops per step and work-item (an FMA
// counts 2). The sum is written so that the compiler keeps every chain; no contraction, so the
// host recomputes it exactly (host/bench/bandwidth.cpp).
#pragma OPENCL FP_CONTRACT OFF
__kernel void fma_peak(__global float* out, uint steps, float a, float b) {
  const size_t i = get_global_id(0);
  float8 x = (float8)((float)(i & 1023u) * 1e-4f) + (float8)(0.0f, 0.1f, 0.2f, 0.3f, 0.4f, 0.5f, 0.6f, 0.7f);
  float8 y = x + 0.05f;
  for (uint s = 0; s < steps; ++s) {
    x = fma(x, (float8)a, (float8)b);
    y = fma(y, (float8)a, (float8)b);
  }
  const float8 sum = x + y;
  const float4 half_sum = sum.lo + sum.hi;
  out[i] = half_sum.x + half_sum.y + half_sum.z + half_sum.w;
}
