/* tutorials/labs/02-lookups/mipmap.h: LAB 2 (chapter 2, porting the MIP map): the resampling to
 * powers of two, the wrap modes and the lookups. This is examples/pbrtv3/mipmap.h, the course's plain
 * C port of pbrt-v3's MIPMap, with the bodies chapter 2 ports taken out. Write them back; everything
 * else is given and works (lab 1's weights and levels are filled in here).
 *
 * What you write (search for "TODO"):
 *   TODO 1  in pbrt_MIPMap_init: <<Apply sWeights to zoom in s direction>> (chapter 2, "Step 2")
 *   TODO 2  in pbrt_MIPMap_init: <<Resample image in t direction>>, then clamp ("Step 2")
 *   TODO 3  pbrt_MIPMap_Texel: the three wrap modes ("Step 2", Texel)
 *   TODO 4  pbrt_MIPMap_triangle: bilinear interpolation on one level ("Step 3")
 *   TODO 5  pbrt_MIPMap_Lookup: the trilinear lookup ("Step 3")
 *   TODO 6  (optional) pbrt_MIPMap_EWA and pbrt_MIPMap_Lookup_dst ("Trilinear against EWA")
 * Build and check: `sh scripts/lab.sh 2` (from the repository root). The test compares your MIP map
 * with pbrt's, compiled separately from examples/pbrtv3/mipmap.h, and says what differs. Do TODO 3
 * early: the given levels loop reads level i - 1 through your Texel.
 * Untouched, this file compiles and runs, and the test fails: every TODO returns zeros.
 */
#ifndef PBRT_V3_MIPMAP_H
#define PBRT_V3_MIPMAP_H

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

/* ==== 2.1 the class definitions ======================================================================
 * pbrt's small geometry types, used by value as pbrt does. */
typedef struct pbrt_Point2i { int x, y; } pbrt_Point2i;
typedef struct pbrt_Point2f { float x, y; } pbrt_Point2f;
typedef struct pbrt_Vector2f { float x, y; } pbrt_Vector2f;
static inline pbrt_Point2i pbrt_Point2i_make(int x, int y) { pbrt_Point2i p; p.x = x; p.y = y; return p; }
static inline pbrt_Point2f pbrt_Point2f_make(float x, float y) { pbrt_Point2f p; p.x = x; p.y = y; return p; }
static inline pbrt_Vector2f pbrt_Vector2f_make(float x, float y) { pbrt_Vector2f v; v.x = x; v.y = y; return v; }

/* T: pbrt's RGBSpectrum, three floats, and the operators MIPMap uses on it. */
typedef struct pbrt_RGBSpectrum { float c[3]; } pbrt_RGBSpectrum;
static inline pbrt_RGBSpectrum pbrt_RGBSpectrum_make(float v) { /* RGBSpectrum(v), also T(0.f) */
  pbrt_RGBSpectrum r;
  r.c[0] = r.c[1] = r.c[2] = v;
  return r;
}
static inline pbrt_RGBSpectrum pbrt_add(pbrt_RGBSpectrum a, pbrt_RGBSpectrum b) { /* a + b */
  int i;
  for (i = 0; i < 3; ++i) a.c[i] += b.c[i];
  return a;
}
static inline pbrt_RGBSpectrum pbrt_mul(float f, pbrt_RGBSpectrum s) { /* f * s (and s * f) */
  int i;
  for (i = 0; i < 3; ++i) s.c[i] *= f;
  return s;
}
static inline pbrt_RGBSpectrum pbrt_div(pbrt_RGBSpectrum s, float f) { /* s / f */
  int i;
  for (i = 0; i < 3; ++i) s.c[i] /= f;
  return s;
}

/* <<MIPMap Helper Declarations>> */
typedef enum pbrt_ImageWrap { pbrt_ImageWrap_Repeat, pbrt_ImageWrap_Black, pbrt_ImageWrap_Clamp } pbrt_ImageWrap;
typedef struct pbrt_ResampleWeight {
  int firstTexel;
  float weight[4];
} pbrt_ResampleWeight;

/* The forward declaration (the seed: `template <typename T, int logBlockSize = 2> class
 * BlockedArray;` in the global header): pbrt_MIPMap below only holds pointers to it. */
typedef struct pbrt_BlockedArray pbrt_BlockedArray;

/* <<MIPMap Declarations>>: MIPMap<RGBSpectrum>'s private data. */
#define pbrt_WeightLUTSize 128
typedef struct pbrt_MIPMap {
  int doTrilinear;             /* const bool doTrilinear */
  float maxAnisotropy;         /* const Float maxAnisotropy */
  pbrt_ImageWrap wrapMode;     /* const ImageWrap wrapMode */
  pbrt_Point2i resolution;     /* after the constructor: the power-of-two resolution of level 0 */
  pbrt_BlockedArray **pyramid; /* std::vector<std::unique_ptr<BlockedArray<T>>> pyramid */
  int nLevels;                 /* pyramid.size() */
} pbrt_MIPMap;

/* ---- BlockedArray (src/core/memory.h): texels in 4x4 blocks, so that texels close in 2D are close
 * in memory. logBlockSize is pbrt's template parameter, 2 by default. */
#define pbrt_logBlockSize 2
struct pbrt_BlockedArray {
  pbrt_RGBSpectrum *data;
  int uRes, vRes, uBlocks;
};

/* AllocAligned<T>(n) (the seed: new T[n]): calloc, which also zeroes the texels as pbrt's placement
 * `new (&data[i]) T()` does. Out of memory stops the program with a message, as new[] would throw. */
static inline void *pbrt_AllocArray(size_t count, size_t size) {
  void *p = calloc(count, size);
  if (!p) {
    fprintf(stderr, "pbrt port: out of memory (%lu x %lu bytes)\n", (unsigned long)count, (unsigned long)size);
    exit(1);
  }
  return p;
}
static inline int pbrt_BlockedArray_BlockSize(void) { return 1 << pbrt_logBlockSize; }
static inline int pbrt_BlockedArray_RoundUp(int x) {
  return (x + pbrt_BlockedArray_BlockSize() - 1) & ~(pbrt_BlockedArray_BlockSize() - 1);
}
static inline int pbrt_BlockedArray_uSize(const pbrt_BlockedArray *a) { return a->uRes; }
static inline int pbrt_BlockedArray_vSize(const pbrt_BlockedArray *a) { return a->vRes; }
static inline int pbrt_BlockedArray_Block(int a) { return a >> pbrt_logBlockSize; }
static inline int pbrt_BlockedArray_Offset(int a) { return a & (pbrt_BlockedArray_BlockSize() - 1); }
/* operator()(u, v): the texel's address. */
static inline pbrt_RGBSpectrum *pbrt_BlockedArray_at(const pbrt_BlockedArray *a, int u, int v) {
  int bu = pbrt_BlockedArray_Block(u), bv = pbrt_BlockedArray_Block(v);
  int ou = pbrt_BlockedArray_Offset(u), ov = pbrt_BlockedArray_Offset(v);
  int offset = pbrt_BlockedArray_BlockSize() * pbrt_BlockedArray_BlockSize() * (a->uBlocks * bv + bu);
  offset += pbrt_BlockedArray_BlockSize() * ov + ou;
  return &a->data[offset];
}
/* new BlockedArray<T>(uRes, vRes, d): d (row-major, may be NULL) is copied in. */
static inline pbrt_BlockedArray *pbrt_BlockedArray_new(int uRes, int vRes, const pbrt_RGBSpectrum *d) {
  pbrt_BlockedArray *a = (pbrt_BlockedArray *)pbrt_AllocArray(1, sizeof(pbrt_BlockedArray));
  int nAlloc = pbrt_BlockedArray_RoundUp(uRes) * pbrt_BlockedArray_RoundUp(vRes), u, v;
  a->uRes = uRes;
  a->vRes = vRes;
  a->uBlocks = pbrt_BlockedArray_RoundUp(uRes) >> pbrt_logBlockSize;
  a->data = (pbrt_RGBSpectrum *)pbrt_AllocArray((size_t)nAlloc, sizeof(pbrt_RGBSpectrum)); /* was AllocAligned */
  if (d)
    for (v = 0; v < vRes; ++v)
      for (u = 0; u < uRes; ++u) *pbrt_BlockedArray_at(a, u, v) = d[v * uRes + u];
  return a;
}
/* delete (~BlockedArray: FreeAligned(data), the seed's delete[] data) */
static inline void pbrt_BlockedArray_delete(pbrt_BlockedArray *a) {
  if (!a) return;
  free(a->data);
  free(a);
}
/* GetLinearArray(a): the texels back in row-major order. */
static inline void pbrt_BlockedArray_GetLinearArray(const pbrt_BlockedArray *b, pbrt_RGBSpectrum *a) {
  int u, v;
  for (v = 0; v < b->vRes; ++v)
    for (u = 0; u < b->uRes; ++u) *a++ = *pbrt_BlockedArray_at(b, u, v);
}

#ifndef PBRT_MIPMAP_CLASS_ONLY
/* ==== 2.2 the constructor ===========================================================================
 * The helpers it needs, from src/core/pbrt.h and src/core/texture.cpp. */
static inline int pbrt_IsPowerOf2(int v) { return v && !(v & (v - 1)); }
static inline int32_t pbrt_RoundUpPow2(int32_t v) {
  v--;
  v |= v >> 1;
  v |= v >> 2;
  v |= v >> 4;
  v |= v >> 8;
  v |= v >> 16;
  return v + 1;
}
static inline int pbrt_Log2Int(uint32_t v) { /* pbrt: 31 - __builtin_clz(v), the index of the top bit */
  int r = 0;
  while (v >>= 1) ++r;
  return r;
}
static inline int pbrt_Mod(int a, int b) { /* Mod<int>: the result is in [0, b) also for a < 0 */
  int result = a - (a / b) * b;
  return (result < 0) ? result + b : result;
}
static inline int pbrt_Clamp(int val, int low, int high) {
  if (val < low) return low;
  else if (val > high) return high;
  else return val;
}
static inline float pbrt_max(float a, float b) { return (a < b) ? b : a; } /* std::max */
static inline float pbrt_Log2(float x) {
  const float invLog2 = 1.442695040888963387004650940071f;
  return logf(x) * invLog2;
}
static inline pbrt_RGBSpectrum pbrt_Lerp(float t, pbrt_RGBSpectrum s1, pbrt_RGBSpectrum s2) {
  return pbrt_add(pbrt_mul(1 - t, s1), pbrt_mul(t, s2)); /* (1 - t) * s1 + t * s2 */
}
/* Lanczos(x, tau = 2): a sinc windowed by a wider sinc, 0 outside [-1, 1]. */
static inline float pbrt_Lanczos(float x, float tau) {
  float s, lanczos;
  x = fabsf(x);
  if (x < 1e-5f) return 1;
  if (x > 1.f) return 0;
  x *= 3.14159265358979323846f; /* Pi */
  s = sinf(x * tau) / (x * tau);
  lanczos = sinf(x) / x;
  return s * lanczos;
}

/* MIPMap::resampleWeights(oldRes, newRes): 4 taps per output texel (the caller frees the array). */
static inline pbrt_ResampleWeight *pbrt_MIPMap_resampleWeights(int oldRes, int newRes) {
  pbrt_ResampleWeight *wt = (pbrt_ResampleWeight *)pbrt_AllocArray((size_t)newRes, sizeof(pbrt_ResampleWeight));
  float filterwidth = 2.f;
  int i, j;
  for (i = 0; i < newRes; ++i) {
    /* <<Compute image resampling weights for ith texel>> */
    float center = (i + .5f) * oldRes / newRes, invSumWts;
    wt[i].firstTexel = (int)floorf((center - filterwidth) + 0.5f);
    for (j = 0; j < 4; ++j) {
      float pos = wt[i].firstTexel + j + .5f;
      wt[i].weight[j] = pbrt_Lanczos((pos - center) / filterwidth, 2.f);
    }
    /* <<Normalize filter weights for texel resampling>> */
    invSumWts = 1 / (wt[i].weight[0] + wt[i].weight[1] + wt[i].weight[2] + wt[i].weight[3]);
    for (j = 0; j < 4; ++j) wt[i].weight[j] *= invSumWts;
  }
  return wt;
}
/* MIPMap::clamp(v): v.Clamp(0, Infinity), negative Lanczos ringing to 0. */
static inline pbrt_RGBSpectrum pbrt_MIPMap_clamp(pbrt_RGBSpectrum v) {
  int i;
  for (i = 0; i < 3; ++i) v.c[i] = v.c[i] < 0.f ? 0.f : v.c[i];
  return v;
}

static inline int pbrt_MIPMap_Width(const pbrt_MIPMap *mip) { return mip->resolution.x; }
static inline int pbrt_MIPMap_Height(const pbrt_MIPMap *mip) { return mip->resolution.y; }
static inline int pbrt_MIPMap_Levels(const pbrt_MIPMap *mip) { return mip->nLevels; }

/* MIPMap::Texel(level, s, t): integer texel coordinates through the wrap mode. */
static inline pbrt_RGBSpectrum pbrt_MIPMap_Texel(const pbrt_MIPMap *mip, int level, int s, int t) {
  const pbrt_BlockedArray *l = mip->pyramid[level];
  /* <<Compute texel (s,t) accounting for boundary conditions>>
   * TODO 3: bring (s, t) into the level (sizes pbrt_BlockedArray_uSize(l) and vSize(l)) by the wrap
   * mode: Repeat: pbrt_Mod (which stays >= 0 for negative s); Clamp: pbrt_Clamp to [0, size - 1];
   * Black: a texel outside the level is black (pbrt_RGBSpectrum_make(0.f)). Then return
   * *pbrt_BlockedArray_at(l, s, t). Untouched: black. */
  (void)l;
  (void)s;
  (void)t;
  return pbrt_RGBSpectrum_make(0.f);
}

/* pbrt's EWA weights, filled by the first constructor (static Float weightLut[WeightLUTSize]). */
static float pbrt_MIPMap_weightLut[pbrt_WeightLUTSize];

/* MIPMap(resolution, img, doTrilinear = false, maxAnisotropy = 8.f, wrapMode = ImageWrap::Repeat).
 * img: resolution.x * resolution.y texels, row-major. */
static inline void pbrt_MIPMap_init(pbrt_MIPMap *mip, pbrt_Point2i res, const pbrt_RGBSpectrum *img, int doTrilinear,
                                    float maxAnisotropy, pbrt_ImageWrap wrapMode) {
  pbrt_RGBSpectrum *resampledImage = NULL; /* std::unique_ptr<T[]> resampledImage = nullptr */
  int i, s, t, j;
  mip->doTrilinear = doTrilinear;
  mip->maxAnisotropy = maxAnisotropy;
  mip->wrapMode = wrapMode;
  mip->resolution = res;
  if (!pbrt_IsPowerOf2(mip->resolution.x) || !pbrt_IsPowerOf2(mip->resolution.y)) {
    /* <<Resample image to power-of-two resolution>> */
    pbrt_Point2i resPow2 = pbrt_Point2i_make(pbrt_RoundUpPow2(mip->resolution.x), pbrt_RoundUpPow2(mip->resolution.y));
    pbrt_ResampleWeight *sWeights, *tWeights;
    pbrt_RGBSpectrum *workData;
    /* <<Resample image in s direction>> */
    sWeights = pbrt_MIPMap_resampleWeights(mip->resolution.x, resPow2.x);
    resampledImage = (pbrt_RGBSpectrum *)pbrt_AllocArray((size_t)resPow2.x * (size_t)resPow2.y, sizeof(pbrt_RGBSpectrum));
    /* <<Apply sWeights to zoom in s direction>>: pbrt runs ParallelFor([&](int t) {...}, resolution[1], 16),
     * which calls the function for t = 0 .. resolution[1] - 1 (16 values of t per task); without
     * threads, that is this loop. */
    for (t = 0; t < mip->resolution.y; ++t) {
      for (s = 0; s < resPow2.x; ++s) {
        /* <<Compute texel (s,t) in s-zoomed image>>
         * TODO 1: resampledImage[t * resPow2.x + s] = the sum over j = 0..3 of
         * sWeights[s].weight[j] * img[t * mip->resolution.x + origS], origS = sWeights[s].firstTexel + j.
         * origS may fall outside [0, resolution.x): under Repeat wrap it with pbrt_Mod, under Clamp
         * clamp it with pbrt_Clamp, under Black skip the tap (compare with ==, not =).
         * Untouched: the resampled image stays black. */
        (void)sWeights;
        (void)j;
      }
    }
    /* <<Resample image in t direction>> */
    tWeights = pbrt_MIPMap_resampleWeights(mip->resolution.y, resPow2.y);
    /* pbrt keeps one work buffer per thread (resampleBufs[ThreadIndex]); one thread needs one */
    workData = (pbrt_RGBSpectrum *)pbrt_AllocArray((size_t)resPow2.y, sizeof(pbrt_RGBSpectrum));
    for (s = 0; s < resPow2.x; ++s) { /* ParallelFor([&](int s) {...}, resPow2[0], 32) */
      /* TODO 2: the same in t, for column s of the s-zoomed image (rows 0 .. resolution.y - 1 hold it):
       * workData[t] for t = 0 .. resPow2.y - 1 = the sum over j of tWeights[t].weight[j] *
       * resampledImage[offset * resPow2.x + s], offset = tWeights[t].firstTexel + j, wrapped against
       * resolution.y as in TODO 1. Only then write column s back: resampledImage[t * resPow2.x + s] =
       * pbrt_MIPMap_clamp(workData[t]) (why a separate buffer? you would overwrite rows you still read;
       * why clamp? Lanczos has negative lobes, and pbrt clamps the ringing to 0).
       * Untouched: the column stays as TODO 1 left it. */
      (void)tWeights;
      (void)workData;
    }
    free(workData);
    free(sWeights);
    free(tWeights);
    mip->resolution = resPow2;
  }
  /* <<Initialize levels of MIPMap from image>> */
  mip->nLevels = 1 + pbrt_Log2Int((uint32_t)(mip->resolution.x > mip->resolution.y ? mip->resolution.x : mip->resolution.y));
  mip->pyramid = (pbrt_BlockedArray **)pbrt_AllocArray((size_t)mip->nLevels, sizeof(pbrt_BlockedArray *));
  /* <<Initialize most detailed level of MIPMap>> */
  mip->pyramid[0] = pbrt_BlockedArray_new(mip->resolution.x, mip->resolution.y, resampledImage ? resampledImage : img);
  for (i = 1; i < mip->nLevels; ++i) {
    /* <<Initialize ith MIPMap level from (i-1)st level>> */
    int sRes = pbrt_BlockedArray_uSize(mip->pyramid[i - 1]) / 2, tRes = pbrt_BlockedArray_vSize(mip->pyramid[i - 1]) / 2;
    if (sRes < 1) sRes = 1; /* std::max(1, ...) */
    if (tRes < 1) tRes = 1;
    mip->pyramid[i] = pbrt_BlockedArray_new(sRes, tRes, NULL);
    /* <<Filter four texels from finer level of pyramid>>: ParallelFor over t, here a loop */
    for (t = 0; t < tRes; ++t)
      for (s = 0; s < sRes; ++s)
        *pbrt_BlockedArray_at(mip->pyramid[i], s, t) =
            pbrt_mul(.25f, pbrt_add(pbrt_add(pbrt_add(pbrt_MIPMap_Texel(mip, i - 1, 2 * s, 2 * t),
                                                      pbrt_MIPMap_Texel(mip, i - 1, 2 * s + 1, 2 * t)),
                                             pbrt_MIPMap_Texel(mip, i - 1, 2 * s, 2 * t + 1)),
                                    pbrt_MIPMap_Texel(mip, i - 1, 2 * s + 1, 2 * t + 1)));
  }
  /* <<Initialize EWA filter weights if needed>> */
  if (pbrt_MIPMap_weightLut[0] == 0.) {
    for (i = 0; i < pbrt_WeightLUTSize; ++i) {
      float alpha = 2;
      float r2 = (float)i / (float)(pbrt_WeightLUTSize - 1);
      pbrt_MIPMap_weightLut[i] = expf(-alpha * r2) - expf(-alpha);
    }
  }
  free(resampledImage);
}

/* ~MIPMap(): the unique_ptrs delete every level. */
static inline void pbrt_MIPMap_free(pbrt_MIPMap *mip) {
  int i;
  for (i = 0; i < mip->nLevels; ++i) pbrt_BlockedArray_delete(mip->pyramid[i]);
  free(mip->pyramid);
  mip->pyramid = NULL;
  mip->nLevels = 0;
}

/* ==== 2.3 the lookups ===============================================================================
 * MIPMap::triangle(level, st): bilinear between the four texels around st on one level. */
static inline pbrt_RGBSpectrum pbrt_MIPMap_triangle(const pbrt_MIPMap *mip, int level, pbrt_Point2f st) {
  level = pbrt_Clamp(level, 0, pbrt_MIPMap_Levels(mip) - 1);
  /* TODO 4: st (in [0, 1]) times the level's size, minus half a texel (texel centres lie at
   * half-integers), gives s and t; s0 = floor(s), t0 = floor(t), ds = s - s0, dt = t - t0. Return the
   * four texels (s0, t0), (s0, t0 + 1), (s0 + 1, t0), (s0 + 1, t0 + 1), read with pbrt_MIPMap_Texel,
   * weighted (1 - ds)(1 - dt), (1 - ds) dt, ds (1 - dt), ds dt. Untouched: black. */
  (void)st;
  return pbrt_RGBSpectrum_make(0.f);
}

/* MIPMap::Lookup(st, width = 0.f): the triangle filter on the two levels around the width, blended
 * (trilinear). width is in [0,1] texture units: 1 is the whole texture. */
static inline pbrt_RGBSpectrum pbrt_MIPMap_Lookup(const pbrt_MIPMap *mip, pbrt_Point2f st, float width) {
  /* <<Compute MIPMap level for trilinear filtering>>
   * TODO 5: the level whose texels are width wide: Levels() - 1 + pbrt_Log2(max(width, 1e-8)).
   * <<Perform trilinear interpolation at appropriate MIPMap level>>: below level 0, triangle on level 0;
   * at or above the last level, its one texel (Texel(Levels() - 1, 0, 0)); otherwise blend triangle on
   * iLevel = floor(level) and on iLevel + 1 with pbrt_Lerp(level - iLevel, ...). Untouched: black. */
  (void)mip;
  (void)st;
  (void)width;
  return pbrt_RGBSpectrum_make(0.f);
}

/* MIPMap::EWA(level, st, dst0, dst1): the Gaussian-weighted average over the ellipse on one level. */
static inline pbrt_RGBSpectrum pbrt_MIPMap_EWA(const pbrt_MIPMap *mip, int level, pbrt_Point2f st, pbrt_Vector2f dst0,
                                               pbrt_Vector2f dst1) {
  /* TODO 6 (optional): pbrt's EWA on one level ("Trilinear against EWA" in chapter 2): past the last
   * level, its one texel; else scale st (minus half a texel) and both differentials to the level's
   * texels, <<Compute ellipse coefficients to bound EWA filter region>> (A, B, C, divided by
   * F = A C - B^2 / 4), <<Compute the ellipse's (s,t) bounding box in texture space>>, then
   * <<Scan over ellipse bound and compute quadratic equation>>: every texel with r2 < 1 adds
   * pbrt_MIPMap_weightLut[min(int(r2 * pbrt_WeightLUTSize), pbrt_WeightLUTSize - 1)] times the texel;
   * return the sum divided by the sum of the weights. Untouched: black. */
  (void)mip;
  (void)level;
  (void)st;
  (void)dst0;
  (void)dst1;
  return pbrt_RGBSpectrum_make(0.f);
}

/* MIPMap::Lookup(st, dst0, dst1): EWA over the footprint the two differentials span (or, with
 * doTrilinear, the trilinear lookup with the largest component as its width). */
static inline pbrt_RGBSpectrum pbrt_MIPMap_Lookup_dst(const pbrt_MIPMap *mip, pbrt_Point2f st, pbrt_Vector2f dst0,
                                                      pbrt_Vector2f dst1) {
  /* TODO 6 (optional): with doTrilinear, Lookup(st, width) with the largest |component| of dst0 and
   * dst1 as the width. Else <<Compute ellipse minor and major axes>> (dst0 the longer),
   * <<Clamp ellipse eccentricity if too large>> (scale dst1 so that minor * maxAnisotropy >= major),
   * a zero minor axis is triangle(0, st); else <<Choose level of detail for EWA lookup and perform EWA
   * filtering>>: lod = max(0, Levels() - 1 + Log2(minorLength)), and blend EWA on floor(lod) and the
   * level above. Untouched: black. */
  (void)mip;
  (void)st;
  (void)dst0;
  (void)dst1;
  return pbrt_RGBSpectrum_make(0.f);
}
#endif /* PBRT_MIPMAP_CLASS_ONLY */
#endif /* PBRT_V3_MIPMAP_H */
