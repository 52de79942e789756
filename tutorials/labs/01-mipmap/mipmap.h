/* tutorials/labs/01-mipmap/mipmap.h: LAB 1 (chapter 1, the MIP map): the constructor's weights and
 * levels. This is examples/pbrtv3/mipmap.h, the course's plain C port of pbrt-v3's MIPMap, with the
 * bodies chapter 1 explains taken out. Write them back; everything else is given and works.
 *
 * What you write (search for "TODO"):
 *   TODO 1  pbrt_MIPMap_resampleWeights: the four Lanczos taps of every new texel, normalised
 *           (chapter 1, "Constructor step 1"; pbrt's <<Compute image resampling weights for ith texel>> and
 *           <<Normalize filter weights for texel resampling>>)
 *   TODO 2  in pbrt_MIPMap_init: the number of levels (<<Initialize levels of MIPMap from image>>)
 *   TODO 3  in pbrt_MIPMap_init: levels 1, 2, ... from the level before ("Constructor step 2",
 *           <<Initialize ith MIPMap level from (i-1)st level>>, the box filter)
 *   TODO 4  in pbrt_MIPMap_init: the EWA weight table ("Constructor step 3")
 * Build and check: `sh scripts/lab.sh 1` (from the repository root). The test compares your MIP map
 * with pbrt's, compiled separately from examples/pbrtv3/mipmap.h, and says what differs.
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
  /* TODO 1: for each new texel i (0 .. newRes - 1):
   *  - its centre in the old image's texel units: center = (i + .5f) * oldRes / newRes;
   *  - wt[i].firstTexel: the first of the 4 old texels it reads, floor(center - filterwidth + 0.5);
   *  - wt[i].weight[j], j = 0..3: old texel firstTexel + j has its centre at pos = firstTexel + j + .5f;
   *    its weight is pbrt_Lanczos((pos - center) / filterwidth, 2.f);
   *  - <<Normalize filter weights for texel resampling>>: divide the four weights by their sum, so that
   *    a constant image stays constant.
   * Untouched: all weights 0 (AllocArray zeroes the array), so the resampled image is black. */
  (void)oldRes;
  (void)filterwidth;
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
  /* <<Compute texel (s,t) accounting for boundary conditions>> */
  switch (mip->wrapMode) {
  case pbrt_ImageWrap_Repeat:
    s = pbrt_Mod(s, pbrt_BlockedArray_uSize(l));
    t = pbrt_Mod(t, pbrt_BlockedArray_vSize(l));
    break;
  case pbrt_ImageWrap_Clamp:
    s = pbrt_Clamp(s, 0, pbrt_BlockedArray_uSize(l) - 1);
    t = pbrt_Clamp(t, 0, pbrt_BlockedArray_vSize(l) - 1);
    break;
  case pbrt_ImageWrap_Black:
    if (s < 0 || s >= pbrt_BlockedArray_uSize(l) || t < 0 || t >= pbrt_BlockedArray_vSize(l))
      return pbrt_RGBSpectrum_make(0.f); /* static const T black = 0.f */
    break;
  }
  return *pbrt_BlockedArray_at(l, s, t);
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
        /* <<Compute texel (s,t) in s-zoomed image>> */
        pbrt_RGBSpectrum *out = &resampledImage[t * resPow2.x + s];
        *out = pbrt_RGBSpectrum_make(0.f);
        for (j = 0; j < 4; ++j) {
          int origS = sWeights[s].firstTexel + j;
          if (mip->wrapMode == pbrt_ImageWrap_Repeat)
            origS = pbrt_Mod(origS, mip->resolution.x);
          else if (mip->wrapMode == pbrt_ImageWrap_Clamp) /* `==`: the seed's listing has `=` */
            origS = pbrt_Clamp(origS, 0, mip->resolution.x - 1);
          if (origS >= 0 && origS < mip->resolution.x)
            *out = pbrt_add(*out, pbrt_mul(sWeights[s].weight[j], img[t * mip->resolution.x + origS]));
        }
      }
    }
    /* <<Resample image in t direction>> */
    tWeights = pbrt_MIPMap_resampleWeights(mip->resolution.y, resPow2.y);
    /* pbrt keeps one work buffer per thread (resampleBufs[ThreadIndex]); one thread needs one */
    workData = (pbrt_RGBSpectrum *)pbrt_AllocArray((size_t)resPow2.y, sizeof(pbrt_RGBSpectrum));
    for (s = 0; s < resPow2.x; ++s) { /* ParallelFor([&](int s) {...}, resPow2[0], 32) */
      for (t = 0; t < resPow2.y; ++t) {
        workData[t] = pbrt_RGBSpectrum_make(0.f);
        for (j = 0; j < 4; ++j) {
          int offset = tWeights[t].firstTexel + j;
          if (mip->wrapMode == pbrt_ImageWrap_Repeat)
            offset = pbrt_Mod(offset, mip->resolution.y);
          else if (mip->wrapMode == pbrt_ImageWrap_Clamp)
            offset = pbrt_Clamp(offset, 0, mip->resolution.y - 1);
          if (offset >= 0 && offset < mip->resolution.y)
            workData[t] = pbrt_add(workData[t], pbrt_mul(tWeights[t].weight[j], resampledImage[offset * resPow2.x + s]));
        }
      }
      for (t = 0; t < resPow2.y; ++t) resampledImage[t * resPow2.x + s] = pbrt_MIPMap_clamp(workData[t]);
    }
    free(workData);
    free(sWeights);
    free(tWeights);
    mip->resolution = resPow2;
  }
  /* <<Initialize levels of MIPMap from image>> */
  /* TODO 2: the number of levels: 1 + Log2Int of the larger side (512x256 has 10 levels, down to 1x1).
   * Untouched: 1 (level 0 only). */
  mip->nLevels = 1;
  mip->pyramid = (pbrt_BlockedArray **)pbrt_AllocArray((size_t)mip->nLevels, sizeof(pbrt_BlockedArray *));
  /* <<Initialize most detailed level of MIPMap>> */
  mip->pyramid[0] = pbrt_BlockedArray_new(mip->resolution.x, mip->resolution.y, resampledImage ? resampledImage : img);
  for (i = 1; i < mip->nLevels; ++i) {
    /* <<Initialize ith MIPMap level from (i-1)st level>>
     * TODO 3: level i has half the size of level i - 1 on each side, but at least 1 (std::max(1, ...)):
     * create it with pbrt_BlockedArray_new(sRes, tRes, NULL), then set each of its texels (s, t)
     * (*pbrt_BlockedArray_at(mip->pyramid[i], s, t) = ...) to the box filter of level i - 1:
     * .25f times the sum of the four texels (2s, 2t), (2s+1, 2t), (2s, 2t+1), (2s+1, 2t+1), each read
     * with pbrt_MIPMap_Texel(mip, i - 1, ...) (which handles the wrap mode when a side is 1).
     * Helpers: pbrt_add(a, b), pbrt_mul(f, s). Untouched: every level above 0 is a black 1x1 level. */
    mip->pyramid[i] = pbrt_BlockedArray_new(1, 1, NULL);
    (void)s;
    (void)t;
  }
  /* <<Initialize EWA filter weights if needed>> */
  if (pbrt_MIPMap_weightLut[0] == 0.) {
    /* TODO 4: for i = 0 .. pbrt_WeightLUTSize - 1: r2 = i / (pbrt_WeightLUTSize - 1) (as floats) and
     * pbrt_MIPMap_weightLut[i] = exp(-alpha r2) - exp(-alpha) with alpha = 2: a Gaussian in the squared
     * radius, shifted down to reach 0 at r2 = 1. Untouched: the table stays 0. */
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
  float s, t, ds, dt;
  int s0, t0;
  level = pbrt_Clamp(level, 0, pbrt_MIPMap_Levels(mip) - 1);
  s = st.x * pbrt_BlockedArray_uSize(mip->pyramid[level]) - 0.5f;
  t = st.y * pbrt_BlockedArray_vSize(mip->pyramid[level]) - 0.5f;
  s0 = (int)floorf(s);
  t0 = (int)floorf(t);
  ds = s - s0;
  dt = t - t0;
  return pbrt_add(pbrt_add(pbrt_add(pbrt_mul((1 - ds) * (1 - dt), pbrt_MIPMap_Texel(mip, level, s0, t0)),
                                    pbrt_mul((1 - ds) * dt, pbrt_MIPMap_Texel(mip, level, s0, t0 + 1))),
                           pbrt_mul(ds * (1 - dt), pbrt_MIPMap_Texel(mip, level, s0 + 1, t0))),
                  pbrt_mul(ds * dt, pbrt_MIPMap_Texel(mip, level, s0 + 1, t0 + 1)));
}

/* MIPMap::Lookup(st, width = 0.f): the triangle filter on the two levels around the width, blended
 * (trilinear). width is in [0,1] texture units: 1 is the whole texture. */
static inline pbrt_RGBSpectrum pbrt_MIPMap_Lookup(const pbrt_MIPMap *mip, pbrt_Point2f st, float width) {
  /* <<Compute MIPMap level for trilinear filtering>> */
  float level = pbrt_MIPMap_Levels(mip) - 1 + pbrt_Log2(pbrt_max(width, (float)1e-8));
  /* <<Perform trilinear interpolation at appropriate MIPMap level>> */
  if (level < 0)
    return pbrt_MIPMap_triangle(mip, 0, st);
  else if (level >= pbrt_MIPMap_Levels(mip) - 1)
    return pbrt_MIPMap_Texel(mip, pbrt_MIPMap_Levels(mip) - 1, 0, 0);
  else {
    int iLevel = (int)floorf(level);
    float delta = level - iLevel;
    return pbrt_Lerp(delta, pbrt_MIPMap_triangle(mip, iLevel, st), pbrt_MIPMap_triangle(mip, iLevel + 1, st));
  }
}

/* MIPMap::EWA(level, st, dst0, dst1): the Gaussian-weighted average over the ellipse on one level. */
static inline pbrt_RGBSpectrum pbrt_MIPMap_EWA(const pbrt_MIPMap *mip, int level, pbrt_Point2f st, pbrt_Vector2f dst0,
                                               pbrt_Vector2f dst1) {
  float A, B, C, invF, det, invDet, uSqrt, vSqrt, sumWts = 0;
  int s0, s1, t0, t1, it, is, uSize, vSize;
  pbrt_RGBSpectrum sum = pbrt_RGBSpectrum_make(0.f);
  if (level >= pbrt_MIPMap_Levels(mip)) return pbrt_MIPMap_Texel(mip, pbrt_MIPMap_Levels(mip) - 1, 0, 0);
  /* <<Convert EWA coordinates to appropriate scale for level>> */
  uSize = pbrt_BlockedArray_uSize(mip->pyramid[level]);
  vSize = pbrt_BlockedArray_vSize(mip->pyramid[level]);
  st.x = st.x * uSize - 0.5f;
  st.y = st.y * vSize - 0.5f;
  dst0.x *= uSize;
  dst0.y *= vSize;
  dst1.x *= uSize;
  dst1.y *= vSize;
  /* <<Compute ellipse coefficients to bound EWA filter region>> */
  A = dst0.y * dst0.y + dst1.y * dst1.y + 1;
  B = -2 * (dst0.x * dst0.y + dst1.x * dst1.y);
  C = dst0.x * dst0.x + dst1.x * dst1.x + 1;
  invF = 1 / (A * C - B * B * 0.25f);
  A *= invF;
  B *= invF;
  C *= invF;
  /* <<Compute the ellipse's (s,t) bounding box in texture space>> */
  det = -B * B + 4 * A * C;
  invDet = 1 / det;
  uSqrt = sqrtf(det * C);
  vSqrt = sqrtf(A * det);
  s0 = (int)ceilf(st.x - 2 * invDet * uSqrt);
  s1 = (int)floorf(st.x + 2 * invDet * uSqrt);
  t0 = (int)ceilf(st.y - 2 * invDet * vSqrt);
  t1 = (int)floorf(st.y + 2 * invDet * vSqrt);
  /* <<Scan over ellipse bound and compute quadratic equation>> */
  for (it = t0; it <= t1; ++it) {
    float tt = it - st.y;
    for (is = s0; is <= s1; ++is) {
      float ss = is - st.x;
      /* <<Compute squared radius and filter texel if inside ellipse>> */
      float r2 = A * ss * ss + B * ss * tt + C * tt * tt;
      if (r2 < 1) {
        int index = (int)(r2 * pbrt_WeightLUTSize);
        float weight;
        if (index > pbrt_WeightLUTSize - 1) index = pbrt_WeightLUTSize - 1; /* std::min */
        weight = pbrt_MIPMap_weightLut[index];
        sum = pbrt_add(sum, pbrt_mul(weight, pbrt_MIPMap_Texel(mip, level, is, it)));
        sumWts += weight;
      }
    }
  }
  return pbrt_div(sum, sumWts);
}

/* MIPMap::Lookup(st, dst0, dst1): EWA over the footprint the two differentials span (or, with
 * doTrilinear, the trilinear lookup with the largest component as its width). */
static inline pbrt_RGBSpectrum pbrt_MIPMap_Lookup_dst(const pbrt_MIPMap *mip, pbrt_Point2f st, pbrt_Vector2f dst0,
                                                      pbrt_Vector2f dst1) {
  float majorLength, minorLength, lod;
  int ilod;
  if (mip->doTrilinear) {
    float width = pbrt_max(pbrt_max(fabsf(dst0.x), fabsf(dst0.y)), pbrt_max(fabsf(dst1.x), fabsf(dst1.y)));
    return pbrt_MIPMap_Lookup(mip, st, width); /* pbrt-v3 before its commit aaa552a: 2 * width */
  }
  /* <<Compute ellipse minor and major axes>> */
  if (dst0.x * dst0.x + dst0.y * dst0.y < dst1.x * dst1.x + dst1.y * dst1.y) { /* std::swap(dst0, dst1) */
    pbrt_Vector2f tmp = dst0;
    dst0 = dst1;
    dst1 = tmp;
  }
  majorLength = sqrtf(dst0.x * dst0.x + dst0.y * dst0.y);
  minorLength = sqrtf(dst1.x * dst1.x + dst1.y * dst1.y);
  /* <<Clamp ellipse eccentricity if too large>> */
  if (minorLength * mip->maxAnisotropy < majorLength && minorLength > 0) {
    float scale = majorLength / (minorLength * mip->maxAnisotropy);
    dst1.x *= scale;
    dst1.y *= scale;
    minorLength *= scale;
  }
  if (minorLength == 0) return pbrt_MIPMap_triangle(mip, 0, st);
  /* <<Choose level of detail for EWA lookup and perform EWA filtering>> */
  lod = pbrt_max((float)0, pbrt_MIPMap_Levels(mip) - (float)1 + pbrt_Log2(minorLength));
  ilod = (int)floorf(lod);
  return pbrt_Lerp(lod - ilod, pbrt_MIPMap_EWA(mip, ilod, st, dst0, dst1), pbrt_MIPMap_EWA(mip, ilod + 1, st, dst0, dst1));
}
#endif /* PBRT_MIPMAP_CLASS_ONLY */
#endif /* PBRT_V3_MIPMAP_H */
