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

/* >> the reference path: pbrt-v4's Get1D / Get2D for one sample, as written there */
float elr_zsobol_ref_1d(elr_sampler *S, int dim) {
  uint64_t index = elr__zsobol_index(S, dim);
  uint32_t v = elr_sobol_bits(&S->T->sobol, index, 0);
  return elr_bits_to_float(elr_randomize(v, S->randomize, (uint32_t)elr_sampler_dim_hash(S, dim + 1)));
}

void elr_zsobol_ref_2d(elr_sampler *S, int dim, float u[2]) {
  uint64_t index = elr__zsobol_index(S, dim), h = elr_sampler_dim_hash(S, dim + 2);
  u[0] = elr_bits_to_float(elr_randomize(elr_sobol_bits(&S->T->sobol, index, 0), S->randomize, (uint32_t)h));
  u[1] = elr_bits_to_float(elr_randomize(elr_sobol_bits(&S->T->sobol, index, 1), S->randomize, (uint32_t)(h >> 32)));
}

/* >> the fast path: the same bits, with what depends only on the pixel and the dimension made once per
 * pixel (for sample counts up to ELR_ZSOBOL_FAST_SPP and dimensions below 64; the reference otherwise).
 *   - The permuted index of sample s is the pixel's permuted digits (zpixel[dim], index bits log2spp
 *     and up, the same for all its samples) OR the permuted sample digits (bits below log2spp), which
 *     depend on s, the pixel and the dimension: zlow[dim * spp + s], made for the pixel's spp samples at
 *     once, on the dimension's first request. A digit's permutation is chosen by a hash of the digits
 *     above it, so the hashes are shared by samples with those digits alike: (spp - 1) / 3 hashes per
 *     pixel and dimension for a power-of-4 count (plus spp / 2 for the lowest bit of an odd power of
 *     two), where the reference makes log2(spp) / 2 per sample.
 *   - A Sobol' point is linear over GF(2) in its index, and the two parts hold disjoint bits: the
 *     pixel part's point is made once (zsob), the sample's from the first byte table alone.
 *   - fastowen works on the bit-reversed point: the pixel part and the byte table (rlut) are kept
 *     reversed, and the final reversal is needed for the 24 bits the float keeps only (rev8, three
 *     bytes). */

/* the pixel's Morton code (pbrt-v4's StartPixelSample without the sample), for the fast path */
void elr_zsobol_start_pixel(elr_sampler *S, uint64_t morton) { S->zmorton = morton; S->zfast = 0; }

/* zlow and zsob of dimension dim for the current pixel */
static void elr__zsobol_make(elr_sampler *S, int dim) {
  int L = S->log2spp, odd = L & 1, spp = S->spp, i, s, c;
  uint64_t m0 = S->zmorton << L, dh = (uint64_t)(0x55555555u * (uint32_t)dim), pix;
  uint8_t *low = S->zlow + (size_t)dim * (size_t)spp;
  /* the pixel's digits: the reference's (and its cache), for any of its samples */
  { uint64_t keep = (uint64_t)S->hindex; S->hindex = (int64_t)m0; pix = elr__zsobol_index(S, dim) & ~(uint64_t)(spp - 1); S->hindex = (int64_t)keep; }
  for (s = 0; s < spp; s++) low[s] = 0;
  /* <<Apply random permutations to full base-4 digits>>, the sample's: digit i at bit 2i - odd, its
   * permutation chosen by the bits above it (the pixel's and the sample's higher digits) */
  for (i = (L + odd) / 2 - 1; i >= odd; i--) {
    int shift = 2 * i - odd, nprefix = spp >> (shift + 2), p;
    for (p = 0; p < nprefix; p++) {
      uint64_t above = (m0 >> (shift + 2)) | (uint64_t)p;
      const unsigned char *perm = elr__perm4[(unsigned)((elr_mix64(above ^ dh) >> 24) % 24u)];
      for (s = p << (shift + 2); s < (p + 1) << (shift + 2); s++) low[s] = (uint8_t)(low[s] | (perm[(s >> shift) & 3] << shift));
    }
  }
  /* <<Handle power-of-2 (but not 4) sample count>> */
  if (odd)
    for (s = 0; s < spp; s++) low[s] = (uint8_t)(low[s] | (((uint64_t)s & 1u) ^ (elr_mix64(((m0 | (uint64_t)s) >> 1) ^ dh) & 1u)));
  for (c = 0; c < 2; c++) {
    uint32_t v = elr_sobol_bits(&S->T->sobol, pix, c);
    S->zsob[dim][c] = S->randomize == ELR_RANDOMIZE_FAST_OWEN ? elr_reverse_bits32(v) : v;
  }
  S->zfast |= 1ull << dim;
}

/* pbrt-v4's FastOwenScrambler on the reversed point r, and the float of its first 24 digits */
static float elr__fast_owen_float(const elr_sobol *T, uint32_t r, uint32_t seed) {
  r ^= r * 0x3d20adeau;
  r += seed;
  r *= (seed >> 16) | 1u;
  r ^= r * 0x05526c56u;
  r ^= r * 0x53a22864u;
  /* reverse(r) >> 8: the low three bytes of r, each reversed, in the opposite order */
  return (float)(((uint32_t)T->rev8[r & 255u] << 16) | ((uint32_t)T->rev8[(r >> 8) & 255u] << 8) | T->rev8[(r >> 16) & 255u]) * 0x1p-24f;
}

static int elr__zsobol_fast(elr_sampler *S, int dim) {
  if (dim < 0 || dim >= 64 || !S->zlow) return 0;
  if (!((S->zfast >> dim) & 1u)) elr__zsobol_make(S, dim);
  return 1;
}

float elr_zsobol_1d(elr_sampler *S, int dim) {
  const elr_sobol *T = &S->T->sobol;
  unsigned low;
  uint32_t seed;
  if (!elr__zsobol_fast(S, dim)) return elr_zsobol_ref_1d(S, dim);
  low = S->zlow[(size_t)dim * (size_t)S->spp + ((size_t)S->hindex & (size_t)(S->spp - 1))];
  seed = (uint32_t)elr_sampler_dim_hash(S, dim + 1);
  if (S->randomize == ELR_RANDOMIZE_FAST_OWEN) return elr__fast_owen_float(T, S->zsob[dim][0] ^ T->rlut[0][low], seed);
  return elr_bits_to_float(elr_randomize(S->zsob[dim][0] ^ T->lut[0][0][low], S->randomize, seed));
}

void elr_zsobol_2d(elr_sampler *S, int dim, float u[2]) {
  const elr_sobol *T = &S->T->sobol;
  unsigned low;
  uint64_t h;
  if (!elr__zsobol_fast(S, dim)) { elr_zsobol_ref_2d(S, dim, u); return; }
  low = S->zlow[(size_t)dim * (size_t)S->spp + ((size_t)S->hindex & (size_t)(S->spp - 1))];
  h = elr_sampler_dim_hash(S, dim + 2);
  if (S->randomize == ELR_RANDOMIZE_FAST_OWEN) {
    u[0] = elr__fast_owen_float(T, S->zsob[dim][0] ^ T->rlut[0][low], (uint32_t)h);
    u[1] = elr__fast_owen_float(T, S->zsob[dim][1] ^ T->rlut[1][low], (uint32_t)(h >> 32));
    return;
  }
  u[0] = elr_bits_to_float(elr_randomize(S->zsob[dim][0] ^ T->lut[0][0][low], S->randomize, (uint32_t)h));
  u[1] = elr_bits_to_float(elr_randomize(S->zsob[dim][1] ^ T->lut[1][0][low], S->randomize, (uint32_t)(h >> 32)));
}
