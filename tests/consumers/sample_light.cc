// sample_light.cc: the C++ program of the consumer tests, the same 2 x 1 light as sample_light.c
// (which explains the expected numbers), compiled as C++ from the installed headers.
#define EL_IMPLEMENTATION
#include "envlight.h"
#include "film.h" // not used: proves the fifth header is installed and compiles as C++ too

#include <cmath>
#include <cstdio>
#include <cstring>
#include <vector>

int main() {
  const std::vector<float> px = {1, 1, 1, 3, 3, 3};
  el_envlight light;
  el_envlight_options opt;
  std::memset(&opt, 0, sizeof opt); // all zero: pbrt-v3's light
  if (el_envlight_init(&light, px.data(), 2, 1, 3, &opt) != EL_SUCCESS) {
    std::printf("FAIL: el_envlight_init on a 2 x 1 map\n");
    return 1;
  }
  int right = 0, bad = 0;
  for (int j = 0; j < 16; j++)
    for (int i = 0; i < 16; i++) {
      const float u[2] = {(i + 0.5f) / 16, (j + 0.5f) / 16};
      float wi[3], L[3], le[3], pdf;
      el_envlight_sample_li(&light, u, wi, L, &pdf);
      el_envlight_le(&light, wi, le);
      if (!(pdf > 0 && pdf < 1e3f) || std::fabs(L[0] - le[0]) > 1e-6f * le[0] || !(L[0] >= 1 && L[0] <= 3)) bad++;
      if (wi[1] < 0) right++;
    }
  el_envlight_free(&light);
  const bool ok = right == 160 && bad == 0;
  std::printf("%s: C++ consumer, %d of 256 samples in the bright half (160 expected), %d bad samples\n",
              ok ? "PASS" : "FAIL", right, bad);
  return ok ? 0 : 1;
}
