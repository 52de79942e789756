/* tests/labs/lab_patch.h: what lab 5 calls in each build of patch.h (lab_patch_side.c): ref_* is
 * tests/labs/patch_ref/patch.h (the appendix's formulas), stu_* the file under test. */
#ifndef LAB_PATCH_H
#define LAB_PATCH_H
#define LAB_PATCH_DECLARE(p)                          \
  double p##_lin_inv(double a, double b, double u); \
  void p##_patch_sample(const double c[4], double u1, double u2, double *s, double *t);
LAB_PATCH_DECLARE(ref)
LAB_PATCH_DECLARE(stu)
#endif
