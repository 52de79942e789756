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
 * corner, in the power-of-two square that covers them.
 *
 * Two paths give the same bits (test_render_samplers checks every draw and the rendered images): the
 * reference, pbrt-v4's GetSampleIndex and SobolSample for one sample as written there (elr_zsobol_ref_1d,
 * _2d), and the fast path (up to 256 spp; the environment variable ELR_ZSOBOL_REFERENCE forces the
 * reference), which makes a pixel's points of a dimension for all its samples at once (below).
 * Instructions per camera sample on bench_city (16 spp, direct lighting, bench/callgrind_parts.py):
 * 1225 -> 512 for the sampler (path, 4 spp: 2123 -> 1411). */
#include "elr_internal.h"
#include <string.h>

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
 * On a dimension's first request in a pixel (as a 1D or as a 2D draw: their scrambles differ), the
 * pixel's points of that dimension for all its samples are made at once; a draw is then a load.
 *   - The permuted index of sample s is the pixel's permuted digits (index bits log2spp and up, the same
 *     for all its samples) OR the permuted sample digits (bits below log2spp), which depend on s, the
 *     pixel and the dimension (zlow). A digit's permutation is chosen by a hash of the digits above it,
 *     so samples with those digits alike share it: (spp - 1) / 3 hashes per pixel and dimension for a
 *     power-of-4 count (plus spp / 2 for the lowest bit of an odd power of two), where the reference
 *     makes log2(spp) / 2 per sample. The pixel's digits are kept per dimension from its last pixel:
 *     only the digits below the highest one in which the two Morton codes differ are made again.
 *   - A Sobol' point is linear over GF(2) in its index, and the two parts hold disjoint bits: the
 *     pixel part's point is made once (zsob), the sample's from the first byte table alone.
 *   - fastowen works on the bit-reversed point: the pixel part and the byte table (rlut) are kept
 *     reversed; the hash, the final reversal and the conversion run four samples at a time with SSE2. */

/* the pixel's Morton code (pbrt-v4's StartPixelSample without the sample), for the fast path */
void elr_zsobol_start_pixel(elr_sampler *S, uint64_t morton) { S->zmorton = morton; S->zfast = S->zf1 = S->zf2 = 0; }

/* the permuted pixel digits of dimension dim (index bits log2spp and up), as elr__zsobol_index makes
 * them: pixel digit j (bits 2j, 2j + 1 of the Morton code) at index bit log2spp + 2j, its permutation
 * chosen by the Morton code's digits above j */
static uint64_t elr__zsobol_pixel(elr_sampler *S, int dim) {
  int L = S->log2spp, j = S->T->log2res - 1;
  uint64_t m = S->zmorton, dh = (uint64_t)(0x55555555u * (uint32_t)dim), index = 0;
  if (dim < 64 && ((S->zpvalid >> dim) & 1u)) { /* the digits above the highest that differs: as last time */
    uint64_t diff = m ^ S->zpm[dim];
#if defined(__GNUC__)
    j = diff ? (63 - __builtin_clzll(diff)) / 2 : -1;
#else
    while (j >= 0 && !((diff >> (2 * j)) & 3u)) j--;
#endif
    index = j < 0 ? S->zpp[dim] : S->zpp[dim] & ~((((uint64_t)1 << (2 * j + 2)) - 1u) << L);
  }
  for (; j >= 0; j--) {
    unsigned digit = (unsigned)(m >> (2 * j)) & 3u;
    unsigned p = (unsigned)((elr_mix64((m >> (2 * j + 2)) ^ dh) >> 24) % 24u);
    index |= (uint64_t)elr__perm4[p][digit] << (L + 2 * j);
  }
  if (dim < 64) { S->zpm[dim] = m; S->zpp[dim] = index; S->zpvalid |= 1ull << dim; }
  return index;
}

/* zlow and zsob of dimension dim for the current pixel */
static void elr__zsobol_make(elr_sampler *S, int dim) {
  int L = S->log2spp, odd = L & 1, spp = S->spp, i, n = 1, q, c;
  uint64_t m0 = S->zmorton << L, dh = (uint64_t)(0x55555555u * (uint32_t)dim), pix = elr__zsobol_pixel(S, dim);
  uint8_t *low = S->zlow + (size_t)dim * (size_t)spp, tmp[ELR_ZSOBOL_FAST_SPP];
  /* <<Apply random permutations to full base-4 digits>>, the sample's, from the highest: digit i (at
   * bit shift = 2i - odd) of sample s has its permutation chosen by s >> (shift + 2) (with the pixel's
   * bits above); tmp[s >> shift] holds the permuted digits down to i */
  tmp[0] = 0;
  for (i = (L + odd) / 2 - 1; i >= odd; i--) {
    int shift = 2 * i - odd;
    for (q = n - 1; q >= 0; q--) { /* in place, from the top: entry q becomes entries 4q .. 4q + 3 */
      const unsigned char *perm = elr__perm4[(unsigned)((elr_mix64(((m0 >> (shift + 2)) | (uint64_t)q) ^ dh) >> 24) % 24u)];
      uint8_t hi = tmp[q];
      tmp[4 * q] = (uint8_t)(hi | (perm[0] << shift)); tmp[4 * q + 1] = (uint8_t)(hi | (perm[1] << shift));
      tmp[4 * q + 2] = (uint8_t)(hi | (perm[2] << shift)); tmp[4 * q + 3] = (uint8_t)(hi | (perm[3] << shift));
    }
    n *= 4;
  }
  /* <<Handle power-of-2 (but not 4) sample count>>: the lowest bit of sample s flipped by a hash of s >> 1 */
  if (odd)
    for (q = 0; q < n; q++) {
      unsigned flip = (unsigned)(elr_mix64(((m0 >> 1) | (uint64_t)q) ^ dh) & 1u);
      low[2 * q] = (uint8_t)(tmp[q] | flip); low[2 * q + 1] = (uint8_t)(tmp[q] | (flip ^ 1u));
    }
  else memcpy(low, tmp, (size_t)n);
  for (c = 0; c < 2; c++) {
    uint32_t v = elr_sobol_bits(&S->T->sobol, pix, c);
    S->zsob[dim][c] = S->randomize == ELR_RANDOMIZE_FAST_OWEN ? elr_reverse_bits32(v) : v;
  }
  S->zfast |= 1ull << dim;
}

/* component c of the pixel's points of dimension dim, scrambled with seed, into out[3 s] (s < spp):
 * pbrt-v4's SobolSample(index, c, randomizer) */
#if defined(__SSE2__) && !defined(ELR_NO_SIMD)
#include <emmintrin.h>
static __m128i elr__mullo(__m128i a, __m128i b) { /* 32-bit products, four lanes (SSE2 has only pmuludq) */
  __m128i e = _mm_mul_epu32(a, b), o = _mm_mul_epu32(_mm_srli_epi64(a, 32), _mm_srli_epi64(b, 32));
  return _mm_unpacklo_epi32(_mm_shuffle_epi32(e, _MM_SHUFFLE(0, 0, 2, 0)), _mm_shuffle_epi32(o, _MM_SHUFFLE(0, 0, 2, 0)));
}
static __m128i elr__swap(__m128i v, uint32_t mask, int k) { /* swap the k-bit groups picked by mask with their neighbours */
  __m128i m = _mm_set1_epi32((int)mask);
  return _mm_or_si128(_mm_slli_epi32(_mm_and_si128(v, m), k), _mm_and_si128(_mm_srli_epi32(v, k), m));
}
#endif
/* the scrambled points of the pixel for dimension dim: 2D (two = 1; components 0 and 1 with the seeds
 * h and h >> 32, into out[3 s], out[3 s + 1]) or 1D (component 0 with seed h, into out[3 s + 2]), for
 * every sample s: pbrt-v4's SobolSample(index, c, randomizer) */
#if defined(__SSE2__) && !defined(ELR_NO_SIMD)
/* FastOwenScrambler on four reversed points, then the floats of their first 24 digits */
static __m128 elr__fast_owen4(__m128i r, __m128i sd, __m128i sm) {
  r = _mm_xor_si128(r, elr__mullo(r, _mm_set1_epi32(0x3d20adea)));
  r = _mm_add_epi32(r, sd);
  r = elr__mullo(r, sm);
  r = _mm_xor_si128(r, elr__mullo(r, _mm_set1_epi32(0x05526c56)));
  r = _mm_xor_si128(r, elr__mullo(r, _mm_set1_epi32(0x53a22864)));
  /* elr_reverse_bits32(r) >> 8: the reversal of the low 24 bits */
  r = _mm_or_si128(_mm_slli_epi32(r, 16), _mm_srli_epi32(r, 16));
  r = elr__swap(r, 0x00ff00ffu, 8);
  r = elr__swap(r, 0x0f0f0f0fu, 4);
  r = elr__swap(r, 0x33333333u, 2);
  r = elr__swap(r, 0x55555555u, 1);
  return _mm_mul_ps(_mm_cvtepi32_ps(_mm_srli_epi32(r, 8)), _mm_set1_ps(0x1p-24f));
}
#endif
static void elr__zsobol_points(elr_sampler *S, int dim, int two, uint64_t h, float *out) {
  const elr_sobol *T = &S->T->sobol;
  const uint8_t *low = S->zlow + (size_t)dim * (size_t)S->spp;
  int s = 0, spp = S->spp, nc = two ? 2 : 1, c, off = two ? 0 : 2;
  uint32_t seed[2], base[2];
  seed[0] = (uint32_t)h; seed[1] = (uint32_t)(h >> 32);
  base[0] = S->zsob[dim][0]; base[1] = S->zsob[dim][1];
  if (S->randomize != ELR_RANDOMIZE_FAST_OWEN) {
    for (c = 0; c < nc; c++)
      for (s = 0; s < spp; s++) out[3 * s + off + c] = elr_bits_to_float(elr_randomize(base[c] ^ T->lut[c][0][low[s]], S->randomize, seed[c]));
    return;
  }
#if defined(__SSE2__) && !defined(ELR_NO_SIMD)
  {
    const __m128i sd0 = _mm_set1_epi32((int)seed[0]), sm0 = _mm_set1_epi32((int)((seed[0] >> 16) | 1u));
    const __m128i sd1 = _mm_set1_epi32((int)seed[1]), sm1 = _mm_set1_epi32((int)((seed[1] >> 16) | 1u));
    for (; s + 4 <= spp; s += 4) {
      float f[4];
      unsigned l0 = low[s], l1 = low[s + 1], l2 = low[s + 2], l3 = low[s + 3];
      __m128i r = _mm_set_epi32((int)(base[0] ^ T->rlut[0][l3]), (int)(base[0] ^ T->rlut[0][l2]), (int)(base[0] ^ T->rlut[0][l1]),
                                (int)(base[0] ^ T->rlut[0][l0]));
      _mm_storeu_ps(f, elr__fast_owen4(r, sd0, sm0));
      out[3 * s + off] = f[0]; out[3 * s + 3 + off] = f[1]; out[3 * s + 6 + off] = f[2]; out[3 * s + 9 + off] = f[3];
      if (two) {
        r = _mm_set_epi32((int)(base[1] ^ T->rlut[1][l3]), (int)(base[1] ^ T->rlut[1][l2]), (int)(base[1] ^ T->rlut[1][l1]), (int)(base[1] ^ T->rlut[1][l0]));
        _mm_storeu_ps(f, elr__fast_owen4(r, sd1, sm1));
        out[3 * s + 1] = f[0]; out[3 * s + 4] = f[1]; out[3 * s + 7] = f[2]; out[3 * s + 10] = f[3];
      }
    }
  }
#endif
  for (; s < spp; s++)
    for (c = 0; c < nc; c++) {
      uint32_t r = base[c] ^ T->rlut[c][low[s]];
      r ^= r * 0x3d20adeau;
      r += seed[c];
      r *= (seed[c] >> 16) | 1u;
      r ^= r * 0x05526c56u;
      r ^= r * 0x53a22864u;
      out[3 * s + off + c] = elr_bits_to_float(elr_reverse_bits32(r));
    }
}

/* the pixel's 1D (two = 0) or 2D points of dimension dim, made if needed; NULL past the fast path */
const float *elr_zsobol_table(elr_sampler *S, int dim, int two) {
  float *t;
  if (dim < 0 || dim >= 64 || !S->zlow) return NULL;
  t = S->zpt + (size_t)dim * 3u * (size_t)S->spp;
  if (!(((two ? S->zf2 : S->zf1) >> dim) & 1u)) {
    if (!((S->zfast >> dim) & 1u)) elr__zsobol_make(S, dim);
    if (two) {
      uint64_t h = elr_sampler_dim_hash(S, dim + 2);
      elr__zsobol_points(S, dim, 1, h, t);
      S->zf2 |= 1ull << dim;
    } else {
      elr__zsobol_points(S, dim, 0, elr_sampler_dim_hash(S, dim + 1), t);
      S->zf1 |= 1ull << dim;
    }
  }
  return t + 3 * ((size_t)S->hindex & (size_t)(S->spp - 1));
}

