/* sampler_halton.c: pbrt-v3's HaltonSampler (samplers/halton.cpp) with the radical inverses of
 * core/lowdiscrepancy.cpp it uses.
 *
 * One global Halton sequence over the image: its first two dimensions (bases 2 and 3, scaled by the
 * smallest powers 2^j, 3^k that cover up to 128 x 128 pixels) place sample i of pixel (x, y) inside
 * that pixel, found by the inverse radical inverses and the Chinese remainder theorem
 * (GetIndexForSample). Dimensions from 2 on are radical inverses in the next primes with random digit
 * permutations (ScrambledRadicalInverse with pbrt-v3's ComputeRadicalInversePermutations); past the
 * 256 primes, uniform random numbers from the pixel's stream. sampler.c asks for pixel offsets and
 * dimensions; the tables are made once per render and shared by its threads. */
#include "elr_internal.h"
#include <stdlib.h>
#include <string.h>

static int64_t elr__mod(int64_t a, int64_t b) { int64_t r = a % b; return r < 0 ? r + b : r; }
static void elr__egcd(int64_t a, int64_t b, int64_t *x, int64_t *y) {
  int64_t d, xp, yp;
  if (b == 0) { *x = 1; *y = 0; return; }
  d = a / b;
  elr__egcd(b, a % b, &xp, &yp);
  *x = yp; *y = xp - d * yp;
}
static int64_t elr__mulinv(int64_t a, int64_t n) { int64_t x, y; elr__egcd(a, n, &x, &y); return elr__mod(x, n); }

/* The tables of a render whose sample bounds are w x h pixels: primes, digit permutations (from the
 * seed), the base scales of the first two dimensions. */
int elr_halton_init(elr_halton *H, int w, int h, uint64_t seed) {
  int i, n = 0, total = 0;
  elr_rng r;
  memset(H, 0, sizeof *H);
  for (i = 2; n < ELR_HALTON_DIMS; i++) {
    int k, p = 1;
    for (k = 2; k * k <= i; k++) if (i % k == 0) { p = 0; break; }
    if (p) { H->perm_off[n] = total; total += i; H->primes[n++] = i; }
  }
  H->ndims = n;
  H->perm = (uint16_t *)malloc(sizeof(uint16_t) * (size_t)total);
  if (!H->perm) return -1;
  /* <<ComputeRadicalInversePermutations>> */
  elr_rng_seed(&r, 0x853c49e6748fea9bULL, seed);
  for (i = 0; i < n; i++) {
    int b = H->primes[i], k;
    uint16_t *pp = H->perm + H->perm_off[i];
    for (k = 0; k < b; k++) pp[k] = (uint16_t)k;
    for (k = b - 1; k > 0; k--) { int j = (int)(elr_rng_u32(&r) % (uint32_t)(k + 1)); uint16_t t = pp[k]; pp[k] = pp[j]; pp[j] = t; }
  }
  /* <<Find radical inverse base scales and exponents that cover sampling area>> */
  for (i = 0; i < 2; i++) {
    int base = i == 0 ? 2 : 3, scale = 1, e = 0, res = i == 0 ? w : h;
    if (res > 128) res = 128;
    while (scale < res) { scale *= base; ++e; }
    H->base_scales[i] = scale; H->base_exps[i] = e;
  }
  /* <<Compute stride in samples for visiting each pixel area>> and <<Compute multiplicative inverses for baseScales>> */
  H->stride = (int64_t)H->base_scales[0] * H->base_scales[1];
  H->mult_inv[0] = (int)elr__mulinv(H->base_scales[1], H->base_scales[0]);
  H->mult_inv[1] = (int)elr__mulinv(H->base_scales[0], H->base_scales[1]);
  return 0;
}
void elr_halton_free(elr_halton *H) { free(H->perm); H->perm = NULL; }

/* >> radical inverses (pbrt-v3 core/lowdiscrepancy.h/.cpp) */
static double elr__radical_inverse(int base, uint64_t a) {
  double inv = 1.0 / base, invn = 1.0;
  uint64_t rev = 0;
  while (a) { uint64_t next = a / (uint64_t)base, digit = a - next * (uint64_t)base; rev = rev * (uint64_t)base + digit; invn *= inv; a = next; }
  return (double)rev * invn;
}
static float elr__scrambled_ri(int base, uint64_t a, const uint16_t *perm) {
  double inv = 1.0 / base, invn = 1.0, r;
  uint64_t rev = 0;
  while (a) { uint64_t next = a / (uint64_t)base, digit = a - next * (uint64_t)base; rev = rev * (uint64_t)base + perm[digit]; invn *= inv; a = next; }
  r = invn * ((double)rev + inv * perm[0] / (1.0 - inv));
  return r < ELR_ONE_MINUS_EPS ? (float)r : ELR_ONE_MINUS_EPS;
}
static uint64_t elr__inv_ri(int base, uint64_t inverse, int ndigits) {
  uint64_t index = 0;
  int i;
  for (i = 0; i < ndigits; i++) { uint64_t digit = inverse % (uint64_t)base; inverse /= (uint64_t)base; index = index * (uint64_t)base + digit; }
  return index;
}

/* GetIndexForSample(0) of pixel (px, py): the index of the pixel's first sample in the global sequence
 * (sample k is offset + k * stride). */
int64_t elr_halton_pixel_offset(const elr_halton *H, int px, int py) {
  int64_t off = 0;
  if (H->stride > 1) {
    int64_t pm[2];
    int i;
    pm[0] = elr__mod(px, 128); pm[1] = elr__mod(py, 128);
    for (i = 0; i < 2; i++) {
      uint64_t dimoff = elr__inv_ri(i == 0 ? 2 : 3, (uint64_t)pm[i], H->base_exps[i]);
      off += (int64_t)dimoff * (H->stride / H->base_scales[i]) * H->mult_inv[i];
    }
    off %= H->stride;
  }
  return off;
}

/* SampleDimension(index, dim); dimensions past the primes come from rng. */
float elr_halton_sample(const elr_halton *H, int64_t index, int dim, elr_rng *rng) {
  if (dim == 0) return (float)fmin(elr__radical_inverse(2, (uint64_t)index >> H->base_exps[0]), ELR_ONE_MINUS_EPS);
  if (dim == 1) return (float)fmin(elr__radical_inverse(3, (uint64_t)index / (uint64_t)H->base_scales[1]), ELR_ONE_MINUS_EPS);
  if (dim < H->ndims) return elr__scrambled_ri(H->primes[dim], (uint64_t)index, H->perm + H->perm_off[dim]);
  return elr_rng_float(rng);
}
