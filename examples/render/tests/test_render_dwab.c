/* test_render_dwab: lossy environment maps (issue 24). The HDRIs Blender ships are DWAB-compressed EXR
 * files whose ringing leaves small negative texels; the renderer used to refuse them ("texel (615, 230)
 * is NaN, infinite or negative"). Now LightSource "infinite" clamps finite negatives to 0 by default
 * ("string badtexels" "clampnegative") with one warning that counts them and names the most negative
 * value, keeps NaN and infinite texels as errors naming the file and the texel unless the scene says
 * "zero", and refuses negatives too with "error".
 *
 * 1. data/envmaps/dwab/city.exr (Blender's own DWAB file, 213 KB, CC0) loads with exactly one warning;
 *    the light's counts equal those the test finds itself in the decoded image (texels with a negative
 *    channel, the most negative value and its texel), and the warning names them and the file.
 * 2. It renders like its lossless copy data/envmaps/city.hdr: relative MSE (mean of (x - ref)^2 /
 *    (ref^2 + 0.01), bench_render's) under 2e-3 at equal samples and seed, for the path tracer with
 *    product sampling and with the map alone; and the two differ (the lossy texels are used, not the .hdr).
 * 3. "badtexels" "error" refuses the DWAB map naming the file, the texel and "negative".
 * 4. A map with a NaN and an infinite texel (a PFM written here): the default refuses it naming the file
 *    and texel; "zero" loads it with one warning counting 2 such texels; an unknown policy is an error. */
#include "render_test_util.h"

#ifndef EL_TEST_DATA_DIR
#define EL_TEST_DATA_DIR "data"
#endif

static double rel_mse(const elr_image *a, const elr_image *ref) {
  size_t n = (size_t)a->width * (size_t)a->height * 3, i;
  double s = 0;
  for (i = 0; i < n; i++) {
    double d = (double)a->rgb[i] - (double)ref->rgb[i];
    s += d * d / ((double)ref->rgb[i] * ref->rgb[i] + 0.01);
  }
  return s / (double)n;
}

static int g_rotate = 1; /* the light turned as envlight_demo.pbrt turns it (0: light space = world) */
static const char *scene_text(const char *map, const char *extra, const char *sampling) {
  static char buf[2048];
  snprintf(buf, sizeof buf,
           "LookAt 0 1.6 -6.2   0 0.8 0   0 1 0\n"
           "Camera \"perspective\" \"float fov\" [ 38 ]\n"
           "Film \"image\" \"integer xresolution\" [ 64 ] \"integer yresolution\" [ 40 ]\n"
           "Sampler \"halton\" \"integer pixelsamples\" [ 16 ]\n"
           "Integrator \"path\" \"integer maxdepth\" [ 3 ]\n"
           "WorldBegin\n"
           "AttributeBegin\n%s"
           " LightSource \"infinite\" \"string mapname\" \"%s\" %s \"string sampling\" \"%s\"\n"
           "AttributeEnd\n"
           "AttributeBegin\n Translate -1.2 0.9 0\n Material \"matte\" \"rgb Kd\" [ 0.65 0.25 0.2 ]\n"
           " Shape \"sphere\" \"float radius\" 0.9\nAttributeEnd\n"
           "AttributeBegin\n Translate 1.2 0.9 0.6\n Material \"plastic\" \"rgb Kd\" [ 0.1 0.2 0.5 ] \"rgb Ks\" [ 0.5 0.5 0.5 ]"
           " \"float roughness\" 0.05\n Shape \"sphere\" \"float radius\" 0.9\nAttributeEnd\n"
           "Material \"matte\" \"rgb Kd\" [ 0.5 0.5 0.5 ]\n"
           "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point P\" [ -12 0 -12 12 0 -12 12 0 12 -12 0 12 ]\n"
           "WorldEnd\n",
           g_rotate ? " Rotate -90 1 0 0\n Rotate 120 0 0 1\n" : "", map, extra, sampling);
  return buf;
}

/* the test's own count of what the light should report, from the image reader */
static void count_negatives(const char *path, size_t *count, float *most, int *mx, int *my) {
  el_image im;
  char e[256];
  size_t i, n;
  *count = 0; *most = 0; *mx = *my = -1;
  if (el_image_load(path, &im, e, sizeof e) != 0) { printf("cannot read %s: %s\n", path, e); return; }
  n = (size_t)im.width * (size_t)im.height;
  for (i = 0; i < n; i++) {
    int c, any = 0;
    for (c = 0; c < 3; c++) {
      float v = im.pixels[i * (size_t)im.channels + (size_t)(im.channels >= 3 ? c : 0)];
      if (v < 0) {
        any = 1;
        if (v < *most) { *most = v; *mx = (int)(i % (size_t)im.width); *my = (int)(i / (size_t)im.width); }
      }
    }
    *count += (size_t)any;
  }
  el_image_free(&im);
}

static void lossy_map(void) {
  const char *dwab = EL_TEST_DATA_DIR "/envmaps/dwab/city.exr", *hdr = EL_TEST_DATA_DIR "/envmaps/city.hdr";
  char err[1024];
  size_t count;
  float most;
  int mx, my, k;
  elr_scene *s;
  FILE *f = fopen(dwab, "rb");
  long size = -1;
  if (f) { fseek(f, 0, SEEK_END); size = ftell(f); fclose(f); }
  rt_check(size > 0 && size < 300000, "%s is in the repository and small (%ld bytes < 300 KB)", dwab, size);
  count_negatives(dwab, &count, &most, &mx, &my);
  rt_check(count > 0 && most < 0, "the DWAB map holds negative texels (%zu, the most negative %g at (%d, %d))", count, (double)most, mx, my);

  /* 1. loads, one warning, the counts */
  s = rt_load("dwab.pbrt", scene_text(dwab, "", "product"), err, sizeof err);
  rt_check(s != NULL, "the DWAB map loads (it used to be refused): %s", s ? "ok" : err);
  if (s) {
    const el_envlight *env = s->light[0].env;
    rt_check(elr_scene_warnings(s) == 1, "exactly one warning (%d)", elr_scene_warnings(s));
    rt_check(env->negative_texels == count && env->nonfinite_texels == 0, "the light counts %zu negative texels (the test: %zu)",
             env->negative_texels, count);
    rt_check(env->most_negative == most && env->most_negative_index == my * 1024 + mx,
             "the most negative value %g at (%d, %d) (the test: %g at (%d, %d))", (double)env->most_negative,
             env->most_negative_index % 1024, env->most_negative_index / 1024, (double)most, mx, my);
    elr_scene_free(s);
  }

  /* 2. renders like the lossless copy */
  for (k = 0; k < 2; k++) {
    const char *sampling = k ? "map" : "product";
    elr_scene *a = rt_load("a.pbrt", scene_text(dwab, "", sampling), err, sizeof err);
    elr_scene *b = rt_load("b.pbrt", scene_text(hdr, "", sampling), err, sizeof err);
    elr_image ia, ib;
    memset(&ia, 0, sizeof ia); memset(&ib, 0, sizeof ib);
    if (a && b && rt_render(a, 0, -1, -1, 2, 7, &ia, NULL) == 0 && rt_render(b, 0, -1, -1, 2, 7, &ib, NULL) == 0) {
      double e = rel_mse(&ia, &ib);
      size_t i, differ = 0;
      for (i = 0; i < (size_t)ia.width * (size_t)ia.height * 3; i++) differ += ia.rgb[i] != ib.rgb[i];
      rt_check(e < 2e-3, "sampling \"%s\": DWAB against lossless at 16 spp, the same seed: relative MSE %.3g < 2e-3", sampling, e);
      rt_check(differ > 0, "sampling \"%s\": the images differ (%zu values): the lossy texels were rendered", sampling, differ);
    } else rt_check(0, "sampling \"%s\": both scenes load and render (%s)", sampling, err);
    elr_image_free(&ia); elr_image_free(&ib);
    if (a) elr_scene_free(a);
    if (b) elr_scene_free(b);
  }

  /* 3. "error" refuses it, naming file, texel and the problem */
  s = rt_load("strict.pbrt", scene_text(dwab, "\"string badtexels\" \"error\"", "product"), err, sizeof err);
  rt_check(s == NULL && strstr(err, "dwab/city.exr") && strstr(err, "negative") && strstr(err, "texel ("),
           "\"badtexels\" \"error\" refuses it: %s", s ? "(loaded)" : err);
  if (s) elr_scene_free(s);
}

static void nonfinite_map(void) {
  float px[8 * 4 * 3];
  char err[1024];
  elr_scene *s;
  int i;
  g_rotate = 0;
  for (i = 0; i < 8 * 4 * 3; i++) px[i] = 0.5f;
  px[3 * (1 * 8 + 5) + 1] = NAN;      /* texel (5, 1) */
  px[3 * (2 * 8 + 2) + 0] = INFINITY; /* texel (2, 2) */
  px[3 * (3 * 8 + 7) + 2] = -0.25f;   /* texel (7, 3), negative */
  if (el_image_write_pfm(rt_path("bad.pfm"), px, 8, 4, 3, err, sizeof err) != 0) { rt_check(0, "write bad.pfm: %s", err); return; }
  s = rt_load("nan.pbrt", scene_text(rt_path("bad.pfm"), "", "product"), err, sizeof err);
  rt_check(s == NULL && strstr(err, "bad.pfm") && strstr(err, "texel (5, 1) is NaN"), "a NaN texel stays an error naming the file and texel: %s",
           s ? "(loaded)" : err);
  if (s) elr_scene_free(s);
  s = rt_load("zero.pbrt", scene_text(rt_path("bad.pfm"), "\"string badtexels\" \"zero\"", "product"), err, sizeof err);
  rt_check(s != NULL, "\"badtexels\" \"zero\" loads it: %s", s ? "ok" : err);
  if (s) {
    const el_envlight *env = s->light[0].env;
    rt_check(env->nonfinite_texels == 2 && env->negative_texels == 1 && env->most_negative == -0.25f &&
                 env->most_negative_index == 3 * 8 + 7 && elr_scene_warnings(s) == 2,
             "2 NaN / infinite texels and 1 negative one became 0, one warning each (%zu, %zu, %g, %d warnings)", env->nonfinite_texels,
             env->negative_texels, (double)env->most_negative, elr_scene_warnings(s));
    { /* le at the three texels' centres (the light is not rotated): 0 in the channel that was bad */
      static const int tx[3][3] = {{5, 1, 1}, {2, 2, 0}, {7, 3, 2}};
      int k, ok = 1;
      for (k = 0; k < 3; k++) {
        float d[3], rgb[3];
        el_envlight_uv_to_dir((tx[k][0] + 0.5f) / 8.0f, (tx[k][1] + 0.5f) / 4.0f, d);
        el_envlight_le(env, d, rgb);
        if (!(fabsf(rgb[tx[k][2]]) < 1e-4f)) ok = 0;
      }
      rt_check(ok, "the three texels are 0 in the light (le at their centres)");
    }
    elr_scene_free(s);
  }
  s = rt_load("what.pbrt", scene_text(rt_path("bad.pfm"), "\"string badtexels\" \"ignore\"", "product"), err, sizeof err);
  rt_check(s == NULL && strstr(err, "badtexels must be"), "an unknown policy is an error: %s", s ? "(loaded)" : err);
  if (s) elr_scene_free(s);
}

int main(void) {
  rt_mkdir("test_render_dwab");
  lossy_map();
  nonfinite_map();
  return rt_finish("test_render_dwab");
}
