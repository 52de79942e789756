/* bench_product.c: the research behind el_envlight_sample_li_cos (issue 13): which density close to
 * L(w) max(0, n.w) can be sampled at a constant cost per sample, and what each candidate buys.
 *
 *   bench_product [MAP ...]   the table below for each MAP (default: the five CC0 maps in ../shared/envmaps)
 *   bench_product --picture [OUT.png] [MAP]   where the samples of one shading point land: 2000 of
 *                             el_envlight_sample_li over the lat-long map (default city.hdr from data/envmaps),
 *                             then 2000 of el_envlight_sample_li_cos for a tilted normal, the normal's
 *                             horizon drawn; samples above it yellow, below it red. Written to OUT.png
 *                             (default out/product_samples.png, the folder created) for the tutorial
 *   bench_product --library [MAP ...]   the library's own sampler (el_envlight_sample_li_cos) against
 *                             sample_li: its tables (bytes, build ms: best and median of 5 builds, one
 *                             core), and per normal the relative variance per sample, the time per
 *                             sample (best of 3 runs, interleaved) and the time-to-unit-variance
 *                             (relative variance x ns per sample; lower is better). Default maps: city
 *                             and studio from data/envmaps. NSAMP as below.
 *   bench_product --batch [MAP ...]   el_envlight_sample_li_cos_n and pdf_li_cos_n (n at once, batches of 64)
 *                             against the single calls and sample_li, with a new random normal per sample:
 *                             CPU ns per sample, best of REPS (5) interleaved rounds. Default maps: city
 *                             and studio from data/envmaps.
 *   bench_product --candidates [MAP ...]   issue 20's two unbuilt designs against the library's sampler
 *                             (section "--candidates" below: alias tables in place of the guide-table
 *                             searches; Conty and Lecocq's per-point coarse level, 12x12, 16x8, 16x16):
 *                             tables (MiB), build ms, relative variance per sample (geometric mean over the
 *                             six normals) with independent points and with Owen-scrambled Sobol' points
 *                             (64 per estimate), the estimator's |z| against the quadrature, a chi-square
 *                             of the cell picks, the pdf function checked bit for bit on every 16th sample,
 *                             CPU ns per sample with a new random normal per call (best of REPS, 3,
 *                             interleaved rounds) and relvar x ns. Default maps: city and studio. SEED=n
 *                             shifts the independent streams; VERBOSE=1 prints each normal's z and chi2 z.
 *   bench_product --callgrind OP N [MAP]   N calls of one candidate (OP: loop, lib, alias2, alias4, alias2c, cl12x12,
 *                             cl16x8, cl16x16, + "_pdf", C&L + "_pass"), for bench/callgrind_product.sh:
 *                             OPS="lib alias2 alias4 cl12x12 lib_pdf cl12x12_pdf" sh bench/callgrind_product.sh
 *                             build/bin/bench_product data/envmaps/city.hdr 20000
 *   environment: NSAMP=n (samples per cell, 200000), ONLY=text (only strategies whose name holds it),
 *                MS=a,b,c (the three normal-table sizes, 8,16,32), BUILD=digits (build only tables
 *                3 * cells index + size index), DENSE=1 (an optimistic, NOT conservative bound: the
 *                maximum over 9x9 normals of each bin, to see what a tighter bin bound could buy)
 *
 * Every candidate here is a PROTOTYPE written for clarity (el_distribution2d per cell, le() for the
 * radiance, libm trigonometry, linear scans): its variances are those of the densities, its times are
 * not the library's (bench_envlight measures el_envlight_sample_li_cos, which implements the winner).
 *
 * The candidates. All use cells: a Ku x Kv grid over the map. A shading point with normal n picks a
 * cell with probability proportional to M_c B_c(n), M_c the cell's mass under a density of the map
 * alone and B_c(n) an upper bound of max(0, n.w) over the cell, then a point inside the cell from that
 * density restricted to the cell (CDF inversion at each step, two levels per random number). So the
 * density is the map's density times B_c(n) / sum_c' M_c' B_c'(n): unbiased whenever B_c(n) > 0 for every
 * cell that holds a direction above the surface. Two densities of the map:
 *  - (bins)  the light's own piecewise-constant density (cell averages of the bilinear le() x sin);
 *  - "warp"  the bilinear interpolant of le()'s luminance x sin(theta) at the texel centres (Mitsuba 3's
 *            density), sampled by marginal-conditional inversion of its bilinear patches (the cells are
 *            groups of patches). It follows the radiance le() returns inside each texel.
 * and three kinds of bound:
 *  - plain        no cosine: sample_li itself, and the warp alone (importance BILINEAR): the reference.
 *  - exact KuxKv  B_c(n) = max over the cell of n.w, exactly, per shading point (a spherical rectangle:
 *                 the best phi, then the peak of a sin(theta) + b cos(theta) on the cell's theta range).
 *                 O(Ku Kv) work per shading point (Conty and Lecocq 2018 build such a CDF per point over
 *                 12x12 equal-area cells): the best any per-point scheme gets at that cell size.
 *  - table MxM KuxKv  tables over an octahedral grid of M x M normal bins: B_bc = cos(max(0, angle from
 *                 the bin's centre normal to the nearest point of the cell - the bin's angular radius)),
 *                 an upper bound for every normal of the bin. A sample costs a table lookup and searches.
 *  - MIS: one sample of the strategy + one cosine-weighted sample, balance heuristic (the renderer's
 *         way to add the BSDF sample).
 * Hierarchical warping of the product (Clarberg et al. 2005) needs a product map per shading point
 * (O(cells) work, as "exact", on a pyramid): its variance is that of "exact" at its finest level.
 *
 * Output per map: for each normal (light space: up +z, down -z, sideways +x and +y, facing the map's
 * brightest texel ("sun") and away from it) the relative variance per sample of the irradiance estimate
 * (luminance) Var / E^2, E from a quadrature of the bilinear reconstruction; their geometric mean; the
 * fraction of light samples below the horizon; the tables' memory and build time (prototype).
 */
#define _POSIX_C_SOURCE 199309L
#define EL_IMPLEMENTATION
#include "envlight.h"
#include "image_io.h"
#include "picture.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#ifndef EL_SOURCE_DIR
#define EL_SOURCE_DIR "."
#endif

static const double PI = 3.14159265358979323846;
#include "bench_common.h" /* rng, rng_f (PCG32), process_now, make_parent_dir */
static double lum3(const float *c) { return 0.212671 * c[0] + 0.715160 * c[1] + 0.072169 * c[2]; }
static double dot3(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/* ---- the maximum of n.w over a lat-long cell [phi0, phi1] x [theta0, theta1] (light space) ---- */
static double cell_maxcos(const double n[3], double phi0, double phi1, double th0, double th1) {
  double r = sqrt(n[0] * n[0] + n[1] * n[1]), c, a, b, best, t;
  double pn = atan2(n[1], n[0]);
  /* the best phi: the normal's own if it is inside the interval (mod 2 pi), else the nearer end */
  double d0 = pn - phi0;
  d0 -= 2 * PI * floor(d0 / (2 * PI));
  if (d0 <= phi1 - phi0) c = 1.0;
  else c = fmax(cos(phi0 - pn), cos(phi1 - pn));
  a = r * c; b = n[2];
  best = fmax(a * sin(th0) + b * cos(th0), a * sin(th1) + b * cos(th1));
  t = atan2(a, b); /* the maximum of a sin + b cos over all theta */
  if (t >= th0 && t <= th1) best = sqrt(a * a + b * b);
  return best;
}

/* ---- octahedral normal bins ---- */
static void oct_encode(const double n[3], double *u, double *v) {
  double s = fabs(n[0]) + fabs(n[1]) + fabs(n[2]), x = n[0] / s, y = n[1] / s;
  if (n[2] < 0) {
    double ax = fabs(x), ay = fabs(y);
    x = (1 - ay) * (n[0] >= 0 ? 1 : -1);
    y = (1 - ax) * (n[1] >= 0 ? 1 : -1);
  }
  *u = 0.5 * (x + 1); *v = 0.5 * (y + 1);
}
static void oct_decode(double u, double v, double n[3]) {
  double x = 2 * u - 1, y = 2 * v - 1, z = 1 - fabs(x) - fabs(y), len;
  if (z < 0) {
    double ax = fabs(x), ay = fabs(y);
    x = (1 - ay) * (x >= 0 ? 1 : -1);
    y = (1 - ax) * (y >= 0 ? 1 : -1);
  }
  len = sqrt(x * x + y * y + z * z);
  n[0] = x / len; n[1] = y / len; n[2] = z / len;
}
static int oct_bin(const double n[3], int m) {
  double u, v;
  int i, j;
  oct_encode(n, &u, &v);
  i = (int)(u * m); j = (int)(v * m);
  if (i > m - 1) i = m - 1;
  if (j > m - 1) j = m - 1;
  return j * m + i;
}
/* the bin's centre direction and an angular radius covering every normal of the bin (the farthest
 * point of the bin's boundary, sampled densely, plus the largest spacing of the samples) */
static void oct_cone(int b, int m, double c[3], double *radius) {
  int i = b % m, j = b / m, e, k, S = 64;
  double worst = 0, gap = 0, prev[3] = {0, 0, 1}, first[3] = {0, 0, 1};
  oct_decode((i + 0.5) / m, (j + 0.5) / m, c);
  for (e = 0; e < 4; ++e)
    for (k = 0; k < S; ++k) {
      double t = (double)k / S, u, v, d[3];
      if (e == 0) { u = i + t; v = j; }
      else if (e == 1) { u = i + 1; v = j + t; }
      else if (e == 2) { u = i + 1 - t; v = j + 1; }
      else { u = i; v = j + 1 - t; }
      oct_decode(u / m, v / m, d);
      worst = fmax(worst, acos(fmin(1.0, dot3(c, d))));
      if (e || k) gap = fmax(gap, acos(fmin(1.0, dot3(prev, d))));
      else memcpy(first, d, sizeof first);
      memcpy(prev, d, sizeof prev);
    }
  gap = fmax(gap, acos(fmin(1.0, dot3(prev, first))));
  *radius = worst + gap + 1e-4;
}

/* ---- cells ---- */
typedef struct {
  int ku, kv, nu, nv;
  int *x0, *y0;           /* ku + 1, kv + 1 bin boundaries */
  int *cu_of, *cv_of;     /* nu, nv: the cell column / row of a bin */
  el_distribution2d *cell;/* kv * ku: the light's density inside the cell */
  double *mass;           /* kv * ku */
  double build_s;
  size_t bytes;
} cells;
/* pmf of every bin of the light's distribution (bins = texels here), from its pdf table */
static double bin_pmf(const el_envlight *l, int i, int j) {
  return (double)l->pdf_table[(size_t)j * l->dist.nu + i] * (2 * PI * PI) / ((double)l->dist.nu * l->dist.nv);
}
static void cells_init(cells *c, const el_envlight *l, int ku, int kv) {
  int nu = l->dist.nu, nv = l->dist.nv, a, b, i, j;
  double t = process_now();
  float *f;
  c->ku = ku; c->kv = kv; c->nu = nu; c->nv = nv;
  c->x0 = (int *)malloc((ku + 1) * sizeof(int)); c->y0 = (int *)malloc((kv + 1) * sizeof(int));
  c->cu_of = (int *)malloc(nu * sizeof(int)); c->cv_of = (int *)malloc(nv * sizeof(int));
  for (a = 0; a <= ku; ++a) c->x0[a] = (int)((long)a * nu / ku);
  for (b = 0; b <= kv; ++b) c->y0[b] = (int)((long)b * nv / kv);
  for (a = 0; a < ku; ++a) for (i = c->x0[a]; i < c->x0[a + 1]; ++i) c->cu_of[i] = a;
  for (b = 0; b < kv; ++b) for (j = c->y0[b]; j < c->y0[b + 1]; ++j) c->cv_of[j] = b;
  c->cell = (el_distribution2d *)calloc((size_t)ku * kv, sizeof(el_distribution2d));
  c->mass = (double *)calloc((size_t)ku * kv, sizeof(double));
  f = (float *)malloc((size_t)nu * nv * sizeof(float));
  c->bytes = 0;
  for (b = 0; b < kv; ++b)
    for (a = 0; a < ku; ++a) {
      int w = c->x0[a + 1] - c->x0[a], h = c->y0[b + 1] - c->y0[b];
      double m = 0;
      for (j = 0; j < h; ++j)
        for (i = 0; i < w; ++i) {
          double p = bin_pmf(l, c->x0[a] + i, c->y0[b] + j);
          f[j * w + i] = (float)p;
          m += p;
        }
      c->mass[b * ku + a] = m;
      el_distribution2d_init(&c->cell[b * ku + a], f, w, h, NULL);
      c->bytes += el_distribution2d_bytes(&c->cell[b * ku + a]);
    }
  free(f);
  c->build_s = process_now() - t;
}
static void cells_free(cells *c) {
  int k;
  for (k = 0; k < c->ku * c->kv; ++k) el_distribution2d_free(&c->cell[k]);
  free(c->cell); free(c->mass); free(c->x0); free(c->y0); free(c->cu_of); free(c->cv_of);
}
static void cell_bounds(const cells *c, int a, int b, double *p0, double *p1, double *t0, double *t1) {
  *p0 = 2 * PI * c->x0[a] / c->nu; *p1 = 2 * PI * c->x0[a + 1] / c->nu;
  *t0 = PI * c->y0[b] / c->nv; *t1 = PI * c->y0[b + 1] / c->nv;
}

/* ---- normal tables over any set of ku x kv cells (mass[k], bounds(k)) ---- */
typedef void (*bounds_fn)(const void *cells, int a, int b, double *p0, double *p1, double *t0, double *t1);
typedef struct {
  int m, ku, kv;
  el_distribution2d *tab; /* m*m distributions over the ku x kv cells */
  double build_s;
  size_t bytes;
} ntables;
static void ntables_init(ntables *t, const void *cs, int ku, int kv, const double *mass, bounds_fn bf, int m) {
  int b, k, K = ku * kv;
  float *f = (float *)malloc(K * sizeof(float));
  double t0 = process_now();
  t->m = m; t->ku = ku; t->kv = kv;
  t->tab = (el_distribution2d *)calloc((size_t)m * m, sizeof(el_distribution2d));
  t->bytes = 0;
  for (b = 0; b < m * m; ++b) {
    double cn[3], rad;
    oct_cone(b, m, cn, &rad);
    for (k = 0; k < K; ++k) {
      double p0, p1, th0, th1, mc, ang, bound;
      bf(cs, k % ku, k / ku, &p0, &p1, &th0, &th1);
      if (getenv("DENSE")) { /* not conservative: the maximum over 9x9 normals of the bin (the potential of a tighter bound) */
        int ii, jj;
        bound = 0;
        for (jj = 0; jj <= 8; ++jj)
          for (ii = 0; ii <= 8; ++ii) {
            double nn[3];
            oct_decode((b % m + ii / 8.0) / m, (b / m + jj / 8.0) / m, nn);
            bound = fmax(bound, cell_maxcos(nn, p0, p1, th0, th1));
          }
      } else {
        mc = cell_maxcos(cn, p0, p1, th0, th1);
        ang = acos(fmax(-1.0, fmin(1.0, mc))) - rad;
        bound = ang <= 0 ? 1.0 : ang >= PI / 2 ? 0.0 : cos(ang);
      }
      f[k] = (float)(mass[k] * bound);
    }
    el_distribution2d_init(&t->tab[b], f, ku, kv, NULL);
    t->bytes += el_distribution2d_bytes(&t->tab[b]);
  }
  free(f);
  t->build_s = process_now() - t0;
}
static void ntables_free(ntables *t) {
  int b;
  for (b = 0; b < t->m * t->m; ++b) el_distribution2d_free(&t->tab[b]);
  free(t->tab);
}
static void cells_bf(const void *c, int a, int b, double *p0, double *p1, double *t0, double *t1) { cell_bounds((const cells *)c, a, b, p0, p1, t0, t1); }

/* ---- the continuous warp: the bilinear reconstruction's luminance times sin(theta), as bilinear
 * patches between texel centres (Mitsuba 3's density), sampled per cell by marginal-conditional CDF
 * inversion of the patches (linear marginal in v per patch row, linear conditional in u per patch) ---- */
typedef struct {
  int w, h, ku, kv;
  double *V;      /* (h + 2) vertex rows x w: lum x sin(pi v_k); v_0 = 0, v_k = (k - 0.5) / h, v_{h+1} = 1 */
  double *vk;     /* h + 2 */
  int *a0, *b0;   /* ku + 1 patch column bounds, kv + 1 patch row bounds (patch rows: h + 1) */
  double *S;      /* (h + 2) x ku: per vertex row, the integral over the cell column of the linear interpolant */
  double *mass;   /* kv x ku: the cell's integral of the bilinear density over (u, v) */
  double total;
  int *cu_of, *cv_of; /* per patch column / row */
  double build_s;
  size_t bytes;   /* what the library would store: 4 bytes per vertex (a CDF) + the row sums */
} warp;
static double wlin(double a, double b, double q) { /* t in [0,1] with int_0^t ((1-x) a + x b) = q * (a + b) / 2 */
  double d = a * a + q * (b * b - a * a);
  if (a + b <= 0) return q;
  return q * (a + b) / (a + sqrt(d > 0 ? d : 0));
}
static void warp_init(warp *W, const el_envlight *l, const el_image *im, int ku, int kv) {
  int w = im->width, h = im->height, k, i, a, b;
  double t0 = process_now();
  W->w = w; W->h = h; W->ku = ku; W->kv = kv;
  W->V = (double *)calloc((size_t)(h + 2) * w, sizeof(double));
  W->vk = (double *)malloc((h + 2) * sizeof(double));
  W->S = (double *)calloc((size_t)(h + 2) * ku, sizeof(double));
  W->mass = (double *)calloc((size_t)ku * kv, sizeof(double));
  W->a0 = (int *)malloc((ku + 1) * sizeof(int)); W->b0 = (int *)malloc((kv + 1) * sizeof(int));
  W->cu_of = (int *)malloc(w * sizeof(int)); W->cv_of = (int *)malloc((h + 1) * sizeof(int));
  (void)l;
  for (k = 0; k < h + 2; ++k) {
    W->vk[k] = k == 0 ? 0.0 : k == h + 1 ? 1.0 : (k - 0.5) / h;
    if (k >= 1 && k <= h)
      for (i = 0; i < w; ++i) W->V[(size_t)k * w + i] = lum3(im->pixels + 3 * ((size_t)(k - 1) * w + i)) * sin(PI * W->vk[k]);
  }
  for (a = 0; a <= ku; ++a) W->a0[a] = (int)((long)a * w / ku);
  for (b = 0; b <= kv; ++b) W->b0[b] = (int)((long)b * (h + 1) / kv);
  for (a = 0; a < ku; ++a) for (i = W->a0[a]; i < W->a0[a + 1]; ++i) W->cu_of[i] = a;
  for (b = 0; b < kv; ++b) for (i = W->b0[b]; i < W->b0[b + 1]; ++i) W->cv_of[i] = b;
  for (k = 0; k < h + 2; ++k)
    for (a = 0; a < ku; ++a) {
      double s = 0;
      for (i = W->a0[a]; i < W->a0[a + 1]; ++i) s += 0.5 * (W->V[(size_t)k * w + i] + W->V[(size_t)k * w + (i + 1) % w]) / w;
      W->S[k * ku + a] = s;
    }
  W->total = 0;
  for (b = 0; b < kv; ++b)
    for (a = 0; a < ku; ++a) {
      double m = 0;
      int r;
      for (r = W->b0[b]; r < W->b0[b + 1]; ++r) m += 0.5 * (W->S[r * ku + a] + W->S[(r + 1) * ku + a]) * (W->vk[r + 1] - W->vk[r]);
      W->mass[b * ku + a] = m;
      W->total += m;
    }
  W->bytes = ((size_t)(h + 2) * (w + ku) + (size_t)(h + 2) * ku * 2) * 4;
  W->build_s = process_now() - t0;
}
static void warp_free(warp *W) {
  free(W->V); free(W->vk); free(W->S); free(W->mass); free(W->a0); free(W->b0); free(W->cu_of); free(W->cv_of);
}
/* bilinear density at patch (i, r), fractions (s, t) */
static double warp_bilin(const warp *W, int i, int r, double s, double t) {
  int w = W->w, i1 = (i + 1) % w;
  const double *p = W->V + (size_t)r * w, *q = p + w;
  return (1 - t) * ((1 - s) * p[i] + s * p[i1]) + t * ((1 - s) * q[i] + s * q[i1]);
}
/* sample (u, v) inside cell (a, b) from x in [0,1)^2; returns the density over (u, v) within the cell
 * (bilin / mass_cell) and the light-space direction */
static double warp_sample_cell(const warp *W, int a, int b, double x0, double x1, double d[3], double *st) {
  int ku = W->ku, r, i, w = W->w;
  double m = W->mass[b * ku + a], acc = 0, q = x1 * m, t, tot, s, g0 = 0, g1 = 0, u, v, mr = 0;
  for (r = W->b0[b]; r < W->b0[b + 1]; ++r) {
    mr = 0.5 * (W->S[r * ku + a] + W->S[(r + 1) * ku + a]) * (W->vk[r + 1] - W->vk[r]);
    if (acc + mr > q || r == W->b0[b + 1] - 1) break;
    acc += mr;
  }
  t = wlin(W->S[r * ku + a], W->S[(r + 1) * ku + a], mr > 0 ? fmin(1.0, fmax(0.0, (q - acc) / mr)) : 0.5);
  tot = (1 - t) * W->S[r * ku + a] + t * W->S[(r + 1) * ku + a];
  q = x0 * tot; acc = 0;
  for (i = W->a0[a]; i < W->a0[a + 1]; ++i) {
    g0 = (1 - t) * W->V[(size_t)r * w + i] + t * W->V[(size_t)(r + 1) * w + i];
    g1 = (1 - t) * W->V[(size_t)r * w + (i + 1) % w] + t * W->V[(size_t)(r + 1) * w + (i + 1) % w];
    mr = 0.5 * (g0 + g1) / w;
    if (acc + mr > q || i == W->a0[a + 1] - 1) break;
    acc += mr;
  }
  s = wlin(g0, g1, mr > 0 ? fmin(1.0, fmax(0.0, (q - acc) / mr)) : 0.5);
  u = (i + s + 0.5) / w; if (u >= 1) u -= 1;
  v = W->vk[r] + t * (W->vk[r + 1] - W->vk[r]);
  *st = sin(PI * v);
  d[0] = *st * cos(2 * PI * u); d[1] = *st * sin(2 * PI * u); d[2] = cos(PI * v);
  return warp_bilin(W, i, r, s, t) / m;
}
/* patch, fractions and cell of a light-space direction; returns sin(theta) */
static double warp_locate(const warp *W, const double d[3], int *i, int *r, double *s, double *t) {
  double u = atan2(d[1], d[0]) / (2 * PI), v = acos(fmax(-1.0, fmin(1.0, d[2]))) / PI, x;
  int h = W->h;
  if (u < 0) u += 1;
  x = u * W->w - 0.5; if (x < 0) x += W->w;
  *i = (int)x; if (*i > W->w - 1) *i = W->w - 1;
  *s = x - *i;
  *r = (int)(v * h + 0.5); if (*r > h) *r = h;
  *t = (v - W->vk[*r]) / (W->vk[*r + 1] - W->vk[*r]);
  return sqrt(d[0] * d[0] + d[1] * d[1]);
}
static void warp_cell_bounds(const warp *W, int a, int b, double *p0, double *p1, double *t0, double *t1) {
  *p0 = 2 * PI * (W->a0[a] + 0.5) / W->w; *p1 = 2 * PI * (W->a0[a + 1] + 0.5) / W->w;
  *t0 = PI * W->vk[W->b0[b]]; *t1 = PI * W->vk[W->b0[b + 1]];
}

static void warp_bf(const void *W, int a, int b, double *p0, double *p1, double *t0, double *t1) { warp_cell_bounds((const warp *)W, a, b, p0, p1, t0, t1); }

/* ---- strategies ---- */
enum { ST_PLAIN, ST_EXACT, ST_TABLE };
typedef struct {
  int kind;
  const char *name;
  cells *c;   /* piecewise-constant cells, or */
  warp *W;    /* bilinear-patch cells */
  ntables *t;
  el_distribution2d pt; /* "exact": the per-point distribution over cells */
  int pt_valid;
} strategy;

/* light-space direction of bin (i, j) at fractions (fu, fv); returns sin(theta) */
static double bin_dir(const cells *c, int i, int j, float fu, float fv, double d[3]) {
  double u = (i + fu) / c->nu, v = (j + fv) / c->nv, st = sin(PI * v);
  d[0] = st * cos(2 * PI * u); d[1] = st * sin(2 * PI * u); d[2] = cos(PI * v);
  return st;
}
static int s_ku(const strategy *s) { return s->c ? s->c->ku : s->W->ku; }
static int s_kv(const strategy *s) { return s->c ? s->c->kv : s->W->kv; }
static void exact_prepare(strategy *s, const double n[3]) {
  int k, ku = s_ku(s), kv = s_kv(s), K = ku * kv;
  float *f = (float *)malloc(K * sizeof(float));
  for (k = 0; k < K; ++k) {
    double p0, p1, t0, t1, m;
    if (s->c) { cell_bounds(s->c, k % ku, k / ku, &p0, &p1, &t0, &t1); m = s->c->mass[k]; }
    else { warp_cell_bounds(s->W, k % ku, k / ku, &p0, &p1, &t0, &t1); m = s->W->mass[k]; }
    f[k] = (float)(m * fmax(0.0, cell_maxcos(n, p0, p1, t0, t1)));
  }
  if (s->pt_valid) el_distribution2d_free(&s->pt);
  el_distribution2d_init(&s->pt, f, ku, kv, NULL);
  s->pt_valid = 1;
  free(f);
}
static const el_distribution2d *cell_choice(strategy *s, const double n[3]) {
  if (s->kind == ST_EXACT) return &s->pt;
  return &s->t->tab[oct_bin(n, s->t->m)];
}
/* sample: light-space direction and its solid-angle pdf (0: none) */
static double strat_sample(strategy *s, el_envlight *l, const double n[3], const float u[2], double d[3]) {
  if (s->kind == ST_PLAIN && !s->W) {
    float wi[3], p;
    el_envlight_sample_li(l, u, wi, NULL, &p);
    d[0] = wi[0]; d[1] = wi[1]; d[2] = wi[2];
    return p;
  } else if (s->kind == ST_PLAIN) { /* the global warp: one cell */
    double st, p = warp_sample_cell(s->W, 0, 0, u[0], u[1], d, &st);
    return p / (2 * PI * PI * fmax(st, 1e-7));
  } else {
    const el_distribution2d *cd = cell_choice(s, n);
    int cu, cv, li, lj, k, ku = s_ku(s), kv = s_kv(s);
    float fu, fv, gu, gv, pc, pw;
    double st;
    el_distribution2d_sample_bins(cd, u[0], u[1], &cu, &cv, &fu, &fv, &pc);
    if (!(pc > 0)) return 0;
    k = cv * ku + cu;
    if (s->W) {
      double pin = warp_sample_cell(s->W, cu, cv, fu, fv, d, &st);
      return (double)pc / (ku * kv) * pin / (2 * PI * PI * fmax(st, 1e-7));
    } else {
      const cells *c = s->c;
      el_distribution2d_sample_bins(&c->cell[k], fu, fv, &li, &lj, &gu, &gv, &pw);
      if (!(pw > 0)) return 0;
      st = bin_dir(c, c->x0[cu] + li, c->y0[cv] + lj, gu, gv, d);
      /* pc = pmf_c * K, pw = pmf_in * w * h: the density over (u, v) is pmf_c pmf_in nu nv */
      return (double)pc / (ku * kv) * pw / ((double)(c->x0[cu + 1] - c->x0[cu]) * (c->y0[cv + 1] - c->y0[cv])) *
             (double)c->nu * c->nv / (2 * PI * PI * fmax(st, 1e-7));
    }
  }
}
static double strat_pdf(strategy *s, el_envlight *l, const double n[3], const double d[3]) {
  if (s->kind == ST_PLAIN && !s->W) {
    float w[3];
    w[0] = (float)d[0]; w[1] = (float)d[1]; w[2] = (float)d[2];
    return el_envlight_pdf_li(l, w);
  } else if (s->W) {
    int i, r, cu, cv, ku = s_ku(s), kv = s_kv(s);
    double ss, t, st = warp_locate(s->W, d, &i, &r, &ss, &t), pc = 1.0;
    cu = s->W->cu_of[i]; cv = s->W->cv_of[r];
    if (s->kind != ST_PLAIN) pc = el_distribution2d_pdf(cell_choice(s, n), (cu + 0.5f) / ku, (cv + 0.5f) / kv) / (ku * kv);
    return pc * warp_bilin(s->W, i, r, ss, t) / s->W->mass[cv * ku + cu] / (2 * PI * PI * fmax(st, 1e-7));
  } else {
    const cells *c = s->c;
    const el_distribution2d *cd = cell_choice(s, n);
    double u = atan2(d[1], d[0]) / (2 * PI), v = acos(fmax(-1.0, fmin(1.0, d[2]))) / PI, st = sqrt(d[0] * d[0] + d[1] * d[1]);
    int i, j, cu, cv, w, h;
    double pc, pw;
    if (u < 0) u += 1;
    i = (int)(u * c->nu); j = (int)(v * c->nv);
    if (i > c->nu - 1) i = c->nu - 1;
    if (j > c->nv - 1) j = c->nv - 1;
    cu = c->cu_of[i]; cv = c->cv_of[j];
    w = c->x0[cu + 1] - c->x0[cu]; h = c->y0[cv + 1] - c->y0[cv];
    pc = el_distribution2d_pdf(cd, (cu + 0.5f) / c->ku, (cv + 0.5f) / c->kv);
    pw = el_distribution2d_pdf(&c->cell[cv * c->ku + cu], (i - c->x0[cu] + 0.5f) / w, (j - c->y0[cv] + 0.5f) / h);
    return pc / (c->ku * c->kv) * pw / ((double)w * h) * (double)c->nu * c->nv / (2 * PI * PI * fmax(st, 1e-7));
  }
}

/* ---- quadrature of E(n) over the bilinear reconstruction (2x2 midpoints per texel) ---- */
static void quadrature(const el_image *im, double n[][3], int nn, double *E) {
  int x, y, a, b, k, s = 2, W = im->width, H = im->height;
  for (k = 0; k < nn; ++k) E[k] = 0;
#define LUM(xx, yy) lum3(im->pixels + 3 * ((size_t)((yy) < 0 ? 0 : (yy) > H - 1 ? H - 1 : (yy)) * W + (size_t)((((xx) % W) + W) % W)))
  for (y = 0; y < H; ++y)
    for (b = 0; b < s; ++b) {
      double v0 = (y + (double)b / s) / H, v1 = (y + (b + 1.0) / s) / H, v = 0.5 * (v0 + v1);
      double dom = (cos(PI * v0) - cos(PI * v1)) * 2 * PI / (W * s), st = sin(PI * v), ct = cos(PI * v);
      double t = v * H - 0.5, fy;
      int y0 = (int)floor(t);
      fy = t - y0;
      for (x = 0; x < W; ++x)
        for (a = 0; a < s; ++a) {
          double u = (x + (a + 0.5) / s) / W, ss = u * W - 0.5, fx, L, w[3];
          int x0 = (int)floor(ss);
          fx = ss - x0;
          L = (1 - fy) * ((1 - fx) * LUM(x0, y0) + fx * LUM(x0 + 1, y0)) + fy * ((1 - fx) * LUM(x0, y0 + 1) + fx * LUM(x0 + 1, y0 + 1));
          w[0] = st * cos(2 * PI * u); w[1] = st * sin(2 * PI * u); w[2] = ct;
          for (k = 0; k < nn; ++k) {
            double c = dot3(n[k], w);
            if (c > 0) E[k] += L * c * dom;
          }
        }
    }
#undef LUM
}

#define NN 6
static const char *NNAME[NN] = {"up", "down", "side+x", "side+y", "sun", "away"};

static void frame(const double n[3], double b1[3], double b2[3]) {
  double t[3] = {1, 0, 0}, d, len;
  if (fabs(n[0]) > 0.9) { t[0] = 0; t[1] = 1; }
  d = dot3(t, n);
  b1[0] = t[0] - d * n[0]; b1[1] = t[1] - d * n[1]; b1[2] = t[2] - d * n[2];
  len = sqrt(dot3(b1, b1));
  b1[0] /= len; b1[1] /= len; b1[2] /= len;
  b2[0] = n[1] * b1[2] - n[2] * b1[1]; b2[1] = n[2] * b1[0] - n[0] * b1[2]; b2[2] = n[0] * b1[1] - n[1] * b1[0];
}

/* relative variance per sample of light sampling alone (mis = 0) or one light + one cosine sample with
 * the balance heuristic (mis = 1); *below: fraction of light samples below the horizon */
static double run(strategy *s, el_envlight *l, const double n[3], double E, int ns, int mis, uint64_t seed, double *below, double *ns_per) {
  double sum = 0, sum2 = 0, b1[3], b2[3], t;
  long i, nb = 0;
  rng r;
  r.s = seed;
  frame(n, b1, b2);
  if (s->kind == ST_EXACT) exact_prepare(s, n);
  t = process_now();
  for (i = 0; i < ns; ++i) {
    float u[2], L[3], w[3];
    double d[3], p, c, f = 0;
    u[0] = rng_f(&r); u[1] = rng_f(&r);
    p = strat_sample(s, l, n, u, d);
    if (p > 0) {
      c = dot3(n, d);
      if (c > 0) {
        w[0] = (float)d[0]; w[1] = (float)d[1]; w[2] = (float)d[2];
        el_envlight_le(l, w, L);
        f += lum3(L) * c / (mis ? p + c / PI : p);
      } else ++nb;
    }
    if (mis) {
      double rr, ph, lz;
      u[0] = rng_f(&r); u[1] = rng_f(&r);
      rr = sqrt((double)u[0]); ph = 2 * PI * u[1]; lz = sqrt(fmax(0.0, 1 - u[0]));
      for (c = 0; c < 3; ++c) d[(int)c] = rr * cos(ph) * b1[(int)c] + rr * sin(ph) * b2[(int)c] + lz * n[(int)c];
      if (lz > 0) {
        w[0] = (float)d[0]; w[1] = (float)d[1]; w[2] = (float)d[2];
        el_envlight_le(l, w, L);
        f += lum3(L) * lz / (lz / PI + strat_pdf(s, l, n, d));
      }
    }
    sum += f; sum2 += f * f;
  }
  *ns_per = (process_now() - t) / ns * 1e9;
  *below = (double)nb / ns;
  {
    double m = sum / ns, var = fmax(0.0, sum2 / ns - m * m);
    (void)m;
    return var / (E * E);
  }
}

/* the normals NNAME (light space): up, down, sideways, the brightest texel and away from it; returns
 * the brightest texel's luminance */
static double six_normals(const el_image *img, double N[NN][3]) {
  double best = -1;
  int x, y, k;
  memset(N, 0, NN * sizeof N[0]);
  N[0][2] = 1; N[1][2] = -1; N[2][0] = 1; N[3][1] = 1;
  for (y = 0; y < img->height; ++y)
    for (x = 0; x < img->width; ++x) {
      double v = lum3(img->pixels + 3 * ((size_t)y * img->width + x));
      if (v > best) {
        double uu = (x + 0.5) / img->width, vv = (y + 0.5) / img->height;
        best = v;
        N[4][0] = sin(PI * vv) * cos(2 * PI * uu); N[4][1] = sin(PI * vv) * sin(2 * PI * uu); N[4][2] = cos(PI * vv);
      }
    }
  for (k = 0; k < 3; ++k) N[5][k] = -N[4][k];
  return best;
}

static void do_map(const char *path, int nsamp, const char *only) {
  el_image img;
  char err[512];
  el_envlight l;
  double N[NN][3], E[NN], best;
  int k, q, ns = 0, m, ci, wi;
  static const int CK[][2] = {{16, 8}, {32, 16}, {64, 32}};
  static int MS[3] = {8, 16, 32};
  static char names[64][40];
  cells C[3];
  warp Wg, WC[3];
  ntables T[2][3][3];
  strategy S[64];
  if (el_image_load(path, &img, err, sizeof err) != 0) { printf("(%s)\n", err); return; }
  if (el_envlight_init(&l, img.pixels, img.width, img.height, 3, NULL) != EL_SUCCESS) return;
  el_envlight_prepare_sampling(&l);
  best = six_normals(&img, N);
  quadrature(&img, N, NN, E);
  printf("\n%s (%dx%d), brightest texel %.3g at theta %.0f deg; E:", path, img.width, img.height, best, acos(N[4][2]) * 180 / PI);
  for (k = 0; k < NN; ++k) printf(" %s %.3g", NNAME[k], E[k]);
  printf("\n");
  if (getenv("MS")) sscanf(getenv("MS"), "%d,%d,%d", &MS[0], &MS[1], &MS[2]);
  memset(S, 0, sizeof S);
  warp_init(&Wg, &l, &img, 1, 1);
  S[ns].kind = ST_PLAIN; S[ns++].name = "plain sample_li";
  S[ns].kind = ST_PLAIN; S[ns].W = &Wg; S[ns++].name = "plain, bilinear warp";
  for (ci = 0; ci < 3; ++ci) {
    cells_init(&C[ci], &l, CK[ci][0], CK[ci][1]);
    warp_init(&WC[ci], &l, &img, CK[ci][0], CK[ci][1]);
    for (wi = 0; wi < 2; ++wi) {
      snprintf(names[ns], sizeof names[ns], "exact %dx%d%s", CK[ci][0], CK[ci][1], wi ? " warp" : "");
      S[ns].kind = ST_EXACT; S[ns].name = names[ns];
      if (wi) S[ns].W = &WC[ci]; else S[ns].c = &C[ci];
      ++ns;
      for (m = 0; m < 3; ++m) {
        if (getenv("BUILD") && !strchr(getenv("BUILD"), '0' + ci * 3 + m)) { memset(&T[wi][ci][m], 0, sizeof T[wi][ci][m]); continue; }
        if (wi) ntables_init(&T[wi][ci][m], &WC[ci], CK[ci][0], CK[ci][1], WC[ci].mass, warp_bf, MS[m]);
        else ntables_init(&T[wi][ci][m], &C[ci], CK[ci][0], CK[ci][1], C[ci].mass, cells_bf, MS[m]);
        snprintf(names[ns], sizeof names[ns], "table %d^2 %dx%d%s", MS[m], CK[ci][0], CK[ci][1], wi ? " warp" : "");
        S[ns].kind = ST_TABLE; S[ns].name = names[ns]; S[ns].t = &T[wi][ci][m];
        if (wi) S[ns].W = &WC[ci]; else S[ns].c = &C[ci];
        ++ns;
      }
    }
  }
  printf("  %-28s %-6s", "strategy", "");
  for (k = 0; k < NN; ++k) printf(" %8s", NNAME[k]);
  printf(" %8s %7s %6s %8s %8s\n", "geomean", "below", "MB", "build ms", "ns");
  for (q = 0; q < ns; ++q) {
    int mis;
    if (only && !strstr(S[q].name, only) && q > 1) continue;
    if (S[q].t && !S[q].t->tab) continue;
    for (mis = 0; mis < 2; ++mis) {
      double lg = 0, bel = 0, rv[NN], nsp, nst = 0, bt = 0;
      size_t bytes = 0;
      for (k = 0; k < NN; ++k) {
        double b;
        rv[k] = run(&S[q], &l, N[k], E[k], nsamp, mis, 0x9e3779b97f4a7c15ULL * (k + 1) + q, &b, &nsp);
        lg += log(rv[k]) / NN;
        bel += b / NN;
        nst += nsp / NN;
      }
      if (S[q].t) { bytes += S[q].t->bytes; bt += S[q].t->build_s; }
      if (S[q].c) { bytes += S[q].c->bytes; bt += S[q].c->build_s; }
      if (S[q].W) { bytes += S[q].W->bytes; bt += S[q].W->build_s; }
      printf("  %-28s %-6s", S[q].name, mis ? "+MIS" : "light");
      for (k = 0; k < NN; ++k) printf(" %8.3g", rv[k]);
      printf(" %8.3g %6.1f%% %6.2f %8.1f %8.0f\n", exp(lg), 100 * bel, bytes / 1048576.0, bt * 1e3, nst);
    }
    if (S[q].pt_valid) el_distribution2d_free(&S[q].pt);
  }
  fflush(stdout);
  for (ci = 0; ci < 3; ++ci) {
    for (wi = 0; wi < 2; ++wi) for (m = 0; m < 3; ++m) if (T[wi][ci][m].tab) ntables_free(&T[wi][ci][m]);
    cells_free(&C[ci]);
    warp_free(&WC[ci]);
  }
  warp_free(&Wg);
  el_envlight_free(&l);
  el_image_free(&img);
}

/* ---- the picture: where 2000 samples of one shading point land, plain versus product ---- */
static int picture(const char *out, const char *path) {
  el_image img;
  char err[512], label[128];
  el_envlight l;
  int W, H, panel, x, y, i, ns = 2000, below;
  unsigned char *pix;
  double nl[3], u0 = 0.45, v0 = 0.30; /* the normal: light-space direction at (u, v) = (0.45, 0.30) */
  float n[3];
  if (el_image_load(path, &img, err, sizeof err) != 0) { fprintf(stderr, "%s\n", err); return 1; }
  if (el_envlight_init(&l, img.pixels, img.width, img.height, 3, NULL) != EL_SUCCESS) { fprintf(stderr, "%s: init failed\n", path); return 1; }
  W = img.width; H = img.height;
  nl[0] = sin(PI * v0) * cos(2 * PI * u0); nl[1] = sin(PI * v0) * sin(2 * PI * u0); nl[2] = cos(PI * v0);
  n[0] = (float)nl[0]; n[1] = (float)nl[1]; n[2] = (float)nl[2];
  pix = (unsigned char *)calloc((size_t)W * 2 * H * 3, 1);
  for (panel = 0; panel < 2; ++panel) {
    unsigned char *im = pix + (size_t)panel * W * H * 3;
    rng r;
    r.s = 2024;
    for (y = 0; y < H; ++y) /* the map, one stop darker */
      for (x = 0; x < W; ++x) {
        const float *t = img.pixels + 3 * ((size_t)y * W + x);
        unsigned char *p = im + 3 * ((size_t)y * W + x);
        p[0] = picture_to8(0.5 * t[0]); p[1] = picture_to8(0.5 * t[1]); p[2] = picture_to8(0.5 * t[2]);
      }
    for (x = 0; x < W; ++x) /* the normal's horizon: n.w = 0 along each column, found by bisection on theta */
      for (i = 0; i < 2; ++i) {
        double ph = 2 * PI * (x + 0.5) / W, a = nl[0] * cos(ph) + nl[1] * sin(ph), b = nl[2];
        double th = atan2(-b, a); /* a sin(th) + b cos(th) = 0 */
        if (i) th += PI;
        th -= 2 * PI * floor(th / (2 * PI));
        if (th <= PI) picture_dot(im, W, H, x, (int)(th / PI * H), 1, 80, 220, 255);
      }
    for (i = -6; i <= 6; ++i) { /* the normal: a white cross */
      picture_dot(im, W, H, (int)(u0 * W) + i, (int)(v0 * H), 1, 255, 255, 255);
      picture_dot(im, W, H, (int)(u0 * W), (int)(v0 * H) + i, 1, 255, 255, 255);
    }
    below = 0;
    for (i = 0; i < ns; ++i) {
      float u[2], wi[3], L[3], p;
      double uu, vv, c;
      u[0] = rng_f(&r); u[1] = rng_f(&r);
      if (panel == 0) el_envlight_sample_li(&l, u, wi, L, &p);
      else el_envlight_sample_li_cos(&l, n, u, wi, L, &p);
      if (!(p > 0)) continue;
      uu = atan2(wi[1], wi[0]) / (2 * PI); if (uu < 0) uu += 1;
      vv = acos(fmax(-1.0, fmin(1.0, wi[2]))) / PI;
      c = n[0] * wi[0] + n[1] * wi[1] + n[2] * wi[2];
      if (c <= 0) ++below;
      if (c > 0) picture_dot(im, W, H, (int)(uu * W), (int)(vv * H), 1, 255, 230, 40);
      else picture_dot(im, W, H, (int)(uu * W), (int)(vv * H), 1, 255, 40, 40);
    }
    snprintf(label, sizeof label, "%s: %d SAMPLES, %d BELOW THE HORIZON (RED)",
             panel == 0 ? "PLAIN (SAMPLE LI)" : "PRODUCT (SAMPLE LI COS)", ns, below);
    el_draw_label(im, W, H, 8, 8, label);
    el_draw_label(im, W, H, 8, 34, "THE NORMAL: WHITE CROSS. ITS HORIZON: BLUE");
    printf("%s: %d of %d samples below the horizon\n", panel == 0 ? "sample_li" : "sample_li_cos", below, ns);
  }
  make_parent_dir(out);
  if (el_image_write_png(out, pix, W, 2 * H, 3, err, sizeof err) != 0) { fprintf(stderr, "%s\n", err); return 1; }
  printf("wrote %s\n", out);
  free(pix);
  el_envlight_free(&l);
  el_image_free(&img);
  return 0;
}

/* ---- --library: the library's sampler as shipped (issue 20's numbers) ---- */
static void library_map(const char *path, int nsamp) {
  el_image img;
  char err[512];
  el_envlight l;
  double N[NN][3], E[NN], ms[5], gv[2] = {0, 0}, gt[2] = {0, 0};
  int k, j;
  size_t bytes = 0;
  if (el_image_load(path, &img, err, sizeof err) != 0) { printf("(%s)\n", err); return; }
  for (k = 0; k < 5; ++k) { /* builds on fresh lights */
    double t0;
    if (el_envlight_init(&l, img.pixels, img.width, img.height, 3, NULL) != EL_SUCCESS) return;
    t0 = process_now();
    el_envlight_prepare_product(&l, NULL);
    ms[k] = (process_now() - t0) * 1e3;
    bytes = el_envlight_product_bytes(&l);
    el_envlight_free(&l);
  }
  qsort(ms, 5, sizeof ms[0], cmp_double);
  if (el_envlight_init(&l, img.pixels, img.width, img.height, 3, NULL) != EL_SUCCESS) return;
  el_envlight_prepare_product(&l, NULL);
  el_envlight_prepare_sampling(&l);
  six_normals(&img, N);
  quadrature(&img, N, NN, E);
  printf("\n%s (%dx%d): product tables %.2f MiB (%zu bytes), build %.1f ms best, %.1f median of 5\n", path, img.width, img.height,
         bytes / 1048576.0, bytes, ms[0], ms[2]);
  printf("  %-7s %-14s %10s %9s %11s   %-14s %10s %9s %11s\n", "normal", "sample_li_cos", "relvar", "ns", "relvar x ns", "sample_li", "relvar", "ns", "relvar x ns");
  for (k = 0; k < NN; ++k) {
    float n[3];
    double rv[2], tn[2];
    int strat;
    for (j = 0; j < 3; ++j) n[j] = (float)N[k][j];
    for (strat = 0; strat < 2; ++strat) {
      double s1 = 0, s2 = 0, tbest = 1e30;
      int rep;
      rng g;
      for (rep = 0; rep < 3; ++rep) {
        double t0 = process_now();
        g.s = 0x9e3779b97f4a7c15ull * (uint64_t)(k + 1);
        s1 = s2 = 0;
        for (j = 0; j < nsamp; ++j) {
          float u[2], wi[3], rgb[3], pdf, c;
          u[0] = rng_f(&g); u[1] = rng_f(&g);
          if (strat == 0) el_envlight_sample_li_cos(&l, n, u, wi, rgb, &pdf);
          else el_envlight_sample_li(&l, u, wi, rgb, &pdf);
          c = wi[0] * n[0] + wi[1] * n[1] + wi[2] * n[2];
          if (pdf > 0 && c > 0) { double f = lum3(rgb) * c / pdf; s1 += f; s2 += f * f; }
        }
        t0 = process_now() - t0;
        if (t0 < tbest) tbest = t0;
      }
      { double m = s1 / nsamp; rv[strat] = (s2 / nsamp - m * m) / (E[k] * E[k]); }
      tn[strat] = tbest / nsamp * 1e9;
      gv[strat] += log(rv[strat]); gt[strat] += log(tn[strat]);
    }
    printf("  %-7s %-14s %10.4g %9.1f %11.4g   %-14s %10.4g %9.1f %11.4g\n", NNAME[k], "", rv[0], tn[0], rv[0] * tn[0], "", rv[1], tn[1], rv[1] * tn[1]);
  }
  printf("  %-7s %-14s %10.4g %9.1f %11.4g   %-14s %10.4g %9.1f %11.4g   (geometric means; product: %.1fx the efficiency)\n", "geomean", "",
         exp(gv[0] / NN), exp(gt[0] / NN), exp((gv[0] + gt[0]) / NN), "", exp(gv[1] / NN), exp(gt[1] / NN), exp((gv[1] + gt[1]) / NN),
         exp((gv[1] + gt[1] - gv[0] - gt[0]) / NN));
  el_envlight_free(&l);
  el_image_free(&img);
}

/* nb uniform random directions (normals) and nb pairs u, from a PCG32 stream at seed (--batch's) */
static void random_dirs_u(float *nrm, float *uu, int nb, uint64_t seed) {
  rng g;
  int k;
  g.s = seed;
  for (k = 0; k < nb; ++k) {
    float z = 1.0f - 2.0f * rng_f(&g), r = sqrtf(z < 1.0f && z > -1.0f ? 1.0f - z * z : 0.0f), ph = 6.2831853f * rng_f(&g);
    nrm[3 * k] = r * cosf(ph); nrm[3 * k + 1] = r * sinf(ph); nrm[3 * k + 2] = z;
    uu[2 * k] = rng_f(&g); uu[2 * k + 1] = rng_f(&g);
  }
}
/* ---- --batch: n at once (el_envlight_sample_li_cos_n, pdf_li_cos_n) against the single calls ---- */
/* A new random normal per sample (renderer-like: the normal tables' rows are cache-cold), 2^20 samples
 * precomputed (normals, u); the calls with the radiance, in batches of 64. CPU ns per sample, best of
 * REPS rounds, each round running every variant once (interleaved, so a load change hits all alike). */
static void batch_map(const char *path, int reps) {
  enum { NB = 1 << 20, CB = 64, NV = 5 };
  static const char *names[NV] = {"sample_li_cos", "sample_li_cos_n", "pdf_li_cos", "pdf_li_cos_n", "sample_li"};
  el_image img;
  char err[512];
  el_envlight l;
  float *nrm = (float *)malloc(3 * (size_t)NB * sizeof(float)), *uu = (float *)malloc(2 * (size_t)NB * sizeof(float));
  float *wi = (float *)malloc(3 * (size_t)NB * sizeof(float)), *rgb = (float *)malloc(3 * (size_t)NB * sizeof(float));
  float *pdf = (float *)malloc((size_t)NB * sizeof(float));
  double best[NV], sum[NV];
  int k, v, rep;
  if (!nrm || !uu || !wi || !rgb || !pdf) return;
  if (el_image_load(path, &img, err, sizeof err) != 0) { printf("(%s)\n", err); return; }
  if (el_envlight_init(&l, img.pixels, img.width, img.height, 3, NULL) != EL_SUCCESS) return;
  el_envlight_prepare_product(&l, NULL);
  el_envlight_prepare_sampling(&l);
  random_dirs_u(nrm, uu, NB, 0x853c49e6748fea9bull); /* uniform directions */
  for (v = 0; v < NV; ++v) best[v] = 1e30;
  for (rep = 0; rep < reps; ++rep)
    for (v = 0; v < NV; ++v) {
      double t0 = process_now(), acc = 0;
      if (v == 0) for (k = 0; k < NB; ++k) el_envlight_sample_li_cos(&l, nrm + 3 * k, uu + 2 * k, wi + 3 * k, rgb + 3 * k, pdf + k);
      else if (v == 1) for (k = 0; k < NB; k += CB) el_envlight_sample_li_cos_n(&l, CB, nrm + 3 * k, uu + 2 * k, wi + 3 * k, rgb + 3 * k, pdf + k);
      else if (v == 2) for (k = 0; k < NB; ++k) pdf[k] = el_envlight_pdf_li_cos(&l, nrm + 3 * k, wi + 3 * ((k + CB) & (NB - 1)));
      else if (v == 3) for (k = 0; k < NB; k += CB) el_envlight_pdf_li_cos_n(&l, CB, nrm + 3 * k, wi + 3 * ((k + CB) & (NB - 1)), pdf + k);
      else for (k = 0; k < NB; ++k) el_envlight_sample_li(&l, uu + 2 * k, wi + 3 * k, rgb + 3 * k, pdf + k);
      t0 = process_now() - t0;
      for (k = 0; k < NB; ++k) acc += pdf[k];
      sum[v] = acc;
      if (t0 < best[v]) best[v] = t0;
      if (v == 4) /* the pdfs' directions: product samples again */
        for (k = 0; k < NB; k += CB) el_envlight_sample_li_cos_n(&l, CB, nrm + 3 * k, uu + 2 * k, wi + 3 * k, NULL, pdf + k);
    }
  printf("\n%s (%dx%d): a new random normal per sample, %d samples, batches of %d, best of %d interleaved rounds (CPU ns per sample)\n",
         path, img.width, img.height, NB, CB, reps);
  for (v = 0; v < NV; ++v) printf("  %-16s %7.1f ns   (sum of pdfs %.6g)\n", names[v], best[v] / NB * 1e9, sum[v]);
  printf("  batched / single: sample %.2fx, pdf %.2fx the time\n", best[1] / best[0], best[3] / best[2]);
  el_envlight_free(&l);
  el_image_free(&img);
  free(nrm); free(uu); free(wi); free(rgb); free(pdf);
}

/* ---- --candidates: issue 20's two designs not built before, as designs (the library's own tables and
 * helpers underneath, so that instructions and time compare with el_envlight_sample_li_cos) ----
 *
 * (1) ALIAS: Walker's alias tables (Vose's construction, in integers) in place of the guide-table
 *     searches, over the library's own integer widths (the normal bins' cell rows and cells, and for
 *     "alias 4" also each cell's patch rows and each patch row's patches). Exact: bucket k of n keeps k
 *     when 32768 frac(u n) < thr_k, else takes al_k, so every entry is picked with exactly its integer
 *     share and the density (and the pdf, pdf_li_cos's own: checked bit for bit) is the library's. The
 *     rest of u goes on to the next level, but it is no longer monotone in u: the stratification breaks.
 *     Entries of 8 bytes (threshold, alias, both widths); "4-byte" (the cell levels only): threshold |
 *     alias << 16, the widths read from the library's CDFs (the same picks, less memory, one more read).
 * (2) C&L: Conty and Lecocq 2018's per-point coarse level. A KU x KV level of lat-long cells (the
 *     library's patch tables built with those cells, one normal bin), each cell's mass, and per shading
 *     point the exact maximum of n.w over every cell (the spherical rectangle's, as the normal tables'
 *     build computes it, + 1e-5 for float rounding), with SSE2 (four cells a step), times the mass: a CDF
 *     over the cell rows and, inside the picked row, over its cells (u[1], then u[0]), then the library's
 *     patch-row and patch picks and its bilinear inside the patch. pdf: the same weights (all cells
 *     again: a pdf costs a weight pass too), P(cell) = weight / total, times the library's patch density. */
typedef struct { uint16_t thr, w, wa, al; } aentry; /* keep k when 32768 frac < thr; else al; w, wa: the widths */
typedef struct { uint32_t off, lib; uint16_t as, len; } arow; /* lib: the library's row, from its table's start */
typedef struct {
  const struct el_envlight__warp *W;
  uint32_t *bin_off; /* m * m: the bin's kv cell-row entries in pool */
  arow *rows;        /* m * m * kv: each row's span (as the sparse table's) and its entries in pool */
  aentry *pool, *prow, *pcol; /* prow, pcol: at the offsets of the library's CDFs */
  uint32_t *pool4;   /* the compact cell levels: pool's threshold | alias << 16, the widths read from the library's CDFs */
  size_t cell_bytes, patch_bytes, cell_bytes4; /* the cell levels' tables, the patch levels' (besides the library's, which the pdf reads) */
} alias_tabs;

/* Vose's construction over the widths c[k + 1] - c[k] of an integer CDF (32768 units), exactly: scaled
 * widths s_k = w_k n, buckets of 32768 */
static void alias_build(const uint16_t *c, int n, aentry *e, uint32_t *s, int *lst) {
  int *small = lst, *large = lst + n, ns = 0, nl = 0, k;
  for (k = 0; k < n; ++k) {
    e[k].w = e[k].wa = (uint16_t)(c[k + 1] - c[k]);
    e[k].thr = 32768; e[k].al = (uint16_t)k;
    s[k] = (uint32_t)e[k].w * (uint32_t)n;
    if (s[k] < 32768u) small[ns++] = k; else large[nl++] = k;
  }
  if (c[n] != 32768u) return; /* no mass: never picked */
  while (ns && nl) {
    int lo = small[--ns], g = large[--nl];
    e[lo].thr = (uint16_t)s[lo]; e[lo].al = (uint16_t)g; e[lo].wa = e[g].w;
    s[g] -= 32768u - s[lo];
    if (s[g] < 32768u) small[ns++] = g; else large[nl++] = g;
  }
}
static void alias_init(alias_tabs *A, const struct el_envlight__warp *W) {
  int m = W->m, kv = W->kv, ku = W->ku, h = W->h, bin, a, b, r;
  size_t pos = 0, nprow = (size_t)ku * (size_t)(h + 1 + kv), npcol = (size_t)(h + 1) * W->cond_stride;
  uint32_t *s = (uint32_t *)malloc(4096 * sizeof(uint32_t));
  int *lst = (int *)malloc(8192 * sizeof(int));
  A->W = W;
  A->bin_off = (uint32_t *)malloc((size_t)m * m * sizeof(uint32_t));
  A->rows = (arow *)malloc((size_t)m * m * kv * sizeof(arow));
  A->pool = (aentry *)malloc((size_t)m * m * (size_t)kv * (size_t)(ku + 1) * sizeof(aentry));
  A->prow = (aentry *)calloc(nprow, sizeof(aentry));
  A->pcol = (aentry *)calloc(npcol, sizeof(aentry));
  for (bin = 0; bin < m * m; ++bin) {
    const uint16_t *tab = W->cos_tab + W->cos_off[bin];
    A->bin_off[bin] = (uint32_t)pos;
    alias_build(tab, kv, A->pool + pos, s, lst);
    pos += (size_t)kv;
    for (b = 0; b < kv; ++b) {
      const uint16_t *row = el_envlight__sparse_row(W, tab, b);
      arow *ar = A->rows + (size_t)bin * kv + b;
      ar->off = (uint32_t)pos; ar->lib = (uint32_t)(row - tab); ar->as = row[0]; ar->len = row[1];
      if (row[1]) alias_build(row + 2, row[1], A->pool + pos, s, lst);
      pos += row[1];
    }
  }
  A->pool = (aentry *)realloc(A->pool, pos * sizeof(aentry));
  A->pool4 = (uint32_t *)malloc(pos * sizeof(uint32_t));
  for (r = 0; r < (int)pos; ++r) A->pool4[r] = (uint32_t)A->pool[r].thr | (uint32_t)A->pool[r].al << 16;
  for (a = 0; a < ku; ++a)
    for (b = 0; b < kv; ++b) {
      size_t base = (size_t)a * (size_t)(h + 1 + kv) + (size_t)W->b0[b] + (size_t)b;
      alias_build(W->prow + base, W->b0[b + 1] - W->b0[b], A->prow + base, s, lst);
    }
  for (r = 0; r <= h; ++r)
    for (a = 0; a < ku; ++a) {
      size_t base = (size_t)r * W->cond_stride + (size_t)W->coff[a];
      alias_build(W->pcol + base, W->a0[a + 1] - W->a0[a], A->pcol + base, s, lst);
    }
  A->cell_bytes = (size_t)m * m * (sizeof(uint32_t) + (size_t)kv * sizeof(arow)) + pos * sizeof(aentry);
  A->patch_bytes = (nprow + npcol) * sizeof(aentry);
  A->cell_bytes4 = (size_t)m * m * (sizeof(uint32_t) + (size_t)kv * sizeof(arow)) + pos * sizeof(uint32_t);
  free(s); free(lst);
}
static void alias_free(alias_tabs *A) { free(A->bin_off); free(A->rows); free(A->pool); free(A->pool4); free(A->prow); free(A->pcol); }
/* one pick among n entries with x in [0, 1]: the entry, the rest of x for the next level, its width */
static inline int alias_pick(const aentry *e, int n, float x, float *rest, uint32_t *w) {
  float y = x * (float)n, z;
  int k = (int)y;
  k = k < n - 1 ? k : n - 1;
  z = (y - (float)k) * 32768.0f;
  z = z < 32767.998f ? z : 32767.998f;
  e += k;
  if (z < (float)e->thr) { *rest = z / (float)e->thr; *w = e->w; return k; }
  *rest = (z - (float)e->thr) / (float)(32768 - e->thr); *w = e->wa;
  return e->al;
}
/* the same pick from a compact entry (threshold | alias << 16), the width from the CDF c */
static inline int alias_pick4(const uint32_t *e, const uint16_t *c, int n, float x, float *rest, uint32_t *w) {
  float y = x * (float)n, z, thr;
  int k = (int)y;
  uint32_t v;
  k = k < n - 1 ? k : n - 1;
  z = (y - (float)k) * 32768.0f;
  z = z < 32767.998f ? z : 32767.998f;
  v = e[k];
  thr = (float)(v & 0xffffu);
  if (z < thr) *rest = z / thr;
  else { *rest = (z - thr) / (32768.0f - thr); k = (int)(v >> 16); }
  *w = (uint32_t)(c[k + 1] - c[k]);
  return k;
}
/* the octahedral bin of world normal n (el_envlight__prod_table's, for unit-ish n) */
static inline int normal_bin(const el_envlight *l, const struct el_envlight__warp *W, const float n[3]) {
  float nl[3], x, y;
  int i, j, mm = W->m;
  el_envlight__to_light(l, n, nl);
  el_envlight__oct_encode(nl, &x, &y);
  i = (int)(x * (float)mm); j = (int)(y * (float)mm);
  i = i < mm - 1 ? (i > 0 ? i : 0) : mm - 1;
  j = j < mm - 1 ? (j > 0 ? j : 0) : mm - 1;
  return j * mm + i;
}

/* The library's steps after its pick (el_envlight__prod_sample, copied: the bench cannot call half of
 * it): (s, t) in patch (P->i, P->r) from the bilinear, the direction, located again as the pdf locates
 * it; the density from the widths (wc, P->wr) times scale when it lands in that patch, else pdf_at's */
typedef float (*pdf_at_fn)(const void *ctx, const float d[3], float uv[2]);
static inline void finish_patch(const el_envlight *l, const struct el_envlight__warp *W, const el_envlight__pick *P, uint32_t wc, float scale,
                                pdf_at_fn pdf_at, const void *ctx, float wi[3], float rgb[3], float *pdf) {
  float d[3], uv[2] = {0, 0}, c[4], t, s, u, v, vp, p = 0.0f, lo = 2.44140625e-4f, hi = 0.999755859f;
  int i = P->i, r = P->r, k;
  el_envlight__ploc loc;
  el_envlight__prod_corners(W, i, r, c);
  t = el_envlight__lin_invf(c[0] + c[1], c[2] + c[3], P->q);
  s = el_envlight__lin_invf(c[0] + t * (c[2] - c[0]), c[1] + t * (c[3] - c[1]), P->s);
  t = t > lo ? (t < hi ? t : hi) : lo;
  s = s > lo ? (s < hi ? s : hi) : lo;
  for (k = 0; k < 2; ++k, s = t = 0.5f) {
    u = ((float)i + 0.5f + s) * W->inv_w;
    u = u >= 1.0f ? u - 1.0f : u;
    u = u < 0.99999994f ? u : 0.99999994f;
    if (r == 0) v = vp = t * W->half_inv_h;
    else if (r == W->h) { vp = (1.0f - t) * W->half_inv_h; v = 1.0f - vp; }
    else { v = ((float)r - 0.5f + t) * W->inv_h; vp = v < 0.5f ? v : 1.0f - v; }
    el_envlight__uvp_to_dir(u, v, vp, d);
    el_envlight__to_world(l, d, wi);
    if (!l->exact_transform) el_envlight__mul_transpose(l->to_world, wi, d);
    if (el_envlight__prod_locate(W, d, &loc) && loc.i == i && loc.r == r) {
      p = el_envlight__prod_eval(W, &loc, wc, P->wr, c) * scale;
      uv[0] = loc.u; uv[1] = loc.v;
    } else p = pdf_at(ctx, d, uv);
    if (p > 0.0f) break;
  }
  *pdf = p;
  if (rgb) {
    if (p > 0.0f) el_envlight__bilerp(l, uv[0], uv[1], rgb);
    else rgb[0] = rgb[1] = rgb[2] = 0.0f;
  }
}
typedef struct { const struct el_envlight__warp *W; const uint16_t *tab; } lib_ctx;
static float lib_pdf_at(const void *ctx, const float d[3], float uv[2]) {
  const lib_ctx *c = (const lib_ctx *)ctx;
  return el_envlight__prod_pdf_light(c->W, c->tab, d, uv);
}
static void alias_sample(const el_envlight *l, const alias_tabs *A, int levels, const float n[3], const float u[2], float wi[3], float rgb[3], float *pdf) {
  const struct el_envlight__warp *W = A->W;
  int bin = normal_bin(l, W, n), kv = W->kv, b, a;
  const arow *ar;
  uint32_t w1, w2, w3, w4;
  lib_ctx ctx;
  el_envlight__pick P;
  ctx.W = W; ctx.tab = W->cos_tab + W->cos_off[bin];
  if (ctx.tab[kv] == 0) { *pdf = 0.0f; wi[0] = wi[1] = 0.0f; wi[2] = 1.0f; if (rgb) rgb[0] = rgb[1] = rgb[2] = 0.0f; return; }
  if (levels == 1) { /* compact entries, widths from the library's tables */
    b = alias_pick4(A->pool4 + A->bin_off[bin], ctx.tab, kv, el_envlight__clamp01(u[1]), &P.f1, &w1);
    ar = A->rows + (size_t)bin * (size_t)kv + (size_t)b;
    a = ar->as + alias_pick4(A->pool4 + ar->off, ctx.tab + ar->lib + 2, ar->len, el_envlight__clamp01(u[0]), &P.f0, &w2);
  } else {
    b = alias_pick(A->pool + A->bin_off[bin], kv, el_envlight__clamp01(u[1]), &P.f1, &w1);
    ar = A->rows + (size_t)bin * (size_t)kv + (size_t)b;
    a = ar->as + alias_pick(A->pool + ar->off, ar->len, el_envlight__clamp01(u[0]), &P.f0, &w2);
  }
  a -= a >= W->ku ? W->ku : 0;
  P.a = a; P.b = b;
  if (levels == 4) {
    size_t base = (size_t)a * (size_t)(W->h + 1 + kv) + (size_t)W->b0[b] + (size_t)b;
    P.r = W->b0[b] + alias_pick(A->prow + base, W->b0[b + 1] - W->b0[b], P.f1, &P.q, &w3);
    base = (size_t)P.r * W->cond_stride + (size_t)W->coff[a];
    P.i = W->a0[a] + alias_pick(A->pcol + base, W->a0[a + 1] - W->a0[a], P.f0, &P.s, &w4);
    P.wr = w3 * w4;
  } else {
    P.p = W->prow + (size_t)a * ((size_t)W->h + 1 + (size_t)kv) + (size_t)W->b0[b] + (size_t)b;
    el_envlight__pick3(W, &P);
    el_envlight__pick4(W, &P);
  }
  finish_patch(l, W, &P, w1 * w2, 1.0f, lib_pdf_at, &ctx, wi, rgb, pdf);
}

/* C&L: the coarse level, per shading point */
#define CL_MAX 256
typedef struct {
  struct el_envlight__warp *W; /* the library's patch tables with ku x kv cells (one normal bin, unused) */
  int ku, kv;                  /* ku a multiple of 4 */
  float mass[CL_MAX], cp[4][CL_MAX / 4 + 4], ct[CL_MAX][4]; /* masses (kv x ku); per column cos, sin of phi0, phi1; per row of theta0, theta1 */
  size_t bytes;
} cl_level;
typedef struct { float w[CL_MAX], rows[CL_MAX / 4], total; } cl_point;
static int cl_init(cl_level *C, const el_envlight *l, int ku, int kv) {
  const struct el_envlight__warp *W;
  int a, b, i, r;
  memset(C, 0, sizeof *C);
  if (ku % 4 || ku * kv > CL_MAX || el_envlight__prod_build(l, ku, kv, 1, &C->W) != EL_SUCCESS) return 0;
  W = C->W; C->ku = W->ku; C->kv = W->kv;
  for (r = 0; r <= W->h; ++r) /* the masses: each patch's mean corner x its height (as the build's) */
    for (i = 0; i < W->w; ++i) {
      float c[4];
      el_envlight__prod_corners(W, i, r, c);
      C->mass[W->cv_of[r] * ku + W->cu_of[i]] += (c[0] + c[1] + c[2] + c[3]) * (r == 0 || r == W->h ? 0.5f : 1.0f);
    }
  for (a = 0; a < ku; ++a) { /* the cells' edges, as el_envlight__cos_build's */
    double p0 = 2.0 * PI * (W->a0[a] + 0.5) / W->w, p1 = 2.0 * PI * (W->a0[a + 1] + 0.5) / W->w;
    C->cp[0][a] = (float)cos(p0); C->cp[1][a] = (float)sin(p0); C->cp[2][a] = (float)cos(p1); C->cp[3][a] = (float)sin(p1);
  }
  for (b = 0; b < kv; ++b) {
    int r0 = W->b0[b], r1 = W->b0[b + 1];
    double v0 = r0 == 0 ? 0.0 : (r0 - 0.5) / W->h, v1 = r1 == W->h + 1 ? 1.0 : (r1 - 0.5) / W->h;
    C->ct[b][0] = (float)cos(PI * v0); C->ct[b][1] = (float)sin(PI * v0); C->ct[b][2] = (float)cos(PI * v1); C->ct[b][3] = (float)sin(PI * v1);
  }
  C->bytes = W->warp_bytes + sizeof *C - sizeof C->W; /* the patch tables, and the level (its normal table is not needed) */
  return 1;
}
/* the weights mass x max(0, max of n.w over the cell + 1e-5) of light-space normal n, the rows' sums, the total */
static inline void cl_weights(const cl_level *C, const float n[3], cl_point *P) {
  int a, b, ku = C->ku;
  float len = sqrtf(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]), nx = n[0] / len, ny = n[1] / len, nz = n[2] / len;
  float A[CL_MAX / 4 + 4], PK[CL_MAX / 4 + 4], tot = 0.0f;
#if EL_ENVLIGHT__SSE
  __m128 vx = _mm_set1_ps(nx), vy = _mm_set1_ps(ny), vz = _mm_set1_ps(nz), rr = _mm_set1_ps(sqrtf(nx * nx + ny * ny)), zero = _mm_setzero_ps();
  __m128 eps = _mm_set1_ps(1e-5f);
  for (a = 0; a < ku; a += 4) { /* the best horizontal component per cell column: n's own phi inside, else the nearer edge */
    __m128 c0 = _mm_loadu_ps(C->cp[0] + a), s0 = _mm_loadu_ps(C->cp[1] + a), c1 = _mm_loadu_ps(C->cp[2] + a), s1 = _mm_loadu_ps(C->cp[3] + a);
    __m128 in = _mm_and_ps(_mm_cmpge_ps(_mm_sub_ps(_mm_mul_ps(c0, vy), _mm_mul_ps(s0, vx)), zero),
                           _mm_cmpge_ps(_mm_sub_ps(_mm_mul_ps(vx, s1), _mm_mul_ps(vy, c1)), zero));
    __m128 edge = _mm_max_ps(_mm_add_ps(_mm_mul_ps(vx, c0), _mm_mul_ps(vy, s0)), _mm_add_ps(_mm_mul_ps(vx, c1), _mm_mul_ps(vy, s1)));
    __m128 av = _mm_or_ps(_mm_and_ps(in, rr), _mm_andnot_ps(in, edge));
    _mm_storeu_ps(A + a, av);
    _mm_storeu_ps(PK + a, _mm_sqrt_ps(_mm_add_ps(_mm_mul_ps(av, av), _mm_mul_ps(vz, vz))));
  }
  for (b = 0; b < C->kv; ++b) { /* a sin(theta) + b cos(theta): its peak if inside the rows' theta range, else the better edge */
    __m128 c0 = _mm_set1_ps(C->ct[b][0]), s0 = _mm_set1_ps(C->ct[b][1]), c1 = _mm_set1_ps(C->ct[b][2]), s1 = _mm_set1_ps(C->ct[b][3]), sum = zero;
    for (a = 0; a < ku; a += 4) {
      __m128 av = _mm_loadu_ps(A + a), f0 = _mm_add_ps(_mm_mul_ps(av, s0), _mm_mul_ps(vz, c0)), f1 = _mm_add_ps(_mm_mul_ps(av, s1), _mm_mul_ps(vz, c1));
      __m128 in = _mm_and_ps(_mm_cmpgt_ps(_mm_sub_ps(_mm_mul_ps(av, c0), _mm_mul_ps(vz, s0)), zero),
                             _mm_cmplt_ps(_mm_sub_ps(_mm_mul_ps(av, c1), _mm_mul_ps(vz, s1)), zero));
      __m128 mv = _mm_or_ps(_mm_and_ps(in, _mm_loadu_ps(PK + a)), _mm_andnot_ps(in, _mm_max_ps(f0, f1)));
      __m128 wv = _mm_mul_ps(_mm_loadu_ps(C->mass + b * ku + a), _mm_max_ps(_mm_add_ps(mv, eps), zero));
      _mm_storeu_ps(P->w + b * ku + a, wv);
      sum = _mm_add_ps(sum, wv);
    }
    sum = _mm_add_ps(sum, _mm_movehl_ps(sum, sum));
    sum = _mm_add_ss(sum, _mm_shuffle_ps(sum, sum, 1));
    P->rows[b] = _mm_cvtss_f32(sum);
    tot += P->rows[b];
  }
#else
  float rr = sqrtf(nx * nx + ny * ny);
  for (a = 0; a < ku; ++a) {
    float c0 = C->cp[0][a], s0 = C->cp[1][a], c1 = C->cp[2][a], s1 = C->cp[3][a], d0 = nx * c0 + ny * s0, d1 = nx * c1 + ny * s1;
    A[a] = c0 * ny - s0 * nx >= 0.0f && nx * s1 - ny * c1 >= 0.0f ? rr : (d0 > d1 ? d0 : d1);
    PK[a] = sqrtf(A[a] * A[a] + nz * nz);
  }
  for (b = 0; b < C->kv; ++b) {
    const float *t = C->ct[b];
    float sum = 0.0f;
    for (a = 0; a < ku; ++a) {
      float f0 = A[a] * t[1] + nz * t[0], f1 = A[a] * t[3] + nz * t[2], mv = f0 > f1 ? f0 : f1;
      if (A[a] * t[0] - nz * t[1] > 0.0f && A[a] * t[2] - nz * t[3] < 0.0f) mv = PK[a];
      mv += 1e-5f;
      P->w[b * ku + a] = C->mass[b * ku + a] * (mv > 0.0f ? mv : 0.0f);
      sum += P->w[b * ku + a];
    }
    P->rows[b] = sum;
    tot += sum;
  }
#endif
  P->total = tot;
}
/* index in [0, n) of x in [0, 1] under weights w (none 0 picked), *rest: the fraction inside it */
static inline int cl_pick(const float *w, int n, float tot, float x, float *rest) {
  int k, last = 0;
  x *= tot;
  for (k = 0; k < n; ++k) {
    if (w[k] > 0.0f) { last = k; if (x < w[k]) break; }
    x -= w[k];
  }
  k = k < n ? k : last;
  x /= w[k];
  *rest = x < 1.0f ? (x > 0.0f ? x : 0.0f) : 1.0f;
  return k;
}
typedef struct { const cl_level *C; const cl_point *P; } cl_ctx;
static float cl_pdf_at(const void *ctx, const float d[3], float uv[2]) {
  const cl_ctx *x = (const cl_ctx *)ctx;
  const struct el_envlight__warp *W = x->C->W;
  el_envlight__ploc q;
  float c[4], wcell;
  int a, b;
  const uint16_t *pc, *pr;
  uint32_t wr;
  uv[0] = uv[1] = 0.0f;
  if (!el_envlight__prod_locate(W, d, &q)) return 0.0f;
  uv[0] = q.u; uv[1] = q.v;
  a = W->cu_of[q.i]; b = W->cv_of[q.r];
  wcell = x->P->w[b * x->C->ku + a];
  pc = W->pcol + (size_t)q.r * W->cond_stride + (size_t)W->coff[a] + (size_t)(q.i - W->a0[a]);
  pr = W->prow + (size_t)a * ((size_t)W->h + 1 + (size_t)W->kv) + (size_t)q.r + (size_t)b;
  wr = (uint32_t)(pc[1] - pc[0]) * (uint32_t)(pr[1] - pr[0]);
  if (!(wcell > 0.0f) || wr == 0) return 0.0f;
  el_envlight__prod_corners(W, q.i, q.r, c);
  return el_envlight__prod_eval(W, &q, 1u << 30, wr, c) * (wcell / x->P->total);
}
static void cl_sample(const el_envlight *l, const cl_level *C, const float n[3], const float u[2], float wi[3], float rgb[3], float *pdf) {
  const struct el_envlight__warp *W = C->W;
  cl_point pt;
  cl_ctx ctx;
  el_envlight__pick P;
  float nl[3];
  int a, b;
  el_envlight__to_light(l, n, nl);
  cl_weights(C, nl, &pt);
  if (!(pt.total > 0.0f)) { *pdf = 0.0f; wi[0] = wi[1] = 0.0f; wi[2] = 1.0f; if (rgb) rgb[0] = rgb[1] = rgb[2] = 0.0f; return; }
  b = cl_pick(pt.rows, C->kv, pt.total, el_envlight__clamp01(u[1]), &P.f1);
  a = cl_pick(pt.w + b * C->ku, C->ku, pt.rows[b], el_envlight__clamp01(u[0]), &P.f0);
  P.a = a; P.b = b;
  P.p = W->prow + (size_t)a * ((size_t)W->h + 1 + (size_t)W->kv) + (size_t)W->b0[b] + (size_t)b;
  el_envlight__pick3(W, &P);
  el_envlight__pick4(W, &P);
  ctx.C = C; ctx.P = &pt;
  finish_patch(l, W, &P, 1u << 30, pt.w[b * C->ku + a] / pt.total, cl_pdf_at, &ctx, wi, rgb, pdf);
}
static float cl_pdf(const el_envlight *l, const cl_level *C, const float n[3], const float wi[3]) {
  cl_point pt;
  cl_ctx ctx;
  float nl[3], d[3], uv[2];
  el_envlight__to_light(l, n, nl);
  if (!el_envlight__to_light_dir(l, wi, d)) return 0.0f;
  cl_weights(C, nl, &pt);
  if (!(pt.total > 0.0f)) return 0.0f;
  ctx.C = C; ctx.P = &pt;
  return cl_pdf_at(&ctx, d, uv);
}

/* the candidates behind one interface */
enum { CA_LIB, CA_ALIAS2, CA_ALIAS4, CA_ALIAS2C, CA_CL };
typedef struct { int kind; const char *name; const alias_tabs *A; const cl_level *C; } cand;
static inline void cand_sample(const el_envlight *l, const cand *c, const float n[3], const float u[2], float wi[3], float rgb[3], float *pdf) {
  if (c->kind == CA_LIB) el_envlight_sample_li_cos(l, n, u, wi, rgb, pdf);
  else if (c->kind == CA_CL) cl_sample(l, c->C, n, u, wi, rgb, pdf);
  else alias_sample(l, c->A, c->kind == CA_ALIAS4 ? 4 : c->kind == CA_ALIAS2C ? 1 : 2, n, u, wi, rgb, pdf);
}
static inline float cand_pdf(const el_envlight *l, const cand *c, const float n[3], const float wi[3]) {
  return c->kind == CA_CL ? cl_pdf(l, c->C, n, wi) : el_envlight_pdf_li_cos(l, n, wi);
}

/* n calls of candidate c's sample (what 0: the loop alone, 1: sample with radiance, 2: pdf, 3: C&L's pass; -1: 1 with nrm's first normal only) over the
 * nb precomputed normals (a new one per call, (k * 7) mod nb as bench_envlight's) and u; returns a sum */
static double cand_loop(const el_envlight *l, const cand *c, int what, long n, const float *nrm, const float *uu, int nb) {
  double acc = 0;
  long k, mn = what < 0 ? 0 : nb - 1; /* what -1: sample with the radiance, always the first normal */
  float wi[3], L[3], p;
  if (what == 0) for (k = 0; k < n; ++k) acc += nrm[3 * ((k * 7) & (nb - 1))] + uu[2 * (k & (nb - 1))];
  else if (what == 1 || what == -1)
    for (k = 0; k < n; ++k) {
      cand_sample(l, c, nrm + 3 * ((k * 7) & mn), uu + 2 * (k & (nb - 1)), wi, L, &p);
      acc += p + wi[0];
    }
  else if (what == 2) for (k = 0; k < n; ++k) acc += cand_pdf(l, c, nrm + 3 * ((k * 7) & (nb - 1)), nrm + 3 * (k & (nb - 1)));
  else if (c->kind == CA_CL) /* C&L's per-point pass alone (to light space and the weights) */
    for (k = 0; k < n; ++k) {
      cl_point pt;
      float nl[3];
      el_envlight__to_light(l, nrm + 3 * ((k * 7) & (nb - 1)), nl);
      cl_weights(c->C, nl, &pt);
      acc += pt.total + uu[2 * (k & (nb - 1))];
    }
  return acc;
}

#define NCAND 7
#define CL0 4 /* the first C&L candidate */
static const int CL_SIZE[3][2] = {{12, 12}, {16, 8}, {16, 16}};
/* builds the candidates of light l (its product tables built); returns the count */
static int cand_make(const el_envlight *l, cand *c, alias_tabs *A, cl_level *C, double *build_ms) {
  const struct el_envlight__warp *W = el_envlight__prod_ensure(l, EL_ENVLIGHT__CELLS_U, EL_ENVLIGHT__CELLS_V, EL_ENVLIGHT__NORMAL_BINS);
  static char names[3][24];
  double t;
  int k;
  memset(c, 0, NCAND * sizeof *c);
  c[0].kind = CA_LIB; c[0].name = "library sample_li_cos";
  t = process_now();
  alias_init(A, W);
  build_ms[1] = build_ms[2] = (process_now() - t) * 1e3;
  c[1].kind = CA_ALIAS2; c[1].name = "alias, cell levels"; c[1].A = A;
  c[2].kind = CA_ALIAS4; c[2].name = "alias, all 4 levels"; c[2].A = A;
  c[3].kind = CA_ALIAS2C; c[3].name = "alias, cells, 4-byte"; c[3].A = A;
  build_ms[3] = build_ms[1];
  for (k = 0; k < 3; ++k) {
    t = process_now();
    if (!cl_init(C + k, l, CL_SIZE[k][0], CL_SIZE[k][1])) return CL0 + k;
    build_ms[CL0 + k] = (process_now() - t) * 1e3;
    snprintf(names[k], sizeof names[k], "C&L %dx%d per point", CL_SIZE[k][0], CL_SIZE[k][1]);
    c[CL0 + k].kind = CA_CL; c[CL0 + k].name = names[k]; c[CL0 + k].C = C + k;
  }
  return NCAND;
}
static void cand_free(alias_tabs *A, cl_level *C, int nc) {
  int k;
  alias_free(A);
  for (k = CL0; k < nc; ++k) el_envlight__warp_free(C[k - CL0].W);
}

/* the chi-square check of the cell pick: each cell's probability for normal n (the library's cell
 * table's integer widths for the library and alias; the weights for C&L) and the cell a sample lands in */
static const struct el_envlight__warp *cand_warp(const el_envlight *l, const cand *c) {
  return c->kind == CA_CL ? c->C->W : el_envlight__prod_ensure(l, EL_ENVLIGHT__CELLS_U, EL_ENVLIGHT__CELLS_V, EL_ENVLIGHT__NORMAL_BINS);
}
static void cand_cell_p(const el_envlight *l, const cand *c, const float n[3], double *pc) {
  const struct el_envlight__warp *W = cand_warp(l, c);
  int a, b, k;
  if (c->kind == CA_CL) {
    cl_point pt;
    float nl[3];
    el_envlight__to_light(l, n, nl);
    cl_weights(c->C, nl, &pt);
    for (k = 0; k < W->ku * W->kv; ++k) pc[k] = pt.w[k] / pt.total;
    return;
  }
  for (b = 0; b < W->kv; ++b) {
    const uint16_t *tab = W->cos_tab + W->cos_off[normal_bin(l, W, n)], *row = el_envlight__sparse_row(W, tab, b);
    for (a = 0; a < W->ku; ++a) {
      k = a - (int)row[0] + (a < (int)row[0] ? W->ku : 0);
      pc[b * W->ku + a] = k < (int)row[1] ? (double)(tab[b + 1] - tab[b]) * (row[k + 3] - row[k + 2]) / 1073741824.0 : 0.0;
    }
  }
}
static int cand_cell_of(const el_envlight *l, const cand *c, const float wi[3]) {
  const struct el_envlight__warp *W = cand_warp(l, c);
  el_envlight__ploc q;
  float d[3];
  if (!el_envlight__to_light_dir(l, wi, d) || !el_envlight__prod_locate(W, d, &q)) return -1;
  return W->cv_of[q.r] * W->ku + W->cu_of[q.i];
}
/* (chi^2 - dof) / sqrt(2 dof) of counts against n pc, over the cells expecting >= 5 (the rest pooled) */
static double chi2_z(const long *cnt, const double *pc, int nc, long n) {
  double chi = 0, eo = 0, oo = 0;
  int k, dof = -1;
  for (k = 0; k < nc; ++k) {
    double e = pc[k] * (double)n;
    if (e >= 5) { chi += (cnt[k] - e) * (cnt[k] - e) / e; ++dof; }
    else { eo += e; oo += (double)cnt[k]; }
  }
  if (eo >= 5) { chi += (oo - eo) * (oo - eo) / eo; ++dof; }
  return dof > 0 ? (chi - dof) / sqrt(2.0 * dof) : 0.0;
}

/* everything the candidates need for one map: the light (its product tables built), the candidates, and
 * NB random normals and u (a new normal per call in the timing and callgrind loops) */
enum { CAND_NB = 1 << 18 };
typedef struct {
  el_image img;
  el_envlight l;
  alias_tabs A;
  cl_level C[3];
  cand c[NCAND];
  int nc;
  double build_ms[NCAND];
  float nrm[3 * CAND_NB], uu[2 * CAND_NB];
} cand_set;
static cand_set *cand_set_make(const char *path) {
  cand_set *S = (cand_set *)calloc(1, sizeof *S);
  char err[512];
  double t;
  if (!S) return NULL;
  if (el_image_load(path, &S->img, err, sizeof err) != 0) { printf("(%s)\n", err); free(S); return NULL; }
  if (el_envlight_init(&S->l, S->img.pixels, S->img.width, S->img.height, 3, NULL) != EL_SUCCESS) { el_image_free(&S->img); free(S); return NULL; }
  t = process_now();
  el_envlight_prepare_product(&S->l, NULL);
  t = (process_now() - t) * 1e3;
  S->nc = cand_make(&S->l, S->c, &S->A, S->C, S->build_ms);
  S->build_ms[0] = t;
  random_dirs_u(S->nrm, S->uu, CAND_NB, 0x853c49e6748fea9bull);
  return S;
}
static void cand_set_free(cand_set *S) {
  cand_free(&S->A, S->C, S->nc);
  el_envlight_free(&S->l);
  el_image_free(&S->img);
  free(S);
}

static void candidates_map(const char *path, int nsamp, int reps) {
  enum { NB = CAND_NB, NLD = 64 };
  cand_set *S = cand_set_make(path);
  double N[NN][3], E[NN], tbest[NCAND], tpdf[NCAND], tfix[NCAND][NN], t, *build_ms;
  int nc, q, k, j, rep, trials = nsamp / NLD;
  size_t bytes[NCAND];
  const float *nrm, *uu;
  cand *c;
  if (!S) return;
  nc = S->nc; c = S->c; nrm = S->nrm; uu = S->uu; build_ms = S->build_ms;
  bytes[0] = el_envlight_product_bytes(&S->l);
  bytes[1] = bytes[0] + S->A.cell_bytes;
  bytes[2] = bytes[1] + S->A.patch_bytes;
  bytes[3] = bytes[0] + S->A.cell_bytes4;
  for (k = CL0; k < nc; ++k) bytes[k] = S->C[k - CL0].bytes;
  six_normals(&S->img, N);
  quadrature(&S->img, N, NN, E);
  for (q = 0; q < nc; ++q) { tbest[q] = tpdf[q] = 1e30; for (k = 0; k < NN; ++k) tfix[q][k] = 1e30; }
  for (rep = 0; rep < reps; ++rep) /* time per sample, a new random normal per call (and a fixed one), interleaved rounds */
    for (q = 0; q < nc; ++q) {
      volatile double sink;
      for (k = 0; k < NN; ++k) {
        float n1[3];
        n1[0] = (float)N[k][0]; n1[1] = (float)N[k][1]; n1[2] = (float)N[k][2];
        t = process_now();
        sink = cand_loop(&S->l, c + q, -1, NB / 4, n1, uu, NB);
        t = process_now() - t;
        if (t < tfix[q][k]) tfix[q][k] = t;
      }
      t = process_now();
      sink = cand_loop(&S->l, c + q, 1, NB, nrm, uu, NB);
      t = process_now() - t;
      if (t < tbest[q]) tbest[q] = t;
      if (q == 0 || q >= CL0) {
        t = process_now();
        sink = cand_loop(&S->l, c + q, 2, NB, nrm, uu, NB);
        t = process_now() - t;
        if (t < tpdf[q]) tpdf[q] = t;
      }
      (void)sink;
    }
  printf("\n%s (%dx%d): %d samples per normal (independent), %d x %d (Owen-scrambled Sobol', one estimate of %d points per trial);\n"
         "ns per sample with the radiance, best of %d interleaved rounds of %d calls (CPU time)\n",
         path, S->img.width, S->img.height, nsamp, trials, NLD, NLD, reps, NB);
  printf("  %-22s %6s %8s %8s %6s %6s %9s %9s %6s %7s %7s %7s %7s %7s %s\n", "candidate", "MiB", "build ms", "relvar", "max|z|", "chi2 z", "pdf diff", "relvar LD",
         "LD/ind", "ns", "x ns", "ns fix", "x ns", "pdf ns", "holes");
  for (q = 0; q < nc; ++q) {
    double gv = 0, gl = 0, gf = 0, zmax = 0, cmax = 0, *pc = (double *)malloc(2048 * sizeof(double));
    long bad = 0, checked = 0, above = 0, hole = 0, *cnt = (long *)malloc(2048 * sizeof(long));
    const struct el_envlight__warp *Wc = cand_warp(&S->l, c + q);
    for (k = 0; k < NN; ++k) {
      float n[3];
      double s1 = 0, s2 = 0, m, var, e1 = 0, e2 = 0;
      rng g;
      g.s = 0x9e3779b97f4a7c15ull * (uint64_t)(k + 1) + (getenv("SEED") ? (uint64_t)atol(getenv("SEED")) : 0u);
      for (j = 0; j < 3; ++j) n[j] = (float)N[k][j];
      memset(cnt, 0, 2048 * sizeof(long));
      for (j = 0; j < nsamp; ++j) {
        float u[2], wi[3], rgb[3], pdf, cs;
        int cell;
        u[0] = rng_f(&g); u[1] = rng_f(&g);
        cand_sample(&S->l, c + q, n, u, wi, rgb, &pdf);
        if (pdf > 0 && (cell = cand_cell_of(&S->l, c + q, wi)) >= 0) ++cnt[cell];
        cs = wi[0] * n[0] + wi[1] * n[1] + wi[2] * n[2];
        if (pdf > 0 && cs > 0) { double f = lum3(rgb) * cs / pdf; s1 += f; s2 += f * f; }
        if ((j & 15) == 0) { /* the pdf function at the sample: the same bits */
          float p2 = cand_pdf(&S->l, c + q, n, wi);
          bad += memcmp(&p2, &pdf, sizeof p2) != 0 && pdf > 0;
          ++checked;
        }
      }
      m = s1 / nsamp; var = s2 / nsamp - m * m;
      gv += log(var / (E[k] * E[k])) / NN;
      cand_cell_p(&S->l, c + q, n, pc);
      if (fabs(chi2_z(cnt, pc, Wc->ku * Wc->kv, nsamp)) > fabs(cmax)) cmax = chi2_z(cnt, pc, Wc->ku * Wc->kv, nsamp);
      if (getenv("VERBOSE"))
        printf("    %-22s %-7s z %6.2f chi2 z %6.2f relvar %.4g\n", c[q].name, NNAME[k], (m - E[k]) / sqrt(var / nsamp), chi2_z(cnt, pc, Wc->ku * Wc->kv, nsamp),
               var / (E[k] * E[k]));
      if (fabs(m - E[k]) / sqrt(var / nsamp) > zmax) zmax = fabs(m - E[k]) / sqrt(var / nsamp);
      for (j = 0; j < trials; ++j) { /* low-discrepancy points: the variance of one estimate of NLD points, x NLD */
        uint32_t sa = hash32((uint32_t)(k * 7919 + j * 2 + 1)), sb = hash32((uint32_t)(k * 7919 + j * 2 + 2)), i;
        double est = 0;
        for (i = 0; i < NLD; ++i) {
          float u[2], wi[3], rgb[3], pdf, cs;
          u[0] = owen24(sobol0(i), sa); u[1] = owen24(sobol1(i), sb);
          cand_sample(&S->l, c + q, n, u, wi, rgb, &pdf);
          cs = wi[0] * n[0] + wi[1] * n[1] + wi[2] * n[2];
          if (pdf > 0 && cs > 0) est += lum3(rgb) * cs / pdf;
        }
        est /= NLD;
        e1 += est; e2 += est * est;
      }
      m = e1 / trials;
      gl += log((e2 / trials - m * m) * NLD / (E[k] * E[k])) / NN;
    }
    for (k = 0; k < NN; ++k) gf += log(tfix[q][k] / (NB / 4) * 1e9) / NN;
    for (k = 0; k < NB; ++k) { /* support: a random normal and direction above it where le > 0 must have pdf > 0 */
      const float *n = nrm + 3 * k, *w = nrm + 3 * ((k * 7 + 1) & (NB - 1));
      float L[3];
      if (n[0] * w[0] + n[1] * w[1] + n[2] * w[2] <= 1e-6f) continue;
      el_envlight_le(&S->l, w, L);
      ++above;
      hole += lum3(L) > 0 && !(cand_pdf(&S->l, c + q, n, w) > 0);
    }
    printf("  %-22s %6.2f %8.1f %8.4f %6.2f %6.2f %4ld/%-4ld %9.4f %6.2f %7.1f %7.2f %7.1f %7.2f", c[q].name, bytes[q] / 1048576.0, build_ms[q], exp(gv), zmax, cmax,
           bad, checked, exp(gl), exp(gl - gv), tbest[q] / NB * 1e9, exp(gv) * tbest[q] / NB * 1e9, exp(gf), exp(gv + gf));
    printf(" %7.1f", tpdf[q] < 1e30 ? tpdf[q] / NB * 1e9 : 0.0);
    printf(" %ld/%ld\n", hole, above);
    free(pc); free(cnt);
    fflush(stdout);
  }
  printf("  (relvar: geometric mean over the six normals of Var / E^2 per sample, E the quadrature; max|z|: the largest |mean - E| /\n"
         "   standard error over the normals; chi2 z: the cells' counts against their probabilities, (chi^2 - dof) / sqrt(2 dof),\n"
         "   the largest |.| of the normals; pdf diff: samples whose pdf function differs from the returned pdf, of those checked;\n"
         "   LD/ind: Sobol' variance per point over independent; ns: a new random normal per call; ns fix: one normal per run, the\n"
         "   geometric mean over the six; x ns: relvar x ns, the time to unit variance; pdf ns: random normals and directions\n"
         "   (0: pdf_li_cos itself); holes: random normals and directions above them with le > 0 but pdf 0, of those tried;\n"
         "   MiB: everything a query reads)\n");
  cand_set_free(S);
}

/* --callgrind OP N [MAP]: only N calls of OP after the setup (callgrind_product.sh's interface). OP: loop,
 * lib, alias2, alias4, alias2c, cl12x12, cl16x8, cl16x16 (samples with the radiance), one of those + "_pdf", or a
 * C&L one + "_pass" (its per-point pass alone: the normal to light space and the cells' weights) */
static int candidates_callgrind(const char *op, long n, const char *map) {
  static const char *ops[NCAND] = {"lib", "alias2", "alias4", "alias2c", "cl12x12", "cl16x8", "cl16x16"};
  cand_set *S = cand_set_make(map ? map : EL_SOURCE_DIR "/data/envmaps/city.hdr");
  volatile double sink = 0;
  int q;
  size_t len = 0;
  if (!S) return 1;
  if (!strcmp(op, "loop")) sink = cand_loop(&S->l, S->c, 0, n, S->nrm, S->uu, CAND_NB);
  else {
    for (q = 0; q < S->nc; ++q) {
      len = strlen(ops[q]);
      if (!strncmp(op, ops[q], len) && (op[len] == 0 || !strcmp(op + len, "_pdf") || (q >= CL0 && !strcmp(op + len, "_pass")))) break;
    }
    if (q == S->nc) { fprintf(stderr, "unknown OP %s\n", op); cand_set_free(S); return 2; }
    sink = cand_loop(&S->l, S->c + q, op[len] == 0 ? 1 : op[len + 2] == 'd' ? 2 : 3, n, S->nrm, S->uu, CAND_NB);
  }
  (void)sink;
  cand_set_free(S);
  return 0;
}

int main(int argc, char **argv) {
  const char *maps[5] = {"city", "sunset", "night", "forest", "studio"};
  const char *only = getenv("ONLY");
  int i, nsamp = getenv("NSAMP") ? atoi(getenv("NSAMP")) : 200000;
  if (argc > 1 && !strcmp(argv[1], "--library")) {
    if (argc == 2) {
      library_map(EL_SOURCE_DIR "/data/envmaps/city.hdr", nsamp);
      library_map(EL_SOURCE_DIR "/data/envmaps/studio.hdr", nsamp);
    }
    for (i = 2; i < argc; ++i) library_map(argv[i], nsamp);
    return 0;
  }
  if (argc > 1 && !strcmp(argv[1], "--candidates")) {
    int reps = getenv("REPS") ? atoi(getenv("REPS")) : 3;
    if (argc == 2) {
      candidates_map(EL_SOURCE_DIR "/data/envmaps/city.hdr", nsamp, reps);
      candidates_map(EL_SOURCE_DIR "/data/envmaps/studio.hdr", nsamp, reps);
    }
    for (i = 2; i < argc; ++i) candidates_map(argv[i], nsamp, reps);
    return 0;
  }
  if (argc >= 4 && !strcmp(argv[1], "--callgrind")) return candidates_callgrind(argv[2], atol(argv[3]), argc >= 5 ? argv[4] : NULL);
  if (argc > 1 && !strcmp(argv[1], "--batch")) {
    int reps = getenv("REPS") ? atoi(getenv("REPS")) : 5;
    if (argc == 2) {
      batch_map(EL_SOURCE_DIR "/data/envmaps/city.hdr", reps);
      batch_map(EL_SOURCE_DIR "/data/envmaps/studio.hdr", reps);
    }
    for (i = 2; i < argc; ++i) batch_map(argv[i], reps);
    return 0;
  }
  if (argc > 1 && !strcmp(argv[1], "--picture"))
    return picture(argc > 2 ? argv[2] : "out/product_samples.png", argc > 3 ? argv[3] : EL_SOURCE_DIR "/data/envmaps/city.hdr");
  printf("Relative variance per sample of the irradiance estimate (Var / E^2, luminance) by normal (light space)\n"
         "'light': the strategy alone; '+MIS': one sample of it + one cosine sample, balance heuristic.\n"
         "'below': light samples below the horizon (wasted). MB, build: the strategy's tables.\n");
  if (argc > 1) {
    for (i = 1; i < argc; ++i) do_map(argv[i], nsamp, only);
    return 0;
  }
  for (i = 0; i < 5; ++i) {
    char path[512];
    snprintf(path, sizeof path, "%s/../shared/envmaps/%s.hdr", EL_SOURCE_DIR, maps[i]);
    do_map(path, nsamp, only);
  }
  return 0;
}
