/* sampler_stratified.c: pbrt-v3's StratifiedSampler (samplers/stratified.cpp).
 *
 * For each of the first `dimensions` 1D and 2D dimensions of a pixel: one jittered sample per stratum
 * (xsamples x ysamples strata in 2D, their product in 1D), shuffled across the pixel's samples so that
 * the dimensions are not correlated (<<StratifiedSample1D>>, <<StratifiedSample2D>>, <<Shuffle>> of
 * StartPixel). sampler.c makes a dimension's strata on its first request in a pixel and hands them
 * out; dimensions past `dimensions` are uniform random. Each dimension's stream depends only on the
 * seed, the pixel and the dimension, so the same pixel gets the same numbers in any tile order. */
#include "elr_internal.h"

#define ELR_MINF(a, b) ((a) < (b) ? (a) : (b))

/* dimension d (two: of the 2D dimensions) of this pixel, for all its samples */
void elr_stratified_make(elr_sampler *S, int two, int d) {
  int i, n = S->spp;
  elr_rng r;
  elr_rng_seed(&r, elr_mix64(S->seed * 0x9e3779b97f4a7c15ULL + 3 + (uint64_t)(2 * d + two)),
               elr_mix64(((uint64_t)(uint32_t)S->px << 32) ^ (uint64_t)(uint32_t)S->py));
  if (!two) {
    float *a = S->s1d + (size_t)d * (size_t)n;
    for (i = 0; i < n; i++) a[i] = ELR_MINF(((float)i + (S->jitter ? elr_rng_float(&r) : 0.5f)) / (float)n, ELR_ONE_MINUS_EPS);
    for (i = n - 1; i > 0; i--) { int j = (int)(elr_rng_u32(&r) % (uint32_t)(i + 1)); float t = a[i]; a[i] = a[j]; a[j] = t; }
  } else {
    float *b = S->s2d + (size_t)d * (size_t)n * 2;
    int x, y;
    float ix = 1.f / (float)S->xs, iy = 1.f / (float)S->ys;
    for (y = 0; y < S->ys; y++)
      for (x = 0; x < S->xs; x++) {
        float jx = S->jitter ? elr_rng_float(&r) : 0.5f, jy = S->jitter ? elr_rng_float(&r) : 0.5f;
        b[2 * (y * S->xs + x)] = ELR_MINF(((float)x + jx) * ix, ELR_ONE_MINUS_EPS);
        b[2 * (y * S->xs + x) + 1] = ELR_MINF(((float)y + jy) * iy, ELR_ONE_MINUS_EPS);
      }
    for (i = n - 1; i > 0; i--) {
      int j = (int)(elr_rng_u32(&r) % (uint32_t)(i + 1));
      float t0 = b[2 * i], t1 = b[2 * i + 1];
      b[2 * i] = b[2 * j]; b[2 * i + 1] = b[2 * j + 1]; b[2 * j] = t0; b[2 * j + 1] = t1;
    }
  }
}
