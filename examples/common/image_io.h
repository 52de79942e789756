/* image_io.h: reading and writing image files for envlight's examples, tests and benchmarks.
 *
 * Not part of the library (envlight's headers never touch files). Built on Debian's stb
 * (stb_image / stb_image_write, linked as libstb.so) and the reference OpenEXR library (libopenexr-dev:
 * OpenEXRCore checks the header, the C++ library codes the pixels); PFM is ours.
 *
 *   el_image img;
 *   char err[256];
 *   if (el_image_load("city.hdr", &img, err, sizeof err) != 0) { fprintf(stderr, "%s\n", err); ... }
 *   ... img.pixels[(y * img.width + x) * img.channels + c], row 0 at the top ...
 *   el_image_free(&img);
 *
 * Every function returns 0 on success; on failure it returns -1 and writes a message that names the
 * file and the problem ("city.hdr: file is truncated") into err. Rows are stored top to bottom.
 */
#ifndef EL_IMAGE_IO_H
#define EL_IMAGE_IO_H
#include <stddef.h>
#ifdef __cplusplus
extern "C" {
#endif

typedef struct el_image {
  int width, height, channels; /* channels: 1..4 */
  float *pixels;               /* row-major, top row first, width*height*channels floats */
  int is_8bit;                 /* 1 when the file held 8-bit values (PNG/JPEG/...): pixels are the raw
                                  code values / 255, not linearised; HDR formats give 0 (linear) */
  /* The reader's policy for values a renderer cannot use: it changes none. Every value is the file's
   * (lossy EXR compression, DWAA/DWAB, rings to small negatives: Blender's HDRIs hold 3 to 784 texels
   * below 0, down to -0.0033; float files can hold NaN and infinities), and el_image_load counts them
   * here so that the caller applies its own policy (envlight: el_envlight_options.bad_texels; the
   * renderer: LightSource "infinite"'s "string badtexels"). */
  size_t negative_values;      /* finite values < 0 (every channel kept counts) */
  size_t nonfinite_values;     /* NaN or infinite values */
  float most_negative;         /* the most negative finite value, 0 when there is none */
} el_image;

/* .hdr (Radiance RGBE), .exr (OpenEXR), .pfm, and 8-bit formats stb_image reads (.png .jpg .tga .bmp).
 * Values are returned exactly as decoded (negative, NaN and infinite ones too; img's counts say how many).
 * HDR formats give 3 channels, 8-bit formats their own channel count. EXR: every compression, scanline
 * or tiled (level 0), half/float/uint; part 0 of a multi-part file; R, G, B of the default layer, else
 * of the first layer with all three ("diffuse.R"...), else Y as grey; alpha and other channels are
 * dropped. Deep, luminance/chroma and subsampled EXR files fail as "unsupported". */
int el_image_load(const char *path, el_image *img, char *err, size_t errlen);
void el_image_free(el_image *img);

/* Writers. The format follows the extension: .png takes 8-bit data (el_image_write_png), the others
 * take linear floats with 1, 3 or 4 channels. el_image_write_float dispatches on .exr .hdr .pfm.
 * EXR is written as float32 scanlines with ZIP compression (lossless): 1 channel as Y, 3 as R, G, B,
 * 4 as R, G, B, A. */
int el_image_write_png(const char *path, const unsigned char *rgb8, int width, int height, int channels,
                       char *err, size_t errlen);
int el_image_write_float(const char *path, const float *pixels, int width, int height, int channels,
                         char *err, size_t errlen);
int el_image_write_exr(const char *path, const float *pixels, int width, int height, int channels,
                       char *err, size_t errlen);
int el_image_write_hdr(const char *path, const float *pixels, int width, int height, int channels,
                       char *err, size_t errlen);
int el_image_write_pfm(const char *path, const float *pixels, int width, int height, int channels,
                       char *err, size_t errlen);

/* The lower-case extension of path without the dot ("" when there is none), in a static buffer. */
const char *el_image_extension(const char *path);

/* 0 when path names a regular file (or a symbolic link to one); else -1 and why in `why` (strerror's
 * "No such file or directory" or "Is a directory", or "is not a regular file (a FIFO, device or socket)"). Checked
 * before opening an input: opening a FIFO for reading would wait for a writer forever. */
int el_file_is_regular(const char *path, char *why, size_t whylen);

#ifdef __cplusplus
}
#endif
#endif
