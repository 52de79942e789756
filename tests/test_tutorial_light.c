/* test_tutorial_light.c: the course's plain port of pbrt-v3's InfiniteAreaLight
 * (examples/pbrtv3/infinite.h, chapter 3) against envlight.h, on the same map (data/envmaps/city.hdr)
 * and the same light-to-world matrix (pbrt's RotateX(-90) * RotateZ(120), as the chapter's example).
 *
 * Where the two agree, and within what (each bound is derived here, none taken from either's output):
 *  1. Le: the same bilinear lookup. The library finds (u, v) with an atan polynomial (2.5e-7 rad) and
 *     its own copy of the rotation; the two light-space directions differ by at most 5e-7, which moves
 *     phi by up to 5e-7 / sin(theta). The value can move by that distance (in texels) times the
 *     largest nearby texel, twice (u and v), plus float rounding. Within half a texel of a pole the
 *     two differ on purpose (below, 2).
 *  2. The pole fix. pbrt's MIPMap wraps v as it wraps u (Repeat), so the north pole's lookup blends
 *     the south pole's row in (pbrt-v3 issue #63); the library clamps v. On an 8 x 4 map the north
 *     pole reads 504.5 in the port and 4.5 in the library, by hand. And at the south pole pbrt's
 *     sin(acos(-1)) is sinf(3.1415927f) = -8.7e-8, not 0, so its guard never fires and Pdf_Li is
 *     negative; the library's is finite and >= 0.
 *  3. The importance map. pbrt samples the bilinear map at twice the resolution, at the points
 *     i +- 1/4, j +- 1/4 of texel (i, j). Per axis their bilinear weights add up to 2 x (1/8, 3/4,
 *     1/8), which are exactly the weights of the average of the bilinear map over the texel: the
 *     library's default importance (the cell average, at the map's own resolution). So the port's
 *     four values of a texel, each divided by its own sin theta, add up to 4 x the cell average with
 *     Repeat in v (checked to float rounding), and the library's probability of each texel is the
 *     cell average with Clamp in v, times sin theta, normalised, to within its integer CDF's bound
 *     (2 + m q) 2^-24 per dimension (distribution2d.h; m bins, share q).
 *  4. Sampling (the library with EL_ENVLIGHT_IMPORTANCE_PBRT_V3: pbrt's own bins). For the same u, the
 *     library's direction, put back through pbrt's marginal and conditional CDFs, gives u back to
 *     within the largest gap between the two CDFs, plus the direction's error and the library's in-bin
 *     margin (2^-21) times the CDF's slope. Its pdf is pbrt's Pdf_Li of that direction to within the
 *     integer-CDF bound of the bin, the normalisation shift of the two pole rows (where the library
 *     clamps) and pbrt's own sinf(acosf(z)) rounding near the poles.
 *  5. Irradiance: both estimators are unbiased for their own Le, which differ only within half a
 *     texel of the poles: the two estimates agree within 4 standard errors plus that cap's share.
 */
#define EL_IMPLEMENTATION
#include "envlight.h"
#include "image_io.h"
#include "../examples/pbrtv3/infinite.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifndef EL_TEST_DATA_DIR
#define EL_TEST_DATA_DIR "data"
#endif
#define UNIT (1.0 / 16777216.0) /* 2^-24 */
#define PI_D 3.14159265358979323846

#define TUTORIAL_RNG_SEED 77u
#include "tutorial_check.h" /* check, checkf, frand */

static double lum_d(const float *rgb) { return 0.212671 * rgb[0] + 0.715160 * rgb[1] + 0.072169 * rgb[2]; }

/* world -> light space in double, with the port's WorldToLight; then (u, v) in [0, 1] */
static void light_uv(const pbrt_InfiniteAreaLight *p, const float w[3], double *u, double *v, double *sin_theta) {
  double l[3], r;
  int i;
  for (i = 0; i < 3; ++i)
    l[i] = (double)p->WorldToLight.m[3 * i] * w[0] + (double)p->WorldToLight.m[3 * i + 1] * w[1] +
           (double)p->WorldToLight.m[3 * i + 2] * w[2];
  r = sqrt(l[0] * l[0] + l[1] * l[1] + l[2] * l[2]);
  *u = atan2(l[1], l[0]) / (2 * PI_D);
  if (*u < 0) *u += 1;
  *v = acos(fmax(-1.0, fmin(1.0, l[2] / r))) / PI_D;
  *sin_theta = sqrt(l[0] * l[0] + l[1] * l[1]) / r;
}

/* pbrt's CDF at x (linear within a bin) and its slope, in double */
static double cdf_at(const pbrt_Distribution1D *d, double x, double *slope) {
  double t = x * d->n;
  int o = (int)t;
  if (o >= d->n) o = d->n - 1;
  if (o < 0) o = 0;
  *slope = ((double)d->cdf[o + 1] - d->cdf[o]) * d->n;
  return d->cdf[o] + (t - o) * ((double)d->cdf[o + 1] - d->cdf[o]);
}
static double cdf_gap(const pbrt_Distribution1D *p, const uint32_t *c) {
  double D = 0;
  int i;
  for (i = 0; i <= p->n; ++i) D = fmax(D, fabs(c[i] * UNIT - p->cdf[i]));
  return D;
}

/* the luminance of texel (x, y), x wrapped; y wrapped (repeat) or clamped */
static double texel_lum(const pbrt_Lmap *m, int x, int y, int repeat) {
  x = ((x % m->width) + m->width) % m->width;
  if (repeat) y = ((y % m->height) + m->height) % m->height;
  else y = y < 0 ? 0 : y >= m->height ? m->height - 1 : y;
  return lum_d(m->texels + 3 * ((size_t)y * m->width + x));
}
/* the average of the bilinear map's luminance over texel (i, j): weights 1/8, 3/4, 1/8 per axis */
static double cell_average(const pbrt_Lmap *m, int i, int j, int repeat) {
  static const double w[3] = {0.125, 0.75, 0.125};
  double s = 0;
  int a, b;
  for (b = 0; b < 3; ++b)
    for (a = 0; a < 3; ++a) s += w[a] * w[b] * texel_lum(m, i - 1 + a, j - 1 + b, repeat);
  return s;
}

static pbrt_InfiniteAreaLight g_port;
static el_envlight g_lib, g_lib_pbrt;

/* 1. Le */
static void test_le(void) {
  int k, ok = 1, n = 0;
  double worst = 0;
  for (k = 0; k < 100000; ++k) {
    float w[3], a[3], b[3], z = 1 - 2 * frand(), ph = 2 * pbrt_Pi * frand(), r = sqrtf(fmaxf(0, 1 - z * z));
    double u, v, st, ds, dt, big = 0, bound;
    int c, s0, t0, x, y;
    w[0] = r * cosf(ph);
    w[1] = r * sinf(ph);
    w[2] = z;
    light_uv(&g_port, w, &u, &v, &st);
    if (v * g_port.Lmap.height < 0.5 || v * g_port.Lmap.height > g_port.Lmap.height - 0.5) continue; /* 2. */
    pbrt_InfiniteAreaLight_Le(&g_port, w, a);
    el_envlight_le(&g_lib, w, b);
    s0 = (int)floor(u * g_port.Lmap.width - 0.5);
    t0 = (int)floor(v * g_port.Lmap.height - 0.5);
    for (y = t0 - 1; y <= t0 + 2; ++y)
      for (x = s0 - 1; x <= s0 + 2; ++x)
        for (c = 0; c < 3; ++c) {
          int yy = y < 0 ? 0 : y >= g_port.Lmap.height ? g_port.Lmap.height - 1 : y;
          int xx = ((x % g_port.Lmap.width) + g_port.Lmap.width) % g_port.Lmap.width;
          big = fmax(big, g_port.Lmap.texels[3 * ((size_t)yy * g_port.Lmap.width + xx) + c]);
        }
    ds = (5e-7 / st + 2.5e-7) / (2 * PI_D) * g_port.Lmap.width;
    dt = (5e-7 + 2.5e-7) / PI_D * g_port.Lmap.height;
    bound = 2 * (ds + dt) * big + 2e-6 * big + 1e-30;
    for (c = 0; c < 3; ++c) {
      if (!(fabs(a[c] - b[c]) <= bound)) ok = 0;
      worst = fmax(worst, fabs(a[c] - b[c]) / bound);
    }
    ++n;
  }
  checkf(ok, "Le: port and library agree on %.0f random directions away from the poles (worst %.2f of the bound)", n, worst);
}

/* 2. the poles: an 8 x 4 map whose top row is 1..8 and bottom row 1001..1008 (identity matrix) */
static void test_poles(void) {
  float tex[8 * 4 * 3], north[3] = {0, 0, 1}, south[3] = {0, 0, -1}, a[3], b[3], p_port, p_lib;
  int res[2] = {8, 4}, x, y, c;
  pbrt_InfiniteAreaLight port;
  el_envlight lib;
  pbrt_Transform id = pbrt_RotateZ(0);
  for (y = 0; y < 4; ++y)
    for (x = 0; x < 8; ++x)
      for (c = 0; c < 3; ++c) tex[3 * (y * 8 + x) + c] = y == 0 ? (float)(x + 1) : y == 3 ? (float)(1000 + x + 1) : 10.0f;
  check(pbrt_InfiniteAreaLight_init(&port, &id, tex, res) == 0 &&
            el_envlight_init(&lib, tex, 8, 4, 3, NULL) == EL_SUCCESS,
        "8 x 4 pole map: both build");
  pbrt_InfiniteAreaLight_Le(&port, north, a);
  el_envlight_le(&lib, north, b);
  /* port: s = -0.5, t = -0.5: the four texels (7, 3), (7, 0), (0, 3), (0, 0) with weight 1/4 each
   * (Repeat in v brings row 3 in); library: t clamped to row 0, (8 + 1) / 2 */
  checkf(a[0] == 504.5f && fabs(b[0] - 4.5) < 1e-5,
         "north pole of the 8 x 4 map: port %.6g (Repeat in v: (1008 + 8 + 1001 + 1) / 4 = 504.5), library %.6g (Clamp: 4.5)", a[0], b[0]);
  pbrt_InfiniteAreaLight_free(&port);
  el_envlight_free(&lib);
  /* the south pole of city.hdr: the light's -z, in the world */
  {
    float wl[3];
    pbrt_Transform_Vector(&g_port.LightToWorld, south, wl);
    p_port = pbrt_InfiniteAreaLight_Pdf_Li(&g_port, wl);
    p_lib = el_envlight_pdf_li(&g_lib, wl);
  }
  checkf(p_port < 0 && p_lib >= 0 && isfinite(p_lib),
         "south pole of city.hdr: pbrt's Pdf_Li %.4g (sinf(acosf(-1)) = -8.7e-8 passes its sinTheta == 0 guard), the library's %.4g", p_port, p_lib);
}

/* 3. the importance map */
static void test_importance(void) {
  const pbrt_Lmap *m = &g_port.Lmap;
  int W = m->width, H = m->height, i, j, ok_port = 1, ok_lib = 1;
  double worst_port = 0, worst_lib = 0, total = 0, pole = 0, *f = (double *)malloc(sizeof(double) * (size_t)W * H);
  for (j = 0; j < H; ++j)
    for (i = 0; i < W; ++i) {
      double sum = 0, ca = cell_average(m, i, j, 1);
      int a, b;
      for (b = 0; b < 2; ++b) {
        int v = 2 * j + b;
        double s = (double)sinf(pbrt_Pi * (v + .5f) / (2 * H));
        for (a = 0; a < 2; ++a) sum += g_port.distribution.pConditionalV[v].func[2 * i + a] / s;
      }
      if (!(fabs(sum - 4 * ca) <= 4e-6 * ca + 1e-30)) ok_port = 0;
      worst_port = fmax(worst_port, fabs(sum - 4 * ca) / (4 * ca + 1e-30));
      f[(size_t)j * W + i] = cell_average(m, i, j, 0) * sin(PI_D * (j + 0.5) / H);
      total += f[(size_t)j * W + i];
      if (j == 0 || j == H - 1) pole = fmax(pole, fabs(ca - cell_average(m, i, j, 0)) / cell_average(m, i, j, 0));
    }
  checkf(ok_port, "importance: the port's 4 point lookups per texel add up to 4 x the texel's cell average (Repeat in v), to %.2g (bound 4e-6)", worst_port, 0);
  check(g_lib.imp_w == W && g_lib.imp_h == H, "importance: the library's default map has one bin per texel");
  for (j = 0; j < H; ++j) {
    double row = 0, qv, ev, pv = (g_lib.dist.marginal[j + 1] - g_lib.dist.marginal[j]) * UNIT;
    const uint32_t *c = g_lib.dist.cdf + (size_t)j * (W + 1);
    for (i = 0; i < W; ++i) row += f[(size_t)j * W + i];
    qv = row / total;
    ev = (2 + H * qv) * UNIT;
    for (i = 0; i < W; ++i) {
      double qu = f[(size_t)j * W + i] / row, eu = (2 + W * qu) * UNIT, pu = (c[i + 1] - c[i]) * UNIT;
      double bound = ev * qu + eu * qv + ev * eu + 1e-5 * qv * qu;
      if (!(fabs(pv * pu - qv * qu) <= bound)) ok_lib = 0;
      worst_lib = fmax(worst_lib, fabs(pv * pu - qv * qu) / bound);
    }
  }
  checkf(ok_lib, "importance: the library's probability of every texel is its cell average (Clamp in v) x sin theta, normalised, within the integer-CDF bound (worst %.2f of it)", worst_lib, 0);
  printf("      (in the two pole rows Repeat and Clamp cell averages differ by up to %.3g: the pole fix)\n", pole);
  free(f);
}

/* 4. sampling: the library with pbrt's own importance bins */
static void test_sampling(void) {
  const pbrt_Distribution2D *pd = &g_port.distribution;
  int nu = pd->nu, nv = pd->nv, k, okm = 1, okc = 1, okp = 1, npdf = 0;
  double Dm = cdf_gap(&pd->pMarginal, g_lib_pbrt.dist.marginal), total = 0, shift, wm = 0, wc = 0, wp = 0;
  for (k = 0; k < nv; ++k) total += pd->pMarginal.func[k];
  shift = (pd->pMarginal.func[0] + pd->pMarginal.func[nv - 1]) / total;
  check(g_lib_pbrt.imp_w == nu && g_lib_pbrt.imp_h == nv, "sampling: EL_ENVLIGHT_IMPORTANCE_PBRT_V3 has pbrt's 2x bins");
  for (k = 0; k < 200000; ++k) {
    float uu[2], wi[3], L[3], pdf;
    double u, v, st, slope, e, dv, du, Dc;
    int row, col;
    uu[0] = frand();
    uu[1] = frand();
    el_envlight_sample_li(&g_lib_pbrt, uu, wi, L, &pdf);
    light_uv(&g_port, wi, &u, &v, &st);
    /* the direction's error (7e-7 rad: the library's 1.7e-7, its rotation and ours, 2e-7 each), and
     * the library's margin: a sampled point stays 2^-21 (in u and in v) inside its bin */
    dv = (7e-7 / PI_D) + 1.0 / (1 << 21);
    du = (7e-7 / fmax(st, 1e-12) / (2 * PI_D)) + 1.0 / (1 << 21);
    e = fabs(cdf_at(&pd->pMarginal, v, &slope) - uu[1]);
    if (!(e <= Dm + dv * slope + 4 * UNIT)) okm = 0;
    wm = fmax(wm, e / (Dm + dv * slope + 4 * UNIT));
    row = (int)(v * nv);
    if (row > nv - 1) row = nv - 1;
    Dc = cdf_gap(&pd->pConditionalV[row], g_lib_pbrt.dist.cdf + (size_t)row * (nu + 1));
    e = fabs(cdf_at(&pd->pConditionalV[row], u, &slope) - uu[0]);
    if (!(e <= Dc + du * slope + 4 * UNIT)) okc = 0;
    wc = fmax(wc, e / (Dc + du * slope + 4 * UNIT));
    /* the pdf, away from bin edges and the pole rows */
    col = (int)(u * nu);
    if (col > nu - 1) col = nu - 1;
    if (row > 0 && row < nv - 1 && fabs(u * nu - floor(u * nu + 0.5)) > 1e-3 && fabs(v * nv - floor(v * nv + 0.5)) > 1e-3) {
      double qv = pd->pMarginal.func[row] / total, fu = pd->pConditionalV[row].func[col];
      double qu = fu / (pd->pConditionalV[row].funcInt * nu);
      double ev = (2 + nv * qv) * UNIT, eu = (2 + nu * qu) * UNIT;
      /* pbrt's sinf(acosf(z)) near a pole: z's rounding (6e-8) moves theta by 6e-8 / sin theta */
      double rel = ev / qv + eu / qu + ev * eu / (qv * qu) + shift + (nu + nv + 4) * UNIT + 1e-5 +
                   6e-8 / (st * st) + 1e-6 / st;
      float pp = pbrt_InfiniteAreaLight_Pdf_Li(&g_port, wi);
      if (!(fabs(pdf / pp - 1) <= rel)) okp = 0;
      wp = fmax(wp, fabs(pdf / pp - 1) / rel);
      ++npdf;
    }
  }
  checkf(okm, "sampling: pbrt's marginal CDF at the library's v is u[1] to within the CDF gap (%.3g) and the direction's error (worst %.2f of the bound)", Dm, wm);
  checkf(okc, "sampling: the row's conditional CDF at the library's u is u[0] to within that row's gap and the direction's error (worst %.2f of the bound)", wc, 0);
  checkf(okp, "sampling: the library's pdf is pbrt's Pdf_Li of the same direction within the bin's integer-CDF bound and the pole rows' shift (%.0f samples; worst %.2f of the bound)", npdf, wp);
}

/* 5. irradiance of a surface facing the world's up (+y): lum(L) cos / pdf, for both lights */
static void test_irradiance(void) {
  enum { N = 200000 };
  double s[2] = {0, 0}, s2[2] = {0, 0}, mean[2], se, cap = 0;
  int k, which, x, c;
  for (which = 0; which < 2; ++which)
    for (k = 0; k < N; ++k) {
      float uu[2], wi[3], L[3], pdf;
      double y;
      uu[0] = frand();
      uu[1] = frand();
      if (which == 0) pbrt_InfiniteAreaLight_Sample_Li(&g_port, uu, wi, &pdf, L);
      else el_envlight_sample_li(&g_lib, uu, wi, L, &pdf);
      y = pdf > 0 && wi[1] > 0 ? lum_d(L) * wi[1] / pdf : 0;
      s[which] += y;
      s2[which] += y * y;
    }
  for (which = 0; which < 2; ++which) mean[which] = s[which] / N;
  se = sqrt((s2[0] / N - mean[0] * mean[0]) / N + (s2[1] / N - mean[1] * mean[1]) / N);
  /* the half-texel caps at the poles: solid angle 2 x 2 pi (1 - cos(pi / (2 H))) times the largest
   * luminance of the two pole rows and their neighbours (either Le stays below it there) */
  for (x = 0; x < g_port.Lmap.width; ++x)
    for (c = 0; c < 2; ++c) {
      int y0 = c ? g_port.Lmap.height - 2 : 0, y;
      for (y = y0; y < y0 + 2; ++y) cap = fmax(cap, lum_d(g_port.Lmap.texels + 3 * ((size_t)y * g_port.Lmap.width + x)));
    }
  cap *= 2 * 2 * PI_D * (1 - cos(PI_D / (2 * g_port.Lmap.height)));
  checkf(fabs(mean[0] - mean[1]) <= 4 * se + cap,
         "irradiance facing up: port %.5g, library %.5g, within 4 standard errors and the pole caps", mean[0], mean[1]);
}

int main(void) {
  char err[512];
  el_image img;
  pbrt_Transform rx = pbrt_RotateX(-90), rz = pbrt_RotateZ(120), l2w = pbrt_Transform_mul(&rx, &rz);
  el_envlight_options lo;
  float *rgb;
  int res[2], i;
  if (el_image_load(EL_TEST_DATA_DIR "/envmaps/city.hdr", &img, err, sizeof err) != 0) {
    printf("FAIL: %s\n", err);
    return 1;
  }
  rgb = (float *)malloc(sizeof(float) * 3 * (size_t)img.width * img.height);
  for (i = 0; i < img.width * img.height; ++i) memcpy(rgb + 3 * i, img.pixels + (size_t)img.channels * i, 3 * sizeof(float));
  res[0] = img.width;
  res[1] = img.height;
  memset(&lo, 0, sizeof lo);
  memcpy(lo.light_to_world, l2w.m, sizeof lo.light_to_world);
  check(pbrt_InfiniteAreaLight_init(&g_port, &l2w, rgb, res) == 0, "city.hdr: the port builds");
  check(el_envlight_init(&g_lib, rgb, img.width, img.height, 3, &lo) == EL_SUCCESS &&
            el_envlight_prepare_sampling(&g_lib) == EL_SUCCESS,
        "city.hdr: the library builds (default importance)");
  lo.importance = EL_ENVLIGHT_IMPORTANCE_PBRT_V3;
  check(el_envlight_init(&g_lib_pbrt, rgb, img.width, img.height, 3, &lo) == EL_SUCCESS &&
            el_envlight_prepare_sampling(&g_lib_pbrt) == EL_SUCCESS,
        "city.hdr: the library builds (EL_ENVLIGHT_IMPORTANCE_PBRT_V3)");
  test_le();
  test_poles();
  test_importance();
  test_sampling();
  test_irradiance();
  pbrt_InfiniteAreaLight_free(&g_port);
  el_envlight_free(&g_lib);
  el_envlight_free(&g_lib_pbrt);
  el_image_free(&img);
  free(rgb);
  printf("%d passed, %d failed\n", g_pass, g_fail);
  return g_fail ? 1 : 0;
}
