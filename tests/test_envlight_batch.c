/* test_envlight_batch.c: product sampling n at once (el_envlight_sample_li_cos_n, el_envlight_pdf_li_cos_n,
 * issue 20; el_envlight_pdf_li_n, el_envlight_le_n, issue 21) against the single calls, bit for bit:
 * every output (wi, rgb, pdf) of every lane equals what
 * el_envlight_sample_li_cos / el_envlight_pdf_li_cos return for that lane's inputs, compared as bytes
 * (a NaN or a -0 would differ). The single calls are the reference (test_envlight tests them against
 * mathematics); the batched calls run another code path (four lanes of SSE2), so the comparison can fail.
 *
 *   - lights: city and studio (the CC0 maps) under the identity, the y-up matrix (a signed permutation)
 *     and a general rotation (37 degrees about (1, 2, 3)); compensated studio; a one-texel sun at 1e12;
 *     a 2100 x 6 map (the coarse vertex grid: over 2048 columns); a 1 x 8 and an 8 x 1 map; an all-black
 *     map, a constant light and an equal-area map (the single calls' fallbacks);
 *   - the first batched call builds the tables (no query ran before);
 *   - normals: random directions of random lengths (2^-40 .. 2^40), and hostile lanes among ordinary
 *     ones: NaN, +-Inf, zero, -0, denormal, FLT_MAX components, the poles, the seam (y = +-0, x < 0),
 *     grazing; u at 0, 1 - ulp, 1, -0.25, 2 and NaN;
 *   - n = 0, 1, 2, 3, 4, 5, 17 and 45 (the tails of the four-lane blocks and of the 32-lane staged
 *     passes), rgb NULL and not;
 *   - pdf_li_cos_n on the sampled directions (equal to the returned pdfs: the round trip) and on hostile
 *     directions (NaN, zero, denormal, huge, non-unit);
 *   - el_envlight_pdf_li_n and el_envlight_le_n (issue 21: a wave's escaped rays) against pdf_li and le
 *     at the same random, hostile and sampled directions, n as above (the first call of a light's pdf
 *     builds its sampling tables);
 *   - el_envlight_pdf_li_cos_le_n (issue 21: an escaped ray's pdf and radiance in one pass) against
 *     pdf_li_cos and le at the same directions and normals (random, hostile, sampled), n as above.
 * Built twice: as is, and with EL_NO_SIMD (test_envlight_batch_scalar: the plain loop).
 */
#define EL_IMPLEMENTATION
#include "envlight.h"
#include "image_io.h"
#include "test_common.h"
#include "test_rng.h"

#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifndef EL_TEST_DATA_DIR
#define EL_TEST_DATA_DIR "data"
#endif

enum { NMAX = 64 };

/* studio.hdr and city.hdr from the test data; 0 (and a failed check) when either is missing */
static int load_maps(el_image *studio, el_image *city) {
  static const char *names[2] = {"studio.hdr", "city.hdr"};
  el_image *img[2];
  char path[512], err[512];
  int k;
  img[0] = studio; img[1] = city;
  memset(studio, 0, sizeof *studio);
  memset(city, 0, sizeof *city);
  for (k = 0; k < 2; ++k) {
    snprintf(path, sizeof path, "%s/envmaps/%s", EL_TEST_DATA_DIR, names[k]);
    if (el_image_load(path, img[k], err, sizeof err) != 0) {
      check(0, "load the test map %s (%s)", path, err);
      return 0;
    }
  }
  return 1;
}

static float nanf_(void) { volatile float z = 0.0f; return z / z; }

/* a random direction of random length: components in [-1, 1], scaled by 2^k, k in [-40, 40] */
static void random_normal(rng *r, float n[3]) {
  float s = ldexpf(1.0f, (int)(rng_u32(r) % 81u) - 40);
  int k;
  for (k = 0; k < 3; ++k) n[k] = (2.0f * rng_f(r) - 1.0f) * s;
}

/* lane i of a batch: most lanes random, some hostile (which depends on the batch's variant) */
static void hostile_normal(int which, float n[3]) {
  const float inf = FLT_MAX * 2.0f, nan = nanf_();
  static const float T[][3] = {{0, 0, 1}, {0, 0, -1}, {-1, 0, 0}, {-1, -0.0f, 0.3f}, {0.6f, -0.8f, 0}, {1e-40f, 0, 0},
                               {1e-40f, -1e-41f, 2e-40f}, {FLT_MAX, FLT_MAX, 1}, {FLT_MAX, -FLT_MAX, -FLT_MAX},
                               {0, 0, 0}, {-0.0f, -0.0f, -0.0f}, {3e38f, 1e-30f, -2e38f}, {1, 1e-7f, -1e-8f}};
  const int nt = (int)(sizeof T / sizeof T[0]);
  if (which < nt) { n[0] = T[which][0]; n[1] = T[which][1]; n[2] = T[which][2]; return; }
  n[0] = 0.3f; n[1] = 0.2f; n[2] = 0.1f;
  switch (which - nt) {
  case 0: n[1] = nan; break;
  case 1: n[0] = inf; break;
  case 2: n[2] = -inf; break;
  default: n[0] = nan; n[1] = nan; n[2] = nan; break;
  }
}
#define N_HOSTILE 17

/* one light: batches of every size, hostile lanes, both outputs against the single calls */
static void check_light(const char *name, el_envlight *l, uint64_t seed) {
  static const int sizes[] = {17, 0, 1, 2, 3, 4, 5, 45}; /* 17 first: the batched call builds the tables; 45: a
                                                                * full staged pass of 32 lanes and a tail */
  rng r = rng_make(seed);
  int rep, bad_s = 0, bad_p = 0, bad_trip = 0, bad_pl = 0, bad_le = 0, bad_cl = 0, batches = 0, lanes = 0, sampled = 0;
  for (rep = 0; rep < 800; ++rep) {
    float nrm[3 * NMAX], u[2 * NMAX], wa[3 * NMAX], wb[3 * NMAX], La[3 * NMAX], Lb[3 * NMAX], pa[NMAX], pb[NMAX];
    float dirs[3 * NMAX], qa[NMAX], qb[NMAX];
    int n = sizes[rep % 8], rgb = (rep / 8) % 2 == 0, i;
    for (i = 0; i < n; ++i) {
      random_normal(&r, nrm + 3 * i);
      u[2 * i] = rng_f(&r); u[2 * i + 1] = rng_f(&r);
    }
    if (rep % 3 == 1) /* hostile lanes among ordinary ones */
      for (i = 0; i < n; i += 2) hostile_normal((rep / 3 + i) % N_HOSTILE, nrm + 3 * i);
    if (rep % 5 == 2 && n >= 5) {
      const float uh[10] = {0.0f, 0.0f, 0x1.fffffep-1f, 0x1.fffffep-1f, 1.0f, 0.5f, -0.25f, 2.0f, nanf_(), 0.3f};
      memcpy(u, uh, sizeof uh);
    }
    memset(wa, 0x7f, sizeof wa); memset(La, 0x7f, sizeof La); memset(pa, 0x7f, sizeof pa);
    memcpy(wb, wa, sizeof wa); memcpy(Lb, La, sizeof La); memcpy(pb, pa, sizeof pa);
    el_envlight_sample_li_cos_n(l, n, nrm, u, wa, rgb ? La : NULL, pa);
    for (i = 0; i < n; ++i) el_envlight_sample_li_cos(l, nrm + 3 * i, u + 2 * i, wb + 3 * i, rgb ? Lb + 3 * i : NULL, pb + i);
    if (memcmp(wa, wb, sizeof wa) || memcmp(La, Lb, sizeof La) || memcmp(pa, pb, sizeof pa)) {
      if (bad_s++ < 3)
        for (i = 0; i < n; ++i)
          if (memcmp(wa + 3 * i, wb + 3 * i, 12) || memcmp(pa + i, pb + i, 4) || memcmp(La + 3 * i, Lb + 3 * i, 12)) {
            printf("  %s rep %d lane %d of %d: n (%g %g %g) u (%g %g): batched wi (%.9g %.9g %.9g) pdf %.9g, single (%.9g %.9g %.9g) %.9g\n",
                   name, rep, i, n, nrm[3 * i], nrm[3 * i + 1], nrm[3 * i + 2], u[2 * i], u[2 * i + 1], wa[3 * i], wa[3 * i + 1],
                   wa[3 * i + 2], pa[i], wb[3 * i], wb[3 * i + 1], wb[3 * i + 2], pb[i]);
            break;
          }
    }
    /* pdf_li_cos_n at the sampled directions: the returned pdfs (the round trip), and as pdf_li_cos */
    memset(qa, 0x7f, sizeof qa);
    el_envlight_pdf_li_cos_n(l, n, nrm, wb, qa);
    for (i = 0; i < n; ++i) {
      sampled += pb[i] > 0.0f;
      if (pb[i] > 0.0f && memcmp(qa + i, pb + i, 4)) ++bad_trip;
    }
    /* and at other directions: random ones (half of them below the surface), hostile ones */
    for (i = 0; i < n; ++i) random_normal(&r, dirs + 3 * i);
    if (rep % 3 == 2)
      for (i = 1; i < n; i += 2) hostile_normal((rep / 3 + i) % N_HOSTILE, dirs + 3 * i);
    memset(qa, 0x7f, sizeof qa); memset(qb, 0x7f, sizeof qb);
    el_envlight_pdf_li_cos_n(l, n, nrm, dirs, qa);
    for (i = 0; i < n; ++i) qb[i] = el_envlight_pdf_li_cos(l, nrm + 3 * i, dirs + 3 * i);
    if (memcmp(qa, qb, sizeof qa)) {
      if (bad_p++ < 3)
        for (i = 0; i < n; ++i)
          if (memcmp(qa + i, qb + i, 4)) {
            printf("  %s rep %d lane %d of %d: pdf_li_cos_n %.9g, pdf_li_cos %.9g\n", name, rep, i, n, qa[i], qb[i]);
            break;
          }
    }
    /* pdf_li_n and le_n at the same directions (random, hostile) and at the sampled ones, as pdf_li and le */
    for (i = 0; i < 2; ++i) {
      const float *dd = i ? wb : dirs;
      float La2[3 * NMAX], Lb2[3 * NMAX];
      int k;
      memset(qa, 0x7f, sizeof qa); memset(qb, 0x7f, sizeof qb); memset(La2, 0x7f, sizeof La2); memcpy(Lb2, La2, sizeof La2);
      el_envlight_pdf_li_n(l, n, dd, qa);
      el_envlight_le_n(l, n, dd, La2);
      for (k = 0; k < n; ++k) { qb[k] = el_envlight_pdf_li(l, dd + 3 * k); el_envlight_le(l, dd + 3 * k, Lb2 + 3 * k); }
      if (memcmp(qa, qb, sizeof qa) && bad_pl++ < 3)
        for (k = 0; k < n; ++k)
          if (memcmp(qa + k, qb + k, 4)) { printf("  %s rep %d lane %d of %d: pdf_li_n %.9g, pdf_li %.9g\n", name, rep, k, n, qa[k], qb[k]); break; }
      if (memcmp(La2, Lb2, sizeof La2) && bad_le++ < 3)
        for (k = 0; k < n; ++k)
          if (memcmp(La2 + 3 * k, Lb2 + 3 * k, 12)) { printf("  %s rep %d lane %d of %d: le_n %.9g, le %.9g\n", name, rep, k, n, La2[3 * k], Lb2[3 * k]); break; }
    }
    /* pdf_li_cos_le_n (issue 21: both lookups in one pass) at the same directions (random, hostile) and at
     * the sampled ones, with the same normals (hostile ones among them), as pdf_li_cos and le */
    for (i = 0; i < 2; ++i) {
      const float *dd = i ? wb : dirs;
      float La2[3 * NMAX], Lb2[3 * NMAX];
      int k;
      memset(qa, 0x7f, sizeof qa); memset(qb, 0x7f, sizeof qb); memset(La2, 0x7f, sizeof La2); memcpy(Lb2, La2, sizeof La2);
      el_envlight_pdf_li_cos_le_n(l, n, nrm, dd, qa, La2);
      for (k = 0; k < n; ++k) { qb[k] = el_envlight_pdf_li_cos(l, nrm + 3 * k, dd + 3 * k); el_envlight_le(l, dd + 3 * k, Lb2 + 3 * k); }
      if ((memcmp(qa, qb, sizeof qa) || memcmp(La2, Lb2, sizeof La2)) && bad_cl++ < 3)
        for (k = 0; k < n; ++k)
          if (memcmp(qa + k, qb + k, 4) || memcmp(La2 + 3 * k, Lb2 + 3 * k, 12)) {
            printf("  %s rep %d lane %d of %d: pdf_li_cos_le_n %.9g (%.9g %.9g %.9g), pdf_li_cos %.9g, le (%.9g %.9g %.9g)\n", name, rep, k, n,
                   qa[k], La2[3 * k], La2[3 * k + 1], La2[3 * k + 2], qb[k], Lb2[3 * k], Lb2[3 * k + 1], Lb2[3 * k + 2]);
            break;
          }
    }
    ++batches; lanes += n;
  }
  check(bad_cl == 0, "pdf_li_cos_le_n: %s: %d of %d batches bit-identical to pdf_li_cos and le", name, 2 * batches - bad_cl, 2 * batches);
  check(bad_pl == 0, "pdf_li_n: %s: %d of %d batches bit-identical to pdf_li", name, 2 * batches - bad_pl, 2 * batches);
  check(bad_le == 0, "le_n: %s: %d of %d batches bit-identical to le", name, 2 * batches - bad_le, 2 * batches);
  check(bad_s == 0, "sample_li_cos_n: %s: %d of %d batches (%d lanes) bit-identical to sample_li_cos", name, batches - bad_s, batches, lanes);
  check(bad_p == 0, "pdf_li_cos_n: %s: %d of %d batches bit-identical to pdf_li_cos", name, batches - bad_p, batches);
  check(bad_trip == 0, "pdf_li_cos_n: %s: the pdf of each of %d samples at its direction is the returned pdf (%d differ)", name, sampled, bad_trip);
}

static el_result make(el_envlight *l, const float *px, int w, int h, const float m[9], int comp, int mapping) {
  el_envlight_options o;
  memset(&o, 0, sizeof o);
  if (m) memcpy(o.light_to_world, m, sizeof o.light_to_world);
  o.compensated = comp;
  o.mapping = mapping;
  return el_envlight_init(l, px, w, h, 3, &o);
}

static void run(const char *name, const float *px, int w, int h, const float m[9], int comp, int mapping, uint64_t seed) {
  el_envlight l;
  if (make(&l, px, w, h, m, comp, mapping) != EL_SUCCESS) { check(0, "%s: the light initialises", name); return; }
  check_light(name, &l, seed); /* its first call builds the tables */
  el_envlight_free(&l);
}

int main(void) {
  el_image studio, city;
  float rot[9], yup[9], *sun, *coarse, *thin, black[16 * 8 * 3], ea[32 * 32 * 3];
  int i;
  if (!load_maps(&studio, &city)) return 1;
  rotation37(rot);
  el_envlight_yup_matrix(yup);
  run("city", city.pixels, city.width, city.height, NULL, 0, 0, 1);
  run("city y-up", city.pixels, city.width, city.height, yup, 0, 0, 2);
  run("city rotated", city.pixels, city.width, city.height, rot, 0, 0, 3);
  run("studio", studio.pixels, studio.width, studio.height, NULL, 0, 0, 4);
  run("studio rotated", studio.pixels, studio.width, studio.height, rot, 0, 0, 5);
  run("studio compensated", studio.pixels, studio.width, studio.height, NULL, 1, 0, 6);
  sun = (float *)malloc(256 * 128 * 3 * sizeof(float));
  coarse = (float *)malloc(2100 * 6 * 3 * sizeof(float));
  thin = (float *)malloc(8 * 3 * sizeof(float));
  if (!sun || !coarse || !thin) { check(0, "allocate the generated maps"); return 1; }
  for (i = 0; i < 256 * 128 * 3; ++i) sun[i] = (i / 3) / 256 < 64 ? 1.0f : 0.1f;
  sun[3 * (40 * 256 + 77)] = sun[3 * (40 * 256 + 77) + 1] = sun[3 * (40 * 256 + 77) + 2] = 1e12f;
  run("one-texel sun at 1e12, rotated", sun, 256, 128, rot, 0, 0, 7);
  for (i = 0; i < 2100 * 6; ++i) coarse[3 * i] = coarse[3 * i + 1] = coarse[3 * i + 2] = (float)(1 + (i * 7919) % 13) * (i % 2100 < 300 ? 100.0f : 1.0f);
  run("2100x6 (coarse grid)", coarse, 2100, 6, NULL, 0, 0, 8);
  for (i = 0; i < 8 * 3; ++i) thin[i] = (float)(1 + i % 5);
  run("1x8", thin, 1, 8, NULL, 0, 0, 9);
  run("8x1 rotated", thin, 8, 1, rot, 0, 0, 10);
  memset(black, 0, sizeof black);
  run("all black", black, 16, 8, NULL, 0, 0, 11);
  for (i = 0; i < 32 * 32 * 3; ++i) ea[i] = (float)(1 + (i * 31) % 17);
  run("equal-area 32x32", ea, 32, 32, NULL, 0, EL_ENVLIGHT_MAPPING_EQUAL_AREA, 12);
  { /* the constant light */
    el_envlight l;
    float c[3] = {0.5f, 1.0f, 2.0f};
    if (el_envlight_init_constant(&l, c, NULL) == EL_SUCCESS) { check_light("constant", &l, 13); el_envlight_free(&l); }
    else check(0, "constant: the light initialises");
  }
  free(sun); free(coarse); free(thin);
  el_image_free(&studio);
  el_image_free(&city);
  printf("test_envlight_batch: %d passed, %d failed\n", g_pass, g_fail);
  return g_fail ? 1 : 0;
}
