/* test_render_split: splitting (render.c: several light and BSDF sample pairs per camera sample, for the
 * direct-lighting integrator's strategy "all") keeps the image unbiased, and its switches work.
 *  1. n = 4 pairs against none (one pair): the images differ, their means agree: the mean over pixels
 *     of the per-pixel luminance difference is within 4 standard errors of 0 (the standard error from
 *     the pixels' spread; a false alarm has probability about 6e-5). With the average over the pairs
 *     taken wrongly (a factor 4/3 on the light) z was 14.8 here.
 *  2. auto: the pilot's choice n is reported (elr_stats.split, split_auto) and the image is the one
 *     rendered with n given (bit for bit: the pilot's seeds are not the render's), so 1. covers it.
 *  3. The Integrator's "splitting" "off" and --split off (the option) give one pair; a light's own
 *     "samples" count is honoured (auto does not override it); the path tracer is never split. */
#include "render_test_util.h"

static elr_scene *load(const char *integrator, const char *light, char *err) {
  static char buf[4096];
  snprintf(buf, sizeof buf,
           "LookAt 0 1 -4  0 0.5 0  0 1 0\nCamera \"perspective\" \"float fov\" 45\n"
           "Film \"image\" \"integer xresolution\" 40 \"integer yresolution\" 32\n"
           "Sampler \"random\" \"integer pixelsamples\" 4\n%s\n"
           "WorldBegin\nLightSource \"infinite\" \"string mapname\" \"env.pfm\"%s\n"
           "AttributeBegin\nMaterial \"plastic\" \"rgb Kd\" [ 0.5 0.4 0.3 ] \"float roughness\" 0.1\n"
           "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point P\" [ -5 0 -5  5 0 -5  5 0 5  -5 0 5 ]\nAttributeEnd\n"
           "AttributeBegin\nMaterial \"matte\" \"rgb Kd\" [ 0.7 0.5 0.3 ]\nTranslate 0 0.5 0\nShape \"sphere\" \"float radius\" 0.5\nAttributeEnd\n"
           "WorldEnd\n",
           integrator, light);
  return rt_load("split.pbrt", buf, err, 512);
}

static int render(elr_scene *s, int split, int seed, elr_image *img, elr_stats *st, char *err) {
  elr_render_options o;
  elr_render_options_default(&o);
  o.nthreads = 2; o.seed = (uint64_t)seed; o.quiet = 1; o.split = split;
  return elr_render(s, &o, img, st, err, 512);
}

static double lum(const float *c) { return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]; }

int main(void) {
  char err[512];
  elr_scene *s;
  elr_image a, b;
  elr_stats sa, sb;
  rt_mkdir("test_render_split");
  { /* a small sun in a dim sky: light sampling's variance dominates */
    float env[3 * 64 * 32];
    int i;
    for (i = 0; i < 64 * 32; i++) {
      float v = (i % 64 == 20 && i / 64 == 9) ? 4000.f : 0.3f + 0.2f * (float)((i * 13) % 5);
      env[3 * i] = v; env[3 * i + 1] = 0.9f * v; env[3 * i + 2] = 0.8f * v;
    }
    el_image_write_pfm(rt_path("env.pfm"), env, 64, 32, 3, err, sizeof err);
  }
  s = load("Integrator \"directlighting\"", "", err);
  if (!s) { rt_check(0, "scene: %s", err); return rt_finish("test_render_split"); }
  /* 1. four pairs against one: the same mean */
  if (render(s, ELR_SPLIT_OFF, 3, &a, &sa, err) == 0 && render(s, 4, 4, &b, &sb, err) == 0) {
    int k, n = a.width * a.height;
    double sum = 0, sum2 = 0, mean, se, z, ma = 0;
    for (k = 0; k < n; k++) {
      double d = lum(&b.rgb[3 * k]) - lum(&a.rgb[3 * k]);
      sum += d; sum2 += d * d; ma += lum(&a.rgb[3 * k]);
    }
    mean = sum / n; se = sqrt((sum2 / n - mean * mean) / (n - 1)); z = se > 0 ? mean / se : 0;
    rt_check(sa.split == 1 && sb.split == 4 && sb.shadow_rays > 3 * sa.shadow_rays && fabs(z) < 4.0 && ma > 0,
             "4 pairs per camera sample against 1: split %d / %d, shadow rays %llu / %llu; mean difference %.4g (image mean %.4g), "
             "standard error %.3g, z = %.2f (|z| < 4)", sa.split, sb.split, (unsigned long long)sa.shadow_rays, (unsigned long long)sb.shadow_rays,
             mean, ma / n, se, z);
    elr_image_free(&a); elr_image_free(&b);
  } else rt_check(0, "split renders: %s", err);
  /* 2. auto: the image of the n it chose */
  if (render(s, ELR_SPLIT_AUTO, 3, &a, &sa, err) == 0) {
    if (render(s, sa.split >= 2 ? sa.split : ELR_SPLIT_OFF, 3, &b, &sb, err) == 0) {
      size_t nb = sizeof(float) * 3 * (size_t)a.width * a.height;
      rt_check(sa.split_auto == 1 && sa.split >= 1 && sa.split <= 16 && sa.t_split_pilot > 0 && memcmp(a.rgb, b.rgb, nb) == 0 &&
                   sa.shadow_rays == sb.shadow_rays,
               "auto splitting chose %d pair%s (pilot %.3f s, relative variance %.3g / %.3g, CPU %.4f / %.4f s at 1 / 4 pairs): %s image as "
               "%d given", sa.split, sa.split == 1 ? "" : "s", sa.t_split_pilot, sa.split_var[0], sa.split_var[1], sa.split_cpu[0],
               sa.split_cpu[1], memcmp(a.rgb, b.rgb, nb) == 0 ? "the same" : "a DIFFERENT", sa.split);
      elr_image_free(&b);
    } else rt_check(0, "split render: %s", err);
    elr_image_free(&a);
  } else rt_check(0, "auto split render: %s", err);
  elr_scene_free(s);
  /* 3. the switches */
  {
    static const struct { const char *integrator, *light; int split, expect, expect_auto; } cases[] = {
      {"Integrator \"directlighting\" \"string splitting\" \"auto\"", "", -1, -1, 1},      /* the scene asks for it */
      {"Integrator \"directlighting\" \"string splitting\" \"off\"", "", -1, 1, 0},        /* the scene turns it off */
      {"Integrator \"directlighting\"", "", -1, 1, 0},                                      /* the default: off */
      {"Integrator \"directlighting\" \"string splitting\" \"auto\"", "", ELR_SPLIT_OFF, 1, 0}, /* the option turns it off */
      {"Integrator \"directlighting\"", " \"integer samples\" 3", ELR_SPLIT_AUTO, 1, 0},   /* the light's count is kept */
      {"Integrator \"directlighting\"", " \"integer samples\" 3", 5, 1, 0},
      {"Integrator \"path\"", "", ELR_SPLIT_AUTO, 1, 0},                                    /* the path tracer: never */
      {"Integrator \"directlighting\" \"string strategy\" \"one\"", "", 4, 1, 0},           /* nor strategy "one" */
    };
    int c;
    for (c = 0; c < (int)(sizeof cases / sizeof cases[0]); c++) {
      s = load(cases[c].integrator, cases[c].light, err);
      if (s && render(s, cases[c].split, 1, &a, &sa, err) == 0) {
        rt_check(sa.split_auto == cases[c].expect_auto && (cases[c].expect < 0 ? sa.split >= 1 : sa.split == cases[c].expect),
                 "%s%s, option %d: split %d (auto %d), expected %d (auto %d)", cases[c].integrator, cases[c].light, cases[c].split, sa.split,
                 sa.split_auto, cases[c].expect, cases[c].expect_auto);
        elr_image_free(&a);
      } else rt_check(0, "switch case %d: %s", c, err);
      elr_scene_free(s);
    }
  }
  /* the parser's error */
  s = load("Integrator \"directlighting\" \"string splitting\" \"sometimes\"", "", err);
  rt_check(!s && strstr(err, "splitting must be") != NULL, "a bad \"splitting\" value is an error naming it: %s", err);
  elr_scene_free(s);
  return rt_finish("test_render_split");
}
