/* tutorials/labs/03-light/sampling.h: LAB 3 (chapter 3, the infinite area light), part 1 of 2: the distributions.
 * This is examples/pbrtv3/sampling.h with the bodies chapter 3 ports taken out. Write them back; everything
 * else is given and works.
 *
 * What you write (search for "TODO"; the lab is sampling.h and infinite.h in this directory):
 *   sampling.h  TODO 1  pbrt_Distribution1D_init: the CDF and funcInt (chapter 3, "Step 2: Distribution1D and Distribution2D")
 *               TODO 2  pbrt_Distribution1D_SampleContinuous
 *               TODO 3  pbrt_Distribution2D_init: one Distribution1D per row, and the marginal
 *               TODO 4  pbrt_Distribution2D_SampleContinuous
 *               TODO 5  pbrt_Distribution2D_Pdf
 *   infinite.h  TODO 6  pbrt_InfiniteAreaLight_Sample_Li ("Step 3")
 *               TODO 7  pbrt_InfiniteAreaLight_Pdf_Li ("Step 3")
 * Build and check: `sh scripts/lab.sh 3` (from the repository root). The test compares your
 * distributions and light with pbrt's, compiled separately from examples/pbrtv3/, and says what
 * differs. Untouched, these files compile and run, and the test fails: every TODO returns zeros.
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
  d->cdf = (float *)calloc((size_t)n + 1, sizeof(float));
  if (!d->func || !d->cdf) {
    free(d->func);
    free(d->cdf);
    d->func = d->cdf = NULL;
    return -1;
  }
  memcpy(d->func, f, sizeof(float) * (size_t)n);
  /* <<Compute integral of step function at x_i>>
   * TODO 1: cdf[0] = 0 and cdf[i] = cdf[i - 1] + func[i - 1] / n: the integral of the step function
   * (each step is 1/n wide) up to x = i / n. funcInt is cdf[n], the whole integral.
   * <<Transform step function integral into CDF>>: divide every cdf[i] by funcInt so that cdf[n] is 1;
   * if funcInt is 0 (an all-black row), make the CDF uniform: cdf[i] = i / n.
   * Untouched: cdf all 0 (calloc), funcInt 0. */
  d->funcInt = 0;
  (void)i;
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
  /* TODO 2: <<Find surrounding CDF segments and offset>>: offset = pbrt_FindInterval(n + 1, cdf, u), the
   * step whose CDF segment holds u (give it to *off if off is not NULL). <<Compute offset along CDF
   * segment>>: du = u - cdf[offset], divided by the segment's height cdf[offset + 1] - cdf[offset]
   * when that is > 0. <<Compute PDF for sampled offset>>: *pdf (if pdf is not NULL) = func[offset] /
   * funcInt, or 0 when funcInt is 0. <<Return x in [0, 1) corresponding to sample>>: (offset + du) / n.
   * Untouched: x = 0 with pdf 0. */
  (void)d;
  (void)u;
  if (off) *off = 0;
  if (pdf) *pdf = 0;
  return 0;
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
  /* TODO 3: <<Compute conditional sampling distribution for v~>>: for each row v, initialise
   * pConditionalV[v] with the row's nu values (they start at func + v * nu) and put its funcInt into
   * marginalFunc[v]. <<Compute marginal sampling distribution p[v~]>>: initialise pMarginal with the
   * nv values of marginalFunc. Set ok = 0 if an init returns an error.
   * Untouched: every row and the marginal stay empty (n = 0, no arrays). */
  (void)func;
  (void)v;
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
  /* TODO 4: u[1] picks the row: sample pMarginal continuously with u[1] (its offset is the row v, its
   * pdf pdfs[1]), then sample the row's distribution pConditionalV[v] with u[0] (pdf pdfs[0]).
   * uv = (the column's x, the row's x); *pdf = pdfs[0] * pdfs[1].
   * Untouched: uv = (0, 0) with pdf 0. */
  (void)d;
  (void)u;
  uv[0] = uv[1] = 0;
  *pdf = 0;
}

/* The density SampleContinuous has at point p. */
static inline float pbrt_Distribution2D_Pdf(const pbrt_Distribution2D *d, const float p[2]) {
  /* TODO 5: the bin holding p: iu = int(p[0] * nu) and iv = int(p[1] * nv), each clamped into the grid
   * with pbrt_Clamp (p may be exactly 1); the density there is the row's func[iu] divided by the
   * marginal's funcInt (the integral of the whole function). Untouched: 0. */
  (void)d;
  (void)p;
  return 0;
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
