/* tests/labs/lab_02_lookups.c: lab 2 (tutorials/02-porting-the-mipmap.md): the resampling to powers of
 * two, Texel's wrap modes, triangle, the trilinear Lookup and (optional) EWA, in the file under test
 * (stu_*) against pbrt's (ref_*, examples/pbrtv3/mipmap.h built separately), plus facts derived by
 * hand (a constant image stays constant; texels inside a level are the image's; triangle at a texel
 * centre is that texel). */
#include "lab_check.h"
#include "lab_mipmap.h"

#include <stdlib.h>

enum { REPEAT, BLACK, CLAMP }; /* pbrt_ImageWrap's order */
static const char *wrap_name[3] = {"Repeat", "Black", "Clamp"};

static void test_image(int w, int h, unsigned seed, float *rgb) {
  int i;
  for (i = 0; i < 3 * w * h; ++i) {
    seed = seed * 1664525u + 1013904223u;
    rgb[i] = (float)(seed >> 8) / 16777216.f;
  }
}
static int same3(const float *a, const float *b, double tol) {
  return lab_close(a[0], b[0], tol) && lab_close(a[1], b[1], tol) && lab_close(a[2], b[2], tol);
}

static void part_resample(void) {
  static const int sizes[][2] = {{5, 3}, {3, 6}, {6, 4}};
  int k, wrap, repeat_ok;
  lab_part("part 1, TODO 1 and 2: resampling to powers of two (chapter 2, \"Step 2\")");
  for (k = 0; k < 3; ++k)
    for (wrap = 0, repeat_ok = 0; wrap < 3; ++wrap) {
      int w = sizes[k][0], h = sizes[k][1], w0, h0, w1, h1, i, neg = 0, zero = 1;
      float img[3 * 6 * 6], a[3 * 8 * 8], b[3 * 8 * 8];
      void *m0, *m1;
      test_image(w, h, (unsigned)(3 + k), img);
      m0 = ref_mip_new(w, h, img, wrap, 0, 8.f);
      m1 = stu_mip_new(w, h, img, wrap, 0, 8.f);
      ref_level_size(m0, 0, &w0, &h0);
      stu_level_size(m1, 0, &w1, &h1);
      if (lab_check(w0 == w1 && h0 == h1, "the %dx%d image: your level 0 is %dx%d, pbrt's %dx%d", w, h, w1, h1, w0, h0)) {
        ref_level_texels(m0, 0, a);
        stu_level_texels(m1, 0, b);
        for (i = 0; i < 3 * w0 * h0; ++i) {
          if (b[i] < 0) neg = 1;
          if (b[i] != 0) zero = 0;
        }
        for (i = 0; i < 3 * w0 * h0; ++i)
          if (!lab_close(a[i], b[i], 1e-4)) break;
        if (wrap == REPEAT) repeat_ok = i == 3 * w0 * h0;
        lab_check(i == 3 * w0 * h0, "the %dx%d image resampled to %dx%d (wrap %s): level 0 differs from pbrt's at texel (%d, %d): %.5f against %.5f: %s",
                  w, h, w0, h0, wrap_name[wrap], (i / 3) % w0, (i / 3) / w0, i < 3 * w0 * h0 ? b[i] : 0., i < 3 * w0 * h0 ? a[i] : 0.,
                  zero ? "level 0 is black: TODO 1 (the s pass) or TODO 2 (the t pass) not written yet?"
                  : neg ? "it has negative texels: clamp the t pass's result with pbrt_MIPMap_clamp (Lanczos rings below 0)"
                  : repeat_ok ? "under Repeat your level 0 agrees, under this wrap mode it does not: check how the taps outside the "
                                "image are wrapped (Clamp: pbrt_Clamp; Black: skip the tap), and compare the mode with ==: the seed's listing has "
                                "`wrapMode = ImageWrap::Clamp`, which changes the mode"
                  : w0 != w && h0 != h ? "both sides are resampled: s first into resampledImage, then t per column through workData"
                                       : "the side that is not a power of two is resampled: check the taps' wrap (Mod for Repeat, Clamp, skip for Black)");
      }
      ref_mip_free(m0);
      stu_mip_free(m1);
    }
  { /* by hand: normalised weights keep a constant image constant (Repeat and Clamp) */
    float img[3 * 5 * 3], b[3 * 8 * 4];
    int i;
    for (i = 0; i < 3 * 5 * 3; ++i) img[i] = 0.5f;
    for (k = 0; k < 2; ++k) {
      void *m1 = stu_mip_new(5, 3, img, k ? CLAMP : REPEAT, 0, 8.f);
      int w1, h1;
      stu_level_size(m1, 0, &w1, &h1);
      if (w1 * h1 <= 32) {
        stu_level_texels(m1, 0, b);
        for (i = 0; i < 3 * w1 * h1; ++i)
          if (!lab_close(b[i], 0.5, 1e-5)) break;
        lab_check(i == 3 * w1 * h1, "a constant 5x3 image of 0.5 (wrap %s) is %.5f at texel (%d, %d) of level 0: resampling must keep it 0.5",
                  k ? "Clamp" : "Repeat", i < 3 * w1 * h1 ? b[i] : 0., (i / 3) % w1, (i / 3) / w1);
      }
      stu_mip_free(m1);
    }
  }
}

static void part_texel(void) {
  float img[3 * 4 * 2], a[3], b[3];
  int wrap, s, t;
  lab_part("part 2, TODO 3: Texel and the wrap modes (chapter 2, \"Step 2\")");
  test_image(4, 2, 5, img);
  for (wrap = 0; wrap < 3; ++wrap) {
    void *m0 = ref_mip_new(4, 2, img, wrap, 0, 8.f), *m1 = stu_mip_new(4, 2, img, wrap, 0, 8.f);
    int bad = 0;
    for (t = -3; t < 5 && !bad; ++t)
      for (s = -5; s < 9 && !bad; ++s) {
        int inside = s >= 0 && s < 4 && t >= 0 && t < 2;
        ref_texel(m0, 0, s, t, a);
        stu_texel(m1, 0, s, t, b);
        if (inside) /* by hand: inside the level, the image's own texel */
          bad = !lab_check(same3(b, img + 3 * (t * 4 + s), 1e-6),
                           "Texel(0, %d, %d) inside the 4x2 level is (%.4f, %.4f, %.4f), the image's texel is (%.4f, %.4f, %.4f): "
                           "return *pbrt_BlockedArray_at(l, s, t)",
                           s, t, b[0], b[1], b[2], img[3 * (t * 4 + s)], img[3 * (t * 4 + s) + 1], img[3 * (t * 4 + s) + 2]);
        else
          bad = !lab_check(same3(a, b, 1e-6), "Texel(0, %d, %d) of a 4x2 level under %s is %.4f, pbrt's %.4f: %s", s, t, wrap_name[wrap],
                           b[0], a[0],
                           wrap == REPEAT  ? "Repeat wraps s and t with pbrt_Mod, which stays >= 0 for negative s (C's % does not)"
                           : wrap == CLAMP ? "Clamp moves s into [0, uSize - 1] and t into [0, vSize - 1]"
                                           : "Black returns black for every texel outside the level");
      }
    if (!bad) lab_check(1, "");
    ref_mip_free(m0);
    stu_mip_free(m1);
  }
}

static void part_triangle(void) {
  float img[3 * 8 * 4], a[3], b[3];
  void *m0, *m1;
  int k, level;
  lab_part("part 3, TODO 4: triangle, bilinear on one level (chapter 2, \"Step 3\")");
  test_image(8, 4, 9, img);
  m0 = ref_mip_new(8, 4, img, REPEAT, 0, 8.f);
  m1 = stu_mip_new(8, 4, img, REPEAT, 0, 8.f);
  { /* by hand: at the centre of texel (s, t) of level 0 the lookup is that texel */
    int s = 5, t = 2;
    stu_triangle(m1, 0, (s + .5f) / 8, (t + .5f) / 4, b);
    lab_check(same3(b, img + 3 * (t * 8 + s), 1e-5),
              "triangle(0, st) at the centre of texel (5, 2), st = (0.6875, 0.625), is %.5f, the texel is %.5f: s = st.x * uSize - 0.5f "
              "(texel centres lie at half-integers), then ds = s - floor(s) is 0",
              b[0], img[3 * (t * 8 + s)]);
  }
  for (level = 0; level < 2; ++level)
    for (k = 0; k < 12; ++k) {
      float s = (float)k / 11.f * 1.2f - 0.1f, t = (float)((k * 7) % 12) / 11.f;
      ref_triangle(m0, level, s, t, a);
      stu_triangle(m1, level, s, t, b);
      if (!lab_check(same3(a, b, 1e-5),
                     "triangle(level %d, st = (%.3f, %.3f)) is %.5f, pbrt's is %.5f: the weights are (1 - ds)(1 - dt) for (s0, t0), "
                     "(1 - ds) dt for (s0, t0 + 1), ds (1 - dt) for (s0 + 1, t0) and ds dt for (s0 + 1, t0 + 1)%s",
                     level, s, t, b[0], a[0], level ? " (level 1 also needs your Texel and the given box filter: fix part 2 first)" : ""))
        break;
    }
  ref_mip_free(m0);
  stu_mip_free(m1);
}

static void part_lookup(void) {
  static const float widths[] = {0, 1e-3f, 0.05f, 0.1f, 0.2f, 0.3f, 0.45f, 0.7f, 1.f, 4.f};
  float img[3 * 16 * 8], a[3], b[3], lo[3], hi[3];
  void *m0, *m1;
  int k;
  lab_part("part 4, TODO 5: Lookup(st, width), trilinear (chapter 2, \"Step 3\")");
  test_image(16, 8, 21, img);
  m0 = ref_mip_new(16, 8, img, REPEAT, 0, 8.f);
  m1 = stu_mip_new(16, 8, img, REPEAT, 0, 8.f);
  for (k = 0; k < 10; ++k) {
    float w = widths[k], s = 0.37f + 0.05f * (float)k, t = 0.61f - 0.03f * (float)k;
    float level = 4 + log2f(w > 1e-8f ? w : 1e-8f);
    const char *hint;
    ref_lookup(m0, s, t, w, a);
    stu_lookup(m1, s, t, w, b);
    if (same3(a, b, 1e-5)) {
      lab_check(1, "");
      continue;
    }
    if (level < 0) hint = "below level 0 the lookup is triangle(0, st)";
    else if (level >= 4) hint = "at or above the last level it is that level's one texel, Texel(Levels() - 1, 0, 0)";
    else {
      int il = (int)floorf(level);
      ref_triangle(m0, il, s, t, lo);
      ref_triangle(m0, il + 1, s, t, hi);
      hint = same3(b, lo, 1e-5) || same3(b, hi, 1e-5)
                 ? "yours is triangle on one level: blend the two levels around it, pbrt_Lerp(level - iLevel, triangle(iLevel), triangle(iLevel + 1))"
                 : "level = Levels() - 1 + Log2(max(width, 1e-8)), iLevel = floor(level), then pbrt_Lerp(level - iLevel, ...)";
    }
    lab_check(0, "Lookup(st = (%.2f, %.2f), width = %g) is %.5f, pbrt's %.5f (pbrt's level is %.3f of 0..4): %s", s, t, w, b[0], a[0],
              level, hint);
  }
  ref_mip_free(m0);
  stu_mip_free(m1);
}

static void part_ewa(void) {
  float img[3 * 16 * 16], a[3], b[3];
  int k, trilinear, touched = 0;
  test_image(16, 16, 33, img);
  for (trilinear = 0; trilinear < 2 && !touched; ++trilinear) {
    void *m1 = stu_mip_new(16, 16, img, REPEAT, trilinear, 8.f);
    for (k = 0; k < 8; ++k) {
      float d0[2] = {0.002f + 0.01f * (float)k, 0.001f}, d1[2] = {0.0005f, 0.003f * (float)(k + 1)};
      stu_lookup_dst(m1, 0.3f + 0.05f * (float)k, 0.7f, d0, d1, b);
      if (b[0] != 0 || b[1] != 0 || b[2] != 0) touched = 1;
    }
    stu_mip_free(m1);
  }
  if (!touched) {
    lab_part_skip("part 5, TODO 6 (optional): EWA and Lookup(st, dst0, dst1)", "not written (every lookup is black)");
    return;
  }
  lab_part("part 5, TODO 6 (optional): EWA and Lookup(st, dst0, dst1) (chapter 2, \"Trilinear against EWA\")");
  for (trilinear = 0; trilinear < 2; ++trilinear) {
    void *m0 = ref_mip_new(16, 16, img, REPEAT, trilinear, 8.f), *m1 = stu_mip_new(16, 16, img, REPEAT, trilinear, 8.f);
    for (k = 0; k < 8; ++k) {
      float d0[2] = {0.002f + 0.01f * (float)k, 0.001f}, d1[2] = {0.0005f, 0.003f * (float)(k + 1)};
      ref_lookup_dst(m0, 0.3f + 0.05f * (float)k, 0.7f, d0, d1, a);
      stu_lookup_dst(m1, 0.3f + 0.05f * (float)k, 0.7f, d0, d1, b);
      if (!lab_check(same3(a, b, 1e-4), "Lookup(st, dst0 = (%g, %g), dst1 = (%g, %g)) with doTrilinear = %d is %.5f, pbrt's %.5f: %s", d0[0],
                     d0[1], d1[0], d1[1], trilinear, b[0], a[0],
                     trilinear ? "with doTrilinear it is Lookup(st, width) with the largest |component| as the width (not 2 * width)"
                               : "check the ellipse's axes and the anisotropy clamp, lod = max(0, Levels() - 1 + Log2(minorLength)), "
                                 "and EWA's weights (weightLut[min(int(r2 * WeightLUTSize), WeightLUTSize - 1)], divided by their sum)"))
        break;
    }
    ref_mip_free(m0);
    stu_mip_free(m1);
  }
}

int main(void) {
  printf("lab 2: the MIP map's resampling, wrap modes and lookups (tutorials/02-porting-the-mipmap.md), your file against pbrt's\n\n");
  part_resample();
  part_texel();
  part_triangle();
  part_lookup();
  part_ewa();
  return lab_finish("lab 2 (the MIP map's resampling and lookups)");
}
