/* test_tutorial_distribution.c: the course's plain port of pbrt-v3's Distribution1D / Distribution2D
 * (examples/pbrtv3/sampling.h, chapter 3) against distribution2d.h, on the same inputs.
 *
 * They cannot agree bit for bit: pbrt keeps a float CDF (a running float sum, then divided by its
 * total), the library an integer one (2^24 units per row, one unit at least for every bin with f > 0,
 * the rest shared out from 64-bit prefix sums). What the mathematics of the two allows, and what is
 * checked:
 *  1. Probabilities. Bin i's share of the row is q = f_i / sum f. The library's pmf is within
 *     (2 + m q) 2^-24 of q (m = the number of positive bins: its one-unit floor plus rounding), pbrt's
 *     within (n + 2) 2^-24 q (n float additions in funcInt, one division). So the two differ by at
 *     most the sum of both.
 *  2. Points. Both invert their CDF at u, linearly within the bin. So the library's point x, put
 *     through pbrt's CDF (linear within each bin), gives back u to within D = the largest difference
 *     between the two CDFs at any bin edge, plus the rounding of x itself (two float spacings of a
 *     point below 1, at most 2^-23, times the CDF's slope there) and 2^-22 for the rest. For 2D, the
 *     same holds for the marginal at u[1] and for the conditional of the row the library chose at u[0].
 *  3. What only the library does: every bin with f > 0 is reachable (pbrt's float CDF gives 3995 of
 *     the 4096 bins of the sun row a zero step: they are never sampled), and the pdf of the
 *     sampled point equals the pdf returned with it (pbrt's point (offset + du) / n can round up into
 *     the next bin, whose pdf Pdf() then returns).
 * Each bound is stated in the check that uses it; none is taken from either program's output.
 */
#define EL_DISTRIBUTION2D_IMPLEMENTATION
#include "distribution2d.h"
#include "../examples/pbrtv3/sampling.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#define UNIT (1.0 / 16777216.0) /* 2^-24 */

#define TUTORIAL_RNG_SEED 2024u
#include "tutorial_check.h" /* check, checkf, frand */

/* pbrt's CDF at x in [0, 1] (linear within each bin), in double */
static double pbrt_cdf_at(const pbrt_Distribution1D *d, double x) {
  double t = x * d->n;
  int o = (int)t;
  if (o >= d->n) o = d->n - 1;
  if (o < 0) o = 0;
  return d->cdf[o] + (t - o) * ((double)d->cdf[o + 1] - d->cdf[o]);
}
/* the slope of pbrt's CDF at x: the density there */
static double pbrt_slope_at(const pbrt_Distribution1D *d, double x) {
  int o = (int)(x * d->n);
  if (o >= d->n) o = d->n - 1;
  if (o < 0) o = 0;
  return ((double)d->cdf[o + 1] - d->cdf[o]) * d->n;
}
/* the largest difference between the two CDFs at a bin edge */
static double cdf_gap(const pbrt_Distribution1D *p, const uint32_t *c) {
  double D = 0;
  int i;
  for (i = 0; i <= p->n; ++i) {
    double g = fabs(c[i] * UNIT - p->cdf[i]);
    if (g > D) D = g;
  }
  return D;
}

/* 1. and 2. in 1D, on a row of n random values in [0.1, 10) */
static void test_row(int n) {
  float *f = (float *)malloc(sizeof(float) * (size_t)n);
  pbrt_Distribution1D p;
  el_distribution1d d;
  double sum = 0, worst = 0, D, worst_u = 0, worst_x = 0;
  int i, k, ok = 1, m = n;
  char what[160];
  for (i = 0; i < n; ++i) sum += f[i] = 0.1f + 9.9f * frand();
  check(pbrt_Distribution1D_init(&p, f, n) == 0 && el_distribution1d_init(&d, f, n, NULL) == EL_SUCCESS,
        "1D row: both build");
  for (i = 0; i < n; ++i) {
    double q = f[i] / sum, lib = (d.cdf[i + 1] - d.cdf[i]) * UNIT, pb = pbrt_Distribution1D_DiscretePDF(&p, i);
    double bound = (2 + m * q) * UNIT + (n + 2) * UNIT * q;
    if (!(fabs(lib - pb) <= bound)) ok = 0;
    if (fabs(lib - pb) / bound > worst) worst = fabs(lib - pb) / bound;
  }
  snprintf(what, sizeof what, "1D row of %d: every pmf of the library within (2 + m q) 2^-24 + (n + 2) 2^-24 q of pbrt's (worst %.2f of the bound)", n, worst);
  check(ok, what);
  D = cdf_gap(&p, d.cdf);
  ok = 1;
  for (k = 0; k < 100000; ++k) {
    float u = (k + 0.5f) / 100000.0f, x = el_distribution1d_sample_continuous(&d, u, NULL, NULL);
    float xp = pbrt_Distribution1D_SampleContinuous(&p, u, NULL, NULL);
    double e = fabs(pbrt_cdf_at(&p, x) - u);
    if (!(e <= D + 2 * UNIT * pbrt_slope_at(&p, x) + 4 * UNIT)) ok = 0;
    if (e > worst_u) worst_u = e;
    if (fabs(x - xp) > worst_x) worst_x = fabs(x - xp);
  }
  checkf(ok, "1D row: pbrt's CDF at the library's point is u to within D + rounding (D = %.3g, worst %.3g)", D, worst_u);
  printf("      (the two points differ by at most %.3g of the interval)\n", worst_x);
  pbrt_Distribution1D_free(&p);
  el_distribution1d_free(&d);
  free(f);
}

/* 3. the sun row: 4096 bins of 1e-2, one of 1e6 */
static void test_sun_row(void) {
  enum { N = 4096 };
  static float f[N];
  pbrt_Distribution1D p;
  el_distribution1d d;
  int i, dead_pbrt = 0, dead_lib = 0;
  double lost = 0;
  for (i = 0; i < N; ++i) f[i] = 1e-2f;
  f[100] = 1e6f;
  check(pbrt_Distribution1D_init(&p, f, N) == 0 && el_distribution1d_init(&d, f, N, NULL) == EL_SUCCESS,
        "sun row: both build");
  for (i = 0; i < N; ++i) {
    if (f[i] > 0 && p.cdf[i + 1] == p.cdf[i]) { ++dead_pbrt; lost += f[i]; }
    if (f[i] > 0 && d.cdf[i + 1] == d.cdf[i]) ++dead_lib;
  }
  checkf(dead_pbrt == 3995 && dead_lib == 0,
         "sun row: positive bins with a zero CDF step: pbrt %.0f (issue: 3995), library %.0f", dead_pbrt, dead_lib);
  printf("      (pbrt never samples %.3g of the row's integral)\n", lost / (1e6 + (N - 1) * 1e-2));
  pbrt_Distribution1D_free(&p);
  el_distribution1d_free(&d);
}

/* 1. and 2. in 2D, on a 64 x 32 map like an environment: a sky, a dark ground, a sun, times sin theta */
static void test_map(void) {
  enum { NU = 64, NV = 32 };
  static float f[NU * NV];
  pbrt_Distribution2D p;
  el_distribution2d d;
  double total = 0, Dm, worst = 0, worst_m = 0, worst_c = 0;
  int u, v, k, ok = 1, okm = 1, okc = 1, mv = NV, mu = NU;
  for (v = 0; v < NV; ++v)
    for (u = 0; u < NU; ++u) {
      double s = sin(3.14159265358979 * (v + 0.5) / NV), sky = v < NV / 2 ? 1.0 + v * 0.1 : 0.05;
      double x = sky * (0.5 + frand());
      if (u == 20 && v == 9) x = 3e4;
      total += f[v * NU + u] = (float)(x * s);
    }
  check(pbrt_Distribution2D_init(&p, f, NU, NV) == 0 && el_distribution2d_init(&d, f, NU, NV, NULL) == EL_SUCCESS,
        "64 x 32 map with a sun: both build");
  /* 1. the density of each bin: pdf = pmf_row * pmf_column | row * nu * nv */
  for (v = 0; v < NV; ++v) {
    double rsum = 0, qv, ev;
    for (u = 0; u < NU; ++u) rsum += f[v * NU + u];
    qv = rsum / total;
    ev = (2 + mv * qv) * UNIT + (NV + 2) * UNIT * qv;
    for (u = 0; u < NU; ++u) {
      float pt[2];
      double qu = f[v * NU + u] / rsum, eu = (2 + mu * qu) * UNIT + (NU + 2) * UNIT * qu;
      double bound = (ev * qu + eu * qv + ev * eu) * NU * NV + 1e-6 * qv * qu * NU * NV;
      double lib, pb;
      pt[0] = (u + 0.5f) / NU;
      pt[1] = (v + 0.5f) / NV;
      lib = el_distribution2d_pdf(&d, pt[0], pt[1]);
      pb = pbrt_Distribution2D_Pdf(&p, pt);
      if (!(fabs(lib - pb) <= bound)) ok = 0;
      if (fabs(lib - pb) / bound > worst) worst = fabs(lib - pb) / bound;
    }
  }
  checkf(ok, "64 x 32 map: every bin's pdf agrees within the two rows' integer-CDF and float bounds (worst %.2f of the bound)", worst, 0);
  /* 2. points: marginal at u[1], the conditional of the library's row at u[0] */
  Dm = cdf_gap(&p.pMarginal, d.marginal);
  for (k = 0; k < 200000; ++k) {
    float uu[2], x, y, pdf;
    int row;
    double em, ec, Dc;
    uu[0] = frand();
    uu[1] = frand();
    el_distribution2d_sample(&d, uu[0], uu[1], &x, &y, &pdf);
    row = (int)(y * NV);
    em = fabs(pbrt_cdf_at(&p.pMarginal, y) - uu[1]);
    Dc = cdf_gap(&p.pConditionalV[row], d.cdf + (size_t)row * (NU + 1));
    ec = fabs(pbrt_cdf_at(&p.pConditionalV[row], x) - uu[0]);
    if (!(em <= Dm + 2 * UNIT * pbrt_slope_at(&p.pMarginal, y) + 4 * UNIT)) okm = 0;
    if (!(ec <= Dc + 2 * UNIT * pbrt_slope_at(&p.pConditionalV[row], x) + 4 * UNIT)) okc = 0;
    if (em > worst_m) worst_m = em;
    if (ec > worst_c) worst_c = ec;
  }
  checkf(okm, "64 x 32 map: pbrt's marginal CDF at the library's v is u[1] to within D + rounding (D = %.3g, worst %.3g)", Dm, worst_m);
  checkf(okc, "64 x 32 map: the row's conditional CDF at the library's u is u[0] to within that row's D + rounding (worst %.3g)", worst_c, 0);
  pbrt_Distribution2D_free(&p);
  el_distribution2d_free(&d);
}

/* 3. pdf(sample(u)) == pdf: a 4096 x 1 map of alternating 1 and 3, u just below each bin's upper CDF
 * edge. pbrt's offset + du is a float near the offset: from offset 2048 on its spacing is 2^-12 or
 * more, coarser than 1 - du, so it can round up to offset + 1, the next bin, whose pdf Pdf() returns. */
static void test_point_in_bin(void) {
  enum { N = 4096 };
  static float f[N];
  pbrt_Distribution2D p;
  el_distribution2d d;
  int i, bad_pbrt = 0, bad_lib = 0, tried = 0;
  for (i = 0; i < N; ++i) f[i] = (i & 1) ? 3.0f : 1.0f;
  check(pbrt_Distribution2D_init(&p, f, N, 1) == 0 && el_distribution2d_init(&d, f, N, 1, NULL) == EL_SUCCESS,
        "4096 x 1 alternating map: both build");
  for (i = 0; i < N - 1; ++i) {
    float uu[2], uv[2], pdf, x, y, pdfl;
    uu[0] = nextafterf(p.pConditionalV[0].cdf[i + 1], 0.0f);
    uu[1] = 0.5f;
    pbrt_Distribution2D_SampleContinuous(&p, uu, uv, &pdf);
    if (pbrt_Distribution2D_Pdf(&p, uv) != pdf) ++bad_pbrt;
    el_distribution2d_sample(&d, uu[0], uu[1], &x, &y, &pdfl);
    if (el_distribution2d_pdf(&d, x, y) != pdfl) ++bad_lib;
    ++tried;
  }
  checkf(bad_pbrt > 0 && bad_lib == 0,
         "u just below a bin's CDF edge: Pdf(sample) != the sampled pdf for %.0f points of pbrt's, %.0f of the library's", bad_pbrt, bad_lib);
  printf("      (%d points tried)\n", tried);
  pbrt_Distribution2D_free(&p);
  el_distribution2d_free(&d);
}

int main(void) {
  test_row(1000);
  test_row(4096);
  test_sun_row();
  test_map();
  test_point_in_bin();
  printf("%d passed, %d failed\n", g_pass, g_fail);
  return g_fail ? 1 : 0;
}
