/* sun_measure.h: shared by tests/test_render_sun.c and bench/bench_sun_render.c (issue 22). Renders a scene
 * with several seeds, the sun cache off and on, and compares the pixels' variance over the seeds in the
 * shadowed and in the lit pixels. Which pixels are which comes from the geometry, not from the renderer's
 * cache: a pixel is SHADOWED when the first hits of 5 rays through it (its centre and 4 points 0.3 pixel
 * away) all have the largest hot spot's axis (el_envlight_hotspots_init) occluded or behind their
 * geometric normal, LIT when all 5 see it, else neither (the shadow's edges). */
#ifndef SUN_MEASURE_H
#define SUN_MEASURE_H
#include "el_render.h"
#include "elr_internal.h"
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { SM_OTHER = 0, SM_SHADOW = 1, SM_LIT = 2 };

/* the classes of the w x h pixels of scene s (rendered once already, so that its light's tables exist);
 * returns NULL when the scene has no environment with a hot spot */
static unsigned char *sm_classes(elr_scene *s, int *w, int *h) {
  elr_camera cam;
  el_envlight_hotspots hs;
  const elr_light *l = NULL;
  unsigned char *cls;
  elr_v3 axis;
  int fb[4], x, y, i;
  for (i = 0; i < s->nlight; i++) if (s->light[i].kind == ELR_LIGHT_INFINITE && s->light[i].env_sample) { l = &s->light[i]; break; }
  /* (the scene's own light l->env: the sun's direction does not depend on the density a render samples, and
   * the default render samples le()'s patches under a sun, which has no hot spots: issue 22) */
  if (!l || el_envlight_hotspots_init(&hs, l->env, NULL) != EL_SUCCESS) return NULL;
  if (hs.count == 0) { el_envlight_hotspots_free(&hs); return NULL; }
  axis = elr_v(hs.spot[0].axis[0], hs.spot[0].axis[1], hs.spot[0].axis[2]);
  el_envlight_hotspots_free(&hs);
  elr_film_bounds(&s->d, fb);
  *w = fb[2] - fb[0]; *h = fb[3] - fb[1];
  elr_camera_init(&cam, &s->d, 1, 0);
  cls = (unsigned char *)calloc((size_t)*w * (size_t)*h, 1);
  if (!cls) return NULL;
  for (y = 0; y < *h; y++)
    for (x = 0; x < *w; x++) {
      static const float off[5][2] = {{0.5f, 0.5f}, {0.2f, 0.2f}, {0.8f, 0.2f}, {0.2f, 0.8f}, {0.8f, 0.8f}};
      int seen = 0, dark = 0, k;
      for (k = 0; k < 5; k++) {
        elr_ray r;
        elr_hit hit;
        elr_v3 n;
        elr_camera_ray(&cam, (float)(fb[0] + x) + off[k][0], (float)(fb[1] + y) + off[k][1], &r);
        if (!elr_intersect(s, r.o, r.d, INFINITY, &hit)) continue;
        n = elr_dot(hit.ng, r.d) <= 0.f ? hit.ng : elr_mul(hit.ng, -1.f);
        if (elr_dot(n, axis) <= 0.f || elr_occluded(s, elr_spawn_origin(&hit, axis), axis, INFINITY)) dark++;
        else seen++;
      }
      cls[y * *w + x] = dark == 5 ? SM_SHADOW : seen == 5 ? SM_LIT : SM_OTHER;
    }
  return cls;
}

typedef struct sm_result {
  int n[3];              /* pixels per class */
  double mean[3];        /* the class's mean luminance (over its pixels and the seeds) */
  double var[3];         /* the class's mean per-pixel variance of the luminance over the seeds */
  double med[3];         /* and its median over the class's pixels */
  double cpu;            /* CPU seconds of the renders' loops (all seeds) */
  double *m, *v;         /* per pixel: mean and variance over the seeds */
  elr_stats st;          /* the last render's */
} sm_result;

static int sm__cmp_double(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return x < y ? -1 : x > y ? 1 : 0;
}
static int sm_loop = -1;       /* the renders' per-tile loop (elr_render_options.loop; -1 the default) */
static int sm_importance = -1; /* and the environment's importance map (elr_render_options.importance) */
static int sm_sampler = -1;    /* and the sampler (elr_render_options.sampler; -1: the scene's) */
/* nseeds renders at spp of scene s with the sun cache (sun: the env_sun option, 1 on, 0 off, 2 split) into r; 0 on success */
static int sm_run(elr_scene *s, int spp, int nseeds, int sun, int nthreads, const unsigned char *cls, int w, int h, sm_result *r) {
  double *s1, *s2;
  int k, i, np = w * h;
  memset(r, 0, sizeof *r);
  s1 = (double *)calloc((size_t)np, sizeof(double)); s2 = (double *)calloc((size_t)np, sizeof(double));
  if (!s1 || !s2) { free(s1); free(s2); return -1; }
  for (k = 0; k < nseeds; k++) {
    elr_render_options o;
    elr_image im;
    char err[512];
    elr_render_options_default(&o);
    o.spp = spp; o.nthreads = nthreads; o.seed = (uint64_t)(1000 + k); o.quiet = 1; o.env_sun = sun; o.loop = sm_loop; o.importance = sm_importance;
    if (sm_sampler >= 0) o.sampler = sm_sampler;
    if (elr_render(s, &o, &im, &r->st, err, sizeof err) != 0 || im.width != w || im.height != h) {
      printf("render failed: %s\n", err); free(s1); free(s2); return -1;
    }
    r->cpu += r->st.t_render_cpu;
    for (i = 0; i < np; i++) {
      double y = 0.2126 * im.rgb[3 * i] + 0.7152 * im.rgb[3 * i + 1] + 0.0722 * im.rgb[3 * i + 2];
      s1[i] += y; s2[i] += y * y;
    }
    elr_image_free(&im);
  }
  for (i = 0; i < np; i++) {
    double m = s1[i] / nseeds, v = (s2[i] - nseeds * m * m) / (nseeds - 1);
    s1[i] = m; s2[i] = v > 0 ? v : 0;
    r->n[cls[i]]++; r->mean[cls[i]] += m; r->var[cls[i]] += s2[i];
  }
  for (k = 0; k < 3; k++) if (r->n[k]) { r->mean[k] /= r->n[k]; r->var[k] /= r->n[k]; }
  r->m = s1; r->v = s2;
  for (k = 0; k < 3; k++) { /* the medians */
    double *t = (double *)malloc((size_t)(r->n[k] + 1) * sizeof(double));
    int n = 0;
    if (!t) continue;
    for (i = 0; i < np; i++) if (cls[i] == k) t[n++] = s2[i];
    qsort(t, (size_t)n, sizeof(double), sm__cmp_double);
    r->med[k] = n ? t[n / 2] : 0.0;
    free(t);
  }
  return 0;
}
static void sm_free(sm_result *r) { free(r->m); free(r->v); r->m = r->v = NULL; }

/* the z score of the difference of the class means of a and b (nseeds renders each): the mean over the
 * class's pixels of (mean_a - mean_b), over its standard error (the pixels independent) */
static double sm_z(const sm_result *a, const sm_result *b, const unsigned char *cls, int np, int c, int nseeds) {
  double d = 0, v = 0;
  int i, n = 0;
  for (i = 0; i < np; i++)
    if (c < 0 || cls[i] == c) { d += a->m[i] - b->m[i]; v += (a->v[i] + b->v[i]) / nseeds; n++; }
  return n && v > 0 ? d / sqrt(v) : 0.0;
}
#endif
