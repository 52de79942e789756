/* bench_sun_render.c: the renderer's noise in the sun's shadow and in the sun, with issue 22's sun cache
 * (examples/render/sun.c, --sun on) and without it (--sun off: the renderer's density before it).
 *
 *   bench_sun_render [SPP [SEEDS [THREADS [SCENE.pbrt ...]]]]   samples per pixel (16), seeds per case (16),
 *                    threads (2), scenes (scenes/sun_shadow_object.pbrt: direct lighting; scenes/sun_porch.pbrt:
 *                    path tracing, maxdepth 3; scenes/bench_city.pbrt: city.hdr's sun, direct lighting).
 *                    Run from the repository's root.
 *
 * For each scene: its pixels classed SHADOWED (5 rays through the pixel all hit points that do not see the
 * largest hot spot's axis), LIT (all 5 see it) or neither (examples/render/tests/sun_measure.h); SEEDS
 * renders with the cache off and on. Printed per class: the mean luminance with each (and the z score of
 * their difference: unbiased when |z| is small), the mean over its pixels of the variance over the seeds,
 * and their ratio (off / on: the gain at equal samples); the CPU seconds of one render loop (plus, for
 * "on", the pilot's CPU seconds) and the gain at equal time (variance x seconds, off / on). */
#include "tests/sun_measure.h"

int main(int argc, char **argv) {
  static const char *defaults[3] = {"scenes/sun_shadow_object.pbrt", "scenes/sun_porch.pbrt", "scenes/bench_city.pbrt"};
  int spp = argc > 1 ? atoi(argv[1]) : 16, ns = argc > 2 ? atoi(argv[2]) : 16, nt = argc > 3 ? atoi(argv[3]) : 2;
  const char **scenes = argc > 4 ? (const char **)(argv + 4) : defaults;
  int nsc = argc > 4 ? argc - 4 : 3, i, c;
  if (spp < 1 || ns < 2 || ns > 1024 || nt < 1) { fprintf(stderr, "usage: bench_sun_render [SPP [SEEDS>=2 [THREADS [SCENE ...]]]]\n"); return 1; }
  printf("bench_sun_render: %d spp, %d seeds, %d threads\n", spp, ns, nt);
  for (i = 0; i < nsc; i++) {
    elr_scene *s = NULL;
    char err[512];
    unsigned char *cls;
    sm_result off, on;
    elr_image im;
    elr_render_options o;
    int w, h;
    double toff, ton;
    if (elr_scene_load(scenes[i], &s, 1, err, sizeof err) != 0) { printf("%s: %s\n", scenes[i], err); return 1; }
    elr_render_options_default(&o);
    o.spp = 1; o.quiet = 1; o.nthreads = nt;
    if (elr_render(s, &o, &im, NULL, err, sizeof err) != 0) { printf("%s: %s\n", scenes[i], err); return 1; }
    elr_image_free(&im);
    if (getenv("SUN_CLASSES_FROM")) { /* (classes from another scene of the same geometry: e.g. its map without the sun) */
      elr_scene *c2 = NULL;
      if (elr_scene_load(getenv("SUN_CLASSES_FROM"), &c2, 1, err, sizeof err) != 0 || elr_render(c2, &o, &im, NULL, err, sizeof err) != 0) {
        printf("%s\n", err); return 1;
      }
      elr_image_free(&im);
      cls = sm_classes(c2, &w, &h);
      elr_scene_free(c2);
    } else
      cls = sm_classes(s, &w, &h);
    if (!cls) { printf("%s: no hot spot\n", scenes[i]); elr_scene_free(s); continue; }
    if (sm_run(s, spp, ns, 0, nt, cls, w, h, &off) || sm_run(s, spp, ns, 1, nt, cls, w, h, &on)) return 1;
    toff = off.cpu / ns; ton = on.cpu / ns + on.st.t_sun_cpu;
    printf("%s (%dx%d, %s): cpu per render off %.3f s, on %.3f s (pilot %.3f s CPU); %.1f%% of the sun's light samples at lowered "
           "vertices, %.1f%% in a spot's cone (off: see --stats)\n",
           scenes[i], w, h, on.st.integrator_path ? "path" : "directlighting", toff, ton, on.st.t_sun_cpu,
           on.st.sun_looked ? 100.0 * (double)on.st.sun_lowered / (double)on.st.sun_looked : 0.0,
           on.st.sun_looked ? 100.0 * (double)on.st.sun_to_spot / (double)on.st.sun_looked : 0.0);
    for (c = 1; c <= 2; c++) {
      double g = on.var[c] > 0 ? off.var[c] / on.var[c] : 0;
      printf("  %-8s %6d px  mean off %.5g on %.5g (z %+.2f)  variance off %.4g on %.4g: %.2fx less at equal spp, %.2fx at equal time;"
             " median pixel's variance %.2fx less\n",
             c == 1 ? "shadowed" : "lit", on.n[c], off.mean[c], on.mean[c], sm_z(&on, &off, cls, w * h, c, ns), off.var[c], on.var[c], g,
             g * toff / ton, on.med[c] > 0 ? off.med[c] / on.med[c] : 0.0);
    }
    printf("  all pixels: z %+.2f\n", sm_z(&on, &off, cls, w * h, -1, ns));
    if (getenv("SUN_DUMP")) { /* (the per-pixel variance, off then on, side by side: sqrt scaled to the off image's 99th percentile... its max) */
      elr_image v;
      double mx = 0;
      int p2, x, y;
      char path[600];
      v.width = 2 * w; v.height = h; v.rgb = (float *)calloc((size_t)6 * (size_t)w * (size_t)h, sizeof(float));
      for (p2 = 0; p2 < w * h; p2++) if (cls[p2] == 1 && sqrt(off.v[p2]) > mx) mx = sqrt(off.v[p2]);
      for (y = 0; y < h; y++) for (x = 0; x < w; x++) {
        float a0 = (float)(sqrt(off.v[y * w + x]) / mx), a1 = (float)(sqrt(on.v[y * w + x]) / mx);
        float *q0 = &v.rgb[3 * (y * 2 * w + x)], *q1 = &v.rgb[3 * (y * 2 * w + w + x)];
        q0[0] = q0[1] = q0[2] = a0; q1[0] = q1[1] = q1[2] = a1;
        if (cls[y * w + x] == 1) { q0[0] *= 0.6f; q1[0] *= 0.6f; }
      }
      if (getenv("SUN_RATIO")) /* (instead: log2 of the variance ratio off / on, 3x3 box-averaged variances; green > 0, red < 0, 1 = 4x) */
        for (y = 0; y < h; y++) for (x = 0; x < w; x++) {
          double a0 = 0, a1 = 0, r;
          int dx, dy;
          float *q0 = &v.rgb[3 * (y * 2 * w + x)];
          for (dy = -1; dy <= 1; dy++) for (dx = -1; dx <= 1; dx++) {
            int xx = x + dx < 0 ? 0 : x + dx >= w ? w - 1 : x + dx, yy = y + dy < 0 ? 0 : y + dy >= h ? h - 1 : y + dy;
            a0 += off.v[yy * w + xx]; a1 += on.v[yy * w + xx];
          }
          r = a1 > 0 && a0 > 0 ? log2(a0 / a1) / 2 : 0;
          q0[0] = r < 0 ? (float)-r : 0.f; q0[1] = r > 0 ? (float)r : 0.f; q0[2] = cls[y * w + x] == 1 ? 0.3f : 0.f;
        }
      snprintf(path, sizeof path, "%s_%d.png", getenv("SUN_DUMP"), i);
      elr_image_write(&v, path, err, sizeof err);
      free(v.rgb);
    }
    sm_free(&off); sm_free(&on); free(cls);
    elr_scene_free(s);
  }
  return 0;
}
