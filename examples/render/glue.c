/* glue.c: the renderer's only contact with envlight's headers (film.h, envlight.h, mipmap.h), which
 * it implements here (EL_*_IMPLEMENTATION) and wraps in the small interface of elr_internal.h. */
#include "elr_internal.h"
#include <stdlib.h>
#include <string.h>

#define EL_FILM_IMPLEMENTATION
#include "film.h"

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
  o.crop[0] = (float)x0 / (float)xres; o.crop[1] = (float)x1 / (float)xres;
  o.crop[2] = (float)y0 / (float)yres; o.crop[3] = (float)y1 / (float)yres;
  if (x0 == 0 && y0 == 0 && x1 == xres && y1 == yres) memset(o.crop, 0, sizeof o.crop);
  switch (fd->type) {
  case ELR_PF_TRIANGLE: o.filter.type = EL_FILTER_TRIANGLE; break;
  case ELR_PF_GAUSSIAN: o.filter.type = EL_FILTER_GAUSSIAN; o.filter.gaussian_alpha = fd->alpha; break;
  case ELR_PF_MITCHELL:
    o.filter.type = EL_FILTER_MITCHELL;
    o.filter.mitchell_b = fd->b; o.filter.mitchell_c = fd->c;
    if (fd->b == 0.f && fd->c == 0.f) o.filter.mitchell_b = o.filter.mitchell_c = 1e-30f;
    break;
  case ELR_PF_SINC: o.filter.type = EL_FILTER_LANCZOS; o.filter.lanczos_tau = fd->tau; break;
  default: o.filter.type = EL_FILTER_BOX; break;
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
    float v = el_srgb_encode(rgb[i]) * 255.f + 0.5f;
    out[i] = (unsigned char)(v < 0.f ? 0.f : (v > 255.f ? 255.f : v));
  }
  return 0;
}

/* >> environment (fallback until envlight.h lands: bilinear lat-long, uniform sphere sampling) */
struct elr_envmap {
  float *rgb; int w, h;
  float m[9]; /* light to world */
  float scale[3];
};
int elr_env_create(const float *rgb, int w, int h, const float scale[3], const float l2w[9], int compensated,
                   elr_envmap **out, char *err, size_t errlen) {
  elr_envmap *e = (elr_envmap *)calloc(1, sizeof *e);
  (void)compensated;
  if (!e) { snprintf(err, errlen, "out of memory"); return -1; }
  e->rgb = (float *)malloc(sizeof(float) * 3 * (size_t)w * (size_t)h);
  if (!e->rgb) { free(e); snprintf(err, errlen, "out of memory"); return -1; }
  memcpy(e->rgb, rgb, sizeof(float) * 3 * (size_t)w * (size_t)h);
  e->w = w; e->h = h;
  memcpy(e->m, l2w, sizeof e->m);
  memcpy(e->scale, scale, sizeof e->scale);
  *out = e;
  return 0;
}
void elr_env_free(elr_envmap *e) { if (e) { free(e->rgb); free(e); } }
elr_v3 elr_env_le(const elr_envmap *e, elr_v3 d) {
  /* world to light: the transpose of the rotation */
  elr_v3 wl = elr_norm(elr_v(e->m[0] * d.x + e->m[3] * d.y + e->m[6] * d.z, e->m[1] * d.x + e->m[4] * d.y + e->m[7] * d.z,
                             e->m[2] * d.x + e->m[5] * d.y + e->m[8] * d.z));
  float theta = acosf(wl.z < -1.f ? -1.f : (wl.z > 1.f ? 1.f : wl.z));
  float phi = atan2f(wl.y, wl.x);
  float s, t, x, y, fx, fy;
  int x0, y0, x1, y1, c;
  elr_v3 r;
  float v[3];
  if (phi < 0) phi += 2.f * ELR_PI;
  s = phi / (2.f * ELR_PI); t = theta / ELR_PI;
  x = s * e->w - 0.5f; y = t * e->h - 0.5f;
  x0 = (int)floorf(x); y0 = (int)floorf(y); fx = x - x0; fy = y - y0;
  x1 = x0 + 1; y1 = y0 + 1;
  x0 = ((x0 % e->w) + e->w) % e->w; x1 = ((x1 % e->w) + e->w) % e->w;
  y0 = ((y0 % e->h) + e->h) % e->h; y1 = ((y1 % e->h) + e->h) % e->h;
  for (c = 0; c < 3; c++) {
    v[c] = (1 - fx) * (1 - fy) * e->rgb[3 * ((size_t)y0 * e->w + x0) + c] + fx * (1 - fy) * e->rgb[3 * ((size_t)y0 * e->w + x1) + c] +
           (1 - fx) * fy * e->rgb[3 * ((size_t)y1 * e->w + x0) + c] + fx * fy * e->rgb[3 * ((size_t)y1 * e->w + x1) + c];
  }
  r = elr_v(v[0] * e->scale[0], v[1] * e->scale[1], v[2] * e->scale[2]);
  return r;
}
int elr_env_prepare(elr_envmap *e) { (void)e; return 0; }
elr_v3 elr_env_sample(const elr_envmap *e, float u0, float u1, elr_v3 *wi, float *pdf) {
  float z = 1.f - 2.f * u0, r = sqrtf(fmaxf(0.f, 1.f - z * z)), phi = 2.f * ELR_PI * u1;
  *wi = elr_v(r * cosf(phi), r * sinf(phi), z);
  *pdf = 1.f / (4.f * ELR_PI);
  return elr_env_le(e, *wi);
}
float elr_env_pdf(const elr_envmap *e, elr_v3 wi) { (void)e; (void)wi; return 1.f / (4.f * ELR_PI); }
size_t elr_env_distribution_bytes(const elr_envmap *e) { (void)e; return 0; }
size_t elr_env_image_bytes(const elr_envmap *e) { return sizeof(float) * 3 * (size_t)e->w * (size_t)e->h; }

/* >> MIP map (fallback until mipmap.h lands: bilinear level 0) */
struct elr_mip { float *rgb; int w, h, wrap; };
int elr_mip_create(const float *rgb, int w, int h, int wrap, int filter, float maxaniso, elr_mip **out, char *err,
                   size_t errlen) {
  elr_mip *m = (elr_mip *)calloc(1, sizeof *m);
  (void)filter; (void)maxaniso;
  if (!m) { snprintf(err, errlen, "out of memory"); return -1; }
  m->rgb = (float *)malloc(sizeof(float) * 3 * (size_t)w * (size_t)h);
  if (!m->rgb) { free(m); snprintf(err, errlen, "out of memory"); return -1; }
  memcpy(m->rgb, rgb, sizeof(float) * 3 * (size_t)w * (size_t)h);
  m->w = w; m->h = h; m->wrap = wrap;
  *out = m;
  return 0;
}
void elr_mip_free(elr_mip *m) { if (m) { free(m->rgb); free(m); } }
static elr_v3 elr__texel(const elr_mip *m, int x, int y) {
  if (m->wrap == ELR_WRAP_REPEAT) { x = ((x % m->w) + m->w) % m->w; y = ((y % m->h) + m->h) % m->h; }
  else if (m->wrap == ELR_WRAP_CLAMP) { x = x < 0 ? 0 : (x >= m->w ? m->w - 1 : x); y = y < 0 ? 0 : (y >= m->h ? m->h - 1 : y); }
  else if (x < 0 || y < 0 || x >= m->w || y >= m->h) return elr_v(0, 0, 0);
  return elr_v(m->rgb[3 * ((size_t)y * m->w + x)], m->rgb[3 * ((size_t)y * m->w + x) + 1], m->rgb[3 * ((size_t)y * m->w + x) + 2]);
}
elr_v3 elr_mip_lookup(elr_mip *m, float s, float t, float dsdx, float dtdx, float dsdy, float dtdy) {
  float x = s * m->w - 0.5f, y = t * m->h - 0.5f, fx, fy;
  int x0, y0;
  (void)dsdx; (void)dtdx; (void)dsdy; (void)dtdy;
  if (!isfinite(x) || !isfinite(y) || fabsf(x) > 1e8f || fabsf(y) > 1e8f) return elr_v(0, 0, 0);
  x0 = (int)floorf(x); y0 = (int)floorf(y); fx = x - x0; fy = y - y0;
  return elr_add(elr_add(elr_mul(elr__texel(m, x0, y0), (1 - fx) * (1 - fy)), elr_mul(elr__texel(m, x0 + 1, y0), fx * (1 - fy))),
                 elr_add(elr_mul(elr__texel(m, x0, y0 + 1), (1 - fx) * fy), elr_mul(elr__texel(m, x0 + 1, y0 + 1), fx * fy)));
}
void elr_mip_stats(const elr_mip *m, int *levels_built, size_t *bytes) {
  *levels_built = 1; *bytes = sizeof(float) * 3 * (size_t)m->w * (size_t)m->h;
}
