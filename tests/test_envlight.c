/* test_envlight.c: envlight.h against mathematics, never against its own output.
 *
 *   - orientation: an asymmetric map seen through el_envlight_yup_matrix / zup_matrix agrees texel for
 *     texel with Mitsuba 3's and Blender's own lat-long formulas, and pbrt's RotateX(-90) is shown to
 *     be their mirror image (u' = 0.25 - u);
 *   - le: texel values at texel centres, bilinear halfway, Repeat across the seam, Clamp at the poles
 *     (no north-south leak, pbrt-v3 issue #63);
 *   - sample_li against pdf_li: chi-square goodness of fit over a grid of the sphere (studio, city, one
 *     hot texel, hot pole rows; plain / compensated; identity / rotation; three samplers), significance
 *     0.01 with a Bonferroni correction; pdf_li(sample_li(u).dir) within 2^-20 of pdf (bit for bit with
 *     a general rotation); pdf_li integrates to 1;
 *   - unbiasedness: irradiance at several normals from sample_li vs a quadrature over the texels (our
 *     own bilinear reconstruction, written here), within 3 standard errors, including a generated
 *     8192x4096 map with a 1e12 dynamic range; compensated sampling with MIS;
 *   - power / integral vs quadrature; sample_le / pdf_le geometry; the bounding spheres preprocess
 *     accepts (radii 2^-80 .. 2^80) and finite outputs for every accepted one;
 *   - directions scaled by 2^-125 .. 2^127, FLT_MAX and denormals under every matrix;
 *   - hard cases: all black, 1x1, 1xN, Nx1, NaN / Inf / negative texels, u at 0, 1 - ulp and 1, NaN,
 *     zero, huge, tiny and non-unit directions, both poles, bad matrices and scales, the lazy build
 *     (le alone builds nothing) and a concurrent first use from two threads.
 */
#define _POSIX_C_SOURCE 200809L
#define EL_IMPLEMENTATION
#include "envlight.h"
#include "image_io.h"

#include <math.h>
#include <pthread.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifndef EL_TEST_DATA_DIR
#define EL_TEST_DATA_DIR "data"
#endif

static const double PI = 3.14159265358979323846;
#include "test_common.h" /* check (a PASS / FAIL line, counted in g_pass / g_fail), rotation37 */

#include "test_rng.h"   /* rng, rng_make, rng_f: PCG32, 24-bit floats in [0,1) */
#include "test_chisq.h" /* gammq, chisq_pooled: the chi-square statistic and p-value */

/* ---- independent reference mapping (double precision libm) --------------------------------- */
static void ref_uv_to_dir(double u, double v, double d[3]) { /* pbrt-v3, light space */
  double th = PI * v, ph = 2.0 * PI * u;
  d[0] = sin(th) * cos(ph); d[1] = sin(th) * sin(ph); d[2] = cos(th);
}
static void ref_dir_to_uv(const double d[3], double *u, double *v) {
  double len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]), z = d[2] / len, p;
  if (z > 1) z = 1;
  if (z < -1) z = -1;
  p = atan2(d[1], d[0]);
  if (p < 0) p += 2 * PI;
  *u = p / (2 * PI);
  *v = acos(z) / PI;
}
/* world <-> light with a row-major matrix (world = M light) */
static void mat_mul(const float m[9], const double a[3], double b[3]) {
  int i;
  for (i = 0; i < 3; ++i) b[i] = m[3 * i] * a[0] + m[3 * i + 1] * a[1] + m[3 * i + 2] * a[2];
}
static void mat_mul_t(const float m[9], const double a[3], double b[3]) {
  int i;
  for (i = 0; i < 3; ++i) b[i] = m[i] * a[0] + m[3 + i] * a[1] + m[6 + i] * a[2];
}
static void identity(float m[9]) { int i; for (i = 0; i < 9; ++i) m[i] = (i % 4 == 0) ? 1.0f : 0.0f; }

/* Our own bilinear reconstruction (pbrt's s*w - 0.5, Repeat in u, Clamp in v), in double. */
typedef struct { const float *px; int w, h; } image;
static double img_at(const image *im, int x, int y, int c) {
  x %= im->w; if (x < 0) x += im->w;
  if (y < 0) y = 0;
  if (y > im->h - 1) y = im->h - 1;
  return im->px[((size_t)y * im->w + x) * 3 + c];
}
static double ref_bilerp(const image *im, double u, double v, int c) {
  double s = u * im->w - 0.5, t = v * im->h - 0.5;
  int x0 = (int)floor(s), y0 = (int)floor(t);
  double fx = s - x0, fy = t - y0;
  return (1 - fy) * ((1 - fx) * img_at(im, x0, y0, c) + fx * img_at(im, x0 + 1, y0, c)) +
         fy * ((1 - fx) * img_at(im, x0, y0 + 1, c) + fx * img_at(im, x0 + 1, y0 + 1, c));
}
static double lum3(double r, double g, double b) { return 0.212671 * r + 0.715160 * g + 0.072169 * b; }

/* ---- loading the test maps ---------------------------------------------------------------- */
static int load_map(const char *name, el_image *img) {
  char path[512], err[512];
  snprintf(path, sizeof path, "%s/envmaps/%s", EL_TEST_DATA_DIR, name);
  if (el_image_load(path, img, err, sizeof err) != 0) { printf("cannot load %s\n", err); return -1; }
  return 0;
}

/* a light of RGB texels px (w x h) under the matrix m (NULL: identity), compensated or not, with a sampler
 * and an importance (0: the defaults) */
static el_result make_light_with(el_envlight *l, const float *px, int w, int h, const float m[9], int comp, int sampler,
                                 int imp) {
  el_envlight_options o;
  memset(&o, 0, sizeof o);
  if (m) memcpy(o.light_to_world, m, sizeof o.light_to_world);
  o.compensated = comp;
  o.sampler = sampler;
  o.importance = imp;
  return el_envlight_init(l, px, w, h, 3, &o);
}
static el_result make_light(el_envlight *l, const float *px, int w, int h, const float m[9], int comp, int sampler) {
  return make_light_with(l, px, w, h, m, comp, sampler, 0);
}

/* ======================================================================================== */
/* 1. Orientation                                                                            */
/* ======================================================================================== */
static void test_orientation(void) {
  enum { W = 8, H = 4 };
  float px[W * H * 3], m[9];
  el_envlight l;
  int x, y, ok_pbrt = 1, ok_yup = 1, ok_zup = 1, ok_mirror = 1, same_as_unmirrored = 0;
  double worst = 0;
  /* every texel different (an asymmetric map), channels different too */
  for (y = 0; y < H; ++y)
    for (x = 0; x < W; ++x) {
      float *p = px + (y * W + x) * 3;
      p[0] = (float)(1 + x + W * y); p[1] = 100.0f + (float)(x * x + 3 * y); p[2] = 0.5f * (float)(y + 1);
    }
  /* pbrt-v3 identity: light-space formula */
  make_light(&l, px, W, H, NULL, 0, 0);
  for (y = 0; y < H; ++y)
    for (x = 0; x < W; ++x) {
      double d[3]; float fd[3], rgb[3];
      ref_uv_to_dir((x + 0.5) / W, (y + 0.5) / H, d);
      fd[0] = (float)d[0]; fd[1] = (float)d[1]; fd[2] = (float)d[2];
      el_envlight_le(&l, fd, rgb);
      worst = fmax(worst, fabs(rgb[0] - px[(y * W + x) * 3]));
      if (fabs(rgb[0] - px[(y * W + x) * 3]) > 1e-3 || fabs(rgb[1] - px[(y * W + x) * 3 + 1]) > 1e-3) ok_pbrt = 0;
    }
  el_envlight_free(&l);
  check(ok_pbrt, "orientation: identity matrix = pbrt-v3's mapping theta from +z, phi = atan2(y,x) (max err %.2g)", worst);

  /* Mitsuba 3 (y up, right-handed): u = atan2(d.x, -d.z) / 2pi (wrapped to [0,1)), v = acos(d.y) / pi */
  el_envlight_yup_matrix(m);
  make_light(&l, px, W, H, m, 0, 0);
  for (y = 0; y < H; ++y)
    for (x = 0; x < W; ++x) {
      double u = (x + 0.5) / W, v = (y + 0.5) / H, th = PI * v, ph = 2 * PI * u;
      float fd[3], rgb[3];
      /* invert Mitsuba's formula: atan2(dx, -dz) = ph, dy = cos(th) */
      fd[0] = (float)(sin(th) * sin(ph)); fd[1] = (float)cos(th); fd[2] = (float)(-sin(th) * cos(ph));
      el_envlight_le(&l, fd, rgb);
      if (fabs(rgb[0] - px[(y * W + x) * 3]) > 1e-3) ok_yup = 0;
      /* pbrt's RotateX(-90) (light +z -> world +y) instead: */
    }
  /* "unmirrored" stated physically: stand inside, look at the image centre (u = 0.5, v = 0.5) with
   * +y up; in a right-handed world "right" = forward x up. A texel to the right of the centre in the
   * image (u > 0.5) must be what you see on your right. */
  {
    double fwd[3], up[3] = {0, 1, 0}, right[3];
    float dir[3], rgb[3];
    double u = 0.5, th = PI * 0.5, ph = 2 * PI * u;
    fwd[0] = sin(th) * sin(ph); fwd[1] = cos(th); fwd[2] = -sin(th) * cos(ph);
    right[0] = fwd[1] * up[2] - fwd[2] * up[1];
    right[1] = fwd[2] * up[0] - fwd[0] * up[2];
    right[2] = fwd[0] * up[1] - fwd[1] * up[0];
    /* 1/8 turn to the right, a bit above the horizon (row 1) */
    dir[0] = (float)(fwd[0] + right[0]); dir[1] = (float)(fwd[1] + right[1] + 0.6); dir[2] = (float)(fwd[2] + right[2]);
    el_envlight_le(&l, dir, rgb);
    /* the texel right of centre: u = 0.625 -> x = 5 (centre u = 0.5 is the edge between x = 3, 4),
     * 45 degrees to the right = u + 0.125 -> x = 5 sits at 0.6875: le is between texels 4 and 5 */
    check(rgb[0] > px[(1 * W + 4) * 3] - 1e-3 && rgb[0] < px[(1 * W + 5) * 3] + 1e-3 &&
          rgb[0] > px[(1 * W + 3) * 3] + 0.5,
          "orientation: y-up matrix, looking at the image centre, the texels to the right in the image are on "
          "the viewer's right (le %.3f between texels x=4 %.1f and x=5 %.1f; x=3 is %.1f)", rgb[0],
          px[(1 * W + 4) * 3], px[(1 * W + 5) * 3], px[(1 * W + 3) * 3]);
  }
  el_envlight_free(&l);
  check(ok_yup, "orientation: el_envlight_yup_matrix reproduces Mitsuba 3's u = atan2(x,-z)/2pi, v = acos(y)/pi at all 32 texels");

  /* Blender (z up, right-handed): u = (atan2(d.y, -d.x) - pi) / -2pi = 0.5 - atan2(y, x) / 2pi, v = acos(z)/pi */
  el_envlight_zup_matrix(m);
  make_light(&l, px, W, H, m, 0, 0);
  for (y = 0; y < H; ++y)
    for (x = 0; x < W; ++x) {
      double u = (x + 0.5) / W, v = (y + 0.5) / H, th = PI * v, ph = 2 * PI * (0.5 - u);
      float fd[3], rgb[3];
      fd[0] = (float)(sin(th) * cos(ph)); fd[1] = (float)(sin(th) * sin(ph)); fd[2] = (float)cos(th);
      el_envlight_le(&l, fd, rgb);
      if (fabs(rgb[0] - px[(y * W + x) * 3]) > 1e-3) ok_zup = 0;
    }
  el_envlight_free(&l);
  check(ok_zup, "orientation: el_envlight_zup_matrix reproduces Blender's u = 0.5 - atan2(y,x)/2pi, v = acos(z)/pi at all 32 texels");

  /* pbrt's RotateX(-90): [1 0 0; 0 0 1; 0 -1 0] (light z -> world y): a mirror image of Mitsuba's view */
  {
    float rx[9] = {1, 0, 0, 0, 0, 1, 0, -1, 0};
    make_light(&l, px, W, H, rx, 0, 0);
    for (y = 0; y < H; ++y)
      for (x = 0; x < W; ++x) {
        double u = (x + 0.5) / W, v = (y + 0.5) / H, th = PI * v, ph = 2 * PI * u;
        float fd[3], rgb[3];
        int xm = ((1 - x) % W + W) % W; /* u' = 0.25 - u */
        fd[0] = (float)(sin(th) * sin(ph)); fd[1] = (float)cos(th); fd[2] = (float)(-sin(th) * cos(ph));
        el_envlight_le(&l, fd, rgb);
        if (fabs(rgb[0] - px[(y * W + xm) * 3]) > 1e-3) ok_mirror = 0;
        if (fabs(rgb[0] - px[(y * W + x) * 3]) <= 1e-3) ++same_as_unmirrored;
      }
    el_envlight_free(&l);
    check(ok_mirror && same_as_unmirrored == 0,
          "orientation: pbrt's RotateX(-90) shows texel (0.25 - u) where Mitsuba shows u: a mirror image "
          "(%d of 32 texels agree with Mitsuba)", same_as_unmirrored);
  }
}

/* ======================================================================================== */
/* 1b. The polynomial mapping against libm in double                                         */
/* ======================================================================================== */
static void test_mapping_accuracy(void) {
  rng r = rng_make(5);
  int i, n = 200000;
  double worst_dir = 0, worst_u = 0, worst_v = 0, worst_len = 0;
  for (i = 0; i < n; ++i) {
    double u = rng_f(&r), v = rng_f(&r), d[3], du, dv, uu, vv, dot, len;
    float fd[3], fu, fv;
    if (i < 4) { u = (i & 1) ? 0.99999994 : 0.0; v = (i & 2) ? 1.0 : 0.0; }
    ref_uv_to_dir(u, v, d);
    el_envlight_uv_to_dir((float)u, (float)v, fd);
    len = sqrt((double)fd[0] * fd[0] + (double)fd[1] * fd[1] + (double)fd[2] * fd[2]);
    dot = (fd[0] * d[0] + fd[1] * d[1] + fd[2] * d[2]) / len;
    worst_dir = fmax(worst_dir, acos(fmin(1.0, dot)) > 0 ? sqrt(fmax(0.0, 2 * (1 - dot))) : 0.0);
    worst_len = fmax(worst_len, fabs(len - 1));
    /* the inverse, away from the poles where u is undefined */
    fd[0] = (float)d[0]; fd[1] = (float)d[1]; fd[2] = (float)d[2];
    el_envlight_dir_to_uv(fd, &fu, &fv);
    {
      double dd[3] = {fd[0], fd[1], fd[2]};
      ref_dir_to_uv(dd, &uu, &vv);
    }
    du = fabs(fu - uu); if (du > 0.5) du = 1 - du;
    dv = fabs(fv - vv);
    if (sin(PI * vv) > 1e-3) worst_u = fmax(worst_u, du * sin(PI * vv)); /* as an angle on the sphere / 2pi */
    worst_v = fmax(worst_v, dv);
  }
  check(worst_dir < 1e-6 && worst_len < 1e-6, "mapping: uv -> dir polynomials within %.2g rad of libm (double), |dir| - 1 within %.2g, "
        "over %d random (u, v) and the corners", worst_dir, worst_len, n);
  check(worst_u < 1e-7 && worst_v < 2e-7, "mapping: dir -> uv (atan polynomial) within %.2g (u, times sin theta) and %.2g (v) of libm",
        worst_u, worst_v);
}

/* ======================================================================================== */
/* 2. le                                                                                     */
/* ======================================================================================== */
static void test_le(const el_image *studio) {
  el_envlight l;
  image im;
  rng r = rng_make(7);
  int i, bad = 0, n = 2000;
  double worst = 0;
  im.px = studio->pixels; im.w = studio->width; im.h = studio->height;
  make_light(&l, studio->pixels, studio->width, studio->height, NULL, 0, 0);
  /* texel centres: le = texel (to the rounding of the direction: relative to the neighbourhood) */
  for (i = 0; i < n; ++i) {
    int x = (int)(rng_f(&r) * im.w), y = (int)(rng_f(&r) * im.h), c;
    double d[3], nb = 0;
    float fd[3], rgb[3];
    ref_uv_to_dir((x + 0.5) / im.w, (y + 0.5) / im.h, d);
    fd[0] = (float)d[0]; fd[1] = (float)d[1]; fd[2] = (float)d[2];
    el_envlight_le(&l, fd, rgb);
    for (c = -1; c <= 1; ++c) { int e; for (e = -1; e <= 1; ++e) nb = fmax(nb, img_at(&im, x + e, y + c, 1)); }
    for (c = 0; c < 3; ++c) {
      double want = img_at(&im, x, y, c), err = fabs(rgb[c] - want) / (nb + 1e-30);
      worst = fmax(worst, err);
      if (err > 1e-4) ++bad;
    }
  }
  check(bad == 0, "le: %d random texel centres of studio reproduce their texel (worst error %.2g of the 3x3 maximum)", n, worst);
  /* random directions vs our own bilinear in double */
  bad = 0; worst = 0;
  for (i = 0; i < n; ++i) {
    double d[3], u, v, want;
    float fd[3], rgb[3];
    d[0] = rng_f(&r) - 0.5; d[1] = rng_f(&r) - 0.5; d[2] = rng_f(&r) - 0.5;
    fd[0] = (float)d[0]; fd[1] = (float)d[1]; fd[2] = (float)d[2];
    ref_dir_to_uv(d, &u, &v);
    want = ref_bilerp(&im, u, v, 1);
    el_envlight_le(&l, fd, rgb);
    worst = fmax(worst, fabs(rgb[1] - want) / (want + 1e-3));
    if (fabs(rgb[1] - want) > 1e-3 * (want + 1e-3)) ++bad;
  }
  check(bad == 0, "le: %d random directions match a double-precision bilinear reconstruction (worst rel %.2g)", n, worst);
  check(el_envlight_sampling_bytes(&l) == 0, "lazy: a light used only for le has built no sampling tables (%zu bytes)",
        el_envlight_sampling_bytes(&l));
  el_envlight_free(&l);

  /* seam and poles on a tiny map: Repeat in u, Clamp in v (no north-south leak: pbrt-v3 issue #63) */
  {
    enum { W = 4, H = 3 };
    float px[W * H * 3], rgb[3], north[3] = {0, 0, 1}, south[3] = {0, 0, -1}, fd[3];
    double d[3];
    int k;
    for (k = 0; k < W * H; ++k) { int y = k / W, x = k % W; px[3 * k] = px[3 * k + 1] = px[3 * k + 2] = (float)(y == 0 ? 1 + x : y == H - 1 ? 1000 + x : 50); }
    make_light(&l, px, W, H, NULL, 0, 0);
    el_envlight_le(&l, north, rgb);
    /* the pole is (u, v) = (0, 0): halfway between texels x = 3 and x = 0 of row 0 */
    check(fabs(rgb[0] - 2.5f) < 1e-4f, "le: north pole = mean of the top row's texels at the seam (%.6f, want 2.5; "
          "pbrt-v3's Repeat in v would mix in the bottom row's 1000s)", rgb[0]);
    el_envlight_le(&l, south, rgb);
    check(fabs(rgb[0] - 1001.5f) < 1e-2f, "le: south pole = mean of the bottom row's texels at the seam (%.4f, want (1003 + 1000)/2)", rgb[0]);
    /* just north of the seam at row 0 centre: u -> 0+ and 1- both give texels 3 and 0 half and half */
    ref_uv_to_dir(1e-6, 0.5 / H, d);
    fd[0] = (float)d[0]; fd[1] = (float)d[1]; fd[2] = (float)d[2];
    el_envlight_le(&l, fd, rgb);
    check(fabs(rgb[0] - 2.5f) < 1e-3f, "le: Repeat across the seam u = 0 (%.5f, want 2.5 = (texel 3 + texel 0)/2)", rgb[0]);
    el_envlight_free(&l);
  }
}

/* ======================================================================================== */
/* 3. Chi-square: sample_li against pdf_li                                                   */
/* ======================================================================================== */
/* Cells: a Gu x Gv grid in light-space (u, v), each a union of whole importance bins (nu, nv multiples
 * of Gu, Gv), so the expected probability is exact: the sum over its bins of pdf_li at the bin centre
 * (world direction through our own double-precision mapping) times sin(theta_c) dtheta dphi, which is
 * p_uv du dv exactly for a density p_uv / (2 pi^2 sin theta). */
static int g_chi2_tests = 0;
static const int CHI2_TESTS_PLANNED = 18;

static void chi2_light(const char *name, el_envlight *l, const float m[9], int gu, int gv, int n, uint64_t seed) {
  int nu = l->imp_w, nv = l->imp_h, i, j, cells = gu * gv, pooled_cells = 0, dof;
  double *expect = (double *)calloc((size_t)cells, sizeof(double));
  double *obs = (double *)calloc((size_t)cells, sizeof(double));
  double chi2, total = 0, pval, alpha = 0.01 / CHI2_TESTS_PLANNED;
  int impossible = 0, mismatch = 0, nonfinite = 0;
  rng r = rng_make(seed);
  el_envlight_prepare_sampling(l);
  nu = l->imp_w; nv = l->imp_h;
  for (j = 0; j < nv; ++j)
    for (i = 0; i < nu; ++i) {
      double u = (i + 0.5) / nu, v = (j + 0.5) / nv, dl[3], dw[3];
      float fd[3], p;
      ref_uv_to_dir(u, v, dl);
      mat_mul(m, dl, dw);
      fd[0] = (float)dw[0]; fd[1] = (float)dw[1]; fd[2] = (float)dw[2];
      p = el_envlight_pdf_li(l, fd);
      expect[(j * gv / nv) * gu + (i * gu / nu)] += p * sin(PI * v) * (PI / nv) * (2 * PI / nu);
    }
  for (i = 0; i < cells; ++i) total += expect[i];
  for (i = 0; i < n; ++i) {
    float uu[2], wi[3], rgb[3], p, q;
    double dw[3], dl[3], u, v;
    int cu, cv;
    uu[0] = rng_f(&r); uu[1] = rng_f(&r);
    el_envlight_sample_li(l, uu, wi, rgb, &p);
    if (!(p > 0)) continue;
    if (!(p < 1e30f) || wi[0] != wi[0]) { ++nonfinite; continue; }
    q = el_envlight_pdf_li(l, wi);
    if (!(fabsf(p - q) <= 1e-4f * p)) ++mismatch;
    dw[0] = wi[0]; dw[1] = wi[1]; dw[2] = wi[2];
    mat_mul_t(m, dw, dl);
    ref_dir_to_uv(dl, &u, &v);
    cu = (int)(u * gu); cv = (int)(v * gv);
    if (cu >= gu) cu = gu - 1;
    if (cv >= gv) cv = gv - 1;
    obs[cv * gu + cu] += 1;
  }
  chi2 = chisq_pooled(expect, obs, (size_t)cells, total, n, &impossible, &pooled_cells);
  dof = pooled_cells - 1;
  pval = dof > 0 ? gammq(0.5 * dof, 0.5 * chi2) : 1.0;
  ++g_chi2_tests;
  check(pval > alpha && impossible == 0 && fabs(total - 1) < 1e-4,
        "chi2 %-34s: chi2 = %.1f, %d dof, p = %.3g (> %.2g), pdf_li sums to %.6f, %d samples in zero-pdf cells",
        name, chi2, dof, pval, alpha, total, impossible);
  check(mismatch == 0 && nonfinite == 0, "chi2 %-34s: pdf_li(sample dir) == sampled pdf for all %d samples (%d mismatches, %d non-finite)",
        name, n, mismatch, nonfinite);
  free(expect);
  free(obs);
}

static void chi2_map(const char *name, const float *px, int w, int h, int gu, int gv, int n, int comp,
                     int rotate, int sampler, uint64_t seed) {
  el_envlight l;
  float m[9];
  char label[128];
  el_result res;
  if (rotate) rotation37(m); else identity(m);
  res = make_light(&l, px, w, h, m, comp, sampler);
  snprintf(label, sizeof label, "%s%s%s%s", name, comp ? " compensated" : "", rotate ? " rotated" : "",
           sampler == EL_ENVLIGHT_SAMPLER_CDF ? " CDF" : sampler == EL_ENVLIGHT_SAMPLER_ALIAS ? " alias" : "");
  if (res != EL_SUCCESS) { check(0, "chi2 %s: init failed (%s)", label, el_result_string(res)); return; }
  chi2_light(label, &l, m, gu, gv, n, seed);
  el_envlight_free(&l);
}

static void test_chi2(const el_image *studio, const el_image *city) {
  enum { HW = 64, HH = 32 };
  float *hot = (float *)calloc(HW * HH * 3, sizeof(float));
  float *poles = (float *)malloc(HW * HH * 3 * sizeof(float));
  int k, comp, rot, n = 200000;
  hot[(10 * HW + 41) * 3 + 0] = 1e6f; hot[(10 * HW + 41) * 3 + 1] = 2e6f; hot[(10 * HW + 41) * 3 + 2] = 5e5f;
  for (k = 0; k < HW * HH; ++k) {
    int y = k / HW, x = k % HW;
    float v = (y == 0 || y == HH - 1) ? 1000.0f * (1.0f + (float)(x % 5)) : 0.25f;
    poles[3 * k] = poles[3 * k + 1] = poles[3 * k + 2] = v;
  }
  for (comp = 0; comp < 2; ++comp)
    for (rot = 0; rot < 2; ++rot) {
      chi2_map("studio", studio->pixels, studio->width, studio->height, 64, 32, n, comp, rot, 0, 11 + comp + 2 * rot);
      chi2_map("city", city->pixels, city->width, city->height, 64, 32, n, comp, rot, 0, 21 + comp + 2 * rot);
      chi2_map("hot texel 64x32", hot, HW, HH, 64, 32, n, comp, rot, 0, 31 + comp + 2 * rot);
      chi2_map("hot pole rows 64x32", poles, HW, HH, 64, 32, n, comp, rot, 0, 41 + comp + 2 * rot);
    }
  chi2_map("city", city->pixels, city->width, city->height, 64, 32, n, 0, 0, EL_ENVLIGHT_SAMPLER_CDF, 51);
  chi2_map("city", city->pixels, city->width, city->height, 64, 32, n, 0, 1, EL_ENVLIGHT_SAMPLER_ALIAS, 52);
  check(g_chi2_tests == CHI2_TESTS_PLANNED,
        "chi2: %d goodness-of-fit tests, Bonferroni over %d", g_chi2_tests, CHI2_TESTS_PLANNED);
  free(hot);
  free(poles);
}

/* ======================================================================================== */
/* 3b. The importance map is the exact mean of the bilinear le over each bin, times sin(theta) */
/* ======================================================================================== */
/* Expected density of bin (i, j): the mean of our own bilinear reconstruction over the bin by a
 * 32x32 midpoint rule (exact for a bilinear function on sub-cells that do not straddle its kinks, which
 * 32 sub-cells per bin do not when bins are texels or halves of texels), times sin(theta_c), normalised. */
static void test_importance_map(void) {
  enum { W = 8, H = 4 };
  float px[W * H * 3];
  image im;
  int k, res;
  rng r = rng_make(99);
  for (k = 0; k < W * H * 3; ++k) px[k] = rng_f(&r) * (k % 5 == 0 ? 100.0f : 1.0f);
  im.px = px; im.w = W; im.h = H;
  for (res = 0; res < 3; ++res) {
    int nu = res == 0 ? W : res == 1 ? 2 * W : 5, nv = res == 0 ? H : res == 1 ? 2 * H : 3, i, j, a, b, S = 32;
    double *want = (double *)malloc((size_t)nu * nv * sizeof(double)), total = 0, worst = 0;
    el_envlight l;
    el_envlight_options o;
    memset(&o, 0, sizeof o);
    o.importance_width = nu; o.importance_height = nv;
    el_envlight_init(&l, px, W, H, 3, &o);
    for (j = 0; j < nv; ++j)
      for (i = 0; i < nu; ++i) {
        double m = 0;
        for (b = 0; b < S; ++b)
          for (a = 0; a < S; ++a) {
            double u = (i + (a + 0.5) / S) / nu, v = (j + (b + 0.5) / S) / nv;
            m += lum3(ref_bilerp(&im, u, v, 0), ref_bilerp(&im, u, v, 1), ref_bilerp(&im, u, v, 2));
          }
        want[j * nu + i] = m / (S * S) * sin(PI * (j + 0.5) / nv);
        total += want[j * nu + i];
      }
    for (j = 0; j < nv; ++j)
      for (i = 0; i < nu; ++i) {
        double d[3], p_uv, expect = want[j * nu + i] / total * nu * nv, v = (j + 0.5) / nv;
        float fd[3];
        ref_uv_to_dir((i + 0.5) / nu, v, d);
        fd[0] = (float)d[0]; fd[1] = (float)d[1]; fd[2] = (float)d[2];
        p_uv = el_envlight_pdf_li(&l, fd) * 2 * PI * PI * sin(PI * v); /* back to a density over (u, v) */
        worst = fmax(worst, fabs(p_uv - expect) / expect);
      }
    check(worst < 1e-4,
          "importance map %dx%d of an 8x4 map = the mean of the bilinear le over each bin x sin(theta): worst rel err %.2g",
          nu, nv, worst);
    el_envlight_free(&l);
    free(want);
  }
}

/* ======================================================================================== */
/* 4. pdf_li integrates to 1 (a grid NOT aligned with the bins)                              */
/* ======================================================================================== */
static void test_pdf_integral(const el_image *studio) {
  /* The bin-aligned sums in the chi-square tests are exact (to 1e-4); here a world-space midpoint grid
   * tilted against the rotated light's bins. Smooth map: the midpoint rule's error on the bins' edges
   * stays small (a sun would hold most of the mass in a few bins and need a far finer grid). */
  el_envlight l;
  float m[9];
  int comp;
  rotation37(m);
  for (comp = 0; comp < 2; ++comp) {
    int i, j, nu = 3000, nv = 1400;
    double s = 0;
    make_light(&l, studio->pixels, studio->width, studio->height, m, comp, 0);
    for (j = 0; j < nv; ++j) {
      double v = (j + 0.5) / nv, dom = (cos(PI * j / nv) - cos(PI * (j + 1) / nv)) * 2 * PI / nu;
      for (i = 0; i < nu; ++i) {
        double dw[3];
        float fd[3];
        ref_uv_to_dir((i + 0.5) / nu, v, dw);
        fd[0] = (float)dw[0]; fd[1] = (float)dw[1]; fd[2] = (float)dw[2];
        s += el_envlight_pdf_li(&l, fd) * dom;
      }
    }
    check(fabs(s - 1) < 2e-3, "pdf_li integrates to 1 over a %dx%d world grid not aligned with the rotated bins: %.5f (studio, %s)",
          nu, nv, s, comp ? "compensated" : "plain");
    el_envlight_free(&l);
  }
}

/* ======================================================================================== */
/* 5. Unbiasedness: irradiance vs quadrature                                                 */
/* ======================================================================================== */
#define NNORM 4
static const double NORMALS[NNORM][3] = {{0, 0, 1}, {0.6, 0, -0.8}, {0.36, -0.48, 0.8}, {-1, 0, 0}};

/* E(n) = integral of L(w) max(0, n.w) dw over the sphere (light space n), luminance of L, by the
 * midpoint rule on s x s sub-cells of each texel (s even: sub-cells never straddle a kink of the
 * bilinear reconstruction, so the reconstruction is exactly bilinear inside each), or for s = 1 with the
 * exact cell mean of the reconstruction (the separable 1/8, 3/4, 1/8 filter) at the texel centre. The
 * reconstruction is linear, so we work on the luminance image. */
static void quadrature(const image *im, int s, const double n[][3], int nn, double *E) {
  int x, y, a, b, k, W = im->w, H = im->h, WS = W * s;
  float *lum = (float *)malloc((size_t)W * H * sizeof(float));
  double *cu = (double *)malloc((size_t)WS * sizeof(double)), *su = (double *)malloc((size_t)WS * sizeof(double));
  for (k = 0; k < nn; ++k) E[k] = 0;
  for (k = 0; k < W * H; ++k) lum[k] = (float)lum3(im->px[3 * (size_t)k], im->px[3 * (size_t)k + 1], im->px[3 * (size_t)k + 2]);
  for (x = 0; x < WS; ++x) { double u = (x + 0.5) / WS; cu[x] = cos(2 * PI * u); su[x] = sin(2 * PI * u); }
#define LUM(xx, yy) ((double)lum[(size_t)((yy) < 0 ? 0 : (yy) > H - 1 ? H - 1 : (yy)) * W + (size_t)((((xx) % W) + W) % W)])
  for (y = 0; y < H; ++y)
    for (b = 0; b < s; ++b) {
      double v0 = (y + (double)b / s) / H, v1 = (y + (b + 1.0) / s) / H, v = 0.5 * (v0 + v1);
      double dom = (cos(PI * v0) - cos(PI * v1)) * 2 * PI / WS, st = sin(PI * v), ct = cos(PI * v);
      double t = v * H - 0.5, fy;
      int y0 = (int)floor(t);
      double acc[8] = {0, 0, 0, 0, 0, 0, 0, 0};
      fy = t - y0;
      for (x = 0; x < W; ++x)
        for (a = 0; a < s; ++a) {
          double L, w0, w1, w2;
          if (s == 1) {
            double r0 = 0.125 * LUM(x - 1, y - 1) + 0.75 * LUM(x, y - 1) + 0.125 * LUM(x + 1, y - 1);
            double r1 = 0.125 * LUM(x - 1, y) + 0.75 * LUM(x, y) + 0.125 * LUM(x + 1, y);
            double r2 = 0.125 * LUM(x - 1, y + 1) + 0.75 * LUM(x, y + 1) + 0.125 * LUM(x + 1, y + 1);
            L = 0.125 * r0 + 0.75 * r1 + 0.125 * r2;
          } else {
            double u = (x + (a + 0.5) / s) / W, ss = u * W - 0.5, fx;
            int x0 = (int)floor(ss);
            fx = ss - x0;
            L = (1 - fy) * ((1 - fx) * LUM(x0, y0) + fx * LUM(x0 + 1, y0)) + fy * ((1 - fx) * LUM(x0, y0 + 1) + fx * LUM(x0 + 1, y0 + 1));
          }
          w0 = st * cu[x * s + a]; w1 = st * su[x * s + a]; w2 = ct;
          for (k = 0; k < nn; ++k) {
            double c = n[k][0] * w0 + n[k][1] * w1 + n[k][2] * w2;
            if (c > 0) acc[k] += L * c;
          }
        }
      for (k = 0; k < nn; ++k) E[k] += acc[k] * dom;
    }
#undef LUM
  free(lum); free(cu); free(su);
}

/* unit b1, b2 completing the unit normal n to a right-handed frame (for cosine-weighted samples) */
static void frame_around(const double n[3], double b1[3], double b2[3]) {
  double t[3] = {1, 0, 0}, d, len;
  if (fabs(n[0]) > 0.9) { t[0] = 0; t[1] = 1; }
  d = t[0] * n[0] + t[1] * n[1] + t[2] * n[2];
  b1[0] = t[0] - d * n[0]; b1[1] = t[1] - d * n[1]; b1[2] = t[2] - d * n[2];
  len = sqrt(b1[0] * b1[0] + b1[1] * b1[1] + b1[2] * b1[2]);
  b1[0] /= len; b1[1] /= len; b1[2] /= len;
  b2[0] = n[1] * b1[2] - n[2] * b1[1]; b2[1] = n[2] * b1[0] - n[0] * b1[2]; b2[2] = n[0] * b1[1] - n[1] * b1[0];
}

/* MC estimate of E(n) for each normal (world normal = M * light normal) with sample_li; mis: one-sample
 * MIS between sample_li and cosine sampling (balance heuristic), needed with compensation. */
static void irradiance_mc(el_envlight *l, const float m[9], int nsamp, int mis, uint64_t seed, double *mean, double *se) {
  int k, i;
  for (k = 0; k < NNORM; ++k) {
    double nl[3], nw[3], sum = 0, sum2 = 0, b1[3], b2[3];
    rng r = rng_make(seed + (uint64_t)k);
    nl[0] = NORMALS[k][0]; nl[1] = NORMALS[k][1]; nl[2] = NORMALS[k][2];
    mat_mul(m, nl, nw);
    frame_around(nw, b1, b2);
    for (i = 0; i < nsamp; ++i) {
      float uu[2], wi[3], rgb[3], p;
      double f = 0;
      uu[0] = rng_f(&r); uu[1] = rng_f(&r);
      if (!mis || rng_f(&r) < 0.5f) {
        el_envlight_sample_li(l, uu, wi, rgb, &p);
        if (p > 0) {
          double c = nw[0] * wi[0] + nw[1] * wi[1] + nw[2] * wi[2];
          if (c > 0) {
            double pc = c / PI, denom = mis ? 0.5 * p + 0.5 * pc : p;
            f = lum3(rgb[0], rgb[1], rgb[2]) * c / denom;
          }
        }
      } else { /* cosine sampling */
        double rr = sqrt((double)uu[0]), ph = 2 * PI * uu[1], lx = rr * cos(ph), ly = rr * sin(ph), lz = sqrt(fmax(0.0, 1 - uu[0]));
        float fd[3];
        double c = lz;
        fd[0] = (float)(lx * b1[0] + ly * b2[0] + lz * nw[0]);
        fd[1] = (float)(lx * b1[1] + ly * b2[1] + lz * nw[1]);
        fd[2] = (float)(lx * b1[2] + ly * b2[2] + lz * nw[2]);
        if (c > 0) {
          double pl = el_envlight_pdf_li(l, fd), pc = c / PI;
          el_envlight_le(l, fd, rgb);
          f = lum3(rgb[0], rgb[1], rgb[2]) * c / (0.5 * pl + 0.5 * pc);
        }
      }
      sum += f; sum2 += f * f;
    }
    mean[k] = sum / nsamp;
    se[k] = sqrt(fmax(0.0, sum2 / nsamp - mean[k] * mean[k]) / (nsamp - 1));
  }
}

static void unbiased_case(const char *name, const float *px, int w, int h, int qs, int nsamp, int comp, int rotate,
                          int imp_w, int imp_h) {
  el_envlight l;
  el_envlight_options o;
  image im;
  double E[NNORM], mean[NNORM], se[NNORM], worst = 0;
  float m[9];
  int k, ok = 1;
  el_result res;
  if (rotate) rotation37(m); else identity(m);
  im.px = px; im.w = w; im.h = h;
  quadrature(&im, qs, NORMALS, NNORM, E);
  memset(&o, 0, sizeof o);
  memcpy(o.light_to_world, m, sizeof m);
  o.compensated = comp;
  o.importance_width = imp_w; o.importance_height = imp_h;
  res = el_envlight_init(&l, px, w, h, 3, &o);
  if (res != EL_SUCCESS) { check(0, "unbiased %s: init %s", name, el_result_string(res)); return; }
  irradiance_mc(&l, m, nsamp, comp, 1234, mean, se);
  for (k = 0; k < NNORM; ++k) {
    double z = (mean[k] - E[k]) / se[k];
    if (!(fabs(z) <= 3.0)) ok = 0;
    if (fabs(z) > worst) worst = fabs(z);
  }
  check(ok, "unbiased %-44s: irradiance at %d normals within 3 SE of quadrature (worst |z| = %.2f; E = %.4g %.4g %.4g %.4g, "
        "rel SE %.1e)", name, NNORM, worst, E[0], E[1], E[2], E[3], se[0] / (E[0] + 1e-300));
  el_envlight_free(&l);
}

static void test_unbiased(const el_image *studio, const el_image *city) {
  unbiased_case("studio", studio->pixels, studio->width, studio->height, 4, 200000, 0, 0, 0, 0);
  unbiased_case("studio rotated", studio->pixels, studio->width, studio->height, 4, 200000, 0, 1, 0, 0);
  unbiased_case("city (sun 3e4)", city->pixels, city->width, city->height, 4, 200000, 0, 0, 0, 0);
  unbiased_case("city compensated + MIS", city->pixels, city->width, city->height, 4, 200000, 1, 1, 0, 0);
  unbiased_case("city, importance 300x100 (not a divisor)", city->pixels, city->width, city->height, 4, 200000, 0, 0, 300, 100);
  { /* a generated 8192x4096 map with a 1e12 range: smooth sky 1e-6..1e-4, a 1e6 sun, a dark band */
    int W = 8192, H = 4096, x, y;
    float *px = (float *)malloc((size_t)W * H * 3 * sizeof(float));
    if (!px) { check(0, "unbiased 8192x4096: out of memory"); return; }
    for (y = 0; y < H; ++y)
      for (x = 0; x < W; ++x) {
        float *p = px + ((size_t)y * W + x) * 3;
        float s = 1e-6f * (1.0f + 99.0f * (float)(y % 97) / 96.0f);
        if (y > 3000 && y < 3100) s = 0.0f;
        p[0] = s; p[1] = 0.9f * s; p[2] = 1.2f * s;
      }
    for (y = 1000; y < 1003; ++y)
      for (x = 5000; x < 5003; ++x) { float *p = px + ((size_t)y * W + x) * 3; p[0] = p[1] = p[2] = 1e6f; }
    px[((size_t)12 * W + 77) * 3 + 1] = 3e5f; /* a lone hot texel near the north pole */
    unbiased_case("generated 8192x4096, 1e12 range, importance 2048x1024", px, W, H, 1, 400000, 0, 1, 2048, 1024);
    free(px);
  }
}

/* ======================================================================================== */
/* 6. integral / power, sample_le / pdf_le                                                   */
/* ======================================================================================== */
static void test_power(const el_image *studio) {
  el_envlight l;
  image im;
  float integ[3], pw[3], c[3] = {1, 2, 3}, u[4] = {0.3f, 0.7f, 0.9f, 0.2f}, org[3], dir[3], nrm[3], rgb[3], pp, pd, pp2, pd2;
  double q[3] = {0, 0, 0}, dd;
  int x, y, a, b, ch, s = 4, ok;
  im.px = studio->pixels; im.w = studio->width; im.h = studio->height;
  make_light(&l, studio->pixels, studio->width, studio->height, NULL, 0, 0);
  for (y = 0; y < im.h; ++y)
    for (b = 0; b < s; ++b) {
      double v0 = (y + (double)b / s) / im.h, v1 = (y + (b + 1.0) / s) / im.h, v = 0.5 * (v0 + v1);
      double dom = (cos(PI * v0) - cos(PI * v1)) * 2 * PI / (im.w * s);
      for (x = 0; x < im.w; ++x)
        for (a = 0; a < s; ++a)
          for (ch = 0; ch < 3; ++ch) q[ch] += ref_bilerp(&im, (x + (a + 0.5) / s) / im.w, v, ch) * dom;
    }
  el_envlight_integral(&l, integ);
  ok = 1;
  for (ch = 0; ch < 3; ++ch) if (fabs(integ[ch] - q[ch]) > 1e-4 * q[ch]) ok = 0;
  check(ok, "integral of le over the sphere = quadrature: %.6g %.6g %.6g vs %.6g %.6g %.6g", integ[0], integ[1], integ[2], q[0], q[1], q[2]);
  el_envlight_power(&l, pw);
  check(pw[0] == 0 && pw[1] == 0, "power before preprocess (radius 0) is 0");
  el_envlight_sample_le(&l, u, org, dir, nrm, rgb, &pp, &pd);
  check(pp == 0 && pd == 0, "sample_le before preprocess gives pdfs 0");
  el_envlight_preprocess(&l, c, 2.0f);
  el_envlight_power(&l, pw);
  check(fabs(pw[1] - PI * 4 * q[1]) < 1e-4 * PI * 4 * q[1], "power = pi r^2 * integral (pbrt-v4's Phi): %.6g vs %.6g", pw[1], PI * 4 * q[1]);
  el_envlight_sample_le(&l, u, org, dir, nrm, rgb, &pp, &pd);
  el_envlight_pdf_le(&l, dir, &pp2, &pd2);
  { /* origin: on the plane through c + 2 * (-dir) perpendicular to dir, within radius 2 of that point */
    double rel[3], along, perp2;
    for (ch = 0; ch < 3; ++ch) rel[ch] = org[ch] - c[ch];
    along = rel[0] * dir[0] + rel[1] * dir[1] + rel[2] * dir[2];
    perp2 = rel[0] * rel[0] + rel[1] * rel[1] + rel[2] * rel[2] - along * along;
    dd = dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2];
    check(fabs(along + 2) < 1e-5 && perp2 <= 4 * (1 + 1e-5) && fabs(dd - 1) < 1e-5,
          "sample_le: origin on the disk of radius r facing the direction, r away from the centre (along %.6f, perp %.4f)", along, sqrt(perp2));
  }
  check(fabsf(pp - 1.0f / (float)(PI * 4)) < 1e-6f && pp2 == pp && fabsf(pd - pd2) <= 1e-4f * pd && pd > 0 &&
        nrm[0] == dir[0] && nrm[2] == dir[2],
        "sample_le / pdf_le: pdf_pos = 1/(pi r^2) = %.6f, pdf_dir %.6g == pdf_le %.6g, normal = ray direction", pp, pd, pd2);
  el_envlight_free(&l);
}

static int finite3(const float *v) { return fabsf(v[0]) <= FLT_MAX && fabsf(v[1]) <= FLT_MAX && fabsf(v[2]) <= FLT_MAX; }

/* The bounding spheres preprocess accepts give finite outputs everywhere; the others are refused (before,
 * radius 1e-30 gave pdf_pos = +Inf, FLT_MAX gave origins near FLT_MAX and pdf_pos 0, a NaN centre NaN
 * origins). Radii 2^k for k in [-80, 80] around three centres: accepted exactly when 2^-64 <= r <= 2^62
 * and r >= 2^-20 max|c| (127, 81 and 14 radii of the three); then 64 sample_le rays each have finite
 * origins, unit directions, a finite normal-float pdf_pos > 0 equal to pdf_le's, and power() is finite. */
static void test_preprocess(void) {
  static const float centres[3][3] = {{0.0f, 0.0f, 0.0f}, {1.0f, -2.0f, 3.0f}, {-3e20f, 1e15f, 7e19f}};
  float px[8 * 4 * 3], pw[3], ok_c[3] = {0.0f, 0.0f, 0.0f}, bad[3];
  el_envlight l;
  int i, k, ci, wrong = 0, tested = 0, accepted = 0, nonfinite = 0;
  rng r = rng_make(77);
  for (i = 0; i < 8 * 4 * 3; ++i) px[i] = 0.2f + (float)(i % 7);
  make_light(&l, px, 8, 4, NULL, 0, 0);
  for (ci = 0; ci < 3; ++ci)
    for (k = -80; k <= 80; ++k) {
      float R = ldexpf(1.0f, k), m = 0.0f;
      int want, j;
      el_result res;
      for (j = 0; j < 3; ++j) m = fabsf(centres[ci][j]) > m ? fabsf(centres[ci][j]) : m;
      want = k >= -64 && k <= 62 && (double)R >= ldexp((double)m, -20);
      res = el_envlight_preprocess(&l, centres[ci], R);
      ++tested;
      if ((res == EL_SUCCESS) != want || (!want && res != EL_ERROR_INVALID_ARGUMENT)) ++wrong;
      if (res != EL_SUCCESS) continue;
      ++accepted;
      for (j = 0; j < 64; ++j) {
        float u[4], org[3], dir[3], nrm[3], rgb[3], pp, pd, pp2, pd2, dd;
        u[0] = rng_f(&r); u[1] = rng_f(&r); u[2] = j == 0 ? 0.0f : j == 1 ? 1.0f : rng_f(&r); u[3] = j < 2 ? 1.0f : rng_f(&r);
        el_envlight_sample_le(&l, u, org, dir, nrm, rgb, &pp, &pd);
        el_envlight_pdf_le(&l, dir, &pp2, &pd2);
        dd = dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2];
        if (!finite3(org) || !finite3(dir) || !finite3(rgb) || !(fabsf(dd - 1.0f) < 1e-5f) || !(pp >= FLT_MIN && pp <= FLT_MAX) ||
            !(pd > 0.0f && pd <= FLT_MAX) || pp2 != pp || !(pd2 > 0.0f && pd2 <= FLT_MAX))
          ++nonfinite;
      }
      el_envlight_power(&l, pw);
      if (!finite3(pw) || !(pw[0] > 0.0f)) ++nonfinite;
    }
  check(wrong == 0 && accepted == 127 + 81 + 14, "preprocess: %d of %d spheres accepted or refused as documented (%d accepted)", tested - wrong, tested, accepted);
  check(nonfinite == 0, "preprocess: every accepted sphere gives finite sample_le / pdf_le / power outputs (%d failures)", nonfinite);
  /* the issue's cases, each refused with the documented error, and the light keeps its sphere */
  check(el_envlight_preprocess(&l, ok_c, 2.0f) == EL_SUCCESS, "preprocess: centre 0, radius 2 accepted");
  check(el_envlight_preprocess(&l, ok_c, 1e-30f) == EL_ERROR_INVALID_ARGUMENT, "radius 1e-30: EL_ERROR_INVALID_ARGUMENT");
  check(el_envlight_preprocess(&l, ok_c, FLT_MAX) == EL_ERROR_INVALID_ARGUMENT, "radius FLT_MAX: EL_ERROR_INVALID_ARGUMENT");
  check(el_envlight_preprocess(&l, ok_c, INFINITY) == EL_ERROR_INFINITE, "radius +Inf: EL_ERROR_INFINITE");
  check(el_envlight_preprocess(&l, ok_c, NAN) == EL_ERROR_NAN, "radius NaN: EL_ERROR_NAN");
  check(el_envlight_preprocess(&l, ok_c, 0.0f) == EL_ERROR_INVALID_ARGUMENT && el_envlight_preprocess(&l, ok_c, -1.0f) == EL_ERROR_INVALID_ARGUMENT,
        "radius 0 and -1: EL_ERROR_INVALID_ARGUMENT");
  bad[0] = 0.0f; bad[1] = NAN; bad[2] = 0.0f;
  check(el_envlight_preprocess(&l, bad, 1.0f) == EL_ERROR_NAN, "a NaN centre: EL_ERROR_NAN");
  bad[1] = -INFINITY;
  check(el_envlight_preprocess(&l, bad, 1.0f) == EL_ERROR_INFINITE, "an infinite centre: EL_ERROR_INFINITE");
  bad[1] = 1e30f;
  check(el_envlight_preprocess(&l, bad, 1.0f) == EL_ERROR_INVALID_ARGUMENT, "radius 1 at a centre 1e30 away (below its float step): refused");
  check(el_envlight_preprocess(&l, NULL, 1.0f) == EL_ERROR_INVALID_ARGUMENT, "a NULL centre: EL_ERROR_INVALID_ARGUMENT");
  check(l.radius == 2.0f && l.center[0] == 0.0f && l.center[1] == 0.0f, "refused spheres leave the light's sphere as it was");
  el_envlight_free(&l);
}

/* ======================================================================================== */
/* 7. Hard cases                                                                             */
/* ======================================================================================== */
static double grid_integral(el_envlight *l) { /* bin-independent grid integral of pdf_li */
  int i, j, nu = 400, nv = 200;
  double s = 0;
  for (j = 0; j < nv; ++j) {
    double dom = (cos(PI * j / nv) - cos(PI * (j + 1) / nv)) * 2 * PI / nu;
    for (i = 0; i < nu; ++i) {
      double d[3];
      float fd[3];
      ref_uv_to_dir((i + 0.5) / nu, (j + 0.5) / nv, d);
      fd[0] = (float)d[0]; fd[1] = (float)d[1]; fd[2] = (float)d[2];
      s += el_envlight_pdf_li(l, fd) * dom;
    }
  }
  return s;
}

static int sample_consistent(el_envlight *l, int n, uint64_t seed, int *finite) {
  rng r = rng_make(seed);
  int i, bad = 0;
  *finite = 1;
  for (i = 0; i < n; ++i) {
    float uu[2], wi[3], rgb[3], p, q;
    uu[0] = rng_f(&r); uu[1] = rng_f(&r);
    el_envlight_sample_li(l, uu, wi, rgb, &p);
    q = el_envlight_pdf_li(l, wi);
    if (!(p >= 0 && p < 1e30f) || !(q >= 0 && q < 1e30f) || wi[0] != wi[0] || rgb[0] != rgb[0]) *finite = 0;
    if (p > 0 && !(fabsf(p - q) <= 1e-4f * p)) ++bad;
  }
  return bad;
}

/* Samples at the very ends of the distribution (u at 0, one ulp below 1, at 1) on small maps whose
 * importance grid is not a power of two (nv = 17, 31): v = (iv + fv) / nv rounds, so sin(theta) next to
 * the south pole must come from the bin (1 - fv), not from 1 - v, or it drops below pdf_li's floor and
 * the two pdfs differ (they did by 27% before the fix). */
static void test_pole_rounding(void) {
  static const int imp[3][2] = {{35, 17}, {33, 31}, {64, 32}};
  const int w = 64, h = 32;
  float *px = (float *)malloc((size_t)w * h * 3 * sizeof(float));
  static const float us[5] = {0.0f, 1e-30f, 0.5f, 0x1.fffffep-1f, 1.0f};
  int k, i, j, bad = 0, n = 0;
  for (i = 0; i < w * h * 3; ++i) px[i] = 0.5f + (float)(i % 13) * 0.1f;
  for (k = 0; k < 3; ++k) {
    el_envlight l;
    el_envlight_options o;
    memset(&o, 0, sizeof o);
    o.importance_width = imp[k][0];
    o.importance_height = imp[k][1];
    if (el_envlight_init(&l, px, w, h, 3, &o) != EL_SUCCESS) { ++bad; continue; }
    for (i = 0; i < 5; ++i)
      for (j = 0; j < 5; ++j) {
        float uu[2], wi[3], p, q;
        uu[0] = us[i]; uu[1] = us[j];
        el_envlight_sample_li(&l, uu, wi, NULL, &p);
        q = el_envlight_pdf_li(&l, wi);
        ++n;
        if (!(p > 0 && p < 1e30f && fabsf(p - q) <= 1e-4f * p)) ++bad;
      }
    el_envlight_free(&l);
  }
  free(px);
  check(bad == 0, "u at 0, 1e-30, 0.5, 1 - 2^-24 and 1 on importance grids 35x17, 33x31, 64x32: pdf_li(wi) == pdf "
        "(%d of %d differ)", bad, n);
}

static void test_hard_cases(void) {
  el_envlight l;
  el_envlight_options o;
  el_result res;
  float rgb[3], wi[3], p, uu[2], dir[3];
  int fin, k;
  static float black[16 * 8 * 3];
  /* all black */
  res = make_light(&l, black, 16, 8, NULL, 0, 0);
  uu[0] = 0.3f; uu[1] = 0.6f;
  el_envlight_sample_li(&l, uu, wi, rgb, &p);
  dir[0] = 0.2f; dir[1] = -0.4f; dir[2] = 0.5f;
  el_envlight_le(&l, dir, rgb);
  check(res == EL_SUCCESS && p == 0 && el_envlight_pdf_li(&l, dir) == 0 && rgb[0] == 0 && wi[0] == wi[0],
        "all-black map: init ok, sample_li pdf 0, pdf_li 0, le 0, direction finite");
  el_envlight_free(&l);
  { /* all black, compensated: no division by the zero mean */
    res = make_light(&l, black, 16, 8, NULL, 1, 2);
    el_envlight_sample_li(&l, uu, wi, rgb, &p);
    check(res == EL_SUCCESS && p == 0 && el_envlight_pdf_li(&l, dir) == 0, "all-black map, compensated, alias sampler: pdf 0");
    el_envlight_free(&l);
  }
  /* 1x1, 1xN, Nx1 */
  {
    float one[3] = {2, 3, 4}, col[1 * 7 * 3], row[9 * 1 * 3];
    double s;
    int bad;
    for (k = 0; k < 21; ++k) col[k] = (float)(1 + (k / 3) * (k / 3));
    for (k = 0; k < 27; ++k) row[k] = (float)(1 + (k / 3) % 4);
    res = make_light(&l, one, 1, 1, NULL, 0, 0);
    el_envlight_le(&l, dir, rgb);
    s = grid_integral(&l);
    bad = sample_consistent(&l, 20000, 3, &fin);
    check(res == EL_SUCCESS && rgb[0] == 2 && rgb[2] == 4 && fabs(s - 1) < 1e-2 && bad == 0 && fin,
          "1x1 map: le = texel everywhere, pdf_li integrates to %.5f, samples consistent and finite", s);
    el_envlight_free(&l);
    res = make_light(&l, col, 1, 7, NULL, 0, 1);
    s = grid_integral(&l);
    bad = sample_consistent(&l, 20000, 4, &fin);
    check(res == EL_SUCCESS && fabs(s - 1) < 1e-2 && bad == 0 && fin, "1x7 map (one column): pdf_li integrates to %.5f, samples consistent", s);
    el_envlight_free(&l);
    res = make_light(&l, row, 9, 1, NULL, 0, 2);
    s = grid_integral(&l);
    bad = sample_consistent(&l, 20000, 5, &fin);
    check(res == EL_SUCCESS && fabs(s - 1) < 1e-2 && bad == 0 && fin, "9x1 map (one row): pdf_li integrates to %.5f, samples consistent", s);
    el_envlight_free(&l);
  }
  /* NaN / Inf / negative texels */
  {
    float px[4 * 2 * 3];
    for (k = 0; k < 24; ++k) px[k] = 1.0f;
    px[5 * 3 + 1] = NAN;
    memset(&o, 0, sizeof o);
    res = el_envlight_init(&l, px, 4, 2, 3, &o);
    check(res == EL_ERROR_NAN && l.bad_index == 5 && l.texels == NULL && l.width == 0,
          "NaN texel: EL_ERROR_NAN, light.bad_index names texel %d (want 5), the rest zeroed", l.bad_index);
    px[5 * 3 + 1] = 1.0f; px[2 * 3 + 2] = INFINITY;
    res = el_envlight_init(&l, px, 4, 2, 3, &o);
    check(res == EL_ERROR_INFINITE && l.bad_index == 2, "Inf texel: EL_ERROR_INFINITE naming texel %d (want 2)", l.bad_index);
    px[2 * 3 + 2] = 1.0f; px[7 * 3] = -0.5f;
    res = el_envlight_init(&l, px, 4, 2, 3, &o);
    check(res == EL_ERROR_NEGATIVE && l.bad_index == 7, "negative texel: EL_ERROR_NEGATIVE naming texel %d (want 7)", l.bad_index);
    px[1] = NAN; px[4] = INFINITY;
    o.bad_texels = EL_ENVLIGHT_BAD_TEXELS_ZERO;
    res = el_envlight_init(&l, px, 4, 2, 3, &o);
    if (res == EL_SUCCESS) {
      double s = grid_integral(&l);
      int bad = sample_consistent(&l, 20000, 6, &fin);
      float d2[3];
      double u = 0.125, v = 0.25, d[3];
      ref_uv_to_dir(u, v, d); /* the centre of texel 0 */
      d2[0] = (float)d[0]; d2[1] = (float)d[1]; d2[2] = (float)d[2];
      el_envlight_le(&l, d2, rgb);
      check(bad == 0 && fin && fabs(s - 1) < 1e-2 && fabsf(rgb[1]) < 1e-4f && rgb[0] == rgb[0],
            "BAD_TEXELS_ZERO: NaN, Inf and negative become 0 (texel 0 green %.2g), pdf integrates to %.4f, samples fine", rgb[1], s);
      el_envlight_free(&l);
    } else check(0, "BAD_TEXELS_ZERO: init failed (%s)", el_result_string(res));
    o.bad_texels = 0;
    res = el_envlight_init(&l, px, 0, 2, 3, &o);
    check(res == EL_ERROR_EMPTY && l.bad_index == -1, "0-wide image: EL_ERROR_EMPTY, bad_index -1");
    {
      float bad_rgb[3] = {1.0f, -1.0f, 1.0f};
      res = el_envlight_init_constant(&l, bad_rgb, &o);
      check(res == EL_ERROR_NEGATIVE && l.bad_index == 0, "constant light with a negative component: bad_index 0");
      bad_rgb[1] = 2.0f;
      res = el_envlight_init_constant(&l, bad_rgb, &o);
      check(res == EL_SUCCESS && l.bad_index == -1, "constant light: bad_index -1 on success");
      el_envlight_free(&l);
    }
    res = el_envlight_init(&l, px, 4, -2, 3, &o);
    check(res == EL_ERROR_INVALID_ARGUMENT, "negative height: EL_ERROR_INVALID_ARGUMENT");
    res = el_envlight_init(&l, px, 65536, 65536, 3, &o);
    check(res == EL_ERROR_SIZE_OVERFLOW, "65536x65536 (more texels than an int indexes): EL_ERROR_SIZE_OVERFLOW");
    res = el_envlight_init(&l, NULL, 4, 2, 3, &o);
    check(res == EL_ERROR_INVALID_ARGUMENT, "NULL pixels: EL_ERROR_INVALID_ARGUMENT");
  }
  /* matrices and scales */
  {
    float px[2 * 2 * 3], m[9];
    for (k = 0; k < 12; ++k) px[k] = 1.0f;
    memset(&o, 0, sizeof o);
    identity(o.light_to_world); o.light_to_world[0] = 1.01f;
    res = el_envlight_init(&l, px, 2, 2, 3, &o);
    check(res == EL_ERROR_NOT_ORTHONORMAL, "a scaled matrix: EL_ERROR_NOT_ORTHONORMAL");
    identity(o.light_to_world); o.light_to_world[1] = 0.3f;
    res = el_envlight_init(&l, px, 2, 2, 3, &o);
    check(res == EL_ERROR_NOT_ORTHONORMAL, "a sheared matrix: EL_ERROR_NOT_ORTHONORMAL");
    identity(o.light_to_world); o.light_to_world[4] = NAN;
    res = el_envlight_init(&l, px, 2, 2, 3, &o);
    check(res == EL_ERROR_NAN, "a NaN in the matrix: EL_ERROR_NAN");
    identity(o.light_to_world); o.light_to_world[8] = -1.0f;
    res = el_envlight_init(&l, px, 2, 2, 3, &o);
    check(res == EL_SUCCESS, "a reflection (det -1) is accepted");
    el_envlight_free(&l);
    rotation37(m);
    memcpy(o.light_to_world, m, sizeof m);
    o.light_to_world[0] += 3e-5f; /* float noise of a user's matrix: accepted and re-orthonormalised */
    res = el_envlight_init(&l, px, 2, 2, 3, &o);
    check(res == EL_SUCCESS, "a rotation with 3e-5 of noise is accepted (and re-orthonormalised)");
    el_envlight_free(&l);
    memset(&o, 0, sizeof o);
    o.scale[1] = -1.0f;
    res = el_envlight_init(&l, px, 2, 2, 3, &o);
    check(res == EL_ERROR_NEGATIVE, "negative scale: EL_ERROR_NEGATIVE");
    o.scale[0] = 2.0f; o.scale[1] = 0.0f; o.scale[2] = 0.5f;
    res = el_envlight_init(&l, px, 2, 2, 3, &o);
    el_envlight_le(&l, dir, rgb);
    check(res == EL_SUCCESS && rgb[0] == 2.0f && rgb[1] == 0.0f && rgb[2] == 0.5f, "scale (2, 0, 0.5) multiplies the texels");
    el_envlight_free(&l);
    memset(&o, 0, sizeof o);
    o.scale[0] = 3e38f;
    px[0] = 10.0f;
    res = el_envlight_init(&l, px, 2, 2, 3, &o);
    check(res == EL_ERROR_INFINITE && l.bad_index == 0, "scale * texel overflowing float: EL_ERROR_INFINITE naming texel 0");
  }
  /* u at 0, 1 - ulp, 1 (and beyond); NaN u */
  {
    float px[8 * 4 * 3];
    float us[5] = {0.0f, 0.99999994f, 1.0f, -3.0f, NAN};
    int a, b, ok = 1;
    for (k = 0; k < 96; ++k) px[k] = (float)(1 + k % 13);
    make_light(&l, px, 8, 4, NULL, 0, 0);
    for (a = 0; a < 5; ++a)
      for (b = 0; b < 5; ++b) {
        float q, len;
        uu[0] = us[a]; uu[1] = us[b];
        el_envlight_sample_li(&l, uu, wi, rgb, &p);
        q = el_envlight_pdf_li(&l, wi);
        len = wi[0] * wi[0] + wi[1] * wi[1] + wi[2] * wi[2];
        if (!(p > 0 && p < 1e30f && fabsf(p - q) <= 1e-4f * p && fabsf(len - 1) < 1e-5f && rgb[0] >= 1)) ok = 0;
      }
    check(ok, "u in {0, 1-ulp, 1, -3, NaN}^2: finite unit directions, pdf > 0 and == pdf_li, radiance in range");
    /* directions: NaN, zero, Inf -> 0; non-unit, tiny, huge -> same as unit */
    {
      float d1[3] = {0.3f, -0.5f, 0.2f}, dn[3], nan3[3] = {NAN, 0, 1}, zero[3] = {0, 0, 0}, inf3[3] = {INFINITY, 0, 0};
      float L1[3], L2[3], p1, p2;
      float scales[4] = {3.0f, 1e-30f, 1e30f, 1e-41f};
      int s_ok = 1, si;
      el_envlight_le(&l, d1, L1);
      p1 = el_envlight_pdf_li(&l, d1);
      for (si = 0; si < 4; ++si) {
        for (k = 0; k < 3; ++k) dn[k] = d1[k] * scales[si];
        el_envlight_le(&l, dn, L2);
        p2 = el_envlight_pdf_li(&l, dn);
        if (fabsf(L1[0] - L2[0]) > 1e-4f * L1[0] || fabsf(p1 - p2) > 1e-4f * p1) s_ok = 0;
      }
      check(s_ok, "non-unit directions (x3, x1e-30, x1e30, x1e-41 subnormal) give the unit direction's le and pdf");
      el_envlight_le(&l, nan3, L2);
      p2 = el_envlight_pdf_li(&l, nan3);
      check(L2[0] == 0 && L2[1] == 0 && p2 == 0, "NaN direction: le 0, pdf 0");
      el_envlight_le(&l, zero, L2);
      p2 = el_envlight_pdf_li(&l, zero);
      check(L2[0] == 0 && p2 == 0, "zero direction: le 0, pdf 0");
      el_envlight_le(&l, inf3, L2);
      p2 = el_envlight_pdf_li(&l, inf3);
      check(L2[0] == 0 && p2 == 0, "infinite direction: le 0, pdf 0");
    }
    el_envlight_free(&l);
  }
  /* both poles: finite pdfs, hot pole rows sample consistently, sin(pi) issue */
  {
    enum { W = 32, H = 16 };
    float px[W * H * 3], north[3] = {0, 0, 1}, south[3] = {0, 0, -1}, south2[3];
    double d[3];
    float pn, ps, ps2;
    int bad;
    for (k = 0; k < W * H * 3; ++k) { int y = (k / 3) / W; px[k] = (y == 0 || y == H - 1) ? 1e4f : 1e-2f; }
    make_light(&l, px, W, H, NULL, 0, 0);
    pn = el_envlight_pdf_li(&l, north);
    ps = el_envlight_pdf_li(&l, south);
    ref_uv_to_dir(0.3, 1.0, d); /* float(sin(pi)) direction: x, y = ~1e-16, z = -1 */
    south2[0] = (float)d[0]; south2[1] = (float)d[1]; south2[2] = (float)d[2];
    ps2 = el_envlight_pdf_li(&l, south2);
    bad = sample_consistent(&l, 50000, 9, &fin);
    check(pn > 0 && pn < 1e30f && ps > 0 && ps < 1e30f && ps2 > 0 && ps2 < 1e30f && bad == 0 && fin,
          "poles: pdf_li at the north pole %.3g, south pole %.3g, south via sin(pi) %.3g: finite and > 0; "
          "50000 samples of hot pole rows consistent", pn, ps, ps2);
    el_envlight_free(&l);
  }
  /* constant light */
  {
    float c[3] = {0.5f, 1.0f, 2.0f};
    double s;
    int bad;
    res = el_envlight_init_constant(&l, c, NULL);
    el_envlight_le(&l, dir, rgb);
    s = grid_integral(&l);
    bad = sample_consistent(&l, 20000, 10, &fin);
    uu[0] = 0.2f; uu[1] = 0.9f;
    el_envlight_sample_li(&l, uu, wi, rgb, &p);
    check(res == EL_SUCCESS && rgb[2] == 2.0f && fabs(p - 1 / (4 * PI)) < 1e-7 && fabs(s - 1) < 1e-3 && bad == 0 && fin,
          "constant light: le = colour, uniform sphere pdf 1/4pi, integrates to %.5f", s);
    el_envlight_integral(&l, rgb);
    check(fabs(rgb[1] - 4 * PI) < 1e-5, "constant light: integral = 4 pi L (%.6f)", rgb[1]);
    el_envlight_free(&l);
  }
  el_envlight_free(&l); /* freeing a zeroed light is harmless */
  check(1, "free on a zeroed light is harmless");
}

/* ======================================================================================== */
/* 8. Lazy build from two threads at once                                                    */
/* ======================================================================================== */
typedef struct { el_envlight *l; float out[64]; } thread_arg;
static void *thread_fn(void *p) {
  thread_arg *a = (thread_arg *)p;
  int i;
  for (i = 0; i < 16; ++i) {
    float uu[2], wi[3], rgb[3], pdf;
    uu[0] = (float)i / 16.0f; uu[1] = 0.37f;
    el_envlight_sample_li(a->l, uu, wi, rgb, &pdf);
    a->out[4 * i] = wi[0]; a->out[4 * i + 1] = wi[1]; a->out[4 * i + 2] = wi[2]; a->out[4 * i + 3] = pdf;
  }
  return NULL;
}
/* The default guide sampler returns CDF inversion's points (pbrt's samples), bit for bit. */
/* The guide sampler (sample_li's inline path) returns exactly the CDF sampler's direction, pdf and
 * radiance, with and without the radiance, on city and on a generated map whose rows each hold one
 * 1e5 texel among 1s: the dim bins of every row then crowd a guide cell (more than 64 bins start in
 * it), so the inline path's fallback to the binary search runs too (counted here). */
static void test_guide_equals_cdf(const el_image *city) {
  const int cw = 512, ch = 256;
  float *crowd = (float *)malloc((size_t)cw * ch * 3 * sizeof(float));
  int mi, i;
  for (i = 0; i < cw * ch; ++i) {
    int x = i % cw, y = i / cw;
    float v = x == (y * 37) % cw ? 1e5f : 1.0f;
    crowd[3 * i] = crowd[3 * i + 1] = crowd[3 * i + 2] = v;
  }
  for (mi = 0; mi < 2; ++mi) {
    el_envlight a, b;
    rng r = rng_make(77 + mi);
    int same = 0, same_norgb = 0, crowded = 0, n = 100000;
    const float *px = mi == 0 ? city->pixels : crowd;
    int w = mi == 0 ? city->width : cw, h = mi == 0 ? city->height : ch;
    make_light(&a, px, w, h, NULL, 0, EL_ENVLIGHT_SAMPLER_GUIDE);
    make_light(&b, px, w, h, NULL, 0, EL_ENVLIGHT_SAMPLER_CDF);
    el_envlight_prepare_sampling(&a);
    for (i = 0; i < n; ++i) {
      float uu[2], wa[3], wb[3], La[3], Lb[3], pa, pb, fu, fv, pd;
      int iu, iv;
      uu[0] = rng_f(&r); uu[1] = rng_f(&r);
      el_envlight_sample_li(&a, uu, wa, La, &pa);
      el_envlight_sample_li(&b, uu, wb, Lb, &pb);
      same += memcmp(wa, wb, sizeof wa) == 0 && pa == pb && memcmp(La, Lb, sizeof La) == 0;
      el_envlight_sample_li(&a, uu, wa, NULL, &pa);
      el_envlight_sample_li(&b, uu, wb, NULL, &pb);
      same_norgb += memcmp(wa, wb, sizeof wa) == 0 && pa == pb;
      /* did this u land in a crowded guide cell (marginal or row)? */
      el_distribution2d_sample_bins(&a.dist, uu[0], uu[1], &iu, &iv, &fu, &fv, &pd);
      if ((a.fast.guide_v[(int)(uu[1] * a.fast.gv_scale)] & EL_DISTRIBUTION__GUIDE_CROWDED) ||
          (a.fast.guide_u[(size_t)iv * a.fast.guide_stride + (size_t)(uu[0] * a.fast.gu_scale)] & EL_DISTRIBUTION__GUIDE_CROWDED)) ++crowded;
    }
    check(same == n && same_norgb == n && (mi == 0 || crowded > 100),
          "%s: the default guide sampler returns exactly the CDF sampler's direction, pdf and radiance (%d of %d; without "
          "the radiance %d of %d; %d samples in crowded guide cells)", mi == 0 ? "city" : "crowded rows", same, n, same_norgb, n, crowded);
    el_envlight_free(&a);
    el_envlight_free(&b);
  }
  free(crowd);
}

/* sample_li_n returns exactly what sample_li returns, sample by sample, with and without the radiance:
 * on city (the staged inline path), on a map whose rows crowd guide cells (the fallback inside a
 * batch), with a general rotation and with the CDF sampler (the plain loop), on a constant light, a
 * map too small for the direction tables and an all-black map; before the tables exist (the first call
 * builds them), for n = 37 (not a multiple of the batch of 16), n = 1 and n = 0, with u outside [0, 1)
 * and NaN among ordinary values. */
static void test_sample_li_n(const el_image *city) {
  enum { N = 37 };
  const int cw = 512, ch = 256;
  float *crowd = (float *)malloc((size_t)cw * ch * 3 * sizeof(float)), black[16 * 8 * 3], small[5 * 3 * 3];
  float rot[9] = {0.36f, 0.48f, -0.8f, -0.8f, 0.6f, 0.0f, 0.48f, 0.64f, 0.6f};
  int kind, i;
  for (i = 0; i < cw * ch; ++i) {
    int x = i % cw, y = i / cw;
    crowd[3 * i] = crowd[3 * i + 1] = crowd[3 * i + 2] = x == (y * 37) % cw ? 1e5f : 1.0f;
  }
  memset(black, 0, sizeof black);
  for (i = 0; i < 5 * 3 * 3; ++i) small[i] = (float)(1 + i % 7);
  for (kind = 0; kind < 7; ++kind) {
    el_envlight l;
    rng r = rng_make(1234 + kind);
    int rep, same = 0, n = 0;
    el_result res;
    if (kind == 0) res = make_light(&l, city->pixels, city->width, city->height, NULL, 0, EL_ENVLIGHT_SAMPLER_GUIDE);
    else if (kind == 1) res = make_light(&l, crowd, cw, ch, NULL, 0, EL_ENVLIGHT_SAMPLER_GUIDE);
    else if (kind == 2) res = make_light(&l, city->pixels, city->width, city->height, rot, 0, EL_ENVLIGHT_SAMPLER_GUIDE);
    else if (kind == 3) res = make_light(&l, city->pixels, city->width, city->height, NULL, 0, EL_ENVLIGHT_SAMPLER_CDF);
    else if (kind == 4) { float c[3] = {0.5f, 1.0f, 2.0f}; res = el_envlight_init_constant(&l, c, NULL); }
    else if (kind == 5) res = make_light(&l, small, 5, 3, NULL, 0, 0);
    else res = make_light(&l, black, 16, 8, NULL, 0, 0);
    if (res != EL_SUCCESS) { check(0, "sample_li_n: light %d initialises", kind); continue; }
    for (rep = 0; rep < 400; ++rep) {
      float u[2 * N], wa[3 * N], wb[3 * N], La[3 * N], Lb[3 * N], pa[N], pb[N];
      int m = rep == 1 ? 1 : (rep == 2 ? 0 : N), ok = 1;
      for (i = 0; i < 2 * N; ++i) u[i] = rng_f(&r);
      if (rep % 5 == 3) { u[0] = -0.25f; u[3] = 1.0f; u[4] = 0x1.fffffep-1f; u[7] = 2.0f; u[8] = 0.0f / 0.0f; u[11] = 1e30f; }
      memset(wa, 0x7f, sizeof wa); memset(La, 0x7f, sizeof La); memset(pa, 0x7f, sizeof pa);
      memcpy(wb, wa, sizeof wa); memcpy(Lb, La, sizeof La); memcpy(pb, pa, sizeof pa);
      /* rep 0 runs before any table exists: sample_li_n builds them */
      el_envlight_sample_li_n(&l, m, u, wa, rep % 2 ? NULL : La, pa);
      for (i = 0; i < m; ++i) el_envlight_sample_li(&l, u + 2 * i, wb + 3 * i, rep % 2 ? NULL : Lb + 3 * i, pb + i);
      ok = memcmp(wa, wb, sizeof wa) == 0 && memcmp(pa, pb, sizeof pa) == 0 && memcmp(La, Lb, sizeof La) == 0;
      same += ok; ++n;
    }
    check(same == n, "sample_li_n: light %d (%s): %d of %d batches bit-identical to sample_li", kind,
          kind == 0 ? "city" : kind == 1 ? "crowded rows" : kind == 2 ? "general rotation" : kind == 3 ? "CDF sampler" :
          kind == 4 ? "constant" : kind == 5 ? "5x3 map" : "all black", same, n);
    el_envlight_free(&l);
  }
  free(crowd);
}

static void test_threads(const el_image *city) {
  el_envlight l;
  thread_arg a[2];
  pthread_t t[2];
  int i, same;
  size_t bytes_before;
  make_light(&l, city->pixels, city->width, city->height, NULL, 0, 1);
  bytes_before = el_envlight_sampling_bytes(&l);
  for (i = 0; i < 2; ++i) { a[i].l = &l; pthread_create(&t[i], NULL, thread_fn, &a[i]); }
  for (i = 0; i < 2; ++i) pthread_join(t[i], NULL);
  same = memcmp(a[0].out, a[1].out, sizeof a[0].out) == 0 && a[0].out[3] > 0;
  check(bytes_before == 0 && same && el_envlight_sampling_bytes(&l) > 0,
        "lazy build: nothing before first use; two threads using the light at once get identical samples; then %zu bytes of tables",
        el_envlight_sampling_bytes(&l));
  el_envlight_free(&l);
}

/* sample_li's table path (maps of at least 256x128 bins: angle addition from per-row and per-column
 * tables, short polynomials for the in-bin angle) against libm in double: the direction of the point
 * (bin + fraction) the distribution picked, through the matrix, and its pdf p / (2 pi^2 sin theta).
 * The bin and fraction come from distribution2d's binary searches on the light's own distribution (the
 * CDF sampler's, clamped to the documented 2^-21 margin); 256x128 has the largest in-bin angles (pi/128). */
static void test_table_directions(const el_image *city) {
  static const int sizes[2][2] = {{256, 128}, {0, 0}};
  int si, mi, smp;
  for (smp = 0; smp < 2; ++smp) /* the CDF sampler (the slow path) and the guide (sample_li's inline path) */
  for (si = 0; si < 2; ++si)
    for (mi = 0; mi < 3; ++mi) {
      int w = sizes[si][0], h = sizes[si][1], i, n = 50000;
      float *px = NULL, m[9];
      const float *pix;
      el_envlight l;
      rng r = rng_make(900 + si * 3 + mi);
      double worst_dir = 0, worst_pdf = 0, worst_len = 0;
      if (w == 0) { w = city->width; h = city->height; pix = city->pixels; }
      else {
        px = (float *)malloc((size_t)w * h * 3 * sizeof(float));
        for (i = 0; i < w * h * 3; ++i) px[i] = 0.01f + rng_f(&r) * (i % 97 == 5 ? 1000.0f : 1.0f);
        for (i = 0; i < 3 * w; ++i) { px[i] = 50.0f; px[(size_t)w * h * 3 - 1 - i] = 80.0f; } /* bright pole rows */
        pix = px;
      }
      if (mi == 0) identity(m);
      else if (mi == 1) el_envlight_yup_matrix(m);
      else rotation37(m);
      make_light(&l, pix, w, h, m, 0, smp ? EL_ENVLIGHT_SAMPLER_GUIDE : EL_ENVLIGHT_SAMPLER_CDF);
      el_envlight_prepare_sampling(&l);
      for (i = 0; i < n; ++i) {
        float uu[2], wi[3], p, fu, fv, pb;
        int iu, iv;
        double u, v, ld[3], d[3], dot, len, ref_pdf;
        uu[0] = rng_f(&r); uu[1] = rng_f(&r);
        if (i < 4) { uu[0] = (i & 1) ? 0x1.fffffep-1f : 0.0f; uu[1] = (i & 2) ? 0x1.fffffep-1f : 0.0f; }
        el_envlight_sample_li(&l, uu, wi, NULL, &p);
        el_distribution2d_sample_bins(&l.dist, uu[0], uu[1], &iu, &iv, &fu, &fv, &pb);
        fu = fu < l.u_margin ? l.u_margin : fu > l.u_margin_hi ? l.u_margin_hi : fu;
        fv = fv < l.v_margin ? l.v_margin : fv > l.v_margin_hi ? l.v_margin_hi : fv;
        u = (iu + (double)fu) / l.dist.nu;
        v = (iv + (double)fv) / l.dist.nv;
        ref_uv_to_dir(u, v, ld);
        mat_mul(m, ld, d); /* m is a float matrix: normalise its result too */
        len = sqrt((double)wi[0] * wi[0] + (double)wi[1] * wi[1] + (double)wi[2] * wi[2]);
        dot = (wi[0] * d[0] + wi[1] * d[1] + wi[2] * d[2]) / (len * sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]));
        worst_dir = fmax(worst_dir, sqrt(fmax(0.0, 2 * (1 - dot))));
        worst_len = fmax(worst_len, fabs(len - 1));
        /* a general rotation returns pdf_li(wi) (the world -> light round trip may cross a bin edge) */
        ref_pdf = mi == 2 ? el_envlight_pdf_li(&l, wi) : pb / (2 * PI * PI * sin(PI * v));
        worst_pdf = fmax(worst_pdf, fabs(p - ref_pdf) / ref_pdf);
      }
      /* a general rotation must return pdf_li(wi) itself, bit for bit (so any bin-edge crossing of the
       * round trip cannot make the two differ) */
      check(l.dir_tables == 1 && worst_dir < 5e-7 && worst_len < 1e-6 && (mi == 2 ? worst_pdf == 0 : worst_pdf < 2e-6),
            "sample_li table path, %s sampler, %dx%d, %s: direction within %.2g rad of libm (double), |wi| - 1 within %.2g, "
            "pdf within %.2g relative of p / (2 pi^2 sin theta) (rotation: of pdf_li(wi)), %d samples incl. u corners",
            smp ? "guide" : "CDF", w, h, mi == 0 ? "identity" : mi == 1 ? "y-up" : "rotation", worst_dir, worst_len, worst_pdf, n);
      el_envlight_free(&l);
      free(px);
    }
}

/* pdf_li finds a bin from the direction alone (diamond-angle tables, no atan): samples placed at the
 * very edges of their bins (u at a bin's first and last CDF unit, so the fractions are clamped to the
 * margin) must still be found in their own bin. The map alternates 1 and 16 (times noise) so a
 * neighbouring bin's pdf differs by a large factor; rows and columns next to both poles, the equator,
 * the quadrant boundaries and the seam are all visited. */
static void test_pdf_bin_edges(void) {
  static const int sizes[3][2] = {{4096, 2048}, {1000, 500}, {128, 64}};
  int si, mi;
  for (si = 0; si < 3; ++si)
    for (mi = 0; mi < 2; ++mi) {
      int w = sizes[si][0], h = sizes[si][1], a, b, e0, e1, n = 0, bad = 0;
      int rows[16], cols[24];
      float *px = (float *)malloc((size_t)w * h * 3 * sizeof(float)), m[9];
      el_envlight l;
      rng r = rng_make(4242 + si * 2 + mi);
      size_t i;
      double worst = 0;
      for (i = 0; i < (size_t)w * h; ++i) {
        int x = (int)(i % (size_t)w), y = (int)(i / (size_t)w);
        float v = (((x + y) & 1) ? 16.0f : 1.0f) * (0.9f + 0.2f * rng_f(&r));
        px[3 * i] = px[3 * i + 1] = px[3 * i + 2] = v;
      }
      if (mi == 0) identity(m); else el_envlight_yup_matrix(m);
      make_light(&l, px, w, h, m, 0, EL_ENVLIGHT_SAMPLER_GUIDE);
      el_envlight_prepare_sampling(&l);
      {
        int nu = l.dist.nu, nv = l.dist.nv;
        int rr[16] = {0, 1, 2, nv / 4, nv / 2 - 2, nv / 2 - 1, nv / 2, nv / 2 + 1, 3 * nv / 4, nv - 3, nv - 2, nv - 1, 0, 0, 0, 0};
        int cc[24] = {0, 1, nu / 8, nu / 4 - 1, nu / 4, nu / 2 - 1, nu / 2, nu / 2 + 1, 3 * nu / 4 - 1, 3 * nu / 4, 7 * nu / 8, nu - 2, nu - 1,
                      0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0};
        for (a = 12; a < 16; ++a) rr[a] = (int)(rng_f(&r) * nv);
        for (a = 13; a < 24; ++a) cc[a] = (int)(rng_f(&r) * nu);
        memcpy(rows, rr, sizeof rows);
        memcpy(cols, cc, sizeof cols);
        for (a = 0; a < 16; ++a)
          for (e1 = 0; e1 < 2; ++e1) {
            int j = rows[a];
            uint32_t kv = e1 ? l.dist.marginal[j + 1] - 1 : l.dist.marginal[j];
            const uint32_t *row = l.dist.cdf + (size_t)j * (size_t)(nu + 1);
            if (l.dist.marginal[j + 1] == l.dist.marginal[j]) continue;
            for (b = 0; b < 24; ++b)
              for (e0 = 0; e0 < 2; ++e0) {
                int c = cols[b], iu, iv;
                uint32_t ku = e0 ? row[c + 1] - 1 : row[c];
                float uu[2], wi[3], p, q, fu, fv, pb;
                if (row[c + 1] == row[c]) continue;
                uu[0] = (float)ku / 16777216.0f;
                uu[1] = (float)kv / 16777216.0f;
                el_distribution2d_sample_bins(&l.dist, uu[0], uu[1], &iu, &iv, &fu, &fv, &pb);
                if (iu != c || iv != j) { ++bad; continue; } /* the u chosen do not pick this bin */
                el_envlight_sample_li(&l, uu, wi, NULL, &p);
                q = el_envlight_pdf_li(&l, wi);
                ++n;
                worst = fmax(worst, fabs((double)q / p - 1));
                if (!(fabsf(p - q) <= 1e-5f * p)) ++bad;
              }
          }
      }
      check(bad == 0 && n > 1000, "pdf_li finds the sampled bin for samples at bin edges, %dx%d, %s: %d samples, %d wrong, "
            "worst relative pdf difference %.2g", w, h, mi == 0 ? "identity" : "y-up", n, bad, worst);
      el_envlight_free(&l);
      free(px);
    }
}

/* Finite directions of any magnitude give the results of the same direction at unit scale, under every
 * matrix (before, a general rotation summed products of huge components to +Inf: le 0 and pdf 0). The
 * direction (1, -0.75, 0.5) (largest component 1, every component a normal float down to 2^-125) scaled
 * by 2^k is rescaled exactly, so le and pdf_li must equal the unscaled ones bit for bit for k in
 * [-125, 127]; FLT_MAX times it and the denormal (1e-45, 0, 0) agree to rounding. */
static void test_direction_scale(const el_image *city) {
  int mi, k, c, bad = 0, n = 0, far_bad = 0;
  for (mi = 0; mi < 3; ++mi) {
    el_envlight l;
    float m[9], d0[3] = {1.0f, -0.75f, 0.5f}, L0[3], p0, x0[3] = {1.0f, 0.0f, 0.0f}, Lx[3], px0;
    if (mi == 0) identity(m); else if (mi == 1) el_envlight_yup_matrix(m); else rotation37(m);
    make_light(&l, city->pixels, city->width, city->height, m, 0, 0);
    el_envlight_le(&l, d0, L0);
    p0 = el_envlight_pdf_li(&l, d0);
    el_envlight_le(&l, x0, Lx);
    px0 = el_envlight_pdf_li(&l, x0);
    for (k = -125; k <= 127; ++k) {
      float d[3], L[3], p;
      for (c = 0; c < 3; ++c) d[c] = ldexpf(d0[c], k);
      el_envlight_le(&l, d, L);
      p = el_envlight_pdf_li(&l, d);
      ++n;
      if (L[0] != L0[0] || L[1] != L0[1] || L[2] != L0[2] || p != p0) ++bad;
    }
    {
      float d[3], L[3], p, tiny[3] = {1e-45f, 0.0f, 0.0f};
      for (c = 0; c < 3; ++c) d[c] = d0[c] * FLT_MAX;
      el_envlight_le(&l, d, L);
      p = el_envlight_pdf_li(&l, d);
      for (c = 0; c < 3; ++c) if (!(fabsf(L[c] - L0[c]) <= 1e-3f * L0[c])) ++far_bad;
      if (!(fabsf(p - p0) <= 1e-3f * p0)) ++far_bad;
      el_envlight_le(&l, tiny, L);
      p = el_envlight_pdf_li(&l, tiny);
      if (L[0] != Lx[0] || L[1] != Lx[1] || p != px0) ++far_bad;
      if (!(p0 > 0.0f && L0[1] > 0.0f)) ++far_bad;
    }
    el_envlight_free(&l);
  }
  check(bad == 0, "directions scaled by 2^-125 .. 2^127 give the unscaled le and pdf_li bit for bit (identity, y-up, "
        "rotation): %d of %d differ", bad, n);
  check(far_bad == 0, "FLT_MAX-scaled and denormal directions: le and pdf_li of the unit direction (%d wrong)", far_bad);
}

/* What envlight.h states about pdf_li(sample_li(u).dir), checked exactly: with a signed-permutation
 * matrix (identity, y-up, z-up) it is within 2^-20 relative of the sampled pdf (the same bin value over
 * sin(theta) rounded two ways), with a general rotation equal bit for bit; zero exactly when the sampled
 * pdf is zero. Every sampler, plain and compensated, the direction-table path (city, 1024x512; 256x128)
 * and the small-map path (64x32, and the non-power-of-two importance grid 35x17); u uniform, near both
 * poles, and at the corners. */
static void test_pdf_round_trip(const el_image *city) {
  static const int sizes[4][4] = {{0, 0, 0, 0}, {256, 128, 0, 0}, {64, 32, 0, 0}, {64, 32, 35, 17}};
  int si, mi, smp, comp;
  for (si = 0; si < 4; ++si)
    for (mi = 0; mi < 4; ++mi)
      for (smp = 0; smp < 3; ++smp)
        for (comp = 0; comp < 2; ++comp) {
          int w = sizes[si][0], h = sizes[si][1], i, n = si == 0 ? 60000 : 20000, same = 0, bad = 0;
          float *px = NULL, m[9];
          const float *pix;
          el_envlight l;
          el_envlight_options o;
          rng r = rng_make(4000 + (uint64_t)(si * 64 + mi * 16 + smp * 2 + comp));
          double worst = 0;
          if (w == 0) { w = city->width; h = city->height; pix = city->pixels; }
          else {
            px = (float *)malloc((size_t)w * h * 3 * sizeof(float));
            for (i = 0; i < w * h * 3; ++i) px[i] = 0.01f + rng_f(&r) * (i % 89 == 3 ? 500.0f : 1.0f);
            pix = px;
          }
          if (mi == 0) identity(m);
          else if (mi == 1) el_envlight_yup_matrix(m);
          else if (mi == 2) el_envlight_zup_matrix(m);
          else rotation37(m);
          memset(&o, 0, sizeof o);
          memcpy(o.light_to_world, m, sizeof m);
          o.sampler = smp;
          o.compensated = comp;
          o.importance_width = sizes[si][2];
          o.importance_height = sizes[si][3];
          if (el_envlight_init(&l, pix, w, h, 3, &o) != EL_SUCCESS) { check(0, "round trip: init"); free(px); continue; }
          for (i = 0; i < n; ++i) {
            float uu[2], wi[3], p, q;
            uu[0] = rng_f(&r);
            uu[1] = i % 3 == 0 ? rng_f(&r) * 1e-3f : i % 3 == 1 ? 1.0f - rng_f(&r) * 1e-3f : rng_f(&r);
            if (i < 4) { uu[0] = (i & 1) ? 0x1.fffffep-1f : 0.0f; uu[1] = (i & 2) ? 0x1.fffffep-1f : 0.0f; }
            el_envlight_sample_li(&l, uu, wi, NULL, &p);
            q = el_envlight_pdf_li(&l, wi);
            same += p == q;
            if (!(p > 0.0f)) { bad += q != 0.0f; continue; }
            worst = fmax(worst, fabs((double)q / (double)p - 1.0));
            if (mi == 3 ? q != p : !(fabs((double)q / (double)p - 1.0) <= 0x1p-20)) ++bad;
          }
          if (bad || (si == 0 && smp == 0 && comp == 0))
            check(bad == 0, "pdf_li(sample_li(u).dir) vs pdf, %dx%d (importance %dx%d), %s, %s sampler%s: %d samples, "
                  "%d outside the bound (%s), worst %.2g relative (%.2f * 2^-23), %.0f%% bit for bit",
                  w, h, l.dist.nu, l.dist.nv, mi == 0 ? "identity" : mi == 1 ? "y-up" : mi == 2 ? "z-up" : "rotation",
                  smp == 0 ? "guide" : smp == 1 ? "CDF" : "alias", comp ? ", compensated" : "", n, bad,
                  mi == 3 ? "equal" : "2^-20", worst, worst * 8388608.0, 100.0 * same / n);
          else ++g_pass;
          el_envlight_free(&l);
          free(px);
        }
}

/* ======================================================================================== */
/* 9. Product sampling (sample_li_cos / pdf_li_cos) and the bilinear warp (importance BILINEAR) */
/* ======================================================================================== */
/* A sampler under test: sample_li_cos for a normal (kind 0) or sample_li of a light in importance mode
 * BILINEAR (kind 1), and the pdf the chi-square test compares its samples with (normally the matching
 * pdf function; the negative controls give another one, which the test must reject). */
typedef struct {
  el_envlight *l;
  int kind;               /* 0: sample_li_cos(n); 1: sample_li */
  float n[3];             /* the world normal of kind 0 */
  el_envlight *pdf_light; /* the light whose pdf is compared (normally l) */
  int pdf_kind;           /* 0: pdf_li_cos(pdf_n); 1: pdf_li */
  float pdf_n[3];
} psrc;
static void ps_sample(const psrc *s, const float u[2], float wi[3], float rgb[3], float *pdf) {
  if (s->kind == 0) el_envlight_sample_li_cos(s->l, s->n, u, wi, rgb, pdf);
  else el_envlight_sample_li(s->l, u, wi, rgb, pdf);
}
static float ps_pdf_self(const psrc *s, const float wi[3]) {
  return s->kind == 0 ? el_envlight_pdf_li_cos(s->l, s->n, wi) : el_envlight_pdf_li(s->l, wi);
}
static float ps_pdf_tested(const psrc *s, const float wi[3]) {
  return s->pdf_kind == 0 ? el_envlight_pdf_li_cos(s->pdf_light, s->pdf_n, wi) : el_envlight_pdf_li(s->pdf_light, wi);
}

/* Chi-square over cells of the warp's bilinear patches (patch column i spans the texel centres i and
 * i + 1, patch row r spans vertex rows r and r + 1 at v = 0, 0.5 / h, 1.5 / h, ..., 1): gu x gv cells,
 * gu dividing w. A density bilinear in each patch (the warp's, and the product's, which is the warp
 * times a per-cell constant) integrates exactly by the patch midpoint, so the expected probability of a
 * cell is the sum over its patches of pdf(midpoint) x 2 pi^2 sin(theta) x the patch's (u, v) area.
 * Also: every sample's pdf is finite and > 0 and equals the pdf function at its direction bit for bit,
 * and its radiance equals le(wi) bit for bit. Returns the p-value (1 when the test could not run). */
static int g_prod_tests = 0;
#define PROD_TESTS_PLANNED 31
/* sub x sub midpoints per patch for the expectation (1: exact for a density bilinear in the map's
 * patches; maps over the product's size cap are bilinear in coarser patches: 4 there) */
static int g_chi2_sub = 1;
static double chi2_patches(const char *name, const psrc *s, const float m[9], int w, int h, int gu, int gv, int n,
                           uint64_t seed, int expect_pass) {
  int cells = gu * gv, i, r, pooled = 0, dof, impossible = 0, mismatch = 0, nonfinite = 0, rgb_mismatch = 0, zero = 0;
  double *expect = (double *)calloc((size_t)cells, sizeof(double)), *obs = (double *)calloc((size_t)cells, sizeof(double));
  double chi2, total = 0, pval, alpha = 0.01 / PROD_TESTS_PLANNED;
  rng g = rng_make(seed);
  for (r = 0; r <= h; ++r) {
    double v0 = r == 0 ? 0.0 : (r - 0.5) / h, v1 = r == h ? 1.0 : (r + 0.5) / h, v = 0.5 * (v0 + v1);
    for (i = 0; i < w; ++i) {
      int a, b, ns = g_chi2_sub;
      for (b = 0; b < ns; ++b)
        for (a = 0; a < ns; ++a) {
          double u = (i + 0.5 + (a + 0.5) / ns) / w, vs = ns == 1 ? v : v0 + (v1 - v0) * (b + 0.5) / ns, dl[3], dw[3];
          float fd[3], p;
          if (u >= 1) u -= 1;
          ref_uv_to_dir(u, vs, dl);
          mat_mul(m, dl, dw);
          fd[0] = (float)dw[0]; fd[1] = (float)dw[1]; fd[2] = (float)dw[2];
          p = ps_pdf_tested(s, fd);
          expect[(r * gv / (h + 1)) * gu + i * gu / w] += p * 2 * PI * PI * sin(PI * vs) * (v1 - v0) / w / (ns * ns);
        }
    }
  }
  for (i = 0; i < cells; ++i) total += expect[i];
  for (i = 0; i < n; ++i) {
    float uu[2], wi[3], rgb[3], L[3], p, q;
    double dw[3], dl[3], u, v, x;
    int pi, pr;
    uu[0] = rng_f(&g); uu[1] = rng_f(&g);
    ps_sample(s, uu, wi, rgb, &p);
    if (!(p > 0)) { ++zero; continue; }
    if (!(p < 1e30f) || wi[0] != wi[0]) { ++nonfinite; continue; }
    q = ps_pdf_self(s, wi);
    if (q != p) ++mismatch;
    el_envlight_le(s->l, wi, L);
    dw[0] = wi[0]; dw[1] = wi[1]; dw[2] = wi[2];
    mat_mul_t(m, dw, dl);
    ref_dir_to_uv(dl, &u, &v);
    if (s->kind == 1 && s->l->exact_transform && w >= 256 && h >= 128) {
      /* importance BILINEAR's sample_li under a signed permutation on maps of at least 256 x 128 (its fast
       * path): le at the point's own (u, v), as the other modes (envlight.h: sample_li) */
      if (!rgb_near_le(s->l->texels, w, h, u, v, L, rgb)) ++rgb_mismatch;
    } else if (L[0] != rgb[0] || L[1] != rgb[1] || L[2] != rgb[2]) ++rgb_mismatch;
    x = u * w - 0.5;
    if (x < 0) x += w;
    pi = (int)x; if (pi > w - 1) pi = w - 1;
    pr = (int)(v * h + 0.5); if (pr > h) pr = h;
    obs[(pr * gv / (h + 1)) * gu + pi * gu / w] += 1;
  }
  chi2 = chisq_pooled(expect, obs, (size_t)cells, total, n, &impossible, &pooled);
  dof = pooled - 1;
  pval = dof > 0 ? gammq(0.5 * dof, 0.5 * chi2) : 1.0;
  if (expect_pass) {
    ++g_prod_tests;
    check(pval > alpha && impossible == 0 && fabs(total - 1) < 2e-3 && zero == 0,
          "chi2 %-46s: chi2 = %.1f, %d dof, p = %.3g (> %.2g), pdf integrates to %.5f, %d in zero-pdf cells, %d pdf 0",
          name, chi2, dof, pval, alpha, total, impossible, zero);
    check(mismatch == 0 && nonfinite == 0 && rgb_mismatch == 0,
          "chi2 %-46s: every pdf finite, > 0, == the pdf function bit for bit, radiance == le (%d, %d, %d differ of %d)",
          name, nonfinite, mismatch, rgb_mismatch, n);
  } else {
    /* a negative control: the samples against a wrong pdf must be rejected */
    check(pval < 1e-6 || impossible > 0, "chi2 negative control %-36s: rejected (chi2 = %.1f, %d dof, p = %.2g, %d impossible)",
          name, chi2, dof, pval, impossible);
  }
  free(expect);
  free(obs);
  return pval;
}

/* Inside the patches: a chi-square over the 4 x 4 sub-squares of every patch (the expectation from the pdf
 * at each sub-square's midpoint, exact for a bilinear density; cells expecting fewer than 5 samples
 * pooled). The patch-aligned test above cannot see how samples spread inside a patch; this one does
 * (small maps only: 16 pdf evaluations per patch). */
static void chi2_fractions(const char *name, const psrc *s, const float m[9], int w, int h, int n, uint64_t seed) {
  size_t cells = (size_t)(h + 1) * w * 16, k;
  double *expect = (double *)calloc(cells, sizeof(double)), *obs = (double *)calloc(cells, sizeof(double));
  double chi2, total = 0, pval;
  int i, r, a, b, dof, used = 0;
  rng g = rng_make(seed);
  for (r = 0; r <= h; ++r) {
    double v0 = r == 0 ? 0.0 : (r - 0.5) / h, v1 = r == h ? 1.0 : (r + 0.5) / h;
    for (i = 0; i < w; ++i)
      for (b = 0; b < 4; ++b)
        for (a = 0; a < 4; ++a) {
          double u = (i + 0.5 + (a + 0.5) / 4) / w, v = v0 + (b + 0.5) / 4 * (v1 - v0), dl[3], dw[3];
          float fd[3];
          if (u >= 1) u -= 1;
          ref_uv_to_dir(u, v, dl);
          mat_mul(m, dl, dw);
          fd[0] = (float)dw[0]; fd[1] = (float)dw[1]; fd[2] = (float)dw[2];
          expect[(((size_t)r * w + i) * 4 + b) * 4 + a] = ps_pdf_tested(s, fd) * 2 * PI * PI * sin(PI * v) * (v1 - v0) / w / 16;
        }
  }
  for (k = 0; k < cells; ++k) total += expect[k];
  for (i = 0; i < n; ++i) {
    float uu[2], wi[3], rgb[3], p;
    double dw[3], dl[3], u, v, x, y, fs, ft;
    int pr, pi;
    uu[0] = rng_f(&g); uu[1] = rng_f(&g);
    ps_sample(s, uu, wi, rgb, &p);
    if (!(p > 0)) continue;
    dw[0] = wi[0]; dw[1] = wi[1]; dw[2] = wi[2];
    mat_mul_t(m, dw, dl);
    ref_dir_to_uv(dl, &u, &v);
    x = u * w - 0.5;
    if (x < 0) x += w;
    pi = (int)x; if (pi > w - 1) pi = w - 1;
    fs = x - pi;
    y = v * h + 0.5;
    pr = (int)y; if (pr > h) pr = h;
    ft = pr == 0 ? 2 * v * h : pr == h ? 1 - 2 * (1 - v) * h : y - pr;
    a = (int)(fs * 4); b = (int)(ft * 4);
    a = a < 0 ? 0 : a > 3 ? 3 : a; b = b < 0 ? 0 : b > 3 ? 3 : b;
    obs[(((size_t)pr * w + pi) * 4 + b) * 4 + a] += 1;
  }
  chi2 = chisq_pooled(expect, obs, cells, total, n, NULL, &used); /* zero-pdf cells pooled */
  dof = used - 1;
  pval = dof > 0 ? gammq(0.5 * dof, 0.5 * chi2) : 1.0;
  ++g_prod_tests;
  check(pval > 0.01 / PROD_TESTS_PLANNED && dof > 10, "chi2 inside patches %-30s: 4x4 sub-squares of every patch: chi2 = %.1f, "
        "%d dof, p = %.3g", name, chi2, dof, pval);
  free(expect);
  free(obs);
}

static el_result make_light_imp(el_envlight *l, const float *px, int w, int h, const float m[9], int comp, int imp) {
  return make_light_with(l, px, w, h, m, comp, 0, imp);
}
/* a box-filtered copy of an image at w / f x h / f (keeps the tests fast on the 1024x512 maps) */
static float *shrink(const el_image *im, int f) {
  int w = im->width / f, h = im->height / f, x, y, a, b, c;
  float *px = (float *)calloc((size_t)w * h * 3, sizeof(float));
  for (y = 0; y < h; ++y)
    for (x = 0; x < w; ++x)
      for (b = 0; b < f; ++b)
        for (a = 0; a < f; ++a)
          for (c = 0; c < 3; ++c)
            px[((size_t)y * w + x) * 3 + c] += im->pixels[((size_t)(y * f + b) * im->width + x * f + a) * 3 + c] / (float)(f * f);
  return px;
}
/* light-space normal -> world normal */
static void world_normal(const float m[9], const double nl[3], float n[3]) {
  double nw[3];
  mat_mul(m, nl, nw);
  n[0] = (float)nw[0]; n[1] = (float)nw[1]; n[2] = (float)nw[2];
}

static void chi2_product_case(const char *name, const float *px, int w, int h, int matrix, int comp, const double nl[3],
                              int gu, int gv, int n, uint64_t seed) {
  el_envlight l;
  float m[9];
  psrc s;
  char label[160];
  if (matrix == 1) rotation37(m);
  else if (matrix == 2) el_envlight_yup_matrix(m);
  else if (matrix == 3) el_envlight_zup_matrix(m);
  else identity(m);
  if (make_light_imp(&l, px, w, h, m, comp, 0) != EL_SUCCESS) { check(0, "chi2 %s: init failed", name); return; }
  memset(&s, 0, sizeof s);
  s.l = s.pdf_light = &l;
  world_normal(m, nl, s.n);
  memcpy(s.pdf_n, s.n, sizeof s.n);
  snprintf(label, sizeof label, "cos %s%s%s n=(%.2g,%.2g,%.2g)", name, comp ? " comp" : "",
           matrix == 1 ? " rotated" : matrix == 2 ? " y-up" : matrix == 3 ? " z-up" : "", nl[0], nl[1], nl[2]);
  chi2_patches(label, &s, m, w, h, gu, gv, n, seed, 1);
  el_envlight_free(&l);
}

static void chi2_bilinear_case(const char *name, const float *px, int w, int h, int matrix, int comp, int gu, int gv, int n, uint64_t seed) {
  el_envlight l;
  float m[9];
  psrc s;
  char label[160];
  if (matrix == 1) rotation37(m); else identity(m);
  if (make_light_imp(&l, px, w, h, m, comp, EL_ENVLIGHT_IMPORTANCE_BILINEAR) != EL_SUCCESS) { check(0, "chi2 %s: init failed", name); return; }
  memset(&s, 0, sizeof s);
  s.l = s.pdf_light = &l;
  s.kind = s.pdf_kind = 1;
  snprintf(label, sizeof label, "BILINEAR %s%s%s", name, comp ? " comp" : "", matrix == 1 ? " rotated" : "");
  chi2_patches(label, &s, m, w, h, gu, gv, n, seed, 1);
  el_envlight_free(&l);
}

/* maps for the hard cases, 64 x 32 unless said */
enum { PW = 64, PH = 32 };
static float *map_sun(void) { /* a one-texel sun at 1e12 on a dim sky (1 above, 0.1 below the horizon) */
  float *px = (float *)malloc(PW * PH * 3 * sizeof(float));
  int k;
  for (k = 0; k < PW * PH; ++k) px[3 * k] = px[3 * k + 1] = px[3 * k + 2] = (k / PW) < PH / 2 ? 1.0f : 0.1f;
  px[(9 * PW + 40) * 3] = px[(9 * PW + 40) * 3 + 1] = px[(9 * PW + 40) * 3 + 2] = 1e12f;
  return px;
}
static float *map_black_half(void) { /* the upper half black, the lower half a ramp */
  float *px = (float *)calloc(PW * PH * 3, sizeof(float));
  int k;
  for (k = PW * PH / 2; k < PW * PH; ++k) px[3 * k] = px[3 * k + 1] = px[3 * k + 2] = 1.0f + (float)(k % PW) / 8.0f;
  return px;
}
static float *map_stripes(void) { /* 128 x 64: lit bands of columns, one across the seam (122..5), one at
  40..50, a bright column at 90, black between them (issue 20's sparse normal tables: each cell row keeps
  the span of its cells with weight, which wraps at the seam and holds black cells inside it) */
  float *px = (float *)calloc(128 * 64 * 3, sizeof(float));
  int k;
  for (k = 0; k < 128 * 64; ++k) {
    int x = k % 128, y = k / 128;
    float v = (x >= 122 || x <= 5) ? 2.0f + (float)(y % 7) : (x >= 40 && x <= 50) ? 1.0f : x == 90 ? 300.0f : 0.0f;
    px[3 * k] = px[3 * k + 1] = px[3 * k + 2] = v;
  }
  return px;
}
static float *map_pole_rows(void) { /* bright first and last rows */
  float *px = (float *)malloc(PW * PH * 3 * sizeof(float));
  int k;
  for (k = 0; k < PW * PH; ++k) {
    int y = k / PW, x = k % PW;
    float v = (y == 0 || y == PH - 1) ? 1000.0f * (1.0f + (float)(x % 5)) : 0.25f;
    px[3 * k] = px[3 * k + 1] = px[3 * k + 2] = v;
  }
  return px;
}

static void test_product_chi2(const el_image *studio, const el_image *city) {
  static const double UP[3] = {0, 0, 1}, DOWN[3] = {0, 0, -1}, SEAM[3] = {1, 0, 0}, SIDE[3] = {0, 1, 0};
  static const double TILT[3] = {0.36, -0.48, 0.8}, NEAR_POLE[3] = {1e-4, 0, -1};
  double sun[3];
  float *st = shrink(studio, 4), *ct = shrink(city, 4), *sunmap = map_sun(), *half = map_black_half(), *poles = map_pole_rows();
  float col[1 * 48 * 3], row[64 * 1 * 3];
  int k, n = 100000;
  { /* the direction of the sun texel (9, 40) of map_sun, and the way away from it */
    double u = 40.5 / PW, v = 9.5 / PH;
    ref_uv_to_dir(u, v, sun);
  }
  for (k = 0; k < 48 * 3; ++k) col[k] = (float)(1 + (k / 3) % 7) * ((k / 3) == 20 ? 500.0f : 1.0f);
  for (k = 0; k < 64 * 3; ++k) row[k] = (float)(1 + (k / 3) % 9);
  /* real maps (studio and city box-filtered to 256x128; studio full size once) */
  chi2_product_case("studio 256x128", st, 256, 128, 0, 0, UP, 64, 32, n, 101);
  chi2_product_case("studio 256x128", st, 256, 128, 0, 0, SEAM, 64, 32, n, 102);
  chi2_product_case("studio 256x128", st, 256, 128, 1, 0, TILT, 64, 32, n, 103);
  chi2_product_case("studio 256x128", st, 256, 128, 2, 0, DOWN, 64, 32, n, 104);
  chi2_product_case("city 256x128", ct, 256, 128, 3, 0, SIDE, 64, 32, n, 105);
  chi2_product_case("city 256x128", ct, 256, 128, 1, 1, UP, 64, 32, n, 106);
  chi2_product_case("studio 1024x512", studio->pixels, studio->width, studio->height, 0, 0, TILT, 64, 32, n, 107);
  /* synthetic hard maps */
  chi2_product_case("sun 1e12 64x32", sunmap, PW, PH, 0, 0, DOWN, 32, 16, n, 108);    /* the sun below the horizon */
  chi2_product_case("sun 1e12 64x32", sunmap, PW, PH, 1, 0, NEAR_POLE, 32, 16, n, 109);
  chi2_product_case("black upper half 64x32", half, PW, PH, 0, 0, SEAM, 32, 16, n, 110);
  chi2_product_case("pole rows 64x32", poles, PW, PH, 0, 0, UP, 32, 16, n, 111);
  chi2_product_case("pole rows 64x32", poles, PW, PH, 2, 1, NEAR_POLE, 32, 16, n, 112);
  chi2_product_case("1x48", col, 1, 48, 0, 0, TILT, 1, 24, n, 113);
  { /* spans of cells with weight that wrap at the seam and hold black cells (sparse normal tables) */
    static const double BACK[3] = {-0.6, 0.8, 0.0}, SEAM_UP[3] = {0.6, 0.0, 0.8};
    float *stripes = map_stripes();
    chi2_product_case("stripes 128x64", stripes, 128, 64, 0, 0, SEAM, 64, 32, n, 142);
    chi2_product_case("stripes 128x64", stripes, 128, 64, 1, 0, BACK, 64, 32, n, 143);
    chi2_product_case("stripes 128x64", stripes, 128, 64, 0, 1, SEAM_UP, 64, 32, n, 144);
    free(stripes);
  }
  chi2_product_case("64x1", row, 64, 1, 1, 0, SIDE, 32, 2, n, 114);
  { /* sizes the cells do not divide: 300x100 (64 cells over 300 patch columns), 60x21 (fewer patches than cells) */
    float *odd = (float *)malloc(300 * 100 * 3 * sizeof(float));
    rng g = rng_make(7);
    for (k = 0; k < 300 * 100 * 3; ++k) odd[k] = rng_f(&g) * (k % 97 == 0 ? 50.0f : 1.0f);
    chi2_product_case("random 300x100", odd, 300, 100, 1, 0, TILT, 60, 20, n, 140);
    chi2_product_case("random 60x21", odd, 60, 21, 0, 1, SEAM, 30, 11, n, 141);
    free(odd);
  }
  /* the bilinear warp alone (importance BILINEAR) */
  chi2_bilinear_case("studio 256x128", st, 256, 128, 0, 0, 64, 32, n, 121);
  chi2_bilinear_case("city 256x128", ct, 256, 128, 1, 0, 64, 32, n, 122);
  chi2_bilinear_case("city 256x128", ct, 256, 128, 0, 1, 64, 32, n, 123);
  chi2_bilinear_case("pole rows 64x32", poles, PW, PH, 1, 0, 32, 16, n, 124);
  chi2_bilinear_case("black upper half 64x32", half, PW, PH, 0, 0, 32, 16, n, 125);
  chi2_bilinear_case("1x48", col, 1, 48, 0, 0, 1, 24, n, 126);
  chi2_bilinear_case("64x1", row, 64, 1, 0, 0, 32, 2, n, 127);
  { /* the sun map seen from the sun's side: most samples in the sun's patches (few cells tested) */
    el_envlight l;
    psrc s;
    float m[9];
    identity(m);
    make_light_imp(&l, sunmap, PW, PH, m, 0, 0);
    memset(&s, 0, sizeof s);
    s.l = s.pdf_light = &l;
    world_normal(m, sun, s.n);
    memcpy(s.pdf_n, s.n, sizeof s.n);
    chi2_patches("cos sun 1e12 64x32, facing the sun", &s, m, PW, PH, 32, 16, n, 115, 1);
    el_envlight_free(&l);
  }
  { /* y-up city at 512x256, the sun's side of the normal */
    float m[9], *c2 = shrink(city, 2);
    el_envlight l;
    psrc s;
    el_envlight_yup_matrix(m);
    make_light_imp(&l, c2, 512, 256, m, 0, 0);
    memset(&s, 0, sizeof s);
    s.l = s.pdf_light = &l;
    world_normal(m, TILT, s.n);
    memcpy(s.pdf_n, s.n, sizeof s.n);
    chi2_patches("cos city 512x256 y-up n=(0.36,-0.48,0.8)", &s, m, 512, 256, 64, 32, n, 116, 1);
    /* negative controls (the harness must have the power to see a wrong pdf): the samples of this
     * normal against the pdf of a normal 10 degrees away, against the warp without the cosine (the
     * plain table: a zero normal) and against the light's piecewise-constant pdf_li */
    {
      double t = tan(10.0 * PI / 180.0), nl2[3], len; /* TILT tilted towards (0.8, 0.6, 0), perpendicular to it */
      nl2[0] = TILT[0] + 0.8 * t; nl2[1] = TILT[1] + 0.6 * t; nl2[2] = TILT[2];
      len = sqrt(nl2[0] * nl2[0] + nl2[1] * nl2[1] + nl2[2] * nl2[2]);
      nl2[0] /= len; nl2[1] /= len; nl2[2] /= len;
      world_normal(m, nl2, s.pdf_n);
      chi2_patches("(normal 10 degrees off)", &s, m, 512, 256, 64, 32, n, 117, 0);
      s.pdf_n[0] = s.pdf_n[1] = s.pdf_n[2] = 0.0f;
      chi2_patches("(no cosine: the warp alone)", &s, m, 512, 256, 64, 32, n, 118, 0);
      s.pdf_kind = 1;
      chi2_patches("(the piecewise-constant pdf_li)", &s, m, 512, 256, 64, 32, n, 119, 0);
    }
    el_envlight_free(&l);
    free(c2);
  }
  { /* importance BILINEAR's sample_li against the CELL_AVERAGE light's pdf_li, on city: must be rejected */
    el_envlight lb, lc;
    psrc s;
    float m[9];
    identity(m);
    make_light_imp(&lb, ct, 256, 128, m, 0, EL_ENVLIGHT_IMPORTANCE_BILINEAR);
    make_light_imp(&lc, ct, 256, 128, m, 0, 0);
    memset(&s, 0, sizeof s);
    s.l = &lb; s.kind = 1; s.pdf_light = &lc; s.pdf_kind = 1;
    chi2_patches("(BILINEAR samples vs CELL_AVERAGE pdf)", &s, m, 256, 128, 64, 32, n, 120, 0);
    el_envlight_free(&lb);
    el_envlight_free(&lc);
  }
  { /* inside the patches: the sun map facing the sun (the sun's four patches hold nearly all the mass,
       each steeply linear), pole rows (the linear ramp of the pole patches), city 128x64 (BILINEAR) */
    el_envlight l;
    psrc s;
    float m[9], *c8 = shrink(city, 8);
    identity(m);
    make_light_imp(&l, sunmap, PW, PH, m, 0, 0);
    memset(&s, 0, sizeof s);
    s.l = s.pdf_light = &l;
    world_normal(m, sun, s.n);
    memcpy(s.pdf_n, s.n, sizeof s.n);
    chi2_fractions("cos sun 1e12, facing the sun", &s, m, PW, PH, n, 131);
    el_envlight_free(&l);
    make_light_imp(&l, poles, PW, PH, m, 0, 0);
    s.l = s.pdf_light = &l;
    s.n[0] = s.n[1] = 0; s.n[2] = 1;
    memcpy(s.pdf_n, s.n, sizeof s.n);
    chi2_fractions("cos pole rows, normal up", &s, m, PW, PH, n, 132);
    el_envlight_free(&l);
    make_light_imp(&l, c8, 128, 64, m, 0, EL_ENVLIGHT_IMPORTANCE_BILINEAR);
    s.l = s.pdf_light = &l;
    s.kind = s.pdf_kind = 1;
    chi2_fractions("BILINEAR city 128x64", &s, m, 128, 64, n, 133);
    el_envlight_free(&l);
    free(c8);
  }
  check(g_prod_tests == PROD_TESTS_PLANNED, "chi2 product and warp: %d goodness-of-fit tests, Bonferroni over %d", g_prod_tests, PROD_TESTS_PLANNED);
  free(st); free(ct); free(sunmap); free(half); free(poles);
}

/* Maps over product sampling's size cap (2048 x 1024 vertices) use a coarse vertex grid, each coarse vertex
 * the largest lum of the texels of its 3 x 3 coarse bins: the density must stay > 0 wherever le() > 0
 * (checked around every lit texel of sparse maps, where one texel's reach is all there is: at offsets
 * up to 1.45 texels, 6 normals), and the sampler must draw that density (chi-square). A 4100 x 24 map
 * (coarse in u, 4100 / 2048 not an integer) and a 12 x 1100 map (coarse in v). */
static void test_product_coarse(void) {
  int wa = 4100, ha = 24, wb = 12, hb = 1100, k, mi;
  float *A = (float *)calloc((size_t)wa * ha * 3, sizeof(float)), *B = (float *)calloc((size_t)wb * hb * 3, sizeof(float));
  static const double UP[3] = {0, 0, 1}, TILT[3] = {0.36, -0.48, 0.8};
  static const float offs[7] = {-1.45f, -0.9f, -0.5f, 0.0f, 0.5f, 0.9f, 1.45f};
  for (k = 0; k < 40; ++k) { /* isolated lit texels; one at 1e3 (A), one at 1e12 (B) */
    int x = (k * 397 + 11) % wa, y = (k * 5 + 1) % ha, c;
    for (c = 0; c < 3; ++c) A[((size_t)y * wa + x) * 3 + c] = k == 7 ? 1e3f : 1.0f + (float)k;
    x = (k * 5 + 3) % wb; y = (k * 271 + 2) % hb;
    for (c = 0; c < 3; ++c) B[((size_t)y * wb + x) * 3 + c] = k == 9 ? 1e12f : 2.0f + (float)k;
  }
  for (mi = 0; mi < 2; ++mi) {
    const float *px = mi ? B : A;
    int w = mi ? wb : wa, h = mi ? hb : ha, x, y, bad = 0, tried = 0;
    el_envlight l;
    float m[9];
    identity(m);
    make_light_imp(&l, px, w, h, m, 0, 0);
    for (y = 0; y < h; ++y)
      for (x = 0; x < w; ++x) {
        int a, b, q;
        if (!(px[((size_t)y * w + x) * 3] > 0)) continue;
        for (q = 0; q < 6; ++q) {
          float n[3] = {0, 0, 0};
          n[q / 2] = q % 2 ? -1.0f : 1.0f;
          for (a = 0; a < 7; ++a)
            for (b = 0; b < 7; ++b) {
              double d[3], u = (x + 0.5 + offs[a]) / w, v = (y + 0.5 + offs[b]) / h;
              float fd[3], L[3], p;
              if (v <= 0 || v >= 1) continue;
              if (u < 0) u += 1; else if (u >= 1) u -= 1;
              ref_uv_to_dir(u, v, d);
              fd[0] = (float)d[0]; fd[1] = (float)d[1]; fd[2] = (float)d[2];
              if (n[0] * fd[0] + n[1] * fd[1] + n[2] * fd[2] <= 1e-6f) continue;
              el_envlight_le(&l, fd, L);
              if (!(L[0] + L[1] + L[2] > 0)) continue;
              ++tried;
              p = el_envlight_pdf_li_cos(&l, n, fd);
              if (!(p > 0 && p < 1e30f)) ++bad;
            }
        }
      }
    check(bad == 0 && tried > 0, "coarse product grid, sparse %dx%d: pdf_li_cos > 0 at all %d directions around lit texels "
          "above the surface with le > 0 (%d not)", w, h, tried, bad);
    el_envlight_free(&l);
  }
  g_chi2_sub = 4;
  chi2_product_case("coarse sparse 4100x24", A, wa, ha, 0, 0, TILT, 64, 12, 100000, 150);
  chi2_product_case("coarse sparse 12x1100", B, wb, hb, 1, 0, UP, 12, 64, 100000, 151);
  g_chi2_sub = 1;
  free(A); free(B);
}

/* pdf_li_cos > 0 wherever le > 0 and n.w > 0 (no compensation), over a grid of directions finer than
 * the maps' texels and 12 normals (both poles, the seam and its other side, random ones), on the hard
 * maps. (That it integrates to 1 the chi-square tests check exactly, over the patches.) */
static void test_product_coverage(const el_image *studio) {
  float *sunmap = map_sun(), *half = map_black_half(), *poles = map_pole_rows(), *st = shrink(studio, 8);
  const float *maps[4];
  const char *names[4] = {"sun 1e12", "black half", "pole rows", "studio 128x64"};
  int sizes[4][2] = {{PW, PH}, {PW, PH}, {PW, PH}, {128, 64}}, mi, rot;
  maps[0] = sunmap; maps[1] = half; maps[2] = poles; maps[3] = st;
  for (mi = 0; mi < 4; ++mi)
    for (rot = 0; rot < 2; ++rot) {
      el_envlight l;
      float m[9];
      int k, i, j, bad = 0, tried = 0, NU = 240, NV = 120;
      rng g = rng_make(500 + mi);
      if (rot) rotation37(m); else identity(m);
      make_light_imp(&l, maps[mi], sizes[mi][0], sizes[mi][1], m, 0, 0);
      for (k = 0; k < 12; ++k) { /* normals: the poles, the seam, and random ones */
        float n[3];
        if (k == 0) { n[0] = 0; n[1] = 0; n[2] = 1; }
        else if (k == 1) { n[0] = 0; n[1] = 0; n[2] = -1; }
        else if (k == 2) { n[0] = 1; n[1] = 0; n[2] = 0; }
        else if (k == 3) { n[0] = 1; n[1] = -1e-7f; n[2] = 0; }
        else {
          double z = 1 - 2 * rng_f(&g), r = sqrt(fmax(0.0, 1 - z * z)), ph = 2 * PI * rng_f(&g);
          n[0] = (float)(r * cos(ph)); n[1] = (float)(r * sin(ph)); n[2] = (float)z;
        }
        for (j = 0; j < NV; ++j) {
          double v = (j + 0.5) / NV;
          for (i = 0; i < NU; ++i) {
            double d[3];
            float fd[3], L[3], p;
            ref_uv_to_dir((i + 0.5) / NU, v, d);
            fd[0] = (float)d[0]; fd[1] = (float)d[1]; fd[2] = (float)d[2];
            p = el_envlight_pdf_li_cos(&l, n, fd);
            if (n[0] * fd[0] + n[1] * fd[1] + n[2] * fd[2] > 1e-6f) {
              el_envlight_le(&l, fd, L);
              if (L[0] + L[1] + L[2] > 0) { ++tried; if (!(p > 0 && p < 1e30f)) ++bad; }
            }
          }
        }
      }
      check(bad == 0 && tried > 0, "pdf_li_cos on %s%s, 12 normals (poles, seam): > 0 at all %d grid directions above the "
            "surface with le > 0 (%d not)", names[mi], rot ? " rotated" : "", tried, bad);
      el_envlight_free(&l);
    }
  free(sunmap); free(half); free(poles); free(st);
}

/* Unbiased: irradiance E(n) for the NORMALS above from sample_li_cos alone (and, compensated, with MIS
 * against cosine sampling through pdf_li_cos) against the quadrature of the texels, within 3.5 standard
 * errors; also importance BILINEAR's sample_li. A negative control scales the pdf by 1.03: must fail. */
static void test_product_unbiased(const el_image *studio, const el_image *city) {
  int mapi, mode;
  float *half[2];
  half[0] = shrink(studio, 2); half[1] = shrink(city, 2); /* 512x256: a quarter of the quadrature */
  for (mapi = 0; mapi < 2; ++mapi)
    for (mode = 0; mode < 5; ++mode) {
      image ref;
      el_envlight l;
      float m[9];
      double E[NNORM], worst = 0, worst_bad = 0;
      int k, i, nsamp = 60000, comp = mode == 2, imp = mode == 3 ? EL_ENVLIGHT_IMPORTANCE_BILINEAR : 0;
      if (mode == 1 || mode == 2) rotation37(m); else identity(m);
      ref.px = half[mapi]; ref.w = 512; ref.h = 256;
      quadrature(&ref, 2, NORMALS, NNORM, E);
      make_light_imp(&l, half[mapi], 512, 256, m, comp, imp);
      for (k = 0; k < NNORM; ++k) {
        double nl[3], sum = 0, sum2 = 0, sumb = 0, mean, se, b1[3], b2[3];
        float n[3];
        rng g = rng_make(900 + 10 * mode + k + 100 * mapi);
        nl[0] = NORMALS[k][0]; nl[1] = NORMALS[k][1]; nl[2] = NORMALS[k][2];
        world_normal(m, nl, n);
        { /* a frame around n for the cosine samples */
          double nw[3] = {n[0], n[1], n[2]};
          frame_around(nw, b1, b2);
        }
        for (i = 0; i < nsamp; ++i) {
          float uu[2], wi[3], rgb[3], p;
          double f = 0;
          uu[0] = rng_f(&g); uu[1] = rng_f(&g);
          if (mode == 2 && rng_f(&g) >= 0.5f) { /* MIS: the cosine half */
            double rr = sqrt((double)uu[0]), ph = 2 * PI * uu[1], lx = rr * cos(ph), ly = rr * sin(ph), lz = sqrt(fmax(0.0, 1 - uu[0]));
            float fd[3];
            fd[0] = (float)(lx * b1[0] + ly * b2[0] + lz * n[0]);
            fd[1] = (float)(lx * b1[1] + ly * b2[1] + lz * n[1]);
            fd[2] = (float)(lx * b1[2] + ly * b2[2] + lz * n[2]);
            if (lz > 0) {
              el_envlight_le(&l, fd, rgb);
              f = lum3(rgb[0], rgb[1], rgb[2]) * lz / (0.5 * el_envlight_pdf_li_cos(&l, n, fd) + 0.5 * lz / PI);
            }
          } else {
            if (mode == 3) el_envlight_sample_li(&l, uu, wi, rgb, &p);
            else el_envlight_sample_li_cos(&l, n, uu, wi, rgb, &p);
            if (p > 0) {
              double c = n[0] * wi[0] + n[1] * wi[1] + n[2] * wi[2];
              if (c > 0) f = lum3(rgb[0], rgb[1], rgb[2]) * c / (mode == 2 ? 0.5 * p + 0.5 * c / PI : p);
            }
          }
          sum += f; sum2 += f * f;
          sumb += mode == 2 ? f : f / 1.03; /* the negative control: a pdf 3% too high */
        }
        mean = sum / nsamp;
        se = sqrt(fmax(0.0, sum2 / nsamp - mean * mean) / (nsamp - 1));
        worst = fmax(worst, fabs(mean - E[k]) / se);
        worst_bad = fmax(worst_bad, fabs(sumb / nsamp - E[k]) / se);
      }
      if (mode == 4) { /* the negative control, reported as such */
        check(worst_bad > 4.0, "unbiased negative control (%s 512x256, pdf x 1.03): detected, worst |z| = %.1f", mapi ? "city" : "studio", worst_bad);
      } else {
        check(worst < 3.5, "unbiased %-6s 512x256 %-30s: E at %d normals within 3.5 SE of the quadrature (worst |z| %.2f)",
              mapi ? "city" : "studio", mode == 0 ? "sample_li_cos" : mode == 1 ? "sample_li_cos rotated" :
              mode == 2 ? "compensated, MIS with cosine" : "BILINEAR sample_li", NNORM, worst);
      }
      el_envlight_free(&l);
    }
  free(half[0]);
  free(half[1]);
}

/* Hard inputs: NaN / zero / huge / infinite normals, u at the ends and NaN, zero and NaN directions,
 * black maps, the constant light, 1x1; prepare_product's options; the lazy build from two threads. */
typedef struct { el_envlight *l; float out[64]; } prod_thread_arg;
static void *prod_thread_fn(void *p) {
  prod_thread_arg *a = (prod_thread_arg *)p;
  int i;
  for (i = 0; i < 16; ++i) {
    float uu[2], wi[3], rgb[3], pdf, n[3] = {0.3f, 0.4f, 0.5f};
    uu[0] = (float)i / 16.0f; uu[1] = 0.37f;
    el_envlight_sample_li_cos(a->l, n, uu, wi, rgb, &pdf);
    a->out[4 * i] = wi[0]; a->out[4 * i + 1] = wi[1]; a->out[4 * i + 2] = wi[2]; a->out[4 * i + 3] = pdf;
  }
  return NULL;
}
/* Texels at the ends of the float range (a denormal 1e-44, 1e-38 near FLT_MIN, a 1e30 sun, 3e38 near
 * FLT_MAX) on a black map: product sampling stores its vertex grid in bfloat16 rounded up (issue 20), so
 * every lit texel must keep a density > 0 towards it (a truncation would drop the denormal), and samples
 * must keep their pdf == pdf_li_cos. */
static void test_product_tiny_values(void) {
  static const int TX[4][2] = {{10, 5}, {30, 20}, {50, 12}, {20, 27}};
  static const float TV[4] = {1e-44f, 1e-38f, 1e30f, 3e38f};
  float *px = (float *)calloc(PW * PH * 3, sizeof(float)), m[9];
  el_envlight l;
  int k, c, ok = 1, rt = 1;
  for (k = 0; k < 4; ++k)
    for (c = 0; c < 3; ++c) px[(TX[k][1] * PW + TX[k][0]) * 3 + c] = TV[k];
  identity(m);
  if (make_light_imp(&l, px, PW, PH, m, 0, 0) != EL_SUCCESS) { check(0, "tiny values: init failed"); free(px); return; }
  for (k = 0; k < 4; ++k) {
    double d[3];
    float n[3], wi[3], rgb[3], p, q;
    int j;
    ref_uv_to_dir((TX[k][0] + 0.5) / PW, (TX[k][1] + 0.5) / PH, d);
    for (c = 0; c < 3; ++c) n[c] = (float)d[c];
    if (!(el_envlight_pdf_li_cos(&l, n, n) > 0.0f)) ok = 0; /* towards the texel, from a surface facing it */
    for (j = 0; j < 64; ++j) {
      float uu[2];
      uu[0] = ((float)j + 0.5f) / 64.0f; uu[1] = (float)((j * 37) % 64 + 0.5f) / 64.0f;
      el_envlight_sample_li_cos(&l, n, uu, wi, rgb, &p);
      q = el_envlight_pdf_li_cos(&l, n, wi);
      if (!(p > 0.0f) || p != q || !(p < INFINITY)) rt = 0;
    }
  }
  check(ok, "product sampling, texels of 1e-44 (denormal), 1e-38, 1e30 and 3e38 on a black map: pdf_li_cos > 0 towards each");
  check(rt, "product sampling on that map: 256 samples with pdf > 0, finite, == pdf_li_cos bit for bit");
  el_envlight_free(&l);
  free(px);
}

static void test_product_hard(const el_image *city) {
  el_envlight l;
  float *sunmap = map_sun();
  float wi[3], rgb[3], p, uu[2] = {0.3f, 0.6f}, dir[3] = {0.2f, -0.4f, 0.5f}, n[3] = {0, 0, 1};
  int k, ok;
  { /* normals and directions that are not unit: scaled ones (2^-149 .. FLT_MAX) give the unit ones' results,
     * under the identity and under a general rotation (whose sums of huge products would overflow if the
     * vectors were not scaled in world space first); zero, NaN, Inf normals: no sample (pdf 0) */
    float nu[3] = {0.5f, -0.75f, 0.25f}, ns[3], zero[3] = {0, 0, 0}, nan3[3] = {NAN, 0, 1}, inf3[3] = {INFINITY, 0, 0};
    float scales[5] = {4.0f, 1e-30f, 1e30f, 1e-41f, 3.4e38f}, dscales[5] = {4.0f, 0x1p-100f, 0x1p100f, 0x1p126f, 0x1p-120f};
    float p0, pz, pn, pi, ds[3], m[9];
    int mi;
    for (mi = 0; mi < 2; ++mi) {
      if (mi == 0) identity(m); else rotation37(m);
      make_light_imp(&l, sunmap, PW, PH, m, 0, 0);
      p0 = el_envlight_pdf_li_cos(&l, nu, dir);
      ok = p0 > 0;
      for (k = 0; k < 5; ++k) {
        int c;
        for (c = 0; c < 3; ++c) { ns[c] = nu[c] * scales[k]; ds[c] = dir[c] * dscales[k]; }
        if (el_envlight_pdf_li_cos(&l, ns, dir) != p0 || el_envlight_pdf_li_cos(&l, nu, ds) != p0) ok = 0;
      }
      check(ok, "pdf_li_cos (%s): a normal scaled by 4, 1e-30, 1e30, 1e-41 (subnormal), 3.4e38 and a direction by 4, 2^-100, "
                "2^100, 2^126, 2^-120 give the unit ones' pdf", mi ? "general rotation" : "identity");
      pz = el_envlight_pdf_li_cos(&l, zero, dir); pn = el_envlight_pdf_li_cos(&l, nan3, dir); pi = el_envlight_pdf_li_cos(&l, inf3, dir);
      check(pz == 0 && pn == 0 && pi == 0, "zero, NaN and infinite normals: pdf_li_cos 0 (%.4g, %.4g, %.4g) (%s)", pz, pn, pi,
            mi ? "general rotation" : "identity");
      el_envlight_sample_li_cos(&l, nan3, uu, wi, rgb, &p);
      check(p == 0 && wi[0] == wi[0] && wi[1] == wi[1] && wi[2] == wi[2] && rgb[0] == 0 && rgb[1] == 0 && rgb[2] == 0,
            "sample_li_cos with a NaN normal: no sample (pdf 0, radiance 0, a finite direction)");
      el_envlight_free(&l);
    }
    make_light_imp(&l, sunmap, PW, PH, NULL, 0, 0);
  }
  { /* u at the ends, NaN; directions zero / NaN / huge */
    float us[5] = {0.0f, 0.99999994f, 1.0f, -3.0f, NAN}, z3[3] = {0, 0, 0}, nan3[3] = {NAN, 1, 0}, big[3];
    int a, b;
    ok = 1;
    for (a = 0; a < 5; ++a)
      for (b = 0; b < 5; ++b) {
        float q, len;
        uu[0] = us[a]; uu[1] = us[b];
        el_envlight_sample_li_cos(&l, n, uu, wi, rgb, &p);
        q = el_envlight_pdf_li_cos(&l, n, wi);
        len = wi[0] * wi[0] + wi[1] * wi[1] + wi[2] * wi[2];
        if (!(p > 0 && p < 1e30f && p == q && fabsf(len - 1) < 1e-5f && rgb[0] == rgb[0])) ok = 0;
      }
    check(ok, "sample_li_cos: u in {0, 1-ulp, 1, -3, NaN}^2 gives finite unit directions with pdf > 0 == pdf_li_cos");
    for (k = 0; k < 3; ++k) big[k] = dir[k] * 1e30f;
    check(el_envlight_pdf_li_cos(&l, n, z3) == 0 && el_envlight_pdf_li_cos(&l, n, nan3) == 0 &&
          el_envlight_pdf_li_cos(&l, n, big) == el_envlight_pdf_li_cos(&l, n, dir),
          "pdf_li_cos: zero and NaN directions give 0, a huge one the unit direction's pdf");
    el_envlight_free(&l);
  }
  { /* the warp is monotone: for a fixed u0, theta never decreases as u1 grows from 0 (tiny steps near 0
     * and 1, where the pole rows' linear ramps start from 0), for the warp alone and with a normal */
    int mode, bad = 0, tried = 0;
    float *poles = map_pole_rows();
    for (mode = 0; mode < 2; ++mode) {
      el_envlight lm;
      float u0s[3] = {0.0f, 0.37f, 0.99999994f};
      int a;
      make_light_imp(&lm, poles, PW, PH, NULL, 0, mode ? 0 : EL_ENVLIGHT_IMPORTANCE_BILINEAR);
      for (a = 0; a < 3; ++a) {
        double prev = -1;
        for (k = 0; k <= 2000; ++k) {
          float u1 = k == 0 ? 0.0f : k < 100 ? (float)k * 1e-7f : k > 1900 ? 1.0f - (float)(2000 - k) * 6e-8f : (float)k / 2000.0f, th;
          uu[0] = u0s[a]; uu[1] = u1 < 0.99999994f ? u1 : 0.99999994f;
          if (mode) el_envlight_sample_li_cos(&lm, n, uu, wi, rgb, &p);
          else el_envlight_sample_li(&lm, uu, wi, rgb, &p);
          th = (float)atan2(sqrt((double)wi[0] * wi[0] + (double)wi[1] * wi[1]), (double)wi[2]); /* accurate at the poles */
          ++tried;
          if ((double)th < prev - 1e-6) ++bad;
          prev = th;
        }
      }
      el_envlight_free(&lm);
    }
    check(bad == 0, "the warp is monotone in u1 (theta never decreases), BILINEAR and sample_li_cos, from u1 = 0: %d of %d steps back", bad, tried);
    free(poles);
  }
  { /* black maps: pdf 0 everywhere, samples with pdf 0; a map black where the normal looks */
    static float black[16 * 8 * 3];
    float *half = map_black_half(), up[3] = {0, 0, 1};
    el_result r1 = make_light_imp(&l, black, 16, 8, NULL, 0, 0);
    el_envlight_sample_li_cos(&l, n, uu, wi, rgb, &p);
    check(r1 == EL_SUCCESS && p == 0 && rgb[0] == 0 && wi[0] == wi[0] && el_envlight_pdf_li_cos(&l, n, dir) == 0,
          "all-black map: sample_li_cos pdf 0, radiance 0, direction finite; pdf_li_cos 0");
    el_envlight_free(&l);
    make_light_imp(&l, black, 16, 8, NULL, 1, EL_ENVLIGHT_IMPORTANCE_BILINEAR);
    el_envlight_sample_li(&l, uu, wi, rgb, &p);
    check(p == 0 && el_envlight_pdf_li(&l, dir) == 0, "all-black map, BILINEAR, compensated: sample_li pdf 0, pdf_li 0");
    el_envlight_free(&l);
    /* the upper half black and the normal straight up: nothing above the surface emits except the
     * bilinear spill of the lower half's first row, 1.5 texels above the horizon at most */
    make_light_imp(&l, half, PW, PH, NULL, 0, 0);
    el_envlight_sample_li_cos(&l, up, uu, wi, rgb, &p);
    check(p > 0 && p == el_envlight_pdf_li_cos(&l, up, wi), "black upper half, normal up: a sample with pdf %.3g (the horizon's cells)", p);
    el_envlight_free(&l);
    free(half);
  }
  { /* the constant light: exactly cosine-weighted sampling */
    float c[3] = {1, 2, 3}, zero3[3] = {0, 0, 0}, nn[3] = {0.6f, 0, 0.8f}, nan3[3] = {NAN, 0, 0};
    double sum = 0;
    int below = 0, bad = 0;
    rng g = rng_make(77);
    el_envlight_init_constant(&l, c, NULL);
    for (k = 0; k < 20000; ++k) {
      float cth;
      uu[0] = rng_f(&g); uu[1] = rng_f(&g);
      el_envlight_sample_li_cos(&l, nn, uu, wi, rgb, &p);
      cth = nn[0] * wi[0] + nn[1] * wi[1] + nn[2] * wi[2];
      if (p > 0 && cth <= 0) ++below;
      if (p > 0 && (fabsf(p - cth / (float)PI) > 1e-5f || p != el_envlight_pdf_li_cos(&l, nn, wi) || rgb[1] != 2)) ++bad;
      if (p > 0) sum += lum3(rgb[0], rgb[1], rgb[2]) * cth / p;
    }
    sum /= 20000;
    check(below == 0 && bad == 0 && fabs(sum - PI * lum3(1, 2, 3)) < 1e-3 * sum,
          "constant light: sample_li_cos is cosine sampling (pdf cos/pi, %d below, %d wrong), E = pi L exactly (%.6g)", below, bad, sum);
    el_envlight_sample_li_cos(&l, nan3, uu, wi, rgb, &p);
    check(fabsf(p - 0.0795774715f) < 1e-7f && el_envlight_pdf_li_cos(&l, nan3, wi) == p, "constant light, NaN normal: uniform sphere, pdf 1/4pi");
    el_envlight_free(&l);
    el_envlight_init_constant(&l, zero3, NULL);
    el_envlight_sample_li_cos(&l, nn, uu, wi, rgb, &p);
    check(p == 0 && el_envlight_pdf_li_cos(&l, nn, dir) == 0, "black constant light: pdf 0");
    el_envlight_free(&l);
  }
  { /* 1x1: the warp is constant, the product is the cells' bound */
    float one[3] = {2, 3, 4};
    int bad;
    make_light_imp(&l, one, 1, 1, NULL, 0, 0);
    bad = 0;
    for (k = 0; k < 1000; ++k) {
      uu[0] = (k % 37) / 37.0f; uu[1] = (float)k / 1000.0f;
      el_envlight_sample_li_cos(&l, n, uu, wi, rgb, &p);
      if (!(p > 0 && p == el_envlight_pdf_li_cos(&l, n, wi) && rgb[0] == 2)) ++bad;
    }
    check(bad == 0, "1x1 map: samples finite, pdf == pdf_li_cos, radiance the texel (%d bad)", bad);
    el_envlight_free(&l);
  }
  { /* prepare_product: options */
    el_envlight_product_options po;
    size_t b0, b1;
    make_light_imp(&l, city->pixels, city->width, city->height, NULL, 0, 0);
    memset(&po, 0, sizeof po);
    po.cells_u = 16; /* cells_v missing */
    check(el_envlight_prepare_product(&l, &po) == EL_ERROR_INVALID_ARGUMENT, "prepare_product: cells_u without cells_v is an error");
    po.cells_v = 300;
    check(el_envlight_prepare_product(&l, &po) == EL_ERROR_INVALID_ARGUMENT, "prepare_product: 300 cells is an error");
    b0 = el_envlight_product_bytes(&l);
    po.cells_u = 16; po.cells_v = 8; po.normal_bins = 8;
    check(el_envlight_prepare_product(&l, &po) == EL_SUCCESS, "prepare_product: 16x8 cells, 8x8 normal bins");
    b1 = el_envlight_product_bytes(&l);
    po.normal_bins = 16;
    check(b0 == 0 && b1 > 0 && el_envlight_prepare_product(&l, &po) == EL_ERROR_INVALID_ARGUMENT &&
          el_envlight_prepare_product(&l, NULL) == EL_SUCCESS && el_envlight_sampling_bytes(&l) == 0,
          "prepare_product: no tables before, %zu bytes after (the light's own sampling tables not built); other sizes later: an error", b1);
    el_envlight_free(&l);
  }
  { /* the lazy build from two threads at once */
    prod_thread_arg a[2];
    pthread_t t[2];
    int same;
    make_light_imp(&l, city->pixels, city->width, city->height, NULL, 0, 0);
    for (k = 0; k < 2; ++k) { a[k].l = &l; pthread_create(&t[k], NULL, prod_thread_fn, &a[k]); }
    for (k = 0; k < 2; ++k) pthread_join(t[k], NULL);
    same = memcmp(a[0].out, a[1].out, sizeof a[0].out) == 0 && a[0].out[3] > 0;
    check(same && el_envlight_product_bytes(&l) > 0, "product tables: two threads' first use at once gives identical samples");
    el_envlight_free(&l);
  }
  free(sunmap);
}

int main(void) {
  el_image studio, city;
  memset(&studio, 0, sizeof studio);
  memset(&city, 0, sizeof city);
  if (load_map("studio.hdr", &studio) || load_map("city.hdr", &city)) {
    check(0, "load the test maps from %s/envmaps", EL_TEST_DATA_DIR);
    printf("test_envlight: %d passed, %d failed\n", g_pass, g_fail);
    return 1;
  }
  test_orientation();
  test_mapping_accuracy();
  test_table_directions(&city);
  test_pdf_bin_edges();
  test_pdf_round_trip(&city);
  test_direction_scale(&city);
  test_le(&studio);
  test_chi2(&studio, &city);
  test_importance_map();
  test_pdf_integral(&studio);
  test_unbiased(&studio, &city);
  test_power(&studio);
  test_preprocess();
  test_hard_cases();
  test_pole_rounding();
  test_guide_equals_cdf(&city);
  test_sample_li_n(&city);
  test_threads(&city);
  test_product_chi2(&studio, &city);
  test_product_coverage(&studio);
  test_product_coarse();
  test_product_unbiased(&studio, &city);
  test_product_hard(&city);
  test_product_tiny_values();
  el_image_free(&studio);
  el_image_free(&city);
  printf("test_envlight: %d passed, %d failed\n", g_pass, g_fail);
  return g_fail ? 1 : 0;
}
