/* 01_mipmap_pyramid.c: the MIP map of the course's 400x235 test image, built by the plain C port of
 * pbrt-v3 and by the library, level by level, in one labelled picture (chapter 1 of the course,
 * tutorials/01-mipmap.md).
 *
 * WHAT IT DEMONSTRATES
 *   A MIP map is a pyramid: level 0 is the image, each next level has half the resolution and holds
 *   the average of the 2x2 texels under it, down to one texel. 400 and 235 are not powers of two, so
 *   pbrt's constructor first resamples the image up to 512x256 (RoundUpPow2, resampleWeights, a
 *   Lanczos filter), then box-filters it down to 1x1: 10 levels. The test image has detail at every
 *   scale (a checkerboard whose checks shrink from left to right over a colour ramp), so each level
 *   shows which detail it has averaged away. The program builds the pyramid twice, with the course's
 *   port (examples/pbrtv3/mipmap.h) and with the library (mipmap.h), checks that every level is the
 *   same bit for bit, and times both in the same run. Then two places where the library departs:
 *   Black wrap (pbrt's top level loses half its energy on a 2:1 image) and keep_resolution (no
 *   resampling at all).
 *
 * WHICH PART OF PBRT IT MIRRORS
 *   pbrt-v3 src/core/mipmap.h, book section 10.4 (Image Texture), the MIPMap constructor:
 *   <<Resample image to power-of-two resolution>>, <<Initialize levels of MIPMap from image>>,
 *   <<Initialize most detailed level of MIPMap>>, <<Initialize ith MIPMap level from (i-1)st level>>.
 *
 * HOW TO RUN IT
 *   build/bin/01_mipmap_pyramid [output-directory]   (default: out, created if missing)
 *   build/bin/01_mipmap_pyramid tutorials/images     (the picture in the tutorial)
 *   build/bin/01_mipmap_pyramid --answers            (the numbers the exercises ask for; no picture)
 *   build/bin/01_mipmap_pyramid --help               (this usage; exit 0)
 *
 * WHAT IT WRITES
 *   <dir>/01-pyramid.png (936 x 568): the input and every level, each labelled with its size (levels 2
 *   to 9 enlarged, one texel per block of pixels). On stdout: each level's size and mean, the
 *   comparison with the library, the build times of both.
 */
#define _POSIX_C_SOURCE 200809L /* clock_gettime, mkdir */
#define EL_IMPLEMENTATION
#include "mipmap.h"          /* the library */
#include "film.h"            /* el_film_srgb_to_byte: linear to sRGB bytes for the PNG */
#include "pbrtv3/mipmap.h"   /* the course's plain port of pbrt-v3's MIPMap */
#include "image_io.h"        /* examples/common: PNG writing */
#include "picture.h"         /* examples/common: the test image, labels */

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

#define W 400 /* the seed's test image: int mW = 400, mH = 235; */
#define H 235

static double now(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* The mean of one level of the port's pyramid (all three channels). */
static double port_level_mean(const pbrt_MIPMap *mip, int level) {
  const pbrt_BlockedArray *l = mip->pyramid[level];
  double sum = 0;
  int s, t, c;
  for (t = 0; t < l->vRes; ++t)
    for (s = 0; s < l->uRes; ++s)
      for (c = 0; c < 3; ++c) sum += pbrt_BlockedArray_at(l, s, t)->c[c];
  return sum / (3.0 * l->uRes * l->vRes);
}

/* Do the port's level and the library's level hold the same floats, bit for bit? */
static int same_level(const pbrt_MIPMap *mip, const el_mipmap *m, int level) {
  const pbrt_BlockedArray *l = mip->pyramid[level];
  const float *d = el_mipmap_level_data(m, level);
  int s, t;
  if (l->uRes != el_mipmap_level_width(m, level) || l->vRes != el_mipmap_level_height(m, level)) return 0;
  for (t = 0; t < l->vRes; ++t)
    for (s = 0; s < l->uRes; ++s)
      if (memcmp(pbrt_BlockedArray_at(l, s, t)->c, d + 3 * (t * l->uRes + s), 3 * sizeof(float)) != 0) return 0;
  return 1;
}

/* ---- the picture ------------------------------------------------------------------------------- */
#define CW 936
#define CH 568
/* Draws a w x h level into a pw x ph box of the canvas at (x0, y0), one texel per block of pixels
 * (nearest neighbour), and its label below the box. */
static void draw_level(unsigned char *canvas, const pbrt_RGBSpectrum *texels, int w, int h, int x0, int y0, int pw,
                       int ph, const char *label) {
  int x, y, c;
  for (y = 0; y < ph; ++y)
    for (x = 0; x < pw; ++x) {
      const pbrt_RGBSpectrum *p = &texels[(y * h / ph) * w + x * w / pw];
      for (c = 0; c < 3; ++c) canvas[3 * ((y0 + y) * CW + x0 + x) + c] = el_film_srgb_to_byte(p->c[c]);
    }
  el_draw_label(canvas, CW, CH, x0, y0 + ph, label);
}
static int write_picture(const char *path, const pbrt_MIPMap *mip, const float *img) {
  unsigned char *canvas = (unsigned char *)malloc(3 * CW * CH);
  char label[64], err[256];
  int l, r;
  memset(canvas, 24, 3 * CW * CH);
  el_draw_text(canvas, CW, CH, 8, 8, 2, "THE MIP MAP OF THE 400X235 TEST IMAGE. LEVELS 2-9 ENLARGED", 230, 230, 230);
  draw_level(canvas, (const pbrt_RGBSpectrum *)img, W, H, 8, 30, W, H, "INPUT 400X235");
  for (l = 0; l < pbrt_MIPMap_Levels(mip); ++l) {
    const pbrt_BlockedArray *a = mip->pyramid[l];
    pbrt_RGBSpectrum *texels = (pbrt_RGBSpectrum *)malloc(sizeof(pbrt_RGBSpectrum) * a->uRes * a->vRes);
    int x0, y0, pw, ph;
    pbrt_BlockedArray_GetLinearArray(a, texels); /* the level in row-major order */
    if (l == 0) { x0 = 416; y0 = 30; pw = 512; ph = 256; }                  /* as it is */
    else if (l <= 3) { x0 = 8 + (l - 1) * 264; y0 = 316; pw = 256; ph = 128; } /* 1x, 2x, 4x */
    else { x0 = 8 + (l - 4) * 136; y0 = 474; pw = 128; ph = 64; }         /* 4x .. 128x */
    if (l <= 3) snprintf(label, sizeof label, "LEVEL %d: %dX%d", l, a->uRes, a->vRes);
    else snprintf(label, sizeof label, "%d: %dX%d", l, a->uRes, a->vRes);
    draw_level(canvas, texels, a->uRes, a->vRes, x0, y0, pw, ph, label);
    free(texels);
  }
  r = el_image_write_png(path, canvas, CW, CH, 3, err, sizeof err);
  if (r != 0) fprintf(stderr, "01_mipmap_pyramid: %s\n", err);
  else printf("wrote %s\n", path);
  free(canvas);
  return r;
}

/* ---- the exercises' numbers -------------------------------------------------------------------- */
static void answers(const float *img) {
  static const int sizes[][2] = {{2048, 1024}, {400, 235}, {1, 1}, {3000, 1}};
  pbrt_ResampleWeight *wt;
  pbrt_MIPMap mip;
  int i, j;
  double bytes0, bytes;
  printf("exercise 1.1: level counts\n");
  for (i = 0; i < 4; ++i) {
    int w = pbrt_RoundUpPow2(sizes[i][0]), h = pbrt_RoundUpPow2(sizes[i][1]);
    printf("  %d x %d -> level 0 %d x %d, %d levels\n", sizes[i][0], sizes[i][1], w, h,
           1 + pbrt_Log2Int((uint32_t)(w > h ? w : h)));
  }
  printf("exercise 1.2: resampleWeights(400, 512)\n");
  wt = pbrt_MIPMap_resampleWeights(400, 512);
  for (i = 0; i < 512; i += 511) {
    printf("  texel %d: firstTexel %d, weights", i, wt[i].firstTexel);
    for (j = 0; j < 4; ++j) printf(" %.4f", wt[i].weight[j]);
    printf("\n");
  }
  free(wt);
  printf("exercise 1.3: memory of the 512 x 256 RGB pyramid\n");
  pbrt_MIPMap_init(&mip, pbrt_Point2i_make(W, H), (const pbrt_RGBSpectrum *)img, 0, 8.f, pbrt_ImageWrap_Repeat);
  bytes0 = sizeof(pbrt_RGBSpectrum) * 512.0 * 256.0;
  for (bytes = 0, i = 0; i < pbrt_MIPMap_Levels(&mip); ++i)
    bytes += sizeof(pbrt_RGBSpectrum) * (double)mip.pyramid[i]->uRes * mip.pyramid[i]->vRes;
  printf("  level 0 %.0f bytes, all levels %.0f bytes, ratio %.4f\n", bytes0, bytes, bytes / bytes0);
  pbrt_MIPMap_free(&mip);
  printf("exercise 1.4: Black wrap, the port's top level against the mean of level 0\n");
  for (i = 0; i < 3; ++i) {
    int w = 64, h = 64 >> (2 * i); /* 1:1, 4:1, 16:1 */
    float *flat = (float *)malloc(sizeof(float) * 3 * w * h);
    for (j = 0; j < 3 * w * h; ++j) flat[j] = 0.5f;
    pbrt_MIPMap_init(&mip, pbrt_Point2i_make(w, h), (const pbrt_RGBSpectrum *)flat, 0, 8.f, pbrt_ImageWrap_Black);
    printf("  %d x %d: top level holds %.4f of the mean\n", w, h,
           port_level_mean(&mip, pbrt_MIPMap_Levels(&mip) - 1) / port_level_mean(&mip, 0));
    pbrt_MIPMap_free(&mip);
    free(flat);
  }
}

int main(int argc, char **argv) {
  static float img[W * H * 3];
  const char *dir = "out";
  char path[1024];
  pbrt_MIPMap mip, mipb;
  el_mipmap m, mb, mk;
  el_mipmap_options o;
  double t_port = 1e30, t_lib = 1e30, t;
  int l, rep, same = 1, top;
  if (argc > 1 && (!strcmp(argv[1], "--help") || !strcmp(argv[1], "-h") || (argv[1][0] == '-' && strcmp(argv[1], "--answers")))) {
    int help = !strcmp(argv[1], "--help") || !strcmp(argv[1], "-h");
    fprintf(help ? stdout : stderr,
            "usage: 01_mipmap_pyramid [output-directory]   (default: out, created if missing)\n"
            "       01_mipmap_pyramid --answers            (the numbers the exercises ask for; no picture)\n");
    return help ? 0 : 1;
  }
  el_test_image(img, W, H); /* the course's 400x235 test image (linear RGB) */
  if (argc > 1 && !strcmp(argv[1], "--answers")) {
    answers(img);
    return 0;
  }
  if (argc > 1) dir = argv[1];
  if (mkdir(dir, 0777) != 0 && errno != EEXIST) {
    fprintf(stderr, "01_mipmap_pyramid: cannot create directory %s: %s\n", dir, strerror(errno));
    return 1;
  }

  /* The port: MIPMap<RGBSpectrum>(Point2i(400, 235), img), pbrt's defaults (doTrilinear false,
   * maxAnisotropy 8, Repeat). The RGB floats are RGBSpectrum texels (three floats each). */
  pbrt_MIPMap_init(&mip, pbrt_Point2i_make(W, H), (const pbrt_RGBSpectrum *)img, 0, 8.f, pbrt_ImageWrap_Repeat);
  printf("input %d x %d, resampled to %d x %d, %d levels\n", W, H, pbrt_MIPMap_Width(&mip), pbrt_MIPMap_Height(&mip),
         pbrt_MIPMap_Levels(&mip));
  for (l = 0; l < pbrt_MIPMap_Levels(&mip); ++l)
    printf("  level %d: %3d x %-3d mean %.5f\n", l, mip.pyramid[l]->uRes, mip.pyramid[l]->vRes, port_level_mean(&mip, l));

  /* The library on the same image: all-zero options are pbrt's defaults. Its upper levels are built
   * on first need; el_mipmap_build_levels builds them now. */
  if (el_mipmap_init(&m, img, W, H, 3, NULL) != EL_SUCCESS || el_mipmap_build_levels(&m) != EL_SUCCESS) {
    fprintf(stderr, "01_mipmap_pyramid: el_mipmap_init failed\n");
    return 1;
  }
  for (l = 0; l < el_mipmap_levels(&m); ++l) same = same && same_level(&mip, &m, l);
  printf("library: %d levels, the same as the port's bit for bit: %s\n", el_mipmap_levels(&m), same ? "yes" : "NO");

  /* Black wrap: pbrt's box filter reads texel 2t+1 of the 2x1 level through Texel(), and Black makes
   * it 0, so the 1x1 level holds half the mean. The library reads the one row twice. */
  memset(&o, 0, sizeof o);
  o.wrap_u = o.wrap_v = EL_MIPMAP_WRAP_BLACK;
  pbrt_MIPMap_init(&mipb, pbrt_Point2i_make(W, H), (const pbrt_RGBSpectrum *)img, 0, 8.f, pbrt_ImageWrap_Black);
  el_mipmap_init(&mb, img, W, H, 3, &o);
  top = pbrt_MIPMap_Levels(&mipb) - 1;
  for (same = 1, l = 0; l < top; ++l) same = same && same_level(&mipb, &mb, l);
  printf("Black wrap: levels 0-%d the same bit for bit: %s\n", top - 1, same ? "yes" : "NO");
  {
    const float *d = el_mipmap_level_data(&mb, top);
    printf("Black wrap, level %d (1x1): port %.5f, library %.5f, level 0 mean %.5f\n", top, port_level_mean(&mipb, top),
           (d[0] + d[1] + d[2]) / 3.0, port_level_mean(&mipb, 0));
  }
  pbrt_MIPMap_free(&mipb);
  el_mipmap_free(&mb);

  /* keep_resolution = 1 (the library only): level 0 is the input as it is, the upper levels are exact
   * area averages of odd sizes: 400x235, 200x117, ... 1x1. */
  memset(&o, 0, sizeof o);
  o.keep_resolution = 1;
  el_mipmap_init(&mk, img, W, H, 3, &o);
  printf("keep_resolution = 1: %d levels:", el_mipmap_levels(&mk));
  for (l = 0; l < el_mipmap_levels(&mk); ++l) printf(" %dx%d", el_mipmap_level_width(&mk, l), el_mipmap_level_height(&mk, l));
  {
    const float *d = el_mipmap_level_data(&mk, el_mipmap_levels(&mk) - 1);
    double in = 0;
    int i;
    for (i = 0; i < W * H * 3; ++i) in += img[i];
    printf("\nkeep_resolution = 1: input mean %.5f, 1x1 level %.5f\n", in / (W * H * 3), (d[0] + d[1] + d[2]) / 3.0);
  }
  el_mipmap_free(&mk);

  /* The cost, in the same run: each builds the whole pyramid 9 times, interleaved; the fastest of
   * each counts (the machine is shared and noisy). */
  for (rep = 0; rep < 9; ++rep) {
    pbrt_MIPMap p2;
    el_mipmap m2;
    t = now();
    pbrt_MIPMap_init(&p2, pbrt_Point2i_make(W, H), (const pbrt_RGBSpectrum *)img, 0, 8.f, pbrt_ImageWrap_Repeat);
    t = now() - t;
    if (t < t_port) t_port = t;
    pbrt_MIPMap_free(&p2);
    t = now();
    el_mipmap_init(&m2, img, W, H, 3, NULL);
    el_mipmap_build_levels(&m2);
    t = now() - t;
    if (t < t_lib) t_lib = t;
    el_mipmap_free(&m2);
  }
  printf("build, all levels (fastest of 9): port %.2f ms, library %.2f ms, %.1fx\n", 1e3 * t_port, 1e3 * t_lib,
         t_port / t_lib);

  snprintf(path, sizeof path, "%s/01-pyramid.png", dir);
  if (write_picture(path, &mip, img)) return 1;
  pbrt_MIPMap_free(&mip);
  el_mipmap_free(&m);
  return 0;
}
