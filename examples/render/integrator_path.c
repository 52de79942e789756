/* integrator_path.c: the path tracer (pbrt-v3's PathIntegrator, integrators/path.cpp; the book's section
 * 14.5).
 *
 * Next-event estimation from every light at every vertex, one sample each (UniformSampleAllLights;
 * pbrt-v3 samples one light per vertex, chosen by "lightsamplestrategy", which is the same estimator
 * for a scene of one light), and the continuation ray's BSDF sample reused as the MIS partner of the
 * light sample: when it leaves
 * the scene, the environment it sees is weighted by the power heuristic against light sampling
 * (pbrt-v4's arrangement: one fewer ray per vertex than pbrt-v3's EstimateDirect, the same
 * expectation). pbrt-v3's Russian roulette: after 3 bounces, when the throughput's largest component
 * is below rrthreshold. Later rays carry no differentials (pbrt-v3 spawns them without), so their
 * textures are point sampled. Area lights hit by the path would add their emission here, MIS-weighted
 * in the same way (the previous vertex's BSDF pdf against the light's Pdf_Li from it). */
#include "elr_internal.h"
#include <string.h>

/* pbrt-v3's PathIntegrator::Li along the path state p: a camera ray (elr_path_begin) or the rest of a
 * path whose first vertex render_batched.c shaded. */
elr_v3 elr_path_li(const elr_ctx *C, elr_sampler *S, const elr_path_state *p, elr_tstats *ts) {
  const elr_scene *s = C->s;
  elr_v3 L = p->L, beta = p->beta;
  elr_ray r = p->ray;
  int depth, specular = p->specular;
  float prev_pdf = p->prev_pdf;
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
          if (C->ls == ELR_LS_MIS) w = elr_power_heuristic(prev_pdf, elr_light_pdf_li(l, NULL, r.d));
        }
        L = elr_add(L, elr_mul(elr_vmul(beta, elr_light_le(l, r.d)), w));
      }
      break;
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
      L = elr_add(L, elr_vmul(beta, elr_uniform_sample_all_lights(C, S, &h, &b, wo, 0, 0, ts)));
    /* <<Sample BSDF to get new path direction>> */
    elr_sampler_get2d(S, u);
    f = elr_bsdf_sample(&b, wo, u[0], u[1], &wi, &pdf, &spec);
    if (elr_isblack(f) || pdf == 0.f) break;
    beta = elr_mul(elr_vmul(beta, f), fabsf(elr_dot(wi, b.ns)) / pdf);
    specular = spec; prev_pdf = pdf;
    /* the last vertex's continuation only matters for the environment's BSDF-sampled part */
    if (depth + 1 == C->maxdepth && (!C->has_env || (!spec && C->ls == ELR_LS_LIGHT && C->light_sampling))) break;
    r.o = elr_spawn_origin(&h, wi); r.d = wi; r.has_diff = 0;
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
