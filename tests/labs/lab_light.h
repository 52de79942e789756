/* tests/labs/lab_light.h: what lab 3 calls in each build of sampling.h and infinite.h
 * (lab_light_side.c): ref_* is examples/pbrtv3 (pbrt's behaviour), stu_* the files under test. */
#ifndef LAB_LIGHT_H
#define LAB_LIGHT_H
#define LAB_LIGHT_DECLARE(p)                                                                   \
  void *p##_d1_new(const float *f, int n);                                                   \
  void p##_d1_free(void *d);                                                                 \
  float p##_d1_funcint(const void *d);                                                       \
  void p##_d1_cdf(const void *d, float *cdf);                                                \
  float p##_d1_sample(const void *d, float u, float *pdf, int *off);                          \
  void *p##_d2_new(const float *f, int nu, int nv);                                          \
  void p##_d2_free(void *d);                                                                 \
  float p##_d2_funcint(const void *d);                                                       \
  void p##_d2_sample(const void *d, float u0, float u1, float *uv, float *pdf);              \
  float p##_d2_pdf(const void *d, float p0, float p1);                                       \
  void *p##_light_new(const float *texels, int w, int h);                                    \
  void p##_light_free(void *l);                                                              \
  void p##_light_sample(const void *l, float u0, float u1, float *wi, float *pdf, float *L); \
  float p##_light_pdf(const void *l, const float *w);
LAB_LIGHT_DECLARE(ref)
LAB_LIGHT_DECLARE(stu)
#endif
