/* tutorial_check.h: the checks and the random numbers the course's tests (test_tutorial_*.c) share.
 * Define TUTORIAL_RNG_SEED before including it: each test keeps its own sequence. */
#ifndef TUTORIAL_CHECK_H
#define TUTORIAL_CHECK_H
#include <stdio.h>

static int g_pass, g_fail;
/* one check: counted, and printed with what it checks */
static void check(int ok, const char *what) {
  if (ok) g_pass++;
  else g_fail++;
  printf("%s: %s\n", ok ? "PASS" : "FAIL", what);
}
/* the same, with two numbers in the message (fmt takes two doubles) */
static void checkf(int ok, const char *fmt, double a, double b) {
  char buf[400];
  snprintf(buf, sizeof buf, fmt, a, b);
  check(ok, buf);
}
/* a uniform float in [0, 1) from a linear congruential generator (Numerical Recipes' constants) */
#include "test_rng.h" /* lcg_f */
static lcg g_rng = {TUTORIAL_RNG_SEED};
static float frand(void) { return lcg_f(&g_rng); }
#endif
