/* elr_internal.h: the renderer's private declarations, one section per concept; each section names
 * the file that implements it (README.md's file table says which part of pbrt-v3 each file mirrors).
 * Only examples/render (its tests and bench/bench_render.c) include it. The library's headers are
 * included for their declarations (envlight_impl.c compiles them); colours and directions cross to
 * them as float[3] (elr_to3, elr_from3).
 *   vectors, transforms (transform.c)      scene description (parser.c and api*.c, scene.c, ply.c, loopsubdiv.c)
 *   intersection (scene.c, shapes.c)      textures, materials, BSDFs (textures.c, materials.c, reflection.c)
 *   ray differentials (interaction.c)     lights (lights.c)          camera (camera.c)
 *   samplers (sampler*.c)                 film (film.c)              a render (render.c)
 *   integrators (integrator*.c, render_wave.c) */
#ifndef ELR_INTERNAL_H
#define ELR_INTERNAL_H
#include "el_render.h"
#include "envlight.h"
#include "film.h"
#include "mipmap.h"
#include <math.h>
#include <stdint.h>
#include <stdio.h>

#ifndef ELR_PI
#define ELR_PI 3.14159265358979323846f
/* LightSource "infinite" "float portalmapshare" default (bench/bench_portal_render.c measures it) */
#define ELR_PORTAL_MAP_SHARE 0.5
#endif
#define ELR_INV_PI 0.31830988618379067154f
#define ELR_ONE_MINUS_EPS 0x1.fffffep-1f
/* rarely taken branches of hot functions stay out of line, so that the common case keeps its registers */
#if defined(__GNUC__)
#define ELR_NOINLINE __attribute__((noinline))
#else
#define ELR_NOINLINE
#endif

/* >> vectors */
typedef struct elr_v3 { float x, y, z; } elr_v3;
static inline elr_v3 elr_v(float x, float y, float z) { elr_v3 r; r.x = x; r.y = y; r.z = z; return r; }
static inline elr_v3 elr_add(elr_v3 a, elr_v3 b) { return elr_v(a.x + b.x, a.y + b.y, a.z + b.z); }
static inline elr_v3 elr_sub(elr_v3 a, elr_v3 b) { return elr_v(a.x - b.x, a.y - b.y, a.z - b.z); }
static inline elr_v3 elr_mul(elr_v3 a, float s) { return elr_v(a.x * s, a.y * s, a.z * s); }
static inline elr_v3 elr_vmul(elr_v3 a, elr_v3 b) { return elr_v(a.x * b.x, a.y * b.y, a.z * b.z); }
static inline float elr_dot(elr_v3 a, elr_v3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static inline elr_v3 elr_cross(elr_v3 a, elr_v3 b) {
  return elr_v(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
static inline float elr_len(elr_v3 a) { return sqrtf(elr_dot(a, a)); }
static inline elr_v3 elr_norm(elr_v3 a) {
  float l = elr_len(a);
  return l > 0.f ? elr_mul(a, 1.f / l) : elr_v(0.f, 0.f, 1.f);
}
static inline float elr_maxc(elr_v3 a) { float m = a.x > a.y ? a.x : a.y; return m > a.z ? m : a.z; }
static inline int elr_isblack(elr_v3 a) { return a.x == 0.f && a.y == 0.f && a.z == 0.f; }
/* the library's float[3] (envlight.h, film.h, mipmap.h take and return colours and directions so) */
static inline void elr_to3(elr_v3 a, float f[3]) { f[0] = a.x; f[1] = a.y; f[2] = a.z; }
static inline elr_v3 elr_from3(const float f[3]) { return elr_v(f[0], f[1], f[2]); }
/* Orthonormal basis around unit n (Duff et al. 2017). */
static inline void elr_onb(elr_v3 n, elr_v3 *s, elr_v3 *t) {
  float sign = n.z >= 0.f ? 1.f : -1.f;
  float a = -1.f / (sign + n.z), b = n.x * n.y * a;
  *s = elr_v(1.f + sign * n.x * n.x * a, sign * b, -sign * n.x);
  *t = elr_v(b, sign + n.y * n.y * a, -n.y);
}

/* >> transforms (transform.c): pbrt-v3's Transform, a matrix and its inverse, row-major, column vectors */
typedef struct elr_xform { double m[4][4], inv[4][4]; } elr_xform;
void elr_xform_identity(elr_xform *t);
int elr_xform_from_matrix(elr_xform *t, double m[4][4]); /* -1 when singular */
void elr_xform_mul(elr_xform *out, const elr_xform *a, const elr_xform *b); /* a*b */
void elr_xform_invert(elr_xform *out, const elr_xform *a);
elr_v3 elr_xpoint(const elr_xform *t, elr_v3 p);
elr_v3 elr_xvector(const elr_xform *t, elr_v3 v);
elr_v3 elr_xnormal(const elr_xform *t, elr_v3 n); /* by the inverse transpose */
elr_v3 elr_xvector_inv(const elr_xform *t, elr_v3 v);
elr_v3 elr_xpoint_inv(const elr_xform *t, elr_v3 p);

/* >> scene description (parser.c, paramset.c and api*.c read it; scene.c builds the lights and the Embree scene, and frees it) */
/* the PixelFilter directive's parameters (film.c makes film.h's filter of them) */
enum { ELR_PF_BOX = 0, ELR_PF_TRIANGLE, ELR_PF_GAUSSIAN, ELR_PF_MITCHELL, ELR_PF_SINC };
typedef struct elr_filter_desc { int type; float xw, yw, alpha, b, c, tau; int nonneg; } elr_filter_desc; /* nonneg: "bool nonnegative" */

enum { ELR_TEX_CONST = 0, ELR_TEX_CHECKER = 1, ELR_TEX_IMAGE = 2, ELR_TEX_SCALE = 3, ELR_TEX_MIX = 4 };
typedef struct elr_texture {
  int kind;
  elr_v3 value;            /* constant */
  int tex1, tex2;          /* checkerboard, scale, mix: sub-textures */
  int amount;              /* mix: the float texture that blends tex1 (0) to tex2 (1) */
  int aa_closedform;       /* checkerboard aamode */
  float su, sv, du, dv;    /* uv mapping */
  el_mipmap *mip;          /* imagemap (mipmap.h; upper levels built on the first lookup that needs them) */
  int is_float;
} elr_texture;

enum { ELR_MAT_MATTE = 0, ELR_MAT_MIRROR = 1, ELR_MAT_PLASTIC = 2, ELR_MAT_GLASS = 3, ELR_MAT_METAL = 4, ELR_MAT_UBER = 5,
       ELR_MAT_SUBSTRATE = 6 };
typedef struct elr_material {
  int kind;
  int kd, ks, kr, rough; /* texture indices (-1: none) */
  int remap;
  int kt, urough, vrough, index, eta, k, opacity; /* glass, metal, uber, substrate (-1: none) */
} elr_material;
#define ELR_MAT_NTEX 11 /* the texture indices of a material, as an array: elr_material_textures */
static inline void elr_material_textures(const elr_material *m, int t[ELR_MAT_NTEX]) {
  t[0] = m->kd; t[1] = m->ks; t[2] = m->kr; t[3] = m->rough; t[4] = m->kt; t[5] = m->urough; t[6] = m->vrough;
  t[7] = m->index; t[8] = m->eta; t[9] = m->k; t[10] = m->opacity;
}

/* Every shape: its material, the area light it carries (an index in elr_scene.light, or -1) and its
 * orientation: flip = 1 when pbrt-v3 turns its normals around (ReverseOrientation; for a triangle mesh
 * without normals also a transformation that swaps handedness), which the hit records and the sampled
 * points of shapes.c apply. The normals decide which side of a one-sided area light emits. */
typedef struct elr_mesh {
  int ntri, nvert;
  unsigned *idx;  /* 3*ntri */
  float *p;       /* 3*nvert, world space */
  float *n;       /* 3*nvert or NULL, world space */
  float *uv;      /* 2*nvert or NULL */
  int material, light; /* light: the area light this shape carries (an index in elr_scene.light), or -1 */
  int flip;       /* pbrt-v3: ReverseOrientation xor a transform that swaps handedness (see shapes.c) */
  int object;     /* -1: in the world; else the ObjectBegin prototype (elr_object) it belongs to */
} elr_mesh;

typedef struct elr_sphere {
  elr_xform o2w; /* object to world (an instance's object space, for a prototype's sphere) */
  float radius;
  int material, light;
  int flip;      /* pbrt-v3: ReverseOrientation xor a transform that swaps handedness */
  int object;    /* -1, or the prototype it belongs to */
  /* the intersection callbacks' (elr_sphere_prepare): the centre wc in o2w's target space (in float), o2w.inv's
   * 3x3 with wc's place in object space as the fourth column, radius^2; sim: o2w is a similarity, of scale wr / radius;
   * dbl: every ray in double (radius^2 or a r^2 out of float's comfortable range: shapes.c) */
  float wc[3], w2o[12], r2, wr;
  int sim, dbl;
} elr_sphere;

/* pbrt-v3's Disk (shapes/disk.cpp): the annulus innerradius <= r <= radius, 0 <= phi <= phimax, at
 * z = height in object space (in the world only: not inside ObjectBegin) */
typedef struct elr_disk {
  elr_xform o2w;
  float height, radius, inner, phimax; /* phimax in radians */
  int material, light, flip;
} elr_disk;

/* ObjectBegin ... ObjectEnd: a prototype (pbrt-v3's renderOptions->instances[name]) whose shapes are the
 * meshes and spheres with .object == its index, in its own space (the CTM at each Shape); ObjectInstance
 * places it with the CTM of that line (pbrt-v3's TransformedPrimitive). scene.c makes each prototype that
 * is instanced one Embree scene, and each instance an Embree instance of it: one copy of the geometry. */
typedef struct elr_sphere_set { /* user-geometry primID -> sphere; simd: elr_sphere_simd() */
  const struct elr_sphere *sph; const int *idx; int simd;
} elr_sphere_set;
typedef struct elr_object {
  int nmesh, nsph, ninstances;
  double lo[3], hi[3];        /* the bounds of its shapes, in its space */
  /* Embree (scene.c) */
  void *rtscene;
  int *geom_mesh;             /* per geometry id of its scene: the mesh, or -1 (the spheres) */
  unsigned ngeom, sphere_geom;
  int *sph_user;
  elr_sphere_set spheres;
} elr_object;
typedef struct elr_instance { int object; elr_xform xf; /* instance to world */ } elr_instance;

/* how an infinite light is sampled at a vertex whose lobes all reflect: the product of the map and the
 * clamped cosine (el_envlight_sample_li_cos), or the map alone (el_envlight_sample_li, pbrt-v3's) */
enum { ELR_ENVLS_PRODUCT = 0, ELR_ENVLS_MAP = 1 };
/* issue 20's per-lobe choice: with product sampling, a vertex whose glossy lobe has a Trowbridge-Reitz
 * alpha below this and no diffuse lobe (metal) samples the map alone under a sun map, the product around
 * wo's mirror direction otherwise (elr_bsdf_cos_normal; measured with bench/lobes.py) */
#define ELR_ENV_LOBE_ALPHA 0.1f
/* and a vertex whose lobes are diffuse or glossy with alpha at least this is estimated, by directlighting,
 * with the product light sample alone (no BSDF sample: elr_env_light_only) */
#define ELR_ENV_LIGHT_ALPHA 0.3f
/* a map whose brightest texels covering ELR_ENV_SUN_AREA of the sphere (about twice the sun's solid
 * angle) hold more than ELR_ENV_SUN_SHARE of its power is a sun map: there diffuse-only vertices take MIS,
 * never the light sample alone (render.c's elr__sun_share; city.hdr 0.219, studio.hdr 0.004: its lights
 * are larger) */
#define ELR_ENV_SUN_AREA 1e-5
#define ELR_ENV_SUN_SHARE 0.1f
/* how those diffuse-only vertices sample a sun map (elr_render_options.env_sun_diffuse, render's --env-sun-diffuse)
 * (ELR_ENVSD_SUNCOS: the map alone where the sun's axis is within acos(ELR_ENV_SUN_COS) of the vertex's normal,
 * the product with MIS elsewhere: elr_bsdf_cos_normal). Measured with bench/sun_rule.py (time to unit variance
 * against the map alone, 16 and 64 spp): the product with MIS everywhere wins where the sun is low or behind
 * the normal (sunrise.hdr's plane, the sun at cos 0.42: 2.3-2.5x; spheres' far sides, sunrise's shadows) and
 * loses where it is high (city.hdr's plane, cos 0.74: 0.82-0.91x; its shadows 0.69-0.73x), as the map alone
 * then sends the sun's share where the cosine is near its maximum and the product sample costs 1.3-1.4x;
 * the normal's test keeps both halves (bench_city 1.32-1.36x, was 0.88-0.97x; lobes_city unchanged).
 * Since the wave loop draws product samples in batches (el_envlight_sample_li_cos_n: 2.8-3.5x cheaper per
 * sample) the product with MIS everywhere (ELR_ENVSD_PRODUCT) is the default: bench/sun_rule.py, 6 seeds,
 * 16 spp, against the map alone (its default density), default sun rule -> product everywhere: bench_city
 * 1.58 -> 1.84x (the pixels the rule sent to the map 0.95 -> 1.10x), lobes_city 1.23 -> 1.35x, sun_shadow_object
 * 1.68 -> 1.70x, sun_porch 1.63 -> 1.66x, and sun_shadow_object with the sun raised to 80 degrees (10 from the
 * ground's normal) 1.08 -> 1.89x (per sample 1.07 -> 1.63x): the product sample now costs less than the
 * map's (le()'s patch density) and its cosine still helps where the sun is high */
/* ELR_ENVSD_TWO (issue 22's lit pixels, bench/ld_lit.py): directlighting spends the BSDF sample's numbers and ray
 * on a second product light sample (each weighted 1/2; elr_env_two), in both loops (render_wave.c draws it with the first) */
/* ELR_ENVSD_TWO_PIXEL: the same per pixel, chosen before its samples (integrator_direct.c's elr_two_pixel: the camera
 * ray through its centre and a shadow ray towards the sun's axis): the two samples where that ray misses the scene,
 * its hit sees the sun or has it below the geometric horizon, product MIS where the scene hides the sun */
enum { ELR_ENVSD_MAP = 0, ELR_ENVSD_PRODUCT = 1, ELR_ENVSD_ALONE = 2, ELR_ENVSD_SUNCOS = 3, ELR_ENVSD_TWO = 4, ELR_ENVSD_TWO_PIXEL = 5 };
#define ELR_ENV_SUN_COS 0.5f
#define ELR_ENV_SUN_DIFFUSE ELR_ENVSD_PRODUCT
enum { ELR_LIGHT_INFINITE = 0, ELR_LIGHT_POINT = 1, ELR_LIGHT_DISTANT = 2, ELR_LIGHT_AREA = 3 };
enum { ELR_SHAPE_MESH = 0, ELR_SHAPE_SPHERE = 1, ELR_SHAPE_DISK = 2 }; /* also elr_hit.kind */
typedef struct elr_light {
  int kind;
  elr_v3 L;          /* L * scale (point: I * scale; area: the emitted radiance Lemit) */
  elr_v3 pos, dir;   /* point: world position; distant: world direction towards the light */
  int nsamples;
  /* area: pbrt-v3's DiffuseAreaLight on one shape (a whole triangle mesh is one light, sampled by area
   * over its triangles); lights.c, and shapes.c for the shape's Sample and Pdf. Built before a render
   * that samples the light (elr_area_light_prepare): the area and, for a mesh, its area CDF. */
  int shape_kind, shape;   /* ELR_SHAPE_* and the index in s->mesh, s->sph or s->disk */
  int twosided;
  int prepared;
  double area;             /* world-space area */
  double *tri_cdf;         /* mesh: ntri + 1 cumulative triangle areas, tri_cdf[ntri] = area */
  int cone;                /* sphere under a similarity transform: sampled in the cone it subtends */
  elr_v3 center;           /* sphere: world centre; */
  float wradius;           /* and world radius (cone) */
  double det;              /* sphere (ellipsoid) and disk: |det| of the object-to-world 3x3 */
  elr_v3 n_disk;           /* disk: the world normal, oriented */
  double build_seconds;
  /* infinite: envlight.h's light (a constant L is a constant light); lights.c */
  el_envlight *env;        /* the radiance, as the scene gave it: le */
  el_envlight *env_sample; /* the density sample_li and pdf_li use: env, or env_alt */
  el_envlight *env_alt;    /* another density the render options asked for, or NULL */
  int le_same;             /* env_sample's le is env's, bit for bit (env itself, or env_alt over env's texels and matrix):
                            * an escaped ray's pdf and radiance then come from one el_envlight_pdf_li_cos_le_n call */
  int compensated, importance; /* the scene's density: EL_ENVLIGHT_IMPORTANCE_* */
  int importance_auto;         /* 1: the scene gave no "importance": BILINEAR under a sun (issue 22), else importance; 2: so chosen */
  int alt_compensated, alt_importance;
  int sampling;            /* the scene's "sampling": ELR_ENVLS_PRODUCT (the default) or ELR_ENVLS_MAP */
  int product;             /* this render: reflection-only vertices sample el_envlight_sample_li_cos */
  int has_map;
  int mapping;             /* infinite: EL_ENVLIGHT_MAPPING_* (pbrt-v4's "filename" with a square image: equal-area) */
  float *env_pixels;       /* infinite: the image env reads in place (options.no_copy), freed with the light */
  int bad_texels;          /* the scene's "badtexels": EL_ENVLIGHT_BAD_TEXELS_* (CLAMP_NEGATIVE by default) */
  /* pbrt-v4's "point3 portal" (issue 23): envlight.h's portal sampler, or NULL; with it sample_li and
   * pdf_li sample through the portals seen from the shading point (the map's sampling behind them) */
  el_envlight_portal *portal;
  float portal_share;      /* "float portalmapshare": the map's share of the light samples where a portal is seen */
  float *portal_points;    /* the portals' points (portal_count x 12 floats), to rebuild the tables when a */
  int portal_count, portal_compensated; /* render asks for another compensation (--compensated): the one built */
  /* sun.c (issue 22): the hot spots of env_sample (sun_hs_of), found by the first render that asked and kept
   * for the next ones, as the sampling tables are; freed with the light */
  struct el_envlight_hotspots *sun_hs;
  const el_envlight *sun_hs_of;
} elr_light;

/* LightSource "infinite" as the parser read it (pbrt-v4's LightSceneEntity: the parser describes, the
 * scene builds): scene.c's elr_scene_make_lights reads its image and makes envlight's light of it, in the
 * slot s->light[light] that the parser filled with the light's kind and options. */
typedef struct elr_infinite_desc {
  int light;                /* its index in s->light */
  char *path;               /* "mapname" or "filename", resolved; NULL: a constant light */
  int v4_filename;          /* given as pbrt-v4's "filename" (a square image is then an equal-area map) */
  float scale[3];           /* L times scale */
  float l2w[9];             /* light to world: the CTM's rotation */
  float *portal;            /* pbrt-v4's "point3 portal": nportal rectangles of 4 world-space points */
  int nportal;
  char *file; int line;     /* the directive, for messages; */
  char *filename_file; int filename_line; /* the "filename" parameter's place, */
  char *portal_file; int portal_line;     /* and the portal's */
} elr_infinite_desc;

/* Texture "imagemap" as the parser read it: scene.c's elr_scene_make_textures reads the image and makes
 * the MIP map of texture s->tex[tex] (pbrt-v3's ImageTexture constructor, after the parse) */
typedef struct elr_imagemap_desc {
  int tex;                  /* its index in s->tex */
  char *path, *name;        /* the image (resolved) and the texture's name, for messages */
  int gamma, is_float;      /* sRGB-decode 8-bit images; a float texture (luminance) */
  float scale, maxaniso;
  int filter, wrap;         /* el_mipmap_filter, el_mipmap_wrap */
  char *file; int line;     /* the directive */
} elr_imagemap_desc;

typedef struct elr_scene_desc {
  /* camera */
  elr_xform cam2world;
  float fov, frameaspect, screen[4];
  int has_screen, has_frameaspect;
  /* film */
  int xres, yres;
  float crop[4];
  char filename[1024];
  elr_filter_desc filter;
  /* sampler */
  int sampler, spp, xs, ys, jitter, dims;
  int randomize, has_seed; /* sobol, zsobol, paddedsobol: "string randomization", "integer seed" */
  int64_t sseed;
  /* integrator */
  int integrator_path, maxdepth, light_sampling;
  float rrthreshold;
  int direct_one;     /* directlighting: pbrt-v3's "strategy" "one" (else "all") */
  int split_auto;     /* directlighting: envlight's "splitting" "auto" (1) or "off" (0): render.c's pilot */
  int light_strategy; /* path: pbrt-v3's "lightsamplestrategy" (ELR_LSTRAT_*) */
} elr_scene_desc;

struct elr_scene {
  elr_scene_desc d;
  elr_texture *tex; int ntex, captex;
  elr_material *mat; int nmat, capmat;
  elr_mesh *mesh; int nmesh, capmesh;
  elr_sphere *sph; int nsph, capsph;
  elr_disk *disk; int ndisk, capdisk;
  elr_light *light; int nlight, caplight;
  elr_object *obj; int nobj, capobj;
  elr_instance *inst; int ninst, capinst;
  elr_infinite_desc *envdesc; int nenvdesc, capenvdesc; /* api_lights.c's infinite lights, for elr_scene_make_lights */
  elr_imagemap_desc *texdesc; int ntexdesc, captexdesc; /* api_materials.c's image textures, for elr_scene_make_textures */
  int warnings;
  /* issue 20: where the environment is product-sampled, vertices with a glossy lobe of Trowbridge-Reitz
   * alpha below this and no diffuse lobe sample the map alone under a sun (elr_bsdf.env_map), else the
   * product around wo's mirror direction (elr_bsdf.env_mirror); 0 never (set by elr_render) */
  float env_lobe_alpha;
  /* and vertices whose glossy lobes (if any) all have alpha >= this take directlighting's product light
   * sample alone, without the BSDF sample (elr_bsdf.env_light_only; INFINITY never) */
  float env_light_alpha;
  /* and under a sun (elr__sun_share > ELR_ENV_SUN_SHARE) vertices with only diffuse lobes take MIS: the map alone
   * where the sun is near their normal, the product elsewhere (env_sun_diffuse) */
  int env_sunny;
  int env_sun_diffuse; /* ELR_ENVSD_*: how they do (ELR_ENV_SUN_DIFFUSE unless render's options say) */
  elr_v3 env_sun_axis; float env_sun_cos; /* ELR_ENVSD_SUNCOS: the brightest texel's direction (world), the threshold */
  float env_sun_share;
  char last_warning[512];
  int quiet;
  double t_parse, t_images, t_embree;
  size_t bytes_textures, bytes_embree;
  /* Embree */
  void *device, *rtscene;
  unsigned *geom_kind;  /* per Embree geometry id: 0 mesh, 1 spheres, 2 an instance (geom_index: which), 3 the disks */
  int *geom_index;
  unsigned ngeom;
  unsigned sphere_geom; /* geometry id of the sphere user geometry, or ~0u */
  unsigned disk_geom;   /* geometry id of the disk user geometry (primID = disk index), or ~0u */
  unsigned builtin_geom; /* geometry id of Embree's sphere primitives (similarity transforms), or ~0u */
  int *sph_builtin, *sph_user, nbuiltin, nuser; /* primID -> sphere index */
  elr_sphere_set world_spheres; /* the user geometry's data: sph, sph_user */
  float world_radius;
  elr_v3 world_center;
  int *mat_textured; /* per material: 1 when a texture varies over the surface (needs uv) */
  int any_textured;
};

int elr_parse(elr_scene *s, const char *text, size_t len, const char *name, const char *base_dir,
              char *err, size_t errlen);
void elr_warn(elr_scene *s, const char *file, int line, const char *fmt, ...);
int elr_ply_load(const char *path, elr_mesh *m, char *err, size_t errlen); /* ply.c */
/* imageio.c: the scene's images (pbrt-v3's ReadImage): el_image_load with a size check (-1 with why), and
 * the image as linear RGB times scale (NULL: out of memory, *bad = -1; or texel *bad is NaN, infinite or
 * overflows when scaled, its value *bad_value) */
struct el_image;
int elr_image_read(const char *path, struct el_image *img, char *why, size_t n);
float *elr_image_rgb(const struct el_image *img, int gamma, float scale, int64_t *bad, float *bad_value);
/* parser.c's messages: "file:line: error: ..." into err (control characters of the scene's strings
 * replaced), and warnings (elr_warn, above) */
void elr_error(char *err, size_t errlen, const char *file, int line, const char *fmt, ...);
/* loopsubdiv.c: pbrt-v3's LoopSubdivide of the control mesh (indices in [0, npoints), P: 3 npoints) into
 * out (object space: idx, p, n); *dropped: triangles that repeat a vertex, left out. -1 with err. */
int elr_loop_subdivide(int levels, const int *indices, int nindices, const double *P, int npoints, elr_mesh *out, int *dropped,
                       char *err, size_t errlen);
/* scene.c: the lights and image textures the parser described (elr_infinite_desc, elr_imagemap_desc), then
 * the Embree scene */
int elr_scene_make_lights(elr_scene *s, char *err, size_t errlen);
int elr_scene_make_textures(elr_scene *s, char *err, size_t errlen);
int elr_scene_build(elr_scene *s, char *err, size_t errlen); /* Embree (scene.c) */
void elr_scene_release(elr_scene *s);

/* >> intersection (scene.c: Embree; shapes.c: each shape's hit record and parameterisation) */
/* a ray with pbrt-v3's RayDifferential (has_diff: rx and ry, the rays through the next pixels) */
typedef struct elr_ray { elr_v3 o, d; int has_diff; elr_v3 rxo, rxd, ryo, ryd; } elr_ray;
typedef struct elr_hit {
  float t;
  elr_v3 p, ng, ns;    /* ng, ns unit; ns on the side of ng */
  elr_v3 dpdu, dpdv, dndu, dndv;
  float u, v;          /* texture coordinates */
  int material;
  float eps;           /* offset for spawned rays */
  int light;           /* the area light of the shape hit (an index in s->light), or -1 */
  /* for elr_hit_uv */
  int kind, mesh, has_uv; /* kind ELR_SHAPE_*: 0 triangle, 1 sphere, 2 disk */
  int flip;               /* the shape's flip (ReverseOrientation xor a mirroring transform): ng, ns and, from
                             elr_hit_uv, dndu and dndv above are already turned */
  int inst;               /* -1, or the instance (elr_instance) whose prototype's shape was hit: the shape's
                             data are in the prototype's space, the hit record in world space */
  unsigned prim;
  float b1, b2;
  elr_v3 pobj;
} elr_hit;
void elr_hit_uv(const elr_scene *s, elr_hit *h); /* u, v, dpdu, dpdv, dndu, dndv (textures, differentials) */
/* shapes.c: the hit records, and the sphere as Embree's user geometry */
void elr_sphere_hit(const elr_scene *s, int si, elr_v3 o, elr_v3 d, elr_hit *h);
void elr_triangle_hit(const elr_scene *s, int mesh, unsigned tri, float b1, float b2, elr_hit *h);
struct RTCBoundsFunctionArguments;
struct RTCIntersectFunctionNArguments;
struct RTCOccludedFunctionNArguments;
void elr_sphere_prepare(elr_sphere *sp); /* w2o and r2, before Embree's build (scene.c) */
/* the sphere callbacks' intersection of rays i0 .. i0 + 15 of N in Embree's RTCRayN layout (valid[i]
 * -1: a ray to answer) with vectors of width simd (0 none, 1 SSE2, 2 AVX; at most elr_sphere_simd()):
 * the bits of the rays that hit (bit i - i0), with t[i - i0] (the same t for every width) */
unsigned elr_sphere_hit_rays(const elr_sphere *sp, int simd, const float *ray, unsigned N, unsigned i0, const int *valid, float t[16]);
int elr_sphere_simd(void); /* the widest this CPU runs (or the environment's ELR_SPHERE_SIMD when lower) */
void elr_sphere_bounds(const struct RTCBoundsFunctionArguments *a);
void elr_sphere_intersect(const struct RTCIntersectFunctionNArguments *a);
void elr_sphere_occluded(const struct RTCOccludedFunctionNArguments *a);
void elr_disk_hit(const elr_scene *s, int di, elr_v3 o, elr_v3 d, elr_hit *h);
void elr_disk_bounds(const struct RTCBoundsFunctionArguments *a);
void elr_disk_intersect(const struct RTCIntersectFunctionNArguments *a);
void elr_disk_occluded(const struct RTCOccludedFunctionNArguments *a);
/* shapes.c: a point on an area light's shape (pbrt-v3's Shape::Sample(ref, u)) with its normal and its
 * solid-angle density seen from ref (0 when it cannot be used), and that density for the point lh where
 * a ray from ref reached the shape (Shape::Pdf(ref, wi), which intersects the ray itself; the
 * integrators have the hit already). elr_shape_prepare computes the area and a mesh's area CDF. */
void elr_shape_sample(const elr_scene *s, const elr_light *l, elr_v3 ref, const float u[2], elr_v3 *p, elr_v3 *n, float *pdf);
float elr_shape_pdf(const elr_scene *s, const elr_light *l, elr_v3 ref, const elr_hit *lh);
int elr_shape_prepare(const elr_scene *s, elr_light *l, int build_cdf);
int elr_intersect(const elr_scene *s, elr_v3 o, elr_v3 d, float tmax, elr_hit *h);
int elr_occluded(const elr_scene *s, elr_v3 o, elr_v3 d, float tmax);
void elr_raw_intersect(const elr_scene *s, elr_v3 o, elr_v3 d, float *t, unsigned *geom); /* no shading */
/* a wave of rays in structure-of-arrays form (Embree's RTCRayHitNp), traced by one call (scene.c; the
 * wave loop render_wave.c). Shadow rays: tfar < 0 after elr_wave_occluded when something is in the way. */
#define ELR_WAVE_RAYS 512 /* rays in a wave at most */
#define ELR_WAVE_CHUNK 64 /* rays per rtcIntersect1M / rtcOccluded1M stream */
enum { ELR_WAVE_API_SINGLE = 0, ELR_WAVE_API_PACKET16 = 1, ELR_WAVE_API_STREAM = 2, ELR_WAVE_API_SOA = 3 };
#define ELR_WAVE_API_DEFAULT ELR_WAVE_API_PACKET16 /* the fastest measured (bench_render) */
typedef struct elr_wave_rays {
  int n;
  float ox[ELR_WAVE_RAYS], oy[ELR_WAVE_RAYS], oz[ELR_WAVE_RAYS], tnear[ELR_WAVE_RAYS];
  float dx[ELR_WAVE_RAYS], dy[ELR_WAVE_RAYS], dz[ELR_WAVE_RAYS], time[ELR_WAVE_RAYS], tfar[ELR_WAVE_RAYS];
  unsigned mask[ELR_WAVE_RAYS], id[ELR_WAVE_RAYS], flags[ELR_WAVE_RAYS];
  float ngx[ELR_WAVE_RAYS], ngy[ELR_WAVE_RAYS], ngz[ELR_WAVE_RAYS], u[ELR_WAVE_RAYS], v[ELR_WAVE_RAYS];
  unsigned prim[ELR_WAVE_RAYS], geom[ELR_WAVE_RAYS], inst[ELR_WAVE_RAYS];
} elr_wave_rays;
/* the fields of every ray of w that elr_wave_add leaves as they are: tnear and time 0, mask ~0, id its
 * index, flags 0 (once, before the first elr_wave_add) */
void elr_wave_rays_init(elr_wave_rays *w);
/* ray n of the wave (inline: the wave loop adds a few rays per camera sample); geom and inst
 * RTC_INVALID_GEOMETRY_ID (~0u), as a miss leaves them */
static inline void elr_wave_add(elr_wave_rays *w, elr_v3 o, elr_v3 d, float tmax) {
  int i = w->n++;
  w->ox[i] = o.x; w->oy[i] = o.y; w->oz[i] = o.z;
  w->dx[i] = d.x; w->dy[i] = d.y; w->dz[i] = d.z;
  w->tfar[i] = tmax; w->geom[i] = w->inst[i] = ~0u;
}
void elr_wave_intersect(const elr_scene *s, elr_wave_rays *w, int api, int coherent);
void elr_wave_occluded(const elr_scene *s, elr_wave_rays *w, int api, int coherent);
int elr_wave_hit(const elr_scene *s, const elr_wave_rays *w, int i, elr_hit *h); /* 0: ray i left the scene */
/* the origin of a ray leaving h in direction d: offset along the geometric normal to the side d goes
 * (pbrt-v3's OffsetRayOrigin, with a fixed relative epsilon instead of its error bounds) */
static inline elr_v3 elr_spawn_origin(const elr_hit *h, elr_v3 d) {
  return elr_add(h->p, elr_mul(h->ng, elr_dot(d, h->ng) >= 0.f ? h->eps : -h->eps));
}

/* >> textures (textures.c), materials (materials.c) and BSDFs (reflection.c) */
typedef struct elr_tex_ctx { /* where textures are evaluated: (u, v) and its screen-space derivatives */
  float u, v, dudx, dudy, dvdx, dvdy;
} elr_tex_ctx;
elr_v3 elr_tex_eval(const elr_scene *s, int tex, const elr_tex_ctx *c);

/* pbrt-v3's BxDFType flags and the BxDFs of core/reflection.h that the materials use (reflection.c) */
enum { ELR_BSDF_REFLECTION = 1, ELR_BSDF_TRANSMISSION = 2, ELR_BSDF_DIFFUSE = 4, ELR_BSDF_GLOSSY = 8, ELR_BSDF_SPECULAR = 16,
       ELR_BSDF_ALL = 31 };
enum { ELR_BXDF_LAMBERTIAN = 0, ELR_BXDF_SPECULAR_REFLECTION, ELR_BXDF_SPECULAR_TRANSMISSION, ELR_BXDF_FRESNEL_SPECULAR,
       ELR_BXDF_MICROFACET_REFLECTION, ELR_BXDF_MICROFACET_TRANSMISSION, ELR_BXDF_FRESNEL_BLEND,
       ELR_BXDF_OREN_NAYAR /* matte of sigma > 0: R, and A and B in ax, ay */ };
enum { ELR_FRESNEL_NOOP = 0, ELR_FRESNEL_DIELECTRIC, ELR_FRESNEL_CONDUCTOR };
typedef struct elr_bxdf {
  int type, flags, fresnel; /* ELR_BXDF_*, ELR_BSDF_* flags, the Fresnel term of a reflection (ELR_FRESNEL_*) */
  elr_v3 R, T;              /* the reflection and transmission scales; FresnelBlend: R = Rd, T = Rs */
  float ax, ay;             /* Trowbridge-Reitz alphas (microfacet lobes, FresnelBlend) */
  float eta_a, eta_b;       /* dielectric Fresnel: etaI, etaT; transmission: etaA outside, etaB inside */
  elr_v3 eta, k;            /* conductor Fresnel: eta and k of the metal (etaI 1) */
} elr_bxdf;
#define ELR_MAX_BXDFS 6

/* A BSDF in the shading frame. matte, mirror and plastic use the fixed lobes (up to one diffuse, one
 * glossy and one specular reflection; nlobes = 0); glass, metal, uber and substrate a list of pbrt-v3's
 * BxDFs (nlobes > 0), in a frame around the shading normal turned as pbrt-v3 orients it (the side a
 * dielectric calls outside). spec_r, spec_t: a specular reflection, a specular transmission lobe exists
 * (the direct-lighting integrator follows them); eta: pbrt-v3's BSDF::eta, the relative index of
 * refraction of the inside (1 for materials that do not refract). */
typedef struct elr_bsdf {
  elr_v3 ns, ss, ts, ng;
  elr_v3 kd, ks, kr;
  float alpha;
  int has_diffuse, has_glossy, has_specular, ncomp;
  int spec_r, spec_t, nlobes;
  float eta;
  int env_mirror; /* a peaked glossy lobe under a map without a sun: product sampling around wo's mirror direction
                     (elr_bsdf_cos_normal), with MIS against the BSDF sample */
  int env_map; /* a glossy lobe peaked enough that the environment's map alone samples this vertex (elr_bsdf_cos_normal) */
  int env_light_only; /* no lobe narrower than the scene's env_light_alpha: directlighting's product light sample
                         alone estimates the environment here (elr_env_light_only) */
  int env_two;      /* ELR_ENVSD_TWO at a diffuse-only vertex under a sun: two product light samples (elr_env_two) */
  int env_sun_test; /* ELR_ENVSD_SUNCOS at a diffuse-only vertex under a sun: elr_bsdf_cos_normal chooses the map
                       alone where its normal is within acos(env_sun_cos) of env_sun_axis */
  elr_v3 env_sun_axis; float env_sun_cos;
  elr_bxdf lobe[ELR_MAX_BXDFS];
} elr_bsdf;
void elr_bsdf_init(const elr_scene *s, const elr_hit *h, const elr_tex_ctx *c, elr_bsdf *b);
/* a material whose BSDF is the same at every hit but for its frame (constant textures, no anisotropic
 * lobe): 1 and its BSDF t, else 0 (materials.c; render_wave.c makes a hit's BSDF from t by a copy and
 * the frame) */
int elr_bsdf_constant(const elr_scene *s, int mi, elr_bsdf *t);
elr_v3 elr_bsdf_f(const elr_bsdf *b, elr_v3 wo, elr_v3 wi);
float elr_bsdf_pdf(const elr_bsdf *b, elr_v3 wo, elr_v3 wi);
/* Returns f; *specular is 0 when the sampled lobe was not specular, 1 for a specular reflection, 2 for a
 * specular transmission. */
elr_v3 elr_bsdf_sample(const elr_bsdf *b, elr_v3 wo, float u0, float u1, elr_v3 *wi, float *pdf, int *specular);
/* f and pdf of a BSDF of no lobe list and no glossy lobe (elr_bsdf_f and elr_bsdf_pdf there: Lambertian
 * alone needs no local frame), and elr_bsdf_f and elr_bsdf_pdf with that case inline (the wave loop) */
static inline elr_v3 elr_bsdf_lambert_f(const elr_bsdf *b, elr_v3 woW, elr_v3 wiW) {
  int reflect = elr_dot(wiW, b->ng) * elr_dot(woW, b->ng) > 0.f;
  return reflect && b->has_diffuse && elr_dot(woW, b->ns) != 0.f ? elr_mul(b->kd, ELR_INV_PI) : elr_v(0, 0, 0);
}
static inline float elr_bsdf_lambert_pdf(const elr_bsdf *b, elr_v3 woW, elr_v3 wiW) {
  float co = elr_dot(woW, b->ns), ci = elr_dot(wiW, b->ns);
  return b->has_diffuse && co * ci > 0.f ? fabsf(ci) * ELR_INV_PI / (float)b->ncomp : 0.f;
}
/* both, with the dot products they share computed once (the same floats as the two calls) */
static inline elr_v3 elr_bsdf_f_pdf_inl(const elr_bsdf *b, elr_v3 wo, elr_v3 wi, float *pdf) {
  float co, ci;
  if (b->nlobes || b->has_glossy) { *pdf = elr_bsdf_pdf(b, wo, wi); return elr_bsdf_f(b, wo, wi); }
  co = elr_dot(wo, b->ns); ci = elr_dot(wi, b->ns);
  *pdf = b->has_diffuse && co * ci > 0.f ? fabsf(ci) * ELR_INV_PI / (float)b->ncomp : 0.f;
  return elr_dot(wi, b->ng) * elr_dot(wo, b->ng) > 0.f && b->has_diffuse && co != 0.f ? elr_mul(b->kd, ELR_INV_PI) : elr_v(0, 0, 0);
}
static inline elr_v3 elr_bsdf_f_inl(const elr_bsdf *b, elr_v3 wo, elr_v3 wi) {
  return b->nlobes || b->has_glossy ? elr_bsdf_f(b, wo, wi) : elr_bsdf_lambert_f(b, wo, wi);
}
static inline float elr_bsdf_pdf_inl(const elr_bsdf *b, elr_v3 wo, elr_v3 wi) {
  return b->nlobes || b->has_glossy ? elr_bsdf_pdf(b, wo, wi) : elr_bsdf_lambert_pdf(b, wo, wi);
}
/* a direction of the shading frame in world space */
static inline elr_v3 elr_bsdf_to_world(const elr_bsdf *b, elr_v3 v) {
  return elr_add(elr_add(elr_mul(b->ss, v.x), elr_mul(b->ts, v.y)), elr_mul(b->ns, v.z));
}
/* <<Cosine-sample the hemisphere, flipping the direction if necessary>> (concentric disk) for the fixed
 * lobes (z from r^2 (cos^2 + sin^2), as they always computed it; the clamp is fmaxf(0, z^2)'s value,
 * NaN to 0, without its libm call) */
static inline elr_v3 elr_bsdf_fixed_cosine_sample(float woz, float u0, float u1) {
  float ox = 2.f * u0 - 1.f, oy = 2.f * u1 - 1.f, r, th, z2;
  elr_v3 wi;
  if (ox == 0.f && oy == 0.f) { r = 0.f; th = 0.f; }
  else if (fabsf(ox) > fabsf(oy)) { r = ox; th = (ELR_PI / 4.f) * (oy / ox); }
  else { r = oy; th = ELR_PI / 2.f - (ELR_PI / 4.f) * (ox / oy); }
  z2 = 1.f - r * r * (cosf(th) * cosf(th) + sinf(th) * sinf(th));
  wi = elr_v(r * cosf(th), r * sinf(th), sqrtf(z2 > 0.f ? z2 : 0.f));
  if (woz < 0.f) wi.z = -wi.z;
  return wi;
}
/* elr_bsdf_sample of a Lambertian lobe alone (matte) and u0 in [0, 1): its general steps where the
 * component is 0 and u0 stays as it is, with wo.z alone of the local wo (the same floats); inline, and
 * elr_bsdf_sample_inl with it (the wave loop) */
static inline int elr_bsdf_lambert_alone(const elr_bsdf *b, float u0) {
  return b->ncomp == 1 && b->has_diffuse && !b->nlobes && u0 >= 0.f && u0 < 1.f;
}
static inline elr_v3 elr_bsdf_lambert_sample(const elr_bsdf *b, elr_v3 woW, float u0, float u1, elr_v3 *wiW, float *pdf, int *specular) {
  /* (the results into locals, stored at the end, so that the store through wiW does not make the compiler read b's
   * fields and redo the dot products with wo; issue 21) */
  float woz = elr_dot(woW, b->ns), p;
  elr_v3 wi, f;
  if (woz == 0.f) { *pdf = 0.f; *specular = 0; return elr_v(0, 0, 0); }
  wi = elr_bsdf_to_world(b, elr_bsdf_fixed_cosine_sample(woz, u0, u1));
  f = elr_bsdf_lambert_f(b, woW, wi);
  p = elr_bsdf_lambert_pdf(b, woW, wi);
  *pdf = p; *wiW = wi; *specular = 0;
  return f;
}
static inline elr_v3 elr_bsdf_sample_inl(const elr_bsdf *b, elr_v3 wo, float u0, float u1, elr_v3 *wi, float *pdf, int *specular) {
  return elr_bsdf_lambert_alone(b, u0) ? elr_bsdf_lambert_sample(b, wo, u0, u1, wi, pdf, specular) : elr_bsdf_sample(b, wo, u0, u1, wi, pdf, specular);
}
/* pbrt-v3's BSDF::Sample_f restricted to the lobes whose flags all lie in `type` (ELR_BSDF_*): the
 * direct-lighting integrator's specular reflection and transmission; *flags: the sampled lobe's */
elr_v3 elr_bsdf_sample_type(const elr_bsdf *b, elr_v3 wo, float u0, float u1, int type, elr_v3 *wi, float *pdf, int *flags);
/* The normal whose clamped cosine product sampling of the environment weights at this vertex (seen
 * from wo): the GEOMETRIC normal ng turned to wo's side. Every reflection lobe's f is 0 unless wi is on
 * wo's side of ng (pbrt-v3's BSDF::f tests reflect = (wi.ng)(wo.ng) > 0; Lambertian then reflects even
 * below the shading hemisphere), so max(0, n.wi) > 0 wherever f |wi.ns| > 0 and light sampling alone
 * stays unbiased; with the shading normal it would miss that sliver of smooth-shaded meshes (ns = ng on
 * spheres, disks and flat triangles). Returns 0 (sample the map alone) when a non-specular lobe
 * transmits (rough glass): its light comes from both sides. Light sample and BSDF sample's MIS weight
 * use the same normal, and the path tracer keeps it for its continuation ray (elr_path_state.prev_n).
 * Returns 0 too where a glossy lobe is peaked (b->env_map, set by elr_bsdf_init: its Trowbridge-Reitz
 * alpha below the scene's env_lobe_alpha, no diffuse lobe): there the product of the map and the cosine follows the
 * lobe no better than the map does and costs more (issue 20, bench/lobes.py); that is, under a sun map
 * (elr_scene.env_sunny). Under other maps such a lobe (b->env_mirror, no diffuse lobe) gets wo's mirror
 * direction about ns in place of the normal: the product of the map and the clamped cosine around the
 * mirror direction, a broad proxy of the lobe that MIS with the BSDF sample (which covers the whole
 * lobe) keeps unbiased; never taken alone (elr_env_light_only is 0 there: that needs the normal's
 * cosine, positive wherever f is). */
static inline int elr_bsdf_cos_normal(const elr_bsdf *b, elr_v3 wo, elr_v3 *n) {
  int i;
  if (b->env_map) return 0; /* issue 20's per-lobe choice: a peaked glossy lobe (elr_bsdf_lobe_alpha) */
  for (i = 0; i < b->nlobes; i++)
    if ((b->lobe[i].flags & ELR_BSDF_TRANSMISSION) && !(b->lobe[i].flags & ELR_BSDF_SPECULAR)) return 0;
  if (b->env_mirror) { *n = elr_sub(elr_mul(b->ns, 2.f * elr_dot(wo, b->ns)), wo); return 1; } /* (any length: only its direction counts) */
  *n = elr_dot(wo, b->ng) < 0.f ? elr_mul(b->ng, -1.f) : b->ng;
  if (b->env_sun_test && elr_dot(*n, b->env_sun_axis) >= b->env_sun_cos) return 0; /* (the sun high above: the map alone) */
  return 1;
}
/* Issue 20's per-lobe choice, second half: whether EstimateDirect at this vertex (BSDF b, product-sampling
 * normal found: has_n) takes the environment's product light sample alone, with weight 1 and no BSDF
 * sample. Where the lobes are diffuse or broad (b->env_light_only) the product of the map and the cosine
 * is close to the integrand and the BSDF sample's ray and pdf_li_cos cost more than they reduce the
 * variance (bench/lobes.py). Unbiased as light sampling alone is (the product density is positive
 * wherever f |ns.wi| is). Only where the BSDF sample would be MIS's partner of this light sample alone
 * (sample_bsdf: directlighting; the path tracer's continuation is its BSDF sample either way). Not
 * with the compensated density (max(L - mean, 0): unbiased only together with the BSDF sample). */
static inline int elr_env_light_only(int ls_mis, int sample_bsdf, const elr_light *l, int has_n, const elr_bsdf *b) {
  return ls_mis && sample_bsdf && has_n && l->kind == ELR_LIGHT_INFINITE && l->product && b->env_light_only && !l->env_sample->compensated;
}
/* ELR_ENVSD_TWO: where the product light sample would be MIS's partner of a BSDF sample at a diffuse-only
 * vertex under a sun map (directlighting), a second product light sample takes the BSDF sample's numbers
 * instead, both weighted 1/2: unbiased as the light sample alone (the same conditions) */
static inline int elr_env_two(int ls_mis, int sample_bsdf, const elr_light *l, int has_n, const elr_bsdf *b) {
  return ls_mis && sample_bsdf && has_n && l->kind == ELR_LIGHT_INFINITE && l->product && b->env_two && !l->env_sample->compensated;
}
/* The path tracer too (issue 22): UniformSampleOneLight's BSDF draw, which its continuation ray leaves unused,
 * gives the second product light sample (elr_estimate_direct with sample_bsdf 0), and the continuation ray that
 * leaves the scene from such a vertex takes weight 0 for that light (elr_path_state.prev_two: the vertex's part,
 * elr_path_two; elr_env_two_light the light's). Unbiased as above: light l's sample alone there, no MIS. */
static inline int elr_env_two_light(const elr_light *l) {
  return l->kind == ELR_LIGHT_INFINITE && l->product && !l->env_sample->compensated;
}
/* a BSDF of pbrt-v3's BxDF list: the frame (unit ns and ng), then lobes added (NULL when full) */
void elr_bsdf_begin(elr_bsdf *b, elr_v3 ns, elr_v3 ng, float eta);
elr_bxdf *elr_bsdf_add(elr_bsdf *b, int type);
float elr_roughness_to_alpha(float r);
/* the Trowbridge-Reitz alpha of the BSDF's most peaked glossy reflection lobe (sqrt(ax ay) when
 * anisotropic; INFINITY without a glossy lobe): what the per-lobe choice of the environment's sampling
 * compares with the scene's env_lobe_alpha */
float elr_bsdf_lobe_alpha(const elr_bsdf *b);
/* pbrt-v3's FrDielectric (cos_i signed: below the surface, the indices swap) and FrConductor (etaI 1) */
float elr_fr_dielectric(float cos_i, float eta_i, float eta_t);
elr_v3 elr_fr_conductor(float cos_i, elr_v3 eta, elr_v3 k);

/* >> ray differentials at a hit (interaction.c): the texture footprint; the radiance a hit emits */
void elr_compute_differentials(const elr_scene *s, const elr_ray *r, elr_hit *h, elr_tex_ctx *c, elr_v3 *dpdx, elr_v3 *dpdy);
/* pbrt-v3's SurfaceInteraction::Le: the radiance the hit's area light (if any) emits towards w */
elr_v3 elr_hit_le(const elr_scene *s, const elr_hit *h, elr_v3 w);

/* >> lights (lights.c): pbrt-v3's Light interface for point, distant, infinite and area lights */
/* pbrt-v3's Sample_Li results with its VisibilityTester: the radiance arriving at the shading point
 * from the light sample, the unit direction towards it, its solid-angle density (1 for delta lights),
 * and where the shadow ray ends (at p_light when at_point: 1 a point light, 2 a point on an area light;
 * else after dist: INFINITY for the environment) */
typedef struct elr_light_sample {
  elr_v3 L, wi;
  float pdf;
  elr_v3 p_light;
  float dist;
  int at_point;
  int portal; /* an infinite light with portals: 1 sampled through them, 0 the map's fallback; else -1 */
} elr_light_sample;
static inline int elr_light_emits(const elr_light *l) { return elr_maxc(l->L) > 0.f; }
static inline int elr_light_is_delta(const elr_light *l) { return l->kind == ELR_LIGHT_POINT || l->kind == ELR_LIGHT_DISTANT; }
/* n: the vertex's product-sampling normal (elr_bsdf_cos_normal), or NULL where the BSDF transmits; an
 * infinite light with product = 1 then samples the map times max(0, n.wi), and pdf_li is that density */
void elr_light_sample_li(const elr_light *l, const elr_scene *s, elr_v3 p, const elr_v3 *n, const float u[2], elr_light_sample *ls);
float elr_light_pdf_li(const elr_light *l, const elr_v3 *n, elr_v3 wi);
/* the same at shading point p: with portals the density depends on it (elr_light_pdf_li then gives the
 * map's own density: only the loops that never meet a portal light call it) */
float elr_light_pdf_li_at(const elr_light *l, elr_v3 p, const elr_v3 *n, elr_v3 wi);
/* pbrt-v4's portals of an infinite light with a map: count rectangles of 4 world-space points (12 floats
 * each, pbrt-v4's vertex order); -1 with err naming the problem */
int elr_infinite_set_portals(elr_light *l, const float *pts, int count, char *err, size_t errlen);
elr_v3 elr_light_le(const elr_light *l, elr_v3 dir);
int elr_infinite_init(elr_light *l, const float *rgb, int w, int h, const float scale[3], const float l2w[9], char *err,
                      size_t errlen);
int elr_infinite_prepare(elr_light *l, int compensated, int importance, int product, int need_map);
void elr_light_prefetch(const elr_light *l, elr_v3 wi);
void elr_light_free(elr_light *l);
/* area lights: pbrt-v3's DiffuseAreaLight::L (the radiance leaving a point of normal n towards w) */
static inline elr_v3 elr_area_light_L(const elr_light *l, elr_v3 n, elr_v3 w) {
  return l->twosided || elr_dot(n, w) > 0.f ? l->L : elr_v(0, 0, 0);
}
/* Pdf_Li of an area light for the ray from ref that reached it at lh (see elr_shape_pdf) */
float elr_area_light_pdf(const elr_scene *s, const elr_light *l, elr_v3 ref, const elr_hit *lh);
int elr_area_light_prepare(const elr_scene *s, elr_light *l, int build_cdf); /* -1: out of memory */
/* pbrt-v3's Light::Power, its luminance (RGBSpectrum::y): the "power" light sample strategy's weight */
double elr_light_power(const elr_scene *s, const elr_light *l);

/* >> light selection (lightdistrib.c): pbrt-v3's LightDistribution (core/lightdistrib.cpp) */
enum { ELR_LSTRAT_UNIFORM = 0, ELR_LSTRAT_POWER = 1, ELR_LSTRAT_SPATIAL = 2 };
typedef struct elr_light_distrib {
  int n;               /* the emitting lights it chooses among */
  int *index;          /* their indices in s->light */
  el_distribution1d d; /* pbrt-v3's Distribution1D over them, built only when n > 1 */
  float *pick;         /* per light of the scene: the probability that it is chosen (0: never) */
  int strategy;        /* ELR_LSTRAT_UNIFORM or ELR_LSTRAT_POWER */
  size_t bytes;
  double seconds;
} elr_light_distrib;
int elr_light_distrib_init(elr_light_distrib *D, const elr_scene *s, int strategy);
void elr_light_distrib_free(elr_light_distrib *D);
/* the light chosen by u (D->n > 1; with one light it is that light and no number is needed) */
static inline const elr_light *elr_light_distrib_sample(const elr_light_distrib *D, const elr_scene *s, float u, float *pick) {
  int k = D->n > 1 ? el_distribution1d_sample_discrete(&D->d, u, NULL, NULL) : 0;
  *pick = D->pick[D->index[k]];
  return &s->light[D->index[k]];
}

/* >> spectra (spectrum.c): pbrt-v3's spectral parameter values as RGB (its RGBSpectrum build) */
void elr_xyz_to_rgb(const double xyz[3], double rgb[3]);                                    /* XYZToRGB */
void elr_spectrum_from_sampled(const double *lambda, const double *v, int n, double rgb[3]); /* FromSampled */
void elr_blackbody(const double *lambda, int n, double T, double *Le);                       /* Blackbody */
void elr_blackbody_rgb(double T, double rgb[3]); /* FromSampled(BlackbodyNormalized(T)): a "blackbody" value of scale 1 */
int elr_float_file_parse(const char *text, size_t len, double *vals, int cap, int *bad_line); /* ReadFloatFile */

/* >> camera (camera.c): pbrt-v3's PerspectiveCamera */
typedef struct elr_camera {
  elr_v3 o, x, y, z;               /* origin and the images of the camera's axes, world space */
  float sx0, sx1, sy0, sy1;        /* the screen window */
  float tanhalf;                   /* tan(fov / 2) */
  int xres, yres;
  float diff_scale;                /* 1 / sqrt(spp) */
  int differentials;               /* rays carry differentials (some texture filters over them) */
} elr_camera;
void elr_camera_init(elr_camera *C, const elr_scene_desc *d, int spp, int differentials);
void elr_camera_ray(const elr_camera *C, float fx, float fy, elr_ray *r);

/* >> samplers (sampler.c: the interface and "random"; sampler_stratified.c, sampler_zerotwo.c, sampler_halton.c,
 *    sampler_sobol.c, sampler_zsobol.c, sampler_paddedsobol.c; lowdiscrepancy.c their shared helpers) */
/* PCG32, pbrt-v3's RNG (core/rng.h) */
typedef struct elr_rng { uint64_t state, inc; } elr_rng;
static inline uint32_t elr_rng_u32(elr_rng *r) {
  uint64_t old = r->state;
  uint32_t xs, rot;
  r->state = old * 0x5851f42d4c957f2dULL + r->inc;
  xs = (uint32_t)(((old >> 18u) ^ old) >> 27u);
  rot = (uint32_t)(old >> 59u);
  return (xs >> rot) | (xs << ((~rot + 1u) & 31));
}
static inline void elr_rng_seed(elr_rng *r, uint64_t seq, uint64_t seed) { /* pbrt's SetSequence */
  r->state = 0u; r->inc = (seq << 1u) | 1u;
  elr_rng_u32(r); r->state += seed; elr_rng_u32(r);
}
static inline float elr_rng_float(elr_rng *r) { return (float)(elr_rng_u32(r) >> 8) * 0x1p-24f; } /* [0, 1) */
/* a 64-bit mixer (splitmix64's finaliser, Stafford's variant 13): seeds from (seed, pixel, dimension) */
static inline uint64_t elr_mix64(uint64_t x) {
  x ^= x >> 31; x *= 0x7fb5d329728ea185ULL; x ^= x >> 27; x *= 0x81dadef4bc2dd44dULL; x ^= x >> 33;
  return x;
}

/* a 32-bit binary fraction as a float in [0, 1): its first 24 digits, exactly. pbrt's min(v * 0x1p-32f,
 * OneMinusEpsilon) rounds to nearest instead, which can carry a point across the boundary of its
 * elementary interval (0x3fffffff becomes 0.25) or to 1 */
static inline float elr_bits_to_float(uint32_t v) { return (float)(v >> 8) * 0x1p-24f; }
static inline uint32_t elr_reverse_bits32(uint32_t n) {
  n = (n << 16) | (n >> 16);
  n = ((n & 0x00ff00ffu) << 8) | ((n & 0xff00ff00u) >> 8);
  n = ((n & 0x0f0f0f0fu) << 4) | ((n & 0xf0f0f0f0u) >> 4);
  n = ((n & 0x33333333u) << 2) | ((n & 0xccccccccu) >> 2);
  return ((n & 0x55555555u) << 1) | ((n & 0xaaaaaaaau) >> 1);
}
/* a uniform integer in [0, b) without modulo bias (pbrt's RNG::UniformUInt32(b)) */
static inline uint32_t elr_rng_bounded(elr_rng *r, uint32_t b) {
  uint32_t threshold = (0u - b) % b;
  for (;;) { uint32_t v = elr_rng_u32(r); if (v >= threshold) return v % b; }
}

/* the halton sampler's tables (sampler_halton.c), one per render, shared by its threads */
#define ELR_HALTON_DIMS 256
typedef struct elr_halton {
  int base_scales[2], base_exps[2], mult_inv[2];
  int64_t stride;
  int ndims;
  int primes[ELR_HALTON_DIMS];
  uint16_t *perm; int perm_off[ELR_HALTON_DIMS];
} elr_halton;
int elr_halton_init(elr_halton *H, int w, int h, uint64_t seed);
void elr_halton_free(elr_halton *H);
int64_t elr_halton_pixel_offset(const elr_halton *H, int px, int py);
float elr_halton_sample(const elr_halton *H, int64_t index, int dim, elr_rng *rng);

/* the Sobol' generator matrices and index tables (lowdiscrepancy.c), one set per render */
#define ELR_SOBOL_DIMS 1024   /* pbrt's NumSobolDimensions */
#define ELR_SOBOL_COLUMNS 52  /* pbrt's SobolMatrixSize: index bits a matrix has columns for */
typedef struct elr_sobol {
  int ndims;                          /* matrices made (2 for the samplers that use dimensions 0 and 1 only) */
  uint32_t *C;                        /* ndims x ELR_SOBOL_COLUMNS */
  int log2res;                        /* SobolIntervalToIndex's image: 2^log2res pixels square */
  uint64_t inv[64], delta[64];        /* its tables (lowdiscrepancy.c) */
  uint32_t lut[2][7][256];            /* dimensions 0 and 1 a byte of the index at a time: the XOR of the
                                         columns of each byte value (the zsobol, paddedsobol and 02sequence loops) */
  uint64_t q64[2][256];               /* lut[0][0] | lut[1][0] << 32: both dimensions of an index byte in one
                                         word, as they are ([0]) and each half bit-reversed ([1]: zsobol's
                                         fast path with fastowen) */
  uint8_t rev8[256];                  /* each byte bit-reversed */
} elr_sobol;
int elr_sobol_init(elr_sobol *T, int ndims, int log2res);
void elr_sobol_free(elr_sobol *T);
uint64_t elr_sobol_interval_to_index(const elr_sobol *T, uint64_t frame, int x, int y);
/* dimension d (< T->ndims) of Sobol' point `index`, unrandomized, as a 32-bit fraction (pbrt's SobolSample
 * before its randomizer); index bits past ELR_SOBOL_COLUMNS are ignored */
static inline uint32_t elr_sobol_bits(const elr_sobol *T, uint64_t index, int d) {
  const uint32_t *c = T->C + (size_t)d * ELR_SOBOL_COLUMNS, *end = c + ELR_SOBOL_COLUMNS;
  uint32_t v = 0;
  if (d < 2) { /* the same sum, a byte at a time (the plain loop below is the definition) */
    const uint32_t (*l)[256] = T->lut[d];
    return l[0][index & 255u] ^ l[1][(index >> 8) & 255u] ^ l[2][(index >> 16) & 255u] ^ l[3][(index >> 24) & 255u] ^
           l[4][(index >> 32) & 255u] ^ l[5][(index >> 40) & 255u] ^ l[6][(index >> 48) & 15u];
  }
  for (; index && c < end; index >>= 1, c++) if (index & 1u) v ^= *c;
  return v;
}
/* pbrt-v4's RandomizeStrategy ("string randomization": none, permutedigits, fastowen, owen) */
enum { ELR_RANDOMIZE_NONE = 0, ELR_RANDOMIZE_PERMUTE_DIGITS = 1, ELR_RANDOMIZE_FAST_OWEN = 2, ELR_RANDOMIZE_OWEN = 3 };
uint32_t elr_randomize(uint32_t v, int strategy, uint32_t seed);
uint32_t elr_permutation_element(uint32_t i, uint32_t n, uint32_t p);
void elr_gray_code_sample(const uint32_t *C, uint32_t n, uint32_t scramble, uint32_t *out);

#define ELR_ZSOBOL_LEVELS 24 /* zsobol's fast path: images up to 2^24 pixels square */
/* a render's sampler tables, made once and shared by its threads: Halton's permutations, Sobol's
 * matrices, the sample bounds the global samplers index their sequence over */
typedef struct elr_sampler_tables {
  elr_halton halton;
  elr_sobol sobol;
  int bx0, by0, res, log2res; /* sample bounds' corner; the power-of-two square that covers them (sobol, zsobol) */
  uint64_t zdig[2][ELR_ZSOBOL_LEVELS][4]; /* zsobol's fast path: the Sobol' point (both dimensions, as q64) of
                                             pixel digit v at level j (index bits log2spp + 2j, + 1) */
} elr_sampler_tables;

/* which sampler a render's threads make, with pbrt's parameters (elr_sampler_choose) */
typedef struct elr_sampler_desc {
  int kind, spp, xs, ys, jitter, dims;
  int randomize;  /* ELR_RANDOMIZE_*: sobol, zsobol, paddedsobol */
  int has_seed;   /* pbrt-v4's "integer seed" given: it replaces --seed for the scrambles */
  int64_t seed;
} elr_sampler_desc;
int elr_sampler_tables_init(elr_sampler_tables *T, const elr_sampler_desc *d, const int sample_bounds[4], uint64_t seed);
void elr_sampler_tables_free(elr_sampler_tables *T);
/* whether every draw the wave loop makes ahead gives the same number in any order (pixel samplers
 * only within their `dimensions`) */
int elr_sampler_order_free(const elr_sampler_desc *d);

/* one thread's sampler: its parameters and where it is (pixel, sample, dimension) */
typedef struct elr_sampler {
  int kind, spp, xs, ys, jitter, dims, randomize;
  uint64_t seed;   /* --seed: the random streams */
  uint32_t sseed;  /* the scrambles' seed (zsobol, paddedsobol, sobol): the scene's "seed" or --seed */
  int log2spp;
  const elr_sampler_tables *T;
  /* per pixel */
  int px, py, sample;
  elr_rng rng;
  float *s1d, *s2d; /* stratified, 02sequence: dims * spp, dims * spp * 2 */
  uint32_t *bits;   /* 02sequence: spp * 2 scratch */
  int d1, d2, dim, made1, made2;
  int64_t hindex, hoffset; /* halton: the sample's index and the pixel's first; sobol: the sample's index;
                              zsobol: the Morton index of pixel and sample */
  uint64_t zvalid, zpixel[64]; /* zsobol: the pixel's permuted digits for dimensions 0..63 (bit d of zvalid: known) */
  /* zsobol's fast path (sampler_zsobol.c; spp <= ELR_ZSOBOL_FAST_SPP): per pixel the Morton code, and per
   * dimension d < 64 met in the pixel (bit d of zfast) the permuted sample digits of each sample
   * (zlow[d * spp + s]) and the Sobol' point of the pixel's digits (zsob[d], both dimensions as the
   * tables' q64) */
  uint64_t zmorton, zfast, zf1, zf2; /* zf1, zf2: bit d, dimension d's 1D or 2D points of the pixel made */
  uint8_t *zlow;
  float *zpt, *zp1;           /* zsobol's fast path: the pixel's points, 2D (zpt[(d * spp + s) * 2 + 0, 1]), 1D (zp1[d * spp + s]) */
  uint64_t zsob[64];
  int zsimd;                  /* zsobol's fast path: 0 scalar, 1 SSE2, 2 AVX2 (elr_zsobol_simd) */
  const uint64_t *zq, (*zdig)[4]; /* the tables' q64 and zdig for the sampler's randomization */
  /* the Morton code and the permuted pixel digits' point of the last pixel met in each dimension, with
   * each digit's permutation p (an index into the 24) and permuted digit d (pd[dim][j] = 4 p + d): the
   * sampler's own (zown), or another's when they share (zshare: elr_sampler_share) */
  struct elr_zsobol_last { uint64_t m[64], P[64], valid; uint8_t pd[64][ELR_ZSOBOL_LEVELS]; } zown, *zshare;
  uint64_t dhash[72];          /* elr_dim_hash(d, sseed) of the first dimensions: the scrambles' seeds */
} elr_sampler;
int elr_sampler_choose(elr_sampler_desc *d, const elr_scene *s, const elr_render_options *o, char *err, size_t errlen);
int elr_sampler_init(elr_sampler *S, const elr_sampler_desc *d, uint64_t seed, const elr_sampler_tables *T);
void elr_sampler_free(elr_sampler *S);
void elr_sampler_start_pixel(elr_sampler *S, int px, int py);
void elr_sampler_start_sample(elr_sampler *S, int sample);
float elr_sampler_get1d(elr_sampler *S);
void elr_sampler_get2d(elr_sampler *S, float u[2]);
void elr_sampler_camera_sample(elr_sampler *S, int k, int x, int y, float *fx, float *fy);
/* S keeps what it remembers from pixel to pixel (zsobol's last pixel per dimension) in `with`'s: the
 * samplers of one thread that take neighbouring pixels in turn share it (the numbers do not change) */
void elr_sampler_share(elr_sampler *S, elr_sampler *with);
void elr_stratified_make(elr_sampler *S, int two, int d);
void elr_zerotwo_make(elr_sampler *S, int two, int d);
float elr_sobol_sampler_1d(const elr_sampler *S, int dim);
/* zsobol's draws: the pixel's points of the dimension when made (the fast path's tables), else made
 * (elr_zsobol_table) or the reference's (sampler_zsobol.c) */
const float *elr_zsobol_table(elr_sampler *S, int dim, int two);
float elr_zsobol_ref_1d(elr_sampler *S, int dim);
void elr_zsobol_ref_2d(elr_sampler *S, int dim, float u[2]);
static inline float elr_zsobol_1d(elr_sampler *S, int dim) {
  const float *t;
  if ((unsigned)dim < 64u && ((S->zf1 >> dim) & 1u)) return S->zp1[(size_t)dim * (size_t)S->spp + ((size_t)S->hindex & (size_t)(S->spp - 1))];
  t = elr_zsobol_table(S, dim, 0);
  return t ? t[0] : elr_zsobol_ref_1d(S, dim);
}
/* the current sample's 2D point of dimension dim where the pixel's are made, else NULL */
static inline const float *elr_zsobol_made2(const elr_sampler *S, int dim) {
  return (unsigned)dim < 64u && ((S->zf2 >> dim) & 1u) ? S->zpt + ((size_t)dim * (size_t)S->spp + ((size_t)S->hindex & (size_t)(S->spp - 1))) * 2u : NULL;
}
static inline void elr_zsobol_2d(elr_sampler *S, int dim, float u[2]) {
  const float *t = elr_zsobol_made2(S, dim);
  if (!t && !(t = elr_zsobol_table(S, dim, 1))) { elr_zsobol_ref_2d(S, dim, u); return; }
  u[0] = t[0]; u[1] = t[1];
}
/* zsobol's reference path (pbrt-v4's GetSampleIndex, SobolSample and randomizer as written there): the
 * fast path above gives the same bits (test_render_samplers) */
#define ELR_ZSOBOL_FAST_SPP 256
void elr_zsobol_start_pixel(elr_sampler *S, uint64_t morton);
void elr_zsobol_tables_init(elr_sampler_tables *T, int log2spp);
void elr_zsobol_draw2d(elr_sampler *S, float u[2]); /* elr_sampler_get2d's zsobol case out of line */
int elr_zsobol_simd(void);
float elr_paddedsobol_1d(const elr_sampler *S, int dim);
void elr_paddedsobol_2d(const elr_sampler *S, int dim, float u[2]);
/* a 64-bit hash of a dimension and a seed (pbrt-v4's Hash(dimension, seed)): a scramble's seed */
static inline uint64_t elr_dim_hash(int dim, uint32_t seed) {
  return elr_mix64((((uint64_t)(uint32_t)dim << 32) | seed) ^ 0x9e3779b97f4a7c15ULL);
}
/* the scramble seed of dimension d (elr_dim_hash(d, S->sseed), kept for the first 72) */
static inline uint64_t elr_sampler_dim_hash(const elr_sampler *S, int d) { return d >= 0 && d < 72 ? S->dhash[d] : elr_dim_hash(d, S->sseed); }
/* a number for a dimension past a sequence's table: a hash of seed, pixel, sample and dimension. These
 * hashes are the samplers' shared helpers, inline here so that sampler_*.c never call back into
 * sampler.c (which dispatches to them: test_render_layout checks the direction) */
static inline float elr_sampler_hash_float(const elr_sampler *S, int dim) {
  uint64_t h = elr_mix64(S->seed ^ 0xd1b54a32d192ed03ULL);
  h = elr_mix64(h ^ (((uint64_t)(uint32_t)S->px << 32) | (uint32_t)S->py));
  h = elr_mix64(h ^ (((uint64_t)(uint32_t)S->sample << 32) | (uint32_t)dim));
  return (float)(h >> 40) * 0x1p-24f;
}
/* for draws made ahead (render_wave.c): a 2D draw skipped, and a camera sample's place saved and restored */
typedef struct elr_sampler_pos { int sample, d1, d2, dim; int64_t hindex; elr_rng rng; } elr_sampler_pos;
void elr_sampler_skip2d(elr_sampler *S);
void elr_sampler_save(const elr_sampler *S, elr_sampler_pos *p);
void elr_sampler_restore(elr_sampler *S, const elr_sampler_pos *p);

/* >> film (film.c): the scene's Film and PixelFilter as film.h's el_film */
/* pbrt-v3's croppedPixelBounds: [b[0], b[2]) x [b[1], b[3]) of the full resolution */
void elr_film_bounds(const elr_scene_desc *d, int b[4]);
int elr_film_init(el_film *f, const elr_scene_desc *d, const int b[4], char *err, size_t errlen);

/* >> a render (render.c): what it decided, read by every thread */
#define ELR_SPLIT_LIGHTS 64      /* splitting applies to scenes of at most this many lights */
#define ELR_SPLIT_MAX_GIVEN 1024 /* --split N: at most this */
typedef struct elr_tstats { /* one thread's counts */
  uint64_t camera, bounce, shadow, bsdfl, samples;
  uint64_t env_product, env_map; /* environment light samples drawn by product sampling, by the map alone */
  uint64_t env_light_only;       /* of the product ones: without a BSDF sample (elr_env_light_only) */
  uint64_t portal_used, portal_fallback; /* light samples through portals, and behind them (the map's) */
  double t_embree; /* the wave loop: seconds inside its Embree calls */
  uint64_t sun_looked, sun_lowered, sun_dark, sun_to_spot; /* sun.c (--stats): environment light samples at vertices the
                        sun cache knows, of them where it lowered the spots' weight (and where it saw no spot), and of
                        the looked-up ones those that landed in a spot's cone */
  uint64_t sunsplit_vertices, sunsplit_sky_only; /* --sun split: vertices split, of them with every spot below the horizon */
  int env_two_pixel; /* ELR_ENVSD_TWO_PIXEL: the current pixel's choice (1 two product samples, 0 MIS), made by the
                        reference loop at each pixel (elr_two_pixel), read by elr_estimate_direct (the wave loop: W->two_pix) */
} elr_tstats;
typedef struct elr_ctx {
  elr_scene *s;
  elr_camera cam;
  elr_sampler_desc sampler;
  int spp;                /* sampler.spp */
  int path, maxdepth;     /* the integrator: path (1) or directlighting (0), and pbrt's maxdepth */
  float rr;               /* the path tracer's rrthreshold */
  int ls;                 /* ELR_LS_*: the strategies that estimate direct light */
  int light_sampling;     /* 0: no light is ever sampled (nothing emits, or nothing non-specular) */
  int has_env;            /* an emitting infinite light exists */
  int has_area;           /* an emitting area light exists */
  int direct_one;         /* directlighting: strategy "one" (one light chosen per vertex) */
  elr_light_distrib ld;   /* which light next-event estimation samples (built for the path tracer and
                             strategy "one" when more than one light emits) */
  /* render_wave.c: the one emitting light, a sampled environment, whose light samples a wave draws
   * together; NULL: one sample at a time */
  const elr_light *batch_light;
  int loop;               /* ELR_LOOP_*: the per-tile loop (ELR_LOOP_WAVE needs batch_light) */
  int wave_api;           /* render_wave.c: ELR_WAVE_API_* */
  const struct elr_sun *sun; /* sun.c: where the environment's hot spots are hidden (NULL: not learnt) */
  const struct elr_sunsplit *sunsplit; /* sun.c, --sun split: one spot and one sky sample per diffuse vertex (NULL: off) */
} elr_ctx;

/* >> integrators (integrator.c: pbrt-v3's core/integrator.cpp; integrator_direct.c, integrator_path.c) */
/* pbrt-v3's PowerHeuristic(1, f, 1, g); for densities whose squares would overflow (an area light seen
 * at a grazing angle: 1e20 and more) the same weight from their ratio, instead of inf / inf */
static inline float elr_power_heuristic(float f, float g) {
  float f2 = f * f, g2 = g * g;
  if (f > 1e18f || g > 1e18f) {
    float r = f >= g ? g / f : f / g, w = 1.f / (1.f + r * r);
    return f >= g ? w : 1.f - w;
  }
  return f2 + g2 > 0.f ? f2 / (f2 + g2) : 0.f;
}
/* A path in flight (the locals of pbrt-v3's Li loops): the ray it continues along, the bounces so far,
 * the radiance gathered and the throughput; for the path tracer whether the last bounce was specular
 * and its BSDF pdf. */
typedef struct elr_path_state {
  elr_ray ray;
  int depth;
  elr_v3 L, beta;
  int specular;
  float prev_pdf;
  int prev_has_n;  /* the last vertex's product-sampling normal (elr_bsdf_cos_normal) exists: prev_n */
  elr_v3 prev_n;
  float eta_scale; /* pbrt-v3's etaScale: the radiance scaling of the refractions so far, left out of Russian roulette */
  const struct elr_sun_cell *prev_sun; /* sun.c: the last vertex's sun-cache cell (NULL: the light's own density) */
  int prev_two; /* ELR_ENVSD_TWO(_PIXEL): the last vertex took two product light samples of an environment (elr_path_two) */
} elr_path_state;
static inline void elr_path_begin(elr_path_state *p, const elr_ray *camera_ray) {
  p->ray = *camera_ray; p->depth = 0; p->L = elr_v(0, 0, 0); p->beta = elr_v(1, 1, 1); p->specular = 0; p->prev_pdf = 0.f;
  p->prev_has_n = 0; p->prev_n = elr_v(0, 0, 0); p->eta_scale = 1.f; p->prev_sun = NULL; p->prev_two = 0;
}

elr_v3 elr_infinite_le(const elr_scene *s, elr_v3 d);
/* pbrt-v3's VisibilityTester::Unoccluded of a light sample taken at h (integrator.c: lights.c traces no rays) */
int elr_light_unoccluded(const elr_scene *s, const elr_hit *h, const elr_light_sample *ls);
/* a light sample's term of elr_estimate_direct (integrator.c; occ: its shadow ray's answer, -1: traced there) */
void elr_light_term(const elr_ctx *C, const elr_hit *h, const elr_bsdf *b, elr_v3 wo, const elr_light_sample *ls, int mis, float pick,
                    float other, int occ, elr_tstats *ts, elr_v3 *Ld);
void elr_estimate_direct(const elr_ctx *C, const elr_hit *h, const elr_bsdf *b, elr_v3 wo, const elr_light *l, const float ul[2],
                         const float us[2], int sample_bsdf, float pick, elr_tstats *ts, elr_v3 *Ld);
elr_v3 elr_uniform_sample_all_lights(const elr_ctx *C, elr_sampler *S, const elr_hit *h, const elr_bsdf *b, elr_v3 wo, int use_counts,
                                     int sample_bsdf, elr_tstats *ts);
elr_v3 elr_uniform_sample_one_light(const elr_ctx *C, elr_sampler *S, const elr_hit *h, const elr_bsdf *b, elr_v3 wo, int sample_bsdf,
                                    elr_tstats *ts);
int elr_specular_reflect(const elr_ctx *C, elr_sampler *S, const elr_ray *r, const elr_hit *h, const elr_tex_ctx *tc, elr_v3 dpdx,
                         elr_v3 dpdy, const elr_bsdf *b, elr_ray *rd, elr_v3 *beta, elr_tstats *ts);
int elr_specular_transmit(const elr_ctx *C, elr_sampler *S, const elr_ray *r, const elr_hit *h, const elr_tex_ctx *tc, elr_v3 dpdx,
                          elr_v3 dpdy, const elr_bsdf *b, elr_ray *rd, elr_v3 *beta, elr_tstats *ts);
int elr_direct_specular(const elr_ctx *C, elr_sampler *S, const elr_ray *r, const elr_hit *h, const elr_tex_ctx *tc, elr_v3 dpdx,
                        elr_v3 dpdy, const elr_bsdf *b, elr_v3 beta, int depth, int allow_split, elr_path_state out[2], elr_tstats *ts);
/* <<Update the term that tracks radiance scaling for refraction>> after a specular transmission from wo */
static inline float elr_eta_scale(float eta_scale, const struct elr_bsdf *b, elr_v3 wo) {
  return eta_scale * (elr_dot(wo, b->ng) > 0.f ? b->eta * b->eta : 1.f / (b->eta * b->eta));
}
elr_v3 elr_direct_li(const elr_ctx *C, elr_sampler *S, const elr_path_state *p, elr_tstats *ts);
elr_v3 elr_direct_li_branches(const elr_ctx *C, elr_sampler *S, const elr_path_state *p, const elr_path_state *waiting, int nwaiting,
                              int splits, elr_tstats *ts);
elr_v3 elr_path_li(const elr_ctx *C, elr_sampler *S, const elr_path_state *p, elr_tstats *ts);
/* ELR_ENVSD_TWO(_PIXEL) in the path tracer (integrator.c): the vertex's part (BSDF b, wo; the pixel's choice in ts),
 * and whether a ray that left such a vertex (prev_two, its sun-cache cell and split) gives light l weight 0 */
int elr_path_two(const elr_ctx *C, const elr_bsdf *b, elr_v3 wo, const elr_tstats *ts);
int elr_path_two_light(const elr_ctx *C, const elr_light *l, int prev_two, const struct elr_sun_cell *prev_sun, int prev_split);
/* render_wave.c: a camera sample's first vertex, computed ahead: the camera ray's
 * hit (hit = 0: it left the scene) and, at a hit, the environment sample for the first light-sampling
 * draw there. */
typedef struct elr_first {
  int hit;
  elr_hit *h;
  elr_v3 wi, L;
  float pdf;
  /* the direct-lighting integrator's, at a hit: the texture footprint and BSDF, and (bs = 1) the BSDF
   * sample of the first draw of light sampling; when it will trace a BSDF ray (bray = 1), the
   * environment's pdf and radiance in its direction */
  int bs, bray;
  elr_tex_ctx tc;
  elr_v3 dpdx, dpdy;
  elr_bsdf b;
  elr_v3 fb, wb, Lb;
  float bpdf, bpdf_env;
  /* the shadow rays of the light sample and of the BSDF sample: -1 traced in the shading, else their
   * answers, traced by the wave loop (1: occluded) */
  int occ_l, occ_b;
  /* the light's further samples (its "samples" count, or splitting) drawn ahead the same way: their light
   * sample, BSDF sample and shadow rays' answers (the wave loop); the others, from nmore + 1 on, drawn in
   * the shading */
  const struct elr_first *more;
  int nmore;
  const struct elr_sun_cell *sun; /* sun.c: the vertex's sun-cache cell (elr_sun_lookup, made once per vertex) */
  /* ELR_ENVSD_TWO(_PIXEL) (two = 1): the second product light sample, drawn from the BSDF sample's numbers
   * (no BSDF sample then: bs, bray 0), and its shadow ray's answer as occ_l's */
  int two, occ_l2;
  elr_v3 wi2, L2;
  float pdf2;
  /* --sun split (sun.c; split 2: a spot and a sky sample, 1: the sky alone, 0: none): sample k in ssl[k], the other
   * light technique's density there in sother[k] (elr_sunsplit_sample), their shadow rays' answers occ_l and occ_l2;
   * nsplit the product normal (the BSDF sample's MIS weight: elr_sunsplit_pdf) */
  int split;
  elr_light_sample ssl[2];
  float sother[2];
  elr_v3 nsplit;
} elr_first;
/* elr_direct_li with its first vertex computed ahead in f (camera ray r; the sampler at the sample's
 * first draw after its camera sample) */
elr_v3 elr_direct_first(const elr_ctx *C, elr_sampler *S, const elr_ray *r, const elr_first *f, elr_tstats *ts);
/* ELR_ENVSD_TWO_PIXEL: pixel (x, y)'s choice (integrator_direct.c; 1: two product light samples, 0: product MIS), two
 * rays counted in ts; the reference loop and the wave loop make it at the pixel's start */
int elr_two_pixel(const elr_ctx *C, int x, int y, elr_tstats *ts);

/* render_wave.c: a thread's wave loop (its samplers, one per pixel of a wave, and the wave's arrays) */
typedef struct elr_wave elr_wave;
elr_wave *elr_wave_new(const elr_ctx *C, const elr_sampler_tables *T, uint64_t seed, int tile); /* NULL: out of memory */
void elr_wave_free(elr_wave *W);
void elr_wave_render_tile(const elr_ctx *C, elr_wave *W, int x0, int y0, int x1, int y1, el_film_tile *tile, elr_tstats *ts);

/* >> sun.c: where the environment's hot spots are hidden (issue 22): a pilot's cache of their visibility
 * over world-space cells, and the light density that moves a hidden spot's samples to the rest */
typedef struct elr_sun elr_sun;
typedef struct elr_sun_cell elr_sun_cell;
#define ELR_SUN_INFO_SPOTS EL_ENVLIGHT_HOTSPOT_MAX
typedef struct elr_sun_info {
  int spots;                                /* hot spots found (el_envlight_hotspots_init's defaults) */
  el_envlight_hotspot spot[ELR_SUN_INFO_SPOTS];
  float cell, floor;                        /* the cells' edge (world units); the spots' share where none is seen */
  int64_t pilot_points, pilot_rays, cells, cells_lowered, cells_dark; /* dark: no spot seen */
  int64_t cells_horizon;                    /* lowered cells whose spots all lay below the pilot's horizons */
  double seconds, cpu_seconds;              /* the pilot and the table: wall time, CPU time (all threads) */
} elr_sun_info;
/* 0 and *out set (NULL when the light has no hot spot), -1 out of memory. The pilot runs on nthreads threads
 * (the same cache for any number). */
int elr_sun_build(const elr_ctx *C, const elr_light *l, const int fb[4], int nthreads, elr_sun **out);
void elr_sun_free(elr_sun *S);
const elr_sun_info *elr_sun_get_info(const elr_sun *S);
const elr_light *elr_sun_light(const elr_sun *S);
/* the cell of hit h seen from wo when it lowers a spot's weight; NULL: the light's own density there */
const elr_sun_cell *elr_sun_lookup(const elr_sun *S, const elr_hit *h, elr_v3 wo);
/* the light sample and the pdf at a vertex of cell c (n: product sampling's normal, or NULL: the map alone) */
void elr_sun_sample(const elr_sun *S, const elr_sun_cell *c, const elr_v3 *n, const float u[2], float wi[3], float L[3], float *pdf);
float elr_sun_pdf(const elr_sun *S, const elr_sun_cell *c, const elr_v3 *n, const float wi[3]);
int elr_sun_in_spot(const elr_sun *S, const float wi[3]);
/* elr_bsdf_cos_normal at a vertex of cell c (NULL: the same): at a lowered cell also where only the sun map's
 * choice for diffuse lobes asked for the map alone (sun.c) */
int elr_sun_cos_normal(const elr_scene *s, const elr_sun_cell *c, const elr_bsdf *b, elr_v3 wo, elr_v3 *n);
float elr_sun_cell_alpha(const elr_sun_cell *c); /* sum P_k v_k / sum P_k of the cell (NULL: 1) */
int elr_sun_cell_product(const elr_sun_cell *c, int has_n); /* the cell's density at a vertex with a product normal is the product's */
void elr_sun_count(const elr_sun *S, const elr_sun_cell *c, const float wi[3], float pdf, elr_tstats *ts); /* --stats */
/* elr_light_sample_li for the sun's light at a vertex of cell c (not NULL), counted for --stats */
void elr_sun_light_sample(const elr_sun *S, const elr_sun_cell *c, const elr_v3 *n, const float u[2], elr_light_sample *ls, elr_tstats *ts);
/* --sun split (sun.c): at a vertex with a product normal n under a sun map, two light samples, one from the
 * hot spots alone and one from the rest x cosine, MIS-weighted with the BSDF sample over the three */
typedef struct elr_sunsplit elr_sunsplit;
int elr_sunsplit_build(const elr_light *l, elr_sunsplit **out); /* 0 and *out (NULL: no hot spot), -1 out of memory */
void elr_sunsplit_free(elr_sunsplit *P);
double elr_sunsplit_cpu(const elr_sunsplit *P); /* CPU seconds of the build (hot spots and tables) */
const elr_light *elr_sunsplit_light(const elr_sunsplit *P);
int elr_sunsplit_spot(const elr_sunsplit *P); /* how the spot sample is drawn (sun.c's ELR_SUNSPLIT_SPOT) */
/* whether vertex (BSDF b, product normal n or NULL) of light l splits, and then from which part: 2 both, 1 the sky only
 * (every spot below n's horizon), 0 no split */
int elr_sunsplit_at(const elr_sunsplit *P, const elr_light *l, const elr_bsdf *b, const elr_v3 *n);
/* the light sample of part k (0 the spots, 1 the sky) at normal n, counted for --stats; *other: the other part's density
 * at its direction */
void elr_sunsplit_sample(const elr_sunsplit *P, int k, int parts, elr_v3 n, const float u[2], elr_light_sample *ls, float *other, elr_tstats *ts);
/* sqrt(p_0^2 + p_1^2) of the parts' densities at wi, what the power heuristic of a BSDF sample compares (parts: as
 * elr_sunsplit_at says, 1 the sky alone) */
float elr_sunsplit_pdf(const elr_sunsplit *P, int parts, elr_v3 n, elr_v3 wi);

#endif
