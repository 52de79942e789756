/* imageio.c: writing the rendered image (pbrt-v3 core/imageio.cpp, WriteImage), and reading the
 * scene's images (ReadImage: the image textures, the environment maps).
 *
 * The format follows the file's extension: .png as 8-bit sRGB (film.h's el_film_srgb_to_byte: pbrt's
 * GammaCorrect and TO_BYTE), .exr, .pfm and .hdr as linear floats (examples/common/image_io.h). */
#include "elr_internal.h"
#include "image_io.h"
#include <stdlib.h>
#include <string.h>

void elr_image_free(elr_image *img) { if (img) { free(img->rgb); img->rgb = NULL; } }

int elr_image_write(const elr_image *img, const char *path, char *err, size_t errlen) {
  const char *ext = el_image_extension(path);
  if (!strcmp(ext, "png")) {
    size_t i, n = (size_t)img->width * (size_t)img->height;
    unsigned char *b = (unsigned char *)malloc(n * 3);
    int r;
    if (!b) { snprintf(err, errlen, "out of memory"); return -1; }
    for (i = 0; i < 3 * n; i++) b[i] = el_film_srgb_to_byte(img->rgb[i]);
    r = el_image_write_png(path, b, img->width, img->height, 3, err, errlen);
    free(b);
    return r;
  }
  if (!strcmp(ext, "exr") || !strcmp(ext, "pfm") || !strcmp(ext, "hdr"))
    return el_image_write_float(path, img->rgb, img->width, img->height, 3, err, errlen);
  snprintf(err, errlen, "%s: unknown output format \".%s\" (use .png, .exr, .pfm or .hdr)", path, ext);
  return -1;
}

/* >> reading (pbrt-v3's ReadImage): the scene's image textures and environment maps */
int elr_image_read(const char *path, el_image *img, char *why, size_t n) {
  char e[512];
  if (el_image_load(path, img, e, sizeof e) != 0) { snprintf(why, n, "cannot read image: %s", e); return -1; }
  if (img->width <= 0 || img->height <= 0 || img->width > 65536 || img->height > 65536) {
    int w = img->width, h = img->height;
    el_image_free(img);
    snprintf(why, n, "image \"%s\" has an absurd size (%d x %d; 1 to 65536 per side)", path, w, h);
    return -1;
  }
  return 0;
}

/* channels -> linear RGB (3 floats per texel); 8-bit input with gamma: sRGB to linear. A NaN or
 * infinite texel, or one that overflows when scaled, stops it: its callers name the file and the texel
 * (it used to become 0 silently). */
float *elr_image_rgb(const el_image *img, int gamma, float scale, int64_t *bad, float *bad_value) {
  size_t n = (size_t)img->width * (size_t)img->height, i;
  float *rgb = (float *)malloc(n * 3 * sizeof(float));
  *bad = -1;
  if (!rgb) return NULL;
  for (i = 0; i < n; i++) {
    int c;
    for (c = 0; c < 3; c++) {
      int src = img->channels >= 3 ? c : 0;
      float v = img->pixels[i * (size_t)img->channels + (size_t)src];
      if (img->is_8bit && gamma)
        v = v <= 0.04045f ? v / 12.92f : powf((v + 0.055f) / 1.055f, 2.4f);
      if (!isfinite(v) || !isfinite(v * scale)) {
        free(rgb);
        *bad = (int64_t)i;
        *bad_value = v;
        return NULL;
      }
      rgb[i * 3 + (size_t)c] = v * scale;
    }
  }
  return rgb;
}
