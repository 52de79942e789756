/* test_render_materials: pbrt-v3's glass, metal, uber and substrate (materials.c, reflection.c) against
 * closed forms and conservation laws, each answer computed here, independently of the code under test.
 *
 * 1. FrDielectric against the Fresnel equations written with Snell's law in double precision (both
 *    sides of the surface, total internal reflection past the critical angle); ((n-1)/(n+1))^2 at
 *    normal incidence.
 * 2. A smooth dielectric conserves energy at every angle: the reflected fraction F(theta_i) plus the
 *    transmitted fraction (SpecularTransmission's f |cos| with the radiance scaling (etaI/etaT)^2 taken
 *    out) is 1, on both sides; the refracted direction obeys Snell's law; FresnelSpecular's two
 *    branches carry f |cos| / pdf = 1 and (etaI/etaT)^2.
 * 3. FrConductor against the complex Fresnel equations (n + ik, C99 complex arithmetic) at every angle,
 *    at normal incidence against ((n-1)^2 + k^2) / ((n+1)^2 + k^2) for aluminium (n 1.0972, k 6.7942 at
 *    550 nm: R = 0.9161, a published reflectance of about 0.916) and the copper default; with k = 0 the
 *    conductor equals FrDielectric(1, eta), and a metal lobe of k = 0 equals the dielectric
 *    microfacet reflection.
 * 4. Reciprocity: f(wo, wi) = f(wi, wo) for the reflection lobes (metal, substrate, uber, rough glass);
 *    for rough transmission pbrt-v3's radiance-transport rule f(wo, wi) / eta_o^2 = f(wi, wo) / eta_i^2
 *    (eta on the side of each direction).
 * 5. Sampling agrees with evaluation: the albedo estimated with Sample_f (f |cos| / pdf) equals the
 *    albedo integrated from f by a quadrature over the sphere, for each lobe kind, within 2%;
 *    FresnelBlend with Rs = 0 against its closed-form albedo (quadrature of its diffuse formula).
 * 6. Renders: a smooth glass sphere under a constant sky L = 1 renders L in every pixel with the path
 *    tracer (enough depth, no Russian roulette: within 1e-5; with roulette the mean within 1%) and with
 *    directlighting (maxdepth 10: within 1e-3); glass of index 1 is invisible in front of a non-constant
 *    map; a metal sphere under a constant sky never gets brighter than the sky; an uber of opacity 0 is
 *    invisible; Integrator "whitted" falls back to path with its maxdepth. */
#include "render_test_util.h"
#include <complex.h>

#define PI 3.14159265358979323846

/* >> small helpers */
static elr_v3 dir_sph(double theta, double phi) { return elr_v((float)(sin(theta) * cos(phi)), (float)(sin(theta) * sin(phi)), (float)cos(theta)); }
static double maxrel(elr_v3 a, elr_v3 b) {
  double d = fabs(a.x - b.x), m = fmax(fabs(a.x), fabs(b.x));
  if (fabs(a.y - b.y) > d) d = fabs(a.y - b.y);
  if (fabs(a.z - b.z) > d) d = fabs(a.z - b.z);
  m = fmax(m, fmax(fmax(fabs(a.y), fabs(b.y)), fmax(fabs(a.z), fabs(b.z))));
  return m > 0 ? d / m : 0;
}
static uint64_t rs = 88172645463325252ULL;
static double rnd(void) { rs ^= rs << 13; rs ^= rs >> 7; rs ^= rs << 17; return (double)(rs >> 11) * 0x1p-53; }
/* a BSDF in the frame z up */
static void frame(elr_bsdf *b, float eta) { elr_bsdf_begin(b, elr_v(0, 0, 1), elr_v(0, 0, 1), eta); }

/* the Fresnel reflectance of unpolarised light at a dielectric interface, incident from index n1 */
static double fresnel_ref(double cosi, double n1, double n2) {
  double sini = sqrt(fmax(0, 1 - cosi * cosi)), sint = n1 / n2 * sini, cost, rs, rp;
  if (sint >= 1) return 1;
  cost = sqrt(1 - sint * sint);
  rs = (n1 * cosi - n2 * cost) / (n1 * cosi + n2 * cost);
  rp = (n1 * cost - n2 * cosi) / (n1 * cost + n2 * cosi);
  return 0.5 * (rs * rs + rp * rp);
}
/* the same for a conductor of complex index n + ik (from vacuum) */
static double conductor_ref(double cosi, double n, double k) {
  double complex eta = n + k * I, s2 = 1 - cosi * cosi, ct = csqrt(eta * eta - s2);
  double complex rs = (cosi - ct) / (cosi + ct), rp = (eta * eta * cosi - ct) / (eta * eta * cosi + ct);
  return 0.5 * (creal(rs * conj(rs)) + creal(rp * conj(rp)));
}

static void fresnel_dielectric(void) {
  static const double etas[3] = {1.33, 1.5, 2.4};
  int e, i;
  double worst = 0;
  for (e = 0; e < 3; e++)
    for (i = -200; i <= 200; i++) {
      double c = i / 200.0, ref = c > 0 ? fresnel_ref(c, 1.0, etas[e]) : fresnel_ref(-c, etas[e], 1.0);
      double got = elr_fr_dielectric((float)c, 1.f, (float)etas[e]);
      if (i == 0) continue; /* grazing: both 1 */
      if (fabs(got - ref) > worst) worst = fabs(got - ref);
    }
  rt_check(worst < 5e-6, "FrDielectric = the Fresnel equations for eta 1.33, 1.5, 2.4 at 400 cosines on both sides, TIR included (max |diff| %.2g; "
           "float arithmetic, largest next to the critical angle)", worst);
  rt_check(fabs(elr_fr_dielectric(1.f, 1.f, 1.5f) - 0.04) < 1e-7, "normal incidence on glass 1.5: ((n-1)/(n+1))^2 = 0.04 (%.8f)",
           elr_fr_dielectric(1.f, 1.f, 1.5f));
  rt_check(elr_fr_dielectric(-0.5f, 1.f, 1.5f) == 1.f, "from inside glass 1.5 at 60 degrees (past the critical 41.8): total internal reflection");
}

static void energy_smooth(void) {
  static const double etas[2] = {1.5, 2.4};
  int e, i, side;
  double worst = 0, worst80 = 0, worst_snell = 0, worst_fs = 0;
  for (e = 0; e < 2; e++)
    for (side = 0; side < 2; side++)
      for (i = 1; i < 100; i++) {
        elr_bsdf br, bt, bf;
        elr_bxdf *x;
        double th = i / 100.0 * PI / 2, sum, ei = side ? etas[e] : 1.0, et = side ? 1.0 : etas[e];
        elr_v3 wo = dir_sph(th, 0.7), wi, f;
        float pdf;
        int fl;
        if (side) wo.z = -wo.z;
        frame(&br, (float)etas[e]);
        x = elr_bsdf_add(&br, ELR_BXDF_SPECULAR_REFLECTION);
        x->fresnel = ELR_FRESNEL_DIELECTRIC; x->eta_a = 1.f; x->eta_b = (float)etas[e];
        f = elr_bsdf_sample_type(&br, wo, 0.5f, 0.5f, ELR_BSDF_ALL, &wi, &pdf, &fl);
        sum = f.x * fabs(wi.z) / pdf;
        frame(&bt, (float)etas[e]);
        x = elr_bsdf_add(&bt, ELR_BXDF_SPECULAR_TRANSMISSION);
        x->eta_a = 1.f; x->eta_b = (float)etas[e];
        f = elr_bsdf_sample_type(&bt, wo, 0.5f, 0.5f, ELR_BSDF_ALL, &wi, &pdf, &fl);
        if (pdf > 0) {
          double sin_i = sin(th), sin_t = sqrt((double)wi.x * wi.x + (double)wi.y * wi.y);
          sum += f.x * fabs(wi.z) / pdf * (et * et) / (ei * ei);
          if (fabs(ei * sin_i - et * sin_t) > worst_snell) worst_snell = fabs(ei * sin_i - et * sin_t);
          if (wi.z * wo.z >= 0) worst_snell = 1;
          if (fabs(wi.x * wo.y - wi.y * wo.x) > 1e-6) worst_snell = 1; /* in the plane of incidence */
        }
        if (fabs(sum - 1) > worst) worst = fabs(sum - 1);
        if (th <= 80 * PI / 180 && fabs(sum - 1) > worst80) worst80 = fabs(sum - 1);
        /* FresnelSpecular: reflect with probability F, f |cos| / pdf = 1 then, (etaI/etaT)^2 when transmitted */
        frame(&bf, (float)etas[e]);
        x = elr_bsdf_add(&bf, ELR_BXDF_FRESNEL_SPECULAR);
        x->eta_a = 1.f; x->eta_b = (float)etas[e];
        {
          double F = side ? fresnel_ref(cos(th), etas[e], 1.0) : fresnel_ref(cos(th), 1.0, etas[e]), v;
          f = elr_bsdf_sample_type(&bf, wo, (float)(F * 0.5), 0.5f, ELR_BSDF_ALL, &wi, &pdf, &fl);
          v = f.x * fabs(wi.z) / pdf;
          if (fabs(v - 1) > worst_fs || !(fl & ELR_BSDF_REFLECTION)) worst_fs = fmax(fabs(v - 1), (fl & ELR_BSDF_REFLECTION) ? 0 : 1);
          if (F < 0.999) {
            f = elr_bsdf_sample_type(&bf, wo, (float)(F + (1 - F) * 0.5), 0.5f, ELR_BSDF_ALL, &wi, &pdf, &fl);
            v = f.x * fabs(wi.z) / pdf / ((ei * ei) / (et * et));
            if (fabs(v - 1) > worst_fs || !(fl & ELR_BSDF_TRANSMISSION)) worst_fs = fmax(fabs(v - 1), (fl & ELR_BSDF_TRANSMISSION) ? 0 : 1);
          }
        }
      }
  rt_check(worst80 < 5e-6 && worst < 1e-4, "smooth dielectric, eta 1.5 and 2.4, from both sides, 99 angles: reflected + transmitted = 1 (max |R + T - 1| "
           "%.2g up to 80 degrees, %.2g at 89: float rounding of the refracted cosine, where the inner angle is near critical)", worst80, worst);
  rt_check(worst_snell < 1e-5, "refraction obeys Snell's law in the plane of incidence (max |n1 sin1 - n2 sin2| %.2g)", worst_snell);
  rt_check(worst_fs < 1e-5, "FresnelSpecular: f |cos| / pdf = 1 reflected, (etaI/etaT)^2 transmitted (max dev %.2g)", worst_fs);
}

static void conductor(void) {
  static const double nk[4][2] = {{1.0972, 6.7942}, {0.2, 3.9}, {1.5, 0.0}, {0.05, 0.3}};
  int m, i;
  double worst = 0, worst_k0 = 0;
  for (m = 0; m < 4; m++)
    for (i = 0; i <= 100; i++) {
      double c = i / 100.0, ref = conductor_ref(c, nk[m][0], nk[m][1]);
      elr_v3 got = elr_fr_conductor((float)c, elr_v((float)nk[m][0], (float)nk[m][0], (float)nk[m][0]), elr_v((float)nk[m][1], (float)nk[m][1], (float)nk[m][1]));
      if (fabs(got.x - ref) > worst) worst = fabs(got.x - ref);
    }
  rt_check(worst < 2e-5, "FrConductor = the complex Fresnel equations for 4 metals at 101 angles (max |diff| %.2g)", worst);
  { /* published optical constants: pbrt-v3's copper table (materials/metal.cpp) at 604.8 nm, n 0.35125, k 3.01075 */
    double n = 0.35125, k = 3.01075, ref = ((n - 1) * (n - 1) + k * k) / ((n + 1) * (n + 1) + k * k);
    elr_v3 got = elr_fr_conductor(1.f, elr_v((float)n, (float)n, (float)n), elr_v((float)k, (float)k, (float)k));
    rt_check(fabs(got.x - ref) < 1e-5 && fabs(ref - 0.87099) < 1e-4, "copper at 604.8 nm, normal incidence: %.5f = ((n-1)^2+k^2)/((n+1)^2+k^2) = %.5f", got.x, ref);
  }
  for (i = 1; i <= 100; i++) {
    double c = i / 100.0;
    elr_v3 got = elr_fr_conductor((float)c, elr_v(1.5f, 2.f, 3.f), elr_v(0, 0, 0));
    double d = fmax(fabs(got.x - elr_fr_dielectric((float)c, 1.f, 1.5f)), fmax(fabs(got.y - elr_fr_dielectric((float)c, 1.f, 2.f)),
                                                                                  fabs(got.z - elr_fr_dielectric((float)c, 1.f, 3.f))));
    if (d > worst_k0) worst_k0 = d;
  }
  rt_check(worst_k0 < 2e-6, "a conductor with k = 0 reflects as FrDielectric(1, eta) (eta 1.5, 2, 3; max |diff| %.2g)", worst_k0);
  { /* the whole lobe: metal of k = 0 against the dielectric microfacet reflection of glass */
    elr_bsdf a, b;
    elr_bxdf *x;
    double w = 0;
    frame(&a, 1.f); frame(&b, 1.5f);
    x = elr_bsdf_add(&a, ELR_BXDF_MICROFACET_REFLECTION); x->fresnel = ELR_FRESNEL_CONDUCTOR; x->eta = elr_v(1.5f, 1.5f, 1.5f);
    x->k = elr_v(0, 0, 0); x->ax = 0.3f; x->ay = 0.2f;
    x = elr_bsdf_add(&b, ELR_BXDF_MICROFACET_REFLECTION); x->fresnel = ELR_FRESNEL_DIELECTRIC; x->eta_a = 1.f; x->eta_b = 1.5f;
    x->ax = 0.3f; x->ay = 0.2f;
    for (i = 0; i < 1000; i++) {
      elr_v3 wo = dir_sph(acos(rnd()), 2 * PI * rnd()), wi = dir_sph(acos(rnd()), 2 * PI * rnd());
      double r = maxrel(elr_bsdf_f(&a, wo, wi), elr_bsdf_f(&b, wo, wi));
      if (r > w) w = r;
    }
    rt_check(w < 1e-5, "a rough metal lobe of k = 0 equals the dielectric microfacet reflection, 1000 direction pairs (max rel %.2g)", w);
  }
}


static void reciprocity(void) {
  static const char *mats[5] = {"Material \"metal\" \"float uroughness\" 0.3 \"float vroughness\" 0.1 \"bool remaproughness\" \"false\"",
                                "Material \"metal\"",
                                "Material \"substrate\" \"rgb Kd\" [ 0.6 0.3 0.2 ] \"rgb Ks\" [ 0.2 0.4 0.1 ] \"float uroughness\" 0.2",
                                "Material \"uber\" \"rgb Kd\" [ 0.5 0.4 0.3 ] \"rgb Ks\" [ 0.3 0.3 0.3 ] \"float roughness\" 0.05",
                                "Material \"glass\" \"float uroughness\" 0.15 \"float vroughness\" 0.3"};
  int m, i;
  for (m = 0; m < 5; m++) {
    elr_bsdf b;
    double w = 0;
    if (rt_bsdf_of(mats[m], &b) != 0) continue;
    for (i = 0; i < 2000; i++) {
      elr_v3 wo = dir_sph(acos(rnd()), 2 * PI * rnd()), wi = dir_sph(acos(rnd()), 2 * PI * rnd());
      elr_v3 f1 = elr_bsdf_f(&b, wo, wi), f2 = elr_bsdf_f(&b, wi, wo);
      double r = maxrel(f1, f2);
      if (r > w) w = r;
    }
    rt_check(w < 2e-4 && b.nlobes > 0, "reciprocity f(wo, wi) = f(wi, wo) of reflection: %s (2000 pairs, max rel %.2g)", mats[m], w);
  }
  { /* rough transmission: f(wo, wi) / eta_o^2 = f(wi, wo) / eta_i^2 */
    elr_bsdf b;
    double w = 0;
    int n = 0;
    if (rt_bsdf_of("Material \"glass\" \"float uroughness\" 0.3 \"float vroughness\" 0.3 \"float index\" 1.5", &b) == 0) {
      for (i = 0; i < 4000; i++) {
        elr_v3 wo = dir_sph(acos(rnd()), 2 * PI * rnd()), wi = dir_sph(acos(rnd()), 2 * PI * rnd());
        elr_v3 f1, f2;
        double eo, ei, a, c;
        wi.z = -wi.z; /* the other side */
        if (i & 1) { wo.z = -wo.z; wi.z = -wi.z; }
        f1 = elr_bsdf_f(&b, wo, wi); f2 = elr_bsdf_f(&b, wi, wo);
        eo = wo.z > 0 ? 1.0 : 1.5; ei = wi.z > 0 ? 1.0 : 1.5;
        a = f1.x / (eo * eo); c = f2.x / (ei * ei);
        if (fmax(a, c) > 1e-3) { n++; if (fabs(a - c) / fmax(a, c) > w) w = fabs(a - c) / fmax(a, c); }
        else if (fabs(a - c) > 0.05 * fmax(a, c) + 1e-7) w = 1; /* small values: (1 - F) near grazing, in float */
      }
      rt_check(n > 500 && w < 5e-3, "rough glass transmission: f(wo, wi) / eta_o^2 = f(wi, wo) / eta_i^2 (%d pairs with f > 1e-3: max rel %.2g; "
               "smaller ones within 5%%: 1 - F in float near grazing; a wrong power of eta would be off by 125%%)", n, w);
    }
  }
}

/* the albedo of b for wo by Sample_f (n samples) and by a midpoint quadrature of f |cos| over the sphere */
static void albedo(const elr_bsdf *b, elr_v3 wo, int n, double *sampled, double *quad) {
  int i, j, N = 400;
  double s = 0, q = 0;
  for (i = 0; i < n; i++) {
    elr_v3 wi, f;
    float pdf;
    int spec;
    f = elr_bsdf_sample(b, wo, (float)rnd(), (float)rnd(), &wi, &pdf, &spec);
    if (pdf > 0 && !spec) s += f.y * fabs(wi.z) / pdf;
  }
  /* quadrature in (cos theta, phi): dw = dcos dphi, refined where lobes are narrow */
  for (i = 0; i < 2 * N; i++)
    for (j = 0; j < 2 * N; j++) {
      double c = -1 + (i + 0.5) / N, ph = PI * (j + 0.5) / N, st = sqrt(fmax(0, 1 - c * c));
      elr_v3 wi = elr_v((float)(st * cos(ph)), (float)(st * sin(ph)), (float)c);
      q += elr_bsdf_f(b, wo, wi).y * fabs(c) * (1.0 / N) * (PI / N);
    }
  *sampled = s / n; *quad = q;
}
static void sampling(void) {
  static const char *mats[5] = {"Material \"metal\" \"float roughness\" 0.3", "Material \"substrate\" \"float uroughness\" 0.3 \"float vroughness\" 0.15",
                                "Material \"uber\" \"float roughness\" 0.3", "Material \"glass\" \"float uroughness\" 0.4 \"float vroughness\" 0.4",
                                "Material \"glass\" \"float uroughness\" 0.4 \"float vroughness\" 0.4"};
  int m;
  for (m = 0; m < 5; m++) {
    elr_bsdf b;
    double sa, qa;
    elr_v3 wo = dir_sph(m == 4 ? PI - 0.6 : 0.6, 0.3);
    if (rt_bsdf_of(mats[m], &b) != 0) continue;
    albedo(&b, wo, 400000, &sa, &qa);
    rt_check(fabs(sa - qa) < 0.02 * qa + 2e-3, "Sample_f agrees with f: albedo by sampling %.4f, by quadrature %.4f: %s%s", sa, qa, mats[m],
             m == 4 ? " (from inside)" : "");
    rt_check(qa < 1.0 + 2e-3, "  and does not exceed 1 (%.4f)", qa);
  }
  { /* FresnelBlend away from its (narrow: alpha 0.001) specular peak: Ashikhmin and Shirley's diffuse term
     * 28 / (23 pi) Rd (1 - Rs) (1 - (1 - cos_i / 2)^5) (1 - (1 - cos_o / 2)^5) */
    elr_bsdf b;
    elr_bxdf *x;
    double w = 0;
    int i, n = 0;
    frame(&b, 1.f);
    x = elr_bsdf_add(&b, ELR_BXDF_FRESNEL_BLEND); x->R = elr_v(0.5f, 0.5f, 0.5f); x->T = elr_v(0.3f, 0.3f, 0.3f); x->ax = x->ay = 0.001f;
    for (i = 0; i < 2000; i++) {
      elr_v3 wo = dir_sph(acos(rnd()), 2 * PI * rnd()), wi = dir_sph(acos(rnd()), 2 * PI * rnd()), m = elr_v(-wo.x, -wo.y, wo.z);
      double ref = 28.0 / (23.0 * PI) * 0.5 * 0.7 * (1 - pow(1 - wi.z / 2, 5)) * (1 - pow(1 - wo.z / 2, 5)), got = elr_bsdf_f(&b, wo, wi).x;
      (void)m;
      /* the specular peak (D(wh) ~ alpha^2 / (pi sin^4 theta_h)) and grazing directions (where its 1 / max(cos) grows
       * and the diffuse term vanishes) left out */
      if (elr_norm(elr_add(wo, wi)).z > cos(0.5) || wo.z < 0.1f || wi.z < 0.1f) continue;
      n++;
      if (fabs(got - ref) / ref > w) w = fabs(got - ref) / ref;
    }
    rt_check(w < 1e-3, "FresnelBlend away from its specular peak = Ashikhmin-Shirley's diffuse term (%d pairs, max rel %.2g)", n, w);
  }
}

/* >> renders */
static void write_gradient_map(const char *name) {
  float px[16 * 8 * 3];
  char e[256];
  int i;
  for (i = 0; i < 16 * 8; i++) { px[3 * i] = 0.2f + (float)(i % 16) * 0.1f; px[3 * i + 1] = 0.3f + (float)(i / 16) * 0.2f; px[3 * i + 2] = 1.f; }
  if (el_image_write_pfm(rt_path(name), px, 16, 8, 3, e, sizeof e) != 0) { printf("cannot write %s: %s\n", name, e); exit(1); }
}
static int render_str(const char *name, const char *text, int spp, elr_image *img, elr_stats *st) {
  char err[512];
  elr_scene *s = rt_load(name, text, err, sizeof err);
  int r;
  if (!s) { rt_check(0, "%s: %s", name, err); return -1; }
  r = rt_render(s, spp, -1, -1, 2, 5, img, st);
  elr_scene_free(s);
  return r;
}
static const char *scene(char *buf, size_t n, const char *integrator, const char *light, const char *material) {
  snprintf(buf, n,
           "LookAt 0 0 -4  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [ 40 ]\n"
           "Film \"image\" \"integer xresolution\" [ 24 ] \"integer yresolution\" [ 24 ]\n"
           "Sampler \"random\" \"integer pixelsamples\" [ 8 ]\nIntegrator %s\nWorldBegin\n%s\n%s\n"
           "Shape \"sphere\" \"float radius\" 1\nWorldEnd\n", integrator, light, material);
  return buf;
}
static void renders(void) {
  char buf[4096];
  elr_image img, ref;
  elr_stats st;
  int k;
  double worst, mean;
  /* white furnace: glass in vacuum under L = 1 */
  if (render_str("g1.pbrt", scene(buf, sizeof buf, "\"path\" \"integer maxdepth\" 200 \"float rrthreshold\" 0", "LightSource \"infinite\"", "Material \"glass\""), 16,
                 &img, &st) == 0) {
    for (k = 0, worst = 0; k < 24 * 24 * 3; k++) worst = fmax(worst, fabs(img.rgb[k] - 1.0));
    rt_check(worst < 1e-5, "white furnace, glass sphere (index 1.5), path tracer, maxdepth 200, no roulette: every pixel = L = 1 (max dev %.2g)", worst);
    rt_check(st.shadow_rays == 0 && st.light_sampling_used == 0, "only specular surfaces: no light sampling, no shadow rays");
    elr_image_free(&img);
  }
  if (render_str("g2.pbrt", scene(buf, sizeof buf, "\"path\" \"integer maxdepth\" 50", "LightSource \"infinite\"", "Material \"glass\" \"float index\" 2.4"), 64,
                 &img, &st) == 0) {
    for (k = 0, mean = 0, worst = 0; k < 24 * 24 * 3; k++) { mean += img.rgb[k]; worst = fmax(worst, fabs(img.rgb[k] - 1.0)); }
    mean /= 24 * 24 * 3;
    rt_check(fabs(mean - 1) < 0.01, "white furnace, index 2.4, Russian roulette on: mean %.5f = 1 within 1%%", mean);
    /* pbrt-v3's etaScale keeps paths inside glass (beta 1 / 2.4^2) out of roulette: without it they would
     * be ended with probability 0.83 and the pixels would scatter by tens of percent */
    rt_check(worst < 0.04, "  and no pixel off by 4%% (max %.3f; 0.079 when roulette counts the radiance scaling of refraction: pbrt-v3 leaves it out, etaScale)", worst);
    elr_image_free(&img);
  }
  if (render_str("g3.pbrt", scene(buf, sizeof buf, "\"directlighting\" \"integer maxdepth\" 7", "LightSource \"infinite\"", "Material \"glass\""), 2, &img, &st) == 0) {
    /* maxdepth 7: 63 branches at most, all followed (no random choice); a path still inside after 6
     * refractions or reflections is lost: at most F(60 deg)^4 < 1e-4 for the pixels whose camera ray
     * meets the sphere within 60 degrees of its normal (within 6 pixels of the centre) */
    int x, y, nc = 0;
    for (y = 0, worst = 0; y < 24; y++)
      for (x = 0; x < 24; x++) {
        double r2 = (x - 11.5) * (x - 11.5) + (y - 11.5) * (y - 11.5);
        if (r2 > 36 && r2 < 144) continue; /* near the silhouette */
        nc += r2 <= 36;
        for (k = 0; k < 3; k++) worst = fmax(worst, fabs(img.rgb[3 * (24 * y + x) + k] - 1.0));
      }
    rt_check(nc > 100 && worst < 1e-3, "white furnace, glass, directlighting (reflection and transmission both followed, 6 bounces): %d central pixels "
             "and the background within 1e-3 of 1 (%.2g)", nc, worst);
    elr_image_free(&img);
  }
  /* glass of index 1 is invisible */
  write_gradient_map("grad.pfm");
  if (render_str("noglass.pbrt", scene(buf, sizeof buf, "\"path\"", "LightSource \"infinite\" \"string mapname\" \"grad.pfm\"", "Material \"matte\"\nScale 0.001 0.001 0.001"),
                 4, &ref, &st) == 0) {
    const char *integ[2] = {"\"path\" \"integer maxdepth\" 20", "\"directlighting\" \"integer maxdepth\" 20"};
    int q;
    for (q = 0; q < 2; q++) {
      if (render_str("idx1.pbrt", scene(buf, sizeof buf, integ[q], "LightSource \"infinite\" \"string mapname\" \"grad.pfm\"", "Material \"glass\" \"float index\" 1"),
                     4, &img, &st) == 0) {
        for (k = 0, worst = 0; k < 24 * 24 * 3; k++) worst = fmax(worst, fabs(img.rgb[k] - ref.rgb[k]) / ref.rgb[k]);
        rt_check(worst < 1e-4, "glass of index 1 in front of a gradient map (%s) renders as the map alone (max rel %.2g)", integ[q], worst);
        elr_image_free(&img);
      }
    }
    /* uber of opacity 0: SpecularTransmission(1, 1, 1), invisible too */
    if (render_str("op0.pbrt", scene(buf, sizeof buf, "\"path\" \"integer maxdepth\" 20", "LightSource \"infinite\" \"string mapname\" \"grad.pfm\"",
                                     "Material \"uber\" \"rgb opacity\" [ 0 0 0 ]"), 4, &img, &st) == 0) {
      for (k = 0, worst = 0; k < 24 * 24 * 3; k++) worst = fmax(worst, fabs(img.rgb[k] - ref.rgb[k]) / ref.rgb[k]);
      rt_check(worst < 1e-4, "uber of opacity 0 renders as the map alone (max rel %.2g)", worst);
      elr_image_free(&img);
    }
    elr_image_free(&ref);
  }
  /* a metal sphere under L = 1: reflects at most the sky (FrConductor <= 1, microfacet energy loss) */
  if (render_str("m1.pbrt", scene(buf, sizeof buf, "\"path\"", "LightSource \"infinite\"", "Material \"metal\" \"float roughness\" 0.2"), 64, &img, &st) == 0) {
    double mx = 0, mn = 1;
    for (k = 0; k < 24 * 24 * 3; k++) { mx = fmax(mx, img.rgb[k]); mn = fmin(mn, img.rgb[k]); }
    rt_check(mx < 1.0 + 0.02 && mn > 0.1, "copper under L = 1: every pixel in (0.1, 1] (min %.3f, max %.3f; the sky itself is 1)", mn, mx);
    /* the centre pixel sees the sphere head on: about copper's normal-incidence reflectance, red above green above blue */
    {
      const float *c = &img.rgb[3 * (12 * 24 + 12)];
      rt_check(c[0] > c[1] && c[1] > c[2], "copper's colour: red %.3f > green %.3f > blue %.3f", c[0], c[1], c[2]);
    }
    elr_image_free(&img);
  }
  /* the wave loop (render_wave.c: a wave's environment samples drawn together) gives the one-at-a-time
   * image bit for bit with the new materials too: its first vertex goes through the same BSDFs and
   * specular branches */
  {
    static const char *integ[2] = {"\"path\" \"integer maxdepth\" 6", "\"directlighting\" \"integer maxdepth\" 6"};
    int q;
    for (q = 0; q < 2; q++) {
      char err[512];
      elr_scene *s;
      snprintf(buf, sizeof buf,
               "LookAt 0 1 -4  0 0.3 0  0 1 0\nCamera \"perspective\" \"float fov\" [ 45 ]\n"
               "Film \"image\" \"integer xresolution\" [ 24 ] \"integer yresolution\" [ 16 ]\n"
               "Sampler \"halton\" \"integer pixelsamples\" [ 8 ]\nIntegrator %s\nWorldBegin\n"
               "LightSource \"infinite\" \"string mapname\" \"grad.pfm\"\n"
               "AttributeBegin\nTranslate -1.2 0.4 0\nMaterial \"glass\"\nShape \"sphere\" \"float radius\" 0.4\nAttributeEnd\n"
               "AttributeBegin\nTranslate -0.4 0.4 0\nMaterial \"metal\" \"float roughness\" 0.1\nShape \"sphere\" \"float radius\" 0.4\nAttributeEnd\n"
               "AttributeBegin\nTranslate 0.4 0.4 0\nMaterial \"uber\" \"rgb Kr\" [ 0.2 0.2 0.2 ] \"rgb opacity\" [ 0.6 0.6 0.6 ]\nShape \"sphere\" \"float radius\" 0.4\nAttributeEnd\n"
               "AttributeBegin\nTranslate 1.2 0.4 0\nMaterial \"glass\" \"float uroughness\" 0.2 \"float vroughness\" 0.1\nShape \"sphere\" \"float radius\" 0.4\nAttributeEnd\n"
               "Material \"substrate\"\nShape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point P\" [ -5 0 -5 5 0 -5 5 0 5 -5 0 5 ]\n"
               "WorldEnd\n", integ[q]);
      s = rt_load("batch.pbrt", buf, err, sizeof err);
      if (!s) { rt_check(0, "batch scene: %s", err); continue; }
      {
        elr_render_options o;
        elr_image a, b;
        elr_stats sa, sb;
        elr_render_options_default(&o);
        o.nthreads = 2; o.seed = 3; o.quiet = 1;
        o.env_sampling = 0; /* (batching draws the map's own samples) */
        if (elr_render(s, &o, &a, &sa, err, sizeof err) == 0) {
          o.no_batch = 1;
          if (elr_render(s, &o, &b, &sb, err, sizeof err) == 0) {
            rt_check(sa.light_samples_batched && !sb.light_samples_batched &&
                     memcmp(a.rgb, b.rgb, sizeof(float) * 3 * (size_t)a.width * (size_t)a.height) == 0,
                     "%s: glass, metal, uber, rough glass, substrate: the batched image is the one-at-a-time image, bit for bit", integ[q]);
            elr_image_free(&b);
          }
          elr_image_free(&a);
        }
        /* with product sampling (the default) rough glass's vertices sample the map alone: its tables
         * are built too (and not for a scene without rough transmission: test_render_strategies) */
        elr_render_options_default(&o);
        o.nthreads = 2; o.seed = 3; o.quiet = 1; o.spp = 1;
        if (elr_render(s, &o, &a, &sa, err, sizeof err) == 0) {
          rt_check(sa.light[0].env_product && sa.light[0].env_map_built && !sa.light_samples_batched,
                   "%s: product sampling with rough glass: the map's own tables built as well, one sample at a time", integ[q]);
          elr_image_free(&a);
        }
      }
      elr_scene_free(s);
    }
  }
  /* whitted falls back to path, keeping its maxdepth */
  {
    char err[512];
    elr_scene *s = rt_load("whitted.pbrt", scene(buf, sizeof buf, "\"whitted\" \"integer maxdepth\" 7", "LightSource \"infinite\"", "Material \"glass\""), err, sizeof err);
    rt_check(s && s->d.integrator_path == 1 && s->d.maxdepth == 7 && strstr(elr_scene_last_warning(s), "\"whitted\"") &&
             strstr(elr_scene_last_warning(s), "path"),
             "Integrator \"whitted\": path with maxdepth 7 and a warning naming it (\"%s\")", s ? elr_scene_last_warning(s) : err);
    elr_scene_free(s);
  }
}

int main(void) {
  rt_mkdir("test_render_materials");
  fresnel_dielectric();
  energy_smooth();
  conductor();
  reciprocity();
  sampling();
  renders();
  return rt_finish("test_render_materials");
}
