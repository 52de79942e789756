/* test_rng.h: the random numbers that the tests and the benchmarks share (bench/bench_common.h includes
 * it). Header-only static inline functions, C99 and C++.
 *
 *   rng r = rng_make(seed);       a PCG32 stream (O'Neill's pcg32, XSH RR, the default increment);
 *   rng g = {0x853c49e6748fea9bULL};  or set the state r.s yourself (the programs that drew from one
 *                                 global stream start at this state);
 *   rng_u32(&r)                   the next 32 bits;
 *   rng_f(&r)                     the next float in [0, 1): the top 24 bits, so exact and never 1;
 *   hash32(i)                     a 32-bit integer hash (Wellons' lowbias32), for random numbers
 *                                 indexed by sample (the same number whatever the order of the draws);
 *   lcg g = {seed}; lcg_f(&g)     the film tests' and bench's linear congruential generator (Numerical
 *                                 Recipes' constants, 32-bit unsigned; lcg_next: the next state), floats
 *                                 in [0, 1) from its top 24 bits;
 *   xorshift32 x = {seed}; xorshift32_f(&x)  the MIP map tests' Marsaglia xorshift (13, 17, 5), likewise;
 *   xorshift64 x = {seed}; xorshift64_f(&x)  the portal's 64-bit xorshift (13, 7, 17), its top 24 bits;
 *   splitmix64 g = {seed}; splitmix64_next(&g), splitmix64_f(&g)  Steele et al.'s SplitMix64 (the
 *                                 distribution tests' and bench_ld_point's stream), floats from its top 24 bits;
 *   sobol0(i), sobol1(i)          the first two dimensions of Sobol's sequence (van der Corput and its
 *                                 partner: a (0,2)-sequence), 32 bits;
 *   owen24(v, seed)               a nested uniform (Owen) scramble of v's top 24 bits, as a float in [0, 1)
 *                                 (bench_ld_point's and bench_product's low-discrepancy points).
 *
 * The streams are fixed: tests that check numbers drawn from a given seed rely on them. */
#ifndef EL_TEST_RNG_H
#define EL_TEST_RNG_H

#include <stdint.h>

typedef struct { uint64_t s; } rng;
static inline uint32_t rng_u32(rng *r) {
  uint64_t old = r->s;
  uint32_t x, rot;
  r->s = old * 6364136223846793005ULL + 1442695040888963407ULL;
  x = (uint32_t)(((old >> 18) ^ old) >> 27);
  rot = (uint32_t)(old >> 59);
  return (x >> rot) | (x << ((32u - rot) & 31u));
}
static inline float rng_f(rng *r) { return (float)(rng_u32(r) >> 8) * (1.0f / 16777216.0f); }
static inline rng rng_make(uint64_t seed) {
  rng r;
  r.s = seed * 2654435761ULL + 12345;
  rng_u32(&r);
  return r;
}

static inline uint32_t hash32(uint32_t x) {
  x ^= x >> 16; x *= 0x7feb352dU; x ^= x >> 15; x *= 0x846ca68bU; x ^= x >> 16;
  return x;
}

typedef struct { unsigned s; } lcg;
static inline unsigned lcg_next(lcg *r) { return r->s = r->s * 1664525u + 1013904223u; }
static inline float lcg_f(lcg *r) { return (float)(lcg_next(r) >> 8) * (1.0f / 16777216.0f); }

typedef struct { unsigned s; } xorshift32;
static inline float xorshift32_f(xorshift32 *r) {
  r->s ^= r->s << 13;
  r->s ^= r->s >> 17;
  r->s ^= r->s << 5;
  return (float)(r->s >> 8) * (1.0f / 16777216.0f);
}

typedef struct { unsigned long long s; } xorshift64;
static inline float xorshift64_f(xorshift64 *r) {
  r->s ^= r->s << 13; r->s ^= r->s >> 7; r->s ^= r->s << 17;
  return (float)(r->s >> 40) * (1.0f / 16777216.0f);
}

typedef struct { uint64_t s; } splitmix64;
static inline uint64_t splitmix64_next(splitmix64 *r) {
  uint64_t z = (r->s += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}
static inline float splitmix64_f(splitmix64 *r) { return (float)(splitmix64_next(r) >> 40) * (1.0f / 16777216.0f); }

static inline uint32_t sobol0(uint32_t i) { uint32_t r = 0, b = 0x80000000u; for (; i; i >>= 1, b >>= 1) if (i & 1) r ^= b; return r; }
static inline uint32_t sobol1(uint32_t i) {
  uint32_t r = 0, v = 0x80000000u;
  for (; i; i >>= 1, v ^= v >> 1) if (i & 1) r ^= v;
  return r;
}
/* bit i of v (31 down to 8) flipped by a hash of the bits above it and the seed */
static inline float owen24(uint32_t v, uint32_t seed) {
  uint32_t out = 0;
  int i;
  for (i = 31; i >= 8; i--) {
    uint32_t prefix = i == 31 ? 0 : (v >> (i + 1)) | (1u << (31 - i));
    uint32_t b = (v >> i) & 1u;
    b ^= hash32(prefix ^ hash32(seed + (uint32_t)i)) & 1u;
    out |= b << i;
  }
  return (float)(out >> 8) * (1.0f / 16777216.0f);
}

#endif
