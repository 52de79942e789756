/* bench_envlight.c: what the infinite area light's accuracy costs in time and memory.
 *
 *   bench_envlight                       every table below (runs itself under callgrind if valgrind exists)
 *   bench_envlight --no-callgrind        without the instruction counts
 *   bench_envlight --quick               1024x512 and 2048x1024 only, no callgrind, fewer samples
 *   bench_envlight --product             tables 4 and 5 only (product sampling)
 *   bench_envlight --csv [--quick]       the CSV that bench/report.py plots (see csv_mode)
 *   bench_envlight --callgrind OP N [MAP] only N calls of OP after the setup (a generated 2048x1024 map,
 *                                        the pbrt-v3 target's size, or the RGB map file MAP). OP: loop
 *                                        sample_cdf sample_guide sample_alias sample_guide_rgb pdf le
 *                                        sample_rotated pdf_rotated build; importance BILINEAR:
 *                                        sample_bilinear sample_bilinear_rgb pdf_bilinear build_bilinear
 *                                        sample_bilinear_rotated pdf_bilinear_rotated;
 *                                        product sampling (a new normal per call): sample_cos
 *                                        sample_cos_rgb pdf_cos sample_cos_rotated pdf_cos_rotated
 *                                        build_product; n at once (sample_li_cos_n, pdf_li_cos_n,
 *                                        batches of 64, the same normals and u): sample_cos_n
 *                                        sample_cos_n_rgb pdf_cos_n sample_cos_n_rotated pdf_cos_n_rotated;
 *                                        pdf_li_n, le_n (batches of 64, run_pdf's directions): pdf_n le_n;
 *                                        pdf_li_cos_le_n (pdf_cos_n's normals and directions): pdf_cos_le_n
 *                                        pdf_cos_le_n_rotated, and le_n alone on them: le_cos_n le_cos_n_rotated;
 *                                        the hot-spot mixture with the rest x cosine (256 prepared
 *                                        tables, spots at 3%): sample_mix_cos_rgb pdf_mix_cos
 *   EL_ENVMAPS=DIR                       the CC0 maps' folder (default ../shared/envmaps next to the repository)
 *
 * Instructions per call, by hand: valgrind --tool=callgrind --callgrind-out-file=/dev/null
 * build/bin/bench_envlight --callgrind pdf N for N = 0 and N = 200000; (Ir(N) - Ir(0)) / N from the
 * "Collected" line, minus the "loop" op's count (reading precomputed random numbers, summing the results).
 *
 * Tables:
 *  1. Build and memory, for generated 1024x512, 2048x1024 and 8192x4096 maps (a sky gradient with
 *     texture noise and a 3e4 sun, like ../shared/envmaps/city): el_envlight_init (copy, check, integrate)
 *     and the lazy sampling build (importance map + distribution + bin finders + pdf table) for each
 *     importance choice, their bytes, then sample_li / pdf_li / le throughput per sampler.
 *     pbrt-v3 on this kind of machine (issue 3): constructor 313 ms and ~100 MB (MIPMap + 4096x2048
 *     distribution) for 2048x1024; Sample_Li 5.2 M/s and ~470 instructions; Pdf_Li ~300 instructions.
 *  2. Instructions per call (callgrind) on the 2048x1024 map. Measured (gcc 12 -O3, loop subtracted):
 *     sample_li guide 93.5 (95.6-97.6 on the five CC0 1024x512 maps, with MAP), alias 240, CDF 394, guide
 *     + radiance 257, general rotation 218 (2026-12-01, after sample_li_n's helpers were shared: 95,
 *     96.6-98.6, 261, 214 before); at the start of the SSE work: 176, 274, 428, 335, 302; before
 *     the bin + direction-table rewrite: 303, 305, 467, 437, 420. pdf_li 75 (rotation 93; 76 and 95
 *     before the rescaling of huge directions moved out of line; before the branch-free bin finders:
 *     114, 131), le 248 (250 before that move), construction 117 M (before the SSE2 construction
 *     loops: 185 M). Targets sample_li <= 100 and pdf_li <= 80 met; throughput (>= 26 M/s): see README.md.
 *  3. Variance of a direct-lighting estimate: the irradiance (luminance) of a diffuse point at three
 *     normals, for the maps in ../shared/envmaps (data/envmaps if missing), per strategy: uniform sphere,
 *     cosine, light sampling with each importance map (CELL_AVERAGE = ours, PBRT_V3 = 2x-resolution point
 *     lookups, TEXEL = raw texels: biased with a bilinear le, pbrt-v3 issue #62), the compensated density
 *     with MIS (one light + one cosine sample, balance heuristic, per pair), and the alias sampler; also
 *     CELL_AVERAGE at twice the image's resolution (importance_width/height). Each
 *     row: variance per sample relative to E^2, |bias| in standard errors against a quadrature of the
 *     bilinear reconstruction, ns per sample, and the efficiency 1 / (relative variance * time) normalised
 *     to light sampling with CELL_AVERAGE and the default (guide) sampler; and, for light sampling, the
 *     relative variance of lum(le) / pdf (how well the density matches the map, whatever the cosine).
 *     BILINEAR (le()'s patch density, issue 22) is among the rows.
 *  4. Product sampling: for each CC0 map and six normals (up, down, two sideways, facing the brightest
 *     texel and away from it) the relative variance per sample of the irradiance estimate with
 *     sample_li, sample_li in importance BILINEAR and sample_li_cos, each alone and with one cosine
 *     sample (balance and power heuristics), the samples below the horizon, ns per estimate and the
 *     efficiency; the tables' build time and memory.
 *  5. Stratification: Var(256 independent samples) / Var(16x16 jittered) for each sampler.
 */
#define _POSIX_C_SOURCE 199309L /* clock_gettime */
#define EL_IMPLEMENTATION
#include "envlight.h"
#include "image_io.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#ifdef __GLIBC__
#include <malloc.h> /* mallopt: large blocks straight from and back to the system, so no build reuses
                       pages an earlier one faulted in (glibc would otherwise keep them in its heap) */
#endif

#ifndef EL_SOURCE_DIR
#define EL_SOURCE_DIR "."
#endif

static const double PI = 3.14159265358979323846;

/* process_now: CPU time of this process, not wall time: the benchmark is single-threaded, and on a
 * machine shared with other jobs the wall clock also counts the time we wait for a core. */
#include "bench_common.h" /* process_now, cpu_now, median, hash32, rng (PCG32) */

/* 2^20 precomputed uniform numbers in [0,1) (24 bits), and as many random directions */
#define NP (1 << 20)
static float *g_u, *g_dir;
static void make_random(void) {
  int i;
  g_u = (float *)malloc(2 * NP * sizeof(float));
  g_dir = (float *)malloc(3 * NP * sizeof(float));
  for (i = 0; i < 2 * NP; ++i) g_u[i] = (float)(hash32((uint32_t)i * 2654435761u + 17u) >> 8) * (1.0f / 16777216.0f);
  for (i = 0; i < NP; ++i) {
    float z = 1.0f - 2.0f * g_u[2 * i], r = sqrtf(fmaxf(0.0f, 1.0f - z * z)), ph = 6.2831853f * g_u[2 * i + 1];
    g_dir[3 * i] = r * cosf(ph); g_dir[3 * i + 1] = r * sinf(ph); g_dir[3 * i + 2] = z;
  }
}

/* A city-like map: bright sky gradient above, dark ground below, texture noise, a 3e4 sun. */
static float *make_map(int w, int h) {
  float *px = (float *)malloc((size_t)w * h * 3 * sizeof(float));
  int x, y;
  const float su = 0.3f, sv = 0.3f, r = 0.004f;
  for (y = 0; y < h; ++y) {
    float vv = (y + 0.5f) / h, sky = vv < 0.5f ? 0.3f + 1.4f * vv : 0.05f;
    for (x = 0; x < w; ++x) {
      float uu = (x + 0.5f) / w, du = uu - su, dv = (vv - sv) * 0.5f;
      float noise = (float)(hash32((uint32_t)(y * w + x)) >> 8) * (1.0f / 16777216.0f);
      float v = sky * (0.6f + 0.8f * noise);
      float *p = px + ((size_t)y * w + x) * 3;
      if (du * du + dv * dv < r * r) v = 3e4f;
      p[0] = v; p[1] = 0.9f * v; p[2] = 0.8f * v;
    }
  }
  return px;
}

static el_result make_light(el_envlight *l, const float *px, int w, int h, int importance, int sampler, int comp,
                            const float *m) {
  el_envlight_options o;
  memset(&o, 0, sizeof o);
  o.importance = importance;
  o.sampler = sampler;
  o.compensated = comp;
  if (m) memcpy(o.light_to_world, m, sizeof o.light_to_world);
  return el_envlight_init(l, px, w, h, 3, &o);
}

/* a general rotation: 37 degrees about the axis (1, 2, 3) (Rodrigues) */
static float ROT[9];
static void make_rot(void) {
  double n = sqrt(14.0), x = 1 / n, y = 2 / n, z = 3 / n, a = 37.0 * PI / 180.0, c = cos(a), s = sin(a), t = 1 - c;
  double r[9] = {t * x * x + c, t * x * y - s * z, t * x * z + s * y, t * x * y + s * z, t * y * y + c,
                 t * y * z - s * x, t * x * z - s * y, t * y * z + s * x, t * z * z + c};
  int i;
  for (i = 0; i < 9; ++i) ROT[i] = (float)r[i];
}

/* ---- throughput loops (also the callgrind bodies) ---- */
static double run_sample(el_envlight *l, long n, int rgb) {
  double acc = 0;
  long k;
  float wi[3], L[3], p;
  for (k = 0; k < n; ++k) {
    el_envlight_sample_li(l, g_u + 2 * (k & (NP - 1)), wi, rgb ? L : NULL, &p);
    acc += p + wi[0];
  }
  return acc;
}
static double run_pdf(el_envlight *l, long n) {
  double acc = 0;
  long k;
  for (k = 0; k < n; ++k) acc += el_envlight_pdf_li(l, g_dir + 3 * (k & (NP - 1)));
  return acc;
}
static double run_le(el_envlight *l, long n) {
  double acc = 0;
  long k;
  float L[3];
  for (k = 0; k < n; ++k) { el_envlight_le(l, g_dir + 3 * (k & (NP - 1)), L); acc += L[1]; }
  return acc;
}
/* product sampling: each call with its own normal (the random directions), as a renderer's shading points */
static double run_sample_cos(el_envlight *l, long n, int rgb) {
  double acc = 0;
  long k;
  float wi[3], L[3], p;
  for (k = 0; k < n; ++k) {
    el_envlight_sample_li_cos(l, g_dir + 3 * ((k * 7) & (NP - 1)), g_u + 2 * (k & (NP - 1)), wi, rgb ? L : NULL, &p);
    acc += p + wi[0];
  }
  return acc;
}
static double run_pdf_cos(el_envlight *l, long n) {
  double acc = 0;
  long k;
  for (k = 0; k < n; ++k) acc += el_envlight_pdf_li_cos(l, g_dir + 3 * ((k * 7) & (NP - 1)), g_dir + 3 * (k & (NP - 1)));
  return acc;
}
/* the hot-spot mixture with the rest x cosine (issue 22's sun cache in a shadowed cell): the spots at a 3%
 * floor, MIXN tables prepared beforehand for random normals (the renderer's per-cell tables), each call
 * another table; sample with the radiance, and the pdf of a random direction */
#define MIXN 256
static el_envlight_hotspots g_hs;
static el_envlight_mix_cos_table *g_mixt;
static int prepare_mix(el_envlight *l) {
  el_envlight_mix_weights w;
  int k;
  if (el_envlight_hotspots_init(&g_hs, l, NULL) != EL_SUCCESS || g_hs.count == 0) { fprintf(stderr, "no hot spot\n"); return 1; }
  el_envlight_hotspots_weights(&g_hs, 0.03f, &w);
  g_mixt = (el_envlight_mix_cos_table *)malloc(MIXN * sizeof *g_mixt);
  if (!g_mixt) return 1;
  for (k = 0; k < MIXN; ++k) el_envlight_mix_cos_prepare(l, &g_hs, &w, g_dir + 3 * (size_t)(k * 4099 & (NP - 1)), &g_mixt[k]);
  return 0;
}
static double run_sample_mix_cos(el_envlight *l, long n) {
  double acc = 0;
  long k;
  float wi[3], L[3], p;
  for (k = 0; k < n; ++k) {
    el_envlight_sample_li_mix_cos_table(l, &g_hs, &g_mixt[(k * 7) & (MIXN - 1)], g_u + 2 * (k & (NP - 1)), wi, L, &p);
    acc += p + wi[0];
  }
  return acc;
}
static double run_pdf_mix_cos(el_envlight *l, long n) {
  double acc = 0;
  long k;
  for (k = 0; k < n; ++k) acc += el_envlight_pdf_li_mix_cos_table(l, &g_hs, &g_mixt[(k * 7) & (MIXN - 1)], g_dir + 3 * (k & (NP - 1)));
  return acc;
}
/* the same calls n at once (sample_li_cos_n, pdf_li_cos_n), batches of 64: g_nrm holds the single loops'
 * normals in call order (g_nrm[3k..] = g_dir[3 (7k mod NP)..]), so the samples are the same */
#define CB 64
static float *g_nrm;
static void make_normals(void) {
  long k;
  g_nrm = (float *)malloc(3 * (size_t)NP * sizeof(float));
  for (k = 0; k < NP; ++k) memcpy(g_nrm + 3 * k, g_dir + 3 * ((k * 7) & (NP - 1)), 3 * sizeof(float));
}
static double run_sample_cos_n(el_envlight *l, long n, int rgb) {
  double acc = 0;
  long k;
  int j, m;
  float wi[3 * CB], L[3 * CB], p[CB];
  for (k = 0; k < n; k += CB) {
    long o = k & (NP - 1);
    m = n - k < CB ? (int)(n - k) : CB;
    el_envlight_sample_li_cos_n(l, m, g_nrm + 3 * o, g_u + 2 * o, wi, rgb ? L : NULL, p);
    for (j = 0; j < m; ++j) acc += p[j] + wi[3 * j];
  }
  return acc;
}
static double run_pdf_cos_n(el_envlight *l, long n) {
  double acc = 0;
  long k;
  int j, m;
  float p[CB];
  for (k = 0; k < n; k += CB) {
    long o = k & (NP - 1);
    m = n - k < CB ? (int)(n - k) : CB;
    el_envlight_pdf_li_cos_n(l, m, g_nrm + 3 * o, g_dir + 3 * o, p);
    for (j = 0; j < m; ++j) acc += p[j];
  }
  return acc;
}
/* pdf_li_cos_le_n (issue 21: an escaped ray's product pdf and le in one pass), run_pdf_cos_n's normals and
 * directions; le = 1: le_n alone on those directions (pdf_cos_n + le_cos_n: the two calls it replaces) */
static double run_pdf_cos_le_n(el_envlight *l, long n, int le) {
  double acc = 0;
  long k;
  int j, m;
  float p[CB], v[3 * CB];
  for (k = 0; k < n; k += CB) {
    long o = k & (NP - 1);
    m = n - k < CB ? (int)(n - k) : CB;
    if (le) el_envlight_le_n(l, m, g_dir + 3 * o, v);
    else el_envlight_pdf_li_cos_le_n(l, m, g_nrm + 3 * o, g_dir + 3 * o, p, v);
    for (j = 0; j < m; ++j) acc += (le ? 0.0f : p[j]) + v[3 * j + 1];
  }
  return acc;
}
/* pdf_li_n (le = 0) and le_n (le = 1) (issue 21: a wave's escaped rays), batches of 64 of the
 * directions run_pdf / run_le use */
static double run_escape_n(el_envlight *l, long n, int le) {
  double acc = 0;
  long k;
  int j, m;
  float v[3 * CB];
  for (k = 0; k < n; k += CB) {
    m = n - k < CB ? (int)(n - k) : CB;
    if (le) el_envlight_le_n(l, m, g_dir + 3 * (k & (NP - 1)), v);
    else el_envlight_pdf_li_n(l, m, g_dir + 3 * (k & (NP - 1)), v);
    for (j = 0; j < m; ++j) acc += v[le ? 3 * j + 1 : j];
  }
  return acc;
}
static double run_loop(long n) { /* the loop alone: read the inputs, sum */
  double acc = 0;
  long k;
  for (k = 0; k < n; ++k) { const float *u = g_u + 2 * (k & (NP - 1)); acc += u[0] + u[1]; }
  return acc;
}
static double rate(double (*fn)(el_envlight *, long, int), el_envlight *l, int arg) {
  double best = 1e30;
  int rep;
  long n = 1 << 21;
  volatile double sink;
  for (rep = 0; rep < 3; ++rep) {
    double t = process_now();
    sink = fn(l, n, arg);
    t = process_now() - t;
    if (t < best) best = t;
  }
  (void)sink;
  return n / best * 1e-6;
}
/* A renderer's loop in miniature: each light sample (with its radiance) is followed by other work that
 * reads memory (here 8 random lines of a 64 MB buffer, standing in for ray traversal, shading and the
 * film), so the sample's cache misses cannot overlap with the next sample's. batch = 0: sample_li one at
 * a time, each followed by its share of the work; batch = 16: sample_li_n for 16 samples, then the
 * work of 16 (the order a renderer that draws a pixel's light samples together uses). */
#define POLLUTE_N (1 << 24)
static float *g_pollute;
static double pollute(long k) {
  double a = 0;
  int j;
  for (j = 0; j < 8; ++j) a += g_pollute[hash32((uint32_t)(k * 8 + j)) & (POLLUTE_N - 1)];
  return a;
}
/* batch = 2, 3: an escaped ray's pdf_li and le (random directions), one at a time or pdf_li_n + le_n
 * for 16 (issue 21) */
static double run_interleaved(el_envlight *l, long n, int batch) {
  double acc = 0;
  long k, j;
  float wi[3 * 16], L[3 * 16], p[16];
  for (k = 0; k + 16 <= n; k += 16) {
    const float *u = g_u + 2 * (k & (NP - 1)), *d = g_dir + 3 * (k & (NP - 1));
    if (batch == 3) {
      el_envlight_pdf_li_n(l, 16, d, p);
      el_envlight_le_n(l, 16, d, L);
      for (j = 0; j < 16; ++j) acc += p[j] + L[3 * j] + pollute(k + j);
    } else if (batch == 2)
      for (j = 0; j < 16; ++j) { p[0] = el_envlight_pdf_li(l, d + 3 * j); el_envlight_le(l, d + 3 * j, L); acc += p[0] + L[0] + pollute(k + j); }
    else if (batch) {
      el_envlight_sample_li_n(l, 16, u, wi, L, p);
      for (j = 0; j < 16; ++j) acc += p[j] + L[3 * j] + pollute(k + j);
    } else
      for (j = 0; j < 16; ++j) { el_envlight_sample_li(l, u + 2 * j, wi, L, p); acc += p[0] + L[0] + pollute(k + j); }
  }
  return acc;
}
static double run_pollute_only(el_envlight *l, long n, int a) {
  double acc = 0;
  long k;
  (void)l; (void)a;
  for (k = 0; k < n; ++k) acc += pollute(k);
  return acc;
}
static double fn_sample(el_envlight *l, long n, int rgb) { return run_sample(l, n, rgb); }
static double fn_sample_cos(el_envlight *l, long n, int rgb) { return run_sample_cos(l, n, rgb); }
static double fn_pdf_cos(el_envlight *l, long n, int a) { (void)a; return run_pdf_cos(l, n); }
static double fn_pdf(el_envlight *l, long n, int a) { (void)a; return run_pdf(l, n); }
static double fn_le(el_envlight *l, long n, int a) { (void)a; return run_le(l, n); }
static double fn_escape_n(el_envlight *l, long n, int le) { return run_escape_n(l, n, le); }

/* ---- --callgrind OP N ---- */
static int callgrind_mode(const char *op, long n, const char *map) {
  static el_envlight l;
  int w = 2048, h = 1024, sampler = 0, rot = 0, imp = 0;
  float *px;
  volatile double sink = 0;
  el_image img;
  make_random();
  memset(&img, 0, sizeof img);
  if (map) { /* a map file instead of the generated one */
    char err[256];
    if (el_image_load(map, &img, err, sizeof err) != 0) { fprintf(stderr, "%s\n", err); return 1; }
    if (img.channels != 3) { fprintf(stderr, "%s: %d channels, want RGB\n", map, img.channels); el_image_free(&img); return 1; }
    w = img.width; h = img.height;
    px = (float *)malloc((size_t)w * h * 3 * sizeof(float));
    if (!px) return 1;
    memcpy(px, img.pixels, (size_t)w * h * 3 * sizeof(float));
    el_image_free(&img);
  } else px = make_map(w, h);
  if (!strcmp(op, "sample_cdf")) sampler = EL_ENVLIGHT_SAMPLER_CDF;
  if (!strcmp(op, "sample_guide") || !strcmp(op, "sample_guide_rgb")) sampler = EL_ENVLIGHT_SAMPLER_GUIDE;
  if (!strcmp(op, "sample_alias")) sampler = EL_ENVLIGHT_SAMPLER_ALIAS;
  if (!strcmp(op, "sample_rotated") || !strcmp(op, "pdf_rotated") || !strcmp(op, "sample_cos_rotated") || !strcmp(op, "pdf_cos_rotated") ||
      !strcmp(op, "sample_cos_n_rotated") || !strcmp(op, "pdf_cos_n_rotated") || !strcmp(op, "pdf_cos_le_n_rotated") ||
      !strcmp(op, "le_cos_n_rotated") || !strcmp(op, "sample_bilinear_rotated") || !strcmp(op, "pdf_bilinear_rotated")) {
    sampler = EL_ENVLIGHT_SAMPLER_GUIDE; rot = 1; make_rot();
  }
  if (!strncmp(op, "sample_bilinear", 15) || !strncmp(op, "pdf_bilinear", 12)) imp = EL_ENVLIGHT_IMPORTANCE_BILINEAR;
  if (make_light(&l, px, w, h, imp, sampler, 0, rot ? ROT : NULL) != EL_SUCCESS) return 1;
  if (strstr(op, "_cos") || !strcmp(op, "build_product")) el_envlight_prepare_product(&l, NULL);
  else el_envlight_prepare_sampling(&l);
  if (!strcmp(op, "build")) { /* n constructions (init + sampling tables) of the same light */
    long k;
    for (k = 0; k < n; ++k) {
      el_envlight b;
      make_light(&b, px, w, h, 0, EL_ENVLIGHT_SAMPLER_GUIDE, 0, NULL);
      el_envlight_prepare_sampling(&b);
      el_envlight_free(&b);
    }
  } else if (!strcmp(op, "build_product")) { /* n builds of the product tables (warp + normal tables) */
    long k;
    for (k = 0; k < n; ++k) {
      el_envlight b;
      make_light(&b, px, w, h, 0, EL_ENVLIGHT_SAMPLER_GUIDE, 0, NULL);
      el_envlight_prepare_product(&b, NULL);
      el_envlight_free(&b);
    }
  } else if (!strcmp(op, "build_bilinear")) { /* n builds of importance BILINEAR's tables (the warp) */
    long k;
    for (k = 0; k < n; ++k) {
      el_envlight b;
      make_light(&b, px, w, h, EL_ENVLIGHT_IMPORTANCE_BILINEAR, EL_ENVLIGHT_SAMPLER_GUIDE, 0, NULL);
      el_envlight_prepare_sampling(&b);
      el_envlight_free(&b);
    }
  } else if (!strcmp(op, "sample_cos_n") || !strcmp(op, "sample_cos_n_rgb") || !strcmp(op, "sample_cos_n_rotated")) {
    make_normals();
    sink = run_sample_cos_n(&l, n, !strcmp(op, "sample_cos_n_rgb"));
  } else if (!strcmp(op, "pdf_cos_n") || !strcmp(op, "pdf_cos_n_rotated")) {
    make_normals();
    sink = run_pdf_cos_n(&l, n);
  } else if (!strcmp(op, "pdf_cos_le_n") || !strcmp(op, "pdf_cos_le_n_rotated") || !strcmp(op, "le_cos_n") || !strcmp(op, "le_cos_n_rotated")) {
    make_normals();
    sink = run_pdf_cos_le_n(&l, n, op[0] == 'l');
  } else if (!strcmp(op, "sample_cos") || !strcmp(op, "sample_cos_rgb") || !strcmp(op, "sample_cos_rotated")) sink = run_sample_cos(&l, n, !strcmp(op, "sample_cos_rgb"));
  else if (!strcmp(op, "pdf_cos") || !strcmp(op, "pdf_cos_rotated")) sink = run_pdf_cos(&l, n);
  else if (!strcmp(op, "sample_mix_cos_rgb") || !strcmp(op, "pdf_mix_cos")) {
    if (prepare_mix(&l)) return 1;
    sink = op[0] == 's' ? run_sample_mix_cos(&l, n) : run_pdf_mix_cos(&l, n);
    el_envlight_hotspots_free(&g_hs);
    free(g_mixt);
  }
  else if (!strcmp(op, "pdf_bilinear") || !strcmp(op, "pdf_bilinear_rotated")) sink = run_pdf(&l, n);
  else if (!strcmp(op, "loop")) sink = run_loop(n);
  else if (!strncmp(op, "sample_", 7)) sink = run_sample(&l, n, !strcmp(op, "sample_guide_rgb") || !strcmp(op, "sample_bilinear_rgb"));
  else if (!strcmp(op, "pdf") || !strcmp(op, "pdf_rotated")) sink = run_pdf(&l, n);
  else if (!strcmp(op, "le")) sink = run_le(&l, n);
  else if (!strcmp(op, "pdf_n") || !strcmp(op, "le_n")) sink = run_escape_n(&l, n, !strcmp(op, "le_n"));
  else { fprintf(stderr, "unknown OP %s\n", op); return 2; }
  (void)sink;
  el_envlight_free(&l);
  free(px);
  return 0;
}
static double callgrind_ir(const char *self, const char *op, long n) {
  char cmd[1024], line[512];
  FILE *fp;
  double ir = -1;
  snprintf(cmd, sizeof cmd, "valgrind --tool=callgrind --callgrind-out-file=/dev/null '%s' --callgrind %s %ld 2>&1", self, op, n);
  fp = popen(cmd, "r");
  if (!fp) return -1;
  while (fgets(line, sizeof line, fp)) {
    char *c = strstr(line, "Collected :");
    if (c) ir = atof(c + 11);
  }
  pclose(fp);
  return ir;
}
static double instr_per_call(const char *self, const char *op, long n) {
  double a = callgrind_ir(self, op, 0), b = callgrind_ir(self, op, n);
  return (a < 0 || b < 0) ? -1 : (b - a) / n;
}

/* ---- variance of the irradiance estimate ---- */
typedef struct { const float *px; int w, h; } image;
static double lum3(double r, double g, double b) { return 0.212671 * r + 0.715160 * g + 0.072169 * b; }
static double img_lum(const image *im, int x, int y) {
  const float *p;
  x %= im->w; if (x < 0) x += im->w;
  if (y < 0) y = 0;
  if (y > im->h - 1) y = im->h - 1;
  p = im->px + ((size_t)y * im->w + x) * 3;
  return lum3(p[0], p[1], p[2]);
}
/* E(n) by the midpoint rule on 2x2 sub-cells per texel of the bilinear reconstruction (light space) */
static void quadrature(const image *im, const double n[][3], int nn, double *E) {
  int x, y, a, b, k, s = 2;
  for (k = 0; k < nn; ++k) E[k] = 0;
  for (y = 0; y < im->h; ++y)
    for (b = 0; b < s; ++b) {
      double v0 = (y + (double)b / s) / im->h, v1 = (y + (b + 1.0) / s) / im->h, v = 0.5 * (v0 + v1);
      double dom = (cos(PI * v0) - cos(PI * v1)) * 2 * PI / (im->w * s), st = sin(PI * v), ct = cos(PI * v);
      double t = v * im->h - 0.5, fy;
      int y0 = (int)floor(t);
      fy = t - y0;
      for (x = 0; x < im->w; ++x)
        for (a = 0; a < s; ++a) {
          double u = (x + (a + 0.5) / s) / im->w, ss = u * im->w - 0.5, fx, L, w[3];
          int x0 = (int)floor(ss);
          fx = ss - x0;
          L = (1 - fy) * ((1 - fx) * img_lum(im, x0, y0) + fx * img_lum(im, x0 + 1, y0)) +
              fy * ((1 - fx) * img_lum(im, x0, y0 + 1) + fx * img_lum(im, x0 + 1, y0 + 1));
          w[0] = st * cos(2 * PI * u); w[1] = st * sin(2 * PI * u); w[2] = ct;
          for (k = 0; k < nn; ++k) {
            double c = n[k][0] * w[0] + n[k][1] * w[1] + n[k][2] * w[2];
            if (c > 0) E[k] += L * c * dom;
          }
        }
    }
}

enum { S_UNIFORM, S_COSINE, S_CELL, S_CELL2, S_PBRT, S_TEXEL, S_COMP_MIS, S_ALIAS, S_BILIN, S_N };
static const char *S_NAME[S_N] = {"uniform sphere", "cosine", "light: CELL_AVERAGE (ours)", "light: CELL_AVERAGE 2x",
                                  "light: PBRT_V3 (2x)",
                                  "light: TEXEL (issue #62)", "compensated + MIS (pair)", "light: alias sampler",
                                  "light: BILINEAR (warp)"};

static void frame(const double n[3], double b1[3], double b2[3]) {
  double t[3] = {1, 0, 0}, d, len;
  if (fabs(n[0]) > 0.9) { t[0] = 0; t[1] = 1; }
  d = t[0] * n[0] + t[1] * n[1] + t[2] * n[2];
  b1[0] = t[0] - d * n[0]; b1[1] = t[1] - d * n[1]; b1[2] = t[2] - d * n[2];
  len = sqrt(b1[0] * b1[0] + b1[1] * b1[1] + b1[2] * b1[2]);
  b1[0] /= len; b1[1] /= len; b1[2] /= len;
  b2[0] = n[1] * b1[2] - n[2] * b1[1]; b2[1] = n[2] * b1[0] - n[0] * b1[2]; b2[2] = n[0] * b1[1] - n[1] * b1[0];
}

/* One estimate of E(n) with strategy s from 2 (or 4) uniform numbers u. */
static double estimate(int s, el_envlight *l, const double n[3], const double b1[3], const double b2[3], const float *u) {
  float wi[3], L[3], p;
  double c;
  if (s == S_UNIFORM) {
    double z = 1 - 2.0 * u[0], r = sqrt(fmax(0.0, 1 - z * z)), ph = 2 * PI * u[1];
    wi[0] = (float)(r * cos(ph)); wi[1] = (float)(r * sin(ph)); wi[2] = (float)z;
    c = n[0] * wi[0] + n[1] * wi[1] + n[2] * wi[2];
    if (c <= 0) return 0;
    el_envlight_le(l, wi, L);
    return lum3(L[0], L[1], L[2]) * c * 4 * PI;
  }
  if (s == S_COSINE || s == S_COMP_MIS) {
    double f = 0;
    double rr = sqrt((double)u[0]), ph = 2 * PI * u[1], lx = rr * cos(ph), ly = rr * sin(ph), lz = sqrt(fmax(0.0, 1 - u[0]));
    wi[0] = (float)(lx * b1[0] + ly * b2[0] + lz * n[0]);
    wi[1] = (float)(lx * b1[1] + ly * b2[1] + lz * n[1]);
    wi[2] = (float)(lx * b1[2] + ly * b2[2] + lz * n[2]);
    if (lz > 0) {
      el_envlight_le(l, wi, L);
      if (s == S_COSINE) return lum3(L[0], L[1], L[2]) * PI;
      p = el_envlight_pdf_li(l, wi);
      f = lum3(L[0], L[1], L[2]) * lz / (lz / PI + p); /* balance heuristic, one sample of each */
    }
    /* and the light sample of the pair */
    el_envlight_sample_li(l, u + 2, wi, L, &p);
    c = n[0] * wi[0] + n[1] * wi[1] + n[2] * wi[2];
    if (p > 0 && c > 0) f += lum3(L[0], L[1], L[2]) * c / (p + c / PI);
    return f;
  }
  el_envlight_sample_li(l, u, wi, L, &p);
  if (!(p > 0)) return 0;
  c = n[0] * wi[0] + n[1] * wi[1] + n[2] * wi[2];
  if (c <= 0) return 0;
  return lum3(L[0], L[1], L[2]) * c / p;
}

/* PCG32 (bench_common.h's rng) for the variance runs (independent streams per strategy and normal) */

typedef double (*estimator)(int s, el_envlight *l, const double n[3], const double b1[3], const double b2[3], const float *u);
/* the mean and variance of nsamp irradiance estimates est(s, l, n, ...) for the normal n, from the
 * random stream of (s, k): the variance table and the --csv runs draw the same numbers */
static void moments(estimator est, int s, int k, el_envlight *l, const double n[3], long nsamp, double *mean, double *var) {
  double b1[3], b2[3], sum = 0, sum2 = 0;
  long i;
  rng r;
  r.s = 0x853c49e6748fea9bULL + 7919u * (uint64_t)(s * 3 + k);
  frame(n, b1, b2);
  for (i = 0; i < nsamp; ++i) {
    float u[4];
    double f;
    u[0] = rng_f(&r); u[1] = rng_f(&r); u[2] = rng_f(&r); u[3] = rng_f(&r);
    f = est(s, l, n, b1, b2, u);
    sum += f; sum2 += f * f;
  }
  *mean = sum / nsamp;
  *var = fmax(0.0, sum2 / nsamp - *mean * *mean);
}

static void variance_table(const char *path, int nsamp) {
  el_image img;
  char err[512];
  image im;
  static const double N3[3][3] = {{0, 0, 1}, {1, 0, 0}, {0, 0.6, -0.8}}; /* up, horizon, down-ish (light space) */
  double E[3];
  el_envlight lights[S_N];
  int s, k, ok[S_N];
  double res_rv[S_N][3], res_bias[S_N][3], res_ns[S_N], res_mean[S_N];
  if (el_image_load(path, &img, err, sizeof err) != 0) { printf("  (%s)\n", err); return; }
  im.px = img.pixels; im.w = img.width; im.h = img.height;
  quadrature(&im, N3, 3, E);
  for (s = 0; s < S_N; ++s) {
    int imp = s == S_PBRT ? EL_ENVLIGHT_IMPORTANCE_PBRT_V3 : s == S_TEXEL ? EL_ENVLIGHT_IMPORTANCE_TEXEL :
              s == S_BILIN ? EL_ENVLIGHT_IMPORTANCE_BILINEAR : 0;
    el_envlight_options o;
    memset(&o, 0, sizeof o);
    o.importance = imp;
    o.sampler = s == S_ALIAS ? EL_ENVLIGHT_SAMPLER_ALIAS : EL_ENVLIGHT_SAMPLER_GUIDE;
    o.compensated = s == S_COMP_MIS;
    if (s == S_CELL2) { o.importance_width = 2 * img.width; o.importance_height = 2 * img.height; }
    ok[s] = el_envlight_init(&lights[s], img.pixels, img.width, img.height, 3, &o) == EL_SUCCESS;
    if (ok[s]) el_envlight_prepare_sampling(&lights[s]);
  }
  printf("\n%s (%dx%d): E(up) = %.4g, E(horizon) = %.4g, E(down) = %.4g; %d samples per cell\n", path, img.width,
         img.height, E[0], E[1], E[2], nsamp);
  printf("  %-28s %27s %20s %8s %10s %9s %10s\n", "strategy", "rel. variance (up/hor/down)", "|bias|/SE (u/h/d)", "ns/spl",
         "efficiency", "ns x var", "lum/pdf");
  for (s = 0; s < S_N; ++s) {
    double *rv = res_rv[s], *bias = res_bias[s], t, mean_rv = 0;
    if (!ok[s]) continue;
    t = process_now();
    for (k = 0; k < 3; ++k) {
      double mean, var;
      moments(estimate, s, k, &lights[s], N3[k], nsamp, &mean, &var);
      rv[k] = var / (E[k] * E[k]);
      bias[k] = fabs(mean - E[k]) / sqrt(var / nsamp + 1e-300);
      mean_rv += rv[k] / 3;
    }
    res_ns[s] = (process_now() - t) / (3.0 * nsamp) * 1e9;
    res_mean[s] = mean_rv;
  }
  for (s = 0; s < S_N; ++s) {
    if (!ok[s]) { printf("  %-28s init failed\n", S_NAME[s]); continue; }
    printf("  %-28s %8.3g %8.3g %8.3g  %6.1f %6.1f %6.1f %8.0f %10.3g %9.3g", S_NAME[s], res_rv[s][0], res_rv[s][1],
           res_rv[s][2], res_bias[s][0], res_bias[s][1], res_bias[s][2], res_ns[s],
           ok[S_CELL] ? (res_mean[S_CELL] * res_ns[S_CELL]) / (res_mean[s] * res_ns[s]) : 0.0, res_mean[s] * res_ns[s]);
    if (s >= S_CELL && s != S_COMP_MIS) { /* how well the density matches le alone: rel. variance of lum(le)/pdf */
      double sum = 0, sum2 = 0, m;
      long i;
      rng r;
      r.s = 0x1234567ULL + (uint64_t)s;
      for (i = 0; i < nsamp; ++i) {
        float u[2], wi[3], L[3], p;
        double f = 0;
        u[0] = rng_f(&r); u[1] = rng_f(&r);
        el_envlight_sample_li(&lights[s], u, wi, L, &p);
        if (p > 0) f = lum3(L[0], L[1], L[2]) / p;
        sum += f; sum2 += f * f;
      }
      m = sum / nsamp;
      printf(" %10.3g", m > 0 ? fmax(0.0, sum2 / nsamp - m * m) / (m * m) : 0.0);
    }
    printf("\n");
  }
  for (s = 0; s < S_N; ++s) if (ok[s]) el_envlight_free(&lights[s]);
  el_image_free(&img);
}

/* ---- product sampling: variance by orientation, against plain light sampling ---- */
/* The strategies of table 4: light sampling alone (one sample) or with MIS (one light sample + one
 * cosine sample, balance heuristic, as the renderer does), for sample_li (CELL_AVERAGE), sample_li in
 * importance BILINEAR (the warp) and sample_li_cos (the warp x the cosine bound). */
enum { P_PLAIN, P_BILIN, P_COS, P_N };
static const char *P_NAME[P_N] = {"sample_li (CELL_AVERAGE)", "sample_li (BILINEAR warp)", "sample_li_cos (product)"};
static double p_estimate(int s, int mis, el_envlight *l, const double n[3], const float nf[3], const double b1[3], const double b2[3], const float *u, int *below) {
  float wi[3], L[3], p;
  double c, f = 0;
  if (s == P_COS) el_envlight_sample_li_cos(l, nf, u, wi, L, &p);
  else el_envlight_sample_li(l, u, wi, L, &p);
  if (p > 0) {
    c = n[0] * wi[0] + n[1] * wi[1] + n[2] * wi[2];
    if (c > 0) f = lum3(L[0], L[1], L[2]) * c / (mis == 2 ? p * (1 + (c / PI) * (c / PI) / (p * p)) : mis ? p + c / PI : p);
    else ++*below;
  }
  if (mis) { /* the cosine (BSDF) sample of the pair, weighted with the strategy's own pdf */
    double rr = sqrt((double)u[2]), ph = 2 * PI * u[3], lx = rr * cos(ph), ly = rr * sin(ph), lz = sqrt(fmax(0.0, 1 - u[2]));
    wi[0] = (float)(lx * b1[0] + ly * b2[0] + lz * n[0]);
    wi[1] = (float)(lx * b1[1] + ly * b2[1] + lz * n[1]);
    wi[2] = (float)(lx * b1[2] + ly * b2[2] + lz * n[2]);
    if (lz > 0) {
      p = s == P_COS ? el_envlight_pdf_li_cos(l, nf, wi) : el_envlight_pdf_li(l, wi);
      el_envlight_le(l, wi, L);
      f += lum3(L[0], L[1], L[2]) * lz / (mis == 2 ? (lz / PI) * (1 + p * p / ((lz / PI) * (lz / PI))) : lz / PI + p);
    }
  }
  return f;
}
#define PN 6
static const char *PN_NAME[PN] = {"up", "down", "side+x", "side+y", "sun", "away"};
static void product_table(const char *path, int nsamp) {
  el_image img;
  char err[512];
  image im;
  double N[PN][3], E[PN], best = -1, t0;
  el_envlight lights[P_N];
  int s, k, x, y, mis;
  if (el_image_load(path, &img, err, sizeof err) != 0) { printf("  (%s)\n", err); return; }
  im.px = img.pixels; im.w = img.width; im.h = img.height;
  memset(N, 0, sizeof N);
  N[0][2] = 1; N[1][2] = -1; N[2][0] = 1; N[3][1] = 1;
  for (y = 0; y < img.height; ++y) /* "sun": the brightest texel's direction */
    for (x = 0; x < img.width; ++x) {
      double v = img_lum(&im, x, y);
      if (v > best) {
        double uu = (x + 0.5) / img.width, vv = (y + 0.5) / img.height;
        best = v;
        N[4][0] = sin(PI * vv) * cos(2 * PI * uu); N[4][1] = sin(PI * vv) * sin(2 * PI * uu); N[4][2] = cos(PI * vv);
      }
    }
  for (k = 0; k < 3; ++k) N[5][k] = -N[4][k];
  quadrature(&im, (const double(*)[3])N, PN, E);
  printf("\n%s (%dx%d), brightest texel %.3g at theta %.0f deg; %d samples per cell\n", path, img.width, img.height, best,
         acos(N[4][2]) * 180 / PI, nsamp);
  for (s = 0; s < P_N; ++s) {
    el_envlight_options o;
    memset(&o, 0, sizeof o);
    o.importance = s == P_BILIN ? EL_ENVLIGHT_IMPORTANCE_BILINEAR : 0;
    el_envlight_init(&lights[s], img.pixels, img.width, img.height, 3, &o);
    t0 = process_now();
    if (s == P_COS) el_envlight_prepare_product(&lights[s], NULL); else el_envlight_prepare_sampling(&lights[s]);
    printf("  %-26s tables %6.1f ms, %6.2f MB\n", P_NAME[s], (process_now() - t0) * 1e3,
           (el_envlight_sampling_bytes(&lights[s]) + el_envlight_product_bytes(&lights[s])) / 1048576.0);
  }
  printf("  %-26s %-5s", "relative variance per", "");
  for (k = 0; k < PN; ++k) printf(" %8s", PN_NAME[k]);
  printf(" %8s %7s %7s %10s %9s\n", "geomean", "below", "ns", "efficiency", "ns x var");
  for (mis = 0; mis < 3; ++mis) {
    double ref = 0;
    for (s = 0; s < P_N; ++s) {
      double rv[PN], lg = 0, nbelow = 0, t;
      t = process_now();
      for (k = 0; k < PN; ++k) {
        double b1[3], b2[3], sum = 0, sum2 = 0, mean;
        float nf[3];
        long i;
        int below = 0;
        rng r;
        r.s = 0x853c49e6748fea9bULL + 7919u * (uint64_t)(s * PN + k);
        frame(N[k], b1, b2);
        nf[0] = (float)N[k][0]; nf[1] = (float)N[k][1]; nf[2] = (float)N[k][2];
        for (i = 0; i < nsamp; ++i) {
          float u[4];
          double f;
          u[0] = rng_f(&r); u[1] = rng_f(&r); u[2] = rng_f(&r); u[3] = rng_f(&r);
          f = p_estimate(s, mis, &lights[s], N[k], nf, b1, b2, u, &below);
          sum += f; sum2 += f * f;
        }
        mean = sum / nsamp;
        rv[k] = fmax(0.0, sum2 / nsamp - mean * mean) / (E[k] * E[k]);
        lg += log(rv[k] > 0 ? rv[k] : 1e-30) / PN;
        nbelow += (double)below / nsamp / PN;
      }
      t = (process_now() - t) / (PN * (double)nsamp) * 1e9;
      if (s == 0) ref = exp(lg) * t;
      printf("  %-26s %-5s", P_NAME[s], mis == 2 ? "+MISp" : mis ? "+MIS" : "light");
      for (k = 0; k < PN; ++k) printf(" %8.3g", rv[k]);
      printf(" %8.3g %6.1f%% %7.0f %10.3g %9.3g\n", exp(lg), 100 * nbelow, t, ref / (exp(lg) * t), exp(lg) * t);
    }
  }
  for (s = 0; s < P_N; ++s) el_envlight_free(&lights[s]);
  el_image_free(&img);
}

/* Stratification: the variance of a 256-sample estimate with 16x16 jittered u against independent u,
 * over 400 repeats; a warp that keeps stratification keeps much of the jittered points' advantage. */
static void strat_table(const char *path) {
  el_image img;
  char err[512];
  el_envlight lights[P_N];
  static const double NS[2][3] = {{0, 0, 1}, {0.6, 0, -0.8}};
  int s, k;
  if (el_image_load(path, &img, err, sizeof err) != 0) { printf("  (%s)\n", err); return; }
  printf("  %s:", path);
  for (s = 0; s < P_N; ++s) {
    el_envlight_options o;
    memset(&o, 0, sizeof o);
    o.importance = s == P_BILIN ? EL_ENVLIGHT_IMPORTANCE_BILINEAR : 0;
    el_envlight_init(&lights[s], img.pixels, img.width, img.height, 3, &o);
  }
  for (k = 0; k < 2; ++k)
    for (s = 0; s < P_N; ++s) {
      double var[2];
      int st;
      float nf[3];
      nf[0] = (float)NS[k][0]; nf[1] = (float)NS[k][1]; nf[2] = (float)NS[k][2];
      for (st = 0; st < 2; ++st) {
        double sum = 0, sum2 = 0, m;
        int rep, i;
        rng r;
        r.s = 0x1234567ULL + (uint64_t)(k * 10 + s);
        for (rep = 0; rep < 400; ++rep) {
          double est = 0;
          for (i = 0; i < 256; ++i) {
            float u[2], wi[3], L[3], p;
            double c;
            if (st) { u[0] = ((i % 16) + rng_f(&r)) / 16.0f; u[1] = ((i / 16) + rng_f(&r)) / 16.0f; }
            else { u[0] = rng_f(&r); u[1] = rng_f(&r); }
            if (s == P_COS) el_envlight_sample_li_cos(&lights[s], nf, u, wi, L, &p);
            else el_envlight_sample_li(&lights[s], u, wi, L, &p);
            c = NS[k][0] * wi[0] + NS[k][1] * wi[1] + NS[k][2] * wi[2];
            if (p > 0 && c > 0) est += lum3(L[0], L[1], L[2]) * c / p;
          }
          est /= 256;
          sum += est; sum2 += est * est;
        }
        m = sum / 400;
        var[st] = fmax(1e-300, sum2 / 400 - m * m);
      }
      printf(" %s %s %.2fx;", k ? "n=(0.6,0,-0.8)" : "up", s == P_PLAIN ? "sample_li" : s == P_BILIN ? "BILINEAR" : "li_cos",
             var[0] / var[1]);
    }
  printf("\n");
  for (s = 0; s < P_N; ++s) el_envlight_free(&lights[s]);
  el_image_free(&img);
}

/* ---- --csv: the numbers bench/report.py plots (docs/accuracy-vs-time.md) ----
 *   envvar,MAP,STRATEGY,relvar,ns,relbias2   relative variance per estimate of E(n) (mean over the three
 *       normals of table 3), CPU ns per estimate (median of interleaved runs), squared relative bias
 *       (mean over the normals of ((mean - E) / E)^2, against the quadrature; noise included).
 *   envbuild,IMPORTANCE,WIDTH,ms,bytes       init + the sampling tables for a generated WIDTH x WIDTH/2
 *       city-like map (make_map), CPU ms (median of 3 interleaved runs; 1 above 2048), el_envlight_bytes. */
enum { C_UNIFORM, C_COSINE, C_CELL, C_CELL2, C_PBRT, C_TEXEL, C_BILIN, C_PROD, C_MIS, C_MIS_COMP, C_N };
static const char *C_NAME[C_N] = {"uniform sphere", "cosine (BSDF)", "CELL_AVERAGE (default)", "CELL_AVERAGE 2x",
                                  "PBRT_V3 2x (pbrt-v3)", "TEXEL", "BILINEAR (patches)",
                                  "product sample_li_cos", "MIS pair (light + cosine)", "MIS pair compensated"};
static double c_estimate(int s, el_envlight *l, const double n[3], const double b1[3], const double b2[3], const float *u) {
  static const int to_s[C_N] = {S_UNIFORM, S_COSINE, S_CELL, S_CELL2, S_PBRT, S_TEXEL, S_BILIN, 0, S_COMP_MIS, S_COMP_MIS};
  if (s == C_PROD) {
    float nf[3];
    int below = 0;
    nf[0] = (float)n[0]; nf[1] = (float)n[1]; nf[2] = (float)n[2];
    return p_estimate(P_COS, 0, l, n, nf, b1, b2, u, &below);
  }
  return estimate(to_s[s], l, n, b1, b2, u);
}
static void csv_variance(const char *path, const char *name, int nsamp, int reps) {
  static const double N3[3][3] = {{0, 0, 1}, {1, 0, 0}, {0, 0.6, -0.8}};
  el_image img;
  char err[512];
  image im;
  double E[3], t[C_N][16];
  el_envlight lights[C_N];
  int s, k, r;
  if (el_image_load(path, &img, err, sizeof err) != 0) { fprintf(stderr, "bench_envlight: %s\n", err); return; }
  im.px = img.pixels; im.w = img.width; im.h = img.height;
  quadrature(&im, N3, 3, E);
  for (s = 0; s < C_N; ++s) {
    el_envlight_options o;
    memset(&o, 0, sizeof o);
    o.importance = s == C_PBRT ? EL_ENVLIGHT_IMPORTANCE_PBRT_V3 : s == C_TEXEL ? EL_ENVLIGHT_IMPORTANCE_TEXEL :
                   s == C_BILIN ? EL_ENVLIGHT_IMPORTANCE_BILINEAR : 0;
    o.compensated = s == C_MIS_COMP;
    if (s == C_CELL2) { o.importance_width = 2 * img.width; o.importance_height = 2 * img.height; }
    if (el_envlight_init(&lights[s], img.pixels, img.width, img.height, 3, &o) != EL_SUCCESS) {
      fprintf(stderr, "bench_envlight: %s: init failed for %s\n", path, C_NAME[s]);
      exit(1);
    }
    if (s == C_PROD) el_envlight_prepare_product(&lights[s], NULL);
    else el_envlight_prepare_sampling(&lights[s]);
  }
  for (r = 0; r < reps; ++r) /* timing: every strategy in turn, reps times */
    for (s = 0; s < C_N; ++s) {
      double b1[3], b2[3], acc = 0, t0;
      volatile double sink;
      long i, n = nsamp / 10 + 1;
      rng g;
      g.s = 0x9e3779b97f4a7c15ULL + (uint64_t)r;
      frame(N3[0], b1, b2);
      t0 = cpu_now();
      for (i = 0; i < n; ++i) {
        float u[4];
        u[0] = rng_f(&g); u[1] = rng_f(&g); u[2] = rng_f(&g); u[3] = rng_f(&g);
        acc += c_estimate(s, &lights[s], N3[0], b1, b2, u);
      }
      t[s][r] = (cpu_now() - t0) * 1e9 / (double)n;
      sink = acc;
      (void)sink;
    }
  for (s = 0; s < C_N; ++s) {
    double rv = 0, rb2 = 0;
    for (k = 0; k < 3; ++k) {
      double mean, var;
      moments(c_estimate, s, k, &lights[s], N3[k], nsamp, &mean, &var);
      rv += var / (E[k] * E[k]) / 3;
      rb2 += (mean - E[k]) * (mean - E[k]) / (E[k] * E[k]) / 3;
    }
    printf("envvar,%s,%s,%.6g,%.3f,%.6g\n", name, C_NAME[s], rv, median(t[s], reps), rb2);
    fflush(stdout);
  }
  for (s = 0; s < C_N; ++s) el_envlight_free(&lights[s]);
  el_image_free(&img);
}
static void csv_build(int quick) {
  static const char *name[5] = {"CELL_AVERAGE (default)", "PBRT_V3 2x (pbrt-v3)", "TEXEL", "BILINEAR (patches)",
                                "product sample_li_cos"};
  int widths[5] = {512, 1024, 2048, 4096, 8192}, nw = quick ? 2 : 5, k, imp, r;
  for (k = 0; k < nw; ++k) {
    int w = widths[k], h = w / 2, reps = w > 2048 ? 1 : 3;
    float *px = make_map(w, h);
    double t[5][3];
    size_t bytes[5] = {0, 0, 0, 0, 0};
    for (r = 0; r < reps; ++r)
      for (imp = 0; imp < 5; ++imp) {
        el_envlight l;
        double t0;
        if (imp == EL_ENVLIGHT_IMPORTANCE_PBRT_V3 && w > 4096) continue; /* 16384 x 8192 bins */
        t0 = cpu_now();
        if (make_light(&l, px, w, h, imp == 4 ? 0 : imp, 0, 0, NULL) != EL_SUCCESS) exit(1);
        if (imp == 4) el_envlight_prepare_product(&l, NULL);
        else el_envlight_prepare_sampling(&l);
        t[imp][r] = (cpu_now() - t0) * 1e3;
        bytes[imp] = el_envlight_bytes(&l);
        el_envlight_free(&l);
      }
    for (imp = 0; imp < 5; ++imp)
      if (bytes[imp]) printf("envbuild,%s,%d,%.3f,%zu\n", name[imp], w, median(t[imp], reps), bytes[imp]);
    fflush(stdout);
    free(px);
  }
}
/* The CC0 map `name`: map_dir/name.hdr, else the repository's copy (data/envmaps has city and studio);
 * 0 when neither exists. */
static int map_path(char *path, size_t n, const char *map_dir, const char *name) {
  FILE *f;
  snprintf(path, n, "%s/%s.hdr", map_dir, name);
  f = fopen(path, "rb");
  if (f) { fclose(f); return 1; }
  if (strcmp(name, "city") && strcmp(name, "studio")) return 0;
  snprintf(path, n, "%s/data/envmaps/%s.hdr", EL_SOURCE_DIR, name);
  return 1;
}
static int csv_mode(const char *src, int quick) {
  char path[600];
  printf("kind,a,b,c,d,e\n");
  snprintf(path, sizeof path, "%s/data/envmaps/city.hdr", src);
  csv_variance(path, "city (sun)", quick ? 20000 : 400000, quick ? 3 : 7);
  snprintf(path, sizeof path, "%s/data/envmaps/studio.hdr", src);
  csv_variance(path, "studio (smooth)", quick ? 20000 : 400000, quick ? 3 : 7);
  csv_build(quick);
  return 0;
}

int main(int argc, char **argv) {
  int sizes[3][2] = {{1024, 512}, {2048, 1024}, {8192, 4096}}, nsizes = 3, use_cg = 1, nsamp = 200000, i;
  const char *maps[5] = {"city", "forest", "night", "studio", "sunset"};
  char map_dir[400];
  /* the CC0 maps: EL_ENVMAPS, else ../shared/envmaps next to the repository (data/envmaps has city, studio) */
  if (getenv("EL_ENVMAPS")) snprintf(map_dir, sizeof map_dir, "%s", getenv("EL_ENVMAPS"));
  else snprintf(map_dir, sizeof map_dir, "%s/../shared/envmaps", EL_SOURCE_DIR);
#ifdef __GLIBC__
  mallopt(M_MMAP_THRESHOLD, 1 << 20);
#endif
  if (argc >= 4 && !strcmp(argv[1], "--callgrind")) return callgrind_mode(argv[2], atol(argv[3]), argc >= 5 ? argv[4] : NULL);
  if (argc >= 2 && !strcmp(argv[1], "--csv")) { make_random(); return csv_mode(EL_SOURCE_DIR, argc >= 3 && !strcmp(argv[2], "--quick")); }
  if (argc == 2 && !strcmp(argv[1], "--product")) { /* tables 4 and 5 only */
    make_random();
    for (i = 0; i < 5; ++i) {
      char path[512 + 64];
      if (!map_path(path, sizeof path, map_dir, maps[i])) continue;
      product_table(path, nsamp);
    }
    for (i = 0; i < 5; i += 3) {
      char path[512 + 64];
      if (!map_path(path, sizeof path, map_dir, maps[i])) continue;
      strat_table(path);
    }
    return 0;
  }
  if (argc == 2 && !strcmp(argv[1], "--no-callgrind")) use_cg = 0;
  else if (argc == 2 && !strcmp(argv[1], "--quick")) { use_cg = 0; nsizes = 2; nsamp = 50000; }
  else if (argc != 1) { fprintf(stderr, "usage: %s [--no-callgrind | --quick | --product | --callgrind OP N [MAP]]\n", argv[0]); return 2; }
  if (use_cg && system("valgrind --version >/dev/null 2>&1") != 0) { printf("(valgrind not found: no instruction counts)\n"); use_cg = 0; }
  make_random();

  printf("1. Build, memory and throughput (generated city-like maps, one thread, -O3, CPU time, best of 3; every\n"
         "   build gets fresh memory from the system, its page faults included as in pbrt's constructor)\n");
  printf("   pbrt-v3 reference (issue 3, 2048x1024): constructor 313 ms, ~100 MB, Sample_Li 5.2 M/s\n");
  for (i = 0; i < nsizes; ++i) {
    int w = sizes[i][0], h = sizes[i][1], imp;
    float *px = make_map(w, h);
    printf("\n  %d x %d\n", w, h);
    printf("  %-22s %9s %10s %10s %10s %10s\n", "importance map", "init ms", "sampling", "bins", "table MB", "total MB");
    for (imp = 0; imp < 5; ++imp) { /* 3: BILINEAR (the warp); 4: the product tables (warp + normal tables) */
      el_envlight l;
      double t0, t1 = 1e30, t2 = 1e30;
      int rep;
      if (imp == EL_ENVLIGHT_IMPORTANCE_PBRT_V3 && w > 2048) continue; /* 16384x8192 bins: pbrt's choice, skipped */
      if (imp == 4) {
        for (rep = 0; rep < (w > 2048 ? 1 : 3); ++rep) {
          make_light(&l, px, w, h, 0, 0, 0, NULL);
          t0 = process_now();
          el_envlight_prepare_product(&l, NULL);
          t0 = process_now() - t0; if (t0 < t2) t2 = t0;
          if (rep < (w > 2048 ? 0 : 2)) el_envlight_free(&l);
        }
        printf("  %-22s %9s %7.1f ms %4dx%-5d %10.1f %10.1f\n", "product (sample_li_cos)", "", t2 * 1e3, 64, 32,
               el_envlight_product_bytes(&l) / 1048576.0, el_envlight_bytes(&l) / 1048576.0);
        el_envlight_free(&l);
        continue;
      }
      for (rep = 0; rep < (w > 2048 ? 1 : 3); ++rep) {
        t0 = process_now();
        if (make_light(&l, px, w, h, imp, 0, 0, NULL) != EL_SUCCESS) { printf("  init failed\n"); break; }
        t0 = process_now() - t0; if (t0 < t1) t1 = t0;
        t0 = process_now();
        el_envlight_prepare_sampling(&l);
        t0 = process_now() - t0; if (t0 < t2) t2 = t0;
        if (rep < (w > 2048 ? 0 : 2)) el_envlight_free(&l);
      }
      printf("  %-22s %9.1f %7.1f ms %4dx%-5d %10.1f %10.1f\n",
             imp == 0 ? "CELL_AVERAGE (default)" : imp == 1 ? "PBRT_V3 (2x res)" : imp == 2 ? "TEXEL" : "BILINEAR (patches)", t1 * 1e3, t2 * 1e3,
             l.imp_w, l.imp_h, el_envlight_sampling_bytes(&l) / 1048576.0, el_envlight_bytes(&l) / 1048576.0);
      el_envlight_free(&l);
    }
    {
      int smp;
      printf("  %-22s %12s %14s %12s %12s\n", "sampler", "sample_li M/s", "+radiance M/s", "pdf_li M/s", "le M/s");
      for (smp = 0; smp < 3; ++smp) {
        el_envlight l;
        if (make_light(&l, px, w, h, 0, smp, 0, NULL) != EL_SUCCESS) continue;
        el_envlight_prepare_sampling(&l);
        printf("  %-22s %12.1f %14.1f %12.1f %12.1f\n", smp == EL_ENVLIGHT_SAMPLER_GUIDE ? "guide table (default)" : smp == EL_ENVLIGHT_SAMPLER_CDF ? "CDF" : "alias table",
               rate(fn_sample, &l, 0), rate(fn_sample, &l, 1), rate(fn_pdf, &l, 0), rate(fn_le, &l, 0));
        el_envlight_free(&l);
      }
      { /* importance BILINEAR's sample_li / pdf_li, and product sampling (one normal per call) */
        el_envlight l;
        if (make_light(&l, px, w, h, EL_ENVLIGHT_IMPORTANCE_BILINEAR, 0, 0, NULL) == EL_SUCCESS) {
          el_envlight_prepare_sampling(&l);
          printf("  %-22s %12.1f %14.1f %12.1f %12s\n", "BILINEAR (patches)", rate(fn_sample, &l, 0), rate(fn_sample, &l, 1), rate(fn_pdf, &l, 0), "");
          el_envlight_free(&l);
        }
        if (make_light(&l, px, w, h, 0, 0, 0, NULL) == EL_SUCCESS) {
          el_envlight_prepare_product(&l, NULL);
          printf("  %-22s %12.1f %14.1f %12.1f %12s  (sample_li_cos, pdf_li_cos)\n", "product", rate(fn_sample_cos, &l, 0),
                 rate(fn_sample_cos, &l, 1), rate(fn_pdf_cos, &l, 0), "");
          el_envlight_free(&l);
        }
      }
    }
    if (w == 2048) {
      /* sample_li + radiance inside a loop that does other memory work between samples (see
       * run_interleaved): ns per sample once the other work's own time is taken off */
      el_envlight l;
      if (make_light(&l, px, w, h, 0, EL_ENVLIGHT_SAMPLER_GUIDE, 0, NULL) == EL_SUCCESS) {
        double t_work, t_one, t_batch;
        long k;
        if (!g_pollute) {
          g_pollute = (float *)malloc(sizeof(float) * POLLUTE_N);
          for (k = 0; k < POLLUTE_N; ++k) g_pollute[k] = (float)(k & 7);
        }
        el_envlight_prepare_sampling(&l);
        t_work = 1e3 / rate(run_pollute_only, &l, 0);
        t_one = 1e3 / rate(run_interleaved, &l, 0);
        t_batch = 1e3 / rate(run_interleaved, &l, 1);
        printf("  in a loop with other memory work between samples (%.1f ns per sample of it, taken off):\n"
               "    sample_li + radiance one at a time %5.1f ns;  sample_li_n, 16 at a time %5.1f ns (%.1fx)\n",
               t_work, t_one - t_work, t_batch - t_work, (t_one - t_work) / (t_batch - t_work));
        t_one = 1e3 / rate(run_interleaved, &l, 2);
        t_batch = 1e3 / rate(run_interleaved, &l, 3);
        printf("    pdf_li + le one at a time %5.1f ns;  pdf_li_n + le_n, 16 at a time %5.1f ns (%.1fx)\n",
               t_one - t_work, t_batch - t_work, (t_one - t_work) / (t_batch - t_work));
        printf("  alone (batches of 64): pdf_li %5.1f ns, pdf_li_n %5.1f ns; le %5.1f ns, le_n %5.1f ns\n", 1e3 / rate(fn_pdf, &l, 0),
               1e3 / rate(fn_escape_n, &l, 0), 1e3 / rate(fn_le, &l, 0), 1e3 / rate(fn_escape_n, &l, 1));
        el_envlight_free(&l);
      }
    }
    free(px);
  }

  if (use_cg) {
    static const char *ops[] = {"sample_cdf", "sample_guide", "sample_alias", "sample_guide_rgb", "pdf", "le", "sample_rotated", "pdf_rotated",
                                "sample_bilinear", "sample_bilinear_rgb", "pdf_bilinear", "sample_cos", "sample_cos_rgb", "pdf_cos",
                                "sample_cos_rotated", "pdf_cos_rotated"};
    static const char *what[] = {"sample_li, CDF sampler, no radiance", "sample_li, guide sampler, no radiance",
                                 "sample_li, alias sampler, no radiance", "sample_li, guide sampler, with radiance",
                                 "pdf_li (random directions)", "le (random directions)",
                                 "sample_li, guide, general rotation", "pdf_li, general rotation",
                                 "sample_li, BILINEAR, no radiance", "sample_li, BILINEAR, with radiance", "pdf_li, BILINEAR",
                                 "sample_li_cos, no radiance (random normals)", "sample_li_cos, with radiance",
                                 "pdf_li_cos (random normals, directions)", "sample_li_cos, general rotation",
                                 "pdf_li_cos, general rotation"};
    double loop = instr_per_call(argv[0], "loop", 200000), build = instr_per_call(argv[0], "build", 2);
    double build_p = instr_per_call(argv[0], "build_product", 2), build_b = instr_per_call(argv[0], "build_bilinear", 2);
    unsigned k;
    printf("\n2. Instructions per call (callgrind, 2048x1024, 200000 calls, the loop's %.1f subtracted)\n", loop);
    printf("   targets: sample_li <= 100 without the radiance lookup (pbrt-v3 ~470), pdf_li <= 80 (pbrt-v3 ~300)\n");
    for (k = 0; k < sizeof ops / sizeof ops[0]; ++k) {
      double ipc = instr_per_call(argv[0], ops[k], 200000);
      printf("  %-44s %8.1f\n", what[k], ipc - loop);
    }
    printf("  %-44s %8.1f M (%.1f per texel)\n", "construction: init + tables (default: guide)", build * 1e-6, build / (2048.0 * 1024.0));
    printf("  %-44s %8.1f M (%.1f per texel)\n", "construction: init + BILINEAR's warp", build_b * 1e-6, build_b / (2048.0 * 1024.0));
    printf("  %-44s %8.1f M (%.1f per texel)\n", "construction: init + product tables", build_p * 1e-6, build_p / (2048.0 * 1024.0));
  }

  printf("\n3. Variance of a direct-lighting estimate (irradiance, luminance, of a diffuse point; light space\n"
         "   normals up (0,0,1), horizon (1,0,0), down (0,0.6,-0.8)); efficiency relative to CELL_AVERAGE + guide;\n"
         "   'ns x var' the time-to-unit-variance: the mean relative variance per sample x ns per sample\n");
  for (i = 0; i < 5; ++i) {
    char path[512 + 64];
    if (!map_path(path, sizeof path, map_dir, maps[i])) continue;
    variance_table(path, nsamp);
  }

  printf("\n4. Product sampling (el_envlight_sample_li_cos): relative variance per sample of the irradiance estimate by\n"
         "   normal (light space: up +z, down -z, sideways, facing the brightest texel and away from it); 'light' one\n"
         "   sample of the strategy, '+MIS' one of it and one cosine sample (balance heuristic; '+MISp' power heuristic)\n"
         "   per estimate; 'below' the\n"
         "   light samples below the horizon (wasted); ns per estimate; efficiency 1 / (geomean x ns), normalised to\n"
         "   the first row of each block; 'ns x var' the time-to-unit-variance, geomean x ns (smaller is better)\n");
  for (i = 0; i < 5; ++i) {
    char path[512 + 64];
    if (!map_path(path, sizeof path, map_dir, maps[i])) continue;
    product_table(path, nsamp);
  }
  printf("\n5. Stratification kept by each sampler: Var(256 independent samples) / Var(16x16 jittered), 400 repeats\n");
  for (i = 0; i < 5; i += 3) { /* city, studio */
    char path[512 + 64];
    if (!map_path(path, sizeof path, map_dir, maps[i])) continue;
    strat_table(path);
  }
  return 0;
}
