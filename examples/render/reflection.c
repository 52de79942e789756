/* reflection.c: the BSDF and its lobes (pbrt-v3 core/reflection.cpp), the Trowbridge-Reitz microfacet
 * distribution (core/microfacet.cpp) and the Fresnel terms.
 *
 * Two arrangements of pbrt-v3's BSDF class, both evaluated as pbrt-v3 does (the shading frame around
 * the shading normal; a lobe reflects only when wi and wo lie on the same side of the geometric normal,
 * transmits only when they do not; Sample_f chooses one of the matching components uniformly and
 * returns the average pdf and the sum of the non-specular f):
 *   - the fixed lobes of matte, mirror and plastic (LambertianReflection; MicrofacetReflection with
 *     isotropic Trowbridge-Reitz and plastic's FresnelDielectric(1.5, 1); SpecularReflection with
 *     FresnelNoOp), the renderer's first and fastest path, kept as it was;
 *   - a list of BxDFs (">> BxDFs" below) for glass, metal, uber, substrate and matte of sigma > 0:
 *     LambertianReflection, OrenNayar,
 *     SpecularReflection and SpecularTransmission, FresnelSpecular (smooth glass in the path tracer),
 *     MicrofacetReflection and MicrofacetTransmission with anisotropic Trowbridge-Reitz, FresnelBlend;
 *     Fresnel terms FresnelNoOp, FresnelDielectric, FresnelConductor.
 * Transmission is radiance transport (pbrt-v3's TransportMode::Radiance): a ray entering a denser medium
 * carries (etaI / etaT)^2 of the radiance. Microfacet normals are sampled from their visible distribution
 * (Heitz 2018, exact for anisotropic alphas: the density pbrt-v3's Pdf states). */
#include "elr_internal.h"
#include <string.h>

/* >> microfacets (pbrt-v3 src/core/microfacet.cpp, TrowbridgeReitzDistribution) */
float elr_roughness_to_alpha(float r) {
  float x;
  r = fmaxf(r, 1e-3f);
  x = logf(r);
  return 1.62142f + 0.819955f * x + 0.1734f * x * x + 0.0171201f * x * x * x + 0.000640711f * x * x * x * x;
}
static float elr__tr_d(float alpha, elr_v3 wh) {
  float c2 = wh.z * wh.z, s2 = fmaxf(0.f, 1.f - c2), tan2, e;
  if (c2 <= 0.f) return 0.f;
  tan2 = s2 / c2;
  if (!isfinite(tan2)) return 0.f;
  e = tan2 / (alpha * alpha);
  return 1.f / (ELR_PI * alpha * alpha * c2 * c2 * (1.f + e) * (1.f + e));
}
static float elr__tr_lambda(float alpha, elr_v3 w) {
  float c2 = w.z * w.z, s2 = fmaxf(0.f, 1.f - c2), a2t2;
  if (c2 <= 0.f) return 0.f;
  a2t2 = alpha * alpha * s2 / c2;
  if (!isfinite(a2t2)) return 0.f;
  return (-1.f + sqrtf(1.f + a2t2)) * 0.5f;
}
static float elr__tr_g1(float alpha, elr_v3 w) { return 1.f / (1.f + elr__tr_lambda(alpha, w)); }
static float elr__tr_g(float alpha, elr_v3 wo, elr_v3 wi) {
  return 1.f / (1.f + elr__tr_lambda(alpha, wo) + elr__tr_lambda(alpha, wi));
}
/* pdf of wh with visible-normal sampling: D(wh) G1(wo) |wo.wh| / |cos wo| */
static float elr__tr_pdf_wh(float alpha, elr_v3 wo, elr_v3 wh) {
  if (wo.z == 0.f) return 0.f;
  return elr__tr_d(alpha, wh) * elr__tr_g1(alpha, wo) * fabsf(elr_dot(wo, wh)) / fabsf(wo.z);
}
/* Heitz 2018, "Sampling the GGX Distribution of Visible Normals" (exact; pbrt-v4's Sample_wm) */
static elr_v3 elr__tr2_sample(float ax, float ay, elr_v3 wo, float u0, float u1);
static elr_v3 elr__tr_sample_wh(float alpha, elr_v3 wo, float u0, float u1) { return elr__tr2_sample(alpha, alpha, wo, u0, u1); }
/* pbrt-v3's FrDielectric */
float elr_fr_dielectric(float cosi, float etai, float etat) {
  float sini, sint, cost, rpar, rperp;
  cosi = cosi < -1.f ? -1.f : (cosi > 1.f ? 1.f : cosi);
  if (cosi <= 0.f) { float t = etai; etai = etat; etat = t; cosi = fabsf(cosi); }
  sini = sqrtf(fmaxf(0.f, 1.f - cosi * cosi));
  sint = etai / etat * sini;
  if (sint >= 1.f) return 1.f;
  cost = sqrtf(fmaxf(0.f, 1.f - sint * sint));
  rpar = ((etat * cosi) - (etai * cost)) / ((etat * cosi) + (etai * cost));
  rperp = ((etai * cosi) - (etat * cost)) / ((etai * cosi) + (etat * cost));
  return (rpar * rpar + rperp * rperp) * 0.5f;
}

/* >> BSDF (core/reflection.cpp) */
static elr_v3 elr__to_local(const elr_bsdf *b, elr_v3 v) { return elr_v(elr_dot(v, b->ss), elr_dot(v, b->ts), elr_dot(v, b->ns)); }
static elr_v3 elr__glossy_f(const elr_bsdf *b, elr_v3 wo, elr_v3 wi) {
  float co = fabsf(wo.z), ci = fabsf(wi.z), F;
  elr_v3 wh = elr_add(wi, wo);
  if (ci == 0.f || co == 0.f) return elr_v(0, 0, 0);
  if (wh.x == 0.f && wh.y == 0.f && wh.z == 0.f) return elr_v(0, 0, 0);
  wh = elr_norm(wh);
  /* pbrt-v3 plastic: FresnelDielectric(1.5, 1), evaluated as MicrofacetReflection::f does: <<For the
   * Fresnel call, make sure that wh is in the same hemisphere as the surface normal>>. Below the shading
   * normal (a mesh whose normals point inwards: pbrt-v3's loopsubdiv, killeroo-simple.pbrt) the cosine is
   * then negative and FrDielectric swaps the indices: no total internal reflection past 41.8 degrees. */
  F = elr_fr_dielectric(elr_dot(wi, wh.z < 0.f ? elr_mul(wh, -1.f) : wh), 1.5f, 1.f);
  return elr_mul(b->ks, elr__tr_d(b->alpha, wh) * elr__tr_g(b->alpha, wo, wi) * F / (4.f * ci * co));
}
static float elr__glossy_pdf(const elr_bsdf *b, elr_v3 wo, elr_v3 wi) {
  elr_v3 wh;
  if (wo.z * wi.z <= 0.f) return 0.f;
  wh = elr_norm(elr_add(wo, wi));
  return elr__tr_pdf_wh(b->alpha, wo, wh) / (4.f * fabsf(elr_dot(wo, wh)));
}
static ELR_NOINLINE elr_v3 elr__list_f(const elr_bsdf *b, elr_v3 woW, elr_v3 wiW, int type);
static ELR_NOINLINE float elr__list_pdf(const elr_bsdf *b, elr_v3 woW, elr_v3 wiW, int type);
elr_v3 elr_bsdf_f(const elr_bsdf *b, elr_v3 woW, elr_v3 wiW) {
  elr_v3 wo, wi, f = elr_v(0, 0, 0);
  int reflect;
  if (b->nlobes) return elr__list_f(b, woW, wiW, ELR_BSDF_ALL);
  if (!b->has_glossy) return elr_bsdf_lambert_f(b, woW, wiW);
  reflect = elr_dot(wiW, b->ng) * elr_dot(woW, b->ng) > 0.f;
  wo = elr__to_local(b, woW); wi = elr__to_local(b, wiW);
  if (wo.z == 0.f || !reflect) return f;
  if (b->has_diffuse) f = elr_mul(b->kd, ELR_INV_PI);
  if (b->has_glossy) f = elr_add(f, elr__glossy_f(b, wo, wi));
  return f;
}
float elr_bsdf_pdf(const elr_bsdf *b, elr_v3 woW, elr_v3 wiW) {
  elr_v3 wo, wi;
  float pdf = 0.f;
  if (b->nlobes) return elr__list_pdf(b, woW, wiW, ELR_BSDF_ALL);
  if (!b->has_glossy) return elr_bsdf_lambert_pdf(b, woW, wiW);
  wo = elr__to_local(b, woW); wi = elr__to_local(b, wiW);
  if (wo.z == 0.f || b->ncomp == 0) return 0.f;
  if (b->has_diffuse && wo.z * wi.z > 0.f) pdf += fabsf(wi.z) * ELR_INV_PI;
  if (b->has_glossy) pdf += elr__glossy_pdf(b, wo, wi);
  return pdf / (float)b->ncomp;
}
elr_v3 elr_bsdf_sample(const elr_bsdf *b, elr_v3 woW, float u0, float u1, elr_v3 *wiW, float *pdf, int *specular) {
  elr_v3 wo, wi;
  int comp, k = 0, which = -1;
  if (elr_bsdf_lambert_alone(b, u0)) return elr_bsdf_lambert_sample(b, woW, u0, u1, wiW, pdf, specular);
  if (b->nlobes) {
    int flags = 0;
    elr_v3 f = elr_bsdf_sample_type(b, woW, u0, u1, ELR_BSDF_ALL, wiW, pdf, &flags);
    *specular = !(flags & ELR_BSDF_SPECULAR) ? 0 : (flags & ELR_BSDF_TRANSMISSION && !(flags & ELR_BSDF_REFLECTION) ? 2 : 1);
    return f;
  }
  wo = elr__to_local(b, woW);
  *pdf = 0.f; *specular = 0;
  if (b->ncomp == 0 || wo.z == 0.f) return elr_v(0, 0, 0);
  /* pbrt-v3: choose the component with u0, then remap u0 to [0,1) for the component's own sampling */
  comp = (int)(u0 * (float)b->ncomp);
  if (comp >= b->ncomp) comp = b->ncomp - 1;
  u0 = u0 * (float)b->ncomp - (float)comp;
  if (u0 > ELR_ONE_MINUS_EPS) u0 = ELR_ONE_MINUS_EPS;
  if (b->has_diffuse) { if (k == comp) which = 0; k++; }
  if (b->has_glossy) { if (k == comp) which = 1; k++; }
  if (b->has_specular) { if (k == comp) which = 2; k++; }
  if (which == 2) {
    /* SpecularReflection with FresnelNoOp: f = R / |cos wi|, pdf 1 (only lobe of a mirror) */
    wi = elr_v(-wo.x, -wo.y, wo.z);
    *wiW = elr_bsdf_to_world(b, wi);
    *specular = 1;
    *pdf = 1.f / (float)b->ncomp;
    if (wi.z == 0.f) { *pdf = 0.f; return elr_v(0, 0, 0); }
    return elr_mul(b->kr, 1.f / fabsf(wi.z));
  }
  if (which == 0) {
    wi = elr_bsdf_fixed_cosine_sample(wo.z, u0, u1);
  } else {
    elr_v3 wh = elr__tr_sample_wh(b->alpha, wo, u0, u1);
    float d = elr_dot(wo, wh);
    if (d < 0.f) return elr_v(0, 0, 0);
    wi = elr_sub(elr_mul(wh, 2.f * d), wo);
    if (wo.z * wi.z <= 0.f) return elr_v(0, 0, 0);
  }
  *wiW = elr_bsdf_to_world(b, wi);
  if (!b->has_glossy) { /* (elr_bsdf_pdf and elr_bsdf_f, inlined) */
    *pdf = elr_bsdf_lambert_pdf(b, woW, *wiW);
    return elr_bsdf_lambert_f(b, woW, *wiW);
  }
  *pdf = elr_bsdf_pdf(b, woW, *wiW);
  if (b->has_specular) *pdf *= 1.f; /* a specular lobe never matches a non-specular direction */
  return elr_bsdf_f(b, woW, *wiW);
}

/* >> BxDFs: pbrt-v3's BSDF as a list of BxDFs (glass, metal, uber, substrate) */

/* pbrt-v3's FrConductor (Lagarde's formulation; etaI = 1), for |cos_i|. Where eta and k are both 0 at
 * normal incidence its Rp is 0 / 0: the limit, a perfect reflector, is returned there. */
elr_v3 elr_fr_conductor(float cos_i, elr_v3 eta, elr_v3 k) {
  float c[3], e[3], kk[3], r[3];
  int i;
  cos_i = fminf(fabsf(cos_i), 1.f);
  e[0] = eta.x; e[1] = eta.y; e[2] = eta.z; kk[0] = k.x; kk[1] = k.y; kk[2] = k.z;
  for (i = 0; i < 3; i++) {
    float cos2 = cos_i * cos_i, sin2 = 1.f - cos2, eta2 = e[i] * e[i], etak2 = kk[i] * kk[i];
    float t0 = eta2 - etak2 - sin2, a2plusb2 = sqrtf(t0 * t0 + 4.f * eta2 * etak2), t1 = a2plusb2 + cos2;
    float a = sqrtf(0.5f * (a2plusb2 + t0)), t2 = 2.f * cos_i * a, rs = (t1 - t2) / (t1 + t2);
    float t3 = cos2 * a2plusb2 + sin2 * sin2, t4 = t2 * sin2, rp = t3 + t4 > 0.f ? rs * (t3 - t4) / (t3 + t4) : rs;
    c[i] = 0.5f * (rp + rs);
    r[i] = isfinite(c[i]) ? c[i] : 1.f;
  }
  return elr_v(r[0], r[1], r[2]);
}

/* the Fresnel term of a reflection lobe at cos_i (pbrt-v3's Fresnel::Evaluate) */
static elr_v3 elr__fresnel(const elr_bxdf *x, float cos_i) {
  if (x->fresnel == ELR_FRESNEL_DIELECTRIC) { float F = elr_fr_dielectric(cos_i, x->eta_a, x->eta_b); return elr_v(F, F, F); }
  if (x->fresnel == ELR_FRESNEL_CONDUCTOR) return elr_fr_conductor(cos_i, x->eta, x->k);
  return elr_v(1, 1, 1);
}

/* anisotropic Trowbridge-Reitz (pbrt-v3 TrowbridgeReitzDistribution: D, Lambda, G1, G, Pdf with
 * sampleVisibleArea, Sample_wh) */
static float elr__cos2phi(elr_v3 w) {
  float s2 = fmaxf(0.f, 1.f - w.z * w.z), st = sqrtf(s2), c;
  if (st == 0.f) return 1.f;
  c = w.x / st; c = c < -1.f ? -1.f : (c > 1.f ? 1.f : c);
  return c * c;
}
static float elr__sin2phi(elr_v3 w) {
  float s2 = fmaxf(0.f, 1.f - w.z * w.z), st = sqrtf(s2), c;
  if (st == 0.f) return 0.f;
  c = w.y / st; c = c < -1.f ? -1.f : (c > 1.f ? 1.f : c);
  return c * c;
}
static float elr__tr2_d(float ax, float ay, elr_v3 wh) {
  float c2 = wh.z * wh.z, tan2 = fmaxf(0.f, 1.f - c2) / c2, e;
  if (c2 <= 0.f || !isfinite(tan2)) return 0.f;
  e = (elr__cos2phi(wh) / (ax * ax) + elr__sin2phi(wh) / (ay * ay)) * tan2;
  return 1.f / (ELR_PI * ax * ay * c2 * c2 * (1.f + e) * (1.f + e));
}
static float elr__tr2_lambda(float ax, float ay, elr_v3 w) {
  float c2 = w.z * w.z, tan2 = fmaxf(0.f, 1.f - c2) / c2, alpha2;
  if (c2 <= 0.f || !isfinite(tan2)) return 0.f;
  alpha2 = elr__cos2phi(w) * ax * ax + elr__sin2phi(w) * ay * ay;
  return (-1.f + sqrtf(1.f + alpha2 * tan2)) * 0.5f;
}
static float elr__tr2_g1(float ax, float ay, elr_v3 w) { return 1.f / (1.f + elr__tr2_lambda(ax, ay, w)); }
static float elr__tr2_g(float ax, float ay, elr_v3 wo, elr_v3 wi) {
  return 1.f / (1.f + elr__tr2_lambda(ax, ay, wo) + elr__tr2_lambda(ax, ay, wi));
}
static float elr__tr2_pdf(float ax, float ay, elr_v3 wo, elr_v3 wh) {
  if (wo.z == 0.f) return 0.f;
  return elr__tr2_d(ax, ay, wh) * elr__tr2_g1(ax, ay, wo) * fabsf(elr_dot(wo, wh)) / fabsf(wo.z);
}
static elr_v3 elr__tr2_sample(float ax, float ay, elr_v3 wo, float u0, float u1) {
  int flip = wo.z < 0.f;
  elr_v3 v = flip ? elr_mul(wo, -1.f) : wo, vh, t1, t2, nh, ne;
  float lensq, r, phi, p1, p2, s;
  vh = elr_norm(elr_v(ax * v.x, ay * v.y, v.z));
  lensq = vh.x * vh.x + vh.y * vh.y;
  t1 = lensq > 0.f ? elr_mul(elr_v(-vh.y, vh.x, 0.f), 1.f / sqrtf(lensq)) : elr_v(1.f, 0.f, 0.f);
  t2 = elr_cross(vh, t1);
  r = sqrtf(u0); phi = 2.f * ELR_PI * u1;
  p1 = r * cosf(phi); p2 = r * sinf(phi);
  s = 0.5f * (1.f + vh.z);
  p2 = (1.f - s) * sqrtf(fmaxf(0.f, 1.f - p1 * p1)) + s * p2;
  nh = elr_add(elr_add(elr_mul(t1, p1), elr_mul(t2, p2)), elr_mul(vh, sqrtf(fmaxf(0.f, 1.f - p1 * p1 - p2 * p2))));
  ne = elr_norm(elr_v(ax * nh.x, ay * nh.y, fmaxf(1e-6f, nh.z)));
  return flip ? elr_mul(ne, -1.f) : ne;
}

/* pbrt-v3's Refract: wi around n (on wi's side) with eta = etaI / etaT; 0 at total internal reflection */
static int elr__refract(elr_v3 wi, elr_v3 n, float eta, elr_v3 *wt) {
  float cos_i = elr_dot(n, wi), sin2_i = fmaxf(0.f, 1.f - cos_i * cos_i), sin2_t = eta * eta * sin2_i, cos_t;
  if (sin2_t >= 1.f) return 0;
  cos_t = sqrtf(1.f - sin2_t);
  *wt = elr_add(elr_mul(wi, -eta), elr_mul(n, eta * cos_i - cos_t));
  return 1;
}

/* one BxDF's f, Pdf and Sample_f in the shading frame (wo, wi local) */
static elr_v3 elr__bxdf_f(const elr_bxdf *x, elr_v3 wo, elr_v3 wi) {
  switch (x->type) {
  case ELR_BXDF_LAMBERTIAN: return elr_mul(x->R, ELR_INV_PI);
  case ELR_BXDF_OREN_NAYAR: { /* OrenNayar::f: R / pi (A + B max(0, cos(phi_i - phi_o)) sin(alpha) tan(beta)) */
    float si = sqrtf(fmaxf(0.f, 1.f - wi.z * wi.z)), so = sqrtf(fmaxf(0.f, 1.f - wo.z * wo.z)), maxcos = 0.f, sa, tb;
    if (si > 1e-4f && so > 1e-4f) {
      float ci = fminf(fmaxf(wi.x / si, -1.f), 1.f), sni = fminf(fmaxf(wi.y / si, -1.f), 1.f);
      float co = fminf(fmaxf(wo.x / so, -1.f), 1.f), sno = fminf(fmaxf(wo.y / so, -1.f), 1.f);
      maxcos = fmaxf(0.f, ci * co + sni * sno);
    }
    if (fabsf(wi.z) > fabsf(wo.z)) { sa = so; tb = si / fabsf(wi.z); }
    else { sa = si; tb = wo.z != 0.f ? so / fabsf(wo.z) : 0.f; } /* (both grazing: pbrt-v3 divides by 0) */
    return elr_mul(x->R, ELR_INV_PI * (x->ax + x->ay * maxcos * sa * tb));
  }
  case ELR_BXDF_MICROFACET_REFLECTION: { /* MicrofacetReflection::f */
    float co = fabsf(wo.z), ci = fabsf(wi.z);
    elr_v3 wh = elr_add(wi, wo), F;
    if (ci == 0.f || co == 0.f) return elr_v(0, 0, 0);
    if (wh.x == 0.f && wh.y == 0.f && wh.z == 0.f) return elr_v(0, 0, 0);
    wh = elr_norm(wh);
    /* <<For the Fresnel call, make sure that wh is in the same hemisphere as the surface normal>> */
    F = elr__fresnel(x, elr_dot(wi, wh.z < 0.f ? elr_mul(wh, -1.f) : wh));
    return elr_mul(elr_vmul(x->R, F), elr__tr2_d(x->ax, x->ay, wh) * elr__tr2_g(x->ax, x->ay, wo, wi) / (4.f * ci * co));
  }
  case ELR_BXDF_MICROFACET_TRANSMISSION: { /* MicrofacetTransmission::f (radiance transport) */
    float eta, F, sq, factor, v;
    elr_v3 wh;
    if (wo.z * wi.z > 0.f || wo.z == 0.f || wi.z == 0.f) return elr_v(0, 0, 0); /* transmission only */
    eta = wo.z > 0.f ? x->eta_b / x->eta_a : x->eta_a / x->eta_b;
    wh = elr_norm(elr_add(wo, elr_mul(wi, eta)));
    if (wh.z < 0.f) wh = elr_mul(wh, -1.f);
    if (elr_dot(wo, wh) * elr_dot(wi, wh) > 0.f) return elr_v(0, 0, 0);
    /* pbrt-v4's <<Discard backfacing microfacets>>: pbrt-v3 goes on with such a wh, and its Fresnel term
     * is then total reflection for one of (wo, wi) and (wi, wo) but not the other (f not reciprocal);
     * visible-normal sampling never makes these pairs */
    if (elr_dot(wh, wo) * wo.z < 0.f || elr_dot(wh, wi) * wi.z < 0.f) return elr_v(0, 0, 0);
    F = elr_fr_dielectric(elr_dot(wo, wh), x->eta_a, x->eta_b);
    sq = elr_dot(wo, wh) + eta * elr_dot(wi, wh);
    factor = 1.f / eta;
    v = fabsf(elr__tr2_d(x->ax, x->ay, wh) * elr__tr2_g(x->ax, x->ay, wo, wi) * eta * eta * fabsf(elr_dot(wi, wh)) *
              fabsf(elr_dot(wo, wh)) * factor * factor / (wi.z * wo.z * sq * sq));
    return elr_mul(x->T, (1.f - F) * v);
  }
  case ELR_BXDF_FRESNEL_BLEND: { /* FresnelBlend::f (Ashikhmin-Shirley) */
    float ci = fabsf(wi.z), co = fabsf(wo.z), a = 1.f - 0.5f * ci, b = 1.f - 0.5f * co, cwh, p5;
    elr_v3 diffuse, wh = elr_add(wi, wo), one_minus_rs = elr_sub(elr_v(1, 1, 1), x->T), schlick;
    diffuse = elr_mul(elr_vmul(x->R, one_minus_rs), (28.f / (23.f * ELR_PI)) * (1.f - a * a * a * a * a) * (1.f - b * b * b * b * b));
    if (wh.x == 0.f && wh.y == 0.f && wh.z == 0.f) return elr_v(0, 0, 0);
    wh = elr_norm(wh);
    cwh = elr_dot(wi, wh);
    p5 = (1.f - cwh) * (1.f - cwh) * (1.f - cwh) * (1.f - cwh) * (1.f - cwh);
    schlick = elr_add(x->T, elr_mul(one_minus_rs, p5)); /* SchlickFresnel(dot(wi, wh)) */
    return elr_add(diffuse, elr_mul(schlick, elr__tr2_d(x->ax, x->ay, wh) / (4.f * fabsf(cwh) * fmaxf(ci, co))));
  }
  default: return elr_v(0, 0, 0); /* specular lobes: a delta, never hit by a chosen direction */
  }
}
static float elr__bxdf_pdf(const elr_bxdf *x, elr_v3 wo, elr_v3 wi) {
  switch (x->type) {
  case ELR_BXDF_LAMBERTIAN: case ELR_BXDF_OREN_NAYAR: /* BxDF::Pdf: the cosine */
    return wo.z * wi.z > 0.f ? fabsf(wi.z) * ELR_INV_PI : 0.f;
  case ELR_BXDF_MICROFACET_REFLECTION: {
    elr_v3 wh;
    if (!(wo.z * wi.z > 0.f)) return 0.f;
    wh = elr_norm(elr_add(wo, wi));
    return elr__tr2_pdf(x->ax, x->ay, wo, wh) / (4.f * elr_dot(wo, wh));
  }
  case ELR_BXDF_MICROFACET_TRANSMISSION: {
    float eta, sq;
    elr_v3 wh;
    if (wo.z * wi.z > 0.f) return 0.f;
    eta = wo.z > 0.f ? x->eta_b / x->eta_a : x->eta_a / x->eta_b;
    wh = elr_norm(elr_add(wo, elr_mul(wi, eta)));
    if (elr_dot(wo, wh) * elr_dot(wi, wh) > 0.f) return 0.f;
    if (wh.z < 0.f) wh = elr_mul(wh, -1.f);
    if (elr_dot(wh, wo) * wo.z < 0.f || elr_dot(wh, wi) * wi.z < 0.f) return 0.f; /* (as in f) */
    /* <<Compute change of variables dwh_dwi for microfacet transmission>> */
    sq = elr_dot(wo, wh) + eta * elr_dot(wi, wh);
    return elr__tr2_pdf(x->ax, x->ay, wo, wh) * fabsf(eta * eta * elr_dot(wi, wh) / (sq * sq));
  }
  case ELR_BXDF_FRESNEL_BLEND: {
    elr_v3 wh;
    if (!(wo.z * wi.z > 0.f)) return 0.f;
    wh = elr_norm(elr_add(wo, wi));
    return 0.5f * (fabsf(wi.z) * ELR_INV_PI + elr__tr2_pdf(x->ax, x->ay, wo, wh) / (4.f * elr_dot(wo, wh)));
  }
  default: return 0.f;
  }
}
/* <<Cosine-sample the hemisphere, flipping the direction if necessary>> (concentric disk) */
static elr_v3 elr__cosine_sample(elr_v3 wo, float u0, float u1) {
  float ox = 2.f * u0 - 1.f, oy = 2.f * u1 - 1.f, r, th;
  elr_v3 wi;
  if (ox == 0.f && oy == 0.f) { r = 0.f; th = 0.f; }
  else if (fabsf(ox) > fabsf(oy)) { r = ox; th = (ELR_PI / 4.f) * (oy / ox); }
  else { r = oy; th = ELR_PI / 2.f - (ELR_PI / 4.f) * (ox / oy); }
  wi = elr_v(r * cosf(th), r * sinf(th), sqrtf(fmaxf(0.f, 1.f - r * r)));
  if (wo.z < 0.f) wi.z = -wi.z;
  return wi;
}
/* BxDF::Sample_f of each kind: the direction, its pdf (0: none), f; *flags the lobe's (FresnelSpecular:
 * the branch taken) */
static elr_v3 elr__bxdf_sample(const elr_bxdf *x, elr_v3 wo, float u0, float u1, elr_v3 *wi, float *pdf, int *flags) {
  elr_v3 z = elr_v(0, 0, 0);
  *pdf = 0.f; *flags = x->flags;
  switch (x->type) {
  case ELR_BXDF_LAMBERTIAN: case ELR_BXDF_OREN_NAYAR: /* (OrenNayar: BxDF::Sample_f, the cosine) */
    *wi = elr__cosine_sample(wo, u0, u1);
    *pdf = elr__bxdf_pdf(x, wo, *wi);
    return elr__bxdf_f(x, wo, *wi);
  case ELR_BXDF_SPECULAR_REFLECTION: /* SpecularReflection::Sample_f */
    *wi = elr_v(-wo.x, -wo.y, wo.z);
    if (wi->z == 0.f) return z;
    *pdf = 1.f;
    return elr_mul(elr_vmul(elr__fresnel(x, wi->z), x->R), 1.f / fabsf(wi->z));
  case ELR_BXDF_SPECULAR_TRANSMISSION: { /* SpecularTransmission::Sample_f */
    int entering = wo.z > 0.f;
    float ei = entering ? x->eta_a : x->eta_b, et = entering ? x->eta_b : x->eta_a;
    elr_v3 ft;
    if (!elr__refract(wo, elr_v(0.f, 0.f, wo.z < 0.f ? -1.f : 1.f), ei / et, wi) || wi->z == 0.f) return z;
    *pdf = 1.f;
    ft = elr_mul(x->T, 1.f - elr_fr_dielectric(wi->z, x->eta_a, x->eta_b));
    /* <<Account for non-symmetry with transmission to different medium>> */
    ft = elr_mul(ft, (ei * ei) / (et * et));
    return elr_mul(ft, 1.f / fabsf(wi->z));
  }
  case ELR_BXDF_FRESNEL_SPECULAR: { /* FresnelSpecular::Sample_f: reflect with probability F */
    float F = elr_fr_dielectric(wo.z, x->eta_a, x->eta_b);
    if (u0 < F) {
      *wi = elr_v(-wo.x, -wo.y, wo.z);
      if (wi->z == 0.f) return z;
      *flags = ELR_BSDF_SPECULAR | ELR_BSDF_REFLECTION;
      *pdf = F;
      return elr_mul(x->R, F / fabsf(wi->z));
    } else {
      int entering = wo.z > 0.f;
      float ei = entering ? x->eta_a : x->eta_b, et = entering ? x->eta_b : x->eta_a;
      if (!elr__refract(wo, elr_v(0.f, 0.f, wo.z < 0.f ? -1.f : 1.f), ei / et, wi) || wi->z == 0.f) return z;
      *flags = ELR_BSDF_SPECULAR | ELR_BSDF_TRANSMISSION;
      *pdf = 1.f - F;
      return elr_mul(x->T, (1.f - F) * (ei * ei) / (et * et) / fabsf(wi->z));
    }
  }
  case ELR_BXDF_MICROFACET_REFLECTION: {
    elr_v3 wh;
    if (wo.z == 0.f) return z;
    wh = elr__tr2_sample(x->ax, x->ay, wo, u0, u1);
    if (elr_dot(wo, wh) < 0.f) return z;
    *wi = elr_sub(elr_mul(wh, 2.f * elr_dot(wo, wh)), wo);
    if (!(wo.z * wi->z > 0.f)) return z;
    *pdf = elr__tr2_pdf(x->ax, x->ay, wo, wh) / (4.f * elr_dot(wo, wh));
    return elr__bxdf_f(x, wo, *wi);
  }
  case ELR_BXDF_MICROFACET_TRANSMISSION: {
    elr_v3 wh;
    float eta;
    if (wo.z == 0.f) return z;
    wh = elr__tr2_sample(x->ax, x->ay, wo, u0, u1);
    if (elr_dot(wo, wh) < 0.f) return z;
    eta = wo.z > 0.f ? x->eta_a / x->eta_b : x->eta_b / x->eta_a;
    if (!elr__refract(wo, wh, eta, wi)) return z;
    *pdf = elr__bxdf_pdf(x, wo, *wi);
    return elr__bxdf_f(x, wo, *wi);
  }
  case ELR_BXDF_FRESNEL_BLEND: {
    if (u0 < 0.5f) {
      u0 = fminf(2.f * u0, ELR_ONE_MINUS_EPS);
      *wi = elr__cosine_sample(wo, u0, u1);
    } else {
      elr_v3 wh;
      u0 = fminf(2.f * (u0 - 0.5f), ELR_ONE_MINUS_EPS);
      wh = elr__tr2_sample(x->ax, x->ay, wo, u0, u1);
      *wi = elr_sub(elr_mul(wh, 2.f * elr_dot(wo, wh)), wo);
      if (!(wo.z * wi->z > 0.f)) return z;
    }
    *pdf = elr__bxdf_pdf(x, wo, *wi);
    return elr__bxdf_f(x, wo, *wi);
  }
  default: return z;
  }
}

void elr_bsdf_begin(elr_bsdf *b, elr_v3 ns, elr_v3 ng, float eta) {
  b->ns = ns; b->ng = ng;
  elr_onb(ns, &b->ss, &b->ts);
  b->has_diffuse = b->has_glossy = b->has_specular = b->ncomp = 0;
  b->spec_r = b->spec_t = b->nlobes = 0;
  b->kd = b->ks = b->kr = elr_v(0, 0, 0);
  b->alpha = 1.f;
  b->eta = eta;
  b->env_map = b->env_light_only = b->env_mirror = b->env_sun_test = b->env_two = 0;
}
float elr_bsdf_lobe_alpha(const elr_bsdf *b) {
  float a = INFINITY;
  int i;
  if (b->nlobes == 0) return b->has_glossy ? b->alpha : INFINITY;
  for (i = 0; i < b->nlobes; i++) {
    const elr_bxdf *x = &b->lobe[i];
    if ((x->type == ELR_BXDF_MICROFACET_REFLECTION || x->type == ELR_BXDF_FRESNEL_BLEND) && sqrtf(x->ax * x->ay) < a) a = sqrtf(x->ax * x->ay);
  }
  return a;
}
elr_bxdf *elr_bsdf_add(elr_bsdf *b, int type) {
  elr_bxdf *x;
  static const int flags[] = {ELR_BSDF_REFLECTION | ELR_BSDF_DIFFUSE, ELR_BSDF_REFLECTION | ELR_BSDF_SPECULAR,
                              ELR_BSDF_TRANSMISSION | ELR_BSDF_SPECULAR, ELR_BSDF_REFLECTION | ELR_BSDF_TRANSMISSION | ELR_BSDF_SPECULAR,
                              ELR_BSDF_REFLECTION | ELR_BSDF_GLOSSY, ELR_BSDF_TRANSMISSION | ELR_BSDF_GLOSSY,
                              ELR_BSDF_REFLECTION | ELR_BSDF_GLOSSY, ELR_BSDF_REFLECTION | ELR_BSDF_DIFFUSE};
  if (b->nlobes >= ELR_MAX_BXDFS) return NULL;
  x = &b->lobe[b->nlobes++];
  memset(x, 0, sizeof *x);
  x->type = type; x->flags = flags[type];
  x->R = x->T = elr_v(1, 1, 1); x->ax = x->ay = 1.f; x->eta_a = x->eta_b = 1.f;
  b->ncomp++;
  if (x->flags & ELR_BSDF_DIFFUSE) b->has_diffuse = 1;
  if (x->flags & ELR_BSDF_GLOSSY) b->has_glossy = 1;
  if (x->flags & ELR_BSDF_SPECULAR) {
    b->has_specular = 1;
    if (x->flags == (ELR_BSDF_REFLECTION | ELR_BSDF_SPECULAR)) b->spec_r = 1;
    if (x->flags == (ELR_BSDF_TRANSMISSION | ELR_BSDF_SPECULAR)) b->spec_t = 1;
  }
  return x;
}

/* pbrt-v3's BSDF::f, Pdf and Sample_f over the lobes whose flags lie in type */
static int elr__matches(const elr_bxdf *x, int type) { return (x->flags & type) == x->flags; }
static ELR_NOINLINE elr_v3 elr__list_f(const elr_bsdf *b, elr_v3 woW, elr_v3 wiW, int type) {
  elr_v3 wo = elr__to_local(b, woW), wi = elr__to_local(b, wiW), f = elr_v(0, 0, 0);
  int reflect = elr_dot(wiW, b->ng) * elr_dot(woW, b->ng) > 0.f, i;
  if (wo.z == 0.f) return f;
  for (i = 0; i < b->nlobes; i++) {
    const elr_bxdf *x = &b->lobe[i];
    if (elr__matches(x, type) && ((reflect && (x->flags & ELR_BSDF_REFLECTION)) || (!reflect && (x->flags & ELR_BSDF_TRANSMISSION))))
      f = elr_add(f, elr__bxdf_f(x, wo, wi));
  }
  return f;
}
static ELR_NOINLINE float elr__list_pdf(const elr_bsdf *b, elr_v3 woW, elr_v3 wiW, int type) {
  elr_v3 wo = elr__to_local(b, woW), wi = elr__to_local(b, wiW);
  float pdf = 0.f;
  int i, n = 0;
  if (wo.z == 0.f) return 0.f;
  for (i = 0; i < b->nlobes; i++)
    if (elr__matches(&b->lobe[i], type)) { n++; pdf += elr__bxdf_pdf(&b->lobe[i], wo, wi); }
  return n > 0 ? pdf / (float)n : 0.f;
}
elr_v3 elr_bsdf_sample_type(const elr_bsdf *b, elr_v3 woW, float u0, float u1, int type, elr_v3 *wiW, float *pdf, int *flags) {
  elr_v3 wo, wi, f;
  int i, n = 0, comp, count;
  const elr_bxdf *x = NULL;
  *pdf = 0.f; *flags = 0;
  if (!b->nlobes) { /* the fixed lobes (mirror's specular reflection is the only specular one there) */
    int spec;
    if (type == ELR_BSDF_ALL || (type == (ELR_BSDF_REFLECTION | ELR_BSDF_SPECULAR) && b->has_specular && b->ncomp == 1)) {
      f = elr_bsdf_sample(b, woW, u0, u1, wiW, pdf, &spec);
      *flags = spec ? ELR_BSDF_REFLECTION | ELR_BSDF_SPECULAR : ELR_BSDF_REFLECTION;
      return f;
    }
    return elr_v(0, 0, 0);
  }
  /* <<Choose which BxDF to sample>> */
  for (i = 0; i < b->nlobes; i++) n += elr__matches(&b->lobe[i], type);
  if (n == 0) return elr_v(0, 0, 0);
  comp = (int)(u0 * (float)n);
  if (comp >= n) comp = n - 1;
  for (i = 0, count = comp; i < b->nlobes; i++)
    if (elr__matches(&b->lobe[i], type) && count-- == 0) { x = &b->lobe[i]; break; }
  /* <<Remap BxDF sample u to [0,1)^2>> */
  u0 = fminf(u0 * (float)n - (float)comp, ELR_ONE_MINUS_EPS);
  /* <<Sample chosen BxDF>> */
  wo = elr__to_local(b, woW);
  if (wo.z == 0.f) return elr_v(0, 0, 0);
  f = elr__bxdf_sample(x, wo, u0, u1, &wi, pdf, flags);
  if (*pdf == 0.f) { *flags = 0; return elr_v(0, 0, 0); }
  *wiW = elr_bsdf_to_world(b, wi);
  /* <<Compute overall PDF with all matching BxDFs>> */
  if (!(x->flags & ELR_BSDF_SPECULAR) && n > 1)
    for (i = 0; i < b->nlobes; i++)
      if (&b->lobe[i] != x && elr__matches(&b->lobe[i], type)) *pdf += elr__bxdf_pdf(&b->lobe[i], wo, wi);
  if (n > 1) *pdf /= (float)n;
  /* <<Compute value of BSDF for sampled direction>> */
  if (!(x->flags & ELR_BSDF_SPECULAR)) f = elr__list_f(b, woW, *wiW, type);
  return f;
}
