/* render.c: a render (pbrt-v3's SamplerIntegrator::Render, core/integrator.cpp, with the choices of
 * core/api.cpp's RenderOptions): what the scene calls for, then tiles of 16 x 16 pixels on threads.
 *
 * elr_render decides once per render what to build and simulate: the sampler (sampler.c), the camera
 * (camera.c), the film (film.c); nothing at all when nothing emits (a black image, no ray traced);
 * whether any light is sampled (not when no surface has a non-specular lobe); the environment's
 * sampling distribution only when some surface samples it; an area light's area CDF only when it is
 * sampled; the light distribution (lightdistrib.c) only when there is a choice to make. Threads take
 * tiles in turn; each tile has its own film tile and the tiles are merged in tile order, whatever order
 * they finish in, so the image is the same for any thread count. The per-tile loop (elr_ctx.loop), as
 * pbrt-v4 keeps a CPU and a wavefront integrator: one sample at a time (the reference, below, with
 * integrator_direct.c and integrator_path.c) or waves of camera samples (render_wave.c, the fast one:
 * the default where the environment is the only light that emits). For directlighting, splitting (elr__split_choose) may give each camera sample several light
 * and BSDF sample pairs, chosen by a pilot from measured variance and cost. */
#define _POSIX_C_SOURCE 200809L
#include "elr_internal.h"
#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

/* >> tiles and threads */
typedef struct elr_job {
  elr_ctx *C;
  el_film *film;
  const elr_render_options *o;
  int bx0, by0, bx1, by1, tile, ntx, nty, ntiles;
  int stride;               /* render tiles 0, stride, 2 stride, ... (the splitting pilot); 1: all */
  uint64_t seed;            /* the samplers' seed */
  int quiet;                /* no progress bar */
  pthread_mutex_t mu;
  int next_tile, next_merge, done;
  el_film_tile **ready; /* finished tiles waiting for their turn to merge */
  elr_tstats total;
  double t0, last_print, cpu0;
  int failed;
  const elr_sampler_tables *T; /* the sampler's tables, shared by the threads */
} elr_job;

static void elr__progress(elr_job *J, int final) {
  double now = elr_now(), el = now - J->t0, frac = (double)J->done / (double)J->ntiles, rem;
  int i, w = 40, fill = (int)(frac * w);
  char bar[64];
  if (J->quiet) return;
  if (!final && now - J->last_print < 0.1) return;
  J->last_print = now;
  for (i = 0; i < w; i++) bar[i] = i < fill ? '=' : (i == fill ? '>' : ' ');
  bar[w] = 0;
  rem = frac > 0 ? el / frac - el : 0.0;
  fprintf(stderr, "\r[%s] %3d%%  %.1fs elapsed, %.1fs remaining   ", bar, (int)(frac * 100.0 + 0.5), el, final ? 0.0 : rem);
  if (final) fprintf(stderr, "\n");
  fflush(stderr);
}

/* adds a finished tile to the film and frees it */
static void elr__merge(el_film *film, el_film_tile *t) {
  el_film_merge_tile(film, t); /* fails only for a splat buffer, and nothing splats */
  el_film_tile_free(t);
  free(t);
}

static void *elr__worker(void *arg) {
  elr_job *J = (elr_job *)arg;
  elr_ctx *C = J->C;
  elr_sampler S;
  elr_tstats ts;
  elr_wave *W = NULL;
  memset(&ts, 0, sizeof ts);
  if (elr_sampler_init(&S, &C->sampler, J->seed, J->T) != 0 ||
      (C->loop == ELR_LOOP_WAVE && !(W = elr_wave_new(C, J->T, J->seed, J->tile)))) {
    elr_sampler_free(&S);
    pthread_mutex_lock(&J->mu); J->failed = 1; pthread_mutex_unlock(&J->mu);
    return NULL;
  }
  for (;;) {
    int t, tx, ty, x0, y0, x1, y1, x, y, k;
    el_film_tile *tile;
    pthread_mutex_lock(&J->mu);
    t = J->failed ? J->ntiles : J->next_tile++;
    pthread_mutex_unlock(&J->mu);
    if (t >= J->ntiles) break;
    if (J->stride > 1 && t % J->stride != 0) { /* a tile the pilot leaves out: an empty tile in its place */
      pthread_mutex_lock(&J->mu); J->ready[t] = NULL; J->done++; pthread_mutex_unlock(&J->mu);
      continue;
    }
    tx = t % J->ntx; ty = t / J->ntx;
    x0 = J->bx0 + tx * J->tile; y0 = J->by0 + ty * J->tile;
    x1 = x0 + J->tile < J->bx1 ? x0 + J->tile : J->bx1;
    y1 = y0 + J->tile < J->by1 ? y0 + J->tile : J->by1;
    /* <<Compute sample bounds for tile>>, <<Get FilmTile for tile>> */
    tile = (el_film_tile *)calloc(1, sizeof *tile);
    if (!tile || el_film_tile_init(J->film, tile, x0, y0, x1, y1) != EL_SUCCESS) {
      free(tile);
      pthread_mutex_lock(&J->mu); J->failed = 1; pthread_mutex_unlock(&J->mu);
      break;
    }
    /* <<Loop over pixels in tile to render them>> */
    if (W) elr_wave_render_tile(C, W, x0, y0, x1, y1, tile, &ts); /* render_wave.c */
    else for (y = y0; y < y1; y++)
      for (x = x0; x < x1; x++) {
        elr_sampler_start_pixel(&S, x, y);
        if (C->s->env_sunny && C->s->env_sun_diffuse == ELR_ENVSD_TWO_PIXEL) ts.env_two_pixel = elr_two_pixel(C, x, y, &ts);
        /* <<Loop over pixel samples>> */
        for (k = 0; k < C->spp; k++) {
          float fx, fy, rgb[3];
          elr_ray r;
          elr_path_state p;
          elr_v3 L;
          /* <<Initialize CameraSample for current sample>>, <<Generate camera ray for current sample>> */
          elr_sampler_camera_sample(&S, k, x, y, &fx, &fy);
          elr_camera_ray(&C->cam, fx, fy, &r);
          ts.camera++;
          /* <<Evaluate radiance along camera ray>> */
          elr_path_begin(&p, &r);
          L = C->path ? elr_path_li(C, &S, &p, &ts) : elr_direct_li(C, &S, &p, &ts);
          /* <<Add camera ray's contribution to image>> */
          elr_to3(L, rgb);
          el_film_tile_add_sample(tile, fx, fy, rgb, 1.f);
          ts.samples++;
        }
      }
    pthread_mutex_lock(&J->mu);
    /* <<Merge image tile into Film>>, in tile order whatever order threads finish them: the same sums
     * for any thread count */
    J->ready[t] = tile;
    while (J->next_merge < J->ntiles && (J->ready[J->next_merge] || (J->stride > 1 && J->next_merge % J->stride != 0))) {
      if (J->ready[J->next_merge]) elr__merge(J->film, J->ready[J->next_merge]);
      J->ready[J->next_merge] = NULL;
      J->next_merge++;
    }
    J->done++;
    elr__progress(J, 0);
    pthread_mutex_unlock(&J->mu);
  }
  pthread_mutex_lock(&J->mu);
  J->total.camera += ts.camera; J->total.bounce += ts.bounce; J->total.shadow += ts.shadow;
  J->total.bsdfl += ts.bsdfl; J->total.samples += ts.samples; J->total.t_embree += ts.t_embree;
  J->total.env_product += ts.env_product; J->total.env_map += ts.env_map; J->total.env_light_only += ts.env_light_only;
  J->total.sun_looked += ts.sun_looked; J->total.sun_lowered += ts.sun_lowered; J->total.sun_dark += ts.sun_dark;
  J->total.sun_to_spot += ts.sun_to_spot;
  J->total.sunsplit_vertices += ts.sunsplit_vertices; J->total.sunsplit_sky_only += ts.sunsplit_sky_only;
  J->total.portal_used += ts.portal_used; J->total.portal_fallback += ts.portal_fallback;
  pthread_mutex_unlock(&J->mu);
  elr_sampler_free(&S);
  elr_wave_free(W);
  return NULL;
}

void elr_render_options_default(elr_render_options *o) {
  memset(o, 0, sizeof *o);
  o->light_sampling = -1; o->compensated = -1; o->importance = -1; o->randomization = -1; o->env_sampling = -1;
  o->env_lobe_alpha = -1.f; o->env_light_alpha = -1.f;
  o->loop = -1; o->wave_api = -1; o->split = -1; o->env_sun = -1; o->env_sun_diffuse = -1; o->env_sun_cos = -3.f;
}

/* >> what the scene calls for */
/* per material, whether a texture varies over its surface (then hits need (u, v), camera rays carry
 * differentials); made once per scene */
static int elr__find_textured(elr_scene *s) {
  int i;
  if (s->mat_textured) return 0;
  s->mat_textured = (int *)calloc((size_t)s->nmat + 1, sizeof(int));
  if (!s->mat_textured) return -1;
  for (i = 0; i < s->nmat; i++) {
    int t[ELR_MAT_NTEX], k;
    elr_material_textures(&s->mat[i], t);
    for (k = 0; k < ELR_MAT_NTEX; k++) if (t[k] >= 0 && s->tex[t[k]].kind != ELR_TEX_CONST) s->mat_textured[i] = 1;
    if (s->mat_textured[i]) s->any_textured = 1;
  }
  return 0;
}

/* whether material m may have a non-specular lobe somewhere: all but mirror and smooth glass (its
 * roughness textures constant 0) */
static int elr__may_be_nonspecular(const elr_scene *s, const elr_material *m) {
  if (m->kind == ELR_MAT_MIRROR) return 0;
  if (m->kind == ELR_MAT_GLASS) {
    const elr_texture *u = &s->tex[m->urough], *v = &s->tex[m->vrough];
    return !(u->kind == ELR_TEX_CONST && u->value.x == 0.f && v->kind == ELR_TEX_CONST && v->value.x == 0.f);
  }
  return 1;
}
/* whether material m may have a non-specular transmission lobe (rough glass): its vertices sample the
 * environment's map alone (elr_bsdf_cos_normal), so the map's tables are needed with product sampling */
static int elr__may_transmit_rough(const elr_scene *s, const elr_material *m) { return m->kind == ELR_MAT_GLASS && elr__may_be_nonspecular(s, m); }
static int elr__mat_transmits_rough(const elr_scene *s) {
  int i;
  for (i = 0; i < s->nmesh; i++) if (elr__may_transmit_rough(s, &s->mat[s->mesh[i].material])) return 1;
  for (i = 0; i < s->nsph; i++) if (elr__may_transmit_rough(s, &s->mat[s->sph[i].material])) return 1;
  for (i = 0; i < s->ndisk; i++) if (elr__may_transmit_rough(s, &s->mat[s->disk[i].material])) return 1;
  return 0;
}
/* The share of the environment's power (luminance x solid angle) that its brightest texels covering
 * ELR_ENV_SUN_AREA of the sphere hold: a sun's. Issue 20: under such a map the product light sample alone
 * misses the sky wherever the sun is occluded (bench/lobes.py's shadows region: 0.41x the map alone's
 * efficiency on city.hdr), so diffuse-only lobes there keep MIS (elr_scene.env_sunny): product MIS
 * (ELR_ENVSD_PRODUCT; the sun rule by the normal, ELR_ENVSD_SUNCOS, before batched product samples: bench/sun_rule.py). */
typedef struct { float lum, w; } elr__texel_lw;
static int elr__cmp_lum(const void *a, const void *b) {
  float x = ((const elr__texel_lw *)a)->lum, y = ((const elr__texel_lw *)b)->lum;
  return x < y ? 1 : x > y ? -1 : 0;
}
static double elr__sun_share(const el_envlight *e, float axis[3]) {
  double P = 0, W = 0, Ps = 0, Ws = 0;
  size_t n, k, imax = 0;
  float lmax = -1.f;
  int x, y;
  elr__texel_lw *t;
  if (!e || e->width <= 0 || !e->texels) return 0.0;
  n = (size_t)e->width * (size_t)e->height;
  t = (elr__texel_lw *)malloc(n * sizeof *t);
  if (!t) return 0.0;
  for (y = 0; y < e->height; y++) {
    float w = e->mapping == EL_ENVLIGHT_MAPPING_LATLONG ? (float)sin(3.14159265358979 * (y + 0.5) / e->height) : 1.f;
    for (x = 0; x < e->width; x++) {
      size_t i = (size_t)y * (size_t)e->width + (size_t)x;
      const float *c = &e->texels[3 * i];
      t[i].lum = 0.2126f * c[0] + 0.7152f * c[1] + 0.0722f * c[2];
      t[i].w = w;
      if (t[i].lum > lmax) { lmax = t[i].lum; imax = i; }
      P += (double)w * t[i].lum; W += w;
    }
  }
  { /* the brightest texel's direction, world space (the sun rule by the normal: ELR_ENVSD_SUNCOS) */
    float u = ((float)(imax % (size_t)e->width) + 0.5f) / (float)e->width, v = ((float)(imax / (size_t)e->width) + 0.5f) / (float)e->height, d[3];
    int j;
    if (e->mapping == EL_ENVLIGHT_MAPPING_LATLONG) el_envlight_uv_to_dir(u, v, d); else el_envlight_square_to_dir(u, v, d);
    for (j = 0; j < 3; j++) axis[j] = e->to_world[3 * j] * d[0] + e->to_world[3 * j + 1] * d[1] + e->to_world[3 * j + 2] * d[2];
  }
  qsort(t, n, sizeof *t, elr__cmp_lum);
  for (k = 0; k < n && Ws < ELR_ENV_SUN_AREA * W; k++) { /* (of the last texel only the part that fits: coarse maps) */
    double part = ELR_ENV_SUN_AREA * W - Ws < t[k].w ? (ELR_ENV_SUN_AREA * W - Ws) / t[k].w : 1.0;
    Ps += part * t[k].w * t[k].lum; Ws += part * t[k].w;
  }
  free(t);
  return P > 0.0 ? Ps / P : 0.0;
}
/* whether some shape's material may have a glossy reflection lobe (plastic, metal, uber, substrate)
 * of alpha below a (elr_bsdf_lobe_alpha's sqrt(ax ay) is below a when either alpha is): issue 20's
 * per-lobe choice samples the environment's map alone there */
/* (a roughness texture that is not constant may go below the threshold anywhere) */
static int elr__rough_below(const elr_scene *s, int t, int remap, float a) {
  float r;
  if (t < 0 || s->tex[t].kind != ELR_TEX_CONST) return 1;
  r = s->tex[t].value.x;
  r = remap ? elr_roughness_to_alpha(r) : r; /* (materials.c's alphas; their floors are below any useful threshold) */
  return r < a;
}
static int elr__may_be_glossy(const elr_scene *s, const elr_material *m, float a) {
  switch (m->kind) {
  case ELR_MAT_PLASTIC: return elr__rough_below(s, m->rough, m->remap, a);
  case ELR_MAT_METAL: case ELR_MAT_UBER: {
    int u = m->urough >= 0 ? m->urough : m->rough, v = m->vrough >= 0 ? m->vrough : m->rough;
    return elr__rough_below(s, u, m->remap, a) || elr__rough_below(s, v, m->remap, a);
  }
  case ELR_MAT_SUBSTRATE: return elr__rough_below(s, m->urough, m->remap, a) || elr__rough_below(s, m->vrough, m->remap, a);
  default: return 0;
  }
}
static int elr__mat_glossy(const elr_scene *s, float a) {
  int i;
  for (i = 0; i < s->nmesh; i++) if (elr__may_be_glossy(s, &s->mat[s->mesh[i].material], a)) return 1;
  for (i = 0; i < s->nsph; i++) if (elr__may_be_glossy(s, &s->mat[s->sph[i].material], a)) return 1;
  for (i = 0; i < s->ndisk; i++) if (elr__may_be_glossy(s, &s->mat[s->disk[i].material], a)) return 1;
  return 0;
}
static int elr__mat_nonspecular(const elr_scene *s) {
  int i;
  /* a material with a non-specular lobe, used by some shape */
  for (i = 0; i < s->nmesh; i++) if (elr__may_be_nonspecular(s, &s->mat[s->mesh[i].material])) return 1;
  for (i = 0; i < s->nsph; i++) if (elr__may_be_nonspecular(s, &s->mat[s->sph[i].material])) return 1;
  for (i = 0; i < s->ndisk; i++) if (elr__may_be_nonspecular(s, &s->mat[s->disk[i].material])) return 1;
  return 0;
}

/* Whether anything emits (*emits) and whether any light is sampled (some light emits and some surface
 * has a non-specular lobe); the sampling distributions of the environments that will be sampled, built
 * now (*env_sampled); the areas of the emitting area lights and the area CDFs of those that are
 * sampled; the light distribution of next-event estimation when it chooses one light among several;
 * whether the wave loop applies (batch_light: its light samples drawn together) and runs. */
static int elr__decide_lights(elr_ctx *C, const elr_render_options *o, elr_stats *st, int *env_sampled, int *emits, char *err,
                              size_t errlen) {
  elr_scene *s = C->s;
  int i;
  float lobe_alpha = o->env_lobe_alpha < 0.f ? ELR_ENV_LOBE_ALPHA : o->env_lobe_alpha;
  float light_alpha = o->env_light_alpha < 0.f ? ELR_ENV_LIGHT_ALPHA : o->env_light_alpha;
  *emits = 0;
  s->env_lobe_alpha = 0.f; s->env_light_alpha = INFINITY; /* (set below where an environment is product-sampled) */
  s->env_sunny = 0; s->env_sun_share = 0.f;
  for (i = 0; i < s->nlight; i++) if (elr_light_emits(&s->light[i])) *emits = 1;
  for (i = 0; i < s->nlight; i++) if (elr_light_emits(&s->light[i]) && s->light[i].kind == ELR_LIGHT_INFINITE) C->has_env = 1;
  for (i = 0; i < s->nlight; i++) if (elr_light_emits(&s->light[i]) && s->light[i].kind == ELR_LIGHT_AREA) C->has_area = 1;
  C->light_sampling = *emits && elr__mat_nonspecular(s);
  C->direct_one = !C->path && s->d.direct_one;
  if (!C->light_sampling) return 0;
  /* area lights: the area (the sampling pdfs, the "power" weights) and, when they are sampled, a mesh's
   * area CDF (pbrt-v3's one light per triangle chosen by area) */
  for (i = 0; i < s->nlight; i++) {
    elr_light *l = &s->light[i];
    if (l->kind == ELR_LIGHT_AREA && elr_light_emits(l)) {
      double t0 = elr_now();
      if (elr_area_light_prepare(s, l, C->ls != ELR_LS_BSDF) != 0) { snprintf(err, errlen, "out of memory for an area light's area CDF"); return -1; }
      if (st) st->t_area_lights += elr_now() - t0;
    }
  }
  /* the light distribution: which light next-event estimation samples (path: lightsamplestrategy;
   * directlighting "one": uniform; "all" samples every light and needs none) */
  if (C->path || C->direct_one) {
    if (elr_light_distrib_init(&C->ld, s, C->path ? s->d.light_strategy : ELR_LSTRAT_UNIFORM) != 0) {
      snprintf(err, errlen, "out of memory for the light distribution");
      return -1;
    }
  }
  for (i = 0; i < s->nlight; i++) {
    elr_light *l = &s->light[i];
    if (l->kind == ELR_LIGHT_INFINITE && elr_light_emits(l) && C->ls != ELR_LS_BSDF) {
      double t0 = elr_now();
      /* (the map's own tables too where some vertex may choose the map alone: a rough transmission or,
       * issue 20's per-lobe choice, a glossy lobe that may be below the threshold) */
      int need_map = elr__mat_transmits_rough(s) || (lobe_alpha > 0.f && elr__mat_glossy(s, lobe_alpha)), importance = o->importance;
      float axis[3] = {0, 0, 0};
      double share = -1.0;
      /* no importance given (scene nor --importance): under a sun the map alone samples le()'s patches
       * (EL_ENVLIGHT_IMPORTANCE_BILINEAR, issue 22: bench/sun_rule.py --strategies pbrtv3,default; README)
       * with a low-discrepancy sampler, whose points it keeps stratified; not with independent samples
       * (about break-even there: its CPU for 1.06x less variance), nor with --sun on, whose cache needs
       * the hot spots of a piecewise-constant density (--sun split finds them on the light's own density, and
       * takes the patches with any sampler: its spot sample draws them, sun.c) */
      if (l->importance_auto) l->importance_auto = 1; /* (2: chosen below, for --stats) */
      if (importance < 0 && l->importance_auto && (o->env_sun <= 0 || o->env_sun == 2) && (C->sampler.kind != ELR_SAMPLER_RANDOM || o->env_sun == 2) && l->env->mapping == EL_ENVLIGHT_MAPPING_LATLONG && !l->portal) {
        share = elr__sun_share(l->env, axis);
        if (share > ELR_ENV_SUN_SHARE) { importance = EL_ENVLIGHT_IMPORTANCE_BILINEAR; l->importance_auto = 2; /* (--stats) */ }
      }
      if (elr_infinite_prepare(l, o->compensated, importance, o->env_sampling, need_map) != 0) {
        snprintf(err, errlen, "environment: cannot build the sampling distribution");
        return -1;
      }
      if (l->product) {
        s->env_lobe_alpha = lobe_alpha; s->env_light_alpha = light_alpha;
        s->env_sun_share = (float)(share >= 0.0 ? share : elr__sun_share(l->env, axis));
        s->env_sunny = s->env_sun_share > ELR_ENV_SUN_SHARE;
        s->env_sun_diffuse = o->env_sun_diffuse < 0 ? ELR_ENV_SUN_DIFFUSE : o->env_sun_diffuse;
        s->env_sun_cos = o->env_sun_cos > -2.f ? o->env_sun_cos : ELR_ENV_SUN_COS;
        s->env_sun_axis = elr_v(axis[0], axis[1], axis[2]); /* (the brightest texel's direction) */
      }
      if (st) st->t_distribution += elr_now() - t0;
      *env_sampled = 1;
    }
  }
  /* a pixel's light samples drawn together when the only emitting light is a sampled environment */
  /* (with a pixel sampler, only when its dimensions cover the three 2D draws made ahead: draws past
   * them come from the pixel's one random stream, whose order batching would change) */
  /* (with product sampling only the wave loop draws them, one at a time: below) */
  if (*env_sampled && !o->no_batch && elr_sampler_order_free(&C->sampler)) {
    int nemit = 0;
    for (i = 0; i < s->nlight; i++) if (elr_light_emits(&s->light[i])) { nemit++; C->batch_light = &s->light[i]; }
    if (nemit != 1) C->batch_light = NULL;
  }
  /* the per-tile loop: the wave loop needs batch_light and is the default there (bench_render --loops
   * measures both), except for the path tracer with a pixel sampler (stratified, 02sequence) and product
   * sampling: that sampler's draws past its dimensions come from the pixel's one stream, which the wave
   * loop reaches in another order (other numbers of the same distribution: test_render_wave), so the
   * reference keeps its image. With the map alone that case took the batched loop (render_batched.c,
   * the reference's image), which the wave loop replaced: bench_city's path tracer with the map alone
   * and stratified samples, one thread, loop CPU 0.50 s in the wave loop, 0.63 s batched, 0.89 s one at
   * a time. */
  C->loop = ELR_LOOP_ONE;
  if (C->batch_light) {
    int pixel_sampler = C->sampler.kind == ELR_SAMPLER_STRATIFIED || C->sampler.kind == ELR_SAMPLER_ZEROTWO;
    C->loop = o->loop == ELR_LOOP_ONE || o->loop == ELR_LOOP_WAVE       ? o->loop
              : C->path && pixel_sampler && C->batch_light->product ? ELR_LOOP_ONE
                                                                    : ELR_LOOP_WAVE;
    /* (ELR_ENVSD_TWO(_PIXEL), two product light samples at diffuse vertices under a sun map, directlighting and path:
     * the wave loop too, the same image: render_wave.c, test_render_wave) */
    /* (portals, whose density depends on the shading point, are sampled by the wave loop at each
     * vertex, el_envlight_portal_sample_li; with a pixel sampler like the map alone: test_render_portal) */
  }
  C->wave_api = o->wave_api >= ELR_WAVE_API_SINGLE && o->wave_api <= ELR_WAVE_API_SOA ? o->wave_api : ELR_WAVE_API_DEFAULT;
  return 0;
}

/* >> statistics: what the render built and what it cost (elr_stats; stats.c prints them) */
static void elr__fill_stats(elr_stats *st, const elr_scene *s, const elr_ctx *C, const elr_tstats *T, const el_film *film, int nthreads,
                            int env_sampled, const elr_image *out) {
  int i;
  st->t_parse = s->t_parse; st->t_images = s->t_images; st->t_embree = s->t_embree;
  st->bytes_embree = s->bytes_embree; st->bytes_film = el_film_bytes(film);
  st->bytes_splats = film->splats ? (size_t)film->width * (size_t)film->height * 3 * sizeof(double) : 0; st->splats_allocated = st->bytes_splats > 0;
  st->camera_rays = T->camera; st->bounce_rays = T->bounce; st->shadow_rays = T->shadow;
  st->env_product_samples = T->env_product; st->env_map_samples = T->env_map; st->env_light_only_samples = T->env_light_only;
  st->bsdf_light_rays = T->bsdfl; st->samples = T->samples;
  st->distribution_built = env_sampled; st->light_sampling_used = C->light_sampling;
  st->light_samples_batched = C->batch_light != NULL && C->loop != ELR_LOOP_ONE && !C->batch_light->product && !C->batch_light->portal;
  st->loop = C->loop; st->wave_api = C->wave_api; st->t_embree_loop = T->t_embree;
  st->nthreads = nthreads; st->spp = C->spp; st->width = out->width; st->height = out->height;
  st->maxdepth = C->maxdepth; st->integrator_path = C->path; st->sampler = C->sampler.kind;
  st->sampler_randomization = C->sampler.randomize;
  st->rejected_samples = el_film_rejected_samples(film);
  for (i = 0; i < s->ntex; i++) {
    if (s->tex[i].kind == ELR_TEX_IMAGE) {
      const el_mipmap *m = s->tex[i].mip;
      st->mip_textures++;
      st->mip_levels_built += el_mipmap_levels_built(m) ? el_mipmap_levels(m) : 1; /* level 0 always exists */
      st->bytes_mip += el_mipmap_bytes(m);
    }
  }
  st->bytes_textures = s->bytes_textures;
  for (i = 0; i < s->nlight; i++)
    if (s->light[i].kind == ELR_LIGHT_INFINITE) {
      const el_envlight *e = s->light[i].env;
      st->bytes_textures += sizeof(float) * 3 * (size_t)e->width * (size_t)e->height;
      if (env_sampled) st->bytes_distribution = el_envlight_sampling_bytes(s->light[i].env_sample) + el_envlight_product_bytes(s->light[i].env_sample);
    }
  /* the lights: what was built for which */
  st->lights = s->nlight;
  if (!C->light_sampling) snprintf(st->light_strategy, sizeof st->light_strategy, "none");
  else if (!C->path && !C->direct_one) snprintf(st->light_strategy, sizeof st->light_strategy, "all");
  else snprintf(st->light_strategy, sizeof st->light_strategy, "%s",
                C->ld.strategy == ELR_LSTRAT_UNIFORM ? "uniform" : (C->path && s->d.light_strategy == ELR_LSTRAT_SPATIAL ? "power (for spatial)" : "power"));
  st->light_distribution_built = C->ld.n > 1;
  st->bytes_light_distribution = C->ld.n > 1 ? C->ld.bytes : 0;
  st->t_light_distribution = C->ld.seconds;
  for (i = 0; i < s->nlight; i++) {
    const elr_light *l = &s->light[i];
    elr_light_stats *ls;
    st->lights_emitting += elr_light_emits(l);
    st->lights_area += l->kind == ELR_LIGHT_AREA;
    if (i >= ELR_STATS_LIGHTS) continue;
    ls = &st->light[st->nlight_stats++];
    ls->kind = l->kind; ls->emits = elr_light_emits(l); ls->nsamples = l->nsamples;
    ls->pick = C->ld.pick ? C->ld.pick[i] : (ls->emits && C->light_sampling ? 1.f : 0.f);
    if (l->kind == ELR_LIGHT_INFINITE && env_sampled && ls->emits && C->ls != ELR_LS_BSDF && C->light_sampling) {
      ls->tables_built = 1; ls->bytes = el_envlight_sampling_bytes(l->env_sample) + el_envlight_product_bytes(l->env_sample);
      ls->env_product = l->product; ls->env_lobe_alpha = l->product ? s->env_lobe_alpha : 0.f;
      ls->env_light_alpha = l->product ? s->env_light_alpha : INFINITY;
      ls->env_sun_share = l->product ? s->env_sun_share : 0.f;
      ls->env_map_built = el_envlight_sampling_bytes(l->env_sample) > 0;
      ls->env_importance = l->env_sample->importance;
      ls->env_importance_auto = l->importance_auto == 2;
    }
    if (l->kind == ELR_LIGHT_INFINITE && l->portal) {
      ls->env_portals = l->portal->count; ls->env_portal_bytes = el_envlight_portal_bytes(l->portal); ls->env_portal_share = l->portal->map_share;
      ls->env_portal_compensated = l->portal->compensated;
      ls->env_portal_used = T->portal_used; ls->env_portal_fallback = T->portal_fallback; /* (the one emitting light with portals) */
    }
    if (l->kind == ELR_LIGHT_AREA) {
      ls->shape_kind = l->shape_kind; ls->shape = l->shape; ls->twosided = l->twosided; ls->area = l->area;
      ls->ntri = l->shape_kind == ELR_SHAPE_MESH ? s->mesh[l->shape].ntri : 0;
      ls->tables_built = l->tri_cdf != NULL;
      ls->bytes = l->tri_cdf ? sizeof(double) * ((size_t)ls->ntri + 1) : 0;
      ls->seconds = l->build_seconds;
    }
    if (C->light_sampling && ls->emits && (l->kind != ELR_LIGHT_AREA || l->prepared)) ls->power = elr_light_power(s, l);
  }
}

/* Renders the tiles (every stride-th: the splitting pilot) into film on nthreads threads with the
 * samplers' seed; J holds the counts afterwards. -1 with err on failure. */
static int elr__run(const elr_ctx *C, const elr_render_options *o, el_film *film, const elr_sampler_tables *T, int nthreads, int stride,
             uint64_t seed, int quiet, elr_job *J, char *err, size_t errlen) {
  pthread_t *th = NULL;
  int i, rc = -1;
  memset(J, 0, sizeof *J);
  J->seed = seed; J->quiet = quiet;
  J->C = (elr_ctx *)C; J->film = film; J->o = o; J->T = T; J->stride = stride;
  {
    int b[4];
    el_film_sample_bounds(film, b);
    J->bx0 = b[0]; J->by0 = b[1]; J->bx1 = b[2]; J->by1 = b[3];
  }
  /* <<Compute number of tiles, nTiles, to use for parallel rendering>> */
  J->tile = o->tile_size > 0 ? o->tile_size : 16;
  J->ntx = (J->bx1 - J->bx0 + J->tile - 1) / J->tile; J->nty = (J->by1 - J->by0 + J->tile - 1) / J->tile;
  J->ntiles = J->ntx * J->nty;
  J->ready = (el_film_tile **)calloc((size_t)J->ntiles, sizeof(el_film_tile *));
  th = (pthread_t *)calloc((size_t)nthreads, sizeof(pthread_t));
  if (!J->ready || !th) { snprintf(err, errlen, "out of memory"); goto fail; }
  pthread_mutex_init(&J->mu, NULL);
  J->t0 = elr_now(); J->last_print = 0;
  J->cpu0 = elr_cpu_now();
  { /* <<Render image tiles in parallel>> */
    int started = 0;
    for (i = 0; i < nthreads; i++) {
      if (pthread_create(&th[i], NULL, elr__worker, J) != 0) break;
      started++;
    }
    if (started == 0) elr__worker(J);
    for (i = 0; i < started; i++) pthread_join(th[i], NULL);
  }
  pthread_mutex_destroy(&J->mu);
  if (J->failed || J->next_merge != J->ntiles) {
    for (i = 0; i < J->ntiles; i++) if (J->ready[i]) elr__merge(film, J->ready[i]);
    snprintf(err, errlen, "rendering failed (out of memory for a film tile or sampler)");
    goto fail;
  }
  rc = 0;
fail:
  free(th);
  free(J->ready); J->ready = NULL;
  return rc;
}

/* >> splitting (the direct-lighting integrator, strategy "all"): how many light and BSDF sample pairs
 * each camera sample takes at its first vertex, in the spirit of Rath et al. 2022, "EARS:
 * efficiency-aware Russian roulette and splitting". With n pairs the variance of a camera sample's
 * estimate is about A + B / n (A: the camera part, pixel footprint and visible surface; B: one light
 * and BSDF pair's) and its cost C + D n, so their product, error x time at any sample count, is least
 * at n = sqrt(B C / (A D)). A pilot measures the two: every stride-th tile rendered twice (other
 * seeds) with n = 1 and with n = ELR_SPLIT_PILOT_N; the variance from the two renders' difference
 * (relative, as bench_render's relMSE), the cost as the process's CPU time. The n kept is the integer
 * in [1, ELR_SPLIT_MAX] that minimises the fitted product, when it predicts at least 5% less than
 * n = 1 (else 1). Every n gives an unbiased image (pbrt-v3's UniformSampleAllLights averages a light's
 * samples), and the pilot's seeds are not the render's, so the choice does not bias it either. Used
 * only where the scene leaves every light's "samples" at 1 (a scene's counts are honoured), and
 * switched off by the Integrator's "splitting" "off" or --split off. */
#define ELR_SPLIT_PILOT_N 4
#define ELR_SPLIT_MAX 16
static double elr__cpu_now(void) {
  struct timespec t;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}
static void elr__split_set(elr_scene *s, int n, int saved[ELR_SPLIT_LIGHTS]) {
  int i;
  for (i = 0; i < s->nlight && i < ELR_SPLIT_LIGHTS; i++) {
    if (saved[i] < 0) saved[i] = s->light[i].nsamples;
    s->light[i].nsamples = n;
  }
}
static void elr__split_restore(elr_scene *s, int saved[ELR_SPLIT_LIGHTS]) {
  int i;
  for (i = 0; i < s->nlight && i < ELR_SPLIT_LIGHTS; i++)
    if (saved[i] >= 0) { s->light[i].nsamples = saved[i]; saved[i] = -1; }
}
static int elr__split_choose(elr_ctx *C, const elr_render_options *o, elr_scene *s, const int fb[4], const elr_sampler_tables *T,
                             int nthreads, elr_stats *st, int saved[ELR_SPLIT_LIGHTS], char *err, size_t errlen) {
  int i, mode = o->split >= 0 ? o->split : (s->d.split_auto ? ELR_SPLIT_AUTO : ELR_SPLIT_OFF), rep, k, ntiles, stride, n;
  int ns[2] = {1, ELR_SPLIT_PILOT_N};
  float *img[2][2] = {{NULL, NULL}, {NULL, NULL}};
  double var[2] = {0, 0}, cpu[2] = {0, 0}, t0 = elr_now(), A, B, Ct, D, best, base;
  size_t npx = (size_t)(fb[2] - fb[0]) * (size_t)(fb[3] - fb[1]) * 3;
  if (st) st->split = 1;
  if (C->path || C->direct_one || !C->light_sampling || mode == ELR_SPLIT_OFF || s->nlight > ELR_SPLIT_LIGHTS) return 0;
  for (i = 0; i < s->nlight; i++) if (elr_light_emits(&s->light[i]) && s->light[i].nsamples != 1) return 0; /* the scene's counts */
  if (mode >= 2) { /* a given n */
    elr__split_set(s, mode > ELR_SPLIT_MAX_GIVEN ? ELR_SPLIT_MAX_GIVEN : mode, saved);
    if (st) st->split = s->light[0].nsamples;
    return 0;
  }
  /* the pilot: about 5 tiles, each render of them twice with n = 1 and n = ELR_SPLIT_PILOT_N, interleaved */
  {
    int tile = o->tile_size > 0 ? o->tile_size : 16;
    ntiles = ((fb[2] - fb[0] + tile - 1) / tile) * ((fb[3] - fb[1] + tile - 1) / tile);
    stride = ntiles / 5 > 1 ? ntiles / 5 : 1;
  }
  for (rep = 0; rep < 2; rep++)
    for (k = 0; k < 2; k++) {
      el_film f;
      elr_job J;
      double c0;
      memset(&f, 0, sizeof f);
      img[rep][k] = (float *)malloc(sizeof(float) * npx);
      if (!img[rep][k] || elr_film_init(&f, &s->d, fb, err, errlen) != 0) { snprintf(err, errlen, "out of memory for the splitting pilot"); goto fail; }
      elr__split_set(s, ns[k], saved);
      c0 = elr__cpu_now();
      if (elr__run(C, o, &f, T, nthreads, stride, o->seed ^ (0x9b1a7e5ULL + (uint64_t)rep * 0x51ed27ULL), 1, &J, err, errlen) != 0) {
        el_film_free(&f); goto fail;
      }
      cpu[k] += elr__cpu_now() - c0;
      el_film_get_rgb(&f, 1.f, img[rep][k]);
      el_film_free(&f);
    }
  elr__split_restore(s, saved);
  for (k = 0; k < 2; k++) {
    size_t j;
    for (j = 0; j < npx; j++) {
      double a = img[0][k][j], b = img[1][k][j], m = 0.5 * (a + b);
      var[k] += (a - b) * (a - b) / (m * m + 1e-2);
    }
  }
  /* the model: var(n) = A + B / n, cost(n) = Ct + D n, through the two pilots */
  B = (var[0] - var[1]) * (double)ns[1] / (double)(ns[1] - ns[0]);
  A = var[0] - B;
  D = (cpu[1] - cpu[0]) / (double)(ns[1] - ns[0]);
  Ct = cpu[0] - D;
  if (A < 1e-3 * var[0]) A = 1e-3 * var[0];      /* (noise: keep the product finite) */
  if (D < 1e-3 * cpu[0]) D = 1e-3 * cpu[0];
  if (Ct < 1e-3 * cpu[0]) Ct = 1e-3 * cpu[0];
  base = (A + B) * (Ct + D);
  n = 1; best = base;
  if (B > 0)
    for (k = 2; k <= ELR_SPLIT_MAX; k++) {
      double e = (A + B / k) * (Ct + D * k);
      if (e < best) { best = e; n = k; }
    }
  if (best > 0.95 * base) n = 1;
  if (n > 1) elr__split_set(s, n, saved);
  if (st) {
    st->split = n; st->split_auto = 1; st->t_split_pilot = elr_now() - t0;
    st->split_var[0] = var[0]; st->split_var[1] = var[1]; st->split_cpu[0] = cpu[0]; st->split_cpu[1] = cpu[1];
    st->split_gain = best > 0 ? base / best : 1.0;
  }
  for (rep = 0; rep < 2; rep++) for (k = 0; k < 2; k++) free(img[rep][k]);
  return 0;
fail:
  elr__split_restore(s, saved);
  for (rep = 0; rep < 2; rep++) for (k = 0; k < 2; k++) free(img[rep][k]);
  return -1;
}

/* issue 22 (sun.c): the pilot that learns where the sampled environment's hot spots are hidden, for the
 * first emitting environment sampled by product sampling (the default; not behind portals) */
static int elr__sun_prepare(elr_ctx *C, const elr_render_options *o, const int fb[4], int nthreads, elr_stats *st, elr_sun **sun,
                            elr_sunsplit **split) {
  const elr_scene *s = C->s;
  int i;
  *sun = NULL; *split = NULL;
  if (o->env_sun <= 0 || !C->light_sampling || C->ls == ELR_LS_BSDF) return 0; /* (-1, the default: off, el_render.h) */
  for (i = 0; i < s->nlight; i++) {
    const elr_light *l = &s->light[i];
    if (l->kind != ELR_LIGHT_INFINITE || !elr_light_emits(l) || !l->product || l->portal || !l->env_sample) continue;
    /* only under a sun (elr__sun_share): on studio.hdr's lamps the cache gave 2.4x MORE variance in the
     * largest lamp's shadow (its other lamps stay lit and the rest x cosine draws them without the cosine:
     * envlight.h's NOTES ON HOT SPOTS 4), bench/bench_sun_render.c on scenes/bench_studio.pbrt */
    if (!s->env_sunny) return 0;
    if (o->env_sun == 2) { /* --sun split: no pilot; either loop (render_wave.c: the same image, test_render_wave) */
      if (elr_sunsplit_build(l, split) != 0) return -1;
      C->sunsplit = *split;
      if (st && *split) { st->sunsplit_used = 1; st->sunsplit_spot = elr_sunsplit_spot(*split); st->t_sun_cpu = elr_sunsplit_cpu(*split); }
      return 0;
    }
    if (elr_sun_build(C, l, fb, nthreads, sun) != 0) return -1;
    C->sun = *sun;
    if (st && *sun) {
      const elr_sun_info *in = elr_sun_get_info(*sun);
      int k;
      st->sun_used = 1; st->sun_spots = in->spots; st->sun_cell = in->cell; st->sun_floor = in->floor;
      for (k = 0; k < in->spots && k < 8; k++) {
        st->sun_spot_axis[k][0] = in->spot[k].axis[0]; st->sun_spot_axis[k][1] = in->spot[k].axis[1]; st->sun_spot_axis[k][2] = in->spot[k].axis[2];
        st->sun_spot_half_angle[k] = in->spot[k].half_angle; st->sun_spot_share[k] = in->spot[k].share;
      }
      st->sun_pilot_points = in->pilot_points; st->sun_pilot_rays = in->pilot_rays; st->sun_cells = in->cells;
      st->sun_cells_lowered = in->cells_lowered; st->sun_cells_dark = in->cells_dark; st->sun_cells_horizon = in->cells_horizon; st->t_sun = in->seconds;
      st->t_sun_cpu = in->cpu_seconds;
    }
    return 0;
  }
  return 0;
}

int elr_render(elr_scene *s, const elr_render_options *o, elr_image *out, elr_stats *st, char *err, size_t errlen) {
  elr_sun *sun = NULL;
  elr_sunsplit *sunsplit = NULL;
  elr_ctx C;
  elr_job J;
  elr_sampler_tables T;
  el_film film;
  int split_saved[ELR_SPLIT_LIGHTS];
  int i, nthreads, x0, y0, x1, y1, rc = -1, env_sampled = 0, emits = 0, fb[4];
  double t_start = elr_now();
  memset(&C, 0, sizeof C); memset(&J, 0, sizeof J); memset(&T, 0, sizeof T); memset(&film, 0, sizeof film);
  for (i = 0; i < ELR_SPLIT_LIGHTS; i++) split_saved[i] = -1;
  memset(out, 0, sizeof *out);
  if (st) memset(st, 0, sizeof *st);
  C.s = s;
  if (elr_sampler_choose(&C.sampler, s, o, err, errlen) != 0) return -1;
  C.spp = C.sampler.spp;
  C.ls = o->light_sampling >= 0 ? o->light_sampling : s->d.light_sampling;
  C.maxdepth = s->d.maxdepth; C.path = s->d.integrator_path; C.rr = s->d.rrthreshold;
  elr_film_bounds(&s->d, fb);
  x0 = fb[0]; y0 = fb[1]; x1 = fb[2]; y1 = fb[3];
  if (x1 <= x0 || y1 <= y0) { snprintf(err, errlen, "the crop window covers no pixel"); return -1; }
  if ((double)(x1 - x0) * (double)(y1 - y0) * (double)C.spp > 1e12) {
    snprintf(err, errlen, "%d x %d pixels at %d samples is more than 1e12 samples", x1 - x0, y1 - y0, C.spp);
    return -1;
  }
  if (elr_film_init(&film, &s->d, fb, err, errlen) != 0) return -1;
  /* <<Decide what the scene calls for>> */
  if (elr__find_textured(s) != 0) { snprintf(err, errlen, "out of memory"); goto done; }
  elr_camera_init(&C.cam, &s->d, C.spp, s->any_textured);
  if (elr__decide_lights(&C, o, st, &env_sampled, &emits, err, errlen) != 0) goto done;
  if (!emits) { /* nothing emits: the image is black whatever is traced (the parser warned), so nothing is */
    out->width = x1 - x0; out->height = y1 - y0;
    out->rgb = (float *)calloc((size_t)out->width * (size_t)out->height * 3, sizeof(float));
    if (!out->rgb) { snprintf(err, errlen, "out of memory"); goto done; }
    if (st) {
      memset(&J.total, 0, sizeof J.total);
      elr__fill_stats(st, s, &C, &J.total, &film, 0, 0, out);
      st->nothing_emits = 1;
    }
    rc = 0;
    goto done;
  }
  { /* the sampler's tables (Halton's permutations, Sobol's matrices), for the film's sample bounds */
    int b[4];
    el_film_sample_bounds(&film, b);
    if (elr_sampler_tables_init(&T, &C.sampler, b, o->seed) != 0) { snprintf(err, errlen, "out of memory"); goto done; }
  }
  nthreads = o->nthreads > 0 ? o->nthreads : (int)sysconf(_SC_NPROCESSORS_ONLN);
  if (nthreads < 1) nthreads = 1;
  if (nthreads > 1024) nthreads = 1024;
  if (elr__sun_prepare(&C, o, fb, nthreads, st, &sun, &sunsplit) != 0) { snprintf(err, errlen, "out of memory for the sun cache"); goto done; }
  /* splitting: the light and BSDF samples per camera sample, chosen by a pilot */
  if (elr__split_choose(&C, o, s, fb, &T, nthreads, st, split_saved, err, errlen) != 0) goto done;
  if (elr__run(&C, o, &film, &T, nthreads, 1, o->seed, o->quiet, &J, err, errlen) != 0) goto done;
  elr__progress(&J, 1);
  out->width = x1 - x0; out->height = y1 - y0;
  out->rgb = (float *)malloc(sizeof(float) * 3 * (size_t)out->width * (size_t)out->height);
  if (!out->rgb) { snprintf(err, errlen, "out of memory"); goto done; }
  el_film_get_rgb(&film, 1.f, out->rgb);
  if (st) {
    st->t_render = elr_now() - J.t0;
    st->t_render_cpu = elr_cpu_now() - J.cpu0;
    elr__fill_stats(st, s, &C, &J.total, &film, nthreads, env_sampled, out);
    st->sun_looked = J.total.sun_looked; st->sun_lowered = J.total.sun_lowered; st->sun_dark = J.total.sun_dark;
    st->sun_to_spot = J.total.sun_to_spot;
    st->sunsplit_vertices = J.total.sunsplit_vertices; st->sunsplit_sky_only = J.total.sunsplit_sky_only;
  }
  rc = 0;
done:
  elr_sun_free(sun); elr_sunsplit_free(sunsplit);
  if (st) st->t_total = elr_now() - t_start + s->t_parse;
  free(J.ready); elr_sampler_tables_free(&T);
  elr__split_restore(s, split_saved);
  elr_light_distrib_free(&C.ld);
  el_film_free(&film);
  if (rc != 0) { free(out->rgb); out->rgb = NULL; out->width = out->height = 0; }
  return rc;
}
