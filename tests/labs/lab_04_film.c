/* tests/labs/lab_04_film.c: lab 4 (tutorials/04-tone-mapping.md): FilmTile::AddSample, Film::WriteImage,
 * the sRGB curve and TO_BYTE in the file under test (stu_*) against pbrt's (ref_*, examples/pbrtv3/
 * film.h built separately), plus values derived by hand (a box-filtered sample lands in one pixel
 * with weight 1; gamma(0.5) = 0.735357; 0.18 is code 118; a pixel with weight sum 2 is its sum / 2). */
#include "lab_check.h"
#include "lab_film.h"

#include <stdlib.h>

enum { BOX, TRIANGLE, GAUSSIAN, MITCHELL };
static const char *filter_name[4] = {"box", "triangle", "gaussian", "mitchell"};
#define XR 7
#define YR 5

static void part_add(void) {
  float c0[3 * XR * YR], c1[3 * XR * YR], w0[XR * YR], w1[XR * YR];
  float pf[2 * 12], L[3 * 12], wt[12];
  int i, f;
  lab_part("part 1, TODO 1: FilmTile::AddSample (chapter 4, \"The film again\")");
  { /* by hand: a box filter of radius 0.5 puts a sample at (2.5, 1.5) into pixel (2, 1) alone, weight 1 */
    float p[2] = {2.5f, 1.5f}, l[3] = {1, 2, 3}, one = 1;
    stu_add_samples(XR, YR, BOX, 0.5f, 1, p, l, &one, c1, w1);
    for (i = 0; i < XR * YR; ++i)
      if (w1[i] != (i == 1 * XR + 2 ? 1.f : 0.f)) break;
    lab_check(i == XR * YR && c1[3 * (XR + 2)] == 1 && c1[3 * (XR + 2) + 2] == 3,
              "a box filter (radius 0.5), one sample L = (1, 2, 3) at pFilm = (2.5, 1.5), the centre of pixel (2, 1): pixel (%d, %d) has filterWeightSum %g "
              "(should be %g) and contribSum.r %g: the sample reaches only pixel (2, 1), with weight 1 (pFilmDiscrete = pFilm - 0.5 puts pixel centres "
              "at integers)",
              i < XR * YR ? i % XR : 2, i < XR * YR ? i / XR : 1, i < XR * YR ? w1[i] : w1[XR + 2], i < XR * YR && i == XR + 2 ? 1. : i < XR * YR ? 0. : 1.,
              c1[3 * (XR + 2)]);
  }
  for (i = 0; i < 12; ++i) {
    pf[2 * i] = 0.3f + 0.61f * (float)i;
    pf[2 * i + 1] = 0.2f + 0.43f * (float)((i * 5) % 12);
    L[3 * i] = 0.5f + 0.1f * (float)i;
    L[3 * i + 1] = 1.f;
    L[3 * i + 2] = 2.f - 0.1f * (float)i;
    wt[i] = i % 3 ? 1.f : 0.5f;
  }
  for (f = 0; f < 4; ++f) {
    float radius = f == BOX ? 0.5f : (f == TRIANGLE ? 1.3f : 2.f);
    int touched_differ = 0;
    ref_add_samples(XR, YR, f, radius, 12, pf, L, wt, c0, w0);
    stu_add_samples(XR, YR, f, radius, 12, pf, L, wt, c1, w1);
    for (i = 0; i < XR * YR; ++i)
      if ((w0[i] != 0) != (w1[i] != 0)) touched_differ = 1;
    for (i = 0; i < XR * YR; ++i)
      if (!lab_close(w0[i], w1[i], 1e-5)) break;
    if (!lab_check(i == XR * YR, "the %s filter (radius %g), 12 samples: pixel (%d, %d) has filterWeightSum %g, pbrt's %g: %s", filter_name[f], radius,
                   i % XR, i / XR, i < XR * YR ? w1[i] : 0., i < XR * YR ? w0[i] : 0.,
                   touched_differ ? "the sample reaches other pixels than pbrt's: pFilmDiscrete = pFilm - 0.5, p0 = ceil(pFilmDiscrete - radius), "
                                    "p1 = floor(pFilmDiscrete + radius) + 1, clipped to the tile's pixelBounds"
                                  : "the right pixels, other weights: the table index is floor(|(x - pFilmDiscrete.x) * invFilterRadius.x * "
                                    "filterTableSize|), at most filterTableSize - 1, and the same in y; the weight is "
                                    "filterTable[iy * filterTableSize + ix]"))
      continue;
    for (i = 0; i < 3 * XR * YR; ++i)
      if (!lab_close(c0[i], c1[i], 1e-5)) break;
    lab_check(i == 3 * XR * YR, "the %s filter (radius %g), 12 samples: pixel (%d, %d)'s contribSum is %g, pbrt's %g (the weights agree): contribSum += L * "
              "sampleWeight * filterWeight",
              filter_name[f], radius, (i / 3) % XR, (i / 3) / XR, i < 3 * XR * YR ? c1[i] : 0., i < 3 * XR * YR ? c0[i] : 0.);
  }
}

static void part_write(void) {
  float xyz[3 * XR * YR], ws[XR * YR], sp[3 * XR * YR], a[3 * XR * YR], b[3 * XR * YR];
  int i, k;
  lab_part("part 2, TODO 2: Film::WriteImage (chapter 4, \"The film again\" and \"splatXYZ\")");
  { /* by hand: XYZ of RGB (1, 0.5, 0.2) summed with weight 2 is RGB (0.5, 0.25, 0.1) */
    float one[3] = {0.412453f + 0.357580f * 0.5f + 0.180423f * 0.2f, 0.212671f + 0.715160f * 0.5f + 0.072169f * 0.2f,
                    0.019334f + 0.119193f * 0.5f + 0.950227f * 0.2f},
          w = 2, z[3] = {0, 0, 0}, out[3];
    stu_write_image(1, 1, one, &w, z, 1, 1, out);
    lab_check(lab_close(out[0], 0.5, 2e-3) && lab_close(out[1], 0.25, 2e-3) && lab_close(out[2], 0.1, 2e-3),
              "a pixel holding the XYZ of RGB (1, 0.5, 0.2) with filterWeightSum 2 gives RGB (%.4f, %.4f, %.4f), should be (0.5, 0.25, 0.1): %s", out[0],
              out[1], out[2],
              lab_close(out[0], 1, 2e-3) ? "did you divide by the filter weights' sum (<<Normalize pixel with weight sum>>)?"
                                         : "pbrt_XYZToRGB, then times 1 / filterWeightSum");
  }
  for (k = 0; k < 3; ++k) {
    float scale = k == 2 ? 0.5f : 1.f, splatScale = k == 1 ? 0.25f : 1.f;
    for (i = 0; i < XR * YR; ++i) {
      xyz[3 * i] = 0.1f * (float)(i % 7);
      xyz[3 * i + 1] = 0.05f * (float)(i % 5) + (i == 4 ? -1.f : 0.f); /* one pixel with a negative channel */
      xyz[3 * i + 2] = 0.3f;
      ws[i] = (i % 6 == 0) ? 0.f : 0.5f + 0.25f * (float)(i % 4);
      sp[3 * i] = sp[3 * i + 1] = sp[3 * i + 2] = (k == 1 && i % 3 == 0) ? 0.2f : 0.f;
    }
    ref_write_image(XR, YR, xyz, ws, sp, scale, splatScale, a);
    stu_write_image(XR, YR, xyz, ws, sp, scale, splatScale, b);
    for (i = 0; i < 3 * XR * YR; ++i)
      if (!lab_close(a[i], b[i], 1e-5)) break;
    if (i < 3 * XR * YR) {
      int p = i / 3;
      lab_check(0, "WriteImage (%s): pixel (%d, %d) channel %d is %g, pbrt's %g: %s", k == 0 ? "plain" : k == 1 ? "with splats" : "scale 0.5", p % XR, p / XR,
                i % 3, b[i], a[i],
                b[i] == 0 && a[i] != 0                ? "yours is 0: TODO 2 not written yet?"
                : b[i] < 0 && a[i] >= 0               ? "clamp each normalised channel below at 0 (fmaxf(0.f, ...))"
                : k == 1 && sp[3 * p] != 0            ? "add splatScale times the splat's RGB (pbrt_XYZToRGB of splatXYZ), after normalising"
                : k == 2                              ? "multiply by film->scale last"
                : ws[p] != 0 && lab_close(b[i], a[i] * ws[p], 1e-4) ? "did you divide by the filter weights' sum?"
                : ws[p] == 0                          ? "a pixel whose filterWeightSum is 0 is left as it is (no division)"
                                                      : "XYZ to RGB with pbrt_XYZToRGB, then times 1 / filterWeightSum");
    } else
      lab_check(1, "");
  }
}

static void part_gamma(void) {
  static const float v[] = {0, 0.001f, 0.0031308f, 0.004f, 0.18f, 0.5f, 1, 2};
  int i;
  lab_part("part 3, TODO 3: GammaCorrect, the sRGB curve (chapter 4, \"Gamma correction and TO_BYTE\")");
  /* by hand: 1.055 * 0.5^(1/2.4) - 0.055 */
  lab_check(lab_close(stu_gamma(0.5f), 0.735357, 1e-5), "GammaCorrect(0.5) is %g, should be 1.055 * 0.5^(1/2.4) - 0.055 = 0.735357", stu_gamma(0.5f));
  for (i = 0; i < 8; ++i)
    lab_check(lab_close(stu_gamma(v[i]), ref_gamma(v[i]), 1e-6), "GammaCorrect(%g) is %g, pbrt's %g: %s", v[i], stu_gamma(v[i]), ref_gamma(v[i]),
              v[i] <= 0.0031308f ? "up to 0.0031308 the curve is linear, 12.92 v" : "above 0.0031308 it is 1.055 v^(1/2.4) - 0.055");
}

static void part_byte(void) {
  static const float v[] = {0, 0.0005f, 0.01f, 0.18f, 0.5f, 0.9f, 1, 2, 40, -1};
  unsigned char a[30], b[30];
  int i;
  lab_part("part 4, TODO 4: TO_BYTE, curve, round, clamp (chapter 4, \"Gamma correction and TO_BYTE\")");
  ref_bytes(v, 10, a);
  stu_bytes(v, 10, b);
  /* by hand (the chapter): mid-grey 0.18 is code 118 */
  lab_check(b[9] == 118, "TO_BYTE(0.18) is %d, should be 118 (the chapter's mid-grey)%s", b[9],
            b[9] == 117 ? ": round, + 0.5f before the cast" : b[9] == 46 ? ": apply the curve (pbrt_GammaCorrect) first" : "");
  for (i = 0; i < 10; ++i) {
    int d = (int)b[3 * i] - (int)a[3 * i];
    lab_check(d == 0, "TO_BYTE(%g) is %d, pbrt's %d: %s", v[i], b[3 * i], a[3 * i],
              d == -1 ? "yours is one lower: round (+ 0.5f) before the cast truncates"
              : v[i] > 1 || v[i] < 0 ? "clamp 255 * curve + 0.5 to [0, 255] (pbrt_Clampf) before the cast"
                                     : "255 * pbrt_GammaCorrect(v) + 0.5f, clamped, cast to uint8_t");
  }
}

int main(void) {
  printf("lab 4: the film and tone mapping (tutorials/04-tone-mapping.md), your file against pbrt's\n\n");
  part_add();
  part_write();
  part_gamma();
  part_byte();
  return lab_finish("lab 4 (the film and tone mapping)");
}
