/* envlight.h - pbrt's infinite area light (a latitude-longitude environment map): radiance, importance
 * sampling, pdfs and power, numerically hardened. envlight v0.1.0 - MIT or public domain
 *
 * DO THIS in exactly one C or C++ file (the first line alone is enough):
 *     #define EL_IMPLEMENTATION   // implements every envlight header included after it
 *     #include "envlight.h"
 * Every other file includes it without the macro. envlight.h includes distribution2d.h for its
 * declarations. EL_ENVLIGHT_IMPLEMENTATION instead implements envlight.h alone, not distribution2d.h
 * (which then needs EL_DISTRIBUTION2D_IMPLEMENTATION too, or the link fails): a module's own macro
 * never implements another module's header.
 *
 * USAGE (C; where C writes `= {0}`, C++ writes `= {}`; tests/test_snippets.c compiles both)
 * >> usage
 *     // given: const float *rgb; int width, height; const float u[2], wi_bsdf[3]; float *pdf_mis, Le[3];
 *     el_envlight light;                             // rgb: width * height * 3 floats, row 0 = theta 0
 *     el_envlight_options opt = {0};                 // C++: = {}. All zero: pbrt-v3's light
 *     el_envlight_yup_matrix(opt.light_to_world);    // y-up right-handed world, as Mitsuba 3 shows maps
 *     if (el_envlight_init(&light, rgb, width, height, 3, &opt) != EL_SUCCESS) return 1;  // light.bad_index
 *     float wi[3], L[3], pdf;
 *     el_envlight_sample_li(&light, u, wi, L, &pdf); // builds the sampling tables on first use
 *     *pdf_mis = el_envlight_pdf_li(&light, wi_bsdf);  // the light's pdf of a BSDF sample, for MIS
 *     el_envlight_le(&light, wi_bsdf, Le);           // radiance along a ray that escapes (no tables)
 *     el_envlight_free(&light);
 * << usage
 * The caller skips a sample whose pdf is 0, as pbrt does; el_envlight_sample_li_n draws n at once.
 *
 * OPTIONS (define before including): EL_MALLOC / EL_REALLOC / EL_FREE (all or none), EL_ASSERT,
 * EL_STATIC, EL_DEF; EL_NO_SIMD (the scalar code instead of SSE2: the same results);
 * EL_ENVLIGHT_NO_ATOMICS (no thread-safe lazy build: call el_envlight_prepare_sampling first).
 *
 * PORTS pbrt-v3's InfiniteAreaLight (src/lights/infinite.h, infinite.cpp): the constructor's
 * distribution (a Distribution2D over the map's luminance times sin theta), Le, Sample_Li, Pdf_Li,
 * Sample_Le, Pdf_Le, Power and Preprocess, with pbrt-v3's mapping (u, v) = (phi / 2pi, theta / pi);
 * and pbrt-v4 ImageInfiniteLight's MIS-compensated distribution and equal-area square maps. Beyond
 * pbrt: product sampling (map x cosine), hot spots (a sun) as a mixture, portals (windows; pbrt-v4's
 * PortalImageInfiniteLight with a cheaper sampler). NOTES after the declarations: the
 * mapping and its orientation, where and why it departs from pbrt (the density, the poles, the integer
 * CDF), what it costs, memory, thread safety, input conventions.
 */
#ifndef EL_ENVLIGHT_H
#define EL_ENVLIGHT_H

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

#include "distribution2d.h"

#ifdef __cplusplus
extern "C" {
#endif

/* >> declarations */

/* How the importance map (the bins the sampler draws from) is computed from the image. */
#define EL_ENVLIGHT_IMPORTANCE_CELL_AVERAGE 0 /* default: exact mean of the bilinear le() over each bin */
#define EL_ENVLIGHT_IMPORTANCE_PBRT_V3 1      /* pbrt-v3: 2x the image resolution, le() at bin centres */
#define EL_ENVLIGHT_IMPORTANCE_TEXEL 2        /* raw texel luminance, image resolution (biased with a
                                                 bilinear le: kept to measure issue #62) */
/* Which sampler draws from it (all three have identical pdfs). The default is the guide table: it
 * returns exactly the points of CDF inversion (pbrt's), so all-zero options still mean pbrt's samples,
 * at 175 instead of 428 instructions per sample_li for 1 byte per bin. */
#define EL_ENVLIGHT_SAMPLER_GUIDE 0 /* default: guide table, O(1) expected; CDF inversion's points */
#define EL_ENVLIGHT_SAMPLER_CDF 1   /* two binary searches (pbrt's method); the same points */
#define EL_ENVLIGHT_SAMPLER_ALIAS 2 /* alias table: O(1); does not keep stratification */
/* What init does with NaN, infinite or negative texels. */
#define EL_ENVLIGHT_BAD_TEXELS_ERROR 0 /* default: an error naming the texel (el_envlight.bad_index) */
#define EL_ENVLIGHT_BAD_TEXELS_ZERO 1  /* they become 0 */
#define EL_ENVLIGHT_BAD_TEXELS_CLAMP_NEGATIVE 2 /* finite negatives become 0; NaN and infinite texels stay
                                                  errors. For lossy files: DWAA/DWAB-compressed EXRs (e.g. the
                                                  HDRIs Blender ships) ring to small negatives, -0.0039 at worst
                                                  on those maps; el_envlight.negative_texels counts them */

/* The largest importance-map resolution per axis (the 2^-21 in-bin margin must stay far below a bin). */
#define EL_ENVLIGHT_MAX_IMPORTANCE 65536
/* The default cap of the importance map's width (its height: half of it): a map wider than 4096 is
 * summarised by 4096 x 2048 exact cell averages (73 MB of tables at most) unless options.importance_cap
 * says otherwise; maps up to 4096x2048 (and pbrt-v3's 2x map of a 2048x1024 image) are untouched. Chosen
 * by measurement (NOTES: BIG MAPS): on a 16k map with a 0.5-degree sun it costs 1.9x the irradiance
 * variance of the full resolution for 6% of its tables (2048: 3.2x for 1.6%). */
#define EL_ENVLIGHT_IMPORTANCE_CAP 4096
/* How the image maps to the sphere (options.mapping). */
#define EL_ENVLIGHT_MAPPING_LATLONG 0    /* default: pbrt-v3's latitude-longitude map, width x height */
#define EL_ENVLIGHT_MAPPING_EQUAL_AREA 1 /* pbrt-v4's square equal-area octahedral map (Clarberg 2008), N x N */
/* The radii el_envlight_preprocess accepts: 2^-64 and 2^62, where sample_le's pdf_pos = 1 / (pi r^2)
 * is still a finite, normal float. */
#define EL_ENVLIGHT_MIN_RADIUS 5.42101086e-20f
#define EL_ENVLIGHT_MAX_RADIUS 4.61168602e18f

/* All zero = pbrt-v3's InfiniteAreaLight with the image's own resolution for the importance map. */
typedef struct el_envlight_options {
  float scale[3];          /* RGB multiplier of the texels (pbrt's "L"); all zero means (1, 1, 1) */
  float light_to_world[9]; /* row-major 3x3, world = M * light; a rotation or a reflection (checked to
                              1e-4, then re-orthonormalised). All zero means the identity. */
  int compensated;         /* 1: pbrt-v4's MIS-compensated density (NOTES: MIS COMPENSATION) */
  int importance;          /* EL_ENVLIGHT_IMPORTANCE_* */
  int importance_width;    /* bins of the importance map; 0, 0: the image's resolution (PBRT_V3: twice */
  int importance_height;   /*  it), each capped at EL_ENVLIGHT_MAX_IMPORTANCE. TEXEL ignores these. */
  int sampler;             /* EL_ENVLIGHT_SAMPLER_* */
  int bad_texels;          /* EL_ENVLIGHT_BAD_TEXELS_*; what became 0 is reported in the light's fields */
  /* big maps and pbrt-v4's maps (issue 24; NOTES: BIG MAPS, EQUAL-AREA MAPS) */
  int importance_cap;      /* when importance_width is 0: the largest importance width (height: half; an
                              equal-area map: half per axis). 0: EL_ENVLIGHT_IMPORTANCE_CAP; < 0: no cap */
  int no_copy;             /* 1: keep a pointer to the caller's pixels instead of copying them (channels 3,
                              scale all zero or (1, 1, 1)); they must stay alive and unchanged until
                              el_envlight_free. A texel bad_texels must replace makes init copy after all */
  int mapping;             /* EL_ENVLIGHT_MAPPING_* */
} el_envlight_options;

/* The light. PUBLIC (read, never write): width, height, bad_index and what init replaced by 0
 * (negative_texels, nonfinite_texels, most_negative, most_negative_index). Every other field is PRIVATE:
 * the implementation's state and tables, which may change in any version without notice; read the
 * light through the functions below (el_envlight_le, el_envlight_bytes, ...) and change it only through
 * el_envlight_init / el_envlight_preprocess / el_envlight_free. */
typedef struct el_envlight {
  int width, height;       /* PUBLIC: the image; 0 x 0 for a constant light */
  /* ---- private from here on (but bad_index and the counts, below) ---- */
  float *texels;           /* width*height*3, scaled, row 0 = theta 0 */
  float constant[3];       /* the radiance of a constant light (scaled) */
  float to_world[9];       /* row-major, orthonormal */
  int exact_transform;     /* 1 when to_world is a signed permutation (round trips are exact) */
  int perm[3], iperm[3];   /* then world[i] = sign[i] * light[perm[i]], light[j] = isign[j] * world[iperm[j]] */
  float sign[3], isign[3];
  int compensated, importance, sampler, imp_w, imp_h;
  double integral[3];      /* integral of le over the sphere, per channel (for power()) */
  float center[3], radius; /* the scene's bounding sphere (preprocess) */
  /* sampling tables, built on first need */
  int state;               /* 0: not built, 1: being built, 2: ready, 3: failed (queries give pdf 0) */
  el_result sampling_result;
  int fell_back;           /* compensated map was empty: the plain density is used */
  el_distribution2d dist;
  el_distribution2d_fast fast;
  /* bin finders for pdf_li without atan: cell c of a table over a monotone angle parameter holds the
   * number of bin edges below the cell and the one edge inside it (or 2 / 5 when none) */
  int *u_base, *v_base;
  float *u_edge, *v_edge;
  int u_cells, v_cells;
  float u_cell_scale, v_cell_scale;
  float u_margin, v_margin;  /* EL_ENVLIGHT__MARGIN in bin units (plus rounding slack) */
  float *pdf_table;        /* nu*nv: the distribution's pdf of each bin / (2 pi^2) */
  /* sample_li's direction tables (maps with nu >= 128 and nv >= 64; else the sinpi/cospi path): row j
   * holds sin and cos of its edge nearer a pole (theta_j = pi j / nv in the north, pi (j+1) / nv in the
   * south) and the offset of that edge in bins (0 or -1); column i holds phi_i = 2 pi i / nu's cos and sin
   * already multiplied into the matrix (below). The point's angles are edge + fraction * bin angle, by
   * angle addition. */
  int dir_tables;
  int hot;                 /* flags stored with release after the tables: EL_ENVLIGHT__HOT_SAMPLE (1) sample_li's
                              inline guide path is usable and its result final, ..._SAMPLE_FINISH (4) usable
                              with the pdf recomputed, EL_ENVLIGHT__HOT_PDF (2) pdf_li's inline path is usable */
  float *dir_consts;       /* 12 16-byte aligned 4-vectors; lanes (v, v, u, u): the margins, 1 - the margins,
                              the bin angles (pi / nv, 2 pi / nu); M2 = the third column of to_world, 0; the
                              polynomial coefficients -1/6, 1, -1/2, 0; for the SSE search, lanes (u0, u1,
                              u0, u1): 2^24, 2^24, guide cells per row, guide cells of the marginal; the
                              clamp 0x1.fffffep-1; pdf_k, 0, 0, 0; zeros. Kept here (not as constants in the
                              code) so that the compiler uses them as memory operands */
  float *row_tab;          /* nv * 16, aligned: s = sin theta_ref, c = cos theta_ref, 0, 0, then c, -s, 0, 0,
                              then the offset of the reference edge in bins (0 or -1) twice, 0, 0; then (guide
                              sampler) two pointers: the row's CDF row and its guide row, which sample_li's SSE
                              search reads from the same 64-byte record */
  float *col_tab;          /* nu * 8, aligned: P_i = cos phi_i M0 + sin phi_i M1, 0, Q_i = cos phi_i M1 -
                              sin phi_i M0, 0 (M0, M1: the first two columns of to_world), so that the world
                              direction is sin theta (cos b P_i + sin b Q_i) + cos theta M2 */
  void *dir_alloc;         /* the allocation holding the three */
  const uint32_t **gv_ptr; /* guide sampler: the marginal guide as pointers into dist.marginal (bit 0 set: a
                              crowded cell), and the row record of marginal entry p at row_key + 16 p (as
                              integers; computed once, so sample_li needs neither the marginal's base nor v) */
  uintptr_t row_key;
  int table_done;          /* exact_transform and not all-zero (so every sampled bin has p > 0): the table
                              direction and pdf are final unless the radiance is wanted */
  float v_angle, u_angle;  /* pi / nv, 2 pi / nu */
  float u_margin_hi, v_margin_hi; /* 1 - u_margin, 1 - v_margin */
  int bad_index;           /* PUBLIC. After init: the index y*width+x of the first bad texel when init failed on one
                              (EL_ERROR_NAN, _INFINITE, _NEGATIVE), else -1. A failed init zeroes every
                              other field. */
  /* PUBLIC. After a successful init: the texels that bad_texels ZERO or CLAMP_NEGATIVE replaced by 0
   * (for a warning such as "299 negative texels clamped to 0, the most negative -0.0016 at (x, y)"). A
   * texel counts once however many of its channels were replaced; the constant light counts as one. */
  size_t negative_texels;  /* texels with a finite negative channel */
  size_t nonfinite_texels; /* texels with a NaN or infinite channel or a scaled value that overflowed (ZERO) */
  float most_negative;     /* the most negative channel value as given (before the scale); 0 when none */
  int most_negative_index; /* its texel y*width+x; -1 when none */
  /* ---- private again ---- product sampling and the bilinear warp (NOTES ON PRODUCT SAMPLING below the
   * API): their own tables, built on first use with their own once-flags (the same scheme as state) */
  int warp_state, cos_state;        /* 0 not built, 1 being built, 2 ready, 3 failed */
  el_result warp_result, cos_result;
  struct el_envlight__warp *warp;   /* the warp's cells and CDFs (private) */
  struct el_envlight__warp *prod;   /* product sampling's patches, cells and normal tables (private; cos_state) */
  int mapping;             /* EL_ENVLIGHT_MAPPING_* */
  int borrowed;            /* 1: texels is the caller's array (options.no_copy): never written nor freed */
} el_envlight;

/* pixels: width*height*channels floats (row-major, row 0 first), copied into RGB. channels 1 (grey) or
 * 2 (grey, alpha) give (g, g, g); 3 and 4 give RGB (alpha ignored, not checked). opt may be NULL (all-zero
 * options). On failure *l is zeroed but for l->bad_index, which names the first bad texel (or is -1);
 * freeing it is safe. */
EL_DEF el_result el_envlight_init(el_envlight *l, const float *pixels, int width, int height, int channels,
                                  const el_envlight_options *opt);
/* A constant-radiance light (pbrt-v3's InfiniteAreaLight without a map): uniform sphere sampling, pdf
 * 1 / 4 pi (0 when rgb is black); options.compensated has no effect (the map would fall back anyway). */
EL_DEF el_result el_envlight_init_constant(el_envlight *l, const float rgb[3], const el_envlight_options *opt);
EL_DEF void el_envlight_free(el_envlight *l);
/* Build the sampling tables now (they are otherwise built on first need). Returns their build result;
 * safe to call more than once and from several threads (NOTES below, point 6). */
EL_DEF el_result el_envlight_prepare_sampling(el_envlight *l);
/* pbrt's Preprocess: the scene's bounding sphere, used by sample_le, pdf_le and power only. Accepts a
 * finite centre and a radius in [EL_ENVLIGHT_MIN_RADIUS, EL_ENVLIGHT_MAX_RADIUS] (2^-64 .. 2^62) that
 * is at least 2^-20 max|centre[k]| (so that sample_le's disk spans at least 8 float steps around the
 * centre); then every output of sample_le, pdf_le and power is finite. Otherwise EL_ERROR_NAN,
 * EL_ERROR_INFINITE (a centre or radius component that is NaN / infinite) or EL_ERROR_INVALID_ARGUMENT
 * (NULL, a radius <= 0 or outside those bounds), and the light keeps its previous sphere. */
EL_DEF el_result el_envlight_preprocess(el_envlight *l, const float center[3], float radius);

/* Radiance arriving along -dir (a ray leaving the scene along dir). Reads only: never builds tables. */
EL_DEF void el_envlight_le(const el_envlight *l, const float dir[3], float rgb[3]);
/* Sample a direction wi (world, unit) with solid-angle density *pdf; rgb (may be NULL) gets the radiance:
 * le(wi) bit for bit under a general rotation and in importance BILINEAR; with a signed-permutation
 * matrix (identity, y-up, z-up) le at the sample's own (u, v), which differs from le(wi) only as a
 * shift of at most 1e-4 texel would (le's atan rounds; NOTES 4). */
EL_DEF void el_envlight_sample_li(const el_envlight *l, const float u[2], float wi[3], float rgb[3], float *pdf);
/* n samples at once: wi[3i..], rgb[3i..] (rgb may be NULL) and pdf[i] for u[2i], u[2i+1], bit for bit
 * what n calls of sample_li return. For renderers that draw several light samples before using them
 * (a pixel's samples, a wavefront): the table and texel reads of up to 32 samples are started together
 * (prefetched in stages) instead of one dependent cache miss after another. n <= 0 does nothing. The
 * output arrays must not overlap u (as for every _n call below: outputs never alias inputs). */
EL_DEF void el_envlight_sample_li_n(const el_envlight *l, int n, const float *u, float *wi, float *rgb, float *pdf);
/* The solid-angle density with which sample_li picks dir. */
EL_DEF float el_envlight_pdf_li(const el_envlight *l, const float dir[3]);
/* n at once: pdf[i] = pdf_li(dirs[3i..]) and rgb[3i..] = le(dirs[3i..]), bit for bit, for a wave's
 * escaped rays: the table entries (le's texels) of up to 32 directions are prefetched together, so that
 * their cache misses overlap: 2-2.5x less time on a 2048x1024 map (NOTES 5: BATCHES). n <= 0 does nothing;
 * pdf and rgb must not overlap dirs. */
EL_DEF void el_envlight_pdf_li_n(const el_envlight *l, int n, const float *dirs, float *pdf);
EL_DEF void el_envlight_le_n(const el_envlight *l, int n, const float *dirs, float *rgb);
/* pbrt-v3 Sample_Le: u[0],u[1] pick the direction, u[2],u[3] the point on the disk of the bounding
 * sphere facing it. ray_dir points INTO the scene; normal = ray_dir (pbrt's nLight). pdf_pos is w.r.t.
 * area of the disk (1 / (pi r^2)), pdf_dir w.r.t. solid angle. Before preprocess (radius 0): all zero. */
EL_DEF void el_envlight_sample_le(const el_envlight *l, const float u[4], float ray_org[3], float ray_dir[3],
                                  float normal[3], float rgb[3], float *pdf_pos, float *pdf_dir);
/* pbrt-v3 Pdf_Le for a ray entering the scene along ray_dir. */
EL_DEF void el_envlight_pdf_le(const el_envlight *l, const float ray_dir[3], float *pdf_pos, float *pdf_dir);
/* pi r^2 * integral(le) d omega (pbrt-v4's Phi); 0 before preprocess. */
EL_DEF void el_envlight_power(const el_envlight *l, float rgb[3]);
/* integral(le) d omega over the sphere, per channel (exact for the bilinear reconstruction). */
EL_DEF void el_envlight_integral(const el_envlight *l, float rgb[3]);
/* Bytes in use: the struct, the texels (not the caller's, with options.no_copy) and the tables built. */
EL_DEF size_t el_envlight_bytes(const el_envlight *l);
/* Bytes of the sampling tables alone (0 until built). */
EL_DEF size_t el_envlight_sampling_bytes(const el_envlight *l);

/* The light_to_world matrices for the usual right-handed worlds (NOTES below: MAPPING AND ORIENTATION). */
EL_DEF void el_envlight_yup_matrix(float m[9]);
EL_DEF void el_envlight_zup_matrix(float m[9]);

/* The light-space mapping itself (no matrix): dir -> (u, v) in [0,1] (zero / NaN dir: 0, 0), and
 * (u, v) -> unit dir. Both use the same polynomials as the light. */
EL_DEF void el_envlight_dir_to_uv(const float dir[3], float *u, float *v);
EL_DEF void el_envlight_uv_to_dir(float u, float v, float dir[3]);
/* The same for pbrt-v4's equal-area square (EqualAreaSphereToSquare / EqualAreaSquareToSphere, light space:
 * +z is the square's centre, -z its corners). Accurate to about 2e-7 in (u, v) (pbrt-v4's polynomial: 4e-6). */
EL_DEF void el_envlight_dir_to_square(const float dir[3], float *u, float *v);
EL_DEF void el_envlight_square_to_dir(float u, float v, float dir[3]);

/* << declarations */

/* >> declarations: product sampling and the bilinear warp (issue 13; NOTES ON PRODUCT SAMPLING below) */

/* Importance mode 3: the density is the bilinear interpolant of le()'s luminance times sin(theta) over
 * le()'s own patches (Mitsuba 3's density), so lum(le) / pdf is nearly constant and low-discrepancy points
 * keep their stratification through the warp: a discrete table over the patches, then a bilinear warp
 * inside one. sample_li, sample_li_n, pdf_li, sample_le and pdf_le use it; about 515 / 240 instructions
 * instead of 97 / 76 (NOTES ON PRODUCT SAMPLING 1). */
#define EL_ENVLIGHT_IMPORTANCE_BILINEAR 3

/* Table sizes of product sampling (all zero: the defaults, 64 x 32 cells and 32 x 32 normal bins). */
typedef struct el_envlight_product_options {
  int cells_u, cells_v; /* the warp's cells (both or neither; each 1..256, capped at the map's patches) */
  int normal_bins;      /* octahedral normal bins per axis, 1..256 (normal_bins^2 cell tables) */
} el_envlight_product_options;

/* Sample a direction wi (world, unit) for a surface of world normal n, with a density close to
 * L(wi) max(0, n.wi): *pdf is its solid-angle density, rgb (may be NULL) gets le(wi), bit for bit.
 * n need not be unit length (only its direction counts; it must point to the side the light arrives
 * from); a zero, NaN or infinite n gives no sample (pdf 0).
 * Directions fall below the surface only in cells that straddle its horizon: n.wi <= 0 there, the sample
 * contributes nothing. How many depends on the light near the horizon (NOTES 2: 0.1-39% per orientation
 * on the CC0 maps, 1.2-7.5% averaged over six; 89-95% for a sun just below the horizon; sample_li:
 * 46-58%), so a caller cannot count on most samples being usable. pdf 0: no sample
 * (a black map, nothing emits above this surface, or an unusable n); skip it. Cost: about 815
 * instructions (940 with rgb), the pdf included; sample_li_cos_n below: about 625 (755). Builds its
 * tables on first use (5.4 MiB for a
 * 1024x512 map, at most 12 MiB for any map: larger maps use a 2048x1024 coarse grid); thread-safe
 * like sample_li's lazy build; the light's own sampling tables (sample_li's) are not needed. */
EL_DEF void el_envlight_sample_li_cos(const el_envlight *l, const float n[3], const float u[2], float wi[3],
                                      float rgb[3], float *pdf);
/* The density with which sample_li_cos(l, n, .) picks wi, for MIS against BSDF sampling at the same
 * point: pdf_li_cos(n, sample_li_cos(n, u).wi) is the returned pdf, bit for bit. > 0 wherever le(wi) > 0
 * and n.wi > 0 (without compensation); also > 0 slightly below the horizon. A zero or NaN wi, or a
 * zero, NaN or infinite n, gives 0. About 400 instructions (pdf_li_cos_n: 335). Builds the tables on
 * first use. */
EL_DEF float el_envlight_pdf_li_cos(const el_envlight *l, const float n[3], const float wi[3]);
/* n at once, for wave loops (a renderer's shading points of one stage): normals[3i..] and u[2i..] in,
 * wi[3i..], rgb[3i..] (may be NULL) and pdf[i] out (arrays of points, as sample_li_n), bit for bit what
 * n calls of sample_li_cos return; pdf_li_cos_n likewise pdf[i] = pdf_li_cos(normals[3i..], wi[3i..]).
 * With SSE2 the arithmetic runs on four samples at once and the table reads of 16 samples are started
 * together: about 625 / 335 instructions per sample and 2-3.5x less time with random normals (NOTES 2,
 * COST); without SSE2 (or with FMA contraction: -mfma) a loop of single calls. n <= 0 does nothing. The
 * outputs must not overlap normals, u or wi (an input of pdf_li_cos_n). */
EL_DEF void el_envlight_sample_li_cos_n(const el_envlight *l, int n, const float *normals, const float *u, float *wi,
                                        float *rgb, float *pdf);
EL_DEF void el_envlight_pdf_li_cos_n(const el_envlight *l, int n, const float *normals, const float *wi, float *pdf);
/* Both of an escaped ray's lookups for MIS against product sampling, n at once: pdf[i] =
 * pdf_li_cos(normals[3i..], dirs[3i..]) and rgb[3i..] = le(dirs[3i..]), bit for bit what pdf_li_cos_n and
 * le_n return (so the same normals: any length, pointing to the side the light arrives from; a zero, NaN
 * or infinite normal gives pdf 0, the direction's le all the same; a zero, NaN or infinite direction gives
 * pdf 0 and le 0). pdf 0 means sample_li_cos never picks that direction for that normal (no light there,
 * or below the cells that straddle the horizon): MIS gives the BSDF sample the whole weight. With SSE2
 * one pass: le's (u, v) is where the pdf locates the direction, so the mapping runs once and the texel
 * reads are requested with the pdf's (about 480 instructions per direction against 332 + 256 for the two
 * calls; NOTES ON PRODUCT SAMPLING, PDF AND RADIANCE AT ONCE). n <= 0 does nothing; pdf and rgb must not
 * overlap normals or dirs. */
EL_DEF void el_envlight_pdf_li_cos_le_n(const el_envlight *l, int n, const float *normals, const float *dirs, float *pdf, float *rgb);
/* Build the product tables now (before sharing the light when there are no atomics), with sizes (opt
 * may be NULL: the defaults on a first build, whatever was built otherwise). Returns the build's result;
 * EL_ERROR_INVALID_ARGUMENT for sizes out of range or different from those of tables already built
 * (options apply to the first build only: call it before the first query). The constant light needs
 * no tables (EL_SUCCESS). */
EL_DEF el_result el_envlight_prepare_product(const el_envlight *l, const el_envlight_product_options *opt);
/* Bytes of the warp and the normal tables once built (0 before; el_envlight_bytes includes them; in mode
 * BILINEAR the warp is counted by el_envlight_sampling_bytes instead). */
EL_DEF size_t el_envlight_product_bytes(const el_envlight *l);

/* << declarations: product sampling */

/* ----------------------------------------------------------------------------------------------------
 * NOTES ON PRODUCT SAMPLING AND THE BILINEAR WARP (issue 13; the numbers: bench/bench_envlight.c tables
 * 1, 2, 4, 5 and bench/bench_product.c, gcc 12 -O3, no -march, this project's shared 2-core machine)
 *
 * 1. IMPORTANCE MODE BILINEAR: LE()'S PATCHES (issue 22; before it, a continuous warp of cells). The density
 *    is the bilinear interpolant of V = lum x sin(theta) at the texel centres (the vertices of le()'s
 *    bilinear patches; two vertex rows of value 0 at the poles): Mitsuba 3's envmap density. Where the
 *    cell-average density (the default) is constant over a texel while le() is bilinear, this one follows
 *    le() inside the texel: the relative variance of lum(le) / pdf per sample is 3.2e-6 on city against 0.099
 *    (tests/test_envlight_patch.c), so a sun stops adding variance of its own and low-discrepancy points keep
 *    their stratification: bench/bench_ld_point.c (city, an upward normal, 64 points per estimate, relative
 *    variance of one estimate, independent / Owen-scrambled Sobol'): the light sample alone 3.78e-3 / 2.07e-6
 *    (CELL_AVERAGE 6.30e-3 / 1.76e-3, PBRT_V3 4.41e-3 / 4.24e-4), with one cosine sample and the power
 *    heuristic 4.12e-3 / 2.32e-4 (6.59e-3 / 1.82e-3, 4.76e-3 / 5.53e-4): 2.4x less than PBRT_V3 with the
 *    low-discrepancy points, 1.16x with independent ones.
 *    SAMPLING: one discrete table over the w x (h + 1) patches (distribution2d.h's integer CDFs, each patch's
 *    weight the mean of its corners x its height, so every patch with a positive corner is reachable at any
 *    dynamic range; the light's own guide tables, or its CDF or alias sampler), then (s, t) inside the patch
 *    in closed form: t from the marginal (1 - t)(V00 + V01) + t (V10 + V11), s from the conditional at t,
 *    each the inverse of a linear density (a quadratic, in the form without cancellation: exact at zero and
 *    at equal corners), kept 2^-12 of a patch inside its edges. Every step is monotone in its u. The corners
 *    are bfloat16 rounded up, scaled by a power of two (the density is bil / mean: unchanged) so that the
 *    squares stay normal floats. The density of a patch is its integer share x bil(s, t) / mean(corners) /
 *    (du dv 2 pi^2 sin theta): one factor K per patch stored with its four corners in a 16-byte record (one
 *    cache line per query).
 *    THE PDF (maps of at least 256 x 128; smaller ones take le()'s atans, product sampling's locate): no
 *    atan. The patch column and row come from bin finders over half texels (pdf_li's diamond angle and its t
 *    = 1 - z / (r + |z|), 2w and 2h bins: the texel centres are the odd edges); s and t from the angle to a
 *    reference edge of the patch, atan of the tangent of the difference ((y c - x s) / (x c + y s), at most
 *    pi / 128: q - q^3 / 3). sample_li forms its direction from the same references by angle addition, then
 *    finds it again as pdf_li does, so its pdf is pdf_li(wi) bit for bit (tested on every sample of the
 *    chi-square tests, for identity, y-up and general rotations); its radiance is le at that point's (u, v)
 *    under a signed permutation (le(wi) but for le()'s atan polynomial: within 2e-4 of the four texels'
 *    range, tested), le(wi) itself under a general rotation; when rounding moves the point into another patch
 *    the pdf is that patch's, and if that has no mass the sample moves to its patch's centre (issue 24's
 *    rule).
 *    sample_li_n prefetches in passes (the marginal row and its guide entry, the CDF entries, the patch's
 *    record, its texels), bit-identical to sample_li: the renderer's waves draw their map samples through it
 *    (without it, bench_city's render loop took 1.24x pbrt-v3's density's CPU; with it 1.04-1.05x).
 *    COST (bench/callgrind_product.sh with OPS=...bilinear..., city 1024x512, the loop subtracted): sample_li
 *    515 instructions (668 with the radiance: le at the point's own (u, v), as the other modes under a signed
 *    permutation; 552 under a general rotation, whose radiance is le(wi)), pdf_li 241 (257); before (the
 *    continuous warp): 1174 (1301), 422. CELL_AVERAGE: 97.6 (266), 76. The issue's targets (250 / 150) are
 *    NOT met: the pick (the guide search, ~60), the two inversions (~50), the direction (~40), finding it
 *    again (~90) and the density (~30), plus the calls: the relocation buys the bit-for-bit pdf; without it
 *    (the sample's own (s, t), exact transforms) sample_li measured 342. The renderer's per-camera-sample
 *    instructions on bench_city (zsobol, callgrind, spp 8 - spp 4) are 8% above its default PBRT_V3
 *    density's.
 *    MEMORY: 2 bytes per vertex (bfloat16), 16 per patch (the records), 4 + 1 per patch (the integer CDFs and
 *    guide tables), the finders and reference tables (about 200 KB at 1024x512): 11.7 MB at 1024x512
 *    (CELL_AVERAGE 4.7, PBRT_V3 18.3, the continuous warp 4.6). Maps over the cap (EL_ENVLIGHT_IMPORTANCE_CAP
 *    wide) take CELL_AVERAGE's capped tables, as PBRT_V3 does: about 190 MB for a 4096 x 2048 map, the
 *    largest.
 *    BUILD: 100 M instructions, 15 ms at 1024x512 (PBRT_V3 44 ms).
 *    IN THE RENDERER (bench/sun_rule.py --strategies pbrtv3,default: relative variance across 8 seeds x the
 *    render loop's CPU, interleaved; the map alone at diffuse vertices facing a sun), time to unit variance
 *    against PBRT_V3, whole image / lit / shadowed pixels of bench_city: zsobol 16 spp 1.10 / 1.22 / 0.95, 64
 *    spp 1.11 / 1.31 / 0.91; independent 16 spp 1.02 / 1.05 / 0.97, 64 spp 0.96 / 0.99 / 0.91 (the lit
 *    pixels' variance 1.29-1.45x lower with zsobol, 1.09x with independent samples; the render loop's CPU
 *    +4-12%). The renderer takes it by default under a sun map with a low-discrepancy sampler
 *    (examples/render/README.md).
 *
 * 2. PRODUCT SAMPLING (sample_li_cos, pdf_li_cos): a density close to L(w) max(0, n.w). The map's
 *    patches are grouped into 64 x 32 cells; a cell is picked with probability proportional to its
 *    mass under the warp times B(cell, n), an upper bound of max(0, n.w) over the cell, then the warp
 *    runs inside the cell. B comes from a table per octahedral bin of the (light-space) normal, 32 x 32
 *    bins: for the bin's centre normal c the exact maximum of c.w over the cell (a spherical rectangle:
 *    the best phi, then the peak of a sin(theta) + b cos(theta) on the cell's theta range), widened by
 *    the bin's angular radius r (the farthest point of its boundary, sampled, plus the sampling gap and
 *    1e-4): B = cos(max(0, angle(c, cell) - r)). So B > 0 for every cell holding a direction above the
 *    surface of any normal of the bin: pdf_li_cos > 0 wherever le > 0 and n.w > 0 (compensation aside),
 *    and light sampling alone is unbiased (tested: a grid of directions x 12 normals, the poles and the
 *    seam among them, on hard maps; and against quadratures of the irradiance). Inside the cell (issue
 *    20) a patch row is picked from the cell's integer CDF over its rows (each row's mass, every row
 *    with mass at least one of 32768 units), a patch from that row's CDF over the cell column, then
 *    (s, t) inside the patch from the bilinear itself (t from the linear marginal, s from the linear
 *    conditional at t: two square roots), kept 2^-12 of a patch inside its edges (the round trip of a
 *    general rotation must find the same patch). The density is P(cell | n) x the patch's integer
 *    share x bil(s, t) / mean(corners): the warp's bilinear interpolant up to the units' rounding (the
 *    same variance per sample as before, measured). A sample costs a table lookup, four small binary
 *    searches, two linear inversions, the direction and the atan pair that locates it again (its pdf
 *    then from the widths it picked); the pdf the atan pair and the same tables.
 *    WHERE IT CANNOT STAY ABOVE THE SURFACE: in cells that straddle the horizon of the bin's normals
 *    (the cells' size plus the bins' radius); such samples come back with n.wi <= 0 and contribute
 *    nothing. Their share is the share of the bound's mass in those cells, so it depends on how bright
 *    the map is just below the horizon, not on a fixed fraction (bench/bench_hdri.c, 65,536 samples,
 *    light space = world): on the five CC0 maps 0.1-4.1% for normals up, +x, -y, towards and away from
 *    the brightest texel, but 39% (night) and 17% (studio) facing down and 18.5% on city for n = (0.6,
 *    -0.8, 0); averaged over bench_envlight's six orientations 1.2-7.5% per map (sample_li: 46-58%). A
 *    sun one to four texel rows below the horizon (a 2x2-texel sun of 1e4 on a 0.01 sky, 512x256) sends
 *    89-95% of the samples below it (an independent campaign measured 99.8% for its sun, and 50.8% on
 *    a sunrise map for n = (0.6, -0.8, 0)); 16 rows below, 24%; 64 rows, 1%. The estimate stays
 *    unbiased (the pdf is exact); only the share of useful samples drops, and with it the efficiency
 *    of that pixel. Finer cells or normal bins (el_envlight_product_options) narrow the straddling band.
 *    VARIANCE (table 4, diffuse surface, 6 orientations: up, down, two sideways, facing the brightest
 *    texel and away; geometric mean of the relative variance per sample, 200,000 samples): light
 *    sampling alone 0.034 (city) - 0.062 (night) against 2.0-2.7 for sample_li: 42-77x less, 22-36x the
 *    efficiency (1 / variance x time) with the cost below. With one cosine sample besides (MIS, balance
 *    heuristic) the pair's variance is 0.07-0.12 against 0.36-1.27 (5-11x less; 3.4-6.2x the
 *    efficiency; the power heuristic: 4-10x, 3.3-6.3x). At equal sample count, two product samples beat
 *    a product and a cosine sample under the balance heuristic by 3.4-6x: for a diffuse lobe the BSDF
 *    sample is better spent on a second light sample.
 *    CANDIDATES TRIED (bench/bench_product.c, same quantity, city / studio): per shading point exact
 *    bounds over 16x8 / 32x16 / 64x32 cells (O(cells) work per point, Conty and Lecocq 2018's scheme),
 *    0.062 / 0.022 / 0.0074 and 0.070 / 0.026 / 0.0093 with the warp inside cells, 0.117 / 0.059 / 0.032
 *    and 0.127 / 0.078 / 0.052 with cell averages; tables over 8^2, 16^2, 32^2, 64^2 normal bins,
 *    e.g. 32^2 x 64x32 (the default) 0.033 / 0.036, 16^2 x 32x16 0.10 / 0.11, 64^2 x 64x32 0.018 / 0.022
 *    (17 MB of tables); a tighter per-bin bound (the maximum over 81 normals of the bin, not
 *    conservative) would gain only 15%. The warp inside cells gains 2.4-5.6x over cell averages (city, studio). Hierarchical
 *    warping of the product (Clarberg et al. 2005) needs a product map per point, O(cells) work like
 *    "exact". The default is the best variance at a fixed cost per sample, for 2.9 MB of normal tables.
 *    COST (bench/callgrind_product.sh: callgrind, city.hdr 1024x512, default options, a new random normal per
 *    call, the loop's own 9 subtracted): sample_li_cos 814 instructions (941 with the radiance; 863 under a
 *    general rotation), pdf_li_cos 400 (424); sample_li 97 (265 with the radiance), pdf_li 76 (the pick
 *    in stages shared with the batched call below: 806, 933, 855, 408 and 436 before). With binary
 *    searches in place of the guide tables (below): 902 (1029; 951); before the round before: 988 (1116;
 *    1034), 408 (432); before issue 20: 1179, 1310 and 444. Issue 20's targets (sample_li_cos <= 400 and <=
 *    1.25x sample_li, pdf_li_cos <= 150 and <= 1.5x pdf_li) are NOT met: the floor of this design is about
 *    the pdf plus the pick. The pdf (408) is the normal's bin (to light space, octahedral encoding: about
 *    60), wi to light space (27), (u, v) to the bilinear's precision (the two atan polynomials le() itself
 *    uses, so that rgb is le(wi) bit for bit: about 110; the patch density's atan-free locate costs as much,
 *    Tried since below), the four table widths (about 50), the corners and
 *    the density (about 60) and the calls; the sample adds the pick (four searches over 32, ~37, ~16 and 16
 *    entries: about 190 as binary searches, about 95 with the guide tables), two linear inversions, the
 *    direction (sinpi, cospi) and the atan pair again (bit-for-bit agreement with pdf_li_cos needs the
 *    direction located as the pdf locates it; by angle addition and without atan: 742, Tried since below).
 *    N AT ONCE (sample_li_cos_n, pdf_li_cos_n; issue 20): the same work, bit for bit, with the arithmetic
 *    on four lanes of SSE2 (normal -> bin, the linear inversions, the direction's sinpi / cospi, the atan
 *    pair, the density) and the table reads lane by lane, in four stages over 16 samples (cell row, cell,
 *    patch row, patch: each stage requests the next stage's lines, then the corners and the texels), so
 *    that 16 samples' cache misses overlap. Counted the same way in batches of 64 (bench_envlight
 *    --callgrind sample_cos_n ...: callgrind_product.sh): sample 624 instructions per sample (756 with the
 *    radiance: its texels located once, for the prefetch and the blend; 640 under a general rotation), pdf
 *    333 (341); city and studio alike. The four lanes alone (4 samples per block, no stages): 542 and 245;
 *    the stages and prefetches cost about 80 / 88 instructions and save far more time. Time (bench_product
 *    --batch: a new random normal per sample, radiance included, CPU ns, best of 2-3 interleaved rounds,
 *    2-core machine at load 3-7): city sample_li_cos 373-478 -> 127-142 ns (2.8-3.5x), pdf_li_cos 94-130 ->
 *    52-56 ns (2-2.3x; sample_li 100-114); studio 325 -> 122 and 91 -> 48; without the prefetches city
 *    217-224 and 59 ns. Issue 20's targets are not met this way either: the floor is the scalar part, the
 *    four searches (about 125 per sample, the guides' forward scans) and the pick's address and fraction
 *    arithmetic (about 110), the normal's table and the lanes' bookkeeping; the vector part is about 120
 *    per sample (the atan-free locate, Tried since below, on four lanes: 625 and 400, its references
 *    gathered lane by lane). In render's wave loop (render_wave.c, the wave's product samples in one call):
 *    callgrind_parts.sh, instructions per camera sample, city 4064 -> 3993 (light part 1066 -> 996), studio
 *    3264 -> 3114 (1011 -> 860; four lanes without stages or the texel reuse: 3969 and 3058); render CPU
 *    time, one thread, 64 spp, best of 3 interleaved: bench_city 1.98 -> 1.88 s, bench_studio 1.47 -> 1.18
 *    s, images byte-identical.
 *    PDF AND RADIANCE AT ONCE (pdf_li_cos_le_n; issue 21: a wave's escaped BSDF rays, whose MIS weight needs
 *    the product pdf and whose estimate needs le): pdf_li_cos_n's pass, and le's four texels located from
 *    the (u, v) the pdf's locate computes anyway (the same light-space direction, the same atan polynomials
 *    and square root as le's: bit for bit) and requested with the pdf's table lines. Directions that need
 *    rescaling (zero, NaN, infinite, huge) take le's own cold path. bench_envlight --callgrind pdf_cos_le_n
 *    (city 1024x512, batches of 64, the loop's 9 subtracted): 481 instructions per direction against 332 +
 *    256 for pdf_li_cos_n and le_n (490 against 341 + 272 under a general rotation). The guide tables'
 *    forward scans step eight uint16 entries at a time with SSE2 (compared as int16 after - 32768; the
 *    first entry above k from the compare's mask): sample_cos_n 632.6 -> 631.8 instructions, but render's
 *    loop CPU 0.93-0.97x (bench_city and bench_studio, direct and path, 6 interleaved rounds against the
 *    same binary with the scalar scan; likely its varying step count's mispredicted exit branch).
 *    TIME-TO-UNIT-VARIANCE (bench/bench_product --library: relative variance per sample x CPU ns per
 *    sample, geometric mean over six normals, one fixed normal per run, 200,000 samples, loaded 2-core
 *    machine): city 6.50 (0.0338 x 192 ns; before this round 6.92: 0.0338 x 204 ns; sample_li 214:
 *    2.56 x 84 ns), studio 6.62 (0.0396 x 167 ns; before 6.80: 0.0396 x 172; sample_li 124): 33x and 19x
 *    sample_li's efficiency. With a new random normal per call (renderer-like, cache-cold normal
 *    tables; 1 M calls, best of 6 interleaved runs, CPU time): sample_li_cos 249 -> 238 ns, pdf_li_cos
 *    69 -> 72 ns (the sparse tables' row offset is one more dependent load).
 *    ISSUE 20, WHAT WAS TRIED (each measured; kept if it paid in time-to-unit-variance):
 *    kept: guide tables (Chen's cutpoint method: for each of the four CDFs 8 bytes, the first candidate entry
 *    of each eighth of its units, then a forward scan; the same index as the binary search, so the same
 *    samples bit for bit, checked over 400,000 random normals and u on city and studio): sample_li_cos 902 ->
 *    806 instructions (the normal bins' cell-row and span guides -58, in the sparse tables; the patch-row and
 *    patch guides -38, beside pcol and prow); random normals 286-302 -> 268-276 ns per sample (bench_envlight
 *    --callgrind sample_cos 5 M, user time, 3 interleaved runs), bench_product --library city 203 / 206 ->
 *    182 / 194 ns; +549,400 bytes (4.86 -> 5.38 MiB; 4 buckets: +275 KB for 854 instructions), build +3.5-4
 *    ms interleaved (16.2-16.5 -> 20.0-20.3 ms best of 5, NSAMP=1000; 242 -> 264 M instructions). Dropped:
 *    the octahedral fold without branches (the same bins: +25 instructions, no gain in ns). Kept in earlier
 *    rounds: the built check inlined (-25 instructions per call); the sample's pdf from the widths it picked
 *    once the direction, located again, lands in the same patch (-70; the same bits as pdf_li_cos: the same
 *    evaluation of the same values); sparse normal tables (each cell row only the span of cells with weight,
 *    wrapping at the seam: 4.3 -> 2.9 MB, +14 instructions in the pdf, +23
 *    in the sample); the vertex grid in bfloat16 rounded up (the patch CDFs built from the rounded
 *    values: -1 MB, and the fastest per sample: half the cache footprint); the bounds' phi part per cell
 *    column and two cells at a time (build 20.4 -> 15.7 ms, bit-identical tables). Dropped: the corners
 *    recomputed from the texels instead of a stored grid (meets 4 MiB: 3.85 MiB, the same bits, but
 *    +54 / +73 instructions and 18% more time per
 *    sample with random normals: the texels are 6 MB against the grid's 1-2); a branch-free binary
 *    search with fixed steps (-13 instructions per sample: not worth its code); the light's own
 *    piecewise-constant bins inside the cells (pdf_li_cos = pdf_li x a per-cell ratio, about 110 / 340
 *    instructions estimated: 2.4x the variance on city, 0.080 against 0.033, 20x for the normal facing
 *    up, where the sun's texel dominates and its density is flat while le is bilinear); an SSE2 count in
 *    place of the binary searches (1049 instructions against 953). Tried since: the batched call for n
 *    normals (N AT ONCE above: 624 / 333 instructions, 2-3.5x less time); the patch density's atan-free
 *    locate (grids of at least 256 x 128: its half-texel finders and reference angles, the sample's
 *    direction by angle addition, its patch checked by the signs of cross products with the patch's edges
 *    so that the sampler skips the finders; git history: commit 7995289, reverted by the next), dropped: city,
 *    instructions sample_li_cos 813 -> 742, pdf_li_cos 402 -> 420 (the finders alone, without the signs'
 *    rule: 795 and 397), sample_li_cos_n 624 -> 625, pdf_li_cos_n 332 -> 400; bench_product --batch (best
 *    of 3 interleaved) city 290 -> 276, 116.5 -> 116.0, 68 -> 71, 47.3 -> 48.1 ns, studio 259 -> 239,
 *    112 -> 109, 69 -> 80, 44 -> 47; --library (one normal per run) city 207 -> 180 ns, studio 185 -> 174:
 *    the single sample gains, the batched calls the renderer uses do not, the pdfs lose, and rgb would be
 *    le(wi) only to the patch density's tolerance (188 KB more tables). Built (below): alias tables (they
 *    break the stratification), Conty and Lecocq's per-point 12x12
 *    coarse level (bench_product: its variance at 16x8 cells is 2x the tables'). Not tried: an equal-area or
 *    diamond-angle patch layout without atan (le() itself is lat-long with atan: rgb and the bilinear
 *    density would no longer be le's; on le's own patches locating without atan did not pay, above).
 *    CANDIDATES BUILT IN BENCH_PRODUCT --CANDIDATES (issue 20's two designs not built before, as prototypes
 *    on the library's own tables and helpers; city / studio 1024x512. Instructions with the radiance and a
 *    new random normal per call: OPS="lib alias2 alias4 alias2c cl12x12 cl16x8 cl16x16 lib_pdf cl12x12_pdf"
 *    sh bench/callgrind_product.sh build/bin/bench_product data/envmaps/city.hdr 20000. The rest: REPS=5
 *    bench_product --candidates: relative variance per sample, geometric mean over the six normals, 200,000
 *    independent samples, and per point with 3125 estimates of 64 Owen-scrambled Sobol' points; CPU ns per
 *    sample with random normals and with one normal per run, best of 5 interleaved rounds, loaded 2-core
 *    machine.) Today's sampler in the same harness: 940 / 943 instructions, variance 0.0338 / 0.0395, Sobol'
 *    0.0030 / 0.0031, 321 / 243 ns with random normals (212 / 171 with one normal), relvar x ns 10.9 / 9.6
 *    (7.2 / 6.8).
 *    ALIAS TABLES (Walker / Vose in integers over the library's own widths: each entry keeps exactly its
 *    share, so density and pdf are today's; pdf_li_cos of every 16th sample equal bit for bit): the two
 *    cell levels 876 / 881 instructions, all four levels 822 / 830 (the guided searches: -64, -118); 8-byte
 *    entries (threshold, alias, both widths): 15.3 MiB (cell levels) or 19.9 (all four) against 5.38, built
 *    in 21 ms more; 4-byte entries for the cell levels (the widths read from the library's CDFs, which the
 *    pdf keeps) 880 / 887 instructions and 10.6 MiB. Independent points: the same variance; with one normal
 *    per run 203 / 165 ns (4-byte 197 / 165: relvar x ns 6.6 / 6.5, 8% / 4% under today's), with random
 *    normals 452 / 319 ns (4-byte 374 / 287: +16% / +18%, the larger tables miss the cache; relvar x ns 12.5 /
 *    11.2). Sobol' points: 0.0172 / 0.0098 per point, 5.7x / 3.2x today's (all four levels 5.8x / 3.5x): the
 *    rest of u that goes on to the next level is not monotone in u, so Sobol' gains 2-4x over independent
 *    points instead of 11-13x. Not kept: the renderer's default points are low-discrepancy.
 *    CONTY AND LECOCQ'S PER-POINT COARSE LEVEL (lat-long cells, not their equal-area ones; per point the exact
 *    maximum of n.w over each cell + 1e-5, SSE2 four cells a step, times the cell's mass; a CDF over the cell
 *    rows, then over the row's cells; then the library's patch-row and patch picks and bilinear, so the pdf
 *    is exact, checked bit for bit and by a chi-square of the cells; 2.1 MiB of tables built in 6-8 ms,
 *    which would meet the issue's memory and build targets): 12x12 2741 / 2753 instructions (the pass over
 *    the cells alone 1839: about 40 per four cells), 16x8 2493, 16x16 3821 / 3825; its pdf needs the whole
 *    pass too: 2448 / 2126, 2181, 3827 / 3186 (pdf_li_cos 410; 158 / 163, 151 / 146, 216 / 215 ns against
 *    101 / 91). Variance 0.052 / 0.072 (12x12), 0.063 / 0.073 (16x8), 0.034 / 0.047 (16x16); Sobol' 0.0069 /
 *    0.0063, 0.0067 / 0.0095, 0.0059 / 0.0051 (1.6-3.1x today's); random normals 378 / 288, 387 / 265, 446 /
 *    339 ns, one normal 321 / 267, 321 / 255, 401 / 313; relvar x ns 19.7 / 20.7, 24.3 / 19.3, 15.2 / 15.9
 *    (1.4-2.2x today's; one normal 1.9-2.8x). A sample and a pdf at the same point sharing one pass would
 *    still take about 3350 instructions against today's 1350.
 *    Unbiased (both): the estimators' |z| against the quadrature and the cells' chi-square z within 2.7 (today's
 *    too) but for one normal each at the default seed (4.2 alias side+x and 4.4 C&L 16x16 down on city, 3.5
 *    C&L 16x8 on sunset), which other seeds at 4x the samples do not repeat (all <= 2.4 at 800,000, city and
 *    sunset); no direction above a random normal with le > 0 got pdf 0 (131,790 pairs each). Sunset and night
 *    (../shared/envmaps, 100,000 samples) repeat the pattern: alias with Sobol' points 6.5x / 5.1x today's
 *    variance, C&L relvar x ns 1.7-2.4x today's. Neither design replaces the tables.
 *    MEMORY: the vertex grid (2 bytes per vertex, bfloat16), the patch CDFs (2 bytes per patch) and the
 *    sparse normal tables (2.9 MB for 32^2 bins x 64 x 32 cells; dense they were 4.3) and the guide tables
 *    (0.55 MB): 5,643,316 bytes = 5.38 MiB at 1024x512 (4.86 without the guides, 7.3 MiB before this round,
 *    8.7 before issue 20; the target 4 MiB is not met
 *    with the default options: 32x16 cells and 16^2 bins give 2.4 MB, for 3x the variance; the other
 *    way, normal_bins 48 gives 1.6-1.7x less variance per sample at the same instructions per sample,
 *    for 8.1 MiB and a 34 ms build: city 0.054 -> 0.033, studio 0.050 -> 0.029, geometric mean over up,
 *    down, +x, +y, (0.6, -0.8, 0), (0.3, 0.5, 0.81); 64 gives 0.030 and 0.027 for 12.5 MiB). Maps over
 *    2048x1024 use a coarse grid of that size (each coarse vertex the largest lum of the texels of its 3
 *    x 3 coarse bins, so the density stays > 0 wherever le is): at most 11.8 MiB for any map (11.0
 *    without the guide tables, 16.4 before, 1.09 GB before issue 20). BUILD: 264 M instructions at
 *    1024x512 with init (242 M without the guide tables, 310 M before; the bounds two cells at a time
 *    with SSE2, the same bits as the scalar code), 15.7 ms without the guide tables (best of 7, CPU
 *    time, 2-core machine at load 5; 20.4 before, interleaved; target 20 ms), about 20 ms with them
 *    (interleaved: 16.2-16.5 -> 20.0-20.3 ms, best of 5); 4096x2048: about 80 ms.
 *
 * 3. EXACTNESS. pdf_li_cos(n, wi) of a sampled wi equals the returned pdf bit for bit, and rgb equals
 *    le(wi) bit for bit (signed-permutation matrices and general rotations alike: the sampler brings
 *    wi back to light space as pdf_li_cos does). For continuous u the cell, patch row and patch are
 *    picked with exactly their integer shares and (s, t) by exact inversion of the bilinear, but for
 *    the 2^-12 band at each patch edge (points there are moved onto it; the density differs by 2^-12 of
 *    the patch's variation: no measurable bias). For u on a 2^-24 lattice the fractions inside a cell
 *    see the lattice of the remaining fraction (the chi-square tests at 100,000 samples see nothing).
 *    (Issue 24 had kept the earlier warp's points 2^-21 inside their patch and moved points that still
 *    left it to the patch's centre; the 2^-12 band does that job here: tested with u at 0 and within 8
 *    ulps of 1, and with sparse maps under a general rotation.)
 *
 * 4. INPUTS. n and wi need not be unit length: they are rescaled in world space when their light-space
 *    squared length leaves the normal floats (as pdf_li and le do), so the results depend only on their
 *    directions, also for components near FLT_MAX or denormal under a general rotation. A zero,
 *    NaN or infinite n gives pdf 0 for a map (no sample). The constant light: cosine-weighted hemisphere
 *    sampling, exactly the product (pdf max(0, n.w) / pi), or sample_li's uniform sphere for an
 *    unusable n. A black map, or a normal whose hemisphere holds no mass: pdf 0 (skip the sample).
 *    Compensation (options.compensated): the vertices become max(lum - mean, 0) x sin (the mean from
 *    the exact integral); use it with MIS only, as sample_li's. 1xN and Nx1 maps work (one patch
 *    column; two pole patch rows).
 *
 * 5. THREADS. The product tables are built on first use by their own once-flag (the same
 *    scheme as the sampling tables: atomics with GCC/Clang, else call el_envlight_prepare_product before
 *    sharing the light); the build writes through the const pointer, so never define an el_envlight
 *    object itself const. After that every query is read-only. The light's own sampling tables
 *    (sample_li's) are not built by product sampling, nor the normal tables by importance BILINEAR. */

/* >> declarations: hot spots and the mixture sampler (issue 22; NOTES ON HOT SPOTS below) */

/* The most hot spots a map can have (el_envlight_hotspots.spot[]). */
#define EL_ENVLIGHT_HOTSPOT_MAX 8

/* How hot spots are found (all zero: the defaults in brackets; NOTES ON HOT SPOTS 1). */
typedef struct el_envlight_hotspot_options {
  float min_radiance;   /* a bin is hot when its mean density is >= this x the map's mean (power / 4 pi) [100] */
  float min_share;      /* a spot is kept when it holds >= this share of the map's sampling mass [0.05] */
  float max_half_angle; /* ... and its cone's half-angle is <= this, in radians [0.2, 11.5 degrees] */
  int max_spots;        /* at most this many spots, the largest shares first, 1..EL_ENVLIGHT_HOTSPOT_MAX [8] */
} el_envlight_hotspot_options;

/* One hot spot: a connected set of importance bins, described by a cone. */
typedef struct el_envlight_hotspot {
  float axis[3];    /* world space, unit: the mass-weighted mean direction of its bins */
  float half_angle; /* radians: every bin of the spot lies within this angle of axis */
  float share;      /* the probability with which sample_li lands in it (its share of the power, for a
                       light without compensation) */
  int bins;         /* importance bins in it */
} el_envlight_hotspot;

/* The hot spots of one light and the tables that sample "spot k" and "the rest" apart. PUBLIC: count,
 * spot[], rest_share; the rest is private. Made by el_envlight_hotspots_init, freed by
 * el_envlight_hotspots_free (safe on a zeroed struct). */
typedef struct el_envlight_hotspots {
  int count;                                  /* PUBLIC: 0 .. EL_ENVLIGHT_HOTSPOT_MAX */
  el_envlight_hotspot spot[EL_ENVLIGHT_HOTSPOT_MAX]; /* PUBLIC: the largest share first */
  float rest_share;                           /* PUBLIC: 1 - the spots' shares */
  /* ---- private ---- */
  const float *key;                           /* the light's pdf table it was made for */
  int nu, nv;                                 /* its importance bins */
  double share_d[EL_ENVLIGHT_HOTSPOT_MAX + 1]; /* spots' and rest's shares (index count = the rest) */
  int rect[EL_ENVLIGHT_HOTSPOT_MAX][4];       /* first column (wraps), first row, columns, rows */
  unsigned char *mask[EL_ENVLIGHT_HOTSPOT_MAX]; /* columns x rows: 1 = the bin belongs to the spot */
  el_distribution2d dist[EL_ENVLIGHT_HOTSPOT_MAX + 1]; /* each spot's bins, then the rest (index count) */
  el_distribution2d_fast rest_fast;           /* the rest's guide table (constant expected time) */
  int rest_fast_ok;
  int cells_u, cells_v;                       /* the rest x cosine part: cells of the rest's bins */
  float *cell_cone;                           /* 6 arrays of a float per cell: the cone's centre x, y, z
                                                 (light space), cos and sin of its radius; the rest's mass */
  double *cell_mass;                          /* per cell: the rest's probability under sample_li */
  uint16_t *cell_tab;                         /* per cell: the rest's bins in it as integer CDFs with guides
                                                 (el_envlight__hot_cells), one cell after another */
  uint32_t *cell_off;                         /* per cell: where its table starts in cell_tab */
  unsigned char *cell_of_col, *cell_of_row;   /* per bin column / row: its cell column / row */
  int cell_u0[33], cell_v0[17];               /* the cells' first bin column / row (and the end) */
  /* importance BILINEAR (el_envlight_sample_li_spot): each spot's rectangle of le()'s patches */
  const void *pkey;                           /* the light's patch records it was made for */
  int prect[EL_ENVLIGHT_HOTSPOT_MAX][4];      /* first patch column (wraps), first patch row, columns, rows */
  uint64_t *prow[EL_ENVLIGHT_HOTSPOT_MAX];    /* rows + 1: the rows' CDF in the patch table's 2^48 units */
  float inv_pmass[EL_ENVLIGHT_HOTSPOT_MAX];   /* 1 / the rectangle's probability under sample_li (0: none) */
  float pcos[EL_ENVLIGHT_HOTSPOT_MAX];        /* cos of a cone about spot[k].axis that holds the rectangle (pdf_li_spot's
                                                 early 0 for the directions far from it) */
} el_envlight_hotspots;

/* Mixture weights: the probability of drawing from spot k (spot[k], k < count) and from the rest of the
 * map (rest), normalised by their sum. All zero (or NULL), any NaN, infinite or negative weight, or a sum
 * of 0 over the parts that have mass: the DEFAULT weights, each part's own share, which give
 * sample_li's density exactly (then sample_li_mix is sample_li and pdf_li_mix is pdf_li, bit for bit). */
typedef struct el_envlight_mix_weights {
  float spot[EL_ENVLIGHT_HOTSPOT_MAX];
  float rest;
} el_envlight_mix_weights;

/* Find the hot spots of l (builds its sampling tables if needed). opt may be NULL (the defaults).
 * A constant light, a black map or a map without a compact bright region: count 0 (success; the mixture
 * is then sample_li itself). Importance BILINEAR: the spots of le()'s patch density, for sample_li_spot
 * only (the mixture samplers are sample_li there; NOTES ON HOT SPOTS 6). EL_ERROR_INVALID_ARGUMENT for NULL pointers or
 * options out of range (negative, NaN, max_spots > EL_ENVLIGHT_HOTSPOT_MAX), EL_ERROR_OUT_OF_MEMORY, or
 * the light's own table build result. On failure *h is zeroed. Extra memory: about 6 bytes per bin
 * (the rest's distribution, 4; the rest x cosine part's cell tables, 2: NOTES ON HOT SPOTS 4) when a
 * spot is found, nothing otherwise. */
EL_DEF el_result el_envlight_hotspots_init(el_envlight_hotspots *h, const el_envlight *l,
                                           const el_envlight_hotspot_options *opt);
EL_DEF void el_envlight_hotspots_free(el_envlight_hotspots *h);
/* Weights that give the spots together the probability spot_share (clamped to [0, 1]), shared among
 * them in proportion to their own shares, and the rest 1 - spot_share. A NaN spot_share, or no spot:
 * the default weights (all zero). */
EL_DEF void el_envlight_hotspots_weights(const el_envlight_hotspots *h, float spot_share, el_envlight_mix_weights *w);
/* Sample the mixture sum_k w_k p_k + w_rest p_rest, where p_k is sample_li's density restricted to spot k
 * (renormalised) and p_rest the density restricted to the rest: wi (world, unit), rgb (may be NULL) the
 * radiance as sample_li gives it (le(wi); le at the sample's own (u, v) under a signed-permutation
 * matrix) and *pdf = el_envlight_pdf_li_mix(l, h, w, wi) bit for bit. u[0] picks the part and is reused
 * (remapped) inside it. pdf 0: no sample (skip it). h must come from this light (else, or with default
 * weights: sample_li itself). About 2x sample_li's cost plus pdf_li's. */
EL_DEF void el_envlight_sample_li_mix(const el_envlight *l, const el_envlight_hotspots *h,
                                      const el_envlight_mix_weights *w, const float u[2], float wi[3],
                                      float rgb[3], float *pdf);
/* n samples at once (u[2i], u[2i+1] -> wi[3i..], rgb[3i..] (may be NULL), pdf[i]), bit for bit n calls
 * of sample_li_mix; with default weights (or h unusable) el_envlight_sample_li_n itself. n <= 0: nothing. */
EL_DEF void el_envlight_sample_li_mix_n(const el_envlight *l, const el_envlight_hotspots *h,
                                        const el_envlight_mix_weights *w, int n, const float *u, float *wi,
                                        float *rgb, float *pdf);
/* The mixture with the rest drawn in proportion to the map times a cosine bound of the surface of world
 * normal n (NOTES ON HOT SPOTS 4): spot k as in sample_li_mix, the rest's cells (32 x 16) picked by their
 * mass times max(1e-3, an upper bound of n.w over the cell), then sample_li's density inside the cell
 * (up to its 16-bit tables' rounding).
 * Default weights here mean each part's own share. No spot (or h unusable): sample_li_cos itself, and
 * pdf_li_mix_cos is pdf_li_cos. A zero or NaN n: bound 1 (sample_li_mix's density). *pdf equals
 * pdf_li_mix_cos(l, h, w, n, wi) bit for bit. Cost: O(cells) per call (512 bounds), sample and pdf. */
EL_DEF void el_envlight_sample_li_mix_cos(const el_envlight *l, const el_envlight_hotspots *h,
                                          const el_envlight_mix_weights *w, const float n[3], const float u[2],
                                          float wi[3], float rgb[3], float *pdf);
EL_DEF float el_envlight_pdf_li_mix_cos(const el_envlight *l, const el_envlight_hotspots *h,
                                        const el_envlight_mix_weights *w, const float n[3], const float dir[3]);
/* The per-call work of sample_li_mix_cos and pdf_li_mix_cos for one (w, n), done once (issue 22's renderer:
 * a shading point's light sample and its BSDF sample's pdf, and points that share a normal): prepare fills
 * t (about 2.2 KB, no allocation), then the _table calls give exactly what sample_li_mix_cos and
 * pdf_li_mix_cos give with that w and n, bit for bit (they are those calls' own second halves). */
typedef struct el_envlight_mix_cos_table {
  int usable, hn;                            /* h usable with l; the normal was usable (nl) */
  float n[3], nl[3], s;                      /* the world normal; in light space; the bounds' sum S(n) */
  double a[EL_ENVLIGHT_HOTSPOT_MAX + 1];     /* the normalised weights */
  float bm[32 * 16];                         /* the cells' running sums of bound x mass */
} el_envlight_mix_cos_table;
EL_DEF void el_envlight_mix_cos_prepare(const el_envlight *l, const el_envlight_hotspots *h, const el_envlight_mix_weights *w,
                                        const float n[3], el_envlight_mix_cos_table *t);
EL_DEF void el_envlight_sample_li_mix_cos_table(const el_envlight *l, const el_envlight_hotspots *h, const el_envlight_mix_cos_table *t,
                                                const float u[2], float wi[3], float rgb[3], float *pdf);
EL_DEF float el_envlight_pdf_li_mix_cos_table(const el_envlight *l, const el_envlight_hotspots *h, const el_envlight_mix_cos_table *t,
                                              const float dir[3]);
/* The mixture's solid-angle density at dir: pdf_li(dir) x w_part / share_part for the part holding dir
 * (0 for a part of weight 0). With default weights: pdf_li(dir), bit for bit. */
EL_DEF float el_envlight_pdf_li_mix(const el_envlight *l, const el_envlight_hotspots *h,
                                    const el_envlight_mix_weights *w, const float dir[3]);
/* Spot k alone: sample_li's density restricted to a region R_k around spot k and renormalised, pdf_li(dir) /
 * P(R_k) inside R_k, 0 outside (NOTES ON HOT SPOTS 5). Importance BILINEAR: R_k is the rectangle of le()'s
 * patches that covers the spot's cone (wrapping at the seam; a cone over a pole: full patch rows), drawn
 * with the patch table's own integer weights and its in-patch bilinear inversion, so the sample's *pdf is
 * pdf_li_spot(wi) bit for bit; other modes: R_k is the spot's bins (sample_li_mix with spot k's weight
 * alone). rgb may be NULL. k out of range, h not made for l, a zero or NaN dir: pdf 0 (and wi a valid
 * unit vector, rgb 0). */
EL_DEF void el_envlight_sample_li_spot(const el_envlight *l, const el_envlight_hotspots *h, int k, const float u[2],
                                       float wi[3], float rgb[3], float *pdf);
EL_DEF float el_envlight_pdf_li_spot(const el_envlight *l, const el_envlight_hotspots *h, int k, const float dir[3]);

/* << declarations: hot spots */

/* ----------------------------------------------------------------------------------------------------
 * NOTES ON HOT SPOTS AND THE MIXTURE SAMPLER (issue 22; numbers: bench/bench_sun.c, gcc 12 -O3, this
 * project's shared, loaded 2-core machine)
 *
 * 1. FINDING THEM. On the light's importance bins (sample_li's own distribution: probability m_b per
 *    bin), a bin is a CORE bin when its density m_b / (solid angle of the bin) is at least min_radiance
 *    times the map's mean 1 / (4 pi), a RIM bin when at least min_radiance / 8 (a one-texel sun's edge
 *    neighbours hold 1/6 of its density in the cell-average map: its bilinear spill belongs to it).
 *    Bins are grouped into connected components (8 neighbours, u wraps around the seam, a pole row's
 *    bins also touch the bins half a turn away): a core with its rim; when that region's cone is too
 *    wide, each core region alone. A component is a spot when its share sum(m_b) >= min_share and every
 *    corner and edge midpoint of its bins lies within max_half_angle of its axis (the mass-weighted
 *    mean direction); the largest max_spots are kept, sorted by share.
 *    MEASURED (defaults: min_radiance 100, min_share 0.05, max_half_angle 11.5 deg; share / half-angle):
 *    city: 1 spot, its sun, 0.245 / 2.1 deg (124 bins); forest: 1, 0.065 / 3.4 deg (sun through the
 *    leaves); night: 3 lamps, 0.174 / 5.6, 0.153 / 2.2, 0.077 / 1.6 deg; studio: 4 lamps, 0.335 / 7.6,
 *    0.260 / 6.6, 0.153 / 8.2, 0.117 / 2.9 deg; sunset: none (its sun holds 0.024 < min_share).
 *    Generated 1024x512 maps: a sunrise (disc of 0.5 deg at 7.9 deg elevation) 0.750 / 1.2 deg; two
 *    suns 0.537 / 0.9 and 0.395 / 1.0; a sun at the pole (the first row) 0.994 / 0.7 deg; across the
 *    seam 0.923 / 1.0; one texel 0.899 / 0.6 deg; a smooth sky: none. The thresholds matter little
 *    on suns: from min_radiance 10 to 1000 the spots of city, night (3 largest), the generated maps
 *    keep their count and their shares change by <= 0.01; studio loses a lamp at 300 and all at 1000
 *    (they are a few hundred times the mean, not a sun's 10^4x); forest keeps its one spot (3.4 deg at
 *    10, 1.6 deg at 1000). COST: one pass over the bins plus a search per component, about 21 M
 *    instructions at 1024x512 (callgrind).
 * 2. THE MIXTURE. p(w) = sum_k a_k p_li(w) [w in S_k] / P_k + a_r p_li(w) [w in rest] / P_r, where P_k,
 *    P_r are the shares (their sample_li probabilities) and a the normalised weights: sample_li's density
 *    rescaled per part by a / P. a = P (the default) is p_li. Each part is sampled from its own integer
 *    CDF over the same bins (distribution2d.h; the rest through a guide table), uniform inside the bin
 *    like sample_li (the same direction tables); the returned pdf is the pdf query's (the part of a
 *    direction is found with pdf_li's own bin search), so sample and query agree bit for bit. The
 *    sampled density equals the stated one up to the integer CDFs' rounding of bin probabilities (about
 *    2^-32 of the part) and directions rounded across a bin edge at a spot's border (within 2^-21 of a
 *    bin, as sample_li). tests/test_envlight_sun.c: chi-square over the bins, unbiasedness against a
 *    quadrature, default weights bit for bit.
 * 3. WHAT IT BUYS: a point where the sun is hidden (bench_sun table 3: E = integral of L max(0, n.w) V,
 *    V = 0 in the largest spot's cone; variance per sample, 2^20 samples; the spot's weight moved to 0
 *    and the other parts keeping their proportions). Against sample_li (= default weights): sunrise
 *    7.9x less (n up) and 6.7x (n towards the sun), two suns 2.3x / 2.2x, city 2.2x / 2.1x, studio 1.9x
 *    / 1.7x, night 1.4x, forest 1.3x / 1.2x. Against sample_li_cos (product sampling, which keeps
 *    drawing the hidden sun: 66% of its samples on sunrise for n up, 87% towards the sun): 2.8x / 6.5x
 *    less on sunrise, 1.1x / 1.5x on two suns, 1.25x / 1.3x on city, but MORE on the maps whose rest is
 *    far from uniform in cosine (forest 5x, night 3.5x, studio 2.5x more: the mixture's rest has no
 *    cosine factor). A weight of 0.02 instead of 0 keeps 93-98% of the gain. The share of samples in the
 *    sun's cone follows the weight exactly (10.0% for 0.1, 2.0% for 0.02).
 *    PRODUCT SAMPLING RESTRICTED TO THE REST (sample_li_cos with the draws in the cone rejected, scaled
 *    by the acceptance rate: what an exact "rest x product" part would reach; not implemented, it needs
 *    the product sampler's cells without the spots' bins) gives, n up / towards the spot, 34x / 160x
 *    less variance than sample_li_cos on sunrise, 45x / 18x on city, 6x / 6x forest, 2.7x / 23x night,
 *    2.4x / 29x studio, 240x / 300x two suns (the second one below the horizon).
 * 4. THE REST x COSINE MIXTURE (sample_li_mix_cos, pdf_li_mix_cos): the rest's bins grouped into 32 x 16
 *    cells; per call every cell gets B = max(1e-3, cos(max(0, angle(n, centre) - radius))), an upper
 *    bound of n.w over the cell (its cone: the farthest of 5 x 5 points plus a tenth of the cell's
 *    angle; the floor keeps every cell with mass reachable, so light sampling alone stays unbiased);
 *    a cell is picked with probability B x its rest mass / S(n), then a rest bin of the cell from the
 *    cell's table (uint16 integer CDFs of 32768 units: its rows, then the row's bins, each with the product
 *    section's 8-bucket guide), uniform in (u, v) inside the bin: sample_li's density inside the cell up
 *    to the tables' rounding (every bin with mass keeps at least one unit). pdf = a_rest x B x the cell's
 *    mass / S(n) x the bin's two widths / 2^30 over its solid angle (the entries the sample just read, not
 *    the light's pdf table), as sample_li_mix on the spots. Shadowed point (table 3, the
 *    spot's weight 0.02 / 0) against sample_li_cos: sunrise 16x / 20x less variance (n up), 111x / 165x
 *    (n towards the sun); city 10x / 19x and 12x / 21x; two suns 1.7x and 3.0x; forest 0.96x / 1.3x and
 *    1.6x / 2.0x; but night 0.76x-1.3x and studio 0.43x-0.76x (more variance: their other lamps stay lit
 *    and are drawn without the cosine, and 32 x 16 cells bound the cosine loosely). COST: O(cells) per
 *    sample and per pdf (512 bounds in a vectorisable loop, then a running sum): 7.3x (3.4 against
 *    0.47 us) and, before the loop was vectorised, 9.2x sample_li_cos's time with radiance (sunrise, best
 *    of 5 interleaved rounds, loaded machine); so at equal time it wins on sun maps (sunrise, city:
 *    10-165x less variance), not on lamp maps. el_envlight_mix_cos_prepare does the 512 bounds once per (w, n)
 *    and the _table calls reuse them (a shading point's sample and its BSDF sample's pdf, points sharing a
 *    normal: issue 22's renderer first kept 8 per thread, 4.6x -> 1.8x its render time with the cache on
 *    scenes/sun_shadow_object.pbrt; now one per shadowed cell of its cache, shared, 1.3x). The pdfs of
 *    the mixtures find pdf_li's bin once (el_envlight__hot_pdf_li_bin: its search and hot_bin's were a
 *    third of the pdf's instructions). A sample then read a cell's el_distribution2d (its marginal and a
 *    row, uint32), the light's pdf table twice (the direction's pdf, then the mixture's) and the texels at
 *    random places; now (issue 22's cost round) one row of its cell table (guided searches, no pdf-table
 *    read: the pdf comes from the same entries; the direction from the direction tables without their pdf;
 *    under a signed-permutation matrix the radiance at the sample's own (u, v), as sample_li's) and the
 *    texels. bench/callgrind_product.sh with OPS="sample_mix_cos_rgb pdf_mix_cos" (city.hdr, spots at 3%,
 *    256 prepared tables): sample with radiance 1060 -> 845 instructions, pdf 287 -> 265 (sunrise.hdr:
 *    1043 -> 827, 288 -> 265); the renderer's dark-cell CPU: see examples/render/sun.c. MEMORY: the cell
 *    tables, 2 bytes per rest bin plus 10 per cell row (1.3 MB at 1024x512 bins, 4.6 MB at 2048x1024; the
 *    el_distribution2d cells were twice that), the rest's own distribution (sample_li_mix's) and the
 *    light's tables.
 * 5. USE. A weight of 0 makes its part's pdf 0: unbiased only where the integrand is 0 there (a shadowed
 *    sun) or with MIS against another technique; keep a floor otherwise. Compensation: the shares are
 *    those of the compensated density. COST: sample_li_mix with radiance 3.9-4.4x sample_li's time on
 *    the sunrise map (292 against 66 ns; 1645 against 416 ns in a busier run; best of 5 interleaved
 *    rounds, loaded machine): the part's search, the pdf query (pdf_li and the bin search) and le(wi).
 *    MEMORY: the rest's distribution and guide table, 2.6 MB at 1024x512 (the light's own tables:
 *    4.9 MB), and each spot's bins. Thread safety: h is read-only after init; it
 *    refers to the light's tables, so free h before l; it is only used with the light it was made from
 *    (checked: another light's h gives sample_li / pdf_li).
 * 6. IMPORTANCE BILINEAR (le()'s patches; the render's density under a sun). The spots are found as in 1 on the
 *    texels' vertex values (luminance x sin theta, compensated as the patch density is: the density's own
 *    weights at the texel centres, one bin per texel); there are no mixture tables (sample_li_mix and the
 *    others are sample_li there). Instead each spot gets R_k, the rectangle of le()'s patches covering its
 *    cone widened by one texel (the patches around a hot texel's vertex reach a texel beyond it): columns
 *    from the cone's extent in phi (asin(sin a / sin theta)), wrapping at the seam; a cone that reaches a
 *    pole takes full patch rows from that pole. sample_li_spot draws a patch row of R_k from the rows'
 *    CDF of wv_r x (the row's integer units over R_k's columns) (uint64, the patch table's own 2^48
 *    units), then a column by the row's own integer CDF restricted to those columns, then (s, t) by
 *    sample_li's own in-patch inversion (el_envlight__patch_finish_at): the probability of a patch is
 *    exactly its sample_li probability / P(R_k), so the density is pdf_li / P(R_k) on R_k. Memory: 8 bytes
 *    per patch row of R_k. Why: sunrise.hdr's sun holds 75% of le()'s patch mass; sample_li kept inside
 *    the cone wastes a quarter of the split's spot samples (sun.c, SPLITTING BY COMPONENT). Measured
 *    (bench_sun 1. and 5.): on the CC0 maps the same spots as the piecewise-constant bins give (city 0.245,
 *    forest 0.065, night 3, studio 4, sunset none; shares within 0.001); on the 1024x512 sunrise map a
 *    rectangle of 9 x 6 patches, sample_li_spot with radiance 120 ns against sample_li's 145, pdf_li_spot
 *    1.08x pdf_li's time.
 */

/* >> declarations: portals (issue 23; NOTES ON PORTALS below) */

/* At most this many portals per light. */
#define EL_ENVLIGHT_PORTAL_MAX 16

typedef struct el_envlight_portal_options {
  int resolution;  /* rectified image texels per axis, 4..4096; 0: twice the map's height within 64..2048
                      (about 2 x 2 rectified texels per map texel at the window's centre: a sun, which
                      le() spreads bilinearly over 2 x 2 map texels, stays sharp) */
  int supersample; /* importance lookups per texel and axis, 1..16; 0: 2 */
  int compensated; /* 1: density max(lum - mean, 0) (the mean over the portal's hemisphere): MIS only */
  float map_share; /* 0..1: the share of samples drawn by the map's own sample_li where a portal is seen
                      (a defensive mixture: a point outside the room that sees a portal's back still
                      finds the sun). 0: pbrt-v4's pure portal density */
  int map_share_outside; /* 1: map_share only at points on or behind some portal's plane (outside a convex
                            room whose windows are the portals: the sphere outside a second window);
                            points in front of every portal's plane get the pure portal density.
                            0: map_share wherever a portal is seen */
} el_envlight_portal_options;

/* One or more planar rectangular portals (windows) of a light, in world space, with pbrt-v4's vertex
 * order and frame: x along p3 - p0, y along p1 - p0, z = x cross y points from the room to the outside
 * (a shading point sees the portal when the portal lies on the +z side of it). PUBLIC (read, never
 * write): count, res, map_share, map_share_outside, bad_index and error; the rest is private. */
typedef struct el_envlight_portal {
  int count, res;                           /* PUBLIC: portals, rectified texels per axis */
  double frame[EL_ENVLIGHT_PORTAL_MAX][12]; /* per portal: p0, x, y, z (unit) */
  double size[EL_ENVLIGHT_PORTAL_MAX][2];   /* |p3 - p0|, |p1 - p0| */
  uint64_t *sat;                            /* count x (res+1)^2 integer summed-area tables */
  int compensated, fell_back;               /* fell_back: the compensated density was empty: plain one */
  float map_share;                          /* options.map_share */
  int map_share_outside;                    /* options.map_share_outside */
  int bad_index;                            /* after a failed init: the portal at fault, else -1 */
  char error[128];                          /* after a failed init: what is wrong, else "" */
} el_envlight_portal;

/* points: count x 4 vertices x 3 floats, world space (pbrt-v4's "point3 portal", ignoring the light's
 * CTM). The tables are built from light's le() (its matrix and scale); pass the same light to the
 * queries (the portal keeps no pointer to it). opt may be NULL. Errors:
 * EL_ERROR_INVALID_ARGUMENT (count outside 1..EL_ENVLIGHT_PORTAL_MAX, options out of range, a degenerate
 * or non-rectangular portal), EL_ERROR_NAN / EL_ERROR_INFINITE (a vertex), EL_ERROR_OUT_OF_MEMORY; then
 * p->error names the problem ("portal 1: not planar: ...") and p->bad_index the portal. */
EL_DEF el_result el_envlight_portal_init(el_envlight_portal *p, const el_envlight *light, const float *points,
                                         int count, const el_envlight_portal_options *opt);
EL_DEF void el_envlight_portal_free(el_envlight_portal *p);
/* Sample a direction wi (world, unit) from point pos: through the portals pos sees, in proportion to
 * the map's luminance there, with solid-angle density *pdf; rgb (may be NULL) gets le(wi). Returns 1
 * when the portals were used, 0 when pos sees no portal (it lies behind every portal's plane or on it)
 * and the map's own sample_li was used instead. With options.map_share s > 0, where pos sees a portal
 * a share s of the samples comes from the map's sample_li and the pdf is the mixture's,
 * (1 - s) portal + s map (then directions outside the portals keep the map's share); with
 * options.map_share_outside only where pos also lies on or behind some portal's plane. */
EL_DEF int el_envlight_portal_sample_li(const el_envlight_portal *p, const el_envlight *light, const float pos[3],
                                        const float u[2], float wi[3], float rgb[3], float *pdf);
/* The density with which sample_li picks wi at pos: 0 for a direction through no portal (when pos sees
 * one), the map's pdf_li when it sees none. */
EL_DEF float el_envlight_portal_pdf_li(const el_envlight_portal *p, const el_envlight *light, const float pos[3],
                                       const float wi[3]);
/* 1 when pos sees a portal (the portal strategy applies there), else 0 (the map's sampling). */
EL_DEF int el_envlight_portal_sees(const el_envlight_portal *p, const float pos[3]);
/* Bytes of the portal's tables: 8 per rectified texel (the tables are all it keeps). */
EL_DEF size_t el_envlight_portal_bytes(const el_envlight_portal *p);

/* << declarations: portals */

/* ----------------------------------------------------------------------------------------------------
 * NOTES ON PORTALS (issue 23; Bitterli, Novak, Jarosz 2015, "Portal-masked environment map sampling";
 * pbrt-v4's PortalImageInfiniteLight, src/pbrt/lights.{h,cpp}, WindowedPiecewiseConstant2D in
 * src/pbrt/util/sampling.h)
 *
 * 1. THE RECTIFIED DOMAIN (pbrt-v4's): a direction w with local z > 0 in a portal's frame has angles
 *    alpha = atan(w.x / w.z), beta = atan(w.y / w.z), and (a, b) = (alpha / pi + 1/2, beta / pi + 1/2) in
 *    [0,1]^2; dw / d(a,b) = pi^2 (1 - w.x^2)(1 - w.y^2) / w.z. From any point in front of the portal,
 *    the directions through it are the rectangle between the images of p0 and p2: a window.
 * 2. THE DENSITY: the rectified image holds, per texel, the mean over supersample^2 points of
 *    luminance(le(w)) x dw/d(a,b) (so a texel's mass is the luminance integrated over its solid angle;
 *    le() carries the light's matrix and scale), quantised to integers (2^40 units over the largest
 *    portal's image, every texel at least 1 unit without compensation, so that every direction through
 *    a portal has pdf > 0 even where the supersampling missed a sun). The density at a point is that
 *    image restricted to the windows, texels cut by a window's edge counted by their covered part: the
 *    map's own radiance distribution through the portals, not a uniform solid angle.
 * 3. THE SAMPLER (not pbrt-v4's bisection of a continuous double SAT, ~400 table reads): one INTEGER
 *    summed-area table per portal (uint64, 8 bytes per texel, exact sums, no cancellation however small
 *    the window or bright the sun elsewhere). The window's row masses have a closed-form prefix (4 table
 *    reads per row boundary, two adjacent pairs), so the row is found by integer binary search over the
 *    window's rows and the position in the row by linear inversion; then the column by a binary search
 *    over the row's prefix (2 reads per step). pdf = q_texel R^2 / (window mass) / (dw/d(a,b)), the exact
 *    density of those steps. Several portals: one is picked by the windows' masses with the same u.
 *    No rectified RGB image: radiance is le() of the map. The searches prefetch the rows of the steps
 *    ahead (at 1024^2 most steps miss the cache). COST (bench/bench_portal.c, 4 floor points of a room,
 *    gcc -O3, a shared 2-core machine): 206-236 ns per sample with the radiance and the pdf, against
 *    1006-1175 ns for a plain port of pbrt-v4's sampler (bisection over a double SAT) at the same
 *    resolution: 4.9x less; at equal variance (the same density: relative variance 0.039 both on a
 *    smooth sky, 0.045 / 0.047 on city; the map's sample_li: 50 / 25). MEMORY: 8 bytes per rectified
 *    texel (pbrt-v4: 24); the default resolution is twice the map's height (city, 1024x512: 1024^2,
 *    8 MB per portal, built in about 0.3 s), because le() spreads a sun bilinearly over 2 x 2 map
 *    texels and a density constant per rectified texel follows that only with about 2 x 2 rectified
 *    texels per map texel: at the map's height the irradiance's variance was 3.6x higher (0.165) and
 *    the rendered room's gain 5.3x instead of 8x. The renderer (bench/bench_portal_render.c, path
 *    traced, depth 3): time to unit variance 8.0x better on city with its sun shining in (the rest is
 *    indirect light from the sunlit floor, which paths find by BSDF sampling), 166x on an overcast
 *    sky; direct light alone (depth 1) 37x and 1800x.
 * 4. FALLBACK: a point on or behind every portal's plane (or seeing windows of zero mass) uses the map's
 *    sample_li / pdf_li, so the strategy stays unbiased everywhere; sample_li returns which was used.
 *    Directions through no portal have pdf 0 (as pbrt-v4): the caller's BSDF samples must find them.
 * 5. COMPENSATION (pbrt-v4 has none for portals): max(lum - mean, 0), mean over the portal's whole
 *    hemisphere of directions (solid-angle weighted): with MIS only (dim directions get pdf 0).
 *    MAP SHARE (options.map_share): a point outside the room may stand in front of a portal's plane and
 *    see its back; its sun is then sought only through the room. A share s of the samples from the
 *    map's sample_li, pdf (1 - s) portal + s map, keeps such points well sampled (the renderer uses
 *    0.1: a sphere outside a window read 1% dark at 8 seeds without it, -3.6 sd; with it 0.07 sd).
 *    options.map_share_outside keeps the share to points on or behind some portal's plane (outside a
 *    convex room whose windows are the portals), so that the room's inside keeps the pure portal
 *    density: in the renderer's one-window rooms the share everywhere cost 25% of the time to unit
 *    variance (its map pdf per sample, its samples that hit the walls); a point outside beyond a
 *    windowless wall then finds its sun by the caller's BSDF samples alone (unbiased, noisier).
 * 6. INPUTS: a NaN, infinite or zero u is clamped as sample_li's; a NaN or zero wi has pdf 0; a NaN pos
 *    sees no portal. Queries are read-only and thread-safe (the fallback builds the light's tables lazily,
 *    as sample_li does). */

/* ----------------------------------------------------------------------------------------------------
 * NOTES ON GLOSSY LOBES (issue 20's "every lobe"; measured in examples/render with bench/lobes.py: time
 * to unit variance of direct lighting, light and BSDF sample with MIS, against sample_li's map alone)
 *
 * sample_li_cos follows L(w) max(0, n.w): the integrand of a diffuse lobe. For a glossy Trowbridge-Reitz
 * lobe of alpha below about 0.1 (near-specular metal) pass wo's MIRROR DIRECTION r = 2 (wo.n) n - wo in
 * place of n, to sample_li_cos and to pdf_li_cos alike (the BSDF sample's MIS weight): the product then
 * follows L(w) max(0, r.w), a broad proxy of the lobe around its peak. It is no bound of the lobe (the
 * lobe's tail past 90 degrees of r has pdf 0), so use it only with MIS against the BSDF sample, which
 * covers the whole lobe. Measured on a metal of alpha 0.02: 3.4x the map alone's efficiency under
 * studio.hdr (around n: 2.4x), 6.1x at alpha 0.06 (around n: 3.9x); at alpha 0.2 n is better (5.5x
 * against 4.5x). Under a map with a sun (city.hdr: its brightest 1e-5 of the sphere holds 22% of the
 * power) neither pays: the variance is the map alone's, the product sample costs more (0.64-0.73x), so
 * the renderer keeps sample_li there. A lobe with a diffuse part (plastic) keeps n at every alpha (alpha
 * 0.05: 1.8x on city, 6.6x on studio; the mirror 0.5x). Broad lobes (alpha 0.3 and more beside a diffuse
 * part, 0.6 and more without) do best with the product light sample alone, no BSDF sample (weight 1).
 * TRIED AND DROPPED: the product of the map with the lobe itself at one shading point, as a k x k grid
 * over the lobe's sampling square (cells of equal GGX probability weighted by le() at their centres,
 * used as the BSDF sample, MIS with the renderer's light sample): 0.8-1.5x less variance than the choice
 * above (studio: the mirror's proxy; city: the map alone) for k^2 = 16-64 lookups per point (about 10,000
 * instructions at k = 4), so 0.16-0.47x of its efficiency.
 */

#ifdef __cplusplus
}
#endif
#endif /* EL_ENVLIGHT_H */

/* ====================================================================================================
 * NOTES (the reasons behind the API; a user of the functions above needs none of this)
 *
 * MAPPING AND ORIENTATION (pbrt-v3's, in light space): theta is the angle from +z, phi = atan2(y, x) in
 * [0, 2pi), and (u, v) = (phi / 2pi, theta / pi); u runs along a row (left to right), v down the
 * image (row 0 is theta = 0). world = light_to_world * light.
 *   Mirroring. This mapping shows the image unmirrored only in a LEFT-handed world (pbrt's): seen from
 *   inside, with +z up, "to the right" of direction phi is phi + d in a left-handed frame and phi - d in a
 *   right-handed one. So in a right-handed world (Blender, Mitsuba, OpenGL, Embree users) pbrt's
 *   "RotateX(-90)" (light +z -> world +y) shows the map MIRRORED left-right compared with those tools;
 *   no rotation can fix that, a reflection can. Therefore:
 *   - el_envlight_yup_matrix(): y up, right-handed, exactly Mitsuba 3's convention (u = 0.5 looks
 *     along +z, u = 0.25 along +x, u = 0 / 1 along -z). It is a reflection (determinant -1).
 *   - el_envlight_zup_matrix(): z up, right-handed, exactly Blender's (u = 0.5 looks along +x, u = 0.75
 *     along +y). Also a reflection.
 *   tests/test_envlight.c proves both with an asymmetric map against Mitsuba's and Blender's own
 *   formulas, and shows that a plain RotateX(-90) gives u' = 0.25 - u (a mirror image).
 *
 * OPERATIONS (directions are float[3] pointing away from the scene, in world space):
 *   le(dir)          bilinear at full resolution, Repeat in u, Clamp in v (pbrt-v3 used Repeat in v too,
 *                    so the north pole row bled into the south pole: pbrt-v3 issue #63).
 *   sample_li(u0,u1) a direction, its radiance and its solid-angle pdf. pdf_li(dir) the same pdf.
 *   sample_le / pdf_le  rays entering the scene's bounding sphere (bidirectional methods); they need
 *                    el_envlight_preprocess(center, radius), nothing else does.
 *   power()          pi r^2 * integral of L over the sphere (pbrt-v4's Phi; pbrt-v3's Power returned
 *                    pi r^2 * the unweighted mean texel, off by 4 pi and ignoring sin(theta)).
 *   bytes()          the memory in use (image copy + whatever sampling tables exist).
 *
 * WHERE IT DEPARTS FROM pbrt, AND WHY (pbrt-v3 InfiniteAreaLight, src/lights/infinite.{h,cpp})
 * 1. The sampling density (pbrt-v3 issue #62). le() is bilinear but the density is piecewise constant.
 *    pbrt-v3 builds its distribution at TWICE the image resolution from point lookups (4x the memory and
 *    time). Ours (EL_ENVLIGHT_IMPORTANCE_CELL_AVERAGE, the default) uses one bin per texel whose value is
 *    the EXACT average of the bilinear reconstruction over the bin (separable weights 1/8, 3/4, 1/8 when
 *    bins and texels coincide; exact tent integrals for any other resolution), times sin(theta) at the
 *    bin centre. Every direction where le() > 0 has pdf > 0 (so light sampling alone is unbiased), at a
 *    quarter of pbrt's bins. bench/bench_envlight.c measures the variance of the choices (CELL_AVERAGE,
 *    PBRT_V3 = 2x point lookups, TEXEL = raw texels, which misses the bilinear spill of a bright texel
 *    into its dark neighbours: a bias): at 2x, cell averages and point lookups are equally good, and 2x
 *    cuts the mismatch between density and le by 4x (the irradiance variance by 0-30%) for 4x the table
 *    memory; ask for it with importance_width/height when the memory is there.
 * 2. The distribution is distribution2d.h's integer-CDF one: every bin with f > 0 is reachable at any
 *    dynamic range (pbrt's float CDF loses bins next to a sun). Samplers: a guide table (the default:
 *    constant expected time, exactly CDF inversion's points, so it keeps stratification), CDF inversion
 *    itself (binary searches) or an alias table (constant time, does NOT keep the stratification of
 *    low-discrepancy input).
 * 3. Poles. sinf(pi) is -8.7e-8, so pbrt-v3's "if (sinTheta == 0) pdf = 0" never fires at the south pole
 *    and its pdf can be negative or huge. Here sample_li's sin(theta) is built from the bin edge nearer
 *    the pole (sin exactly 0 there) plus a positive term, never a difference (small maps: sinpi(min(v,
 *    1 - v)), an exact argument), sampled points stay at least 2^-21 (in u and v) inside their bin (so never on a pole or a
 *    bin edge), and pdf_li clamps sin(theta) below at 1.4e-6 (the value at v = 2^-21). Every pdf returned
 *    is finite and >= 0.
 * 4. pdf_li(sample_li(u).dir) against the sampled pdf: both are the same bin's value divided by
 *    sin(theta), which sample_li takes from the sampled angle and pdf_li from the direction. For
 *    signed-permutation matrices (identity, y-up, z-up) the 2^-21 margin exceeds every rounding error of
 *    the direction and of pdf_li's own bin search, so the bin is the same and the two pdfs differ only
 *    by the rounding of sin(theta): by at most 2^-20 relative (measured at most 3.7 * 2^-23 = 4.4e-7;
 *    about half agree bit for bit; tests/test_envlight.c checks the bound for every sampler, map size
 *    and matrix). sample_li could compute its pdf with pdf_li's arithmetic and match bit for bit, but
 *    that measured 126.6 instead of 93.5 instructions per sample. For a general rotation, rounding in
 *    the round trip world -> light can move a direction near a pole across a bin edge, so sample_li
 *    returns pdf_li(dir) itself: equal bit for bit (about 120 more instructions per sample: 218 instead
 *    of 93.5 with the guide sampler). If that bin has no mass (a lit pole row next to dark bins: the
 *    pdf would be 0, a lost sample), the sample moves to its own bin's centre. Its radiance is then
 *    le(wi) itself, from the same light-space direction as the pdf (near a pole the sample's own (u, v)
 *    can be a texel away from wi's: 0.915 against 0.586 in issue 24's campaign, radiance and pdf of
 *    different points). With a signed permutation the radiance stays the lookup at the sample's own
 *    (u, v): it differs from le(wi) as a shift of at most 1e-4 texel would (tests/test_envlight_edges.c,
 *    city), far below what an MIS weight or an estimate can see, and le(wi) would cost 21% more per
 *    sample with radiance (bench/bench_hdri.c: 478 against 576 ns, best of 5 interleaved rounds on a
 *    loaded machine; 157 ns without radiance).
 * 5. No libm trigonometry on the hot paths. sample_li finds the BIN and the fractions within it (no
 *    float point placement), then builds the direction from per-row tables (sin, cos of the bin's
 *    pole-side edge) and per-column tables (cos, sin of phi_i already multiplied into light_to_world) by
 *    angle addition, with x - x^3/6 and 1 - x^2/2 for the in-bin angle (<= pi/128: maps of at least
 *    256x128 bins; smaller maps use sinpi/cospi polynomials, 1.9e-7 relative). With SSE2 (any x86-64;
 *    EL_NO_SIMD turns it off) the guide sampler's search runs inline in sample_li with vector ends (u
 *    clamped and scaled to units and guide cells at once, each bin's two CDF entries read as one 8-byte
 *    pair, the fractions computed in the lanes the direction wants), the two angles go through the
 *    polynomials together and the direction is formed as 4-vectors; the scalar code does the same
 *    operations in the same order. The pdf is the bin's, (wv wu) K from its integer widths, the pdf
 *    table's expression, / sin theta.
 *    le: an atan polynomial (2.5e-7 rad) for (u, v). pdf_li needs only the bin, not (u, v): a table over
 *    a monotone "diamond angle" of (x, y) and one over t = 1 - z / (r + |z|) on both hemispheres (each
 *    cell holds at most one bin edge, compared exactly), then a per-bin pdf table: three divisions, two
 *    square roots (the hardware instruction, without libm's errno branch), no atan, no branch.
 *    Costs, measured by bench/bench_envlight.c (callgrind, gcc 12 -O3, no -march; the generated
 *    2048x1024 map): sample_li 93.5 instructions with the guide sampler (95.6-97.6 on the five CC0
 *    1024x512 maps in ../shared/envmaps: --callgrind OP N MAP), 394 with CDF inversion, 240 with the
 *    alias table; with the radiance 257; pdf_li 75 (general rotation 93); le 248; construction 117 M
 *    instructions, 27-31 ms with fresh memory, about 11 ms of it page faults (pbrt-v3: ~470, ~300,
 *    313 ms). See tutorials/05-appendix-fast-paths.md, A3.9.
 *    BATCHES. Each sample_li is a chain of dependent cache misses on a large map (the guide entry, the
 *    CDF pair it points to, the texels), and in a renderer's loop the work between two samples (ray
 *    traversal, shading) keeps their misses from overlapping. el_envlight_sample_li_n takes n samples
 *    and prefetches in stages, 32 samples at a time (guide entries, then CDF pairs, then the samples
 *    and their texel rows, then the radiance), running sample_li's own code for every result, so the
 *    results are bit-identical. bench_envlight (2048x1024, a loop with other memory work between
 *    samples, quiet machine): 114-135 ns per sample one at a time, 64-92 ns batched (1.4-1.9x); the
 *    renderer's bench_render loop, which draws a pixel's light samples together, runs 1.2x faster
 *    with it (the same image). el_envlight_pdf_li_n and el_envlight_le_n (issue 21: a wave's escaped
 *    rays) do the same in two passes: each direction to light space and its pdf bin (le: its four
 *    texels) prefetched, then the single call's arithmetic (bit for bit). Instructions as the single
 *    calls' (callgrind, loop subtracted: pdf_li 82, pdf_li_n 88; le 255, le_n 252); time (2048x1024,
 *    random directions, batches of 64, CPU ns per call, loaded 2-core machine): pdf_li 29-38 -> 14-17,
 *    le 101-132 -> 40-69; bench_envlight's loop with other memory work: pdf_li + le 160-186 -> 100-114
 *    ns (1.6x). Passes over 32 lanes (16: about 10% slower per call, sample_li_n too); le_n then waits
 *    on its prefetches (perf: a third of its samples), the line-fill buffers full. The renderer's wave
 *    loop (render --stats loop CPU, 1 thread, 32 spp, 5 interleaved runs): bench_city direct 0.96 ->
 *    0.78 s, path 1.43 -> 1.21 s, bench_studio path 1.45 -> 1.18 s, direct 0.58 -> 0.57 s; against a
 *    later main (4 runs): 0.87x, 0.85x, 0.82x, 1.00x (the map alone on bench_city direct: 0.84x).
 *    MEMORY: the texels (12 bytes each) + the distribution (4 bytes per bin) + the pdf table (4 bytes per
 *    bin) + the guide (1 byte per bin) or alias (8 bytes per bin) table when chosen + the bin finders
 *    and direction tables (64 bytes per row, 32 per column: tiny). 2048x1024: 25 MB + 18 MB with the
 *    default guide table (pbrt-v3: ~100 MB).
 * 6. Only what is used is built. init copies (and scales) the texels and integrates them; nothing else.
 *    The sampling distribution is built on the first sample_li / pdf_li / sample_le / pdf_le, or by
 *    el_envlight_prepare_sampling(). THREAD SAFETY: the lazy build is thread-safe with GCC/Clang (a
 *    __atomic once-flag: one thread builds, the others spin until it is done); without those builtins
 *    (or with EL_ENVLIGHT_NO_ATOMICS) call el_envlight_prepare_sampling() before sharing the light.
 *    After that, every query is read-only and thread-safe. No MIP pyramid is built: le() is a level-0
 *    bilinear lookup; a renderer that wants filtered (ray-differential) lookups builds an el_mipmap
 *    from the same pixels (mipmap.h).
 * 7. Bad input is an error, not a NaN later: NaN / Inf / negative texels (light.bad_index names the
 *    first one; or EL_ENVLIGHT_BAD_TEXELS_ZERO turns them into 0), a non-orthonormal matrix, a bad
 *    scale, sizes that overflow.
 *
 * INPUT CONVENTIONS for the queries (which never fail): a direction need not be unit length: any finite,
 * nonzero one is normalised safely (scaled by its largest component first, so components near FLT_MAX
 * or denormal work under any matrix) and the result depends only on its direction; a zero, NaN or
 * infinite direction gives le = 0 and pdf = 0. u outside [0,1) is clamped (NaN -> 0, 1 -> 0x1.fffffep-1). A light with no
 * emission (all black) has pdf 0 everywhere and sample_li returns pdf 0, radiance 0.
 * A sample with pdf 0 must be skipped by the caller (as in pbrt).
 * MIS COMPENSATION (options.compensated, pbrt-v4): the density is max(L - mean L, 0) sin(theta), so
 * light sampling alone NO LONGER covers the dim parts of the map: use it only with MIS against BSDF
 * sampling. A map where nothing exceeds the mean (a constant one) falls back to the plain density.
 *
 * BIG MAPS (issue 24; bench/bench_bigmaps.c, numbers in docs/accuracy-vs-time.md). A 16384x8192 map is a
 * 1.5 GB float image. Before: init copied it (1.5 GB more, page-faulted in) and the sampling tables were
 * built at its resolution (1.15 GB; with the product tables 2.4x the image at peak, 5-18 s CPU). Now:
 *   - THE CAP. When importance_width is 0 the importance map is at most importance_cap x importance_cap/2
 *     bins (EL_ENVLIGHT_IMPORTANCE_CAP = 4096 by default; -1: none), each the EXACT mean of le()'s bilinear
 *     reconstruction over the bin (the CELL_AVERAGE weights for any ratio, bins need not divide the image),
 *     times sin(theta). The pdf is exact for the piecewise-constant density actually sampled (pdf_li and
 *     sample_li agree as in point 4); radiance is still read from the full image. A capped PBRT_V3 map
 *     takes cell averages (its point lookups at fewer bins could miss a small sun: pdf 0 where le > 0);
 *     TEXEL is never capped. The cost, measured on a 16384x8192 map with a 0.5-degree sun (radiance 1e5,
 *     half the map's power), relative variance per sample of sample_li's estimates (full resolution /
 *     cap 8192 / 4096 / 2048 / 1024): the luminance integral 0.026 / 0.072 / 0.19 / 0.43 / 1.08, the
 *     irradiance of a surface facing the sun 0.37 / 0.45 / 0.69 / 1.16 / 2.45; tables 1155 / 289 / 73 / 18 /
 *     4.7 MB. A bin wider than the sun's edge mixes sun and sky: that is the whole cost. 4096 keeps the
 *     tables within 0.05x of a 16k image and 0.19x of an 8k one, at 1.9x the irradiance variance of full
 *     resolution on that map (2048: 3.1x); maps up to 4096x2048, and pbrt-v3's 2x map of a 2048x1024 image,
 *     are untouched. Ask for the full resolution with importance_cap = -1 when the memory is there.
 *     Product sampling's tables may use the same cap: the resolved size is (imp_w, imp_h), and the
 *     exact bin means at any size come from one streaming pass (el_envlight__cell_average).
 *   - NO COPY. options.no_copy = 1 keeps a pointer to the caller's pixels (3 channels, no scale: fold a
 *     scale into the pixels first). init then only reads them once (validation and the integral: 0.26-0.34 s
 *     CPU for 16k instead of 0.8-1.1 s with the copy's page faults; with the capped sampling tables
 *     0.7-1.0 s CPU and 72 MB, 0.047x the image; with issue 20's product tables too, 1.4-1.5 s CPU and 93 MB,
 *     0.061x) and el_envlight_bytes leaves them out.
 *     LIFETIME: the pixels must stay allocated and unchanged until el_envlight_free (the light reads them
 *     on every le and sample_li, and its tables describe them); el_envlight_free does not free them. A
 *     texel that BAD_TEXELS_ZERO or CLAMP_NEGATIVE must replace makes init copy after all (light.borrowed
 *     then says 0, and the counts are the copy's); a texel the policy refuses is named without a copy.
 *   - Half floats would halve a copy (0.5x the image), still above the 0.25x budget that no_copy meets
 *     with 0.05x: not done.
 *   - The tables of a capped map are small and filled in one pass each (no calloc-then-touch of arrays
 *     of the image's size); the build reads the image once, row by row, through a ring of u-filtered rows.
 *
 * EQUAL-AREA MAPS (options.mapping = EL_ENVLIGHT_MAPPING_EQUAL_AREA: pbrt-v4's ImageInfiniteLight,
 * Clarberg 2008's octahedral equal-area square). A square N x N image; light space as pbrt-v4's
 * EqualAreaSquareToSphere: the square's centre is +z, its corners -z, (1, 1/2) is +x, (1/2, 1) is +y
 * (el_envlight_square_to_dir / el_envlight_dir_to_square; the light_to_world matrix applies as for
 * lat-long maps). le is the nearest texel (pbrt-v4's LookupNearest), so each texel is exactly a patch of
 * solid angle 4 pi / N^2 with constant radiance: the importance map is the texels' luminance (box means
 * of it under the cap, which is importance_cap / 2 per axis), with no sin(theta), and pdf = mapPdf /
 * (4 pi). The integral is exact. sample_li returns pdf_li(wi) and le(wi) themselves (bit for bit; the
 * mapping's round trip, about 2e-7 in (u, v), stays inside the 2^-21 margin: every sampled point's pdf is
 * its bin's, tests/test_envlight_bigmaps.c). Costs (bench_bigmaps table 3, 2896^2 against 4096x2048
 * lat-long, two runs): sample_li 1.2-1.3x, pdf_li 1.3-1.5x the lat-long times (no inline fast paths),
 * le 0.7x (a nearest lookup), tables 0.8x. Native rather than converted on load: a conversion to lat-long resamples (blurs) the
 * map and its pdf would no longer describe pbrt-v4's image. Not supported (EL_ERROR_INVALID_ARGUMENT):
 * importance PBRT_V3 and BILINEAR, a non-square image. Product sampling has no equal-area tables:
 * sample_li_cos and pdf_li_cos are sample_li and pdf_li there (unbiased, no cosine factor), and
 * prepare_product builds sample_li's tables.
 * ==================================================================================================== */

/* ====================================================================================================
 * IMPLEMENTATION BELOW. Stop reading here if you only need the API.
 * ==================================================================================================== */

#if defined(EL_IMPLEMENTATION) || defined(EL_ENVLIGHT_IMPLEMENTATION)
#ifndef EL_ENVLIGHT_IMPLEMENTATION_DONE
#define EL_ENVLIGHT_IMPLEMENTATION_DONE

#include <float.h>
#include <math.h>
#include <string.h>

/* SSE2 (x86-64 always has it) for sample_li's search and direction, the guided CDF searches and the construction loops;
 * define EL_NO_SIMD for the scalar code, which does the same operations in the same order */
#if !defined(EL_NO_SIMD) && (defined(__SSE2__) || defined(_M_X64) || (defined(_M_IX86_FP) && _M_IX86_FP >= 2))
#define EL_ENVLIGHT__SSE 1
#include <emmintrin.h>
#else
#define EL_ENVLIGHT__SSE 0
#endif

#if !defined(EL_ENVLIGHT_NO_ATOMICS) && (defined(__GNUC__) || defined(__clang__))
#define EL_ENVLIGHT__ATOMICS 1
#else
#define EL_ENVLIGHT__ATOMICS 0
#endif

#if defined(__GNUC__) || defined(__clang__)
#define EL_ENVLIGHT__NOINLINE __attribute__((noinline))
#else
#define EL_ENVLIGHT__NOINLINE
#endif

#ifdef __cplusplus
extern "C" {
#endif

/* >> private helpers: constants and polynomials */

#define EL_ENVLIGHT__PI 3.14159265358979323846
#define EL_ENVLIGHT__MARGIN 4.76837158203125e-7f /* 2^-21: sampled points stay this far inside a bin */
#define EL_ENVLIGHT__SIN_MIN 1.4e-6f             /* pdf_li's floor for sin(theta) (< sin(pi 2^-21)) */
#define EL_ENVLIGHT__HOT_SAMPLE 1
#define EL_ENVLIGHT__HOT_PDF 2
#define EL_ENVLIGHT__HOT_SAMPLE_FINISH 4
#define EL_ENVLIGHT__INV_2PI2 0.05066059182116889f /* 1 / (2 pi^2) */

/* sqrt without libm's errno branch (sqrtf(x < 0) must set errno, so compilers call it for such x):
 * the hardware instruction. Callers pass x >= 0. */
static inline float el_envlight__sqrt(float x) {
#if (defined(__GNUC__) || defined(__clang__)) && (defined(__x86_64__) || (defined(__i386__) && defined(__SSE__)))
  float r;
  __asm__("sqrtss %1, %0" : "=x"(r) : "x"(x));
  return r;
#elif (defined(__GNUC__) || defined(__clang__)) && defined(__aarch64__)
  float r;
  __asm__("fsqrt %s0, %s1" : "=w"(r) : "w"(x));
  return r;
#else
  return sqrtf(x);
#endif
}

/* sin(pi x) for |x| <= 0.5: minimax odd polynomial, max relative error 1.9e-7 in float. */
static inline float el_envlight__sinpi(float x) {
  float x2 = x * x;
  return x * (3.14159264f + x2 * (-5.16770968f + x2 * (2.55006972f + x2 * (-0.598242108f + x2 * 0.0775603462f))));
}
/* cos(pi x) for |x| <= 0.5: minimax even polynomial, absolute error about 1e-7 in float. */
static inline float el_envlight__cospi(float x) {
  float x2 = x * x;
  return 1.0f + x2 * (-4.93480216f + x2 * (4.05870960f + x2 * (-1.33521610f + x2 * (0.234953918f + x2 * -0.0244206859f))));
}
/* atan(t) for t in [0,1]: minimax odd polynomial, absolute error 2.5e-7 rad. */
static inline float el_envlight__atan01(float t) {
  float t2 = t * t;
  return t * (0.999996111f + t2 * (-0.333173674f + t2 * (0.198078099f + t2 * (-0.132333200f +
              t2 * (0.0796232593f + t2 * (-0.0336038535f + t2 * 0.00681166904f))))));
}
/* atan2(y, x) / 2pi in [0, 1] (pbrt's SphericalPhi / 2pi; (0,0) -> 0). May return 1.0 for y = -tiny. */
static inline float el_envlight__phi_turns(float y, float x) {
  float ax = fabsf(x), ay = fabsf(y);
  float mx = ax > ay ? ax : ay, mn = ax > ay ? ay : ax;
  float a = el_envlight__atan01(mn / (mx > FLT_MIN ? mx : FLT_MIN)) * 0.159154943f; /* 1/2pi */
  if (ay > ax) a = 0.25f - a;
  if (x < 0.0f) a = 0.5f - a;
  if (y < 0.0f) a = 1.0f - a;
  return a;
}
/* atan2(r, z) / pi in [0, 1] for r >= 0 (pbrt's SphericalTheta / pi). */
static inline float el_envlight__theta_halfturns(float r, float z) {
  float az = fabsf(z);
  float mx = az > r ? az : r, mn = az > r ? r : az;
  float a = el_envlight__atan01(mn / (mx > FLT_MIN ? mx : FLT_MIN)) * 0.318309886f; /* 1/pi */
  if (r > az) a = 0.5f - a;
  if (z < 0.0f) a = 1.0f - a;
  return a;
}
/* Light-space (u, v) in [0,1] -> unit direction, with accurate sin(theta) at both poles; vp is v's
 * distance to the nearer pole (min(v, 1 - v), or better when the caller knows it exactly). Returns
 * sin(theta). */
static inline float el_envlight__uvp_to_dir(float u, float v, float vp, float d[3]) {
  float st = el_envlight__sinpi(vp); /* no sinf(pi) = -8.7e-8 */
  float ct = el_envlight__sinpi(0.5f - v);
  float a = 2.0f * u; /* phi = pi a, a in [0, 2] */
  int n = (int)(a + 0.5f); /* 0, 1 or 2 */
  float r = a - (float)n;  /* [-0.5, 0.5] */
  float sgn = (n & 1) ? -1.0f : 1.0f;
  float sp = sgn * el_envlight__sinpi(r), cp = sgn * el_envlight__cospi(r);
  d[0] = st * cp;
  d[1] = st * sp;
  d[2] = ct;
  return st;
}
static inline float el_envlight__uv_to_dir(float u, float v, float d[3]) {
  return el_envlight__uvp_to_dir(u, v, v < 0.5f ? v : 1.0f - v, d);
}
static inline void el_envlight__mul(const float m[9], const float a[3], float b[3]) {
  b[0] = m[0] * a[0] + m[1] * a[1] + m[2] * a[2];
  b[1] = m[3] * a[0] + m[4] * a[1] + m[5] * a[2];
  b[2] = m[6] * a[0] + m[7] * a[1] + m[8] * a[2];
}
static inline void el_envlight__mul_transpose(const float m[9], const float a[3], float b[3]) {
  b[0] = m[0] * a[0] + m[3] * a[1] + m[6] * a[2];
  b[1] = m[1] * a[0] + m[4] * a[1] + m[7] * a[2];
  b[2] = m[2] * a[0] + m[5] * a[1] + m[8] * a[2];
}
/* world -> light and light -> world with the permutation fast path */
static inline void el_envlight__to_light(const el_envlight *l, const float w[3], float d[3]) {
  if (l->exact_transform) { /* world[i] = sign[i] * light[perm[i]] */
    d[0] = l->isign[0] * w[l->iperm[0]];
    d[1] = l->isign[1] * w[l->iperm[1]];
    d[2] = l->isign[2] * w[l->iperm[2]];
  } else el_envlight__mul_transpose(l->to_world, w, d);
}
static inline void el_envlight__to_world(const el_envlight *l, const float d[3], float w[3]) {
  if (l->exact_transform) {
    w[0] = l->sign[0] * d[l->perm[0]];
    w[1] = l->sign[1] * d[l->perm[1]];
    w[2] = l->sign[2] * d[l->perm[2]];
  } else el_envlight__mul(l->to_world, d, w);
}
static inline float el_envlight__clamp_u(float u) {
  if (!(u > 0.0f)) return 0.0f;
  return u < 0.99999994f ? u : 0.99999994f;
}

/* Cold path for a light-space direction whose squared length is not a normal float: NaN / Inf / zero
 * -> 0 (unusable), otherwise rescale by the largest component and return 1. */
static int el_envlight__rescale(float d[3]) {
  float m = fabsf(d[0]);
  if (d[0] != d[0] || d[1] != d[1] || d[2] != d[2]) return 0;
  if (fabsf(d[1]) > m) m = fabsf(d[1]);
  if (fabsf(d[2]) > m) m = fabsf(d[2]);
  if (!(m > 0.0f) || m > FLT_MAX) return 0;
  d[0] /= m; d[1] /= m; d[2] /= m;
  return 1;
}

/* Cold path for a WORLD direction whose light-space squared length is not a normal float: a zero, NaN or
 * infinite direction (returns 0), or finite components so large or so small that their squares, or the
 * sums of a general rotation, leave the float range. The world direction is scaled by its largest
 * component first (the results depend only on the direction), then taken to light space, where its
 * squared length lies in [1, 3]. */
static EL_ENVLIGHT__NOINLINE int el_envlight__to_light_rescaled(const el_envlight *l, const float w[3], float d[3]) {
  float s[3];
  s[0] = w[0]; s[1] = w[1]; s[2] = w[2];
  if (!el_envlight__rescale(s)) return 0;
  el_envlight__to_light(l, s, d);
  return 1;
}
/* A world vector (direction or normal) to light space so that the result depends only on its direction,
 * as le and pdf_li do it: when the light-space squared length is not a normal float (components near
 * FLT_MAX overflow in a general rotation's sums, denormal ones lose their bits in its products) the world
 * vector is rescaled first. Returns 0 for a zero, NaN or infinite vector. */
static int el_envlight__to_light_dir(const el_envlight *l, const float w[3], float d[3]) {
  float len2;
  el_envlight__to_light(l, w, d);
  len2 = (d[0] * d[0] + d[1] * d[1]) + d[2] * d[2];
  if (len2 >= FLT_MIN && len2 <= FLT_MAX) return 1;
  return el_envlight__to_light_rescaled(l, w, d);
}

/* The four texels of the bilinear lookup at (u, v) in [0,1]^2, Repeat in u, Clamp in v (pbrt's s*w - 0.5
 * convention), and the weights of the second column and row. */
static inline void el_envlight__bilerp_texels(const el_envlight *l, float u, float v, const float *p[4], float *fx, float *fy) {
  int w = l->width, h = l->height, x0, y0, x1, y1;
  float s = u * (float)w - 0.5f, t = v * (float)h - 0.5f;
  EL_ASSERT(u >= 0.0f && u <= 1.0f && v >= 0.0f && v <= 1.0f);
  x0 = (int)(s + 1.0f) - 1; /* floor for s >= -1 */
  y0 = (int)(t + 1.0f) - 1;
  *fx = s - (float)x0;
  *fy = t - (float)y0;
  x1 = x0 + 1;
  if (x0 < 0) x0 += w;
  if (x1 >= w) x1 -= w;
  y1 = y0 + 1;
  if (y0 < 0) y0 = 0;
  if (y1 > h - 1) y1 = h - 1;
  if (y0 > h - 1) y0 = h - 1;
  EL_ASSERT(x0 >= 0 && x0 < w && x1 >= 0 && x1 < w && y0 >= 0 && y1 < h);
  p[0] = l->texels + ((size_t)y0 * (size_t)w + (size_t)x0) * 3;
  p[1] = l->texels + ((size_t)y0 * (size_t)w + (size_t)x1) * 3;
  p[2] = l->texels + ((size_t)y1 * (size_t)w + (size_t)x0) * 3;
  p[3] = l->texels + ((size_t)y1 * (size_t)w + (size_t)x1) * 3;
}

/* The bilinear blend of the four texels p (el_envlight__bilerp_texels) with weights fx, fy. */
static inline void el_envlight__bilerp_at(const float *const p[4], float fx, float fy, float rgb[3]) {
  const float *p00 = p[0], *p01 = p[1], *p10 = p[2], *p11 = p[3];
  int c;
  for (c = 0; c < 3; ++c) {
    float a = p00[c] + fx * (p01[c] - p00[c]);
    float b = p10[c] + fx * (p11[c] - p10[c]);
    rgb[c] = a + fy * (b - a);
    if (rgb[c] < 0.0f) rgb[c] = 0.0f; /* rounding of a + f (b - a) with huge ranges */
  }
}
/* Bilinear lookup at (u, v) in [0,1]^2: Repeat in u, Clamp in v. */
static void el_envlight__bilerp(const el_envlight *l, float u, float v, float rgb[3]) {
  const float *p[4];
  float fx, fy;
  el_envlight__bilerp_texels(l, u, v, p, &fx, &fy);
  el_envlight__bilerp_at(p, fx, fy, rgb);
}

/* The radiance at light-space (u, v). */
static void el_envlight__lookup(const el_envlight *l, float u, float v, float rgb[3]) {
  if (l->width == 0) {
    rgb[0] = l->constant[0]; rgb[1] = l->constant[1]; rgb[2] = l->constant[2];
    return;
  }
  el_envlight__bilerp(l, u, v, rgb);
}

static float el_envlight__luminance(const float *rgb) {
  return 0.212671f * rgb[0] + 0.715160f * rgb[1] + 0.072169f * rgb[2]; /* pbrt's y() */
}

/* >> the patch grid (product sampling, importance BILINEAR): forward declarations (the sections are near
 * the end of the file) */
#define EL_ENVLIGHT__CELLS_U 64
#define EL_ENVLIGHT__CELLS_V 32
#define EL_ENVLIGHT__NORMAL_BINS 32
struct el_envlight__warp;
static void el_envlight__warp_free(struct el_envlight__warp *W);
/* importance BILINEAR: le()'s patches (the section "importance BILINEAR" after product sampling) */
static el_result el_envlight__patch_build(el_envlight *l);
static void el_envlight__patch_sample(const el_envlight *l, const float uu[2], float wi[3], float rgb[3], float *pdf);
static float el_envlight__patch_pdf_li(const el_envlight *l, const float dir[3]);
static void el_envlight__patch_sample_n(const el_envlight *l, int n, const float *u, float *wi, float *rgb, float *pdf);
static size_t el_envlight__warp_bytes(const el_envlight *l);

/* >> private helpers: validation */

static el_result el_envlight__check_value(float x) {
  if (x != x) return EL_ERROR_NAN;
  if (x > FLT_MAX || x < -FLT_MAX) return EL_ERROR_INFINITE;
  if (x < 0.0f) return EL_ERROR_NEGATIVE;
  return EL_SUCCESS;
}

/* Validate M (orthonormal to 1e-4), then Gram-Schmidt it in double (keeping the determinant's sign) so
 * that its transpose is its inverse to float precision. */
static el_result el_envlight__set_matrix(el_envlight *l, const float *m) {
  double a[9], e;
  int i, j, k, zero = 1, perm = 1;
  for (i = 0; i < 9; ++i) {
    if (m[i] != m[i]) return EL_ERROR_NAN;
    if (m[i] > FLT_MAX || m[i] < -FLT_MAX) return EL_ERROR_INFINITE;
    if (m[i] != 0.0f) zero = 0;
  }
  if (zero) {
    for (i = 0; i < 9; ++i) l->to_world[i] = (i % 4 == 0) ? 1.0f : 0.0f;
    l->exact_transform = 1;
    for (i = 0; i < 3; ++i) { l->perm[i] = l->iperm[i] = i; l->sign[i] = l->isign[i] = 1.0f; }
    return EL_SUCCESS;
  }
  for (i = 0; i < 9; ++i) a[i] = m[i];
  for (i = 0; i < 3; ++i)
    for (j = 0; j < 3; ++j) { /* (M^T M)_ij: columns i and j */
      double s = 0.0;
      for (k = 0; k < 3; ++k) s += a[3 * k + i] * a[3 * k + j];
      e = s - (i == j ? 1.0 : 0.0);
      if (fabs(e) > 1e-4) return EL_ERROR_NOT_ORTHONORMAL;
    }
  /* Gram-Schmidt on the columns (c0, c1, c2 = c2 - projections) */
  for (j = 0; j < 3; ++j) {
    double n = 0.0;
    for (k = 0; k < j; ++k) {
      double d = 0.0;
      for (i = 0; i < 3; ++i) d += a[3 * i + j] * a[3 * i + k];
      for (i = 0; i < 3; ++i) a[3 * i + j] -= d * a[3 * i + k];
    }
    for (i = 0; i < 3; ++i) n += a[3 * i + j] * a[3 * i + j];
    n = sqrt(n);
    for (i = 0; i < 3; ++i) a[3 * i + j] /= n;
  }
  for (i = 0; i < 9; ++i) {
    l->to_world[i] = (float)a[i];
    if (l->to_world[i] != 0.0f && l->to_world[i] != 1.0f && l->to_world[i] != -1.0f) perm = 0;
  }
  l->exact_transform = perm;
  if (perm)
    for (i = 0; i < 3; ++i)
      for (j = 0; j < 3; ++j)
        if (l->to_world[3 * i + j] != 0.0f) {
          l->perm[i] = j; l->sign[i] = l->to_world[3 * i + j];
          l->iperm[j] = i; l->isign[j] = l->to_world[3 * i + j];
        }
  return EL_SUCCESS;
}

static el_result el_envlight__common(el_envlight *l, const el_envlight_options *opt, float scale[3]) {
  int c;
  el_result r;
  if (opt->importance < 0 || opt->importance > EL_ENVLIGHT_IMPORTANCE_BILINEAR || opt->sampler < 0 || opt->sampler > 2 ||
      opt->bad_texels < 0 || opt->bad_texels > EL_ENVLIGHT_BAD_TEXELS_CLAMP_NEGATIVE || opt->importance_width < 0 || opt->importance_height < 0 ||
      opt->importance_width > EL_ENVLIGHT_MAX_IMPORTANCE || opt->importance_height > EL_ENVLIGHT_MAX_IMPORTANCE)
    return EL_ERROR_INVALID_ARGUMENT;
  if ((opt->importance_width == 0) != (opt->importance_height == 0)) return EL_ERROR_INVALID_ARGUMENT;
  if (opt->mapping < 0 || opt->mapping > EL_ENVLIGHT_MAPPING_EQUAL_AREA) return EL_ERROR_INVALID_ARGUMENT;
  for (c = 0; c < 3; ++c) {
    r = el_envlight__check_value(opt->scale[c]);
    if (r != EL_SUCCESS) return r;
  }
  if (opt->scale[0] == 0.0f && opt->scale[1] == 0.0f && opt->scale[2] == 0.0f) scale[0] = scale[1] = scale[2] = 1.0f;
  else for (c = 0; c < 3; ++c) scale[c] = opt->scale[c];
  r = el_envlight__set_matrix(l, opt->light_to_world);
  if (r != EL_SUCCESS) return r;
  l->compensated = opt->compensated != 0;
  l->importance = opt->importance;
  l->sampler = opt->sampler;
  return EL_SUCCESS;
}

/* The solid angle weights of the image rows: W[y] = 2 pi^2 * integral over v of the row's (clamped) tent
 * times sin(pi v), so that the integral of the bilinear le over the sphere is sum_y W[y] * mean(row y).
 * Closed form: int sin(pi v) = -cos(pi v)/pi, int v sin(pi v) = sin(pi v)/pi^2 - v cos(pi v)/pi. */
static double el_envlight__lin_sin(double a, double b, double p, double q) {
  /* integral over [p, q] of (a + b v) sin(pi v) dv */
  const double PI = EL_ENVLIGHT__PI;
  double i0 = (cos(PI * p) - cos(PI * q)) / PI;
  double i1 = (sin(PI * q) - sin(PI * p)) / (PI * PI) - (q * cos(PI * q) - p * cos(PI * p)) / PI;
  return a * i0 + b * i1;
}
static double el_envlight__row_weight(int y, int h) {
  double c = (y + 0.5) / h, d = 1.0 / h, s = 0.0;
  double lo = c - d, hi = c + d;
  /* rising part [c - d, c]: weight (v - (c - d)) / d; falling [c, c + d]: ((c + d) - v) / d.
   * Clamp: row 0 has weight 1 on [0, c], row h-1 weight 1 on [c, 1]. */
  if (y == 0) s += el_envlight__lin_sin(1.0, 0.0, 0.0, c);
  else s += el_envlight__lin_sin(-lo / d, 1.0 / d, lo, c);
  if (y == h - 1) s += el_envlight__lin_sin(1.0, 0.0, c, 1.0);
  else s += el_envlight__lin_sin(hi / d, -1.0 / d, c, hi);
  return 2.0 * EL_ENVLIGHT__PI * EL_ENVLIGHT__PI * s;
}

/* The parameters the bin finders use: the "diamond angle" p in [0, 4) for phi and t in [0, 2] for
 * theta. p = 2 - sign(y) (1 + x / (|x| + |y|)) (here sign(+0) = +; pdf_li counts y = -0 as negative,
 * the seam's other side); t = 1 - z / (r + |z|) with r = sqrt(x^2
 * + y^2). Within each quadrant (each hemisphere for t) they are tan(a) / (1 + tan(a)) of the angle a from
 * the quadrant's start, whose derivative 1 / (cos a + sin a)^2 lies in [1/2, 1] per radian, so a table of
 * cells of width 1 / (2 bins) per unit (edges are at least pi / bins radians apart) holds at most one edge
 * per cell. No atan, no branch. */
static double el_envlight__diamond(double y, double x) {
  double s = fabs(x) + fabs(y), q = 1.0 + (s > 0.0 ? x / s : 0.0);
  return y >= 0.0 ? 2.0 - q : 2.0 + q;
}
static el_result el_envlight__finder(int n, int quarters, int **base, float **edge, int *cells) {
  /* quarters = 4: phi edges 2 pi b / n over p in [0, 4); quarters = 2: theta edges pi b / n over
   * t in [0, 2] */
  int k = 2 * n * quarters + 2, c, b;
  *cells = k;
  *base = (int *)EL_MALLOC((size_t)k * sizeof(int));
  *edge = (float *)EL_MALLOC((size_t)k * sizeof(float));
  if (!*base || !*edge) return EL_ERROR_OUT_OF_MEMORY;
  for (c = 0; c < k; ++c) { (*base)[c] = -1; (*edge)[c] = 5.0f; }
  for (b = 1; b < n; ++b) {
    double a, pb;
    int cell;
    if (quarters == 4) {
      a = 2.0 * EL_ENVLIGHT__PI * b / n;
      pb = el_envlight__diamond(sin(a), cos(a));
    } else {
      a = EL_ENVLIGHT__PI * b / n;
      pb = 2 * b == n ? 1.0 : 1.0 - cos(a) / (sin(a) + fabs(cos(a)));
    }
    cell = (int)(pb * (k - 2) / quarters);
    if (cell > k - 1) cell = k - 1;
    EL_ASSERT(cell >= 0 && (*edge)[cell] == 5.0f); /* one edge per cell */
    (*edge)[cell] = (float)pb;
    (*base)[cell] = b - 1; /* edges below this one */
  }
  /* base[c] = number of edges in cells before c */
  {
    int count = 0;
    for (c = 0; c < k; ++c) {
      int here = (*base)[c] >= 0;
      (*base)[c] = count;
      count += here;
    }
  }
  return EL_SUCCESS;
}

/* Floats in the direction tables' allocation: 12 constant vectors, 16 per row, 8 per column, alignment slack. */
static size_t el_envlight__dir_floats(int nu, int nv) { return 48 + (size_t)nv * 16 + (size_t)nu * 8 + 4; }

static void el_envlight__free_tables(el_envlight *l) {
  el_distribution2d_fast_free(&l->fast);
  el_distribution2d_free(&l->dist);
  EL_FREE(l->u_base); EL_FREE(l->u_edge); EL_FREE(l->v_base); EL_FREE(l->v_edge); EL_FREE(l->pdf_table);
  EL_FREE(l->dir_alloc);
  EL_FREE((void *)l->gv_ptr);
  l->gv_ptr = NULL;
  l->u_base = l->v_base = NULL; l->u_edge = l->v_edge = NULL; l->pdf_table = NULL;
  l->row_tab = l->col_tab = l->dir_consts = NULL; l->dir_alloc = NULL; l->dir_tables = l->table_done = 0;
}

/* >> construction helpers: SSE2 where available (x86-64 always has it; EL_NO_SIMD gives the scalar
 * code, which does the same operations in the same order, so both give the same bits).
 * Construction at 2048x1024 (bench/bench_envlight.c, every build in fresh memory from the system, so its
 * page faults count as in pbrt's constructor; gcc 12 -O3, no -march): init 10.4-12.4 ms, about 6 of it
 * faulting in the 24 MB of texels; the sampling tables 12.9-18.6 ms, about 5 of it faulting in their
 * 18 MB; together 23-31 ms over many runs (pbrt-v3: 313 ms) and 117 M instructions (callgrind; 184 M
 * before the SSE2 loops). */

/* src * k, with its bits' validity mark (see el_envlight__row3) or-ed into *top */
static inline float el_envlight__scale1(float src, float k, uint32_t *top) {
  float v = src * k;
  uint32_t b;
  memcpy(&b, &v, sizeof b);
  *top |= b | (b + 0x00800000u);
  return v;
}
/* <<Copy, validate and scale the texels>> of one RGB row (channels == 3) and sum them per channel: the
 * fast path of el_envlight_init, one pass over the row. Blocks of 4 texels are 12 floats in which lane k
 * holds channel k % 3: k12 is the scale in that pattern. A product's bits b give b | (b + 2^23) with the
 * top bit set exactly when b >= 0x7f800000 (NaN, infinite) or b has the sign bit (negative, or -0 from a
 * negative texel times a zero scale): then the row returns 0 and the caller redoes it texel by texel
 * (which names the bad texel or zeroes it). Sums: one double per lane of the 12 (independent chains),
 * then per channel ((l_c + l_c+3) + (l_c+6 + l_c+9)) + the leftover texels. */
static int el_envlight__row3(const float *src, float *dst, int w, const float *k12, double sum[3]) {
  double acc[12], t[3] = {0.0, 0.0, 0.0};
  uint32_t top = 0;
  int x = 0, k;
#if EL_ENVLIGHT__SSE
  {
    const __m128 k0 = _mm_loadu_ps(k12), k1 = _mm_loadu_ps(k12 + 4), k2 = _mm_loadu_ps(k12 + 8);
    const __m128i h = _mm_set1_epi32(0x00800000);
    __m128i bad = _mm_setzero_si128();
    __m128d a0 = _mm_setzero_pd(), a1 = a0, a2 = a0, a3 = a0, a4 = a0, a5 = a0;
    for (; x + 4 <= w; x += 4, src += 12, dst += 12) {
      __m128 p0 = _mm_mul_ps(_mm_loadu_ps(src), k0), p1 = _mm_mul_ps(_mm_loadu_ps(src + 4), k1);
      __m128 p2 = _mm_mul_ps(_mm_loadu_ps(src + 8), k2);
      __m128i b0 = _mm_castps_si128(p0), b1 = _mm_castps_si128(p1), b2 = _mm_castps_si128(p2);
      bad = _mm_or_si128(bad, _mm_or_si128(_mm_or_si128(_mm_or_si128(b0, _mm_add_epi32(b0, h)), _mm_or_si128(b1, _mm_add_epi32(b1, h))),
                                           _mm_or_si128(b2, _mm_add_epi32(b2, h))));
      _mm_storeu_ps(dst, p0); _mm_storeu_ps(dst + 4, p1); _mm_storeu_ps(dst + 8, p2);
      a0 = _mm_add_pd(a0, _mm_cvtps_pd(p0)); a1 = _mm_add_pd(a1, _mm_cvtps_pd(_mm_movehl_ps(p0, p0)));
      a2 = _mm_add_pd(a2, _mm_cvtps_pd(p1)); a3 = _mm_add_pd(a3, _mm_cvtps_pd(_mm_movehl_ps(p1, p1)));
      a4 = _mm_add_pd(a4, _mm_cvtps_pd(p2)); a5 = _mm_add_pd(a5, _mm_cvtps_pd(_mm_movehl_ps(p2, p2)));
    }
    _mm_storeu_pd(acc, a0); _mm_storeu_pd(acc + 2, a1); _mm_storeu_pd(acc + 4, a2);
    _mm_storeu_pd(acc + 6, a3); _mm_storeu_pd(acc + 8, a4); _mm_storeu_pd(acc + 10, a5);
    top = _mm_movemask_ps(_mm_castsi128_ps(bad)) ? 0x80000000u : 0u;
  }
#else
  for (k = 0; k < 12; ++k) acc[k] = 0.0;
  for (; x + 4 <= w; x += 4, src += 12, dst += 12)
    for (k = 0; k < 12; ++k) acc[k] += dst[k] = el_envlight__scale1(src[k], k12[k], &top);
#endif
  for (; x < w; ++x, src += 3, dst += 3)
    for (k = 0; k < 3; ++k) t[k] += dst[k] = el_envlight__scale1(src[k], k12[k], &top);
  for (k = 0; k < 3; ++k) sum[k] = ((acc[k] + acc[k + 3]) + (acc[k + 6] + acc[k + 9])) + t[k];
  return !(top & 0x80000000u);
}

/* el_envlight__row3 without the copy (options.no_copy, scale 1): validates one RGB row of the caller's
 * pixels and sums it per channel, reading it once and writing nothing. The same validity test and the
 * same sums, in the same order, as el_envlight__row3 with a scale of 1. */
static int el_envlight__row3_check(const float *src, int w, double sum[3]) {
  double acc[12], t[3] = {0.0, 0.0, 0.0};
  uint32_t top = 0;
  int x = 0, k;
#if EL_ENVLIGHT__SSE
  {
    const __m128i h = _mm_set1_epi32(0x00800000);
    __m128i bad = _mm_setzero_si128();
    __m128d a0 = _mm_setzero_pd(), a1 = a0, a2 = a0, a3 = a0, a4 = a0, a5 = a0;
    for (; x + 4 <= w; x += 4, src += 12) {
      __m128 p0 = _mm_loadu_ps(src), p1 = _mm_loadu_ps(src + 4), p2 = _mm_loadu_ps(src + 8);
      __m128i b0 = _mm_castps_si128(p0), b1 = _mm_castps_si128(p1), b2 = _mm_castps_si128(p2);
      bad = _mm_or_si128(bad, _mm_or_si128(_mm_or_si128(_mm_or_si128(b0, _mm_add_epi32(b0, h)), _mm_or_si128(b1, _mm_add_epi32(b1, h))),
                                           _mm_or_si128(b2, _mm_add_epi32(b2, h))));
      a0 = _mm_add_pd(a0, _mm_cvtps_pd(p0)); a1 = _mm_add_pd(a1, _mm_cvtps_pd(_mm_movehl_ps(p0, p0)));
      a2 = _mm_add_pd(a2, _mm_cvtps_pd(p1)); a3 = _mm_add_pd(a3, _mm_cvtps_pd(_mm_movehl_ps(p1, p1)));
      a4 = _mm_add_pd(a4, _mm_cvtps_pd(p2)); a5 = _mm_add_pd(a5, _mm_cvtps_pd(_mm_movehl_ps(p2, p2)));
    }
    _mm_storeu_pd(acc, a0); _mm_storeu_pd(acc + 2, a1); _mm_storeu_pd(acc + 4, a2);
    _mm_storeu_pd(acc + 6, a3); _mm_storeu_pd(acc + 8, a4); _mm_storeu_pd(acc + 10, a5);
    top = _mm_movemask_ps(_mm_castsi128_ps(bad)) ? 0x80000000u : 0u;
  }
#else
  for (k = 0; k < 12; ++k) acc[k] = 0.0;
  for (; x + 4 <= w; x += 4, src += 12)
    for (k = 0; k < 12; ++k) acc[k] += el_envlight__scale1(src[k], 1.0f, &top);
#endif
  for (; x < w; ++x, src += 3)
    for (k = 0; k < 3; ++k) t[k] += el_envlight__scale1(src[k], 1.0f, &top);
  for (k = 0; k < 3; ++k) sum[k] = ((acc[k] + acc[k + 3]) + (acc[k + 6] + acc[k + 9])) + t[k];
  return !(top & 0x80000000u);
}

/* The weight of row y's mean in the integral of le over the sphere: the bilinear lat-long rows' exact
 * solid angle, or 4 pi / N^2 per texel of an equal-area map (each texel covers that solid angle exactly,
 * and le is its nearest lookup). */
static double el_envlight__row_wgt(const el_envlight *l, int y, int w, int h) {
  if (l->mapping == EL_ENVLIGHT_MAPPING_EQUAL_AREA) return 4.0 * EL_ENVLIGHT__PI / ((double)w * (double)h);
  return el_envlight__row_weight(y, h) / w;
}

/* >> construction */

/* A failed init: *l zeroed but for bad_index. */
static el_result el_envlight__fail(el_envlight *l, el_result r, int bad_index) {
  el_envlight_free(l);
  l->bad_index = bad_index;
  return r;
}

EL_DEF el_result el_envlight_init(el_envlight *l, const float *pixels, int width, int height, int channels,
                                  const el_envlight_options *opt) {
  el_envlight_options zero;
  float scale[3], k12[12];
  size_t n, i;
  el_result r;
  int y, x, c;
  if (!l) return EL_ERROR_INVALID_ARGUMENT;
  memset(l, 0, sizeof *l);
  l->bad_index = -1;
  l->most_negative_index = -1;
  if (!opt) { memset(&zero, 0, sizeof zero); opt = &zero; }
  if (!pixels || channels < 1 || channels > 4) return EL_ERROR_INVALID_ARGUMENT;
  if (width <= 0 || height <= 0) return width == 0 || height == 0 ? EL_ERROR_EMPTY : EL_ERROR_INVALID_ARGUMENT;
  if ((size_t)width > (size_t)2147483647 / (size_t)height) return EL_ERROR_SIZE_OVERFLOW;
  n = (size_t)width * (size_t)height;
  if (n > ((size_t)-1) / (3 * sizeof(float))) return EL_ERROR_SIZE_OVERFLOW;
  r = el_envlight__common(l, opt, scale);
  if (r != EL_SUCCESS) return el_envlight__fail(l, r, -1);
  l->mapping = opt->mapping;
  if (l->mapping == EL_ENVLIGHT_MAPPING_EQUAL_AREA &&
      (width != height || opt->importance == EL_ENVLIGHT_IMPORTANCE_PBRT_V3 || opt->importance == EL_ENVLIGHT_IMPORTANCE_BILINEAR))
    return el_envlight__fail(l, EL_ERROR_INVALID_ARGUMENT, -1); /* a square image; box cell averages only */
  if (opt->importance == EL_ENVLIGHT_IMPORTANCE_TEXEL) {
    l->imp_w = width; l->imp_h = height;
    if (l->imp_w > EL_ENVLIGHT_MAX_IMPORTANCE || l->imp_h > EL_ENVLIGHT_MAX_IMPORTANCE) return el_envlight__fail(l, EL_ERROR_SIZE_OVERFLOW, -1);
  } else if (opt->importance_width > 0) {
    l->imp_w = opt->importance_width; l->imp_h = opt->importance_height;
  } else {
    int k = opt->importance == EL_ENVLIGHT_IMPORTANCE_PBRT_V3 ? 2 : 1;
    l->imp_w = width <= EL_ENVLIGHT_MAX_IMPORTANCE / k ? k * width : EL_ENVLIGHT_MAX_IMPORTANCE;
    l->imp_h = height <= EL_ENVLIGHT_MAX_IMPORTANCE / k ? k * height : EL_ENVLIGHT_MAX_IMPORTANCE;
    if (opt->importance_cap >= 0) { /* the default cap (NOTES: BIG MAPS) */
      int cw = opt->importance_cap > 0 ? opt->importance_cap : EL_ENVLIGHT_IMPORTANCE_CAP, ch = cw / 2;
      if (ch < 1) ch = 1;
      if (l->mapping == EL_ENVLIGHT_MAPPING_EQUAL_AREA) cw = ch;
      if (l->imp_w > cw || l->imp_h > ch) {
        l->imp_w = l->imp_w < cw ? l->imp_w : cw;
        l->imp_h = l->imp_h < ch ? l->imp_h : ch;
        /* point lookups at fewer bins than pbrt-v3's 2x could miss a small sun (pdf 0 where le > 0):
         * a capped map takes the exact cell averages */
        l->importance = EL_ENVLIGHT_IMPORTANCE_CELL_AVERAGE;
      }
    }
  }
  if (opt->no_copy) { /* <<keep the caller's texels>>: validate and integrate them in one read */
    int copy = 0;
    if (channels != 3 || scale[0] != 1.0f || scale[1] != 1.0f || scale[2] != 1.0f) return el_envlight__fail(l, EL_ERROR_INVALID_ARGUMENT, -1);
    for (y = 0; y < height && !copy; ++y) {
      double row[3], wgt = el_envlight__row_wgt(l, y, width, height);
      const float *src = pixels + (size_t)y * (size_t)width * 3;
      if (!el_envlight__row3_check(src, width, row)) { /* texel by texel, as the copy's careful path: a -0 passes */
        row[0] = row[1] = row[2] = 0.0;
        for (x = 0; x < width && !copy; ++x)
          for (c = 0; c < 3; ++c) {
            r = el_envlight__check_value(src[3 * x + c]);
            if (r != EL_SUCCESS) { /* name it without a copy, or zero it in a copy */
              if (opt->bad_texels != EL_ENVLIGHT_BAD_TEXELS_ZERO &&
                  !(r == EL_ERROR_NEGATIVE && opt->bad_texels == EL_ENVLIGHT_BAD_TEXELS_CLAMP_NEGATIVE))
                return el_envlight__fail(l, r, y * width + x);
              copy = 1;
              break;
            }
            row[c] += src[3 * x + c];
          }
      }
      for (c = 0; c < 3; ++c) l->integral[c] += row[c] * wgt;
    }
    if (!copy) {
      memcpy(&l->texels, &pixels, sizeof l->texels); /* the caller's: never written (l->borrowed) */
      l->borrowed = 1;
      l->width = width; l->height = height;
      return EL_SUCCESS;
    }
    l->integral[0] = l->integral[1] = l->integral[2] = 0.0; /* a texel to zero: copy after all */
  }
  l->texels = (float *)EL_MALLOC(n * 3 * sizeof(float));
  if (!l->texels) return el_envlight__fail(l, EL_ERROR_OUT_OF_MEMORY, -1);
  l->width = width; l->height = height;
  /* <<Copy, validate and scale the texels>> and integrate them over the sphere (power): RGB rows in one
   * vectorised pass each (el_envlight__row3); other channel counts, and a row holding a bad texel, texel
   * by texel */
  for (c = 0; c < 12; ++c) k12[c] = scale[c % 3];
  for (y = 0; y < height; ++y) {
    double row[3] = {0.0, 0.0, 0.0}, wgt = el_envlight__row_wgt(l, y, width, height);
    if (channels == 3 && el_envlight__row3(pixels + (size_t)y * (size_t)width * 3, l->texels + (size_t)y * (size_t)width * 3, width, k12, row)) {
      for (c = 0; c < 3; ++c) l->integral[c] += row[c] * wgt;
      continue;
    }
    row[0] = row[1] = row[2] = 0.0;
    for (x = 0; x < width; ++x) {
      float in[3], out[3];
      uint32_t bits[3];
      const float *p;
      int neg = 0, nonfinite = 0;
      i = (size_t)y * (size_t)width + (size_t)x;
      p = pixels + (size_t)channels * i;
      in[0] = p[0];
      in[1] = channels >= 3 ? p[1] : p[0];
      in[2] = channels >= 3 ? p[2] : p[0];
      /* fast path: a float is finite and >= +0 when its bits, unsigned, are below 0x7f800000; the OR of
       * three such patterns is below it only if each is (rarely it is not although each is: the careful
       * path then accepts them). Only the scaled products are tested: the scale is finite and >= 0, so a
       * NaN, infinite or negative texel gives a NaN, infinite or sign-bit product (-x * 0 = -0), which
       * the careful path then judges from the texel itself. */
      out[0] = in[0] * scale[0]; out[1] = in[1] * scale[1]; out[2] = in[2] * scale[2];
      memcpy(bits, out, sizeof bits);
      if ((bits[0] | bits[1] | bits[2]) < 0x7f800000u) {
        float *t = l->texels + 3 * i;
        t[0] = out[0]; t[1] = out[1]; t[2] = out[2];
        row[0] += out[0]; row[1] += out[1]; row[2] += out[2];
        continue;
      }
      for (c = 0; c < 3; ++c) { /* the careful path: say which texel is bad, or zero it */
        float v = in[c];
        r = el_envlight__check_value(v);
        if (r != EL_SUCCESS) {
          if (opt->bad_texels == EL_ENVLIGHT_BAD_TEXELS_ZERO ||
              (r == EL_ERROR_NEGATIVE && opt->bad_texels == EL_ENVLIGHT_BAD_TEXELS_CLAMP_NEGATIVE)) {
            if (r == EL_ERROR_NEGATIVE) {
              neg = 1;
              if (v < l->most_negative) { l->most_negative = v; l->most_negative_index = (int)i; }
            } else nonfinite = 1;
            v = 0.0f;
          } else return el_envlight__fail(l, r, (int)i);
        }
        v *= scale[c];
        if (v > FLT_MAX) { /* scale * texel overflowed */
          if (opt->bad_texels == EL_ENVLIGHT_BAD_TEXELS_ZERO) { v = 0.0f; nonfinite = 1; }
          else return el_envlight__fail(l, EL_ERROR_INFINITE, (int)i);
        }
        l->texels[3 * i + (size_t)c] = v;
        row[c] += v;
      }
      l->negative_texels += (size_t)neg;
      l->nonfinite_texels += (size_t)nonfinite;
    }
    for (c = 0; c < 3; ++c) l->integral[c] += row[c] * wgt;
  }
  return EL_SUCCESS;
}

EL_DEF el_result el_envlight_init_constant(el_envlight *l, const float rgb[3], const el_envlight_options *opt) {
  el_envlight_options zero;
  float scale[3];
  el_result r;
  int c;
  if (!l) return EL_ERROR_INVALID_ARGUMENT;
  memset(l, 0, sizeof *l);
  l->bad_index = -1;
  l->most_negative_index = -1;
  if (!opt) { memset(&zero, 0, sizeof zero); opt = &zero; }
  if (!rgb) return EL_ERROR_INVALID_ARGUMENT;
  r = el_envlight__common(l, opt, scale);
  if (r != EL_SUCCESS) return el_envlight__fail(l, r, -1);
  for (c = 0; c < 3; ++c) {
    float v;
    r = el_envlight__check_value(rgb[c]);
    if (r != EL_SUCCESS) {
      if (opt->bad_texels != EL_ENVLIGHT_BAD_TEXELS_ZERO &&
          !(r == EL_ERROR_NEGATIVE && opt->bad_texels == EL_ENVLIGHT_BAD_TEXELS_CLAMP_NEGATIVE))
        return el_envlight__fail(l, r, 0);
      if (r == EL_ERROR_NEGATIVE) {
        l->negative_texels = 1;
        if (rgb[c] < l->most_negative) { l->most_negative = rgb[c]; l->most_negative_index = 0; }
      } else l->nonfinite_texels = 1;
      v = 0.0f;
    } else v = rgb[c] * scale[c];
    if (v > FLT_MAX) {
      if (opt->bad_texels != EL_ENVLIGHT_BAD_TEXELS_ZERO) return el_envlight__fail(l, EL_ERROR_INFINITE, 0);
      l->nonfinite_texels = 1;
      v = 0.0f;
    }
    l->constant[c] = v;
    l->integral[c] = 4.0 * EL_ENVLIGHT__PI * v;
  }
  return EL_SUCCESS;
}

EL_DEF void el_envlight_free(el_envlight *l) {
  if (!l) return;
  el_envlight__free_tables(l);
  el_envlight__warp_free(l->warp);
  el_envlight__warp_free(l->prod);
  if (!l->borrowed) EL_FREE(l->texels);
  memset(l, 0, sizeof *l);
}

EL_DEF el_result el_envlight_preprocess(el_envlight *l, const float center[3], float radius) {
  float m = 0.0f;
  int k;
  el_result r;
  if (!l || !center) return EL_ERROR_INVALID_ARGUMENT;
  for (k = 0; k < 3; ++k) {
    if (center[k] != center[k]) return EL_ERROR_NAN;
    if (!(fabsf(center[k]) <= FLT_MAX)) return EL_ERROR_INFINITE;
    if (fabsf(center[k]) > m) m = fabsf(center[k]);
  }
  r = el_envlight__check_value(radius); /* NaN, infinite, negative */
  if (r == EL_ERROR_NEGATIVE) r = EL_ERROR_INVALID_ARGUMENT;
  if (r != EL_SUCCESS) return r;
  /* <<Compute scene bounding sphere>> is the caller's; here: pdf_pos = 1 / (pi r^2) must be a finite
   * normal float, and the origins centre + r (disk point + direction) must resolve the disk. With
   * r <= 2^62 they cannot overflow: |centre| + 2r rounds to at most FLT_MAX. */
  if (!(radius >= EL_ENVLIGHT_MIN_RADIUS && radius <= EL_ENVLIGHT_MAX_RADIUS) || radius < m * 9.5367431640625e-7f)
    return EL_ERROR_INVALID_ARGUMENT;
  l->center[0] = center[0]; l->center[1] = center[1]; l->center[2] = center[2];
  l->radius = radius;
  return EL_SUCCESS;
}

/* >> the importance map */

/* One axis of the exact "mean of the linear reconstruction over each bin" weights. Texel k's tent is
 * centred at k + 0.5 (texel units) with half-width 1; wrap: indices modulo n, else clamped (so the
 * reconstruction is constant between the border and the first/last texel centre, as le()). Bin b covers
 * [b * n / nb, (b + 1) * n / nb]. Output: start[nb + 1], idx[], wt[] (weights of a bin sum to 1). */
static double el_envlight__tent_cdf(double x) { /* integral of max(0, 1 - |t|) from -inf to x */
  if (x <= -1.0) return 0.0;
  if (x <= 0.0) return 0.5 * (x + 1.0) * (x + 1.0);
  if (x <= 1.0) return 1.0 - 0.5 * (1.0 - x) * (1.0 - x);
  return 1.0;
}
static el_result el_envlight__axis_weights(int n, int nb, int wrap, int **start, int **idx, float **wt) {
  size_t cap = (size_t)nb * (size_t)((n + nb - 1) / nb + 4), m = 0;
  int b, k;
  *start = (int *)EL_MALLOC(((size_t)nb + 1) * sizeof(int));
  *idx = (int *)EL_MALLOC(cap * sizeof(int));
  *wt = (float *)EL_MALLOC(cap * sizeof(float));
  if (!*start || !*idx || !*wt) return EL_ERROR_OUT_OF_MEMORY;
  for (b = 0; b < nb; ++b) {
    double a = (double)b * n / nb, e = (double)(b + 1) * n / nb;
    int k0 = (int)floor(a - 1.5), k1 = (int)floor(e + 0.5);
    (*start)[b] = (int)m;
    for (k = k0; k <= k1; ++k) {
      double c = k + 0.5, wk = (el_envlight__tent_cdf(e - c) - el_envlight__tent_cdf(a - c)) / (e - a);
      int j = k;
      if (!(wk > 0.0)) continue;
      if (wrap) { j %= n; if (j < 0) j += n; }
      else { if (j < 0) j = 0; if (j > n - 1) j = n - 1; }
      EL_ASSERT(m < cap);
      (*idx)[m] = j; (*wt)[m] = (float)wk; ++m;
    }
  }
  (*start)[nb] = (int)m;
  return EL_SUCCESS;
}

/* f[j * nu + i] = mean luminance of the bilinear le over bin (i, j) (no sin yet). */
/* The same when the bins are the texels: the separable 1/8, 3/4, 1/8 stencil (wrap in u, clamp in v),
 * on three rolling rows of u-filtered luminance. */
static el_result el_envlight__cell_average_same(const el_envlight *l, float *f, int times_sin) {
  int w = l->width, h = l->height, y, x, k;
  float *rows = (float *)EL_MALLOC((size_t)4 * (size_t)w * sizeof(float)), *lum, *hr[3];
  if (!rows) return EL_ERROR_OUT_OF_MEMORY;
  lum = rows + 3 * (size_t)w;
  for (k = 0; k < 3; ++k) hr[k] = rows + (size_t)k * (size_t)w;
  for (y = -1; y <= h; ++y) {
    int src = y < 0 ? 0 : y > h - 1 ? h - 1 : y;
    const float *t = l->texels + (size_t)src * (size_t)w * 3;
    float *out = hr[(y + 1) % 3];
    x = 0;
#if EL_ENVLIGHT__SSE
    { /* 4 texels (12 floats) at a time: r0 g0 b0 r1 | g1 b1 r2 g2 | b2 r3 g3 b3, split into R, G, B by five
         shuffles; the same products and sums as the scalar loop */
      const __m128 wr = _mm_set1_ps(0.212671f), wg = _mm_set1_ps(0.715160f), wb = _mm_set1_ps(0.072169f);
      for (; x + 4 <= w; x += 4) {
        __m128 p0 = _mm_loadu_ps(t + 3 * x), p1 = _mm_loadu_ps(t + 3 * x + 4), p2 = _mm_loadu_ps(t + 3 * x + 8);
        __m128 yy = _mm_shuffle_ps(p1, p2, _MM_SHUFFLE(2, 1, 3, 2)); /* r2 g2 r3 g3 */
        __m128 zz = _mm_shuffle_ps(p0, p1, _MM_SHUFFLE(1, 0, 2, 1)); /* g0 b0 g1 b1 */
        __m128 rr = _mm_shuffle_ps(p0, yy, _MM_SHUFFLE(2, 0, 3, 0));
        __m128 gg = _mm_shuffle_ps(zz, yy, _MM_SHUFFLE(3, 1, 2, 0));
        __m128 bb = _mm_shuffle_ps(zz, p2, _MM_SHUFFLE(3, 0, 3, 1));
        _mm_storeu_ps(lum + x, _mm_add_ps(_mm_add_ps(_mm_mul_ps(wr, rr), _mm_mul_ps(wg, gg)), _mm_mul_ps(wb, bb)));
      }
    }
#endif
    for (; x < w; ++x) lum[x] = 0.212671f * t[3 * x] + 0.715160f * t[3 * x + 1] + 0.072169f * t[3 * x + 2];
    if (w == 1) out[0] = lum[0];
    else {
      out[0] = 0.75f * lum[0] + 0.125f * (lum[w - 1] + lum[1]);
      for (x = 1; x < w - 1; ++x) out[x] = 0.75f * lum[x] + 0.125f * (lum[x - 1] + lum[x + 1]);
      out[w - 1] = 0.75f * lum[w - 1] + 0.125f * (lum[w - 2] + lum[0]);
    }
    if (y >= 1) { /* rows y-2, y-1, y are ready: bin row y-1 */
      const float *a = hr[(y - 1) % 3], *m = hr[y % 3], *c = hr[(y + 1) % 3];
      float *dst = f + (size_t)(y - 1) * (size_t)w;
      if (times_sin) { /* the <<times sin(theta)>> pass of el_envlight__build fused in: the same products */
        float s = (float)sin(EL_ENVLIGHT__PI * ((y - 1) + 0.5) / h);
        for (x = 0; x < w; ++x) {
          float v0 = 0.75f * m[x] + 0.125f * (a[x] + c[x]), v = v0 * s;
          dst[x] = v < FLT_MAX ? v : FLT_MAX;
        }
      } else for (x = 0; x < w; ++x) dst[x] = 0.75f * m[x] + 0.125f * (a[x] + c[x]);
    }
  }
  EL_FREE(rows);
  return EL_SUCCESS;
}

/* One axis of the exact "mean of the nearest (box) reconstruction over each bin" weights (equal-area
 * maps): texel k covers [k, k + 1], bin b [b n / nb, (b + 1) n / nb]; the same output as axis_weights. */
static el_result el_envlight__box_weights(int n, int nb, int **start, int **idx, float **wt) {
  size_t cap = (size_t)nb * (size_t)((n + nb - 1) / nb + 2), m = 0;
  int b, k;
  *start = (int *)EL_MALLOC(((size_t)nb + 1) * sizeof(int));
  *idx = (int *)EL_MALLOC(cap * sizeof(int));
  *wt = (float *)EL_MALLOC(cap * sizeof(float));
  if (!*start || !*idx || !*wt) return EL_ERROR_OUT_OF_MEMORY;
  for (b = 0; b < nb; ++b) {
    double a = (double)b * n / nb, e = (double)(b + 1) * n / nb;
    (*start)[b] = (int)m;
    for (k = (int)floor(a); k < n && (double)k < e; ++k) {
      double lo = a > k ? a : (double)k, hi = e < k + 1.0 ? e : k + 1.0;
      if (!(hi > lo)) continue;
      EL_ASSERT(m < cap);
      (*idx)[m] = k; (*wt)[m] = (float)((hi - lo) / (e - a)); ++m;
    }
  }
  (*start)[nb] = (int)m;
  return EL_SUCCESS;
}

/* lum[x] = the luminance of texel x of a row of w RGB texels: the products and sums of
 * el_envlight__luminance, 4 texels at a time with SSE2 (the same bits) */
static void el_envlight__lum_row(const float *t, float *lum, int w) {
  int x = 0;
#if EL_ENVLIGHT__SSE
  const __m128 wr = _mm_set1_ps(0.212671f), wg = _mm_set1_ps(0.715160f), wb = _mm_set1_ps(0.072169f);
  for (; x + 4 <= w; x += 4) { /* r0 g0 b0 r1 | g1 b1 r2 g2 | b2 r3 g3 b3 -> R, G, B (as cell_average_same) */
    __m128 p0 = _mm_loadu_ps(t + 3 * x), p1 = _mm_loadu_ps(t + 3 * x + 4), p2 = _mm_loadu_ps(t + 3 * x + 8);
    __m128 yy = _mm_shuffle_ps(p1, p2, _MM_SHUFFLE(2, 1, 3, 2));
    __m128 zz = _mm_shuffle_ps(p0, p1, _MM_SHUFFLE(1, 0, 2, 1));
    __m128 rr = _mm_shuffle_ps(p0, yy, _MM_SHUFFLE(2, 0, 3, 0));
    __m128 gg = _mm_shuffle_ps(zz, yy, _MM_SHUFFLE(3, 1, 2, 0));
    __m128 bb = _mm_shuffle_ps(zz, p2, _MM_SHUFFLE(3, 0, 3, 1));
    _mm_storeu_ps(lum + x, _mm_add_ps(_mm_add_ps(_mm_mul_ps(wr, rr), _mm_mul_ps(wg, gg)), _mm_mul_ps(wb, bb)));
  }
#endif
  for (; x < w; ++x) lum[x] = el_envlight__luminance(t + 3 * x);
}

/* box: the equal-area map's nearest reconstruction (box weights) instead of le()'s bilinear one. */
static el_result el_envlight__cell_average(const el_envlight *l, float *f, int nu, int nv, int box) {
  int w = l->width, h = l->height;
  int *us = NULL, *ui = NULL, *vs = NULL, *vi = NULL, j, i, e, span = 1, cached_hi = -1;
  float *uw = NULL, *vw = NULL, *lum = NULL, *cache = NULL;
  el_result r = box ? el_envlight__box_weights(w, nu, &us, &ui, &uw) : el_envlight__axis_weights(w, nu, 1, &us, &ui, &uw);
  if (r == EL_SUCCESS) r = box ? el_envlight__box_weights(h, nv, &vs, &vi, &vw) : el_envlight__axis_weights(h, nv, 0, &vs, &vi, &vw);
  if (r != EL_SUCCESS) goto done;
  /* the widest range of rows one bin row needs: a ring of that many u-filtered rows */
  for (j = 0; j < nv; ++j) {
    int lo = vi[vs[j]], hi = vi[vs[j]];
    for (e = vs[j]; e < vs[j + 1]; ++e) { if (vi[e] < lo) lo = vi[e]; if (vi[e] > hi) hi = vi[e]; }
    if (hi - lo + 1 > span) span = hi - lo + 1;
  }
  lum = (float *)EL_MALLOC((size_t)w * sizeof(float));
  cache = (float *)EL_MALLOC((size_t)span * (size_t)nu * sizeof(float));
  if (!lum || !cache) { r = EL_ERROR_OUT_OF_MEMORY; goto done; }
  for (j = 0; j < nv; ++j) {
    float *out = f + (size_t)j * (size_t)nu;
    int hi = 0;
    for (e = vs[j]; e < vs[j + 1]; ++e) if (vi[e] > hi) hi = vi[e];
    /* <<u-filter the rows this bin row needs that are not cached yet>> */
    while (cached_hi < hi) {
      int y = ++cached_hi;
      const float *src = l->texels + (size_t)y * (size_t)w * 3;
      float *dst = cache + (size_t)(y % span) * (size_t)nu;
      el_envlight__lum_row(src, lum, w);
      for (i = 0; i < nu; ++i) {
        float s = 0.0f;
        int q;
        for (q = us[i]; q < us[i + 1]; ++q) s += uw[q] * lum[ui[q]];
        dst[i] = s;
      }
    }
    for (i = 0; i < nu; ++i) out[i] = 0.0f;
    for (e = vs[j]; e < vs[j + 1]; ++e) {
      const float *src = cache + (size_t)(vi[e] % span) * (size_t)nu;
      float wv = vw[e];
      for (i = 0; i < nu; ++i) out[i] += wv * src[i];
    }
  }
done:
  EL_FREE(us); EL_FREE(ui); EL_FREE(uw); EL_FREE(vs); EL_FREE(vi); EL_FREE(vw);
  EL_FREE(lum); EL_FREE(cache);
  return r;
}

static el_result el_envlight__build(el_envlight *l) {
  int nu = l->imp_w, nv = l->imp_h, i, j, any = 0, sin_done = 0;
  float pdf_k;
  size_t nb, q;
  float *f;
  el_result r = EL_SUCCESS;
  el_distribution_options dopt;
  if (l->width == 0) return EL_SUCCESS; /* constant light: uniform sampling, no tables */
  if (l->importance == EL_ENVLIGHT_IMPORTANCE_BILINEAR) return el_envlight__patch_build(l); /* le()'s patches */
  nb = (size_t)nu * (size_t)nv;
  /* pdf_li indexes the pdf table with 32-bit arithmetic: at most 2^32 - 1 bins (a 16 GB table) */
  if (nb > ((size_t)-1) / sizeof(float) || (uint64_t)nb > 0xffffffffu) return EL_ERROR_SIZE_OVERFLOW;
  f = (float *)EL_MALLOC(nb * sizeof(float));
  if (!f) return EL_ERROR_OUT_OF_MEMORY;
  /* <<Compute scalar-valued image img from environment map>> */
  if (l->mapping == EL_ENVLIGHT_MAPPING_EQUAL_AREA) { /* le is the nearest texel: box means, no sin */
    sin_done = 1;
    if (nu == l->width && nv == l->height) for (q = 0; q < nb; ++q) f[q] = el_envlight__luminance(l->texels + 3 * q);
    else r = el_envlight__cell_average(l, f, nu, nv, 1);
  } else if (l->importance == EL_ENVLIGHT_IMPORTANCE_CELL_AVERAGE) {
    if (nu == l->width && nv == l->height) { sin_done = !l->compensated; r = el_envlight__cell_average_same(l, f, sin_done); }
    else r = el_envlight__cell_average(l, f, nu, nv, 0);
  } else if (l->importance == EL_ENVLIGHT_IMPORTANCE_PBRT_V3) {
    for (j = 0; j < nv; ++j)
      for (i = 0; i < nu; ++i) {
        float rgb[3];
        el_envlight__bilerp(l, ((float)i + 0.5f) / (float)nu, ((float)j + 0.5f) / (float)nv, rgb);
        f[(size_t)j * (size_t)nu + (size_t)i] = el_envlight__luminance(rgb);
      }
  } else {
    for (q = 0; q < nb; ++q) f[q] = el_envlight__luminance(l->texels + 3 * q);
  }
  if (r != EL_SUCCESS) { EL_FREE(f); return r; }
  /* texels are finite and >= 0 and every weight is >= 0, so f is >= 0 and at worst +Inf (a sum of values
   * near FLT_MAX); the sin(theta) pass below clamps it to FLT_MAX */
  if (l->compensated) {
    /* <<Initialize compensated PDF>> (pbrt-v4): subtract the solid-angle mean of L, clamp at 0 */
    double sum = 0.0, area = 0.0, mean;
    for (j = 0; j < nv; ++j) { /* equal-area bins all have the same solid angle */
      double da = l->mapping == EL_ENVLIGHT_MAPPING_EQUAL_AREA ? 1.0 : cos(EL_ENVLIGHT__PI * j / nv) - cos(EL_ENVLIGHT__PI * (j + 1) / nv), rs = 0.0;
      for (i = 0; i < nu; ++i) rs += f[(size_t)j * (size_t)nu + (size_t)i];
      sum += rs * da; area += da * nu;
    }
    mean = sum / area;
    for (q = 0; q < nb; ++q) if ((double)f[q] > mean) { any = 1; break; }
    if (any) {
      for (q = 0; q < nb; ++q) f[q] = (double)f[q] > mean ? (float)((double)f[q] - mean) : 0.0f;
    } else l->fell_back = 1;
  }
  for (j = 0; j < nv && !sin_done; ++j) { /* <<times sin(theta)>> at the bin centre (> 0 for every bin) */
    float s = (float)sin(EL_ENVLIGHT__PI * (j + 0.5) / nv), *row = f + (size_t)j * (size_t)nu;
    for (i = 0; i < nu; ++i) {
      float v = row[i] * s;
      row[i] = v < FLT_MAX ? v : FLT_MAX;
    }
  }
  memset(&dopt, 0, sizeof dopt);
  r = el_distribution2d_init(&l->dist, f, nu, nv, &dopt);
  if (r != EL_SUCCESS) { EL_FREE(f); return r; }
  /* f is not needed any more: its memory (already paged in) becomes the per-bin pdf table below */
  l->pdf_table = f;
  if (l->mapping == EL_ENVLIGHT_MAPPING_EQUAL_AREA) { /* pdf = mapPdf / (4 pi): no finders, no direction tables */
    l->u_margin = EL_ENVLIGHT__MARGIN * (float)nu * 1.0001f;
    l->v_margin = EL_ENVLIGHT__MARGIN * (float)nv * 1.0001f;
    l->u_margin_hi = 1.0f - l->u_margin;
    l->v_margin_hi = 1.0f - l->v_margin;
    pdf_k = (float)((double)l->dist.v_pdf_scale * (double)l->dist.u_pdf_scale / (4.0 * EL_ENVLIGHT__PI));
    for (j = 0; j < nv; ++j) {
      const uint32_t *row = l->dist.cdf + (size_t)j * ((size_t)nu + 1);
      float wv = (float)(int32_t)(l->dist.marginal[j + 1] - l->dist.marginal[j]);
      for (i = 0; i < nu; ++i) f[(size_t)j * (size_t)nu + (size_t)i] = (wv * (float)(int32_t)(row[i + 1] - row[i])) * pdf_k;
    }
    if (l->sampler != EL_ENVLIGHT_SAMPLER_CDF) {
      el_distribution_fast_options fo;
      memset(&fo, 0, sizeof fo);
      fo.method = l->sampler == EL_ENVLIGHT_SAMPLER_ALIAS ? EL_DISTRIBUTION_FAST_ALIAS : EL_DISTRIBUTION_FAST_GUIDE;
      fo.guide_shrink_log2 = 2;
      r = el_distribution2d_fast_init_ex(&l->fast, &l->dist, &fo);
      if (r != EL_SUCCESS) { el_envlight__free_tables(l); return r; }
    }
    return EL_SUCCESS;
  }
  r = el_envlight__finder(nu, 4, &l->u_base, &l->u_edge, &l->u_cells);
  if (r == EL_SUCCESS) r = el_envlight__finder(nv, 2, &l->v_base, &l->v_edge, &l->v_cells);
  if (r != EL_SUCCESS) { el_envlight__free_tables(l); return r; }
  l->u_margin = EL_ENVLIGHT__MARGIN * (float)nu * 1.0001f;
  l->v_margin = EL_ENVLIGHT__MARGIN * (float)nv * 1.0001f;
  l->u_margin_hi = 1.0f - l->u_margin;
  l->v_margin_hi = 1.0f - l->v_margin;
  l->v_angle = (float)(EL_ENVLIGHT__PI / nv);
  l->u_angle = (float)(2.0 * EL_ENVLIGHT__PI / nu);
  if (nu >= 256 && nv >= 128) { /* bin angles <= pi/128 = 0.0245: there x - x^3/6 and 1 - x^2/2 are sin
                                   and cos to float precision (x^5/120 <= 7e-11, x^4/24 <= 1.5e-8) */
    float *dc;
    l->dir_alloc = EL_MALLOC(el_envlight__dir_floats(nu, nv) * sizeof(float));
    if (!l->dir_alloc) { el_envlight__free_tables(l); return EL_ERROR_OUT_OF_MEMORY; }
    dc = l->dir_consts = (float *)l->dir_alloc + ((16u - ((size_t)l->dir_alloc & 15u)) & 15u) / sizeof(float);
    l->col_tab = dc + 48; /* right after the constants: sample_li reaches both from one register */
    l->row_tab = l->col_tab + (size_t)nu * 8;
    for (j = 0; j < nv; ++j) {
      int north = 2 * j < nv, k = north ? j : j + 1; /* the edge nearer the pole */
      int kk = k < nv - k ? k : nv - k;              /* sin from the nearer pole: exactly 0 at both */
      float *t = l->row_tab + 16 * (size_t)j;
      memset(t, 0, 16 * sizeof(float));
      t[0] = (float)sin(EL_ENVLIGHT__PI * kk / nv);
      t[1] = 2 * k == nv ? 0.0f : (float)cos(EL_ENVLIGHT__PI * k / nv);
      t[4] = t[1]; t[5] = -t[0];
      t[8] = t[9] = north ? 0.0f : -1.0f;
    }
    for (i = 0; i < nu; ++i) {
      /* float products and sums as sample_li would form them for cp = c cb - s sb, sp = s cb + c sb and
       * then M (cp, sp, .): exact for a signed permutation M, so the result is the permuted light-space
       * direction bit for bit */
      double a = 2.0 * EL_ENVLIGHT__PI * i / nu;
      float c = 4 * i == nu || 4 * i == 3 * nu ? 0.0f : (float)cos(a), sn = 2 * i == nu ? 0.0f : (float)sin(a);
      float *t = l->col_tab + 8 * (size_t)i;
      int k;
      for (k = 0; k < 3; ++k) {
        float m0 = l->to_world[3 * k], m1 = l->to_world[3 * k + 1];
        t[k] = c * m0 + sn * m1;
        t[4 + k] = c * m1 - sn * m0;
      }
      t[3] = t[7] = 0.0f;
    }
    for (i = 0; i < 2; ++i) {
      dc[i] = l->v_margin; dc[2 + i] = l->u_margin;
      dc[4 + i] = l->v_margin_hi; dc[6 + i] = l->u_margin_hi;
      dc[8 + i] = l->v_angle; dc[10 + i] = l->u_angle;
    }
    dc[12] = l->to_world[2]; dc[13] = l->to_world[5]; dc[14] = l->to_world[8]; dc[15] = 0.0f;
    for (i = 40; i < 48; ++i) dc[i] = 0.0f; /* dc[40] = pdf_k, below */
    for (i = 0; i < 4; ++i) { dc[16 + i] = -0.166666667f; dc[20 + i] = 1.0f; dc[24 + i] = -0.5f; dc[28 + i] = 0.0f; }
    /* sample_li's SSE search: u to units and guide cells (filled in below), the clamp of u */
    for (i = 0; i < 4; ++i) { dc[32 + i] = 16777216.0f; dc[36 + i] = 0.99999994f; }
    l->dir_tables = 1;
    l->table_done = l->exact_transform && !l->dist.all_zero;
  }
  l->u_cell_scale = (float)(l->u_cells - 2) * 0.25f;
  l->v_cell_scale = (float)(l->v_cells - 2) * 0.5f;
  /* the pdf of bin (i, j) / (2 pi^2) is (wv wu) K, wv and wu its integer widths (exact as floats) and
   * K = v_pdf_scale u_pdf_scale / (2 pi^2) (0 when all-zero): the same expression as sample_li's, which
   * forms it from the CDF entries its search read, so the two agree bit for bit */
  pdf_k = l->dist.v_pdf_scale * l->dist.u_pdf_scale * EL_ENVLIGHT__INV_2PI2;
  if (l->dir_tables) l->dir_consts[40] = pdf_k; /* sample_li's copy */
  for (j = 0; j < nv; ++j) {
    const uint32_t *row = l->dist.cdf + (size_t)j * ((size_t)nu + 1);
    float wv = (float)(int32_t)(l->dist.marginal[j + 1] - l->dist.marginal[j]), k = pdf_k;
    float *dst = l->pdf_table + (size_t)j * (size_t)nu;
    /* a bin's width is at most 2^24 units: as int32_t it converts to the same float, and the loop vectorises */
    for (i = 0; i < nu; ++i) dst[i] = (wv * (float)(int32_t)(row[i + 1] - row[i])) * k;
  }
  if (l->sampler != EL_ENVLIGHT_SAMPLER_CDF) {
    el_distribution_fast_options fo;
    memset(&fo, 0, sizeof fo);
    fo.method = l->sampler == EL_ENVLIGHT_SAMPLER_ALIAS ? EL_DISTRIBUTION_FAST_ALIAS : EL_DISTRIBUTION_FAST_GUIDE;
    /* guide rows of a quarter as many cells as bins (1 byte per bin, distribution2d's default). Half as
     * many (2 bytes per bin) saves about 2 instructions per sample_li but measured 10% slower in
     * bench_render's loop and in sample_li with the radiance (twice the table: more cache misses) */
    fo.guide_shrink_log2 = 2;
    r = el_distribution2d_fast_init_ex(&l->fast, &l->dist, &fo);
    if (r != EL_SUCCESS) { el_envlight__free_tables(l); return r; }
    if (l->dir_tables && fo.method == EL_DISTRIBUTION_FAST_GUIDE) {
      l->dir_consts[34] = l->fast.gu_scale; l->dir_consts[35] = l->fast.gv_scale;
      l->gv_ptr = (const uint32_t **)EL_MALLOC(((size_t)l->fast.gv + 1) * sizeof *l->gv_ptr);
      if (!l->gv_ptr) { el_envlight__free_tables(l); return EL_ERROR_OUT_OF_MEMORY; }
      for (i = 0; i <= l->fast.gv; ++i) {
        uint32_t g = l->fast.guide_v[i];
        l->gv_ptr[i] = (const uint32_t *)(const void *)((const char *)(l->fast.marginal + (g & ~EL_DISTRIBUTION__GUIDE_CROWDED)) +
                                                         ((g & EL_DISTRIBUTION__GUIDE_CROWDED) ? 1 : 0));
      }
      l->row_key = (uintptr_t)l->row_tab - ((uintptr_t)l->fast.marginal << 4); /* mod 2^N */
      for (j = 0; j < nv; ++j) { /* floats 12-15 of the row record: two pointers (8-byte aligned) */
        const uint32_t **rq = (const uint32_t **)(void *)(l->row_tab + 16 * (size_t)j + 12);
        rq[0] = l->fast.cdf + (size_t)j * l->fast.row_stride;
        rq[1] = l->fast.guide_u + (size_t)j * l->fast.guide_stride;
      }
    }
  }
  return EL_SUCCESS;
}

/* Which inline fast paths are usable once the tables are built (stored after them, with release). */
static int el_envlight__hot_bits(const el_envlight *l, el_result r) {
  if (r != EL_SUCCESS || l->width == 0 || l->importance == EL_ENVLIGHT_IMPORTANCE_BILINEAR || l->mapping != EL_ENVLIGHT_MAPPING_LATLONG) return 0;
  /* sample_li's inline path: direction tables and the guide sampler; HOT_SAMPLE when the table direction
   * and pdf are final (table_done: a signed-permutation matrix, a map that is not all black), else
   * HOT_SAMPLE_FINISH (the pdf is then recomputed from wi) */
  int inl = l->dir_tables && l->sampler == EL_ENVLIGHT_SAMPLER_GUIDE;
  return EL_ENVLIGHT__HOT_PDF | (inl ? (l->table_done ? EL_ENVLIGHT__HOT_SAMPLE : EL_ENVLIGHT__HOT_SAMPLE_FINISH) : 0);
}

/* The once-scheme: state 0 -> 1 (one builder) -> 2 ready / 3 failed. Returns 1 when tables are usable. */
static int el_envlight__ensure_slow(el_envlight *l) {
#if EL_ENVLIGHT__ATOMICS
  int expected = 0;
  if (__atomic_compare_exchange_n(&l->state, &expected, 1, 0, __ATOMIC_ACQ_REL, __ATOMIC_ACQUIRE)) {
    el_result r = el_envlight__build(l);
    l->sampling_result = r;
    __atomic_store_n(&l->state, r == EL_SUCCESS ? 2 : 3, __ATOMIC_RELEASE);
    __atomic_store_n(&l->hot, el_envlight__hot_bits(l, r), __ATOMIC_RELEASE);
  } else {
    while (__atomic_load_n(&l->state, __ATOMIC_ACQUIRE) == 1) { /* another thread builds */ }
  }
  return __atomic_load_n(&l->state, __ATOMIC_ACQUIRE) == 2;
#else
  if (l->state == 0) {
    el_result r = el_envlight__build(l);
    l->sampling_result = r;
    l->state = r == EL_SUCCESS ? 2 : 3;
    l->hot = el_envlight__hot_bits(l, r);
  }
  return l->state == 2;
#endif
}
/* Queries take a const light and build its tables on first need: the lazy tables are the light's one
 * mutable part, guarded by the once-flag above (as el_mipmap's upper levels are). The light itself is
 * never a const object (el_envlight_init wrote it), so writing through the cast is defined. */
static inline int el_envlight__ensure(const el_envlight *l) {
#if EL_ENVLIGHT__ATOMICS
  if (__atomic_load_n(&l->state, __ATOMIC_ACQUIRE) == 2) return 1;
#else
  if (l->state == 2) return 1;
#endif
  return el_envlight__ensure_slow((el_envlight *)l);
}

/* The hot bits (el_envlight__hot_bits) as the queries read them. */
static inline int el_envlight__hot_now(const el_envlight *l) {
#if EL_ENVLIGHT__ATOMICS
  return __atomic_load_n(&l->hot, __ATOMIC_ACQUIRE);
#else
  return l->hot;
#endif
}

EL_DEF el_result el_envlight_prepare_sampling(el_envlight *l) {
  if (!l) return EL_ERROR_INVALID_ARGUMENT;
  el_envlight__ensure(l);
  return l->sampling_result;
}

/* >> queries */

EL_DEF void el_envlight_dir_to_uv(const float dir[3], float *u, float *v) {
  float d[3], r2, len2;
  d[0] = dir[0]; d[1] = dir[1]; d[2] = dir[2];
  r2 = d[0] * d[0] + d[1] * d[1];
  len2 = r2 + d[2] * d[2];
  if (!(len2 >= FLT_MIN && len2 <= FLT_MAX)) {
    if (!el_envlight__rescale(d)) { *u = 0.0f; *v = 0.0f; return; }
    r2 = d[0] * d[0] + d[1] * d[1];
  }
  *u = el_envlight__phi_turns(d[1], d[0]);
  *v = el_envlight__theta_halfturns(sqrtf(r2), d[2]);
}

EL_DEF void el_envlight_uv_to_dir(float u, float v, float d[3]) {
  u = el_envlight__clamp_u(u);
  if (!(v > 0.0f)) v = 0.0f;
  if (v > 1.0f) v = 1.0f;
  el_envlight__uv_to_dir(u, v, d);
}

static inline float el_envlight__sample_bin(const el_envlight *l, float u0, float u1, int *iu, int *iv, float *fu, float *fv);

/* >> equal-area maps (pbrt-v4's ImageInfiniteLight: EqualAreaSquareToSphere, EqualAreaSphereToSquare;
 * Clarberg 2008). Light space: the square's centre is +z, its corners -z, u grows with x, v with y. */

/* (u, v) in [0,1]^2 -> unit direction. r (the distance from the diagonal fold, pbrt's "1 - d") and
 * 1 - r^2 = |sd| (1 + r) are formed without cancellation, so sin(theta) and z stay accurate at both poles. */
static void el_envlight__square_to_dir(float u, float v, float d[3]) {
  float uu = 2.0f * u - 1.0f, vv = 2.0f * v - 1.0f, up = fabsf(uu), vp = fabsf(vv), s = up + vp;
  float sd = 1.0f - s, r = sd >= 0.0f ? s : 2.0f - s, t, st, z;
  t = r > 0.0f ? 0.25f * ((vp - up) / r + 1.0f) : 0.25f; /* phi / pi within the quadrant, [0, 1/2] */
  t = t > 0.0f ? (t < 0.5f ? t : 0.5f) : 0.0f;
  z = fabsf(sd) * (1.0f + r);
  st = r * el_envlight__sqrt(2.0f - r * r);
  d[0] = copysignf(el_envlight__cospi(t), uu) * st;
  d[1] = copysignf(el_envlight__sinpi(t), vv) * st;
  d[2] = sd >= 0.0f ? z : -z;
}

/* Direction (any length whose squared length is a normal float) -> (u, v) in [0,1]^2. 1 - |z| / len is
 * formed as r2 / (len (len + |z|)), so the radius does not lose its digits near the poles; the angle is
 * the light's atan polynomial (2.5e-7 rad), not pbrt-v4's 4e-6 one. */
static void el_envlight__dir_to_square(const float d[3], float *u, float *v) {
  float x = d[0], y = d[1], z = d[2], ax = fabsf(x), ay = fabsf(y), az = fabsf(z);
  float r2 = x * x + y * y, len = el_envlight__sqrt(r2 + z * z), r, mx = ax > ay ? ax : ay, mn = ax > ay ? ay : ax, phi, a, b;
  r = el_envlight__sqrt(r2 / (len * (len + az)));
  phi = el_envlight__atan01(mx > 0.0f ? mn / mx : 0.0f) * 0.636619772f; /* 2 / pi */
  if (ax < ay) phi = 1.0f - phi;
  b = phi * r;
  a = r - b;
  if (z < 0.0f) { float t = a; a = 1.0f - b; b = 1.0f - t; }
  a = copysignf(a, x);
  b = copysignf(b, y);
  a = 0.5f * (a + 1.0f); b = 0.5f * (b + 1.0f);
  *u = a > 0.0f ? (a < 1.0f ? a : 1.0f) : 0.0f;
  *v = b > 0.0f ? (b < 1.0f ? b : 1.0f) : 0.0f;
}

/* le of an equal-area map: the nearest texel (pbrt-v4's LookupNearest; u = 1 takes the last column). */
static void el_envlight__ea_le(const el_envlight *l, const float d[3], float rgb[3]) {
  float u, v;
  int x, y;
  const float *p;
  el_envlight__dir_to_square(d, &u, &v);
  x = (int)(u * (float)l->width); y = (int)(v * (float)l->height);
  x = x < l->width - 1 ? x : l->width - 1;
  y = y < l->height - 1 ? y : l->height - 1;
  p = l->texels + ((size_t)y * (size_t)l->width + (size_t)x) * 3;
  rgb[0] = p[0]; rgb[1] = p[1]; rgb[2] = p[2];
}

/* pdf_li of an equal-area map for a world direction (tables built): the bin's mapPdf / (4 pi). */
static float el_envlight__ea_pdf_li(const el_envlight *l, const float dir[3]) {
  float d[3], u, v, len2;
  int iu, iv;
  el_envlight__to_light(l, dir, d);
  len2 = (d[0] * d[0] + d[1] * d[1]) + d[2] * d[2];
  if (!(len2 >= FLT_MIN && len2 <= FLT_MAX) && !el_envlight__to_light_rescaled(l, dir, d)) return 0.0f;
  el_envlight__dir_to_square(d, &u, &v);
  iu = (int)(u * (float)l->dist.nu); iv = (int)(v * (float)l->dist.nv);
  iu = iu < l->dist.nu - 1 ? iu : l->dist.nu - 1;
  iv = iv < l->dist.nv - 1 ? iv : l->dist.nv - 1;
  return l->pdf_table[(size_t)iv * (size_t)l->dist.nu + (size_t)iu];
}

/* sample_li of an equal-area map (tables built): the bin and the point in it, kept 2^-21 inside its
 * edges, mapped to the sphere; pdf and radiance are pdf_li(wi) and le(wi) themselves, so they agree
 * bit for bit with what a caller computes from wi (the round trip's error, about 2e-7 in (u, v), stays
 * inside the margin: tests/test_envlight_bigmaps.c counts the samples whose pdf is not their bin's). */
static void el_envlight__ea_sample(const el_envlight *l, const float uu[2], float wi[3], float rgb[3], float *pdf) {
  float fu, fv, p, d[3];
  int iu, iv;
  p = el_envlight__sample_bin(l, uu[0], uu[1], &iu, &iv, &fu, &fv);
  if (!(p > 0.0f)) {
    wi[0] = l->to_world[2]; wi[1] = l->to_world[5]; wi[2] = l->to_world[8]; *pdf = 0.0f;
    if (rgb) rgb[0] = rgb[1] = rgb[2] = 0.0f;
    return;
  }
  el_envlight__square_to_dir(((float)iu + fu) * l->dist.u_width, ((float)iv + fv) * l->dist.v_width, d);
  el_envlight__to_world(l, d, wi);
  *pdf = p = el_envlight__ea_pdf_li(l, wi);
  if (rgb) {
    if (p > 0.0f) el_envlight_le(l, wi, rgb);
    else rgb[0] = rgb[1] = rgb[2] = 0.0f;
  }
}

EL_DEF void el_envlight_dir_to_square(const float dir[3], float *u, float *v) {
  float d[3], len2;
  d[0] = dir[0]; d[1] = dir[1]; d[2] = dir[2];
  len2 = (d[0] * d[0] + d[1] * d[1]) + d[2] * d[2];
  if (!(len2 >= FLT_MIN && len2 <= FLT_MAX) && !el_envlight__rescale(d)) { *u = 0.0f; *v = 0.0f; return; }
  el_envlight__dir_to_square(d, u, v);
}

EL_DEF void el_envlight_square_to_dir(float u, float v, float dir[3]) {
  u = u > 0.0f ? (u < 1.0f ? u : 1.0f) : 0.0f; /* NaN -> 0 */
  v = v > 0.0f ? (v < 1.0f ? v : 1.0f) : 0.0f;
  el_envlight__square_to_dir(u, v, dir);
}

static void el_envlight__ea_le(const el_envlight *l, const float d[3], float rgb[3]);
/* le for the light-space direction d, whose r2 = x^2 + y^2 is given. */
static inline void el_envlight__le_light(const el_envlight *l, const float d[3], float r2, float rgb[3]) {
  float u, v;
  if (l->width == 0) { rgb[0] = l->constant[0]; rgb[1] = l->constant[1]; rgb[2] = l->constant[2]; return; }
  if (l->mapping != EL_ENVLIGHT_MAPPING_LATLONG) { el_envlight__ea_le(l, d, rgb); return; }
  u = el_envlight__phi_turns(d[1], d[0]);
  v = el_envlight__theta_halfturns(sqrtf(r2), d[2]);
  el_envlight__bilerp(l, u, v, rgb);
}

/* le's rare case: a direction that needs el_envlight__to_light_rescaled (zero, NaN, infinite: 0). */
static EL_ENVLIGHT__NOINLINE void el_envlight__le_cold(const el_envlight *l, const float dir[3], float rgb[3]) {
  float d[3];
  if (!el_envlight__to_light_rescaled(l, dir, d)) { rgb[0] = rgb[1] = rgb[2] = 0.0f; return; }
  el_envlight__le_light(l, d, d[0] * d[0] + d[1] * d[1], rgb);
}

EL_DEF void el_envlight_le(const el_envlight *l, const float dir[3], float rgb[3]) {
  float d[3], r2, len2;
  el_envlight__to_light(l, dir, d);
  r2 = d[0] * d[0] + d[1] * d[1];
  len2 = r2 + d[2] * d[2];
  if (!(len2 >= FLT_MIN && len2 <= FLT_MAX)) { el_envlight__le_cold(l, dir, rgb); return; }
  el_envlight__le_light(l, d, r2, rgb);
}


/* pdf_core's first half: the pdf_table entry of (x, y, z), r = sqrt(x^2 + y^2) (pdf_li_n prefetches it) */
static inline size_t el_envlight__pdf_bin(const el_envlight *l, float x, float y, float z, float r) {
  float pu, t;
  uint32_t iu, iv;
  size_t c;
  /* <<Find the u bin>>: the diamond angle of (x, y), then its table cell. + FLT_MIN: x = y = 0 (a pole)
   * gives pu = 1; it changes x / s only where sin(theta) < 1e-30, far below the floor SIN_MIN. A y of -0
   * counts as negative: pu = 4 - 0, the seam's other side (a set of measure zero). */
  pu = 2.0f - copysignf(1.0f + x / (fabsf(x) + fabsf(y) + FLT_MIN), y);
  pu = pu < 3.99999976f ? pu : 3.99999976f;         /* y < 0 too small to resolve: the last bin */
  c = (size_t)(int64_t)(pu * l->u_cell_scale);
  EL_ASSERT(c < (size_t)l->u_cells);
  iu = (uint32_t)l->u_base[c] + (pu >= l->u_edge[c]);
  /* <<Find the v bin>>: t = 1 - z / (r + |z|) over both hemispheres */
  t = 1.0f - z / (r + fabsf(z));
  c = (size_t)(int64_t)(t * l->v_cell_scale);
  EL_ASSERT(c < (size_t)l->v_cells);
  iv = (uint32_t)l->v_base[c] + (t >= l->v_edge[c]);
  EL_ASSERT(iu < (uint32_t)l->dist.nu && iv < (uint32_t)l->dist.nv);
  return (size_t)(iv * (uint32_t)l->dist.nu + iu); /* nu * nv < 2^32 (checked at build) */
}
/* pdf_core's second half: the entry p (mapPdf / (2 pi^2)) over sin(theta) */
static inline float el_envlight__pdf_at(float p, float r, float len) {
  /* p / sin(theta), sin(theta) = r / len, floored at SIN_MIN */
  r = r > EL_ENVLIGHT__SIN_MIN * len ? r : EL_ENVLIGHT__SIN_MIN * len;
  p = p * len / r;
  EL_ASSERT(p >= 0.0f && p <= FLT_MAX);
  return p;
}
/* pdf_li for a light-space direction (x, y, z) with r2 = x^2 + y^2 and len2 = r2 + z^2 a normal float,
 * for a map: no calls, no branches. */
static inline float el_envlight__pdf_core(const el_envlight *l, float x, float y, float z, float r2, float len2) {
  float r = el_envlight__sqrt(r2), len = el_envlight__sqrt(len2);
  return el_envlight__pdf_at(l->pdf_table[el_envlight__pdf_bin(l, x, y, z, r)], r, len);
}

/* The rare cases: a direction whose squared length is not a normal float (rescaled; zero, NaN, Inf: 0),
 * the constant light. */
static EL_ENVLIGHT__NOINLINE float el_envlight__pdf_cold(const el_envlight *l, float x, float y, float z) {
  float d[3], r2, len2;
  d[0] = x; d[1] = y; d[2] = z;
  r2 = d[0] * d[0] + d[1] * d[1];
  len2 = r2 + d[2] * d[2];
  if (!(len2 >= FLT_MIN && len2 <= FLT_MAX)) {
    if (!el_envlight__rescale(d)) return 0.0f;
    r2 = d[0] * d[0] + d[1] * d[1];
    len2 = r2 + d[2] * d[2];
  }
  if (l->width == 0) return (l->constant[0] > 0.0f || l->constant[1] > 0.0f || l->constant[2] > 0.0f) ? 0.0795774715f : 0.0f;
  return el_envlight__pdf_core(l, d[0], d[1], d[2], r2, len2);
}

/* pdf_li for a light-space direction d (not necessarily unit). The hot path is a leaf. */
static inline float el_envlight__pdf_light(const el_envlight *l, const float dir[3]) {
  float x = dir[0], y = dir[1], z = dir[2];
  float r2 = x * x + y * y, len2 = r2 + z * z;
  if (!(len2 >= FLT_MIN && len2 <= FLT_MAX) || l->width == 0) return el_envlight__pdf_cold(l, x, y, z);
  return el_envlight__pdf_core(l, x, y, z, r2, len2);
}

/* pdf_li for a world direction that needs el_envlight__to_light_rescaled. */
static EL_ENVLIGHT__NOINLINE float el_envlight__pdf_world_cold(const el_envlight *l, const float dir[3]) {
  float d[3];
  if (!el_envlight__to_light_rescaled(l, dir, d)) return 0.0f;
  return el_envlight__pdf_light(l, d);
}

static EL_ENVLIGHT__NOINLINE float el_envlight__pdf_li_rest(const el_envlight *l, const float dir[3]) {
  float d[3], len2;
  if (l->mapping != EL_ENVLIGHT_MAPPING_LATLONG && l->width > 0) return el_envlight__ea_pdf_li(l, dir);
  el_envlight__to_light(l, dir, d);
  len2 = (d[0] * d[0] + d[1] * d[1]) + d[2] * d[2];
  if (!(len2 >= FLT_MIN && len2 <= FLT_MAX)) return el_envlight__pdf_world_cold(l, dir);
  return el_envlight__pdf_light(l, d);
}

/* pdf_li without the inline path: a small frame, so that importance BILINEAR's call is a tail call */
static EL_ENVLIGHT__NOINLINE float el_envlight__pdf_li_slow(const el_envlight *l, const float dir[3]) {
  if (!el_envlight__ensure(l)) return 0.0f;
  if (l->importance == EL_ENVLIGHT_IMPORTANCE_BILINEAR && l->width > 0) return el_envlight__patch_pdf_li(l, dir);
  return el_envlight__pdf_li_rest(l, dir);
}

EL_DEF float el_envlight_pdf_li(const el_envlight *l, const float dir[3]) {
  float d[3], r2, len2;
  /* the hot bit EL_ENVLIGHT__HOT_PDF: tables built, and a map (not the constant light) */
#if EL_ENVLIGHT__ATOMICS
  if (!(__atomic_load_n(&l->hot, __ATOMIC_ACQUIRE) & EL_ENVLIGHT__HOT_PDF)) return el_envlight__pdf_li_slow(l, dir);
#else
  if (!(l->hot & EL_ENVLIGHT__HOT_PDF)) return el_envlight__pdf_li_slow(l, dir);
#endif
  el_envlight__to_light(l, dir, d);
  r2 = d[0] * d[0] + d[1] * d[1];
  len2 = r2 + d[2] * d[2];
  if (!(len2 >= FLT_MIN && len2 <= FLT_MAX)) return el_envlight__pdf_world_cold(l, dir);
  return el_envlight__pdf_core(l, d[0], d[1], d[2], r2, len2);
}

/* The bin and the fractions within it for (u0, u1), from the light's sampler (no float point
 * placement); the fractions are kept EL_ENVLIGHT__MARGIN inside the bin: never on an edge, a pole or the
 * seam. Returns the bin's mapPdf / (2 pi^2). Every sampler goes through here, so samplers that pick the
 * same bin and fraction (guide and CDF) give the same direction bit for bit. */
static inline float el_envlight__sample_bin(const el_envlight *l, float u0, float u1, int *iu, int *iv, float *fu, float *fv) {
  float a, b, p;
  if (l->sampler == EL_ENVLIGHT_SAMPLER_CDF) el_distribution2d_sample_bins(&l->dist, u0, u1, iu, iv, &a, &b, &p);
  else el_distribution2d_fast_sample_bins(&l->fast, u0, u1, iu, iv, &a, &b, &p);
  (void)p;
  a = a > l->u_margin ? a : l->u_margin;
  *fu = a < l->u_margin_hi ? a : l->u_margin_hi;
  b = b > l->v_margin ? b : l->v_margin;
  *fv = b < l->v_margin_hi ? b : l->v_margin_hi;
  return l->pdf_table[(size_t)*iv * (size_t)l->dist.nu + (size_t)*iu]; /* mapPdf / (2 pi^2) */
}

/* Sample (u, v) and the light-space direction; returns the pdf w.r.t. solid angle (0: no sample). The
 * constant light and maps too small for the direction tables (sample_li handles those itself). */
static float el_envlight__sample_light(const el_envlight *l, float u0, float u1, float *pu, float *pv, float d[3]) {
  float fu, fv, p, st;
  int iu, iv;
  if (l->width == 0) { /* constant: uniform sphere, pdf 1 / 4 pi */
    float u = el_envlight__clamp_u(u0), v = el_envlight__clamp_u(u1);
    float z = 1.0f - 2.0f * v, r = sqrtf(4.0f * v * (1.0f - v)); /* 1 - z^2 without cancellation */
    float a = 2.0f * u;
    int n = (int)(a + 0.5f);
    float t = a - (float)n, sgn = (n & 1) ? -1.0f : 1.0f;
    d[0] = r * sgn * el_envlight__cospi(t);
    d[1] = r * sgn * el_envlight__sinpi(t);
    d[2] = z;
    *pu = u; *pv = v;
    return (l->constant[0] > 0.0f || l->constant[1] > 0.0f || l->constant[2] > 0.0f) ? 0.0795774715f : 0.0f;
  }
  /* <<Find (u, v) sample coordinates in infinite light texture>> */
  p = el_envlight__sample_bin(l, u0, u1, &iu, &iv, &fu, &fv);
  *pu = ((float)iu + fu) * l->dist.u_width;
  *pv = ((float)iv + fv) * l->dist.v_width;
  if (!(p > 0.0f)) { d[0] = 0.0f; d[1] = 0.0f; d[2] = 1.0f; return 0.0f; }
  /* <<Compute direction for infinite light sample>>. sin(theta) from the distance to the nearer pole
   * formed from the bin (1 - fv is exact): at least the margin, whatever the rounding of v = (iv + fv)
   * / nv when nv is not a power of two (from 1 - v it could come out below the floor SIN_MIN) */
  st = ((float)(l->dist.nv - 1 - iv) + (1.0f - fv)) * l->dist.v_width; /* the distance to the south pole */
  st = el_envlight__uvp_to_dir(*pu, *pv, *pv < st ? *pv : st, d);
  /* <<Compute PDF for sampled infinite light direction>>: mapPdf / (2 pi^2 sin(theta)) */
  EL_ASSERT(st >= EL_ENVLIGHT__SIN_MIN);
  return p / st;
}

/* The rare parts of the table path: a zero pdf (an all-black map), a general rotation (the pdf is
 * recomputed from wi), the radiance. */
static EL_ENVLIGHT__NOINLINE void el_envlight__sample_table(const el_envlight *l, int iu, int iv, float fu, float fv, float wi[3], float rgb[3], float *pdf);
static EL_ENVLIGHT__NOINLINE void el_envlight__sample_li_finish(const el_envlight *l, int iu, int iv, float fu, float fv, float wi[3], float rgb[3], float *pdf) {
  float p = *pdf;
  if (!(p > 0.0f)) { wi[0] = l->to_world[2]; wi[1] = l->to_world[5]; wi[2] = l->to_world[8]; *pdf = 0.0f; }
  else if (!l->exact_transform) {
    float back[3];
    el_envlight__mul_transpose(l->to_world, wi, back);
    *pdf = p = el_envlight__pdf_light(l, back); /* bit-identical to pdf_li(wi) */
    if (!(p > 0.0f) && (fu != 0.5f || fv != 0.5f)) {
      /* rounding in the round trip moved a point near a pole (where phi is ill-conditioned) into a bin
       * without mass: the bin's centre instead (issue 24) */
      el_envlight__sample_table(l, iu, iv, 0.5f, 0.5f, wi, rgb, pdf);
      return;
    }
    if (rgb) { /* le(wi) itself, from the direction the pdf was computed from (issue 24: near a pole the
                * sample's own (u, v) can be a texel away from wi's) */
      if (p > 0.0f) el_envlight__le_light(l, back, back[0] * back[0] + back[1] * back[1], rgb);
      else rgb[0] = rgb[1] = rgb[2] = 0.0f;
    }
    return;
  }
  if (rgb) {
    if (p > 0.0f) el_envlight__lookup(l, ((float)iu + fu) * l->dist.u_width, ((float)iv + fv) * l->dist.v_width, rgb);
    else rgb[0] = rgb[1] = rgb[2] = 0.0f;
  }
}

#if EL_ENVLIGHT__SSE
/* _mm_shuffle_ps(a, a, imm) as pshufd: one instruction whatever registers hold a (shufps overwrites its
 * source, so the compiler adds a copy when a is still needed) */
#define EL_ENVLIGHT__SPLAT(a, imm) _mm_castsi128_ps(_mm_shuffle_epi32(_mm_castps_si128(a), (imm)))
/* <<Compute direction for infinite light sample>> for bin (iv, iu) (rt, ct: its row and column entries of
 * the direction tables) and the fractions f = (fv, fv, fu, fu) within it: theta = theta_ref + a,
 * |a| <= pi/128, and phi = phi_i + b, 0 <= b <= 2 pi/256; there sin x = x - x^3/6 and cos x = 1 - x^2/2
 * are exact to float precision (the next terms are below 1.5e-8 relative). The column table holds
 * phi_i's cos and sin already multiplied into the matrix: wi = sin theta (cos b P_i + sin b Q_i) +
 * cos theta M2. Lanes (v, v, u, u) = (a, a, b, b); the fractions are first clamped EL_ENVLIGHT__MARGIN
 * inside the bin; fv - 1 is exact (no cancellation). Stores wi and *pdf = p / sin(theta) (p = 0 gives
 * 0); returns the clamped fractions. Inlined into sample_li's hot path and into
 * el_envlight__sample_table from this one source, so every sampler gives the same bits for the same bin
 * and fractions; a compiler that contracts into fused multiply-adds does so alike in both (test_envlight
 * passes built with -march=native -ffp-contract=fast, 5 FMAs in each copy). */
static inline __m128 el_envlight__dir_sse(const el_envlight *l, const float *rt, const float *ct, __m128 f, float p, float wi[3], float *pdf) {
  const float *dc = l->dir_consts;
  __m128 x, x2, sn, cs, t, w;
  f = _mm_min_ps(_mm_max_ps(f, _mm_load_ps(dc)), _mm_load_ps(dc + 4));
  x = _mm_mul_ps(_mm_add_ps(f, _mm_load_ps(rt + 8)), _mm_load_ps(dc + 8));        /* (a, a, b, b) */
  x2 = _mm_mul_ps(x, x);
  sn = _mm_add_ps(x, _mm_mul_ps(_mm_mul_ps(x, x2), _mm_load_ps(dc + 16)));
  cs = _mm_add_ps(_mm_load_ps(dc + 20), _mm_mul_ps(x2, _mm_load_ps(dc + 24)));
  /* cos b P_i + sin b Q_i, then (sin theta, cos theta) = ca (s, c) + sa (c, -s): both sin terms >= 0,
   * exact near both poles */
  w = _mm_add_ps(_mm_mul_ps(EL_ENVLIGHT__SPLAT(cs, 0xaa), _mm_load_ps(ct)), _mm_mul_ps(EL_ENVLIGHT__SPLAT(sn, 0xaa), _mm_load_ps(ct + 4)));
  t = _mm_add_ps(_mm_mul_ps(cs, _mm_load_ps(rt)), _mm_mul_ps(sn, _mm_load_ps(rt + 4)));
  w = _mm_add_ps(_mm_mul_ps(EL_ENVLIGHT__SPLAT(t, 0), w), _mm_mul_ps(EL_ENVLIGHT__SPLAT(t, 0x55), _mm_load_ps(dc + 12)));
  _mm_storel_pi((__m64 *)(void *)wi, w);
  _mm_store_ss(wi + 2, _mm_movehl_ps(w, w));
  /* <<Compute PDF for sampled infinite light direction>>: mapPdf / (2 pi^2 sin(theta)) */
  EL_ASSERT(_mm_cvtss_f32(t) >= EL_ENVLIGHT__SIN_MIN);
  *pdf = p / _mm_cvtss_f32(t);
  return f;
}
#endif

#if !EL_ENVLIGHT__SSE
/* <<Compute direction for infinite light sample>> without SSE: el_envlight__dir_sse's operations, lane
 * by lane (see there); *fu, *fv clamped as it clamps them. Returns sin(theta). */
static float el_envlight__dir_scalar(const el_envlight *l, int iu, int iv, float *pfu, float *pfv, float wi[3]) {
  const float *rt = l->row_tab + 16 * (size_t)iv, *ct = l->col_tab + 8 * (size_t)iu, *dc = l->dir_consts;
  float fu = *pfu, fv = *pfv, a, b, a2, b2, sa, ca, sb, cb, st, cth;
  fv = fv > dc[0] ? fv : dc[0];
  fv = fv < dc[4] ? fv : dc[4];
  fu = fu > dc[2] ? fu : dc[2];
  fu = fu < dc[6] ? fu : dc[6];
  a = (fv + rt[8]) * dc[8]; b = (fu + 0.0f) * dc[10];
  a2 = a * a; b2 = b * b;
  sa = a + a * a2 * dc[16]; ca = dc[20] + a2 * dc[24];
  sb = b + b * b2 * dc[16]; cb = dc[20] + b2 * dc[24];
  st = ca * rt[0] + sa * rt[4];
  cth = ca * rt[1] + sa * rt[5];
  wi[0] = st * (cb * ct[0] + sb * ct[4]) + cth * dc[12];
  wi[1] = st * (cb * ct[1] + sb * ct[5]) + cth * dc[13];
  wi[2] = st * (cb * ct[2] + sb * ct[6]) + cth * dc[14];
  *pfu = fu; *pfv = fv;
  return st;
}
#endif

/* sample_li from a bin and its fractions through the direction tables (every sampler but sample_li's
 * inline guide path comes here). A leaf (its only call is a tail call), so it saves no registers. */
static EL_ENVLIGHT__NOINLINE void el_envlight__sample_table(const el_envlight *l, int iu, int iv, float fu, float fv, float wi[3], float rgb[3], float *pdf) {
  /* mapPdf / (2 pi^2): the bin's pdf_table entry, the value pdf_li finds (sample_li's inline path forms
   * the same value from the CDF entries its search read) */
  float p = l->pdf_table[(size_t)iv * (size_t)l->dist.nu + (size_t)iu];
#if EL_ENVLIGHT__SSE
  __m128 f = el_envlight__dir_sse(l, l->row_tab + 16 * (size_t)iv, l->col_tab + 8 * (size_t)iu,
                                  _mm_movelh_ps(_mm_set1_ps(fv), _mm_set1_ps(fu)), p, wi, pdf);
  if (l->table_done && !rgb) return;
  fu = _mm_cvtss_f32(_mm_movehl_ps(f, f));
  fv = _mm_cvtss_f32(f);
#else
  float st = el_envlight__dir_scalar(l, iu, iv, &fu, &fv, wi);
  EL_ASSERT(st >= EL_ENVLIGHT__SIN_MIN);
  *pdf = p / st;
  if (l->table_done && !rgb) return;
#endif
  el_envlight__sample_li_finish(l, iu, iv, fu, fv, wi, rgb, pdf);
}

static EL_ENVLIGHT__NOINLINE void el_envlight__sample_li_rest(const el_envlight *l, const float uu[2], float wi[3], float rgb[3], float *pdf) {
  float d[3], u, v, p;
  if (l->mapping != EL_ENVLIGHT_MAPPING_LATLONG && l->width > 0) { /* pbrt-v4's equal-area map */
    el_envlight__ea_sample(l, uu, wi, rgb, pdf);
    return;
  }
  if (l->dir_tables) {
    int iu, iv;
    float fu, fv, pb;
    if (l->sampler == EL_ENVLIGHT_SAMPLER_CDF) el_distribution2d_sample_bins(&l->dist, uu[0], uu[1], &iu, &iv, &fu, &fv, &pb);
    else el_distribution2d_fast_sample_bins_general(&l->fast, uu[0], uu[1], &iu, &iv, &fu, &fv, &pb);
    el_envlight__sample_table(l, iu, iv, fu, fv, wi, rgb, pdf);
    return;
  }
  p = el_envlight__sample_light(l, uu[0], uu[1], &u, &v, d);
  el_envlight__to_world(l, d, wi);
  if (!l->exact_transform && p > 0.0f && l->width > 0) {
    float back[3];
    el_envlight__mul_transpose(l->to_world, wi, back);
    p = el_envlight__pdf_light(l, back); /* bit-identical to pdf_li(wi) */
    if (!(p > 0.0f)) { /* moved into a bin without mass near a pole: the bin's centre (as sample_li_finish) */
      float cu = ((float)(int)(u * (float)l->dist.nu) + 0.5f) * l->dist.u_width;
      float cv = ((float)(int)(v * (float)l->dist.nv) + 0.5f) * l->dist.v_width;
      el_envlight__uvp_to_dir(cu, cv, cv < 0.5f ? cv : 1.0f - cv, d);
      el_envlight__to_world(l, d, wi);
      el_envlight__mul_transpose(l->to_world, wi, back);
      p = el_envlight__pdf_light(l, back);
    }
    *pdf = p;
    if (rgb) { /* le(wi), as sample_li_finish */
      if (p > 0.0f) el_envlight__le_light(l, back, back[0] * back[0] + back[1] * back[1], rgb);
      else rgb[0] = rgb[1] = rgb[2] = 0.0f;
    }
    return;
  }
  *pdf = p;
  if (rgb) {
    if (p > 0.0f) el_envlight__lookup(l, u, v, rgb);
    else rgb[0] = rgb[1] = rgb[2] = 0.0f;
  }
}

/* sample_li without the inline path: a small frame, so that importance BILINEAR's call is a tail call */
static EL_ENVLIGHT__NOINLINE void el_envlight__sample_li_slow(const el_envlight *l, const float uu[2], float wi[3], float rgb[3], float *pdf) {
  if (!el_envlight__ensure(l)) {
    wi[0] = 0.0f; wi[1] = 0.0f; wi[2] = 1.0f; *pdf = 0.0f;
    if (rgb) rgb[0] = rgb[1] = rgb[2] = 0.0f;
    return;
  }
  if (l->importance == EL_ENVLIGHT_IMPORTANCE_BILINEAR && l->width > 0) { el_envlight__patch_sample(l, uu, wi, rgb, pdf); return; } /* le()'s patches */
  el_envlight__sample_li_rest(l, uu, wi, rgb, pdf);
}

#if EL_ENVLIGHT__SSE
#if defined(__GNUC__) || defined(__clang__)
#define EL_ENVLIGHT__ALWAYS_INLINE inline __attribute__((always_inline))
#else
#define EL_ENVLIGHT__ALWAYS_INLINE inline
#endif
/* sample_li's inline path: the guide table's bin search, then the table direction; returns 0 (nothing
 * written) for a crowded guide cell. With final = 1 (a signed-permutation matrix and a map that is not
 * black) the table's direction and pdf are the result; otherwise (a general rotation, a black map)
 * el_envlight__sample_li_finish recomputes the pdf from wi or sets the black map's result. The search's
 * ends are vectors: u is clamped, scaled to units and to guide cells in one go, the two CDF entries
 * around each bin are read as one 8-byte pair, and the fractions come out in the lane order the
 * direction wants. */
/* The inline path's first half: (u0, u1) clamped as el_distribution2d clamps u (NaN, <= 0 -> 0;
 * >= 1 -> 0x1.fffffep-1) and scaled, *su = (u0 2^24, u1 2^24, u0 gu, u1 gv) (exact), *ku = u0 in CDF
 * units, *cu = u0's guide cell, and the marginal search: returns the marginal CDF entry of the row (NULL
 * for a crowded marginal guide cell, which the slow path binary-searches). */
static EL_ENVLIGHT__ALWAYS_INLINE const uint32_t *el_envlight__guide_row(const el_envlight *l, const float uu[2], __m128 *su, uint32_t *ku, size_t *cu) {
  const float *dc = l->dir_consts;
  const uint32_t *pv;
  __m128 s;
  __m128i k;
  uint32_t kv;
  s = _mm_castsi128_ps(_mm_loadl_epi64((const __m128i *)(const void *)uu));
  s = _mm_min_ps(_mm_max_ps(s, _mm_load_ps(dc + 44)), _mm_load_ps(dc + 36)); /* dc + 44: zeros */
  s = _mm_mul_ps(_mm_movelh_ps(s, s), _mm_load_ps(dc + 32));
  k = _mm_cvttps_epi32(s);
  *su = s;
  *ku = (uint32_t)_mm_cvtsi128_si32(k);
  kv = (uint32_t)_mm_cvtsi128_si32(_mm_shuffle_epi32(k, 0x55));
  *cu = (size_t)(uint32_t)_mm_cvtsi128_si32(_mm_shuffle_epi32(k, 0xaa));
  pv = l->gv_ptr[(size_t)(uint32_t)_mm_cvtsi128_si32(_mm_shuffle_epi32(k, 0xff))];
  if ((uintptr_t)pv & 1u) return NULL;
  while (pv[1] <= kv) ++pv; /* at most 64 steps */
  return pv;
}
/* the row record of marginal entry pv: row_tab + 64 v = row_key + 16 pv (as integers); its floats 12..15
 * hold the row's CDF and guide row pointers */
static EL_ENVLIGHT__ALWAYS_INLINE const float *el_envlight__row_record(const el_envlight *l, const uint32_t *pv) {
  return (const float *)(uintptr_t)(l->row_key + ((uintptr_t)pv << 4));
}

static EL_ENVLIGHT__ALWAYS_INLINE int el_envlight__sample_guide_sse(const el_envlight *l, const float uu[2], float wi[3], float rgb[3], float *pdf, int final, float *uvout) {
  /* <<Find (u, v) sample coordinates in infinite light texture>>, as a bin and fractions: the guide
   * table's CDF inversion (el_distribution2d_fast_guide_bins, the same integers and float operations) */
  const el_distribution2d_fast *fd = &l->fast;
  const float *dc = l->dir_consts;
  const uint32_t *pv, *pu, *row, *const *rp;
  const float *rt;
  __m128 su, x, c, d, f;
  __m128i a, b;
  uint32_t ku, g;
  size_t ou, cu;
  float p;
  pv = el_envlight__guide_row(l, uu, &su, &ku, &cu);
  if (pv) {
    a = _mm_loadl_epi64((const __m128i *)(const void *)pv); /* (c0v, c1v) */
    rt = el_envlight__row_record(l, pv); /* byte offset 4 u below */
    rp = (const uint32_t *const *)(const void *)(rt + 12);
    g = rp[1][cu];
    if (!(g & EL_DISTRIBUTION__GUIDE_CROWDED)) {
      row = rp[0];
      pu = row + g;
      while (pu[1] <= ku) ++pu;
      ou = (size_t)((const char *)pu - (const char *)row);
      /* the bin's CDF entries (c0v, c1v, c0u, c1u) as floats (integers <= 2^24: exact), then
       * f = (x - c0) / (c1 - c0) per axis in lanes (v, v, u, u), and the bin's pdf / (2 pi^2),
       * (wv wu) K, pdf_table's expression */
      b = _mm_loadl_epi64((const __m128i *)(const void *)pu);
      c = _mm_cvtepi32_ps(_mm_unpacklo_epi64(a, b));
      d = EL_ENVLIGHT__SPLAT(c, _MM_SHUFFLE(2, 2, 0, 0));
      c = _mm_sub_ps(EL_ENVLIGHT__SPLAT(c, _MM_SHUFFLE(3, 3, 1, 1)), d);
      x = EL_ENVLIGHT__SPLAT(su, _MM_SHUFFLE(0, 0, 1, 1));
      f = _mm_div_ps(_mm_sub_ps(x, d), c);
      p = _mm_cvtss_f32(_mm_mul_ss(EL_ENVLIGHT__SPLAT(c, 0xaa), c)) * dc[40]; /* (wv wu) K */
      f = el_envlight__dir_sse(l, rt, (const float *)(const void *)((const char *)(dc + 48) + 8 * ou), f, p, wi, pdf);
      if (uvout && *pdf > 0.0f) { /* sample_li_n: the (u, v) at which sample_li_finish would look the radiance up */
        uvout[0] = ((float)(int)(ou / 4) + _mm_cvtss_f32(_mm_movehl_ps(f, f))) * l->dist.u_width;
        uvout[1] = ((float)(int)(pv - fd->marginal) + _mm_cvtss_f32(f)) * l->dist.v_width;
        return 2;
      }
      if (final && !rgb) return 1;
      el_envlight__sample_li_finish(l, (int)(ou / 4), (int)(pv - fd->marginal), _mm_cvtss_f32(_mm_movehl_ps(f, f)), _mm_cvtss_f32(f), wi, rgb, pdf);
      return 1;
    }
  }
  return 0;
}

static EL_ENVLIGHT__NOINLINE void el_envlight__sample_li_slow(const el_envlight *l, const float uu[2], float wi[3], float rgb[3], float *pdf);
/* The inline path with the pdf recomputed (a general rotation, a black map): out of line, so that the
 * common case's function stays small. */
static EL_ENVLIGHT__NOINLINE void el_envlight__sample_li_finishing(const el_envlight *l, const float uu[2], float wi[3], float rgb[3], float *pdf) {
  if (!el_envlight__sample_guide_sse(l, uu, wi, rgb, pdf, 0, NULL)) el_envlight__sample_li_slow(l, uu, wi, rgb, pdf);
}
#endif

/* The hot path has no calls but tail calls; anything it does not take (tables not built yet, the CDF
 * or alias sampler, a crowded guide cell, the constant light, small maps) goes to
 * el_envlight__sample_li_slow. */
EL_DEF void el_envlight_sample_li(const el_envlight *l, const float uu[2], float wi[3], float rgb[3], float *pdf) {
#if EL_ENVLIGHT__ATOMICS
  int hot = __atomic_load_n(&l->hot, __ATOMIC_ACQUIRE); /* built, direction tables, guide sampler */
#else
  int hot = l->hot;
#endif
#if EL_ENVLIGHT__SSE
  if (hot & EL_ENVLIGHT__HOT_SAMPLE) {
    if (el_envlight__sample_guide_sse(l, uu, wi, rgb, pdf, 1, NULL)) return;
  } else if (hot & EL_ENVLIGHT__HOT_SAMPLE_FINISH) {
    el_envlight__sample_li_finishing(l, uu, wi, rgb, pdf);
    return;
  }
#else
  if ((hot & (EL_ENVLIGHT__HOT_SAMPLE | EL_ENVLIGHT__HOT_SAMPLE_FINISH)) && el_distribution2d_u_in_range(uu[0], uu[1])) {
    float fu, fv, pb;
    int iu, iv;
    if (el_distribution2d_fast_guide_bins(&l->fast, uu[0], uu[1], &iu, &iv, &fu, &fv, &pb)) {
      /* <<Find (u, v) sample coordinates in infinite light texture>>: done, as a bin and fractions */
      el_envlight__sample_table(l, iu, iv, fu, fv, wi, rgb, pdf);
      return;
    }
  }
#endif
  el_envlight__sample_li_slow(l, uu, wi, rgb, pdf);
}

#if EL_ENVLIGHT__SSE && (defined(__GNUC__) || defined(__clang__))
#define EL_ENVLIGHT__BATCH 32 /* lanes per staged pass (16: 10% slower per sample, issue 21) */
#endif

EL_DEF void el_envlight_sample_li_n(const el_envlight *l, int n, const float *u, float *wi, float *rgb, float *pdf) {
  int i;
#if EL_ENVLIGHT__SSE && (defined(__GNUC__) || defined(__clang__))
  if (n > 1 && (el_envlight__hot_now(l) & EL_ENVLIGHT__HOT_SAMPLE)) {
    /* Four passes over up to 32 samples; each pass starts the next pass's cache misses for all of
     * them, so that they overlap: (1) the guide entry, (2) the CDF entries it points to, (3) the sample
     * itself (sample_li's inline path; its radiance's texels), (4) the radiance. Passes 1, 2 and the
     * texel prefetch only read; every result comes from the code sample_li runs. */
    int i0, m;
    for (i0 = 0; i0 < n; i0 += EL_ENVLIGHT__BATCH) {
      float uv[2 * EL_ENVLIGHT__BATCH];
      unsigned char done[EL_ENVLIGHT__BATCH];
      const uint32_t *const *rps[EL_ENVLIGHT__BATCH];
      size_t cus[EL_ENVLIGHT__BATCH];
      m = n - i0 < EL_ENVLIGHT__BATCH ? n - i0 : EL_ENVLIGHT__BATCH;
      for (i = 0; i < m; ++i) { /* the marginal search (small tables, in cache) */
        __m128 su;
        uint32_t ku;
        const uint32_t *pv = el_envlight__guide_row(l, u + 2 * (i0 + i), &su, &ku, &cus[i]);
        rps[i] = pv ? (const uint32_t *const *)(const void *)(el_envlight__row_record(l, pv) + 12) : NULL;
        if (rps[i]) __builtin_prefetch(rps[i][1] + cus[i]);
      }
      for (i = 0; i < m; ++i) {
        const uint32_t *const *rp = rps[i];
        uint32_t g;
        if (!rp) continue;
        g = rp[1][cus[i]];
        if (!(g & EL_DISTRIBUTION__GUIDE_CROWDED)) __builtin_prefetch(rp[0] + g + 1); /* the first pair the search reads */
      }
      for (i = 0; i < m; ++i) {
        const int j = i0 + i;
        float *c = rgb ? rgb + 3 * j : NULL;
        int r = el_envlight__sample_guide_sse(l, u + 2 * j, wi + 3 * j, c, pdf + j, 1, c ? uv + 2 * i : NULL);
        done[i] = 1;
        if (r == 0) {
          el_envlight__sample_li_slow(l, u + 2 * j, wi + 3 * j, c, pdf + j);
        } else if (r == 2) { /* sampled; the radiance is left for pass 4, its four texels prefetched */
          const float *p[4];
          float fx, fy;
          int q;
          el_envlight__bilerp_texels(l, uv[2 * i], uv[2 * i + 1], p, &fx, &fy);
          /* per row the pair's first float and last float: both lines of the 24 bytes */
          for (q = 0; q < 4; ++q) __builtin_prefetch(p[q] + 2 * (q & 1));
          done[i] = 0;
        }
      }
      if (rgb)
        for (i = 0; i < m; ++i) {
          const int j = i0 + i;
          if (done[i]) continue;
          /* what el_envlight__sample_li_finish does with a positive pdf that needs no recomputing */
          el_envlight__lookup(l, uv[2 * i], uv[2 * i + 1], rgb + 3 * j);
        }
    }
    return;
  }
#endif
  if (n > 1 && l->importance == EL_ENVLIGHT_IMPORTANCE_BILINEAR && l->width > 0 && el_envlight__ensure(l)) {
    el_envlight__patch_sample_n(l, n, u, wi, rgb, pdf); /* (importance BILINEAR: its own batches) */
    return;
  }
  for (i = 0; i < n; ++i) el_envlight_sample_li(l, u + 2 * i, wi + 3 * i, rgb ? rgb + 3 * i : NULL, pdf + i);
}

/* pdf_li_n and le_n: two passes over up to 32 directions; the first maps each to light space and finds
 * the table entry (pdf_li's pdf_table bin; le's four texels) and prefetches it, so that the cache misses
 * of the 32 overlap; the second reads them with the single call's arithmetic. Cold lanes (zero, NaN,
 * infinite or rescaled directions) go through the single call's own cold path in the first pass. */
EL_DEF void el_envlight_pdf_li_n(const el_envlight *l, int n, const float *dirs, float *pdf) {
  int i;
#ifdef EL_ENVLIGHT__BATCH
  if (n > 1 && (el_envlight__hot_now(l) & EL_ENVLIGHT__HOT_PDF)) {
    int i0, m;
    for (i0 = 0; i0 < n; i0 += EL_ENVLIGHT__BATCH) {
      float rs[EL_ENVLIGHT__BATCH], lens[EL_ENVLIGHT__BATCH];
      size_t bin[EL_ENVLIGHT__BATCH];
      unsigned char cold[EL_ENVLIGHT__BATCH];
      m = n - i0 < EL_ENVLIGHT__BATCH ? n - i0 : EL_ENVLIGHT__BATCH;
      for (i = 0; i < m; ++i) { /* el_envlight_pdf_li's hot path up to the table read */
        const float *w = dirs + 3 * (i0 + i);
        float d[3], r2, len2;
        el_envlight__to_light(l, w, d);
        r2 = d[0] * d[0] + d[1] * d[1];
        len2 = r2 + d[2] * d[2];
        cold[i] = !(len2 >= FLT_MIN && len2 <= FLT_MAX);
        if (cold[i]) { pdf[i0 + i] = el_envlight__pdf_world_cold(l, w); continue; }
        rs[i] = el_envlight__sqrt(r2);
        lens[i] = el_envlight__sqrt(len2);
        bin[i] = el_envlight__pdf_bin(l, d[0], d[1], d[2], rs[i]);
        __builtin_prefetch(l->pdf_table + bin[i]);
      }
      for (i = 0; i < m; ++i)
        if (!cold[i]) pdf[i0 + i] = el_envlight__pdf_at(l->pdf_table[bin[i]], rs[i], lens[i]);
    }
    return;
  }
#endif
  for (i = 0; i < n; ++i) pdf[i] = el_envlight_pdf_li(l, dirs + 3 * i);
}

EL_DEF void el_envlight_le_n(const el_envlight *l, int n, const float *dirs, float *rgb) {
  int i;
#ifdef EL_ENVLIGHT__BATCH
  if (n > 1 && l->width > 0 && l->mapping == EL_ENVLIGHT_MAPPING_LATLONG) {
    int i0, m;
    for (i0 = 0; i0 < n; i0 += EL_ENVLIGHT__BATCH) {
      const float *p[4 * EL_ENVLIGHT__BATCH];
      float fx[EL_ENVLIGHT__BATCH], fy[EL_ENVLIGHT__BATCH];
      unsigned char cold[EL_ENVLIGHT__BATCH];
      m = n - i0 < EL_ENVLIGHT__BATCH ? n - i0 : EL_ENVLIGHT__BATCH;
      for (i = 0; i < m; ++i) { /* el_envlight_le up to the texel reads (el_envlight__le_light's (u, v)) */
        const float *w = dirs + 3 * (i0 + i);
        float d[3], r2, len2;
        int q;
        el_envlight__to_light(l, w, d);
        r2 = d[0] * d[0] + d[1] * d[1];
        len2 = r2 + d[2] * d[2];
        cold[i] = !(len2 >= FLT_MIN && len2 <= FLT_MAX);
        if (cold[i]) { el_envlight__le_cold(l, w, rgb + 3 * (i0 + i)); continue; }
        el_envlight__bilerp_texels(l, el_envlight__phi_turns(d[1], d[0]), el_envlight__theta_halfturns(sqrtf(r2), d[2]),
                                   p + 4 * i, &fx[i], &fy[i]);
        for (q = 0; q < 4; ++q) __builtin_prefetch(p[4 * i + q] + 2 * (q & 1)); /* as sample_li_n */
      }
      for (i = 0; i < m; ++i)
        if (!cold[i]) el_envlight__bilerp_at(p + 4 * i, fx[i], fy[i], rgb + 3 * (i0 + i));
    }
    return;
  }
#endif
  for (i = 0; i < n; ++i) el_envlight_le(l, dirs + 3 * i, rgb + 3 * i);
}

static void el_envlight__basis(const float n[3], float b1[3], float b2[3]) {
  float sign = n[2] >= 0.0f ? 1.0f : -1.0f;
  float a = -1.0f / (sign + n[2]), b = n[0] * n[1] * a;
  b1[0] = 1.0f + sign * n[0] * n[0] * a; b1[1] = sign * b; b1[2] = -sign * n[0];
  b2[0] = b; b2[1] = sign + n[1] * n[1] * a; b2[2] = -n[1];
}

EL_DEF void el_envlight_sample_le(const el_envlight *l, const float u[4], float ray_org[3], float ray_dir[3],
                                  float normal[3], float rgb[3], float *pdf_pos, float *pdf_dir) {
  float wi[3], L[3], p, b1[3], b2[3], dx, dy, R = l->radius;
  int k;
  el_envlight_sample_li(l, u, wi, L, &p);
  if (!(p > 0.0f) || !(R > 0.0f)) {
    for (k = 0; k < 3; ++k) { ray_org[k] = l->center[k]; ray_dir[k] = -wi[k]; normal[k] = -wi[k]; rgb[k] = 0.0f; }
    *pdf_pos = 0.0f; *pdf_dir = 0.0f;
    return;
  }
  /* <<Compute origin for infinite light sample ray>>: a point on the disk facing wi, pushed out by R */
  el_envlight__basis(wi, b1, b2);
  { /* Shirley-Chiu concentric disk */
    float a = 2.0f * el_envlight__clamp_u(u[2]) - 1.0f, b = 2.0f * el_envlight__clamp_u(u[3]) - 1.0f, rr, q;
    if (a == 0.0f && b == 0.0f) { dx = 0.0f; dy = 0.0f; }
    else if (fabsf(a) > fabsf(b)) { rr = a; q = 0.25f * (b / a); dx = rr * el_envlight__cospi(q); dy = rr * el_envlight__sinpi(q); }
    else { rr = b; q = 0.25f * (a / b); dx = rr * el_envlight__sinpi(q); dy = rr * el_envlight__cospi(q); }
  }
  for (k = 0; k < 3; ++k) {
    ray_org[k] = l->center[k] + R * (dx * b1[k] + dy * b2[k]) + R * wi[k];
    ray_dir[k] = -wi[k];
    normal[k] = -wi[k];
    rgb[k] = L[k];
  }
  *pdf_dir = p;
  *pdf_pos = 1.0f / (float)(EL_ENVLIGHT__PI * (double)R * (double)R);
}

EL_DEF void el_envlight_pdf_le(const el_envlight *l, const float ray_dir[3], float *pdf_pos, float *pdf_dir) {
  float w[3];
  w[0] = -ray_dir[0]; w[1] = -ray_dir[1]; w[2] = -ray_dir[2];
  if (!(l->radius > 0.0f)) { *pdf_pos = 0.0f; *pdf_dir = 0.0f; return; }
  *pdf_dir = el_envlight_pdf_li(l, w);
  *pdf_pos = 1.0f / (float)(EL_ENVLIGHT__PI * (double)l->radius * (double)l->radius);
}

EL_DEF void el_envlight_integral(const el_envlight *l, float rgb[3]) {
  int c;
  for (c = 0; c < 3; ++c) rgb[c] = l->integral[c] < FLT_MAX ? (float)l->integral[c] : FLT_MAX;
}

EL_DEF void el_envlight_power(const el_envlight *l, float rgb[3]) {
  int c;
  double a = EL_ENVLIGHT__PI * (double)l->radius * (double)l->radius;
  for (c = 0; c < 3; ++c) {
    double p = a * l->integral[c];
    rgb[c] = p < FLT_MAX ? (float)p : FLT_MAX;
  }
}

EL_DEF size_t el_envlight_sampling_bytes(const el_envlight *l) {
  size_t b = 0;
#if EL_ENVLIGHT__ATOMICS
  int s = __atomic_load_n(&l->state, __ATOMIC_ACQUIRE);
#else
  int s = l->state;
#endif
  if (s != 2 || l->width == 0) return 0;
  if (l->importance == EL_ENVLIGHT_IMPORTANCE_BILINEAR) return el_envlight__warp_bytes(l); /* the patch tables */
  b += el_distribution2d_bytes(&l->dist);
  b += (size_t)(l->u_cells + l->v_cells) * (sizeof(int) + sizeof(float));
  b += (size_t)l->dist.nu * (size_t)l->dist.nv * sizeof(float); /* pdf_table */
  if (l->dir_tables) b += el_envlight__dir_floats(l->dist.nu, l->dist.nv) * sizeof(float);
  if (l->gv_ptr) b += ((size_t)l->fast.gv + 1) * sizeof *l->gv_ptr;
  if (l->sampler != EL_ENVLIGHT_SAMPLER_CDF) b += el_distribution2d_fast_bytes(&l->fast);
  return b;
}

EL_DEF size_t el_envlight_bytes(const el_envlight *l) {
  return sizeof *l + (l->borrowed ? 0 : (size_t)l->width * (size_t)l->height * 3 * sizeof(float)) + el_envlight_sampling_bytes(l) +
         el_envlight_product_bytes(l);
}

EL_DEF void el_envlight_yup_matrix(float m[9]) {
  /* world x = light y, world y = light z, world z = -light x (Mitsuba 3: u = atan2(x, -z) / 2pi) */
  static const float k[9] = {0, 1, 0, 0, 0, 1, -1, 0, 0};
  memcpy(m, k, sizeof k);
}

EL_DEF void el_envlight_zup_matrix(float m[9]) {
  /* world = (-light x, light y, light z) (Blender: u = 0.5 - atan2(y, x) / 2pi) */
  static const float k[9] = {-1, 0, 0, 0, 1, 0, 0, 0, 1};
  memcpy(m, k, sizeof k);
}

/* >> the patch grid
 * The density of importance mode BILINEAR and, times a per-cell cosine bound, of sample_li_cos: the
 * luminance of le()'s bilinear reconstruction times sin(theta), taken as the bilinear interpolant of its
 * values at the texel centres (the vertices) - Mitsuba 3's envmap density. Vertex row k is at v_k =
 * (k - 0.5) / h for k = 1..h (texel row k - 1), with two pole rows v_0 = 0 and v_{h+1} = 1 whose value
 * is 0 (sin 0); so there are h + 1 patch rows (the two at the poles half as tall) and w patch columns
 * (patch column i spans the texel centres i and i + 1, wrapping at the seam). Product sampling groups
 * the patches into cells (its section below); importance BILINEAR samples them from one table (the
 * section "importance BILINEAR"). Until issue 22 mode BILINEAR had a continuous warp of its own here
 * (per-row integer CDFs blended at t, about 1100 instructions per sample). */

#define EL_ENVLIGHT__CELL_UNITS 32768u  /* a cell table's integer total (its entries are uint16_t) */

struct el_envlight__warp {
  int w, h, ku, kv;      /* the image (w patch columns, h + 1 patch rows); cells */
  int all_zero;          /* no mass anywhere: every pdf is 0 */
  float offset;          /* compensation: the mean luminance subtracted from every vertex (0: plain) */
  int fell_back;         /* compensated, but no vertex exceeds the mean: the plain density */
  float *sin_row;        /* h: sin(pi v_k) of texel row k - 1 */
  float *V;              /* (h + 2) x w: the vertex values; rows 0 and h + 1 (the poles) are 0 */
  uint16_t *V16;         /* product sampling: V as bfloat16 (the top half of the float, rounded up) */
  size_t cond_stride;    /* w + ku: a patch row's entries in pcol */
  int *coff;             /* ku: the first CDF entry of cell column a in a row of pcol (a0[a] + a) */
  int row_len, marg_len; /* a cell table's CDF lengths: ku + 1 and kv + 1 */
  float inv_w, inv_h, half_inv_h; /* 1 / w, 1 / h, 0.5 / h */
  int *a0, *b0;          /* ku + 1 patch-column, kv + 1 patch-row bounds of the cells */
  int *cu_of, *cv_of;    /* w, h + 1: the cell column / row of a patch column / row */
  double *mass;          /* kv x ku: each cell's integral over (u, v) */
  size_t table_len;      /* entries of a cell table: the cell rows' CDF (kv + 1 entries), then kv rows'
                            CDFs over their cells (ku + 1 entries each) */
  size_t warp_bytes;
  /* the normal tables (cos_state) */
  int m;                 /* octahedral bins per axis */
  uint16_t *cos_tab;     /* m * m sparse cell tables (el_envlight__cell_table_sparse), one after another */
  uint32_t *cos_off;     /* m * m: where each bin's table starts in cos_tab */
  size_t cos_bytes;
  /* product sampling's patches (issue 20; a product table set uses w, h, ku, kv, a0, b0, cu_of, cv_of,
     coff, sin_row, V, mass and the normal tables above, and these two) */
  uint16_t *pcol;        /* (h + 1) x (w + ku): patch row r's CDF over the patches of each cell column */
  uint16_t *prow;        /* ku x (h + 1 + kv): per cell column, each cell's CDF over its patch rows */
  int coarse;            /* 1: V is a max-filtered coarse grid of the map (maps over the size cap) */
  uint8_t *gcol, *grow;  /* guide tables (issue 20) of pcol per (r, a) and prow per (a, b), or NULL */
  float dens_k;          /* 2^-60 w h / (2 pi^2): integer widths -> density per solid angle x sin */
};

/* cdf[0..n] for n weights >= 0, total `units`: every positive weight gets at least one unit and the rest
 * goes in proportion through exact 64-bit fixed-point prefix sums (no rounding error accumulates along
 * the row). All zero: cdf all 0, returns 0. */
static int el_envlight__int_cdf(const double *f, int n, uint32_t units, uint32_t *cdf) {
  double total = 0.0, k, rest;
  uint64_t p = 0, ptot = 0;
  uint32_t m = 0, c = 0;
  int i;
  for (i = 0; i < n; ++i) { total += f[i]; m += f[i] > 0.0; }
  cdf[0] = 0;
  if (m == 0 || !(total > 0.0)) { for (i = 0; i < n; ++i) cdf[i + 1] = 0; return 0; }
  k = 1099511627776.0 / total; /* 2^40 fixed point of each weight's share */
  for (i = 0; i < n; ++i) ptot += (uint64_t)(int64_t)(f[i] * k); /* < 2^41: int64 is exact and one instruction */
  rest = (double)(units - m);
  for (i = 0; i < n; ++i) {
    p += (uint64_t)(int64_t)(f[i] * k);
    c += f[i] > 0.0;
    /* p / ptot is monotone in i and exactly 1 from the last positive weight on (ptot >= 2^40 / n - n > 0),
     * so zero weights after it get no unit and cdf[n] = units */
    cdf[i + 1] = c + (uint32_t)(rest * ((double)p / (double)ptot));
  }
  return 1;
}

/* A cell table from kv x ku weights: the cell rows' CDF, then each row's CDF over its cells, in
 * EL_ENVLIGHT__CELL_UNITS. tmp: ku + kv + 2 uint32 and kv doubles. */
static void el_envlight__cell_rows_cdf(const struct el_envlight__warp *W, const double *wgt, uint16_t *tab, uint32_t *tmp, double *rows) {
  /* the cell rows' sums (rows[0..kv-1]) and their CDF (tab[0..kv]), shared by both table layouts */
  int a, b, ku = W->ku, kv = W->kv;
  for (b = 0; b < kv; ++b) {
    double s = 0.0;
    for (a = 0; a < ku; ++a) s += wgt[(size_t)b * (size_t)ku + (size_t)a];
    rows[b] = s;
  }
  el_envlight__int_cdf(rows, kv, EL_ENVLIGHT__CELL_UNITS, tmp);
  for (b = 0; b <= kv; ++b) tab[b] = (uint16_t)tmp[b];
}

/* Guide tables (Chen's cutpoint method, issue 20): for a CDF c[0..n] over 32768 units, g[j] (j < 8) is the
 * last i in [0, n - 1] with c[i] <= j 4096; the search starts there and steps forward: the same i as
 * el_envlight__search16 for k < 32768. */
#define EL_ENVLIGHT__GUIDE_K 8
#define EL_ENVLIGHT__GUIDE_SHIFT 12 /* 32768 / GUIDE_K = 2^GUIDE_SHIFT */
#define EL_ENVLIGHT__GUIDE_E (EL_ENVLIGHT__GUIDE_K / 2) /* uint16 entries a guide takes inside a sparse table */
static void el_envlight__guide_build(const uint16_t *c, int n, uint8_t *g) {
  /* g[j] = #{i in [1, n - 1]: c[i] <= j 2^GUIDE_SHIFT} (c is monotone): c[i] counts from bucket
   * ceil(c[i] / 2^GUIDE_SHIFT) on. The counts per bucket (n <= 256: at most 255 each) are bytes of one
   * register, so the loop has no branch and no store-to-load chain (the build's time: issue 20) */
  uint64_t cnt = 0;
  int i, j, acc = 0;
  for (i = 1; i < n; ++i) {
    uint32_t b = ((uint32_t)c[i] + (1u << EL_ENVLIGHT__GUIDE_SHIFT) - 1u) >> EL_ENVLIGHT__GUIDE_SHIFT;
    cnt += b < EL_ENVLIGHT__GUIDE_K ? (uint64_t)1 << (8u * b) : 0u;
  }
  for (j = 0; j < EL_ENVLIGHT__GUIDE_K; ++j) { acc += (int)((cnt >> (8 * j)) & 255u); g[j] = (uint8_t)acc; }
}
static inline int el_envlight__search_guided(const uint16_t *c, int n, const uint8_t *g, uint32_t k) {
  int i;
  k = k < 32767u ? k : 32767u;
  i = g[k >> EL_ENVLIGHT__GUIDE_SHIFT];
#if EL_ENVLIGHT__SSE && (defined(__GNUC__) || defined(__clang__))
  /* eight steps at once while c[i + 1 .. i + 8] lie in [0, n - 1]: the entries <= k are a prefix (c is
   * monotone), so the steps are the lanes before the first entry > k (uint16 compared as int16 after
   * - 32768 on both sides) */
  {
    const __m128i bias = _mm_set1_epi16((short)(-32767 - 1)), kk = _mm_set1_epi16((short)((int)k - 32768));
    while (i + 8 < n) {
      __m128i v = _mm_xor_si128(_mm_loadu_si128((const __m128i *)(const void *)(c + i + 1)), bias);
      unsigned m = (unsigned)_mm_movemask_epi8(_mm_cmpgt_epi16(v, kk));
      if (m) return i + (int)((unsigned)__builtin_ctz(m) >> 1);
      i += 8;
    }
  }
#endif
  while (i + 1 < n && (uint32_t)c[i + 1] <= k) ++i;
  return i;
}

/* A sparse cell table (the normal tables, issue 20): the cell rows' CDF (kv + 1 entries, padded to an
 * even count P), kv row offsets (uint32, read with memcpy) from the table's start, then per row its span
 * of cells with weight, a_s (first cell) and L (cells, wrapping at the seam: the complement of the
 * longest circular run of zero weights), and its CDF over those L cells (L + 1 entries). Below a normal's
 * horizon the weights are 0, so a row holds about half its cells. Returns the entries used (at most
 * el_envlight__sparse_max). tmp: ku + kv + 2 uint32; rows: kv + ku doubles. */
static size_t el_envlight__sparse_max(const struct el_envlight__warp *W) {
  return (size_t)((W->kv + 2) & ~1) + 2 * (size_t)W->kv + EL_ENVLIGHT__GUIDE_E + (size_t)W->kv * ((size_t)W->ku + 3 + EL_ENVLIGHT__GUIDE_E);
}
static size_t el_envlight__cell_table_sparse(const struct el_envlight__warp *W, const double *wgt, uint16_t *tab, uint32_t *tmp, double *rows) {
  int b, ku = W->ku, kv = W->kv;
  size_t pos = (size_t)((kv + 2) & ~1) + 2 * (size_t)kv + EL_ENVLIGHT__GUIDE_E;
  double *span = rows + kv;
  el_envlight__cell_rows_cdf(W, wgt, tab, tmp, rows);
  el_envlight__guide_build(tab, kv, (uint8_t *)(tab + (size_t)((kv + 2) & ~1) + 2 * (size_t)kv)); /* the rows' guide */
  for (b = 0; b < kv; ++b) {
    const double *w = wgt + (size_t)b * (size_t)ku;
    int run = 0, best = 0, best_end = -1, lead = 0, as, len, k, kk;
    uint32_t off = (uint32_t)pos + EL_ENVLIGHT__GUIDE_E; /* after the row's guide */
    /* the longest circular run of zeros: the longest inside the row, or the trailing run joined to the
     * leading one across the seam */
    while (lead < ku && !(w[lead] > 0.0)) ++lead;
    for (k = lead; k < ku; ++k) {
      run = w[k] > 0.0 ? 0 : run + 1;
      if (run > best) { best = run; best_end = k; }
    }
    if (lead == ku) best = ku; /* all zero */
    else if (run + lead > best) { best = run + lead; best_end = lead - 1 >= 0 ? lead - 1 : ku - 1; }
    len = ku - best;
    as = len == 0 || best == 0 ? 0 : (best_end + 1 < ku ? best_end + 1 : 0);
    for (k = 0, kk = as; k < len; ++k, kk = kk + 1 < ku ? kk + 1 : 0) span[k] = w[kk];
    if (len > 0) el_envlight__int_cdf(span, len, EL_ENVLIGHT__CELL_UNITS, tmp);
    else tmp[0] = 0;
    memcpy(tab + (size_t)((kv + 2) & ~1) + 2 * (size_t)b, &off, sizeof off);
    pos += EL_ENVLIGHT__GUIDE_E;
    tab[pos] = (uint16_t)as; tab[pos + 1] = (uint16_t)len;
    for (k = 0; k <= len; ++k) tab[pos + 2 + (size_t)k] = (uint16_t)tmp[k];
    el_envlight__guide_build(tab + pos + 2, len > 0 ? len : 1, (uint8_t *)(tab + pos - EL_ENVLIGHT__GUIDE_E));
    pos += (size_t)len + 3;
  }
  return pos;
}

/* Row b of a sparse cell table: [a_s, L, CDF over L + 1 entries] */
static inline const uint16_t *el_envlight__sparse_row(const struct el_envlight__warp *W, const uint16_t *tab, int b) {
  uint32_t off;
  memcpy(&off, tab + (size_t)((W->kv + 2) & ~1) + 2 * (size_t)b, sizeof off);
  return tab + off;
}

/* Last i in [0, n - 1] with c[i] <= k (c[0] = 0 <= k), uint16 entries: a branch-free binary search. */
static inline int el_envlight__search16(const uint16_t *c, int n, uint32_t k) {
  int lo = 0;
  while (n > 1) {
    int half = n >> 1;
    lo = ((uint32_t)c[lo + half] <= k) ? lo + half : lo;
    n -= half;
  }
  return lo;
}

/* The vertex value of texel (i, j): its luminance (minus the compensation offset, clamped at 0) times
 * the sin of its row (stored in W->V at build time; queries read it). */
static inline float el_envlight__vertex_of(const el_envlight *l, const struct el_envlight__warp *W, int i, int j) {
  float y = el_envlight__luminance(l->texels + ((size_t)j * (size_t)W->w + (size_t)i) * 3);
  y = y < FLT_MAX ? y : FLT_MAX;
  y = y > W->offset ? y - W->offset : 0.0f;
  return y * W->sin_row[j];
}


static void el_envlight__warp_free(struct el_envlight__warp *W) {
  if (!W) return;
  EL_FREE(W->sin_row); EL_FREE(W->V); EL_FREE(W->coff); EL_FREE(W->a0); EL_FREE(W->b0);
  EL_FREE(W->cu_of); EL_FREE(W->cv_of); EL_FREE(W->mass); EL_FREE(W->cos_tab); EL_FREE(W->cos_off); EL_FREE(W->V16); EL_FREE(W->gcol); EL_FREE(W->grow);
  EL_FREE(W->pcol); EL_FREE(W->prow);
  EL_FREE(W);
}

/* u in [0,1) as the fast samplers clamp it: NaN and <= 0 -> 0, >= 1 -> 0x1.fffffep-1 */
static inline float el_envlight__clamp01(float u) {
  u = u > 0.0f ? u : 0.0f;
  return u < 0.99999994f ? u : 0.99999994f;
}

/* theta_halfturns with the distance to the nearer pole as well (same operations for *v) */
static inline void el_envlight__theta_vp(float r, float z, float *v, float *vp) {
  float az = fabsf(z);
  float mx = az > r ? az : r, mn = az > r ? r : az;
  float a = el_envlight__atan01(mn / (mx > FLT_MIN ? mx : FLT_MIN)) * 0.318309886f; /* 1/pi */
  if (r > az) a = 0.5f - a;
  *vp = a;
  if (z < 0.0f) a = 1.0f - a;
  *v = a;
}

/* >> product sampling
 * Cells times a cosine bound: the density of sample_li_cos is P(cell | n) times the warp inside the
 * cell, P(cell | n) proportional to the cell's mass times an upper bound of max(0, n.w) over the cell,
 * read from a table for the octahedral bin of n (the bound holds for every normal of the bin: the
 * exact maximum over the cell for the bin's centre normal, widened by the bin's angular radius). */

/* Octahedral coordinates of a unit-ish n in [0,1]^2 (the lower hemisphere folded out to the corners);
 * the build decodes bin corners with el_envlight__oct_decode, the same map in double. */
static inline void el_envlight__oct_encode(const float n[3], float *x, float *y) {
  float s = fabsf(n[0]) + fabsf(n[1]) + fabsf(n[2]), px = n[0] / s, py = n[1] / s;
  if (n[2] < 0.0f) {
    float qx = (1.0f - fabsf(py)) * (px >= 0.0f ? 1.0f : -1.0f), qy = (1.0f - fabsf(px)) * (py >= 0.0f ? 1.0f : -1.0f);
    px = qx; py = qy;
  }
  *x = 0.5f * px + 0.5f; *y = 0.5f * py + 0.5f;
}
static void el_envlight__oct_decode(double x, double y, double n[3]) {
  double px = 2.0 * x - 1.0, py = 2.0 * y - 1.0, z = 1.0 - fabs(px) - fabs(py), len;
  if (z < 0.0) {
    double qx = (1.0 - fabs(py)) * (px >= 0.0 ? 1.0 : -1.0), qy = (1.0 - fabs(px)) * (py >= 0.0 ? 1.0 : -1.0);
    px = qx; py = qy;
  }
  len = sqrt(px * px + py * py + z * z);
  n[0] = px / len; n[1] = py / len; n[2] = z / len;
}

/* max of n.w over the lat-long cell [phi0, phi1] x [theta0, theta1] (light space), exactly: over phi
 * the best is the normal's own phi if inside, else the nearer edge (el_envlight__col_maxcos: a, the best
 * horizontal component, per cell column); then a sin(theta) + b cos(theta) peaks at atan2(a, b) if
 * inside, else at an edge (el_envlight__row_maxcos, per cell). cp: cos, sin of phi0, of phi1, and 1 when
 * phi1 - phi0 > pi (then "inside" is "not in the complement", narrower than pi); ct: cos, sin of theta0,
 * of theta1. */
static double el_envlight__col_maxcos(const double n[3], const double cp[5]) {
  double c0 = cp[0] * n[1] - cp[1] * n[0], c1 = n[0] * cp[3] - n[1] * cp[2];
  int inside = cp[4] > 0.0 ? !(c1 < 0.0 && c0 < 0.0) : (c0 >= 0.0 && c1 >= 0.0);
  if (inside) return sqrt(n[0] * n[0] + n[1] * n[1]);
  else { double d0 = n[0] * cp[0] + n[1] * cp[1], d1 = n[0] * cp[2] + n[1] * cp[3]; return d0 > d1 ? d0 : d1; }
}
static inline double el_envlight__row_maxcos(double a, double b, const double ct[4]) {
  double f0 = a * ct[1] + b * ct[0], f1 = a * ct[3] + b * ct[2], best = f0 > f1 ? f0 : f1;
  if (a * ct[0] - b * ct[1] > 0.0 && a * ct[2] - b * ct[3] < 0.0) best = sqrt(a * a + b * b); /* the peak is inside */
  return best;
}

/* <<Build the normal tables>>: for each of m x m octahedral bins, the bin's centre normal c and an
 * angular radius covering every normal the float encoder puts in the bin (the farthest point of the
 * bin's boundary, sampled 32 times per edge, plus the largest gap between samples, plus 1e-4), then per
 * cell the bound cos(max(0, angle(c, cell) - radius)) (1 when the cell is within the radius, 0 when it
 * is 90 degrees beyond), times the cell's mass, into a cell table. The phi part of the maximum is per
 * cell column, the theta part per cell (issue 20: a third of the build's instructions). */
static el_result el_envlight__cos_build(struct el_envlight__warp *W, int m) {
  int ku = W->ku, kv = W->kv, K = ku * kv, bin, k, e, q, a, b;
  double *geo = (double *)EL_MALLOC(((size_t)ku * 6 + (size_t)kv * 4) * sizeof(double)), *wgt = (double *)EL_MALLOC(((size_t)K + (size_t)kv + (size_t)ku) * sizeof(double));
  double *gcol = geo, *grow = geo + (size_t)ku * 5, *acol = grow + (size_t)kv * 4;
  uint32_t *tmp = (uint32_t *)EL_MALLOC(((size_t)ku + (size_t)kv + 2) * sizeof(uint32_t));
  size_t smax = el_envlight__sparse_max(W), used = 0;
  if ((size_t)m * (size_t)m > ((size_t)-1) / sizeof(uint16_t) / smax || (size_t)m * (size_t)m * smax > 0xffffffffu) { EL_FREE(geo); EL_FREE(wgt); EL_FREE(tmp); return EL_ERROR_SIZE_OVERFLOW; }
  /* the worst case, shrunk to what the bins use at the end */
  W->cos_tab = (uint16_t *)EL_MALLOC((size_t)m * (size_t)m * smax * sizeof(uint16_t));
  W->cos_off = (uint32_t *)EL_MALLOC((size_t)m * (size_t)m * sizeof(uint32_t));
  if (!geo || !wgt || !tmp || !W->cos_tab || !W->cos_off) {
    EL_FREE(geo); EL_FREE(wgt); EL_FREE(tmp); EL_FREE(W->cos_tab); EL_FREE(W->cos_off); W->cos_tab = NULL; W->cos_off = NULL;
    return EL_ERROR_OUT_OF_MEMORY;
  }
  W->m = m;
  for (a = 0; a < ku; ++a) { /* the cells' edges: phi at patch-column bounds (texel centres), theta at vertex rows */
    double p0 = 2.0 * EL_ENVLIGHT__PI * (W->a0[a] + 0.5) / W->w, p1 = 2.0 * EL_ENVLIGHT__PI * (W->a0[a + 1] + 0.5) / W->w;
    double *g = gcol + 5 * (size_t)a;
    g[0] = cos(p0); g[1] = sin(p0); g[2] = cos(p1); g[3] = sin(p1);
    g[4] = p1 - p0 > EL_ENVLIGHT__PI ? 1.0 : 0.0;
  }
  for (b = 0; b < kv; ++b) {
    int r0 = W->b0[b], r1 = W->b0[b + 1];
    double v0 = r0 == 0 ? 0.0 : (r0 - 0.5) / W->h, v1 = r1 == W->h + 1 ? 1.0 : (r1 - 0.5) / W->h;
    double *g = grow + 4 * (size_t)b;
    g[0] = cos(EL_ENVLIGHT__PI * v0); g[1] = sin(EL_ENVLIGHT__PI * v0); g[2] = cos(EL_ENVLIGHT__PI * v1); g[3] = sin(EL_ENVLIGHT__PI * v1);
  }
  for (bin = 0; bin < m * m; ++bin) {
    int bi = bin % m, bj = bin / m;
    double c[3], prev[3], first[3], dmin = 1.0, gmin = 1.0, rad, cr, sr;
    el_envlight__oct_decode((bi + 0.5) / m, (bj + 0.5) / m, c);
    el_envlight__oct_decode((double)bi / m, (double)bj / m, first); /* the boundary's first sample */
    memcpy(prev, first, sizeof prev);
    for (e = 0; e < 4; ++e)
      for (q = 0; q < 32; ++q) {
        double t = q / 32.0, x, y, dv[3], dc, dp;
        if (e == 0) { x = bi + t; y = bj; }
        else if (e == 1) { x = bi + 1; y = bj + t; }
        else if (e == 2) { x = bi + 1 - t; y = bj + 1; }
        else { x = bi; y = bj + 1 - t; }
        el_envlight__oct_decode(x / m, y / m, dv);
        dc = c[0] * dv[0] + c[1] * dv[1] + c[2] * dv[2];
        if (dc < dmin) dmin = dc;
        dp = prev[0] * dv[0] + prev[1] * dv[1] + prev[2] * dv[2];
        if (dp < gmin) gmin = dp;
        memcpy(prev, dv, sizeof prev);
      }
    { double dp = prev[0] * first[0] + prev[1] * first[1] + prev[2] * first[2]; if (dp < gmin) gmin = dp; }
    rad = acos(dmin > -1.0 ? dmin : -1.0) + acos(gmin < 1.0 ? gmin : 1.0) + 1e-4;
    cr = cos(rad); sr = sin(rad);
    for (a = 0; a < ku; ++a) acol[a] = el_envlight__col_maxcos(c, gcol + 5 * (size_t)a);
    for (b = 0, k = 0; b < kv; ++b)
      for (a = 0; a < ku; ++a, ++k) {
        double mc, bound;
#if EL_ENVLIGHT__SSE
        if (a + 1 < ku && rad < EL_ENVLIGHT__PI) { /* two cells at once: the scalar code's operations, in its order */
          const double *ct = grow + 4 * (size_t)b;
          __m128d A = _mm_loadu_pd(acol + a), B = _mm_set1_pd(c[2]), zero = _mm_setzero_pd();
          __m128d c0 = _mm_set1_pd(ct[0]), s0 = _mm_set1_pd(ct[1]), c1 = _mm_set1_pd(ct[2]), s1 = _mm_set1_pd(ct[3]);
          __m128d f0 = _mm_add_pd(_mm_mul_pd(A, s0), _mm_mul_pd(B, c0)), f1 = _mm_add_pd(_mm_mul_pd(A, s1), _mm_mul_pd(B, c1));
          __m128d best = _mm_max_pd(f0, f1); /* f0 > f1 ? f0 : f1 (equal: f1) */
          __m128d in = _mm_and_pd(_mm_cmpgt_pd(_mm_sub_pd(_mm_mul_pd(A, c0), _mm_mul_pd(B, s0)), zero),
                                  _mm_cmplt_pd(_mm_sub_pd(_mm_mul_pd(A, c1), _mm_mul_pd(B, s1)), zero));
          __m128d peak = _mm_sqrt_pd(_mm_add_pd(_mm_mul_pd(A, A), _mm_mul_pd(B, B)));
          __m128d mv = _mm_or_pd(_mm_and_pd(in, peak), _mm_andnot_pd(in, best));
          __m128d sa = _mm_max_pd(_mm_sub_pd(_mm_set1_pd(1.0), _mm_mul_pd(mv, mv)), zero); /* sa > 0 ? sa : 0 */
          __m128d bb = _mm_max_pd(_mm_add_pd(_mm_mul_pd(mv, _mm_set1_pd(cr)), _mm_mul_pd(_mm_sqrt_pd(sa), _mm_set1_pd(sr))), zero);
          __m128d one = _mm_cmpge_pd(mv, _mm_set1_pd(cr));
          __m128d bnd = _mm_or_pd(_mm_and_pd(one, _mm_set1_pd(1.0)), _mm_andnot_pd(one, bb));
          _mm_storeu_pd(wgt + k, _mm_mul_pd(_mm_loadu_pd(W->mass + k), bnd)); /* a mass of 0 gives 0, as the skip */
          ++a; ++k;
          continue;
        }
#endif
        if (!(W->mass[k] > 0.0)) { wgt[k] = 0.0; continue; } /* no mass: no bound needed */
        mc = el_envlight__row_maxcos(acol[a], c[2], grow + 4 * (size_t)b);
        if (rad >= EL_ENVLIGHT__PI) bound = 1.0;
        else if (mc >= cr) bound = 1.0;
        else { /* cos(angle - rad) = mc cos(rad) + sin(angle) sin(rad) */
          double sa = 1.0 - mc * mc;
          bound = mc * cr + sqrt(sa > 0.0 ? sa : 0.0) * sr;
          bound = bound > 0.0 ? bound : 0.0;
        }
        wgt[k] = W->mass[k] * bound;
      }
    W->cos_off[bin] = (uint32_t)used;
    used += el_envlight__cell_table_sparse(W, wgt, W->cos_tab + used, tmp, wgt + K);
    used += used & 1; /* each table starts at an even entry (its offsets are 4-byte words) */
  }
  { uint16_t *t = (uint16_t *)EL_REALLOC(W->cos_tab, (used > 0 ? used : 1) * sizeof(uint16_t)); if (t) W->cos_tab = t; }
  W->cos_bytes = used * sizeof(uint16_t) + (size_t)m * (size_t)m * sizeof(uint32_t);
  EL_FREE(geo); EL_FREE(wgt); EL_FREE(tmp);
  return EL_SUCCESS;
}

/* >> product sampling over patches (issue 20)
 * The density is the one before (the cells' P(cell | n) from the normal tables, then inside the cell the
 * bilinear interpolant of the vertex values V = lum x sin(theta), normalised), sampled more cheaply: the
 * cell's patch row and the patch in it are picked from small integer CDFs (each patch with mass gets a
 * unit, so none is unreachable at any dynamic range), then the point inside the patch from the bilinear
 * itself (two linear inversions). The density of a patch is its integer share times bil(s, t) / mean(V of
 * its corners): the bilinear interpolant up to the units' rounding. pdf_li_cos reads the same widths, so
 * the sample's pdf is pdf_li_cos's (computed by the same function from the same light-space direction).
 * Maps over EL_ENVLIGHT__PROD_MAX_W x _H use a coarse vertex grid of that size: each coarse vertex holds
 * the largest lum over the fine texels of its 3 x 3 coarse bins (times its own sin), so the density is > 0
 * wherever le() is (a texel reaches 1 texel around it, and every point of a coarse patch is within one
 * coarse step of a corner). The tables stay below a fixed size whatever the map. */
#define EL_ENVLIGHT__PROD_MAX_W 2048
#define EL_ENVLIGHT__PROD_MAX_H 1024
#define EL_ENVLIGHT__PATCH_UNITS 32768u

/* t in [0, 1] with int_0^t ((1 - x) a + x b) dx = q (a + b) / 2, in float (as el_envlight__lin_inv) */
static inline float el_envlight__lin_invf(float a, float b, float q) {
  float m = a > b ? a : b, d, den, t;
  if (!(m > 0.0f)) return q;
  a /= m; b /= m;
  d = a * a + q * (b * b - a * a);
  den = a + el_envlight__sqrt(d > 0.0f ? d : 0.0f);
  t = den > 0.0f ? q * (a + b) / den : 0.0f;
  return t < 1.0f ? (t > 0.0f ? t : 0.0f) : 1.0f;
}

/* bfloat16 (the upper 16 bits of a float) of v >= 0, rounded up (a positive value stays positive; the
 * largest finite bfloat16 for values beyond it), and back */
static uint16_t el_envlight__bf16_up(float v) {
  uint32_t b;
  memcpy(&b, &v, sizeof b);
  if (b & 0xffffu) b += 0x10000u;
  b >>= 16;
  return (uint16_t)(b >= 0x7f80u ? 0x7f7fu : b);
}
static inline float el_envlight__bf16(uint16_t h) {
  uint32_t b = (uint32_t)h << 16;
  float v;
  memcpy(&v, &b, sizeof v);
  return v;
}

/* <<Build the product tables>>: vertex grid, cells, patch CDFs, cell masses, plain and normal tables. */
static EL_ENVLIGHT__NOINLINE el_result el_envlight__prod_build(const el_envlight *l, int ku, int kv, int m, struct el_envlight__warp **out) {
  struct el_envlight__warp *W;
  int w = l->width, h = l->height, gw, gh, i, j, a, b, r, k;
  double *wgt = NULL, *rs = NULL, total = 0.0;
  float *bins = NULL, *rowmax = NULL;
  uint32_t *tmp = NULL;
  size_t nv, np, nr, big, kk;
  el_result res;
  *out = NULL;
  W = (struct el_envlight__warp *)EL_MALLOC(sizeof *W);
  if (!W) return EL_ERROR_OUT_OF_MEMORY;
  memset(W, 0, sizeof *W);
  gw = w < EL_ENVLIGHT__PROD_MAX_W ? w : EL_ENVLIGHT__PROD_MAX_W;
  gh = h < EL_ENVLIGHT__PROD_MAX_H ? h : EL_ENVLIGHT__PROD_MAX_H;
  W->coarse = gw != w || gh != h;
  ku = ku < gw ? ku : gw;
  kv = kv < gh + 1 ? kv : gh + 1;
  W->w = gw; W->h = gh; W->ku = ku; W->kv = kv;
  W->marg_len = kv + 1;
  W->row_len = ku + 1;
  W->table_len = (size_t)W->marg_len + (size_t)kv * (size_t)W->row_len;
  W->cond_stride = (size_t)gw + (size_t)ku;
  W->inv_w = 1.0f / (float)gw; W->inv_h = 1.0f / (float)gh; W->half_inv_h = 0.5f / (float)gh;
  W->dens_k = (float)(8.673617379884035e-19 * (double)gw * (double)gh / (2.0 * EL_ENVLIGHT__PI * EL_ENVLIGHT__PI)); /* 2^-60 */
  nv = ((size_t)gh + 2) * (size_t)gw;
  np = ((size_t)gh + 1) * W->cond_stride;
  nr = (size_t)ku * ((size_t)gh + 1 + (size_t)kv);
  big = (size_t)(gw > gh + 1 ? gw : gh + 1);
  W->sin_row = (float *)EL_MALLOC((size_t)gh * sizeof(float));
  W->V = (float *)EL_MALLOC(nv * sizeof(float));
  W->coff = (int *)EL_MALLOC((size_t)ku * sizeof(int));
  W->pcol = (uint16_t *)EL_MALLOC(np * sizeof(uint16_t));
  W->prow = (uint16_t *)EL_MALLOC(nr * sizeof(uint16_t));
  W->a0 = (int *)EL_MALLOC(((size_t)ku + 1) * sizeof(int));
  W->b0 = (int *)EL_MALLOC(((size_t)kv + 1) * sizeof(int));
  W->cu_of = (int *)EL_MALLOC((size_t)gw * sizeof(int));
  W->cv_of = (int *)EL_MALLOC(((size_t)gh + 1) * sizeof(int));
  W->mass = (double *)EL_MALLOC((size_t)ku * (size_t)kv * sizeof(double));
  wgt = (double *)EL_MALLOC((big + (size_t)ku * (size_t)kv) * sizeof(double));
  rs = (double *)EL_MALLOC(((size_t)gh + 1) * (size_t)ku * sizeof(double));
  tmp = (uint32_t *)EL_MALLOC((big + (size_t)ku + (size_t)kv + 2) * sizeof(uint32_t));
  if (W->coarse) {
    bins = (float *)EL_MALLOC((size_t)gh * (size_t)gw * sizeof(float));
    rowmax = (float *)EL_MALLOC((size_t)gw * sizeof(float));
  }
  if (!W->sin_row || !W->V || !W->coff || !W->pcol || !W->prow || !W->a0 || !W->b0 || !W->cu_of || !W->cv_of || !W->mass ||
      !wgt || !rs || !tmp || (W->coarse && (!bins || !rowmax))) {
    res = EL_ERROR_OUT_OF_MEMORY;
    goto fail;
  }
  for (a = 0; a <= ku; ++a) W->a0[a] = (int)((int64_t)a * gw / ku);
  for (b = 0; b <= kv; ++b) W->b0[b] = (int)((int64_t)b * (gh + 1) / kv);
  for (a = 0; a < ku; ++a) for (i = W->a0[a]; i < W->a0[a + 1]; ++i) W->cu_of[i] = a;
  for (a = 0; a < ku; ++a) W->coff[a] = W->a0[a] + a;
  for (b = 0; b < kv; ++b) for (r = W->b0[b]; r < W->b0[b + 1]; ++r) W->cv_of[r] = b;
  for (j = 0; j < gh; ++j) W->sin_row[j] = (float)sin(EL_ENVLIGHT__PI * (j + 0.5) / gh);
  /* <<Initialize compensated PDF>> (pbrt-v4), as the warp: the mean luminance subtracted, clamped at 0 */
  if (l->compensated) {
    double mean = (0.212671 * l->integral[0] + 0.715160 * l->integral[1] + 0.072169 * l->integral[2]) / (4.0 * EL_ENVLIGHT__PI);
    int any = 0, x, y;
    W->offset = mean < (double)FLT_MAX ? (float)mean : FLT_MAX;
    for (y = 0; y < h && !any; ++y)
      for (x = 0; x < w; ++x) {
        float v = el_envlight__luminance(l->texels + ((size_t)y * (size_t)w + (size_t)x) * 3);
        if ((v < FLT_MAX ? v : FLT_MAX) > W->offset) { any = 1; break; }
      }
    if (!any) { W->offset = 0.0f; W->fell_back = 1; }
  }
  for (i = 0; i < gw; ++i) W->V[i] = W->V[((size_t)gh + 1) * (size_t)gw + (size_t)i] = 0.0f;
  if (!W->coarse) {
    for (j = 0; j < gh; ++j)
      for (i = 0; i < gw; ++i) W->V[((size_t)j + 1) * (size_t)gw + (size_t)i] = el_envlight__vertex_of(l, W, i, j);
  } else {
    /* bins[jb][ib]: the largest lum (less the offset) over the fine texels whose centres fall in coarse
     * bin (ib, jb); then each coarse vertex takes the largest of its 3 x 3 bins (wrapping in u) */
    int x, y;
    for (k = 0; k < gh * gw; ++k) bins[k] = 0.0f;
    for (y = 0; y < h; ++y) {
      int jb = (int)(((int64_t)2 * y + 1) * gh / (2 * (int64_t)h));
      float *br = bins + (size_t)jb * (size_t)gw;
      for (x = 0; x < w; ++x) {
        int ib = (int)(((int64_t)2 * x + 1) * gw / (2 * (int64_t)w));
        float v = el_envlight__luminance(l->texels + ((size_t)y * (size_t)w + (size_t)x) * 3);
        v = v < FLT_MAX ? v : FLT_MAX;
        v = v > W->offset ? v - W->offset : 0.0f;
        if (v > br[ib]) br[ib] = v;
      }
    }
    for (j = 0; j < gh; ++j) {
      for (i = 0; i < gw; ++i) {
        float v = 0.0f;
        for (k = j - 1; k <= j + 1; ++k)
          if (k >= 0 && k < gh && bins[(size_t)k * (size_t)gw + (size_t)i] > v) v = bins[(size_t)k * (size_t)gw + (size_t)i];
        rowmax[i] = v;
      }
      for (i = 0; i < gw; ++i) {
        float v = rowmax[i], vl = rowmax[i > 0 ? i - 1 : gw - 1], vr = rowmax[i + 1 < gw ? i + 1 : 0];
        v = v > vl ? v : vl;
        v = v > vr ? v : vr;
        W->V[((size_t)j + 1) * (size_t)gw + (size_t)i] = v * W->sin_row[j];
      }
    }
  }
  /* the vertex values as the queries read them: bfloat16, rounded up */
  W->V16 = (uint16_t *)EL_MALLOC(nv * sizeof(uint16_t));
  if (!W->V16) { res = EL_ERROR_OUT_OF_MEMORY; goto fail; }
  for (kk = 0; kk < nv; ++kk) { W->V16[kk] = el_envlight__bf16_up(W->V[kk]); W->V[kk] = el_envlight__bf16(W->V16[kk]); }
  /* patch (i, r): corners V[r][i], V[r][i+1], V[r+1][i], V[r+1][i+1]; mass = their mean x dv (dv 1 / gh, half
   * at the pole rows; du = 1 / gw is common). pcol: each cell column's patches per patch row. */
  for (r = 0; r <= gh; ++r) {
    const float *v0 = W->V + (size_t)r * (size_t)gw, *v1 = v0 + gw;
    double dv = (r == 0 || r == gh) ? 0.5 : 1.0;
    for (a = 0; a < ku; ++a) {
      int n = W->a0[a + 1] - W->a0[a];
      uint16_t *c = W->pcol + (size_t)r * W->cond_stride + (size_t)W->coff[a];
      double s = 0.0;
      for (k = 0; k < n; ++k) {
        int i0 = W->a0[a] + k, i1 = i0 + 1 < gw ? i0 + 1 : 0;
        wgt[k] = (double)v0[i0] + (double)v0[i1] + (double)v1[i0] + (double)v1[i1];
        s += wgt[k];
      }
      rs[(size_t)r * (size_t)ku + (size_t)a] = 0.25 * s * dv;
      el_envlight__int_cdf(wgt, n, EL_ENVLIGHT__PATCH_UNITS, tmp);
      for (k = 0; k <= n; ++k) c[k] = (uint16_t)tmp[k];
    }
  }
  /* prow: each cell's CDF over its patch rows; the cells' masses */
  for (a = 0; a < ku; ++a)
    for (b = 0; b < kv; ++b) {
      int n = W->b0[b + 1] - W->b0[b];
      uint16_t *c = W->prow + (size_t)a * ((size_t)gh + 1 + (size_t)kv) + (size_t)W->b0[b] + (size_t)b;
      double s = 0.0;
      for (k = 0; k < n; ++k) { wgt[k] = rs[(size_t)(W->b0[b] + k) * (size_t)ku + (size_t)a]; s += wgt[k]; }
      el_envlight__int_cdf(wgt, n, EL_ENVLIGHT__PATCH_UNITS, tmp);
      for (k = 0; k <= n; ++k) c[k] = (uint16_t)tmp[k];
      W->mass[(size_t)b * (size_t)ku + (size_t)a] = s;
      total += s;
    }
  W->all_zero = !(total > 0.0);
  if (gw / ku + 1 <= 256 && (gh + 1) / kv + 1 <= 256) { /* guide tables (uint8 entries): cells up to 256 patches a side */
    W->gcol = (uint8_t *)EL_MALLOC(((size_t)gh + 1) * (size_t)ku * EL_ENVLIGHT__GUIDE_K);
    W->grow = (uint8_t *)EL_MALLOC((size_t)ku * (size_t)kv * EL_ENVLIGHT__GUIDE_K);
    if (!W->gcol || !W->grow) { EL_FREE(W->gcol); EL_FREE(W->grow); W->gcol = NULL; W->grow = NULL; }
    else {
      for (r = 0; r <= gh; ++r)
        for (a = 0; a < ku; ++a)
          el_envlight__guide_build(W->pcol + (size_t)r * W->cond_stride + (size_t)W->coff[a], W->a0[a + 1] - W->a0[a],
                                   W->gcol + ((size_t)r * (size_t)ku + (size_t)a) * EL_ENVLIGHT__GUIDE_K);
      for (a = 0; a < ku; ++a)
        for (b = 0; b < kv; ++b)
          el_envlight__guide_build(W->prow + (size_t)a * ((size_t)gh + 1 + (size_t)kv) + (size_t)W->b0[b] + (size_t)b, W->b0[b + 1] - W->b0[b],
                                   W->grow + ((size_t)a * (size_t)kv + (size_t)b) * EL_ENVLIGHT__GUIDE_K);
    }
  }
  EL_FREE(wgt); EL_FREE(rs); EL_FREE(tmp); EL_FREE(bins); EL_FREE(rowmax);
  wgt = NULL; rs = NULL; tmp = NULL; bins = NULL; rowmax = NULL;
  EL_FREE(W->V); W->V = NULL; /* the queries read V16 */
  res = el_envlight__cos_build(W, m);
  if (res != EL_SUCCESS) goto fail;
  EL_FREE(W->mass); W->mass = NULL; /* only the build needs the cells' masses (and no plain table) */
  W->warp_bytes = sizeof *W + (size_t)gh * sizeof(float) + nv * sizeof(uint16_t) + (size_t)ku * sizeof(int) + np * sizeof(uint16_t) +
                  nr * sizeof(uint16_t) + ((size_t)ku + (size_t)kv + 2 + (size_t)gw + (size_t)gh + 1) * sizeof(int) +
                  (W->gcol ? ((size_t)gh + 1 + (size_t)kv) * (size_t)ku * EL_ENVLIGHT__GUIDE_K : 0);
  *out = W;
  return EL_SUCCESS;
fail:
  EL_FREE(wgt); EL_FREE(rs); EL_FREE(tmp); EL_FREE(bins); EL_FREE(rowmax);
  el_envlight__warp_free(W);
  return res;
}

/* The product tables' once-scheme (cos_state; the same scheme as the sampling tables). NULL: failed.
 * The built case is inlined into the queries (el_envlight__prod_ensure); the build stays out of line. */
static EL_ENVLIGHT__NOINLINE const struct el_envlight__warp *el_envlight__prod_ensure_slow(const el_envlight *cl, int ku, int kv, int m) {
  el_envlight *l = (el_envlight *)cl;
#if EL_ENVLIGHT__ATOMICS
  int expected = 0;
  if (__atomic_compare_exchange_n(&l->cos_state, &expected, 1, 0, __ATOMIC_ACQ_REL, __ATOMIC_ACQUIRE)) {
    struct el_envlight__warp *W = NULL;
    el_result r = el_envlight__prod_build(l, ku, kv, m, &W);
    l->prod = W;
    l->cos_result = r;
    __atomic_store_n(&l->cos_state, r == EL_SUCCESS ? 2 : 3, __ATOMIC_RELEASE);
  } else {
    while (__atomic_load_n(&l->cos_state, __ATOMIC_ACQUIRE) == 1) { /* another thread builds */ }
  }
  return __atomic_load_n(&l->cos_state, __ATOMIC_ACQUIRE) == 2 ? l->prod : NULL;
#else
  if (l->cos_state == 0) {
    struct el_envlight__warp *W = NULL;
    l->cos_result = el_envlight__prod_build(l, ku, kv, m, &W);
    l->prod = W;
    l->cos_state = l->cos_result == EL_SUCCESS ? 2 : 3;
  }
  return l->cos_state == 2 ? l->prod : NULL;
#endif
}
static inline const struct el_envlight__warp *el_envlight__prod_ensure(const el_envlight *l, int ku, int kv, int m) {
#if EL_ENVLIGHT__ATOMICS
  if (__atomic_load_n(&l->cos_state, __ATOMIC_ACQUIRE) == 2) return l->prod;
#else
  if (l->cos_state == 2) return l->prod;
#endif
  return el_envlight__prod_ensure_slow(l, ku, kv, m);
}

/* The cell table for world normal n (its octahedral bin's), or NULL for a zero, NaN or infinite n. A
 * huge or tiny n is scaled in world space first, so the bin depends only on n's direction. */
static inline const uint16_t *el_envlight__prod_table(const el_envlight *l, const struct el_envlight__warp *W, const float n[3]) {
  float nl[3], s, x, y;
  int i, j, mm = W->m;
  s = fabsf(n[0]) + fabsf(n[1]) + fabsf(n[2]);
  if (!(s >= 1e-18f && s <= 1e18f)) {
    if (!el_envlight__to_light_rescaled(l, n, nl)) return NULL;
  } else el_envlight__to_light(l, n, nl);
  el_envlight__oct_encode(nl, &x, &y);
  i = (int)(x * (float)mm); j = (int)(y * (float)mm);
  i = i < mm - 1 ? (i > 0 ? i : 0) : mm - 1;
  j = j < mm - 1 ? (j > 0 ? j : 0) : mm - 1;
  return W->cos_tab + W->cos_off[(size_t)j * (size_t)mm + (size_t)i];
}

/* The corners V[r][i], V[r][i + 1], V[r + 1][i], V[r + 1][i + 1] of patch (i, r) (bfloat16: issue 20, half
 * the memory of floats; the tables were built from the same rounded values). */
static inline void el_envlight__prod_corners(const struct el_envlight__warp *W, int i, int r, float c[4]) {
  int gw = W->w, i1 = i + 1 < gw ? i + 1 : 0;
  const uint16_t *V = W->V16 + (size_t)r * (size_t)gw;
  c[0] = el_envlight__bf16(V[i]); c[1] = el_envlight__bf16(V[i1]);
  c[2] = el_envlight__bf16(V[(size_t)gw + (size_t)i]); c[3] = el_envlight__bf16(V[(size_t)gw + (size_t)i1]);
}

/* Where the pdf finds a light-space direction (any length): le()'s (u, v), the patch (column i, vertex
 * row r), s in it, Y = v gh + 0.5, vp, sin theta's r (rr) and the squared length. 0: a zero or NaN d. */
typedef struct el_envlight__ploc { float u, v, vp, rr, len2, s, Y; int i, r; } el_envlight__ploc;
static inline int el_envlight__prod_locate(const struct el_envlight__warp *W, const float dir[3], el_envlight__ploc *q) {
  float dd[3], r2, len2, X, Y, s;
  int gw = W->w, gh = W->h, i, r;
  dd[0] = dir[0]; dd[1] = dir[1]; dd[2] = dir[2];
  r2 = dd[0] * dd[0] + dd[1] * dd[1];
  len2 = r2 + dd[2] * dd[2];
  if (!(len2 >= FLT_MIN && len2 <= FLT_MAX)) {
    if (!el_envlight__rescale(dd)) return 0;
    r2 = dd[0] * dd[0] + dd[1] * dd[1];
    len2 = r2 + dd[2] * dd[2];
  }
  q->len2 = len2;
  q->rr = el_envlight__sqrt(r2);
  q->u = el_envlight__phi_turns(dd[1], dd[0]);
  el_envlight__theta_vp(q->rr, dd[2], &q->v, &q->vp);
  X = q->u * (float)gw - 0.5f;
  if (X < 0.0f) X += (float)gw;
  i = (int)X;
  if (i > gw - 1) i = gw - 1;
  s = X - (float)i;
  q->s = s < 1.0f ? (s > 0.0f ? s : 0.0f) : 1.0f;
  Y = q->v * (float)gh + 0.5f;
  r = (int)Y;
  if (r > gh) r = gh;
  q->Y = Y; q->i = i; q->r = r;
  return 1;
}

/* The density at a located point of patch (q->i, q->r) whose cell has integer width wc (cell row x cell)
 * and patch width wr (patch row x patch): P / (mean(corners) du dv 2 pi^2) x bil(s, t) / sin(theta).
 * The sampler calls it with the widths it picked from, the pdf with the widths it reads: the same bits. */
static inline float el_envlight__prod_eval(const struct el_envlight__warp *W, const el_envlight__ploc *q, uint32_t wc, uint32_t wr, const float c[4]) {
  int gh = W->h, r = q->r;
  float v00 = c[0], v01 = c[1], v10 = c[2], v11 = c[3], s = q->s, t;
  float sum = (v00 + v01) + (v10 + v11), e0 = v00 + s * (v01 - v00), e1 = v10 + s * (v11 - v10), len, p;
  p = (float)wc * (float)wr * W->dens_k * 4.0f / sum; /* P / (mean du dv 2 pi^2) */
  len = el_envlight__sqrt(q->len2);
  /* bil / sin(theta). In the pole rows one edge is 0 and t = 2 gh vp (or 1 - t), dv halves: bil / sin =
   * 2 gh e (vp / sin theta) x 2, with vp / sin -> 1 / pi at the pole itself */
  if (r == 0 || r == gh) {
    float ratio = q->rr > 0.0f ? q->vp * len / q->rr : 0.318309886f;
    p *= 4.0f * (float)gh * (r == 0 ? e1 : e0) * ratio;
  } else {
    t = q->Y - (float)r;
    t = t < 1.0f ? (t > 0.0f ? t : 0.0f) : 1.0f;
    p *= (e0 + t * (e1 - e0)) * len / q->rr;
  }
  return p < FLT_MAX ? p : FLT_MAX;
}

#if defined(__GNUC__) || defined(__clang__)
#define EL_ENVLIGHT__PROD_INLINE inline __attribute__((always_inline)) /* into the single and the batched calls */
#else
#define EL_ENVLIGHT__PROD_INLINE inline
#endif
/* The integer widths the pdf reads for patch (i, r) under cell table tab: the cell's (cell row x cell)
 * and the patch's (patch row x patch). Returns 0 when either is 0 (no density there). */
static EL_ENVLIGHT__PROD_INLINE int el_envlight__prod_widths(const struct el_envlight__warp *W, const uint16_t *tab, int i, int r, uint32_t *wc, uint32_t *wr) {
  int a = W->cu_of[i], b = W->cv_of[r], k;
  const uint16_t *row = el_envlight__sparse_row(W, tab, b), *pc, *pr;
  k = a - (int)row[0]; /* the cell's place in its row's span */
  k += k < 0 ? W->ku : 0;
  *wc = k < (int)row[1] ? (uint32_t)(tab[b + 1] - tab[b]) * (uint32_t)(row[k + 3] - row[k + 2]) : 0u;
  pc = W->pcol + (size_t)r * W->cond_stride + (size_t)W->coff[a] + (size_t)(i - W->a0[a]);
  pr = W->prow + (size_t)a * ((size_t)W->h + 1 + (size_t)W->kv) + (size_t)r + (size_t)b;
  *wr = (uint32_t)(pc[1] - pc[0]) * (uint32_t)(pr[1] - pr[0]);
  return *wc != 0 && *wr != 0;
}

/* <<Compute PDF>> of product sampling at a light-space direction d (any length) for cell table tab:
 * P(cell) P(patch row | cell) P(patch | row) bil(s, t) / mean(corners) / (du dv 2 pi^2 sin theta). uv (may
 * be NULL) gets the (u, v) at which le() looks d up. */
static float el_envlight__prod_pdf_light(const struct el_envlight__warp *W, const uint16_t *tab, const float dir[3], float *uv) {
  el_envlight__ploc q;
  float c[4];
  uint32_t wc, wr;
  if (uv) uv[0] = uv[1] = 0.0f;
  if (!el_envlight__prod_locate(W, dir, &q)) return 0.0f;
  if (uv) { uv[0] = q.u; uv[1] = q.v; }
  if (!el_envlight__prod_widths(W, tab, q.i, q.r, &wc, &wr)) return 0.0f;
  el_envlight__prod_corners(W, q.i, q.r, c);
  return el_envlight__prod_eval(W, &q, wc, wr, c);
}

/* <<Pick a cell>>, then its patch row and the patch for u, in four stages (each ends at the next table
 * it reads, P->p, so that the batched call can start those reads for several samples before it needs
 * them): the patch (P->i, P->r), the fractions P->q (of the patch row's units) and P->s (of the
 * patch's), the cell's integer width P->wc and the patch's P->wr (as the pdf reads them). */
typedef struct el_envlight__pick { const uint16_t *p; float x0, f0, f1, q, s; int a, b, r, i; uint32_t wc, wr; } el_envlight__pick;
/* 1: the cell row b, from the table's rows CDF; P->p: the row's span [a_s, L, CDF] */
static EL_ENVLIGHT__PROD_INLINE void el_envlight__pick1(const struct el_envlight__warp *W, const uint16_t *tab, const float uu[2], el_envlight__pick *P) {
  float x1 = el_envlight__clamp01(uu[1]) * (float)EL_ENVLIGHT__CELL_UNITS;
  int b;
  P->x0 = el_envlight__clamp01(uu[0]) * (float)EL_ENVLIGHT__CELL_UNITS;
  b = el_envlight__search_guided(tab, W->kv, (const uint8_t *)(tab + (size_t)((W->kv + 2) & ~1) + 2 * (size_t)W->kv), (uint32_t)x1);
  P->f1 = (x1 - (float)tab[b]) / (float)(tab[b + 1] - tab[b]);
  P->wc = (uint32_t)(tab[b + 1] - tab[b]);
  P->p = el_envlight__sparse_row(W, tab, b);
  P->b = b;
}
/* 2: a cell a of the row's span; P->p: the cell's CDF over its patch rows */
static EL_ENVLIGHT__PROD_INLINE void el_envlight__pick2(const struct el_envlight__warp *W, el_envlight__pick *P) {
  const uint16_t *row = P->p, *cc = row + 2;
  int a = el_envlight__search_guided(cc, (int)row[1], (const uint8_t *)(row - EL_ENVLIGHT__GUIDE_E), (uint32_t)P->x0), b = P->b;
  P->f0 = (P->x0 - (float)cc[a]) / (float)(cc[a + 1] - cc[a]);
  P->wc *= (uint32_t)(cc[a + 1] - cc[a]);
  a += (int)row[0];
  a -= a >= W->ku ? W->ku : 0;
  P->a = a;
  P->p = W->prow + (size_t)a * ((size_t)W->h + 1 + (size_t)W->kv) + (size_t)W->b0[b] + (size_t)b;
}
/* 3: the patch row r, with f1; P->p: the row's CDF over the cell column */
static EL_ENVLIGHT__PROD_INLINE void el_envlight__pick3(const struct el_envlight__warp *W, el_envlight__pick *P) {
  const uint16_t *pr = P->p;
  int a = P->a, n = W->b0[P->b + 1] - W->b0[P->b], r;
  float x = el_envlight__clamp01(P->f1) * (float)EL_ENVLIGHT__PATCH_UNITS;
  r = W->grow ? el_envlight__search_guided(pr, n, W->grow + ((size_t)a * (size_t)W->kv + (size_t)P->b) * EL_ENVLIGHT__GUIDE_K, (uint32_t)x)
              : el_envlight__search16(pr, n, (uint32_t)x);
  P->q = (x - (float)pr[r]) / (float)(pr[r + 1] - pr[r]);
  P->wr = (uint32_t)(pr[r + 1] - pr[r]);
  r += W->b0[P->b];
  P->r = r;
  P->p = W->pcol + (size_t)r * W->cond_stride + (size_t)W->coff[a];
}
/* 4: the patch i, with f0 */
static EL_ENVLIGHT__PROD_INLINE void el_envlight__pick4(const struct el_envlight__warp *W, el_envlight__pick *P) {
  const uint16_t *pc = P->p;
  int a = P->a, n = W->a0[a + 1] - W->a0[a], i;
  float x = el_envlight__clamp01(P->f0) * (float)EL_ENVLIGHT__PATCH_UNITS;
  i = W->gcol ? el_envlight__search_guided(pc, n, W->gcol + ((size_t)P->r * (size_t)W->ku + (size_t)a) * EL_ENVLIGHT__GUIDE_K, (uint32_t)x)
              : el_envlight__search16(pc, n, (uint32_t)x);
  P->s = (x - (float)pc[i]) / (float)(pc[i + 1] - pc[i]);
  P->wr *= (uint32_t)(pc[i + 1] - pc[i]);
  P->i = i + W->a0[a];
}

/* <<Sample the product>>: cell, patch row, patch, then (s, t) from the bilinear; wi and the pdf as
 * pdf_li_cos computes it at wi: the direction located again (the atans), and when it lands in the
 * patch it came from (all but a measure-zero set), the density from the widths already read. */
static EL_ENVLIGHT__PROD_INLINE void el_envlight__prod_sample(const el_envlight *l, const struct el_envlight__warp *W, const uint16_t *tab, const float uu[2], float wi[3], float rgb[3], float *pdf) {
  float d[3], uv[2], q, t, s, u, v, vp, c[4], p;
  int gh = W->h, r, i, n;
  uint32_t wc, wr;
  el_envlight__ploc loc;
  el_envlight__pick P;
  el_envlight__pick1(W, tab, uu, &P);
  el_envlight__pick2(W, &P);
  el_envlight__pick3(W, &P);
  el_envlight__pick4(W, &P);
  i = P.i; r = P.r; q = P.q; s = P.s; wc = P.wc; wr = P.wr;
  /* (s, t) in the patch: t from the marginal (linear), s from the conditional at t (linear) */
  el_envlight__prod_corners(W, i, r, c);
  t = el_envlight__lin_invf(c[0] + c[1], c[2] + c[3], q);
  s = el_envlight__lin_invf(c[0] + t * (c[2] - c[0]), c[1] + t * (c[3] - c[1]), s);
  /* 2^-12 of a patch inside its edges: a q of exactly 0 or 1 (x on a unit) would put the point on the
   * edge, where the pdf may read the neighbour (after a general rotation's round trip, ~1e-7 rad): pdf 0
   * next to a patch without mass. The density there is within 2^-12 of the edge's: no measurable bias */
  t = t > 2.44140625e-4f ? (t < 0.999755859f ? t : 0.999755859f) : 2.44140625e-4f;
  s = s > 2.44140625e-4f ? (s < 0.999755859f ? s : 0.999755859f) : 2.44140625e-4f;
  for (n = 0; n < 2; ++n) {
    /* <<Compute direction>>: u from the patch's left vertex, v and its distance to the nearer pole */
    u = ((float)i + 0.5f + s) * W->inv_w;
    if (u >= 1.0f) u -= 1.0f;
    u = u < 0.99999994f ? u : 0.99999994f;
    if (r == 0) { vp = t * W->half_inv_h; v = vp; }
    else if (r == gh) { vp = (1.0f - t) * W->half_inv_h; v = 1.0f - vp; }
    else { v = ((float)r - 0.5f + t) * W->inv_h; vp = v < 0.5f ? v : 1.0f - v; }
    el_envlight__uvp_to_dir(u, v, vp, d);
    el_envlight__to_world(l, d, wi);
    if (!l->exact_transform) el_envlight__mul_transpose(l->to_world, wi, d); /* as pdf_li_cos brings wi back */
    if (el_envlight__prod_locate(W, d, &loc) && loc.i == i && loc.r == r) { /* the pdf's own path, its reads skipped */
      p = el_envlight__prod_eval(W, &loc, wc, wr, c);
      uv[0] = loc.u; uv[1] = loc.v;
    } else p = el_envlight__prod_pdf_light(W, tab, d, uv);
    if (p > 0.0f) break;
    /* the round trip left the patch for one without mass (near a pole under a general rotation, where
     * 1e-7 of direction is a large step in phi): the patch's centre instead, as issue 24 did */
    s = 0.5f; t = 0.5f;
  }
  *pdf = p;
  if (rgb) {
    if (p > 0.0f) el_envlight__bilerp(l, uv[0], uv[1], rgb); /* le(wi): the same (u, v) */
    else rgb[0] = rgb[1] = rgb[2] = 0.0f;
  }
}

/* The constant light: cosine-weighted hemisphere sampling about n, exactly the product (pdf
 * max(0, n.w) / pi); a zero, NaN or infinite n: sample_li's uniform sphere. */
static float el_envlight__cos_pdf_constant(const el_envlight *l, const float n[3], const float wi[3]) {
  float nn[3], ww[3], ln, lw, c;
  if (!(l->constant[0] > 0.0f || l->constant[1] > 0.0f || l->constant[2] > 0.0f)) return 0.0f;
  nn[0] = n[0]; nn[1] = n[1]; nn[2] = n[2];
  ww[0] = wi[0]; ww[1] = wi[1]; ww[2] = wi[2];
  lw = ww[0] * ww[0] + ww[1] * ww[1] + ww[2] * ww[2]; /* the direction first: an unusable one gives 0 */
  if (!(lw >= FLT_MIN && lw <= FLT_MAX)) {
    if (!el_envlight__rescale(ww)) return 0.0f;
    lw = ww[0] * ww[0] + ww[1] * ww[1] + ww[2] * ww[2];
  }
  ln = nn[0] * nn[0] + nn[1] * nn[1] + nn[2] * nn[2];
  if (!(ln >= FLT_MIN && ln <= FLT_MAX)) {
    if (!el_envlight__rescale(nn)) return 0.0795774715f; /* 1 / 4 pi */
    ln = nn[0] * nn[0] + nn[1] * nn[1] + nn[2] * nn[2];
  }
  c = (nn[0] * ww[0] + nn[1] * ww[1] + nn[2] * ww[2]) / (sqrtf(ln) * sqrtf(lw));
  return c > 0.0f ? c * 0.318309886f : 0.0f;
}
static EL_ENVLIGHT__NOINLINE void el_envlight__cos_sample_constant(const el_envlight *l, const float n[3], const float uu[2], float wi[3], float rgb[3], float *pdf) {
  float nn[3], b1[3], b2[3], ln, a, b, dx, dy, rr, q, z;
  int k;
  nn[0] = n[0]; nn[1] = n[1]; nn[2] = n[2];
  ln = nn[0] * nn[0] + nn[1] * nn[1] + nn[2] * nn[2];
  if (!(ln >= FLT_MIN && ln <= FLT_MAX) && !el_envlight__rescale(nn)) {
    el_envlight_sample_li((el_envlight *)l, uu, wi, rgb, pdf); /* constant: uniform sphere, no tables */
    return;
  }
  ln = sqrtf(nn[0] * nn[0] + nn[1] * nn[1] + nn[2] * nn[2]);
  nn[0] /= ln; nn[1] /= ln; nn[2] /= ln;
  el_envlight__basis(nn, b1, b2);
  /* Shirley-Chiu concentric disk, then up to the hemisphere (Malley) */
  a = 2.0f * el_envlight__clamp01(uu[0]) - 1.0f; b = 2.0f * el_envlight__clamp01(uu[1]) - 1.0f;
  if (a == 0.0f && b == 0.0f) { dx = 0.0f; dy = 0.0f; }
  else if (fabsf(a) > fabsf(b)) { rr = a; q = 0.25f * (b / a); dx = rr * el_envlight__cospi(q); dy = rr * el_envlight__sinpi(q); }
  else { rr = b; q = 0.25f * (a / b); dx = rr * el_envlight__sinpi(q); dy = rr * el_envlight__cospi(q); }
  z = 1.0f - dx * dx - dy * dy;
  z = el_envlight__sqrt(z > 0.0f ? z : 0.0f);
  for (k = 0; k < 3; ++k) wi[k] = dx * b1[k] + dy * b2[k] + z * nn[k];
  *pdf = el_envlight__cos_pdf_constant(l, n, wi);
  if (rgb) for (k = 0; k < 3; ++k) rgb[k] = *pdf > 0.0f ? l->constant[k] : 0.0f;
}

EL_DEF el_result el_envlight_prepare_product(const el_envlight *l, const el_envlight_product_options *opt) {
  int ku = EL_ENVLIGHT__CELLS_U, kv = EL_ENVLIGHT__CELLS_V, m = EL_ENVLIGHT__NORMAL_BINS;
  const struct el_envlight__warp *W;
  if (!l) return EL_ERROR_INVALID_ARGUMENT;
  if (opt) {
    if ((opt->cells_u == 0) != (opt->cells_v == 0) || opt->cells_u < 0 || opt->cells_u > 256 || opt->cells_v < 0 ||
        opt->cells_v > 256 || opt->normal_bins < 0 || opt->normal_bins > 256)
      return EL_ERROR_INVALID_ARGUMENT;
    if (opt->cells_u) { ku = opt->cells_u; kv = opt->cells_v; }
    if (opt->normal_bins) m = opt->normal_bins;
  }
  if (l->width == 0) return EL_SUCCESS; /* the constant light needs no tables */
  if (l->mapping != EL_ENVLIGHT_MAPPING_LATLONG) /* equal-area maps: sample_li's tables (issue 24) */
    return el_envlight__ensure(l) ? EL_SUCCESS : l->sampling_result;
  W = el_envlight__prod_ensure(l, ku, kv, m);
  if (!W) return l->cos_result;
  if (opt && ((opt->cells_u && (W->ku != (ku < W->w ? ku : W->w) || W->kv != (kv < W->h + 1 ? kv : W->h + 1))) ||
              (opt->normal_bins && W->m != m)))
    return EL_ERROR_INVALID_ARGUMENT; /* built before with other sizes */
  return EL_SUCCESS;
}

EL_DEF void el_envlight_sample_li_cos(const el_envlight *l, const float n[3], const float u[2], float wi[3], float rgb[3], float *pdf) {
  const struct el_envlight__warp *W;
  const uint16_t *tab;
  if (l->width == 0) { el_envlight__cos_sample_constant(l, n, u, wi, rgb, pdf); return; }
  if (l->mapping != EL_ENVLIGHT_MAPPING_LATLONG) { el_envlight_sample_li(l, u, wi, rgb, pdf); return; } /* no product tables */
  W = el_envlight__prod_ensure(l, EL_ENVLIGHT__CELLS_U, EL_ENVLIGHT__CELLS_V, EL_ENVLIGHT__NORMAL_BINS);
  tab = W ? el_envlight__prod_table(l, W, n) : NULL;
  if (!tab || W->all_zero || tab[W->kv] == 0) { /* no tables, an unusable n, or nothing emits above it */
    wi[0] = l->to_world[2]; wi[1] = l->to_world[5]; wi[2] = l->to_world[8]; *pdf = 0.0f;
    if (rgb) rgb[0] = rgb[1] = rgb[2] = 0.0f;
    return;
  }
  el_envlight__prod_sample(l, W, tab, u, wi, rgb, pdf);
}

EL_DEF float el_envlight_pdf_li_cos(const el_envlight *l, const float n[3], const float wi[3]) {
  const struct el_envlight__warp *W;
  const uint16_t *tab;
  float d[3];
  if (l->width == 0) return el_envlight__cos_pdf_constant(l, n, wi);
  if (l->mapping != EL_ENVLIGHT_MAPPING_LATLONG) return el_envlight_pdf_li(l, wi); /* sample_li_cos is sample_li there */
  W = el_envlight__prod_ensure(l, EL_ENVLIGHT__CELLS_U, EL_ENVLIGHT__CELLS_V, EL_ENVLIGHT__NORMAL_BINS);
  if (!W || W->all_zero) return 0.0f;
  tab = el_envlight__prod_table(l, W, n);
  if (!tab || tab[W->kv] == 0) return 0.0f;
  if (!el_envlight__to_light_dir(l, wi, d)) return 0.0f; /* rescaled in world space first (issue 24) */
  return el_envlight__prod_pdf_light(W, tab, d, NULL);
}

/* >> product sampling, n at once (issue 20): the single calls' arithmetic on four lanes with SSE2, the
 * table reads (the normal's table, the four searches, the widths, the corners) lane by lane. Every vector
 * step is the scalar step's operations in the scalar code's order (min/max as SSE's MINPS/MAXPS, which
 * are the scalar code's `a < b ? a : b` / `a > b ? a : b`; selects for its branches), so each lane gets
 * the single call's bits. A lane off the common path (a normal or direction that needs rescaling, a
 * sample whose round trip leaves its patch or finds no density) is recomputed by the single call's own
 * code. The plain loop over single calls: without SSE2 (EL_NO_SIMD, other CPUs), with x87 float
 * evaluation, and where a compiler may fuse multiply-adds (FMA code: scalar and vector would fuse
 * differently; measured: clang -march=native fuses the scalar code and not the intrinsics, and 1 batch
 * in 3-4 differs; gcc happened to fuse both alike). */
#if EL_ENVLIGHT__SSE && defined(FLT_EVAL_METHOD) && FLT_EVAL_METHOD == 0 && !defined(__FMA__)
#define EL_ENVLIGHT__COS4 1
#define EL_ENVLIGHT__V(x) _mm_set1_ps(x)
static inline __m128 el_envlight__sel4(__m128 m, __m128 a, __m128 b) { return _mm_or_ps(_mm_and_ps(m, a), _mm_andnot_ps(m, b)); }
static inline __m128 el_envlight__abs4(__m128 x) { return _mm_andnot_ps(_mm_set1_ps(-0.0f), x); }
/* x < 1 ? (x > 0 ? x : 0) : 1 */
static inline __m128 el_envlight__clamp01_4(__m128 x) { return _mm_min_ps(_mm_max_ps(x, _mm_setzero_ps()), EL_ENVLIGHT__V(1.0f)); }
/* integer x > hi ? hi : x (SSE2 has no pminsd) */
static inline __m128i el_envlight__mini4(__m128i x, int hi) {
  __m128i h = _mm_set1_epi32(hi), gt = _mm_cmpgt_epi32(x, h);
  return _mm_or_si128(_mm_and_si128(gt, h), _mm_andnot_si128(gt, x));
}
static inline __m128 el_envlight__sinpi4(__m128 x) { /* el_envlight__sinpi */
  __m128 x2 = _mm_mul_ps(x, x), p = _mm_mul_ps(x2, EL_ENVLIGHT__V(0.0775603462f));
  p = _mm_mul_ps(x2, _mm_add_ps(EL_ENVLIGHT__V(-0.598242108f), p));
  p = _mm_mul_ps(x2, _mm_add_ps(EL_ENVLIGHT__V(2.55006972f), p));
  p = _mm_mul_ps(x2, _mm_add_ps(EL_ENVLIGHT__V(-5.16770968f), p));
  return _mm_mul_ps(x, _mm_add_ps(EL_ENVLIGHT__V(3.14159264f), p));
}
static inline __m128 el_envlight__cospi4(__m128 x) { /* el_envlight__cospi */
  __m128 x2 = _mm_mul_ps(x, x), p = _mm_mul_ps(x2, EL_ENVLIGHT__V(-0.0244206859f));
  p = _mm_mul_ps(x2, _mm_add_ps(EL_ENVLIGHT__V(0.234953918f), p));
  p = _mm_mul_ps(x2, _mm_add_ps(EL_ENVLIGHT__V(-1.33521610f), p));
  p = _mm_mul_ps(x2, _mm_add_ps(EL_ENVLIGHT__V(4.05870960f), p));
  p = _mm_mul_ps(x2, _mm_add_ps(EL_ENVLIGHT__V(-4.93480216f), p));
  return _mm_add_ps(EL_ENVLIGHT__V(1.0f), p);
}
/* el_envlight__atan01 of mn / max(mx, FLT_MIN) */
static inline __m128 el_envlight__atan_ratio4(__m128 mn, __m128 mx) {
  __m128 t = _mm_div_ps(mn, _mm_max_ps(mx, EL_ENVLIGHT__V(FLT_MIN))), t2 = _mm_mul_ps(t, t);
  __m128 p = _mm_mul_ps(t2, EL_ENVLIGHT__V(0.00681166904f));
  p = _mm_mul_ps(t2, _mm_add_ps(EL_ENVLIGHT__V(-0.0336038535f), p));
  p = _mm_mul_ps(t2, _mm_add_ps(EL_ENVLIGHT__V(0.0796232593f), p));
  p = _mm_mul_ps(t2, _mm_add_ps(EL_ENVLIGHT__V(-0.132333200f), p));
  p = _mm_mul_ps(t2, _mm_add_ps(EL_ENVLIGHT__V(0.198078099f), p));
  p = _mm_mul_ps(t2, _mm_add_ps(EL_ENVLIGHT__V(-0.333173674f), p));
  return _mm_mul_ps(t, _mm_add_ps(EL_ENVLIGHT__V(0.999996111f), p));
}
/* to world space (el_envlight__to_world) or, with back = 1, to light space (el_envlight__to_light):
 * x[3] -> y[3], the same operations in the same order */
static inline void el_envlight__xform4(const el_envlight *l, int back, const __m128 x[3], __m128 y[3]) {
  const float *m = l->to_world, *sg = back ? l->isign : l->sign;
  const int *pm = back ? l->iperm : l->perm;
  const int a = back ? 1 : 3, b = back ? 3 : 1; /* M's row k (to world) or column k (to light) */
  int k;
  if (l->exact_transform)
    for (k = 0; k < 3; ++k) y[k] = _mm_mul_ps(_mm_set1_ps(sg[k]), x[pm[k]]);
  else
    for (k = 0; k < 3; ++k)
      y[k] = _mm_add_ps(_mm_add_ps(_mm_mul_ps(_mm_set1_ps(m[a * k]), x[0]), _mm_mul_ps(_mm_set1_ps(m[a * k + b]), x[1])), _mm_mul_ps(_mm_set1_ps(m[a * k + 2 * b]), x[2]));
}
/* three rows of four floats <-> four points of three (AoS, p[3 k + c]); lanes >= m are padded with lane 0 */
static inline void el_envlight__load3x4(const float *p, int m, __m128 x[3]) {
  float t[12];
  int k, c;
  if (m == 4) { /* a0 = x0 y0 z0 x1, a1 = y1 z1 x2 y2, a2 = z2 x3 y3 z3 */
    __m128 a0 = _mm_loadu_ps(p), a1 = _mm_loadu_ps(p + 4), a2 = _mm_loadu_ps(p + 8);
    __m128 b = _mm_shuffle_ps(a1, a2, _MM_SHUFFLE(1, 0, 3, 2));  /* x2 y2 z2 x3 */
    __m128 e = _mm_shuffle_ps(a0, a1, _MM_SHUFFLE(1, 0, 2, 1));  /* y0 z0 y1 z1 */
    __m128 d = _mm_shuffle_ps(a1, a2, _MM_SHUFFLE(3, 2, 3, 3));  /* y2 y2 y3 z3 */
    x[0] = _mm_shuffle_ps(a0, b, _MM_SHUFFLE(3, 0, 3, 0));
    x[1] = _mm_shuffle_ps(e, d, _MM_SHUFFLE(2, 0, 2, 0));
    x[2] = _mm_shuffle_ps(e, _mm_shuffle_ps(b, d, _MM_SHUFFLE(3, 3, 2, 2)), _MM_SHUFFLE(2, 0, 3, 1));
    return;
  }
  for (k = 0; k < 4; ++k)
    for (c = 0; c < 3; ++c) t[4 * c + k] = p[3 * (k < m ? k : 0) + c];
  x[0] = _mm_loadu_ps(t); x[1] = _mm_loadu_ps(t + 4); x[2] = _mm_loadu_ps(t + 8);
}
/* Where the pdf finds four light-space directions (el_envlight__prod_locate, its common path): lanes
 * whose squared length is not a normal float are 0 in the returned mask (the scalar code rescales them). */
typedef struct el_envlight__ploc4 { __m128 u, v, vp, rr, len2, s, Y; __m128i i, r; } el_envlight__ploc4;
static inline __m128 el_envlight__prod_locate4(const struct el_envlight__warp *W, const __m128 d[3], el_envlight__ploc4 *q) {
  __m128 r2 = _mm_add_ps(_mm_mul_ps(d[0], d[0]), _mm_mul_ps(d[1], d[1])), len2 = _mm_add_ps(r2, _mm_mul_ps(d[2], d[2]));
  __m128 ok = _mm_and_ps(_mm_cmpge_ps(len2, EL_ENVLIGHT__V(FLT_MIN)), _mm_cmple_ps(len2, EL_ENVLIGHT__V(FLT_MAX)));
  __m128 ax = el_envlight__abs4(d[0]), ay = el_envlight__abs4(d[1]), az = el_envlight__abs4(d[2]), zero = _mm_setzero_ps(), a, X, Y, gw = _mm_set1_ps((float)W->w);
  q->len2 = len2;
  q->rr = _mm_sqrt_ps(r2);
  /* el_envlight__phi_turns(d[1], d[0]) */
  a = _mm_mul_ps(el_envlight__atan_ratio4(_mm_min_ps(ay, ax), _mm_max_ps(ax, ay)), EL_ENVLIGHT__V(0.159154943f));
  a = el_envlight__sel4(_mm_cmpgt_ps(ay, ax), _mm_sub_ps(EL_ENVLIGHT__V(0.25f), a), a);
  a = el_envlight__sel4(_mm_cmplt_ps(d[0], zero), _mm_sub_ps(EL_ENVLIGHT__V(0.5f), a), a);
  q->u = el_envlight__sel4(_mm_cmplt_ps(d[1], zero), _mm_sub_ps(EL_ENVLIGHT__V(1.0f), a), a);
  /* el_envlight__theta_vp(rr, d[2]) */
  a = _mm_mul_ps(el_envlight__atan_ratio4(_mm_min_ps(q->rr, az), _mm_max_ps(az, q->rr)), EL_ENVLIGHT__V(0.318309886f));
  q->vp = a = el_envlight__sel4(_mm_cmpgt_ps(q->rr, az), _mm_sub_ps(EL_ENVLIGHT__V(0.5f), a), a);
  q->v = el_envlight__sel4(_mm_cmplt_ps(d[2], zero), _mm_sub_ps(EL_ENVLIGHT__V(1.0f), a), a);
  X = _mm_sub_ps(_mm_mul_ps(q->u, gw), EL_ENVLIGHT__V(0.5f));
  X = _mm_add_ps(X, _mm_and_ps(_mm_cmplt_ps(X, zero), gw)); /* + 0 leaves X's bits: X >= -0.5, never -0 */
  q->i = el_envlight__mini4(_mm_cvttps_epi32(X), W->w - 1);
  q->s = el_envlight__clamp01_4(_mm_sub_ps(X, _mm_cvtepi32_ps(q->i)));
  q->Y = Y = _mm_add_ps(_mm_mul_ps(q->v, _mm_set1_ps((float)W->h)), EL_ENVLIGHT__V(0.5f));
  q->r = el_envlight__mini4(_mm_cvttps_epi32(Y), W->h);
  return ok;
}
/* el_envlight__prod_eval on four lanes: widths as floats fwc, fwr; corners c[4] */
static inline __m128 el_envlight__prod_eval4(const struct el_envlight__warp *W, const el_envlight__ploc4 *q, __m128 fwc, __m128 fwr, const __m128 c[4]) {
  __m128 sum = _mm_add_ps(_mm_add_ps(c[0], c[1]), _mm_add_ps(c[2], c[3]));
  __m128 e0 = _mm_add_ps(c[0], _mm_mul_ps(q->s, _mm_sub_ps(c[1], c[0]))), e1 = _mm_add_ps(c[2], _mm_mul_ps(q->s, _mm_sub_ps(c[3], c[2])));
  __m128 p = _mm_div_ps(_mm_mul_ps(_mm_mul_ps(_mm_mul_ps(fwc, fwr), _mm_set1_ps(W->dens_k)), EL_ENVLIGHT__V(4.0f)), sum);
  __m128 len = _mm_sqrt_ps(q->len2), t = el_envlight__clamp01_4(_mm_sub_ps(q->Y, _mm_cvtepi32_ps(q->r)));
  __m128 f = _mm_div_ps(_mm_mul_ps(_mm_add_ps(e0, _mm_mul_ps(t, _mm_sub_ps(e1, e0))), len), q->rr);
  __m128i ri = _mm_sub_epi32(q->r, _mm_set1_epi32(1)); /* pole rows (0, h): r - 1 outside [0, h - 2] */
  if (_mm_movemask_epi8(_mm_or_si128(_mm_cmpgt_epi32(_mm_setzero_si128(), ri), _mm_cmpgt_epi32(ri, _mm_set1_epi32(W->h - 2))))) {
    __m128 top = _mm_castsi128_ps(_mm_cmpeq_epi32(q->r, _mm_setzero_si128()));
    __m128 pole = _mm_or_ps(top, _mm_castsi128_ps(_mm_cmpeq_epi32(q->r, _mm_set1_epi32(W->h))));
    __m128 ratio = el_envlight__sel4(_mm_cmpgt_ps(q->rr, _mm_setzero_ps()), _mm_div_ps(_mm_mul_ps(q->vp, len), q->rr), EL_ENVLIGHT__V(0.318309886f));
    f = el_envlight__sel4(pole, _mm_mul_ps(_mm_mul_ps(_mm_mul_ps(EL_ENVLIGHT__V(4.0f), _mm_set1_ps((float)W->h)), el_envlight__sel4(top, e1, e0)), ratio), f);
  }
  return _mm_min_ps(_mm_mul_ps(p, f), EL_ENVLIGHT__V(FLT_MAX));
}
/* el_envlight__lin_invf on four lanes */
static inline __m128 el_envlight__lin_invf4(__m128 a, __m128 b, __m128 q) {
  __m128 m = _mm_max_ps(a, b), zero = _mm_setzero_ps(), d, den, t;
  a = _mm_div_ps(a, m); b = _mm_div_ps(b, m);
  d = _mm_add_ps(_mm_mul_ps(a, a), _mm_mul_ps(q, _mm_sub_ps(_mm_mul_ps(b, b), _mm_mul_ps(a, a))));
  den = _mm_add_ps(a, _mm_sqrt_ps(_mm_max_ps(d, zero)));
  t = _mm_and_ps(_mm_cmpgt_ps(den, zero), _mm_div_ps(_mm_mul_ps(q, _mm_add_ps(a, b)), den));
  return el_envlight__sel4(_mm_cmpgt_ps(m, zero), el_envlight__clamp01_4(t), q);
}
/* The normal tables of four world normals x[3] (el_envlight__prod_table): tab[k] for each lane < m. */
static EL_ENVLIGHT__PROD_INLINE void el_envlight__prod_table4(const el_envlight *l, const struct el_envlight__warp *W, const float *n, int m, const __m128 x[3], const uint16_t *tab[4]) {
  __m128 d[3], s, px, py, one = EL_ENVLIGHT__V(1.0f), zero = _mm_setzero_ps(), half = EL_ENVLIGHT__V(0.5f), neg = EL_ENVLIGHT__V(-1.0f), fm = _mm_set1_ps((float)W->m), low;
  __m128i bi, bj;
  int ok, k, ii[4], jj[4];
  s = _mm_add_ps(_mm_add_ps(el_envlight__abs4(x[0]), el_envlight__abs4(x[1])), el_envlight__abs4(x[2]));
  ok = _mm_movemask_ps(_mm_and_ps(_mm_cmpge_ps(s, EL_ENVLIGHT__V(1e-18f)), _mm_cmple_ps(s, EL_ENVLIGHT__V(1e18f))));
  el_envlight__xform4(l, 1, x, d);
  /* el_envlight__oct_encode */
  s = _mm_add_ps(_mm_add_ps(el_envlight__abs4(d[0]), el_envlight__abs4(d[1])), el_envlight__abs4(d[2]));
  px = _mm_div_ps(d[0], s); py = _mm_div_ps(d[1], s);
  low = _mm_cmplt_ps(d[2], zero);
  s = _mm_mul_ps(_mm_sub_ps(one, el_envlight__abs4(py)), el_envlight__sel4(_mm_cmpge_ps(px, zero), one, neg));
  py = el_envlight__sel4(low, _mm_mul_ps(_mm_sub_ps(one, el_envlight__abs4(px)), el_envlight__sel4(_mm_cmpge_ps(py, zero), one, neg)), py);
  px = el_envlight__sel4(low, s, px);
  px = _mm_add_ps(_mm_mul_ps(half, px), half); py = _mm_add_ps(_mm_mul_ps(half, py), half);
  bi = _mm_cvttps_epi32(_mm_mul_ps(px, fm)); bj = _mm_cvttps_epi32(_mm_mul_ps(py, fm));
  /* i < m - 1 ? (i > 0 ? i : 0) : m - 1 */
  bi = el_envlight__mini4(_mm_and_si128(bi, _mm_cmpgt_epi32(bi, _mm_setzero_si128())), W->m - 1);
  bj = el_envlight__mini4(_mm_and_si128(bj, _mm_cmpgt_epi32(bj, _mm_setzero_si128())), W->m - 1);
  _mm_storeu_si128((__m128i *)(void *)ii, bi); _mm_storeu_si128((__m128i *)(void *)jj, bj);
  for (k = 0; k < m; ++k)
    tab[k] = (ok >> k) & 1 ? W->cos_tab + W->cos_off[(size_t)jj[k] * (size_t)W->m + (size_t)ii[k]] : el_envlight__prod_table(l, W, n + 3 * k);
}
#else
#define EL_ENVLIGHT__COS4 0
#endif

#define EL_ENVLIGHT__CB 16 /* samples per block: their table reads are started stage by stage, together */
/* a read of the line at byte offset off from p requested (integer arithmetic: the address may lie past
 * the table's end, where prefetching is harmless but pointer arithmetic would not be defined) */
#define EL_ENVLIGHT__PF(p, off) _mm_prefetch((const char *)((uintptr_t)(const void *)(p) + (uintptr_t)(off)), _MM_HINT_T0)

EL_DEF void el_envlight_sample_li_cos_n(const el_envlight *l, int n, const float *normals, const float *u, float *wi, float *rgb, float *pdf) {
  int j;
#if EL_ENVLIGHT__COS4
  const struct el_envlight__warp *W;
  if (n > 1 && l->width > 0 && l->mapping == EL_ENVLIGHT_MAPPING_LATLONG &&
      (W = el_envlight__prod_ensure(l, EL_ENVLIGHT__CELLS_U, EL_ENVLIGHT__CELLS_V, EL_ENVLIGHT__NORMAL_BINS)) != NULL) {
    const float lo = 2.44140625e-4f, hi = 0.999755859f;
    const int gw = W->w;
    for (j = 0; j < n; j += EL_ENVLIGHT__CB) {
      const uint16_t *tab[EL_ENVLIGHT__CB];
      el_envlight__pick P[EL_ENVLIGHT__CB];
      float fq[EL_ENVLIGHT__CB], fs[EL_ENVLIGHT__CB], fwc[EL_ENVLIGHT__CB], fwr[EL_ENVLIGHT__CB], cs[4][EL_ENVLIGHT__CB];
      float ow[EL_ENVLIGHT__CB][4], pp[EL_ENVLIGHT__CB], uvs[2 * EL_ENVLIGHT__CB], c4[4], fxy[2 * EL_ENVLIGHT__CB];
      const float *tp[EL_ENVLIGHT__CB][4];
      int ii[EL_ENVLIGHT__CB], rr[EL_ENVLIGHT__CB], m = n - j < EL_ENVLIGHT__CB ? n - j : EL_ENVLIGHT__CB, k, g;
      unsigned live = 0, good = 0;
      for (g = 0; g < m; g += 4) { /* the normals' tables; their first lines requested */
        __m128 x[3];
        int mg = m - g < 4 ? m - g : 4;
        el_envlight__load3x4(normals + 3 * (j + g), mg, x);
        el_envlight__prod_table4(l, W, normals + 3 * (j + g), mg, x, tab + g);
        for (k = g; k < g + mg; ++k)
          if (tab[k]) { EL_ENVLIGHT__PF(tab[k], 0); EL_ENVLIGHT__PF(tab[k], 64); EL_ENVLIGHT__PF(tab[k], 128); EL_ENVLIGHT__PF(tab[k], 192); }
      }
      /* <<Pick a cell>>, its patch row and the patch, stage by stage over the block's samples */
      for (k = 0; k < m; ++k)
        if (tab[k] && !W->all_zero && tab[k][W->kv] != 0) {
          live |= 1u << k;
          el_envlight__pick1(W, tab[k], u + 2 * (j + k), &P[k]);
          EL_ENVLIGHT__PF(P[k].p, -2 * EL_ENVLIGHT__GUIDE_E); EL_ENVLIGHT__PF(P[k].p, 56);
        }
      for (k = 0; k < m; ++k)
        if ((live >> k) & 1) {
          el_envlight__pick2(W, &P[k]);
          EL_ENVLIGHT__PF(P[k].p, 0);
          if (W->grow) EL_ENVLIGHT__PF(W->grow, ((size_t)P[k].a * (size_t)W->kv + (size_t)P[k].b) * EL_ENVLIGHT__GUIDE_K);
        }
      for (k = 0; k < m; ++k)
        if ((live >> k) & 1) {
          el_envlight__pick3(W, &P[k]);
          EL_ENVLIGHT__PF(P[k].p, 0);
          if (W->gcol) EL_ENVLIGHT__PF(W->gcol, ((size_t)P[k].r * (size_t)W->ku + (size_t)P[k].a) * EL_ENVLIGHT__GUIDE_K);
        }
      for (k = 0; k < m; ++k)
        if ((live >> k) & 1) {
          const uint16_t *V;
          el_envlight__pick4(W, &P[k]);
          V = W->V16 + (size_t)P[k].r * (size_t)gw + (size_t)P[k].i;
          EL_ENVLIGHT__PF(V, 0); EL_ENVLIGHT__PF(V, 2 * gw);
        }
      for (k = 0; k < m; ++k) /* the lanes in rows of four; no sample (or padding): harmless values */
        if ((live >> k) & 1) {
          ii[k] = P[k].i; rr[k] = P[k].r; fq[k] = P[k].q; fs[k] = P[k].s;
          fwc[k] = (float)(int)P[k].wc; fwr[k] = (float)(int)P[k].wr; /* < 2^31 */
          el_envlight__prod_corners(W, P[k].i, P[k].r, c4);
          cs[0][k] = c4[0]; cs[1][k] = c4[1]; cs[2][k] = c4[2]; cs[3][k] = c4[3];
        } else {
          ii[k] = 0; rr[k] = 1; fq[k] = fs[k] = 0.5f; fwc[k] = fwr[k] = 1.0f; cs[0][k] = cs[1][k] = cs[2][k] = cs[3][k] = 1.0f;
        }
      for (g = 0; g < m; g += 4) {
        __m128 c[4], t, s, uu, v, vp, vm, d[3], w[3], w3, p, ok, zero = _mm_setzero_ps(), one = EL_ENVLIGHT__V(1.0f);
        __m128i vi, vr, nn;
        el_envlight__ploc4 q;
        for (k = m; k < g + 4; ++k) { /* padding lanes of the last row */
          ii[k] = 0; rr[k] = 1; fq[k] = fs[k] = 0.5f; fwc[k] = fwr[k] = 1.0f; cs[0][k] = cs[1][k] = cs[2][k] = cs[3][k] = 1.0f;
        }
        c[0] = _mm_loadu_ps(cs[0] + g); c[1] = _mm_loadu_ps(cs[1] + g); c[2] = _mm_loadu_ps(cs[2] + g); c[3] = _mm_loadu_ps(cs[3] + g);
        /* (s, t) in the patch, 2^-12 inside its edges (el_envlight__prod_sample) */
        t = el_envlight__lin_invf4(_mm_add_ps(c[0], c[1]), _mm_add_ps(c[2], c[3]), _mm_loadu_ps(fq + g));
        s = el_envlight__lin_invf4(_mm_add_ps(c[0], _mm_mul_ps(t, _mm_sub_ps(c[2], c[0]))), _mm_add_ps(c[1], _mm_mul_ps(t, _mm_sub_ps(c[3], c[1]))),
                                   _mm_loadu_ps(fs + g));
        t = _mm_min_ps(_mm_max_ps(t, EL_ENVLIGHT__V(lo)), EL_ENVLIGHT__V(hi));
        s = _mm_min_ps(_mm_max_ps(s, EL_ENVLIGHT__V(lo)), EL_ENVLIGHT__V(hi));
        /* <<Compute direction>> */
        vi = _mm_loadu_si128((const __m128i *)(const void *)(ii + g)); vr = _mm_loadu_si128((const __m128i *)(const void *)(rr + g));
        uu = _mm_mul_ps(_mm_add_ps(_mm_add_ps(_mm_cvtepi32_ps(vi), EL_ENVLIGHT__V(0.5f)), s), _mm_set1_ps(W->inv_w));
        uu = _mm_sub_ps(uu, _mm_and_ps(_mm_cmpge_ps(uu, one), one));
        uu = _mm_min_ps(uu, EL_ENVLIGHT__V(0.99999994f));
        v = _mm_mul_ps(_mm_add_ps(_mm_sub_ps(_mm_cvtepi32_ps(vr), EL_ENVLIGHT__V(0.5f)), t), _mm_set1_ps(W->inv_h));
        vp = el_envlight__sel4(_mm_cmplt_ps(v, EL_ENVLIGHT__V(0.5f)), v, _mm_sub_ps(one, v));
        if (_mm_movemask_ps(_mm_castsi128_ps(_mm_or_si128(_mm_cmpeq_epi32(vr, _mm_setzero_si128()), _mm_cmpeq_epi32(vr, _mm_set1_epi32(W->h)))))) { /* pole rows */
          __m128 top = _mm_castsi128_ps(_mm_cmpeq_epi32(vr, _mm_setzero_si128())), bot = _mm_castsi128_ps(_mm_cmpeq_epi32(vr, _mm_set1_epi32(W->h)));
          __m128 vt = _mm_mul_ps(t, _mm_set1_ps(W->half_inv_h)), vb = _mm_mul_ps(_mm_sub_ps(one, t), _mm_set1_ps(W->half_inv_h));
          vp = el_envlight__sel4(top, vt, el_envlight__sel4(bot, vb, vp));
          v = el_envlight__sel4(top, vt, el_envlight__sel4(bot, _mm_sub_ps(one, vb), v));
        }
        /* el_envlight__uvp_to_dir */
        vm = _mm_add_ps(uu, uu); /* 2 u */
        nn = _mm_cvttps_epi32(_mm_add_ps(vm, EL_ENVLIGHT__V(0.5f)));
        vm = _mm_sub_ps(vm, _mm_cvtepi32_ps(nn));
        { /* sgn = n odd ? -1 : 1, as a sign bit */
          __m128 sgn = _mm_castsi128_ps(_mm_slli_epi32(nn, 31)), st = el_envlight__sinpi4(vp);
          d[0] = _mm_mul_ps(st, _mm_xor_ps(sgn, el_envlight__cospi4(vm)));
          d[1] = _mm_mul_ps(st, _mm_xor_ps(sgn, el_envlight__sinpi4(vm)));
          d[2] = el_envlight__sinpi4(_mm_sub_ps(EL_ENVLIGHT__V(0.5f), v));
        }
        el_envlight__xform4(l, 0, d, w);
        if (!l->exact_transform) el_envlight__xform4(l, 1, w, d); /* as pdf_li_cos brings wi back */
        /* the pdf's own path at wi (el_envlight__prod_locate, el_envlight__prod_eval), its reads skipped */
        ok = el_envlight__prod_locate4(W, d, &q);
        ok = _mm_and_ps(ok, _mm_castsi128_ps(_mm_and_si128(_mm_cmpeq_epi32(q.i, vi), _mm_cmpeq_epi32(q.r, vr))));
        p = el_envlight__prod_eval4(W, &q, _mm_loadu_ps(fwc + g), _mm_loadu_ps(fwr + g), c);
        good |= (unsigned)_mm_movemask_ps(_mm_and_ps(ok, _mm_cmpgt_ps(p, zero))) << g;
        w3 = zero;
        _MM_TRANSPOSE4_PS(w[0], w[1], w[2], w3);
        _mm_storeu_ps(ow[g], w[0]); _mm_storeu_ps(ow[g + 1], w[1]); _mm_storeu_ps(ow[g + 2], w[2]); _mm_storeu_ps(ow[g + 3], w3);
        _mm_storeu_ps(pp + g, p);
        _mm_storeu_ps(uvs + 2 * g, _mm_unpacklo_ps(q.u, q.v)); _mm_storeu_ps(uvs + 2 * g + 4, _mm_unpackhi_ps(q.u, q.v));
      }
      good &= live;
      if (rgb) /* le(wi) at the same (u, v): its texels requested, blended below */
        for (k = 0; k < m; ++k)
          if ((good >> k) & 1) {
            el_envlight__bilerp_texels(l, uvs[2 * k], uvs[2 * k + 1], tp[k], &fxy[2 * k], &fxy[2 * k + 1]);
            EL_ENVLIGHT__PF(tp[k][0], 0); EL_ENVLIGHT__PF(tp[k][1], 8); EL_ENVLIGHT__PF(tp[k][2], 0); EL_ENVLIGHT__PF(tp[k][3], 8);
          }
      for (k = 0; k < m; ++k) {
        float *wk = wi + 3 * (j + k), *ck = rgb ? rgb + 3 * (j + k) : NULL;
        if ((good >> k) & 1) {
          wk[0] = ow[k][0]; wk[1] = ow[k][1]; wk[2] = ow[k][2]; pdf[j + k] = pp[k];
          if (ck) el_envlight__bilerp_at(tp[k], fxy[2 * k], fxy[2 * k + 1], ck);
        } else if ((live >> k) & 1) el_envlight_sample_li_cos(l, normals + 3 * (j + k), u + 2 * (j + k), wk, ck, pdf + j + k); /* rare */
        else { /* as sample_li_cos: no sample */
          wk[0] = l->to_world[2]; wk[1] = l->to_world[5]; wk[2] = l->to_world[8]; pdf[j + k] = 0.0f;
          if (ck) ck[0] = ck[1] = ck[2] = 0.0f;
        }
      }
    }
    return;
  }
#endif
  for (j = 0; j < n; ++j) el_envlight_sample_li_cos(l, normals + 3 * j, u + 2 * j, wi + 3 * j, rgb ? rgb + 3 * j : NULL, pdf + j);
}

#if EL_ENVLIGHT__COS4
/* pdf_li_cos_n's four-lane body; with rgb (pdf_li_cos_le_n) also le at each direction's (u, v), which the
 * pdf's location computes anyway (le's own (u, v): the same light-space direction, atan polynomials and
 * square root). Returns 0 where the caller runs the plain loops. */
static EL_ENVLIGHT__PROD_INLINE int el_envlight__pdf_cos_n(const el_envlight *l, int n, const float *normals, const float *wi, float *pdf, float *rgb) {
  int j;
  const struct el_envlight__warp *W;
  if (n > 1 && l->width > 0 && l->mapping == EL_ENVLIGHT_MAPPING_LATLONG &&
      (W = el_envlight__prod_ensure(l, EL_ENVLIGHT__CELLS_U, EL_ENVLIGHT__CELLS_V, EL_ENVLIGHT__NORMAL_BINS)) != NULL && !W->all_zero) {
    const int gw = W->w;
    for (j = 0; j < n; j += EL_ENVLIGHT__CB) {
      const uint16_t *tab[EL_ENVLIGHT__CB];
      el_envlight__ploc4 q[EL_ENVLIGHT__CB / 4];
      float fwc[EL_ENVLIGHT__CB], fwr[EL_ENVLIGHT__CB], cs[4][EL_ENVLIGHT__CB], c4[4], uvs[2 * EL_ENVLIGHT__CB], fxy[2 * EL_ENVLIGHT__CB];
      const float *tp[EL_ENVLIGHT__CB][4];
      int ii[EL_ENVLIGHT__CB], rr[EL_ENVLIGHT__CB], m = n - j < EL_ENVLIGHT__CB ? n - j : EL_ENVLIGHT__CB, k, g;
      unsigned ok = 0, live = 0;
      for (g = 0; g < m; g += 4) { /* the normals' tables and where the directions lie; the reads requested */
        __m128 x[3], d[3];
        int mg = m - g < 4 ? m - g : 4;
        el_envlight__load3x4(normals + 3 * (j + g), mg, x);
        el_envlight__prod_table4(l, W, normals + 3 * (j + g), mg, x, tab + g);
        el_envlight__load3x4(wi + 3 * (j + g), mg, x);
        el_envlight__xform4(l, 1, x, d); /* el_envlight__to_light_dir: lanes that need rescaling go to the single call */
        ok |= (unsigned)_mm_movemask_ps(el_envlight__prod_locate4(W, d, &q[g / 4])) << g;
        _mm_storeu_si128((__m128i *)(void *)(ii + g), q[g / 4].i); _mm_storeu_si128((__m128i *)(void *)(rr + g), q[g / 4].r);
        if (rgb) { _mm_storeu_ps(uvs + 2 * g, _mm_unpacklo_ps(q[g / 4].u, q[g / 4].v)); _mm_storeu_ps(uvs + 2 * g + 4, _mm_unpackhi_ps(q[g / 4].u, q[g / 4].v)); }
        for (k = g; k < g + mg; ++k) {
          int a, b;
          const uint16_t *V;
          if (rgb && ((ok >> k) & 1)) { /* le's texels (whatever the normal), requested */
            el_envlight__bilerp_texels(l, uvs[2 * k], uvs[2 * k + 1], tp[k], &fxy[2 * k], &fxy[2 * k + 1]);
            EL_ENVLIGHT__PF(tp[k][0], 0); EL_ENVLIGHT__PF(tp[k][1], 8); EL_ENVLIGHT__PF(tp[k][2], 0); EL_ENVLIGHT__PF(tp[k][3], 8);
          }
          if (!tab[k] || !((ok >> k) & 1)) continue;
          a = W->cu_of[ii[k]]; b = W->cv_of[rr[k]];
          V = W->V16 + (size_t)rr[k] * (size_t)gw + (size_t)ii[k];
          EL_ENVLIGHT__PF(tab[k], 2 * b); EL_ENVLIGHT__PF(tab[k], 2 * (((W->kv + 2) & ~1) + 2 * b));
          EL_ENVLIGHT__PF(W->pcol + (size_t)rr[k] * W->cond_stride + (size_t)W->coff[a] + (size_t)(ii[k] - W->a0[a]), 0);
          EL_ENVLIGHT__PF(W->prow + (size_t)a * ((size_t)W->h + 1 + (size_t)W->kv) + (size_t)rr[k] + (size_t)b, 0);
          EL_ENVLIGHT__PF(V, 0); EL_ENVLIGHT__PF(V, 2 * gw);
        }
      }
      for (k = 0; k < m; ++k) /* the cell's row span, requested */
        if (tab[k] && ((ok >> k) & 1)) EL_ENVLIGHT__PF(el_envlight__sparse_row(W, tab[k], W->cv_of[rr[k]]), 4 + 2 * (W->cu_of[ii[k]] & ~15));
      for (k = 0; k < m; ++k) { /* the table reads, lane by lane */
        uint32_t wc, wr;
        if (tab[k] && tab[k][W->kv] != 0 && ((ok >> k) & 1) && el_envlight__prod_widths(W, tab[k], ii[k], rr[k], &wc, &wr)) {
          live |= 1u << k;
          fwc[k] = (float)(int)wc; fwr[k] = (float)(int)wr; /* < 2^31 */
          el_envlight__prod_corners(W, ii[k], rr[k], c4);
          cs[0][k] = c4[0]; cs[1][k] = c4[1]; cs[2][k] = c4[2]; cs[3][k] = c4[3];
        } else {
          fwc[k] = fwr[k] = 1.0f; cs[0][k] = cs[1][k] = cs[2][k] = cs[3][k] = 1.0f;
        }
      }
      for (k = m; k < ((m + 3) & ~3); ++k) { fwc[k] = fwr[k] = 1.0f; cs[0][k] = cs[1][k] = cs[2][k] = cs[3][k] = 1.0f; }
      for (g = 0; g < m; g += 4) {
        __m128 c[4];
        float pp[4];
        c[0] = _mm_loadu_ps(cs[0] + g); c[1] = _mm_loadu_ps(cs[1] + g); c[2] = _mm_loadu_ps(cs[2] + g); c[3] = _mm_loadu_ps(cs[3] + g);
        _mm_storeu_ps(pp, el_envlight__prod_eval4(W, &q[g / 4], _mm_loadu_ps(fwc + g), _mm_loadu_ps(fwr + g), c));
        for (k = g; k < g + 4 && k < m; ++k) {
          if ((live >> k) & 1) pdf[j + k] = pp[k - g];
          else if (tab[k] && tab[k][W->kv] != 0 && !((ok >> k) & 1)) pdf[j + k] = el_envlight_pdf_li_cos(l, normals + 3 * (j + k), wi + 3 * (j + k));
          else pdf[j + k] = 0.0f;
        }
      }
      if (rgb)
        for (k = 0; k < m; ++k) {
          if ((ok >> k) & 1) el_envlight__bilerp_at(tp[k], fxy[2 * k], fxy[2 * k + 1], rgb + 3 * (j + k));
          else el_envlight__le_cold(l, wi + 3 * (j + k), rgb + 3 * (j + k)); /* (what le does with such a direction) */
        }
    }
    return 1;
  }
  return 0;
}
#endif

EL_DEF void el_envlight_pdf_li_cos_n(const el_envlight *l, int n, const float *normals, const float *wi, float *pdf) {
  int j;
#if EL_ENVLIGHT__COS4
  if (el_envlight__pdf_cos_n(l, n, normals, wi, pdf, NULL)) return;
#endif
  for (j = 0; j < n; ++j) pdf[j] = el_envlight_pdf_li_cos(l, normals + 3 * j, wi + 3 * j);
}

EL_DEF void el_envlight_pdf_li_cos_le_n(const el_envlight *l, int n, const float *normals, const float *dirs, float *pdf, float *rgb) {
#if EL_ENVLIGHT__COS4
  if (el_envlight__pdf_cos_n(l, n, normals, dirs, pdf, rgb)) return;
#endif
  el_envlight_pdf_li_cos_n(l, n, normals, dirs, pdf);
  el_envlight_le_n(l, n, dirs, rgb);
}

EL_DEF size_t el_envlight_product_bytes(const el_envlight *l) {
  int cs;
#if EL_ENVLIGHT__ATOMICS
  cs = __atomic_load_n(&l->cos_state, __ATOMIC_ACQUIRE);
#else
  cs = l->cos_state;
#endif
  return (cs == 2 && l->prod) ? l->prod->warp_bytes + l->prod->cos_bytes : 0;
}

/* >> importance BILINEAR: le()'s patches (issue 22's patch density; NOTES ON PRODUCT SAMPLING, point 1)
 * The density is the bilinear interpolant, over each of le()'s patches (the patch grid's layout above: w patch
 * columns between texel centres, h + 1 patch rows, the two pole rows half as tall with a vertex row of
 * 0), of the vertex values V = lum x sin(theta) at the texel centres, as bfloat16 rounded up (the product
 * sampler's grid: el_envlight__prod_corners reads both). A patch is picked from one discrete 2D table
 * over the patches (distribution2d.h's integer CDFs, each patch's mass its corners' mean x its height,
 * and its guide tables: the light's own sampler, l->dist and l->fast), then (s, t) inside it by two
 * linear inversions (t from the marginal (1 - t)(V00 + V01) + t (V10 + V11), s from the conditional at
 * t). Its density is the patch's integer share x bil(s, t) / mean(corners) / (du dv 2 pi^2 sin theta):
 * el_envlight__prod_eval's expression with the distribution's 2^24 x 2^24 units (dens_k = 2^-48 w h /
 * (2 pi^2)), stored per patch as the factor K of its record. pdf_li locates the direction (the fast path
 * below on maps of at least 256 x 128; on smaller ones le()'s own atans, product sampling's locate) and
 * reads one record. sample_li locates its own direction the same way, so its pdf is pdf_li(wi)'s, bit
 * for bit. */

/* t in [0, 1] with int_0^t ((1 - x) a + x b) dx = q (a + b) / 2 for a, b >= 0, not both 0: the inverse
 * CDF of a linear density in the form without cancellation (a = b: t = q; a = 0: sqrt(q); b = 0: 1 -
 * sqrt(1 - q)). For the patch grid's values (at most 2^61 for a sum of two: the squares stay finite);
 * sums below 2^-40 are scaled up first, so that the squares stay normal floats. */
static inline float el_envlight__lin_inv(float a, float b, float q) {
  float d, den, t;
  if (a + b < 9.09494702e-13f) { a *= 1.20892582e24f; b *= 1.20892582e24f; } /* 2^-40, 2^80 */
  d = a * a + q * (b * b - a * a);
  den = a + el_envlight__sqrt(d > 0.0f ? d : 0.0f);
  t = den > 0.0f ? q * (a + b) / den : 0.0f; /* den = 0: a = 0 and q = 0, the start of a ramp from 0 */
  return t < 1.0f ? (t > 0.0f ? t : 0.0f) : 1.0f;
}

/* (u, v) and the light-space unit direction of (s, t) in patch (i, r), as le() maps them: u from the
 * patch's left texel centre (wrapping at the seam), v and its distance vp to the nearer pole. */
static inline float el_envlight__patch_uv(const struct el_envlight__warp *W, int i, int r, float s, float t, float *u, float *v) {
  float vp;
  *u = ((float)i + 0.5f + s) * W->inv_w;
  if (*u >= 1.0f) *u -= 1.0f;
  *u = *u < 0.99999994f ? *u : 0.99999994f;
  if (r == 0) { vp = t * W->half_inv_h; *v = vp; }
  else if (r == W->h) { vp = (1.0f - t) * W->half_inv_h; *v = 1.0f - vp; }
  else { *v = ((float)r - 0.5f + t) * W->inv_h; vp = *v < 0.5f ? *v : 1.0f - *v; }
  return vp;
}
static inline void el_envlight__patch_dir(const struct el_envlight__warp *W, int i, int r, float s, float t, float d[3]) {
  float u, v, vp = el_envlight__patch_uv(W, i, r, s, t, &u, &v);
  el_envlight__uvp_to_dir(u, v, vp, d);
}

/* THE FAST PATH (maps of at least 256 x 128: patch angles <= pi / 128): where pdf_li finds a direction
 * without atan. The patch column and row come from bin finders over half texels (el_envlight__finder
 * with 2w and 2h bins: the texel centres are the odd edges), as pdf_li's own bins; s and t from the angle
 * to a reference edge of the patch, atan of the tangent of the difference, (y c - x s) / (x c + y s) for
 * phi and (r c - z s) / (z c + r s) for theta (|angle| <= pi / 128: atan q = q - q^3 / 3 to float
 * precision). Column i's reference is its texel centre phi_i (cos, sin: col_tab[2 i]); patch row r's
 * (row_tab[8 r]: cos, sin, t0, 1 / dtheta, dtheta) is its edge nearer the pole (the pole itself for the
 * two pole rows), so that sample_li's sin(theta) = s cos a + c sin a never cancels; t = t0 + angle /
 * dtheta. sample_li forms its direction from the same references by angle addition (sin b = b - b^3 / 6,
 * cos b = 1 - b^2 / 2). The light's own pdf_li tables (u_base, u_edge, v_base, v_edge; col_tab, row_tab
 * in dir_alloc) hold them: mode BILINEAR has no others. */
static el_result el_envlight__patch_tables(el_envlight *l, int w, int h) {
  int i, r;
  el_result res = el_envlight__finder(2 * w, 4, &l->u_base, &l->u_edge, &l->u_cells);
  if (res == EL_SUCCESS) res = el_envlight__finder(2 * h, 2, &l->v_base, &l->v_edge, &l->v_cells);
  if (res != EL_SUCCESS) return res;
  l->u_cell_scale = (float)(l->u_cells - 2) * 0.25f;
  l->v_cell_scale = (float)(l->v_cells - 2) * 0.5f;
  l->dir_alloc = EL_MALLOC(((size_t)2 * (size_t)w + 8 * ((size_t)h + 1)) * sizeof(float));
  if (!l->dir_alloc) return EL_ERROR_OUT_OF_MEMORY;
  l->col_tab = (float *)l->dir_alloc;
  l->row_tab = l->col_tab + 2 * (size_t)w;
  for (i = 0; i < w; ++i) {
    double a = 2.0 * EL_ENVLIGHT__PI * (i + 0.5) / w;
    l->col_tab[2 * i] = (float)cos(a); l->col_tab[2 * i + 1] = (float)sin(a);
  }
  for (r = 0; r <= h; ++r) {
    float *t = l->row_tab + 8 * (size_t)r;
    double dt = (r == 0 || r == h ? 0.5 : 1.0) * EL_ENVLIGHT__PI / h, ref;
    int north = 2 * r <= h; /* the middle row (h even) may take either edge */
    ref = north ? (r == 0 ? 0.0 : EL_ENVLIGHT__PI * (r - 0.5) / h) : (r == h ? EL_ENVLIGHT__PI : EL_ENVLIGHT__PI * (r + 0.5) / h);
    memset(t, 0, 8 * sizeof(float));
    t[0] = (float)cos(ref); t[1] = north ? (float)sin(ref) : (float)sin(EL_ENVLIGHT__PI - ref); /* sin 0 and sin pi: exactly 0 */
    t[2] = north ? 0.0f : 1.0f;
    t[3] = (float)(1.0 / dt); t[4] = (float)dt;
  }
  return EL_SUCCESS;
}

/* atan(q) for |q| <= tan(pi / 128): q - q^3 / 3 (the next term, q^5 / 5, is below 2e-9 q) */
static inline float el_envlight__atan_small(float q) { return q - q * q * q * 0.333333343f; }

/* The fast path's <<Locate the patch>> of a light-space direction (x, y, z), r2 = x^2 + y^2 and len2
 * normal floats: patch (i, r), fractions (s, t), and rr = sqrt(r2), len = sqrt(len2) in q (q.u, q.v,
 * q.vp, q.Y unused). */
static inline void el_envlight__patch_find(const el_envlight *l, float x, float y, float z, float r2, float len2, el_envlight__ploc *q) {
  float rr = el_envlight__sqrt(r2), pu, tv, cs, sn, a;
  const float *rt;
  uint32_t hu, hv;
  size_t c;
  int i, r;
  pu = 2.0f - copysignf(1.0f + x / (fabsf(x) + fabsf(y) + FLT_MIN), y); /* pdf_li's diamond angle */
  pu = pu < 3.99999976f ? pu : 3.99999976f;
  c = (size_t)(int64_t)(pu * l->u_cell_scale);
  hu = (uint32_t)l->u_base[c] + (pu >= l->u_edge[c]); /* the half texel */
  tv = 1.0f - z / (rr + fabsf(z));
  c = (size_t)(int64_t)(tv * l->v_cell_scale);
  hv = (uint32_t)l->v_base[c] + (tv >= l->v_edge[c]);
  i = hu == 0 ? l->width - 1 : (int)((hu - 1u) >> 1);
  r = (int)((hv + 1u) >> 1);
  cs = l->col_tab[2 * i]; sn = l->col_tab[2 * i + 1];
  a = el_envlight__atan_small((y * cs - x * sn) / (x * cs + y * sn)) * ((float)l->width * 0.159154943f);
  q->s = a < 1.0f ? (a > 0.0f ? a : 0.0f) : 1.0f;
  rt = l->row_tab + 8 * (size_t)r;
  a = rt[2] + el_envlight__atan_small((rr * rt[0] - z * rt[1]) / (z * rt[0] + rr * rt[1])) * rt[3];
  q->Y = a < 1.0f ? (a > 0.0f ? a : 0.0f) : 1.0f; /* t */
  q->i = i; q->r = r; q->rr = rr; q->len2 = el_envlight__sqrt(len2); /* len */
}

/* The fast path's density at a found point of patch (q->i, q->r) with factor K (pdf_table) and corners c:
 * K bil(s, t) / sin(theta), sin(theta) = rr / len; in the pole rows (one edge 0) bil / sin -> the other
 * edge x (1 / dtheta) at the pole itself (rr = 0). */
static inline float el_envlight__patch_density(const el_envlight *l, const el_envlight__ploc *q, float K, const float c[4]) {
  float s = q->s, t = q->Y, e0 = c[0] + s * (c[1] - c[0]), e1 = c[2] + s * (c[3] - c[2]), p;
  if (q->rr > 0.0f) p = K * (e0 + t * (e1 - e0)) * (q->len2 / q->rr);
  else p = K * (e0 + e1) * l->row_tab[8 * (size_t)q->r + 3]; /* the exact pole: one of e0, e1 is 0 */
  return p < FLT_MAX ? p : FLT_MAX;
}

/* Patch (i, r)'s record: returns K, c gets the corners (el_envlight__prod_corners' values) */
static inline float el_envlight__patch_rec(const el_envlight *l, int i, int r, float c[4]) {
  const float *rec = l->pdf_table + 4 * ((size_t)r * (size_t)l->width + (size_t)i);
  uint32_t a, b;
  memcpy(&a, rec + 1, 4); memcpy(&b, rec + 2, 4);
  c[0] = el_envlight__bf16((uint16_t)(a & 0xffffu)); c[1] = el_envlight__bf16((uint16_t)(a >> 16));
  c[2] = el_envlight__bf16((uint16_t)(b & 0xffffu)); c[3] = el_envlight__bf16((uint16_t)(b >> 16));
  return rec[0];
}

/* The fast path's pdf_li of a light-space direction (x, y, z) whose r2 and len2 are normal floats */
static inline float el_envlight__patch_pdf_fast(const el_envlight *l, float x, float y, float z, float r2, float len2, el_envlight__ploc *q) {
  float c[4], K;
  el_envlight__patch_find(l, x, y, z, r2, len2, q);
  K = el_envlight__patch_rec(l, q->i, q->r, c);
  if (!(K > 0.0f)) return 0.0f; /* a patch without mass */
  return el_envlight__patch_density(l, q, K, c);
}

/* <<Build the patch tables>>: the vertex grid (bfloat16), the patches' masses, the distribution over them
 * and its guide tables. The patches are the image's, whatever importance_width says (maps over the cap
 * never get here: init gives them CELL_AVERAGE). */
static el_result el_envlight__patch_build(el_envlight *l) {
  struct el_envlight__warp *W;
  int w = l->width, h = l->height, i, j, r;
  float *f = NULL;
  size_t nv = ((size_t)h + 2) * (size_t)w;
  el_result res = EL_ERROR_OUT_OF_MEMORY;
  el_distribution_options dopt;
  W = (struct el_envlight__warp *)EL_MALLOC(sizeof *W);
  if (!W) return EL_ERROR_OUT_OF_MEMORY;
  memset(W, 0, sizeof *W);
  W->w = w; W->h = h;
  W->inv_w = 1.0f / (float)w; W->inv_h = 1.0f / (float)h; W->half_inv_h = 0.5f / (float)h;
  W->dens_k = (float)(3.552713678800501e-15 * (double)w * (double)h / (2.0 * EL_ENVLIGHT__PI * EL_ENVLIGHT__PI)); /* 2^-48 */
  W->sin_row = (float *)EL_MALLOC((size_t)h * sizeof(float));
  W->V16 = (uint16_t *)EL_MALLOC(nv * sizeof(uint16_t));
  f = (float *)EL_MALLOC(((size_t)h + 1) * (size_t)w * sizeof(float));
  if (!W->sin_row || !W->V16 || !f) goto fail;
  for (j = 0; j < h; ++j) W->sin_row[j] = (float)sin(EL_ENVLIGHT__PI * (j + 0.5) / h);
  /* <<Initialize compensated PDF>> (pbrt-v4): the mean luminance (the exact integral of le / 4 pi)
   * subtracted from every vertex, clamped at 0; none above it: the plain density */
  if (l->compensated) {
    double mean = (0.212671 * l->integral[0] + 0.715160 * l->integral[1] + 0.072169 * l->integral[2]) / (4.0 * EL_ENVLIGHT__PI);
    int any = 0;
    W->offset = mean < (double)FLT_MAX ? (float)mean : FLT_MAX;
    for (j = 0; j < h && !any; ++j)
      for (i = 0; i < w; ++i) if (el_envlight__vertex_of(l, W, i, j) > 0.0f) { any = 1; break; }
    if (!any) { W->offset = 0.0f; W->fell_back = l->fell_back = 1; }
  }
  /* the vertex rows: 0 at the poles; the values scaled by a power of two so that the largest is 2^60 (the
   * density does not change: it is bil / mean), positive ones at least 2^-60, so that el_envlight__lin_inv's
   * squares stay normal floats */
  {
    float vmax = 0.0f, k = 1.0f;
    int e;
    for (j = 0; j < h; ++j)
      for (i = 0; i < w; ++i) { float v = el_envlight__vertex_of(l, W, i, j); vmax = v > vmax ? v : vmax; }
    if (vmax > 0.0f) { (void)frexpf(vmax, &e); k = ldexpf(1.0f, 60 - e); }
    for (i = 0; i < w; ++i) W->V16[i] = W->V16[((size_t)h + 1) * (size_t)w + (size_t)i] = 0;
    for (j = 0; j < h; ++j)
      for (i = 0; i < w; ++i) {
        double v = (double)el_envlight__vertex_of(l, W, i, j) * (double)k;
        W->V16[((size_t)j + 1) * (size_t)w + (size_t)i] = el_envlight__bf16_up(v > 0.0 ? (float)(v > 8.67361738e-19 ? v : 8.67361738e-19) : 0.0f);
      }
  }
  /* each patch's mass over the table's equal bins: the mean of its (rounded) corners x its height (the
   * pole rows half) */
  for (r = 0; r <= h; ++r)
    for (i = 0; i < w; ++i) {
      float c[4];
      el_envlight__prod_corners(W, i, r, c);
      f[(size_t)r * (size_t)w + (size_t)i] = ((c[0] + c[1]) + (c[2] + c[3])) * (r == 0 || r == h ? 0.125f : 0.25f);
    }
  memset(&dopt, 0, sizeof dopt);
  res = el_distribution2d_init(&l->dist, f, w, h + 1, &dopt);
  if (res != EL_SUCCESS) goto fail;
  W->all_zero = l->dist.all_zero;
  /* each patch's record (l->pdf_table, 16 bytes: one cache line for everything the pdf reads of it): its
   * density factor K = P / (mean(corners) du dv 2 pi^2), P from its integer widths, so that the pdf is K
   * bil(s, t) / sin(theta); then its four corners as bfloat16 pairs (V[r][i], V[r][i + 1]) and (V[r + 1][i],
   * V[r + 1][i + 1]) */
  EL_FREE(f);
  f = NULL;
  l->pdf_table = (float *)EL_MALLOC(((size_t)h + 1) * (size_t)w * 4 * sizeof(float));
  if (!l->pdf_table) { el_envlight__free_tables(l); res = EL_ERROR_OUT_OF_MEMORY; goto fail; }
  for (r = 0; r <= h; ++r) {
    const uint32_t *row = l->dist.cdf + (size_t)r * ((size_t)w + 1);
    const uint16_t *V = W->V16 + (size_t)r * (size_t)w;
    float wv = (float)(int32_t)(l->dist.marginal[r + 1] - l->dist.marginal[r]);
    for (i = 0; i < w; ++i) {
      float c[4], wu = (float)(int32_t)(row[i + 1] - row[i]), sum, *rec = l->pdf_table + 4 * ((size_t)r * (size_t)w + (size_t)i);
      int i1 = i + 1 < w ? i + 1 : 0;
      uint32_t top = (uint32_t)V[i] | (uint32_t)V[i1] << 16, bottom = (uint32_t)V[(size_t)w + (size_t)i] | (uint32_t)V[(size_t)w + (size_t)i1] << 16;
      el_envlight__prod_corners(W, i, r, c);
      sum = (c[0] + c[1]) + (c[2] + c[3]);
      rec[0] = wu > 0.0f ? wv * wu * W->dens_k * (r == 0 || r == h ? 8.0f : 4.0f) / sum : 0.0f;
      memcpy(rec + 1, &top, 4); memcpy(rec + 2, &bottom, 4); rec[3] = 0.0f;
    }
  }
  if (l->sampler != EL_ENVLIGHT_SAMPLER_CDF) {
    el_distribution_fast_options fo;
    memset(&fo, 0, sizeof fo);
    fo.method = l->sampler == EL_ENVLIGHT_SAMPLER_ALIAS ? EL_DISTRIBUTION_FAST_ALIAS : EL_DISTRIBUTION_FAST_GUIDE;
    fo.guide_shrink_log2 = 2; /* as the other modes: 1 byte per patch */
    res = el_distribution2d_fast_init_ex(&l->fast, &l->dist, &fo);
    if (res != EL_SUCCESS) { el_envlight__free_tables(l); goto fail; }
  }
  W->warp_bytes = sizeof *W + (size_t)h * sizeof(float) + nv * sizeof(uint16_t) + el_distribution2d_bytes(&l->dist) +
                  ((size_t)h + 1) * (size_t)w * 4 * sizeof(float) + /* the records */
                  (l->sampler != EL_ENVLIGHT_SAMPLER_CDF ? el_distribution2d_fast_bytes(&l->fast) : 0);
  if (w >= 256 && h >= 128) { /* the fast path's tables (below): patch edges without atan, directions by angle addition */
    res = el_envlight__patch_tables(l, w, h);
    if (res != EL_SUCCESS) { el_envlight__free_tables(l); goto fail; }
    W->warp_bytes += (size_t)(l->u_cells + l->v_cells) * (sizeof(int) + sizeof(float)) + ((size_t)2 * (size_t)w + 8 * ((size_t)h + 1)) * sizeof(float);
  }
  l->warp = W;
  l->warp_state = 2;
  return EL_SUCCESS;
fail:
  EL_FREE(f);
  el_envlight__warp_free(W);
  return res;
}

static size_t el_envlight__warp_bytes(const el_envlight *l) { return l->warp ? l->warp->warp_bytes : 0; }

/* The density of patch (q->i, q->r) at a located point: its two integer widths, then the corners. */
static inline float el_envlight__patch_eval(const el_envlight *l, const el_envlight__ploc *q) {
  const uint32_t *row = l->dist.cdf + (size_t)q->r * ((size_t)l->dist.nu + 1);
  uint32_t wv = l->dist.marginal[q->r + 1] - l->dist.marginal[q->r], wu = row[q->i + 1] - row[q->i];
  float c[4];
  if (wv == 0 || wu == 0) return 0.0f; /* a patch without mass (all four corners 0) */
  el_envlight__prod_corners(l->warp, q->i, q->r, c);
  return el_envlight__prod_eval(l->warp, q, wv, wu, c);
}

/* pdf_li in importance mode BILINEAR (the tables are built); q: where it found dir (its patch q->i, q->r;
 * unset when it returns 0 before locating) */
static inline float el_envlight__patch_pdf_at(const el_envlight *l, const float dir[3], el_envlight__ploc *q) {
  float d[3];
  if (!l->warp || l->warp->all_zero) return 0.0f;
  if (!el_envlight__to_light_dir(l, dir, d)) return 0.0f; /* rescaled in world space first (issue 24) */
  if (l->col_tab) { /* (to_light_dir left len2 a normal float) */
    float r2 = d[0] * d[0] + d[1] * d[1], len2 = r2 + d[2] * d[2];
    if (len2 < 8.67361738e-19f) { /* 2^-60: a short d's squares may be denormal (inexact); 2^40 d is exact */
      d[0] *= 1.09951163e12f; d[1] *= 1.09951163e12f; d[2] *= 1.09951163e12f;
      r2 = d[0] * d[0] + d[1] * d[1]; len2 = r2 + d[2] * d[2];
    }
    return el_envlight__patch_pdf_fast(l, d[0], d[1], d[2], r2, len2, q);
  }
  if (!el_envlight__prod_locate(l->warp, d, q)) return 0.0f;
  return el_envlight__patch_eval(l, q);
}
static EL_ENVLIGHT__NOINLINE float el_envlight__patch_pdf_li(const el_envlight *l, const float dir[3]) {
  el_envlight__ploc q;
  return el_envlight__patch_pdf_at(l, dir, &q);
}

#if defined(__GNUC__) || defined(__clang__)
#define EL_ENVLIGHT__HOT_INLINE inline __attribute__((always_inline))
#else
#define EL_ENVLIGHT__HOT_INLINE inline
#endif
/* The sample at (s, t) of patch (i, r) (factor K, corners c): its world direction and its pdf, pdf_li's
 * at wi; q gets where pdf_li located it (the small maps' path: its (u, v) too). */
static EL_ENVLIGHT__HOT_INLINE float el_envlight__patch_point(const el_envlight *l, int i, int r, float s, float t, float K, const float c[4],
                                                             float wi[3], el_envlight__ploc *q) {
  float d[3];
  if (l->col_tab) { /* the fast path: angle addition from the patch's references */
    const float *ct = l->col_tab + 2 * (size_t)i, *rt = l->row_tab + 8 * (size_t)r;
    float b = s * (6.28318531f * l->warp->inv_w), a = (t - rt[2]) * rt[4], b2 = b * b, a2 = a * a;
    float cb = 1.0f - 0.5f * b2, sb = b - b * b2 * 0.166666672f, ca = 1.0f - 0.5f * a2, sa = a - a * a2 * 0.166666672f;
    float st = rt[1] * ca + rt[0] * sa, r2, len2;
    d[0] = st * (ct[0] * cb - ct[1] * sb);
    d[1] = st * (ct[1] * cb + ct[0] * sb);
    d[2] = rt[0] * ca - rt[1] * sa;
    el_envlight__to_world(l, d, wi);
    if (!l->exact_transform) el_envlight__mul_transpose(l->to_world, wi, d); /* as pdf_li brings wi back */
    r2 = d[0] * d[0] + d[1] * d[1]; len2 = r2 + d[2] * d[2];
    el_envlight__patch_find(l, d[0], d[1], d[2], r2, len2, q);
    if (q->i == i && q->r == r) return el_envlight__patch_density(l, q, K, c); /* pdf_li's arithmetic, its reads done */
    return el_envlight__patch_pdf_fast(l, d[0], d[1], d[2], r2, len2, q);
  }
  el_envlight__patch_dir(l->warp, i, r, s, t, d);
  el_envlight__to_world(l, d, wi);
  if (!l->exact_transform) el_envlight__mul_transpose(l->to_world, wi, d); /* as pdf_li brings wi back */
  if (!el_envlight__prod_locate(l->warp, d, q)) return 0.0f; /* (not for a unit d) */
  return el_envlight__patch_eval(l, q);
}

/* the rare retry at the patch's centre, out of line */
static EL_ENVLIGHT__NOINLINE float el_envlight__patch_centre(const el_envlight *l, int i, int r, float K, const float c[4], float wi[3],
                                                           el_envlight__ploc *q) {
  return el_envlight__patch_point(l, i, r, 0.5f, 0.5f, K, c, wi, q);
}

/* The sample of patch (i, r) at fractions (fu, fv) of its units: (s, t), the direction, its pdf, its
 * radiance. With uvout (sample_li_n) and rgb wanted, a fast-path sample under a signed permutation leaves
 * its radiance's (u, v) there (returns 1) for the caller to look up later. */
static EL_ENVLIGHT__HOT_INLINE int el_envlight__patch_finish_at(const el_envlight *l, int i, int r, float fu, float fv, float wi[3], float rgb[3],
                                                               float *pdf, float *uvout, el_envlight__ploc *qq) {
  float c[4], s, t, p, K;
  el_envlight__ploc q;
  q.u = q.v = 0.0f;
  K = el_envlight__patch_rec(l, i, r, c);
  /* (s, t) in the patch: t from the marginal (linear), s from the conditional at t (linear) */
  t = el_envlight__lin_inv(c[0] + c[1], c[2] + c[3], fv);
  s = el_envlight__lin_inv(c[0] + t * (c[2] - c[0]), c[1] + t * (c[3] - c[1]), fu);
  /* 2^-12 of a patch inside its edges (as product sampling): pdf_li, which locates the direction again,
   * finds this patch on maps up to 4096 x 2048, so that a sample at the edge of a patch next to one
   * without mass does not get pdf 0 */
  t = t > 2.44140625e-4f ? (t < 0.999755859f ? t : 0.999755859f) : 2.44140625e-4f;
  s = s > 2.44140625e-4f ? (s < 0.999755859f ? s : 0.999755859f) : 2.44140625e-4f;
  p = el_envlight__patch_point(l, i, r, s, t, K, c, wi, &q);
  /* the round trip left the patch for one without mass (near a pole under a general rotation, or a map
   * over 4096 wide): the patch's centre instead, as issue 24 did */
  if (!(p > 0.0f)) p = el_envlight__patch_centre(l, i, r, K, c, wi, &q);
  *pdf = p;
  if (rgb) {
    if (!(p > 0.0f)) rgb[0] = rgb[1] = rgb[2] = 0.0f;
    else if (!l->col_tab) el_envlight__bilerp(l, q.u, q.v, rgb); /* le(wi): the same (u, v) */
    else if (!l->exact_transform) el_envlight_le(l, wi, rgb); /* le(wi) itself, as the other modes' rotations */
    else { /* as the other modes under a signed permutation: le at the point's own (u, v), where pdf_li
            * found it (its patch, s, t): le(wi) but for le()'s atan polynomial, 1e-4 texel at most */
      float uv[2];
      el_envlight__patch_uv(l->warp, q.i, q.r, q.s, q.Y, uv, uv + 1);
      if (uvout) { uvout[0] = uv[0]; uvout[1] = uv[1]; *qq = q; return 1; }
      el_envlight__bilerp(l, uv[0], uv[1], rgb);
    }
  }
  *qq = q;
  return 0;
}
static int el_envlight__patch_finish(const el_envlight *l, int i, int r, float fu, float fv, float wi[3], float rgb[3], float *pdf, float *uvout) {
  el_envlight__ploc q;
  return el_envlight__patch_finish_at(l, i, r, fu, fv, wi, rgb, pdf, uvout, &q);
}

/* <<Pick a patch>>: the light's sampler over the patch table (guide: CDF inversion's patch) */
static inline void el_envlight__patch_pick(const el_envlight *l, const float uu[2], int *i, int *r, float *fu, float *fv) {
  float pb;
  if (l->sampler == EL_ENVLIGHT_SAMPLER_CDF) el_distribution2d_sample_bins(&l->dist, uu[0], uu[1], i, r, fu, fv, &pb);
  else el_distribution2d_fast_sample_bins(&l->fast, uu[0], uu[1], i, r, fu, fv, &pb);
}

/* sample_li in importance mode BILINEAR (the tables are built) */
static EL_ENVLIGHT__NOINLINE void el_envlight__patch_sample(const el_envlight *l, const float uu[2], float wi[3], float rgb[3], float *pdf) {
  float fu, fv;
  int i, r;
  if (!l->warp || l->warp->all_zero) { /* nothing emits */
    wi[0] = l->to_world[2]; wi[1] = l->to_world[5]; wi[2] = l->to_world[8]; *pdf = 0.0f;
    if (rgb) rgb[0] = rgb[1] = rgb[2] = 0.0f;
    return;
  }
  el_envlight__patch_pick(l, uu, &i, &r, &fu, &fv);
  el_envlight__patch_finish(l, i, r, fu, fv, wi, rgb, pdf, NULL);
}

/* sample_li_n in importance mode BILINEAR, the tables built: up to 16 samples at a time in passes that
 * start the next pass's cache misses for all of them (as the other modes' sample_li_n): (1) the row
 * search in the small marginal, then the guide entry of the row; (2) the CDF entries it points to; (3)
 * the patch (sample_li's own pick), then its record; (4) the sample (sample_li's own code), then the
 * texels of its patch; (5) the radiance, le(wi). The results are sample_li's, bit for bit. */
static void el_envlight__patch_sample_n(const el_envlight *l, int n, const float *u, float *wi, float *rgb, float *pdf) {
#if defined(__GNUC__) || defined(__clang__)
  const el_distribution2d_fast *f = &l->fast;
  int i0, m, k;
  if (l->warp->all_zero || l->sampler != EL_ENVLIGHT_SAMPLER_GUIDE) {
    for (k = 0; k < n; ++k) el_envlight__patch_sample(l, u + 2 * k, wi + 3 * k, rgb ? rgb + 3 * k : NULL, pdf + k);
    return;
  }
  for (i0 = 0; i0 < n; i0 += 16) {
    size_t gix[16];
    int pi[16], pr[16];
    float pfu[16], pfv[16], uv[32];
    const float *tx[16][4];
    unsigned char later[16];
    m = n - i0 < 16 ? n - i0 : 16;
    for (k = 0; k < m; ++k) { /* (1) */
      const float *uk = u + 2 * (i0 + k);
      uint32_t g, kv;
      size_t v;
      gix[k] = (size_t)-1;
      if (!el_distribution2d_u_in_range(uk[0], uk[1])) continue;
      g = f->guide_v[(size_t)(int64_t)(uk[1] * f->gv_scale)];
      if (g & EL_DISTRIBUTION__GUIDE_CROWDED) continue;
      kv = (uint32_t)(int32_t)(uk[1] * 16777216.0f);
      for (v = g; f->marginal[v + 1] <= kv; ++v) {}
      gix[k] = v * f->guide_stride + (size_t)(int64_t)(uk[0] * f->gu_scale);
      __builtin_prefetch(f->guide_u + gix[k]);
      __builtin_prefetch(f->cdf + v * f->row_stride); /* (the row's start, for the search's first step) */
    }
    for (k = 0; k < m; ++k) { /* (2) */
      uint32_t g;
      if (gix[k] == (size_t)-1) continue;
      g = f->guide_u[gix[k]];
      if (!(g & EL_DISTRIBUTION__GUIDE_CROWDED)) __builtin_prefetch(f->cdf + (gix[k] / f->guide_stride) * f->row_stride + g + 1);
    }
    for (k = 0; k < m; ++k) { /* (3) */
      el_envlight__patch_pick(l, u + 2 * (i0 + k), &pi[k], &pr[k], &pfu[k], &pfv[k]);
      __builtin_prefetch(l->pdf_table + 4 * ((size_t)pr[k] * (size_t)l->width + (size_t)pi[k]));
    }
    for (k = 0; k < m; ++k) { /* (4); the radiance of a fast-path sample waits for (5), its texels prefetched */
      const int j = i0 + k;
      later[k] = (unsigned char)el_envlight__patch_finish(l, pi[k], pr[k], pfu[k], pfv[k], wi + 3 * j, rgb ? rgb + 3 * j : NULL, pdf + j, uv + 2 * k);
      if (later[k]) { /* (uv becomes the weights fx, fy) */
        int q;
        el_envlight__bilerp_texels(l, uv[2 * k], uv[2 * k + 1], tx[k], uv + 2 * k, uv + 2 * k + 1);
        for (q = 0; q < 4; ++q) __builtin_prefetch(tx[k][q] + 2 * (q & 1)); /* (as the other modes' batches) */
      }
    }
    for (k = 0; k < m; ++k) /* (5) the radiance, as el_envlight__patch_finish forms it (el_envlight__bilerp) */
      if (later[k]) el_envlight__bilerp_at(tx[k], uv[2 * k], uv[2 * k + 1], rgb + 3 * (i0 + k));
  }
#else
  int k;
  for (k = 0; k < n; ++k) el_envlight__patch_sample(l, u + 2 * k, wi + 3 * k, rgb ? rgb + 3 * k : NULL, pdf + k);
#endif
}

/* >> hot spots and the mixture sampler (issue 22; NOTES ON HOT SPOTS) */

/* the rest x cosine part's helpers (defined with the cells, below) */
static float el_envlight__hot_bounds(const el_envlight_hotspots *h, const float *nl, float *bm);
/* the cosine bound of a cell from ca = n . centre (the same float expression in the loop and the pdf) */
static inline float el_envlight__hot_b(float ca, float cr, float sr) {
  float sa = 1.0f - ca * ca, b = ca * cr + el_envlight__sqrt(sa > 0.0f ? sa : 0.0f) * sr;
  b = ca >= cr ? 1.0f : b;       /* the normal's direction lies within the cone */
  return b > 1e-3f ? b : 1e-3f;  /* a floor: every cell with rest mass stays reachable */
}
static int el_envlight__hot_normal(const el_envlight *l, const float n[3], float nl[3]);
#define EL_ENVLIGHT__HOT_ROW(cols) ((size_t)EL_ENVLIGHT__GUIDE_E + (size_t)(cols) + 1u) /* uint16 entries of a row */
/* index i of a cell table's CDF c[0..n] (guide g) with c[i] <= k < c[i + 1]: the guide for n <= 256 (what
 * el_envlight__guide_build allows), else the binary search: the same i */
static inline int el_envlight__hot_search(const uint16_t *c, int n, const uint8_t *g, uint32_t k) {
  return n <= 256 ? el_envlight__search_guided(c, n, g, k) : el_envlight__search16(c, n, k < EL_ENVLIGHT__CELL_UNITS - 1u ? k : EL_ENVLIGHT__CELL_UNITS - 1u);
}

static int el_envlight__hot_cell_of_uv(const el_envlight_hotspots *h, int iu, int iv);

/* The importance bin pdf_li finds for a world direction (its own bin search, el_envlight__pdf_core's
 * first half: keep the two in step), as iv * nu + iu; -1 for a direction pdf_li gives 0 (zero, NaN,
 * infinite). The chi-square tests of tests/test_envlight_sun.c fail if they disagree. */
static inline void el_envlight__hot_find_bin(const el_envlight *l, const float d[3], float r, uint32_t *iu, uint32_t *iv) {
  /* pdf_core's bin finders for the light-space d, r = sqrt(d0^2 + d1^2) */
  float pu = 2.0f - copysignf(1.0f + d[0] / (fabsf(d[0]) + fabsf(d[1]) + FLT_MIN), d[1]), t;
  size_t c;
  pu = pu < 3.99999976f ? pu : 3.99999976f;
  c = (size_t)(int64_t)(pu * l->u_cell_scale);
  *iu = (uint32_t)l->u_base[c] + (pu >= l->u_edge[c]);
  t = 1.0f - d[2] / (r + fabsf(d[2]));
  c = (size_t)(int64_t)(t * l->v_cell_scale);
  *iv = (uint32_t)l->v_base[c] + (t >= l->v_edge[c]);
}
static int64_t el_envlight__hot_bin(const el_envlight *l, const float dir[3]) {
  float d[3];
  uint32_t iu, iv;
  if (!el_envlight__to_light_dir(l, dir, d)) return -1; /* as pdf_li: rescaled in world space if needed */
  el_envlight__hot_find_bin(l, d, el_envlight__sqrt(d[0] * d[0] + d[1] * d[1]), &iu, &iv);
  return (int64_t)iv * (int64_t)l->dist.nu + (int64_t)iu;
}

/* pdf_li's inline path up to its table read (EL_ENVLIGHT__HOT_PDF, a normal-length direction:
 * el_envlight__pdf_core's own arithmetic): the bin (iu, iv), the direction's length and r = sin(theta)
 * len with pdf_li's floor, so that pdf_li = pdf_table[bin] x len / r bit for bit. 0 elsewhere. */
static int el_envlight__hot_bin_core(const el_envlight *l, const float dir[3], int *biu, int *biv, float *blen, float *br) {
  float d[3], r2, len2, r, len;
  uint32_t iu, iv;
#if EL_ENVLIGHT__ATOMICS
  int hot = (__atomic_load_n(&l->hot, __ATOMIC_ACQUIRE) & EL_ENVLIGHT__HOT_PDF) != 0;
#else
  int hot = (l->hot & EL_ENVLIGHT__HOT_PDF) != 0;
#endif
  if (!hot) return 0;
  el_envlight__to_light(l, dir, d);
  r2 = d[0] * d[0] + d[1] * d[1];
  len2 = r2 + d[2] * d[2];
  if (!(len2 >= FLT_MIN && len2 <= FLT_MAX)) return 0;
  r = el_envlight__sqrt(r2); len = el_envlight__sqrt(len2);
  el_envlight__hot_find_bin(l, d, r, &iu, &iv);
  *biu = (int)iu; *biv = (int)iv; *blen = len;
  *br = r > EL_ENVLIGHT__SIN_MIN * len ? r : EL_ENVLIGHT__SIN_MIN * len;
  return 1;
}

/* pdf_li(dir) and the bin it reads (iu, iv; -1 where el_envlight__hot_bin gives -1), from one bin search:
 * on pdf_li's inline path el_envlight__hot_bin_core, so both equal pdf_li's and hot_bin's bit for bit;
 * elsewhere those two calls. (Issue 22: the rest x cosine's pdf made the search twice, a third of its cost.) */
static float el_envlight__hot_pdf_li_bin(const el_envlight *l, const float dir[3], int *biu, int *biv) {
  float p, len, r;
  int64_t b;
  if (el_envlight__hot_bin_core(l, dir, biu, biv, &len, &r))
    return l->pdf_table[(size_t)*biv * (size_t)l->dist.nu + (size_t)*biu] * len / r;
  p = el_envlight_pdf_li(l, dir);
  b = p > 0.0f ? el_envlight__hot_bin(l, dir) : -1;
  *biu = b < 0 ? -1 : (int)(b % l->dist.nu); *biv = b < 0 ? -1 : (int)(b / l->dist.nu);
  return p;
}

/* The bin pdf_li reads for dir (iu, iv) and the factor it applies to the bin's table entry (len / r: 1 /
 * sin(theta) with pdf_li's floor), without reading the table (el_envlight__hot_bin_core); elsewhere (an
 * odd length, a mapping without the inline pdf) pdf_li / its table entry. Returns 0 where pdf_li is 0.
 * (Issue 22: the rest x cosine part's pdf comes from its cell tables, which its sample has just read, not
 * from the light's pdf table: one random read less per sample.) */
static int el_envlight__hot_locate(const el_envlight *l, const float dir[3], int *biu, int *biv, float *isin) {
  float p, len, r, e;
  if (el_envlight__hot_bin_core(l, dir, biu, biv, &len, &r)) { *isin = len / r; return 1; }
  p = el_envlight__hot_pdf_li_bin(l, dir, biu, biv); /* (its slow path: the inline one just failed) */
  if (!(p > 0.0f) || *biu < 0) return 0;
  e = l->pdf_table[(size_t)*biv * (size_t)l->dist.nu + (size_t)*biu];
  if (!(e > 0.0f)) return 0;
  *isin = p / e;
  return 1;
}

/* Which part holds bin (iu, iv): a spot index, or h->count for the rest. */
static int el_envlight__hot_part_uv(const el_envlight_hotspots *h, int iu, int iv) {
  int k;
  for (k = 0; k < h->count; ++k) {
    const int *rc = h->rect[k];
    int x = iu - rc[0], y = iv - rc[1];
    if (x < 0) x += h->nu;
    if (x < rc[2] && y >= 0 && y < rc[3] && h->mask[k][(size_t)y * (size_t)rc[2] + (size_t)x]) return k;
  }
  return h->count;
}

/* The normalised weights a[0..count] (count = the rest); 0 when they are the defaults. */
static int el_envlight__hot_weights(const el_envlight_hotspots *h, const el_envlight_mix_weights *w, double a[EL_ENVLIGHT_HOTSPOT_MAX + 1]) {
  double sum = 0.0;
  int k;
  if (!w) return 0;
  for (k = 0; k <= h->count; ++k) {
    float x = k < h->count ? w->spot[k] : w->rest;
    if (!(x >= 0.0f && x <= FLT_MAX)) return 0; /* NaN, negative or infinite: the defaults */
    a[k] = h->share_d[k] > 0.0 ? (double)x : 0.0; /* a part without mass cannot be drawn */
    sum += a[k];
  }
  if (!(sum > 0.0)) return 0;
  for (k = 0; k <= h->count; ++k) a[k] /= sum;
  return 1;
}

/* h made for this light, with at least one spot and tables usable */
static int el_envlight__hot_usable(const el_envlight *l, const el_envlight_hotspots *h) {
  return h && h->count > 0 && l->width > 0 && el_envlight__ensure(l) && h->key == l->pdf_table &&
         h->nu == l->dist.nu && h->nv == l->dist.nv;
}

/* The world direction of bin (iu, iv) at fractions (fu, fv) of the light's own grid, as sample_li builds
 * it: the fractions kept the margin inside the bin (as el_envlight__sample_bin keeps them), then the
 * direction tables (without their pdf: the callers make theirs) or the (u, v) mapping. uv: the sample's
 * own (u, v) where the tables are exact (table_done: a signed-permutation matrix), for its radiance as
 * sample_li_finish looks it up; else uv[0] = -1. Both hot-spot samplers go through here; with and without
 * SSE the same operations (el_envlight__dir_sse, el_envlight__dir_scalar). */
static void el_envlight__hot_bin_to_world(const el_envlight *l, int iu, int iv, float fu, float fv, float wi[3], float uv[2]) {
  uv[0] = -1.0f;
  fu = fu > l->u_margin ? fu : l->u_margin;
  fu = fu < l->u_margin_hi ? fu : l->u_margin_hi;
  fv = fv > l->v_margin ? fv : l->v_margin;
  fv = fv < l->v_margin_hi ? fv : l->v_margin_hi;
  if (l->dir_tables) { /* (the tables clamp to the same margins: fu and fv stay as they are) */
#if EL_ENVLIGHT__SSE
    float p;
    (void)el_envlight__dir_sse(l, l->row_tab + 16 * (size_t)iv, l->col_tab + 8 * (size_t)iu, _mm_movelh_ps(_mm_set1_ps(fv), _mm_set1_ps(fu)), 1.0f, wi, &p);
#else
    (void)el_envlight__dir_scalar(l, iu, iv, &fu, &fv, wi);
#endif
    if (l->table_done) { uv[0] = ((float)iu + fu) * l->dist.u_width; uv[1] = ((float)iv + fv) * l->dist.v_width; }
  } else {
    float d[3], pu = ((float)iu + fu) * l->dist.u_width, pv = ((float)iv + fv) * l->dist.v_width;
    float st = ((float)(l->dist.nv - 1 - iv) + (1.0f - fv)) * l->dist.v_width;
    el_envlight__uvp_to_dir(pu, pv, pv < st ? pv : st, d);
    el_envlight__to_world(l, d, wi);
  }
}

/* A mixture sample's radiance: le at the sample's own (u, v) where el_envlight__hot_bin_to_world gave it
 * (a signed-permutation matrix: sample_li's choice, without le's atan pair), else le(wi); 0 for pdf 0. */
static void el_envlight__hot_rgb(const el_envlight *l, const float wi[3], const float uv[2], float pdf, float rgb[3]) {
  if (!rgb) return;
  if (!(pdf > 0.0f)) rgb[0] = rgb[1] = rgb[2] = 0.0f;
  else if (uv[0] >= 0.0f) el_envlight__lookup(l, uv[0], uv[1], rgb);
  else el_envlight_le(l, wi, rgb);
}

/* pdf_li_mix with usable h and normalised weights a */
static float el_envlight__hot_pdf(const el_envlight *l, const el_envlight_hotspots *h, const double *a, const float dir[3]) {
  float p;
  int k, iu, iv;
  p = el_envlight__hot_pdf_li_bin(l, dir, &iu, &iv); /* (pdf_li and hot_bin from one search) */
  if (!(p > 0.0f) || iu < 0) return 0.0f;
  k = el_envlight__hot_part_uv(h, iu, iv);
  p = (float)((double)p * (a[k] / h->share_d[k]));
  return p < FLT_MAX ? p : FLT_MAX;
}

EL_DEF float el_envlight_pdf_li_mix(const el_envlight *l, const el_envlight_hotspots *h,
                                    const el_envlight_mix_weights *w, const float dir[3]) {
  double a[EL_ENVLIGHT_HOTSPOT_MAX + 1];
  if (!el_envlight__hot_usable(l, h) || !el_envlight__hot_weights(h, w, a)) return el_envlight_pdf_li(l, dir);
  return el_envlight__hot_pdf(l, h, a, dir);
}

EL_DEF void el_envlight_sample_li_mix(const el_envlight *l, const el_envlight_hotspots *h,
                                      const el_envlight_mix_weights *w, const float u[2], float wi[3],
                                      float rgb[3], float *pdf) {
  double a[EL_ENVLIGHT_HOTSPOT_MAX + 1], c = 0.0, u0;
  float fu, fv, pb, uu, uv[2];
  int k, iu, iv;
  if (!el_envlight__hot_usable(l, h) || !el_envlight__hot_weights(h, w, a)) {
    el_envlight_sample_li(l, u, wi, rgb, pdf);
    return;
  }
  /* pick the part with u[0] and remap it to [0, 1) within the part */
  u0 = (double)el_envlight__clamp_u(u[0]);
  for (k = 0; k < h->count; ++k) {
    if (a[k] > 0.0 && u0 < c + a[k]) break;
    c += a[k];
  }
  if (k == h->count && !(a[k] > 0.0)) { /* rounding past the last part of mass: the last one with weight */
    for (k = h->count; k > 0 && !(a[k] > 0.0); --k) {}
    c = 1.0 - a[k];
  }
  uu = (float)((u0 - c) / a[k]);
  uu = el_envlight__clamp_u(uu);
  if (k == h->count && h->rest_fast_ok) el_distribution2d_fast_sample_bins(&h->rest_fast, uu, u[1], &iu, &iv, &fu, &fv, &pb);
  else el_distribution2d_sample_bins(&h->dist[k], uu, u[1], &iu, &iv, &fu, &fv, &pb);
  if (k < h->count) {
    iu += h->rect[k][0];
    if (iu >= h->nu) iu -= h->nu;
    iv += h->rect[k][1];
  }
  /* <<Compute direction for infinite light sample>>: sample_li's own construction for this bin */
  el_envlight__hot_bin_to_world(l, iu, iv, fu, fv, wi, uv);
  *pdf = el_envlight__hot_pdf(l, h, a, wi);
  if (!(*pdf > 0.0f) && !l->exact_transform) { /* rounded into a bin without mass near a pole: its centre (as sample_li_finish) */
    el_envlight__hot_bin_to_world(l, iu, iv, 0.5f, 0.5f, wi, uv);
    *pdf = el_envlight__hot_pdf(l, h, a, wi);
  }
  el_envlight__hot_rgb(l, wi, uv, *pdf, rgb);
}

EL_DEF void el_envlight_sample_li_mix_n(const el_envlight *l, const el_envlight_hotspots *h,
                                        const el_envlight_mix_weights *w, int n, const float *u, float *wi,
                                        float *rgb, float *pdf) {
  double a[EL_ENVLIGHT_HOTSPOT_MAX + 1];
  int i;
  if (n <= 0) return;
  if (!el_envlight__hot_usable(l, h) || !el_envlight__hot_weights(h, w, a)) {
    el_envlight_sample_li_n(l, n, u, wi, rgb, pdf);
    return;
  }
  for (i = 0; i < n; ++i) el_envlight_sample_li_mix(l, h, w, u + 2 * i, wi + 3 * i, rgb ? rgb + 3 * i : NULL, pdf + i);
}

/* the parts' weights for the cosine mixture: normalised weights, or the shares (defaults) */
static void el_envlight__hot_weights_cos(const el_envlight_hotspots *h, const el_envlight_mix_weights *w, double *a) {
  int k;
  if (el_envlight__hot_weights(h, w, a)) return;
  for (k = 0; k <= h->count; ++k) a[k] = h->share_d[k];
}

/* The rest x cosine part's pdf of a rest bin (iu, iv) of cell c: the part's weight a_r x the cell's share
 * B_c m_c / S(n) x the bin's share in the cell (its two integer widths / 2^30) over the bin's solid angle
 * (nu nv / (2 pi^2) x isin, as pdf_li). 0 for a bin without rest mass (a spot's, or a black one). */
static float el_envlight__hot_rest_pdf(const el_envlight_hotspots *h, double ar, const float *nl, float s,
                                       int c, int iu, int iv, float isin) {
  const float *q = h->cell_cone;
  const uint16_t *t = h->cell_tab + h->cell_off[c], *row;
  size_t nc = (size_t)h->cells_u * (size_t)h->cells_v, cc = (size_t)c;
  int cu = c % h->cells_u, cv = c / h->cells_u, rows = h->cell_v0[cv + 1] - h->cell_v0[cv];
  int cols = h->cell_u0[cu + 1] - h->cell_u0[cu], y = iv - h->cell_v0[cv], x = iu - h->cell_u0[cu];
  uint32_t wv, wu;
  double bnd = 1.0, p;
  row = t + EL_ENVLIGHT__HOT_ROW(rows) + (size_t)y * EL_ENVLIGHT__HOT_ROW(cols) + EL_ENVLIGHT__GUIDE_E;
  wv = (uint32_t)t[EL_ENVLIGHT__GUIDE_E + (size_t)y + 1] - t[EL_ENVLIGHT__GUIDE_E + (size_t)y];
  wu = (uint32_t)row[x + 1] - row[x];
  if (!(wv * wu > 0u) || !(s > 0.0f)) return 0.0f;
  if (nl) bnd = el_envlight__hot_b(nl[0] * q[cc] + nl[1] * q[nc + cc] + nl[2] * q[2 * nc + cc], q[3 * nc + cc], q[4 * nc + cc]);
  p = ar * bnd * (double)q[5 * nc + cc] / (double)s * (double)(wv * wu) *
      ((double)h->nu * (double)h->nv / (2.0 * EL_ENVLIGHT__PI * EL_ENVLIGHT__PI * 1073741824.0)) * (double)isin;
  return p < (double)FLT_MAX ? (float)p : FLT_MAX;
}

static float el_envlight__hot_pdf_cos(const el_envlight *l, const el_envlight_hotspots *h, const double *a, const float *nl,
                                      float s, const float dir[3]) {
  float p, isin;
  int k, iu, iv;
  if (!h->cell_tab) { /* no rest: the spots alone */
    p = el_envlight__hot_pdf_li_bin(l, dir, &iu, &iv);
    if (!(p > 0.0f) || iu < 0) return 0.0f;
    k = el_envlight__hot_part_uv(h, iu, iv);
    p = (float)((double)p * (a[k] / h->share_d[k]));
    return p < FLT_MAX ? p : FLT_MAX;
  }
  if (!el_envlight__hot_locate(l, dir, &iu, &iv, &isin)) return 0.0f;
  p = el_envlight__hot_rest_pdf(h, a[h->count], nl, s, el_envlight__hot_cell_of_uv(h, iu, iv), iu, iv, isin);
  if (p > 0.0f) return p;
  k = el_envlight__hot_part_uv(h, iu, iv); /* (no rest mass there: a spot's bin, or none) */
  if (k == h->count) return 0.0f;
  p = l->pdf_table[(size_t)iv * (size_t)l->dist.nu + (size_t)iu] * isin; /* pdf_li, as el_envlight__hot_pdf_li_bin forms it */
  p = (float)((double)p * (a[k] / h->share_d[k]));
  return p < FLT_MAX ? p : FLT_MAX;
}

EL_DEF float el_envlight_pdf_li_mix_cos(const el_envlight *l, const el_envlight_hotspots *h,
                                        const el_envlight_mix_weights *w, const float n[3], const float dir[3]) {
  double a[EL_ENVLIGHT_HOTSPOT_MAX + 1];
  float nl[3], s = 0.0f;
  int hn;
  if (!el_envlight__hot_usable(l, h)) return el_envlight_pdf_li_cos(l, n, dir);
  el_envlight__hot_weights_cos(h, w, a);
  hn = el_envlight__hot_normal(l, n, nl);
  if (h->cell_tab) s = el_envlight__hot_bounds(h, hn ? nl : NULL, NULL);
  return el_envlight__hot_pdf_cos(l, h, a, hn ? nl : NULL, s, dir);
}

EL_DEF void el_envlight_mix_cos_prepare(const el_envlight *l, const el_envlight_hotspots *h, const el_envlight_mix_weights *w,
                                        const float n[3], el_envlight_mix_cos_table *t) {
  int k;
  t->n[0] = n ? n[0] : 0.0f; t->n[1] = n ? n[1] : 0.0f; t->n[2] = n ? n[2] : 0.0f;
  t->usable = el_envlight__hot_usable(l, h);
  t->hn = 0; t->s = 0.0f; t->nl[0] = t->nl[1] = t->nl[2] = 0.0f;
  for (k = 0; k <= EL_ENVLIGHT_HOTSPOT_MAX; ++k) t->a[k] = 0.0;
  if (!t->usable) return;
  el_envlight__hot_weights_cos(h, w, t->a);
  t->hn = el_envlight__hot_normal(l, t->n, t->nl);
  if (h->cell_tab) t->s = el_envlight__hot_bounds(h, t->hn ? t->nl : NULL, t->bm);
}

EL_DEF float el_envlight_pdf_li_mix_cos_table(const el_envlight *l, const el_envlight_hotspots *h, const el_envlight_mix_cos_table *tab,
                                              const float dir[3]) {
  if (!tab->usable || !el_envlight__hot_usable(l, h)) return el_envlight_pdf_li_cos(l, tab->n, dir);
  return el_envlight__hot_pdf_cos(l, h, tab->a, tab->hn ? tab->nl : NULL, tab->s, dir);
}

EL_DEF void el_envlight_sample_li_mix_cos(const el_envlight *l, const el_envlight_hotspots *h,
                                          const el_envlight_mix_weights *w, const float n[3], const float u[2],
                                          float wi[3], float rgb[3], float *pdf) {
  el_envlight_mix_cos_table t;
  if (!el_envlight__hot_usable(l, h)) { el_envlight_sample_li_cos(l, n, u, wi, rgb, pdf); return; }
  el_envlight_mix_cos_prepare(l, h, w, n, &t);
  el_envlight_sample_li_mix_cos_table(l, h, &t, u, wi, rgb, pdf);
}

EL_DEF void el_envlight_sample_li_mix_cos_table(const el_envlight *l, const el_envlight_hotspots *h, const el_envlight_mix_cos_table *tab,
                                                const float u[2], float wi[3], float rgb[3], float *pdf) {
  const double *a = tab->a;
  const float *nl = tab->nl, *bm = tab->bm, s = tab->s;
  double c = 0.0, u0;
  float fu, fv, pb, uu, uv[2];
  int k, iu, iv, hn = tab->hn, cell = 0;
  if (!tab->usable || !el_envlight__hot_usable(l, h)) { el_envlight_sample_li_cos(l, tab->n, u, wi, rgb, pdf); return; }
  u0 = (double)el_envlight__clamp_u(u[0]);
  for (k = 0; k < h->count; ++k) {
    if (a[k] > 0.0 && u0 < c + a[k]) break;
    c += a[k];
  }
  if (k == h->count && !(a[k] > 0.0 && h->cell_tab && s > 0.0f)) {
    for (k = h->count - 1; k > 0 && !(a[k] > 0.0); --k) {}
    c = 0.0;
    { int t; for (t = 0; t < k; ++t) c += a[t]; }
    if (!(a[k] > 0.0)) { wi[0] = 0.0f; wi[1] = 0.0f; wi[2] = 1.0f; *pdf = 0.0f; if (rgb) rgb[0] = rgb[1] = rgb[2] = 0.0f; return; }
  }
  uu = el_envlight__clamp_u((float)((u0 - c) / a[k]));
  if (k < h->count) {
    el_distribution2d_sample_bins(&h->dist[k], uu, u[1], &iu, &iv, &fu, &fv, &pb);
    iu += h->rect[k][0];
    if (iu >= h->nu) iu -= h->nu;
    iv += h->rect[k][1];
  } else { /* the rest: a cell by its bound x mass (a branch-free search of the running sums), then its
            * row and column from the cell's table (guided searches) */
    int n = h->cells_u * h->cells_v, lo = 0, cu, cv, rows, cols, y, x;
    float t = uu * s, prev, xv, xu;
    const uint16_t *tb, *rc, *row;
    while (n > 1) { int half = n >> 1; lo = bm[lo + half - 1] > t ? lo : lo + half; n -= half; }
    cell = lo;
    while (cell > 0 && !(h->cell_mass[cell] > 0.0)) --cell; /* never a cell without mass */
    while (!(h->cell_mass[cell] > 0.0) && cell + 1 < h->cells_u * h->cells_v) ++cell;
    prev = cell > 0 ? bm[cell - 1] : 0.0f;
    uu = el_envlight__clamp_u((t - prev) / (bm[cell] - prev > 0.0f ? bm[cell] - prev : 1.0f));
    cu = cell % h->cells_u; cv = cell / h->cells_u;
    rows = h->cell_v0[cv + 1] - h->cell_v0[cv]; cols = h->cell_u0[cu + 1] - h->cell_u0[cu];
    tb = h->cell_tab + h->cell_off[cell];
    rc = tb + EL_ENVLIGHT__GUIDE_E;
    xv = el_envlight__clamp_u(u[1]) * (float)EL_ENVLIGHT__CELL_UNITS; xu = uu * (float)EL_ENVLIGHT__CELL_UNITS;
    y = el_envlight__hot_search(rc, rows, (const uint8_t *)tb, (uint32_t)xv);
    row = tb + EL_ENVLIGHT__HOT_ROW(rows) + (size_t)y * EL_ENVLIGHT__HOT_ROW(cols);
    x = el_envlight__hot_search(row + EL_ENVLIGHT__GUIDE_E, cols, (const uint8_t *)row, (uint32_t)xu);
    row += EL_ENVLIGHT__GUIDE_E;
    fv = (xv - (float)rc[y]) / (float)(rc[y + 1] - rc[y]);
    fu = (xu - (float)row[x]) / (float)(row[x + 1] - row[x]);
    iu = h->cell_u0[cu] + x;
    iv = h->cell_v0[cv] + y;
  }
  el_envlight__hot_bin_to_world(l, iu, iv, fu, fv, wi, uv);
  *pdf = el_envlight__hot_pdf_cos(l, h, a, hn ? nl : NULL, s, wi);
  if (!(*pdf > 0.0f) && !l->exact_transform) { /* rounded into a bin without mass near a pole: its centre (as sample_li_finish) */
    el_envlight__hot_bin_to_world(l, iu, iv, 0.5f, 0.5f, wi, uv);
    *pdf = el_envlight__hot_pdf_cos(l, h, a, hn ? nl : NULL, s, wi);
  }
  el_envlight__hot_rgb(l, wi, uv, *pdf, rgb);
}

EL_DEF void el_envlight_hotspots_weights(const el_envlight_hotspots *h, float spot_share, el_envlight_mix_weights *w) {
  int k;
  double s = 0.0;
  if (!w) return;
  memset(w, 0, sizeof *w);
  if (!h || h->count <= 0 || spot_share != spot_share) return;
  spot_share = spot_share > 0.0f ? (spot_share < 1.0f ? spot_share : 1.0f) : 0.0f;
  for (k = 0; k < h->count; ++k) s += h->share_d[k];
  if (!(s > 0.0)) return;
  for (k = 0; k < h->count; ++k) w->spot[k] = (float)((double)spot_share * h->share_d[k] / s);
  w->rest = 1.0f - spot_share;
  if (!(h->share_d[h->count] > 0.0) && spot_share > 0.0f) w->rest = 0.0f;
}

EL_DEF void el_envlight_hotspots_free(el_envlight_hotspots *h) {
  int k;
  if (!h) return;
  if (h->rest_fast_ok) el_distribution2d_fast_free(&h->rest_fast); /* before the distribution it shares */
  for (k = 0; k <= EL_ENVLIGHT_HOTSPOT_MAX; ++k) el_distribution2d_free(&h->dist[k]);
  for (k = 0; k < EL_ENVLIGHT_HOTSPOT_MAX; ++k) { EL_FREE(h->mask[k]); EL_FREE(h->prow[k]); }
  EL_FREE(h->cell_tab); EL_FREE(h->cell_off); EL_FREE(h->cell_of_col); EL_FREE(h->cell_of_row);
  EL_FREE(h->cell_cone); EL_FREE(h->cell_mass);
  memset(h, 0, sizeof *h);
}

/* the light-space direction of bin point (u, v) in bin units */
static void el_envlight__hot_dir(int nu, int nv, double u, double v, double d[3]) {
  double phi = 2.0 * EL_ENVLIGHT__PI * u / nu, th = EL_ENVLIGHT__PI * v / nv;
  d[0] = sin(th) * cos(phi); d[1] = sin(th) * sin(phi); d[2] = cos(th);
}

/* the neighbours of bin (iu, iv): 8 around it (u wraps), and at a pole row the bins half a turn away */
static int el_envlight__hot_neighbours(int nu, int nv, int iu, int iv, int64_t nb[11]) {
  int n = 0, dx, dy;
  for (dy = -1; dy <= 1; ++dy)
    for (dx = -1; dx <= 1; ++dx) {
      int x = iu + dx, y = iv + dy;
      if ((dx == 0 && dy == 0) || y < 0 || y >= nv) continue;
      x = (x % nu + nu) % nu;
      nb[n++] = (int64_t)y * nu + x;
    }
  if (iv == 0 || iv == nv - 1)
    for (dx = -1; dx <= 1; ++dx) nb[n++] = (int64_t)iv * nu + (((iu + nu / 2 + dx) % nu + nu) % nu);
  return n;
}

/* state bits of a bin during the search */
#define EL_ENVLIGHT__HOT_CORE 1u  /* density >= min_radiance x the mean */
#define EL_ENVLIGHT__HOT_WARM 2u  /* density >= min_radiance / 8 x the mean (a core's rim) */
#define EL_ENVLIGHT__HOT_SEEN 4u  /* visited by the first pass (core + rim) */
#define EL_ENVLIGHT__HOT_CSEEN 8u /* visited by the core-only pass */
#define EL_ENVLIGHT__HOT_BUILT 16u /* visited by the build pass */

/* Breadth-first search from seed over bins with a bit of `accept`, marking `seen`; the component's
 * bins go to queue. Returns their number. */
static int64_t el_envlight__hot_grow(int nu, int nv, unsigned char *state, int64_t *queue, int64_t seed, unsigned accept, unsigned seen) {
  int64_t head = 0, tail = 0;
  state[seed] = (unsigned char)(state[seed] | seen);
  queue[tail++] = seed;
  while (head < tail) {
    int64_t q = queue[head++], nbr[11];
    int n = el_envlight__hot_neighbours(nu, nv, (int)(q % nu), (int)(q / nu), nbr), t;
    for (t = 0; t < n; ++t)
      if ((state[nbr[t]] & accept) && !(state[nbr[t]] & seen)) { state[nbr[t]] = (unsigned char)(state[nbr[t]] | seen); queue[tail++] = nbr[t]; }
  }
  return tail;
}

/* A component's share (of the light's total), axis (light space, unit) and half-angle (radians, over its
 * bins' corners and edge midpoints). Returns 0 when its mass is spread too wide for a mean direction. */
static int el_envlight__hot_cone(const float *tab, int nu, int nv, const int64_t *queue, int64_t n, const double *rowk, double total,
                                 double *share, double ax[3], double *half) {
  double d[3], len, cmin = 1.0, s = 0.0;
  int64_t t;
  ax[0] = ax[1] = ax[2] = 0.0;
  for (t = 0; t < n; ++t) {
    int64_t q = queue[t];
    double m = (double)tab[q] * rowk[q / nu];
    el_envlight__hot_dir(nu, nv, (double)(q % nu) + 0.5, (double)(q / nu) + 0.5, d);
    ax[0] += m * d[0]; ax[1] += m * d[1]; ax[2] += m * d[2];
    s += m;
  }
  *share = s / total;
  len = sqrt(ax[0] * ax[0] + ax[1] * ax[1] + ax[2] * ax[2]);
  *half = EL_ENVLIGHT__PI;
  if (!(len > 0.5 * s)) return 0; /* mass spread over far more than a hemisphere: not compact */
  ax[0] /= len; ax[1] /= len; ax[2] /= len;
  for (t = 0; t < n; ++t) {
    int64_t q = queue[t];
    int pu, pv;
    for (pv = 0; pv <= 2; ++pv)
      for (pu = 0; pu <= 2; ++pu) {
        double c;
        el_envlight__hot_dir(nu, nv, (double)(q % nu) + 0.5 * pu, (double)(q / nu) + 0.5 * pv, d);
        c = ax[0] * d[0] + ax[1] * d[1] + ax[2] * d[2];
        if (c < cmin) cmin = c;
      }
  }
  cmin = cmin < 1.0 ? (cmin > -1.0 ? cmin : -1.0) : 1.0;
  *half = acos(cmin);
  return 1;
}

/* The rest x cosine part's cells: cells_u x cells_v rectangles of bins, each with the rest's mass, a
 * bounding cone (centre, cos and sin of its radius: the farthest of 5 x 5 points of the cell, plus a
 * tenth of the cell's larger angle, since the cell's edges bulge between the points) and a table of its
 * rest bins (f: the pdf table with the spots' bins zeroed): in EL_ENVLIGHT__CELL_UNITS (uint16), the
 * cell's rows' CDF with its guide (the product section's el_envlight__guide_build: 8 one-byte buckets),
 * then per row its guide and its CDF over the cell's columns: [g 4][rows + 1] then rows x [g 4][cols + 1].
 * A bin's probability in the cell is its two integer widths / 2^30 (the pdf reads the same entries). */
static el_result el_envlight__hot_cells(el_envlight_hotspots *h, const el_envlight *l, const float *f, const double *rowk, double total) {
  int cu, cv, nu = l->dist.nu, nv = l->dist.nv, i, j, a, b;
  size_t nc, len = 0;
  double *wts = NULL;
  uint32_t *tmp = NULL;
  h->cells_u = nu < 32 ? nu : 32;
  h->cells_v = nv < 16 ? nv : 16;
  nc = (size_t)h->cells_u * (size_t)h->cells_v;
  for (cu = 0; cu <= h->cells_u; ++cu) h->cell_u0[cu] = (int)((int64_t)cu * nu / h->cells_u);
  for (cv = 0; cv <= h->cells_v; ++cv) h->cell_v0[cv] = (int)((int64_t)cv * nv / h->cells_v);
  for (cv = 0; cv < h->cells_v; ++cv)
    for (cu = 0; cu < h->cells_u; ++cu) {
      size_t rows = (size_t)(h->cell_v0[cv + 1] - h->cell_v0[cv]), cols = (size_t)(h->cell_u0[cu + 1] - h->cell_u0[cu]);
      len += EL_ENVLIGHT__HOT_ROW(rows) + rows * EL_ENVLIGHT__HOT_ROW(cols);
    }
  h->cell_cone = (float *)EL_MALLOC(nc * 6 * sizeof(float));
  h->cell_mass = (double *)EL_MALLOC(nc * sizeof(double));
  h->cell_tab = (uint16_t *)EL_MALLOC(len * sizeof(uint16_t));
  h->cell_off = (uint32_t *)EL_MALLOC(nc * sizeof(uint32_t));
  h->cell_of_col = (unsigned char *)EL_MALLOC((size_t)nu);
  h->cell_of_row = (unsigned char *)EL_MALLOC((size_t)nv);
  wts = (double *)EL_MALLOC(((size_t)nu + (size_t)nv) * sizeof(double));
  tmp = (uint32_t *)EL_MALLOC(((size_t)nu + (size_t)nv + 2) * sizeof(uint32_t));
  if (!h->cell_cone || !h->cell_mass || !h->cell_tab || !h->cell_off || !h->cell_of_col || !h->cell_of_row || !wts || !tmp ||
      len > 0xFFFFFFFFu) {
    EL_FREE(wts); EL_FREE(tmp);
    return len > 0xFFFFFFFFu ? EL_ERROR_SIZE_OVERFLOW : EL_ERROR_OUT_OF_MEMORY;
  }
  for (cu = 0; cu < h->cells_u; ++cu) for (i = h->cell_u0[cu]; i < h->cell_u0[cu + 1]; ++i) h->cell_of_col[i] = (unsigned char)cu;
  for (cv = 0; cv < h->cells_v; ++cv) for (j = h->cell_v0[cv]; j < h->cell_v0[cv + 1]; ++j) h->cell_of_row[j] = (unsigned char)cv;
  len = 0;
  for (cv = 0; cv < h->cells_v; ++cv)
    for (cu = 0; cu < h->cells_u; ++cu) {
      int u0 = h->cell_u0[cu], u1 = h->cell_u0[cu + 1], v0 = h->cell_v0[cv], v1 = h->cell_v0[cv + 1];
      size_t c = (size_t)cv * (size_t)h->cells_u + (size_t)cu;
      double m = 0.0, ctr[3] = {0.0, 0.0, 0.0}, vlen, cmin = 1.0, d[3], rad, ext;
      uint16_t *t = h->cell_tab + len, *rc = t + EL_ENVLIGHT__GUIDE_E;
      h->cell_off[c] = (uint32_t)len;
      len += EL_ENVLIGHT__HOT_ROW(v1 - v0) + (size_t)(v1 - v0) * EL_ENVLIGHT__HOT_ROW(u1 - u0);
      for (j = v0; j < v1; ++j) { /* each row: its CDF over the cell's columns, and its weight */
        uint16_t *row = t + EL_ENVLIGHT__HOT_ROW(v1 - v0) + (size_t)(j - v0) * EL_ENVLIGHT__HOT_ROW(u1 - u0);
        double rs = 0.0;
        for (i = u0; i < u1; ++i) { wts[i - u0] = (double)f[(size_t)j * (size_t)nu + (size_t)i]; rs += wts[i - u0]; }
        wts[(size_t)(u1 - u0) + (size_t)(j - v0)] = rs;
        m += rs * rowk[j];
        el_envlight__int_cdf(wts, u1 - u0, EL_ENVLIGHT__CELL_UNITS, tmp);
        for (i = 0; i <= u1 - u0; ++i) row[EL_ENVLIGHT__GUIDE_E + (size_t)i] = (uint16_t)tmp[i];
        memset(row, 0, EL_ENVLIGHT__GUIDE_E * sizeof(uint16_t));
        if (u1 - u0 <= 256) el_envlight__guide_build(row + EL_ENVLIGHT__GUIDE_E, u1 - u0, (uint8_t *)row);
      }
      el_envlight__int_cdf(wts + (u1 - u0), v1 - v0, EL_ENVLIGHT__CELL_UNITS, tmp); /* the rows' CDF */
      for (j = 0; j <= v1 - v0; ++j) rc[j] = (uint16_t)tmp[j];
      memset(t, 0, EL_ENVLIGHT__GUIDE_E * sizeof(uint16_t));
      if (v1 - v0 <= 256) el_envlight__guide_build(rc, v1 - v0, (uint8_t *)t);
      h->cell_mass[c] = m / total;
      h->cell_cone[5 * nc + c] = (float)(m / total);
      for (b = 0; b <= 4; ++b)
        for (a = 0; a <= 4; ++a) {
          el_envlight__hot_dir(nu, nv, u0 + (u1 - u0) * a / 4.0, v0 + (v1 - v0) * b / 4.0, d);
          ctr[0] += d[0]; ctr[1] += d[1]; ctr[2] += d[2];
        }
      vlen = sqrt(ctr[0] * ctr[0] + ctr[1] * ctr[1] + ctr[2] * ctr[2]);
      if (vlen > 0.0) { ctr[0] /= vlen; ctr[1] /= vlen; ctr[2] /= vlen; } else { ctr[0] = 0.0; ctr[1] = 0.0; ctr[2] = 1.0; }
      for (b = 0; b <= 4; ++b)
        for (a = 0; a <= 4; ++a) {
          double cc;
          el_envlight__hot_dir(nu, nv, u0 + (u1 - u0) * a / 4.0, v0 + (v1 - v0) * b / 4.0, d);
          cc = ctr[0] * d[0] + ctr[1] * d[1] + ctr[2] * d[2];
          if (cc < cmin) cmin = cc;
        }
      ext = EL_ENVLIGHT__PI * (u1 - u0 > v1 - v0 ? 2.0 * (u1 - u0) / nu : (double)(v1 - v0) / nv);
      rad = acos(cmin < 1.0 ? (cmin > -1.0 ? cmin : -1.0) : 1.0) + 0.1 * ext;
      if (rad > EL_ENVLIGHT__PI) rad = EL_ENVLIGHT__PI;
      h->cell_cone[c] = (float)ctr[0]; h->cell_cone[nc + c] = (float)ctr[1]; h->cell_cone[2 * nc + c] = (float)ctr[2];
      h->cell_cone[3 * nc + c] = (float)cos(rad); h->cell_cone[4 * nc + c] = (float)sin(rad);
    }
  EL_FREE(wts); EL_FREE(tmp);
  return EL_SUCCESS;
}

/* The cosine bounds of every cell for the light-space normal nl (NULL: 1) times the cell's mass, summed
 * into bm (cumulative; may be NULL); returns their sum S(n). Two loops: the bounds (vectorisable: the
 * cones are stored as arrays), then the running sum. */
static float el_envlight__hot_bounds(const el_envlight_hotspots *h, const float *nl, float *bm) {
  int c, nc = h->cells_u * h->cells_v;
  const float *q = h->cell_cone;
  float s = 0.0f, tmp[32 * 16], *b = bm ? bm : tmp;
  size_t n = (size_t)nc;
  if (nl) {
    float x = nl[0], y = nl[1], z = nl[2];
    for (c = 0; c < nc; ++c) {
      size_t i = (size_t)c;
      b[c] = el_envlight__hot_b(x * q[i] + y * q[n + i] + z * q[2 * n + i], q[3 * n + i], q[4 * n + i]) * q[5 * n + i];
    }
  } else
    for (c = 0; c < nc; ++c) b[c] = q[5 * n + (size_t)c];
  for (c = 0; c < nc; ++c) { s += b[c]; b[c] = s; }
  return s;
}

/* the light-space unit normal of a world normal; 0 for a zero, NaN or infinite one */
static int el_envlight__hot_normal(const el_envlight *l, const float n[3], float nl[3]) {
  float len;
  if (!n || !el_envlight__to_light_dir(l, n, nl)) return 0;
  len = sqrtf(nl[0] * nl[0] + nl[1] * nl[1] + nl[2] * nl[2]);
  if (!(len > 0.0f) || !(len <= FLT_MAX)) return 0;
  nl[0] /= len; nl[1] /= len; nl[2] /= len;
  return 1;
}

/* the cell of bin (iu, iv) */
static int el_envlight__hot_cell_of_uv(const el_envlight_hotspots *h, int iu, int iv) {
  return (int)h->cell_of_row[iv] * h->cells_u + (int)h->cell_of_col[iu];
}

/* Keep a candidate among the max_spots largest shares >= min_share (sorted, largest first). */
static void el_envlight__hot_keep(double share, float min_share, int64_t seed, unsigned accept, int max_spots, int *found,
                                  double *cand_share, int64_t *cand_seed, unsigned *cand_accept) {
  int s, ins;
  if (share < (double)min_share) return;
  if (*found == max_spots && !(share > cand_share[*found - 1])) return;
  ins = *found < max_spots ? (*found)++ : *found - 1;
  for (s = ins; s > 0 && cand_share[s - 1] < share; --s) {
    cand_share[s] = cand_share[s - 1]; cand_seed[s] = cand_seed[s - 1]; cand_accept[s] = cand_accept[s - 1];
  }
  cand_share[s] = share; cand_seed[s] = seed; cand_accept[s] = accept;
}

/* spot k's public description (the light-space axis ax to world) and share; h->count = k + 1 */
static void el_envlight__hot_set_spot(el_envlight_hotspots *h, const el_envlight *l, int k, const double ax[3], double half, double share, int64_t bins) {
  float la[3], wa[3];
  la[0] = (float)ax[0]; la[1] = (float)ax[1]; la[2] = (float)ax[2];
  el_envlight__to_world(l, la, wa);
  h->spot[k].axis[0] = wa[0]; h->spot[k].axis[1] = wa[1]; h->spot[k].axis[2] = wa[2];
  h->spot[k].half_angle = (float)half;
  h->spot[k].share = (float)share;
  h->spot[k].bins = (int)bins;
  h->share_d[k] = share;
  h->count = k + 1;
}

/* Importance BILINEAR: spot k's rectangle of le()'s patches around the light-space cone (ax, half), and
 * its rows' CDF (NOTES ON HOT SPOTS 6) */
static el_result el_envlight__hot_patch_rect(el_envlight_hotspots *h, const el_envlight *l, int k, const double ax[3], double half) {
  int w = l->width, hh = l->height, r0, r1, i0 = 0, cols = w, rows, j;
  double c = ax[2] < 1.0 ? (ax[2] > -1.0 ? ax[2] : -1.0) : 1.0, th = acos(c), ph = atan2(ax[1], ax[0]);
  double a = half + EL_ENVLIGHT__PI / hh, tmin = th - a, tmax = th + a, v, mass;
  uint64_t *C;
  if (ph < 0.0) ph += 2.0 * EL_ENVLIGHT__PI;
  /* patch row r spans v in [(r - 0.5) / h, (r + 0.5) / h] (the pole rows half) */
  v = tmin / EL_ENVLIGHT__PI * hh + 0.5; r0 = tmin <= 0.0 ? 0 : (int)(v < hh ? v : hh);
  v = tmax / EL_ENVLIGHT__PI * hh + 0.5; r1 = tmax >= EL_ENVLIGHT__PI ? hh : (int)(v < hh ? v : hh);
  if (tmin > 0.0 && tmax < EL_ENVLIGHT__PI) { /* no pole: the cone's phi extent, one column more each side */
    double s = sin(a) / sin(th), dphi = (s < 1.0 ? asin(s) : 0.5 * EL_ENVLIGHT__PI) + 2.0 * EL_ENVLIGHT__PI / w, u0, u1;
    if (s < 1.0 && dphi < EL_ENVLIGHT__PI) { /* patch column i spans u in [(i + 0.5) / w, (i + 1.5) / w] */
      u0 = (ph - dphi) / (2.0 * EL_ENVLIGHT__PI) * w - 0.5; u1 = (ph + dphi) / (2.0 * EL_ENVLIGHT__PI) * w - 0.5;
      i0 = (int)floor(u0);
      cols = (int)floor(u1) - i0 + 1;
      if (cols >= w) { cols = w; i0 = 0; }
      i0 = ((i0 % w) + w) % w;
    }
  }
  rows = r1 - r0 + 1;
  C = (uint64_t *)EL_MALLOC(((size_t)rows + 1) * sizeof(uint64_t));
  if (!C) return EL_ERROR_OUT_OF_MEMORY;
  C[0] = 0;
  for (j = 0; j < rows; ++j) {
    const uint32_t *rc = l->dist.cdf + (size_t)(r0 + j) * ((size_t)w + 1);
    uint64_t wv = l->dist.marginal[r0 + j + 1] - l->dist.marginal[r0 + j], W;
    W = i0 + cols <= w ? (uint64_t)(rc[i0 + cols] - rc[i0]) : (uint64_t)(rc[w] - rc[i0]) + (uint64_t)(rc[i0 + cols - w] - rc[0]);
    C[j + 1] = C[j] + wv * W;
  }
  h->prow[k] = C;
  h->prect[k][0] = i0; h->prect[k][1] = r0; h->prect[k][2] = cols; h->prect[k][3] = rows;
  { /* the farthest point of the rectangle's edges from the axis (65 points an edge), widened by two patch heights */
    double vb[2], ub[2], far = 0.0, d[3];
    int e, t;
    vb[0] = r0 == 0 ? 0.0 : (r0 - 0.5) / hh; vb[1] = r1 == hh ? 1.0 : (r1 + 0.5) / hh;
    ub[0] = (i0 + 0.5) / w; ub[1] = (i0 + cols + 0.5) / w;
    for (e = 0; e < 4; ++e)
      for (t = 0; t <= 64; ++t) {
        double f = t / 64.0, uu = e < 2 ? ub[0] + f * (ub[1] - ub[0]) : ub[e - 2], vv = e < 2 ? vb[e] : vb[0] + f * (vb[1] - vb[0]), cc;
        el_envlight__hot_dir(1, 1, uu, vv, d);
        cc = ax[0] * d[0] + ax[1] * d[1] + ax[2] * d[2];
        cc = acos(cc < 1.0 ? (cc > -1.0 ? cc : -1.0) : 1.0);
        if (cc > far) far = cc;
      }
    far += 2.0 * EL_ENVLIGHT__PI / hh + (ub[1] - ub[0]) * 2.0 * EL_ENVLIGHT__PI / 64.0 + 1e-3;
    h->pcos[k] = far < EL_ENVLIGHT__PI ? (float)cos(far) : -2.0f;
  }
  mass = (double)C[rows] * 3.552713678800501e-15; /* 2^-48 */
  h->inv_pmass[k] = mass > 0.0 ? (float)(1.0 / mass) : 0.0f;
  return EL_SUCCESS;
}

/* h's spot k has a patch rectangle of this light (importance BILINEAR) */
static int el_envlight__hot_spot_ok(const el_envlight *l, const el_envlight_hotspots *h, int k) {
  return k >= 0 && k < h->count && h->pkey && el_envlight__ensure(l) && h->pkey == (const void *)l->pdf_table && h->nu == l->width &&
         h->nv == l->height && h->prow[k] && h->inv_pmass[k] > 0.0f;
}
/* patch (i, r) lies in spot k's rectangle */
static int el_envlight__hot_in_prect(const el_envlight_hotspots *h, int k, int i, int r) {
  int x = i - h->prect[k][0];
  if (x < 0) x += h->nu;
  return r >= h->prect[k][1] && r - h->prect[k][1] < h->prect[k][3] && x < h->prect[k][2];
}
/* the last index j in [lo, hi) with a[j] <= x (a non-decreasing, a[lo] <= x) */
static int el_envlight__hot_find32(const uint32_t *a, int lo, int hi, double x) {
  while (hi - lo > 1) { int m = lo + (hi - lo) / 2; if ((double)a[m] <= x) lo = m; else hi = m; }
  return lo;
}

EL_DEF float el_envlight_pdf_li_spot(const el_envlight *l, const el_envlight_hotspots *h, int k, const float dir[3]) {
  el_envlight__ploc q;
  float p;
  if (!l || !h || !dir || k < 0 || k >= h->count) return 0.0f;
  if (l->importance != EL_ENVLIGHT_IMPORTANCE_BILINEAR) {
    el_envlight_mix_weights w;
    memset(&w, 0, sizeof w);
    w.spot[k] = 1.0f;
    return el_envlight_pdf_li_mix(l, h, &w, dir);
  }
  { /* far from the rectangle (in double: no overflow or underflow for any float dir; NaN: on to the full query,
     * which gives 0) */
    const float *a = h->spot[k].axis;
    double c = (double)dir[0] * a[0] + (double)dir[1] * a[1] + (double)dir[2] * a[2];
    double n2 = (double)dir[0] * dir[0] + (double)dir[1] * dir[1] + (double)dir[2] * dir[2];
    if (c < (double)h->pcos[k] * sqrt(n2)) return 0.0f;
  }
  if (!el_envlight__hot_spot_ok(l, h, k)) return 0.0f;
  p = el_envlight__patch_pdf_at(l, dir, &q);
  if (!(p > 0.0f) || !el_envlight__hot_in_prect(h, k, q.i, q.r)) return 0.0f;
  return p * h->inv_pmass[k];
}

EL_DEF void el_envlight_sample_li_spot(const el_envlight *l, const el_envlight_hotspots *h, int k, const float u[2],
                                       float wi[3], float rgb[3], float *pdf) {
  el_envlight__ploc q;
  const uint64_t *C;
  const uint32_t *rc;
  float u0, u1, fu, fv, p = 0.0f;
  double x, y, seg;
  int j, r, i, i0, cols, w;
  *pdf = 0.0f;
  wi[0] = 0.0f; wi[1] = 0.0f; wi[2] = 1.0f;
  if (rgb) rgb[0] = rgb[1] = rgb[2] = 0.0f;
  if (!l || !h || !u || k < 0 || k >= h->count) return;
  if (l->importance != EL_ENVLIGHT_IMPORTANCE_BILINEAR) {
    el_envlight_mix_weights mw;
    memset(&mw, 0, sizeof mw);
    mw.spot[k] = 1.0f;
    el_envlight_sample_li_mix(l, h, &mw, u, wi, rgb, pdf);
    return;
  }
  if (!el_envlight__hot_spot_ok(l, h, k) || !(u[0] >= 0.0f && u[0] <= 1.0f) || !(u[1] >= 0.0f && u[1] <= 1.0f)) return;
  u0 = u[0] < 0.99999994f ? u[0] : 0.99999994f; u1 = u[1] < 0.99999994f ? u[1] : 0.99999994f;
  /* the patch row: the rectangle's rows' CDF (uint64: searched as doubles) */
  C = h->prow[k];
  x = (double)u1 * (double)C[h->prect[k][3]];
  { int lo = 0, hi = h->prect[k][3]; while (hi - lo > 1) { int m = lo + (hi - lo) / 2; if ((double)C[m] <= x) lo = m; else hi = m; } j = lo; }
  while (j > 0 && C[j + 1] == C[j]) --j; /* (x rounded onto the end of the last row with mass) */
  if (C[j + 1] == C[j]) return;
  fv = (float)((x - (double)C[j]) / (double)(C[j + 1] - C[j]));
  r = h->prect[k][1] + j;
  /* the patch: the row's own integer CDF over the rectangle's columns (two runs across the seam) */
  w = l->width; i0 = h->prect[k][0]; cols = h->prect[k][2];
  rc = l->dist.cdf + (size_t)r * ((size_t)w + 1);
  seg = i0 + cols <= w ? (double)(rc[i0 + cols] - rc[i0]) : (double)(rc[w] - rc[i0]);
  y = (double)u0 * (i0 + cols <= w ? seg : seg + (double)(rc[i0 + cols - w] - rc[0]));
  if (y < seg) { x = (double)rc[i0] + y; i = el_envlight__hot_find32(rc, i0, i0 + cols <= w ? i0 + cols : w, x); }
  else { x = (double)rc[0] + (y - seg); i = el_envlight__hot_find32(rc, 0, i0 + cols - w, x); }
  while (rc[i + 1] == rc[i] && i > 0) --i; /* (as for the row) */
  if (rc[i + 1] == rc[i]) return;
  fu = (float)((x - (double)rc[i]) / (double)(rc[i + 1] - rc[i]));
  fu = fu < 0.99999994f ? (fu > 0.0f ? fu : 0.0f) : 0.99999994f;
  fv = fv < 0.99999994f ? (fv > 0.0f ? fv : 0.0f) : 0.99999994f;
  (void)el_envlight__patch_finish_at(l, i, r, fu, fv, wi, rgb, &p, NULL, &q);
  if (p > 0.0f && el_envlight__hot_in_prect(h, k, q.i, q.r)) *pdf = p * h->inv_pmass[k];
  else if (rgb) rgb[0] = rgb[1] = rgb[2] = 0.0f;
}

EL_DEF el_result el_envlight_hotspots_init(el_envlight_hotspots *h, const el_envlight *l,
                                           const el_envlight_hotspot_options *opt) {
  float min_rad = 100.0f, min_share = 0.05f, max_half = 0.2f;
  int max_spots = EL_ENVLIGHT_HOTSPOT_MAX, nu, nv, k, found = 0;
  int64_t nb, b, *queue = NULL, *queue2 = NULL;
  unsigned char *state = NULL;
  float *f = NULL, *vt = NULL;
  const float *tab;
  const int bil = l && l->importance == EL_ENVLIGHT_IMPORTANCE_BILINEAR;
  double *rowk = NULL, total = 0.0;
  int64_t cand_seed[EL_ENVLIGHT_HOTSPOT_MAX] = {0};
  double cand_share[EL_ENVLIGHT_HOTSPOT_MAX] = {0};
  unsigned cand_accept[EL_ENVLIGHT_HOTSPOT_MAX] = {0};
  el_result r = EL_SUCCESS;
  if (!h) return EL_ERROR_INVALID_ARGUMENT;
  memset(h, 0, sizeof *h);
  if (!l) return EL_ERROR_INVALID_ARGUMENT;
  if (opt) {
    if (opt->min_radiance != 0.0f) min_rad = opt->min_radiance;
    if (opt->min_share != 0.0f) min_share = opt->min_share;
    if (opt->max_half_angle != 0.0f) max_half = opt->max_half_angle;
    if (opt->max_spots != 0) max_spots = opt->max_spots;
    if (!(min_rad > 0.0f && min_rad <= FLT_MAX) || !(min_share > 0.0f && min_share <= 1.0f) ||
        !(max_half > 0.0f && max_half <= (float)EL_ENVLIGHT__PI) || max_spots < 1 || max_spots > EL_ENVLIGHT_HOTSPOT_MAX)
      return EL_ERROR_INVALID_ARGUMENT;
  }
  h->rest_share = 1.0f;
  if (l->width == 0) return EL_SUCCESS;
  if (!el_envlight__ensure(l)) return l->sampling_result;
  if (!l->pdf_table || !(el_distribution2d_integral(&l->dist) > 0.0f)) return EL_SUCCESS; /* black */
  if (bil) { /* the texels' vertex values as the bins, normalised as a density over (u, v) (NOTES 6) */
    int i, j;
    double sum = 0.0;
    if (!l->warp || l->warp->all_zero) return EL_SUCCESS;
    nu = l->width; nv = l->height;
    vt = (float *)EL_MALLOC((size_t)nu * (size_t)nv * sizeof(float));
    if (!vt) return EL_ERROR_OUT_OF_MEMORY;
    for (j = 0; j < nv; ++j) for (i = 0; i < nu; ++i) sum += (double)(vt[(size_t)j * (size_t)nu + (size_t)i] = el_envlight__vertex_of(l, l->warp, i, j));
    if (!(sum > 0.0)) { EL_FREE(vt); return EL_SUCCESS; }
    sum *= 2.0 * EL_ENVLIGHT__PI * EL_ENVLIGHT__PI / ((double)nu * (double)nv);
    for (b = 0; b < (int64_t)nu * nv; ++b) vt[b] = (float)(vt[b] / sum);
    tab = vt;
  } else { nu = l->dist.nu; nv = l->dist.nv; tab = l->pdf_table; }
  nb = (int64_t)nu * (int64_t)nv;
  state = (unsigned char *)EL_MALLOC((size_t)nb);
  queue = (int64_t *)EL_MALLOC((size_t)nb * sizeof(int64_t));
  queue2 = (int64_t *)EL_MALLOC((size_t)nb * sizeof(int64_t));
  rowk = (double *)EL_MALLOC((size_t)nv * sizeof(double));
  if (!state || !queue || !queue2 || !rowk) { r = EL_ERROR_OUT_OF_MEMORY; goto done; }
  { /* <<hot bins>>: bin b's probability m_b = pdf_table[b] 2 pi^2 / (nu nv); its density over its solid
     * angle against the mean 1 / (4 pi): core when m_b 4 pi / area_b >= min_rad, rim when >= min_rad / 8 */
    int j, i;
    double mk = 2.0 * EL_ENVLIGHT__PI * EL_ENVLIGHT__PI / ((double)nu * (double)nv);
    for (j = 0; j < nv; ++j) {
      double area = 2.0 * EL_ENVLIGHT__PI / nu * (cos(EL_ENVLIGHT__PI * j / nv) - cos(EL_ENVLIGHT__PI * (j + 1) / nv));
      rowk[j] = mk;
      for (i = 0; i < nu; ++i) {
        double m = (double)tab[(size_t)j * (size_t)nu + (size_t)i] * mk, ratio = m * 4.0 * EL_ENVLIGHT__PI / area;
        total += m;
        state[(int64_t)j * nu + i] = (unsigned char)(!(m > 0.0) ? 0u : ratio >= (double)min_rad ? EL_ENVLIGHT__HOT_CORE | EL_ENVLIGHT__HOT_WARM
                                                 : ratio >= (double)min_rad / 8.0 ? EL_ENVLIGHT__HOT_WARM : 0u);
      }
    }
  }
  /* <<components>>: a core with its rim; when that is too wide or spread, the core alone (and every other
   * core of the region alone). Keep the max_spots largest shares >= min_share within max_half. */
  for (b = 0; b < nb; ++b) {
    int64_t n1, t;
    double share, ax[3], half;
    if (!(state[b] & EL_ENVLIGHT__HOT_CORE) || (state[b] & EL_ENVLIGHT__HOT_SEEN)) continue;
    n1 = el_envlight__hot_grow(nu, nv, state, queue, b, EL_ENVLIGHT__HOT_WARM, EL_ENVLIGHT__HOT_SEEN);
    if (el_envlight__hot_cone(tab, nu, nv, queue, n1, rowk, total, &share, ax, &half) && half <= (double)max_half) {
      el_envlight__hot_keep(share, min_share, b, EL_ENVLIGHT__HOT_WARM, max_spots, &found, cand_share, cand_seed, cand_accept);
      continue;
    }
    for (t = 0; t < n1; ++t) { /* too wide with its rim: each core of the region alone */
      int64_t seed = queue[t], n2;
      if (!(state[seed] & EL_ENVLIGHT__HOT_CORE) || (state[seed] & EL_ENVLIGHT__HOT_CSEEN)) continue;
      n2 = el_envlight__hot_grow(nu, nv, state, queue2, seed, EL_ENVLIGHT__HOT_CORE, EL_ENVLIGHT__HOT_CSEEN);
      if (el_envlight__hot_cone(tab, nu, nv, queue2, n2, rowk, total, &share, ax, &half) && half <= (double)max_half)
        el_envlight__hot_keep(share, min_share, seed, EL_ENVLIGHT__HOT_CORE, max_spots, &found, cand_share, cand_seed, cand_accept);
    }
  }
  /* <<build the parts>>: each spot's rectangle, mask and distribution; the rest's distribution */
  EL_FREE(queue2); queue2 = NULL; /* the peak of temporary memory: 1 + 8 + 4 bytes per bin from here */
  if (bil) { /* importance BILINEAR: the cones and each one's patch rectangle (NOTES 6) */
    double rs = 1.0;
    for (k = 0; k < found; ++k) {
      int64_t tail = el_envlight__hot_grow(nu, nv, state, queue, cand_seed[k], cand_accept[k], EL_ENVLIGHT__HOT_BUILT);
      double share, ax[3], half;
      el_envlight__hot_cone(tab, nu, nv, queue, tail, rowk, total, &share, ax, &half);
      r = el_envlight__hot_patch_rect(h, l, k, ax, half);
      if (r != EL_SUCCESS) goto done;
      el_envlight__hot_set_spot(h, l, k, ax, half, share, tail);
      rs -= share;
    }
    h->share_d[found] = rs > 0.0 ? rs : 0.0;
    h->rest_share = (float)h->share_d[found];
    h->pkey = l->pdf_table;
    h->nu = nu; h->nv = nv;
    goto done;
  }
  {
    double rest = 0.0;
    size_t q;
    f = (float *)EL_MALLOC((size_t)nb * sizeof(float));
    if (!f) { r = EL_ERROR_OUT_OF_MEMORY; goto done; }
    memcpy(f, l->pdf_table, (size_t)nb * sizeof(float));
    for (k = 0; k < found; ++k) {
      int64_t tail, t2;
      double share, ax[3], half;
      int gap_start = 0, gap_len = 0, run = 0, x, i, y0 = nv, y1 = -1, cols, rows;
      unsigned char *colused;
      float *g;
      el_distribution_options dopt;
      tail = el_envlight__hot_grow(nu, nv, state, queue, cand_seed[k], cand_accept[k], EL_ENVLIGHT__HOT_BUILT);
      /* columns used; the rectangle's columns are the complement of the longest circular gap */
      colused = (unsigned char *)EL_MALLOC((size_t)nu);
      if (!colused) { r = EL_ERROR_OUT_OF_MEMORY; goto done; }
      memset(colused, 0, (size_t)nu);
      for (t2 = 0; t2 < tail; ++t2) {
        int row = (int)(queue[t2] / nu);
        colused[queue[t2] % nu] = 1;
        if (row < y0) y0 = row;
        if (row > y1) y1 = row;
      }
      for (i = 0; i < 2 * nu; ++i) { /* twice around: the longest run of unused columns */
        if (!colused[i % nu]) { if (++run > gap_len && run <= nu) { gap_len = run; gap_start = (i - run + 1) % nu; } }
        else run = 0;
      }
      EL_FREE(colused);
      cols = nu - gap_len;
      h->rect[k][0] = gap_len ? (gap_start + gap_len) % nu : 0;
      h->rect[k][1] = y0;
      h->rect[k][2] = cols;
      h->rect[k][3] = rows = y1 - y0 + 1;
      h->mask[k] = (unsigned char *)EL_MALLOC((size_t)cols * (size_t)rows);
      g = (float *)EL_MALLOC((size_t)cols * (size_t)rows * sizeof(float));
      if (!h->mask[k] || !g) { EL_FREE(g); r = EL_ERROR_OUT_OF_MEMORY; goto done; }
      memset(h->mask[k], 0, (size_t)cols * (size_t)rows);
      for (q = 0; q < (size_t)cols * (size_t)rows; ++q) g[q] = 0.0f;
      for (t2 = 0; t2 < tail; ++t2) {
        int64_t qq = queue[t2];
        int iu = (int)(qq % nu), iv = (int)(qq / nu);
        x = iu - h->rect[k][0];
        if (x < 0) x += nu;
        h->mask[k][(size_t)(iv - y0) * (size_t)cols + (size_t)x] = 1;
        g[(size_t)(iv - y0) * (size_t)cols + (size_t)x] = l->pdf_table[qq];
        f[qq] = 0.0f;
      }
      memset(&dopt, 0, sizeof dopt);
      r = el_distribution2d_init(&h->dist[k], g, cols, rows, &dopt);
      EL_FREE(g);
      if (r != EL_SUCCESS) goto done;
      el_envlight__hot_cone(tab, nu, nv, queue, tail, rowk, total, &share, ax, &half);
      el_envlight__hot_set_spot(h, l, k, ax, half, share, tail);
    }
    if (found > 0) {
      el_distribution_options dopt;
      int anyrest = 0;
      for (b = 0; b < nb; b += nu) { /* (row by row: no division per bin) */
        int i;
        for (i = 0; i < nu; ++i) rest += (double)f[b + i] * rowk[b / nu];
      }
      rest /= total;
      h->share_d[found] = rest > 0.0 ? rest : 0.0;
      h->rest_share = (float)h->share_d[found];
      memset(&dopt, 0, sizeof dopt);
      for (q = 0; q < (size_t)nb; ++q) if (f[q] > 0.0f) { anyrest = 1; break; }
      if (anyrest) {
        r = el_distribution2d_init(&h->dist[found], f, nu, nv, &dopt);
        if (r == EL_SUCCESS) {
          r = el_distribution2d_fast_init(&h->rest_fast, &h->dist[found]);
          h->rest_fast_ok = r == EL_SUCCESS;
        }
      } else { h->share_d[found] = 0.0; h->rest_share = 0.0f; }
      if (r != EL_SUCCESS) goto done;
      if (anyrest) r = el_envlight__hot_cells(h, l, f, rowk, total);
      if (r != EL_SUCCESS) goto done;
      h->key = l->pdf_table;
      h->nu = nu; h->nv = nv;
    }
  }
done:
  EL_FREE(state); EL_FREE(queue); EL_FREE(queue2); EL_FREE(rowk); EL_FREE(f); EL_FREE(vt);
  if (r != EL_SUCCESS) el_envlight_hotspots_free(h);
  return r;
}

/* << hot spots */

/* >> portals (issue 23; NOTES ON PORTALS below the declarations) */

#define EL_ENVLIGHT__PORTAL_UNITS 1099511627776.0 /* 2^40: the quantised mass of the largest portal image */
/* A hint, no effect on any result: the binary searches below start loading the table entries of both
 * possible next steps, so that one step's cache misses overlap the current step's (the plain search
 * waits for one miss after another) */
#if defined(__GNUC__) || defined(__clang__)
#define EL_ENVLIGHT__PORTAL_PREFETCH(a) __builtin_prefetch(a)
#else
#define EL_ENVLIGHT__PORTAL_PREFETCH(a) ((void)(a))
#endif

/* atan2(x, z) / pi for z > 0, in (-1/2, 1/2) (the rectified angle of a direction, in turns of pi). */
static double el_envlight__portal_angle(double x, double z) {
  double ax = fabs(x);
  double a;
  if (ax <= z) a = (double)el_envlight__atan01((float)(ax / z)) * (1.0 / EL_ENVLIGHT__PI);
  else a = 0.5 - (double)el_envlight__atan01((float)(z / ax)) * (1.0 / EL_ENVLIGHT__PI);
  return x < 0.0 ? -a : a;
}

/* A window: portal k's directions from a point, in texel coordinates [x0, x1] x [y0, y1] of [0, R]^2,
 * with the integer prefix values the sampler and the pdf share. */
typedef struct el_envlight__pwin {
  double x0, x1, y0, y1;
  int ia, ib;        /* floor of x0, x1 (<= R - 1) */
  double fa, fb;     /* x0 - ia, x1 - ib */
  double k0, mass;   /* K at y0 (the prefix of the rows below y0), the window's mass */
  int behind;        /* the point is on or behind the portal's plane (or NaN) */
} el_envlight__pwin;

/* K(j): the mass of rows < j between columns x0 and x1 (4 table reads, two adjacent pairs). */
static double el_envlight__portal_k(const uint64_t *S, int R, const el_envlight__pwin *w, int j) {
  const uint64_t *row = S + (size_t)j * (size_t)(R + 1);
  uint64_t a0 = row[w->ia], a1 = row[w->ia + 1], b0 = row[w->ib], b1 = row[w->ib + 1];
  return (double)(int64_t)(b0 - a0) + w->fb * (double)(b1 - b0) - w->fa * (double)(a1 - a0);
}
/* K at a continuous row coordinate y in [0, R]. */
static double el_envlight__portal_kc(const uint64_t *S, int R, const el_envlight__pwin *w, double y) {
  int j = (int)y;
  double k;
  if (j > R - 1) j = R - 1;
  k = el_envlight__portal_k(S, R, w, j);
  return k + (y - (double)j) * (el_envlight__portal_k(S, R, w, j + 1) - k);
}

/* Portal k's window from pos: 0 when pos does not see it (on or behind its plane, or NaN). */
static int el_envlight__portal_window(const el_envlight_portal *p, int k, const double pos[3], el_envlight__pwin *w) {
  const double *f = p->frame[k];
  double r[3], x0, y0, z, R = (double)p->res;
  r[0] = f[0] - pos[0]; r[1] = f[1] - pos[1]; r[2] = f[2] - pos[2];
  z = r[0] * f[9] + r[1] * f[10] + r[2] * f[11];
  w->behind = !(z > 1e-9 * (fabs(f[0]) + fabs(f[1]) + fabs(f[2]) + p->size[k][0] + p->size[k][1]));
  if (w->behind) return 0;
  x0 = r[0] * f[3] + r[1] * f[4] + r[2] * f[5];
  y0 = r[0] * f[6] + r[1] * f[7] + r[2] * f[8];
  w->x0 = (el_envlight__portal_angle(x0, z) + 0.5) * R;
  w->x1 = (el_envlight__portal_angle(x0 + p->size[k][0], z) + 0.5) * R;
  w->y0 = (el_envlight__portal_angle(y0, z) + 0.5) * R;
  w->y1 = (el_envlight__portal_angle(y0 + p->size[k][1], z) + 0.5) * R;
  if (w->x0 < 0.0) w->x0 = 0.0;
  if (w->x1 > R) w->x1 = R;
  if (w->y0 < 0.0) w->y0 = 0.0;
  if (w->y1 > R) w->y1 = R;
  if (!(w->x1 > w->x0) || !(w->y1 > w->y0)) return 0;
  w->ia = (int)w->x0; if (w->ia > p->res - 1) w->ia = p->res - 1;
  w->ib = (int)w->x1; if (w->ib > p->res - 1) w->ib = p->res - 1;
  w->fa = w->x0 - (double)w->ia;
  w->fb = w->x1 - (double)w->ib;
  return 1;
}

/* All windows from pos and their masses; returns the total mass (0: the fallback). */
static double el_envlight__portal_windows(const el_envlight_portal *p, const float pos[3], el_envlight__pwin *w, int *seen) {
  double P[3], total = 0.0;
  int k;
  size_t n = (size_t)(p->res + 1) * (size_t)(p->res + 1);
  P[0] = pos[0]; P[1] = pos[1]; P[2] = pos[2];
  for (k = 0; k < p->count; ++k) {
    seen[k] = el_envlight__portal_window(p, k, P, &w[k]);
    w[k].mass = 0.0;
    if (seen[k]) {
      const uint64_t *S = p->sat + n * (size_t)k;
      w[k].k0 = el_envlight__portal_kc(S, p->res, &w[k], w[k].y0);
      w[k].mass = el_envlight__portal_kc(S, p->res, &w[k], w[k].y1) - w[k].k0;
      if (!(w[k].mass > 0.0)) { w[k].mass = 0.0; seen[k] = 0; }
      total += w[k].mass;
    }
  }
  return total;
}

/* The map's share at a point whose windows are w (options.map_share and map_share_outside). */
static double el_envlight__portal_share(const el_envlight_portal *p, const el_envlight__pwin *w) {
  int k;
  if (!p->map_share_outside) return (double)p->map_share;
  for (k = 0; k < p->count; ++k)
    if (w[k].behind) return (double)p->map_share;
  return 0.0;
}

/* Rectified (a - 1/2, b - 1/2) -> local unit direction; returns dw/d(a,b). */
static double el_envlight__portal_dir(double ta, double tb, double d[3]) {
  double sa = (double)el_envlight__sinpi((float)ta), ca = (double)el_envlight__cospi((float)ta);
  double sb = (double)el_envlight__sinpi((float)tb), cb = (double)el_envlight__cospi((float)tb);
  double v0 = sa * cb, v1 = ca * sb, v2 = ca * cb, n = sqrt(v0 * v0 + v1 * v1 + v2 * v2);
  d[0] = v0 / n; d[1] = v1 / n; d[2] = v2 / n;
  /* pi^2 (1 - wx^2)(1 - wy^2) / wz = pi^2 ca^2 cb^2 / n^4 * n / (ca cb) */
  return EL_ENVLIGHT__PI * EL_ENVLIGHT__PI * ca * cb / (n * n * n);
}

EL_DEF void el_envlight_portal_free(el_envlight_portal *p) {
  if (!p) return;
  EL_FREE(p->sat);
  memset(p, 0, sizeof *p);
  p->bad_index = -1;
}

static el_result el_envlight__portal_fail(el_envlight_portal *p, el_result r, int k, const char *msg) {
  char buf[128];
  size_t i;
  const char *pre = "portal ";
  size_t o = 0;
  for (i = 0; pre[i] && o < sizeof buf - 1; ++i) buf[o++] = pre[i];
  if (k >= 10 && o < sizeof buf - 1) buf[o++] = (char)('0' + k / 10);
  if (o < sizeof buf - 1) buf[o++] = (char)('0' + k % 10);
  if (o < sizeof buf - 1) buf[o++] = ':';
  if (o < sizeof buf - 1) buf[o++] = ' ';
  for (i = 0; msg[i] && o < sizeof buf - 1; ++i) buf[o++] = msg[i];
  buf[o] = 0;
  el_envlight_portal_free(p);
  p->bad_index = k;
  memcpy(p->error, buf, o + 1);
  return r;
}

EL_DEF el_result el_envlight_portal_init(el_envlight_portal *p, const el_envlight *light, const float *points,
                                         int count, const el_envlight_portal_options *opt) {
  el_envlight_portal_options o;
  int k, i, j, R, ss;
  size_t n;
  double *f = NULL, fmax = 0.0, unit;
  if (!p) return EL_ERROR_INVALID_ARGUMENT;
  memset(p, 0, sizeof *p);
  p->bad_index = -1;
  if (opt) o = *opt;
  else memset(&o, 0, sizeof o);
  if (!light || !points) {
    memcpy(p->error, "NULL light or points", 21);
    return EL_ERROR_INVALID_ARGUMENT;
  }
  if (count < 1 || count > EL_ENVLIGHT_PORTAL_MAX) {
    memcpy(p->error, "portal count outside 1..16", 27);
    return EL_ERROR_INVALID_ARGUMENT;
  }
  R = o.resolution ? o.resolution : (light->height < 32 ? 64 : light->height > 1024 ? 2048 : 2 * light->height);
  ss = o.supersample ? o.supersample : 2;
  if (R < 4 || R > 4096 || ss < 1 || ss > 16 || !(o.map_share >= 0.0f && o.map_share <= 1.0f)) {
    memcpy(p->error, "resolution outside 4..4096, supersample outside 1..16 or map_share outside 0..1", 80);
    return EL_ERROR_INVALID_ARGUMENT;
  }
  /* the frames (pbrt-v4: Frame::FromXY(p03, p01), with its 0.001 tolerances) */
  for (k = 0; k < count; ++k) {
    const float *v = points + 12 * k;
    double e01[3], e03[3], e12[3], e32[3], l01 = 0, l03 = 0, l12 = 0, l32 = 0, d, scale = 0.0;
    for (i = 0; i < 12; ++i) {
      if (v[i] != v[i]) return el_envlight__portal_fail(p, EL_ERROR_NAN, k, "a vertex coordinate is NaN");
      if (v[i] > FLT_MAX || v[i] < -FLT_MAX) return el_envlight__portal_fail(p, EL_ERROR_INFINITE, k, "a vertex coordinate is infinite");
      if (fabs((double)v[i]) > scale) scale = fabs((double)v[i]);
    }
    for (i = 0; i < 3; ++i) {
      e01[i] = (double)v[3 + i] - v[i]; e03[i] = (double)v[9 + i] - v[i];
      e12[i] = (double)v[6 + i] - v[3 + i]; e32[i] = (double)v[6 + i] - v[9 + i];
      l01 += e01[i] * e01[i]; l03 += e03[i] * e03[i]; l12 += e12[i] * e12[i]; l32 += e32[i] * e32[i];
    }
    l01 = sqrt(l01); l03 = sqrt(l03); l12 = sqrt(l12); l32 = sqrt(l32);
    if (!(l01 > 1e-6 * scale) || !(l03 > 1e-6 * scale) || !(l12 > 1e-6 * scale) || !(l32 > 1e-6 * scale))
      return el_envlight__portal_fail(p, EL_ERROR_INVALID_ARGUMENT, k, "degenerate: an edge has zero length (vertices coincide)");
    for (i = 0; i < 3; ++i) { e01[i] /= l01; e03[i] /= l03; e12[i] /= l12; e32[i] /= l32; }
#define EL_ENVLIGHT__DOT(a, b) ((a)[0] * (b)[0] + (a)[1] * (b)[1] + (a)[2] * (b)[2])
    if (fabs(EL_ENVLIGHT__DOT(e01, e32) - 1.0) > 0.001 || fabs(EL_ENVLIGHT__DOT(e12, e03) - 1.0) > 0.001)
      return el_envlight__portal_fail(p, EL_ERROR_INVALID_ARGUMENT, k,
                                      "not a planar rectangle: opposite edges are not parallel (non-planar, or wrong vertex order)");
    if (fabs(EL_ENVLIGHT__DOT(e01, e12)) > 0.001 || fabs(EL_ENVLIGHT__DOT(e12, e32)) > 0.001 ||
        fabs(EL_ENVLIGHT__DOT(e32, e03)) > 0.001 || fabs(EL_ENVLIGHT__DOT(e03, e01)) > 0.001)
      return el_envlight__portal_fail(p, EL_ERROR_INVALID_ARGUMENT, k, "not a rectangle: its sides are not perpendicular");
    /* x = p03, y = p01 made exactly orthogonal, z = x cross y */
    d = EL_ENVLIGHT__DOT(e01, e03);
    for (i = 0; i < 3; ++i) e01[i] -= d * e03[i];
    d = sqrt(EL_ENVLIGHT__DOT(e01, e01));
    for (i = 0; i < 3; ++i) e01[i] /= d;
#undef EL_ENVLIGHT__DOT
    for (i = 0; i < 3; ++i) {
      p->frame[k][i] = v[i];
      p->frame[k][3 + i] = e03[i];
      p->frame[k][6 + i] = e01[i];
    }
    p->frame[k][9] = e03[1] * e01[2] - e03[2] * e01[1];
    p->frame[k][10] = e03[2] * e01[0] - e03[0] * e01[2];
    p->frame[k][11] = e03[0] * e01[1] - e03[1] * e01[0];
    p->size[k][0] = l03;
    p->size[k][1] = l01;
  }
  p->count = count;
  p->res = R;
  p->compensated = o.compensated ? 1 : 0;
  p->map_share = o.map_share;
  p->map_share_outside = o.map_share_outside ? 1 : 0;
  n = (size_t)(R + 1) * (size_t)(R + 1);
  p->sat = (uint64_t *)EL_MALLOC(n * (size_t)count * sizeof(uint64_t));
  f = (double *)EL_MALLOC((size_t)R * (size_t)R * (size_t)count * sizeof(double));
  if (!p->sat || !f) {
    EL_FREE(f);
    return el_envlight__portal_fail(p, EL_ERROR_OUT_OF_MEMORY, 0, "out of memory for the tables");
  }
  /* the rectified images: mean of lum(le) dw/dab over ss x ss points per texel */
  for (k = 0; k < count; ++k) {
    const double *fr = p->frame[k];
    double *fk = f + (size_t)R * (size_t)R * (size_t)k, sum_lj = 0.0, sum_j = 0.0, mean, s = 0.0;
    double *lum = (double *)EL_MALLOC((size_t)R * (size_t)R * sizeof(double));
    if (!lum) {
      EL_FREE(f);
      return el_envlight__portal_fail(p, EL_ERROR_OUT_OF_MEMORY, k, "out of memory for the tables");
    }
    for (j = 0; j < R; ++j)
      for (i = 0; i < R; ++i) {
        double aj = 0.0, al = 0.0;
        int sy, sx;
        for (sy = 0; sy < ss; ++sy)
          for (sx = 0; sx < ss; ++sx) {
            double ta = ((double)i + ((double)sx + 0.5) / (double)ss) / (double)R - 0.5;
            double tb = ((double)j + ((double)sy + 0.5) / (double)ss) / (double)R - 0.5;
            double d[3], J = el_envlight__portal_dir(ta, tb, d);
            float wd[3], rgb[3];
            int c;
            for (c = 0; c < 3; ++c) wd[c] = (float)(d[0] * fr[3 + c] + d[1] * fr[6 + c] + d[2] * fr[9 + c]);
            el_envlight_le(light, wd, rgb);
            al += (double)el_envlight__luminance(rgb) * J;
            aj += J;
          }
        fk[(size_t)j * (size_t)R + (size_t)i] = al / (double)(ss * ss);
        lum[(size_t)j * (size_t)R + (size_t)i] = aj / (double)(ss * ss); /* dw/dab for the mean */
        sum_lj += al; sum_j += aj;
      }
    if (p->compensated) {
      mean = sum_j > 0.0 ? sum_lj / sum_j : 0.0; /* the solid-angle mean luminance */
      for (i = 0; i < R * R; ++i) {
        double c = fk[i] - mean * lum[i];
        fk[i] = c > 0.0 ? c : 0.0;
      }
    }
    EL_FREE(lum);
    for (i = 0; i < R * R; ++i) s += fk[i];
    if (s > fmax) fmax = s;
  }
  if (p->compensated && !(fmax > 0.0)) { /* nothing above the mean: the plain density, as the light does */
    EL_FREE(f);
    EL_FREE(p->sat);
    {
      el_envlight_portal_options o2 = o;
      el_result r;
      o2.compensated = 0;
      r = el_envlight_portal_init(p, light, points, count, &o2);
      if (r == EL_SUCCESS) p->fell_back = 1;
      return r;
    }
  }
  unit = fmax > 0.0 ? EL_ENVLIGHT__PORTAL_UNITS / fmax : 0.0;
  if (!(unit < 1e300)) unit = 0.0; /* fmax denormal */
  for (k = 0; k < count; ++k) {
    const double *fk = f + (size_t)R * (size_t)R * (size_t)k;
    uint64_t *S = p->sat + n * (size_t)k;
    for (i = 0; i <= R; ++i) S[i] = 0;
    for (j = 0; j < R; ++j) {
      uint64_t run = 0;
      S[(size_t)(j + 1) * (size_t)(R + 1)] = 0;
      for (i = 0; i < R; ++i) {
        double q = fk[(size_t)j * (size_t)R + (size_t)i] * unit;
        uint64_t qi = (uint64_t)(q < 1099511627776.0 ? q : 1099511627776.0);
        if (q > (double)qi) qi++;   /* ceil: every texel with mass > 0 gets a unit */
        if (!p->compensated && qi == 0) qi = 1;
        run += qi;
        S[(size_t)(j + 1) * (size_t)(R + 1) + (size_t)i + 1] = S[(size_t)j * (size_t)(R + 1) + (size_t)i + 1] + run;
      }
    }
  }
  EL_FREE(f);
  return EL_SUCCESS;
}

EL_DEF int el_envlight_portal_sees(const el_envlight_portal *p, const float pos[3]) {
  el_envlight__pwin w[EL_ENVLIGHT_PORTAL_MAX];
  int seen[EL_ENVLIGHT_PORTAL_MAX];
  if (!p || !p->sat || !pos) return 0;
  return el_envlight__portal_windows(p, pos, w, seen) > 0.0;
}

EL_DEF size_t el_envlight_portal_bytes(const el_envlight_portal *p) {
  if (!p || !p->sat) return 0;
  return (size_t)(p->res + 1) * (size_t)(p->res + 1) * (size_t)p->count * sizeof(uint64_t);
}

/* The portals' density alone at unit world direction D, given the windows of the point (total > 0). */
static double el_envlight__portal_density(const el_envlight_portal *p, const el_envlight__pwin *w, const int *seen, double total,
                                          const double D[3]) {
  double acc = 0.0;
  int k, R = p->res;
  size_t n = (size_t)(R + 1) * (size_t)(R + 1);
  for (k = 0; k < p->count; ++k) {
    const double *f = p->frame[k];
    double lx, ly, lz, x, y, J, q;
    int i, j;
    const uint64_t *r0, *r1;
    if (!seen[k]) continue;
    lz = D[0] * f[9] + D[1] * f[10] + D[2] * f[11];
    if (!(lz > 0.0)) continue;
    lx = D[0] * f[3] + D[1] * f[4] + D[2] * f[5];
    ly = D[0] * f[6] + D[1] * f[7] + D[2] * f[8];
    x = (el_envlight__portal_angle(lx, lz) + 0.5) * (double)R;
    y = (el_envlight__portal_angle(ly, lz) + 0.5) * (double)R;
    if (x < w[k].x0 || x > w[k].x1 || y < w[k].y0 || y > w[k].y1) continue;
    i = (int)x; if (i > R - 1) i = R - 1;
    j = (int)y; if (j > R - 1) j = R - 1;
    r0 = p->sat + n * (size_t)k + (size_t)j * (size_t)(R + 1);
    r1 = r0 + (R + 1);
    q = (double)((r1[i + 1] - r1[i]) - (r0[i + 1] - r0[i]));
    J = EL_ENVLIGHT__PI * EL_ENVLIGHT__PI * (ly * ly + lz * lz) * (lx * lx + lz * lz) / lz; /* (1-x^2)(1-y^2)/z */
    if (J > 0.0) acc += q / J;
  }
  return acc * (double)R * (double)R / total;
}
/* a float direction, normalised in double; 0 for a zero, NaN or infinite one */
static int el_envlight__portal_unit(const float wi[3], double D[3]) {
  double len;
  D[0] = wi[0]; D[1] = wi[1]; D[2] = wi[2];
  len = sqrt(D[0] * D[0] + D[1] * D[1] + D[2] * D[2]);
  if (!(len > 0.0) || len > 1e300) return 0;
  D[0] /= len; D[1] /= len; D[2] /= len;
  return 1;
}

EL_DEF int el_envlight_portal_sample_li(const el_envlight_portal *p, const el_envlight *light, const float pos[3],
                                        const float u[2], float wi[3], float rgb[3], float *pdf) {
  el_envlight__pwin w[EL_ENVLIGHT_PORTAL_MAX];
  int seen[EL_ENVLIGHT_PORTAL_MAX], k, lo, hi, R;
  double total, t, y, x, kl, kh, q, d[3], J, pl, ph, share;
  const uint64_t *S, *r0, *r1;
  size_t n, stride;
  float u0 = el_envlight__clamp_u(u[0]), u1 = el_envlight__clamp_u(u[1]);
  total = (p && p->sat && pos) ? el_envlight__portal_windows(p, pos, w, seen) : 0.0;
  if (!(total > 0.0)) {
    el_envlight_sample_li(light, u, wi, rgb, pdf);
    return 0;
  }
  share = el_envlight__portal_share(p, w);
  if (share > 0.0) { /* <<Defensive mixture>>: u1 picks the map or the portals, then is stretched back */
    double D[3];
    if ((double)u1 < share) {
      float um[2], pm;
      um[0] = u0;
      um[1] = el_envlight__clamp_u((float)((double)u1 / share));
      el_envlight_sample_li(light, um, wi, rgb, &pm);
      *pdf = el_envlight__portal_unit(wi, D) ? (float)(share * (double)pm + (1.0 - share) * el_envlight__portal_density(p, w, seen, total, D)) : 0.0f;
      return 1;
    }
    u1 = el_envlight__clamp_u((float)(((double)u1 - share) / (1.0 - share)));
  }
  R = p->res;
  n = (size_t)(R + 1) * (size_t)(R + 1);
  stride = (size_t)(R + 1);
  /* <<Pick a portal>> and the target in its rows' prefix, with u1 */
  t = (double)u1 * total;
  for (k = 0; k < p->count - 1; ++k) {
    if (!seen[k]) continue;
    if (t < w[k].mass) break;
    t -= w[k].mass;
  }
  while (!seen[k]) --k; /* t rounded past the last seen portal */
  if (t > w[k].mass) t = w[k].mass;
  S = p->sat + n * (size_t)k;
  t += w[k].k0;
  /* <<Find the row>>: the largest j in the window's rows with K(j) <= t */
  lo = (int)w[k].y0; if (lo > R - 1) lo = R - 1;
  hi = (int)w[k].y1; if ((double)hi < w[k].y1) hi++; /* ceil */
  if (hi > R) hi = R;
  { /* the first step's row and both of the next step's */
    int mid = (lo + hi) >> 1, g[3], gi;
    g[0] = mid; g[1] = (lo + mid) >> 1; g[2] = (mid + hi) >> 1;
    for (gi = 0; gi < 3; ++gi) {
      EL_ENVLIGHT__PORTAL_PREFETCH(S + (size_t)g[gi] * stride + w[k].ia);
      EL_ENVLIGHT__PORTAL_PREFETCH(S + (size_t)g[gi] * stride + w[k].ib);
    }
  }
  while (hi - lo > 1) {
    int mid = (lo + hi) >> 1, gi, g[4];
    /* (the rows of the four possible steps after the next: the next step's were asked for last time) */
    g[0] = (lo + ((lo + mid) >> 1)) >> 1; g[1] = (((lo + mid) >> 1) + mid) >> 1;
    g[2] = (mid + ((mid + hi) >> 1)) >> 1; g[3] = (((mid + hi) >> 1) + hi) >> 1;
    for (gi = 0; gi < 4; ++gi) {
      EL_ENVLIGHT__PORTAL_PREFETCH(S + (size_t)g[gi] * stride + w[k].ia);
      EL_ENVLIGHT__PORTAL_PREFETCH(S + (size_t)g[gi] * stride + w[k].ib);
    }
    if (el_envlight__portal_k(S, R, &w[k], mid) <= t) lo = mid;
    else hi = mid;
  }
  kl = el_envlight__portal_k(S, R, &w[k], lo);
  kh = el_envlight__portal_k(S, R, &w[k], lo + 1);
  y = kh > kl ? (double)lo + (t - kl) / (kh - kl) : (double)lo + 0.5;
  if (y < w[k].y0) y = w[k].y0;
  if (y > w[k].y1) y = w[k].y1;
  if (y < (double)lo) y = (double)lo;
  if (y > (double)lo + 0.9999999) y = (double)lo + 0.9999999;
  /* <<Find the column>> in row lo: its prefix P(i) = S(i, lo + 1) - S(i, lo) */
  r0 = S + (size_t)lo * stride;
  r1 = r0 + stride;
  pl = (double)(r1[w[k].ia] - r0[w[k].ia]);
  ph = (double)(r1[w[k].ia + 1] - r0[w[k].ia + 1]);
  t = pl + w[k].fa * (ph - pl);
  pl = (double)(r1[w[k].ib] - r0[w[k].ib]);
  ph = (double)(r1[w[k].ib + 1] - r0[w[k].ib + 1]);
  t += (double)u0 * (pl + w[k].fb * (ph - pl) - t);
  {
    int a = w[k].ia, b = w[k].ib + 1;
    while (b - a > 1) {
      int mid = (a + b) >> 1, m0 = (a + mid) >> 1, m1 = (mid + b) >> 1;
      EL_ENVLIGHT__PORTAL_PREFETCH(r0 + m0); EL_ENVLIGHT__PORTAL_PREFETCH(r1 + m0); /* (both next steps) */
      EL_ENVLIGHT__PORTAL_PREFETCH(r0 + m1); EL_ENVLIGHT__PORTAL_PREFETCH(r1 + m1);
      if ((double)(r1[mid] - r0[mid]) <= t) a = mid;
      else b = mid;
    }
    lo = a;
  }
  pl = (double)(r1[lo] - r0[lo]);
  ph = (double)(r1[lo + 1] - r0[lo + 1]);
  q = ph - pl;
  x = q > 0.0 ? (double)lo + (t - pl) / q : (double)lo + 0.5;
  if (x < w[k].x0) x = w[k].x0;
  if (x > w[k].x1) x = w[k].x1;
  if (x < (double)lo) x = (double)lo;
  if (x > (double)lo + 0.9999999) x = (double)lo + 0.9999999;
  /* <<Direction and pdf>> */
  J = el_envlight__portal_dir(x / (double)R - 0.5, y / (double)R - 0.5, d);
  {
    const double *f = p->frame[k];
    int c;
    for (c = 0; c < 3; ++c) wi[c] = (float)(d[0] * f[3 + c] + d[1] * f[6 + c] + d[2] * f[9 + c]);
  }
  {
    double D[3], pp;
    /* other portals' windows may hold wi too: the pdf is the mixture's */
    if (p->count > 1) pp = el_envlight__portal_unit(wi, D) ? el_envlight__portal_density(p, w, seen, total, D) : 0.0;
    else pp = q * (double)R * (double)R / (total * J);
    if (share > 0.0) pp = (1.0 - share) * pp + share * (double)el_envlight_pdf_li(light, wi);
    *pdf = (float)pp;
  }
  if (rgb) el_envlight_le(light, wi, rgb);
  return 1;
}

EL_DEF float el_envlight_portal_pdf_li(const el_envlight_portal *p, const el_envlight *light, const float pos[3],
                                       const float wi[3]) {
  el_envlight__pwin w[EL_ENVLIGHT_PORTAL_MAX];
  int seen[EL_ENVLIGHT_PORTAL_MAX];
  double total, D[3], pp, share;
  total = (p && p->sat && pos) ? el_envlight__portal_windows(p, pos, w, seen) : 0.0;
  if (!(total > 0.0)) return el_envlight_pdf_li(light, wi);
  if (!el_envlight__portal_unit(wi, D)) return 0.0f;
  pp = el_envlight__portal_density(p, w, seen, total, D);
  share = el_envlight__portal_share(p, w);
  if (share > 0.0) pp = (1.0 - share) * pp + share * (double)el_envlight_pdf_li(light, wi);
  return (float)pp;
}

/* << portals */

#ifdef __cplusplus
}
#endif

#endif /* EL_ENVLIGHT_IMPLEMENTATION_DONE */
#endif /* EL_ENVLIGHT_IMPLEMENTATION */

/*
 * VERSION HISTORY
 *   0.1  first version: pbrt-v3 mapping with documented orientation matrices, bilinear le with Clamp in
 *        v, exact cell-average importance map, integer-CDF / guide / alias samplers, compensation,
 *        lazy thread-safe tables, pole-safe pdfs, exact power.
 *
 * LICENCE: MIT or public domain (Unlicense), your choice, as stb.
 *   MIT: Copyright (c) 2026 envlight authors. Permission is hereby granted, free of charge, to any person
 *   obtaining a copy of this software to deal in it without restriction, subject to including this notice.
 *   THE SOFTWARE IS PROVIDED "AS IS", WITHOUT WARRANTY OF ANY KIND.
 *   Public domain: this is free and unencumbered software released into the public domain.
 */
