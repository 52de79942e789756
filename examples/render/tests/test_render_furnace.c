/* test_render_furnace: white-furnace tests of the renderer (examples/render).
 *
 * 1. A diffuse sphere of albedo rho under a constant environment L: wherever the sphere covers a whole
 *    pixel, the reflected radiance is rho * L (the sphere is convex: every point sees the whole upper
 *    hemisphere of sky), and the background is L. With BSDF sampling only, every sample is exactly
 *    rho * L (cosine sampling cancels f cos / pdf), so pixels match to float precision. So with the
 *    environment's product sampling (the default): for a constant light el_envlight_sample_li_cos is
 *    cosine sampling, pdf cos / pi, so light sampling alone and MIS (both pdfs equal: weights 1/2) are
 *    exact too (a pdf_li_cos with another normal than the light sample's, or a density that is not the
 *    product, breaks that: seen). With the map alone (pbrt-v3's uniform sphere for a constant light),
 *    light sampling only and MIS converge to it.
 * 2. Inside a closed diffuse sphere of radius 1 with a point light of intensity I at its centre, the
 *    irradiance from the light is I / r^2 everywhere on the wall and the interior of a sphere spreads
 *    uniform radiance uniformly, so path tracing with maxdepth n gives
 *        L_n = (I / pi) * rho * (1 - rho^n) / (1 - rho)      (the geometric series),
 *    with zero variance up to bounce 4 (cosine sampling, exact NEE) and Russian roulette noise beyond. */
#include "render_test_util.h"

static const char *sphere_scene(char *buf, size_t n, float rho, const char *integrator) {
  snprintf(buf, n,
           "LookAt 0 0 -4  0 0 0  0 1 0\n"
           "Camera \"perspective\" \"float fov\" [ 40 ]\n"
           "Film \"image\" \"integer xresolution\" [ 32 ] \"integer yresolution\" [ 32 ]\n"
           "Sampler \"random\" \"integer pixelsamples\" [ 16 ]\n"
           "Integrator \"%s\"\n"
           "WorldBegin\n"
           "LightSource \"infinite\" \"rgb L\" [ 1 1 1 ]\n"
           "Material \"matte\" \"rgb Kd\" [ %g %g %g ]\n"
           "Shape \"sphere\" \"float radius\" 1\n"
           "WorldEnd\n", integrator, rho, rho, rho);
  return buf;
}

/* 1 inside the silhouette, 0 outside, -1 too close to call (independent pinhole maths) */
static int covered(int x, int y) {
  double t = tan(20.0 * 3.14159265358979 / 180.0), sx = -1 + (x + 0.5) / 32.0 * 2, sy = 1 - (y + 0.5) / 32.0 * 2;
  double dx = sx * t, dy = sy * t, ang = atan(sqrt(dx * dx + dy * dy)), a = asin(1.0 / 4.0);
  double pix = 2 * t / 32.0; /* about one pixel in angle (near the axis) */
  if (ang < a - 1.5 * pix) return 1;
  if (ang > a + 1.5 * pix) return 0;
  return -1;
}

static void convex_furnace(const char *integrator) {
  char buf[2048], err[512];
  elr_scene *s = rt_load("furnace.pbrt", sphere_scene(buf, sizeof buf, 0.5f, integrator), err, sizeof err);
  int ls, x, y, k;
  const char *names[5] = {"MIS", "light sampling only", "BSDF sampling only", "MIS, map alone", "light sampling only, map alone"};
  if (!s) { rt_check(0, "load furnace scene: %s", err); return; }
  for (k = 0; k < 5; k++) {
    elr_image img;
    elr_stats st;
    elr_render_options o;
    double sum = 0, maxerr = 0, bgerr = 0;
    int n = 0, nb = 0, exact = k < 3; /* product sampling: every sample exact */
    ls = k % 3;
    elr_render_options_default(&o);
    o.spp = exact ? 4 : 256; o.light_sampling = ls; o.nthreads = 2; o.seed = 7; o.quiet = 1; o.env_sampling = k < 3;
    if (elr_render(s, &o, &img, &st, err, sizeof err) != 0) { rt_check(0, "render: %s", err); continue; }
    for (y = 0; y < 32; y++)
      for (x = 0; x < 32; x++) {
        int c = covered(x, y), k;
        for (k = 0; k < 3; k++) {
          float v = img.rgb[3 * (y * 32 + x) + k];
          if (c == 1) { sum += v; n++; if (fabs(v - 0.5) > maxerr) maxerr = fabs(v - 0.5); }
          if (c == 0) { nb++; if (fabs(v - 1.0) > bgerr) bgerr = fabs(v - 1.0); }
        }
      }
    rt_check(n > 300 && nb > 300, "%s/%s: %d sphere and %d background pixel channels tested", integrator, names[k], n, nb);
    rt_check(bgerr < 1e-5, "%s/%s: background = L exactly (max error %.2g)", integrator, names[k], bgerr);
    if (exact) {
      rt_check(maxerr < 1e-4, "%s/%s: every sphere pixel = rho L = 0.5 (max error %.2g)", integrator, names[k], maxerr);
    } else {
      double mean = sum / n;
      rt_check(fabs(mean - 0.5) < 0.005, "%s/%s: mean over the sphere %.5f = rho L = 0.5 (+-1%%)", integrator, names[k], mean);
      rt_check(maxerr < 0.2, "%s/%s: every sphere pixel within 40%% of 0.5 (max error %.3f)", integrator, names[k], maxerr);
    }
    rt_check(st.light_sampling_used == 1 && st.distribution_built == (ls != 2), "%s/%s: light sampling used, distribution %s",
             integrator, names[k], ls != 2 ? "built" : "not built (BSDF sampling only)");
    if (ls != 2) rt_check(st.light[0].env_product == (k < 3), "%s/%s: --stats: %s", integrator, names[k], k < 3 ? "product sampling" : "the map alone");
    elr_image_free(&img);
  }
  elr_scene_free(s);
}

static void closed_sphere(void) {
  int depths[6] = {0, 1, 2, 3, 5, 8}, i;
  double rho = 0.5;
  for (i = 0; i < 6; i++) {
    char buf[2048], err[512];
    elr_scene *s;
    elr_image img;
    elr_stats st;
    int n = depths[i], k;
    double expect = n == 0 ? 0.0 : (1.0 / 3.14159265358979) * rho * (1 - pow(rho, n)) / (1 - rho), mean = 0, maxdev = 0;
    snprintf(buf, sizeof buf,
             "LookAt 0.2 0.1 -0.5  0.3 0.2 1  0 1 0\n"
             "Camera \"perspective\" \"float fov\" [ 60 ]\n"
             "Film \"image\" \"integer xresolution\" [ 16 ] \"integer yresolution\" [ 16 ]\n"
             "Sampler \"random\" \"integer pixelsamples\" [ 16 ]\n"
             "Integrator \"path\" \"integer maxdepth\" [ %d ]\n"
             "WorldBegin\n"
             "LightSource \"point\" \"rgb I\" [ 1 1 1 ] \"point from\" [ 0 0 0 ]\n"
             "Material \"matte\" \"rgb Kd\" [ %g %g %g ]\n"
             "Shape \"sphere\" \"float radius\" 1\n"
             "WorldEnd\n", n, rho, rho, rho);
    s = rt_load("closed.pbrt", buf, err, sizeof err);
    if (!s) { rt_check(0, "load closed sphere: %s", err); continue; }
    if (rt_render(s, n > 4 ? 64 : 4, -1, -1, 2, 3, &img, &st) != 0) { rt_check(0, "render"); elr_scene_free(s); continue; }
    for (k = 0; k < 16 * 16 * 3; k++) {
      mean += img.rgb[k];
      if (fabs(img.rgb[k] - expect) > maxdev) maxdev = fabs(img.rgb[k] - expect);
    }
    mean /= 16 * 16 * 3;
    if (n <= 4)
      rt_check(maxdev <= 1e-4 * (expect + 1e-3) * 10 + 1e-6, "closed sphere, maxdepth %d: every pixel %.6f = (I/pi) rho (1-rho^n)/(1-rho) = %.6f (max dev %.2g)",
               n, mean, expect, maxdev);
    else
      rt_check(fabs(mean - expect) < 0.005 * expect, "closed sphere, maxdepth %d: mean %.6f = %.6f within 0.5%% (Russian roulette beyond bounce 3)",
               n, mean, expect);
    if (n == 1) rt_check(st.bounce_rays == 0, "maxdepth 1: no bounce rays traced (%llu)", (unsigned long long)st.bounce_rays);
    elr_image_free(&img);
    elr_scene_free(s);
  }
}

/* 3. A distant light (pbrt-v3: radiance L arriving from direction from - to) on a matte plane: every
 * pixel on the plane is (rho / pi) L cos(theta), exactly (a delta light: no sampling noise); a sphere
 * standing on the plane casts a shadow in which the plane is black. */
static void distant(void) {
  char err[512], buf[2048];
  elr_scene *s;
  elr_image img;
  elr_stats st;
  double rho = 0.6, L = 2.0, c = cos(60.0 * 3.14159265358979 / 180.0), expect = rho / 3.14159265358979 * L * c, worst = 0;
  int x, y, lit = 0, dark = 0;
  snprintf(buf, sizeof buf,
           "LookAt 0 5 0  0 0 0  0 0 1\n"
           "Camera \"perspective\" \"float fov\" 60\n"
           "Film \"image\" \"integer xresolution\" 24 \"integer yresolution\" 24\n"
           "Sampler \"random\" \"integer pixelsamples\" 2\n"
           "Integrator \"directlighting\"\n"
           "WorldBegin\n"
           "LightSource \"distant\" \"point from\" [ 0 0 0 ] \"point to\" [ -0.8660254 -0.5 0 ] \"rgb L\" [ %g %g %g ]\n"
           "Material \"matte\" \"rgb Kd\" [ %g %g %g ]\n"
           "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point P\" [ -50 0 -50  50 0 -50  50 0 50  -50 0 50 ]\n"
           "Translate 0 1 0\nShape \"sphere\" \"float radius\" 0.5\n"
           "WorldEnd\n", L, L, L, rho, rho, rho);
  s = rt_load("distant.pbrt", buf, err, sizeof err);
  if (!s) { rt_check(0, "distant scene: %s", err); return; }
  if (rt_render(s, 0, -1, -1, 2, 1, &img, &st) == 0) {
    for (y = 0; y < 24; y++)
      for (x = 0; x < 24; x++) {
        double v = img.rgb[3 * (y * 24 + x)];
        if (fabs(v - expect) < 1e-4 * expect) lit++;
        else if (v == 0.0) dark++;
        else if (fabs(v - expect) > worst) worst = fabs(v - expect);
      }
    /* mixed pixels (sphere edge, shadow edge, sphere itself) are neither; most are lit plane */
    rt_check(lit > 300 && dark > 5, "distant light at 60 deg from the normal: %d plane pixels = rho L cos / pi = %.5f exactly, %d in shadow", lit,
             expect, dark);
    rt_check(st.distribution_built == 0 && st.shadow_rays > 0, "delta light only: no distribution, %llu shadow rays", (unsigned long long)st.shadow_rays);
    elr_image_free(&img);
  }
  elr_scene_free(s);
}

int main(void) {
  rt_mkdir("test_render_furnace");
  convex_furnace("directlighting");
  convex_furnace("path");
  closed_sphere();
  distant();
  return rt_finish("test_render_furnace");
}
