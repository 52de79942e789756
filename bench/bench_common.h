/* bench_common.h: the clocks, the median and the small chores that the benchmarks share, and the
 * random numbers of tests/test_rng.h (rng, rng_u32, rng_f, rng_make, hash32). Header-only static inline
 * functions, C99 and C++. Define _POSIX_C_SOURCE (199309L or later) before the first include: the
 * clocks are POSIX's clock_gettime.
 *
 *   wall_now()      seconds of CLOCK_MONOTONIC (wall time);
 *   process_now()   this process's CPU seconds (a single-threaded benchmark: the time we wait for a core
 *                   on a shared machine does not count);
 *   cpu_now()       this thread's CPU seconds;
 *   median(v, n)    the median of n doubles (sorts v);
 *   make_parent_dir(path)  creates the folder that holds the file `path` (one level; quiet if it exists
 *                   or cannot be made: the write that follows reports the error);
 *   picture_to8(x)  a radiance x as an 8-bit sRGB value of x / (1 + x) (the sample pictures' tone map);
 *   picture_dot(img, W, H, x, y, r, R, G, B)  a (2r + 1)^2 square of colour (R, G, B) at (x, y) on a
 *                   W x H RGB8 lat-long picture: x wraps around, y is clipped. */
#ifndef EL_BENCH_COMMON_H
#define EL_BENCH_COMMON_H

#include "../tests/test_rng.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

static inline double wall_now(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}
static inline double process_now(void) {
  struct timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}
static inline double cpu_now(void) {
  struct timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static inline int cmp_double(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return x < y ? -1 : x > y;
}
static inline double median(double *v, int n) {
  qsort(v, (size_t)n, sizeof *v, cmp_double);
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

static inline void make_parent_dir(const char *path) {
  char dir[512];
  const char *slash = strrchr(path, '/');
  if (slash && slash - path < (long)sizeof dir) {
    memcpy(dir, path, (size_t)(slash - path));
    dir[slash - path] = 0;
    mkdir(dir, 0777);
  }
}

static inline unsigned char picture_to8(double x) {
  double t = x / (1 + x);
  t = t <= 0.0031308 ? 12.92 * t : 1.055 * pow(t, 1 / 2.4) - 0.055;
  return (unsigned char)(t <= 0 ? 0 : t >= 1 ? 255 : (int)(t * 255 + 0.5));
}
static inline void picture_dot(unsigned char *img, int W, int H, int x, int y, int r, unsigned char cr, unsigned char cg,
                               unsigned char cb) {
  int dx, dy;
  for (dy = -r; dy <= r; ++dy)
    for (dx = -r; dx <= r; ++dx) {
      int xx = ((x + dx) % W + W) % W, yy = y + dy;
      unsigned char *q;
      if (yy < 0 || yy >= H) continue;
      q = img + 3 * ((size_t)yy * (size_t)W + (size_t)xx);
      q[0] = cr; q[1] = cg; q[2] = cb;
    }
}

#endif
