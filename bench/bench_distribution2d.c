/* bench_distribution2d.c: what each way of sampling a 2D piecewise-constant distribution costs (build
 * time, bytes, samples per second, instructions per sample and per pdf) beside what it gets right
 * (positive bins that can never be sampled, and the share of the integral they hold: a bias).
 *
 *   bench_distribution2d                  the tables below (runs itself under callgrind if valgrind exists)
 *   bench_distribution2d --no-callgrind   timing columns only
 *   bench_distribution2d --quick          only 1024x512 and 2048x1024 (and no callgrind)
 *   bench_distribution2d --callgrind OP N [W H]   only N calls of OP after the setup, on a W x H distribution
 *                                         (default 4096 2048). OP: pbrt_sample pbrt_pdf cdf_sample
 *                                         guide_sample guide0_sample alias_sample pdf loop
 *
 * Instructions per call, by hand: valgrind --tool=callgrind --callgrind-out-file=cg.N bench_distribution2d
 * --callgrind guide_sample N for N = 0 and N = 200000; (Ir(N) - Ir(0)) / N, Ir from the "totals:" line.
 * The table subtracts the benchmark loop's own instructions (reading a precomputed (u0,u1) pair and
 * summing the outputs), measured the same way with OP loop.
 * Measured (gcc 12 -O3, loop subtracted): guide s=2 106 instructions per 2D sample at 1024x512 to
 * 4096x2048 and 129 at 4000x2000 (123 and 148 before crowded guide cells were flagged in the table),
 * alias 125; tutorials/05-appendix-fast-paths.md (section A2) has the full table.
 *
 * Methods, all on the same input:
 *  - pbrt-v3: Distribution1D / Distribution2D (src/core/sampling.h) as the course ports them
 *    (examples/pbrtv3/sampling.h): float func and float CDF per row, FindInterval's binary search,
 *    pdf = func / funcInt. The "before".
 *  - CDF: el_distribution2d_sample, integer CDF, branch-free binary search.
 *  - guide s: el_distribution2d_fast with a guide table of next_pow2(n) / 2^s cells per row (s = 2 is
 *    the default: 1 byte per bin; s = 0: 4 bytes per bin). Same points as CDF (stratification kept).
 *  - alias: el_distribution2d_fast with the exact integer alias table (8 bytes per bin; stratification lost).
 * The input is an environment-map-like density: a sky gradient with texture noise, times sin(theta), and
 * a sun of 3e4 covering a few texels (like ../shared/envmaps/city), generated in code at each size.
 * Stratification: the RMSE of an integral estimated with jittered (16x16) and with independent u, for
 * the guide table (CDF inversion) and the alias table: what keeping stratification buys.
 * Timing: 2^20 precomputed random (u0, u1) pairs, looped, one thread, gcc -O3; every time is the best of
 * three runs (the machine may be shared).
 */
#define _POSIX_C_SOURCE 199309L /* clock_gettime */
#define EL_DISTRIBUTION2D_IMPLEMENTATION
#include "distribution2d.h"
#include "../examples/pbrtv3/sampling.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bench_common.h" /* wall_now, hash32 */

/* ---- the input ---- */
static float *make_map(int nu, int nv) {
  float *f = (float *)malloc((size_t)nu * nv * sizeof(float));
  int u, v;
  const float su = 0.3f, sv = 0.3f, r = 0.004f; /* sun position and radius (in u units) */
  for (v = 0; v < nv; ++v) {
    float vv = (v + 0.5f) / nv, st = sinf(3.14159265f * vv);
    float sky = vv < 0.5f ? 0.3f + 1.4f * vv : 0.05f; /* bright sky above, dark ground below */
    for (u = 0; u < nu; ++u) {
      float uu = (u + 0.5f) / nu, du = uu - su, dv = (vv - sv) * 0.5f;
      float noise = (float)(hash32((uint32_t)(v * nu + u)) >> 8) * (1.0f / 16777216.0f);
      float x = sky * (0.6f + 0.8f * noise);
      if (du * du + dv * dv < r * r) x = 3e4f;
      f[(size_t)v * nu + u] = x * st;
    }
  }
  return f;
}

/* ---- pbrt-v3 Distribution1D / Distribution2D: the course's plain port (examples/pbrtv3/sampling.h) ---- */
/* ---- operations ---- */
enum { NP = 1 << 20 };
static float *g_u;
static void make_u(void) {
  int i;
  uint32_t s = 12345u;
  g_u = (float *)malloc(2 * NP * sizeof(float));
  for (i = 0; i < 2 * NP; ++i) { s = s * 1664525u + 1013904223u; g_u[i] = (float)(hash32(s) >> 8) * (1.0f / 16777216.0f); }
}

enum { M_PBRT, M_CDF, M_GUIDE0, M_GUIDE2, M_GUIDE4, M_ALIAS, M_COUNT };
static const char *method_name[M_COUNT] = {"pbrt-v3", "CDF", "guide s=0", "guide s=2", "guide s=4", "alias"};

typedef struct {
  pbrt_Distribution2D pb;
  el_distribution2d d;
  el_distribution2d_fast fast;
  int method;
} ctx;

/* build the method's own structures; c->d must already hold the CDF for the fast methods */
static int build(ctx *c, int method, const float *f, int nu, int nv) {
  el_distribution_fast_options fo;
  c->method = method;
  memset(&fo, 0, sizeof fo);
  switch (method) {
  case M_PBRT: return pbrt_Distribution2D_init(&c->pb, f, nu, nv) != 0;
  case M_CDF: return el_distribution2d_init(&c->d, f, nu, nv, NULL) != EL_SUCCESS;
  case M_GUIDE0: fo.guide_shrink_log2 = -1; break; /* negative: as many cells as the next power of two */
  case M_GUIDE2: fo.guide_shrink_log2 = 2; break;
  case M_GUIDE4: fo.guide_shrink_log2 = 4; break;
  case M_ALIAS: fo.method = EL_DISTRIBUTION_FAST_ALIAS; break;
  }
  return el_distribution2d_fast_init_ex(&c->fast, &c->d, &fo) != EL_SUCCESS;
}
static void unbuild(ctx *c) {
  if (c->method == M_PBRT) pbrt_Distribution2D_free(&c->pb);
  else if (c->method == M_CDF) el_distribution2d_free(&c->d);
  else el_distribution2d_fast_free(&c->fast);
}
static size_t bytes(const ctx *c) {
  if (c->method == M_PBRT) return pbrt_Distribution2D_bytes(&c->pb);
  if (c->method == M_CDF) return el_distribution2d_bytes(&c->d);
  return el_distribution2d_bytes(&c->d) + el_distribution2d_fast_bytes(&c->fast);
}
static double run_samples(const ctx *c, long n) {
  double acc = 0;
  long k;
  float x, y, p;
  /* one loop per method, so that the loop itself costs the same few instructions for each */
  if (c->method == M_PBRT)
    for (k = 0; k < n; ++k) {
      const float *u = g_u + 2 * (k & (NP - 1));
      float uv[2];
      pbrt_Distribution2D_SampleContinuous(&c->pb, u, uv, &p);
      acc += uv[0] + uv[1] + p;
    }
  else if (c->method == M_CDF)
    for (k = 0; k < n; ++k) {
      const float *u = g_u + 2 * (k & (NP - 1));
      el_distribution2d_sample(&c->d, u[0], u[1], &x, &y, &p);
      acc += x + y + p;
    }
  else
    for (k = 0; k < n; ++k) {
      const float *u = g_u + 2 * (k & (NP - 1));
      el_distribution2d_fast_sample(&c->fast, u[0], u[1], &x, &y, &p);
      acc += x + y + p;
    }
  return acc;
}
/* the loop alone (same loads and sums, no sampling): subtracted from the instruction counts */
static double run_baseline(long n) {
  double acc = 0;
  long k;
  for (k = 0; k < n; ++k) {
    const float *u = g_u + 2 * (k & (NP - 1));
    float x = u[0] * 0.5f, y = u[1] * 0.5f, p = u[0] + u[1];
    acc += x + y + p;
  }
  return acc;
}
static double run_pdfs(const ctx *c, long n) {
  double acc = 0;
  long k;
  if (c->method == M_PBRT)
    for (k = 0; k < n; ++k) {
      const float *u = g_u + 2 * (k & (NP - 1));
      acc += pbrt_Distribution2D_Pdf(&c->pb, u);
    }
  else
    for (k = 0; k < n; ++k) {
      const float *u = g_u + 2 * (k & (NP - 1));
      acc += el_distribution2d_pdf(&c->d, u[0], u[1]);
    }
  return acc;
}

/* ---- stratification: does a sampler keep the stratification of jittered u? ----
 * Estimate I = integral of f * h over [0,1]^2 with samples from the distribution of f: the estimator
 * f(x) h(x) / pdf(x), h(u,v) = 1 + 0.9 sin(2 pi u) sin(pi v) (smooth). The reference is exact: f is
 * piecewise constant and h integrates in closed form over each bin. RMSE over 200 estimates of 256
 * samples each, u jittered on a 16x16 grid or independent. */
static double h_fun(float u, float v) { return 1.0 + 0.9 * sin(6.283185307179586 * u) * sin(3.141592653589793 * v); }
static void stratification_table(void) {
  enum { NU = 1024, NV = 512, T = 200, G = 16 };
  float *f = make_map(NU, NV);
  el_distribution2d d;
  el_distribution2d_fast fg, fa;
  el_distribution_fast_options fo;
  double ref = 0, *su = (double *)malloc(NU * sizeof(double)), *sv = (double *)malloc(NV * sizeof(double));
  int iu, iv, method, jit, t;
  uint32_t rs = 777u;
  const double pi = 3.141592653589793;
  for (iu = 0; iu < NU; ++iu) su[iu] = (cos(2 * pi * iu / NU) - cos(2 * pi * (iu + 1) / NU)) / (2 * pi);
  for (iv = 0; iv < NV; ++iv) sv[iv] = (cos(pi * iv / NV) - cos(pi * (iv + 1) / NV)) / pi;
  for (iv = 0; iv < NV; ++iv)
    for (iu = 0; iu < NU; ++iu) ref += f[(size_t)iv * NU + iu] * (1.0 / ((double)NU * NV) + 0.9 * su[iu] * sv[iv]);
  el_distribution2d_init(&d, f, NU, NV, NULL);
  el_distribution2d_fast_init(&fg, &d);
  memset(&fo, 0, sizeof fo);
  fo.method = EL_DISTRIBUTION_FAST_ALIAS;
  el_distribution2d_fast_init_ex(&fa, &d, &fo);
  printf("stratification (1024x512 map, 256 samples per estimate, 200 estimates; relative RMSE of the integral of f*h):\n");
  printf("  %-26s %12s %12s\n", "sampler", "jittered u", "random u");
  for (method = 0; method < 2; ++method) {
    double rmse[2];
    for (jit = 0; jit < 2; ++jit) {
      double se = 0;
      for (t = 0; t < T; ++t) {
        double est = 0;
        int i, j;
        for (j = 0; j < G; ++j)
          for (i = 0; i < G; ++i) {
            float u0, u1, x, y, p;
            rs = rs * 1664525u + 1013904223u; u0 = (float)(hash32(rs) >> 8) * (1.0f / 16777216.0f);
            rs = rs * 1664525u + 1013904223u; u1 = (float)(hash32(rs) >> 8) * (1.0f / 16777216.0f);
            if (jit == 0) { u0 = (i + u0) / G; u1 = (j + u1) / G; if (u0 >= 1) u0 = 0.99999994f; if (u1 >= 1) u1 = 0.99999994f; }
            el_distribution2d_fast_sample(method == 0 ? &fg : &fa, u0, u1, &x, &y, &p);
            iu = el_distribution2d__bin(x, 0.0f, d.u_scale, NU);
            iv = el_distribution2d__bin(y, 0.0f, d.v_scale, NV);
            est += f[(size_t)iv * NU + iu] * h_fun(x, y) / p;
          }
        est /= G * G;
        se += (est - ref) * (est - ref);
      }
      rmse[jit] = sqrt(se / T) / ref;
    }
    printf("  %-26s %12.3g %12.3g\n", method == 0 ? "guide (= CDF inversion)" : "alias", rmse[0], rmse[1]);
  }
  printf("\n");
  el_distribution2d_fast_free(&fg); el_distribution2d_fast_free(&fa); el_distribution2d_free(&d);
  free(su); free(sv); free(f);
}

/* --callgrind OP N [W H] */
static int callgrind_mode(const char *op, long n, int nu, int nv) {
  static ctx c;
  float *f;
  int method, pdf = 0;
  volatile double sink;
  make_u();
  if (!strcmp(op, "loop")) { sink = run_baseline(n); (void)sink; return 0; }
  f = make_map(nu, nv);
  if (!strcmp(op, "pbrt_sample")) method = M_PBRT;
  else if (!strcmp(op, "pbrt_pdf")) { method = M_PBRT; pdf = 1; }
  else if (!strcmp(op, "cdf_sample")) method = M_CDF;
  else if (!strcmp(op, "pdf")) { method = M_CDF; pdf = 1; }
  else if (!strcmp(op, "guide_sample")) method = M_GUIDE2;
  else if (!strcmp(op, "guide0_sample")) method = M_GUIDE0;
  else if (!strcmp(op, "alias_sample")) method = M_ALIAS;
  else { fprintf(stderr, "unknown OP %s\n", op); return 2; }
  if (method != M_PBRT && build(&c, M_CDF, f, nu, nv)) { fprintf(stderr, "build failed\n"); return 1; }
  if (method != M_PBRT && method != M_CDF && build(&c, method, f, nu, nv)) { fprintf(stderr, "build failed\n"); return 1; }
  if (method == M_PBRT) build(&c, M_PBRT, f, nu, nv);
  sink = pdf ? run_pdfs(&c, n) : run_samples(&c, n);
  (void)sink;
  return 0;
}

static double callgrind_ir(const char *self, const char *op, long n, int nu, int nv) {
  char cmd[1024], line[512], file[128];
  FILE *fp;
  double ir = -1;
  snprintf(file, sizeof file, "/tmp/bench_distribution2d_cg.%ld.%ld", (long)time(NULL) % 100000, n);
  snprintf(cmd, sizeof cmd, "valgrind --tool=callgrind --callgrind-out-file=%s '%s' --callgrind %s %ld %d %d >/dev/null 2>&1", file, self, op, n, nu, nv);
  if (system(cmd) != 0) return -1;
  fp = fopen(file, "r");
  if (!fp) return -1;
  while (fgets(line, sizeof line, fp))
    if (!strncmp(line, "totals:", 7) || !strncmp(line, "summary:", 8)) ir = atof(strchr(line, ':') + 1);
  fclose(fp);
  remove(file);
  return ir;
}
static double instr_per_call(const char *self, const char *op, long n, int nu, int nv) {
  double a = callgrind_ir(self, op, 0, nu, nv), b = callgrind_ir(self, op, n, nu, nv);
  return (a < 0 || b < 0) ? -1 : (b - a) / n;
}

int main(int argc, char **argv) {
  int sizes[4][2] = {{1024, 512}, {2048, 1024}, {4096, 2048}, {8192, 4096}}, nsizes = 4, s, m, use_cg = 1;
  if (argc >= 4 && !strcmp(argv[1], "--callgrind"))
    return callgrind_mode(argv[2], atol(argv[3]), argc >= 6 ? atoi(argv[4]) : 4096, argc >= 6 ? atoi(argv[5]) : 2048);
  if (argc == 2 && !strcmp(argv[1], "--no-callgrind")) use_cg = 0;
  else if (argc == 2 && !strcmp(argv[1], "--quick")) { use_cg = 0; nsizes = 2; }
  else if (argc != 1) { fprintf(stderr, "usage: %s [--no-callgrind | --quick | --callgrind OP N [W H]]\n", argv[0]); return 2; }
  if (use_cg && system("valgrind --version >/dev/null 2>&1") != 0) { printf("(valgrind not found: no instruction counts)\n"); use_cg = 0; }
  make_u();
  printf("2D piecewise-constant sampling: env-map-like density (sky * sin(theta) + a 3e4 sun), one thread, -O3\n");
  printf("build = construction of that method's structures (fast samplers: on top of the CDF's build)\n\n");
  stratification_table();
  for (s = 0; s < nsizes; ++s) {
    int nu = sizes[s][0], nv = sizes[s][1];
    float *f = make_map(nu, nv);
    static ctx base, c;
    double unreach = 0, share = 0, cdf_ms;
    printf("%d x %d (%.1f M bins)\n", nu, nv, (double)nu * nv / 1e6);
    printf("  %-10s %9s %9s %11s %11s %s\n", "method", "build ms", "MB", "sample M/s", "pdf M/s", "unreachable positive bins (their share of the integral)");
    {
      /* best of 3 builds: the machine is shared */
      int rep;
      cdf_ms = 1e30;
      for (rep = 0; rep < 3; ++rep) {
        double t0 = wall_now();
        if (rep) el_distribution2d_free(&base.d);
        build(&base, M_CDF, f, nu, nv);
        if ((wall_now() - t0) * 1e3 < cdf_ms) cdf_ms = (wall_now() - t0) * 1e3;
      }
    }
    for (m = 0; m < M_COUNT; ++m) {
      double build_ms = 1e30, ts = 1e30, tp = 1e30, sink = 0;
      long ns = 2000000, np = 4000000;
      int rep;
      for (rep = 0; rep < 3; ++rep) { /* best of 3 for every timing */
        double t0;
        c = base;
        t0 = wall_now();
        if (m != M_CDF) build(&c, m, f, nu, nv);
        if ((wall_now() - t0) * 1e3 < build_ms) build_ms = (wall_now() - t0) * 1e3;
        if (rep < 2 && m != M_CDF) unbuild(&c);
      }
      if (m == M_CDF) build_ms = cdf_ms;
      if (m == M_PBRT) pbrt_Distribution2D_unreachable(&c.pb, &unreach, &share);
      sink += run_samples(&c, 100000); /* warm up */
      for (rep = 0; rep < 3; ++rep) {
        double t0 = wall_now();
        sink += run_samples(&c, ns);
        if (wall_now() - t0 < ts) ts = wall_now() - t0;
        t0 = wall_now();
        sink += (m <= M_CDF) ? run_pdfs(&c, np) : 0;
        if (wall_now() - t0 < tp) tp = wall_now() - t0;
      }
      if (m <= M_CDF)
        printf("  %-10s %9.1f %9.1f %11.1f %11.1f   ", method_name[m], build_ms, bytes(&c) / 1048576.0, ns / ts / 1e6, np / tp / 1e6);
      else
        printf("  %-10s %9.1f %9.1f %11.1f %11s   ", method_name[m], build_ms, bytes(&c) / 1048576.0, ns / ts / 1e6, "(= CDF)");
      if (m == M_PBRT) printf("%.0f (%.2g)\n", unreach, share);
      else printf("0 (by construction; tested)\n");
      if (sink == 12345.678) printf(" ");
      if (m != M_CDF) unbuild(&c);
    }
    el_distribution2d_free(&base.d);
    free(f);
    printf("\n");
  }
  if (use_cg) {
    const char *ops[7] = {"pbrt_sample", "cdf_sample", "guide0_sample", "guide_sample", "alias_sample", "pbrt_pdf", "pdf"};
    const char *what[7] = {"pbrt-v3 sample", "CDF sample", "guide s=0 sample", "guide s=2 sample (default fast)", "alias sample", "pbrt-v3 pdf", "pdf (all methods)"};
    int cs[4][2] = {{1024, 512}, {2048, 1024}, {4096, 2048}, {4000, 2000}}, i, j;
    double loop = instr_per_call(argv[0], "loop", 200000, 16, 16);
    printf("instructions per call (callgrind, 200000 calls; the benchmark loop's own %.1f per iteration,\n"
           "measured with OP loop, already subtracted; 8192 x 4096 is left out: its setup under valgrind takes\n"
           "minutes; 4000 x 2000 shows a size that is not a power of two, one bin check more per axis):\n", loop);
    printf("  %-34s", "");
    for (j = 0; j < 4; ++j) printf(" %11dx%d", cs[j][0], cs[j][1]);
    printf("\n");
    for (i = 0; i < 7; ++i) {
      printf("  %-34s", what[i]);
      for (j = 0; j < 4; ++j) printf(" %16.1f", instr_per_call(argv[0], ops[i], 200000, cs[j][0], cs[j][1]) - loop);
      printf("\n");
      fflush(stdout);
    }
  }
  return 0;
}
