/* test_render_strategies: one scene, four ways of estimating direct light, one answer.
 *
 * Light sampling only, BSDF sampling only, MIS (power heuristic) of both, and MIS with envlight's
 * compensated distribution (pbrt-v4's: the density of max(L - mean, 0), which is only unbiased together
 * with BSDF sampling) are different estimators of the same integral, so their images converge to the
 * same mean. A missing or double-counted MIS weight, a pdf in the wrong measure, or a sampling density
 * that misses part of the map shows up as a different mean. The scene has a matte and a glossy plastic
 * sphere on a plane, under a 64 x 32 map with a sky gradient and a small bright sun (40x the sky),
 * rendered with directlighting and with path (maxdepth 3). Means are compared over the image and over
 * 4 x 4-pixel blocks (2% and 8%; the seed-to-seed spread of MIS itself is printed: about 0.3% and 3%).
 * A bias this test caught: skipping the BSDF sample where the light's pdf is 0 (pbrt-v3's EstimateDirect
 * does) loses 10% of the image with the compensated density. */
#include "render_test_util.h"

#define RES 16

static void make_map(void) {
  static float m[3 * 64 * 32];
  char err[256];
  int x, y;
  for (y = 0; y < 32; y++)
    for (x = 0; x < 64; x++) {
      float sky = 0.4f + 1.2f * (1.0f - y / 31.0f), sun = (abs(x - 20) <= 1 && abs(y - 9) <= 1) ? 40.f : 0.f;
      m[3 * (y * 64 + x)] = sky * 0.8f + sun;
      m[3 * (y * 64 + x) + 1] = sky * 0.9f + sun;
      m[3 * (y * 64 + x) + 2] = sky + sun * 0.8f;
    }
  if (el_image_write_pfm(rt_path("sky.pfm"), m, 64, 32, 3, err, sizeof err) != 0) printf("write: %s\n", err);
}

static const char *scene_text(const char *integ) {
  static char buf[2048];
  snprintf(buf, sizeof buf,
           "LookAt 0 1.5 -4  0 0.6 0  0 1 0\n"
           "Camera \"perspective\" \"float fov\" [ 45 ]\n"
           "Film \"image\" \"integer xresolution\" [ %d ] \"integer yresolution\" [ %d ]\n"
           "Sampler \"random\" \"integer pixelsamples\" [ 4 ]\n"
           "Integrator %s\n"
           "WorldBegin\n"
           "AttributeBegin\n  Rotate -90 1 0 0\n  LightSource \"infinite\" \"string mapname\" \"sky.pfm\"\nAttributeEnd\n"
           "AttributeBegin\n  Translate -0.7 0.6 0\n  Material \"matte\" \"rgb Kd\" [ 0.7 0.5 0.3 ]\n  Shape \"sphere\" \"float radius\" 0.6\nAttributeEnd\n"
           "AttributeBegin\n  Translate 0.7 0.6 0\n  Material \"plastic\" \"rgb Kd\" [ 0.2 0.3 0.5 ] \"rgb Ks\" [ 0.6 0.6 0.6 ] \"float roughness\" 0.15\n"
           "  Shape \"sphere\" \"float radius\" 0.6\nAttributeEnd\n"
           "Material \"matte\" \"rgb Kd\" [ 0.5 0.5 0.5 ]\n"
           "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point P\" [ -5 0 -5  5 0 -5  5 0 5  -5 0 5 ]\n"
           "WorldEnd\n", RES, RES, integ);
  return buf;
}

static void blocks(const elr_image *img, double *b /* 17: 16 blocks + mean */) {
  int x, y, c;
  memset(b, 0, sizeof(double) * 17);
  for (y = 0; y < RES; y++)
    for (x = 0; x < RES; x++)
      for (c = 0; c < 3; c++) { double v = img->rgb[3 * (y * RES + x) + c]; b[(y / 4) * 4 + x / 4] += v / 48.0; b[16] += v / (RES * RES * 3); }
}

static void run(const char *integ) {
  char err[512];
  elr_scene *s = rt_load("strat.pbrt", scene_text(integ), err, sizeof err);
  const char *names[5] = {"MIS", "light sampling only", "BSDF sampling only", "MIS + compensated distribution",
                          "light sampling only, pbrt-v3 importance map"};
  int spp[5] = {512, 512, 2048, 512, 512};
  double ref[17], res[5][17], spread = 0;
  int k, i;
  if (!s) { rt_check(0, "load: %s", err); return; }
  /* the seed-to-seed spread of MIS at this sample count: the scale of the tolerances */
  for (k = 0; k < 5; k++) {
    elr_image img;
    elr_stats st;
    elr_render_options o;
    elr_render_options_default(&o);
    o.spp = spp[k]; o.light_sampling = k == 3 ? 0 : (k == 4 ? 1 : k); o.compensated = k == 3 ? 1 : 0; o.importance = k == 4 ? 1 : 0;
    o.nthreads = 2; o.seed = (uint64_t)(11 + k); o.quiet = 1;
    if (elr_render(s, &o, &img, &st, err, sizeof err) != 0) { rt_check(0, "render %s", names[k]); elr_scene_free(s); return; }
    blocks(&img, res[k]);
    if (k == 0) {
      elr_image img2;
      elr_stats st2;
      double b2[17];
      if (rt_render(s, spp[k], 0, 0, 2, 99, &img2, &st2) == 0) {
        blocks(&img2, b2);
        for (i = 0; i < 16; i++) if (fabs(b2[i] - res[0][i]) / res[0][i] > spread) spread = fabs(b2[i] - res[0][i]) / res[0][i];
        printf("      %s: MIS seed-to-seed difference of the image mean %.2f%%\n", integ, 100 * fabs(b2[16] - res[0][16]) / res[0][16]);
        elr_image_free(&img2);
      }
      rt_check(st.distribution_built && st.shadow_rays > 0 && st.bsdf_light_rays + st.bounce_rays > 0,
               "%s/MIS: distribution built, %llu shadow rays", integ, (unsigned long long)st.shadow_rays);
    }
    if (k == 2) rt_check(!st.distribution_built && st.shadow_rays == 0, "%s/BSDF only: no distribution, no shadow rays", integ);
    elr_image_free(&img);
  }
  memcpy(ref, res[0], sizeof ref);
  printf("      %s: MIS seed-to-seed spread of block means %.2f%%\n", integ, 100 * spread);
  for (k = 1; k < 5; k++) {
    double worst = 0, dm = fabs(res[k][16] - ref[16]) / ref[16];
    for (i = 0; i < 16; i++) if (fabs(res[k][i] - ref[i]) / ref[i] > worst) worst = fabs(res[k][i] - ref[i]) / ref[i];
    rt_check(dm < 0.02, "%s: %s image mean %.4f vs MIS %.4f (%.2f%%, tolerance 2%%)", integ, names[k], res[k][16], ref[16], 100 * dm);
    rt_check(worst < 0.08, "%s: %s 4x4-block means within 8%% of MIS (worst %.2f%%)", integ, names[k], 100 * worst);
  }
  elr_scene_free(s);
}

/* The same image for the same seed whatever the thread count (per-pixel random streams, tiles merged
 * in tile order), for every sampler; a different seed gives a different image. */
static void determinism(void) {
  char err[512];
  elr_scene *s = rt_load("det.pbrt", scene_text("\"path\" \"integer maxdepth\" [ 3 ]"), err, sizeof err);
  const char *names[3] = {"random", "stratified", "halton"};
  int k;
  if (!s) { rt_check(0, "load: %s", err); return; }
  for (k = 0; k < 3; k++) {
    elr_render_options o;
    elr_image a, b, c;
    elr_stats st;
    int same, differ;
    elr_render_options_default(&o);
    o.spp = 8; o.quiet = 1; o.sampler = k + 1; o.seed = 5; o.tile_size = 4;
    o.nthreads = 1;
    if (elr_render(s, &o, &a, &st, err, sizeof err) != 0) { rt_check(0, "render: %s", err); continue; }
    o.nthreads = 3;
    if (elr_render(s, &o, &b, &st, err, sizeof err) != 0) { rt_check(0, "render: %s", err); elr_image_free(&a); continue; }
    o.seed = 6;
    if (elr_render(s, &o, &c, &st, err, sizeof err) != 0) { rt_check(0, "render: %s", err); elr_image_free(&a); elr_image_free(&b); continue; }
    same = !memcmp(a.rgb, b.rgb, sizeof(float) * 3 * RES * RES);
    differ = memcmp(a.rgb, c.rgb, sizeof(float) * 3 * RES * RES) != 0;
    rt_check(same && differ, "%s: 1 and 3 threads give bit-identical images; another seed a different one", names[k]);
    elr_image_free(&a); elr_image_free(&b); elr_image_free(&c);
  }
  elr_scene_free(s);
}

int main(void) {
  rt_mkdir("test_render_strategies");
  make_map();
  run("\"directlighting\"");
  run("\"path\" \"integer maxdepth\" [ 3 ]");
  determinism();
  return rt_finish("test_render_strategies");
}
