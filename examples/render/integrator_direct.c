/* integrator_direct.c: pbrt-v3's DirectLightingIntegrator (integrators/directlighting.cpp; the book's
 * section 14.3).
 *
 * At each hit, the radiance the surface emits (an area light: pbrt-v3's isect.Le), then the light from
 * the light sources by pbrt-v3's strategy "all" (UniformSampleAllLights: each light's "samples"
 * count, light and BSDF sampling combined with the power heuristic) or "one" (UniformSampleOneLight:
 * one light chosen uniformly, one sample of each), then the specular reflection and transmission
 * followed up to maxdepth. */
#include "elr_internal.h"

/* The branches of the recursion that one call follows at most (each vertex of glass makes two), and
 * how many are kept waiting: past these, elr_direct_specular follows one of the two at random. */
#define ELR_DIRECT_SPLITS 64
#define ELR_DIRECT_PENDING 32

/* pbrt-v3's DirectLightingIntegrator::Li along the path state p: a camera ray (elr_path_begin) or the
 * rest of a path whose first vertex render_wave.c shaded. Its recursion (SpecularReflect, then
 * SpecularTransmit) runs as a loop carrying the throughput beta, with the transmitted branches of
 * glass waiting on a small stack: no stack growth whatever maxdepth says. */
elr_v3 elr_direct_li(const elr_ctx *C, elr_sampler *S, const elr_path_state *p, elr_tstats *ts) { return elr_direct_li_branches(C, S, p, NULL, 0, 0, ts); }

/* the same with branches already waiting (render_wave.c: those of a first vertex shaded ahead) and
 * splits already made */
elr_v3 elr_direct_li_branches(const elr_ctx *C, elr_sampler *S, const elr_path_state *p, const elr_path_state *waiting, int nwaiting,
                              int splits, elr_tstats *ts) {
  const elr_scene *s = C->s;
  elr_v3 L = p->L, beta = p->beta;
  elr_ray r = p->ray;
  elr_path_state pending[ELR_DIRECT_PENDING];
  int depth = p->depth, npending = 0;
  for (; npending < nwaiting && npending < ELR_DIRECT_PENDING; npending++) pending[npending] = waiting[npending];
  for (;;) {
    elr_hit h;
    elr_bsdf b;
    elr_tex_ctx tc;
    elr_v3 wo, dpdx, dpdy;
    elr_path_state next[2];
    int n;
    /* <<Find closest ray intersection or return background radiance>> */
    if (!elr_intersect(s, r.o, r.d, INFINITY, &h)) {
      L = elr_add(L, elr_vmul(beta, elr_infinite_le(s, r.d)));
    } else {
      /* <<Compute scattering functions for surface interaction>> */
      elr_compute_differentials(s, &r, &h, &tc, &dpdx, &dpdy);
      elr_bsdf_init(s, &h, &tc, &b);
      wo = elr_mul(r.d, -1.f);
      /* <<Compute emitted light if ray hit an area light source>> */
      if (h.light >= 0) L = elr_add(L, elr_vmul(beta, elr_hit_le(s, &h, wo)));
      /* <<Compute direct lighting for DirectLightingIntegrator integrator>> */
      if (C->light_sampling && (b.has_diffuse || b.has_glossy))
        L = elr_add(L, elr_vmul(beta, C->direct_one ? elr_uniform_sample_one_light(C, S, &h, &b, wo, 1, ts)
                                                    : elr_uniform_sample_all_lights(C, S, &h, &b, wo, 1, 1, ts)));
      /* <<Trace rays for specular reflection and refraction>> */
      if (depth + 1 < C->maxdepth && (b.spec_r || b.spec_t)) {
        n = elr_direct_specular(C, S, &r, &h, &tc, dpdx, dpdy, &b, beta, depth, splits < ELR_DIRECT_SPLITS && npending < ELR_DIRECT_PENDING,
                                next, ts);
        if (n == 2) { pending[npending++] = next[1]; splits++; }
        if (n >= 1) { r = next[0].ray; beta = next[0].beta; depth = next[0].depth; continue; }
      }
    }
    /* this branch is done: the next one waiting, if any */
    if (npending == 0) return L;
    npending--;
    r = pending[npending].ray; beta = pending[npending].beta; depth = pending[npending].depth;
  }
}

/* ELR_ENVSD_TWO_PIXEL: pixel (x, y)'s choice for all its samples (so that they keep one strategy and their
 * nets; made at the pixel's start by render.c's reference loop and render_wave.c): 1 (two product light samples) when the camera ray through its centre misses the scene, or its hit
 * sees the sun's axis (the brightest texel's direction) or has it below the geometric horizon on the
 * camera's side; 0 (product MIS) when the scene hides the sun there. Two rays per pixel, counted. */
int elr_two_pixel(const elr_ctx *C, int x, int y, elr_tstats *ts) {
  const elr_scene *s = C->s;
  elr_ray r;
  elr_hit h;
  elr_v3 a = s->env_sun_axis, ng;
  elr_camera_ray(&C->cam, (float)x + 0.5f, (float)y + 0.5f, &r);
  ts->camera++;
  if (!elr_intersect(s, r.o, r.d, INFINITY, &h)) return 1;
  ng = elr_dot(r.d, h.ng) > 0.f ? elr_mul(h.ng, -1.f) : h.ng;
  if (!(elr_dot(a, ng) > 0.f)) return 1;
  ts->shadow++;
  return !elr_occluded(s, elr_spawn_origin(&h, a), a, INFINITY);
}
