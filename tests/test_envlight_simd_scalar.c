/* test_envlight_simd_scalar.c: the header promises that EL_NO_SIMD gives the same results as the SSE2
 * code (the scalar code does the same operations in the same order). One program holds both builds
 * (envlight_simd_part.c compiled twice, EL_STATIC) and compares their bits: sample_li, sample_li_mix
 * and the rest x cosine mixture (wi, rgb, pdf), sample_li_cos_n and pdf_li_cos_n (four lanes against
 * the plain loop), pdf_li_cos_le_n (hostile normals and directions among random ones) on a 512 x 256 map with a sun (the direction tables),
 * under the identity (a signed permutation: the radiance at the sample's own (u, v)) and a general
 * rotation. Neither build is the reference: they must agree (before the fix of the mixtures' scalar
 * path, the rgb of the mixture samples differed under the identity). On a CPU without SSE2 both halves
 * are the scalar code and the test passes trivially (it says so). */
#include "envlight_simd_part.h"
#include "test_common.h"
#include "test_rng.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { W = 512, H = 256, N = 20000 };

int main(void) {
  static const char *part[4] = {"sample_li", "sample_li_mix", "sample_li_mix_cos_table", "sample_li_cos_n (the rgb: pdf_li_cos_n at wi)"};
  float rot[9], *px = (float *)malloc((size_t)W * H * 3 * sizeof(float)), *u = (float *)malloc(2 * (size_t)N * sizeof(float));
  float *a = (float *)malloc((size_t)N * ELS_FLOATS * sizeof(float)), *b = (float *)malloc((size_t)N * ELS_FLOATS * sizeof(float));
  rng r = rng_make(7);
  int i, mi, p, c;
  if (!px || !u || !a || !b) { check(0, "allocate"); return 1; }
  rotation37(rot);
  for (i = 0; i < W * H * 3; ++i) px[i] = 0.1f + (float)(((i / 3) * 7919) % 13) * 0.05f; /* a busy sky */
  for (c = 0; c < 3; ++c) px[3 * (60 * W + 200) + c] = 1e7f;                            /* and a sun */
  for (i = 0; i < 2 * N; ++i) u[i] = rng_f(&r);
#if !(defined(__SSE2__) || defined(_M_X64))
  printf("(no SSE2 in this build: both halves are the scalar code)\n");
#endif
  for (mi = 0; mi < 2; ++mi) {
    int sa = els_simd_draws(px, W, H, mi ? rot : NULL, u, N, a), sb = els_scalar_draws(px, W, H, mi ? rot : NULL, u, N, b);
    check(sa == 1 && sb == 1, "%s: one hot spot in each build (%d, %d)", mi ? "rotated" : "identity", sa, sb);
    for (p = 0; p < 4; ++p)
      for (c = 0; c < 3; ++c) { /* wi, rgb, pdf */
        int diff = 0, first = -1, off = 7 * p + 3 * c, len = c == 2 ? 1 : 3;
        for (i = 0; i < N; ++i)
          if (memcmp(a + (size_t)i * ELS_FLOATS + off, b + (size_t)i * ELS_FLOATS + off, (size_t)len * sizeof(float))) { diff++; if (first < 0) first = i; }
        check(diff == 0, "%s, %s: %s of the SSE2 and the EL_NO_SIMD builds bit-identical (%d of %d draws differ, first %d)",
              mi ? "rotated" : "identity", part[p], c == 0 ? "wi" : c == 1 ? "rgb" : "pdf", diff, N, first);
      }
  }
  { /* pdf_li_cos_le_n (issue 21): four lanes against the plain loops, random normals and directions of any
     * length, every seventh lane a zero, NaN, huge or non-unit one */
    float *nv = (float *)malloc(6 * (size_t)N * sizeof(float)), *dv = nv ? nv + 3 * (size_t)N : NULL, nan = 0.0f;
    volatile float z = 0.0f;
    nan = z / z;
    if (!nv) { check(0, "allocate"); return 1; }
    for (i = 0; i < 6 * N; ++i) nv[i] = (2.0f * rng_f(&r) - 1.0f) * (i % 5 == 0 ? 1e-3f : 1.0f);
    for (i = 0; i < 2 * N; i += 7) { /* i: a point of nv (i < N) or dv */
      float *q = nv + 3 * (size_t)i, h = (i / 7) % 4 == 0 ? 0.0f : (i / 7) % 4 == 1 ? nan : (i / 7) % 4 == 2 ? 3e38f : 1e-30f;
      q[i % 3] = h;
      if ((i / 7) % 4 == 0) q[0] = q[1] = q[2] = 0.0f;
    }
    for (mi = 0; mi < 2; ++mi) {
      int sa = els_simd_pdf_le(px, W, H, mi ? rot : NULL, nv, dv, N, a), sb = els_scalar_pdf_le(px, W, H, mi ? rot : NULL, nv, dv, N, b);
      int diff = 0, first = -1;
      check(sa == 0 && sb == 0, "pdf_li_cos_le_n: the lights initialise");
      for (i = 0; i < N; ++i)
        if (memcmp(a + 4 * (size_t)i, b + 4 * (size_t)i, 4 * sizeof(float))) { diff++; if (first < 0) first = i; }
      check(diff == 0, "%s, pdf_li_cos_le_n: pdf and rgb of the SSE2 and the EL_NO_SIMD builds bit-identical (%d of %d differ, first %d)",
            mi ? "rotated" : "identity", diff, N, first);
    }
    free(nv);
  }
  free(px); free(u); free(a); free(b);
  printf("test_envlight_simd_scalar: %d passed, %d failed\n", g_pass, g_fail);
  return g_fail ? 1 : 0;
}
