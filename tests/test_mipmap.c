/* test_mipmap.c: mipmap.h against mathematics.
 *
 * Expected values come from: level sizes worked out by hand; box averages and exact area averages
 * computed here in double from the input texels; means of whole levels; the Lanczos resampling weights
 * written out again in double; hand-computed bilinear blends at texel centres and edges; a
 * brute-force, supersampled Gaussian footprint (the filter EWA approximates) on an anisotropic
 * checkerboard; pbrt-v3's trilinear and EWA lookups transcribed here in float (the issue asks for
 * pbrt's results to float precision). Nothing is compared with an earlier output of mipmap.h.
 */
#define EL_IMPLEMENTATION
#include "mipmap.h"

#include <float.h>
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int g_pass, g_fail;
static void check(int ok, const char *what) {
  if (ok) g_pass++;
  else g_fail++;
  printf("%s: %s\n", ok ? "PASS" : "FAIL", what);
}
static char g_buf[512];
#define CHECKF(ok, ...)                                                                             \
  do {                                                                                              \
    snprintf(g_buf, sizeof g_buf, __VA_ARGS__);                                                     \
    check(ok, g_buf);                                                                               \
  } while (0)

#include "test_rng.h" /* xorshift32_f */
static xorshift32 g_rng = {2463534242u};
static float *random_image(int w, int h, int C) {
  float *p = (float *)malloc(sizeof(float) * (size_t)w * (size_t)h * (size_t)C);
  size_t i;
  for (i = 0; i < (size_t)w * (size_t)h * (size_t)C; ++i) p[i] = 0.1f + xorshift32_f(&g_rng);
  return p;
}
static el_mipmap_options opts(el_mipmap_wrap wu, el_mipmap_wrap wv, int keep) {
  el_mipmap_options o;
  memset(&o, 0, sizeof o);
  o.wrap_u = wu;
  o.wrap_v = wv;
  o.keep_resolution = keep;
  return o;
}
static const char *wrap_name(el_mipmap_wrap w) {
  return w == EL_MIPMAP_WRAP_REPEAT ? "repeat" : (w == EL_MIPMAP_WRAP_BLACK ? "black" : "clamp");
}
static double rel(double a, double b) { return fabs(a - b) / (fabs(b) > 1e-6 ? fabs(b) : 1e-6); }

/* ---- level counts and sizes ------------------------------------------------------------------- */
static void test_sizes(void) {
  struct {
    int w, h, keep, levels;
    int sizes[12][2];
  } cases[] = {
      {8, 8, 0, 4, {{8, 8}, {4, 4}, {2, 2}, {1, 1}}},
      {16, 4, 0, 5, {{16, 4}, {8, 2}, {4, 1}, {2, 1}, {1, 1}}},
      {1, 8, 0, 4, {{1, 8}, {1, 4}, {1, 2}, {1, 1}}},
      {8, 1, 0, 4, {{8, 1}, {4, 1}, {2, 1}, {1, 1}}},
      {1, 1, 0, 1, {{1, 1}}},
      /* not a power of two: pbrt resamples up to 512x256 */
      {400, 235, 0, 10, {{512, 256}, {256, 128}, {128, 64}, {64, 32}, {32, 16}, {16, 8}, {8, 4}, {4, 2}, {2, 1}, {1, 1}}},
      {3, 1, 0, 3, {{4, 1}, {2, 1}, {1, 1}}},
      /* keep_resolution: n -> max(1, floor(n/2)) */
      {400, 235, 1, 9, {{400, 235}, {200, 117}, {100, 58}, {50, 29}, {25, 14}, {12, 7}, {6, 3}, {3, 1}, {1, 1}}},
      {5, 3, 1, 3, {{5, 3}, {2, 1}, {1, 1}}},
      {1, 7, 1, 3, {{1, 7}, {1, 3}, {1, 1}}},
  };
  int k, l;
  for (k = 0; k < (int)(sizeof cases / sizeof cases[0]); ++k) {
    float *img = random_image(cases[k].w, cases[k].h, 3);
    el_mipmap m;
    el_mipmap_options o = opts(EL_MIPMAP_WRAP_REPEAT, EL_MIPMAP_WRAP_REPEAT, cases[k].keep);
    int ok;
    el_result r = el_mipmap_init(&m, img, cases[k].w, cases[k].h, 3, &o);
    ok = r == EL_SUCCESS && el_mipmap_levels(&m) == cases[k].levels;
    for (l = 0; ok && l < cases[k].levels; ++l)
      ok = el_mipmap_level_width(&m, l) == cases[k].sizes[l][0] && el_mipmap_level_height(&m, l) == cases[k].sizes[l][1];
    CHECKF(ok, "%dx%d%s: %d levels of the expected sizes", cases[k].w, cases[k].h,
           cases[k].keep ? " (keep_resolution)" : "", cases[k].levels);
    CHECKF(el_mipmap_level_width(&m, cases[k].levels) == 0 && el_mipmap_level_width(&m, -1) == 0,
           "  level width 0 outside [0, levels)");
    el_mipmap_free(&m);
    free(img);
  }
}

/* ---- laziness and bytes ------------------------------------------------------------------------ */
static void test_lazy(void) {
  float *img = random_image(64, 32, 3), o[3];
  el_mipmap m;
  size_t l0 = 64 * 32 * 3 * sizeof(float), all = 0;
  int l;
  el_mipmap_init(&m, img, 64, 32, 3, NULL);
  check(!el_mipmap_levels_built(&m), "lazy: after init levels 1.. are not built");
  CHECKF(el_mipmap_bytes(&m) == l0, "lazy: bytes after init = level 0 only (%zu)", l0);
  el_mipmap_bilerp(&m, 0, 0.3f, 0.6f, o);
  el_mipmap_texel(&m, 0, 5, 7, o);
  el_mipmap_lookup(&m, 0.3f, 0.6f, 0.0f, o);                            /* width 0: level 0 */
  el_mipmap_lookup_differentials(&m, 0.3f, 0.6f, 0.0f, 0.0f, 0.0f, 0.0f, o); /* zero footprint */
  check(!el_mipmap_levels_built(&m), "lazy: level-0 lookups build nothing");
  el_mipmap_lookup(&m, 0.3f, 0.6f, 0.2f, o);
  check(el_mipmap_levels_built(&m), "lazy: a wide trilinear lookup builds the upper levels");
  for (l = 0; l < el_mipmap_levels(&m); ++l)
    all += (size_t)el_mipmap_level_width(&m, l) * (size_t)el_mipmap_level_height(&m, l) * 3 * sizeof(float);
  CHECKF(el_mipmap_bytes(&m) == all, "bytes after the build = all levels (%zu)", all);
  check(el_mipmap_build_levels(&m) == EL_SUCCESS, "explicit build after a lazy one: success");
  el_mipmap_free(&m);
  check(el_mipmap_bytes(&m) == 0 && m.level_data[0] == NULL, "free zeroes the map");
  el_mipmap_free(&m);
  free(img);
}

/* ---- box levels against averages computed here ------------------------------------------------- */
static double texel_d(const float *img, int w, int x, int y, int c, int C) { return img[((size_t)y * w + x) * C + c]; }

static void test_box_levels(void) {
  float *img = random_image(8, 8, 3), *img2 = random_image(4, 1, 1), p5[5] = {1, 2, 4, 8, 16};
  float p3[3] = {1, 10, 100};
  el_mipmap m;
  const float *l1;
  int x, y, c, ok = 1;
  el_mipmap_init(&m, img, 8, 8, 3, NULL);
  l1 = el_mipmap_level_data(&m, 1);
  for (y = 0; y < 4; ++y)
    for (x = 0; x < 4; ++x)
      for (c = 0; c < 3; ++c) {
        double e = 0.25 * (texel_d(img, 8, 2 * x, 2 * y, c, 3) + texel_d(img, 8, 2 * x + 1, 2 * y, c, 3) +
                           texel_d(img, 8, 2 * x, 2 * y + 1, c, 3) + texel_d(img, 8, 2 * x + 1, 2 * y + 1, c, 3));
        if (rel(l1[(y * 4 + x) * 3 + c], e) > 1e-6) ok = 0;
      }
  check(ok, "8x8: level 1 texels are 2x2 box averages");
  el_mipmap_free(&m);
  /* 4x1 -> 2x1 -> 1x1: a 1-tall side reuses its row */
  el_mipmap_init(&m, img2, 4, 1, 1, NULL);
  l1 = el_mipmap_level_data(&m, 1);
  check(rel(l1[0], 0.5 * (img2[0] + img2[1])) < 1e-6 && rel(l1[1], 0.5 * (img2[2] + img2[3])) < 1e-6,
        "4x1: level 1 = pairwise averages");
  check(rel(el_mipmap_level_data(&m, 2)[0], 0.25 * (img2[0] + img2[1] + img2[2] + img2[3])) < 1e-6,
        "4x1: level 2 = mean");
  el_mipmap_free(&m);
  /* keep_resolution, odd sizes: exact area averages. 5 -> 2: output 0 covers texels [0, 2.5),
   * (p0 + p1 + 0.5 p2) / 2.5; output 1 covers [2.5, 5), (0.5 p2 + p3 + p4) / 2.5. 3 -> 1: the mean. */
  {
    el_mipmap_options o = opts(EL_MIPMAP_WRAP_BLACK, EL_MIPMAP_WRAP_BLACK, 1);
    el_mipmap_init(&m, p5, 5, 1, 1, &o);
    l1 = el_mipmap_level_data(&m, 1);
    CHECKF(rel(l1[0], (1 + 2 + 0.5 * 4) / 2.5) < 1e-6 && rel(l1[1], (0.5 * 4 + 8 + 16) / 2.5) < 1e-6,
           "keep 5x1 -> 2x1: area weights (1, 1, 1/2)/2.5 and (1/2, 1, 1)/2.5: got %g %g", l1[0], l1[1]);
    el_mipmap_free(&m);
    el_mipmap_init(&m, p3, 1, 3, 1, &o);
    CHECKF(rel(el_mipmap_level_data(&m, 1)[0], 37.0) < 1e-6, "keep 1x3 -> 1x1 = mean 37: got %g",
           el_mipmap_level_data(&m, 1)[0]);
    el_mipmap_free(&m);
  }
  free(img);
  free(img2);
}

/* ---- every level's mean equals the base mean ---------------------------------------------------- */
static void level_means(int w, int h, int keep, el_mipmap_wrap wu, el_mipmap_wrap wv) {
  float *img = random_image(w, h, 2);
  el_mipmap m;
  el_mipmap_options o = opts(wu, wv, keep);
  double base[2] = {0, 0}, worst = 0;
  int l, c;
  size_t i, n;
  el_mipmap_init(&m, img, w, h, 2, &o);
  for (l = 0; l < el_mipmap_levels(&m); ++l) {
    const float *d = el_mipmap_level_data(&m, l);
    double mean[2] = {0, 0};
    n = (size_t)el_mipmap_level_width(&m, l) * (size_t)el_mipmap_level_height(&m, l);
    for (i = 0; i < n; ++i)
      for (c = 0; c < 2; ++c) mean[c] += d[i * 2 + c];
    for (c = 0; c < 2; ++c) {
      mean[c] /= (double)n;
      if (l == 0) base[c] = mean[c];
      else if (rel(mean[c], base[c]) > worst) worst = rel(mean[c], base[c]);
    }
  }
  CHECKF(worst < 2e-6, "%dx%d%s %s/%s: every level's mean = level 0's (worst rel. diff %.2g)", w, h,
         keep ? " keep" : "", wrap_name(wu), wrap_name(wv), worst);
  if (keep) {
    double in = 0;
    for (i = 0; i < (size_t)w * h; ++i) in += img[2 * i];
    CHECKF(rel(in / ((double)w * h), base[0]) < 1e-6, "  keep_resolution: level 0 mean = input mean");
  }
  el_mipmap_free(&m);
  free(img);
}
static void test_means(void) {
  static const int sizes[][3] = {{16, 4, 0}, {4, 16, 0}, {1, 8, 0}, {8, 1, 0}, {64, 2, 0}, {400, 235, 1},
                                 {7, 5, 1}, {37, 1, 1}, {1, 19, 1}, {100, 60, 0}};
  static const el_mipmap_wrap wraps[3] = {EL_MIPMAP_WRAP_REPEAT, EL_MIPMAP_WRAP_CLAMP, EL_MIPMAP_WRAP_BLACK};
  int s, a;
  for (s = 0; s < (int)(sizeof sizes / sizeof sizes[0]); ++s)
    for (a = 0; a < 3; ++a) level_means(sizes[s][0], sizes[s][1], sizes[s][2], wraps[a], wraps[(a + 1) % 3]);
}

/* ---- constant images stay constant ----------------------------------------------------------- */
static void test_constant(void) {
  static const float cval[3] = {0.25f, 0.5f, 2.0f};
  static const el_mipmap_wrap wraps[2] = {EL_MIPMAP_WRAP_REPEAT, EL_MIPMAP_WRAP_CLAMP};
  int w = 37, h = 23, a, b, l, i, c, k;
  float *img = (float *)malloc(sizeof(float) * 3 * w * h);
  for (i = 0; i < w * h; ++i)
    for (c = 0; c < 3; ++c) img[3 * i + c] = cval[c];
  for (a = 0; a < 2; ++a)
    for (b = 0; b < 2; ++b)
      for (k = 0; k < 2; ++k) { /* k: filter of lookup_differentials, EWA then trilinear */
        el_mipmap m;
        el_mipmap_options o = opts(wraps[a], wraps[b], 0);
        double worst_level = 0, worst_lookup = 0;
        o.filter = k ? EL_MIPMAP_FILTER_TRILINEAR : EL_MIPMAP_FILTER_EWA;
        el_mipmap_init(&m, img, w, h, 3, &o);
        for (l = 0; l < el_mipmap_levels(&m); ++l) {
          const float *d = el_mipmap_level_data(&m, l);
          int n = el_mipmap_level_width(&m, l) * el_mipmap_level_height(&m, l);
          for (i = 0; i < n; ++i)
            for (c = 0; c < 3; ++c)
              if (rel(d[3 * i + c], cval[c]) > worst_level) worst_level = rel(d[3 * i + c], cval[c]);
        }
        for (i = 0; i < 3000; ++i) {
          float s = -1.5f + 4 * xorshift32_f(&g_rng), t = -1.5f + 4 * xorshift32_f(&g_rng), o4[8][3];
          float len = powf(10.0f, -4 + 4 * xorshift32_f(&g_rng)), ang = 6.2831853f * xorshift32_f(&g_rng), r = 1 + 30 * xorshift32_f(&g_rng);
          int f;
          el_mipmap_point(&m, (int)(xorshift32_f(&g_rng) * 12), s, t, o4[0]);
          el_mipmap_bilerp(&m, (int)(xorshift32_f(&g_rng) * 12), s, t, o4[1]);
          el_mipmap_lookup(&m, s, t, len, o4[2]);
          el_mipmap_lookup_filtered(&m, EL_MIPMAP_FILTER_POINT, s, t, len, o4[3]);
          el_mipmap_lookup_filtered(&m, EL_MIPMAP_FILTER_BILINEAR, s, t, len, o4[4]);
          el_mipmap_lookup_differentials(&m, s, t, len * cosf(ang), len * sinf(ang), -len / r * sinf(ang),
                                         len / r * cosf(ang), o4[5]);
          el_mipmap_lookup_differentials(&m, s, t, len, len, 2 * len, 2 * len, o4[6]); /* parallel */
          el_mipmap_texel(&m, (int)(xorshift32_f(&g_rng) * 12), (int)(xorshift32_f(&g_rng) * 200) - 100, (int)(xorshift32_f(&g_rng) * 200) - 100, o4[7]);
          for (f = 0; f < 8; ++f)
            for (c = 0; c < 3; ++c)
              if (rel(o4[f][c], cval[c]) > worst_lookup) worst_lookup = rel(o4[f][c], cval[c]);
        }
        CHECKF(worst_level < 1e-5 && worst_lookup < 1e-5,
               "constant 37x23 (resampled) %s/%s %s: levels and all lookups constant (worst %.2g, %.2g)",
               wrap_name(wraps[a]), wrap_name(wraps[b]), k ? "trilinear" : "EWA", worst_level, worst_lookup);
        el_mipmap_free(&m);
      }
  free(img);
}

/* ---- point and bilinear exact at texel centres; bilinear and trilinear by hand ------------------ */
static void test_centres(void) {
  static const int sizes[][3] = {{8, 4, 0}, {5, 3, 1}, {16, 16, 0}, {1, 6, 1}};
  int s;
  for (s = 0; s < 4; ++s) {
    int w = sizes[s][0], h = sizes[s][1], x, y, c, ok_b = 1, ok_p = 1, ok_l0 = 1;
    float *img = random_image(w, h, 3), o[3];
    el_mipmap m;
    el_mipmap_options op = opts(EL_MIPMAP_WRAP_CLAMP, EL_MIPMAP_WRAP_REPEAT, sizes[s][2]);
    el_mipmap_init(&m, img, w, h, 3, &op);
    for (y = 0; y < h; ++y)
      for (x = 0; x < w; ++x) {
        el_mipmap_bilerp(&m, 0, (x + 0.5f) / w, (y + 0.5f) / h, o);
        for (c = 0; c < 3; ++c) ok_b &= fabsf(o[c] - img[(y * w + x) * 3 + c]) <= 1e-6f * img[(y * w + x) * 3 + c];
        el_mipmap_point(&m, 0, (x + 0.01f + 0.98f * xorshift32_f(&g_rng)) / w, (y + 0.01f + 0.98f * xorshift32_f(&g_rng)) / h, o);
        for (c = 0; c < 3; ++c) ok_p &= o[c] == img[(y * w + x) * 3 + c];
        el_mipmap_lookup(&m, (x + 0.5f) / w, (y + 0.5f) / h, 0.0f, o);
        for (c = 0; c < 3; ++c) ok_l0 &= fabsf(o[c] - img[(y * w + x) * 3 + c]) <= 1e-6f * img[(y * w + x) * 3 + c];
      }
    CHECKF(ok_b, "%dx%d: bilinear at texel centres = the texels", w, h);
    CHECKF(ok_p, "%dx%d: point lookups anywhere inside a texel = that texel (exactly)", w, h);
    CHECKF(ok_l0, "%dx%d: trilinear with width 0 at texel centres = the texels", w, h);
    el_mipmap_free(&m);
    free(img);
  }
  /* Hand values on a 4x2 one-channel image (Repeat):
   *   row 0: 1 2 4 8      row 1: 16 32 64 128
   * bilinear at s = 2/4 (between texels 1 and 2), t = 0.25 (row 0 centre): (2 + 4) / 2 = 3;
   * at s = 2/4, t = 0.5 (between the rows): (2 + 4 + 32 + 64) / 4 = 25.5;
   * at s = 0 (between texel 3 and, wrapped, texel 0), t = 0.25: (8 + 1) / 2 = 4.5;
   * at s = 0.375 (x = 1), t = 0.375 (y = 0.25): 0.75 * 2 + 0.25 * 32 = 9.5. */
  {
    float img[8] = {1, 2, 4, 8, 16, 32, 64, 128}, o[1];
    el_mipmap m;
    el_mipmap_init(&m, img, 4, 2, 1, NULL);
    el_mipmap_bilerp(&m, 0, 0.5f, 0.25f, o);
    CHECKF(o[0] == 3.0f, "4x2 bilinear between two texels: 3 (got %g)", o[0]);
    el_mipmap_bilerp(&m, 0, 0.5f, 0.5f, o);
    CHECKF(o[0] == 25.5f, "4x2 bilinear between four texels: 25.5 (got %g)", o[0]);
    el_mipmap_bilerp(&m, 0, 0.0f, 0.25f, o);
    CHECKF(o[0] == 4.5f, "4x2 bilinear across the repeat seam: 4.5 (got %g)", o[0]);
    el_mipmap_bilerp(&m, 0, 0.375f, 0.375f, o);
    CHECKF(fabsf(o[0] - 9.5f) < 1e-6f, "4x2 bilinear at (1, 0.25) texels: 9.5 (got %g)", o[0]);
    el_mipmap_free(&m);
  }
  /* Trilinear level convention (pbrt-v3 after PR #275): level = levels - 1 + log2(width).
   * 16x16: 5 levels. width 1/16 -> level 0 (bilinear on level 0); width 1/8 -> level 1; width
   * sqrt(2)/16 -> level 0.5, the average of the bilinear lookups on levels 0 and 1; width >= 1 -> the
   * 1x1 level (the mean). */
  {
    float *img = random_image(16, 16, 1), o[1], a[1], b[1];
    double mean = 0;
    int i;
    el_mipmap m;
    for (i = 0; i < 256; ++i) mean += img[i];
    mean /= 256;
    el_mipmap_init(&m, img, 16, 16, 1, NULL);
    el_mipmap_bilerp(&m, 0, 0.3f, 0.7f, a);
    el_mipmap_bilerp(&m, 1, 0.3f, 0.7f, b);
    el_mipmap_lookup(&m, 0.3f, 0.7f, 1.0f / 16, o);
    CHECKF(fabsf(o[0] - a[0]) <= 1e-6f * a[0], "trilinear width 1/16 on 16x16 = bilinear on level 0");
    el_mipmap_lookup(&m, 0.3f, 0.7f, 1.0f / 8, o);
    CHECKF(fabsf(o[0] - b[0]) <= 1e-6f * b[0], "trilinear width 1/8 = bilinear on level 1");
    el_mipmap_lookup(&m, 0.3f, 0.7f, 1.41421356f / 16, o);
    CHECKF(fabsf(o[0] - 0.5f * (a[0] + b[0])) <= 2e-6f * a[0], "trilinear width sqrt(2)/16 = mean of levels 0 and 1");
    el_mipmap_lookup(&m, 0.3f, 0.7f, 1.0f, o);
    CHECKF(rel(o[0], mean) < 1e-6, "trilinear width 1 = the image mean (1x1 level)");
    el_mipmap_lookup_differentials(&m, 0.3f, 0.7f, 0.0f, 0.0f, 0.0f, 0.0f, o);
    CHECKF(fabsf(o[0] - a[0]) <= 1e-6f * a[0], "EWA with zero differentials = bilinear on level 0");
    el_mipmap_free(&m);
    free(img);
  }
}

/* ---- per-axis wrap at the borders ------------------------------------------------------------- */
static void test_wrap(void) {
  /* An asymmetric 4x3 image (an "F"): values 1..12 row by row, one channel. */
  float img[12] = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12}, o[1], e;
  el_mipmap m;
  el_mipmap_options op = opts(EL_MIPMAP_WRAP_REPEAT, EL_MIPMAP_WRAP_CLAMP, 1);
  el_mipmap_init(&m, img, 4, 3, 1, &op);
  el_mipmap_texel(&m, 0, -1, 0, o);
  check(o[0] == 4, "repeat u / clamp v: texel (-1, 0) = texel (3, 0)");
  el_mipmap_texel(&m, 0, 5, 1, o);
  check(o[0] == 6, "repeat u: texel (5, 1) = texel (1, 1)");
  el_mipmap_texel(&m, 0, 0, -1, o);
  check(o[0] == 1, "clamp v: texel (0, -1) = texel (0, 0)");
  el_mipmap_texel(&m, 0, 2, 7, o);
  check(o[0] == 11, "clamp v: texel (2, 7) = texel (2, 2)");
  el_mipmap_texel(&m, 0, -2147483647 - 1, 2147483647, o);
  check(o[0] == 9, "texel (INT_MIN, INT_MAX): repeat u gives column 0, clamp v row 2");
  el_mipmap_bilerp(&m, 0, 0.0f, 0.5f, o); /* x = -0.5: half texel 3, half texel 0 of row 1 */
  CHECKF(o[0] == 0.5f * (8 + 5), "repeat u at s = 0: (8 + 5)/2 (got %g)", o[0]);
  el_mipmap_bilerp(&m, 0, 0.125f, 0.0f, o); /* y = -0.5: clamp -> row 0 */
  CHECKF(o[0] == 1, "clamp v at t = 0: row 0 (got %g)", o[0]);
  el_mipmap_bilerp(&m, 0, 0.125f + 3.0f, 1.0f + 5.0f, o);
  CHECKF(o[0] == 9, "repeat u at s + 3, clamp v far below: texel (0, 2) (got %g)", o[0]);
  el_mipmap_bilerp(&m, 0, 0.125f + 1000000.0f, 0.5f, o);
  CHECKF(o[0] == 5, "repeat u at s + 1e6: texel (0, 1) (got %g)", o[0]);
  el_mipmap_free(&m);
  op = opts(EL_MIPMAP_WRAP_BLACK, EL_MIPMAP_WRAP_REPEAT, 1);
  el_mipmap_init(&m, img, 4, 3, 1, &op);
  el_mipmap_texel(&m, 0, -1, 0, o);
  check(o[0] == 0, "black u / repeat v: texel (-1, 0) = 0");
  el_mipmap_texel(&m, 0, 1, -1, o);
  check(o[0] == 10, "repeat v: texel (1, -1) = texel (1, 2)");
  el_mipmap_bilerp(&m, 0, 0.0f, 0.5f, o);
  CHECKF(o[0] == 0.5f * 5, "black u at s = 0: half of texel (0, 1) (got %g)", o[0]);
  el_mipmap_bilerp(&m, 0, 0.375f, 0.0f, o); /* x = 1, y = -0.5: rows 2 and 0 */
  CHECKF(o[0] == 0.5f * (10 + 2), "repeat v at t = 0: (10 + 2)/2 (got %g)", o[0]);
  el_mipmap_point(&m, 0, -0.01f, 0.5f, o);
  check(o[0] == 0, "black u: a point lookup left of the image is 0");
  el_mipmap_free(&m);
  /* Clamp u / Black v on the EWA path: a wide footprint far below the image is black, one far right
   * of it (Clamp) sees only the last column. */
  op = opts(EL_MIPMAP_WRAP_CLAMP, EL_MIPMAP_WRAP_BLACK, 1);
  el_mipmap_init(&m, img, 4, 3, 1, &op);
  el_mipmap_lookup_differentials(&m, 0.5f, 5.0f, 0.1f, 0, 0, 0.1f, o);
  check(o[0] == 0, "black v: EWA footprint far below the image = 0");
  el_mipmap_lookup_differentials(&m, 1e30f, 0.5f, 1e-3f, 0, 0, 1e-3f, o);
  e = 8; /* texel (3, 1) */
  CHECKF(fabsf(o[0] - e) < 1e-5f, "clamp u: EWA at s = 1e30 (small footprint) = texel (3, 1) (got %g)", o[0]);
  el_mipmap_free(&m);
}

/* ---- EWA against a brute-force Gaussian footprint on an anisotropic checkerboard ---------------- */
/* An anisotropic checkerboard: 2-texel-wide columns of contrast 2:1 times 8-texel-tall bands of
 * contrast 10:1 (a product, so that averaging across the columns keeps the bands). */
static float checker(int x, int y) { return (((y >> 3) & 1) ? 1.0f : 0.1f) * (((x >> 1) & 1) ? 1.0f : 0.5f); }
static double gaussian_reference(const float *img, int n, float s, float t, float d0s, float d0t, float d1s,
                                 float d1t) {
  /* pbrt's filter shape exp(-2 r^2) - exp(-2), r < 1, over the ellipse {st + u dst0 + v dst1}, each
   * sample the texel containing it (Repeat), 64 x 64 stratified samples. */
  double sum = 0, sw = 0;
  int i, j;
  for (j = 0; j < 64; ++j)
    for (i = 0; i < 64; ++i) {
      double u = -1 + (2 * i + 1) / 64.0, v = -1 + (2 * j + 1) / 64.0, r2 = u * u + v * v, w;
      double x, y;
      int xi, yi;
      if (r2 >= 1) continue;
      w = exp(-2 * r2) - exp(-2.0);
      x = (s + u * d0s + v * d1s) * n;
      y = (t + u * d0t + v * d1t) * n;
      xi = (int)floor(x);
      yi = (int)floor(y);
      xi = ((xi % n) + n) % n;
      yi = ((yi % n) + n) % n;
      sum += w * img[yi * n + xi];
      sw += w;
    }
  return sum / sw;
}
static void test_ewa(void) {
  int n = 256, x, y, i;
  float *img = (float *)malloc(sizeof(float) * n * n);
  el_mipmap m, mt;
  el_mipmap_options o;
  double err_ewa = 0, err_tri = 0, max_ewa = 0;
  for (y = 0; y < n; ++y)
    for (x = 0; x < n; ++x) img[y * n + x] = checker(x, y);
  el_mipmap_init(&m, img, n, n, 1, NULL); /* EWA, anisotropy 8 */
  o = opts(EL_MIPMAP_WRAP_REPEAT, EL_MIPMAP_WRAP_REPEAT, 0);
  o.filter = EL_MIPMAP_FILTER_TRILINEAR;
  el_mipmap_init(&mt, img, n, n, 1, &o);
  /* Footprints elongated across the 2-texel columns (u), narrow along v where the 16-texel checks
   * are: the ideal filter averages the columns away and keeps the rows. Major 8..24 texels along u,
   * minor 1..3 along v, slightly rotated. */
  for (i = 0; i < 400; ++i) {
    float s = xorshift32_f(&g_rng), t = xorshift32_f(&g_rng), major = (8 + 16 * xorshift32_f(&g_rng)) / n, minor = (1 + 2 * xorshift32_f(&g_rng)) / n;
    float ang = 0.2f * (xorshift32_f(&g_rng) - 0.5f), r[1], q[1];
    float d0s = major * cosf(ang), d0t = major * sinf(ang), d1s = -minor * sinf(ang), d1t = minor * cosf(ang);
    double ref = gaussian_reference(img, n, s, t, d0s, d0t, d1s, d1t), e;
    el_mipmap_lookup_differentials(&m, s, t, d0s, d0t, d1s, d1t, r);
    el_mipmap_lookup_differentials(&mt, s, t, d0s, d0t, d1s, d1t, q);
    e = fabs(r[0] - ref);
    err_ewa += e * e;
    err_tri += (q[0] - ref) * (q[0] - ref);
    if (e > max_ewa) max_ewa = e;
  }
  err_ewa = sqrt(err_ewa / 400);
  err_tri = sqrt(err_tri / 400);
  /* Stated error: EWA blurs by the MIP level it reads (the minor axis is 1-2 texels there) and by
   * pbrt's +1 texel regularisation, so it is not the ideal filter; on this 0.1/1 checkerboard its rms
   * error against the ideal footprint stays below 0.06 (measured 0.035) and its worst below 0.25,
   * while isotropic trilinear, which must blur over the major axis, is at least twice as far off. */
  CHECKF(err_ewa < 0.06, "EWA vs supersampled Gaussian footprint, anisotropic checkerboard: rms %.4f < 0.06", err_ewa);
  CHECKF(max_ewa < 0.25, "  worst EWA error %.4f < 0.25", max_ewa);
  CHECKF(err_tri > 2 * err_ewa, "  trilinear is further off (rms %.4f > 2 x %.4f)", err_tri, err_ewa);
  el_mipmap_free(&m);
  el_mipmap_free(&mt);
  free(img);
}

/* ---- lookups against pbrt-v3's algorithm, transcribed here in float ------------------------------ */
/* pbrt-v3's Texel, triangle, Lookup(st, width) and EWA / Lookup(st, dst0, dst1) (src/core/mipmap.h)
 * and pbrt-v4's bilinear Lookup (Bilerp on level max(0, floor(level))), written out again line by line
 * over the levels (which test_box_levels checks against box averages), with Repeat in u and Clamp in
 * v. mipmap.h must give the same results to float precision: it trims each EWA row to the ellipse's
 * chord, walks ss and tt incrementally and has fast paths for footprints inside a level, all of which
 * must leave every texel's weight as pbrt's. (The only intended difference is the level's logarithm,
 * within about 1e-7 of log2f, which moves the blend between two levels in its last bits.) */
static void ref_texel(const el_mipmap *m, int l, int s, int t, float *o) {
  int w = el_mipmap_level_width(m, l), h = el_mipmap_level_height(m, l), c;
  const float *p;
  s = ((s % w) + w) % w;             /* Repeat */
  t = t < 0 ? 0 : (t >= h ? h - 1 : t); /* Clamp */
  p = el_mipmap_level_data(m, l) + 3 * ((size_t)t * (size_t)w + (size_t)s);
  for (c = 0; c < 3; ++c) o[c] = p[c];
}
static void ref_triangle(const el_mipmap *m, int l, float s, float t, float *o) {
  float a[3], b[3], cc[3], d[3], ds, dt;
  int s0, t0, c;
  l = l < 0 ? 0 : (l >= el_mipmap_levels(m) ? el_mipmap_levels(m) - 1 : l);
  s = s * el_mipmap_level_width(m, l) - 0.5f;
  t = t * el_mipmap_level_height(m, l) - 0.5f;
  s0 = (int)floorf(s);
  t0 = (int)floorf(t);
  ds = s - s0;
  dt = t - t0;
  ref_texel(m, l, s0, t0, a);
  ref_texel(m, l, s0, t0 + 1, b);
  ref_texel(m, l, s0 + 1, t0, cc);
  ref_texel(m, l, s0 + 1, t0 + 1, d);
  for (c = 0; c < 3; ++c)
    o[c] = (1 - ds) * (1 - dt) * a[c] + (1 - ds) * dt * b[c] + ds * (1 - dt) * cc[c] + ds * dt * d[c];
}
static void ref_trilinear(const el_mipmap *m, float s, float t, float width, float *o) {
  int n = el_mipmap_levels(m), il, c;
  float level = n - 1 + log2f(width > 1e-8f ? width : 1e-8f), a[3], b[3], delta;
  if (level < 0) {
    ref_triangle(m, 0, s, t, o);
    return;
  }
  if (level >= n - 1) {
    ref_texel(m, n - 1, 0, 0, o);
    return;
  }
  il = (int)floorf(level);
  delta = level - il;
  ref_triangle(m, il, s, t, a);
  ref_triangle(m, il + 1, s, t, b);
  for (c = 0; c < 3; ++c) o[c] = (1 - delta) * a[c] + delta * b[c];
}
static void ref_bilinear(const el_mipmap *m, float s, float t, float width, float *o) { /* pbrt-v4 */
  int n = el_mipmap_levels(m);
  float level = n - 1 + log2f(width > 1e-8f ? width : 1e-8f);
  if (level >= n - 1) {
    ref_texel(m, n - 1, 0, 0, o);
    return;
  }
  ref_triangle(m, level < 0 ? 0 : (int)floorf(level), s, t, o);
}
static void ref_ewa_level(const el_mipmap *m, int l, float s, float t, float d00, float d01, float d10,
                          float d11, float *o) {
  float A, B, C, invF, det, invDet, uSqrt, vSqrt, sum[3] = {0, 0, 0}, sumWts = 0, lut[128], w, h;
  int s0, s1, t0, t1, it, is, i, c;
  if (l >= el_mipmap_levels(m)) {
    ref_texel(m, el_mipmap_levels(m) - 1, 0, 0, o);
    return;
  }
  for (i = 0; i < 128; ++i) lut[i] = expf(-2.0f * ((float)i / 127.0f)) - expf(-2.0f);
  w = (float)el_mipmap_level_width(m, l);
  h = (float)el_mipmap_level_height(m, l);
  s = s * w - 0.5f;
  t = t * h - 0.5f;
  d00 *= w;
  d01 *= h;
  d10 *= w;
  d11 *= h;
  A = d01 * d01 + d11 * d11 + 1;
  B = -2 * (d00 * d01 + d10 * d11);
  C = d00 * d00 + d10 * d10 + 1;
  invF = 1 / (A * C - B * B * 0.25f);
  A *= invF;
  B *= invF;
  C *= invF;
  det = -B * B + 4 * A * C;
  invDet = 1 / det;
  uSqrt = sqrtf(det * C);
  vSqrt = sqrtf(A * det);
  s0 = (int)ceilf(s - 2 * invDet * uSqrt);
  s1 = (int)floorf(s + 2 * invDet * uSqrt);
  t0 = (int)ceilf(t - 2 * invDet * vSqrt);
  t1 = (int)floorf(t + 2 * invDet * vSqrt);
  for (it = t0; it <= t1; ++it) {
    float tt = it - t;
    for (is = s0; is <= s1; ++is) {
      float ss = is - s, r2 = A * ss * ss + B * ss * tt + C * tt * tt, wt, tx[3];
      if (r2 >= 1) continue;
      i = (int)(r2 * 128);
      wt = lut[i > 127 ? 127 : i];
      ref_texel(m, l, is, it, tx);
      for (c = 0; c < 3; ++c) sum[c] += tx[c] * wt;
      sumWts += wt;
    }
  }
  for (c = 0; c < 3; ++c) o[c] = sum[c] / sumWts;
}
static void ref_ewa(const el_mipmap *m, float s, float t, float d00, float d01, float d10, float d11, float *o) {
  float major, minor, lod, a[3], b[3];
  int ilod, c;
  if (d00 * d00 + d01 * d01 < d10 * d10 + d11 * d11) {
    float x = d00, y = d01;
    d00 = d10;
    d01 = d11;
    d10 = x;
    d11 = y;
  }
  major = sqrtf(d00 * d00 + d01 * d01);
  minor = sqrtf(d10 * d10 + d11 * d11);
  if (minor * 8 < major && minor > 0) { /* max anisotropy 8 */
    float scale = major / (minor * 8);
    d10 *= scale;
    d11 *= scale;
    minor *= scale;
  }
  lod = el_mipmap_levels(m) - (float)1 + log2f(minor);
  if (lod < 0) lod = 0;
  ilod = (int)floorf(lod);
  ref_ewa_level(m, ilod, s, t, d00, d01, d10, d11, a);
  ref_ewa_level(m, ilod + 1, s, t, d00, d01, d10, d11, b);
  for (c = 0; c < 3; ++c) o[c] = (1 - (lod - ilod)) * a[c] + (lod - ilod) * b[c];
}
static float max_rel3(const float *a, const float *b) {
  float d = 0;
  int c;
  for (c = 0; c < 3; ++c) {
    float e = fabsf(a[c] - b[c]) / (fabsf(b[c]) > 1e-3f ? fabsf(b[c]) : 1e-3f);
    if (e > d) d = e;
  }
  return d;
}
static void test_pbrt_algorithm(void) {
  /* 128x64 RGB, Repeat in u and Clamp in v (an environment map's modes). Coordinates in [-0.15, 1.15]
   * and footprints from a third of a texel to a fifth of the texture, so that lookups fall inside
   * levels (the fast paths), across their borders and seams (the general paths), and on the coarsest
   * levels. */
  float *img = random_image(128, 64, 3), o[3], r[3], dtri = 0, dewa = 0, dbil = 0;
  el_mipmap m;
  el_mipmap_options op = opts(EL_MIPMAP_WRAP_REPEAT, EL_MIPMAP_WRAP_CLAMP, 0);
  int i;
  el_mipmap_init(&m, img, 128, 64, 3, &op);
  for (i = 0; i < 3000; ++i) {
    float s = -0.15f + 1.3f * xorshift32_f(&g_rng), t = -0.15f + 1.3f * xorshift32_f(&g_rng);
    float len = powf(10.0f, -2.6f + 1.9f * xorshift32_f(&g_rng)), ratio = 1 + 11 * xorshift32_f(&g_rng);
    float ang = 6.2831853f * xorshift32_f(&g_rng), e;
    float d0s = len * cosf(ang), d0t = len * sinf(ang), d1s = -len / ratio * sinf(ang), d1t = len / ratio * cosf(ang);
    el_mipmap_lookup(&m, s, t, 2 * len, o);
    ref_trilinear(&m, s, t, 2 * len, r);
    e = max_rel3(o, r);
    if (e > dtri) dtri = e;
    el_mipmap_lookup_filtered(&m, EL_MIPMAP_FILTER_BILINEAR, s, t, 2 * len, o);
    ref_bilinear(&m, s, t, 2 * len, r);
    e = max_rel3(o, r);
    if (e > dbil) dbil = e;
    el_mipmap_lookup_differentials(&m, s, t, d0s, d0t, d1s, d1t, o);
    ref_ewa(&m, s, t, d0s, d0t, d1s, d1t, r);
    e = max_rel3(o, r);
    if (e > dewa) dewa = e;
  }
  /* A texel weighted wrongly, or one row or column more or less, moves a result by 1e-3 or more. */
  CHECKF(dtri < 2e-5f, "trilinear equals pbrt-v3's algorithm to float precision (3000 lookups, max rel. diff %.2g)",
         dtri);
  CHECKF(dbil < 2e-5f, "bilinear (pbrt-v4's filter) equals its algorithm to float precision (max rel. diff %.2g)",
         dbil);
  CHECKF(dewa < 2e-5f, "EWA equals pbrt-v3's algorithm to float precision (3000 lookups, max rel. diff %.2g)", dewa);
  el_mipmap_free(&m);
  free(img);
}

/* Differentials with the non-EWA filters, against the pbrt code they follow, written out again:
 * pbrt-v3 (src/core/mipmap.h, since commit aaa552a "Fix trilinear filtering") computes
 *     Float width = std::max(std::max(std::abs(dst0[0]), std::abs(dst0[1])),
 *                            std::max(std::abs(dst1[0]), std::abs(dst1[1])));
 *     return Lookup(st, width);
 * for doTrilinear (before that commit it passed 2 * width); pbrt-v4's MIPMap::Filter passes 2 * width
 * for its point and bilinear filters. */
static void test_differentials_width(void) {
  float *img = random_image(128, 64, 3), o[3], r[3], dtri = 0, dbil = 0, dold = 0;
  el_mipmap mt, mb;
  el_mipmap_options op = opts(EL_MIPMAP_WRAP_REPEAT, EL_MIPMAP_WRAP_CLAMP, 0);
  int i;
  op.filter = EL_MIPMAP_FILTER_TRILINEAR;
  el_mipmap_init(&mt, img, 128, 64, 3, &op);
  op.filter = EL_MIPMAP_FILTER_BILINEAR;
  el_mipmap_init(&mb, img, 128, 64, 3, &op);
  for (i = 0; i < 2000; ++i) {
    float s = -0.15f + 1.3f * xorshift32_f(&g_rng), t = -0.15f + 1.3f * xorshift32_f(&g_rng);
    float len = powf(10.0f, -2.6f + 1.9f * xorshift32_f(&g_rng)), ratio = 1 + 11 * xorshift32_f(&g_rng), ang = 6.2831853f * xorshift32_f(&g_rng), e;
    float d0s = len * cosf(ang), d0t = len * sinf(ang), d1s = -len / ratio * sinf(ang), d1t = len / ratio * cosf(ang);
    float width = fmaxf(fmaxf(fabsf(d0s), fabsf(d0t)), fmaxf(fabsf(d1s), fabsf(d1t)));
    el_mipmap_lookup_differentials(&mt, s, t, d0s, d0t, d1s, d1t, o);
    ref_trilinear(&mt, s, t, width, r); /* pbrt-v3: Lookup(st, width) */
    e = max_rel3(o, r);
    if (e > dtri) dtri = e;
    ref_trilinear(&mt, s, t, 2 * width, r); /* the old formula, which must differ */
    e = max_rel3(o, r);
    if (e > dold) dold = e;
    el_mipmap_lookup_differentials(&mb, s, t, d0s, d0t, d1s, d1t, o);
    ref_bilinear(&mb, s, t, 2 * width, r); /* pbrt-v4: Lookup(st, 2 * width) */
    e = max_rel3(o, r);
    if (e > dbil) dbil = e;
  }
  CHECKF(dtri < 2e-5f, "trilinear differentials: pbrt-v3's Lookup(st, max |d|) (2000 lookups, max rel. diff %.2g)", dtri);
  CHECKF(dold > 1e-2f, "... and not the old Lookup(st, 2 max |d|) (max rel. diff %.2g)", dold);
  CHECKF(dbil < 2e-5f, "bilinear differentials: pbrt-v4's Lookup(st, 2 max |d|) (max rel. diff %.2g)", dbil);
  el_mipmap_free(&mt);
  el_mipmap_free(&mb);
  free(img);
}

/* ---- resampling against the Lanczos weights written out again ---------------------------------- */
static double lanczos_d(double x) { /* windowed sinc, tau = 2, on [-1, 1] as pbrt's Lanczos(x, 2) */
  const double pi = 3.14159265358979323846;
  x = fabs(x);
  if (x < 1e-5) return 1;
  if (x > 1) return 0;
  return sin(pi * x * 2) / (pi * x * 2) * sin(pi * x) / (pi * x);
}
static void test_resample(void) {
  /* 3x1 -> 4x1, Clamp: output i is centred at (i + 0.5) * 3/4 in input texels; taps at
   * floor(centre - 2 + 0.5) + j, j = 0..3, weights Lanczos((tap + 0.5 - centre) / 2), normalised;
   * negative results clamped to 0. */
  float img[3] = {1.0f, 5.0f, 2.0f};
  el_mipmap m;
  el_mipmap_options o = opts(EL_MIPMAP_WRAP_CLAMP, EL_MIPMAP_WRAP_CLAMP, 0);
  const float *d;
  int i, j, ok = 1;
  el_mipmap_init(&m, img, 3, 1, 1, &o);
  d = el_mipmap_level_data(&m, 0);
  for (i = 0; i < 4; ++i) {
    double centre = (i + 0.5) * 3.0 / 4.0, wsum = 0, v = 0;
    int first = (int)floor(centre - 2 + 0.5);
    for (j = 0; j < 4; ++j) {
      double w = lanczos_d((first + j + 0.5 - centre) / 2);
      int k = first + j < 0 ? 0 : (first + j > 2 ? 2 : first + j);
      wsum += w;
      v += w * img[k];
    }
    v /= wsum;
    if (v < 0) v = 0;
    if (fabs(d[i] - v) > 1e-5 * fabs(v) + 1e-6) ok = 0;
    printf("  resampled texel %d: %.6f (expected %.6f)\n", i, d[i], v);
  }
  check(ok, "3x1 -> 4x1 resampling = Lanczos(tau 2) weights written out again");
  el_mipmap_free(&m);
}

/* ---- hard inputs give finite values inside the texel range ----------------------------------- */
static void test_hard_inputs(void) {
  const float inf = (float)HUGE_VAL, nan = (float)(HUGE_VAL - HUGE_VAL);
  const float coords[] = {nan, inf, -inf, 1e30f, -1e30f, 1e9f + 0.5f, -7.25f, 0.0f, 1.0f, 0.5f, -1e-30f, 3e38f};
  const float widths[] = {nan, -1.0f, 0.0f, 1e-30f, 1e-4f, 0.3f, 1e30f, inf};
  const float diffs[][4] = {{0, 0, 0, 0},       {1e-3f, 1e-3f, 2e-3f, 2e-3f}, {nan, 0, 0, nan},
                            {inf, 0, 0, inf},   {1e30f, -1e30f, 1e30f, 1e30f}, {1e-40f, 0, 0, 1e-40f},
                            {0.1f, 0, 0, 0},    {1e-2f, 0, 0, 1e-9f},          {-inf, nan, inf, 1},
                            {0.3f, 0.2f, -0.2f, 0.3f}};
  static const el_mipmap_wrap wraps[3] = {EL_MIPMAP_WRAP_REPEAT, EL_MIPMAP_WRAP_CLAMP, EL_MIPMAP_WRAP_BLACK};
  int a, b, i, j, k, c, bad = 0, count = 0;
  float hi = -1e30f;
  float *img = random_image(32, 16, 3); /* a power of two: no resampling, so every result is a
                                           convex combination of texels (or 0 under Black) */
  for (i = 0; i < 32 * 16 * 3; ++i)
    if (img[i] > hi) hi = img[i];
  for (a = 0; a < 3; ++a)
    for (b = 0; b < 3; ++b) {
      el_mipmap m[2];
      el_mipmap_options o = opts(wraps[a], wraps[b], 0);
      int f;
      el_mipmap_init(&m[0], img, 32, 16, 3, &o);
      o.max_anisotropy = 1024;
      el_mipmap_init(&m[1], img, 32, 16, 3, &o);
      for (f = 0; f < 2; ++f)
        for (i = 0; i < (int)(sizeof coords / sizeof coords[0]); ++i)
          for (j = 0; j < (int)(sizeof coords / sizeof coords[0]); ++j) {
            float out[6][3];
            for (k = 0; k < (int)(sizeof widths / sizeof widths[0]); ++k) {
              el_mipmap_lookup(&m[f], coords[i], coords[j], widths[k], out[0]);
              el_mipmap_lookup_filtered(&m[f], EL_MIPMAP_FILTER_POINT, coords[i], coords[j], widths[k], out[1]);
              el_mipmap_lookup_filtered(&m[f], EL_MIPMAP_FILTER_BILINEAR, coords[i], coords[j], widths[k], out[2]);
              el_mipmap_point(&m[f], k - 2, coords[i], coords[j], out[3]);
              el_mipmap_bilerp(&m[f], k * 3 - 5, coords[i], coords[j], out[4]);
              el_mipmap_texel(&m[f], k, (int)(xorshift32_f(&g_rng) * 4e9f - 2e9f), (int)(xorshift32_f(&g_rng) * 4e9f - 2e9f), out[5]);
              for (c = 0; c < 18; ++c) {
                float v = out[c / 3][c % 3];
                count++;
                if (!(v >= 0 && v <= hi * (1 + 1e-6f))) bad++; /* also catches NaN */
              }
            }
            for (k = 0; k < (int)(sizeof diffs / sizeof diffs[0]); ++k) {
              el_mipmap_lookup_differentials(&m[f], coords[i], coords[j], diffs[k][0], diffs[k][1], diffs[k][2],
                                             diffs[k][3], out[0]);
              for (c = 0; c < 3; ++c) {
                count++;
                if (!(out[0][c] >= 0 && out[0][c] <= hi * (1 + 1e-6f))) bad++;
              }
            }
          }
      el_mipmap_free(&m[0]);
      el_mipmap_free(&m[1]);
    }
  CHECKF(bad == 0, "hard inputs (NaN, inf, 1e30, huge ints, NaN/negative/inf widths, zero/parallel/NaN/inf "
                   "differentials, every wrap pair, anisotropy 8 and 1024): %d results, %d not finite in "
                   "[0, max texel]", count, bad);
  free(img);
}

/* ---- init errors ----------------------------------------------------------------------------- */
static void test_errors(void) {
  float img[12] = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12};
  el_mipmap m;
  el_mipmap_options o = opts(EL_MIPMAP_WRAP_REPEAT, EL_MIPMAP_WRAP_REPEAT, 0);
  check(el_mipmap_init(NULL, img, 2, 2, 3, NULL) == EL_ERROR_INVALID_ARGUMENT, "NULL map rejected");
  check(el_mipmap_init(&m, NULL, 2, 2, 3, NULL) == EL_ERROR_INVALID_ARGUMENT, "NULL pixels rejected");
  check(el_mipmap_init(&m, img, 0, 2, 3, NULL) == EL_ERROR_INVALID_ARGUMENT, "width 0 rejected");
  check(el_mipmap_init(&m, img, 2, 2, 5, NULL) == EL_ERROR_INVALID_ARGUMENT, "5 channels rejected");
  o.wrap_v = (el_mipmap_wrap)7;
  check(el_mipmap_init(&m, img, 2, 2, 3, &o) == EL_ERROR_INVALID_ARGUMENT, "unknown wrap mode rejected");
  o.wrap_v = EL_MIPMAP_WRAP_REPEAT;
  o.max_anisotropy = -1;
  check(el_mipmap_init(&m, img, 2, 2, 3, &o) == EL_ERROR_INVALID_ARGUMENT, "negative max_anisotropy rejected");
  o.max_anisotropy = (float)(HUGE_VAL - HUGE_VAL);
  check(el_mipmap_init(&m, img, 2, 2, 3, &o) == EL_ERROR_NAN, "NaN max_anisotropy: EL_ERROR_NAN");
  o.max_anisotropy = 0;
  img[7] = (float)(HUGE_VAL - HUGE_VAL); /* float 7 = texel 2 = (x 0, y 1) */
  check(el_mipmap_init(&m, img, 2, 2, 3, &o) == EL_ERROR_NAN && m.bad_index == 2 && m.level_data[0] == NULL,
        "a NaN texel: EL_ERROR_NAN, m.bad_index names texel 2 (y*width+x), the rest zeroed");
  img[7] = (float)HUGE_VAL;
  check(el_mipmap_init(&m, img, 2, 2, 3, &o) == EL_ERROR_INFINITE && m.bad_index == 2,
        "an infinite texel: EL_ERROR_INFINITE, m.bad_index 2");
  img[11] = (float)-HUGE_VAL;
  check(el_mipmap_init(&m, img, 4, 1, 3, &o) == EL_ERROR_INFINITE && m.bad_index == 2,
        "the first of two bad texels is named");
  img[7] = 8;
  check(el_mipmap_init(&m, img, 4, 1, 3, &o) == EL_ERROR_INFINITE && m.bad_index == 3, "texel 3 of a 4x1 map");
  img[11] = 12;
  check(el_mipmap_init(&m, img, (1 << 24) + 1, 1, 1, &o) == EL_ERROR_SIZE_OVERFLOW && m.bad_index == -1,
        "a side above 2^24: size overflow, bad_index -1 (no texel to blame)");
  check(m.level_data[0] == NULL && m.levels == 0, "failed init leaves a zeroed map");
  el_mipmap_free(&m);
  check(el_mipmap_init(&m, img, 2, 2, 3, &o) == EL_SUCCESS && m.max_anisotropy == 8.0f && m.filter == EL_MIPMAP_FILTER_EWA &&
            m.bad_index == -1,
        "all-zero options: EWA, max anisotropy 8 (pbrt's defaults); bad_index -1");
  el_mipmap_free(&m);
}

/* ---- concurrent first lookups build the levels once ---------------------------------------- */
typedef struct thread_arg {
  el_mipmap *m;
  float out[64];
} thread_arg;
static void *lookup_thread(void *p) {
  thread_arg *a = (thread_arg *)p;
  int i;
  for (i = 0; i < 64; ++i) el_mipmap_lookup(a->m, (i + 0.5f) / 64, 0.5f, 1.0f, a->out + i);
  return NULL;
}
static void test_threads(void) {
  float *img = random_image(512, 256, 1);
  double mean = 0;
  int i, k, ok = 1;
  pthread_t th[4];
  thread_arg args[4];
  el_mipmap m;
  for (i = 0; i < 512 * 256; ++i) mean += img[i];
  mean /= 512 * 256;
  el_mipmap_init(&m, img, 512, 256, 1, NULL);
  for (k = 0; k < 4; ++k) {
    args[k].m = &m;
    pthread_create(&th[k], NULL, lookup_thread, &args[k]);
  }
  for (k = 0; k < 4; ++k) pthread_join(th[k], NULL);
  for (k = 0; k < 4; ++k)
    for (i = 0; i < 64; ++i) ok &= rel(args[k].out[i], mean) < 1e-5;
  check(ok && el_mipmap_levels_built(&m), "4 threads' first lookups (width 1) all see the built levels: the mean");
  el_mipmap_free(&m);
  free(img);
}

int main(void) {
  test_sizes();
  test_lazy();
  test_box_levels();
  test_means();
  test_constant();
  test_centres();
  test_wrap();
  test_ewa();
  test_pbrt_algorithm();
  test_differentials_width();
  test_resample();
  test_hard_inputs();
  test_errors();
  test_threads();
  printf("test_mipmap: %d passed, %d failed\n", g_pass, g_fail);
  return g_fail != 0;
}
