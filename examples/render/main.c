/* render: a pbrt-v3-format scene renderer on Embree, lit by envlight.h (examples/render).
 *
 *   render SCENE.pbrt [--outfile F] [--spp N] [--nthreads N] [--seed S] [--stats] [--quiet]
 *
 * Reads the pbrt-v3 subset documented in el_render.h and issue 5, renders it on all cores (or
 * --nthreads) and writes F (or the Film's "filename"); the format follows the extension: .png (sRGB,
 * 8 bits), .exr, .pfm, .hdr (linear floats). A progress bar with elapsed and remaining time goes to
 * stderr unless --quiet; the closing line gives the time, samples per second and rays per second;
 * --stats prints what was built and what each part cost. Exit code 0 on success, 1 on any error
 * (nothing is written then).
 *
 * Hidden test and benchmark options: --light-sampling mis|light|bsdf, --compensated 0|1,
 * --env-sampling product|map (the environment sampled by the map x the surface's cosine, or the map alone),
 * --env-lobe-alpha A (with product sampling, vertices with a glossy lobe of Trowbridge-Reitz alpha below A and no
 * diffuse lobe sample the map alone under a sun map, the product around the mirror direction otherwise; 0 never;
 * default ELR_ENV_LOBE_ALPHA), --env-light-alpha A (and directlighting vertices
 * whose lobes are diffuse or of alpha >= A take the product light sample alone; inf never; ELR_ENV_LIGHT_ALPHA),
 * --env-sun-diffuse map|product|alone|suncos|two|twopixel (under a sun map, diffuse-only vertices: the map alone with MIS, the
 * product with MIS, the product light sample alone, the sun rule by the normal, two product light samples in place of
 * directlighting's light + BSDF pair (the path tracer: of its light sample, the continuation ray's environment weighted 0
 * there), twopixel: that where the pixel's centre sees the sun,
 * product MIS where not; default ELR_ENV_SUN_DIFFUSE: product),
 * --env-sun-cos C (the sun rule's threshold: the map alone where the sun is within acos(C) of the normal),
 * --sampler random|stratified|halton|sobol|02sequence|zsobol|paddedsobol, --importance cellaverage|pbrt-v3|texel (the environment's
 * importance map: envlight's cell average, pbrt-v3's 2x-resolution point lookups, raw texels),
 * --split off|auto|N (light and BSDF sample pairs per camera sample, directlighting), --loop one|wave (the per-tile loop: the reference or the wave loop), --wave-api single|packet16|stream|soa (how the wave loop calls Embree),
 * --sun auto|off|on|split (issue 22, sun.c: a pilot learns where the map's hot spots are hidden; auto: off for now;
 * split: one light sample of the hot spots and one of the rest x cosine at each diffuse vertex). */
#include "el_render.h"
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define SAMPLERS "random|stratified|halton|sobol|02sequence|zsobol|paddedsobol"
static void usage(void) {
  fprintf(stderr, "usage: render SCENE.pbrt [--outfile F] [--spp N] [--nthreads N] [--seed S] [--stats] [--quiet]\n"
                  "  --spp N       samples per pixel instead of the scene's (sobol, 02sequence, zsobol: rounded up to a power of two)\n"
                  "  --seed S      the random streams and scrambles (the same seed gives the same image on any thread count)\n"
                  "  --stats       what was built and what each part cost, with the sampler that ran\n"
                  "  --sampler S   instead of the scene's Sampler: " SAMPLERS "\n"
                  "  --randomization none|permutedigits|fastowen|owen   the scramble of sobol, zsobol, paddedsobol\n"
                  "A scene without a Sampler directive is rendered with %s, %d spp (pbrt-v3's default is halton, 16 spp).\n",
          elr_sampler_kind_name(ELR_DEFAULT_SAMPLER), ELR_DEFAULT_SPP);
}
static int parse_int(const char *s, long lo, long hi, long *out) {
  char *e;
  long v;
  errno = 0;
  v = strtol(s, &e, 10);
  if (errno || *e || e == s || v < lo || v > hi) return -1;
  *out = v;
  return 0;
}

/* The index of m among the '|'-separated names of choices ("mis|light|bsdf": "light" is 1); else
 * prints "render: OPT CHOICES" and gives -1. */
static int parse_choice(const char *opt, const char *m, const char *choices) {
  const char *c = choices;
  size_t n = strlen(m);
  int k = 0;
  for (;;) {
    const char *end = strchr(c, '|');
    size_t len = end ? (size_t)(end - c) : strlen(c);
    if (len == n && !strncmp(c, m, n)) return k;
    if (!end) break;
    c = end + 1;
    k++;
  }
  fprintf(stderr, "render: %s %s\n", opt, choices);
  return -1;
}

int main(int argc, char **argv) {
  const char *scene = NULL, *outfile = NULL;
  elr_render_options o;
  int stats = 0, i;
  elr_scene *s = NULL;
  elr_image img;
  elr_stats st;
  char err[1024];
  double t0;
  elr_render_options_default(&o);
  for (i = 1; i < argc; i++) {
    const char *a = argv[i];
    long v;
    if (!strcmp(a, "--outfile") && i + 1 < argc) outfile = argv[++i];
    else if (!strcmp(a, "--spp") && i + 1 < argc) {
      if (parse_int(argv[++i], 1, 1 << 24, &v)) { fprintf(stderr, "render: --spp must be an integer in [1, 16777216], got \"%s\"\n", argv[i]); return 1; }
      o.spp = (int)v;
    } else if (!strcmp(a, "--nthreads") && i + 1 < argc) {
      if (parse_int(argv[++i], 1, 1024, &v)) { fprintf(stderr, "render: --nthreads must be an integer in [1, 1024], got \"%s\"\n", argv[i]); return 1; }
      o.nthreads = (int)v;
    } else if (!strcmp(a, "--seed") && i + 1 < argc) {
      char *e; unsigned long long sd;
      errno = 0; sd = strtoull(argv[++i], &e, 10);
      if (errno || *e || argv[i][0] == '-' || e == argv[i]) { fprintf(stderr, "render: --seed must be a non-negative integer, got \"%s\"\n", argv[i]); return 1; }
      o.seed = (uint64_t)sd;
    } else if (!strcmp(a, "--stats")) stats = 1;
    else if (!strcmp(a, "--quiet")) o.quiet = 1;
    else if (!strcmp(a, "--light-sampling") && i + 1 < argc) {
      if ((o.light_sampling = parse_choice(a, argv[++i], "mis|light|bsdf")) < 0) return 1;
    } else if (!strcmp(a, "--compensated") && i + 1 < argc) {
      if (parse_int(argv[++i], 0, 1, &v)) { fprintf(stderr, "render: --compensated 0|1\n"); return 1; }
      o.compensated = (int)v;
    } else if (!strcmp(a, "--env-sampling") && i + 1 < argc) {
      int k = parse_choice(a, argv[++i], "product|map");
      if (k < 0) return 1;
      o.env_sampling = 1 - k; /* product 1, map 0 */
    } else if (!strcmp(a, "--env-lobe-alpha") && i + 1 < argc) {
      char *e;
      double x;
      errno = 0; x = strtod(argv[++i], &e);
      if (errno || *e || e == argv[i] || !(x >= 0.0 && x <= 1e30)) { fprintf(stderr, "render: --env-lobe-alpha must be a number >= 0, got \"%s\"\n", argv[i]); return 1; }
      o.env_lobe_alpha = (float)x;
    } else if (!strcmp(a, "--env-light-alpha") && i + 1 < argc) {
      char *e;
      double x;
      errno = 0; x = strtod(argv[++i], &e);
      if (errno || *e || e == argv[i] || !(x >= 0.0)) { fprintf(stderr, "render: --env-light-alpha must be a number >= 0 or inf, got \"%s\"\n", argv[i]); return 1; }
      o.env_light_alpha = (float)x;
    } else if (!strcmp(a, "--importance") && i + 1 < argc) {
      if ((o.importance = parse_choice(a, argv[++i], "cellaverage|pbrt-v3|texel|bilinear")) < 0) return 1;
    } else if (!strcmp(a, "--sampler") && i + 1 < argc) {
      int k = elr_sampler_kind_from_name(argv[++i]);
      if (k <= 0) { fprintf(stderr, "render: --sampler %s\n", SAMPLERS); return 1; }
      o.sampler = k;
    } else if (!strcmp(a, "--randomization") && i + 1 < argc) {
      if ((o.randomization = parse_choice(a, argv[++i], "none|permutedigits|fastowen|owen")) < 0) return 1;
    } else if (!strcmp(a, "--env-sun-diffuse") && i + 1 < argc) {
      if ((o.env_sun_diffuse = parse_choice(a, argv[++i], "map|product|alone|suncos|two|twopixel")) < 0) return 1;
    } else if (!strcmp(a, "--env-sun-cos") && i + 1 < argc) {
      char *e;
      double x;
      errno = 0; x = strtod(argv[++i], &e);
      if (errno || *e || e == argv[i] || !(x >= -1.0 && x <= 1.0)) { fprintf(stderr, "render: --env-sun-cos must be a number in [-1, 1], got \"%s\"\n", argv[i]); return 1; }
      o.env_sun_cos = (float)x;
    } else if (!strcmp(a, "--sun") && i + 1 < argc) {
      int k = parse_choice(a, argv[++i], "auto|off|on|split");
      if (k < 0) return 1;
      o.env_sun = k - 1; /* auto -1, off 0, on 1, split 2 */
    } else if (!strcmp(a, "--loop") && i + 1 < argc) {
      const char *m = argv[++i];
      if (!strcmp(m, "one")) o.loop = ELR_LOOP_ONE; else if (!strcmp(m, "wave")) o.loop = ELR_LOOP_WAVE;
      else if (!strcmp(m, "batched")) {
        fprintf(stderr, "render: --loop batched is gone: the wave loop (--loop wave, the default where it applies) draws the light "
                        "samples together now; --loop one is the reference\n");
        return 1;
      } else { fprintf(stderr, "render: --loop one|wave\n"); return 1; }
    } else if (!strcmp(a, "--split") && i + 1 < argc) {
      const char *m = argv[++i];
      if (!strcmp(m, "off")) o.split = 0; else if (!strcmp(m, "auto")) o.split = 1;
      else if (!parse_int(m, 2, 1024, &v)) o.split = (int)v;
      else { fprintf(stderr, "render: --split off|auto|N (N in [2, 1024])\n"); return 1; }
    } else if (!strcmp(a, "--wave-api") && i + 1 < argc) {
      if ((o.wave_api = parse_choice(a, argv[++i], "single|packet16|stream|soa")) < 0) return 1;
    } else if (!strcmp(a, "--help") || !strcmp(a, "-h")) { usage(); return 0; }
    else if (a[0] == '-' && a[1] == '-') { fprintf(stderr, "render: unknown or incomplete option \"%s\"\n", a); usage(); return 1; }
    else if (!scene) scene = a;
    else { fprintf(stderr, "render: more than one scene file (\"%s\", \"%s\")\n", scene, a); usage(); return 1; }
  }
  if (!scene) { usage(); return 1; }
  t0 = elr_now();
  if (elr_scene_load(scene, &s, o.quiet, err, sizeof err) != 0) { fprintf(stderr, "%s\n", err); return 1; }
  if (!outfile) outfile = elr_scene_film_filename(s);
  {
    /* refuse an unknown output format before spending the render time */
    const char *dot = strrchr(outfile, '.');
    if (!dot || (strcmp(dot, ".png") && strcmp(dot, ".exr") && strcmp(dot, ".pfm") && strcmp(dot, ".hdr") &&
                 strcmp(dot, ".PNG") && strcmp(dot, ".EXR") && strcmp(dot, ".PFM") && strcmp(dot, ".HDR"))) {
      fprintf(stderr, "render: %s: unknown output format (use .png, .exr, .pfm or .hdr)\n", outfile);
      elr_scene_free(s);
      return 1;
    }
  }
  if (elr_render(s, &o, &img, &st, err, sizeof err) != 0) { fprintf(stderr, "render: %s\n", err); elr_scene_free(s); return 1; }
  if (elr_image_write(&img, outfile, err, sizeof err) != 0) {
    fprintf(stderr, "render: %s\n", err); elr_image_free(&img); elr_scene_free(s); return 1;
  }
  {
    double t = st.t_render;
    unsigned long long rays = st.camera_rays + st.bounce_rays + st.shadow_rays + st.bsdf_light_rays;
    if (stats) elr_stats_print(&st, stderr);
    if (st.rejected_samples > 0) /* a warning, shown even with --quiet: the image lacks those samples */
      fprintf(stderr, "render: warning: %llu of %llu samples rejected (NaN, infinite or negative radiance: overflowing texels or "
              "intensities?); the film left them out\n", (unsigned long long)st.rejected_samples, (unsigned long long)st.samples);
    fprintf(stderr, "render: %s: %d x %d, %d spp in %.3f s (total %.3f s): %.3g samples/s, %.3g rays/s\n", outfile, img.width,
            img.height, st.spp, t, elr_now() - t0, t > 0 ? (double)st.samples / t : 0.0, t > 0 ? (double)rays / t : 0.0);
  }
  elr_image_free(&img);
  elr_scene_free(s);
  return 0;
}
