/* sampler_sobol.c: pbrt-v3's SobolSampler (samplers/sobol.cpp) with the Sobol' sequence of
 * core/lowdiscrepancy.h (here lowdiscrepancy.c).
 *
 * A global sampler: one Sobol' sequence over the image's power-of-two bounding square of
 * 2^m x 2^m pixels (m = log2 of the sample bounds' larger side, rounded up). Its first 2^(2m) points
 * put one point in each pixel, and every block of 2^(2m) points after them does the same; sample k of
 * pixel (x, y) is the point of block k that falls in that pixel (pbrt-v3's SobolIntervalToIndex, found
 * by the inverse of the linear map from the index's low 2m bits to the pixel: lowdiscrepancy.c).
 * Dimensions 0 and 1 are the point's position inside its pixel; dimension d >= 2 is the d-th Sobol'
 * coordinate of the same index (SampleDimension). pixelsamples is rounded up to a power of two.
 * pbrt-v3 uses the sequence as it is (no randomization: the image does not depend on the seed); the
 * "string randomization" parameter of pbrt-v4's SobolSampler (none by default here, as pbrt-v3;
 * permutedigits, fastowen, owen) scrambles dimensions 2 and up with a seed per dimension.
 * Past pbrt's 1024 dimensions pbrt-v3 stops with an error; here they are hashed random numbers. */
#include "elr_internal.h"

/* SampleDimension(index, dim) for the sampler's current sample (S->hindex) */
float elr_sobol_sampler_1d(const elr_sampler *S, int dim) {
  const elr_sampler_tables *T = S->T;
  uint32_t v;
  if (dim >= T->sobol.ndims) return elr_sampler_hash_float(S, dim);
  v = elr_sobol_bits(&T->sobol, (uint64_t)S->hindex, dim);
  if (dim < 2) {
    /* <<Remap Sobol' dimensions used for pixel samples>>: the position inside the pixel */
    float s = elr_bits_to_float(v) * (float)T->res + (float)(dim == 0 ? T->bx0 - S->px : T->by0 - S->py);
    return s > 0.f ? (s < ELR_ONE_MINUS_EPS ? s : ELR_ONE_MINUS_EPS) : 0.f;
  }
  if (S->randomize != ELR_RANDOMIZE_NONE) v = elr_randomize(v, S->randomize, (uint32_t)elr_sampler_dim_hash(S, dim));
  return elr_bits_to_float(v);
}
