/* sampler.c: the sampler interface and the random sampler.
 *
 * pbrt-v3 core/sampler.cpp: a Sampler starts each pixel (StartPixel) and each of its samples
 * (SetSampleNumber), then hands out the sample's dimensions in the order the integrator asks for them
 * (Get1D, Get2D; GetCameraSample first). Two families, as in pbrt-v3:
 *   - pixel samplers make every dimension for all the pixel's samples at once (PixelSampler):
 *     "stratified" (sampler_stratified.c), "02sequence" (sampler_zerotwo.c); past their `dimensions`,
 *     uniform numbers from the pixel's stream;
 *   - global samplers compute dimension d of sample i of one sequence over the image
 *     (GlobalSampler: GetIndexForSample, SampleDimension): "halton" (sampler_halton.c), "sobol"
 *     (sampler_sobol.c). pbrt-v4's "zsobol" (sampler_zsobol.c) and "paddedsobol"
 *     (sampler_paddedsobol.c) also compute any (pixel, sample, dimension) directly, from a hash of it.
 * "random" (samplers/random.cpp) is here: uniform numbers from a stream of its own per pixel sample.
 * The camera sample takes dimensions 0 and 1 (the film position); global samplers leave 2..4 to time
 * and lens, as pbrt does, so the integrator's first draw is dimension 5 there.
 * Every pixel's numbers depend only on the seed and the pixel, so the image is the same for any thread
 * count and tile order. MakeSampler (api.cpp: which sampler, how many samples) is elr_sampler_choose. */
#include "elr_internal.h"
#include <stdlib.h>
#include <string.h>

static const char *const elr__sampler_names[ELR_SAMPLER_COUNT] = {"default", "random", "stratified", "halton", "sobol",
                                                                   "02sequence", "zsobol", "paddedsobol"};
const char *elr_sampler_kind_name(int kind) { return kind >= 0 && kind < ELR_SAMPLER_COUNT ? elr__sampler_names[kind] : "unknown"; }
int elr_sampler_kind_from_name(const char *name) {
  int k;
  if (!strcmp(name, "lowdiscrepancy")) return ELR_SAMPLER_ZEROTWO; /* pbrt-v3's other name for it */
  for (k = 1; k < ELR_SAMPLER_COUNT; k++) if (!strcmp(name, elr__sampler_names[k])) return k;
  return -1;
}

static int elr__round_up_pow2(int n) { int p = 1; while (p < n && p < (1 << 30)) p <<= 1; return p; }
static int elr__log2(int n) { int l = 0; while ((1 << (l + 1)) <= n) l++; return l; }

/* pbrt-v3's MakeSampler: the scene's sampler, or the options' (the scene description itself is never
 * changed); a stratified sampler takes the nearest grid to the requested count. */
int elr_sampler_choose(elr_sampler_desc *d, const elr_scene *s, const elr_render_options *o, char *err, size_t errlen) {
  d->spp = o->spp > 0 ? o->spp : s->d.spp;
  d->kind = o->sampler != ELR_SAMPLER_DEFAULT ? o->sampler : s->d.sampler;
  d->xs = s->d.xs; d->ys = s->d.ys; d->jitter = s->d.jitter; d->dims = s->d.dims;
  d->randomize = s->d.randomize; d->has_seed = s->d.has_seed; d->seed = s->d.sseed;
  if (d->kind != s->d.sampler) { /* another sampler than the scene's: pbrt's defaults for it */
    d->jitter = 1; d->dims = 4; d->xs = d->ys = 0; d->has_seed = 0; d->seed = 0;
    d->randomize = d->kind == ELR_SAMPLER_ZSOBOL || d->kind == ELR_SAMPLER_PADDEDSOBOL ? ELR_RANDOMIZE_FAST_OWEN : ELR_RANDOMIZE_NONE;
  }
  if (o->randomization >= ELR_RANDOMIZE_NONE && o->randomization <= ELR_RANDOMIZE_OWEN) d->randomize = o->randomization;
  /* sobol, 02sequence and zsobol need a power of two (pbrt-v3 rounds up; the parser warned for the
   * scene's count; pbrt-v4's zsobol would round a count down) */
  if (d->kind == ELR_SAMPLER_SOBOL || d->kind == ELR_SAMPLER_ZEROTWO || d->kind == ELR_SAMPLER_ZSOBOL) {
    if (d->spp > (1 << 24)) { snprintf(err, errlen, "samples per pixel %d out of range [1, 16777216]", d->spp); return -1; }
    d->spp = elr__round_up_pow2(d->spp);
  }
  if (d->kind == ELR_SAMPLER_STRATIFIED) {
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
  if ((d->kind == ELR_SAMPLER_STRATIFIED || d->kind == ELR_SAMPLER_ZEROTWO) && (double)d->spp * (double)(d->dims + 1) > (double)(1 << 24)) {
    snprintf(err, errlen, "%s sampler: %d samples per pixel in %d dimensions need %.0f MiB per thread (at most 16777216 "
             "samples times dimensions + 1)", elr_sampler_kind_name(d->kind), d->spp, d->dims, (double)d->spp * (d->dims + 1) * 12.0 / 1048576.0);
    return -1;
  }
  return 0;
}

/* The render's tables, for sample bounds b = [b0, b2) x [b1, b3): only the chosen sampler's. */
int elr_sampler_tables_init(elr_sampler_tables *T, const elr_sampler_desc *d, const int b[4], uint64_t seed) {
  int w = b[2] - b[0], h = b[3] - b[1];
  memset(T, 0, sizeof *T);
  T->bx0 = b[0]; T->by0 = b[1];
  T->res = elr__round_up_pow2(w > h ? w : h);
  T->log2res = elr__log2(T->res);
  if (d->kind == ELR_SAMPLER_HALTON) return elr_halton_init(&T->halton, w, h, seed);
  if (d->kind == ELR_SAMPLER_SOBOL) return elr_sobol_init(&T->sobol, ELR_SOBOL_DIMS, T->log2res);
  /* the others use Sobol' dimensions 0 and 1 only */
  if (d->kind == ELR_SAMPLER_ZEROTWO || d->kind == ELR_SAMPLER_PADDEDSOBOL) return elr_sobol_init(&T->sobol, 2, 0);
  if (d->kind == ELR_SAMPLER_ZSOBOL) {
    if (elr_sobol_init(&T->sobol, 2, 0) != 0) return -1;
    elr_zsobol_tables_init(T, elr__log2(d->spp));
  }
  return 0;
}
void elr_sampler_tables_free(elr_sampler_tables *T) { elr_halton_free(&T->halton); elr_sobol_free(&T->sobol); }

int elr_sampler_order_free(const elr_sampler_desc *d) {
  if (d->kind == ELR_SAMPLER_STRATIFIED || d->kind == ELR_SAMPLER_ZEROTWO) return d->dims >= 3;
  return 1;
}

/* One render thread's sampler (T: the render's tables). */
int elr_sampler_init(elr_sampler *S, const elr_sampler_desc *d, uint64_t seed, const elr_sampler_tables *T) {
  memset(S, 0, sizeof *S);
  S->kind = d->kind; S->spp = d->spp; S->xs = d->xs; S->ys = d->ys; S->jitter = d->jitter; S->dims = d->dims;
  S->randomize = d->randomize;
  S->seed = seed; S->T = T;
  S->sseed = d->has_seed ? (uint32_t)d->seed : (uint32_t)(seed ^ (seed >> 32));
  S->log2spp = elr__log2(d->spp);
  { int k; for (k = 0; k < 72; k++) S->dhash[k] = elr_dim_hash(k, S->sseed); }
  if (S->kind == ELR_SAMPLER_ZSOBOL && S->spp <= ELR_ZSOBOL_FAST_SPP && T->log2res <= ELR_ZSOBOL_LEVELS && !getenv("ELR_ZSOBOL_REFERENCE")) {
    S->zlow = (uint8_t *)malloc((size_t)64 * (size_t)S->spp); /* the fast path's tables (sampler_zsobol.c) */
    S->zpt = (float *)malloc(sizeof(float) * 3 * 64 * (size_t)S->spp);
    if (!S->zlow || !S->zpt) { elr_sampler_free(S); return -1; }
    S->zp1 = S->zpt + 2 * 64 * (size_t)S->spp;
    S->zsimd = elr_zsobol_simd();
    S->zq = T->sobol.q64[S->randomize == ELR_RANDOMIZE_FAST_OWEN]; S->zdig = T->zdig[S->randomize == ELR_RANDOMIZE_FAST_OWEN];
  }
  if (S->kind == ELR_SAMPLER_STRATIFIED || S->kind == ELR_SAMPLER_ZEROTWO) {
    S->s1d = (float *)malloc(sizeof(float) * (size_t)S->spp * (size_t)(S->dims + 1));
    S->s2d = (float *)malloc(sizeof(float) * 2 * (size_t)S->spp * (size_t)(S->dims + 1));
    if (!S->s1d || !S->s2d) { elr_sampler_free(S); return -1; }
    if (S->kind == ELR_SAMPLER_ZEROTWO) {
      S->bits = (uint32_t *)malloc(sizeof(uint32_t) * 2 * (size_t)S->spp);
      if (!S->bits) { elr_sampler_free(S); return -1; }
    }
  }
  return 0;
}
void elr_sampler_free(elr_sampler *S) {
  free(S->s1d); free(S->s2d); free(S->bits); free(S->zlow); free(S->zpt);
  S->s1d = S->s2d = NULL; S->bits = NULL; S->zlow = NULL; S->zpt = S->zp1 = NULL;
}

/* a Morton code of (x, y): x in the even bits, y in the odd */
static uint64_t elr__spread2(uint32_t x) {
  uint64_t v = x;
  v = (v | (v << 16)) & 0x0000ffff0000ffffULL;
  v = (v | (v << 8)) & 0x00ff00ff00ff00ffULL;
  v = (v | (v << 4)) & 0x0f0f0f0f0f0f0f0fULL;
  v = (v | (v << 2)) & 0x3333333333333333ULL;
  return (v | (v << 1)) & 0x5555555555555555ULL;
}

/* pbrt-v3's StartPixel */
void elr_sampler_start_pixel(elr_sampler *S, int px, int py) {
  S->px = px; S->py = py;
  if (S->kind != ELR_SAMPLER_ZSOBOL) /* (zsobol draws nothing from the pixel's stream) */
    elr_rng_seed(&S->rng, elr_mix64(S->seed * 0x9e3779b97f4a7c15ULL + 1), elr_mix64(elr_mix64(((uint64_t)(uint32_t)px << 32) ^ (uint64_t)(uint32_t)py) ^ S->seed));
  if (S->kind == ELR_SAMPLER_STRATIFIED || S->kind == ELR_SAMPLER_ZEROTWO) {
    /* strata (or (0,2)-sequence points) are made on the first request of each dimension in this pixel (every request of a
     * dimension comes with sample 0 first), so dimensions a render never asks for cost nothing */
    S->made1 = S->made2 = 0;
  } else if (S->kind == ELR_SAMPLER_HALTON) {
    S->hoffset = elr_halton_pixel_offset(&S->T->halton, px, py);
  }
  S->zvalid = 0; /* zsobol's permuted pixel digits belong to the last pixel */
  if (S->kind == ELR_SAMPLER_ZSOBOL)
    elr_zsobol_start_pixel(S, (elr__spread2((uint32_t)(py - S->T->by0)) << 1) | elr__spread2((uint32_t)(px - S->T->bx0)));
}

/* pbrt-v4's StartPixelSample: the Morton index of the pixel, then the sample */
static int64_t elr__zsobol_hindex(const elr_sampler *S, int sample) { return (int64_t)((S->zmorton << S->log2spp) | (uint64_t)(uint32_t)sample); }

/* pbrt-v3's SetSampleNumber: sample `sample` of the pixel, from its first dimension */
void elr_sampler_start_sample(elr_sampler *S, int sample) {
  S->sample = sample; S->d1 = S->d2 = 0; S->dim = 0;
  if (S->kind == ELR_SAMPLER_HALTON) S->hindex = S->hoffset + (int64_t)sample * S->T->halton.stride;
  /* <<GetIndexForSample>>: the sample's index in the image-wide Sobol' sequence */
  if (S->kind == ELR_SAMPLER_SOBOL) S->hindex = (int64_t)elr_sobol_interval_to_index(&S->T->sobol, (uint64_t)sample, S->px - S->T->bx0, S->py - S->T->by0);
  if (S->kind == ELR_SAMPLER_ZSOBOL) S->hindex = elr__zsobol_hindex(S, sample);
  if (S->kind == ELR_SAMPLER_RANDOM) {
    /* every pixel sample its own stream: the same numbers whatever the tile order */
    uint64_t k = elr_mix64(elr_mix64(elr_mix64(S->seed ^ 0x632be59bd9b4e019ULL) ^ (uint64_t)(uint32_t)S->px) ^ (uint64_t)(uint32_t)S->py);
    elr_rng_seed(&S->rng, elr_mix64(S->seed + 0x2545f4914f6cdd1dULL), elr_mix64(k ^ (uint64_t)(uint32_t)sample));
  }
}

/* a pixel sampler's dimension made for the whole pixel on its first request */
static void elr__make(elr_sampler *S, int two, int d) {
  if (S->kind == ELR_SAMPLER_ZEROTWO) elr_zerotwo_make(S, two, d); else elr_stratified_make(S, two, d);
}

float elr_sampler_get1d(elr_sampler *S) {
  float v;
  switch (S->kind) {
  case ELR_SAMPLER_STRATIFIED: case ELR_SAMPLER_ZEROTWO:
    if (S->d1 >= S->dims) break;
    if (S->d1 >= S->made1) { elr__make(S, 0, S->d1); S->made1 = S->d1 + 1; }
    return S->s1d[(size_t)(S->d1++) * (size_t)S->spp + (size_t)S->sample];
  case ELR_SAMPLER_HALTON: return elr_halton_sample(&S->T->halton, S->hindex, S->dim++, &S->rng);
  case ELR_SAMPLER_SOBOL: return elr_sobol_sampler_1d(S, S->dim++);
  case ELR_SAMPLER_ZSOBOL: v = elr_zsobol_1d(S, S->dim); S->dim++; return v;
  case ELR_SAMPLER_PADDEDSOBOL: v = elr_paddedsobol_1d(S, S->dim); S->dim++; return v;
  default: break;
  }
  return elr_rng_float(&S->rng);
}
static ELR_NOINLINE void elr__get2d(elr_sampler *S, float u[2]) {
  switch (S->kind) {
  case ELR_SAMPLER_STRATIFIED: case ELR_SAMPLER_ZEROTWO: {
    const float *b;
    if (S->d2 >= S->dims) break;
    if (S->d2 >= S->made2) { elr__make(S, 1, S->d2); S->made2 = S->d2 + 1; }
    b = S->s2d + ((size_t)S->d2 * (size_t)S->spp + (size_t)S->sample) * 2;
    S->d2++; u[0] = b[0]; u[1] = b[1];
    return;
  }
  case ELR_SAMPLER_HALTON:
    u[0] = elr_halton_sample(&S->T->halton, S->hindex, S->dim, &S->rng);
    u[1] = elr_halton_sample(&S->T->halton, S->hindex, S->dim + 1, &S->rng);
    S->dim += 2;
    return;
  case ELR_SAMPLER_SOBOL:
    u[0] = elr_sobol_sampler_1d(S, S->dim); u[1] = elr_sobol_sampler_1d(S, S->dim + 1);
    S->dim += 2;
    return;
  case ELR_SAMPLER_ZSOBOL: elr_zsobol_2d(S, S->dim, u); S->dim += 2; return;
  case ELR_SAMPLER_PADDEDSOBOL: elr_paddedsobol_2d(S, S->dim, u); S->dim += 2; return;
  default: break;
  }
  u[0] = elr_rng_float(&S->rng); u[1] = elr_rng_float(&S->rng);
}
void elr_sampler_get2d(elr_sampler *S, float u[2]) {
  const float *t; /* zsobol's points of the pixel made: a load (the common case, ahead of the switch) */
  if (S->kind == ELR_SAMPLER_ZSOBOL) {
    if ((t = elr_zsobol_made2(S, S->dim)) != NULL) { u[0] = t[0]; u[1] = t[1]; S->dim += 2; return; }
    elr_zsobol_draw2d(S, u);
    return;
  }
  elr__get2d(S, u);
}

/* pbrt-v3's GetCameraSample for camera sample k of pixel (x, y): starts the sample and draws its film
 * position (continuous raster coordinates). Drawing it again gives the same position and leaves the
 * sampler in the same state. */
static ELR_NOINLINE void elr__camera_sample(elr_sampler *S, int k, int x, int y, float *fx, float *fy) {
  float u[2];
  elr_sampler_start_sample(S, k);
  elr_sampler_get2d(S, u);
  /* global samplers: time and lens take dimensions 2..4 (pbrt-v3's GetCameraSample; pbrt-v4's too) */
  if (S->kind == ELR_SAMPLER_HALTON || S->kind == ELR_SAMPLER_SOBOL || S->kind == ELR_SAMPLER_ZSOBOL || S->kind == ELR_SAMPLER_PADDEDSOBOL) S->dim = 5;
  *fx = u[0] + (float)x; *fy = u[1] + (float)y;
}
void elr_sampler_camera_sample(elr_sampler *S, int k, int x, int y, float *fx, float *fy) {
  const float *t;
  if (S->kind == ELR_SAMPLER_ZSOBOL && S->zlow) { /* zsobol's point made: the steps above without the other samplers' tests */
    S->sample = k; S->d1 = S->d2 = 0;
    S->hindex = elr__zsobol_hindex(S, k);
    if ((t = elr_zsobol_made2(S, 0)) != NULL) { S->dim = 5; *fx = t[0] + (float)x; *fy = t[1] + (float)y; return; }
  }
  elr__camera_sample(S, k, x, y, fx, fy);
}

void elr_sampler_share(elr_sampler *S, elr_sampler *with) {
  if (S != with && S->kind == ELR_SAMPLER_ZSOBOL && with->kind == ELR_SAMPLER_ZSOBOL && S->spp == with->spp && S->randomize == with->randomize)
    S->zshare = with->zshare ? with->zshare : &with->zown;
}

/* >> for draws made ahead (render_wave.c) */
/* the sampler's state after a 2D draw, without the draw's work */
void elr_sampler_skip2d(elr_sampler *S) {
  float u[2];
  /* sobol, zsobol, paddedsobol: every (pixel, sample, dimension) computed on its own (past the Sobol'
   * table, a hash) */
  if (S->kind == ELR_SAMPLER_ZSOBOL || S->kind == ELR_SAMPLER_SOBOL || S->kind == ELR_SAMPLER_PADDEDSOBOL) { S->dim += 2; return; }
  if ((S->kind == ELR_SAMPLER_STRATIFIED || S->kind == ELR_SAMPLER_ZEROTWO) && S->d2 < S->dims && S->d2 < S->made2) { S->d2++; return; }
  if (S->kind == ELR_SAMPLER_HALTON && S->dim + 1 < S->T->halton.ndims) { S->dim += 2; return; }
  elr_sampler_get2d(S, u);
}
/* where a camera sample's draws have got to. The random sampler's stream is the sample's own and part
 * of it; the stream of stratified, 02sequence and halton (for draws past their dimensions or prime
 * bases) is the pixel's, shared by its samples in order, and is left alone. */
void elr_sampler_save(const elr_sampler *S, elr_sampler_pos *p) {
  p->sample = S->sample; p->d1 = S->d1; p->d2 = S->d2; p->dim = S->dim; p->hindex = S->hindex; p->rng = S->rng;
}
void elr_sampler_restore(elr_sampler *S, const elr_sampler_pos *p) {
  S->sample = p->sample; S->d1 = p->d1; S->d2 = p->d2; S->dim = p->dim; S->hindex = p->hindex;
  if (S->kind == ELR_SAMPLER_RANDOM) S->rng = p->rng;
}
