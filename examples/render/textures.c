/* textures.c: pbrt-v3's textures/ directory: constant.cpp, checkerboard.cpp (Checkerboard2DTexture,
 * with its closed-form box filter over the ray footprint), imagemap.cpp (ImageTexture: a MIP map of
 * mipmap.h, filtered by el_mipmap_lookup_differentials), all through the UVMapping2D of core/texture.cpp,
 * and scale.cpp (ScaleTexture: tex1 * tex2) and mix.cpp (MixTexture: (1 - amount) tex1 + amount tex2),
 * which combine other textures. The parser (api_materials.c) makes them (a scale or mix of constants is
 * made a constant there; an image texture's MIP map is made by scene.c after the parse); materials.c
 * evaluates them at shading points. Float textures hold their value in all three components. */
#include "elr_internal.h"

/* The texture ti at the shading point's (u, v) and its screen-space differentials: pbrt-v3's
 * Texture<T>::Evaluate for the kinds of textures/ below (ti < 0: black). */
elr_v3 elr_tex_eval(const elr_scene *s, int ti, const elr_tex_ctx *c) {
  const elr_texture *t;
  float st0, st1, ds0x, ds1x, ds0y, ds1y;
  if (ti < 0 || ti >= s->ntex) return elr_v(0, 0, 0);
  t = &s->tex[ti];
  if (t->kind == ELR_TEX_CONST) return t->value; /* textures/constant.cpp */
  if (t->kind == ELR_TEX_SCALE) /* textures/scale.cpp, ScaleTexture::Evaluate */
    return elr_vmul(elr_tex_eval(s, t->tex1, c), elr_tex_eval(s, t->tex2, c));
  if (t->kind == ELR_TEX_MIX) { /* textures/mix.cpp, MixTexture::Evaluate */
    elr_v3 t1 = elr_tex_eval(s, t->tex1, c), t2 = elr_tex_eval(s, t->tex2, c);
    float amt = elr_tex_eval(s, t->amount, c).x;
    return elr_add(elr_mul(t1, 1.f - amt), elr_mul(t2, amt));
  }
  /* <<UVMapping2D::Map>> */
  st0 = t->su * c->u + t->du; st1 = t->sv * c->v + t->dv;
  ds0x = t->su * c->dudx; ds1x = t->sv * c->dvdx;
  ds0y = t->su * c->dudy; ds1y = t->sv * c->dvdy;
  if (t->kind == ELR_TEX_CHECKER) { /* textures/checkerboard.cpp, Checkerboard2DTexture */
    float ds = fmaxf(fabsf(ds0x), fabsf(ds0y)), dt = fmaxf(fabsf(ds1x), fabsf(ds1y));
    float s0 = st0 - ds, s1 = st0 + ds, t0 = st1 - dt, t1 = st1 + dt;
    if (!isfinite(st0) || !isfinite(st1) || fabsf(st0) > 1e9f || fabsf(st1) > 1e9f) return elr_tex_eval(s, t->tex2, c);
    if (!t->aa_closedform || !(ds > 0.f || dt > 0.f) || (floorf(s0) == floorf(s1) && floorf(t0) == floorf(t1))) {
      /* <<Point sample Checkerboard2DTexture>> */
      if (((int)floorf(st0) + (int)floorf(st1)) % 2 == 0) return elr_tex_eval(s, t->tex1, c);
      return elr_tex_eval(s, t->tex2, c);
    } else {
      /* <<Apply box filter to checkerboard region>> */
#define ELR_BUMPINT(x) ((float)(int)floorf((x) / 2) + 2 * fmaxf((x) / 2 - (float)(int)floorf((x) / 2) - 0.5f, 0.f))
      /* a filter 1 check or wider averages to 0.5: decided first, so that a huge differential (grazing
       * angles, a large uscale) never reaches the int conversions below (undefined beyond INT_MAX) */
      float area2 = 0.5f;
      if (ds < 1.f && dt < 1.f) {
        float sint = ds > 0.f ? (ELR_BUMPINT(s1) - ELR_BUMPINT(s0)) / (2 * ds) : 0.5f;
        float tint = dt > 0.f ? (ELR_BUMPINT(t1) - ELR_BUMPINT(t0)) / (2 * dt) : 0.5f;
        area2 = sint + tint - 2 * sint * tint;
      }
#undef ELR_BUMPINT
      return elr_add(elr_mul(elr_tex_eval(s, t->tex1, c), 1.f - area2), elr_mul(elr_tex_eval(s, t->tex2, c), area2));
    }
  }
  { /* ImageTexture::Evaluate: the MIP map's filtered lookup over the footprint (mipmap.h) */
    float rgb[3];
    el_mipmap_lookup_differentials(t->mip, st0, st1, ds0x, ds1x, ds0y, ds1y, rgb);
    return elr_from3(rgb);
  }
}
