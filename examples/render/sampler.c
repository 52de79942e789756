/* sampler.c: the sampler interface and the random sampler.
 *
 * pbrt-v3 core/sampler.cpp: a Sampler starts each pixel (StartPixel) and each of its samples
 * (SetSampleNumber), then hands out the sample's dimensions in the order the integrator asks for them
 * (Get1D, Get2D; GetCameraSample first). Two families, as in pbrt-v3:
 *   - pixel samplers make every dimension for all the pixel's samples at once (PixelSampler):
 *     "stratified" (sampler_stratified.c; pbrt-v3's "02sequence" would be another);
 *   - global samplers compute dimension d of sample i of one sequence over the image
 *     (GlobalSampler: GetIndexForSample, SampleDimension): "halton" (sampler_halton.c; "sobol" would be
 *     another).
 * "random" (samplers/random.cpp) is here: uniform numbers from a stream of its own per pixel sample.
 * Every pixel's numbers depend only on the seed and the pixel, so the image is the same for any thread
 * count and tile order. MakeSampler (api.cpp: which sampler, how many samples) is elr_sampler_choose. */
#include "elr_internal.h"
#include <stdlib.h>
#include <string.h>

/* pbrt-v3's MakeSampler: the scene's sampler, or the options' (the scene description itself is never
 * changed); a stratified sampler takes the nearest grid to the requested count. */
int elr_sampler_choose(elr_sampler_desc *d, const elr_scene *s, const elr_render_options *o, char *err, size_t errlen) {
  d->spp = o->spp > 0 ? o->spp : s->d.spp;
  d->kind = o->sampler != ELR_SAMPLER_DEFAULT ? o->sampler : s->d.sampler;
  d->xs = s->d.xs; d->ys = s->d.ys; d->jitter = s->d.jitter; d->dims = s->d.dims;
  if (d->kind == ELR_SAMPLER_STRATIFIED) {
    if (s->d.sampler != ELR_SAMPLER_STRATIFIED) { d->jitter = 1; d->dims = 4; d->xs = d->ys = 0; } /* pbrt-v3's defaults */
    if (o->spp > 0 || d->xs < 1 || d->ys < 1) { /* the nearest grid to the requested count */
      int q = (int)floor(sqrt((double)d->spp));
      if (q < 1) q = 1;
      d->xs = q; d->ys = (d->spp + q - 1) / q;
    }
    d->spp = d->xs * d->ys;
  }
  if (d->spp <= 0 || d->spp > (1 << 24)) { snprintf(err, errlen, "samples per pixel %d out of range [1, 16777216]", d->spp); return -1; }
  /* the parser's limit, again for a sample count given here: every render thread of the stratified
   * sampler holds spp * (dimensions + 1) 1D and 2D samples (12 bytes) */
  if (d->kind == ELR_SAMPLER_STRATIFIED && (double)d->spp * (double)(d->dims + 1) > (double)(1 << 24)) {
    snprintf(err, errlen, "stratified sampler: %d samples per pixel in %d dimensions need %.0f MiB per thread (at most 16777216 "
             "samples times dimensions + 1)", d->spp, d->dims, (double)d->spp * (d->dims + 1) * 12.0 / 1048576.0);
    return -1;
  }
  return 0;
}

/* One render thread's sampler (H: the render's Halton tables, for the halton sampler). */
int elr_sampler_init(elr_sampler *S, const elr_sampler_desc *d, uint64_t seed, const elr_halton *H) {
  memset(S, 0, sizeof *S);
  S->kind = d->kind; S->spp = d->spp; S->xs = d->xs; S->ys = d->ys; S->jitter = d->jitter; S->dims = d->dims;
  S->seed = seed; S->H = H;
  if (S->kind == ELR_SAMPLER_STRATIFIED) {
    S->s1d = (float *)malloc(sizeof(float) * (size_t)S->spp * (size_t)(S->dims + 1));
    S->s2d = (float *)malloc(sizeof(float) * 2 * (size_t)S->spp * (size_t)(S->dims + 1));
    if (!S->s1d || !S->s2d) { elr_sampler_free(S); return -1; }
  }
  return 0;
}
void elr_sampler_free(elr_sampler *S) { free(S->s1d); free(S->s2d); S->s1d = S->s2d = NULL; }

/* pbrt-v3's StartPixel */
void elr_sampler_start_pixel(elr_sampler *S, int px, int py) {
  S->px = px; S->py = py;
  elr_rng_seed(&S->rng, elr_mix64(S->seed * 0x9e3779b97f4a7c15ULL + 1), elr_mix64(elr_mix64(((uint64_t)(uint32_t)px << 32) ^ (uint64_t)(uint32_t)py) ^ S->seed));
  if (S->kind == ELR_SAMPLER_STRATIFIED) {
    /* strata are made on the first request of each dimension in this pixel (every request of a
     * dimension comes with sample 0 first), so dimensions a render never asks for cost nothing */
    S->made1 = S->made2 = 0;
  } else if (S->kind == ELR_SAMPLER_HALTON) {
    S->hoffset = elr_halton_pixel_offset(S->H, px, py);
  }
}

/* pbrt-v3's SetSampleNumber: sample `sample` of the pixel, from its first dimension */
void elr_sampler_start_sample(elr_sampler *S, int sample) {
  S->sample = sample; S->d1 = S->d2 = 0; S->dim = 0;
  if (S->kind == ELR_SAMPLER_HALTON) S->hindex = S->hoffset + (int64_t)sample * S->H->stride;
  if (S->kind == ELR_SAMPLER_RANDOM) {
    /* every pixel sample its own stream: the same numbers whatever the tile order */
    uint64_t k = elr_mix64(elr_mix64(elr_mix64(S->seed ^ 0x632be59bd9b4e019ULL) ^ (uint64_t)(uint32_t)S->px) ^ (uint64_t)(uint32_t)S->py);
    elr_rng_seed(&S->rng, elr_mix64(S->seed + 0x2545f4914f6cdd1dULL), elr_mix64(k ^ (uint64_t)(uint32_t)sample));
  }
}

float elr_sampler_get1d(elr_sampler *S) {
  if (S->kind == ELR_SAMPLER_STRATIFIED && S->d1 < S->dims) {
    if (S->d1 >= S->made1) { elr_stratified_make(S, 0, S->d1); S->made1 = S->d1 + 1; }
    return S->s1d[(size_t)(S->d1++) * (size_t)S->spp + (size_t)S->sample];
  }
  if (S->kind == ELR_SAMPLER_HALTON) return elr_halton_sample(S->H, S->hindex, S->dim++, &S->rng);
  return elr_rng_float(&S->rng);
}
void elr_sampler_get2d(elr_sampler *S, float u[2]) {
  if (S->kind == ELR_SAMPLER_STRATIFIED && S->d2 < S->dims) {
    const float *b;
    if (S->d2 >= S->made2) { elr_stratified_make(S, 1, S->d2); S->made2 = S->d2 + 1; }
    b = S->s2d + ((size_t)S->d2 * (size_t)S->spp + (size_t)S->sample) * 2;
    S->d2++; u[0] = b[0]; u[1] = b[1]; return;
  }
  if (S->kind == ELR_SAMPLER_HALTON) {
    u[0] = elr_halton_sample(S->H, S->hindex, S->dim, &S->rng);
    u[1] = elr_halton_sample(S->H, S->hindex, S->dim + 1, &S->rng);
    S->dim += 2;
    return;
  }
  u[0] = elr_rng_float(&S->rng); u[1] = elr_rng_float(&S->rng);
}

/* pbrt-v3's GetCameraSample for camera sample k of pixel (x, y): starts the sample and draws its film
 * position (continuous raster coordinates). Drawing it again gives the same position and leaves the
 * sampler in the same state. */
void elr_sampler_camera_sample(elr_sampler *S, int k, int x, int y, float *fx, float *fy) {
  float u[2];
  elr_sampler_start_sample(S, k);
  elr_sampler_get2d(S, u);
  if (S->kind == ELR_SAMPLER_HALTON) S->dim = 5; /* pbrt-v3: time and lens take dimensions 2..4 */
  *fx = u[0] + (float)x; *fy = u[1] + (float)y;
}

/* >> for draws made ahead (render_batched.c) */
/* the sampler's state after a 2D draw, without the draw's work */
void elr_sampler_skip2d(elr_sampler *S) {
  float u[2];
  if (S->kind == ELR_SAMPLER_STRATIFIED && S->d2 < S->dims && S->d2 < S->made2) { S->d2++; return; }
  if (S->kind == ELR_SAMPLER_HALTON && S->dim + 1 < S->H->ndims) { S->dim += 2; return; }
  elr_sampler_get2d(S, u);
}
/* where a camera sample's draws have got to. The random sampler's stream is the sample's own and part
 * of it; the other samplers' stream (for draws past their strata or prime bases) is the pixel's, shared
 * by its samples in order, and is left alone. */
void elr_sampler_save(const elr_sampler *S, elr_sampler_pos *p) {
  p->sample = S->sample; p->d1 = S->d1; p->d2 = S->d2; p->dim = S->dim; p->hindex = S->hindex; p->rng = S->rng;
}
void elr_sampler_restore(elr_sampler *S, const elr_sampler_pos *p) {
  S->sample = p->sample; S->d1 = p->d1; S->d2 = p->d2; S->dim = p->dim; S->hindex = p->hindex;
  if (S->kind == ELR_SAMPLER_RANDOM) S->rng = p->rng;
}
