/* test_chisq.h: the chi-square statistic and p-value that the sampling tests share (test_distribution2d,
 * test_envlight, test_envlight_bigmaps, test_envlight_portal, test_envlight_sun). Include it after <math.h>.
 *
 * gammq(a, x) is the regularized upper incomplete gamma function Q(a, x) (Numerical Recipes' gammq):
 * the p-value of a chi-square statistic x with 2a degrees of freedom is gammq(dof / 2, x / 2).
 *
 * chisq_pooled(expect, obs, cells, total, n, impossible, &used) is Pearson's statistic of the counts
 * obs[i] against the expected counts e_i = expect[i] / total * n (total = 1 when expect already holds
 * probabilities), the cells with e_i < 5 pooled into one cell (which counts when its expectation is
 * > 0). With `impossible` non-NULL a cell of expect[i] == 0 stays out of the sum and *impossible is
 * incremented for each such cell that holds samples; with NULL it joins the pool. *used is the number
 * of cells in the sum (the pool is one): the degrees of freedom are *used - 1. */
#ifndef EL_TEST_CHISQ_H
#define EL_TEST_CHISQ_H

#include <math.h>
#include <stddef.h>

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

static inline double chisq_pooled(const double *expect, const double *obs, size_t cells, double total,
                                  double n, int *impossible, int *used) {
  double chi2 = 0, pool_e = 0, pool_o = 0;
  size_t i;
  *used = 0;
  for (i = 0; i < cells; ++i) {
    double e = expect[i] / total * n;
    if (impossible && expect[i] == 0) { if (obs[i] > 0) ++*impossible; continue; }
    if (e < 5) { pool_e += e; pool_o += obs[i]; continue; }
    chi2 += (obs[i] - e) * (obs[i] - e) / e;
    ++*used;
  }
  if (pool_e > 0) { chi2 += (pool_o - pool_e) * (pool_o - pool_e) / pool_e; ++*used; }
  return chi2;
}

#endif
