/* film.c: the scene's Film "image" and PixelFilter as film.h's el_film.
 *
 * pbrt-v3: core/film.cpp (the Film constructor: croppedPixelBounds from the crop window) and the
 * pixel filters of its filters/ directory (box, triangle, gaussian, mitchell, sinc) as api.cpp's
 * MakeFilter creates them. The render loop adds samples to el_film_tile's and merges them
 * into the el_film made here; imageio.c writes the image. */
#include "elr_internal.h"
#include <string.h>

/* <<Compute film image bounds>> (pbrt-v3: ceil of the crop window times the resolution) */
void elr_film_bounds(const elr_scene_desc *d, int b[4]) {
  b[0] = (int)ceil(d->xres * (double)d->crop[0]); b[2] = (int)ceil(d->xres * (double)d->crop[1]);
  b[1] = (int)ceil(d->yres * (double)d->crop[2]); b[3] = (int)ceil(d->yres * (double)d->crop[3]);
}

/* The film of the full resolution d->xres x d->yres over the pixels [b[0], b[2]) x [b[1], b[3]). */
int elr_film_init(el_film *f, const elr_scene_desc *d, const int b[4], char *err, size_t errlen) {
  el_film_options o;
  const elr_filter_desc *fd = &d->filter;
  int xres = d->xres, yres = d->yres, x0 = b[0], y0 = b[1], x1 = b[2], y1 = b[3];
  el_result r;
  memset(&o, 0, sizeof o);
  o.width = xres; o.height = yres;
  /* film.h takes pbrt's fractions and applies ceil(res * fraction): half a pixel below each integer
   * bound gives that bound back whatever the float rounding */
  o.crop[0] = x0 > 0 ? ((float)x0 - 0.5f) / (float)xres : 0.f; o.crop[1] = ((float)x1 - 0.5f) / (float)xres;
  o.crop[2] = y0 > 0 ? ((float)y0 - 0.5f) / (float)yres : 0.f; o.crop[3] = ((float)y1 - 0.5f) / (float)yres;
  if (x0 == 0 && y0 == 0 && x1 == xres && y1 == yres) memset(o.crop, 0, sizeof o.crop);
  /* pbrt-v3's filters (MakeFilter): box, triangle, gaussian, mitchell, sinc (windowed: film.h's Lanczos) */
  switch (fd->type) {
  case ELR_PF_TRIANGLE: o.filter.type = EL_FILM_FILTER_TRIANGLE; break;
  case ELR_PF_GAUSSIAN: o.filter.type = EL_FILM_FILTER_GAUSSIAN; o.filter.gaussian_alpha = fd->alpha; break;
  case ELR_PF_MITCHELL:
    o.filter.type = EL_FILM_FILTER_MITCHELL;
    o.filter.mitchell_b = fd->b; o.filter.mitchell_c = fd->c;
    if (fd->b == 0.f && fd->c == 0.f) o.filter.mitchell_b = o.filter.mitchell_c = 1e-30f; /* all zero means 1/3, 1/3 to film.h */
    break;
  case ELR_PF_SINC: o.filter.type = EL_FILM_FILTER_LANCZOS; o.filter.lanczos_tau = fd->tau; break;
  default: o.filter.type = EL_FILM_FILTER_BOX; break;
  }
  o.filter.radius[0] = fd->xw; o.filter.radius[1] = fd->yw;
  o.nonnegative_filter = fd->nonneg; /* "bool nonnegative": the negative lobes count as 0 */
  r = el_film_init(f, &o);
  if (r != EL_SUCCESS) { snprintf(err, errlen, "film: %s", el_result_string(r)); return -1; }
  if (f->x0 != x0 || f->y0 != y0 || f->x1 != x1 || f->y1 != y1) {
    /* the crop fractions we passed must give back our pixel bounds exactly */
    el_film_free(f);
    snprintf(err, errlen, "film: crop window bounds mismatch"); return -1;
  }
  return 0;
}
