/* imageio.c: writing the rendered image (pbrt-v3 core/imageio.cpp, WriteImage).
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
