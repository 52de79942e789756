/* sample_light.c: the C program of the consumer tests (tests/consumers/run_consumer.cmake). It uses envlight
 * the way a project that found it with find_package or add_subdirectory does: one file defines
 * EL_IMPLEMENTATION, includes the headers from the include path the envlight::envlight target gave
 * it, builds a 2 x 1 environment light and samples it.
 *
 * The map: left texel 1, right texel 3 (grey). With the default importance (one bin per texel, the
 * cell average of the bilinear reconstruction) the bins weigh 3/4 * 1 + 2 * 1/8 * 3 = 1.5 and
 * 3/4 * 3 + 2 * 1/8 * 1 = 2.5, so the right half (u in [0.5, 1), phi in [pi, 2 pi), wi.y < 0) takes
 * 2.5 / 4 of the samples: of the 16 x 16 stratified samples below, the 10 columns with
 * u0 >= 0.375, that is 160 of 256. Every sample's radiance is el_envlight_le along it. */
#define EL_IMPLEMENTATION
#include "envlight.h"
#include "film.h" /* not used: proves the fifth header is installed and compiles here too */

#include <math.h>
#include <stdio.h>
#include <string.h>

int main(void) {
  const float px[6] = {1, 1, 1, 3, 3, 3};
  el_envlight light;
  el_envlight_options opt;
  int i, j, right = 0, bad = 0;
  memset(&opt, 0, sizeof opt); /* all zero: pbrt-v3's light */
  if (el_envlight_init(&light, px, 2, 1, 3, &opt) != EL_SUCCESS) {
    printf("FAIL: el_envlight_init on a 2 x 1 map\n");
    return 1;
  }
  for (j = 0; j < 16; j++)
    for (i = 0; i < 16; i++) {
      float u[2], wi[3], L[3], le[3], pdf;
      u[0] = (i + 0.5f) / 16; u[1] = (j + 0.5f) / 16;
      el_envlight_sample_li(&light, u, wi, L, &pdf);
      el_envlight_le(&light, wi, le);
      if (!(pdf > 0 && pdf < 1e3f) || fabsf(L[0] - le[0]) > 1e-6f * le[0] || !(L[0] >= 1 && L[0] <= 3)) bad++;
      if (wi[1] < 0) right++;
    }
  el_envlight_free(&light);
  printf("%s: C consumer, %d of 256 samples in the bright half (160 expected), %d bad samples\n",
         right == 160 && bad == 0 ? "PASS" : "FAIL", right, bad);
  return right == 160 && bad == 0 ? 0 : 1;
}
