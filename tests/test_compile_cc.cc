/* test_compile_cc.cc: every envlight header, with every implementation, in one C++ translation unit,
 * built twice (test_compile_cc as C++11, test_compile_cc17 as C++17) with -Wall -Wextra -Wconversion
 * -Wsign-conversion -Wshadow -Werror (see tests/CMakeLists.txt). Including each header twice proves the
 * include guards and the implementation once-guards; the calls below prove the declarations link.
 * test_compile_c.c does the same as C99.
 *
 * const_light() proves the const API from C++: it holds only a `const el_envlight &` and samples and
 * queries through it (the sampling tables are built lazily behind the const reference), and every init
 * takes its options as a const object (options are input only; what an init reports on failure,
 * bad_index, is a field of the object it initialised). */
#define EL_IMPLEMENTATION
#include "blockedarray.h"
#include "mipmap.h"
#include "distribution2d.h"
#include "envlight.h"
#include "film.h"
#include "blockedarray.h"
#include "mipmap.h"
#include "distribution2d.h"
#include "envlight.h"
#include "film.h"

#include <stdio.h>
#include <string.h>

static int failures = 0, passes = 0;
static void check(int ok, const char *what) {
  if (ok) passes++; else { failures++; printf("FAIL: %s\n", what); }
}

/* Sampling and queries through a const reference; the first query builds the tables. */
static void const_light(const el_envlight &light) {
  const float u[2] = {0.3f, 0.6f}, u4[4] = {0.7f, 0.2f, 0.5f, 0.5f}, un[6] = {0.1f, 0.2f, 0.3f, 0.4f, 0.5f, 0.6f};
  float wi[3], rgb[3], pdf, wn[9], rgbn[9], pdfn[3], org[3], dir[3], nrm[3], pp, pd, pp2, pd2, le[3];
  int i, same = 1;
  check(el_envlight_sampling_bytes(&light) == 0, "const light: no sampling tables before the first query");
  el_envlight_sample_li(&light, u, wi, rgb, &pdf);
  check(pdf > 0.0f && el_envlight_sampling_bytes(&light) > 0, "const light: sample_li builds the tables and samples");
  check(el_envlight_pdf_li(&light, wi) > 0.0f, "const light: pdf_li");
  el_envlight_sample_li_n(&light, 3, un, wn, rgbn, pdfn);
  for (i = 0; i < 3; ++i) {
    float w1[3], c1[3], p1;
    el_envlight_sample_li(&light, un + 2 * i, w1, c1, &p1);
    same &= (p1 == pdfn[i] && w1[0] == wn[3 * i] && c1[1] == rgbn[3 * i + 1]);
  }
  check(same != 0, "const light: sample_li_n equals sample_li");
  el_envlight_sample_le(&light, u4, org, dir, nrm, rgb, &pp, &pd);
  el_envlight_pdf_le(&light, dir, &pp2, &pd2);
  check(pp > 0.0f && pd > 0.0f && pp2 == pp, "const light: sample_le and pdf_le");
  el_envlight_le(&light, wi, le);
  check(le[0] > 0.0f, "const light: le");
}

int main(void) {
  float img[4 * 2 * 3], out[3], f[6] = {1, 2, 3, 4, 5, 6};
  int i;
  el_blockedarray ba;
  el_mipmap mm;
  el_distribution2d d2;
  el_envlight light;
  el_film film;
  el_film_options fo;
  float rgb[3] = {0.5f, 0.5f, 0.5f}, dir[3] = {0, 0, 1};
  for (i = 0; i < 24; i++) img[i] = 1.0f;

  memset(&ba, 0, sizeof ba);
  check(el_blockedarray_init(&ba, 4, 2, 3, 0, img) == EL_SUCCESS, "blockedarray init");
  check(el_blockedarray_at(&ba, 3, 1)[2] == 1.0f, "blockedarray access");
  el_blockedarray_free(&ba);

  check(el_mipmap_init(&mm, img, 4, 2, 3, NULL) == EL_SUCCESS, "mipmap init");
  el_mipmap_lookup(&mm, 0.3f, 0.7f, 0.1f, out);
  check(out[0] > 0.999f && out[0] < 1.001f, "mipmap trilinear of a constant image");
  el_mipmap_free(&mm);

  check(el_distribution2d_init(&d2, f, 3, 2, NULL) == EL_SUCCESS, "distribution2d init");
  check(el_distribution2d_pdf(&d2, 0.9f, 0.9f) > 0.0f, "distribution2d pdf");
  el_distribution2d_free(&d2);

  check(el_envlight_init(&light, img, 4, 2, 3, NULL) == EL_SUCCESS, "envlight init");
  el_envlight_le(&light, dir, out);
  check(out[1] > 0.999f && out[1] < 1.001f, "envlight le of a constant map");
  { /* product sampling: a sample above the normal's horizon whose pdf the pdf function repeats */
    float u[2] = {0.3f, 0.6f}, wi[3], L[3], p;
    el_envlight_sample_li_cos(&light, dir, u, wi, L, &p);
    check(p > 0.0f && p == el_envlight_pdf_li_cos(&light, dir, wi) && el_envlight_product_bytes(&light) > 0,
          "envlight sample_li_cos and pdf_li_cos agree");
  }
  el_envlight_free(&light);

  {
    /* const options everywhere; bad_index on the object after a failed init */
    const el_mipmap_options mo = {};
    const el_distribution_options dopt = {};
    const el_envlight_options eo = {};
    const float center[3] = {0.0f, 0.0f, 0.0f};
    float bad[4] = {1.0f, 2.0f, 3.0f, 4.0f};
    el_distribution1d d1;
    bad[2] = -1.0f;
    check(el_mipmap_init(&mm, img, 4, 2, 3, &mo) == EL_SUCCESS && mm.bad_index == -1, "mipmap init with const options");
    el_mipmap_free(&mm);
    check(el_distribution1d_init(&d1, bad, 4, &dopt) == EL_ERROR_NEGATIVE && d1.bad_index == 2,
          "distribution1d: const options, bad_index 2 on the object");
    check(el_distribution2d_init(&d2, bad, 2, 2, &dopt) == EL_ERROR_NEGATIVE && d2.bad_index == 2,
          "distribution2d: const options, bad_index 2 on the object");
    check(el_envlight_init(&light, img, 4, 2, 3, &eo) == EL_SUCCESS && light.bad_index == -1, "envlight init with const options");
    el_envlight_preprocess(&light, center, 1.0f);
    const_light(light);
    el_envlight_free(&light);
  }

  memset(&fo, 0, sizeof fo);
  fo.width = 4;
  fo.height = 4;
  check(el_film_init(&film, &fo) == EL_SUCCESS, "film init");
  el_film_add_sample(&film, 1.5f, 1.5f, rgb, 1.0f);
  el_film_free(&film);

  check(strcmp(el_result_string(EL_SUCCESS), "success") == 0, "el_result_string");
  printf("test_compile_cc (C++ %ld): %d passed, %d failed\n", (long)__cplusplus, passes, failures);
  return failures != 0;
}
