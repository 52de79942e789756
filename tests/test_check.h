/* test_check.h: the PASS / FAIL line that the envlight tests share (test_envlight, test_envlight_bigmaps,
 * test_envlight_edges, test_envlight_sun). check(ok, fmt, ...) prints "PASS " or "FAIL " and the
 * printf-formatted message on one line and counts it in g_pass or g_fail (the test's main prints the
 * totals and returns g_fail != 0). */
#ifndef EL_TEST_CHECK_H
#define EL_TEST_CHECK_H

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

#endif
