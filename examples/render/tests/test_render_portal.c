/* test_render_portal.c: pbrt-v4's "point3 portal" on the infinite light (issue 23). A room lit through
 * one window by the CC0 city map (its sun shines in) and by a generated overcast sky: the image with the
 * portal agrees with the image without it within noise (unbiased: the means of the lit floor and of
 * the whole image, over 4 seeds each), and its pixels' error against a high-spp reference is smaller;
 * (path, and direct lighting on city); --stats reports the strategy; the wave loop samples the portals as the reference loop (bit for bit with
 * halton, within noise with a pixel sampler); --compensated rebuilds the portal's tables compensated; a
 * portal that is not a rectangle, or on a light without a map, is an error naming the problem. Small
 * images, a few seconds. */
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

static const char *g_integrator = "path", *g_sampler = "halton";
static elr_scene *load_room(const char *map, const char *portal, int depth) {
  char text[8192], err[512];
  elr_scene *s;
  snprintf(text, sizeof text,
           "LookAt -1.8 1.5 1.8   1 0.5 -0.8   0 1 0\nCamera \"perspective\" \"float fov\" [ 62 ]\n"
           "Film \"image\" \"integer xresolution\" [ 40 ] \"integer yresolution\" [ 30 ]\n"
           "Sampler \"%s\" \"integer pixelsamples\" [ 16 ]\nIntegrator \"%s\" \"integer maxdepth\" [ %d ]\nWorldBegin\n"
           "AttributeBegin\n Rotate -90 1 0 0\n Rotate 120 0 0 1\n LightSource \"infinite\" \"string mapname\" \"%s/envmaps/%s\" %s\nAttributeEnd\n%s",
           g_sampler, g_integrator, depth, EL_TEST_DATA_DIR, map, portal, ROOM);
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

static int render_loop(elr_scene *s, int loop, int comp, uint64_t seed, elr_image *img, elr_stats *st) {
  elr_render_options o;
  char err[512];
  elr_render_options_default(&o);
  o.spp = 16; o.nthreads = 2; o.seed = seed; o.quiet = 1; o.loop = loop; o.compensated = comp;
  if (elr_render(s, &o, img, st, err, sizeof err) != 0) { printf("render failed: %s\n", err); return -1; }
  return 0;
}

/* The wave loop (render_wave.c) samples the portals at each vertex as the reference loop does: with an
 * order-free sampler (halton) the two images are the same bit for bit; with a pixel sampler forced into
 * the wave loop (stratified: other numbers of the same distribution) the mean of the per-pixel
 * difference over 4 seeds is within 4 standard errors of 0 (the standard error from the differences'
 * own spread over the pixels: a false alarm has probability about 6e-5). Path (depth 3) and direct
 * lighting. The default loop for a portal scene is the wave loop, and --stats counts its samples. */
static void loops(const char *map, const char *integrator) {
  const char *portal = "\"point3 portal\" [ 2 1.2 0.4   2 2.2 0.4   2 2.2 -0.8   2 1.2 -0.8 ]";
  elr_scene *s;
  elr_image a, b;
  elr_stats sa, sb;
  int i, k, n, same = 1;
  double sum = 0, sum2 = 0;
  g_integrator = integrator;
  s = load_room(map, portal, 3);
  if (!s) { rt_check(0, "%s %s: scene loads", map, integrator); g_integrator = "path"; return; }
  if (render_loop(s, -1, -1, 1, &a, &sa) || render_loop(s, ELR_LOOP_ONE, -1, 1, &b, &sb)) { rt_check(0, "renders"); elr_scene_free(s); return; }
  rt_check(sa.loop == ELR_LOOP_WAVE && sb.loop == ELR_LOOP_ONE, "%s %s: a portal scene runs the wave loop by default (loop %d)", map, integrator, sa.loop);
  for (i = 0; i < a.width * a.height * 3; ++i) same &= a.rgb[i] == b.rgb[i];
  rt_check(same, "%s %s, halton: the wave loop's image is the reference loop's, bit for bit", map, integrator);
  rt_check(sa.light[0].env_portal_used == sb.light[0].env_portal_used && sa.light[0].env_portal_fallback == sb.light[0].env_portal_fallback &&
               sa.light[0].env_portal_used > 0,
           "%s %s: both loops count the same portal samples (%llu, %llu through the portal)", map, integrator,
           (unsigned long long)sa.light[0].env_portal_used, (unsigned long long)sb.light[0].env_portal_used);
  elr_image_free(&a); elr_image_free(&b);
  elr_scene_free(s);
  g_sampler = "stratified";
  s = load_room(map, portal, 3);
  g_sampler = "halton";
  if (!s) { rt_check(0, "%s %s stratified: scene loads", map, integrator); g_integrator = "path"; return; }
  n = 0;
  for (k = 0; k < 4; ++k) {
    if (render_loop(s, ELR_LOOP_WAVE, -1, (uint64_t)k + 7, &a, &sa) || render_loop(s, ELR_LOOP_ONE, -1, (uint64_t)k + 7, &b, &sb)) break;
    for (i = 0; i < a.width * a.height; ++i) {
      double la = 0.2126 * a.rgb[3 * i] + 0.7152 * a.rgb[3 * i + 1] + 0.0722 * a.rgb[3 * i + 2];
      double lb = 0.2126 * b.rgb[3 * i] + 0.7152 * b.rgb[3 * i + 1] + 0.0722 * b.rgb[3 * i + 2];
      sum += la - lb; sum2 += (la - lb) * (la - lb); n++;
    }
    elr_image_free(&a); elr_image_free(&b);
  }
  {
    double m = n ? sum / n : 0, se = n > 1 ? sqrt((sum2 / n - m * m) / (n - 1)) : 1;
    rt_check(n == 4 * 40 * 30 && sa.loop == ELR_LOOP_WAVE && fabs(m) <= 4 * se, /* (direct lighting: the same image, 0 and 0) */
             "%s %s, stratified in the wave loop: mean per-pixel difference %.3g, %.2f standard errors from 0", map, integrator, m, se > 0 ? m / se : 0);
  }
  elr_scene_free(s);
  g_integrator = "path";
}

/* --compensated 1 (elr_render_options.compensated) rebuilds the portal's tables compensated, and 0 back
 * without; the compensated portal (with MIS) stays unbiased: its image mean agrees with the plain
 * portal's within noise (4 seeds each) */
static void compensated(const char *map) {
  const char *portal = "\"point3 portal\" [ 2 1.2 0.4   2 2.2 0.4   2 2.2 -0.8   2 1.2 -0.8 ]";
  elr_scene *s = load_room(map, portal, 3);
  elr_image a;
  elr_stats st;
  double m[2][4], avg[2] = {0, 0}, var[2] = {0, 0};
  int c, k, ok = 1;
  if (!s) { rt_check(0, "%s: scene loads", map); return; }
  rt_check(!s->light[0].portal->compensated, "%s: the scene's portal is not compensated", map);
  for (c = 1; c >= 0; --c)
    for (k = 0; k < 4; ++k) {
      if (render_loop(s, -1, c, (uint64_t)k + 21, &a, &st)) { ok = 0; break; }
      ok &= st.light[0].env_portal_compensated == c && s->light[0].portal->compensated == c;
      m[c][k] = image_mean(&a); avg[c] += m[c][k] / 4;
      elr_image_free(&a);
    }
  rt_check(ok, "%s: --compensated 1 builds the portal compensated (--stats says so), --compensated 0 plain again", map);
  for (c = 0; c < 2; ++c)
    for (k = 0; k < 4; ++k) var[c] += (m[c][k] - avg[c]) * (m[c][k] - avg[c]) / 12;
  rt_check(fabs(avg[1] - avg[0]) < 4 * sqrt(var[0] + var[1]) + 0.005 * avg[0], "%s: compensated portal mean %.5g (sd %.2g), plain %.5g (sd %.2g)", map,
           avg[1], sqrt(var[1]), avg[0], sqrt(var[0]));
  elr_scene_free(s);
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
  g_integrator = "directlighting"; /* (the direct-lighting integrator: its wave loop's first vertex too) */
  compare("city.hdr");
  g_integrator = "path";
  loops("city.hdr", "path");
  loops("city.hdr", "directlighting");
  compensated("city.hdr");
  compensated("overcast.pfm");
  errors();
  return rt_finish("test_render_portal");
}
