/* tests/labs/lab_light_side.c: one build of the distributions and the light (examples/pbrtv3's
 * sampling.h and infinite.h, or lab 3's copies: the include path decides), exported as LAB_SIDE_*. */
#include "infinite.h"
#include "lab_side.h"
#include "lab_light.h"

#include <stdio.h>

void *LAB_FN(d1_new)(const float *f, int n) {
  pbrt_Distribution1D *d = (pbrt_Distribution1D *)calloc(1, sizeof *d);
  if (!d || pbrt_Distribution1D_init(d, f, n) != 0) exit(2);
  return d;
}
void LAB_FN(d1_free)(void *d) {
  pbrt_Distribution1D_free((pbrt_Distribution1D *)d);
  free(d);
}
float LAB_FN(d1_funcint)(const void *d) { return ((const pbrt_Distribution1D *)d)->funcInt; }
void LAB_FN(d1_cdf)(const void *d, float *cdf) {
  const pbrt_Distribution1D *e = (const pbrt_Distribution1D *)d;
  memcpy(cdf, e->cdf, sizeof(float) * ((size_t)e->n + 1));
}
float LAB_FN(d1_sample)(const void *d, float u, float *pdf, int *off) {
  return pbrt_Distribution1D_SampleContinuous((const pbrt_Distribution1D *)d, u, pdf, off);
}
void *LAB_FN(d2_new)(const float *f, int nu, int nv) {
  pbrt_Distribution2D *d = (pbrt_Distribution2D *)calloc(1, sizeof *d);
  if (!d || pbrt_Distribution2D_init(d, f, nu, nv) != 0) exit(2);
  return d;
}
void LAB_FN(d2_free)(void *d) {
  pbrt_Distribution2D_free((pbrt_Distribution2D *)d);
  free(d);
}
float LAB_FN(d2_funcint)(const void *d) { return ((const pbrt_Distribution2D *)d)->pMarginal.funcInt; }
void LAB_FN(d2_sample)(const void *d, float u0, float u1, float *uv, float *pdf) {
  float u[2];
  u[0] = u0;
  u[1] = u1;
  pbrt_Distribution2D_SampleContinuous((const pbrt_Distribution2D *)d, u, uv, pdf);
}
float LAB_FN(d2_pdf)(const void *d, float p0, float p1) {
  float p[2];
  p[0] = p0;
  p[1] = p1;
  return pbrt_Distribution2D_Pdf((const pbrt_Distribution2D *)d, p);
}
/* The chapter's orientation: LightToWorld = RotateX(-90) (the seed's y-up world) */
void *LAB_FN(light_new)(const float *texels, int w, int h) {
  pbrt_InfiniteAreaLight *l = (pbrt_InfiniteAreaLight *)calloc(1, sizeof *l);
  pbrt_Transform rx = pbrt_RotateX(-90);
  int res[2];
  res[0] = w;
  res[1] = h;
  if (!l || pbrt_InfiniteAreaLight_init(l, &rx, texels, res) != 0) exit(2);
  return l;
}
void LAB_FN(light_free)(void *l) {
  pbrt_InfiniteAreaLight_free((pbrt_InfiniteAreaLight *)l);
  free(l);
}
void LAB_FN(light_sample)(const void *l, float u0, float u1, float *wi, float *pdf, float *L) {
  float u[2];
  u[0] = u0;
  u[1] = u1;
  pbrt_InfiniteAreaLight_Sample_Li((const pbrt_InfiniteAreaLight *)l, u, wi, pdf, L);
}
float LAB_FN(light_pdf)(const void *l, const float *w) { return pbrt_InfiniteAreaLight_Pdf_Li((const pbrt_InfiniteAreaLight *)l, w); }
