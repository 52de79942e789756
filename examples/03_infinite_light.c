/* 03_infinite_light.c: chapter 3 of the course, the infinite area light (tutorials/03-infinite-area-light.md).
 *
 * NEEDS_EMBREE NEEDS_STB: these markers make examples/CMakeLists.txt link Embree 3 and stb.
 *
 * WHAT IT DEMONSTRATES, in the chapter's steps
 *   1. The seed's loading code: stbi_loadf, every texel times L (examples/pbrtv3/infinite.h).
 *   2. The plain port of pbrt-v3's InfiniteAreaLight (the same file): the map's luminance at twice its
 *      resolution times sin(theta), and the Distribution2D over it (examples/pbrtv3/sampling.h).
 *      Picture: that importance map with its marginal CDF, four conditional CDFs and 1000 samples.
 *   3. Le, Sample_Li and Pdf_Li at a few directions.
 *   4. A scene built in code on Embree (three diffuse spheres on a ground, y up as in the seed) lit by
 *      the port's light, direct lighting only, the way pbrt-v3's DirectLightingIntegrator estimates it.
 *      Picture: four sampling strategies at equal samples, each with its error against a reference;
 *      and the render.
 *   5. envlight.h, the library's light, beside the port: the same render, and what each costs.
 *
 * WHICH PART OF PBRT IT MIRRORS
 *   pbrt-v3 src/lights/infinite.{h,cpp} (book 12.6 "Infinite Area Lights", 14.2.4 for its sampling),
 *   src/core/sampling.{h,cpp} (13.6.7, 2D distributions), src/core/integrator.cpp EstimateDirect
 *   (14.3.1) with the power heuristic (13.10.1), LookAt (2.7.7) and the pinhole PerspectiveCamera
 *   (6.2.2). pbrt's conventions are kept: its LEFT-handed LookAt (right = cross(up, dir)), the field of
 *   view on the shorter image axis, raster y down, and the light's mapping (light +z is the map's top
 *   row, (u, v) = (phi / 2pi, theta / pi)). The light is turned into this y-up world by RotateX(-90),
 *   as pbrt's own example scenes do.
 *
 * HOW TO RUN IT
 *   build/bin/03_infinite_light [--quick | --answers] [--out DIR] [envmap]
 *     (nothing)   every step, with the pictures (about a minute on two cores)
 *     --quick     steps 1, 2, 3 and 5's numbers; no pictures, no rendering (a few seconds)
 *     --answers   the numbers the chapter's exercises ask for
 *     --out DIR   where the pictures go (default out/; the course's copies are in tutorials/images)
 *     --help      the usage (exit 0)
 *     envmap      default data/envmaps/city.hdr; a power-of-two map (the port keeps MIP level 0 only)
 *
 * WHAT IT WRITES
 *   DIR/03-importance.png, DIR/03-strategies.png, DIR/03-render.png; on stdout each step's numbers.
 */
#define _POSIX_C_SOURCE 200809L /* clock_gettime, mkdir under -std=c99 */
#define EL_IMPLEMENTATION       /* this file compiles the envlight implementations */
#include "envlight.h"
#include "film.h"
#include "canvas.h"   /* examples/common: page composition */
#include "image_io.h" /* examples/common: the checked loader, PNG writing */
#include "picture.h"  /* examples/common: labels */
#include <stb_image.h>        /* the seed's loader (Debian's libstb) */
#include "pbrtv3/infinite.h"  /* the port: InfiniteAreaLight, and with it pbrtv3/sampling.h */

#include <embree3/rtcore.h>
#include <errno.h>
#include <math.h>
#include <pthread.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

#ifndef EL_SOURCE_DIR
#define EL_SOURCE_DIR "."
#endif
#ifndef LIGHT_ROTATE_DEG
#define LIGHT_ROTATE_DEG 294.0f /* RotateZ in light space before RotateX(-90): turns the sun */
#endif
#define THREADS 2

static double process_cpu(void) { /* the CPU seconds of all threads: the renders' cost */
  struct timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}
static double cpu_now(void) { /* this thread's CPU seconds: the comparisons, steady on a busy machine */
  struct timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* ---- small vectors and a random number generator ------------------------------------------------- */
typedef struct vec3 { float x, y, z; } vec3;
static vec3 v3(float x, float y, float z) { vec3 v; v.x = x; v.y = y; v.z = z; return v; }
static vec3 add(vec3 a, vec3 b) { return v3(a.x + b.x, a.y + b.y, a.z + b.z); }
static vec3 sub(vec3 a, vec3 b) { return v3(a.x - b.x, a.y - b.y, a.z - b.z); }
static vec3 mul(vec3 a, float s) { return v3(a.x * s, a.y * s, a.z * s); }
static float dot(vec3 a, vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static vec3 cross(vec3 a, vec3 b) { return v3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x); }
static vec3 normalize(vec3 a) { return mul(a, 1.0f / sqrtf(dot(a, a))); }

/* PCG32, as pbrt-v3's RNG; one stream per pixel, so the image does not depend on the threads */
typedef struct rng { uint64_t state, inc; } rng;
static uint32_t rng_u32(rng *r) {
  uint64_t old = r->state;
  uint32_t xorshifted = (uint32_t)(((old >> 18u) ^ old) >> 27u), rot = (uint32_t)(old >> 59u);
  r->state = old * 6364136223846793005ULL + r->inc;
  return (xorshifted >> rot) | (xorshifted << ((32u - rot) & 31u));
}
static float rng_float(rng *r) { return (float)(rng_u32(r) >> 8) * (1.0f / 16777216.0f); } /* [0, 1) */
static void rng_seed(rng *r, uint64_t seq) {
  r->state = 0u;
  r->inc = (seq << 1u) | 1u;
  rng_u32(r);
  r->state += 0x853c49e6748fea9bULL;
  rng_u32(r);
}

/* ---- the light the renderer sees: the port (step 4) or the library (step 5) ---------------------- */
/* Three calls, as pbrt's integrators see a light: Le for rays that escape, Sample_Li and Pdf_Li for
 * next-event estimation and multiple importance sampling. */
typedef struct light {
  const pbrt_InfiniteAreaLight *port; /* exactly one of the two is set */
  const el_envlight *lib;
} light;

static void light_Le(const light *l, vec3 d, float L[3]) {
  float w[3];
  w[0] = d.x; w[1] = d.y; w[2] = d.z;
  if (l->port) pbrt_InfiniteAreaLight_Le(l->port, w, L);
  else el_envlight_le(l->lib, w, L);
}
static float light_Sample_Li(const light *l, const float u[2], vec3 *wi, float L[3]) {
  float w[3], pdf;
  if (l->port) pbrt_InfiniteAreaLight_Sample_Li(l->port, u, w, &pdf, L);
  else el_envlight_sample_li(l->lib, u, w, L, &pdf);
  *wi = v3(w[0], w[1], w[2]);
  return pdf;
}
static float light_Pdf_Li(const light *l, vec3 wi) {
  float w[3];
  w[0] = wi.x; w[1] = wi.y; w[2] = wi.z;
  return l->port ? pbrt_InfiniteAreaLight_Pdf_Li(l->port, w) : el_envlight_pdf_li(l->lib, w);
}

/* ---- step 4: the scene on Embree: a ground plane and three spheres, y up ------------------------- */
typedef struct sphere_def { float x, y, z, r, kd[3]; } sphere_def;
static const sphere_def SPHERES[3] = {
    {0.0f, 1.0f, 0.0f, 1.0f, {0.80f, 0.80f, 0.80f}},   /* white, in the middle */
    {2.1f, 0.7f, -0.4f, 0.7f, {0.80f, 0.25f, 0.20f}},  /* red, at x > 0: on the image's right */
    {-1.9f, 0.5f, -0.9f, 0.5f, {0.20f, 0.35f, 0.80f}}, /* blue, at x < 0: on the left */
};
static const float GROUND_KD[3] = {0.50f, 0.50f, 0.45f};

typedef struct scene {
  RTCDevice device;
  RTCScene rtc;
  unsigned ground_id; /* Embree's geometry ID of the ground, to tell what a ray hit */
} scene;

static int scene_build(scene *s) {
  RTCGeometry g;
  float *v;
  unsigned *idx;
  int i;
  s->device = rtcNewDevice(NULL); /* Embree's context: thread pool, memory, settings (NULL: defaults) */
  if (!s->device) return -1;
  s->rtc = rtcNewScene(s->device); /* an empty container; its BVH is built when it is committed */
  /* the ground: two triangles covering [-12, 12]^2 at y = 0 */
  g = rtcNewGeometry(s->device, RTC_GEOMETRY_TYPE_TRIANGLE);
  v = (float *)rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), 4);
  idx = (unsigned *)rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), 2);
  if (!v || !idx) return -1;
  for (i = 0; i < 4; ++i) {
    v[3 * i] = (i == 1 || i == 2) ? 12.0f : -12.0f;
    v[3 * i + 1] = 0.0f;
    v[3 * i + 2] = i >= 2 ? 12.0f : -12.0f;
  }
  idx[0] = 0; idx[1] = 1; idx[2] = 2;
  idx[3] = 0; idx[4] = 2; idx[5] = 3;
  rtcCommitGeometry(g);                    /* the buffers are final */
  s->ground_id = rtcAttachGeometry(s->rtc, g); /* this ID comes back in every hit on it */
  rtcReleaseGeometry(g);                   /* the scene keeps its own reference */
  /* the spheres: Embree's exact sphere primitive (like pbrt's Sphere, not a tessellation), one
   * (x, y, z, radius) per sphere; the hit's primID says which */
  g = rtcNewGeometry(s->device, RTC_GEOMETRY_TYPE_SPHERE_POINT);
  v = (float *)rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, 4 * sizeof(float), 3);
  if (!v) return -1;
  for (i = 0; i < 3; ++i) {
    v[4 * i] = SPHERES[i].x;
    v[4 * i + 1] = SPHERES[i].y;
    v[4 * i + 2] = SPHERES[i].z;
    v[4 * i + 3] = SPHERES[i].r;
  }
  rtcCommitGeometry(g);
  rtcAttachGeometry(s->rtc, g);
  rtcReleaseGeometry(g);
  rtcCommitScene(s->rtc); /* builds the BVH; afterwards any number of threads may trace */
  return 0;
}
static void scene_free(scene *s) {
  if (s->rtc) rtcReleaseScene(s->rtc);
  if (s->device) rtcReleaseDevice(s->device);
}

/* rtcIntersect1: the closest hit along a ray. 0 on a miss; else the distance, geometry, primitive and
 * the (unnormalised) geometric normal. */
static int trace(RTCScene rtc, vec3 o, vec3 d, float *t, unsigned *geom, unsigned *prim, vec3 *ng) {
  struct RTCIntersectContext ctx;
  struct RTCRayHit rh;
  rtcInitIntersectContext(&ctx);
  rh.ray.org_x = o.x; rh.ray.org_y = o.y; rh.ray.org_z = o.z;
  rh.ray.dir_x = d.x; rh.ray.dir_y = d.y; rh.ray.dir_z = d.z;
  rh.ray.tnear = 0.0f;
  rh.ray.tfar = INFINITY;
  rh.ray.mask = 0xFFFFFFFFu;
  rh.ray.flags = 0;
  rh.ray.time = 0.0f;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID; /* stays so on a miss */
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(rtc, &ctx, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return 0;
  *t = rh.ray.tfar;
  *geom = rh.hit.geomID;
  *prim = rh.hit.primID;
  *ng = v3(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z);
  return 1;
}
/* rtcOccluded1: does anything block the ray? (any hit ends the search). A shadow ray towards an
 * infinite light needs no end point: tfar = infinity. Embree sets tfar to -inf on a blocker. */
static int occluded(RTCScene rtc, vec3 o, vec3 d) {
  struct RTCIntersectContext ctx;
  struct RTCRay ray;
  rtcInitIntersectContext(&ctx);
  ray.org_x = o.x; ray.org_y = o.y; ray.org_z = o.z;
  ray.dir_x = d.x; ray.dir_y = d.y; ray.dir_z = d.z;
  ray.tnear = 0.0f;
  ray.tfar = INFINITY;
  ray.mask = 0xFFFFFFFFu;
  ray.flags = 0;
  ray.time = 0.0f;
  rtcOccluded1(rtc, &ctx, &ray);
  return ray.tfar < 0.0f;
}

/* pbrt-v3's LookAt and PerspectiveCamera (a pinhole): pbrt is LEFT-handed, right = cross(up, dir) */
typedef struct camera { vec3 eye, right, up, dir; float sx, sy; int w, h; } camera;
static camera camera_make(int w, int h) {
  camera c;
  vec3 look = v3(0.0f, 0.7f, 0.0f), up = v3(0.0f, 1.0f, 0.0f);
  float aspect = (float)w / (float)h, t = tanf(0.5f * 38.0f * pbrt_Pi / 180.0f); /* "fov" 38 */
  c.eye = v3(0.0f, 2.6f, -7.5f);
  c.dir = normalize(sub(look, c.eye));
  c.right = normalize(cross(up, c.dir)); /* with dir ~ +z and up = +y this is +x */
  c.up = cross(c.dir, c.right);
  c.sx = aspect > 1 ? t * aspect : t; /* the fov applies to the shorter image axis */
  c.sy = aspect > 1 ? t : t / aspect;
  c.w = w;
  c.h = h;
  return c;
}
static vec3 camera_ray(const camera *c, float px, float py) { /* raster x right, y DOWN */
  float x = (2 * px / (float)c->w - 1) * c->sx, y = (1 - 2 * py / (float)c->h) * c->sy;
  return normalize(add(add(mul(c->right, x), mul(c->up, y)), c->dir));
}

/* ---- step 4: direct lighting of a diffuse surface, pbrt-v3's EstimateDirect ----------------------- */
enum { UNIFORM, BSDF, LIGHT, MIS };
static const char *STRATEGY[4] = {"UNIFORM SPHERE", "BSDF (COSINE)", "LIGHT SAMPLING", "MIS (PBRT)"};

static float power_heuristic(float f, float g) { return f * f + g * g > 0 ? f * f / (f * f + g * g) : 0; }

/* an orthonormal frame (s, t, n) around n (Duff et al.'s, as pbrt-v4's CoordinateSystem) */
static void frame(vec3 n, vec3 *s, vec3 *t) {
  float sign = n.z >= 0 ? 1.0f : -1.0f, a = -1.0f / (sign + n.z), b = n.x * n.y * a;
  *s = v3(1 + sign * n.x * n.x * a, sign * b, -sign * n.x);
  *t = v3(b, sign + n.y * n.y * a, -n.y);
}

/* The radiance arriving at the camera along the ray (o, d). */
static void radiance(const scene *sc, const light *l, int strategy, vec3 o, vec3 d, rng *r, float out[3]) {
  float t, kd[3], L[3], pdf_light, pdf_bsdf, cos_theta, u[2];
  unsigned geom, prim;
  vec3 ng, n, p, wi, s, tt;
  int k;
  out[0] = out[1] = out[2] = 0;
  if (!trace(sc->rtc, o, d, &t, &geom, &prim, &ng)) { /* the ray escapes: pbrt's Le(ray) */
    light_Le(l, d, out);
    return;
  }
  memcpy(kd, geom == sc->ground_id ? GROUND_KD : SPHERES[prim].kd, sizeof kd);
  n = normalize(ng);
  if (dot(n, d) > 0) n = mul(n, -1.0f);   /* face the viewer (pbrt's matte is two-sided) */
  p = add(add(o, mul(d, t)), mul(n, 1e-4f)); /* off the surface, so shadow rays miss it (pbrt: SpawnRay) */
  frame(n, &s, &tt);

  if (strategy == UNIFORM) { /* no importance sampling: UniformSampleSphere, pdf 1 / 4pi */
    float z = 1 - 2 * rng_float(r), rad = sqrtf(fmaxf(0, 1 - z * z)), phi = 2 * pbrt_Pi * rng_float(r);
    wi = v3(rad * cosf(phi), rad * sinf(phi), z);
    cos_theta = dot(wi, n);
    if (cos_theta > 0 && !occluded(sc->rtc, p, wi)) {
      light_Le(l, wi, L);
      for (k = 0; k < 3; ++k) out[k] += kd[k] / pbrt_Pi * L[k] * cos_theta * (4 * pbrt_Pi); /* f Li cos / pdf */
    }
    return;
  }
  if (strategy == LIGHT || strategy == MIS) {
    /* <<Sample light source with multiple importance sampling>> */
    u[0] = rng_float(r);
    u[1] = rng_float(r);
    pdf_light = light_Sample_Li(l, u, &wi, L);
    cos_theta = dot(wi, n);
    if (pdf_light > 0 && cos_theta > 0) {
      /* <<Evaluate BSDF for light sampling strategy>>: f = kd / pi; the BSDF's own pdf, cos / pi */
      float w = strategy == MIS ? power_heuristic(pdf_light, cos_theta / pbrt_Pi) : 1.0f;
      /* <<Add light's contribution to reflected radiance>>, if the shadow ray gets through */
      if (!occluded(sc->rtc, p, wi))
        for (k = 0; k < 3; ++k) out[k] += kd[k] / pbrt_Pi * L[k] * cos_theta * w / pdf_light;
    }
  }
  if (strategy == BSDF || strategy == MIS) {
    /* <<Sample BSDF with multiple importance sampling>>: a cosine-distributed direction (pbrt's
     * CosineSampleHemisphere), for which f cos / pdf = kd */
    float u1 = rng_float(r), u2 = rng_float(r), rad = sqrtf(u1), phi = 2 * pbrt_Pi * u2;
    float lz = sqrtf(fmaxf(0, 1 - u1));
    wi = add(add(mul(s, rad * cosf(phi)), mul(tt, rad * sinf(phi))), mul(n, lz));
    pdf_bsdf = lz / pbrt_Pi;
    if (pdf_bsdf > 0 && !occluded(sc->rtc, p, wi)) {
      /* <<Add light contribution from material sampling>>: the ray escapes and sees the light; the
       * light's pdf of this direction gives the MIS weight (pbrt returns early when it is 0; the power
       * heuristic then gives weight 1, which is right for any light density) */
      float w = strategy == MIS ? power_heuristic(pdf_bsdf, light_Pdf_Li(l, wi)) : 1.0f;
      light_Le(l, wi, L);
      for (k = 0; k < 3; ++k) out[k] += kd[k] * L[k] * w;
    }
  }
}

/* Renders w x h pixels at spp samples each (the mean of the samples: a box filter, as the seed has no
 * pixel filter) into rgb; rows are shared out between the threads. Returns the CPU seconds taken. */
typedef struct job {
  const scene *sc;
  const light *l;
  camera cam;
  int strategy, spp, thread;
  uint64_t seed;
  float *rgb;
} job;
static void *render_rows(void *arg) {
  const job *j = (const job *)arg;
  int x, y, s;
  for (y = j->thread; y < j->cam.h; y += THREADS)
    for (x = 0; x < j->cam.w; ++x) {
      float sum[3] = {0, 0, 0}, L[3];
      rng r;
      int c;
      rng_seed(&r, ((uint64_t)y * (uint64_t)j->cam.w + (uint64_t)x) ^ (j->seed << 32));
      for (s = 0; s < j->spp; ++s) {
        float px = (float)x + rng_float(&r), py = (float)y + rng_float(&r);
        radiance(j->sc, j->l, j->strategy, j->cam.eye, camera_ray(&j->cam, px, py), &r, L);
        for (c = 0; c < 3; ++c) sum[c] += L[c];
      }
      for (c = 0; c < 3; ++c) j->rgb[3 * ((size_t)y * (size_t)j->cam.w + (size_t)x) + c] = sum[c] / (float)j->spp;
    }
  return NULL;
}
static double render(const scene *sc, const light *l, int strategy, int w, int h, int spp, uint64_t seed, float *rgb) {
  pthread_t th[THREADS];
  job jobs[THREADS];
  int i, started[THREADS];
  double t0 = process_cpu();
  for (i = 0; i < THREADS; ++i) {
    jobs[i].sc = sc;
    jobs[i].l = l;
    jobs[i].cam = camera_make(w, h);
    jobs[i].strategy = strategy;
    jobs[i].spp = spp;
    jobs[i].thread = i;
    jobs[i].seed = seed;
    jobs[i].rgb = rgb;
  }
  for (i = 1; i < THREADS; ++i) started[i] = pthread_create(&th[i], NULL, render_rows, &jobs[i]) == 0;
  render_rows(&jobs[0]); /* this thread takes rows 0, THREADS, 2 THREADS, ... */
  for (i = 1; i < THREADS; ++i) {
    if (started[i]) pthread_join(th[i], NULL);
    else render_rows(&jobs[i]); /* a thread that did not start: its rows here */
  }
  return process_cpu() - t0;
}

/* relative MSE against a reference: the mean over pixels and channels of (x - ref)^2 / (ref^2 + 0.01)
 * (the 0.01 keeps black pixels from dominating) */
static double rel_mse(const float *x, const float *ref, size_t n) {
  double s = 0;
  size_t i;
  for (i = 0; i < n; ++i) s += ((double)x[i] - ref[i]) * ((double)x[i] - ref[i]) / ((double)ref[i] * ref[i] + 0.01);
  return s / (double)n;
}

/* ---- the pictures -------------------------------------------------------------------------------- */
static void make_dir(const char *dir) {
  if (mkdir(dir, 0777) != 0 && errno != EEXIST) fprintf(stderr, "03_infinite_light: cannot create %s\n", dir);
}
static int write_page(const char *dir, const char *name, const unsigned char *page, int w, int h) {
  char path[1024], err[512];
  snprintf(path, sizeof path, "%s/%s", dir, name);
  if (el_image_write_png(path, page, w, h, 3, err, sizeof err) != 0) {
    fprintf(stderr, "03_infinite_light: %s\n", err);
    return -1;
  }
  printf("        wrote %s\n", path);
  return 0;
}
/* linear RGB -> 8-bit with pbrt's output curve (clamp, sRGB) one stop darker (the sunlit ground is
 * about 1.1) */
static void to8(const float *rgb, int w, int h, unsigned char *out) {
  el_film_output_options o;
  memset(&o, 0, sizeof o);
  o.exposure = -1.0f;
  el_film_to_srgb8(rgb, w, h, &o, out);
}

/* Step 2's picture: the port's importance map (log scale) with 1000 of its samples, its marginal CDF
 * to the right and four rows' conditional CDFs below. */
static int picture_importance(const pbrt_InfiniteAreaLight *port, const char *dir) {
  enum { MW = 1024, MH = 512, SIDE = 180, BELOW = 250, W = MW + SIDE, H = MH + BELOW + 30 };
  static const unsigned char col[4][3] = {{255, 90, 60}, {90, 220, 90}, {90, 160, 255}, {240, 200, 40}};
  const pbrt_Distribution2D *d = &port->distribution;
  unsigned char *page = (unsigned char *)calloc((size_t)W * H * 3, 1);
  int rows[4], x, y, i, k, sx = d->nu / MW, sy = d->nv / MH;
  float top = 0;
  char text[128];
  if (!page) return -1;
  for (i = 0; i < d->nu * d->nv; ++i) top = fmaxf(top, d->pConditionalV[i / d->nu].func[i % d->nu]);
  /* the map: each page pixel shows the largest of the sx x sy bins under it, 6 decades of log10 */
  for (y = 0; y < MH; ++y)
    for (x = 0; x < MW; ++x) {
      float m = 0, g;
      int a, b;
      for (b = 0; b < sy; ++b)
        for (a = 0; a < sx; ++a) m = fmaxf(m, d->pConditionalV[y * sy + b].func[x * sx + a]);
      g = m > 0 ? 1 + log10f(m / top) / 6 : 0;
      g = g < 0 ? 0 : g;
      el_canvas_fill(page, W, H, x, y + 30, x + 1, y + 31, (unsigned char)(255 * g), (unsigned char)(255 * g),
                     (unsigned char)(255 * g));
    }
  /* four rows: the sun's (the brightest bin's), one of the sky, the horizon, one of the ground */
  for (i = 0, k = 0; i < d->nu * d->nv; ++i)
    if (d->pConditionalV[i / d->nu].func[i % d->nu] == top) k = i / d->nu;
  rows[0] = k;
  rows[1] = d->nv / 8;
  rows[2] = d->nv / 2;
  rows[3] = 3 * d->nv / 4;
  for (i = 0; i < 4; ++i) {
    const pbrt_Distribution1D *c = &d->pConditionalV[rows[i]];
    int yy = 30 + rows[i] * MH / d->nv, px = 0, py = 0;
    for (x = 0; x < MW; x += 4) el_canvas_fill(page, W, H, x, yy, x + 2, yy + 1, col[i][0], col[i][1], col[i][2]);
    for (x = 0; x <= c->n; x += 2) { /* the conditional CDF, below the map */
      int qx = x * MW / c->n, qy = H - 30 - (int)(c->cdf[x] * (BELOW - 100));
      if (x) el_canvas_line(page, W, H, px, py, qx, qy, col[i][0], col[i][1], col[i][2]);
      px = qx;
      py = qy;
    }
    snprintf(text, sizeof text, "ROW %d%s", rows[i], i == 0 ? " (SUN)" : "");
    el_draw_text(page, W, H, 10 + 240 * i, MH + 64, 2, text, col[i][0], col[i][1], col[i][2]);
  }
  el_draw_text(page, W, H, 10, MH + 40, 2, "CONDITIONAL CDFS OF FOUR ROWS, OVER U", 255, 255, 255);
  el_draw_text(page, W, H, MW - 40, H - 24, 2, "U=1", 160, 160, 160);
  el_draw_text(page, W, H, 10, H - 24, 2, "U=0", 160, 160, 160);
  /* the marginal CDF, to the right: v down, the CDF to the right */
  {
    int px = MW, py = 30;
    for (y = 0; y <= d->nv; ++y) {
      int qx = MW + 10 + (int)(d->pMarginal.cdf[y] * (SIDE - 30)), qy = 30 + y * MH / d->nv;
      el_canvas_line(page, W, H, px, py, qx, qy, 255, 255, 255);
      px = qx;
      py = qy;
    }
    el_draw_text(page, W, H, MW + 8, MH + 40, 2, "MARGINAL CDF", 255, 255, 255);
    el_draw_text(page, W, H, MW + 8, MH + 64, 2, "OVER V (DOWN)", 255, 255, 255);
  }
  /* 1000 sampled points (u, v), through the port's Distribution2D */
  {
    rng r;
    rng_seed(&r, 3);
    for (i = 0; i < 1000; ++i) {
      float u[2], uv[2], pdf;
      u[0] = rng_float(&r);
      u[1] = rng_float(&r);
      pbrt_Distribution2D_SampleContinuous(d, u, uv, &pdf);
      el_canvas_dot(page, W, H, (int)(uv[0] * MW), 30 + (int)(uv[1] * MH), 1, 255, 40, 40);
    }
  }
  snprintf(text, sizeof text, "LUMINANCE X SIN(THETA), %d X %d BINS (LOG SCALE, 6 DECADES), 1000 SAMPLES (RED)", d->nu, d->nv);
  el_draw_label(page, W, H, 4, 2, text);
  k = write_page(dir, "03-importance.png", page, W, H);
  free(page);
  return k;
}

/* ---- step 5: what each light costs ---------------------------------------------------------------- */
static volatile float g_sink; /* the timed loops' results go here, so the compiler keeps the loops */
static void time_lights(const pbrt_InfiniteAreaLight *port, const el_envlight *lib, int n) {
  float *u = (float *)malloc(sizeof(float) * 2 * (size_t)n), acc = 0;
  double t[2][3];
  int i, which;
  rng r;
  if (!u) return;
  rng_seed(&r, 9);
  for (i = 0; i < 2 * n; ++i) u[i] = rng_float(&r);
  for (which = 0; which < 2; ++which) {
    double t0 = cpu_now();
    for (i = 0; i < n; ++i) { /* Sample_Li with its radiance */
      float wi[3], L[3], pdf;
      if (which) el_envlight_sample_li(lib, u + 2 * i, wi, L, &pdf);
      else pbrt_InfiniteAreaLight_Sample_Li(port, u + 2 * i, wi, &pdf, L);
      acc += pdf + L[0];
    }
    t[which][0] = cpu_now() - t0;
    t0 = cpu_now();
    for (i = 0; i < n; ++i) { /* Pdf_Li and Le of a direction uniform on the sphere */
      float z = 1 - 2 * u[2 * i], ph = 2 * pbrt_Pi * u[2 * i + 1], s = sqrtf(fmaxf(0, 1 - z * z)), w[3];
      w[0] = s * cosf(ph); w[1] = s * sinf(ph); w[2] = z;
      acc += which ? el_envlight_pdf_li(lib, w) : pbrt_InfiniteAreaLight_Pdf_Li(port, w);
    }
    t[which][1] = cpu_now() - t0;
    t0 = cpu_now();
    for (i = 0; i < n; ++i) {
      float z = 1 - 2 * u[2 * i], ph = 2 * pbrt_Pi * u[2 * i + 1], s = sqrtf(fmaxf(0, 1 - z * z)), w[3], L[3];
      w[0] = s * cosf(ph); w[1] = s * sinf(ph); w[2] = z;
      if (which) el_envlight_le(lib, w, L);
      else pbrt_InfiniteAreaLight_Le(port, w, L);
      acc += L[1];
    }
    t[which][2] = cpu_now() - t0;
  }
  printf("        Sample_Li + its Le: port %.0f ns, envlight.h %.0f ns (%.1fx)   [CPU time of one thread, this run]\n",
         1e9 * t[0][0] / n, 1e9 * t[1][0] / n, t[0][0] / t[1][0]);
  printf("        Pdf_Li:             port %.0f ns, envlight.h %.0f ns (%.1fx)\n", 1e9 * t[0][1] / n, 1e9 * t[1][1] / n,
         t[0][1] / t[1][1]);
  printf("        Le:                 port %.0f ns, envlight.h %.0f ns (%.1fx)\n", 1e9 * t[0][2] / n, 1e9 * t[1][2] / n,
         t[0][2] / t[1][2]);
  g_sink = acc;
  free(u);
}

/* ---- the exercises' numbers ------------------------------------------------------------------------ */
static int cmp_double(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}
static void answers(const pbrt_InfiniteAreaLight *port, const el_envlight *lib) {
  const pbrt_Lmap *m = &port->Lmap;
  pbrt_Transform r90 = pbrt_RotateX(90), rm90 = pbrt_RotateX(-90);
  float z[3] = {0, 0, 1}, south[3] = {0, 0, -1}, w[3], a[3], b[3];
  double worst = 0, sun = 0, *lum = (double *)malloc(sizeof(double) * (size_t)m->width * (size_t)m->height / 2);
  int i, j, n = 0;
  /* 1. twice the resolution: pbrt's four point lookups per texel against the texel's cell average */
  for (j = 1; j < m->height - 1; ++j)
    for (i = 0; i < m->width; ++i) {
      double sum = 0, ca = 0;
      static const double tw[3] = {0.125, 0.75, 0.125};
      int p, q;
      for (q = 0; q < 2; ++q)
        for (p = 0; p < 2; ++p)
          sum += port->distribution.pConditionalV[2 * j + q].func[2 * i + p] / sinf(pbrt_Pi * (2 * j + q + .5f) / (2 * m->height));
      for (q = 0; q < 3; ++q)
        for (p = 0; p < 3; ++p)
          ca += tw[p] * tw[q] * pbrt_y(m->texels + 3 * ((size_t)(j - 1 + q) * m->width + (size_t)((i - 1 + p + m->width) % m->width)));
      worst = fmax(worst, fabs(sum / 4 - ca) / ca);
    }
  printf("answer 1: the mean of pbrt's 4 lookups per texel equals the texel's cell average to %.1e (relative)\n", worst);
  printf("          bins: pbrt %d x %d, envlight.h %d x %d\n", port->distribution.nu, port->distribution.nv, lib->imp_w, lib->imp_h);
  /* 2. the poles */
  printf("answer 2: sinf(acosf(-1)) = %.6e, sinf(acosf(1)) = %g\n", (double)sinf(acosf(-1.0f)), (double)sinf(acosf(1.0f)));
  pbrt_Transform_Vector(&port->LightToWorld, south, w);
  printf("          Pdf_Li at the south pole: port %.6g, envlight.h %.6g\n", (double)pbrt_InfiniteAreaLight_Pdf_Li(port, w),
         (double)el_envlight_pdf_li(lib, w));
  pbrt_Transform_Vector(&port->LightToWorld, z, w);
  printf("          Pdf_Li at the north pole: port %.6g, envlight.h %.6g\n", (double)pbrt_InfiniteAreaLight_Pdf_Li(port, w),
         (double)el_envlight_pdf_li(lib, w));
  /* 3. Clamp in v: the north pole's Le */
  pbrt_InfiniteAreaLight_Le(port, w, a);
  el_envlight_le(lib, w, b);
  printf("answer 3: Le at the north pole: port (Repeat in v) %.4g %.4g %.4g, envlight.h (Clamp) %.4g %.4g %.4g\n", a[0], a[1],
         a[2], b[0], b[1], b[2]);
  /* 4. RotateX(90) and RotateX(-90): where the map's top row (light +z) points in the world */
  pbrt_Transform_Vector(&r90, z, a);
  pbrt_Transform_Vector(&rm90, z, b);
  printf("answer 4: light +z goes to (%ld, %ld, %ld) under RotateX(90), to (%ld, %ld, %ld) under RotateX(-90)\n",
         lrintf(a[0]), lrintf(a[1]), lrintf(a[2]), lrintf(b[0]), lrintf(b[1]), lrintf(b[2]));
  /* 5. the seed's brightening: the brightest texel against the median of the upper half */
  for (i = 0; lum && i < m->width * m->height / 2; ++i, ++n) {
    lum[i] = pbrt_y(m->texels + 3 * (size_t)i);
    sun = fmax(sun, lum[i]);
  }
  if (lum) {
    double sky;
    qsort(lum, (size_t)n, sizeof(double), cmp_double);
    sky = lum[n / 2];
    printf("answer 5: sun / sky (brightest texel / median of the upper half): r %.4g, r + sqrt(r) %.4g, r * sqrt(r) %.4g\n",
           sun / sky, (sun + sqrt(sun)) / (sky + sqrt(sky)), sun * sqrt(sun) / (sky * sqrt(sky)));
  }
  free(lum);
}

int main(int argc, char **argv) {
  const char *map = EL_SOURCE_DIR "/data/envmaps/city.hdr", *dir = "out", *name;
  int quick = 0, want_answers = 0, i, res[2], status = 1;
  float L[3] = {1, 1, 1}, *texels = NULL;
  char err[512];
  el_image checked;
  pbrt_InfiniteAreaLight port;
  el_envlight lib;
  el_envlight_options lo;
  pbrt_Transform rx = pbrt_RotateX(-90), rz = pbrt_RotateZ(LIGHT_ROTATE_DEG), LightToWorld = pbrt_Transform_mul(&rx, &rz);
  scene sc;
  double t0, t_port, t_lib;

  for (i = 1; i < argc; ++i) {
    if (!strcmp(argv[i], "--quick")) quick = 1;
    else if (!strcmp(argv[i], "--answers")) want_answers = 1;
    else if (!strcmp(argv[i], "--out") && i + 1 < argc) dir = argv[++i];
    else if (argv[i][0] != '-') map = argv[i];
    else {
      int help = !strcmp(argv[i], "--help") || !strcmp(argv[i], "-h");
      fprintf(help ? stdout : stderr, "usage: 03_infinite_light [--quick | --answers] [--out DIR] [envmap]\n"
              "  (nothing)   every step, with the pictures\n"
              "  --quick     steps 1, 2, 3 and 5's numbers; no pictures, no rendering\n"
              "  --answers   the numbers the chapter's exercises ask for\n"
              "  --out DIR   where the pictures go (default out/)\n"
              "  envmap      default data/envmaps/city.hdr; a power-of-two map (the port keeps MIP level 0 only)\n");
      return help ? 0 : 1;
    }
  }
  name = strrchr(map, '/') ? strrchr(map, '/') + 1 : map;
  memset(&sc, 0, sizeof sc);
  memset(&lib, 0, sizeof lib);
  memset(&port, 0, sizeof port);

  /* 1. The map. stb reads some truncated and corrupt files without noticing, so the checked loader
   *    reads the file first (its error names the file and the problem); then the seed's code. */
  if (el_image_load(map, &checked, err, sizeof err) != 0) {
    fprintf(stderr, "03_infinite_light: %s\n", err);
    return 1;
  }
  el_image_free(&checked);
  texels = pbrt_LoadEnvironmentMap(map, L, res);
  if (!texels) {
    fprintf(stderr, "03_infinite_light: %s: stb_image cannot read it as an RGB image\n", map);
    return 1;
  }
  if (!want_answers) printf("step 1: %s read with stbi_loadf: %d x %d texels, each times L = (1, 1, 1)\n", name, res[0], res[1]);

  /* 2. The port's light: <<Compute scalar-valued image img from environment map>> at twice the map's
   *    resolution, then <<Compute sampling distributions for rows and columns of image>>. */
  t0 = cpu_now();
  i = pbrt_InfiniteAreaLight_init(&port, &LightToWorld, texels, res);
  t_port = cpu_now() - t0;
  if (i != 0) {
    fprintf(stderr, "03_infinite_light: %s: %s\n", map,
            i == -2 ? "the port takes maps whose sides are powers of two, less than 4:1" : "out of memory");
    goto done;
  }
  if (!want_answers) {
    double unreach, share;
    pbrt_Distribution2D_unreachable(&port.distribution, &unreach, &share);
    printf("step 2: the port's Distribution2D: %d x %d bins (twice the map), %.1f MB\n", port.distribution.nu,
           port.distribution.nv, pbrt_Distribution2D_bytes(&port.distribution) / 1048576.0);
    printf("        positive bins its float CDF never samples: %.0f (%.2g of the integral)\n", unreach, share);
  }

  /* 3. The three queries, at the world's zenith and at one sample */
  if (!want_answers) {
    float ahead[3] = {0, 0, 1}, u[2] = {0.5f, 0.5f}, wi[3], pdf, Ls[3], La[3];
    pbrt_InfiniteAreaLight_Le(&port, ahead, La);
    pbrt_InfiniteAreaLight_Sample_Li(&port, u, wi, &pdf, Ls);
    printf("step 3: Le(0, 0, 1) = (%.4f, %.4f, %.4f): the horizon, straight ahead of the camera\n", La[0], La[1], La[2]);
    printf("        Sample_Li(0.5, 0.5): wi = (%.4f, %.4f, %.4f), pdf %.4f, L = (%.4f, %.4f, %.4f)\n", wi[0], wi[1], wi[2],
           pdf, Ls[0], Ls[1], Ls[2]);
    printf("        Pdf_Li(wi) = %.4f\n", pbrt_InfiniteAreaLight_Pdf_Li(&port, wi));
  }

  /* 5 (built here, used in 4 and 5). The library's light: the same texels, the same matrix. */
  memset(&lo, 0, sizeof lo); /* all zero: pbrt-v3's light, with the library's defaults */
  memcpy(lo.light_to_world, LightToWorld.m, sizeof lo.light_to_world);
  t0 = cpu_now();
  if (el_envlight_init(&lib, texels, res[0], res[1], 3, &lo) != EL_SUCCESS || el_envlight_prepare_sampling(&lib) != EL_SUCCESS) {
    fprintf(stderr, "03_infinite_light: %s: envlight.h refused the map\n", map);
    goto done;
  }
  t_lib = cpu_now() - t0;
  if (want_answers) {
    answers(&port, &lib);
    status = 0;
    goto done;
  }

  if (!quick) { /* 2's picture, then 4: render with the port's light */
    enum { PW = 240, PH = 180, RW = 480, RH = 360, SPP = 16, REF_SPP = 512, RENDER_SPP = 64 };
    light lp, ll;
    float *ref = (float *)malloc(sizeof(float) * 3 * PW * PH), *img = (float *)malloc(sizeof(float) * 3 * RW * RH);
    float *img2 = (float *)malloc(sizeof(float) * 3 * RW * RH);
    unsigned char *p8 = (unsigned char *)malloc(3 * RW * RH), *page = (unsigned char *)calloc(3 * 2 * RW * RH, 1);
    char text[128];
    double t;
    int s;
    make_dir(dir);
    if (!ref || !img || !img2 || !p8 || !page || picture_importance(&port, dir) != 0 || scene_build(&sc) != 0) {
      fprintf(stderr, "03_infinite_light: out of memory, or no Embree device\n");
      free(ref); free(img); free(img2); free(p8); free(page);
      goto done;
    }
    lp.port = &port; lp.lib = NULL;
    ll.port = NULL; ll.lib = &lib;
    t = render(&sc, &lp, MIS, PW, PH, REF_SPP, 999, ref);
    printf("step 4: reference: MIS, %d spp, %d x %d, %.1f CPU s\n", REF_SPP, PW, PH, t);
    for (s = 0; s < 4; ++s) {
      double e;
      t = render(&sc, &lp, s, PW, PH, SPP, 1, img);
      e = rel_mse(img, ref, 3 * PW * PH);
      printf("        %-18s %d spp: relMSE %.4g, %.2f CPU s\n", STRATEGY[s], SPP, e, t);
      to8(img, PW, PH, p8);
      el_canvas_blit(page, 2 * PW, 2 * PH, p8, PW, PH, (s % 2) * PW, (s / 2) * PH, 1);
      el_draw_label(page, 2 * PW, 2 * PH, (s % 2) * PW + 4, (s / 2) * PH + 4, STRATEGY[s]);
      snprintf(text, sizeof text, "RELMSE %.3g", e);
      el_draw_label(page, 2 * PW, 2 * PH, (s % 2) * PW + 4, (s / 2) * PH + PH - 26, text);
    }
    write_page(dir, "03-strategies.png", page, 2 * PW, 2 * PH);
    /* the render, with the port's light and with the library's, the same seed */
    t = render(&sc, &lp, MIS, RW, RH, RENDER_SPP, 5, img);
    to8(img, RW, RH, p8);
    el_canvas_blit(page, 2 * RW, RH, p8, RW, RH, 0, 0, 1);
    snprintf(text, sizeof text, "PBRT-V3 PORT: %.1f CPU S", t);
    el_draw_label(page, 2 * RW, RH, 4, 4, text);
    printf("        the render, MIS, %d spp, %d x %d: the port's light %.1f CPU s", RENDER_SPP, RW, RH, t);
    t = render(&sc, &ll, MIS, RW, RH, RENDER_SPP, 5, img2);
    to8(img2, RW, RH, p8);
    el_canvas_blit(page, 2 * RW, RH, p8, RW, RH, RW, 0, 1);
    snprintf(text, sizeof text, "ENVLIGHT.H: %.1f CPU S", t);
    el_draw_label(page, 2 * RW, RH, RW + 4, 4, text);
    printf(", envlight.h's %.1f CPU s; relMSE between the two %.3g\n", t, rel_mse(img2, img, 3 * RW * RH));
    snprintf(text, sizeof text, "MIS, %d SPP, BOTH", RENDER_SPP);
    el_draw_label(page, 2 * RW, RH, 4, RH - 26, text);
    write_page(dir, "03-render.png", page, 2 * RW, RH);
    free(ref); free(img); free(img2); free(p8); free(page);
  }

  /* 5. The library beside the port */
  {
    float south[3] = {0, 0, -1}, w[3];
    pbrt_Transform_Vector(&port.LightToWorld, south, w);
    printf("step 5: envlight.h: %d x %d bins (one per texel), %.1f MB with the texels; the port %.1f MB\n", lib.imp_w,
           lib.imp_h, el_envlight_bytes(&lib) / 1048576.0, pbrt_InfiniteAreaLight_bytes(&port) / 1048576.0);
    printf("        positive bins never sampled: 0 (its integer CDF gives each at least 1 of 2^24 units)\n");
    printf("        Pdf_Li at the south pole: port %.4g, envlight.h %.4g\n", pbrt_InfiniteAreaLight_Pdf_Li(&port, w),
           el_envlight_pdf_li(&lib, w));
    printf("        construction: port %.1f ms, envlight.h %.1f ms (%.1fx)   [CPU time of one thread, this run]\n",
           1e3 * t_port, 1e3 * t_lib, t_port / t_lib);
    time_lights(&port, &lib, quick ? 200000 : 1000000);
  }
  status = 0;
done:
  scene_free(&sc);
  pbrt_InfiniteAreaLight_free(&port);
  el_envlight_free(&lib);
  free(texels);
  return status;
}
