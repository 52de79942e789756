/* 03_infinite_light.c: objects lit only by an environment map (chapter 3 of the tutorial).
 *
 * NEEDS_EMBREE: this marker makes examples/CMakeLists.txt link the program with Embree 3.
 *
 * WHAT IT DEMONSTRATES
 *   The chapter's picture: three diffuse spheres on a diffuse ground plane, with no light but a
 *   latitude-longitude environment map (by default data/envmaps/city.hdr, whose sun is 3e4 times
 *   brighter than its sky). Each pixel is shaded with direct lighting only, estimated the way pbrt-v3's
 *   DirectLightingIntegrator does it for one light: one direction drawn from the environment's
 *   importance-sampling distribution (envlight.h's sample_li) and one from the surface's cosine lobe,
 *   combined by multiple importance sampling (the power heuristic, which needs the light's pdf_li of the
 *   BSDF's direction). Rays that miss every object show the environment itself (le). The film (film.h)
 *   accumulates the box-filtered samples and encodes sRGB.
 *   It is written for reading, like Embree's tutorials/minimal: every Embree call is commented.
 *
 * WHICH PART OF PBRT IT MIRRORS
 *   pbrt-v3, section 12.6 "Infinite Area Lights" and 14.2.4 "Infinite Area Lights" (its sampling;
 *   src/lights/infinite.h, infinite.cpp): the light, with
 *   its fragments <<Compute scalar-valued image img from environment map>>, <<Compute sampling
 *   distributions for rows and columns of image>>, <<Find (u,v) sample coordinates in infinite light
 *   texture>>, <<Convert infinite light sample point to direction>>, <<Compute PDF for
 *   sampled infinite light direction>>, <<Return radiance value for infinite light direction>> all live
 *   in envlight.h; this file only calls them. Section 14.3.1 "Estimating the Direct Lighting Integral"
 *   (src/core/integrator.cpp, EstimateDirect) for the shading below, with its fragments named where
 *   they happen; 13.10.1 for the power heuristic. Sections 6.2.2 (PerspectiveCamera) and 2.7.7 (LookAt)
 *   for the camera.
 *   pbrt-v3's conventions are kept: a LEFT-handed camera (LookAt's "right" is cross(up, dir)), the field
 *   of view on the shorter image axis, raster y pointing down, and the light's mapping: in light space
 *   +z is "up", (u, v) = (phi / 2pi, theta / pi), row 0 of the map is the zenith.
 *   The tutorial's world is y-up, so it rotated the light (InfinityLightToWorld = RotateX(90)); this
 *   scene is z-up like pbrt's own test scenes, and its light-to-world is a rotation about z that turns
 *   the sun to light the spheres from the front-left (change LIGHT_ROTATE_Z_DEG below to see it move).
 *
 * HOW TO RUN IT
 *   build/bin/03_infinite_light [envmap.hdr|.exr|.pfm] [out.png|.exr|.pfm|.hdr] [spp] [strategy] [seed]
 *     envmap    default EL_SOURCE_DIR "/data/envmaps/city.hdr"
 *     out       default out/03_infinite_light.png (the folder is created); a float format keeps HDR
 *     spp       samples per pixel, default 16
 *     strategy  mis (default, pbrt's), light (environment sampling only), bsdf (cosine sampling only),
 *               uniform (directions uniform on the sphere: what a light without importance sampling,
 *               like the tutorial's earlier environment light, can do)
 *     seed      default 0; the image depends only on it, not on the number of threads
 *   tutorials/03-infinite-light-render.md measures the noise of each strategy against time.
 *
 * WHAT IT WRITES
 *   The image (400x300), and on stdout the sampling distribution's size and build time, the image's
 *   path, the render time and the ray rate.
 */
#define _POSIX_C_SOURCE 200809L /* clock_gettime, sysconf under -std=c99 */
#define EL_IMPLEMENTATION       /* this file compiles the envlight implementations (all headers) */
#include "envlight.h"
#include "film.h"
#include "image_io.h" /* examples/common: reading .hdr/.exr, writing .png/.exr */

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
#include <unistd.h>

#ifndef EL_SOURCE_DIR
#define EL_SOURCE_DIR "."
#endif

#define WIDTH 400
#define HEIGHT 300
#define FOV_DEG 38.0f              /* pbrt "fov": on the shorter axis (here the vertical one) */
#define LIGHT_ROTATE_Z_DEG 120.0f  /* the light-to-world rotation about +z */
#define PI_F 3.14159265358979323846f

enum strategy { STRATEGY_MIS, STRATEGY_LIGHT, STRATEGY_BSDF, STRATEGY_UNIFORM };

/* ---------------------------------------------------------------------------------------------------
 * Small vector helpers (pbrt's Vector3f, reduced to what a reader needs)
 * ------------------------------------------------------------------------------------------------ */
typedef struct vec3 { float x, y, z; } vec3;
static vec3 v3(float x, float y, float z) { vec3 v; v.x = x; v.y = y; v.z = z; return v; }
static vec3 add(vec3 a, vec3 b) { return v3(a.x + b.x, a.y + b.y, a.z + b.z); }
static vec3 sub(vec3 a, vec3 b) { return v3(a.x - b.x, a.y - b.y, a.z - b.z); }
static vec3 mul(vec3 a, float s) { return v3(a.x * s, a.y * s, a.z * s); }
static float dot(vec3 a, vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static vec3 cross(vec3 a, vec3 b) {
  return v3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
static vec3 normalize(vec3 a) { return mul(a, 1.0f / sqrtf(dot(a, a))); }

/* A tiny PCG32 random number generator (pbrt-v3's RNG is PCG32 too), seeded per pixel so that the
 * image does not depend on how rows are shared out between threads. */
typedef struct rng { uint64_t state, inc; } rng;
static uint32_t rng_u32(rng *r) {
  uint64_t old = r->state;
  uint32_t xorshifted, rot;
  r->state = old * 6364136223846793005ULL + r->inc;
  xorshifted = (uint32_t)(((old >> 18u) ^ old) >> 27u);
  rot = (uint32_t)(old >> 59u);
  return (xorshifted >> rot) | (xorshifted << ((32u - rot) & 31u));
}
static float rng_float(rng *r) { /* [0, 1): 24 random bits, never rounds up to 1 */
  return (float)(rng_u32(r) >> 8) * (1.0f / 16777216.0f);
}
static void rng_seed(rng *r, uint64_t seq) {
  r->state = 0u;
  r->inc = (seq << 1u) | 1u;
  rng_u32(r);
  r->state += 0x853c49e6748fea9bULL;
  rng_u32(r);
}

/* ---------------------------------------------------------------------------------------------------
 * The scene, built in code: a ground plane (two triangles) and three spheres
 * ------------------------------------------------------------------------------------------------ */
typedef struct sphere_def { float x, y, z, r; float kd[3]; } sphere_def;
static const sphere_def SPHERES[3] = {
    {0.0f, 0.0f, 1.0f, 1.0f, {0.80f, 0.80f, 0.80f}},   /* white, in the middle */
    {-2.1f, -0.4f, 0.7f, 0.7f, {0.80f, 0.25f, 0.20f}}, /* red, at x < 0: on the image's RIGHT */
    {1.9f, -0.9f, 0.5f, 0.5f, {0.20f, 0.35f, 0.80f}},  /* blue, at x > 0: on the image's LEFT */
};
/* Why red is on the right: the camera looks along +y with +z up, and pbrt's left-handed LookAt puts
 * cross(up, dir) = cross(+z, +y) = -x on the image's right. A right-handed renderer (Mitsuba, Embree's
 * tutorials) given the same numbers shows the mirror image. */
static const float GROUND_KD[3] = {0.50f, 0.50f, 0.45f};
#define GROUND_HALF 12.0f

typedef struct scene {
  RTCDevice device;
  RTCScene rtc;
  unsigned ground_id, spheres_id; /* Embree's geometry IDs, to tell what a ray hit */
} scene;

static void embree_error(void *user, enum RTCError code, const char *str) {
  (void)user;
  fprintf(stderr, "03_infinite_light: Embree error %d: %s\n", (int)code, str);
}

static int scene_build(scene *s) {
  RTCGeometry geom;
  float *vertices;
  unsigned *indices;
  int i;

  /* rtcNewDevice: Embree's context (its thread pool, memory, settings). NULL: the default settings. */
  s->device = rtcNewDevice(NULL);
  if (!s->device) {
    fprintf(stderr, "03_infinite_light: cannot create an Embree device (error %d)\n",
            (int)rtcGetDeviceError(NULL));
    return -1;
  }
  /* rtcSetDeviceErrorFunction: every later Embree error is reported through this callback. */
  rtcSetDeviceErrorFunction(s->device, embree_error, NULL);

  /* rtcNewScene: an empty container of geometries; the BVH is built when it is committed. */
  s->rtc = rtcNewScene(s->device);

  /* -- the ground: a triangle mesh of two triangles covering [-12, 12]^2 at z = 0 -- */
  /* rtcNewGeometry: a geometry of a given type, not yet in any scene. */
  geom = rtcNewGeometry(s->device, RTC_GEOMETRY_TYPE_TRIANGLE);
  /* rtcSetNewGeometryBuffer: Embree allocates a buffer (slot 0 of the vertex buffer: 3 floats per
   * vertex, 4 vertices) and returns a pointer we fill. Embree may read 16 bytes past a vertex, which
   * its own allocation accounts for. */
  vertices = (float *)rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                              3 * sizeof(float), 4);
  /* ... and the index buffer: 3 unsigned ints per triangle, 2 triangles. */
  indices = (unsigned *)rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                3 * sizeof(unsigned), 2);
  if (!vertices || !indices) return -1;
  vertices[0] = -GROUND_HALF; vertices[1] = -GROUND_HALF; vertices[2] = 0.0f;
  vertices[3] = GROUND_HALF;  vertices[4] = -GROUND_HALF; vertices[5] = 0.0f;
  vertices[6] = GROUND_HALF;  vertices[7] = GROUND_HALF;  vertices[8] = 0.0f;
  vertices[9] = -GROUND_HALF; vertices[10] = GROUND_HALF; vertices[11] = 0.0f;
  indices[0] = 0; indices[1] = 1; indices[2] = 2;
  indices[3] = 0; indices[4] = 2; indices[5] = 3;
  /* rtcCommitGeometry: the buffers are final; Embree may now read them. */
  rtcCommitGeometry(geom);
  /* rtcAttachGeometry: put it into the scene; the returned ID comes back in every hit on it. */
  s->ground_id = rtcAttachGeometry(s->rtc, geom);
  /* rtcReleaseGeometry: drop our reference; the scene keeps its own. */
  rtcReleaseGeometry(geom);

  /* -- the spheres: Embree's exact sphere primitive (not a tessellation), like pbrt's Sphere -- */
  /* RTC_GEOMETRY_TYPE_SPHERE_POINT: each "vertex" is a sphere, (x, y, z, radius) as 4 floats. */
  geom = rtcNewGeometry(s->device, RTC_GEOMETRY_TYPE_SPHERE_POINT);
  vertices = (float *)rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4,
                                              4 * sizeof(float), 3);
  if (!vertices) return -1;
  for (i = 0; i < 3; ++i) {
    vertices[4 * i + 0] = SPHERES[i].x;
    vertices[4 * i + 1] = SPHERES[i].y;
    vertices[4 * i + 2] = SPHERES[i].z;
    vertices[4 * i + 3] = SPHERES[i].r;
  }
  rtcCommitGeometry(geom);
  s->spheres_id = rtcAttachGeometry(s->rtc, geom);
  rtcReleaseGeometry(geom);

  /* rtcCommitScene: build the acceleration structure (a BVH). After this the scene is read-only and
   * any number of threads may trace rays in it at once. */
  rtcCommitScene(s->rtc);
  return 0;
}

static void scene_free(scene *s) {
  /* rtcReleaseScene / rtcReleaseDevice: reference counted; this frees the BVH and the geometries. */
  if (s->rtc) rtcReleaseScene(s->rtc);
  if (s->device) rtcReleaseDevice(s->device);
}

/* ---------------------------------------------------------------------------------------------------
 * The camera: pbrt-v3's LookAt and PerspectiveCamera (pinhole)
 * ------------------------------------------------------------------------------------------------ */
typedef struct camera {
  vec3 eye, right, up, dir; /* camera-to-world: columns right, up, dir (pbrt's LookAt) */
  float screen_x, screen_y; /* half extents of the screen window at distance 1: tan(fov/2) * aspect */
} camera;

static void camera_init(camera *c, vec3 eye, vec3 look, vec3 up) {
  float aspect = (float)WIDTH / (float)HEIGHT, t = tanf(0.5f * FOV_DEG * PI_F / 180.0f);
  c->eye = eye;
  c->dir = normalize(sub(look, eye));
  /* pbrt-v3 LookAt: right = cross(up, dir). With z up and dir pointing into the scene this is the
   * LEFT-handed frame: the image's right side is what a right-handed renderer would show mirrored. */
  c->right = normalize(cross(normalize(up), c->dir));
  c->up = cross(c->dir, c->right);
  /* pbrt's screen window is [-aspect, aspect] x [-1, 1] when the image is wider than tall: the fov
   * applies to the shorter axis. */
  if (aspect > 1.0f) { c->screen_x = t * aspect; c->screen_y = t; }
  else { c->screen_x = t; c->screen_y = t / aspect; }
}

/* The direction of the ray through raster position (px, py): raster x to the right, y DOWN. */
static vec3 camera_ray(const camera *c, float px, float py) {
  float sx = (2.0f * px / (float)WIDTH - 1.0f) * c->screen_x;
  float sy = (1.0f - 2.0f * py / (float)HEIGHT) * c->screen_y;
  return normalize(add(add(mul(c->right, sx), mul(c->up, sy)), c->dir));
}

/* ---------------------------------------------------------------------------------------------------
 * Ray queries
 * ------------------------------------------------------------------------------------------------ */
/* rtcIntersect1: the closest hit along one ray. Returns 0 on a miss, else fills t, the geometry ID and
 * the (unnormalised) geometric normal. */
static int trace_closest(RTCScene rtc, vec3 o, vec3 d, float *t, unsigned *geom_id, unsigned *prim_id,
                         vec3 *ng) {
  struct RTCIntersectContext ctx;
  struct RTCRayHit rh;
  /* rtcInitIntersectContext: per-query settings; INCOHERENT is right for scattered rays. */
  rtcInitIntersectContext(&ctx);
  rh.ray.org_x = o.x; rh.ray.org_y = o.y; rh.ray.org_z = o.z;
  rh.ray.dir_x = d.x; rh.ray.dir_y = d.y; rh.ray.dir_z = d.z;
  rh.ray.tnear = 0.0f;
  rh.ray.tfar = INFINITY;
  rh.ray.mask = 0xFFFFFFFFu; /* every geometry */
  rh.ray.flags = 0;
  rh.ray.time = 0.0f;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID; /* stays so on a miss */
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(rtc, &ctx, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return 0;
  *t = rh.ray.tfar; /* on a hit, tfar is the hit distance */
  *geom_id = rh.hit.geomID;
  *prim_id = rh.hit.primID;
  *ng = v3(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z);
  return 1;
}

/* rtcOccluded1: does anything block the ray? Cheaper than rtcIntersect1 (any hit ends the search).
 * A direction towards an infinite light needs no tfar: the light is "behind" every object. */
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
  return ray.tfar < 0.0f; /* Embree sets tfar to -inf when it found a blocker */
}

/* ---------------------------------------------------------------------------------------------------
 * Shading: direct lighting of a Lambertian surface by the environment (pbrt-v3 EstimateDirect)
 * ------------------------------------------------------------------------------------------------ */
typedef struct render_ctx {
  scene *sc;
  el_envlight *light;
  camera cam;
  el_film *film;
  pthread_mutex_t film_mutex;
  int spp, strategy, next_row;
  uint64_t seed;
  pthread_mutex_t row_mutex;
  unsigned long long rays; /* all threads' rays, summed under film_mutex */
} render_ctx;

static float power_heuristic(float fpdf, float gpdf) { /* pbrt's PowerHeuristic with nf = ng = 1 */
  float f2 = fpdf * fpdf, g2 = gpdf * gpdf;
  return f2 + g2 > 0.0f ? f2 / (f2 + g2) : 0.0f;
}

/* An orthonormal frame around n (Duff et al. 2017, as pbrt-v4's CoordinateSystem). */
static void make_frame(vec3 n, vec3 *s, vec3 *t) {
  float sign = n.z >= 0.0f ? 1.0f : -1.0f;
  float a = -1.0f / (sign + n.z), b = n.x * n.y * a;
  *s = v3(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x);
  *t = v3(b, sign + n.y * n.y * a, -n.y);
}

/* The radiance reaching the camera along one camera ray. */
static void radiance(render_ctx *c, vec3 o, vec3 d, rng *r, float out[3], unsigned long long *rays) {
  float t, kd[3], wdir[3], L[3], pdf_light, pdf_bsdf, w, cos_theta;
  unsigned gid, pid;
  vec3 ng, n, p, wi, s_axis, t_axis;
  int k;

  *rays += 1;
  if (!trace_closest(c->sc->rtc, o, d, &t, &gid, &pid, &ng)) {
    /* <<Add contribution of each light source>> for a ray that escapes: the environment itself,
     * pbrt's Le(ray) (<<Return radiance value for infinite light direction>>). */
    wdir[0] = d.x; wdir[1] = d.y; wdir[2] = d.z;
    el_envlight_le(c->light, wdir, out);
    return;
  }
  if (gid == c->sc->ground_id) {
    memcpy(kd, GROUND_KD, sizeof kd);
  } else {
    memcpy(kd, SPHERES[pid].kd, sizeof kd);
  }
  /* The surface point, its normal turned towards the viewer (pbrt's matte is two-sided), and the point
   * moved off the surface a little so that shadow rays do not hit it again (pbrt's SpawnRay offsets
   * by the floating-point error bounds; a fixed epsilon is enough for this scene's scale). */
  n = normalize(ng);
  if (dot(n, d) > 0.0f) n = mul(n, -1.0f);
  p = add(add(o, mul(d, t)), mul(n, 1e-4f));
  make_frame(n, &s_axis, &t_axis);
  out[0] = out[1] = out[2] = 0.0f;

  if (c->strategy == STRATEGY_UNIFORM) {
    /* No importance sampling: a direction uniform on the sphere (pdf 1 / 4pi), pbrt's
     * UniformSampleSphere. Most of them land on the dim sky; the sun is found by chance. */
    float u1 = rng_float(r), u2 = rng_float(r);
    float z = 1.0f - 2.0f * u1, rad = sqrtf(fmaxf(0.0f, 1.0f - z * z)), phi = 2.0f * PI_F * u2;
    wi = v3(rad * cosf(phi), rad * sinf(phi), z);
    cos_theta = dot(wi, n);
    if (cos_theta > 0.0f) {
      *rays += 1;
      if (!occluded(c->sc->rtc, p, wi)) {
        wdir[0] = wi.x; wdir[1] = wi.y; wdir[2] = wi.z;
        el_envlight_le(c->light, wdir, L);
        /* f * Li * cos / pdf = (kd / pi) * Li * cos * 4pi */
        for (k = 0; k < 3; ++k) out[k] += kd[k] * L[k] * cos_theta * 4.0f;
      }
    }
    return;
  }

  if (c->strategy == STRATEGY_MIS || c->strategy == STRATEGY_LIGHT) {
    /* <<Sample light source with multiple importance sampling>>: the light picks a direction in
     * proportion to its (filtered) brightness: pbrt's InfiniteAreaLight::Sample_Li. */
    float u[2];
    u[0] = rng_float(r);
    u[1] = rng_float(r);
    el_envlight_sample_li(c->light, u, wdir, L, &pdf_light);
    wi = v3(wdir[0], wdir[1], wdir[2]);
    cos_theta = dot(wi, n);
    if (pdf_light > 0.0f && cos_theta > 0.0f) {
      /* <<Evaluate BSDF for light sampling strategy>>: f = kd / pi, and the BSDF's own pdf for the
       * MIS weight: cosine sampling has pdf cos / pi. */
      pdf_bsdf = cos_theta / PI_F;
      w = c->strategy == STRATEGY_MIS ? power_heuristic(pdf_light, pdf_bsdf) : 1.0f;
      *rays += 1;
      /* <<Add light's contribution to reflected radiance>> if nothing blocks the way to the light
       * (pbrt's VisibilityTester::Unoccluded) */
      if (!occluded(c->sc->rtc, p, wi))
        for (k = 0; k < 3; ++k) out[k] += kd[k] / PI_F * L[k] * cos_theta * w / pdf_light;
    }
  }

  if (c->strategy == STRATEGY_MIS || c->strategy == STRATEGY_BSDF) {
    /* <<Sample BSDF with multiple importance sampling>>, <<Sample scattered direction for surface
     * interactions>>: a cosine-distributed direction (pbrt's CosineSampleHemisphere, Malley's method),
     * for which f * cos / pdf = kd. */
    float u1 = rng_float(r), u2 = rng_float(r);
    float rad = sqrtf(u1), phi = 2.0f * PI_F * u2;
    float lx = rad * cosf(phi), ly = rad * sinf(phi), lz = sqrtf(fmaxf(0.0f, 1.0f - u1));
    wi = add(add(mul(s_axis, lx), mul(t_axis, ly)), mul(n, lz));
    pdf_bsdf = lz / PI_F;
    if (pdf_bsdf > 0.0f) {
      *rays += 1;
      if (!occluded(c->sc->rtc, p, wi)) {
        /* <<Add light contribution from material sampling>>: the ray escapes, so it sees the
         * environment; <<Account for light contributions along sampled direction wi>>: the light's
         * pdf of this direction (pbrt's Pdf_Li) gives the MIS weight. (pbrt-v3 returns early when
         * Pdf_Li is 0; the power heuristic then gives weight 1, which is right whatever the light's
         * density, and with envlight.h's default density pdf_li > 0 wherever le > 0 anyway.) */
        wdir[0] = wi.x; wdir[1] = wi.y; wdir[2] = wi.z;
        el_envlight_le(c->light, wdir, L);
        w = 1.0f;
        if (c->strategy == STRATEGY_MIS) {
          pdf_light = el_envlight_pdf_li(c->light, wdir);
          w = power_heuristic(pdf_bsdf, pdf_light);
        }
        for (k = 0; k < 3; ++k) out[k] += kd[k] * L[k] * w;
      }
    }
  }
}

/* One thread: takes the next unrendered row until none is left, renders it into its own film tile and
 * merges the tile into the film (film.h's tiles need no locks while samples are added). */
static void *render_rows(void *arg) {
  render_ctx *c = (render_ctx *)arg;
  el_film_tile tile;
  unsigned long long rays = 0;
  memset(&tile, 0, sizeof tile);
  for (;;) {
    int y, x, s;
    pthread_mutex_lock(&c->row_mutex);
    y = c->next_row++;
    pthread_mutex_unlock(&c->row_mutex);
    if (y >= HEIGHT) break;
    /* samples are taken in row y: pixels [0, WIDTH) x [y, y + 1) */
    if ((tile.film ? el_film_tile_reset(&tile, 0, y, WIDTH, y + 1)
                   : el_film_tile_init(c->film, &tile, 0, y, WIDTH, y + 1)) != EL_SUCCESS) {
      fprintf(stderr, "03_infinite_light: out of memory\n");
      break;
    }
    for (x = 0; x < WIDTH; ++x) {
      rng r;
      rng_seed(&r, ((uint64_t)y * WIDTH + (uint64_t)x) ^ (c->seed << 32)); /* one stream per pixel */
      for (s = 0; s < c->spp; ++s) {
        float px = (float)x + rng_float(&r), py = (float)y + rng_float(&r), L[3];
        radiance(c, c->cam.eye, camera_ray(&c->cam, px, py), &r, L, &rays);
        el_film_tile_add_sample(&tile, px, py, L, 1.0f);
      }
    }
    pthread_mutex_lock(&c->film_mutex);
    el_film_merge_tile(c->film, &tile);
    pthread_mutex_unlock(&c->film_mutex);
  }
  pthread_mutex_lock(&c->film_mutex);
  c->rays += rays;
  pthread_mutex_unlock(&c->film_mutex);
  el_film_tile_free(&tile);
  return NULL;
}

static double now(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Make the folder of path (one level, as in "out/x.png"). */
static void make_parent_dir(const char *path) {
  char dir[1024];
  const char *slash = strrchr(path, '/');
  size_t n;
  if (!slash) return;
  n = (size_t)(slash - path);
  if (n == 0 || n >= sizeof dir) return;
  memcpy(dir, path, n);
  dir[n] = '\0';
  if (mkdir(dir, 0777) != 0 && errno != EEXIST) fprintf(stderr, "cannot create %s\n", dir);
}

int main(int argc, char **argv) {
  const char *map_path = argc > 1 ? argv[1] : EL_SOURCE_DIR "/data/envmaps/city.hdr";
  const char *out_path = argc > 2 ? argv[2] : "out/03_infinite_light.png";
  int spp = argc > 3 ? atoi(argv[3]) : 16, strategy = STRATEGY_MIS, nthreads, i, status = 1;
  char err[512];
  el_image map;
  el_envlight light;
  el_film_options fo;
  el_film film;
  scene sc;
  render_ctx ctx;
  pthread_t threads[64];
  float *rgb = NULL;
  unsigned char *srgb = NULL;
  double t0, t_render;

  if (argc > 4) {
    if (!strcmp(argv[4], "mis")) strategy = STRATEGY_MIS;
    else if (!strcmp(argv[4], "light")) strategy = STRATEGY_LIGHT;
    else if (!strcmp(argv[4], "bsdf")) strategy = STRATEGY_BSDF;
    else if (!strcmp(argv[4], "uniform")) strategy = STRATEGY_UNIFORM;
    else {
      fprintf(stderr, "usage: %s [envmap] [out.png|.exr|.pfm] [spp] [mis|light|bsdf|uniform] [seed]\n",
              argv[0]);
      return 1;
    }
  }
  if (spp < 1 || spp > 1 << 20) {
    fprintf(stderr, "03_infinite_light: spp must be in 1..%d\n", 1 << 20);
    return 1;
  }
  memset(&sc, 0, sizeof sc);
  memset(&light, 0, sizeof light);
  memset(&film, 0, sizeof film);
  memset(&map, 0, sizeof map);

  /* 1. The environment map: an equirectangular (latitude-longitude) image, row 0 = the zenith. */
  if (el_image_load(map_path, &map, err, sizeof err) != 0) {
    fprintf(stderr, "03_infinite_light: %s\n", err);
    return 1;
  }

  /* 2. The light: pbrt-v3's InfiniteAreaLight constructor. pbrt keeps the texels in a MIPMap
   *    (its Lmap) but only ever looks them up at level 0, bilinearly; envlight.h keeps the level-0
   *    image and does the same lookup without building a pyramid. <<Initialize sampling PDFs for
   *    infinite area light>>: <<Compute scalar-valued image img from environment map>> (the luminance
   *    of the bilinear image averaged over each bin, times sin(theta) for the lat-long map's stretched
   *    poles) and <<Compute sampling distributions for rows and columns of image>> (the 2D
   *    piecewise-constant distribution that Sample_Li inverts) happen in envlight.h, on first use or
   *    in prepare_sampling below. LightToWorld here: a rotation about +z. */
  {
    el_envlight_options lo;
    float a = LIGHT_ROTATE_Z_DEG * PI_F / 180.0f;
    el_result res;
    memset(&lo, 0, sizeof lo); /* all zero: pbrt's defaults */
    lo.light_to_world[0] = cosf(a); lo.light_to_world[1] = -sinf(a); lo.light_to_world[2] = 0.0f;
    lo.light_to_world[3] = sinf(a); lo.light_to_world[4] = cosf(a);  lo.light_to_world[5] = 0.0f;
    lo.light_to_world[6] = 0.0f;    lo.light_to_world[7] = 0.0f;     lo.light_to_world[8] = 1.0f;
    res = el_envlight_init(&light, map.pixels, map.width, map.height, map.channels, &lo);
    if (res != EL_SUCCESS) {
      fprintf(stderr, "03_infinite_light: %s: %s\n", map_path, el_result_string(res));
      el_image_free(&map);
      return 1;
    }
  }

  /* The sampling tables (pbrt's Distribution2D over the map) are built on the first sample_li or
   * pdf_li anyway, thread-safely; building them here keeps their cost out of the render time and shows
   * it. The bsdf and uniform strategies never ask for them (no sample_li, no pdf_li), so for them the
   * tables are never built. */
  if (strategy == STRATEGY_MIS || strategy == STRATEGY_LIGHT) {
    el_result res;
    t0 = now();
    res = el_envlight_prepare_sampling(&light);
    if (res != EL_SUCCESS) {
      fprintf(stderr, "03_infinite_light: sampling tables: %s\n", el_result_string(res));
      goto done;
    }
    printf("sampling distribution: %dx%d bins, %.1f KiB, built in %.3f s\n", light.imp_w, light.imp_h,
           (double)el_envlight_sampling_bytes(&light) / 1024.0, now() - t0);
  }

  /* 3. The scene and the camera. */
  if (scene_build(&sc) != 0) goto done;
  memset(&ctx, 0, sizeof ctx);
  camera_init(&ctx.cam, v3(0.0f, -7.5f, 2.6f), v3(0.0f, 0.0f, 0.7f), v3(0.0f, 0.0f, 1.0f));

  /* 4. The film: all-zero options are pbrt's default, a box filter of radius 0.5. */
  memset(&fo, 0, sizeof fo);
  fo.width = WIDTH;
  fo.height = HEIGHT;
  if (el_film_init(&film, &fo) != EL_SUCCESS) {
    fprintf(stderr, "03_infinite_light: cannot create the film\n");
    goto done;
  }

  /* 5. Render: one thread per core, rows handed out one at a time. */
  ctx.sc = &sc;
  ctx.light = &light;
  ctx.film = &film;
  ctx.spp = spp;
  ctx.strategy = strategy;
  ctx.seed = argc > 5 ? (uint64_t)strtoull(argv[5], NULL, 10) : 0u;
  pthread_mutex_init(&ctx.film_mutex, NULL);
  pthread_mutex_init(&ctx.row_mutex, NULL);
  nthreads = (int)sysconf(_SC_NPROCESSORS_ONLN);
  if (nthreads < 1) nthreads = 1;
  if (nthreads > 64) nthreads = 64;
  t0 = now();
  for (i = 0; i < nthreads; ++i)
    if (pthread_create(&threads[i], NULL, render_rows, &ctx) != 0) break;
  nthreads = i; /* the threads that started */
  if (nthreads == 0) render_rows(&ctx);
  for (i = 0; i < nthreads; ++i) pthread_join(threads[i], NULL);
  t_render = now() - t0;

  /* 6. Output: linear RGB from the film, then (for PNG) pbrt's clamp and sRGB encoding. */
  rgb = (float *)malloc((size_t)WIDTH * HEIGHT * 3 * sizeof(float));
  srgb = (unsigned char *)malloc((size_t)WIDTH * HEIGHT * 3);
  if (!rgb || !srgb) goto done;
  el_film_get_rgb(&film, 1.0f, rgb);
  make_parent_dir(out_path);
  if (!strcmp(el_image_extension(out_path), "png")) {
    /* pbrt's output curve (clamp at 1, exact sRGB, round to nearest) after one stop less exposure:
     * the sunlit ground is about 1.1 in linear RGB and would clip to white. */
    el_film_output_options oo;
    memset(&oo, 0, sizeof oo);
    oo.exposure = -1.0f;
    if (el_film_to_srgb8(rgb, WIDTH, HEIGHT, &oo, srgb) != EL_SUCCESS ||
        el_image_write_png(out_path, srgb, WIDTH, HEIGHT, 3, err, sizeof err) != 0) {
      fprintf(stderr, "03_infinite_light: %s\n", err);
      goto done;
    }
  } else if (el_image_write_float(out_path, rgb, WIDTH, HEIGHT, 3, err, sizeof err) != 0) {
    fprintf(stderr, "03_infinite_light: %s\n", err);
    goto done;
  }
  printf("wrote %s (%dx%d, %d spp, %s): %.3f s on %d threads, %.2f M rays/s\n", out_path, WIDTH, HEIGHT,
         spp, argc > 4 ? argv[4] : "mis", t_render, nthreads > 0 ? nthreads : 1,
         (double)ctx.rays / t_render * 1e-6);
  status = 0;

done:
  free(rgb);
  free(srgb);
  el_film_free(&film);
  scene_free(&sc);
  el_envlight_free(&light);
  el_image_free(&map);
  return status;
}
