/* mipmap.h - an image pyramid with pbrt-v3's MIPMap lookups (point, bilinear, trilinear, EWA)
 * envlight v0.1.0 - MIT or public domain
 *
 * DO THIS in exactly one C or C++ file (the first line alone is enough):
 *     #define EL_IMPLEMENTATION   // implements every envlight header included after it
 *     #include "mipmap.h"
 * Every other file includes it without the macro. mipmap.h includes blockedarray.h for its declarations;
 * EL_MIPMAP_IMPLEMENTATION instead implements mipmap.h alone, not blockedarray.h: a module's own macro
 * never implements another module's header.
 *
 * USAGE (C; where C writes `= {0}`, C++ writes `= {}`; tests/test_snippets.c compiles both)
 * >> usage
 *     // given: const float *rgb; float s, t, dsdx, dtdx, dsdy, dtdy;   (rgb: 400 * 235 * 3 floats)
 *     el_mipmap m;
 *     el_mipmap_options opt = {0};             // C++: = {}. All zero: pbrt-v3's Repeat, EWA, anisotropy 8
 *     opt.wrap_v = EL_MIPMAP_WRAP_CLAMP;       // per axis: an environment map's v, say
 *     if (el_mipmap_init(&m, rgb, 400, 235, 3, &opt) != EL_SUCCESS) return 1;  // m.bad_index: NaN texel
 *     float c[3];
 *     el_mipmap_lookup(&m, s, t, 0.15f, c);    // trilinear, filter width 0.15 (1: the whole image)
 *     el_mipmap_lookup_differentials(&m, s, t, dsdx, dtdx, dsdy, dtdy, c);  // EWA
 *     el_mipmap_free(&m);
 * << usage
 * (s, t) = (0, 0) is the corner of the first texel of row 0; upper levels are built on first need.
 *
 * OPTIONS (define before including): EL_MALLOC / EL_REALLOC / EL_FREE (all or none), EL_ASSERT,
 * EL_STATIC, EL_DEF; EL_MIPMAP_YIELD() (what a thread waiting for another thread's lazy build of the
 * upper levels does between polls; default: a CPU pause hint on x86, nothing elsewhere);
 * EL_MIPMAP_NO_ATOMICS (no lazy building: init builds every level).
 *
 * PORTS pbrt-v3's MIPMap<T> (src/core/mipmap.h, book section 10.4): resampleWeights and Lanczos for
 * the power-of-two resampling, the box-filtered pyramid, Texel() with ImageWrap, triangle(), Lookup(st,
 * width) (trilinear) and Lookup(st, dst0, dst1) (EWA with weightLut); from pbrt-v4, per-axis wrap modes
 * and the point and bilinear filters. NOTES after the declarations: accuracy against pbrt, costs,
 * where and why it departs from pbrt, threads, coordinates.
 */
#ifndef EL_MIPMAP_H
#define EL_MIPMAP_H

#include "blockedarray.h"

#ifdef __cplusplus
extern "C" {
#endif

/* >> mipmap declarations */

/* pbrt's ImageWrap, chosen per axis. */
typedef enum el_mipmap_wrap {
  EL_MIPMAP_WRAP_REPEAT = 0, /* the texture tiles the plane (pbrt's default) */
  EL_MIPMAP_WRAP_BLACK = 1,  /* outside the texture everything is 0 */
  EL_MIPMAP_WRAP_CLAMP = 2   /* outside, the nearest border texel */
} el_mipmap_wrap;

/* The filter of el_mipmap_lookup_differentials (pbrt-v3: doTrilinear false = EWA, the default) and of
 * el_mipmap_lookup_filtered. Zero is pbrt's default, EWA. */
typedef enum el_mipmap_filter {
  EL_MIPMAP_FILTER_EWA = 0,       /* elliptically weighted average over the footprint of two differentials */
  EL_MIPMAP_FILTER_TRILINEAR = 1, /* bilinear on two levels, blended (pbrt-v3 doTrilinear = true) */
  EL_MIPMAP_FILTER_BILINEAR = 2,  /* bilinear on the level a trilinear lookup would use first (pbrt-v4) */
  EL_MIPMAP_FILTER_POINT = 3      /* the texel containing (s, t) on that level (pbrt-v4) */
} el_mipmap_filter;

/* All-zero means pbrt-v3's defaults: Repeat in both axes, EWA, max anisotropy 8, non-power-of-two
 * images resampled up to a power of two. */
typedef struct el_mipmap_options {
  el_mipmap_wrap wrap_u, wrap_v;  /* per axis; u = s along rows, v = t down the rows */
  el_mipmap_filter filter; /* for el_mipmap_lookup_differentials */
  float max_anisotropy;    /* EWA eccentricity clamp; 0 -> 8 (pbrt's default); else in [1, 1024] */
  int keep_resolution;     /* 1: level 0 is the input as is, for any size (no power-of-two
                              resampling); upper levels are exact area averages. 0: pbrt's resampling. */
} el_mipmap_options;

#define EL_MIPMAP_MAX_LEVELS 26 /* 1 + log2(2^24) = 25 levels at most, one spare */

/* A MIP map. Fields are readable; change them only through the functions. */
typedef struct el_mipmap {
  int width, height;          /* level-0 resolution (the resampled one when resampling happened) */
  int input_width, input_height; /* what el_mipmap_init was given */
  int channels;               /* floats per texel, 1..4 */
  int levels;                 /* levels of the full pyramid: 1 + floor(log2(max(width, height))) */
  el_mipmap_wrap wrap_u, wrap_v;
  el_mipmap_filter filter;
  float max_anisotropy;       /* after defaulting */
  int resampled;              /* 1 when level 0 was resampled to a power of two */
  int level_width[EL_MIPMAP_MAX_LEVELS], level_height[EL_MIPMAP_MAX_LEVELS];
  float level_size[EL_MIPMAP_MAX_LEVELS][2]; /* (float)level_width, (float)level_height */
  float *level_data[EL_MIPMAP_MAX_LEVELS]; /* row-major, channels interleaved, row 0 first; [0] always,
                                              the others once built (read them via el_mipmap_level_data) */
  size_t level0_bytes;        /* bytes of level_data[0] */
  size_t upper_bytes;         /* bytes of the one allocation holding levels 1.. (0 until built) */
  long build_state;           /* 0 upper levels not built, 1 building, 2 built, 3 out of memory */
  int bad_index;              /* after init: the index y*width+x of the first NaN or infinite input texel when
                                 init failed on one (EL_ERROR_NAN, EL_ERROR_INFINITE), else -1 (capped at
                                 INT_MAX). A failed init zeroes every other field. */
} el_mipmap;

/* Builds level 0 from `pixels` (width*height*channels floats, row-major, row 0 first, channels 1..4),
 * resampling it to a power of two unless it is one or opt->keep_resolution is set. opt may be NULL
 * (pbrt's defaults). Levels 1.. are built on first need. Errors: EL_ERROR_INVALID_ARGUMENT (NULL,
 * size < 1, channels outside 1..4, an unknown enum, max_anisotropy negative or outside [1,1024]),
 * EL_ERROR_NAN / EL_ERROR_INFINITE (a texel or max_anisotropy), EL_ERROR_SIZE_OVERFLOW (a side
 * above 2^24, or bytes overflow), EL_ERROR_OUT_OF_MEMORY. On failure *m is zeroed but for m->bad_index,
 * which names the first NaN or infinite texel (or is -1). */
EL_DEF el_result el_mipmap_init(el_mipmap *m, const float *pixels, int width, int height, int channels,
                                const el_mipmap_options *opt);
/* Releases everything and zeroes *m. Safe on a zeroed struct and on NULL. */
EL_DEF void el_mipmap_free(el_mipmap *m);
/* Builds levels 1.. now, if not built yet. Thread-safe. EL_SUCCESS or EL_ERROR_OUT_OF_MEMORY. */
EL_DEF el_result el_mipmap_build_levels(el_mipmap *m);
/* 1 when levels 1.. exist (built lazily or explicitly, or the map has one level), else 0. */
EL_DEF int el_mipmap_levels_built(const el_mipmap *m);

EL_DEF int el_mipmap_levels(const el_mipmap *m);                  /* total level count */
EL_DEF int el_mipmap_level_width(const el_mipmap *m, int level);  /* 0 for a level out of range */
EL_DEF int el_mipmap_level_height(const el_mipmap *m, int level);
/* Row-major texels of a level (building levels 1.. if needed); NULL for a level out of range or when
 * the build ran out of memory. */
EL_DEF const float *el_mipmap_level_data(const el_mipmap *m, int level);

/* pbrt's Texel(level, s, t): integer texel coordinates, any int, through the wrap modes. A level
 * outside [0, levels) is clamped into it. */
EL_DEF void el_mipmap_texel(const el_mipmap *m, int level, int s, int t, float *out);
/* The texel containing (s, t) (coordinates in [0,1] units) on a level, through the wrap modes. */
EL_DEF void el_mipmap_point(const el_mipmap *m, int level, float s, float t, float *out);
/* pbrt's Bilerp / triangle(level, st): bilinear between the four texels around (s*w - 0.5, t*h - 0.5). */
EL_DEF void el_mipmap_bilerp(const el_mipmap *m, int level, float s, float t, float *out);
/* pbrt-v3's Lookup(st, width): trilinear. level = levels - 1 + log2(max(width, 1e-8)); level < 0:
 * bilinear on level 0; level >= levels - 1: the 1x1 level; else the blend of the bilinear lookups on
 * floor(level) and floor(level) + 1. width is in [0,1] texture units (1 = the whole texture). */
EL_DEF void el_mipmap_lookup(const el_mipmap *m, float s, float t, float width, float *out);
/* pbrt-v4's Lookup(st, width) with an explicit filter: POINT and BILINEAR on level
 * max(0, floor(level)), TRILINEAR as el_mipmap_lookup; EWA (which needs differentials) acts as
 * TRILINEAR here. */
EL_DEF void el_mipmap_lookup_filtered(const el_mipmap *m, el_mipmap_filter filter, float s, float t,
                                      float width, float *out);
/* pbrt-v3's Lookup(st, dst0, dst1) with dst0 = (dsdx, dtdx), dst1 = (dsdy, dtdy), by the map's filter:
 * EWA; TRILINEAR: el_mipmap_lookup(st, max |component|), as pbrt-v3 since its commit aaa552a "Fix
 * trilinear filtering" (the bilinear taps already filter, so 2 max |d| would blur twice); POINT and
 * BILINEAR, pbrt-v4's filters: lookup_filtered with pbrt-v4's width 2 * max |component|. */
EL_DEF void el_mipmap_lookup_differentials(const el_mipmap *m, float s, float t, float dsdx, float dtdx,
                                           float dsdy, float dtdy, float *out);
/* Heap bytes in use: level 0, plus levels 1.. once built. */
EL_DEF size_t el_mipmap_bytes(const el_mipmap *m);
/* << mipmap declarations */

#ifdef __cplusplus
}
#endif
#endif /* EL_MIPMAP_H */

/* ====================================================================================================
 * NOTES (the reasons behind the API; a user of the functions above needs none of this)
 *
 * What it ports, in detail: pbrt-v3's MIPMap<T> (src/core/mipmap.h, book section 10.4): power-of-two
 * resampling with 4-tap Lanczos weights (resampleWeights, tau 2, negative ringing clamped to 0), box
 * filtered levels down to 1x1, Texel() with wrap modes, triangle() (bilinear), Lookup(st, width)
 * (trilinear, with the level convention of pbrt-v3 after its trilinear fix, PR #275:
 * level = nLevels - 1 + log2(max(width, 1e-8)), so width 1 means "the whole texture", the 1x1
 * level), and Lookup(st, dst0, dst1) (EWA with pbrt's 128-entry Gaussian table, alpha 2, anisotropy
 * clamp, default 8; with doTrilinear, Lookup(st, max |d|) as pbrt-v3 since its commit aaa552a "Fix
 * trilinear filtering"). From pbrt-v4 it takes per-axis wrap modes and point / bilinear filters.
 * For power-of-two images levels and lookups equal pbrt-v3's to float precision: the same float
 * operations in the same order, except the logarithm that picks the level (ours needs no libm call);
 * measured against the course's literal port of pbrt-v3 (examples/pbrtv3/mipmap.h) by
 * tests/test_tutorial_mipmap.c and bench/bench_mipmap.c: levels identical, lookups within 3e-6 relative
 * (tests/test_mipmap.c checks lookups against pbrt's algorithm written out in float).
 * Cost (gcc -O3, 2048x1024 RGB, random footprints, bench_mipmap --instructions): 225 instructions per
 * trilinear lookup and 1,462 per EWA lookup at anisotropy 8, against 579 and 2,928 for the literal
 * port: 3-channel fast paths for footprints inside a level, EWA rows trimmed to the ellipse's chord.
 *
 * Where it departs from pbrt, and why:
 *  - Levels are built lazily: init builds level 0 only; levels 1.. are allocated and built on the
 *    first lookup that needs them (or by el_mipmap_build_levels). An environment light that only
 *    reads level 0 pays for nothing else.
 *  - Box filtering never reads outside the level: pbrt-v3 reads texel 2s+1 through the wrap mode, so
 *    with Black wrap a level whose width (or height) reached 1 loses half its energy per level. Here a
 *    1-wide axis reuses its texel (what Repeat and Clamp give in pbrt), so every level has the mean of
 *    level 0 under every wrap mode.
 *  - keep_resolution = 1 keeps a non-power-of-two image as level 0 texel for texel (no resampling;
 *    envlight uses this so that radiance lookups reproduce the map exactly). Its upper levels are
 *    exact area averages: level sizes go n -> max(1, floor(n/2)) and an odd n is reduced with 3-tap
 *    weights (1 - i/n', 1, (i+1)/n') / (2 + 1/n'), which preserves the mean exactly.
 *  - Every input gives a defined, finite result (for finite texels): NaN coordinates count as 0;
 *    infinite or huge coordinates are reduced (Repeat) or pinned outside the image (Clamp, Black)
 *    without integer overflow; NaN or negative widths count as 0 (bilinear at level 0), infinite ones
 *    give the 1x1 level; NaN differentials count as 0, huge ones are limited to 1e8; zero or parallel
 *    differentials are fine (pbrt's "+1" keeps the EWA ellipse at least one texel wide). The EWA
 *    ellipse's determinant uses pbrt's expression when it is accurate and the cancellation-free one,
 *    F = 1 + |dst0|^2 + |dst1|^2 + (dst0 x dst1)^2, when pbrt's loses more than 0.1% (very
 *    anisotropic footprints, where pbrt's can go negative and produce NaN).
 *  - Input texels must be finite (EL_ERROR_NAN / EL_ERROR_INFINITE otherwise); negative values are
 *    allowed and kept (pbrt only clamps after resampling, as here).
 *  - Sizes: each side at most 2^24 texels (EL_ERROR_SIZE_OVERFLOW beyond), max_anisotropy at most 1024.
 *
 * Threads: every lookup is safe to call concurrently with other lookups on the same map. The lazy
 * build is guarded by a once-flag (GCC/Clang __atomic builtins, MSVC Interlocked functions): the first
 * thread that needs an upper level builds all of them while the others wait (spinning with
 * EL_MIPMAP_YIELD()). el_mipmap_build_levels() builds them explicitly (also thread-safe). With
 * EL_MIPMAP_NO_ATOMICS, or a compiler with neither, el_mipmap_init builds every level eagerly instead
 * (so lookups stay thread-safe; only the laziness is lost). init and free are not thread-safe (as for
 * any object). If the lazy build runs out of memory, lookups fall back to level 0 (bilinear) and
 * el_mipmap_build_levels() reports EL_ERROR_OUT_OF_MEMORY.
 *
 * Coordinates: s (u) runs along a row, t (v) down the rows; (0,0) is the corner of texel (0,0) of
 * row 0 (the first row of the row-major input), texel (i, j) covers [i/w, (i+1)/w) x [j/h, (j+1)/h),
 * and its centre is at ((i + 0.5)/w, (j + 0.5)/h). `out` always receives `channels` floats.
 * ==================================================================================================== */

/* ---------------------------------------------------------------------------------------------
 * Implementation below; stop reading here if you only need the API.
 * --------------------------------------------------------------------------------------------- */
#if defined(EL_IMPLEMENTATION) || defined(EL_MIPMAP_IMPLEMENTATION)
#ifndef EL_MIPMAP_IMPLEMENTATION_DONE
#define EL_MIPMAP_IMPLEMENTATION_DONE
#include <string.h>
#include <math.h>

/* >> mipmap: once-flag for the lazy build */
#if !defined(EL_MIPMAP_NO_ATOMICS) && (defined(__GNUC__) || defined(__clang__))
#define EL_MIPMAP__LAZY 1
static long el_mipmap__load(const long *p) { return __atomic_load_n(p, __ATOMIC_ACQUIRE); }
static void el_mipmap__store(long *p, long v) { __atomic_store_n(p, v, __ATOMIC_RELEASE); }
static int el_mipmap__cas(long *p, long expected, long desired) {
  return __atomic_compare_exchange_n(p, &expected, desired, 0, __ATOMIC_ACQ_REL, __ATOMIC_ACQUIRE);
}
#elif !defined(EL_MIPMAP_NO_ATOMICS) && defined(_MSC_VER)
#include <intrin.h>
#define EL_MIPMAP__LAZY 1
static long el_mipmap__load(const long *p) { return _InterlockedCompareExchange((volatile long *)p, 0, 0); }
static void el_mipmap__store(long *p, long v) { _InterlockedExchange((volatile long *)p, v); }
static int el_mipmap__cas(long *p, long expected, long desired) {
  return _InterlockedCompareExchange((volatile long *)p, desired, expected) == expected;
}
#else
#define EL_MIPMAP__LAZY 0 /* no atomics: el_mipmap_init builds every level eagerly */
static long el_mipmap__load(const long *p) { return *p; }
static void el_mipmap__store(long *p, long v) { *p = v; }
static int el_mipmap__cas(long *p, long expected, long desired) {
  if (*p != expected) return 0;
  *p = desired;
  return 1;
}
#endif
#ifndef EL_MIPMAP_YIELD
#if (defined(__GNUC__) || defined(__clang__)) && (defined(__x86_64__) || defined(__i386__))
#define EL_MIPMAP_YIELD() __builtin_ia32_pause()
#elif defined(_MSC_VER) && (defined(_M_X64) || defined(_M_IX86))
#define EL_MIPMAP_YIELD() _mm_pause()
#else
#define EL_MIPMAP_YIELD() ((void)0)
#endif
#endif

#if defined(__GNUC__) || defined(__clang__)
#define EL_MIPMAP__INLINE static inline __attribute__((always_inline))
#define EL_MIPMAP__NOINLINE static __attribute__((noinline))
#elif defined(_MSC_VER)
#define EL_MIPMAP__INLINE static __forceinline
#define EL_MIPMAP__NOINLINE static __declspec(noinline)
#else
#define EL_MIPMAP__INLINE static inline
#define EL_MIPMAP__NOINLINE static
#endif
#define EL_MIPMAP__MAX_SIDE (1 << 24)
#define EL_MIPMAP__STATE_NONE 0L
#define EL_MIPMAP__STATE_BUILDING 1L
#define EL_MIPMAP__STATE_BUILT 2L
#define EL_MIPMAP__STATE_FAILED 3L

/* pbrt-v3's EWA weight table: weightLut[i] = exp(-2 i/127) - exp(-2), evaluated in float with
 * glibc's expf exactly as pbrt's constructor does; a constant table, so there is no first-use race. */
static const float el_mipmap__weight_lut[128] = {
  0.864664733f, 0.849040031f, 0.83365953f, 0.818519294f, 0.80361563f, 0.788944781f,
  0.774503231f, 0.760287285f, 0.746293485f, 0.732518315f, 0.718958378f, 0.705610275f,
  0.692470789f, 0.679536581f, 0.666804492f, 0.654271305f, 0.641933978f, 0.629789352f,
  0.617834508f, 0.606066525f, 0.594482362f, 0.583079159f, 0.571854174f, 0.560804546f,
  0.549927592f, 0.539220572f, 0.528680861f, 0.518305838f, 0.50809288f, 0.498039544f,
  0.488143265f, 0.478401601f, 0.468812168f, 0.45937258f, 0.450080454f, 0.440933526f,
  0.431929469f, 0.423066139f, 0.414341331f, 0.405752778f, 0.397298455f, 0.388976216f,
  0.380784035f, 0.372719884f, 0.364781618f, 0.356967449f, 0.34927541f, 0.341703475f,
  0.334249914f, 0.32691282f, 0.319690347f, 0.312580705f, 0.305582166f, 0.298692942f,
  0.291911423f, 0.285235822f, 0.278664529f, 0.272195935f, 0.265828371f, 0.259560347f,
  0.253390193f, 0.247316495f, 0.241337672f, 0.235452279f, 0.229658857f, 0.223955944f,
  0.21834214f, 0.212816045f, 0.207376286f, 0.202021524f, 0.196750447f, 0.191561714f,
  0.186454013f, 0.181426153f, 0.176476851f, 0.171604887f, 0.166809067f, 0.162088141f,
  0.157441005f, 0.152866468f, 0.148363426f, 0.143930718f, 0.139567271f, 0.135272011f,
  0.131043866f, 0.126881793f, 0.122784719f, 0.11875169f, 0.114781633f, 0.11087364f,
  0.107026696f, 0.103239879f, 0.0995122194f, 0.0958427936f, 0.0922307223f, 0.0886750817f,
  0.0851749927f, 0.0817295909f, 0.0783380121f, 0.0749994367f, 0.0717130303f, 0.0684779733f,
  0.0652934611f, 0.0621587038f, 0.0590728968f, 0.0560353249f, 0.0530452281f, 0.0501018465f,
  0.0472044498f, 0.0443523228f, 0.0415447652f, 0.0387810767f, 0.0360605568f, 0.0333825648f,
  0.0307464004f, 0.0281514227f, 0.0255970061f, 0.0230824798f, 0.0206072628f, 0.0181707144f,
  0.0157722086f, 0.013411209f, 0.0110870898f, 0.0087992847f, 0.0065472275f, 0.00433036685f,
  0.0021481365f, 0.0f};

/* >> mipmap: small helpers */
/* pbrt's MIP level (levels - 1) + log2(x) for x >= 1e-8 (or +infinity), split into its integer part
 * *il and its fraction *frac in [0, 1), without a libm call: the integer part is the float's exponent;
 * the fraction is log2 of the mantissa m in [1, 2): m = (1 + k/16)(1 + r) with k its first 4 bits,
 * log2(1 + k/16) from a table, log2(1 + r) for 0 <= r < 1/16 from its series to r^5 (truncation 1e-8).
 * Within about 1e-7 of log2. pbrt-v3 computes log(x) / log(2) with libm and then level - floor(level),
 * so the fraction agrees with pbrt's to float precision, not to the bit. */
static const float el_mipmap__log2_head[16] = {
    0.0f, 0.0874628425f, 0.169925004f, 0.247927517f, 0.321928084f, 0.392317414f, 0.459431618f, 0.523561954f,
    0.584962487f, 0.643856168f, 0.700439692f, 0.754887521f, 0.807354927f, 0.857980967f, 0.906890571f, 0.954196334f};
static const float el_mipmap__log2_inv[16] = {
    1.0f, 0.941176474f, 0.888888896f, 0.842105269f, 0.800000012f, 0.761904776f, 0.727272749f, 0.695652187f,
    0.666666687f, 0.639999986f, 0.615384638f, 0.592592597f, 0.571428597f, 0.551724136f, 0.533333361f, 0.516129017f};
EL_MIPMAP__INLINE void el_mipmap__level(float x, int levels, int *il, float *frac) {
  unsigned int b, k;
  float mf, r, f;
  memcpy(&b, &x, sizeof b);
  *il = levels - 1 + ((int)(b >> 23) - 127);
  k = (b >> 19) & 15u;
  b = (b & 0x007fffffu) | 0x3f800000u;
  memcpy(&mf, &b, sizeof mf);
  r = mf * el_mipmap__log2_inv[k] - 1.0f;
  f = el_mipmap__log2_head[k] +
      r * (1.44269502f + r * (-0.721347511f + r * (0.48089835f + r * (-0.360673755f + r * 0.288539022f))));
  if (f >= 1.0f) { /* rounding just below the next power of two */
    *il += 1;
    f = 0.0f;
  }
  *frac = f;
}

/* floor for |x| < 2^30 without a libm call. */
EL_MIPMAP__INLINE int el_mipmap__ifloor(float x) {
  int i = (int)x;
  return ((float)i > x) ? i - 1 : i;
}
EL_MIPMAP__INLINE int el_mipmap__ifloor_nb(float x) { /* the same without a branch */
  int i = (int)x;
  return i - ((float)i > x);
}
static int el_mipmap__is_pow2(int v) { return v > 0 && (v & (v - 1)) == 0; }
static int el_mipmap__round_up_pow2(int v) {
  int p = 1;
  while (p < v) p <<= 1; /* v <= 2^24 */
  return p;
}
/* pbrt's Texel() index remapping for one axis; -1 means "Black: outside, value 0". */
static int el_mipmap__wrap(int i, int n, el_mipmap_wrap w) {
  int r;
  if ((unsigned)i < (unsigned)n) return i;
  if (w == EL_MIPMAP_WRAP_REPEAT) {
    r = i % n;
    return r < 0 ? r + n : r;
  }
  if (w == EL_MIPMAP_WRAP_CLAMP) return i < 0 ? 0 : n - 1;
  return -1;
}
/* A coordinate (in [0,1] units) made safe for point/bilinear/trilinear lookups: [-1, 2] is used as
 * given (pbrt's arithmetic); beyond it, Repeat keeps the fractional part (exact) and Clamp/Black pin
 * to -1 or 2, which gives the same texels; NaN counts as 0. */
static float el_mipmap__sane(float s, el_mipmap_wrap w) {
  float f;
  if (s >= -1.0f && s <= 2.0f) return s;
  if (s != s) return 0.0f;
  if (w == EL_MIPMAP_WRAP_REPEAT) {
    if (s > 1e30f || s < -1e30f) return 0.0f; /* also +-infinity */
    f = s - floorf(s);
    return f;
  }
  return s < 0.0f ? -1.0f : 2.0f;
}
/* The same for EWA: Clamp/Black keep far coordinates (the footprint can be wide), only finite. */
static float el_mipmap__sane_ewa(float s, el_mipmap_wrap w) {
  if (w == EL_MIPMAP_WRAP_REPEAT) return el_mipmap__sane(s, w);
  if (s != s) return 0.0f;
  if (s > 1e20f) return 1e20f;
  if (s < -1e20f) return -1e20f;
  return s;
}
/* A differential: NaN counts as 0, magnitudes are limited to 1e8 (far beyond the 1x1 level). */
static float el_mipmap__sane_d(float d) {
  if (fabsf(d) <= 1e8f) return d; /* the common case, one test */
  if (d != d) return 0.0f;
  if (d > 1e8f) return 1e8f;
  if (d < -1e8f) return -1e8f;
  return d;
}

/* Two bilinear taps along one axis of size n: indices (wrapped) and weights (0 for Black outside).
 * s has been through el_mipmap__sane. */
EL_MIPMAP__INLINE void el_mipmap__axis(float s, int n, float fn, el_mipmap_wrap w, int *i0, int *i1, float *w0,
                                       float *w1) {
  float x = s * fn - 0.5f;
  int i = el_mipmap__ifloor(x);
  float d = x - (float)i;
  *w0 = 1.0f - d;
  *w1 = d;
  if ((unsigned)i < (unsigned)(n - 1)) {
    *i0 = i;
    *i1 = i + 1;
    return;
  }
  *i0 = el_mipmap__wrap(i, n, w);
  *i1 = el_mipmap__wrap(i + 1, n, w);
  if (*i0 < 0) { *i0 = 0; *w0 = 0.0f; }
  if (*i1 < 0) { *i1 = 0; *w1 = 0.0f; }
}

static int el_mipmap__clamp_level(const el_mipmap *m, int level) {
  return level < 0 ? 0 : (level >= m->levels ? m->levels - 1 : level);
}

/* >> mipmap: building levels */
/* Box reduction of a level whose sides are even or 1 (every level of a power-of-two pyramid):
 * pbrt's .25 * (T(2s,2t) + T(2s+1,2t) + T(2s,2t+1) + T(2s+1,2t+1)), same order of additions; a
 * 1-wide side reuses its texel (pbrt's Repeat/Clamp result; pbrt's Black would add zeros). */
static void el_mipmap__reduce_pow2(const float *src, int sw, int sh, float *dst, int dw, int dh, int C) {
  int s, t, c;
  size_t srow = (size_t)sw * (size_t)C;
  int du = sw > 1 ? C : 0; /* offset of texel 2s+1 from 2s */
  for (t = 0; t < dh; ++t) {
    const float *r0 = src + (size_t)(2 * t) * srow;
    const float *r1 = (2 * t + 1 < sh) ? r0 + srow : r0;
    float *o = dst + (size_t)t * (size_t)dw * (size_t)C;
    if (C == 3 && du == 3) {
      for (s = 0; s < dw; ++s) {
        const float *a = r0 + 6 * s, *b = r1 + 6 * s;
        o[3 * s + 0] = .25f * (((a[0] + a[3]) + b[0]) + b[3]);
        o[3 * s + 1] = .25f * (((a[1] + a[4]) + b[1]) + b[4]);
        o[3 * s + 2] = .25f * (((a[2] + a[5]) + b[2]) + b[5]);
      }
    } else {
      for (s = 0; s < dw; ++s) {
        const float *a = r0 + (size_t)(2 * s) * (size_t)C, *b = r1 + (size_t)(2 * s) * (size_t)C;
        for (c = 0; c < C; ++c) o[s * C + c] = .25f * (((a[c] + a[c + du]) + b[c]) + b[c + du]);
      }
    }
  }
}

/* Area weights from n texels to n2 = max(1, floor(n/2)): output i covers [i n/n2, (i+1) n/n2).
 * n even: taps 2i, 2i+1, weights 1/2; n == 1: tap 0, weight 1; n odd >= 3: taps 2i, 2i+1, 2i+2 with
 * weights (1 - i/n2, 1, (i+1)/n2) / (2 + 1/n2). first[i] is the first tap, wt[3 i + j] the weights. */
static void el_mipmap__area_weights(int n, int n2, int *first, float *wt) {
  int i;
  for (i = 0; i < n2; ++i) {
    first[i] = 2 * i;
    if (n == 1) {
      first[i] = 0;
      wt[3 * i] = 1.0f; wt[3 * i + 1] = 0.0f; wt[3 * i + 2] = 0.0f;
    } else if ((n & 1) == 0) {
      wt[3 * i] = 0.5f; wt[3 * i + 1] = 0.5f; wt[3 * i + 2] = 0.0f;
    } else {
      double r = 2.0 + 1.0 / n2;
      wt[3 * i] = (float)((1.0 - (double)i / n2) / r);
      wt[3 * i + 1] = (float)(1.0 / r);
      wt[3 * i + 2] = (float)(((double)(i + 1) / n2) / r);
    }
  }
}

/* General (non-power-of-two) reduction: separable exact area averages; tmp holds dw x sh texels. */
static int el_mipmap__reduce_area(const float *src, int sw, int sh, float *dst, int dw, int dh, int C,
                                  float *tmp) {
  int *fu, *fv, s, t, c, j;
  float *wu, *wv;
  size_t n = (size_t)dw + (size_t)dh;
  fu = (int *)EL_MALLOC(n * sizeof(int));
  wu = (float *)EL_MALLOC(3 * n * sizeof(float));
  if (!fu || !wu) {
    if (fu) EL_FREE(fu);
    if (wu) EL_FREE(wu);
    return 0;
  }
  fv = fu + dw;
  wv = wu + 3 * (size_t)dw;
  el_mipmap__area_weights(sw, dw, fu, wu);
  el_mipmap__area_weights(sh, dh, fv, wv);
  for (t = 0; t < sh; ++t) { /* along rows */
    const float *r = src + (size_t)t * (size_t)sw * (size_t)C;
    float *o = tmp + (size_t)t * (size_t)dw * (size_t)C;
    for (s = 0; s < dw; ++s)
      for (c = 0; c < C; ++c) {
        float acc = 0.0f;
        for (j = 0; j < 3; ++j) {
          int k = fu[s] + j;
          if (k < sw) acc += wu[3 * s + j] * r[(size_t)k * (size_t)C + (size_t)c];
        }
        o[(size_t)s * (size_t)C + (size_t)c] = acc;
      }
  }
  for (t = 0; t < dh; ++t) { /* down the columns, a whole row at a time */
    size_t rowf = (size_t)dw * (size_t)C, k;
    float *o = dst + (size_t)t * rowf;
    for (k = 0; k < rowf; ++k) o[k] = 0.0f;
    for (j = 0; j < 3; ++j) {
      int v = fv[t] + j;
      float wgt = wv[3 * t + j];
      const float *r;
      if (v >= sh || wgt == 0.0f) continue;
      r = tmp + (size_t)v * rowf;
      for (k = 0; k < rowf; ++k) o[k] += wgt * r[k];
    }
  }
  EL_FREE(fu);
  EL_FREE(wu);
  return 1;
}

/* Builds levels 1.. into one allocation. Returns 1 on success, 0 when out of memory. */
static int el_mipmap__build_upper(el_mipmap *m) {
  size_t total = 0, off = 0, tmpn = 0;
  int i, C = m->channels, needs_area = 0;
  float *block, *tmp = NULL;
  for (i = 1; i < m->levels; ++i) {
    total += (size_t)m->level_width[i] * (size_t)m->level_height[i] * (size_t)C;
    if (((m->level_width[i - 1] & 1) && m->level_width[i - 1] > 1) ||
        ((m->level_height[i - 1] & 1) && m->level_height[i - 1] > 1)) {
      size_t t = (size_t)m->level_width[i] * (size_t)m->level_height[i - 1] * (size_t)C;
      needs_area = 1;
      if (t > tmpn) tmpn = t;
    }
  }
  if (total == 0) return 1;
  block = (float *)EL_MALLOC(total * sizeof(float));
  if (!block) return 0;
  if (needs_area) {
    tmp = (float *)EL_MALLOC(tmpn * sizeof(float));
    if (!tmp) {
      EL_FREE(block);
      return 0;
    }
  }
  for (i = 1; i < m->levels; ++i) {
    /* <<Initialize ith MIPMap level from (i-1)st level>> */
    int sw = m->level_width[i - 1], sh = m->level_height[i - 1];
    int dw = m->level_width[i], dh = m->level_height[i];
    float *dst = block + off;
    off += (size_t)dw * (size_t)dh * (size_t)C;
    if (((sw & 1) == 0 || sw == 1) && ((sh & 1) == 0 || sh == 1)) {
      el_mipmap__reduce_pow2(m->level_data[i - 1], sw, sh, dst, dw, dh, C);
    } else if (!el_mipmap__reduce_area(m->level_data[i - 1], sw, sh, dst, dw, dh, C, tmp)) {
      EL_FREE(block);
      if (tmp) EL_FREE(tmp);
      for (i = 1; i < m->levels; ++i) m->level_data[i] = NULL;
      return 0;
    }
    m->level_data[i] = dst;
  }
  if (tmp) EL_FREE(tmp);
  m->upper_bytes = total * sizeof(float);
  return 1;
}

/* Returns 1 when levels 1.. are readable, 0 when their build ran out of memory. */
static int el_mipmap__ensure_slow(el_mipmap *m) {
  for (;;) {
    long st = el_mipmap__load(&m->build_state);
    if (st == EL_MIPMAP__STATE_BUILT) return 1;
    if (st == EL_MIPMAP__STATE_FAILED) return 0;
    if (st == EL_MIPMAP__STATE_NONE &&
        el_mipmap__cas(&m->build_state, EL_MIPMAP__STATE_NONE, EL_MIPMAP__STATE_BUILDING)) {
      int ok = el_mipmap__build_upper(m);
      el_mipmap__store(&m->build_state, ok ? EL_MIPMAP__STATE_BUILT : EL_MIPMAP__STATE_FAILED);
      return ok;
    }
    EL_MIPMAP_YIELD();
  }
}
static int el_mipmap__ensure(const el_mipmap *m) {
  if (el_mipmap__load(&m->build_state) == EL_MIPMAP__STATE_BUILT) return 1;
  return el_mipmap__ensure_slow((el_mipmap *)m); /* the map is not const: init wrote it */
}

/* pbrt's ResampleWeight / resampleWeights(oldRes, newRes) and Lanczos(x, tau = 2), in float. */
static float el_mipmap__lanczos(float x, float tau) {
  float s, l;
  x = fabsf(x);
  if (x < 1e-5f) return 1;
  if (x > 1.f) return 0;
  x *= 3.14159265358979323846f;
  s = sinf(x * tau) / (x * tau);
  l = sinf(x) / x;
  return s * l;
}
static void el_mipmap__resample_weights(int oldres, int newres, el_mipmap_wrap wrap, int *idx, float *wt) {
  int i, j;
  float filterwidth = 2.f;
  for (i = 0; i < newres; ++i) {
    /* <<Compute image resampling weights for ith texel>> */
    float center = ((float)i + .5f) * (float)oldres / (float)newres;
    int first = (int)floorf((center - filterwidth) + 0.5f);
    float inv;
    for (j = 0; j < 4; ++j) {
      float pos = (float)(first + j) + .5f;
      wt[4 * i + j] = el_mipmap__lanczos((pos - center) / filterwidth, 2.0f);
    }
    /* <<Normalize filter weights for texel resampling>> */
    inv = 1 / (wt[4 * i] + wt[4 * i + 1] + wt[4 * i + 2] + wt[4 * i + 3]);
    for (j = 0; j < 4; ++j) {
      int k = el_mipmap__wrap(first + j, oldres, wrap);
      wt[4 * i + j] *= inv;
      if (k < 0) { /* Black: the tap reads 0; pbrt skips it, adding 0 * texel 0 is the same */
        k = 0;
        wt[4 * i + j] = 0.0f;
      }
      idx[4 * i + j] = k;
    }
  }
}

/* <<Resample image to power-of-two resolution>>: s first (rows of the input), then t, clamp at 0. */
static el_result el_mipmap__resample(el_mipmap *m, const float *img, int w, int h, int nw, int nh,
                                     float *out) {
  int C = m->channels, s, t, j, c;
  size_t rowf = (size_t)nw * (size_t)C, k;
  float *tmp = (float *)EL_MALLOC(rowf * (size_t)h * sizeof(float));
  int *si = (int *)EL_MALLOC(4 * ((size_t)nw + (size_t)nh) * sizeof(int));
  float *sw = (float *)EL_MALLOC(4 * ((size_t)nw + (size_t)nh) * sizeof(float));
  int *ti;
  float *tw;
  if (!tmp || !si || !sw) {
    if (tmp) EL_FREE(tmp);
    if (si) EL_FREE(si);
    if (sw) EL_FREE(sw);
    return EL_ERROR_OUT_OF_MEMORY;
  }
  ti = si + 4 * (size_t)nw;
  tw = sw + 4 * (size_t)nw;
  el_mipmap__resample_weights(w, nw, m->wrap_u, si, sw);
  el_mipmap__resample_weights(h, nh, m->wrap_v, ti, tw);
  /* <<Apply sWeights to zoom in s direction>> */
  for (t = 0; t < h; ++t) {
    const float *r = img + (size_t)t * (size_t)w * (size_t)C;
    float *o = tmp + (size_t)t * rowf;
    if (C == 3) {
      for (s = 0; s < nw; ++s) {
        const int *ix = si + 4 * s;
        const float *wt = sw + 4 * s;
        const float *p0 = r + 3 * ix[0], *p1 = r + 3 * ix[1], *p2 = r + 3 * ix[2], *p3 = r + 3 * ix[3];
        o[3 * s + 0] = (((0.f + wt[0] * p0[0]) + wt[1] * p1[0]) + wt[2] * p2[0]) + wt[3] * p3[0];
        o[3 * s + 1] = (((0.f + wt[0] * p0[1]) + wt[1] * p1[1]) + wt[2] * p2[1]) + wt[3] * p3[1];
        o[3 * s + 2] = (((0.f + wt[0] * p0[2]) + wt[1] * p1[2]) + wt[2] * p2[2]) + wt[3] * p3[2];
      }
    } else {
      for (s = 0; s < nw; ++s)
        for (c = 0; c < C; ++c) {
          float acc = 0.f;
          for (j = 0; j < 4; ++j) acc += sw[4 * s + j] * r[(size_t)si[4 * s + j] * (size_t)C + (size_t)c];
          o[(size_t)s * (size_t)C + (size_t)c] = acc;
        }
    }
  }
  /* <<Resample image in t direction>>, a whole output row at a time */
  for (t = 0; t < nh; ++t) {
    const int *ix = ti + 4 * t;
    const float *wt = tw + 4 * t;
    const float *r0 = tmp + (size_t)ix[0] * rowf, *r1 = tmp + (size_t)ix[1] * rowf;
    const float *r2 = tmp + (size_t)ix[2] * rowf, *r3 = tmp + (size_t)ix[3] * rowf;
    float w0 = wt[0], w1 = wt[1], w2 = wt[2], w3 = wt[3];
    float *o = out + (size_t)t * rowf;
    for (k = 0; k < rowf; ++k) {
      float v = (((0.f + w0 * r0[k]) + w1 * r1[k]) + w2 * r2[k]) + w3 * r3[k];
      o[k] = v < 0.f ? 0.f : v; /* pbrt's clamp(): negative ringing to 0 */
    }
  }
  EL_FREE(tmp);
  EL_FREE(si);
  EL_FREE(sw);
  return EL_SUCCESS;
}

/* EL_SUCCESS when all n floats are finite, else EL_ERROR_NAN / EL_ERROR_INFINITE for the first bad one,
 * whose index goes to *bad. */
static el_result el_mipmap__check_finite(const float *p, size_t n, size_t *bad) {
  float acc[8] = {0, 0, 0, 0, 0, 0, 0, 0};
  size_t i = 0, j;
  for (; i + 8 <= n; i += 8)
    for (j = 0; j < 8; ++j) acc[j] += p[i + j] - p[i + j]; /* 0 for finite, NaN otherwise */
  for (; i < n; ++i) acc[0] += p[i] - p[i];
  if (acc[0] + acc[1] + acc[2] + acc[3] + acc[4] + acc[5] + acc[6] + acc[7] == 0.0f) return EL_SUCCESS;
  for (i = 0; i < n; ++i) {
    *bad = i;
    if (p[i] != p[i]) return EL_ERROR_NAN;
    if (p[i] - p[i] != 0.0f) return EL_ERROR_INFINITE;
  }
  return EL_SUCCESS;
}

/* >> mipmap: init, free, queries */
EL_DEF el_result el_mipmap_init(el_mipmap *m, const float *pixels, int width, int height, int channels,
                                const el_mipmap_options *opt) {
  el_mipmap_options o;
  int w, h, i, keep;
  size_t nfl, bad = 0;
  el_result r;
  if (!m) return EL_ERROR_INVALID_ARGUMENT;
  memset(m, 0, sizeof *m);
  m->bad_index = -1;
  if (!pixels || width < 1 || height < 1 || channels < 1 || channels > 4) return EL_ERROR_INVALID_ARGUMENT;
  if (opt) o = *opt;
  else memset(&o, 0, sizeof o);
  if ((int)o.wrap_u < 0 || (int)o.wrap_u > 2 || (int)o.wrap_v < 0 || (int)o.wrap_v > 2 ||
      (int)o.filter < 0 || (int)o.filter > 3)
    return EL_ERROR_INVALID_ARGUMENT;
  if (o.max_anisotropy != o.max_anisotropy) return EL_ERROR_NAN;
  if (o.max_anisotropy > 1e30f) return EL_ERROR_INFINITE;
  if (o.max_anisotropy == 0.0f) o.max_anisotropy = 8.0f;
  if (o.max_anisotropy < 1.0f || o.max_anisotropy > 1024.0f) return EL_ERROR_INVALID_ARGUMENT;
  if (width > EL_MIPMAP__MAX_SIDE || height > EL_MIPMAP__MAX_SIDE) return EL_ERROR_SIZE_OVERFLOW;
  keep = o.keep_resolution || (el_mipmap__is_pow2(width) && el_mipmap__is_pow2(height));
  w = keep ? width : el_mipmap__round_up_pow2(width);
  h = keep ? height : el_mipmap__round_up_pow2(height);
  if ((size_t)w > ((size_t)-1) / sizeof(float) / (size_t)channels / (size_t)h / 2)
    return EL_ERROR_SIZE_OVERFLOW; /* level 0 and the resampling buffer must fit */
  if ((size_t)width > ((size_t)-1) / sizeof(float) / (size_t)channels / (size_t)height)
    return EL_ERROR_SIZE_OVERFLOW;
  r = el_mipmap__check_finite(pixels, (size_t)width * (size_t)height * (size_t)channels, &bad);
  if (r != EL_SUCCESS) {
    bad /= (size_t)channels; /* the texel */
    m->bad_index = bad <= 2147483647u ? (int)bad : 2147483647;
    return r;
  }
  m->input_width = width;
  m->input_height = height;
  m->width = w;
  m->height = h;
  m->channels = channels;
  m->wrap_u = o.wrap_u;
  m->wrap_v = o.wrap_v;
  m->filter = o.filter;
  m->max_anisotropy = o.max_anisotropy;
  m->resampled = !keep;
  /* <<Initialize levels of MIPMap from image>>: sizes now, texels of levels 1.. on first need */
  m->levels = 1;
  m->level_width[0] = w;
  m->level_height[0] = h;
  while (m->level_width[m->levels - 1] > 1 || m->level_height[m->levels - 1] > 1) {
    int pw = m->level_width[m->levels - 1], ph = m->level_height[m->levels - 1];
    m->level_width[m->levels] = pw > 1 ? pw / 2 : 1;
    m->level_height[m->levels] = ph > 1 ? ph / 2 : 1;
    m->levels++;
  }
  nfl = (size_t)w * (size_t)h * (size_t)channels;
  m->level_data[0] = (float *)EL_MALLOC(nfl * sizeof(float));
  if (!m->level_data[0]) {
    memset(m, 0, sizeof *m);
    m->bad_index = -1;
    return EL_ERROR_OUT_OF_MEMORY;
  }
  m->level0_bytes = nfl * sizeof(float);
  /* <<Initialize most detailed level of MIPMap>> */
  if (keep) {
    memcpy(m->level_data[0], pixels, nfl * sizeof(float));
  } else {
    r = el_mipmap__resample(m, pixels, width, height, w, h, m->level_data[0]);
    if (r != EL_SUCCESS) {
      EL_FREE(m->level_data[0]);
      memset(m, 0, sizeof *m);
      m->bad_index = -1;
      return r;
    }
  }
  for (i = m->levels; i < EL_MIPMAP_MAX_LEVELS; ++i) m->level_width[i] = m->level_height[i] = 0;
  for (i = 0; i < m->levels; ++i) {
    m->level_size[i][0] = (float)m->level_width[i];
    m->level_size[i][1] = (float)m->level_height[i];
  }
  m->build_state = (m->levels == 1) ? EL_MIPMAP__STATE_BUILT : EL_MIPMAP__STATE_NONE;
#if !EL_MIPMAP__LAZY
  if (el_mipmap_build_levels(m) != EL_SUCCESS) {
    el_mipmap_free(m);
    m->bad_index = -1;
    return EL_ERROR_OUT_OF_MEMORY;
  }
#endif
  return EL_SUCCESS;
}

EL_DEF void el_mipmap_free(el_mipmap *m) {
  if (!m) return;
  if (m->level_data[0]) EL_FREE(m->level_data[0]);
  if (m->levels > 1 && m->level_data[1]) EL_FREE(m->level_data[1]); /* the block of levels 1.. */
  memset(m, 0, sizeof *m);
}

EL_DEF el_result el_mipmap_build_levels(el_mipmap *m) {
  if (!m || !m->level_data[0]) return EL_ERROR_INVALID_ARGUMENT;
  el_mipmap__cas(&m->build_state, EL_MIPMAP__STATE_FAILED, EL_MIPMAP__STATE_NONE); /* retry */
  return el_mipmap__ensure_slow(m) ? EL_SUCCESS : EL_ERROR_OUT_OF_MEMORY;
}
EL_DEF int el_mipmap_levels_built(const el_mipmap *m) {
  return m && el_mipmap__load(&m->build_state) == EL_MIPMAP__STATE_BUILT;
}
EL_DEF int el_mipmap_levels(const el_mipmap *m) { return m ? m->levels : 0; }
EL_DEF int el_mipmap_level_width(const el_mipmap *m, int level) {
  return (m && level >= 0 && level < m->levels) ? m->level_width[level] : 0;
}
EL_DEF int el_mipmap_level_height(const el_mipmap *m, int level) {
  return (m && level >= 0 && level < m->levels) ? m->level_height[level] : 0;
}
EL_DEF const float *el_mipmap_level_data(const el_mipmap *m, int level) {
  if (!m || level < 0 || level >= m->levels) return NULL;
  if (level > 0 && !el_mipmap__ensure(m)) return NULL;
  return m->level_data[level];
}
EL_DEF size_t el_mipmap_bytes(const el_mipmap *m) {
  if (!m) return 0;
  return m->level0_bytes + (el_mipmap_levels_built(m) ? m->upper_bytes : 0);
}

/* >> mipmap: lookups */
/* Level usable for a lookup: 0 when levels 1.. are needed but could not be built. */
static int el_mipmap__usable(const el_mipmap *m, int level) {
  if (level <= 0) return 0;
  return el_mipmap__ensure(m) ? level : 0;
}

static void el_mipmap__texel(const el_mipmap *m, int level, int s, int t, float *out) {
  int C = m->channels, c;
  int su = el_mipmap__wrap(s, m->level_width[level], m->wrap_u);
  int tv = el_mipmap__wrap(t, m->level_height[level], m->wrap_v);
  const float *p;
  if (su < 0 || tv < 0) {
    for (c = 0; c < C; ++c) out[c] = 0.0f;
    return;
  }
  p = m->level_data[level] + ((size_t)tv * (size_t)m->level_width[level] + (size_t)su) * (size_t)C;
  for (c = 0; c < C; ++c) out[c] = p[c];
}

EL_DEF void el_mipmap_texel(const el_mipmap *m, int level, int s, int t, float *out) {
  level = el_mipmap__usable(m, el_mipmap__clamp_level(m, level));
  el_mipmap__texel(m, level, s, t, out);
}

EL_DEF void el_mipmap_point(const el_mipmap *m, int level, float s, float t, float *out) {
  int n, k;
  level = el_mipmap__usable(m, el_mipmap__clamp_level(m, level));
  n = m->level_width[level];
  s = el_mipmap__sane(s, m->wrap_u) * (float)n;
  k = m->level_height[level];
  t = el_mipmap__sane(t, m->wrap_v) * (float)k;
  el_mipmap__texel(m, level, el_mipmap__ifloor(s), el_mipmap__ifloor(t), out);
}

/* pbrt's triangle(level, st): (1-ds)(1-dt) T00 + (1-ds) dt T01 + ds (1-dt) T10 + ds dt T11.
 * s and t have been through el_mipmap__sane. C is the channel count: callers pass a constant where
 * they can, so that each copy is specialised. */
EL_MIPMAP__INLINE void el_mipmap__bilerp_c(const el_mipmap *m, int level, float s, float t, float *out,
                                           int C) {
  int u0, u1, v0, v1, c, w = m->level_width[level];
  float a0, a1, b0, b1, k00, k01, k10, k11;
  size_t stride = (size_t)w * (size_t)C, c0, c1;
  const float *d = m->level_data[level], *r0, *r1;
  el_mipmap__axis(s, w, m->level_size[level][0], m->wrap_u, &u0, &u1, &a0, &a1);
  el_mipmap__axis(t, m->level_height[level], m->level_size[level][1], m->wrap_v, &v0, &v1, &b0, &b1);
  k00 = a0 * b0;
  k01 = a0 * b1;
  k10 = a1 * b0;
  k11 = a1 * b1;
  r0 = d + (size_t)v0 * stride;
  r1 = d + (size_t)v1 * stride;
  c0 = (size_t)u0 * (size_t)C;
  c1 = (size_t)u1 * (size_t)C;
  for (c = 0; c < C; ++c) {
    size_t k = (size_t)c;
    out[c] = k00 * r0[c0 + k] + k01 * r1[c0 + k] + k10 * r0[c1 + k] + k11 * r1[c1 + k];
  }
}
static void el_mipmap__bilerp(const el_mipmap *m, int level, float s, float t, float *out) {
  switch (m->channels) {
  case 1: el_mipmap__bilerp_c(m, level, s, t, out, 1); break;
  case 2: el_mipmap__bilerp_c(m, level, s, t, out, 2); break;
  case 3: el_mipmap__bilerp_c(m, level, s, t, out, 3); break;
  default: el_mipmap__bilerp_c(m, level, s, t, out, 4); break;
  }
}

EL_DEF void el_mipmap_bilerp(const el_mipmap *m, int level, float s, float t, float *out) {
  level = el_mipmap__usable(m, el_mipmap__clamp_level(m, level));
  el_mipmap__bilerp(m, level, el_mipmap__sane(s, m->wrap_u), el_mipmap__sane(t, m->wrap_v), out);
}

/* pbrt's triangle() for 3 channels at level coordinates (x, y) = (s w - 0.5, t h - 0.5) that are known
 * to lie in [0, w - 1) x [0, h - 1): no wrapping, (int) is floor, and the four texels are two runs of
 * 6 contiguous floats, one row apart. The same operations in the same order as el_mipmap__bilerp_c. */
EL_MIPMAP__INLINE void el_mipmap__bilerp3_inside(const float *data, int w, float x, float y, float *out) {
  int i = (int)x, j = (int)y;
  float ds = x - (float)i, dt = y - (float)j;
  float k00 = (1.0f - ds) * (1.0f - dt), k01 = (1.0f - ds) * dt, k10 = ds * (1.0f - dt), k11 = ds * dt;
  const float *r0 = data + ((size_t)j * (size_t)w + (size_t)i) * 3, *r1 = r0 + (size_t)w * 3;
  out[0] = k00 * r0[0] + k01 * r1[0] + k10 * r0[3] + k11 * r1[3];
  out[1] = k00 * r0[1] + k01 * r1[1] + k10 * r0[4] + k11 * r1[4];
  out[2] = k00 * r0[2] + k01 * r1[2] + k10 * r0[5] + k11 * r1[5];
}

EL_DEF void el_mipmap_lookup_filtered(const el_mipmap *m, el_mipmap_filter filter, float s, float t,
                                      float width, float *out) {
  float frac;
  int il;
  if (filter != EL_MIPMAP_FILTER_POINT && filter != EL_MIPMAP_FILTER_BILINEAR) {
    el_mipmap_lookup(m, s, t, width, out);
    return;
  }
  /* pbrt-v4: <<Compute MIPMap level>>, then one level */
  if (!(width > 1e-8f)) width = 1e-8f; /* also NaN and negative widths */
  el_mipmap__level(width, m->levels, &il, &frac);
  if (il >= m->levels - 1) {
    el_mipmap__texel(m, el_mipmap__usable(m, m->levels - 1), 0, 0, out);
    return;
  }
  if (il < 0) il = 0;
  if (filter == EL_MIPMAP_FILTER_POINT) {
    el_mipmap_point(m, il, s, t, out);
    return;
  }
  if (m->channels == 3 && (il == 0 || el_mipmap__load(&m->build_state) == EL_MIPMAP__STATE_BUILT)) {
    /* the common case: 3 channels, (s, t) inside the level's interior (no wrapping; NaN fails) */
    const float *size = m->level_size[il];
    float x = s * size[0] - 0.5f, y = t * size[1] - 0.5f;
    if (x >= 0.0f && x < size[0] - 1.0f && y >= 0.0f && y < size[1] - 1.0f) {
      el_mipmap__bilerp3_inside(m->level_data[il], m->level_width[il], x, y, out);
      return;
    }
  }
  el_mipmap__bilerp(m, el_mipmap__usable(m, il), el_mipmap__sane(s, m->wrap_u), el_mipmap__sane(t, m->wrap_v),
                    out);
}

/* Every trilinear case but the common one below: any channel count, borders, levels out of range.
 * Out of line, so that the common case needs no callee-saved registers. */
EL_MIPMAP__NOINLINE void el_mipmap__lookup_general(const el_mipmap *m, int il, float delta, float s, float t, float *out) {
  float a[4], b[4];
  int c, C = m->channels;
  /* <<Perform trilinear interpolation at appropriate MIPMap level>> */
  if (il >= m->levels - 1) {
    el_mipmap__texel(m, el_mipmap__usable(m, m->levels - 1), 0, 0, out);
    return;
  }
  s = el_mipmap__sane(s, m->wrap_u);
  t = el_mipmap__sane(t, m->wrap_v);
  if (il < 0 || !el_mipmap__ensure(m)) { /* (levels 1.. are unavailable only when out of memory) */
    el_mipmap__bilerp(m, 0, s, t, out);
    return;
  }
  if (C == 3) {
    el_mipmap__bilerp_c(m, il, s, t, a, 3);
    el_mipmap__bilerp_c(m, il + 1, s, t, b, 3);
  } else {
    el_mipmap__bilerp(m, il, s, t, a);
    el_mipmap__bilerp(m, il + 1, s, t, b);
  }
  for (c = 0; c < C; ++c) out[c] = (1 - delta) * a[c] + delta * b[c]; /* pbrt's Lerp */
}

EL_DEF void el_mipmap_lookup(const el_mipmap *m, float s, float t, float width, float *out) {
  /* <<Compute MIPMap level for trilinear filtering>>: level = il + delta */
  float delta;
  int il;
  if (!(width > 1e-8f)) width = 1e-8f; /* also NaN and negative widths */
  el_mipmap__level(width, m->levels, &il, &delta);
  /* The common case, in one piece: 3 channels, 0 <= il < levels - 1, levels built, and (s, t) inside
   * the interior of level il + 1: x1 = s w1 - 0.5 in [0, w1 - 1), and the same for y1. Then (s, t) is
   * inside the interior of level il too, because w >= 2 w1 (w1 = floor(w / 2) once w1 >= 2):
   * x1 >= 0 gives s w >= 1, so x >= 0.5; x1 < w1 - 1 gives s w1 < w1 - 0.5, so s w < w - w / (2 w1) <= w - 1
   * and x < w - 1.5 (half a texel of slack on each side covers every rounding). NaN fails the tests. */
  if (m->channels == 3 && (unsigned)il < (unsigned)(m->levels - 1) &&
      el_mipmap__load(&m->build_state) == EL_MIPMAP__STATE_BUILT) {
    const float *size1 = m->level_size[il + 1];
    float x1 = s * size1[0] - 0.5f, y1 = t * size1[1] - 0.5f;
    if (x1 >= 0.0f && x1 < size1[0] - 1.0f && y1 >= 0.0f && y1 < size1[1] - 1.0f) {
      float a[3], b[3];
      el_mipmap__bilerp3_inside(m->level_data[il], m->level_width[il], s * m->level_size[il][0] - 0.5f,
                                t * m->level_size[il][1] - 0.5f, a);
      el_mipmap__bilerp3_inside(m->level_data[il + 1], m->level_width[il + 1], x1, y1, b);
      out[0] = (1 - delta) * a[0] + delta * b[0]; /* pbrt's Lerp */
      out[1] = (1 - delta) * a[1] + delta * b[1];
      out[2] = (1 - delta) * a[2] + delta * b[2];
      return;
    }
  }
  el_mipmap__lookup_general(m, il, delta, s, t, out);
}

/* >> mipmap: EWA */
static int el_mipmap__iceil(float x) { return -el_mipmap__ifloor(-x); }

/* Pins a footprint that lies entirely outside a Clamp axis next to the image, moved by a whole number
 * of texels (the same texels, the same weights), so that huge coordinates cannot overflow an int. */
static float el_mipmap__pin(float x, float r, int n) {
  float f = x - floorf(x);
  if (x < 0.0f) return -(ceilf(r) + 2.0f) + f;
  return (float)n + ceilf(r) + 1.0f + f;
}

/* One row's texels p..pend (inclusive, contiguous, C floats each) of pbrt's EWA loop: r2 with pbrt's
 * expression, table weight when r2 < 1. Two texels per iteration (the same additions in the same
 * order as one at a time). */
EL_MIPMAP__INLINE void el_mipmap__ewa_span(const float *p, const float *pend, float fis, float x, float A,
                                           float B, float tt, float ctt, float *acc, float *sumw, int C) {
  int c;
  float sw = *sumw;
  for (; p < pend; p += 2 * C, fis += 2.0f) {
    float ss = fis - x, ss1 = (fis + 1.0f) - x;
    float r2 = A * ss * ss + B * ss * tt + ctt, r21 = A * ss1 * ss1 + B * ss1 * tt + ctt;
    if (r2 < 1) {
      /* r2 in [0, 1) up to rounding, so (int)(r2 * 128) is 0..127; & 127 keeps any rounding accident
       * inside the table */
      float wgt = el_mipmap__weight_lut[(int)(r2 * 128) & 127];
      for (c = 0; c < C; ++c) acc[c] += p[c] * wgt;
      sw += wgt;
    }
    if (r21 < 1) {
      float wgt = el_mipmap__weight_lut[(int)(r21 * 128) & 127];
      for (c = 0; c < C; ++c) acc[c] += p[C + c] * wgt;
      sw += wgt;
    }
  }
  if (p == pend) { /* an odd count: the last texel */
    float ss = fis - x;
    float r2 = A * ss * ss + B * ss * tt + ctt;
    if (r2 < 1) {
      float wgt = el_mipmap__weight_lut[(int)(r2 * 128) & 127];
      for (c = 0; c < C; ++c) acc[c] += p[c] * wgt;
      sw += wgt;
    }
  }
  *sumw = sw;
}

/* <<Convert EWA coordinates to appropriate scale for level>>, <<Compute ellipse coefficients to bound
 * EWA filter region>> and the half-sizes of <<Compute the ellipse's (s,t) bounding box in texture
 * space>>: pbrt's operations in pbrt's order, but for F when pbrt's loses too much (below). */
typedef struct el_mipmap__ellipse {
  float x, y;    /* the centre in texel units of the level: s w - 0.5, t h - 0.5 */
  float A, B, C; /* r2 = A ss^2 + B ss tt + C tt^2, normalised so that r2 = 1 on the ellipse */
  float det;     /* 4 A C - B^2 */
  float ru, rv;  /* half-sizes of the bounding box (pbrt's 2 invDet uSqrt, 2 invDet vSqrt) */
} el_mipmap__ellipse;
EL_MIPMAP__INLINE void el_mipmap__ellipse_init(const float *size, float s, float t, float d0s, float d0t,
                                               float d1s, float d1t, el_mipmap__ellipse *e) {
  float A, B, Cc, F, cr, invF, det, invDet;
  int well;
  e->x = s * size[0] - 0.5f;
  e->y = t * size[1] - 0.5f;
  d0s *= size[0];
  d0t *= size[1];
  d1s *= size[0];
  d1t *= size[1];
  A = d0t * d0t + d1t * d1t + 1;
  B = -2 * (d0s * d0t + d1s * d1t);
  Cc = d0s * d0s + d1s * d1s + 1;
  F = A * Cc - B * B * 0.25f;
  /* F = (A C - B^2/4) loses about A C / F ulps to cancellation; beyond 1e3 ulps (thin ellipses at high
   * anisotropy, where pbrt's F can even turn negative) use the same quantity without cancellation,
   * F = 1 + |dst0|^2 + |dst1|^2 + (dst0 x dst1)^2, and det = 4 / F (what it is exactly). */
  well = F > 1.25e-4f * (A * Cc);
  if (!well) {
    cr = d0s * d1t - d0t * d1s;
    F = 1 + d0s * d0s + d0t * d0t + d1s * d1s + d1t * d1t + cr * cr;
  }
  invF = 1 / F;
  A *= invF;
  B *= invF;
  Cc *= invF;
  det = well ? -B * B + 4 * A * Cc : 4 * invF;
  invDet = 1 / det;
  e->A = A;
  e->B = B;
  e->C = Cc;
  e->det = det;
  e->ru = 2 * invDet * sqrtf(det * Cc);
  e->rv = 2 * invDet * sqrtf(A * det);
}

/* pbrt's EWA(level, st, dst0, dst1) for C channels (a constant in each inlined copy), any position and
 * wrap mode. s, t already made safe by el_mipmap__sane_ewa. pbrt loops over the ellipse's bounding
 * box and keeps the texels with r2 = A ss^2 + B ss tt + C tt^2 < 1; here each row's loop is trimmed to
 * the ellipse's chord in that row (plus a margin), so the skipped texels all have r2 >= 1 (or r2 so
 * close to 1 that their table weight is 0, see el_mipmap__ewa3_inside), and each kept texel gets
 * pbrt's r2, computed with the same operations in the same order, hence the same table weight. */
EL_MIPMAP__INLINE void el_mipmap__ewa_c(const el_mipmap *m, int level, float s, float t, float d0s,
                                        float d0t, float d1s, float d1t, float *out, int C) {
  int nu, nv, c, t0, t1, it;
  float fit, x, y, A, B, Cc, ru, rv, inv2A, fourA, mg, acc[4], sumw = 0.0f;
  const float *data;
  el_mipmap_wrap wu = m->wrap_u;
  size_t rowstride;
  el_mipmap__ellipse e;
  if (level >= m->levels) {
    el_mipmap__texel(m, m->levels - 1, 0, 0, out);
    return;
  }
  nu = m->level_width[level];
  nv = m->level_height[level];
  data = m->level_data[level];
  rowstride = (size_t)nu * (size_t)C;
  el_mipmap__ellipse_init(m->level_size[level], s, t, d0s, d0t, d1s, d1t, &e);
  x = e.x;
  y = e.y;
  A = e.A;
  B = e.B;
  Cc = e.C;
  ru = e.ru;
  rv = e.rv;
  if (wu != EL_MIPMAP_WRAP_REPEAT && (x + ru < -1.0f || x - ru > (float)nu)) {
    if (wu == EL_MIPMAP_WRAP_BLACK) {
      for (c = 0; c < C; ++c) out[c] = 0.0f;
      return;
    }
    x = el_mipmap__pin(x, ru, nu);
  }
  if (m->wrap_v != EL_MIPMAP_WRAP_REPEAT && (y + rv < -1.0f || y - rv > (float)nv)) {
    if (m->wrap_v == EL_MIPMAP_WRAP_BLACK) {
      for (c = 0; c < C; ++c) out[c] = 0.0f;
      return;
    }
    y = el_mipmap__pin(y, rv, nv);
  }
  t0 = el_mipmap__iceil(y - rv);
  t1 = el_mipmap__ifloor(y + rv);
  /* <<Scan over ellipse bound and compute quadratic equation>>, one chord per row */
  for (c = 0; c < C; ++c) acc[c] = 0.0f;
  inv2A = 0.5f / A;
  fourA = 4 * A;
  mg = 0.05f + 1e-6f * (fabsf(x) + ru); /* covers the rounding of the chord's ends */
  if (x - ru - mg > 1.0f && x + ru + mg < (float)nu - 2.0f && t0 >= 0 && t1 < nv) {
    /* the whole ellipse inside the level (the common case; 3 channels try el_mipmap__ewa3_inside
     * first): no wrapping on any row */
    const float *rp = data + (size_t)t0 * rowstride;
    for (it = t0, fit = (float)t0; it <= t1; ++it, fit += 1.0f, rp += rowstride) {
      float tt = fit - y;
      float ctt = Cc * tt * tt, btt = B * tt;
      float disc = btt * btt - fourA * (ctt - 1);
      float cs = x - btt * inv2A, hw = (disc > 0 ? sqrtf(disc) * inv2A : 0.0f) + mg;
      int lo = -el_mipmap__ifloor_nb(hw - cs), hi = el_mipmap__ifloor_nb(cs + hw);
      if (lo <= hi)
        el_mipmap__ewa_span(rp + (size_t)lo * (size_t)C, rp + (size_t)hi * (size_t)C, (float)lo, x, A, B, tt, ctt,
                            acc, &sumw, C);
    }
    t1 = t0 - 1; /* done: skip the general loop */
  }
  for (it = t0, fit = (float)t0; it <= t1; ++it, fit += 1.0f) {
    float tt = fit - y; /* fit == (float)it exactly: pbrt's it - st[1] */
    float ctt = Cc * tt * tt, btt = B * tt;
    float disc = btt * btt - fourA * (ctt - 1);
    float cs = x - btt * inv2A, hw = (disc > 0 ? sqrtf(disc) * inv2A : 0.0f) + mg;
    int lo = -el_mipmap__ifloor_nb(hw - cs), hi = el_mipmap__ifloor_nb(cs + hw), row, is, col;
    float fis;
    const float *rp, *p;
    /* (no need to clip [lo, hi] to pbrt's box [s0, s1]: texels outside it have r2 >= 1 but for
     * rounding at the tangent points, where the table weight is 0 anyway) */
    if (lo > hi) continue;
    row = (unsigned)it < (unsigned)nv ? it : el_mipmap__wrap(it, nv, m->wrap_v);
    fis = (float)lo;
    if (row < 0) { /* a Black row: texels count with value 0, as in pbrt */
      for (is = lo; is <= hi; ++is, fis += 1.0f) {
        float ss = fis - x;
        float r2 = A * ss * ss + B * ss * tt + ctt;
        if (r2 < 1) sumw += el_mipmap__weight_lut[(int)(r2 * 128) & 127];
      }
      continue;
    }
    rp = data + (size_t)row * rowstride;
    if ((unsigned)lo < (unsigned)nu && (unsigned)hi < (unsigned)nu) { /* inside: no wrapping */
      el_mipmap__ewa_span(rp + (size_t)lo * (size_t)C, rp + (size_t)hi * (size_t)C, fis, x, A, B, tt, ctt, acc, &sumw,
                          C);
    } else if (wu == EL_MIPMAP_WRAP_REPEAT) { /* the column index walks and wraps */
      for (is = lo, col = el_mipmap__wrap(lo, nu, wu); is <= hi; ++is, fis += 1.0f) {
        float ss = fis - x;
        float r2 = A * ss * ss + B * ss * tt + ctt;
        if (r2 < 1) {
          float wgt = el_mipmap__weight_lut[(int)(r2 * 128) & 127];
          p = rp + (size_t)col * (size_t)C;
          for (c = 0; c < C; ++c) acc[c] += p[c] * wgt;
          sumw += wgt;
        }
        if (++col == nu) col = 0;
      }
    } else {
      for (is = lo; is <= hi; ++is, fis += 1.0f) {
        float ss = fis - x;
        float r2 = A * ss * ss + B * ss * tt + ctt;
        if (r2 < 1) {
          float wgt = el_mipmap__weight_lut[(int)(r2 * 128) & 127];
          col = el_mipmap__wrap(is, nu, wu);
          if (col >= 0) {
            p = rp + (size_t)col * (size_t)C;
            for (c = 0; c < C; ++c) acc[c] += p[c] * wgt;
          }
          sumw += wgt; /* Black texels count with value 0, as in pbrt */
        }
      }
    }
  }
  if (!(sumw > 0.0f)) { /* cannot happen (the ellipse holds a disc of radius 1), kept as a guard */
    for (c = 0; c < C; ++c) out[c] = 0.0f;
    return;
  }
  for (c = 0; c < C; ++c) out[c] = acc[c] / sumw;
}
EL_MIPMAP__NOINLINE void el_mipmap__ewa3(const el_mipmap *m, int level, float s, float t, float d0s,
                                         float d0t, float d1s, float d1t, float *out) {
  el_mipmap__ewa_c(m, level, s, t, d0s, d0t, d1s, d1t, out, 3);
}

/* The texels p..last (inclusive, 3 floats each) of one row for el_mipmap__ewa3_inside; ss is the
 * first one's is - x. Two texels per iteration. */
EL_MIPMAP__INLINE void el_mipmap__ewa3_span(const float *p, const float *last, float ss, float A, float B,
                                            float tt, float ctt, float *acc, float *sumw) {
  int c;
  float sw = *sumw;
  for (; p < last; p += 6, ss += 2.0f) {
    float ss1 = ss + 1.0f;
    float r2 = A * ss * ss + B * ss * tt + ctt, r21 = A * ss1 * ss1 + B * ss1 * tt + ctt;
    if (r2 < 1) {
      /* r2 in [0, 1) up to rounding, so (int)(r2 * 128) is 0..127; & 127 keeps any rounding accident
       * inside the table */
      float wgt = el_mipmap__weight_lut[(int)(r2 * 128) & 127];
      for (c = 0; c < 3; ++c) acc[c] += p[c] * wgt;
      sw += wgt;
    }
    if (r21 < 1) {
      float wgt = el_mipmap__weight_lut[(int)(r21 * 128) & 127];
      for (c = 0; c < 3; ++c) acc[c] += p[3 + c] * wgt;
      sw += wgt;
    }
  }
  if (p == last) { /* an odd count: the last texel */
    float r2 = A * ss * ss + B * ss * tt + ctt;
    if (r2 < 1) {
      float wgt = el_mipmap__weight_lut[(int)(r2 * 128) & 127];
      for (c = 0; c < 3; ++c) acc[c] += p[c] * wgt;
      sw += wgt;
    }
  }
  *sumw = sw;
}

/* pbrt's EWA() on one level for 3 channels when the ellipse lies inside the level with a texel to
 * spare on every side (the common case): x - ru > 1, y - rv > 1, x + ru < w - 2, y + rv < h - 1.
 * Returns 0, having written nothing, otherwise. No wrapping, and:
 *  - is - x is exact (x > 1 + ru, so |is - x| < x < 2^24 ulp(x), and is is a multiple of ulp(x)), so
 *    each row steps ss by 1 from its first texel and gets pbrt's ss bit for bit; the same holds for
 *    it - y, so tt steps by 1 from row to row;
 *  - all the bounds are positive, so (int) is floor: pbrt's box is s0 = ceil(x - ru) .. s1 =
 *    floor(x + ru) and t0 .. t1; (int)(v) + 1 is ceil(v) unless v is an integer, and then it leaves
 *    out the column or row that touches the ellipse, where r2 >= 1 (or within rounding of 1, where the
 *    table weight is 0, which pbrt adds as 0);
 *  - each row's chord comes from the ellipse's equation solved for ss: centre x - B tt / (2 A), half
 *    width sqrt(1/A - det tt^2 / (4 A^2)) plus the margin mg, clipped to pbrt's [s0, s1]. Its error
 *    in half width squared (det's cancellation, a few 1e-3 relative at worst since A C / F < 8000 on
 *    this path and far less at anisotropy 8, times 1/A) is below the gap between the chords of
 *    r2 = 127/128 and r2 = 1, (1/A)/128: a texel it leaves out has r2 >= 127/128 by pbrt's
 *    arithmetic too (same A, B, C), whose table weight is 0. */
EL_MIPMAP__INLINE int el_mipmap__ewa3_inside(const el_mipmap *m, int level, float s, float t, float d0s,
                                             float d0t, float d1s, float d1t, float *out) {
  el_mipmap__ellipse e;
  const float *rp;
  float mg, P, Q, K, tt, acc[3] = {0.0f, 0.0f, 0.0f}, sumw = 0.0f;
  int s0, s1, it, t1;
  size_t stride;
  if (level >= m->levels) return 0;
  el_mipmap__ellipse_init(m->level_size[level], s, t, d0s, d0t, d1s, d1t, &e);
  mg = 0.05f + 1e-6f * (e.x + e.ru); /* covers the rounding of the chord's centre (x > 0 below) */
  if (!(e.x - e.ru - mg > 1.0f && e.x + e.ru + mg < m->level_size[level][0] - 2.0f && e.y - e.rv > 1.0f &&
        e.y + e.rv < m->level_size[level][1] - 1.0f))
    return 0; /* (also NaN) */
  /* <<Compute the ellipse's (s,t) bounding box in texture space>> */
  s0 = (int)(e.x - e.ru) + 1;
  s1 = (int)(e.x + e.ru);
  it = (int)(e.y - e.rv) + 1;
  t1 = (int)(e.y + e.rv);
  P = 1 / e.A;               /* the half width squared of the centre row */
  Q = e.det * 0.25f * P * P; /* its decrease per tt^2 */
  K = -0.5f * e.B * P;       /* the chord's centre moves by K per row */
  stride = (size_t)m->level_width[level] * 3;
  rp = m->level_data[level] + (size_t)it * stride;
  /* <<Scan over ellipse bound and compute quadratic equation>>, one chord per row */
  for (tt = (float)it - e.y; it <= t1; ++it, tt += 1.0f, rp += stride) {
    float ctt = e.C * tt * tt, h2 = P - Q * (tt * tt), cs = e.x + K * tt;
    float hw = (h2 > 0.0f ? sqrtf(h2) : 0.0f) + mg;
    int lo = (int)(cs - hw) + 1, hi = (int)(cs + hw); /* ceil and floor where it matters (> 0) */
    if (lo < s0) lo = s0;
    if (hi > s1) hi = s1;
    if (lo <= hi)
      el_mipmap__ewa3_span(rp + 3 * (size_t)lo, rp + 3 * (size_t)hi, (float)lo - e.x, e.A, e.B, tt, ctt, acc,
                           &sumw);
  }
  if (!(sumw > 0.0f)) return 0; /* cannot happen (the ellipse holds a disc of radius 1), kept as a guard */
  out[0] = acc[0] / sumw;
  out[1] = acc[1] / sumw;
  out[2] = acc[2] / sumw;
  return 1;
}

static void el_mipmap__ewa(const el_mipmap *m, int level, float s, float t, float d0s, float d0t,
                           float d1s, float d1t, float *out) {
  switch (m->channels) {
  case 1: el_mipmap__ewa_c(m, level, s, t, d0s, d0t, d1s, d1t, out, 1); break;
  case 2: el_mipmap__ewa_c(m, level, s, t, d0s, d0t, d1s, d1t, out, 2); break;
  case 3: el_mipmap__ewa_c(m, level, s, t, d0s, d0t, d1s, d1t, out, 3); break;
  default: el_mipmap__ewa_c(m, level, s, t, d0s, d0t, d1s, d1t, out, 4); break;
  }
}

EL_DEF void el_mipmap_lookup_differentials(const el_mipmap *m, float s, float t, float dsdx, float dtdx,
                                           float dsdy, float dtdy, float *out) {
  float d0s = el_mipmap__sane_d(dsdx), d0t = el_mipmap__sane_d(dtdx);
  float d1s = el_mipmap__sane_d(dsdy), d1t = el_mipmap__sane_d(dtdy);
  float l0, l1, major, minor, f, a[4], b[4];
  int ilod, c, C = m->channels;
  if (m->filter != EL_MIPMAP_FILTER_EWA) {
    float w = fabsf(d0s);
    if (fabsf(d0t) > w) w = fabsf(d0t);
    if (fabsf(d1s) > w) w = fabsf(d1s);
    if (fabsf(d1t) > w) w = fabsf(d1t);
    if (m->filter == EL_MIPMAP_FILTER_TRILINEAR) el_mipmap_lookup(m, s, t, w, out); /* pbrt-v3 (aaa552a) */
    else el_mipmap_lookup_filtered(m, m->filter, s, t, 2 * w, out);               /* pbrt-v4 */
    return;
  }
  /* <<Compute ellipse minor and major axes>> */
  l0 = d0s * d0s + d0t * d0t;
  l1 = d1s * d1s + d1t * d1t;
  if (l0 < l1) {
    float tmp = d0s;
    d0s = d1s;
    d1s = tmp;
    tmp = d0t;
    d0t = d1t;
    d1t = tmp;
    tmp = l0;
    l0 = l1;
    l1 = tmp;
  }
  major = sqrtf(l0);
  minor = sqrtf(l1);
  /* <<Clamp ellipse eccentricity if too large>> */
  if (minor * m->max_anisotropy < major && minor > 0) {
    float scale = major / (minor * m->max_anisotropy);
    d1s *= scale;
    d1t *= scale;
    minor *= scale;
  }
  if (minor == 0) {
    el_mipmap__bilerp(m, 0, el_mipmap__sane(s, m->wrap_u), el_mipmap__sane(t, m->wrap_v), out);
    return;
  }
  /* <<Choose level of detail for EWA lookup and perform EWA filtering>> */
  el_mipmap__level(minor, m->levels, &ilod, &f); /* lod = ilod + f */
  if (ilod < 0) { /* lod = max(0, ...) */
    ilod = 0;
    f = 0;
  }
  if ((ilod > 0 || f > 0) && !el_mipmap__ensure(m)) { /* out of memory: level 0 only */
    ilod = 0;
    f = 0;
  }
  s = el_mipmap__sane_ewa(s, m->wrap_u);
  t = el_mipmap__sane_ewa(t, m->wrap_v);
  if (C == 3) { /* the common case, specialised: one inlined copy for both levels */
    int k;
    b[0] = b[1] = b[2] = 0.0f; /* when f == 0: pbrt computes (1 - 0) a + 0 b = a as well */
    for (k = 0; k <= (f > 0); ++k)
      if (!el_mipmap__ewa3_inside(m, ilod + k, s, t, d0s, d0t, d1s, d1t, k ? b : a))
        el_mipmap__ewa3(m, ilod + k, s, t, d0s, d0t, d1s, d1t, k ? b : a);
    out[0] = (1 - f) * a[0] + f * b[0];
    out[1] = (1 - f) * a[1] + f * b[1];
    out[2] = (1 - f) * a[2] + f * b[2];
    return;
  }
  el_mipmap__ewa(m, ilod, s, t, d0s, d0t, d1s, d1t, a);
  if (f == 0) { /* pbrt computes (1 - 0) a + 0 b = a as well */
    for (c = 0; c < C; ++c) out[c] = a[c];
    return;
  }
  el_mipmap__ewa(m, ilod + 1, s, t, d0s, d0t, d1s, d1t, b);
  for (c = 0; c < C; ++c) out[c] = (1 - f) * a[c] + f * b[c];
}
/* << mipmap implementation */

#endif /* EL_MIPMAP_IMPLEMENTATION_DONE */
#endif /* implementation */

/* Version history
 *   0.1.0  first release: pbrt-v3 MIPMap (resampling, box levels, Texel, triangle, trilinear, EWA),
 *          per-axis wrap, point/bilinear filters, lazy thread-safe upper levels, keep_resolution.
 *
 * Licence: MIT or public domain (choose one), like stb.
 *   MIT: Copyright (c) 2026 the envlight authors. Permission is hereby granted, free of charge, to any
 *   person obtaining a copy of this software, to deal in it without restriction, including the rights
 *   to use, copy, modify, merge, publish, distribute, sublicense and/or sell copies, subject to
 *   including this notice. THE SOFTWARE IS PROVIDED "AS IS", WITHOUT WARRANTY OF ANY KIND.
 *   Public domain: anyone may use this file for any purpose, without any conditions.
 */
