/* film.h - envlight's film: pixel filters, weighted accumulation, splats, sRGB and tone mapping.
 * envlight v0.1.0 - MIT or public domain
 *
 * DO THIS in exactly one C or C++ file (the first line alone is enough):
 *     #define EL_IMPLEMENTATION   // implements every envlight header included after it
 *     #include "film.h"
 * Every other file includes it without the macro. EL_FILM_IMPLEMENTATION instead implements film.h
 * alone: a module's own macro never implements another module's header.
 *
 * USAGE (C; where C writes `= {0}`, C++ writes `= {}`; tests/test_snippets.c compiles both)
 * >> usage
 *     // given: float px, py; const float L[3]; float *rgb; unsigned char *srgb8;  (640 * 480 * 3 each)
 *     el_film film;
 *     el_film_options fo = {0};                  // C++: = {}. All zero but the size: pbrt's box filter
 *     fo.width = 640; fo.height = 480;
 *     fo.filter.type = EL_FILM_FILTER_GAUSSIAN;  // pbrt's "gaussian": radius 2, alpha 2
 *     if (el_film_init(&film, &fo) != EL_SUCCESS) return 1;
 *     int b[4];                                    // the pixels to sample: [b[0],b[2]) x [b[1],b[3]),
 *     el_film_sample_bounds(&film, b);             // the image grown by the filter's radius
 *     el_film_add_sample(&film, px, py, L, 1.0f);  // raster position, radiance, ray weight
 *     el_film_get_rgb(&film, 1.0f, rgb);           // linear RGB, row 0 at the top
 *     el_film_to_srgb8(rgb, film.width, film.height, NULL, srgb8);  // clamp, exact sRGB (pbrt's TO_BYTE)
 *     el_film_free(&film);
 * << usage
 * Threads: each thread adds its samples to its own el_film_tile, then el_film_merge_tile under a lock.
 *
 * OPTIONS (define before including): EL_MALLOC / EL_REALLOC / EL_FREE (all or none), EL_ASSERT,
 * EL_STATIC (private functions in this translation unit), EL_DEF.
 *
 * PORTS pbrt-v3's Film and FilmTile (src/core/film.h, film.cpp: AddSample with its filterTable,
 * AddSplat, GetSampleBounds, MergeFilmTile, WriteImage), its filters (src/filters/: box, triangle,
 * gaussian, mitchell, sinc) and the sRGB curve GammaCorrect and TO_BYTE of src/core/imageio.cpp; tone
 * mapping goes past pbrt (exposure, exponential, Reinhard, ACES, dithering). NOTES after the
 * declarations: where and why it departs from pbrt.
 */
#ifndef EL_FILM_H
#define EL_FILM_H

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

#include <math.h>

#ifdef __cplusplus
extern "C" {
#endif

/* >> filters (pbrt-v3 src/filters/) */
typedef enum el_film_filter_type {
  EL_FILM_FILTER_BOX = 0,  /* pbrt "box":      radius 0.5 */
  EL_FILM_FILTER_TRIANGLE, /* pbrt "triangle": radius 2 */
  EL_FILM_FILTER_GAUSSIAN, /* pbrt "gaussian": radius 2, alpha 2 */
  EL_FILM_FILTER_MITCHELL, /* pbrt "mitchell": radius 2, B = C = 1/3 */
  EL_FILM_FILTER_LANCZOS   /* pbrt "sinc":     radius 4, tau 3 */
} el_film_filter_type;

/* A pixel filter. Zero fields take pbrt-v3's defaults for the type (see above): a radius of 0 (either
 * axis) means the default radius on that axis, alpha/tau 0 mean the default, and mitchell_b ==
 * mitchell_c == 0 means B = C = 1/3 (for B = C = 0 pass a tiny value such as 1e-30f). */
typedef struct el_film_filter {
  el_film_filter_type type;
  float radius[2];      /* x and y half-widths in pixels (pbrt "xwidth", "ywidth") */
  float gaussian_alpha; /* pbrt "alpha" */
  float mitchell_b, mitchell_c;
  float lanczos_tau;    /* pbrt "tau" */
} el_film_filter;

/* Fills every default of *in into *out. EL_ERROR_INVALID_ARGUMENT for NULL pointers, an unknown type, or
 * a negative, NaN or infinite parameter (or a radius above 64 pixels). */
EL_DEF el_result el_film_filter_resolve(const el_film_filter *in, el_film_filter *out);
/* The filter's exact value at offset (x, y) from the pixel centre (pbrt's Filter::Evaluate); `f` must be
 * resolved. 0 outside the radius and for NaN offsets. */
EL_DEF float el_film_filter_eval(const el_film_filter *f, float x, float y);

/* >> film */
#define EL_FILM_TABLE_SIZE 16 /* pbrt-v3's filterTableWidth */

typedef struct el_film_options {
  int width, height;     /* full resolution in pixels (pbrt "xresolution", "yresolution"); > 0 */
  float crop[4];         /* pbrt "cropwindow" x0 x1 y0 y1 in [0,1]; all zero = the whole image */
  el_film_filter filter; /* all zero = pbrt's default box filter */
  int exact_filter;      /* 0: pbrt's 16x16 precomputed weight table; 1: evaluate the filter exactly */
  float max_component;   /* > 0: scale a sample down so its largest component is at most this
                            (pbrt-v4 "maxcomponentvalue"); 0 = off */
  float scale;           /* pbrt "scale": output multiplier; 0 = 1 */
  int xyz_round_trip;    /* 1: pass output through pbrt-v3's RGBToXYZ then XYZToRGB (matches pbrt) */
  int nonnegative_filter; /* 1: a negative filter weight (the lobes of mitchell and sinc) counts as 0, so
                             every pixel is a weighted mean of its samples and stays within their range;
                             0 (pbrt): at low spp such filters overshoot without bound (NOTES) */
} el_film_options;

/* Counters. `samples` counts accepted add_sample calls; rejected ones are counted by reason (a sample
 * with several faults counts once, in the first matching class: nan, then inf, then negative). */
typedef struct el_film_stats {
  unsigned long long samples;           /* accepted samples */
  unsigned long long rejected_nan;      /* NaN in the position, a component, or the weight */
  unsigned long long rejected_inf;      /* an infinite position, component or weight */
  unsigned long long rejected_negative; /* a negative component or weight */
  unsigned long long clamped;           /* accepted samples scaled down by max_component */
  unsigned long long splats;            /* accepted splats (inside the film) */
  unsigned long long splats_rejected;   /* NaN / Inf / negative splats */
  unsigned long long splats_outside;    /* splats outside the film, or outside a tile's bounds */
} el_film_stats;

/* The film. Caller-owned; fields are readable, change them only through the functions. */
typedef struct el_film {
  int full_width, full_height; /* the full resolution */
  int x0, y0, x1, y1;          /* cropped pixel bounds [x0,x1) x [y0,y1) in full-resolution raster space */
  int width, height;           /* x1 - x0, y1 - y0: the size of every output image */
  el_film_filter filter;       /* resolved: no zero defaults left */
  float inv_radius[2];
  int exact_filter, xyz_round_trip;
  int nonnegative_filter;      /* el_film_options.nonnegative_filter */
  float max_component, scale;
  float table[EL_FILM_TABLE_SIZE * EL_FILM_TABLE_SIZE]; /* pbrt's filterTable, row = y */
  double *pixels;              /* width*height*4: weighted r, g, b sums and the filter weight sum */
  double *splats;              /* width*height*3, NULL until the first splat */
  el_film_stats stats;
} el_film;

/* A tile: a private accumulation buffer over a pixel rectangle. One thread per tile, no locks. */
typedef struct el_film_tile {
  const el_film *film;
  int x0, y0, x1, y1; /* pixel bounds it accumulates: the sample region grown by the filter radius,
                         clipped to the film's cropped bounds (pbrt's GetFilmTile); may be empty */
  double *pixels;     /* (x1-x0)*(y1-y0)*4 */
  size_t capacity;    /* doubles allocated in pixels */
  double *splats;     /* (x1-x0)*(y1-y0)*3, NULL until the first tile splat */
  size_t splat_capacity;
  el_film_stats stats;
} el_film_tile;

/* Creates the film: EL_ERROR_INVALID_ARGUMENT (NULL, size <= 0, bad filter, NaN/negative option),
 * EL_ERROR_EMPTY (the crop window covers no pixel), EL_ERROR_SIZE_OVERFLOW, EL_ERROR_OUT_OF_MEMORY.
 * `opt` may be NULL only to be rejected. On failure *f is zeroed (el_film_free on it is safe). */
EL_DEF el_result el_film_init(el_film *f, const el_film_options *opt);
EL_DEF void el_film_free(el_film *f);   /* safe on a zeroed film */
EL_DEF void el_film_clear(el_film *f);  /* zero all sums, splats and counters */

/* pbrt's GetSampleBounds: the pixel rectangle [b[0],b[2]) x [b[1],b[3]) a renderer must sample so that
 * every film pixel gets its full filter support (the cropped bounds grown by the radius). */
EL_DEF void el_film_sample_bounds(const el_film *f, int b[4]);

/* A tile for samples taken in pixels [x0,x1) x [y0,y1) (continuous raster positions in [x0,x1) x
 * [y0,y1)). Contributions outside the tile's own bounds are dropped (as pbrt's FilmTile), so give each
 * sample to the tile whose sample region holds it. _reset reuses the tile's memory for a new region and
 * zeroes it. Errors: EL_ERROR_INVALID_ARGUMENT (NULL, x1 < x0, y1 < y0), SIZE_OVERFLOW, OUT_OF_MEMORY. */
EL_DEF el_result el_film_tile_init(const el_film *f, el_film_tile *t, int x0, int y0, int x1, int y1);
EL_DEF el_result el_film_tile_reset(el_film_tile *t, int x0, int y0, int x1, int y1);
EL_DEF void el_film_tile_free(el_film_tile *t); /* safe on a zeroed tile */

/* Adds one sample at continuous raster position (px, py) (pixel (x, y) has its centre at (x + 0.5,
 * y + 0.5); y grows downwards, row 0 is the top): every pixel within the filter radius gets
 * rgb * weight * filter and filter (pbrt's contribSum / filterWeightSum; `weight` is pbrt's ray weight,
 * it does not enter the weight sum). Rejected (and counted) when a position, component or weight is
 * NaN or infinite, or a component or the weight is negative. */
EL_DEF void el_film_tile_add_sample(el_film_tile *t, float px, float py, const float rgb[3], float weight);
/* n samples at once, the same as n el_film_tile_add_sample calls in order (the same sums and counters,
 * bit for bit): positions px[i], py[i], radiance rgb[3i .. 3i+2], weight[i] (weight NULL: all 1). With
 * the box filter of radius 0.5 and no max_component, one loop without a call per sample (NOTES). */
EL_DEF void el_film_tile_add_samples(el_film_tile *t, int n, const float *px, const float *py, const float *rgb, const float *weight);
/* A splat into the tile's own splat buffer (allocated on the tile's first splat). Splats outside the
 * tile's bounds are counted in splats_outside: give a light-tracing thread a tile over the whole film.
 * Returns EL_ERROR_OUT_OF_MEMORY only when the first allocation fails (the splat is then dropped). */
EL_DEF el_result el_film_tile_add_splat(el_film_tile *t, float px, float py, const float rgb[3]);
/* Adds the tile's sums, splats and counters into the film. Not thread-safe: merges into one film must
 * be serialised by the caller (a mutex around this call); adding to different tiles needs no lock.
 * Returns EL_ERROR_OUT_OF_MEMORY only if the film's splat buffer has to be allocated and cannot be. */
EL_DEF el_result el_film_merge_tile(el_film *f, const el_film_tile *t);

/* Single-threaded conveniences: the same as a tile over the whole film. */
EL_DEF void el_film_add_sample(el_film *f, float px, float py, const float rgb[3], float weight);
/* A splat (pbrt's AddSplat): added unweighted to pixel floor(px), floor(py). The splat buffer is
 * allocated on the first splat (EL_ERROR_OUT_OF_MEMORY if that fails; the splat is dropped). */
EL_DEF el_result el_film_add_splat(el_film *f, float px, float py, const float rgb[3]);

/* Linear RGB, film.width * film.height * 3 floats, row 0 at the top (pbrt's WriteImage before
 * encoding): max(0, sum / weight_sum) (0 when the weight sum is 0) + splat_scale * splat, times
 * scale. Every value is finite and >= 0 (a NaN or negative splat_scale counts as 0). pbrt's BDPT passes
 * splat_scale = 1 / samples per pixel. */
EL_DEF void el_film_get_rgb(const el_film *f, float splat_scale, float *out_rgb);

EL_DEF unsigned long long el_film_rejected_samples(const el_film *f); /* nan + inf + negative */
EL_DEF size_t el_film_bytes(const el_film *f);                         /* heap bytes held */

/* >> colour: pbrt-v3's RGB <-> XYZ matrices (src/core/spectrum.h) */
static inline void el_film_rgb_to_xyz(const float rgb[3], float xyz[3]) {
  xyz[0] = 0.412453f * rgb[0] + 0.357580f * rgb[1] + 0.180423f * rgb[2];
  xyz[1] = 0.212671f * rgb[0] + 0.715160f * rgb[1] + 0.072169f * rgb[2];
  xyz[2] = 0.019334f * rgb[0] + 0.119193f * rgb[1] + 0.950227f * rgb[2];
}
static inline void el_film_xyz_to_rgb(const float xyz[3], float rgb[3]) {
  rgb[0] = 3.240479f * xyz[0] - 1.537150f * xyz[1] - 0.498535f * xyz[2];
  rgb[1] = -0.969256f * xyz[0] + 1.875991f * xyz[1] + 0.041556f * xyz[2];
  rgb[2] = 0.055648f * xyz[0] - 0.204043f * xyz[1] + 1.057311f * xyz[2];
}

/* >> sRGB encoding (pbrt-v3 GammaCorrect and TO_BYTE, src/core/imageio.cpp) */
/* The exact sRGB curve: 12.92 x for x <= 0.0031308, 1.055 x^(1/2.4) - 0.055 above. Not clamped above
 * (2.0 encodes to about 1.353); returns 0 for NaN and for x <= 0 (the linear segment ends at 0). */
static inline float el_film_srgb_encode(float linear) {
  if (!(linear > 0.0f)) return 0.0f; /* NaN and negatives */
  if (linear <= 0.0031308f) return 12.92f * linear;
  return 1.055f * (float)pow((double)linear, 1.0 / 2.4) - 0.055f;
}
/* The inverse curve: x / 12.92 for x <= 0.04045, ((x + 0.055) / 1.055)^2.4 above; 0 for NaN and x <= 0. */
static inline float el_film_srgb_decode(float encoded) {
  if (!(encoded > 0.0f)) return 0.0f;
  if (encoded <= 0.04045f) return encoded * (1.0f / 12.92f);
  return (float)pow(((double)encoded + 0.055) / 1.055, 2.4);
}
/* pbrt's TO_BYTE: (uint8_t)clamp(255 * encode(v) + 0.5, 0, 255), i.e. round to nearest; NaN gives 0,
 * +Inf gives 255. */
static inline unsigned char el_film_srgb_to_byte(float linear) {
  float v = 255.0f * el_film_srgb_encode(linear) + 0.5f;
  if (!(v > 0.0f)) return 0;
  if (v >= 255.0f) return 255;
  return (unsigned char)v;
}

/* >> tone mapping */
typedef enum el_film_tonemap {
  EL_FILM_TONEMAP_CLAMP = 0,    /* pbrt: values above 1 clip (per channel) */
  EL_FILM_TONEMAP_EXPONENTIAL,  /* the tutorial's HDRtoLDR: 1 - exp(-k x) per channel */
  EL_FILM_TONEMAP_REINHARD,     /* x / (1 + x) per channel (Reinhard et al. 2002, simple form) */
  EL_FILM_TONEMAP_ACES          /* Narkowicz's fit of the ACES RRT+ODT: x(2.51x+0.03) / (x(2.43x+0.59)+0.14) */
} el_film_tonemap;

/* All zero = pbrt's output: no exposure change, clamp, no dithering. */
typedef struct el_film_output_options {
  float exposure;     /* in stops: linear values are multiplied by 2^exposure before the curve */
  el_film_tonemap tonemap;
  float exp_k;        /* k of the exponential curve; 0 means 1 */
  int dither;         /* 1: add triangular (TPDF) noise of +-1 code value before rounding; codes 0 and
                         255 stay exact so black and clipped white are not speckled */
  unsigned seed;      /* dither pattern seed (deterministic per pixel, channel and seed) */
} el_film_output_options;

/* The curve alone: maps a linear value x >= 0 to [0, 1] (clamp: to [0, x] clipped at 1). NaN and
 * negative x give 0, +Inf gives 1. `k` is used by the exponential curve only (<= 0 or NaN: 1). */
static inline float el_film_tonemap_eval(el_film_tonemap t, float x, float k) {
  float y;
  if (!(x > 0.0f)) return 0.0f;
  switch (t) {
  case EL_FILM_TONEMAP_EXPONENTIAL:
    if (!(k > 0.0f)) k = 1.0f;
    y = 1.0f - (float)exp(-(double)k * (double)x);
    break;
  case EL_FILM_TONEMAP_REINHARD:
    y = x > 1e30f ? 1.0f : x / (1.0f + x);
    break;
  case EL_FILM_TONEMAP_ACES:
    y = x > 1e15f ? 2.51f / 2.43f : (x * (2.51f * x + 0.03f)) / (x * (2.43f * x + 0.59f) + 0.14f);
    break;
  case EL_FILM_TONEMAP_CLAMP:
  default:
    y = x;
    break;
  }
  return y < 1.0f ? y : 1.0f;
}

/* Linear RGB (width*height*3 floats) to 8-bit sRGB (width*height*3 bytes): exposure, the curve, the
 * exact sRGB encoding, round to nearest (optionally dithered). Without dithering the code is found by
 * comparing the curve's output with the 255 linear thresholds between codes (computed in double per
 * call): the correctly rounded code, with no pow per value; el_film_srgb_to_byte (pbrt's float formula)
 * agrees except for values within float rounding of a threshold (tests/test_film.c counts them). `o`
 * NULL = all-zero options. NaN and negative inputs give 0 and +Inf gives 255, at every exposure (2^exposure
 * may round to 0 or overflow; it scales finite values only). EL_ERROR_INVALID_ARGUMENT for NULL buffers,
 * a size <= 0, an unknown tone mapper or an exposure that is NaN or infinite; EL_ERROR_SIZE_OVERFLOW for
 * absurd sizes. */
EL_DEF el_result el_film_to_srgb8(const float *rgb, int width, int height, const el_film_output_options *o,
                                  unsigned char *out);

#ifdef __cplusplus
}
#endif
#endif /* EL_FILM_H */

/* ====================================================================================================
 * NOTES (the reasons behind the API; a user of the functions above needs none of this)
 *
 * Threads: each thread owns an el_film_tile (el_film_tile_init / _reset for the region it samples),
 * adds samples to it without locks, and hands it to el_film_merge_tile under the caller's mutex.
 *
 * What it ports: pbrt-v3's Film / FilmTile (src/core/film.h, film.cpp) and its filters
 * (src/filters/box, triangle, gaussian, mitchell, sinc), the sRGB curve and TO_BYTE of imageio.cpp.
 * Where it departs from pbrt, and why:
 *  - Sums are kept in double (pbrt: float contribSum, float filterWeightSum). With a million samples per
 *    pixel a float sum drops every addend below sum * 2^-24; a double keeps them.
 *  - Pixels are accumulated in linear RGB. pbrt-v3 converts each tile's sums to XYZ on merge and back to
 *    RGB on output; with an RGBSpectrum build that is a linear map M^-1 M, the identity up to the 6-digit
 *    rounding of pbrt's matrices (|M^-1 M - I| is about 1e-6, measured in tests/test_film.c). Set
 *    el_film_options.xyz_round_trip to apply pbrt's two matrices anyway (values then match pbrt's).
 *    Only a spectral renderer (SampledSpectrum) needs XYZ for real; this film takes RGB.
 *  - A sample with a NaN or infinite position, or a NaN, infinite or negative component or weight, is
 *    rejected whole (it adds no filter weight either) and COUNTED by reason (el_film_stats,
 *    el_film_rejected_samples). pbrt-v3's integrators log such radiance and replace it by 0, which still
 *    adds the filter weight and so darkens the pixel; FilmTile::AddSample itself checks nothing, so a
 *    NaN (or an Inf, through Inf - Inf in XYZToRGB) that reaches it makes the pixel's sums NaN, and
 *    WriteImage's std::max(0, NaN) outputs 0: the whole pixel goes black (tests/test_tutorial_film.c).
 *  - The optional clamp is pbrt-v4's maxcomponentvalue (scale the sample so its largest component is at
 *    most the limit), not pbrt-v3's maxsampleluminance.
 *  - Splats land on floor(p), so p in (-1, 0) never doubles onto the edge pixel (pbrt-v3 once truncated
 *    with (Point2i)p; fixed in pbrt-v3 commit 9adaee8). The splat buffer exists only after a splat.
 *  - A pixel with a zero filter-weight sum outputs 0 (plus its splats); every output value is finite,
 *    and NaN never reaches the 8-bit conversion (in pbrt, (uint8_t) of NaN is undefined behaviour).
 *  - Filters with negative lobes (mitchell, and sinc = Lanczos most of all) divide by a weight sum that
 *    can be near 0 or negative when few samples reach a pixel, exactly as pbrt-v3 does. At 1 spp with
 *    samples in [0, 1] (tests/test_film.c, 64x64): Lanczos weight sums from -0.17 to 2.8 and pixels
 *    from -138 to 132, Mitchell 0.24 to 2.2 and -0.09 to 1.37 (issue 24's campaign saw Lanczos sums
 *    from -0.28 to 2.9 and pixels up to 7465); output is max(0, .), so the negative ones turn black. Such filters need many samples per pixel (their
 *    weight sums then approach the filter's integral). Remedies: a filter without negative lobes
 *    (box, triangle, gaussian), or el_film_options.nonnegative_filter = 1, which counts negative weights
 *    as 0: every pixel is then a weighted mean of its samples, within their range (tests/test_film.c),
 *    at the price of most of the sharpening the lobes were for. The renderer's PixelFilter takes it as
 *    "bool nonnegative".
 *  - el_film_tile_add_samples: a renderer that shades samples in batches (examples/render/render_wave.c)
 *    hands them over in one call. With pbrt's default box filter (radius 0.5) a sample off the pixel
 *    edges adds to one pixel with weight 1; the batch does that in a loop of its own (93 instructions a
 *    sample against 169 for a call each: bench/callgrind_parts.sh, the renderer's film part) and gives
 *    every other sample (rejected, on a pixel edge, outside the tile) to the one-sample code.
 *  - Tone mapping beyond pbrt's clamp: exposure in stops, the exponential 1 - exp(-k x) curve, Reinhard,
 *    Narkowicz's fitted ACES curve, and optional dithering of the 8-bit output.
 * ==================================================================================================== */

/* ============================================================================================
 * implementation below; stop reading here if you only need the API
 * ============================================================================================ */
#if defined(EL_IMPLEMENTATION) || defined(EL_FILM_IMPLEMENTATION)
#ifndef EL_FILM_IMPLEMENTATION_DONE
#define EL_FILM_IMPLEMENTATION_DONE

#include <float.h>
#include <limits.h>
#include <string.h>

#ifdef __cplusplus
extern "C" {
#endif

static int el_film__finite(float x) { return x == x && x - x == 0.0f; }

/* >> filter evaluation */
static float el_film__sinc(float x) { /* pbrt-v3 LanczosSincFilter::Sinc */
  x = (float)fabs((double)x);
  if (x < 1e-5f) return 1.0f;
  return (float)(sin(3.14159265358979323846 * (double)x) / (3.14159265358979323846 * (double)x));
}

/* The 1D factor of a (separable) pbrt filter on axis `a`; every pbrt-v3 filter is a product f(x) f(y). */
static float el_film__eval1(const el_film_filter *f, float x, int a) {
  float r = f->radius[a];
  x = (float)fabs((double)x);
  if (!(x <= r)) return 0.0f; /* NaN and outside */
  switch (f->type) {
  case EL_FILM_FILTER_BOX: return 1.0f;
  case EL_FILM_FILTER_TRIANGLE: return r - x > 0.0f ? r - x : 0.0f;
  case EL_FILM_FILTER_GAUSSIAN: {
    float v = (float)exp(-(double)f->gaussian_alpha * (double)x * (double)x) -
              (float)exp(-(double)f->gaussian_alpha * (double)r * (double)r);
    return v > 0.0f ? v : 0.0f;
  }
  case EL_FILM_FILTER_MITCHELL: {
    float B = f->mitchell_b, C = f->mitchell_c;
    float t = (float)fabs(2.0 * (double)x / (double)r); /* <<Mitchell1D>>: x = |2 x / radius| in [0,2] */
    if (t > 1.0f)
      return ((-B - 6 * C) * t * t * t + (6 * B + 30 * C) * t * t + (-12 * B - 48 * C) * t + (8 * B + 24 * C)) *
             (1.0f / 6.0f);
    return ((12 - 9 * B - 6 * C) * t * t * t + (-18 + 12 * B + 6 * C) * t * t + (6 - 2 * B)) * (1.0f / 6.0f);
  }
  case EL_FILM_FILTER_LANCZOS: /* <<WindowedSinc>> */
    return el_film__sinc(x) * el_film__sinc(x / f->lanczos_tau);
  }
  return 0.0f;
}

EL_DEF float el_film_filter_eval(const el_film_filter *f, float x, float y) {
  if (!f) return 0.0f;
  return el_film__eval1(f, x, 0) * el_film__eval1(f, y, 1);
}

static int el_film__bad_param(float v) { return !(v >= 0.0f) || !el_film__finite(v); }

EL_DEF el_result el_film_filter_resolve(const el_film_filter *in, el_film_filter *out) {
  el_film_filter f;
  float defr;
  int a;
  if (!in || !out) return EL_ERROR_INVALID_ARGUMENT;
  f = *in;
  switch (f.type) {
  case EL_FILM_FILTER_BOX: defr = 0.5f; break;
  case EL_FILM_FILTER_TRIANGLE: case EL_FILM_FILTER_GAUSSIAN: case EL_FILM_FILTER_MITCHELL: defr = 2.0f; break;
  case EL_FILM_FILTER_LANCZOS: defr = 4.0f; break;
  default: return EL_ERROR_INVALID_ARGUMENT;
  }
  for (a = 0; a < 2; a++) {
    if (el_film__bad_param(f.radius[a]) || f.radius[a] > 64.0f) return EL_ERROR_INVALID_ARGUMENT;
    if (f.radius[a] == 0.0f) f.radius[a] = defr;
  }
  if (el_film__bad_param(f.gaussian_alpha) || el_film__bad_param(f.lanczos_tau)) return EL_ERROR_INVALID_ARGUMENT;
  if (!el_film__finite(f.mitchell_b) || !el_film__finite(f.mitchell_c)) return EL_ERROR_INVALID_ARGUMENT;
  if (f.gaussian_alpha == 0.0f) f.gaussian_alpha = 2.0f;
  if (f.lanczos_tau == 0.0f) f.lanczos_tau = 3.0f;
  if (f.mitchell_b == 0.0f && f.mitchell_c == 0.0f) f.mitchell_b = f.mitchell_c = 1.0f / 3.0f;
  *out = f;
  return EL_SUCCESS;
}

/* >> film construction */
static void el_film__zero_stats(el_film_stats *s) { memset(s, 0, sizeof *s); }

EL_DEF el_result el_film_init(el_film *f, const el_film_options *opt) {
  float c[4];
  int i, x, y;
  size_t n;
  el_result r;
  if (!f) return EL_ERROR_INVALID_ARGUMENT;
  memset(f, 0, sizeof *f);
  if (!opt || opt->width <= 0 || opt->height <= 0) return EL_ERROR_INVALID_ARGUMENT;
  r = el_film_filter_resolve(&opt->filter, &f->filter);
  if (r != EL_SUCCESS) return r;
  if (el_film__bad_param(opt->max_component) || el_film__bad_param(opt->scale)) return EL_ERROR_INVALID_ARGUMENT;
  /* <<Compute film image bounds>>: pbrt clamps the crop window to [0,1] and sorts each pair */
  for (i = 0; i < 4; i++) {
    if (opt->crop[i] != opt->crop[i]) return EL_ERROR_INVALID_ARGUMENT;
    c[i] = opt->crop[i] < 0.0f ? 0.0f : opt->crop[i] > 1.0f ? 1.0f : opt->crop[i];
  }
  if (c[0] == 0.0f && c[1] == 0.0f && c[2] == 0.0f && c[3] == 0.0f) { c[1] = 1.0f; c[3] = 1.0f; }
  f->full_width = opt->width;
  f->full_height = opt->height;
  f->x0 = (int)ceil((double)opt->width * (c[0] < c[1] ? c[0] : c[1]));
  f->x1 = (int)ceil((double)opt->width * (c[0] < c[1] ? c[1] : c[0]));
  f->y0 = (int)ceil((double)opt->height * (c[2] < c[3] ? c[2] : c[3]));
  f->y1 = (int)ceil((double)opt->height * (c[2] < c[3] ? c[3] : c[2]));
  f->width = f->x1 - f->x0;
  f->height = f->y1 - f->y0;
  if (f->width <= 0 || f->height <= 0) { memset(f, 0, sizeof *f); return EL_ERROR_EMPTY; }
  if ((size_t)f->width > ((size_t)-1) / 4 / sizeof(double) / (size_t)f->height ||
      (double)f->width * (double)f->height * 3.0 > (double)INT_MAX) {
    memset(f, 0, sizeof *f);
    return EL_ERROR_SIZE_OVERFLOW;
  }
  f->inv_radius[0] = 1.0f / f->filter.radius[0];
  f->inv_radius[1] = 1.0f / f->filter.radius[1];
  f->exact_filter = opt->exact_filter != 0;
  f->xyz_round_trip = opt->xyz_round_trip != 0;
  f->nonnegative_filter = opt->nonnegative_filter != 0;
  f->max_component = opt->max_component;
  f->scale = opt->scale == 0.0f ? 1.0f : opt->scale;
  /* <<Precompute filter weight table>> */
  for (y = 0; y < EL_FILM_TABLE_SIZE; y++)
    for (x = 0; x < EL_FILM_TABLE_SIZE; x++) {
      float w = el_film_filter_eval(&f->filter, ((float)x + 0.5f) * f->filter.radius[0] / EL_FILM_TABLE_SIZE,
                                    ((float)y + 0.5f) * f->filter.radius[1] / EL_FILM_TABLE_SIZE);
      f->table[y * EL_FILM_TABLE_SIZE + x] = f->nonnegative_filter && w < 0.0f ? 0.0f : w;
    }
  n = (size_t)f->width * (size_t)f->height * 4;
  f->pixels = (double *)EL_MALLOC(n * sizeof(double));
  if (!f->pixels) { memset(f, 0, sizeof *f); return EL_ERROR_OUT_OF_MEMORY; }
  memset(f->pixels, 0, n * sizeof(double));
  el_film__zero_stats(&f->stats);
  return EL_SUCCESS;
}

EL_DEF void el_film_free(el_film *f) {
  if (!f) return;
  if (f->pixels) EL_FREE(f->pixels);
  if (f->splats) EL_FREE(f->splats);
  memset(f, 0, sizeof *f);
}

EL_DEF void el_film_clear(el_film *f) {
  if (!f || !f->pixels) return;
  memset(f->pixels, 0, (size_t)f->width * (size_t)f->height * 4 * sizeof(double));
  if (f->splats) memset(f->splats, 0, (size_t)f->width * (size_t)f->height * 3 * sizeof(double));
  el_film__zero_stats(&f->stats);
}

EL_DEF void el_film_sample_bounds(const el_film *f, int b[4]) {
  if (!f || !b) return;
  /* pbrt: Floor(pMin + 0.5 - radius), Ceil(pMax - 0.5 + radius) */
  b[0] = (int)floor(f->x0 + 0.5 - f->filter.radius[0]);
  b[1] = (int)floor(f->y0 + 0.5 - f->filter.radius[1]);
  b[2] = (int)ceil(f->x1 - 0.5 + f->filter.radius[0]);
  b[3] = (int)ceil(f->y1 - 0.5 + f->filter.radius[1]);
}

/* >> tiles */
EL_DEF el_result el_film_tile_reset(el_film_tile *t, int x0, int y0, int x1, int y1) {
  const el_film *f;
  double bx0, by0, bx1, by1;
  size_t n;
  if (!t || !t->film || x1 < x0 || y1 < y0) return EL_ERROR_INVALID_ARGUMENT;
  f = t->film;
  /* <<Bound image pixels that samples in sampleBounds contribute to>> */
  bx0 = ceil((double)x0 - 0.5 - f->filter.radius[0]);
  by0 = ceil((double)y0 - 0.5 - f->filter.radius[1]);
  bx1 = floor((double)x1 - 0.5 + f->filter.radius[0]) + 1.0;
  by1 = floor((double)y1 - 0.5 + f->filter.radius[1]) + 1.0;
  if (bx0 < f->x0) bx0 = f->x0;
  if (by0 < f->y0) by0 = f->y0;
  if (bx1 > f->x1) bx1 = f->x1;
  if (by1 > f->y1) by1 = f->y1;
  if (bx1 < bx0) bx1 = bx0;
  if (by1 < by0) by1 = by0;
  t->x0 = (int)bx0; t->y0 = (int)by0; t->x1 = (int)bx1; t->y1 = (int)by1;
  n = (size_t)(t->x1 - t->x0) * (size_t)(t->y1 - t->y0) * 4; /* at most the film's size: no overflow */
  if (n > t->capacity) {
    double *p = (double *)EL_REALLOC(t->pixels, n * sizeof(double));
    if (!p) return EL_ERROR_OUT_OF_MEMORY;
    t->pixels = p;
    t->capacity = n;
  }
  if (n) memset(t->pixels, 0, n * sizeof(double));
  if (t->splats) memset(t->splats, 0, t->splat_capacity * sizeof(double));
  el_film__zero_stats(&t->stats);
  return EL_SUCCESS;
}

EL_DEF el_result el_film_tile_init(const el_film *f, el_film_tile *t, int x0, int y0, int x1, int y1) {
  el_result r;
  if (!t) return EL_ERROR_INVALID_ARGUMENT;
  memset(t, 0, sizeof *t);
  if (!f || !f->pixels) return EL_ERROR_INVALID_ARGUMENT;
  t->film = f;
  r = el_film_tile_reset(t, x0, y0, x1, y1);
  if (r != EL_SUCCESS) el_film_tile_free(t);
  return r;
}

EL_DEF void el_film_tile_free(el_film_tile *t) {
  if (!t) return;
  if (t->pixels) EL_FREE(t->pixels);
  if (t->splats) EL_FREE(t->splats);
  memset(t, 0, sizeof *t);
}

/* Checks a sample; returns 1 to accept, else counts the reason in s and returns 0. */
static int el_film__classify(el_film_stats *s, float px, float py, const float *rgb, float w) {
  float v[6];
  int i;
  if (!rgb) { s->rejected_nan++; return 0; }
  v[0] = px; v[1] = py; v[2] = rgb[0]; v[3] = rgb[1]; v[4] = rgb[2]; v[5] = w;
  for (i = 0; i < 6; i++)
    if (v[i] != v[i]) { s->rejected_nan++; return 0; }
  for (i = 0; i < 6; i++)
    if (v[i] - v[i] != 0.0f) { s->rejected_inf++; return 0; }
  for (i = 2; i < 6; i++)
    if (v[i] < 0.0f) { s->rejected_negative++; return 0; }
  return 1;
}

/* fast path, inlined: finite positions (x - x is 0 only for finite x), components and weight in
   [0, FLT_MAX] (every comparison with NaN is false); the rare rest is classified and counted */
static unsigned el_film__bits(float v) { /* the IEEE-754 pattern (memcpy: no aliasing UB) */
  unsigned u;
  memcpy(&u, &v, sizeof u);
  return u;
}
static int el_film__accept(el_film_stats *s, float px, float py, const float *rgb, float w) {
  /* as unsigned patterns, finite non-negative floats are exactly those below 0x7f800000 (+Inf); a
     finite position of either sign has its magnitude bits below it. -0.0 takes the slow path. */
  if (rgb) {
    /* all six tests, combined with & rather than && (one branch, not six); the patterns are read first,
       so that no operand of & has a call in it (clang's -Wbitwise-instead-of-logical) */
    unsigned bx = el_film__bits(px) & 0x7fffffffu, by = el_film__bits(py) & 0x7fffffffu;
    unsigned b0 = el_film__bits(rgb[0]), b1 = el_film__bits(rgb[1]), b2 = el_film__bits(rgb[2]), bw = el_film__bits(w);
    if ((bx < 0x7f800000u) & (by < 0x7f800000u) & (b0 < 0x7f800000u) & (b1 < 0x7f800000u) & (b2 < 0x7f800000u) &
        (bw < 0x7f800000u))
      return 1;
  }
  return el_film__classify(s, px, py, rgb, w);
}

/* floor for |x| well inside the int range (callers clip first): no libm call */
static int el_film__floori(double x) {
  int i = (int)x;
  return i - (x < (double)i);
}

/* <<FilmTile::AddSample>> into the buffer `buf` over pixel bounds [bx0,bx1) x [by0,by1). */
static void el_film__add(const el_film *f, el_film_stats *s, double *buf, int bx0, int by0, int bx1,
                         int by1, float px, float py, const float *rgb, float w) {
  float L[3];
  double pdx, pdy, rx = f->filter.radius[0], ry = f->filter.radius[1];
  int x0, y0, x1, y1, x, y, bw = bx1 - bx0, i;
  float wx[2 * 64 + 2], wy[2 * 64 + 2];
  int ix[2 * 64 + 2], iy[2 * 64 + 2];
  if (!el_film__accept(s, px, py, rgb, w)) return;
  s->samples++;
  L[0] = rgb[0] * w; L[1] = rgb[1] * w; L[2] = rgb[2] * w;
  if (f->max_component > 0.0f) { /* pbrt-v4 maxcomponentvalue, on the radiance before the ray weight */
    float m = rgb[0] > rgb[1] ? rgb[0] : rgb[1];
    m = m > rgb[2] ? m : rgb[2];
    if (m > f->max_component) {
      float k = f->max_component / m;
      L[0] = rgb[0] * k * w; L[1] = rgb[1] * k * w; L[2] = rgb[2] * k * w;
      s->clamped++;
    }
  }
  /* Box filter of radius 0.5 (pbrt's default film filter): the support [ceil(px - 1), floor(px)] is the
   * single pixel floor(px), weight 1, unless px or py is an integer (then the general path below adds
   * to both neighbours, as pbrt does). The same sums as the general path, bit for bit (w = 1 times L). */
  if (f->filter.type == EL_FILM_FILTER_BOX && rx == 0.5 && ry == 0.5 && px >= (float)bx0 && px < (float)bx1 &&
      py >= (float)by0 && py < (float)by1) {
    int ixp = (int)px, iyp = (int)py; /* px, py >= bx0, by0 >= 0 here: truncation is floor */
    if ((float)ixp != px && (float)iyp != py && bx0 >= 0 && by0 >= 0) {
      double *p = buf + ((size_t)(iyp - by0) * (size_t)bw + (size_t)(ixp - bx0)) * 4;
      p[0] += (double)L[0]; p[1] += (double)L[1]; p[2] += (double)L[2]; p[3] += 1.0;
      return;
    }
  }
  /* <<Compute sample's raster bounds>> (in double, clipped before converting to int) */
  pdx = (double)px - 0.5;
  pdy = (double)py - 0.5;
  if (pdx + rx < bx0 - 1.0 || pdx - rx > bx1 || pdy + ry < by0 - 1.0 || pdy - ry > by1) return;
  x0 = -el_film__floori(rx - pdx); /* ceil(pdx - rx) */
  y0 = -el_film__floori(ry - pdy);
  x1 = el_film__floori(pdx + rx) + 1;
  y1 = el_film__floori(pdy + ry) + 1;
  if (x0 < bx0) x0 = bx0;
  if (y0 < by0) y0 = by0;
  if (x1 > bx1) x1 = bx1;
  if (y1 > by1) y1 = by1;
  if (x1 <= x0 || y1 <= y0) return;
  if (f->exact_filter) {
    for (x = x0; x < x1; x++) wx[x - x0] = el_film__eval1(&f->filter, (float)(x - pdx), 0);
    for (y = y0; y < y1; y++) wy[y - y0] = el_film__eval1(&f->filter, (float)(y - pdy), 1);
  } else {
    /* <<Precompute x and y filter table offsets>> */
    for (x = x0; x < x1; x++) {
      float fx = (float)fabs((x - pdx) * f->inv_radius[0] * EL_FILM_TABLE_SIZE);
      int k = (int)fx;
      ix[x - x0] = k < EL_FILM_TABLE_SIZE - 1 ? k : EL_FILM_TABLE_SIZE - 1;
    }
    for (y = y0; y < y1; y++) {
      float fy = (float)fabs((y - pdy) * f->inv_radius[1] * EL_FILM_TABLE_SIZE);
      int k = (int)fy;
      iy[y - y0] = k < EL_FILM_TABLE_SIZE - 1 ? k : EL_FILM_TABLE_SIZE - 1;
    }
  }
  /* <<Loop over filter support and add sample to pixel arrays>> */
  {
    double l0 = L[0], l1 = L[1], l2 = L[2];
    size_t stride = (size_t)bw * 4;
    double *row = buf + ((size_t)(y0 - by0) * (size_t)bw + (size_t)(x0 - bx0)) * 4;
    int nx = x1 - x0;
    for (y = y0; y < y1; y++, row += stride) {
      double *p = row;
      if (!f->exact_filter) {
        const float *trow = f->table + iy[y - y0] * EL_FILM_TABLE_SIZE;
        for (i = 0; i < nx; i++, p += 4) {
          double fw = trow[ix[i]];
          p[0] += l0 * fw; p[1] += l1 * fw; p[2] += l2 * fw; p[3] += fw;
        }
      } else {
        double fy = wy[y - y0], lo = f->nonnegative_filter ? 0.0 : -DBL_MAX; /* the 2D weight clamped */
        for (i = 0; i < nx; i++, p += 4) {
          double fw = (double)wx[i] * fy;
          fw = fw > lo ? fw : lo;
          p[0] += l0 * fw; p[1] += l1 * fw; p[2] += l2 * fw; p[3] += fw;
        }
      }
    }
  }
}

EL_DEF void el_film_tile_add_sample(el_film_tile *t, float px, float py, const float rgb[3], float weight) {
  if (!t || !t->film) return;
  el_film__add(t->film, &t->stats, t->pixels, t->x0, t->y0, t->x1, t->y1, px, py, rgb, weight);
}

EL_DEF void el_film_tile_add_samples(el_film_tile *t, int n, const float *px, const float *py, const float *rgb, const float *weight) {
  const el_film *f;
  int i = 0;
  if (!t || !t->film || n <= 0 || !px || !py || !rgb) return;
  f = t->film;
  /* el_film__add's box fast path for the run: the accept test's all-finite-and-non-negative case, the
   * sample strictly inside a pixel of the tile (the tile's bounds non-negative), no clamp */
  if (f->filter.type == EL_FILM_FILTER_BOX && f->filter.radius[0] == 0.5f && f->filter.radius[1] == 0.5f && !(f->max_component > 0.0f) &&
      t->x0 >= 0 && t->y0 >= 0) {
    const float bx0 = (float)t->x0, by0 = (float)t->y0, bx1 = (float)t->x1, by1 = (float)t->y1;
    const size_t bw = (size_t)(t->x1 - t->x0);
    const int x0 = t->x0, y0 = t->y0;
    double *buf = t->pixels;
    unsigned long long accepted = 0; /* (kept in a register: added to the counter before any slow call) */
    for (; i < n; i++) {
      float x = px[i], y = py[i], w = weight ? weight[i] : 1.0f;
      const float *c = rgb + 3 * (size_t)i;
      unsigned bx = el_film__bits(x) & 0x7fffffffu, by = el_film__bits(y) & 0x7fffffffu;
      unsigned b0 = el_film__bits(c[0]), b1 = el_film__bits(c[1]), b2 = el_film__bits(c[2]), bwt = el_film__bits(w);
      if ((bx < 0x7f800000u) & (by < 0x7f800000u) & (b0 < 0x7f800000u) & (b1 < 0x7f800000u) & (b2 < 0x7f800000u) & (bwt < 0x7f800000u) &
          (x >= bx0) & (x < bx1) & (y >= by0) & (y < by1)) {
        int ix = (int)x, iy = (int)y;
        if ((float)ix != x && (float)iy != y) {
          double *p = buf + ((size_t)(iy - y0) * bw + (size_t)(ix - x0)) * 4;
          accepted++;
          p[0] += (double)(c[0] * w); p[1] += (double)(c[1] * w); p[2] += (double)(c[2] * w); p[3] += 1.0;
          continue;
        }
      }
      t->stats.samples += accepted; accepted = 0;
      el_film__add(f, &t->stats, t->pixels, t->x0, t->y0, t->x1, t->y1, x, y, c, w);
    }
    t->stats.samples += accepted;
    return;
  }
  for (; i < n; i++)
    el_film__add(f, &t->stats, t->pixels, t->x0, t->y0, t->x1, t->y1, px[i], py[i], rgb + 3 * (size_t)i, weight ? weight[i] : 1.0f);
}

EL_DEF void el_film_add_sample(el_film *f, float px, float py, const float rgb[3], float weight) {
  if (!f || !f->pixels) return;
  el_film__add(f, &f->stats, f->pixels, f->x0, f->y0, f->x1, f->y1, px, py, rgb, weight);
}

/* <<Film::AddSplat>>: returns the buffer index of the pixel, or -1 when rejected or outside. */
static long el_film__splat_index(const el_film *f, el_film_stats *s, int bx0, int by0, int bx1, int by1,
                                 float px, float py, const float *rgb, float *L) {
  double fx, fy;
  float m;
  el_film_stats scratch;
  memset(&scratch, 0, sizeof scratch);
  if (!el_film__accept(&scratch, px, py, rgb, 1.0f)) { s->splats_rejected++; return -1; }
  fx = floor((double)px); /* floor, not truncation: (-1, 0) is outside, not pixel 0 (pbrt 9adaee8) */
  fy = floor((double)py);
  if (fx < bx0 || fx >= bx1 || fy < by0 || fy >= by1) { s->splats_outside++; return -1; }
  L[0] = rgb[0]; L[1] = rgb[1]; L[2] = rgb[2];
  m = L[0] > L[1] ? L[0] : L[1];
  m = m > L[2] ? m : L[2];
  if (f->max_component > 0.0f && m > f->max_component) {
    float k = f->max_component / m;
    L[0] *= k; L[1] *= k; L[2] *= k;
    s->clamped++;
  }
  s->splats++;
  return ((long)(fy - by0) * (long)(bx1 - bx0) + (long)(fx - bx0)) * 3;
}

EL_DEF el_result el_film_add_splat(el_film *f, float px, float py, const float rgb[3]) {
  float L[3];
  long k;
  if (!f || !f->pixels) return EL_ERROR_INVALID_ARGUMENT;
  k = el_film__splat_index(f, &f->stats, f->x0, f->y0, f->x1, f->y1, px, py, rgb, L);
  if (k < 0) return EL_SUCCESS;
  if (!f->splats) {
    size_t n = (size_t)f->width * (size_t)f->height * 3;
    f->splats = (double *)EL_MALLOC(n * sizeof(double));
    if (!f->splats) { f->stats.splats--; return EL_ERROR_OUT_OF_MEMORY; }
    memset(f->splats, 0, n * sizeof(double));
  }
  f->splats[k + 0] += L[0];
  f->splats[k + 1] += L[1];
  f->splats[k + 2] += L[2];
  return EL_SUCCESS;
}

EL_DEF el_result el_film_tile_add_splat(el_film_tile *t, float px, float py, const float rgb[3]) {
  float L[3];
  long k;
  if (!t || !t->film) return EL_ERROR_INVALID_ARGUMENT;
  k = el_film__splat_index(t->film, &t->stats, t->x0, t->y0, t->x1, t->y1, px, py, rgb, L);
  if (k < 0) return EL_SUCCESS;
  if (!t->splats || t->splat_capacity < (size_t)(t->x1 - t->x0) * (size_t)(t->y1 - t->y0) * 3) {
    size_t n = (size_t)(t->x1 - t->x0) * (size_t)(t->y1 - t->y0) * 3;
    double *p = (double *)EL_REALLOC(t->splats, n * sizeof(double));
    if (!p) { t->stats.splats--; return EL_ERROR_OUT_OF_MEMORY; }
    t->splats = p;
    t->splat_capacity = n;
    memset(t->splats, 0, n * sizeof(double));
  }
  t->splats[k + 0] += L[0];
  t->splats[k + 1] += L[1];
  t->splats[k + 2] += L[2];
  return EL_SUCCESS;
}

static void el_film__stats_add(el_film_stats *d, const el_film_stats *s) {
  d->samples += s->samples;
  d->rejected_nan += s->rejected_nan;
  d->rejected_inf += s->rejected_inf;
  d->rejected_negative += s->rejected_negative;
  d->clamped += s->clamped;
  d->splats += s->splats;
  d->splats_rejected += s->splats_rejected;
  d->splats_outside += s->splats_outside;
}

EL_DEF el_result el_film_merge_tile(el_film *f, const el_film_tile *t) {
  int x, y, tw;
  if (!f || !t || !f->pixels || t->film != f) return EL_ERROR_INVALID_ARGUMENT;
  tw = t->x1 - t->x0;
  /* <<Merge pixel into Film::pixels>> */
  for (y = t->y0; y < t->y1; y++) {
    const double *src = t->pixels + (size_t)(y - t->y0) * (size_t)tw * 4;
    double *dst = f->pixels + ((size_t)(y - f->y0) * (size_t)f->width + (size_t)(t->x0 - f->x0)) * 4;
    for (x = 0; x < tw * 4; x++) dst[x] += src[x];
  }
  if (t->splats && t->stats.splats) { /* a tile that never splatted since its reset adds nothing */
    if (!f->splats) {
      size_t n = (size_t)f->width * (size_t)f->height * 3;
      f->splats = (double *)EL_MALLOC(n * sizeof(double));
      if (!f->splats) return EL_ERROR_OUT_OF_MEMORY;
      memset(f->splats, 0, n * sizeof(double));
    }
    for (y = t->y0; y < t->y1; y++) {
      const double *src = t->splats + (size_t)(y - t->y0) * (size_t)tw * 3;
      double *dst = f->splats + ((size_t)(y - f->y0) * (size_t)f->width + (size_t)(t->x0 - f->x0)) * 3;
      for (x = 0; x < tw * 3; x++) dst[x] += src[x];
    }
  }
  el_film__stats_add(&f->stats, &t->stats);
  return EL_SUCCESS;
}

/* >> output */
static float el_film__finite_clamp(double v) {
  if (!(v > 0.0)) return 0.0f; /* NaN, negatives */
  if (v > FLT_MAX) return FLT_MAX;
  return (float)v;
}

EL_DEF void el_film_get_rgb(const el_film *f, float splat_scale, float *out) {
  size_t i, n;
  double ss = splat_scale > 0.0f && el_film__finite(splat_scale) ? splat_scale : 0.0;
  if (!f || !f->pixels || !out) return;
  n = (size_t)f->width * (size_t)f->height;
  for (i = 0; i < n; i++) {
    const double *p = f->pixels + i * 4;
    double c[3];
    int k;
    /* <<Normalize pixel with weight sum>>: a zero weight sum gives 0; the sign test keeps pbrt's
       max(0, .) for negative-lobe filters */
    for (k = 0; k < 3; k++) {
      double v = p[3] != 0.0 ? p[k] / p[3] : 0.0;
      c[k] = v > 0.0 ? v : 0.0;
    }
    /* <<Add splat value at pixel>> */
    if (f->splats)
      for (k = 0; k < 3; k++) c[k] += ss * f->splats[i * 3 + (size_t)k];
    if (f->xyz_round_trip) { /* pbrt-v3: ToXYZ on merge, XYZToRGB on output */
      float rgb[3], xyz[3];
      rgb[0] = el_film__finite_clamp(c[0]); rgb[1] = el_film__finite_clamp(c[1]); rgb[2] = el_film__finite_clamp(c[2]);
      el_film_rgb_to_xyz(rgb, xyz);
      el_film_xyz_to_rgb(xyz, rgb);
      c[0] = rgb[0]; c[1] = rgb[1]; c[2] = rgb[2];
    }
    /* <<Scale pixel value by scale>> */
    for (k = 0; k < 3; k++) out[i * 3 + (size_t)k] = el_film__finite_clamp(c[k] * f->scale);
  }
}

EL_DEF unsigned long long el_film_rejected_samples(const el_film *f) {
  if (!f) return 0;
  return f->stats.rejected_nan + f->stats.rejected_inf + f->stats.rejected_negative;
}

EL_DEF size_t el_film_bytes(const el_film *f) {
  size_t n;
  if (!f || !f->pixels) return 0;
  n = (size_t)f->width * (size_t)f->height;
  return n * 4 * sizeof(double) + (f->splats ? n * 3 * sizeof(double) : 0);
}

/* A small integer hash (lowbias32, Chris Wellons) for the dither pattern. */
static unsigned el_film__hash(unsigned x) {
  x ^= x >> 16; x *= 0x7feb352dU; x ^= x >> 15; x *= 0x846ca68bU; x ^= x >> 16;
  return x;
}

/* The 255 linear thresholds of the 8-bit sRGB codes: code(y) >= k exactly when y >= decode((k - 0.5)/255),
 * each rounded UP to a float so that a float comparison decides as exact arithmetic would. */
static void el_film__srgb_thresholds(float th[256]) {
  int k;
  th[0] = 0.0f; /* unused */
  for (k = 1; k < 256; k++) {
    double e = (k - 0.5) / 255.0, t;
    float tf;
    t = e <= 0.04045 ? e / 12.92 : pow((e + 0.055) / 1.055, 2.4);
    tf = (float)t;
    if ((double)tf < t) tf = nextafterf(tf, 2.0f);
    th[k] = tf;
  }
}

/* the code of y: the largest k with y >= th[k] (0 if none; NaN gives 0), by an 8-step search */
static unsigned char el_film__code(const float th[256], float y) {
  int c = 0, step;
  for (step = 128; step > 0; step >>= 1)
    if (y >= th[c + step]) c += step;
  return (unsigned char)c;
}

EL_DEF el_result el_film_to_srgb8(const float *rgb, int width, int height, const el_film_output_options *o,
                                  unsigned char *out) {
  el_film_output_options d;
  float gain, th[256];
  size_t i, n;
  if (!rgb || !out || width <= 0 || height <= 0) return EL_ERROR_INVALID_ARGUMENT;
  if ((size_t)width > ((size_t)-1) / 3 / sizeof(float) / (size_t)height) return EL_ERROR_SIZE_OVERFLOW;
  if (o) d = *o; else memset(&d, 0, sizeof d);
  if ((int)d.tonemap < (int)EL_FILM_TONEMAP_CLAMP || (int)d.tonemap > (int)EL_FILM_TONEMAP_ACES) return EL_ERROR_INVALID_ARGUMENT;
  if (!el_film__finite(d.exposure)) return EL_ERROR_INVALID_ARGUMENT;
  gain = (float)pow(2.0, (double)d.exposure);
  n = (size_t)width * (size_t)height * 3;
  if (!d.dither) el_film__srgb_thresholds(th);
  for (i = 0; i < n; i++) {
    float x = rgb[i];
    float y;
    if (gain != 1.0f && x <= FLT_MAX) x *= gain; /* +Inf stays +Inf (Inf * 0 would be NaN), NaN stays NaN */
    y = el_film_tonemap_eval(d.tonemap, x, d.exp_k);
    if (!d.dither) {
      out[i] = el_film__code(th, y); /* = round(255 encode(y)) in exact arithmetic, without a pow */
    } else {
      /* encode, then add TPDF noise in code units: (u1 - u2) with u uniform in [0,1) */
      float e = 255.0f * el_film_srgb_encode(y) + 0.5f;
      if (e > 0.5f && e < 254.5f) {
        unsigned h1 = el_film__hash((unsigned)i * 2u + 0x9e3779b9u * (d.seed + 1u));
        unsigned h2 = el_film__hash(h1 ^ 0x85ebca6bu);
        e += (float)((double)(h1 >> 8) * (1.0 / 16777216.0) - (double)(h2 >> 8) * (1.0 / 16777216.0));
      }
      out[i] = (unsigned char)(e <= 0.0f ? 0 : e >= 255.0f ? 255 : (int)e);
    }
  }
  return EL_SUCCESS;
}

#ifdef __cplusplus
}
#endif
#endif /* EL_FILM_IMPLEMENTATION_DONE */
#endif /* EL_IMPLEMENTATION || EL_FILM_IMPLEMENTATION */

/* ------------------------------------------------------------------------------------------------
 * Version history
 *   0.1  first release: pbrt-v3 filters (table or exact), double sums, tiles, splats, counted
 *        rejection, max-component clamp, exact sRGB, exposure, tone mappers, dithering.
 * ------------------------------------------------------------------------------------------------
 * Licence: MIT or public domain (choose one), as stb.
 * MIT: Copyright (c) 2026 the envlight authors. Permission is hereby granted, free of charge, to any
 * person obtaining a copy of this software to deal in it without restriction, subject to including
 * this notice. THE SOFTWARE IS PROVIDED "AS IS", WITHOUT WARRANTY OF ANY KIND.
 * Public domain (Unlicense): anyone may copy, modify, publish, use, compile, sell or distribute this
 * software, in source or binary form, for any purpose, commercial or not, by any means.
 * ------------------------------------------------------------------------------------------------ */
