/* tests/labs/lab_mipmap_side.c: one build of a MIPMap port (examples/pbrtv3/mipmap.h, or a lab's
 * copy: the include path decides), exported as LAB_SIDE_* (see lab_mipmap.h). */
#include "mipmap.h"
#include "lab_side.h"
#include "lab_mipmap.h"

void LAB_FN(weights)(int oldRes, int newRes, int *firstTexel, float *weights4) {
  pbrt_ResampleWeight *wt = pbrt_MIPMap_resampleWeights(oldRes, newRes);
  int i, j;
  for (i = 0; i < newRes; ++i) {
    firstTexel[i] = wt[i].firstTexel;
    for (j = 0; j < 4; ++j) weights4[4 * i + j] = wt[i].weight[j];
  }
  free(wt);
}
void *LAB_FN(mip_new)(int w, int h, const float *rgb, int wrap, int doTrilinear, float maxAnisotropy) {
  pbrt_MIPMap *mip = (pbrt_MIPMap *)calloc(1, sizeof *mip);
  pbrt_RGBSpectrum *img = (pbrt_RGBSpectrum *)calloc((size_t)w * (size_t)h, sizeof *img);
  int i, c;
  if (!mip || !img) exit(2);
  for (i = 0; i < w * h; ++i)
    for (c = 0; c < 3; ++c) img[i].c[c] = rgb[3 * i + c];
  pbrt_MIPMap_init(mip, pbrt_Point2i_make(w, h), img, doTrilinear, maxAnisotropy, (pbrt_ImageWrap)wrap);
  free(img);
  return mip;
}
void LAB_FN(mip_free)(void *mip) {
  pbrt_MIPMap_free((pbrt_MIPMap *)mip);
  free(mip);
}
int LAB_FN(levels)(const void *mip) { return pbrt_MIPMap_Levels((const pbrt_MIPMap *)mip); }
void LAB_FN(level_size)(const void *mip, int level, int *w, int *h) {
  const pbrt_MIPMap *m = (const pbrt_MIPMap *)mip;
  *w = pbrt_BlockedArray_uSize(m->pyramid[level]);
  *h = pbrt_BlockedArray_vSize(m->pyramid[level]);
}
void LAB_FN(level_texels)(const void *mip, int level, float *rgb) {
  const pbrt_MIPMap *m = (const pbrt_MIPMap *)mip;
  const pbrt_BlockedArray *l = m->pyramid[level];
  int u, v, c;
  for (v = 0; v < l->vRes; ++v)
    for (u = 0; u < l->uRes; ++u)
      for (c = 0; c < 3; ++c) rgb[3 * (v * l->uRes + u) + c] = pbrt_BlockedArray_at(l, u, v)->c[c];
}
void LAB_FN(weightlut)(float *lut128) {
  int i;
  for (i = 0; i < pbrt_WeightLUTSize; ++i) lut128[i] = pbrt_MIPMap_weightLut[i];
}
static void lab_out(pbrt_RGBSpectrum r, float *rgb) {
  rgb[0] = r.c[0];
  rgb[1] = r.c[1];
  rgb[2] = r.c[2];
}
void LAB_FN(texel)(const void *mip, int level, int s, int t, float *rgb) {
  lab_out(pbrt_MIPMap_Texel((const pbrt_MIPMap *)mip, level, s, t), rgb);
}
void LAB_FN(triangle)(const void *mip, int level, float s, float t, float *rgb) {
  lab_out(pbrt_MIPMap_triangle((const pbrt_MIPMap *)mip, level, pbrt_Point2f_make(s, t)), rgb);
}
void LAB_FN(lookup)(const void *mip, float s, float t, float width, float *rgb) {
  lab_out(pbrt_MIPMap_Lookup((const pbrt_MIPMap *)mip, pbrt_Point2f_make(s, t), width), rgb);
}
void LAB_FN(lookup_dst)(const void *mip, float s, float t, const float *dst0, const float *dst1, float *rgb) {
  lab_out(pbrt_MIPMap_Lookup_dst((const pbrt_MIPMap *)mip, pbrt_Point2f_make(s, t), pbrt_Vector2f_make(dst0[0], dst0[1]),
                                 pbrt_Vector2f_make(dst1[0], dst1[1])),
          rgb);
}
