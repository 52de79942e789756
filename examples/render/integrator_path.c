/* integrator_path.c: the path tracer (pbrt-v3's PathIntegrator, integrators/path.cpp; the book's section
 * 14.5).
 *
 * Next-event estimation from one light per vertex (UniformSampleOneLight, the light chosen by the
 * "lightsamplestrategy": lightdistrib.c), and the continuation ray's BSDF sample reused as the MIS
 * partner of the light sample: the environment it sees when it leaves the scene, and the area light it
 * hits, are weighted by the power heuristic of the previous vertex's BSDF pdf against the probability
 * of that light's choice times its Pdf_Li from that vertex (pbrt-v4's arrangement: one fewer ray per
 * vertex than pbrt-v3's EstimateDirect, the same expectation). For the environment that Pdf_Li is the
 * density the previous vertex's light sample had: with product sampling, pdf_li_cos with that vertex's
 * normal (elr_bsdf_cos_normal: its geometric normal on wo's side, or for a peaked metal lobe without a sun in the map
 * the mirror direction of wo), kept in prev_n. Camera rays and specular bounces see
 * emitters unweighted. pbrt-v3's Russian roulette: after 3 bounces, when the throughput's largest
 * component is below rrthreshold. Later rays carry no differentials (pbrt-v3 spawns them without), so
 * their textures are point sampled. Refraction (glass, uber's Kt) scales the radiance by (etaI / etaT)^2
 * in the BSDF (pbrt-v3's radiance transport), and Russian roulette leaves that scaling out (etaScale). */
#include "elr_internal.h"
#include <string.h>

/* pbrt-v3's PathIntegrator::Li along the path state p: a camera ray (elr_path_begin) or the rest of a
 * path already under way (its state after a first vertex shaded elsewhere). */
elr_v3 elr_path_li(const elr_ctx *C, elr_sampler *S, const elr_path_state *p, elr_tstats *ts) {
  const elr_scene *s = C->s;
  elr_v3 L = p->L, beta = p->beta;
  elr_ray r = p->ray;
  int depth, specular = p->specular, prev_has_n = p->prev_has_n;
  float prev_pdf = p->prev_pdf, eta_scale = p->eta_scale;
  elr_v3 prev_n = p->prev_n, prev_p = p->ray.o; /* prev_p: where the last light sample was drawn (portals) */
  const elr_sun_cell *prev_sun = p->prev_sun; /* and its sun-cache cell (sun.c) */
  int prev_split = 0; /* and whether it split its light sample (--sun split, sun.c: elr_sunsplit_at's answer; p is a
                         camera ray's state here: render.c's loop; the wave loop keeps its own, render_wave.c) */
  int prev_two = p->prev_two; /* and whether it took two product light samples (ELR_ENVSD_TWO(_PIXEL): elr_path_two) */
  for (depth = p->depth;; depth++) {
    elr_hit h;
    elr_bsdf b;
    elr_tex_ctx tc;
    elr_v3 wo, wi, f, dpdx, dpdy;
    float pdf, u[2];
    int spec;
    /* <<Intersect ray with scene and store intersection in isect>> */
    if (!elr_intersect(s, r.o, r.d, INFINITY, &h)) {
      /* escaped: the environment, MIS-weighted against light sampling after a non-specular bounce */
      int li;
      for (li = 0; li < s->nlight; li++) {
        const elr_light *l = &s->light[li];
        float w = 1.f;
        if (l->kind != ELR_LIGHT_INFINITE || !elr_light_emits(l)) continue;
        if (depth > 0 && !specular && C->light_sampling) {
          if (C->ls == ELR_LS_LIGHT) continue;
          if (elr_path_two_light(C, l, prev_two, prev_sun, prev_split)) continue; /* (its light sample alone: weight 0 here) */
          if (C->ls == ELR_LS_MIS) /* the light's density as the previous vertex's light sample had it: its normal */
          {
            float d[3];
            elr_to3(r.d, d);
            w = elr_power_heuristic(prev_pdf, C->ld.pick[li] * (prev_split && l == elr_sunsplit_light(C->sunsplit) ? elr_sunsplit_pdf(C->sunsplit, prev_split, prev_n, r.d)
                                                                : prev_sun && l == elr_sun_light(C->sun)
                                                                    ? elr_sun_pdf(C->sun, prev_sun, prev_has_n ? &prev_n : NULL, d)
                                                                    : elr_light_pdf_li_at(l, prev_p, prev_has_n ? &prev_n : NULL, r.d)));
          }
        }
        L = elr_add(L, elr_mul(elr_vmul(beta, elr_light_le(l, r.d)), w));
      }
      break;
    }
    /* <<Possibly add emitted light at intersection>>: an area light, weighted as the environment above */
    if (h.light >= 0) {
      elr_v3 Le = elr_hit_le(s, &h, elr_mul(r.d, -1.f));
      float w = 1.f;
      if (depth > 0 && !specular && C->light_sampling) {
        if (C->ls == ELR_LS_LIGHT) w = 0.f;
        else if (C->ls == ELR_LS_MIS) w = elr_power_heuristic(prev_pdf, C->ld.pick[h.light] * elr_area_light_pdf(s, &s->light[h.light], r.o, &h));
      }
      L = elr_add(L, elr_mul(elr_vmul(beta, Le), w));
    }
    /* <<Terminate path if maxDepth was reached>> */
    if (depth >= C->maxdepth) break;
    /* <<Compute scattering functions and skip over medium boundaries>> */
    if (depth == 0) elr_compute_differentials(s, &r, &h, &tc, &dpdx, &dpdy);
    else {
      memset(&tc, 0, sizeof tc);
      if (s->mat_textured[h.material]) { elr_hit_uv(s, &h); tc.u = h.u; tc.v = h.v; }
    }
    elr_bsdf_init(s, &h, &tc, &b);
    wo = elr_mul(r.d, -1.f);
    /* <<Sample illumination from lights to find path contribution>> */
    if (C->light_sampling && (b.has_diffuse || b.has_glossy))
      L = elr_add(L, elr_vmul(beta, elr_uniform_sample_one_light(C, S, &h, &b, wo, 0, ts)));
    /* <<Sample BSDF to get new path direction>> */
    elr_sampler_get2d(S, u);
    f = elr_bsdf_sample(&b, wo, u[0], u[1], &wi, &pdf, &spec);
    if (elr_isblack(f) || pdf == 0.f) break;
    beta = elr_mul(elr_vmul(beta, f), fabsf(elr_dot(wi, b.ns)) / pdf);
    specular = spec; prev_pdf = pdf;
    prev_p = h.p;
    prev_sun = C->sun ? elr_sun_lookup(C->sun, &h, wo) : NULL;
    prev_has_n = elr_sun_cos_normal(s, prev_sun, &b, wo, &prev_n); /* the normal this vertex's light sample used */
    prev_split = C->sunsplit && C->light_sampling && (b.has_diffuse || b.has_glossy) ? elr_sunsplit_at(C->sunsplit, elr_sunsplit_light(C->sunsplit), &b, prev_has_n ? &prev_n : NULL) : 0;
    prev_two = elr_path_two(C, &b, wo, ts);
    if (spec == 2) eta_scale = elr_eta_scale(eta_scale, &b, wo); /* a specular transmission */
    /* the last vertex's continuation only matters for the emitters' BSDF-sampled part */
    if (depth + 1 == C->maxdepth && (!(C->has_env || C->has_area) || (!spec && C->ls == ELR_LS_LIGHT && C->light_sampling))) break;
    r.o = elr_spawn_origin(&h, wi); r.d = wi; r.has_diff = 0;
    ts->bounce++;
    { /* <<Possibly terminate the path with Russian roulette>> (pbrt-v3: after bounce 3; rrBeta = beta etaScale:
       * the radiance scaling of refraction left out, so that a ray about to leave glass is not ended) */
      float mc = elr_maxc(beta) * eta_scale;
      if (depth > 3 && mc < C->rr) {
        float q = fmaxf(0.05f, 1.f - mc);
        if (elr_sampler_get1d(S) < q) break;
        beta = elr_mul(beta, 1.f / (1.f - q));
      }
    }
  }
  return L;
}
