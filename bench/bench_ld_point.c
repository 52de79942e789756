/* bench_ld_point.c: how much of a low-discrepancy sampler's stratification survives the map's warp, at
 * one lit ground point (issue 21/22's finding: on bench_city, Mitsuba's multijitter gains 8x over
 * independent, our zsobol 6x, lit pixels 2.4-2.75x Mitsuba's).
 *
 *   bench_ld_point [MAP.hdr [N [TRIALS [IMPORTANCE [RES]]]]]   map (data/envmaps/city.hdr; - for it), points per estimate (64),
 *                  trials (4000), the light's importance map (EL_ENVLIGHT_IMPORTANCE_*: 0 cell average, 1 pbrt-v3
 *                  (the renderer's default), 2 texel, 3 bilinear (Mitsuba 3's density); default 1), RES: the
 *                  importance map's bins per texel and axis (0: the mode's own)
 *
 * The irradiance at an upward normal (the map's own frame, +z up, nothing occluded) estimated from N
 * points, TRIALS times with fresh randomisation; printed: the variance of one estimate per point set
 * (independent, jittered N = k x k with each 2D dimension jittered on its own and paired at random,
 * multi-jitter (jittered and n-rooks, as Mitsuba 3's multijitter), Owen-scrambled Sobol' (0,2)-nets, the two 2D dimensions with independent scrambles and their pairing
 * shuffled) and its gain over independent points, for
 *   (a) the light sample alone, bilinear radiance (el_envlight_sample_li as the renderer uses it),
 *   (b) the same with the radiance of the sampled texel (nearest, piecewise constant like the pdf),
 *   (c) the ideal warp: L / pdf constant (cos only), what stratification gives when the warp is exact,
 *   (d) one light + one cosine BSDF sample with the power heuristic (the renderer's map-alone MIS),
 *   (e) (d) with the nearest radiance.
 * (a) against (b) shows whether the radiance that varies inside a texel while the pdf does not (pbrt-v3's
 * piecewise-constant density under a bilinear lookup) eats the gain in the sun's few texels.
 *   (f), (g): (a), (d) with a prototype of the proposed fix (below: the bilinear density, sampled by the
 * discrete table over le()'s patches and a bilinear warp inside the patch).
 *
 *   bench_ld_point --lit [MAP.hdr [N [TRIALS]]]   (issue 22's lit pixels) a ground point beside a sphere: the
 *                  plane z = 0 of the map's frame, a sphere of radius 1 at (0, 0, 1) hiding part of the sky,
 *                  points at distance 1.5-4 on the sun's side; the irradiance (luminance, V by the sphere) by
 *                  product sampling alone, with a cosine sample and the power or balance heuristic, the patch
 *                  density alone and with MIS, two product samples (independent nets, one 2N net, a shifted
 *                  copy), a product + a patch sample (balance), and split weights (the light sample carries
 *                  lum - c, the cosine sample min(lum, c)). City, 64 points, 1000 trials, Owen-scrambled
 *                  Sobol' (2026-12-02): product MIS power 1.8-2.7e-4 at every point (independent 2.0-2.6e-3),
 *                  the product alone 3.5e-5-3.2e-4 (1.0e-4-1.0e-3), two product samples 1.8e-5-1.7e-4, one
 *                  2N net 1.2e-5-1.1e-4; without the sphere the product alone 1.7e-5 (the patch density
 *                  alone 2e-6: the cells' constant cosine bounds cost stratification, but the sphere's edge
 *                  costs more); split weights 2.0-2.9e-4 (their light part: the sky's samples weighted 0).
 *                  A cosine MIS partner keeps a floor of about 2e-4 whatever the weights: the light
 *                  sample's weighted integrand steps between the sun (weight ~1) and the sky (~0.1).
 * The prototype became the library's importance mode BILINEAR (issue 22; envlight.h, NOTES ON PRODUCT
 * SAMPLING 1): with IMPORTANCE 3, rows (a) and (d) are the library's sampler and match (f) and (g) (city,
 * 64 points, 4000 trials, Owen-scrambled Sobol': light alone 2.07e-6 against the prototype's 2.37e-6,
 * MIS 2.32e-4 against 2.32e-4); the prototype stays as the double-precision reference it was. */
#define EL_IMPLEMENTATION
#include "envlight.h"
#include "image_io.h"
#include "../tests/test_rng.h" /* splitmix64, hash32, sobol0, sobol1, owen24 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static splitmix64 g_s = {0x9E3779B97F4A7C15ull};
static uint64_t rnd64(void) { return splitmix64_next(&g_s); }
static float rndf(void) { return splitmix64_f(&g_s); }
static void shuffle(int *p, int n) { int i; for (i = 0; i < n; i++) p[i] = i; for (i = n - 1; i > 0; i--) { int j = (int)(rnd64() % (uint64_t)(i + 1)), t = p[i]; p[i] = p[j]; p[j] = t; } }

/* n 2D points of kind k (0 independent, 1 jittered k x k, 2 Owen-scrambled Sobol', 3 multi-jitter), into u[2 i] */
static void points(int kind, int n, float *u) {
  int i, perm[4096];
  if (kind == 0) { for (i = 0; i < 2 * n; i++) u[i] = rndf(); return; }
  shuffle(perm, n);
  if (kind == 1) {
    int k = (int)(sqrt((double)n) + 0.5);
    for (i = 0; i < n; i++) { int c = perm[i]; u[2 * i] = ((float)(c % k) + rndf()) / (float)k; u[2 * i + 1] = ((float)(c / k) + rndf()) / (float)k; }
  } else if (kind == 3) { /* multi-jitter (Chiu, Shirley and Wang 1994): jittered k x k and n-rooks, fine strata shuffled */
    int k = (int)(sqrt((double)n) + 0.5), a, b, sx[64][64], sy[64][64];
    for (a = 0; a < k; a++) { shuffle(sx[a], k); shuffle(sy[a], k); }
    for (i = 0; i < n; i++) {
      int c = perm[i];
      a = c % k; b = c / k; /* the coarse cell (a, b) */
      u[2 * i] = ((float)(a * k + sx[a][b]) + rndf()) / (float)n;
      u[2 * i + 1] = ((float)(b * k + sy[b][a]) + rndf()) / (float)n;
    }
  } else {
    uint32_t s0 = (uint32_t)rnd64(), s1 = (uint32_t)rnd64();
    for (i = 0; i < n; i++) { uint32_t c = (uint32_t)perm[i]; u[2 * i] = owen24(sobol0(c), s0); u[2 * i + 1] = owen24(sobol1(c), s1); }
  }
  for (i = 0; i < 2 * n; i++) if (u[i] >= 1.0f) u[i] = 0.99999994f;
}

static const float *g_px;
static int g_w, g_h;
static double lum(const float *c) { return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]; }
static double nearest(const float d[3]) { /* the texel's luminance (pbrt-v3's (u, v) = (phi / 2pi, theta / pi)) */
  float u, v;
  int x, y;
  el_envlight_dir_to_uv(d, &u, &v);
  x = (int)(u * (float)g_w); y = (int)(v * (float)g_h);
  x = x < 0 ? 0 : x >= g_w ? g_w - 1 : x; y = y < 0 ? 0 : y >= g_h ? g_h - 1 : y;
  return lum(g_px + 3 * ((size_t)y * (size_t)g_w + (size_t)x));
}

/* ---- the proposed fix, as a prototype: piecewise-constant bins on le()'s bilinear patches (between texel
 * centres; half rows at the poles, where le() is constant in v), each bin's mass its exact integral of
 * the corners' lum x sin(theta_centre), then a bilinear warp inside the chosen patch (Mitsuba 3's density,
 * sampled by the discrete 2D table plus two linear inversions). Its pdf is exact for its own sampler. */
static el_distribution2d g_pd;
static float *g_corner; /* (h) x (w): lum x sin(theta) of texel (x, y) */
static double g_total;
static float corner(int x, int y) { return g_corner[(size_t)y * (size_t)g_w + (size_t)((x + g_w) % g_w)]; }
static void patch_rows(int r, int *y0, int *y1, double *v0, double *hv) {
  *y0 = r == 0 ? 0 : r - 1; *y1 = r == g_h ? g_h - 1 : r;
  *v0 = r == 0 ? 0.0 : (r - 0.5) / g_h; *hv = (r == 0 || r == g_h) ? 0.5 / g_h : 1.0 / g_h;
}
static int patch_init(void) {
  int x, y, r;
  float *f = (float *)malloc(sizeof(float) * (size_t)g_w * (size_t)(g_h + 1));
  g_corner = (float *)malloc(sizeof(float) * (size_t)g_w * (size_t)g_h);
  for (y = 0; y < g_h; y++)
    for (x = 0; x < g_w; x++) g_corner[(size_t)y * g_w + x] = (float)(lum(g_px + 3 * ((size_t)y * g_w + x)) * sin(3.14159265358979 * (y + 0.5) / g_h));
  g_total = 0;
  for (r = 0; r <= g_h; r++) {
    int y0, y1; double v0, hv;
    patch_rows(r, &y0, &y1, &v0, &hv);
    for (x = 0; x < g_w; x++) { /* bins of equal size in the table: f is the mass over the bin's area */
      double m = (corner(x, y0) + corner(x + 1, y0) + corner(x, y1) + corner(x + 1, y1)) * 0.25 * hv / g_w;
      f[(size_t)r * g_w + x] = (float)m;
      g_total += m;
    }
  }
  r = el_distribution2d_init(&g_pd, f, g_w, g_h + 1, NULL) != EL_SUCCESS;
  free(f);
  return r;
}
/* t in [0, 1) with density proportional to (1 - t) A + t B */
static double lin_inv(double A, double B, double xi) {
  if (A + B <= 0) return xi;
  return xi * (A + B) / (A + sqrt(A * A + xi * (B * B - A * A)));
}
static double patch_density_uv(int i, int r, double s, double t) { /* pdf over (u, v) */
  int y0, y1; double v0, hv, a, b, c, d, mass, val;
  patch_rows(r, &y0, &y1, &v0, &hv);
  a = corner(i, y0); b = corner(i + 1, y0); c = corner(i, y1); d = corner(i + 1, y1);
  mass = (a + b + c + d) * 0.25 * hv / g_w;
  if (mass <= 0) return 0;
  val = (1 - t) * ((1 - s) * a + s * b) + t * ((1 - s) * c + s * d);
  return val / g_total; /* the mass's share x val / mean corner / area = val / total */
}
static void uv_dir(double u, double v, float d[3]) {
  double ph = 2 * 3.14159265358979 * u, th = 3.14159265358979 * v;
  d[0] = (float)(sin(th) * cos(ph)); d[1] = (float)(sin(th) * sin(ph)); d[2] = (float)cos(th);
}
static double patch_pdf(const float d[3]);
static void patch_sample(const float uu[2], float wi[3], float *pdf) {
  int i, r, y0, y1; float fu, fv, pb; double v0, hv, a, b, c, d, s, t, u, v, sth;
  el_distribution2d_sample_bins(&g_pd, uu[0], uu[1], &i, &r, &fu, &fv, &pb);
  patch_rows(r, &y0, &y1, &v0, &hv);
  a = corner(i, y0); b = corner(i + 1, y0); c = corner(i, y1); d = corner(i + 1, y1);
  t = lin_inv(a + b, c + d, fv);
  s = lin_inv((1 - t) * a + t * c, (1 - t) * b + t * d, fu);
  u = (i + 0.5 + s) / g_w; if (u >= 1) u -= 1;
  v = v0 + t * hv;
  sth = sin(3.14159265358979 * v);
  uv_dir(u, v, wi);
  /* the pdf of the returned (float) direction, as sample_li returns pdf_li(wi): at a patch's zero corner
   * the density of the exact (s, t) may be 0 where le() of the rounded direction is not */
  *pdf = sth > 0 ? (float)patch_pdf(wi) : 0.f;
}
static double patch_pdf(const float d[3]) {
  double ph = atan2(d[1], d[0]), th = acos(fmax(-1.0, fmin(1.0, d[2]))), u, v, x, s, t, sth;
  int i, r;
  if (ph < 0) ph += 2 * 3.14159265358979;
  u = ph / (2 * 3.14159265358979); v = th / 3.14159265358979;
  x = u * g_w - 0.5; if (x < 0) x += g_w;
  i = (int)x; if (i >= g_w) i = g_w - 1; s = x - i;
  if (v < 0.5 / g_h) { r = 0; t = v / (0.5 / g_h); }
  else if (v >= (g_h - 0.5) / g_h) { r = g_h; t = (v - (g_h - 0.5) / g_h) / (0.5 / g_h); }
  else { double yv = v * g_h - 0.5; r = (int)yv + 1; if (r > g_h - 1) r = g_h - 1; t = yv - (r - 1); }
  sth = sin(th);
  return sth > 0 ? patch_density_uv(i, r, s, t) / (2 * 3.14159265358979 * 3.14159265358979 * sth) : 0;
}
static void cos_sample(const float u[2], float d[3], float *pdf) {
  double r = sqrt(u[0]), ph = 2 * 3.14159265358979 * u[1];
  d[0] = (float)(r * cos(ph)); d[1] = (float)(r * sin(ph)); d[2] = (float)sqrt(fmax(0.0, 1.0 - u[0]));
  *pdf = d[2] / 3.14159265f;
}

/* ---- --lit: a lit ground point beside a sphere (issue 22: why the lit pixels keep less of the
 * low-discrepancy gain than Mitsuba's). The ground of bench_city in the map's frame: the plane z = 0,
 * normal +z, a sphere of radius 1 at (0, 0, 1) hiding part of the sky; ground points at distance D from
 * the sphere's foot, on the sun's side (azimuth of the brightest texel + A degrees). Estimators of the
 * irradiance (luminance, V by the sphere), N points each, per point kind: */
static double g_P[3];
static int visible(const float w[3]) { /* the ray from g_P along w misses the sphere */
  double c[3] = {-g_P[0], -g_P[1], 1.0 - g_P[2]}, b = w[0] * c[0] + w[1] * c[1] + w[2] * c[2], cc = c[0] * c[0] + c[1] * c[1] + c[2] * c[2] - 1.0;
  return !(b > 0 && b * b > cc);
}
static double heur(double a, double b, int power) { return power ? a * a / (a * a + b * b) : a / (a + b); }
#define LIT_E 16
static int lit_study(int argc, char **argv) {
  const char *path = argc > 2 && strcmp(argv[2], "-") ? argv[2] : EL_SOURCE_DIR "/data/envmaps/city.hdr";
  int N = argc > 3 ? atoi(argv[3]) : 64, T = argc > 4 ? atoi(argv[4]) : 2000, kind, e, t, i, p, x, y, bx = 0, by = 0;
  static const char *ename[LIT_E] = {"product alone", "product MIS power", "product MIS balance", "patch map alone", "patch map MIS power",
                                     "2 product (BSDF dims)", "product+patch MIS bal", "product, no occluder",
                                     "product+cos clamp c", "product+cos clamp 4c", "compensated+cos clamp c",
                                     "cos alone", "clamp c: light part", "clamp c: BSDF part",
                                     "2 product, one 2N net", "2 product, u + (1/2, 1/2)"};
  static const double pts[][2] = {{1.5, 0}, {2.5, 0}, {4, 0}, {2.5, 90}, {2.5, -60}};
  static const char *kname[4] = {"independent", "jittered", "sobol-owen", "multijitter"};
  el_envlight_options opt;
  el_image img;
  el_envlight l, lc;
  char err[256];
  float *ul, *ub, *u2n, best = -1.f, sun[3], n[3] = {0, 0, 1};
  double phis, cmean = 0;
  if (N < 1 || N > 4096 || T < 2 || (int)(sqrt((double)N) + 0.5) * (int)(sqrt((double)N) + 0.5) != N) { fprintf(stderr, "bench_ld_point --lit: N a square in 1..4096, TRIALS >= 2\n"); return 1; }
  if (el_image_load(path, &img, err, sizeof err) != 0) { fprintf(stderr, "%s\n", err); return 1; }
  memset(&opt, 0, sizeof opt);
  opt.importance = EL_ENVLIGHT_IMPORTANCE_BILINEAR;
  if (el_envlight_init(&l, img.pixels, img.width, img.height, 3, &opt) != EL_SUCCESS) { fprintf(stderr, "%s: init failed\n", path); return 1; }
  opt.compensated = 1;
  if (el_envlight_init(&lc, img.pixels, img.width, img.height, 3, &opt) != EL_SUCCESS) { fprintf(stderr, "%s: init failed\n", path); return 1; }
  for (y = 0; y < img.height; y++) /* the mean luminance over the sphere (the compensation's offset, about) */
    for (x = 0; x < img.width; x++) cmean += lum(img.pixels + 3 * ((size_t)y * (size_t)img.width + (size_t)x)) * sin(3.14159265358979 * (y + 0.5) / img.height);
  cmean *= 3.14159265358979 / img.height * 2 * 3.14159265358979 / img.width / (4 * 3.14159265358979);
  for (y = 0; y < img.height; y++)
    for (x = 0; x < img.width; x++) { float v = (float)lum(img.pixels + 3 * ((size_t)y * (size_t)img.width + (size_t)x)); if (v > best) { best = v; bx = x; by = y; } }
  uv_dir((bx + 0.5) / img.width, (by + 0.5) / img.height, sun);
  phis = atan2(sun[1], sun[0]);
  printf("mean luminance c = %.4g\n", cmean);
  printf("%s: sun at texel (%d, %d), elevation %.1f degrees; %d points per estimate, %d trials; relative variance of one estimate (luminance)\n", path, bx, by,
         asin(sun[2]) * 180 / 3.14159265358979, N, T);
  ul = (float *)malloc(sizeof(float) * 2 * (size_t)N); ub = (float *)malloc(sizeof(float) * 2 * (size_t)N);
  u2n = (float *)malloc(sizeof(float) * 4 * (size_t)N);
  for (p = 0; p < (int)(sizeof pts / sizeof pts[0]); p++) {
    double a = phis + pts[p][1] * 3.14159265358979 / 180;
    g_P[0] = pts[p][0] * cos(a); g_P[1] = pts[p][0] * sin(a); g_P[2] = 0;
    printf("ground point at distance %.1f, azimuth sun%+.0f: the sun %s\n", pts[p][0], pts[p][1], visible(sun) ? "visible" : "HIDDEN");
    for (kind = 0; kind < 4; kind += 2) {
      double s1[LIT_E] = {0}, s2[LIT_E] = {0};
      for (t = 0; t < T; t++) {
        double acc[LIT_E] = {0};
        points(kind, N, ul); points(kind, N, ub);
        if (2 * N <= 4096) { /* (kinds 0 and 2: points() takes any n) */
          points(kind, 2 * N, u2n);
          for (i = 0; i < 2 * N; i++) {
            float w[3], L[3], pp;
            el_envlight_sample_li_cos(&l, n, u2n + 2 * i, w, L, &pp);
            if (pp > 0 && w[2] > 0) acc[14] += 0.5 * visible(w) * lum(L) * w[2] / 3.14159265 / pp;
          }
        }
        for (i = 0; i < N; i++) {
          float w[3], L[3], pp, us[2];
          us[0] = ul[2 * i] + 0.5f; us[1] = ul[2 * i + 1] + 0.5f;
          if (us[0] >= 1.f) us[0] -= 1.f;
          if (us[1] >= 1.f) us[1] -= 1.f;
          el_envlight_sample_li_cos(&l, n, ul + 2 * i, w, L, &pp);
          if (pp > 0 && w[2] > 0) acc[15] += 0.5 * visible(w) * lum(L) * w[2] / 3.14159265 / pp;
          el_envlight_sample_li_cos(&l, n, us, w, L, &pp);
          if (pp > 0 && w[2] > 0) acc[15] += 0.5 * visible(w) * lum(L) * w[2] / 3.14159265 / pp;
        }
        for (i = 0; i < N; i++) {
          float wl[3], Ll[3], pl, wm[3], Lm[3], pm, wb[3], pb, Lb[3], w2[3], L2[3], p2, wc[3], Lc[3], pcc;
          el_envlight_sample_li_cos(&l, n, ul + 2 * i, wl, Ll, &pl);
          el_envlight_sample_li(&l, ul + 2 * i, wm, Lm, &pm);
          el_envlight_sample_li_cos(&l, n, ub + 2 * i, w2, L2, &p2);
          cos_sample(ub + 2 * i, wb, &pb);
          el_envlight_sample_li_cos(&lc, n, ul + 2 * i, wc, Lc, &pcc);
          if (pcc > 0 && wc[2] > 0) { /* the compensated product: the light carries lum - c */
            double f = lum(Lc) * wc[2] / 3.14159265, lm = lum(Lc);
            acc[10] += visible(wc) * (lm > 1.5 * cmean ? 1 - 1.5 * cmean / lm : 0) * f / pcc;
          }
          if (pl > 0 && wl[2] > 0) { /* clamp weights: the light carries lum - c, the BSDF sample min(lum, c) */
            double f = lum(Ll) * wl[2] / 3.14159265, lm = lum(Ll), v = visible(wl);
            acc[8] += v * (lm > cmean ? 1 - cmean / lm : 0) * f / pl; acc[12] += v * (lm > cmean ? 1 - cmean / lm : 0) * f / pl;
            acc[9] += v * (lm > 4 * cmean ? 1 - 4 * cmean / lm : 0) * f / pl;
          }
          if (pl > 0 && wl[2] > 0) {
            double f = lum(Ll) * wl[2] / 3.14159265, v = visible(wl), pbl = wl[2] / 3.14159265, pml = el_envlight_pdf_li(&l, wl);
            acc[0] += v * f / pl; acc[1] += v * heur(pl, pbl, 1) * f / pl; acc[2] += v * heur(pl, pbl, 0) * f / pl;
            acc[5] += 0.5 * v * f / pl; acc[6] += v * f / (pl + pml); acc[7] += f / pl;
          }
          if (p2 > 0 && w2[2] > 0) acc[5] += 0.5 * visible(w2) * lum(L2) * w2[2] / 3.14159265 / p2;
          if (pm > 0 && wm[2] > 0) {
            double f = lum(Lm) * wm[2] / 3.14159265, v = visible(wm), pbm = wm[2] / 3.14159265, plm = el_envlight_pdf_li_cos(&l, n, wm);
            acc[3] += v * f / pm; acc[4] += v * heur(pm, pbm, 1) * f / pm; acc[6] += v * f / (pm + plm);
          }
          if (pb > 0 && visible(wb)) {
            double f, pc = el_envlight_pdf_li_cos(&l, n, wb), pmb = el_envlight_pdf_li(&l, wb);
            el_envlight_le(&l, wb, Lb);
            f = lum(Lb) * wb[2] / 3.14159265;
            double lm = lum(Lb);
            acc[8] += (lm > cmean ? cmean / lm : 1) * f / pb; acc[13] += (lm > cmean ? cmean / lm : 1) * f / pb; acc[11] += f / pb; acc[9] += (lm > 4 * cmean ? 4 * cmean / lm : 1) * f / pb;
            acc[10] += (lm > 1.5 * cmean ? 1.5 * cmean / lm : 1) * f / pb;
            acc[1] += heur(pb, pc, 1) * f / pb; acc[2] += heur(pb, pc, 0) * f / pb; acc[4] += heur(pb, pmb, 1) * f / pb;
          }
        }
        for (e = 0; e < LIT_E; e++) { double v = acc[e] / N; s1[e] += v; s2[e] += v * v; }
      }
      printf("  %-12s", kname[kind]);
      for (e = 0; e < LIT_E; e++) { double m = s1[e] / T; printf("  %s %.2e", ename[e], (s2[e] - s1[e] * m) / (T - 1) / (m * m)); }
      printf("  (mean %.4g, no occluder %.4g)\n", s1[0] / T, s1[7] / T);
    }
  }
  free(ul); free(ub); free(u2n); el_envlight_free(&l); el_envlight_free(&lc); el_image_free(&img);
  return 0;
}

int main(int argc, char **argv) {
  const char *path = argc > 1 && strcmp(argv[1], "-") ? argv[1] : EL_SOURCE_DIR "/data/envmaps/city.hdr"; /* - : the default (the tutorial's quote) */
  int N = argc > 2 ? atoi(argv[2]) : 64, T = argc > 3 ? atoi(argv[3]) : 4000, imp = argc > 4 ? atoi(argv[4]) : 1, res = argc > 5 ? atoi(argv[5]) : 0, kind, e, t, i;
  el_envlight_options opt;
  el_image img;
  el_envlight l;
  char err[256];
  static const char *kname[4] = {"independent", "jittered", "sobol-owen", "multijitter"};
  static const char *ename[7] = {"(a) light alone, bilinear L", "(b) light alone, texel L", "(c) ideal warp (L/pdf const)",
                                 "(d) MIS light+BSDF, bilinear", "(e) MIS light+BSDF, texel L",
                                 "(f) patch warp, light alone", "(g) patch warp, MIS light+BSDF"};
  double var[4][7], mean[4][7];
  float *ul, *ub;
  if (argc > 1 && !strcmp(argv[1], "--lit")) return lit_study(argc, argv);
  if (N < 1 || N > 4096 || T < 2 || (int)(sqrt((double)N) + 0.5) * (int)(sqrt((double)N) + 0.5) != N) { fprintf(stderr, "bench_ld_point: N a square in 1..4096, TRIALS >= 2\n"); return 1; }
  if (el_image_load(path, &img, err, sizeof err) != 0) { fprintf(stderr, "%s\n", err); return 1; }
  memset(&opt, 0, sizeof opt);
  opt.importance = imp;
  if (res > 0) { opt.importance_width = res * img.width; opt.importance_height = res * img.height; opt.importance_cap = -1; }
  if (el_envlight_init(&l, img.pixels, img.width, img.height, 3, &opt) != EL_SUCCESS) { fprintf(stderr, "%s: init failed\n", path); return 1; }
  g_px = img.pixels; g_w = img.width; g_h = img.height;
  if (patch_init()) { fprintf(stderr, "patch table failed\n"); return 1; }
  ul = (float *)malloc(sizeof(float) * 2 * (size_t)N); ub = (float *)malloc(sizeof(float) * 2 * (size_t)N);
  for (kind = 0; kind < 4; kind++) {
    double s1[7] = {0}, s2[7] = {0};
    for (t = 0; t < T; t++) {
      double acc[7] = {0};
      points(kind, N, ul); points(kind, N, ub);
      for (i = 0; i < N; i++) {
        float wi[3], L[3], pdf, wb[3], pb, Lb[3];
        el_envlight_sample_li(&l, ul + 2 * i, wi, L, &pdf);
        if (pdf > 0 && wi[2] > 0) {
          double c = wi[2], pbs = wi[2] / 3.14159265, w = pdf * pdf / ((double)pdf * pdf + pbs * pbs);
          acc[0] += lum(L) * c / pdf; acc[1] += nearest(wi) * c / pdf; acc[2] += c;
          acc[3] += w * lum(L) * c / pdf; acc[4] += w * nearest(wi) * c / pdf;
        }
        { /* the prototype: light alone and MIS with the same BSDF sample below */
          float wp[3], pp, Lp[3];
          patch_sample(ul + 2 * i, wp, &pp);
          if (pp > 0 && wp[2] > 0) {
            double c = wp[2], pbs = wp[2] / 3.14159265, w = (double)pp * pp / ((double)pp * pp + pbs * pbs);
            el_envlight_le(&l, wp, Lp);
            acc[5] += lum(Lp) * c / pp; acc[6] += w * lum(Lp) * c / pp;
          }
        }
        cos_sample(ub + 2 * i, wb, &pb);
        if (pb > 0) {
          double pl = el_envlight_pdf_li(&l, wb), w = (double)pb * pb / ((double)pb * pb + pl * pl);
          el_envlight_le(&l, wb, Lb);
          acc[3] += w * lum(Lb) * wb[2] / pb; acc[4] += w * nearest(wb) * wb[2] / pb;
          pl = patch_pdf(wb); w = (double)pb * pb / ((double)pb * pb + pl * pl);
          acc[6] += w * lum(Lb) * wb[2] / pb;
        }
      }
      for (e = 0; e < 7; e++) { double x = acc[e] / N; s1[e] += x; s2[e] += x * x; }
    }
    for (e = 0; e < 7; e++) { mean[kind][e] = s1[e] / T; var[kind][e] = (s2[e] - s1[e] * s1[e] / T) / (T - 1); }
  }
  printf("%s, importance %d res %d, %d points per estimate, %d trials: relative variance of one estimate (gain over independent)\n", path, imp, res, N, T);
  for (e = 0; e < 7; e++) {
    printf("%-32s", ename[e]);
    for (kind = 0; kind < 4; kind++) printf("  %s %.3e (%.2fx)", kname[kind], var[kind][e] / (mean[0][e] * mean[0][e]), var[0][e] / var[kind][e]);
    printf("  mean %.4g\n", mean[0][e]);
  }
  free(ul); free(ub); el_envlight_free(&l); el_image_free(&img);
  return 0;
}
