/* 04_tone_mapping.c: chapter 4 of the course, the film and tone mapping (tutorials/04-tone-mapping.md).
 *
 * NEEDS_EL_RENDER: this marker makes examples/CMakeLists.txt link the renderer of examples/render.
 *
 * WHAT IT DEMONSTRATES, in the chapter's steps
 *   1. pbrt-v3's film path as the course ports it (examples/pbrtv3/film.h: FilmTile::AddSample with
 *      the 16 x 16 filter table, MergeFilmTile's XYZ, WriteImage, TO_BYTE) beside film.h, on the same
 *      camera samples: a zone plate (rings finer and finer towards the corners), 16 random samples per
 *      pixel, through pbrt's default box filter and through the Mitchell filter. It prints how far the
 *      two films' pixels are apart and what each costs. Picture: the two filtered zone plates.
 *   2. The seed's comparison (its section 4.4): the demo scene (scenes/envlight_demo.pbrt) rendered by
 *      examples/render with direct lighting and with path tracing, one frame (one sample per pixel)
 *      each, written through the seed's HDRtoLDR and through pbrt's TO_BYTE, the seed's way (RGB to
 *      XYZ to RGB, then TO_BYTE). Picture: the 2 x 2 comparison.
 *   3. film.h's tone curves (pbrt's clamp, the exponential, Reinhard, ACES) on the same scene, path
 *      traced at 64 samples per pixel so that noise does not hide the curves. Picture: 2 x 2.
 *
 * WHICH PART OF PBRT IT MIRRORS
 *   pbrt-v3 src/core/film.{h,cpp} (book 7.9 "Film and the Imaging Pipeline"), src/filters/ (7.8
 *   "Image Reconstruction"), src/core/spectrum.h (RGBToXYZ, XYZToRGB), src/core/imageio.cpp (TO_BYTE
 *   with GammaCorrect). The renders use examples/render, a pbrt-v3 scene renderer on Embree whose film
 *   is film.h.
 *
 * HOW TO RUN IT
 *   build/bin/04_tone_mapping [--quick | --answers] [--out DIR]
 *     (nothing)   every step, with the pictures (under a minute on two cores)
 *     --quick     step 1's numbers only (a few seconds)
 *     --answers   the numbers the chapter's exercises ask for
 *     --out DIR   where the pictures go (default out/; the course's copies are in tutorials/images)
 *     --help      the usage (exit 0)
 *
 * WHAT IT WRITES
 *   DIR/04-filters.png, DIR/04-seed-comparison.png, DIR/04-tone-curves.png; each step's numbers.
 */
#define _POSIX_C_SOURCE 200809L /* clock_gettime, mkdir under -std=c99 */
/* no EL_FILM_IMPLEMENTATION here: the renderer library (examples/render/envlight_impl.c) compiles it */
#include "film.h"
#include "canvas.h"           /* examples/common: page composition */
#include "el_render.h"        /* examples/render: the scene renderer */
#include "image_io.h"         /* examples/common: PNG writing */
#include "picture.h"          /* examples/common: labels */
#include "pbrtv3/film.h"      /* the port */

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

#ifndef EL_SOURCE_DIR
#define EL_SOURCE_DIR "."
#endif

static double cpu_now(void) { /* this thread's CPU seconds: steady on a busy machine */
  struct timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}
static void make_dir(const char *dir) {
  if (mkdir(dir, 0777) != 0 && errno != EEXIST) fprintf(stderr, "04_tone_mapping: cannot create %s\n", dir);
}
static int write_page(const char *dir, const char *name, const unsigned char *page, int w, int h) {
  char path[1024], err[512];
  snprintf(path, sizeof path, "%s/%s", dir, name);
  if (el_image_write_png(path, page, w, h, 3, err, sizeof err) != 0) {
    fprintf(stderr, "04_tone_mapping: %s\n", err);
    return -1;
  }
  printf("        wrote %s\n", path);
  return 0;
}

/* ---- step 1: the same samples through pbrt's film and through film.h ------------------------------ */
/* the zone plate 0.5 + 0.5 cos(pi r^2 / (0.6 ZP)), r in pixels from the centre: its rings are as fine
 * as a pixel (the Nyquist limit) at r = 0.3 ZP = 77 pixels, finer beyond */
enum { ZP = 256, SPP = 16 };
static float zone_plate(float x, float y) {
  double dx = x - ZP / 2.0, dy = y - ZP / 2.0;
  return (float)(0.5 + 0.5 * cos(3.14159265358979323846 * (dx * dx + dy * dy) / (0.6 * ZP)));
}
static unsigned g_rng = 1u;
static float frand(void) {
  g_rng = g_rng * 1664525u + 1013904223u;
  return (float)(g_rng >> 8) * (1.0f / 16777216.0f);
}

/* One filter: the samples of every pixel of the sample bounds (the film grown by the filter's radius,
 * pbrt's GetSampleBounds), through both films. Prints the comparison; writes film.h's 8-bit plate. */
static int compare_films(int pbrt_type, el_film_filter_type el_type, const char *name, unsigned char *out8) {
  float *smp = NULL, *rgb_p = (float *)malloc(sizeof(float) * 3 * ZP * ZP), *rgb_l = (float *)malloc(sizeof(float) * 3 * ZP * ZP);
  unsigned char *p8 = (unsigned char *)malloc(3 * ZP * ZP);
  pbrt_Filter filter = pbrt_MakeFilter(pbrt_type, 0, 0); /* pbrt's defaults for the type */
  pbrt_Film pf;
  pbrt_FilmTile tile;
  el_film film;
  el_film_options fo;
  int b[4], x, y, s, differ = 0, status = -1;
  size_t n = 0, k;
  double t_pbrt, t_lib, worst = 0;
  memset(&fo, 0, sizeof fo);
  fo.width = fo.height = ZP;
  fo.filter.type = el_type; /* all other filter fields zero: pbrt's defaults */
  if (!rgb_p || !rgb_l || !p8 || pbrt_Film_init(&pf, ZP, ZP, &filter, 1, INFINITY) != 0) goto out;
  if (el_film_init(&film, &fo) != EL_SUCCESS) { pbrt_Film_free(&pf); goto out; }
  el_film_sample_bounds(&film, b);
  smp = (float *)malloc(sizeof(float) * 3 * (size_t)(b[2] - b[0]) * (size_t)(b[3] - b[1]) * SPP);
  if (!smp || pbrt_Film_GetFilmTile(&pf, b, &tile) != 0) { free(smp); smp = NULL; el_film_free(&film); pbrt_Film_free(&pf); goto out; }
  g_rng = 1u;
  for (y = b[1]; y < b[3]; y++) /* the camera samples: a raster position and its radiance */
    for (x = b[0]; x < b[2]; x++)
      for (s = 0; s < SPP; s++, n++) {
        smp[3 * n] = (float)x + frand();
        smp[3 * n + 1] = (float)y + frand();
        smp[3 * n + 2] = zone_plate(smp[3 * n], smp[3 * n + 1]);
      }
  t_pbrt = cpu_now();
  for (k = 0; k < n; k++) {
    float L[3];
    L[0] = L[1] = L[2] = smp[3 * k + 2];
    pbrt_FilmTile_AddSample(&tile, smp + 3 * k, L, 1.0f);
  }
  pbrt_Film_MergeFilmTile(&pf, &tile);
  t_pbrt = cpu_now() - t_pbrt;
  t_lib = cpu_now();
  for (k = 0; k < n; k++) {
    float L[3];
    L[0] = L[1] = L[2] = smp[3 * k + 2];
    el_film_add_sample(&film, smp[3 * k], smp[3 * k + 1], L, 1.0f);
  }
  t_lib = cpu_now() - t_lib;
  pbrt_Film_WriteImage(&pf, 0, rgb_p);
  pbrt_WriteImage8(rgb_p, ZP, ZP, p8);
  el_film_get_rgb(&film, 0, rgb_l);
  el_film_to_srgb8(rgb_l, ZP, ZP, NULL, out8); /* NULL: pbrt's clamp, the exact sRGB curve, rounding */
  for (k = 0; k < 3 * ZP * ZP; k++) {
    worst = fmax(worst, fabs((double)rgb_p[k] - rgb_l[k]));
    differ += p8[k] != out8[k];
  }
  printf("        %-8s pixels differ by at most %.2g; 8-bit codes differ in %d of %d\n", name, worst, differ, 3 * ZP * ZP);
  printf("        %-8s AddSample: port %.1f ns, film.h %.1f ns per sample   [CPU time, this run]\n", name, 1e9 * t_pbrt / (double)n,
         1e9 * t_lib / (double)n);
  pbrt_FilmTile_free(&tile);
  pbrt_Film_free(&pf);
  el_film_free(&film);
  status = 0;
out:
  free(smp);
  free(rgb_p);
  free(rgb_l);
  free(p8);
  return status;
}

/* ---- steps 2 and 3: renders of the demo scene ----------------------------------------------------- */
enum { RW = 480, RH = 300 };
/* The demo scene with its Integrator line replaced by `integrator` and a RW x RH film, rendered at spp
 * samples per pixel: linear RGB (film.h's output: finite, >= 0). */
static float *render_demo(const char *integrator, int spp, double *seconds) {
  char path[1024], err[512], *text, *out;
  const char *line;
  FILE *f;
  long size;
  elr_scene *s = NULL;
  elr_render_options o;
  elr_image img;
  elr_stats st;
  snprintf(path, sizeof path, "%s/scenes/envlight_demo.pbrt", EL_SOURCE_DIR);
  f = fopen(path, "rb");
  if (!f) { fprintf(stderr, "04_tone_mapping: cannot open %s\n", path); return NULL; }
  fseek(f, 0, SEEK_END);
  size = ftell(f);
  fseek(f, 0, SEEK_SET);
  text = (char *)malloc((size_t)size + 1);
  out = (char *)malloc((size_t)size + 512);
  if (!text || !out || fread(text, 1, (size_t)size, f) != (size_t)size) { fclose(f); free(text); free(out); return NULL; }
  fclose(f);
  text[size] = 0;
  /* the scene text with our Film and Integrator lines in place of its own */
  out[0] = 0;
  for (line = text; *line;) {
    const char *e = strchr(line, '\n');
    size_t len = e ? (size_t)(e - line + 1) : strlen(line);
    if (!strncmp(line, "Film ", 5))
      sprintf(out + strlen(out), "Film \"image\" \"integer xresolution\" [ %d ] \"integer yresolution\" [ %d ]\n", RW, RH);
    else if (!strncmp(line, "    \"string filename\"", 21))
      ; /* the Film's second line */
    else if (!strncmp(line, "Integrator ", 11))
      sprintf(out + strlen(out), "Integrator \"%s\" \"integer maxdepth\" [ 5 ]\n", integrator);
    else
      strncat(out, line, len);
    line += len;
  }
  free(text);
  snprintf(path, sizeof path, "%s/scenes", EL_SOURCE_DIR);
  if (elr_scene_load_string(out, "envlight_demo.pbrt", path, &s, 1, err, sizeof err) != 0) {
    fprintf(stderr, "04_tone_mapping: %s\n", err);
    free(out);
    return NULL;
  }
  free(out);
  elr_render_options_default(&o);
  o.spp = spp;
  o.nthreads = 2;
  o.quiet = 1;
  o.seed = 1;
  if (elr_render(s, &o, &img, &st, err, sizeof err) != 0) {
    fprintf(stderr, "04_tone_mapping: %s\n", err);
    elr_scene_free(s);
    return NULL;
  }
  *seconds = st.t_render;
  elr_scene_free(s);
  return img.rgb; /* elr_image_free would free it: the caller frees it instead */
}

/* The seed's two ways to 8 bits: HDRtoLDR per channel, and its section 4.4 code (FromRGB, ToXYZ,
 * XYZToRGB, TO_BYTE). */
static void seed_hdr_to_ldr(const float *rgb, unsigned char *out) {
  int i;
  for (i = 0; i < 3 * RW * RH; i++) out[i] = pbrt_seed_HDRtoLDR(rgb[i]);
}
static void seed_to_byte(const float *rgb, unsigned char *out) {
  int offset;
  for (offset = 0; offset < 3 * RW * RH; offset += 3) {
    float xyz[3], c[3];
    pbrt_RGBToXYZ(rgb + offset, xyz); /* Spectrum colorA = Spectrum::FromRGB(buffer_f + offset); colorA.ToXYZ(xyz) */
    pbrt_XYZToRGB(xyz, c);
    out[offset + 0] = TO_BYTE(c[0]);
    out[offset + 1] = TO_BYTE(c[1]);
    out[offset + 2] = TO_BYTE(c[2]);
  }
}

/* ---- the exercises' numbers ------------------------------------------------------------------------ */
static void answers(void) {
  static const float x[7] = {0.01f, 0.05f, 0.18f, 0.5f, 1.0f, 2.0f, 4.0f};
  float s = 1.0f, v[3], xyz[3], back[3], dev = 0, seed = 0, cross[2];
  int i, j, frame;
  printf("answer 1: linear  HDRtoLDR (seed)  TO_BYTE (pbrt)  film.h EXPONENTIAL k=4\n");
  for (i = 0; i < 7; i++) {
    el_film_output_options o;
    unsigned char c[3];
    float rgb[3];
    memset(&o, 0, sizeof o);
    o.tonemap = EL_FILM_TONEMAP_EXPONENTIAL;
    o.exp_k = 4;
    rgb[0] = rgb[1] = rgb[2] = x[i];
    el_film_to_srgb8(rgb, 1, 1, &o, c);
    printf("          %6.2f  %14d  %14d  %22d\n", x[i], pbrt_seed_HDRtoLDR(x[i]), TO_BYTE(x[i]), c[0]);
  }
  for (j = 0; j < 2; j++) { /* where the two curves cross: bisection on [0.001, 0.5] and [0.5, 1] */
    float lo = j ? 0.5f : 0.001f, hi = j ? 1.0f : 0.5f;
    for (i = 0; i < 40; i++) {
      float m = 0.5f * (lo + hi);
      if ((1 - expf(-4 * m) > pbrt_GammaCorrect(m)) == (j == 0)) hi = m;
      else lo = m;
    }
    cross[j] = lo;
  }
  printf("          the curves cross at x = %.3f and x = %.3f: HDRtoLDR is darker below the first and above the second\n",
         cross[0], cross[1]);
  for (j = 0; j < 3; j++) { /* 2. the XYZ round trip on the unit vectors */
    v[0] = v[1] = v[2] = 0;
    v[j] = 1;
    pbrt_RGBToXYZ(v, xyz);
    pbrt_XYZToRGB(xyz, back);
    for (i = 0; i < 3; i++) dev = fmaxf(dev, fabsf(back[i] - v[i]));
  }
  /* the last digits depend on the compiler: clang fuses a * b + c (-ffp-contract=on) where gcc -O3 without
   * -march does not, so the quoted line is the bound and the value follows on its own line */
  if (dev < 1e-6f) printf("answer 2: XYZToRGB(RGBToXYZ(e_i)) differs from e_i by less than 1e-06\n");
  else printf("answer 2: XYZToRGB(RGBToXYZ(e_i)) differs from e_i by %.2g\n", dev);
  printf("          (by %.2g in this build)\n", dev);
  while (s + 1e-3f != s) s *= 2; /* 3. the float sum that no longer moves */
  printf("answer 3: adding 1e-3 to a float sum changes nothing once the sum reaches %.0f\n", s);
  printf("answer 4: the seed's running average after a NaN frame:");
  for (frame = 1; frame <= 4; frame++) { /* fbuffer = w dat + (1 - w) fbuffer, w = 1 / frame */
    float dat = frame == 2 ? (float)NAN : 0.5f, w = 1.0f / (float)frame;
    seed = w * dat + (1 - w) * seed;
    printf(" frame %d: %g%s", frame, seed, frame < 4 ? "," : "\n");
  }
}

int main(int argc, char **argv) {
  const char *dir = "out";
  int quick = 0, want_answers = 0, i, status = 1;
  for (i = 1; i < argc; i++) {
    if (!strcmp(argv[i], "--quick")) quick = 1;
    else if (!strcmp(argv[i], "--answers")) want_answers = 1;
    else if (!strcmp(argv[i], "--out") && i + 1 < argc) dir = argv[++i];
    else {
      int help = !strcmp(argv[i], "--help") || !strcmp(argv[i], "-h");
      fprintf(help ? stdout : stderr, "usage: 04_tone_mapping [--quick | --answers] [--out DIR]\n"
              "  (nothing)   every step, with the pictures\n"
              "  --quick     step 1's numbers only\n"
              "  --answers   the numbers the chapter's exercises ask for\n"
              "  --out DIR   where the pictures go (default out/)\n");
      return help ? 0 : 1;
    }
  }
  if (want_answers) {
    answers();
    return 0;
  }

  /* 1. pbrt's film and film.h, on the same samples */
  {
    unsigned char *box = (unsigned char *)malloc(3 * ZP * ZP), *mit = (unsigned char *)malloc(3 * ZP * ZP), *page;
    printf("step 1: a %d x %d zone plate, %d random samples per pixel, through pbrt's film (the port) and film.h\n", ZP, ZP, SPP);
    if (!box || !mit || compare_films(pbrt_BoxFilter, EL_FILM_FILTER_BOX, "box", box) != 0 ||
        compare_films(pbrt_MitchellFilter, EL_FILM_FILTER_MITCHELL, "mitchell", mit) != 0) {
      fprintf(stderr, "04_tone_mapping: out of memory\n");
      free(box); free(mit);
      return 1;
    }
    if (!quick && (page = (unsigned char *)calloc((size_t)3 * 4 * ZP * 2 * ZP, 1)) != NULL) {
      make_dir(dir);
      el_canvas_blit(page, 4 * ZP, 2 * ZP, box, ZP, ZP, 0, 0, 2);
      el_canvas_blit(page, 4 * ZP, 2 * ZP, mit, ZP, ZP, 2 * ZP, 0, 2);
      el_draw_label(page, 4 * ZP, 2 * ZP, 4, 4, "BOX, RADIUS 0.5 (THE PBRT DEFAULT)");
      el_draw_label(page, 4 * ZP, 2 * ZP, 2 * ZP + 4, 4, "MITCHELL, RADIUS 2, B = C = 1/3");
      el_draw_label(page, 4 * ZP, 2 * ZP, 4, 2 * ZP - 26, "16 RANDOM SAMPLES PER PIXEL, SHOWN 2X");
      write_page(dir, "04-filters.png", page, 4 * ZP, 2 * ZP);
      free(page);
    }
    free(box);
    free(mit);
  }
  if (quick) return 0;

  /* 2. the seed's comparison: one frame of direct lighting and one of path tracing, two ways to 8 bits */
  {
    static const char *integrator[2] = {"directlighting", "path"};
    static const char *row[2] = {"DIRECT LIGHTING", "PATH TRACING"};
    unsigned char *page = (unsigned char *)calloc((size_t)3 * 2 * RW * 2 * RH, 1), *p8 = (unsigned char *)malloc(3 * RW * RH);
    char text[128];
    int r;
    make_dir(dir);
    printf("step 2: the seed's comparison: scenes/envlight_demo.pbrt, %d x %d, one sample per pixel\n", RW, RH);
    for (r = 0; r < 2 && page && p8; r++) {
      double t;
      float *rgb = render_demo(integrator[r], 1, &t);
      if (!rgb) { free(page); free(p8); return 1; }
      printf("        %s: %.2f s\n", integrator[r], t);
      seed_hdr_to_ldr(rgb, p8);
      el_canvas_blit(page, 2 * RW, 2 * RH, p8, RW, RH, 0, r * RH, 1);
      snprintf(text, sizeof text, "%s: HDRTOLDR", row[r]);
      el_draw_label(page, 2 * RW, 2 * RH, 4, r * RH + 4, text);
      seed_to_byte(rgb, p8);
      el_canvas_blit(page, 2 * RW, 2 * RH, p8, RW, RH, RW, r * RH, 1);
      snprintf(text, sizeof text, "%s: PBRT SRGB", row[r]);
      el_draw_label(page, 2 * RW, 2 * RH, RW + 4, r * RH + 4, text);
      free(rgb);
    }
    el_draw_label(page, 2 * RW, 2 * RH, 4, 2 * RH - 26, "ONE FRAME (1 SAMPLE PER PIXEL) EACH");
    el_draw_label(page, 2 * RW, 2 * RH, RW + 4, 2 * RH - 26, "1 - EXP(-4X) LEFT, SRGB RIGHT");
    write_page(dir, "04-seed-comparison.png", page, 2 * RW, 2 * RH);
    free(page);
    free(p8);
  }

  /* 3. film.h's curves on the path-traced scene */
  {
    static const el_film_tonemap curve[4] = {EL_FILM_TONEMAP_CLAMP, EL_FILM_TONEMAP_EXPONENTIAL, EL_FILM_TONEMAP_REINHARD,
                                             EL_FILM_TONEMAP_ACES};
    static const char *label[4] = {"CLAMP (PBRT)", "EXPONENTIAL K=4", "REINHARD X/(1+X)", "ACES (NARKOWICZ)"};
    unsigned char *page = (unsigned char *)calloc((size_t)3 * 2 * RW * 2 * RH, 1), *p8 = (unsigned char *)malloc(3 * RW * RH);
    double t;
    float *rgb = render_demo("path", 64, &t);
    int c;
    if (!rgb || !page || !p8) { free(rgb); free(page); free(p8); return 1; }
    printf("step 3: film.h's tone curves: the same scene path traced at 64 samples per pixel (%.1f s)\n", t);
    for (c = 0; c < 4; c++) {
      el_film_output_options o;
      memset(&o, 0, sizeof o); /* exposure 0: as the seed */
      o.tonemap = curve[c];
      o.exp_k = 4; /* the seed's k: 1 / (1 - 0.75) */
      el_film_to_srgb8(rgb, RW, RH, &o, p8);
      el_canvas_blit(page, 2 * RW, 2 * RH, p8, RW, RH, (c % 2) * RW, (c / 2) * RH, 1);
      el_draw_label(page, 2 * RW, 2 * RH, (c % 2) * RW + 4, (c / 2) * RH + 4, label[c]);
    }
    el_draw_label(page, 2 * RW, 2 * RH, 4, RH - 26, "PATH TRACING, 64 SPP, THEN SRGB");
    write_page(dir, "04-tone-curves.png", page, 2 * RW, 2 * RH);
    free(rgb);
    free(page);
    free(p8);
  }
  status = 0;
  return status;
}
