/* render_wave.c: the wave loop. A tile's camera samples go through the integrator a wave at a time,
 * each stage for the whole wave before the next: the wave's rays in one Embree call (packets of 16 or
 * streams: scene.c's elr_wave_intersect / elr_wave_occluded), its environment light samples in one
 * el_envlight_sample_li_n call, its environment lookups in one pass, so that their cache misses overlap.
 * With product sampling (the default: a normal per sample) in one el_envlight_sample_li_cos_n call
 * (elr__env_samples).
 * pbrt-v3 has no such loop; the model is pbrt-v4's WavefrontPathIntegrator (src/pbrt/wavefront/
 * integrator.cpp, surfscatter.cpp), whose stages each run over a queue of many paths (over the whole
 * image, on the GPU or the CPU): here over a tile's wave on one thread, with Embree's packets.
 *
 * The same computation as the one-sample-at-a-time loop of render.c (integrator_direct.c,
 * integrator_path.c), in another order, for the scenes where the environment is the only light
 * that emits, and it is sampled (elr_render decides: elr_ctx.batch_light,
 * elr_ctx.loop). A wave is up to ELR_WAVE camera samples of consecutive pixels of the tile (each pixel's
 * samples together, one sampler per pixel: the sampler gives every (pixel, sample, dimension) its
 * number whichever order they are asked in).
 *
 * Direct lighting: the first vertex computed ahead (elr_first), with the
 *   wave's camera rays, light samples and shadow rays (light and BSDF sampled) each in one call; then
 *   its shading in the wave (elr__direct_shade) where no specular bounce follows and it emits nothing
 *   (in structure-of-arrays form, elr__soa_*, where its BSDF is a lone Lambertian lobe; an escaped camera
 *   ray's radiance in one el_envlight_le_n call),
 *   else elr_direct_first, with the shadow rays' answers, and the reference integrator from the second
 *   vertex (specular reflection and transmission, a light's further "samples"). The wave's radiance
 *   goes to the film in one el_film_tile_add_samples call.
 * Path: every vertex is a wave. For the paths still alive: their rays in one call; at each hit the
 *   BSDF, the light-sample and BSDF draws; the light samples in one el_envlight_sample_li_n call and
 *   the escaped rays' environment (pdf and radiance) in el_envlight_pdf_li_n (pdf_li_cos_n with product
 *   sampling) and el_envlight_le_n calls, as in direct lighting; the shadow rays in one call; then
 *   each path's radiance, throughput and Russian roulette as elr_path_li computes them.
 * Each sample's sums are made in the reference's order, and the film takes the samples in the
 * reference's order, so the image is bit for bit the one-at-a-time image where the sampler gives the
 * same numbers in any order: every sampler for the direct-lighting first vertex (render.c asks for
 * elr_sampler_order_free); for the path tracer's later vertices, the pixel samplers (stratified,
 * 02sequence) draw past their dimensions from the pixel's one stream, which the wave reaches in another
 * order: other numbers of the same distribution (test_render_wave checks both). A change to
 * EstimateDirect or to elr_path_li must be made here too (test_render_wave fails until it is). */
#include "elr_internal.h"
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#ifndef ELR_WAVE
#define ELR_WAVE 256 /* camera samples in a wave at most */
#endif
#if ELR_WAVE % 8 != 0
#error "ELR_WAVE must be a multiple of 8 (ELR_SOA_PAD)"
#endif

/* >> a first vertex computed ahead (elr_first): its shading in the reference's order (moved here from
 * render_batched.c, the batched loop, when the wave loop replaced it) */
/* ELR_ENVSD_TWO(_PIXEL): Ld plus one of the two product light samples' terms weighted 1/2, as elr_estimate_direct
 * sums it (elr__light_term without MIS into its own sum); fl its BSDF value times the cosine (read where pdf > 0),
 * occ its shadow ray's answer (-1: traced here) */
static elr_v3 elr__two_term(const elr_ctx *C, const elr_hit *h, elr_v3 Ld, elr_v3 fl, elr_v3 wi, elr_v3 L, float pdf, int occ, elr_tstats *ts) {
  elr_v3 Lt = elr_v(0, 0, 0);
  if (pdf > 0.f && !elr_isblack(fl)) {
    ts->shadow++;
    if (!(occ >= 0 ? occ : elr_occluded(C->s, elr_spawn_origin(h, wi), wi, INFINITY))) Lt = elr_add(Lt, elr_mul(elr_vmul(fl, L), 1.f / pdf));
  }
  return elr_add(Ld, elr_mul(Lt, 0.5f));
}

/* --sun split (sun.c): the spot and sky samples' terms drawn ahead in f, as elr_estimate_direct's split branch
 * sums them (their shadow rays' answers in f: the wave's) */
static void elr__split_terms(const elr_ctx *C, const elr_hit *h, const elr_bsdf *b, elr_v3 wo, const elr_first *f, elr_tstats *ts, elr_v3 *Ld) {
  int k;
  for (k = 2 - f->split; k < 2; k++)
    elr_light_term(C, h, b, wo, &f->ssl[k], C->ls == ELR_LS_MIS, 1.f, f->sother[k], k ? f->occ_l2 : f->occ_l, ts, Ld);
}

/* elr_estimate_direct for the environment's first sample at a first vertex (hit h, BSDF b), with the
 * light sample and the BSDF sample (and the environment's pdf and radiance in its direction) drawn
 * ahead in f */
static void elr__estimate_direct_ahead(const elr_ctx *C, const elr_hit *h, const elr_bsdf *b, elr_v3 wo, const elr_first *f,
                                       int sample_bsdf, elr_tstats *ts, elr_v3 *Ld) {
  const elr_scene *s = C->s;
  elr_v3 nc;
  /* issue 20: the product light sample alone where the lobes are diffuse or broad (as elr_estimate_direct) */
  /* (the normal as the light sample's: at a lowered sun-cache cell, sun.c's) */
  const elr_sun_cell *sc = f->sun; /* (elr_sun_lookup's, made by the wave loop) */
  int lonly = !sc && C->ls == ELR_LS_MIS && elr_env_light_only(1, sample_bsdf, C->batch_light, elr_sun_cos_normal(s, sc, b, wo, &nc), b);
  if (f->two) { /* (two product light samples, no BSDF sample) */
    elr_v3 fl = elr_v(0, 0, 0);
    if (f->pdf > 0.f) fl = elr_mul(elr_bsdf_f(b, wo, f->wi), fabsf(elr_dot(f->wi, b->ns)));
    *Ld = elr__two_term(C, h, *Ld, fl, f->wi, f->L, f->pdf, f->occ_l, ts);
    if (f->pdf2 > 0.f) fl = elr_mul(elr_bsdf_f(b, wo, f->wi2), fabsf(elr_dot(f->wi2, b->ns)));
    *Ld = elr__two_term(C, h, *Ld, fl, f->wi2, f->L2, f->pdf2, f->occ_l2, ts);
    return;
  }
  if (f->split) elr__split_terms(C, h, b, wo, f, ts, Ld); /* (then the BSDF sample's term; f->pdf 0) */
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
 * (the wave loop's direct lighting, with the shadow rays' answers in f) */
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

/* the wave's Embree calls, timed (a few calls per wave: the clock costs nothing next to them) */
static void elr__intersect(const elr_ctx *C, elr_wave_rays *w, int coherent, elr_tstats *ts) {
  double t0 = elr_now();
  elr_wave_intersect(C->s, w, C->wave_api, coherent);
  ts->t_embree += elr_now() - t0;
}
static void elr__occluded(const elr_ctx *C, elr_wave_rays *w, elr_tstats *ts) {
  double t0 = elr_now();
  elr_wave_occluded(C->s, w, C->wave_api, 0);
  ts->t_embree += elr_now() - t0;
}

/* The first vertex of direct lighting where the BSDF is a lone Lambertian lobe (matte of sigma 0, constant
 * Kd), one lane per camera sample (issue 21): elr__direct_soa's arrays, one float (or flag) per lane, so
 * that each stage is a loop over plain arrays that gcc and clang vectorise (SSE2 at -O3). */
typedef struct elr_wave_soa {
  int n, nsh, nb, lane[ELR_WAVE]; /* lanes in use (their light and BSDF shadow rays, --stats); each one's camera sample (index in the wave) */
  /* the hit (point, geometric and shading normal, ray offset), wo, the material (Kd, issue 20's flags) */
  float px[ELR_WAVE], py[ELR_WAVE], pz[ELR_WAVE], gx[ELR_WAVE], gy[ELR_WAVE], gz[ELR_WAVE];
  float nx[ELR_WAVE], ny[ELR_WAVE], nz[ELR_WAVE], eps[ELR_WAVE], ox[ELR_WAVE], oy[ELR_WAVE], oz[ELR_WAVE];
  float kr[ELR_WAVE], kg[ELR_WAVE], kb[ELR_WAVE];
  int elo[ELR_WAVE], emap[ELR_WAVE], stest[ELR_WAVE]; /* env_light_only, env_map, env_sun_test */
  float sax[ELR_WAVE], say[ELR_WAVE], saz[ELR_WAVE], scos[ELR_WAVE]; /* env_sun_axis, env_sun_cos */
  float ul[2 * ELR_WAVE], v0[ELR_WAVE], v1[ELR_WAVE]; /* the light draw (pairs, as envlight.h takes them), the BSDF draw */
  /* the product-sampling normal (has_n), lonly; the BSDF sample: direction, f, pdf (whether it traces a ray: elr__soa_shadows) */
  int has_n[ELR_WAVE], lonly[ELR_WAVE];
  float cx[ELR_WAVE], cy[ELR_WAVE], cz[ELR_WAVE], th[ELR_WAVE], r[ELR_WAVE], c[ELR_WAVE], s[ELR_WAVE];
  float wbx[ELR_WAVE], wby[ELR_WAVE], wbz[ELR_WAVE], fbr[ELR_WAVE], fbg[ELR_WAVE], fbb[ELR_WAVE], bpdf[ELR_WAVE];
  /* the light sample (as envlight.h returns it), its f |cos| and BSDF pdf; the shadow rays (index in W->shadows or -1) */
  float wl[3 * ELR_WAVE], Ll[3 * ELR_WAVE], lpdf[ELR_WAVE];
  float wlx[ELR_WAVE], wly[ELR_WAVE], wlz[ELR_WAVE], llr[ELR_WAVE], llg[ELR_WAVE], llb[ELR_WAVE]; /* (the same, by component) */
  float flr[ELR_WAVE], flg[ELR_WAVE], flb[ELR_WAVE], flpdf[ELR_WAVE], dlg[ELR_WAVE], dbg[ELR_WAVE];
  int sh[ELR_WAVE], bsh[ELR_WAVE];
  /* the environment in the BSDF sample's direction (where its ray escaped) */
  float bpe[ELR_WAVE], lbr[ELR_WAVE], lbg[ELR_WAVE], lbb[ELR_WAVE];
  /* ELR_ENVSD_TWO(_PIXEL): the material's and pixel's choice (etwo), the lane's (two: elr_env_two), and the second
   * product light sample (from the BSDF draw v0, v1) as the first's arrays above */
  int etwo[ELR_WAVE], two[ELR_WAVE], sh2[ELR_WAVE];
  float wl2[3 * ELR_WAVE], Ll2[3 * ELR_WAVE], lpdf2[ELR_WAVE];
  float wlx2[ELR_WAVE], wly2[ELR_WAVE], wlz2[ELR_WAVE], llr2[ELR_WAVE], llg2[ELR_WAVE], llb2[ELR_WAVE];
  float flr2[ELR_WAVE], flg2[ELR_WAVE], flb2[ELR_WAVE], flpdf2[ELR_WAVE], dlg2[ELR_WAVE];
  int tk[ELR_WAVE]; /* the template whose fields (kr ... scos) lane i holds, from an earlier wave too; -1: none */
} elr_wave_soa;

struct elr_wave {
  elr_sampler *S; /* one per pixel of a wave */
  int nS, npix;   /* samplers made, pixels per wave */
  /* per camera sample of the wave */
  int pix[ELR_WAVE];
  float fx[ELR_WAVE], fy[ELR_WAVE];
  elr_sampler_pos pos[ELR_WAVE];
  elr_ray cam[ELR_WAVE];
  elr_hit h[ELR_WAVE];
  elr_first f[ELR_WAVE]; /* direct lighting */
  int npair, cap;        /* the light sample pairs drawn ahead per camera sample; camera samples per wave (ELR_WAVE / npair) */
  elr_first more[ELR_WAVE]; /* the further pairs of each camera sample (elr_first.more) */
  elr_first *pair[ELR_WAVE];
  int pair_of[ELR_WAVE];
  /* the first vertex shaded here (elr__direct_shade), per pair: its light sample's BSDF value times the
   * cosine and its lonly; per camera sample: shaded here (1) or by elr_direct_first (0), and its Ld */
  elr_v3 fl[ELR_WAVE];
  float flpdf[ELR_WAVE]; /* and the BSDF's pdf in its direction (computed with fl: the dot products they share) */
  int lonly[ELR_WAVE], fast[ELR_WAVE]; /* (fast 2: the camera ray left the scene; Ld its radiance) */
  /* ELR_ENVSD_TWO(_PIXEL): per pair, its second light sample's index in W->u (or -1), BSDF value times the
   * cosine and shadow ray; per pixel of the wave, its choice (ELR_ENVSD_TWO_PIXEL: elr_two_pixel) */
  int light2[ELR_WAVE], shadow2[ELR_WAVE], two_pix[ELR_WAVE];
  elr_v3 fl2[ELR_WAVE];
  elr_v3 Ld[ELR_WAVE];
  float rgb[3 * ELR_WAVE]; /* each camera sample's radiance, to the film in one call */
  /* path: each path's state, and at its vertex the BSDF, the light sample and the BSDF sample */
  elr_path_state p[ELR_WAVE];
  int alive[ELR_WAVE], ray[ELR_WAVE], light[ELR_WAVE], shadow[ELR_WAVE], escaped[ELR_WAVE], bshadow[ELR_WAVE];
  elr_bsdf b[ELR_WAVE];
  int bt[ELR_WAVE]; /* 1 + the template (W->tmpl) whose fields b holds, or 0: elr__bsdf_init copies them again only when it changes */
  elr_v3 fs[ELR_WAVE], wnext[ELR_WAVE], contrib[ELR_WAVE];
  float pdfs[ELR_WAVE];
  int spec[ELR_WAVE];
  /* the environment sampled (u in, directions, radiance, pdf out) and looked up */
  float u[2 * ELR_WAVE], wi[3 * ELR_WAVE], Le[3 * ELR_WAVE], pdf[ELR_WAVE];
  elr_v3 normal[ELR_WAVE]; /* product sampling: each light sample's normal (elr_bsdf_cos_normal), */
  int has_n[ELR_WAVE];     /* or 0: the map alone */
  const elr_sun_cell *sc[ELR_WAVE];  /* sun.c: each light sample's sun-cache cell (NULL: the light's own density) */
  const elr_sun_cell *vsc[ELR_WAVE]; /* and each camera sample's vertex's */
  elr_v3 lpos[ELR_WAVE];   /* portals (issue 23): each light sample's point, */
  elr_v3 prevp[ELR_WAVE];  /* and each path's last vertex (its escaped ray's pdf is taken there) */
  /* --sun split, the path tracer: per path, its vertex's split (elr_first.split), spot and sky samples (2 j + k), the
   * other light technique's densities there and their shadow rays; the split of the vertex its ray left (prevsplit:
   * elr_path_li's prev_split, the escaped ray's MIS weight) */
  int psplit[ELR_WAVE], prevsplit[ELR_WAVE], psh[2 * ELR_WAVE];
  int ptwo[ELR_WAVE]; /* ELR_ENVSD_TWO(_PIXEL), the path tracer: its vertex's elr_path_two (two product light samples there) */
  elr_light_sample pssl[2 * ELR_WAVE];
  float psother[2 * ELR_WAVE];
  elr_wave_rays rays, shadows;
  /* per material, the BSDF it has at every hit but for the frame (elr_bsdf_constant), or -1: its index in tmpl */
  int *tmpl_of;
  elr_bsdf *tmpl;
  unsigned char *tmpl_lambert; /* per template: a lone Lambertian lobe (elr__soa_lambert_ok), shaded in A */
  elr_wave_soa A; /* direct lighting: the first vertices of such lanes, structure of arrays (elr__direct_soa) */
};

/* elr_sun_cos_normal with its first case inline (no lowered cell, or a BSDF whose choice the cell does not
 * change: elr_bsdf_cos_normal, inline in elr_internal.h); sun.c's test, repeated: keep the two alike */
static inline int elr__cos_normal(const elr_scene *s, const elr_sun_cell *c, const elr_bsdf *b, elr_v3 wo, elr_v3 *n) {
  return !c || !(b->env_map || b->env_sun_test) ? elr_bsdf_cos_normal(b, wo, n) : elr_sun_cos_normal(s, c, b, wo, n);
}

/* elr_bsdf_init for the wave: from the material's constant BSDF where it has one (a copy of the fields
 * elr_bsdf_init writes, then the frame elr_bsdf_init makes: the same BSDF), else elr_bsdf_init. held (or NULL):
 * 1 + the template whose fields b holds already (0: none), so that they are copied only when it changes */
static inline void elr__bsdf_init(const elr_scene *s, const elr_wave *W, const elr_hit *h, const elr_tex_ctx *tc, elr_bsdf *b, int *held) {
  int t = W->tmpl_of[h->material];
  const elr_bsdf *c;
  if (t < 0) { elr_bsdf_init(s, h, tc, b); if (held) *held = 0; return; }
  c = &W->tmpl[t];
  if (!held || *held != t + 1) {
    memcpy(b, c, offsetof(elr_bsdf, lobe)); /* (a size the compiler knows: moves, no call) */
    if (c->nlobes) memcpy(b->lobe, c->lobe, (size_t)c->nlobes * sizeof(elr_bxdf));
    if (held) *held = t + 1;
  }
  b->ns = h->ns; b->ng = h->ng;
  elr_onb(b->ns, &b->ss, &b->ts);
}

/* a material's constant BSDF that elr__direct_soa shades: a lone Lambertian lobe (elr_bsdf_lambert_alone's
 * case, nothing specular or glossy; issue 20's choice made per material: env_map, env_sun_test) */
static int elr__soa_lambert_ok(const elr_bsdf *t) {
  return t->has_diffuse && !t->has_glossy && !t->has_specular && t->ncomp == 1 && !t->nlobes && !t->spec_r && !t->spec_t && !t->env_mirror;
}

elr_wave *elr_wave_new(const elr_ctx *C, const elr_sampler_tables *T, uint64_t seed, int tile) {
  elr_wave *W = (elr_wave *)calloc(1, sizeof *W);
  int i, k, npix, two;
  if (!W) return NULL;
  /* direct lighting, strategy "all": the light's sample pairs drawn ahead with the first, up to ELR_WAVE */
  W->npair = !C->path && !C->direct_one ? C->batch_light->nsamples : 1;
  /* (ELR_ENVSD_TWO(_PIXEL): up to two light samples a pair, in the wave's arrays of ELR_WAVE) */
  two = C->s->env_sunny && (C->s->env_sun_diffuse == ELR_ENVSD_TWO || C->s->env_sun_diffuse == ELR_ENVSD_TWO_PIXEL); /* (the path tracer too) */
  two |= !C->path && C->sunsplit; /* (--sun split: a spot and a sky sample, and the BSDF sample: three shadow rays a pair) */
  if (W->npair > ELR_WAVE / (1 + two)) W->npair = ELR_WAVE / (1 + two);
  W->cap = ELR_WAVE / ((1 + two) * W->npair);
  npix = C->spp >= W->cap ? 1 : W->cap / C->spp;
  if (npix > tile * tile) npix = tile * tile;
  W->S = (elr_sampler *)calloc((size_t)npix, sizeof(elr_sampler));
  if (!W->S) { free(W); return NULL; }
  for (i = 0; i < npix; i++) {
    if (elr_sampler_init(&W->S[i], &C->sampler, seed, T) != 0) { elr_wave_free(W); return NULL; }
    W->nS++;
    elr_sampler_share(&W->S[i], &W->S[0]); /* (zsobol: the wave's neighbouring pixels share their digits) */
  }
  W->npix = npix;
  elr_wave_rays_init(&W->rays); elr_wave_rays_init(&W->shadows);
  /* the materials' constant BSDFs (counted first: memory for those alone) */
  W->tmpl_of = (int *)malloc(((size_t)C->s->nmat + 1) * sizeof(int));
  if (!W->tmpl_of) { elr_wave_free(W); return NULL; }
  for (i = 0, k = 0; i < C->s->nmat; i++) {
    elr_bsdf t;
    W->tmpl_of[i] = elr_bsdf_constant(C->s, i, &t) ? k++ : -1;
  }
  W->tmpl = (elr_bsdf *)malloc(((size_t)k + 1) * sizeof(elr_bsdf));
  if (!W->tmpl) { elr_wave_free(W); return NULL; }
  for (i = 0; i < C->s->nmat; i++) if (W->tmpl_of[i] >= 0) elr_bsdf_constant(C->s, i, &W->tmpl[W->tmpl_of[i]]);
  W->tmpl_lambert = (unsigned char *)calloc((size_t)k + 1, 1);
  if (!W->tmpl_lambert) { elr_wave_free(W); return NULL; }
  for (i = 0; i < k; i++) W->tmpl_lambert[i] = (unsigned char)elr__soa_lambert_ok(&W->tmpl[i]);
  for (i = 0; i < ELR_WAVE; i++) W->A.tk[i] = -1;
  return W;
}

void elr_wave_free(elr_wave *W) {
  int i;
  if (!W) return;
  for (i = 0; i < W->nS; i++) elr_sampler_free(&W->S[i]);
  free(W->S); free(W->tmpl_of); free(W->tmpl); free(W->tmpl_lambert);
  free(W);
}

/* the n light samples whose draws are in W->u, into wi, Le, pdf: in one el_envlight_sample_li_n call
 * for the map alone; with product sampling in one el_envlight_sample_li_cos_n call, each for the normal of its
 * vertex (normal[i], or the map alone where has_n[i] is 0, as elr_light_sample_li does); with portals
 * one el_envlight_portal_sample_li each, at its point pos[i] (counted for --stats as elr_estimate_direct);
 * at a vertex whose sun-cache cell lowers a hot spot (sc[i], sun.c) elr_sun_sample */
static void elr__env_samples(const elr_light *l, int n, const float *u, const elr_v3 *normal, const int *has_n, const elr_v3 *pos,
                             float *wi, float *Le, float *pdf, const elr_sun *sun, const elr_sun_cell *const *sc, elr_tstats *ts) {
  int i, k, nm = 0, idx[ELR_WAVE];
  float um[2 * ELR_WAVE], wm[3 * ELR_WAVE], Lm[3 * ELR_WAVE], pm[ELR_WAVE];
  if (l->portal) {
    for (i = 0; i < n; i++) {
      float pp[3];
      elr_to3(pos[i], pp);
      if (el_envlight_portal_sample_li(l->portal, l->env_sample, pp, &u[2 * i], &wi[3 * i], &Le[3 * i], &pdf[i])) ts->portal_used++;
      else ts->portal_fallback++;
    }
    return;
  }
  if (!l->product) { el_envlight_sample_li_n(l->env_sample, n, u, wi, Le, pdf); return; }
  if (sun) { /* (sun.c: the vertices whose cell lowers a hot spot's weight, then the rest as below; --stats; a horizon cell's
             * product samples with the others: elr_sun_cell_product) */
    nm = 0;
    for (i = 0; i < n; i++)
      if (sc[i] && !elr_sun_cell_product(sc[i], has_n[i])) elr_sun_sample(sun, sc[i], has_n[i] ? &normal[i] : NULL, &u[2 * i], &wi[3 * i], &Le[3 * i], &pdf[i]);
  } else { /* the map alone for all (diffuse vertices under a sun): one call on the arrays themselves */
    for (i = 0; i < n && !has_n[i]; i++) {}
    if (i == n) { el_envlight_sample_li_n(l->env_sample, n, u, wi, Le, pdf); return; }
  }
  { /* the product samples (a normal each) in one el_envlight_sample_li_cos_n call: the same bits as one
     * el_envlight_sample_li_cos each, four samples' arithmetic at a time (issue 20) */
    float nn[3 * ELR_WAVE];
    int nc = 0;
    for (i = 0; i < n && has_n[i] && !(sun && sc[i]); i++) elr_to3(normal[i], &nn[3 * i]);
    if (n > 0 && i == n) { /* (every vertex has a normal and no sun-cache cell: u, wi, Le and pdf used in place, no copies) */
      el_envlight_sample_li_cos_n(l->env_sample, n, nn, u, wi, Le, pdf);
      if (sun) for (i = 0; i < n; i++) elr_sun_count(sun, sc[i], &wi[3 * i], pdf[i], ts);
      return;
    }
    for (i = 0; i < n; i++)
      if (!(sun && sc[i] && !elr_sun_cell_product(sc[i], 1)) && has_n[i]) { idx[nc] = i; elr_to3(normal[i], &nn[3 * nc]); um[2 * nc] = u[2 * i]; um[2 * nc + 1] = u[2 * i + 1]; nc++; }
    if (nc > 0) el_envlight_sample_li_cos_n(l->env_sample, nc, nn, um, wm, Lm, pm);
    for (k = 0; k < nc; k++) {
      i = idx[k];
      memcpy(&wi[3 * i], &wm[3 * k], 3 * sizeof(float)); memcpy(&Le[3 * i], &Lm[3 * k], 3 * sizeof(float)); pdf[i] = pm[k];
    }
  }
  for (i = 0; i < n; i++) /* (gathered: the map's samples in one el_envlight_sample_li_n call below, as the map alone draws them) */
    if (!(sun && sc[i]) && !has_n[i]) { idx[nm] = i; um[2 * nm] = u[2 * i]; um[2 * nm + 1] = u[2 * i + 1]; nm++; }
  if (nm > 0) {
    el_envlight_sample_li_n(l->env_sample, nm, um, wm, Lm, pm);
    for (k = 0; k < nm; k++) {
      i = idx[k];
      memcpy(&wi[3 * i], &wm[3 * k], 3 * sizeof(float)); memcpy(&Le[3 * i], &Lm[3 * k], 3 * sizeof(float)); pdf[i] = pm[k];
    }
  }
  if (sun) for (i = 0; i < n; i++) elr_sun_count(sun, sc[i], &wi[3 * i], pdf[i], ts);
}

/* The first vertex of the camera samples W->fast marks (a hit that emits nothing and from which the
 * reference follows no specular bounce), shaded here rather than by elr_direct_first: its
 * elr__sample_lights_ahead and elr__estimate_direct_ahead (above) with the same sums in the
 * same order (bit for bit: test_render_wave), without the sampler's restore and skips (nothing draws
 * after the first vertex then) and with the light sample's BSDF value already computed for the shadow
 * ray (W->fl). Each pair's terms into its camera sample's W->Ld; the 1 / nsamples in the film loop. */
static void elr__direct_shade(const elr_ctx *C, elr_wave *W, int np, elr_tstats *ts) {
  int k;
  for (k = 0; k < np; k++) {
    const elr_first *p = W->pair[k];
    int j = W->pair_of[k];
    const elr_bsdf *b = &W->f[j].b;
    elr_v3 Ld = W->Ld[j];
    if (!W->fast[j]) continue;
    if (p->two) { /* (two product light samples, no BSDF sample) */
      Ld = elr__two_term(C, W->f[j].h, Ld, W->fl[k], p->wi, p->L, p->pdf, p->occ_l, ts);
      W->Ld[j] = elr__two_term(C, W->f[j].h, Ld, W->fl2[k], p->wi2, p->L2, p->pdf2, p->occ_l2, ts);
      continue;
    }
    if (p->split) elr__split_terms(C, W->f[j].h, b, elr_mul(W->cam[j].d, -1.f), p, ts, &Ld); /* (then the BSDF sample's; p->pdf 0) */
    /* <<Sample light source with multiple importance sampling>> (W->fl: set where pdf > 0) */
    if (C->ls != ELR_LS_BSDF && p->pdf > 0.f && !elr_isblack(W->fl[k])) {
      ts->shadow++;
      if (!p->occ_l) {
        float w = 1.f;
        if (C->ls == ELR_LS_MIS && !W->lonly[k]) w = elr_power_heuristic(p->pdf, W->flpdf[k]);
        Ld = elr_add(Ld, elr_mul(elr_vmul(W->fl[k], p->L), w / p->pdf));
      }
    }
    /* <<Sample BSDF with multiple importance sampling>> */
    if (p->bray) {
      elr_v3 fb = elr_mul(p->fb, fabsf(elr_dot(p->wb, b->ns)));
      ts->bsdfl++;
      if (!p->occ_b) {
        float w = C->ls == ELR_LS_MIS ? elr_power_heuristic(p->bpdf, p->bpdf_env) : 1.f;
        Ld = elr_add(Ld, elr_mul(elr_vmul(fb, p->Lb), w / p->bpdf));
      }
    }
    W->Ld[j] = Ld;
  }
}

/* >> the first vertex of direct lighting in structure-of-arrays form (issue 21)
 * Where the wave loop shades the first vertex itself (elr__direct_shade's lanes) and the BSDF is a lone
 * Lambertian lobe, under the environment alone (no portals, no sun cache, MIS, one light sample pair per
 * camera sample), its steps run over W->A, a stage at a time over all such lanes: the BSDF sample
 * (elr_bsdf_lambert_sample), the product-sampling normal (elr_bsdf_cos_normal) and lonly
 * (elr_env_light_only), the light sample's f and pdf (elr_bsdf_f_pdf_inl), the shadow rays' origins
 * (elr_spawn_origin), the MIS weights (elr_power_heuristic) and the sums of elr__direct_shade: the same
 * floating-point operations in the same order as those functions, each condition a select, so the
 * same bits (test_render_wave). The readable one-lane form is the code those names point to. Only the
 * cosine of the disk sample's angle stays a libm call a lane (a vector sine would round otherwise). */
/* ELR_SOA_CLONES: the SoA stages built for SSE2 and AVX2, chosen at run time by the CPU (gcc and clang's
 * target_clones; AVX2 without FMA, so the same roundings) */
#if defined(ELR_SOA_AVX2) && (defined(__GNUC__) || defined(__clang__)) && defined(__x86_64__)
#define ELR_SOA_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define ELR_SOA_CLONES
#endif
/* the vector loops run to n rounded up to 8 lanes (the arrays hold ELR_WAVE, a multiple of 8): no scalar
 * remainder, so that gcc vectorises them at -O2 too (its very cheap cost model); the lanes past n hold
 * an earlier wave's values (or calloc's zeros), computed and never read */
#define ELR_SOA_PAD(n) (((n) + 7) & ~7)
static inline float elr__ph_sel(float f, float g) { /* elr_power_heuristic, both branches computed and selected */
  float f2 = f * f, g2 = g * g, rg = g / f, rf = f / g, r = f >= g ? rg : rf, wr = 1.f / (1.f + r * r), q = f2 / (f2 + g2);
  float wbig = f >= g ? wr : 1.f - wr, wn = f2 + g2 > 0.f ? q : 0.f;
  return ((f > 1e18f) | (g > 1e18f)) ? wbig : wn;
}

/* lane j (a hit, not emitting) of the wave into W->A where its BSDF is a lone Lambertian lobe: 1 (its draws
 * made), or 0 (shaded by elr__direct_wave's general steps) */
static int elr__soa_add(const elr_ctx *C, elr_wave *W, int j) {
  elr_wave_soa *A = &W->A;
  const elr_hit *h = &W->h[j];
  const elr_bsdf *t;
  elr_sampler *S;
  float us[2];
  int i = A->n, k = W->tmpl_of[h->material];
  if (k < 0 || !W->tmpl_lambert[k] || h->light >= 0) return 0;
  t = &W->tmpl[k];
  S = &W->S[W->pix[j]];
  elr_sampler_restore(S, &W->pos[j]);
  elr_sampler_get2d(S, &A->ul[2 * i]);
  elr_sampler_get2d(S, us);
  A->v0[i] = us[0]; A->v1[i] = us[1];
  if (!(us[0] >= 0.f && us[0] < 1.f)) return 0; /* (elr_bsdf_lambert_alone's u0; the general steps draw again) */
  A->lane[i] = j;
  A->px[i] = h->p.x; A->py[i] = h->p.y; A->pz[i] = h->p.z; A->gx[i] = h->ng.x; A->gy[i] = h->ng.y; A->gz[i] = h->ng.z;
  A->nx[i] = h->ns.x; A->ny[i] = h->ns.y; A->nz[i] = h->ns.z; A->eps[i] = h->eps;
  A->ox[i] = W->cam[j].d.x * -1.f; A->oy[i] = W->cam[j].d.y * -1.f; A->oz[i] = W->cam[j].d.z * -1.f;
  if (A->tk[i] != k) { /* (the template's fields: copied only where the lane's template changes) */
    A->tk[i] = k;
    A->kr[i] = t->kd.x; A->kg[i] = t->kd.y; A->kb[i] = t->kd.z;
    A->elo[i] = t->env_light_only; A->emap[i] = t->env_map; A->stest[i] = t->env_sun_test;
    A->sax[i] = t->env_sun_axis.x; A->say[i] = t->env_sun_axis.y; A->saz[i] = t->env_sun_axis.z; A->scos[i] = t->env_sun_cos;
  }
  A->etwo[i] = t->env_two && (C->s->env_sun_diffuse == ELR_ENVSD_TWO || W->two_pix[W->pix[j]] > 0);
  A->n++;
  return 1;
}

/* the BSDF samples and product-sampling normals of W->A's lanes, then their light samples */
ELR_SOA_CLONES static void elr__soa_sample(const elr_ctx *C, elr_wave *W, elr_tstats *ts) {
  elr_wave_soa *A = &W->A;
  const elr_light *l = C->batch_light;
  const int n = A->n, lo_ok = l->kind == ELR_LIGHT_INFINITE && l->product && !l->env_sample->compensated;
  int i, nn = 0, nlo = 0, ntwo = 0;
  for (i = 0; i < ELR_SOA_PAD(n); i++) { /* the normal (elr_bsdf_cos_normal), lonly; the disk sample's radius and angle */
    float dgo = A->ox[i] * A->gx[i] + A->oy[i] * A->gy[i] + A->oz[i] * A->gz[i], sg = dgo < 0.f ? -1.f : 1.f;
    float cx = A->gx[i] * sg, cy = A->gy[i] * sg, cz = A->gz[i] * sg;
    float ox = 2.f * A->v0[i] - 1.f, oy = 2.f * A->v1[i] - 1.f, ta = (ELR_PI / 4.f) * (oy / ox), tb = ELR_PI / 2.f - (ELR_PI / 4.f) * (ox / oy);
    int zero = (ox == 0.f) & (oy == 0.f), big = fabsf(ox) > fabsf(oy);
    int has = (A->emap[i] == 0) & !((A->stest[i] != 0) & (cx * A->sax[i] + cy * A->say[i] + cz * A->saz[i] >= A->scos[i]));
    A->cx[i] = cx; A->cy[i] = cy; A->cz[i] = cz;
    A->has_n[i] = has;
    A->two[i] = has & A->etwo[i] & lo_ok; /* (elr_env_two; MIS) */
    A->lonly[i] = (has & A->elo[i] & lo_ok) | A->two[i];
    A->r[i] = zero ? 0.f : big ? ox : oy;
    A->th[i] = zero ? 0.f : big ? ta : tb;
  }
  for (i = 0; i < n; i++) nlo += A->lonly[i];
  for (i = 0; i < n; i++) { /* (one sincosf a lane, none where the light sample is taken alone) */
    float th = A->th[i];
    if (A->lonly[i]) { A->c[i] = 1.f; A->s[i] = 0.f; continue; }
    A->c[i] = cosf(th); A->s[i] = sinf(th);
  }
  if (nlo < n) for (i = 0; i < ELR_SOA_PAD(n); i++) { /* the cosine sample in the frame of ns (elr_onb), in world space; its f and pdf */
    float x = A->nx[i], y = A->ny[i], z = A->nz[i], sign = z >= 0.f ? 1.f : -1.f, a = -1.f / (sign + z), b = x * y * a;
    float ssx = 1.f + sign * x * x * a, ssy = sign * b, ssz = -sign * x, tsx = b, tsy = sign + y * y * a, tsz = -y;
    float r = A->r[i], c = A->c[i], sn = A->s[i], z2 = 1.f - r * r * (c * c + sn * sn);
    float co = A->ox[i] * x + A->oy[i] * y + A->oz[i] * z, lx = r * c, ly = r * sn, lz = sqrtf(z2 > 0.f ? z2 : 0.f);
    float wx, wy, wz, ci, pdf, dgo, dgi, fr, fg, fb;
    int f0;
    lz = co < 0.f ? -lz : lz;
    wx = ssx * lx + tsx * ly + x * lz; wy = ssy * lx + tsy * ly + y * lz; wz = ssz * lx + tsz * ly + z * lz;
    ci = wx * x + wy * y + wz * z;
    pdf = co * ci > 0.f ? fabsf(ci) * ELR_INV_PI : 0.f; /* (/ ncomp, 1) */
    dgi = wx * A->gx[i] + wy * A->gy[i] + wz * A->gz[i]; dgo = A->ox[i] * A->gx[i] + A->oy[i] * A->gy[i] + A->oz[i] * A->gz[i];
    f0 = !((dgi * dgo > 0.f) & (co != 0.f));
    A->wbx[i] = wx; A->wby[i] = wy; A->wbz[i] = wz; A->bpdf[i] = pdf;
    fr = A->kr[i] * ELR_INV_PI; fg = A->kg[i] * ELR_INV_PI; fb = A->kb[i] * ELR_INV_PI; /* (loaded in every lane: a select, no branch) */
    fr = f0 ? 0.f : fr; fg = f0 ? 0.f : fg; fb = f0 ? 0.f : fb;
    A->fbr[i] = fr; A->fbg[i] = fg; A->fbb[i] = fb;
    A->dbg[i] = dgi;
  }
  /* the light samples (elr__env_samples' map and product cases) */
  for (i = 0; i < n; i++) { nn += A->has_n[i]; ntwo += A->two[i]; }
  if (l->product) { ts->env_product += (uint64_t)(nn + ntwo); ts->env_map += (uint64_t)(n - nn); ts->env_light_only += (uint64_t)(nlo + ntwo); } /* (--stats) */
  if (ntwo > 0) { /* (the second product light samples, from the BSDF draws, in one call) */
    float nv[3 * ELR_WAVE], um[2 * ELR_WAVE], wm[3 * ELR_WAVE], Lm[3 * ELR_WAVE], pm[ELR_WAVE];
    int idx[ELR_WAVE], m = 0;
    for (i = 0; i < n; i++)
      if (A->two[i]) { idx[m] = i; nv[3 * m] = A->cx[i]; nv[3 * m + 1] = A->cy[i]; nv[3 * m + 2] = A->cz[i]; um[2 * m] = A->v0[i]; um[2 * m + 1] = A->v1[i]; m++; }
    el_envlight_sample_li_cos_n(l->env_sample, m, nv, um, wm, Lm, pm);
    for (i = 0; i < m; i++) {
      memcpy(&A->wl2[3 * idx[i]], &wm[3 * i], 3 * sizeof(float)); memcpy(&A->Ll2[3 * idx[i]], &Lm[3 * i], 3 * sizeof(float));
      A->lpdf2[idx[i]] = pm[i];
    }
  }
  if (n == 0) return;
  if (!l->product || nn == 0) el_envlight_sample_li_n(l->env_sample, n, A->ul, A->wl, A->Ll, A->lpdf);
  else {
    float nv[3 * ELR_WAVE], um[2 * ELR_WAVE], wm[3 * ELR_WAVE], Lm[3 * ELR_WAVE], pm[ELR_WAVE];
    int idx[ELR_WAVE], k, m = 0;
    if (nn == n) {
      for (i = 0; i < n; i++) { nv[3 * i] = A->cx[i]; nv[3 * i + 1] = A->cy[i]; nv[3 * i + 2] = A->cz[i]; }
      el_envlight_sample_li_cos_n(l->env_sample, n, nv, A->ul, A->wl, A->Ll, A->lpdf);
      return;
    }
    for (k = 0; k < 2; k++) { /* the product lanes, then the map's */
      m = 0;
      for (i = 0; i < n; i++)
        if (A->has_n[i] == !k) {
          idx[m] = i; nv[3 * m] = A->cx[i]; nv[3 * m + 1] = A->cy[i]; nv[3 * m + 2] = A->cz[i];
          um[2 * m] = A->ul[2 * i]; um[2 * m + 1] = A->ul[2 * i + 1]; m++;
        }
      if (m > 0 && k == 0) el_envlight_sample_li_cos_n(l->env_sample, m, nv, um, wm, Lm, pm);
      else if (m > 0) el_envlight_sample_li_n(l->env_sample, m, um, wm, Lm, pm);
      for (i = 0; i < m; i++) {
        memcpy(&A->wl[3 * idx[i]], &wm[3 * i], 3 * sizeof(float)); memcpy(&A->Ll[3 * idx[i]], &Lm[3 * i], 3 * sizeof(float));
        A->lpdf[idx[i]] = pm[i];
      }
    }
  }
}

/* lane i's light sample (direction w): its f |cos| (fl), BSDF pdf and n_g . w (elr_bsdf_f_pdf_inl, elr__soa_shadows) */
static inline void elr__soa_fl(const elr_wave_soa *A, int i, float wx, float wy, float wz, float *flr, float *flg, float *flb, float *flpdf, float *dlg) {
  float x = A->nx[i], y = A->ny[i], z = A->nz[i];
  float co = A->ox[i] * x + A->oy[i] * y + A->oz[i] * z, ci = wx * x + wy * y + wz * z, ac = fabsf(ci);
  float dgi = wx * A->gx[i] + wy * A->gy[i] + wz * A->gz[i], dgo = A->ox[i] * A->gx[i] + A->oy[i] * A->gy[i] + A->oz[i] * A->gz[i];
  int f0 = !((dgi * dgo > 0.f) & (co != 0.f));
  float fr = A->kr[i] * ELR_INV_PI, fg = A->kg[i] * ELR_INV_PI, fb = A->kb[i] * ELR_INV_PI;
  *flpdf = co * ci > 0.f ? ac * ELR_INV_PI : 0.f;
  *flr = (f0 ? 0.f : fr) * ac; *flg = (f0 ? 0.f : fg) * ac; *flb = (f0 ? 0.f : fb) * ac;
  *dlg = dgi;
}

/* the light samples' f |cos| and BSDF pdf (elr_bsdf_f_pdf_inl) of W->A's lanes, and their shadow rays and
 * the BSDF samples' into W->shadows */
ELR_SOA_CLONES static void elr__soa_shadows(elr_wave *W) {
  elr_wave_soa *A = &W->A;
  const int n = A->n;
  int i, ntwo = 0, nsh0 = W->shadows.n, nb = 0;
  for (i = 0; i < n; i++) { /* (by component: the loops below take four lanes at a time, not two) */
    A->wlx[i] = A->wl[3 * i]; A->wly[i] = A->wl[3 * i + 1]; A->wlz[i] = A->wl[3 * i + 2];
    A->llr[i] = A->Ll[3 * i]; A->llg[i] = A->Ll[3 * i + 1]; A->llb[i] = A->Ll[3 * i + 2];
    ntwo += A->two[i];
  }
  for (i = 0; i < ELR_SOA_PAD(n); i++) elr__soa_fl(A, i, A->wlx[i], A->wly[i], A->wlz[i], &A->flr[i], &A->flg[i], &A->flb[i], &A->flpdf[i], &A->dlg[i]);
  if (ntwo > 0) { /* (the second light samples of ELR_ENVSD_TWO's lanes: the same, and their shadow rays; sh2 read in those lanes alone) */
    for (i = 0; i < n; i++) A->sh2[i] = -1;
    for (i = 0; i < ELR_SOA_PAD(n); i++) { /* (the lanes without one: an earlier wave's values, computed and never read) */
      A->wlx2[i] = A->wl2[3 * i]; A->wly2[i] = A->wl2[3 * i + 1]; A->wlz2[i] = A->wl2[3 * i + 2];
      A->llr2[i] = A->Ll2[3 * i]; A->llg2[i] = A->Ll2[3 * i + 1]; A->llb2[i] = A->Ll2[3 * i + 2];
      elr__soa_fl(A, i, A->wlx2[i], A->wly2[i], A->wlz2[i], &A->flr2[i], &A->flg2[i], &A->flb2[i], &A->flpdf2[i], &A->dlg2[i]);
    }
    for (i = 0; i < n; i++)
      if (A->two[i] && A->lpdf2[i] > 0.f && !(A->flr2[i] == 0.f && A->flg2[i] == 0.f && A->flb2[i] == 0.f)) {
        float e = A->dlg2[i] >= 0.f ? A->eps[i] : -A->eps[i];
        A->sh2[i] = W->shadows.n;
        elr_wave_add(&W->shadows, elr_v(A->px[i] + A->gx[i] * e, A->py[i] + A->gy[i] * e, A->pz[i] + A->gz[i] * e), elr_v(A->wlx2[i], A->wly2[i], A->wlz2[i]), INFINITY);
      }
  }
  for (i = 0; i < n; i++) { /* (elr_wave_add, elr_spawn_origin) */
    A->sh[i] = A->bsh[i] = -1;
    if (A->lpdf[i] > 0.f && !(A->flr[i] == 0.f && A->flg[i] == 0.f && A->flb[i] == 0.f)) {
      float e = A->dlg[i] >= 0.f ? A->eps[i] : -A->eps[i];
      A->sh[i] = W->shadows.n;
      elr_wave_add(&W->shadows, elr_v(A->px[i] + A->gx[i] * e, A->py[i] + A->gy[i] * e, A->pz[i] + A->gz[i] * e), elr_v(A->wlx[i], A->wly[i], A->wlz[i]), INFINITY);
    }
    if (!A->lonly[i] && A->bpdf[i] > 0.f && !(A->fbr[i] == 0.f && A->fbg[i] == 0.f && A->fbb[i] == 0.f)) { /* (elr_estimate_direct's BSDF ray) */
      float e = A->dbg[i] >= 0.f ? A->eps[i] : -A->eps[i];
      A->bsh[i] = W->shadows.n; nb++;
      elr_wave_add(&W->shadows, elr_v(A->px[i] + A->gx[i] * e, A->py[i] + A->gy[i] * e, A->pz[i] + A->gz[i] * e), elr_v(A->wbx[i], A->wby[i], A->wbz[i]), INFINITY);
    }
  }
  A->nsh = W->shadows.n - nsh0 - nb; A->nb = nb; /* (--stats: the light samples' shadow rays, the BSDF samples') */
}

/* after the shadow rays: the environment in the escaped BSDF samples' directions, then each lane's Ld
 * (elr__direct_shade's sums) into W->Ld */
ELR_SOA_CLONES static void elr__soa_shade(const elr_ctx *C, elr_wave *W, elr_tstats *ts) {
  elr_wave_soa *A = &W->A;
  const elr_light *l = C->batch_light;
  const int n = A->n, le_same = l->le_same; /* (the product lanes' le comes with their pdf: el_envlight_pdf_li_cos_le_n) */
  float dm[3 * ELR_WAVE], dc[3 * ELR_WAVE], nv[3 * ELR_WAVE], de[3 * ELR_WAVE], pq[ELR_WAVE], Le[3 * ELR_WAVE];
  int km[ELR_WAVE], kc[ELR_WAVE], ke[ELR_WAVE], nm = 0, nc = 0, ne = 0, i;
  for (i = 0; i < n; i++) { /* (the shadow rays' answers: 1 where the term counts; sh2's in the ELR_ENVSD_TWO loop below) */
    A->sh[i] = A->sh[i] >= 0 && !(W->shadows.tfar[A->sh[i]] < 0.f);
    A->bsh[i] = A->bsh[i] >= 0 && !(W->shadows.tfar[A->bsh[i]] < 0.f);
  }
  ts->shadow += (uint64_t)A->nsh; ts->bsdfl += (uint64_t)A->nb; /* (--stats, counted in elr__soa_shadows) */
  for (i = 0; i < n; i++) { /* (the escaped BSDF rays gathered without branches: every lane written, the counts
                              * moved by its flags; whether a ray escaped is a coin toss the branch predictor loses) */
    int e = A->bsh[i], c = e & (l->product && A->has_n[i]);
    float x = A->wbx[i], y = A->wby[i], z = A->wbz[i];
    A->bpe[i] = 0.f; A->lbr[i] = A->lbg[i] = A->lbb[i] = 0.f;
    if (!le_same) { de[3 * ne] = x; de[3 * ne + 1] = y; de[3 * ne + 2] = z; ke[ne] = i; ne += e; } /* (a test the predictor wins) */
    dc[3 * nc] = x; dc[3 * nc + 1] = y; dc[3 * nc + 2] = z; kc[nc] = i;
    nv[3 * nc] = A->cx[i]; nv[3 * nc + 1] = A->cy[i]; nv[3 * nc + 2] = A->cz[i]; nc += c;
    dm[3 * nm] = x; dm[3 * nm + 1] = y; dm[3 * nm + 2] = z; km[nm] = i; nm += e & !c;
  }
  if (nm > 0) el_envlight_pdf_li_n(l->env_sample, nm, dm, pq);
  for (i = 0; i < nm; i++) A->bpe[km[i]] = pq[i];
  if (le_same) { /* (the others' le: the escaped rays without a product pdf are dm's) */
    if (nc > 0) el_envlight_pdf_li_cos_le_n(l->env_sample, nc, nv, dc, pq, Le);
    for (i = 0; i < nc; i++) { A->bpe[kc[i]] = pq[i]; A->lbr[kc[i]] = Le[3 * i]; A->lbg[kc[i]] = Le[3 * i + 1]; A->lbb[kc[i]] = Le[3 * i + 2]; }
    if (nm > 0) el_envlight_le_n(l->env, nm, dm, Le);
    for (i = 0; i < nm; i++) { A->lbr[km[i]] = Le[3 * i]; A->lbg[km[i]] = Le[3 * i + 1]; A->lbb[km[i]] = Le[3 * i + 2]; }
  } else {
    if (nc > 0) el_envlight_pdf_li_cos_n(l->env_sample, nc, nv, dc, pq);
    for (i = 0; i < nc; i++) A->bpe[kc[i]] = pq[i];
    if (ne > 0) el_envlight_le_n(l->env, ne, de, Le);
    for (i = 0; i < ne; i++) { A->lbr[ke[i]] = Le[3 * i]; A->lbg[ke[i]] = Le[3 * i + 1]; A->lbb[ke[i]] = Le[3 * i + 2]; }
  }
  for (i = 0; i < ELR_SOA_PAD(n); i++) { /* (elr__direct_shade: Ld from 0, the light sample's term, then the BSDF sample's) */
    int ul = A->sh[i], ub = A->bsh[i];
    float lp = A->lpdf[i], wp = elr__ph_sel(lp, A->flpdf[i]), wl = A->lonly[i] ? 1.f : wp, sl = wl / lp;
    float bp = A->bpdf[i], wb = elr__ph_sel(bp, A->bpe[i]), sb = wb / bp;
    float ac = fabsf(A->wbx[i] * A->nx[i] + A->wby[i] * A->ny[i] + A->wbz[i] * A->nz[i]);
    float tr = 0.f + A->flr[i] * A->llr[i] * sl, tg = 0.f + A->flg[i] * A->llg[i] * sl, tb = 0.f + A->flb[i] * A->llb[i] * sl;
    float lr = ul ? tr : 0.f, lg = ul ? tg : 0.f, lb = ul ? tb : 0.f;
    float br = lr + A->fbr[i] * ac * A->lbr[i] * sb, bg = lg + A->fbg[i] * ac * A->lbg[i] * sb, bb = lb + A->fbb[i] * ac * A->lbb[i] * sb;
    A->flr[i] = ub ? br : lr; A->flg[i] = ub ? bg : lg; A->flb[i] = ub ? bb : lb;
  }
  for (i = 0; i < n; i++) { /* each lane's Ld into W->Ld */
    if (A->two[i]) { /* (ELR_ENVSD_TWO: elr__two_term's sums, each term weighted 1/2; no BSDF sample) */
      float s2 = 1.f / A->lpdf2[i], t1r = A->flr[i], t1g = A->flg[i], t1b = A->flb[i]; /* (the first term: lr above, lonly's weight 1) */
      int u2 = A->sh2[i] >= 0 && !(W->shadows.tfar[A->sh2[i]] < 0.f); /* (its shadow ray's answer) */
      float t2r = u2 ? 0.f + A->flr2[i] * A->llr2[i] * s2 : 0.f, t2g = u2 ? 0.f + A->flg2[i] * A->llg2[i] * s2 : 0.f, t2b = u2 ? 0.f + A->flb2[i] * A->llb2[i] * s2 : 0.f;
      A->flr[i] = (0.f + t1r * 0.5f) + t2r * 0.5f; A->flg[i] = (0.f + t1g * 0.5f) + t2g * 0.5f; A->flb[i] = (0.f + t1b * 0.5f) + t2b * 0.5f;
    }
    W->Ld[A->lane[i]] = elr_v(A->flr[i], A->flg[i], A->flb[i]);
  }
}

/* --sun split: light sample ls's shadow ray into sh where elr_light_term traces one (hit h, BSDF b, wo): its index, or -1 */
static int elr__split_shadow(elr_wave_rays *sh, const elr_hit *h, const elr_bsdf *b, elr_v3 wo, const elr_light_sample *ls) {
  if (!(ls->pdf > 0.f) || elr_isblack(elr_mul(elr_bsdf_f(b, wo, ls->wi), fabsf(elr_dot(ls->wi, b->ns))))) return -1;
  elr_wave_add(sh, elr_spawn_origin(h, ls->wi), ls->wi, ls->dist);
  return sh->n - 1;
}

/* the direct-lighting integrator's first vertex for the m camera samples of the wave (their camera rays
 * in W->rays, traced): the hits' BSDF samples, light samples and environment lookups for the whole
 * wave, for each of the light's W->npair sample pairs (its "samples" count, or splitting's), then all
 * their shadow rays */
static void elr__direct_wave(const elr_ctx *C, elr_wave *W, int m, elr_tstats *ts) {
  const el_envlight *env = C->batch_light->env, *env_sample = C->batch_light->env_sample;
  /* (W->A's lanes: a lone Lambertian lobe under the environment alone, one pair, MIS; elr__soa_add) */
  const int soa = W->npair == 1 && C->light_sampling && C->ls == ELR_LS_MIS && !C->batch_light->portal && !C->sun && !C->sunsplit;
  int j, k, n = 0, np = 0, nm = 0, nesc = 0;
  W->shadows.n = 0; W->A.n = 0;
  for (j = 0; j < m; j++) {
    elr_first *q = &W->f[j];
    elr_sampler *S;
    elr_v3 wo;
    q->h = &W->h[j]; /* (the pair loop below sets the light sampling's fields: elr_direct_first reads them nowhere else) */
    q->hit = elr_wave_hit(C->s, &W->rays, j, &W->h[j]);
    W->fast[j] = 0;
    if (!q->hit) { elr_to3(W->cam[j].d, &W->wi[3 * nesc]); W->escaped[nesc++] = j; W->fast[j] = 2; continue; } /* (its radiance below) */
    if (soa && elr__soa_add(C, W, j)) { W->fast[j] = 1; continue; } /* (shaded in W->A) */
    S = &W->S[W->pix[j]]; wo = elr_mul(W->cam[j].d, -1.f);
    elr_sampler_restore(S, &W->pos[j]);
    elr_compute_differentials(C->s, &W->cam[j], &W->h[j], &q->tc, &q->dpdx, &q->dpdy);
    elr__bsdf_init(C->s, W, &W->h[j], &q->tc, &q->b, NULL);
    if (!C->light_sampling || !(q->b.has_diffuse || q->b.has_glossy)) continue;
    /* shaded below (elr__direct_shade) unless it emits or the reference follows a specular bounce */
    W->fast[j] = W->h[j].light < 0 && !(1 < C->maxdepth && (q->b.spec_r || q->b.spec_t)) &&
                 W->npair == (C->direct_one ? 1 : C->batch_light->nsamples); /* (else the samples past ELR_WAVE's: elr_direct_first) */
    W->Ld[j] = elr_v(0, 0, 0);
    W->vsc[j] = C->sun ? elr_sun_lookup(C->sun, &W->h[j], wo) : NULL;
    q->more = &W->more[nm]; q->nmore = W->npair - 1; nm += W->npair - 1;
    for (k = 0; k < W->npair; k++) { /* each pair's light draw, then its BSDF draw */
      elr_first *p = k == 0 ? q : &W->more[nm - (W->npair - 1) + k - 1];
      float us[2];
      int lonly = 0, two = 0;
      p->bs = p->bray = p->two = p->split = 0; p->occ_l = p->occ_b = p->occ_l2 = -1; p->pdf = p->pdf2 = 0.f; p->sun = W->vsc[j];
      W->pair[np] = p; W->pair_of[np] = j; W->light[np] = W->light2[np] = -1; W->lonly[np] = 0;
      elr_sampler_get2d(S, &W->u[2 * n]);
      elr_sampler_get2d(S, us);
      if (C->ls != ELR_LS_BSDF && C->sunsplit) { /* (--sun split: as elr_estimate_direct, no sun cache then) */
        elr_v3 nv;
        int has = elr_sun_cos_normal(C->s, NULL, &q->b, wo, &nv), kk;
        p->split = elr_sunsplit_at(C->sunsplit, C->batch_light, &q->b, has ? &nv : NULL);
        if (p->split) {
          ts->sunsplit_vertices++; ts->sunsplit_sky_only += (uint64_t)(p->split == 1);
          p->nsplit = nv; p->ssl[0].pdf = 0.f;
          for (kk = 2 - p->split; kk < 2; kk++) elr_sunsplit_sample(C->sunsplit, kk, p->split, nv, &W->u[2 * n], &p->ssl[kk], &p->sother[kk], ts);
        }
      }
      if (C->ls != ELR_LS_BSDF && !p->split) {
        W->sc[n] = W->vsc[j];
        W->has_n[n] = elr__cos_normal(C->s, W->sc[n], &q->b, wo, &W->normal[n]);
        W->lpos[n] = W->h[j].p;
        lonly = !W->sc[n] && elr_env_light_only(C->ls == ELR_LS_MIS, 1, C->batch_light, W->has_n[n], &q->b); /* (as elr_estimate_direct) */
        /* (ELR_ENVSD_TWO: a second product light sample from the BSDF draw, as elr_estimate_direct) */
        two = !W->sc[n] && elr_env_two(C->ls == ELR_LS_MIS, 1, C->batch_light, W->has_n[n], &q->b) &&
              (C->s->env_sun_diffuse != ELR_ENVSD_TWO_PIXEL || W->two_pix[W->pix[j]] > 0);
        if (two) lonly = 1;
        if (C->batch_light->product) { if (W->has_n[n]) ts->env_product += (uint64_t)(1 + two); else ts->env_map++; ts->env_light_only += (uint64_t)(lonly * (1 + two)); } /* (--stats) */
        W->light[np] = n++;
        W->lonly[np] = lonly;
        if (two) {
          W->u[2 * n] = us[0]; W->u[2 * n + 1] = us[1];
          W->sc[n] = W->sc[n - 1]; W->has_n[n] = W->has_n[n - 1]; W->normal[n] = W->normal[n - 1]; W->lpos[n] = W->lpos[n - 1];
          W->light2[np] = n++;
          p->two = 1;
        }
      }
      if (C->ls != ELR_LS_LIGHT && !lonly) {
        int spec;
        p->fb = elr_bsdf_sample_inl(&q->b, wo, us[0], us[1], &p->wb, &p->bpdf, &spec);
        p->bs = 1;
        p->bray = !spec && p->bpdf > 0.f && !elr_isblack(p->fb); /* elr_estimate_direct's BSDF ray */
      }
      np++;
    }
  }
  /* the camera rays that left the scene: their radiance, elr_direct_first's p.L + beta (0 + Le) (the
   * environment is the only light that emits: elr_infinite_le's sum is its le), in one el_envlight_le_n
   * call (the same bits as el_envlight_le each; their cache misses overlap) */
  el_envlight_le_n(env, nesc, W->wi, W->Le);
  for (k = 0; k < nesc; k++) W->Ld[W->escaped[k]] = elr_add(elr_v(0, 0, 0), elr_from3(&W->Le[3 * k]));
  /* the light samples */
  elr__env_samples(C->batch_light, n, W->u, W->normal, W->has_n, W->lpos, W->wi, W->Le, W->pdf, C->sun, W->sc, ts);
  elr__soa_sample(C, W, ts);
  /* the shadow rays elr_direct_first will ask about: the light sample's when its BSDF value is not
   * black, the BSDF sample's (W->shadow, W->bshadow: their index in W->shadows) */
  for (k = 0; k < np; k++) {
    elr_first *p = W->pair[k], *q = &W->f[W->pair_of[k]];
    int i = W->light[k];
    W->shadow[k] = W->bshadow[k] = W->shadow2[k] = -1;
    if (p->split) { /* (the spot and sky samples' shadow rays where elr_light_term traces one) */
      elr_v3 wo = elr_mul(W->cam[W->pair_of[k]].d, -1.f);
      int kk;
      for (kk = 2 - p->split; kk < 2; kk++) *(kk ? &W->shadow2[k] : &W->shadow[k]) = elr__split_shadow(&W->shadows, q->h, &q->b, wo, &p->ssl[kk]);
    }
    if (W->light2[k] >= 0) { /* (the second light sample: its shadow ray as the first's) */
      elr_v3 wo = elr_mul(W->cam[W->pair_of[k]].d, -1.f);
      float pb;
      int i2 = W->light2[k];
      p->wi2 = elr_from3(&W->wi[3 * i2]); p->L2 = elr_from3(&W->Le[3 * i2]); p->pdf2 = W->pdf[i2];
      if (p->pdf2 > 0.f && !elr_isblack(W->fl2[k] = elr_mul(elr_bsdf_f_pdf_inl(&q->b, wo, p->wi2, &pb), fabsf(elr_dot(p->wi2, q->b.ns))))) {
        W->shadow2[k] = W->shadows.n;
        elr_wave_add(&W->shadows, elr_spawn_origin(q->h, p->wi2), p->wi2, INFINITY);
      }
    }
    if (i >= 0) {
      elr_v3 wo = elr_mul(W->cam[W->pair_of[k]].d, -1.f);
      p->wi = elr_from3(&W->wi[3 * i]); p->L = elr_from3(&W->Le[3 * i]); p->pdf = W->pdf[i];
      if (p->pdf > 0.f && !elr_isblack(W->fl[k] = elr_mul(elr_bsdf_f_pdf_inl(&q->b, wo, p->wi, &W->flpdf[k]), fabsf(elr_dot(p->wi, q->b.ns))))) {
        W->shadow[k] = W->shadows.n;
        elr_wave_add(&W->shadows, elr_spawn_origin(q->h, p->wi), p->wi, INFINITY);
      }
    }
    if (p->bray) {
      W->bshadow[k] = W->shadows.n;
      elr_wave_add(&W->shadows, elr_spawn_origin(q->h, p->wb), p->wb, INFINITY);
    }
  }
  elr__soa_shadows(W);
  elr__occluded(C, &W->shadows, ts);
  for (k = 0; k < np; k++) {
    elr_first *p = W->pair[k];
    p->occ_l = W->shadow[k] >= 0 ? W->shadows.tfar[W->shadow[k]] < 0.f : 0;
    p->occ_b = W->bshadow[k] >= 0 ? W->shadows.tfar[W->bshadow[k]] < 0.f : 0;
    p->occ_l2 = W->shadow2[k] >= 0 ? W->shadows.tfar[W->shadow2[k]] < 0.f : 0;
  }
  /* the environment's pdf (with product sampling, for the vertex's normal) and radiance in the directions
   * of the BSDF samples whose rays escaped (the others' are never read): gathered into one
   * el_envlight_pdf_li_n, one el_envlight_pdf_li_cos_n and one el_envlight_le_n call, the same bits as
   * one call each (issue 21: their table reads' cache misses overlap) */
  {
    float de[3 * ELR_WAVE], dm[3 * ELR_WAVE], dc[3 * ELR_WAVE], nn[3 * ELR_WAVE], Le[3 * ELR_WAVE], pq[ELR_WAVE];
    int ke[ELR_WAVE], km[ELR_WAVE], kc[ELR_WAVE], ne = 0, nm = 0, nc = 0;
    const int le_same = C->batch_light->le_same; /* (then the product pairs' le comes with their pdf: el_envlight_pdf_li_cos_le_n) */
    for (k = 0; k < np; k++) {
      elr_first *p = W->pair[k];
      float *d = &de[3 * ne];
      if (!p->bray || p->occ_b) continue;
      elr_to3(p->wb, d);
      ke[ne++] = k;
      if (p->split) p->bpdf_env = elr_sunsplit_pdf(C->sunsplit, p->split, p->nsplit, p->wb); /* (as elr_estimate_direct) */
      else if (C->batch_light->portal) p->bpdf_env = elr_light_pdf_li_at(C->batch_light, W->f[W->pair_of[k]].h->p, NULL, p->wb);
      else if (C->batch_light->product) { /* (the normal of the pair's light sample where it has one: the same call) */
        elr_v3 nv;
        const elr_sun_cell *c = W->vsc[W->pair_of[k]];
        int i = W->light[k], has = i >= 0 ? W->has_n[i] : elr_sun_cos_normal(C->s, c, &W->f[W->pair_of[k]].b, elr_mul(W->cam[W->pair_of[k]].d, -1.f), &nv);
        if (i >= 0 && has) nv = W->normal[i];
        if (c && !elr_sun_cell_product(c, has)) p->bpdf_env = elr_sun_pdf(C->sun, c, has ? &nv : NULL, d);
        else if (has) { elr_to3(nv, &nn[3 * nc]); memcpy(&dc[3 * nc], d, 3 * sizeof(float)); kc[nc++] = k; ne -= le_same; } /* (elr_light_pdf_li) */
        else { memcpy(&dm[3 * nm], d, 3 * sizeof(float)); km[nm++] = k; }
      } else { memcpy(&dm[3 * nm], d, 3 * sizeof(float)); km[nm++] = k; }
    }
    el_envlight_pdf_li_n(env_sample, nm, dm, pq);
    for (k = 0; k < nm; k++) W->pair[km[k]]->bpdf_env = pq[k];
    if (le_same) {
      el_envlight_pdf_li_cos_le_n(env_sample, nc, nn, dc, pq, Le);
      for (k = 0; k < nc; k++) { W->pair[kc[k]]->bpdf_env = pq[k]; W->pair[kc[k]]->Lb = elr_from3(&Le[3 * k]); }
    } else {
      el_envlight_pdf_li_cos_n(env_sample, nc, nn, dc, pq);
      for (k = 0; k < nc; k++) W->pair[kc[k]]->bpdf_env = pq[k];
    }
    el_envlight_le_n(env, ne, de, Le);
    for (k = 0; k < ne; k++) W->pair[ke[k]]->Lb = elr_from3(&Le[3 * k]);
  }
  elr__soa_shade(C, W, ts);
  elr__direct_shade(C, W, np, ts);
}

/* the path tracer (elr_path_li) for the m camera samples of the wave, every vertex a wave; their camera
 * rays in W->rays, traced */
static void elr__path_wave(const elr_ctx *C, elr_wave *W, int m, elr_tstats *ts) {
  const elr_scene *s = C->s;
  const elr_light *l = C->batch_light;
  const el_envlight *env = l->env, *env_sample = l->env_sample;
  const float pick = C->ld.pick ? C->ld.pick[l - s->light] : 1.f; /* the one emitting light: 1 */
  const int two_pixel = s->env_sunny && s->env_sun_diffuse == ELR_ENVSD_TWO_PIXEL; /* (ts->env_two_pixel: each path's pixel's) */
  int j, depth, nalive = m;
  int ej[ELR_WAVE]; /* each escaped ray's path */
  for (j = 0; j < m; j++) { elr_path_begin(&W->p[j], &W->cam[j]); W->alive[j] = 1; W->ray[j] = j; W->prevsplit[j] = 0; }
  for (depth = 0; nalive > 0; depth++) {
    int n = 0, ne = 0;
    if (depth > 0) elr__intersect(C, &W->rays, 0, ts); /* the rays of the paths alive, in one call (added at the end of the
                                                        * last vertex's loop, in the order of their paths) */
    /* <<Intersect ray with scene and store intersection in isect>>, <<Possibly add emitted light at
     * intersection>>, the BSDF, the draws of light sampling and of the BSDF sample */
    for (j = 0; j < m; j++) {
      elr_path_state *p = &W->p[j];
      elr_hit *h = &W->h[j];
      elr_bsdf *b = &W->b[j];
      elr_sampler *S;
      elr_tex_ctx tc;
      elr_v3 wo, dpdx, dpdy;
      float u[2];
      if (!W->alive[j]) continue; /* (its light, escaped, psplit, ptwo and shadow read for the paths alive alone) */
      W->light[j] = W->light2[j] = W->escaped[j] = -1; W->psplit[j] = W->ptwo[j] = 0;
      if (!elr_wave_hit(s, &W->rays, W->ray[j], h)) { /* escaped: its environment in the pass below */
        float d[3];
        if (p->depth > 0 && !p->specular && C->light_sampling && p->prev_two && elr_path_two_light(C, l, p->prev_two, p->prev_sun, W->prevsplit[j])) {
          W->alive[j] = 0; nalive--; /* (ELR_ENVSD_TWO(_PIXEL): the environment's weight is 0, as elr_path_li; nothing to look up) */
          continue;
        }
        elr_to3(p->ray.d, d);
        W->escaped[j] = ne; ej[ne] = j;
        memcpy(&W->wi[3 * ne], d, sizeof d);
        ne++;
        continue;
      }
      if (h->light >= 0) {
        elr_v3 Le = elr_hit_le(s, h, elr_mul(p->ray.d, -1.f));
        float w = 1.f;
        if (p->depth > 0 && !p->specular && C->light_sampling) {
          if (C->ls == ELR_LS_LIGHT) w = 0.f;
          else if (C->ls == ELR_LS_MIS) w = elr_power_heuristic(p->prev_pdf, C->ld.pick[h->light] * elr_area_light_pdf(s, &s->light[h->light], p->ray.o, h));
        }
        p->L = elr_add(p->L, elr_mul(elr_vmul(p->beta, Le), w));
      }
      /* <<Terminate path if maxDepth was reached>> */
      if (p->depth >= C->maxdepth) { W->alive[j] = 0; nalive--; continue; }
      /* <<Compute scattering functions and skip over medium boundaries>> */
      if (p->depth == 0) elr_compute_differentials(s, &p->ray, h, &tc, &dpdx, &dpdy);
      else {
        memset(&tc, 0, sizeof tc);
        if (s->mat_textured[h->material]) { elr_hit_uv(s, h); tc.u = h->u; tc.v = h->v; }
      }
      elr__bsdf_init(s, W, h, &tc, b, &W->bt[j]);
      wo = elr_mul(p->ray.d, -1.f);
      S = &W->S[W->pix[j]];
      elr_sampler_restore(S, &W->pos[j]);
      if (C->light_sampling && (b->has_diffuse || b->has_glossy)) {
        /* UniformSampleOneLight with the one light: its light draw, then the BSDF draw it makes and
         * does not use (sample_bsdf = 0): skipped, the sampler left where the draw leaves it */
        elr_sampler_get2d(S, &W->u[2 * n]);
        W->sc[n] = C->sun ? elr_sun_lookup(C->sun, h, wo) : NULL;
        W->has_n[n] = elr__cos_normal(s, W->sc[n], b, wo, &W->normal[n]);
        W->lpos[n] = h->p;
        /* (--sun split: the spot and sky samples drawn here, as elr_estimate_direct; no sun cache then) */
        W->psplit[j] = C->sunsplit && C->ls != ELR_LS_BSDF ? elr_sunsplit_at(C->sunsplit, l, b, W->has_n[n] ? &W->normal[n] : NULL) : 0;
        if (W->psplit[j]) {
          int k;
          ts->sunsplit_vertices++; ts->sunsplit_sky_only += (uint64_t)(W->psplit[j] == 1);
          W->pssl[2 * j].pdf = 0.f;
          for (k = 2 - W->psplit[j]; k < 2; k++) elr_sunsplit_sample(C->sunsplit, k, W->psplit[j], W->normal[n], &W->u[2 * n], &W->pssl[2 * j + k], &W->psother[2 * j + k], ts);
        } else {
          if (l->product) { if (W->has_n[n]) ts->env_product++; else ts->env_map++; } /* (--stats) */
          W->light[j] = n++;
        }
        if (two_pixel) ts->env_two_pixel = W->two_pix[W->pix[j]];
        W->ptwo[j] = b->env_two ? elr_path_two(C, b, wo, ts) : 0; /* (its first test inline: no call at most vertices) */
        if (W->light[j] >= 0 && W->ptwo[j] && elr_path_two_light(C, l, 1, W->sc[n - 1], 0)) {
          /* ELR_ENVSD_TWO(_PIXEL): the BSDF draw is the second product light sample's, at the same vertex */
          int i = n - 1;
          elr_sampler_get2d(S, &W->u[2 * n]);
          W->sc[n] = W->sc[i]; W->has_n[n] = W->has_n[i]; W->normal[n] = W->normal[i]; W->lpos[n] = W->lpos[i];
          ts->env_product++; ts->env_light_only += 2; /* (--stats, as elr_estimate_direct counts them) */
          W->light2[j] = n++;
        } else elr_sampler_skip2d(S);
      }
      /* <<Sample BSDF to get new path direction>> */
      elr_sampler_get2d(S, u);
      W->fs[j] = elr_bsdf_sample_inl(b, wo, u[0], u[1], &W->wnext[j], &W->pdfs[j], &W->spec[j]);
      elr_sampler_save(S, &W->pos[j]);
    }
    int le_done = 0; /* (the escaped rays' le already looked up: le_same below) */
    /* the light samples in one call; the escaped rays' environment in one pass */
    elr__env_samples(l, n, W->u, W->normal, W->has_n, W->lpos, W->wi + 3 * ne, W->Le + 3 * ne, W->pdf + ne, C->sun, W->sc, ts);
    /* (batched: el_envlight_pdf_li_n, el_envlight_pdf_li_cos_n and el_envlight_le_n over the escaped rays,
     * the same bits as one call each; issue 21) */
    if (!l->portal && !l->product) el_envlight_pdf_li_n(env_sample, ne, W->wi, W->pdf);
    else {
      float dm[3 * ELR_WAVE], dc[3 * ELR_WAVE], nn[3 * ELR_WAVE], pq[ELR_WAVE];
      int km[ELR_WAVE], kc[ELR_WAVE], nm = 0, nc = 0, k, e;
      for (e = 0; e < ne; e++) { /* (with product sampling, for the normal of the vertex the ray left) */
        j = ej[e];
        if (l->portal) /* (at the vertex the ray left, as elr_path_li's prev_p) */
          W->pdf[e] = W->p[j].depth > 0 ? elr_light_pdf_li_at(l, W->prevp[j], NULL, elr_from3(&W->wi[3 * e])) : 0.f;
        else if (W->p[j].depth > 0 && !W->p[j].specular && C->light_sampling && C->ls == ELR_LS_MIS) { /* (only where the weight is
          * used, as elr_path_li: a camera ray's pdf would build the map's own tables for nothing) */
          if (W->prevsplit[j]) W->pdf[e] = elr_sunsplit_pdf(C->sunsplit, W->prevsplit[j], W->p[j].prev_n, elr_from3(&W->wi[3 * e])); /* (as elr_path_li) */
          else if (W->p[j].prev_sun && !elr_sun_cell_product(W->p[j].prev_sun, W->p[j].prev_has_n)) W->pdf[e] = elr_sun_pdf(C->sun, W->p[j].prev_sun, W->p[j].prev_has_n ? &W->p[j].prev_n : NULL, &W->wi[3 * e]);
          else if (W->p[j].prev_has_n) { elr_to3(W->p[j].prev_n, &nn[3 * nc]); kc[nc++] = e; } /* (elr_light_pdf_li; directions below) */
          else { memcpy(&dm[3 * nm], &W->wi[3 * e], 3 * sizeof(float)); km[nm++] = e; }
        } else W->pdf[e] = 0.f;
      }
      el_envlight_pdf_li_n(env_sample, nm, dm, pq);
      for (k = 0; k < nm; k++) W->pdf[km[k]] = pq[k];
      if (nc == ne && nc > 0) { /* (every escaped ray's pdf with its normal, kc[k] = k: W->wi, W->pdf, W->Le in place, no copies) */
        if (l->le_same) { el_envlight_pdf_li_cos_le_n(env_sample, nc, nn, W->wi, W->pdf, W->Le); le_done = 1; }
        else el_envlight_pdf_li_cos_n(env_sample, nc, nn, W->wi, W->pdf);
        nc = 0;
      }
      for (k = 0; k < nc; k++) memcpy(&dc[3 * k], &W->wi[3 * kc[k]], 3 * sizeof(float));
      if (l->le_same && nc > 0) { /* (le_same: these rays' le with their pdf in one el_envlight_pdf_li_cos_le_n call,
        * the other escaped rays' in one el_envlight_le_n call) */
        float Lq[3 * ELR_WAVE];
        int q = 0;
        el_envlight_pdf_li_cos_le_n(env_sample, nc, nn, dc, pq, Lq);
        for (k = 0; k < nc; k++) { W->pdf[kc[k]] = pq[k]; memcpy(&W->Le[3 * kc[k]], &Lq[3 * k], 3 * sizeof(float)); }
        for (k = 0, nm = 0; k < ne; k++) /* (the others: kc ascends as the escaped rays' indices do) */
          if (q < nc && kc[q] == k) q++;
          else { memcpy(&dm[3 * nm], &W->wi[3 * k], 3 * sizeof(float)); km[nm++] = k; }
        el_envlight_le_n(env, nm, dm, Lq);
        for (k = 0; k < nm; k++) memcpy(&W->Le[3 * km[k]], &Lq[3 * k], 3 * sizeof(float));
        le_done = 1;
      } else if (nc > 0) {
        el_envlight_pdf_li_cos_n(env_sample, nc, nn, dc, pq);
        for (k = 0; k < nc; k++) W->pdf[kc[k]] = pq[k];
      }
    }
    if (!le_done) el_envlight_le_n(env, ne, W->wi, W->Le);
    /* escaped paths end; the light samples' BSDF values, MIS weights and shadow rays */
    W->shadows.n = 0;
    for (j = 0; j < m; j++) {
      elr_path_state *p = &W->p[j];
      int e, i;
      if (!W->alive[j]) continue; /* (the escaped paths are alive until here) */
      e = W->escaped[j]; i = W->light[j];
      W->shadow[j] = -1;
      if (e >= 0) {
        float w = 1.f;
        int skip = 0;
        if (p->depth > 0 && !p->specular && C->light_sampling) {
          if (C->ls == ELR_LS_LIGHT) skip = 1;
          else if (C->ls == ELR_LS_MIS) w = elr_power_heuristic(p->prev_pdf, pick * W->pdf[e]);
        }
        if (!skip) p->L = elr_add(p->L, elr_mul(elr_vmul(p->beta, elr_from3(&W->Le[3 * e])), w));
        W->alive[j] = 0; nalive--;
        continue;
      }
      if (i >= 0 && W->light2[j] >= 0) { /* (two product light samples: each one's f |cos| and shadow ray; elr__two_term below) */
        const elr_bsdf *b = &W->b[j];
        elr_v3 wo = elr_mul(p->ray.d, -1.f);
        int k;
        for (k = 0; k < 2; k++) {
          int q = ne + (k ? W->light2[j] : i);
          elr_v3 wi = elr_from3(&W->wi[3 * q]), fl = elr_v(0, 0, 0);
          int *sh = k ? &W->shadow2[j] : &W->shadow[j];
          *sh = -1;
          if (W->pdf[q] > 0.f) fl = elr_mul(elr_bsdf_f(b, wo, wi), fabsf(elr_dot(wi, b->ns)));
          if (!elr_isblack(fl)) { *sh = W->shadows.n; elr_wave_add(&W->shadows, elr_spawn_origin(&W->h[j], wi), wi, INFINITY); }
          if (k) W->fl2[j] = fl; else W->fl[j] = fl;
        }
      } else if (i >= 0) { /* elr_estimate_direct's light-sampled term (no BSDF-sampled term in the path tracer) */
        const elr_bsdf *b = &W->b[j];
        elr_v3 wo = elr_mul(p->ray.d, -1.f), wi = elr_from3(&W->wi[3 * (ne + i)]);
        float lpdf = W->pdf[ne + i];
        W->contrib[j] = elr_v(0, 0, 0);
        if (C->ls != ELR_LS_BSDF && lpdf > 0.f) {
          float bpdf;
          elr_v3 fl = elr_mul(elr_bsdf_f_pdf_inl(b, wo, wi, &bpdf), fabsf(elr_dot(wi, b->ns)));
          if (!elr_isblack(fl)) {
            float w = 1.f;
            ts->shadow++;
            if (C->ls == ELR_LS_MIS) w = elr_power_heuristic(pick * lpdf, bpdf);
            W->contrib[j] = elr_mul(elr_vmul(fl, elr_from3(&W->Le[3 * (ne + i)])), w / lpdf);
            W->shadow[j] = W->shadows.n;
            elr_wave_add(&W->shadows, elr_spawn_origin(&W->h[j], wi), wi, INFINITY);
          }
        }
      }
      if (W->psplit[j]) { /* (--sun split: the spot and sky samples' shadow rays, two a path at most: ELR_WAVE_RAYS) */
        int k;
        for (k = 2 - W->psplit[j]; k < 2; k++) W->psh[2 * j + k] = elr__split_shadow(&W->shadows, &W->h[j], &W->b[j], elr_mul(p->ray.d, -1.f), &W->pssl[2 * j + k]);
      }
    }
    elr__occluded(C, &W->shadows, ts);
    /* each path's direct light, then its next ray (<<Possibly terminate the path with Russian roulette>>), into
     * W->rays (read by the stages above: free now) */
    W->rays.n = 0;
    for (j = 0; j < m; j++) {
      elr_path_state *p = &W->p[j];
      const elr_bsdf *b = &W->b[j];
      elr_v3 wo = elr_mul(p->ray.d, -1.f), wi = W->wnext[j], f = W->fs[j];
      float pdf = W->pdfs[j];
      int spec = W->spec[j];
      if (!W->alive[j]) continue;
      if (W->light2[j] >= 0) { /* (two product light samples, each weighted 1/2, as elr_estimate_direct sums them) */
        int q1 = ne + W->light[j], q2 = ne + W->light2[j], s1 = W->shadow[j], s2 = W->shadow2[j];
        elr_v3 Ld = elr__two_term(C, &W->h[j], elr_v(0, 0, 0), W->fl[j], elr_from3(&W->wi[3 * q1]), elr_from3(&W->Le[3 * q1]), W->pdf[q1],
                                  s1 >= 0 ? W->shadows.tfar[s1] < 0.f : 0, ts);
        Ld = elr__two_term(C, &W->h[j], Ld, W->fl2[j], elr_from3(&W->wi[3 * q2]), elr_from3(&W->Le[3 * q2]), W->pdf[q2],
                           s2 >= 0 ? W->shadows.tfar[s2] < 0.f : 0, ts);
        p->L = elr_add(p->L, elr_vmul(p->beta, elr_mul(Ld, 1.f / pick)));
      } else if (W->light[j] >= 0) {
        elr_v3 Ld = elr_v(0, 0, 0);
        if (W->shadow[j] >= 0 && !(W->shadows.tfar[W->shadow[j]] < 0.f)) Ld = elr_add(Ld, W->contrib[j]);
        p->L = elr_add(p->L, elr_vmul(p->beta, elr_mul(Ld, 1.f / pick)));
      } else if (W->psplit[j]) { /* (--sun split: elr_estimate_direct's split terms, then UniformSampleOneLight's 1 / pick) */
        elr_v3 Ld = elr_v(0, 0, 0);
        int k, i;
        for (k = 2 - W->psplit[j]; k < 2; k++) {
          i = W->psh[2 * j + k];
          elr_light_term(C, &W->h[j], b, wo, &W->pssl[2 * j + k], C->ls == ELR_LS_MIS, pick, W->psother[2 * j + k], i >= 0 ? W->shadows.tfar[i] < 0.f : 0, ts, &Ld);
        }
        p->L = elr_add(p->L, elr_vmul(p->beta, elr_mul(Ld, 1.f / pick)));
      }
      if (elr_isblack(f) || pdf == 0.f) { W->alive[j] = 0; nalive--; continue; }
      p->beta = elr_mul(elr_vmul(p->beta, f), fabsf(elr_dot(wi, b->ns)) / pdf);
      p->specular = spec; p->prev_pdf = pdf;
      if (W->light[j] >= 0) { /* its sun-cache cell and the normal its light sample used (the same calls, made above) */
        int i = W->light[j];
        p->prev_sun = W->sc[i]; p->prev_has_n = W->has_n[i]; p->prev_n = W->normal[i];
      } else {
        p->prev_sun = C->sun ? elr_sun_lookup(C->sun, &W->h[j], wo) : NULL;
        p->prev_has_n = elr_sun_cos_normal(s, p->prev_sun, b, wo, &p->prev_n);
      }
      W->prevsplit[j] = C->sunsplit && C->light_sampling && (b->has_diffuse || b->has_glossy) /* (as elr_path_li's prev_split) */
                          ? elr_sunsplit_at(C->sunsplit, elr_sunsplit_light(C->sunsplit), b, p->prev_has_n ? &p->prev_n : NULL) : 0;
      p->prev_two = W->ptwo[j]; /* (as elr_path_li's prev_two: elr_path_two, 0 without light sampling there) */
      W->prevp[j] = W->h[j].p;
      if (spec == 2) p->eta_scale = elr_eta_scale(p->eta_scale, b, wo);
      if (p->depth + 1 == C->maxdepth && (!(C->has_env || C->has_area) || (!spec && C->ls == ELR_LS_LIGHT && C->light_sampling))) {
        W->alive[j] = 0; nalive--; continue;
      }
      p->ray.o = elr_spawn_origin(&W->h[j], wi); p->ray.d = wi; p->ray.has_diff = 0;
      ts->bounce++;
      {
        float mc = elr_maxc(p->beta) * p->eta_scale;
        if (p->depth > 3 && mc < C->rr) {
          elr_sampler *S = &W->S[W->pix[j]];
          float q = fmaxf(0.05f, 1.f - mc);
          elr_sampler_restore(S, &W->pos[j]);
          if (elr_sampler_get1d(S) < q) { W->alive[j] = 0; nalive--; continue; }
          elr_sampler_save(S, &W->pos[j]);
          p->beta = elr_mul(p->beta, 1.f / (1.f - q));
        }
      }
      p->depth++;
      W->ray[j] = W->rays.n; elr_wave_add(&W->rays, p->ray.o, p->ray.d, INFINITY);
    }
  }
}

/* The camera samples of tile [x0, x1) x [y0, y1) into tile, a wave at a time: whole pixels while they
 * fit (each with its own sampler), or, when a pixel has more than W->cap samples, W->cap of them
 * (then a wave is one pixel and its sampler goes on in the next). */
void elr_wave_render_tile(const elr_ctx *C, elr_wave *W, int x0, int y0, int x1, int y1, el_film_tile *tile, elr_tstats *ts) {
  int w = x1 - x0, npx = w * (y1 - y0), p = 0, k0 = 0;
  while (p < npx) {
    int m = 0, j, np = 0;
    W->rays.n = 0;
    while (p < npx && np < W->npix) {
      int x = x0 + (p % w), y = y0 + (p / w), k, take = C->spp - k0;
      elr_sampler *S = &W->S[np];
      if (take > W->cap - m) {
        if (m > 0) break;
        take = W->cap;
      }
      if (k0 == 0) elr_sampler_start_pixel(S, x, y);
      if (k0 == 0 && C->s->env_sunny && C->s->env_sun_diffuse == ELR_ENVSD_TWO_PIXEL) W->two_pix[np] = elr_two_pixel(C, x, y, ts);
      for (k = k0; k < k0 + take; k++, m++) {
        /* <<Initialize CameraSample for current sample>>, <<Generate camera ray for current sample>> */
        W->pix[m] = np;
        elr_sampler_camera_sample(S, k, x, y, &W->fx[m], &W->fy[m]);
        elr_sampler_save(S, &W->pos[m]);
        elr_camera_ray(&C->cam, W->fx[m], W->fy[m], &W->cam[m]);
        elr_wave_add(&W->rays, W->cam[m].o, W->cam[m].d, INFINITY); /* (the wave's camera rays, traced in one call below) */
        ts->camera++;
      }
      np++;
      k0 += take;
      if (k0 < C->spp) break; /* the pixel goes on in the next wave (npix is 1 then) */
      k0 = 0; p++;
    }
    elr__intersect(C, &W->rays, 1, ts);
    if (C->path) elr__path_wave(C, W, m, ts);
    else elr__direct_wave(C, W, m, ts);
    /* <<Add camera ray's contribution to image>>, in the reference's order (one film call for the wave) */
    for (j = 0; j < m; j++) {
      elr_v3 L;
      if (C->path) L = W->p[j].L;
      else if (W->fast[j] == 2) { /* (left the scene: elr_direct_first's p.L + beta Le, Le made above) */
        elr_path_state ps;
        elr_path_begin(&ps, &W->cam[j]);
        L = elr_add(ps.L, elr_vmul(ps.beta, W->Ld[j]));
      } else if (W->fast[j]) { /* elr_direct_first's sums: p.L + beta (0 + Ld / n) */
        elr_path_state ps;
        elr_path_begin(&ps, &W->cam[j]);
        L = elr_add(ps.L, elr_vmul(ps.beta, elr_add(elr_v(0, 0, 0), elr_mul(W->Ld[j], 1.f / (float)(C->direct_one ? 1 : C->batch_light->nsamples)))));
      } else {
        elr_sampler *S = &W->S[W->pix[j]];
        elr_sampler_restore(S, &W->pos[j]); /* the sampler back at sample j, after its film draw */
        ts->env_two_pixel = W->two_pix[W->pix[j]]; /* (ELR_ENVSD_TWO_PIXEL: the pixel's choice, for its later vertices) */
        L = elr_direct_first(C, S, &W->cam[j], &W->f[j], ts);
      }
      elr_to3(L, &W->rgb[3 * j]);
      ts->samples++;
    }
    el_film_tile_add_samples(tile, m, W->fx, W->fy, W->rgb, NULL);
  }
}
