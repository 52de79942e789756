/* test_render_samplers: each sampler's numbers are what pbrt's definitions say, and every sampler
 * renders the same image in expectation.
 *  1. Sobol' generator matrices (lowdiscrepancy.c, from Joe and Kuo's direction numbers): the first
 *     points of dimensions 0 and 1 (0, 1/2, 1/4, 3/4 ... and 0, 1/2, 3/4, 1/4, 5/8, 1/8, 3/8, 7/8),
 *     columns of dimensions 1, 2, 6, 100 and 1023 against SciPy's unscrambled Sobol' (an independent
 *     implementation of the same direction numbers) and, past 32 index bits, against pbrt-v3's table.
 *  2. SobolIntervalToIndex: for 2^m x 2^m images (m = 1..4), sample f of every pixel is the one point
 *     of block f (indices f 4^m .. (f + 1) 4^m - 1) inside the pixel, found by brute force; a few
 *     indices computed with pbrt-v3's own tables.
 *  3. Randomizations: after random digit permutation, fast Owen and Owen scrambling, the first 2^k
 *     points of dimensions 0 and 1 are still a (0, k, 2)-net (every elementary interval of area 2^-k,
 *     of every shape, holds exactly one point), the points moved, and other seeds move them elsewhere.
 *  4. Through the sampler interface, on an image whose sample bounds start at (-1, -1) as a wide filter
 *     makes them: every number in [0, 1), 40 dimensions deep; a pixel's film positions are a
 *     (0, k, 2)-net inside the pixel for sobol, 02sequence, zsobol and paddedsobol, their 2D dimensions
 *     (0, k, 2)-nets and their 1D dimensions stratified (02sequence within its `dimensions`); the sobol
 *     sampler's dimension 5 and up are the Sobol' coordinates of the brute-force index.
 *  5. Renders: for each sampler the same image on 1 and 3 threads and with other tile sizes; its image
 *     mean within 4 standard deviations of the random sampler's (sigma: the spread of the random
 *     sampler's image mean over 8 seeds at the same spp), for both integrators; pbrt-v3's sobol does not
 *     depend on --seed, its "randomization" does; a scene's "integer seed" replaces --seed.
 *  6. The Sampler directive: pixel counts rounded up to powers of two with a warning, the names
 *     "lowdiscrepancy" and "pmj02bn", bad parameters as errors naming file and line. */
#include "render_test_util.h"

/* >> point-set properties */
/* every elementary interval of area 1/n (n = 2^k; all shapes 2^-a x 2^-(k-a)) holds exactly one point */
static int is_net(const float *p, int n) {
  static int count[1 << 12];
  int k = 0, a, i;
  while ((1 << k) < n) k++;
  if ((1 << k) != n || n > (1 << 12)) return 0;
  for (a = 0; a <= k; a++) {
    int nx = 1 << a, ny = 1 << (k - a);
    memset(count, 0, sizeof(int) * (size_t)n);
    for (i = 0; i < n; i++) {
      int cx = (int)(p[2 * i] * (float)nx), cy = (int)(p[2 * i + 1] * (float)ny);
      if (p[2 * i] < 0.f || p[2 * i] >= 1.f || p[2 * i + 1] < 0.f || p[2 * i + 1] >= 1.f) return 0;
      count[cy * nx + cx]++;
    }
    for (i = 0; i < n; i++) if (count[i] != 1) return 0;
  }
  return 1;
}
static int is_stratified(const float *v, int n) {
  static int count[1 << 12];
  int i;
  memset(count, 0, sizeof(int) * (size_t)n);
  for (i = 0; i < n; i++) {
    if (!(v[i] >= 0.f && v[i] < 1.f)) return 0;
    count[(int)(v[i] * (float)n)]++;
  }
  for (i = 0; i < n; i++) if (count[i] != 1) return 0;
  return 1;
}

/* how many distinct values the XOR of the strata (of n) of two dimensions' values takes over a pixel's
 * n samples: 1 when one is the other's random digit scramble in the same order (two dimensions of an
 * unshuffled (0,2)-sequence), about 0.63 n for a random pairing */
static int distinct_xor(const float *a, const float *b, int n, int stride) {
  static unsigned char seen[1 << 12];
  int i, d = 0;
  memset(seen, 0, (size_t)n);
  for (i = 0; i < n; i++) {
    int x = ((int)(a[stride * i] * (float)n)) ^ ((int)(b[stride * i] * (float)n));
    if (x >= 0 && x < n && !seen[x]) { seen[x] = 1; d++; }
  }
  return d;
}

/* >> 1. the generator matrices */
static void test_matrices(void) {
  elr_sobol T;
  static const float d0[8] = {0.f, 0.5f, 0.25f, 0.75f, 0.125f, 0.625f, 0.375f, 0.875f};
  static const float d1[8] = {0.f, 0.5f, 0.75f, 0.25f, 0.625f, 0.125f, 0.375f, 0.875f};
  /* columns 0, 3, 12, 20 of dimensions 1, 2, 6, 100, 1023: SciPy 1.17's qmc.Sobol(d=1024, scramble=False,
   * bits=32) at the point whose Gray code is 2^j; columns 31, 32, 40, 51: pbrt-v3's SobolMatrices32 */
  static const int dims[5] = {1, 2, 6, 100, 1023}, cols[8] = {0, 3, 12, 20, 31, 32, 40, 51};
  static const uint32_t expect[8][5] = {
    {0x80000000u, 0x80000000u, 0x80000000u, 0x80000000u, 0x80000000u},
    {0xf0000000u, 0x90000000u, 0xd0000000u, 0x70000000u, 0xb0000000u},
    {0x88880000u, 0x80680000u, 0x46780000u, 0x1c080000u, 0xf3f80000u},
    {0x88008800u, 0x6868e800u, 0x9e78d800u, 0x2a003800u, 0xb32f7800u},
    {0xffffffffu, 0xc5005555u, 0xc0104477u, 0x29427f87u, 0x651de84du},
    {0x80000000u, 0x68808000u, 0xa0f86680u, 0xaa9e134du, 0xc09cfa24u},
    {0x80800000u, 0xe880e880u, 0x1e786680u, 0xd5880000u, 0x0ebd51a0u},
    {0xf000f000u, 0x90000000u, 0x33001010u, 0x175e4900u, 0x1397876eu}};
  int i, j, ok = 1, bad = 0;
  if (elr_sobol_init(&T, ELR_SOBOL_DIMS, 0) != 0) { rt_check(0, "elr_sobol_init"); return; }
  for (i = 0; i < 8; i++)
    ok &= elr_bits_to_float(elr_sobol_bits(&T, (uint64_t)i, 0)) == d0[i] && elr_bits_to_float(elr_sobol_bits(&T, (uint64_t)i, 1)) == d1[i];
  rt_check(ok, "unscrambled Sobol': dimension 0 is 0, 1/2, 1/4, 3/4, 1/8, ...; dimension 1 is 0, 1/2, 3/4, 1/4, 5/8, 1/8, 3/8, 7/8 (index order; in Gray-code order 3/8, 7/8, 5/8, 1/8)");
  for (j = 0; j < 8; j++)
    for (i = 0; i < 5; i++) {
      uint32_t c = elr_sobol_bits(&T, 1ull << cols[j], dims[i]);
      if (c != expect[j][i]) { if (bad++ < 3) printf("  dimension %d column %d: %08x, expected %08x\n", dims[i], cols[j], c, expect[j][i]); }
    }
  rt_check(bad == 0, "generator matrix columns against SciPy's Sobol' and pbrt-v3's table: %d of 40 differ", bad);
  /* index bits past the 52 columns are ignored, as pbrt's SobolSample */
  rt_check(elr_sobol_bits(&T, (1ull << 52) | 5u, 3) == elr_sobol_bits(&T, 5u, 3), "index bits past 52 are ignored");
  elr_sobol_free(&T);
}

/* >> 2. SobolIntervalToIndex */
static void test_interval_to_index(void) {
  int m, bad = 0, n = 0;
  elr_sobol T;
  for (m = 1; m <= 4; m++) {
    int x, y;
    uint64_t f;
    if (elr_sobol_init(&T, 2, m) != 0) { rt_check(0, "elr_sobol_init m = %d", m); return; }
    for (x = 0; x < (1 << m); x++)
      for (y = 0; y < (1 << m); y++)
        for (f = 0; f < 8; f++) {
          uint64_t i, found = ~0ull, got = elr_sobol_interval_to_index(&T, f, x, y);
          for (i = f << (2 * m); i < (f + 1) << (2 * m); i++) /* brute force: the point of block f in pixel (x, y) */
            if ((int)(elr_sobol_bits(&T, i, 0) >> (32 - m)) == x && (int)(elr_sobol_bits(&T, i, 1) >> (32 - m)) == y) {
              if (found != ~0ull) found = ~1ull; /* two points in one pixel: not a net */
              else found = i;
            }
          n++;
          if (got != found) { if (bad++ < 3) printf("  m %d pixel (%d, %d) sample %llu: index %llu, brute force %llu\n", m, x, y, (unsigned long long)f, (unsigned long long)got, (unsigned long long)found); }
        }
    if (m == 2) { /* computed with pbrt-v3's VdCSobolMatrices / VdCSobolMatricesInv */
      bad += elr_sobol_interval_to_index(&T, 0, 0, 1) != 12u; bad += elr_sobol_interval_to_index(&T, 0, 1, 0) != 10u;
      bad += elr_sobol_interval_to_index(&T, 4, 0, 0) != 68u; n += 3;
    }
    if (m == 3) {
      bad += elr_sobol_interval_to_index(&T, 1, 0, 0) != 120u; bad += elr_sobol_interval_to_index(&T, 2, 0, 0) != 136u;
      bad += elr_sobol_interval_to_index(&T, 3, 0, 0) != 240u; n += 3;
    }
    elr_sobol_free(&T);
  }
  rt_check(bad == 0, "SobolIntervalToIndex: sample f of each pixel is block f's point in it (brute force) and pbrt-v3's index (%d of %d differ)", bad, n);
  elr_sobol_init(&T, 2, 0);
  rt_check(elr_sobol_interval_to_index(&T, 5, 0, 0) == 5u, "a one-pixel image: sample f is index f (pbrt-v4; pbrt-v3 gives 0 for all)");
  elr_sobol_free(&T);
}

/* >> 3. randomizations keep the (0, 2)-sequence's stratification */
static void test_randomizations(void) {
  static const char *names[4] = {"none", "permutedigits", "fastowen", "owen"};
  static float p[2 * 4096], q[2 * 4096];
  elr_sobol T;
  int r, k;
  elr_sobol_init(&T, 2, 0);
  for (r = 0; r < 4; r++) {
    int nets = 0, tries = 0, moved = 1, differ = 1, inrange = 1;
    for (k = 2; k <= 12; k += 2) {
      int n = 1 << k, seed, i;
      for (seed = 1; seed <= 5; seed++) {
        uint32_t s0 = (uint32_t)elr_mix64((uint64_t)seed * 77u), s1 = (uint32_t)elr_mix64((uint64_t)seed * 91u + 3u);
        int same = 1, same2 = 1;
        for (i = 0; i < n; i++) {
          uint32_t a = elr_sobol_bits(&T, (uint64_t)i, 0), b = elr_sobol_bits(&T, (uint64_t)i, 1);
          p[2 * i] = elr_bits_to_float(elr_randomize(a, r, s0)); p[2 * i + 1] = elr_bits_to_float(elr_randomize(b, r, s1));
          q[2 * i] = elr_bits_to_float(elr_randomize(a, r, s0 ^ 0x1234567u));
          q[2 * i + 1] = elr_bits_to_float(elr_randomize(b, r, s1 ^ 0x7654321u));
          same &= p[2 * i] == elr_bits_to_float(a);
          same2 &= p[2 * i] == q[2 * i];
          inrange &= p[2 * i] >= 0.f && p[2 * i] < 1.f && p[2 * i + 1] >= 0.f && p[2 * i + 1] < 1.f;
        }
        nets += is_net(p, n) && is_net(q, n); tries++;
        if (r > 0) { moved &= !same; differ &= !same2; }
      }
    }
    rt_check(nets == tries && moved && differ && inrange,
             "randomization %s: 2^2..2^12 points of dimensions 0, 1 stay (0, k, 2)-nets (%d of %d), in [0, 1)%s", names[r], nets, tries,
             r ? ", moved, and moved elsewhere by another seed" : "");
  }
  /* Owen scrambling is nested: two points with the same first j digits keep them equal, and the digit
   * where they first differ stays different */
  {
    int ok = 1, j, t;
    for (t = 0; t < 2000; t++) {
      uint32_t a = (uint32_t)elr_mix64((uint64_t)t), b, sa, sb, seed = (uint32_t)elr_mix64((uint64_t)t + 99u);
      for (j = 0; j < 32 && ok; j += 5) {
        uint32_t mask = j ? ~0u << (32 - j) : 0u;
        b = (a & mask) | (~a & ~mask & (0x80000000u >> j)) | ((uint32_t)elr_mix64((uint64_t)t * 7u) & ~mask & ((0x80000000u >> j) - 1u));
        for (r = 2; r <= 3; r++) {
          sa = elr_randomize(a, r, seed); sb = elr_randomize(b, r, seed);
          ok &= (sa & mask) == (sb & mask) && (((sa ^ sb) >> (31 - j)) & 1u);
        }
      }
    }
    rt_check(ok, "fastowen and owen are nested scrambles: shared leading digits stay shared, the first differing digit stays different");
  }
  elr_sobol_free(&T);
}

/* >> 4. the samplers through the interface */
typedef struct tsamp { elr_sampler_desc d; elr_sampler_tables T; elr_sampler S; } tsamp;
static int tsamp_init(tsamp *t, int kind, int spp, int dims, int randomize, uint64_t seed) {
  static const int b[4] = {-1, -1, 21, 13}; /* a 20 x 12 image with a filter of radius 1.5 */
  memset(t, 0, sizeof *t);
  t->d.kind = kind; t->d.spp = spp; t->d.dims = dims; t->d.jitter = 1; t->d.randomize = randomize;
  if (kind == ELR_SAMPLER_STRATIFIED) { t->d.xs = 4; t->d.ys = spp / 4; }
  if (elr_sampler_tables_init(&t->T, &t->d, b, seed) != 0) return -1;
  return elr_sampler_init(&t->S, &t->d, seed, &t->T);
}
static void tsamp_free(tsamp *t) { elr_sampler_free(&t->S); elr_sampler_tables_free(&t->T); }

static void test_interface(void) {
  static const int kinds[7] = {ELR_SAMPLER_RANDOM, ELR_SAMPLER_STRATIFIED, ELR_SAMPLER_HALTON, ELR_SAMPLER_SOBOL, ELR_SAMPLER_ZEROTWO,
                               ELR_SAMPLER_ZSOBOL, ELR_SAMPLER_PADDEDSOBOL};
  static float film[2 * 256], d2[3][2 * 256], d1[2][256];
  int ki, spp_i;
  for (ki = 0; ki < 7; ki++)
    for (spp_i = 0; spp_i < 3; spp_i++) {
      static const int spps[3] = {8, 16, 64};
      int kind = kinds[ki], spp = spps[spp_i], nets = 1, strat = 1, inrange = 1, x, y, k, j, rnd, coupled = 0, total_pairs = 0;
      int ld = kind == ELR_SAMPLER_SOBOL || kind == ELR_SAMPLER_ZEROTWO || kind == ELR_SAMPLER_ZSOBOL || kind == ELR_SAMPLER_PADDEDSOBOL;
      int dims_net = kind == ELR_SAMPLER_ZEROTWO || kind == ELR_SAMPLER_ZSOBOL || kind == ELR_SAMPLER_PADDEDSOBOL;
      for (rnd = 0; rnd < (ld ? 3 : 1); rnd++) {
        static const int rz[3] = {ELR_RANDOMIZE_FAST_OWEN, ELR_RANDOMIZE_OWEN, ELR_RANDOMIZE_NONE};
        tsamp t;
        if (kind == ELR_SAMPLER_STRATIFIED && spp == 8) continue;
        if (tsamp_init(&t, kind, spp, 4, rz[rnd], 3) != 0) { rt_check(0, "sampler %s init", elr_sampler_kind_name(kind)); continue; }
        for (y = -1; y < 13; y += 3)
          for (x = -1; x < 21; x += 4) {
            elr_sampler_start_pixel(&t.S, x, y);
            for (k = 0; k < spp; k++) {
              float fx, fy, u[2];
              elr_sampler_camera_sample(&t.S, k, x, y, &fx, &fy);
              film[2 * k] = fx - (float)x; film[2 * k + 1] = fy - (float)y;
              /* the integrator's draws: 2D, 1D, 2D, 1D, 2D, then deeper ones (past pixel samplers' dimensions) */
              elr_sampler_get2d(&t.S, &d2[0][2 * k]); d1[0][k] = elr_sampler_get1d(&t.S);
              elr_sampler_get2d(&t.S, &d2[1][2 * k]); d1[1][k] = elr_sampler_get1d(&t.S);
              elr_sampler_get2d(&t.S, &d2[2][2 * k]);
              for (j = 0; j < 3; j++) inrange &= d2[j][2 * k] >= 0.f && d2[j][2 * k] < 1.f && d2[j][2 * k + 1] >= 0.f && d2[j][2 * k + 1] < 1.f;
              inrange &= film[2 * k] >= 0.f && film[2 * k] < 1.f && film[2 * k + 1] >= 0.f && film[2 * k + 1] < 1.f;
              for (j = 0; j < 30; j++) {
                float v = elr_sampler_get1d(&t.S);
                elr_sampler_get2d(&t.S, u);
                inrange &= v >= 0.f && v < 1.f && u[0] >= 0.f && u[0] < 1.f && u[1] >= 0.f && u[1] < 1.f;
              }
            }
            if (spp >= 16) { /* dimensions are paired at random (pbrt's shuffles, permutations): not one a function of the other */
              total_pairs++;
              coupled += distinct_xor(d1[0], d1[1], spp, 1) < spp / 4 || distinct_xor(d2[0], d2[1], spp, 2) < spp / 4;
            }
            if (ld) nets &= is_net(film, spp);
            if (dims_net) {
              for (j = 0; j < 3; j++) nets &= is_net(d2[j], spp);
              for (j = 0; j < 2; j++) strat &= is_stratified(d1[j], spp);
            }
          }
        tsamp_free(&t);
      }
      if (ld)
        rt_check(nets && strat && inrange, "%s, %d spp: numbers in [0, 1) 95 draws deep; film positions%s (0, k, 2)-nets in each pixel%s",
                 elr_sampler_kind_name(kind), spp, dims_net ? " and 2D dimensions" : "", dims_net ? ", 1D dimensions stratified" : "");
      else rt_check(inrange, "%s, %d spp: numbers in [0, 1) 95 draws deep", elr_sampler_kind_name(kind), spp);
      /* (not for sobol, whose dimensions are one sequence's coordinates, nor zsobol, which pairs them by
       * nested permutations of the digits of one index: some pixels have few distinct XORs, as pbrt-v4's) */
      if (spp >= 16 && kind != ELR_SAMPLER_SOBOL && kind != ELR_SAMPLER_ZSOBOL)
        rt_check(coupled == 0, "%s, %d spp: two 1D and two 2D dimensions of a pixel are not paired in a fixed way (%d of %d pixels: fewer than "
                 "spp / 4 distinct XORs of their strata)", elr_sampler_kind_name(kind), spp, coupled, total_pairs);
    }
  /* the sobol sampler's dimensions 5 and up are the Sobol' coordinates of the sample's index (pbrt-v3's
   * SampleDimension), the index found by brute force as in section 2 (image 20 x 12 in a 32 x 32 square) */
  {
    tsamp t;
    int bad = 0, x, y, k;
    tsamp_init(&t, ELR_SAMPLER_SOBOL, 4, 4, ELR_RANDOMIZE_NONE, 1);
    for (y = -1; y < 13; y += 5)
      for (x = -1; x < 21; x += 6) {
        elr_sampler_start_pixel(&t.S, x, y);
        for (k = 0; k < 4; k++) {
          float fx, fy, u[2], v;
          uint64_t i, idx = 0;
          elr_sampler_camera_sample(&t.S, k, x, y, &fx, &fy);
          elr_sampler_get2d(&t.S, u);
          v = elr_sampler_get1d(&t.S);
          for (i = (uint64_t)k << 10; i < (uint64_t)(k + 1) << 10; i++)
            if ((int)(elr_sobol_bits(&t.T.sobol, i, 0) >> 27) == x + 1 && (int)(elr_sobol_bits(&t.T.sobol, i, 1) >> 27) == y + 1) idx = i;
          bad += u[0] != elr_bits_to_float(elr_sobol_bits(&t.T.sobol, idx, 5)) || u[1] != elr_bits_to_float(elr_sobol_bits(&t.T.sobol, idx, 6)) ||
                 v != elr_bits_to_float(elr_sobol_bits(&t.T.sobol, idx, 7));
        }
      }
    rt_check(bad == 0, "sobol: the integrator's first draws are dimensions 5, 6, 7 of the pixel's brute-force index (%d wrong)", bad);
    tsamp_free(&t);
  }
}

/* >> 5. renders */
static void make_map(void) {
  static float m[3 * 64 * 32];
  char err[256];
  int x, y;
  for (y = 0; y < 32; y++)
    for (x = 0; x < 64; x++) {
      float sky = 0.3f + 1.0f * (1.0f - (float)y / 31.0f), sun = (abs(x - 20) <= 1 && abs(y - 9) <= 1) ? 30.f : 0.f;
      m[3 * (y * 64 + x)] = sky * 0.8f + sun; m[3 * (y * 64 + x) + 1] = sky * 0.9f + sun; m[3 * (y * 64 + x) + 2] = sky + sun * 0.7f;
    }
  if (el_image_write_pfm(rt_path("sky.pfm"), m, 64, 32, 3, err, sizeof err) != 0) printf("write: %s\n", err);
}
static elr_scene *load_scene(const char *sampler, const char *integ) {
  static char buf[4096];
  char err[512];
  elr_scene *s;
  snprintf(buf, sizeof buf,
           "LookAt 0 1.5 -4  0 0.6 0  0 1 0\nCamera \"perspective\" \"float fov\" [ 45 ]\n"
           "Film \"image\" \"integer xresolution\" [ 20 ] \"integer yresolution\" [ 14 ]\nPixelFilter \"gaussian\"\n%s\nIntegrator %s\n"
           "WorldBegin\nAttributeBegin\n  Rotate -90 1 0 0\n  LightSource \"infinite\" \"string mapname\" \"sky.pfm\"\nAttributeEnd\n"
           "AttributeBegin\n  Material \"plastic\" \"rgb Kd\" [ 0.4 0.3 0.2 ] \"rgb Ks\" [ 0.3 0.3 0.3 ] \"float roughness\" 0.05\n"
           "  Translate -0.6 0.6 0\n  Shape \"sphere\" \"float radius\" 0.6\nAttributeEnd\n"
           "AttributeBegin\n  Material \"matte\" \"rgb Kd\" [ 0.6 0.6 0.6 ]\n  Translate 0.7 0.5 0.2\n  Shape \"sphere\" \"float radius\" 0.5\nAttributeEnd\n"
           "AttributeBegin\n  Material \"matte\" \"rgb Kd\" [ 0.5 0.5 0.5 ]\n"
           "  Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point P\" [ -8 0 -8  8 0 -8  8 0 8  -8 0 8 ]\nAttributeEnd\nWorldEnd\n",
           sampler, integ);
  s = rt_load("samplers.pbrt", buf, err, sizeof err);
  if (!s) printf("load: %s\n", err);
  return s;
}
static int render_opts(elr_scene *s, int nthreads, int tile, uint64_t seed, elr_image *img) {
  elr_render_options o;
  elr_stats st;
  char err[512];
  elr_render_options_default(&o);
  o.nthreads = nthreads; o.tile_size = tile; o.seed = seed; o.quiet = 1;
  if (elr_render(s, &o, img, &st, err, sizeof err) != 0) { printf("render: %s\n", err); return -1; }
  return 0;
}
static double image_mean(const elr_image *a) {
  double m = 0;
  int i;
  for (i = 0; i < a->width * a->height * 3; i++) m += a->rgb[i];
  return m / (a->width * a->height * 3);
}
static int same_image(const elr_image *a, const elr_image *b) {
  return a->width == b->width && a->height == b->height && memcmp(a->rgb, b->rgb, sizeof(float) * 3 * (size_t)a->width * (size_t)a->height) == 0;
}

static void test_renders(void) {
  static const char *samplers[7] = {
    "Sampler \"random\" \"integer pixelsamples\" 64", "Sampler \"stratified\" \"integer xsamples\" 8 \"integer ysamples\" 8",
    "Sampler \"halton\" \"integer pixelsamples\" 64", "Sampler \"sobol\" \"integer pixelsamples\" 64",
    "Sampler \"02sequence\" \"integer pixelsamples\" 64", "Sampler \"zsobol\" \"integer pixelsamples\" 64",
    "Sampler \"paddedsobol\" \"integer pixelsamples\" 64"};
  static const char *integs[2] = {"\"directlighting\"", "\"path\" \"integer maxdepth\" 4"};
  int ig, k;
  make_map();
  for (ig = 0; ig < 2; ig++) {
    double ref = 0, ref2 = 0, sigma;
    elr_scene *s = load_scene(samplers[0], integs[ig]);
    elr_image img;
    if (!s) { rt_check(0, "scene"); return; }
    for (k = 0; k < 8; k++) { /* the random sampler's image mean over 8 seeds */
      double m;
      if (render_opts(s, 2, 0, 100 + (uint64_t)k, &img) != 0) { rt_check(0, "render"); elr_scene_free(s); return; }
      m = image_mean(&img); ref += m; ref2 += m * m;
      elr_image_free(&img);
    }
    elr_scene_free(s);
    ref /= 8; sigma = sqrt(fmax(ref2 / 8 - ref * ref, 0.0) * 8.0 / 7.0);
    for (k = 0; k < 7; k++) {
      elr_image a, b, c;
      int ok;
      double m;
      s = load_scene(samplers[k], integs[ig]);
      if (!s) { rt_check(0, "scene %d", k); continue; }
      if (render_opts(s, 1, 0, 7, &a) != 0) { elr_scene_free(s); rt_check(0, "render"); continue; }
      ok = render_opts(s, 3, 0, 7, &b) == 0 && same_image(&a, &b);
      if (ok) { elr_image_free(&b); ok = render_opts(s, 2, 5, 7, &b) == 0 && same_image(&a, &b); }
      rt_check(ok, "%s, %s: the same image on 1 and 3 threads, and with 5 x 5-pixel tiles on 2", samplers[k], integs[ig]);
      elr_image_free(&b);
      m = image_mean(&a);
      rt_check(fabs(m - ref) <= 4.0 * sigma * sqrt(1.0 + 1.0 / 8.0),
               "%s, %s: image mean %.5f, the random sampler's %.5f (over 8 seeds, sigma %.5f): within 4 sigma", samplers[k], integs[ig], m, ref,
               sigma);
      if (render_opts(s, 2, 0, 8, &c) == 0) {
        /* pbrt-v3's sobol is not randomized: the seed changes nothing; every other sampler's image moves */
        if (k == 3) rt_check(same_image(&a, &c), "sobol (pbrt-v3, no randomization): --seed does not change the image");
        else rt_check(!same_image(&a, &c), "%s: another --seed gives another image", samplers[k]);
        elr_image_free(&c);
      }
      elr_image_free(&a);
      elr_scene_free(s);
    }
  }
  { /* the scene's randomization and seed */
    elr_scene *s = load_scene("Sampler \"sobol\" \"integer pixelsamples\" 16 \"string randomization\" \"owen\"", integs[0]);
    elr_image a, b;
    if (s && render_opts(s, 2, 0, 1, &a) == 0) {
      if (render_opts(s, 2, 0, 2, &b) == 0) { rt_check(!same_image(&a, &b), "sobol with \"randomization\" \"owen\": --seed changes the image"); elr_image_free(&b); }
      elr_image_free(&a);
    }
    elr_scene_free(s);
    s = load_scene("Sampler \"zsobol\" \"integer pixelsamples\" 16 \"integer seed\" 5", integs[0]);
    if (s && render_opts(s, 2, 0, 1, &a) == 0) {
      if (render_opts(s, 2, 0, 2, &b) == 0) { rt_check(same_image(&a, &b), "zsobol with \"integer seed\" 5: the scene's seed replaces --seed"); elr_image_free(&b); }
      elr_image_free(&a);
    }
    elr_scene_free(s);
  }
}

/* >> 7. zsobol's fast path (per-pixel tables, sampler_zsobol.c) gives the reference's bits: every
 * sample count it takes (1 .. 256, odd and even powers of two) and one past it, every randomization, 1D
 * and 2D draws mixed, dimensions past its 64, samples in a scrambled order and pixels revisited, far
 * apart and along rows, by two samplers that share their last pixels' digits (elr_sampler_share), with
 * each fastowen loop the CPU runs (plain, SSE2, AVX2); and
 * the rendered image is the same bit for bit (direct lighting and path, reference path forced with
 * ELR_ZSOBOL_REFERENCE). */
static void test_zsobol_fast(void) {
  static const int rz[4] = {ELR_RANDOMIZE_NONE, ELR_RANDOMIZE_PERMUTE_DIGITS, ELR_RANDOMIZE_FAST_OWEN, ELR_RANDOMIZE_OWEN};
  int L, r, bad = 0, fast_used = 0, draws = 0, simd, nsimd = elr_zsobol_simd(), runs = 0;
  /* fastowen's loops: AVX2, SSE2 and the plain one, each that this CPU runs */
  for (simd = 0; simd <= nsimd; simd++) for (L = 0; L <= 9; L++)
    for (r = 0; r < 4; r++) {
      int spp = 1 << L, x, y, k, j, pass, npix = 0;
      tsamp a, b, c;
      if (rz[r] != ELR_RANDOMIZE_FAST_OWEN && simd < nsimd) continue;
      if (tsamp_init(&a, ELR_SAMPLER_ZSOBOL, spp, 4, rz[r], 11) != 0 || tsamp_init(&b, ELR_SAMPLER_ZSOBOL, spp, 4, rz[r], 11) != 0 ||
          tsamp_init(&c, ELR_SAMPLER_ZSOBOL, spp, 4, rz[r], 11) != 0) {
        rt_check(0, "zsobol init"); return;
      }
      runs++;
      fast_used += a.S.zlow != NULL && a.S.zsimd == nsimd;
      a.S.zsimd = c.S.zsimd = simd;
      elr_sampler_share(&c.S, &a.S); /* a and c take pixels in turn, as the wave's samplers do */
      for (pass = 0; pass < 3; pass++) /* pixels far apart, then (pass 2) along rows */
        for (y = -1; y < (pass < 2 ? 13 : 3); y += pass < 2 ? 5 + pass : 3)
          for (x = -1; x < 21; x += pass < 2 ? 7 - pass : 1) {
            elr_sampler *f = npix++ % 3 == 2 ? &c.S : &a.S;
            elr_sampler_start_pixel(f, x, y);
            elr_sampler_start_pixel(&b.S, x, y);
            for (k = 0; k < spp && k < (pass < 2 ? 64 : 16); k++) {
              int sample = (int)(((unsigned)k * 37u + (unsigned)pass * 5u) & (unsigned)(spp - 1)); /* not in order */
              float fa, fb, ga, gb;
              elr_sampler_camera_sample(f, sample, x, y, &fa, &ga);
              elr_sampler_camera_sample(&b.S, sample, x, y, &fb, &gb);
              bad += memcmp(&fa, &fb, sizeof fa) != 0 || memcmp(&ga, &gb, sizeof ga) != 0;
              for (j = 5; j < 72; j++) {
                float u[2], v[2];
                if ((j * 7 + k) % 3 == 0) {
                  u[0] = elr_zsobol_1d(f, j); v[0] = elr_zsobol_ref_1d(&b.S, j);
                  bad += memcmp(u, v, sizeof(float)) != 0;
                } else {
                  elr_zsobol_2d(f, j, u); elr_zsobol_ref_2d(&b.S, j, v);
                  bad += memcmp(u, v, sizeof u) != 0;
                }
                draws++;
              }
            }
          }
      tsamp_free(&a); tsamp_free(&b); tsamp_free(&c);
    }
  rt_check(bad == 0 && fast_used == runs - 4 - nsimd, "zsobol: the fast path's numbers are the reference's bit for bit (%d of %d draws differ; "
           "fast path used for %d of %d sample counts x randomizations x SIMD loops up to 256 spp; the widest SIMD loop %d)",
           bad, draws, fast_used, runs - 4 - nsimd, nsimd);
  { /* the largest sample count a render takes (2^24): the tables' digit points are made for every level,
     * at index bits up to 24 + 2 x 23 = 70; bits past the 52 Sobol' columns add nothing (a shift of 64 or
     * more was undefined: the sanitizer build stops on it) */
    tsamp t;
    int j, v, nonzero = 0;
    if (tsamp_init(&t, ELR_SAMPLER_ZSOBOL, 1 << 24, 4, ELR_RANDOMIZE_FAST_OWEN, 5) != 0) rt_check(0, "zsobol init at 2^24 spp");
    else {
      for (j = (ELR_SOBOL_COLUMNS - 24) / 2; j < ELR_ZSOBOL_LEVELS; j++)
        for (v = 0; v < 4; v++) nonzero += t.T.zdig[0][j][v] != 0 || t.T.zdig[1][j][v] != 0;
      rt_check(nonzero == 0 && t.S.zlow == NULL, "zsobol at 2^24 spp: the digit points past the Sobol' columns are 0 (%d of %d are not), "
               "no fast path", nonzero, 4 * (ELR_ZSOBOL_LEVELS - (ELR_SOBOL_COLUMNS - 24) / 2));
      tsamp_free(&t);
    }
  }
  {
    static const char *integs[2] = {"\"directlighting\"", "\"path\" \"integer maxdepth\" 4"};
    int ig;
    make_map();
    for (ig = 0; ig < 2; ig++) {
      elr_scene *s = load_scene("Sampler \"zsobol\" \"integer pixelsamples\" 32", integs[ig]);
      elr_image fa, rf;
      if (!s) { rt_check(0, "scene"); continue; }
      if (render_opts(s, 2, 0, 7, &fa) == 0) {
        setenv("ELR_ZSOBOL_REFERENCE", "1", 1);
        if (render_opts(s, 2, 0, 7, &rf) == 0) {
          rt_check(same_image(&fa, &rf), "zsobol, %s: the fast path's image is the reference path's bit for bit", integs[ig]);
          elr_image_free(&rf);
        }
        unsetenv("ELR_ZSOBOL_REFERENCE");
        elr_image_free(&fa);
      }
      elr_scene_free(s);
    }
  }
}

/* >> 6. the Sampler directive */
static void test_parser(void) {
  static const char *bad[][2] = { /* the directive, a word the error must contain */
    {"Sampler \"zsobol\" \"string randomization\" \"bogus\"", "unknown randomization"},
    {"Sampler \"sobol\" \"integer pixelsamples\" 0", "pixelsamples"},
    {"Sampler \"02sequence\" \"integer dimensions\" 65", "dimensions"},
    {"Sampler \"02sequence\" \"integer pixelsamples\" 8388608", "MiB"},
    {"Sampler \"paddedsobol\" \"float seed\" 3", "seed"},
    {"Sampler \"sobol\" \"integer pixelsamples\" 16777217", "exceed 16777216"},
  };
  char err[512], text[1024];
  elr_scene *s;
  int i;
  for (i = 0; i < (int)(sizeof bad / sizeof bad[0]); i++) {
    snprintf(text, sizeof text, "Film \"image\" \"integer xresolution\" 8 \"integer yresolution\" 8\n\n%s\nWorldBegin\nWorldEnd\n", bad[i][0]);
    s = rt_load("bad.pbrt", text, err, sizeof err);
    rt_check(!s && strstr(err, "bad.pbrt:3: error:") && strstr(err, bad[i][1]), "%s: an error at bad.pbrt:3 (%s)", bad[i][0], s ? "loaded" : err);
    elr_scene_free(s);
  }
  {
    static const char *good[][3] = { /* directive, sampler name, spp */
      {"Sampler \"sobol\" \"integer pixelsamples\" 37", "sobol", "64"},
      {"Sampler \"02sequence\" \"integer pixelsamples\" 5", "02sequence", "8"},
      {"Sampler \"lowdiscrepancy\"", "02sequence", "16"},
      {"Sampler \"zsobol\" \"integer pixelsamples\" 100", "zsobol", "128"},
      {"Sampler \"paddedsobol\" \"integer pixelsamples\" 100", "paddedsobol", "100"},
      {"Sampler \"pmj02bn\" \"integer pixelsamples\" 16", "zsobol", "16"},
      {"Sampler \"maxmindist\"", "halton", "16"},
      {"Sampler \"sobol\"", "sobol", "16"},
    };
    for (i = 0; i < (int)(sizeof good / sizeof good[0]); i++) {
      elr_image img;
      elr_stats st;
      elr_render_options o;
      int warn_expected = i == 0 || i == 1 || i == 3 || i == 5 || i == 6;
      snprintf(text, sizeof text, "Film \"image\" \"integer xresolution\" 4 \"integer yresolution\" 4\n%s\nWorldBegin\nLightSource \"point\"\nWorldEnd\n", good[i][0]);
      s = rt_load("good.pbrt", text, err, sizeof err);
      if (!s) { rt_check(0, "%s: %s", good[i][0], err); continue; }
      elr_render_options_default(&o); o.quiet = 1; o.nthreads = 1;
      if (elr_render(s, &o, &img, &st, err, sizeof err) == 0) {
        rt_check(!strcmp(elr_sampler_kind_name(st.sampler), good[i][1]) && st.spp == atoi(good[i][2]) &&
                 (warn_expected ? strstr(elr_scene_last_warning(s), "good.pbrt:2: warning:") != NULL : elr_scene_warnings(s) == 0),
                 "%s: renders with %s at %d spp%s%s", good[i][0], elr_sampler_kind_name(st.sampler), st.spp, warn_expected ? "; warning " : "",
                 warn_expected ? elr_scene_last_warning(s) : "");
        elr_image_free(&img);
      } else rt_check(0, "%s: %s", good[i][0], err);
      /* --spp and --sampler: the power of two above, pbrt's defaults for a sampler the scene did not name */
      o.spp = 20; o.sampler = ELR_SAMPLER_ZSOBOL;
      if (elr_render(s, &o, &img, &st, err, sizeof err) == 0) {
        if (i == 0) rt_check(st.spp == 32 && st.sampler == ELR_SAMPLER_ZSOBOL, "--sampler zsobol --spp 20: zsobol at 32 spp (%d)", st.spp);
        elr_image_free(&img);
      }
      elr_scene_free(s);
    }
  }
}

int main(void) {
  rt_mkdir("test_render_samplers");
  test_matrices();
  test_interval_to_index();
  test_randomizations();
  test_interface();
  test_renders();
  test_zsobol_fast();
  test_parser();
  return rt_finish("test_render_samplers");
}
