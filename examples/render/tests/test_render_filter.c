/* test_render_filter: PixelFilter's "bool nonnegative" (envlight's extension, film.h's
 * el_film_options.nonnegative_filter; issue 24). The camera looks straight at an environment map whose
 * texels are random values in [0, 1], at 1 sample per pixel: every sample lies in [0, 1]. pbrt-v3's
 * "sinc" (Lanczos) filter divides by weight sums that can be near 0 or negative there, so pixels leave
 * [0, 1] (measured and printed: the behaviour film.h documents); with "bool nonnegative" "true" every
 * pixel is a weighted mean of its samples and stays within [0, 1]; "mitchell" likewise. */
#include "render_test_util.h"

static void run(const char *filter, int nonneg, float *lo, float *hi) {
  char scene[1024], err[512];
  elr_scene *s;
  elr_image img;
  size_t i;
  *lo = 1e30f; *hi = -1e30f;
  snprintf(scene, sizeof scene,
           "LookAt 0 0 0  1 0 0  0 0 1\nCamera \"perspective\" \"float fov\" [ 90 ]\n"
           "Film \"image\" \"integer xresolution\" [ 48 ] \"integer yresolution\" [ 48 ]\n"
           "PixelFilter \"%s\" \"bool nonnegative\" \"%s\"\nSampler \"random\" \"integer pixelsamples\" [ 1 ]\n"
           "WorldBegin\nLightSource \"infinite\" \"string mapname\" \"noise.pfm\"\nWorldEnd\n",
           filter, nonneg ? "true" : "false");
  s = rt_load("filter.pbrt", scene, err, sizeof err);
  if (!s) { rt_check(0, "load: %s", err); return; }
  memset(&img, 0, sizeof img);
  if (rt_render(s, 0, -1, -1, 1, 3, &img, NULL) == 0) {
    for (i = 0; i < (size_t)img.width * (size_t)img.height * 3; i++) {
      if (img.rgb[i] < *lo) *lo = img.rgb[i];
      if (img.rgb[i] > *hi) *hi = img.rgb[i];
    }
  }
  elr_image_free(&img);
  elr_scene_free(s);
}

int main(void) {
  float *px = (float *)malloc(sizeof(float) * 3 * 256 * 128), lo, hi;
  char err[256];
  unsigned r = 12345u;
  int i;
  rt_mkdir("test_render_filter");
  for (i = 0; i < 3 * 256 * 128; i++) { r = r * 1664525u + 1013904223u; px[i] = (float)(r >> 8) / 16777216.0f; }
  if (el_image_write_pfm(rt_path("noise.pfm"), px, 256, 128, 3, err, sizeof err) != 0) { rt_check(0, "write: %s", err); return rt_finish("test_render_filter"); }
  free(px);
  run("sinc", 0, &lo, &hi);
  rt_check(hi > 1.0f, "sinc, 1 spp, samples in [0, 1]: pixels %g .. %g leave [0, 1] (pbrt-v3's behaviour; negatives are output as 0)", lo, hi);
  run("sinc", 1, &lo, &hi);
  rt_check(lo >= 0.0f && hi <= 1.0f, "sinc with \"bool nonnegative\": pixels %g .. %g within [0, 1]", lo, hi);
  run("mitchell", 1, &lo, &hi);
  rt_check(lo >= 0.0f && hi <= 1.0f, "mitchell with \"bool nonnegative\": pixels %g .. %g within [0, 1]", lo, hi);
  return rt_finish("test_render_filter");
}
