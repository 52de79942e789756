/* bench_hdri.c: the numbers behind issue 24's notes in envlight.h (real HDRIs and their edge cases).
 *
 *   build/bin/bench_hdri [MAPDIR]      (MAPDIR: ../shared/envmaps by default, else data/envmaps)
 *
 * 1. Below the horizon: the fraction of el_envlight_sample_li_cos's samples (pdf > 0) with n.wi <= 0,
 *    per map, for the six orientations of bench_envlight's table 4 (up, down, +x, -y, towards the
 *    brightest texel and away from it), for n = (0.6, -0.8, 0) and (0.6, 0, 0.8), and for a generated
 *    map whose sun (2x2 texels of 1e4 on a 0.01 sky, 512x256) sits one texel row below the horizon of
 *    n = +z, and 1 / 4 / 16 rows below. 65536 stratified samples each, identity matrix (light space =
 *    world, z up).
 * 2. sample_li's radiance: the time of sample_li with its radiance (the lookup at the sample's own
 *    (u, v)) against sample_li without it plus le(wi) (the cost of returning le(wi) instead), identity
 *    and a general rotation, city; 5 interleaved rounds of 2^20 samples each, ns per sample, min and
 *    max. Under a general rotation sample_li now returns le(wi) itself.
 * The machine is shared by several jobs: read ratios and ranges, not single times.
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

#include "bench_common.h" /* rng_f (PCG32), wall_now */
static rng g_rng = {0x853c49e6748fea9bULL}; /* one stream for the whole program */

static double below(const el_envlight *l, const float n[3]) {
  int j, b = 0, valid = 0, count = 65536;
  for (j = 0; j < count; ++j) {
    float u[2], wi[3], pdf;
    u[0] = ((float)(j % 256) + rng_f(&g_rng)) / 256.0f;
    u[1] = ((float)(j / 256) + rng_f(&g_rng)) / 256.0f;
    el_envlight_sample_li_cos(l, n, u, wi, NULL, &pdf);
    if (!(pdf > 0.0f)) continue;
    ++valid;
    if (n[0] * wi[0] + n[1] * wi[1] + n[2] * wi[2] <= 0.0f) ++b;
  }
  return valid ? 100.0 * b / valid : -1.0;
}

static void horizon_table(const char *dir) {
  static const char *maps[5] = {"city", "forest", "night", "studio", "sunset"};
  int mi, k;
  printf("1. sample_li_cos: %% of samples below the horizon (n.wi <= 0), 65536 stratified samples\n");
  printf("%-8s %6s %6s %6s %6s %6s %6s | %6s %6s\n", "map", "up", "down", "+x", "-y", "bright", "away", "(.6,-.8,0)", "(.6,0,.8)");
  for (mi = 0; mi < 5; ++mi) {
    char path[600], err[256];
    el_image im;
    el_envlight l;
    size_t i, n, best = 0;
    float bl = -1.0f, bu, bv, bd[3], ns[8][3] = {{0, 0, 1}, {0, 0, -1}, {1, 0, 0}, {0, -1, 0}, {0}, {0}, {0.6f, -0.8f, 0}, {0.6f, 0, 0.8f}};
    snprintf(path, sizeof path, "%s/%s.exr", dir, maps[mi]);
    if (el_image_load(path, &im, err, sizeof err) != 0) { printf("%-8s (%s)\n", maps[mi], err); continue; }
    if (el_envlight_init(&l, im.pixels, im.width, im.height, im.channels, NULL) != EL_SUCCESS) { el_image_free(&im); continue; }
    n = (size_t)im.width * (size_t)im.height;
    for (i = 0; i < n; ++i) {
      const float *p = im.pixels + i * (size_t)im.channels;
      float y = 0.2126f * p[0] + 0.7152f * p[1] + 0.0722f * p[2];
      if (y > bl) { bl = y; best = i; }
    }
    bu = ((float)(best % (size_t)im.width) + 0.5f) / (float)im.width;
    bv = ((float)(best / (size_t)im.width) + 0.5f) / (float)im.height;
    el_envlight_uv_to_dir(bu, bv, bd);
    for (k = 0; k < 3; ++k) { ns[4][k] = bd[k]; ns[5][k] = -bd[k]; }
    printf("%-8s", maps[mi]);
    for (k = 0; k < 8; ++k) printf(" %6.1f%s", below(&l, ns[k]), k == 5 ? " |" : "");
    printf("\n");
    el_envlight_free(&l);
    el_image_free(&im);
  }
  { /* a sun just below the horizon of n = +z */
    int w = 512, h = 256, x, y, rows[4] = {1, 4, 16, 64};
    float *px = (float *)malloc((size_t)w * (size_t)h * 3 * sizeof(float)), up[3] = {0, 0, 1};
    printf("generated 512x256, sky 0.01, a 2x2-texel sun of 1e4 whose upper row is R rows below the horizon of n = +z:\n");
    for (k = 0; k < 4; ++k) {
      el_envlight l;
      for (y = 0; y < h; ++y)
        for (x = 0; x < w; ++x) {
          float v = (y == h / 2 - 1 + rows[k] || y == h / 2 + rows[k]) && (x == 100 || x == 101) ? 1e4f : 0.01f;
          float *t = px + 3 * ((size_t)y * (size_t)w + (size_t)x);
          t[0] = t[1] = t[2] = v;
        }
      el_envlight_init(&l, px, w, h, 3, NULL);
      printf("  R = %2d: %5.1f%% below\n", rows[k], below(&l, up));
      el_envlight_free(&l);
    }
    free(px);
  }
}

static void radiance_cost(const char *dir) {
  char path[600], err[256];
  el_image im;
  int gi, round;
  float *u = (float *)malloc(2 * sizeof(float) * (1 << 20));
  int i;
  snprintf(path, sizeof path, "%s/city.exr", dir);
  if (el_image_load(path, &im, err, sizeof err) != 0) { printf("(%s)\n", err); free(u); return; }
  for (i = 0; i < 2 * (1 << 20); ++i) u[i] = rng_f(&g_rng);
  printf("2. sample_li's radiance on city, ns per sample over 5 interleaved rounds of 2^20 (min - max)\n");
  for (gi = 0; gi < 2; ++gi) {
    el_envlight l;
    el_envlight_options o;
    double t[3][2] = {{1e30, 0}, {1e30, 0}, {1e30, 0}}, sink = 0;
    memset(&o, 0, sizeof o);
    if (gi) { /* 37 degrees about (1, 2, 3) */
      double ax[3] = {1, 2, 3}, nn = sqrt(14.0), a = 37.0 * 3.14159265358979323846 / 180.0, c = cos(a), s = sin(a), tt = 1 - c;
      double x = ax[0] / nn, y = ax[1] / nn, z = ax[2] / nn;
      double r[9] = {tt * x * x + c, tt * x * y - s * z, tt * x * z + s * y, tt * x * y + s * z, tt * y * y + c,
                     tt * y * z - s * x, tt * x * z - s * y, tt * y * z + s * x, tt * z * z + c};
      for (i = 0; i < 9; ++i) o.light_to_world[i] = (float)r[i];
    }
    el_envlight_init(&l, im.pixels, im.width, im.height, im.channels, &o);
    el_envlight_prepare_sampling(&l);
    for (round = 0; round < 5; ++round) {
      int v;
      for (v = 0; v < 3; ++v) {
        double t0 = wall_now(), dt;
        for (i = 0; i < (1 << 20); ++i) {
          float wi[3], rgb[3], pdf;
          if (v == 0) el_envlight_sample_li(&l, u + 2 * i, wi, NULL, &pdf), rgb[0] = pdf;
          else if (v == 1) el_envlight_sample_li(&l, u + 2 * i, wi, rgb, &pdf);
          else { el_envlight_sample_li(&l, u + 2 * i, wi, NULL, &pdf); el_envlight_le(&l, wi, rgb); }
          sink += (double)rgb[0];
        }
        dt = (wall_now() - t0) * 1e9 / (1 << 20);
        if (dt < t[v][0]) t[v][0] = dt;
        if (dt > t[v][1]) t[v][1] = dt;
      }
    }
    printf("  %-16s no radiance %5.1f - %5.1f ns, with its radiance %5.1f - %5.1f ns, + le(wi) %5.1f - %5.1f ns (sink %g)\n",
           gi ? "general rotation" : "identity", t[0][0], t[0][1], t[1][0], t[1][1], t[2][0], t[2][1], sink > 0 ? 1.0 : 0.0);
    el_envlight_free(&l);
  }
  el_image_free(&im);
  free(u);
}

int main(int argc, char **argv) {
  const char *dir = argc > 1 ? argv[1] : "../shared/envmaps";
  FILE *f;
  char probe[600];
  snprintf(probe, sizeof probe, "%s/city.exr", dir);
  f = fopen(probe, "rb");
  if (!f) { printf("(%s not found: give the folder of city.exr ... sunset.exr)\n", probe); return 1; }
  fclose(f);
  horizon_table(dir);
  radiance_cost(dir);
  return 0;
}
