/* materials.c: pbrt-v3's materials/ directory: each material's ComputeScatteringFunctions, which
 * evaluates its textures at the shading point and makes the BSDF's lobes (reflection.c).
 *   matte.cpp    LambertianReflection(Kd), or OrenNayar(Kd, sigma) where sigma (degrees) is not 0
 *   mirror.cpp   SpecularReflection(Kr, FresnelNoOp)
 *   plastic.cpp  LambertianReflection(Kd) + MicrofacetReflection(Ks, Trowbridge-Reitz(roughness),
 *                FresnelDielectric(1.5, 1))
 *   glass.cpp    smooth: FresnelSpecular(Kr, Kt, 1, eta) in the path tracer (pbrt-v3's
 *                allowMultipleLobes), SpecularReflection(Kr, FresnelDielectric(1, eta)) +
 *                SpecularTransmission(Kt, 1, eta) in directlighting; rough (uroughness or vroughness
 *                not 0): MicrofacetReflection + MicrofacetTransmission
 *   metal.cpp    MicrofacetReflection(1, Trowbridge-Reitz, FresnelConductor(1, eta, k)); pbrt-v3's
 *                default eta and k are its copper spectra as RGB (below)
 *   uber.cpp     SpecularTransmission(1 - opacity, 1, 1) + LambertianReflection(opacity Kd) +
 *                MicrofacetReflection(opacity Ks, FresnelDielectric(1, eta)) +
 *                SpecularReflection(opacity Kr, FresnelDielectric(1, eta)) + SpecularTransmission(opacity Kt, 1, eta)
 *   substrate.cpp FresnelBlend(Kd, Ks, Trowbridge-Reitz(uroughness, vroughness))
 * Spectra are RGB (pbrt-v3's default RGBSpectrum); "Clamp" is pbrt-v3's Spectrum::Clamp (negatives to 0). */
#include "elr_internal.h"
#include <string.h>

/* max(v, 0) per component, NaN to 0: fmaxf(x, 0.f)'s values (-0 to +0 as well), without its libm call */
static elr_v3 elr__clamp0(elr_v3 v) { return elr_v(v.x > 0.f ? v.x : 0.f, v.y > 0.f ? v.y : 0.f, v.z > 0.f ? v.z : 0.f); }
static float elr__ftex(const elr_scene *s, int t, const elr_tex_ctx *c) { return elr_tex_eval(s, t, c).x; }
/* an index of refraction from a texture, kept where the Fresnel and refraction maths stay finite */
static float elr__eta(float e) { return e > 1e-3f ? (e < 1e3f ? e : 1e3f) : 1e-3f; }
/* TrowbridgeReitzDistribution's alphas (its constructor's floor of 0.001), remapped from roughness or not */
static float elr__alpha(float r, int remap) {
  float a = remap ? elr_roughness_to_alpha(r) : r;
  return a > 0.001f ? a : 0.001f;
}

/* glass, metal, uber, substrate: pbrt-v3's BxDF lists, in the frame pbrt-v3 orients */
static ELR_NOINLINE void elr__bsdf_list(const elr_scene *s, const elr_material *m, const elr_hit *h, const elr_tex_ctx *c, elr_bsdf *b) {
  elr_v3 ns = h->ns, ng = h->ng; /* oriented as pbrt-v3 orients them (the shape's flip is in the hit record) */
  elr_bxdf *x;
  int multiple = s->d.integrator_path; /* pbrt-v3's allowMultipleLobes: the path tracer's */
  switch (m->kind) {
  case ELR_MAT_GLASS: { /* GlassMaterial::ComputeScatteringFunctions */
    float eta = elr__eta(elr__ftex(s, m->index, c)), ur = elr__ftex(s, m->urough, c), vr = elr__ftex(s, m->vrough, c);
    elr_v3 R = elr__clamp0(elr_tex_eval(s, m->kr, c)), T = elr__clamp0(elr_tex_eval(s, m->kt, c));
    int specular = ur == 0.f && vr == 0.f;
    elr_bsdf_begin(b, ns, ng, eta);
    if (elr_isblack(R) && elr_isblack(T)) break;
    if (specular && multiple) {
      x = elr_bsdf_add(b, ELR_BXDF_FRESNEL_SPECULAR);
      x->R = R; x->T = T; x->eta_a = 1.f; x->eta_b = eta;
    } else {
      float ax = elr__alpha(ur, m->remap), ay = elr__alpha(vr, m->remap);
      if (!elr_isblack(R)) {
        x = elr_bsdf_add(b, specular ? ELR_BXDF_SPECULAR_REFLECTION : ELR_BXDF_MICROFACET_REFLECTION);
        x->R = R; x->fresnel = ELR_FRESNEL_DIELECTRIC; x->eta_a = 1.f; x->eta_b = eta; x->ax = ax; x->ay = ay;
      }
      if (!elr_isblack(T)) {
        x = elr_bsdf_add(b, specular ? ELR_BXDF_SPECULAR_TRANSMISSION : ELR_BXDF_MICROFACET_TRANSMISSION);
        x->T = T; x->eta_a = 1.f; x->eta_b = eta; x->ax = ax; x->ay = ay;
      }
    }
    break;
  }
  case ELR_MAT_METAL: { /* MetalMaterial::ComputeScatteringFunctions */
    float ur = elr__ftex(s, m->urough >= 0 ? m->urough : m->rough, c), vr = elr__ftex(s, m->vrough >= 0 ? m->vrough : m->rough, c);
    elr_bsdf_begin(b, ns, ng, 1.f);
    x = elr_bsdf_add(b, ELR_BXDF_MICROFACET_REFLECTION);
    x->R = elr_v(1, 1, 1); x->fresnel = ELR_FRESNEL_CONDUCTOR;
    x->eta = elr_tex_eval(s, m->eta, c); x->k = elr_tex_eval(s, m->k, c);
    x->ax = elr__alpha(ur, m->remap); x->ay = elr__alpha(vr, m->remap);
    break;
  }
  case ELR_MAT_UBER: { /* UberMaterial::ComputeScatteringFunctions */
    float e = elr__eta(elr__ftex(s, m->index, c));
    elr_v3 op = elr__clamp0(elr_tex_eval(s, m->opacity, c)), t = elr__clamp0(elr_sub(elr_v(1, 1, 1), op)), kd, ks, kr, kt;
    elr_bsdf_begin(b, ns, ng, elr_isblack(t) ? e : 1.f);
    if (!elr_isblack(t)) { x = elr_bsdf_add(b, ELR_BXDF_SPECULAR_TRANSMISSION); x->T = t; x->eta_a = x->eta_b = 1.f; }
    kd = elr_vmul(op, elr__clamp0(elr_tex_eval(s, m->kd, c)));
    if (!elr_isblack(kd)) { x = elr_bsdf_add(b, ELR_BXDF_LAMBERTIAN); x->R = kd; }
    ks = elr_vmul(op, elr__clamp0(elr_tex_eval(s, m->ks, c)));
    if (!elr_isblack(ks)) {
      float ru = elr__ftex(s, m->urough >= 0 ? m->urough : m->rough, c), rv = m->vrough >= 0 ? elr__ftex(s, m->vrough, c) : ru;
      x = elr_bsdf_add(b, ELR_BXDF_MICROFACET_REFLECTION);
      x->R = ks; x->fresnel = ELR_FRESNEL_DIELECTRIC; x->eta_a = 1.f; x->eta_b = e;
      x->ax = elr__alpha(ru, m->remap); x->ay = elr__alpha(rv, m->remap);
    }
    kr = elr_vmul(op, elr__clamp0(elr_tex_eval(s, m->kr, c)));
    if (!elr_isblack(kr)) { x = elr_bsdf_add(b, ELR_BXDF_SPECULAR_REFLECTION); x->R = kr; x->fresnel = ELR_FRESNEL_DIELECTRIC; x->eta_a = 1.f; x->eta_b = e; }
    kt = elr_vmul(op, elr__clamp0(elr_tex_eval(s, m->kt, c)));
    if (!elr_isblack(kt)) { x = elr_bsdf_add(b, ELR_BXDF_SPECULAR_TRANSMISSION); x->T = kt; x->eta_a = 1.f; x->eta_b = e; }
    break;
  }
  default: { /* SubstrateMaterial::ComputeScatteringFunctions */
    elr_v3 d = elr__clamp0(elr_tex_eval(s, m->kd, c)), sp = elr__clamp0(elr_tex_eval(s, m->ks, c));
    elr_bsdf_begin(b, ns, ng, 1.f);
    if (!elr_isblack(d) || !elr_isblack(sp)) {
      x = elr_bsdf_add(b, ELR_BXDF_FRESNEL_BLEND);
      x->R = d; x->T = sp;
      x->ax = elr__alpha(elr__ftex(s, m->urough, c), m->remap); x->ay = elr__alpha(elr__ftex(s, m->vrough, c), m->remap);
    }
    break;
  }
  }
  { /* BSDF::BSDF's frame: ss = Normalize(shading.dpdu), ts = Cross(ns, ss) (the shape's dp/du, made
     * orthogonal to ns as pbrt-v3's shading geometry makes it). Only an anisotropic microfacet lobe can
     * tell one frame around ns from another, so the hit's dp/du is computed for those alone (elr_hit_uv
     * on a copy); the others keep elr_onb's frame. A dp/du along ns keeps it too. */
    int k, aniso = 0;
    for (k = 0; k < b->nlobes; k++) {
      const elr_bxdf *l = &b->lobe[k];
      if ((l->type == ELR_BXDF_MICROFACET_REFLECTION || l->type == ELR_BXDF_MICROFACET_TRANSMISSION || l->type == ELR_BXDF_FRESNEL_BLEND) && l->ax != l->ay)
        aniso = 1;
    }
    if (aniso) {
      elr_hit hu = *h;
      elr_v3 d;
      float d2;
      elr_hit_uv(s, &hu);
      d = elr_sub(hu.dpdu, elr_mul(b->ns, elr_dot(b->ns, hu.dpdu)));
      d2 = elr_dot(d, d);
      if (d2 > 1e-12f * elr_dot(hu.dpdu, hu.dpdu) && isfinite(d2)) {
        b->ss = elr_mul(d, 1.f / sqrtf(d2));
        b->ts = elr_cross(b->ns, b->ss);
      }
    }
  }
}

/* Issue 20's per-lobe choice of the environment's sampling at this BSDF (elr_bsdf_cos_normal,
 * elr_env_light_only). A PEAKED lobe (a glossy lobe of alpha below the scene's env_lobe_alpha and no
 * diffuse lobe: metal) samples the map alone under a sun map (elr_scene.env_sunny), elsewhere the
 * product of the map and the clamped cosine around wo's mirror direction (b->env_mirror), with MIS.
 * A lobe with a diffuse part (plastic, uber, substrate) keeps the product around the normal whatever
 * its glossy alpha. The product light sample alone where every glossy lobe's alpha is at least
 * env_light_alpha and a diffuse lobe carries part of the reflection, or at least twice that without
 * one (metal: its glossy lobe is all of the reflection). Measured with bench/lobes.py (time to unit
 * variance against the map alone, city-studio): the light sample alone against product MIS: plastic
 * 0.61-1.5x at alpha 0.2, 0.99-2.3x at 0.3, 2.2-4.5x at 0.46; metal 0.57-1.7x at 0.3, 0.90-2.0x at 0.5,
 * 1.45-1.9x at 0.8. Metal below env_lobe_alpha: product MIS around the normal 0.73-3.8x at 0.05,
 * 1.09-5.8x at 0.1; around the mirror direction 0.64x (city: a sun; its variance is that of the map
 * alone, 0.0059 against 0.0062, and the product sample costs more) and 3.3x (studio; the normal's
 * product 2.4x) at alpha 0.02, studio 6.1x (normal 3.9x) at 0.06, 4.5x (normal 5.5x) at 0.2: so the
 * mirror below 0.1 where no sun, the map alone under one. Plastic of alpha 0.05 (diffuse part): the
 * product around the normal 1.86x (city) and 5.95x (studio), the map alone then being what it lost
 * before (0.92x, 0.91x: the same variance at the product tables' extra time), the mirror 0.51x (studio:
 * the diffuse lobe is not around the mirror direction). Diffuse-only lobes under a sun map (elr__sun_share):
 * MIS, never the light sample alone (it leaves the sky unsampled in the shadows: 0.18-0.41x): by default
 * product MIS (ELR_ENVSD_PRODUCT since the wave loop's batched product samples); with ELR_ENVSD_SUNCOS (the
 * sun rule) by the map alone where the sun is within acos(ELR_ENV_SUN_COS) = 60 degrees of the normal
 * (elr_bsdf_cos_normal tests it on wo's side), by the product elsewhere (bench/sun_rule.py, elr_internal.h). */
static void elr__env_choice(const elr_scene *s, elr_bsdf *b) {
  float a = elr_bsdf_lobe_alpha(b);
  int diffuse = b->has_diffuse, peaked, sun_diffuse, i;
  for (i = 0; i < b->nlobes; i++) diffuse |= b->lobe[i].type == ELR_BXDF_LAMBERTIAN || b->lobe[i].type == ELR_BXDF_FRESNEL_BLEND;
  peaked = a < s->env_lobe_alpha && !diffuse;
  sun_diffuse = s->env_sunny && a == INFINITY && diffuse; /* (a sun: elr__sun_share; env_sun_diffuse says how) */
  b->env_map = (peaked && s->env_sunny) || (sun_diffuse && s->env_sun_diffuse == ELR_ENVSD_MAP);
  b->env_mirror = peaked && !s->env_sunny; /* (MIS only: the mirror's cosine is no bound of f) */
  b->env_sun_test = sun_diffuse && s->env_sun_diffuse == ELR_ENVSD_SUNCOS;
  b->env_two = sun_diffuse && (s->env_sun_diffuse == ELR_ENVSD_TWO || s->env_sun_diffuse == ELR_ENVSD_TWO_PIXEL);
  if (b->env_sun_test) { b->env_sun_axis = s->env_sun_axis; b->env_sun_cos = s->env_sun_cos; }
  b->env_light_only = !b->env_mirror && !(sun_diffuse && (s->env_sun_diffuse == ELR_ENVSD_PRODUCT || b->env_sun_test || b->env_two)) && s->env_light_alpha < INFINITY &&
                      a >= (diffuse ? 1.f : 2.f) * s->env_light_alpha; /* (INFINITY: never) */
}

/* The BSDF of the hit's material at the shading point c (its textures evaluated there). */
void elr_bsdf_init(const elr_scene *s, const elr_hit *h, const elr_tex_ctx *c, elr_bsdf *b) {
  const elr_material *m = &s->mat[h->material];
  if (m->kind > ELR_MAT_PLASTIC) {
    elr__bsdf_list(s, m, h, c, b);
    elr__env_choice(s, b);
    return;
  }
  b->nlobes = 0; b->eta = 1.f;
  b->ns = h->ns; b->ng = h->ng;
  elr_onb(b->ns, &b->ss, &b->ts);
  b->has_diffuse = b->has_glossy = b->has_specular = 0;
  b->kd = b->ks = b->kr = elr_v(0, 0, 0);
  b->alpha = 1.f;
  if (m->kind == ELR_MAT_MATTE) { /* MatteMaterial::ComputeScatteringFunctions */
    float sig = m->rough >= 0 ? elr__ftex(s, m->rough, c) : 0.f;
    b->kd = elr__clamp0(elr_tex_eval(s, m->kd, c));
    if (sig != 0.f && !elr_isblack(b->kd)) { /* OrenNayar(r, Clamp(sigma, 0, 90)): its constructor's A and B */
      float sr = (sig < 0.f ? 0.f : (sig > 90.f ? 90.f : sig)) * (ELR_PI / 180.f), s2 = sr * sr;
      elr_bxdf *x;
      elr_v3 kd = b->kd;
      elr_bsdf_begin(b, h->ns, h->ng, 1.f);
      x = elr_bsdf_add(b, ELR_BXDF_OREN_NAYAR);
      x->R = kd; x->ax = 1.f - (s2 / (2.f * (s2 + 0.33f))); x->ay = 0.45f * s2 / (s2 + 0.09f);
      return;
    }
    b->has_diffuse = !elr_isblack(b->kd);
  } else if (m->kind == ELR_MAT_MIRROR) { /* MirrorMaterial::ComputeScatteringFunctions */
    b->kr = elr__clamp0(elr_tex_eval(s, m->kr, c)); /* pbrt-v3: Kr->Evaluate(*si).Clamp() */
    b->has_specular = !elr_isblack(b->kr);
  } else { /* PlasticMaterial::ComputeScatteringFunctions */
    float r;
    b->kd = elr__clamp0(elr_tex_eval(s, m->kd, c)); /* pbrt-v3: Kd->Evaluate(*si).Clamp() */
    b->ks = elr__clamp0(elr_tex_eval(s, m->ks, c));
    r = elr_tex_eval(s, m->rough, c).x;
    b->alpha = m->remap ? elr_roughness_to_alpha(r) : r;
    if (!(b->alpha > 1e-4f)) b->alpha = 1e-4f;
    b->has_diffuse = !elr_isblack(b->kd);
    b->has_glossy = !elr_isblack(b->ks);
  }
  b->ncomp = b->has_diffuse + b->has_glossy + b->has_specular;
  b->spec_r = b->has_specular; b->spec_t = 0;
  elr__env_choice(s, b);
}

/* The BSDF of material mi where it is the same at every hit but for its frame: every texture of the
 * material constant (elr_scene.mat_textured 0) and no anisotropic lobe (whose frame follows the hit's
 * dp/du). Returns 1 and t (elr_bsdf_init at a made-up hit, ns = ng = +z), or 0. elr_bsdf_init_like then
 * makes a hit's BSDF from t: the same fields elr_bsdf_init writes, with the same values (the frame is
 * elr_onb around the hit's ns in both), for a copy and a frame instead of the material's evaluation
 * (the wave loop, render_wave.c: elr_wave_new makes one t per material). */
int elr_bsdf_constant(const elr_scene *s, int mi, elr_bsdf *t) {
  elr_hit h;
  elr_tex_ctx c;
  int k;
  if (mi < 0 || mi >= s->nmat || !s->mat_textured || s->mat_textured[mi]) return 0;
  memset(&h, 0, sizeof h); memset(&c, 0, sizeof c); memset(t, 0, sizeof *t);
  h.material = mi; h.ns = h.ng = elr_v(0.f, 0.f, 1.f); h.inst = -1;
  h.has_uv = 1; /* (an anisotropic lobe's frame asks elr_hit_uv: nothing to look up at a made-up hit; refused below) */
  elr_bsdf_init(s, &h, &c, t);
  for (k = 0; k < t->nlobes; k++) {
    const elr_bxdf *l = &t->lobe[k];
    if ((l->type == ELR_BXDF_MICROFACET_REFLECTION || l->type == ELR_BXDF_MICROFACET_TRANSMISSION || l->type == ELR_BXDF_FRESNEL_BLEND) && l->ax != l->ay)
      return 0;
  }
  return 1;
}
