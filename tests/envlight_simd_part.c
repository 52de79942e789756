/* envlight_simd_part.c: half of test_envlight_simd_scalar (not a test of its own: the glob takes
 * test_*.c only). The library built privately (EL_STATIC) as this translation unit's compile flags
 * say: once as is (SSE2 on x86), once with EL_NO_SIMD (tests/CMakeLists.txt), under the names
 * ELS_PART(draws). */
#if defined(__GNUC__) || defined(__clang__)
#pragma GCC diagnostic ignored "-Wunused-function" /* (EL_STATIC: the functions this part does not call) */
#endif
#define EL_STATIC
#define EL_IMPLEMENTATION
#include "envlight.h"
#include "envlight_simd_part.h"

#include <stdlib.h>
#include <string.h>

int ELS_PART(draws)(const float *px, int w, int h, const float m[9], const float *u, int n, float *out) {
  el_envlight l;
  el_envlight_options o;
  el_envlight_hotspots hs;
  el_envlight_mix_weights mw;
  el_envlight_mix_cos_table t;
  const float nrm[3] = {0.2f, 0.3f, 0.9f};
  int i, spots;
  memset(&o, 0, sizeof o);
  if (m) memcpy(o.light_to_world, m, sizeof o.light_to_world);
  if (el_envlight_init(&l, px, w, h, 3, &o) != EL_SUCCESS) return -1;
  if (el_envlight_hotspots_init(&hs, &l, NULL) != EL_SUCCESS) { el_envlight_free(&l); return -1; }
  el_envlight_hotspots_weights(&hs, 0.03f, &mw);
  el_envlight_mix_cos_prepare(&l, &hs, &mw, nrm, &t);
  for (i = 0; i < n; ++i) { /* per draw: sample_li, sample_li_mix, the rest x cosine mixture: wi, rgb, pdf */
    float *q = out + (size_t)i * ELS_FLOATS;
    el_envlight_sample_li(&l, u + 2 * i, q, q + 3, q + 6);
    el_envlight_sample_li_mix(&l, &hs, &mw, u + 2 * i, q + 7, q + 10, q + 13);
    el_envlight_sample_li_mix_cos_table(&l, &hs, &t, u + 2 * i, q + 14, q + 17, q + 20);
  }
  { /* product sampling n at once (normal (u1 - 0.5, u0 - 0.5, 0.3) per draw), then its pdf there */
    float *nv = (float *)malloc((size_t)n * 7 * sizeof(float)), *wi = nv + 3 * (size_t)n, *pd = wi + 3 * (size_t)n;
    if (!nv) { el_envlight_hotspots_free(&hs); el_envlight_free(&l); return -1; }
    for (i = 0; i < n; ++i) { nv[3 * i] = u[2 * i + 1] - 0.5f; nv[3 * i + 1] = u[2 * i] - 0.5f; nv[3 * i + 2] = 0.3f; }
    el_envlight_sample_li_cos_n(&l, n, nv, u, wi, NULL, pd);
    for (i = 0; i < n; ++i) { float *q = out + (size_t)i * ELS_FLOATS + 21; memcpy(q, wi + 3 * i, 3 * sizeof(float)); q[6] = pd[i]; }
    el_envlight_pdf_li_cos_n(&l, n, nv, wi, pd);
    for (i = 0; i < n; ++i) { /* (the rgb slot: the pdf at wi, 0, 0) */
      float *q = out + (size_t)i * ELS_FLOATS + 24;
      q[0] = pd[i]; q[1] = q[2] = 0.0f;
    }
    free(nv);
  }
  spots = hs.count;
  el_envlight_hotspots_free(&hs);
  el_envlight_free(&l);
  return spots;
}

int ELS_PART(pdf_le)(const float *px, int w, int h, const float m[9], const float *nrm, const float *dirs, int n, float *out) {
  el_envlight l;
  el_envlight_options o;
  float *buf = (float *)malloc((size_t)n * 4 * sizeof(float));
  int i;
  memset(&o, 0, sizeof o);
  if (m) memcpy(o.light_to_world, m, sizeof o.light_to_world);
  if (!buf || el_envlight_init(&l, px, w, h, 3, &o) != EL_SUCCESS) { free(buf); return -1; }
  el_envlight_pdf_li_cos_le_n(&l, n, nrm, dirs, buf, buf + n);
  for (i = 0; i < n; ++i) { out[4 * i] = buf[i]; memcpy(out + 4 * i + 1, buf + n + 3 * i, 3 * sizeof(float)); }
  free(buf);
  el_envlight_free(&l);
  return 0;
}
