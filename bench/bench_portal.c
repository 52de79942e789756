/* bench_portal.c: envlight's portal sampling (issue 23) against a plain port of pbrt-v4's
 * PortalImageInfiniteLight sampler (WindowedPiecewiseConstant2D: bisection over a double summed-area
 * table, src/pbrt/util/sampling.h; ImageBounds / RenderFromImage, src/pbrt/lights.h) and against the
 * map's own sampling, for the irradiance at points on the floor of a room lit through one window.
 *
 *   bench_portal [MAP.hdr|-smooth|""] [N] [R] [SS]   MAP default data/envmaps/city.hdr (a sun; the window
 *                                        is put so that it shines in); -smooth: a generated overcast sky;
 *                                        N samples per point and run (200000); R the rectified resolution
 *                                        of both portal samplers (0: envlight's default, twice the map's
 *                                        height); SS envlight's supersampling (0: its default, 2)
 *
 *   bench_portal --picture [OUT.png] [MAP]   where 2000 samples of one floor point land on the lat-long
 *                                        map (light space), map sampling above and the portal below, the
 *                                        window's outline in blue; samples through it yellow, blocked red;
 *                                        default out/portal_samples.png (the folder created), city.hdr
 *
 * Printed per strategy: ns per sample (sample + radiance + pdf; CPU time, best and worst of 5 runs
 * interleaved), the variance per sample of lum(L) cos / pdf (the mean over 4 floor points of the
 * relative variance), the efficiency 1 / (variance x time) relative to pbrt-v4's port, and the bytes
 * per rectified texel. Both portal samplers use le() of the map for the radiance (pbrt-v4 reads its
 * rectified RGB image instead: 12 more bytes per texel), the same resolution and the same window. */
#define _POSIX_C_SOURCE 199309L
#define EL_IMPLEMENTATION
#include "../envlight.h"
#include "../examples/common/image_io.h"
#include "../examples/common/picture.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static const double PI = 3.14159265358979323846;
#include "bench_common.h" /* process_now, make_parent_dir, picture_to8 / picture_dot, xorshift64_f */
static double lum(const float *c) { return 0.212671 * c[0] + 0.715160 * c[1] + 0.072169 * c[2]; }
static xorshift64 g_rng = {88172645463325252ULL};

/* ---- the pbrt-v4 port: SummedAreaTable (double), WindowedPiecewiseConstant2D, the portal frame ---- */
typedef struct pbrt_portal {
  int n;             /* resolution */
  double *sum;       /* n x n, sum(x, y) inclusive */
  float *func;       /* n x n */
  double p0[3], p2[3], X[3], Y[3], Z[3];
} pbrt_portal;
static double sat_lookup_int(const pbrt_portal *P, int x, int y) {
  if (x == 0 || y == 0) return 0;
  x = x - 1 < P->n - 1 ? x - 1 : P->n - 1;
  y = y - 1 < P->n - 1 ? y - 1 : P->n - 1;
  return P->sum[(size_t)y * (size_t)P->n + (size_t)x];
}
static float sat_lookup(const pbrt_portal *P, float x, float y) {
  int x0, y0;
  float v00, v10, v01, v11, dx, dy;
  x *= (float)P->n; y *= (float)P->n;
  x0 = (int)x; y0 = (int)y;
  v00 = (float)sat_lookup_int(P, x0, y0); v10 = (float)sat_lookup_int(P, x0 + 1, y0);
  v01 = (float)sat_lookup_int(P, x0, y0 + 1); v11 = (float)sat_lookup_int(P, x0 + 1, y0 + 1);
  dx = x - (float)(int)x; dy = y - (float)(int)y;
  return (1 - dx) * (1 - dy) * v00 + (1 - dx) * dy * v01 + dx * (1 - dy) * v10 + dx * dy * v11;
}
static float sat_integral(const pbrt_portal *P, const float b[4]) { /* b: xmin, ymin, xmax, ymax */
  double s = ((double)sat_lookup(P, b[2], b[3]) - (double)sat_lookup(P, b[0], b[3])) +
             ((double)sat_lookup(P, b[0], b[1]) - (double)sat_lookup(P, b[2], b[1]));
  s /= (double)P->n * (double)P->n;
  return s > 0 ? (float)s : 0.0f;
}
static float sample_bisection(const pbrt_portal *P, const float *box, int axis, float bint, float u, float mn, float mx) {
  float b[4], t, pmin, pmax;
  memcpy(b, box, sizeof b);
  while (ceilf((float)P->n * mx) - floorf((float)P->n * mn) > 1) {
    float mid = (mn + mx) / 2;
    b[2 + axis] = mid;
    if (sat_integral(P, b) / bint > u) mx = mid;
    else mn = mid;
  }
  b[2 + axis] = mn; pmin = sat_integral(P, b) / bint;
  b[2 + axis] = mx; pmax = sat_integral(P, b) / bint;
  t = (u - pmin) / (pmax - pmin);
  t = (1 - t) * mn + t * mx;
  return t < mn ? mn : (t > mx ? mx : t);
}
static float wpc_eval(const pbrt_portal *P, float x, float y) {
  int ix = (int)(x * (float)P->n), iy = (int)(y * (float)P->n);
  if (ix > P->n - 1) ix = P->n - 1;
  if (iy > P->n - 1) iy = P->n - 1;
  return P->func[(size_t)iy * (size_t)P->n + (size_t)ix];
}
static int wpc_sample(const pbrt_portal *P, const float u[2], const float b[4], float p[2], float *pdf) {
  float bint = sat_integral(P, b), bc[4], cint;
  int n = P->n;
  if (bint == 0) { *pdf = 0; return 0; }
  p[0] = sample_bisection(P, b, 0, bint, u[0], b[0], b[2]);
  bc[0] = floorf(p[0] * (float)n) / (float)n; bc[1] = b[1];
  bc[2] = ceilf(p[0] * (float)n) / (float)n; bc[3] = b[3];
  if (bc[0] == bc[2]) bc[2] += 1.0f / (float)n;
  cint = sat_integral(P, bc);
  if (cint == 0) { *pdf = 0; return 0; }
  p[1] = sample_bisection(P, bc, 1, cint, u[1], b[1], b[3]);
  *pdf = wpc_eval(P, p[0], p[1]) / bint;
  return 1;
}
static void norm3(double v[3]) { double l = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); v[0] /= l; v[1] /= l; v[2] /= l; }
/* pbrt-v4 ImageFromRender */
static int image_from_render(const pbrt_portal *P, const double w[3], float uv[2]) {
  double x = w[0] * P->X[0] + w[1] * P->X[1] + w[2] * P->X[2], y = w[0] * P->Y[0] + w[1] * P->Y[1] + w[2] * P->Y[2];
  double z = w[0] * P->Z[0] + w[1] * P->Z[1] + w[2] * P->Z[2], a, b;
  if (z <= 0) return 0;
  a = (atan2(x, z) + PI / 2) / PI; b = (atan2(y, z) + PI / 2) / PI;
  uv[0] = (float)(a < 0 ? 0 : a > 1 ? 1 : a); uv[1] = (float)(b < 0 ? 0 : b > 1 ? 1 : b);
  return 1;
}
/* pbrt-v4 RenderFromImage: returns dw/duv ("duv_dw") */
static float render_from_image(const pbrt_portal *P, float u, float v, float wo[3]) {
  float alpha = (float)(-PI / 2 + u * PI), beta = (float)(-PI / 2 + v * PI);
  float x = tanf(alpha), y = tanf(beta), l = sqrtf(x * x + y * y + 1), w[3];
  int c;
  w[0] = x / l; w[1] = y / l; w[2] = 1 / l;
  for (c = 0; c < 3; ++c) wo[c] = (float)(w[0] * P->X[c] + w[1] * P->Y[c] + w[2] * P->Z[c]);
  return (float)(PI * PI) * (1 - w[0] * w[0]) * (1 - w[1] * w[1]) / w[2];
}
static void pbrt_init(pbrt_portal *P, const el_envlight *L, const float *v, int n) {
  int i, x, y;
  double e01[3], e03[3];
  P->n = n;
  for (i = 0; i < 3; ++i) { P->p0[i] = v[i]; P->p2[i] = v[6 + i]; e01[i] = (double)v[3 + i] - v[i]; e03[i] = (double)v[9 + i] - v[i]; }
  norm3(e01); norm3(e03);
  memcpy(P->X, e03, sizeof e03); memcpy(P->Y, e01, sizeof e01);
  P->Z[0] = e03[1] * e01[2] - e03[2] * e01[1]; P->Z[1] = e03[2] * e01[0] - e03[0] * e01[2]; P->Z[2] = e03[0] * e01[1] - e03[1] * e01[0];
  P->func = (float *)malloc(sizeof(float) * (size_t)n * (size_t)n);
  P->sum = (double *)malloc(sizeof(double) * (size_t)n * (size_t)n);
  for (y = 0; y < n; ++y)
    for (x = 0; x < n; ++x) { /* the image resampled at pixel centres, times duv_dw (GetSamplingDistribution) */
      float w[3], rgb[3], J = render_from_image(P, ((float)x + 0.5f) / (float)n, ((float)y + 0.5f) / (float)n, w);
      el_envlight_le(L, w, rgb);
      P->func[y * n + x] = (float)((rgb[0] + rgb[1] + rgb[2]) / 3.0) * J;
    }
  for (y = 0; y < n; ++y)
    for (x = 0; x < n; ++x) {
      double s = P->func[y * n + x];
      if (x > 0) s += P->sum[y * n + x - 1];
      if (y > 0) s += P->sum[(y - 1) * n + x];
      if (x > 0 && y > 0) s -= P->sum[(y - 1) * n + x - 1];
      P->sum[y * n + x] = s;
    }
}
/* pbrt-v4 PortalImageInfiniteLight::SampleLi (ImageBounds, the windowed sample, RenderFromImage), the
 * radiance from le() */
static int pbrt_sample(const pbrt_portal *P, const el_envlight *L, const float pos[3], const float u[2], float wi[3], float rgb[3], float *pdf) {
  double d0[3], d2[3];
  float b0[2], b1[2], b[4], uv[2], mpdf, J;
  int i;
  for (i = 0; i < 3; ++i) { d0[i] = P->p0[i] - pos[i]; d2[i] = P->p2[i] - pos[i]; }
  norm3(d0); norm3(d2);
  if (!image_from_render(P, d0, b0) || !image_from_render(P, d2, b1)) { *pdf = 0; return 0; }
  b[0] = b0[0] < b1[0] ? b0[0] : b1[0]; b[2] = b0[0] < b1[0] ? b1[0] : b0[0];
  b[1] = b0[1] < b1[1] ? b0[1] : b1[1]; b[3] = b0[1] < b1[1] ? b1[1] : b0[1];
  if (!wpc_sample(P, u, b, uv, &mpdf)) { *pdf = 0; return 0; }
  J = render_from_image(P, uv[0], uv[1], wi);
  if (J == 0) { *pdf = 0; return 0; }
  *pdf = mpdf / J;
  el_envlight_le(L, wi, rgb);
  return 1;
}

/* ---- the room: a window of 1.2 x 1.0 m facing the sun's azimuth, 2 m from the floor points, as high as the
 * sun's elevation asks for the sun to shine through it onto the middle of the floor (points 1 and 2 see the
 * sun through the window, points 0 and 3 see the window without it) ---- */
typedef struct room { float portal[12]; float pts[4][3]; float n[3]; double center[3], X[3], Y[3], Z[3], hx, hy; } room;
static void make_room(room *r, const double sun[3]) {
  /* world y up; the window faces the horizontal part of sun (into the sky) */
  double h[3] = {sun[0], 0, sun[2]}, up[3] = {0, 1, 0}, X[3], hl, lift;
  int i, k;
  if (h[0] * h[0] + h[2] * h[2] < 1e-6) { h[0] = 1; h[2] = 0; }
  hl = sqrt(sun[0] * sun[0] + sun[2] * sun[2]);
  lift = hl > 1e-3 ? 2.0 * sun[1] / hl : 1.5; /* the sun's height over 2 m of floor */
  if (lift < 0.8) lift = 0.8;
  if (lift > 4.0) lift = 4.0;
  norm3(h);
  /* frame: Z = h, Y = up (p0 -> p1), X = Y cross Z ... pbrt's Z = X cross Y, so X = Y cross Z */
  X[0] = up[1] * h[2] - up[2] * h[1]; X[1] = up[2] * h[0] - up[0] * h[2]; X[2] = up[0] * h[1] - up[1] * h[0];
  r->hx = 0.6; r->hy = 0.5;
  for (i = 0; i < 3; ++i) {
    r->center[i] = 2.0 * h[i] + (i == 1 ? lift : 0.0);
    r->X[i] = X[i]; r->Y[i] = up[i]; r->Z[i] = h[i];
  }
  for (i = 0; i < 3; ++i) {
    double p0 = r->center[i] - r->hx * X[i] - r->hy * up[i];
    r->portal[i] = (float)p0;
    r->portal[3 + i] = (float)(p0 + 2 * r->hy * up[i]);
    r->portal[6 + i] = (float)(p0 + 2 * r->hy * up[i] + 2 * r->hx * X[i]);
    r->portal[9 + i] = (float)(p0 + 2 * r->hx * X[i]);
  }
  for (k = 0; k < 4; ++k) { /* floor points across the sun's patch and aside */
    double off = 0.8 * (k - 1.5);
    for (i = 0; i < 3; ++i) r->pts[k][i] = (float)(off * X[i]);
    r->pts[k][1] = 0;
  }
  r->n[0] = 0; r->n[1] = 1; r->n[2] = 0;
}
/* does the ray pos + t wi pass through the window? (for the map's own sampling) */
static int through(const room *r, const float pos[3], const float wi[3]) {
  double dz = wi[0] * r->Z[0] + wi[1] * r->Z[1] + wi[2] * r->Z[2], oz = 0, t, q[3], x = 0, y = 0;
  int i;
  if (dz <= 0) return 0;
  for (i = 0; i < 3; ++i) oz += (r->center[i] - pos[i]) * r->Z[i];
  t = oz / dz;
  for (i = 0; i < 3; ++i) q[i] = pos[i] + t * wi[i] - r->center[i];
  for (i = 0; i < 3; ++i) { x += q[i] * r->X[i]; y += q[i] * r->Y[i]; }
  return fabs(x) <= r->hx && fabs(y) <= r->hy;
}

#define NSTRAT 3
static const char *names[NSTRAT] = {"map sample_li (no portal)", "pbrt-v4 port (bisection, double SAT)", "envlight portal (integer SAT)"};

/* ---- the picture: where the samples of one floor point land, map sampling against the portal ---- */
/* world direction -> pixel of the lat-long map (light space: the transpose of light_to_world) */
static void to_pixel(const float m[9], const float w[3], int W, int H, int *x, int *y) {
  float d[3], u, v;
  d[0] = m[0] * w[0] + m[3] * w[1] + m[6] * w[2];
  d[1] = m[1] * w[0] + m[4] * w[1] + m[7] * w[2];
  d[2] = m[2] * w[0] + m[5] * w[1] + m[8] * w[2];
  el_envlight_dir_to_uv(d, &u, &v);
  *x = (int)(u * (float)W); *y = (int)(v * (float)H);
}
static void find_sun(const float *px, int w, int h, const float m[9], double sun[3]);
static int picture(const char *out, const char *path) {
  el_image img;
  el_envlight L;
  el_envlight_options lo;
  el_envlight_portal EP;
  room rm;
  char err[512], label[160];
  int W, H, panel, x, y, i, ns = 2000, k;
  unsigned char *pix;
  double sun[3];
  const float *pos;
  if (el_image_load(path, &img, err, sizeof err) != 0) { fprintf(stderr, "%s\n", err); return 1; }
  memset(&lo, 0, sizeof lo);
  el_envlight_yup_matrix(lo.light_to_world);
  if (el_envlight_init(&L, img.pixels, img.width, img.height, 3, &lo) != EL_SUCCESS) { fprintf(stderr, "%s: init failed\n", path); return 1; }
  find_sun(img.pixels, img.width, img.height, lo.light_to_world, sun);
  make_room(&rm, sun);
  pos = rm.pts[1];
  if (el_envlight_portal_init(&EP, &L, rm.portal, 1, NULL) != EL_SUCCESS) { fprintf(stderr, "%s\n", EP.error); return 1; }
  W = img.width; H = img.height;
  pix = (unsigned char *)calloc((size_t)W * 2 * (size_t)H * 3, 1);
  for (panel = 0; panel < 2; ++panel) {
    unsigned char *im = pix + (size_t)panel * (size_t)W * (size_t)H * 3;
    int nthrough = 0;
    g_rng.s = 88172645463325252ULL;
    for (y = 0; y < H; ++y) /* the map, one stop darker */
      for (x = 0; x < W; ++x) {
        const float *t = img.pixels + 3 * ((size_t)y * (size_t)W + (size_t)x);
        unsigned char *q = im + 3 * ((size_t)y * (size_t)W + (size_t)x);
        q[0] = picture_to8(0.5 * t[0]); q[1] = picture_to8(0.5 * t[1]); q[2] = picture_to8(0.5 * t[2]);
      }
    for (k = 0; k < 4; ++k) /* the window's outline seen from the point */
      for (i = 0; i <= 400; ++i) {
        const float *a = rm.portal + 3 * k, *b = rm.portal + 3 * ((k + 1) % 4);
        float w[3];
        int c;
        for (c = 0; c < 3; ++c) w[c] = a[c] + (b[c] - a[c]) * (float)i / 400.0f - pos[c];
        to_pixel(lo.light_to_world, w, W, H, &x, &y);
        picture_dot(im, W, H, x, y, 0, 80, 220, 255);
      }
    for (i = 0; i < ns; ++i) {
      float u[2], wi[3], rgb[3], pdf;
      int ok;
      u[0] = xorshift64_f(&g_rng); u[1] = xorshift64_f(&g_rng);
      if (panel == 0) el_envlight_sample_li(&L, u, wi, rgb, &pdf);
      else el_envlight_portal_sample_li(&EP, &L, pos, u, wi, rgb, &pdf);
      if (!(pdf > 0)) continue;
      ok = through(&rm, pos, wi);
      nthrough += ok;
      to_pixel(lo.light_to_world, wi, W, H, &x, &y);
      if (ok) picture_dot(im, W, H, x, y, 1, 255, 230, 40);
      else picture_dot(im, W, H, x, y, 1, 255, 40, 40);
    }
    snprintf(label, sizeof label, "%s: %d OF %d SAMPLES THROUGH THE WINDOW (YELLOW)", panel == 0 ? "MAP (SAMPLE LI)" : "PORTAL (PORTAL SAMPLE LI)",
             nthrough, ns);
    el_draw_label(im, W, H, 8, 8, label);
    el_draw_label(im, W, H, 8, 34, "THE WINDOW SEEN FROM A POINT ON THE FLOOR: BLUE");
    printf("%s: %d of %d samples through the window\n", panel == 0 ? "el_envlight_sample_li" : "el_envlight_portal_sample_li", nthrough, ns);
  }
  make_parent_dir(out);
  if (el_image_write_png(out, pix, W, 2 * H, 3, err, sizeof err) != 0) { fprintf(stderr, "%s\n", err); return 1; }
  printf("wrote %s\n", out);
  free(pix);
  el_envlight_portal_free(&EP);
  el_envlight_free(&L);
  el_image_free(&img);
  return 0;
}
/* the sun: the brightest texel, in world space */
static void find_sun(const float *px, int w, int h, const float m[9], double sun[3]) {
  int bi = 0, i;
  double bl = -1;
  float dl[3];
  for (i = 0; i < w * h; ++i) if (lum(px + 3 * i) > bl) { bl = lum(px + 3 * i); bi = i; }
  el_envlight_uv_to_dir((float)(((bi % w) + 0.5) / w), (float)(((bi / w) + 0.5) / h), dl);
  for (i = 0; i < 3; ++i) sun[i] = m[3 * i] * dl[0] + m[3 * i + 1] * dl[1] + m[3 * i + 2] * dl[2];
}

int main(int argc, char **argv) {
  el_image img;
  el_envlight L;
  el_envlight_options lo;
  el_envlight_portal EP;
  pbrt_portal PP;
  room rm;
  char err[256];
  const char *path = argc > 1 && argv[1][0] ? argv[1] : EL_SOURCE_DIR "/data/envmaps/city.hdr";
  int N = argc > 2 ? atoi(argv[2]) : 200000, R = argc > 3 ? atoi(argv[3]) : 0, SS = argc > 4 ? atoi(argv[4]) : 0, s, k, rep, i, w, h;
  double sun[3] = {0.6, 0.5, 0.6}, best[NSTRAT], worst[NSTRAT], var[NSTRAT], bestv = 0;
  float *px;
  if (argc > 1 && !strcmp(argv[1], "--picture"))
    return picture(argc > 2 ? argv[2] : "out/portal_samples.png", argc > 3 ? argv[3] : EL_SOURCE_DIR "/data/envmaps/city.hdr");
  memset(&lo, 0, sizeof lo);
  el_envlight_yup_matrix(lo.light_to_world);
  if (strcmp(path, "-smooth") == 0) { /* an overcast sky: CIE-like, 2:1 zenith to horizon, dark ground */
    w = 256; h = 128;
    px = (float *)malloc(sizeof(float) * 3 * (size_t)w * (size_t)h);
    for (i = 0; i < w * h; ++i) {
      double th = PI * ((i / w) + 0.5) / h, c = cos(th), v = c > 0 ? (1 + 2 * c) / 3 : 0.1;
      px[3 * i] = (float)v; px[3 * i + 1] = (float)v; px[3 * i + 2] = (float)(1.1 * v);
    }
  } else {
    if (el_image_load(path, &img, err, sizeof err) != 0) {
      fprintf(stderr, "bench_portal: %s\n", err);
      return 1;
    }
    w = img.width; h = img.height; px = img.pixels;
  }
  if (el_envlight_init(&L, px, w, h, 3, &lo) != EL_SUCCESS) { fprintf(stderr, "bench_portal: bad map\n"); return 1; }
  if (strcmp(path, "-smooth") != 0) {
    find_sun(px, w, h, lo.light_to_world, sun);
    printf("sun direction (world, y up): %.3f %.3f %.3f\n", sun[0], sun[1], sun[2]);
  }
  make_room(&rm, sun);
  {
    el_envlight_portal_options po;
    double t0;
    memset(&po, 0, sizeof po);
    po.resolution = R;
    po.supersample = SS;
    t0 = process_now();
    if (el_envlight_portal_init(&EP, &L, rm.portal, 1, &po) != EL_SUCCESS) { fprintf(stderr, "bench_portal: %s\n", EP.error); return 1; }
    printf("build: envlight portal %.1f ms (%dx%d, supersample %d); ", 1e3 * (process_now() - t0), EP.res, EP.res, SS ? SS : 2);
    R = EP.res;
    t0 = process_now();
    pbrt_init(&PP, &L, rm.portal, R);
    printf("pbrt-v4 port %.1f ms\n", 1e3 * (process_now() - t0));
  }
  el_envlight_prepare_sampling(&L);
  for (s = 0; s < NSTRAT; ++s) { best[s] = 1e30; worst[s] = 0; var[s] = 0; }
  for (rep = 0; rep < 5; ++rep)
    for (s = 0; s < NSTRAT; ++s) {
      double t0 = process_now(), sinkt = 0, tt;
      for (k = 0; k < 4; ++k) {
        double sum = 0, sum2 = 0;
        g_rng.s = 88172645463325252ULL + (unsigned long long)(k * 7 + rep * 131);
        for (i = 0; i < N; ++i) {
          float u[2], wi[3], rgb[3], pdf = 0, f = 0, c;
          u[0] = xorshift64_f(&g_rng); u[1] = xorshift64_f(&g_rng);
          if (s == 0) {
            el_envlight_sample_li(&L, u, wi, rgb, &pdf);
            if (pdf > 0 && !through(&rm, rm.pts[k], wi)) pdf = -1;
          } else if (s == 1) pbrt_sample(&PP, &L, rm.pts[k], u, wi, rgb, &pdf);
          else el_envlight_portal_sample_li(&EP, &L, rm.pts[k], u, wi, rgb, &pdf);
          c = wi[0] * rm.n[0] + wi[1] * rm.n[1] + wi[2] * rm.n[2];
          if (pdf > 0 && c > 0) f = (float)(lum(rgb) * c / pdf);
          sum += f; sum2 += (double)f * f;
        }
        sinkt += sum;
        if (rep == 0) {
          double m = sum / N;
          var[s] += (sum2 / N - m * m) / (m * m) / 4;
          if (k == 0) printf("  %-38s point 0: E = %.5g\n", names[s], m);
        }
      }
      tt = (process_now() - t0) / (4.0 * N) * 1e9;
      if (tt < best[s]) best[s] = tt;
      if (tt > worst[s]) worst[s] = tt;
      if (sinkt < 0) printf("?");
    }
  printf("\n%-38s %16s %12s %14s %10s\n", "strategy", "ns/sample", "rel. var", "efficiency", "B/texel");
  bestv = 1.0 / (var[1] * best[1]);
  for (s = 0; s < NSTRAT; ++s)
    printf("%-38s %7.1f - %6.1f %12.4g %13.3gx %10s\n", names[s], best[s], worst[s], var[s], 1.0 / (var[s] * best[s]) / bestv,
           s == 0 ? "-" : s == 1 ? "24 (8 SAT + 4 func + 12 RGB image)" : "8 (SAT)");
  printf("cost ratio pbrt-v4 port / envlight: %.2f (best times), %.2f-%.2f (ranges); variance ratio %.3f\n", best[1] / best[2],
         worst[1] / best[2] < best[1] / worst[2] ? worst[1] / best[2] : best[1] / worst[2], worst[1] / best[2] > best[1] / worst[2] ? worst[1] / best[2] : best[1] / worst[2], var[1] / var[2]);
  printf("(CPU time on a shared, loaded machine: compare ratios; 4 floor points x %d samples per run)\n", N);
  printf("(the port's density point-samples the map at rectified texel centres, pbrt-v4's image resampling; with le() as the\n"
         " radiance here a sun between centres costs it variance, which pbrt-v4 itself, reading its rectified image, turns into\n"
         " resampling error instead: compare the variances on -smooth, the costs on both)\n");
  el_envlight_portal_free(&EP);
  el_envlight_free(&L);
  return 0;
}
