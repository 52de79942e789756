/* tutorials/labs/04-film/film.h: LAB 4 (chapter 4, the film and tone mapping). This is
 * examples/pbrtv3/film.h, the course's plain C port of pbrt-v3's film, with the bodies chapter 4
 * explains taken out. Write them back; everything else (the filters, the film's table, GetFilmTile,
 * MergeFilmTile) is given and works.
 *
 * What you write (search for "TODO"):
 *   TODO 1  pbrt_FilmTile_AddSample: a sample into the pixels its filter reaches (chapter 4, "The film again")
 *   TODO 2  pbrt_Film_WriteImage: XYZ to RGB, divided by the weight sum, splats, scale ("The film again", "splatXYZ")
 *   TODO 3  pbrt_GammaCorrect: the sRGB curve ("Gamma correction and TO_BYTE")
 *   TODO 4  TO_BYTE: curve, round, clamp (the same section)
 * Build and check: `sh scripts/lab.sh 4` (from the repository root). The test compares your film with
 * pbrt's, compiled separately from examples/pbrtv3/film.h, and says what differs.
 * Untouched, this file compiles and runs, and the test fails: every TODO returns zeros.
 */
#ifndef PBRTV3_FILM_H
#define PBRTV3_FILM_H

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* >> pbrt.h and spectrum.h */
static inline float pbrt_Clampf(float val, float low, float high) { /* pbrt's Clamp, for floats */
  if (val < low) return low;
  if (val > high) return high;
  return val;
}
/* the sRGB curve (pbrt's GammaCorrect) */
static inline float pbrt_GammaCorrect(float value) {
  /* TODO 3: the sRGB curve: 12.92 value up to 0.0031308, above it 1.055 value^(1/2.4) - 0.055
   * (powf; write the exponent as (float)(1.f / 2.4f)). Untouched: 0. */
  (void)value;
  return 0;
}
static inline void pbrt_XYZToRGB(const float xyz[3], float rgb[3]) {
  rgb[0] = 3.240479f * xyz[0] - 1.537150f * xyz[1] - 0.498535f * xyz[2];
  rgb[1] = -0.969256f * xyz[0] + 1.875991f * xyz[1] + 0.041556f * xyz[2];
  rgb[2] = 0.055648f * xyz[0] - 0.204043f * xyz[1] + 1.057311f * xyz[2];
}
static inline void pbrt_RGBToXYZ(const float rgb[3], float xyz[3]) {
  xyz[0] = 0.412453f * rgb[0] + 0.357580f * rgb[1] + 0.180423f * rgb[2];
  xyz[1] = 0.212671f * rgb[0] + 0.715160f * rgb[1] + 0.072169f * rgb[2];
  xyz[2] = 0.019334f * rgb[0] + 0.119193f * rgb[1] + 0.950227f * rgb[2];
}

/* >> the filters (src/filters/): Evaluate(p) at an offset p from the pixel centre, |p| <= radius */
enum { pbrt_BoxFilter, pbrt_TriangleFilter, pbrt_GaussianFilter, pbrt_MitchellFilter };
typedef struct pbrt_Filter {
  int type;
  float radius[2], invRadius[2];
  float alpha, expX, expY; /* gaussian: alpha and exp(-alpha radius^2) per axis */
  float B, C;              /* mitchell */
} pbrt_Filter;

/* CreateBoxFilter ... CreateMitchellFilter with the parameters pbrt's scene files give them: radius
 * (xwidth = ywidth), and alpha (gaussian) or B = C (mitchell); pass 0 for pbrt's defaults (box 0.5,
 * the others 2; alpha 2; B = C = 1/3). */
static inline pbrt_Filter pbrt_MakeFilter(int type, float radius, float param) {
  pbrt_Filter f;
  memset(&f, 0, sizeof f);
  f.type = type;
  if (radius <= 0) radius = type == pbrt_BoxFilter ? 0.5f : 2.f;
  f.radius[0] = f.radius[1] = radius;
  f.invRadius[0] = f.invRadius[1] = 1 / radius;
  f.alpha = param > 0 ? param : 2.f;
  f.expX = expf(-f.alpha * f.radius[0] * f.radius[0]);
  f.expY = expf(-f.alpha * f.radius[1] * f.radius[1]);
  f.B = f.C = param > 0 ? param : 1.f / 3.f;
  return f;
}
static inline float pbrt_Gaussian(const pbrt_Filter *f, float d, float expv) {
  float g = expf(-f->alpha * d * d) - expv;
  return g > 0 ? g : 0;
}
static inline float pbrt_Mitchell1D(const pbrt_Filter *f, float x) {
  float B = f->B, C = f->C;
  x = fabsf(2 * x);
  if (x > 1)
    return ((-B - 6 * C) * x * x * x + (6 * B + 30 * C) * x * x + (-12 * B - 48 * C) * x + (8 * B + 24 * C)) *
           (1.f / 6.f);
  else
    return ((12 - 9 * B - 6 * C) * x * x * x + (-18 + 12 * B + 6 * C) * x * x + (6 - 2 * B)) * (1.f / 6.f);
}
static inline float pbrt_Filter_Evaluate(const pbrt_Filter *f, const float p[2]) {
  switch (f->type) {
  case pbrt_TriangleFilter: {
    float x = f->radius[0] - fabsf(p[0]), y = f->radius[1] - fabsf(p[1]);
    return (x > 0 ? x : 0) * (y > 0 ? y : 0);
  }
  case pbrt_GaussianFilter: return pbrt_Gaussian(f, p[0], f->expX) * pbrt_Gaussian(f, p[1], f->expY);
  case pbrt_MitchellFilter: return pbrt_Mitchell1D(f, p[0] * f->invRadius[0]) * pbrt_Mitchell1D(f, p[1] * f->invRadius[1]);
  default: return 1.;
  }
}

/* >> Film */
#define pbrt_filterTableWidth 16
typedef struct pbrt_Pixel {
  float xyz[3];          /* the weighted sum of the samples, in XYZ */
  float filterWeightSum; /* the sum of their filter weights */
  float splatXYZ[3];     /* pbrt: AtomicFloat, for light tracing; 0 for a path tracer */
  float pad;
} pbrt_Pixel;
typedef struct pbrt_Film {
  int fullResolution[2];
  pbrt_Filter filter;
  float scale, maxSampleLuminance;
  pbrt_Pixel *pixels; /* fullResolution[0] * fullResolution[1]: croppedPixelBounds is the whole image */
  float filterTable[pbrt_filterTableWidth * pbrt_filterTableWidth];
} pbrt_Film;

/* Film(resolution, cropWindow, filt, diagonal, filename, scale, maxSampleLuminance), with the whole
 * image as its crop window. pbrt's defaults: scale 1, maxSampleLuminance Infinity. Returns 0, or -1
 * when memory runs out. */
static inline int pbrt_Film_init(pbrt_Film *film, int xres, int yres, const pbrt_Filter *filt, float scale,
                                 float maxSampleLuminance) {
  int x, y, offset = 0;
  film->fullResolution[0] = xres;
  film->fullResolution[1] = yres;
  film->filter = *filt;
  film->scale = scale;
  film->maxSampleLuminance = maxSampleLuminance;
  /* <<Allocate film image storage>> */
  film->pixels = (pbrt_Pixel *)calloc((size_t)xres * (size_t)yres, sizeof(pbrt_Pixel));
  if (!film->pixels) return -1;
  /* <<Precompute filter weight table>> */
  for (y = 0; y < pbrt_filterTableWidth; ++y) {
    for (x = 0; x < pbrt_filterTableWidth; ++x, ++offset) {
      float p[2];
      p[0] = (x + 0.5f) * film->filter.radius[0] / pbrt_filterTableWidth;
      p[1] = (y + 0.5f) * film->filter.radius[1] / pbrt_filterTableWidth;
      film->filterTable[offset] = pbrt_Filter_Evaluate(&film->filter, p);
    }
  }
  return 0;
}
static inline void pbrt_Film_free(pbrt_Film *film) {
  free(film->pixels);
  film->pixels = NULL;
}

/* >> FilmTile: a thread's private part of the film, over the pixels its samples reach */
typedef struct pbrt_FilmTilePixel {
  float contribSum[3];   /* Spectrum contribSum: sum of L * sampleWeight * filterWeight */
  float filterWeightSum; /* sum of filterWeight */
} pbrt_FilmTilePixel;
typedef struct pbrt_FilmTile {
  int pixelBounds[4]; /* pMin.x, pMin.y, pMax.x, pMax.y: pixels [pMin, pMax) */
  float filterRadius[2], invFilterRadius[2];
  const float *filterTable;
  int filterTableSize;
  float maxSampleLuminance;
  pbrt_FilmTilePixel *pixels;
} pbrt_FilmTile;

/* Film::GetFilmTile(sampleBounds): the tile for samples taken in pixels [x0, x1) x [y0, y1). Returns 0,
 * or -1 when memory runs out. */
static inline int pbrt_Film_GetFilmTile(const pbrt_Film *film, const int sampleBounds[4], pbrt_FilmTile *tile) {
  /* <<Bound image pixels that samples in sampleBounds contribute to>> */
  int p0x = (int)ceilf(sampleBounds[0] - 0.5f - film->filter.radius[0]);
  int p0y = (int)ceilf(sampleBounds[1] - 0.5f - film->filter.radius[1]);
  int p1x = (int)floorf(sampleBounds[2] - 0.5f + film->filter.radius[0]) + 1;
  int p1y = (int)floorf(sampleBounds[3] - 0.5f + film->filter.radius[1]) + 1;
  /* Intersect(Bounds2i(p0, p1), croppedPixelBounds) */
  tile->pixelBounds[0] = p0x > 0 ? p0x : 0;
  tile->pixelBounds[1] = p0y > 0 ? p0y : 0;
  tile->pixelBounds[2] = p1x < film->fullResolution[0] ? p1x : film->fullResolution[0];
  tile->pixelBounds[3] = p1y < film->fullResolution[1] ? p1y : film->fullResolution[1];
  if (tile->pixelBounds[2] < tile->pixelBounds[0]) tile->pixelBounds[2] = tile->pixelBounds[0];
  if (tile->pixelBounds[3] < tile->pixelBounds[1]) tile->pixelBounds[3] = tile->pixelBounds[1];
  tile->filterRadius[0] = film->filter.radius[0];
  tile->filterRadius[1] = film->filter.radius[1];
  tile->invFilterRadius[0] = 1 / film->filter.radius[0];
  tile->invFilterRadius[1] = 1 / film->filter.radius[1];
  tile->filterTable = film->filterTable;
  tile->filterTableSize = pbrt_filterTableWidth;
  tile->maxSampleLuminance = film->maxSampleLuminance;
  tile->pixels = (pbrt_FilmTilePixel *)calloc(
      (size_t)(tile->pixelBounds[2] - tile->pixelBounds[0]) * (size_t)(tile->pixelBounds[3] - tile->pixelBounds[1]) + 1,
      sizeof(pbrt_FilmTilePixel));
  return tile->pixels ? 0 : -1;
}
static inline void pbrt_FilmTile_free(pbrt_FilmTile *tile) {
  free(tile->pixels);
  tile->pixels = NULL;
}
static inline pbrt_FilmTilePixel *pbrt_FilmTile_GetPixel(const pbrt_FilmTile *tile, int x, int y) {
  int width = tile->pixelBounds[2] - tile->pixelBounds[0];
  return &tile->pixels[(y - tile->pixelBounds[1]) * width + (x - tile->pixelBounds[0])];
}

/* FilmTile::AddSample(pFilm, L, sampleWeight): pFilm in continuous raster coordinates (pixel (x, y)
 * covers [x, x + 1) x [y, y + 1)). */
static inline void pbrt_FilmTile_AddSample(pbrt_FilmTile *tile, const float pFilm[2], const float Lin[3],
                                           float sampleWeight) {
  /* TODO 1 (pbrt's FilmTile::AddSample):
   *  - L = Lin; if its luminance (0.212671 R + 0.715160 G + 0.072169 B) exceeds maxSampleLuminance,
   *    scale L down to it;
   *  - <<Compute sample's raster bounds>>: pFilmDiscrete = pFilm - 0.5 (pixel centres at integers);
   *    p0 = ceil(pFilmDiscrete - filterRadius), p1 = floor(pFilmDiscrete + filterRadius) + 1, then
   *    p0 = max(p0, pixelBounds' min), p1 = min(p1, pixelBounds' max) (pixelBounds[0..1] min, [2..3] max);
   *  - <<Precompute x and y filter table offsets>>: for x in [p0.x, p1.x): ifx[x - p0.x] =
   *    min(floor(|(x - pFilmDiscrete.x) * invFilterRadius.x * filterTableSize|), filterTableSize - 1);
   *    the same in y (ify);
   *  - <<Loop over filter support and add sample to pixel arrays>>: for every pixel (x, y) in
   *    [p0, p1): filterWeight = filterTable[ify[y - p0.y] * filterTableSize + ifx[x - p0.x]];
   *    the pixel (pbrt_FilmTile_GetPixel) gets contribSum += L * sampleWeight * filterWeight and
   *    filterWeightSum += filterWeight.
   * Untouched: the sample is dropped. */
  (void)tile;
  (void)pFilm;
  (void)Lin;
  (void)sampleWeight;
}

/* Film::MergeFilmTile(tile): the tile's sums, converted to XYZ, added into the film (pbrt holds the
 * film's mutex here). */
static inline void pbrt_Film_MergeFilmTile(pbrt_Film *film, const pbrt_FilmTile *tile) {
  int x, y, i;
  for (y = tile->pixelBounds[1]; y < tile->pixelBounds[3]; ++y)
    for (x = tile->pixelBounds[0]; x < tile->pixelBounds[2]; ++x) {
      /* <<Merge pixel into Film::pixels>> */
      const pbrt_FilmTilePixel *tilePixel = pbrt_FilmTile_GetPixel(tile, x, y);
      pbrt_Pixel *mergePixel = &film->pixels[y * film->fullResolution[0] + x];
      float xyz[3];
      pbrt_RGBToXYZ(tilePixel->contribSum, xyz); /* tilePixel.contribSum.ToXYZ(xyz) */
      for (i = 0; i < 3; ++i) mergePixel->xyz[i] += xyz[i];
      mergePixel->filterWeightSum += tilePixel->filterWeightSum;
    }
}

/* Film::WriteImage(splatScale) up to the call of pbrt::WriteImage: the final linear RGB of every pixel
 * into rgb (3 floats per pixel, row 0 at the top). */
static inline void pbrt_Film_WriteImage(const pbrt_Film *film, float splatScale, float *rgb) {
  /* TODO 2 (pbrt's Film::WriteImage, before the file is written): for every pixel (offset 0 .. xres
   * yres - 1, rgb[3 offset ...]):
   *  - <<Convert pixel XYZ color to RGB>>: pbrt_XYZToRGB(pixel->xyz, &rgb[3 * offset]);
   *  - <<Normalize pixel with weight sum>>: if filterWeightSum is not 0, multiply each channel by
   *    1 / filterWeightSum and clamp it below at 0 (fmaxf(0.f, ...));
   *  - <<Add splat value at pixel>>: add splatScale times the splat's RGB (pbrt_XYZToRGB of splatXYZ);
   *  - <<Scale pixel value by scale>>: multiply by film->scale.
   * Untouched: every pixel black. */
  int n = film->fullResolution[0] * film->fullResolution[1];
  (void)splatScale;
  memset(rgb, 0, sizeof(float) * 3 * (size_t)n);
}

/* >> imageio.cpp, pbrt::WriteImage for an 8-bit file (PNG, TGA): the sRGB curve, round, clamp */
/* TODO 4: TO_BYTE(v): the curve (pbrt_GammaCorrect), times 255, rounded (+ 0.5f before the cast
 * truncates), clamped to [0, 255] with pbrt_Clampf, then cast to uint8_t. Untouched: 0. */
#define TO_BYTE(v) ((void)(v), (uint8_t)0)
static inline void pbrt_WriteImage8(const float *rgb, int xres, int yres, uint8_t *rgb8) {
  uint8_t *dst = rgb8;
  int x, y;
  for (y = 0; y < yres; ++y) {
    for (x = 0; x < xres; ++x) {
      dst[0] = TO_BYTE(rgb[3 * (y * xres + x) + 0]);
      dst[1] = TO_BYTE(rgb[3 * (y * xres + x) + 1]);
      dst[2] = TO_BYTE(rgb[3 * (y * xres + x) + 2]);
      dst += 3;
    }
  }
}

/* >> the seed's output curve, HDRtoLDR. The seed's section 四 names it (from its earlier book) without
 * printing it; its published source (github.com/feimos32/PBRT3-DezemingFamily, SourceFiles/13 -
 * PBRT3InfiniteLight.zip, Core/FrameBuffer.h, update_f_u_c) computes, per channel of the running
 * average, temp_c = 1 - exp(-x / (1 - exposure)) with exposure = 0.75 (so 1 - exp(-4 x)), and stores
 * temp_c * 255 in the byte: no sRGB curve, and truncation instead of rounding. */
static inline uint8_t pbrt_seed_HDRtoLDR(float x) {
  float exposure = 0.75;
  float temp_c = 1.0f - expf(-x * 1.0f / (1 - exposure));
  return (uint8_t)(temp_c * 255);
}

#endif /* PBRTV3_FILM_H */
