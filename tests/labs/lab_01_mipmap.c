/* tests/labs/lab_01_mipmap.c: lab 1 (tutorials/01-mipmap.md): the MIP map's resampling weights, its
 * levels and the EWA weight table, in the file under test (stu_*, lab_mipmap_side.c built against
 * it) against pbrt's (ref_*, the same file built against examples/pbrtv3/mipmap.h), plus facts
 * derived by hand (weights sum to 1, each level keeps the mean under Repeat, the table's ends).
 * Prints one line per part and, for a difference, what the chapter says about it. */
#include "lab_check.h"
#include "lab_mipmap.h"

#include <stdlib.h>

enum { REPEAT, BLACK, CLAMP }; /* pbrt_ImageWrap's order */
static const char *wrap_name[3] = {"Repeat", "Black", "Clamp"};

static void test_image(int w, int h, unsigned seed, float *rgb) {
  int i;
  for (i = 0; i < 3 * w * h; ++i) {
    seed = seed * 1664525u + 1013904223u;
    rgb[i] = (float)(seed >> 8) / 16777216.f; /* in [0, 1) */
  }
}

static void part_weights(void) {
  static const int cases[][2] = {{5, 8}, {3, 4}, {400, 512}, {235, 256}};
  int k;
  lab_part("part 1, TODO 1: resampleWeights (chapter 1, \"Constructor step 1\")");
  for (k = 0; k < 4; ++k) {
    int oldRes = cases[k][0], newRes = cases[k][1], i, j, bad = 0;
    int *f0 = (int *)calloc((size_t)newRes, sizeof(int)), *f1 = (int *)calloc((size_t)newRes, sizeof(int));
    float *w0 = (float *)calloc((size_t)newRes * 4, sizeof(float)), *w1 = (float *)calloc((size_t)newRes * 4, sizeof(float));
    ref_weights(oldRes, newRes, f0, w0);
    stu_weights(oldRes, newRes, f1, w1);
    for (i = 0; i < newRes && !bad; ++i) {
      float sum = w1[4 * i] + w1[4 * i + 1] + w1[4 * i + 2] + w1[4 * i + 3];
      if (sum == 0 && w1[4 * i] == 0) {
        bad = !lab_check(0, "resampleWeights(%d, %d): texel %d's four weights are all 0 (TODO 1 not written yet?)", oldRes,
                         newRes, i);
        break;
      }
      if (!lab_check(f1[i] == f0[i],
                     "resampleWeights(%d, %d): texel %d's firstTexel is %d, pbrt's is %d: its centre is center = (i + .5f) * "
                     "oldRes / newRes = %g, and firstTexel = floor(center - filterwidth + 0.5) with filterwidth 2",
                     oldRes, newRes, i, f1[i], f0[i], (i + .5) * oldRes / newRes)) {
        bad = 1;
        break;
      }
      /* by hand: normalised weights sum to 1 */
      if (!lab_check(fabsf(sum - 1) < 1e-5f,
                     "resampleWeights(%d, %d): texel %d's weights sum to %.6f, not 1: did you divide by the filter weights' "
                     "sum (<<Normalize filter weights for texel resampling>>)? Without it a constant image does not stay "
                     "constant",
                     oldRes, newRes, i, sum)) {
        bad = 1;
        break;
      }
      for (j = 0; j < 4; ++j)
        if (!lab_check(lab_close(w1[4 * i + j], w0[4 * i + j], 1e-5),
                       "resampleWeights(%d, %d): texel %d's weight[%d] is %.6f, pbrt's is %.6f: tap j's centre is pos = "
                       "firstTexel + j + .5f, its weight Lanczos((pos - center) / filterwidth, 2.f), before normalising",
                       oldRes, newRes, i, j, w1[4 * i + j], w0[4 * i + j])) {
          bad = 1;
          break;
        }
    }
    if (!bad) { /* by hand (exercise 1.2): texel newRes - 1 - i has texel i's weights in reverse order */
      for (j = 0; j < 4; ++j)
        if (!lab_check(lab_close(w1[4 * (newRes - 1) + j], w1[3 - j], 1e-5),
                       "resampleWeights(%d, %d): the last texel's weights are not the first texel's reversed", oldRes, newRes))
          break;
    }
    free(f0); free(f1); free(w0); free(w1);
  }
  { /* the weights in use: a 5x3 image, resampled to 8x4 by the given loops with your weights */
    float img[3 * 5 * 3], a[3 * 8 * 4], b[3 * 8 * 4];
    int wrap, w0, h0, w1, h1, i;
    test_image(5, 3, 7, img);
    for (wrap = 0; wrap < 3; ++wrap) {
      void *m0 = ref_mip_new(5, 3, img, wrap, 0, 8.f), *m1 = stu_mip_new(5, 3, img, wrap, 0, 8.f);
      ref_level_size(m0, 0, &w0, &h0);
      stu_level_size(m1, 0, &w1, &h1);
      if (lab_check(w0 == w1 && h0 == h1, "a 5x3 image: your level 0 is %dx%d, pbrt's %dx%d", w1, h1, w0, h0)) {
        ref_level_texels(m0, 0, a);
        stu_level_texels(m1, 0, b);
        for (i = 0; i < 3 * w0 * h0; ++i)
          if (!lab_close(a[i], b[i], 1e-4)) break;
        lab_check(i == 3 * w0 * h0,
                  "a 5x3 image resampled to 8x4 (wrap %s) with your weights: level 0 differs from pbrt's at texel (%d, %d): "
                  "%.5f against %.5f",
                  wrap_name[wrap], (i / 3) % w0, (i / 3) / w0, i < 3 * w0 * h0 ? b[i] : 0., i < 3 * w0 * h0 ? a[i] : 0.);
      }
      ref_mip_free(m0);
      stu_mip_free(m1);
    }
  }
}

static void part_levels(void) {
  static const int sizes[][2] = {{8, 4}, {16, 16}, {4, 1}, {1, 1}, {2, 8}};
  int k, wrap;
  lab_part("part 2, TODO 2 and 3: the number of levels and the box filter (chapter 1, \"Constructor step 2\")");
  for (k = 0; k < 5; ++k)
    for (wrap = 0; wrap < 3; ++wrap) {
      int w = sizes[k][0], h = sizes[k][1], n0, n1, i, bad = 0;
      float *img = (float *)malloc(sizeof(float) * 3 * (size_t)(w * h)), *a = (float *)malloc(sizeof(float) * 3 * (size_t)(w * h)),
            *b = (float *)malloc(sizeof(float) * 3 * (size_t)(w * h));
      void *m0, *m1;
      test_image(w, h, (unsigned)(11 + k), img);
      m0 = ref_mip_new(w, h, img, wrap, 0, 8.f);
      m1 = stu_mip_new(w, h, img, wrap, 0, 8.f);
      n0 = ref_levels(m0);
      n1 = stu_levels(m1);
      if (lab_check(n0 == n1, "the %dx%d image (wrap %s) has %d levels in your MIP map, %d in pbrt's: nLevels = 1 + Log2Int(max(width, height))",
                    w, h, wrap_name[wrap], n1, n0)) {
        for (i = 1; i < n0 && !bad; ++i) {
          int w0, h0, w1, h1, j;
          double m_0 = 0, m_prev = 0;
          ref_level_size(m0, i, &w0, &h0);
          stu_level_size(m1, i, &w1, &h1);
          if (!lab_check(w0 == w1 && h0 == h1,
                         "%dx%d image, level %d: yours is %dx%d, pbrt's %dx%d: each side halves, but never below 1 (std::max(1, ...))",
                         w, h, i, w1, h1, w0, h0)) {
            bad = 1;
            break;
          }
          ref_level_texels(m0, i, a);
          stu_level_texels(m1, i, b);
          for (j = 0; j < 3 * w0 * h0; ++j)
            if (!lab_close(a[j], b[j], 1e-5)) break;
          if (j < 3 * w0 * h0) {
            double ratio = a[j] != 0 ? b[j] / a[j] : 0;
            const char *hint = fabs(ratio - 4) < 1e-3 ? "it is 4 times pbrt's: did you forget the .25f?"
                               : b[j] == 0          ? "it is 0: is the texel written at all (*pbrt_BlockedArray_at(pyramid[i], s, t) = ...)?"
                                                    : "texel (s, t) of level i is .25f times the sum of texels (2s, 2t), (2s+1, 2t), (2s, 2t+1) "
                                                      "and (2s+1, 2t+1) of level i - 1, read with pbrt_MIPMap_Texel(mip, i - 1, ...)";
            lab_check(0, "%dx%d image (wrap %s): level %d differs from pbrt's at texel (%d, %d): %.5f against %.5f: %s", w, h,
                      wrap_name[wrap], i, (j / 3) % w0, (j / 3) / w0, b[j], a[j], hint);
            bad = 1;
            break;
          }
          if (wrap == REPEAT) { /* by hand: under Repeat each level keeps level 0's mean */
            stu_level_texels(m1, 0, a);
            for (j = 0; j < 3 * w * h; ++j) m_0 += a[j];
            for (j = 0; j < 3 * w1 * h1; ++j) m_prev += b[j];
            m_0 /= w * h;
            m_prev /= w1 * h1;
            lab_check(fabs(m_0 - m_prev) < 1e-4, "%dx%d image (Repeat): level %d's mean is %.5f, level 0's %.5f: the box filter keeps the mean",
                      w, h, i, m_prev / 3, m_0 / 3);
          }
        }
      }
      ref_mip_free(m0);
      stu_mip_free(m1);
      free(img); free(a); free(b);
    }
}

static void part_lut(void) {
  float a[128], b[128], img[3] = {1, 1, 1};
  int i;
  void *m0 = ref_mip_new(1, 1, img, 0, 0, 8.f), *m1 = stu_mip_new(1, 1, img, 0, 0, 8.f);
  lab_part("part 3, TODO 4: the EWA weight table (chapter 1, \"Constructor step 3\")");
  ref_weightlut(a);
  stu_weightlut(b);
  /* by hand: exp(-2 * 0) - exp(-2) and exp(-2 * 1) - exp(-2) */
  lab_check(lab_close(b[0], 1 - exp(-2.), 1e-6), "weightLut[0] is %.6f, should be exp(0) - exp(-2) = %.6f (r2 = 0, alpha = 2)", b[0],
            1 - exp(-2.));
  lab_check(fabsf(b[127]) < 1e-6f, "weightLut[127] is %.6f, should be 0: r2 = 127 / (WeightLUTSize - 1) = 1, exp(-2) - exp(-2)", b[127]);
  for (i = 0; i < 128; ++i)
    if (!lab_close(a[i], b[i], 1e-6)) break;
  lab_check(i == 128, "weightLut[%d] is %.6f, pbrt's is %.6f: r2 = (float)i / (float)(WeightLUTSize - 1), weight exp(-alpha r2) - exp(-alpha)",
            i, i < 128 ? b[i] : 0., i < 128 ? a[i] : 0.);
  ref_mip_free(m0);
  stu_mip_free(m1);
}

int main(void) {
  printf("lab 1: the MIP map's weights and levels (tutorials/01-mipmap.md), your file against pbrt's\n\n");
  part_weights();
  part_levels();
  part_lut();
  return lab_finish("lab 1 (the MIP map's weights and levels)");
}
