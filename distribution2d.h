/* distribution2d.h - 1D and 2D piecewise-constant distributions that sample every bin they claim to.
 * envlight v0.1.0 - MIT or public domain
 *
 * DO THIS in exactly one C or C++ file (the first line alone is enough):
 *     #define EL_IMPLEMENTATION   // implements every envlight header included after it
 *     #include "distribution2d.h"
 * Every other file includes it without the macro. EL_DISTRIBUTION2D_IMPLEMENTATION instead implements
 * distribution2d.h alone: a module's own macro never implements another module's header.
 *
 * USAGE (C; where C writes `= {0}`, C++ writes `= {}`; tests/test_snippets.c compiles both)
 * >> usage
 *     // given: float u0, u1;                      (uniform in [0,1): u1 picks the row, u0 the column)
 *     float f[8] = {1, 2, 0, 1, 4, 0, 0, 1};     // 4 columns, 2 rows: f[v * 4 + u] >= 0
 *     el_distribution2d d;
 *     el_distribution_options opt = {0};          // C++: = {}. All zero: [0,1]^2, bad values are errors
 *     if (el_distribution2d_init(&d, f, 4, 2, &opt) != EL_SUCCESS) return 1;  // d.bad_index
 *     float u, v, pdf;
 *     el_distribution2d_sample(&d, u0, u1, &u, &v, &pdf);  // pdf == el_distribution2d_pdf(&d, u, v)
 *     el_distribution2d_fast fast;                // the same distribution in O(1) expected time:
 *     if (el_distribution2d_fast_init(&fast, &d) == EL_SUCCESS)  // the same points and pdfs
 *       el_distribution2d_fast_sample(&fast, u0, u1, &u, &v, &pdf);
 *     el_distribution2d_fast_free(&fast);         // before d, whose tables it shares
 *     el_distribution2d_free(&d);
 * << usage
 *
 * OPTIONS (define before including): EL_MALLOC / EL_REALLOC / EL_FREE (all or none), EL_ASSERT,
 * EL_STATIC, EL_DEF; EL_NO_SIMD (the scalar construction loops instead of SSE2: the same results).
 *
 * PORTS pbrt-v3's Distribution1D / Distribution2D (src/core/sampling.h: SampleContinuous,
 * SampleDiscrete, Pdf, funcInt, the marginal and conditional distributions) and pbrt-v4's
 * PiecewiseConstant1D / PiecewiseConstant2D (src/pbrt/util/sampling.h: a domain rectangle and Invert),
 * with an integer CDF instead of pbrt's float one, and guide-table and alias-table samplers of the same
 * distribution. NOTES after the declarations: where and why it departs from pbrt, stratification,
 * conventions, costs, threads, limits.
 */
#ifndef EL_DISTRIBUTION2D_H
#define EL_DISTRIBUTION2D_H

/* >> shared declarations (identical in every envlight header; guarded so any set of headers can be
 * included together, in any order). Change it in every header at once, or not at all. */
#ifndef EL_SHARED_DECLARATIONS
#define EL_SHARED_DECLARATIONS
#include <stddef.h>
#ifndef EL_DEF
#ifdef EL_STATIC
#define EL_DEF static
#else
#define EL_DEF extern
#endif
#endif
#ifndef EL_ASSERT
#include <assert.h>
#define EL_ASSERT(x) assert(x)
#endif
#if defined(EL_MALLOC) && defined(EL_FREE) && defined(EL_REALLOC)
/* the user supplied all three */
#elif !defined(EL_MALLOC) && !defined(EL_FREE) && !defined(EL_REALLOC)
#include <stdlib.h>
#define EL_MALLOC(sz) malloc(sz)
#define EL_REALLOC(p, newsz) realloc(p, newsz)
#define EL_FREE(p) free(p)
#else
#error "envlight: define all of EL_MALLOC, EL_REALLOC and EL_FREE, or none of them"
#endif
#ifdef __cplusplus
extern "C" {
#endif
/* What a constructor, loader or parser returns. el_result_string() explains a value. */
typedef enum el_result {
  EL_SUCCESS = 0,
  EL_ERROR_INVALID_ARGUMENT = 1, /* a NULL pointer, a size <= 0, channels outside 1..4, an unknown enum */
  EL_ERROR_OUT_OF_MEMORY = 2,    /* EL_MALLOC returned NULL */
  EL_ERROR_SIZE_OVERFLOW = 3,    /* a byte count would overflow size_t (or exceeds an int index) */
  EL_ERROR_NAN = 4,              /* an input value is NaN */
  EL_ERROR_INFINITE = 5,         /* an input value is infinite */
  EL_ERROR_NEGATIVE = 6,         /* an input value is negative where only >= 0 is allowed */
  EL_ERROR_NOT_ORTHONORMAL = 7,  /* a matrix that must be a rotation or reflection is not */
  EL_ERROR_EMPTY = 8             /* an input has no elements (n = 0, a 0-sized image) */
} el_result;
static inline const char *el_result_string(el_result r) {
  switch (r) {
  case EL_SUCCESS: return "success";
  case EL_ERROR_INVALID_ARGUMENT: return "invalid argument (NULL pointer, non-positive size, or value out of range)";
  case EL_ERROR_OUT_OF_MEMORY: return "out of memory";
  case EL_ERROR_SIZE_OVERFLOW: return "size overflow: the requested size is too large";
  case EL_ERROR_NAN: return "input contains a NaN value";
  case EL_ERROR_INFINITE: return "input contains an infinite value";
  case EL_ERROR_NEGATIVE: return "input contains a negative value";
  case EL_ERROR_NOT_ORTHONORMAL: return "matrix is not orthonormal (not a rotation or reflection)";
  case EL_ERROR_EMPTY: return "input is empty (zero elements)";
  }
  return "unknown el_result value";
}
#ifdef __cplusplus
}
#endif
#endif /* EL_SHARED_DECLARATIONS */
/* << shared declarations */

#include <stdint.h>
#include <string.h> /* memcpy in the inline bin sampler */

#ifdef __cplusplus
extern "C" {
#endif

/* >> declarations */

#define EL_DISTRIBUTION_UNITS 16777216u  /* 2^24: the CDF's integer total; a bin's pmf is units * 2^-24 */
#define EL_DISTRIBUTION_MAX_BINS 4194304 /* 2^22 bins per dimension at most */

/* Options for both constructors. All zero = pbrt's behaviour where it is sound: domain [0,1] (1D) or
 * [0,1]^2 (2D), and bad values (NaN, Inf, negative) are errors. */
typedef struct el_distribution_options {
  int clamp_bad_values; /* 0: NaN/Inf/negative -> error (d.bad_index); 1: NaN and negative (also -Inf)
                           count as 0, +Inf counts as FLT_MAX */
  float domain[4];      /* u0, v0, u1, v1 (2D: [u0,u1] x [v0,v1]; 1D: [domain[0], domain[2]]).
                           All four zero = the unit square / unit interval. */
} el_distribution_options;

/* A 1D piecewise-constant distribution over n bins of the domain [x0, x1]. */
typedef struct el_distribution1d {
  uint32_t *cdf;      /* n+1 integers, cdf[0] = 0, cdf[n] = 2^24; bin i has cdf[i+1]-cdf[i] units */
  int n;
  int all_zero;       /* 1: every f was 0: sampling is uniform, every pdf is 0 */
  float x0, x1;       /* the domain */
  float bin_scale;    /* n / (x1 - x0): x -> bin coordinate */
  float bin_width;    /* (x1 - x0) / n */
  float pdf_scale;    /* 2^-24 * n / (x1 - x0), 0 when all_zero: pdf = units * pdf_scale */
  float integral;     /* sum f_i * (x1 - x0) / n (clamped to FLT_MAX) */
  float last;         /* (float)(n - 1) */
  int exact;          /* 1 when x0 = 0 and the bin width is a power of two: placing a point needs no check */
  int bad_index;      /* after init: the index of the first bad value when init failed on one (EL_ERROR_NAN,
                         _INFINITE, _NEGATIVE), else -1. A failed init zeroes every other field. */
} el_distribution1d;

/* f has n values >= 0. opt may be NULL (all-zero options). On failure *d is zeroed but for d->bad_index
 * (freeing it is safe). */
EL_DEF el_result el_distribution1d_init(el_distribution1d *d, const float *f, int n, const el_distribution_options *opt);
EL_DEF void el_distribution1d_free(el_distribution1d *d);
/* A point in [x0, x1) with density *pdf (w.r.t. length; 0 for all-zero input); *offset = its bin.
 * pdf and offset may be NULL. */
EL_DEF float el_distribution1d_sample_continuous(const el_distribution1d *d, float u, float *pdf, int *offset);
/* A bin index with probability *pmf (exactly units * 2^-24; 0 for all-zero input), and *u_remapped, the
 * position of u within the bin's interval, in [0,1) (resolution: 1/units of the bin near u = 1). */
EL_DEF int el_distribution1d_sample_discrete(const el_distribution1d *d, float u, float *pmf, float *u_remapped);
/* The density sample_continuous has at x (x clamped to the domain; NaN -> x0). */
EL_DEF float el_distribution1d_pdf(const el_distribution1d *d, float x);
/* pbrt-v4 Invert: the u in [0,1] that sample_continuous maps to x (x clamped to the domain). For x in a
 * bin of zero width (f = 0), the u where that bin would start. */
EL_DEF float el_distribution1d_invert(const el_distribution1d *d, float x);
EL_DEF float el_distribution1d_integral(const el_distribution1d *d);
EL_DEF size_t el_distribution1d_bytes(const el_distribution1d *d);

/* A 2D piecewise-constant distribution: nv rows (marginal in v) of nu bins (conditional in u). */
typedef struct el_distribution2d {
  uint32_t *cdf;      /* nv rows of nu+1 integers (row v starts at cdf + v*(nu+1)) */
  uint32_t *marginal; /* nv+1 integers: the rows' CDF */
  int nu, nv;
  int all_zero;
  float domain[4];    /* u0, v0, u1, v1 */
  float u_scale, v_scale; /* nu / (u1-u0), nv / (v1-v0) */
  float u_width, v_width; /* (u1-u0) / nu, (v1-v0) / nv */
  float u_pdf_scale, v_pdf_scale; /* 2^-24 * nu / (u1-u0), 2^-24 * nv / (v1-v0); 0 when all_zero */
  float integral;     /* sum f * area / (nu*nv) (clamped to FLT_MAX) */
  float u_last, v_last; /* (float)(nu - 1), (float)(nv - 1) */
  int u_exact, v_exact; /* as el_distribution1d.exact, per axis */
  int bad_index;      /* after init: the index v*nu+u of the first bad value when init failed on one, else -1
                         (capped at INT_MAX). A failed init zeroes every other field. */
} el_distribution2d;

/* f[v*nu + u], nu columns, nv rows, all >= 0. opt may be NULL. On failure *d is zeroed but for
 * d->bad_index. */
EL_DEF el_result el_distribution2d_init(el_distribution2d *d, const float *f, int nu, int nv, const el_distribution_options *opt);
EL_DEF void el_distribution2d_free(el_distribution2d *d);
/* CDF inversion (stratification-preserving): u1 picks the row (v), u0 the column (u), as in pbrt.
 * (*out_u, *out_v) lies in [u0,u1) x [v0,v1); *pdf is w.r.t. area of the domain and equals
 * el_distribution2d_pdf(d, *out_u, *out_v) exactly. All-zero input: the uniform point, pdf 0.
 * Cost: two binary searches (log2 nu + log2 nv steps). */
EL_DEF void el_distribution2d_sample(const el_distribution2d *d, float u0, float u1, float *out_u, float *out_v, float *pdf);
/* The density of sample()'s points at (u, v), clamped to the domain, NaN -> the lower end. */
EL_DEF float el_distribution2d_pdf(const el_distribution2d *d, float u, float v);
/* pbrt-v4 Invert: (u0, u1) in [0,1]^2 that sample() maps to (u, v). */
EL_DEF void el_distribution2d_invert(const el_distribution2d *d, float u, float v, float *out_u0, float *out_u1);
EL_DEF float el_distribution2d_integral(const el_distribution2d *d);
EL_DEF size_t el_distribution2d_bytes(const el_distribution2d *d);

/* >> constant-time sampler of the same 2D distribution */
#define EL_DISTRIBUTION_FAST_GUIDE 0 /* default: guide-table CDF inversion; same points as sample(), keeps
                                        stratification; O(1) expected, O(log n) worst case per dimension */
#define EL_DISTRIBUTION_FAST_ALIAS 1 /* Walker/Vose alias table with exact integer weights; O(1) worst case;
                                        same pdf, different points; does NOT keep stratification */
typedef struct el_distribution_fast_options {
  int method;           /* EL_DISTRIBUTION_FAST_GUIDE (0) or EL_DISTRIBUTION_FAST_ALIAS */
  int guide_shrink_log2;/* guide: cells per row = (next power of two >= nu) >> s, where s = this value
                           when > 0, s = 0 when < 0 (as many cells as bins, 4 bytes per bin), and s = 2
                           when 0 (the default: a quarter as many cells as bins, 1 byte per bin) */
} el_distribution_fast_options;

typedef struct el_distribution2d_fast {
  int method;
  int nu, nv;
  /* copied from the el_distribution2d, whose arrays are shared: free the fast sampler first */
  const uint32_t *cdf, *marginal;
  float domain[4];
  float u_scale, v_scale, u_width, v_width, u_pdf_scale, v_pdf_scale;
  float u_last, v_last;
  int u_exact, v_exact;
  size_t row_stride;    /* nu + 1 */
  size_t guide_stride;  /* gu + 1 */
  /* guide table: cell g of a row covers units [g << shift, (g+1) << shift) */
  uint32_t *guide_u;    /* nv rows of gu+1 bin indices */
  uint32_t *guide_v;    /* gv+1 */
  int gu, gv, shift_u, shift_v;
  /* alias table: cell j covers units [start[j], start[j+1]); k < split -> bin j, else bin alias */
  uint32_t *alias_u;    /* nv rows of nu (split, alias) pairs */
  uint32_t *alias_v;    /* nv (split, alias) pairs */
  uint32_t *start_u;    /* nu+1 */
  uint32_t *start_v;    /* nv+1 */
  float gu_scale, gv_scale; /* (float)gu, (float)gv: a guide cell is floor(u * cells), as (units >> shift) */
} el_distribution2d_fast;

/* d must stay alive and unchanged while f is used (f shares its CDF arrays). On failure *f is zeroed. */
EL_DEF el_result el_distribution2d_fast_init(el_distribution2d_fast *f, const el_distribution2d *d);
EL_DEF el_result el_distribution2d_fast_init_ex(el_distribution2d_fast *f, const el_distribution2d *d, const el_distribution_fast_options *opt);
EL_DEF void el_distribution2d_fast_free(el_distribution2d_fast *f);
/* Same contract as el_distribution2d_sample; *pdf == el_distribution2d_pdf(d, *out_u, *out_v) exactly.
 * With the guide method the point is also identical to el_distribution2d_sample's. */
EL_DEF void el_distribution2d_fast_sample(const el_distribution2d_fast *f, float u0, float u1, float *out_u, float *out_v, float *pdf);
/* Same value as el_distribution2d_pdf (shared bins), for callers holding only the fast sampler. */
EL_DEF float el_distribution2d_fast_pdf(const el_distribution2d_fast *f, float u, float v);
/* Bytes of the fast sampler's own tables (not counting the shared CDF). */
EL_DEF size_t el_distribution2d_fast_bytes(const el_distribution2d_fast *f);

/* >> bins instead of points: for callers that map a bin to something else (envlight.h maps it to a
 * direction through per-row and per-column tables) and so need no float point placement.
 * (*iu, *iv) is the bin CDF inversion (or the alias table) picks for (u0, u1), chosen with exactly the
 * sample() probability, and *fu, *fv in [0, 1] the position of u within the bin's interval of units
 * (the same fractions sample() places its point with; rounding may give exactly 1), and *pdf the bin's
 * density, exactly el_distribution2d_pdf() at any point of the bin (the same expression, from the CDF
 * entries the search has just read). u is clamped as in sample(). The guide-table and CDF versions
 * return identical results for the same u. */
EL_DEF void el_distribution2d_sample_bins(const el_distribution2d *d, float u0, float u1, int *iu, int *iv, float *fu, float *fv, float *pdf);
EL_DEF void el_distribution2d_fast_sample_bins_general(const el_distribution2d_fast *f, float u0, float u1, int *iu, int *iv, float *fu, float *fv, float *pdf);
#define EL_DISTRIBUTION__GUIDE_CROWDED 0x80000000u /* a guide cell where more than 64 bins start */
/* Last i in [lo, lo+len-1] with c[i] <= k, given c[lo] <= k. Branch-free binary search. */
static inline int el_distribution2d__search(const uint32_t *c, int lo, int len, uint32_t k) {
  while (len > 1) {
    int half = len >> 1;
    lo = (c[lo + half] <= k) ? lo + half : lo;
    len -= half;
  }
  return lo;
}

/* Inline, no calls, for a guide-method sampler and u0, u1 in [+0, 1) only (el_distribution2d_u_in_range):
 * the guide table (one table read and a short scan per dimension). Returns 0 without writing anything
 * when a cell is crowded (then call el_distribution2d_fast_sample_bins_general, which binary-searches
 * it). */
static inline int el_distribution2d_fast_guide_bins(const el_distribution2d_fast *f, float u0, float u1, int *iu, int *iv, float *fu, float *fv, float *pdf) {
  /* v first, then u, each finished (fraction, width) before the next starts: few live registers */
  float xv = u1 * 16777216.0f, xu = u0 * 16777216.0f, wv, wu, av; /* exact */
  uint32_t kv = (uint32_t)(int32_t)xv, ku, g, c0, c1;
  const uint32_t *row, *mg = f->marginal;
  size_t v, u;
  /* the cell floor(u * cells) equals (units >> shift): cells is a power of two, the product exact */
  g = f->guide_v[(size_t)(int64_t)(u1 * f->gv_scale)];
  if (g & EL_DISTRIBUTION__GUIDE_CROWDED) return 0; /* many bins start in this cell: binary search */
  v = g;
  while ((c1 = mg[v + 1]) <= kv) ++v; /* at most 64 steps */
  c0 = mg[v];
  wv = (float)(int32_t)(c1 - c0);
  av = (xv - (float)(int32_t)c0) / wv;
  g = f->guide_u[v * f->guide_stride + (size_t)(int64_t)(u0 * f->gu_scale)];
  if (g & EL_DISTRIBUTION__GUIDE_CROWDED) return 0;
  ku = (uint32_t)(int32_t)xu;
  row = f->cdf + v * f->row_stride;
  u = g;
  while ((c1 = row[u + 1]) <= ku) ++u;
  c0 = row[u];
  wu = (float)(int32_t)(c1 - c0);
  *fu = (xu - (float)(int32_t)c0) / wu;
  *fv = av;
  *pdf = (wv * f->v_pdf_scale) * (wu * f->u_pdf_scale); /* el_distribution2d_pdf's expression */
  *iv = (int)v;
  *iu = (int)u;
  return 1;
}
/* 1 when u0 and u1 both lie in [+0, 1) (not NaN, not -0): one integer comparison of the larger bits. */
static inline int el_distribution2d_u_in_range(float u0, float u1) {
  uint32_t b0, b1;
  memcpy(&b0, &u0, 4);
  memcpy(&b1, &u1, 4);
  return (b0 > b1 ? b0 : b1) < 0x3f800000u;
}
/* Any method, any u: the guide table's inline path, or 0 (u outside [0,1) or NaN, the alias method, a
 * crowded cell): then call el_distribution2d_fast_sample_bins_general. */
static inline int el_distribution2d_fast_sample_bins_try(const el_distribution2d_fast *f, float u0, float u1, int *iu, int *iv, float *fu, float *fv, float *pdf) {
  if (el_distribution2d_u_in_range(u0, u1) && f->method == EL_DISTRIBUTION_FAST_GUIDE)
    return el_distribution2d_fast_guide_bins(f, u0, u1, iu, iv, fu, fv, pdf);
  return 0;
}
/* Any u, any method: the same results as the general function. */
static inline void el_distribution2d_fast_sample_bins(const el_distribution2d_fast *f, float u0, float u1, int *iu, int *iv, float *fu, float *fv, float *pdf) {
  if (!el_distribution2d_fast_sample_bins_try(f, u0, u1, iu, iv, fu, fv, pdf)) el_distribution2d_fast_sample_bins_general(f, u0, u1, iu, iv, fu, fv, pdf);
}
/* << constant-time sampler */

/* >> inline helpers (hot, shared by every translation unit) */

/* u in [0,1) as a float multiple of 2^-24 resolution: NaN/negative -> 0, >= 1 -> 0x1.fffffep-1. Returns
 * u * 2^24 (exact). */
static inline float el_distribution2d__units(float u) {
  u = u > 0.0f ? u : 0.0f;                 /* NaN -> 0 (maxss) */
  u = u < 0.99999994f ? u : 0.99999994f;  /* 0x1.fffffep-1 (minss) */
  return u * 16777216.0f;
}
/* The bin of x in a domain starting at x0, scale = n/(x1-x0), last = (float)(n-1): clamped, NaN -> 0. */
static inline int el_distribution2d__bin_last(float x, float x0, float scale, float last) {
  float t = (x - x0) * scale;
  t = t > 0.0f ? t : 0.0f;
  t = t < last ? t : last;
  return (int)t;
}
static inline int el_distribution2d__bin(float x, float x0, float scale, int n) {
  return el_distribution2d__bin_last(x, x0, scale, (float)(n - 1));
}
/* << inline helpers */

/* << declarations */

#ifdef __cplusplus
}
#endif
#endif /* EL_DISTRIBUTION2D_H */

/* ====================================================================================================
 * NOTES (the reasons behind the API; a user of the functions above needs none of this)
 *
 * WHAT IT PORTS: pbrt-v3 Distribution1D / Distribution2D (src/core/sampling.h) and pbrt-v4
 * PiecewiseConstant1D / PiecewiseConstant2D (src/pbrt/util/sampling.h): continuous and discrete sampling,
 * pdf, integral, domain rectangle, and pbrt-v4's Invert (point -> u).
 *
 * WHERE IT DEPARTS FROM pbrt, AND WHY
 * 1. The CDF is integer. pbrt stores a float CDF built by cdf[i] = cdf[i-1] + func[i]/n. Once the sum
 *    passes a large value, small increments round away: on a 4096-bin row holding one 1e6 texel among
 *    1e-2 values, 3995 bins have a positive pdf and a CDF step of zero, so they are never sampled (a
 *    bias: their radiance never enters an estimate). Here the CDF of every row is a list of integers
 *    c[0] = 0 <= c[1] <= ... <= c[n] = 2^24 ("units" of 2^-24). A uniform u in [0,1) is turned into
 *    k = floor(u * 2^24) - exact, since u * 2^24 is a float times a power of two - and bin i is the one
 *    with c[i] <= k < c[i+1]. So bin i is chosen with probability EXACTLY (c[i+1] - c[i]) * 2^-24, for
 *    continuous uniform u and equally for u drawn as j * 2^-24 (the usual 24-bit float generator), and
 *    that exact probability is the pmf we state: the pdf is a function of the integer widths, not of f.
 *    Every bin with f > 0 gets at least one unit, so every such bin is reachable (f = 0 bins get none);
 *    the remaining 2^24 - m units (m = number of positive bins) are shared in proportion to f.
 *    Consequence: each pmf is within (2 + m f/sum) * 2^-24 of f/sum (rounding, plus a uniform floor of
 *    m * 2^-24 of the mass, <= 0.05% for 8192 bins) - a tiny change in variance, no bias, at any
 *    dynamic range (tested to 1e12). The CDF is built from 64-bit fixed-point prefix sums: no rounding
 *    error accumulates along a row (pbrt's float running sum is what loses the small bins).
 * 2. pdf(sample(u)) == the pdf returned by sample(u), bit for bit: the sampled point is placed strictly
 *    inside its bin (it is nudged by an ulp when rounding would carry it to a neighbour), never equals
 *    the domain's upper end, and pdf() recomputes the same bin with the same expression.
 * 3. All-zero input is valid: pdf 0 everywhere, integral 0, and sample() returns the uniform point
 *    (CDF inversion of a constant function) with pdf 0 - never 0/0 (pbrt-v3 and v4 return NaN).
 * 4. Bad input is an error naming the first bad index (d.bad_index): n == 0 -> EL_ERROR_EMPTY,
 *    n < 0 or f == NULL -> EL_ERROR_INVALID_ARGUMENT, NaN -> EL_ERROR_NAN, +-Inf -> EL_ERROR_INFINITE, negative -> EL_ERROR_NEGATIVE (checked in that
 *    order for each value). With options.clamp_bad_values = 1: NaN and negative (including -Inf) count as
 *    0 and +Inf as FLT_MAX.
 * 5. Memory: 4 bytes per bin (pbrt: 8, func and cdf). The values f are not kept.
 * 6. A constant-expected-time sampler of the SAME distribution (el_distribution2d_fast): the pdf is a
 *    function of the bin, and the fast samplers choose each bin with exactly the same integer number of
 *    units, so their pdfs are identical to the CDF sampler's (not just close).
 *
 * STRATIFICATION. CDF inversion is monotone in u: stratified or low-discrepancy u (Sobol', Halton,
 * jittered) stay stratified in the output. el_distribution2d_sample and the GUIDE-table fast sampler
 * (EL_DISTRIBUTION_FAST_GUIDE, the default) are CDF inversion and return exactly the same points for
 * the same u. The ALIAS-table sampler (EL_DISTRIBUTION_FAST_ALIAS) is not monotone: it destroys the
 * stratification of its input (fine for independent random numbers). bench/bench_distribution2d.c
 * measures both; the guide table is the default because it is as fast and keeps stratification.
 *
 * u AND POINT CONVENTIONS. u outside [0,1) is clamped: NaN and u <= 0 act as 0, u >= 1 acts as
 * 0x1.fffffep-1 (so u = 1 is in range). pdf() and invert() clamp a point outside the domain to it
 * (pbrt's convention) and treat NaN as the domain's lower end. Sample positions within a bin come from
 * the same u through the float t = i + fraction (i the bin), so bin i >= 1 has at most 2^(23 -
 * floor(log2 i)) distinct positions however many units w it has (4096 in bin 4000); a bin with w units
 * at most half that many, and bin 0, has w.
 *
 * COST (bench/bench_distribution2d.c, 4096x2048, gcc -O3, callgrind): a 2D sample with its pdf takes
 * about 106 instructions with the guide table, 125 with the alias table and about 300 with the binary
 * searches (pbrt-v3: about 350); pdf() about 32 (pbrt-v3: 13, from its second array). A guide cell in
 * which more than 64 bins start is flagged in the table (bit 31) and searched by bisection (a linear scan
 * of up to 64 steps costs about what the bisection does; fewer flags keep more samples on the inline
 * path: on real maps 8 sent about 10% of samples to bisection); the marginal's
 * guide has 4 cells per row (a sun crowds it), the rows' one a quarter cell per bin. Callers that need
 * the bin rather than a point (envlight.h) use el_distribution2d_fast_sample_bins: bin, fractions and
 * pdf, no point placement, inline (envlight.h's SSE2 sample_li does the same search with vector ends,
 * in about 55 of its 95 instructions). Memory: CDF 4
 * bytes per bin, guide table +1 byte per bin (default), alias table +8 bytes per bin. Building runs
 * two passes over each row's values, in SSE2 on x86 (EL_NO_SIMD: scalar code giving the same integers):
 * the check and sum, about 4.5 instructions per bin, and the integer CDF, about 14 (scalar: 11 and 17);
 * the guide table adds about 10 per bin (callgrind, 2048x1024 map of envlight's bench, gcc 12 -O3, no
 * -march). The fast paths take u in [0,1); an "exact"
 * axis (domain starting at 0, power-of-two bin width: any power-of-two size on [0,1]) needs no check
 * of the placed point, other axes one (a few instructions more); anything else, and the rare point
 * that rounding carries out of its bin, takes a general path with the same results.
 *
 * THREADS. Everything after init is read-only: any number of threads may sample and query at once.
 * Queries need a successful init (a struct zeroed by a failed init may only be freed).
 *
 * LIMITS. At most 2^22 = EL_DISTRIBUTION_MAX_BINS bins per dimension (EL_ERROR_SIZE_OVERFLOW beyond);
 * nu * nv bins must fit in memory (sizes are overflow-checked). A domain must be finite, non-empty, and
 * resolve its bins: each bin at least 4 times as wide as the float step just inside the domain's end of
 * larger magnitude, and the largest pdf finite (EL_ERROR_INVALID_ARGUMENT otherwise). The unit interval
 * (2^-24 below 1) takes the full 2^22 bins.
 * ==================================================================================================== */

/* ====================================================================================================
 * IMPLEMENTATION BELOW. Stop reading here if you only need the API.
 * ==================================================================================================== */

#if defined(EL_IMPLEMENTATION) || defined(EL_DISTRIBUTION2D_IMPLEMENTATION)
#ifndef EL_DISTRIBUTION2D_IMPLEMENTATION_DONE
#define EL_DISTRIBUTION2D_IMPLEMENTATION_DONE

/* The constructors' loops in SSE2 where available (x86-64 always has it; EL_NO_SIMD gives the scalar
 * code, which does the same operations in the same order: both give the same bits). */
#if !defined(EL_NO_SIMD) && (defined(__SSE2__) || defined(_M_X64) || (defined(_M_IX86_FP) && _M_IX86_FP >= 2))
#define EL_DISTRIBUTION2D__BUILD_SSE2 1
#include <emmintrin.h>
#else
#define EL_DISTRIBUTION2D__BUILD_SSE2 0
#endif

#include <float.h>
#include <string.h>

#ifdef __cplusplus
extern "C" {
#endif

/* >> private helpers */

/* The float just below / above x (x finite). */
static float el_distribution2d__next_down(float x) {
  uint32_t b;
  if (x == 0.0f) return -1.40129846e-45f;
  memcpy(&b, &x, 4);
  if (x > 0.0f) b -= 1u; else b += 1u;
  memcpy(&x, &b, 4);
  return x;
}
static float el_distribution2d__next_up(float x) {
  uint32_t b;
  if (x == 0.0f) return 1.40129846e-45f;
  memcpy(&b, &x, 4);
  if (x > 0.0f) b += 1u; else b -= 1u;
  memcpy(&x, &b, 4);
  return x;
}

#if defined(__GNUC__) || defined(__clang__)
#define EL_DISTRIBUTION2D__NOINLINE __attribute__((noinline))
#else
#define EL_DISTRIBUTION2D__NOINLINE
#endif

/* General domains: x = x0 + t * width, then nudge x by ulps until it maps back to bin i, below x1. */
static EL_DISTRIBUTION2D__NOINLINE float el_distribution2d__place_general(int i, float t, float x0, float x1, float width, float scale, float last) {
  float x = x0 + t * width;
  int b, guard;
  if (x >= x1) x = el_distribution2d__next_down(x1);
  b = el_distribution2d__bin_last(x, x0, scale, last);
  for (guard = 0; b > i && guard < 64; ++guard) {
    x = el_distribution2d__next_down(x);
    b = el_distribution2d__bin_last(x, x0, scale, last);
  }
  for (guard = 0; b < i && guard < 64; ++guard) {
    x = el_distribution2d__next_up(x);
    b = el_distribution2d__bin_last(x, x0, scale, last);
  }
  return x;
}
static EL_DISTRIBUTION2D__NOINLINE float el_distribution2d__below(int i) { return el_distribution2d__next_down((float)(i + 1)); }
/* The fast paths' placement: x = x0 + t * width, t in [i, i+1). On an exact axis x is in bin i with no
 * rounding; otherwise check it the way pdf() will look it up (and below x1). 0: let the general path
 * place it. */
static inline int el_distribution2d__place_fast(float t, int i, float x0, float x1, float width, float scale, int exact, float *x) {
  float y = x0 + t * width;
  *x = y;
  if (exact) return (int)t == i;
  return (int)t == i && y < x1 && (int)((y - x0) * scale) == i;
}

/* Place a point at fraction frac in [0,1] of bin i so that it maps back to bin i and stays below x1.
 * t = i + frac is kept below i + 1 (rounding could carry it there); on an exact axis (x0 = 0, width a
 * power of two) x = t * width and (int)(x * scale) = (int)t = i with no rounding at all. */
static inline float el_distribution2d__place(int i, float frac, float x0, float x1, float width, float scale, float last, int exact) {
  float t = (float)i + frac;
  if ((int)t > i) t = el_distribution2d__below(i);
  if (exact) return t * width;
  return el_distribution2d__place_general(i, t, x0, x1, width, scale, last);
}


/* NaN and negative -> 0, +Inf -> FLT_MAX; valid values unchanged. */
static inline double el_distribution2d__sanitize(float x) {
  if (x >= 0.0f) return x <= FLT_MAX ? (double)x : (double)FLT_MAX;
  return 0.0;
}

/* Check n values; on the first bad one return its error and index (unless clamping). Also the sum
 * (after clamping) and the number of positive values. Fast path: four independent double sums and one
 * validity flag (no branch per value); the slow path runs only when some value is bad. */
static el_result el_distribution2d__scan(const float *f, size_t n, int clamp, double *sum, size_t *positive, size_t *bad) {
  double s0 = 0.0, s1 = 0.0, s2 = 0.0, s3 = 0.0, s = 0.0;
  size_t i, m = 0, n4 = n & ~(size_t)3;
  uint32_t acc = 0;
  int ok;
  *sum = 0.0;
  *positive = 0;
  /* A float is finite and >= +0 exactly when its bits, as an unsigned integer, are below 0x7f800000,
   * i.e. when neither bits nor bits + 0x00800000 has the top bit set (-0.0 fails too and goes to the
   * careful loop, which accepts it). Nonzero bits then mean a positive value. */
#if EL_DISTRIBUTION2D__BUILD_SSE2
  { /* the same four sums (lanes s0 s1 | s2 s3), the same flag; zeros counted per lane */
    const __m128i h = _mm_set1_epi32(0x00800000), zero = _mm_setzero_si128();
    __m128i a = zero, zeros = zero;
    __m128d s01 = _mm_setzero_pd(), s23 = _mm_setzero_pd();
    uint32_t z[4];
    double t[4];
    for (i = 0; i < n4; i += 4) {
      __m128 x = _mm_loadu_ps(f + i);
      __m128i b = _mm_castps_si128(x);
      a = _mm_or_si128(a, _mm_or_si128(b, _mm_add_epi32(b, h)));
      zeros = _mm_sub_epi32(zeros, _mm_cmpeq_epi32(b, zero));
      s01 = _mm_add_pd(s01, _mm_cvtps_pd(x));
      s23 = _mm_add_pd(s23, _mm_cvtps_pd(_mm_movehl_ps(x, x)));
    }
    _mm_storeu_si128((__m128i *)z, zeros);
    _mm_storeu_pd(t, s01); _mm_storeu_pd(t + 2, s23);
    s0 = t[0]; s1 = t[1]; s2 = t[2]; s3 = t[3];
    m = n4 - ((size_t)z[0] + z[1] + z[2] + z[3]);
    acc = _mm_movemask_ps(_mm_castsi128_ps(a)) ? 0x80000000u : 0u;
  }
#else
  for (i = 0; i < n4; i += 4) {
    uint32_t b[4];
    memcpy(b, f + i, sizeof b);
    acc |= (b[0] | (b[0] + 0x00800000u)) | (b[1] | (b[1] + 0x00800000u)) | (b[2] | (b[2] + 0x00800000u)) | (b[3] | (b[3] + 0x00800000u));
    m += (size_t)((b[0] != 0) + (b[1] != 0) + (b[2] != 0) + (b[3] != 0));
    s0 += (double)f[i]; s1 += (double)f[i + 1]; s2 += (double)f[i + 2]; s3 += (double)f[i + 3];
  }
#endif
  for (i = n4; i < n; ++i) {
    uint32_t b0;
    memcpy(&b0, f + i, sizeof b0);
    acc |= b0 | (b0 + 0x00800000u);
    m += (size_t)(b0 != 0);
    s0 += (double)f[i];
  }
  ok = !(acc & 0x80000000u);
  if (ok) {
    *sum = (s0 + s1) + (s2 + s3);
    *positive = m;
    return EL_SUCCESS;
  }
  m = 0;
  for (i = 0; i < n; ++i) {
    float x = f[i];
    if (!(x >= 0.0f && x <= FLT_MAX)) {
      if (!clamp) {
        *bad = i;
        if (x != x) return EL_ERROR_NAN;
        if (x > FLT_MAX || x < -FLT_MAX) return EL_ERROR_INFINITE;
        return EL_ERROR_NEGATIVE;
      }
    }
    {
      double v = el_distribution2d__sanitize(x);
      s += v;
      m += (v > 0.0);
    }
  }
  *sum = s;
  *positive = m;
  return EL_SUCCESS;
}

/* The integer CDF of n weights: positive bins get one unit each, the remaining R = 2^24 - m units are
 * shared in proportion to the prefix sums: c[i] = (positive bins before i) + round(R * S_i / sum).
 * The prefix sums are kept in 64-bit fixed point (2^-24 of a unit): each weight's share is truncated
 * once, independently (no long floating-point dependency chain; all n truncations together lose less
 * than n * 2^-24 <= 1/4 unit, so the last positive bin still ends exactly at 2^24). Monotone by
 * construction; a positive bin is at least one unit wide, a zero bin exactly zero. sum == 0: uniform. */
static void el_distribution2d__cdf_uniform(uint32_t *c, int n) {
  int i;
  for (i = 0; i <= n; ++i) c[i] = (uint32_t)(((uint64_t)i * EL_DISTRIBUTION_UNITS) / (uint64_t)n);
}
static void el_distribution2d__cdf_float(uint32_t *c, const float *f, int n, double sum, uint32_t m, int clamp) {
  double q;
  int64_t p = 0;
  uint32_t pos = 0;
  int i;
  if (!(sum > 0.0)) { el_distribution2d__cdf_uniform(c, n); return; }
  q = (double)(EL_DISTRIBUTION_UNITS - m) / sum * 16777216.0;
  c[0] = 0;
  if (!clamp) {
    i = 0;
#if EL_DISTRIBUTION2D__BUILD_SSE2
    { /* four bins at a time, the same integers: (int64_t)y for 0 <= y = x q < 2^49 is floor(y) = r - (r > y)
         with r = (y + 2^52) - 2^52 (y rounded to an integer, exactly), whose bits are those of y + 2^52
         minus those of 2^52; then prefix sums within the vector plus the running total */
      const __m128d big = _mm_set1_pd(4503599627370496.0), qq = _mm_set1_pd(q);
      const __m128i bigi = _mm_castpd_si128(big), half = _mm_set_epi32(0, 8388608, 0, 8388608);
      const __m128 fzero = _mm_setzero_ps();
      __m128i run = _mm_setzero_si128(), runpos = _mm_setzero_si128();
      int64_t pp[2];
      for (; i + 4 <= n; i += 4) {
        __m128 x = _mm_loadu_ps(f + i);
        __m128d y0 = _mm_mul_pd(_mm_cvtps_pd(x), qq), y1 = _mm_mul_pd(_mm_cvtps_pd(_mm_movehl_ps(x, x)), qq);
        __m128d t0 = _mm_add_pd(y0, big), t1 = _mm_add_pd(y1, big);
        __m128i k0 = _mm_add_epi64(_mm_sub_epi64(_mm_castpd_si128(t0), bigi), _mm_castpd_si128(_mm_cmpgt_pd(_mm_sub_pd(t0, big), y0)));
        __m128i k1 = _mm_add_epi64(_mm_sub_epi64(_mm_castpd_si128(t1), bigi), _mm_castpd_si128(_mm_cmpgt_pd(_mm_sub_pd(t1, big), y1)));
        __m128i pm = _mm_castps_si128(_mm_cmpgt_ps(x, fzero)), u;
        k0 = _mm_add_epi64(k0, _mm_slli_si128(k0, 8));
        k1 = _mm_add_epi64(k1, _mm_slli_si128(k1, 8));
        k0 = _mm_add_epi64(k0, run);
        run = _mm_shuffle_epi32(k0, _MM_SHUFFLE(3, 2, 3, 2));
        k1 = _mm_add_epi64(k1, run);
        run = _mm_shuffle_epi32(k1, _MM_SHUFFLE(3, 2, 3, 2));
        k0 = _mm_srli_epi64(_mm_add_epi64(k0, half), 24);
        k1 = _mm_srli_epi64(_mm_add_epi64(k1, half), 24);
        u = _mm_castps_si128(_mm_shuffle_ps(_mm_castsi128_ps(k0), _mm_castsi128_ps(k1), _MM_SHUFFLE(2, 0, 2, 0)));
        pm = _mm_add_epi32(pm, _mm_slli_si128(pm, 4)); /* -(positive bins up to each lane) */
        pm = _mm_add_epi32(pm, _mm_slli_si128(pm, 8));
        pm = _mm_sub_epi32(runpos, pm);
        runpos = _mm_shuffle_epi32(pm, _MM_SHUFFLE(3, 3, 3, 3));
        _mm_storeu_si128((__m128i *)(c + i + 1), _mm_add_epi32(u, pm));
      }
      _mm_storeu_si128((__m128i *)pp, run);
      p = pp[0];
      pos = (uint32_t)_mm_cvtsi128_si32(runpos);
    }
#endif
    for (; i < n; ++i) { /* values already validated */
      float x = f[i];
      p += (int64_t)((double)x * q);
      pos += (uint32_t)(x > 0.0f);
      c[i + 1] = pos + (uint32_t)((p + 8388608) >> 24);
    }
  } else {
    for (i = 0; i < n; ++i) {
      double v = el_distribution2d__sanitize(f[i]);
      p += (int64_t)(v * q);
      pos += (uint32_t)(v > 0.0);
      c[i + 1] = pos + (uint32_t)((p + 8388608) >> 24);
    }
  }
  /* trailing zero bins end exactly at 2^24 (a safety net; the bound above already gives it) */
  c[n] = EL_DISTRIBUTION_UNITS;
  for (i = n - 1; i > 0 && !(el_distribution2d__sanitize(f[i]) > 0.0); --i) c[i] = EL_DISTRIBUTION_UNITS;
}
static void el_distribution2d__cdf_double(uint32_t *c, const double *f, int n, double sum, uint32_t m) {
  double q;
  int64_t p = 0;
  uint32_t pos = 0;
  int i;
  if (!(sum > 0.0)) { el_distribution2d__cdf_uniform(c, n); return; }
  q = (double)(EL_DISTRIBUTION_UNITS - m) / sum * 16777216.0;
  c[0] = 0;
  for (i = 0; i < n; ++i) {
    double v = f[i];
    p += (int64_t)(v * q);
    pos += (uint32_t)(v > 0.0);
    c[i + 1] = pos + (uint32_t)((p + 8388608) >> 24);
  }
  c[n] = EL_DISTRIBUTION_UNITS;
  for (i = n - 1; i > 0 && !(f[i] > 0.0); --i) c[i] = EL_DISTRIBUTION_UNITS;
}

/* Validate a domain [a, b] with n bins; compute scale, width and the unit pdf scale. */
static el_result el_distribution2d__domain(float a, float b, int n, float *scale, float *width, float *pdf_scale) {
  float w, ulp, m;
  if (!(a > -FLT_MAX && a < FLT_MAX && b > -FLT_MAX && b < FLT_MAX) || !(b > a)) return EL_ERROR_INVALID_ARGUMENT;
  w = b - a;
  if (!(w <= FLT_MAX)) return EL_ERROR_INVALID_ARGUMENT;
  m = (a < 0 ? -a : a) > (b < 0 ? -b : b) ? (a < 0 ? -a : a) : (b < 0 ? -b : b);
  /* the float step just inside the domain's end of larger magnitude (below 1 it is 2^-24, not the
   * 2^-23 above 1): every bin must hold at least 4 floats, so [0,1] resolves 2^22 bins */
  ulp = m - el_distribution2d__next_down(m);
  if (!(w / (float)n >= 4.0f * ulp)) return EL_ERROR_INVALID_ARGUMENT;
  *scale = (float)n / w;
  *width = w / (float)n;
  *pdf_scale = (float)((double)n / (double)w / (double)EL_DISTRIBUTION_UNITS);
  if (!(*scale <= FLT_MAX) || !(*width > 0.0f) || !(*pdf_scale > 0.0f) || !((double)*pdf_scale * EL_DISTRIBUTION_UNITS <= FLT_MAX))
    return EL_ERROR_INVALID_ARGUMENT;
  return EL_SUCCESS;
}

/* 1 when x0 = 0, width = (x1-x0)/n is a power of two (not tiny) and n * width == x1 exactly */
static int el_distribution2d__exact(float x0, float x1, float width, float scale, int n) {
  uint32_t bits;
  if (x0 != 0.0f || !(width >= 1e-30f) || !(width <= 1e30f)) return 0;
  memcpy(&bits, &width, 4);
  return (bits & 0x7fffffu) == 0 && (double)width * (double)n == (double)x1 && (double)scale * (double)width == 1.0;
}

static float el_distribution2d__clamp_float(double x) { return x <= (double)FLT_MAX ? (float)x : FLT_MAX; }

/* << private helpers */

/* >> 1D */

/* A failed init: *d zeroed but for bad_index. */
static el_result el_distribution2d__fail1(el_distribution1d *d, el_result r, int bad_index) {
  el_distribution1d_free(d);
  d->bad_index = bad_index;
  return r;
}

EL_DEF el_result el_distribution1d_init(el_distribution1d *d, const float *f, int n, const el_distribution_options *opt) {
  el_distribution_options zero;
  el_result r;
  double sum;
  size_t m, bad = 0;
  float a = 0.0f, b = 1.0f;
  if (!opt) { memset(&zero, 0, sizeof zero); opt = &zero; }
  if (!d) return EL_ERROR_INVALID_ARGUMENT;
  memset(d, 0, sizeof *d);
  d->bad_index = -1;
  if (n <= 0) return n == 0 ? EL_ERROR_EMPTY : EL_ERROR_INVALID_ARGUMENT;
  if (!f) return EL_ERROR_INVALID_ARGUMENT;
  if (n > EL_DISTRIBUTION_MAX_BINS) return EL_ERROR_SIZE_OVERFLOW;
  if (opt->domain[0] != 0.0f || opt->domain[1] != 0.0f || opt->domain[2] != 0.0f || opt->domain[3] != 0.0f) {
    a = opt->domain[0];
    b = opt->domain[2];
  }
  d->n = n;
  d->x0 = a;
  d->x1 = b;
  r = el_distribution2d__domain(a, b, n, &d->bin_scale, &d->bin_width, &d->pdf_scale);
  if (r != EL_SUCCESS) return el_distribution2d__fail1(d, r, -1);
  d->last = (float)(n - 1);
  d->exact = el_distribution2d__exact(a, b, d->bin_width, d->bin_scale, n);
  r = el_distribution2d__scan(f, (size_t)n, opt->clamp_bad_values, &sum, &m, &bad);
  if (r != EL_SUCCESS) return el_distribution2d__fail1(d, r, (int)bad);
  d->cdf = (uint32_t *)EL_MALLOC(((size_t)n + 1) * sizeof(uint32_t));
  if (!d->cdf) return el_distribution2d__fail1(d, EL_ERROR_OUT_OF_MEMORY, -1);
  el_distribution2d__cdf_float(d->cdf, f, n, sum, (uint32_t)m, opt->clamp_bad_values);
  d->all_zero = !(sum > 0.0);
  if (d->all_zero) d->pdf_scale = 0.0f;
  d->integral = el_distribution2d__clamp_float(sum * ((double)b - (double)a) / (double)n);
  return EL_SUCCESS;
}

EL_DEF void el_distribution1d_free(el_distribution1d *d) {
  if (!d) return;
  EL_FREE(d->cdf);
  memset(d, 0, sizeof *d);
}

EL_DEF float el_distribution1d_sample_continuous(const el_distribution1d *d, float u, float *pdf, int *offset) {
  float x = el_distribution2d__units(u), frac, w;
  uint32_t k = (uint32_t)x;
  int i = el_distribution2d__search(d->cdf, 0, d->n, k);
  w = (float)(d->cdf[i + 1] - d->cdf[i]);
  frac = (x - (float)d->cdf[i]) / w;
  if (pdf) *pdf = w * d->pdf_scale;
  if (offset) *offset = i;
  return el_distribution2d__place(i, frac, d->x0, d->x1, d->bin_width, d->bin_scale, d->last, d->exact);
}

EL_DEF int el_distribution1d_sample_discrete(const el_distribution1d *d, float u, float *pmf, float *u_remapped) {
  float x = el_distribution2d__units(u), frac, w;
  uint32_t k = (uint32_t)x;
  int i = el_distribution2d__search(d->cdf, 0, d->n, k);
  w = (float)(d->cdf[i + 1] - d->cdf[i]);
  frac = (x - (float)d->cdf[i]) / w;
  if (frac > 0.99999994f) frac = 0.99999994f;
  if (pmf) *pmf = d->all_zero ? 0.0f : w * (1.0f / 16777216.0f);
  if (u_remapped) *u_remapped = frac;
  return i;
}

EL_DEF float el_distribution1d_pdf(const el_distribution1d *d, float x) {
  int i = el_distribution2d__bin_last(x, d->x0, d->bin_scale, d->last);
  return (float)(d->cdf[i + 1] - d->cdf[i]) * d->pdf_scale;
}

EL_DEF float el_distribution1d_invert(const el_distribution1d *d, float x) {
  int i = el_distribution2d__bin_last(x, d->x0, d->bin_scale, d->last);
  float t = (x - d->x0) * d->bin_scale - (float)i, r;
  if (!(t > 0.0f)) t = 0.0f;
  if (t > 0.99999994f) t = 0.99999994f;
  r = ((float)d->cdf[i] + t * (float)(d->cdf[i + 1] - d->cdf[i])) * (1.0f / 16777216.0f);
  return r > 1.0f ? 1.0f : r;
}

EL_DEF float el_distribution1d_integral(const el_distribution1d *d) { return d->integral; }

EL_DEF size_t el_distribution1d_bytes(const el_distribution1d *d) {
  return sizeof *d + (d->cdf ? ((size_t)d->n + 1) * sizeof(uint32_t) : 0);
}

/* << 1D */

/* >> 2D */

/* A failed init: *d zeroed but for bad_index. */
static el_result el_distribution2d__fail2(el_distribution2d *d, el_result r, int bad_index) {
  el_distribution2d_free(d);
  d->bad_index = bad_index;
  return r;
}

EL_DEF el_result el_distribution2d_init(el_distribution2d *d, const float *f, int nu, int nv, const el_distribution_options *opt) {
  el_distribution_options zero;
  el_result r;
  double total = 0.0, *rowsum = NULL;
  size_t rows_positive = 0, row_entries, bytes;
  float u0 = 0.0f, v0 = 0.0f, u1 = 1.0f, v1 = 1.0f;
  int v;
  if (!opt) { memset(&zero, 0, sizeof zero); opt = &zero; }
  if (!d) return EL_ERROR_INVALID_ARGUMENT;
  memset(d, 0, sizeof *d);
  d->bad_index = -1;
  if (nu < 0 || nv < 0) return EL_ERROR_INVALID_ARGUMENT;
  if (nu == 0 || nv == 0) return EL_ERROR_EMPTY;
  if (!f) return EL_ERROR_INVALID_ARGUMENT;
  if (nu > EL_DISTRIBUTION_MAX_BINS || nv > EL_DISTRIBUTION_MAX_BINS) return EL_ERROR_SIZE_OVERFLOW;
  /* <<Check sizes>>: nv*(nu+1) entries, and nu*nv values addressable */
  row_entries = (size_t)nu + 1;
  if ((size_t)nv > ((size_t)-1) / sizeof(uint32_t) / row_entries) return EL_ERROR_SIZE_OVERFLOW;
  if ((size_t)nv > ((size_t)-1) / sizeof(double)) return EL_ERROR_SIZE_OVERFLOW;
  if ((size_t)nv > ((size_t)-1) / (size_t)nu) return EL_ERROR_SIZE_OVERFLOW;
  bytes = (size_t)nv * row_entries * sizeof(uint32_t);
  if (opt->domain[0] != 0.0f || opt->domain[1] != 0.0f || opt->domain[2] != 0.0f || opt->domain[3] != 0.0f) {
    u0 = opt->domain[0]; v0 = opt->domain[1]; u1 = opt->domain[2]; v1 = opt->domain[3];
  }
  d->domain[0] = u0; d->domain[1] = v0; d->domain[2] = u1; d->domain[3] = v1;
  d->nu = nu;
  d->nv = nv;
  r = el_distribution2d__domain(u0, u1, nu, &d->u_scale, &d->u_width, &d->u_pdf_scale);
  if (r == EL_SUCCESS) r = el_distribution2d__domain(v0, v1, nv, &d->v_scale, &d->v_width, &d->v_pdf_scale);
  if (r == EL_SUCCESS && !((double)d->u_pdf_scale * (double)d->v_pdf_scale * 281474976710656.0 <= FLT_MAX)) r = EL_ERROR_INVALID_ARGUMENT;
  if (r != EL_SUCCESS) return el_distribution2d__fail2(d, r, -1);
  d->u_last = (float)(nu - 1);
  d->v_last = (float)(nv - 1);
  d->u_exact = el_distribution2d__exact(u0, u1, d->u_width, d->u_scale, nu);
  d->v_exact = el_distribution2d__exact(v0, v1, d->v_width, d->v_scale, nv);
  d->cdf = (uint32_t *)EL_MALLOC(bytes);
  d->marginal = (uint32_t *)EL_MALLOC(((size_t)nv + 1) * sizeof(uint32_t));
  rowsum = (double *)EL_MALLOC((size_t)nv * sizeof(double));
  if (!d->cdf || !d->marginal || !rowsum) {
    EL_FREE(rowsum);
    return el_distribution2d__fail2(d, EL_ERROR_OUT_OF_MEMORY, -1);
  }
  /* <<Compute conditional sampling distribution for each row>>, validating as we go */
  for (v = 0; v < nv; ++v) {
    const float *row = f + (size_t)v * (size_t)nu;
    size_t m = 0, bad = 0;
    r = el_distribution2d__scan(row, (size_t)nu, opt->clamp_bad_values, &rowsum[v], &m, &bad);
    if (r != EL_SUCCESS) {
      size_t flat = (size_t)v * (size_t)nu + bad;
      EL_FREE(rowsum);
      return el_distribution2d__fail2(d, r, flat <= 2147483647u ? (int)flat : 2147483647);
    }
    el_distribution2d__cdf_float(d->cdf + (size_t)v * row_entries, row, nu, rowsum[v], (uint32_t)m, opt->clamp_bad_values);
    total += rowsum[v];
    rows_positive += (rowsum[v] > 0.0);
  }
  /* <<Compute marginal sampling distribution>>: the weights are the row sums */
  {
    double s = 0.0;
    for (v = 0; v < nv; ++v) s += rowsum[v];
    el_distribution2d__cdf_double(d->marginal, rowsum, nv, s, (uint32_t)rows_positive);
    total = s;
  }
  EL_FREE(rowsum);
  d->all_zero = !(total > 0.0);
  if (d->all_zero) { d->u_pdf_scale = 0.0f; d->v_pdf_scale = 0.0f; }
  d->integral = el_distribution2d__clamp_float(total * ((double)u1 - (double)u0) * ((double)v1 - (double)v0) / ((double)nu * (double)nv));
  return EL_SUCCESS;
}

EL_DEF void el_distribution2d_free(el_distribution2d *d) {
  if (!d) return;
  EL_FREE(d->cdf);
  EL_FREE(d->marginal);
  memset(d, 0, sizeof *d);
}

/* Any u, any domain. */
static EL_DISTRIBUTION2D__NOINLINE void el_distribution2d__sample_general(const el_distribution2d *d, float u0, float u1, float *out_u, float *out_v, float *pdf) {
  /* <<Sample the marginal distribution (u1 -> row)>> */
  float xv = el_distribution2d__units(u1), xu = el_distribution2d__units(u0), wv, wu, fv, fu;
  int iv = el_distribution2d__search(d->marginal, 0, d->nv, (uint32_t)xv), iu;
  const uint32_t *row = d->cdf + (size_t)iv * ((size_t)d->nu + 1);
  /* <<Sample the conditional distribution of that row (u0 -> column)>> */
  iu = el_distribution2d__search(row, 0, d->nu, (uint32_t)xu);
  wv = (float)(d->marginal[iv + 1] - d->marginal[iv]);
  wu = (float)(row[iu + 1] - row[iu]);
  fv = (xv - (float)d->marginal[iv]) / wv;
  fu = (xu - (float)row[iu]) / wu;
  *out_u = el_distribution2d__place(iu, fu, d->domain[0], d->domain[2], d->u_width, d->u_scale, d->u_last, d->u_exact);
  *out_v = el_distribution2d__place(iv, fv, d->domain[1], d->domain[3], d->v_width, d->v_scale, d->v_last, d->v_exact);
  *pdf = (wv * d->v_pdf_scale) * (wu * d->u_pdf_scale);
}

/* The common case as a leaf function (no calls, so no saved registers): u in [0,1) and a point that
 * lands in its bin at the first try; anything else goes to the general path, which gives the same
 * result wherever both apply. */
EL_DEF void el_distribution2d_sample(const el_distribution2d *d, float u0, float u1, float *out_u, float *out_v, float *pdf) {
  float xv = u1 * 16777216.0f, xu = u0 * 16777216.0f;
  uint32_t b0, b1;
  memcpy(&b0, &u0, 4);
  memcpy(&b1, &u1, 4);
  if ((b0 > b1 ? b0 : b1) < 0x3f800000u) { /* both in [+0, 1): the bits of 1.0f bound them as integers */
    uint32_t kv = (uint32_t)(int32_t)xv, ku = (uint32_t)(int32_t)xu;
    int iv = el_distribution2d__search(d->marginal, 0, d->nv, kv), iu;
    const uint32_t *row = d->cdf + (size_t)iv * ((size_t)d->nu + 1);
    int32_t cv, cu;
    float wv, wu, tv, tu;
    iu = el_distribution2d__search(row, 0, d->nu, ku);
    cv = (int32_t)d->marginal[iv];
    cu = (int32_t)row[iu];
    wv = (float)((int32_t)d->marginal[iv + 1] - cv);
    wu = (float)((int32_t)row[iu + 1] - cu);
    tv = (float)iv + (xv - (float)cv) / wv;
    tu = (float)iu + (xu - (float)cu) / wu;
    if (d->u_exact & d->v_exact) { /* no rounding anywhere: only a carry into the next bin can happen */
      if ((int)tv == iv && (int)tu == iu) {
        *out_u = tu * d->u_width;
        *out_v = tv * d->v_width;
        *pdf = (wv * d->v_pdf_scale) * (wu * d->u_pdf_scale);
        return;
      }
    } else if (el_distribution2d__place_fast(tu, iu, d->domain[0], d->domain[2], d->u_width, d->u_scale, 0, out_u) &&
               el_distribution2d__place_fast(tv, iv, d->domain[1], d->domain[3], d->v_width, d->v_scale, 0, out_v)) {
      *pdf = (wv * d->v_pdf_scale) * (wu * d->u_pdf_scale);
      return;
    }
  }
  el_distribution2d__sample_general(d, u0, u1, out_u, out_v, pdf);
}

EL_DEF void el_distribution2d_sample_bins(const el_distribution2d *d, float u0, float u1, int *iu, int *iv, float *fu, float *fv, float *pdf) {
  float xv = el_distribution2d__units(u1), xu = el_distribution2d__units(u0);
  int v = el_distribution2d__search(d->marginal, 0, d->nv, (uint32_t)xv), u;
  const uint32_t *row = d->cdf + (size_t)v * ((size_t)d->nu + 1);
  u = el_distribution2d__search(row, 0, d->nu, (uint32_t)xu);
  *iv = v;
  *iu = u;
  {
    float wv = (float)((int32_t)d->marginal[v + 1] - (int32_t)d->marginal[v]), wu = (float)((int32_t)row[u + 1] - (int32_t)row[u]);
    *fv = (xv - (float)(int32_t)d->marginal[v]) / wv;
    *fu = (xu - (float)(int32_t)row[u]) / wu;
    *pdf = (wv * d->v_pdf_scale) * (wu * d->u_pdf_scale);
  }
}

EL_DEF float el_distribution2d_pdf(const el_distribution2d *d, float u, float v) {
  int iu = el_distribution2d__bin_last(u, d->domain[0], d->u_scale, d->u_last);
  int iv = el_distribution2d__bin_last(v, d->domain[1], d->v_scale, d->v_last);
  const uint32_t *row = d->cdf + (size_t)iv * ((size_t)d->nu + 1);
  float wv = (float)(d->marginal[iv + 1] - d->marginal[iv]);
  float wu = (float)(row[iu + 1] - row[iu]);
  return (wv * d->v_pdf_scale) * (wu * d->u_pdf_scale);
}

static float el_distribution2d__invert1(const uint32_t *c, float last, float x, float x0, float scale) {
  int i = el_distribution2d__bin_last(x, x0, scale, last);
  float t = (x - x0) * scale - (float)i, r;
  if (!(t > 0.0f)) t = 0.0f;
  if (t > 0.99999994f) t = 0.99999994f;
  r = ((float)c[i] + t * (float)(c[i + 1] - c[i])) * (1.0f / 16777216.0f);
  return r > 1.0f ? 1.0f : r;
}

EL_DEF void el_distribution2d_invert(const el_distribution2d *d, float u, float v, float *out_u0, float *out_u1) {
  int iv = el_distribution2d__bin_last(v, d->domain[1], d->v_scale, d->v_last);
  *out_u1 = el_distribution2d__invert1(d->marginal, d->v_last, v, d->domain[1], d->v_scale);
  *out_u0 = el_distribution2d__invert1(d->cdf + (size_t)iv * ((size_t)d->nu + 1), d->u_last, u, d->domain[0], d->u_scale);
}

EL_DEF float el_distribution2d_integral(const el_distribution2d *d) { return d->integral; }

EL_DEF size_t el_distribution2d_bytes(const el_distribution2d *d) {
  size_t b = sizeof *d;
  if (d->cdf) b += (size_t)d->nv * ((size_t)d->nu + 1) * sizeof(uint32_t);
  if (d->marginal) b += ((size_t)d->nv + 1) * sizeof(uint32_t);
  return b;
}

/* << 2D */

/* >> fast samplers */

static void el_distribution2d__guide_build(uint32_t *g, int cells, int shift, const uint32_t *c, int n) {
  /* g[cell] = the last bin i starting at or below the cell's first unit cell << shift, i.e. the number
   * of i in [1, n-1] with c[i] <= cell << shift, i.e. with k_i = ceil(c[i] / 2^shift) <= cell. k_i is
   * monotone in i (0 <= k_i <= cells), so storing i at g[k_i] leaves there the largest i of that k, and a
   * running maximum over the cells gives the count. No data-dependent branch (the scan that walked c per
   * cell mispredicted at every cell boundary). */
  int cell, i;
  uint32_t m = 0, add = ((uint32_t)1 << shift) - 1u;
  for (cell = 0; cell <= cells; ++cell) g[cell] = 0;
  for (i = 1; i + 3 < n; i += 4) { /* unrolled: the stores stay in order of i */
    g[(c[i] + add) >> shift] = (uint32_t)i;
    g[(c[i + 1] + add) >> shift] = (uint32_t)i + 1u;
    g[(c[i + 2] + add) >> shift] = (uint32_t)i + 2u;
    g[(c[i + 3] + add) >> shift] = (uint32_t)i + 3u;
  }
  for (; i < n; ++i) g[(c[i] + add) >> shift] = (uint32_t)i;
  /* the running maximum, and in the same pass the flag of a crowded cell (more than 64 bins start in
   * it) in bit 31: the inline fast path then leaves it to the binary search, with one test instead of
   * reading the next entry. g[cells] = n - 1. */
  m = g[0];
  for (cell = 0; cell + 1 < cells; ++cell) {
    uint32_t next = g[cell + 1] > m ? g[cell + 1] : m;
    g[cell] = m | ((uint32_t)(next - m > 64u) << 31);
    m = next;
  }
  g[cells - 1] = m | ((uint32_t)((uint32_t)(n - 1) - m > 64u) << 31);
  g[cells] = (uint32_t)(n - 1);
}

static int el_distribution2d__guide_cells(int n, int shrink, int *shift) {
  int lg = 0;
  while ((1 << lg) < n) ++lg;
  lg -= shrink;
  if (lg < 0) lg = 0;
  if (lg > 24) lg = 24;
  *shift = 24 - lg;
  return 1 << lg;
}

/* Cell j of n alias cells covers units [start[j], start[j+1]) = {k : floor(k*n / 2^24) = j}. */
static void el_distribution2d__alias_starts(uint32_t *s, int n) {
  int j;
  for (j = 0; j <= n; ++j) s[j] = (uint32_t)((((uint64_t)j << 24) + (uint64_t)n - 1) / (uint64_t)n);
}

/* Vose's alias method with exact integers: bin i weighs c[i+1]-c[i] units, cell j holds start[j+1]-start[j]
 * units; since both total 2^24, every cell ends exactly full. work: 2n ints of scratch. */
static void el_distribution2d__alias_build(uint32_t *cells, const uint32_t *c, const uint32_t *start, int n, int64_t *w, int *small, int *large) {
  int ns = 0, nl = 0, j;
  for (j = 0; j < n; ++j) {
    int64_t cap = (int64_t)(start[j + 1] - start[j]);
    w[j] = (int64_t)(c[j + 1] - c[j]);
    cells[2 * j] = start[j + 1]; /* full by default */
    cells[2 * j + 1] = (uint32_t)j;
    if (w[j] < cap) small[ns++] = j;
    else if (w[j] > cap) large[nl++] = j;
  }
  while (ns > 0 && nl > 0) {
    int s = small[--ns], l = large[nl - 1];
    int64_t caps = (int64_t)(start[s + 1] - start[s]), capl;
    cells[2 * s] = start[s] + (uint32_t)w[s];
    cells[2 * s + 1] = (uint32_t)l;
    w[l] -= caps - w[s];
    capl = (int64_t)(start[l + 1] - start[l]);
    if (w[l] <= capl) {
      --nl;
      if (w[l] < capl) small[ns++] = l;
    }
  }
  /* exact arithmetic leaves both lists empty; anything left is full by default */
}

EL_DEF el_result el_distribution2d_fast_init(el_distribution2d_fast *f, const el_distribution2d *d) {
  return el_distribution2d_fast_init_ex(f, d, NULL);
}

EL_DEF el_result el_distribution2d_fast_init_ex(el_distribution2d_fast *f, const el_distribution2d *d, const el_distribution_fast_options *opt) {
  int method = opt ? opt->method : EL_DISTRIBUTION_FAST_GUIDE;
  int shrink = !opt || opt->guide_shrink_log2 == 0 ? 2 : opt->guide_shrink_log2 < 0 ? 0 : opt->guide_shrink_log2;
  int v;
  size_t row_entries;
  if (!f) return EL_ERROR_INVALID_ARGUMENT;
  memset(f, 0, sizeof *f);
  if (!d || !d->cdf || !d->marginal || d->nu <= 0 || d->nv <= 0) return EL_ERROR_INVALID_ARGUMENT;
  if (method != EL_DISTRIBUTION_FAST_GUIDE && method != EL_DISTRIBUTION_FAST_ALIAS) return EL_ERROR_INVALID_ARGUMENT;
  f->method = method;
  f->nu = d->nu; f->nv = d->nv;
  f->cdf = d->cdf; f->marginal = d->marginal;
  memcpy(f->domain, d->domain, sizeof f->domain);
  f->u_scale = d->u_scale; f->v_scale = d->v_scale;
  f->u_width = d->u_width; f->v_width = d->v_width;
  f->u_pdf_scale = d->u_pdf_scale; f->v_pdf_scale = d->v_pdf_scale;
  f->u_last = d->u_last; f->v_last = d->v_last;
  f->u_exact = d->u_exact; f->v_exact = d->v_exact;
  f->row_stride = (size_t)d->nu + 1;
  row_entries = (size_t)d->nu + 1;
  if (method == EL_DISTRIBUTION_FAST_GUIDE) {
    size_t gu1;
    f->gu = el_distribution2d__guide_cells(d->nu, shrink, &f->shift_u);
    f->gv = el_distribution2d__guide_cells(d->nv, -2, &f->shift_v); /* 4 cells per row: the marginal is
                                                                        small and often crowded (a sun) */
    gu1 = (size_t)f->gu + 1;
    f->guide_stride = gu1;
    f->gu_scale = (float)f->gu;
    f->gv_scale = (float)f->gv;
    if ((size_t)d->nv > ((size_t)-1) / sizeof(uint32_t) / gu1) { memset(f, 0, sizeof *f); return EL_ERROR_SIZE_OVERFLOW; }
    f->guide_u = (uint32_t *)EL_MALLOC((size_t)d->nv * gu1 * sizeof(uint32_t));
    f->guide_v = (uint32_t *)EL_MALLOC(((size_t)f->gv + 1) * sizeof(uint32_t));
    if (!f->guide_u || !f->guide_v) { el_distribution2d_fast_free(f); return EL_ERROR_OUT_OF_MEMORY; }
    for (v = 0; v < d->nv; ++v)
      el_distribution2d__guide_build(f->guide_u + (size_t)v * gu1, f->gu, f->shift_u, d->cdf + (size_t)v * row_entries, d->nu);
    el_distribution2d__guide_build(f->guide_v, f->gv, f->shift_v, d->marginal, d->nv);
  } else {
    int nmax = d->nu > d->nv ? d->nu : d->nv;
    int64_t *w;
    int *small, *large;
    if ((size_t)d->nv > ((size_t)-1) / (2 * sizeof(uint32_t)) / (size_t)d->nu) { memset(f, 0, sizeof *f); return EL_ERROR_SIZE_OVERFLOW; }
    f->alias_u = (uint32_t *)EL_MALLOC((size_t)d->nv * (size_t)d->nu * 2 * sizeof(uint32_t));
    f->alias_v = (uint32_t *)EL_MALLOC((size_t)d->nv * 2 * sizeof(uint32_t));
    f->start_u = (uint32_t *)EL_MALLOC(row_entries * sizeof(uint32_t));
    f->start_v = (uint32_t *)EL_MALLOC(((size_t)d->nv + 1) * sizeof(uint32_t));
    w = (int64_t *)EL_MALLOC((size_t)nmax * sizeof(int64_t));
    small = (int *)EL_MALLOC((size_t)nmax * sizeof(int));
    large = (int *)EL_MALLOC((size_t)nmax * sizeof(int));
    if (!f->alias_u || !f->alias_v || !f->start_u || !f->start_v || !w || !small || !large) {
      EL_FREE(w); EL_FREE(small); EL_FREE(large);
      el_distribution2d_fast_free(f);
      return EL_ERROR_OUT_OF_MEMORY;
    }
    el_distribution2d__alias_starts(f->start_u, d->nu);
    el_distribution2d__alias_starts(f->start_v, d->nv);
    for (v = 0; v < d->nv; ++v)
      el_distribution2d__alias_build(f->alias_u + (size_t)v * (size_t)d->nu * 2, d->cdf + (size_t)v * row_entries, f->start_u, d->nu, w, small, large);
    el_distribution2d__alias_build(f->alias_v, d->marginal, f->start_v, d->nv, w, small, large);
    EL_FREE(w); EL_FREE(small); EL_FREE(large);
  }
  return EL_SUCCESS;
}

EL_DEF void el_distribution2d_fast_free(el_distribution2d_fast *f) {
  if (!f) return;
  EL_FREE(f->guide_u); EL_FREE(f->guide_v);
  EL_FREE(f->alias_u); EL_FREE(f->alias_v);
  EL_FREE(f->start_u); EL_FREE(f->start_v);
  memset(f, 0, sizeof *f);
}

/* One dimension of the guide-table search: the bin of unit k, exactly as the binary search finds it. */
static inline int el_distribution2d__guide_find(const uint32_t *c, const uint32_t *g, int shift, uint32_t k) {
  uint32_t cell = k >> shift;
  int lo = (int)(g[cell] & ~EL_DISTRIBUTION__GUIDE_CROWDED), hi = (int)(g[cell + 1] & ~EL_DISTRIBUTION__GUIDE_CROWDED);
  if (hi - lo > 8) return el_distribution2d__search(c, lo, hi - lo + 1, k); /* many tiny bins: O(log) */
  while (c[lo + 1] <= k) ++lo; /* stops by hi: c[hi + 1] > (cell+1) << shift > k, and c[n] = 2^24 */
  return lo;
}

/* One dimension of the alias table: bin and the position of x within the bin's piece, in [0,1). */
static inline int el_distribution2d__alias_find(const uint32_t *cells, const uint32_t *start, int n, float x, float *frac) {
  uint32_t k = (uint32_t)x;
  uint32_t j = (uint32_t)(((uint64_t)k * (uint64_t)n) >> 24);
  uint32_t split = cells[2 * j], lo, hi;
  int i;
  if (k < split) { i = (int)j; lo = start[j]; hi = split; }
  else { i = (int)cells[2 * j + 1]; lo = split; hi = start[j + 1]; }
  *frac = (x - (float)lo) / (float)(hi - lo);
  if (*frac > 0.99999994f) *frac = 0.99999994f;
  return i;
}

/* Any u, any domain. */
static EL_DISTRIBUTION2D__NOINLINE void el_distribution2d__fast_sample_general(const el_distribution2d_fast *f, float u0, float u1, float *out_u, float *out_v, float *pdf) {
  float xv = u1 * 16777216.0f, xu = u0 * 16777216.0f, wv, wu, fv, fu;
  int iv, iu;
  const uint32_t *row;
  if (!(xv >= 0.0f && xv < 16777216.0f)) xv = el_distribution2d__units(u1); /* NaN, < 0, >= 1 */
  if (!(xu >= 0.0f && xu < 16777216.0f)) xu = el_distribution2d__units(u0);
  if (f->method == EL_DISTRIBUTION_FAST_GUIDE) {
    int32_t cv, cu;
    iv = el_distribution2d__guide_find(f->marginal, f->guide_v, f->shift_v, (uint32_t)(int32_t)xv);
    row = f->cdf + (size_t)iv * f->row_stride;
    iu = el_distribution2d__guide_find(row, f->guide_u + (size_t)iv * f->guide_stride, f->shift_u, (uint32_t)(int32_t)xu);
    cv = (int32_t)f->marginal[iv];
    cu = (int32_t)row[iu];
    wv = (float)((int32_t)f->marginal[iv + 1] - cv);
    wu = (float)((int32_t)row[iu + 1] - cu);
    fv = (xv - (float)cv) / wv;
    fu = (xu - (float)cu) / wu;
  } else {
    iv = el_distribution2d__alias_find(f->alias_v, f->start_v, f->nv, xv, &fv);
    row = f->cdf + (size_t)iv * f->row_stride;
    iu = el_distribution2d__alias_find(f->alias_u + (size_t)iv * (size_t)f->nu * 2, f->start_u, f->nu, xu, &fu);
    wv = (float)(int32_t)(f->marginal[iv + 1] - f->marginal[iv]);
    wu = (float)(int32_t)(row[iu + 1] - row[iu]);
  }
  *out_u = el_distribution2d__place(iu, fu, f->domain[0], f->domain[2], f->u_width, f->u_scale, f->u_last, f->u_exact);
  *out_v = el_distribution2d__place(iv, fv, f->domain[1], f->domain[3], f->v_width, f->v_scale, f->v_last, f->v_exact);
  *pdf = (wv * f->v_pdf_scale) * (wu * f->u_pdf_scale);
}

/* Leaf fast path as in el_distribution2d_sample: u in [0,1), point in its bin at the first try. */
EL_DEF void el_distribution2d_fast_sample(const el_distribution2d_fast *f, float u0, float u1, float *out_u, float *out_v, float *pdf) {
  float xv = u1 * 16777216.0f, xu = u0 * 16777216.0f;
  uint32_t b0, b1;
  memcpy(&b0, &u0, 4);
  memcpy(&b1, &u1, 4);
  if ((b0 > b1 ? b0 : b1) < 0x3f800000u) { /* both in [+0, 1): the bits of 1.0f bound them as integers */
    int iv, iu;
    const uint32_t *row;
    float wv, wu, tv, tu;
    if (f->method == EL_DISTRIBUTION_FAST_GUIDE) {
      uint32_t kv = (uint32_t)(int32_t)xv, ku = (uint32_t)(int32_t)xu, cell;
      const uint32_t *g;
      int32_t cv, cu;
      /* guide cell, then a short linear scan; a crowded cell (> 64 bins) takes the general path */
      cell = kv >> f->shift_v;
      iv = (int)f->guide_v[cell];
      if (iv < 0) goto general; /* EL_DISTRIBUTION__GUIDE_CROWDED */
      while (f->marginal[iv + 1] <= kv) ++iv;
      row = f->cdf + (size_t)iv * f->row_stride;
      g = f->guide_u + (size_t)iv * f->guide_stride;
      cell = ku >> f->shift_u;
      iu = (int)g[cell];
      if (iu < 0) goto general;
      while (row[iu + 1] <= ku) ++iu;
      cv = (int32_t)f->marginal[iv];
      cu = (int32_t)row[iu];
      wv = (float)((int32_t)f->marginal[iv + 1] - cv);
      wu = (float)((int32_t)row[iu + 1] - cu);
      tv = (float)iv + (xv - (float)cv) / wv;
      tu = (float)iu + (xu - (float)cu) / wu;
    } else {
      float fv, fu;
      iv = el_distribution2d__alias_find(f->alias_v, f->start_v, f->nv, xv, &fv);
      row = f->cdf + (size_t)iv * f->row_stride;
      iu = el_distribution2d__alias_find(f->alias_u + (size_t)iv * (size_t)f->nu * 2, f->start_u, f->nu, xu, &fu);
      wv = (float)(int32_t)(f->marginal[iv + 1] - f->marginal[iv]);
      wu = (float)(int32_t)(row[iu + 1] - row[iu]);
      tv = (float)iv + fv;
      tu = (float)iu + fu;
    }
    if (f->u_exact & f->v_exact) { /* no rounding anywhere: only a carry into the next bin can happen */
      if ((int)tv == iv && (int)tu == iu) {
        *out_u = tu * f->u_width;
        *out_v = tv * f->v_width;
        *pdf = (wv * f->v_pdf_scale) * (wu * f->u_pdf_scale);
        return;
      }
    } else if (el_distribution2d__place_fast(tu, iu, f->domain[0], f->domain[2], f->u_width, f->u_scale, 0, out_u) &&
               el_distribution2d__place_fast(tv, iv, f->domain[1], f->domain[3], f->v_width, f->v_scale, 0, out_v)) {
      *pdf = (wv * f->v_pdf_scale) * (wu * f->u_pdf_scale);
      return;
    }
  }
general:
  el_distribution2d__fast_sample_general(f, u0, u1, out_u, out_v, pdf);
}

EL_DEF void el_distribution2d_fast_sample_bins_general(const el_distribution2d_fast *f, float u0, float u1, int *iu, int *iv, float *fu, float *fv, float *pdf) {
  float xv = el_distribution2d__units(u1), xu = el_distribution2d__units(u0);
  const uint32_t *row;
  if (f->method == EL_DISTRIBUTION_FAST_GUIDE) {
    int32_t cv, cu;
    *iv = el_distribution2d__guide_find(f->marginal, f->guide_v, f->shift_v, (uint32_t)(int32_t)xv);
    row = f->cdf + (size_t)*iv * f->row_stride;
    *iu = el_distribution2d__guide_find(row, f->guide_u + (size_t)*iv * f->guide_stride, f->shift_u, (uint32_t)(int32_t)xu);
    cv = (int32_t)f->marginal[*iv];
    cu = (int32_t)row[*iu];
    *fv = (xv - (float)cv) / (float)((int32_t)f->marginal[*iv + 1] - cv);
    *fu = (xu - (float)cu) / (float)((int32_t)row[*iu + 1] - cu);
  } else {
    *iv = el_distribution2d__alias_find(f->alias_v, f->start_v, f->nv, xv, fv);
    *iu = el_distribution2d__alias_find(f->alias_u + (size_t)*iv * (size_t)f->nu * 2, f->start_u, f->nu, xu, fu);
  }
  row = f->cdf + (size_t)*iv * f->row_stride;
  *pdf = ((float)(int32_t)(f->marginal[*iv + 1] - f->marginal[*iv]) * f->v_pdf_scale) * ((float)(int32_t)(row[*iu + 1] - row[*iu]) * f->u_pdf_scale);
}

EL_DEF float el_distribution2d_fast_pdf(const el_distribution2d_fast *f, float u, float v) {
  int iu = el_distribution2d__bin_last(u, f->domain[0], f->u_scale, f->u_last);
  int iv = el_distribution2d__bin_last(v, f->domain[1], f->v_scale, f->v_last);
  const uint32_t *row = f->cdf + (size_t)iv * ((size_t)f->nu + 1);
  float wv = (float)(f->marginal[iv + 1] - f->marginal[iv]);
  float wu = (float)(row[iu + 1] - row[iu]);
  return (wv * f->v_pdf_scale) * (wu * f->u_pdf_scale);
}

EL_DEF size_t el_distribution2d_fast_bytes(const el_distribution2d_fast *f) {
  size_t b = sizeof *f;
  if (f->guide_u) b += (size_t)f->nv * ((size_t)f->gu + 1) * sizeof(uint32_t);
  if (f->guide_v) b += ((size_t)f->gv + 1) * sizeof(uint32_t);
  if (f->alias_u) b += (size_t)f->nv * (size_t)f->nu * 2 * sizeof(uint32_t);
  if (f->alias_v) b += (size_t)f->nv * 2 * sizeof(uint32_t);
  if (f->start_u) b += ((size_t)f->nu + 1) * sizeof(uint32_t);
  if (f->start_v) b += ((size_t)f->nv + 1) * sizeof(uint32_t);
  return b;
}

/* << fast samplers */

#ifdef __cplusplus
}
#endif

#endif /* EL_DISTRIBUTION2D_IMPLEMENTATION_DONE */
#endif /* EL_DISTRIBUTION2D_IMPLEMENTATION */

/*
 * VERSION HISTORY
 *   0.1  first version: integer CDF (every positive bin reachable, pdf = exact probability), 1D/2D
 *        sampling, pdf, invert, guide-table and alias-table constant-time samplers.
 *
 * LICENCE: MIT or public domain (Unlicense), your choice, as stb.
 *   MIT: Copyright (c) 2026 envlight authors. Permission is hereby granted, free of charge, to any person
 *   obtaining a copy of this software to deal in it without restriction, subject to including this notice.
 *   THE SOFTWARE IS PROVIDED "AS IS", WITHOUT WARRANTY OF ANY KIND.
 *   Public domain: this is free and unencumbered software released into the public domain.
 */
