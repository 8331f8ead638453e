// Coherent shadow maps, streaming per-pixel greedy compression (Talpe §5.2).
// Maps arrive in batches in sequence order, laid out [map][pixel]. Each pixel keeps its open run's
// (max z1, min z2) between batches; a run is extended while max z1 < min z2 (strict), and a closed
// run is written as (max z1, min z2, inclusive end index). Two passes per batch: count the runs each
// pixel closes, then (after an exclusive scan of the counts) write them. CPU shape: one work-item
// per pixel, consecutive work-items read consecutive depths, no barriers.
// Native reference: compress_reference in host/csm/compress.cpp.

// State of a pixel before the first map: the neutral run (-inf, +inf).
kernel void csm_segment_count(global const float* z1, global const float* z2, uint pixels, uint maps, uint first_seq,
                              uint close_at_end, global const float* state_lo, global const float* state_hi,
                              global uint* counts) {
  const size_t p = get_global_id(0);
  if (p >= pixels) return;
  float lo = state_lo[p], hi = state_hi[p];
  uint closed = 0;
  for (uint k = 0; k < maps; ++k) {
    const float a = z1[(size_t)k * pixels + p], b = z2[(size_t)k * pixels + p];
    const float nlo = fmax(lo, a), nhi = fmin(hi, b);
    if (nlo < nhi) {
      lo = nlo;
      hi = nhi;
    } else {
      closed += (first_seq + k > 0) ? 1u : 0u;
      lo = a;
      hi = b;
    }
  }
  counts[p] = closed + close_at_end;
}

kernel void csm_segment_emit(global const float* z1, global const float* z2, uint pixels, uint maps, uint first_seq,
                             uint close_at_end, global float* state_lo, global float* state_hi,
                             global const uint* offsets, global float* out_lo, global float* out_hi,
                             global uint* out_end) {
  const size_t p = get_global_id(0);
  if (p >= pixels) return;
  float lo = state_lo[p], hi = state_hi[p];
  uint at = offsets[p];
  for (uint k = 0; k < maps; ++k) {
    const float a = z1[(size_t)k * pixels + p], b = z2[(size_t)k * pixels + p];
    const float nlo = fmax(lo, a), nhi = fmin(hi, b);
    if (nlo < nhi) {
      lo = nlo;
      hi = nhi;
    } else {
      if (first_seq + k > 0) {
        out_lo[at] = lo;
        out_hi[at] = hi;
        out_end[at] = first_seq + k - 1;
        ++at;
      }
      lo = a;
      hi = b;
    }
  }
  if (close_at_end) {
    out_lo[at] = lo;
    out_hi[at] = hi;
    out_end[at] = first_seq + maps - 1;
  }
  state_lo[p] = lo;
  state_hi[p] = hi;
}
