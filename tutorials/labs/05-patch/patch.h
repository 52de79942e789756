/* tutorials/labs/05-patch/patch.h: LAB 5 (appendix A3.15, the patch density). Sample a point inside one
 * of le()'s bilinear patches with a density proportional to the bilinear interpolant of its four
 * corners: two linear inversions, in closed form.
 *
 * What you write (search for "TODO"):
 *   TODO 1  patch_lin_inv: the inverse CDF of a linear density on [0, 1] (A3.15, step 2)
 *   TODO 2  patch_sample: t from the marginal, then s from the conditional at that t (A3.15, step 2)
 * Build and check: `sh scripts/lab.sh 5` (from the repository root). The test checks that your t and s
 * are the roots of the CDFs the appendix writes out, at equal corners, at zero corners and at corners
 * 10^6 apart, and says what differs.
 * Untouched, this file compiles and runs, and the test fails: every TODO returns zeros.
 */
#ifndef LAB_PATCH_H_FILE
#define LAB_PATCH_H_FILE

#include <math.h>

/* t in [0, 1] with density proportional to (1 - t) a + t b (a, b >= 0, not both 0), from u in [0, 1]:
 * the root of F(t) = (a t + (b - a) t^2 / 2) / ((a + b) / 2) = u. */
static inline double patch_lin_inv(double a, double b, double u) {
  /* TODO 1: solve F(t) = u. The quadratic's root (-a + sqrt(...)) / (b - a) divides 0 by 0 when a = b;
   * multiply above and below by (a + sqrt(...)) to get the form without cancellation (A3.15). */
  (void)a;
  (void)b;
  (void)u;
  return 0;
}

/* (s, t) in the patch with corners c[0], c[1] (top, t = 0) and c[2], c[3] (bottom, t = 1), density
 * proportional to the bilinear interpolant: t from the marginal, then s from the conditional at t. */
static inline void patch_sample(const double c[4], double u1, double u2, double *s, double *t) {
  /* TODO 2: t = patch_lin_inv(top row's sum, bottom row's sum, u1); then s from the linear density
   * whose ends are the left and right edges' values at that t. */
  (void)c;
  (void)u1;
  (void)u2;
  *s = 0;
  *t = 0;
}
#endif
