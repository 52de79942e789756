/* tests/labs/patch_ref/patch.h: lab 5's reference (appendix A3.15, the patch density): the two linear
 * inversions that sample (s, t) inside one of le()'s bilinear patches, in plain C. The library's version
 * is envlight.h's el_envlight__lin_inv and its call in el_envlight__patch_finish (float, with a rescue for
 * tiny values); this one is the appendix's formulas as written. The lab's student copy is
 * tutorials/labs/05-patch/patch.h; tests/labs/lab_05_patch.c checks it. */
#ifndef LAB_PATCH_H_FILE
#define LAB_PATCH_H_FILE

#include <math.h>

/* t in [0, 1] with density proportional to (1 - t) a + t b (a, b >= 0, not both 0), from u in [0, 1]:
 * the root of F(t) = (a t + (b - a) t^2 / 2) / ((a + b) / 2) = u, without cancellation. */
static inline double patch_lin_inv(double a, double b, double u) {
  double den = a + sqrt(a * a + u * (b * b - a * a));
  return den > 0 ? u * (a + b) / den : 0;
}

/* (s, t) in the patch with corners c[0], c[1] (top, t = 0) and c[2], c[3] (bottom, t = 1), density
 * proportional to the bilinear interpolant: t from the marginal, then s from the conditional at t. */
static inline void patch_sample(const double c[4], double u1, double u2, double *s, double *t) {
  *t = patch_lin_inv(c[0] + c[1], c[2] + c[3], u1);
  *s = patch_lin_inv((1 - *t) * c[0] + *t * c[2], (1 - *t) * c[1] + *t * c[3], u2);
}
#endif
