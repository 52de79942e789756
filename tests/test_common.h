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

static void rotation37(float m[9]) {
  double ax[3] = {1, 2, 3}, n = sqrt(14.0), a = 37.0 * 3.14159265358979323846 / 180.0, c = cos(a), s = sin(a), t = 1 - c;
  double x = ax[0] / n, y = ax[1] / n, z = ax[2] / n;
  double r[9] = {t * x * x + c, t * x * y - s * z, t * x * z + s * y, t * x * y + s * z, t * y * y + c,
                 t * y * z - s * x, t * x * z - s * y, t * y * z + s * x, t * z * z + c};
  int i;
  for (i = 0; i < 9; ++i) m[i] = (float)r[i];
}

#endif
