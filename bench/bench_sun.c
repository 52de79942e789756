#define EL_IMPLEMENTATION
#include "envlight.h"
#include "image_io.h"
#include <stdio.h>
#include <math.h>
#include <string.h>
int main(int argc, char **argv) {
  static const char *maps[5] = {"city", "forest", "night", "studio", "sunset"};
  float th[6] = {10, 30, 100, 300, 1000, 3000};
  int mi, t, k;
  for (mi = 0; mi < 5; ++mi) {
    char path[600], err[256]; el_image im; el_envlight l;
    snprintf(path, sizeof path, "/work/shared/envmaps/%s.exr", maps[mi]);
    if (el_image_load(path, &im, err, sizeof err) != 0) { printf("%s\n", err); continue; }
    el_envlight_init(&l, im.pixels, im.width, im.height, im.channels, NULL);
    printf("%s %dx%d\n", maps[mi], im.width, im.height);
    for (t = 0; t < 6; ++t) {
      el_envlight_hotspots h; el_envlight_hotspot_options o; memset(&o, 0, sizeof o);
      o.min_radiance = th[t]; o.min_share = argc > 1 ? (float)atof(argv[1]) : 0.01f; o.max_half_angle = 0.5f;
      el_result r = el_envlight_hotspots_init(&h, &l, &o);
      printf("  thr %5.0f: r=%d count %d rest %.3f |", th[t], r, h.count, h.rest_share);
      for (k = 0; k < h.count; ++k) printf(" [%.3f %.2fdeg %db ax(%.2f %.2f %.2f)]", h.spot[k].share, h.spot[k].half_angle * 57.2958, h.spot[k].bins, h.spot[k].axis[0], h.spot[k].axis[1], h.spot[k].axis[2]);
      printf("\n");
      el_envlight_hotspots_free(&h);
    }
    el_envlight_free(&l); el_image_free(&im);
  }
  return 0;
}
