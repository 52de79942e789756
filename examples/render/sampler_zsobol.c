/* sampler_zsobol.c: pbrt-v4's ZSobolSampler (samplers.h; Ahmed and Wonka, "Screen-space blue-noise
 * diffusion of Monte Carlo sampling error via hierarchical ordering of pixels", SIGGRAPH Asia 2020).
 *
 * One Sobol' (0,2)-sequence (dimensions 0 and 1 only) over the whole image, indexed by the Morton code
 * of the pixel followed by the sample number: pixel p's samples are 2^k consecutive points of a
 * Z-ordered sequence, so neighbouring pixels get points of one well-distributed set and their errors
 * are decorrelated (blue-noise-like). For each dimension the index is shuffled by a random permutation
 * of every base-4 digit, chosen by a hash of the digits above it and the dimension (and the lowest
 * bit flipped by a hash when the sample count is an odd power of two); the point is then scrambled
 * (pbrt-v4's "randomization": fastowen by default, owen, permutedigits or none) with a seed hashed from
 * the dimension and "integer seed" (default: --seed). A 1D dimension is Sobol' dimension 0 of that
 * index, a 2D dimension Sobol' dimensions 0 and 1. pixelsamples is rounded up to a power of two
 * (pbrt-v4 would use the power of two below it). The Morton code counts pixels from the sample bounds'
 * corner, in the power-of-two square that covers them. */
#include "elr_internal.h"

/* the 24 permutations of four digits, in lexicographic order */
static const unsigned char elr__perm4[24][4] = {
  {0, 1, 2, 3}, {0, 1, 3, 2}, {0, 2, 1, 3}, {0, 2, 3, 1}, {0, 3, 1, 2}, {0, 3, 2, 1},
  {1, 0, 2, 3}, {1, 0, 3, 2}, {1, 2, 0, 3}, {1, 2, 3, 0}, {1, 3, 0, 2}, {1, 3, 2, 0},
  {2, 0, 1, 3}, {2, 0, 3, 1}, {2, 1, 0, 3}, {2, 1, 3, 0}, {2, 3, 0, 1}, {2, 3, 1, 0},
  {3, 0, 1, 2}, {3, 0, 2, 1}, {3, 1, 0, 2}, {3, 1, 2, 0}, {3, 2, 0, 1}, {3, 2, 1, 0}};

/* the permuted digit of Morton index m at bit `shift` for dimension dim (dh = 0x55555555 * dim) */
static uint64_t elr__zsobol_digit(uint64_t m, int shift, uint64_t dh) {
  unsigned digit = (unsigned)(m >> shift) & 3u;
  unsigned p = (unsigned)((elr_mix64((m >> (shift + 2)) ^ dh) >> 24) % 24u); /* chosen by the digits above */
  return (uint64_t)elr__perm4[p][digit] << shift;
}

/* pbrt-v4's GetSampleIndex: the current Morton index (S->hindex) with its base-4 digits permuted for
 * dimension dim. The pixel's digits (those above the sample number's) are permuted alike for all its
 * samples: they are kept per dimension (the first 64) until the next pixel. */
static uint64_t elr__zsobol_index(elr_sampler *S, int dim) {
  int odd = S->log2spp & 1, ndigits = S->T->log2res + (S->log2spp + 1) / 2, first_pixel_digit = (S->log2spp + odd) / 2, i;
  uint64_t m = (uint64_t)S->hindex, index = 0, dh = (uint64_t)(0x55555555u * (uint32_t)dim);
  /* <<Apply random permutations to full base-4 digits>>: the pixel's (from the cache), then the sample's */
  if (dim < 64 && ((S->zvalid >> dim) & 1u)) index = S->zpixel[dim];
  else {
    for (i = ndigits - 1; i >= first_pixel_digit; i--) index |= elr__zsobol_digit(m, 2 * i - odd, dh);
    if (dim < 64) { S->zpixel[dim] = index; S->zvalid |= 1ull << dim; }
  }
  for (i = first_pixel_digit - 1; i >= odd; i--) index |= elr__zsobol_digit(m, 2 * i - odd, dh);
  /* <<Handle power-of-2 (but not 4) sample count>> */
  if (odd) index |= (m & 1u) ^ (elr_mix64((m >> 1) ^ dh) & 1u);
  return index;
}

float elr_zsobol_1d(elr_sampler *S, int dim) {
  uint64_t index = elr__zsobol_index(S, dim);
  uint32_t v = elr_sobol_bits(&S->T->sobol, index, 0);
  return elr_bits_to_float(elr_randomize(v, S->randomize, (uint32_t)elr_sampler_dim_hash(S, dim + 1)));
}

void elr_zsobol_2d(elr_sampler *S, int dim, float u[2]) {
  uint64_t index = elr__zsobol_index(S, dim), h = elr_sampler_dim_hash(S, dim + 2);
  u[0] = elr_bits_to_float(elr_randomize(elr_sobol_bits(&S->T->sobol, index, 0), S->randomize, (uint32_t)h));
  u[1] = elr_bits_to_float(elr_randomize(elr_sobol_bits(&S->T->sobol, index, 1), S->randomize, (uint32_t)(h >> 32)));
}
