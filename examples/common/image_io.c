/* image_io.c: see image_io.h. stb and OpenEXR come compiled from Debian (libstb.so; libOpenEXRCore and
 * libOpenEXR, the reference OpenEXR library): this file includes only their declarations. */
#define _POSIX_C_SOURCE 200809L /* stat */
#include "image_io.h"
#include "exr_codec.h"

#include <sys/stat.h>

#include <ctype.h>
#include <errno.h>
#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <stb_image.h>
#include <stb_image_write.h>
#include <openexr.h>
#include <zlib.h>

/* The most pixels a file may decode to (16384 x 16384): run-length encoded HDR and deflated PNG data
 * expand by up to 1000 times, so a 64 MB Radiance file of 2^24 x 64 pixels asked stb_image for 12 GB of
 * floats before anything could refuse its size. */
#define EL_IO__MAX_PIXELS ((double)(1 << 28))

static int el_io__fail(char *err, size_t errlen, const char *path, const char *fmt, ...) {
  if (err && errlen) {
    va_list ap;
    int n = snprintf(err, errlen, "%s: ", path ? path : "(null)");
    if (n < 0) n = 0;
    if ((size_t)n < errlen) {
      char *c;
      va_start(ap, fmt);
      vsnprintf(err + n, errlen - (size_t)n, fmt, ap);
      va_end(ap);
      /* the message may quote bytes of a corrupt file (a PFM header token): keep it printable ASCII */
      for (c = err + n; *c; c++)
        if (*c == '\n' || *c == '\t') *c = ' '; /* library messages may span lines */
        else if ((unsigned char)*c < 32 || (unsigned char)*c >= 127) *c = '?';
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

/* ---- Radiance HDR: stb_image reads past the end of a truncated file as zeros and "succeeds", and
 * converts any 8-bit image named .hdr to float. So we check the header and walk the scanlines' run
 * lengths first (no decoding): the file must hold every byte of every scanline. */
static int el_io__check_hdr(const char *path, FILE *f, long size, char *err, size_t errlen) {
  unsigned char *b;
  long pos = 0, i;
  int w = 0, h = 0, y;
  char line[256];
  size_t n;
  if (size < 0) return el_io__fail(err, errlen, path, "cannot determine the file size");
  b = (unsigned char *)malloc((size_t)size + 1);
  if (!b) return el_io__fail(err, errlen, path, "out of memory");
  n = fread(b, 1, (size_t)size, f);
  if (n != (size_t)size) { free(b); return el_io__fail(err, errlen, path, "cannot read file (%s)", ferror(f) ? strerror(errno) : "short read"); }
/* the message is formatted before b is freed: its arguments may read b */
#define EL_IO__HDR_FAIL(...) do { el_io__fail(err, errlen, path, __VA_ARGS__); free(b); return -1; } while (0)
  if (size < 2 || b[0] != '#' || b[1] != '?') EL_IO__HDR_FAIL("not a Radiance HDR file (no '#?' signature at the start)");
  /* header lines up to an empty line; FORMAT must be 32-bit_rle_rgbe when present */
  for (;;) {
    long s0 = pos;
    while (pos < size && b[pos] != '\n') ++pos;
    if (pos >= size) EL_IO__HDR_FAIL("file is truncated (the header has no end)");
    i = pos - s0 < (long)sizeof line - 1 ? pos - s0 : (long)sizeof line - 1;
    memcpy(line, b + s0, (size_t)i);
    line[i] = 0;
    ++pos;
    if (i == 0) break;
    if (!strncmp(line, "FORMAT=", 7) && strcmp(line + 7, "32-bit_rle_rgbe"))
      EL_IO__HDR_FAIL("unsupported Radiance HDR pixel format '%s' (only 32-bit_rle_rgbe)", line + 7);
  }
  { /* resolution line: "-Y h +X w" */
    long s0 = pos;
    char *e1, *e2;
    long hh, ww;
    while (pos < size && b[pos] != '\n') ++pos;
    if (pos >= size) EL_IO__HDR_FAIL("file is truncated (no resolution line)");
    i = pos - s0 < (long)sizeof line - 1 ? pos - s0 : (long)sizeof line - 1;
    memcpy(line, b + s0, (size_t)i);
    line[i] = 0;
    ++pos;
    if (strncmp(line, "-Y ", 3)) EL_IO__HDR_FAIL("unsupported Radiance HDR orientation '%s' (only '-Y height +X width')", line);
    hh = strtol(line + 3, &e1, 10);
    if (strncmp(e1, " +X ", 4)) EL_IO__HDR_FAIL("unsupported Radiance HDR orientation '%s' (only '-Y height +X width')", line);
    ww = strtol(e1 + 4, &e2, 10);
    if (*e2 || hh <= 0 || ww <= 0 || hh > (1 << 24) || ww > (1 << 24))
      EL_IO__HDR_FAIL("bad Radiance HDR resolution line '%s'", line);
    if ((double)hh * (double)ww > EL_IO__MAX_PIXELS)
      EL_IO__HDR_FAIL("Radiance HDR image too large (%ld x %ld, more than %.0f pixels)", ww, hh, EL_IO__MAX_PIXELS);
    w = (int)ww; h = (int)hh;
  }
  /* scanlines */
  for (y = 0; y < h; ++y) {
    if (w >= 8 && w < 32768 && pos + 4 > size)
      EL_IO__HDR_FAIL("file is truncated (scanline %d of %d is missing)", y + 1, h);
    if (w < 8 || w >= 32768 || b[pos] != 2 || b[pos + 1] != 2 || (b[pos + 2] & 0x80)) {
      /* flat (uncompressed). stb_image then decodes the whole image flat from here -- from row 0 again
       * when this is not the first scanline, overwriting the rows it had decoded -- so a file that mixes
       * run-length encoded and flat scanlines would load with wrong pixels: refuse it */
      double need = 4.0 * ((double)w * (double)h);
      if (y > 0)
        EL_IO__HDR_FAIL("unsupported Radiance HDR: scanline %d of %d is flat while the ones before it are run-length encoded", y + 1, h);
      if ((double)(size - pos) < need)
        EL_IO__HDR_FAIL("file is truncated (%ld bytes of flat pixel data from scanline %d of %d, %.0f expected)",
                        size - pos, y + 1, h, need);
      break;
    }
    {
      int sw = (int)b[pos + 2] << 8 | (int)b[pos + 3];
      if (sw != w) EL_IO__HDR_FAIL("corrupt Radiance HDR (scanline %d of %d says width %d, the header %d)", y + 1, h, sw, w);
    }
    pos += 4;
    {
      int c;
      for (c = 0; c < 4; ++c) {
        int x = 0;
        while (x < w) {
          int count;
          if (pos >= size) EL_IO__HDR_FAIL("file is truncated (scanline %d of %d is incomplete)", y + 1, h);
          count = b[pos++];
          if (count > 128) { count -= 128; pos += 1; }
          else pos += count;
          if (count == 0 || x + count > w)
            EL_IO__HDR_FAIL("corrupt Radiance HDR (bad run length in scanline %d of %d)", y + 1, h);
          if (pos > size) EL_IO__HDR_FAIL("file is truncated (scanline %d of %d is incomplete)", y + 1, h);
          x += count;
        }
      }
    }
  }
#undef EL_IO__HDR_FAIL
  free(b);
  return 0;
}

/* ---- PNG: Debian's stb_image (git 2022-09-08) decodes a corrupt zlib stream without noticing (a
 * distance code 30 or 31, or a length code 286 or 287, indexes past its tables; a distance of 0 copies
 * bytes not yet written), so a corrupt IDAT "loaded" with pixels from uninitialised memory (a different
 * image in every run). So the chunks are walked and the image data inflated with zlib first (output
 * discarded): the stream must be valid and hold every byte the header's size asks for. */
static int el_io__check_png(const char *path, FILE *f, long size, char *err, size_t errlen) {
  static const unsigned char sig[8] = {0x89, 'P', 'N', 'G', 0x0d, 0x0a, 0x1a, 0x0a};
  unsigned char *b, out[16384];
  long pos = 8;
  int seen_ihdr = 0, zr = Z_OK, done = 0;
  double expect = 0;
  z_stream z;
  if (size < 0) return el_io__fail(err, errlen, path, "cannot determine the file size");
  if (size > (1L << 30)) return el_io__fail(err, errlen, path, "PNG file larger than 1 GiB");
  b = (unsigned char *)malloc((size_t)size + 1);
  if (!b) return el_io__fail(err, errlen, path, "out of memory");
  if (fread(b, 1, (size_t)size, f) != (size_t)size) { free(b); return el_io__fail(err, errlen, path, "cannot read file (short read)"); }
  if (size < 8 || memcmp(b, sig, 8)) { free(b); return el_io__fail(err, errlen, path, "not a PNG file (bad signature)"); }
  memset(&z, 0, sizeof z);
  if (inflateInit(&z) != Z_OK) { free(b); return el_io__fail(err, errlen, path, "cannot initialise zlib"); }
#define EL_IO__PNG_FAIL(...) do { el_io__fail(err, errlen, path, __VA_ARGS__); inflateEnd(&z); free(b); return -1; } while (0)
  for (;;) {
    unsigned long len;
    const unsigned char *t;
    if (size - pos < 12) EL_IO__PNG_FAIL("file is truncated (a chunk header is missing%s)", seen_ihdr ? " before IEND" : "");
    len = (unsigned long)b[pos] << 24 | (unsigned long)b[pos + 1] << 16 | (unsigned long)b[pos + 2] << 8 | b[pos + 3];
    t = b + pos + 4;
    if (len > 0x7fffffffUL || (double)len > (double)(size - pos - 12))
      EL_IO__PNG_FAIL("file is truncated or corrupt (chunk '%c%c%c%c' of %lu bytes at byte %ld)", isprint(t[0]) ? t[0] : '?',
                      isprint(t[1]) ? t[1] : '?', isprint(t[2]) ? t[2] : '?', isprint(t[3]) ? t[3] : '?', len, pos);
    if (!seen_ihdr) {
      static const int chans[7] = {1, 0, 3, 1, 2, 0, 4};
      const unsigned char *d = t + 4;
      double w, h;
      int depth, ct, il, ch, pass;
      if (memcmp(t, "IHDR", 4) || len != 13) EL_IO__PNG_FAIL("corrupt PNG (the first chunk is not a 13-byte IHDR)");
      w = (double)((unsigned long)d[0] << 24 | (unsigned long)d[1] << 16 | (unsigned long)d[2] << 8 | d[3]);
      h = (double)((unsigned long)d[4] << 24 | (unsigned long)d[5] << 16 | (unsigned long)d[6] << 8 | d[7]);
      depth = d[8]; ct = d[9]; il = d[12];
      ch = ct <= 6 ? chans[ct] : 0;
      if (w < 1 || h < 1 || ch == 0 || !(depth == 1 || depth == 2 || depth == 4 || depth == 8 || depth == 16) || il > 1)
        EL_IO__PNG_FAIL("corrupt PNG header (%.0f x %.0f, bit depth %d, colour type %d, interlace %d)", w, h, depth, ct, il);
      if (w * h > EL_IO__MAX_PIXELS) EL_IO__PNG_FAIL("PNG image too large (%.0f x %.0f, more than %.0f pixels)", w, h, EL_IO__MAX_PIXELS);
      if (!il) expect = h * (1 + floor((w * ch * depth + 7) / 8));
      else
        for (pass = 0; pass < 7; pass++) { /* Adam7: the passes' origins and steps */
          static const int x0[7] = {0, 4, 0, 2, 0, 1, 0}, y0[7] = {0, 0, 4, 0, 2, 0, 1}, dx[7] = {8, 8, 4, 4, 2, 2, 1}, dy[7] = {8, 8, 8, 4, 4, 2, 2};
          double pw = floor((w - x0[pass] + dx[pass] - 1) / dx[pass]), ph = floor((h - y0[pass] + dy[pass] - 1) / dy[pass]);
          if (pw > 0 && ph > 0) expect += ph * (1 + floor((pw * ch * depth + 7) / 8));
        }
      seen_ihdr = 1;
    } else if (!memcmp(t, "IDAT", 4) && !done) {
      z.next_in = (Bytef *)(b + pos + 8);
      z.avail_in = (uInt)len;
      while (z.avail_in > 0 && !done) {
        z.next_out = out; z.avail_out = sizeof out;
        zr = inflate(&z, Z_NO_FLUSH);
        if (zr == Z_STREAM_END) done = 1;
        else if (zr != Z_OK && zr != Z_BUF_ERROR)
          EL_IO__PNG_FAIL("corrupt PNG image data (zlib: %s)", z.msg ? z.msg : "invalid stream");
        else if (zr == Z_BUF_ERROR && z.avail_out != 0) break; /* needs the next IDAT */
      }
      while (!done && z.avail_in == 0) { /* flush what zlib holds back */
        z.next_out = out; z.avail_out = sizeof out;
        zr = inflate(&z, Z_NO_FLUSH);
        if (zr == Z_STREAM_END) done = 1;
        else if (zr != Z_OK && zr != Z_BUF_ERROR) EL_IO__PNG_FAIL("corrupt PNG image data (zlib: %s)", z.msg ? z.msg : "invalid stream");
        if (z.avail_out != 0) break;
      }
    } else if (!memcmp(t, "IEND", 4)) break;
    pos += 12 + (long)len;
  }
  if (!done) EL_IO__PNG_FAIL("file is truncated or corrupt (the image data stream does not end)");
  if ((double)z.total_out < expect)
    EL_IO__PNG_FAIL("corrupt PNG (the image data holds %lu bytes, %.0f expected)", (unsigned long)z.total_out, expect);
#undef EL_IO__PNG_FAIL
  inflateEnd(&z);
  free(b);
  return 0;
}

/* ---- OpenEXR, through the reference library (Debian's libopenexr-dev, OpenEXR 3.1). Its C core
 * (OpenEXRCore, openexr.h) reads the header and the chunk offset table here, so that everything below
 * is checked before anything of the image's size is allocated: the data window (at most
 * EL_IO__MAX_PIXELS), the bytes one chunk unpacks to (EL_IO__EXR_MAX_CHUNK_BYTES: a header may
 * announce thousands of channels), and that every chunk of the image lies inside the file. The pixels
 * are then decoded by its C++ library (exr_codec.cc), which has every compression: OpenEXRCore 3.1 has
 * no DWAA/DWAB decoder.
 *
 * What is read: part 0 (of a multi-part file too), level 0 (of a tiled MIP/RIP map too). Channels R, G
 * and B of the default layer, else of the first layer (in the file's alphabetical order) that has all
 * three ("diffuse.R", "diffuse.G", "diffuse.B"), else Y the same way (grey); other channels (A, Z, ...)
 * are skipped, any pixel type (half, float, uint) becomes float. Deep images, luminance/chroma images
 * (Y with RY, BY) and subsampled channels are refused as unsupported. */
#define EL_IO__EXR_MAX_CHUNK_BYTES ((double)(1 << 28))

/* OpenEXRCore reports each problem to a callback (its default prints to stderr): keep the first one. */
typedef struct el_io__exr_log { char msg[200]; } el_io__exr_log;
static void el_io__exr_log_error(exr_const_context_t f, exr_result_t code, const char *msg) {
  void *u = NULL;
  el_io__exr_log *log;
  if (exr_get_user_data(f, &u) != EXR_ERR_SUCCESS || !u) return;
  log = (el_io__exr_log *)u;
  if (!log->msg[0]) snprintf(log->msg, sizeof log->msg, "%s", msg ? msg : exr_get_default_error_message(code));
}
/* OpenEXRCore's message for result r (the first one it reported, else the code's generic text) */
static const char *el_io__exr_why(const el_io__exr_log *log, exr_result_t r) {
  return log->msg[0] ? log->msg : exr_get_default_error_message(r);
}

/* The channel of `layer` (a prefix such as "" or "diffuse.") called `base`, or -1. */
static int el_io__exr_find(const exr_attr_chlist_t *cl, const char *layer, size_t layer_len, const char *base) {
  int i;
  for (i = 0; i < cl->num_channels; i++) {
    const char *n = cl->entries[i].name.str;
    if (n && strlen(n) == layer_len + strlen(base) && !strncmp(n, layer, layer_len) && !strcmp(n + layer_len, base)) return i;
  }
  return -1;
}
/* The channels to read (see above) into idx[0..2]; returns 3 (RGB), 1 (grey: idx[0] only) or 0. */
static int el_io__exr_pick(const exr_attr_chlist_t *cl, int idx[3]) {
  static const char *const rgb[3] = {"R", "G", "B"};
  int want, i, c;
  for (want = 3; want >= 1; want -= 2) {
    const char *const *bases = want == 3 ? rgb : NULL;
    /* the default layer first (layer_len 0), then each layer in the channel list's order */
    for (i = -1; i < cl->num_channels; i++) {
      const char *n = i < 0 ? "" : cl->entries[i].name.str, *dot = i < 0 ? NULL : strrchr(n, '.');
      size_t layer_len = dot ? (size_t)(dot - n) + 1 : 0;
      if (i >= 0 && (!dot || strcmp(dot + 1, want == 3 ? "R" : "Y"))) continue; /* not a layered R (or Y) */
      for (c = 0; c < want; c++)
        if ((idx[c] = el_io__exr_find(cl, n, layer_len, bases ? bases[c] : "Y")) < 0) break;
      if (c == want) return want;
    }
  }
  return 0;
}

static int el_io__load_exr(const char *path, long size, el_image *img, char *err, size_t errlen) {
  exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
  exr_context_t f = NULL;
  el_io__exr_log log;
  exr_result_t r;
  exr_storage_t storage;
  exr_attr_box2i_t dw;
  const exr_attr_chlist_t *cl;
  int parts, idx[3] = {-1, -1, -1}, n, c, k, tiled;
  int32_t lines = 1, nx = 1, ny = 1;
  uint32_t tile_w = 0, tile_h = 0;
  double w, h, bytes_per_pixel = 0;
  char layout[160], msg[300], note[200];
  const char *names[3] = {NULL, NULL, NULL};
  size_t i, npix;
  log.msg[0] = 0;
  init.error_handler_fn = el_io__exr_log_error;
  init.user_data = &log;
  init.max_image_width = init.max_image_height = 1 << 28; /* no side can be longer under EL_IO__MAX_PIXELS */
  init.max_tile_width = init.max_tile_height = 1 << 16;
  init.flags = EXR_CONTEXT_FLAG_DISABLE_CHUNK_RECONSTRUCTION; /* a bad chunk table is an error, not a search */
#define EL_IO__EXR_FAIL(...) do { el_io__fail(err, errlen, path, __VA_ARGS__); exr_finish(&f); return -1; } while (0)
  r = exr_start_read(&f, path, &init);
  if (r == EXR_ERR_FEATURE_NOT_IMPLEMENTED) EL_IO__EXR_FAIL("unsupported EXR (%s)", el_io__exr_why(&log, r));
  if (r != EXR_ERR_SUCCESS) EL_IO__EXR_FAIL("corrupt or truncated EXR header (%s)", el_io__exr_why(&log, r));
  /* OpenEXRCore reads on past some bad values (a compression code it does not know becomes ZIP): its
   * message explains a failure of the decoder better than the decoder's own */
  snprintf(note, sizeof note, "%s", log.msg);
  if (exr_get_count(f, &parts) != EXR_ERR_SUCCESS || parts < 1 || exr_get_storage(f, 0, &storage) != EXR_ERR_SUCCESS ||
      exr_get_data_window(f, 0, &dw) != EXR_ERR_SUCCESS || exr_get_channels(f, 0, &cl) != EXR_ERR_SUCCESS || !cl)
    EL_IO__EXR_FAIL("corrupt EXR header (%s)", el_io__exr_why(&log, EXR_ERR_FILE_BAD_HEADER));
  if (storage != EXR_STORAGE_SCANLINE && storage != EXR_STORAGE_TILED)
    EL_IO__EXR_FAIL("unsupported EXR: part 0 of %d is a deep image (several samples per pixel)", parts);
  tiled = storage == EXR_STORAGE_TILED;
  w = (double)dw.max.x - dw.min.x + 1;
  h = (double)dw.max.y - dw.min.y + 1;
  if (w < 1 || h < 1 || w * h > EL_IO__MAX_PIXELS)
    EL_IO__EXR_FAIL("EXR data window of %.0f x %.0f pixels is empty or too large (at most %.0f pixels)", w, h, EL_IO__MAX_PIXELS);
  /* the channels */
  layout[0] = 0;
  for (c = 0; c < cl->num_channels; c++) {
    size_t len = strlen(layout);
    if (len + 40 < sizeof layout) snprintf(layout + len, sizeof layout - len, "%s%.32s", c ? ", " : "", cl->entries[c].name.str);
    else if (len + 5 < sizeof layout && !strstr(layout, "...")) snprintf(layout + len, sizeof layout - len, ", ...");
    bytes_per_pixel += cl->entries[c].pixel_type == EXR_PIXEL_HALF ? 2 : 4;
  }
  n = el_io__exr_pick(cl, idx);
  if (n == 0) EL_IO__EXR_FAIL("unsupported EXR channel layout (channels: %s): need R, G and B, or Y", cl->num_channels ? layout : "none");
  if (n == 1) {
    const char *y = cl->entries[idx[0]].name.str;
    size_t layer_len = strlen(y) - 1;
    if (el_io__exr_find(cl, y, layer_len, "RY") >= 0 || el_io__exr_find(cl, y, layer_len, "BY") >= 0)
      EL_IO__EXR_FAIL("unsupported EXR: luminance/chroma channels (%s); save it as RGB", layout);
  }
  for (c = 0; c < n; c++) {
    const exr_attr_chlist_entry_t *e = &cl->entries[idx[c]];
    if (e->x_sampling != 1 || e->y_sampling != 1)
      EL_IO__EXR_FAIL("unsupported EXR: channel %s is subsampled (%d x %d)", e->name.str, e->x_sampling, e->y_sampling);
    names[c] = e->name.str;
  }
  /* the chunks: how much one unpacks to, and that each lies inside the file (OpenEXRCore reads the
   * offset table on the first request, after checking that the file can hold it) */
  if (tiled) {
    exr_tile_level_mode_t levels;
    exr_tile_round_mode_t round;
    int32_t lw, lh;
    if (exr_get_tile_descriptor(f, 0, &tile_w, &tile_h, &levels, &round) != EXR_ERR_SUCCESS ||
        exr_get_level_sizes(f, 0, 0, 0, &lw, &lh) != EXR_ERR_SUCCESS || tile_w < 1 || tile_h < 1)
      EL_IO__EXR_FAIL("corrupt EXR tile description (%s)", el_io__exr_why(&log, EXR_ERR_INVALID_ATTR));
    nx = (int32_t)(((int64_t)lw + tile_w - 1) / tile_w);
    ny = (int32_t)(((int64_t)lh + tile_h - 1) / tile_h);
    if (bytes_per_pixel * tile_w * tile_h > EL_IO__EXR_MAX_CHUNK_BYTES)
      EL_IO__EXR_FAIL("EXR tiles of %u x %u pixels and %d channels are too large (more than %.0f bytes each)", tile_w, tile_h,
                      cl->num_channels, EL_IO__EXR_MAX_CHUNK_BYTES);
  } else {
    if (exr_get_scanlines_per_chunk(f, 0, &lines) != EXR_ERR_SUCCESS || lines < 1)
      EL_IO__EXR_FAIL("corrupt EXR header (%s)", el_io__exr_why(&log, EXR_ERR_INVALID_ATTR));
    ny = (int32_t)((h + lines - 1) / lines);
    if (bytes_per_pixel * w * lines > EL_IO__EXR_MAX_CHUNK_BYTES)
      EL_IO__EXR_FAIL("EXR chunks of %.0f x %d pixels and %d channels are too large (more than %.0f bytes each)", w, (int)lines,
                      cl->num_channels, EL_IO__EXR_MAX_CHUNK_BYTES);
  }
  for (k = 0; k < nx * ny; k++) {
    exr_chunk_info_t ci;
    memset(&ci, 0, sizeof ci);
    log.msg[0] = 0;
    r = tiled ? exr_read_tile_chunk_info(f, 0, k % nx, k / nx, 0, 0, &ci)
              : exr_read_scanline_chunk_info(f, 0, dw.min.y + k * lines, &ci);
    if (r != EXR_ERR_SUCCESS)
      EL_IO__EXR_FAIL("file is truncated or corrupt (pixel chunk %d of %d: %s)", k + 1, nx * ny, el_io__exr_why(&log, r));
    if ((double)ci.data_offset + (double)ci.packed_size > (double)size)
      EL_IO__EXR_FAIL("file is truncated (pixel chunk %d of %d ends at byte %.0f, the file has %ld bytes)", k + 1, nx * ny,
                      (double)ci.data_offset + (double)ci.packed_size, size);
  }
#undef EL_IO__EXR_FAIL
  /* decode: the channel names belong to f, which the decoder does not use (it opens the file again) */
  npix = (size_t)w * (size_t)h;
  img->pixels = (float *)malloc(npix * 3 * sizeof(float));
  if (!img->pixels) { exr_finish(&f); return el_io__fail(err, errlen, path, "out of memory"); }
  msg[0] = 0;
  if (el_exr_decode(path, names, dw.min.x, dw.min.y, (int)w, (int)h, img->pixels, msg, sizeof msg) != 0) {
    exr_finish(&f);
    el_image_free(img);
    if (note[0]) return el_io__fail(err, errlen, path, "corrupt or unsupported EXR header (%s)", note);
    return el_io__fail(err, errlen, path, "cannot decode EXR pixels (OpenEXR: %s)", msg);
  }
  exr_finish(&f);
  if (n == 1)
    for (i = 0; i < npix; i++) img->pixels[3 * i + 1] = img->pixels[3 * i + 2] = img->pixels[3 * i];
  img->width = (int)w; img->height = (int)h; img->channels = 3; img->is_8bit = 0;
  return 0;
}

/* The first bytes of a file (fewer when it is shorter); returns how many were read. */
static size_t el_io__magic(FILE *f, unsigned char *m, size_t n) {
  size_t k;
  if (fseek(f, 0, SEEK_SET) != 0) return 0;
  k = fread(m, 1, n, f);
  fseek(f, 0, SEEK_SET);
  return k;
}

static int el_io__load_any(const char *path, el_image *img, char *err, size_t errlen);
/* Loads, then counts the values the reader keeps although a renderer cannot use them (its policy: it
 * changes no value; the caller decides). */
int el_image_load(const char *path, el_image *img, char *err, size_t errlen) {
  size_t i, n;
  int r = el_io__load_any(path, img, err, errlen);
  if (r != 0) return r;
  n = (size_t)img->width * (size_t)img->height * (size_t)img->channels;
  for (i = 0; i < n; i++) {
    float v = img->pixels[i];
    if (v != v || v > FLT_MAX || v < -FLT_MAX) img->nonfinite_values++;
    else if (v < 0.0f) {
      img->negative_values++;
      if (v < img->most_negative) img->most_negative = v;
    }
  }
  return 0;
}

static int el_io__load_any(const char *path, el_image *img, char *err, size_t errlen) {
  const char *ext;
  FILE *f;
  if (!img) return el_io__fail(err, errlen, path, "no output image given");
  memset(img, 0, sizeof *img);
  if (!path || !*path) return el_io__fail(err, errlen, "(empty path)", "no file name given");
  {
    char why[128];
    if (el_file_is_regular(path, why, sizeof why) != 0) return el_io__fail(err, errlen, path, "cannot open file (%s)", why);
  }
  f = fopen(path, "rb");
  if (!f) return el_io__fail(err, errlen, path, "cannot open file (%s)", strerror(errno));
  ext = el_image_extension(path);
  {
    unsigned char m[8];
    long size = el_io__file_size(f);
    errno = 0;
    if (el_io__magic(f, m, 1) != 1 && ferror(f)) { /* e.g. a directory: fopen succeeds, reading fails */
      int e = errno;
      fclose(f);
      return el_io__fail(err, errlen, path, "cannot read file (%s)", e ? strerror(e) : "read error");
    }
    if (size == 0) { fclose(f); return el_io__fail(err, errlen, path, "file is empty"); }
    if (!strcmp(ext, "exr")) {
      static const unsigned char exr_magic[4] = {0x76, 0x2f, 0x31, 0x01};
      if (el_io__magic(f, m, 4) != 4 || memcmp(m, exr_magic, 4)) {
        fclose(f);
        return el_io__fail(err, errlen, path, "not an OpenEXR file (bad magic number)");
      }
    }
    if (!strcmp(ext, "hdr")) {
      int r = el_io__check_hdr(path, f, size, err, errlen);
      if (r) { fclose(f); return r; }
    }
    if (!strcmp(ext, "png")) {
      int r = el_io__check_png(path, f, size, err, errlen);
      if (r) { fclose(f); return r; }
    }
  }
  if (!strcmp(ext, "pfm")) {
    int r = el_io__load_pfm(path, f, img, err, errlen);
    fclose(f);
    return r;
  }
  if (!strcmp(ext, "exr")) {
    long size = el_io__file_size(f);
    fclose(f);
    return el_io__load_exr(path, size, img, err, errlen);
  }
  fclose(f);
  if (!strcmp(ext, "hdr")) {
    int w, h, n;
    float *p = stbi_loadf(path, &w, &h, &n, 3);
    if (!p) {
      const char *why = stbi_failure_reason();
      return el_io__fail(err, errlen, path, "cannot read Radiance HDR (%s)", why && why[0] ? why : "corrupt file");
    }
    img->pixels = p; img->width = w; img->height = h; img->channels = 3; img->is_8bit = 0;
    return 0;
  }
  if (!strcmp(ext, "png") || !strcmp(ext, "jpg") || !strcmp(ext, "jpeg") || !strcmp(ext, "tga") ||
      !strcmp(ext, "bmp")) {
    int w, h, n;
    size_t i, count;
    unsigned char *p;
    if (stbi_info(path, &w, &h, &n) && (double)w * (double)h > EL_IO__MAX_PIXELS)
      return el_io__fail(err, errlen, path, "image too large (%d x %d, more than %.0f pixels)", w, h, EL_IO__MAX_PIXELS);
    p = stbi_load(path, &w, &h, &n, 0);
    if (!p) {
      const char *why = stbi_failure_reason();
      return el_io__fail(err, errlen, path, "cannot read image (%s)", why && why[0] ? why : "corrupt or unsupported file");
    }
    count = (size_t)w * (size_t)h * (size_t)n;
    img->pixels = (float *)malloc(count * sizeof(float));
    if (!img->pixels) { stbi_image_free(p); return el_io__fail(err, errlen, path, "out of memory"); }
    for (i = 0; i < count; i++) img->pixels[i] = p[i] / 255.0f;
    stbi_image_free(p);
    img->width = w; img->height = h; img->channels = n; img->is_8bit = 1;
    return 0;
  }
  if (!*ext) return el_io__fail(err, errlen, path, "unsupported image format: the name has no extension (supported: .hdr .exr .pfm .png .jpg .tga .bmp)");
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
  char msg[300];
  if (el_io__check_args(path, pixels, width, height, channels, err, errlen)) return -1;
  if (channels == 2) return el_io__fail(err, errlen, path, "EXR writer takes 1, 3 or 4 channels, not 2");
  msg[0] = 0;
  if (el_exr_encode(path, pixels, width, height, channels, msg, sizeof msg) != 0)
    return el_io__fail(err, errlen, path, "cannot write EXR (OpenEXR: %s)", msg);
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

int el_file_is_regular(const char *path, char *why, size_t whylen) {
  struct stat st;
  const char *w = NULL;
  if (!path || !*path) w = "no file name given";
  else if (stat(path, &st) != 0) w = strerror(errno);
  else if (S_ISDIR(st.st_mode)) w = strerror(EISDIR); /* "Is a directory", as reading one would say */
  else if (!S_ISREG(st.st_mode)) w = "is not a regular file (a FIFO, device or socket)";
  if (!w) return 0;
  if (why && whylen) snprintf(why, whylen, "%s", w);
  return -1;
}
