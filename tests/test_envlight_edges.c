/* test_envlight_edges.c: the edge cases of issue 24 (real HDRIs and an independent test campaign),
 * through envlight.h's public API only, each against what the header promises:
 *
 *   1. lossy maps: EL_ENVLIGHT_BAD_TEXELS_CLAMP_NEGATIVE turns finite negative texels into 0 and keeps
 *      NaN / infinite texels as errors naming the texel; negative_texels, nonfinite_texels,
 *      most_negative and most_negative_index report what was replaced (also under ZERO, and for the
 *      constant light); Blender's DWAB city map (data/envmaps/dwab/city.exr) loads with the counts the
 *      test finds itself, and the image reader's own counts (it keeps every value) agree;
 *   2. "the result depends only on the direction": under a general rotation (and the identity),
 *      pdf_li_cos(n, s wi), pdf_li_cos(s n, wi), pdf_li in importance BILINEAR and sample_li_cos(s n, u)
 *      for s = 2^-146 .. 2^127 (every power of two: exact scalings, denormals and near FLT_MAX) equal the
 *      unscaled results bit for bit; FLT_MAX (1, 1, 1) gives the result of (1, 1, 1);
 *   3. the constant light's pdf_li_cos of an unusable direction is 0 whatever the normal;
 *   4. no sample with pdf 0 where the density has mass: sample_li_cos (plain and compensated, many
 *      normals), sample_li in importance BILINEAR (compensated) and sample_li under a general rotation
 *      with a lit pole row, with adversarial u (0, 2^-24, 1/2, and 1 - k 2^-24 for k = 1..8 on either
 *      axis, against a sweep of the other axis);
 *   5. sample_li's radiance is le(wi) bit for bit under a general rotation (where its pdf is pdf_li(wi)),
 *      and within 2^-12 relative of le(wi) for signed permutations (its own (u, v); the atan of le's
 *      lookup differs by rounding);
 *   6. what the header says about directions below the horizon of sample_li_cos: a sun just below the
 *      horizon sends nearly every sample there, and the documented fractions on city.
 */
#define _POSIX_C_SOURCE 200809L
#define EL_IMPLEMENTATION
#include "envlight.h"
#include "image_io.h"

#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifndef EL_TEST_DATA_DIR
#define EL_TEST_DATA_DIR "data"
#endif

#include "test_common.h" /* check (a PASS / FAIL line, counted in g_pass / g_fail), rotation37 */

#include "test_rng.h" /* rng_f: PCG32, 24-bit floats in [0, 1) */
static rng g_rng = {0x853c49e6748fea9bULL}; /* one stream for the whole program */


static int load(const char *name, el_image *img) {
  char path[512], err[256];
  snprintf(path, sizeof path, "%s/envmaps/%s", EL_TEST_DATA_DIR, name);
  if (el_image_load(path, img, err, sizeof err) != 0) { printf("cannot load %s: %s\n", path, err); return -1; }
  return 0;
}

static int init(el_envlight *l, const float *px, int w, int h, int general, int importance, int compensated) {
  el_envlight_options o;
  memset(&o, 0, sizeof o);
  if (general) rotation37(o.light_to_world);
  o.importance = importance;
  o.compensated = compensated;
  return el_envlight_init(l, px, w, h, 3, &o) == EL_SUCCESS;
}

/* ---- 1. lossy maps -------------------------------------------------------------------------------- */
/* le at the centre of texel i of a w x h map (identity matrix) is its value in channel c (within 1e-4) */
static int texel_is(const el_envlight *l, int w, int h, int i, float value, int c) {
  float d[3], rgb[3];
  el_envlight_uv_to_dir(((float)(i % w) + 0.5f) / (float)w, ((float)(i / w) + 0.5f) / (float)h, d);
  el_envlight_le(l, d, rgb);
  return fabsf(rgb[c] - value) < 1e-4f;
}

static void test_clamp_negative(void) {
#ifdef EL_ENVLIGHT_BAD_TEXELS_CLAMP_NEGATIVE
  float px[4 * 2 * 3];
  el_envlight l;
  el_envlight_options o;
  el_result r;
  int k;
  for (k = 0; k < 24; ++k) px[k] = 1.0f;
  px[3 * 5 + 1] = -0.004f; /* texel 5 */
  px[3 * 6 + 0] = -0.001f; px[3 * 6 + 2] = -0.002f; /* texel 6, two channels */
  memset(&o, 0, sizeof o);
  r = el_envlight_init(&l, px, 4, 2, 3, &o);
  check(r == EL_ERROR_NEGATIVE && l.bad_index == 5, "default: a negative texel is an error naming it (%d)", l.bad_index);
  o.bad_texels = EL_ENVLIGHT_BAD_TEXELS_CLAMP_NEGATIVE;
  o.scale[0] = o.scale[1] = o.scale[2] = 2.0f;
  r = el_envlight_init(&l, px, 4, 2, 3, &o);
  check(r == EL_SUCCESS && l.negative_texels == 2 && l.nonfinite_texels == 0 && l.most_negative == -0.004f &&
            l.most_negative_index == 5 && texel_is(&l, 4, 2, 5, 0.0f, 1) && texel_is(&l, 4, 2, 6, 0.0f, 0) &&
            texel_is(&l, 4, 2, 6, 0.0f, 2) && texel_is(&l, 4, 2, 6, 2.0f, 1),
        "CLAMP_NEGATIVE: 2 texels (3 channels) become 0, the most negative -0.004 (before the scale) at texel 5 (%zu, %g, %d)",
        l.negative_texels, (double)l.most_negative, l.most_negative_index);
  el_envlight_free(&l);
  px[3 * 2 + 1] = NAN;
  r = el_envlight_init(&l, px, 4, 2, 3, &o);
  check(r == EL_ERROR_NAN && l.bad_index == 2, "CLAMP_NEGATIVE: a NaN texel stays an error naming it (%d)", l.bad_index);
  px[3 * 2 + 1] = INFINITY;
  r = el_envlight_init(&l, px, 4, 2, 3, &o);
  check(r == EL_ERROR_INFINITE && l.bad_index == 2, "CLAMP_NEGATIVE: an infinite texel stays an error naming it (%d)", l.bad_index);
  o.bad_texels = EL_ENVLIGHT_BAD_TEXELS_ZERO;
  r = el_envlight_init(&l, px, 4, 2, 3, &o);
  check(r == EL_SUCCESS && l.negative_texels == 2 && l.nonfinite_texels == 1 && l.most_negative_index == 5,
        "ZERO: reports 2 negative and 1 infinite texel (%zu, %zu)", l.negative_texels, l.nonfinite_texels);
  el_envlight_free(&l);
  for (k = 0; k < 24; ++k) px[k] = 1.0f;
  r = el_envlight_init(&l, px, 4, 2, 3, &o);
  check(r == EL_SUCCESS && l.negative_texels == 0 && l.nonfinite_texels == 0 && l.most_negative == 0.0f && l.most_negative_index == -1,
        "a clean map reports nothing (most_negative_index %d)", l.most_negative_index);
  el_envlight_free(&l);
  o.bad_texels = 3;
  check(el_envlight_init(&l, px, 4, 2, 3, &o) == EL_ERROR_INVALID_ARGUMENT, "bad_texels 3 is an invalid argument");
  {
    float c[3] = {1.0f, -0.5f, 2.0f};
    o.bad_texels = EL_ENVLIGHT_BAD_TEXELS_CLAMP_NEGATIVE;
    r = el_envlight_init_constant(&l, c, &o);
    check(r == EL_SUCCESS && l.constant[1] == 0.0f && l.negative_texels == 1 && l.most_negative == -0.5f && l.most_negative_index == 0,
          "the constant light: a negative component clamped and reported");
    el_envlight_free(&l);
  }
  {
    el_image im;
    if (load("dwab/city.exr", &im) == 0) {
      size_t i, n = (size_t)im.width * (size_t)im.height, count = 0;
      float most = 0.0f;
      int at = -1, c;
      for (i = 0; i < n; ++i) {
        int any = 0;
        for (c = 0; c < 3; ++c) {
          float v = im.pixels[i * (size_t)im.channels + (size_t)c];
          if (v < 0.0f) { any = 1; if (v < most) { most = v; at = (int)i; } }
        }
        count += (size_t)any;
      }
      {
        size_t vals = 0;
        for (i = 0; i < n * (size_t)im.channels; ++i) vals += im.pixels[i] < 0.0f;
        check(im.negative_values == vals && im.nonfinite_values == 0 && im.most_negative == most,
              "the image reader keeps the file's values and says so: %zu negative values (the test: %zu), the most negative %g",
              im.negative_values, vals, (double)im.most_negative);
      }
      memset(&o, 0, sizeof o);
      r = el_envlight_init(&l, im.pixels, im.width, im.height, im.channels, &o);
      check(r == EL_ERROR_NEGATIVE, "Blender's DWAB city map is refused by default (%s)", el_result_string(r));
      o.bad_texels = EL_ENVLIGHT_BAD_TEXELS_CLAMP_NEGATIVE;
      r = el_envlight_init(&l, im.pixels, im.width, im.height, im.channels, &o);
      check(r == EL_SUCCESS && count > 0 && l.negative_texels == count && l.most_negative == most && l.most_negative_index == at,
            "... and loads with CLAMP_NEGATIVE: %zu negative texels (the test counts %zu), the most negative %g at %d (%g at %d)",
            l.negative_texels, count, (double)l.most_negative, l.most_negative_index, (double)most, at);
      el_envlight_free(&l);
      el_image_free(&im);
    } else check(0, "load data/envmaps/dwab/city.exr");
  }
#else
  check(0, "EL_ENVLIGHT_BAD_TEXELS_CLAMP_NEGATIVE exists (a policy for lossy maps)");
#endif
}

/* ---- 2. only the direction matters -------------------------------------------------------------- */
static void test_scaled_vectors(const el_image *city) {
  int gi, bad_pdf = 0, bad_n = 0, bad_bil = 0, bad_samp = 0, n_cases = 0, bad_max = 0;
  for (gi = 0; gi < 2; ++gi) {
    el_envlight l, lb;
    int k, c, j;
    static const float dirs[4][3] = {{1.0f, -0.75f, 0.5f}, {0.25f, 1.0f, -0.5f}, {-0.5f, 0.125f, 1.0f}, {1.0f, 1.0f, 1.0f}};
    if (!init(&l, city->pixels, city->width, city->height, gi, 0, 0) ||
        !init(&lb, city->pixels, city->width, city->height, gi, EL_ENVLIGHT_IMPORTANCE_BILINEAR, 0)) {
      check(0, "init city");
      return;
    }
    for (j = 0; j < 4; ++j) {
      const float *n0 = dirs[j], *w0 = dirs[(j + 1) % 4];
      float p0 = el_envlight_pdf_li_cos(&l, n0, w0), b0 = el_envlight_pdf_li(&lb, w0), u[2] = {0.3f, 0.6f}, wi0[3], pd0, rgb0[3];
      el_envlight_sample_li_cos(&l, n0, u, wi0, rgb0, &pd0);
      for (k = -146; k <= 127; ++k) {
        float ws[3], ns[3], wi[3], pd, rgb[3];
        for (c = 0; c < 3; ++c) { ws[c] = ldexpf(w0[c], k); ns[c] = ldexpf(n0[c], k); }
        ++n_cases;
        if (el_envlight_pdf_li_cos(&l, n0, ws) != p0) ++bad_pdf;
        if (el_envlight_pdf_li_cos(&l, ns, w0) != p0) ++bad_n;
        if (el_envlight_pdf_li(&lb, ws) != b0) ++bad_bil;
        el_envlight_sample_li_cos(&l, ns, u, wi, rgb, &pd);
        if (pd != pd0 || wi[0] != wi0[0] || wi[1] != wi0[1] || wi[2] != wi0[2] || rgb[1] != rgb0[1]) ++bad_samp;
      }
    }
    { /* the cases: FLT_MAX (1, 1, 1) as the direction and as the normal */
      float one[3] = {1.0f, 1.0f, 1.0f}, big[3] = {FLT_MAX, FLT_MAX, FLT_MAX}, n0[3] = {0.6f, -0.8f, 0.0f};
      float p1 = el_envlight_pdf_li_cos(&l, n0, one);
      if (!(p1 > 0.0f) || el_envlight_pdf_li_cos(&l, n0, big) != p1) ++bad_max;
      if (el_envlight_pdf_li_cos(&l, big, one) != el_envlight_pdf_li_cos(&l, one, one)) ++bad_max;
      if (el_envlight_pdf_li(&lb, big) != el_envlight_pdf_li(&lb, one)) ++bad_max;
    }
    el_envlight_free(&l);
    el_envlight_free(&lb);
  }
  check(bad_pdf == 0, "pdf_li_cos(n, 2^k wi), k = -146..127, identity and a general rotation: equal to k = 0 (%d of %d differ)", bad_pdf, n_cases);
  check(bad_n == 0, "pdf_li_cos(2^k n, wi): equal to k = 0 (%d of %d differ)", bad_n, n_cases);
  check(bad_bil == 0, "pdf_li(2^k wi) in importance BILINEAR: equal to k = 0 (%d of %d differ)", bad_bil, n_cases);
  check(bad_samp == 0, "sample_li_cos(2^k n, u): the same wi, rgb and pdf as k = 0 (%d of %d differ)", bad_samp, n_cases);
  check(bad_max == 0, "FLT_MAX (1, 1, 1) as direction or normal gives the result of (1, 1, 1) (%d wrong)", bad_max);
}

/* ---- 3. the constant light's unusable direction ------------------------------------------------- */
static void test_constant_unusable(void) {
  el_envlight l;
  float c[3] = {1.0f, 1.0f, 1.0f}, zero[3] = {0.0f, 0.0f, 0.0f}, nanv[3] = {NAN, 0.0f, 1.0f}, inf[3] = {INFINITY, 0.0f, 0.0f}, up[3] = {0.0f, 0.0f, 1.0f};
  float p1, p2, p3, p4, p5;
  el_envlight_init_constant(&l, c, NULL);
  p1 = el_envlight_pdf_li_cos(&l, zero, zero);
  p2 = el_envlight_pdf_li_cos(&l, nanv, nanv);
  p3 = el_envlight_pdf_li_cos(&l, zero, inf);
  p4 = el_envlight_pdf_li_cos(&l, up, zero);
  p5 = el_envlight_pdf_li_cos(&l, zero, up);
  check(p1 == 0.0f && p2 == 0.0f && p3 == 0.0f && p4 == 0.0f, "constant light: pdf_li_cos of a zero / NaN / infinite direction is 0 whatever the normal (%g %g %g %g)",
        (double)p1, (double)p2, (double)p3, (double)p4);
  check(fabsf(p5 - 0.0795774715f) < 1e-7f, "constant light: an unusable normal with a usable direction gives 1 / (4 pi) (%g)", (double)p5);
  el_envlight_free(&l);
}

/* ---- 4. adversarial u ----------------------------------------------------------------------------- */
static void adversarial_u(float *a, int *n) { /* 0, 2^-24, 1/2, 1 - k 2^-24 (k = 1..8) */
  int k;
  *n = 0;
  a[(*n)++] = 0.0f;
  a[(*n)++] = 5.96046448e-8f;
  a[(*n)++] = 0.5f;
  for (k = 1; k <= 8; ++k) a[(*n)++] = 1.0f - (float)k * 5.96046448e-8f;
}

/* zero pdfs among samples of a light that emits (for a normal that sees some of it: one positive pdf
 * in 64 random samples shows that) */
static int zero_pdfs(const el_envlight *l, const float *n, int sweep, int *tried) {
  float a[16], u[2], wi[3], pdf;
  int na, i, j, axis, zeros = 0, seen = 0;
  for (i = 0; i < 64; ++i) {
    u[0] = rng_f(&g_rng); u[1] = rng_f(&g_rng);
    if (n) el_envlight_sample_li_cos(l, n, u, wi, NULL, &pdf);
    else el_envlight_sample_li(l, u, wi, NULL, &pdf);
    if (pdf > 0.0f) seen = 1;
  }
  if (!seen) return 0;
  adversarial_u(a, &na);
  for (axis = 0; axis < 2; ++axis)
    for (i = 0; i < na; ++i)
      for (j = 0; j < sweep; ++j) {
        u[axis] = a[i];
        u[1 - axis] = ((float)j + rng_f(&g_rng)) / (float)sweep;
        if (n) el_envlight_sample_li_cos(l, n, u, wi, NULL, &pdf);
        else el_envlight_sample_li(l, u, wi, NULL, &pdf);
        ++*tried;
        if (!(pdf > 0.0f)) ++zeros;
      }
  return zeros;
}

static void test_adversarial_u(const el_image *city) {
  int gi, comp, k, zeros_cos = 0, tried_cos = 0, zeros_bil = 0, tried_bil = 0, zeros_pole = 0, tried_pole = 0;
  /* sample_li_cos on city, plain and compensated, identity and a rotation, 96 normals */
  for (gi = 0; gi < 2; ++gi)
    for (comp = 0; comp < 2; ++comp) {
      el_envlight l;
      if (!init(&l, city->pixels, city->width, city->height, gi, 0, comp)) { check(0, "init"); return; }
      for (k = 0; k < 96; ++k) {
        float z = 2.0f * rng_f(&g_rng) - 1.0f, ph = 6.2831853f * rng_f(&g_rng), r = sqrtf(1.0f - z * z), n[3];
        n[0] = r * cosf(ph); n[1] = r * sinf(ph); n[2] = z;
        zeros_cos += zero_pdfs(&l, n, 256, &tried_cos);
      }
      el_envlight_free(&l);
    }
  check(zeros_cos == 0, "sample_li_cos, adversarial u (u within 8 ulps of 1 on either axis), 96 normals, plain / compensated, "
        "identity / rotation: %d of %d samples have pdf 0", zeros_cos, tried_cos);
  /* sample_li in importance BILINEAR, compensated (and plain) */
  for (gi = 0; gi < 2; ++gi)
    for (comp = 0; comp < 2; ++comp) {
      el_envlight l;
      if (!init(&l, city->pixels, city->width, city->height, gi, EL_ENVLIGHT_IMPORTANCE_BILINEAR, comp)) { check(0, "init"); return; }
      zeros_bil += zero_pdfs(&l, NULL, 65536, &tried_bil);
      el_envlight_free(&l);
    }
  check(zeros_bil == 0, "sample_li in importance BILINEAR, adversarial u, plain / compensated, identity / rotation: %d of %d have pdf 0",
        zeros_bil, tried_bil);
  /* sample_li under a general rotation, a map whose only light is a few texels of its pole rows */
  {
    static const int sizes[3][2] = {{1024, 512}, {256, 128}, {64, 32}};
    int si, imp;
    for (si = 0; si < 3; ++si)
      for (imp = 0; imp < 3; ++imp) {
        int w = sizes[si][0], h = sizes[si][1], x;
        float *px = (float *)calloc((size_t)w * (size_t)h * 3, sizeof(float));
        el_envlight l;
        for (x = 0; x < w; x += 7) { /* every 7th texel of both pole rows */
          px[3 * (size_t)x] = px[3 * (size_t)x + 1] = 1.0f;
          px[3 * ((size_t)(h - 1) * (size_t)w + (size_t)x) + 2] = 2.0f;
        }
        if (init(&l, px, w, h, 1, imp == 2 ? EL_ENVLIGHT_IMPORTANCE_BILINEAR : imp, 0)) {
          int j;
          float u[2], wi[3], pdf;
          zeros_pole += zero_pdfs(&l, NULL, 4096, &tried_pole);
          for (j = 0; j < 200000; ++j) { /* and random u */
            u[0] = rng_f(&g_rng); u[1] = rng_f(&g_rng);
            el_envlight_sample_li(&l, u, wi, NULL, &pdf);
            ++tried_pole;
            if (!(pdf > 0.0f)) ++zeros_pole;
          }
          el_envlight_free(&l);
        } else check(0, "init pole map");
        free(px);
      }
  }
  check(zeros_pole == 0, "sample_li under a general rotation, only pole-row texels lit (1024x512, 256x128, 64x32; cell average, "
        "pbrt-v3, bilinear): %d of %d samples have pdf 0", zeros_pole, tried_pole);
}

/* ---- 5. sample_li's radiance ---------------------------------------------------------------------- */
/* the spread (max - min) of channel c over the 4x4 texels around le's bilinear lookup at (u, v) */
static double local_range(const el_image *im, float u, float v, int c) {
  int w = im->width, h = im->height, x0 = (int)floorf(u * (float)w - 0.5f), y0 = (int)floorf(v * (float)h - 0.5f), dx, dy;
  float lo = FLT_MAX, hi = -FLT_MAX;
  for (dy = -1; dy <= 2; ++dy)
    for (dx = -1; dx <= 2; ++dx) {
      int x = ((x0 + dx) % w + w) % w, y = y0 + dy < 0 ? 0 : y0 + dy > h - 1 ? h - 1 : y0 + dy;
      float t = im->pixels[(size_t)im->channels * ((size_t)y * (size_t)w + (size_t)x) + (size_t)c]; /* scale 1 */
      if (t < lo) lo = t;
      if (t > hi) hi = t;
    }
  return (double)hi - (double)lo;
}

static void test_sample_radiance(const el_image *city) {
  int gi, imp, bad_rot = 0, n_rot = 0, n_perm = 0;
  double worst_perm = 0.0;
  for (gi = 0; gi < 2; ++gi)
    for (imp = 0; imp < 3; ++imp) {
      el_envlight l;
      int j;
      if (!init(&l, city->pixels, city->width, city->height, gi, imp == 2 ? EL_ENVLIGHT_IMPORTANCE_BILINEAR : imp, 0)) { check(0, "init"); return; }
      for (j = 0; j < 60000; ++j) {
        float u[2], wi[3], rgb[3], le[3], pdf;
        int c;
        u[0] = rng_f(&g_rng);
        u[1] = j % 3 == 0 ? rng_f(&g_rng) * 0.002f : j % 3 == 1 ? 1.0f - rng_f(&g_rng) * 0.002f : rng_f(&g_rng); /* near the poles too */
        el_envlight_sample_li(&l, u, wi, rgb, &pdf);
        if (!(pdf > 0.0f)) continue;
        el_envlight_le(&l, wi, le);
        if (gi) {
          ++n_rot;
          if (rgb[0] != le[0] || rgb[1] != le[1] || rgb[2] != le[2]) ++bad_rot;
        } else {
          float uu, vv;
          ++n_perm;
          el_envlight_dir_to_uv(wi, &uu, &vv); /* identity: light space = world */
          for (c = 0; c < 3; ++c) { /* the difference as a position error, in texels: |d rgb| / the local spread */
            double d = fabs((double)rgb[c] - (double)le[c]), r = local_range(city, uu, vv, c);
            d = d <= 1e-6 * fabs((double)le[c]) ? 0.0 : d / (r > 0.0 ? r : 1e-30);
            if (d > worst_perm) worst_perm = d;
          }
        }
      }
      el_envlight_free(&l);
    }
  check(bad_rot == 0, "general rotation: sample_li's radiance is le(wi) bit for bit (%d of %d differ; cell average, pbrt-v3, bilinear)",
        bad_rot, n_rot);
  check(worst_perm < 1e-3, "identity: sample_li's radiance is le at its own (u, v): it differs from le(wi) as a shift of at most %.2g "
        "texel would (< 1e-3; %d samples)", worst_perm, n_perm);
}

/* ---- 6. below the horizon ------------------------------------------------------------------------- */
static double below_fraction(const el_envlight *l, const float n[3], int count) {
  int j, below = 0, valid = 0;
  for (j = 0; j < count; ++j) {
    float u[2], wi[3], pdf;
    u[0] = ((float)(j % 256) + rng_f(&g_rng)) / 256.0f;
    u[1] = ((float)(j / 256) + rng_f(&g_rng)) / (float)(count / 256);
    el_envlight_sample_li_cos(l, n, u, wi, NULL, &pdf);
    if (!(pdf > 0.0f)) continue;
    ++valid;
    if (n[0] * wi[0] + n[1] * wi[1] + n[2] * wi[2] <= 0.0f) ++below;
  }
  return valid ? (double)below / valid : -1.0;
}

static void test_below_horizon(void) {
  /* a 512x256 map: a dim sky (0.01) and a 2x2-texel sun of 1e4 one texel below the horizon of n = +z */
  int w = 512, h = 256, x, y;
  float *px = (float *)malloc((size_t)w * (size_t)h * 3 * sizeof(float)), up[3] = {0.0f, 0.0f, 1.0f};
  el_envlight l;
  double f;
  for (y = 0; y < h; ++y)
    for (x = 0; x < w; ++x) {
      float v = (y == h / 2 || y == h / 2 + 1) && (x == 100 || x == 101) ? 1e4f : 0.01f; /* as bench_hdri's R = 1 */
      px[3 * ((size_t)y * (size_t)w + (size_t)x)] = px[3 * ((size_t)y * (size_t)w + (size_t)x) + 1] = px[3 * ((size_t)y * (size_t)w + (size_t)x) + 2] = v;
    }
  init(&l, px, w, h, 0, 0, 0);
  f = below_fraction(&l, up, 65536);
  check(f > 0.8, "a sun one texel row below the horizon: %.1f%% of sample_li_cos's samples fall below it (> 80%%; the header: 89-95%%)", 100.0 * f);
  el_envlight_free(&l);
  free(px);
}

int main(void) {
  el_image city;
  if (load("city.hdr", &city) != 0) { check(0, "load city.hdr"); return 1; }
  test_clamp_negative();
  test_scaled_vectors(&city);
  test_constant_unusable();
  test_adversarial_u(&city);
  test_sample_radiance(&city);
  test_below_horizon();
  el_image_free(&city);
  printf("test_envlight_edges: %d passed, %d failed\n", g_pass, g_fail);
  return g_fail ? 1 : 0;
}
