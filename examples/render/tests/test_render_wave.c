/* test_render_wave: the wave loop (render_wave.c) against the one-sample-at-a-time reference (render.c
 * with integrator_direct.c and integrator_path.c).
 *  1. Bit for bit, with the same ray counts, where the sampler gives the same numbers in any order:
 *     direct lighting and path, each of the wave loop's four ways of calling Embree (rtcIntersect1,
 *     packets of 16, rtcIntersect1M, rtcIntersectNp), samplers random / halton / zsobol / sobol /
 *     stratified (direct lighting), a light's "samples" 3, strategy "one", light sampling only, BSDF
 *     sampling only, a textured plane (ray differentials), a mirror and a glass sphere (specular
 *     bounces), 1 spp (a wave of 256 pixels over several rows and tiles), 300 and 289 spp (a pixel in two
 *     waves), an image whose tiles are not whole (20 x 18 pixels).
 *  2. The same image for 1 and 3 threads.
 *  3. The path tracer with the stratified sampler, forced into the wave loop: draws past the sampler's
 *     dimensions come in another order, so the images differ; the mean of the per-pixel difference
 *     (luminance) must be within 4 standard errors of 0 (the standard error from the pixels' own
 *     spread: a false alarm has probability about 6e-5).
 *  4. The render chose the wave loop (elr_stats.loop) where it should, and not where it should not (BSDF
 *     sampling only samples no light: the cases of 1. with it run the reference loop).
 *  5. Bit for bit on spheres alone with constant materials: the BSDFs the wave loop copies from one made
 *     per render (matte, Oren-Nayar, plastic, glass) and those it does not (anisotropic metal, substrate).
 *  6. Bit for bit, with the same ray and strategy counts, on matte surfaces alone (the waves whose first
 *     vertices render_wave.c shades in structure-of-arrays form, elr__soa_*; and the path tracer on
 *     them) under a sun map: each way
 *     diffuse vertices take it (the map alone with MIS, the product with MIS, the sun test choosing
 *     per vertex, the product light sample alone), the map alone for every vertex, and a smooth map
 *     (the product light sample alone); a matte of Kd 0 in one channel, a light of 2 samples (not shaded
 *     there) and halton; --env-sun-diffuse two and twopixel (two product light samples where the BSDF sample
 *     was; twopixel's choice per pixel, its two rays counted), with a mirror (later vertices in the reference
 *     integrator with the pixel's choice) and a light of 2 samples.
 *  7. --sun split (a spot, a sky and the BSDF sample, three-way MIS) bit for bit, with the same ray, strategy and
 *     split-vertex counts, directlighting and path, light sampling alone too: zsobol, random, halton, a mirror, a
 *     light of 2 samples, on 6.'s one-texel sun and on a sun in a halo and a bright sky (where light samples meet the
 *     other light technique's density: a one-ulp change to the wave's weight of those samples fails cases 5, 6, 9
 *     and 10; to the path wave's escaped-ray split pdf, cases 7 to 10).
 *  9. le_same (issue 21: an escaped BSDF ray's product pdf and radiance in one el_envlight_pdf_li_cos_le_n call) bit for
 *     bit, on and off (env_alt under a general rotation: its matrix bits differ), direct lighting and path, sun and smooth
 *     maps, --compensated (a 1.0001 factor on the joint call's radiance in the SoA or the path stage fails it). */
#include "render_test_util.h"

static elr_scene *load(const char *sampler, const char *integrator, const char *lightparams, int w, int h, char *err) {
  static char buf[8192];
  snprintf(buf, sizeof buf,
           "LookAt 0 1 -4  0 0.5 0  0 1 0\nCamera \"perspective\" \"float fov\" 45\n"
           "Film \"image\" \"integer xresolution\" %d \"integer yresolution\" %d\n%s\n%s\n"
           "WorldBegin\nLightSource \"infinite\" \"string mapname\" \"env.pfm\" \"float scale\" 2%s\n"
           "Texture \"chk\" \"spectrum\" \"checkerboard\" \"float uscale\" 8 \"float vscale\" 8\n"
           "AttributeBegin\nMaterial \"plastic\" \"texture Kd\" \"chk\" \"float roughness\" 0.05\n"
           "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point P\" [ -5 0 -5  5 0 -5  5 0 5  -5 0 5 ]\n"
           "  \"float uv\" [ 0 0 1 0 1 1 0 1 ]\nAttributeEnd\n"
           "AttributeBegin\nMaterial \"matte\" \"rgb Kd\" [ 0.7 0.5 0.3 ]\nTranslate -0.6 0.5 0\nShape \"sphere\" \"float radius\" 0.5\nAttributeEnd\n"
           "AttributeBegin\nMaterial \"mirror\"\nTranslate 0.7 0.5 0.3\nShape \"sphere\" \"float radius\" 0.4\nAttributeEnd\n"
           "AttributeBegin\nMaterial \"glass\"\nTranslate 0.1 0.3 -1\nShape \"sphere\" \"float radius\" 0.3\nAttributeEnd\n"
           "AttributeBegin\nMaterial \"metal\" \"float roughness\" 0.2\nTranslate -0.2 1.3 0.8\nShape \"sphere\" \"float radius\" 0.35\nAttributeEnd\n"
           "WorldEnd\n",
           w, h, sampler, integrator, lightparams);
  return rt_load("wave.pbrt", buf, err, 512);
}

/* issue 20's per-lobe thresholds for the render below (-1: the defaults) */
static float lobe_alpha = -1.f, light_alpha = -1.f;
static int sun_diffuse = -1; /* (ELR_ENVSD_*; -1 the default) */
static int sun_mode = -1;    /* (render --sun: 2 split; -1 the default) */
static int render(elr_scene *s, int loop, int api, int ls, int nthreads, int spp, elr_image *img, elr_stats *st, char *err) {
  elr_render_options o;
  elr_render_options_default(&o);
  o.nthreads = nthreads; o.seed = 11; o.quiet = 1; o.loop = loop; o.wave_api = api; o.light_sampling = ls; o.spp = spp;
  o.env_lobe_alpha = lobe_alpha; o.env_light_alpha = light_alpha; o.env_sun_diffuse = sun_diffuse; o.env_sun = sun_mode;
  return elr_render(s, &o, img, st, err, 512);
}

/* 6. and 7.'s scene: two matte spheres on a matte plane under map (sun.pfm or env.pfm), a mirror sphere in front
 * of them if mirror */
static elr_scene *load_matte(const char *sampler, int path, const char *map, const char *light, int mirror, char *err) {
  static char buf[4096];
  snprintf(buf, sizeof buf,
           "LookAt 0 1.5 -4  0 0.5 0  0 1 0\nCamera \"perspective\" \"float fov\" 45\n"
           "Film \"image\" \"integer xresolution\" 24 \"integer yresolution\" 18\n%s\nIntegrator %s\n"
           "WorldBegin\nAttributeBegin\nRotate -90 1 0 0\nLightSource \"infinite\" \"string mapname\" \"%s\"%s\nAttributeEnd\n"
           "AttributeBegin\nMaterial \"matte\" \"rgb Kd\" [ 0.7 0.5 0 ]\nTranslate -0.6 0.5 0\nShape \"sphere\" \"float radius\" 0.5\nAttributeEnd\n"
           "AttributeBegin\nMaterial \"matte\" \"rgb Kd\" [ 0.2 0.6 0.3 ]\nTranslate 0.6 0.7 0.4\nShape \"sphere\" \"float radius\" 0.6\nAttributeEnd\n"
           "AttributeBegin\nMaterial \"matte\" \"rgb Kd\" [ 0.4 0.4 0.4 ]\n"
           "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point P\" [ -5 0 -5  5 0 -5  5 0 5  -5 0 5 ]\nAttributeEnd\n%s\nWorldEnd\n",
           sampler, path ? "\"path\" \"integer maxdepth\" 5" : "\"directlighting\"", map, light,
           mirror ? "AttributeBegin\nMaterial \"mirror\"\nTranslate 0 0.4 -1.2\nShape \"sphere\" \"float radius\" 0.35\nAttributeEnd" : "");
  return rt_load("wave_soa.pbrt", buf, err, 512);
}

int main(void) {
  char err[512];
  rt_mkdir("test_render_wave");
  {
    float env[3 * 32 * 16];
    int i;
    for (i = 0; i < 3 * 32 * 16; i++) env[i] = 0.2f + (float)((i * 7) % 11) * (i % 3 == 0 ? 3.f : 1.f);
    el_image_write_pfm(rt_path("env.pfm"), env, 32, 16, 3, err, sizeof err);
  }
  /* 1. and 2. bit for bit */
  {
    static const struct { const char *sampler, *integrator, *light; int ls, spp, w, h; } cases[] = {
      {"Sampler \"stratified\" \"integer xsamples\" 4 \"integer ysamples\" 4", "Integrator \"directlighting\"", "", -1, 0, 20, 18},
      {"Sampler \"zsobol\" \"integer pixelsamples\" 16", "Integrator \"directlighting\"", " \"integer samples\" 3", -1, 0, 20, 18},
      {"Sampler \"halton\" \"integer pixelsamples\" 7", "Integrator \"directlighting\" \"string strategy\" \"one\"", "", -1, 0, 20, 18},
      {"Sampler \"random\" \"integer pixelsamples\" 4", "Integrator \"directlighting\"", "", ELR_LS_LIGHT, 0, 20, 18},
      {"Sampler \"random\" \"integer pixelsamples\" 4", "Integrator \"directlighting\"", "", ELR_LS_BSDF, 0, 20, 18},
      {"Sampler \"random\" \"integer pixelsamples\" 1", "Integrator \"directlighting\"", "", -1, 0, 40, 36},
      {"Sampler \"halton\" \"integer pixelsamples\" 300", "Integrator \"directlighting\"", "", -1, 0, 6, 5},
      {"Sampler \"stratified\" \"integer xsamples\" 17 \"integer ysamples\" 17", "Integrator \"directlighting\"", "", -1, 0, 6, 5},
      {"Sampler \"zsobol\" \"integer pixelsamples\" 8", "Integrator \"path\" \"integer maxdepth\" 6", "", -1, 0, 20, 18},
      {"Sampler \"random\" \"integer pixelsamples\" 5", "Integrator \"path\" \"integer maxdepth\" 8", "", -1, 0, 20, 18},
      {"Sampler \"halton\" \"integer pixelsamples\" 3", "Integrator \"path\" \"integer maxdepth\" 5", "", ELR_LS_LIGHT, 0, 20, 18},
      {"Sampler \"sobol\" \"integer pixelsamples\" 4", "Integrator \"path\" \"integer maxdepth\" 5", "", ELR_LS_BSDF, 0, 20, 18},
      {"Sampler \"random\" \"integer pixelsamples\" 1", "Integrator \"path\" \"integer maxdepth\" 5", "", -1, 0, 40, 36},
      {"Sampler \"zsobol\" \"integer pixelsamples\" 512", "Integrator \"path\" \"integer maxdepth\" 3", "", -1, 0, 4, 3},
      /* the cases above sample the product of the map and the cosine (the default); the map alone: */
      {"Sampler \"zsobol\" \"integer pixelsamples\" 16", "Integrator \"directlighting\"", " \"integer samples\" 2 \"string sampling\" \"map\"", -1, 0, 20, 18},
      {"Sampler \"random\" \"integer pixelsamples\" 5", "Integrator \"path\" \"integer maxdepth\" 8", " \"string sampling\" \"map\"", -1, 0, 20, 18},
      /* issue 20's per-lobe choice with all three strategies in one image (the defaults put the plastic, alpha
       * 0.31, the metal, 0.68, and the matte surfaces all at the product light sample alone): thresholds
       * 0.7 and 1 send the metal to product MIS around the mirror direction (no sun here), the plastic to
       * product MIS around the normal, the mattes to the product light sample alone (MIX_FIRST on; the map
       * alone: the two cases above) */
      {"Sampler \"stratified\" \"integer xsamples\" 4 \"integer ysamples\" 4", "Integrator \"directlighting\"", "", -1, 0, 20, 18},
      {"Sampler \"zsobol\" \"integer pixelsamples\" 16", "Integrator \"directlighting\"", " \"integer samples\" 3", -1, 0, 20, 18},
      {"Sampler \"random\" \"integer pixelsamples\" 5", "Integrator \"path\" \"integer maxdepth\" 8", "", -1, 0, 20, 18},
    };
    const int MIX_FIRST = (int)(sizeof cases / sizeof cases[0]) - 3;
    int c, api;
    for (c = 0; c < (int)(sizeof cases / sizeof cases[0]); c++) {
      elr_scene *s = load(cases[c].sampler, cases[c].integrator, cases[c].light, cases[c].w, cases[c].h, err);
      elr_image ref;
      elr_stats sr;
      lobe_alpha = c >= MIX_FIRST ? 0.7f : -1.f; light_alpha = c >= MIX_FIRST ? 1.f : -1.f;
      if (!s) { rt_check(0, "case %d: %s", c, err); continue; }
      if (render(s, ELR_LOOP_ONE, -1, cases[c].ls, 2, cases[c].spp, &ref, &sr, err) != 0) { rt_check(0, "case %d: %s", c, err); elr_scene_free(s); continue; }
      for (api = ELR_WAVE_API_SINGLE; api <= ELR_WAVE_API_SOA; api++) {
        elr_image img;
        elr_stats st;
        int nthreads = api == ELR_WAVE_API_PACKET16 ? 3 : 1; /* the same image for any thread count */
        if (render(s, ELR_LOOP_WAVE, api, cases[c].ls, nthreads, cases[c].spp, &img, &st, err) != 0) { rt_check(0, "case %d api %d: %s", c, api, err); continue; }
        {
          size_t n = (size_t)img.width * img.height * 3, k, diff = 0;
          double m = 0;
          for (k = 0; k < n; k++) { diff += memcmp(&img.rgb[k], &ref.rgb[k], sizeof(float)) != 0; m += img.rgb[k]; }
          rt_check(st.loop == (cases[c].ls == ELR_LS_BSDF ? ELR_LOOP_ONE : ELR_LOOP_WAVE) && sr.loop == ELR_LOOP_ONE && diff == 0 && m > 0 && st.shadow_rays == sr.shadow_rays &&
                       st.bounce_rays == sr.bounce_rays && st.bsdf_light_rays == sr.bsdf_light_rays && st.camera_rays == sr.camera_rays &&
                   st.env_product_samples == sr.env_product_samples && st.env_map_samples == sr.env_map_samples &&
                   st.env_light_only_samples == sr.env_light_only_samples &&
                   (c < MIX_FIRST || c == MIX_FIRST + 2 || (sr.env_light_only_samples > 0 && sr.env_product_samples > sr.env_light_only_samples)),
                   "case %d (%s, %s), wave api %d, %d thread%s: %zu of %zu values differ from the reference; rays camera %llu/%llu, "
                   "bounce %llu/%llu, shadow %llu/%llu, bsdf %llu/%llu",
                   c, cases[c].sampler, cases[c].integrator, api, nthreads, nthreads > 1 ? "s" : "", diff, n,
                   (unsigned long long)st.camera_rays, (unsigned long long)sr.camera_rays, (unsigned long long)st.bounce_rays,
                   (unsigned long long)sr.bounce_rays, (unsigned long long)st.shadow_rays, (unsigned long long)sr.shadow_rays,
                   (unsigned long long)st.bsdf_light_rays, (unsigned long long)sr.bsdf_light_rays);
          elr_image_free(&img);
        }
      }
      elr_image_free(&ref);
      elr_scene_free(s);
    }
  }
  /* 3. the path tracer, stratified, forced into the wave loop: the same mean */
  {
    elr_scene *s = load("Sampler \"stratified\" \"integer xsamples\" 2 \"integer ysamples\" 2", "Integrator \"path\" \"integer maxdepth\" 5", "",
                        48, 40, err);
    elr_image a, b;
    elr_stats sa, sb;
    if (s && render(s, ELR_LOOP_ONE, -1, -1, 2, 0, &a, &sa, err) == 0 && render(s, ELR_LOOP_WAVE, -1, -1, 2, 0, &b, &sb, err) == 0) {
      int k, n = a.width * a.height, same = 1;
      double sum = 0, sum2 = 0, mean, se, z;
      for (k = 0; k < n; k++) {
        double ya = 0.2126 * a.rgb[3 * k] + 0.7152 * a.rgb[3 * k + 1] + 0.0722 * a.rgb[3 * k + 2];
        double yb = 0.2126 * b.rgb[3 * k] + 0.7152 * b.rgb[3 * k + 1] + 0.0722 * b.rgb[3 * k + 2];
        sum += yb - ya; sum2 += (yb - ya) * (yb - ya);
        if (ya != yb) same = 0;
      }
      mean = sum / n;
      se = sqrt((sum2 / n - mean * mean) / (n - 1));
      z = se > 0 ? mean / se : 0;
      rt_check(!same && sb.loop == ELR_LOOP_WAVE && fabs(z) < 4.0,
               "path + stratified in the wave loop: other numbers past the sampler's dimensions (images %s), the same mean: "
               "mean difference %.3g, standard error %.3g, z = %.2f (|z| < 4)", same ? "EQUAL" : "differ", mean, se, z);
      elr_image_free(&a); elr_image_free(&b);
    } else rt_check(0, "stratified path scene: %s", err);
    elr_scene_free(s);
  }
  /* 4. which loop runs by default */
  {
    static const struct { const char *sampler, *integrator; int loop; } cases[] = {
      {"Sampler \"stratified\" \"integer xsamples\" 2 \"integer ysamples\" 2", "Integrator \"directlighting\"", ELR_LOOP_WAVE},
      {"Sampler \"zsobol\" \"integer pixelsamples\" 4", "Integrator \"path\"", ELR_LOOP_WAVE},
      /* a pixel sampler's path tracer: the reference loop with product sampling (it keeps the reference's
       * image), the wave loop for the map alone (where the batched loop ran, before the wave loop replaced it) */
      {"Sampler \"stratified\" \"integer xsamples\" 2 \"integer ysamples\" 2", "Integrator \"path\"", ELR_LOOP_ONE},
      {"Sampler \"stratified\" \"integer xsamples\" 2 \"integer ysamples\" 2", "Integrator \"path\"", ELR_LOOP_WAVE},
    };
    int c;
    for (c = 0; c < 4; c++) {
      elr_scene *s = load(cases[c].sampler, cases[c].integrator, c == 3 ? " \"string sampling\" \"map\"" : "", 8, 8, err);
      elr_image img;
      elr_stats st;
      if (s && render(s, -1, -1, -1, 1, 0, &img, &st, err) == 0) {
        rt_check(st.loop == cases[c].loop, "default loop for %s, %s: %d (expected %d)", cases[c].sampler, cases[c].integrator, st.loop, cases[c].loop);
        elr_image_free(&img);
      } else rt_check(0, "default loop case %d: %s", c, err);
      elr_scene_free(s);
    }
  }
  /* 5. materials whose BSDF the wave loop copies from one made per render (elr_bsdf_constant: constant
   * textures) and those it does not (anisotropic lobes, whose frame follows the hit), in a scene of
   * spheres alone (no mesh for a made-up hit to look up): bit for bit against the reference */
  {
    static const char *integ[2] = {"Integrator \"directlighting\"", "Integrator \"path\" \"integer maxdepth\" 5"};
    int c;
    for (c = 0; c < 2; c++) {
      static char buf[4096];
      elr_scene *s;
      elr_image ref, img;
      elr_stats sr, st;
      snprintf(buf, sizeof buf,
               "LookAt 0 1 -4  0 0.5 0  0 1 0\nCamera \"perspective\" \"float fov\" 45\n"
               "Film \"image\" \"integer xresolution\" 24 \"integer yresolution\" 16\nSampler \"zsobol\" \"integer pixelsamples\" 8\n%s\n"
               "WorldBegin\nLightSource \"infinite\" \"string mapname\" \"env.pfm\"\n"
               "AttributeBegin\nMaterial \"metal\" \"float uroughness\" 0.05 \"float vroughness\" 0.3\nTranslate -0.9 0.5 0\nShape \"sphere\" \"float radius\" 0.45\nAttributeEnd\n"
               "AttributeBegin\nMaterial \"substrate\" \"float uroughness\" 0.1 \"float vroughness\" 0.4\nTranslate 0 0.5 0\nShape \"sphere\" \"float radius\" 0.45\nAttributeEnd\n"
               "AttributeBegin\nMaterial \"matte\" \"float sigma\" 20\nTranslate 0.9 0.5 0\nShape \"sphere\" \"float radius\" 0.45\nAttributeEnd\n"
               "AttributeBegin\nMaterial \"plastic\" \"float roughness\" 0.2\nTranslate -0.5 1.3 0.5\nShape \"sphere\" \"float radius\" 0.4\nAttributeEnd\n"
               "AttributeBegin\nMaterial \"glass\"\nTranslate 0.5 1.3 0.5\nShape \"sphere\" \"float radius\" 0.4\nAttributeEnd\n"
               "AttributeBegin\nMaterial \"matte\"\nTranslate 0 -100 0\nShape \"sphere\" \"float radius\" 100\nAttributeEnd\nWorldEnd\n",
               integ[c]);
      s = rt_load("wave_const.pbrt", buf, err, 512);
      if (!s) { rt_check(0, "constant-BSDF scene: %s", err); continue; }
      if (render(s, ELR_LOOP_ONE, -1, -1, 1, 0, &ref, &sr, err) == 0 && render(s, ELR_LOOP_WAVE, -1, -1, 2, 0, &img, &st, err) == 0) {
        size_t n = (size_t)img.width * img.height * 3, k, diff = 0;
        for (k = 0; k < n; k++) diff += memcmp(&img.rgb[k], &ref.rgb[k], sizeof(float)) != 0;
        rt_check(st.loop == ELR_LOOP_WAVE && diff == 0, "constant BSDFs, %s: %zu of %zu values differ from the reference", integ[c], diff, n);
        elr_image_free(&img); elr_image_free(&ref);
      } else rt_check(0, "constant-BSDF scene, %s: %s", integ[c], err);
      elr_scene_free(s);
    }
  }
  /* 6. matte alone (structure-of-arrays shading) under a sun map and a smooth one */
  {
    /* (expected: light samples of the product alone, of the map alone (with product sampling on), of product MIS) */
    static const struct { const char *sampler, *light; int sun, sd; float light_alpha; int alone, map, mis, path, mirror; } cases[] = {
      {"Sampler \"zsobol\" \"integer pixelsamples\" 8", "", 1, ELR_ENVSD_PRODUCT, -1.f, 0, 0, 1, 0, 0},
      {"Sampler \"stratified\" \"integer xsamples\" 3 \"integer ysamples\" 3", "", 1, ELR_ENVSD_MAP, -1.f, 0, 1, 0, 0, 0},
      {"Sampler \"zsobol\" \"integer pixelsamples\" 8", "", 1, ELR_ENVSD_SUNCOS, -1.f, 0, 1, 1, 0, 0},
      {"Sampler \"halton\" \"integer pixelsamples\" 5", "", 1, ELR_ENVSD_ALONE, -1.f, 1, 0, 0, 0, 0},
      {"Sampler \"zsobol\" \"integer pixelsamples\" 8", " \"string sampling\" \"map\"", 1, -1, -1.f, 0, 0, 0, 0, 0},
      {"Sampler \"zsobol\" \"integer pixelsamples\" 8", " \"integer samples\" 2", 1, -1, -1.f, 0, 0, 1, 0, 0},
      {"Sampler \"zsobol\" \"integer pixelsamples\" 8", "", 0, -1, -1.f, 1, 0, 0, 0, 0},
      {"Sampler \"random\" \"integer pixelsamples\" 4", "", 0, -1, INFINITY, 0, 0, 1, 0, 0},
      /* --env-sun-diffuse two and twopixel (two product light samples, no BSDF sample; per pixel: some pixels
       * product MIS), with a mirror sphere (the matte seen in it shaded by elr_direct_first with the
       * pixel's choice) and a light of 2 samples (no structure-of-arrays lanes) */
      {"Sampler \"zsobol\" \"integer pixelsamples\" 8", "", 1, ELR_ENVSD_TWO, -1.f, 1, 0, 0, 0, 0},
      {"Sampler \"zsobol\" \"integer pixelsamples\" 8", "", 1, ELR_ENVSD_TWO_PIXEL, -1.f, 1, 0, 1, 0, 0},
      {"Sampler \"random\" \"integer pixelsamples\" 4", "", 1, ELR_ENVSD_TWO_PIXEL, -1.f, 1, 0, 1, 0, 1},
      {"Sampler \"halton\" \"integer pixelsamples\" 5", " \"integer samples\" 2", 1, ELR_ENVSD_TWO, -1.f, 1, 0, 0, 0, 1},
      {"Sampler \"zsobol\" \"integer pixelsamples\" 8", " \"integer samples\" 2", 1, ELR_ENVSD_TWO_PIXEL, -1.f, 1, 0, 1, 0, 1},
      /* the path tracer (never the light sample alone) */
      {"Sampler \"zsobol\" \"integer pixelsamples\" 8", "", 1, ELR_ENVSD_PRODUCT, -1.f, 0, 0, 1, 1, 0},
      {"Sampler \"zsobol\" \"integer pixelsamples\" 4", "", 1, ELR_ENVSD_SUNCOS, -1.f, 0, 1, 1, 1, 0},
      {"Sampler \"random\" \"integer pixelsamples\" 4", " \"string sampling\" \"map\"", 0, -1, -1.f, 0, 0, 0, 1, 0},
      {"Sampler \"zsobol\" \"integer pixelsamples\" 8", "", 0, -1, -1.f, 0, 0, 1, 1, 0},
    };
    /* (a sun: one texel of a 512 x 256 map, where the sun test's share, ELR_ENV_SUN_AREA of the sphere, is a texel) */
    static float env[3 * 512 * 256];
    int c, i;
    for (i = 0; i < 512 * 256; i++) env[3 * i] = env[3 * i + 1] = env[3 * i + 2] = 0.3f + 0.05f * (float)(i % 7);
    env[3 * (60 * 512 + 90)] = env[3 * (60 * 512 + 90) + 1] = 2e5f; env[3 * (60 * 512 + 90) + 2] = 1.5e5f;
    el_image_write_pfm(rt_path("sun.pfm"), env, 512, 256, 3, err, sizeof err);
    for (c = 0; c < (int)(sizeof cases / sizeof cases[0]); c++) {
      elr_scene *s = load_matte(cases[c].sampler, cases[c].path, cases[c].sun ? "sun.pfm" : "env.pfm", cases[c].light, cases[c].mirror, err);
      elr_image ref, img;
      elr_stats sr, st;
      if (!s) { rt_check(0, "matte scene %d: %s", c, err); continue; }
      sun_diffuse = cases[c].sd; light_alpha = cases[c].light_alpha; lobe_alpha = -1.f;
      if (render(s, ELR_LOOP_ONE, -1, -1, 1, 0, &ref, &sr, err) == 0 && render(s, ELR_LOOP_WAVE, -1, -1, 2, 0, &img, &st, err) == 0) {
        size_t n = (size_t)img.width * img.height * 3, k, diff = 0;
        for (k = 0; k < n; k++) diff += memcmp(&img.rgb[k], &ref.rgb[k], sizeof(float)) != 0;
        rt_check(st.loop == ELR_LOOP_WAVE && diff == 0 && st.shadow_rays == sr.shadow_rays && st.bsdf_light_rays == sr.bsdf_light_rays &&
                     st.bounce_rays == sr.bounce_rays && st.camera_rays == sr.camera_rays &&
                     st.env_product_samples == sr.env_product_samples && st.env_map_samples == sr.env_map_samples &&
                     st.env_light_only_samples == sr.env_light_only_samples,
                 "matte case %d (%s%s, sun %d, diffuse %d): %zu of %zu values differ from the reference; shadow %llu/%llu, bsdf %llu/%llu, "
                 "product %llu/%llu, map %llu/%llu, alone %llu/%llu",
                 c, cases[c].sampler, cases[c].light, cases[c].sun, cases[c].sd, diff, n, (unsigned long long)st.shadow_rays,
                 (unsigned long long)sr.shadow_rays, (unsigned long long)st.bsdf_light_rays, (unsigned long long)sr.bsdf_light_rays,
                 (unsigned long long)st.env_product_samples, (unsigned long long)sr.env_product_samples,
                 (unsigned long long)st.env_map_samples, (unsigned long long)sr.env_map_samples,
                 (unsigned long long)st.env_light_only_samples, (unsigned long long)sr.env_light_only_samples);
        /* (each way taken: a vertex of the light sample alone, of product MIS, of the map alone, as the case asks) */
        rt_check((sr.env_light_only_samples > 0) == cases[c].alone && (sr.env_map_samples > 0) == cases[c].map &&
                     (sr.env_product_samples > sr.env_light_only_samples) == cases[c].mis,
                 "matte case %d: strategies product %llu, map %llu, alone %llu", c, (unsigned long long)sr.env_product_samples,
                 (unsigned long long)sr.env_map_samples, (unsigned long long)sr.env_light_only_samples);
        elr_image_free(&img); elr_image_free(&ref);
      } else rt_check(0, "matte scene %d: %s", c, err);
      elr_scene_free(s);
    }
    sun_diffuse = -1; light_alpha = -1.f;
  }
  /* 7. --sun split (sun.c: a spot and a sky sample and the BSDF sample, three-way MIS) in the wave loop on 6.'s
   * sun map: bit for bit, the same ray and strategy counts, vertices split; with a mirror (the mattes seen in
   * it: the reference integrator's split) and a light of 2 samples */
  {
    static const struct { const char *sampler, *light; int mirror, wide, path, ls; } cases[] = {
      {"Sampler \"zsobol\" \"integer pixelsamples\" 8", "", 0, 0, 0, -1},
      {"Sampler \"random\" \"integer pixelsamples\" 4", "", 0, 0, 0, -1},
      {"Sampler \"random\" \"integer pixelsamples\" 4", "", 1, 0, 0, -1},
      {"Sampler \"zsobol\" \"integer pixelsamples\" 8", " \"integer samples\" 2", 1, 0, 0, -1},
      {"Sampler \"halton\" \"integer pixelsamples\" 5", "", 1, 0, 0, -1},
      /* a sun of one texel in a halo of 10 x 10 texels (about 7 degrees wide): its rectangle holds sky, so many light samples meet
       * the other light technique's density there (with the one-texel sun, 2 of the split case 0-4's samples) */
      {"Sampler \"zsobol\" \"integer pixelsamples\" 8", "", 0, 1, 0, -1},
      {"Sampler \"random\" \"integer pixelsamples\" 4", "", 1, 1, 0, -1},
      /* the path tracer (maxdepth 5: the escaped rays' weights against the split densities) */
      {"Sampler \"zsobol\" \"integer pixelsamples\" 8", "", 0, 0, 1, -1},
      {"Sampler \"random\" \"integer pixelsamples\" 4", "", 1, 0, 1, -1},
      {"Sampler \"zsobol\" \"integer pixelsamples\" 8", "", 1, 1, 1, -1},
      {"Sampler \"random\" \"integer pixelsamples\" 4", "", 0, 1, 1, -1},
      /* light sampling alone (the split weights without the BSDF's density) */
      {"Sampler \"zsobol\" \"integer pixelsamples\" 8", "", 1, 1, 0, ELR_LS_LIGHT},
      {"Sampler \"random\" \"integer pixelsamples\" 4", "", 1, 1, 1, ELR_LS_LIGHT},
    };
    static float env[3 * 512 * 256];
    int c, i, x, y;
    for (i = 0; i < 512 * 256; i++) env[3 * i] = env[3 * i + 1] = env[3 * i + 2] = 0.3f + 0.05f * (float)(i % 7);
    for (y = 48; y < 74; y++) /* (a bright sky about it, below the hot spots' threshold: sky samples in the spot's rectangle) */
      for (x = 78; x < 104; x++) env[3 * (y * 512 + x)] = env[3 * (y * 512 + x) + 1] = env[3 * (y * 512 + x) + 2] = 150.f;
    for (y = 56; y < 66; y++)
      for (x = 86; x < 96; x++) env[3 * (y * 512 + x)] = env[3 * (y * 512 + x) + 1] = 2000.f, env[3 * (y * 512 + x) + 2] = 1500.f;
    env[3 * (60 * 512 + 90)] = env[3 * (60 * 512 + 90) + 1] = 2e5f; env[3 * (60 * 512 + 90) + 2] = 1.5e5f; /* (a sun map: ELR_ENV_SUN_SHARE) */
    el_image_write_pfm(rt_path("sunwide.pfm"), env, 512, 256, 3, err, sizeof err);
    sun_mode = 2;
    for (c = 0; c < (int)(sizeof cases / sizeof cases[0]); c++) {
      elr_scene *s = load_matte(cases[c].sampler, cases[c].path, cases[c].wide ? "sunwide.pfm" : "sun.pfm", cases[c].light, cases[c].mirror, err);
      elr_image ref, img;
      elr_stats sr, st;
      if (!s) { rt_check(0, "split scene %d: %s", c, err); continue; }
      if (render(s, ELR_LOOP_ONE, -1, cases[c].ls, 1, 0, &ref, &sr, err) == 0 && render(s, ELR_LOOP_WAVE, -1, cases[c].ls, 2, 0, &img, &st, err) == 0) {
        size_t n = (size_t)img.width * img.height * 3, k, diff = 0;
        for (k = 0; k < n; k++) diff += memcmp(&img.rgb[k], &ref.rgb[k], sizeof(float)) != 0;
        rt_check(st.loop == ELR_LOOP_WAVE && sr.loop == ELR_LOOP_ONE && diff == 0 && sr.sunsplit_vertices > 0 &&
                     st.sunsplit_vertices == sr.sunsplit_vertices && st.sunsplit_sky_only == sr.sunsplit_sky_only &&
                     st.shadow_rays == sr.shadow_rays && st.bsdf_light_rays == sr.bsdf_light_rays && st.bounce_rays == sr.bounce_rays &&
                     st.camera_rays == sr.camera_rays && st.env_product_samples == sr.env_product_samples &&
                     st.env_map_samples == sr.env_map_samples && st.env_light_only_samples == sr.env_light_only_samples,
                 "split case %d (%s%s, mirror %d, path %d): %zu of %zu values differ from the reference; split vertices %llu/%llu, shadow "
                 "%llu/%llu, bsdf %llu/%llu, product %llu/%llu",
                 c, cases[c].sampler, cases[c].light, cases[c].mirror, cases[c].path, diff, n, (unsigned long long)st.sunsplit_vertices,
                 (unsigned long long)sr.sunsplit_vertices, (unsigned long long)st.shadow_rays, (unsigned long long)sr.shadow_rays,
                 (unsigned long long)st.bsdf_light_rays, (unsigned long long)sr.bsdf_light_rays,
                 (unsigned long long)st.env_product_samples, (unsigned long long)sr.env_product_samples);
        elr_image_free(&img); elr_image_free(&ref);
      } else rt_check(0, "split scene %d: %s", c, err);
      elr_scene_free(s);
    }
    sun_mode = -1;
  }
  /* 8. --env-sun-diffuse two and twopixel in the path tracer (issue 22: two product light samples at every diffuse
   * vertex, the second from UniformSampleOneLight's BSDF draw, and weight 0 for the environment where the
   * continuation ray from such a vertex leaves the scene) on 6.'s sun map: bit for bit, the same ray and strategy
   * counts; zsobol, random, halton, a mirror (its reflections: vertices after a specular bounce), twopixel with
   * pixels of both choices; with --sun on (two left out at the cells that lower the sun: their MIS kept) and --sun split
   * (two left out: the split's three-way MIS), where only the first condition below is asked */
  {
    static const struct { const char *sampler; int sd, mirror, mis, sun; } cases[] = {
      {"Sampler \"zsobol\" \"integer pixelsamples\" 8", ELR_ENVSD_TWO, 0, 0, -1},
      {"Sampler \"random\" \"integer pixelsamples\" 4", ELR_ENVSD_TWO, 1, 0, -1},
      {"Sampler \"zsobol\" \"integer pixelsamples\" 8", ELR_ENVSD_TWO_PIXEL, 0, 1, -1},
      {"Sampler \"random\" \"integer pixelsamples\" 4", ELR_ENVSD_TWO_PIXEL, 1, 1, -1},
      {"Sampler \"halton\" \"integer pixelsamples\" 5", ELR_ENVSD_TWO_PIXEL, 1, 1, -1},
      {"Sampler \"zsobol\" \"integer pixelsamples\" 300", ELR_ENVSD_TWO, 1, 0, -1}, /* (a pixel in several waves) */
      {"Sampler \"zsobol\" \"integer pixelsamples\" 8", ELR_ENVSD_TWO, 1, 0, 1},
      {"Sampler \"random\" \"integer pixelsamples\" 4", ELR_ENVSD_TWO_PIXEL, 1, 1, 2},
    };
    int c;
    for (c = 0; c < (int)(sizeof cases / sizeof cases[0]); c++) {
      elr_scene *s = load_matte(cases[c].sampler, 1, "sun.pfm", "", cases[c].mirror, err);
      elr_image ref, img;
      elr_stats sr, st;
      if (!s) { rt_check(0, "path two scene %d: %s", c, err); continue; }
      sun_diffuse = cases[c].sd; sun_mode = cases[c].sun;
      if (render(s, ELR_LOOP_ONE, -1, -1, 1, 0, &ref, &sr, err) == 0 && render(s, ELR_LOOP_WAVE, -1, -1, 2, 0, &img, &st, err) == 0) {
        size_t n = (size_t)img.width * img.height * 3, k, diff = 0;
        for (k = 0; k < n; k++) diff += memcmp(&img.rgb[k], &ref.rgb[k], sizeof(float)) != 0;
        rt_check(st.loop == ELR_LOOP_WAVE && sr.loop == ELR_LOOP_ONE && diff == 0 && st.shadow_rays == sr.shadow_rays &&
                     st.bounce_rays == sr.bounce_rays && st.camera_rays == sr.camera_rays && st.env_product_samples == sr.env_product_samples &&
                     st.env_map_samples == sr.env_map_samples && st.env_light_only_samples == sr.env_light_only_samples,
                 "path two case %d (%s, diffuse %d, mirror %d): %zu of %zu values differ from the reference; shadow %llu/%llu, bounce "
                 "%llu/%llu, product %llu/%llu, alone %llu/%llu",
                 c, cases[c].sampler, cases[c].sd, cases[c].mirror, diff, n, (unsigned long long)st.shadow_rays, (unsigned long long)sr.shadow_rays,
                 (unsigned long long)st.bounce_rays, (unsigned long long)sr.bounce_rays, (unsigned long long)st.env_product_samples,
                 (unsigned long long)sr.env_product_samples, (unsigned long long)st.env_light_only_samples,
                 (unsigned long long)sr.env_light_only_samples);
        /* (two taken at vertices: light samples alone; twopixel's pixels of product MIS too, two's none) */
        if (cases[c].sun < 0)
          rt_check(sr.env_light_only_samples > 0 && (sr.env_product_samples > sr.env_light_only_samples) == cases[c].mis,
                   "path two case %d: product %llu, alone %llu", c, (unsigned long long)sr.env_product_samples, (unsigned long long)sr.env_light_only_samples);
        elr_image_free(&img); elr_image_free(&ref);
      } else rt_check(0, "path two scene %d: %s", c, err);
      elr_scene_free(s);
    }
    sun_diffuse = -1; sun_mode = -1;
  }
  /* 9. le_same (issue 21): where the density's light (env_sample) has env's le, the wave looks up an escaped BSDF ray's
   * product pdf and radiance in one el_envlight_pdf_li_cos_le_n call; bit for bit the reference's two lookups. The
   * sun map (the patch density: env_alt over env's texels), the smooth one (env itself) and the smooth one with
   * --compensated (env_alt again), the light under a general rotation (the matrix compared bit for bit) or the
   * scene's; direct lighting (structure-of-arrays lanes; a light of 2 samples: the general stage) and the path tracer */
  {
    /* (same: le_same expected; under the rotation env_alt's matrix, made again from env's, differs in its bits: the two lookups) */
    static const struct { const char *map, *light; int rot, path, comp, same; } cases[] = {
      {"sun.pfm", "", 0, 0, -1, 1}, {"sun.pfm", " \"integer samples\" 2", 0, 0, -1, 1}, {"sun.pfm", "", 0, 1, -1, 1},
      {"sun.pfm", "", 1, 0, -1, 0}, {"sun.pfm", "", 1, 1, -1, 0},
      {"env.pfm", "", 0, 0, -1, 1}, {"env.pfm", "", 1, 1, -1, 1}, {"env.pfm", " \"integer samples\" 2", 1, 0, -1, 1},
      {"env.pfm", " \"integer samples\" 2", 0, 0, 1, 1}, {"env.pfm", "", 0, 1, 1, 1}, {"env.pfm", "", 1, 1, 1, 0},
    };
    int c;
    for (c = 0; c < (int)(sizeof cases / sizeof cases[0]); c++) {
      static char buf[4096];
      elr_scene *s;
      elr_image ref, img;
      elr_stats sr, st;
      elr_render_options o;
      snprintf(buf, sizeof buf,
               "LookAt 0 1.5 -4  0 0.5 0  0 1 0\nCamera \"perspective\" \"float fov\" 45\n"
               "Film \"image\" \"integer xresolution\" 24 \"integer yresolution\" 18\nSampler \"zsobol\" \"integer pixelsamples\" 8\nIntegrator %s\n"
               "WorldBegin\nAttributeBegin\n%s\nLightSource \"infinite\" \"string mapname\" \"%s\"%s\nAttributeEnd\n"
               "AttributeBegin\nMaterial \"matte\" \"rgb Kd\" [ 0.7 0.5 0 ]\nTranslate -0.6 0.5 0\nShape \"sphere\" \"float radius\" 0.5\nAttributeEnd\n"
               "AttributeBegin\nMaterial \"matte\" \"rgb Kd\" [ 0.4 0.4 0.4 ]\n"
               "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point P\" [ -5 0 -5  5 0 -5  5 0 5  -5 0 5 ]\nAttributeEnd\nWorldEnd\n",
               cases[c].path ? "\"path\" \"integer maxdepth\" 5" : "\"directlighting\"", cases[c].rot ? "Rotate 37 1 2 3" : "Rotate -90 1 0 0",
               cases[c].map, cases[c].light);
      s = rt_load("wave_lesame.pbrt", buf, err, 512);
      if (!s) { rt_check(0, "le_same scene %d: %s", c, err); continue; }
      elr_render_options_default(&o);
      o.nthreads = 2; o.seed = 11; o.quiet = 1; o.compensated = cases[c].comp;
      o.env_light_alpha = INFINITY; /* (product MIS on the mattes under the smooth map too: BSDF samples) */
      o.loop = ELR_LOOP_ONE;
      if (elr_render(s, &o, &ref, &sr, err, 512) == 0) {
        o.loop = ELR_LOOP_WAVE;
        if (elr_render(s, &o, &img, &st, err, 512) == 0) {
          size_t n = (size_t)img.width * img.height * 3, k, diff = 0;
          int i, same = 0;
          for (k = 0; k < n; k++) diff += memcmp(&img.rgb[k], &ref.rgb[k], sizeof(float)) != 0;
          for (i = 0; i < s->nlight; i++) if (s->light[i].kind == ELR_LIGHT_INFINITE) same = s->light[i].le_same && s->light[i].product;
          rt_check(st.loop == ELR_LOOP_WAVE && same == cases[c].same && diff == 0 && st.bsdf_light_rays == sr.bsdf_light_rays &&
                       st.bounce_rays == sr.bounce_rays && (cases[c].path ? st.bounce_rays : st.bsdf_light_rays) > 0,
                   "le_same case %d (%s%s, rotated %d, path %d, compensated %d): le_same %d, %zu of %zu values differ from the reference; bsdf rays "
                   "%llu/%llu, bounces %llu/%llu", c, cases[c].map, cases[c].light, cases[c].rot, cases[c].path, cases[c].comp, same, diff, n,
                   (unsigned long long)st.bsdf_light_rays, (unsigned long long)sr.bsdf_light_rays, (unsigned long long)st.bounce_rays,
                   (unsigned long long)sr.bounce_rays);
          elr_image_free(&img);
        } else rt_check(0, "le_same scene %d: %s", c, err);
        elr_image_free(&ref);
      } else rt_check(0, "le_same scene %d: %s", c, err);
      elr_scene_free(s);
    }
  }
  return rt_finish("test_render_wave");
}
