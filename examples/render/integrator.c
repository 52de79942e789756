/* integrator.c: camera, samplers, the two integrators, tiles on threads, stats, scene load/free and
 * image output.
 *
 * Camera: pbrt-v3's PerspectiveCamera (pinhole): the screen window spans [-frame, frame] x [-1, 1] (or
 * [-1, 1] x [-1/frame, 1/frame]) so fov applies to the shorter image axis; raster y grows downwards;
 * rays carry differentials scaled by 1/sqrt(spp) (pbrt's ScaleDifferentials).
 *
 * Samplers: "random"; "stratified" (pbrt-v3's StratifiedSampler: jittered strata for the first
 * `dimensions` 1D and 2D dimensions, shuffled across the pixel's samples, uniform random after); "halton"
 * (pbrt-v3's HaltonSampler: one global Halton sequence whose first two dimensions land in the pixel,
 * random digit permutations for the others). Every pixel's random numbers depend only on --seed and
 * the pixel, so the image is the same for every thread count.
 *
 * Integrators: "directlighting" is pbrt-v3's DirectLightingIntegrator (strategy "all": every light,
 * its `samples` count, light and BSDF sampling combined with the power heuristic; specular reflection
 * recursed to maxdepth). "path" is a unidirectional path tracer with next-event estimation from every
 * light at every vertex, the continuation ray's BSDF sample reused as the MIS partner (pbrt-v4's
 * arrangement: one fewer ray per vertex than pbrt-v3, the same expectation), and pbrt-v3's Russian
 * roulette (after 3 bounces, when the throughput's largest component is below rrthreshold). */
#define _POSIX_C_SOURCE 200809L
#include "elr_internal.h"
#include "image_io.h"
#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* >> render context */
typedef struct elr_ctx {
  elr_scene *s;
  int ls;                 /* ELR_LS_* */
  int light_sampling;     /* 0: no light is ever sampled (nothing emits, or nothing non-specular) */
  int has_env;            /* an emitting infinite light exists */
  int maxdepth, path;
  float rr;
  elr_camera cam;
  elr_sampler_desc sampler;
  int spp;                /* sampler.spp */
  /* batched light samples (elr__pixel_batched): the one emitting light, an environment, whose first
   * light sample is each camera sample's second 2D draw; NULL: one sample at a time */
  const elr_light *batch_light;
} elr_ctx;

/* A camera sample's first vertex and light sample, computed ahead by elr__pixel_batched: the camera
 * ray's hit (hit = 0: it left the scene) and, at a hit, the environment sample for the first draw of
 * light sampling there. */
typedef struct elr_first {
  int hit;
  const elr_hit *h;
  elr_v3 wi, L;
  float pdf;
  /* the direct-lighting integrator's, at a hit: the texture footprint and BSDF, and (bs = 1) the BSDF
   * sample of the first draw of light sampling; when it will trace a BSDF ray (bray = 1), the
   * environment's pdf and radiance in its direction */
  int bs, bray;
  elr_tex_ctx tc;
  elr_v3 dpdx, dpdy;
  elr_bsdf b;
  elr_v3 fb, wb, Lb;
  float bpdf, bpdf_env;
} elr_first;

typedef struct elr_tstats { uint64_t camera, bounce, shadow, bsdfl, samples; } elr_tstats;

static float elr__power(float a, float b) { float a2 = a * a, b2 = b * b; return a2 + b2 > 0.f ? a2 / (a2 + b2) : 0.f; }
static elr_v3 elr__env_le(const elr_scene *s, elr_v3 d) {
  int i;
  elr_v3 L = elr_v(0, 0, 0);
  for (i = 0; i < s->nlight; i++)
    if (s->light[i].kind == ELR_LIGHT_INFINITE && elr_light_emits(&s->light[i])) L = elr_add(L, elr_light_le(&s->light[i], d));
  return L;
}

/* Direct light at a surface point from every light: pbrt-v3's EstimateDirect for each light, with
 * the strategies ctx->ls selects. `nsamples_all`: use each light's sample count (directlighting). */
static elr_v3 elr__direct(const elr_ctx *C, elr_sampler *S, const elr_hit *h, const elr_bsdf *b, elr_v3 wo, int use_counts,
                          elr_tstats *ts, const elr_first *first) {
  const elr_scene *s = C->s;
  elr_v3 Ld = elr_v(0, 0, 0);
  int li;
  for (li = 0; li < s->nlight; li++) {
    const elr_light *l = &s->light[li];
    int n = use_counts ? l->nsamples : 1, k;
    elr_v3 sum = elr_v(0, 0, 0);
    if (!elr_light_emits(l)) continue;
    for (k = 0; k < n; k++) {
      float ul0 = 0.f, ul1 = 0.f, us0 = 0.f, us1 = 0.f;
      const elr_first *pre = first && k == 0 && l == C->batch_light ? first : NULL; /* drawn ahead */
      if (pre) elr_sampler_skip2d(S); else { float u[2]; elr_sampler_get2d(S, u); ul0 = u[0]; ul1 = u[1]; }
      if (pre && pre->bs) elr_sampler_skip2d(S); else { float u[2]; elr_sampler_get2d(S, u); us0 = u[0]; us1 = u[1]; }
      if (l->kind != ELR_LIGHT_INFINITE) {
        /* delta lights: light sampling only */
        elr_v3 wi, Li, f;
        float dist;
        if (l->kind == ELR_LIGHT_POINT) {
          elr_v3 dp = elr_sub(l->pos, h->p);
          float d2 = elr_dot(dp, dp);
          if (d2 <= 0.f) continue;
          dist = sqrtf(d2); wi = elr_mul(dp, 1.f / dist);
          Li = elr_mul(l->L, 1.f / d2);
        } else {
          wi = l->dir; Li = l->L; dist = 2.f * s->world_radius + elr_len(elr_sub(h->p, s->world_center)) + 1.f;
        }
        f = elr_mul(elr_bsdf_f(b, wo, wi), fabsf(elr_dot(wi, b->ns)));
        if (elr_isblack(f)) continue;
        {
          elr_v3 o = elr_spawn_origin(h, wi);
          float tmax = l->kind == ELR_LIGHT_POINT ? elr_len(elr_sub(l->pos, o)) * (1.f - 1e-4f) : dist;
          ts->shadow++;
          if (elr_occluded(s, o, wi, tmax)) continue;
        }
        sum = elr_add(sum, elr_vmul(f, Li));
        continue;
      }
      /* the environment. The BSDF sample is drawn first: when it will need the map's pdf and radiance
       * (after its shadow ray), their cache lines are prefetched now and arrive while the light sample
       * and both shadow rays run (a random direction's texels and pdf bin are cache misses in the
       * multi-megabyte tables). The contributions are added in pbrt-v3's order: light, then BSDF. */
      {
        elr_v3 wb = elr_v(0, 0, 0), fb = elr_v(0, 0, 0);
        float bpdf = 0.f;
        int bsdf_ray = 0;
        if (C->ls != ELR_LS_LIGHT && !C->path) { /* in the path integrator the continuation ray plays this part */
          if (pre && pre->bs) { fb = pre->fb; wb = pre->wb; bpdf = pre->bpdf; bsdf_ray = pre->bray; }
          else {
            int spec;
            fb = elr_bsdf_sample(b, wo, us0, us1, &wb, &bpdf, &spec);
            bsdf_ray = !spec && bpdf > 0.f && !elr_isblack(fb);
            if (bsdf_ray) elr_infinite_prefetch(l, wb);
          }
        }
        /* light sampling */
        if (C->ls != ELR_LS_BSDF) {
          elr_v3 wi, Li, f;
          float lpdf, spdf;
          /* the radiance comes with the sample (pbrt-v3's Sample_Li: the map looked up at the sampled
           * (u, v), no second direction-to-(u, v) mapping) */
          if (pre) { Li = pre->L; wi = pre->wi; lpdf = pre->pdf; }
          else {
            float u[2], w3[3], L3[3];
            u[0] = ul0; u[1] = ul1;
            el_envlight_sample_li(l->env_sample, u, w3, L3, &lpdf);
            wi = elr_from3(w3); Li = elr_from3(L3);
          }
          if (lpdf > 0.f) {
            f = elr_mul(elr_bsdf_f(b, wo, wi), fabsf(elr_dot(wi, b->ns)));
            if (!elr_isblack(f)) {
              ts->shadow++;
              if (!elr_occluded(s, elr_spawn_origin(h, wi), wi, INFINITY)) {
                float w = 1.f;
                if (C->ls == ELR_LS_MIS) { spdf = elr_bsdf_pdf(b, wo, wi); w = elr__power(lpdf, spdf); }
                sum = elr_add(sum, elr_mul(elr_vmul(f, Li), w / lpdf));
              }
            }
          }
        }
        /* BSDF sampling */
        if (bsdf_ray) {
          fb = elr_mul(fb, fabsf(elr_dot(wb, b->ns)));
          ts->bsdfl++;
          if (!elr_occluded(s, elr_spawn_origin(h, wb), wb, INFINITY)) {
            /* pbrt-v3 returns when Pdf_Li is 0; with a compensated density that would drop the dim parts
             * of the map, which only BSDF sampling covers: the power heuristic then gives weight 1 */
            float w;
            elr_v3 Lb;
            if (pre && pre->bs) { w = C->ls == ELR_LS_MIS ? elr__power(bpdf, pre->bpdf_env) : 1.f; Lb = pre->Lb; }
            else { w = C->ls == ELR_LS_MIS ? elr__power(bpdf, elr_light_pdf_li(l, h, wb)) : 1.f; Lb = elr_light_le(l, wb); }
            sum = elr_add(sum, elr_mul(elr_vmul(fb, Lb), w / bpdf));
          }
        }
      }
    }
    Ld = elr_add(Ld, elr_mul(sum, 1.f / (float)n));
  }
  return Ld;
}

/* pbrt-v3's DirectLightingIntegrator::Li. Its SpecularReflect recursion has one branch (reflection
 * only: no material here transmits), so it runs as a loop carrying the throughput: no stack growth
 * whatever maxdepth says. */
static elr_v3 elr__li_direct(const elr_ctx *C, elr_sampler *S, const elr_ray *r0, elr_tstats *ts, const elr_first *first) {
  const elr_scene *s = C->s;
  elr_v3 L = elr_v(0, 0, 0), beta = elr_v(1, 1, 1);
  elr_ray r = *r0;
  int depth;
  for (depth = 0;; depth++) {
    elr_hit h;
    elr_bsdf b;
    elr_tex_ctx tc;
    elr_v3 wo, dpdx, dpdy, wi, f;
    float pdf, u0, u1;
    int spec;
    elr_ray rd;
    const elr_first *f0 = depth == 0 ? first : NULL;
    if (f0 ? !f0->hit : !elr_intersect(s, r.o, r.d, INFINITY, &h)) return elr_add(L, elr_vmul(beta, elr__env_le(s, r.d)));
    if (f0) h = *f0->h;
    if (f0) { tc = f0->tc; dpdx = f0->dpdx; dpdy = f0->dpdy; b = f0->b; } /* a hit's, made ahead */
    else {
      elr_compute_differentials(s, &r, &h, &tc, &dpdx, &dpdy);
      elr_bsdf_init(s, &h, &tc, &b);
    }
    wo = elr_mul(r.d, -1.f);
    if (C->light_sampling && (b.has_diffuse || b.has_glossy)) L = elr_add(L, elr_vmul(beta, elr__direct(C, S, &h, &b, wo, 1, ts, f0)));
    if (!(depth + 1 < C->maxdepth && b.has_specular)) break;
    /* <<SpecularReflect>> */
    { float u[2]; elr_sampler_get2d(S, u); u0 = u[0]; u1 = u[1]; }
    f = elr_bsdf_sample(&b, wo, u0, u1, &wi, &pdf, &spec);
    if (!(spec && pdf > 0.f && !elr_isblack(f) && elr_dot(wi, b.ns) != 0.f)) break;
    rd.o = elr_spawn_origin(&h, wi); rd.d = wi; rd.has_diff = 0;
    if (r.has_diff && s->any_textured) {
      /* <<Compute ray differential rd for specular reflection>> */
      elr_v3 ns = b.ns;
      elr_v3 dndx = elr_add(elr_mul(h.dndu, tc.dudx), elr_mul(h.dndv, tc.dvdx));
      elr_v3 dndy = elr_add(elr_mul(h.dndu, tc.dudy), elr_mul(h.dndv, tc.dvdy));
      elr_v3 dwodx = elr_sub(elr_mul(r.rxd, -1.f), wo), dwody = elr_sub(elr_mul(r.ryd, -1.f), wo);
      float dDNdx = elr_dot(dwodx, ns) + elr_dot(wo, dndx), dDNdy = elr_dot(dwody, ns) + elr_dot(wo, dndy);
      rd.has_diff = 1;
      rd.rxo = elr_add(rd.o, dpdx); rd.ryo = elr_add(rd.o, dpdy);
      rd.rxd = elr_add(elr_sub(wi, dwodx), elr_mul(elr_add(elr_mul(dndx, elr_dot(wo, ns)), elr_mul(ns, dDNdx)), 2.f));
      rd.ryd = elr_add(elr_sub(wi, dwody), elr_mul(elr_add(elr_mul(dndy, elr_dot(wo, ns)), elr_mul(ns, dDNdy)), 2.f));
    }
    ts->bounce++;
    beta = elr_mul(elr_vmul(beta, f), fabsf(elr_dot(wi, b.ns)) / pdf);
    r = rd;
  }
  return L;
}

static elr_v3 elr__li_path(const elr_ctx *C, elr_sampler *S, const elr_ray *r0, elr_tstats *ts, const elr_first *first) {
  const elr_scene *s = C->s;
  elr_v3 L = elr_v(0, 0, 0), beta = elr_v(1, 1, 1), o = r0->o, d = r0->d;
  int depth, specular = 0;
  float prev_pdf = 0.f;
  elr_ray r = *r0;
  for (depth = 0;; depth++) {
    elr_hit h;
    elr_bsdf b;
    elr_tex_ctx tc;
    elr_v3 wo, wi, f, dpdx, dpdy;
    float pdf, u0, u1;
    int spec;
    const elr_first *f0 = depth == 0 ? first : NULL;
    if (f0 ? !f0->hit : !elr_intersect(s, o, d, INFINITY, &h)) {
      /* escaped: the environment, MIS-weighted against light sampling after a non-specular bounce */
      int li;
      for (li = 0; li < s->nlight; li++) {
        const elr_light *l = &s->light[li];
        float w = 1.f;
        if (l->kind != ELR_LIGHT_INFINITE || !elr_light_emits(l)) continue;
        if (depth > 0 && !specular && C->light_sampling) {
          if (C->ls == ELR_LS_LIGHT) continue;
          if (C->ls == ELR_LS_MIS) w = elr__power(prev_pdf, elr_light_pdf_li(l, NULL, d));
        }
        L = elr_add(L, elr_mul(elr_vmul(beta, elr_light_le(l, d)), w));
      }
      break;
    }
    if (f0) h = *f0->h;
    if (depth >= C->maxdepth) break;
    if (depth == 0) elr_compute_differentials(s, &r, &h, &tc, &dpdx, &dpdy);
    else {
      /* pbrt-v3's path tracer spawns later rays without differentials: point-sampled textures */
      memset(&tc, 0, sizeof tc);
      if (s->mat_textured[h.material]) { elr_hit_uv(s, &h); tc.u = h.u; tc.v = h.v; }
    }
    elr_bsdf_init(s, &h, &tc, &b);
    wo = elr_mul(d, -1.f);
    if (C->light_sampling && (b.has_diffuse || b.has_glossy)) L = elr_add(L, elr_vmul(beta, elr__direct(C, S, &h, &b, wo, 0, ts, f0)));
    { float u[2]; elr_sampler_get2d(S, u); u0 = u[0]; u1 = u[1]; }
    f = elr_bsdf_sample(&b, wo, u0, u1, &wi, &pdf, &spec);
    if (elr_isblack(f) || pdf == 0.f) break;
    beta = elr_mul(elr_vmul(beta, f), fabsf(elr_dot(wi, b.ns)) / pdf);
    specular = spec; prev_pdf = pdf;
    /* the last vertex's continuation only matters for the environment's BSDF-sampled part */
    if (depth + 1 == C->maxdepth && (!C->has_env || (!spec && C->ls == ELR_LS_LIGHT && C->light_sampling))) break;
    o = elr_spawn_origin(&h, wi); d = wi;
    ts->bounce++;
    { /* <<Possibly terminate the path with Russian roulette>> (pbrt-v3: after bounce 3) */
      float mc = elr_maxc(beta);
      if (depth > 3 && mc < C->rr) {
        float q = fmaxf(0.05f, 1.f - mc);
        if (elr_sampler_get1d(S) < q) break;
        beta = elr_mul(beta, 1.f / (1.f - q));
      }
    }
  }
  return L;
}

/* One pixel's camera samples with their environment light samples drawn together: for up to 32
 * samples at a time, (1) the camera rays and their hits, each hit's light-sample numbers (the
 * sampler's draws in the order the shading makes them) and, for the direct-lighting integrator, its
 * BSDF and BSDF sample, whose environment texels and pdf bin are prefetched; (2) the light samples in
 * one elr_env_sample_n call, which overlaps their table and texel cache misses (one at a time, each
 * is a chain of dependent misses that the shading between them cannot hide); (3) the shading, which
 * takes all of these instead of computing them, with the sampler put back where sample k's film draw
 * left it. The sampler gives every (sample, dimension) the same number whichever order they are asked
 * in, so the image is bit for bit the one-at-a-time image (test_render_pipeline checks it). */
#define ELR_BATCH 32
static void elr__pixel_batched(const elr_ctx *C, elr_sampler *S, int x, int y, el_film_tile *tile, elr_tstats *ts) {
  elr_ray r[ELR_BATCH];
  elr_hit h[ELR_BATCH];
  elr_first f[ELR_BATCH];
  float fx[ELR_BATCH], fy[ELR_BATCH], u[2 * ELR_BATCH], wi[3 * ELR_BATCH], Le[3 * ELR_BATCH], pdf[ELR_BATCH];
  elr_sampler_pos pos[ELR_BATCH];
  float rgb[3];
  int idx[ELR_BATCH], k0, k, m, n;
  for (k0 = 0; k0 < C->spp; k0 += ELR_BATCH) {
    m = C->spp - k0 < ELR_BATCH ? C->spp - k0 : ELR_BATCH;
    n = 0;
    for (k = 0; k < m; k++) {
      elr_sampler_camera_sample(S, k0 + k, x, y, &fx[k], &fy[k]);
      elr_sampler_save(S, &pos[k]);
      elr_camera_ray(&C->cam, fx[k], fy[k], &r[k]);
      ts->camera++;
      f[k].h = &h[k];
      f[k].hit = elr_intersect(C->s, r[k].o, r[k].d, INFINITY, &h[k]);
      f[k].bs = f[k].bray = 0;
      idx[k] = -1;
      if (!f[k].hit) continue;
      elr_sampler_get2d(S, &u[2 * n]); /* the first light draw at the hit */
      idx[k] = n++;
      if (!C->path) {
        /* the direct-lighting integrator's shading up to the BSDF sample (its environment lookups come
         * in the pass below) */
        elr_first *q = &f[k];
        float us[2];
        elr_compute_differentials(C->s, &r[k], &h[k], &q->tc, &q->dpdx, &q->dpdy);
        elr_bsdf_init(C->s, &h[k], &q->tc, &q->b);
        elr_sampler_get2d(S, us); /* the BSDF draw that follows the light draw */
        if (C->ls != ELR_LS_LIGHT && (q->b.has_diffuse || q->b.has_glossy)) {
          int spec;
          q->fb = elr_bsdf_sample(&q->b, elr_mul(r[k].d, -1.f), us[0], us[1], &q->wb, &q->bpdf, &spec);
          q->bs = 1;
          q->bray = !spec && q->bpdf > 0.f && !elr_isblack(q->fb); /* elr__direct's bsdf_ray */
        }
      }
    }
    /* the environment's pdf and radiance in the BSDF samples' directions, for all of them in one pass
     * (pdf_li has no branch, so their cache misses overlap): used when the BSDF ray is not occluded */
    if (!C->path)
      for (k = 0; k < m; k++) {
        elr_first *q = &f[k];
        if (!q->bray) continue;
        float d[3], L3[3];
        elr_to3(q->wb, d);
        q->bpdf_env = el_envlight_pdf_li(C->batch_light->env_sample, d);
        el_envlight_le(C->batch_light->env, d, L3);
        q->Lb = elr_from3(L3);
      }
    el_envlight_sample_li_n(C->batch_light->env_sample, n, u, wi, Le, pdf);
    for (k = 0; k < m; k++) {
      elr_v3 L;
      if (idx[k] >= 0) {
        int j = idx[k];
        f[k].wi = elr_v(wi[3 * j], wi[3 * j + 1], wi[3 * j + 2]);
        f[k].L = elr_v(Le[3 * j], Le[3 * j + 1], Le[3 * j + 2]);
        f[k].pdf = pdf[j];
      }
      elr_sampler_restore(S, &pos[k]); /* the sampler back at sample k, after its film draw */
      L = C->path ? elr__li_path(C, S, &r[k], ts, &f[k]) : elr__li_direct(C, S, &r[k], ts, &f[k]);
      elr_to3(L, rgb);
      el_film_tile_add_sample(tile, fx[k], fy[k], rgb, 1.f);
      ts->samples++;
    }
  }
}

/* >> tiles and threads */
typedef struct elr_job {
  elr_ctx *C;
  el_film *film;
  const elr_render_options *o;
  int bx0, by0, bx1, by1, tile, ntx, nty, ntiles;
  pthread_mutex_t mu;
  int next_tile, next_merge, done;
  el_film_tile **ready; /* finished tiles waiting for their turn to merge */
  elr_tstats total;
  double t0, last_print;
  int failed;
  const elr_halton *H;
} elr_job;

static void elr__progress(elr_job *J, int final) {
  double now = elr_now(), el = now - J->t0, frac = (double)J->done / (double)J->ntiles, rem;
  int i, w = 40, fill = (int)(frac * w);
  char bar[64];
  if (J->o->quiet) return;
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
  memset(&ts, 0, sizeof ts);
  if (elr_sampler_init(&S, &C->sampler, J->o->seed, J->H) != 0) {
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
    tx = t % J->ntx; ty = t / J->ntx;
    x0 = J->bx0 + tx * J->tile; y0 = J->by0 + ty * J->tile;
    x1 = x0 + J->tile < J->bx1 ? x0 + J->tile : J->bx1;
    y1 = y0 + J->tile < J->by1 ? y0 + J->tile : J->by1;
    tile = (el_film_tile *)calloc(1, sizeof *tile);
    if (!tile || el_film_tile_init(J->film, tile, x0, y0, x1, y1) != EL_SUCCESS) {
      free(tile);
      pthread_mutex_lock(&J->mu); J->failed = 1; pthread_mutex_unlock(&J->mu);
      break;
    }
    for (y = y0; y < y1; y++)
      for (x = x0; x < x1; x++) {
        elr_sampler_start_pixel(&S, x, y);
        if (C->batch_light) elr__pixel_batched(C, &S, x, y, tile, &ts);
        else
          for (k = 0; k < C->spp; k++) {
            float fx, fy, rgb[3];
            elr_ray r;
            elr_v3 L;
            elr_sampler_camera_sample(&S, k, x, y, &fx, &fy);
            elr_camera_ray(&C->cam, fx, fy, &r);
            ts.camera++;
            L = C->path ? elr__li_path(C, &S, &r, &ts, NULL) : elr__li_direct(C, &S, &r, &ts, NULL);
            elr_to3(L, rgb);
            el_film_tile_add_sample(tile, fx, fy, rgb, 1.f);
            ts.samples++;
          }
      }
    pthread_mutex_lock(&J->mu);
    /* merge tiles in tile order, whatever order threads finish them: the same sums for any thread count */
    J->ready[t] = tile;
    while (J->next_merge < J->ntiles && J->ready[J->next_merge]) {
      elr__merge(J->film, J->ready[J->next_merge]);
      J->ready[J->next_merge] = NULL;
      J->next_merge++;
    }
    J->done++;
    elr__progress(J, 0);
    pthread_mutex_unlock(&J->mu);
  }
  pthread_mutex_lock(&J->mu);
  J->total.camera += ts.camera; J->total.bounce += ts.bounce; J->total.shadow += ts.shadow;
  J->total.bsdfl += ts.bsdfl; J->total.samples += ts.samples;
  pthread_mutex_unlock(&J->mu);
  elr_sampler_free(&S);
  return NULL;
}

void elr_render_options_default(elr_render_options *o) {
  memset(o, 0, sizeof *o);
  o->light_sampling = -1; o->compensated = -1; o->importance = -1;
}

static int elr__mat_nonspecular(const elr_scene *s) {
  int i;
  /* a material with a non-specular lobe, used by some shape */
  for (i = 0; i < s->nmesh; i++) if (s->mat[s->mesh[i].material].kind != ELR_MAT_MIRROR) return 1;
  for (i = 0; i < s->nsph; i++) if (s->mat[s->sph[i].material].kind != ELR_MAT_MIRROR) return 1;
  return 0;
}

int elr_render(elr_scene *s, const elr_render_options *o, elr_image *out, elr_stats *st, char *err, size_t errlen) {
  elr_ctx C;
  elr_job J;
  elr_halton H;
  el_film film;
  pthread_t *th = NULL;
  int i, nthreads, x0, y0, x1, y1, rc = -1, nonspec, env_sampled = 0, fb[4];
  double t_start = elr_now();
  memset(&C, 0, sizeof C); memset(&J, 0, sizeof J); memset(&H, 0, sizeof H); memset(&film, 0, sizeof film);
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
  if (!s->mat_textured) {
    s->mat_textured = (int *)calloc((size_t)s->nmat + 1, sizeof(int));
    if (!s->mat_textured) { snprintf(err, errlen, "out of memory"); goto done; }
    for (i = 0; i < s->nmat; i++) {
      const elr_material *m = &s->mat[i];
      int t[4], k;
      t[0] = m->kd; t[1] = m->ks; t[2] = m->kr; t[3] = m->rough;
      for (k = 0; k < 4; k++) if (t[k] >= 0 && s->tex[t[k]].kind != ELR_TEX_CONST) s->mat_textured[i] = 1;
      if (s->mat_textured[i]) s->any_textured = 1;
    }
  }
  elr_camera_init(&C.cam, &s->d, C.spp, s->any_textured);
  nonspec = elr__mat_nonspecular(s);
  {
    int emits = 0;
    for (i = 0; i < s->nlight; i++) if (elr_light_emits(&s->light[i])) emits = 1;
    for (i = 0; i < s->nlight; i++) if (elr_light_emits(&s->light[i]) && s->light[i].kind == ELR_LIGHT_INFINITE) C.has_env = 1;
    C.light_sampling = emits && nonspec;
    for (i = 0; i < s->nlight; i++) {
      elr_light *l = &s->light[i];
      if (l->kind == ELR_LIGHT_INFINITE && elr_light_emits(l) && C.light_sampling && C.ls != ELR_LS_BSDF) {
        double t0 = elr_now();
        if (elr_infinite_prepare(l, o->compensated, o->importance) != 0) { snprintf(err, errlen, "environment: cannot build the sampling distribution"); goto done; }
        if (st) { st->t_distribution += elr_now() - t0; st->bytes_distribution += el_envlight_sampling_bytes(l->env_sample); }
        env_sampled = 1;
      }
    }
    /* a pixel's light samples drawn together when the only emitting light is a sampled environment */
    /* (with the stratified sampler, only when its strata cover the three 2D draws made ahead: draws
     * past them come from the pixel's one random stream, whose order batching would change) */
    if (env_sampled && !o->no_batch && (C.sampler.kind != ELR_SAMPLER_STRATIFIED || C.sampler.dims >= 3)) {
      int nemit = 0;
      for (i = 0; i < s->nlight; i++) if (elr_light_emits(&s->light[i])) { nemit++; C.batch_light = &s->light[i]; }
      if (nemit != 1) C.batch_light = NULL;
    }
  }
  if (C.sampler.kind == ELR_SAMPLER_HALTON) {
    int b[4];
    el_film_sample_bounds(&film, b);
    if (elr_halton_init(&H, b[2] - b[0], b[3] - b[1], o->seed) != 0) { snprintf(err, errlen, "out of memory"); goto done; }
  }
  nthreads = o->nthreads > 0 ? o->nthreads : (int)sysconf(_SC_NPROCESSORS_ONLN);
  if (nthreads < 1) nthreads = 1;
  if (nthreads > 1024) nthreads = 1024;
  J.C = &C; J.film = &film; J.o = o; J.H = &H;
  {
    int b[4];
    el_film_sample_bounds(&film, b);
    J.bx0 = b[0]; J.by0 = b[1]; J.bx1 = b[2]; J.by1 = b[3];
  }
  J.tile = o->tile_size > 0 ? o->tile_size : 16;
  J.ntx = (J.bx1 - J.bx0 + J.tile - 1) / J.tile; J.nty = (J.by1 - J.by0 + J.tile - 1) / J.tile;
  J.ntiles = J.ntx * J.nty;
  J.ready = (el_film_tile **)calloc((size_t)J.ntiles, sizeof(el_film_tile *));
  th = (pthread_t *)calloc((size_t)nthreads, sizeof(pthread_t));
  if (!J.ready || !th) { snprintf(err, errlen, "out of memory"); goto done; }
  pthread_mutex_init(&J.mu, NULL);
  J.t0 = elr_now(); J.last_print = 0;
  {
    int started = 0;
    for (i = 0; i < nthreads; i++) {
      if (pthread_create(&th[i], NULL, elr__worker, &J) != 0) break;
      started++;
    }
    if (started == 0) elr__worker(&J);
    for (i = 0; i < started; i++) pthread_join(th[i], NULL);
  }
  pthread_mutex_destroy(&J.mu);
  if (J.failed || J.next_merge != J.ntiles) {
    for (i = 0; i < J.ntiles; i++) if (J.ready[i]) elr__merge(&film, J.ready[i]);
    snprintf(err, errlen, "rendering failed (out of memory for a film tile or sampler)");
    goto done;
  }
  elr__progress(&J, 1);
  out->width = x1 - x0; out->height = y1 - y0;
  out->rgb = (float *)malloc(sizeof(float) * 3 * (size_t)out->width * (size_t)out->height);
  if (!out->rgb) { snprintf(err, errlen, "out of memory"); goto done; }
  el_film_get_rgb(&film, 1.f, out->rgb);
  if (st) {
    st->t_parse = s->t_parse; st->t_images = s->t_images; st->t_embree = s->t_embree;
    st->t_render = elr_now() - J.t0;
    st->bytes_embree = s->bytes_embree; st->bytes_film = el_film_bytes(&film);
    st->bytes_splats = film.splats ? (size_t)film.width * (size_t)film.height * 3 * sizeof(double) : 0; st->splats_allocated = st->bytes_splats > 0;
    st->camera_rays = J.total.camera; st->bounce_rays = J.total.bounce; st->shadow_rays = J.total.shadow;
    st->bsdf_light_rays = J.total.bsdfl; st->samples = J.total.samples;
    st->distribution_built = env_sampled; st->light_sampling_used = C.light_sampling;
    st->light_samples_batched = C.batch_light != NULL;
    st->nthreads = nthreads; st->spp = C.spp; st->width = out->width; st->height = out->height;
    st->maxdepth = C.maxdepth; st->integrator_path = C.path; st->sampler = C.sampler.kind;
    st->rejected_samples = el_film_rejected_samples(&film);
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
        if (env_sampled) st->bytes_distribution = el_envlight_sampling_bytes(s->light[i].env_sample);
      }
  }
  rc = 0;
done:
  if (st) st->t_total = elr_now() - t_start + s->t_parse;
  free(J.ready); free(th); elr_halton_free(&H);
  el_film_free(&film);
  if (rc != 0) { free(out->rgb); out->rgb = NULL; out->width = out->height = 0; }
  return rc;
}
