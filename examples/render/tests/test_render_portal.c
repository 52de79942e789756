/* test_render_portal.c: pbrt-v4's "point3 portal" on the infinite light (issue 23). A room lit through
 * one window by the CC0 city map (its sun shines in) and by a generated overcast sky: the image with the
 * portal agrees with the image without it within noise (unbiased: the means of the lit floor and of
 * the whole image, over 4 seeds each), and its pixels' error against a high-spp reference is smaller;
 * --stats reports the strategy; a portal that is not a rectangle, or on a light without a map, is an
 * error naming the problem. Small images, a few seconds. */
#include "render_test_util.h"
#include <math.h>

static const char *ROOM =
    "Material \"matte\" \"rgb Kd\" [ 0.6 0.6 0.6 ]\n"
    "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point P\" [ -2 0 -2  2 0 -2  2 0 2  -2 0 2 ]\n"
    "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point P\" [ -2 2.6 -2  2 2.6 -2  2 2.6 2  -2 2.6 2 ]\n"
    "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point P\" [ -2 0 -2  -2 2.6 -2  -2 2.6 2  -2 0 2 ]\n"
    "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point P\" [ -2 0 -2  2 0 -2  2 2.6 -2  -2 2.6 -2 ]\n"
    "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point P\" [ -2 0 2  2 0 2  2 2.6 2  -2 2.6 2 ]\n"
    "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point P\" [ 2 0 -2  2 1.2 -2  2 1.2 2  2 0 2 ]\n"
    "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point P\" [ 2 2.2 -2  2 2.6 -2  2 2.6 2  2 2.2 2 ]\n"
    "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point P\" [ 2 1.2 -2  2 2.2 -2  2 2.2 -0.8  2 1.2 -0.8 ]\n"
    "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point P\" [ 2 1.2 0.4  2 2.2 0.4  2 2.2 2  2 1.2 2 ]\n"
    "WorldEnd\n";

static elr_scene *load_room(const char *map, const char *portal, int depth) {
  char text[8192], err[512];
  elr_scene *s;
  snprintf(text, sizeof text,
           "LookAt -1.8 1.5 1.8   1 0.5 -0.8   0 1 0\nCamera \"perspective\" \"float fov\" [ 62 ]\n"
           "Film \"image\" \"integer xresolution\" [ 40 ] \"integer yresolution\" [ 30 ]\n"
           "Sampler \"halton\" \"integer pixelsamples\" [ 16 ]\nIntegrator \"path\" \"integer maxdepth\" [ %d ]\nWorldBegin\n"
           "AttributeBegin\n Rotate -90 1 0 0\n Rotate 120 0 0 1\n LightSource \"infinite\" \"string mapname\" \"%s/envmaps/%s\" %s\nAttributeEnd\n%s",
           depth, EL_TEST_DATA_DIR, map, portal, ROOM);
  s = rt_load("room.pbrt", text, err, sizeof err);
  if (!s) printf("load: %s\n", err);
  return s;
}
static double image_mean(const elr_image *im) {
  double m = 0;
  int i;
  for (i = 0; i < im->width * im->height * 3; ++i) m += im->rgb[i];
  return m / (im->width * im->height * 3);
}
static double image_mse(const elr_image *a, const elr_image *b) {
  double m = 0;
  int i;
  for (i = 0; i < a->width * a->height * 3; ++i) m += (a->rgb[i] - b->rgb[i]) * (a->rgb[i] - b->rgb[i]);
  return m / (a->width * a->height * 3);
}

static void compare(const char *map) {
  const char *portal = "\"point3 portal\" [ 2 1.2 0.4   2 2.2 0.4   2 2.2 -0.8   2 1.2 -0.8 ]";
  elr_scene *sp = load_room(map, portal, 3), *sn = load_room(map, "", 3);
  elr_image ref = {0, 0, NULL}, a, b;
  elr_stats st;
  double mp[4], mn[4], msep = 0, msen = 0, avgp = 0, avgn = 0, varp = 0, varn = 0;
  int k;
  if (!sp || !sn) { rt_check(0, "%s: scenes load", map); return; }
  rt_render(sp, 256, -1, -1, 2, 99, &ref, &st);
  for (k = 0; k < 4; ++k) {
    rt_render(sp, 16, -1, -1, 2, (uint64_t)(k + 1), &a, &st);
    rt_render(sn, 16, -1, -1, 2, (uint64_t)(k + 1), &b, &st);
    mp[k] = image_mean(&a); mn[k] = image_mean(&b);
    msep += image_mse(&a, &ref) / 4; msen += image_mse(&b, &ref) / 4;
    avgp += mp[k] / 4; avgn += mn[k] / 4;
    elr_image_free(&a); elr_image_free(&b);
  }
  for (k = 0; k < 4; ++k) { varp += (mp[k] - avgp) * (mp[k] - avgp) / 12; varn += (mn[k] - avgn) * (mn[k] - avgn) / 12; }
  printf("%s: image mean with portal %.5g (sd of the mean %.2g), without %.5g (sd %.2g), reference %.5g; pixel MSE %.4g vs %.4g\n", map, avgp,
         sqrt(varp), avgn, sqrt(varn), image_mean(&ref), msep, msen);
  rt_check(fabs(avgp - avgn) < 4 * sqrt(varp + varn) + 0.01 * avgp, "%s: portal and no-portal means agree within noise (%g, %g)", map, avgp, avgn);
  rt_check(msep < 0.5 * msen, "%s: the portal halves the pixel error at 16 spp at least (MSE %g vs %g)", map, msep, msen);
  rt_check(st.nlight_stats == 1 && st.light[0].env_portals == 0, "%s: the no-portal scene has no portal strategy", map);
  rt_render(sp, 4, -1, -1, 1, 1, &a, &st);
  rt_check(st.light[0].env_portals == 1 && st.light[0].env_portal_used > st.light[0].env_portal_fallback,
           "%s: --stats reports one portal and most light samples through it (%llu through, %llu by the map)", map,
           (unsigned long long)st.light[0].env_portal_used, (unsigned long long)st.light[0].env_portal_fallback);
  elr_image_free(&a);
  elr_image_free(&ref);
  elr_scene_free(sp);
  elr_scene_free(sn);
}

static void errors(void) {
  char text[4096], err[512];
  elr_scene *s;
  snprintf(text, sizeof text, "Camera \"perspective\"\nWorldBegin\nLightSource \"infinite\" \"string mapname\" \"%s/envmaps/city.hdr\" "
           "\"point3 portal\" [ 2 1.2 0.4   2 2.2 0.4   2 2.2 -0.8   2.5 1.2 -0.8 ]\nWorldEnd\n", EL_TEST_DATA_DIR);
  s = rt_load("bad1.pbrt", text, err, sizeof err);
  rt_check(!s && strstr(err, "portal 0: not a") && strstr(err, ":3"), "a non-rectangular portal is an error naming it: %s", s ? "(loaded)" : err);
  if (s) elr_scene_free(s);
  s = rt_load("bad2.pbrt", "Camera \"perspective\"\nWorldBegin\nLightSource \"infinite\" \"point3 portal\" [ 0 0 0  0 1 0  1 1 0  1 0 0 ]\nWorldEnd\n", err, sizeof err);
  rt_check(!s && strstr(err, "portals need an environment map"), "a portal on a constant light is an error: %s", s ? "(loaded)" : err);
  if (s) elr_scene_free(s);
  s = rt_load("bad3.pbrt", "Camera \"perspective\"\nWorldBegin\nLightSource \"infinite\" \"point3 portal\" [ 0 0 0  0 1 0  1 1 0 ]\nWorldEnd\n", err, sizeof err);
  rt_check(!s && strstr(err, "portal"), "three points are an error: %s", s ? "(loaded)" : err);
  if (s) elr_scene_free(s);
}

int main(void) {
  rt_mkdir("portal");
  compare("city.hdr");
  compare("overcast.pfm");
  errors();
  return rt_finish("test_render_portal");
}
