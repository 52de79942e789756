/* tutorials/labs/03-light/infinite.h: LAB 3 (chapter 3, the infinite area light), part 2 of 2: the light.
 * This is examples/pbrtv3/infinite.h with the bodies chapter 3 ports taken out. Write them back; everything
 * else is given and works.
 *
 * What you write (search for "TODO"; the lab is sampling.h and infinite.h in this directory):
 *   sampling.h  TODO 1  pbrt_Distribution1D_init: the CDF and funcInt (chapter 3, "Step 2: Distribution1D and Distribution2D")
 *               TODO 2  pbrt_Distribution1D_SampleContinuous
 *               TODO 3  pbrt_Distribution2D_init: one Distribution1D per row, and the marginal
 *               TODO 4  pbrt_Distribution2D_SampleContinuous
 *               TODO 5  pbrt_Distribution2D_Pdf
 *   infinite.h  TODO 6  pbrt_InfiniteAreaLight_Sample_Li ("Step 3")
 *               TODO 7  pbrt_InfiniteAreaLight_Pdf_Li ("Step 3")
 * Build and check: `sh scripts/lab.sh 3` (from the repository root). The test compares your
 * distributions and light with pbrt's, compiled separately from examples/pbrtv3/, and says what
 * differs. Untouched, these files compile and run, and the test fails: every TODO returns zeros.
 */
#ifndef PBRTV3_INFINITE_H
#define PBRTV3_INFINITE_H

#include "sampling.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define pbrt_Pi 3.14159265358979323846f
#define pbrt_InvPi 0.31830988618379067154f
#define pbrt_Inv2Pi 0.15915494309189533577f

/* >> Transform, for directions: a 3x3 matrix and its inverse (pbrt keeps both, m and mInv) */
typedef struct pbrt_Transform {
  float m[9], mInv[9]; /* row-major: out[i] = sum_j m[3 i + j] v[j] */
} pbrt_Transform;

static inline float pbrt_Radians(float deg) { return (pbrt_Pi / 180) * deg; }

static inline void pbrt_Transpose3(const float a[9], float t[9]) {
  int i, j;
  for (i = 0; i < 3; ++i)
    for (j = 0; j < 3; ++j) t[3 * i + j] = a[3 * j + i];
}
/* RotateX(theta), theta in degrees: y' = cos y - sin z, z' = sin y + cos z */
static inline pbrt_Transform pbrt_RotateX(float theta) {
  pbrt_Transform t;
  float sinTheta = sinf(pbrt_Radians(theta)), cosTheta = cosf(pbrt_Radians(theta));
  float m[9] = {1, 0, 0, 0, 0, 0, 0, 0, 0};
  m[4] = cosTheta; m[5] = -sinTheta;
  m[7] = sinTheta; m[8] = cosTheta;
  memcpy(t.m, m, sizeof m);
  pbrt_Transpose3(t.m, t.mInv);
  return t;
}
/* RotateZ(theta): x' = cos x - sin y, y' = sin x + cos y */
static inline pbrt_Transform pbrt_RotateZ(float theta) {
  pbrt_Transform t;
  float sinTheta = sinf(pbrt_Radians(theta)), cosTheta = cosf(pbrt_Radians(theta));
  float m[9] = {0, 0, 0, 0, 0, 0, 0, 0, 1};
  m[0] = cosTheta; m[1] = -sinTheta;
  m[3] = sinTheta; m[4] = cosTheta;
  memcpy(t.m, m, sizeof m);
  pbrt_Transpose3(t.m, t.mInv);
  return t;
}
/* a * b: apply b first (pbrt's Transform::operator*) */
static inline pbrt_Transform pbrt_Transform_mul(const pbrt_Transform *a, const pbrt_Transform *b) {
  pbrt_Transform t;
  int i, j, k;
  for (i = 0; i < 3; ++i)
    for (j = 0; j < 3; ++j) {
      t.m[3 * i + j] = 0;
      t.mInv[3 * i + j] = 0;
      for (k = 0; k < 3; ++k) {
        t.m[3 * i + j] += a->m[3 * i + k] * b->m[3 * k + j];
        t.mInv[3 * i + j] += b->mInv[3 * i + k] * a->mInv[3 * k + j];
      }
    }
  return t;
}
static inline pbrt_Transform pbrt_Inverse(const pbrt_Transform *t) {
  pbrt_Transform r;
  memcpy(r.m, t->mInv, sizeof r.m);
  memcpy(r.mInv, t->m, sizeof r.mInv);
  return r;
}
/* (*t)(Vector3f v) */
static inline void pbrt_Transform_Vector(const pbrt_Transform *t, const float v[3], float out[3]) {
  int i;
  float r[3];
  for (i = 0; i < 3; ++i) r[i] = t->m[3 * i] * v[0] + t->m[3 * i + 1] * v[1] + t->m[3 * i + 2] * v[2];
  memcpy(out, r, sizeof r);
}

/* >> geometry.h: spherical coordinates of a direction (theta from +z, phi from +x towards +y) */
static inline float pbrt_SphericalTheta(const float v[3]) {
  return acosf(v[2] < -1 ? -1 : v[2] > 1 ? 1 : v[2]); /* acos(Clamp(v.z, -1, 1)) */
}
static inline float pbrt_SphericalPhi(const float v[3]) {
  float p = atan2f(v[1], v[0]);
  return (p < 0) ? (p + 2 * pbrt_Pi) : p;
}

/* RGBSpectrum::y(): the luminance */
static inline float pbrt_y(const float rgb[3]) {
  const float YWeight[3] = {0.212671f, 0.715160f, 0.072169f};
  return YWeight[0] * rgb[0] + YWeight[1] * rgb[1] + YWeight[2] * rgb[2];
}

/* >> Lmap: the part of MIPMap<RGBSpectrum> the light uses (level 0, pbrt's default wrap: Repeat) */
typedef struct pbrt_Lmap {
  int width, height; /* Width(), Height(): powers of two here */
  int levels;        /* Levels(): 1 + Log2Int(max(width, height)), as the full pyramid would have */
  float *texels;     /* pyramid[0]: width * height RGB (pbrt tiles it in a BlockedArray) */
} pbrt_Lmap;

/* pbrt's Mod: a result in [0, b) also for negative a */
static inline int pbrt_Mod(int a, int b) {
  int result = a - (a / b) * b;
  return (result < 0) ? result + b : result;
}
/* MIPMap::Texel(0, s, t) under ImageWrap::Repeat */
static inline const float *pbrt_Lmap_Texel(const pbrt_Lmap *l, int s, int t) {
  /* <<Compute texel (s,t) accounting for boundary conditions>> */
  s = pbrt_Mod(s, l->width);
  t = pbrt_Mod(t, l->height);
  return l->texels + 3 * ((size_t)t * (size_t)l->width + (size_t)s);
}
/* MIPMap::triangle(0, st): bilinear interpolation of level 0, texel centres at half-integers */
static inline void pbrt_Lmap_triangle(const pbrt_Lmap *l, const float st[2], float rgb[3]) {
  float s = st[0] * l->width - 0.5f, t = st[1] * l->height - 0.5f;
  int s0 = (int)floorf(s), t0 = (int)floorf(t), c;
  float ds = s - s0, dt = t - t0;
  const float *a = pbrt_Lmap_Texel(l, s0, t0), *b = pbrt_Lmap_Texel(l, s0, t0 + 1);
  const float *e = pbrt_Lmap_Texel(l, s0 + 1, t0), *f = pbrt_Lmap_Texel(l, s0 + 1, t0 + 1);
  for (c = 0; c < 3; ++c)
    rgb[c] = (1 - ds) * (1 - dt) * a[c] + (1 - ds) * dt * b[c] + ds * (1 - dt) * e[c] + ds * dt * f[c];
}
/* Log2(x) of pbrt.h */
static inline float pbrt_Log2(float x) {
  const float invLog2 = 1.442695040888963387004650940071f;
  return logf(x) * invLog2;
}
/* MIPMap::Lookup(st, width) for the widths the light passes. <<Compute MIPMap level for trilinear
 * filtering>> gives level = Levels() - 1 + Log2(max(width, 1e-8)), below 0 for all of them (Le and
 * Sample_Li pass width 0; pbrt_InfiniteAreaLight_init checks the constructor's width), and a level
 * below 0 is triangle(0, st), the bilinear lookup of level 0. Other widths need chapter 2's MIPMap. */
static inline void pbrt_Lmap_Lookup(const pbrt_Lmap *l, const float st[2], float rgb[3]) {
  pbrt_Lmap_triangle(l, st, rgb);
}

/* >> InfiniteAreaLight */
typedef struct pbrt_InfiniteAreaLight {
  pbrt_Transform LightToWorld, WorldToLight;
  pbrt_Lmap Lmap;
  pbrt_Distribution2D distribution;
} pbrt_InfiniteAreaLight;

static inline int pbrt_IsPowerOf2(int v) { return v > 0 && (v & (v - 1)) == 0; }
static inline int pbrt_Log2Int(int v) {
  int r = 0;
  while (v > 1) { v >>= 1; ++r; }
  return r;
}

static inline void pbrt_InfiniteAreaLight_free(pbrt_InfiniteAreaLight *light) {
  free(light->Lmap.texels);
  light->Lmap.texels = NULL;
  pbrt_Distribution2D_free(&light->distribution);
}

/* InfiniteAreaLight(LightToWorld, L, nSamples, texmap), from the texels of the map already read and
 * multiplied by L (pbrt reads them with ReadImage inside the constructor; the seed with stbi_loadf,
 * pbrt_LoadEnvironmentMap below). The texels (resolution[0] x resolution[1] RGB, row 0 = theta 0) are
 * copied, as MIPMap copies them. Returns 0; -1 when memory runs out; -2 for a map this port's Lmap does
 * not cover (see the top of the file). */
static inline int pbrt_InfiniteAreaLight_init(pbrt_InfiniteAreaLight *light, const pbrt_Transform *LightToWorld,
                                              const float *texels, const int resolution[2]) {
  int width, height, u, v;
  float fwidth, *img;
  size_t bytes = sizeof(float) * 3 * (size_t)resolution[0] * (size_t)resolution[1];
  memset(light, 0, sizeof *light);
  light->LightToWorld = *LightToWorld;
  light->WorldToLight = pbrt_Inverse(LightToWorld);
  if (!pbrt_IsPowerOf2(resolution[0]) || !pbrt_IsPowerOf2(resolution[1])) return -2;
  /* Lmap.reset(new MIPMap<RGBSpectrum>(resolution, texels.get())): its level 0 */
  light->Lmap.width = resolution[0];
  light->Lmap.height = resolution[1];
  light->Lmap.levels = 1 + pbrt_Log2Int(resolution[0] > resolution[1] ? resolution[0] : resolution[1]);
  width = 2 * light->Lmap.width;
  height = 2 * light->Lmap.height;
  fwidth = 0.5f / (width < height ? width : height);
  if (light->Lmap.levels - 1 + pbrt_Log2(fwidth) >= 0) return -2; /* a map 4 times as wide as tall, or more */
  light->Lmap.texels = (float *)malloc(bytes);
  if (!light->Lmap.texels) return -1;
  memcpy(light->Lmap.texels, texels, bytes);

  /* <<Initialize sampling PDFs for infinite area light>> */
  /* <<Compute scalar-valued image img from environment map>> */
  img = (float *)malloc(sizeof(float) * (size_t)width * (size_t)height);
  if (!img) {
    pbrt_InfiniteAreaLight_free(light);
    return -1;
  }
  for (v = 0; v < height; ++v) { /* pbrt: ParallelFor over the rows */
    float vp = (v + .5f) / (float)height;
    float sinTheta = sinf(pbrt_Pi * (v + .5f) / height);
    for (u = 0; u < width; ++u) {
      float up = (u + .5f) / (float)width, st[2], rgb[3];
      st[0] = up;
      st[1] = vp;
      pbrt_Lmap_Lookup(&light->Lmap, st, rgb); /* Lmap->Lookup(Point2f(up, vp), fwidth) */
      img[u + v * width] = pbrt_y(rgb);
      img[u + v * width] *= sinTheta;
    }
  }
  /* <<Compute sampling distributions for rows and columns of image>> */
  if (pbrt_Distribution2D_init(&light->distribution, img, width, height) != 0) {
    free(img);
    pbrt_InfiniteAreaLight_free(light);
    return -1;
  }
  free(img);
  return 0;
}

/* Le(ray): the radiance arriving along a ray that leaves the scene in direction d (world space) */
static inline void pbrt_InfiniteAreaLight_Le(const pbrt_InfiniteAreaLight *light, const float d[3], float L[3]) {
  float w[3], st[2], len;
  pbrt_Transform_Vector(&light->WorldToLight, d, w); /* Normalize(WorldToLight(ray.d)) */
  len = sqrtf(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
  w[0] /= len; w[1] /= len; w[2] /= len;
  st[0] = pbrt_SphericalPhi(w) * pbrt_Inv2Pi;
  st[1] = pbrt_SphericalTheta(w) * pbrt_InvPi;
  pbrt_Lmap_Lookup(&light->Lmap, st, L); /* Lmap->Lookup(st) */
}

/* Sample_Li(ref, u, &wi, &pdf, &vis): a direction wi (world space, towards the light) with solid-angle
 * density *pdf, and the radiance L arriving from it. A sample with pdf 0 must be skipped. (pbrt returns
 * black and leaves *pdf alone when mapPdf is 0; its caller had set it to 0. Here *pdf is set.) */
static inline void pbrt_InfiniteAreaLight_Sample_Li(const pbrt_InfiniteAreaLight *light, const float u[2], float wi[3],
                                                    float *pdf, float L[3]) {
  /* TODO 6: <<Find (u,v) sample coordinates in infinite light texture>>: sample light->distribution
   * with u (uv and mapPdf); if mapPdf is 0, return pdf 0 and black. <<Convert infinite light sample
   * point to direction>>: theta = uv[1] pi, phi = uv[0] 2 pi; the direction (sin theta cos phi,
   * sin theta sin phi, cos theta) is in the light's space: wi is it through light->LightToWorld
   * (pbrt_Transform_Vector). <<Compute PDF for sampled infinite light direction>>: the density in
   * (u, v) becomes a density in solid angle: *pdf = mapPdf / (2 pi^2 sin theta), 0 if sin theta is 0.
   * <<Return radiance value for infinite light direction>>: L = the map at uv (pbrt_Lmap_Lookup).
   * Untouched: wi = (0, 0, 0), pdf 0, black. */
  (void)light;
  (void)u;
  wi[0] = wi[1] = wi[2] = 0;
  *pdf = 0;
  L[0] = L[1] = L[2] = 0;
}

/* Pdf_Li(ref, w): the density with which Sample_Li picks the world direction w */
static inline float pbrt_InfiniteAreaLight_Pdf_Li(const pbrt_InfiniteAreaLight *light, const float w[3]) {
  /* TODO 7: the inverse of TODO 6: bring w into the light's space (light->WorldToLight), take its
   * spherical angles (pbrt_SphericalTheta, pbrt_SphericalPhi), return 0 if sin theta is 0, else the
   * distribution's Pdf at (phi / 2 pi, theta / pi) divided by 2 pi^2 sin theta.
   * Untouched: 0. */
  (void)light;
  (void)w;
  return 0;
}

/* Bytes the light holds: the texels of level 0 (the whole pyramid would add a third) and the
 * distribution. */
static inline size_t pbrt_InfiniteAreaLight_bytes(const pbrt_InfiniteAreaLight *light) {
  return sizeof(float) * 3 * (size_t)light->Lmap.width * (size_t)light->Lmap.height +
         pbrt_Distribution2D_bytes(&light->distribution);
}

#ifdef STBI_INCLUDE_STB_IMAGE_H
/* The seed's loading code (its section 三, "读取文件我采用的是 stb_image.h"): stbi_loadf, then each
 * texel times L, into RGB. Returns the texels (free them with free) and their resolution, or NULL when
 * stb cannot read the file or it has fewer than 3 channels (the seed reads channels 0, 1 and 2 of every
 * texel). stb reads some truncated and corrupt files without noticing: the chapter's example checks
 * the file with el_image_load (examples/common) before it gets here. */
static inline float *pbrt_LoadEnvironmentMap(const char *texmap, const float L[3], int resolution[2]) {
  int imageWidth, imageHeight, nrComponents, i, j;
  float *data = stbi_loadf(texmap, &imageWidth, &imageHeight, &nrComponents, 0), *data_s;
  if (!data) return NULL;
  if (nrComponents < 3) {
    stbi_image_free(data);
    return NULL;
  }
  data_s = (float *)malloc(sizeof(float) * 3 * (size_t)imageWidth * (size_t)imageHeight);
  if (data_s) {
    for (j = 0; j < imageHeight; j++) {
      for (i = 0; i < imageWidth; i++) {
        float *r = data_s + 3 * ((size_t)i + (size_t)j * (size_t)imageWidth); /* RGBSpectrum r */
        const float *texel = data + ((size_t)i + (size_t)j * (size_t)imageWidth) * (size_t)nrComponents;
        r[0] = L[0] * texel[0];
        r[1] = L[1] * texel[1];
        r[2] = L[2] * texel[2];
      }
    }
    resolution[0] = imageWidth;
    resolution[1] = imageHeight;
  }
  stbi_image_free(data); /* the seed: free(data) */
  return data_s;
}
#endif

#endif /* PBRTV3_INFINITE_H */
