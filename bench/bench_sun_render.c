/* bench_sun_render.c: the renderer's noise in the sun's shadow and in the sun, with issue 22's sun cache
 * (examples/render/sun.c, --sun on) and without it (--sun off: the renderer's density before it).
 *
 *   bench_sun_render [SPP [SEEDS [THREADS [SCENE.pbrt ...]]]]   samples per pixel (16), seeds per case (16),
 *                    threads (2), scenes (scenes/sun_shadow_object.pbrt: direct lighting; scenes/sun_porch.pbrt:
 *                    path tracing, maxdepth 3; scenes/bench_city.pbrt: city.hdr's sun, direct lighting).
 *                    Run from the repository's root.
 *   bench_sun_render --csv [SPP [SEEDS [THREADS [SCENE ...]]]]   the same as CSV rows
 *                    (kind,option,scene,class,spp,pixels,mean,variance,cpu_s; option off / on)
 *   bench_sun_render [--csv] [--split] [--loop-one] ...   --split: --sun split (sun.c: one spot and one sky sample per
 *                    diffuse vertex, in the default's loop) in place of --sun on; --loop-one: every render in the one-sample loop
 *                    (the default's wave loop left out of the comparison); --pbrt-v3: every render with pbrt-v3's importance
 *                    map (the default under a sun is le()'s patch density); --random: the
 *                    independent sampler (pbrt's "random") in place of the scenes'
 *   bench_sun_render --shadow-point   the library alone at one shadowed ground point: which density pays
 *                    (light sample alone, and with a cosine BSDF sample), see shadow_point below
 *   bench_sun_render --lit-point [MAP]   the library alone at one lit ground point (MAP: sunrise or city, data/envmaps):
 *                    --sun split's estimator against the
 *                    default's, per term (lit_point below)
 *   bench_sun_render --picture [OUT.png]   where 2000 light samples of a shadowed ground point land, without
 *                    and with the cache (the course's appendix, A3.14)
 *
 * For each scene: its pixels classed SHADOWED (5 rays through the pixel all hit points that do not see the
 * largest hot spot's axis), LIT (all 5 see it) or neither (examples/render/tests/sun_measure.h); SEEDS
 * renders with the cache off and on. Printed per class: the mean luminance with each (and the z score of
 * their difference: unbiased when |z| is small), the mean over its pixels of the variance over the seeds,
 * and their ratio (off / on: the gain at equal samples); the CPU seconds of one render loop (plus, for
 * "on", the pilot's CPU seconds; the best of 5 interleaved off / on renders of seed 1000) and the gain at
 * equal time (variance x seconds, off / on). Not counted: finding the map's hot spots and building their
 * tables, once per light (a fresh `render --sun on` pays it: see --stats). */
#define _POSIX_C_SOURCE 200809L /* bench_common.h's clocks */
#include "tests/sun_measure.h"
#include "image_io.h"
#include "picture.h"
#include "bench_common.h"
#include <sys/stat.h>
#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

/* ---- the picture: where the light samples of one shadowed ground point land, before and after ---- */
/* the picture's helpers, the clocks and the generator are bench_common.h's (test_rng.h's 64-bit xorshift) */
static xorshift64 g_rng = {88172645463325252ULL};
static float frand(void) { return xorshift64_f(&g_rng); }
/* The point (-1.5, 0, 0) of scenes/sun_shadow_object.pbrt's ground, in the block's shadow: 2000 light
 * samples of the renderer's density there without the cache (a diffuse vertex under a sun map: the map
 * alone, el_envlight_sample_li) and with it (elr_sun_sample: the rest x cosine, the sun at the floor),
 * drawn on the lat-long map (2x): red in the sun's cone, orange blocked by the scene, yellow reaching the
 * sky, grey below the ground's horizon. */
static int picture(const char *out) {
  elr_scene *s = NULL;
  elr_image im;
  elr_render_options o;
  elr_ctx C;
  elr_sun *S = NULL;
  elr_hit hit;
  char err[512], label[200];
  const elr_light *l;
  const el_envlight *e;
  const elr_sun_cell *cell;
  int fb[4], panel, W, H, x, y, i, ns = 2000, Z = 2;
  unsigned char *pix;
  elr_v3 n = elr_v(0, 1, 0), wo;
  if (elr_scene_load(EL_SOURCE_DIR "/scenes/sun_shadow_object.pbrt", &s, 1, err, sizeof err) != 0) { fprintf(stderr, "%s\n", err); return 1; }
  elr_render_options_default(&o);
  o.spp = 1; o.quiet = 1; o.nthreads = 1;
  o.importance = EL_ENVLIGHT_IMPORTANCE_PBRT_V3; /* (the scene's own density, whose hot spots the cache needs: the
                                                    default under a sun is le()'s patch density since issue 22) */
  if (elr_render(s, &o, &im, NULL, err, sizeof err) != 0) { fprintf(stderr, "%s\n", err); return 1; }
  elr_image_free(&im);
  l = &s->light[0]; e = l->env_sample;
  memset(&C, 0, sizeof C);
  C.s = s;
  elr_camera_init(&C.cam, &s->d, 1, 0);
  elr_film_bounds(&s->d, fb);
  if (elr_sun_build(&C, l, fb, 1, &S) != 0 || !S) { fprintf(stderr, "no sun cache\n"); return 1; }
  if (!elr_intersect(s, elr_v(-1.5f, 1.f, 0.f), elr_v(0, -1, 0), INFINITY, &hit)) { fprintf(stderr, "no ground\n"); return 1; }
  wo = elr_norm(elr_sub(elr_v(0, 2.6f, -7), hit.p));
  cell = elr_sun_lookup(S, &hit, wo);
  W = Z * e->width; H = Z * e->height;
  pix = (unsigned char *)calloc((size_t)W * 2 * (size_t)H * 3, 1);
  if (!pix) return 1;
  for (panel = 0; panel < 2; ++panel) {
    unsigned char *pm = pix + (size_t)panel * (size_t)W * (size_t)H * 3;
    int nsun = 0, nsky = 0, nblock = 0, nbelow = 0;
    g_rng.s = 88172645463325252ULL;
    for (y = 0; y < H; ++y) /* the map, one stop darker */
      for (x = 0; x < W; ++x) {
        const float *t = e->texels + 3 * ((size_t)(y / Z) * (size_t)e->width + (size_t)(x / Z));
        unsigned char *q = pm + 3 * ((size_t)y * (size_t)W + (size_t)x);
        q[0] = picture_to8(0.5 * t[0]); q[1] = picture_to8(0.5 * t[1]); q[2] = picture_to8(0.5 * t[2]);
      }
    for (i = 0; i < ns; ++i) {
      float u[2], wi[3], L[3], pdf, d[3], uu, vv;
      elr_v3 w;
      u[0] = frand(); u[1] = frand();
      if (panel == 0) el_envlight_sample_li(e, u, wi, L, &pdf);
      else elr_sun_sample(S, cell, &n, u, wi, L, &pdf);
      if (!(pdf > 0.f)) continue;
      w = elr_from3(wi);
      d[0] = e->to_world[0] * wi[0] + e->to_world[3] * wi[1] + e->to_world[6] * wi[2]; /* (light space) */
      d[1] = e->to_world[1] * wi[0] + e->to_world[4] * wi[1] + e->to_world[7] * wi[2];
      d[2] = e->to_world[2] * wi[0] + e->to_world[5] * wi[1] + e->to_world[8] * wi[2];
      el_envlight_dir_to_uv(d, &uu, &vv);
      x = (int)(uu * (float)W); y = (int)(vv * (float)H);
      if (elr_sun_in_spot(S, wi)) { nsun++; picture_dot(pm, W, H, x, y, 2, 255, 40, 40); }
      else if (elr_dot(w, n) <= 0.f) { nbelow++; picture_dot(pm, W, H, x, y, 1, 150, 150, 150); }
      else if (elr_occluded(s, elr_spawn_origin(&hit, w), w, INFINITY)) { nblock++; picture_dot(pm, W, H, x, y, 1, 255, 140, 0); }
      else { nsky++; picture_dot(pm, W, H, x, y, 1, 255, 230, 40); }
    }
    snprintf(label, sizeof label, "%s: %d IN THE SUN (RED), %d REACH THE SKY (YELLOW)", panel == 0 ? "BEFORE (THE MAP ALONE)" : "AFTER (THE SUN CACHE)", nsun, nsky);
    el_draw_label(pm, W, H, 8, 8, label);
    snprintf(label, sizeof label, "%d BLOCKED BY THE SCENE (ORANGE), %d BELOW THE GROUND (GREY)", nblock, nbelow);
    el_draw_label(pm, W, H, 8, 34, label);
    printf("%s: of %d samples %d in the sun's cone, %d blocked by the scene, %d below the ground, %d reach the sky\n",
           panel == 0 ? "before (el_envlight_sample_li)" : "after (the sun cache's mixture)", ns, nsun, nblock, nbelow, nsky);
  }
  make_parent_dir(out);
  if (el_image_write_png(out, pix, W, 2 * H, 3, err, sizeof err) != 0) { fprintf(stderr, "%s\n", err); return 1; }
  printf("wrote %s\n", out);
  free(pix);
  elr_sun_free(S);
  elr_scene_free(s);
  return 0;
}

/* ---- one shadowed point, the library alone: which density pays in a shadow ----
 * A ground point (normal up, light space of sunrise.hdr) behind a wall: the directions within 57 degrees of
 * the sun's azimuth and below 34 degrees of elevation are blocked (WALL), or only those within 3 degrees
 * of the sun (CONE: a small object). Variance per camera sample of E = integral of L max(0, n.w) V over
 * 2^18 camera samples, for the light sample alone and for the light sample with a cosine BSDF sample
 * (the power heuristic), each density: sample_li, sample_li_cos, the mixture with the spot at 3%
 * (sample_li_mix) and the rest x cosine mixture (sample_li_mix_cos). */
static float g_ax[3];
static int g_cone;
static int vis(const float *w) {
  double el = asin(w[2]), a = atan2(w[1], w[0]) - atan2(g_ax[1], g_ax[0]);
  if (g_cone) return w[0] * g_ax[0] + w[1] * g_ax[1] + w[2] * g_ax[2] < cos(3.0 * M_PI / 180);
  while (a > M_PI) a -= 2 * M_PI;
  while (a < -M_PI) a += 2 * M_PI;
  return !(fabs(a) < 1.0 && el < 0.6);
}
static int shadow_point(void) {
  el_image img;
  el_envlight l;
  el_envlight_hotspots h;
  el_envlight_mix_weights w;
  char err[256];
  const float n[3] = {0, 0, 1};
  static const char *name[4] = {"sample_li", "sample_li_cos", "sample_li_mix (sun 3%)", "sample_li_mix_cos (sun 3%)"};
  int which, bsdf, i, N = 1 << 18;
  if (el_image_load(EL_SOURCE_DIR "/data/envmaps/sunrise.hdr", &img, err, sizeof err) != 0) { fprintf(stderr, "%s\n", err); return 1; }
  if (el_envlight_init(&l, img.pixels, img.width, img.height, 3, NULL) != EL_SUCCESS || el_envlight_hotspots_init(&h, &l, NULL) != EL_SUCCESS || h.count != 1) return 1;
  memcpy(g_ax, h.spot[0].axis, sizeof g_ax);
  memset(&w, 0, sizeof w);
  w.spot[0] = 0.03f * h.rest_share / 0.97f; w.rest = h.rest_share;
  for (g_cone = 0; g_cone < 2; g_cone++) {
    printf("%s: variance per camera sample, light sample alone | with a cosine BSDF sample (MIS)\n",
           g_cone ? "CONE (the sun hidden by a small object)" : "WALL (the sun and the low sky behind a wall hidden)");
    for (which = 0; which < 4; which++) {
      double v[2];
      for (bsdf = 0; bsdf < 2; bsdf++) {
        double s1 = 0, s2 = 0;
        g_rng.s = 88172645463325252ULL;
        for (i = 0; i < N; i++) {
          float u[2], u2[2], wi[3], L[3], pdf, d[3], Lb[3];
          double f = 0, pc, pl, pb, mis;
          u[0] = frand(); u[1] = frand(); u2[0] = frand(); u2[1] = frand();
          if (which == 0) el_envlight_sample_li(&l, u, wi, L, &pdf);
          else if (which == 1) el_envlight_sample_li_cos(&l, n, u, wi, L, &pdf);
          else if (which == 2) el_envlight_sample_li_mix(&l, &h, &w, u, wi, L, &pdf);
          else el_envlight_sample_li_mix_cos(&l, &h, &w, n, u, wi, L, &pdf);
          pc = wi[2] > 0 ? wi[2] / M_PI : 0;
          mis = bsdf ? (double)pdf * pdf / ((double)pdf * pdf + pc * pc) : 1.0;
          if (pdf > 0 && wi[2] > 0 && vis(wi)) f += L[1] * wi[2] / M_PI / pdf * mis;
          if (bsdf) {
            double r = sqrt(u2[0]), ph = 2 * M_PI * u2[1];
            d[0] = (float)(r * cos(ph)); d[1] = (float)(r * sin(ph)); d[2] = (float)sqrt(1 - u2[0]);
            pb = d[2] / M_PI;
            pl = which == 0 ? el_envlight_pdf_li(&l, d) : which == 1 ? el_envlight_pdf_li_cos(&l, n, d)
                 : which == 2 ? el_envlight_pdf_li_mix(&l, &h, &w, d) : el_envlight_pdf_li_mix_cos(&l, &h, &w, n, d);
            if (vis(d) && pb > 0) { el_envlight_le(&l, d, Lb); f += Lb[1] * d[2] / M_PI / pb * (pb * pb / (pb * pb + pl * pl)); }
          }
          s1 += f; s2 += f * f;
        }
        s1 /= N;
        v[bsdf] = s2 / N - s1 * s1;
      }
      printf("  %-28s %.3g | %.3g\n", name[which], v[0], v[1]);
    }
  }
  el_envlight_hotspots_free(&h);
  el_envlight_free(&l);
  el_image_free(&img);
  return 0;
}

/* ---- one lit point, the library alone: --sun split's estimator against the default's (issue 22) ----
 * The ground point of --shadow-point (normal up, sunrise.hdr) with nothing in the way. Variance per camera
 * sample over 2^18 independent camera samples of: the default (a product sample, sample_li_cos, and a cosine
 * BSDF sample, the power heuristic) and --sun split's (a spot sample: the map's density, sample_li, kept inside
 * the spot's cone, widened as sun.c does, from le()'s patches (importance BILINEAR) or the piecewise-constant
 * bins (pbrt-v3's); a sky sample, the rest x cosine; the BSDF sample; the power heuristic over the three), and
 * each term's share: the sun's cone (the spot and the BSDF sample there) and the rest. Last, what a spot sampler
 * over le()'s patches would give (not in the library): the patches renormalised to the cone, drawn by rejection,
 * their probability of the cone estimated from 2^22 draws (a diagnostic: its error, 2e-4, biases the mean); and
 * that sampler as the library now has it, exact: el_envlight_sample_li_spot (le()'s patches renormalised to a
 * rectangle of patches around the cone, the hot spots of the BILINEAR light itself); last, that spot sampler with the
 * sky drawn by product sampling over the patches (sample_li_cos, the sun included) instead of the rest x cosine. */
static int lit_point(const char *map) { /* map: an .hdr under data/envmaps (sunrise by default) */
  el_image img;
  el_envlight lp, lb;
  el_envlight_options o;
  el_envlight_hotspots h, hb;
  el_envlight_mix_weights wr;
  char err[256];
  const float n[3] = {0, 0, 1};
  int way, i, N = 1 << 18;
  float ch;
  double pcone;
  char path[512];
  snprintf(path, sizeof path, "%s/data/envmaps/%s.hdr", EL_SOURCE_DIR, map);
  if (el_image_load(path, &img, err, sizeof err) != 0) { fprintf(stderr, "%s\n", err); return 1; }
  memset(&o, 0, sizeof o);
  o.importance = EL_ENVLIGHT_IMPORTANCE_PBRT_V3;
  if (el_envlight_init(&lp, img.pixels, img.width, img.height, 3, &o) != EL_SUCCESS || el_envlight_hotspots_init(&h, &lp, NULL) != EL_SUCCESS || h.count != 1) return 1;
  o.importance = EL_ENVLIGHT_IMPORTANCE_BILINEAR;
  if (el_envlight_init(&lb, img.pixels, img.width, img.height, 3, &o) != EL_SUCCESS || el_envlight_hotspots_init(&hb, &lb, NULL) != EL_SUCCESS || hb.count != 1) return 1;
  memset(&wr, 0, sizeof wr);
  wr.rest = 1.f;
  ch = cosf(1.1f * h.spot[0].half_angle + 1e-3f);
  { /* the patches' probability of the cone, for way 3 (2^22 draws: about 2e-4 relative) */
    int in = 0, M = 1 << 22;
    g_rng.s = 1234567ULL;
    for (i = 0; i < M; i++) {
      float u[2], wi[3], pdf;
      u[0] = frand(); u[1] = frand();
      el_envlight_sample_li(&lb, u, wi, NULL, &pdf);
      in += pdf > 0 && wi[0] * h.spot[0].axis[0] + wi[1] * h.spot[0].axis[1] + wi[2] * h.spot[0].axis[2] >= ch;
    }
    pcone = (double)in / M;
  }
  printf("LIT (%s.hdr, normal up, nothing in the way; the patches put %.3f in the cone): variance per camera sample [sun's cone | rest]\n", map, pcone);
  for (way = 0; way < 6; way++) {
    const el_envlight *ls = way == 1 || way >= 3 ? &lb : &lp;
    double s1 = 0, s2 = 0, c1[2] = {0, 0}, c2[2] = {0, 0};
    g_rng.s = 88172645463325252ULL;
    for (i = 0; i < N; i++) {
      float u[2], u2[2], u3[2], wi[3], L[3], pdf, d[3], Lb[3];
      double f = 0, fc[2] = {0, 0}, pb, po, pc;
      int t;
      u[0] = frand(); u[1] = frand(); u2[0] = frand(); u2[1] = frand(); u3[0] = frand(); u3[1] = frand();
      for (t = 0; t < (way ? 2 : 1); t++) { /* the light samples */
        int inc;
        if (way == 0) el_envlight_sample_li_cos(&lp, n, u, wi, L, &pdf);
        else if (t == 0 && way == 3) { /* (rejection until in the cone: the patches renormalised to it) */
          float uu[2];
          int k;
          uu[0] = u[0]; uu[1] = u[1];
          for (k = 0; k < 1000; k++) {
            el_envlight_sample_li(ls, uu, wi, L, &pdf);
            if (wi[0] * h.spot[0].axis[0] + wi[1] * h.spot[0].axis[1] + wi[2] * h.spot[0].axis[2] >= ch) break;
            uu[0] = frand(); uu[1] = frand();
          }
          pdf = (float)(pdf / pcone);
        } else if (t == 0 && way >= 4) el_envlight_sample_li_spot(&lb, &hb, 0, u, wi, L, &pdf);
        else if (t == 1 && way == 5) el_envlight_sample_li_cos(&lb, n, u3, wi, L, &pdf); /* (the sky by product sampling: sun included) */
        else if (t == 0) { el_envlight_sample_li(ls, u, wi, L, &pdf); if (wi[0] * h.spot[0].axis[0] + wi[1] * h.spot[0].axis[1] + wi[2] * h.spot[0].axis[2] < ch) pdf = 0; }
        else el_envlight_sample_li_mix_cos(&lp, &h, &wr, n, u3, wi, L, &pdf);
        if (!(pdf > 0) || wi[2] <= 0) continue;
        inc = wi[0] * h.spot[0].axis[0] + wi[1] * h.spot[0].axis[1] + wi[2] * h.spot[0].axis[2] >= ch;
        pc = wi[2] / M_PI;
        po = way == 0 ? 0 : t == 0 ? (way == 5 ? el_envlight_pdf_li_cos(&lb, n, wi) : el_envlight_pdf_li_mix_cos(&lp, &h, &wr, n, wi)) : way >= 4 ? el_envlight_pdf_li_spot(&lb, &hb, 0, wi)
             : inc ? el_envlight_pdf_li(ls, wi) / (way == 3 ? pcone : 1.0) : 0;
        fc[!inc] += L[1] * wi[2] / M_PI / pdf * ((double)pdf * pdf / ((double)pdf * pdf + po * po + pc * pc));
      }
      { /* the BSDF sample */
        double r = sqrt(u2[0]), ph = 2 * M_PI * u2[1], pl;
        int inc;
        d[0] = (float)(r * cos(ph)); d[1] = (float)(r * sin(ph)); d[2] = (float)sqrt(1 - u2[0]);
        pb = d[2] / M_PI;
        inc = d[0] * h.spot[0].axis[0] + d[1] * h.spot[0].axis[1] + d[2] * h.spot[0].axis[2] >= ch;
        if (way == 0) pl = el_envlight_pdf_li_cos(&lp, n, d);
        else { double a = way == 5 ? el_envlight_pdf_li_cos(&lb, n, d) : el_envlight_pdf_li_mix_cos(&lp, &h, &wr, n, d), b = way >= 4 ? el_envlight_pdf_li_spot(&lb, &hb, 0, d) : inc ? el_envlight_pdf_li(ls, d) / (way == 3 ? pcone : 1.0) : 0; pl = sqrt(a * a + b * b); }
        if (pb > 0) { el_envlight_le(&lp, d, Lb); fc[!inc] += Lb[1] * d[2] / M_PI / pb * (pb * pb / (pb * pb + pl * pl)); }
      }
      f = fc[0] + fc[1];
      s1 += f; s2 += f * f;
      for (t = 0; t < 2; t++) { c1[t] += fc[t]; c2[t] += fc[t] * fc[t]; }
    }
    printf("  %-58s mean %.5g  variance %.4g [%.4g | %.4g]\n",
           way == 0 ? "default: sample_li_cos + BSDF" : way == 1 ? "split: the patches in the cone + rest x cosine + BSDF"
           : way == 2 ? "split: the bins in the cone + rest x cosine + BSDF" : way == 3 ? "split: the patches renormalised to the cone (rejection) + ..."
           : way == 4 ? "split: sample_li_spot (the patches' rectangle) + ..." : "sample_li_spot + product sampling (patches x cos) + BSDF",
           s1 / N, s2 / N - (s1 / N) * (s1 / N), c2[0] / N - (c1[0] / N) * (c1[0] / N), c2[1] / N - (c1[1] / N) * (c1[1] / N));
  }
  el_envlight_hotspots_free(&h); el_envlight_hotspots_free(&hb);
  el_envlight_free(&lp); el_envlight_free(&lb);
  el_image_free(&img);
  return 0;
}

#define CPU_ROUNDS 5
int main(int argc, char **argv) {
  if (argc > 1 && !strcmp(argv[1], "--shadow-point")) return shadow_point();
  if (argc > 1 && !strcmp(argv[1], "--lit-point")) return lit_point(argc > 2 ? argv[2] : "sunrise");
  if (argc > 1 && !strcmp(argv[1], "--picture")) return picture(argc > 2 ? argv[2] : "out/03-sun-samples.png");
  static const char *defaults[3] = {"scenes/sun_shadow_object.pbrt", "scenes/sun_porch.pbrt", "scenes/bench_city.pbrt"};
  int csv = argc > 1 && !strcmp(argv[1], "--csv"), cmp = 1; /* cmp: the env_sun compared with off (1 on, 2 split) */
  if (csv) { argc--; argv++; }
  for (;;) { /* --split: --sun split instead of on; --loop-one: every render in the one-sample loop */
    if (argc > 1 && !strcmp(argv[1], "--split")) cmp = 2;
    else if (argc > 1 && !strcmp(argv[1], "--loop-one")) sm_loop = ELR_LOOP_ONE;
    else if (argc > 1 && !strcmp(argv[1], "--pbrt-v3")) sm_importance = EL_ENVLIGHT_IMPORTANCE_PBRT_V3;
    else if (argc > 1 && !strcmp(argv[1], "--random")) sm_sampler = ELR_SAMPLER_RANDOM;
    else break;
    argc--; argv++;
  }
  {
  int spp = argc > 1 ? atoi(argv[1]) : 16, ns = argc > 2 ? atoi(argv[2]) : 16, nt = argc > 3 ? atoi(argv[3]) : 2;
  const char **scenes = argc > 4 ? (const char **)(argv + 4) : defaults;
  int nsc = argc > 4 ? argc - 4 : 3, i, c;
  if (spp < 1 || ns < 2 || ns > 1024 || nt < 1) { fprintf(stderr, "usage: bench_sun_render [SPP [SEEDS>=2 [THREADS [SCENE ...]]]]\n"); return 1; }
  if (csv) printf("kind,option,scene,class,spp,pixels,mean,variance,cpu_s\n");
  else printf("bench_sun_render: %d spp, %d seeds, %d threads\n", spp, ns, nt);
  for (i = 0; i < nsc; i++) {
    elr_scene *s = NULL;
    char err[512];
    unsigned char *cls;
    sm_result off, on;
    elr_image im;
    elr_render_options o;
    int w, h;
    double toff, ton;
    if (elr_scene_load(scenes[i], &s, 1, err, sizeof err) != 0) { printf("%s: %s\n", scenes[i], err); return 1; }
    elr_render_options_default(&o);
    o.spp = 1; o.quiet = 1; o.nthreads = nt;
    if (elr_render(s, &o, &im, NULL, err, sizeof err) != 0) { printf("%s: %s\n", scenes[i], err); return 1; }
    elr_image_free(&im);
    if (getenv("SUN_CLASSES_FROM")) { /* (classes from another scene of the same geometry: e.g. its map without the sun) */
      elr_scene *c2 = NULL;
      if (elr_scene_load(getenv("SUN_CLASSES_FROM"), &c2, 1, err, sizeof err) != 0 || elr_render(c2, &o, &im, NULL, err, sizeof err) != 0) {
        printf("%s\n", err); return 1;
      }
      elr_image_free(&im);
      cls = sm_classes(c2, &w, &h);
      elr_scene_free(c2);
    } else
      cls = sm_classes(s, &w, &h);
    if (!cls) { printf("%s: no hot spot\n", scenes[i]); elr_scene_free(s); continue; }
    if (sm_run(s, spp, ns, 0, nt, cls, w, h, &off) || sm_run(s, spp, ns, cmp, nt, cls, w, h, &on)) return 1;
    toff = off.cpu / ns; ton = on.cpu / ns + on.st.t_sun_cpu;
    { /* the CPU per render for the equal-time columns: the best of CPU_ROUNDS interleaved rounds (off, on; the
       * render loop, plus the pilot for on), since the runs above take every off render, then every on one,
       * and a shared machine's load drifts between them (issue 22: their ratio moved by 10-20%) */
      int r, mode;
      toff = ton = 1e30;
      for (r = 0; r < CPU_ROUNDS; r++)
        for (mode = 0; mode < 2; mode++) {
          elr_stats st;
          double t;
          o.spp = spp; o.seed = 1000; o.env_sun = mode ? cmp : 0; o.loop = sm_loop; o.importance = sm_importance;
          if (sm_sampler >= 0) o.sampler = sm_sampler;
          if (elr_render(s, &o, &im, &st, err, sizeof err) != 0) { printf("%s: %s\n", scenes[i], err); return 1; }
          elr_image_free(&im);
          t = st.t_render_cpu + (mode ? st.t_sun_cpu : 0.0);
          if (mode) ton = t < ton ? t : ton; else toff = t < toff ? t : toff;
        }
    }
    if (csv) {
      for (c = 1; c <= 2; c++) {
        printf("sun_cache,off,%s,%s,%d,%d,%.6g,%.6g,%.4f\n", scenes[i], c == 1 ? "shadowed" : "lit", spp, off.n[c], off.mean[c], off.var[c], toff);
        printf("sun_cache,%s,%s,%s,%d,%d,%.6g,%.6g,%.4f\n", cmp == 2 ? "split" : "on", scenes[i], c == 1 ? "shadowed" : "lit", spp, on.n[c], on.mean[c], on.var[c], ton);
      }
      sm_free(&off); sm_free(&on); free(cls);
      elr_scene_free(s);
      continue;
    }
    if (cmp == 2)
      printf("%s (%dx%d, %s): cpu per render off %.3f s, split %.3f s (tables %.3f s CPU); %llu vertices split, %llu of them the sky "
             "alone (\"on\" below: split)\n", scenes[i], w, h, on.st.integrator_path ? "path" : "directlighting", toff, ton, on.st.t_sun_cpu,
             (unsigned long long)on.st.sunsplit_vertices, (unsigned long long)on.st.sunsplit_sky_only);
    else
    printf("%s (%dx%d, %s): cpu per render off %.3f s, on %.3f s (pilot %.3f s CPU); %.1f%% of the sun's light samples at lowered "
           "vertices, %.1f%% in a spot's cone (off: see --stats)\n",
           scenes[i], w, h, on.st.integrator_path ? "path" : "directlighting", toff, ton, on.st.t_sun_cpu,
           on.st.sun_looked ? 100.0 * (double)on.st.sun_lowered / (double)on.st.sun_looked : 0.0,
           on.st.sun_looked ? 100.0 * (double)on.st.sun_to_spot / (double)on.st.sun_looked : 0.0);
    for (c = 1; c <= 2; c++) {
      double g = on.var[c] > 0 ? off.var[c] / on.var[c] : 0;
      printf("  %-8s %6d px  mean off %.5g on %.5g (z %+.2f)  variance off %.4g on %.4g: %.2fx less at equal spp, %.2fx at equal time;"
             " median pixel's variance %.2fx less\n",
             c == 1 ? "shadowed" : "lit", on.n[c], off.mean[c], on.mean[c], sm_z(&on, &off, cls, w * h, c, ns), off.var[c], on.var[c], g,
             g * toff / ton, on.med[c] > 0 ? off.med[c] / on.med[c] : 0.0);
    }
    { /* the whole image: the mean over all its pixels of the variance over the seeds */
      double va = 0, vb = 0;
      int p;
      for (p = 0; p < w * h; p++) { va += off.v[p]; vb += on.v[p]; }
      printf("  all pixels: z %+.2f  variance off %.4g on %.4g: %.2fx less at equal spp, %.2fx at equal time\n", sm_z(&on, &off, cls, w * h, -1, ns),
             va / (w * h), vb / (w * h), vb > 0 ? va / vb : 0.0, vb > 0 ? va / vb * toff / ton : 0.0);
    }
    if (getenv("SUN_DUMP")) { /* (the per-pixel variance, off then on, side by side: sqrt scaled to the off image's 99th percentile... its max) */
      elr_image v;
      double mx = 0;
      int p2, x, y;
      char path[600];
      v.width = 2 * w; v.height = h; v.rgb = (float *)calloc((size_t)6 * (size_t)w * (size_t)h, sizeof(float));
      for (p2 = 0; p2 < w * h; p2++) if (cls[p2] == 1 && sqrt(off.v[p2]) > mx) mx = sqrt(off.v[p2]);
      for (y = 0; y < h; y++) for (x = 0; x < w; x++) {
        float a0 = (float)(sqrt(off.v[y * w + x]) / mx), a1 = (float)(sqrt(on.v[y * w + x]) / mx);
        float *q0 = &v.rgb[3 * (y * 2 * w + x)], *q1 = &v.rgb[3 * (y * 2 * w + w + x)];
        q0[0] = q0[1] = q0[2] = a0; q1[0] = q1[1] = q1[2] = a1;
        if (cls[y * w + x] == 1) { q0[0] *= 0.6f; q1[0] *= 0.6f; }
      }
      if (getenv("SUN_RATIO")) /* (instead: log2 of the variance ratio off / on, 3x3 box-averaged variances; green > 0, red < 0, 1 = 4x) */
        for (y = 0; y < h; y++) for (x = 0; x < w; x++) {
          double a0 = 0, a1 = 0, r;
          int dx, dy;
          float *q0 = &v.rgb[3 * (y * 2 * w + x)];
          for (dy = -1; dy <= 1; dy++) for (dx = -1; dx <= 1; dx++) {
            int xx = x + dx < 0 ? 0 : x + dx >= w ? w - 1 : x + dx, yy = y + dy < 0 ? 0 : y + dy >= h ? h - 1 : y + dy;
            a0 += off.v[yy * w + xx]; a1 += on.v[yy * w + xx];
          }
          r = a1 > 0 && a0 > 0 ? log2(a0 / a1) / 2 : 0;
          q0[0] = r < 0 ? (float)-r : 0.f; q0[1] = r > 0 ? (float)r : 0.f; q0[2] = cls[y * w + x] == 1 ? 0.3f : 0.f;
        }
      snprintf(path, sizeof path, "%s_%d.png", getenv("SUN_DUMP"), i);
      elr_image_write(&v, path, err, sizeof err);
      free(v.rgb);
    }
    sm_free(&off); sm_free(&on); free(cls);
    elr_scene_free(s);
  }
  }
  return 0;
}
