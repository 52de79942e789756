/* bench_bigmaps.c: what a big environment map costs (issue 24): time and peak memory of el_envlight_init,
 * the sampling tables and the product tables from 1024x512 to 16384x8192, and the variance the default
 * cap of the importance map costs on a map whose 0.5-degree sun needs resolution.
 *
 *   bench_bigmaps                 tables 1-3, maps up to 16384x8192 (needs about 6 GB of memory, 1-3 min)
 *   bench_bigmaps --quick         up to 2048x1024, fewer samples (a second)
 *   bench_bigmaps --max W         maps up to W x W/2
 *   bench_bigmaps --build-only    table 1 only
 *   bench_bigmaps --csv [--quick] the rows as CSV (kind,option,...) for bench/report.py
 *
 * The map is generated in code: a sky gradient with texel noise, a dark ground, and a sun of angular
 * diameter 0.5 degrees (radiance 1e5: about half of the map's power) at 30 degrees elevation.
 *
 * Tables:
 *  1. Build cost per map size and configuration: today's (a copy of the image, importance map at the
 *     image's resolution: importance_cap = -1), the default (a copy, the importance map capped at
 *     EL_ENVLIGHT_IMPORTANCE_CAP), and no_copy (the caller's pixels, capped). Wall and CPU (user + system)
 *     milliseconds of el_envlight_init, el_envlight_prepare_sampling and el_envlight_prepare_product, and
 *     the peak memory above the caller's image (Linux: VmHWM after resetting it through
 *     /proc/self/clear_refs, minus VmRSS before init), in MB and as a fraction of the image's bytes.
 *  2. The cap's cost in variance, on the largest map: per cap (512 .. no cap) the relative variance per
 *     sample of sample_li's estimate of the map's luminance integral (lum(le) / pdf) and of the irradiance
 *     of a surface facing up and one facing the sun, its bias in standard errors against the exact
 *     integral, the sampling tables' build time (CPU) and bytes.
 *  3. Equal-area maps (pbrt-v4) against the lat-long map of the same texel count: CPU ns per sample_li,
 *     pdf_li and le, and the tables' build time (native equal-area sampling vs. converting on load).
 *
 * Wall times on a machine shared with other jobs are noisy: tables 2 and 3 and the CPU columns use this
 * process's CPU time (user + system); run it twice, read ranges.
 */
#define _POSIX_C_SOURCE 199309L /* clock_gettime */
#define EL_IMPLEMENTATION
#include "envlight.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <sys/resource.h>
#ifdef __GLIBC__
#include <malloc.h> /* mallopt: large blocks straight from and back to the system, so that no run reuses
                       pages an earlier one faulted in, and the peak memory is each run's own */
#endif

static const double PI = 3.14159265358979323846;

#include "bench_common.h" /* wall_now, hash32 */
static double cpu(void) { /* user + system: page faults are system time */
  struct rusage ru;
  getrusage(RUSAGE_SELF, &ru);
  return ru.ru_utime.tv_sec + 1e-6 * ru.ru_utime.tv_usec + ru.ru_stime.tv_sec + 1e-6 * ru.ru_stime.tv_usec;
}
/* VmRSS / VmHWM of this process in bytes (0 where /proc is missing) */
static double proc_kb(const char *key) {
  FILE *f = fopen("/proc/self/status", "r");
  char line[256];
  double v = 0.0;
  size_t n = strlen(key);
  if (!f) return 0.0;
  while (fgets(line, sizeof line, f))
    if (!strncmp(line, key, n)) { v = atof(line + n + 1); break; }
  fclose(f);
  return v * 1024.0;
}
/* resets VmHWM to the current RSS (Linux >= 4.0); returns 0 where it cannot */
static int reset_hwm(void) {
  FILE *f = fopen("/proc/self/clear_refs", "w");
  if (!f) return 0;
  fputs("5", f);
  return fclose(f) == 0;
}

static float rnd(uint32_t i) { return (float)(hash32(i * 2654435761u + 12345u) >> 8) * (1.0f / 16777216.0f); }

/* the sun: 30 degrees above the horizon (light space, +z up), at phi = 1 rad; 0.5 degree diameter */
static const double SUN_ELEV = 30.0, SUN_PHI = 1.0, SUN_RADIUS_DEG = 0.25;
static const float SUN_L = 1e5f;
static void sun_dir(double d[3]) {
  double t = (90.0 - SUN_ELEV) * PI / 180.0;
  d[0] = sin(t) * cos(SUN_PHI); d[1] = sin(t) * sin(SUN_PHI); d[2] = cos(t);
}

/* lat-long w x h: sky (brighter towards the horizon) with noise, ground 0.05, the sun; the sun is tested
 * only in the rows and columns that can hold it */
static float *make_map(int w, int h) {
  float *px = (float *)malloc((size_t)w * (size_t)h * 3 * sizeof(float));
  double s[3], cr = cos(SUN_RADIUS_DEG * PI / 180.0), tsun = (90.0 - SUN_ELEV) / 180.0, pad = 2.0 * SUN_RADIUS_DEG / 180.0;
  int x, y, y0, y1;
  if (!px) return NULL;
  sun_dir(s);
  for (y = 0; y < h; ++y) {
    float vv = (y + 0.5f) / (float)h, sky = vv < 0.5f ? 0.3f + 1.4f * vv : 0.05f;
    float *row = px + (size_t)y * (size_t)w * 3;
    for (x = 0; x < w; ++x) {
      float v = sky * (0.6f + 0.8f * rnd((uint32_t)y * (uint32_t)w + (uint32_t)x));
      row[3 * x] = v; row[3 * x + 1] = 0.9f * v; row[3 * x + 2] = 0.8f * v;
    }
  }
  y0 = (int)floor((tsun - pad) * h); y1 = (int)ceil((tsun + pad) * h);
  for (y = y0 < 0 ? 0 : y0; y < (y1 > h ? h : y1); ++y) {
    double th = PI * (y + 0.5) / h;
    for (x = 0; x < w; ++x) {
      double ph = 2.0 * PI * (x + 0.5) / w, d = sin(th) * cos(ph) * s[0] + sin(th) * sin(ph) * s[1] + cos(th) * s[2];
      if (d >= cr) {
        float *p = px + ((size_t)y * (size_t)w + (size_t)x) * 3;
        p[0] = SUN_L; p[1] = 0.95f * SUN_L; p[2] = 0.9f * SUN_L;
      }
    }
  }
  return px;
}

/* the same scene as an equal-area N x N map (each texel: the direction at its centre) */
static float *make_map_square(int n) {
  float *px = (float *)malloc((size_t)n * (size_t)n * 3 * sizeof(float));
  double s[3], cr = cos(SUN_RADIUS_DEG * PI / 180.0);
  int x, y;
  if (!px) return NULL;
  sun_dir(s);
  for (y = 0; y < n; ++y)
    for (x = 0; x < n; ++x) {
      float d[3], *p = px + ((size_t)y * (size_t)n + (size_t)x) * 3, v;
      double th;
      el_envlight_square_to_dir((x + 0.5f) / (float)n, (y + 0.5f) / (float)n, d);
      th = acos(d[2] > 1.0f ? 1.0 : d[2]) / PI;
      v = (th < 0.5 ? 0.3f + 1.4f * (float)th : 0.05f) * (0.6f + 0.8f * rnd((uint32_t)y * (uint32_t)n + (uint32_t)x));
      if (d[0] * s[0] + d[1] * s[1] + d[2] * s[2] >= cr) v = SUN_L;
      p[0] = v; p[1] = 0.9f * v; p[2] = 0.8f * v;
    }
  return px;
}

static int g_csv;

/* Table 1: one configuration on one map: cap (0 default, -1 none), no_copy */
static void build_row(const float *px, int w, int h, const char *name, int cap, int no_copy) {
  el_envlight l;
  el_envlight_options o;
  el_result r;
  double img = (double)w * h * 12.0, rss0, t0, c0, t1, c1, t2, c2, t3, c3, hwm1, hwm2;
  int hwm_ok;
  memset(&o, 0, sizeof o);
  o.importance_cap = cap;
  o.no_copy = no_copy;
  hwm_ok = reset_hwm();
  rss0 = proc_kb("VmRSS:");
  t0 = wall_now(); c0 = cpu();
  r = el_envlight_init(&l, px, w, h, 3, &o);
  if (r != EL_SUCCESS) { printf("init failed: %s\n", el_result_string(r)); return; }
  t1 = wall_now(); c1 = cpu();
  r = el_envlight_prepare_sampling(&l);
  t2 = wall_now(); c2 = cpu();
  hwm1 = proc_kb("VmHWM:");
  if (r == EL_SUCCESS) r = el_envlight_prepare_product(&l, NULL);
  t3 = wall_now(); c3 = cpu();
  hwm2 = proc_kb("VmHWM:");
  if (r != EL_SUCCESS) printf("tables failed: %s\n", el_result_string(r));
  if (g_csv)
    printf("bigmap_build,%s,%d,%d,%.1f,%.1f,%.1f,%.1f,%.1f,%.1f,%.1f,%.1f,%.1f,%.3f,%.1f,%.3f,%d,%d\n", name, w, h, img / 1048576.0,
           1e3 * (t1 - t0), 1e3 * (t2 - t1), 1e3 * (t3 - t2), 1e3 * (c1 - c0), 1e3 * (c2 - c1), 1e3 * (c3 - c2),
           hwm_ok ? (hwm1 - rss0) / 1048576.0 : -1.0, hwm_ok ? (hwm2 - rss0) / 1048576.0 : -1.0,
           hwm_ok ? (hwm1 - rss0) / img : -1.0, (double)el_envlight_sampling_bytes(&l) / 1048576.0,
           hwm_ok ? (hwm2 - rss0) / img : -1.0, l.imp_w, l.imp_h);
  else
    printf("%5dx%-5d %-22s %6.0f %6.0f %6.0f | %6.0f %6.0f %6.0f | %7.0f %7.0f | %7.0f %6.3f | %7.0f %6.3f  %dx%d\n", w, h, name,
           1e3 * (t1 - t0), 1e3 * (t2 - t1), 1e3 * (t3 - t2), 1e3 * (c1 - c0), 1e3 * (c2 - c1), 1e3 * (c3 - c2),
           1e3 * (t2 - t0), 1e3 * (c2 - c0),
           hwm_ok ? (hwm1 - rss0) / 1048576.0 : -1.0, hwm_ok ? (hwm1 - rss0) / img : -1.0,
           hwm_ok ? (hwm2 - rss0) / 1048576.0 : -1.0, hwm_ok ? (hwm2 - rss0) / img : -1.0, l.imp_w, l.imp_h);
  fflush(stdout);
  el_envlight_free(&l);
}

/* Table 2: the cap's variance on the largest map */
static void variance_row(const float *px, int w, int h, int cap, int n) {
  el_envlight l;
  el_envlight_options o;
  float integral[3];
  double s[3], t0, tb, m[3] = {0, 0, 0}, q[3] = {0, 0, 0}, exact;
  int i, k;
  memset(&o, 0, sizeof o);
  o.importance_cap = cap;
  o.no_copy = 1;
  if (el_envlight_init(&l, px, w, h, 3, &o) != EL_SUCCESS) { printf("init failed\n"); return; }
  sun_dir(s);
  t0 = cpu();
  el_envlight_prepare_sampling(&l);
  tb = cpu() - t0;
  el_envlight_integral(&l, integral);
  exact = 0.212671 * integral[0] + 0.715160 * integral[1] + 0.072169 * integral[2];
  for (i = 0; i < n; ++i) {
    float u[2], wi[3], rgb[3], pdf;
    double y, x[3];
    u[0] = rnd(2u * (uint32_t)i); u[1] = rnd(2u * (uint32_t)i + 1u);
    el_envlight_sample_li(&l, u, wi, rgb, &pdf);
    y = pdf > 0.0f ? (0.212671 * rgb[0] + 0.715160 * rgb[1] + 0.072169 * rgb[2]) / pdf : 0.0;
    x[0] = y;
    x[1] = y * (wi[2] > 0.0f ? wi[2] : 0.0);
    x[2] = y * fmax(0.0, wi[0] * s[0] + wi[1] * s[1] + wi[2] * s[2]);
    for (k = 0; k < 3; ++k) { m[k] += x[k]; q[k] += x[k] * x[k]; }
  }
  for (k = 0; k < 3; ++k) { m[k] /= n; q[k] = q[k] / n - m[k] * m[k]; }
  {
    double rv[3], bias = fabs(m[0] - exact) / sqrt(q[0] / n);
    for (k = 0; k < 3; ++k) rv[k] = q[k] / (m[k] * m[k]);
    if (g_csv)
      printf("bigmap_cap,%d,%d,%d,%d,%d,%.5g,%.5g,%.5g,%.2f,%.1f,%.2f\n", cap, w, h, l.imp_w, l.imp_h, rv[0], rv[1], rv[2], bias,
             1e3 * tb, (double)el_envlight_sampling_bytes(&l) / 1048576.0);
    else
      printf("%-6d %5dx%-5d %10.4g %10.4g %10.4g %8.2f %9.0f %9.1f\n", cap, l.imp_w, l.imp_h, rv[0], rv[1], rv[2], bias, 1e3 * tb,
             (double)el_envlight_sampling_bytes(&l) / 1048576.0);
  }
  fflush(stdout);
  el_envlight_free(&l);
}

/* Table 3: ns per call on an equal-area map and on the lat-long map of the same texel count */
static void speed_row(const char *name, const float *px, int w, int h, int mapping) {
  el_envlight l;
  el_envlight_options o;
  double t0, tb, ts, tp, tl, acc = 0.0;
  int i, n = 1 << 20;
  memset(&o, 0, sizeof o);
  o.mapping = mapping;
  if (el_envlight_init(&l, px, w, h, 3, &o) != EL_SUCCESS) { printf("init failed\n"); return; }
  t0 = cpu(); el_envlight_prepare_sampling(&l); tb = cpu() - t0;
  t0 = cpu();
  for (i = 0; i < n; ++i) {
    float u[2], wi[3], rgb[3], pdf;
    u[0] = rnd(2u * (uint32_t)i); u[1] = rnd(2u * (uint32_t)i + 1u);
    el_envlight_sample_li(&l, u, wi, rgb, &pdf);
    acc += pdf + rgb[0];
  }
  ts = (cpu() - t0) / n;
  t0 = cpu();
  for (i = 0; i < n; ++i) {
    float d[3];
    d[0] = rnd(3u * (uint32_t)i) - 0.5f; d[1] = rnd(3u * (uint32_t)i + 1u) - 0.5f; d[2] = rnd(3u * (uint32_t)i + 2u) - 0.5f;
    acc += el_envlight_pdf_li(&l, d);
  }
  tp = (cpu() - t0) / n;
  t0 = cpu();
  for (i = 0; i < n; ++i) {
    float d[3], rgb[3];
    d[0] = rnd(3u * (uint32_t)i) - 0.5f; d[1] = rnd(3u * (uint32_t)i + 1u) - 0.5f; d[2] = rnd(3u * (uint32_t)i + 2u) - 0.5f;
    el_envlight_le(&l, d, rgb);
    acc += rgb[1];
  }
  tl = (cpu() - t0) / n;
  if (g_csv) printf("bigmap_mapping,%s,%d,%d,%.1f,%.1f,%.1f,%.2f\n", name, w, h, 1e9 * ts, 1e9 * tp, 1e9 * tl, 1e3 * tb);
  else printf("%-24s %5dx%-5d %9.1f %9.1f %9.1f %9.2f   (%g)\n", name, w, h, 1e9 * ts, 1e9 * tp, 1e9 * tl, 1e3 * tb, acc > 0.0 ? 0.0 : 1.0);
  el_envlight_free(&l);
}

int main(int argc, char **argv) {
  int quick = 0, maxw = 16384, a, w, nvar, build_only = 0;
  float *px;
#ifdef __GLIBC__
  mallopt(M_MMAP_THRESHOLD, 1 << 16);
  mallopt(M_TRIM_THRESHOLD, 1 << 16);
#endif
  for (a = 1; a < argc; ++a) {
    if (!strcmp(argv[a], "--quick")) quick = 1;
    else if (!strcmp(argv[a], "--csv")) g_csv = 1;
    else if (!strcmp(argv[a], "--max") && a + 1 < argc) maxw = atoi(argv[++a]);
    else if (!strcmp(argv[a], "--build-only")) build_only = 1;
    else { fprintf(stderr, "usage: bench_bigmaps [--quick] [--csv] [--max W] [--build-only]\n"); return 2; }
  }
  if (quick && maxw > 2048) maxw = 2048;
  if (maxw < 1024) maxw = 1024;
  nvar = quick ? 1 << 16 : 1 << 22;
  if (g_csv) /* the header row (report.py skips it); then kind,option,... rows */
    printf("kind,option,w,h,...: bigmap_build,config,w,h,image MB,wall init,wall smp,wall prd,cpu init,cpu smp,cpu prd,peak smp MB,peak all "
           "MB,peak smp/image,tables MB,peak all/image,imp_w,imp_h | bigmap_cap,cap,w,h,imp_w,imp_h,relvar lum,relvar E up,relvar E sun,"
           "bias/se,build ms,tables MB | bigmap_mapping,name,w,h,ns sample_li,ns pdf_li,ns le,tables ms\n");
  if (!g_csv) {
    printf("Table 1: build cost: wall ms and CPU ms (user + system) of init, the sampling tables (smp) and the product tables (prd);\n"
           "peak = VmHWM above the caller's image after the sampling tables and after the product tables, MB and x the image's bytes\n");
    printf("%-11s %-22s %6s %6s %6s | %6s %6s %6s | %7s %7s | %7s %6s | %7s %6s  %s\n", "map", "configuration", "init", "smp", "prd",
           "cpu in", "cpu sm", "cpu pr", "in+smp", "cpu i+s", "peak is", "ximg", "peak al", "ximg", "importance");
  }
  for (w = 1024; w <= maxw; w *= 2) {
    int h = w / 2;
    px = make_map(w, h);
    if (!px) { printf("%dx%d: out of memory\n", w, h); break; }
    build_row(px, w, h, "copy nocap (before)", -1, 0);
    build_row(px, w, h, "copy cap (default)", 0, 0);
    build_row(px, w, h, "no_copy cap", 0, 1);
    if (w == maxw && !build_only) {
      if (!g_csv) {
        printf("\nTable 2: the cap's variance on the %dx%d sun map (0.5 degree sun), %d samples of sample_li (no_copy)\n", w, h, nvar);
        printf("%-6s %-11s %10s %10s %10s %8s %9s %9s\n", "cap", "importance", "relvar lum", "E up", "E sun", "bias/se", "build ms", "tables MB");
      }
      {
        int caps[6] = {512, 1024, 2048, 4096, 8192, -1}, c;
        for (c = 0; c < 6; ++c)
          if (caps[c] < 0 || caps[c] < w) variance_row(px, w, h, caps[c], nvar);
      }
    }
    free(px);
  }
  if (build_only) return 0;
  if (!g_csv) {
    printf("\nTable 3: equal-area (pbrt-v4) against lat-long maps of the same texel count (ns per call; tables ms)\n");
    printf("%-24s %-11s %9s %9s %9s %9s\n", "mapping", "map", "sample_li", "pdf_li", "le", "tables");
  }
  {
    int n = quick ? 512 : 2048, m = (int)(n * 1.41421356); /* m^2 = 2 n^2 texels */
    px = make_map(2 * n, n);
    if (px) { speed_row("lat-long", px, 2 * n, n, EL_ENVLIGHT_MAPPING_LATLONG); free(px); }
    px = make_map_square(m);
    if (px) { speed_row("equal-area (native)", px, m, m, EL_ENVLIGHT_MAPPING_EQUAL_AREA); free(px); }
  }
  return 0;
}
