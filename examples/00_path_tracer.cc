/* 00_path_tracer.cc: a complete path tracer on envlight's headers, without Embree.
 *
 * WHAT IT DEMONSTRATES
 *   Three diffuse spheres on a checkered ground plane (intersection code written out here), lit only by
 *   an environment map. At every bounce, multiple importance sampling (MIS) with the power heuristic
 *   combines a direction from the map's product sampling (envlight.h's el_envlight_sample_li_cos: the
 *   map times the clamped cosine of the hit's normal; --plain: the map alone, el_envlight_sample_li)
 *   with one from the cosine lobe;
 *   the cosine direction is also the path's next ray, so its MIS weight is applied where that ray
 *   escapes to the map ("escaped" in Li). The ground's texture is filtered by mipmap.h over a footprint
 *   from ray differentials; film.h filters the samples with pbrt's Gaussian and writes exact sRGB.
 *   It is C++11 for Vec3's operators; the headers are C99 and compile as C++ as they are.
 *
 * WHICH PARTS OF PBRT IT MIRRORS (pbrt-v3 book sections; fragment names in the code)
 *   PathIntegrator::Li (14.5) in pbrt-v4's form: the BSDF sample that continues the path is also
 *   EstimateDirect's BSDF sample (14.3.1). PowerHeuristic (13.10.1), CosineSampleHemisphere (13.6.3),
 *   Sphere (3.2), ray differentials (10.1), MIPMap (10.4), InfiniteAreaLight (12.6, 14.2.4), Film and
 *   GaussianFilter (7.8, 7.9). Unlike pbrt the world is y-up and right-handed, as in Mitsuba 3.
 *
 * HOW TO RUN IT (--help prints this usage)
 *   build/bin/00_path_tracer [map.hdr|.exr|.pfm] [out.png|.pfm|.exr] [spp] [width] [height]
 *     defaults: EL_SOURCE_DIR "/data/envmaps/city.hdr", 00_path_tracer.png, 16, 480, 270.
 *   build/bin/00_path_tracer --furnace [out] [spp] [width] [height]: a white sphere (albedo 1) fills the
 *     frame under a sky of radiance 1 + 0.75 P3(cos theta), P3 the Legendre polynomial. A cosine lobe
 *     has no l = 3 part, so every pixel must be 1, as under a constant sky of 1, while this sky's
 *     importance sampling is far from uniform: a wrong MIS weight or pdf shows (tests/test_path_tracer.c).
 *   build/bin/00_path_tracer --plain [map] [out] [spp] [width] [height]: the same with plain light
 *     sampling (el_envlight_sample_li / el_envlight_pdf_li) instead of product sampling.
 *   build/bin/00_path_tracer --compare [map] [spp] [width] [height]: renders the scene both ways (no
 *     file) and prints for each the variance per sample (luminance, mean over the pixels of each
 *     pixel's sample variance), the render time and their product, the time-to-unit-variance.
 *   The picture depends only on the arguments, not on the number of threads.
 *
 * WHAT IT WRITES
 *   The picture: .png (exact sRGB, 8 bits) or linear floats (.pfm, .exr); on stdout its path.
 *
 * TO COPY IT INTO YOUR PROJECT
 *   Copy all five headers: envlight.h includes distribution2d.h, mipmap.h includes blockedarray.h, film.h
 *   stands alone; one file defines EL_IMPLEMENTATION before including them, as this one does. They need
 *   only the C standard library. Image files go through examples/common/image_io.h (on Debian's stb);
 *   in your project call stb itself (Debian: libstb-dev, link -lstb): stbi_loadf(path, &w, &h, &n, 3)
 *   from <stb/stb_image.h>, stbi_write_png(path, w, h, 3, bytes, 3 * w) from <stb/stb_image_write.h>.
 */
#define EL_IMPLEMENTATION  // implements every envlight header included after it, in this file only
#include "envlight.h"      // includes distribution2d.h
#include "film.h"
#include "mipmap.h"        // includes blockedarray.h
#include "image_io.h"      // examples/common: el_image_load, el_image_write_png / _float

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>
#include <vector>

#ifndef EL_SOURCE_DIR
#define EL_SOURCE_DIR "."
#endif

static const float PI = 3.14159265358979f;
static const int MAX_DEPTH = 5;  // pbrt's "maxdepth" default

// ---- vectors and random numbers ----------------------------------------------------------------
struct Vec3 { float x, y, z; };
static Vec3 v3(float x, float y, float z) { Vec3 v = {x, y, z}; return v; }
static Vec3 operator+(Vec3 a, Vec3 b) { return v3(a.x + b.x, a.y + b.y, a.z + b.z); }
static Vec3 operator-(Vec3 a, Vec3 b) { return v3(a.x - b.x, a.y - b.y, a.z - b.z); }
static Vec3 operator*(Vec3 a, Vec3 b) { return v3(a.x * b.x, a.y * b.y, a.z * b.z); }
static Vec3 operator*(Vec3 a, float s) { return v3(a.x * s, a.y * s, a.z * s); }
static float dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static Vec3 cross(Vec3 a, Vec3 b) { return v3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x); }
static Vec3 normalize(Vec3 a) { return a * (1.0f / std::sqrt(dot(a, a))); }
static Vec3 rgb(const float c[3]) { return v3(c[0], c[1], c[2]); }

struct Rng {  // PCG32, as pbrt's RNG; one stream per pixel, so threads do not change the picture
  uint64_t state, inc;
  explicit Rng(uint64_t stream) : state(0u), inc((stream << 1u) | 1u) { next(); state += 0x853c49e6748fea9bULL; next(); }
  uint32_t next() {
    uint64_t old = state;
    state = old * 6364136223846793005ULL + inc;
    uint32_t xorshifted = uint32_t(((old >> 18u) ^ old) >> 27u), rot = uint32_t(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((32u - rot) & 31u));
  }
  float uniform() { return float(next() >> 8) * (1.0f / 16777216.0f); }  // [0, 1)
};

// ---- the scene: spheres, the ground plane y = 0, the environment --------------------------------
// pbrt's RayDifferential: dx, dy are the directions of the camera rays through the next pixel in x
// and in y (same origin: a pinhole camera); a bounced ray has none.
struct Ray { Vec3 o, d; bool has_differentials; Vec3 dx, dy; };
static Ray ray_from(Vec3 o, Vec3 d) { Ray r = {o, d, false, d, d}; return r; }
struct Sphere { Vec3 center; float radius; Vec3 albedo; };
struct Hit { float t; Vec3 p, n; int sphere; };  // sphere -1: the ground

// The ground's texture repeats every GROUND_TILE units in x and z.
struct Scene { std::vector<Sphere> spheres; bool has_ground; el_mipmap ground; el_envlight light; };
static const float GROUND_TILE = 2.0f;

// pbrt's Sphere::Intersect (3.2.2) for a unit-length d: |o + t d - c|^2 = r^2, the nearest t > tmin.
static bool intersect_sphere(const Sphere &s, const Ray &r, float *t) {
  Vec3 oc = r.o - s.center;
  float b = dot(oc, r.d), c = dot(oc, oc) - s.radius * s.radius, disc = b * b - c;
  if (disc < 0.0f) return false;
  float root = std::sqrt(disc), tmin = 1e-4f;
  *t = -b - root > tmin ? -b - root : -b + root;
  return *t > tmin;
}

static bool intersect(const Scene &sc, const Ray &r, Hit *h) {
  float t;
  h->t = INFINITY;
  for (size_t i = 0; i < sc.spheres.size(); ++i)
    if (intersect_sphere(sc.spheres[i], r, &t) && t < h->t) { h->t = t; h->sphere = int(i); }
  if (sc.has_ground && r.d.y < 0.0f && (t = -r.o.y / r.d.y) > 1e-4f && t < h->t) { h->t = t; h->sphere = -1; }
  if (h->t == INFINITY) return false;
  h->p = r.o + r.d * h->t;
  h->n = h->sphere >= 0 ? normalize(h->p - sc.spheres[size_t(h->sphere)].center) : v3(0.0f, 1.0f, 0.0f);
  h->p = h->p + h->n * 1e-4f;  // lift the point off the surface, so that rays leaving it miss it
  return true;
}

// ---- sampling: pbrt's PowerHeuristic (nf = ng = 1) and CosineSampleHemisphere ------------------
static float power_heuristic(float f_pdf, float g_pdf) { return f_pdf * f_pdf / (f_pdf * f_pdf + g_pdf * g_pdf); }

static Vec3 cosine_sample(Vec3 n, float u0, float u1, float *pdf) {
  float r = std::sqrt(u0), phi = 2.0f * PI * u1, z = std::sqrt(1.0f - u0);  // Malley: disk -> hemisphere
  float s = n.z >= 0.0f ? 1.0f : -1.0f, a = -1.0f / (s + n.z), b = n.x * n.y * a;  // a frame around n
  Vec3 t1 = v3(1.0f + s * n.x * n.x * a, s * b, -s * n.x), t2 = v3(b, s + n.y * n.y * a, -n.y);
  *pdf = z / PI;  // cos(theta) / pi
  return t1 * (r * std::cos(phi)) + t2 * (r * std::sin(phi)) + n * z;
}

// The ground's texture at hit point p, filtered over the footprint of the ray (pbrt's
// ComputeDifferentials, <<Estimate screen space change in p and (u, v)>>): the offset rays meet the
// plane y = 0 at q; the differences of the texture coordinates (s, t) = (x, z) / GROUND_TILE are the
// footprint. Without differentials (after a bounce, as in pbrt-v3) it is zero: the finest level.
static Vec3 ground_albedo(const Scene &sc, const Ray &ray, Vec3 p) {
  float dst[4] = {0, 0, 0, 0};  // ds/dx, dt/dx, ds/dy, dt/dy
  Vec3 offset[2] = {ray.dx, ray.dy};
  for (int k = 0; k < 2 && ray.has_differentials; ++k) {
    if (offset[k].y >= 0.0f) continue;  // this offset ray misses the plane: no footprint on this axis
    Vec3 q = ray.o + offset[k] * (-ray.o.y / offset[k].y);
    dst[2 * k] = (q.x - p.x) / GROUND_TILE;
    dst[2 * k + 1] = (q.z - p.z) / GROUND_TILE;
  }
  float c[3];
  el_mipmap_lookup_differentials(&sc.ground, p.x / GROUND_TILE, p.z / GROUND_TILE, dst[0], dst[1], dst[2], dst[3], c);
  return rgb(c);
}

// ---- the integrator: pbrt's PathIntegrator::Li for diffuse surfaces ----------------------------
// product: light samples from el_envlight_sample_li_cos (the map times max(0, n.wi) at the hit), whose
// pdf for another direction is el_envlight_pdf_li_cos with the same normal; else el_envlight_sample_li.
static Vec3 Li(const Scene &sc, Ray ray, Rng &rng, bool product) {
  Vec3 L = v3(0, 0, 0), beta = v3(1, 1, 1);  // radiance so far, path throughput
  float bsdf_pdf = 0.0f;                     // the pdf of the cosine sample that made `ray`
  Vec3 prev_n = v3(0, 0, 0);                 // the normal of the hit that made `ray`
  for (int depth = 0;; ++depth) {
    Hit h;
    if (!intersect(sc, ray, &h)) {
      // <<Add emitted light from the environment>>: the ray escaped to the map.
      float Le[3];
      el_envlight_le(&sc.light, &ray.d.x, Le);
      float w = 1.0f;  // the camera ray sees the map directly: no other strategy could find it
      if (depth > 0) {
        // The escaped ray is a cosine sample at the last hit; the light sample there could have
        // drawn the same direction, with the light's pdf. MIS weight of the BSDF strategy:
        float light_pdf = product ? el_envlight_pdf_li_cos(&sc.light, &prev_n.x, &ray.d.x) : el_envlight_pdf_li(&sc.light, &ray.d.x);
        w = power_heuristic(bsdf_pdf, light_pdf);
      }
      L = L + beta * rgb(Le) * w;
      break;
    }
    if (depth == MAX_DEPTH) break;

    // The diffuse BSDF f = albedo / pi; the ground's albedo through the MIP map (EWA filter).
    Vec3 albedo = h.sphere >= 0 ? sc.spheres[size_t(h.sphere)].albedo : ground_albedo(sc, ray, h.p);

    // <<Sample illumination from lights to find path contribution>> (EstimateDirect, light sample)
    // Product sampling: the normal need not be unit length; it must face the side the light arrives
    // from (the outside of the surface). pdf 0 means no sample (nothing emits above this surface).
    float u[2] = {rng.uniform(), rng.uniform()}, wi[3], Li_light[3], light_pdf;
    if (product) el_envlight_sample_li_cos(&sc.light, &h.n.x, u, wi, Li_light, &light_pdf);
    else el_envlight_sample_li(&sc.light, u, wi, Li_light, &light_pdf);
    float cos_l = dot(h.n, v3(wi[0], wi[1], wi[2]));
    Hit blocker;
    if (light_pdf > 0.0f && cos_l > 0.0f && !intersect(sc, ray_from(h.p, v3(wi[0], wi[1], wi[2])), &blocker)) {
      float w = power_heuristic(light_pdf, cos_l / PI);  // the BSDF would draw wi with cos / pi
      L = L + beta * albedo * rgb(Li_light) * (cos_l / PI * w / light_pdf);
    }

    // <<Sample BSDF to get new path direction>>: f cos / pdf = albedo for a cosine-weighted sample.
    float u0 = rng.uniform(), u1 = rng.uniform();
    ray = ray_from(h.p, cosine_sample(h.n, u0, u1, &bsdf_pdf));
    prev_n = h.n;
    beta = beta * albedo;

    // <<Possibly terminate the path with Russian roulette>>
    if (depth > 3) {
      float q = std::max(0.05f, 1.0f - std::max(beta.x, std::max(beta.y, beta.z)));
      if (rng.uniform() < q) break;
      beta = beta * (1.0f / (1.0f - q));
    }
  }
  return L;
}

// ---- the camera: pbrt's PerspectiveCamera with GenerateRayDifferential, y-up, right-handed -----
struct Camera {
  Vec3 eye, fwd, right, up;  // right and up span the image plane at distance 1: half its width, height
  float width, height;
  Camera(Vec3 from, Vec3 at, float vfov_deg, int w, int h) : eye(from), width(float(w)), height(float(h)) {
    float tan_half = std::tan(0.5f * vfov_deg * PI / 180.0f);
    fwd = normalize(at - from);
    right = normalize(cross(fwd, v3(0, 1, 0))) * (tan_half * width / height);
    up = cross(normalize(right), fwd) * tan_half;
  }
  Vec3 dir(float px, float py) const {  // raster (0, 0) is the top left corner, y grows downwards
    return normalize(fwd + right * (2.0f * px / width - 1.0f) + up * (1.0f - 2.0f * py / height));
  }
  // GenerateRayDifferential, then ScaleDifferentials(scale): pbrt shrinks the offsets to the spacing
  // of the samples, 1 / sqrt(spp) pixels (at least 1/8), since the pixel filter blurs the rest.
  Ray ray(float px, float py, float scale) const {
    Vec3 d = dir(px, py);
    Ray r = {eye, d, true, d + (dir(px + 1.0f, py) - d) * scale, d + (dir(px, py + 1.0f) - d) * scale};
    return r;
  }
};

// A 256 x 256 checker (4 x 4 squares) for the ground: its far squares are smaller than a pixel.
static std::vector<float> checker_texture(int n) {
  std::vector<float> tex(size_t(n * n * 3));
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      bool light = ((x * 4 / n) + (y * 4 / n)) % 2 == 0;
      for (int c = 0; c < 3; ++c) tex[size_t((y * n + x) * 3 + c)] = light ? 0.75f - 0.04f * float(c) : 0.06f;
    }
  return tex;
}

// 4. Render. Bands of 16 rows, each into its own FilmTile, taken by the threads in turn; the tiles
//    are merged in band order afterwards, so the sums (and the picture) do not depend on threads.
//    Returns the tiles that could not be allocated; *variance gets the mean over the pixels of each
//    pixel's sample variance (luminance), *seconds the wall time.
static int render(const Scene &sc, const Camera &cam, el_film *film, int spp, bool product, double *variance, double *seconds) {
  int b[4];
  el_film_sample_bounds(film, b);
  float diff_scale = std::max(0.125f, 1.0f / std::sqrt(float(spp)));
  int bands = (b[3] - b[1] + 15) / 16;
  std::vector<el_film_tile> tiles(static_cast<size_t>(bands));  // zeroed
  std::vector<double> band_var(static_cast<size_t>(bands), 0.0);
  std::atomic<int> next_band(0);
  auto work = [&]() {
    for (int band = next_band++; band < bands; band = next_band++) {
      int y0 = b[1] + 16 * band, y1 = std::min(y0 + 16, b[3]);
      el_film_tile &tile = tiles[size_t(band)];
      if (el_film_tile_init(film, &tile, b[0], y0, b[2], y1) != EL_SUCCESS) continue;  // merge reports it
      for (int y = y0; y < y1; ++y)
        for (int x = b[0]; x < b[2]; ++x) {
          Rng rng(uint64_t(y - b[1]) * uint64_t(b[2] - b[0]) + uint64_t(x - b[0]));
          double sum = 0.0, sum2 = 0.0;
          for (int s = 0; s < spp; ++s) {
            float px = float(x) + rng.uniform(), py = float(y) + rng.uniform();
            Vec3 L = Li(sc, cam.ray(px, py, diff_scale), rng, product);
            el_film_tile_add_sample(&tile, px, py, &L.x, 1.0f);
            double lum = 0.212671 * L.x + 0.715160 * L.y + 0.072169 * L.z;
            sum += lum; sum2 += lum * lum;
          }
          if (spp > 1) band_var[size_t(band)] += std::max(0.0, (sum2 - sum * sum / spp) / (spp - 1));
        }
    }
  };
  auto t0 = std::chrono::steady_clock::now();
  std::vector<std::thread> threads;
  for (unsigned i = 0; i < std::max(1u, std::thread::hardware_concurrency()); ++i) threads.push_back(std::thread(work));
  for (size_t i = 0; i < threads.size(); ++i) threads[i].join();
  *seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  int lost = 0;  // tiles that could not be allocated: merging a zeroed tile is an error
  double var = 0.0;
  for (size_t i = 0; i < tiles.size(); ++i) {
    lost += el_film_merge_tile(film, &tiles[i]) != EL_SUCCESS;
    el_film_tile_free(&tiles[i]);
    var += band_var[i];
  }
  *variance = var / (double(b[2] - b[0]) * double(b[3] - b[1]));
  return lost;
}

static const char kUsage[] =
    "usage: 00_path_tracer [map.hdr|.exr|.pfm] [out.png|.pfm|.exr] [spp] [width] [height]\n"
    "       00_path_tracer --furnace [out] [spp] [width] [height]   (a white sphere that must render as 1)\n"
    "       00_path_tracer --plain [map] [out] [spp] [width] [height]   (sample_li, not product sampling)\n"
    "       00_path_tracer --compare [map] [spp] [width] [height]   (both ways: variance and time, no file)\n";

int main(int argc, char **argv) {
  if (argc > 1 && (std::string(argv[1]) == "--help" || std::string(argv[1]) == "-h")) {
    std::fputs(kUsage, stdout);
    return 0;
  }
  // --plain and --compare come first and are taken off the arguments; --compare has no output file
  bool plain = argc > 1 && std::string(argv[1]) == "--plain";
  bool compare = argc > 1 && std::string(argv[1]) == "--compare";
  if (plain || compare) { ++argv; --argc; }
  int k = compare ? 1 : 0;  // --compare: [map] [spp] [width] [height]
  bool furnace = argc > 1 && std::string(argv[1]) == "--furnace";
  if (argc > 1 && argv[1][0] == '-' && !furnace) {  // an option it does not know (not a file name)
    std::fprintf(stderr, "00_path_tracer: unknown option %s\n%s", argv[1], kUsage);
    return 1;
  }
  std::string map_path = argc > 1 && !furnace ? argv[1] : EL_SOURCE_DIR "/data/envmaps/city.hdr";
  std::string out_path = argc > 2 && !compare ? argv[2] : "00_path_tracer.png";
  int spp = argc > 3 - k ? std::atoi(argv[3 - k]) : 16, width = argc > 4 - k ? std::atoi(argv[4 - k]) : 480;
  int height = argc > 5 - k ? std::atoi(argv[5 - k]) : 270;
  if (spp < 1 || spp > 65536 || width < 1 || width > 8192 || height < 1 || height > 8192) {
    std::fprintf(stderr, "00_path_tracer: spp must be in 1..65536, width and height in 1..8192\n");
    return 1;
  }
  char err[512] = "";

  // 1. The light (pbrt's InfiniteAreaLight), from the map file or from the furnace's sky (128 x 64
  //    texels of 1 + 0.75 P3(cos theta), theta at the row's centre; row 0 is the zenith).
  Scene sc = Scene();  // value-initialised: no spheres, no ground, zeroed envlight and mipmap
  el_image map = el_image();
  std::vector<float> sky(furnace ? 128 * 64 * 3 : 0);
  for (size_t i = 0; i < sky.size(); ++i) {
    float c = std::cos(PI * (float(i / (128 * 3)) + 0.5f) / 64.0f);
    sky[i] = 1.0f + 0.75f * 0.5f * (5.0f * c * c * c - 3.0f * c);
  }
  if (!furnace && el_image_load(map_path.c_str(), &map, err, sizeof err) != 0) {
    std::fprintf(stderr, "00_path_tracer: %s\n", err);
    return 1;
  }
  el_envlight_options lo = {};                // C: = {0}. All zero: pbrt-v3's light
  el_envlight_yup_matrix(lo.light_to_world);  // y-up, right-handed: maps look as in Mitsuba 3
  el_result res = furnace ? el_envlight_init(&sc.light, sky.data(), 128, 64, 3, &lo)
                          : el_envlight_init(&sc.light, map.pixels, map.width, map.height, map.channels, &lo);
  el_image_free(&map);
  if (res != EL_SUCCESS) {
    std::fprintf(stderr, "00_path_tracer: %s: %s\n", map_path.c_str(), el_result_string(res));
    return 1;
  }

  // 2. The objects and the ground's MIP map; the camera.
  Vec3 eye = v3(0.0f, 1.3f, 5.5f), at = v3(0.0f, 0.7f, 0.0f);
  if (furnace) {
    Sphere white = {at, 4.5f, v3(1, 1, 1)};  // its surface is 0.3 in front of the eye: it fills the frame
    sc.spheres.push_back(white);
  } else {
    Sphere s[3] = {{v3(0.0f, 1.0f, 0.0f), 1.0f, v3(0.8f, 0.8f, 0.8f)},
                   {v3(-2.1f, 0.7f, 0.6f), 0.7f, v3(0.8f, 0.25f, 0.2f)},
                   {v3(1.9f, 0.5f, 0.9f), 0.5f, v3(0.2f, 0.35f, 0.8f)}};
    sc.spheres.assign(s, s + 3);
    sc.has_ground = true;
    std::vector<float> tex = checker_texture(256);
    el_mipmap_options mo = {};  // C: = {0}. All zero: pbrt-v3's Repeat wrap and EWA filter
    res = el_mipmap_init(&sc.ground, tex.data(), 256, 256, 3, &mo);
  }
  Camera cam(eye, at, 40.0f, width, height);

  // 3. The film, with pbrt's Gaussian filter (radius 2, alpha 2). pbrt's GetSampleBounds grows the
  //    image by the radius, so that border pixels get their full filter support too.
  el_film_options fo = {};  // C: = {0}. All zero but the size: pbrt's box filter
  fo.width = width;
  fo.height = height;
  fo.filter.type = EL_FILM_FILTER_GAUSSIAN;
  el_film film = el_film();
  if (res == EL_SUCCESS) res = el_film_init(&film, &fo);
  if (res != EL_SUCCESS) {
    std::fprintf(stderr, "00_path_tracer: %s\n", el_result_string(res));
    return 1;
  }

  // 4. Render (above), once; or both ways for --compare (product first: it builds its own tables, the
  //    plain pass then builds the light's sampling tables; each pass's time includes its build).
  double var = 0.0, secs = 0.0;
  int lost = 0;
  if (compare) {
    double var_p = 0.0, secs_p = 0.0;
    lost = render(sc, cam, &film, spp, true, &var_p, &secs_p);
    el_film_clear(&film);
    lost += render(sc, cam, &film, spp, false, &var, &secs);
    std::printf("%-32s %14s %10s %22s\n", "light sampling (MIS with cosine)", "variance/spl", "time (s)", "time x variance");
    std::printf("%-32s %14.5g %10.3f %22.5g\n", "product (sample_li_cos)", var_p, secs_p, var_p * secs_p);
    std::printf("%-32s %14.5g %10.3f %22.5g\n", "plain (sample_li)", var, secs, var * secs);
    std::printf("product: %.2fx less variance per sample, %.2fx the time, %.2fx the efficiency (1 / time x variance)\n",
                var / var_p, secs_p / secs, (var * secs) / (var_p * secs_p));
    el_film_free(&film);
    el_mipmap_free(&sc.ground);
    el_envlight_free(&sc.light);
    return lost > 0;
  }
  lost = render(sc, cam, &film, spp, !plain, &var, &secs);

  // 5. Output: linear RGB; for .png one stop darker (the sunlit ground would clip; the furnace keeps
  //    1 as white), then pbrt's clamp at 1, the exact sRGB curve and rounding (TO_BYTE).
  std::vector<float> linear(size_t(width) * size_t(height) * 3);
  std::vector<unsigned char> srgb(linear.size());
  el_film_get_rgb(&film, 1.0f, linear.data());
  el_film_output_options oo = {};  // C: = {0}. All zero: pbrt's output curve
  oo.exposure = furnace ? 0.0f : -1.0f;
  int failed = 1;
  if (lost > 0)
    std::snprintf(err, sizeof err, "out of memory for %d film tiles", lost);
  else if (el_image_extension(out_path.c_str()) != std::string("png"))
    failed = el_image_write_float(out_path.c_str(), linear.data(), width, height, 3, err, sizeof err);
  else if (el_film_to_srgb8(linear.data(), width, height, &oo, srgb.data()) == EL_SUCCESS)
    failed = el_image_write_png(out_path.c_str(), srgb.data(), width, height, 3, err, sizeof err);
  if (failed) std::fprintf(stderr, "00_path_tracer: %s\n", err[0] ? err : "cannot encode the picture");
  else std::printf("wrote %s (%dx%d, %d spp, %s sampling, %.2f s)\n", out_path.c_str(), width, height, spp, plain ? "plain light" : "product", secs);
  el_film_free(&film);
  el_mipmap_free(&sc.ground);
  el_envlight_free(&sc.light);
  return failed;
}
