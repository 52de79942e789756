/* bench_sun.c: the numbers behind envlight.h's NOTES ON HOT SPOTS (issue 22: the sun).
 *
 *   build/bin/bench_sun [MAPDIR]      (MAPDIR: ../shared/envmaps by default, else data/envmaps)
 *
 * 1. Hot spots found on the five CC0 maps and on generated 1024x512 maps (a sunrise, two suns, a sun at
 *    the pole, across the seam, of one texel, none), for min_radiance 10 .. 1000 (the default 100) and
 *    the other options at their defaults: count, each spot's share, half-angle and bins.
 * 2. Where the samples go: the share of samples landing in the largest spot's cone and within 1 degree
 *    of its axis, for sample_li (= the mixture's default weights), el_envlight_sample_li_cos and the
 *    mixture with the largest spot's weight moved to 0.1, 0.02 and 0.
 * 3. A shadowed point: the irradiance estimate E = integral of L(w) max(0, n.w) V(w), V = 0 inside the
 *    largest spot's cone (the sun is occluded), n up (+z, light space = world) and n towards the spot
 *    (its axis, raised to 20 degrees above the horizon when lower). Variance per sample of f / pdf, 2^20 independent samples, for
 *    sample_li, sample_li_cos and the mixture with the largest spot's weight 0.1, 0.02, 0 (the other parts
 *    keep their proportions: the other lamps of night and studio stay lit); the ratio to
 *    sample_li's variance, and the mean against sample_li's (all estimate the same E).
 *    Last row, projected: product sampling restricted to outside the cone (li_cos's samples in the cone
 *    rejected, the estimate scaled by the acceptance rate Z: the variance of f Z / p_cos over accepted
 *    samples), the variance an exact "rest x product sampling" part would reach; then the rest x cosine
 *    mixture that is implemented (el_envlight_sample_li_mix_cos: the rest's 32 x 16 cells by their mass
 *    times a cosine bound) with the largest spot's weight 0.02 and 0.
 * 4. Cost: ns per sample of sample_li and sample_li_mix (spots 0.02) with radiance on the sunrise map,
 *    best of 5 interleaved rounds of 2^20 (the machine is shared: read ratios), and the bytes of the
 *    hot-spot tables.
 * 5. Importance BILINEAR (le()'s patches, the render's density under a sun): the hot spots found on the
 *    same maps at the default min_radiance, and ns per sample of sample_li and el_envlight_sample_li_spot
 *    (the largest spot's patch rectangle) with radiance, and of pdf_li and pdf_li_spot, on the sunrise map.
 */
#define _POSIX_C_SOURCE 200809L
#define EL_IMPLEMENTATION
#include "envlight.h"
#include "image_io.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define PI 3.14159265358979323846

#include "bench_common.h" /* rng_f (PCG32), wall_now */
static rng g_rng = {0x853c49e6748fea9bULL}; /* one stream for the whole program */

#define GW 1024
#define GH 512
enum { G_SUNRISE, G_TWO, G_POLE, G_SEAM, G_ONE, G_NONE, G_COUNT };
static const char *g_name[G_COUNT] = {"sunrise", "two suns", "pole sun", "seam sun", "1-texel", "no sun"};

/* generated maps, light space z up: a sky (brighter towards the horizon and the sun), a dim ground */
static void make_map(int kind, float *px) {
  int x, y, c;
  double sun[3], el = 7.9 * PI / 180, az = 0.3 * 2 * PI;
  sun[0] = cos(el) * cos(az); sun[1] = cos(el) * sin(az); sun[2] = sin(el);
  for (y = 0; y < GH; ++y)
    for (x = 0; x < GW; ++x) {
      double th = PI * (y + 0.5) / GH, ph = 2 * PI * (x + 0.5) / GW, d[3], v[3];
      d[0] = sin(th) * cos(ph); d[1] = sin(th) * sin(ph); d[2] = cos(th);
      if (kind == G_SUNRISE) {
        double c2 = d[0] * sun[0] + d[1] * sun[1] + d[2] * sun[2], ang = acos(c2 > 1 ? 1 : c2);
        double sky = d[2] > 0 ? 0.15 + 0.5 * exp(-d[2] * 4) : 0.03;
        double glow = d[2] > -0.02 ? 2.0 * exp(-ang / 0.15) : 0;
        double disc = ang < 0.5 * PI / 180 ? 2.5e4 : 0;
        v[0] = sky * 0.8 + glow * 1.0 + disc; v[1] = sky * 0.9 + glow * 0.7 + disc * 0.85; v[2] = sky * 1.3 + glow * 0.4 + disc * 0.6;
      } else {
        double sky = d[2] > 0 ? 0.4 + 0.6 * (1 - d[2]) : 0.05;
        v[0] = v[1] = v[2] = sky;
      }
      for (c = 0; c < 3; ++c) px[3 * (y * GW + x) + c] = (float)v[c];
    }
#define SUN(X, Y, V) do { for (c = 0; c < 3; ++c) px[3 * ((Y) * GW + (X)) + c] = (float)(V); } while (0)
  if (kind == G_TWO) { SUN(240, 160, 3e5); SUN(241, 160, 3e5); SUN(240, 161, 3e5); SUN(241, 161, 3e5); SUN(720, 320, 2e5); SUN(721, 320, 2e5); SUN(720, 321, 2e5); SUN(721, 321, 2e5); }
  if (kind == G_POLE) for (x = 0; x < GW; ++x) SUN(x, 0, 5e6);
  if (kind == G_SEAM) { SUN(GW - 1, 200, 4e5); SUN(0, 200, 4e5); SUN(GW - 1, 201, 4e5); SUN(0, 201, 4e5); }
  if (kind == G_ONE) SUN(560, 96, 2e6);
#undef SUN
}

static void spots_line(const char *name, const el_envlight *l, float thr) {
  el_envlight_hotspots h;
  el_envlight_hotspot_options o;
  el_result r;
  int k;
  memset(&o, 0, sizeof o);
  o.min_radiance = thr;
  r = el_envlight_hotspots_init(&h, l, &o);
  printf("  %-9s %6.0f  %s %d spots, rest %.3f:", name, thr, r == EL_SUCCESS ? "" : el_result_string(r), h.count, h.rest_share);
  for (k = 0; k < h.count; ++k) printf(" %.3f/%.2fdeg/%db", h.spot[k].share, h.spot[k].half_angle * 180 / PI, h.spot[k].bins);
  printf("\n");
  el_envlight_hotspots_free(&h);
}

/* sampler: 0 sample_li, 1 sample_li_cos(n), 2..4 mixture with spot weight s, 6, 7 the rest x cosine mixture */
static void draw(const el_envlight *l, const el_envlight_hotspots *h, int which, float s, const float n[3], const float u[2], float wi[3], float rgb[3], float *pdf) {
  if (which == 0) el_envlight_sample_li(l, u, wi, rgb, pdf);
  else if (which == 1) el_envlight_sample_li_cos(l, n, u, wi, rgb, pdf);
  else { /* the largest spot (the occluded one) gets probability s, the other parts keep their proportions */
    el_envlight_mix_weights w;
    int k;
    memset(&w, 0, sizeof w);
    w.spot[0] = s;
    for (k = 1; k < h->count; ++k) w.spot[k] = h->spot[k].share * (1 - s) / (1 - h->spot[0].share);
    w.rest = h->rest_share * (1 - s) / (1 - h->spot[0].share);
    if (which >= 6) el_envlight_sample_li_mix_cos(l, h, &w, n, u, wi, rgb, pdf);
    else el_envlight_sample_li_mix(l, h, &w, u, wi, rgb, pdf);
  }
}

static void study(const char *name, const el_envlight *l) {
  el_envlight_hotspots h;
  const float shares[3] = {0.1f, 0.02f, 0.0f};
  const char *sname[8] = {"sample_li", "li_cos(n)", "mix 0.1", "mix 0.02", "mix 0", "li_cos|rest", "mixcos .02", "mixcos 0"};
  float ax[3], ns[2][3];
  double cosc, cos1 = cos(PI / 180), var0[2] = {0, 0}, mean0[2] = {0, 0};
  int which, ni, i, count = 1 << 20;
  el_envlight_hotspots_init(&h, l, NULL);
  if (h.count == 0) { printf("  %-9s no hot spot: the mixture is sample_li\n", name); el_envlight_hotspots_free(&h); return; }
  ax[0] = h.spot[0].axis[0]; ax[1] = h.spot[0].axis[1]; ax[2] = h.spot[0].axis[2];
  cosc = cos(h.spot[0].half_angle);
  ns[0][0] = 0; ns[0][1] = 0; ns[0][2] = 1;
  { /* towards the spot, kept at least 20 degrees above the horizon */
    double z = ax[2] > sin(20 * PI / 180) ? ax[2] : sin(20 * PI / 180), r = sqrt(ax[0] * ax[0] + ax[1] * ax[1]), k = sqrt(1 - z * z) / (r > 0 ? r : 1);
    ns[1][0] = (float)(ax[0] * k); ns[1][1] = (float)(ax[1] * k); ns[1][2] = (float)z;
  }
  printf("  %-9s largest spot: share %.3f, %.2f deg, axis elevation %.1f deg (%d spots, their total share %.3f)\n", name,
         h.spot[0].share, h.spot[0].half_angle * 180 / PI, asin(ax[2]) * 180 / PI, h.count, 1 - h.rest_share);
  for (ni = 0; ni < 2; ++ni) {
    printf("    n %-6s %-10s %8s %8s %12s %12s %9s %9s\n", ni ? "to sun" : "up", "sampler", "in cone", "<1 deg", "E (mean)", "var/sample", "var ratio", "sli/this");
    for (which = 0; which < 8; ++which) {
      double in = 0, near = 0, sum = 0, sum2 = 0, mean, var;
      if (which == 5) { /* projected: product sampling restricted to outside the cone (rejection; Z = the
                           acceptance rate), what a "rest x cosine" part of the mixture would give */
        double acc = 0, tries = 0, g1 = 0, g2 = 0, z;
        for (i = 0; i < count; ++i) {
          float u[2], wi[3], rgb[3], pdf, c, cs;
          double f;
          u[0] = rng_f(&g_rng); u[1] = rng_f(&g_rng);
          el_envlight_sample_li_cos(l, ns[ni], u, wi, rgb, &pdf);
          tries += 1;
          if (!(pdf > 0)) continue;
          cs = wi[0] * ax[0] + wi[1] * ax[1] + wi[2] * ax[2];
          if (cs >= cosc) continue;
          acc += 1;
          c = ns[ni][0] * wi[0] + ns[ni][1] * wi[1] + ns[ni][2] * wi[2];
          f = c > 0 ? (0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2]) * c / pdf : 0;
          g1 += f; g2 += f * f;
        }
        z = acc / tries;
        mean = z * g1 / acc; /* = g1 / tries */
        var = z * z * (g2 / acc) - mean * mean;
        printf("    %-8s %-10s %7s  %7s  %12.5g %12.4g %9.3f %9.2fx  (projected; %.1f%% of li_cos's draws were in the cone)\n", "", sname[which], "-", "-",
               mean, var, var / var0[ni], var > 0 ? var0[ni] / var : 0.0, 100 * (1 - z));
        continue;
      }
      g_rng.s = 0x853c49e6748fea9bULL + (uint64_t)ni;
      for (i = 0; i < count; ++i) {
        float u[2], wi[3], rgb[3], pdf, c, cs;
        double f = 0;
        u[0] = rng_f(&g_rng); u[1] = rng_f(&g_rng);
        draw(l, &h, which, which >= 6 ? shares[which - 5] : which >= 2 ? shares[which - 2] : 0, ns[ni], u, wi, rgb, &pdf);
        if (!(pdf > 0)) continue;
        cs = wi[0] * ax[0] + wi[1] * ax[1] + wi[2] * ax[2];
        if (cs >= cosc) in += 1;
        if (cs >= cos1) near += 1;
        c = ns[ni][0] * wi[0] + ns[ni][1] * wi[1] + ns[ni][2] * wi[2];
        if (c > 0 && cs < cosc) f = (0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2]) * c / pdf; /* V = 0 in the cone */
        sum += f; sum2 += f * f;
      }
      mean = sum / count;
      var = sum2 / count - mean * mean;
      if (which == 0) { var0[ni] = var; mean0[ni] = mean; }
      printf("    %-8s %-10s %7.1f%% %7.1f%% %12.5g %12.4g %9.3f %9.2fx\n", "", sname[which], 100 * in / count, 100 * near / count, mean, var,
             var / var0[ni], var > 0 ? var0[ni] / var : 0.0);
    }
    printf("    (sample_li's E %.5g: every sampler estimates the same integral; relative sd per sample of sample_li %.3g)\n", mean0[ni],
           sqrt(var0[ni]) / (mean0[ni] > 0 ? mean0[ni] : 1));
  }
  el_envlight_hotspots_free(&h);
}

static void cost(const el_envlight *l) {
  el_envlight_hotspots h;
  el_envlight_mix_weights w;
  float *u = (float *)malloc(sizeof(float) * 2 * (1 << 20));
  double best[4] = {1e30, 1e30, 1e30, 1e30}, worst[4] = {0, 0, 0, 0}, sink = 0;
  const float nup[3] = {0, 0, 1};
  int round, which, i, n = 1 << 20;
  size_t bytes = 0;
  if (!u) return;
  el_envlight_hotspots_init(&h, l, NULL);
  el_envlight_hotspots_weights(&h, 0.02f, &w);
  for (i = 0; i < 2 * n; ++i) u[i] = rng_f(&g_rng);
  for (round = 0; round < 5; ++round)
    for (which = 0; which < 4; ++which) {
      double t0 = wall_now(), t;
      for (i = 0; i < n; ++i) {
        float wi[3], rgb[3], pdf;
        if (which == 0) el_envlight_sample_li(l, u + 2 * i, wi, rgb, &pdf);
        else if (which == 1) el_envlight_sample_li_mix(l, &h, &w, u + 2 * i, wi, rgb, &pdf);
        else if (which == 2) el_envlight_sample_li_cos(l, nup, u + 2 * i, wi, rgb, &pdf);
        else el_envlight_sample_li_mix_cos(l, &h, &w, nup, u + 2 * i, wi, rgb, &pdf);
        sink += pdf + rgb[0];
      }
      t = (wall_now() - t0) / n * 1e9;
      if (t < best[which]) best[which] = t;
      if (t > worst[which]) worst[which] = t;
    }
  for (i = 0; i <= h.count; ++i) bytes += el_distribution2d_bytes(&h.dist[i]);
  if (h.cell_tab) { /* the rest x cosine part's cell tables (uint16, one after another) and their offsets */
    int nc = h.cells_u * h.cells_v, cu = (nc - 1) % h.cells_u, cv = (nc - 1) / h.cells_u, rows = h.cell_v0[cv + 1] - h.cell_v0[cv];
    bytes += 2 * ((size_t)h.cell_off[nc - 1] + 5 + (size_t)rows * (size_t)(6 + h.cell_u0[cu + 1] - h.cell_u0[cu])) + 4 * (size_t)nc + (size_t)(h.nu + h.nv);
  }
  bytes += el_distribution2d_fast_bytes(&h.rest_fast);
  printf("4. cost on the sunrise map (2^20 samples, best - worst of 5 interleaved rounds, loaded machine):\n");
  printf("   sample_li + radiance %.0f - %.0f ns, sample_li_mix (spots 0.02) + radiance %.0f - %.0f ns (%.2fx at best); hot-spot tables %.2f MB (light's sampling tables %.2f MB) [%g]\n",
         best[0], worst[0], best[1], worst[1], best[1] / best[0], bytes / 1e6, el_envlight_sampling_bytes(l) / 1e6, sink > 0 ? 0.0 : 1.0);
  printf("   sample_li_cos (n up) + radiance %.0f - %.0f ns, sample_li_mix_cos + radiance %.0f - %.0f ns (%.2fx at best)\n",
         best[2], worst[2], best[3], worst[3], best[3] / best[2]);
  el_envlight_hotspots_free(&h);
  free(u);
}

static void cost_spot(const float *px) {
  el_envlight l;
  el_envlight_options o;
  el_envlight_hotspots h;
  float *u = (float *)malloc(sizeof(float) * 2 * (1 << 20)), d[3];
  double best[4] = {1e30, 1e30, 1e30, 1e30}, sink = 0;
  int round, which, i, n = 1 << 20;
  memset(&o, 0, sizeof o);
  o.importance = EL_ENVLIGHT_IMPORTANCE_BILINEAR;
  if (!u || el_envlight_init(&l, px, GW, GH, 3, &o) != EL_SUCCESS) { free(u); return; }
  el_envlight_hotspots_init(&h, &l, NULL);
  for (i = 0; i < 2 * n; ++i) u[i] = rng_f(&g_rng);
  for (round = 0; round < 5 && h.count > 0; ++round)
    for (which = 0; which < 4; ++which) {
      double t0 = wall_now(), t;
      for (i = 0; i < n; ++i) {
        float wi[3], rgb[3], pdf;
        if (which == 0) el_envlight_sample_li(&l, u + 2 * i, wi, rgb, &pdf);
        else if (which == 1) el_envlight_sample_li_spot(&l, &h, 0, u + 2 * i, wi, rgb, &pdf);
        else { /* (the pdfs at the directions of sample_li_spot's samples: u reused as a direction's angles) */
          float ph = 6.2831853f * u[2 * i], z = 0.9f + 0.1f * u[2 * i + 1], r = sqrtf(1 - z * z), a[3];
          a[0] = r * cosf(ph); a[1] = r * sinf(ph); a[2] = z; /* (around +z; then onto the spot's axis below) */
          d[0] = a[0] + 8 * h.spot[0].axis[0]; d[1] = a[1] + 8 * h.spot[0].axis[1]; d[2] = a[2] + 8 * h.spot[0].axis[2];
          pdf = which == 2 ? el_envlight_pdf_li(&l, d) : el_envlight_pdf_li_spot(&l, &h, 0, d);
          rgb[0] = 0;
        }
        sink += pdf + rgb[0];
      }
      t = (wall_now() - t0) / n * 1e9;
      if (t < best[which]) best[which] = t;
    }
  if (h.count > 0)
    printf("5. importance BILINEAR on the sunrise map (best of 5 interleaved rounds of 2^20): sample_li + radiance %.0f ns, sample_li_spot + "
           "radiance %.0f ns (%.2fx); pdf_li %.0f ns, pdf_li_spot %.0f ns (%.2fx) near the spot; its rectangle %d x %d patches [%g]\n",
           best[0], best[1], best[1] / best[0], best[2], best[3], best[3] / best[2], h.prect[0][2], h.prect[0][3], sink > 0 ? 0.0 : 1.0);
  el_envlight_hotspots_free(&h);
  el_envlight_free(&l);
  free(u);
}

int main(int argc, char **argv) {
  static const char *maps[5] = {"city", "forest", "night", "studio", "sunset"};
  const float thr[5] = {10, 30, 100, 300, 1000};
  const char *dir = argc > 1 ? argv[1] : "../shared/envmaps";
  float *px = (float *)malloc(sizeof(float) * 3 * GW * GH);
  el_envlight ls[5], lg[G_COUNT];
  int have[5] = {0}, mi, t;
  if (!px) return 1;
  for (mi = 0; mi < 5; ++mi) {
    char path[600], err[256];
    el_image im;
    snprintf(path, sizeof path, "%s/%s.exr", dir, maps[mi]);
    if (el_image_load(path, &im, err, sizeof err) != 0) { /* else the copies in data/ (city, studio) */
      snprintf(path, sizeof path, "data/envmaps/%s.hdr", maps[mi]);
      if (el_image_load(path, &im, err, sizeof err) != 0) { printf("%s: %s\n", maps[mi], err); continue; }
    }
    have[mi] = el_envlight_init(&ls[mi], im.pixels, im.width, im.height, im.channels, NULL) == EL_SUCCESS;
    { /* 5.: the same map under importance BILINEAR */
      el_envlight lb;
      el_envlight_options o;
      memset(&o, 0, sizeof o);
      o.importance = EL_ENVLIGHT_IMPORTANCE_BILINEAR;
      if (el_envlight_init(&lb, im.pixels, im.width, im.height, im.channels, &o) == EL_SUCCESS) {
        printf("importance BILINEAR: ");
        spots_line(maps[mi], &lb, 100);
        el_envlight_free(&lb);
      }
    }
    el_image_free(&im);
  }
  for (mi = 0; mi < G_COUNT; ++mi) {
    make_map(mi, px);
    el_envlight_init(&lg[mi], px, GW, GH, 3, NULL);
    if (mi == G_SUNRISE) cost_spot(px);
  }
  printf("1. hot spots (min_share 0.05, max_half_angle 11.5 deg; share/half-angle/bins per spot), by min_radiance\n");
  for (t = 0; t < 5; ++t) {
    for (mi = 0; mi < 5; ++mi) if (have[mi]) spots_line(maps[mi], &ls[mi], thr[t]);
    for (mi = 0; mi < G_COUNT; ++mi) spots_line(g_name[mi], &lg[mi], thr[t]);
  }
  printf("2./3. where the samples go, and a shadowed point (V = 0 in the largest spot's cone), 2^20 samples\n");
  study("sunrise", &lg[G_SUNRISE]);
  for (mi = 0; mi < 5; ++mi) if (have[mi]) study(maps[mi], &ls[mi]);
  study("two suns", &lg[G_TWO]);
  cost(&lg[G_SUNRISE]);
  for (mi = 0; mi < 5; ++mi) if (have[mi]) el_envlight_free(&ls[mi]);
  for (mi = 0; mi < G_COUNT; ++mi) el_envlight_free(&lg[mi]);
  free(px);
  return 0;
}
