/* bench_render: what the renderer's accuracy costs in time, on one fixed scene.
 *
 * The scene: scenes/bench_city.pbrt, a diffuse sphere on a diffuse plane under the city map
 * (data/envmaps/city.hdr, CC0, a 3e4 sun), 320 x 240, direct lighting.
 *
 * Part 1, ray throughput (one thread). Embree's raw rates on this scene: rtcIntersect1 for the camera
 * rays through the pixel centres, rtcOccluded1 for shadow rays from their hit points towards directions
 * drawn from the environment's distribution (arrays prepared beforehand, so only the Embree calls and
 * the ray struct setup are timed). Then the renderer's direct-lighting loop (16 spp, one thread): its
 * rays per second, and its EFFICIENCY = the time Embree alone would need for the same rays (camera rays
 * at the rtcIntersect1 rate, shadow and BSDF-sampled rays at the rtcOccluded1 rate) / the loop's time.
 * The target is >= 70%: the rest is sampling, shading, MIS, film.
 *
 * Part 2, accuracy against time (all threads). A reference of its own: stratified + MIS at --ref-spp
 * (default 1024; a square number of samples). Then relative MSE,
 *     relMSE(x, ref) = mean over pixels and channels of (x - ref)^2 / (ref^2 + 1e-2)
 * (the definition of bench/mitsuba_compare.py), and wall time, at 16, 64 and 256 spp, for each
 * sampler (random, stratified, halton) and each light-sampling option (MIS, light only, BSDF only,
 * MIS with envlight's compensated distribution), all sampling pbrt-v3's importance map (twice the
 * image's resolution from point lookups: the renderer's default); --full adds MIS with envlight's
 * default map of cell averages. relMSE x time is the efficiency (lower is better).
 *
 * Part 3, --samplers (alone): every sampler (random, stratified, halton, sobol, 02sequence, zsobol,
 * paddedsobol, and sobol with pbrt-v4's fastowen randomization) at 16, 64 and 256 spp with MIS, on
 * the sun map (bench_city) and the smooth studio map (scenes/bench_studio.pbrt), for the
 * directlighting and the path integrator (maxdepth 5): relMSE against a stratified reference of
 * --ref-spp samples rendered as two halves with other seeds, the same minus the reference's own noise
 * (relMSE of the halves / 4), that against the random sampler's, and ns per sample (wall time x
 * threads / samples). --scene and --integrator pick one of the four tables. The cost per sample is
 * better read from instruction counts (--callgrind samples N --sampler S, below): wall times move with
 * the machine's load. examples/render/README.md has the measured tables.
 *
 * Part 1b (also --loops alone): the per-tile loops (one sample at a time, the wave loop with each of
 * its four Embree call kinds; the batched loop, render_batched.c, was folded into the wave loop) for
 * the direct-lighting (16 spp) and path (4 spp) integrators, zsobol (an order-free sampler, so every
 * loop gives the same image): time, speed-up, rays per second, Embree's share estimated from raw rates measured on rays of each kind through the
 * same call, and for the wave loop measured (its Embree calls timed). --split (alone): splitting's
 * variance across seeds x CPU time for 1, 2, 4 pairs and auto on bench_city and bench_studio.
 *
 * Run:  build/bin/bench_render [--quick] [--full] [--rays-only] [--packets] [--loops] [--split] [--ref-spp N] [--threads N]
 *       --rays-only: part 1 alone (a few seconds). --packets: what Embree's packet and stream calls
 *       would gain on the camera rays (see packet_rates), alone. The default run renders about 390 M camera samples:
 *       6 minutes measured on the shared 2-core development machine (load average about 4); --full
 *       (465 M) took 12 minutes there at load average 6.
 *       --quick: 16 and 64 spp, reference 256 spp (about a minute); the default takes a few minutes.
 * Instruction counts (DEVELOPERS.md): build/bin/bench_render --callgrind OP N runs only N operations
 * after the setup (--integrator path: the path tracer at 4 spp; --loop one|wave and --wave-api
 * single|packet16|stream|soa choose the loop); OP is intersect (rtcIntersect1 calls), occluded (rtcOccluded1 calls), samples
 * (camera samples of the direct-lighting loop: 16 spp over N / 16 pixels of the middle rows,
 * rounded up to whole rows of 320) or samples1 (the same with light samples drawn one at a time:
 * render_options.no_batch); --sampler S renders those samples with sampler S (default stratified).
 *     valgrind --tool=callgrind build/bin/bench_render --callgrind samples 102400
 *     valgrind --tool=callgrind build/bin/bench_render --callgrind samples 0
 * instructions per sample = (Ir(102400) - Ir(0)) / 102400 (the run prints the samples it rendered).
 *
 * Measured (2026-11-22, shared 2-core AMD EPYC VM; times are the least disturbed of interleaved runs
 * and move by 10-20% with the machine's load, instruction counts do not):
 *   callgrind, N = 25600: 4376 -> 4448 instructions per camera sample from the renderer's performance
 *     pass (same envlight.h): film add 329 -> 160 (box fast path), the light sample's radiance from
 *     sample_li's (u, v) instead of a second mapping in le(), +210 for the prefetch of the BSDF
 *     direction's texels and pdf bin. Embree's share is 1362 (1 rtcIntersect1 + 1.6 rtcOccluded1),
 *     sphere callbacks 304, envlight + distribution2d 604, BSDF 475, sampler 350.
 *   loop time (part 1, 16 spp, 1 thread): 0.63-0.87 s before, 0.62-0.70 s after (medians 0.75 and 0.65
 *     s): EFFICIENCY 18% -> 21%. Embree alone: 0.132 s (19 M intersect, 22 M occluded rays/s).
 *   perf: ~60% of the loop's time is envlight: the light sample's two dependent cache misses in
 *     distribution2d's guide table and CDF row (24%), then its texel lookup (15%), the rest pdf and
 *     BSDF-direction lookups (prefetched); Embree and the sphere callbacks ~16%.
 *   importance map: envlight's cell-average map (a quarter of the tables) makes the loop 5-10% faster
 *     but its relative MSE per sample is 11-33% higher (16/64 spp, quick table): pbrt-v3's map stays
 *     the default (lower relMSE at equal time).
 * (The measurements below that name the batched loop, render_batched.c, are from before it was folded
 * into the wave loop on 2026-12-02.)
 * Measured 2026-12-01 (quiet machine, interleaved runs of this binary and of the previous release's):
 *   a pixel's light samples drawn together (render_batched.c, el_envlight_sample_li_n): loop
 *     0.366-0.384 s, efficiency 27-28%; the same binary with no_batch 0.432-0.446 s (23-24%), the same
 *     image; the previous release 0.448-0.457 s (23%). callgrind: 4518 instructions per camera sample
 *     batched, 4347 one at a time (samples / samples1). Raw rates 25.4 M intersect, 26.7 M occluded
 *     rays/s: Embree alone takes 0.104 s, 85 ns per camera sample.
 * Measured 2026-12-01, the renderer laid out by pbrt-v3's concepts (no wrappers around the library's
 * calls; render_batched.c apart from the reference path), N = 102400: 4485 -> 4319 instructions per
 * camera sample batched, 4351 -> 4379 one at a time; the same images (examples/render/README.md).
 * Measured 2026-12-02, issue 16's format (instances, glass, metal, uber, substrate, Loop subdivision):
 * 4317 -> 4334 instructions per camera sample batched (main's binary and this one, N = 102400); the
 * same images for scenes that use none of it.
 * Measured 2026-12-02, the wave loop (render_wave.c; zsobol, N = 25600, instructions per camera sample,
 * Embree inclusive of the sphere callbacks): direct lighting one at a time 5379 (Embree 1757), wave
 * with packets of 16 4532 (Embree 643); path one at a time 7234 (2274), wave 6389 (979). --loops, best
 * of 5 interleaved rounds at load average 6-9: direct 2.343 -> 1.432 s (1.64x; batched 1.48x), path
 * 0.831 -> 0.439 s (1.89x); Embree's calls 11% and 14% of the wave loop's time (timed). --split on
 * bench_city: 2 and 4 pairs cost 1.25-2.34x more error x time than one; auto keeps one.
 * Instructions per camera sample BY PART (sampler, light, BSDF, film, Embree, camera, loop):
 *     sh bench/callgrind_parts.sh [--integrator path] [--loop one]
 * (two --callgrind samples runs, 25600 and 51200, and bench/callgrind_parts.py on their difference).
 * Measured 2026-12-02 (issue 21), zsobol's fast path: sampler 1225 -> 512 instructions per camera
 * sample with direct lighting, 2123 -> 1411 with the path tracer (4 spp); the same images
 * (examples/render/README.md has the table by part).
 * Measured 2026-12-02 (issue 21, second round), callgrind_parts.sh: direct lighting 4026 -> 3453
 * instructions per camera sample (the first vertex shaded in the wave -249, the BSDF direction's
 * environment only where its shadow ray escaped -99, full packets copied by component -88, the film in
 * one call a wave -67, a map-alone wave's light samples without gather -31, clamp without fmaxf -26,
 * Lambertian f and pdf inlined -15), path 6004 -> 5719; the same images. Not kept: --wave-api stream
 * 4063, soa 3919, single 4809 (packet16 3777 then), the sphere test two lanes at a time with SSE2
 * (Embree 995 -> 1009), active lanes by bit mask (907 -> 936). Loop CPU, one thread, interleaved rounds
 * against main's binary: bench_city 64 spp 0.85-0.90x, bench_studio 0.92-0.95x, path 0.95-0.98x.
 * After merging main's sun cache and product sampler: main 4120 -> 3540 (direct), 6146 -> 5862 (path).
 * Measured 2026-12-02 (issue 21), zsobol's fast path, second step (sampler_zsobol.c): sampler part
 * 461 -> 234 (direct), 1411 -> 527 (path); totals 4062 -> 3833, 6452 -> 5562; the same images. Loop
 * CPU (render --stats, one thread, interleaved): median ratios 0.96-0.98 (direct), 0.93-0.95 (path).
 * Measured 2026-12-02 (issue 21, third round: the wave's shading and bookkeeping), callgrind_parts.sh:
 * direct 4060 -> 3630, path 6453 -> 5765 (BSDF 614 -> 406 and 811 -> 485, now inline in the loop's
 * file; a material's constant BSDF copied per hit, Lambertian sampling and f/pdf inline, elr_wave_add
 * inline; examples/render/README.md has the table); the same images. Loop CPU, one thread, 64 spp, 7
 * interleaved rounds against main's binary: bench_city direct 0.870-0.931x, path 0.873-0.945x,
 * bench_studio 0.917-0.969x.
 * Measured 2026-12-02 (issue 21, fourth round: the first vertex of matte in structure-of-arrays form,
 * render_wave.c's elr__soa_*), callgrind_parts.sh: bench_city direct 3716 -> 3224 (loop 1065 -> 621),
 * bench_studio direct 2678 -> 2449, path unchanged; the same images. Loop CPU, one thread, 64 spp, 5
 * interleaved rounds: bench_city 0.88-0.92x (median 0.915), bench_studio 0.96-1.01x (median 0.967). */
#define _POSIX_C_SOURCE 200809L
#include "el_render.h"
#include "elr_internal.h"
#include <embree3/rtcore.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifndef EL_SOURCE_DIR
#define EL_SOURCE_DIR "."
#endif

static double relmse(const float *a, const float *ref, size_t n) {
  double s = 0;
  size_t i;
  for (i = 0; i < n; i++) { double d = (double)a[i] - ref[i]; s += d * d / ((double)ref[i] * ref[i] + 1e-2); }
  return s / (double)n;
}

typedef struct { elr_v3 o, d; } bray;

/* camera rays through pixel centres, pbrt-v3's pinhole (the same maths as examples/render/camera.c) */
static void camera_rays(const elr_scene *s, bray *r) {
  int w = s->d.xres, h = s->d.yres, x, y;
  double frame = (double)w / h, th = tan(s->d.fov * 3.14159265358979 / 360.0);
  float sx0 = frame > 1 ? (float)-frame : -1.f, sx1 = -sx0, sy0 = frame > 1 ? -1.f : (float)(-1 / frame), sy1 = -sy0;
  for (y = 0; y < h; y++)
    for (x = 0; x < w; x++) {
      float sx = sx0 + (x + 0.5f) / w * (sx1 - sx0), sy = sy1 - (y + 0.5f) / h * (sy1 - sy0);
      elr_v3 dc = elr_norm(elr_v(sx * (float)th, sy * (float)th, 1.f));
      r[y * w + x].o = elr_xpoint(&s->d.cam2world, elr_v(0, 0, 0));
      r[y * w + x].d = elr_norm(elr_xvector(&s->d.cam2world, dc));
    }
}

/* --packets: camera rays through pixel centres in 4 x 4 pixel blocks, traced with rtcIntersect1, with
 * rtcIntersect16 (one block per packet) and as coherent streams of 64 (rtcIntersect1M). The scene is
 * loaded with Embree's own sphere primitive (ELR_EMBREE_SPHERES), because the renderer's user-geometry
 * sphere callbacks take one ray at a time. Best of 3 rounds of 10 passes, one thread. */
static void packet_rates(const elr_scene *s) {
  int w = s->d.xres, h = s->d.yres, n = 0, bx, by, x, y, round, pass, i, k;
  RTCScene sc = (RTCScene)s->rtscene;
  bray *cam = (bray *)malloc(sizeof(bray) * (size_t)w * h), *blk = (bray *)malloc(sizeof(bray) * (size_t)w * h);
  struct RTCRayHit *arr = (struct RTCRayHit *)malloc(sizeof(struct RTCRayHit) * (size_t)w * h);
  struct RTCIntersectContext ctx, coh;
  double best[3] = {0, 0, 0};
  volatile float sink = 0;
  if (!cam || !blk || !arr || w % 4 || h % 4) { printf("packets: needs a resolution divisible by 4\n"); free(cam); free(blk); free(arr); return; }
  camera_rays(s, cam);
  for (by = 0; by < h; by += 4)
    for (bx = 0; bx < w; bx += 4)
      for (y = by; y < by + 4; y++)
        for (x = bx; x < bx + 4; x++) blk[n++] = cam[y * w + x];
  rtcInitIntersectContext(&ctx);
  rtcInitIntersectContext(&coh);
  coh.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  for (round = 0; round < 3; round++) {
    double t[4];
    t[0] = elr_now();
    for (pass = 0; pass < 10; pass++)
      for (i = 0; i < n; i++) {
        struct RTCRayHit rh;
        rh.ray.org_x = blk[i].o.x; rh.ray.org_y = blk[i].o.y; rh.ray.org_z = blk[i].o.z; rh.ray.tnear = 0.f;
        rh.ray.dir_x = blk[i].d.x; rh.ray.dir_y = blk[i].d.y; rh.ray.dir_z = blk[i].d.z; rh.ray.time = 0.f;
        rh.ray.tfar = INFINITY; rh.ray.mask = ~0u; rh.ray.id = 0; rh.ray.flags = 0;
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID; rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(sc, &ctx, &rh);
        sink += rh.ray.tfar;
      }
    t[1] = elr_now();
    for (pass = 0; pass < 10; pass++)
      for (i = 0; i < n; i += 16) {
        RTC_ALIGN(64) struct RTCRayHit16 rh; /* Embree wants the packet and its mask 64-byte aligned */
        RTC_ALIGN(64) int valid[16];
        for (k = 0; k < 16; k++) {
          valid[k] = -1;
          rh.ray.org_x[k] = blk[i + k].o.x; rh.ray.org_y[k] = blk[i + k].o.y; rh.ray.org_z[k] = blk[i + k].o.z; rh.ray.tnear[k] = 0.f;
          rh.ray.dir_x[k] = blk[i + k].d.x; rh.ray.dir_y[k] = blk[i + k].d.y; rh.ray.dir_z[k] = blk[i + k].d.z; rh.ray.time[k] = 0.f;
          rh.ray.tfar[k] = INFINITY; rh.ray.mask[k] = ~0u; rh.ray.id[k] = 0; rh.ray.flags[k] = 0;
          rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID; rh.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
        }
        rtcIntersect16(valid, sc, &ctx, &rh);
        for (k = 0; k < 16; k++) sink += rh.ray.tfar[k];
      }
    t[2] = elr_now();
    for (pass = 0; pass < 10; pass++) {
      for (i = 0; i < n; i++) {
        struct RTCRayHit *rh = &arr[i];
        rh->ray.org_x = blk[i].o.x; rh->ray.org_y = blk[i].o.y; rh->ray.org_z = blk[i].o.z; rh->ray.tnear = 0.f;
        rh->ray.dir_x = blk[i].d.x; rh->ray.dir_y = blk[i].d.y; rh->ray.dir_z = blk[i].d.z; rh->ray.time = 0.f;
        rh->ray.tfar = INFINITY; rh->ray.mask = ~0u; rh->ray.id = 0; rh->ray.flags = 0;
        rh->hit.geomID = RTC_INVALID_GEOMETRY_ID; rh->hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
      }
      for (i = 0; i < n; i += 64) rtcIntersect1M(sc, &coh, arr + i, (unsigned)(n - i < 64 ? n - i : 64), sizeof(struct RTCRayHit));
      for (i = 0; i < n; i++) sink += arr[i].ray.tfar;
    }
    t[3] = elr_now();
    for (k = 0; k < 3; k++) if (10.0 * n / (t[k + 1] - t[k]) > best[k]) best[k] = 10.0 * n / (t[k + 1] - t[k]);
  }
  printf("camera rays in 4 x 4 pixel blocks, Embree's sphere primitive, 1 thread (best of 3):\n"
         "  rtcIntersect1 %.2f M rays/s, rtcIntersect16 %.2f M rays/s (%.2fx), rtcIntersect1M coherent streams of 64 %.2f M rays/s\n",
         best[0] * 1e-6, best[1] * 1e-6, best[1] / best[0], best[2] * 1e-6);
  (void)sink;
  free(cam); free(blk); free(arr);
}

static elr_light *scene_env(elr_scene *s) {
  int i;
  for (i = 0; i < s->nlight; i++) if (s->light[i].kind == ELR_LIGHT_INFINITE) return &s->light[i];
  return NULL;
}

/* shadow rays: from the camera rays' hit points towards environment samples (only those above the
 * surface, as the loop traces them) */
static int shadow_rays(elr_scene *s, const bray *cam, int n, bray *out, int max) {
  elr_light *env = scene_env(s);
  int i, k = 0;
  uint32_t st = 12345;
  elr_infinite_prepare(env, -1, -1, 0, 1); /* the map alone: these shadow rays use el_envlight_sample_li */
  for (i = 0; i < n && k < max; i++) {
    elr_hit h;
    int tries;
    if (!elr_intersect(s, cam[i].o, cam[i].d, INFINITY, &h)) continue;
    for (tries = 0; tries < 8 && k < max; tries++) {
      float u[2], w3[3], L3[3], pdf;
      elr_v3 wi;
      st = st * 1664525u + 1013904223u; u[0] = (st >> 8) * 0x1p-24f;
      st = st * 1664525u + 1013904223u; u[1] = (st >> 8) * 0x1p-24f;
      el_envlight_sample_li(env->env_sample, u, w3, L3, &pdf);
      wi = elr_from3(w3);
      if (pdf > 0 && elr_dot(wi, h.ng) * elr_dot(cam[i].d, h.ng) < 0) {
        out[k].o = elr_add(h.p, elr_mul(h.ng, elr_dot(wi, h.ng) > 0 ? h.eps : -h.eps));
        out[k].d = wi;
        k++;
        break;
      }
    }
  }
  return k;
}

/* bounce rays: from the camera rays' hit points in cosine-distributed directions about the normal (on
 * the side the camera ray came from), as a diffuse bounce leaves */
static int bounce_rays(elr_scene *s, const bray *cam, int n, bray *out, int max) {
  int i, k = 0;
  uint32_t st = 777;
  for (i = 0; i < n && k < max; i++) {
    elr_hit h;
    elr_v3 nn, t1, t2, d;
    float u1, u2, r, ph;
    if (!elr_intersect(s, cam[i].o, cam[i].d, INFINITY, &h)) continue;
    nn = elr_dot(cam[i].d, h.ng) < 0 ? h.ng : elr_mul(h.ng, -1.f);
    elr_onb(nn, &t1, &t2);
    st = st * 1664525u + 1013904223u; u1 = (st >> 8) * 0x1p-24f;
    st = st * 1664525u + 1013904223u; u2 = (st >> 8) * 0x1p-24f;
    r = sqrtf(u1); ph = 6.2831853f * u2;
    d = elr_add(elr_add(elr_mul(t1, r * cosf(ph)), elr_mul(t2, r * sinf(ph))), elr_mul(nn, sqrtf(fmaxf(0.f, 1.f - u1))));
    out[k].o = elr_add(h.p, elr_mul(nn, h.eps)); out[k].d = d;
    k++;
  }
  return k;
}

/* rays per second of the wave functions (scene.c) with Embree call api, in waves of 256 rays (camera rays
 * in the order a tile's wave takes them: pixel rows of 16) */
static double wave_rate(elr_scene *s, const bray *r, int n, int api, int occluded, int coherent) {
  static elr_wave_rays w;
  double t0 = elr_now(), cnt = 0;
  volatile float sink = 0;
  int pass, i, k;
  elr_wave_rays_init(&w);
  for (pass = 0; elr_now() - t0 < 0.3 || pass < 2; pass++) {
    for (i = 0; i < n; i += 256) {
      w.n = 0;
      for (k = i; k < n && k < i + 256; k++) elr_wave_add(&w, r[k].o, r[k].d, INFINITY);
      if (occluded) elr_wave_occluded(s, &w, api, coherent); else elr_wave_intersect(s, &w, api, coherent);
      sink += w.tfar[0];
    }
    cnt += n;
  }
  (void)sink;
  return cnt / (elr_now() - t0);
}

static int g_no_batch; /* render_once: elr_render_options.no_batch */
static int g_randomization = -1; /* render_once: elr_render_options.randomization */
static int g_loop = -1, g_wave_api = -1; /* render_once: elr_render_options.loop, wave_api */
static int render_once(elr_scene *s, int spp, int sampler, int ls, int comp, int imp, int threads, uint64_t seed,
                       elr_image *img, elr_stats *st) {
  elr_render_options o;
  char err[512];
  elr_render_options_default(&o);
  o.no_batch = g_no_batch; o.randomization = g_randomization; o.loop = g_loop; o.wave_api = g_wave_api;
  o.spp = spp; o.sampler = sampler; o.light_sampling = ls; o.compensated = comp; o.importance = imp; o.nthreads = threads;
  o.seed = seed;
  o.quiet = 1;
  if (elr_render(s, &o, img, st, err, sizeof err) != 0) { fprintf(stderr, "bench_render: %s\n", err); return -1; }
  return 0;
}

/* --samplers: relMSE against a high-spp reference at 16, 64, 256 spp for every sampler, on the sun map
 * (bench_city) and the smooth map (bench_studio), with both integrators; and the time per sample.
 * The reference is two stratified renders of ref_spp / 2 samples with other seeds, averaged; its own
 * noise, relMSE(half 1, half 2) / 4 for independent halves, is subtracted ("corrected"), so that
 * errors below the reference's noise are not hidden by it. */
static void sampler_table(int ref_spp, int threads, int quick, const char *only_scene, int only_integrator) {
  static const char *scenes[2] = {"bench_city", "bench_studio"};
  const int nspp = quick ? 2 : 3, spps[3] = {16, 64, 256};
  int sc, ig, k, c;
  printf("sampler table: relMSE against a %d-spp stratified reference (two halves, other seeds), %s threads\n", ref_spp,
         threads > 0 ? "the given" : "all");
  printf("  corrected = relMSE - the reference's own noise (relMSE of its halves / 4); ns/sample: wall time x threads / samples\n\n");
  for (sc = 0; sc < 2; sc++) {
    char path[1024], err[1024];
    elr_scene *s = NULL;
    if (only_scene && strcmp(only_scene, scenes[sc]) != 0) continue;
    snprintf(path, sizeof path, "%s/scenes/%s.pbrt", EL_SOURCE_DIR, scenes[sc]);
    if (elr_scene_load(path, &s, 1, err, sizeof err) != 0) { fprintf(stderr, "bench_render: %s\n", err); return; }
    for (ig = 0; ig < 2; ig++) {
      elr_image r1, r2;
      elr_stats st;
      size_t n;
      double noise, t0 = elr_now(), base_ns = 0;
      if (only_integrator >= 0 && ig != only_integrator) continue;
      s->d.integrator_path = ig; /* the scene's maxdepth (5) for both */
      if (render_once(s, ref_spp / 2, ELR_SAMPLER_STRATIFIED, ELR_LS_MIS, -1, -1, threads, 1001, &r1, &st) != 0) break;
      if (render_once(s, ref_spp / 2, ELR_SAMPLER_STRATIFIED, ELR_LS_MIS, -1, -1, threads, 1002, &r2, &st) != 0) break;
      n = (size_t)r1.width * r1.height * 3;
      noise = relmse(r1.rgb, r2.rgb, n) / 4.0;
      for (k = 0; k < (int)n; k++) r1.rgb[k] = 0.5f * (r1.rgb[k] + r2.rgb[k]);
      printf("%s, %s (maxdepth %d): reference %.1f s, its noise %.3g\n", scenes[sc], ig ? "path" : "directlighting", s->d.maxdepth,
             elr_now() - t0, noise);
      printf("  %-14s %5s %10s %10s %9s %9s %12s\n", "sampler", "spp", "relMSE", "corrected", "vs random", "ns/sample", "relMSE x s");
      for (c = 0; c < nspp; c++) {
        double e_random = 0;
        /* every sampler with pbrt's defaults, then pbrt-v3's sobol with pbrt-v4's default randomization */
        for (k = ELR_SAMPLER_RANDOM; k <= ELR_SAMPLER_COUNT; k++) {
          elr_image img;
          double e, ns, t1 = elr_now();
          int r;
          g_randomization = k == ELR_SAMPLER_COUNT ? ELR_RANDOMIZE_FAST_OWEN : -1;
          r = render_once(s, spps[c], k == ELR_SAMPLER_COUNT ? ELR_SAMPLER_SOBOL : k, ELR_LS_MIS, -1, -1, threads, 7, &img, &st);
          g_randomization = -1;
          if (r != 0) continue;
          e = relmse(img.rgb, r1.rgb, n);
          ns = st.t_render * st.nthreads / (double)st.samples * 1e9;
          if (k == ELR_SAMPLER_RANDOM) { e_random = e - noise; if (c == nspp - 1) base_ns = ns; }
          printf("  %-14s %5d %10.3g %10.3g %9.3f %9.0f %12.3g\n", k == ELR_SAMPLER_COUNT ? "sobol+fastowen" : elr_sampler_kind_name(k), st.spp, e, e - noise,
                 e_random > 0 ? (e - noise) / e_random : 0.0, ns, e * (elr_now() - t1));
          elr_image_free(&img);
        }
      }
      (void)base_ns;
      elr_image_free(&r1); elr_image_free(&r2);
    }
    s->d.integrator_path = 0;
    elr_scene_free(s);
  }
}

/* --loops (and part 1): the per-tile loops (one sample at a time, render_wave.c with each
 * of its Embree calls) on bench_city, direct lighting (16 spp) and path (maxdepth 5, 4 spp), one thread,
 * rounds interleaved, the best of each kept. Per loop: its rays per second; Embree's share of its time
 * ESTIMATED from the raw rates (rtcIntersect1 for camera and bounce rays, rtcOccluded1 for shadow rays,
 * measured here on rays of each kind) as the time Embree alone would take for the loop's rays over the
 * loop's time; for the wave loop also MEASURED (its Embree calls timed: elr_stats.t_embree_loop). */
static void loop_table(elr_scene *s, int rounds, int sampler) {
  enum { NLOOPS = 5 };
  static const char *names[NLOOPS] = {"one at a time", "wave, rtcIntersect1", "wave, packets of 16", "wave, 1M streams", "wave, Np streams"};
  static const int loops[NLOOPS] = {ELR_LOOP_ONE, ELR_LOOP_WAVE, ELR_LOOP_WAVE, ELR_LOOP_WAVE, ELR_LOOP_WAVE};
  static const int apis[NLOOPS] = {-1, ELR_WAVE_API_SINGLE, ELR_WAVE_API_PACKET16, ELR_WAVE_API_STREAM, ELR_WAVE_API_SOA};
  int w = s->d.xres, h = s->d.yres, nsh, nb, ig, round, k, a;
  bray *cam = (bray *)malloc(sizeof(bray) * (size_t)w * h), *sh = (bray *)malloc(sizeof(bray) * (size_t)w * h);
  bray *bo = (bray *)malloc(sizeof(bray) * (size_t)w * h), *blk = (bray *)malloc(sizeof(bray) * (size_t)w * h);
  double rate[3][4]; /* camera, shadow, bounce x the four APIs */
  if (!cam || !sh || !bo || !blk) { free(cam); free(sh); free(bo); free(blk); return; }
  camera_rays(s, cam);
  { /* the camera rays in the wave loop's order: 16 x 16 tiles, rows of 16 pixels */
    int n = 0, tx, ty, x, y;
    for (ty = 0; ty < h; ty += 16)
      for (tx = 0; tx < w; tx += 16)
        for (y = ty; y < ty + 16 && y < h; y++)
          for (x = tx; x < tx + 16 && x < w; x++) blk[n++] = cam[y * w + x];
  }
  nsh = shadow_rays(s, cam, w * h, sh, w * h);
  nb = bounce_rays(s, cam, w * h, bo, w * h);
  for (a = 0; a < 4; a++) { rate[0][a] = rate[1][a] = rate[2][a] = 0; }
  for (round = 0; round < 3; round++)
    for (a = 0; a < 4; a++) {
      double r0 = wave_rate(s, blk, w * h, a, 0, 1), r1 = wave_rate(s, sh, nsh, a, 1, 0), r2 = wave_rate(s, bo, nb, a, 0, 0);
      if (r0 > rate[0][a]) rate[0][a] = r0;
      if (r1 > rate[1][a]) rate[1][a] = r1;
      if (r2 > rate[2][a]) rate[2][a] = r2;
    }
  printf("Embree's raw rates through the wave functions (waves of 256 rays, arrays prepared beforehand; 1 thread, best of 3), M rays/s:\n");
  printf("  %-22s %10s %10s %10s %10s\n", "", "1 by 1", "packet16", "1M stream", "Np stream");
  printf("  %-22s %10.2f %10.2f %10.2f %10.2f\n", "camera (intersect)", rate[0][0] * 1e-6, rate[0][1] * 1e-6, rate[0][2] * 1e-6, rate[0][3] * 1e-6);
  printf("  %-22s %10.2f %10.2f %10.2f %10.2f\n", "shadow (occluded)", rate[1][0] * 1e-6, rate[1][1] * 1e-6, rate[1][2] * 1e-6, rate[1][3] * 1e-6);
  printf("  %-22s %10.2f %10.2f %10.2f %10.2f\n", "bounce (intersect)", rate[2][0] * 1e-6, rate[2][1] * 1e-6, rate[2][2] * 1e-6, rate[2][3] * 1e-6);
  for (ig = 0; ig < 2; ig++) {
    double best[NLOOPS], emb[NLOOPS], ncam = 0, nbo = 0, nshr = 0;
    int spp = ig ? 4 : 16, same[NLOOPS];
    elr_image ref;
    memset(&ref, 0, sizeof ref);
    s->d.integrator_path = ig;
    for (k = 0; k < NLOOPS; k++) { best[k] = 1e30; emb[k] = 0; same[k] = 1; }
    for (round = 0; round < rounds; round++)
      for (k = 0; k < NLOOPS; k++) {
        elr_image img;
        elr_stats st;
        g_loop = loops[k]; g_wave_api = apis[k];
        if (render_once(s, spp, sampler, ELR_LS_MIS, -1, -1, 1, 1, &img, &st) != 0) continue;
        g_loop = g_wave_api = -1;
        if (st.t_render < best[k]) { best[k] = st.t_render; emb[k] = st.t_embree_loop; }
        if (k == 0) { ncam = (double)st.camera_rays; nbo = (double)st.bounce_rays; nshr = (double)st.shadow_rays + st.bsdf_light_rays; }
        if (k == 0 && !ref.rgb) ref = img;
        else {
          same[k] &= ref.rgb && memcmp(ref.rgb, img.rgb, sizeof(float) * 3 * (size_t)img.width * img.height) == 0;
          elr_image_free(&img);
        }
      }
    printf("\n%s loop on bench_city, %d spp %s + MIS, 1 thread, best of %d interleaved rounds:\n", ig ? "path (maxdepth 5)" : "direct-lighting", spp,
           elr_sampler_kind_name(sampler), rounds);
    printf("  %.0f camera + %.0f bounce + %.0f shadow rays; Embree alone at the raw 1-by-1 rates: %.3f s\n", ncam, nbo, nshr,
           ncam / rate[0][0] + nbo / rate[2][0] + nshr / rate[1][0]);
    printf("  %-22s %8s %8s %10s %13s %13s %9s\n", "loop", "time s", "speed-up", "M rays/s", "Embree est.", "Embree meas.", "image");
    for (k = 0; k < NLOOPS; k++) {
      int a2 = apis[k] < 0 ? 0 : apis[k];
      double raw = ncam / rate[0][a2] + nbo / rate[2][a2] + nshr / rate[1][a2];
      if (best[k] >= 1e30) continue;
      printf("  %-22s %8.3f %7.2fx %10.2f %12.0f%% ", names[k], best[k], best[0] / best[k], (ncam + nbo + nshr) / best[k] * 1e-6,
             100.0 * raw / best[k]);
      if (loops[k] == ELR_LOOP_WAVE) printf("%12.0f%% ", 100.0 * emb[k] / best[k]); else printf("%13s ", "-");
      printf("%9s\n", k == 0 ? "reference" : same[k] ? "same" : "DIFFERENT");
    }
    elr_image_free(&ref);
  }
  printf("  (Embree est.: at the raw rates of the loop's own Embree call; wave loops: that call's rate from the table above)\n");
  s->d.integrator_path = 0;
  free(cam); free(sh); free(bo); free(blk);
}

/* --split: error x time of splitting (direct lighting) on the sun map (bench_city) and the smooth studio
 * map (bench_studio) at 16 and 64 spp: for 1 pair (off), 2, 4 and auto, the variance across seeds
 * (relMSE between two renders of other seeds, halved: no reference needed) and the CPU time (wall x
 * threads, the pilot included for auto), their product relative to off's. Rounds interleaved. */
static void split_table(int threads, int rounds) {
  static const char *scenes[2] = {"bench_city", "bench_studio"};
  static const int splits[4] = {ELR_SPLIT_OFF, 2, 4, ELR_SPLIT_AUTO};
  static const char *names[4] = {"off (1 pair)", "2 pairs", "4 pairs", "auto"};
  int sc, c, k, r;
  printf("splitting: variance across seeds x CPU time, direct lighting, the scene's sampler, %s threads, %d interleaved rounds\n",
         threads > 0 ? "the given" : "all", rounds);
  for (sc = 0; sc < 2; sc++) {
    char path[1024], err[1024];
    elr_scene *s = NULL;
    snprintf(path, sizeof path, "%s/scenes/%s.pbrt", EL_SOURCE_DIR, scenes[sc]);
    if (elr_scene_load(path, &s, 1, err, sizeof err) != 0) { fprintf(stderr, "bench_render: %s\n", err); return; }
    s->d.integrator_path = 0;
    for (c = 0; c < 2; c++) {
      int spp = c ? 64 : 16, chosen[4] = {0, 0, 0, 0};
      double var[4] = {0, 0, 0, 0}, cpu[4] = {0, 0, 0, 0};
      for (r = 0; r < rounds; r++)
        for (k = 0; k < 4; k++) {
          elr_render_options o;
          elr_image a, b;
          elr_stats sa, sb;
          elr_render_options_default(&o);
          o.spp = spp; o.nthreads = threads; o.quiet = 1; o.split = splits[k];
          o.seed = 100 + 2 * r;
          if (elr_render(s, &o, &a, &sa, err, sizeof err) != 0) continue;
          o.seed = 101 + 2 * r;
          if (elr_render(s, &o, &b, &sb, err, sizeof err) != 0) { elr_image_free(&a); continue; }
          var[k] += relmse(a.rgb, b.rgb, (size_t)a.width * a.height * 3) / 2.0;
          cpu[k] += ((sa.t_render + sa.t_split_pilot) * sa.nthreads + (sb.t_render + sb.t_split_pilot) * sb.nthreads) / 2.0;
          chosen[k] = sa.split;
          elr_image_free(&a); elr_image_free(&b);
        }
      printf("%s, %d spp:\n  %-14s %6s %12s %10s %12s %10s\n", scenes[sc], spp, "splitting", "pairs", "variance", "CPU s", "var x CPU", "vs off");
      for (k = 0; k < 4; k++) {
        double e = var[k] / rounds * cpu[k] / rounds, e0 = var[0] / rounds * cpu[0] / rounds;
        printf("  %-14s %6d %12.4g %10.3f %12.4g %9.2fx\n", names[k], chosen[k], var[k] / rounds, cpu[k] / rounds, e, e0 > 0 ? e / e0 : 0.0);
      }
    }
    elr_scene_free(s);
  }
}

int main(int argc, char **argv) {
  char path[1024], err[1024];
  elr_scene *s = NULL;
  int i, quick = 0, ref_spp = 1024, threads = 0, cg_n = -1, w, h, rays_only = 0, full = 0, packets = 0, samplers = 0, loops_only = 0, split_only = 0;
  int cg_path = 0; /* --callgrind ... --integrator path */
  int cg_sampler = ELR_SAMPLER_STRATIFIED; /* --sampler: the callgrind loop's */
  const char *only_scene = NULL;           /* --samplers --scene bench_city|bench_studio */
  int only_integrator = -1;                /* --samplers --integrator directlighting|path */
  const char *cg_op = NULL;
  for (i = 1; i < argc; i++) {
    if (!strcmp(argv[i], "--quick")) { quick = 1; ref_spp = 256; }
    else if (!strcmp(argv[i], "--rays-only")) rays_only = 1;
    else if (!strcmp(argv[i], "--full")) full = 1;
    else if (!strcmp(argv[i], "--packets")) packets = 1;
    else if (!strcmp(argv[i], "--samplers")) samplers = 1;
    else if (!strcmp(argv[i], "--loops")) loops_only = 1;
    else if (!strcmp(argv[i], "--split")) split_only = 1;
    else if (!strcmp(argv[i], "--loop") && i + 1 < argc) {
      i++; g_loop = !strcmp(argv[i], "one") ? ELR_LOOP_ONE : ELR_LOOP_WAVE; /* ("batched": folded into the wave loop) */
    }
    else if (!strcmp(argv[i], "--wave-api") && i + 1 < argc) {
      i++; g_wave_api = !strcmp(argv[i], "single") ? 0 : !strcmp(argv[i], "packet16") ? 1 : !strcmp(argv[i], "stream") ? 2 : 3;
    }
    else if (!strcmp(argv[i], "--scene") && i + 1 < argc) only_scene = argv[++i];
    else if (!strcmp(argv[i], "--integrator") && i + 1 < argc) { i++; only_integrator = cg_path = !strcmp(argv[i], "path") ? 1 : 0; }
    else if (!strcmp(argv[i], "--sampler") && i + 1 < argc) {
      cg_sampler = elr_sampler_kind_from_name(argv[++i]);
      if (cg_sampler <= 0) { fprintf(stderr, "bench_render: unknown sampler \"%s\"\n", argv[i]); return 1; }
    }
    else if (!strcmp(argv[i], "--ref-spp") && i + 1 < argc) ref_spp = atoi(argv[++i]);
    else if (!strcmp(argv[i], "--threads") && i + 1 < argc) threads = atoi(argv[++i]);
    else if (!strcmp(argv[i], "--callgrind") && i + 2 < argc) { cg_op = argv[++i]; cg_n = atoi(argv[++i]); }
    else { fprintf(stderr, "usage: bench_render [--quick] [--full] [--rays-only] [--packets] [--samplers [--scene bench_city|bench_studio] [--integrator directlighting|path]] [--ref-spp N] [--threads N] [--loops] [--split] [--callgrind intersect|occluded|samples|samples1 N [--sampler S] [--scene bench_studio] [--integrator path] [--loop one|wave] [--wave-api single|packet16|stream|soa]]\n"); return 1; }
  }
  if (ref_spp < 2) ref_spp = 2;
  setvbuf(stdout, NULL, _IOLBF, 0);
  if (samplers) { sampler_table(ref_spp, threads, quick, only_scene, only_integrator); return 0; }
  if (split_only) { split_table(threads, quick ? 1 : 3); return 0; }
  /* (--callgrind ... --scene bench_studio: the studio map's scene instead) */
  snprintf(path, sizeof path, "%s/scenes/%s.pbrt", EL_SOURCE_DIR, cg_op && only_scene ? only_scene : "bench_city");
  if (packets) setenv("ELR_EMBREE_SPHERES", "1", 1);
  if (elr_scene_load(path, &s, 1, err, sizeof err) != 0) { fprintf(stderr, "bench_render: %s\n", err); return 1; }
  w = s->d.xres; h = s->d.yres;
  if (packets) { packet_rates(s); elr_scene_free(s); return 0; }
  if (loops_only) { loop_table(s, quick ? 2 : 5, ELR_SAMPLER_ZSOBOL); elr_scene_free(s); return 0; }

  if (cg_op) {
    bray *cam = (bray *)malloc(sizeof(bray) * (size_t)w * h), *sh = (bray *)malloc(sizeof(bray) * (size_t)w * h);
    int nsh, k;
    volatile float sink = 0;
    camera_rays(s, cam);
    nsh = shadow_rays(s, cam, w * h, sh, w * h);
    if (!strcmp(cg_op, "intersect")) {
      for (k = 0; k < cg_n; k++) { float t; unsigned g; elr_raw_intersect(s, cam[k % (w * h)].o, cam[k % (w * h)].d, &t, &g); sink += t; }
    } else if (!strcmp(cg_op, "occluded")) {
      for (k = 0; k < cg_n && nsh > 0; k++) sink += (float)elr_occluded(s, sh[k % nsh].o, sh[k % nsh].d, INFINITY);
    } else if (!strcmp(cg_op, "samples") || !strcmp(cg_op, "samples1")) {
      g_no_batch = !strcmp(cg_op, "samples1");
      if (cg_n > 0) {
        elr_image img;
        elr_stats st;
        int rows = (cg_n / (cg_path ? 4 : 16) + w - 1) / w;
        if (rows > h) rows = h;
        /* the middle rows: sphere, plane and sky, like the whole image */
        /* half a pixel inside each bound: the film's ceil(res * fraction) gives the bound back whatever the
         * float rounding (117 / 240 * 240 rounds up to 118) */
        s->d.crop[2] = ((float)((h - rows) / 2) - 0.5f) / (float)h; s->d.crop[3] = ((float)((h - rows) / 2 + rows) - 0.5f) / (float)h;
        s->d.integrator_path = cg_path;
        if (render_once(s, cg_path ? 4 : 16, cg_sampler, ELR_LS_MIS, -1, -1, 1, 1, &img, &st) == 0) {
          printf("%llu camera samples, %llu shadow rays, %llu BSDF-sampled light rays\n", (unsigned long long)st.samples,
                 (unsigned long long)st.shadow_rays, (unsigned long long)st.bsdf_light_rays);
          elr_image_free(&img);
        }
      }
    } else { fprintf(stderr, "bench_render: unknown --callgrind operation \"%s\"\n", cg_op); return 1; }
    printf("%s x %d done (%g)\n", cg_op, cg_n, (double)sink);
    free(cam); free(sh); elr_scene_free(s);
    return 0;
  }

  printf("bench_render: %s, %d x %d, direct lighting\n\n", path, w, h);
  /* >> part 1: rays per second, one thread. Three rounds, each timing the raw calls and the loop back
   * to back; the best of each is kept (on a shared machine the minimum time is the least disturbed). */
  {
    bray *cam = (bray *)malloc(sizeof(bray) * (size_t)w * h), *sh = (bray *)malloc(sizeof(bray) * (size_t)w * h);
    int nsh, pass, round;
    double r_is = 0, r_oc = 0, t_loop = 1e30, ni = 0, no = 0, samples = 0, t_cell = 1e30, ni_c = 0, no_c = 0, t_one = 1e30;
    int same_image = 1;
    volatile float sink = 0;
    camera_rays(s, cam);
    nsh = shadow_rays(s, cam, w * h, sh, w * h);
    for (round = 0; round < 3; round++) {
      double t0, n_is = 0, n_oc = 0;
      elr_image img;
      elr_stats st;
      t0 = elr_now();
      for (pass = 0; elr_now() - t0 < 0.5 || pass < 2; pass++) {
        int k;
        for (k = 0; k < w * h; k++) { float t; unsigned g; elr_raw_intersect(s, cam[k].o, cam[k].d, &t, &g); sink += t; }
        n_is += w * h;
      }
      if (n_is / (elr_now() - t0) > r_is) r_is = n_is / (elr_now() - t0);
      t0 = elr_now();
      for (pass = 0; elr_now() - t0 < 0.5 || pass < 2; pass++) {
        int k;
        for (k = 0; k < nsh; k++) sink += (float)elr_occluded(s, sh[k].o, sh[k].d, INFINITY);
        n_oc += nsh;
      }
      if (n_oc / (elr_now() - t0) > r_oc) r_oc = n_oc / (elr_now() - t0);
      if (render_once(s, 16, ELR_SAMPLER_STRATIFIED, ELR_LS_MIS, -1, -1, 1, 1, &img, &st) == 0) {
        elr_image one;
        ni = (double)st.camera_rays + st.bounce_rays; no = (double)st.shadow_rays + st.bsdf_light_rays;
        samples = (double)st.samples;
        if (st.t_render < t_loop) t_loop = st.t_render;
        /* the same loop with each light sample drawn inside its own sample's shading (no batching) */
        g_no_batch = 1;
        if (render_once(s, 16, ELR_SAMPLER_STRATIFIED, ELR_LS_MIS, -1, -1, 1, 1, &one, &st) == 0) {
          if (st.t_render < t_one) t_one = st.t_render;
          same_image &= memcmp(one.rgb, img.rgb, sizeof(float) * 3 * (size_t)img.width * (size_t)img.height) == 0;
          elr_image_free(&one);
        }
        g_no_batch = 0;
        elr_image_free(&img);
      }
      /* the same loop sampling envlight's cell-average map (1x resolution: a quarter of the tables) */
      if (render_once(s, 16, ELR_SAMPLER_STRATIFIED, ELR_LS_MIS, -1, EL_ENVLIGHT_IMPORTANCE_CELL_AVERAGE, 1, 1, &img, &st) == 0) {
        ni_c = (double)st.camera_rays + st.bounce_rays; no_c = (double)st.shadow_rays + st.bsdf_light_rays;
        if (st.t_render < t_cell) t_cell = st.t_render;
        elr_image_free(&img);
      }
    }
    printf("Embree raw rates, 1 thread (ray arrays prepared beforehand; best of 3 rounds):\n");
    printf("  rtcIntersect1  camera rays through pixel centres      %7.2f M rays/s\n", r_is * 1e-6);
    printf("  rtcOccluded1   shadow rays towards env samples (%d)   %7.2f M rays/s\n", nsh, r_oc * 1e-6);
    if (t_loop < 1e30) {
      double raw_t = ni / r_is + no / r_oc;
      printf("\nrenderer, direct-lighting loop, 16 spp stratified + MIS, 1 thread (best of 3):\n");
      printf("  %.0f intersect + %.0f occlusion rays in %.3f s: %.2f M rays/s, %.2f M samples/s\n", ni, no, t_loop,
             (ni + no) / t_loop * 1e-6, samples / t_loop * 1e-6);
      printf("  Embree alone would take %.3f s for these rays: efficiency %.0f%% of raw (target >= 70%%)\n", raw_t,
             100.0 * raw_t / t_loop);
      if (t_one < 1e30)
        printf("  light samples one at a time (no_batch): %.3f s, efficiency %.0f%%; %s image\n", t_one, 100.0 * raw_t / t_one,
               same_image ? "the same" : "a DIFFERENT");
    }
    if (t_cell < 1e30) {
      double raw_t = ni_c / r_is + no_c / r_oc;
      printf("  the same loop sampling envlight's cell-average map: %.3f s, %.2f M samples/s, efficiency %.0f%%\n", t_cell,
             samples / t_cell * 1e-6, 100.0 * raw_t / t_cell);
    }
    (void)sink;
    free(cam); free(sh);
    printf("\n");
    loop_table(s, 3, ELR_SAMPLER_ZSOBOL);
  }
  /* >> part 2: relative MSE against time */
  if (!rays_only) {
    elr_image ref;
    elr_stats st;
    const char *snames[3] = {"random", "stratified", "halton"};
    const int samplers[3] = {ELR_SAMPLER_RANDOM, ELR_SAMPLER_STRATIFIED, ELR_SAMPLER_HALTON};
    /* importance map 1 = pbrt-v3's (the renderer's default), 0 = envlight's cell averages (--full) */
    const char *lnames[5] = {"MIS", "light only", "BSDF only", "MIS+compensated", "MIS+cell-avg map"};
    const int ls[5] = {ELR_LS_MIS, ELR_LS_LIGHT, ELR_LS_BSDF, ELR_LS_MIS, ELR_LS_MIS}, comp[5] = {0, 0, 0, 1, 0}, imp[5] = {1, 1, 1, 1, 0};
    int nopt = full ? 5 : 4;
    const int spps[3] = {16, 64, 256};
    int nspp = quick ? 2 : 3, a, b, c;
    double t0 = elr_now();
    /* the reference: stratified + MIS (its jitter and shuffles depend on the seed, so it is independent of
     * every image of the table; halton's pixel positions do not depend on the seed, as in pbrt-v3, and a
     * halton reference would share them with the halton rows) */
    if (render_once(s, ref_spp, ELR_SAMPLER_STRATIFIED, ELR_LS_MIS, 0, 1, threads, 1000, &ref, &st) != 0) return 1;
    printf("\nreference: stratified + MIS (pbrt-v3 importance map), %d spp, %.1f s (%d threads)\n", ref_spp, elr_now() - t0, st.nthreads);
    printf("relative MSE against it (seed differs from the reference's), wall time on %d threads:\n\n", st.nthreads);
    printf("  %-10s %-16s %5s %10s %8s %12s\n", "sampler", "light sampling", "spp", "relMSE", "time s", "relMSE x s");
    for (a = 0; a < 3; a++)
      for (b = 0; b < nopt; b++)
        for (c = 0; c < nspp; c++) {
          elr_image img;
          double t1 = elr_now(), t, e;
          if (render_once(s, spps[c], samplers[a], ls[b], comp[b], imp[b], threads, 7, &img, &st) != 0) continue;
          t = elr_now() - t1;
          e = relmse(img.rgb, ref.rgb, (size_t)img.width * img.height * 3);
          printf("  %-10s %-16s %5d %10.3g %8.3f %12.3g\n", snames[a], lnames[b], spps[c], e, t, e * t);
          fflush(stdout);
          elr_image_free(&img);
        }
    printf("\n(each relMSE also holds the reference's own noise: about the stratified + MIS 16-spp value x 16 / %d\n"
           " for independent noise, less with stratification)\n", ref_spp);
    elr_image_free(&ref);
  }
  elr_scene_free(s);
  return 0;
}
