/* bench_mipmap: what each MIP-map filter's accuracy costs in time, and how we compare with pbrt-v3.
 *
 * For a 2048x1024 RGB image (power of two) and a 2000x1000 RGB image (resampled to 2048x1024 with
 * pbrt's Lanczos weights) it prints:
 *   - build time and bytes (level 0 only, as after el_mipmap_init; and the whole pyramid);
 *   - single-thread lookups per second for point, bilinear, trilinear, EWA (anisotropy 8 and 64) with
 *     random coordinates and random footprints (lengths log-uniform in [1e-4, 0.1], anisotropy ratio
 *     uniform in [1, 16], random orientation);
 *   - each filter's error against a supersampled reference footprint (1024 stratified samples of
 *     pbrt's truncated Gaussian exp(-2 r^2) - exp(-2) over the ellipse spanned by the two
 *     differentials, each a point lookup of level 0), on a texture with detail at every scale;
 *   - the largest difference between our levels / lookups and the course's literal C port of
 *     pbrt-v3's MIPMap (examples/pbrtv3/mipmap.h: BlockedArray storage, Texel() with Mod/Clamp,
 *     triangle(), both Lookup()s, EWA(), transcribed line by line from src/core/mipmap.h). That port is
 *     how "equal to pbrt-v3 to float precision" is measured: same inputs, compare outputs
 *     (tests/test_tutorial_mipmap.c checks the same claims).
 *
 * Instruction counts (stable on a noisy machine), as DEVELOPERS.md describes:
 *     valgrind --tool=callgrind --callgrind-out-file=/dev/null build/bin/bench_mipmap --callgrind OP N
 * prints nothing but a checksum; Ir(N) - Ir(0), divided by N, is the cost of one OP. OPs:
 *     build2048 build2000 build400 point bilinear trilinear ewa8 ewa64
 *     pbrt_build2048 pbrt_build2000 pbrt_build400 pbrt_trilinear pbrt_ewa8     (the literal pbrt-v3 port)
 * (build400: the course's 400x235 test image of chapter 1, resampled to 512x256.)
 * `bench_mipmap --instructions` runs those valgrind pairs itself (when valgrind is on the PATH) and
 * prints the table. `bench_mipmap --csv [--quick]` prints the CSV that bench/report.py plots (see
 * csv_mode). Builds count init + el_mipmap_build_levels (every level), like pbrt's constructor.
 * Lookups use the same random inputs as the timing table. Last measured (gcc 12 -O3, x86-64): point 170,
 * bilinear 166, trilinear 225, ewa8 1,462, ewa64 1,632 instructions per lookup; the pbrt-v3 port 579
 * (trilinear) and 2,928 (ewa8); builds 26.7 M and 171.8 M against the port's 91.8 M and 545.7 M.
 */
#define _POSIX_C_SOURCE 200809L /* clock_gettime, popen */
#define EL_IMPLEMENTATION
#include "mipmap.h"
#include "picture.h" /* el_test_image: the course's 400x235 test image (examples/common) */

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

/* The literal port of pbrt-v3's MIPMap<RGBSpectrum> (src/core/mipmap.h, with the trilinear fix of its
 * commit aaa552a) is the course's, examples/pbrtv3/mipmap.h, shared with chapter 2's example and with
 * tests/test_tutorial_mipmap.c (which checks it against mipmap.h). Names follow pbrt. */
#include "../examples/pbrtv3/mipmap.h"

/* ---------------------------------------------------------------------------------------------
 * Inputs
 * --------------------------------------------------------------------------------------------- */
static unsigned long long rng_state = 0x9E3779B97F4A7C15ull;
static float rnd(void) { /* xorshift64*, uniform in [0, 1) */
  rng_state ^= rng_state >> 12;
  rng_state ^= rng_state << 25;
  rng_state ^= rng_state >> 27;
  return (float)((rng_state * 2685821657736338717ull) >> 40) * (1.0f / 16777216.0f);
}
/* A texture with detail at every scale: a checkerboard whose frequency rises along u, over a colour
 * ramp, plus a fine diagonal stripe pattern. */
static float *make_image(int w, int h) {
  float *p = (float *)malloc(sizeof(float) * 3 * (size_t)w * (size_t)h);
  int x, y;
  for (y = 0; y < h; ++y)
    for (x = 0; x < w; ++x) {
      float u = (x + 0.5f) / w, v = (y + 0.5f) / h;
      float f = 4.0f + 252.0f * u * u;
      int ch = ((int)(u * f) + (int)(v * f * 0.5f)) & 1;
      float stripe = 0.5f + 0.5f * sinf(0.9f * (float)(x + 2 * y));
      float *o = p + 3 * ((size_t)y * w + x);
      o[0] = (ch ? 0.9f : 0.1f) * (0.3f + 0.7f * u) + 0.1f * stripe;
      o[1] = (ch ? 0.8f : 0.15f) * (0.3f + 0.7f * v) + 0.1f * stripe;
      o[2] = (ch ? 0.7f : 0.2f) * (1.0f - 0.6f * u);
    }
  return p;
}
typedef struct query {
  float s, t, d0s, d0t, d1s, d1t, width;
} query;
static query *make_queries(int n) {
  query *q = (query *)malloc(sizeof(query) * (size_t)n);
  int i;
  for (i = 0; i < n; ++i) {
    float len = powf(10.0f, -4.0f + 3.0f * rnd()), ratio = 1.0f + 15.0f * rnd();
    float ang = 6.2831853f * rnd();
    q[i].s = rnd();
    q[i].t = rnd();
    q[i].d0s = len * cosf(ang);
    q[i].d0t = len * sinf(ang);
    q[i].d1s = -len / ratio * sinf(ang);
    q[i].d1t = len / ratio * cosf(ang);
    q[i].width = 2 * len; /* what pbrt's trilinear Lookup(st, dst0, dst1) would pass */
  }
  return q;
}

/* The port on a row-major RGB float image: pbrt's defaults (EWA, max anisotropy 8, Repeat). */
static void pbrt_init(pbrt_MIPMap *pm, int w, int h, const float *img) {
  pbrt_MIPMap_init(pm, pbrt_Point2i_make(w, h), (const pbrt_RGBSpectrum *)img, 0, 8.f, pbrt_ImageWrap_Repeat);
}

/* wall_now; cpu_now: the thread's CPU time (a core taken by another process's work does not count: the
 * machine is shared); median */
#include "bench_common.h"

enum { OP_POINT, OP_BILINEAR, OP_TRILINEAR, OP_EWA, OP_PBRT_TRILINEAR, OP_PBRT_EWA };
static float run_op(int op, const el_mipmap *m, const pbrt_MIPMap *pm, const query *q, int n) {
  float acc = 0, o[4];
  int i;
  /* one tight loop for the operations whose instruction counts have targets */
  if (op == OP_TRILINEAR) {
    for (i = 0; i < n; ++i) {
      el_mipmap_lookup(m, q[i].s, q[i].t, q[i].width, o);
      acc += o[0];
    }
    return acc;
  }
  if (op == OP_EWA) {
    for (i = 0; i < n; ++i) {
      el_mipmap_lookup_differentials(m, q[i].s, q[i].t, q[i].d0s, q[i].d0t, q[i].d1s, q[i].d1t, o);
      acc += o[0];
    }
    return acc;
  }
  for (i = 0; i < n; ++i) {
    const query *k = q + i;
    switch (op) {
    case OP_POINT: el_mipmap_lookup_filtered(m, EL_MIPMAP_FILTER_POINT, k->s, k->t, k->width, o); break;
    case OP_BILINEAR: el_mipmap_lookup_filtered(m, EL_MIPMAP_FILTER_BILINEAR, k->s, k->t, k->width, o); break;
    case OP_TRILINEAR: el_mipmap_lookup(m, k->s, k->t, k->width, o); break;
    case OP_EWA: el_mipmap_lookup_differentials(m, k->s, k->t, k->d0s, k->d0t, k->d1s, k->d1t, o); break;
    case OP_PBRT_TRILINEAR: {
      pbrt_RGBSpectrum r = pbrt_MIPMap_Lookup(pm, pbrt_Point2f_make(k->s, k->t), k->width);
      o[0] = r.c[0];
      break;
    }
    default: {
      pbrt_RGBSpectrum r = pbrt_MIPMap_Lookup_dst(pm, pbrt_Point2f_make(k->s, k->t), pbrt_Vector2f_make(k->d0s, k->d0t),
                                                  pbrt_Vector2f_make(k->d1s, k->d1t));
      o[0] = r.c[0];
    }
    }
    acc += o[0];
  }
  return acc;
}

/* The reference: pbrt's filter shape (exp(-2 r^2) - exp(-2), r < 1, over the ellipse spanned by the
 * two differentials, after the same anisotropy clamp) integrated with 32x32 stratified samples, each
 * a point lookup of level 0 (texels are constant over their square). */
static void reference(const el_mipmap *m, const query *k, float maxaniso, float *out) {
  double sum[3] = {0, 0, 0}, sw = 0;
  float d0s = k->d0s, d0t = k->d0t, d1s = k->d1s, d1t = k->d1t;
  float l0 = sqrtf(d0s * d0s + d0t * d0t), l1 = sqrtf(d1s * d1s + d1t * d1t);
  int i, j, c;
  if (l0 < l1) {
    float a = d0s, b = d0t, t = l0;
    d0s = d1s; d0t = d1t; d1s = a; d1t = b; l0 = l1; l1 = t;
  }
  if (l1 * maxaniso < l0 && l1 > 0) {
    float sc = l0 / (l1 * maxaniso);
    d1s *= sc;
    d1t *= sc;
  }
  for (j = 0; j < 32; ++j)
    for (i = 0; i < 32; ++i) {
      float u = -1 + 2 * (i + rnd()) / 32, v = -1 + 2 * (j + rnd()) / 32, r2 = u * u + v * v, w, o[4];
      if (r2 >= 1) continue;
      w = expf(-2 * r2) - expf(-2.0f);
      el_mipmap_point(m, 0, k->s + u * d0s + v * d1s, k->t + u * d0t + v * d1t, o);
      for (c = 0; c < 3; ++c) sum[c] += w * o[c];
      sw += w;
    }
  for (c = 0; c < 3; ++c) out[c] = (float)(sum[c] / sw);
}

static int build_ours(el_mipmap *m, const float *img, int w, int h, float aniso) {
  el_mipmap_options o;
  memset(&o, 0, sizeof o);
  o.max_anisotropy = aniso;
  if (el_mipmap_init(m, img, w, h, 3, &o) != EL_SUCCESS) return 0;
  return el_mipmap_build_levels(m) == EL_SUCCESS;
}

#define CG_POOL 20000
static int callgrind_mode(const char *op, int n) {
  float *img2048 = NULL, *img2000 = NULL, *img400 = NULL, acc = 0;
  el_mipmap m;
  pbrt_MIPMap pm;
  query *q;
  int i, kind = -1, need_ours = 0, need_pbrt = 0;
  float aniso = 8;
  memset(&m, 0, sizeof m);
  memset(&pm, 0, sizeof pm);
  if (!strcmp(op, "build2048") || !strcmp(op, "pbrt_build2048")) img2048 = make_image(2048, 1024);
  else if (!strcmp(op, "build2000") || !strcmp(op, "pbrt_build2000")) img2000 = make_image(2000, 1000);
  else if (!strcmp(op, "build400") || !strcmp(op, "pbrt_build400")) {
    img400 = (float *)malloc(sizeof(float) * 3 * 400 * 235);
    el_test_image(img400, 400, 235);
  }
  else if (!strcmp(op, "point")) { kind = OP_POINT; need_ours = 1; }
  else if (!strcmp(op, "bilinear")) { kind = OP_BILINEAR; need_ours = 1; }
  else if (!strcmp(op, "trilinear")) { kind = OP_TRILINEAR; need_ours = 1; }
  else if (!strcmp(op, "ewa8")) { kind = OP_EWA; need_ours = 1; }
  else if (!strcmp(op, "ewa64")) { kind = OP_EWA; need_ours = 1; aniso = 64; }
  else if (!strcmp(op, "pbrt_trilinear")) { kind = OP_PBRT_TRILINEAR; need_pbrt = 1; }
  else if (!strcmp(op, "pbrt_ewa8")) { kind = OP_PBRT_EWA; need_pbrt = 1; }
  else {
    fprintf(stderr, "bench_mipmap: unknown operation '%s'\n", op);
    return 2;
  }
  if (img2048 || img2000 || img400) {
    int w = img2048 ? 2048 : (img2000 ? 2000 : 400), h = img2048 ? 1024 : (img2000 ? 1000 : 235);
    const float *img = img2048 ? img2048 : (img2000 ? img2000 : img400);
    for (i = 0; i < n; ++i) {
      if (!strncmp(op, "pbrt_", 5)) {
        pbrt_init(&pm, w, h, img);
        acc += pbrt_BlockedArray_at(pm.pyramid[3], 1, 1)->c[0];
        pbrt_MIPMap_free(&pm);
      } else {
        if (!build_ours(&m, img, w, h, 8)) return 1;
        acc += el_mipmap_level_data(&m, 3)[3];
        el_mipmap_free(&m);
      }
    }
    free(img2048);
    free(img2000);
    free(img400);
    printf("checksum %g\n", acc);
    return 0;
  }
  img2048 = make_image(2048, 1024);
  q = make_queries(CG_POOL); /* the same inputs for every N, so that Ir(N) - Ir(0) is the lookups only */
  if (need_ours && !build_ours(&m, img2048, 2048, 1024, aniso)) return 1;
  if (need_pbrt) pbrt_init(&pm, 2048, 1024, img2048);
  for (i = 0; i < n; i += CG_POOL) acc += run_op(kind, &m, &pm, q, n - i < CG_POOL ? n - i : CG_POOL);
  printf("checksum %g\n", acc);
  el_mipmap_free(&m);
  if (need_pbrt) pbrt_MIPMap_free(&pm);
  free(q);
  free(img2048);
  return 0;
}

/* Runs valgrind on ourselves for N and 0 calls and returns (Ir(N) - Ir(0)) / N, or -1. */
static double instructions(const char *self, const char *op, int n) {
  char cmd[1024];
  double ir[2];
  int k;
  for (k = 0; k < 2; ++k) {
    FILE *f;
    char line[512];
    ir[k] = -1;
    snprintf(cmd, sizeof cmd,
             "valgrind --tool=callgrind --callgrind-out-file=/dev/null %s --callgrind %s %d 2>&1", self,
             op, k == 0 ? n : 0);
    f = popen(cmd, "r");
    if (!f) return -1;
    while (fgets(line, sizeof line, f)) {
      char *p = strstr(line, "Collected : ");
      if (p) ir[k] = atof(p + 12);
    }
    pclose(f);
    if (ir[k] < 0) return -1;
  }
  return (ir[0] - ir[1]) / n;
}

static int instructions_table(const char *self) {
  static const char *ops[] = {"build2048", "build2000", "build400", "point", "bilinear", "trilinear", "ewa8", "ewa64",
                              "pbrt_build2048", "pbrt_build2000", "pbrt_build400", "pbrt_trilinear", "pbrt_ewa8"};
  static const int ns[] = {2, 2, 5, 20000, 20000, 20000, 20000, 20000, 1, 1, 5, 20000, 20000};
  static const char *target[] = {"<= 135 M", "<= 388 M", "", "", "", "<= 250", "<= 1,500", "", "(269 M)",
                                 "(776 M)", "", "(~820)", "(~3,700)"};
  int i;
  printf("\nInstructions per operation (valgrind --tool=callgrind, (Ir(N) - Ir(0)) / N):\n");
  printf("| operation | N | instructions | target (pbrt-v3 figure in parentheses) |\n|---|---|---|---|\n");
  for (i = 0; i < (int)(sizeof ops / sizeof ops[0]); ++i) {
    double v = instructions(self, ops[i], ns[i]);
    if (v < 0) {
      printf("valgrind not available: skipped\n");
      return 0;
    }
    if (!strncmp(ops[i], "build", 5) || !strncmp(ops[i], "pbrt_build", 10))
      printf("| %s | %d | %.1f M | %s |\n", ops[i], ns[i], v / 1e6, target[i]);
    else
      printf("| %s | %d | %.0f | %s |\n", ops[i], ns[i], v, target[i]);
    fflush(stdout);
  }
  return 0;
}

static float rel_diff(const float *a, const float *b, int n) {
  float d = 0;
  int i;
  for (i = 0; i < n; ++i) {
    float e = fabsf(a[i] - b[i]) / (fabsf(b[i]) > 1e-3f ? fabsf(b[i]) : 1e-3f);
    if (e > d) d = e;
  }
  return d;
}

static void size_table(int w, int h, const query *q, int nq, const query *qe, int nqe) {
  float *img = make_image(w, h);
  el_mipmap m, m64;
  pbrt_MIPMap pm;
  double t0, t_init, t_all, t_pbrt;
  float maxd_level = 0, maxd_tri = 0, maxd_ewa = 0, o[4];
  int i, l;
  static const char *names[] = {"point", "bilinear", "trilinear", "EWA (aniso 8)", "EWA (aniso 64)"};
  double err[5] = {0, 0, 0, 0, 0};
  t0 = wall_now();
  el_mipmap_init(&m, img, w, h, 3, NULL);
  t_init = wall_now() - t0;
  printf("\n## %dx%d RGB%s\n\n", w, h, (w & (w - 1)) ? " (resampled to 2048x1024)" : "");
  printf("| build | time | bytes |\n|---|---|---|\n");
  printf("| el_mipmap_init (level 0 only, lazy) | %.1f ms | %zu |\n", 1e3 * t_init, el_mipmap_bytes(&m));
  t0 = wall_now();
  el_mipmap_build_levels(&m);
  t_all = wall_now() - t0;
  printf("| + el_mipmap_build_levels (all %d levels) | %.1f ms | %zu |\n", m.levels, 1e3 * (t_init + t_all),
         el_mipmap_bytes(&m));
  t0 = wall_now();
  pbrt_init(&pm, w, h, img);
  t_pbrt = wall_now() - t0;
  printf("| pbrt-v3 port (all levels, BlockedArray) | %.1f ms | %zu |\n", 1e3 * t_pbrt,
         (size_t)(4 * 3 * sizeof(float) * (size_t)pm.resolution.x * pm.resolution.y / 3));
  /* same results? */
  for (l = 0; l < m.levels; ++l) {
    int lw = m.level_width[l], lh = m.level_height[l], x, y;
    const float *d = el_mipmap_level_data(&m, l);
    for (y = 0; y < lh; ++y)
      for (x = 0; x < lw; ++x) {
        float e = rel_diff(d + 3 * ((size_t)y * lw + x), pbrt_BlockedArray_at(pm.pyramid[l], x, y)->c, 3);
        if (e > maxd_level) maxd_level = e;
      }
  }
  for (i = 0; i < nq; ++i) {
    pbrt_Point2f st = pbrt_Point2f_make(q[i].s, q[i].t);
    pbrt_RGBSpectrum r = pbrt_MIPMap_Lookup(&pm, st, q[i].width);
    float e;
    el_mipmap_lookup(&m, q[i].s, q[i].t, q[i].width, o);
    e = rel_diff(o, r.c, 3);
    if (e > maxd_tri) maxd_tri = e;
    r = pbrt_MIPMap_Lookup_dst(&pm, st, pbrt_Vector2f_make(q[i].d0s, q[i].d0t), pbrt_Vector2f_make(q[i].d1s, q[i].d1t));
    el_mipmap_lookup_differentials(&m, q[i].s, q[i].t, q[i].d0s, q[i].d0t, q[i].d1s, q[i].d1t, o);
    e = rel_diff(o, r.c, 3);
    if (e > maxd_ewa) maxd_ewa = e;
  }
  printf("\nLargest relative difference from the pbrt-v3 port (%d random queries): levels %.2g, "
         "trilinear %.2g, EWA %.2g\n",
         nq, maxd_level, maxd_tri, maxd_ewa);
  /* speed */
  build_ours(&m64, img, w, h, 64);
  printf("\n| filter | lookups/s (1 thread) | ns/lookup | rms rel. error vs supersampled footprint |\n"
         "|---|---|---|---|\n");
  for (i = 0; i < nqe; ++i) {
    float ref[3], ref64[3];
    int f;
    reference(&m, qe + i, 8, ref);
    reference(&m, qe + i, 64, ref64);
    for (f = 0; f < 5; ++f) {
      const query *k = qe + i;
      float e = 0;
      int c;
      if (f == 0) el_mipmap_lookup_filtered(&m, EL_MIPMAP_FILTER_POINT, k->s, k->t, k->width, o);
      else if (f == 1) el_mipmap_lookup_filtered(&m, EL_MIPMAP_FILTER_BILINEAR, k->s, k->t, k->width, o);
      else if (f == 2) el_mipmap_lookup(&m, k->s, k->t, k->width, o);
      else if (f == 3) el_mipmap_lookup_differentials(&m, k->s, k->t, k->d0s, k->d0t, k->d1s, k->d1t, o);
      else el_mipmap_lookup_differentials(&m64, k->s, k->t, k->d0s, k->d0t, k->d1s, k->d1t, o);
      for (c = 0; c < 3; ++c) {
        float rr = f == 4 ? ref64[c] : ref[c];
        e += (o[c] - rr) * (o[c] - rr) / (rr * rr + 1e-4f);
      }
      err[f] += e / 3;
    }
  }
  for (i = 0; i < 5; ++i) {
    int op = i < 3 ? i : OP_EWA;
    const el_mipmap *mm = i == 4 ? &m64 : &m;
    double best = 1e30;
    int rep;
    volatile float sink;
    for (rep = 0; rep < 3; ++rep) {
      t0 = wall_now();
      sink = run_op(op, mm, NULL, q, nq);
      t0 = wall_now() - t0;
      if (t0 < best) best = t0;
    }
    (void)sink;
    printf("| %s | %.2f M | %.0f | %.3f |\n", names[i], nq / best / 1e6, 1e9 * best / nq, sqrt(err[i] / nqe));
  }
  {
    double best = 1e30;
    int rep, op;
    volatile float sink;
    for (op = OP_PBRT_TRILINEAR; op <= OP_PBRT_EWA; ++op) {
      best = 1e30;
      for (rep = 0; rep < 3; ++rep) {
        t0 = wall_now();
        sink = run_op(op, &m, &pm, q, nq);
        t0 = wall_now() - t0;
        if (t0 < best) best = t0;
      }
      (void)sink;
      printf("| pbrt-v3 port: %s | %.2f M | %.0f | (same as ours) |\n",
             op == OP_PBRT_TRILINEAR ? "trilinear" : "EWA (aniso 8)", nq / best / 1e6, 1e9 * best / nq);
    }
  }
  el_mipmap_free(&m);
  el_mipmap_free(&m64);
  pbrt_MIPMap_free(&pm);
  free(img);
}

/* ---------------------------------------------------------------------------------------------
 * --csv: the numbers bench/report.py plots (docs/accuracy-vs-time.md), one CSV row per measurement.
 *   lookup,<filter>,<footprint anisotropy>,<ns per lookup>,<rms rel. error>
 *   build,<method>,<input width>,<ms>,<rms rel. error>
 * Lookups: footprints of a fixed anisotropy ratio A (1, 8, 64), major axis log-uniform in [1e-3, 3e-2]
 * of the texture (2 to 60 texels of 2048), random orientation; the error is against the supersampled
 * footprint without any anisotropy clamp (the filter the lookup approximates). Times (the thread's CPU time): the median of
 * `reps` runs, each run timing every filter once in turn (interleaved). Builds: a width x width/2 input
 * (width not a power of two), init + every level, pbrt's Lanczos resampling or keep_resolution; the
 * error is EWA lookups (anisotropy 1 footprints) against the supersampled footprint of the input itself.
 * --------------------------------------------------------------------------------------------- */
static query *make_queries_aniso(int n, float aniso) {
  query *q = (query *)malloc(sizeof(query) * (size_t)n);
  int i;
  for (i = 0; i < n; ++i) {
    float len = powf(10.0f, -3.0f + 1.5f * rnd()), ang = 6.2831853f * rnd();
    q[i].s = rnd();
    q[i].t = rnd();
    q[i].d0s = len * cosf(ang);
    q[i].d0t = len * sinf(ang);
    q[i].d1s = -len / aniso * sinf(ang);
    q[i].d1t = len / aniso * cosf(ang);
    q[i].width = 2 * len;
  }
  return q;
}
/* one lookup of filter f: 0 point, 1 bilinear, 2 trilinear, 3 EWA (m), 4 EWA (m64), 5/6 pbrt-v3 port */
static void csv_lookup(int f, const el_mipmap *m, const el_mipmap *m64, const pbrt_MIPMap *pm, const query *k,
                       float *o) {
  pbrt_RGBSpectrum r;
  switch (f) {
  case 0: el_mipmap_lookup_filtered(m, EL_MIPMAP_FILTER_POINT, k->s, k->t, k->width, o); return;
  case 1: el_mipmap_lookup_filtered(m, EL_MIPMAP_FILTER_BILINEAR, k->s, k->t, k->width, o); return;
  case 2: el_mipmap_lookup(m, k->s, k->t, k->width, o); return;
  case 3: el_mipmap_lookup_differentials(m, k->s, k->t, k->d0s, k->d0t, k->d1s, k->d1t, o); return;
  case 4: el_mipmap_lookup_differentials(m64, k->s, k->t, k->d0s, k->d0t, k->d1s, k->d1t, o); return;
  case 5: r = pbrt_MIPMap_Lookup(pm, pbrt_Point2f_make(k->s, k->t), k->width); break;
  default:
    r = pbrt_MIPMap_Lookup_dst(pm, pbrt_Point2f_make(k->s, k->t), pbrt_Vector2f_make(k->d0s, k->d0t),
                               pbrt_Vector2f_make(k->d1s, k->d1t));
  }
  o[0] = r.c[0]; o[1] = r.c[1]; o[2] = r.c[2];
}
static double rel_err2(const float *o, const float *ref) {
  double e = 0;
  int c;
  for (c = 0; c < 3; ++c) e += (o[c] - ref[c]) * (o[c] - ref[c]) / (ref[c] * ref[c] + 1e-4f);
  return e / 3;
}
static int csv_mode(int quick) {
  static const char *fname[7] = {"point", "bilinear", "trilinear", "EWA max aniso 8 (default)", "EWA max aniso 64",
                                 "pbrt-v3 port: trilinear", "pbrt-v3 port: EWA"};
  static const float anisos[3] = {1, 8, 64};
  int w = quick ? 512 : 2048, h = w / 2, nq = quick ? 4000 : 100000, ne = quick ? 100 : 1000, reps = quick ? 3 : 7;
  float *img = make_image(w, h), o[4];
  el_mipmap m, m64;
  pbrt_MIPMap pm;
  int a, f, i, r;
  double t[7][15];
  printf("kind,option,x,value,error\n");
  build_ours(&m, img, w, h, 8);
  build_ours(&m64, img, w, h, 64);
  pbrt_init(&pm, w, h, img);
  for (a = 0; a < 3; ++a) {
    query *q = make_queries_aniso(nq, anisos[a]), *qe = make_queries_aniso(ne, anisos[a]);
    double err[7] = {0, 0, 0, 0, 0, 0, 0};
    for (i = 0; i < ne; ++i) {
      float ref[3];
      reference(&m, qe + i, 1e9f, ref);
      for (f = 0; f < 7; ++f) {
        csv_lookup(f, &m, &m64, &pm, qe + i, o);
        err[f] += rel_err2(o, ref);
      }
    }
    for (r = 0; r < reps; ++r)
      for (f = 0; f < 7; ++f) {
        volatile float sink = 0;
        double t0 = cpu_now();
        float acc = 0;
        for (i = 0; i < nq; ++i) {
          csv_lookup(f, &m, &m64, &pm, q + i, o);
          acc += o[0];
        }
        sink = acc;
        (void)sink;
        t[f][r] = 1e9 * (cpu_now() - t0) / nq;
      }
    for (f = 0; f < 7; ++f)
      printf("lookup,%s,%g,%.3f,%.5g\n", fname[f], anisos[a], median(t[f], reps), sqrt(err[f] / ne));
    fflush(stdout);
    free(q);
    free(qe);
  }
  el_mipmap_free(&m);
  el_mipmap_free(&m64);
  pbrt_MIPMap_free(&pm);
  free(img);
  { /* builds */
    static const int widths_full[4] = {500, 1000, 2000, 4000}, widths_quick[2] = {250, 500};
    const int *widths = quick ? widths_quick : widths_full;
    int nw = quick ? 2 : 4, k;
    for (k = 0; k < nw; ++k) {
      int bw = widths[k], bh = bw / 2;
      float *in = make_image(bw, bh);
      query *qe = make_queries_aniso(ne, 1);
      el_mipmap ref;
      double tb[2][15], err[2] = {0, 0};
      el_mipmap_options ko;
      memset(&ko, 0, sizeof ko);
      ko.keep_resolution = 1;
      el_mipmap_init(&ref, in, bw, bh, 3, &ko); /* level 0 = the input: the reference's point lookups */
      for (r = 0; r < reps; ++r)
        for (f = 0; f < 2; ++f) {
          el_mipmap mm;
          double t0 = cpu_now();
          el_mipmap_init(&mm, in, bw, bh, 3, f ? &ko : NULL);
          el_mipmap_build_levels(&mm);
          tb[f][r] = 1e3 * (cpu_now() - t0);
          if (r == 0) {
            for (i = 0; i < ne; ++i) {
              float rr[3];
              reference(&ref, qe + i, 1e9f, rr);
              el_mipmap_lookup_differentials(&mm, qe[i].s, qe[i].t, qe[i].d0s, qe[i].d0t, qe[i].d1s, qe[i].d1t, o);
              err[f] += rel_err2(o, rr);
            }
          }
          el_mipmap_free(&mm);
        }
      for (f = 0; f < 2; ++f)
        printf("build,%s,%d,%.3f,%.5g\n", f ? "keep_resolution" : "Lanczos to a power of two (default)", bw,
               median(tb[f], reps), sqrt(err[f] / ne));
      fflush(stdout);
      el_mipmap_free(&ref);
      free(qe);
      free(in);
    }
  }
  return 0;
}

int main(int argc, char **argv) {
  query *q, *qe;
  int nq = 200000, nqe = 2000;
  if (argc >= 4 && !strcmp(argv[1], "--callgrind")) return callgrind_mode(argv[2], atoi(argv[3]));
  if (argc >= 2 && !strcmp(argv[1], "--csv")) return csv_mode(argc >= 3 && !strcmp(argv[2], "--quick"));
  if (argc >= 2 && !strcmp(argv[1], "--quick")) {
    nq = 20000;
    nqe = 200;
  }
  printf("# bench_mipmap: MIP map build and lookups, ours against a literal port of pbrt-v3\n");
  printf("Random queries: s, t uniform; footprint length log-uniform in [1e-4, 0.1], anisotropy ratio\n"
         "uniform in [1, 16]; trilinear/point/bilinear width = 2 x length (pbrt's rule).\n");
  q = make_queries(nq);
  qe = make_queries(nqe);
  size_table(2048, 1024, q, nq, qe, nqe);
  size_table(2000, 1000, q, nq, qe, nqe);
  if (argc >= 2 && !strcmp(argv[argc - 1], "--instructions")) instructions_table(argv[0]);
  else printf("\n(run with --instructions for callgrind instruction counts)\n");
  free(q);
  free(qe);
  return 0;
}
