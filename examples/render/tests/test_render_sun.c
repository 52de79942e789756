/* test_render_sun.c: issue 22's sun cache (sun.c) on the two sun scenes (scenes/sun_shadow_object.pbrt:
 * direct lighting; scenes/sun_porch.pbrt: path tracing; both under data/envmaps/sunrise.hdr).
 *
 * UNBIASED against the renderer's density without the cache (--sun off): 8 seeds each; per class of pixels
 * (shadowed, lit: tests/sun_measure.h, from the geometry) and over the whole image, z = the mean over the
 * pixels of (mean with - mean without) over its standard error (the per-pixel variances over the seeds /
 * 8, the pixels independent); |z| < 4 (a false alarm about 6e-5 per check; a wrong pdf gave |z| > 700).
 * LESS NOISE in the shadow: the mean per-pixel variance of the shadowed pixels at equal samples at least
 * 1.3x lower (direct lighting; measured 1.44x, median pixel 1.35x) and 1.0x (path tracing; measured 1.04x,
 * median pixel 1.23x; the same with product MIS at every diffuse vertex, ELR_ENVSD_PRODUCT, the default since
 * batched product samples), against the default without the cache: since the sun rule by the normal
 * (materials.c, ELR_ENVSD_SUNCOS) the ground under sunrise.hdr's low sun is product-sampled without the
 * cache too (against the map alone there, the rule before, the cache gave 1.9x / 2.9x and 1.35x),
 * the lit pixels' within 5% (they keep their density). DETERMINISTIC: the same image for 1 and 2 threads
 * and for the one-sample and wave loops; off by default. --stats: the hot spot and the sharing of the samples. A map
 * without a hot spot, a map of lamps without a sun (studio.hdr), or --sun off: no cache. Hostile: a camera that sees no surface (the pilot finds no
 * cell), 1 x 1 pixel, a crop window: finite images. --sun split (split_check below): unbiased and deterministic. About 20 s. */
#include "render_test_util.h"
#include "sun_measure.h"

static elr_scene *load(const char *name) {
  char path[512], err[512];
  elr_scene *s = NULL;
  snprintf(path, sizeof path, "%s/../scenes/%s", EL_TEST_DATA_DIR, name);
  if (elr_scene_load(path, &s, 1, err, sizeof err) != 0) { printf("%s: %s\n", path, err); return NULL; }
  return s;
}

static void compare(const char *name, double min_gain) {
  elr_scene *s = load(name);
  elr_image im;
  elr_stats st;
  sm_result off, on;
  unsigned char *cls;
  int w, h, c;
  const int ns = 8, spp = 8;
  if (!s) { rt_check(0, "%s loads", name); return; }
  rt_render(s, 1, -1, -1, 2, 1, &im, &st); /* (the light's tables, for the classes) */
  elr_image_free(&im);
  cls = sm_classes(s, &w, &h);
  if (!cls || sm_run(s, spp, ns, 0, 2, cls, w, h, &off) || sm_run(s, spp, ns, 1, 2, cls, w, h, &on)) { rt_check(0, "%s renders", name); return; }
  for (c = 1; c <= 2; c++) {
    double z = sm_z(&on, &off, cls, w * h, c, ns);
    rt_check(fabs(z) < 4, "%s, %s pixels (%d): means agree with and without the cache (%.5g, %.5g, z %+.2f)", name, c == 1 ? "shadowed" : "lit", on.n[c],
             on.mean[c], off.mean[c], z);
  }
  rt_check(fabs(sm_z(&on, &off, cls, w * h, -1, ns)) < 4, "%s: whole image's means agree (z %+.2f)", name, sm_z(&on, &off, cls, w * h, -1, ns));
  rt_check(on.n[1] > w * h / 5 && off.var[1] >= min_gain * on.var[1], "%s: shadowed pixels' variance %.2fx lower at %d spp (>= %.2f; median pixel %.2fx)", name,
           off.var[1] / on.var[1], spp, min_gain, off.med[1] / on.med[1]);
  rt_check(on.var[2] <= 1.05 * off.var[2] && on.var[2] >= 0.95 * off.var[2], "%s: lit pixels' variance unchanged (%.3fx)", name, off.var[2] / on.var[2]);
  rt_check(on.st.sun_used && on.st.sun_spots == 1 && fabs(on.st.sun_spot_share[0] - 0.75) < 0.02 && on.st.sun_spot_half_angle[0] < 0.05f,
           "%s: --stats: one hot spot, share %.3f (0.75 put in the map), half-angle %.2f deg", name, on.st.sun_spot_share[0],
           on.st.sun_spot_half_angle[0] * 57.2958);
  rt_check(on.st.sun_looked > 0 && on.st.sun_dark > on.st.sun_looked / 5 && on.st.sun_cells_dark > 0 && on.st.sun_pilot_points > 0,
           "%s: --stats: %.1f%% of the light samples where no spot was seen, %lld dark cells", name,
           100.0 * (double)on.st.sun_dark / (double)on.st.sun_looked, (long long)on.st.sun_cells_dark);
  rt_check(!off.st.sun_used && off.st.sun_looked == 0, "%s: --sun off builds no cache", name);
  sm_free(&off); sm_free(&on); free(cls);
  elr_scene_free(s);
}

static int same(elr_scene *s, int loop, int nthreads, const elr_image *ref) {
  elr_render_options o;
  elr_image im;
  char err[512];
  int r;
  elr_render_options_default(&o);
  o.spp = 4; o.nthreads = nthreads; o.loop = loop; o.quiet = 1; o.seed = 5; o.env_sun = 1;
  if (elr_render(s, &o, &im, NULL, err, sizeof err) != 0) return 0;
  r = ref->rgb && im.width == ref->width && im.height == ref->height && !memcmp(im.rgb, ref->rgb, sizeof(float) * 3 * (size_t)im.width * (size_t)im.height);
  elr_image_free(&im);
  return r;
}
static void determinism(const char *name) {
  elr_scene *s = load(name);
  elr_render_options o;
  elr_image ref;
  char err[512];
  if (!s) { rt_check(0, "%s loads", name); return; }
  elr_render_options_default(&o);
  o.spp = 4; o.nthreads = 1; o.loop = ELR_LOOP_ONE; o.quiet = 1; o.seed = 5; o.env_sun = 1;
  if (elr_render(s, &o, &ref, NULL, err, sizeof err) != 0) { rt_check(0, "%s renders", name); elr_scene_free(s); return; }
  rt_check(same(s, ELR_LOOP_ONE, 2, &ref) && same(s, ELR_LOOP_WAVE, 1, &ref) && same(s, ELR_LOOP_WAVE, 2, &ref),
           "%s: with the cache, the same image for 1 and 2 threads, one-sample and wave loops (the first render finds the "
           "hot spots, the others reuse the light's: elr_light.sun_hs; the wave loop looks the cell up once per vertex)", name);
  { /* the default (-1) is off for now (el_render.h) */
    elr_stats st;
    elr_image im;
    rt_render(s, 1, -1, -1, 1, 1, &im, &st);
    rt_check(!st.sun_used, "%s: the default options build no cache", name);
    elr_image_free(&im);
  }
  elr_image_free(&ref);
  elr_scene_free(s);
}

static void no_spot(void) {
  char text[1024], err[512];
  elr_scene *s;
  elr_image im;
  elr_stats st;
  elr_render_options o;
  snprintf(text, sizeof text, "Camera \"perspective\"\nFilm \"image\" \"integer xresolution\" [ 16 ] \"integer yresolution\" [ 16 ]\n"
           "WorldBegin\nLightSource \"infinite\" \"string mapname\" \"%s/envmaps/overcast.pfm\"\n"
           "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point P\" [ -1 -1 2  1 -1 2  1 1 2  -1 1 2 ]\nWorldEnd\n", EL_TEST_DATA_DIR);
  s = rt_load("overcast.pbrt", text, err, sizeof err);
  if (!s) { rt_check(0, "overcast scene loads: %s", err); return; }
  elr_render_options_default(&o);
  o.spp = 2; o.quiet = 1; o.nthreads = 1; o.env_sun = 1;
  rt_check(elr_render(s, &o, &im, &st, err, sizeof err) == 0 && !st.sun_used, "a map without a hot spot (overcast), --sun on: no cache");
  elr_image_free(&im);
  o.env_sun = 2;
  rt_check(elr_render(s, &o, &im, &st, err, sizeof err) == 0 && !st.sunsplit_used, "a map without a hot spot (overcast), --sun split: no split");
  elr_image_free(&im);
  o.env_sun = 1;
  elr_scene_free(s);
  snprintf(text, sizeof text, "Camera \"perspective\"\nFilm \"image\" \"integer xresolution\" [ 16 ] \"integer yresolution\" [ 16 ]\n"
           "WorldBegin\nLightSource \"infinite\" \"string mapname\" \"%s/envmaps/studio.hdr\"\n"
           "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point P\" [ -1 -1 2  1 -1 2  1 1 2  -1 1 2 ]\nWorldEnd\n", EL_TEST_DATA_DIR);
  s = rt_load("studio.pbrt", text, err, sizeof err);
  if (!s) { rt_check(0, "studio scene loads: %s", err); return; }
  rt_check(elr_render(s, &o, &im, &st, err, sizeof err) == 0 && !st.sun_used, "lamps without a sun (studio.hdr: 4 hot spots), --sun on: no cache");
  elr_image_free(&im);
  o.env_sun = 2;
  rt_check(elr_render(s, &o, &im, &st, err, sizeof err) == 0 && !st.sunsplit_used, "lamps without a sun (studio.hdr), --sun split: no split");
  elr_image_free(&im);
  elr_scene_free(s);
}

/* hostile: the pilot sees no surface (the camera looks at the sky; the lit plane is behind it, seen by
 * reflections only): the render works, with no cell; an image of 1 x 1 pixel; a crop window */
static void hostile(void) {
  char text[2048], err[512];
  elr_scene *s;
  elr_image im;
  elr_stats st;
  elr_render_options o;
  int k;
  static const char *cams[3] = {"LookAt 0 1 0  0 5 0.01  0 0 1\nCamera \"perspective\"\nFilm \"image\" \"integer xresolution\" [ 8 ] \"integer yresolution\" [ 8 ]\n",
                                "LookAt 0 2 -4  0 0 0  0 1 0\nCamera \"perspective\"\nFilm \"image\" \"integer xresolution\" [ 1 ] \"integer yresolution\" [ 1 ]\n",
                                "LookAt 0 2 -4  0 0 0  0 1 0\nCamera \"perspective\"\nFilm \"image\" \"integer xresolution\" [ 16 ] \"integer yresolution\" [ 16 ] \"float cropwindow\" [ 0.5 0.75 0.25 0.5 ]\n"};
  for (k = 0; k < 3; k++) {
    int ok, i;
    snprintf(text, sizeof text, "%sWorldBegin\nAttributeBegin\nRotate -90 1 0 0\nLightSource \"infinite\" \"string mapname\" \"%s/envmaps/sunrise.hdr\"\nAttributeEnd\n"
             "Material \"matte\"\nShape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point P\" [ -9 0 -9  9 0 -9  9 0 9  -9 0 9 ]\n"
             "Shape \"sphere\" \"float radius\" 0.5\nWorldEnd\n", cams[k], EL_TEST_DATA_DIR);
    s = rt_load("hostile.pbrt", text, err, sizeof err);
    if (!s) { rt_check(0, "hostile scene %d loads: %s", k, err); continue; }
    elr_render_options_default(&o);
    o.spp = 4; o.quiet = 1; o.nthreads = 2; o.env_sun = 1;
    ok = elr_render(s, &o, &im, &st, err, sizeof err) == 0;
    for (i = 0; ok && i < im.width * im.height * 3; i++) ok = isfinite(im.rgb[i]) && im.rgb[i] >= 0.f;
    rt_check(ok && st.sun_used, "--sun on, %s: renders, finite pixels (%lld pilot points, %lld cells)",
             k == 0 ? "a camera that sees no surface" : k == 1 ? "1 x 1 pixel" : "a crop window", (long long)st.sun_pilot_points, (long long)st.sun_cells);
    if (ok) elr_image_free(&im);
    o.env_sun = 2;
    ok = elr_render(s, &o, &im, &st, err, sizeof err) == 0;
    for (i = 0; ok && i < im.width * im.height * 3; i++) ok = isfinite(im.rgb[i]) && im.rgb[i] >= 0.f;
    rt_check(ok && st.sunsplit_used, "--sun split, %s: renders, finite pixels", k == 0 ? "a camera that sees no surface" : k == 1 ? "1 x 1 pixel" : "a crop window");
    if (ok) elr_image_free(&im);
    elr_scene_free(s);
  }
}

/* --sun split (sun.c: a light sample of the hot spots and one of the rest x cosine at every diffuse vertex, MIS over
 * the three techniques with the BSDF sample; the spot sample el_envlight_sample_li_spot, le()'s patches renormalised to a
 * rectangle around the spot, on both maps; the older ways, sun.c's ELR_SUNSPLIT_SPOT 0 and 2, were checked the same way
 * when they were the default): UNBIASED against the default (--sun off), 8 seeds of 8 spp (city 4) each, per
 * class and over the image, |z| < 4 as above (measured with planted errors: the BSDF sample's weight leaving out the
 * spot sample's density, which counts the sun twice, z +5.2 on sun_shadow_object's lit pixels and whole image, +5.9 on
 * bench_city's, +2.9 on sun_porch's; the light samples' weights ignoring the BSDF's, z +56 to +582; NOT caught: the
 * sky's density left out of the weights inside the spot's widened cone, where little light is); DETERMINISTIC: the
 * same image for 1 and 2 threads; --stats counts
 * the split vertices. (Its noise against the default is bench/bench_sun_render --split's.) */
static void split_check(const char *name, int spp, int spot) {
  elr_scene *s = load(name);
  elr_image im, ref;
  elr_render_options o;
  sm_result off, sp;
  unsigned char *cls;
  char err[512];
  int w, h, c;
  const int ns = 8;
  if (!s) { rt_check(0, "%s loads", name); return; }
  rt_render(s, 1, -1, -1, 2, 1, &im, NULL); /* (the light's tables, for the classes) */
  elr_image_free(&im);
  cls = sm_classes(s, &w, &h);
  if (!cls || sm_run(s, spp, ns, 0, 2, cls, w, h, &off) || sm_run(s, spp, ns, 2, 2, cls, w, h, &sp)) { rt_check(0, "%s renders", name); return; }
  for (c = 1; c <= 2; c++) {
    double z = sm_z(&sp, &off, cls, w * h, c, ns);
    rt_check(fabs(z) < 4, "--sun split, %s, %s pixels (%d): means agree with the default (%.5g, %.5g, z %+.2f)", name, c == 1 ? "shadowed" : "lit",
             sp.n[c], sp.mean[c], off.mean[c], z);
  }
  rt_check(fabs(sm_z(&sp, &off, cls, w * h, -1, ns)) < 4, "--sun split, %s: whole image's means agree (z %+.2f)", name, sm_z(&sp, &off, cls, w * h, -1, ns));
  rt_check(sp.st.sunsplit_used && sp.st.sunsplit_vertices > 0 && !sp.st.sun_used && sp.st.loop == off.st.loop && sp.st.sunsplit_spot == spot,
           "--sun split, %s: --stats: %llu vertices split (%llu of them the sky alone), the spot sample by way %d (%d expected), no "
           "cache, the default's loop", name, (unsigned long long)sp.st.sunsplit_vertices, (unsigned long long)sp.st.sunsplit_sky_only,
           sp.st.sunsplit_spot, spot);
  sm_free(&off); sm_free(&sp); free(cls);
  elr_render_options_default(&o);
  o.spp = 4; o.nthreads = 1; o.quiet = 1; o.seed = 5; o.env_sun = 2;
  if (elr_render(s, &o, &ref, NULL, err, sizeof err) != 0) { rt_check(0, "%s renders: %s", name, err); elr_scene_free(s); return; }
  o.nthreads = 2;
  rt_check(elr_render(s, &o, &im, NULL, err, sizeof err) == 0 && im.width == ref.width && im.height == ref.height &&
               !memcmp(im.rgb, ref.rgb, sizeof(float) * 3 * (size_t)im.width * (size_t)im.height),
           "--sun split, %s: the same image for 1 and 2 threads", name);
  elr_image_free(&im); elr_image_free(&ref);
  elr_scene_free(s);
}

/* --sun split on a map of TWO suns (a generated 256 x 128 PFM: suns of one texel, 3e5 and 2e5, so that the render's sun
 * rule sees a sun; about 0.55 and 0.37 of the power):
 * the spot sample picks a spot by its share and its pdf is the mixture of the two rectangles' (sun.c, ELR_SUNSPLIT_SPOT
 * 3); unbiased against the default over the whole image, 8 seeds of 8 spp, |z| < 4 (planted: every spot sample from the
 * first spot, its pdf still the mixture's: z -254) */
static void two_suns_check(void) {
  char text[2048], err[512];
  elr_scene *s;
  sm_result off, sp;
  unsigned char *cls;
  int w, h, x, y, c;
  const int mw = 256, mh = 128, ns = 8;
  FILE *f = fopen(rt_path("two_suns.pfm"), "wb");
  if (!f) { rt_check(0, "two suns: writes its map"); return; }
  fprintf(f, "PF\n%d %d\n-1.0\n", mw, mh);
  for (y = 0; y < mh; y++)
    for (x = 0; x < mw; x++) {
      float v = 0.4f + 0.3f * (float)y / mh, sun = x == 50 && y == mh - 41 ? 3e5f : x == 160 && y == mh - 45 ? 2e5f : 0.f; /* (PFM rows run bottom to top) */
      for (c = 0; c < 3; c++) { float q = sun > 0.f ? sun : v * (c == 2 ? 1.2f : 1.f); fwrite(&q, 4, 1, f); }
    }
  fclose(f);
  snprintf(text, sizeof text, "LookAt 0 2.6 -7   0 0.3 1.5   0 1 0\nCamera \"perspective\" \"float fov\" [ 45 ]\n"
           "Film \"image\" \"integer xresolution\" [ 48 ] \"integer yresolution\" [ 36 ]\nSampler \"halton\" \"integer pixelsamples\" [ 8 ]\n"
           "Integrator \"directlighting\"\nWorldBegin\nAttributeBegin\nRotate -90 1 0 0\nLightSource \"infinite\" \"string mapname\" \"two_suns.pfm\"\n"
           "AttributeEnd\nMaterial \"matte\" \"rgb Kd\" [ 0.5 0.5 0.5 ]\n"
           "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point P\" [ -30 0 -30  30 0 -30  30 0 30  -30 0 30 ]\n"
           "Translate 0.5 0.8 1\nShape \"sphere\" \"float radius\" 0.8\nWorldEnd\n");
  s = rt_load("two_suns.pbrt", text, err, sizeof err);
  if (!s) { rt_check(0, "two suns scene loads: %s", err); return; }
  { elr_image im; rt_render(s, 1, -1, -1, 2, 1, &im, NULL); elr_image_free(&im); } /* (the light's tables, for the classes) */
  cls = sm_classes(s, &w, &h);
  if (!cls || sm_run(s, 8, ns, 0, 2, cls, w, h, &off) || sm_run(s, 8, ns, 2, 2, cls, w, h, &sp)) { rt_check(0, "two suns renders"); elr_scene_free(s); free(cls); return; }
  rt_check(fabs(sm_z(&sp, &off, cls, w * h, -1, ns)) < 4 && sp.st.sunsplit_used && sp.st.sunsplit_vertices > 0 && sp.st.sunsplit_spot == 3,
           "--sun split, two suns: whole image's means agree (z %+.2f), %llu vertices split, the spot sample by way %d",
           sm_z(&sp, &off, cls, w * h, -1, ns), (unsigned long long)sp.st.sunsplit_vertices, sp.st.sunsplit_spot);
  sm_free(&off); sm_free(&sp); free(cls);
  elr_scene_free(s);
}

int main(void) {
  rt_mkdir("sun");
  compare("sun_shadow_object.pbrt", 1.3);
  compare("sun_porch.pbrt", 1.0);
  determinism("sun_shadow_object.pbrt");
  determinism("sun_porch.pbrt");
  split_check("sun_shadow_object.pbrt", 8, 3); /* (sunrise.hdr: el_envlight_sample_li_spot on le()'s patches) */
  split_check("sun_porch.pbrt", 8, 3);
  split_check("bench_city.pbrt", 4, 3);         /* (city.hdr: the same, its sun 0.245 of the power) */
  two_suns_check();
  no_spot();
  hostile();
  return rt_finish("test_render_sun");
}
