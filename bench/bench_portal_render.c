/* bench_portal_render.c: time to unit variance of the renderer (examples/render) on rooms lit through
 * windows, with pbrt-v4's "point3 portal" on the infinite light and without it (issue 23).
 *
 *   bench_portal_render [DEPTH [SPP [map|product [SEEDS [SHARE]]]]]   maxdepth (3), samples per pixel (16),
 *                       the light sampling of the no-portal render ("product", the renderer's default,
 *                       or "map"), the number of seeds per render (4, at most 64), the portal light's
 *                       "float portalmapshare" (the renderer's default when absent); LOOP=n in the
 *                       environment: both renders' loop (ELR_LOOP_*: 0 one at a time, 2 the wave
 *                       loop, the default for both)
 *
 * For each case (a room with one window under data/envmaps/city.hdr, its sun shining in; the same
 * under data/envmaps/overcast.pfm; a room with two windows and a sphere outside under city.hdr): a
 * reference at 16x SPP with the portal, then SEEDS seeds with and without the portal at SPP, the two
 * renders interleaved. Printed: the image means (unbiased: they agree within their noise), the least CPU
 * seconds of a render loop over the seeds (the same work each time: the least is the one the machine's
 * load disturbed least), the variance of a pixel (over the seeds, the mean over pixels) and the time to
 * unit variance, variance x CPU time, as its ratio (no portal / portal: the gain); then the same with
 * the MSE against the reference (which also holds what does not change with the seed: a conservative
 * gain). 80 x 60 pixels, 2 threads. Run from the build directory or the repository's root. */
#include "../examples/render/el_render.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *WALLS =
    "Material \"matte\" \"rgb Kd\" [ 0.6 0.6 0.6 ]\n"
    "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point P\" [ -2 0 -2  2 0 -2  2 0 2  -2 0 2 ]\n"
    "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point P\" [ -2 2.6 -2  2 2.6 -2  2 2.6 2  -2 2.6 2 ]\n"
    "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point P\" [ -2 0 -2  -2 2.6 -2  -2 2.6 2  -2 0 2 ]\n"
    "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point P\" [ -2 0 2  2 0 2  2 2.6 2  -2 2.6 2 ]\n"
    "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point P\" [ 2 0 -2  2 1.2 -2  2 1.2 2  2 0 2 ]\n"
    "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point P\" [ 2 2.2 -2  2 2.6 -2  2 2.6 2  2 2.2 2 ]\n"
    "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point P\" [ 2 1.2 -2  2 2.2 -2  2 2.2 -0.8  2 1.2 -0.8 ]\n"
    "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point P\" [ 2 1.2 0.4  2 2.2 0.4  2 2.2 2  2 1.2 2 ]\n";
/* the wall z = -2: whole, or with a second window (x -1..0, y 1.2..2.2) and a sphere outside */
static const char *WALL_Z = "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point P\" [ -2 0 -2  2 0 -2  2 2.6 -2  -2 2.6 -2 ]\n";
static const char *WALL_Z_WINDOW =
    "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point P\" [ -2 0 -2  2 0 -2  2 1.2 -2  -2 1.2 -2 ]\n"
    "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point P\" [ -2 2.2 -2  2 2.2 -2  2 2.6 -2  -2 2.6 -2 ]\n"
    "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point P\" [ -2 1.2 -2  -1 1.2 -2  -1 2.2 -2  -2 2.2 -2 ]\n"
    "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point P\" [ 0 1.2 -2  2 1.2 -2  2 2.2 -2  0 2.2 -2 ]\n"
    "AttributeBegin\n Translate 3.2 1.4 -0.2\n Material \"matte\" \"rgb Kd\" [ 0.2 0.5 0.2 ]\n Shape \"sphere\" \"float radius\" 0.5\nAttributeEnd\n";
static const char *PORTAL1 = "2 1.2 0.4   2 2.2 0.4   2 2.2 -0.8   2 1.2 -0.8";
static const char *PORTAL2 = "0 1.2 -2   0 2.2 -2   -1 2.2 -2   -1 1.2 -2";

static char g_dir[512] = "data";
static char g_share[64] = "";
static elr_scene *load(const char *map, int two, int portal, int depth, const char *sampling) {
  static char text[16384];
  char err[512], path[600];
  elr_scene *s = NULL;
  FILE *f;
  snprintf(text, sizeof text,
           "LookAt -1.8 1.5 1.8   1 0.5 -0.8   0 1 0\nCamera \"perspective\" \"float fov\" [ 62 ]\n"
           "Film \"image\" \"integer xresolution\" [ 80 ] \"integer yresolution\" [ 60 ]\n"
           "Sampler \"halton\" \"integer pixelsamples\" [ 16 ]\nIntegrator \"path\" \"integer maxdepth\" [ %d ]\nWorldBegin\n"
           "AttributeBegin\n Rotate -90 1 0 0\n Rotate 120 0 0 1\n LightSource \"infinite\" \"string mapname\" \"%s/envmaps/%s\"\n"
           "  \"string sampling\" \"%s\"%s%s%s%s%s%s\nAttributeEnd\n%s%sWorldEnd\n",
           depth, g_dir, map, sampling, portal ? g_share : "", portal ? " \"point3 portal\" [ " : "", portal ? PORTAL1 : "", portal && two ? "   " : "",
           portal && two ? PORTAL2 : "", portal ? " ]" : "", WALLS, two ? WALL_Z_WINDOW : WALL_Z);
  snprintf(path, sizeof path, "bench_portal_render_scene.pbrt");
  f = fopen(path, "wb");
  if (!f) { perror(path); exit(1); }
  fputs(text, f);
  fclose(f);
  if (elr_scene_load(path, &s, 1, err, sizeof err) != 0) { fprintf(stderr, "bench_portal_render: %s\n", err); exit(1); }
  remove(path);
  return s;
}
static int g_loop = -1;
static double render(elr_scene *s, int spp, uint64_t seed, elr_image *img) {
  elr_render_options o;
  elr_stats st;
  char err[512];
  elr_render_options_default(&o);
  o.spp = spp; o.nthreads = 2; o.seed = seed; o.quiet = 1; o.loop = g_loop;
  if (elr_render(s, &o, img, &st, err, sizeof err) != 0) { fprintf(stderr, "bench_portal_render: %s\n", err); exit(1); }
  return st.t_render_cpu;
}
static double mean(const elr_image *a) {
  double m = 0;
  int i;
  for (i = 0; i < a->width * a->height * 3; ++i) m += a->rgb[i];
  return m / (a->width * a->height * 3);
}
static double mse(const elr_image *a, const elr_image *b) {
  double m = 0;
  int i;
  for (i = 0; i < a->width * a->height * 3; ++i) m += (a->rgb[i] - b->rgb[i]) * (a->rgb[i] - b->rgb[i]);
  return m / (a->width * a->height * 3);
}

int main(int argc, char **argv) {
  int depth = argc > 1 ? atoi(argv[1]) : 3, spp = argc > 2 ? atoi(argv[2]) : 16, c, k;
  const char *sampling = argc > 3 ? argv[3] : "product";
  int ns = argc > 4 ? atoi(argv[4]) : 4;
  if (ns < 2 || ns > 64) ns = 4;
  if (argc > 5) snprintf(g_share, sizeof g_share, " \"float portalmapshare\" %g", atof(argv[5]));
  if (getenv("LOOP")) g_loop = atoi(getenv("LOOP"));
  static const char *maps[3] = {"city.hdr", "overcast.pfm", "city.hdr"};
  static const char *names[3] = {"one window, city (sun in)", "one window, overcast", "two windows + sphere outside, city"};
  FILE *probe = fopen("data/envmaps/city.hdr", "rb");
  if (!probe) snprintf(g_dir, sizeof g_dir, "../data");
  else fclose(probe);
  printf("maxdepth %d, %d spp (reference %d spp with the portal), no-portal light sampling \"%s\"; 80x60, %d seeds; CPU seconds\n", depth, spp,
         16 * spp, sampling, ns);
  if (g_share[0]) printf("portal light:%s\n", g_share);
  printf("%-36s %10s %10s %10s %10s %8s %8s %10s %10s %7s %10s %10s %7s\n", "scene", "mean P", "mean no-P", "sd P", "sd no-P", "cpu P",
         "cpu no-P", "pixvar P", "pixvar noP", "gain", "MSE P", "MSE no-P", "gain");
  for (c = 0; c < 3; ++c) {
    elr_scene *sp = load(maps[c], c == 2, 1, depth, sampling), *sn = load(maps[c], c == 2, 0, depth, sampling);
    elr_image ref, a, b;
    double mp[64], mn[64], rm, ep = 0, en = 0, tp = 0, tn = 0, ap = 0, an = 0, vp = 0, vn = 0, pvp = 0, pvn = 0;
    double *s1p = NULL, *s2p = NULL, *s1n = NULL, *s2n = NULL;
    size_t np = 0, i;
    render(sp, 16 * spp, 1000, &ref);
    rm = mean(&ref);
    for (k = 0; k < ns; ++k) {
      { /* the least CPU time over the seeds (the same work each time: the least is the one the load
         * disturbed least; the two renders interleaved) */
        double t1 = render(sp, spp, (uint64_t)k + 1, &a), t2 = render(sn, spp, (uint64_t)k + 1, &b);
        if (k == 0 || t1 < tp) tp = t1;
        if (k == 0 || t2 < tn) tn = t2;
      }
      if (!s1p) {
        np = (size_t)a.width * (size_t)a.height * 3;
        s1p = (double *)calloc(np, sizeof(double)); s2p = (double *)calloc(np, sizeof(double));
        s1n = (double *)calloc(np, sizeof(double)); s2n = (double *)calloc(np, sizeof(double));
      }
      for (i = 0; i < np; ++i) {
        s1p[i] += a.rgb[i]; s2p[i] += (double)a.rgb[i] * a.rgb[i];
        s1n[i] += b.rgb[i]; s2n[i] += (double)b.rgb[i] * b.rgb[i];
      }
      mp[k] = mean(&a); mn[k] = mean(&b); ap += mp[k] / ns; an += mn[k] / ns;
      ep += mse(&a, &ref) / ns; en += mse(&b, &ref) / ns;
      elr_image_free(&a); elr_image_free(&b);
    }
    for (k = 0; k < ns; ++k) { vp += (mp[k] - ap) * (mp[k] - ap) / (ns * (ns - 1.0)); vn += (mn[k] - an) * (mn[k] - an) / (ns * (ns - 1.0)); }
    for (i = 0; i < np; ++i) { /* per pixel: the sample variance over the seeds */
      pvp += (s2p[i] - s1p[i] * s1p[i] / ns) / (ns - 1.0) / (double)np;
      pvn += (s2n[i] - s1n[i] * s1n[i] / ns) / (ns - 1.0) / (double)np;
    }
    printf("%-36s %10.5g %10.5g %10.2g %10.2g %8.3f %8.3f %10.3g %10.3g %6.1fx %10.3g %10.3g %6.1fx\n", names[c], ap, an, sqrt(vp), sqrt(vn), tp, tn,
           pvp, pvn, (pvn * tn) / (pvp * tp), ep, en, (en * tn) / (ep * tp));
    printf("%-36s reference mean %.5g; difference of the means %.2f sd\n", "", rm, (ap - an) / sqrt(vp + vn));
    free(s1p); free(s2p); free(s1n); free(s2n);
    elr_image_free(&ref);
    elr_scene_free(sp); elr_scene_free(sn);
  }
  printf("(MSE against the reference includes the reference's own noise, 1/16 of the portal's at SPP; a shared, loaded machine)\n");
  return 0;
}
