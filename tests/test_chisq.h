/* test_chisq.h: the chi-square p-value that the sampling tests share (test_distribution2d,
 * test_envlight, test_envlight_bigmaps, test_envlight_portal). Include it after <math.h>.
 *
 * gammq(a, x) is the regularized upper incomplete gamma function Q(a, x) (Numerical Recipes' gammq):
 * the p-value of a chi-square statistic x with 2a degrees of freedom is gammq(dof / 2, x / 2). */
#ifndef EL_TEST_CHISQ_H
#define EL_TEST_CHISQ_H

#include <math.h>

static double gammq(double a, double x) {
  double gln = lgamma(a);
  if (x <= 0) return 1.0;
  if (x < a + 1.0) { /* series for P */
    double ap = a, sum = 1.0 / a, del = sum;
    int n;
    for (n = 0; n < 100000; ++n) {
      ap += 1.0; del *= x / ap; sum += del;
      if (fabs(del) < fabs(sum) * 1e-15) break;
    }
    return 1.0 - sum * exp(-x + a * log(x) - gln);
  } else { /* continued fraction for Q */
    double b = x + 1.0 - a, c = 1.0 / 1e-300, d = 1.0 / b, h = d, an, del;
    int i;
    for (i = 1; i < 100000; ++i) {
      an = -i * (i - a); b += 2.0;
      d = an * d + b; if (fabs(d) < 1e-300) d = 1e-300;
      c = b + an / c; if (fabs(c) < 1e-300) c = 1e-300;
      d = 1.0 / d; del = d * c; h *= del;
      if (fabs(del - 1.0) < 1e-15) break;
    }
    return exp(-x + a * log(x) - gln) * h;
  }
}

#endif
