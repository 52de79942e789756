/* shapes.c: pbrt-v3's Sphere (shapes/sphere.cpp), Triangle (shapes/triangle.cpp) and Disk
 * (shapes/disk.cpp) as the renderer intersects them through Embree (scene.c), and as area lights
 * sample them (core/shape.cpp's Shape::Sample and Shape::Pdf).
 *
 * A sphere is pbrt-v3's Sphere in its object space (any affine object-to-world transform, so a
 * non-uniformly scaled sphere is an exact ellipsoid), intersected in float, 4 or 8 rays at once, and in
 * double where float is not enough (below), never tessellated: Embree's user geometry calls the
 * bounds, intersect and occluded functions below. Triangle
 * meshes are Embree triangle geometries in world space (pbrt-v3 also transforms mesh vertices to world
 * space when it creates them). After Embree's hit, the hit record (elr_sphere_hit, elr_triangle_hit)
 * and, only for textured materials and ray differentials, the parameterisation (elr_hit_uv). A disk is
 * exact too: a second user geometry, intersected in object space. Sampling a point on a shape
 * (pbrt-v3's Shape::Sample and Pdf, for area lights) is at the end. Loop subdivision (loopsubdiv.c)
 * makes triangle meshes. A prototype's shapes (ObjectBegin) are in its own space: their hit records are
 * made there and taken to world space by scene.c.
 *
 * Orientation (pbrt-v3's Intersect): a sphere's normal points out and a disk's along its object-space
 * +z; a triangle's geometric normal is (p0 - p2) x (p1 - p2), turned to the side of the interpolated
 * shading normal when the mesh has normals. ReverseOrientation xor a transformation that swaps
 * handedness turns them all around (each shape's `flip`; pbrt-v3's SurfaceInteraction constructor and
 * SetShadingGeometry). The hit records and the sampled points agree on it: pbrt-v3 itself does not (its
 * Sample ignores the flip of a sphere or disk under a mirroring transformation and of a mesh with
 * normals). */
#include "elr_internal.h"
#include <embree3/rtcore.h>
#include <float.h>
#include <stdlib.h>
#include <string.h>

/* >> sphere */
/* Embree's user-geometry callbacks (scene.c attaches them with an elr_sphere_set as the user pointer:
 * the world's spheres or a prototype's; primID indexes its idx): the bounds of the transformed sphere,
 * padded by a relative 1e-6 */
void elr_sphere_bounds(const struct RTCBoundsFunctionArguments *a) {
  const elr_sphere_set *set = (const elr_sphere_set *)a->geometryUserPtr;
  const elr_sphere *sp = &set->sph[set->idx[a->primID]];
  float r = sp->radius;
  int i;
  struct RTCBounds *b = a->bounds_o;
  b->lower_x = b->lower_y = b->lower_z = FLT_MAX;
  b->upper_x = b->upper_y = b->upper_z = -FLT_MAX;
  for (i = 0; i < 8; i++) {
    elr_v3 c = elr_xpoint(&sp->o2w, elr_v(i & 1 ? r : -r, i & 2 ? r : -r, i & 4 ? r : -r));
    b->lower_x = fminf(b->lower_x, c.x); b->upper_x = fmaxf(b->upper_x, c.x);
    b->lower_y = fminf(b->lower_y, c.y); b->upper_y = fmaxf(b->upper_y, c.y);
    b->lower_z = fminf(b->lower_z, c.z); b->upper_z = fmaxf(b->upper_z, c.z);
  }
  {
    float pad = 1e-6f * (fabsf(b->upper_x) + fabsf(b->upper_y) + fabsf(b->upper_z) + fabsf(b->lower_x) + fabsf(b->lower_y) + fabsf(b->lower_z) + r);
    b->lower_x -= pad; b->lower_y -= pad; b->lower_z -= pad; b->upper_x += pad; b->upper_y += pad; b->upper_z += pad;
  }
}

/* pbrt-v3's Sphere::Intersect: the ray taken to object space, the quadratic solved in double precision
 * (pbrt-v3 uses its EFloat error bounds); returns the nearest t in (tnear, tfar) or -1. The reference,
 * and what elr__sph_hit4 falls back on where float is not enough. */
static double elr__sph_hit(const elr_sphere *sp, float ox, float oy, float oz, float dx, float dy, float dz, float tnear, float tfar) {
  const double(*m)[4] = sp->o2w.inv;
  double o0 = m[0][0] * ox + m[0][1] * oy + m[0][2] * oz + m[0][3];
  double o1 = m[1][0] * ox + m[1][1] * oy + m[1][2] * oz + m[1][3];
  double o2 = m[2][0] * ox + m[2][1] * oy + m[2][2] * oz + m[2][3];
  double d0 = m[0][0] * dx + m[0][1] * dy + m[0][2] * dz;
  double d1 = m[1][0] * dx + m[1][1] * dy + m[1][2] * dz;
  double d2 = m[2][0] * dx + m[2][1] * dy + m[2][2] * dz;
  double r = sp->radius;
  double A = d0 * d0 + d1 * d1 + d2 * d2, B = 2 * (d0 * o0 + d1 * o1 + d2 * o2), C = o0 * o0 + o1 * o1 + o2 * o2 - r * r;
  double disc = B * B - 4 * A * C, q, t0, t1;
  if (disc < 0 || A == 0) return -1;
  disc = sqrt(disc);
  q = B < 0 ? -0.5 * (B - disc) : -0.5 * (B + disc);
  t0 = q / A; t1 = q != 0 ? C / q : t0;
  if (t0 > t1) { double t = t0; t0 = t1; t1 = t; }
  if (t0 > tnear && t0 < tfar) return t0;
  if (t1 > tnear && t1 < tfar) return t1;
  return -1;
}

static int elr__similarity(const elr_xform *t, double *scale);
void elr_sphere_prepare(elr_sphere *sp) {
  int r, c;
  double sc = 1.0;
  elr_v3 wc = elr_xpoint(&sp->o2w, elr_v(0, 0, 0));
  const double w[3] = {wc.x, wc.y, wc.z};
  /* the callbacks take o - wc to object space: o2w.inv's 3x3, then where wc (the centre, rounded to
   * float) lies in object space, a small vector (in double, then float): float's error in o is then
   * relative to o's distance from the sphere, not from the world's origin */
  for (r = 0; r < 3; r++) {
    for (c = 0; c < 3; c++) sp->w2o[4 * r + c] = (float)sp->o2w.inv[r][c];
    sp->w2o[4 * r + 3] = (float)(sp->o2w.inv[r][0] * w[0] + sp->o2w.inv[r][1] * w[1] + sp->o2w.inv[r][2] * w[2] + sp->o2w.inv[r][3]);
  }
  sp->r2 = sp->radius * sp->radius;
  /* float's a r^2 (a = |w2o d|^2, between the squares of w2o's smallest and largest row for a unit d) and r^2
   * must stay far inside float's range (the tests below multiply them by 1e6 and 1e-2): the parser takes a
   * radius of 1e20 under Scale 1e-19 (r^2 overflows: the sphere vanished) or 1e-18 under Scale 1e18 (a r^2
   * underflows: rays hit it anywhere); those, and any like them, take the double path for every ray */
  {
    double lo = DBL_MAX, hi = 0, rr = (double)sp->radius * sp->radius;
    for (r = 0; r < 3; r++) {
      double q = sp->o2w.inv[r][0] * sp->o2w.inv[r][0] + sp->o2w.inv[r][1] * sp->o2w.inv[r][1] + sp->o2w.inv[r][2] * sp->o2w.inv[r][2];
      lo = q < lo ? q : lo; hi = q > hi ? q : hi;
    }
    sp->dbl = !(rr >= 1e-16 && rr <= 1e16 && lo * rr >= 1e-16 && hi * rr <= 1e16);
  }
  sp->sim = elr__similarity(&sp->o2w, &sc);
  sp->wc[0] = wc.x; sp->wc[1] = wc.y; sp->wc[2] = wc.z;
  sp->wr = (float)(sp->radius * sc);
}

/* The callbacks' intersection (issue 21): pbrt-v4's Sphere::BasicIntersect in float (sphere_simd.h), 4
 * or 8 rays at once with SSE2 or AVX where the CPU has them (chosen at run time; a ray alone in plain C,
 * elr__sph_one), and in double (elr__sph_hit) for the rays float cannot answer: the discriminant within
 * 1% of a r^2 of 0 (grazing rays: the root's error grows as 1 / sqrt(disc), and there double decides hit
 * or miss), the origin more than 1000 radii away (float's error in o then nears that 1%), or |o|^2 - r^2
 * within 1.5e-5 |o|^2 of 0 (an origin that near the surface, not one spawned from it: c's sign says
 * inside or out). About 1% of the rays the callbacks test on bench_city take the double path.
 * test_render_sphere_float checks every width and a ray alone bit for bit against each other and
 * against its own long double quadratic on 2.1e5 random rays (grazing, near-surface and spawned ones) and
 * on rays from each centre.
 * Measured (callgrind_parts.sh, bench_city, zsobol): Embree and intersection 988 -> 764 instructions
 * per camera sample (direct), 1543 -> 1227 (path), with elr_sphere_hit's similarity path below; images
 * within 3.5e-4 relative of the double callbacks' (README, Benchmark). */
#define ELR__SPH_REDO 0.01f /* |disc| below this times a r^2: double */
#define ELR__SPH_FAR 1e6f   /* |o|^2 - r^2 above this times r^2: double */
#define ELR__SPH_NEAR 1.5e-5f /* |o|^2 - r^2 within this times |o|^2 of 0: double */
/* one ray (rtcIntersect1, rtcOccluded1, and every ray without SIMD): sphere_simd.h's steps in plain C, in
 * the same order (the same t as the vectors: test_render_sphere_float), leaving at the first sign of a miss;
 * returns 1 on a hit (t in *t), 0 on a miss, -1 where float is not enough (elr__sph_hit decides) */
#if defined(__GNUC__) && !defined(__clang__)
#define ELR__SCALAR __attribute__((optimize("no-tree-vectorize"))) /* (gcc's SLP: more shuffles than it saves here) */
#else
#define ELR__SCALAR
#endif
ELR__SCALAR static int elr__sph_one(const elr_sphere *sp, const float *ray, size_t N, float *t) {
  const float *m = sp->w2o, r2 = sp->r2;
  float ox = ray[0] - sp->wc[0], oy = ray[N] - sp->wc[1], oz = ray[2 * N] - sp->wc[2], dx = ray[4 * N], dy = ray[5 * N], dz = ray[6 * N];
  float o[3], d[3], a, b, ox2, c, l, l2, ar2, disc, q, t0, t1, lo, hi;
  int k;
  for (k = 0; k < 3; k++) {
    const float *row = m + 4 * k;
    d[k] = row[0] * dx + row[1] * dy + row[2] * dz;
    o[k] = row[0] * ox + row[1] * oy + row[2] * oz + row[3];
  }
  a = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
  b = o[0] * d[0] + o[1] * d[1] + o[2] * d[2];
  ox2 = o[0] * o[0] + o[1] * o[1] + o[2] * o[2];
  c = ox2 - r2;
  l = o[1] * d[2] - o[2] * d[1]; l2 = l * l;
  l = o[2] * d[0] - o[0] * d[2]; l2 = l2 + l * l;
  l = o[0] * d[1] - o[1] * d[0]; l2 = l2 + l * l;
  ar2 = a * r2;
  disc = ar2 - l2;
  if ((disc < ar2 * ELR__SPH_REDO && disc > ar2 * -ELR__SPH_REDO) || c > r2 * ELR__SPH_FAR || (c < ox2 * ELR__SPH_NEAR && c > ox2 * -ELR__SPH_NEAR))
    return -1;
  if (!(disc >= 0.f)) return 0;
  q = sqrtf(disc);
  q = b < 0.f ? q - b : (0.f - b) - q;
  t0 = q / a; t1 = c / q;
  lo = t0 < t1 ? t0 : t1; hi = t0 > t1 ? t0 : t1;
  if (lo > ray[3 * N] && lo < ray[8 * N]) { *t = lo; return 1; }
  if (hi > ray[3 * N] && hi < ray[8 * N]) { *t = hi; return 1; }
  return 0;
}
#if (defined(__x86_64__) || defined(__i386__)) && defined(__GNUC__) && !defined(ELR_NO_SIMD)
#define ELR_SPHERE_SIMD 1
#include <immintrin.h>
#define ELR__SPH_NAME elr__sph_hit_sse2
#define ELR__SPH_W 4
#define ELR__SPH_TARGET __attribute__((target("sse2")))
#define V __m128
#define M __m128
#define LOAD(p) _mm_loadu_ps(p)
#define SET1(x) _mm_set1_ps(x)
#define ADD(a, b) _mm_add_ps(a, b)
#define SUB(a, b) _mm_sub_ps(a, b)
#define MUL(a, b) _mm_mul_ps(a, b)
#define DIV(a, b) _mm_div_ps(a, b)
#define SQRT(a) _mm_sqrt_ps(a)
#define MIN(a, b) _mm_min_ps(a, b)
#define MAX(a, b) _mm_max_ps(a, b)
#define LT(a, b) _mm_cmplt_ps(a, b)
#define GT(a, b) _mm_cmpgt_ps(a, b)
#define GE(a, b) _mm_cmpge_ps(a, b)
#define AND(a, b) _mm_and_ps(a, b)
#define OR(a, b) _mm_or_ps(a, b)
#define SEL(m, a, b) _mm_or_ps(_mm_and_ps(m, a), _mm_andnot_ps(m, b))
#define BITS(m) _mm_movemask_ps(m)
#define VALID(p) _mm_movemask_ps(_mm_castsi128_ps(_mm_loadu_si128((const __m128i *)(const void *)(p))))
#include "sphere_simd.h"
#define ELR__SPH_NAME elr__sph_hit_avx
#define ELR__SPH_W 8
#define ELR__SPH_TARGET __attribute__((target("avx")))
#define V __m256
#define M __m256
#define LOAD(p) _mm256_loadu_ps(p)
#define SET1(x) _mm256_set1_ps(x)
#define ADD(a, b) _mm256_add_ps(a, b)
#define SUB(a, b) _mm256_sub_ps(a, b)
#define MUL(a, b) _mm256_mul_ps(a, b)
#define DIV(a, b) _mm256_div_ps(a, b)
#define SQRT(a) _mm256_sqrt_ps(a)
#define MIN(a, b) _mm256_min_ps(a, b)
#define MAX(a, b) _mm256_max_ps(a, b)
#define LT(a, b) _mm256_cmp_ps(a, b, _CMP_LT_OQ)
#define GT(a, b) _mm256_cmp_ps(a, b, _CMP_GT_OQ)
#define GE(a, b) _mm256_cmp_ps(a, b, _CMP_GE_OQ)
#define AND(a, b) _mm256_and_ps(a, b)
#define OR(a, b) _mm256_or_ps(a, b)
#define SEL(m, a, b) _mm256_or_ps(_mm256_and_ps(m, a), _mm256_andnot_ps(m, b)) /* (gcc 12 makes blendv a branch per lane) */
#define BITS(m) _mm256_movemask_ps(m)
#define VALID(p) _mm256_movemask_ps(_mm256_castsi256_ps(_mm256_loadu_si256((const __m256i *)(const void *)(p))))
#include "sphere_simd.h"
#endif

int elr_sphere_simd(void) {
  int w = 0;
  const char *e = getenv("ELR_SPHERE_SIMD");
#if defined(ELR_SPHERE_SIMD)
  __builtin_cpu_init();
  w = __builtin_cpu_supports("avx") ? 2 : 1;
#endif
  if (e && *e >= '0' && *e < '0' + w) w = *e - '0';
  return w;
}

/* one ray in float, or in double where float is not enough: 1 on a hit (t in *t) */
static int elr__sph_ray(const elr_sphere *sp, const float *ray, size_t N, float *t) {
  int hit = sp->dbl ? -1 : elr__sph_one(sp, ray, N, t);
  if (hit < 0) {
    double td = elr__sph_hit(sp, ray[0], ray[N], ray[2 * N], ray[4 * N], ray[5 * N], ray[6 * N], ray[3 * N], ray[8 * N]);
    *t = (float)td;
    hit = td >= 0;
  }
  return hit;
}
/* W rays: a vector of SSE2's or AVX's, or one ray, then the lanes float cannot answer in double */
static unsigned elr__sph_vector(const elr_sphere *sp, unsigned W, const float *ray, size_t N, const int *valid, float *t) {
  int hit, redo;
  unsigned k;
  (void)W; /* (without SIMD: one ray, whatever W) */
#if defined(ELR_SPHERE_SIMD)
  if (W == 8) hit = elr__sph_hit_avx(sp, ray, N, valid, t, &redo);
  else if (W == 4) hit = elr__sph_hit_sse2(sp, ray, N, valid, t, &redo);
  else
#endif
    return valid[0] == -1 && elr__sph_ray(sp, ray, N, t);
  for (k = 0; redo >> k; k++)
    if (redo >> k & 1) {
      double td = elr__sph_hit(sp, ray[k], ray[N + k], ray[2 * N + k], ray[4 * N + k], ray[5 * N + k], ray[6 * N + k], ray[3 * N + k], ray[8 * N + k]);
      hit &= ~(1 << k);
      if (td >= 0) { t[k] = (float)td; hit |= 1 << k; }
    }
  return (unsigned)hit;
}
unsigned elr_sphere_hit_rays(const elr_sphere *sp, int simd, const float *ray, unsigned N, unsigned i0, const int *valid, float t[16]) {
  unsigned bits = 0, i, end = i0 + 16 < N ? i0 + 16 : N, W;
  if (sp->dbl) simd = 0; /* (one ray at a time, each in double: elr__sph_ray) */
  for (i = i0; i < end; i += W) { /* the widest vector the CPU runs that the rays fill (one ray at a time for the rest) */
    W = simd >= 2 && end - i >= 8 ? 8 : simd >= 1 && end - i >= 4 ? 4 : 1;
    bits |= elr__sph_vector(sp, W, ray + i, N, valid + i, t + (i - i0)) << (i - i0);
  }
  return bits;
}

/* Embree's callbacks take N rays at once (N = 1 for rtcIntersect1, 4 to 16 for the packets and streams
 * of render_wave.c), in its RTCRayN / RTCHitN layout: component k of ray i at ((float *)ray)[k * N + i]
 * (org_x 0 .. dir_z 6, tnear 3, tfar 8; the hit after 12 N floats: u 3, v 4, primID 5, geomID 6,
 * instID 7). valid[i] is -1 for the rays to answer. */
#define ELR__RN(r, k, N, i) (((float *)(r))[(size_t)(k) * (N) + (i)])
#define ELR__HN(r, k, N, i) (((unsigned *)(r))[(size_t)(12 + (k)) * (N) + (i)])
void elr_sphere_intersect(const struct RTCIntersectFunctionNArguments *a) {
  const elr_sphere_set *set = (const elr_sphere_set *)a->geometryUserPtr;
  const elr_sphere *sp = &set->sph[set->idx[a->primID]];
  void *rh = a->rayhit;
  unsigned N = a->N, i, k;
  for (i = 0; i < N; i += 16) {
    float t[16];
    unsigned bits = N == 1 ? (unsigned)(a->valid[0] == -1 && elr__sph_ray(sp, (const float *)rh, 1, t)) /* rtcIntersect1 */
                           : elr_sphere_hit_rays(sp, set->simd, (const float *)rh, N, i, a->valid, t);
    for (k = 0; bits; k++, bits >>= 1) {
      unsigned j = i + k;
      if (!(bits & 1)) continue;
      ELR__RN(rh, 8, N, j) = t[k];
      ELR__RN(rh, 12 + 3, N, j) = ELR__RN(rh, 12 + 4, N, j) = 0.f;
      /* the normal is computed in elr_sphere_hit */
      ELR__RN(rh, 12 + 0, N, j) = 0.f; ELR__RN(rh, 12 + 1, N, j) = 0.f; ELR__RN(rh, 12 + 2, N, j) = 1.f;
      ELR__HN(rh, 5, N, j) = a->primID;
      ELR__HN(rh, 6, N, j) = a->geomID;
      ELR__HN(rh, 7, N, j) = a->context->instID[0]; /* the instance whose prototype holds the sphere, or none */
    }
  }
}
void elr_sphere_occluded(const struct RTCOccludedFunctionNArguments *a) {
  const elr_sphere_set *set = (const elr_sphere_set *)a->geometryUserPtr;
  const elr_sphere *sp = &set->sph[set->idx[a->primID]];
  void *r = a->ray;
  unsigned N = a->N, i, k;
  for (i = 0; i < N; i += 16) {
    float t[16];
    unsigned bits = N == 1 ? (unsigned)(a->valid[0] == -1 && elr__sph_ray(sp, (const float *)r, 1, t)) /* rtcOccluded1 */
                           : elr_sphere_hit_rays(sp, set->simd, (const float *)r, N, i, a->valid, t);
    for (k = 0; bits; k++, bits >>= 1)
      if (bits & 1) ELR__RN(r, 8, N, i + k) = -INFINITY;
  }
}

/* The hit record of a ray o + t d (t in h->t) on sphere si: <<Refine sphere intersection point>>
 * (projected onto the sphere in object space, as pbrt-v3 does), the normal. Under a similarity (sp->sim:
 * rotation, uniform scale, translation, the sphere stays a sphere) the same projection in float where
 * the sphere is, onto its centre and radius there, and the object-space point for elr_hit_uv by the
 * float inverse: a third of the instructions (callgrind), the point and normal within a few float ulps
 * of the double path's (test_render_sphere_float). */
void elr_sphere_hit(const elr_scene *s, int si, elr_v3 o, elr_v3 d, elr_hit *h) {
  const elr_sphere *sp = &s->sph[si];
  elr_v3 pw = elr_add(o, elr_mul(d, h->t));
  h->kind = ELR_SHAPE_SPHERE;
  h->prim = (unsigned)si;
  h->material = sp->material;
  h->flip = sp->flip;
  h->light = sp->light;
  if (sp->sim) {
    const float *m = sp->w2o;
    elr_v3 v = elr_sub(pw, elr_v(sp->wc[0], sp->wc[1], sp->wc[2])), q;
    float l = elr_len(v);
    elr_v3 n = l > 0.f ? elr_mul(v, 1.f / l) : elr_v(0, 0, 1);
    q = elr_mul(n, sp->wr); /* the point from the centre */
    h->p = elr_add(elr_v(sp->wc[0], sp->wc[1], sp->wc[2]), q);
    h->pobj = elr_v(m[0] * q.x + m[1] * q.y + m[2] * q.z + m[3], m[4] * q.x + m[5] * q.y + m[6] * q.z + m[7], m[8] * q.x + m[9] * q.y + m[10] * q.z + m[11]);
    h->ng = h->ns = sp->flip ? elr_mul(n, -1.f) : n;
    return;
  }
  {
    const double(*mi)[4] = sp->o2w.inv;
    double x = mi[0][0] * pw.x + mi[0][1] * pw.y + mi[0][2] * pw.z + mi[0][3];
    double y = mi[1][0] * pw.x + mi[1][1] * pw.y + mi[1][2] * pw.z + mi[1][3];
    double z = mi[2][0] * pw.x + mi[2][1] * pw.y + mi[2][2] * pw.z + mi[2][3];
    double r = sp->radius, l = sqrt(x * x + y * y + z * z);
    if (l > 0) { x *= r / l; y *= r / l; z *= r / l; }
    h->pobj = elr_v((float)x, (float)y, (float)z);
    h->p = elr_xpoint(&sp->o2w, h->pobj);
    h->ng = elr_norm(elr_xnormal(&sp->o2w, h->pobj));
    if (sp->flip) h->ng = elr_mul(h->ng, -1.f);
    h->ns = h->ng;
  }
}

/* >> disk (pbrt-v3 shapes/disk.cpp): Embree's user-geometry callbacks (primID indexes s->disk) */
void elr_disk_bounds(const struct RTCBoundsFunctionArguments *a) {
  const elr_scene *s = (const elr_scene *)a->geometryUserPtr;
  const elr_disk *dk = &s->disk[a->primID];
  float r = dk->radius, pad;
  int i;
  struct RTCBounds *b = a->bounds_o;
  b->lower_x = b->lower_y = b->lower_z = FLT_MAX;
  b->upper_x = b->upper_y = b->upper_z = -FLT_MAX;
  for (i = 0; i < 4; i++) { /* Disk::ObjectBound, in world space */
    elr_v3 c = elr_xpoint(&dk->o2w, elr_v(i & 1 ? r : -r, i & 2 ? r : -r, dk->height));
    b->lower_x = fminf(b->lower_x, c.x); b->upper_x = fmaxf(b->upper_x, c.x);
    b->lower_y = fminf(b->lower_y, c.y); b->upper_y = fmaxf(b->upper_y, c.y);
    b->lower_z = fminf(b->lower_z, c.z); b->upper_z = fmaxf(b->upper_z, c.z);
  }
  pad = 1e-6f * (fabsf(b->upper_x) + fabsf(b->upper_y) + fabsf(b->upper_z) + fabsf(b->lower_x) + fabsf(b->lower_y) + fabsf(b->lower_z) + r);
  b->lower_x -= pad; b->lower_y -= pad; b->lower_z -= pad; b->upper_x += pad; b->upper_y += pad; b->upper_z += pad;
}
/* pbrt-v3's Disk::Intersect: the ray in object space (double precision), the plane z = height, then
 * the radii and phimax; returns t in (tnear, tfar) or -1, and the object-space hit in po */
static double elr__disk_hit(const elr_disk *dk, float ox, float oy, float oz, float dx, float dy, float dz, float tnear, float tfar,
                            double po[3]) {
  const double(*m)[4] = dk->o2w.inv;
  double o0 = m[0][0] * ox + m[0][1] * oy + m[0][2] * oz + m[0][3];
  double o1 = m[1][0] * ox + m[1][1] * oy + m[1][2] * oz + m[1][3];
  double o2 = m[2][0] * ox + m[2][1] * oy + m[2][2] * oz + m[2][3];
  double d0 = m[0][0] * dx + m[0][1] * dy + m[0][2] * dz;
  double d1 = m[1][0] * dx + m[1][1] * dy + m[1][2] * dz;
  double d2 = m[2][0] * dx + m[2][1] * dy + m[2][2] * dz;
  double t, x, y, r2, phi;
  /* <<Reject disk intersections for rays parallel to the disk's plane>> */
  if (d2 == 0) return -1;
  t = (dk->height - o2) / d2;
  if (!(t > tnear && t < tfar)) return -1;
  /* <<See if hit point is inside disk radii and phimax>> */
  x = o0 + t * d0; y = o1 + t * d1;
  r2 = x * x + y * y;
  if (r2 > (double)dk->radius * dk->radius || r2 < (double)dk->inner * dk->inner) return -1;
  if (dk->phimax < 6.2831853) {
    phi = atan2(y, x);
    if (phi < 0) phi += 2 * 3.14159265358979323846;
    if (phi > dk->phimax) return -1;
  }
  po[0] = x; po[1] = y; po[2] = dk->height;
  return t;
}
void elr_disk_intersect(const struct RTCIntersectFunctionNArguments *a) {
  const elr_scene *s = (const elr_scene *)a->geometryUserPtr;
  void *rh = a->rayhit;
  unsigned N = a->N, i;
  for (i = 0; i < N; i++) {
    double t, po[3];
    if (a->valid[i] != -1) continue;
    t = elr__disk_hit(&s->disk[a->primID], ELR__RN(rh, 0, N, i), ELR__RN(rh, 1, N, i), ELR__RN(rh, 2, N, i), ELR__RN(rh, 4, N, i),
                      ELR__RN(rh, 5, N, i), ELR__RN(rh, 6, N, i), ELR__RN(rh, 3, N, i), ELR__RN(rh, 8, N, i), po);
    if (t < 0) continue;
    ELR__RN(rh, 8, N, i) = (float)t;
    ELR__RN(rh, 12 + 3, N, i) = ELR__RN(rh, 12 + 4, N, i) = 0.f;
    ELR__RN(rh, 12 + 0, N, i) = 0.f; ELR__RN(rh, 12 + 1, N, i) = 0.f; ELR__RN(rh, 12 + 2, N, i) = 1.f; /* computed in elr_disk_hit */
    ELR__HN(rh, 5, N, i) = a->primID;
    ELR__HN(rh, 6, N, i) = a->geomID;
    ELR__HN(rh, 7, N, i) = RTC_INVALID_GEOMETRY_ID;
  }
}
void elr_disk_occluded(const struct RTCOccludedFunctionNArguments *a) {
  const elr_scene *s = (const elr_scene *)a->geometryUserPtr;
  void *r = a->ray;
  unsigned N = a->N, i;
  for (i = 0; i < N; i++) {
    double po[3];
    if (a->valid[i] != -1) continue;
    if (elr__disk_hit(&s->disk[a->primID], ELR__RN(r, 0, N, i), ELR__RN(r, 1, N, i), ELR__RN(r, 2, N, i), ELR__RN(r, 4, N, i),
                      ELR__RN(r, 5, N, i), ELR__RN(r, 6, N, i), ELR__RN(r, 3, N, i), ELR__RN(r, 8, N, i), po) >= 0)
      ELR__RN(r, 8, N, i) = -INFINITY;
  }
}

/* The hit record of a ray o + t d (t in h->t) on disk di: the point on the plane z = height in object
 * space (<<Refine disk intersection point>>), the normal along the object's +z (turned by flip). */
void elr_disk_hit(const elr_scene *s, int di, elr_v3 o, elr_v3 d, elr_hit *h) {
  const elr_disk *dk = &s->disk[di];
  elr_v3 pw = elr_add(o, elr_mul(d, h->t));
  const double(*mi)[4] = dk->o2w.inv;
  double x = mi[0][0] * pw.x + mi[0][1] * pw.y + mi[0][2] * pw.z + mi[0][3];
  double y = mi[1][0] * pw.x + mi[1][1] * pw.y + mi[1][2] * pw.z + mi[1][3];
  h->kind = ELR_SHAPE_DISK;
  h->prim = (unsigned)di;
  h->pobj = elr_v((float)x, (float)y, dk->height);
  h->p = elr_xpoint(&dk->o2w, h->pobj);
  h->ng = elr_norm(elr_xnormal(&dk->o2w, elr_v(0, 0, 1)));
  if (dk->flip) h->ng = elr_mul(h->ng, -1.f);
  h->ns = h->ng;
  h->material = dk->material;
  h->flip = dk->flip;
  h->light = dk->light;
}

/* >> triangle */
/* The hit record of triangle tri of mesh `mesh` at barycentrics (b1, b2) (pbrt-v3 Triangle::Intersect:
 * the interpolated point, the geometric normal, the shading normal interpolated from the mesh's
 * normals, with the geometric normal turned to its side). */
void elr_triangle_hit(const elr_scene *s, int mesh, unsigned tri, float b1, float b2, elr_hit *h) {
  const elr_mesh *m = &s->mesh[mesh];
  unsigned i0 = m->idx[3 * tri], i1 = m->idx[3 * tri + 1], i2 = m->idx[3 * tri + 2];
  float b0 = 1.f - b1 - b2;
  elr_v3 p0 = elr_v(m->p[3 * i0], m->p[3 * i0 + 1], m->p[3 * i0 + 2]);
  elr_v3 p1 = elr_v(m->p[3 * i1], m->p[3 * i1 + 1], m->p[3 * i1 + 2]);
  elr_v3 p2 = elr_v(m->p[3 * i2], m->p[3 * i2 + 1], m->p[3 * i2 + 2]);
  h->kind = ELR_SHAPE_MESH;
  h->prim = tri;
  h->mesh = mesh;
  h->b1 = b1; h->b2 = b2;
  h->p = elr_add(elr_add(elr_mul(p0, b0), elr_mul(p1, b1)), elr_mul(p2, b2));
  h->ng = elr_norm(elr_cross(elr_sub(p0, p2), elr_sub(p1, p2)));
  if (m->n) {
    elr_v3 n0 = elr_v(m->n[3 * i0], m->n[3 * i0 + 1], m->n[3 * i0 + 2]);
    elr_v3 n1 = elr_v(m->n[3 * i1], m->n[3 * i1 + 1], m->n[3 * i1 + 2]);
    elr_v3 n2 = elr_v(m->n[3 * i2], m->n[3 * i2 + 1], m->n[3 * i2 + 2]);
    elr_v3 ns = elr_add(elr_add(elr_mul(n0, b0), elr_mul(n1, b1)), elr_mul(n2, b2));
    ns = elr_len(ns) > 0 ? elr_norm(ns) : h->ng;
    if (elr_dot(ns, h->ng) < 0) h->ng = elr_mul(h->ng, -1.f); /* pbrt: ng on the side of ns */
    h->ns = ns;
  } else {
    h->ns = h->ng;
  }
  if (m->flip) { h->ng = elr_mul(h->ng, -1.f); h->ns = elr_mul(h->ns, -1.f); }
  h->material = m->material;
  h->flip = m->flip;
  h->light = m->light;
}

/* >> parameterisations */
/* Texture coordinates and the partial derivatives of p and n, only for textured materials and ray
 * differentials: pbrt-v3's Sphere::Intersect and Triangle::Intersect parameterisations. */
void elr_hit_uv(const elr_scene *s, elr_hit *h) {
  if (h->has_uv) return;
  h->has_uv = 1;
  if (h->kind == ELR_SHAPE_SPHERE) {
    const elr_sphere *sp = &s->sph[h->prim];
    double x = h->pobj.x, y = h->pobj.y, z = h->pobj.z, r = sp->radius, phi, theta, zr, cphi, sphi;
    const double PI = 3.14159265358979323846;
    elr_v3 dpdu, dpdv;
    if (x == 0 && y == 0) x = 1e-5 * r;
    phi = atan2(y, x); if (phi < 0) phi += 2 * PI;
    theta = acos(z / r < -1 ? -1 : (z / r > 1 ? 1 : z / r));
    h->u = (float)(phi / (2 * PI));
    h->v = (float)(1.0 - theta / PI); /* (theta - thetaZMin) / (thetaZMax - thetaZMin), thetaZMin = pi */
    zr = sqrt(x * x + y * y);
    cphi = x / zr; sphi = y / zr;
    dpdu = elr_v((float)(-2 * PI * y), (float)(2 * PI * x), 0.f);
    dpdv = elr_mul(elr_v((float)(z * cphi), (float)(z * sphi), (float)(-r * sin(theta))), (float)(-PI));
    h->dpdu = elr_xvector(&sp->o2w, dpdu);
    h->dpdv = elr_xvector(&sp->o2w, dpdv);
    /* Weingarten: for a sphere n = p / r, so dn/du = (dp/du) / r in object space */
    h->dndu = elr_xnormal(&sp->o2w, elr_mul(dpdu, (float)(1.0 / r)));
    h->dndv = elr_xnormal(&sp->o2w, elr_mul(dpdv, (float)(1.0 / r)));
    if (sp->flip) { h->dndu = elr_mul(h->dndu, -1.f); h->dndv = elr_mul(h->dndv, -1.f); }
  } else if (h->kind == ELR_SHAPE_DISK) { /* pbrt-v3's Disk::Intersect parameterisation */
    const elr_disk *dk = &s->disk[h->prim];
    double x = h->pobj.x, y = h->pobj.y, rh = sqrt(x * x + y * y), phi = atan2(y, x);
    const double PI = 3.14159265358979323846;
    if (phi < 0) phi += 2 * PI;
    h->u = (float)(phi / dk->phimax);
    h->v = (float)((dk->radius - rh) / (dk->radius - dk->inner));
    h->dpdu = elr_xvector(&dk->o2w, elr_v((float)(-dk->phimax * y), (float)(dk->phimax * x), 0.f));
    h->dpdv = rh > 0 ? elr_xvector(&dk->o2w, elr_mul(elr_v((float)x, (float)y, 0.f), (float)((dk->inner - dk->radius) / rh)))
                     : elr_v(0, 0, 0);
    h->dndu = h->dndv = elr_v(0, 0, 0);
  } else {
    const elr_mesh *m = &s->mesh[h->mesh];
    unsigned tri = h->prim;
    unsigned i0 = m->idx[3 * tri], i1 = m->idx[3 * tri + 1], i2 = m->idx[3 * tri + 2];
    float b1 = h->b1, b2 = h->b2, b0 = 1.f - b1 - b2;
    elr_v3 p0 = elr_v(m->p[3 * i0], m->p[3 * i0 + 1], m->p[3 * i0 + 2]);
    elr_v3 p1 = elr_v(m->p[3 * i1], m->p[3 * i1 + 1], m->p[3 * i1 + 2]);
    elr_v3 p2 = elr_v(m->p[3 * i2], m->p[3 * i2 + 1], m->p[3 * i2 + 2]);
    float uv0[2] = {0, 0}, uv1[2] = {1, 0}, uv2[2] = {1, 1}; /* pbrt-v3's default uv */
    elr_v3 dp02, dp12;
    float du02, dv02, du12, dv12, det;
    if (m->uv) {
      uv0[0] = m->uv[2 * i0]; uv0[1] = m->uv[2 * i0 + 1];
      uv1[0] = m->uv[2 * i1]; uv1[1] = m->uv[2 * i1 + 1];
      uv2[0] = m->uv[2 * i2]; uv2[1] = m->uv[2 * i2 + 1];
    }
    h->u = b0 * uv0[0] + b1 * uv1[0] + b2 * uv2[0];
    h->v = b0 * uv0[1] + b1 * uv1[1] + b2 * uv2[1];
    /* <<Compute triangle partial derivatives>> */
    dp02 = elr_sub(p0, p2); dp12 = elr_sub(p1, p2);
    du02 = uv0[0] - uv2[0]; dv02 = uv0[1] - uv2[1]; du12 = uv1[0] - uv2[0]; dv12 = uv1[1] - uv2[1];
    det = du02 * dv12 - dv02 * du12;
    if (fabsf(det) < 1e-12f) { /* (around the normal in the mesh's own space: an instance's is taken to world below) */
      elr_onb(h->inst >= 0 ? elr_norm(elr_cross(dp02, dp12)) : h->ng, &h->dpdu, &h->dpdv);
    } else {
      float inv = 1.f / det;
      h->dpdu = elr_mul(elr_sub(elr_mul(dp02, dv12), elr_mul(dp12, dv02)), inv);
      h->dpdv = elr_mul(elr_sub(elr_mul(dp12, du02), elr_mul(dp02, du12)), inv);
    }
    h->dndu = h->dndv = elr_v(0, 0, 0);
    if (m->n && fabsf(det) >= 1e-12f) {
      elr_v3 n0 = elr_v(m->n[3 * i0], m->n[3 * i0 + 1], m->n[3 * i0 + 2]);
      elr_v3 n1 = elr_v(m->n[3 * i1], m->n[3 * i1 + 1], m->n[3 * i1 + 2]);
      elr_v3 n2 = elr_v(m->n[3 * i2], m->n[3 * i2 + 1], m->n[3 * i2 + 2]);
      elr_v3 dn1 = elr_sub(n0, n2), dn2 = elr_sub(n1, n2);
      float inv = 1.f / det;
      h->dndu = elr_mul(elr_sub(elr_mul(dn1, dv12), elr_mul(dn2, dv02)), inv);
      h->dndv = elr_mul(elr_sub(elr_mul(dn2, du02), elr_mul(dn1, du12)), inv);
      if (m->flip) { h->dndu = elr_mul(h->dndu, -1.f); h->dndv = elr_mul(h->dndv, -1.f); }
    }
  }
  if (h->inst >= 0) { /* a prototype's shape: its derivatives to world space, as pbrt-v3's Transform of a SurfaceInteraction */
    const elr_xform *xf = &s->inst[h->inst].xf;
    h->dpdu = elr_xvector(xf, h->dpdu); h->dpdv = elr_xvector(xf, h->dpdv);
    h->dndu = elr_xnormal(xf, h->dndu); h->dndv = elr_xnormal(xf, h->dndv);
  }
}

/* >> sampling points on shapes (pbrt-v3 core/shape.cpp: Shape::Sample(ref, u) and Shape::Pdf(ref, wi),
 * with each shape's own Sample(u)): for area lights (lights.c) */
static double elr__det3(const elr_xform *t) {
  const double(*m)[4] = (const double(*)[4])t->m;
  return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
         m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
}
/* a similarity (rotation, uniform scale, translation): *scale is the scale factor */
static int elr__similarity(const elr_xform *t, double *scale) {
  const double(*m)[4] = (const double(*)[4])t->m;
  double g[3][3], sc;
  int a, b, k;
  for (a = 0; a < 3; a++)
    for (b = 0; b < 3; b++) { g[a][b] = 0; for (k = 0; k < 3; k++) g[a][b] += m[k][a] * m[k][b]; }
  sc = g[0][0];
  for (a = 0; a < 3; a++)
    for (b = 0; b < 3; b++) if (fabs(g[a][b] - (a == b ? sc : 0.0)) > 1e-9 * sc) return 0;
  if (m[3][0] != 0 || m[3][1] != 0 || m[3][2] != 0 || m[3][3] != 1) return 0;
  *scale = sqrt(sc);
  return 1;
}
/* the world area of an ellipsoid's surface element per unit object area, where the object-space unit
 * normal is n: |det A| |A^-T n| (A the transformation's 3x3) */
static double elr__area_scale(const elr_light *l, const elr_xform *o2w, elr_v3 n) { return l->det * (double)elr_len(elr_xnormal(o2w, n)); }

/* pbrt-v3's geometric normal of a triangle at barycentrics (b0, b1, b2), oriented as the hit record's */
static elr_v3 elr__tri_normal(const elr_mesh *m, unsigned tri, float b0, float b1, float b2) {
  unsigned i0 = m->idx[3 * tri], i1 = m->idx[3 * tri + 1], i2 = m->idx[3 * tri + 2];
  elr_v3 p0 = elr_v(m->p[3 * i0], m->p[3 * i0 + 1], m->p[3 * i0 + 2]);
  elr_v3 p1 = elr_v(m->p[3 * i1], m->p[3 * i1 + 1], m->p[3 * i1 + 2]);
  elr_v3 p2 = elr_v(m->p[3 * i2], m->p[3 * i2 + 1], m->p[3 * i2 + 2]);
  elr_v3 n = elr_norm(elr_cross(elr_sub(p0, p2), elr_sub(p1, p2)));
  if (m->n) { /* Faceforward(n, ns) */
    elr_v3 n0 = elr_v(m->n[3 * i0], m->n[3 * i0 + 1], m->n[3 * i0 + 2]);
    elr_v3 n1 = elr_v(m->n[3 * i1], m->n[3 * i1 + 1], m->n[3 * i1 + 2]);
    elr_v3 n2 = elr_v(m->n[3 * i2], m->n[3 * i2 + 1], m->n[3 * i2 + 2]);
    elr_v3 ns = elr_add(elr_add(elr_mul(n0, b0), elr_mul(n1, b1)), elr_mul(n2, b2));
    if (elr_dot(ns, n) < 0.f) n = elr_mul(n, -1.f);
  }
  return m->flip ? elr_mul(n, -1.f) : n;
}

/* The area of the light's shape in world space and what sampling it needs (before a render's threads
 * start): a mesh's cumulative triangle areas (only when build_cdf: the light is sampled); a sphere's
 * centre and radius when its transformation is a similarity (the cone of directions it subtends is then
 * sampled, as pbrt-v3's Sphere::Sample(ref, u)); otherwise (an ellipsoid) its area by quadrature; a
 * disk's oriented normal. Returns -1 when out of memory. */
int elr_shape_prepare(const elr_scene *s, elr_light *l, int build_cdf) {
  const double PI = 3.14159265358979323846;
  if (l->prepared && (!build_cdf || l->shape_kind != ELR_SHAPE_MESH || l->tri_cdf)) return 0;
  if (l->shape_kind == ELR_SHAPE_MESH) {
    const elr_mesh *m = &s->mesh[l->shape];
    double a = 0.0, *cdf = NULL;
    int i;
    if (build_cdf) {
      cdf = (double *)malloc(sizeof(double) * ((size_t)m->ntri + 1));
      if (!cdf) return -1;
    }
    for (i = 0; i < m->ntri; i++) { /* Triangle::Area, in double precision */
      const float *p0 = m->p + 3 * m->idx[3 * i], *p1 = m->p + 3 * m->idx[3 * i + 1], *p2 = m->p + 3 * m->idx[3 * i + 2];
      double e1[3], e2[3], c[3];
      int k;
      for (k = 0; k < 3; k++) { e1[k] = (double)p1[k] - p0[k]; e2[k] = (double)p2[k] - p0[k]; }
      c[0] = e1[1] * e2[2] - e1[2] * e2[1]; c[1] = e1[2] * e2[0] - e1[0] * e2[2]; c[2] = e1[0] * e2[1] - e1[1] * e2[0];
      if (cdf) cdf[i] = a;
      a += 0.5 * sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
    }
    if (cdf) { cdf[m->ntri] = a; free(l->tri_cdf); l->tri_cdf = cdf; }
    l->area = a;
  } else if (l->shape_kind == ELR_SHAPE_SPHERE) {
    const elr_sphere *sp = &s->sph[l->shape];
    double sc, r = sp->radius;
    l->det = fabs(elr__det3(&sp->o2w));
    l->center = elr_xpoint(&sp->o2w, elr_v(0, 0, 0));
    l->cone = elr__similarity(&sp->o2w, &sc);
    if (l->cone) {
      l->wradius = (float)(r * sc);
      l->area = 4.0 * PI * (double)l->wradius * (double)l->wradius;
    } else { /* an ellipsoid: r^2 times the area scale integrated over the unit sphere (midpoints in z and phi) */
      const int nz = 256, nphi = 512;
      double a = 0.0;
      int i, j;
      for (i = 0; i < nz; i++) {
        double z = -1.0 + 2.0 * (i + 0.5) / nz, rr = sqrt(1.0 - z * z);
        for (j = 0; j < nphi; j++) {
          double phi = 2.0 * PI * (j + 0.5) / nphi;
          a += elr__area_scale(l, &sp->o2w, elr_v((float)(rr * cos(phi)), (float)(rr * sin(phi)), (float)z));
        }
      }
      l->area = a * (2.0 / nz) * (2.0 * PI / nphi) * r * r;
    }
  } else {
    const elr_disk *dk = &s->disk[l->shape];
    elr_v3 n = elr_xnormal(&dk->o2w, elr_v(0, 0, 1));
    l->det = fabs(elr__det3(&dk->o2w));
    /* Disk::Area times the constant area scale of the plane */
    l->area = 0.5 * dk->phimax * ((double)dk->radius * dk->radius - (double)dk->inner * dk->inner) * l->det * (double)elr_len(n);
    n = elr_norm(n);
    l->n_disk = dk->flip ? elr_mul(n, -1.f) : n;
  }
  l->prepared = 1;
  return 0;
}

/* the density in area measure with which elr_shape_sample picks the point lh of the light's shape when
 * it samples by area (not the sphere's cone) */
static double elr__area_pdf(const elr_scene *s, const elr_light *l, elr_v3 pobj) {
  if (l->shape_kind == ELR_SHAPE_SPHERE && !l->cone) { /* uniform on the object's sphere, mapped */
    const elr_sphere *sp = &s->sph[l->shape];
    double r = sp->radius, J = elr__area_scale(l, &sp->o2w, elr_mul(pobj, (float)(1.0 / r)));
    return 1.0 / (4.0 * 3.14159265358979323846 * r * r * J);
  }
  return 1.0 / l->area;
}
/* the sphere's cone of directions from ref (ref outside it): 1 - cos(theta_max), without cancellation */
static int elr__cone(const elr_light *l, elr_v3 ref, double *one_minus_cos, double *dc) {
  double dx = (double)l->center.x - ref.x, dy = (double)l->center.y - ref.y, dz = (double)l->center.z - ref.z;
  double d2 = dx * dx + dy * dy + dz * dz, r2 = (double)l->wradius * l->wradius, s2, c;
  /* inside (pbrt-v3 tests the ray origin offset towards the centre: a point on the sphere is inside) */
  if (!l->cone || d2 <= r2 * (1.0 + 1e-4)) return 0;
  s2 = r2 / d2;
  c = sqrt(1.0 - s2);
  *one_minus_cos = s2 / (1.0 + c);
  *dc = sqrt(d2);
  return 1;
}

/* pbrt-v3's Shape::Sample(ref, u, &pdf) for the light's shape: a point *p, its normal *n (the hit
 * record's orientation), and the solid-angle density *pdf of the direction from ref (0: unusable). */
void elr_shape_sample(const elr_scene *s, const elr_light *l, elr_v3 ref, const float u[2], elr_v3 *p, elr_v3 *n, float *pdf) {
  const double PI = 3.14159265358979323846;
  double pa = 0.0, omc, dc, d2, cosl;
  elr_v3 w;
  *pdf = 0.f;
  *p = *n = elr_v(0, 0, 0);
  if (!(l->area > 0.0)) return;
  if (l->shape_kind == ELR_SHAPE_SPHERE && elr__cone(l, ref, &omc, &dc)) {
    /* <<Sample sphere uniformly inside subtended cone>> (pbrt-v3 Sphere::Sample(ref, u)) */
    double sin2max = (double)l->wradius * l->wradius / (dc * dc), invsin = 1.0 / sqrt(sin2max);
    double cost = 1.0 - omc * u[0], sin2 = 1.0 - cost * cost, cosa, sina, phi = 2.0 * PI * u[1];
    elr_v3 wc = elr_mul(elr_sub(l->center, ref), (float)(1.0 / dc)), wx, wy, nw;
    if (sin2max < 0.00068523) { sin2 = sin2max * u[0]; cost = sqrt(1.0 - sin2); } /* small angles: pbrt-v3's Taylor series */
    elr_onb(wc, &wx, &wy);
    /* <<Compute angle alpha from center of sphere to sampled point on surface>> */
    cosa = sin2 * invsin + cost * sqrt(fmax(0.0, 1.0 - sin2 * invsin * invsin));
    sina = sqrt(fmax(0.0, 1.0 - cosa * cosa));
    /* <<Compute surface normal and sampled point on sphere>> */
    nw = elr_add(elr_add(elr_mul(wx, (float)(-sina * cos(phi))), elr_mul(wy, (float)(-sina * sin(phi)))), elr_mul(wc, (float)(-cosa)));
    *p = elr_add(l->center, elr_mul(nw, l->wradius));
    *n = s->sph[l->shape].flip ? elr_mul(nw, -1.f) : nw;
    *pdf = (float)(1.0 / (2.0 * PI * omc)); /* uniform cone pdf */
    return;
  }
  if (l->shape_kind == ELR_SHAPE_MESH) { /* a triangle by area (the CDF), then Triangle::Sample */
    const elr_mesh *m = &s->mesh[l->shape];
    const double *cdf = l->tri_cdf;
    double x = (double)u[0] * l->area;
    int lo = 0, hi = m->ntri - 1;
    unsigned i0, i1, i2;
    float u0, su0, b0, b1, b2;
    if (!cdf) return;
    while (lo < hi) { /* the last triangle whose cumulative area starts at or below x */
      int mid = (lo + hi + 1) / 2;
      if (cdf[mid] <= x) lo = mid; else hi = mid - 1;
    }
    while (lo > 0 && !(cdf[lo + 1] > cdf[lo])) lo--; /* (x = the end of a run of empty triangles) */
    u0 = (float)((x - cdf[lo]) / (cdf[lo + 1] - cdf[lo]));
    if (!(u0 >= 0.f)) u0 = 0.f;
    if (u0 > ELR_ONE_MINUS_EPS) u0 = ELR_ONE_MINUS_EPS;
    su0 = sqrtf(u0); b0 = 1.f - su0; b1 = u[1] * su0; b2 = 1.f - b0 - b1; /* UniformSampleTriangle */
    i0 = m->idx[3 * lo]; i1 = m->idx[3 * lo + 1]; i2 = m->idx[3 * lo + 2];
    *p = elr_add(elr_add(elr_mul(elr_v(m->p[3 * i0], m->p[3 * i0 + 1], m->p[3 * i0 + 2]), b0), elr_mul(elr_v(m->p[3 * i1], m->p[3 * i1 + 1], m->p[3 * i1 + 2]), b1)),
                 elr_mul(elr_v(m->p[3 * i2], m->p[3 * i2 + 1], m->p[3 * i2 + 2]), b2));
    *n = elr__tri_normal(m, (unsigned)lo, b0, b1, b2);
    pa = 1.0 / l->area;
  } else if (l->shape_kind == ELR_SHAPE_SPHERE) { /* Sphere::Sample(u): uniform on the object's sphere */
    const elr_sphere *sp = &s->sph[l->shape];
    float z = 1.f - 2.f * u[0], rr = sqrtf(fmaxf(0.f, 1.f - z * z)), phi = 2.f * ELR_PI * u[1];
    elr_v3 nobj = elr_v(rr * cosf(phi), rr * sinf(phi), z);
    *p = elr_xpoint(&sp->o2w, elr_mul(nobj, sp->radius));
    *n = elr_norm(elr_xnormal(&sp->o2w, nobj));
    if (sp->flip) *n = elr_mul(*n, -1.f);
    pa = elr__area_pdf(s, l, elr_mul(nobj, sp->radius));
  } else { /* Disk::Sample(u) (pbrt-v3 samples the whole disk also for innerradius > 0 or phimax < 360, a
            * bias: a partial disk is sampled here over its own area) */
    const elr_disk *dk = &s->disk[l->shape];
    float x, y;
    if (dk->inner == 0.f && dk->phimax >= 6.2831853f) { /* ConcentricSampleDisk, as pbrt-v3 */
      float ox = 2.f * u[0] - 1.f, oy = 2.f * u[1] - 1.f, r, th;
      if (ox == 0.f && oy == 0.f) { r = 0.f; th = 0.f; }
      else if (fabsf(ox) > fabsf(oy)) { r = ox; th = (ELR_PI / 4.f) * (oy / ox); }
      else { r = oy; th = ELR_PI / 2.f - (ELR_PI / 4.f) * (ox / oy); }
      x = r * cosf(th) * dk->radius; y = r * sinf(th) * dk->radius;
    } else { /* the annulus sector by area: r^2 uniform in [inner^2, radius^2], phi in [0, phimax] */
      float r = sqrtf(dk->inner * dk->inner + u[0] * (dk->radius * dk->radius - dk->inner * dk->inner)), ph = u[1] * dk->phimax;
      x = r * cosf(ph); y = r * sinf(ph);
    }
    *p = elr_xpoint(&dk->o2w, elr_v(x, y, dk->height));
    *n = l->n_disk;
    pa = 1.0 / l->area;
  }
  /* <<Convert from area measure, as returned by the Sample() call above, to solid angle measure>> */
  w = elr_sub(*p, ref);
  d2 = (double)elr_dot(w, w);
  if (d2 == 0.0) return;
  cosl = fabs((double)elr_dot(*n, w)) / sqrt(d2);
  if (!(cosl > 0.0)) return;
  pa *= d2 / cosl;
  *pdf = pa < (double)FLT_MAX ? (float)pa : 0.f;
}

/* pbrt-v3's Shape::Pdf(ref, wi) for the direction from ref that reaches the light's shape at lh */
float elr_shape_pdf(const elr_scene *s, const elr_light *l, elr_v3 ref, const elr_hit *lh) {
  double omc, dc, pa, d2, cosl;
  elr_v3 w;
  if (!(l->area > 0.0)) return 0.f;
  if (l->shape_kind == ELR_SHAPE_SPHERE && elr__cone(l, ref, &omc, &dc)) return (float)(1.0 / (2.0 * 3.14159265358979323846 * omc));
  pa = elr__area_pdf(s, l, lh->pobj);
  w = elr_sub(lh->p, ref);
  d2 = (double)elr_dot(w, w);
  if (d2 == 0.0) return 0.f;
  cosl = fabs((double)elr_dot(lh->ng, w)) / sqrt(d2);
  if (!(cosl > 0.0)) return 0.f;
  pa *= d2 / cosl;
  return pa < (double)FLT_MAX ? (float)pa : 0.f;
}
