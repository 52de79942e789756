/* 04_tone_mapping.c: from linear radiance to 8-bit sRGB (chapter 4 of the tutorial, "tone mapping").
 *
 * WHAT IT DEMONSTRATES
 *   1. The tutorial's comparison. One linear HDR image (by default the CC0 environment map
 *      data/envmaps/city.hdr, whose sun is about 3e4 while the sky is near 1) goes through four curves,
 *      side by side in one labelled picture, all at the same exposure:
 *        - EXPONENTIAL: 1 - exp(-k x), the tutorial's earlier "HDRtoLDR", then sRGB;
 *        - CLAMP: pbrt's own output, values above 1 clip, then the exact sRGB curve (TO_BYTE);
 *        - REINHARD: x / (1 + x);
 *        - ACES: Narkowicz's rational fit of the ACES film curve.
 *      The exposure is chosen once, as Reinhard's "key": the log-average luminance maps to 0.18.
 *   2. What a pixel filter costs and buys. A zone plate (rings whose frequency grows with the radius, so
 *      the outer rings are finer than a pixel) is rendered with 16 random samples per pixel through
 *      film.h twice: with pbrt's default box filter (radius 0.5) and with the Mitchell filter (radius 2,
 *      B = C = 1/3). The box keeps the fine rings' aliases (false rings near the edges) and more noise;
 *      Mitchell fades them, at about twice the time per sample (30 against 55 ns on one run of the test
 *      machine; bench/bench_film.c counts 335 and 821 instructions). The times are printed and drawn.
 *
 * WHICH PART OF PBRT IT MIRRORS
 *   pbrt-v3 section 7.9 "Film and the Imaging Pipeline" (src/core/film.h, film.cpp): FilmTile::AddSample
 *   (<<Compute sample's raster bounds>>, <<Loop over filter support and add sample to pixel arrays>>),
 *   Film::WriteImage (<<Convert pixel XYZ color to RGB>>, <<Normalize pixel with weight sum>>, <<Add
 *   splat value at pixel>>, <<Scale pixel value by scale>>) and imageio.cpp's TO_BYTE with GammaCorrect;
 *   section 7.8 "Image Reconstruction" for the filters. All of it lives in film.h; this file calls it.
 *   The tutorial compares its own HDRtoLDR with pbrt's path in its section 4.4.
 *
 * HOW TO RUN IT
 *   build/bin/04_tone_mapping [input.hdr|.exr|.pfm] [out.png]
 *     input  default EL_SOURCE_DIR "/data/envmaps/city.hdr" (studio.hdr is the other copied map)
 *     out    default out/04_tone_mapping.png (the folder is created)
 *   tutorials/04-tone-mapping.md walks through it; bench/bench_film.c measures every filter.
 *
 * WHAT IT WRITES
 *   One PNG (1024 x 1056): the four tone mappers in a 2 x 2 grid, the two filtered zone plates below
 *   (shown at 2x so pixels are visible), each with its label; on stdout the path, the exposure and the
 *   time per filter.
 */
#define _POSIX_C_SOURCE 199309L /* clock_gettime, mkdir */
#define EL_FILM_IMPLEMENTATION
#include "film.h"
#include "image_io.h" /* examples/common: reading .hdr/.exr/.pfm, writing .png */
#include "picture.h"  /* examples/common: labels */

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


static double now(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

/* copies an RGB8 panel (pw x ph) into the page at (x0, y0), magnified by `mag` (nearest) */
static void blit(unsigned char *page, int w, const unsigned char *panel, int pw, int ph, int x0, int y0, int mag) {
  int x, y;
  for (y = 0; y < ph * mag; y++)
    for (x = 0; x < pw * mag; x++)
      memcpy(page + 3 * ((size_t)(y0 + y) * w + x0 + x), panel + 3 * ((size_t)(y / mag) * pw + x / mag), 3);
}

/* the zone plate: 0.5 + 0.5 cos(pi r^2 / R), r in pixels from the centre; its local frequency r / R
 * cycles per pixel reaches the Nyquist limit 0.5 at r = R / 2 = 77 pixels and 1.2 in the corners */
enum { ZP = 256 };
static float zone_plate(float x, float y) {
  double dx = x - ZP / 2.0, dy = y - ZP / 2.0;
  return (float)(0.5 + 0.5 * cos(3.14159265358979323846 * (dx * dx + dy * dy) / (0.6 * ZP)));
}

static unsigned g_rng = 1u;
static float frand(void) {
  g_rng = g_rng * 1664525u + 1013904223u;
  return (float)(g_rng >> 8) * (1.0f / 16777216.0f);
}

/* renders the zone plate with `spp` random samples per pixel through film.h; returns the seconds spent
 * in el_film_add_sample alone (the samples are drawn and the plate evaluated beforehand) */
static double render_zone_plate(el_film_filter_type type, int spp, unsigned char *out8) {
  el_film film;
  el_film_options fo;
  int b[4], x, y, s;
  size_t n = 0, k;
  double t0, t;
  float *rgb, *smp;
  memset(&fo, 0, sizeof fo);
  fo.width = ZP;
  fo.height = ZP;
  fo.filter.type = type; /* all other filter fields zero: pbrt's defaults */
  if (el_film_init(&film, &fo) != EL_SUCCESS) return -1;
  el_film_sample_bounds(&film, b); /* pbrt's GetSampleBounds: the image grown by the filter radius */
  smp = (float *)malloc(sizeof(float) * 3 * (size_t)(b[2] - b[0]) * (size_t)(b[3] - b[1]) * (size_t)spp);
  rgb = (float *)malloc(sizeof(float) * 3 * ZP * ZP);
  if (!smp || !rgb) { free(smp); free(rgb); el_film_free(&film); return -1; }
  g_rng = 1u;
  for (y = b[1]; y < b[3]; y++)
    for (x = b[0]; x < b[2]; x++)
      for (s = 0; s < spp; s++, n++) { /* a "camera sample" in raster space and its radiance */
        smp[3 * n] = x + frand();
        smp[3 * n + 1] = y + frand();
        smp[3 * n + 2] = zone_plate(smp[3 * n], smp[3 * n + 1]);
      }
  t0 = now();
  for (k = 0; k < n; k++) {
    float c[3];
    c[0] = c[1] = c[2] = smp[3 * k + 2];
    el_film_add_sample(&film, smp[3 * k], smp[3 * k + 1], c, 1.0f);
  }
  t = now() - t0;
  el_film_get_rgb(&film, 1.0f, rgb);
  el_film_to_srgb8(rgb, ZP, ZP, NULL, out8); /* NULL: pbrt's clamp + sRGB + round */
  free(smp);
  free(rgb);
  el_film_free(&film);
  return t;
}

int main(int argc, char **argv) {
  const char *in = argc > 1 ? argv[1] : EL_SOURCE_DIR "/data/envmaps/city.hdr";
  const char *out = argc > 2 ? argv[2] : "out/04_tone_mapping.png";
  char err[512], text[128];
  el_image env;
  enum { PW = 512, PH = 256, W = 2 * PW, H = 2 * PH + 32 + 2 * ZP };
  float *panel = NULL;
  unsigned char *page = NULL, *p8 = NULL;
  double logsum = 0, exposure, tbox, tmit;
  int x, y, c, i, spp = 16;
  static const el_film_tonemap maps[4] = {EL_FILM_TONEMAP_EXPONENTIAL, EL_FILM_TONEMAP_CLAMP, EL_FILM_TONEMAP_REINHARD, EL_FILM_TONEMAP_ACES};
  static const char *names[4] = {"EXPONENTIAL 1-EXP(-X)", "CLAMP (PBRT SRGB)", "REINHARD X/(1+X)", "ACES (NARKOWICZ FIT)"};

  if (el_image_load(in, &env, err, sizeof err) != 0) {
    fprintf(stderr, "04_tone_mapping: %s\n", err);
    return 1;
  }
  if (env.channels < 3) {
    fprintf(stderr, "04_tone_mapping: %s: need an RGB image, got %d channel(s)\n", in, env.channels);
    el_image_free(&env);
    return 1;
  }
  panel = (float *)malloc(sizeof(float) * 3 * PW * PH);
  page = (unsigned char *)calloc((size_t)W * H * 3, 1);
  p8 = (unsigned char *)malloc((size_t)3 * PW * PH);
  if (!panel || !page || !p8) { fprintf(stderr, "04_tone_mapping: out of memory\n"); return 1; }

  /* resample the input to the panel size by area averaging (nearest block of source pixels) */
  for (y = 0; y < PH; y++)
    for (x = 0; x < PW; x++) {
      int sx0 = x * env.width / PW, sx1 = (x + 1) * env.width / PW, sy0 = y * env.height / PH,
          sy1 = (y + 1) * env.height / PH, sx, sy, n = 0;
      double s[3] = {0, 0, 0};
      if (sx1 <= sx0) sx1 = sx0 + 1;
      if (sy1 <= sy0) sy1 = sy0 + 1;
      for (sy = sy0; sy < sy1; sy++)
        for (sx = sx0; sx < sx1; sx++, n++)
          for (c = 0; c < 3; c++) {
            float v = env.pixels[((size_t)sy * env.width + sx) * env.channels + c];
            if (env.is_8bit) v = el_film_srgb_decode(v); /* a PNG/JPEG holds sRGB codes: back to linear */
            s[c] += v == v && v > 0 ? v : 0; /* NaN and negative texels count as 0 */
          }
      for (c = 0; c < 3; c++) panel[3 * (y * PW + x) + c] = (float)(s[c] / n);
    }
  el_image_free(&env);

  /* the exposure: Reinhard's key, log-average luminance -> 0.18 (luminance from pbrt's Y row) */
  for (i = 0; i < PW * PH; i++) {
    double lum = 0.212671 * panel[3 * i] + 0.715160 * panel[3 * i + 1] + 0.072169 * panel[3 * i + 2];
    logsum += log(1e-4 + lum);
  }
  exposure = log2(0.18 / exp(logsum / (PW * PH)));

  /* 1. the four tone mappers, same exposure */
  for (i = 0; i < 4; i++) {
    el_film_output_options o;
    memset(&o, 0, sizeof o);
    o.exposure = (float)exposure;
    o.tonemap = maps[i];
    o.exp_k = 1.0f;
    if (el_film_to_srgb8(panel, PW, PH, &o, p8) != EL_SUCCESS) { fprintf(stderr, "04_tone_mapping: encoding failed\n"); return 1; }
    blit(page, W, p8, PW, PH, (i % 2) * PW, (i / 2) * PH, 1);
    el_draw_label(page, W, H, (i % 2) * PW + 6, (i / 2) * PH + 6, names[i]);
  }
  snprintf(text, sizeof text, "EXPOSURE %+.2f STOPS (KEY 0.18)", exposure);
  el_draw_label(page, W, H, 6, 2 * PH - 28, text);

  /* 2. the zone plate through two pixel filters */
  {
    unsigned char *z8 = (unsigned char *)malloc((size_t)3 * ZP * ZP);
    int y0 = 2 * PH + 32;
    if (!z8) return 1;
    tbox = render_zone_plate(EL_FILM_FILTER_BOX, spp, z8);
    blit(page, W, z8, ZP, ZP, 0, y0, 2);
    tmit = render_zone_plate(EL_FILM_FILTER_MITCHELL, spp, z8);
    blit(page, W, z8, ZP, ZP, 2 * ZP, y0, 2);
    free(z8);
    snprintf(text, sizeof text, "ZONE PLATE, %d RANDOM SAMPLES PER PIXEL, SHOWN 2X", spp);
    el_draw_label(page, W, H, 6, 2 * PH + 5, text);
    snprintf(text, sizeof text, "BOX R=0.5: %.0f MS", 1e3 * tbox);
    el_draw_label(page, W, H, 6, y0 + 6, text);
    snprintf(text, sizeof text, "MITCHELL R=2 B=C=1/3: %.0f MS", 1e3 * tmit);
    el_draw_label(page, W, H, 2 * ZP + 6, y0 + 6, text);
  }

  /* write (the folder of the default path is created) */
  {
    const char *slash = strrchr(out, '/');
    if (slash && slash != out) {
      char dir[512];
      size_t n = (size_t)(slash - out);
      if (n < sizeof dir) {
        memcpy(dir, out, n);
        dir[n] = 0;
        if (mkdir(dir, 0777) != 0 && errno != EEXIST) fprintf(stderr, "04_tone_mapping: cannot create %s\n", dir);
      }
    }
  }
  if (el_image_write_png(out, page, W, H, 3, err, sizeof err) != 0) {
    fprintf(stderr, "04_tone_mapping: %s\n", err);
    return 1;
  }
  printf("input %s, exposure %+.2f stops (log-average luminance -> 0.18)\n", in, exposure);
  printf("zone plate %dx%d, %d spp: box filter %.1f ms (%.1f ns/sample), mitchell %.1f ms (%.1f ns/sample)\n", ZP, ZP,
         spp, 1e3 * tbox, 1e9 * tbox / ((ZP + 0.0) * ZP * spp), 1e3 * tmit, 1e9 * tmit / ((ZP + 4.0) * (ZP + 4.0) * spp));
  printf("%s\n", out);
  free(panel);
  free(page);
  free(p8);
  return 0;
}
