/* tests/labs/lab_film_side.c: one build of the film (examples/pbrtv3/film.h, or lab 4's copy: the
 * include path decides), exported as LAB_SIDE_* (lab_film.h). */
#include "film.h"
#include "lab_side.h"
#include "lab_film.h"

float LAB_FN(gamma)(float v) { return pbrt_GammaCorrect(v); }
void LAB_FN(bytes)(const float *v, int n, unsigned char *out) {
  float *rgb = (float *)malloc(sizeof(float) * 3 * (size_t)n);
  int i;
  if (!rgb) exit(2);
  for (i = 0; i < n; ++i) rgb[3 * i] = rgb[3 * i + 1] = rgb[3 * i + 2] = v[i];
  pbrt_WriteImage8(rgb, n, 1, out); /* 3 bytes per value */
  free(rgb);
}
/* A film of xres x yres with the filter, one tile over all of it, the n samples added: each pixel's
 * contribSum (3 floats) and filterWeightSum. */
void LAB_FN(add_samples)(int xres, int yres, int filter, float radius, int n, const float *pFilm, const float *L,
                         const float *weight, float *contrib, float *wsum) {
  pbrt_Filter f = pbrt_MakeFilter(filter, radius, 0);
  pbrt_Film film;
  pbrt_FilmTile tile;
  int bounds[4], i, x, y;
  bounds[0] = bounds[1] = 0;
  bounds[2] = xres;
  bounds[3] = yres;
  if (pbrt_Film_init(&film, xres, yres, &f, 1, 1e30f) != 0 || pbrt_Film_GetFilmTile(&film, bounds, &tile) != 0) exit(2);
  for (i = 0; i < n; ++i) pbrt_FilmTile_AddSample(&tile, pFilm + 2 * i, L + 3 * i, weight[i]);
  for (y = 0; y < yres; ++y)
    for (x = 0; x < xres; ++x) {
      const pbrt_FilmTilePixel *p = pbrt_FilmTile_GetPixel(&tile, x, y);
      memcpy(contrib + 3 * (y * xres + x), p->contribSum, sizeof p->contribSum);
      wsum[y * xres + x] = p->filterWeightSum;
    }
  pbrt_FilmTile_free(&tile);
  pbrt_Film_free(&film);
}
/* A film whose pixels hold the given sums, through WriteImage */
void LAB_FN(write_image)(int xres, int yres, const float *xyz, const float *wsum, const float *splat, float scale,
                         float splatScale, float *rgb) {
  pbrt_Filter f = pbrt_MakeFilter(pbrt_BoxFilter, 0, 0);
  pbrt_Film film;
  int i;
  if (pbrt_Film_init(&film, xres, yres, &f, scale, 1e30f) != 0) exit(2);
  for (i = 0; i < xres * yres; ++i) {
    memcpy(film.pixels[i].xyz, xyz + 3 * i, sizeof(float) * 3);
    memcpy(film.pixels[i].splatXYZ, splat + 3 * i, sizeof(float) * 3);
    film.pixels[i].filterWeightSum = wsum[i];
  }
  pbrt_Film_WriteImage(&film, splatScale, rgb);
  pbrt_Film_free(&film);
}
