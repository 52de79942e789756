/* test_compile_c.c: every envlight header, with every implementation, in one C99 translation unit
 * compiled with -std=c99 -Wall -Wextra -Wconversion -Wsign-conversion -Wshadow -pedantic -Werror (see
 * tests/CMakeLists.txt). Including each
 * header twice proves the include guards and the implementation once-guards; the calls below prove
 * the declarations link. test_compile_cc.cc does the same as C++. */
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

  memset(&fo, 0, sizeof fo);
  fo.width = 4;
  fo.height = 4;
  check(el_film_init(&film, &fo) == EL_SUCCESS, "film init");
  el_film_add_sample(&film, 1.5f, 1.5f, rgb, 1.0f);
  el_film_free(&film);

  check(strcmp(el_result_string(EL_SUCCESS), "success") == 0, "el_result_string");
  printf("test_compile_c: %d passed, %d failed\n", passes, failures);
  return failures != 0;
}
