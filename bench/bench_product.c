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
  rng g;
  if (!nrm || !uu || !wi || !rgb || !pdf) return;
  if (el_image_load(path, &img, err, sizeof err) != 0) { printf("(%s)\n", err); return; }
  if (el_envlight_init(&l, img.pixels, img.width, img.height, 3, NULL) != EL_SUCCESS) return;
  el_envlight_prepare_product(&l, NULL);
  el_envlight_prepare_sampling(&l);
  g.s = 0x853c49e6748fea9bull;
  for (k = 0; k < NB; ++k) { /* uniform directions */
    float z = 1.0f - 2.0f * rng_f(&g), r = sqrtf(z < 1.0f && z > -1.0f ? 1.0f - z * z : 0.0f), ph = 6.2831853f * rng_f(&g);
    nrm[3 * k] = r * cosf(ph); nrm[3 * k + 1] = r * sinf(ph); nrm[3 * k + 2] = z;
    uu[2 * k] = rng_f(&g); uu[2 * k + 1] = rng_f(&g);
  }
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
