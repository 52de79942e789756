/* test_path_tracer.c: examples/00_path_tracer.cc, the path tracer students copy, renders right.
 *
 * It runs the built program (EL_BIN_DIR/00_path_tracer) at tiny sizes and reads back what it wrote:
 *  1. The furnace (00_path_tracer --furnace): one white diffuse sphere (albedo 1) fills the frame under
 *     a sky of radiance 1 + 0.75 P3(cos theta). The cosine lobe has no l = 3 part (Funk-Hecke:
 *     integral_0^1 P3(t) t dt = 0), so the exact value of every pixel is 1, as under a constant sky of
 *     1. The 64-row map that the example builds from that formula (bilinear between row centres) moves
 *     it by at most 3.0e-4 (a quadrature of the reconstructed map over the sphere, normals at 0..180
 *     degrees). The sky's importance sampling is far from uniform (its pdf varies 7:1), so a wrong MIS
 *     weight, a wrong light pdf or a wrong cosine pdf gives the wrong mean (each was tried, see below).
 *     Checked: every value finite; the mean of all 48 x 48 pixels within 0.5% of 1 (the Monte Carlo
 *     error of that mean is about 0.08% at 64 spp: 2.3% per pixel, about 800 independent pixels under
 *     the Gaussian filter); every pixel within 15% (6.5 sigma of one pixel; the worst is 8.3%).
 *  2. The default scene (city.hdr, 64 x 36, 4 spp) to .pfm: every value finite, not black (mean
 *     > 0.05), not flat, and a second run writes the same file byte for byte (deterministic).
 *  3. The same to .png: it loads, with the size asked for, and is not black.
 * Each mistake below, put into the example, fails check 1 (the mean it gave in brackets; 1.00008
 * without it): the escaped ray weighted 1 instead of by the power heuristic (1.200); the escaped ray's
 * pdf_li replaced by the uniform 1 / 4 pi (1.019: a constant sky could not see this one); the light
 * sample's weight computed with cos instead of cos / pi (0.839); the escaped ray's weight with its two
 * pdfs swapped (0.400); the cosine sample's pdf without its 1 / pi (1.161); the balance heuristic for
 * the escaped ray but the power heuristic for the light sample (0.889). The furnace runs in both of the
 * example's modes: product sampling (its default) and --plain; in product mode, weighting the escaped
 * ray with pdf_li instead of pdf_li_cos (the light's density without the normal) gives 1.297.
 * Skipped (ctest SKIP, exit 77) when the examples are not built. */
#include "image_io.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifndef EL_BIN_DIR
#define EL_BIN_DIR "bin"
#endif
#ifndef EL_HAVE_EXAMPLES
#define EL_HAVE_EXAMPLES 1
#endif

static int g_pass, g_fail;
static void check(int ok, const char *what) {
  if (ok) g_pass++;
  else g_fail++;
  printf("%s: %s\n", ok ? "PASS" : "FAIL", what);
}

/* Runs 00_path_tracer with args; 0 when it exited with 0. */
static int run(const char *args) {
  char cmd[1024];
  snprintf(cmd, sizeof cmd, "\"%s/00_path_tracer\" %s", EL_BIN_DIR, args);
  printf("  running %s\n", cmd);
  fflush(stdout);
  return system(cmd) == 0 ? 0 : -1;
}

/* Loads path; prints why and returns -1 when it cannot. */
static int load(const char *path, el_image *im) {
  char err[512];
  memset(im, 0, sizeof *im);
  if (el_image_load(path, im, err, sizeof err) != 0) {
    printf("  %s\n", err);
    return -1;
  }
  return 0;
}

static int all_finite(const el_image *im) {
  size_t i, n = (size_t)im->width * (size_t)im->height * (size_t)im->channels;
  for (i = 0; i < n; i++)
    if (!isfinite(im->pixels[i])) return 0;
  return 1;
}

static double mean(const el_image *im) {
  size_t i, n = (size_t)im->width * (size_t)im->height * (size_t)im->channels;
  double s = 0;
  for (i = 0; i < n; i++) s += im->pixels[i];
  return n ? s / (double)n : 0.0;
}

/* plain: 00_path_tracer --plain (sample_li / pdf_li); else its default, product sampling (sample_li_cos /
 * pdf_li_cos with the previous hit's normal): the furnace checks each mode's MIS weights and pdfs */
static void test_furnace(int plain) {
  el_image im;
  char msg[256];
  const char *mode = plain ? "furnace, plain light sampling" : "furnace, product sampling";
  size_t i, n, worst_i = 0;
  double m, worst = 0;
  snprintf(msg, sizeof msg, "%s: 00_path_tracer %s--furnace runs", mode, plain ? "--plain " : "");
  check(run(plain ? "--plain --furnace test_path_tracer_furnace.pfm 64 48 48" : "--furnace test_path_tracer_furnace.pfm 64 48 48") == 0, msg);
  if (load("test_path_tracer_furnace.pfm", &im) != 0) {
    check(0, "furnace: its picture loads");
    return;
  }
  check(im.width == 48 && im.height == 48 && im.channels == 3, "furnace: 48 x 48 RGB");
  check(all_finite(&im), "furnace: every value finite");
  n = (size_t)im.width * (size_t)im.height * 3;
  for (i = 0; i < n; i++)
    if (fabs(im.pixels[i] - 1.0) > worst) worst = fabs(im.pixels[i] - 1.0), worst_i = i;
  m = mean(&im);
  snprintf(msg, sizeof msg, "%s: mean %.5f, expected 1 within 0.005", mode, m);
  check(fabs(m - 1.0) < 0.005, msg);
  snprintf(msg, sizeof msg, "%s: worst pixel (%d, %d) %.4f, expected 1 within 0.15", mode,
           (int)(worst_i / 3 % (size_t)im.width), (int)(worst_i / 3 / (size_t)im.width), im.pixels[worst_i]);
  check(worst < 0.15, msg);
  el_image_free(&im);
}

static int same_files(const char *a, const char *b) {
  FILE *fa = fopen(a, "rb"), *fb = fopen(b, "rb");
  int same = fa && fb, ca, cb;
  while (same) {
    ca = getc(fa);
    cb = getc(fb);
    if (ca != cb) same = 0;
    if (ca == EOF) break;
  }
  if (fa) fclose(fa);
  if (fb) fclose(fb);
  return same;
}

static void test_city(void) {
  el_image im;
  char args[1024], msg[256];
  double m, var = 0;
  size_t i, n;
  snprintf(args, sizeof args, "\"%s/envmaps/city.hdr\" test_path_tracer_city.pfm 4 64 36", EL_TEST_DATA_DIR);
  check(run(args) == 0, "city: 00_path_tracer renders city.hdr to .pfm");
  if (load("test_path_tracer_city.pfm", &im) != 0) {
    check(0, "city: its picture loads");
    return;
  }
  check(im.width == 64 && im.height == 36 && im.channels == 3, "city: 64 x 36 RGB");
  check(all_finite(&im), "city: every value finite");
  m = mean(&im);
  n = (size_t)im.width * (size_t)im.height * 3;
  for (i = 0; i < n; i++) var += (im.pixels[i] - m) * (im.pixels[i] - m) / (double)n;
  snprintf(msg, sizeof msg, "city: mean %.4f > 0.05 (not black), standard deviation %.4f > 0.05 (not flat)", m,
           sqrt(var));
  check(m > 0.05 && sqrt(var) > 0.05, msg);
  el_image_free(&im);

  snprintf(args, sizeof args, "\"%s/envmaps/city.hdr\" test_path_tracer_city2.pfm 4 64 36", EL_TEST_DATA_DIR);
  check(run(args) == 0 && same_files("test_path_tracer_city.pfm", "test_path_tracer_city2.pfm"),
        "city: a second run writes the same file byte for byte");

  snprintf(args, sizeof args, "\"%s/envmaps/city.hdr\" test_path_tracer_city.png 4 64 36", EL_TEST_DATA_DIR);
  check(run(args) == 0, "city: 00_path_tracer writes .png");
  if (load("test_path_tracer_city.png", &im) != 0) {
    check(0, "city: the .png loads");
    return;
  }
  m = mean(&im);
  snprintf(msg, sizeof msg, "city: the .png is 64 x 36, mean code %.1f of 255 > 10", m * 255.0);
  check(im.width == 64 && im.height == 36 && m * 255.0 > 10.0, msg);
  el_image_free(&im);
}

int main(void) {
  if (!EL_HAVE_EXAMPLES) {
    printf("SKIP: the examples are not built (EL_BUILD_EXAMPLES=OFF)\n");
    return 77;
  }
  test_furnace(0);
  test_furnace(1);
  test_city();
  printf("%d passed, %d failed\n", g_pass, g_fail);
  return g_fail ? 1 : 0;
}
