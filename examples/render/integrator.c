/* integrator.c: what both integrators share (pbrt-v3 core/integrator.cpp; the book's section 14.3,
 * Direct Lighting).
 *
 *   elr_estimate_direct             EstimateDirect: one light, one light sample and one BSDF sample,
 *                                   combined with the power heuristic (MIS)
 *   elr_uniform_sample_all_lights   UniformSampleAllLights: every light, with its own sample count
 *   elr_uniform_sample_one_light    UniformSampleOneLight: one light chosen by the light distribution
 *   elr_specular_reflect            SpecularReflect: the mirror bounce and its ray differentials
 *   elr_specular_transmit           SpecularTransmit: the refracted bounce and its ray differentials
 *   elr_direct_specular             both, at a vertex of the direct-lighting integrator
 *   elr_infinite_le                 the radiance of the lights at infinity along a ray that leaves
 *   elr_light_unoccluded            VisibilityTester::Unoccluded: a light sample's shadow ray
 *
 * This is the reference a port follows: one light sample at a time, in pbrt-v3's order. The render
 * loop (render.c) calls the integrators of integrator_direct.c and integrator_path.c per camera
 * sample; render_wave.c is the faster arrangement of the same computation for scenes lit by the
 * environment alone. The light interface (lights.c) hides which kind of light is sampled, except in
 * EstimateDirect's BSDF-sampled term: for an area light it needs the ray's hit (is it this light?),
 * where the environment only needs to know that nothing is in the way. */
#include "elr_internal.h"

/* The environment along a ray that leaves the scene in direction d: every emitting infinite light's Le
 * (pbrt-v3's loop over scene.infiniteLights). */
elr_v3 elr_infinite_le(const elr_scene *s, elr_v3 d) {
  int i;
  elr_v3 L = elr_v(0, 0, 0);
  for (i = 0; i < s->nlight; i++)
    if (s->light[i].kind == ELR_LIGHT_INFINITE && elr_light_emits(&s->light[i])) L = elr_add(L, elr_light_le(&s->light[i], d));
  return L;
}

/* pbrt-v3's VisibilityTester::Unoccluded for a light sample taken at h: the shadow ray from h's offset
 * origin towards the light, ending just before a point light or the sampled point of an area light, and
 * past the scene for the others. It lives here, with the integrators that trace it, so that lights.c
 * never calls into the scene (test_render_layout checks it). For an area light the ray aims at the point
 * from the offset origin (pbrt-v3's SpawnRayTo): along wi, a ray that meets the light's surface at a
 * grazing angle would enter it before the point (the origin's offset, 2e-5 of the coordinates, moves the
 * entry by that over the cosine: 0.3% of a sphere light's samples were lost so, at 3 radii, before this). */
int elr_light_unoccluded(const elr_scene *s, const elr_hit *h, const elr_light_sample *ls) {
  elr_v3 o = elr_spawn_origin(h, ls->wi), d;
  float dist;
  if (ls->at_point != 2) {
    float tmax = ls->at_point ? elr_len(elr_sub(ls->p_light, o)) * (1.f - 1e-4f) : ls->dist;
    return !elr_occluded(s, o, ls->wi, tmax);
  }
  d = elr_sub(ls->p_light, o);
  dist = elr_len(d);
  return !(dist > 0.f) || !elr_occluded(s, o, elr_mul(d, 1.f / dist), dist * (1.f - 1e-4f));
}

/* <<Compute BSDF value for light sample>>, the shadow ray and <<Add light's contribution to reflected
 * radiance>> for light sample ls: the power heuristic of pick x its pdf against the BSDF's (when mis)
 * and pick x other, the density of another light technique in its direction (--sun split; 0: none);
 * occ the shadow ray's answer when the caller traced it (the wave loop: 1 occluded, 0 not), -1: traced here */
void elr_light_term(const elr_ctx *C, const elr_hit *h, const elr_bsdf *b, elr_v3 wo, const elr_light_sample *ls, int mis, float pick,
                    float other, int occ, elr_tstats *ts, elr_v3 *Ld) {
  elr_v3 f;
  if (!(ls->pdf > 0.f)) return;
  f = elr_mul(elr_bsdf_f(b, wo, ls->wi), fabsf(elr_dot(ls->wi, b->ns)));
  if (elr_isblack(f)) return;
  ts->shadow++;
  if (occ >= 0 ? !occ : elr_light_unoccluded(C->s, h, ls)) {
    float pb = mis ? elr_bsdf_pdf(b, wo, ls->wi) : 0.f, po = pick * other;
    float w = mis || po > 0.f ? elr_power_heuristic(pick * ls->pdf, po > 0.f ? sqrtf(pb * pb + po * po) : pb) : 1.f;
    *Ld = elr_add(*Ld, elr_mul(elr_vmul(f, ls->L), w / ls->pdf));
  }
}

/* pbrt-v3's EstimateDirect at hit h (BSDF b, outgoing direction wo) for light l, with the 2D numbers
 * ul (the light sample) and us (the BSDF sample). Adds the light-sampled term, then the BSDF-sampled
 * term to *Ld. C->ls chooses the strategies (MIS, light only, BSDF only); delta lights take light
 * sampling alone, and sample_bsdf = 0 leaves out the BSDF-sampled term (the path tracer, whose
 * continuation ray plays that part: its MIS partner can reach any light, so the light sample's weight
 * compares the BSDF's pdf with pick, the probability that l was chosen, times the light's; pbrt-v3's
 * own pair of samples is drawn for l alone: pick 1). */
void elr_estimate_direct(const elr_ctx *C, const elr_hit *h, const elr_bsdf *b, elr_v3 wo, const elr_light *l, const float ul[2],
                         const float us[2], int sample_bsdf, float pick, elr_tstats *ts, elr_v3 *Ld) {
  const elr_scene *s = C->s;
  int delta = elr_light_is_delta(l);
  /* the normal of the environment's product sampling at this vertex (NULL: the BSDF transmits); the
   * BSDF sample's MIS weight below uses the same one, so both pdfs are the same density */
  /* (issue 22, sun.c: where the pilot found the map's hot spots hidden, a density that draws them less) */
  int sunl = C->sun && l == elr_sun_light(C->sun);
  const elr_sun_cell *sc = sunl ? elr_sun_lookup(C->sun, h, wo) : NULL;
  elr_v3 nc;
  const elr_v3 *n = elr_sun_cos_normal(s, sc, b, wo, &nc) ? &nc : NULL;
  /* (--sun split, sun.c: a spot sample and a sky sample, 2; the sky alone, 1; 0: the light's density) */
  int split = C->sunsplit && C->ls != ELR_LS_BSDF ? elr_sunsplit_at(C->sunsplit, l, b, n) : 0;
  /* issue 20: the product light sample alone where the lobes are diffuse or broad (elr_env_light_only) */
  int lonly = !sc && !split && elr_env_light_only(C->ls == ELR_LS_MIS, sample_bsdf, l, n != NULL, b); /* (sun.c, split: MIS kept) */
  /* ELR_ENVSD_TWO: a second product light sample from the BSDF sample's numbers, each weighted 1/2 */
  /* (the path tracer: the second from UniformSampleOneLight's BSDF draw, elr_path_two) */
  int two = !sc && !split && elr_env_two(C->ls == ELR_LS_MIS, sample_bsdf || C->path, l, n != NULL, b), kt;
  if (two && s->env_sun_diffuse == ELR_ENVSD_TWO_PIXEL) two = ts->env_two_pixel > 0; /* (the pixel's choice: render.c) */
  if (two) lonly = 1;
  /* <<Sample light source with multiple importance sampling>> */
  if (split) {
    elr_light_sample ls;
    float other;
    int k;
    ts->sunsplit_vertices++; ts->sunsplit_sky_only += (uint64_t)(split == 1);
    for (k = 2 - split; k < 2; k++) {
      elr_sunsplit_sample(C->sunsplit, k, split, nc, ul, &ls, &other, ts); /* (one u for both: sun.c) */
      elr_light_term(C, h, b, wo, &ls, C->ls == ELR_LS_MIS, pick, other, -1, ts, Ld);
    }
  } else if (delta || C->ls != ELR_LS_BSDF) for (kt = 0; kt <= two; kt++) {
    elr_light_sample ls;
    if (kt) ul = us;
    if (l->kind == ELR_LIGHT_INFINITE && l->product) { if (n) ts->env_product++; else ts->env_map++; ts->env_light_only += (uint64_t)lonly; } /* (--stats) */
    if (sc) elr_sun_light_sample(C->sun, sc, n, ul, &ls, ts);
    else {
      elr_light_sample_li(l, s, h->p, n, ul, &ls);
      if (sunl) { float d[3]; elr_to3(ls.wi, d); elr_sun_count(C->sun, NULL, d, ls.pdf, ts); }
    }
    if (ls.portal >= 0) { if (ls.portal) ts->portal_used++; else ts->portal_fallback++; }
    {
      elr_v3 Lt = elr_v(0, 0, 0); /* (two: each sample's term, weighted 1/2) */
      elr_light_term(C, h, b, wo, &ls, !delta && C->ls == ELR_LS_MIS && !lonly, pick, 0.f, -1, ts, two ? &Lt : Ld);
      if (two) *Ld = elr_add(*Ld, elr_mul(Lt, 0.5f));
    }
  }
  /* <<Sample BSDF with multiple importance sampling>> */
  if (!delta && sample_bsdf && C->ls != ELR_LS_LIGHT && !lonly) {
    elr_v3 wi, f;
    float pdf;
    int spec;
    f = elr_bsdf_sample(b, wo, us[0], us[1], &wi, &pdf, &spec);
    if (!spec && pdf > 0.f && !elr_isblack(f)) {
      f = elr_mul(f, fabsf(elr_dot(wi, b->ns)));
      ts->bsdfl++;
      if (l->kind == ELR_LIGHT_AREA) {
        /* <<Find intersection and compute transmittance>>, <<Add light contribution from material
         * sampling>>: the ray's first hit must be this light's shape (its Pdf_Li from that hit) */
        elr_hit lh;
        if (elr_intersect(s, elr_spawn_origin(h, wi), wi, INFINITY, &lh) && lh.light == (int)(l - s->light)) {
          elr_v3 Li = elr_hit_le(s, &lh, elr_mul(wi, -1.f));
          float w = 1.f;
          if (C->ls == ELR_LS_MIS) w = elr_power_heuristic(pdf, elr_area_light_pdf(s, l, h->p, &lh));
          *Ld = elr_add(*Ld, elr_mul(elr_vmul(f, Li), w / pdf));
        }
        return;
      }
      /* the light's pdf and radiance in direction wi are read after the shadow ray: their cache lines
       * (texels, pdf bin: misses in multi-megabyte tables) are asked for now and arrive meanwhile */
      elr_light_prefetch(l, wi);
      /* <<Find intersection and compute transmittance>>: the environment is reached when nothing is in
       * the way (pbrt-v3 returns when Pdf_Li is 0; with envlight's compensated density that would drop
       * the dim parts of the map, which only BSDF sampling covers: the power heuristic gives them 1) */
      if (!elr_occluded(s, elr_spawn_origin(h, wi), wi, INFINITY)) {
        float w = 1.f;
        if (C->ls == ELR_LS_MIS) {
          float d[3];
          elr_to3(wi, d);
          w = elr_power_heuristic(pdf, split ? elr_sunsplit_pdf(C->sunsplit, split, nc, wi)
                                       : sc  ? elr_sun_pdf(C->sun, sc, n, d)
                                             : elr_light_pdf_li_at(l, h->p, n, wi));
        }
        /* <<Add light contribution from material sampling>> */
        *Ld = elr_add(*Ld, elr_mul(elr_vmul(f, elr_light_le(l, wi)), w / pdf));
      }
    }
  }
}

/* ELR_ENVSD_TWO(_PIXEL) in the path tracer: 1 where elr_estimate_direct at this vertex (BSDF b, wo) takes an
 * environment's two product light samples (elr_env_two's conditions but the light's, the pixel's choice), so that
 * the continuation ray, when it leaves the scene, gives that light nothing (elr_path_two_light: the light's part,
 * with the vertex's sun-cache cell and split as elr_estimate_direct finds them for that light) */
int elr_path_two(const elr_ctx *C, const elr_bsdf *b, elr_v3 wo, const elr_tstats *ts) {
  elr_v3 n;
  if (!C->light_sampling || !(b->has_diffuse || b->has_glossy) || C->ls != ELR_LS_MIS || !b->env_two) return 0;
  if (C->s->env_sun_diffuse == ELR_ENVSD_TWO_PIXEL && !(ts->env_two_pixel > 0)) return 0;
  return elr_bsdf_cos_normal(b, wo, &n);
}
int elr_path_two_light(const elr_ctx *C, const elr_light *l, int prev_two, const elr_sun_cell *prev_sun, int prev_split) {
  return prev_two && elr_env_two_light(l) && !(prev_sun && l == elr_sun_light(C->sun)) && !(prev_split && l == elr_sunsplit_light(C->sunsplit));
}

/* pbrt-v3's UniformSampleAllLights: the direct light at h from every light that emits, each light's
 * estimate the average of its own number of samples (use_counts: its "samples" parameter, as the
 * directlighting integrator; else one). */
elr_v3 elr_uniform_sample_all_lights(const elr_ctx *C, elr_sampler *S, const elr_hit *h, const elr_bsdf *b, elr_v3 wo, int use_counts,
                                     int sample_bsdf, elr_tstats *ts) {
  const elr_scene *s = C->s;
  elr_v3 L = elr_v(0, 0, 0);
  int li;
  for (li = 0; li < s->nlight; li++) {
    const elr_light *l = &s->light[li];
    int n = use_counts ? l->nsamples : 1, k;
    elr_v3 Ld = elr_v(0, 0, 0);
    if (!elr_light_emits(l)) continue;
    for (k = 0; k < n; k++) {
      float ul[2], us[2];
      elr_sampler_get2d(S, ul);
      elr_sampler_get2d(S, us);
      elr_estimate_direct(C, h, b, wo, l, ul, us, sample_bsdf, 1.f, ts, &Ld);
    }
    L = elr_add(L, elr_mul(Ld, 1.f / (float)n));
  }
  return L;
}

/* pbrt-v3's UniformSampleOneLight: one light chosen by C->ld (the path tracer's lightsamplestrategy;
 * uniform for directlighting's strategy "one"), one EstimateDirect for it, divided by the probability
 * of the choice. With a single emitting light no number is drawn for the choice. */
elr_v3 elr_uniform_sample_one_light(const elr_ctx *C, elr_sampler *S, const elr_hit *h, const elr_bsdf *b, elr_v3 wo, int sample_bsdf,
                                    elr_tstats *ts) {
  const elr_light *l;
  elr_v3 Ld = elr_v(0, 0, 0);
  float pick, ul[2], us[2];
  if (C->ld.n == 0) return Ld;
  /* <<Randomly choose a single light to sample, light>> */
  l = elr_light_distrib_sample(&C->ld, C->s, C->ld.n > 1 ? elr_sampler_get1d(S) : 0.f, &pick);
  elr_sampler_get2d(S, ul);
  elr_sampler_get2d(S, us);
  elr_estimate_direct(C, h, b, wo, l, ul, us, sample_bsdf, sample_bsdf ? 1.f : pick, ts, &Ld);
  return elr_mul(Ld, 1.f / pick);
}

/* pbrt-v3's SpecularReflect up to its recursion: the mirror direction at h (ray r arrived, BSDF b,
 * texture footprint tc with dp/dx, dp/dy) as the next ray *rd, with ray differentials when r has
 * them, and the throughput *beta times f |cos| / pdf. Returns 0 when there is nothing to follow. */
int elr_specular_reflect(const elr_ctx *C, elr_sampler *S, const elr_ray *r, const elr_hit *h, const elr_tex_ctx *tc, elr_v3 dpdx,
                         elr_v3 dpdy, const elr_bsdf *b, elr_ray *rd, elr_v3 *beta, elr_tstats *ts) {
  elr_v3 wo = elr_mul(r->d, -1.f), wi, f;
  elr_ray out;
  float pdf, u[2];
  int spec;
  /* <<Compute specular reflection direction wi and BSDF value>> */
  elr_sampler_get2d(S, u);
  if (b->nlobes) { /* pbrt-v3's Sample_f with type BSDF_REFLECTION | BSDF_SPECULAR */
    f = elr_bsdf_sample_type(b, wo, u[0], u[1], ELR_BSDF_REFLECTION | ELR_BSDF_SPECULAR, &wi, &pdf, &spec);
    spec &= ELR_BSDF_SPECULAR;
  } else {
    f = elr_bsdf_sample(b, wo, u[0], u[1], &wi, &pdf, &spec);
  }
  if (!(spec && pdf > 0.f && !elr_isblack(f) && elr_dot(wi, b->ns) != 0.f)) return 0;
  out.o = elr_spawn_origin(h, wi); out.d = wi; out.has_diff = 0;
  if (r->has_diff && C->s->any_textured) {
    /* <<Compute ray differential rd for specular reflection>> */
    elr_v3 ns = b->ns;
    elr_v3 dndx = elr_add(elr_mul(h->dndu, tc->dudx), elr_mul(h->dndv, tc->dvdx));
    elr_v3 dndy = elr_add(elr_mul(h->dndu, tc->dudy), elr_mul(h->dndv, tc->dvdy));
    elr_v3 dwodx = elr_sub(elr_mul(r->rxd, -1.f), wo), dwody = elr_sub(elr_mul(r->ryd, -1.f), wo);
    float dDNdx = elr_dot(dwodx, ns) + elr_dot(wo, dndx), dDNdy = elr_dot(dwody, ns) + elr_dot(wo, dndy);
    out.has_diff = 1;
    out.rxo = elr_add(out.o, dpdx); out.ryo = elr_add(out.o, dpdy);
    out.rxd = elr_add(elr_sub(wi, dwodx), elr_mul(elr_add(elr_mul(dndx, elr_dot(wo, ns)), elr_mul(ns, dDNdx)), 2.f));
    out.ryd = elr_add(elr_sub(wi, dwody), elr_mul(elr_add(elr_mul(dndy, elr_dot(wo, ns)), elr_mul(ns, dDNdy)), 2.f));
  }
  ts->bounce++;
  *beta = elr_mul(elr_vmul(*beta, f), fabsf(elr_dot(wi, b->ns)) / pdf);
  *rd = out;
  return 1;
}

/* pbrt-v3's SpecularTransmit up to its recursion: the refracted direction at h as the next ray *rd
 * (with pbrt-v3's ray differentials for refraction when r has them) and the throughput *beta times
 * f |cos| / pdf (f carries the radiance scaling (etaI / etaT)^2). Returns 0 when nothing transmits. */
int elr_specular_transmit(const elr_ctx *C, elr_sampler *S, const elr_ray *r, const elr_hit *h, const elr_tex_ctx *tc, elr_v3 dpdx,
                          elr_v3 dpdy, const elr_bsdf *b, elr_ray *rd, elr_v3 *beta, elr_tstats *ts) {
  elr_v3 wo = elr_mul(r->d, -1.f), wi, f, ns = b->ns;
  elr_ray out;
  float pdf, u[2];
  int flags;
  elr_sampler_get2d(S, u);
  f = elr_bsdf_sample_type(b, wo, u[0], u[1], ELR_BSDF_TRANSMISSION | ELR_BSDF_SPECULAR, &wi, &pdf, &flags);
  if (!(pdf > 0.f && !elr_isblack(f) && elr_dot(wi, ns) != 0.f)) return 0;
  out.o = elr_spawn_origin(h, wi); out.d = wi; out.has_diff = 0;
  if (r->has_diff && C->s->any_textured) {
    /* <<Compute ray differential rd for specular transmission>> */
    elr_v3 dndx = elr_add(elr_mul(h->dndu, tc->dudx), elr_mul(h->dndv, tc->dvdx));
    elr_v3 dndy = elr_add(elr_mul(h->dndu, tc->dudy), elr_mul(h->dndv, tc->dvdy));
    elr_v3 dwodx, dwody;
    float eta = 1.f / b->eta, dDNdx, dDNdy, mu, cwi, dmudx, dmudy;
    if (elr_dot(wo, ns) < 0.f) { /* leaving: the relative index inverted, the normal and its derivatives turned */
      eta = 1.f / eta; ns = elr_mul(ns, -1.f); dndx = elr_mul(dndx, -1.f); dndy = elr_mul(dndy, -1.f);
    }
    dwodx = elr_sub(elr_mul(r->rxd, -1.f), wo); dwody = elr_sub(elr_mul(r->ryd, -1.f), wo);
    dDNdx = elr_dot(dwodx, ns) + elr_dot(wo, dndx); dDNdy = elr_dot(dwody, ns) + elr_dot(wo, dndy);
    cwi = fabsf(elr_dot(wi, ns));
    mu = eta * elr_dot(wo, ns) - cwi;
    dmudx = (eta - (eta * eta * elr_dot(wo, ns)) / cwi) * dDNdx;
    dmudy = (eta - (eta * eta * elr_dot(wo, ns)) / cwi) * dDNdy;
    out.has_diff = 1;
    out.rxo = elr_add(out.o, dpdx); out.ryo = elr_add(out.o, dpdy);
    out.rxd = elr_add(elr_sub(wi, elr_mul(dwodx, eta)), elr_add(elr_mul(dndx, mu), elr_mul(ns, dmudx)));
    out.ryd = elr_add(elr_sub(wi, elr_mul(dwody, eta)), elr_add(elr_mul(dndy, mu), elr_mul(ns, dmudy)));
  }
  ts->bounce++;
  *beta = elr_mul(elr_vmul(*beta, f), fabsf(elr_dot(wi, b->ns)) / pdf);
  *rd = out;
  return 1;
}

/* The direct-lighting integrator's specular continuations at h (pbrt-v3's DirectLightingIntegrator::Li:
 * SpecularReflect, then SpecularTransmit): up to two next path states (ray, throughput, depth + 1) in
 * out, their number returned. pbrt-v3 follows both, so glass doubles the rays at every vertex; where the
 * caller has no room left for that (allow_split = 0), one of the two is followed, chosen with a sampler
 * draw in proportion to its throughput's largest component and divided by that probability (the same
 * expectation, a bounded cost). */
int elr_direct_specular(const elr_ctx *C, elr_sampler *S, const elr_ray *r, const elr_hit *h, const elr_tex_ctx *tc, elr_v3 dpdx,
                        elr_v3 dpdy, const elr_bsdf *b, elr_v3 beta, int depth, int allow_split, elr_path_state out[2], elr_tstats *ts) {
  int n = 0;
  if (b->spec_r) {
    out[n].beta = beta;
    if (elr_specular_reflect(C, S, r, h, tc, dpdx, dpdy, b, &out[n].ray, &out[n].beta, ts)) out[n++].depth = depth + 1;
  }
  if (b->spec_t) {
    out[n].beta = beta;
    if (elr_specular_transmit(C, S, r, h, tc, dpdx, dpdy, b, &out[n].ray, &out[n].beta, ts)) out[n++].depth = depth + 1;
  }
  if (n == 2 && !allow_split) {
    float m0 = elr_maxc(out[0].beta), m1 = elr_maxc(out[1].beta), p0 = m0 + m1 > 0.f ? m0 / (m0 + m1) : 0.5f;
    if (elr_sampler_get1d(S) < p0) out[0].beta = elr_mul(out[0].beta, 1.f / p0);
    else { out[0] = out[1]; out[0].beta = elr_mul(out[0].beta, 1.f / (1.f - p0)); }
    ts->bounce--; /* one of the two rays is not traced */
    n = 1;
  }
  return n;
}
