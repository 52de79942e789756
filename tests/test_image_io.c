/* test_image_io.c: the image loader of examples/common (el_image_load) on good and bad files.
 *
 * Every failure must return -1 with a message that names the file and the problem: a missing file, an
 * empty one, a directory, truncated files (.hdr RLE and flat, .pfm, .exr), corrupt ones (a bad run
 * length, PNG bytes named .hdr, a bad PFM header, a bad EXR magic number) and unsupported extensions.
 * Good files (written by el_image_write_*, and data/envmaps/city.hdr) load with their size and values.
 * stb_image alone "succeeds" on a truncated .hdr (it reads zeros past the end): the loader's own
 * scanline walk is what catches it.
 */
#include "image_io.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifndef EL_TEST_DATA_DIR
#define EL_TEST_DATA_DIR "data"
#endif

static int g_pass = 0, g_fail = 0;
static void check(int ok, const char *what, const char *detail) {
  printf("%s %s%s%s\n", ok ? "PASS" : "FAIL", what, detail ? ": " : "", detail ? detail : "");
  if (ok) ++g_pass; else ++g_fail;
}

/* load must fail, and the message must contain the path and every given keyword */
static void expect_error(const char *what, const char *path, const char *kw1, const char *kw2) {
  el_image img;
  char err[512];
  int r;
  err[0] = 0;
  r = el_image_load(path, &img, err, sizeof err);
  check(r == -1 && strstr(err, path) && (!kw1 || strstr(err, kw1)) && (!kw2 || strstr(err, kw2)) && img.pixels == NULL,
        what, err);
  if (r == 0) el_image_free(&img);
}

static long file_size(const char *path) {
  FILE *f = fopen(path, "rb");
  long n;
  if (!f) return -1;
  fseek(f, 0, SEEK_END);
  n = ftell(f);
  fclose(f);
  return n;
}
/* copy the first n bytes of src into dst */
static int truncate_copy(const char *src, const char *dst, long n) {
  FILE *a = fopen(src, "rb"), *b = fopen(dst, "wb");
  char *buf = (char *)malloc((size_t)n + 1);
  int ok = a && b && buf && fread(buf, 1, (size_t)n, a) == (size_t)n && fwrite(buf, 1, (size_t)n, b) == (size_t)n;
  if (a) fclose(a);
  if (b) fclose(b);
  free(buf);
  return ok ? 0 : -1;
}
static int write_bytes(const char *path, const void *p, size_t n) {
  FILE *f = fopen(path, "wb");
  int ok = f && fwrite(p, 1, n, f) == n;
  if (f) fclose(f);
  return ok ? 0 : -1;
}

int main(void) {
  enum { W = 37, H = 11 };
  float px[W * H * 3];
  char err[512];
  el_image img;
  int i;
  const char *hdr = "test_image_io_tmp.hdr", *hdr_flat = "test_image_io_tmp_flat.hdr", *cut = "test_image_io_tmp_cut.hdr";
  const char *pfm = "test_image_io_tmp.pfm", *pfm_cut = "test_image_io_tmp_cut.pfm", *exr = "test_image_io_tmp.exr";
  const char *exr_cut = "test_image_io_tmp_cut.exr", *png = "test_image_io_tmp.png", *fake = "test_image_io_tmp_png.hdr";
  const char *bad = "test_image_io_tmp_bad.hdr", *empty = "test_image_io_tmp_empty.hdr", *xyz = "test_image_io_tmp.xyz";
  const char *noext = "test_image_io_tmp_noext", *badpfm = "test_image_io_tmp_bad.pfm", *badexr = "test_image_io_tmp_bad.exr";
  for (i = 0; i < W * H * 3; ++i) px[i] = 0.01f + (float)((i * 7) % 101) * 0.37f;

  /* the real map */
  {
    char path[512];
    snprintf(path, sizeof path, "%s/envmaps/city.hdr", EL_TEST_DATA_DIR);
    i = el_image_load(path, &img, err, sizeof err);
    check(i == 0 && img.width == 1024 && img.height == 512 && img.channels == 3 && !img.is_8bit, "data/envmaps/city.hdr loads as 1024x512 RGB float", i ? err : NULL);
    if (i == 0) el_image_free(&img);
  }
  /* .hdr round trip (RLE: width >= 8) */
  {
    int ok = el_image_write_hdr(hdr, px, W, H, 3, err, sizeof err) == 0 && el_image_load(hdr, &img, err, sizeof err) == 0;
    double worst = 0;
    if (ok) {
      /* RGBE shares one exponent per pixel: the error is relative to the pixel's largest channel */
      for (i = 0; i < W * H * 3; ++i) {
        const float *q = px + 3 * (i / 3);
        double mx = fmax(q[0], fmax(q[1], q[2]));
        worst = fmax(worst, fabs(img.pixels[i] - px[i]) / mx);
      }
      ok = img.width == W && img.height == H && worst < 1.0 / 128;
      el_image_free(&img);
    }
    check(ok, "a .hdr written by el_image_write_hdr loads back (RGBE: within 1/128 of the pixel's largest channel)", ok ? NULL : err);
  }
  /* truncated .hdr at several places: in the header, after the resolution line, mid-scanline, one byte short */
  {
    long n = file_size(hdr), cuts[4];
    int k;
    cuts[0] = 8; cuts[1] = 0; cuts[2] = n / 2; cuts[3] = n - 1;
    { /* just after the resolution line */
      FILE *f = fopen(hdr, "rb");
      int c, newlines = 0;
      long pos = 0;
      int prev = 0;
      while (f && (c = fgetc(f)) != EOF) {
        ++pos;
        if (c == '\n') { if (prev == '\n') newlines = 1; else if (newlines == 1) { cuts[1] = pos; break; } }
        prev = c;
      }
      if (f) fclose(f);
    }
    for (k = 0; k < 4; ++k) {
      char what[128];
      snprintf(what, sizeof what, "a .hdr cut to %ld of %ld bytes: error 'truncated' naming the file", cuts[k], n);
      truncate_copy(hdr, cut, cuts[k]);
      expect_error(what, cut, "truncated", NULL);
    }
  }
  /* flat .hdr (width < 8: no run-length encoding), round trip and truncated */
  {
    float small[4 * 3 * 3];
    int ok;
    for (i = 0; i < 36; ++i) small[i] = 0.5f + (float)i;
    ok = el_image_write_hdr(hdr_flat, small, 4, 3, 3, err, sizeof err) == 0 && el_image_load(hdr_flat, &img, err, sizeof err) == 0;
    if (ok) { ok = img.width == 4 && img.height == 3 && fabs(img.pixels[35] - 35.5f) < 0.5f; el_image_free(&img); }
    check(ok, "a flat (4x3, no RLE) .hdr loads back", ok ? NULL : err);
    truncate_copy(hdr_flat, cut, file_size(hdr_flat) - 3);
    expect_error("a flat .hdr 3 bytes short: error 'truncated' naming the file", cut, "truncated", NULL);
  }
  /* corrupt .hdr: a valid header, then a scanline whose run length overflows the width */
  {
    const char head[] = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 2 +X 8\n";
    unsigned char body[64];
    size_t hn = strlen(head), k;
    memcpy(body, head, hn);
    body[hn] = 2; body[hn + 1] = 2; body[hn + 2] = 0; body[hn + 3] = 8;
    body[hn + 4] = 200; /* a run of 72 > width 8 */
    body[hn + 5] = 1;
    for (k = hn + 6; k < sizeof body; ++k) body[k] = 1;
    write_bytes(bad, body, sizeof body);
    expect_error("a .hdr with a run longer than the scanline: error 'corrupt' naming the file", bad, "corrupt", NULL);
  }
  /* PNG bytes under a .hdr name (stb would convert them to float silently) */
  {
    unsigned char rgb8[8 * 8 * 3];
    for (i = 0; i < 192; ++i) rgb8[i] = (unsigned char)(i * 5);
    el_image_write_png(png, rgb8, 8, 8, 3, err, sizeof err);
    truncate_copy(png, fake, file_size(png));
    expect_error("PNG data named .hdr: error 'not a Radiance HDR' naming the file", fake, "not a Radiance HDR", NULL);
    i = el_image_load(png, &img, err, sizeof err);
    check(i == 0 && img.is_8bit && img.width == 8 && img.channels == 3, "the same PNG under its own name loads (8-bit flagged)", i ? err : NULL);
    if (i == 0) el_image_free(&img);
  }
  /* missing, empty, directory, unsupported */
  expect_error("a missing file: error naming the file and the system's reason", "test_image_io_no_such_file.hdr", "cannot open", "No such file");
  write_bytes(empty, "", 0);
  expect_error("an empty file: error 'empty' naming the file", empty, "empty", NULL);
  expect_error("a directory: error naming it", ".", NULL, NULL);
  write_bytes(xyz, "hello", 5);
  expect_error("an unsupported extension .xyz: error 'unsupported' naming the file and the extension", xyz, "unsupported", ".xyz");
  write_bytes(noext, "hello", 5);
  expect_error("no extension: error 'unsupported' naming the file", noext, "unsupported", NULL);
  /* PFM */
  {
    int ok = el_image_write_pfm(pfm, px, W, H, 3, err, sizeof err) == 0 && el_image_load(pfm, &img, err, sizeof err) == 0;
    if (ok) { ok = img.width == W && img.height == H && memcmp(img.pixels, px, sizeof px) == 0; el_image_free(&img); }
    check(ok, "a .pfm round trip is bit-exact (rows flipped back)", ok ? NULL : err);
    truncate_copy(pfm, pfm_cut, file_size(pfm) - 1);
    expect_error("a .pfm one byte short: error 'truncated' naming the file", pfm_cut, "truncated", NULL);
    write_bytes(badpfm, "PX\n4 4\n-1.0\n", 12);
    expect_error("a .pfm with a bad signature: error 'not a PFM' naming the file", badpfm, "not a PFM", NULL);
    write_bytes(badpfm, "PF\n4 -4\n-1.0\n", 13);
    expect_error("a .pfm with a negative height: error 'bad PFM height' naming the file", badpfm, "bad PFM height", NULL);
  }
  /* EXR */
  {
    int ok = el_image_write_exr(exr, px, W, H, 3, err, sizeof err) == 0 && el_image_load(exr, &img, err, sizeof err) == 0;
    if (ok) { ok = img.width == W && img.height == H && memcmp(img.pixels, px, sizeof px) == 0; el_image_free(&img); }
    check(ok, "an .exr round trip (float32) is bit-exact", ok ? NULL : err);
    truncate_copy(exr, exr_cut, file_size(exr) / 2);
    expect_error("an .exr cut in half: error 'truncated' naming the file", exr_cut, "truncated", NULL);
    truncate_copy(exr, exr_cut, 40);
    expect_error("an .exr cut inside its header: error naming the file", exr_cut, "EXR", NULL);
    truncate_copy(hdr, badexr, file_size(hdr));
    expect_error("Radiance data named .exr: error 'not an OpenEXR file' naming the file", badexr, "not an OpenEXR", NULL);
  }
  remove(hdr); remove(hdr_flat); remove(cut); remove(pfm); remove(pfm_cut); remove(exr); remove(exr_cut); remove(png);
  remove(fake); remove(bad); remove(empty); remove(xyz); remove(noext); remove(badpfm); remove(badexr);
  printf("test_image_io: %d passed, %d failed\n", g_pass, g_fail);
  return g_fail ? 1 : 0;
}
