/* test_tutorial_mipmap.c: the course's plain C port of pbrt-v3's MIPMap (examples/pbrtv3/mipmap.h,
 * chapters 1 and 2) against the library (mipmap.h) on the same inputs.
 *
 * The port is pbrt-v3's code transcribed line by line; the library claims pbrt's results. Where it
 * claims them bit for bit, this test compares bits; where it departs, the test states the bound and the
 * reason, and checks both:
 *  - levels (resampling to a power of two, box-filtered levels), Texel() under every wrap mode, and
 *    triangle() (bilinear) on every level: bit for bit;
 *  - Lookup(st, width) for widths below one texel of level 0 (level 0, bilinear) and at or above 1 (the
 *    1x1 level): bit for bit; between, within 1e-5 relative (measured about 3e-6). The reason: the
 *    library computes the level's log2 without libm (the float's exponent, a table and a series, within
 *    about 1e-7), pbrt-v3 as logf(x) / log(2), so the blend weight between two levels moves in its last
 *    bits;
 *  - Lookup(st, dst0, dst1), EWA: bit for bit when the minor axis is shorter than a texel of level 0
 *    (both use level 0 alone), within 1e-5 relative otherwise (the same logarithm);
 *  - with doTrilinear (the library's EL_MIPMAP_FILTER_TRILINEAR): the width is max |d|, as pbrt-v3's
 *    source since its commit aaa552a "Fix trilinear filtering", within the same bound, and not the
 *    2 max |d| of the code before it;
 *  - Black wrap on a non-square image: the port's levels past the one where a side reaches 1 lose half
 *    their mean per level (pbrt reads texel 2t+1 of a 1-high level through the wrap mode, and Black
 *    gives 0); the library's keep the mean. Equal up to that level, bit for bit.
 * The inputs: the course's 400x235 test image (examples/common/picture.h), random images of 64x32,
 * 13x7, 32x32, 64x16 and 1x1, each wrap mode. */
#define EL_IMPLEMENTATION
#include "mipmap.h"
#include "../examples/pbrtv3/mipmap.h"
#include "picture.h" /* el_test_image: the course's test image */

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int g_pass, g_fail;
static char g_buf[512];
#define CHECKF(ok, ...)                                                                             \
  do {                                                                                              \
    snprintf(g_buf, sizeof g_buf, __VA_ARGS__);                                                     \
    if (ok) g_pass++;                                                                               \
    else g_fail++;                                                                                  \
    printf("%s: %s\n", (ok) ? "PASS" : "FAIL", g_buf);                                              \
  } while (0)

#define BOUND 1e-6f /* the stated bound where the library's logarithm differs from pbrt's: a fraction
                       of the image's largest texel */

#include "test_rng.h" /* xorshift32_f */
static xorshift32 g_rng = {2463534242u};
static float *random_image(int w, int h) {
  float *p = (float *)malloc(sizeof(float) * 3 * (size_t)w * (size_t)h);
  int i;
  for (i = 0; i < 3 * w * h; ++i) p[i] = 0.05f + xorshift32_f(&g_rng);
  return p;
}
static int same_bits(const float *a, const float *b, int n) { return memcmp(a, b, sizeof(float) * (size_t)n) == 0; }
/* The largest difference of 3 channels, as a fraction of the image's largest texel. */
static float diff3(const float *a, const float *b, float scale) {
  float d = 0;
  int c;
  for (c = 0; c < 3; ++c)
    if (fabsf(a[c] - b[c]) > d) d = fabsf(a[c] - b[c]);
  return d / scale;
}
static float max_texel(const float *img, int n) {
  float m = 0;
  int i;
  for (i = 0; i < 3 * n; ++i)
    if (img[i] > m) m = img[i];
  return m;
}
static const char *wrap_name(int w) { return w == 0 ? "Repeat" : (w == 1 ? "Black" : "Clamp"); }

/* Port and library built on the same image. */
typedef struct pair {
  pbrt_MIPMap p;
  el_mipmap m;
  int w, h, wrap;
} pair;
static int pair_init(pair *q, const float *img, int w, int h, int wrap, int doTrilinear) {
  el_mipmap_options o;
  memset(&o, 0, sizeof o);
  o.wrap_u = o.wrap_v = (el_mipmap_wrap)wrap; /* pbrt's ImageWrap values: Repeat 0, Black 1, Clamp 2 */
  o.filter = doTrilinear ? EL_MIPMAP_FILTER_TRILINEAR : EL_MIPMAP_FILTER_EWA;
  q->w = w;
  q->h = h;
  q->wrap = wrap;
  pbrt_MIPMap_init(&q->p, pbrt_Point2i_make(w, h), (const pbrt_RGBSpectrum *)img, doTrilinear, 8.f, (pbrt_ImageWrap)wrap);
  if (el_mipmap_init(&q->m, img, w, h, 3, &o) != EL_SUCCESS) return 0;
  return el_mipmap_build_levels(&q->m) == EL_SUCCESS;
}
static void pair_free(pair *q) {
  pbrt_MIPMap_free(&q->p);
  el_mipmap_free(&q->m);
}
/* The first level that pbrt builds from a level with a side of 1 while the other side is > 1, or
 * levels if there is none. Under Black the levels from there on differ. */
static int first_black_level(const pair *q) {
  int l;
  for (l = 1; l < q->m.levels; ++l) {
    int pw = q->m.level_width[l - 1], ph = q->m.level_height[l - 1];
    if ((pw == 1) != (ph == 1)) return l;
  }
  return q->m.levels;
}
static double level_mean(const float *d, int n) {
  double s = 0;
  int i;
  for (i = 0; i < 3 * n; ++i) s += d[i];
  return s / (3.0 * n);
}

/* Levels, Texel and triangle, bit for bit, on the levels the library claims equal. */
static void test_levels(const char *name, const float *img, int w, int h) {
  int wrap;
  for (wrap = 0; wrap < 3; ++wrap) {
    pair q;
    int l, same = 1, texel_same = 1, tri_same = 1, k, upto, nl;
    if (!pair_init(&q, img, w, h, wrap, 0)) {
      CHECKF(0, "%s %s: el_mipmap_init", name, wrap_name(wrap));
      continue;
    }
    nl = q.m.levels;
    upto = wrap == 1 ? first_black_level(&q) : nl;
    CHECKF(pbrt_MIPMap_Levels(&q.p) == nl && q.p.resolution.x == q.m.width && q.p.resolution.y == q.m.height,
           "%s %s: %d levels, level 0 %dx%d in both", name, wrap_name(wrap), nl, q.m.width, q.m.height);
    for (l = 0; l < upto && l < pbrt_MIPMap_Levels(&q.p); ++l) {
      int lw = q.m.level_width[l], lh = q.m.level_height[l];
      pbrt_RGBSpectrum *lin = (pbrt_RGBSpectrum *)malloc(sizeof(pbrt_RGBSpectrum) * (size_t)lw * (size_t)lh);
      pbrt_BlockedArray_GetLinearArray(q.p.pyramid[l], lin);
      if (pbrt_BlockedArray_uSize(q.p.pyramid[l]) != lw || pbrt_BlockedArray_vSize(q.p.pyramid[l]) != lh ||
          !same_bits(&lin[0].c[0], el_mipmap_level_data(&q.m, l), 3 * lw * lh))
        same = 0;
      free(lin);
      for (k = 0; k < 200; ++k) { /* Texel with any coordinates, several times around the level */
        int s = (int)(xorshift32_f(&g_rng) * 5 * lw) - 2 * lw, t = (int)(xorshift32_f(&g_rng) * 5 * lh) - 2 * lh;
        float o[3];
        pbrt_RGBSpectrum r = pbrt_MIPMap_Texel(&q.p, l, s, t);
        el_mipmap_texel(&q.m, l, s, t, o);
        if (!same_bits(r.c, o, 3)) texel_same = 0;
      }
      for (k = 0; k < 200; ++k) { /* triangle() around and across the borders */
        float s = -0.5f + 2 * xorshift32_f(&g_rng), t = -0.5f + 2 * xorshift32_f(&g_rng), o[3];
        pbrt_RGBSpectrum r = pbrt_MIPMap_triangle(&q.p, l, pbrt_Point2f_make(s, t));
        el_mipmap_bilerp(&q.m, l, s, t, o);
        if (!same_bits(r.c, o, 3)) tri_same = 0;
      }
    }
    CHECKF(same, "%s %s: levels 0..%d bit for bit", name, wrap_name(wrap), upto - 1);
    CHECKF(texel_same, "%s %s: Texel() bit for bit (any int coordinates)", name, wrap_name(wrap));
    CHECKF(tri_same, "%s %s: triangle() = el_mipmap_bilerp bit for bit on every level", name, wrap_name(wrap));
    if (upto < nl) {
      /* Black: from level `upto` on, pbrt's box filter adds two black texels per output texel */
      double m0 = level_mean(el_mipmap_level_data(&q.m, 0), q.m.width * q.m.height), worst_port = 0, worst_lib = 0;
      for (l = upto; l < nl; ++l) {
        int n = q.m.level_width[l] * q.m.level_height[l];
        pbrt_RGBSpectrum *lin = (pbrt_RGBSpectrum *)malloc(sizeof(pbrt_RGBSpectrum) * (size_t)n);
        double expect = m0 / (double)(1 << (l - upto + 1)), mp, ml;
        pbrt_BlockedArray_GetLinearArray(q.p.pyramid[l], lin);
        mp = level_mean(&lin[0].c[0], n);
        ml = level_mean(el_mipmap_level_data(&q.m, l), n);
        if (fabs(mp - expect) / expect > worst_port) worst_port = fabs(mp - expect) / expect;
        if (fabs(ml - m0) / m0 > worst_lib) worst_lib = fabs(ml - m0) / m0;
        free(lin);
      }
      CHECKF(worst_port < 1e-5, "%s Black: the port's levels %d..%d hold 1/2, 1/4, ... of the mean (within 1e-05 relative; worst %.1g)", name,
             upto, nl - 1, worst_port);
      CHECKF(worst_lib < 1e-5, "%s Black: the library's levels %d..%d keep the mean (within 1e-05 relative; worst %.1g)", name, upto, nl - 1,
             worst_lib);
    }
    pair_free(&q);
  }
}

/* Lookup(st, width) and Lookup(st, dst0, dst1): bit for bit where both read one level (or the top), within
 * BOUND elsewhere. */
static void test_lookups(const char *name, const float *img, int w, int h) {
  int wrap;
  for (wrap = 0; wrap < 3; ++wrap) {
    pair q, qt;
    int k, bits_small = 1, bits_top = 1, bits_ewa0 = 1, nl, differ;
    float d_tri = 0, d_ewa = 0, d_dtri = 0, d_book = 0, scale = max_texel(img, w * h);
    if (!pair_init(&q, img, w, h, wrap, 0) || !pair_init(&qt, img, w, h, wrap, 1)) {
      CHECKF(0, "%s %s: el_mipmap_init", name, wrap_name(wrap));
      continue;
    }
    nl = q.m.levels;
    differ = wrap == 1 && first_black_level(&q) < nl; /* Black, non-square: upper levels differ (test_levels) */
    for (k = 0; k < 3000; ++k) {
      float s = -0.2f + 1.4f * xorshift32_f(&g_rng), t = -0.2f + 1.4f * xorshift32_f(&g_rng), o[3], e;
      float texel0 = 1.0f / (float)(1 << (nl - 1)); /* a width of one texel of level 0 */
      float width = powf(10.0f, -3.5f + 3.5f * xorshift32_f(&g_rng)); /* 3e-4 .. 1 */
      float len = powf(10.0f, -3.5f + 3.0f * xorshift32_f(&g_rng)), ratio = 1 + 11 * xorshift32_f(&g_rng), ang = 6.2831853f * xorshift32_f(&g_rng);
      float d0s = len * cosf(ang), d0t = len * sinf(ang), d1s = -len / ratio * sinf(ang), d1t = len / ratio * cosf(ang);
      pbrt_Point2f st = pbrt_Point2f_make(s, t);
      pbrt_Vector2f dst0 = pbrt_Vector2f_make(d0s, d0t), dst1 = pbrt_Vector2f_make(d1s, d1t);
      pbrt_RGBSpectrum r;
      { /* below one texel: level 0 only */
        float wd = 0.9f * texel0 * xorshift32_f(&g_rng);
        r = pbrt_MIPMap_Lookup(&q.p, st, wd);
        el_mipmap_lookup(&q.m, s, t, wd, o);
        if (!same_bits(r.c, o, 3)) bits_small = 0;
      }
      if (differ) continue;
      { /* at or above 1: the 1x1 level */
        float wd = 1.0f + 3 * xorshift32_f(&g_rng);
        r = pbrt_MIPMap_Lookup(&q.p, st, wd);
        el_mipmap_lookup(&q.m, s, t, wd, o);
        if (!same_bits(r.c, o, 3)) bits_top = 0;
      }
      r = pbrt_MIPMap_Lookup(&q.p, st, width);
      el_mipmap_lookup(&q.m, s, t, width, o);
      e = diff3(o, r.c, scale);
      if (e > d_tri) d_tri = e;
      r = pbrt_MIPMap_Lookup_dst(&q.p, st, dst0, dst1);
      el_mipmap_lookup_differentials(&q.m, s, t, d0s, d0t, d1s, d1t, o);
      e = diff3(o, r.c, scale);
      if (e > d_ewa) d_ewa = e;
      if (pbrt_max(len / ratio, len / 8) < 0.9f * texel0 && !same_bits(r.c, o, 3)) /* minor axis after the clamp */
        bits_ewa0 = 0;
      r = pbrt_MIPMap_Lookup_dst(&qt.p, st, dst0, dst1);
      el_mipmap_lookup_differentials(&qt.m, s, t, d0s, d0t, d1s, d1t, o);
      e = diff3(o, r.c, scale);
      if (e > d_dtri) d_dtri = e;
      { /* pbrt-v3 before aaa552a: Lookup(st, 2 * width) */
        float wd = pbrt_max(pbrt_max(fabsf(d0s), fabsf(d0t)), pbrt_max(fabsf(d1s), fabsf(d1t)));
        r = pbrt_MIPMap_Lookup(&qt.p, st, 2 * wd);
        e = diff3(o, r.c, scale);
        if (e > d_book) d_book = e;
      }
    }
    CHECKF(bits_small, "%s %s: Lookup(st, width < 1 texel) bit for bit", name, wrap_name(wrap));
    if (!differ) {
      CHECKF(bits_top, "%s %s: Lookup(st, width >= 1) bit for bit", name, wrap_name(wrap));
      CHECKF(d_tri < BOUND, "%s %s: Lookup(st, width) within %.0e of the largest texel (max %.2g; the level's log2)",
             name, wrap_name(wrap), BOUND, d_tri);
      CHECKF(d_ewa < BOUND, "%s %s: EWA Lookup(st, dst0, dst1) within %.0e (max %.2g)", name, wrap_name(wrap), BOUND,
             d_ewa);
      CHECKF(bits_ewa0, "%s %s: EWA with a minor axis below one texel bit for bit", name, wrap_name(wrap));
      CHECKF(d_dtri < BOUND, "%s %s: doTrilinear Lookup(st, dst0, dst1) within %.0e (max %.2g)", name, wrap_name(wrap),
             BOUND, d_dtri);
      if (nl > 2)
        CHECKF(d_book > 1e-2f, "%s %s: ... which is not pbrt's older Lookup(st, 2 max |d|) (differs by up to %.2g)", name,
               wrap_name(wrap), d_book);
    }
    pair_free(&q);
    pair_free(&qt);
  }
}

/* The seed's test (chapter 2): the 400x235 image drawn through Lookup(st, width) at width 0.15, and at
 * width 0 (the course's choice for the first picture: the seed's text does not give its width). */
static void test_seed(const float *img) {
  pair q;
  int x, y, bits0 = 1;
  float d15 = 0, scale = max_texel(img, 400 * 235);
  if (!pair_init(&q, img, 400, 235, 0, 0)) {
    CHECKF(0, "seed test: el_mipmap_init");
    return;
  }
  for (y = 0; y < 235; ++y)
    for (x = 0; x < 400; ++x) {
      float s = (x + 0.5f) / 400, t = (y + 0.5f) / 235, o[3], e;
      pbrt_RGBSpectrum r = pbrt_MIPMap_Lookup(&q.p, pbrt_Point2f_make(s, t), 0.f);
      el_mipmap_lookup(&q.m, s, t, 0.f, o);
      if (!same_bits(r.c, o, 3)) bits0 = 0;
      r = pbrt_MIPMap_Lookup(&q.p, pbrt_Point2f_make(s, t), 0.15f);
      el_mipmap_lookup(&q.m, s, t, 0.15f, o);
      e = diff3(o, r.c, scale);
      if (e > d15) d15 = e;
    }
  CHECKF(bits0, "seed test, 400x235, width 0: every pixel bit for bit");
  CHECKF(d15 < BOUND, "seed test, 400x235, width 0.15: within %.0e of the largest texel (max %.2g)", BOUND, d15);
  pair_free(&q);
}

int main(void) {
  static float test_img[400 * 235 * 3];
  static const int sizes[][2] = {{64, 32}, {13, 7}, {32, 32}, {64, 16}, {1, 1}};
  int i;
  el_test_image(test_img, 400, 235);
  test_levels("400x235", test_img, 400, 235);
  test_lookups("400x235", test_img, 400, 235);
  for (i = 0; i < (int)(sizeof sizes / sizeof sizes[0]); ++i) {
    float *img = random_image(sizes[i][0], sizes[i][1]);
    char name[32];
    snprintf(name, sizeof name, "%dx%d", sizes[i][0], sizes[i][1]);
    test_levels(name, img, sizes[i][0], sizes[i][1]);
    test_lookups(name, img, sizes[i][0], sizes[i][1]);
    free(img);
  }
  test_seed(test_img);
  printf("test_tutorial_mipmap: %d passed, %d failed\n", g_pass, g_fail);
  return g_fail != 0;
}
