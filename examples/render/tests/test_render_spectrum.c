/* test_render_spectrum: spectral parameter values ("blackbody", "xyz", "spectrum" inline and in .spd
 * files) become the RGB that pbrt-v3's RGBSpectrum build makes of them (spectrum.c), checked against
 * values computed here independently of the renderer's code and tables:
 *  - Planck's law with CODATA 2018 constants (pbrt-v3 uses CODATA 2010's), normalised at Wien's peak;
 *  - the CIE 1931 2-degree colour-matching functions at 5 nm (the CIE's 5 nm table, below; the renderer
 *    has the 1 nm table), interpolated to 1 nm by the CIE's recommended Sprague interpolation (CIE
 *    167:2005), summed over 360 ... 830 nm and scaled by (830 - 360) / 471 over the sum of y, which is
 *    pbrt-v3's FromSampled;
 *  - pbrt-v3's XYZToRGB matrix as published in its core/spectrum.h (checked here to take the sRGB
 *    primaries to the unit vectors within 1e-3).
 * The Sprague-interpolated table and the CIE's 1 nm one give colours within 3e-6 of each other
 * (measured with the colour-science package; the plain 5 nm trapezoid rule is 8e-4 off on a spectrum
 * with kinks), so the checks allow 5e-5 of the largest component. Then: an .spd file gives
 * the inline list's colour bit for bit; a light's out-of-gamut negative components are clamped to 0;
 * a camera sees a blackbody quad light's L; and every bad value is a file:line error. */
#include "render_test_util.h"

/* CIE 1931 2-degree standard observer, 360 ... 830 nm every 5 nm: lambda, x, y, z (CIE 018:2019; printed
 * from the colour-science package's "CIE 1931 2 Degree Standard Observer") */
static const double cie5[95][4] = {
    {360, 0.0001299, 3.917e-06, 0.0006061}, {365, 0.0002321, 6.965e-06, 0.001086}, {370, 0.0004149, 1.239e-05, 0.001946}, {375, 0.0007416, 2.202e-05, 0.003486},
    {380, 0.001368, 3.9e-05, 0.006450001}, {385, 0.002236, 6.4e-05, 0.01054999}, {390, 0.004243, 0.00012, 0.02005001}, {395, 0.00765, 0.000217, 0.03621},
    {400, 0.01431, 0.000396, 0.06785001}, {405, 0.02319, 0.00064, 0.1102}, {410, 0.04351, 0.00121, 0.2074}, {415, 0.07763, 0.00218, 0.3713},
    {420, 0.13438, 0.004, 0.6456}, {425, 0.21477, 0.0073, 1.0390501}, {430, 0.2839, 0.0116, 1.3856}, {435, 0.3285, 0.01684, 1.62296},
    {440, 0.34828, 0.023, 1.74706}, {445, 0.34806, 0.0298, 1.7826}, {450, 0.3362, 0.038, 1.77211}, {455, 0.3187, 0.048, 1.7441},
    {460, 0.2908, 0.06, 1.6692}, {465, 0.2511, 0.0739, 1.5281}, {470, 0.19536, 0.09098, 1.28764}, {475, 0.1421, 0.1126, 1.0419},
    {480, 0.09564, 0.13902, 0.8129501}, {485, 0.05795001, 0.1693, 0.6162}, {490, 0.03201, 0.20802, 0.46518}, {495, 0.0147, 0.2586, 0.3533},
    {500, 0.0049, 0.323, 0.272}, {505, 0.0024, 0.4073, 0.2123}, {510, 0.0093, 0.503, 0.1582}, {515, 0.0291, 0.6082, 0.1117},
    {520, 0.06327, 0.71, 0.07824999}, {525, 0.1096, 0.7932, 0.05725001}, {530, 0.1655, 0.862, 0.04216}, {535, 0.2257499, 0.9148501, 0.02984},
    {540, 0.2904, 0.954, 0.0203}, {545, 0.3597, 0.9803, 0.0134}, {550, 0.4334499, 0.9949501, 0.008749999}, {555, 0.5120501, 1, 0.005749999},
    {560, 0.5945, 0.995, 0.0039}, {565, 0.6784, 0.9786, 0.002749999}, {570, 0.7621, 0.952, 0.0021}, {575, 0.8425, 0.9154, 0.0018},
    {580, 0.9163, 0.87, 0.001650001}, {585, 0.9786, 0.8163, 0.0014}, {590, 1.0263, 0.757, 0.0011}, {595, 1.0567, 0.6949, 0.001},
    {600, 1.0622, 0.631, 0.0008}, {605, 1.0456, 0.5668, 0.0006}, {610, 1.0026, 0.503, 0.00034}, {615, 0.9384, 0.4412, 0.00024},
    {620, 0.8544499, 0.381, 0.00019}, {625, 0.7514, 0.321, 0.0001}, {630, 0.6424, 0.265, 4.999999e-05}, {635, 0.5419, 0.217, 3e-05},
    {640, 0.4479, 0.175, 2e-05}, {645, 0.3608, 0.1382, 1e-05}, {650, 0.2835, 0.107, 0}, {655, 0.2187, 0.0816, 0},
    {660, 0.1649, 0.061, 0}, {665, 0.1212, 0.04458, 0}, {670, 0.0874, 0.032, 0}, {675, 0.0636, 0.0232, 0},
    {680, 0.04677, 0.017, 0}, {685, 0.0329, 0.01192, 0}, {690, 0.0227, 0.00821, 0}, {695, 0.01584, 0.005723, 0},
    {700, 0.01135916, 0.004102, 0}, {705, 0.008110916, 0.002929, 0}, {710, 0.005790346, 0.002091, 0}, {715, 0.004109457, 0.001484, 0},
    {720, 0.002899327, 0.001047, 0}, {725, 0.00204919, 0.00074, 0}, {730, 0.001439971, 0.00052, 0}, {735, 0.0009999493, 0.0003611, 0},
    {740, 0.0006900786, 0.0002492, 0}, {745, 0.0004760213, 0.0001719, 0}, {750, 0.0003323011, 0.00012, 0}, {755, 0.0002348261, 8.48e-05, 0},
    {760, 0.0001661505, 6e-05, 0}, {765, 0.000117413, 4.24e-05, 0}, {770, 8.307527e-05, 3e-05, 0}, {775, 5.870652e-05, 2.12e-05, 0},
    {780, 4.150994e-05, 1.499e-05, 0}, {785, 2.935326e-05, 1.06e-05, 0}, {790, 2.067383e-05, 7.4657e-06, 0}, {795, 1.455977e-05, 5.2578e-06, 0},
    {800, 1.025398e-05, 3.7029e-06, 0}, {805, 7.221456e-06, 2.6078e-06, 0}, {810, 5.085868e-06, 1.8366e-06, 0}, {815, 3.581652e-06, 1.2934e-06, 0},
    {820, 2.522525e-06, 9.1093e-07, 0}, {825, 1.776509e-06, 6.4153e-07, 0}, {830, 1.251141e-06, 4.5181e-07, 0},
};

/* pbrt-v3's XYZToRGB (core/spectrum.h) */
static void xyz2rgb(const double x[3], double r[3]) {
  r[0] = 3.240479 * x[0] - 1.537150 * x[1] - 0.498535 * x[2];
  r[1] = -0.969256 * x[0] + 1.875991 * x[1] + 0.041556 * x[2];
  r[2] = 0.055648 * x[0] - 0.204043 * x[1] + 1.057311 * x[2];
}
static double planck(double nm, double T) { /* W / (m^2 sr m), CODATA 2018 */
  const double h = 6.62607015e-34, c = 299792458.0, k = 1.380649e-23, l = nm * 1e-9;
  return 2.0 * h * c * c / (pow(l, 5.0) * (exp(h * c / (l * k * T)) - 1.0));
}
/* a piecewise-linear spectrum through (lam[i], val[i]), constant beyond its ends */
static double lin(const double *lam, const double *val, int n, double l) {
  int i;
  if (l <= lam[0]) return val[0];
  if (l >= lam[n - 1]) return val[n - 1];
  for (i = 0; l > lam[i + 1]; i++) {}
  return val[i] + (val[i + 1] - val[i]) * (l - lam[i]) / (lam[i + 1] - lam[i]);
}
/* the 5 nm table at 1 nm, 360 ... 830 (471 values per function): Sprague interpolation (CIE 167:2005),
 * the two points beyond each end extrapolated with Sprague's coefficients */
static double cie1[471][3];
static void sprague(void) {
  static const double E[4][6] = {{884, -1960, 3033, -2648, 1080, -180}, {508, -540, 488, -367, 144, -24},
                                 {-24, 144, -367, 488, -540, 508}, {-180, 1080, -2648, 3033, -1960, 884}};
  int k, i, j, m;
  for (k = 0; k < 3; k++) {
    double y[99];
    for (i = 0; i < 95; i++) y[i + 2] = cie5[i][k + 1];
    for (m = 0; m < 4; m++) {
      double s = 0;
      for (j = 0; j < 6; j++) s += E[m][j] * (m < 2 ? cie5[j][k + 1] : cie5[89 + j][k + 1]);
      y[m < 2 ? m : 95 + m] = s / 209.0;
    }
    for (i = 0; i < 94; i++) {
      const double *p = y + i;
      double a1 = (2 * p[0] - 16 * p[1] + 16 * p[3] - 2 * p[4]) / 24, a2 = (-p[0] + 16 * p[1] - 30 * p[2] + 16 * p[3] - p[4]) / 24;
      double a3 = (-9 * p[0] + 39 * p[1] - 70 * p[2] + 66 * p[3] - 33 * p[4] + 7 * p[5]) / 24;
      double a4 = (13 * p[0] - 64 * p[1] + 126 * p[2] - 124 * p[3] + 61 * p[4] - 12 * p[5]) / 24;
      double a5 = (-5 * p[0] + 25 * p[1] - 50 * p[2] + 50 * p[3] - 25 * p[4] + 5 * p[5]) / 24;
      for (j = 0; j < 5; j++) {
        double x = j / 5.0;
        cie1[5 * i + j][k] = p[2] + x * (a1 + x * (a2 + x * (a3 + x * (a4 + x * a5))));
      }
    }
    cie1[470][k] = cie5[94][k + 1];
  }
}
/* the colour of spectrum f (kind 0: blackbody at T normalised to its peak; 1: the list lam/val) */
static void expected(int kind, double T, const double *lam, const double *val, int n, double rgb[3]) {
  double xyz[3] = {0, 0, 0}, sy = 0, peak = kind == 0 ? planck(2.897771955e-3 / T * 1e9, T) : 1.0;
  int i, k;
  for (i = 0; i < 471; i++) {
    double f = kind == 0 ? planck(360.0 + i, T) / peak : lin(lam, val, n, 360.0 + i);
    for (k = 0; k < 3; k++) xyz[k] += f * cie1[i][k];
    sy += cie1[i][1];
  }
  for (k = 0; k < 3; k++) xyz[k] *= (830.0 - 360.0) / 471.0 / sy;
  xyz2rgb(xyz, rgb);
}
static int close3(elr_v3 a, const double e[3], double tol) {
  double m = fmax(fabs(e[0]), fmax(fabs(e[1]), fabs(e[2])));
  return fabs(a.x - e[0]) <= tol * m + 1e-30 && fabs(a.y - e[1]) <= tol * m + 1e-30 && fabs(a.z - e[2]) <= tol * m + 1e-30;
}

static const char *world(const char *body) {
  static char buf[4096];
  snprintf(buf, sizeof buf, "Film \"image\" \"integer xresolution\" 4 \"integer yresolution\" 4\nWorldBegin\n%sWorldEnd\n", body);
  return buf;
}
/* the L of the first light of a scene with an area light made of `decl` on a sphere */
static int area_L(const char *decl, elr_v3 *L, char *err) {
  char body[1024];
  elr_scene *s;
  snprintf(body, sizeof body, "AreaLightSource \"diffuse\" %s\nShape \"sphere\"\n", decl);
  s = rt_load("spec.pbrt", world(body), err, 512);
  if (!s) return -1;
  if (s->nlight != 1) { snprintf(err, 512, "%d lights", s->nlight); elr_scene_free(s); return -1; }
  *L = s->light[0].L;
  elr_scene_free(s);
  return 0;
}

static void expect_error(const char *name, const char *text, const char *where, const char *what) {
  char err[512];
  elr_scene *s = rt_load(name, text, err, sizeof err);
  rt_check(!s && strstr(err, where) && strstr(err, what) && strstr(err, "error"), "%s: error at %s naming \"%s\": \"%s\"", name, where, what,
           s ? "(loaded)" : err);
  elr_scene_free(s);
}

int main(void) {
  static const double temps[7] = {1500, 2000, 2700, 4000, 5500, 6500, 10000};
  static const double lam[5] = {400, 450, 550, 650, 700}, val[5] = {0.1, 0.8, 0.3, 0.9, 0.2};
  char err[512], decl[256];
  elr_v3 L;
  double e[3];
  int i;
  rt_mkdir("test_render_spectrum");
  sprague();
  { /* the reference matrix is the sRGB one: its primaries' XYZ (from the chromaticities, Y = 1 at D65) go to unit vectors */
    static const double xy[3][2] = {{0.64, 0.33}, {0.30, 0.60}, {0.15, 0.06}};
    double worst = 0;
    int k, j;
    for (k = 0; k < 3; k++) {
      double x[3], r[3], w[3] = {0.3127 / 0.3290, 1.0, (1 - 0.3127 - 0.3290) / 0.3290}, Sinv[3][3], S[3];
      /* scale the primaries so that they sum to the white point: solve P s = W (Cramer's rule) */
      double P[3][3], det;
      for (j = 0; j < 3; j++) { P[0][j] = xy[j][0] / xy[j][1]; P[1][j] = 1.0; P[2][j] = (1 - xy[j][0] - xy[j][1]) / xy[j][1]; }
      det = P[0][0] * (P[1][1] * P[2][2] - P[1][2] * P[2][1]) - P[0][1] * (P[1][0] * P[2][2] - P[1][2] * P[2][0]) + P[0][2] * (P[1][0] * P[2][1] - P[1][1] * P[2][0]);
      for (j = 0; j < 3; j++) {
        double Q[3][3];
        int a, b;
        for (a = 0; a < 3; a++) for (b = 0; b < 3; b++) Q[a][b] = b == j ? w[a] : P[a][b];
        S[j] = (Q[0][0] * (Q[1][1] * Q[2][2] - Q[1][2] * Q[2][1]) - Q[0][1] * (Q[1][0] * Q[2][2] - Q[1][2] * Q[2][0]) + Q[0][2] * (Q[1][0] * Q[2][1] - Q[1][1] * Q[2][0])) / det;
      }
      (void)Sinv;
      for (j = 0; j < 3; j++) x[j] = P[j][k] * S[k];
      xyz2rgb(x, r);
      for (j = 0; j < 3; j++) worst = fmax(worst, fabs(r[j] - (j == k ? 1.0 : 0.0)));
    }
    rt_check(worst < 1e-3, "the reference XYZ-to-RGB matrix takes the sRGB primaries to unit vectors (worst %.1e)", worst);
  }
  /* blackbody: (temperature, scale) pairs, normalised as pbrt-v3's BlackbodyNormalized */
  for (i = 0; i < 7; i++) {
    double sc = i % 2 ? 3.0 : 1.0;
    snprintf(decl, sizeof decl, "\"blackbody L\" [ %g %g ]", temps[i], sc);
    expected(0, temps[i], NULL, NULL, 0, e);
    e[0] = fmax(e[0], 0) * sc; e[1] = fmax(e[1], 0) * sc; e[2] = fmax(e[2], 0) * sc; /* a light's negative components: 0 */
    if (area_L(decl, &L, err) != 0) { rt_check(0, "%s: %s", decl, err); continue; }
    rt_check(close3(L, e, 5e-5), "%s: L = (%.6g %.6g %.6g), expected (%.6g %.6g %.6g)", decl, L.x, L.y, L.z, e[0], e[1], e[2]);
  }
  /* the 1500 K one is out of the sRGB gamut: B < 0 before the clamp */
  expected(0, 1500, NULL, NULL, 0, e);
  rt_check(e[2] < 0 && area_L("\"blackbody L\" [ 1500 1 ]", &L, err) == 0 && L.z == 0.f, "1500 K: B = %.3g computed, 0 in the light", e[2]);
  /* xyz */
  {
    double x[3] = {0.3, 0.5, 0.2};
    int ok = area_L("\"xyz L\" [ 0.3 0.5 0.2 ]", &L, err) == 0;
    xyz2rgb(x, e);
    rt_check(ok && close3(L, e, 1e-6), "xyz L (0.3 0.5 0.2): (%.6g %.6g %.6g), expected (%.6g %.6g %.6g)", L.x, L.y, L.z, e[0], e[1], e[2]);
  }
  /* spectrum: an inline list, the same list in a .spd file, on a light and on a material */
  expected(1, 0, lam, val, 5, e);
  {
    elr_v3 Lf;
    int ok = area_L("\"spectrum L\" [ 400 0.1 450 0.8 550 0.3 650 0.9 700 0.2 ]", &L, err) == 0;
    rt_check(ok && close3(L, e, 5e-5), "spectrum L inline: (%.6g %.6g %.6g), expected (%.6g %.6g %.6g)", L.x, L.y, L.z, e[0], e[1], e[2]);
    rt_write("refl.spd", "# a test spectrum: wavelength (nm), value\n400 0.1\n  450\t0.8 # peak\n550 0.3 650 0.9\n\n700 0.2");
    ok = area_L("\"spectrum L\" \"refl.spd\"", &Lf, err) == 0;
    rt_check(ok && Lf.x == L.x && Lf.y == L.y && Lf.z == L.z, "the same spectrum from a .spd file (comments, any spacing): bit for bit (%s)", ok ? "" : err);
  }
  {
    elr_scene *s = rt_load("mat.pbrt", world("Material \"matte\" \"spectrum Kd\" \"refl.spd\"\nShape \"sphere\"\nLightSource \"point\"\n"), err, sizeof err);
    int ok = s && s->nsph == 1;
    elr_v3 kd = ok ? s->tex[s->mat[s->sph[0].material].kd].value : elr_v(0, 0, 0);
    rt_check(ok && close3(kd, e, 5e-5), "spectrum Kd from a .spd file: (%.6g %.6g %.6g) (%s)", kd.x, kd.y, kd.z, ok ? "" : err);
    elr_scene_free(s);
  }
  { /* a flat spectrum: the renderer's table sums (pbrt-v3: Y = 470/471 for a flat 1) */
    double fl[2] = {300, 900}, fv[2] = {1, 1};
    int ok = area_L("\"spectrum L\" [ 300 1 900 1 ]", &L, err) == 0;
    expected(1, 0, fl, fv, 2, e);
    rt_check(ok && close3(L, e, 5e-5), "a flat spectrum 1: (%.6g %.6g %.6g), expected (%.6g %.6g %.6g)", L.x, L.y, L.z, e[0], e[1], e[2]);
  }
  { /* the camera sees a blackbody quad light's L */
    elr_scene *s;
    elr_image img;
    elr_stats st;
    expected(0, 3000, NULL, NULL, 0, e);
    e[0] *= 2; e[1] *= 2; e[2] *= 2;
    s = rt_load("see.pbrt", "LookAt 0 0 -2  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 20\nFilm \"image\" \"integer xresolution\" 4 \"integer yresolution\" 4\n"
                            "Sampler \"random\" \"integer pixelsamples\" 4\nIntegrator \"directlighting\"\nWorldBegin\n"
                            "AreaLightSource \"diffuse\" \"blackbody L\" [ 3000 2 ]\n"
                            "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point P\" [ -1 -1 0  -1 1 0  1 1 0  1 -1 0 ]\nWorldEnd\n",
                err, sizeof err);
    if (s && rt_render(s, 4, -1, -1, 1, 1, &img, &st) == 0) {
      elr_v3 p = elr_v(img.rgb[3 * 5], img.rgb[3 * 5 + 1], img.rgb[3 * 5 + 2]);
      rt_check(close3(p, e, 5e-5), "a camera sees the blackbody quad's L: (%.6g %.6g %.6g), expected (%.6g %.6g %.6g)", p.x, p.y, p.z, e[0], e[1], e[2]);
      elr_image_free(&img);
    } else rt_check(0, "blackbody quad: %s", err);
    elr_scene_free(s);
  }
  /* bad values: file:line errors */
  expect_error("neg.pbrt", world("AreaLightSource \"diffuse\" \"rgb L\" [ -1 1 1 ]\nShape \"sphere\"\n"), "neg.pbrt:3:", "must not be negative");
  expect_error("negsc.pbrt", world("AreaLightSource \"diffuse\" \"rgb L\" [ 1 1 1 ] \"float scale\" -2\nShape \"sphere\"\n"), "negsc.pbrt:3:", "must not be negative");
  expect_error("negspd.pbrt", world("AreaLightSource \"diffuse\" \"spectrum L\" [ 400 1 700 -1 ]\n"), "negspd.pbrt:3:", "must not be negative");
  expect_error("negbb.pbrt", world("LightSource \"point\" \"blackbody I\" [ 6500 -1 ]\n"), "negbb.pbrt:3:", "must not be negative");
  expect_error("t0.pbrt", world("AreaLightSource \"diffuse\" \"blackbody L\" [ 0 1 ]\n"), "t0.pbrt:3:", "must be positive");
  expect_error("tneg.pbrt", world("LightSource \"point\" \"blackbody I\" [ -300 1 ]\n"), "tneg.pbrt:3:", "must be positive");
  expect_error("tinf.pbrt", world("LightSource \"point\" \"blackbody I\" [ inf 1 ]\n"), "tinf.pbrt:3:", "not a finite number");
  expect_error("tnan.pbrt", world("Material \"matte\" \"blackbody Kd\" [ nan 1 ]\n"), "tnan.pbrt:3:", "not a finite number");
  expect_error("tbig.pbrt", world("Material \"matte\" \"blackbody Kd\" [ 1e999 1 ]\n"), "tbig.pbrt:3:", "not finite");
  expect_error("bb1.pbrt", world("AreaLightSource \"diffuse\" \"blackbody L\" [ 6500 ]\n"), "bb1.pbrt:3:", "pbrt-v4");
  expect_error("bb3.pbrt", world("AreaLightSource \"diffuse\" \"blackbody L\" [ 6500 1 2 ]\n"), "bb3.pbrt:3:", "takes 2 values");
  expect_error("odd.pbrt", world("Material \"matte\" \"spectrum Kd\" [ 400 0.5 500 ]\n"), "odd.pbrt:3:", "got 3 numbers");
  expect_error("unsorted.pbrt", world("Material \"matte\" \"spectrum Kd\" [ 500 0.5 400 0.5 ]\n"), "unsorted.pbrt:3:", "not increasing");
  expect_error("same.pbrt", world("Material \"matte\" \"spectrum Kd\" [ 500 0.5 500 0.7 ]\n"), "same.pbrt:3:", "not increasing");
  expect_error("xyz2.pbrt", world("Material \"matte\" \"xyz Kd\" [ 0.5 0.5 ]\n"), "xyz2.pbrt:3:", "takes 3 values");
  expect_error("nospd.pbrt", world("AreaLightSource \"diffuse\" \"spectrum L\" \"nothere.spd\"\n"), "nospd.pbrt:3:", "nothere.spd");
  rt_write("bad.spd", "400 0.5\n450 0.6\n500 zero\n");
  expect_error("badspd.pbrt", world("Material \"matte\" \"spectrum Kd\" \"bad.spd\"\n"), "badspd.pbrt:3:", "line 3 is not a list of numbers");
  rt_write("oddf.spd", "400 0.5 450\n");
  expect_error("oddspd.pbrt", world("Material \"matte\" \"spectrum Kd\" \"oddf.spd\"\n"), "oddspd.pbrt:3:", "holds 3 numbers");
  rt_write("empty.spd", "# nothing\n");
  expect_error("emptyspd.pbrt", world("Material \"matte\" \"spectrum Kd\" \"empty.spd\"\n"), "emptyspd.pbrt:3:", "holds 0 numbers");
  rt_write("unsorted.spd", "500 0.5\n400 0.5\n");
  expect_error("unsspd.pbrt", world("Material \"matte\" \"spectrum Kd\" \"unsorted.spd\"\n"), "unsspd.pbrt:3:", "unsorted.spd");
  expect_error("huge.pbrt", world("Material \"matte\" \"spectrum Kd\" [ 400 1e300 700 1e300 ]\n"), "huge.pbrt:3:", "overflows");
  return rt_finish("test_render_spectrum");
}
