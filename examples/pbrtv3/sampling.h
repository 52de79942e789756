/* examples/pbrtv3/sampling.h: pbrt-v3's Distribution1D and Distribution2D, ported to plain C.
 *
 * The port chapter 3 of the course makes (tutorials/03-infinite-area-light.md): pbrt-v3's
 * src/core/sampling.h and sampling.cpp, book section 13.6.7 ("2D Sampling with Multidimensional
 * Transformations": piecewise-constant 2D distributions). Written the way the seed ports pbrt: C, no
 * SIMD, std::vector turned into malloc'd arrays, member functions turned into functions that take the
 * object first, pbrt's names kept (func, cdf, funcInt, pConditionalV, pMarginal) and its fragment
 * names as comments. It is the "before" of envlight's distribution2d.h: the chapter's example, the
 * tests (tests/test_tutorial_distribution.c, test_tutorial_light.c, test_distribution2d.c) and
 * bench/bench_distribution2d.c all include this one file, so the port exists once.
 *
 * Every function is `static inline`: each file that includes the header gets its own copy, and the
 * compiler does not warn about the functions a file does not use. Like pbrt, the functions trust their
 * input: f must hold n >= 1 finite values >= 0, and u must lie in [0, 1] (pbrt's Pdf converts a NaN
 * point to int, which is undefined behaviour in C and C++). The library checks all of this; the port,
 * like pbrt, does not.
 */
#ifndef PBRTV3_SAMPLING_H
#define PBRTV3_SAMPLING_H

#include <stdlib.h>
#include <string.h>

/* pbrt's Clamp, for ints */
static inline int pbrt_Clamp(int val, int low, int high) {
  if (val < low) return low;
  if (val > high) return high;
  return val;
}

/* pbrt's FindInterval(size, pred) with the predicate Distribution1D passes it, cdf[index] <= u: the
 * largest index in [0, size - 2] whose cdf is <= u, by bisection. */
static inline int pbrt_FindInterval(int size, const float *cdf, float u) {
  int first = 0, len = size;
  while (len > 0) {
    int half = len >> 1, middle = first + half;
    /* <<Bisect range based on value of pred at middle>> */
    if (cdf[middle] <= u) {
      first = middle + 1;
      len -= half + 1;
    } else
      len = half;
  }
  return pbrt_Clamp(first - 1, 0, size - 2);
}

/* >> Distribution1D: a piecewise-constant function on [0, 1] with n steps */
typedef struct pbrt_Distribution1D {
  float *func;   /* the n step values, as given */
  float *cdf;    /* n + 1 values: cdf[0] = 0, ..., cdf[n] = 1 */
  float funcInt; /* the integral of the step function over [0, 1] */
  int n;         /* Count(): func.size() */
} pbrt_Distribution1D;

/* Distribution1D(const Float *f, int n). Returns 0, or -1 when memory runs out (pbrt's vectors would
 * throw). */
static inline int pbrt_Distribution1D_init(pbrt_Distribution1D *d, const float *f, int n) {
  int i;
  d->n = n;
  d->func = (float *)malloc(sizeof(float) * (size_t)n);
  d->cdf = (float *)malloc(sizeof(float) * ((size_t)n + 1));
  if (!d->func || !d->cdf) {
    free(d->func);
    free(d->cdf);
    d->func = d->cdf = NULL;
    return -1;
  }
  memcpy(d->func, f, sizeof(float) * (size_t)n);
  /* <<Compute integral of step function at x_i>> */
  d->cdf[0] = 0;
  for (i = 1; i < n + 1; ++i) d->cdf[i] = d->cdf[i - 1] + d->func[i - 1] / n;
  /* <<Transform step function integral into CDF>> */
  d->funcInt = d->cdf[n];
  if (d->funcInt == 0) {
    for (i = 1; i < n + 1; ++i) d->cdf[i] = (float)i / (float)n;
  } else {
    for (i = 1; i < n + 1; ++i) d->cdf[i] /= d->funcInt;
  }
  return 0;
}

static inline void pbrt_Distribution1D_free(pbrt_Distribution1D *d) {
  free(d->func);
  free(d->cdf);
  d->func = d->cdf = NULL;
}

/* A point x in [0, 1) with density *pdf; *off (may be NULL) gets the step it lies in. */
static inline float pbrt_Distribution1D_SampleContinuous(const pbrt_Distribution1D *d, float u, float *pdf,
                                                         int *off) {
  /* <<Find surrounding CDF segments and offset>> */
  int offset = pbrt_FindInterval(d->n + 1, d->cdf, u);
  float du;
  if (off) *off = offset;
  /* <<Compute offset along CDF segment>> */
  du = u - d->cdf[offset];
  if ((d->cdf[offset + 1] - d->cdf[offset]) > 0) du /= (d->cdf[offset + 1] - d->cdf[offset]);
  /* <<Compute PDF for sampled offset>> */
  if (pdf) *pdf = (d->funcInt > 0) ? d->func[offset] / d->funcInt : 0;
  /* <<Return x in [0, 1) corresponding to sample>> */
  return (offset + du) / d->n;
}

/* A step index with probability *pdf (a probability, not a density); *uRemapped (may be NULL) is u's
 * position within the step's stretch of the CDF, in [0, 1). */
static inline int pbrt_Distribution1D_SampleDiscrete(const pbrt_Distribution1D *d, float u, float *pdf,
                                                     float *uRemapped) {
  /* <<Find surrounding CDF segments and offset>> */
  int offset = pbrt_FindInterval(d->n + 1, d->cdf, u);
  if (pdf) *pdf = (d->funcInt > 0) ? d->func[offset] / (d->funcInt * d->n) : 0;
  if (uRemapped) *uRemapped = (u - d->cdf[offset]) / (d->cdf[offset + 1] - d->cdf[offset]);
  return offset;
}

static inline float pbrt_Distribution1D_DiscretePDF(const pbrt_Distribution1D *d, int index) {
  return d->func[index] / (d->funcInt * d->n);
}

/* >> Distribution2D: nv rows of nu steps on [0, 1]^2; a marginal distribution picks the row (v), the
 * row's conditional distribution the column (u) */
typedef struct pbrt_Distribution2D {
  pbrt_Distribution1D *pConditionalV; /* nv rows, each over nu steps */
  pbrt_Distribution1D pMarginal;      /* over the nv rows' integrals */
  int nu, nv;
} pbrt_Distribution2D;

static inline void pbrt_Distribution2D_free(pbrt_Distribution2D *d) {
  int v;
  if (d->pConditionalV)
    for (v = 0; v < d->nv; ++v) pbrt_Distribution1D_free(&d->pConditionalV[v]);
  free(d->pConditionalV);
  d->pConditionalV = NULL;
  pbrt_Distribution1D_free(&d->pMarginal);
}

/* Distribution2D(const Float *func, int nu, int nv): func[v * nu + u]. Returns 0, or -1 when memory
 * runs out. */
static inline int pbrt_Distribution2D_init(pbrt_Distribution2D *d, const float *func, int nu, int nv) {
  float *marginalFunc;
  int v, ok = 1;
  d->nu = nu;
  d->nv = nv;
  d->pMarginal.func = d->pMarginal.cdf = NULL;
  d->pConditionalV = (pbrt_Distribution1D *)calloc((size_t)nv, sizeof(pbrt_Distribution1D));
  marginalFunc = (float *)malloc(sizeof(float) * (size_t)nv);
  if (!d->pConditionalV || !marginalFunc) ok = 0;
  for (v = 0; ok && v < nv; ++v) {
    /* <<Compute conditional sampling distribution for v~>> */
    if (pbrt_Distribution1D_init(&d->pConditionalV[v], &func[(size_t)v * (size_t)nu], nu) != 0) ok = 0;
    else marginalFunc[v] = d->pConditionalV[v].funcInt;
  }
  /* <<Compute marginal sampling distribution p[v~]>> */
  if (ok && pbrt_Distribution1D_init(&d->pMarginal, marginalFunc, nv) != 0) ok = 0;
  free(marginalFunc);
  if (!ok) {
    pbrt_Distribution2D_free(d);
    return -1;
  }
  return 0;
}

/* A point uv in [0, 1)^2 with density *pdf (with respect to area in [0, 1]^2): u[1] picks the row,
 * u[0] the column within it. (pbrt returns the point; C returns it through uv.) */
static inline void pbrt_Distribution2D_SampleContinuous(const pbrt_Distribution2D *d, const float u[2],
                                                        float uv[2], float *pdf) {
  float pdfs[2];
  int v;
  float d1 = pbrt_Distribution1D_SampleContinuous(&d->pMarginal, u[1], &pdfs[1], &v);
  float d0 = pbrt_Distribution1D_SampleContinuous(&d->pConditionalV[v], u[0], &pdfs[0], NULL);
  *pdf = pdfs[0] * pdfs[1];
  uv[0] = d0;
  uv[1] = d1;
}

/* The density SampleContinuous has at point p. */
static inline float pbrt_Distribution2D_Pdf(const pbrt_Distribution2D *d, const float p[2]) {
  int iu = pbrt_Clamp((int)(p[0] * d->pConditionalV[0].n), 0, d->pConditionalV[0].n - 1);
  int iv = pbrt_Clamp((int)(p[1] * d->pMarginal.n), 0, d->pMarginal.n - 1);
  return d->pConditionalV[iv].func[iu] / d->pMarginal.funcInt;
}

/* Bytes the distribution holds (func and cdf of every row and of the marginal), for the comparison
 * with distribution2d.h's 4 bytes per bin. */
static inline size_t pbrt_Distribution2D_bytes(const pbrt_Distribution2D *d) {
  return (size_t)d->nv * (sizeof(pbrt_Distribution1D) + (2 * (size_t)d->nu + 1) * sizeof(float)) +
         (2 * (size_t)d->nv + 1) * sizeof(float);
}

/* Not pbrt's: the course's count of the bins pbrt never samples. A bin with f > 0 whose CDF step is 0
 * (its share rounded away in the float running sum), or in a row whose marginal step is 0, is never
 * chosen: *count gets their number, *mass_share their share of the integral. */
static inline void pbrt_Distribution2D_unreachable(const pbrt_Distribution2D *d, double *count, double *mass_share) {
  double c = 0, m = 0, tot = 0;
  int u, v;
  for (v = 0; v < d->nv; ++v) {
    const pbrt_Distribution1D *r = &d->pConditionalV[v];
    int row_dead = d->pMarginal.func[v] > 0 && d->pMarginal.cdf[v + 1] == d->pMarginal.cdf[v];
    for (u = 0; u < d->nu; ++u) {
      tot += r->func[u];
      if (r->func[u] > 0 && (row_dead || r->cdf[u + 1] == r->cdf[u])) {
        c += 1;
        m += r->func[u];
      }
    }
  }
  *count = c;
  *mass_share = tot > 0 ? m / tot : 0;
}

#endif /* PBRTV3_SAMPLING_H */
