/* lights.c: the lights and the one interface the integrators see them through (the book's chapter 12,
 * Light Sources, and section 14.2, Sampling Light Sources).
 *
 * pbrt-v3: core/light.h (Light::Sample_Li, Pdf_Li, Le; the VisibilityTester of a light sample is
 * integrator.c's elr_light_unoccluded: the lights trace no rays) and
 * lights/point.cpp (PointLight), lights/distant.cpp (DistantLight), lights/infinite.cpp
 * (InfiniteAreaLight: here envlight.h's el_envlight, called directly: el_envlight_sample_li_cos and
 * el_envlight_pdf_li_cos, the product of the map and the clamped cosine of the shading point's normal,
 * where the BSDF only reflects; el_envlight_sample_li and el_envlight_pdf_li, the map alone, pbrt-v3's,
 * elsewhere or with "string sampling" "map"; el_envlight_le), lights/diffuse.cpp (DiffuseAreaLight). Point and distant
 * lights are delta lights: light sampling only, pdf 1, never hit by a ray. The environment is
 * sampled, and seen by rays that leave the scene. An area light is sampled through its shape's
 * Shape::Sample (shapes.c), and seen by rays that hit its shape (elr_hit.light; interaction.c's
 * elr_hit_le is SurfaceInteraction::Le), Pdf_Li from such a hit (elr_area_light_pdf). A triangle mesh
 * is one light here, sampled by area over its triangles (pbrt-v3 makes one light per triangle: the
 * same expected value, and with the "power" strategy the same probability for each triangle). */
#include "elr_internal.h"
#include <stdlib.h>
#include <string.h>

/* pbrt-v3's Sample_Li: a point on the light seen from the shading point p, drawn with u. */
void elr_light_sample_li(const elr_light *l, const elr_scene *s, elr_v3 p, const elr_v3 *n, const float u[2], elr_light_sample *ls) {
  ls->at_point = 0;
  ls->dist = INFINITY;
  ls->portal = -1;
  switch (l->kind) {
  case ELR_LIGHT_POINT: { /* PointLight::Sample_Li: I / r^2 from the light's position */
    elr_v3 dp = elr_sub(l->pos, p);
    float d2 = elr_dot(dp, dp), dist;
    if (d2 <= 0.f) { ls->pdf = 0.f; ls->L = ls->wi = elr_v(0, 0, 0); return; }
    dist = sqrtf(d2);
    ls->wi = elr_mul(dp, 1.f / dist);
    ls->L = elr_mul(l->L, 1.f / d2);
    ls->pdf = 1.f;
    ls->p_light = l->pos; ls->at_point = 1;
    return;
  }
  case ELR_LIGHT_DISTANT: /* DistantLight::Sample_Li: the shadow ray ends outside the scene's bounding sphere */
    ls->wi = l->dir; ls->L = l->L; ls->pdf = 1.f;
    ls->dist = 2.f * s->world_radius + elr_len(elr_sub(p, s->world_center)) + 1.f;
    return;
  case ELR_LIGHT_AREA: { /* DiffuseAreaLight::Sample_Li: a point on the shape, L(pShape, -wi) */
    elr_v3 pl, nl, dp;
    float d2;
    elr_shape_sample(s, l, p, u, &pl, &nl, &ls->pdf);
    dp = elr_sub(pl, p);
    d2 = elr_dot(dp, dp);
    if (ls->pdf == 0.f || d2 == 0.f) { ls->pdf = 0.f; ls->L = ls->wi = elr_v(0, 0, 0); return; }
    ls->wi = elr_mul(dp, 1.f / sqrtf(d2));
    ls->L = elr_area_light_L(l, nl, elr_mul(ls->wi, -1.f));
    ls->p_light = pl; ls->at_point = 2; /* (the shadow ray aims at pl from its offset origin) */
    return;
  }
  default: { /* InfiniteAreaLight::Sample_Li: the radiance comes with the sample (the map at the sampled
              * (u, v), no second direction-to-(u, v) mapping). With a normal: a density close to
              * L(wi) max(0, n.wi), so no sample is wasted below the surface (envlight.h's NOTES ON
              * PRODUCT SAMPLING); pbrt-v3 samples the map alone. */
    float wi[3], L[3];
    if (l->portal) { /* pbrt-v4's PortalImageInfiniteLight: through the windows p sees (envlight.h) */
      float pp[3];
      elr_to3(p, pp);
      ls->portal = el_envlight_portal_sample_li(l->portal, l->env_sample, pp, u, wi, L, &ls->pdf);
    } else if (n && l->product) {
      float nn[3];
      elr_to3(*n, nn);
      el_envlight_sample_li_cos(l->env_sample, nn, u, wi, L, &ls->pdf);
    } else {
      el_envlight_sample_li(l->env_sample, u, wi, L, &ls->pdf);
    }
    ls->wi = elr_from3(wi); ls->L = elr_from3(L);
    return;
  }
  }
}

/* pbrt-v3's Pdf_Li: the solid-angle density with which elr_light_sample_li with the same normal n
 * (NULL: none) would choose wi (0 for delta lights, which no direction can hit; an area light's is
 * elr_area_light_pdf, from the hit). */
float elr_light_pdf_li(const elr_light *l, const elr_v3 *n, elr_v3 wi) {
  float d[3];
  if (l->kind != ELR_LIGHT_INFINITE) return 0.f;
  elr_to3(wi, d);
  if (n && l->product) {
    float nn[3];
    elr_to3(*n, nn);
    return el_envlight_pdf_li_cos(l->env_sample, nn, d);
  }
  return el_envlight_pdf_li(l->env_sample, d);
}

float elr_light_pdf_li_at(const elr_light *l, elr_v3 p, const elr_v3 *n, elr_v3 wi) {
  float d[3], pp[3];
  if (l->kind != ELR_LIGHT_INFINITE || !l->portal) return elr_light_pdf_li(l, n, wi);
  elr_to3(wi, d);
  elr_to3(p, pp);
  return el_envlight_portal_pdf_li(l->portal, l->env_sample, pp, d);
}

/* pbrt-v3's Light::Le: the radiance a ray that leaves the scene in direction d receives from the light
 * (the environment; 0 for the other lights). */
elr_v3 elr_light_le(const elr_light *l, elr_v3 d) {
  float dir[3], L[3];
  if (l->kind != ELR_LIGHT_INFINITE) return elr_v(0, 0, 0);
  elr_to3(d, dir);
  el_envlight_le(l->env, dir, L);
  return elr_from3(L);
}

/* DiffuseAreaLight::Pdf_Li (Shape::Pdf) for the ray from ref that reached the light at lh. */
float elr_area_light_pdf(const elr_scene *s, const elr_light *l, elr_v3 ref, const elr_hit *lh) { return elr_shape_pdf(s, l, ref, lh); }

/* The area and (build_cdf) a mesh's area CDF, once per scene: shapes.c. */
int elr_area_light_prepare(const elr_scene *s, elr_light *l, int build_cdf) {
  double t0 = elr_now();
  int r = elr_shape_prepare(s, l, build_cdf);
  l->build_seconds += elr_now() - t0;
  return r;
}

/* pbrt-v3's Light::Power(), as its luminance y() (the "power" strategy's weight): 4 pi I for a point
 * light, pi r^2 L for a distant light (r: the scene's bounding sphere), (twosided ? 2 : 1) pi A L for an
 * area light; for the environment pi r^2 times the integral of L over the sphere (envlight.h's
 * power: pbrt-v4's, where pbrt-v3 took the mean texel, 4 pi too little and blind to sin(theta)). */
double elr_light_power(const elr_scene *s, const elr_light *l) {
  double r = s->world_radius, pi = 3.14159265358979323846;
  elr_v3 P;
  switch (l->kind) {
  case ELR_LIGHT_POINT: P = elr_mul(l->L, 4.f); return pi * (0.212671 * P.x + 0.715160 * P.y + 0.072169 * P.z);
  case ELR_LIGHT_DISTANT: P = l->L; return pi * r * r * (0.212671 * P.x + 0.715160 * P.y + 0.072169 * P.z);
  case ELR_LIGHT_AREA: P = l->L; return (l->twosided ? 2.0 : 1.0) * pi * l->area * (0.212671 * P.x + 0.715160 * P.y + 0.072169 * P.z);
  default: {
    float in[3];
    el_envlight_integral(l->env, in);
    return pi * r * r * (0.212671 * in[0] + 0.715160 * in[1] + 0.072169 * in[2]);
  }
  }
}

/* >> infinite light (pbrt-v3 lights/infinite.cpp: envlight.h's el_envlight) */
static int elr__importance(int importance) { /* envlight's map names; anything else: its default */
  return importance == EL_ENVLIGHT_IMPORTANCE_PBRT_V3 || importance == EL_ENVLIGHT_IMPORTANCE_TEXEL ||
                 importance == EL_ENVLIGHT_IMPORTANCE_BILINEAR
             ? importance
             : EL_ENVLIGHT_IMPORTANCE_CELL_AVERAGE;
}

/* The environment of LightSource "infinite": rgb (w x h linear floats, top row first: theta = 0; NULL
 * for a constant light of radiance `scale`), scaled by pbrt's L times scale, turned by the light-to-world
 * rotation l2w (3x3 row-major), sampling l->compensated and l->importance's density. */
int elr_infinite_init(elr_light *l, const float *rgb, int w, int h, const float scale[3], const float l2w[9], char *err,
                      size_t errlen) {
  el_envlight_options o;
  el_result r;
  l->env = (el_envlight *)calloc(1, sizeof *l->env);
  if (!l->env) { snprintf(err, errlen, "out of memory"); return -1; }
  memset(&o, 0, sizeof o);
  memcpy(o.light_to_world, l2w, sizeof o.light_to_world);
  o.compensated = l->compensated;
  o.importance = elr__importance(l->importance);
  o.sampler = EL_ENVLIGHT_SAMPLER_GUIDE; /* the CDF's points in expected O(1): keeps stratification */
  o.mapping = l->mapping; /* pbrt-v4's equal-area maps: box cell averages, pbrt-v4's own density */
  if (o.mapping != EL_ENVLIGHT_MAPPING_LATLONG) o.importance = EL_ENVLIGHT_IMPORTANCE_CELL_AVERAGE;
  o.bad_texels = l->bad_texels; /* the caller reports what became 0 (l->env's negative_texels ...) */
  if (rgb) {
    o.scale[0] = scale[0]; o.scale[1] = scale[1]; o.scale[2] = scale[2];
    /* an unscaled map is read in place (the parser keeps rgb in l->env_pixels when env->borrowed) */
    o.no_copy = scale[0] == 1.f && scale[1] == 1.f && scale[2] == 1.f;
    if (scale[0] == 0.f && scale[1] == 0.f && scale[2] == 0.f) {
      /* all zero means (1,1,1) to envlight: a black light instead */
      float z[3] = {0.f, 0.f, 0.f};
      r = el_envlight_init_constant(l->env, z, &o);
    } else {
      r = el_envlight_init(l->env, rgb, w, h, 3, &o);
    }
  } else {
    r = el_envlight_init_constant(l->env, scale, &o);
  }
  if (r != EL_SUCCESS) {
    if (l->env->bad_index >= 0) {
      int bi = l->env->bad_index, x = bi % (w > 0 ? w : 1), y = bi / (w > 0 ? w : 1), c;
      const float *t = rgb ? rgb + 3 * (size_t)bi : scale;
      float v = t[0];
      for (c = 0; c < 3; ++c) /* the bad channel: NaN, infinite or negative (or it overflows when scaled) */
        if (t[c] != t[c] || !(t[c] >= 0.f && t[c] <= 3.4e38f)) { v = t[c]; break; }
      if (r == EL_ERROR_NEGATIVE)
        snprintf(err, errlen, "texel (%d, %d) is negative (%g; \"string badtexels\" \"clampnegative\" clamps negatives to 0)", x, y, (double)v);
      else if (v != v || v > 3.4e38f || v < -3.4e38f)
        snprintf(err, errlen, "texel (%d, %d) is %s (\"string badtexels\" \"zero\" makes such texels 0)", x, y, v != v ? "NaN" : "infinite");
      else
        snprintf(err, errlen, "texel (%d, %d) times the light's scale overflows", x, y);
    }
    else if (r == EL_ERROR_NOT_ORTHONORMAL)
      snprintf(err, errlen, "the light's transformation must be a rotation (pbrt-v3 maps the environment with the CTM's rotation)");
    else
      snprintf(err, errlen, "environment: %s", el_result_string(r));
    free(l->env);
    l->env = NULL;
    return -1;
  }
  l->env_sample = l->env;
  l->le_same = 1;
  return 0;
}

/* Builds the sampling distribution now (before the render threads start). compensated and importance:
 * -1 for the scene's, else a density the render asks for instead (elr_render_options), made on the
 * first request as a second el_envlight of the same image (env_alt), which sample_li and pdf_li then
 * use (le always reads env). product: -1 the light's "sampling", else 1 product sampling, 0 the map
 * alone; with product sampling the product tables are built (el_envlight_prepare_product), and the
 * map's own tables only when need_map (some surface transmits through a non-specular lobe: its vertices
 * sample the map alone). Returns -1 when the distribution cannot be built. */
static int elr__portal_build(elr_light *l, int compensated, char *err, size_t errlen);
/* 1 when b's le is a's bit for bit: the same light, or env_alt made of a's texels (no_copy) with a's matrix,
 * mapping and constant (le reads nothing else) */
static int elr__le_same(const el_envlight *a, const el_envlight *b) {
  return a == b || (a && b && a->texels == b->texels && a->width == b->width && a->height == b->height && a->mapping == b->mapping &&
                    a->exact_transform == b->exact_transform && !memcmp(a->to_world, b->to_world, sizeof a->to_world) &&
                    !memcmp(a->perm, b->perm, sizeof a->perm) && !memcmp(a->iperm, b->iperm, sizeof a->iperm) &&
                    !memcmp(a->sign, b->sign, sizeof a->sign) && !memcmp(a->isign, b->isign, sizeof a->isign) &&
                    !memcmp(a->constant, b->constant, sizeof a->constant));
}
int elr_infinite_prepare(elr_light *l, int compensated, int importance, int product, int need_map) {
  if (compensated < 0) compensated = l->compensated;
  if (importance < 0) importance = l->importance;
  l->env_sample = l->env;
  if (compensated != l->compensated || importance != l->importance) {
    if (l->env_alt && (l->alt_compensated != compensated || l->alt_importance != importance)) {
      if (l->sun_hs && l->sun_hs_of == l->env_alt) { /* (its hot spots go with it: a new env_alt may reuse the address) */
        el_envlight_hotspots_free(l->sun_hs); free(l->sun_hs); l->sun_hs = NULL; l->sun_hs_of = NULL;
      }
      el_envlight_free(l->env_alt);
      free(l->env_alt);
      l->env_alt = NULL;
    }
    if (!l->env_alt) {
      el_envlight_options o;
      el_result r;
      el_envlight *a = (el_envlight *)calloc(1, sizeof *a);
      if (!a) return -1;
      memset(&o, 0, sizeof o);
      memcpy(o.light_to_world, l->env->to_world, sizeof o.light_to_world);
      o.compensated = compensated;
      o.importance = elr__importance(importance);
      o.sampler = EL_ENVLIGHT_SAMPLER_GUIDE;
      o.mapping = l->env->mapping;
      o.no_copy = 1; /* env's texels (checked, scaled), which live as long as env_alt */
      if (o.mapping != EL_ENVLIGHT_MAPPING_LATLONG) o.importance = EL_ENVLIGHT_IMPORTANCE_CELL_AVERAGE;
      if (l->env->width > 0) r = el_envlight_init(a, l->env->texels, l->env->width, l->env->height, 3, &o);
      else r = el_envlight_init_constant(a, l->env->constant, &o);
      if (r != EL_SUCCESS) { el_envlight_free(a); free(a); return -1; }
      l->env_alt = a; l->alt_compensated = compensated; l->alt_importance = importance;
    }
    l->env_sample = l->env_alt;
  }
  l->le_same = elr__le_same(l->env, l->env_sample);
  l->product = product < 0 ? l->sampling == ELR_ENVLS_PRODUCT : product;
  /* the portals' tables with the compensation this render asks for (--compensated: pbrt-v4's portal
   * light has none; envlight's portal density max(lum - mean, 0) is the MIS partner of the BSDF) */
  if (l->portal && l->portal_compensated != compensated) {
    char err[256];
    if (elr__portal_build(l, compensated, err, sizeof err) != 0) return -1;
  }
  if (l->portal) l->product = 0; /* the portals sample every vertex; the map's own tables behind them */
  if (l->product && el_envlight_prepare_product(l->env_sample, NULL) != EL_SUCCESS) return -1;
  if (l->product && !need_map) return 0;
  return el_envlight_prepare_sampling(l->env_sample) == EL_SUCCESS ? 0 : -1;
}

/* atan2(y, x) to about 1e-5 rad (a minimax polynomial on [0, 1] and the octant symmetries): enough to
 * find a cache line, and a fraction of the exact mapping's cost */
static float elr__atan2_approx(float y, float x) {
  float ax = fabsf(x), ay = fabsf(y), mx = ax > ay ? ax : ay, mn = ax > ay ? ay : ax, a, a2, r;
  if (!(mx > 0.f)) return 0.f;
  a = mn / mx; a2 = a * a;
  r = a * (0.99997726f + a2 * (-0.33262347f + a2 * (0.19354346f + a2 * (-0.11643287f + a2 * (0.05265332f - 0.01172120f * a2)))));
  if (ay > ax) r = 1.57079637f - r;
  if (x < 0.f) r = 3.14159274f - r;
  return y < 0.f ? -r : r;
}

/* A hint, no effect on any result: starts loading the cache lines that elr_light_pdf_li and
 * elr_light_le will read for world direction wi. For the environment: the texels of el_envlight_le's
 * bilinear lookup and el_envlight_pdf_li's pdf bin (approximately: the bin of (u, v), where a
 * neighbouring bin shares the line or costs one more miss later). A random direction's texels and pdf
 * bin are cache misses in the multi-megabyte tables; issued before a shadow ray, they arrive while the
 * ray is traced. Nothing for the other lights. */
void elr_light_prefetch(const elr_light *l, elr_v3 wi) {
#if defined(__GNUC__) || defined(__clang__)
  const el_envlight *e, *p;
  const float *m;
  float d[3], u, v, s, t;
  int x, y, y1, w, h;
  if (l->kind != ELR_LIGHT_INFINITE) return;
  e = l->env_sample; p = l->env; m = p->to_world; w = p->width; h = p->height;
  if (w <= 0 || !p->texels || p->mapping != EL_ENVLIGHT_MAPPING_LATLONG) return;
  d[0] = m[0] * wi.x + m[3] * wi.y + m[6] * wi.z; /* light space: the transpose of the rotation */
  d[1] = m[1] * wi.x + m[4] * wi.y + m[7] * wi.z;
  d[2] = m[2] * wi.x + m[5] * wi.y + m[8] * wi.z;
  /* pbrt's mapping (phi / 2 pi, theta / pi), approximately */
  u = elr__atan2_approx(d[1], d[0]) * 0.159154943f;
  if (u < 0.f) u += 1.f;
  v = elr__atan2_approx(sqrtf(d[0] * d[0] + d[1] * d[1]), d[2]) * 0.318309886f;
  if (!(u >= 0.f && u <= 1.f && v >= 0.f && v <= 1.f)) return;
  s = u * (float)w - 0.5f; t = v * (float)h - 0.5f;
  x = (int)(s + 1.f) - 1; y = (int)(t + 1.f) - 1;
  if (x < 0) x = 0;
  if (x > w - 1) x = w - 1;
  y1 = y + 1 > h - 1 ? h - 1 : y + 1;
  if (y < 0) y = 0;
  if (y > h - 1) y = h - 1;
  /* both texels of each row: x and x + 1 (the line of the pair's last float: a 12-byte texel pair
   * crosses a 64-byte line for 5 columns of 16; for the others it is the same line and costs little) */
  __builtin_prefetch(p->texels + ((size_t)y * (size_t)w + (size_t)x) * 3);
  __builtin_prefetch(p->texels + ((size_t)y * (size_t)w + (size_t)x) * 3 + 5);
  __builtin_prefetch(p->texels + ((size_t)y1 * (size_t)w + (size_t)x) * 3);
  __builtin_prefetch(p->texels + ((size_t)y1 * (size_t)w + (size_t)x) * 3 + 5);
  if (!l->product && e->pdf_table && e->dist.nu > 0 && e->dist.nv > 0) { /* (product sampling reads other tables) */
    int iu = (int)(u * (float)e->dist.nu), iv = (int)(v * (float)e->dist.nv);
    if (iu > e->dist.nu - 1) iu = e->dist.nu - 1;
    if (iv > e->dist.nv - 1) iv = e->dist.nv - 1;
    __builtin_prefetch(e->pdf_table + (size_t)iv * (size_t)e->dist.nu + (size_t)iu);
  }
#else
  (void)l; (void)wi;
#endif
}

/* the portal tables of l's points (l->portal_points) with compensation 0/1, replacing any built */
static int elr__portal_build(elr_light *l, int compensated, char *err, size_t errlen) {
  el_result r;
  el_envlight_portal *P = (el_envlight_portal *)calloc(1, sizeof *P);
  if (!P) { snprintf(err, errlen, "out of memory"); return -1; }
  {
    el_envlight_portal_options po;
    memset(&po, 0, sizeof po);
    po.compensated = compensated; /* pbrt-v4's portal light has no MIS compensation; envlight's does */
    po.map_share = l->portal_share;
    po.map_share_outside = 1; /* (the share only behind some portal's plane: a room's inside keeps the pure portal density) */
    r = el_envlight_portal_init(P, l->env, l->portal_points, l->portal_count, &po);
  }
  if (r != EL_SUCCESS) {
    snprintf(err, errlen, "\"point3 portal\": %s (%s)", P->error, el_result_string(r));
    el_envlight_portal_free(P);
    free(P);
    return -1;
  }
  if (l->portal) { el_envlight_portal_free(l->portal); free(l->portal); }
  l->portal = P;
  l->portal_compensated = compensated;
  return 0;
}

int elr_infinite_set_portals(elr_light *l, const float *pts, int count, char *err, size_t errlen) {
  if (!l->env || !l->has_map) { snprintf(err, errlen, "portals need an environment map (\"mapname\"), as in pbrt-v4"); return -1; }
  free(l->portal_points);
  l->portal_points = (float *)malloc((size_t)(count > 0 ? count : 1) * 12 * sizeof(float));
  if (!l->portal_points) { snprintf(err, errlen, "out of memory"); return -1; }
  if (count > 0) memcpy(l->portal_points, pts, (size_t)count * 12 * sizeof(float));
  l->portal_count = count;
  return elr__portal_build(l, l->compensated, err, errlen);
}

void elr_light_free(elr_light *l) {
  if (l->sun_hs) { el_envlight_hotspots_free(l->sun_hs); free(l->sun_hs); l->sun_hs = NULL; }
  if (l->portal) { el_envlight_portal_free(l->portal); free(l->portal); l->portal = NULL; }
  free(l->portal_points);
  l->portal_points = NULL;
  free(l->tri_cdf);
  l->tri_cdf = NULL;
  if (l->env_alt) { el_envlight_free(l->env_alt); free(l->env_alt); }
  if (l->env) { el_envlight_free(l->env); free(l->env); }
  free(l->env_pixels); /* after the lights that read it */
  l->env_pixels = NULL;
  l->env = l->env_alt = l->env_sample = NULL;
}
