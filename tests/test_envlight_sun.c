/* test_envlight_sun.c: issue 22's hot spots and the mixture sampler (envlight.h, NOTES ON HOT SPOTS),
 * through the public API, on maps generated here (128 x 64, and 512 x 256 for the chi-square of the
 * direction-table path; a smooth sky plus):
 *
 *   1. detection: two suns, a sun at the pole, a sun across the seam, a sun of one texel, each found
 *      where it was put (the cone holds the sun's true direction, is a few bins wide) with a share that
 *      matches the frequency with which sample_li lands in the cone; no sun, a constant light, a black map:
 *      no spot; importance BILINEAR: its spot, and the mixture samplers are sample_li there;
 *   2. default weights (all zero, NULL, NaN, negative, infinite, all-zero sum): sample_li_mix is
 *      sample_li and pdf_li_mix is pdf_li, bit for bit; explicit weights equal to the shares give pdf_li
 *      to 1e-6;
 *   3. chi-square of sample_li_mix against pdf_li_mix over the importance bins (the expected count of a
 *      bin is the integral of pdf_li_mix over it: pdf at the centre x sin(theta) x the bin's angles, exact
 *      for a density c / sin(theta); on 512 x 256 over cells of 4 x 4 bins), on the hard maps, under a general rotation, for spot weights 1e-3,
 *      0.3, 0.999 and 1, and for a compensated light, the CDF and alias samplers and importance TEXEL;
 *      the sampled pdf equals pdf_li_mix(wi) bit for bit; the mixture puts exactly its weight on the spots;
 *   4. unbiasedness: the mean of f / pdf for f = le x max(0, n.w), with arbitrary weights, against a
 *      brute-force quadrature of the same integral (16 points per texel of le itself, 256 at the poles);
 *      and for a shadowed point (f = 0 on the sun) with the sun's weight 0; for sample_li_mix and the
 *      rest x cosine mixture (sample_li_mix_cos, also chi-square tested for normals up, sideways, down
 *      and NaN, and on 512 x 256 with the direction tables);
 *   5. hostile inputs: NaN / infinite u and directions, bad options, hot spots of another light;
 *   6. cells of more than 256 bins a side (8208 x 32 and 128 x 4104 maps), where the rest x cosine tables
 *      have no guide and are searched by bisection: chi-square over every bin, sampled pdf == pdf_li_mix_cos,
 *      unbiasedness, hostile u, normals, directions and weights 0 and 1; that such cells exist is read from
 *      el_envlight_hotspots' private cell_u0 / cell_v0 (the one white-box check here);
 *   7. importance BILINEAR's spots, sample_li_spot / pdf_li_spot: on two suns, a sun at the pole, across the
 *      seam, of one texel (and at 1e12), a weak (city-like) and a horizon (sunrise-like) sun, 128 x 64 and
 *      512 x 256 (the fast path), rotated, compensated: chi-square over le()'s patches split 2 x 2 (the
 *      expected mass of a quarter: pdf x sin(theta) at its centre, exact for the bilinear density), the pdf
 *      integrating to 1, the sampled pdf == pdf_li_spot bit for bit, pdf 0 a few texels beyond the cone and
 *      > 0 all over it, the mean of lum(le) / pdf against a quadrature over the rectangle, hostile inputs.
 */
#define EL_IMPLEMENTATION
#include "envlight.h"

#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define PI 3.14159265358979323846
static int g_w = 128, g_h = 64; /* 512 x 256 once: the direction-table path of maps >= 256 x 128 */
#define W g_w
#define H g_h
#define MAXWH (512 * 256)

#include "test_common.h" /* check (a PASS / FAIL line, counted in g_pass / g_fail), rotation37 */

#include "test_rng.h" /* rng_f: PCG32, 24-bit floats in [0, 1) */
static rng g_rng = {0x853c49e6748fea9bULL}; /* one stream for the whole program */

#include "test_chisq.h" /* gammq, chisq_pooled: the chi-square statistic and p-value */

static void mul(const float m[9], const float a[3], float b[3]) {
  b[0] = m[0] * a[0] + m[1] * a[1] + m[2] * a[2];
  b[1] = m[3] * a[0] + m[4] * a[1] + m[5] * a[2];
  b[2] = m[6] * a[0] + m[7] * a[1] + m[8] * a[2];
}
static void mul_t(const float m[9], const float a[3], float b[3]) {
  b[0] = m[0] * a[0] + m[3] * a[1] + m[6] * a[2];
  b[1] = m[1] * a[0] + m[4] * a[1] + m[7] * a[2];
  b[2] = m[2] * a[0] + m[5] * a[1] + m[8] * a[2];
}
static void uv_dir(double u, double v, double d[3]) { /* pbrt-v3's mapping in light space, double libm */
  double th = PI * v, ph = 2.0 * PI * u;
  d[0] = sin(th) * cos(ph); d[1] = sin(th) * sin(ph); d[2] = cos(th);
}
static double angle_between(const double a[3], const float b[3]) {
  double c = (a[0] * b[0] + a[1] * b[1] + a[2] * b[2]) / sqrt((double)b[0] * b[0] + (double)b[1] * b[1] + (double)b[2] * b[2]);
  return acos(c > 1 ? 1 : (c < -1 ? -1 : c));
}

/* the maps: a smooth sky (brighter at the horizon, a dim ground) and suns of value `sun` on texels */
enum { MAP_NONE, MAP_TWO, MAP_POLE, MAP_SEAM, MAP_ONE, MAP_COUNT };
static const char *map_name[MAP_COUNT] = {"no sun", "two suns", "sun at the pole", "sun across the seam", "one-texel sun"};
static void make_map(int kind, float *px) {
  int x, y, c;
  for (y = 0; y < H; ++y)
    for (x = 0; x < W; ++x) {
      double v = (y + 0.5) / H, sky = v < 0.5 ? 0.4 + 0.6 * v * 2 : 0.05, tint = 1.0 + 0.2 * sin(2 * PI * (x + 0.5) / W);
      for (c = 0; c < 3; ++c) px[3 * (y * W + x) + c] = (float)(sky * tint * (c == 2 ? 1.2 : 1.0));
    }
#define SUN(X, Y, V) do { int xx_ = (X), yy_ = (Y); for (c = 0; c < 3; ++c) px[3 * (yy_ * W + xx_) + c] = (float)(V); } while (0)
  if (kind == MAP_TWO) { SUN(30, 20, 3e4); SUN(31, 20, 3e4); SUN(30, 21, 3e4); SUN(31, 21, 3e4); SUN(90, 40, 2e4); SUN(91, 40, 2e4); SUN(90, 41, 2e4); SUN(91, 41, 2e4); }
  if (kind == MAP_POLE) for (x = 0; x < W; ++x) SUN(x, 0, 5e5);
  if (kind == MAP_SEAM) { SUN(W - 1, 25, 4e4); SUN(0, 25, 4e4); SUN(W - 1, 26, 4e4); SUN(0, 26, 4e4); }
  if (kind == MAP_ONE) SUN(70, 12, 2e5);
#undef SUN
}
/* where each map's suns are (texel centres; the pole: +z) */
static int sun_dirs(int kind, double d[2][3]) {
  if (kind == MAP_TWO) { uv_dir(31.0 / W, 21.0 / H, d[0]); uv_dir(91.0 / W, 41.0 / H, d[1]); return 2; }
  if (kind == MAP_POLE) { d[0][0] = 0; d[0][1] = 0; d[0][2] = 1; return 1; }
  if (kind == MAP_SEAM) { uv_dir(0.0, 26.0 / H, d[0]); return 1; }
  if (kind == MAP_ONE) { uv_dir(70.5 / W, 12.5 / H, d[0]); return 1; }
  return 0;
}

static int g_variant = 0; /* 0 defaults, 1 compensated, 2 the CDF sampler, 3 the alias sampler, 4 importance TEXEL */
static const char *variant_name[5] = {"", " compensated", " CDF sampler", " alias sampler", " importance TEXEL"};
static el_result make_light(el_envlight *l, const float *px, int rotated) {
  el_envlight_options o;
  memset(&o, 0, sizeof o);
  o.compensated = g_variant == 1;
  if (g_variant == 2) o.sampler = EL_ENVLIGHT_SAMPLER_CDF;
  if (g_variant == 3) o.sampler = EL_ENVLIGHT_SAMPLER_ALIAS;
  if (g_variant == 4) o.importance = EL_ENVLIGHT_IMPORTANCE_TEXEL;
  if (rotated) rotation37(o.light_to_world);
  return el_envlight_init(l, px, W, H, 3, &o);
}

/* ---- 1. detection ---- */
static void test_detection(void) {
  static float px[MAXWH * 3];
  int kind, rot;
  for (rot = 0; rot < 2; ++rot)
    for (kind = 0; kind < MAP_COUNT; ++kind) {
      el_envlight l;
      el_envlight_hotspots h;
      double d[2][3];
      float m[9];
      int ns = sun_dirs(kind, d), k, s, i, n = 100000;
      make_map(kind, px);
      if (make_light(&l, px, rot) != EL_SUCCESS) { check(0, "init %s", map_name[kind]); continue; }
      rotation37(m);
      if (rot) for (s = 0; s < ns; ++s) { float a[3], b[3]; a[0] = (float)d[s][0]; a[1] = (float)d[s][1]; a[2] = (float)d[s][2]; mul(m, a, b); d[s][0] = b[0]; d[s][1] = b[1]; d[s][2] = b[2]; }
      check(el_envlight_hotspots_init(&h, &l, NULL) == EL_SUCCESS, "hotspots_init %s%s", map_name[kind], rot ? " (rotated)" : "");
      check(h.count == ns, "%s%s: %d spots found (%d put)", map_name[kind], rot ? " (rotated)" : "", h.count, ns);
      for (k = 0; k < h.count && k < ns; ++k) {
        double best = 10;
        int inside = 0;
        for (s = 0; s < ns; ++s) { double a = angle_between(d[s], h.spot[k].axis); if (a < best) best = a; }
        /* the share against the frequency with which sample_li lands in the cone (which holds the spot) */
        for (i = 0; i < n; ++i) {
          float u[2], wi[3], pdf;
          double c;
          u[0] = rng_f(&g_rng); u[1] = rng_f(&g_rng);
          el_envlight_sample_li(&l, u, wi, NULL, &pdf);
          c = wi[0] * h.spot[k].axis[0] + wi[1] * h.spot[k].axis[1] + wi[2] * h.spot[k].axis[2];
          if (c >= cos(h.spot[k].half_angle) - 1e-6) ++inside;
        }
        check(best <= h.spot[k].half_angle + 1e-6 && h.spot[k].half_angle < 6.0 * PI / H,
              "%s%s spot %d: share %.4f, cone %.2f deg (< 6 bins) holds the sun (%.2f deg off axis)",
              map_name[kind], rot ? " (rotated)" : "", k, h.spot[k].share, h.spot[k].half_angle * 180 / PI, best * 180 / PI);
        check(h.spot[k].share > 0.3 && (double)inside / n >= h.spot[k].share - 0.006 && (double)inside / n <= h.spot[k].share + 0.06,
              "%s%s spot %d: sample_li lands in its cone %.4f of the time (share %.4f, the cone may hold a little more)",
              map_name[kind], rot ? " (rotated)" : "", k, (double)inside / n, h.spot[k].share);
      }
      if (h.count >= 2) check(h.spot[0].share >= h.spot[1].share, "%s: spots sorted by share", map_name[kind]);
      {
        double tot = h.rest_share;
        for (k = 0; k < h.count; ++k) tot += h.spot[k].share;
        check(fabs(tot - 1) < 1e-5, "%s%s: shares + rest sum to 1 (%.7f)", map_name[kind], rot ? " (rotated)" : "", tot);
      }
      el_envlight_hotspots_free(&h);
      el_envlight_free(&l);
    }
  { /* no spot: a constant light, a black map; importance BILINEAR: its spots (section 7), no mixture */
    el_envlight l;
    el_envlight_hotspots h;
    el_envlight_options o;
    float rgb[3] = {1, 1, 1};
    el_envlight_init_constant(&l, rgb, NULL);
    check(el_envlight_hotspots_init(&h, &l, NULL) == EL_SUCCESS && h.count == 0 && h.rest_share == 1.0f, "constant light: no spot");
    el_envlight_hotspots_free(&h); el_envlight_free(&l);
    memset(px, 0, sizeof px);
    el_envlight_init(&l, px, W, H, 3, NULL);
    check(el_envlight_hotspots_init(&h, &l, NULL) == EL_SUCCESS && h.count == 0, "black map: no spot");
    el_envlight_hotspots_free(&h); el_envlight_free(&l);
    make_map(MAP_ONE, px);
    memset(&o, 0, sizeof o);
    o.importance = EL_ENVLIGHT_IMPORTANCE_BILINEAR;
    el_envlight_init(&l, px, W, H, 3, &o);
    { /* the mixture samplers are sample_li there (no mixture tables), bit for bit */
      float u[2] = {0.3f, 0.7f}, wa[3], wb[3], pa, pb;
      el_envlight_mix_weights mw;
      memset(&mw, 0, sizeof mw); mw.spot[0] = 1.0f;
      el_envlight_hotspots_init(&h, &l, NULL);
      el_envlight_sample_li_mix(&l, &h, &mw, u, wa, NULL, &pa);
      el_envlight_sample_li(&l, u, wb, NULL, &pb);
      check(h.count == 1 && !memcmp(wa, wb, sizeof wa) && !memcmp(&pa, &pb, sizeof pa) &&
            el_envlight_pdf_li_mix(&l, &h, &mw, wa) == el_envlight_pdf_li(&l, wa),
            "importance BILINEAR: its one spot found (%d), sample_li_mix / pdf_li_mix are sample_li / pdf_li", h.count);
    }
    el_envlight_hotspots_free(&h); el_envlight_free(&l);
  }
}

/* ---- 7. importance BILINEAR: sample_li_spot / pdf_li_spot (NOTES ON HOT SPOTS 6) ---- */
enum { SPOT_1E12 = MAP_COUNT, SPOT_WEAK, SPOT_HORIZON, SPOT_KINDS };
static const char *spot_name(int kind) {
  return kind == SPOT_1E12 ? "one texel at 1e12" : kind == SPOT_WEAK ? "weak sun (city-like)" : kind == SPOT_HORIZON ? "sunrise-like" : map_name[kind];
}
static void spot_map(int kind, float *px) {
  int c, x, y;
  make_map(kind < MAP_COUNT ? kind : MAP_NONE, px);
  for (c = 0; c < 3; ++c) {
    if (kind == SPOT_1E12) px[3 * (12 * W + 70) + c] = 1e12f;
    if (kind == SPOT_WEAK) for (y = 20; y < 22; ++y) for (x = 40; x < 42; ++x) px[3 * (y * W + x) + c] = 250.0f;
    if (kind == SPOT_HORIZON) for (y = H / 2 - 4; y < H / 2 - 1; ++y) for (x = 10; x < 13; ++x) px[3 * (y * W + x) + c] = 1e4f;
  }
}
/* where a light-space direction falls: patch column (texel centres i .. i + 1), patch row (h + 1 rows, the
 * pole rows half), each split 2 x 2: the bin index in (2 W) x (2 (H + 1)) */
static int patch_bin(const float d[3]) {
  double u = atan2((double)d[1], (double)d[0]) / (2 * PI), v = acos(d[2] / sqrt((double)d[0] * d[0] + (double)d[1] * d[1] + (double)d[2] * d[2])) / PI;
  double pu, pv;
  int i, r, a, b;
  if (u < 0) u += 1;
  pu = u * W - 0.5; if (pu < 0) pu += W;
  i = (int)pu; if (i >= W) i = W - 1;
  if (v < 0.5 / H) { r = 0; pv = v * 2 * H; }
  else if (v >= 1 - 0.5 / H) { r = H; pv = (v - (1 - 0.5 / H)) * 2 * H; }
  else { pv = v * H + 0.5; r = (int)pv; if (r > H - 1) r = H - 1; if (r < 1) r = 1; pv -= r; }
  a = (int)((pu - i) * 2); b = (int)(pv * 2);
  a = a < 0 ? 0 : a > 1 ? 1 : a; b = b < 0 ? 0 : b > 1 ? 1 : b;
  return (2 * r + b) * 2 * W + 2 * i + a;
}
/* the light-space direction at the centre of sub-bin (column x of 2 W, row y of 2 (H + 1)) and its solid
 * angle element sin(theta) du dv (u, v in radians) */
static double patch_bin_at(int x, int y, double fx, double fy, double q, double d[3]) { /* (fx, fy): where in it */
  int r = y / 2, b = y % 2;
  double v0, v1, u = ((x + fx) / 2.0 + 0.5) / W, v;
  if (r == 0) { v0 = 0.25 * b / H; v1 = v0 + 0.25 / H; }
  else if (r == H) { v0 = 1 - 0.5 / H + 0.25 * b / H; v1 = v0 + 0.25 / H; }
  else { v0 = (r - 0.5 + 0.5 * b) / H; v1 = v0 + 0.5 / H; }
  v = v0 + fy * (v1 - v0);
  if (u >= 1) u -= 1;
  uv_dir(u, v, d);
  return sin(PI * v) * (PI * (v1 - v0)) * (2 * PI / (2.0 * W)) / (q * q); /* q x q points */
}
static double patch_bin_dir(int x, int y, double d[3]) { return patch_bin_at(x, y, 0.5, 0.5, 1, d); }
/* the integral of lum(le) over sub-bin (x, y) (light space; m: the light's rotation or NULL), 8 x 8 points */
static double patch_bin_le(const el_envlight *l, const float *m, int x, int y) {
  double sum = 0;
  int a, b;
  for (b = 0; b < 8; ++b)
    for (a = 0; a < 8; ++a) {
      double dd[3], dw = patch_bin_at(x, y, (a + 0.5) / 8, (b + 0.5) / 8, 8, dd);
      float f[3], g[3], rgb[3];
      f[0] = (float)dd[0]; f[1] = (float)dd[1]; f[2] = (float)dd[2];
      if (m) mul(m, f, g); else memcpy(g, f, sizeof f);
      el_envlight_le(l, g, rgb);
      sum += (0.212671 * rgb[0] + 0.715160 * rgb[1] + 0.072169 * rgb[2]) * dw;
    }
  return sum;
}
static void spot_test(int kind, int rot, int comp) {
  static float px[MAXWH * 3];
  static double expect[2 * 513 * 2 * 257], obs[2 * 513 * 2 * 257], lum_ref[2 * 513 * 2 * 257];
  el_envlight l;
  el_envlight_hotspots h;
  el_envlight_options o;
  float m[9];
  int k, nb = 2 * W * 2 * (H + 1), i, n = 100000;
  char name[96];
  spot_map(kind, px);
  memset(&o, 0, sizeof o);
  o.importance = EL_ENVLIGHT_IMPORTANCE_BILINEAR;
  o.compensated = comp;
  if (rot) rotation37(o.light_to_world);
  rotation37(m);
  snprintf(name, sizeof name, "spot %s %dx%d%s%s", spot_name(kind), W, H, rot ? " rotated" : "", comp ? " compensated" : "");
  if (el_envlight_init(&l, px, W, H, 3, &o) != EL_SUCCESS || el_envlight_hotspots_init(&h, &l, NULL) != EL_SUCCESS) { check(0, "%s: init", name); return; }
  check(kind == MAP_NONE ? h.count == 0 : h.count == (kind == MAP_TWO ? 2 : 1), "%s: %d spots (share %.3f, half-angle %.2f deg)", name, h.count,
        h.count ? h.spot[0].share : 0.0f, h.count ? h.spot[0].half_angle * 180 / PI : 0.0);
  for (k = 0; k < h.count; ++k) {
    double total = 0, x2, pval, mean = 0, m2 = 0, ref = 0, sd;
    int mismatch = 0, bad = 0, dof, impossible = 0, outside = 0, uncovered = 0;
    for (i = 0; i < nb; ++i) { /* exact for pdf x sin(theta), bilinear over each patch: the midpoint of each quarter */
      double dd[3], dw = patch_bin_dir(i % (2 * W), i / (2 * W), dd);
      float a[3], b[3], p;
      a[0] = (float)dd[0]; a[1] = (float)dd[1]; a[2] = (float)dd[2];
      if (rot) mul(m, a, b); else memcpy(b, a, sizeof a);
      p = el_envlight_pdf_li_spot(&l, &h, k, b);
      expect[i] = p * dw;
      total += expect[i];
      lum_ref[i] = 0;
      if (p > 0) { lum_ref[i] = patch_bin_le(&l, rot ? m : NULL, i % (2 * W), i / (2 * W)); ref += lum_ref[i]; }
      obs[i] = 0;
      { /* pdf 0 outside a few texels around the cone; every direction of the cone inside (where pdf_li > 0) */
        double ang = angle_between(dd, h.spot[k].axis), tex = PI / H;
        float ax[3];
        if (rot) { mul_t(m, h.spot[k].axis, ax); ang = angle_between(dd, ax); }
        if (p > 0 && ang > 1.5 * (h.spot[k].half_angle + 2 * tex) && !(kind == MAP_POLE)) ++outside; /* (a rectangle's corners) */
        if (ang < h.spot[k].half_angle && !(p > 0) && el_envlight_pdf_li(&l, b) > 0) ++uncovered;
      }
    }
    for (i = 0; i < n; ++i) {
      float u[2], wi[3], rgb[3], pdf, q, d[3], f;
      u[0] = rng_f(&g_rng); u[1] = rng_f(&g_rng);
      el_envlight_sample_li_spot(&l, &h, k, u, wi, rgb, &pdf);
      q = el_envlight_pdf_li_spot(&l, &h, k, wi);
      if (memcmp(&q, &pdf, sizeof q)) ++mismatch;
      if (!(pdf > 0) || !isfinite(pdf) || !isfinite(rgb[0]) || !isfinite(wi[0])) { ++bad; continue; }
      if (rot) mul_t(m, wi, d); else memcpy(d, wi, sizeof d);
      obs[patch_bin(d)]++;
      f = (float)((0.212671 * rgb[0] + 0.715160 * rgb[1] + 0.072169 * rgb[2]) / pdf);
      mean += f; m2 += (double)f * f;
    }
    mean /= n; sd = sqrt((m2 / n - mean * mean) / n);
    x2 = chisq_pooled(expect, obs, (size_t)nb, total, n, &impossible, &dof);
    pval = dof > 1 ? gammq(0.5 * (dof - 1), 0.5 * x2) : 1.0;
    check(pval > 1e-3 && impossible == 0 && fabs(total - 1) < 2e-3, "%s [%d]: chi2 %.1f, %d dof, p = %.3g, pdf integrates to %.5f, %d bins hit at pdf 0",
          name, k, x2, dof - 1, pval, total, impossible);
    check(mismatch == 0 && bad == 0, "%s [%d]: sampled pdf == pdf_li_spot(wi) bit for bit (%d of %d differ, %d bad)", name, k, mismatch, n, bad);
    check(outside == 0 && uncovered == 0, "%s [%d]: pdf 0 beyond 1.5 x (the cone + 2 texels) (%d bins), > 0 over the cone (%d uncovered)", name, k, outside, uncovered);
    check(fabs(mean - ref) < 4.5 * sd + 2e-3 * ref, "%s [%d]: unbiased, mean of lum(le) / pdf %.6g, quadrature over the rectangle %.6g (%.1f sd)",
          name, k, mean, ref, fabs(mean - ref) / (sd > 0 ? sd : 1));
  }
  { /* hostile: NaN, zero, infinite directions; NaN u; k out of range; another light's spots */
    float z[3] = {0, 0, 0}, nn[3] = {NAN, 0, 1}, inf[3] = {INFINITY, 0, 0}, u[2] = {NAN, 0.5f}, u2[2] = {0.5f, 0.5f}, wi[3], rgb[3], pdf;
    int ok = 1, kk;
    el_envlight l2;
    for (kk = -1; kk <= h.count; ++kk) {
      ok &= el_envlight_pdf_li_spot(&l, &h, kk, z) == 0 && el_envlight_pdf_li_spot(&l, &h, kk, nn) == 0 && el_envlight_pdf_li_spot(&l, &h, kk, inf) == 0;
      el_envlight_sample_li_spot(&l, &h, kk, u, wi, rgb, &pdf);
      ok &= pdf == 0 && isfinite(wi[0]) && isfinite(wi[1]) && isfinite(wi[2]) && rgb[0] == 0;
    }
    el_envlight_sample_li_spot(&l, &h, h.count, u2, wi, rgb, &pdf);
    ok &= pdf == 0 && el_envlight_pdf_li_spot(&l, NULL, 0, wi) == 0 && el_envlight_pdf_li_spot(NULL, &h, 0, wi) == 0;
    for (kk = 0; kk < h.count; ++kk) { /* a sample's direction scaled tiny and huge: the same pdf */
      float t[3], b[3];
      int c;
      el_envlight_sample_li_spot(&l, &h, kk, u2, wi, rgb, &pdf);
      for (c = 0; c < 3; ++c) { t[c] = ldexpf(wi[c], -100); b[c] = ldexpf(wi[c], 100); } /* (exact scalings) */
      ok &= pdf > 0 && fabsf(el_envlight_pdf_li_spot(&l, &h, kk, t) - pdf) <= 1e-5f * pdf && fabsf(el_envlight_pdf_li_spot(&l, &h, kk, b) - pdf) <= 1e-5f * pdf;
      /* (to 1e-5: pdf_li itself, which rescales the direction, is not bit for bit across scales) */
    }
    o.compensated = !comp;
    if (el_envlight_init(&l2, px, W, H, 3, &o) == EL_SUCCESS) {
      el_envlight_sample_li_spot(&l2, &h, 0, u2, wi, rgb, &pdf);
      ok &= pdf == 0 && el_envlight_pdf_li_spot(&l2, &h, 0, wi) == 0;
      el_envlight_free(&l2);
    } else ok = 0;
    check(ok, "%s: NaN / zero / infinite directions, NaN u, k out of range, NULL, another light's spots: pdf 0; tiny and huge directions: the unit one's pdf (1e-5)", name);
  }
  el_envlight_hotspots_free(&h);
  el_envlight_free(&l);
}
static void test_spot(void) {
  int kind;
  { /* the other importance modes: spot k is sample_li_mix with its weight alone, bit for bit */
    static float px[MAXWH * 3];
    el_envlight l;
    el_envlight_hotspots h;
    int i, k, bad = 0;
    make_map(MAP_TWO, px);
    make_light(&l, px, 1);
    el_envlight_hotspots_init(&h, &l, NULL);
    for (k = 0; k < h.count; ++k)
      for (i = 0; i < 1000; ++i) {
        el_envlight_mix_weights w;
        float u[2], wa[3], wb[3], ra[3], rb[3], pa, pb;
        memset(&w, 0, sizeof w); w.spot[k] = 1.0f;
        u[0] = rng_f(&g_rng); u[1] = rng_f(&g_rng);
        el_envlight_sample_li_spot(&l, &h, k, u, wa, ra, &pa);
        el_envlight_sample_li_mix(&l, &h, &w, u, wb, rb, &pb);
        bad += memcmp(wa, wb, sizeof wa) || memcmp(ra, rb, sizeof ra) || memcmp(&pa, &pb, sizeof pa) || !(pa > 0) ||
               el_envlight_pdf_li_spot(&l, &h, k, wa) != el_envlight_pdf_li_mix(&l, &h, &w, wa);
      }
    check(h.count == 2 && bad == 0, "spot two suns, the default importance, rotated: sample_li_spot / pdf_li_spot are sample_li_mix / pdf_li_mix "
          "with the spot's weight alone (%d of %d differ)", bad, 1000 * h.count);
    el_envlight_hotspots_free(&h);
    el_envlight_free(&l);
  }
  for (kind = 0; kind < SPOT_KINDS; ++kind) spot_test(kind, kind == MAP_SEAM || kind == SPOT_HORIZON, 0);
  spot_test(MAP_TWO, 1, 0);
  spot_test(SPOT_HORIZON, 0, 1);
  g_w = 512; g_h = 256; /* the fast path (maps of at least 256 x 128): no atan */
  spot_test(SPOT_HORIZON, 0, 0);
  spot_test(MAP_SEAM, 1, 0);
  spot_test(MAP_POLE, 0, 0);
  g_w = 128; g_h = 64;
}

/* ---- 2. default weights ---- */
static void test_defaults(void) {
  static float px[MAXWH * 3];
  el_envlight l;
  el_envlight_hotspots h;
  el_envlight_mix_weights w[6], ws;
  const char *wname[6] = {"all zero", "NaN", "negative", "infinite", "NULL", "rest only on a map... (zero sum)"};
  int i, t, bad_s = 0, bad_p = 0, k, rot;
  for (rot = 0; rot < 2; ++rot) {
    make_map(MAP_TWO, px);
    make_light(&l, px, rot);
    el_envlight_hotspots_init(&h, &l, NULL);
    memset(w, 0, sizeof w);
    w[1].spot[0] = NAN; w[1].rest = 1;
    w[2].spot[1] = -0.5f; w[2].rest = 1;
    w[3].rest = INFINITY;
    w[5].spot[5] = 1.0f; /* a spot that does not exist: ignored, so the sum is 0 */
    for (t = 0; t < 6; ++t) {
      bad_s = bad_p = 0;
      for (i = 0; i < 20000; ++i) {
        float u[2], a[3], b[3], ra[3], rb[3], pa, pb, d[3];
        const el_envlight_mix_weights *wp = t == 4 ? NULL : &w[t];
        u[0] = rng_f(&g_rng); u[1] = rng_f(&g_rng);
        el_envlight_sample_li(&l, u, a, ra, &pa);
        el_envlight_sample_li_mix(&l, &h, wp, u, b, rb, &pb);
        if (memcmp(a, b, sizeof a) || memcmp(ra, rb, sizeof ra) || memcmp(&pa, &pb, sizeof pa)) ++bad_s;
        d[0] = 2 * rng_f(&g_rng) - 1; d[1] = 2 * rng_f(&g_rng) - 1; d[2] = 2 * rng_f(&g_rng) - 1;
        pa = el_envlight_pdf_li(&l, d); pb = el_envlight_pdf_li_mix(&l, &h, wp, d);
        if (memcmp(&pa, &pb, sizeof pa)) ++bad_p;
        pa = el_envlight_pdf_li(&l, a); pb = el_envlight_pdf_li_mix(&l, &h, wp, a);
        if (memcmp(&pa, &pb, sizeof pa)) ++bad_p;
      }
      check(bad_s == 0 && bad_p == 0, "default weights (%s)%s: sample_li_mix == sample_li, pdf_li_mix == pdf_li bit for bit (%d, %d differ)",
            wname[t], rot ? " rotated" : "", bad_s, bad_p);
    }
    /* explicit weights equal to the shares: pdf_li within 1e-6 */
    memset(&ws, 0, sizeof ws);
    for (k = 0; k < h.count; ++k) ws.spot[k] = h.spot[k].share;
    ws.rest = h.rest_share;
    {
      double worst = 0;
      for (i = 0; i < 40000; ++i) {
        float u[2], a[3], pa, pb;
        u[0] = rng_f(&g_rng); u[1] = rng_f(&g_rng);
        el_envlight_sample_li(&l, u, a, NULL, &pa);
        pa = el_envlight_pdf_li(&l, a);
        pb = el_envlight_pdf_li_mix(&l, &h, &ws, a);
        if (fabs(pb / pa - 1) > worst) worst = fabs(pb / pa - 1);
      }
      check(worst < 1e-6, "weights = the shares%s: pdf_li_mix / pdf_li - 1 <= %.2g", rot ? " rotated" : "", worst);
    }
    { /* sample_li_mix_n: n calls of sample_li_mix, bit for bit (moved and default weights) */
      float uu[2 * 37], wa[3 * 37], ra[3 * 37], pa[37], wb[3], rb[3], pb;
      int differ = 0, pass;
      for (pass = 0; pass < 2; ++pass) {
        el_envlight_hotspots_weights(&h, pass ? 0.1f : NAN, &ws);
        for (i = 0; i < 2 * 37; ++i) uu[i] = rng_f(&g_rng);
        el_envlight_sample_li_mix_n(&l, &h, &ws, 37, uu, wa, ra, pa);
        for (i = 0; i < 37; ++i) {
          el_envlight_sample_li_mix(&l, &h, &ws, uu + 2 * i, wb, rb, &pb);
          if (memcmp(wa + 3 * i, wb, sizeof wb) || memcmp(ra + 3 * i, rb, sizeof rb) || memcmp(pa + i, &pb, sizeof pb)) ++differ;
        }
      }
      check(differ == 0, "sample_li_mix_n == sample_li_mix bit for bit%s (%d differ)", rot ? " rotated" : "", differ);
    }
    el_envlight_hotspots_weights(&h, NAN, &ws);
    check(ws.rest == 0 && ws.spot[0] == 0, "hotspots_weights(NaN): the default weights (all zero)");
    el_envlight_hotspots_free(&h);
    el_envlight_free(&l);
  }
}

/* ---- 3. chi-square over the importance bins ---- */
static int g_chi2 = 0;
static const float *g_cosn = NULL; /* non-NULL: the rest x cosine mixture for this world normal */
static const el_envlight_mix_cos_table *g_cost = NULL; /* non-NULL: mix_pdf through this prepared (w, g_cosn) */
static void mix_sample(const el_envlight *l, const el_envlight_hotspots *h, const el_envlight_mix_weights *w, const float u[2], float wi[3], float rgb[3], float *pdf) {
  if (g_cosn) el_envlight_sample_li_mix_cos(l, h, w, g_cosn, u, wi, rgb, pdf);
  else el_envlight_sample_li_mix(l, h, w, u, wi, rgb, pdf);
}
static float mix_pdf(const el_envlight *l, const el_envlight_hotspots *h, const el_envlight_mix_weights *w, const float d[3]) {
  if (g_cost) return el_envlight_pdf_li_mix_cos_table(l, h, g_cost, d); /* (== pdf_li_mix_cos bit for bit: test_table) */
  return g_cosn ? el_envlight_pdf_li_mix_cos(l, h, w, g_cosn, d) : el_envlight_pdf_li_mix(l, h, w, d);
}
/* the bin (x, y) of nu x nv lat-long bins that holds the light-space direction d, and d's (u, v), in double */
static void dir_bin(const float d[3], int nu, int nv, double *uu, double *vv, int *x, int *y) {
  float len = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  *uu = atan2(d[1], d[0]) / (2 * PI); if (*uu < 0) *uu += 1;
  *vv = acos(d[2] / len > 1 ? 1 : (d[2] / len < -1 ? -1 : d[2] / len)) / PI;
  *x = (int)(*uu * nu); *y = (int)(*vv * nv);
  if (*x >= nu) *x = nu - 1;
  if (*y >= nv) *y = nv - 1;
}
/* the integral of mix_pdf over bin (x, y) of nu x nv: pdf(centre) sin(theta_c) dtheta dphi, exact for the
 * mixtures' densities c / sin(theta) in a bin; m: the light's rotation (NULL: none) */
static double bin_mass(const el_envlight *l, const el_envlight_hotspots *h, const el_envlight_mix_weights *w, const float *m,
                       int x, int y, int nu, int nv) {
  double dd[3];
  float a[3], b[3];
  uv_dir((x + 0.5) / nu, (y + 0.5) / nv, dd);
  a[0] = (float)dd[0]; a[1] = (float)dd[1]; a[2] = (float)dd[2];
  if (m) mul(m, a, b); else memcpy(b, a, sizeof a);
  return mix_pdf(l, h, w, b) * sin(PI * (y + 0.5) / nv) * (PI / nv) * (2 * PI / nu);
}
#define CHI2_PLANNED 29
static void chi2(const char *name, int kind, int rot, float spot_share) {
  static float px[MAXWH * 3];
  static double expect[MAXWH];
  static int obs[MAXWH];
  el_envlight l;
  el_envlight_hotspots h;
  el_envlight_mix_weights w;
  float m[9];
  int i, n = g_cosn ? 100000 : 200000, mismatch = 0, nonfinite = 0, dof = -1, zero_pdf_hits = 0, k;
  double frac[2][16], fx2 = 0, fp;
  double x2 = 0, total = 0, pval, alpha = 0.01 / CHI2_PLANNED, spot_mass = 0, spot_obs = 0;
  make_map(kind, px);
  make_light(&l, px, rot);
  rotation37(m);
  el_envlight_hotspots_init(&h, &l, NULL);
  el_envlight_hotspots_weights(&h, spot_share, &w);
  memset(obs, 0, sizeof obs);
  memset(frac, 0, sizeof frac);
  for (i = 0; i < W * H; ++i) { /* the integral of pdf_li_mix over bin i */
    expect[i] = bin_mass(&l, &h, &w, rot ? m : NULL, i % W, i / W, W, H);
    total += expect[i];
  }
  for (i = 0; i < n; ++i) {
    float u[2], wi[3], rgb[3], pdf, q, d[3];
    double uu, vv;
    int x, y;
    u[0] = rng_f(&g_rng); u[1] = rng_f(&g_rng);
    mix_sample(&l, &h, &w, u, wi, rgb, &pdf);
    q = mix_pdf(&l, &h, &w, wi);
    if (memcmp(&q, &pdf, sizeof q)) ++mismatch;
    if (!isfinite(pdf) || !isfinite(rgb[0]) || !isfinite(wi[0]) || !(pdf > 0)) ++nonfinite;
    if (rot) mul_t(m, wi, d); else memcpy(d, wi, sizeof d);
    dir_bin(d, W, H, &uu, &vv, &x, &y);
    obs[y * W + x]++;
    { /* inside its bin the point is uniform in (u, v), as sample_li's */
      int fx = (int)((uu * W - x) * 16), fy = (int)((vv * H - y) * 16);
      frac[0][fx < 0 ? 0 : fx > 15 ? 15 : fx]++;
      frac[1][fy < 0 ? 0 : fy > 15 ? 15 : fy]++;
    }
  }
  { /* cells of agg x agg bins (128 x 64 cells; every bin alone on the 128 x 64 maps) */
    static double ce[128 * 64];
    static double co[128 * 64];
    int agg = W / 128;
    memset(ce, 0, sizeof ce); memset(co, 0, sizeof co);
    for (i = 0; i < W * H; ++i) {
      int c = (i / W / agg) * 128 + (i % W) / agg;
      if (expect[i] == 0 && obs[i]) ++zero_pdf_hits;
      ce[c] += expect[i]; co[c] += obs[i];
    }
    x2 = chisq_pooled(ce, co, 128 * 64, 1.0, n, NULL, &dof); /* (ce: probabilities) */
    dof -= 1;
  }
  pval = dof > 0 ? gammq(0.5 * dof, 0.5 * x2) : 1.0;
  ++g_chi2;
  check(pval > alpha && fabs(total - 1) < 2e-3 && zero_pdf_hits == 0,
        "chi2 %-22s%s%s%s spots %.3f: chi2 = %.1f, %d dof, p = %.3g (> %.2g), pdf sums to %.5f, %d hits in zero-pdf bins",
        name, rot ? " rotated" : "        ", variant_name[g_variant], g_cosn ? " x cos" : "", spot_share, x2, dof, pval, alpha, total, zero_pdf_hits);
  for (i = 0; i < 32; ++i) fx2 += (frac[i / 16][i % 16] - n / 16.0) * (frac[i / 16][i % 16] - n / 16.0) / (n / 16.0);
  fp = gammq(0.5 * 30, 0.5 * fx2);
  check(fp > alpha, "chi2 %-22s: uniform inside the bins in u and v (chi2 %.1f, 30 dof, p = %.3g)", name, fx2, fp);
  check(mismatch == 0 && nonfinite == 0, "chi2 %-22s: sampled pdf == pdf_li_mix(wi) for all %d samples (%d differ, %d non-finite / 0)",
        name, n, mismatch, nonfinite);
  /* the spots get exactly their weight: the mass of the expected counts in spot bins, and the draws
   * (hotspots_weights gives every spot the same factor weight / share) */
  for (k = 0; k < 1 && h.count > 0; ++k) {
    for (i = 0; i < W * H; ++i) {
      int x = i % W, y = i / W;
      double dd[3];
      float a[3], b[3], pm, pl;
      uv_dir((x + 0.5) / W, (y + 0.5) / H, dd);
      a[0] = (float)dd[0]; a[1] = (float)dd[1]; a[2] = (float)dd[2];
      if (rot) mul(m, a, b); else memcpy(b, a, sizeof a);
      pm = mix_pdf(&l, &h, &w, b); pl = el_envlight_pdf_li(&l, b);
      /* a spot bin: its mixture pdf / pdf_li is the spot's factor w / share */
      if (pl > 0 && fabs(pm / pl - w.spot[k] / h.spot[k].share) < 1e-4 * (w.spot[k] / h.spot[k].share) && w.spot[k] / h.spot[k].share != w.rest / h.rest_share) {
        spot_mass += expect[i]; spot_obs += obs[i];
      }
    }
  }
  if (h.count > 0 && spot_share != 1.0f && spot_share != 0.0f) {
    double sd = sqrt(spot_share * (1 - spot_share) / n);
    check(fabs(spot_mass - spot_share) < 2e-3 && fabs(spot_obs / n - spot_share) < 5 * sd + 1e-6,
          "chi2 %-22s: the spots hold %.5f of the pdf and %.5f of the samples (weight %.5f)", name, spot_mass, spot_obs / n, spot_share);
  }
  el_envlight_hotspots_free(&h);
  el_envlight_free(&l);
}

static void test_chi2(void) {
  chi2("two suns", MAP_TWO, 0, 0.3f);
  chi2("two suns", MAP_TWO, 1, 0.3f);
  chi2("two suns", MAP_TWO, 0, 1e-3f);
  chi2("two suns", MAP_TWO, 0, 0.999f);
  chi2("sun at the pole", MAP_POLE, 0, 0.2f);
  chi2("sun at the pole", MAP_POLE, 1, 0.05f);
  chi2("sun across the seam", MAP_SEAM, 0, 0.1f);
  chi2("sun across the seam", MAP_SEAM, 1, 0.9f);
  chi2("one-texel sun", MAP_ONE, 0, 0.02f);
  chi2("one-texel sun", MAP_ONE, 1, 0.5f);
  chi2("one-texel sun", MAP_ONE, 0, 1.0f);
  chi2("sun at the pole", MAP_POLE, 0, 0.0f);
  for (g_variant = 1; g_variant <= 4; ++g_variant) chi2("two suns", MAP_TWO, g_variant & 1, 0.2f);
  g_variant = 0;
  g_w = 512; g_h = 256; /* sample_li's direction tables: the mixture builds its directions with them */
  chi2("512x256 two suns", MAP_TWO, 0, 0.3f);
  chi2("512x256 seam", MAP_SEAM, 1, 0.05f);
  g_w = 128; g_h = 64;
  { /* the rest x cosine mixture: normals up, sideways, down, towards a sun; a NaN normal */
    static const float nup[3] = {0.3f, -0.2f, 0.93f}, nside[3] = {1, 0, 0}, ndown[3] = {0, 0.1f, -1}, nnan[3] = {NAN, 0, 1};
    g_cosn = nup; chi2("two suns", MAP_TWO, 0, 0.3f); chi2("sun at the pole", MAP_POLE, 1, 0.05f);
    g_cosn = nside; chi2("sun across the seam", MAP_SEAM, 1, 0.1f);
    g_cosn = ndown; chi2("two suns", MAP_TWO, 1, 0.0f);
    g_cosn = nnan; chi2("one-texel sun", MAP_ONE, 0, 0.2f);
    /* the direction tables (maps >= 256 x 128) under the cell tables: the renderer's case (a spot at its
     * 3% floor), plain and under a general rotation (a rounding into a massless bin: the bin's centre) */
    g_w = 512; g_h = 256;
    g_cosn = nup; chi2("512x256 two suns", MAP_TWO, 0, 0.03f);
    g_cosn = nside; chi2("512x256 seam", MAP_SEAM, 1, 0.03f);
    g_w = 128; g_h = 64;
    g_cosn = NULL;
  }
}

/* ---- 4. unbiasedness ---- */
static double cosine_integral_q(const el_envlight *l, const float n[3], const double sun[3], double cone, int qu, int qv, int qpu, int qpv) {
  /* brute force: qu x qv points per texel of le itself (qpu x qpv in the two rows at each pole, where
   * le x sin(theta) is far from linear), times the solid angle; 0 within `cone` of sun. An even count
   * per axis puts the texel centres, where le's bilinear pieces meet, on the points' cell edges */
  int x, y, a, b;
  double s = 0;
  for (y = 0; y < H; ++y) {
    int pole = y < 2 || y >= H - 2, q = pole ? qpv : qv, p = pole ? qpu : qu;
    for (b = 0; b < q; ++b) {
      double v = (y + (b + 0.5) / q) / H, dw = sin(PI * v) * (PI / (q * H)) * (2 * PI / (p * W));
      for (x = 0; x < W; ++x)
        for (a = 0; a < p; ++a) {
          double dd[3], c;
          float d[3], rgb[3];
          uv_dir((x + (a + 0.5) / p) / W, v, dd);
          c = n[0] * dd[0] + n[1] * dd[1] + n[2] * dd[2];
          if (c <= 0) continue;
          if (sun && dd[0] * sun[0] + dd[1] * sun[1] + dd[2] * sun[2] >= cos(cone)) continue;
          d[0] = (float)dd[0]; d[1] = (float)dd[1]; d[2] = (float)dd[2];
          el_envlight_le(l, d, rgb);
          s += rgb[1] * c * dw;
        }
    }
  }
  return s;
}
static double cosine_integral(const el_envlight *l, const float n[3], const double sun[3], double cone) {
  return cosine_integral_q(l, n, sun, cone, 4, 4, 16, 16); /* (4 x 4 was 0.9% off in the pole rows of 128 x 64) */
}

/* the mean of f / pdf and its standard error over count samples, f = le x max(0, n.w) (0 within `cone` of
 * sun when sun is non-NULL), from sample_li_mix_cos (cos_mix) or sample_li_mix */
static void estimate(const el_envlight *l, const el_envlight_hotspots *h, const el_envlight_mix_weights *w, const float n[3],
                     const double *sun, double cone, int cos_mix, int count, double *mean, double *sd) {
  double sum = 0, sum2 = 0;
  int i;
  for (i = 0; i < count; ++i) {
    float u[2], wi[3], rgb[3], pdf, c;
    double f = 0;
    u[0] = rng_f(&g_rng); u[1] = rng_f(&g_rng);
    if (cos_mix) el_envlight_sample_li_mix_cos(l, h, w, n, u, wi, rgb, &pdf);
    else el_envlight_sample_li_mix(l, h, w, u, wi, rgb, &pdf);
    c = n[0] * wi[0] + n[1] * wi[1] + n[2] * wi[2];
    if (pdf > 0 && c > 0 && !(sun && wi[0] * sun[0] + wi[1] * sun[1] + wi[2] * sun[2] >= cos(cone))) f = rgb[1] * c / pdf;
    sum += f; sum2 += f * f;
  }
  *mean = sum / count;
  *sd = sqrt((sum2 / count - *mean * *mean) / count);
}

static void unbiased(int kind, float spot_share, int shadow, int cos_mix) {
  static float px[MAXWH * 3];
  el_envlight l;
  el_envlight_hotspots h;
  el_envlight_mix_weights w;
  float n[3] = {0.3f, -0.2f, 0.93f};
  double ref, mean, sd, sun[3], cone = 0;
  int count = cos_mix ? 150000 : 400000;
  make_map(kind, px);
  make_light(&l, px, 0);
  el_envlight_hotspots_init(&h, &l, NULL);
  el_envlight_hotspots_weights(&h, spot_share, &w);
  if (shadow) { /* the sun's cone and a margin of 2 bins are occluded */
    sun[0] = h.spot[0].axis[0]; sun[1] = h.spot[0].axis[1]; sun[2] = h.spot[0].axis[2];
    cone = h.spot[0].half_angle + 2 * PI / H;
  }
  ref = cosine_integral(&l, n, shadow ? sun : NULL, cone);
  estimate(&l, &h, &w, n, shadow ? sun : NULL, cone, cos_mix, count, &mean, &sd);
  check(fabs(mean - ref) < 4.5 * sd + 2e-3 * ref,
        "unbiased %-20s%s spots %.2f%s: mean of f/pdf %.5f, quadrature %.5f (%.1f sd)", map_name[kind], cos_mix ? " x cos" : "", spot_share,
        shadow ? " (sun occluded)" : "", mean, ref, fabs(mean - ref) / (sd > 0 ? sd : 1));
  el_envlight_hotspots_free(&h);
  el_envlight_free(&l);
}

static void test_unbiased(void) {
  unbiased(MAP_TWO, 0.37f, 0, 0);
  unbiased(MAP_TWO, 0.9f, 0, 0);
  unbiased(MAP_ONE, 0.05f, 0, 0);
  unbiased(MAP_SEAM, 0.6f, 0, 0);
  unbiased(MAP_ONE, 0.0f, 1, 0); /* the sun's weight 0 where it is occluded: still unbiased */
  unbiased(MAP_TWO, 0.01f, 1, 0);
  unbiased(MAP_TWO, 0.37f, 0, 1);
  unbiased(MAP_POLE, 0.2f, 0, 1);
  unbiased(MAP_POLE, 0.2f, 0, 0);
  unbiased(MAP_ONE, 0.0f, 1, 1);
  unbiased(MAP_SEAM, 0.02f, 1, 1);
}

/* ---- 5. hostile inputs ---- */
static void test_hostile(void) {
  static float px[MAXWH * 3], px2[MAXWH * 3];
  el_envlight l, l2;
  el_envlight_hotspots h, h2;
  el_envlight_hotspot_options o;
  el_envlight_mix_weights w;
  int bad = 0, i, j, ok = 1;
  float us[6] = {0.0f, 0.99999994f, 1.0f, -1.0f, NAN, INFINITY};
  make_map(MAP_ONE, px);
  make_light(&l, px, 0);
  el_envlight_hotspots_init(&h, &l, NULL);
  el_envlight_hotspots_weights(&h, 0.5f, &w);
  for (i = 0; i < 6; ++i)
    for (j = 0; j < 6; ++j) {
      float u[2], wi[3], rgb[3], pdf;
      u[0] = us[i]; u[1] = us[j];
      el_envlight_sample_li_mix(&l, &h, &w, u, wi, rgb, &pdf);
      if (!isfinite(pdf) || !isfinite(wi[0]) || !isfinite(wi[1]) || !isfinite(wi[2]) || !isfinite(rgb[0]) || !(pdf > 0)) ++bad;
    }
  check(bad == 0, "u at 0, 1, -1, NaN, Inf: finite samples with pdf > 0 (%d bad)", bad);
  {
    float dz[3] = {0, 0, 0}, dn[3] = {NAN, 0, 1}, di[3] = {INFINITY, 0, 0}, dt[3] = {1e-30f, 0, 1e-30f}, db[3] = {3e38f, 0, 3e38f}, d1[3] = {1, 0, 1};
    check(el_envlight_pdf_li_mix(&l, &h, &w, dz) == 0 && el_envlight_pdf_li_mix(&l, &h, &w, dn) == 0 && el_envlight_pdf_li_mix(&l, &h, &w, di) == 0,
          "pdf_li_mix of a zero, NaN or infinite direction: 0");
    check(el_envlight_pdf_li_mix(&l, &h, &w, dt) == el_envlight_pdf_li_mix(&l, &h, &w, d1) &&
          el_envlight_pdf_li_mix(&l, &h, &w, db) == el_envlight_pdf_li_mix(&l, &h, &w, d1),
          "pdf_li_mix of tiny and huge directions: that of the direction");
  }
  /* options out of range */
  memset(&o, 0, sizeof o); o.min_share = NAN;
  ok &= el_envlight_hotspots_init(&h2, &l, &o) == EL_ERROR_INVALID_ARGUMENT && h2.count == 0;
  memset(&o, 0, sizeof o); o.min_radiance = -1;
  ok &= el_envlight_hotspots_init(&h2, &l, &o) == EL_ERROR_INVALID_ARGUMENT;
  memset(&o, 0, sizeof o); o.max_half_angle = INFINITY;
  ok &= el_envlight_hotspots_init(&h2, &l, &o) == EL_ERROR_INVALID_ARGUMENT;
  memset(&o, 0, sizeof o); o.max_spots = EL_ENVLIGHT_HOTSPOT_MAX + 1;
  ok &= el_envlight_hotspots_init(&h2, &l, &o) == EL_ERROR_INVALID_ARGUMENT;
  memset(&o, 0, sizeof o); o.min_share = 2;
  ok &= el_envlight_hotspots_init(&h2, &l, &o) == EL_ERROR_INVALID_ARGUMENT;
  ok &= el_envlight_hotspots_init(NULL, &l, NULL) == EL_ERROR_INVALID_ARGUMENT;
  ok &= el_envlight_hotspots_init(&h2, NULL, NULL) == EL_ERROR_INVALID_ARGUMENT;
  check(ok, "bad options (NaN, negative, infinite, too many spots, share > 1) and NULL: EL_ERROR_INVALID_ARGUMENT");
  el_envlight_hotspots_free(&h2);
  el_envlight_hotspots_free(&h2); /* twice: safe */
  /* the hot spots of another light: the mixture falls back to sample_li / pdf_li of this light */
  make_map(MAP_TWO, px2);
  make_light(&l2, px2, 0);
  el_envlight_hotspots_init(&h2, &l2, NULL);
  bad = 0;
  for (i = 0; i < 2000; ++i) {
    float u[2], a[3], b[3], pa, pb;
    u[0] = rng_f(&g_rng); u[1] = rng_f(&g_rng);
    el_envlight_sample_li(&l, u, a, NULL, &pa);
    el_envlight_sample_li_mix(&l, &h2, &w, u, b, NULL, &pb);
    if (memcmp(a, b, sizeof a) || pa != pb || el_envlight_pdf_li_mix(&l, &h2, &w, a) != el_envlight_pdf_li(&l, a)) ++bad;
  }
  check(bad == 0, "hot spots made for another light: sample_li and pdf_li of this one (%d differ)", bad);
  { /* a light whose whole mass is one spot (black sky): the rest's weight cannot be drawn */
    el_envlight l3;
    el_envlight_hotspots h3;
    memset(px2, 0, sizeof px2);
    px2[3 * (20 * W + 40)] = px2[3 * (20 * W + 40) + 1] = px2[3 * (20 * W + 40) + 2] = 100;
    el_envlight_init(&l3, px2, W, H, 3, NULL);
    memset(&o, 0, sizeof o);
    o.min_radiance = 1; /* every bin with mass is hot */
    el_envlight_hotspots_init(&h3, &l3, &o);
    w.spot[0] = 0.5f; w.rest = 0.5f;
    bad = 0;
    for (i = 0; i < 2000; ++i) {
      float u[2], a[3], pa;
      u[0] = rng_f(&g_rng); u[1] = rng_f(&g_rng);
      el_envlight_sample_li_mix(&l3, &h3, &w, u, a, NULL, &pa);
      if (!(pa > 0) || fabsf(pa - el_envlight_pdf_li(&l3, a)) > 1e-5f * pa) ++bad;
    }
    check(h3.count == 1 && h3.rest_share == 0 && bad == 0, "a black sky and one sun: %d spot, rest share %g, the rest's weight goes to the sun (%d bad)",
          h3.count, h3.rest_share, bad);
    el_envlight_hotspots_free(&h3);
    el_envlight_free(&l3);
  }
  el_envlight_hotspots_free(&h2);
  el_envlight_hotspots_free(&h);
  el_envlight_free(&l2);
  el_envlight_free(&l);
}

/* el_envlight_mix_cos_prepare + the _table calls (the renderer's sun cache: one table per shading normal,
 * reused for many samples and pdfs) give sample_li_mix_cos's and pdf_li_mix_cos's results bit for bit,
 * whichever calls came between, for normals up, sideways, down, zero, and spot weights 0, 0.03, default */
static void test_table(void) {
  static float px[MAXWH * 3];
  static const float normals[5][3] = {{0, 0, 1}, {1, 0, 0}, {0, 0.6f, -0.8f}, {0.3f, -0.5f, 0.81f}, {0, 0, 0}};
  el_envlight l;
  el_envlight_hotspots h;
  int rot, ni, wi_, i, bad = 0, calls = 0;
  for (rot = 0; rot < 2; ++rot) {
    make_map(MAP_ONE, px);
    make_light(&l, px, rot);
    el_envlight_hotspots_init(&h, &l, NULL);
    for (ni = 0; ni < 5; ++ni)
      for (wi_ = 0; wi_ < 3; ++wi_) {
        el_envlight_mix_weights w;
        el_envlight_mix_cos_table t;
        memset(&w, 0, sizeof w);
        if (wi_ < 2) { w.spot[0] = wi_ == 0 ? 0.0f : 0.03f; w.rest = 1.0f; }
        el_envlight_mix_cos_prepare(&l, &h, &w, normals[ni], &t);
        for (i = 0; i < 2000; ++i) {
          float u[2], a[3], b[3], ra[3], rb[3], pa, pb, d[3];
          u[0] = rng_f(&g_rng); u[1] = rng_f(&g_rng);
          el_envlight_sample_li_mix_cos(&l, &h, &w, normals[ni], u, a, ra, &pa);
          el_envlight_sample_li_mix_cos_table(&l, &h, &t, u, b, rb, &pb);
          if (memcmp(a, b, sizeof a) || memcmp(ra, rb, sizeof ra) || memcmp(&pa, &pb, sizeof pa)) ++bad;
          d[0] = 2 * rng_f(&g_rng) - 1; d[1] = 2 * rng_f(&g_rng) - 1; d[2] = 2 * rng_f(&g_rng) - 1;
          pa = el_envlight_pdf_li_mix_cos(&l, &h, &w, normals[ni], d); pb = el_envlight_pdf_li_mix_cos_table(&l, &h, &t, d);
          if (memcmp(&pa, &pb, sizeof pa)) ++bad;
          pa = el_envlight_pdf_li_mix_cos(&l, &h, &w, normals[ni], a); pb = el_envlight_pdf_li_mix_cos_table(&l, &h, &t, a);
          if (memcmp(&pa, &pb, sizeof pa) || !(pa > 0.0f)) ++bad;
          calls += 3;
        }
      }
    el_envlight_hotspots_free(&h);
    el_envlight_free(&l);
  }
  check(bad == 0, "mix_cos_prepare + the _table calls == sample_li_mix_cos / pdf_li_mix_cos bit for bit, one table reused (%d of %d differ)", bad, calls);
}

/* ---- 6. cells of more than 256 bins a side: the rest x cosine tables' binary search ---- */
/* The rest x cosine part cuts the importance bins into 32 x 16 cells (el_envlight_hotspots' cell_u0 and
 * cell_v0); a cell row of more than 256 bins (nu > 8192) or a cell of more than 256 rows (nv > 4096) has no
 * guide table and is searched by bisection (el_envlight__hot_search). Two maps reach it, each with the
 * image's own resolution as its importance grid (the default cell averages; no cap): 8208 x 32 (cells of
 * 256 and 257 bins across, alternately: the guide and the bisection side by side) and 128 x 4104 (cells of
 * 256 and 257 rows). Along the long axis the sky is sparse, 2 lit texels in 24 with random values and the
 * first and last texel of every cell, so a bin's mass differs from its neighbours' (the bilinear spill:
 * 1/8 of a lit neighbour; 0 beyond) and a search one bin off, or one that never reaches a cell's last
 * bin, shows in the chi-square or as samples with pdf 0; a 24-texel sun gives the spot. */
#define LONG_MAXB (128 * 4104)
static int long_lit(int p, int n, int cells) { /* 2 in 24, and the first and last of each cell (el_envlight__hot_cells' split) */
  int c;
  for (c = 0; c <= cells; ++c) if (p == c * n / cells || p == c * n / cells - 1) return 1;
  return p % 24 < 2;
}
static void long_map(int tall, float *px) {
  int x, y, c;
  for (y = 0; y < H; ++y)
    for (x = 0; x < W; ++x) {
      double v = (y + 0.5) / H, r = hash32((uint32_t)(y * W + x) * 2654435761u) / 4294967296.0;
      double val = long_lit(tall ? y : x, tall ? H : W, tall ? 16 : 32) ? (0.2 + 2.8 * r) * (v < 0.5 ? 1.0 : 0.25) : 0.0;
      for (c = 0; c < 3; ++c) px[3 * (y * W + x) + c] = (float)(val * (c == 2 ? 1.2 : 1.0));
    }
  for (y = 0; y < (tall ? 24 : 1); ++y)
    for (x = 0; x < (tall ? 2 : 24); ++x)
      for (c = 0; c < 3; ++c) px[3 * ((y + (tall ? 1500 : 10)) * W + x + (tall ? 40 : 3000)) + c] = 3e3f;
}
static el_result long_light(el_envlight *l, const float *px) {
  el_envlight_options o;
  memset(&o, 0, sizeof o);
  o.importance_width = W; o.importance_height = H;
  return el_envlight_init(l, px, W, H, 3, &o);
}
/* the cells (across for rows, down for tall) longer than 256 bins, and those of 256 or fewer */
static void long_cells(const el_envlight_hotspots *h, int tall, int *longer, int *shorter) {
  int c, nc = tall ? h->cells_v : h->cells_u;
  const int *c0 = tall ? h->cell_v0 : h->cell_u0;
  *longer = *shorter = 0;
  for (c = 0; c < nc; ++c) { if (c0[c + 1] - c0[c] > 256) ++*longer; else ++*shorter; }
}
static void long_chi2(const el_envlight *l, const el_envlight_hotspots *h, const char *name, int tall, const float n[3],
                      float spot_share, int count) {
  static double expect[LONG_MAXB], obs[LONG_MAXB];
  el_envlight_mix_weights w;
  el_envlight_mix_cos_table t;
  const int *c0 = tall ? h->cell_v0 : h->cell_u0;
  int i, dof = 0, mismatch = 0, mismatch_t = 0, bad = 0, zero_hits = 0, in_long = 0;
  double total = 0, x2, pval;
  el_envlight_hotspots_weights(h, spot_share, &w);
  g_cosn = n;
  el_envlight_mix_cos_prepare(l, h, &w, n, &t);
  g_cost = &t; /* (the expected counts of 263 K / 525 K bins: 5x faster than pdf_li_mix_cos) */
  for (i = 0; i < W * H; ++i) { expect[i] = bin_mass(l, h, &w, NULL, i % W, i / W, W, H); total += expect[i]; obs[i] = 0; }
  g_cost = NULL;
  for (i = 0; i < count; ++i) {
    float u[2], wi[3], rgb[3], pdf, q, wt[3], rt[3], pt;
    double uu, vv;
    int x, y, c = 0;
    u[0] = rng_f(&g_rng); u[1] = rng_f(&g_rng);
    el_envlight_sample_li_mix_cos(l, h, &w, n, u, wi, rgb, &pdf);
    q = el_envlight_pdf_li_mix_cos(l, h, &w, n, wi);
    if (memcmp(&q, &pdf, sizeof q)) ++mismatch;
    el_envlight_sample_li_mix_cos_table(l, h, &t, u, wt, rt, &pt); /* the prepared table's sample: the same bits */
    if (memcmp(wt, wi, sizeof wt) || memcmp(rt, rgb, sizeof rt) || memcmp(&pt, &pdf, sizeof pt)) ++mismatch_t;
    if (!(pdf > 0) || !isfinite(pdf) || !isfinite(wi[0] + wi[1] + wi[2]) || !isfinite(rgb[0] + rgb[1] + rgb[2])) ++bad;
    dir_bin(wi, W, H, &uu, &vv, &x, &y);
    obs[y * W + x] += 1;
    if (expect[y * W + x] == 0) ++zero_hits;
    while (c0[c + 1] <= (tall ? y : x)) ++c;
    in_long += c0[c + 1] - c0[c] > 256;
  }
  x2 = chisq_pooled(expect, obs, (size_t)(W * H), 1.0, count, NULL, &dof);
  dof -= 1;
  pval = dof > 0 ? gammq(0.5 * dof, 0.5 * x2) : 1.0;
  check(pval > 0.01 / 4 && fabs(total - 1) < 2e-3 && zero_hits == 0 && in_long > count / 4,
        "long %s x cos spots %.2f: chi2 = %.1f over the bins, %d dof, p = %.3g (> %.2g), pdf sums to %.5f, %d hits in zero-pdf bins, "
        "%.1f%% of the samples in cells of > 256 %s", name, spot_share, x2, dof, pval, 0.01 / 4, total, zero_hits,
        100.0 * in_long / count, tall ? "rows" : "bins across");
  check(mismatch == 0 && mismatch_t == 0 && bad == 0, "long %s x cos spots %.2f: sampled pdf == pdf_li_mix_cos(wi) for all %d samples (%d differ, "
        "%d with pdf 0 or non-finite); sample_li_mix_cos_table gives the same bits (%d differ)", name, spot_share, count, mismatch, bad, mismatch_t);
  g_cosn = NULL;
}
/* hostile inputs on the long maps: u at 0, 1 - ulp, 1, -1, NaN, Inf; normals zero, NaN, Inf, 2^+-120 x a
 * unit one; weights 0 (all on the rest), 1 (all on the spot) and the default; directions zero, NaN, Inf,
 * 2^+-120 x a unit one */
static void long_hostile(const el_envlight *l, const el_envlight_hotspots *h, const char *name) {
  static const float us[6] = {0.0f, 0.99999994f, 1.0f, -1.0f, NAN, INFINITY};
  float normals[7][3] = {{0, 0, 0}, {NAN, 0, 1}, {INFINITY, 0, 1}, {0.5f, -0.5f, 0.7071068f}, {0, 0, 0}, {0, 0, 0}, {0, 0, -1}};
  const float shares[3] = {0.0f, 1.0f, NAN};
  int k, ni, i, j, t, bad = 0, mism = 0, nscaled = 0, scaled = 0, edge = 0, unusable = 0, zero = 0;
  for (k = 0; k < 3; ++k) { normals[4][k] = ldexpf(normals[3][k], 120); normals[5][k] = ldexpf(normals[3][k], -120); }
  for (t = 0; t < 3; ++t) {
    el_envlight_mix_weights w;
    float pz[3];
    el_envlight_hotspots_weights(h, shares[t], &w);
    for (ni = 0; ni < 7; ++ni)
      for (i = 0; i < 6; ++i)
        for (j = 0; j < 6; ++j) {
          float u[2], wi[3], rgb[3], pdf, q;
          u[0] = us[i]; u[1] = us[j];
          el_envlight_sample_li_mix_cos(l, h, &w, normals[ni], u, wi, rgb, &pdf);
          q = el_envlight_pdf_li_mix_cos(l, h, &w, normals[ni], wi);
          if (!(pdf > 0) || !isfinite(pdf) || !isfinite(wi[0] + wi[1] + wi[2]) || !isfinite(rgb[0] + rgb[1] + rgb[2])) ++bad;
          if (memcmp(&q, &pdf, sizeof q)) ++mism;
        }
    for (i = 0; i < 2000; ++i) { /* random directions: scaled normals give the unit one's pdf, unusable ones the zero normal's */
      float d[3], p3, p4, p5, p0, p1, p2, pl;
      d[0] = 2 * rng_f(&g_rng) - 1; d[1] = 2 * rng_f(&g_rng) - 1; d[2] = 2 * rng_f(&g_rng) - 1;
      p3 = el_envlight_pdf_li_mix_cos(l, h, &w, normals[3], d);
      pl = el_envlight_pdf_li(l, d);
      p4 = el_envlight_pdf_li_mix_cos(l, h, &w, normals[4], d); p5 = el_envlight_pdf_li_mix_cos(l, h, &w, normals[5], d);
      p0 = el_envlight_pdf_li_mix_cos(l, h, &w, normals[0], d);
      p1 = el_envlight_pdf_li_mix_cos(l, h, &w, normals[1], d); p2 = el_envlight_pdf_li_mix_cos(l, h, &w, normals[2], d);
      if (p4 != p3 || p5 != p3) ++nscaled;
      if (p1 != p0 || p2 != p0 || el_envlight_pdf_li_mix_cos(l, h, &w, NULL, d) != p0) ++unusable;
      for (k = 0; k < 3; ++k) { pz[k] = ldexpf(d[k], 120); }
      if (!(fabsf(el_envlight_pdf_li(l, pz) - pl) <= 1e-6f * pl)) ++edge;
      else if (!(fabsf(el_envlight_pdf_li_mix_cos(l, h, &w, normals[3], pz) - p3) <= 1e-6f * p3)) ++scaled;
      for (k = 0; k < 3; ++k) { pz[k] = ldexpf(d[k], -120); }
      if (!(fabsf(el_envlight_pdf_li(l, pz) - pl) <= 1e-6f * pl)) ++edge;
      else if (!(fabsf(el_envlight_pdf_li_mix_cos(l, h, &w, normals[3], pz) - p3) <= 1e-6f * p3)) ++scaled;
    }
    {
      float dz[3] = {0, 0, 0}, dn[3] = {NAN, 0, 1}, di[3] = {INFINITY, 0, 0};
      for (ni = 0; ni < 7; ++ni)
        zero += el_envlight_pdf_li_mix_cos(l, h, &w, normals[ni], dz) != 0 || el_envlight_pdf_li_mix_cos(l, h, &w, normals[ni], dn) != 0 ||
                el_envlight_pdf_li_mix_cos(l, h, &w, normals[ni], di) != 0;
    }
  }
  check(bad == 0 && mism == 0, "long %s: u at 0, 1 - ulp, 1, -1, NaN, Inf x normals zero, NaN, Inf, huge, tiny, unit, down x spot weights 0, 1, "
        "default: pdf > 0, finite, == pdf_li_mix_cos(wi) (%d bad, %d differ)", name, bad, mism);
  /* (a scaled direction leaves pdf_li's inline path, whose 1 / sin(theta) is len / r, for pdf_li / its table
   * entry: an ulp apart; and on a bin's edge pdf_li's own slow path may pick the neighbour: those are
   * counted apart, where pdf_li of the two differs by more than 1e-6 too) */
  check(nscaled == 0 && scaled == 0 && edge <= 4 && unusable == 0 && zero == 0, "long %s: pdf_li_mix_cos of normals x 2^+-120 = that of the unit "
        "one bit for bit (%d differ), of directions x 2^+-120 within 1e-6 (%d not; %d of 12000 on a bin edge where pdf_li differs too); NaN, Inf "
        "and NULL normals = the zero normal (bound 1; %d differ); zero, NaN, Inf directions: 0 (%d not)", name, nscaled, scaled, edge, unusable, zero);
}
static void test_long_cells(void) {
  static float px[LONG_MAXB * 3];
  static const float nup[3] = {0.3f, -0.2f, 0.93f}, nside[3] = {0.8f, 0.6f, 0.0f};
  int tall;
  for (tall = 0; tall < 2; ++tall) {
    el_envlight l;
    el_envlight_hotspots h;
    el_envlight_mix_weights w;
    const char *name = tall ? "128x4104 (cells of 256-257 rows)" : "8208x32 (cell rows of 256-257 bins)";
    int longer, shorter;
    double ref, mean, sd, sun[3], cone;
    g_w = tall ? 128 : 8208; g_h = tall ? 4104 : 32;
    long_map(tall, px);
    if (long_light(&l, px) != EL_SUCCESS || el_envlight_hotspots_init(&h, &l, NULL) != EL_SUCCESS) { check(0, "long %s: init", name); continue; }
    long_cells(&h, tall, &longer, &shorter);
    check(h.count == 1 && longer > 0 && shorter > 0, "long %s: %d spot (share %.3f), %d cells %s of > 256 bins, %d of <= 256",
          name, h.count, h.count ? h.spot[0].share : 0.0f, longer, tall ? "down" : "across", shorter);
    long_chi2(&l, &h, name, tall, nup, 0.3f, 200000);
    long_chi2(&l, &h, name, tall, nside, 0.0f, 100000);
    /* unbiasedness: f = le x max(0, n.w), with the sun's weight 0.3, and 0 with the sun occluded */
    el_envlight_hotspots_weights(&h, 0.3f, &w);
    ref = cosine_integral_q(&l, nup, NULL, 0, 2, 2, 2, tall ? 2 : 16);
    estimate(&l, &h, &w, nup, NULL, 0, 1, 100000, &mean, &sd);
    check(fabs(mean - ref) < 4.5 * sd + 2e-3 * ref, "unbiased long %s x cos spots 0.30: mean of f/pdf %.5f, quadrature %.5f (%.1f sd)",
          name, mean, ref, fabs(mean - ref) / (sd > 0 ? sd : 1));
    sun[0] = h.spot[0].axis[0]; sun[1] = h.spot[0].axis[1]; sun[2] = h.spot[0].axis[2];
    cone = h.spot[0].half_angle + 0.05;
    el_envlight_hotspots_weights(&h, 0.0f, &w);
    ref = cosine_integral_q(&l, nup, sun, cone, 2, 2, 2, tall ? 2 : 16);
    estimate(&l, &h, &w, nup, sun, cone, 1, 100000, &mean, &sd);
    check(fabs(mean - ref) < 4.5 * sd + 2e-3 * ref, "unbiased long %s x cos spots 0.00 (sun occluded): mean of f/pdf %.5f, quadrature %.5f (%.1f sd)",
          name, mean, ref, fabs(mean - ref) / (sd > 0 ? sd : 1));
    long_hostile(&l, &h, name);
    el_envlight_hotspots_free(&h);
    el_envlight_free(&l);
  }
  g_w = 128; g_h = 64;
}

int main(void) {
  test_table();
  test_detection();
  test_defaults();
  test_chi2();
  test_unbiased();
  test_hostile();
  test_long_cells();
  test_spot();
  printf("%d passed, %d failed\n", g_pass, g_fail);
  return g_fail ? 1 : 0;
}
