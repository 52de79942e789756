/* tests/labs/lab_film.h: what lab 4 calls in each build of film.h (lab_film_side.c): ref_* is
 * examples/pbrtv3/film.h (pbrt's behaviour), stu_* the file under test. */
#ifndef LAB_FILM_H
#define LAB_FILM_H
#define LAB_FILM_DECLARE(p)                                                                                 \
  float p##_gamma(float v);                                                                               \
  void p##_bytes(const float *v, int n, unsigned char *out);                                              \
  void p##_add_samples(int xres, int yres, int filter, float radius, int n, const float *pFilm, const float *L, \
                       const float *weight, float *contrib, float *wsum);                                  \
  void p##_write_image(int xres, int yres, const float *xyz, const float *wsum, const float *splat, float scale, \
                       float splatScale, float *rgb);
LAB_FILM_DECLARE(ref)
LAB_FILM_DECLARE(stu)
#endif
