/* 02_mipmap_lookup.c: the seed's test of its MIPMap port, redone with the course's plain C port of
 * pbrt-v3 and with the library side by side: Lookup(st, width) at widths 0 and 0.15, trilinear
 * against EWA on a plane seen at a grazing angle, and the three wrap modes (chapter 2 of the course,
 * tutorials/02-porting-the-mipmap.md).
 *
 * WHAT IT DEMONSTRATES
 *   1. The seed's test: it builds a 400x235 image, makes a MIPMap of it and draws it through
 *      Lookup(st, width), then changes the width to 0.15: "还是能看出 with 变大以后图更模糊的" (the
 *      wider lookup is blurrier). Its text does not give the first width; we use 0. Width 0 reads level 0 (512x256) bilinearly; width 0.15 reads level
 *      9 + log2(0.15) = 6.26, a blend of the 8x4 and 4x2 levels.
 *   2. What the two filters are for: a ground plane tiled with the image, seen from one unit above
 *      it, so that the texture shrinks towards the horizon and each pixel's footprint on it becomes a
 *      long, thin ellipse. A bilinear lookup of level 0 aliases; the trilinear lookup (doTrilinear)
 *      removes the aliases but blurs, because it filters a square as wide as the ellipse is long; EWA
 *      filters the ellipse. A reference averages 8 x 8 bilinear samples per pixel; every panel's rms
 *      difference from it is printed and drawn.
 *   3. The wrap modes: the image looked up over two texture widths, so that the lookups leave the
 *      texture: Repeat tiles it, Black is 0 outside, Clamp repeats the border texels. The library
 *      takes a wrap mode per axis (pbrt-v4 does too): Repeat in u and Clamp in v, as an environment
 *      map wants.
 *   Each lookup is made by the port and by the library; the program prints how far apart they are
 *   and how long each takes, in the same run.
 *
 * WHICH PART OF PBRT IT MIRRORS
 *   pbrt-v3 src/core/mipmap.h, book section 10.4 (Image Texture): MIPMap::Texel (ImageWrap),
 *   triangle(), Lookup(st, width) (<<Compute MIPMap level for trilinear filtering>>, <<Perform
 *   trilinear interpolation at appropriate MIPMap level>>), Lookup(st, dst0, dst1) and EWA()
 *   (<<Compute ellipse minor and major axes>>, <<Clamp ellipse eccentricity if too large>>, <<Choose
 *   level of detail for EWA lookup and perform EWA filtering>>). The plane's differentials are worked
 *   out in closed form here, as pbrt's camera and SurfaceInteraction::ComputeDifferentials give them.
 *
 * HOW TO RUN IT
 *   build/bin/02_mipmap_lookup [output-directory]   (default: out, created if missing)
 *   build/bin/02_mipmap_lookup tutorials/images     (the pictures in the tutorial)
 *   build/bin/02_mipmap_lookup --answers            (the numbers the exercises ask for; no pictures)
 *   build/bin/02_mipmap_lookup --help               (this usage; exit 0)
 *
 * WHAT IT WRITES
 *   <dir>/02-seed-test.png (824 x 281), <dir>/02-trilinear-vs-ewa.png (1160 x 246),
 *   <dir>/02-wrap-modes.png (1240 x 222), each panel labelled. On stdout: port against library,
 *   each plane panel's rms difference from the reference, the times of both.
 */
#define _POSIX_C_SOURCE 200809L /* clock_gettime, mkdir */
#define EL_IMPLEMENTATION
#include "mipmap.h"          /* the library */
#include "film.h"            /* el_film_srgb_to_byte: linear to sRGB bytes for the PNG */
#include "pbrtv3/mipmap.h"   /* the course's plain port of pbrt-v3's MIPMap */
#include "image_io.h"        /* examples/common: PNG writing */
#include "picture.h"         /* examples/common: the test image, labels */

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

#define TW 400 /* the seed's test image: int mW = 400, mH = 235; */
#define TH 235

static double now(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* A canvas of RGB bytes: panels of linear RGB floats go in through the exact sRGB curve. */
typedef struct canvas {
  unsigned char *p;
  int w, h;
} canvas;
static canvas canvas_new(int w, int h, const char *title) {
  canvas c;
  c.w = w;
  c.h = h;
  c.p = (unsigned char *)malloc((size_t)3 * w * h);
  memset(c.p, 24, (size_t)3 * w * h);
  el_draw_text(c.p, w, h, 8, 8, 2, title, 230, 230, 230);
  return c;
}
static void canvas_put(canvas *c, const float *panel, int pw, int ph, int x0, int y0, const char *label) {
  int x, y, k;
  for (y = 0; y < ph; ++y)
    for (x = 0; x < pw; ++x)
      for (k = 0; k < 3; ++k)
        c->p[3 * ((size_t)(y0 + y) * c->w + x0 + x) + k] = el_film_srgb_to_byte(panel[3 * (y * pw + x) + k]);
  el_draw_label(c->p, c->w, c->h, x0, y0 + ph - 22, label);
}
static int canvas_write(canvas *c, const char *dir, const char *name) {
  char path[1024], err[256];
  int r;
  snprintf(path, sizeof path, "%s/%s", dir, name);
  r = el_image_write_png(path, c->p, c->w, c->h, 3, err, sizeof err);
  if (r != 0) fprintf(stderr, "02_mipmap_lookup: %s\n", err);
  else printf("wrote %s\n", path);
  free(c->p);
  return r;
}
/* The largest difference between two float images, and whether they are the same bit for bit. */
static float max_diff(const float *a, const float *b, int n, int *same) {
  float d = 0;
  int i;
  *same = memcmp(a, b, sizeof(float) * (size_t)n) == 0;
  for (i = 0; i < n; ++i)
    if (fabsf(a[i] - b[i]) > d) d = fabsf(a[i] - b[i]);
  return d;
}

/* ---- 1. the seed's test: the image through Lookup(st, width) --------------------------------- */
/* The seed does not show its drawing loop; here output pixel (x, y) of a 400x235 panel looks up the
 * texel centre st = ((x + 0.5) / 400, (y + 0.5) / 235). */
static void seed_panel_port(const pbrt_MIPMap *mip, float width, float *out) {
  int x, y;
  for (y = 0; y < TH; ++y)
    for (x = 0; x < TW; ++x) {
      pbrt_Point2f st = pbrt_Point2f_make((x + 0.5f) / TW, (y + 0.5f) / TH);
      pbrt_RGBSpectrum r = pbrt_MIPMap_Lookup(mip, st, width);
      memcpy(out + 3 * (y * TW + x), r.c, sizeof r.c);
    }
}
static void seed_panel_library(const el_mipmap *m, float width, float *out) {
  int x, y;
  for (y = 0; y < TH; ++y)
    for (x = 0; x < TW; ++x) el_mipmap_lookup(m, (x + 0.5f) / TW, (y + 0.5f) / TH, width, out + 3 * (y * TW + x));
}

/* ---- 2. a plane at a grazing angle: camera one unit above y = 0, looking along +z ------------ */
#define PW 280        /* panel width */
#define PH 200        /* panel height */
#define HORIZON 0.12f /* fraction of the panel above the horizon */
#define TILE 0.25f    /* texture repeats per world unit along x */
/* The texture coordinates of the ground seen through panel position (px, py) (continuous pixels),
 * with their derivatives per pixel, dst/dx and dst/dy. Returns 0 for the sky. */
static int plane_st(int pw, int ph, float px, float py, float *s, float *t, float *dsdx, float *dtdx, float *dsdy,
                    float *dtdy) {
  float f = pw * 0.5f, sx = (px - pw * 0.5f) / f, sy = (py - ph * HORIZON) / f;
  float ks = TILE * pw / PW, kt = ks * (float)TW / (float)TH; /* square checks on the ground */
  if (sy <= 1e-4f) return 0;
  /* the ray (sx, -sy, 1) meets the ground y = -1 at x = sx / sy, z = 1 / sy */
  *s = ks * sx / sy;
  *t = kt / sy;
  *dsdx = ks / (sy * f);
  *dtdx = 0.0f;
  *dsdy = -ks * sx / (sy * sy * f);
  *dtdy = -kt / (sy * sy * f);
  return 1;
}
enum { BILINEAR, TRILINEAR, EWA, REFERENCE };
/* Renders the plane with one filter (BILINEAR is triangle() on level 0), through the port (p, ptri: a
 * second port with doTrilinear) or, when p is NULL, through the library (m, mtri); with reduce, the
 * library gets st reduced to [0, 1) first (s - floor(s): the same texels under Repeat). */
static void render_plane(const pbrt_MIPMap *p, const pbrt_MIPMap *ptri, const el_mipmap *m, const el_mipmap *mtri,
                         int filter, int reduce, int pw, int ph, float *out) {
  int x, y, i, j, k;
  for (y = 0; y < ph; ++y)
    for (x = 0; x < pw; ++x) {
      float s, t, a, b, c, d, o[3] = {0, 0, 0}, *q = out + 3 * (y * pw + x);
      if (!plane_st(pw, ph, x + 0.5f, y + 0.5f, &s, &t, &a, &b, &c, &d)) { /* sky */
        q[0] = 0.02f;
        q[1] = 0.03f + 0.1f * (float)y / ph;
        q[2] = 0.08f + 0.3f * (float)y / ph;
        continue;
      }
      if (filter == REFERENCE) { /* 8 x 8 bilinear samples of level 0 over the pixel (the library's) */
        for (j = 0; j < 8; ++j)
          for (i = 0; i < 8; ++i) {
            float ss, tt, u1, u2, u3, u4, r[3];
            if (!plane_st(pw, ph, x + (i + 0.5f) / 8, y + (j + 0.5f) / 8, &ss, &tt, &u1, &u2, &u3, &u4)) continue;
            el_mipmap_bilerp(m, 0, ss, tt, r);
            for (k = 0; k < 3; ++k) o[k] += r[k] / 64;
          }
      } else if (p) {
        pbrt_RGBSpectrum r;
        pbrt_Point2f st = pbrt_Point2f_make(s, t);
        if (filter == BILINEAR) r = pbrt_MIPMap_triangle(p, 0, st);
        else if (filter == TRILINEAR) r = pbrt_MIPMap_Lookup_dst(ptri, st, pbrt_Vector2f_make(a, b), pbrt_Vector2f_make(c, d));
        else r = pbrt_MIPMap_Lookup_dst(p, st, pbrt_Vector2f_make(a, b), pbrt_Vector2f_make(c, d));
        memcpy(o, r.c, sizeof o);
      } else {
        if (reduce) {
          s -= floorf(s);
          t -= floorf(t);
        }
        if (filter == BILINEAR) el_mipmap_bilerp(m, 0, s, t, o);
        else el_mipmap_lookup_differentials(filter == TRILINEAR ? mtri : m, s, t, a, b, c, d, o);
      }
      memcpy(q, o, sizeof o);
    }
}
/* The rms difference of two renderings over the ground (the sky is left out). */
static double rms_ground(const float *a, const float *ref, int pw, int ph) {
  double e = 0;
  int x, y, k, n = 0;
  for (y = 0; y < ph; ++y)
    for (x = 0; x < pw; ++x)
      if (y + 0.5f > ph * HORIZON)
        for (k = 0; k < 3; ++k, ++n) {
          double d = a[3 * (y * pw + x) + k] - ref[3 * (y * pw + x) + k];
          e += d * d;
        }
  return sqrt(e / n);
}

/* ---- 3. the wrap modes: st over [-0.5, 1.5]^2 -------------------------------------------------- */
#define WW 300
#define WH 176
static void wrap_panel(const pbrt_MIPMap *p, const el_mipmap *m, float *out) {
  int x, y;
  for (y = 0; y < WH; ++y)
    for (x = 0; x < WW; ++x) {
      float s = -0.5f + 2.0f * (x + 0.5f) / WW, t = -0.5f + 2.0f * (y + 0.5f) / WH, *q = out + 3 * (y * WW + x);
      if (p) {
        pbrt_RGBSpectrum r = pbrt_MIPMap_Lookup(p, pbrt_Point2f_make(s, t), 0.f);
        memcpy(q, r.c, sizeof r.c);
      } else el_mipmap_lookup(m, s, t, 0.f, q);
      /* a thin white frame where the texture itself lies, [0,1]^2 */
      if ((x == WW / 4 || x == 3 * WW / 4) && y >= WH / 4 && y <= 3 * WH / 4) q[0] = q[1] = q[2] = 1.0f;
      if ((y == WH / 4 || y == 3 * WH / 4) && x >= WW / 4 && x <= 3 * WW / 4) q[0] = q[1] = q[2] = 1.0f;
    }
}

/* ---- the exercises' numbers -------------------------------------------------------------------- */
static void answers(const float *img) {
  pbrt_BlockedArray *a = pbrt_BlockedArray_new(TW, TH, NULL);
  pbrt_MIPMap p, pd;
  el_mipmap m;
  el_mipmap_options o;
  static const float widths[3] = {0.0f, 1.0f / 512, 0.15f}, aniso[3] = {1, 8, 64};
  int i;
  printf("exercise 2.1: BlockedArray(400, 235): uBlocks %d, texel (5, 6) at offset %d, %d texels allocated\n", a->uBlocks,
         (int)(pbrt_BlockedArray_at(a, 5, 6) - a->data), pbrt_BlockedArray_RoundUp(TW) * pbrt_BlockedArray_RoundUp(TH));
  pbrt_BlockedArray_delete(a);
  pbrt_MIPMap_init(&p, pbrt_Point2i_make(TW, TH), (const pbrt_RGBSpectrum *)img, 0, 8.f, pbrt_ImageWrap_Repeat);
  printf("exercise 2.3: the level Lookup(st, width) reads on the %d-level pyramid\n", pbrt_MIPMap_Levels(&p));
  for (i = 0; i < 3; ++i) {
    float level = pbrt_MIPMap_Levels(&p) - 1 + pbrt_Log2(pbrt_max(widths[i], (float)1e-8));
    if (level < 0) printf("  width %.6f: level %.4f < 0: triangle() on level 0\n", widths[i], level);
    else
      printf("  width %.6f: level %.4f: levels %d (%dx%d) and %d (%dx%d), delta %.4f\n", widths[i], level, (int)floorf(level),
             p.pyramid[(int)floorf(level)]->uRes, p.pyramid[(int)floorf(level)]->vRes, (int)floorf(level) + 1,
             p.pyramid[(int)floorf(level) + 1]->uRes, p.pyramid[(int)floorf(level) + 1]->vRes, level - floorf(level));
  }
  printf("exercise 2.4: Lookup(st = (0.3, 0.002), width 0.05) at the top row of the image\n");
  for (i = 0; i < 2; ++i) {
    float c[3];
    memset(&o, 0, sizeof o);
    o.wrap_v = i ? EL_MIPMAP_WRAP_CLAMP : EL_MIPMAP_WRAP_REPEAT;
    el_mipmap_init(&m, img, TW, TH, 3, &o);
    el_mipmap_lookup(&m, 0.3f, 0.002f, 0.05f, c);
    printf("  %s: (%.4f, %.4f, %.4f)\n", i ? "Repeat in u, Clamp in v" : "Repeat in both", c[0], c[1], c[2]);
    el_mipmap_free(&m);
  }
  {
    float c[3];
    el_mipmap_init(&m, img, TW, TH, 3, NULL);
    el_mipmap_texel(&m, 0, 153, 0, c);
    printf("  level 0, row 0, texel 153: (%.4f, %.4f, %.4f)\n", c[0], c[1], c[2]);
    el_mipmap_texel(&m, 0, 153, 255, c);
    printf("  level 0, row 255, texel 153: (%.4f, %.4f, %.4f)\n", c[0], c[1], c[2]);
    el_mipmap_free(&m);
  }
  printf("exercise 2.5: EWA on the plane (140x100) against maxAnisotropy, rms difference from the reference\n");
  {
    float *ref = (float *)malloc(sizeof(float) * 3 * 140 * 100), *pic = (float *)malloc(sizeof(float) * 3 * 140 * 100);
    el_mipmap_init(&m, img, TW, TH, 3, NULL);
    render_plane(NULL, NULL, &m, &m, REFERENCE, 0, 140, 100, ref);
    for (i = 0; i < 3; ++i) {
      pbrt_MIPMap_init(&pd, pbrt_Point2i_make(TW, TH), (const pbrt_RGBSpectrum *)img, 0, aniso[i], pbrt_ImageWrap_Repeat);
      render_plane(&pd, &pd, &m, &m, EWA, 0, 140, 100, pic);
      printf("  maxAnisotropy %2.0f: rms %.4f\n", aniso[i], rms_ground(pic, ref, 140, 100));
      pbrt_MIPMap_free(&pd);
    }
    render_plane(&p, &p, &m, &m, BILINEAR, 0, 140, 100, pic);
    printf("  bilinear on level 0: rms %.4f\n", rms_ground(pic, ref, 140, 100));
    el_mipmap_free(&m);
    free(ref);
    free(pic);
  }
  pbrt_MIPMap_free(&p);
}

int main(int argc, char **argv) {
  static float img[TW * TH * 3], seed0[TW * TH * 3], seed1[TW * TH * 3], libpanel[TW * TH * 3];
  static float ref[PW * PH * 3], plane[4][PW * PH * 3], libplane[PW * PH * 3], wrap[WW * WH * 3];
  static const char *filter_name[3] = {"BILINEAR", "TRILINEAR", "EWA"};
  static const char *wrap_name[3] = {"REPEAT", "BLACK", "CLAMP"};
  const char *dir = "out";
  pbrt_MIPMap p, ptri, pw;
  el_mipmap m, mtri, mw;
  el_mipmap_options o;
  canvas cv;
  char text[80];
  int k, same, rep;
  float d;
  if (argc > 1 && (!strcmp(argv[1], "--help") || !strcmp(argv[1], "-h") || (argv[1][0] == '-' && strcmp(argv[1], "--answers")))) {
    int help = !strcmp(argv[1], "--help") || !strcmp(argv[1], "-h");
    fprintf(help ? stdout : stderr,
            "usage: 02_mipmap_lookup [output-directory]   (default: out, created if missing)\n"
            "       02_mipmap_lookup --answers            (the numbers the exercises ask for; no pictures)\n");
    return help ? 0 : 1;
  }
  el_test_image(img, TW, TH); /* the course's 400x235 test image (linear RGB) */
  if (argc > 1 && !strcmp(argv[1], "--answers")) {
    answers(img);
    return 0;
  }
  if (argc > 1) dir = argv[1];
  if (mkdir(dir, 0777) != 0 && errno != EEXIST) {
    fprintf(stderr, "02_mipmap_lookup: cannot create directory %s: %s\n", dir, strerror(errno));
    return 1;
  }
  /* The port: MIPMap<RGBSpectrum>(Point2i(400, 235), img) with pbrt's defaults (EWA, maxAnisotropy 8,
   * Repeat), and a second one with doTrilinear = true. The library: all-zero options are the same
   * defaults; o.filter = EL_MIPMAP_FILTER_TRILINEAR is doTrilinear. */
  pbrt_MIPMap_init(&p, pbrt_Point2i_make(TW, TH), (const pbrt_RGBSpectrum *)img, 0, 8.f, pbrt_ImageWrap_Repeat);
  pbrt_MIPMap_init(&ptri, pbrt_Point2i_make(TW, TH), (const pbrt_RGBSpectrum *)img, 1, 8.f, pbrt_ImageWrap_Repeat);
  memset(&o, 0, sizeof o);
  o.filter = EL_MIPMAP_FILTER_TRILINEAR;
  if (el_mipmap_init(&m, img, TW, TH, 3, NULL) != EL_SUCCESS || el_mipmap_init(&mtri, img, TW, TH, 3, &o) != EL_SUCCESS) {
    fprintf(stderr, "02_mipmap_lookup: el_mipmap_init failed\n");
    return 1;
  }

  /* 1. the seed's test */
  cv = canvas_new(8 + 2 * (TW + 8), 30 + TH + 16, "THE SEED TEST: LOOKUP(ST, WIDTH) OF THE 400X235 IMAGE, BY THE PORT");
  seed_panel_port(&p, 0.f, seed0);
  seed_panel_library(&m, 0.f, libpanel);
  d = max_diff(seed0, libpanel, TW * TH * 3, &same);
  printf("seed test, width 0: port and library the same bit for bit: %s\n", same ? "yes" : "no");
  seed_panel_port(&p, 0.15f, seed1);
  seed_panel_library(&m, 0.15f, libpanel);
  d = max_diff(seed1, libpanel, TW * TH * 3, &same);
  printf("seed test, width 0.15: largest difference port - library %.1g (the level's logarithm)\n", d);
  canvas_put(&cv, seed0, TW, TH, 8, 30, "WIDTH 0: LEVEL 0 (512X256)");
  canvas_put(&cv, seed1, TW, TH, 16 + TW, 30, "WIDTH 0.15: LEVELS 6 AND 7");
  if (canvas_write(&cv, dir, "02-seed-test.png")) return 1;

  /* 2. trilinear against EWA on the plane */
  cv = canvas_new(8 + 4 * (PW + 8), 30 + PH + 16, "A PLANE AT A GRAZING ANGLE (PORT): RMS DIFFERENCE FROM 8X8 SAMPLES");
  render_plane(NULL, NULL, &m, &mtri, REFERENCE, 0, PW, PH, ref);
  printf("plane, rms difference from the 8x8 reference (port; library):\n");
  for (k = 0; k < 3; ++k) {
    double e;
    render_plane(&p, &ptri, &m, &mtri, k, 0, PW, PH, plane[k]);
    render_plane(NULL, NULL, &m, &mtri, k, 0, PW, PH, libplane);
    e = rms_ground(plane[k], ref, PW, PH);
    printf("  %-17s %.4f; %.4f\n", filter_name[k], e, rms_ground(libplane, ref, PW, PH));
    snprintf(text, sizeof text, "%s %.3f", filter_name[k], e);
    canvas_put(&cv, plane[k], PW, PH, 8 + k * (PW + 8), 30, text);
  }
  canvas_put(&cv, ref, PW, PH, 8 + 3 * (PW + 8), 30, "REFERENCE 8X8");
  if (canvas_write(&cv, dir, "02-trilinear-vs-ewa.png")) return 1;

  /* 3. the wrap modes, the port's three and the library's per-axis pair */
  cv = canvas_new(8 + 4 * (WW + 8), 30 + WH + 16, "WRAP MODES: ST FROM -0.5 TO 1.5, THE TEXTURE FRAMED IN WHITE");
  for (k = 0; k < 3; ++k) {
    pbrt_MIPMap_init(&pw, pbrt_Point2i_make(TW, TH), (const pbrt_RGBSpectrum *)img, 0, 8.f, (pbrt_ImageWrap)k);
    wrap_panel(&pw, NULL, wrap);
    snprintf(text, sizeof text, "PORT: %s", wrap_name[k]);
    canvas_put(&cv, wrap, WW, WH, 8 + k * (WW + 8), 30, text);
    pbrt_MIPMap_free(&pw);
  }
  memset(&o, 0, sizeof o);
  o.wrap_u = EL_MIPMAP_WRAP_REPEAT;
  o.wrap_v = EL_MIPMAP_WRAP_CLAMP;
  el_mipmap_init(&mw, img, TW, TH, 3, &o);
  wrap_panel(NULL, &mw, wrap);
  canvas_put(&cv, wrap, WW, WH, 8 + 3 * (WW + 8), 30, "LIB: U REPEAT, V CLAMP");
  el_mipmap_free(&mw);
  if (canvas_write(&cv, dir, "02-wrap-modes.png")) return 1;

  /* The cost, in the same run: each plane rendering 3 times, port, library and library with st
   * reduced to [0, 1) interleaved; the fastest of each counts (the machine is shared and noisy). The
   * plane's s and t run far beyond 1 (the texture tiles), which the library's fast paths do not take. */
  printf("time per lookup on the plane (fastest of 3):\n");
  for (k = TRILINEAR; k <= EWA; ++k) {
    double tp = 1e30, tl = 1e30, tr = 1e30, t, n = PW * (PH - ceilf(PH * HORIZON - 0.5f)); /* ground pixels */
    for (rep = 0; rep < 3; ++rep) {
      t = now();
      render_plane(&p, &ptri, &m, &mtri, k, 0, PW, PH, plane[3]);
      t = now() - t;
      if (t < tp) tp = t;
      t = now();
      render_plane(NULL, NULL, &m, &mtri, k, 0, PW, PH, libplane);
      t = now() - t;
      if (t < tl) tl = t;
      t = now();
      render_plane(NULL, NULL, &m, &mtri, k, 1, PW, PH, libplane);
      t = now() - t;
      if (t < tr) tr = t;
    }
    printf("  %-9s port %5.0f ns, library %4.0f ns (%.1fx), library on st in [0,1) %4.0f ns (%.1fx)\n",
           k == TRILINEAR ? "trilinear" : "EWA", 1e9 * tp / n, 1e9 * tl / n, tp / tl, 1e9 * tr / n, tp / tr);
  }
  d = max_diff(plane[3], libplane, PW * PH * 3, &same);
  printf("EWA on the plane, port - library with st in [0,1): largest difference %.1g\n", d);
  pbrt_MIPMap_free(&p);
  pbrt_MIPMap_free(&ptri);
  el_mipmap_free(&m);
  el_mipmap_free(&mtri);
  return 0;
}
