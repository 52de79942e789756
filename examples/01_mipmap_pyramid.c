/* 01_mipmap_pyramid.c: build a MIP map of a 400x235 test image and write every level as a PNG
 * (chapter 1-2 of the tutorial, "MIPMap" and "porting MIPMap").
 *
 * WHAT IT DEMONSTRATES
 *   The tutorial builds its MIPMap from a 400x235 image made in code. 400 and 235 are not powers of
 *   two, so pbrt first resamples the image up to 512x256 with 4-tap Lanczos weights (negative ringing
 *   clamped to 0), then box-filters it down, level by level, to 1x1. The test image has detail at
 *   every scale: a checkerboard whose frequency rises from left to right (4 to 64 checks across) over
 *   a colour ramp, so you can watch each level average away the finest checks while the ramp survives.
 *   It also builds the same image with keep_resolution = 1 (level 0 is the input texel for texel, and
 *   the upper levels are exact area averages 400x235, 200x117, ... 1x1) and prints both pyramids'
 *   sizes, means and bytes: every level keeps the mean of level 0.
 *
 * WHICH PART OF PBRT IT MIRRORS
 *   pbrt-v3 section 10.4.1 "Image pyramid" (src/core/mipmap.h): the MIPMap constructor,
 *   <<Resample image to power-of-two resolution>> (resampleWeights, Lanczos), <<Initialize levels of
 *   MIPMap from image>>, <<Initialize most detailed level of MIPMap>>, <<Initialize ith MIPMap level
 *   from (i-1)st level>>. All of it lives in mipmap.h; this file only calls it.
 *
 * HOW TO RUN IT
 *   build/bin/01_mipmap_pyramid [output-directory]        (default: out, created if missing)
 *   tutorials/01-mipmap.md walks through it.
 *
 * WHAT IT WRITES
 *   <dir>/01_input_400x235.png, <dir>/01_level_NN_WxH.png for each of the 10 levels of the resampled
 *   pyramid, and <dir>/01_pyramid.png (800x319), all levels in one picture (the small ones enlarged
 *   with nearest-neighbour pixels so that they can be seen); the paths, and each level's size and
 *   mean for both pyramids, on stdout.
 */
#define _POSIX_C_SOURCE 200809L /* mkdir */
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

#define W 400
#define H 235



static int write_rgb(const char *path, const float *rgb, int w, int h) {
  unsigned char *b = (unsigned char *)malloc((size_t)w * h * 3);
  char err[256];
  int i, r;
  for (i = 0; i < w * h * 3; ++i) b[i] = el_film_srgb_to_byte(rgb[i]);
  r = el_image_write_png(path, b, w, h, 3, err, sizeof err);
  if (r != 0) fprintf(stderr, "01_mipmap_pyramid: %s\n", err);
  else printf("wrote %s\n", path);
  free(b);
  return r;
}

static void print_pyramid(const char *title, const el_mipmap *m) {
  int l, c;
  printf("%s: %d levels, %zu bytes once built\n", title, el_mipmap_levels(m), el_mipmap_bytes(m));
  for (l = 0; l < el_mipmap_levels(m); ++l) {
    int w = el_mipmap_level_width(m, l), h = el_mipmap_level_height(m, l), i;
    const float *d = el_mipmap_level_data(m, l);
    double mean[3] = {0, 0, 0};
    for (i = 0; i < w * h; ++i)
      for (c = 0; c < 3; ++c) mean[c] += d[3 * i + c];
    printf("  level %2d: %4d x %-4d mean (%.5f, %.5f, %.5f)\n", l, w, h, mean[0] / (w * h), mean[1] / (w * h),
           mean[2] / (w * h));
  }
}

int main(int argc, char **argv) {
  const char *dir = argc > 1 ? argv[1] : "out";
  static float img[W * H * 3];
  char path[1024];
  el_mipmap m, mk;
  el_mipmap_options keep;
  el_result r;
  int l, cw, ch, x, y, ox;
  float *canvas;
  if (mkdir(dir, 0777) != 0 && errno != EEXIST) {
    fprintf(stderr, "01_mipmap_pyramid: cannot create directory %s: %s\n", dir, strerror(errno));
    return 1;
  }
  el_test_image(img, W, H);
  snprintf(path, sizeof path, "%s/01_input_%dx%d.png", dir, W, H);
  if (write_rgb(path, img, W, H)) return 1;

  /* <<Resample image to power-of-two resolution>> and <<Initialize levels of MIPMap from image>>:
   * pbrt's defaults (all-zero options: Repeat, EWA, max anisotropy 8). */
  r = el_mipmap_init(&m, img, W, H, 3, NULL);
  if (r != EL_SUCCESS) {
    fprintf(stderr, "01_mipmap_pyramid: el_mipmap_init: %s\n", el_result_string(r));
    return 1;
  }
  printf("level 0 only, right after el_mipmap_init: %zu bytes\n", el_mipmap_bytes(&m));
  el_mipmap_build_levels(&m); /* <<Initialize ith MIPMap level from (i-1)st level>>, all of them */
  for (l = 0; l < el_mipmap_levels(&m); ++l) {
    int w = el_mipmap_level_width(&m, l), h = el_mipmap_level_height(&m, l);
    snprintf(path, sizeof path, "%s/01_level_%02d_%dx%d.png", dir, l, w, h);
    if (write_rgb(path, el_mipmap_level_data(&m, l), w, h)) return 1;
  }
  /* all levels in one picture: level 0 (512x256) at the top left; level 1 (256x128) and level 2
   * (shown at 2x) at the top right; levels 3..9 along the bottom, each enlarged to 110x55 with
   * nearest-neighbour pixels */
  cw = 800;
  ch = 256 + 8 + 55;
  canvas = (float *)malloc(sizeof(float) * 3 * (size_t)cw * ch);
  for (x = 0; x < cw * ch * 3; ++x) canvas[x] = 0.05f;
  for (l = 0; l < el_mipmap_levels(&m); ++l) {
    int w = el_mipmap_level_width(&m, l), h = el_mipmap_level_height(&m, l), pw, ph, oy;
    const float *d = el_mipmap_level_data(&m, l);
    if (l == 0) { ox = 0; oy = 0; pw = 512; ph = 256; }
    else if (l <= 2) { ox = 520; oy = (l - 1) * 128; pw = 256; ph = 128; }
    else { ox = (l - 3) * 114; oy = 264; pw = 110; ph = 55; }
    for (y = 0; y < ph; ++y)
      for (x = 0; x < pw; ++x) {
        int sx = x * w / pw, sy = y * h / ph, c;
        for (c = 0; c < 3; ++c) canvas[3 * ((oy + y) * cw + ox + x) + c] = d[3 * (sy * w + sx) + c];
      }
  }
  snprintf(path, sizeof path, "%s/01_pyramid.png", dir);
  write_rgb(path, canvas, cw, ch);
  free(canvas);
  print_pyramid("resampled to 512x256 (pbrt)", &m);

  memset(&keep, 0, sizeof keep);
  keep.keep_resolution = 1;
  el_mipmap_init(&mk, img, W, H, 3, &keep);
  el_mipmap_build_levels(&mk);
  print_pyramid("keep_resolution = 1 (400x235 as is, exact area averages)", &mk);
  el_mipmap_free(&mk);
  el_mipmap_free(&m);
  return 0;
}
