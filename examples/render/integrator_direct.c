/* integrator_direct.c: pbrt-v3's DirectLightingIntegrator (integrators/directlighting.cpp; the book's
 * section 14.3).
 *
 * At each hit, the light from every light source by pbrt-v3's strategy "all" (UniformSampleAllLights:
 * each light's "samples" count, light and BSDF sampling combined with the power heuristic), then the
 * specular reflection followed up to maxdepth. The Integrator directive's "strategy" "one" is not
 * implemented (the parser warns, and "all" is used). Emission of hit surfaces (area lights, pbrt-v3's
 * isect.Le) would be added at each hit. */
#include "elr_internal.h"

/* pbrt-v3's DirectLightingIntegrator::Li along the path state p: a camera ray (elr_path_begin) or the
 * rest of a path whose first vertex render_batched.c shaded. Its SpecularReflect recursion has one
 * branch (no material here transmits), so it runs as a loop carrying the throughput beta: no stack
 * growth whatever maxdepth says. */
elr_v3 elr_direct_li(const elr_ctx *C, elr_sampler *S, const elr_path_state *p, elr_tstats *ts) {
  const elr_scene *s = C->s;
  elr_v3 L = p->L, beta = p->beta;
  elr_ray r = p->ray;
  int depth;
  for (depth = p->depth;; depth++) {
    elr_hit h;
    elr_bsdf b;
    elr_tex_ctx tc;
    elr_v3 wo, dpdx, dpdy;
    /* <<Find closest ray intersection or return background radiance>> */
    if (!elr_intersect(s, r.o, r.d, INFINITY, &h)) return elr_add(L, elr_vmul(beta, elr_infinite_le(s, r.d)));
    /* <<Compute scattering functions for surface interaction>> */
    elr_compute_differentials(s, &r, &h, &tc, &dpdx, &dpdy);
    elr_bsdf_init(s, &h, &tc, &b);
    wo = elr_mul(r.d, -1.f);
    /* <<Compute direct lighting for DirectLightingIntegrator integrator>> */
    if (C->light_sampling && (b.has_diffuse || b.has_glossy))
      L = elr_add(L, elr_vmul(beta, elr_uniform_sample_all_lights(C, S, &h, &b, wo, 1, 1, ts)));
    /* <<Trace rays for specular reflection and refraction>> */
    if (!(depth + 1 < C->maxdepth && b.has_specular)) break;
    if (!elr_specular_reflect(C, S, &r, &h, &tc, dpdx, dpdy, &b, &r, &beta, ts)) break;
  }
  return L;
}
