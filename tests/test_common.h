/* test_common.h: what the envlight tests share (test_envlight, test_envlight_bigmaps, test_envlight_edges,
 * test_envlight_sun).
 *
 *   check(ok, fmt, ...)   prints "PASS " or "FAIL " and the printf-formatted message on one line and
 *                         counts it in g_pass or g_fail (the test's main prints the totals and returns
 *                         g_fail != 0);
 *   rotation37(m)         the tests' general rotation: 37 degrees about the normalised axis (1, 2, 3)
 *                         (Rodrigues, in double, rounded to float), row-major. */
#ifndef EL_TEST_COMMON_H
#define EL_TEST_COMMON_H

#include <math.h>
#include <stdarg.h>
#include <stdio.h>

static int g_pass = 0, g_fail = 0;

static void check(int ok, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;
static void check(int ok, const char *fmt, ...) {
  va_list ap;
  printf("%s ", ok ? "PASS" : "FAIL");
  va_start(ap, fmt);
  vprintf(fmt, ap);
  va_end(ap);
  printf("\n");
  if (ok) ++g_pass; else ++g_fail;
}

/* 1 when rgb is within 2e-4 of the range of the four texels le() reads at light-space (u, v) of a w x h
 * RGB map (Repeat in u, Clamp in v) from le (+ 1e-6 le): le at a point shifted by 1e-4 texel at most, as
 * sample_li's radiance under a signed permutation (envlight.h) */
static inline int rgb_near_le(const float *texels, int w, int h, double u, double v, const float le[3], const float rgb[3]) {
  int x0 = (int)floor(u * w - 0.5), y0 = (int)floor(v * h - 0.5), c, k;
  for (c = 0; c < 3; ++c) {
    float lo = 3e38f, hi = 0.0f;
    for (k = 0; k < 4; ++k) {
      int xx = ((x0 + (k & 1)) % w + w) % w, yy = y0 + (k >> 1);
      float t;
      yy = yy < 0 ? 0 : yy > h - 1 ? h - 1 : yy;
      t = texels[3 * ((size_t)yy * (size_t)w + (size_t)xx) + c];
      lo = t < lo ? t : lo; hi = t > hi ? t : hi;
    }
    if (!(fabsf(le[c] - rgb[c]) <= 2e-4f * (hi - lo) + 1e-6f * le[c])) return 0;
  }
  return 1;
}

static void rotation37(float m[9]) {
  double ax[3] = {1, 2, 3}, n = sqrt(14.0), a = 37.0 * 3.14159265358979323846 / 180.0, c = cos(a), s = sin(a), t = 1 - c;
  double x = ax[0] / n, y = ax[1] / n, z = ax[2] / n;
  double r[9] = {t * x * x + c, t * x * y - s * z, t * x * z + s * y, t * x * y + s * z, t * y * y + c,
                 t * y * z - s * x, t * x * z - s * y, t * y * z + s * x, t * z * z + c};
  int i;
  for (i = 0; i < 9; ++i) m[i] = (float)r[i];
}

#endif
