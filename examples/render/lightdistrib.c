/* lightdistrib.c: which light next-event estimation samples (pbrt-v3 core/lightdistrib.cpp: the
 * LightDistribution behind the path integrator's "lightsamplestrategy", and integrators/directlighting's
 * strategy "one", which is pbrt-v3's UniformSampleOneLight without a distribution: uniform).
 *
 *   "uniform"  every light of pbrt-v3 equally likely (UniformLightDistribution). pbrt-v3 makes one light
 *              per triangle of an emitting mesh; here a mesh is one light, so it weighs as many lights as
 *              it has triangles: the same chance of picking the mesh as pbrt-v3's.
 *   "power"    in proportion to each light's Power().y() (PowerLightDistribution, via elr_light_power):
 *              a mesh's power is that of its triangles together, and its triangles are then sampled by
 *              area, so each triangle is picked with pbrt-v3's probability.
 *   "spatial"  pbrt-v3's default for the path integrator (SpatialLightDistribution, a voxel grid of
 *              distributions built from light samples) is not implemented: the parser warns and
 *              "power" is used.
 *
 * Only lights that emit are chosen among (pbrt-v3 counts every light, a black one too: the same
 * expected value). Nothing is built for a scene with one emitting light: it is chosen with probability
 * 1 and no random number is drawn for it. The distribution is el_distribution1d (distribution2d.h,
 * pbrt-v3's Distribution1D): its probabilities are exact multiples of 2^-24, the same when sampled
 * and when looked up for an MIS weight (pick[]). */
#include "elr_internal.h"
#include <stdlib.h>
#include <string.h>

int elr_light_distrib_init(elr_light_distrib *D, const elr_scene *s, int strategy) {
  int i, n = 0;
  double t0 = elr_now();
  float *w = NULL;
  memset(D, 0, sizeof *D);
  D->strategy = strategy == ELR_LSTRAT_UNIFORM ? ELR_LSTRAT_UNIFORM : ELR_LSTRAT_POWER; /* spatial: power */
  D->index = (int *)malloc(sizeof(int) * ((size_t)s->nlight + 1));
  D->pick = (float *)calloc((size_t)s->nlight + 1, sizeof(float));
  if (!D->index || !D->pick) { elr_light_distrib_free(D); return -1; }
  for (i = 0; i < s->nlight; i++) if (elr_light_emits(&s->light[i])) D->index[n++] = i;
  D->n = n;
  D->bytes = sizeof(int) * ((size_t)s->nlight + 1) + sizeof(float) * ((size_t)s->nlight + 1);
  if (n == 1) D->pick[D->index[0]] = 1.f;
  if (n > 1) {
    el_result r;
    w = (float *)malloc(sizeof(float) * (size_t)n);
    if (!w) { elr_light_distrib_free(D); return -1; }
    for (i = 0; i < n; i++) {
      const elr_light *l = &s->light[D->index[i]];
      double v;
      if (D->strategy == ELR_LSTRAT_UNIFORM) /* one per pbrt-v3 light: a mesh's triangles */
        v = l->kind == ELR_LIGHT_AREA && l->shape_kind == ELR_SHAPE_MESH ? (double)s->mesh[l->shape].ntri : 1.0;
      else
        v = elr_light_power(s, l);
      w[i] = v < 3e38 ? (float)v : 3e38f; /* (a power beyond the float range: the largest float) */
      if (!(w[i] >= 0.f)) w[i] = 0.f;
    }
    r = el_distribution1d_init(&D->d, w, n, NULL);
    free(w);
    if (r != EL_SUCCESS) { elr_light_distrib_free(D); return -1; }
    for (i = 0; i < n; i++) /* every light's probability, exactly as sample_discrete returns it */
      D->pick[D->index[i]] = (float)(D->d.cdf[i + 1] - D->d.cdf[i]) * (1.f / 16777216.f); /* (uniform when all are 0) */
    D->bytes += el_distribution1d_bytes(&D->d);
  }
  D->seconds = elr_now() - t0;
  return 0;
}

void elr_light_distrib_free(elr_light_distrib *D) {
  el_distribution1d_free(&D->d);
  free(D->index); free(D->pick);
  D->index = NULL; D->pick = NULL; D->n = 0;
}
