/* tests/labs/lab_03_light.c: lab 3 (tutorials/03-infinite-area-light.md): Distribution1D/2D and the
 * infinite light's Sample_Li and Pdf_Li in the files under test (stu_*) against pbrt's (ref_*,
 * examples/pbrtv3 built separately), plus facts derived by hand (a worked CDF; a sample's pdf is
 * Pdf at its point; Pdf_Li integrates to 1 over the sphere). */
#include "lab_check.h"
#include "lab_light.h"

#include <stdlib.h>

#define PI 3.14159265358979323846

static void part_d1(void) {
  static const float f[4] = {1, 2, 0, 5}, hand[5] = {0, .125f, .375f, .375f, 1}, zero[3] = {0, 0, 0};
  float cdf[5], rf[7] = {0.3f, 4, 1, 0, 0.2f, 2.5f, 1}, c0[8], c1[8];
  void *d = stu_d1_new(f, 4), *r, *s;
  int i;
  lab_part("part 1, TODO 1: Distribution1D's CDF (chapter 3, \"Step 2\")");
  /* by hand: steps 1, 2, 0, 5 of width 1/4: integral 2; running sums .25, .75, .75, 2 */
  lab_check(lab_close(stu_d1_funcint(d), 2, 1e-6), "f = {1, 2, 0, 5}: funcInt is %g, should be 2 (the integral: each step is 1/n = 1/4 wide)%s",
            stu_d1_funcint(d), lab_close(stu_d1_funcint(d), 8, 1e-6) ? ": divide func[i - 1] by n" : "");
  stu_d1_cdf(d, cdf);
  for (i = 0; i < 5; ++i)
    if (!lab_close(cdf[i], hand[i], 1e-6)) break;
  lab_check(i == 5, "f = {1, 2, 0, 5}: cdf[%d] is %g, should be %g (cdf = {0, .125, .375, .375, 1})%s", i, i < 5 ? cdf[i] : 0.,
            i < 5 ? hand[i] : 0., cdf[4] != 1 ? ": did you divide the running sums by funcInt (<<Transform step function integral into CDF>>)?" : "");
  stu_d1_free(d);
  d = stu_d1_new(zero, 3);
  stu_d1_cdf(d, cdf);
  lab_check(lab_close(cdf[1], 1 / 3., 1e-6) && lab_close(cdf[3], 1, 1e-6),
            "f = {0, 0, 0}: cdf is {%g, %g, %g, %g}: when funcInt is 0 the CDF is uniform, cdf[i] = i / n", cdf[0], cdf[1], cdf[2], cdf[3]);
  stu_d1_free(d);
  r = ref_d1_new(rf, 7);
  s = stu_d1_new(rf, 7);
  ref_d1_cdf(r, c0);
  stu_d1_cdf(s, c1);
  for (i = 0; i < 8; ++i)
    if (!lab_close(c0[i], c1[i], 1e-6)) break;
  lab_check(i == 8, "a 7-step function: cdf[%d] is %g, pbrt's %g", i, i < 8 ? c1[i] : 0., i < 8 ? c0[i] : 0.);
  ref_d1_free(r);
  stu_d1_free(s);
}

static void part_d1_sample(void) {
  float rf[7] = {0.3f, 4, 1, 0, 0.2f, 2.5f, 1};
  void *r = ref_d1_new(rf, 7), *s = stu_d1_new(rf, 7);
  int k;
  lab_part("part 2, TODO 2: Distribution1D::SampleContinuous (chapter 3, \"Step 2\")");
  for (k = 0; k <= 20; ++k) {
    float u = k == 20 ? 0.99999f : (float)k / 20.f, p0 = -1, p1 = -1, x0, x1;
    int o0 = -1, o1 = -1;
    x0 = ref_d1_sample(r, u, &p0, &o0);
    x1 = stu_d1_sample(s, u, &p1, &o1);
    if (!lab_check(o0 == o1, "SampleContinuous(u = %g): offset %d, pbrt's %d: offset = pbrt_FindInterval(n + 1, cdf, u), the step whose CDF segment holds u",
                   u, o1, o0))
      continue;
    if (!lab_check(lab_close(p0, p1, 1e-5), "SampleContinuous(u = %g): pdf %g, pbrt's %g: the density is func[offset] / funcInt (not divided by n: it is a density on [0, 1])",
                   u, p1, p0))
      continue;
    lab_check(lab_close(x0, x1, 1e-5),
              "SampleContinuous(u = %g): x = %g, pbrt's %g: du = u - cdf[offset], divided by cdf[offset + 1] - cdf[offset]; x = (offset + du) / n", u, x1,
              x0);
  }
  ref_d1_free(r);
  stu_d1_free(s);
}

static float grid[5 * 3] = {1, 0.5f, 3, 0, 2, 0.1f, 0.1f, 0.1f, 0.1f, 0.1f, 4, 0, 0, 1, 0};

static void part_d2(void) {
  void *r = ref_d2_new(grid, 5, 3), *s = stu_d2_new(grid, 5, 3);
  int i, j;
  lab_part("part 3, TODO 3 and 4: Distribution2D and its SampleContinuous (chapter 3, \"Step 2\")");
  /* by hand: the integral of the 5x3 grid over [0,1]^2 is its mean */
  lab_check(lab_close(stu_d2_funcint(s), 12. / 15, 1e-5),
            "a 5x3 grid: the marginal's funcInt is %g, should be the grid's integral, %g: marginalFunc[v] is row v's funcInt", stu_d2_funcint(s),
            12. / 15);
  for (i = 0; i < 5; ++i)
    for (j = 0; j < 5; ++j) {
      float u0 = (i + .3f) / 5, u1 = (j + .6f) / 5, a[2], b[2], pa = -1, pb = -1, sw[2], psw = -1;
      ref_d2_sample(r, u0, u1, a, &pa);
      stu_d2_sample(s, u0, u1, b, &pb);
      if (lab_close(a[0], b[0], 1e-5) && lab_close(a[1], b[1], 1e-5) && lab_close(pa, pb, 1e-5)) {
        lab_check(1, "");
        continue;
      }
      ref_d2_sample(r, u1, u0, sw, &psw);
      lab_check(0, "SampleContinuous(u = (%g, %g)) is uv = (%g, %g) with pdf %g, pbrt's (%g, %g) with pdf %g: %s", u0, u1, b[0], b[1], pb, a[0], a[1],
                pa,
                lab_close(sw[0], b[0], 1e-5) && lab_close(sw[1], b[1], 1e-5) ? "u[1] picks the row (pMarginal), u[0] the column in it"
                : lab_close(a[1], b[1], 1e-5) && !lab_close(a[0], b[0], 1e-5) ? "the row is right: sample pConditionalV[v] (v: the marginal's offset) with u[0]"
                                                                             : "pdf = pdfs[0] * pdfs[1]; uv = (the column's x, the row's x)");
    }
  ref_d2_free(r);
  stu_d2_free(s);
}

static void part_d2_pdf(void) {
  void *r = ref_d2_new(grid, 5, 3), *s = stu_d2_new(grid, 5, 3);
  int i, j;
  lab_part("part 4, TODO 5: Distribution2D::Pdf (chapter 3, \"Step 2\")");
  for (i = 0; i <= 6; ++i)
    for (j = 0; j <= 4; ++j) {
      float p0 = i == 6 ? 1.f : (float)i / 6 + 0.01f, p1 = j == 4 ? 1.f : (float)j / 4 + 0.02f;
      float a = ref_d2_pdf(r, p0, p1), b = stu_d2_pdf(s, p0, p1);
      lab_check(lab_close(a, b, 1e-5), "Pdf(%g, %g) is %g, pbrt's %g: the bin is iu = int(p[0] nu), iv = int(p[1] nv), clamped into the grid "
                "(p = 1 is the last bin); the density is pConditionalV[iv].func[iu] / pMarginal.funcInt",
                p0, p1, b, a);
    }
  { /* by hand: Pdf at a sampled point is the sample's pdf (with pbrt's own sampler) */
    float uv[2], pdf;
    ref_d2_sample(r, 0.77f, 0.31f, uv, &pdf);
    lab_check(lab_close(stu_d2_pdf(s, uv[0], uv[1]), pdf, 1e-5), "Pdf at the point pbrt's SampleContinuous gave for u = (0.77, 0.31) is %g, its pdf %g",
              stu_d2_pdf(s, uv[0], uv[1]), pdf);
  }
  ref_d2_free(r);
  stu_d2_free(s);
}

/* a 16x8 map with a bright spot, and its angle */
static void light_map(float *t) {
  int x, y;
  for (y = 0; y < 8; ++y)
    for (x = 0; x < 16; ++x) {
      float *p = t + 3 * (y * 16 + x);
      p[0] = 0.2f + 0.05f * (float)x;
      p[1] = 0.1f + 0.1f * (float)y;
      p[2] = (x == 11 && y == 2) ? 20.f : 0.3f;
    }
}

static void part_sample_li(void) {
  float map[3 * 16 * 8];
  void *r, *s;
  int i, j;
  lab_part("part 5, TODO 6: InfiniteAreaLight::Sample_Li (chapter 3, \"Step 3\")");
  light_map(map);
  r = ref_light_new(map, 16, 8);
  s = stu_light_new(map, 16, 8);
  for (i = 0; i < 6; ++i)
    for (j = 0; j < 6; ++j) {
      float u0 = (i + .5f) / 6, u1 = (j + .45f) / 6, w0[3], w1[3], p0 = -1, p1 = -1, L0[3], L1[3], ratio;
      ref_light_sample(r, u0, u1, w0, &p0, L0);
      stu_light_sample(s, u0, u1, w1, &p1, L1);
      if (!lab_check(lab_close(w0[0], w1[0], 1e-4) && lab_close(w0[1], w1[1], 1e-4) && lab_close(w0[2], w1[2], 1e-4),
                     "Sample_Li(u = (%.3f, %.3f)): wi = (%.4f, %.4f, %.4f), pbrt's (%.4f, %.4f, %.4f): %s", u0, u1, w1[0], w1[1], w1[2], w0[0], w0[1], w0[2],
                     (w1[0] == 0 && w1[1] == 0 && w1[2] == 0) ? "wi is 0: TODO 6 not written yet?"
                     : (lab_close(w1[0], w0[0], 1e-4) && lab_close(w1[1], -w0[2], 1e-4))
                         ? "it looks like the light's own direction: transform it by LightToWorld"
                         : "theta = uv[1] pi, phi = uv[0] 2 pi, direction (sin theta cos phi, sin theta sin phi, cos theta), then LightToWorld"))
        continue;
      ratio = p0 > 0 ? p1 / p0 : 0;
      if (!lab_check(lab_close(p0, p1, 1e-4), "Sample_Li(u = (%.3f, %.3f)): pdf %g, pbrt's %g: %s", u0, u1, p1, p0,
                     lab_close(ratio, 2 * PI * PI, 1e-3) ? "convert the map's density to solid angle: divide by 2 pi^2 sin theta"
                     : lab_close(ratio * sqrt(1 - w0[1] * w0[1]), 1, 1e-3) || lab_close(ratio, sqrt(1 - w0[1] * w0[1]), 1e-3)
                         ? "the Jacobian is 2 pi^2 sin theta: did you forget the sin theta (or use it twice)?"
                         : "*pdf = mapPdf / (2 pi^2 sin theta), mapPdf from Distribution2D's SampleContinuous (part 3)"))
        continue;
      lab_check(lab_close(L0[0], L1[0], 1e-4) && lab_close(L0[2], L1[2], 1e-4),
                "Sample_Li(u = (%.3f, %.3f)): L = (%g, %g, %g), pbrt's (%g, %g, %g): the radiance is the map at uv (pbrt_Lmap_Lookup)", u0, u1, L1[0], L1[1], L1[2],
                L0[0], L0[1], L0[2]);
    }
  ref_light_free(r);
  stu_light_free(s);
}

static void part_pdf_li(void) {
  float map[3 * 16 * 8];
  void *r, *s;
  int i, j, n = 0, bad = 0;
  double integral = 0;
  lab_part("part 6, TODO 7: InfiniteAreaLight::Pdf_Li (chapter 3, \"Step 3\")");
  light_map(map);
  r = ref_light_new(map, 16, 8);
  s = stu_light_new(map, 16, 8);
  /* directions on a 64 x 32 grid in (cos theta, phi): each cell has solid angle 4 pi / 2048 */
  for (j = 0; j < 32; ++j)
    for (i = 0; i < 64; ++i) {
      double z = 1 - 2 * (j + .5) / 32, phi = 2 * PI * (i + .5) / 64, st = sqrt(1 - z * z);
      float w[3], a, b;
      w[0] = (float)(st * cos(phi));
      w[1] = (float)(st * sin(phi));
      w[2] = (float)z;
      a = ref_light_pdf(r, w);
      b = stu_light_pdf(s, w);
      integral += b * 4 * PI / 2048;
      if (!bad && !lab_close(a, b, 1e-4)) {
        lab_check(0, "Pdf_Li(w = (%.3f, %.3f, %.3f)) is %g, pbrt's %g: %s", w[0], w[1], w[2], b, a,
                  lab_close(b / a, 2 * PI * PI, 1e-3) ? "divide the distribution's Pdf by 2 pi^2 sin theta"
                                                      : "bring w into the light's space with WorldToLight first, then p = (phi / 2 pi, theta / pi)");
        bad = 1;
      }
      n++;
    }
  if (!bad) lab_check(1, "");
  /* by hand: a density over the sphere integrates to 1 (the grid's error is well below 5 percent) */
  lab_check(fabs(integral - 1) < 0.05, "Pdf_Li integrates to %.4f over the sphere, not 1: it must be a density in solid angle", integral);
  { /* by hand: Pdf_Li of a direction pbrt's Sample_Li drew is that sample's pdf */
    float w[3], p, L[3];
    ref_light_sample(r, 0.3f, 0.6f, w, &p, L);
    lab_check(lab_close(stu_light_pdf(s, w), p, 1e-3), "Pdf_Li of the direction pbrt's Sample_Li drew for u = (0.3, 0.6) is %g, its pdf %g", stu_light_pdf(s, w), p);
  }
  (void)n;
  ref_light_free(r);
  stu_light_free(s);
}

int main(void) {
  printf("lab 3: the distributions and the infinite light (tutorials/03-infinite-area-light.md), your files against pbrt's\n\n");
  part_d1();
  part_d1_sample();
  part_d2();
  part_d2_pdf();
  part_sample_li();
  part_pdf_li();
  return lab_finish("lab 3 (the distributions and the infinite light)");
}
