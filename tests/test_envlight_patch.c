/* test_envlight_patch.c: importance BILINEAR's patch density (issue 22: the discrete table over le()'s
 * bilinear patches, then a bilinear warp inside the patch).
 *
 *   1. chi-square: samples against the density integrated from pdf_li over (u, v) bins (the midpoint rule
 *      on sub-cells that split every patch at its texel centres, exact for a piecewise-bilinear density
 *      up to float), on real maps (city, studio), a one-texel sun at 1e12 and one at 1e4, lit pole rows,
 *      1xN and Nx1 maps, under the identity, the y-up reflection and a general rotation; the integral of
 *      the pdf is 1;
 *   2. every sample's pdf equals pdf_li of its direction bit for bit, and its radiance is le(wi) (bit for
 *      bit, but on maps of at least 256 x 128 under a signed permutation le at the point's own (u, v): within
 *      2e-4 of the range of the four texels le() reads);
 *   3. unbiasedness: the mean of lum(L) / pdf equals the luminance integral of le (el_envlight_integral)
 *      within 4 standard errors;
 *   4. the reason for the mode: lum(le) / pdf is nearly constant (the density follows le inside the
 *      sun's texels), far more so than with the default cell averages;
 *   5. hostile inputs: NaN, zero, infinite, denormal and huge directions, u outside [0, 1) and NaN, and
 *      a NaN texel (refused at init, named by bad_index).
 */
#define EL_IMPLEMENTATION
#include "envlight.h"
#include "image_io.h"

#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifndef EL_TEST_DATA_DIR
#define EL_TEST_DATA_DIR "data"
#endif

#include "test_chisq.h"
#include "test_common.h" /* check, rotation37 */
#include "test_rng.h"    /* rng_f */
static rng g_rng = {0x9e3779b97f4a7c15ULL};

#define PI 3.14159265358979323846
#define NTESTS_CHI2 14 /* Bonferroni: the chi-square tests below */

static double lum3(const float *c) { return 0.212671 * c[0] + 0.715160 * c[1] + 0.072169 * c[2]; }

static int make(el_envlight *l, const float *px, int w, int h, int matrix, int importance) {
  el_envlight_options o;
  memset(&o, 0, sizeof o);
  o.importance = importance;
  if (matrix == 1) el_envlight_yup_matrix(o.light_to_world);
  if (matrix == 2) rotation37(o.light_to_world);
  return el_envlight_init(l, px, w, h, 3, &o) == EL_SUCCESS;
}

static void to_light(const el_envlight *l, const float w[3], float d[3]) { /* the transpose of to_world */
  const float *m = l->to_world;
  d[0] = m[0] * w[0] + m[3] * w[1] + m[6] * w[2];
  d[1] = m[1] * w[0] + m[4] * w[1] + m[7] * w[2];
  d[2] = m[2] * w[0] + m[5] * w[1] + m[8] * w[2];
}

/* 1 and 2: nu x nv bins in (u, v); k x k sub-cells per bin (k even: the sub-cell edges include the
 * texel centres when the bins are texels) */
static void chi2_map(const char *name, const float *px, int w, int h, int matrix, int nu, int nv, int k, int n) {
  el_envlight l;
  double *ex, *obs, total = 0, chi2, p;
  int i, j, a, b, used, impossible = 0, bad_pdf = 0, bad_rgb = 0, zero = 0;
  if (!make(&l, px, w, h, matrix, EL_ENVLIGHT_IMPORTANCE_BILINEAR)) { check(0, "%s: init", name); return; }
  /* at least two sub-cells per texel and axis: the midpoint rule is exact on each bilinear piece */
  while (k * nu < 2 * w || k * nv < 2 * h) k *= 2;
  ex = (double *)calloc((size_t)nu * nv, sizeof *ex);
  obs = (double *)calloc((size_t)nu * nv, sizeof *obs);
  for (j = 0; j < nv; ++j)
    for (i = 0; i < nu; ++i)
      for (b = 0; b < k; ++b)
        for (a = 0; a < k; ++a) {
          double u = (i + (a + 0.5) / k) / nu, v = (j + (b + 0.5) / k) / nv;
          float d[3], wd[3];
          const float *m = l.to_world;
          el_envlight_uv_to_dir((float)u, (float)v, d);
          wd[0] = m[0] * d[0] + m[1] * d[1] + m[2] * d[2];
          wd[1] = m[3] * d[0] + m[4] * d[1] + m[5] * d[2];
          wd[2] = m[6] * d[0] + m[7] * d[1] + m[8] * d[2];
          ex[(size_t)j * nu + i] += el_envlight_pdf_li(&l, wd) * sin(PI * v) * 2 * PI * PI / ((double)nu * nv * k * k);
        }
  for (i = 0; i < nu * nv; ++i) total += ex[i];
  for (i = 0; i < n; ++i) {
    float u[2], wi[3], rgb[3], pdf, d[3], uu, vv, le[3];
    int bu, bv;
    u[0] = rng_f(&g_rng); u[1] = rng_f(&g_rng);
    el_envlight_sample_li(&l, u, wi, rgb, &pdf);
    if (!(pdf > 0)) { ++zero; continue; }
    if (pdf != el_envlight_pdf_li(&l, wi)) ++bad_pdf;
    el_envlight_le(&l, wi, le);
    to_light(&l, wi, d);
    el_envlight_dir_to_uv(d, &uu, &vv);
    if (l.exact_transform && w >= 256 && h >= 128) {
      /* the fast path under a signed permutation: le at the point's own (u, v) (envlight.h: sample_li) */
      if (!rgb_near_le(px, w, h, uu, vv, le, rgb)) ++bad_rgb;
    } else if (le[0] != rgb[0] || le[1] != rgb[1] || le[2] != rgb[2]) ++bad_rgb;
    bu = (int)(uu * nu); bv = (int)(vv * nv);
    bu = bu < 0 ? 0 : bu >= nu ? nu - 1 : bu; bv = bv < 0 ? 0 : bv >= nv ? nv - 1 : bv;
    obs[(size_t)bv * nu + bu] += 1;
  }
  chi2 = chisq_pooled(ex, obs, (size_t)nu * nv, total, n - zero, &impossible, &used);
  p = used > 1 ? gammq((used - 1) / 2.0, chi2 / 2.0) : 1.0;
  check(fabs(total - 1) < 2e-3 && p > 1e-3 / NTESTS_CHI2 && impossible == 0 && zero == 0,
        "chi2 patch density %-34s: chi2 = %.1f, %d dof, p = %.3g (> %.2g), pdf integrates to %.5f, %d in zero-pdf bins, %d pdf 0",
        name, chi2, used - 1, p, 1e-3 / NTESTS_CHI2, total, impossible, zero);
  check(bad_pdf == 0 && bad_rgb == 0, "%-34s: sample pdf == pdf_li(wi) bit for bit, radiance le(wi) (bit for bit but for the fast path's signed permutations: 2e-4 of the texels' range) (%d, %d of %d differ)", name,
        bad_pdf, bad_rgb, n);
  free(ex); free(obs);
  el_envlight_free(&l);
}

/* 3 and 4: the mean and relative variance of lum(L) / pdf against the luminance integral */
static void moments(const el_envlight *l, int n, double *z, double *relvar) {
  double s1 = 0, s2 = 0, mean, var, ref;
  float in[3];
  int i;
  for (i = 0; i < n; ++i) {
    float u[2], wi[3], rgb[3], pdf;
    double x = 0;
    u[0] = rng_f(&g_rng); u[1] = rng_f(&g_rng);
    el_envlight_sample_li(l, u, wi, rgb, &pdf);
    if (pdf > 0) x = lum3(rgb) / pdf;
    s1 += x; s2 += x * x;
  }
  mean = s1 / n; var = (s2 - s1 * s1 / n) / (n - 1);
  el_envlight_integral(l, in);
  ref = lum3(in);
  *z = fabs(mean - ref) / sqrt(var / n + 1e-30 * ref * ref);
  *relvar = var / (ref * ref);
}

static float *sun_map(int w, int h, int sx, int sy, float sun) {
  float *px = (float *)malloc(sizeof(float) * 3 * (size_t)w * h);
  int i;
  for (i = 0; i < 3 * w * h; ++i) px[i] = 1.0f;
  for (i = 0; i < 3; ++i) px[3 * ((size_t)sy * w + sx) + i] = sun;
  return px;
}

int main(void) {
  el_image city, studio;
  char path[512], err[256];
  float *sun12, *sun4, *poles, *col, *row;
  int i, x, y;
  snprintf(path, sizeof path, "%s/envmaps/city.hdr", EL_TEST_DATA_DIR);
  if (el_image_load(path, &city, err, sizeof err) != 0) { printf("FAIL %s\n", err); return 1; }
  snprintf(path, sizeof path, "%s/envmaps/studio.hdr", EL_TEST_DATA_DIR);
  if (el_image_load(path, &studio, err, sizeof err) != 0) { printf("FAIL %s\n", err); return 1; }
  sun12 = sun_map(32, 16, 20, 5, 1e12f);
  sun4 = sun_map(32, 16, 31, 2, 1e4f); /* at the seam */
  poles = (float *)malloc(sizeof(float) * 3 * 32 * 16);
  for (y = 0; y < 16; ++y)
    for (x = 0; x < 32; ++x)
      for (i = 0; i < 3; ++i) poles[3 * (y * 32 + x) + i] = (y == 0 || y == 15) ? 50.0f + (float)x : (y == 1 ? 0.0f : 0.1f);
  col = (float *)malloc(sizeof(float) * 3 * 24);
  row = (float *)malloc(sizeof(float) * 3 * 24);
  for (i = 0; i < 24; ++i) {
    int c;
    for (c = 0; c < 3; ++c) { col[3 * i + c] = 1.0f + (float)(i * i % 7) * (float)(c + 1); row[3 * i + c] = (i == 5 ? 400.0f : 0.5f) + (float)c; }
  }

  /* 1, 2 */
  chi2_map("city 1024x512", city.pixels, city.width, city.height, 0, 64, 32, 4, 200000);
  chi2_map("city 1024x512 y-up", city.pixels, city.width, city.height, 1, 64, 32, 4, 200000);
  chi2_map("studio 1024x512 rotated", studio.pixels, studio.width, studio.height, 2, 64, 32, 4, 200000);
  chi2_map("one-texel sun 1e12, 32x16", sun12, 32, 16, 0, 32, 16, 8, 200000);
  chi2_map("one-texel sun 1e12, 32x16 rotated", sun12, 32, 16, 2, 32, 16, 8, 200000);
  chi2_map("one-texel sun 1e4 at the seam, 32x16", sun4, 32, 16, 0, 64, 32, 4, 200000);
  chi2_map("one-texel sun 1e4 at the seam, y-up", sun4, 32, 16, 1, 64, 32, 4, 200000);
  chi2_map("lit pole rows 32x16", poles, 32, 16, 0, 32, 16, 8, 200000);
  chi2_map("lit pole rows 32x16 rotated", poles, 32, 16, 2, 32, 16, 8, 200000);
  chi2_map("1x24", col, 1, 24, 0, 8, 24, 8, 100000);
  chi2_map("24x1", row, 24, 1, 0, 24, 8, 8, 100000);
  chi2_map("24x1 rotated", row, 24, 1, 2, 24, 8, 8, 100000);
  chi2_map("1x24 y-up", col, 1, 24, 1, 8, 24, 8, 100000);
  chi2_map("city 1024x512 rotated", city.pixels, city.width, city.height, 2, 64, 32, 4, 200000);

  { /* 3, 4 */
    el_envlight lb, lc;
    double z, rv, zc, rvc;
    int m;
    for (m = 0; m < 3; ++m) {
      const char *nm[3] = {"city", "one-texel sun 1e12 rotated", "lit pole rows y-up"};
      const float *px[3] = {city.pixels, sun12, poles};
      int ww[3] = {city.width, 32, 32}, hh[3] = {city.height, 16, 16}, mat[3] = {0, 2, 1};
      if (!make(&lb, px[m], ww[m], hh[m], mat[m], EL_ENVLIGHT_IMPORTANCE_BILINEAR) ||
          !make(&lc, px[m], ww[m], hh[m], mat[m], EL_ENVLIGHT_IMPORTANCE_CELL_AVERAGE)) { check(0, "init"); continue; }
      moments(&lb, 200000, &z, &rv);
      moments(&lc, 200000, &zc, &rvc);
      check(z < 4 && zc < 4, "unbiased %-28s: mean lum(L)/pdf within 4 SE of the integral (BILINEAR %.2f SE, CELL_AVERAGE %.2f)", nm[m], z, zc);
      /* the bilinear density leaves lum(le) / pdf nearly constant (bfloat16 corners, sin at texel
       * centres, the integer units of dim patches); cell averages do not inside a sun's texels */
      if (m < 2) check(rv < 1e-2 && rvc > 30 * rv, "%-28s: relative variance of lum(L)/pdf %.3g (CELL_AVERAGE %.3g, %.0fx)", nm[m], rv, rvc, rvc / rv);
      el_envlight_free(&lb); el_envlight_free(&lc);
    }
  }

  { /* sample_li_n: sample_li's results bit for bit (its batches prefetch in passes), with and without rgb */
    el_envlight l;
    int mat, bad = 0, k, tried = 0;
    float u[2 * 101], wi[3 * 101], rgb[3 * 101], pdf[101], w1[3], c1[3], p1;
    for (mat = 0; mat < 3; ++mat) {
      if (!make(&l, mat == 2 ? sun12 : city.pixels, mat == 2 ? 32 : city.width, mat == 2 ? 16 : city.height, mat, EL_ENVLIGHT_IMPORTANCE_BILINEAR)) { check(0, "init"); continue; }
      for (k = 0; k < 2 * 101; ++k) u[k] = rng_f(&g_rng);
      u[0] = 0.0f; u[1] = 0.99999994f; u[2] = NAN; u[3] = 1.5f;
      el_envlight_sample_li_n(&l, 101, u, wi, rgb, pdf);
      for (k = 0; k < 101; ++k, ++tried) {
        el_envlight_sample_li(&l, u + 2 * k, w1, c1, &p1);
        if (p1 != pdf[k] || memcmp(w1, wi + 3 * k, sizeof w1) || memcmp(c1, rgb + 3 * k, sizeof c1)) ++bad;
      }
      el_envlight_sample_li_n(&l, 101, u, wi, NULL, pdf);
      for (k = 0; k < 101; ++k, ++tried) {
        el_envlight_sample_li(&l, u + 2 * k, w1, NULL, &p1);
        if (p1 != pdf[k] || memcmp(w1, wi + 3 * k, sizeof w1)) ++bad;
      }
      el_envlight_free(&l);
    }
    check(bad == 0, "sample_li_n in importance BILINEAR = sample_li bit for bit (city identity / y-up, sun rotated; rgb and NULL): %d of %d differ", bad, tried);
  }
  { /* 5. hostile inputs */
    el_envlight l;
    float dirs[8][3] = {{NAN, 0, 1}, {0, 0, 0}, {INFINITY, 0, 0}, {0, -INFINITY, 1}, {1e-40f, 0, 0}, {0, 0, -1}, {0, 0, 1}, {3e38f, -3e38f, 3e38f}};
    float us[6] = {NAN, -1.0f, 0.0f, 0.99999994f, 1.0f, 2.0f};
    int bad = 0, bad1 = 0, bad2 = 0, bad3 = 0, k, kk, mat;
    for (mat = 0; mat < 3; ++mat) {
      if (!make(&l, city.pixels, city.width, city.height, mat, EL_ENVLIGHT_IMPORTANCE_BILINEAR)) { check(0, "init"); continue; }
      for (k = 0; k < 8; ++k) {
        float p = el_envlight_pdf_li(&l, dirs[k]);
        int unusable = k < 4;
        if (!(p >= 0 && p <= FLT_MAX) || (unusable && p != 0) || (!unusable && k != 4 && !(p > 0))) ++bad1;
      }
      for (k = 0; k < 200; ++k) { /* pdf_li(2^e wi) = pdf_li(wi): denormal and huge components (only the direction counts) */
        float u[2], wi[3], rgb[3], pdf, s[3], e;
        int q;
        u[0] = rng_f(&g_rng); u[1] = rng_f(&g_rng);
        el_envlight_sample_li(&l, u, wi, rgb, &pdf);
        { /* wi with its largest component exactly +-1, so that 2^e scalings and the library's rescaling are exact */
          float m = fabsf(wi[0]) > fabsf(wi[1]) ? fabsf(wi[0]) : fabsf(wi[1]), w1[3], p1;
          m = m > fabsf(wi[2]) ? m : fabsf(wi[2]);
          w1[0] = wi[0] / m; w1[1] = wi[1] / m; w1[2] = wi[2] / m;
          p1 = el_envlight_pdf_li(&l, w1);
          if (!(fabsf(p1 - pdf) <= 1e-3f * pdf)) ++bad2;
          for (q = 0; q < 3; ++q) {
            e = q == 0 ? 7.8886091e-31f /* 2^-100: the squares underflow */ : q == 1 ? 1.2676506e30f /* 2^100: they overflow */ : 0.5f;
            s[0] = w1[0] * e; s[1] = w1[1] * e; s[2] = w1[2] * e;
            if (el_envlight_pdf_li(&l, s) != p1) ++bad2;
          }
        }
      }
      for (k = 0; k < 6; ++k)
        for (kk = 0; kk < 6; ++kk) {
          float u[2], wi[3], rgb[3], pdf, len;
          u[0] = us[k]; u[1] = us[kk];
          el_envlight_sample_li(&l, u, wi, rgb, &pdf);
          len = wi[0] * wi[0] + wi[1] * wi[1] + wi[2] * wi[2];
          if (!(pdf > 0 && pdf <= FLT_MAX) || !(fabsf(len - 1) < 1e-5f) || !(rgb[0] >= 0 && rgb[0] <= FLT_MAX) || pdf != el_envlight_pdf_li(&l, wi)) ++bad3;
        }
      el_envlight_free(&l);
    }
    bad = bad1 + bad2 + bad3;
    check(bad == 0, "hostile directions (NaN, zero, infinite: pdf 0; tiny, huge, 2^e scaled: the unit direction's pdf) and u (NaN, < 0, >= 1): %d, %d, %d bad", bad1, bad2, bad3);
  }
  { /* a NaN texel is refused at init in importance BILINEAR, and named */
    el_envlight l;
    el_envlight_options o;
    el_result r;
    float *px = sun_map(8, 4, 1, 1, 10.0f);
    memset(&o, 0, sizeof o);
    o.importance = EL_ENVLIGHT_IMPORTANCE_BILINEAR;
    px[3 * (2 * 8 + 5) + 1] = NAN;
    r = el_envlight_init(&l, px, 8, 4, 3, &o);
    check(r == EL_ERROR_NAN && l.bad_index == 2 * 8 + 5, "NaN texel, importance BILINEAR: EL_ERROR_NAN at index %d", l.bad_index);
    el_envlight_free(&l);
    free(px);
  }
  { /* an all-black map: pdf 0 everywhere, sample pdf 0 */
    el_envlight l;
    float *px = sun_map(8, 4, 0, 0, 0.0f), u[2] = {0.3f, 0.6f}, wi[3], rgb[3], pdf, d[3] = {0.2f, 0.3f, 0.9f};
    for (i = 0; i < 3 * 32; ++i) px[i] = 0.0f;
    if (make(&l, px, 8, 4, 2, EL_ENVLIGHT_IMPORTANCE_BILINEAR)) {
      el_envlight_sample_li(&l, u, wi, rgb, &pdf);
      check(pdf == 0 && el_envlight_pdf_li(&l, d) == 0 && rgb[1] == 0, "all-black map, BILINEAR, rotated: sample pdf 0, pdf_li 0");
      el_envlight_free(&l);
    } else check(0, "init black");
    free(px);
  }
  free(sun12); free(sun4); free(poles); free(col); free(row);
  el_image_free(&city); el_image_free(&studio);
  printf("%d passed, %d failed\n", g_pass, g_fail);
  return g_fail != 0;
}
