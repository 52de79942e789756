/* test_distribution2d.c: distribution2d.h against mathematics.
 *
 * Where the expectations come from (never from an earlier output of distribution2d.h):
 *  - EXACT FREQUENCIES. A float u = k * 2^-24, k = 0 .. 2^24-1, is the usual uniform generator; the
 *    probability of a bin under it (and under continuous uniform u, since the header promises bin
 *    boundaries on that grid) is (number of k landing in the bin) / 2^24. We count those k, either by
 *    enumerating all 2^24 of them, or - for a monotone sampler - by bisecting for each bin's first k, and
 *    compare with the stated pmf. This is the probability of the sampling procedure, measured.
 *  - hand arithmetic for small distributions (pdf = f / integral, to within the documented 2 units of
 *    2^-24 per bin), integrals summed here in double;
 *  - chi-square goodness of fit (significance 0.01, Bonferroni-corrected over all chi-square tests);
 *  - pbrt-v3's float CDF as the "before": the course's plain port of Distribution1D
 *    (examples/pbrtv3/sampling.h; tests/test_tutorial_distribution.c compares the two in full).
 */
#define EL_DISTRIBUTION2D_IMPLEMENTATION
#include "distribution2d.h"
#include "../examples/pbrtv3/sampling.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static int g_pass, g_fail;
static void check(int ok, const char *what) {
  if (ok) g_pass++; else g_fail++;
  printf("%s: %s\n", ok ? "PASS" : "FAIL", what);
}
static void checkf(int ok, const char *fmt, double a, double b) {
  char buf[512];
  snprintf(buf, sizeof buf, fmt, a, b);
  check(ok, buf);
}
static double now(void) { return (double)clock() / CLOCKS_PER_SEC; }

#define UNITS 16777216.0
#define ONE_MINUS 0.99999994f /* 0x1.fffffep-1 */

#include "test_rng.h" /* splitmix64, hash32 */
static splitmix64 g_rng = {0x9E3779B97F4A7C15ull};
static float rndu(void) { return splitmix64_f(&g_rng); }

#include "test_chisq.h" /* gammq: the chi-square p-value */
#define N_CHI2_TESTS 4 /* Bonferroni: every chi-square test in this file */
/* counts vs expected (expected summing to the number of samples); bins with expected < 5 pooled. */
static void chi2_check(const double *expected, const double *observed, int n, const char *what) {
  double chi = 0, pool_e = 0, pool_o = 0, p;
  int dof = 0, i, impossible = 0;
  char buf[256];
  for (i = 0; i < n; ++i) {
    if (expected[i] == 0.0 && observed[i] > 0) impossible = 1;
    if (expected[i] < 5.0) { pool_e += expected[i]; pool_o += observed[i]; continue; }
    chi += (observed[i] - expected[i]) * (observed[i] - expected[i]) / expected[i];
    ++dof;
  }
  if (pool_e >= 5.0) { chi += (pool_o - pool_e) * (pool_o - pool_e) / pool_e; ++dof; }
  else if (pool_e > 0 || pool_o > 0) { /* fold the pool into nothing: fine for a handful of counts */ }
  dof -= 1;
  p = dof > 0 ? gammq(0.5 * dof, 0.5 * chi) : 1.0;
  snprintf(buf, sizeof buf, "%s: chi2 = %.1f, dof = %d, p = %.4f >= %.5f%s", what, chi, dof, p,
           0.01 / N_CHI2_TESTS, impossible ? " (a sample in a bin of probability 0!)" : "");
  check(!impossible && p >= 0.01 / N_CHI2_TESTS, buf);
}

/* ---- enumeration of all 2^24 grid values of u through a 1D distribution on [0,1], n a power of two ---- */
/* Counts per bin; checks: offsets monotone in u, x inside [i/n, (i+1)/n), x < 1, pdf(x) == returned pdf,
 * and the stated pmf of each bin equals its count / 2^24. Returns the number of failed bins. */
static int enumerate_1d(const el_distribution1d *d, const float *f, const char *name, int *positive_unreached) {
  int n = d->n, i, bad_bins = 0, bad_place = 0, nonmono = 0, prev = 0;
  uint32_t k;
  double *count = (double *)calloc((size_t)n, sizeof(double));
  char buf[256];
  *positive_unreached = 0;
  for (k = 0; k < 16777216u; ++k) {
    float u = (float)k * (1.0f / 16777216.0f), pdf, x;
    int off;
    x = el_distribution1d_sample_continuous(d, u, &pdf, &off);
    if (off < prev) ++nonmono;
    prev = off;
    count[off] += 1.0;
    if (!((double)x >= (double)off / n && (double)x < (double)(off + 1) / n && x < 1.0f) ||
        el_distribution1d_pdf(d, x) != pdf)
      ++bad_place;
  }
  for (i = 0; i < n; ++i) {
    /* the stated pmf of bin i: its density times its width 1/n */
    double stated = (double)el_distribution1d_pdf(d, ((float)i + 0.5f) / (float)n) / n;
    if (stated != count[i] / UNITS) ++bad_bins;
  }
  snprintf(buf, sizeof buf, "%s: all 2^24 u: sampled offsets monotone in u (%d decreases)", name, nonmono);
  check(nonmono == 0, buf);
  snprintf(buf, sizeof buf, "%s: every point inside its bin, below 1, pdf(x) == returned pdf (%d bad)", name, bad_place);
  check(bad_place == 0, buf);
  snprintf(buf, sizeof buf, "%s: every bin's frequency (count/2^24) == its stated pmf (%d bins differ)", name, bad_bins);
  check(bad_bins == 0, buf);
  for (i = 0; i < n; ++i)
    if (count[i] == 0 && f[i] > 0) ++*positive_unreached; /* f > 0: the mathematics, not the stated pdf */
  free(count);
  return bad_bins;
}

/* ---- hand-computed 1D ---- */
static void test_hand_1d(void) {
  float f[4] = {1, 3, 0, 4};
  el_distribution1d d;
  el_distribution_options opt;
  int i, unreached;
  double tol = 2.0 * 4.0 / UNITS; /* pdf = units * n * 2^-24: 2 units of slack per bin, times n */
  double expect[4] = {0.5, 1.5, 0.0, 2.0}; /* f / integral, integral = 8/4 */
  memset(&opt, 0, sizeof opt);
  check(el_distribution1d_init(&d, f, 4, &opt) == EL_SUCCESS && d.bad_index == -1, "1D {1,3,0,4}: init, bad_index -1");
  for (i = 0; i < 4; ++i) {
    float p = el_distribution1d_pdf(&d, (i + 0.5f) / 4);
    checkf(fabs(p - expect[i]) <= tol, "1D {1,3,0,4}: pdf %.9g vs f/integral %.9g", p, expect[i]);
  }
  check(el_distribution1d_pdf(&d, 0.6f) == 0.0f, "1D {1,3,0,4}: zero bin has pdf exactly 0");
  check(el_distribution1d_integral(&d) == 2.0f, "1D {1,3,0,4}: integral == 8/4 exactly");
  /* CDF at a bin boundary == the summed pmf of the bins below it (exact: powers of two) */
  check(el_distribution1d_invert(&d, 0.25f) == el_distribution1d_pdf(&d, 0.1f) / 4, "invert(1/4) == pmf(bin 0)");
  check(el_distribution1d_invert(&d, 0.5f) == el_distribution1d_pdf(&d, 0.1f) / 4 + el_distribution1d_pdf(&d, 0.3f) / 4,
        "invert(1/2) == pmf(0) + pmf(1)");
  check(el_distribution1d_invert(&d, 0.0f) == 0.0f && el_distribution1d_invert(&d, 1.0f) == 1.0f, "invert(0) == 0, invert(1) == 1");
  {
    int bad = 0;
    float worst = 0;
    for (i = 0; i < 10000; ++i) {
      float u = rndu(), pdf, x = el_distribution1d_sample_continuous(&d, u, &pdf, NULL), back = el_distribution1d_invert(&d, x);
      /* x carries ~2^-24 relative rounding; in u that is at most pdf * ulp(x) plus one rounding of u */
      float tolu = pdf * 2.0f * FLT_EPSILON * (x > 0 ? x : 0) + 2.0f * FLT_EPSILON;
      if (fabsf(back - u) > tolu) ++bad;
      if (fabsf(back - u) > worst) worst = fabsf(back - u);
    }
    checkf(bad == 0, "invert(sample(u)) == u to rounding for 10000 u (worst %.3g, %g bad)", worst, bad);
  }
  enumerate_1d(&d, f, "1D {1,3,0,4}", &unreached);
  check(unreached == 0, "1D {1,3,0,4}: every positive bin reached");
  {
    float pmf, ur;
    int b = el_distribution1d_sample_discrete(&d, 0.0f, &pmf, &ur);
    check(b == 0 && pmf == el_distribution1d_pdf(&d, 0.1f) / 4 && ur == 0.0f, "sample_discrete(0): bin 0, its pmf, u_remapped 0");
    b = el_distribution1d_sample_discrete(&d, 1.0f, &pmf, &ur);
    check(b == 3 && ur >= 0.0f && ur < 1.0f, "sample_discrete(1): last bin, u_remapped in [0,1)");
    b = el_distribution1d_sample_discrete(&d, 0.6f, &pmf, &ur);
    check(b == 3 && fabsf(ur - (0.6f - 0.5f) / 0.5f) < 1e-6f, "sample_discrete(0.6) skips the zero bin: bin 3, u_remapped 0.2");
  }
  el_distribution1d_free(&d);
  el_distribution1d_free(&d); /* twice: freeing a zeroed struct is safe */

  /* a domain [2, 6]: densities divide by 4, integral multiplies by 4 */
  opt.domain[0] = 2.0f; opt.domain[2] = 6.0f;
  check(el_distribution1d_init(&d, f, 4, &opt) == EL_SUCCESS, "1D on [2,6]: init");
  for (i = 0; i < 4; ++i) {
    float p = el_distribution1d_pdf(&d, 2.0f + i + 0.5f);
    checkf(fabs(p - expect[i] / 4) <= tol / 4, "1D on [2,6]: pdf %.9g vs %.9g", p, expect[i] / 4);
  }
  check(el_distribution1d_integral(&d) == 8.0f, "1D on [2,6]: integral == 8");
  {
    float pdf, x = el_distribution1d_sample_continuous(&d, 0.5f, &pdf, NULL);
    check(x >= 2.0f && x < 6.0f && pdf == el_distribution1d_pdf(&d, x), "1D on [2,6]: sample in the domain, pdf consistent");
    x = el_distribution1d_sample_continuous(&d, 1.0f, &pdf, NULL);
    check(x < 6.0f && x > 5.0f && pdf == el_distribution1d_pdf(&d, x), "1D on [2,6]: u = 1 stays below 6");
  }
  el_distribution1d_free(&d);
}

/* ---- u edge cases ---- */
static void test_edges(void) {
  float us[7];
  float fa[2] = {1, 0}, fb[2] = {0, 1}, fc[5] = {1, 2, 3, 4, 5};
  el_distribution1d a, b, c;
  int i, ok = 1;
  us[0] = 0.0f; us[1] = ONE_MINUS; us[2] = 1.0f; us[3] = -0.5f; us[4] = (float)NAN; us[5] = (float)INFINITY; us[6] = -(float)INFINITY;
  el_distribution1d_init(&a, fa, 2, NULL);
  el_distribution1d_init(&b, fb, 2, NULL);
  el_distribution1d_init(&c, fc, 5, NULL);
  for (i = 0; i < 7; ++i) {
    float pa, pb, pc, xa = el_distribution1d_sample_continuous(&a, us[i], &pa, NULL);
    float xb = el_distribution1d_sample_continuous(&b, us[i], &pb, NULL);
    float xc = el_distribution1d_sample_continuous(&c, us[i], &pc, NULL);
    if (!(xa >= 0 && xa < 0.5f && pa == 2.0f)) ok = 0;      /* {1,0}: always bin 0, density 2 */
    if (!(xb >= 0.5f && xb < 1.0f && pb == 2.0f)) ok = 0;   /* {0,1}: always bin 1 */
    if (!(xc >= 0 && xc < 1.0f && pc > 0 && pc == el_distribution1d_pdf(&c, xc))) ok = 0;
  }
  check(ok, "u in {0, 0x1.fffffep-1, 1, -0.5, NaN, +Inf, -Inf}: in range, zero bins at either end skipped, pdf consistent");
  {
    float p0, p1, x0 = el_distribution1d_sample_continuous(&c, ONE_MINUS, &p0, NULL), x1 = el_distribution1d_sample_continuous(&c, 1.0f, &p1, NULL);
    check(x0 == x1 && p0 == p1, "u = 1 acts as 0x1.fffffep-1");
  }
  check(el_distribution1d_pdf(&c, -5.0f) == el_distribution1d_pdf(&c, 0.0f) && el_distribution1d_pdf(&c, 7.0f) == el_distribution1d_pdf(&c, 0.9f) &&
        el_distribution1d_pdf(&c, (float)NAN) == el_distribution1d_pdf(&c, 0.0f) && isfinite(el_distribution1d_invert(&c, (float)NAN)),
        "pdf/invert clamp out-of-domain points, NaN -> lower end");
  el_distribution1d_free(&a); el_distribution1d_free(&b); el_distribution1d_free(&c);
}

/* ---- all-zero input ---- */
static void test_all_zero(void) {
  float z[12] = {0};
  el_distribution1d d;
  el_distribution2d d2;
  el_distribution2d_fast fg, fa;
  el_distribution_fast_options fo;
  int i, ok = 1;
  check(el_distribution1d_init(&d, z, 4, NULL) == EL_SUCCESS, "all-zero 1D: init succeeds");
  for (i = 0; i < 20; ++i) {
    float u = rndu(), pdf = -1, pmf = -1, x = el_distribution1d_sample_continuous(&d, u, &pdf, NULL);
    el_distribution1d_sample_discrete(&d, u, &pmf, NULL);
    if (!(pdf == 0.0f && pmf == 0.0f && fabsf(x - u) < 1e-6f && el_distribution1d_pdf(&d, x) == 0.0f)) ok = 0;
  }
  check(ok && el_distribution1d_integral(&d) == 0.0f, "all-zero 1D: sample = uniform point x = u with pdf 0, pmf 0, pdf() 0, integral 0");
  el_distribution1d_free(&d);
  check(el_distribution2d_init(&d2, z, 4, 3, NULL) == EL_SUCCESS, "all-zero 2D: init succeeds");
  memset(&fo, 0, sizeof fo);
  fo.method = EL_DISTRIBUTION_FAST_ALIAS;
  check(el_distribution2d_fast_init(&fg, &d2) == EL_SUCCESS && el_distribution2d_fast_init_ex(&fa, &d2, &fo) == EL_SUCCESS, "all-zero 2D: fast samplers build");
  ok = 1;
  for (i = 0; i < 20; ++i) {
    float u0 = rndu(), u1 = rndu(), x, y, p = -1, xg, yg, pg = -1, xa, ya, pa = -1;
    el_distribution2d_sample(&d2, u0, u1, &x, &y, &p);
    el_distribution2d_fast_sample(&fg, u0, u1, &xg, &yg, &pg);
    el_distribution2d_fast_sample(&fa, u0, u1, &xa, &ya, &pa);
    if (!(p == 0 && pg == 0 && pa == 0 && fabsf(x - u0) < 1e-6f && fabsf(y - u1) < 1e-6f && x < 1 && y < 1 &&
          el_distribution2d_pdf(&d2, x, y) == 0 && xa >= 0 && xa < 1 && ya >= 0 && ya < 1)) ok = 0;
  }
  check(ok && el_distribution2d_integral(&d2) == 0.0f, "all-zero 2D: uniform point, pdf 0 (CDF, guide, alias), pdf() 0, integral 0");
  el_distribution2d_fast_free(&fg); el_distribution2d_fast_free(&fa);
  el_distribution2d_free(&d2);
}

/* ---- bad input ---- */
static void test_bad_input(void) {
  float f[6] = {1, 2, 3, 4, 5, 6};
  el_distribution1d d;
  el_distribution2d d2;
  el_distribution_options opt;
  el_result r;
  memset(&opt, 0, sizeof opt);
  check(el_distribution1d_init(&d, f, 0, &opt) == EL_ERROR_EMPTY, "1D n = 0 -> EL_ERROR_EMPTY");
  check(el_distribution1d_init(&d, f, -3, &opt) == EL_ERROR_INVALID_ARGUMENT, "1D n < 0 -> EL_ERROR_INVALID_ARGUMENT");
  check(el_distribution1d_init(&d, NULL, 3, &opt) == EL_ERROR_INVALID_ARGUMENT, "1D f = NULL -> EL_ERROR_INVALID_ARGUMENT");
  check(el_distribution1d_init(&d, f, EL_DISTRIBUTION_MAX_BINS + 1, &opt) == EL_ERROR_SIZE_OVERFLOW, "1D n > 2^22 -> EL_ERROR_SIZE_OVERFLOW");
  check(el_distribution2d_init(&d2, f, 0, 3, &opt) == EL_ERROR_EMPTY && el_distribution2d_init(&d2, f, 3, 0, &opt) == EL_ERROR_EMPTY, "2D nu = 0 or nv = 0 -> EL_ERROR_EMPTY");
  check(el_distribution2d_init(&d2, f, EL_DISTRIBUTION_MAX_BINS + 1, 1, &opt) == EL_ERROR_SIZE_OVERFLOW, "2D nu > 2^22 -> EL_ERROR_SIZE_OVERFLOW");
  f[4] = (float)NAN; f[2] = -1.0f; /* the NaN is later, so the first bad index is 2 (negative) */
  r = el_distribution1d_init(&d, f, 6, &opt);
  check(r == EL_ERROR_NEGATIVE && d.bad_index == 2, "1D {1,2,-1,4,NaN,6}: EL_ERROR_NEGATIVE at index 2");
  f[2] = 3.0f;
  r = el_distribution1d_init(&d, f, 6, &opt);
  check(r == EL_ERROR_NAN && d.bad_index == 4, "1D NaN at 4: EL_ERROR_NAN, bad_index 4");
  f[4] = 5.0f; f[5] = (float)INFINITY;
  r = el_distribution1d_init(&d, f, 6, &opt);
  check(r == EL_ERROR_INFINITE && d.bad_index == 5, "1D +Inf at 5: EL_ERROR_INFINITE, bad_index 5");
  f[5] = -(float)INFINITY;
  r = el_distribution1d_init(&d, f, 6, &opt);
  check(r == EL_ERROR_INFINITE && d.bad_index == 5, "1D -Inf at 5: EL_ERROR_INFINITE, bad_index 5");
  el_distribution1d_free(&d); /* zeroed on failure: safe */
  {
    /* every position of the 4-wide validity pass and the tail; -0.0 is a zero, not a negative */
    float g[11];
    int pos, k, ok = 1;
    float bads[4];
    el_result want[4] = {EL_ERROR_NAN, EL_ERROR_INFINITE, EL_ERROR_NEGATIVE, EL_ERROR_NEGATIVE};
    bads[0] = (float)NAN; bads[1] = (float)INFINITY; bads[2] = -1e-45f; bads[3] = -(float)FLT_MAX;
    for (pos = 0; pos < 11; ++pos)
      for (k = 0; k < 4; ++k) {
        int j;
        for (j = 0; j < 11; ++j) g[j] = 1.0f + j;
        g[pos] = bads[k];
        if (el_distribution1d_init(&d, g, 11, &opt) != want[k] || d.bad_index != pos) ok = 0;
      }
    check(ok, "NaN, +Inf, -denormal, -FLT_MAX at each of 11 positions: the right error and index");
    for (k = 0; k < 11; ++k) g[k] = 1.0f;
    g[0] = -0.0f; g[9] = -0.0f;
    r = el_distribution1d_init(&d, g, 11, &opt);
    check(r == EL_SUCCESS && el_distribution1d_pdf(&d, 0.5f / 11) == 0.0f && el_distribution1d_pdf(&d, 9.5f / 11) == 0.0f &&
          el_distribution1d_pdf(&d, 1.5f / 11) > 0.0f, "-0.0 is accepted as zero: its bins have pdf 0");
    el_distribution1d_free(&d);
  }
  /* 2D: f[v*nu+u] with nu = 3, nv = 2: (u=2, v=1) is index 5 */
  f[5] = (float)NAN;
  r = el_distribution2d_init(&d2, f, 3, 2, &opt);
  check(r == EL_ERROR_NAN && d2.bad_index == 5 && d2.cdf == NULL, "2D NaN at (u=2,v=1): EL_ERROR_NAN, bad_index 5 = v*nu+u, struct zeroed");
  el_distribution2d_free(&d2);
  /* clamp: NaN -> 0, negative -> 0, +Inf -> FLT_MAX */
  opt.clamp_bad_values = 1;
  f[0] = 1; f[1] = (float)NAN; f[2] = -3; f[3] = 1;
  r = el_distribution1d_init(&d, f, 4, &opt);
  check(r == EL_SUCCESS && d.bad_index == -1 && el_distribution1d_pdf(&d, 0.3f) == 0.0f && el_distribution1d_pdf(&d, 0.6f) == 0.0f &&
        el_distribution1d_pdf(&d, 0.1f) == 2.0f && el_distribution1d_pdf(&d, 0.9f) == 2.0f,
        "clamp: {1,NaN,-3,1} acts as {1,0,0,1} (pdf 2, 0, 0, 2 exactly)");
  el_distribution1d_free(&d);
  f[0] = 1; f[1] = (float)INFINITY;
  r = el_distribution1d_init(&d, f, 2, &opt);
  /* bin 0's share 1/(1+FLT_MAX) rounds to 0 units, plus the one-unit floor: pmf 2^-24, pdf 2 * 2^-24 */
  check(r == EL_SUCCESS && el_distribution1d_pdf(&d, 0.25f) == (float)(2.0 / UNITS) && isfinite(el_distribution1d_integral(&d)),
        "clamp: {1,+Inf} acts as {1,FLT_MAX}: bin 0 keeps its one-unit floor, integral finite");
  el_distribution1d_free(&d);
  /* domains */
  opt.clamp_bad_values = 0;
  f[0] = f[1] = 1;
  opt.domain[0] = 1; opt.domain[2] = 0.5f;
  check(el_distribution1d_init(&d, f, 2, &opt) == EL_ERROR_INVALID_ARGUMENT, "domain with x1 < x0 -> EL_ERROR_INVALID_ARGUMENT");
  opt.domain[0] = 0; opt.domain[2] = (float)INFINITY;
  check(el_distribution1d_init(&d, f, 2, &opt) == EL_ERROR_INVALID_ARGUMENT, "infinite domain -> EL_ERROR_INVALID_ARGUMENT");
  opt.domain[0] = 1e6f; opt.domain[2] = 1e6f + 0.0625f;
  check(el_distribution1d_init(&d, f, 2, &opt) == EL_ERROR_INVALID_ARGUMENT, "domain too narrow to resolve its bins -> EL_ERROR_INVALID_ARGUMENT");
}

/* ---- pbrt's counterexample ---- */
static void test_pbrt_counterexample(void) {
  enum { N = 4096 };
  static float f[N];
  int i, zero_steps = 0, unreached;
  el_distribution1d d;
  pbrt_Distribution1D pbrt;
  for (i = 0; i < N; ++i) f[i] = 1e-2f;
  f[100] = 1e6f;
  /* pbrt-v3's Distribution1D constructor (the course's port) */
  check(pbrt_Distribution1D_init(&pbrt, f, N) == 0, "pbrt-v3's Distribution1D on the same row: init");
  for (i = 0; i < N; ++i)
    if (f[i] > 0 && pbrt.cdf[i + 1] == pbrt.cdf[i]) ++zero_steps;
  pbrt_Distribution1D_free(&pbrt);
  checkf(zero_steps == 3995, "pbrt-v3's float CDF (one 1e6 among 4095 x 1e-2): %g positive bins with a zero CDF step (issue says %g)", zero_steps, 3995);
  check(el_distribution1d_init(&d, f, N, NULL) == EL_SUCCESS, "ours on the same row: init");
  enumerate_1d(&d, f, "pbrt counterexample", &unreached);
  checkf(unreached == 0, "pbrt counterexample: positive bins never sampled: %g (pbrt: %g)", unreached, zero_steps);
  {
    /* every 1e-2 bin: probability >= 2^-24 (the floor) and within 2 units of its share */
    double S = 1e6 + 4095 * (double)1e-2f, worst = 0;
    int ok = 1;
    for (i = 0; i < N; ++i) {
      double pmf = el_distribution1d_pdf(&d, (i + 0.5f) / N) / N, share = (double)f[i] / S;
      double bound = (2.0 + 4096.0 * share) / UNITS;
      if (!(pmf >= 1.0 / UNITS && fabs(pmf - share) <= bound)) ok = 0;
      if (fabs(pmf - share) > worst) worst = fabs(pmf - share);
    }
    checkf(ok, "pbrt counterexample: every pmf >= 2^-24 and |pmf - f/sum| <= (2 + m f/sum) 2^-24 (worst %.3g, 2^-24 = %.3g)", worst, 1.0 / UNITS);
  }
  el_distribution1d_free(&d);
}

/* ---- 1e12 dynamic range row, 8192 bins ---- */
static void test_dynamic_range_1d(void) {
  enum { N = 8192 };
  static float f[N];
  int i, unreached, ok = 1;
  double S = 0, worst_rel = 0;
  el_distribution1d d;
  for (i = 0; i < N; ++i) {
    /* log-uniform in [1e-6, 1e6], scattered by a hash so that huge and tiny values interleave */
    double t = (double)(hash32((uint32_t)i) % 1000001u) / 1000000.0;
    f[i] = (float)pow(10.0, -6.0 + 12.0 * t);
  }
  f[17] = 1e-6f; f[18] = 1e6f; /* both ends present: range 1e12 */
  f[19] = 0.0f;
  for (i = 0; i < N; ++i) S += f[i];
  check(el_distribution1d_init(&d, f, N, NULL) == EL_SUCCESS, "1e12-range row of 8192: init");
  enumerate_1d(&d, f, "1e12 range, 8192 bins", &unreached);
  checkf(unreached == 0, "1e12 range: positive bins never sampled: %g (zero bins: %g)", unreached, 1);
  for (i = 0; i < N; ++i) {
    double pmf = el_distribution1d_pdf(&d, (i + 0.5f) / N) / N, share = f[i] / S;
    if (f[i] == 0) { if (pmf != 0) ok = 0; continue; }
    if (!(fabs(pmf - share) <= (2.0 + N * share) / UNITS)) ok = 0;
    if (share > 1e-4 && fabs(pmf / share - 1) > worst_rel) worst_rel = fabs(pmf / share - 1);
  }
  checkf(ok, "1e12 range: pmf within (2 + m f/sum) 2^-24 of f/sum; worst relative error of bins > 1e-4: %.3g", worst_rel, 0);
  checkf(fabs(el_distribution1d_integral(&d) - S / N) <= 1e-6 * S / N, "1e12 range: integral %.9g == sum/n %.9g", el_distribution1d_integral(&d), S / N);
  el_distribution1d_free(&d);
}

/* ---- 2D: hand-computed, non-unit domains, 1x1/1xN/Nx1 ---- */
static void test_hand_2d(void) {
  /* f[v*nu+u], nu = 4, nv = 2; row sums 4 and 5, total 9; integral 9/8 */
  float f[8] = {1, 2, 0, 1, 4, 0, 0, 1};
  el_distribution2d d;
  el_distribution_options opt;
  int u, v, ok = 1;
  double tol = 4.0 * 8.0 / UNITS * 2; /* two pmfs, each within 2 units, times nu*nv, times pdf <= 2 */
  memset(&opt, 0, sizeof opt);
  check(el_distribution2d_init(&d, f, 4, 2, &opt) == EL_SUCCESS, "2D 4x2 hand example: init");
  for (v = 0; v < 2; ++v)
    for (u = 0; u < 4; ++u) {
      float p = el_distribution2d_pdf(&d, (u + 0.5f) / 4, (v + 0.5f) / 2);
      double e = f[v * 4 + u] / (9.0 / 8.0);
      if (!(fabs(p - e) <= tol) || (f[v * 4 + u] == 0) != (p == 0)) ok = 0;
    }
  check(ok, "2D 4x2: pdf == f / integral (within 2 units per pmf), exactly 0 where f = 0");
  check(el_distribution2d_integral(&d) == 9.0f / 8.0f, "2D 4x2: integral == 9/8");
  {
    float x, y, p, a, b;
    int bad = 0, i;
    for (i = 0; i < 20000; ++i) {
      float u0 = rndu(), u1 = rndu();
      el_distribution2d_sample(&d, u0, u1, &x, &y, &p);
      el_distribution2d_invert(&d, x, y, &a, &b);
      if (p != el_distribution2d_pdf(&d, x, y) || p <= 0) ++bad;
      if (fabsf(a - u0) > 4e-7f * (1 + p) || fabsf(b - u1) > 4e-7f * (1 + p)) ++bad;
    }
    checkf(bad == 0, "2D 4x2: pdf(sample(u)) == pdf, invert(sample(u)) == u (to rounding) for 20000 u (%g bad)", bad, 0);
  }
  el_distribution2d_free(&d);

  /* non-power-of-two sizes and a shifted domain: pdf integrates to 1, consistency */
  {
    float g[15];
    int i, bad = 0;
    double sum = 0, integ = 0, area = 3.0 * 0.5;
    for (i = 0; i < 15; ++i) { g[i] = (float)(1 + (i * 7) % 5); sum += g[i]; }
    g[4] = 0; sum -= (1 + (4 * 7) % 5);
    opt.domain[0] = -1; opt.domain[1] = 10; opt.domain[2] = 2; opt.domain[3] = 10.5f;
    check(el_distribution2d_init(&d, g, 3, 5, &opt) == EL_SUCCESS, "2D 3x5 on [-1,2]x[10,10.5]: init");
    for (v = 0; v < 5; ++v)
      for (u = 0; u < 3; ++u) integ += el_distribution2d_pdf(&d, -1 + u + 0.5f, 10 + (v + 0.5f) * 0.1f) * area / 15;
    checkf(fabs(integ - 1) < 1e-6, "2D 3x5: pdf integrates to 1 over the domain (%.9g)", integ, 0);
    checkf(fabs(el_distribution2d_integral(&d) - sum * area / 15) < 1e-6 * sum, "2D 3x5: integral %.9g == %.9g", el_distribution2d_integral(&d), sum * area / 15);
    for (i = 0; i < 20000; ++i) {
      float x, y, p;
      el_distribution2d_sample(&d, rndu(), rndu(), &x, &y, &p);
      if (!(x >= -1 && x < 2 && y >= 10 && y < 10.5f && p > 0 && p == el_distribution2d_pdf(&d, x, y))) ++bad;
    }
    {
      float x, y, p;
      el_distribution2d_sample(&d, 1.0f, 1.0f, &x, &y, &p);
      if (!(x < 2 && y < 10.5f && p == el_distribution2d_pdf(&d, x, y))) ++bad;
      el_distribution2d_sample(&d, 0.0f, 0.0f, &x, &y, &p);
      if (!(x >= -1 && y >= 10 && p == el_distribution2d_pdf(&d, x, y))) ++bad;
    }
    checkf(bad == 0, "2D 3x5: samples inside the domain (also u = 0, 1), pdf > 0 and == pdf() (%g bad)", bad, 0);
    el_distribution2d_free(&d);
  }
  /* 1x1, 1xN, Nx1 */
  {
    float one = 3.0f, line[5] = {1, 0, 2, 0, 1};
    float x, y, p;
    int bad = 0, i;
    check(el_distribution2d_init(&d, &one, 1, 1, NULL) == EL_SUCCESS, "2D 1x1: init");
    el_distribution2d_sample(&d, 0.7f, 1.0f, &x, &y, &p);
    check(p == 1.0f && fabsf(x - 0.7f) < 1e-6f && y < 1.0f && el_distribution2d_integral(&d) == 3.0f, "2D 1x1: uniform, pdf 1, integral 3");
    el_distribution2d_free(&d);
    int shape, m;
    for (shape = 0; shape < 3; ++shape) {
      int nu = shape == 0 ? 5 : 1, nv = shape == 1 ? 5 : 1;
      el_distribution2d_fast fs[2];
      el_distribution_fast_options fo;
      check(el_distribution2d_init(&d, shape == 2 ? &one : line, nu, nv, NULL) == EL_SUCCESS, shape == 0 ? "2D 5x1: init" : shape == 1 ? "2D 1x5: init" : "2D 1x1 again: init");
      memset(&fo, 0, sizeof fo);
      el_distribution2d_fast_init(&fs[0], &d);
      fo.method = EL_DISTRIBUTION_FAST_ALIAS;
      el_distribution2d_fast_init_ex(&fs[1], &d, &fo);
      for (m = 0; m < 3; ++m)
        for (i = 0; i < 2000; ++i) {
          float u0 = i == 0 ? 1.0f : rndu(), u1 = i == 0 ? 1.0f : rndu();
          if (m == 0) el_distribution2d_sample(&d, u0, u1, &x, &y, &p);
          else el_distribution2d_fast_sample(&fs[m - 1], u0, u1, &x, &y, &p);
          if (!(x >= 0 && x < 1 && y >= 0 && y < 1)) { ++bad; continue; }
          u = (int)(x * 5 * (nu == 5)) + (int)(y * 5 * (nv == 5));
          if (shape == 2) { if (p != 1.0f) ++bad; continue; }
          if (line[u] == 0 || p != el_distribution2d_pdf(&d, x, y) || fabs(p - line[u] / 0.8) > 1e-5) ++bad;
        }
      el_distribution2d_fast_free(&fs[0]); el_distribution2d_fast_free(&fs[1]);
      el_distribution2d_free(&d);
    }
    checkf(bad == 0, "2D 5x1, 1x5, 1x1 with CDF, guide and alias: only positive bins, pdf == f/integral (%g bad)", bad, 0);
  }
}

/* ---- bisection: exact interval widths of a monotone 2D sampler, domain [0,1]^2, power-of-two sizes ---- */
typedef struct {
  const el_distribution2d *d;
  const el_distribution2d_fast *fast;
} sampler;
static void sample_any(const sampler *s, float u0, float u1, float *x, float *y, float *p) {
  if (s->fast) el_distribution2d_fast_sample(s->fast, u0, u1, x, y, p);
  else el_distribution2d_sample(s->d, u0, u1, x, y, p);
}
static int row_of(const sampler *s, uint32_t k) {
  float x, y, p;
  sample_any(s, 0.5f, (float)k * (1.0f / 16777216.0f), &x, &y, &p);
  return (int)(y * (float)s->d->nv);
}
static int col_of(const sampler *s, float u1, uint32_t k) {
  float x, y, p;
  sample_any(s, (float)k * (1.0f / 16777216.0f), u1, &x, &y, &p);
  return (int)(x * (float)s->d->nu);
}
/* first k in [0, 2^24] whose row is >= r (2^24 if none) */
static uint32_t first_row(const sampler *s, int r) {
  uint32_t lo = 0, hi = 16777216u;
  while (lo < hi) { uint32_t mid = lo + (hi - lo) / 2; if (row_of(s, mid) >= r) hi = mid; else lo = mid + 1; }
  return lo;
}
static uint32_t first_col(const sampler *s, float u1, int c) {
  uint32_t lo = 0, hi = 16777216u;
  while (lo < hi) { uint32_t mid = lo + (hi - lo) / 2; if (col_of(s, u1, mid) >= c) hi = mid; else lo = mid + 1; }
  return lo;
}

/* Marginal: every row's exact u1-interval width; then, for the rows listed, every column's u0 interval.
 * Compares P(row) * P(col | row) * nu * nv with pdf() at the bin centre, and positivity with f. */
static void exact_2d(const sampler *s, const float *f, const int *rows, int nrows, const char *name) {
  const el_distribution2d *d = s->d;
  int nu = d->nu, nv = d->nv, r, c, i;
  uint32_t *fr = (uint32_t *)malloc(((size_t)nv + 1) * sizeof(uint32_t));
  uint32_t *fc = (uint32_t *)malloc(((size_t)nu + 1) * sizeof(uint32_t));
  int bad_rows = 0, unreached_rows = 0, bad_cols = 0, unreached_cols = 0;
  char buf[256];
  for (r = 0; r <= nv; ++r) fr[r] = r == 0 ? 0 : first_row(s, r);
  for (r = 0; r < nv; ++r) {
    double rowsum = 0;
    for (c = 0; c < nu; ++c) rowsum += f[(size_t)r * nu + c];
    if (rowsum > 0 && fr[r + 1] == fr[r]) ++unreached_rows;
    if (rowsum == 0 && fr[r + 1] != fr[r]) ++bad_rows;
  }
  for (i = 0; i < nrows; ++i) {
    float u1;
    r = rows[i];
    if (fr[r + 1] == fr[r]) continue;
    u1 = (float)fr[r] * (1.0f / 16777216.0f);
    for (c = 0; c <= nu; ++c) fc[c] = c == 0 ? 0 : first_col(s, u1, c);
    for (c = 0; c < nu; ++c) {
      double pr = (fr[r + 1] - fr[r]) / UNITS, pc = (fc[c + 1] - fc[c]) / UNITS, expect = pr * pc * nu * nv;
      float p = el_distribution2d_pdf(d, (c + 0.5f) / nu, (r + 0.5f) / nv);
      float fv = f[(size_t)r * nu + c];
      if (fv > 0 && pc == 0) ++unreached_cols;
      if (fv == 0 && pc != 0) ++bad_cols;
      if (fabs(p - expect) > expect * 2.5e-7) ++bad_cols;
    }
  }
  snprintf(buf, sizeof buf, "%s: all %d rows: positive rows reachable (%d not), zero rows never sampled (%d are)", name, nv, unreached_rows, bad_rows);
  check(unreached_rows == 0 && bad_rows == 0, buf);
  snprintf(buf, sizeof buf, "%s: %d rows x %d columns: P(row)P(col|row) from exact u-interval widths == pdf * bin area (%d differ), positive bins reachable (%d not)",
           name, nrows, nu, bad_cols, unreached_cols);
  check(bad_cols == 0 && unreached_cols == 0, buf);
  free(fr); free(fc);
}

/* ---- chi-square of the three samplers on a random 32x16 distribution with a 1e6 range ---- */
static void test_chi2_2d(void) {
  enum { NU = 32, NV = 16, NS = 1000000 };
  static float f[NU * NV];
  static double e[NU * NV], of[NU * NV], oc[NU * NV], og[NU * NV], oa[NU * NV];
  el_distribution2d d;
  el_distribution2d_fast fg, fa;
  el_distribution_fast_options fo;
  double S = 0;
  int i, rows[NV], bad = 0, same = 1;
  sampler s;
  for (i = 0; i < NU * NV; ++i) {
    uint32_t h = hash32((uint32_t)i + 12345u);
    f[i] = (h % 11u == 0) ? 0.0f : (float)pow(10.0, -3.0 + 6.0 * (h >> 8) / 16777216.0);
    S += f[i];
  }
  for (i = 0; i < NV; ++i) { f[i * NU + 3] = 0; rows[i] = i; }
  for (i = 0; i < NU; ++i) f[5 * NU + i] = 0; /* an all-zero row */
  S = 0;
  for (i = 0; i < NU * NV; ++i) S += f[i];
  el_distribution2d_init(&d, f, NU, NV, NULL);
  memset(&fo, 0, sizeof fo);
  fo.method = EL_DISTRIBUTION_FAST_ALIAS;
  check(el_distribution2d_fast_init(&fg, &d) == EL_SUCCESS && el_distribution2d_fast_init_ex(&fa, &d, &fo) == EL_SUCCESS, "32x16: guide and alias samplers build");
  for (i = 0; i < NU * NV; ++i) {
    e[i] = el_distribution2d_pdf(&d, (i % NU + 0.5f) / NU, (i / NU + 0.5f) / NV) / (NU * NV) * NS;
    of[i] = f[i] / S * NS;
  }
  for (i = 0; i < NS; ++i) {
    float u0 = rndu(), u1 = rndu(), x, y, p, xg, yg, pg, xa, ya, pa;
    int b;
    el_distribution2d_sample(&d, u0, u1, &x, &y, &p);
    el_distribution2d_fast_sample(&fg, u0, u1, &xg, &yg, &pg);
    el_distribution2d_fast_sample(&fa, u0, u1, &xa, &ya, &pa);
    b = (int)(y * NV) * NU + (int)(x * NU); oc[b] += 1;
    if (p != el_distribution2d_pdf(&d, x, y)) ++bad;
    if (xg != x || yg != y || pg != p) same = 0;
    b = (int)(ya * NV) * NU + (int)(xa * NU); oa[b] += 1;
    if (pa != el_distribution2d_pdf(&d, xa, ya) || pa != el_distribution2d_fast_pdf(&fa, xa, ya) || !(xa < 1 && ya < 1)) ++bad;
    (void)og;
  }
  check(same, "guide sampler returns exactly the CDF sampler's points and pdfs (1e6 random u)");
  checkf(bad == 0, "CDF and alias samplers: pdf(sample) == sample's pdf for 1e6 u (%g bad)", bad, 0);
  chi2_check(e, oc, NU * NV, "32x16, CDF sampler vs stated pdf");
  chi2_check(e, oa, NU * NV, "32x16, alias sampler vs stated pdf");
  chi2_check(of, oc, NU * NV, "32x16, CDF sampler vs f/sum itself");
  chi2_check(of, oa, NU * NV, "32x16, alias sampler vs f/sum itself");
  s.d = &d; s.fast = NULL;
  exact_2d(&s, f, rows, NV, "32x16 CDF sampler");
  s.fast = &fg;
  exact_2d(&s, f, rows, NV, "32x16 guide sampler");
  el_distribution2d_fast_free(&fg); el_distribution2d_fast_free(&fa);
  el_distribution2d_free(&d);
}

/* ---- alias table: exact frequencies by full enumeration of one dimension at a time ---- */
static void test_alias_exact(void) {
  enum { NU = 8, NV = 3 };
  float f[NU * NV] = {1, 0, 1e6f, 3, 1e-3f, 7, 0, 2,   0, 0, 0, 0, 0, 0, 0, 0,   5, 5, 5, 5, 1e-6f, 5, 5, 0};
  el_distribution2d d;
  el_distribution2d_fast fa;
  el_distribution_fast_options fo;
  double rc[NV] = {0}, cc[NU];
  uint32_t k;
  int r, c, bad = 0;
  memset(&fo, 0, sizeof fo);
  fo.method = EL_DISTRIBUTION_FAST_ALIAS;
  el_distribution2d_init(&d, f, NU, NV, NULL);
  el_distribution2d_fast_init_ex(&fa, &d, &fo);
  for (k = 0; k < 16777216u; ++k) {
    float x, y, p;
    el_distribution2d_fast_sample(&fa, 0.37f, (float)k * (1.0f / 16777216.0f), &x, &y, &p);
    rc[(int)(y * NV)] += 1;
  }
  for (r = 0; r < NV; r += 2) { /* rows 0 and 2 (row 1 is all zero and must get nothing) */
    float u1 = -1;
    for (k = 0; k < 16777216u && u1 < 0; ++k) {
      float x, y, p;
      el_distribution2d_fast_sample(&fa, 0.5f, (float)k * (1.0f / 16777216.0f), &x, &y, &p);
      if ((int)(y * NV) == r) u1 = (float)k * (1.0f / 16777216.0f);
    }
    memset(cc, 0, sizeof cc);
    for (k = 0; k < 16777216u; ++k) {
      float x, y, p;
      el_distribution2d_fast_sample(&fa, (float)k * (1.0f / 16777216.0f), u1, &x, &y, &p);
      cc[(int)(x * NU)] += 1;
    }
    for (c = 0; c < NU; ++c) {
      double expect = rc[r] / UNITS * cc[c] / UNITS * NU * NV;
      float p = el_distribution2d_pdf(&d, (c + 0.5f) / NU, (r + 0.5f) / NV);
      if (fabs(p - expect) > 2.5e-7 * expect || ((f[r * NU + c] > 0) != (cc[c] > 0))) ++bad;
    }
  }
  checkf(rc[1] == 0 && bad == 0, "alias 8x3 (1e-6..1e6, zero row): all 2^24 u per dimension: frequencies == stated pdf, positive bins reached, zero bins never (%g bad)", bad, 0);
  el_distribution2d_fast_free(&fa);
  el_distribution2d_free(&d);
}

/* ---- fast samplers on a general domain and non-power-of-two sizes ---- */
static void test_fast_general(void) {
  enum { NU = 7, NV = 5 };
  float f[NU * NV];
  el_distribution2d d;
  el_distribution2d_fast fg, fa;
  el_distribution_fast_options fo;
  el_distribution_options opt;
  double cc[NU], rc[NV];
  int i, bad = 0, same = 1, r, c;
  uint32_t k;
  for (i = 0; i < NU * NV; ++i) f[i] = (float)((i * 5) % 9);   /* zeros at 0, 9, 18, 27 */
  memset(&opt, 0, sizeof opt);
  opt.domain[0] = -1; opt.domain[1] = 10; opt.domain[2] = 2.5f; opt.domain[3] = 10.3f;
  memset(&fo, 0, sizeof fo);
  el_distribution2d_init(&d, f, NU, NV, &opt);
  check(el_distribution2d_fast_init(&fg, &d) == EL_SUCCESS, "7x5 on [-1,2.5]x[10,10.3]: guide builds");
  fo.method = EL_DISTRIBUTION_FAST_ALIAS;
  check(el_distribution2d_fast_init_ex(&fa, &d, &fo) == EL_SUCCESS, "7x5 on [-1,2.5]x[10,10.3]: alias builds");
  for (i = 0; i < 100000; ++i) {
    float u0 = rndu(), u1 = rndu(), x, y, p, xg, yg, pg, xa, ya, pa;
    if (i == 0) { u0 = 1.0f; u1 = 1.0f; }
    if (i == 1) { u0 = 0.0f; u1 = 0.0f; }
    if (i == 2) { u0 = (float)NAN; u1 = -3.0f; }
    el_distribution2d_sample(&d, u0, u1, &x, &y, &p);
    el_distribution2d_fast_sample(&fg, u0, u1, &xg, &yg, &pg);
    el_distribution2d_fast_sample(&fa, u0, u1, &xa, &ya, &pa);
    if (xg != x || yg != y || pg != p) same = 0;
    if (!(xa >= -1 && xa < 2.5f && ya >= 10 && ya < 10.3f && pa > 0 && pa == el_distribution2d_pdf(&d, xa, ya) &&
          pa == el_distribution2d_fast_pdf(&fa, xa, ya)))
      ++bad;
    if (!(x >= -1 && x < 2.5f && y >= 10 && y < 10.3f && p > 0 && p == el_distribution2d_pdf(&d, x, y))) ++bad;
  }
  checkf(same && bad == 0, "7x5 general domain: guide == CDF bit for bit, alias and CDF points inside with pdf == pdf() (%g bad)", bad, 0);
  /* exact alias frequencies with non-power-of-two cells: all 2^24 u1 (rows), then all 2^24 u0 in row 2 */
  memset(rc, 0, sizeof rc);
  memset(cc, 0, sizeof cc);
  for (k = 0; k < 16777216u; ++k) {
    float x, y, p;
    el_distribution2d_fast_sample(&fa, 0.5f, (float)k * (1.0f / 16777216.0f), &x, &y, &p);
    rc[el_distribution2d__bin(y, 10.0f, d.v_scale, NV)] += 1;
  }
  {
    float u1 = -1;
    for (k = 0; k < 16777216u && u1 < 0; ++k) {
      float x, y, p;
      el_distribution2d_fast_sample(&fa, 0.5f, (float)k * (1.0f / 16777216.0f), &x, &y, &p);
      if (el_distribution2d__bin(y, 10.0f, d.v_scale, NV) == 2) u1 = (float)k * (1.0f / 16777216.0f);
    }
    for (k = 0; k < 16777216u; ++k) {
      float x, y, p;
      el_distribution2d_fast_sample(&fa, (float)k * (1.0f / 16777216.0f), u1, &x, &y, &p);
      cc[el_distribution2d__bin(x, -1.0f, d.u_scale, NU)] += 1;
    }
  }
  bad = 0;
  r = 2;
  for (c = 0; c < NU; ++c) {
    /* pdf * bin area = P(row) P(col | row); bin area = (3.5/7) * (0.3/5) */
    double expect = rc[r] / UNITS * cc[c] / UNITS;
    double got = (double)el_distribution2d_pdf(&d, -1.0f + 0.5f * (c + 0.5f), 10.0f + 0.06f * (r + 0.5f)) * (3.5 / 7) * (0.3 / 5);
    if (fabs(got - expect) > 1e-6 * expect || ((f[r * NU + c] > 0) != (cc[c] > 0))) ++bad;
  }
  for (r = 0; r < NV; ++r) {
    double rowsum = 0, expect = rc[r] / UNITS, got = 0;
    for (c = 0; c < NU; ++c) {
      rowsum += f[r * NU + c];
      got += (double)el_distribution2d_pdf(&d, -1.0f + 0.5f * (c + 0.5f), 10.0f + 0.06f * (r + 0.5f)) * (3.5 / 7) * (0.3 / 5);
    }
    if (fabs(got - expect) > 1e-6 || (rowsum > 0) != (rc[r] > 0)) ++bad;
  }
  checkf(bad == 0, "7x5 alias, all 2^24 u per dimension: row and column frequencies == stated pdf x area (%g bad)", bad, 0);
  el_distribution2d_fast_free(&fg); el_distribution2d_fast_free(&fa);
  el_distribution2d_free(&d);
}

/* ---- 8192 x 4096 with a 1e12 range ---- */
static void test_large(void) {
  const int nu = 8192, nv = 4096;
  size_t n = (size_t)nu * nv, i;
  float *f = (float *)malloc(n * sizeof(float));
  el_distribution2d d;
  el_distribution2d_fast fg;
  double S = 0, t0, t1, maxrow = -1, minrow = 1e300;
  int rows[16], nrows = 0, r, bad = 0, same = 1, rmax = 0, rmin = 0;
  sampler s;
  if (!f) { check(0, "8192x4096: allocate input"); return; }
  for (i = 0; i < n; ++i) {
    /* exponent in [-20, 19] (2^40 ~ 1.1e12 range), random mantissa, about 1 in 64 texels zero */
    uint32_t h = hash32((uint32_t)i * 2654435761u + 7u);
    uint32_t bits = ((uint32_t)(127 - 20 + (int)((h >> 23) % 40u)) << 23) | (h & 0x7fffffu);
    float x;
    memcpy(&x, &bits, 4);
    f[i] = ((h >> 17) & 63u) == 0 ? 0.0f : x;
  }
  f[(size_t)1234 * nu + 4321] = 1e12f * 1e-6f * 1e6f; /* a 1e12 sun */
  for (r = 0; r < nv; ++r) {
    double rs = 0;
    const float *row = f + (size_t)r * nu;
    int c;
    for (c = 0; c < nu; ++c) rs += row[c];
    S += rs;
    if (rs > maxrow) { maxrow = rs; rmax = r; }
    if (rs < minrow) { minrow = rs; rmin = r; }
  }
  t0 = now();
  check(el_distribution2d_init(&d, f, nu, nv, NULL) == EL_SUCCESS, "8192x4096 (1e12 range + 1e12 sun): init");
  t1 = now();
  printf("      (construction %.3f s, %.1f MB)\n", t1 - t0, el_distribution2d_bytes(&d) / 1048576.0);
  checkf(fabs(el_distribution2d_integral(&d) - S / n) <= 1e-6 * S / n, "8192x4096: integral %.9g == sum/n %.9g", el_distribution2d_integral(&d), S / n);
  check(el_distribution2d_fast_init(&fg, &d) == EL_SUCCESS, "8192x4096: guide table builds");
  rows[nrows++] = 0; rows[nrows++] = nv - 1; rows[nrows++] = rmax; rows[nrows++] = rmin; rows[nrows++] = 1234;
  while (nrows < 8) { rows[nrows] = (int)(hash32((uint32_t)nrows) % (uint32_t)nv); ++nrows; }
  s.d = &d; s.fast = &fg;
  exact_2d(&s, f, rows, nrows, "8192x4096 guide sampler");
  for (i = 0; i < 200000; ++i) {
    float u0 = rndu(), u1 = rndu(), x, y, p, xg, yg, pg;
    el_distribution2d_sample(&d, u0, u1, &x, &y, &p);
    el_distribution2d_fast_sample(&fg, u0, u1, &xg, &yg, &pg);
    if (!(p > 0 && p == el_distribution2d_pdf(&d, x, y) && x < 1 && y < 1)) ++bad;
    if (xg != x || yg != y || pg != p) same = 0;
  }
  checkf(bad == 0 && same, "8192x4096: 2e5 samples: pdf > 0 and == pdf(); guide == CDF sampler (%g bad)", bad, 0);
  el_distribution2d_fast_free(&fg);
  el_distribution2d_free(&d);
  free(f);
}

/* el_distribution2d_sample_bins (binary searches) against sample()'s point, and the guide table's
 * inline el_distribution2d_fast_sample_bins (_try + _general) against sample_bins, bit for bit, on a map
 * whose sun crowds the guide cells of the dim rows (so both the inline path and its fallback run). */
static void test_sample_bins(void) {
  const int nu = 512, nv = 256;
  float *f = (float *)malloc((size_t)nu * nv * sizeof(float));
  el_distribution2d d;
  el_distribution2d_fast g, a;
  el_distribution_fast_options fo;
  int i, n = 200000, bad_point = 0, bad_guide = 0, bad_alias = 0, tried = 0, fell_back = 0;
  static const float edge[] = {0.0f, 0x1.fffffep-1f, 1.0f, -0.5f, 2.0f, 0.5f};
  char buf[256];
  for (i = 0; i < nu * nv; ++i) f[i] = (i % 7 == 3) ? 0.0f : 0.5f + (float)(hash32((uint32_t)i) >> 8) * (1.0f / 16777216.0f);
  f[100 * nu + 300] = 3e4f; /* a sun (a quarter of the mass): the other bins of its rows crowd the guide cells */
  f[101 * nu + 301] = 1e4f;
  memset(&fo, 0, sizeof fo);
  fo.method = EL_DISTRIBUTION_FAST_ALIAS;
  if (el_distribution2d_init(&d, f, nu, nv, NULL) != EL_SUCCESS || el_distribution2d_fast_init(&g, &d) != EL_SUCCESS ||
      el_distribution2d_fast_init_ex(&a, &d, &fo) != EL_SUCCESS) { check(0, "sample_bins: init"); free(f); return; }
  for (i = 0; i < n + 36; ++i) {
    float u0, u1, x, y, pdf, fu, fv, gfu, gfv, afu, afv, t, bp, gp, ap;
    int iu, iv, giu, giv, aiu, aiv;
    if (i < n) {
      u0 = rndu(); u1 = rndu();
    } else { u0 = edge[(i - n) % 6]; u1 = edge[(i - n) / 6]; }
    el_distribution2d_sample_bins(&d, u0, u1, &iu, &iv, &fu, &fv, &bp);
    el_distribution2d_sample(&d, u0, u1, &x, &y, &pdf);
    /* sample() places its point at (bin + fraction) / n on this exact [0,1]^2 (one ulp lower on a carry) */
    t = (float)iu + fu;
    if ((int)(x * nu) != iu || (int)(y * nv) != iv || !(fu >= 0.0f && fu <= 1.0f && fv >= 0.0f && fv <= 1.0f) ||
        ((int)t == iu && x != t / nu) || pdf != el_distribution2d_pdf(&d, x, y) || !(pdf > 0.0f) || bp != pdf) ++bad_point;
    if (i < n && u0 >= 0.0f && u0 < 1.0f && u1 >= 0.0f && u1 < 1.0f) {
      ++tried;
      if (!el_distribution2d_fast_sample_bins_try(&g, u0, u1, &giu, &giv, &gfu, &gfv, &gp)) ++fell_back;
    }
    el_distribution2d_fast_sample_bins(&g, u0, u1, &giu, &giv, &gfu, &gfv, &gp);
    if (giu != iu || giv != iv || gfu != fu || gfv != fv || gp != bp) ++bad_guide;
    el_distribution2d_fast_sample_bins(&a, u0, u1, &aiu, &aiv, &afu, &afv, &ap);
    if (!(ap > 0.0f) || ap != el_distribution2d_pdf(&d, (aiu + 0.5f) / nu, (aiv + 0.5f) / nv) || !(afu >= 0.0f && afu <= 1.0f && afv >= 0.0f && afv <= 1.0f)) ++bad_alias;
  }
  snprintf(buf, sizeof buf, "sample_bins: the bin of sample()'s point, its fraction, its pdf, > 0 (%d bad of %d, edge u included)", bad_point, n + 36);
  check(bad_point == 0, buf);
  snprintf(buf, sizeof buf, "fast_sample_bins (guide) == sample_bins bit for bit (%d bad); the inline path ran %d times and fell back %d times",
           bad_guide, tried - fell_back, fell_back);
  check(bad_guide == 0 && fell_back > 0 && tried - fell_back > 0, buf);
  snprintf(buf, sizeof buf, "fast_sample_bins (alias): positive bins, their pdf() exactly, fractions in [0,1] (%d bad)", bad_alias);
  check(bad_alias == 0, buf);
  el_distribution2d_fast_free(&a);
  el_distribution2d_fast_free(&g);
  el_distribution2d_free(&d);
  free(f);
}

/* The documented maximum, 2^22 bins per dimension, works on the unit domain, and one more bin is refused
 * (before, 2^22 bins were refused: the resolution check used the float step above 1, 2^-23, though every
 * point lies below 1, where the step is 2^-24). At the limit each bin holds exactly 4 floats: samples
 * must land in their own bin (counted here in double), strictly below 1, with pdf(x) == the sampled pdf;
 * the last bin is reached. The resolution rule itself: [0, 0.5] takes 2^22 bins (4 steps of 2^-25 each),
 * [0, 0.75] does not (3 steps of 2^-24). */
static void test_max_bins(void) {
  const int n = EL_DISTRIBUTION_MAX_BINS;
  float *f = (float *)malloc((size_t)n * sizeof(float)), x, y, p, q;
  el_distribution1d d;
  el_distribution2d d2;
  el_distribution2d_fast fast;
  el_distribution_options opt;
  int i, wrong = 0, last = 0, off;
  char buf[256];
  if (!f) { check(0, "2^22 bins: allocate"); return; }
  for (i = 0; i < n; ++i) f[i] = (hash32((uint32_t)i) & 7u) == 0 ? 0.0f : (float)(hash32((uint32_t)i) >> 8) * 1e-6f;
  f[n - 1] = 1e6f; /* the last bin gets many units */
  memset(&opt, 0, sizeof opt);
  check(n == 4194304, "EL_DISTRIBUTION_MAX_BINS is 2^22");
  check(el_distribution1d_init(&d, f, n + 1, &opt) == EL_ERROR_SIZE_OVERFLOW, "1D, 2^22 + 1 bins: EL_ERROR_SIZE_OVERFLOW");
  if (el_distribution1d_init(&d, f, n, &opt) != EL_SUCCESS) {
    check(0, "1D, 2^22 bins on [0,1]: accepted");
    free(f);
    return;
  }
  for (i = 0; i < 200000; ++i) {
    float u = i < 4 ? (i == 0 ? 0.0f : i == 1 ? ONE_MINUS : i == 2 ? 1.0f : 0.5f) : rndu();
    int bin;
    x = el_distribution1d_sample_continuous(&d, u, &p, &off);
    bin = (int)floor((double)x * n);
    q = el_distribution1d_pdf(&d, x);
    if (!(x >= 0.0f && x < 1.0f) || bin != off || p != q || !(p > 0.0f)) ++wrong;
    last += off == n - 1;
  }
  snprintf(buf, sizeof buf, "1D, 2^22 bins: 200000 samples in their own bin, below 1, pdf(x) == pdf (%d wrong; %d in the last bin)", wrong, last);
  check(wrong == 0 && last > 0, buf);
  el_distribution1d_free(&d);
  opt.domain[2] = 0.5f;
  check(el_distribution1d_init(&d, f, n, &opt) == EL_SUCCESS, "1D, 2^22 bins on [0, 0.5]: accepted (4 steps of 2^-25 per bin)");
  el_distribution1d_free(&d);
  opt.domain[2] = 0.75f;
  check(el_distribution1d_init(&d, f, n, &opt) == EL_ERROR_INVALID_ARGUMENT, "1D, 2^22 bins on [0, 0.75]: refused (3 steps of 2^-24 per bin)");
  memset(&opt, 0, sizeof opt);
  /* 2D: a 2^22 x 1 and a 1 x 2^22 distribution, with the CDF and the guide-table samplers */
  check(el_distribution2d_init(&d2, f, n + 1, 1, &opt) == EL_ERROR_SIZE_OVERFLOW && el_distribution2d_init(&d2, f, 1, n + 1, &opt) == EL_ERROR_SIZE_OVERFLOW,
        "2D, 2^22 + 1 columns or rows: EL_ERROR_SIZE_OVERFLOW");
  for (off = 0; off < 2; ++off) {
    int nu = off ? 1 : n, nv = off ? n : 1;
    wrong = 0;
    if (el_distribution2d_init(&d2, f, nu, nv, &opt) != EL_SUCCESS || el_distribution2d_fast_init(&fast, &d2) != EL_SUCCESS) {
      check(0, off ? "2D, 1 x 2^22: init" : "2D, 2^22 x 1: init");
      continue;
    }
    for (i = 0; i < 100000; ++i) {
      float u0 = rndu(), u1 = rndu(), fx, fy, fp;
      int bu, bv;
      el_distribution2d_sample(&d2, u0, u1, &x, &y, &p);
      el_distribution2d_fast_sample(&fast, u0, u1, &fx, &fy, &fp);
      bu = (int)floor((double)x * nu);
      bv = (int)floor((double)y * nv);
      q = el_distribution2d_pdf(&d2, x, y);
      if (!(x >= 0.0f && x < 1.0f && y >= 0.0f && y < 1.0f) || p != q || !(p > 0.0f) || fx != x || fy != y || fp != p ||
          (nu > 1 ? f[bu] : f[bv]) <= 0.0f)
        ++wrong;
    }
    snprintf(buf, sizeof buf, "2D, %s: 100000 samples below 1, in a positive bin, pdf == pdf(point), guide sampler identical (%d wrong)",
             off ? "1 x 2^22" : "2^22 x 1", wrong);
    check(wrong == 0, buf);
    el_distribution2d_fast_free(&fast);
    el_distribution2d_free(&d2);
  }
  free(f);
}

/* How many distinct points a bin gives (the header: bin i >= 1 has at most 2^(23 - floor(log2 i)), the
 * float step of t = i + fraction; a bin of w units at most half that wide has w; bin 0 has w): every
 * u = k 2^-24 of a bin's units is sampled, the distinct results counted (the sampler is monotone in u,
 * so a change between neighbours is a new point). */
static void test_positions(void) {
  static const int bins[5] = {0, 4000, 1, 700, 4000};
  static const float weight[5] = {30.0f, 0.25f, 1e9f, 1e9f, 1e9f};
  float f[4096];
  int b, i;
  char buf[256];
  for (b = 0; b < 5; ++b) {
    el_distribution1d d;
    uint32_t k, w, distinct = 0;
    float prev = -1.0f;
    long cap;
    int e = 0, ok;
    for (i = 0; i < 4096; ++i) f[i] = 1.0f;
    f[bins[b]] = weight[b];
    el_distribution1d_init(&d, f, 4096, NULL);
    w = d.cdf[bins[b] + 1] - d.cdf[bins[b]];
    for (k = d.cdf[bins[b]]; k < d.cdf[bins[b] + 1]; ++k) {
      int off;
      float x = el_distribution1d_sample_continuous(&d, (float)k * (1.0f / 16777216.0f), NULL, &off);
      if (off == bins[b] && x != prev) ++distinct;
      prev = x;
    }
    if (bins[b] >= 1)
      while ((2 << e) <= bins[b]) ++e; /* floor(log2 i) */
    cap = 1L << (23 - e);
    if (bins[b] == 0 || 2 * (long)w <= cap) ok = distinct == w;
    else ok = (long)distinct <= cap && (long)distinct >= cap - cap / 1000;
    snprintf(buf, sizeof buf, "bin %d of 4096 with %u units: %u distinct points (the header: %s, 2^(23 - floor(log2 i)) = %ld)",
             bins[b], w, distinct, bins[b] == 0 || 2 * (long)w <= cap ? "w" : "at most the float step's", cap);
    check(ok, buf);
    el_distribution1d_free(&d);
  }
}

int main(void) {
  double t = now();
  test_hand_1d();
  test_edges();
  test_all_zero();
  test_bad_input();
  test_pbrt_counterexample();
  test_dynamic_range_1d();
  test_hand_2d();
  test_chi2_2d();
  test_alias_exact();
  test_fast_general();
  test_sample_bins();
  test_large();
  test_max_bins();
  test_positions();
  printf("test_distribution2d: %d passed, %d failed (%.1f s)\n", g_pass, g_fail, now() - t);
  return g_fail != 0;
}
