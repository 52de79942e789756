/* image_io.c: see image_io.h. stb and tinyexr come compiled from Debian (libstb.so, libtinyexr.so);
 * this file includes only their declarations. */
#define _POSIX_C_SOURCE 200809L /* stat */
#include "image_io.h"

#include <sys/stat.h>

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
        if (*c == '\n' || *c == '\t') *c = ' '; /* tinyexr ends its messages with a newline */
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

/* ---- OpenEXR: tinyexr reports a truncated file as "Invalid data found when decoding pixels". When it
 * fails on a single-part scanline file, walk the chunk offset table ourselves to say what is missing. */
static int el_io__diagnose_exr(const char *path, char *err, size_t errlen) {
  EXRVersion ver;
  EXRHeader hdr;
  const char *msg = NULL;
  FILE *f;
  long size, k, n, lines, table;
  int found = 0;
  if (ParseEXRVersionFromFile(&ver, path) != TINYEXR_SUCCESS)
    return el_io__fail(err, errlen, path, "corrupt EXR (bad version field)") , 1;
  InitEXRHeader(&hdr);
  if (ParseEXRHeaderFromFile(&hdr, &ver, path, &msg) != TINYEXR_SUCCESS) {
    el_io__fail(err, errlen, path, "corrupt or truncated EXR header (%s)", msg ? msg : "unknown tinyexr error");
    if (msg) FreeEXRErrorMessage(msg);
    FreeEXRHeader(&hdr);
    return 1;
  }
  if (ver.tiled || ver.multipart || ver.non_image) { FreeEXRHeader(&hdr); return 0; }
  switch (hdr.compression_type) {
  case TINYEXR_COMPRESSIONTYPE_ZIP: lines = 16; break;
  case TINYEXR_COMPRESSIONTYPE_PIZ: lines = 32; break;
  case TINYEXR_COMPRESSIONTYPE_NONE: case TINYEXR_COMPRESSIONTYPE_RLE: case TINYEXR_COMPRESSIONTYPE_ZIPS: lines = 1; break;
  default: FreeEXRHeader(&hdr); return 0;
  }
  n = ((long)hdr.data_window.max_y - hdr.data_window.min_y + 1 + lines - 1) / lines;
  table = 8 + (long)hdr.header_len;
  FreeEXRHeader(&hdr);
  f = fopen(path, "rb");
  if (!f || n <= 0) { if (f) fclose(f); return 0; }
  size = el_io__file_size(f);
  if (size < table + 8 * n) {
    fclose(f);
    return el_io__fail(err, errlen, path, "file is truncated (the chunk offset table needs %ld bytes, the file has %ld)", table + 8 * n, size), 1;
  }
  fseek(f, table, SEEK_SET);
  for (k = 0; k < n && !found; ++k) {
    unsigned char o[8], c[8];
    unsigned long long off = 0;
    long here;
    int i;
    if (fread(o, 1, 8, f) != 8) break;
    for (i = 7; i >= 0; --i) off = (off << 8) | o[i];
    if (off + 8 > (unsigned long long)size) {
      el_io__fail(err, errlen, path, "file is truncated (pixel chunk %ld of %ld starts at byte %llu, the file has %ld bytes)", k + 1, n, off, size);
      found = 1;
      break;
    }
    here = ftell(f);
    if (fseek(f, (long)off + 4, SEEK_SET) == 0 && fread(c, 1, 4, f) == 4) {
      unsigned long long len = (unsigned long long)c[0] | (unsigned long long)c[1] << 8 | (unsigned long long)c[2] << 16 | (unsigned long long)c[3] << 24;
      if (off + 8 + len > (unsigned long long)size) {
        el_io__fail(err, errlen, path, "file is truncated (pixel chunk %ld of %ld ends at byte %llu, the file has %ld bytes)", k + 1, n, off + 8 + len, size);
        found = 1;
      }
    }
    fseek(f, here, SEEK_SET);
  }
  fclose(f);
  return found;
}

/* ---- OpenEXR, single-part files (scanline or tiled: level 0): tinyexr 1.0.1's LoadEXR leaks every
 * channel buffer when decoding fails (FreeEXRImage frees images[c] -- or each tile's -- for c <
 * num_channels, and num_channels is set only after a successful decode), so a corrupt chunk leaked
 * (LeakSanitizer). Here the image's num_channels is set before decoding, so that tinyexr's own clean-up
 * frees them; the RGB conversion is LoadEXR's (R, G, B by name, layer prefixes ignored; a single
 * channel is grey; tiles placed by their offsets). Returns 0 or -1. */
static int el_io__load_exr(const char *path, el_image *img, char *err, size_t errlen) {
  EXRVersion ver;
  EXRHeader hdr;
  EXRImage im;
  const char *msg = NULL;
  int c, idx[3] = {-1, -1, -1}, r;
  size_t i, n;
  if (ParseEXRVersionFromFile(&ver, path) != TINYEXR_SUCCESS) return el_io__fail(err, errlen, path, "corrupt EXR (bad version field)");
  if (ver.multipart || ver.non_image)
    return el_io__fail(err, errlen, path, "multi-part and deep EXR files are not supported");
  InitEXRHeader(&hdr);
  if (ParseEXRHeaderFromFile(&hdr, &ver, path, &msg) != TINYEXR_SUCCESS) {
    el_io__fail(err, errlen, path, "corrupt or truncated EXR header (%s)", msg ? msg : "unknown tinyexr error");
    if (msg) FreeEXRErrorMessage(msg);
    FreeEXRHeader(&hdr);
    return -1;
  }
  if (hdr.num_channels < 1) { FreeEXRHeader(&hdr); return el_io__fail(err, errlen, path, "EXR has no channels"); }
  { /* tinyexr allocates every channel of the data window before it decodes a chunk */
    double w = (double)hdr.data_window.max_x - hdr.data_window.min_x + 1, h = (double)hdr.data_window.max_y - hdr.data_window.min_y + 1;
    if (w < 1 || h < 1 || w * h > EL_IO__MAX_PIXELS) {
      FreeEXRHeader(&hdr);
      return el_io__fail(err, errlen, path, "EXR data window of %.0f x %.0f pixels is empty or too large (at most %.0f pixels)", w, h,
                         EL_IO__MAX_PIXELS);
    }
  }
  for (c = 0; c < hdr.num_channels; c++) {
    const char *nm = hdr.channels[c].name, *dot = strrchr(nm, '.');
    if (dot && dot != nm && dot[1]) nm = dot + 1;
    if (!strcmp(nm, "R") && idx[0] < 0) idx[0] = c;
    else if (!strcmp(nm, "G") && idx[1] < 0) idx[1] = c;
    else if (!strcmp(nm, "B") && idx[2] < 0) idx[2] = c;
    if (hdr.pixel_types[c] == TINYEXR_PIXELTYPE_HALF) hdr.requested_pixel_types[c] = TINYEXR_PIXELTYPE_FLOAT;
  }
  if (hdr.num_channels == 1) idx[0] = idx[1] = idx[2] = 0;
  else if (idx[0] < 0 || idx[1] < 0 || idx[2] < 0) {
    FreeEXRHeader(&hdr);
    return el_io__fail(err, errlen, path, "EXR has %d channels but no R, G and B", hdr.num_channels);
  }
  InitEXRImage(&im);
  im.num_channels = hdr.num_channels; /* see above: tinyexr frees this many channel buffers on failure */
  r = LoadEXRImageFromFile(&im, &hdr, path, &msg);
  if (r != TINYEXR_SUCCESS) {
    char *nl;
    el_io__fail(err, errlen, path, "cannot read EXR (%s)", msg ? msg : "unknown tinyexr error");
    while (err && errlen && (nl = strchr(err, '\n')) != NULL) *nl = ' '; /* tinyexr ends messages with \n */
    if (msg) FreeEXRErrorMessage(msg);
    FreeEXRHeader(&hdr); /* the image's buffers were freed by tinyexr */
    return -1;
  }
  if (im.width <= 0 || im.height <= 0 || (hdr.tiled ? !im.tiles || hdr.tile_size_x <= 0 || hdr.tile_size_y <= 0 : !im.images)) {
    FreeEXRImage(&im); FreeEXRHeader(&hdr);
    return el_io__fail(err, errlen, path, "EXR has no pixels");
  }
  n = (size_t)im.width * (size_t)im.height;
  img->pixels = (float *)malloc(n * 3 * sizeof(float));
  if (!img->pixels) { FreeEXRImage(&im); FreeEXRHeader(&hdr); return el_io__fail(err, errlen, path, "out of memory"); }
  if (hdr.tiled) memset(img->pixels, 0, n * 3 * sizeof(float)); /* texels no tile covers are black */
  for (c = 0; c < 3; c++) {
    int uint = hdr.requested_pixel_types[idx[c]] == TINYEXR_PIXELTYPE_UINT;
    if (!hdr.tiled) {
      const unsigned char *src = im.images[idx[c]];
      for (i = 0; i < n; i++) {
        float v;
        if (uint) { unsigned u; memcpy(&u, src + 4 * i, 4); v = (float)u; }
        else memcpy(&v, src + 4 * i, 4);
        img->pixels[3 * i + (size_t)c] = v;
      }
    } else {
      int t, x, y, tw = hdr.tile_size_x, th = hdr.tile_size_y;
      for (t = 0; t < im.num_tiles; t++) {
        const EXRTile *tile = &im.tiles[t];
        const unsigned char *src = tile->images ? tile->images[idx[c]] : NULL;
        if (!src) continue;
        for (y = 0; y < th && y < tile->height; y++)
          for (x = 0; x < tw && x < tile->width; x++) {
            long ii = (long)tile->offset_x * tw + x, jj = (long)tile->offset_y * th + y;
            float v;
            if (ii < 0 || jj < 0 || ii >= im.width || jj >= im.height) continue;
            if (uint) { unsigned u; memcpy(&u, src + 4 * ((size_t)y * (size_t)tw + (size_t)x), 4); v = (float)u; }
            else memcpy(&v, src + 4 * ((size_t)y * (size_t)tw + (size_t)x), 4);
            img->pixels[3 * ((size_t)jj * (size_t)im.width + (size_t)ii) + (size_t)c] = v;
          }
      }
    }
  }
  img->width = im.width; img->height = im.height; img->channels = 3; img->is_8bit = 0;
  FreeEXRImage(&im);
  FreeEXRHeader(&hdr);
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

int el_image_load(const char *path, el_image *img, char *err, size_t errlen) {
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
  fclose(f);
  if (!strcmp(ext, "exr")) {
    /* Check the chunk table first: it names what a truncated file lacks (tinyexr's message would be
     * 'Invalid data found when decoding pixels'). */
    if (el_io__diagnose_exr(path, err, errlen)) {
      char *nl;
      while (err && errlen && (nl = strchr(err, '\n')) != NULL) *nl = ' '; /* tinyexr ends messages with \n */
      return -1;
    }
    return el_io__load_exr(path, img, err, errlen);
  }
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
