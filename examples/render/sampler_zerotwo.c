/* sampler_zerotwo.c: pbrt-v3's ZeroTwoSequenceSampler (samplers/zerotwosequence.cpp; "02sequence", also
 * named "lowdiscrepancy"), with VanDerCorput and Sobol2D of core/lowdiscrepancy.h.
 *
 * A pixel sampler: for each of the first `dimensions` 1D and 2D dimensions of a pixel, its spp samples
 * (a power of two: pixelsamples is rounded up) are the first spp points of a (0,2)-sequence, the
 * van der Corput sequence in 1D and Sobol's first two dimensions in 2D, each randomized by a random
 * digit scramble (an XOR of a random 32-bit number: the points stay a (0, m, 2)-net, every elementary
 * interval of area 1/spp holding one point), then shuffled across the pixel's samples so that the
 * dimensions are not correlated. Past `dimensions`, uniform numbers from the pixel's stream (as
 * stratified). sampler.c makes a dimension's points on its first request in a pixel; each dimension's
 * stream depends only on the seed, the pixel and the dimension. */
#include "elr_internal.h"

/* dimension d (two: of the 2D dimensions) of this pixel, for all its samples */
void elr_zerotwo_make(elr_sampler *S, int two, int d) {
  const uint32_t *C0 = S->T->sobol.C, *C1 = S->T->sobol.C + ELR_SOBOL_COLUMNS; /* van der Corput; Sobol' dimension 1 */
  uint32_t n = (uint32_t)S->spp, i;
  elr_rng r;
  elr_rng_seed(&r, elr_mix64(S->seed * 0x9e3779b97f4a7c15ULL + 0x02d5eaULL + (uint64_t)(2 * d + two)),
               elr_mix64(((uint64_t)(uint32_t)S->px << 32) ^ (uint64_t)(uint32_t)S->py));
  if (!two) {
    /* <<VanDerCorput>>: n points of the scrambled sequence, then <<Randomly shuffle 1D sample points>> */
    float *a = S->s1d + (size_t)d * n;
    elr_gray_code_sample(C0, n, elr_rng_u32(&r), S->bits);
    for (i = 0; i < n; i++) a[i] = elr_bits_to_float(S->bits[i]);
    for (i = 0; i + 1 < n; i++) { /* pbrt's Shuffle */
      uint32_t o = i + elr_rng_bounded(&r, n - i);
      float t = a[i]; a[i] = a[o]; a[o] = t;
    }
  } else {
    /* <<Sobol2D>> */
    float *b = S->s2d + (size_t)d * n * 2;
    uint32_t sx = elr_rng_u32(&r), sy = elr_rng_u32(&r);
    elr_gray_code_sample(C0, n, sx, S->bits);
    elr_gray_code_sample(C1, n, sy, S->bits + n);
    for (i = 0; i < n; i++) { b[2 * i] = elr_bits_to_float(S->bits[i]); b[2 * i + 1] = elr_bits_to_float(S->bits[n + i]); }
    for (i = 0; i + 1 < n; i++) {
      uint32_t o = i + elr_rng_bounded(&r, n - i);
      float t0 = b[2 * i], t1 = b[2 * i + 1];
      b[2 * i] = b[2 * o]; b[2 * i + 1] = b[2 * o + 1]; b[2 * o] = t0; b[2 * o + 1] = t1;
    }
  }
}
