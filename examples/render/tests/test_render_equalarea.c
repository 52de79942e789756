/* test_render_equalarea: pbrt-v4's environment maps (issue 24). pbrt-v4 names the map "string filename"
 * and wants a square equal-area octahedral image (ImageInfiniteLight, Clarberg 2008); pbrt-v3 names it
 * "string mapname" and reads it as latitude-longitude.
 *
 * data/envmaps/city.hdr (1024x512, lat-long) is resampled here to a 512x512 equal-area map (each texel
 * the mean of 2x2 lookups of the lat-long light at el_envlight_square_to_dir's directions; the mapping
 * itself is checked against pbrt-v4's formulas in tests/test_envlight_bigmaps.c). A diffuse sphere on a
 * ground plane, lit by the map and in front of it, is rendered with the lat-long original ("mapname") and
 * with the equal-area copy ("filename"), at equal samples and different seeds. Stated bound: the relative
 * L2 difference of the two images is at most 1.5x that of two renders of the lat-long map with different
 * seeds, plus 0.02 (the equal-area map's nearest lookup against the lat-long map's bilinear one, seen
 * directly in the background); the same map mirrored left-right must exceed that bound. A 2:1 image given as "filename" renders as the lat-long map (bit for bit,
 * with a warning), and "mapname" together with "filename" is an error. */
#include "render_test_util.h"
#include "envlight.h"

#define N 512

static const char *scene_fmt =
    "LookAt 0 1.2 -4  0 0.6 0  0 1 0\n"
    "Camera \"perspective\" \"float fov\" [ 40 ]\n"
    "Film \"image\" \"integer xresolution\" [ 48 ] \"integer yresolution\" [ 32 ]\n"
    "Sampler \"stratified\" \"integer xsamples\" 4 \"integer ysamples\" 4\n"
    "Integrator \"directlighting\"\n"
    "WorldBegin\n"
    "AttributeBegin\n"
    "  Rotate -90 1 0 0\n"
    "  LightSource \"infinite\" \"string %s\" \"%s\"\n"
    "AttributeEnd\n"
    "Material \"matte\" \"rgb Kd\" [ 0.6 0.6 0.6 ]\n"
    "AttributeBegin\n"
    "  Translate 0 0.8 0\n"
    "  Shape \"sphere\" \"float radius\" 0.8\n"
    "AttributeEnd\n"
    "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point P\" [ -10 0 -10  10 0 -10  10 0 10  -10 0 10 ]\n"
    "WorldEnd\n";

static int render_map(const char *key, const char *file, uint64_t seed, elr_image *img, int *warnings) {
  char scene[2048], err[512], name[64];
  elr_scene *s;
  elr_stats st;
  int r;
  snprintf(scene, sizeof scene, scene_fmt, key, file);
  snprintf(name, sizeof name, "scene_%s_%s.pbrt", key, file);
  s = rt_load(name, scene, err, sizeof err);
  if (!s) { printf("load: %s\n", err); return -1; }
  if (warnings) *warnings = elr_scene_warnings(s);
  r = rt_render(s, 0, -1, -1, 2, seed, img, &st);
  elr_scene_free(s);
  return r;
}

static double rel_l2(const elr_image *a, const elr_image *b) {
  double num = 0, den = 0;
  int i;
  for (i = 0; i < 3 * a->width * a->height; i++) {
    double d = a->rgb[i] - b->rgb[i];
    num += d * d; den += (double)b->rgb[i] * b->rgb[i];
  }
  return sqrt(num / den);
}

int main(void) {
  el_image city;
  el_envlight ll;
  char err[512], path[512];
  float *sq;
  int x, y, s, c, warn = 0;
  elr_image a, b, e, w;
  double d_noise, d_ea;
  rt_mkdir("test_render_equalarea");
  snprintf(path, sizeof path, "%s/envmaps/city.hdr", EL_TEST_DATA_DIR);
  if (el_image_load(path, &city, err, sizeof err) != 0) { rt_check(0, "load %s: %s", path, err); return rt_finish("test_render_equalarea"); }
  if (el_envlight_init(&ll, city.pixels, city.width, city.height, city.channels, NULL) != EL_SUCCESS) {
    rt_check(0, "init city");
    return rt_finish("test_render_equalarea");
  }
  sq = (float *)malloc(sizeof(float) * 3 * N * N);
  for (y = 0; y < N; y++)
    for (x = 0; x < N; x++) {
      float acc[3] = {0, 0, 0};
      for (s = 0; s < 4; s++) {
        float d[3], rgb[3];
        el_envlight_square_to_dir((x + (s % 2 + 0.5f) / 2) / N, (y + (s / 2 + 0.5f) / 2) / N, d);
        el_envlight_le(&ll, d, rgb);
        for (c = 0; c < 3; c++) acc[c] += rgb[c] / 4;
      }
      for (c = 0; c < 3; c++) sq[3 * (y * N + x) + c] = acc[c];
    }
  rt_check(el_image_write_pfm(rt_path("city_ea.pfm"), sq, N, N, 3, err, sizeof err) == 0, "write the equal-area map");
  for (y = 0; y < N; y++) /* the same map mirrored left-right: the comparison below must reject it */
    for (x = 0; x < N / 2; x++)
      for (c = 0; c < 3; c++) {
        float t = sq[3 * (y * N + x) + c];
        sq[3 * (y * N + x) + c] = sq[3 * (y * N + N - 1 - x) + c];
        sq[3 * (y * N + N - 1 - x) + c] = t;
      }
  rt_check(el_image_write_pfm(rt_path("city_ea_mirror.pfm"), sq, N, N, 3, err, sizeof err) == 0, "write the mirrored equal-area map");
  rt_check(el_image_write_pfm(rt_path("city_ll.pfm"), city.pixels, city.width, city.height, city.channels, err, sizeof err) == 0 ||
               city.channels != 3,
           "write the lat-long map");
  free(sq);
  el_envlight_free(&ll);
  el_image_free(&city);

  if (render_map("mapname", "city_ll.pfm", 1, &a, NULL) || render_map("mapname", "city_ll.pfm", 2, &b, NULL) ||
      render_map("filename", "city_ea.pfm", 3, &e, &warn)) {
    rt_check(0, "render");
    return rt_finish("test_render_equalarea");
  }
  d_noise = rel_l2(&b, &a);
  d_ea = rel_l2(&e, &a);
  rt_check(warn == 0, "\"string filename\" with a square map: equal-area, no warning (%d)", warn);
  rt_check(d_ea <= 1.5 * d_noise + 0.02,
           "equal-area city (\"filename\") against lat-long city (\"mapname\"): relative L2 %.4f <= 1.5 x %.4f (two lat-long seeds) + 0.02", d_ea,
           d_noise);
  if (render_map("filename", "city_ea_mirror.pfm", 3, &w, NULL) == 0) {
    double d_m = rel_l2(&w, &a);
    rt_check(d_m > 1.5 * d_noise + 0.02, "the bound can fail: a mirrored equal-area map gives %.4f > %.4f", d_m, 1.5 * d_noise + 0.02);
    elr_image_free(&w);
  }
  /* a 2:1 image as "filename": the lat-long map, with a warning */
  if (render_map("filename", "city_ll.pfm", 1, &w, &warn) == 0) {
    rt_check(warn == 1 && !memcmp(w.rgb, a.rgb, sizeof(float) * 3 * (size_t)a.width * a.height),
             "a 2:1 \"filename\" renders as the lat-long map bit for bit, with one warning (%d)", warn);
    elr_image_free(&w);
  } else rt_check(0, "render a 2:1 filename");
  {
    elr_scene *sc;
    const char *both = "WorldBegin\nLightSource \"infinite\" \"string mapname\" \"city_ll.pfm\" \"string filename\" \"city_ea.pfm\"\nWorldEnd\n";
    sc = rt_load("both.pbrt", both, err, sizeof err);
    rt_check(!sc && strstr(err, "both") != NULL, "\"mapname\" and \"filename\" together are an error: %s", sc ? "(loaded)" : err);
    if (sc) elr_scene_free(sc);
  }
  elr_image_free(&a); elr_image_free(&b); elr_image_free(&e);
  return rt_finish("test_render_equalarea");
}
