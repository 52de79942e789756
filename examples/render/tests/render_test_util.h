/* render_test_util.h: shared helpers of the renderer's tests (a temporary directory, file writing,
 * check counting, rendering a scene string). Each test writes its scenes and maps at run time. */
#ifndef RENDER_TEST_UTIL_H
#define RENDER_TEST_UTIL_H
#define _POSIX_C_SOURCE 200809L
#include "el_render.h"
#include "elr_internal.h"
#include "image_io.h"
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static int rt_pass, rt_fail;
static char rt_dir[256];

static void rt_check(int ok, const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  printf("%s: ", ok ? "ok  " : "FAIL");
  vprintf(fmt, ap);
  printf("\n");
  va_end(ap);
  if (ok) rt_pass++; else rt_fail++;
}
static int rt_finish(const char *name) {
  char cmd[400];
  printf("%s: %d passed, %d failed\n", name, rt_pass, rt_fail);
  if (rt_dir[0]) { snprintf(cmd, sizeof cmd, "rm -rf '%s'", rt_dir); if (system(cmd) != 0) printf("(could not remove %s)\n", rt_dir); }
  return rt_fail ? 1 : 0;
}
static void rt_mkdir(const char *name) {
  snprintf(rt_dir, sizeof rt_dir, "/tmp/%s_XXXXXX", name);
  if (!mkdtemp(rt_dir)) { perror("mkdtemp"); exit(1); }
}
static const char *rt_path(const char *file) {
  static char buf[8][512];
  static int k;
  k = (k + 1) % 8;
  snprintf(buf[k], sizeof buf[k], "%s/%s", rt_dir, file);
  return buf[k];
}
static void rt_write(const char *file, const char *text) {
  FILE *f = fopen(rt_path(file), "wb");
  if (!f) { perror(file); exit(1); }
  fputs(text, f);
  fclose(f);
}
/* Load a scene written to the temp dir; returns NULL (with err) on failure. */
#if defined(__GNUC__)
__attribute__((unused))
#endif
static elr_scene *rt_load(const char *file, const char *text, char *err, size_t errlen) {
  elr_scene *s = NULL;
  rt_write(file, text);
  if (elr_scene_load(rt_path(file), &s, 1, err, errlen) != 0) return NULL;
  return s;
}
/* Render with the given overrides; returns 0 on success. */
#if defined(__GNUC__)
__attribute__((unused))
#endif
static int rt_render(elr_scene *s, int spp, int ls, int comp, int nthreads, uint64_t seed, elr_image *img, elr_stats *st) {
  elr_render_options o;
  char err[512];
  elr_render_options_default(&o);
  o.spp = spp; o.light_sampling = ls; o.compensated = comp; o.nthreads = nthreads; o.seed = seed; o.quiet = 1;
  if (elr_render(s, &o, img, st, err, sizeof err) != 0) { printf("render failed: %s\n", err); return -1; }
  return 0;
}
/* The BSDF of the material text `mat` (e.g. "Material \"metal\""), made through the parser and
 * materials.c (a scene of one sphere, integrator "path"), at n = ns = ng = z with the frame ss = x,
 * ts = y (pbrt-v3's for dpdu = x); returns 0 on success. */
#if defined(__GNUC__)
__attribute__((unused))
#endif
static int rt_bsdf_of(const char *mat, elr_bsdf *b) {
  char buf[2048], err[512];
  elr_scene *s;
  elr_hit h;
  elr_tex_ctx tc;
  snprintf(buf, sizeof buf, "Integrator \"path\"\nWorldBegin\n%s\nShape \"sphere\"\nWorldEnd\n", mat);
  s = rt_load("mat.pbrt", buf, err, sizeof err);
  if (!s) { rt_check(0, "material scene: %s", err); return -1; }
  memset(&h, 0, sizeof h); memset(&tc, 0, sizeof tc);
  h.ns = h.ng = elr_v(0, 0, 1); h.material = s->sph[0].material; h.inst = -1;
  h.has_uv = 1; h.dpdu = elr_v(1, 0, 0); h.dpdv = elr_v(0, 1, 0);
  elr_bsdf_init(s, &h, &tc, b);
  elr_scene_free(s);
  return 0;
}
#endif
