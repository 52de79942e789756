/* reflection.c: the BSDF and its lobes (pbrt-v3 core/reflection.cpp), the Trowbridge-Reitz microfacet
 * distribution (core/microfacet.cpp) and the dielectric Fresnel term.
 *
 * Lobes: LambertianReflection; MicrofacetReflection (Torrance-Sparrow with Trowbridge-Reitz, sampled by
 * its visible normals); SpecularReflection with FresnelNoOp. materials.c chooses them per material.
 * Evaluation follows pbrt-v3's BSDF class: the shading frame around the shading normal, a lobe reflects
 * only when wi and wo lie on the same side of the geometric normal; Sample_f chooses one of the matching
 * components uniformly and returns the average pdf and the sum of the non-specular f. Transmission
 * (glass), conductors (metal) and FresnelBlend (substrate) would be further lobes here. */
#include "elr_internal.h"

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
static elr_v3 elr__tr_sample_wh(float alpha, elr_v3 wo, float u0, float u1) {
  int flip = wo.z < 0.f;
  elr_v3 v = flip ? elr_mul(wo, -1.f) : wo, vh, t1, t2, nh, ne;
  float lensq, r, phi, p1, p2, s;
  vh = elr_norm(elr_v(alpha * v.x, alpha * v.y, v.z));
  lensq = vh.x * vh.x + vh.y * vh.y;
  t1 = lensq > 0.f ? elr_mul(elr_v(-vh.y, vh.x, 0.f), 1.f / sqrtf(lensq)) : elr_v(1.f, 0.f, 0.f);
  t2 = elr_cross(vh, t1);
  r = sqrtf(u0); phi = 2.f * ELR_PI * u1;
  p1 = r * cosf(phi); p2 = r * sinf(phi);
  s = 0.5f * (1.f + vh.z);
  p2 = (1.f - s) * sqrtf(fmaxf(0.f, 1.f - p1 * p1)) + s * p2;
  nh = elr_add(elr_add(elr_mul(t1, p1), elr_mul(t2, p2)), elr_mul(vh, sqrtf(fmaxf(0.f, 1.f - p1 * p1 - p2 * p2))));
  ne = elr_norm(elr_v(alpha * nh.x, alpha * nh.y, fmaxf(1e-6f, nh.z)));
  return flip ? elr_mul(ne, -1.f) : ne;
}
/* pbrt-v3's FrDielectric */
static float elr__fr_dielectric(float cosi, float etai, float etat) {
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
static elr_v3 elr__to_world(const elr_bsdf *b, elr_v3 v) {
  return elr_add(elr_add(elr_mul(b->ss, v.x), elr_mul(b->ts, v.y)), elr_mul(b->ns, v.z));
}
static elr_v3 elr__glossy_f(const elr_bsdf *b, elr_v3 wo, elr_v3 wi) {
  float co = fabsf(wo.z), ci = fabsf(wi.z), F;
  elr_v3 wh = elr_add(wi, wo);
  if (ci == 0.f || co == 0.f) return elr_v(0, 0, 0);
  if (wh.x == 0.f && wh.y == 0.f && wh.z == 0.f) return elr_v(0, 0, 0);
  wh = elr_norm(wh);
  F = elr__fr_dielectric(elr_dot(wi, wh), 1.5f, 1.f); /* pbrt-v3 plastic: FresnelDielectric(1.5, 1) */
  return elr_mul(b->ks, elr__tr_d(b->alpha, wh) * elr__tr_g(b->alpha, wo, wi) * F / (4.f * ci * co));
}
static float elr__glossy_pdf(const elr_bsdf *b, elr_v3 wo, elr_v3 wi) {
  elr_v3 wh;
  if (wo.z * wi.z <= 0.f) return 0.f;
  wh = elr_norm(elr_add(wo, wi));
  return elr__tr_pdf_wh(b->alpha, wo, wh) / (4.f * fabsf(elr_dot(wo, wh)));
}
elr_v3 elr_bsdf_f(const elr_bsdf *b, elr_v3 woW, elr_v3 wiW) {
  elr_v3 wo, wi, f = elr_v(0, 0, 0);
  int reflect = elr_dot(wiW, b->ng) * elr_dot(woW, b->ng) > 0.f;
  if (!b->has_glossy) /* Lambertian alone needs no local frame */
    return reflect && b->has_diffuse && elr_dot(woW, b->ns) != 0.f ? elr_mul(b->kd, ELR_INV_PI) : f;
  wo = elr__to_local(b, woW); wi = elr__to_local(b, wiW);
  if (wo.z == 0.f || !reflect) return f;
  if (b->has_diffuse) f = elr_mul(b->kd, ELR_INV_PI);
  if (b->has_glossy) f = elr_add(f, elr__glossy_f(b, wo, wi));
  return f;
}
float elr_bsdf_pdf(const elr_bsdf *b, elr_v3 woW, elr_v3 wiW) {
  elr_v3 wo, wi;
  float pdf = 0.f;
  if (!b->has_glossy) {
    float co = elr_dot(woW, b->ns), ci = elr_dot(wiW, b->ns);
    return b->has_diffuse && co * ci > 0.f ? fabsf(ci) * ELR_INV_PI / (float)b->ncomp : 0.f;
  }
  wo = elr__to_local(b, woW); wi = elr__to_local(b, wiW);
  if (wo.z == 0.f || b->ncomp == 0) return 0.f;
  if (b->has_diffuse && wo.z * wi.z > 0.f) pdf += fabsf(wi.z) * ELR_INV_PI;
  if (b->has_glossy) pdf += elr__glossy_pdf(b, wo, wi);
  return pdf / (float)b->ncomp;
}
elr_v3 elr_bsdf_sample(const elr_bsdf *b, elr_v3 woW, float u0, float u1, elr_v3 *wiW, float *pdf, int *specular) {
  elr_v3 wo = elr__to_local(b, woW), wi;
  int comp, k = 0, which = -1;
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
    *wiW = elr__to_world(b, wi);
    *specular = 1;
    *pdf = 1.f / (float)b->ncomp;
    if (wi.z == 0.f) { *pdf = 0.f; return elr_v(0, 0, 0); }
    return elr_mul(b->kr, 1.f / fabsf(wi.z));
  }
  if (which == 0) {
    /* <<Cosine-sample the hemisphere, flipping the direction if necessary>> (concentric disk) */
    float ox = 2.f * u0 - 1.f, oy = 2.f * u1 - 1.f, r, th;
    if (ox == 0.f && oy == 0.f) { r = 0.f; th = 0.f; }
    else if (fabsf(ox) > fabsf(oy)) { r = ox; th = (ELR_PI / 4.f) * (oy / ox); }
    else { r = oy; th = ELR_PI / 2.f - (ELR_PI / 4.f) * (ox / oy); }
    wi = elr_v(r * cosf(th), r * sinf(th), sqrtf(fmaxf(0.f, 1.f - r * r * (cosf(th) * cosf(th) + sinf(th) * sinf(th)))));
    if (wo.z < 0.f) wi.z = -wi.z;
  } else {
    elr_v3 wh = elr__tr_sample_wh(b->alpha, wo, u0, u1);
    float d = elr_dot(wo, wh);
    if (d < 0.f) return elr_v(0, 0, 0);
    wi = elr_sub(elr_mul(wh, 2.f * d), wo);
    if (wo.z * wi.z <= 0.f) return elr_v(0, 0, 0);
  }
  *wiW = elr__to_world(b, wi);
  *pdf = elr_bsdf_pdf(b, woW, *wiW);
  if (b->has_specular) *pdf *= 1.f; /* a specular lobe never matches a non-specular direction */
  return elr_bsdf_f(b, woW, *wiW);
}
