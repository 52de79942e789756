/* tests/labs/lab_mipmap.h: what labs 1 and 2 call in each build of mipmap.h (lab_mipmap_side.c):
 * ref_* is examples/pbrtv3/mipmap.h (pbrt's behaviour), stu_* the file under test. Plain C types
 * only, so that the two builds never share a struct. Images are RGB floats, row-major. */
#ifndef LAB_MIPMAP_H
#define LAB_MIPMAP_H
#define LAB_MIPMAP_DECLARE(p)                                                                               \
  void p##_weights(int oldRes, int newRes, int *firstTexel, float *weights4);                             \
  void *p##_mip_new(int w, int h, const float *rgb, int wrap, int doTrilinear, float maxAnisotropy);      \
  void p##_mip_free(void *mip);                                                                           \
  int p##_levels(const void *mip);                                                                        \
  void p##_level_size(const void *mip, int level, int *w, int *h);                                        \
  void p##_level_texels(const void *mip, int level, float *rgb);                                          \
  void p##_weightlut(float *lut128);                                                                      \
  void p##_texel(const void *mip, int level, int s, int t, float *rgb);                                   \
  void p##_triangle(const void *mip, int level, float s, float t, float *rgb);                            \
  void p##_lookup(const void *mip, float s, float t, float width, float *rgb);                            \
  void p##_lookup_dst(const void *mip, float s, float t, const float *dst0, const float *dst1, float *rgb);
LAB_MIPMAP_DECLARE(ref)
LAB_MIPMAP_DECLARE(stu)
#endif
