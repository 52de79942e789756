/* tests/labs/lab_05_patch.c: lab 5 (appendix A3.15, the patch density): patch_lin_inv and patch_sample in
 * the file under test (stu_*), checked against facts derived by hand: the returned t (s) is the root of the
 * CDF the appendix writes out, F(t) = (a t + (b - a) t^2 / 2) / ((a + b) / 2) = u, to 1e-9 (the form without
 * cancellation is good to about 1e-15 in double; the cancelling one misses by about 1e-4 at ends 1e-12 apart,
 * and divides 0 by 0 at equal ones), and the reference (tests/labs/patch_ref/patch.h) must agree. */
#include "lab_check.h"
#include "lab_patch.h"

static double cdf_lin(double a, double b, double t) { return (a * t + (b - a) * t * t / 2) / ((a + b) / 2); }

static void part_lin_inv(void) {
  static const double ab[][2] = {{1, 1}, {1, 3}, {3, 1}, {0, 1}, {1, 0}, {1e-6, 1}, {1, 1e6}, {2.5, 2.5 + 1e-12}, {7, 7}};
  int k, j;
  lab_part("part 1, TODO 1: patch_lin_inv, the inverse CDF of a linear density (appendix A3.15, step 2)");
  for (k = 0; k < (int)(sizeof ab / sizeof ab[0]); ++k)
    for (j = 1; j <= 10; ++j) {
      double a = ab[k][0], b = ab[k][1], u = j == 10 ? 0.999 : j / 10.0, t = stu_lin_inv(a, b, u), F = cdf_lin(a, b, t);
      const char *hint = t != t ? ": NaN: the form with (b - a) below divides 0 by 0 when a = b; use u (a + b) / (a + sqrt(a^2 + u (b^2 - a^2)))"
                         : fabs(t - u) < 1e-12 && a != b ? ": that is u itself, the uniform density: the ends a and b weight it"
                         : fabs(cdf_lin(b, a, t) - u) < 1e-9 ? ": a and b swapped: a is the density at t = 0, b at t = 1"
                         : fabs(F - u) < 1e-3 ? ": close, but not to 1e-9: the form -a + sqrt(...) loses digits to cancellation when a and b are close"
                                              : "";
      lab_check(t >= 0 && t <= 1 && fabs(F - u) <= 1e-9, "a = %g, b = %g, u = %g: t = %.12g, F(t) = %.12g, should be u%s", a, b, u, t, F, hint);
    }
  lab_check(lab_close(stu_lin_inv(3, 3, 0.3), 0.3, 1e-12), "a = b = 3, u = 0.3: t = %g, should be 0.3 (equal ends: the uniform density)", stu_lin_inv(3, 3, 0.3));
  lab_check(lab_close(stu_lin_inv(0, 1, 0.25), 0.5, 1e-12), "a = 0, b = 1, u = 0.25: t = %g, should be 0.5 (density 2t: F(t) = t^2)", stu_lin_inv(0, 1, 0.25));
  lab_check(fabs(ref_lin_inv(1, 3, 0.4) - stu_lin_inv(1, 3, 0.4)) < 1e-12, "a = 1, b = 3, u = 0.4: t = %g, the reference's %g", stu_lin_inv(1, 3, 0.4),
            ref_lin_inv(1, 3, 0.4));
}

static void part_sample(void) {
  static const double cs[][4] = {{1, 2, 3, 4}, {0, 0, 0, 1}, {5, 5, 5, 5}, {1e6, 1, 1, 1e-6}, {0, 1, 0, 1}, {2, 0, 0, 3}};
  int k, i, j;
  lab_part("part 2, TODO 2: patch_sample, t from the marginal, then s at that t (appendix A3.15, step 2)");
  for (k = 0; k < (int)(sizeof cs / sizeof cs[0]); ++k)
    for (i = 0; i < 5; ++i)
      for (j = 0; j < 5; ++j) {
        const double *c = cs[k];
        double u1 = 0.1 + 0.2 * i, u2 = 0.05 + 0.225 * j, s = -1, t = -1, Ft, Fs, a, b;
        stu_patch_sample(c, u1, u2, &s, &t);
        Ft = cdf_lin(c[0] + c[1], c[2] + c[3], t);
        a = (1 - t) * c[0] + t * c[2];
        b = (1 - t) * c[1] + t * c[3];
        Fs = cdf_lin(a, b, s);
        if (!lab_check(t >= 0 && t <= 1 && fabs(Ft - u1) <= 1e-9, "corners {%g, %g, %g, %g}, u1 = %g: t = %.12g, its marginal CDF %.12g, should be u1%s", c[0], c[1],
                       c[2], c[3], u1, t, Ft,
                       fabs(cdf_lin(c[0] + c[1], c[2] + c[3], t) - u2) < 1e-9 ? ": u1 and u2 swapped: t takes u1"
                                                                             : ": t = patch_lin_inv(c[0] + c[1], c[2] + c[3], u1), the top row's sum against the bottom's"))
          continue;
        lab_check(s >= 0 && s <= 1 && fabs(Fs - u2) <= 1e-9, "corners {%g, %g, %g, %g}, u = (%g, %g): s = %.12g, its CDF at t = %g is %.12g, should be u2%s", c[0],
                  c[1], c[2], c[3], u1, u2, s, t, Fs,
                  fabs(cdf_lin(c[0], c[1], s) - u2) < 1e-9 && c[0] != c[2] ? ": s's ends are the edges' values at t, (1 - t) c[0] + t c[2] and (1 - t) c[1] + t c[3], not the top corners"
                                                                         : ": s = patch_lin_inv(left edge at t, right edge at t, u2)");
      }
}

int main(void) {
  printf("lab 5: the patch density's two linear inversions (tutorials/05-appendix-fast-paths.md, A3.15)\n\n");
  part_lin_inv();
  part_sample();
  return lab_finish("lab 5 (the patch density)");
}
