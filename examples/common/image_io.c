/* image_io.c: see image_io.h. stb and tinyexr come compiled from Debian (libstb.so, libtinyexr.so);
 * this file includes only their declarations. */
#include "image_io.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <stb_image.h>
#include <stb_image_write.h>
#include <tinyexr.h>

static int el_io__fail(char *err, size_t errlen, const char *path, const char *fmt, ...) {
  if (err && errlen) {
    va_list ap;
    int n = snprintf(err, errlen, "%s: ", path ? path : "(null)");
    if (n < 0) n = 0;
    if ((size_t)n < errlen) {
      va_start(ap, fmt);
      vsnprintf(err + n, errlen - (size_t)n, fmt, ap);
      va_end(ap);
    }
  }
  return -1;
}

const char *el_image_extension(const char *path) {
  static char ext[16];
  const char *dot = path ? strrchr(path, '.') : NULL;
  const char *slash = path ? strrchr(path, '/') : NULL;
  size_t i = 0;
  ext[0] = 0;
  if (!dot || (slash && slash > dot)) return ext;
  for (dot++; *dot && i + 1 < sizeof ext; dot++) ext[i++] = (char)tolower((unsigned char)*dot);
  ext[i] = 0;
  return ext;
}

void el_image_free(el_image *img) {
  if (!img) return;
  free(img->pixels);
  memset(img, 0, sizeof *img);
}

static long el_io__file_size(FILE *f) {
  long n;
  if (fseek(f, 0, SEEK_END) != 0) return -1;
  n = ftell(f);
  if (fseek(f, 0, SEEK_SET) != 0) return -1;
  return n;
}

/* ---- PFM (Portable Float Map): "PF" (RGB) or "Pf" (grey), width height, scale (<0: little endian),
 * rows bottom to top. */
static int el_io__read_token(FILE *f, char *buf, size_t n) {
  int c;
  size_t i = 0;
  do { c = fgetc(f); } while (c != EOF && isspace(c));
  while (c != EOF && !isspace(c)) {
    if (i + 1 >= n) return -1;
    buf[i++] = (char)c;
    c = fgetc(f);
  }
  buf[i] = 0;
  return i ? 0 : -1; /* one whitespace character after the last token has been consumed */
}

static int el_io__load_pfm(const char *path, FILE *f, el_image *img, char *err, size_t errlen) {
  char tok[64], *end;
  long w, h, size, need;
  double scale;
  int ch, y;
  size_t row;
  unsigned char probe[4] = {1, 0, 0, 0};
  int host_little = probe[0] == 1;
  if (el_io__read_token(f, tok, sizeof tok) || (strcmp(tok, "PF") && strcmp(tok, "Pf")))
    return el_io__fail(err, errlen, path, "not a PFM file (header must start with PF or Pf)");
  ch = tok[1] == 'F' ? 3 : 1;
  if (el_io__read_token(f, tok, sizeof tok)) return el_io__fail(err, errlen, path, "PFM header is truncated");
  w = strtol(tok, &end, 10);
  if (*end || w <= 0 || w > 1 << 20) return el_io__fail(err, errlen, path, "bad PFM width '%s'", tok);
  if (el_io__read_token(f, tok, sizeof tok)) return el_io__fail(err, errlen, path, "PFM header is truncated");
  h = strtol(tok, &end, 10);
  if (*end || h <= 0 || h > 1 << 20) return el_io__fail(err, errlen, path, "bad PFM height '%s'", tok);
  if (el_io__read_token(f, tok, sizeof tok)) return el_io__fail(err, errlen, path, "PFM header is truncated");
  scale = strtod(tok, &end);
  if (*end || scale == 0 || scale != scale) return el_io__fail(err, errlen, path, "bad PFM scale '%s'", tok);
  if ((double)w * (double)h * ch > 1 << 30) return el_io__fail(err, errlen, path, "PFM image too large (%ldx%ld)", w, h);
  row = (size_t)w * (size_t)ch;
  {
    long here = ftell(f);
    size = el_io__file_size(f);
    need = (long)(row * (size_t)h * 4);
    if (here < 0 || size < 0 || fseek(f, here, SEEK_SET) != 0)
      return el_io__fail(err, errlen, path, "cannot seek in file");
    if (size - here < need)
      return el_io__fail(err, errlen, path, "file is truncated (%ld bytes of pixel data, %ld expected)", size - here, need);
  }
  img->pixels = (float *)malloc(row * (size_t)h * sizeof(float));
  if (!img->pixels) return el_io__fail(err, errlen, path, "out of memory");
  img->width = (int)w; img->height = (int)h; img->channels = ch; img->is_8bit = 0;
  for (y = (int)h - 1; y >= 0; y--) { /* PFM stores the bottom row first */
    float *dst = img->pixels + (size_t)y * row;
    size_t i;
    if (fread(dst, 4, row, f) != row) { el_image_free(img); return el_io__fail(err, errlen, path, "file is truncated"); }
    if ((scale < 0) != host_little) {
      for (i = 0; i < row; i++) {
        unsigned char *b = (unsigned char *)(dst + i), t;
        t = b[0]; b[0] = b[3]; b[3] = t; t = b[1]; b[1] = b[2]; b[2] = t;
      }
    }
  }
  return 0;
}

int el_image_load(const char *path, el_image *img, char *err, size_t errlen) {
  const char *ext;
  FILE *f;
  if (!img) return el_io__fail(err, errlen, path, "no output image given");
  memset(img, 0, sizeof *img);
  if (!path || !*path) return el_io__fail(err, errlen, "(empty path)", "no file name given");
  f = fopen(path, "rb");
  if (!f) return el_io__fail(err, errlen, path, "cannot open file (%s)", strerror(errno));
  ext = el_image_extension(path);
  if (el_io__file_size(f) == 0) { fclose(f); return el_io__fail(err, errlen, path, "file is empty"); }
  if (!strcmp(ext, "pfm")) {
    int r = el_io__load_pfm(path, f, img, err, errlen);
    fclose(f);
    return r;
  }
  fclose(f);
  if (!strcmp(ext, "exr")) {
    float *rgba = NULL;
    int w = 0, h = 0, r;
    size_t i, n;
    const char *msg = NULL;
    r = LoadEXR(&rgba, &w, &h, path, &msg);
    if (r != TINYEXR_SUCCESS) {
      el_io__fail(err, errlen, path, "cannot read EXR (%s)", msg ? msg : "unknown tinyexr error");
      if (msg) FreeEXRErrorMessage(msg);
      free(rgba);
      return -1;
    }
    if (w <= 0 || h <= 0) { free(rgba); return el_io__fail(err, errlen, path, "EXR has no pixels"); }
    n = (size_t)w * (size_t)h;
    img->pixels = (float *)malloc(n * 3 * sizeof(float));
    if (!img->pixels) { free(rgba); return el_io__fail(err, errlen, path, "out of memory"); }
    for (i = 0; i < n; i++) {
      img->pixels[3 * i + 0] = rgba[4 * i + 0];
      img->pixels[3 * i + 1] = rgba[4 * i + 1];
      img->pixels[3 * i + 2] = rgba[4 * i + 2];
    }
    free(rgba);
    img->width = w; img->height = h; img->channels = 3; img->is_8bit = 0;
    return 0;
  }
  if (!strcmp(ext, "hdr")) {
    int w, h, n;
    float *p = stbi_loadf(path, &w, &h, &n, 3);
    if (!p) return el_io__fail(err, errlen, path, "cannot read Radiance HDR (%s)", stbi_failure_reason());
    img->pixels = p; img->width = w; img->height = h; img->channels = 3; img->is_8bit = 0;
    return 0;
  }
  if (!strcmp(ext, "png") || !strcmp(ext, "jpg") || !strcmp(ext, "jpeg") || !strcmp(ext, "tga") ||
      !strcmp(ext, "bmp")) {
    int w, h, n;
    size_t i, count;
    unsigned char *p = stbi_load(path, &w, &h, &n, 0);
    if (!p) return el_io__fail(err, errlen, path, "cannot read image (%s)", stbi_failure_reason());
    count = (size_t)w * (size_t)h * (size_t)n;
    img->pixels = (float *)malloc(count * sizeof(float));
    if (!img->pixels) { stbi_image_free(p); return el_io__fail(err, errlen, path, "out of memory"); }
    for (i = 0; i < count; i++) img->pixels[i] = p[i] / 255.0f;
    stbi_image_free(p);
    img->width = w; img->height = h; img->channels = n; img->is_8bit = 1;
    return 0;
  }
  return el_io__fail(err, errlen, path, "unsupported image format '.%s' (supported: .hdr .exr .pfm .png .jpg .tga .bmp)", ext);
}

static int el_io__check_args(const char *path, const void *pixels, int width, int height, int channels,
                             char *err, size_t errlen) {
  if (!pixels) return el_io__fail(err, errlen, path, "no pixels given");
  if (width <= 0 || height <= 0) return el_io__fail(err, errlen, path, "bad image size %dx%d", width, height);
  if (channels < 1 || channels > 4) return el_io__fail(err, errlen, path, "bad channel count %d", channels);
  return 0;
}

int el_image_write_png(const char *path, const unsigned char *rgb8, int width, int height, int channels,
                       char *err, size_t errlen) {
  if (el_io__check_args(path, rgb8, width, height, channels, err, errlen)) return -1;
  if (!stbi_write_png(path, width, height, channels, rgb8, width * channels))
    return el_io__fail(err, errlen, path, "cannot write PNG (%s)", strerror(errno));
  return 0;
}

int el_image_write_hdr(const char *path, const float *pixels, int width, int height, int channels,
                       char *err, size_t errlen) {
  if (el_io__check_args(path, pixels, width, height, channels, err, errlen)) return -1;
  if (!stbi_write_hdr(path, width, height, channels, pixels))
    return el_io__fail(err, errlen, path, "cannot write Radiance HDR (%s)", strerror(errno));
  return 0;
}

int el_image_write_exr(const char *path, const float *pixels, int width, int height, int channels,
                       char *err, size_t errlen) {
  const char *msg = NULL;
  if (el_io__check_args(path, pixels, width, height, channels, err, errlen)) return -1;
  if (channels == 2) return el_io__fail(err, errlen, path, "EXR writer takes 1, 3 or 4 channels, not 2");
  { /* open the file first: tinyexr's SaveEXR leaks its header arrays when it cannot create the file */
    FILE *probe = fopen(path, "wb");
    if (!probe) return el_io__fail(err, errlen, path, "cannot write EXR (cannot open for writing: %s)", strerror(errno));
    fclose(probe);
  }
  if (SaveEXR(pixels, width, height, channels, 0 /* float32 */, path, &msg) != TINYEXR_SUCCESS) {
    el_io__fail(err, errlen, path, "cannot write EXR (%s)", msg ? msg : strerror(errno));
    if (msg) FreeEXRErrorMessage(msg);
    return -1;
  }
  return 0;
}

int el_image_write_pfm(const char *path, const float *pixels, int width, int height, int channels,
                       char *err, size_t errlen) {
  FILE *f;
  int y, x, c, ch = channels == 1 ? 1 : 3;
  unsigned char probe[4] = {1, 0, 0, 0};
  if (el_io__check_args(path, pixels, width, height, channels, err, errlen)) return -1;
  f = fopen(path, "wb");
  if (!f) return el_io__fail(err, errlen, path, "cannot open for writing (%s)", strerror(errno));
  fprintf(f, "%s\n%d %d\n%s\n", ch == 3 ? "PF" : "Pf", width, height, probe[0] == 1 ? "-1.0" : "1.0");
  for (y = height - 1; y >= 0; y--)
    for (x = 0; x < width; x++)
      for (c = 0; c < ch; c++) {
        const float *p = pixels + ((size_t)y * width + x) * channels;
        float v = channels >= 3 ? p[c] : p[0];
        if (channels == 2) v = p[c < 2 ? c : 1];
        if (fwrite(&v, 4, 1, f) != 1) { fclose(f); return el_io__fail(err, errlen, path, "write failed"); }
      }
  if (fclose(f) != 0) return el_io__fail(err, errlen, path, "write failed (%s)", strerror(errno));
  return 0;
}

int el_image_write_float(const char *path, const float *pixels, int width, int height, int channels,
                         char *err, size_t errlen) {
  const char *ext = el_image_extension(path);
  if (!strcmp(ext, "exr")) return el_image_write_exr(path, pixels, width, height, channels, err, errlen);
  if (!strcmp(ext, "hdr")) return el_image_write_hdr(path, pixels, width, height, channels, err, errlen);
  if (!strcmp(ext, "pfm")) return el_image_write_pfm(path, pixels, width, height, channels, err, errlen);
  return el_io__fail(err, errlen, path, "unsupported float image format '.%s' (use .exr .hdr .pfm)", ext);
}
