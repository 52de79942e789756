/* api_materials.c: Material, MakeNamedMaterial's material and Texture (pbrt-v3 core/api.cpp's MakeMaterial,
 * MakeFloatTexture and MakeSpectrumTexture, with the parameters of materials/ and textures/):
 * matte, mirror, plastic, glass, metal, uber, substrate; constant, checkerboard, imagemap (described:
 * scene.c's elr_scene_make_textures reads its image into a MIP map after the parse), scale, mix. */
#include "parser.h"

/* glass's and uber's index of refraction: pbrt-v3's "eta", else "index" (1.5); a number must be one
 * the Fresnel and refraction maths can use (textures are kept in [1e-3, 1e3] where evaluated) */
static int elr__pindex(elr__parser *P) {
  const char *nm = elr__find(P, "eta") ? "eta" : "index";
  elr__param *p = elr__find(P, nm);
  if (p && strcmp(p->type, "texture") != 0) elr__check_range(P, nm, elr__pfloat(P, nm, 1.5), 1e-3, 1e3);
  return elr__ptex(P, nm, elr_v(1.5f, 1.5f, 1.5f), 1);
}
int elr__make_material(elr__parser *P, const char *type) {
  elr_scene *s = P->s;
  elr_material *m;
  int kind;
  if (!strcmp(type, "matte")) kind = ELR_MAT_MATTE;
  else if (!strcmp(type, "mirror")) kind = ELR_MAT_MIRROR;
  else if (!strcmp(type, "plastic")) kind = ELR_MAT_PLASTIC;
  else if (!strcmp(type, "glass")) kind = ELR_MAT_GLASS;
  else if (!strcmp(type, "metal")) kind = ELR_MAT_METAL;
  else if (!strcmp(type, "uber")) kind = ELR_MAT_UBER;
  else if (!strcmp(type, "substrate")) kind = ELR_MAT_SUBSTRATE;
  else {
    char key[200];
    snprintf(key, sizeof key, "Material %.180s", type);
    if (!strcmp(type, "") || !strcmp(type, "none") || !strcmp(type, "interface")) {
      elr__warn_once(P, P->dir_file, P->dir_line, key, "Material \"%s\" (no surface) is not supported; using \"matte\"", type);
    } else {
      elr__warn_once(P, P->dir_file, P->dir_line, key, "Material \"%s\" is not supported; using \"matte\" with its defaults", type);
    }
    { int i; for (i = 0; i < P->nparams; i++) P->params[i].used = 1; }
    kind = -1;
  }
  ELR_PUSH(P, s->mat, s->nmat, s->capmat, elr_material);
  m = &s->mat[s->nmat - 1];
  m->kind = kind < 0 ? ELR_MAT_MATTE : kind;
  m->kd = m->ks = m->kr = m->rough = -1;
  m->kt = m->urough = m->vrough = m->index = m->eta = m->k = m->opacity = -1;
  if (kind < 0) { m->kd = elr__const_tex(P, elr_v(.5f, .5f, .5f)); return s->nmat - 1; }
  if (kind == ELR_MAT_MATTE) {
    m->kd = elr__ptex(P, "Kd", elr_v(.5f, .5f, .5f), 0);
    /* sigma (degrees): pbrt-v3's OrenNayar where it is not 0; its texture in the "rough" slot, only
     * when given, so a matte without it keeps the fixed Lambertian lobe */
    if (elr__find(P, "sigma")) m->rough = elr__ptex(P, "sigma", elr_v(0, 0, 0), 1);
  } else if (kind == ELR_MAT_MIRROR) {
    m->kr = elr__ptex(P, "Kr", elr_v(.9f, .9f, .9f), 0);
  } else if (kind == ELR_MAT_PLASTIC) {
    m->kd = elr__ptex(P, "Kd", elr_v(.25f, .25f, .25f), 0);
    m->ks = elr__ptex(P, "Ks", elr_v(.25f, .25f, .25f), 0);
    m->rough = elr__ptex(P, "roughness", elr_v(.1f, .1f, .1f), 1);
    m->remap = elr__pbool(P, "remaproughness", 1);
  } else if (kind == ELR_MAT_GLASS) { /* CreateGlassMaterial */
    m->kr = elr__ptex(P, "Kr", elr_v(1, 1, 1), 0);
    m->kt = elr__ptex(P, "Kt", elr_v(1, 1, 1), 0);
    m->index = elr__pindex(P);
    m->urough = elr__ptex(P, "uroughness", elr_v(0, 0, 0), 1);
    m->vrough = elr__ptex(P, "vroughness", elr_v(0, 0, 0), 1);
    m->remap = elr__pbool(P, "remaproughness", 1);
  } else if (kind == ELR_MAT_METAL) { /* CreateMetalMaterial: copper by default */
    /* pbrt-v3's CopperN and CopperK spectra (materials/metal.cpp, 56 samples from 298.8 to 885.6 nm)
     * as RGBSpectrum::FromSampled makes them: the CIE 1931 matching functions of core/spectrum.cpp at
     * 1 nm, normalised by CIE_Y_integral, then XYZToRGB; computed in float with pbrt-v3's own tables
     * and order of operations (Mitsuba 3's Cu preset, from other measurements: 0.2004 0.9240 1.1022
     * and 3.9129 2.4528 2.1422) */
    m->eta = elr__ptex(P, "eta", elr_v(0.19999069f, 0.92208463f, 1.09987593f), 0);
    m->k = elr__ptex(P, "k", elr_v(3.90463543f, 2.44763327f, 2.13765264f), 0);
    m->rough = elr__ptex(P, "roughness", elr_v(.01f, .01f, .01f), 1);
    if (elr__find(P, "uroughness")) m->urough = elr__ptex(P, "uroughness", elr_v(0, 0, 0), 1);
    if (elr__find(P, "vroughness")) m->vrough = elr__ptex(P, "vroughness", elr_v(0, 0, 0), 1);
    m->remap = elr__pbool(P, "remaproughness", 1);
  } else if (kind == ELR_MAT_UBER) { /* CreateUberMaterial */
    m->kd = elr__ptex(P, "Kd", elr_v(.25f, .25f, .25f), 0);
    m->ks = elr__ptex(P, "Ks", elr_v(.25f, .25f, .25f), 0);
    m->kr = elr__ptex(P, "Kr", elr_v(0, 0, 0), 0);
    m->kt = elr__ptex(P, "Kt", elr_v(0, 0, 0), 0);
    m->rough = elr__ptex(P, "roughness", elr_v(.1f, .1f, .1f), 1);
    if (elr__find(P, "uroughness")) m->urough = elr__ptex(P, "uroughness", elr_v(0, 0, 0), 1);
    if (elr__find(P, "vroughness")) m->vrough = elr__ptex(P, "vroughness", elr_v(0, 0, 0), 1);
    m->index = elr__pindex(P);
    m->opacity = elr__ptex(P, "opacity", elr_v(1, 1, 1), 0);
    m->remap = elr__pbool(P, "remaproughness", 1);
  } else { /* CreateSubstrateMaterial */
    m->kd = elr__ptex(P, "Kd", elr_v(.5f, .5f, .5f), 0);
    m->ks = elr__ptex(P, "Ks", elr_v(.5f, .5f, .5f), 0);
    m->urough = elr__ptex(P, "uroughness", elr_v(.1f, .1f, .1f), 1);
    m->vrough = elr__ptex(P, "vroughness", elr_v(.1f, .1f, .1f), 1);
    m->remap = elr__pbool(P, "remaproughness", 1);
  }
  if (elr__find(P, "bumpmap")) { elr_warn(P->s, P->dir_file, P->dir_line, "Material: \"bumpmap\" ignored"); elr__find(P, "bumpmap")->used = 1; }
  return s->nmat - 1;
}

/* How many textures one evaluation of texture ti may look up: a checkerboard evaluates both of its
 * sub-textures where its filter straddles an edge, a scale both, a mix all three (textures.c recurses). Every texture already made has a
 * cost of at most ELR_MAX_TEX_COST, so this recursion visits at most that many leaves. */
#define ELR_MAX_TEX_COST 64
static int elr__tex_cost(const elr_scene *s, int ti) {
  const elr_texture *t;
  if (ti < 0 || ti >= s->ntex) return 1;
  t = &s->tex[ti];
  if (t->kind == ELR_TEX_MIX) return elr__tex_cost(s, t->tex1) + elr__tex_cost(s, t->tex2) + elr__tex_cost(s, t->amount);
  if (t->kind != ELR_TEX_CHECKER && t->kind != ELR_TEX_SCALE) return 1;
  return elr__tex_cost(s, t->tex1) + elr__tex_cost(s, t->tex2);
}

void elr__texture(elr__parser *P, const char *name, const char *vtype, const char *cls) {
  elr_scene *s = P->s;
  elr_texture t;
  int is_float = !strcmp(vtype, "float");
  const char *mapping;
  if (!is_float && strcmp(vtype, "spectrum") && strcmp(vtype, "color") && strcmp(vtype, "rgb"))
    elr__failf(P, P->dir_file, P->dir_line, "Texture \"%s\": type \"%s\" must be \"float\" or \"spectrum\"", name, vtype);
  memset(&t, 0, sizeof t);
  t.is_float = is_float;
  mapping = elr__pstring(P, "mapping", "uv");
  if (strcmp(mapping, "uv") != 0) elr_warn(P->s, P->dir_file, P->dir_line, "Texture \"%s\": mapping \"%s\" not supported; using \"uv\"", name, mapping);
  t.su = (float)elr__pfloat(P, "uscale", 1.0); t.sv = (float)elr__pfloat(P, "vscale", 1.0);
  t.du = (float)elr__pfloat(P, "udelta", 0.0); t.dv = (float)elr__pfloat(P, "vdelta", 0.0);
  if (!strcmp(cls, "constant")) {
    t.kind = ELR_TEX_CONST;
    if (is_float) { float v = (float)elr__pfloat(P, "value", 1.0); t.value = elr_v(v, v, v); }
    else t.value = elr__prgb(P, "value", elr_v(1, 1, 1));
  } else if (!strcmp(cls, "checkerboard")) {
    int dim = elr__pint(P, "dimension", 2);
    const char *aa = elr__pstring(P, "aamode", "closedform");
    if (dim != 2) elr__failf(P, P->dir_file, P->dir_line, "Texture \"%s\": checkerboard dimension %d not supported (only 2)", name, dim);
    t.kind = ELR_TEX_CHECKER;
    t.tex1 = elr__ptex(P, "tex1", elr_v(1, 1, 1), is_float);
    t.tex2 = elr__ptex(P, "tex2", elr_v(0, 0, 0), is_float);
    { /* chained checkerboards double the work per level (2^40 lookups from a 40-line file) and recurse
       * once per level on a render thread's stack (200000 levels overflowed it) */
      int cost = elr__tex_cost(s, t.tex1) + elr__tex_cost(s, t.tex2);
      if (cost > ELR_MAX_TEX_COST)
        elr__failf(P, P->dir_file, P->dir_line, "Texture \"%s\": checkerboards nested too deeply (%d texture lookups per evaluation, at most %d)",
                  name, cost, ELR_MAX_TEX_COST);
    }
    if (!strcmp(aa, "closedform")) t.aa_closedform = 1;
    else if (!strcmp(aa, "none")) t.aa_closedform = 0;
    else elr__failf(P, P->dir_file, P->dir_line, "Texture \"%s\": aamode must be \"closedform\" or \"none\"", name);
  } else if (!strcmp(cls, "scale") || !strcmp(cls, "mix")) {
    /* pbrt-v3's ScaleTexture (tex1 * tex2, both 1 by default) and MixTexture ((1 - amount) tex1 +
     * amount tex2; tex1 0, tex2 1, amount 0.5) */
    int mix = cls[0] == 'm';
    float d1 = mix ? 0.f : 1.f;
    const elr_texture *a, *b, *m = NULL;
    t.kind = mix ? ELR_TEX_MIX : ELR_TEX_SCALE;
    t.tex1 = elr__ptex(P, "tex1", elr_v(d1, d1, d1), is_float);
    t.tex2 = elr__ptex(P, "tex2", elr_v(1, 1, 1), is_float);
    t.amount = mix ? elr__ptex(P, "amount", elr_v(.5f, .5f, .5f), 1) : -1;
    {
      int cost = elr__tex_cost(s, t.tex1) + elr__tex_cost(s, t.tex2) + (mix ? elr__tex_cost(s, t.amount) : 0);
      if (cost > ELR_MAX_TEX_COST)
        elr__failf(P, P->dir_file, P->dir_line, "Texture \"%s\": textures nested too deeply (%d texture lookups per evaluation, at most %d)",
                  name, cost, ELR_MAX_TEX_COST);
    }
    /* of constants, a constant (the same sums textures.c would make at every shading point) */
    a = &s->tex[t.tex1]; b = &s->tex[t.tex2];
    if (mix) m = &s->tex[t.amount];
    if (a->kind == ELR_TEX_CONST && b->kind == ELR_TEX_CONST && (!mix || m->kind == ELR_TEX_CONST)) {
      if (mix) t.value = elr_add(elr_mul(a->value, 1.f - m->value.x), elr_mul(b->value, m->value.x));
      else t.value = elr_vmul(a->value, b->value);
      t.kind = ELR_TEX_CONST;
    }
  } else if (!strcmp(cls, "imagemap")) {
    const char *fn = elr__pstring(P, "filename", "");
    const char *wrap = elr__pstring(P, "wrap", "repeat");
    float scale = (float)elr__pfloat(P, "scale", 1.0);
    float maxan = (float)elr__pfloat(P, "maxanisotropy", 8.0);
    el_mipmap_filter filter = EL_MIPMAP_FILTER_EWA;
    el_mipmap_wrap wr;
    int gamma;
    size_t fl = strlen(fn);
    elr_imagemap_desc *D;
    if (elr__find(P, "filter")) {
      const char *f = elr__pstring(P, "filter", "bilinear");
      if (!strcmp(f, "ewa") || !strcmp(f, "EWA")) filter = EL_MIPMAP_FILTER_EWA;
      else if (!strcmp(f, "trilinear")) filter = EL_MIPMAP_FILTER_TRILINEAR;
      else if (!strcmp(f, "bilinear")) filter = EL_MIPMAP_FILTER_BILINEAR;
      else elr__failf(P, elr__find(P, "filter")->file, elr__find(P, "filter")->line, "Texture \"%s\": filter must be \"bilinear\", \"trilinear\" or \"ewa\"", name);
    } else if (elr__find(P, "trilinear")) { /* pbrt-v3's spelling */
      filter = elr__pbool(P, "trilinear", 0) ? EL_MIPMAP_FILTER_TRILINEAR : EL_MIPMAP_FILTER_EWA;
    }
    if (!strcmp(wrap, "repeat")) wr = EL_MIPMAP_WRAP_REPEAT;
    else if (!strcmp(wrap, "black")) wr = EL_MIPMAP_WRAP_BLACK;
    else if (!strcmp(wrap, "clamp")) wr = EL_MIPMAP_WRAP_CLAMP;
    else elr__failf(P, elr__find(P, "wrap")->file, elr__find(P, "wrap")->line, "Texture \"%s\": wrap must be \"repeat\", \"black\" or \"clamp\"", name);
    elr__check_range(P, "maxanisotropy", maxan, 1.0, 1024.0); /* mipmap.h's limit */
    if (!fn[0]) elr__failf(P, P->dir_file, P->dir_line, "Texture \"%s\": imagemap needs \"string filename\"", name);
    gamma = elr__pbool(P, "gamma", (fl > 4 && (!strcmp(fn + fl - 4, ".png") || !strcmp(fn + fl - 4, ".tga"))));
    t.kind = ELR_TEX_IMAGE;
    /* the description scene.c's elr_scene_make_textures reads the image of and makes the MIP map of */
    ELR_PUSH(P, s->texdesc, s->ntexdesc, s->captexdesc, elr_imagemap_desc);
    D = &s->texdesc[s->ntexdesc - 1];
    D->tex = s->ntex; /* the slot the texture takes below */
    D->gamma = gamma; D->is_float = is_float; D->scale = scale; D->maxaniso = maxan;
    D->filter = (int)filter; D->wrap = (int)wr;
    D->line = P->dir_line;
    D->file = elr__heap_strdup(P, P->dir_file ? P->dir_file : "?");
    D->name = elr__heap_strdup(P, name);
    D->path = elr__heap_strdup(P, elr__resolve(P, fn));
  } else {
    char key[200];
    snprintf(key, sizeof key, "Texture %.180s", cls);
    elr__warn_once(P, P->dir_file, P->dir_line, key, "Texture class \"%s\" is not supported; \"%s\" is a constant %s", cls, name,
                   is_float ? "1" : "(1,1,1)");
    { int i; for (i = 0; i < P->nparams; i++) P->params[i].used = 1; }
    t.kind = ELR_TEX_CONST; t.value = elr_v(1, 1, 1);
  }
  ELR_PUSH(P, s->tex, s->ntex, s->captex, elr_texture);
  s->tex[s->ntex - 1] = t;
  /* name it in the current scope */
  if (P->gs.ntex_scope < P->ntexn) { /* drop names of closed scopes */
    elr__name_drop(&P->htex, P->texnames, P->ntexn, P->gs.ntex_scope);
    P->ntexn = P->gs.ntex_scope;
  }
  ELR_PUSH(P, P->texnames, P->ntexn, P->captexn, elr__named);
  P->texnames[P->ntexn - 1].name = elr__strdup(P, name, strlen(name));
  elr__name_add(P, &P->htex, P->texnames, P->ntexn - 1);
  P->texnames[P->ntexn - 1].index = s->ntex - 1;
  P->texnames[P->ntexn - 1].is_float = is_float;
  P->gs.ntex_scope = P->ntexn;
}
