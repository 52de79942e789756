/* tests/labs/lab_check.h: the labs' report. A lab test is in parts (one per TODO or group of TODOs);
 * each part runs checks, and a failed check prints what differs from pbrt and what the chapter says
 * about it. The last line is the verdict, which tests/labs/run_lab.cmake reads:
 *   "lab N (...): all M checks passed"   or   "lab N (...): K of M checks failed"
 * Every part prints "[ok]" or "[FAIL]" (or "[skip]" for an optional part left untouched): the
 * repository's untouched lab files must fail every part that is not optional (run_lab.cmake checks
 * that no "[ok]" line appears), so each part is seen to be able to fail. */
#ifndef LAB_CHECK_H
#define LAB_CHECK_H
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

static int lab_checks, lab_failed, lab_part_checks, lab_part_failed, lab_part_open;
static char lab_part_title[200];

static void lab_part_end(void) {
  if (!lab_part_open) return;
  if (lab_part_failed > 2) printf("    ... and %d more like these\n", lab_part_failed - 2);
  if (lab_part_failed) printf("[FAIL] %s: %d of %d checks failed\n\n", lab_part_title, lab_part_failed, lab_part_checks);
  else printf("[ok]   %s: %d checks passed\n\n", lab_part_title, lab_part_checks);
  lab_part_open = 0;
}
static void lab_part(const char *title) {
  lab_part_end();
  snprintf(lab_part_title, sizeof lab_part_title, "%s", title);
  lab_part_checks = lab_part_failed = 0;
  lab_part_open = 1;
  printf("%s\n", title);
}
/* An optional part that the student left as it was: no checks, no failure. */
static void lab_part_skip(const char *title, const char *why) {
  lab_part_end();
  printf("[skip] %s: %s\n\n", title, why);
}
/* One check. The message (printf format) is printed for the first two failures of a part. Returns ok. */
static int lab_check(int ok, const char *fmt, ...) {
  lab_checks++;
  lab_part_checks++;
  if (!ok) {
    lab_failed++;
    if (++lab_part_failed <= 2) {
      va_list ap;
      printf("  - ");
      va_start(ap, fmt);
      vprintf(fmt, ap);
      va_end(ap);
      printf("\n");
    }
  }
  return ok;
}
/* a and b agree to tol, relative to the larger magnitude (and absolutely below 1); NaN never agrees. */
static int lab_close(double a, double b, double tol) {
  double m = fabs(a) > fabs(b) ? fabs(a) : fabs(b);
  if (a != a || b != b) return 0;
  return fabs(a - b) <= tol * (m > 1 ? m : 1);
}
static int lab_finish(const char *title) {
  (void)lab_part_skip;
  lab_part_end();
  if (lab_failed) printf("%s: %d of %d checks failed\n", title, lab_failed, lab_checks);
  else printf("%s: all %d checks passed\n", title, lab_checks);
  return lab_failed ? 1 : 0;
}
#endif
