/* bench_film.c: what each pixel filter costs (time and instructions per el_film_add_sample) beside what
 * it buys on a supersampled slanted-edge chart, for pbrt's 16x16 weight table and exact evaluation.
 *
 *   bench_film                    the tables below (runs itself under callgrind if valgrind is found)
 *   bench_film --no-callgrind     timing and error columns only
 *   bench_film --csv [--quick]    the CSV that bench/report.py plots (see csv_mode)
 *   bench_film --callgrind OP N   only N calls of operation OP after the setup (OP: add_<filter>_<table|exact>,
 *                                 filter one of box triangle gaussian mitchell lanczos; or srgb8_<tonemap>)
 *
 * Instructions per call, by hand: valgrind --tool=callgrind --callgrind-out-file=cg.N bench_film --callgrind
 * add_mitchell_table N for N = 0 and N = 20000; (Ir(N) - Ir(0)) / N, Ir from the "totals:" line
 * (an srgb8_* call converts a 64x64 block: divide by 4096 more for one pixel).
 *
 * The chart: a 48x48 film of an edge slanted by 5 degrees (radiance 1 on one side, 0.1 on the other).
 *  - "blur RMSE": the filter's converged image (a regular grid of 32x32 samples per pixel) against the
 *    pixel-area average of the chart (64x64 midpoint samples per pixel, computed without film.h). Box is
 *    the area average itself; wider filters blur the edge; negative lobes (Mitchell, Lanczos) sharpen it.
 *  - "noise RMSE": 4 random samples per pixel against the same filter's converged image: what a wider
 *    support buys in variance.
 *  - "table-exact": the largest difference between the converged images made with the table and with
 *    exact weights: what the 16x16 table costs in accuracy.
 */
#define _POSIX_C_SOURCE 199309L /* clock_gettime */
#define EL_FILM_IMPLEMENTATION
#include "film.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static const char *filter_name[5] = {"box", "triangle", "gaussian", "mitchell", "lanczos"};
static const char *tonemap_name[4] = {"clamp", "exponential", "reinhard", "aces"};

#include "bench_common.h" /* wall_now, cpu_now, cmp_double, lcg_f */
static lcg g_rng = {2024u};

static el_film make_film(int w, int h, int type, int exact) {
  el_film f;
  el_film_options o;
  memset(&o, 0, sizeof o);
  o.width = w;
  o.height = h;
  o.filter.type = (el_film_filter_type)type;
  o.exact_filter = exact;
  if (el_film_init(&f, &o) != EL_SUCCESS) { fprintf(stderr, "bench_film: el_film_init failed\n"); exit(1); }
  return f;
}

/* ---- the chart -------------------------------------------------------------------------------- */
enum { CW = 48 };
static float chart(float x, float y) {
  const double a = 5.0 * 3.14159265358979323846 / 180.0;
  return (x - CW / 2.0) * cos(a) + (y - CW / 2.0) * sin(a) > 0 ? 1.0f : 0.1f;
}

/* converged image of a filter: a regular grid of g x g samples per pixel over the sample bounds */
static void converged(int type, int exact, int g, float *out) {
  el_film f = make_film(CW, CW, type, exact);
  int b[4], x, y, i, j;
  el_film_sample_bounds(&f, b);
  for (y = b[1]; y < b[3]; y++)
    for (x = b[0]; x < b[2]; x++)
      for (j = 0; j < g; j++)
        for (i = 0; i < g; i++) {
          float px = x + (i + 0.5f) / g, py = y + (j + 0.5f) / g, v = chart(px, py), c[3];
          c[0] = c[1] = c[2] = v;
          el_film_add_sample(&f, px, py, c, 1.0f);
        }
  el_film_get_rgb(&f, 1.0f, out);
  el_film_free(&f);
}

static double rmse_g(const float *a, const float *b, int n) { /* green channel of rgb images */
  double s = 0;
  int i;
  for (i = 0; i < n; i++) s += (a[3 * i + 1] - b[3 * i + 1]) * (double)(a[3 * i + 1] - b[3 * i + 1]);
  return sqrt(s / n);
}

/* ---- operations for timing and callgrind ---------------------------------------------------------- */
enum { NS = 4096 };
static float g_samples[NS * 5];

static void make_samples(const el_film *f) {
  int b[4], i;
  el_film_sample_bounds(f, b);
  for (i = 0; i < NS; i++) {
    g_samples[5 * i] = b[0] + (b[2] - b[0]) * lcg_f(&g_rng);
    g_samples[5 * i + 1] = b[1] + (b[3] - b[1]) * lcg_f(&g_rng);
    g_samples[5 * i + 2] = lcg_f(&g_rng);
    g_samples[5 * i + 3] = lcg_f(&g_rng);
    g_samples[5 * i + 4] = lcg_f(&g_rng);
  }
}

static void run_adds(el_film *f, long n) {
  long k;
  for (k = 0; k < n; k++) {
    const float *s = g_samples + 5 * (k & (NS - 1));
    el_film_add_sample(f, s[0], s[1], s + 2, 1.0f);
  }
}

static int parse_op(const char *op, int *kind, int *type, int *exact) {
  int t;
  char buf[64];
  for (t = 0; t < 5; t++) {
    snprintf(buf, sizeof buf, "add_%s_table", filter_name[t]);
    if (!strcmp(op, buf)) { *kind = 0; *type = t; *exact = 0; return 1; }
    snprintf(buf, sizeof buf, "add_%s_exact", filter_name[t]);
    if (!strcmp(op, buf)) { *kind = 0; *type = t; *exact = 1; return 1; }
  }
  for (t = 0; t < 4; t++) {
    snprintf(buf, sizeof buf, "srgb8_%s", tonemap_name[t]);
    if (!strcmp(op, buf)) { *kind = 1; *type = t; *exact = 0; return 1; }
  }
  return 0;
}

enum { IW = 256, IH = 256 };

/* --callgrind OP N: the setup, then exactly N calls */
static int callgrind_mode(const char *op, long n) {
  int kind, type, exact;
  if (!parse_op(op, &kind, &type, &exact)) { fprintf(stderr, "bench_film: unknown operation '%s'\n", op); return 2; }
  if (kind == 0) {
    el_film f = make_film(IW, IH, type, exact);
    make_samples(&f);
    run_adds(&f, n);
    el_film_free(&f);
  } else { /* n calls of el_film_to_srgb8 on a 64x64 block (NS pixels): divide by NS for one pixel */
    float *rgb = (float *)malloc(sizeof(float) * 3 * NS);
    unsigned char *out = (unsigned char *)malloc(3 * NS);
    el_film_output_options o;
    long k;
    int i;
    memset(&o, 0, sizeof o);
    o.tonemap = (el_film_tonemap)type;
    for (i = 0; i < 3 * NS; i++) rgb[i] = 4.0f * lcg_f(&g_rng) * lcg_f(&g_rng);
    for (k = 0; k < n; k++) el_film_to_srgb8(rgb, 64, NS / 64, &o, out);
    free(rgb);
    free(out);
  }
  return 0;
}

/* instructions of `self --callgrind op n`, or -1 */
static double callgrind_ir(const char *self, const char *op, long n) {
  char cmd[1024], line[512], file[128];
  FILE *f;
  double ir = -1;
  snprintf(file, sizeof file, "/tmp/bench_film_cg.%ld.%ld", (long)time(NULL) % 100000, n);
  snprintf(cmd, sizeof cmd, "valgrind --tool=callgrind --callgrind-out-file=%s '%s' --callgrind %s %ld >/dev/null 2>&1",
           file, self, op, n);
  if (system(cmd) != 0) return -1;
  f = fopen(file, "r");
  if (!f) return -1;
  while (fgets(line, sizeof line, f))
    if (!strncmp(line, "totals:", 7) || !strncmp(line, "summary:", 8)) ir = atof(strchr(line, ':') + 1);
  fclose(f);
  remove(file);
  return ir;
}

static double instr_per_call(const char *self, const char *op, long n) {
  double a = callgrind_ir(self, op, 0), b = callgrind_ir(self, op, n);
  if (a < 0 || b < 0) return -1;
  return (b - a) / n;
}

/* ---- --csv: the numbers bench/report.py plots (docs/accuracy-vs-time.md) --------------------------
 *   filter,FILTER,WEIGHTS,SPP,ms,alias,detail   a ZW x ZW film of a zone plate 0.5 + 0.5 cos(k r^2) (r from
 *       the centre; local frequency k r / pi cycles per pixel, 1 at the corners: twice the Nyquist
 *       limit), SPP jittered samples per pixel (sqrt(SPP)^2 strata). "alias": RMS of (pixel - 0.5)
 *       where the local frequency exceeds 0.6 cycles/pixel (above Nyquist; a perfect antialiasing filter
 *       leaves flat grey there: what remains is aliasing plus noise). "detail": RMS of (pixel - chart at
 *       the pixel centre) where it is below 0.2 (what the filter blurs away). ms: CPU time of the whole
 *       image (sample positions, chart, el_film_add_sample), the median of 3 interleaved runs.
 *   dither,MODE,ns_per_pixel,pixel_rmse,banding_rmse   el_film_to_srgb8 of a slow linear ramp (0.10 to
 *       0.12 across 1024 pixels): the decoded 8-bit value against the true one, per pixel and after an
 *       8x8 box average (banding: the error one sees from a distance). */
enum { ZW = 96 };
static double zone_k(void) { return 3.14159265358979323846 / (ZW / 2.0 * 1.41421356237309505); }
static float zone(float x, float y) {
  double dx = x - ZW / 2.0, dy = y - ZW / 2.0;
  return (float)(0.5 + 0.5 * cos(zone_k() * (dx * dx + dy * dy)));
}
static void zone_image(int type, int exact, int n, float *out) { /* n x n strata per pixel */
  el_film f = make_film(ZW, ZW, type, exact);
  int b[4], x, y, i, j;
  el_film_sample_bounds(&f, b);
  for (y = b[1]; y < b[3]; y++)
    for (x = b[0]; x < b[2]; x++)
      for (j = 0; j < n; j++)
        for (i = 0; i < n; i++) {
          float px = x + (i + lcg_f(&g_rng)) / n, py = y + (j + lcg_f(&g_rng)) / n, c[3];
          c[0] = c[1] = c[2] = zone(px, py);
          el_film_add_sample(&f, px, py, c, 1.0f);
        }
  el_film_get_rgb(&f, 1.0f, out);
  el_film_free(&f);
}
static double srgb_decode(double v) { return v <= 0.04045 ? v / 12.92 : pow((v + 0.055) / 1.055, 2.4); }
static int csv_mode(int quick) {
  static const int strata_full[5] = {1, 2, 4, 8, 16}, strata_quick[3] = {1, 2, 4};
  const int *strata = quick ? strata_quick : strata_full;
  int ns = quick ? 3 : 5, t, e, k, r, i, reps = 3;
  float *img = (float *)malloc(sizeof(float) * 3 * ZW * ZW);
  printf("kind,a,b,c,d,e,f\n");
  for (k = 0; k < ns; k++) {
    double ms[5][2][3];
    for (r = 0; r < reps; r++)
      for (t = 0; t < 5; t++)
        for (e = 0; e < 2; e++) {
          double t0 = cpu_now();
          zone_image(t, e, strata[k], img);
          ms[t][e][r] = 1e3 * (cpu_now() - t0);
        }
    for (t = 0; t < 5; t++)
      for (e = 0; e < 2; e++) {
        double sa = 0, sd = 0;
        int na = 0, nd = 0;
        g_rng.s = 7u + (unsigned)k; /* the same samples for every filter */
        zone_image(t, e, strata[k], img);
        for (i = 0; i < ZW * ZW; i++) {
          double x = i % ZW + 0.5, y = i / ZW + 0.5, dx = x - ZW / 2.0, dy = y - ZW / 2.0;
          double fr = zone_k() * sqrt(dx * dx + dy * dy) / 3.14159265358979323846, v = img[3 * i + 1];
          if (fr > 0.6) { sa += (v - 0.5) * (v - 0.5); na++; }
          if (fr < 0.2) { double d = v - zone((float)x, (float)y); sd += d * d; nd++; }
        }
        qsort(ms[t][e], 3, sizeof(double), cmp_double);
        printf("filter,%s,%s,%d,%.4f,%.5g,%.5g\n", filter_name[t], e ? "exact" : "table", strata[k] * strata[k],
               ms[t][e][1], sqrt(sa / na), sqrt(sd / nd));
      }
    fflush(stdout);
  }
  free(img);
  { /* dithering */
    enum { RW = 1024, RH = 64 };
    float *ramp = (float *)malloc(sizeof(float) * 3 * RW * RH);
    unsigned char *o8 = (unsigned char *)malloc(3 * RW * RH);
    int d, x, y;
    for (y = 0; y < RH; y++)
      for (x = 0; x < RW; x++) ramp[3 * (y * RW + x)] = ramp[3 * (y * RW + x) + 1] = ramp[3 * (y * RW + x) + 2] =
          0.10f + 0.02f * (x + 0.5f) / RW;
    for (d = 0; d < 2; d++) {
      el_film_output_options o;
      double tt[7], sp = 0, sb = 0;
      int nb = 0;
      memset(&o, 0, sizeof o);
      o.dither = d;
      for (r = 0; r < 7; r++) {
        double t0 = cpu_now();
        el_film_to_srgb8(ramp, RW, RH, &o, o8);
        tt[r] = 1e9 * (cpu_now() - t0) / (RW * RH);
      }
      qsort(tt, 7, sizeof(double), cmp_double);
      for (i = 0; i < RW * RH; i++) {
        double e8 = srgb_decode(o8[3 * i + 1] / 255.0) - ramp[3 * i + 1];
        sp += e8 * e8;
      }
      for (y = 0; y < RH; y += 8)
        for (x = 0; x < RW; x += 8) {
          double a = 0, b = 0;
          int u, v;
          for (v = 0; v < 8; v++)
            for (u = 0; u < 8; u++) {
              a += srgb_decode(o8[3 * ((y + v) * RW + x + u) + 1] / 255.0);
              b += ramp[3 * ((y + v) * RW + x + u) + 1];
            }
          sb += (a - b) * (a - b) / 4096.0;
          nb++;
        }
      printf("dither,%s,%.3f,%.5g,%.5g\n", d ? "TPDF dither" : "round (default)", tt[3], sqrt(sp / (RW * RH)),
             sqrt(sb / nb));
    }
    free(ramp);
    free(o8);
  }
  return 0;
}

int main(int argc, char **argv) {
  int use_cg = 1, t, e, i;
  float *area, *conv[5][2], *noisy;
  if (argc == 4 && !strcmp(argv[1], "--callgrind")) return callgrind_mode(argv[2], atol(argv[3]));
  if (argc >= 2 && !strcmp(argv[1], "--csv")) return csv_mode(argc >= 3 && !strcmp(argv[2], "--quick"));
  if (argc == 2 && !strcmp(argv[1], "--no-callgrind")) use_cg = 0;
  else if (argc != 1) {
    fprintf(stderr, "usage: %s [--no-callgrind | --callgrind OP N]\n", argv[0]);
    return 2;
  }
  if (use_cg && system("valgrind --version >/dev/null 2>&1") != 0) {
    printf("(valgrind not found: no instruction counts)\n");
    use_cg = 0;
  }

  /* the chart's pixel-area average, without film.h */
  area = (float *)malloc(sizeof(float) * 3 * CW * CW);
  noisy = (float *)malloc(sizeof(float) * 3 * CW * CW);
  for (i = 0; i < CW * CW; i++) {
    int x = i % CW, y = i / CW, a, b;
    double s = 0;
    for (b = 0; b < 64; b++)
      for (a = 0; a < 64; a++) s += chart(x + (a + 0.5f) / 64, y + (b + 0.5f) / 64);
    area[3 * i] = area[3 * i + 1] = area[3 * i + 2] = (float)(s / 4096);
  }
  for (t = 0; t < 5; t++)
    for (e = 0; e < 2; e++) {
      conv[t][e] = (float *)malloc(sizeof(float) * 3 * CW * CW);
      converged(t, e, 32, conv[t][e]);
    }

  printf("el_film_add_sample on a %dx%d film (random positions over the sample bounds), and a %dx%d slanted-edge chart\n",
         IW, IH, CW, CW);
  printf("%-9s %-6s %10s %10s %11s %11s %11s %12s\n", "filter", "weights", "ns/sample", "Msample/s", "instr/call",
         "blur RMSE", "noise RMSE", "table-exact");
  for (t = 0; t < 5; t++)
    for (e = 0; e < 2; e++) {
      el_film f = make_film(IW, IH, t, e);
      long n = t == 4 ? 1000000 : 3000000, reps = 0;
      double t0, t1, ir = -1, noise, blur, tdiff = 0;
      char op[64];
      make_samples(&f);
      run_adds(&f, 20000); /* warm up */
      t0 = wall_now();
      do { run_adds(&f, n); reps++; t1 = wall_now(); } while (t1 - t0 < 0.3);
      el_film_free(&f);
      /* noise: 4 random samples per pixel */
      {
        el_film g = make_film(CW, CW, t, e);
        int b[4], k;
        el_film_sample_bounds(&g, b);
        g_rng.s = 99u; /* the same samples for the table and the exact film */
        for (k = 0; k < 4 * (b[2] - b[0]) * (b[3] - b[1]); k++) {
          float px = b[0] + (b[2] - b[0]) * lcg_f(&g_rng), py = b[1] + (b[3] - b[1]) * lcg_f(&g_rng), c[3];
          c[0] = c[1] = c[2] = chart(px, py);
          el_film_add_sample(&g, px, py, c, 1.0f);
        }
        el_film_get_rgb(&g, 1.0f, noisy);
        el_film_free(&g);
      }
      noise = rmse_g(noisy, conv[t][e], CW * CW);
      blur = rmse_g(conv[t][e], area, CW * CW);
      for (i = 0; i < 3 * CW * CW; i++)
        if (fabs(conv[t][0][i] - conv[t][1][i]) > tdiff) tdiff = fabs(conv[t][0][i] - conv[t][1][i]);
      snprintf(op, sizeof op, "add_%s_%s", filter_name[t], e ? "exact" : "table");
      if (use_cg) ir = instr_per_call(argv[0], op, 20000);
      printf("%-9s %-6s %10.1f %10.1f %11.1f %11.4f %11.4f %12.2g\n", filter_name[t], e ? "exact" : "table",
             1e9 * (t1 - t0) / (reps * n), reps * n / (t1 - t0) / 1e6, ir, blur, noise, tdiff);
      fflush(stdout);
    }

  printf("\nel_film_to_srgb8 per pixel (exposure, curve, exact sRGB, round) on a 512x512 image\n");
  printf("%-12s %10s %11s\n", "tone map", "ns/pixel", "instr/pixel");
  {
    enum { PW = 512 };
    float *rgb = (float *)malloc(sizeof(float) * 3 * PW * PW);
    unsigned char *out = (unsigned char *)malloc(3 * PW * PW);
    el_film_output_options o;
    for (i = 0; i < 3 * PW * PW; i++) rgb[i] = 4.0f * lcg_f(&g_rng) * lcg_f(&g_rng);
    for (t = 0; t < 4; t++) {
      double t0, t1, ir = -1;
      long reps = 0;
      char op[64];
      memset(&o, 0, sizeof o);
      o.tonemap = (el_film_tonemap)t;
      t0 = wall_now();
      do { el_film_to_srgb8(rgb, PW, PW, &o, out); reps++; t1 = wall_now(); } while (t1 - t0 < 0.2);
      snprintf(op, sizeof op, "srgb8_%s", tonemap_name[t]);
      if (use_cg) ir = instr_per_call(argv[0], op, 100) / NS;
      printf("%-12s %10.2f %11.1f\n", tonemap_name[t], 1e9 * (t1 - t0) / ((double)reps * PW * PW), ir);
    }
    free(rgb);
    free(out);
  }
  for (t = 0; t < 5; t++) { free(conv[t][0]); free(conv[t][1]); }
  free(area);
  free(noisy);
  return 0;
}
