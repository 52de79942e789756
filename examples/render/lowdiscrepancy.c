/* lowdiscrepancy.c: what the Sobol'-family samplers share (pbrt-v3 core/lowdiscrepancy.h and
 * core/sobolmatrices.cpp; pbrt-v4 util/lowdiscrepancy.h, util/math.h for the permutations).
 *
 *   elr_sobol_init / _free            the Sobol' generator matrices, made at start-up from Joe and Kuo's
 *                                     direction numbers (sobol_directions.h), and the tables that find
 *                                     the index of a pixel's samples (SobolIntervalToIndex)
 *   elr_sobol_bits                    dimension d of point `index`: a sum over GF(2) of matrix columns
 *   elr_sobol_interval_to_index       the index of a pixel's sample `frame` in the image-wide sequence
 *   elr_randomize                     pbrt-v4's randomizations of a 32-bit sample: none, random digit
 *                                     permutation (XOR), Owen scrambling, the fast hash-based Owen scramble
 *   elr_permutation_element           element i of a pseudo-random permutation of n (Kensler 2013)
 *   elr_gray_code_sample              pbrt-v3's GrayCodeSample: n points of one generator matrix
 *
 * A generator matrix C of dimension d is 52 columns of 32 bits; column j is what bit j of the index
 * adds (XOR) to the sample's binary fraction, its most significant bit being the first digit. The
 * sample of index a is sum over the set bits j of a of C[j], times 2^-32. */
#include "elr_internal.h"
#include "sobol_directions.h"
#include <stdlib.h>
#include <string.h>

/* >> the generator matrices */
/* Dimension d's 52 columns (pbrt's SobolMatrixSize). Dimension 0 is the van der Corput sequence (the
 * identity: index bit j is digit j + 1); dimension d >= 1 takes row d - 1 of Joe and Kuo's table, with
 * degree s, coefficients a and initial numbers m_1..m_s: column j < s is m_{j+1} placed so that its
 * top bit is digit j + 1, and later columns follow the recurrence of the primitive polynomial,
 *   V_j = V_{j-s} ^ (V_{j-s} >> s) ^ sum_{k=1}^{s-1} a_k V_{j-k}
 * in 32-bit arithmetic (as in Joe and Kuo's sobol.cc; columns past 32 continue it, as pbrt's table). */
static void elr__sobol_matrix(int d, uint32_t *V) {
  int j;
  if (d == 0) {
    for (j = 0; j < ELR_SOBOL_COLUMNS; j++) V[j] = j < 32 ? 1u << (31 - j) : 0u;
    return;
  }
  {
    const unsigned short *row = elr__sobol_directions[d - 1];
    int s = row[0], k;
    unsigned a = row[1];
    for (j = 0; j < s; j++) V[j] = (uint32_t)row[2 + j] << (31 - j);
    for (j = s; j < ELR_SOBOL_COLUMNS; j++) {
      uint32_t v = V[j - s] ^ (V[j - s] >> s);
      for (k = 1; k < s; k++)
        if ((a >> (s - 1 - k)) & 1u) v ^= V[j - k];
      V[j] = v;
    }
  }
}

/* The top m digits of dimensions 0 and 1 of index bit j's column, packed as (x << m) | y: which pixel
 * of a 2^m x 2^m grid that bit moves the point by. */
static uint64_t elr__pixel_bits(const uint32_t *C0, const uint32_t *C1, int j, int m) {
  uint32_t x = C0[j] >> (32 - m), y = C1[j] >> (32 - m);
  return ((uint64_t)x << m) | y;
}

/* SobolIntervalToIndex's tables for a 2^m x 2^m image, by Gaussian elimination over GF(2). An index is
 * i = (frame << 2m) | l with l < 2^(2m). Its pixel, the top m digits of dimensions 0 and 1, is the
 * linear map A l ^ D frame, where A (2m x 2m) holds the pixel bits of index bits 0..2m-1 and D those of
 * the higher bits. The first 2^(2m) Sobol' points put one point in each pixel (they are a (0, 2m,
 * 2)-net), so A is invertible: l = A^-1 (pixel ^ D frame). inv[k] is A^-1's column k, delta[c] is D's
 * column c (the pixel bits of index bit 2m + c). */
static int elr__interval_tables(elr_sobol *T) {
  int m = T->log2res, n = 2 * m, r, c;
  uint64_t rows[64], inv[64];
  if (m == 0) return 0;
  /* solve A X = I: rows[r] holds row r of A (bit j: index bit j's effect on pixel bit r), inv[r] row r
   * of the identity; row-reduce A to the identity */
  for (r = 0; r < n; r++) {
    rows[r] = 0;
    for (c = 0; c < n; c++)
      if ((elr__pixel_bits(T->C, T->C + ELR_SOBOL_COLUMNS, c, m) >> r) & 1u) rows[r] |= 1ull << c;
    inv[r] = 1ull << r;
  }
  for (c = 0; c < n; c++) {
    int p = -1;
    for (r = c; r < n; r++) if ((rows[r] >> c) & 1u) { p = r; break; }
    if (p < 0) return -1; /* not a net: cannot happen for Sobol' dimensions 0 and 1 */
    if (p != c) { uint64_t t = rows[p]; rows[p] = rows[c]; rows[c] = t; t = inv[p]; inv[p] = inv[c]; inv[c] = t; }
    for (r = 0; r < n; r++)
      if (r != c && ((rows[r] >> c) & 1u)) { rows[r] ^= rows[c]; inv[r] ^= inv[c]; }
  }
  /* inv[r] is row r of A^-1: bit k says pixel bit k contributes to index bit r; store by column */
  for (c = 0; c < n; c++) {
    T->inv[c] = 0;
    for (r = 0; r < n; r++) if ((inv[r] >> c) & 1u) T->inv[c] |= 1ull << r;
  }
  for (c = 0; c + n < ELR_SOBOL_COLUMNS; c++) T->delta[c] = elr__pixel_bits(T->C, T->C + ELR_SOBOL_COLUMNS, n + c, m);
  return 0;
}

/* Matrices for dimensions 0..ndims-1 and, for log2res = m >= 1, the index tables of a 2^m x 2^m image. */
int elr_sobol_init(elr_sobol *T, int ndims, int log2res) {
  int d;
  memset(T, 0, sizeof *T);
  if (ndims < 2) ndims = 2;
  if (ndims > ELR_SOBOL_DIMS) ndims = ELR_SOBOL_DIMS;
  if (log2res < 0 || log2res > 20) return -1;
  T->C = (uint32_t *)malloc(sizeof(uint32_t) * ELR_SOBOL_COLUMNS * (size_t)ndims);
  if (!T->C) return -1;
  T->ndims = ndims; T->log2res = log2res;
  for (d = 0; d < ndims; d++) elr__sobol_matrix(d, T->C + (size_t)d * ELR_SOBOL_COLUMNS);
  for (d = 0; d < 2; d++) { /* byte tables of dimensions 0 and 1 (the last byte holds columns 48..51) */
    const uint32_t *c = T->C + (size_t)d * ELR_SOBOL_COLUMNS;
    int byte, v, j;
    for (byte = 0; byte < 7; byte++)
      for (v = 0; v < 256; v++) {
        uint32_t x = 0;
        for (j = 0; j < 8; j++) if (((v >> j) & 1) && byte * 8 + j < ELR_SOBOL_COLUMNS) x ^= c[byte * 8 + j];
        T->lut[d][byte][v] = x;
      }
  }
  { /* dimensions 0 and 1 of the first byte in one word, as they are and each half reversed */
    int v;
    for (v = 0; v < 256; v++) {
      T->q64[0][v] = (uint64_t)T->lut[0][0][v] | (uint64_t)T->lut[1][0][v] << 32;
      T->q64[1][v] = (uint64_t)elr_reverse_bits32(T->lut[0][0][v]) | (uint64_t)elr_reverse_bits32(T->lut[1][0][v]) << 32;
    }
  }
  { int v; for (v = 0; v < 256; v++) T->rev8[v] = (uint8_t)(elr_reverse_bits32((uint32_t)v) >> 24); }
  if (elr__interval_tables(T) != 0) { elr_sobol_free(T); return -1; }
  return 0;
}
void elr_sobol_free(elr_sobol *T) { free(T->C); T->C = NULL; T->ndims = 0; }

/* pbrt-v3's SobolIntervalToIndex: the index of sample `frame` of pixel (x, y) (0 <= x, y < 2^m, relative
 * to the image's corner). pbrt-v3 returns 0 for m = 0 (a one-pixel image: every sample the same point);
 * this returns frame, as pbrt-v4 does. */
uint64_t elr_sobol_interval_to_index(const elr_sobol *T, uint64_t frame, int x, int y) {
  int m = T->log2res, c;
  uint64_t b, f, l = 0;
  if (m == 0) return frame;
  b = ((uint64_t)(uint32_t)x << m) | (uint32_t)y;
  for (f = frame, c = 0; f && c + 2 * m < ELR_SOBOL_COLUMNS; f >>= 1, c++)
    if (f & 1u) b ^= T->delta[c];
  for (c = 0; b; b >>= 1, c++)
    if (b & 1u) l ^= T->inv[c];
  return (frame << (2 * m)) | l;
}

/* >> randomizations (pbrt-v4's RandomizeStrategy) */
/* Owen's nested uniform scramble (pbrt-v4's OwenScrambler): digit k of the binary fraction (k = 0 the
 * first) is flipped or not by a coin that depends on the seed, k and the k digits above it, so that
 * points which share their first k digits are moved alike and the point set keeps its elementary
 * intervals. One hash per digit: 32 per sample. */
static uint32_t elr__owen(uint32_t v, uint32_t seed) {
  uint32_t out = v;
  int k;
  for (k = 0; k < 32; k++) {
    uint64_t prefix = k ? (uint64_t)(v >> (32 - k)) : 0u;
    if (elr_mix64((((uint64_t)seed << 32) | prefix) + (uint64_t)(k + 1) * 0x9e3779b97f4a7c15ULL) & 1u) out ^= 1u << (31 - k);
  }
  return out;
}
/* pbrt-v4's FastOwenScrambler: the Laine-Karras hash, with N. Vegdahl's constants ("Building a better
 * LK hash", 2021), on the bit-reversed value. In the reversed value the first digit is the lowest bit;
 * each step (XOR with a multiple by an even number, adding the seed, multiplying by an odd number)
 * changes a bit only as a function of the bits below it, that is of the digits above it: a nested
 * scramble, though not with independent coins for every prefix as Owen's. */
static uint32_t elr__fast_owen(uint32_t v, uint32_t seed) {
  v = elr_reverse_bits32(v);
  v ^= v * 0x3d20adeau;
  v += seed;
  v *= (seed >> 16) | 1u;
  v ^= v * 0x05526c56u;
  v ^= v * 0x53a22864u;
  return elr_reverse_bits32(v);
}
uint32_t elr_randomize(uint32_t v, int strategy, uint32_t seed) {
  switch (strategy) {
  case ELR_RANDOMIZE_PERMUTE_DIGITS: return v ^ seed; /* a random permutation of each base-2 digit */
  case ELR_RANDOMIZE_FAST_OWEN: return elr__fast_owen(v, seed);
  case ELR_RANDOMIZE_OWEN: return elr__owen(v, seed);
  default: return v;
  }
}

/* Kensler's permute (A. Kensler, "Correlated Multi-Jittered Sampling", Pixar technical memo 13-01,
 * 2013; pbrt-v4's PermutationElement): element i of a permutation of 0..n-1 chosen by p, without
 * storing it. A hash that is a bijection on the next power of two above n; values past n are hashed
 * again (cycle walking). */
uint32_t elr_permutation_element(uint32_t i, uint32_t n, uint32_t p) {
  uint32_t w = n - 1;
  if (n <= 1) return 0;
  w |= w >> 1; w |= w >> 2; w |= w >> 4; w |= w >> 8; w |= w >> 16;
  do {
    i ^= p; i *= 0xe170893du;
    i ^= p >> 16;
    i ^= (i & w) >> 4;
    i ^= p >> 8; i *= 0x0929eb3fu;
    i ^= p >> 23;
    i ^= (i & w) >> 1; i *= 1u | p >> 27;
    i *= 0x6935fa69u;
    i ^= (i & w) >> 11; i *= 0x74dcb303u;
    i ^= (i & w) >> 2; i *= 0x9e501cc3u;
    i ^= (i & w) >> 2; i *= 0xc860a3dfu;
    i &= w;
    i ^= i >> 5;
  } while (i >= n);
  return (i + p) % n;
}

/* pbrt-v3's GrayCodeSample: the n points v_i = C a_i ^ scramble, a_i running through the Gray code
 * (a_{i+1} differs from a_i in bit ctz(i + 1), so each point is one XOR from the last); they are the
 * first n points of the sequence in another order (all of them when n is a power of two). Returns
 * them as 32-bit fractions. */
void elr_gray_code_sample(const uint32_t *C, uint32_t n, uint32_t scramble, uint32_t *out) {
  uint32_t v = scramble, i;
  for (i = 0; i < n; i++) {
    uint32_t t = i + 1;
    int j = 0;
    out[i] = v;
    while (!(t & 1u) && j < 31) { t >>= 1; j++; }
    v ^= C[j];
  }
}
