/* test_tutorial_film.c: the course's plain port of pbrt-v3's film path (examples/pbrtv3/film.h,
 * chapter 4) against film.h, on the same samples.
 *
 * Where the two agree, and within what (each bound derived here, none taken from either's output):
 *  1. The filtered pixels. Both add L * w * filter into per-pixel sums over tiles and divide by the
 *     sum of the filter weights; pbrt looks the weight up in its 16 x 16 table, as film.h does by
 *     default. Differences: pbrt sums in float (a pixel reached by K samples carries up to about
 *     2K float roundings), film.h in double; pbrt converts every tile's sums to XYZ and back (a
 *     float matrix product each way, which can amplify a rounding by kappa = || |M^-1| |M| ||, from
 *     pbrt's six-digit matrices, computed here). With xyz_round_trip = 1 film.h applies the same two
 *     matrices once at the end, so the pixels agree within (2K + 16) 2^-24 kappa of their value; with
 *     the default (no round trip) also within || M^-1 M - I || of it: pbrt's two matrices are inverse
 *     to six digits only. Sample positions are placed where the table cell cannot depend on float
 *     against double arithmetic (see below); the three filters with weights >= 0 are compared.
 *  2. Sums of very different sizes: one sample of 1e6, then a million of 1e-3 in the same pixel. A
 *     float sum of 1e6 moves in steps of 0.0625, so pbrt's stays at 1e6 (pixel 1e6 / (1e6 + 1));
 *     film.h's double sum gives (1e6 + 1000) / (1e6 + 1).
 *  3. Bytes. TO_BYTE (pbrt's float pow, round by + 0.5) and film.h's codes agree except where
 *     255 encode(x) + 0.5 lies within float rounding (here 2e-4) of an integer, and then by one code.
 *     +Inf gives 255 in both. A NaN reaches TO_BYTE's cast as a NaN (pbrt's Clamp passes it through),
 *     which is undefined behaviour: the test shows the NaN before the cast and does not cast it.
 *     film.h gives 0.
 *  4. Bad samples. pbrt's film adds whatever it is given: a NaN radiance makes the pixel's sums NaN,
 *     and so does +Inf, because XYZToRGB mixes positive and negative coefficients (Inf - Inf); then
 *     WriteImage's std::max(0, NaN) returns 0: the whole pixel goes black. pbrt's integrator sets
 *     such radiance to black before the film, which keeps its filter weight: the pixel darkens.
 *     film.h rejects and counts the sample; the pixel is the mean of the others.
 */
#define EL_FILM_IMPLEMENTATION
#include "film.h"
#include "../examples/pbrtv3/film.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define UNIT (1.0 / 16777216.0)

#define TUTORIAL_RNG_SEED 4242u
#include "tutorial_check.h" /* check, checkf, frand */
static unsigned irand(unsigned n) { return (lcg_next(&g_rng) >> 8) % n; }

/* pbrt's two matrices in double, and the two norms of the header comment */
static const double M[9] = {0.412453, 0.357580, 0.180423, 0.212671, 0.715160, 0.072169, 0.019334, 0.119193, 0.950227};
static const double Mi[9] = {3.240479, -1.537150, -0.498535, -0.969256, 1.875991, 0.041556, 0.055648, -0.204043, 1.057311};
static void norms(double *kappa, double *round_trip) {
  int i, j, k;
  *kappa = *round_trip = 0;
  for (i = 0; i < 3; ++i) {
    double sa = 0, sr = 0;
    for (j = 0; j < 3; ++j) {
      double a = 0, r = 0;
      for (k = 0; k < 3; ++k) {
        a += fabs(Mi[3 * i + k]) * fabs(M[3 * k + j]);
        r += Mi[3 * i + k] * M[3 * k + j];
      }
      sa += a;
      sr += fabs(r - (i == j));
    }
    *kappa = fmax(*kappa, sa);
    *round_trip = fmax(*round_trip, sr);
  }
}

enum { W = 32, H = 24, SPP = 16 };
static const char *pbrt_name[3] = {"box", "triangle", "gaussian"};

/* 1. the same samples through both films, tiled in four quadrants */
static void test_pixels(int type) {
  static float smp[W * H * SPP][6];
  static float rgb_p[W * H * 3], rgb_a[W * H * 3], rgb_b[W * H * 3];
  static int reach[W * H];
  pbrt_Filter filt = pbrt_MakeFilter(type, 0, 0);
  pbrt_Film pf;
  el_film fa, fb;
  el_film_options fo;
  double kappa, rt, worst_a = 0, worst_b = 0;
  int n = 0, q, i, ok_a = 1, ok_b = 1, ok_bounds = 1;
  char what[300];
  norms(&kappa, &rt);
  memset(&fo, 0, sizeof fo);
  fo.width = W;
  fo.height = H;
  fo.filter.type = (el_film_filter_type)type; /* pbrt's BoxFilter .. GaussianFilter, same order */
  fo.xyz_round_trip = 1;
  check(pbrt_Film_init(&pf, W, H, &filt, 1, INFINITY) == 0 && el_film_init(&fa, &fo) == EL_SUCCESS, "films build");
  fo.xyz_round_trip = 0;
  check(el_film_init(&fb, &fo) == EL_SUCCESS, "film without the XYZ round trip builds");
  /* Positions x + (2k + 1) / 128: the table cell is floor(|offset| 16 / radius) with offset =
   * integer + 1/2 - (2k + 1) / 128, i.e. (radius 2) 8 x integer + 4 - (2k + 1) / 16 or (radius 1/2)
   * 32 x integer + 16 - (2k + 1) / 4: never within 1/16 of an integer, so float and double agree. */
  for (q = 0; q < 4; ++q) {
    int b[4], y, x, s;
    pbrt_FilmTile pt;
    el_film_tile ta, tb;
    b[0] = (q & 1) * W / 2;
    b[1] = (q >> 1) * H / 2;
    b[2] = b[0] + W / 2;
    b[3] = b[1] + H / 2;
    memset(&ta, 0, sizeof ta);
    memset(&tb, 0, sizeof tb);
    pbrt_Film_GetFilmTile(&pf, b, &pt);
    el_film_tile_init(&fa, &ta, b[0], b[1], b[2], b[3]);
    el_film_tile_init(&fb, &tb, b[0], b[1], b[2], b[3]);
    if (ta.x0 != pt.pixelBounds[0] || ta.y0 != pt.pixelBounds[1] || ta.x1 != pt.pixelBounds[2] || ta.y1 != pt.pixelBounds[3])
      ok_bounds = 0;
    for (y = b[1]; y < b[3]; ++y)
      for (x = b[0]; x < b[2]; ++x)
        for (s = 0; s < SPP; ++s, ++n) {
          float *p = smp[n];
          int c;
          p[0] = (float)x + (float)(2 * irand(64) + 1) / 128.0f;
          p[1] = (float)y + (float)(2 * irand(64) + 1) / 128.0f;
          for (c = 0; c < 3; ++c) p[2 + c] = 4 * frand();
          p[5] = 0.5f + 0.5f * frand();
          pbrt_FilmTile_AddSample(&pt, p, p + 2, p[5]);
          el_film_tile_add_sample(&ta, p[0], p[1], p + 2, p[5]);
          el_film_tile_add_sample(&tb, p[0], p[1], p + 2, p[5]);
        }
    pbrt_Film_MergeFilmTile(&pf, &pt);
    el_film_merge_tile(&fa, &ta);
    el_film_merge_tile(&fb, &tb);
    pbrt_FilmTile_free(&pt);
    el_film_tile_free(&ta);
    el_film_tile_free(&tb);
  }
  /* K per pixel: the samples within the filter's radius of its centre (box, triangle, gaussian: the
   * table is 0 at the edge only for the triangle; count generously) */
  memset(reach, 0, sizeof reach);
  for (i = 0; i < n; ++i) {
    int x, y;
    for (y = 0; y < H; ++y)
      for (x = 0; x < W; ++x)
        if (fabsf(smp[i][0] - 0.5f - (float)x) <= filt.radius[0] && fabsf(smp[i][1] - 0.5f - (float)y) <= filt.radius[1])
          reach[y * W + x]++;
  }
  pbrt_Film_WriteImage(&pf, 0, rgb_p);
  el_film_get_rgb(&fa, 0, rgb_a);
  el_film_get_rgb(&fb, 0, rgb_b);
  for (i = 0; i < W * H; ++i) {
    double big = fmax(rgb_p[3 * i], fmax(rgb_p[3 * i + 1], rgb_p[3 * i + 2]));
    double ba = (2.0 * reach[i] + 16) * UNIT * kappa * big + 1e-30, bb = ba + rt * big;
    int c;
    for (c = 0; c < 3; ++c) {
      double da = fabs((double)rgb_a[3 * i + c] - rgb_p[3 * i + c]), db = fabs((double)rgb_b[3 * i + c] - rgb_p[3 * i + c]);
      if (!(da <= ba)) ok_a = 0;
      if (!(db <= bb)) ok_b = 0;
      worst_a = fmax(worst_a, da / ba);
      worst_b = fmax(worst_b, db / bb);
    }
  }
  snprintf(what, sizeof what, "%s: the tiles' pixel bounds are pbrt's GetFilmTile's", pbrt_name[type]);
  check(ok_bounds, what);
  snprintf(what, sizeof what, "%s, xyz_round_trip = 1: every pixel within (2K + 16) 2^-24 kappa of pbrt's (kappa %.2f; worst %.2f of the bound)", pbrt_name[type], kappa, worst_a);
  check(ok_a, what);
  snprintf(what, sizeof what, "%s, the default: also within |M^-1 M - I| = %.2g of it (worst %.2f of the bound)", pbrt_name[type], rt, worst_b);
  check(ok_b, what);
  pbrt_Film_free(&pf);
  el_film_free(&fa);
  el_film_free(&fb);
}

/* 2. sums of very different sizes */
static void test_sums(void) {
  pbrt_Filter box = pbrt_MakeFilter(pbrt_BoxFilter, 0, 0);
  pbrt_Film pf;
  pbrt_FilmTile pt;
  el_film ef;
  el_film_options fo;
  int b[4] = {0, 0, 1, 1}, i;
  float p[2] = {0.5f, 0.5f}, big[3] = {1e6f, 1e6f, 1e6f}, small[3] = {1e-3f, 1e-3f, 1e-3f}, rp[3], re[3];
  memset(&fo, 0, sizeof fo);
  fo.width = fo.height = 1;
  pbrt_Film_init(&pf, 1, 1, &box, 1, INFINITY);
  pbrt_Film_GetFilmTile(&pf, b, &pt);
  el_film_init(&ef, &fo);
  pbrt_FilmTile_AddSample(&pt, p, big, 1);
  el_film_add_sample(&ef, 0.5f, 0.5f, big, 1);
  for (i = 0; i < 1000000; ++i) {
    pbrt_FilmTile_AddSample(&pt, p, small, 1);
    el_film_add_sample(&ef, 0.5f, 0.5f, small, 1);
  }
  pbrt_Film_MergeFilmTile(&pf, &pt);
  pbrt_Film_WriteImage(&pf, 0, rp);
  el_film_get_rgb(&ef, 0, re);
  checkf(fabs(rp[1] - 1e6 / (1e6 + 1)) < 2e-6 && fabs(re[1] - (1e6 + 1000) / (1e6 + 1)) < 2e-6,
         "1e6 then a million 1e-3: pbrt's float sums give %.7f (the small ones lost: 1e6 / (1e6 + 1)), film.h's %.7f ((1e6 + 1000) / (1e6 + 1))", rp[1], re[1]);
  pbrt_FilmTile_free(&pt);
  pbrt_Film_free(&pf);
  el_film_free(&ef);
}

/* 3. bytes */
static void test_bytes(void) {
  enum { N = 1100000 };
  static float v[N];
  static unsigned char lib8[N * 3];
  float nan = (float)NAN, inf = (float)INFINITY, c;
  int i, ok = 1, differ = 0, tie_ok = 1;
  for (i = 0; i < N; ++i) v[i] = (float)i * 1e-6f;
  /* film.h's exact codes: one call over an N x 1 "image" of grey pixels is 3 N values; use the first */
  {
    static float img[N * 3];
    for (i = 0; i < N; ++i) img[3 * i] = img[3 * i + 1] = img[3 * i + 2] = v[i];
    el_film_to_srgb8(img, N, 1, NULL, lib8);
  }
  for (i = 0; i < N; ++i) {
    int a = TO_BYTE(v[i]), b = el_film_srgb_to_byte(v[i]), e = lib8[3 * i];
    double x = 255.0 * (v[i] <= 0.0031308 ? 12.92 * v[i] : 1.055 * pow(v[i], 1 / 2.4) - 0.055) + 0.5;
    int near_tie = fabs(x - floor(x + 0.5)) < 2e-4;
    if (a != b || a != e) {
      ++differ;
      if (!near_tie || abs(a - b) > 1 || abs(a - e) > 1) tie_ok = 0;
    }
    if (x > 255.5 && a != 255) ok = 0;
  }
  checkf(tie_ok && ok, "bytes on [0, 1.1]: TO_BYTE and film.h differ on %.0f of %.0f values, each by one code at a rounding tie", differ, N);
  c = pbrt_Clampf(255.f * pbrt_GammaCorrect(nan) + 0.5f, 0.f, 255.f);
  check(c != c && el_film_srgb_to_byte(nan) == 0,
        "NaN: pbrt's Clamp hands TO_BYTE's cast a NaN (undefined behaviour, not executed here); film.h gives 0");
  check(TO_BYTE(inf) == 255 && el_film_srgb_to_byte(inf) == 255, "+Inf: 255 in both");
  check(TO_BYTE(-1.0f) == 0 && el_film_srgb_to_byte(-1.0f) == 0, "negative: 0 in both");
}

/* 4. bad samples in a pixel with three good ones (box filter: their mean is 2) */
static void test_bad_samples(void) {
  int bad, guard;
  for (bad = 0; bad < 2; ++bad)
    for (guard = 0; guard < 2; ++guard) {
      pbrt_Filter box = pbrt_MakeFilter(pbrt_BoxFilter, 0, 0);
      pbrt_Film pf;
      pbrt_FilmTile pt;
      el_film ef;
      el_film_options fo;
      int b[4] = {0, 0, 1, 1}, k;
      float p[2] = {0.5f, 0.5f}, L[3], rp[3], re[3];
      char what[300];
      memset(&fo, 0, sizeof fo);
      fo.width = fo.height = 1;
      pbrt_Film_init(&pf, 1, 1, &box, 1, INFINITY);
      pbrt_Film_GetFilmTile(&pf, b, &pt);
      el_film_init(&ef, &fo);
      for (k = 0; k < 4; ++k) {
        L[0] = L[1] = L[2] = k == 3 ? (bad ? (float)INFINITY : (float)NAN) : (float)(k + 1);
        el_film_add_sample(&ef, p[0], p[1], L, 1);
        /* pbrt's SamplerIntegrator::Render: "Not-a-number radiance value ... Setting to black." (and
         * the same for infinite luminance); the film itself checks nothing */
        if (guard && k == 3) L[0] = L[1] = L[2] = 0;
        pbrt_FilmTile_AddSample(&pt, p, L, 1);
      }
      pbrt_Film_MergeFilmTile(&pf, &pt);
      pbrt_Film_WriteImage(&pf, 0, rp);
      el_film_get_rgb(&ef, 0, re);
      if (guard)
        snprintf(what, sizeof what,
                 "a %s sample among 1, 2, 3, set to black by pbrt's integrator: pbrt's pixel %.6g (6 / 4: the weight stays), film.h's %.6g (rejected and counted)",
                 bad ? "+Inf" : "NaN", rp[1], re[1]);
      else
        snprintf(what, sizeof what,
                 "a %s sample among 1, 2, 3 given to the film: pbrt's pixel %.6g (%s std::max(0, NaN) = 0), film.h's %.6g",
                 bad ? "+Inf" : "NaN", rp[1], bad ? "Inf - Inf = NaN in XYZToRGB, then" : "NaN sums, then", re[1]);
      check((guard ? fabs(rp[1] - 1.5) < 1e-5 : rp[1] == 0.0f) && fabs(re[1] - 2) < 1e-6 &&
                (bad ? ef.stats.rejected_inf : ef.stats.rejected_nan) == 1,
            what);
      pbrt_FilmTile_free(&pt);
      pbrt_Film_free(&pf);
      el_film_free(&ef);
    }
}

int main(void) {
  int t;
  for (t = 0; t < 3; ++t) test_pixels(t);
  test_sums();
  test_bytes();
  test_bad_samples();
  printf("%d passed, %d failed\n", g_pass, g_fail);
  return g_fail ? 1 : 0;
}
