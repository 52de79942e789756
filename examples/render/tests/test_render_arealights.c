/* test_render_arealights: pbrt-v3's diffuse area lights (lights.c, shapes.c, lightdistrib.c) against
 * answers worked out here, never produced by the renderer:
 *  - a sphere light over a white plane: the irradiance from a uniformly emitting sphere of radius r,
 *    centre at distance D, seen entirely above the horizon, is E = pi L (r / D)^2 cos(beta) (beta between
 *    the normal and the direction to the centre), so a Lambertian plane of albedo rho shows
 *    Lo = rho L (r / D)^2 cos(beta); inside a sphere that emits inwards, Lo = rho L;
 *  - a quad light: Lambert's formula for the irradiance from a polygon, E = L / 2 sum_k theta_k
 *    (n . unit(v_k x v_k+1)); one-sided it lights the plane only when its normal faces it
 *    (ReverseOrientation turns it around; normals given with "N" decide the side); two-sided always;
 *  - a disk and an annulus light: the parallel disk's form factor
 *    F = (1 - (h^2 + x^2 - R^2) / sqrt((h^2 + x^2 + R^2)^2 - 4 R^2 x^2)) / 2, Lo = rho L F (an annulus:
 *    F(R) - F(innerradius));
 *  - the camera sees a one-sided emitter's L from its front and nothing from its back;
 *  - light sampling only, BSDF sampling only and MIS (power heuristic), the "uniform" and "power" light
 *    sample strategies and the directlighting strategies "one" and "all" converge to the same image on a
 *    scene with every kind of light (environment, point, quad, sphere, ellipsoid, partial disk);
 *  - what is built: nothing for a scene where nothing emits (no ray traced, one warning), the area CDF
 *    only for a sampled mesh light, no light distribution for one light.
 *
 * The statistics (pixels have independent random streams: Sampler "random"). Against an analytic image
 * e, two renders a and b of different seeds give the per-pixel relative noise sigma^2 = mean((a - b)^2 /
 * (2 e^2)); the bias test asks the mean of ((a + b) / 2 - e) / e to lie within 4 sigma / sqrt(2 N) of 0,
 * the shape test asks the RMS of (a - e) / e to stay below 1.25 sigma + 0.002 (a spatially wrong
 * answer inflates it; for N = 1024 pixels the RMS of pure noise exceeds 1.25 sigma with a probability
 * far below 1e-6). Two estimators of the same image, A and B: the mean of d = A - B over N pixels lies
 * within 4 standard errors (the pixels' own spread of d) of 0. */
#include "render_test_util.h"

#define RES 32

/* >> the analytic images (the plane y = 0, albedo rho, seen straight down from height hc with fov 90:
 * pixel (i, j) covers plane points hc (sx, sy), screen coordinates sx, sy in [-1, 1]) */
typedef double (*lo_fn)(double x, double z, const double *prm);
static void analytic(lo_fn f, const double *prm, double hc, double *e) {
  int i, j, a, b;
  for (j = 0; j < RES; j++)
    for (i = 0; i < RES; i++) {
      double s = 0;
      for (b = 0; b < 8; b++)
        for (a = 0; a < 8; a++) { /* the mean over the pixel (the box filter of radius 0.5) */
          double sx = -1.0 + 2.0 * (i + (a + 0.5) / 8.0) / RES, sy = 1.0 - 2.0 * (j + (b + 0.5) / 8.0) / RES;
          s += f(hc * sx, hc * sy, prm);
        }
      e[j * RES + i] = s / 64.0;
    }
}
/* sphere: prm = rho, L, r, h (centre above the origin) */
static double lo_sphere(double x, double z, const double *p) {
  double D2 = x * x + z * z + p[3] * p[3], D = sqrt(D2);
  return p[0] * p[1] * p[2] * p[2] / D2 * (p[3] / D);
}
/* a polygon of 4 vertices prm[2..13] (x y z), Lambert's formula; prm = rho, L */
static double lo_quad(double x, double z, const double *p) {
  double v[4][3], s = 0;
  int k, c;
  for (k = 0; k < 4; k++) {
    double d[3] = {p[2 + 3 * k] - x, p[3 + 3 * k], p[4 + 3 * k] - z}, l = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for (c = 0; c < 3; c++) v[k][c] = d[c] / l;
  }
  for (k = 0; k < 4; k++) {
    const double *a = v[k], *b = v[(k + 1) % 4];
    double cr[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
    double cl = sqrt(cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]), th = acos(a[0] * b[0] + a[1] * b[1] + a[2] * b[2]);
    s += th * cr[1] / cl; /* n = (0, 1, 0) */
  }
  return p[0] / 3.14159265358979323846 * p[1] * 0.5 * fabs(s);
}
/* a disk or annulus parallel to the plane: prm = rho, L, R, h, inner radius */
static double ff_disk(double R, double h, double x) {
  return 0.5 * (1.0 - (h * h + x * x - R * R) / sqrt((h * h + x * x + R * R) * (h * h + x * x + R * R) - 4.0 * R * R * x * x));
}
static double lo_disk(double x, double z, const double *p) {
  double r = sqrt(x * x + z * z);
  return p[0] * p[1] * (ff_disk(p[2], p[3], r) - (p[4] > 0 ? ff_disk(p[4], p[3], r) : 0.0));
}

/* >> rendering and the statistics */
static int render(elr_scene *s, int spp, int ls, uint64_t seed, double *img) {
  elr_image im;
  elr_stats st;
  int k;
  if (rt_render(s, spp, ls, -1, 2, seed, &im, &st) != 0) return -1;
  for (k = 0; k < im.width * im.height; k++) img[k] = im.rgb[3 * k];
  elr_image_free(&im);
  return 0;
}
static void against_analytic(const char *what, elr_scene *s, int spp, int ls, const double *e) {
  static double a[RES * RES], b[RES * RES];
  double s2 = 0, bias = 0, rms = 0, sig, z;
  int k, n = 0;
  if (!s || render(s, spp, ls, 1, a) || render(s, spp, ls, 2, b)) { rt_check(0, "%s: render", what); return; }
  for (k = 0; k < RES * RES; k++) {
    if (!(e[k] > 1e-6)) continue;
    s2 += (a[k] - b[k]) * (a[k] - b[k]) / (2 * e[k] * e[k]);
    bias += (0.5 * (a[k] + b[k]) - e[k]) / e[k];
    rms += (a[k] - e[k]) * (a[k] - e[k]) / (e[k] * e[k]);
    n++;
  }
  sig = sqrt(s2 / n); bias /= n; rms = sqrt(rms / n);
  z = bias / (sig / sqrt(2.0 * n));
  rt_check(n > RES * RES / 2 && fabs(z) < 4 && rms < 1.25 * sig + 0.002,
           "%s: mean relative error %+.4f%% (%.1f standard errors), RMS %.3f%% for a noise of %.3f%% per pixel", what, 100 * bias, z, 100 * rms,
           100 * sig);
}
static void same_mean(const char *what, elr_scene *s, int spp_a, int ls_a, int spp_b, int ls_b) {
  static double a[RES * RES], b[RES * RES];
  double m = 0, m2 = 0, ma = 0, se;
  int k, N = RES * RES;
  if (!s || render(s, spp_a, ls_a, 3, a) || render(s, spp_b, ls_b, 4, b)) { rt_check(0, "%s: render", what); return; }
  for (k = 0; k < N; k++) { double d = a[k] - b[k]; m += d; m2 += d * d; ma += a[k]; }
  m /= N; ma /= N;
  se = sqrt((m2 / N - m * m) / (N - 1));
  rt_check(ma > 0 && fabs(m) < 4 * se, "%s: image means differ by %+.3f%% (%.1f standard errors of %.3f%%)", what, 100 * m / ma, m / se, 100 * se / ma);
}

static const char *scene(const char *integ, const char *body) {
  static char buf[8192];
  snprintf(buf, sizeof buf,
           "LookAt 0 %s 0  0 0 0  0 0 1\nCamera \"perspective\" \"float fov\" 90\n"
           "Film \"image\" \"integer xresolution\" %d \"integer yresolution\" %d\n"
           "Sampler \"random\" \"integer pixelsamples\" 16\nIntegrator %s\nWorldBegin\n"
           "Material \"matte\" \"rgb Kd\" [ 0.5 0.5 0.5 ]\n"
           "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point P\" [ -20 0 -20  -20 0 20  20 0 20  20 0 -20 ]\n%sWorldEnd\n",
           strstr(body, "HC1") ? "1" : "2", RES, RES, integ, body);
  return buf;
}

static void sphere_light(void) {
  char err[512];
  double prm[4] = {0.5, 10.0, 0.5, 3.0};
  static double e[RES * RES];
  elr_scene *s;
  analytic(lo_sphere, prm, 2.0, e);
  s = rt_load("sph.pbrt", scene("\"directlighting\"", "AttributeBegin\nTranslate 0 3 0\nAreaLightSource \"diffuse\" \"rgb L\" [ 10 10 10 ]\n"
                                                        "Shape \"sphere\" \"float radius\" 0.5\nAttributeEnd\n"), err, sizeof err);
  if (!s) { rt_check(0, "sphere scene: %s", err); return; }
  against_analytic("sphere light, directlighting, MIS", s, 64, ELR_LS_MIS, e);
  against_analytic("sphere light, light sampling only (the cone it subtends)", s, 64, ELR_LS_LIGHT, e);
  against_analytic("sphere light, BSDF sampling only", s, 1024, ELR_LS_BSDF, e);
  elr_scene_free(s);
  /* the same with a Scale 2 on the sphere: a similarity, radius 1 in world space */
  prm[2] = 1.0;
  analytic(lo_sphere, prm, 2.0, e);
  s = rt_load("sph2.pbrt", scene("\"path\" \"integer maxdepth\" 1", "AttributeBegin\nTranslate 0 3 0\nScale 2 2 2\n"
                                                        "AreaLightSource \"area\" \"rgb L\" [ 10 10 10 ]\nShape \"sphere\" \"float radius\" 0.5\nAttributeEnd\n"),
              err, sizeof err);
  against_analytic("sphere light (Scale 2), path tracer, maxdepth 1", s, 64, ELR_LS_MIS, e);
  elr_scene_free(s);
  /* inside a sphere that emits inwards (ReverseOrientation): a uniform sphere of directions of radiance L,
   * so the plane shows rho L everywhere; the sphere is sampled by area from inside */
  {
    int k;
    for (k = 0; k < RES * RES; k++) e[k] = 0.5 * 2.0;
    s = rt_load("inside.pbrt", scene("\"directlighting\"", "AttributeBegin\nReverseOrientation\nAreaLightSource \"diffuse\" \"rgb L\" [ 2 2 2 ]\n"
                                                             "Shape \"sphere\" \"float radius\" 10\nAttributeEnd\n"), err, sizeof err);
    against_analytic("inside a sphere light emitting inwards, MIS", s, 64, ELR_LS_MIS, e);
    against_analytic("inside a sphere light emitting inwards, light sampling only", s, 64, ELR_LS_LIGHT, e);
    elr_scene_free(s);
    /* without ReverseOrientation it emits outwards: nothing reaches the plane inside */
    s = rt_load("inside0.pbrt", scene("\"directlighting\"", "AreaLightSource \"diffuse\" \"rgb L\" [ 2 2 2 ]\nShape \"sphere\" \"float radius\" 10\n"),
                err, sizeof err);
    if (s && render(s, 4, ELR_LS_MIS, 1, e) == 0) {
      double m = 0;
      for (k = 0; k < RES * RES; k++) m = fmax(m, e[k]);
      rt_check(m == 0.0, "inside a one-sided sphere light emitting outwards: black (max %g)", m);
    } else rt_check(0, "inside0: %s", err);
    elr_scene_free(s);
  }
}

static void quad_light(void) {
  /* a 1 x 1 quad at height 1.5 over the plane, seen from height 1 */
  static const char *variants[6][2] = {
      /* the quad's geometric normal (p0 - p2) x (p1 - p2) points down: one-sided, it lights the plane */
      {"one-sided, normal down", "AreaLightSource \"diffuse\" \"rgb L\" [ 5 5 5 ]\n"},
      {"one-sided, ReverseOrientation (normal up): dark", "ReverseOrientation\nAreaLightSource \"diffuse\" \"rgb L\" [ 5 5 5 ]\n"},
      {"two-sided", "AreaLightSource \"diffuse\" \"rgb L\" [ 5 5 5 ] \"bool twosided\" \"true\"\n"},
      {"two-sided, ReverseOrientation", "ReverseOrientation\nAreaLightSource \"diffuse\" \"rgb L\" [ 5 5 5 ] \"bool twosided\" \"true\"\n"},
      {"one-sided, normals \"N\" up (they decide): dark", "AreaLightSource \"diffuse\" \"rgb L\" [ 5 5 5 ]\n"},
      {"one-sided, normals \"N\" up, ReverseOrientation", "ReverseOrientation\nAreaLightSource \"diffuse\" \"rgb L\" [ 5 5 5 ]\n"}};
  static const int lit[6] = {1, 0, 1, 1, 0, 1};
  double prm[14] = {0.5, 5.0, -0.5, 1.5, -0.5, -0.5, 1.5, 0.5, 0.5, 1.5, 0.5, 0.5, 1.5, -0.5};
  static double e[RES * RES];
  char err[512], body[1024];
  int v, k;
  analytic(lo_quad, prm, 1.0, e);
  for (v = 0; v < 6; v++) {
    elr_scene *s;
    snprintf(body, sizeof body, "# HC1\nAttributeBegin\n%sShape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ]\n"
                                "  \"point P\" [ -0.5 1.5 -0.5  0.5 1.5 -0.5  0.5 1.5 0.5  -0.5 1.5 0.5 ]%s\nAttributeEnd\n",
             variants[v][1], v >= 4 ? " \"normal N\" [ 0 1 0  0 1 0  0 1 0  0 1 0 ]" : "");
    s = rt_load("quad.pbrt", scene("\"directlighting\"", body), err, sizeof err);
    if (!s) { rt_check(0, "quad %d: %s", v, err); continue; }
    if (lit[v]) {
      char what[200];
      snprintf(what, sizeof what, "quad light, %s, MIS", variants[v][0]);
      against_analytic(what, s, 64, ELR_LS_MIS, e);
      if (v == 0) {
        against_analytic("quad light, one-sided, light sampling only", s, 64, ELR_LS_LIGHT, e);
        against_analytic("quad light, one-sided, BSDF sampling only", s, 256, ELR_LS_BSDF, e);
      }
    } else {
      static double img[RES * RES];
      double m = 0;
      if (render(s, 16, ELR_LS_MIS, 1, img) == 0)
        for (k = 0; k < RES * RES; k++) m = fmax(m, img[k]);
      rt_check(m == 0.0, "quad light, %s (max %g)", variants[v][0], m);
    }
    elr_scene_free(s);
  }
  /* the path tracer on the two-sided quad (maxdepth 1: the direct light alone) */
  {
    elr_scene *s = rt_load("quadp.pbrt", scene("\"path\" \"integer maxdepth\" 1 \"string lightsamplestrategy\" \"uniform\"",
                                               "# HC1\nAttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [ 5 5 5 ] \"bool twosided\" \"true\"\n"
                                               "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ]\n"
                                               "  \"point P\" [ -0.5 1.5 -0.5  0.5 1.5 -0.5  0.5 1.5 0.5  -0.5 1.5 0.5 ]\nAttributeEnd\n"),
                           err, sizeof err);
    against_analytic("quad light, two-sided, path tracer", s, 64, ELR_LS_MIS, e);
    elr_scene_free(s);
  }
  /* the camera sees the emitting side's L and nothing behind it (directlighting and path) */
  {
    int c, integ;
    for (integ = 0; integ < 2; integ++)
      for (c = 0; c < 2; c++) {
        char buf[2048];
        elr_scene *s;
        elr_image im;
        elr_stats st;
        snprintf(buf, sizeof buf, "LookAt 0 %s 0  0 1.5 0  0 0 1\nCamera \"perspective\" \"float fov\" 30\n"
                                  "Film \"image\" \"integer xresolution\" 4 \"integer yresolution\" 4\nIntegrator \"%s\"\nWorldBegin\n"
                                  "AreaLightSource \"diffuse\" \"rgb L\" [ 5 4 3 ]\nShape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ]\n"
                                  "  \"point P\" [ -0.5 1.5 -0.5  0.5 1.5 -0.5  0.5 1.5 0.5  -0.5 1.5 0.5 ]\nWorldEnd\n",
                 c ? "3" : "0", integ ? "path" : "directlighting");
        s = rt_load("see.pbrt", buf, err, sizeof err);
        if (s && rt_render(s, 4, -1, -1, 1, 1, &im, &st) == 0) {
          float *p = im.rgb + 3 * 5;
          if (!c) rt_check(p[0] == 5.f && p[1] == 4.f && p[2] == 3.f, "%s: the camera sees the emitting side's L (%g %g %g)", integ ? "path" : "directlighting", p[0], p[1], p[2]);
          else /* (its material reflects the light's own samples at grazing angles: 2e-12) */
            rt_check(p[0] < 1e-6f && p[1] < 1e-6f && p[2] < 1e-6f, "%s: the camera sees the back of a one-sided emitter black (%g)", integ ? "path" : "directlighting", p[0]);
          elr_image_free(&im);
        } else rt_check(0, "see: %s", err);
        elr_scene_free(s);
      }
  }
}

static void disk_light(void) {
  char err[512];
  double prm[5] = {0.5, 4.0, 0.6, 1.5, 0.0};
  static double e[RES * RES];
  elr_scene *s;
  /* Rotate 90 about x takes the disk's +z to -y: it faces the plane */
  analytic(lo_disk, prm, 1.0, e);
  s = rt_load("disk.pbrt", scene("\"directlighting\"", "# HC1\nAttributeBegin\nTranslate 0 1.5 0\nRotate 90 1 0 0\n"
                                                         "AreaLightSource \"diffuse\" \"rgb L\" [ 4 4 4 ]\nShape \"disk\" \"float radius\" 0.6\nAttributeEnd\n"),
              err, sizeof err);
  against_analytic("disk light, MIS", s, 64, ELR_LS_MIS, e);
  against_analytic("disk light, light sampling only", s, 64, ELR_LS_LIGHT, e);
  elr_scene_free(s);
  /* an annulus, placed by "height" instead of a translation */
  prm[4] = 0.3;
  analytic(lo_disk, prm, 1.0, e);
  s = rt_load("annulus.pbrt", scene("\"directlighting\"", "# HC1\nAttributeBegin\nRotate 90 1 0 0\nAreaLightSource \"diffuse\" \"rgb L\" [ 4 4 4 ]\n"
                                                            "Shape \"disk\" \"float radius\" 0.6 \"float innerradius\" 0.3 \"float height\" -1.5\nAttributeEnd\n"),
              err, sizeof err);
  against_analytic("annulus light (innerradius 0.3), light sampling only", s, 64, ELR_LS_LIGHT, e);
  against_analytic("annulus light, BSDF sampling only", s, 512, ELR_LS_BSDF, e);
  elr_scene_free(s);
}

/* >> every light together: the estimators agree */
static void strategies(void) {
  static const char *body =
      "AttributeBegin\nRotate -90 1 0 0\nLightSource \"infinite\" \"rgb L\" [ 0.3 0.35 0.4 ]\nAttributeEnd\n"
      "LightSource \"point\" \"point from\" [ 1.5 1.2 0.5 ] \"rgb I\" [ 1 0.8 0.6 ]\n"
      "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [ 3 3 3 ]\n"
      "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point P\" [ -1.6 1.4 -0.6  -1.0 1.4 -0.6  -1.0 1.4 0.6  -1.6 1.4 0.6 ]\nAttributeEnd\n"
      "AttributeBegin\nTranslate 0.9 1.1 -0.9\nAreaLightSource \"diffuse\" \"rgb L\" [ 2 4 2 ]\nShape \"sphere\" \"float radius\" 0.25\nAttributeEnd\n"
      "AttributeBegin\nTranslate -0.8 1.0 1.0\nScale 0.4 0.15 0.3\nAreaLightSource \"diffuse\" \"rgb L\" [ 4 2 2 ]\nShape \"sphere\"\nAttributeEnd\n"
      "AttributeBegin\nTranslate 0.6 1.3 1.0\nRotate 70 1 0 0\nAreaLightSource \"diffuse\" \"rgb L\" [ 3 3 5 ] \"bool twosided\" \"true\"\n"
      "Shape \"disk\" \"float radius\" 0.4 \"float innerradius\" 0.1 \"float phimax\" 270\nAttributeEnd\n"
      "AttributeBegin\nTranslate -0.3 0.35 0\nMaterial \"plastic\" \"rgb Kd\" [ 0.3 0.3 0.6 ] \"rgb Ks\" [ 0.5 0.5 0.5 ] \"float roughness\" 0.2\n"
      "Shape \"sphere\" \"float radius\" 0.35\nAttributeEnd\n";
  char buf[8192], err[512];
  elr_scene *s;
  int k;
  for (k = 0; k < 3; k++) {
    static const char *integ[3] = {"\"path\" \"integer maxdepth\" 3 \"string lightsamplestrategy\" \"power\"",
                                   "\"path\" \"integer maxdepth\" 3 \"string lightsamplestrategy\" \"uniform\"", "\"directlighting\""};
    snprintf(buf, sizeof buf, "LookAt 0 3 -3  0 0.3 0  0 1 0\nCamera \"perspective\" \"float fov\" 60\n"
                              "Film \"image\" \"integer xresolution\" %d \"integer yresolution\" %d\nSampler \"random\"\nIntegrator %s\nWorldBegin\n"
                              "Material \"matte\" \"rgb Kd\" [ 0.6 0.6 0.6 ]\n"
                              "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point P\" [ -3 0 -3  -3 0 3  3 0 3  3 0 -3 ]\n%sWorldEnd\n",
             RES, RES, integ[k], body);
    s = rt_load("all.pbrt", buf, err, sizeof err);
    if (!s) { rt_check(0, "every light: %s", err); return; }
    if (k == 0) {
      same_mean("path, power: light sampling only vs MIS", s, 256, ELR_LS_LIGHT, 256, ELR_LS_MIS);
      same_mean("path, power: BSDF sampling only vs MIS", s, 1024, ELR_LS_BSDF, 256, ELR_LS_MIS);
    } else if (k == 1) {
      elr_scene *p;
      snprintf(buf, sizeof buf, "LookAt 0 3 -3  0 0.3 0  0 1 0\nCamera \"perspective\" \"float fov\" 60\n"
                                "Film \"image\" \"integer xresolution\" %d \"integer yresolution\" %d\nSampler \"random\"\nIntegrator %s\nWorldBegin\n"
                                "Material \"matte\" \"rgb Kd\" [ 0.6 0.6 0.6 ]\n"
                                "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point P\" [ -3 0 -3  -3 0 3  3 0 3  3 0 -3 ]\n%sWorldEnd\n",
               RES, RES, integ[0], body);
      p = rt_load("allp.pbrt", buf, err, sizeof err);
      { /* uniform (this scene) against power (p): one image each */
        static double a[RES * RES], b[RES * RES];
        double m = 0, m2 = 0, ma = 0, se;
        int i, N = RES * RES;
        if (p && render(s, 256, ELR_LS_MIS, 5, a) == 0 && render(p, 256, ELR_LS_MIS, 6, b) == 0) {
          for (i = 0; i < N; i++) { double d = a[i] - b[i]; m += d; m2 += d * d; ma += a[i]; }
          m /= N; ma /= N; se = sqrt((m2 / N - m * m) / (N - 1));
          rt_check(fabs(m) < 4 * se, "path: \"uniform\" vs \"power\" light sample strategy: means differ by %+.3f%% (%.1f standard errors)", 100 * m / ma, m / se);
        } else rt_check(0, "uniform vs power: %s", err);
        elr_scene_free(p);
      }
      same_mean("path, uniform: light sampling only vs MIS", s, 256, ELR_LS_LIGHT, 256, ELR_LS_MIS);
    } else {
      same_mean("directlighting: light sampling only vs MIS", s, 128, ELR_LS_LIGHT, 128, ELR_LS_MIS);
      same_mean("directlighting: BSDF sampling only vs MIS", s, 1024, ELR_LS_BSDF, 128, ELR_LS_MIS);
      { /* strategy "one" against "all" */
        elr_scene *o;
        static double a[RES * RES], b[RES * RES];
        char *q = strstr(buf, "\"directlighting\"");
        memmove(q + strlen("\"directlighting\" \"string strategy\" \"one\""), q + strlen("\"directlighting\""), strlen(q + strlen("\"directlighting\"")) + 1);
        memcpy(q, "\"directlighting\" \"string strategy\" \"one\"", strlen("\"directlighting\" \"string strategy\" \"one\""));
        o = rt_load("one.pbrt", buf, err, sizeof err);
        if (o && o->d.direct_one && render(o, 512, ELR_LS_MIS, 7, a) == 0 && render(s, 128, ELR_LS_MIS, 8, b) == 0) {
          double m = 0, m2 = 0, ma = 0, se;
          int i, N = RES * RES;
          for (i = 0; i < N; i++) { double d = a[i] - b[i]; m += d; m2 += d * d; ma += a[i]; }
          m /= N; ma /= N; se = sqrt((m2 / N - m * m) / (N - 1));
          rt_check(fabs(m) < 4 * se, "directlighting: strategy \"one\" vs \"all\": means differ by %+.3f%% (%.1f standard errors)", 100 * m / ma, m / se);
        } else rt_check(0, "strategy one: %s", err);
        elr_scene_free(o);
      }
    }
    elr_scene_free(s);
  }
}

/* >> what is built and traced */
static void pipeline(void) {
  char err[512];
  elr_scene *s;
  elr_image im;
  elr_stats st;
  /* nothing emits (no light; a black area light): a black image, no ray at all, one warning */
  static const char *dark[2] = {"", "AreaLightSource \"diffuse\" \"rgb L\" [ 0 0 0 ]\nShape \"disk\"\n"};
  int k;
  for (k = 0; k < 2; k++) {
    s = rt_load("dark.pbrt", scene("\"path\"", dark[k]), err, sizeof err);
    if (s && rt_render(s, 8, -1, -1, 2, 1, &im, &st) == 0) {
      double m = 0;
      int i;
      for (i = 0; i < im.width * im.height * 3; i++) m = fmax(m, im.rgb[i]);
      rt_check(m == 0 && st.camera_rays + st.bounce_rays + st.shadow_rays + st.bsdf_light_rays == 0 && st.nothing_emits && im.width == RES &&
                   elr_scene_warnings(s) == 1 && strstr(elr_scene_last_warning(s), "nothing in the scene emits"),
               "%s: a black %d x %d image, %llu rays traced, %d warning (\"%s\")", k ? "a black area light" : "no light", im.width, im.height,
               (unsigned long long)(st.camera_rays + st.bounce_rays + st.shadow_rays), elr_scene_warnings(s), elr_scene_last_warning(s));
      elr_image_free(&im);
    } else rt_check(0, "dark: %s", err);
    elr_scene_free(s);
  }
  /* two disk lights in one plane (each one's own material lit by the other edge-on): solid-angle
   * densities of 1e20 and more, whose squares overflowed the power heuristic (NaN samples that the
   * film rejected: 900 per million in scenes/blackbody_lights.pbrt) */
  s = rt_load("edge.pbrt", "LookAt 0 3 -1  0 1.5 0  0 1 0\nCamera \"perspective\" \"float fov\" 60\n"
                           "Film \"image\" \"integer xresolution\" 64 \"integer yresolution\" 64\nSampler \"random\" \"integer pixelsamples\" 64\n"
                           "Integrator \"directlighting\"\nWorldBegin\n"
                           "AttributeBegin\nTranslate -0.8 1.5 0\nRotate 90 1 0 0\nAreaLightSource \"diffuse\" \"rgb L\" [ 2 2 2 ]\nShape \"disk\" \"float radius\" 0.7\nAttributeEnd\n"
                           "AttributeBegin\nTranslate 0.8 1.5 0\nRotate 90 1 0 0\nAreaLightSource \"diffuse\" \"rgb L\" [ 2 2 2 ]\nShape \"disk\" \"float radius\" 0.7\nAttributeEnd\n"
                           "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point P\" [ -6 0 -6  6 0 -6  6 0 6  -6 0 6 ]\nWorldEnd\n",
              err, sizeof err);
  if (s && rt_render(s, 64, ELR_LS_MIS, -1, 2, 1, &im, &st) == 0) {
    rt_check(st.rejected_samples == 0, "two disk lights in one plane: %llu samples rejected (NaN MIS weights)", (unsigned long long)st.rejected_samples);
    elr_image_free(&im);
  } else rt_check(0, "edge: %s", err);
  elr_scene_free(s);
  /* one mesh light: its area CDF, no light distribution; BSDF sampling only builds no CDF */
  s = rt_load("one.pbrt", scene("\"path\"", "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [ 2 2 2 ]\n"
                                            "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point P\" [ -1 3 -1  1 3 -1  1 3 1  -1 3 1 ]\nAttributeEnd\n"),
              err, sizeof err);
  if (s && rt_render(s, 4, ELR_LS_BSDF, -1, 2, 1, &im, &st) == 0) {
    rt_check(st.nlight_stats == 1 && !st.light[0].tables_built && !st.light_distribution_built && st.shadow_rays == 0,
             "one mesh light, BSDF sampling only: no area CDF, no light distribution, no shadow rays");
    elr_image_free(&im);
  } else rt_check(0, "one light: %s", err);
  if (s && rt_render(s, 4, ELR_LS_MIS, -1, 2, 1, &im, &st) == 0) {
    rt_check(st.nlight_stats == 1 && st.light[0].tables_built && st.light[0].bytes == 3 * sizeof(double) && !st.light_distribution_built &&
                 st.light[0].pick == 1.f && fabs(st.light[0].area - 4.0) < 1e-9 && st.distribution_built == 0,
             "one mesh light, MIS: its area CDF (%zu bytes for 2 triangles, area %g), no light distribution, no environment tables",
             st.light[0].bytes, st.light[0].area);
    elr_image_free(&im);
  } else rt_check(0, "one light: %s", err);
  elr_scene_free(s);
  /* the environment and a sphere light: both sampled, a distribution of 2 built; the environment's
   * tables built; power weights (pbrt-v3's: pi A L for the sphere) */
  s = rt_load("two.pbrt", scene("\"path\" \"string lightsamplestrategy\" \"power\"",
                                "LightSource \"infinite\" \"rgb L\" [ 0.5 0.5 0.5 ]\nAttributeBegin\nTranslate 0 3 0\n"
                                "AreaLightSource \"diffuse\" \"rgb L\" [ 3 3 3 ]\nShape \"sphere\" \"float radius\" 0.5\nAttributeEnd\n"),
              err, sizeof err);
  if (s && rt_render(s, 4, -1, -1, 2, 1, &im, &st) == 0) {
    double psph = 3.14159265358979323846 * 4 * 3.14159265358979323846 * 0.25 * 3.0;
    rt_check(st.light_distribution_built && st.nlight_stats == 2 && st.light[0].tables_built && fabs(st.light[1].power - psph) < 1e-3 * psph &&
                 fabs(st.light[0].pick + st.light[1].pick - 1.f) < 1e-6 && !strcmp(st.light_strategy, "power"),
             "environment + sphere light: a distribution of 2 (p = %.3f, %.3f), the environment's tables, sphere power %.4g (pi A L = %.4g)",
             st.light[0].pick, st.light[1].pick, st.light[1].power, psph);
    elr_image_free(&im);
  } else rt_check(0, "two lights: %s", err);
  elr_scene_free(s);
}

int main(void) {
  rt_mkdir("test_render_arealights");
  sphere_light();
  quad_light();
  disk_light();
  strategies();
  pipeline();
  return rt_finish("test_render_arealights");
}
