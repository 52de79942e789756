/* test_render_pipeline: the renderer simulates only what the scene calls for (issue 5), checked through
 * the statistics that `render --stats` prints:
 *  - nothing emits: no light sampling, no shadow rays, a black image;
 *  - an environment seen only directly and through mirrors: no sampling distribution, no shadow rays,
 *    yet the mirror shows the environment;
 *  - point light only: no environment distribution, shadow rays only towards the point light;
 *  - an image texture seen magnified builds MIP level 0 only; seen minified, the pyramid;
 *  - nothing splats: no splat buffer; path with maxdepth 1 and no environment traces no bounce rays. */
#include "render_test_util.h"

static elr_scene *load(const char *name, const char *body, char *err) {
  static char buf[4096];
  snprintf(buf, sizeof buf,
           "LookAt 0 1 -4  0 0.5 0  0 1 0\nCamera \"perspective\" \"float fov\" 45\n"
           "Film \"image\" \"integer xresolution\" 24 \"integer yresolution\" 24\n"
           "Sampler \"random\" \"integer pixelsamples\" 4\n%s", body);
  return rt_load(name, buf, err, 512);
}

int main(void) {
  char err[512];
  elr_scene *s;
  elr_image img;
  elr_stats st;
  rt_mkdir("test_render_pipeline");
  {
    float env[3 * 16 * 8];
    int i;
    for (i = 0; i < 3 * 16 * 8; i++) env[i] = 0.5f + (float)(i % 7);
    el_image_write_pfm(rt_path("env.pfm"), env, 16, 8, 3, err, sizeof err);
  }
  /* 1. nothing emits */
  s = load("dark.pbrt", "Integrator \"path\"\nWorldBegin\nShape \"sphere\"\nWorldEnd\n", err);
  if (s && rt_render(s, 0, -1, -1, 2, 1, &img, &st) == 0) {
    double m = 0;
    int k;
    for (k = 0; k < 24 * 24 * 3; k++) m += img.rgb[k];
    rt_check(st.light_sampling_used == 0 && st.shadow_rays == 0 && st.distribution_built == 0 && m == 0.0,
             "no light: no light sampling, %llu shadow rays, black image", (unsigned long long)st.shadow_rays);
    elr_image_free(&img);
  } else rt_check(0, "dark scene: %s", err);
  elr_scene_free(s);
  /* 2. mirrors only */
  s = load("mirror.pbrt", "Integrator \"directlighting\"\nWorldBegin\nLightSource \"infinite\" \"string mapname\" \"env.pfm\"\n"
                          "Material \"mirror\"\nShape \"sphere\" \"float radius\" 1\nWorldEnd\n", err);
  if (s && rt_render(s, 0, -1, -1, 2, 1, &img, &st) == 0) {
    float c = img.rgb[3 * (12 * 24 + 12)];
    rt_check(st.distribution_built == 0 && st.shadow_rays == 0 && st.bsdf_light_rays == 0 && st.bounce_rays > 0 && c > 0.4f,
             "environment + mirror sphere: no distribution, no shadow rays, %llu reflected rays, the mirror shows the map (%.3f)",
             (unsigned long long)st.bounce_rays, c);
    elr_image_free(&img);
  } else rt_check(0, "mirror scene: %s", err);
  elr_scene_free(s);
  /* 2b. environment alone, path tracer */
  s = load("bg.pbrt", "WorldBegin\nLightSource \"infinite\" \"string mapname\" \"env.pfm\"\nWorldEnd\n", err);
  if (s && rt_render(s, 0, -1, -1, 2, 1, &img, &st) == 0) {
    rt_check(st.distribution_built == 0 && st.bytes_distribution == 0 && st.shadow_rays == 0 && st.bounce_rays == 0,
             "environment alone: no distribution (0 bytes), no shadow or bounce rays");
    elr_image_free(&img);
  } else rt_check(0, "background scene: %s", err);
  elr_scene_free(s);
  /* 2c. the same with a diffuse sphere: now the distribution is built */
  s = load("diffuse.pbrt", "WorldBegin\nLightSource \"infinite\" \"string mapname\" \"env.pfm\"\nShape \"sphere\"\nWorldEnd\n", err);
  if (s && rt_render(s, 0, -1, -1, 2, 1, &img, &st) == 0) {
    rt_check(st.distribution_built == 1 && st.bytes_distribution > 0 && st.shadow_rays > 0,
             "environment + diffuse sphere: distribution built (%.1f KiB), %llu shadow rays", st.bytes_distribution / 1024.0,
             (unsigned long long)st.shadow_rays);
    rt_check(st.splats_allocated == 0 && st.bytes_splats == 0, "nothing splats: no splat buffer");
    rt_check(st.rejected_samples == 0, "no NaN, infinite or negative sample reached the film");
    elr_image_free(&img);
  } else rt_check(0, "diffuse scene: %s", err);
  elr_scene_free(s);
  /* 3. a point light only, maxdepth 1 */
  s = load("point.pbrt", "Integrator \"path\" \"integer maxdepth\" 1\nWorldBegin\nLightSource \"point\" \"point from\" [ 0 3 0 ] \"rgb I\" [ 5 5 5 ]\n"
                         "Shape \"sphere\"\nWorldEnd\n", err);
  if (s && rt_render(s, 0, -1, -1, 2, 1, &img, &st) == 0) {
    rt_check(st.distribution_built == 0 && st.shadow_rays > 0 && st.bounce_rays == 0,
             "point light, maxdepth 1: no distribution, %llu shadow rays, no bounce rays", (unsigned long long)st.shadow_rays);
    elr_image_free(&img);
  } else rt_check(0, "point scene: %s", err);
  elr_scene_free(s);
  /* 4. MIP levels only when a texture is minified */
  {
    static float tex[3 * 256 * 256];
    int x, y, k;
    for (y = 0; y < 256; y++)
      for (x = 0; x < 256; x++)
        for (k = 0; k < 3; k++) tex[3 * (y * 256 + x) + k] = (float)(((x / 4) + (y / 4)) & 1) * 0.8f + 0.1f;
    el_image_write_pfm(rt_path("big.pfm"), tex, 256, 256, 3, err, sizeof err);
    el_image_write_pfm(rt_path("small.pfm"), tex, 8, 8, 3, err, sizeof err);
    for (k = 0; k < 2; k++) {
      char body[1024];
      snprintf(body, sizeof body,
               "Integrator \"directlighting\"\nWorldBegin\nLightSource \"point\" \"point from\" [ 0 3 -3 ] \"rgb I\" [ 9 9 9 ]\n"
               "Texture \"t\" \"spectrum\" \"imagemap\" \"string filename\" \"%s\" \"string filter\" \"%s\"\n"
               "Material \"matte\" \"texture Kd\" \"t\"\n"
               "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point P\" [ -1 0 -1  1 0 -1  1 1.5 1  -1 1.5 1 ]\n"
               "  \"float uv\" [ 0 0 1 0 1 1 0 1 ]\nWorldEnd\n", k ? "big.pfm" : "small.pfm", k ? "ewa" : "trilinear");
      s = load("tex.pbrt", body, err);
      if (s && rt_render(s, 0, -1, -1, 2, 1, &img, &st) == 0) {
        if (k == 0) rt_check(st.mip_textures == 1 && st.mip_levels_built == 1, "8 x 8 texture seen magnified: MIP level 0 only (%d built)", st.mip_levels_built);
        else rt_check(st.mip_textures == 1 && st.mip_levels_built > 1, "256 x 256 texture seen minified (24 x 24 image): %d MIP levels built", st.mip_levels_built);
        elr_image_free(&img);
      } else rt_check(0, "texture scene: %s", err);
      elr_scene_free(s);
    }
  }
  /* 5. ray differentials reach the texture filters: a checkerboard far finer than the pixels, on a plane
   * facing the camera under a constant sky (BSDF sampling only: every sample is exactly Kd L), seen at
   * the pixel centres. Filtered by the footprint (pbrt's closed-form box filter, or EWA on the MIP map
   * of a 1-texel checker image), every pixel is the checks' mean 0.5; point sampling would give 0 or 1. */
  {
    static float chk[3 * 256 * 256];
    int x, y, k;
    for (y = 0; y < 256; y++)
      for (x = 0; x < 256; x++)
        for (k = 0; k < 3; k++) chk[3 * (y * 256 + x) + k] = (float)((x + y) & 1);
    el_image_write_pfm(rt_path("chk.pfm"), chk, 256, 256, 3, err, sizeof err);
    for (k = 0; k < 3; k++) {
      char buf[2048];
      const char *tex[3] = {"Texture \"t\" \"spectrum\" \"checkerboard\" \"float uscale\" 230 \"float vscale\" 230\n",
                            "Texture \"t\" \"spectrum\" \"imagemap\" \"string filename\" \"chk.pfm\" \"string filter\" \"ewa\"\n",
                            "Texture \"t\" \"spectrum\" \"checkerboard\" \"float uscale\" 230 \"float vscale\" 230 \"string aamode\" \"none\"\n"};
      snprintf(buf, sizeof buf,
               "LookAt 0 0 -1  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 40\n"
               "Film \"image\" \"integer xresolution\" 24 \"integer yresolution\" 24\n"
               "Sampler \"stratified\" \"integer xsamples\" 1 \"integer ysamples\" 1 \"bool jitter\" \"false\"\n"
               "Integrator \"directlighting\"\nWorldBegin\nLightSource \"infinite\"\n%s"
               "Material \"matte\" \"texture Kd\" \"t\"\n"
               "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point P\" [ -1 -1 0  1 -1 0  1 1 0  -1 1 0 ]\n"
               "  \"float uv\" [ 0 0 1 0 1 1 0 1 ]\nWorldEnd\n", tex[k]);
      s = rt_load("chk.pbrt", buf, err, sizeof err);
      if (s && rt_render(s, 0, ELR_LS_BSDF, -1, 2, 1, &img, &st) == 0) {
        double worst = 0;
        int n01 = 0;
        for (y = 4; y < 20; y++)
          for (x = 4; x < 20; x++) {
            float v = img.rgb[3 * (y * 24 + x)];
            if (fabs(v - 0.5) > worst) worst = fabs(v - 0.5);
            if (v < 0.02f || v > 0.98f) n01++;
          }
        if (k < 2) rt_check(worst < 0.1, "%s: every pixel near the mean 0.5 (worst |v - 0.5| = %.3f)",
                            k == 0 ? "checkerboard, closed-form box filter over the ray footprint" : "1-texel checker image, EWA", worst);
        else rt_check(n01 == 16 * 16, "checkerboard with aamode none (point sampled): every pixel 0 or 1 (%d of 256)", n01);
        elr_image_free(&img);
      } else rt_check(0, "checker scene %d: %s", k, err);
      elr_scene_free(s);
    }
  }
  /* 8. The environment light samples drawn together (the wave loop, the default) give the image of
   * drawing each inside its own sample's shading (no_batch: the reference loop), bit for bit: every
   * sampler, both integrators,
   * light-only sampling, textures (ray differentials), a mirror (its bounce must not take the first
   * vertex's light sample), sample counts that fill no wave (up to 256 camera samples) evenly, an environment
   * with several samples per vertex (the first drawn with the wave, then the others one at a time), and the
   * cases that turn batching off (a second emitting light; stratified strata or 02sequence dimensions
   * that cover fewer draws). These cases batch the map's own samples (el_envlight_sample_li_n): the
   * environment is sampled by the map alone here; the wave loop's batched product samples
   * (el_envlight_sample_li_cos_n, the default) are compared with the reference loop in test_render_wave
   * and with the single calls in test_envlight_batch. The path tracer with a pixel sampler ("2")
   * draws past the sampler's dimensions in another order in the wave loop: other numbers of the same
   * distribution (test_render_wave compares the means), so only the loops that ran are checked there. */
  {
    static const char *cases[][3] = { /* sampler and integrator, batched?, the environment's parameters */
      {"Sampler \"stratified\" \"integer xsamples\" 6 \"integer ysamples\" 7\nIntegrator \"directlighting\"\n", "1", ""},
      {"Sampler \"halton\" \"integer pixelsamples\" 37\nIntegrator \"directlighting\"\n", "1", ""},
      {"Sampler \"random\" \"integer pixelsamples\" 33\nIntegrator \"directlighting\"\n", "1", ""},
      {"Sampler \"halton\" \"integer pixelsamples\" 16\nIntegrator \"path\" \"integer maxdepth\" 4\n", "1", ""},
      {"Sampler \"stratified\" \"integer xsamples\" 4 \"integer ysamples\" 4\nIntegrator \"path\" \"integer maxdepth\" 3\n", "2", ""},
      {"Sampler \"random\" \"integer pixelsamples\" 12\nIntegrator \"path\" \"integer maxdepth\" 6\n", "1", ""},
      {"Sampler \"random\" \"integer pixelsamples\" 8\nIntegrator \"directlighting\" \"string strategy\" \"one\"\n", "1", ""},
      {"Sampler \"stratified\" \"integer xsamples\" 3 \"integer ysamples\" 3 \"integer dimensions\" 2\nIntegrator \"directlighting\"\n", "0", ""},
      {"Sampler \"halton\" \"integer pixelsamples\" 8\nIntegrator \"directlighting\"\n", "0", ""},
      {"Sampler \"halton\" \"integer pixelsamples\" 5\nIntegrator \"directlighting\"\n", "1", " \"integer samples\" 3"},
      {"Sampler \"random\" \"integer pixelsamples\" 4\nIntegrator \"path\" \"integer maxdepth\" 3\n", "1", " \"integer samples\" 3"},
      /* the Sobol' samplers: dimensions computed from (pixel, sample, dimension), or a pixel sampler */
      {"Sampler \"sobol\" \"integer pixelsamples\" 64\nIntegrator \"directlighting\"\n", "1", ""},
      {"Sampler \"sobol\" \"integer pixelsamples\" 16 \"string randomization\" \"owen\"\nIntegrator \"path\" \"integer maxdepth\" 4\n", "1", ""},
      {"Sampler \"02sequence\" \"integer pixelsamples\" 16\nIntegrator \"directlighting\"\n", "1", ""},
      {"Sampler \"02sequence\" \"integer pixelsamples\" 8\nIntegrator \"path\" \"integer maxdepth\" 3\n", "2", " \"integer samples\" 3"},
      {"Sampler \"02sequence\" \"integer pixelsamples\" 8 \"integer dimensions\" 2\nIntegrator \"directlighting\"\n", "0", ""},
      {"Sampler \"zsobol\" \"integer pixelsamples\" 64\nIntegrator \"directlighting\"\n", "1", ""},
      {"Sampler \"zsobol\" \"integer pixelsamples\" 8\nIntegrator \"path\" \"integer maxdepth\" 5\n", "1", " \"integer samples\" 3"},
      {"Sampler \"paddedsobol\" \"integer pixelsamples\" 37\nIntegrator \"directlighting\"\n", "1", ""},
      {"Sampler \"paddedsobol\" \"integer pixelsamples\" 16 \"string randomization\" \"owen\"\nIntegrator \"path\" \"integer maxdepth\" 4\n", "1", ""},
    };
    int c;
    for (c = 0; c < (int)(sizeof cases / sizeof cases[0]); c++) {
      static char buf[4096];
      elr_image a, b;
      elr_stats sa, sb;
      elr_render_options o;
      int ok = 0, lsmode;
      snprintf(buf, sizeof buf,
               "LookAt 0 1 -4  0 0.5 0  0 1 0\nCamera \"perspective\" \"float fov\" 45\n"
               "Film \"image\" \"integer xresolution\" 20 \"integer yresolution\" 16\n%s"
               "WorldBegin\nLightSource \"infinite\" \"string mapname\" \"env.pfm\" \"float scale\" 2%s\n%s"
               "Texture \"chk\" \"spectrum\" \"checkerboard\" \"float uscale\" 8 \"float vscale\" 8\n"
               "AttributeBegin\nMaterial \"plastic\" \"texture Kd\" \"chk\" \"float roughness\" 0.05\n"
               "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point P\" [ -5 0 -5  5 0 -5  5 0 5  -5 0 5 ]\n"
               "  \"float uv\" [ 0 0 1 0 1 1 0 1 ]\nAttributeEnd\n"
               "AttributeBegin\nMaterial \"matte\" \"rgb Kd\" [ 0.7 0.5 0.3 ]\nTranslate -0.6 0.5 0\nShape \"sphere\" \"float radius\" 0.5\nAttributeEnd\n"
               "AttributeBegin\nMaterial \"mirror\"\nTranslate 0.7 0.5 0.3\nShape \"sphere\" \"float radius\" 0.4\nAttributeEnd\nWorldEnd\n",
               cases[c][0], cases[c][2], c == 8 ? "LightSource \"point\" \"point from\" [ 0 3 0 ] \"rgb I\" [ 2 2 2 ]\n" : "");
      s = rt_load("batch.pbrt", buf, err, sizeof err);
      if (!s) { rt_check(0, "batch scene %d: %s", c, err); continue; }
      for (lsmode = 0; lsmode < (c == 0 ? 2 : 1); lsmode++) {
        elr_render_options_default(&o);
        o.nthreads = 2; o.seed = 5; o.quiet = 1;
        o.env_sampling = 0; /* batching draws the map's own samples (el_envlight_sample_li_n) */
        if (lsmode) o.light_sampling = ELR_LS_LIGHT;
        if (elr_render(s, &o, &a, &sa, err, sizeof err) == 0) {
          o.no_batch = 1;
          if (elr_render(s, &o, &b, &sb, err, sizeof err) == 0) {
            size_t nb = sizeof(float) * 3 * (size_t)a.width * (size_t)a.height;
            double m = 0;
            int k;
            for (k = 0; k < a.width * a.height * 3; k++) m += a.rgb[k];
            if (cases[c][1][0] == '2')
              ok = sa.light_samples_batched && sa.loop == ELR_LOOP_WAVE && !sb.light_samples_batched && sb.loop == ELR_LOOP_ONE &&
                   sa.camera_rays == sb.camera_rays && m > 0;
            else
              ok = memcmp(a.rgb, b.rgb, nb) == 0 && sa.light_samples_batched == (cases[c][1][0] == '1') && !sb.light_samples_batched &&
                   sa.shadow_rays == sb.shadow_rays && sa.bounce_rays == sb.bounce_rays && m > 0;
            rt_check(ok, "batched light samples, case %d%s: %s image as one at a time (batched: %d, expected %s; shadow rays %llu / %llu)",
                     c, lsmode ? " (light sampling only)" : "", memcmp(a.rgb, b.rgb, nb) == 0 ? "the same" : "a DIFFERENT",
                     sa.light_samples_batched, cases[c][1], (unsigned long long)sa.shadow_rays, (unsigned long long)sb.shadow_rays);
            elr_image_free(&b);
          } else rt_check(0, "batch case %d (one at a time): %s", c, err);
          elr_image_free(&a);
        } else rt_check(0, "batch case %d: %s", c, err);
      }
      elr_scene_free(s);
    }
  }
  return rt_finish("test_render_pipeline");
}
