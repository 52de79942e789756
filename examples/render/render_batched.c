/* render_batched.c: a pixel's environment light samples drawn together (el_envlight_sample_li_n).
 *
 * The same computation as the one-sample-at-a-time loop of render.c with integrator_direct.c and
 * integrator_path.c, in another order, for the scenes where the environment is the only light that
 * emits and is sampled, by its map alone (elr_render decides: elr_ctx.batch_light; product sampling,
 * el_envlight_sample_li_cos, has no n-at-once form and needs each vertex's normal, which the path
 * tracer's first vertex knows only after this file's first phase, so it runs in the wave loop,
 * render_wave.c, or one sample at a time). One environment light sample on its
 * own is a chain of dependent cache misses (guide entry, CDF row, texels) that the shading between
 * two samples cannot hide; el_envlight_sample_li_n overlaps the misses of many. So for up to 32 camera
 * samples of a pixel at a time:
 *   1. the camera rays and their hits, each hit's first light-sample numbers (the sampler's draws in
 *      the order the shading will make them) and, for the direct-lighting integrator, the hit's BSDF
 *      and BSDF sample;
 *   2. the environment's pdf and radiance in those BSDF directions, in one pass (pdf_li has no branch,
 *      so their misses overlap too), and the light samples in one el_envlight_sample_li_n call;
 *   3. the shading of each camera sample's first vertex with all of these instead of computing them,
 *      the sampler put back where the sample's film draw left it; the rest of the path is the
 *      reference integrator's (elr_direct_li, elr_path_li from the second vertex on).
 * The sampler gives every (sample, dimension) the same number whichever order they are asked in, and
 * the first-vertex shading below is the reference's with its sums in the same order, so the image is
 * bit for bit the one-at-a-time image (test_render_pipeline compares them for every sampler and both
 * integrators). A change to EstimateDirect or to either integrator's first vertex must be made here
 * too; the wave loop (render_wave.c) computes the same first vertex for a whole wave of samples and is
 * the default where both apply, except for the path tracer with a pixel sampler (render.c). */
#include "elr_internal.h"

#define ELR_BATCH 32

/* elr_estimate_direct for the environment's first sample at a first vertex (hit h, BSDF b), with the
 * light sample and the BSDF sample (and the environment's pdf and radiance in its direction) drawn
 * ahead in f */
static void elr__estimate_direct_ahead(const elr_ctx *C, const elr_hit *h, const elr_bsdf *b, elr_v3 wo, const elr_first *f,
                                       int sample_bsdf, elr_tstats *ts, elr_v3 *Ld) {
  const elr_scene *s = C->s;
  elr_v3 nc;
  /* issue 20: the product light sample alone where the lobes are diffuse or broad (as elr_estimate_direct) */
  /* (the normal as the light sample's: at a lowered sun-cache cell, sun.c's) */
  const elr_sun_cell *sc = C->sun ? elr_sun_lookup(C->sun, h, wo) : NULL;
  int lonly = !sc && C->ls == ELR_LS_MIS && elr_env_light_only(1, sample_bsdf, C->batch_light, elr_sun_cos_normal(s, sc, b, wo, &nc), b);
  /* <<Sample light source with multiple importance sampling>> */
  if (C->ls != ELR_LS_BSDF && f->pdf > 0.f) {
    elr_v3 fl = elr_mul(elr_bsdf_f(b, wo, f->wi), fabsf(elr_dot(f->wi, b->ns)));
    if (!elr_isblack(fl)) {
      ts->shadow++;
      if (!(f->occ_l >= 0 ? f->occ_l : elr_occluded(s, elr_spawn_origin(h, f->wi), f->wi, INFINITY))) {
        float w = 1.f;
        if (C->ls == ELR_LS_MIS && !lonly) w = elr_power_heuristic(f->pdf, elr_bsdf_pdf(b, wo, f->wi));
        *Ld = elr_add(*Ld, elr_mul(elr_vmul(fl, f->L), w / f->pdf));
      }
    }
  }
  /* <<Sample BSDF with multiple importance sampling>> (f->bray: the conditions of elr_estimate_direct) */
  if (sample_bsdf && f->bray) {
    elr_v3 fb = elr_mul(f->fb, fabsf(elr_dot(f->wb, b->ns)));
    ts->bsdfl++;
    if (!(f->occ_b >= 0 ? f->occ_b : elr_occluded(s, elr_spawn_origin(h, f->wb), f->wb, INFINITY))) {
      float w = C->ls == ELR_LS_MIS ? elr_power_heuristic(f->bpdf, f->bpdf_env) : 1.f;
      *Ld = elr_add(*Ld, elr_mul(elr_vmul(fb, f->Lb), w / f->bpdf));
    }
  }
}

/* elr_uniform_sample_all_lights at a first vertex: the environment is the only light that emits (the
 * others contribute nothing), and its first sample was drawn ahead. */
static elr_v3 elr__sample_lights_ahead(const elr_ctx *C, elr_sampler *S, const elr_hit *h, const elr_bsdf *b, elr_v3 wo,
                                       const elr_first *f, int use_counts, int sample_bsdf, elr_tstats *ts) {
  const elr_light *l = C->batch_light;
  int n = use_counts ? l->nsamples : 1, k;
  elr_v3 L = elr_v(0, 0, 0), Ld = elr_v(0, 0, 0);
  float ul[2], us[2];
  elr_sampler_skip2d(S);                                  /* the light draw, made ahead */
  if (f->bs) elr_sampler_skip2d(S); else elr_sampler_get2d(S, us); /* the BSDF draw (made ahead with its sample) */
  elr__estimate_direct_ahead(C, h, b, wo, f, sample_bsdf, ts, &Ld);
  for (k = 1; k < n; k++) { /* the light's further samples: drawn ahead too (the wave loop's splitting), or as the
                              * reference draws them */
    if (k - 1 < f->nmore) {
      const elr_first *q = &f->more[k - 1];
      elr_sampler_skip2d(S);
      if (q->bs) elr_sampler_skip2d(S); else elr_sampler_get2d(S, us);
      elr__estimate_direct_ahead(C, h, b, wo, q, sample_bsdf, ts, &Ld);
      continue;
    }
    elr_sampler_get2d(S, ul);
    elr_sampler_get2d(S, us);
    elr_estimate_direct(C, h, b, wo, l, ul, us, sample_bsdf, 1.f, ts, &Ld);
  }
  return elr_add(L, elr_mul(Ld, 1.f / (float)n));
}

/* elr_direct_li's first iteration with the vertex computed ahead, then the reference from the second
 * (also the wave loop's, render_wave.c, with the shadow rays' answers in f) */
elr_v3 elr_direct_first(const elr_ctx *C, elr_sampler *S, const elr_ray *r, const elr_first *f, elr_tstats *ts) {
  elr_path_state p;
  elr_v3 wo;
  elr_path_begin(&p, r);
  if (!f->hit) return elr_add(p.L, elr_vmul(p.beta, elr_infinite_le(C->s, r->d)));
  wo = elr_mul(r->d, -1.f);
  if (f->h->light >= 0) p.L = elr_add(p.L, elr_vmul(p.beta, elr_hit_le(C->s, f->h, wo)));
  if (C->light_sampling && (f->b.has_diffuse || f->b.has_glossy)) /* (strategy "one" with one light: "all" with 1 sample) */
    p.L = elr_add(p.L, elr_vmul(p.beta, elr__sample_lights_ahead(C, S, f->h, &f->b, wo, f, !C->direct_one, 1, ts)));
  if (1 < C->maxdepth && (f->b.spec_r || f->b.spec_t)) {
    elr_path_state next[2];
    int n = elr_direct_specular(C, S, r, f->h, &f->tc, f->dpdx, f->dpdy, &f->b, p.beta, 0, 1, next, ts);
    /* the reference's state after its first vertex: the first branch followed, the second waiting */
    if (n >= 1) { next[0].L = p.L; return elr_direct_li_branches(C, S, &next[0], &next[1], n - 1, n - 1, ts); }
  }
  return p.L;
}

/* elr_path_li's first iteration with the hit and its light sample computed ahead, then the reference
 * from the second vertex */
static elr_v3 elr__path_first(const elr_ctx *C, elr_sampler *S, const elr_ray *r, const elr_first *f, elr_tstats *ts) {
  const elr_scene *s = C->s;
  elr_path_state p;
  elr_bsdf b;
  elr_tex_ctx tc;
  elr_v3 wo, wi, fs, dpdx, dpdy;
  float pdf, u[2];
  int spec;
  elr_path_begin(&p, r);
  /* escaped at the camera: the environment, unweighted (the only infinite light that emits) */
  if (!f->hit) return elr_add(p.L, elr_vmul(p.beta, elr_light_le(C->batch_light, r->d)));
  if (f->h->light >= 0) p.L = elr_add(p.L, elr_vmul(p.beta, elr_hit_le(s, f->h, elr_mul(r->d, -1.f))));
  if (C->maxdepth <= 0) return p.L;
  elr_compute_differentials(s, r, f->h, &tc, &dpdx, &dpdy);
  elr_bsdf_init(s, f->h, &tc, &b);
  wo = elr_mul(r->d, -1.f);
  if (C->light_sampling && (b.has_diffuse || b.has_glossy))
    p.L = elr_add(p.L, elr_vmul(p.beta, elr__sample_lights_ahead(C, S, f->h, &b, wo, f, 0, 0, ts)));
  elr_sampler_get2d(S, u);
  fs = elr_bsdf_sample(&b, wo, u[0], u[1], &wi, &pdf, &spec);
  if (elr_isblack(fs) || pdf == 0.f) return p.L;
  p.beta = elr_mul(elr_vmul(p.beta, fs), fabsf(elr_dot(wi, b.ns)) / pdf);
  p.specular = spec; p.prev_pdf = pdf;
  p.prev_has_n = elr_bsdf_cos_normal(&b, wo, &p.prev_n); /* (as elr_path_li; batching runs with map sampling) */
  if (spec == 2) p.eta_scale = elr_eta_scale(p.eta_scale, &b, wo);
  if (1 == C->maxdepth && (!(C->has_env || C->has_area) || (!spec && C->ls == ELR_LS_LIGHT && C->light_sampling))) return p.L;
  p.ray.o = elr_spawn_origin(f->h, wi); p.ray.d = wi; p.ray.has_diff = 0;
  ts->bounce++; /* (Russian roulette starts after bounce 3) */
  p.depth = 1;
  return elr_path_li(C, S, &p, ts);
}

/* Pixel (x, y)'s C->spp camera samples into tile (the sampler started at the pixel). */
void elr_pixel_batched(const elr_ctx *C, elr_sampler *S, int x, int y, el_film_tile *tile, elr_tstats *ts) {
  const el_envlight *env = C->batch_light->env;
  const el_envlight *env_sample = C->batch_light->env_sample;
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
    /* 1. camera rays, hits, the draws at the hits */
    for (k = 0; k < m; k++) {
      elr_sampler_camera_sample(S, k0 + k, x, y, &fx[k], &fy[k]);
      elr_sampler_save(S, &pos[k]);
      elr_camera_ray(&C->cam, fx[k], fy[k], &r[k]);
      ts->camera++;
      f[k].h = &h[k];
      f[k].hit = elr_intersect(C->s, r[k].o, r[k].d, INFINITY, &h[k]);
      f[k].bs = f[k].bray = 0;
      f[k].occ_l = f[k].occ_b = -1; /* the shadow rays traced in the shading */
      f[k].more = NULL; f[k].nmore = 0;
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
          q->bray = !spec && q->bpdf > 0.f && !elr_isblack(q->fb); /* elr_estimate_direct's BSDF ray */
        }
      }
    }
    /* 2. the environment's pdf and radiance in the BSDF samples' directions (used when the BSDF ray
     * is not occluded), then the light samples */
    if (!C->path)
      for (k = 0; k < m; k++) {
        elr_first *q = &f[k];
        float d[3], L3[3];
        if (!q->bray) continue;
        elr_to3(q->wb, d);
        q->bpdf_env = el_envlight_pdf_li(env_sample, d);
        el_envlight_le(env, d, L3);
        q->Lb = elr_from3(L3);
      }
    el_envlight_sample_li_n(env_sample, n, u, wi, Le, pdf);
    /* 3. the shading */
    for (k = 0; k < m; k++) {
      elr_v3 L;
      if (idx[k] >= 0) {
        int j = idx[k];
        f[k].wi = elr_from3(&wi[3 * j]);
        f[k].L = elr_from3(&Le[3 * j]);
        f[k].pdf = pdf[j];
      }
      elr_sampler_restore(S, &pos[k]); /* the sampler back at sample k, after its film draw */
      L = C->path ? elr__path_first(C, S, &r[k], &f[k], ts) : elr_direct_first(C, S, &r[k], &f[k], ts);
      elr_to3(L, rgb);
      el_film_tile_add_sample(tile, fx[k], fy[k], rgb, 1.f);
      ts->samples++;
    }
  }
}
