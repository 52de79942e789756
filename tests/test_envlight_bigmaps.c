/* test_envlight_bigmaps.c: big maps and pbrt-v4's equal-area maps (issue 24), envlight.h.
 *
 *   - The importance cap: the default resolution of a map above the cap (2500x1250 -> 2048x1024, not a
 *     divisor), maps at or below it untouched (1024x512 with pbrt-v3's 2x map, 2048x1024); a capped
 *     light samples exactly as one given the same importance_width / height; sample_li against an
 *     independent double-precision computation of the capped density (exact cell averages of the
 *     bilinear reconstruction over bins that do not divide the image, times sin theta): chi-square over
 *     the bins, pdf_li at every bin, the pdf round trip, and an unbiased estimate of the integral.
 *   - options.no_copy: the caller's pixels are used in place (same samples, bit for bit, as a copy;
 *     fewer bytes), a bad texel is named without a copy, BAD_TEXELS_ZERO copies (the caller's pixels
 *     stay as they were), channels != 3 or a scale are refused.
 *   - Equal-area maps: the mapping against pbrt-v4's formulas (in double, here) and its orientation,
 *     the round trip, chi-square of the sampler against the box means of an independent computation,
 *     pdf and radiance round trips bit for bit, and city.hdr resampled to a 512x512 equal-area map against the
 *     lat-long original (the integral, and irradiance at six normals by light sampling).
 */
#define EL_IMPLEMENTATION
#include "envlight.h"
#include "image_io.h"

#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifndef EL_TEST_DATA_DIR
#define EL_TEST_DATA_DIR "data"
#endif

static const double PI = 3.14159265358979323846;
#include "test_common.h" /* check (a PASS / FAIL line, counted in g_pass / g_fail), rotation37 */

#include "test_rng.h" /* hash32 */
/* 24-bit uniform floats in [0,1) from an index and a stream */
static float rnd(uint32_t i, uint32_t s) { return (float)(hash32(i * 2654435761u + s * 0x9e3779b9u + 12345u) >> 8) * (1.0f / 16777216.0f); }

#include "test_chisq.h" /* gammq, chisq_pooled: the chi-square statistic and p-value */
/* chi-square of observed counts against expected probabilities (cells with expectation < 5 pooled) */
static double chi2_p(const double *obs, const double *prob, int n, double total, int *dof_out) {
  int dof;
  double chi2 = chisq_pooled(prob, obs, (size_t)n, 1.0, total, NULL, &dof);
  dof -= 1;
  *dof_out = dof;
  return dof > 0 ? gammq(0.5 * dof, 0.5 * chi2) : 1.0;
}

static double lum3(const float *p) { return 0.212671 * p[0] + 0.715160 * p[1] + 0.072169 * p[2]; }

/* a sky with noise and a small bright sun, w x h RGB */
static float *make_map(int w, int h, uint32_t seed) {
  float *px = (float *)malloc((size_t)w * (size_t)h * 3 * sizeof(float));
  int x, y;
  for (y = 0; y < h; ++y)
    for (x = 0; x < w; ++x) {
      float v = (0.2f + (float)y / (float)h) * (0.5f + rnd((uint32_t)(y * w + x), seed)), *p = px + ((size_t)y * (size_t)w + (size_t)x) * 3;
      float du = (float)x / (float)w - 0.37f, dv = (float)y / (float)h - 0.31f;
      if (du * du + dv * dv < 0.0004f) v = 500.0f;
      p[0] = v; p[1] = 0.8f * v; p[2] = 0.6f * v + 0.01f * (float)(x % 7);
    }
  return px;
}

/* ---- an independent computation of the capped density (double precision) --------------------- */
/* integral over [a, b] of the tent of texel k (centre k + 0.5, half-width 1), in texel units */
static double tent_int(double k, double a, double b) {
  double c = k + 0.5, lo = a > c - 1 ? a : c - 1, hi = b < c + 1 ? b : c + 1, s = 0.0, x0, x1;
  if (hi <= lo) return 0.0;
  /* rising part [c - 1, c]: 1 + (x - c); falling [c, c + 1]: 1 - (x - c) */
  x0 = lo; x1 = hi < c ? hi : c;
  if (x1 > x0) s += (x1 - x0) + 0.5 * ((x1 - c) * (x1 - c) - (x0 - c) * (x0 - c));
  x0 = lo > c ? lo : c; x1 = hi;
  if (x1 > x0) s += (x1 - x0) - 0.5 * ((x1 - c) * (x1 - c) - (x0 - c) * (x0 - c));
  return s;
}
/* mean over bin [a, b] (texel units) of the 1D linear reconstruction of values f[] (wrap or clamp) */
static void axis_matrix(int n, int nb, int wrap, double *m /* nb x n */) {
  int b, k;
  memset(m, 0, sizeof(double) * (size_t)nb * (size_t)n);
  for (b = 0; b < nb; ++b) {
    double a = (double)b * n / nb, e = (double)(b + 1) * n / nb;
    for (k = -2; k < n + 2; ++k) {
      int j = k;
      double wgt = tent_int(k, a, e) / (e - a);
      if (wgt == 0.0) continue;
      if (wrap) j = ((k % n) + n) % n;
      else j = k < 0 ? 0 : k > n - 1 ? n - 1 : k;
      m[(size_t)b * (size_t)n + (size_t)j] += wgt;
    }
  }
}
/* the probability of each of nu x nv bins under the capped lat-long density: cell mean of the bilinear
 * luminance times sin(theta at the bin centre), normalised */
static void ref_latlong_probs(const float *px, int w, int h, int nu, int nv, double *prob) {
  double *mu = (double *)malloc(sizeof(double) * (size_t)nu * (size_t)w), *mv = (double *)malloc(sizeof(double) * (size_t)nv * (size_t)h);
  double *rows = (double *)malloc(sizeof(double) * (size_t)h * (size_t)nu), sum = 0.0;
  int i, j, x, y;
  axis_matrix(w, nu, 1, mu);
  axis_matrix(h, nv, 0, mv);
  for (y = 0; y < h; ++y)
    for (i = 0; i < nu; ++i) {
      double s = 0.0;
      for (x = 0; x < w; ++x) s += mu[(size_t)i * (size_t)w + (size_t)x] * lum3(px + ((size_t)y * (size_t)w + (size_t)x) * 3);
      rows[(size_t)y * (size_t)nu + (size_t)i] = s;
    }
  for (j = 0; j < nv; ++j)
    for (i = 0; i < nu; ++i) {
      double s = 0.0;
      for (y = 0; y < h; ++y) s += mv[(size_t)j * (size_t)h + (size_t)y] * rows[(size_t)y * (size_t)nu + (size_t)i];
      prob[(size_t)j * (size_t)nu + (size_t)i] = s * sin(PI * (j + 0.5) / nv);
      sum += prob[(size_t)j * (size_t)nu + (size_t)i];
    }
  for (i = 0; i < nu * nv; ++i) prob[i] /= sum;
  free(mu); free(mv); free(rows);
}

/* The relative tolerance of a bin's pdf against its exact probability: distribution2d.h rounds the
 * marginal and each row's conditional to integer units of 2^-24, one unit per positive bin first and the
 * rest in proportion, so a bin's probability is off by up to about a unit of each relative to its own
 * units, and by up to (bins per row + rows) units of 2^-24 from the units given away first; plus 1e-6
 * for float rounding. row: the row's nb exact probabilities (the map has nb rows of bins too, or fewer). */
static double quant_tol(const double *row, int nb, int i) {
  double pr = 0.0;
  int k;
  for (k = 0; k < nb; ++k) pr += row[k];
  return 1e-6 + 2.0 * (1.0 / (pr * 16777216.0) + 1.0 / (row[i] / pr * 16777216.0)) + 2.0 * nb / 16777216.0;
}

/* ---- pbrt-v4's equal-area mapping, in double, as pbrt-v4 writes it (exact atan instead of its polynomial) */
static void ref_square_to_dir(double px, double py, double d[3]) {
  double u = 2 * px - 1, v = 2 * py - 1, up = fabs(u), vp = fabs(v), sd = 1 - (up + vp), dd = fabs(sd), r = 1 - dd;
  double phi = (r == 0 ? 1 : (vp - up) / r + 1) * PI / 4, z = copysign(1 - r * r, sd);
  double cp = copysign(cos(phi), u), sp = copysign(sin(phi), v);
  d[0] = cp * r * sqrt(2 - r * r); d[1] = sp * r * sqrt(2 - r * r); d[2] = z;
}
static void ref_dir_to_square(const double d0[3], double *pu, double *pv) {
  double n = sqrt(d0[0] * d0[0] + d0[1] * d0[1] + d0[2] * d0[2]), x = fabs(d0[0]) / n, y = fabs(d0[1]) / n, z = fabs(d0[2]) / n;
  double r = sqrt(1 - z), a = x > y ? x : y, b = x > y ? y : x, phi, u, v;
  b = a == 0 ? 0 : b / a;
  phi = atan(b) * 2 / PI;
  if (x < y) phi = 1 - phi;
  v = phi * r; u = r - v;
  if (d0[2] < 0) { double t = u; u = v; v = t; u = 1 - u; v = 1 - v; }
  u = copysign(u, d0[0]); v = copysign(v, d0[1]);
  *pu = 0.5 * (u + 1); *pv = 0.5 * (v + 1);
}

/* ---- the cap ---------------------------------------------------------------------------------- */
static void test_cap_defaults(void) {
  el_envlight l, e;
  el_envlight_options o;
  float *px = make_map(2500, 1250, 1);
  int i, same = 1;
  el_result r;
  memset(&o, 0, sizeof o);
  o.importance_cap = 2048;
  r = el_envlight_init(&l, px, 2500, 1250, 3, &o);
  check(r == EL_SUCCESS && l.imp_w == 2048 && l.imp_h == 1024, "cap 2048: a 2500x1250 map gets a 2048x1024 importance map (got %dx%d)", l.imp_w, l.imp_h);
  o.importance_cap = 0;
  o.importance_width = 2048; o.importance_height = 1024;
  el_envlight_init(&e, px, 2500, 1250, 3, &o);
  for (i = 0; i < 20000 && same; ++i) {
    float u[2], w1[3], w2[3], c1[3], c2[3], p1, p2;
    u[0] = rnd((uint32_t)i, 1); u[1] = rnd((uint32_t)i, 2);
    el_envlight_sample_li(&l, u, w1, c1, &p1);
    el_envlight_sample_li(&e, u, w2, c2, &p2);
    same = !memcmp(w1, w2, sizeof w1) && !memcmp(c1, c2, sizeof c1) && p1 == p2 && el_envlight_pdf_li(&l, w1) == el_envlight_pdf_li(&e, w1);
  }
  check(same, "cap: the capped light samples bit for bit as importance_width/height 2048x1024 (20000 samples)");
  el_envlight_free(&e);
  el_envlight_free(&l);
  memset(&o, 0, sizeof o);
  r = el_envlight_init(&l, px, 2500, 1250, 3, &o);
  check(r == EL_SUCCESS && l.imp_w == 2500 && l.imp_h == 1250, "cap: a 2500x1250 map is below the default cap %d (%dx%d)", EL_ENVLIGHT_IMPORTANCE_CAP,
        l.imp_w, l.imp_h);
  el_envlight_free(&l);
  o.importance = EL_ENVLIGHT_IMPORTANCE_PBRT_V3;
  r = el_envlight_init(&l, px, 2500, 1250, 3, &o);
  check(r == EL_SUCCESS && l.imp_w == 4096 && l.imp_h == 2048 && l.importance == EL_ENVLIGHT_IMPORTANCE_CELL_AVERAGE,
        "cap: pbrt-v3's 2x map of a 2500x1250 map is capped at 4096x2048 by default and takes cell averages (%dx%d, importance %d)", l.imp_w,
        l.imp_h, l.importance);
  el_envlight_free(&l);
  o.importance_cap = -1;
  r = el_envlight_init(&l, px, 2500, 1250, 3, &o);
  check(r == EL_SUCCESS && l.imp_w == 5000 && l.imp_h == 2500 && l.importance == EL_ENVLIGHT_IMPORTANCE_PBRT_V3,
        "cap: importance_cap = -1 keeps pbrt-v3's 2x map (%dx%d)", l.imp_w, l.imp_h);
  el_envlight_free(&l);
  o.importance_cap = 0;
  free(px);
  px = make_map(1024, 512, 2);
  r = el_envlight_init(&l, px, 1024, 512, 3, &o);
  check(r == EL_SUCCESS && l.imp_w == 2048 && l.imp_h == 1024 && l.importance == EL_ENVLIGHT_IMPORTANCE_PBRT_V3,
        "cap: a 1024x512 map keeps pbrt-v3's 2048x1024 point-lookup map (the renderer's default)");
  el_envlight_free(&l);
  free(px);
  px = make_map(2048, 1024, 3);
  r = el_envlight_init(&l, px, 2048, 1024, 3, &o);
  check(r == EL_SUCCESS && l.imp_w == 4096 && l.imp_h == 2048 && l.importance == EL_ENVLIGHT_IMPORTANCE_PBRT_V3,
        "cap: a 2048x1024 map keeps pbrt-v3's 4096x2048 map");
  el_envlight_free(&l);
  free(px);
}

/* a map above a small cap whose bins do not divide it: sample_li against the independent density */
static void test_cap_density(void) {
  const int w = 300, h = 150, nu = 64, nv = 32, n = 400000;
  el_envlight l;
  el_envlight_options o;
  float *px = make_map(w, h, 4), integral[3];
  double *prob = (double *)malloc(sizeof(double) * nu * nv), *obs = (double *)calloc((size_t)(nu * nv), sizeof(double));
  double worst = 0.0, m = 0.0, q = 0.0, exact, p;
  int i, j, dof, bad_rt = 0, zero = 0;
  el_result r;
  memset(&o, 0, sizeof o);
  o.importance_cap = nu;
  r = el_envlight_init(&l, px, w, h, 3, &o);
  check(r == EL_SUCCESS && l.imp_w == nu && l.imp_h == nv, "cap %d: a 300x150 map gets %dx%d bins (300 / 64 is not whole)", nu, l.imp_w, l.imp_h);
  ref_latlong_probs(px, w, h, nu, nv, prob);
  /* pdf_li at each bin's centre is the bin's probability over its solid angle, with sin(theta) at the
   * direction: P(bin) nu nv / (2 pi^2 sin theta) */
  for (j = 0; j < nv; ++j)
    for (i = 0; i < nu; ++i) {
      float d[3], got;
      double want, th = PI * (j + 0.5) / nv;
      el_envlight_uv_to_dir((i + 0.5f) / nu, (j + 0.5f) / nv, d);
      got = el_envlight_pdf_li(&l, d);
      want = prob[j * nu + i] * nu * nv / (2 * PI * PI * sin(th));
      if (fabs(got / want - 1) / quant_tol(prob + j * nu, nu, i) > worst) worst = fabs(got / want - 1) / quant_tol(prob + j * nu, nu, i);
    }
  check(worst < 1.0, "cap: pdf_li at all %d bin centres equals the independent capped density (worst error %.2g of the tolerance: the integer "
        "CDF's 2^-24 units and float rounding)", nu * nv, worst);
  el_envlight_integral(&l, integral);
  exact = 0.212671 * integral[0] + 0.715160 * integral[1] + 0.072169 * integral[2];
  for (i = 0; i < n; ++i) {
    float u[2], wi[3], rgb[3], pdf, uu, vv;
    int iu, iv;
    u[0] = rnd((uint32_t)i, 7); u[1] = rnd((uint32_t)i, 8);
    el_envlight_sample_li(&l, u, wi, rgb, &pdf);
    if (!(pdf > 0.0f)) { ++zero; continue; }
    p = el_envlight_pdf_li(&l, wi);
    if (fabs(p / pdf - 1) > 9.5367431640625e-7) ++bad_rt; /* 2^-20: NOTES, point 4 */
    el_envlight_dir_to_uv(wi, &uu, &vv);
    iu = (int)(uu * nu); iv = (int)(vv * nv);
    iu = iu > nu - 1 ? nu - 1 : iu; iv = iv > nv - 1 ? nv - 1 : iv;
    obs[iv * nu + iu] += 1.0;
    p = lum3(rgb) / pdf;
    m += p; q += p * p;
  }
  p = chi2_p(obs, prob, nu * nv, (double)(n - zero), &dof);
  check(p > 1e-3, "cap: chi-square of %d samples over the %dx%d capped bins: p = %.3g (> 1e-3), %d dof", n, nu, nv, p, dof);
  check(bad_rt == 0 && zero == 0, "cap: pdf_li(wi) round trip within 2^-20 for every sample (%d off, %d zero pdfs)", bad_rt, zero);
  m /= n; q = q / n - m * m;
  check(fabs(m - exact) < 4.0 * sqrt(q / n), "cap: light sampling alone is unbiased: lum integral %.5g vs exact %.5g (%.2f standard errors)", m,
        exact, fabs(m - exact) / sqrt(q / n));
  el_envlight_free(&l);
  free(px); free(prob); free(obs);
}

/* ---- no_copy ------------------------------------------------------------------------------------- */
static void test_no_copy(void) {
  el_envlight a, b;
  el_envlight_options o;
  const int w = 301, h = 150;
  float *px = make_map(w, h, 5), *keep, one[3] = {1, 1, 1};
  int i, same = 1;
  size_t ba, bb;
  el_result r;
  memset(&o, 0, sizeof o);
  el_envlight_init(&a, px, w, h, 3, &o);
  o.no_copy = 1;
  r = el_envlight_init(&b, px, w, h, 3, &o);
  check(r == EL_SUCCESS && b.texels == px && b.borrowed == 1, "no_copy: the light reads the caller's pixels in place");
  for (i = 0; i < 3; ++i) same = same && a.integral[i] == b.integral[i];
  for (i = 0; i < 20000 && same; ++i) {
    float u[2], w1[3], w2[3], c1[3], c2[3], p1, p2, d[3];
    u[0] = rnd((uint32_t)i, 3); u[1] = rnd((uint32_t)i, 4);
    el_envlight_sample_li(&a, u, w1, c1, &p1);
    el_envlight_sample_li(&b, u, w2, c2, &p2);
    d[0] = u[0] - 0.5f; d[1] = u[1] - 0.3f; d[2] = 0.2f;
    el_envlight_le(&a, d, c1);
    el_envlight_le(&b, d, c2);
    same = !memcmp(w1, w2, sizeof w1) && !memcmp(c1, c2, sizeof c1) && p1 == p2;
  }
  check(same, "no_copy: the same integral, samples, pdfs and radiance as a copying light, bit for bit");
  ba = el_envlight_bytes(&a); bb = el_envlight_bytes(&b);
  check(ba - bb == (size_t)w * h * 12, "no_copy: el_envlight_bytes leaves out the caller's image (%zu vs %zu)", bb, ba);
  el_envlight_free(&b); /* must not free px (ASan would say so below) */
  el_envlight_free(&a);
  px[3 * (77 * w + 12) + 1] = -0.004f; /* a DWAB-like negative */
  keep = (float *)malloc(sizeof(float) * (size_t)w * h * 3);
  memcpy(keep, px, sizeof(float) * (size_t)w * h * 3);
  r = el_envlight_init(&b, px, w, h, 3, &o);
  check(r == EL_ERROR_NEGATIVE && b.bad_index == 77 * w + 12 && b.texels == NULL,
        "no_copy: a negative texel is an error naming it (%s, bad_index %d)", el_result_string(r), b.bad_index);
  o.bad_texels = EL_ENVLIGHT_BAD_TEXELS_ZERO;
  r = el_envlight_init(&b, px, w, h, 3, &o);
  check(r == EL_SUCCESS && b.texels != px && !b.borrowed && b.texels[3 * (77 * w + 12) + 1] == 0.0f &&
            !memcmp(keep, px, sizeof(float) * (size_t)w * h * 3),
        "no_copy + BAD_TEXELS_ZERO: init copies to zero the texel; the caller's pixels are unchanged");
  el_envlight_free(&b);
  o.bad_texels = EL_ENVLIGHT_BAD_TEXELS_CLAMP_NEGATIVE;
  r = el_envlight_init(&b, px, w, h, 3, &o);
  check(r == EL_SUCCESS && !b.borrowed && b.negative_texels == 1 && b.most_negative == -0.004f && !memcmp(keep, px, sizeof(float) * (size_t)w * h * 3),
        "no_copy + BAD_TEXELS_CLAMP_NEGATIVE: init copies to clamp the texel and counts it (%zu)", b.negative_texels);
  el_envlight_free(&b);
  o.bad_texels = 0;
  px[3 * (77 * w + 12) + 1] = 0.5f;
  check(el_envlight_init(&b, px, w, h, 4, &o) == EL_ERROR_INVALID_ARGUMENT, "no_copy: 4 channels are refused");
  memcpy(o.scale, one, sizeof one);
  o.scale[1] = 2.0f;
  check(el_envlight_init(&b, px, w, h, 3, &o) == EL_ERROR_INVALID_ARGUMENT, "no_copy: a scale other than 1 is refused");
  o.scale[1] = 1.0f;
  check(el_envlight_init(&b, px, w, h, 3, &o) == EL_SUCCESS && b.borrowed, "no_copy: scale (1, 1, 1) is accepted");
  el_envlight_free(&b);
  px[3 * (5 * w + 7)] = -0.0f; /* valid (the fast row test flags its sign bit; the texel-by-texel check passes it) */
  el_envlight_init(&a, px, w, h, 3, NULL);
  r = el_envlight_init(&b, px, w, h, 3, &o);
  check(r == EL_SUCCESS && b.borrowed && b.texels == px && !memcmp(a.integral, b.integral, sizeof a.integral),
        "no_copy: a -0 texel is read in place, with the copying light's integral bit for bit");
  el_envlight_free(&b);
  el_envlight_free(&a);
  free(keep);
  free(px);
}

/* ---- equal-area maps ----------------------------------------------------------------------------- */
static void test_ea_mapping(void) {
  double worst_f = 0.0, worst_i = 0.0, worst_rt = 0.0;
  int i, k;
  struct { float u, v, d[3]; } anchors[6] = {
      {0.5f, 0.5f, {0, 0, 1}}, {1.0f, 0.5f, {1, 0, 0}}, {0.0f, 0.5f, {-1, 0, 0}}, {0.5f, 1.0f, {0, 1, 0}}, {0.5f, 0.0f, {0, -1, 0}}, {0.0f, 0.0f, {0, 0, -1}}};
  int anchors_ok = 1;
  for (i = 0; i < 6; ++i) {
    float d[3];
    el_envlight_square_to_dir(anchors[i].u, anchors[i].v, d);
    for (k = 0; k < 3; ++k) anchors_ok = anchors_ok && fabsf(d[k] - anchors[i].d[k]) < 1e-6f;
  }
  check(anchors_ok, "equal-area: pbrt-v4's orientation: centre +z, (1, .5) +x, (0, .5) -x, (.5, 1) +y, (.5, 0) -y, corner -z");
  for (i = 0; i < 200000; ++i) {
    float u = rnd((uint32_t)i, 11), v = rnd((uint32_t)i, 12), d[3], uu, vv, back[3];
    double rd[3], ru, rv, dd[3];
    el_envlight_square_to_dir(u, v, d);
    ref_square_to_dir(u, v, rd);
    for (k = 0; k < 3; ++k) if (fabs(d[k] - rd[k]) > worst_f) worst_f = fabs(d[k] - rd[k]);
    for (k = 0; k < 3; ++k) dd[k] = d[k];
    ref_dir_to_square(dd, &ru, &rv);
    el_envlight_dir_to_square(d, &uu, &vv);
    if (fabs(uu - ru) > worst_i) worst_i = fabs(uu - ru);
    if (fabs(vv - rv) > worst_i) worst_i = fabs(vv - rv);
    el_envlight_square_to_dir(uu, vv, back);
    for (k = 0; k < 3; ++k) if (fabs(back[k] - d[k]) > worst_rt) worst_rt = fabs(back[k] - d[k]);
  }
  check(worst_f < 1e-6, "equal-area: square_to_dir matches pbrt-v4's EqualAreaSquareToSphere (double) to %.2g (< 1e-6)", worst_f);
  check(worst_i < 1e-6, "equal-area: dir_to_square matches pbrt-v4's EqualAreaSphereToSquare (exact atan) to %.2g (< 1e-6)", worst_i);
  check(worst_rt < 2e-6, "equal-area: the round trip square -> dir -> square -> dir: %.2g (< 2e-6)", worst_rt);
}

/* box means of the luminance of an N x N map over nb x nb bins, normalised (equal-area texels all have
 * the same solid angle) */
static void ref_box_probs(const float *px, int n, int nb, double *prob) {
  double sum = 0.0;
  int i, j, x, y;
  for (j = 0; j < nb; ++j)
    for (i = 0; i < nb; ++i) {
      double a0 = (double)i * n / nb, a1 = (double)(i + 1) * n / nb, b0 = (double)j * n / nb, b1 = (double)(j + 1) * n / nb, s = 0.0;
      for (y = (int)b0; y < n && y < b1; ++y)
        for (x = (int)a0; x < n && x < a1; ++x) {
          double wx = fmin(a1, x + 1.0) - fmax(a0, (double)x), wy = fmin(b1, y + 1.0) - fmax(b0, (double)y);
          if (wx > 0 && wy > 0) s += wx * wy * lum3(px + ((size_t)y * n + x) * 3);
        }
      prob[j * nb + i] = s;
      sum += s;
    }
  for (i = 0; i < nb * nb; ++i) prob[i] /= sum;
}

static void test_ea_sampling(int cap, const float m[9], const char *what) {
  const int n = 150, ns = 300000;
  int nb = cap ? cap / 2 : n, i, dof, zero = 0, rt = 0, binpdf = 0;
  el_envlight l;
  el_envlight_options o;
  float *px = make_map(n, n, 9);
  double *prob = (double *)malloc(sizeof(double) * nb * nb), *obs = (double *)calloc((size_t)(nb * nb), sizeof(double)), p;
  memset(&o, 0, sizeof o);
  o.mapping = EL_ENVLIGHT_MAPPING_EQUAL_AREA;
  o.importance_cap = cap;
  if (m) memcpy(o.light_to_world, m, sizeof o.light_to_world);
  el_result r = el_envlight_init(&l, px, n, n, 3, &o);
  check(r == EL_SUCCESS && l.imp_w == nb && l.imp_h == nb, "equal-area %s: %dx%d bins", what, l.imp_w, l.imp_h);
  ref_box_probs(px, n, nb, prob);
  for (i = 0; i < ns; ++i) {
    float u[2], wi[3], rgb[3], pdf, le[3], d[3];
    double dd[3], su, sv;
    int iu, iv, k;
    u[0] = rnd((uint32_t)i, 21); u[1] = rnd((uint32_t)i, 22);
    el_envlight_sample_li(&l, u, wi, rgb, &pdf);
    if (!(pdf > 0.0f)) { ++zero; continue; }
    el_envlight_le(&l, wi, le);
    if (el_envlight_pdf_li(&l, wi) != pdf || memcmp(le, rgb, sizeof le)) ++rt;
    for (k = 0; k < 3; ++k) d[k] = m ? m[k] * wi[0] + m[3 + k] * wi[1] + m[6 + k] * wi[2] : wi[k]; /* back to light space */
    for (k = 0; k < 3; ++k) dd[k] = d[k];
    ref_dir_to_square(dd, &su, &sv);
    iu = (int)(su * nb); iv = (int)(sv * nb);
    iu = iu > nb - 1 ? nb - 1 : iu; iv = iv > nb - 1 ? nb - 1 : iv;
    obs[iv * nb + iu] += 1.0;
    if (fabs(pdf / (prob[iv * nb + iu] * nb * nb / (4 * PI)) - 1) > quant_tol(prob + iv * nb, nb, iu)) ++binpdf;
  }
  p = chi2_p(obs, prob, nb * nb, (double)(ns - zero), &dof);
  check(p > 1e-3, "equal-area %s: chi-square of %d samples over %dx%d bins: p = %.3g (> 1e-3), %d dof", what, ns, nb, nb, p, dof);
  check(rt == 0 && zero == 0, "equal-area %s: pdf_li(wi) and le(wi) equal the sample's pdf and radiance bit for bit (%d off, %d zero)", what, rt, zero);
  check(binpdf == 0, "equal-area %s: every sample's pdf is the independent box density of its bin / (4 pi) (binned by pbrt-v4's mapping in double; "
        "%d of %d off)", what, binpdf, ns);
  el_envlight_free(&l);
  free(px); free(prob); free(obs);
}

/* city.hdr as an equal-area map (each texel the mean of the lat-long light's le at 2x2 directions in it)
 * against the lat-long original: the integral, and the irradiance at six normals */
static void test_ea_city(void) {
  el_image img;
  char err[256], path[512];
  el_envlight ll, ea;
  el_envlight_options o;
  const int n = 512, ns = 200000;
  float *sq, i1[3], i2[3];
  int x, y, c, k, s;
  double worst = 0.0, worst_se = 0.0;
  static const float normals[6][3] = {{0, 0, 1}, {0, 0, -1}, {1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0.6f, -0.48f, 0.64f}};
  snprintf(path, sizeof path, "%s/envmaps/city.hdr", EL_TEST_DATA_DIR);
  if (el_image_load(path, &img, err, sizeof err) != 0 || img.channels < 3) { check(0, "load %s: %s", path, err); return; }
  memset(&o, 0, sizeof o);
  el_envlight_init(&ll, img.pixels, img.width, img.height, img.channels, &o);
  sq = (float *)malloc(sizeof(float) * (size_t)n * n * 3);
  for (y = 0; y < n; ++y)
    for (x = 0; x < n; ++x) {
      float acc[3] = {0, 0, 0};
      for (s = 0; s < 4; ++s) {
        float d[3], rgb[3];
        el_envlight_square_to_dir((x + (s % 2 + 0.5f) / 2) / n, (y + (s / 2 + 0.5f) / 2) / n, d);
        el_envlight_le(&ll, d, rgb);
        for (c = 0; c < 3; ++c) acc[c] += rgb[c] / 4;
      }
      for (c = 0; c < 3; ++c) sq[((size_t)y * n + x) * 3 + c] = acc[c];
    }
  o.mapping = EL_ENVLIGHT_MAPPING_EQUAL_AREA;
  check(el_envlight_init(&ea, sq, n, n, 3, &o) == EL_SUCCESS, "equal-area city: a %dx%d map resampled from city.hdr (2x2 per texel)", n, n);
  el_envlight_integral(&ll, i1);
  el_envlight_integral(&ea, i2);
  for (c = 0; c < 3; ++c) if (fabs(i2[c] / i1[c] - 1) > worst) worst = fabs(i2[c] / i1[c] - 1);
  check(worst < 2e-3, "equal-area city: the integral of le agrees with the lat-long map's to %.2g (< 2e-3)", worst);
  worst = 0.0;
  for (k = 0; k < 6; ++k) {
    double m[2] = {0, 0}, q[2] = {0, 0}, d, se;
    el_envlight *L[2];
    int j, i;
    L[0] = &ll; L[1] = &ea;
    for (j = 0; j < 2; ++j)
      for (i = 0; i < ns; ++i) {
        float u[2], wi[3], rgb[3], pdf, cs;
        double e;
        u[0] = rnd((uint32_t)i, (uint32_t)(31 + 2 * k + 17 * j)); u[1] = rnd((uint32_t)i, (uint32_t)(32 + 2 * k + 17 * j));
        el_envlight_sample_li(L[j], u, wi, rgb, &pdf);
        cs = wi[0] * normals[k][0] + wi[1] * normals[k][1] + wi[2] * normals[k][2];
        e = pdf > 0.0f && cs > 0.0f ? lum3(rgb) * cs / pdf : 0.0;
        m[j] += e; q[j] += e * e;
      }
    for (j = 0; j < 2; ++j) { m[j] /= ns; q[j] = (q[j] / ns - m[j] * m[j]) / ns; }
    d = fabs(m[1] / m[0] - 1);
    se = fabs(m[1] - m[0]) / sqrt(q[0] + q[1]);
    if (d > worst) worst = d;
    if (se > worst_se) worst_se = se;
  }
  check(worst < 0.01 && worst_se < 5.0,
        "equal-area city: irradiance at 6 normals (light sampling, %d samples each) agrees with the lat-long map: worst %.3g relative (< 1%%), %.2f "
        "standard errors (< 5)",
        ns, worst, worst_se);
  el_envlight_free(&ea);
  el_envlight_free(&ll);
  free(sq);
  el_image_free(&img);
}

static void test_ea_misc(void) {
  el_envlight l;
  el_envlight_options o;
  float *px = make_map(64, 32, 1), n[3] = {0, 0, 1}, u[2] = {0.3f, 0.6f}, wi[3], wj[3], rgb[3], rgj[3], p, q;
  memset(&o, 0, sizeof o);
  o.mapping = EL_ENVLIGHT_MAPPING_EQUAL_AREA;
  check(el_envlight_init(&l, px, 64, 32, 3, &o) == EL_ERROR_INVALID_ARGUMENT, "equal-area: a 2:1 image is refused (pbrt-v4 requires a square)");
  o.importance = EL_ENVLIGHT_IMPORTANCE_BILINEAR;
  check(el_envlight_init(&l, px, 32, 32, 3, &o) == EL_ERROR_INVALID_ARGUMENT, "equal-area: importance BILINEAR is refused");
  o.importance = 0;
  o.mapping = 2;
  check(el_envlight_init(&l, px, 32, 32, 3, &o) == EL_ERROR_INVALID_ARGUMENT, "mapping 2 is refused");
  o.mapping = EL_ENVLIGHT_MAPPING_EQUAL_AREA;
  el_envlight_init(&l, px, 32, 32, 3, &o);
  check(el_envlight_prepare_product(&l, NULL) == EL_SUCCESS && el_envlight_product_bytes(&l) == 0,
        "equal-area: prepare_product succeeds without product tables");
  el_envlight_sample_li_cos(&l, n, u, wi, rgb, &p);
  el_envlight_sample_li(&l, u, wj, rgj, &q);
  check(!memcmp(wi, wj, sizeof wi) && !memcmp(rgb, rgj, sizeof rgb) && p == q && el_envlight_pdf_li_cos(&l, n, wi) == p,
        "equal-area: sample_li_cos / pdf_li_cos are sample_li / pdf_li (documented)");
  o.compensated = 1;
  el_envlight_free(&l);
  check(el_envlight_init(&l, px, 32, 32, 3, &o) == EL_SUCCESS && el_envlight_prepare_sampling(&l) == EL_SUCCESS && !l.fell_back,
        "equal-area: the compensated density builds");
  el_envlight_free(&l);
  free(px);
}

int main(void) {
  float rot[9];
  rotation37(rot);
  test_cap_defaults();
  test_cap_density();
  test_no_copy();
  test_ea_mapping();
  test_ea_sampling(0, NULL, "150x150, full resolution");
  test_ea_sampling(128, NULL, "150x150 capped at 64x64 (not a divisor)");
  test_ea_sampling(128, rot, "capped, general rotation");
  test_ea_city();
  test_ea_misc();
  printf("%d passed, %d failed\n", g_pass, g_fail);
  return g_fail ? 1 : 0;
}
