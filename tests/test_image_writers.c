/* test_image_writers.c: an asymmetric "F" image through every writer in examples/common/image_io.c
 * (PNG, Radiance HDR, PFM, EXR), read back with the matching reader (el_image_load).
 *
 * The image is W x H with an "F" in red (1 on the letter, 0 elsewhere), green = (x + 1) / 8 and
 * blue = (y + 1) / 16. A vertical flip moves the F's bar to the bottom, a horizontal flip moves its
 * stem to the right, a transpose changes the size, and a channel swap mixes the gradients. The values
 * are dyadic with few bits, so RGBE, float32 and PFM store them exactly; the PNG stores code values.
 */
#include "image_io.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int g_pass, g_fail;
static void check(int ok, const char *what) {
  if (ok) g_pass++; else g_fail++;
  printf("%s: %s\n", ok ? "PASS" : "FAIL", what);
}

enum { W = 6, H = 8 };
/* rows top to bottom */
static const char *F_SHAPE[H] = {
  "......",
  ".####.",
  ".#....",
  ".###..",
  ".#....",
  ".#....",
  ".#....",
  "......"};

static float expected(int x, int y, int c) {
  if (c == 0) return F_SHAPE[y][x] == '#' ? 1.0f : 0.0f;
  if (c == 1) return (x + 1) / 8.0f;
  if (c == 2) return (y + 1) / 16.0f;
  return 0.5f; /* alpha */
}

static void make(float *img, int channels) {
  int x, y, c;
  for (y = 0; y < H; y++)
    for (x = 0; x < W; x++)
      for (c = 0; c < channels; c++) img[(y * W + x) * channels + c] = expected(x, y, c);
}

/* compares the loaded image with the expected one; tolerance in absolute units */
static int compare(const el_image *im, int channels, double tol, const char *what) {
  int x, y, c, bad = 0;
  char buf[300];
  if (im->width != W || im->height != H || im->channels != channels) {
    snprintf(buf, sizeof buf, "%s: size %dx%dx%d, expected %dx%dx%d", what, im->width, im->height, im->channels, W, H,
             channels);
    check(0, buf);
    return 0;
  }
  for (y = 0; y < H; y++)
    for (x = 0; x < W; x++)
      for (c = 0; c < channels; c++) {
        double e = expected(x, y, c), g = im->pixels[(y * W + x) * channels + c];
        if (fabs(e - g) > tol) {
          if (bad < 3) printf("  %s: pixel (%d,%d) channel %d: %g, expected %g\n", what, x, y, c, g, e);
          bad++;
        }
      }
  snprintf(buf, sizeof buf, "%s: %dx%d, %d channels, orientation and channel order right (%d bad values)", what, W, H,
           channels, bad);
  check(bad == 0, buf);
  return bad == 0;
}

static void roundtrip_float(const char *ext, int channels_in, int channels_out) {
  char path[256], err[512], what[64];
  float img[W * H * 4];
  el_image im;
  make(img, channels_in);
  snprintf(path, sizeof path, "test_image_writers_%dch.%s", channels_in, ext);
  snprintf(what, sizeof what, ".%s (%d channels written)", ext, channels_in);
  if (el_image_write_float(path, img, W, H, channels_in, err, sizeof err) != 0) {
    printf("  %s\n", err);
    check(0, what);
    return;
  }
  if (el_image_load(path, &im, err, sizeof err) != 0) {
    printf("  %s\n", err);
    check(0, what);
    return;
  }
  if (channels_out == 1) { /* grey: the writer got 1 channel = red */
    int x, y, bad = 0;
    char buf[200];
    for (y = 0; y < H && im.channels >= 1; y++)
      for (x = 0; x < W; x++)
        if (im.pixels[(y * W + x) * im.channels] != expected(x, y, 0)) bad++;
    snprintf(buf, sizeof buf, "%s: grey F read back (%dx%d, %d channels, %d bad)", what, im.width, im.height,
             im.channels, bad);
    check(im.width == W && im.height == H && bad == 0, buf);
  } else {
    compare(&im, channels_out, 0.0, what);
  }
  el_image_free(&im);
  remove(path);
}

int main(void) {
  char err[512];
  unsigned char rgb8[W * H * 4];
  float img[W * H * 3];
  el_image im;
  int i, c;

  /* PNG: 8-bit codes in, codes / 255 out */
  for (c = 3; c <= 4; c += 1) {
    char path[64], what[64];
    make(img, 3);
    for (i = 0; i < W * H; i++) {
      int k;
      for (k = 0; k < 3; k++) rgb8[i * c + k] = (unsigned char)(img[i * 3 + k] * 255.0f + 0.5f);
      if (c == 4) rgb8[i * c + 3] = 128;
    }
    snprintf(path, sizeof path, "test_image_writers_%dch.png", c);
    snprintf(what, sizeof what, ".png (%d channels)", c);
    if (el_image_write_png(path, rgb8, W, H, c, err, sizeof err) != 0 || el_image_load(path, &im, err, sizeof err) != 0) {
      printf("  %s\n", err);
      check(0, what);
      continue;
    }
    check(im.is_8bit == 1, ".png read back as 8-bit");
    {
      int x, y, k, bad = 0;
      char buf[200];
      for (y = 0; y < H; y++)
        for (x = 0; x < W; x++)
          for (k = 0; k < c && im.channels == c; k++) {
            double e = k == 3 ? 128 / 255.0 : floor(expected(x, y, k) * 255.0 + 0.5) / 255.0;
            if (fabs(im.pixels[(y * W + x) * c + k] - e) > 1e-6) bad++;
          }
      snprintf(buf, sizeof buf, "%s: %dx%d (read %dx%dx%d), orientation and channel order right (%d bad)", what, W, H,
               im.width, im.height, im.channels, bad);
      check(im.width == W && im.height == H && im.channels == c && bad == 0, buf);
    }
    el_image_free(&im);
    remove(path);
  }

  roundtrip_float("hdr", 3, 3);
  roundtrip_float("pfm", 3, 3);
  roundtrip_float("exr", 3, 3);
  roundtrip_float("exr", 4, 3); /* alpha dropped by the loader */
  roundtrip_float("pfm", 1, 1);
  roundtrip_float("exr", 1, 1);
  roundtrip_float("hdr", 1, 1);
  roundtrip_float("hdr", 4, 3); /* RGBE has no alpha */
  roundtrip_float("pfm", 4, 3); /* PFM has no alpha */

  /* errors name the file */
  make(img, 3);
  check(el_image_write_float("no_such_dir/x.exr", img, W, H, 3, err, sizeof err) != 0 && strstr(err, "no_such_dir/x.exr"),
        "EXR write into a missing directory fails, naming the file");
  printf("  (%s)\n", err);
  check(el_image_write_float("no_such_dir/x.pfm", img, W, H, 3, err, sizeof err) != 0 && strstr(err, "no_such_dir/x.pfm"),
        "PFM write into a missing directory fails, naming the file");
  check(el_image_write_float("no_such_dir/x.hdr", img, W, H, 3, err, sizeof err) != 0 && strstr(err, "no_such_dir/x.hdr"),
        "HDR write into a missing directory fails, naming the file");
  check(el_image_write_png("no_such_dir/x.png", rgb8, W, H, 3, err, sizeof err) != 0 && strstr(err, "no_such_dir/x.png"),
        "PNG write into a missing directory fails, naming the file");
  check(el_image_write_float("x.tiff", img, W, H, 3, err, sizeof err) != 0 && strstr(err, "x.tiff"),
        "unsupported extension rejected, naming the file");
  check(el_image_write_png("x.png", rgb8, 0, H, 3, err, sizeof err) != 0, "zero width rejected");

  printf("test_image_writers: %d passed, %d failed\n", g_pass, g_fail);
  return g_fail != 0;
}
