/* materials.c: pbrt-v3's materials/ directory: each material's ComputeScatteringFunctions, which
 * evaluates its textures at the shading point and makes the BSDF's lobes (reflection.c).
 *   matte.cpp    LambertianReflection(Kd)            (sigma 0: the Oren-Nayar part is not supported)
 *   mirror.cpp   SpecularReflection(Kr, FresnelNoOp)
 *   plastic.cpp  LambertianReflection(Kd) + MicrofacetReflection(Ks, Trowbridge-Reitz(roughness),
 *                FresnelDielectric(1.5, 1))
 * Further materials (glass, metal, uber, substrate) join here as another ELR_MAT_ kind. */
#include "elr_internal.h"

/* The BSDF of the hit's material at the shading point c (its textures evaluated there). */
void elr_bsdf_init(const elr_scene *s, const elr_hit *h, const elr_tex_ctx *c, elr_bsdf *b) {
  const elr_material *m = &s->mat[h->material];
  b->ns = h->ns; b->ng = h->ng;
  elr_onb(b->ns, &b->ss, &b->ts);
  b->has_diffuse = b->has_glossy = b->has_specular = 0;
  b->kd = b->ks = b->kr = elr_v(0, 0, 0);
  b->alpha = 1.f;
  if (m->kind == ELR_MAT_MATTE) { /* MatteMaterial::ComputeScatteringFunctions */
    b->kd = elr_tex_eval(s, m->kd, c);
    b->has_diffuse = !elr_isblack(b->kd);
  } else if (m->kind == ELR_MAT_MIRROR) { /* MirrorMaterial::ComputeScatteringFunctions */
    b->kr = elr_tex_eval(s, m->kr, c);
    b->has_specular = !elr_isblack(b->kr);
  } else { /* PlasticMaterial::ComputeScatteringFunctions */
    float r;
    b->kd = elr_tex_eval(s, m->kd, c);
    b->ks = elr_tex_eval(s, m->ks, c);
    r = elr_tex_eval(s, m->rough, c).x;
    b->alpha = m->remap ? elr_roughness_to_alpha(r) : r;
    if (!(b->alpha > 1e-4f)) b->alpha = 1e-4f;
    b->has_diffuse = !elr_isblack(b->kd);
    b->has_glossy = !elr_isblack(b->ks);
  }
  b->ncomp = b->has_diffuse + b->has_glossy + b->has_specular;
}
