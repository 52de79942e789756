/* sampler_paddedsobol.c: pbrt-v4's PaddedSobolSampler (samplers.h).
 *
 * Each pixel's spp samples of each dimension are the first spp points of the Sobol' (0,2)-sequence
 * (dimension 0 in 1D, dimensions 0 and 1 in 2D), scrambled ("randomization": fastowen by default,
 * owen, permutedigits, none) and handed to the samples in a random order: a permutation of the sample
 * numbers (Kensler's, elr_permutation_element) and the scramble seeds are hashed from the pixel, the
 * dimension and "integer seed" (default: --seed). So every dimension of a pixel is a stratified
 * (0,2)-sequence and dimensions are "padded" together at random, like pbrt-v3's 02sequence but with
 * Owen scrambling and no table per pixel. Any sample count works (a power of two is best). */
#include "elr_internal.h"

static uint64_t elr__pixel_dim_hash(const elr_sampler *S, int dim) {
  uint64_t h = elr_mix64((((uint64_t)(uint32_t)S->px << 32) | (uint32_t)S->py) ^ 0x5851f42d4c957f2dULL);
  return elr_mix64(h ^ (((uint64_t)(uint32_t)dim << 32) | S->sseed));
}

float elr_paddedsobol_1d(const elr_sampler *S, int dim) {
  uint64_t h = elr__pixel_dim_hash(S, dim);
  uint32_t index = elr_permutation_element((uint32_t)S->sample, (uint32_t)S->spp, (uint32_t)h);
  return elr_bits_to_float(elr_randomize(elr_sobol_bits(&S->T->sobol, index, 0), S->randomize, (uint32_t)(h >> 32)));
}

void elr_paddedsobol_2d(const elr_sampler *S, int dim, float u[2]) {
  uint64_t h = elr__pixel_dim_hash(S, dim), h2 = elr_mix64(h);
  uint32_t index = elr_permutation_element((uint32_t)S->sample, (uint32_t)S->spp, (uint32_t)h);
  u[0] = elr_bits_to_float(elr_randomize(elr_sobol_bits(&S->T->sobol, index, 0), S->randomize, (uint32_t)h2));
  u[1] = elr_bits_to_float(elr_randomize(elr_sobol_bits(&S->T->sobol, index, 1), S->randomize, (uint32_t)(h >> 32)));
}
