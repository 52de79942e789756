/* test_envlight_portal.c: envlight.h's portal sampling (issue 23), checked against its own pdf and
 * against references computed here without the portal code.
 *
 * - chi-square of el_envlight_portal_sample_li against el_envlight_portal_pdf_li, binned in each
 *   portal's rectified (alpha, beta) window computed here from the vertices with libm (points near the
 *   portal's plane, far away, grazing; portals at the pole and across the seam; a sun inside and outside
 *   the window; the y-up matrix and a scale; two portals; compensation), and the pdf's integral over the
 *   windows = 1;
 * - unbiasedness: the mean of lum(L) / pdf against a quadrature of lum(le) over the portal's area
 *   (d omega = z dA / r^3), which never calls the portal code;
 * - pdf round trips, pdf 0 through points just outside the rectangle, the fallback behind the plane;
 * - hostile portals: degenerate, non-planar, not a rectangle, NaN, infinite, bad counts (clear errors). */
#define EL_IMPLEMENTATION
#include "../envlight.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

static const double PI = 3.14159265358979323846;
static int g_pass, g_fail;
static void check(int ok, const char *what, double a, double b) {
  if (ok) g_pass++;
  else g_fail++;
  printf("%s: %s (%g, %g)\n", ok ? "PASS" : "FAIL", what, a, b);
}
#include "test_rng.h" /* xorshift64_f */
static xorshift64 g_rng = {88172645463325252ULL};
static double lum(const float *c) { return 0.212671 * c[0] + 0.715160 * c[1] + 0.072169 * c[2]; }

#include "test_chisq.h" /* gammq: the chi-square p-value */

/* ---- a test map: a sky with an asymmetric gradient, optionally a sun (light space direction) ---- */
#define MW 128
#define MH 64
static float g_map[MW * MH * 3];
static void make_map(const double *sun, double sun_radius_deg) {
  int x, y;
  for (y = 0; y < MH; ++y)
    for (x = 0; x < MW; ++x) {
      double th = PI * (y + 0.5) / MH, ph = 2 * PI * (x + 0.5) / MW;
      double d[3], v = 0.3 + 0.5 * cos(th) * cos(th) + 0.3 * (1 + sin(ph + 0.4)) * sin(th);
      float *t = g_map + 3 * (y * MW + x);
      d[0] = sin(th) * cos(ph); d[1] = sin(th) * sin(ph); d[2] = cos(th);
      t[0] = (float)v; t[1] = (float)(0.8 * v); t[2] = (float)(1.2 * v);
      if (sun && d[0] * sun[0] + d[1] * sun[1] + d[2] * sun[2] > cos(sun_radius_deg * PI / 180)) {
        t[0] = 4000.0f; t[1] = 3800.0f; t[2] = 3500.0f;
      }
    }
}

/* ---- portals from a centre, unit axes ex (p0 -> p3) and ey (p0 -> p1) and sizes ---- */
static void make_portal(float *v, const double c[3], const double ex[3], const double ey[3], double sx, double sy) {
  int i;
  for (i = 0; i < 3; ++i) {
    double p0 = c[i] - 0.5 * sx * ex[i] - 0.5 * sy * ey[i];
    v[i] = (float)p0;
    v[3 + i] = (float)(p0 + sy * ey[i]);
    v[6 + i] = (float)(p0 + sy * ey[i] + sx * ex[i]);
    v[9 + i] = (float)(p0 + sx * ex[i]);
  }
}
static void cross(const double a[3], const double b[3], double c[3]) {
  c[0] = a[1] * b[2] - a[2] * b[1]; c[1] = a[2] * b[0] - a[0] * b[2]; c[2] = a[0] * b[1] - a[1] * b[0];
}
/* the test's own frame and window of a portal seen from pos (libm atan2) */
typedef struct tportal { double o[3], x[3], y[3], z[3], sx, sy, a0, a1, b0, b1; int seen; } tportal;
static void tp_make(tportal *t, const float *v, const float pos[3]) {
  int i;
  double lx = 0, ly = 0, r[3], px = 0, py = 0, pz = 0;
  for (i = 0; i < 3; ++i) { t->o[i] = v[i]; t->x[i] = (double)v[9 + i] - v[i]; t->y[i] = (double)v[3 + i] - v[i]; }
  for (i = 0; i < 3; ++i) { lx += t->x[i] * t->x[i]; ly += t->y[i] * t->y[i]; }
  t->sx = sqrt(lx); t->sy = sqrt(ly);
  for (i = 0; i < 3; ++i) { t->x[i] /= t->sx; t->y[i] /= t->sy; }
  cross(t->x, t->y, t->z);
  for (i = 0; i < 3; ++i) r[i] = t->o[i] - pos[i];
  for (i = 0; i < 3; ++i) { px += r[i] * t->x[i]; py += r[i] * t->y[i]; pz += r[i] * t->z[i]; }
  t->seen = pz > 0;
  t->a0 = atan2(px, pz) / PI + 0.5; t->a1 = atan2(px + t->sx, pz) / PI + 0.5;
  t->b0 = atan2(py, pz) / PI + 0.5; t->b1 = atan2(py + t->sy, pz) / PI + 0.5;
}
/* rectified (a, b) -> world direction, and dw/dab */
static double tp_dir(const tportal *t, double a, double b, float w[3]) {
  double x = tan(PI * (a - 0.5)), y = tan(PI * (b - 0.5)), n = sqrt(x * x + y * y + 1), l[3];
  int i;
  l[0] = x / n; l[1] = y / n; l[2] = 1 / n;
  for (i = 0; i < 3; ++i) w[i] = (float)(l[0] * t->x[i] + l[1] * t->y[i] + l[2] * t->z[i]);
  return PI * PI * (1 - l[0] * l[0]) * (1 - l[1] * l[1]) / l[2];
}
static int tp_ab(const tportal *t, const float w[3], double *a, double *b) {
  double lx = 0, ly = 0, lz = 0;
  int i;
  for (i = 0; i < 3; ++i) { lx += w[i] * t->x[i]; ly += w[i] * t->y[i]; lz += w[i] * t->z[i]; }
  if (!(lz > 0)) return 0;
  *a = atan2(lx, lz) / PI + 0.5; *b = atan2(ly, lz) / PI + 0.5;
  return *a >= t->a0 && *a <= t->a1 && *b >= t->b0 && *b <= t->b1;
}

#define NB 10
#define NSPLIT 64
/* [x0, x1] cut at the multiples of 1 / R: the edges, in order (at most NSPLIT + 2 of them) */
static int split(double x0, double x1, double R, double *e) {
  int n = 0, m = (int)floor(x0 * R) + 1;
  e[n++] = x0;
  for (; m < x1 * R && n < NSPLIT + 1; ++m) e[n++] = m / R;
  e[n++] = x1;
  return n;
}
/* Chi-square of the sampler against its pdf at pos, plus the pdf's integral, the round trip and the
 * unbiasedness of lum(L)/pdf against the quadrature over the portals' areas. */
static void run_case(const char *name, const el_envlight *light, const float *pts, int count, const float pos[3],
                     const el_envlight_portal_options *opt, int nsamples) {
  el_envlight_portal P;
  tportal T[4];
  static double expct[4 * NB * NB], obs[4 * NB * NB];
  double integral = 0, chi = 0, e_acc = 0, o_acc = 0, sum = 0, sum2 = 0, ref = 0, map_in = 0, share = opt ? opt->map_share : 0;
  int k, i, j, s, outside = 0, dof = 0, bad_rt = 0, used = 0;
  char what[200];
  el_result r = el_envlight_portal_init(&P, light, pts, count, opt);
  snprintf(what, sizeof what, "%s: init (%s)", name, P.error);
  check(r == EL_SUCCESS, what, (double)r, 0);
  if (r != EL_SUCCESS) return;
  for (k = 0; k < count; ++k) tp_make(&T[k], pts + 12 * k, pos);
  if (opt && opt->map_share_outside) { /* the share only behind some portal's plane (the test's own frame) */
    int behind = 0;
    for (k = 0; k < count; ++k) behind |= !T[k].seen;
    if (!behind) share = 0;
  }
  memset(obs, 0, sizeof obs);
  /* expected probabilities per bin: midpoint quadrature of pdf * dw/dab */
  for (k = 0; k < count; ++k)
    for (j = 0; j < NB; ++j)
      for (i = 0; i < NB; ++i) {
        /* pdf * dw/dab is constant on each rectified texel (NOTES ON PORTALS 2-3): the bin is cut at
         * the texel lines (multiples of 1 / resolution) and each piece evaluated at its centre */
        double e = 0, A0, A1, B0, B1, ea[2 * NSPLIT + 2], eb[2 * NSPLIT + 2], R = opt && opt->resolution ? opt->resolution : 256;
        int na, nb, si, sj;
        if (!T[k].seen) { expct[(k * NB + j) * NB + i] = 0; continue; }
        A0 = T[k].a0 + (T[k].a1 - T[k].a0) * i / NB; A1 = T[k].a0 + (T[k].a1 - T[k].a0) * (i + 1) / NB;
        B0 = T[k].b0 + (T[k].b1 - T[k].b0) * j / NB; B1 = T[k].b0 + (T[k].b1 - T[k].b0) * (j + 1) / NB;
        na = split(A0, A1, R, ea); nb = split(B0, B1, R, eb);
        for (sj = 0; sj + 1 < nb; ++sj)
          for (si = 0; si + 1 < na; ++si) {
            float w[3];
            double a = 0.5 * (ea[si] + ea[si + 1]), b = 0.5 * (eb[sj] + eb[sj + 1]);
            double J = tp_dir(&T[k], a, b, w);
            e += (double)el_envlight_portal_pdf_li(&P, light, pos, w) * J * (ea[si + 1] - ea[si]) * (eb[sj + 1] - eb[sj]);
            if (share > 0) map_in += (double)el_envlight_pdf_li(light, w) * J * (ea[si + 1] - ea[si]) * (eb[sj + 1] - eb[sj]);
          }
        expct[(k * NB + j) * NB + i] = e;
        integral += e;
      }
  for (s = 0; s < nsamples; ++s) {
    float u[2], wi[3], rgb[3], pdf, pdf2;
    int hit = 0;
    u[0] = xorshift64_f(&g_rng); u[1] = xorshift64_f(&g_rng);
    used += el_envlight_portal_sample_li(&P, light, pos, u, wi, rgb, &pdf);
    pdf2 = el_envlight_portal_pdf_li(&P, light, pos, wi);
    if (!(fabsf(pdf2 - pdf) <= 1e-3f * pdf)) bad_rt++;
    for (k = 0; k < count && !hit; ++k) {
      double a, b;
      if (T[k].seen && tp_ab(&T[k], wi, &a, &b)) {
        int bi = (int)((a - T[k].a0) / (T[k].a1 - T[k].a0) * NB), bj = (int)((b - T[k].b0) / (T[k].b1 - T[k].b0) * NB);
        if (bi > NB - 1) bi = NB - 1;
        if (bj > NB - 1) bj = NB - 1;
        obs[(k * NB + bj) * NB + bi] += 1;
        hit = 1;
      }
    }
    if (!hit) outside++;
    if (pdf > 0 && hit) { double f = lum(rgb) / pdf; sum += f; sum2 += f * f; } /* (outside the windows: the walls) */
  }
  for (i = 0; i < count * NB * NB; ++i) { /* pool bins with < 5 expected */
    e_acc += expct[i] * nsamples; o_acc += obs[i];
    if (e_acc >= 5) { chi += (o_acc - e_acc) * (o_acc - e_acc) / e_acc; dof++; e_acc = o_acc = 0; }
  }
  if (share > 0) { /* the map's samples outside the windows: one more bin */
    double e_out = (1 - integral) * nsamples;
    e_acc += e_out; o_acc += outside;
  }
  if (e_acc > 0) { chi += (o_acc - e_acc) * (o_acc - e_acc) / (e_acc > 1e-9 ? e_acc : 1e-9); dof++; }
  snprintf(what, sizeof what, "%s: every sample used the portals and went through one (samples used, outside)", name);
  check(used == nsamples && (share > 0 || outside <= nsamples / 20000), what, used, outside);
  snprintf(what, sizeof what, "%s: the pdf integrates to 1 over the windows (map share s: 1 - s + s x the map's mass there)", name);
  check(fabs(integral - (1 - share + share * map_in)) < 0.01, what, integral, 1 - share + share * map_in);
  snprintf(what, sizeof what, "%s: chi-square p-value (chi2, dof)", name);
  check(dof > 1 && gammq(0.5 * (dof - 1), 0.5 * chi) > 1e-4, what, chi, dof);
  snprintf(what, sizeof what, "%s: pdf_li(sample) = sample's pdf to 1e-3 (mismatches of %d)", name, nsamples);
  check(bad_rt <= nsamples / 1000, what, bad_rt, 0);
  /* the reference: integral of lum(le) over the portals' areas, d omega = z dA / r^3 */
  for (k = 0; k < count; ++k) {
    int M = 300, x, y;
    double pz = 0;
    for (i = 0; i < 3; ++i) pz += (T[k].o[i] - pos[i]) * T[k].z[i];
    if (!T[k].seen) continue;
    for (y = 0; y < M; ++y)
      for (x = 0; x < M; ++x) {
        double q[3], r2 = 0, dA = T[k].sx * T[k].sy / ((double)M * M);
        float w[3], c[3];
        for (i = 0; i < 3; ++i) q[i] = T[k].o[i] + (x + 0.5) / M * T[k].sx * T[k].x[i] + (y + 0.5) / M * T[k].sy * T[k].y[i] - pos[i];
        for (i = 0; i < 3; ++i) r2 += q[i] * q[i];
        for (i = 0; i < 3; ++i) w[i] = (float)q[i];
        el_envlight_le(light, w, c);
        ref += lum(c) * pz * dA / (r2 * sqrt(r2));
      }
  }
  if (!(opt && opt->compensated)) { /* compensation leaves the dim directions to BSDF samples */
    double mean = sum / nsamples, sd = sqrt((sum2 / nsamples - mean * mean) / nsamples);
    snprintf(what, sizeof what, "%s: mean lum/pdf = quadrature over the portal (estimate, reference)", name);
    check(fabs(mean - ref) < 5 * sd + 3e-3 * ref, what, mean, ref);
  }
  el_envlight_portal_free(&P);
}

static void test_cases(void) {
  el_envlight L;
  el_envlight_options lo;
  el_envlight_portal_options po;
  float pts[24], pos[3];
  double c[3], ex[3], ey[3], c2[3], ex2[3], ey2[3];
  double sun_in[3], sun_out[3];
  memset(&lo, 0, sizeof lo);
  memset(&po, 0, sizeof po);
  po.resolution = 64;
  /* a window in the wall x = 2 facing +x (across the map's seam, phi = 0): z = ex cross ey = +x */
  c[0] = 2; c[1] = 0; c[2] = 1;
  ex[0] = 0; ex[1] = 1; ex[2] = 0;  /* p0 -> p3 along +y */
  ey[0] = 0; ey[1] = 0; ey[2] = 1;  /* p0 -> p1 along +z: y cross z = +x */
  make_portal(pts, c, ex, ey, 1.5, 1.0);
  make_map(NULL, 0);
  if (el_envlight_init(&L, g_map, MW, MH, 3, &lo) != EL_SUCCESS) { check(0, "light init", 0, 0); return; }
  pos[0] = 0; pos[1] = 0.3f; pos[2] = 0.5f;
  run_case("seam window, 2 m inside", &L, pts, 1, pos, &po, 100000);
  pos[0] = 1.99f; pos[1] = 1.2f; pos[2] = 0.2f;
  run_case("seam window, grazing, 1 cm from its plane", &L, pts, 1, pos, &po, 100000);
  pos[0] = -60; pos[1] = 3; pos[2] = 2;
  run_case("seam window, 62 m away", &L, pts, 1, pos, &po, 100000);
  {
    el_envlight_portal_options p2 = po;
    p2.compensated = 1;
    pos[0] = 0; pos[1] = 0.3f; pos[2] = 0.5f;
    run_case("seam window, compensated (no unbiasedness check)", &L, pts, 1, pos, &p2, 100000);
  }
  el_envlight_free(&L);
  /* a skylight facing +z: the pole */
  c[0] = 0; c[1] = 0; c[2] = 3;
  ex[0] = 1; ex[1] = 0; ex[2] = 0; ey[0] = 0; ey[1] = 1; ey[2] = 0; /* x cross y = +z */
  make_portal(pts, c, ex, ey, 1.0, 1.0);
  make_map(NULL, 0);
  el_envlight_init(&L, g_map, MW, MH, 3, &lo);
  pos[0] = 0.2f; pos[1] = -0.1f; pos[2] = 1;
  run_case("skylight at the pole", &L, pts, 1, pos, &po, 100000);
  el_envlight_free(&L);
  /* a sun seen through the seam window, and one outside it */
  c[0] = 2; c[1] = 0; c[2] = 1;
  ex[0] = 0; ex[1] = 1; ex[2] = 0; ey[0] = 0; ey[1] = 0; ey[2] = 1;
  make_portal(pts, c, ex, ey, 1.5, 1.0);
  pos[0] = 0; pos[1] = 0; pos[2] = 0.5f;
  sun_in[0] = 2; sun_in[1] = 0.2; sun_in[2] = 0.6;
  { double n = sqrt(sun_in[0] * sun_in[0] + sun_in[1] * sun_in[1] + sun_in[2] * sun_in[2]); sun_in[0] /= n; sun_in[1] /= n; sun_in[2] /= n; }
  make_map(sun_in, 4);
  el_envlight_init(&L, g_map, MW, MH, 3, &lo);
  run_case("sun inside the window", &L, pts, 1, pos, &po, 100000);
  el_envlight_free(&L);
  sun_out[0] = -0.3; sun_out[1] = 0.5; sun_out[2] = 0.81;
  make_map(sun_out, 4);
  el_envlight_init(&L, g_map, MW, MH, 3, &lo);
  run_case("sun outside the window", &L, pts, 1, pos, &po, 100000);
  el_envlight_free(&L);
  /* the y-up matrix and a scale; two windows (the second in the wall y = -2 facing -y) */
  make_map(sun_in, 4);
  lo.scale[0] = 2; lo.scale[1] = 0.5f; lo.scale[2] = 1;
  el_envlight_yup_matrix(lo.light_to_world);
  el_envlight_init(&L, g_map, MW, MH, 3, &lo);
  run_case("y-up matrix and scale", &L, pts, 1, pos, &po, 100000);
  c2[0] = 0; c2[1] = -2; c2[2] = 1;
  ex2[0] = 1; ex2[1] = 0; ex2[2] = 0; ey2[0] = 0; ey2[1] = 0; ey2[2] = 1; /* x cross z = -y */
  make_portal(pts + 12, c2, ex2, ey2, 1.0, 1.2);
  run_case("two windows", &L, pts, 2, pos, &po, 100000);
  {
    el_envlight_portal_options p3 = po;
    p3.map_share = 0.25f;
    run_case("two windows, map share 0.25 (defensive mixture)", &L, pts, 2, pos, &p3, 100000);
    p3.map_share_outside = 1; /* in front of both portals: the pure portal density */
    run_case("two windows, map share 0.25 outside only, a point inside", &L, pts, 2, pos, &p3, 100000);
    {
      float out[3] = {2.5f, 0.3f, 0.8f}; /* behind window 1's plane, in front of window 2's: the mixture */
      run_case("two windows, map share 0.25 outside only, a point behind window 1", &L, pts, 2, out, &p3, 100000);
    }
  }
  el_envlight_free(&L);
}

static void test_pdf_zero_and_fallback(void) {
  el_envlight L;
  el_envlight_portal P;
  float pts[12], pos[3] = {0, 0.1f, 0.6f}, w[3], u[2] = {0.3f, 0.7f}, wi[3], rgb[3], pdf;
  double c[3] = {2, 0, 1}, ex[3] = {0, 1, 0}, ey[3] = {0, 0, 1};
  int i, zero_out = 1, pos_in = 1, used;
  make_map(NULL, 0);
  el_envlight_init(&L, g_map, MW, MH, 3, NULL);
  make_portal(pts, c, ex, ey, 1.5, 1.0);
  el_envlight_portal_init(&P, &L, pts, 1, NULL);
  for (i = 0; i < 200; ++i) { /* points on a ring just outside (1.01x) and just inside (0.99x) the rectangle */
    double t = 2 * PI * i / 200 + 0.01, sa = 0.75 / fabs(cos(t)), sb = 0.5 / fabs(sin(t)), s = sa < sb ? sa : sb;
    double q[3];
    int k;
    for (k = 0; k < 2; ++k) {
      double f = k ? 0.99 : 1.01;
      q[0] = 2; q[1] = f * s * cos(t); q[2] = 1 + f * s * sin(t) * 1.0;
      w[0] = (float)(q[0] - pos[0]); w[1] = (float)(q[1] - pos[1]); w[2] = (float)(q[2] - pos[2]);
      if (k == 0 && el_envlight_portal_pdf_li(&P, &L, pos, w) != 0.0f) zero_out = 0;
      if (k == 1 && !(el_envlight_portal_pdf_li(&P, &L, pos, w) > 0.0f)) pos_in = 0;
    }
  }
  check(zero_out, "pdf 0 through points 1% outside the window", 0, 0);
  check(pos_in, "pdf > 0 through points 1% inside the window", 0, 0);
  w[0] = -1; w[1] = 0; w[2] = 0;
  check(el_envlight_portal_pdf_li(&P, &L, pos, w) == 0.0f, "pdf 0 away from the window", 0, 0);
  w[0] = NAN; w[1] = 0; w[2] = 0;
  check(el_envlight_portal_pdf_li(&P, &L, pos, w) == 0.0f, "pdf 0 for a NaN direction", 0, 0);
  /* behind the plane: the map's own sampling */
  pos[0] = 3;
  used = el_envlight_portal_sample_li(&P, &L, pos, u, wi, rgb, &pdf);
  {
    float wi2[3], pdf2;
    el_envlight_sample_li(&L, u, wi2, NULL, &pdf2);
    used += (wi2[0] != wi[0] || wi2[1] != wi[1] || wi2[2] != wi[2] || pdf2 != pdf) ? 10 : 0;
  }
  check(used == 0 && el_envlight_portal_pdf_li(&P, &L, pos, wi) == el_envlight_pdf_li(&L, wi),
        "behind the portal's plane: the map's sample_li and pdf_li", used, pdf);
  check(!el_envlight_portal_sees(&P, pos), "behind the plane: sees no portal", 0, 0);
  pos[0] = 2;
  check(!el_envlight_portal_sees(&P, pos), "on the plane: sees no portal", 0, 0);
  pos[0] = NAN;
  check(!el_envlight_portal_sees(&P, pos), "NaN point: sees no portal", 0, 0);
  check(el_envlight_portal_bytes(&P) == 129u * 129u * 8u && P.res == 128, "8 bytes per rectified texel; the default resolution is twice the map height (128)", (double)el_envlight_portal_bytes(&P), 0);
  el_envlight_portal_free(&P);
  el_envlight_free(&L);
}

static void expect_error(const el_envlight *L, const float *pts, int count, el_result want, const char *needle, const char *what) {
  el_envlight_portal P;
  el_result r = el_envlight_portal_init(&P, L, pts, count, NULL);
  printf("  %s -> %s: \"%s\"\n", what, el_result_string(r), P.error);
  check(r == want && strstr(P.error, needle) != NULL && P.sat == NULL, what, r, want);
  el_envlight_portal_free(&P);
}

static void test_hostile(void) {
  el_envlight L;
  float pts[24], q[12];
  double c[3] = {2, 0, 1}, ex[3] = {0, 1, 0}, ey[3] = {0, 0, 1};
  el_envlight_portal_options o;
  el_envlight_portal P;
  make_map(NULL, 0);
  el_envlight_init(&L, g_map, MW, MH, 3, NULL);
  make_portal(pts, c, ex, ey, 1.5, 1.0);
  make_portal(pts + 12, c, ex, ey, 1.5, 1.0);
  memcpy(q, pts, sizeof q);
  q[3] = q[0]; q[4] = q[1]; q[5] = q[2];
  expect_error(&L, q, 1, EL_ERROR_INVALID_ARGUMENT, "degenerate", "degenerate portal (p1 = p0)");
  memcpy(q, pts, sizeof q);
  q[6] += 0.2f; /* p2 off the plane */
  expect_error(&L, q, 1, EL_ERROR_INVALID_ARGUMENT, "not a planar", "non-planar portal");
  memcpy(q, pts, sizeof q);
  q[8] += 0.3f; q[11] += 0.3f; /* a parallelogram: p2, p3 shifted along z */
  expect_error(&L, q, 1, EL_ERROR_INVALID_ARGUMENT, "perpendicular", "parallelogram portal");
  memcpy(q, pts, sizeof q);
  { float t[3]; memcpy(t, q + 3, sizeof t); memcpy(q + 3, q + 6, sizeof t); memcpy(q + 6, t, sizeof t); }
  expect_error(&L, q, 1, EL_ERROR_INVALID_ARGUMENT, "not a planar", "vertices out of order (a bow tie)");
  memcpy(q, pts, sizeof q);
  q[4] = NAN;
  expect_error(&L, q, 1, EL_ERROR_NAN, "NaN", "NaN vertex");
  memcpy(q, pts, sizeof q);
  q[8] = INFINITY;
  expect_error(&L, q, 1, EL_ERROR_INFINITE, "infinite", "infinite vertex");
  pts[12 + 4] = NAN;
  expect_error(&L, pts, 2, EL_ERROR_NAN, "portal 1", "the second portal is named");
  expect_error(&L, pts, 0, EL_ERROR_INVALID_ARGUMENT, "count", "zero portals");
  memset(&o, 0, sizeof o);
  o.resolution = 2;
  check(el_envlight_portal_init(&P, &L, pts, 1, &o) == EL_ERROR_INVALID_ARGUMENT, "resolution 2 is refused", 0, 0);
  el_envlight_portal_free(&P);
  check(el_envlight_portal_init(&P, NULL, pts, 1, NULL) == EL_ERROR_INVALID_ARGUMENT, "NULL light is refused", 0, 0);
  el_envlight_portal_free(&P);
  o.resolution = 0;
  o.map_share = NAN;
  check(el_envlight_portal_init(&P, &L, pts, 1, &o) == EL_ERROR_INVALID_ARGUMENT, "a NaN map_share is refused", 0, 0);
  el_envlight_portal_free(&P);
  o.map_share = 1.5f;
  check(el_envlight_portal_init(&P, &L, pts, 1, &o) == EL_ERROR_INVALID_ARGUMENT, "map_share 1.5 is refused", 0, 0);
  el_envlight_portal_free(&P);
  el_envlight_free(&L);
}

int main(void) {
  test_cases();
  test_pdf_zero_and_fallback();
  test_hostile();
  printf("%d passed, %d failed\n", g_pass, g_fail);
  return g_fail ? 1 : 0;
}
