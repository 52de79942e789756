/* glue.c: the renderer's only contact with envlight's headers (film.h, envlight.h, mipmap.h), which
 * it implements here (EL_*_IMPLEMENTATION) and wraps in the small interface of elr_internal.h. */
#if defined(__linux__) && !defined(_DEFAULT_SOURCE)
#define _DEFAULT_SOURCE /* madvise */
#endif
#include "elr_internal.h"
#include <stdlib.h>
#include <string.h>
#if defined(__linux__)
#include <sys/mman.h>
#endif

/* The headers' allocations through EL_MALLOC (their documented hook): tables of 2 MiB and more (the
 * environment's texels, its sampling tables, MIP levels) are 2 MiB aligned and asked for transparent
 * huge pages. The renderer reads them at random directions: with 4 KiB pages nearly every such read
 * also missed the TLB (the 6 MB map and the 8 MB pdf and CDF tables of pbrt-v3's importance map span
 * thousands of pages). Smaller blocks and reallocations are plain malloc / realloc; free() takes both. */
static void *elr__malloc(size_t n) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  const size_t huge = (size_t)2 << 20;
  if (n >= huge) {
    void *p = NULL;
    if (posix_memalign(&p, huge, n) != 0) return NULL;
    (void)madvise(p, n & ~(huge - 1), MADV_HUGEPAGE); /* a hint: without it the pages are just small */
    return p;
  }
#endif
  return malloc(n);
}
#define EL_MALLOC(sz) elr__malloc(sz)
#define EL_REALLOC(p, newsz) realloc(p, newsz)
#define EL_FREE(p) free(p)

#define EL_FILM_IMPLEMENTATION
#define EL_ENVLIGHT_IMPLEMENTATION
#define EL_DISTRIBUTION2D_IMPLEMENTATION
#define EL_MIPMAP_IMPLEMENTATION
#define EL_BLOCKEDARRAY_IMPLEMENTATION
#include "film.h"
#include "envlight.h"
#include "mipmap.h"

/* >> film (film.h: pbrt-v3's Film and FilmTile) */
struct elr_film { el_film f; };
struct elr_tile { el_film_tile t; };

int elr_film_create(int xres, int yres, int x0, int y0, int x1, int y1, const elr_filter_desc *fd, elr_film **out,
                    char *err, size_t errlen) {
  el_film_options o;
  elr_film *f = (elr_film *)calloc(1, sizeof *f);
  el_result r;
  *out = NULL;
  if (!f) { snprintf(err, errlen, "out of memory"); return -1; }
  memset(&o, 0, sizeof o);
  o.width = xres; o.height = yres;
  /* film.h takes pbrt's fractions and applies ceil(res * fraction): half a pixel below each integer
   * bound gives that bound back whatever the float rounding */
  o.crop[0] = x0 > 0 ? ((float)x0 - 0.5f) / (float)xres : 0.f; o.crop[1] = ((float)x1 - 0.5f) / (float)xres;
  o.crop[2] = y0 > 0 ? ((float)y0 - 0.5f) / (float)yres : 0.f; o.crop[3] = ((float)y1 - 0.5f) / (float)yres;
  if (x0 == 0 && y0 == 0 && x1 == xres && y1 == yres) memset(o.crop, 0, sizeof o.crop);
  switch (fd->type) {
  case ELR_PF_TRIANGLE: o.filter.type = EL_FILM_FILTER_TRIANGLE; break;
  case ELR_PF_GAUSSIAN: o.filter.type = EL_FILM_FILTER_GAUSSIAN; o.filter.gaussian_alpha = fd->alpha; break;
  case ELR_PF_MITCHELL:
    o.filter.type = EL_FILM_FILTER_MITCHELL;
    o.filter.mitchell_b = fd->b; o.filter.mitchell_c = fd->c;
    if (fd->b == 0.f && fd->c == 0.f) o.filter.mitchell_b = o.filter.mitchell_c = 1e-30f;
    break;
  case ELR_PF_SINC: o.filter.type = EL_FILM_FILTER_LANCZOS; o.filter.lanczos_tau = fd->tau; break;
  default: o.filter.type = EL_FILM_FILTER_BOX; break;
  }
  o.filter.radius[0] = fd->xw; o.filter.radius[1] = fd->yw;
  r = el_film_init(&f->f, &o);
  if (r != EL_SUCCESS) { free(f); snprintf(err, errlen, "film: %s", el_result_string(r)); return -1; }
  if (f->f.x0 != x0 || f->f.y0 != y0 || f->f.x1 != x1 || f->f.y1 != y1) {
    /* the crop fractions we passed must give back our pixel bounds exactly */
    el_film_free(&f->f); free(f);
    snprintf(err, errlen, "film: crop window bounds mismatch"); return -1;
  }
  *out = f;
  return 0;
}
void elr_film_free(elr_film *f) { if (f) { el_film_free(&f->f); free(f); } }
elr_tile *elr_film_tile(elr_film *f, int x0, int y0, int x1, int y1) {
  elr_tile *t = (elr_tile *)calloc(1, sizeof *t);
  if (!t) return NULL;
  if (el_film_tile_init(&f->f, &t->t, x0, y0, x1, y1) != EL_SUCCESS) { free(t); return NULL; }
  return t;
}
void elr_tile_add(elr_tile *t, float fx, float fy, elr_v3 L) {
  float rgb[3];
  rgb[0] = L.x; rgb[1] = L.y; rgb[2] = L.z;
  el_film_tile_add_sample(&t->t, fx, fy, rgb, 1.f);
}
void elr_film_merge(elr_film *f, elr_tile *t) {
  if (!t) return;
  el_film_merge_tile(&f->f, &t->t);
  el_film_tile_free(&t->t);
  free(t);
}
void elr_film_rgb(elr_film *f, float *rgb) { el_film_get_rgb(&f->f, 1.f, rgb); }
void elr_film_sample_bounds(const elr_film *f, int *x0, int *y0, int *x1, int *y1) {
  int b[4] = {0, 0, 0, 0};
  el_film_sample_bounds(&f->f, b);
  *x0 = b[0]; *y0 = b[1]; *x1 = b[2]; *y1 = b[3];
}
size_t elr_film_bytes(const elr_film *f) { return el_film_bytes(&f->f); }
size_t elr_film_splat_bytes(const elr_film *f) {
  return f->f.splats ? (size_t)f->f.width * (size_t)f->f.height * 3 * sizeof(double) : 0;
}
uint64_t elr_film_rejected(const elr_film *f) { return el_film_rejected_samples(&f->f); }
int elr_srgb8(const float *rgb, int n, unsigned char *out) {
  int i;
  for (i = 0; i < 3 * n; i++) {
    float v = el_film_srgb_encode(rgb[i]) * 255.f + 0.5f;
    out[i] = (unsigned char)(v < 0.f ? 0.f : (v > 255.f ? 255.f : v));
  }
  return 0;
}

/* >> environment (envlight.h: pbrt-v3's InfiniteAreaLight) */
struct elr_envmap {
  el_envlight plain; /* as the scene asked */
  el_envlight other; /* another density (compensated / importance map), made on demand by elr_env_prepare */
  int scene_comp, scene_imp, other_comp, other_imp, other_ready, use_other;
};
static int elr__imp(int importance) {
  return importance == ELR_IMPORTANCE_PBRT_V3 ? EL_ENVLIGHT_IMPORTANCE_PBRT_V3
       : importance == ELR_IMPORTANCE_TEXEL ? EL_ENVLIGHT_IMPORTANCE_TEXEL : EL_ENVLIGHT_IMPORTANCE_CELL_AVERAGE;
}
int elr_env_create(const float *rgb, int w, int h, const float scale[3], const float l2w[9], int compensated,
                   int importance, elr_envmap **out, char *err, size_t errlen) {
  el_envlight_options o;
  el_result r;
  elr_envmap *e = (elr_envmap *)calloc(1, sizeof *e);
  *out = NULL;
  if (!e) { snprintf(err, errlen, "out of memory"); return -1; }
  memset(&o, 0, sizeof o);
  memcpy(o.light_to_world, l2w, sizeof o.light_to_world);
  o.compensated = compensated;
  o.importance = elr__imp(importance);
  o.sampler = EL_ENVLIGHT_SAMPLER_GUIDE; /* the CDF's points in expected O(1): keeps stratification */
  if (rgb) {
    o.scale[0] = scale[0]; o.scale[1] = scale[1]; o.scale[2] = scale[2];
    if (scale[0] == 0.f && scale[1] == 0.f && scale[2] == 0.f) {
      /* all zero means (1,1,1) to envlight: a black light instead */
      float z[3] = {0.f, 0.f, 0.f};
      r = el_envlight_init_constant(&e->plain, z, &o);
    } else {
      r = el_envlight_init(&e->plain, rgb, w, h, 3, &o);
    }
  } else {
    r = el_envlight_init_constant(&e->plain, scale, &o);
  }
  if (r != EL_SUCCESS) {
    if (e->plain.bad_index >= 0)
      snprintf(err, errlen, "environment map texel (%d, %d) is NaN, infinite or negative", e->plain.bad_index % (w > 0 ? w : 1), e->plain.bad_index / (w > 0 ? w : 1));
    else if (r == EL_ERROR_NOT_ORTHONORMAL)
      snprintf(err, errlen, "the light's transformation must be a rotation (pbrt-v3 maps the environment with the CTM's rotation)");
    else
      snprintf(err, errlen, "environment: %s", el_result_string(r));
    free(e);
    return -1;
  }
  e->scene_comp = compensated;
  e->scene_imp = importance;
  *out = e;
  return 0;
}
void elr_env_free(elr_envmap *e) {
  if (!e) return;
  el_envlight_free(&e->plain);
  el_envlight_free(&e->other);
  free(e);
}
static el_envlight *elr__env_s(const elr_envmap *e) { return (el_envlight *)(e->use_other ? &e->other : &e->plain); }
elr_v3 elr_env_le(const elr_envmap *e, elr_v3 d) {
  float dir[3], c[3];
  dir[0] = d.x; dir[1] = d.y; dir[2] = d.z;
  el_envlight_le(&e->plain, dir, c);
  return elr_v(c[0], c[1], c[2]);
}
int elr_env_prepare(elr_envmap *e, int compensated, int importance) {
  if (compensated < 0) compensated = e->scene_comp;
  if (importance < 0) importance = e->scene_imp;
  e->use_other = 0;
  if (compensated != e->scene_comp || importance != e->scene_imp) {
    if (e->other_ready && (e->other_comp != compensated || e->other_imp != importance)) {
      el_envlight_free(&e->other);
      e->other_ready = 0;
    }
    if (!e->other_ready) {
      el_envlight_options o;
      el_result r;
      memset(&o, 0, sizeof o);
      memcpy(o.light_to_world, e->plain.to_world, sizeof o.light_to_world);
      o.compensated = compensated;
      o.importance = elr__imp(importance);
      o.sampler = EL_ENVLIGHT_SAMPLER_GUIDE;
      if (e->plain.width > 0) r = el_envlight_init(&e->other, e->plain.texels, e->plain.width, e->plain.height, 3, &o);
      else r = el_envlight_init_constant(&e->other, e->plain.constant, &o);
      if (r != EL_SUCCESS) return -1;
      e->other_ready = 1; e->other_comp = compensated; e->other_imp = importance;
    }
    e->use_other = 1;
  }
  return el_envlight_prepare_sampling(elr__env_s(e)) == EL_SUCCESS ? 0 : -1;
}
elr_v3 elr_env_sample(const elr_envmap *e, float u0, float u1, elr_v3 *wi, float *pdf) {
  float u[2], w[3], c[3];
  u[0] = u0; u[1] = u1;
  el_envlight_sample_li(elr__env_s(e), u, w, c, pdf);
  *wi = elr_v(w[0], w[1], w[2]);
  return elr_v(c[0], c[1], c[2]);
}
void elr_env_sample_n(const elr_envmap *e, int n, const float *u, float *wi, float *L, float *pdf) {
  el_envlight_sample_li_n(elr__env_s(e), n, u, wi, L, pdf);
}
void elr_env_sample_dir(const elr_envmap *e, float u0, float u1, elr_v3 *wi, float *pdf) {
  float u[2], w[3];
  u[0] = u0; u[1] = u1;
  el_envlight_sample_li(elr__env_s(e), u, w, NULL, pdf);
  *wi = elr_v(w[0], w[1], w[2]);
}
/* Prefetch the cache lines that elr_env_pdf and elr_env_le will read for world direction wi: the
 * texels of its bilinear lookup and its pdf bin (approximately: the bin of (u, v); a neighbouring bin
 * shares the line or costs one more miss later). No effect on any result. */
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
void elr_env_prefetch(const elr_envmap *e, elr_v3 wi) {
#if defined(__GNUC__) || defined(__clang__)
  const el_envlight *l = elr__env_s(e), *p = &e->plain;
  const float *m = p->to_world;
  float d[3], u, v, s, t;
  int x, y, y1, w = p->width, h = p->height;
  if (w <= 0 || !p->texels) return;
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
  if (l->pdf_table && l->dist.nu > 0 && l->dist.nv > 0) {
    int iu = (int)(u * (float)l->dist.nu), iv = (int)(v * (float)l->dist.nv);
    if (iu > l->dist.nu - 1) iu = l->dist.nu - 1;
    if (iv > l->dist.nv - 1) iv = l->dist.nv - 1;
    __builtin_prefetch(l->pdf_table + (size_t)iv * (size_t)l->dist.nu + (size_t)iu);
  }
#else
  (void)e; (void)wi;
#endif
}
float elr_env_pdf(const elr_envmap *e, elr_v3 wi) {
  float d[3];
  d[0] = wi.x; d[1] = wi.y; d[2] = wi.z;
  return el_envlight_pdf_li(elr__env_s(e), d);
}
size_t elr_env_distribution_bytes(const elr_envmap *e) { return el_envlight_sampling_bytes(elr__env_s(e)); }
size_t elr_env_image_bytes(const elr_envmap *e) { return sizeof(float) * 3 * (size_t)e->plain.width * (size_t)e->plain.height; }

/* >> MIP map (mipmap.h: pbrt-v3's MIPMap; upper levels built on the first lookup that needs them) */
struct elr_mip { el_mipmap m; int filter; };
int elr_mip_create(const float *rgb, int w, int h, int wrap, int filter, float maxaniso, elr_mip **out, char *err,
                   size_t errlen) {
  el_mipmap_options o;
  el_result r;
  elr_mip *m = (elr_mip *)calloc(1, sizeof *m);
  *out = NULL;
  if (!m) { snprintf(err, errlen, "out of memory"); return -1; }
  memset(&o, 0, sizeof o);
  o.wrap_u = o.wrap_v = wrap == ELR_WRAP_BLACK ? EL_MIPMAP_WRAP_BLACK : (wrap == ELR_WRAP_CLAMP ? EL_MIPMAP_WRAP_CLAMP : EL_MIPMAP_WRAP_REPEAT);
  o.filter = filter == ELR_FILTER_TRILINEAR ? EL_MIPMAP_FILTER_TRILINEAR : (filter == ELR_FILTER_BILINEAR ? EL_MIPMAP_FILTER_BILINEAR : EL_MIPMAP_FILTER_EWA);
  o.max_anisotropy = maxaniso;
  r = el_mipmap_init(&m->m, rgb, w, h, 3, &o);
  if (r != EL_SUCCESS) { free(m); snprintf(err, errlen, "MIP map: %s", el_result_string(r)); return -1; }
  m->filter = filter;
  *out = m;
  return 0;
}
void elr_mip_free(elr_mip *m) { if (m) { el_mipmap_free(&m->m); free(m); } }
elr_v3 elr_mip_lookup(elr_mip *m, float s, float t, float dsdx, float dtdx, float dsdy, float dtdy) {
  float c[3];
  el_mipmap_lookup_differentials(&m->m, s, t, dsdx, dtdx, dsdy, dtdy, c);
  return elr_v(c[0], c[1], c[2]);
}
void elr_mip_stats(const elr_mip *m, int *levels_built, size_t *bytes) {
  *levels_built = el_mipmap_levels_built(&m->m) ? el_mipmap_levels(&m->m) : 1; /* level 0 always exists */
  *bytes = el_mipmap_bytes(&m->m);
}
