/* tests/labs/lab_patch_side.c: one build of patch.h (tests/labs/patch_ref/ or lab 5's copy: the include
 * path decides), exported as LAB_SIDE_*. */
#include "patch.h"
#include "lab_side.h"
#include "lab_patch.h"

double LAB_FN(lin_inv)(double a, double b, double u) { return patch_lin_inv(a, b, u); }
void LAB_FN(patch_sample)(const double c[4], double u1, double u2, double *s, double *t) { patch_sample(c, u1, u2, s, t); }
