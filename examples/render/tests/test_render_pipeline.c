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
  return rt_finish("test_render_pipeline");
}
