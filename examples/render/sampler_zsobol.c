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
 * Instructions per camera sample on bench_city (16 spp, direct lighting, bench/callgrind_parts.sh):
 * 1225 -> 512 for the sampler, 461 after the wave loop's own changes (examples/render/README.md), -> 234
 * (path, 4 spp: 2123 -> 1411 -> 527; the second step below). */
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
 *     pixel part's point (zsob) is the XOR of its digits' points (the tables' zdig, one per level and
 *     digit value), changed only where a digit changed; the sample's comes from the first byte's table
 *     (q64). Both dimensions travel in one 64-bit word (dimension 0 in the low half).
 *   - fastowen works on the bit-reversed point: the tables are kept reversed for it; its hash, the final
 *     reversal and the conversion run on 8 values at a time with AVX2 (where the CPU has it: chosen at
 *     run time, elr_zsobol_simd), else 4 with SSE2, else one at a time (the plain loop: the definition).
 *   - The samplers of a wave (render_wave.c: neighbouring pixels in turn) share what they keep of their
 *     last pixels (elr_sampler_share), and the digit's permutation is kept too: a pixel whose Morton
 *     code differs from the last one's first in digit J needs hashes for the digits below J only (about
 *     one per table in a wave's row order, against 4.6 with each sampler's own last pixel at 4 spp).
 * Instructions per camera sample on bench_city (bench/callgrind_parts.sh), sampler part: direct lighting
 * 16 spp 461 -> 234, path 4 spp 1411 -> 527 (with the wave's unused BSDF draw skipped: one table in
 * three fewer); per table at 4 spp about 350 (the hashes ~50 each, fastowen with AVX2 ~75, the rest
 * calls and bookkeeping). pbrt-v4 makes log2(res) + log2(spp) / 2 hashes and two scrambles per draw. */

/* the fast path's tables for a render at 2^log2spp samples per pixel: each pixel digit's Sobol' point */
void elr_zsobol_tables_init(elr_sampler_tables *T, int log2spp) {
  int j, v;
  for (j = 0; j < ELR_ZSOBOL_LEVELS; j++)
    for (v = 0; v < 4; v++) {
      /* (bits past the matrices' 52 columns add nothing; the tables are made for every spp up to 2^24,
       * where log2spp + 2j reaches 70: a shift of 64 or more is undefined, and its index bits are past
       * the columns too) */
      int sh = log2spp + 2 * j;
      uint64_t index = sh < 64 ? (uint64_t)v << sh : 0u;
      uint32_t c0 = elr_sobol_bits(&T->sobol, index, 0), c1 = elr_sobol_bits(&T->sobol, index, 1);
      T->zdig[0][j][v] = (uint64_t)c0 | (uint64_t)c1 << 32;
      T->zdig[1][j][v] = (uint64_t)elr_reverse_bits32(c0) | (uint64_t)elr_reverse_bits32(c1) << 32;
    }
}

/* the pixel's Morton code (pbrt-v4's StartPixelSample without the sample), for the fast path */
void elr_zsobol_start_pixel(elr_sampler *S, uint64_t morton) { S->zmorton = morton; S->zfast = S->zf1 = S->zf2 = 0; }

/* the Sobol' point of dimension dim's permuted pixel digits (index bits log2spp and up, as
 * elr__zsobol_index makes them: pixel digit j, bits 2j and 2j + 1 of the Morton code, at index bit
 * log2spp + 2j, its permutation chosen by the Morton code's digits above j); dh = 0x55555555 * dim */
static uint64_t elr__zsobol_pixel(elr_sampler *S, int dim, uint64_t dh) {
  const uint64_t (*dig)[4] = S->zdig;
  struct elr_zsobol_last *c = S->zshare ? S->zshare : &S->zown;
  uint8_t *pd = c->pd[dim];
  int j = S->T->log2res - 1;
  uint64_t m = S->zmorton, P = 0;
  unsigned p, d;
  if ((c->valid >> dim) & 1u) { /* the digits above the highest that differs: as last time */
    uint64_t diff = m ^ c->m[dim];
    if (!diff) return c->P[dim];
#if defined(__GNUC__)
    j = (63 - __builtin_clzll(diff)) / 2;
#else
    while (!((diff >> (2 * j)) & 3u)) j--;
#endif
    P = c->P[dim];
    /* and digit j's permutation too (chosen by the digits above it): only the digit changed */
    p = pd[j] >> 2; d = elr__perm4[p][(m >> (2 * j)) & 3u];
    P ^= dig[j][d ^ (pd[j] & 3u)]; /* (the new digit's point XOR the old one's) */
    pd[j] = (uint8_t)(4 * p + d);
    j--;
  } else memset(pd, 0, (size_t)(j + 1)); /* (no digits yet) */
  for (; j >= 0; j--) {
    p = (unsigned)((elr_mix64((m >> (2 * j + 2)) ^ dh) >> 24) % 24u);
    d = elr__perm4[p][(m >> (2 * j)) & 3u];
    P ^= dig[j][d ^ (pd[j] & 3u)];
    pd[j] = (uint8_t)(4 * p + d);
  }
  c->m[dim] = m; c->P[dim] = P; c->valid |= 1ull << dim;
  return P;
}

/* zlow (the permuted sample digits of each sample) and zsob (the pixel part's point) of dimension dim */
static void elr__zsobol_make(elr_sampler *S, int dim) {
  int L = S->log2spp, odd = L & 1, i, n = 1, q;
  uint64_t m0 = S->zmorton << L, dh = (uint64_t)(0x55555555u * (uint32_t)dim);
  uint8_t *low = S->zlow + (size_t)dim * (size_t)S->spp;
  S->zsob[dim] = elr__zsobol_pixel(S, dim, dh);
  /* <<Apply random permutations to full base-4 digits>>, the sample's, from the highest: digit i (at
   * bit shift = 2i - odd) of sample s has its permutation chosen by s >> (shift + 2) (with the pixel's
   * bits above); low[s >> shift] holds the permuted digits down to i (made in place, from the top: entry
   * q becomes entries 4q .. 4q + 3) */
  if (L == 2) { /* (4 samples: one digit, one permutation) */
    memcpy(low, elr__perm4[(unsigned)((elr_mix64(S->zmorton ^ dh) >> 24) % 24u)], 4);
    S->zfast |= 1ull << dim;
    return;
  }
  low[0] = 0;
  for (i = (L + odd) / 2 - 1; i >= odd; i--) {
    int shift = 2 * i - odd;
    for (q = n - 1; q >= 0; q--) {
      const unsigned char *perm = elr__perm4[(unsigned)((elr_mix64(((m0 >> (shift + 2)) | (uint64_t)q) ^ dh) >> 24) % 24u)];
      uint8_t hi = low[q];
      low[4 * q] = (uint8_t)(hi | (perm[0] << shift)); low[4 * q + 1] = (uint8_t)(hi | (perm[1] << shift));
      low[4 * q + 2] = (uint8_t)(hi | (perm[2] << shift)); low[4 * q + 3] = (uint8_t)(hi | (perm[3] << shift));
    }
    n *= 4;
  }
  /* <<Handle power-of-2 (but not 4) sample count>>: the lowest bit of sample s flipped by a hash of s >> 1 */
  if (odd)
    for (q = n - 1; q >= 0; q--) {
      unsigned flip = (unsigned)(elr_mix64(((m0 >> 1) | (uint64_t)q) ^ dh) & 1u);
      uint8_t hi = low[q];
      low[2 * q] = (uint8_t)(hi | flip); low[2 * q + 1] = (uint8_t)(hi | (flip ^ 1u));
    }
  S->zfast |= 1ull << dim;
}

/* >> fastowen on n bit-reversed values (pbrt-v4's FastOwenScrambler after its ReverseBits32), two to a
 * word (value k in the low half of in[k / 2] for k even, with seed a; the high half for k odd, with seed
 * b), into floats: the first 24 digits of the scrambled value */
#if (defined(__x86_64__) || defined(__i386__)) && defined(__GNUC__) && !defined(ELR_NO_SIMD)
#define ELR_ZSOBOL_AVX2 1
#include <immintrin.h>
/* eight values: lane k scrambled with seed sd[k] (sm[k] = (sd[k] >> 16) | 1), into out[k] */
__attribute__((target("avx2"))) static inline void elr__fast_owen8(__m256i r, __m256i sd, __m256i sm, float *out) {
  /* the bit reversal: the bytes of each 32-bit lane reversed, then each byte's bits by a nibble table */
  const __m256i bswap = _mm256_setr_epi8(3, 2, 1, 0, 7, 6, 5, 4, 11, 10, 9, 8, 15, 14, 13, 12, 3, 2, 1, 0, 7, 6, 5, 4, 11, 10, 9, 8, 15, 14, 13, 12);
  const __m256i rlo = _mm256_setr_epi8(0, 8, 4, 12, 2, 10, 6, 14, 1, 9, 5, 13, 3, 11, 7, 15, 0, 8, 4, 12, 2, 10, 6, 14, 1, 9, 5, 13, 3, 11, 7, 15);
  const __m256i rhi = _mm256_slli_epi16(rlo, 4), nib = _mm256_set1_epi8(15);
  r = _mm256_xor_si256(r, _mm256_mullo_epi32(r, _mm256_set1_epi32(0x3d20adea)));
  r = _mm256_add_epi32(r, sd);
  r = _mm256_mullo_epi32(r, sm);
  r = _mm256_xor_si256(r, _mm256_mullo_epi32(r, _mm256_set1_epi32(0x05526c56)));
  r = _mm256_xor_si256(r, _mm256_mullo_epi32(r, _mm256_set1_epi32(0x53a22864)));
  r = _mm256_shuffle_epi8(r, bswap);
  r = _mm256_or_si256(_mm256_shuffle_epi8(rhi, _mm256_and_si256(r, nib)), _mm256_shuffle_epi8(rlo, _mm256_and_si256(_mm256_srli_epi16(r, 4), nib)));
  _mm256_storeu_ps(out, _mm256_mul_ps(_mm256_cvtepi32_ps(_mm256_srli_epi32(r, 8)), _mm256_set1_ps(0x1p-24f)));
}
/* the points of elr__zsobol_points with fastowen, the sample parts gathered from q: 2D four samples at a
 * time (both components of sample s in lanes 2s, 2s + 1), 1D eight; returns how many samples it made
 * (all, or none when there are fewer than a vector's) */
__attribute__((target("avx2"))) static int elr__points_avx2(const uint64_t *q, uint64_t P, const uint8_t *low, int spp, int two, uint64_t h,
                                                            float *out) {
  int s = 0;
  if (two) { /* seeds h (component 0) and h >> 32 (component 1) */
    const __m256i Pv = _mm256_set1_epi64x((long long)P), sd = _mm256_set1_epi64x((long long)h);
    const __m256i sm = _mm256_set1_epi64x((long long)(((h >> 16) & 0x0000ffff0000ffffULL) | 0x0000000100000001ULL));
    for (; s + 4 <= spp; s += 4) {
      int l;
      memcpy(&l, low + s, 4);
      elr__fast_owen8(_mm256_xor_si256(_mm256_i32gather_epi64((const long long *)(const void *)q, _mm_cvtepu8_epi32(_mm_cvtsi32_si128(l)), 8), Pv),
                      sd, sm, out + 2 * s);
    }
  } else {
    const uint32_t a = (uint32_t)h;
    const __m256i Pv = _mm256_set1_epi32((int)(uint32_t)P), sd = _mm256_set1_epi32((int)a), sm = _mm256_set1_epi32((int)((a >> 16) | 1u));
    for (; s + 8 <= spp; s += 8) { /* (component 0: the low half of q's word) */
      __m256i idx = _mm256_slli_epi32(_mm256_cvtepu8_epi32(_mm_loadl_epi64((const __m128i *)(const void *)(low + s))), 1);
      elr__fast_owen8(_mm256_xor_si256(_mm256_i32gather_epi32((const int *)(const void *)q, idx, 4), Pv), sd, sm, out + s);
    }
  }
  return s;
}
#endif
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
static int elr__fast_owen_sse2(const uint64_t *in, int n, uint32_t a, uint32_t b, float *out) {
  const __m128i sd = _mm_setr_epi32((int)a, (int)b, (int)a, (int)b);
  const __m128i sm = _mm_setr_epi32((int)((a >> 16) | 1u), (int)((b >> 16) | 1u), (int)((a >> 16) | 1u), (int)((b >> 16) | 1u));
  int k;
  for (k = 0; k + 4 <= n; k += 4) {
    __m128i r = _mm_loadu_si128((const __m128i *)(const void *)(in + k / 2));
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
    _mm_storeu_ps(out + k, _mm_mul_ps(_mm_cvtepi32_ps(_mm_srli_epi32(r, 8)), _mm_set1_ps(0x1p-24f)));
  }
  return k;
}
#endif
static void elr__fast_owen_floats(int simd, const uint64_t *in, int n, uint32_t a, uint32_t b, float *out) {
  int k = 0;
  (void)simd;
#if defined(__SSE2__) && !defined(ELR_NO_SIMD)
  if (simd >= 1 && n >= 4) k = elr__fast_owen_sse2(in, n, a, b, out);
#endif
  for (; k < n; k++) { /* the plain loop: elr__fast_owen of lowdiscrepancy.c without its first reversal */
    uint32_t r = (uint32_t)(in[k / 2] >> (32 * (k & 1))), seed = (k & 1) ? b : a;
    r ^= r * 0x3d20adeau;
    r += seed;
    r *= (seed >> 16) | 1u;
    r ^= r * 0x05526c56u;
    r ^= r * 0x53a22864u;
    out[k] = elr_bits_to_float(elr_reverse_bits32(r));
  }
}

/* the widest of the fast path's fastowen loops this CPU runs: 2 AVX2, 1 SSE2, 0 none */
int elr_zsobol_simd(void) {
#if defined(ELR_ZSOBOL_AVX2)
  __builtin_cpu_init();
  if (__builtin_cpu_supports("avx2")) return 2;
#endif
#if defined(__SSE2__) && !defined(ELR_NO_SIMD)
  return 1;
#else
  return 0;
#endif
}

/* the pixel's points of dimension dim from its pixel part P and its samples' digits low, 2D (two = 1:
 * components 0 and 1 scrambled with the seeds h and h >> 32, into out[2 s], out[2 s + 1]) or 1D
 * (component 0 with seed h, into out[s]), for every sample s: pbrt-v4's SobolSample(index, c, randomizer) */
static void elr__zsobol_points(const elr_sampler *S, uint64_t P, const uint8_t *low, int two, uint64_t h, float *out) {
  const uint64_t *q = S->zq;
  uint64_t in[ELR_ZSOBOL_FAST_SPP];
  uint32_t a = (uint32_t)h, b = two ? (uint32_t)(h >> 32) : a;
  int s, spp = S->spp, n = two ? 2 * spp : spp, k;
  if (two) for (s = 0; s < spp; s++) in[s] = P ^ q[low[s]]; /* component 0 in the low half, 1 in the high */
  else if (spp == 1) in[0] = P ^ q[low[0]];
  else for (s = 0; s < spp; s += 2) in[s / 2] = (uint32_t)(P ^ q[low[s]]) | (P ^ q[low[s + 1]]) << 32; /* samples s, s + 1 */
  if (S->randomize == ELR_RANDOMIZE_FAST_OWEN) elr__fast_owen_floats(S->zsimd, in, n, a, b, out);
  else for (k = 0; k < n; k++) out[k] = elr_bits_to_float(elr_randomize((uint32_t)(in[k / 2] >> (32 * (k & 1))), S->randomize, (k & 1) ? b : a));
}

/* the pixel's 1D (two = 0) or 2D points of dimension dim, made if needed; NULL past the fast path */
const float *elr_zsobol_table(elr_sampler *S, int dim, int two) {
  size_t spp = (size_t)S->spp, s = (size_t)S->hindex & (spp - 1);
  const uint8_t *low;
  uint64_t h, bit = 1ull << (dim & 63);
  float *t;
  if ((unsigned)dim >= 64u || !S->zlow) return NULL;
  if (!(S->zfast & bit)) elr__zsobol_make(S, dim);
  low = S->zlow + (size_t)dim * spp;
  if (two) {
    t = S->zpt + (size_t)dim * 2u * spp;
    if (S->zf2 & bit) return t + 2 * s;
    S->zf2 |= bit; h = S->dhash[dim + 2];
  } else {
    t = S->zp1 + (size_t)dim * spp;
    if (S->zf1 & bit) return t + s;
    S->zf1 |= bit; h = S->dhash[dim + 1];
  }
#if defined(ELR_ZSOBOL_AVX2)
  if (S->zsimd >= 2 && S->randomize == ELR_RANDOMIZE_FAST_OWEN && elr__points_avx2(S->zq, S->zsob[dim], low, (int)spp, two, h, t) == (int)spp)
    return two ? t + 2 * s : t + s;
#endif
  elr__zsobol_points(S, S->zsob[dim], low, two, h, t);
  return two ? t + 2 * s : t + s;
}
void elr_zsobol_draw2d(elr_sampler *S, float u[2]) { elr_zsobol_2d(S, S->dim, u); S->dim += 2; }
