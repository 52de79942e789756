/* 02_mipmap_lookup.c: the same texture through lookups of growing filter width, and a textured plane
 * receding in perspective through point, bilinear, trilinear and EWA lookups, in one labelled picture
 * (chapter 2 of the tutorial, "porting and testing MIPMap").
 *
 * WHAT IT DEMONSTRATES
 *   Row 1, as the tutorial: the 400x235 test image of example 01 (a checkerboard of rising frequency
 *   over a colour ramp, resampled by pbrt's rule to 512x256) drawn into 240x141 panels with
 *   pbrt-v3's trilinear Lookup(st, width) at widths 0, 0.005, 0.02, 0.05 and 0.15. Width 0 reads
 *   level 0 bilinearly: the panel is half the texture's size, so the fine checks at the right alias
 *   into false patterns. Growing widths read higher levels: the aliases go, and so does the detail.
 *   The tutorial shows 0 and 0.15 ("the image is blurrier"); 0.15 means level 9 + log2(0.15) = 6.3,
 *   an 8x4 level, hence the smear.
 *   Row 2: a ground plane tiled with the texture (Repeat), seen from a camera one unit above it, so the
 *   texture shrinks towards the horizon. Point and bilinear lookups of level 0 alias (moire); pbrt's
 *   trilinear lookup, with width = 2 x the largest differential, removes the aliases but blurs the
 *   distance, because a footprint that is long in t and narrow in s is filtered as a square; EWA (max
 *   anisotropy 8) filters the ellipse and keeps the checks sharp across while removing the aliases.
 *   The last panel is a reference: 8 x 8 stratified bilinear samples of level 0 per pixel, averaged.
 *   Each panel's rms difference from the reference and its time per pixel are printed and drawn.
 *
 * WHICH PART OF PBRT IT MIRRORS
 *   pbrt-v3 section 10.4 "Image Texture": 10.4.3 "Isotropic triangle filter" (MIPMap::Lookup(st,
 *   width), triangle(), <<Compute MIPMap level for trilinear filtering>>, <<Perform trilinear
 *   interpolation at appropriate MIPMap level>>) and 10.4.4 "Elliptically weighted average"
 *   (Lookup(st, dst0, dst1), <<Compute ellipse minor and major axes>>, <<Clamp ellipse eccentricity if
 *   too large>>, <<Choose level of detail for EWA lookup and perform EWA filtering>>, EWA()). The ray
 *   differentials of the plane are computed in closed form here, as pbrt's camera and
 *   SurfaceInteraction::ComputeDifferentials would give them.
 *
 * HOW TO RUN IT
 *   build/bin/02_mipmap_lookup [out.png]      (default out/02_mipmap_lookup.png; out/ is created)
 *   scripts/demo.sh runs it. tutorials/02-mipmap-port.md walks through it.
 *
 * WHAT IT WRITES
 *   One PNG (1248 x 377): the five widths above, the five plane renderings below, each labelled; on
 *   stdout the path, then per plane panel its rms difference from the reference and ns per pixel.
 */
#define _POSIX_C_SOURCE 200809L /* clock_gettime, mkdir */
#define EL_IMPLEMENTATION
#include "mipmap.h"
#include "film.h"     /* el_film_srgb_to_byte: the exact sRGB curve (declarations only) */
#include "image_io.h" /* examples/common: PNG writing */
#include "picture.h"  /* examples/common: the test image and labels */

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

#define TW 400 /* the test texture, as in example 01 and the tutorial */
#define TH 235
#define PW 240 /* panel width */
#define PH1 141 /* row 1 panel height (the texture's aspect) */
#define PH2 180 /* row 2 panel height */
#define GAP 8
#define TITLE 30
#define CW (5 * PW + 6 * GAP)
#define CH (TITLE + PH1 + GAP + PH2 + GAP)



static double now(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}



/* ---- the plane: camera 1 unit above y = 0, looking along +z, 90 degree horizontal field of view ---- */
#define HORIZON 0.12f /* fraction of the panel height above the horizon */
#define TILE 0.25f    /* texture repeats per world unit along x */
/* Texture coordinates of the ground point seen through panel position (px, py) (pixels, continuous),
 * and their derivatives per pixel: returns 0 for sky. */
static int plane_st(float px, float py, float *s, float *t, float *dsdx, float *dtdx, float *dsdy, float *dtdy) {
  float f = PW * 0.5f, sx = (px - PW * 0.5f) / f, sy = (py - PH2 * HORIZON) / f;
  float ks = TILE, kt = TILE * (float)TW / (float)TH; /* square checks on the ground */
  if (sy <= 1e-4f) return 0;
  /* <<ray (sx, -sy, 1) meets y = -1 at X = sx / sy, Z = 1 / sy>> */
  *s = ks * sx / sy;
  *t = kt / sy;
  /* d/dpx: dsx = 1/f; d/dpy: dsy = 1/f */
  *dsdx = ks / (sy * f);
  *dtdx = 0.0f;
  *dsdy = -ks * sx / (sy * sy * f);
  *dtdy = -kt / (sy * sy * f);
  return 1;
}

enum { P_POINT, P_BILINEAR, P_TRILINEAR, P_EWA, P_REF };
static void render_plane(const el_mipmap *m, const el_mipmap *mtri, int method, float *out) {
  int x, y, i, j, c;
  for (y = 0; y < PH2; ++y)
    for (x = 0; x < PW; ++x) {
      float s, t, a, b, d, e, o[3] = {0, 0, 0}, *p = out + 3 * (y * PW + x);
      if (!plane_st(x + 0.5f, y + 0.5f, &s, &t, &a, &b, &d, &e)) { /* sky */
        p[0] = 0.02f;
        p[1] = 0.03f + 0.1f * (float)y / PH2;
        p[2] = 0.08f + 0.3f * (float)y / PH2;
        continue;
      }
      switch (method) {
      case P_POINT: el_mipmap_point(m, 0, s, t, o); break;
      case P_BILINEAR: el_mipmap_bilerp(m, 0, s, t, o); break;
      case P_TRILINEAR: el_mipmap_lookup_differentials(mtri, s, t, a, b, d, e, o); break;
      case P_EWA: el_mipmap_lookup_differentials(m, s, t, a, b, d, e, o); break;
      default: /* 8 x 8 stratified samples of level 0 over the pixel */
        for (j = 0; j < 8; ++j)
          for (i = 0; i < 8; ++i) {
            float q[3], ss, tt, u1, u2, u3, u4;
            if (!plane_st(x + (i + 0.5f) / 8, y + (j + 0.5f) / 8, &ss, &tt, &u1, &u2, &u3, &u4)) continue;
            el_mipmap_bilerp(m, 0, ss, tt, q);
            for (c = 0; c < 3; ++c) o[c] += q[c] / 64;
          }
      }
      for (c = 0; c < 3; ++c) p[c] = o[c];
    }
}

static void blit(unsigned char *canvas, const float *panel, int pw, int ph, int ox, int oy) {
  int x, y, c;
  for (y = 0; y < ph; ++y)
    for (x = 0; x < pw; ++x)
      for (c = 0; c < 3; ++c) canvas[3 * ((size_t)(oy + y) * CW + ox + x) + c] = el_film_srgb_to_byte(panel[3 * (y * pw + x) + c]);
}

int main(int argc, char **argv) {
  const char *out_path = argc > 1 ? argv[1] : "out/02_mipmap_lookup.png";
  static float img[TW * TH * 3], panel[PW * PH2 * 3], ref[PW * PH2 * 3];
  static const float widths[5] = {0.0f, 0.005f, 0.02f, 0.05f, 0.15f};
  static const char *names[5] = {"POINT", "BILINEAR", "TRILINEAR", "EWA", "REFERENCE 8X8"};
  unsigned char *canvas = (unsigned char *)calloc((size_t)CW * CH * 3, 1);
  el_mipmap m, mtri;
  el_mipmap_options o;
  char err[256], text[64];
  int k, x, y, c;
  el_result r;
  if (argc <= 1 && mkdir("out", 0777) != 0 && errno != EEXIST) {
    fprintf(stderr, "02_mipmap_lookup: cannot create out/: %s\n", strerror(errno));
    return 1;
  }
  el_test_image(img, TW, TH);
  /* pbrt's defaults: Repeat, EWA, max anisotropy 8; a second map uses pbrt's trilinear option */
  r = el_mipmap_init(&m, img, TW, TH, 3, NULL);
  memset(&o, 0, sizeof o);
  o.filter = EL_MIPMAP_FILTER_TRILINEAR;
  if (r == EL_SUCCESS) r = el_mipmap_init(&mtri, img, TW, TH, 3, &o);
  if (r != EL_SUCCESS) {
    fprintf(stderr, "02_mipmap_lookup: el_mipmap_init: %s\n", el_result_string(r));
    return 1;
  }
  memset(canvas, 24, (size_t)CW * CH * 3);
  el_draw_text(canvas, CW, CH, GAP, 8, 2, "MIPMAP LOOKUPS: TRILINEAR WIDTH (TOP), FILTERS ON A RECEDING PLANE (BOTTOM)", 230,
            230, 230);
  /* row 1: the texture through Lookup(st, width) */
  for (k = 0; k < 5; ++k) {
    for (y = 0; y < PH1; ++y)
      for (x = 0; x < PW; ++x) el_mipmap_lookup(&m, (x + 0.5f) / PW, (y + 0.5f) / PH1, widths[k], panel + 3 * (y * PW + x));
    blit(canvas, panel, PW, PH1, GAP + k * (PW + GAP), TITLE);
    snprintf(text, sizeof text, "W = %g", widths[k]);
    el_draw_label(canvas, CW, CH, GAP + k * (PW + GAP), TITLE + PH1 - 22, text);
  }
  /* row 2: the plane */
  render_plane(&m, &mtri, P_REF, ref);
  printf("plane panels (rms difference from the 8x8 reference, time per pixel):\n");
  for (k = 0; k < 5; ++k) {
    double t0 = now(), t1, e = 0;
    int n = 0;
    render_plane(&m, &mtri, k, panel);
    t1 = now() - t0;
    for (y = 0; y < PH2; ++y)
      for (x = 0; x < PW; ++x)
        if (y + 0.5f > PH2 * HORIZON)
          for (c = 0; c < 3; ++c, ++n) e += (panel[3 * (y * PW + x) + c] - ref[3 * (y * PW + x) + c]) *
                                            (panel[3 * (y * PW + x) + c] - ref[3 * (y * PW + x) + c]);
    e = sqrt(e / n);
    printf("  %-14s rms %.4f   %6.1f ns/pixel\n", names[k], e, 1e9 * t1 / (PW * PH2));
    blit(canvas, panel, PW, PH2, GAP + k * (PW + GAP), TITLE + PH1 + GAP);
    if (k < 4) snprintf(text, sizeof text, "%s %.3f", names[k], e);
    else snprintf(text, sizeof text, "%s", names[k]);
    el_draw_label(canvas, CW, CH, GAP + k * (PW + GAP), TITLE + PH1 + GAP + PH2 - 22, text);
  }
  if (el_image_write_png(out_path, canvas, CW, CH, 3, err, sizeof err) != 0) {
    fprintf(stderr, "02_mipmap_lookup: %s\n", err);
    return 1;
  }
  printf("wrote %s\n", out_path);
  el_mipmap_free(&m);
  el_mipmap_free(&mtri);
  free(canvas);
  return 0;
}
