/* el_render.h: the pieces of `render`, a pbrt-v3-format scene renderer on Embree (examples/render).
 *
 * Not part of the envlight library: an application of it. The renderer reads a pbrt-v3 scene file
 * (parser.c, paramset.c, api*.c), builds an Embree scene of exact spheres, disks, triangle meshes, Loop subdivision surfaces
 * and instances (scene.c, shapes.c, loopsubdiv.c), shades with pbrt-v3's matte / mirror / plastic / glass /
 * metal / uber / substrate materials and its textures (materials.c, textures.c, reflection.c), lights with
 * the infinite area light of envlight.h plus point, distant and diffuse area lights (lights.c, chosen
 * among by lightdistrib.c), and integrates with pbrt-v3's DirectLightingIntegrator or a path tracer with next-event
 * estimation and MIS (integrator*.c), accumulating through film.h over tiles on all cores (render.c).
 * README.md's file table lists every file with the part of pbrt-v3 it mirrors.
 *
 *   elr_scene *s = NULL; char err[512];
 *   if (elr_scene_load("scene.pbrt", &s, err, sizeof err) != 0) { fprintf(stderr, "%s\n", err); exit(1); }
 *   elr_render_options o; elr_render_options_default(&o); o.spp = 16;
 *   elr_image img; elr_stats st;
 *   if (elr_render(s, &o, &img, &st, err, sizeof err) != 0) ...
 *   elr_image_write(&img, "out.png", err, sizeof err);
 *   elr_image_free(&img); elr_scene_free(s);
 *
 * The pipeline is assembled from what the scene uses (see elr_render): no ray at all when nothing
 * emits, no shadow rays or light sampling when no surface has a non-specular lobe, no environment sampling
 * distribution when the environment is only seen directly or through mirrors, no MIP levels above 0
 * for textures never minified, no splat buffer (nothing in this renderer splats), no bounce past
 * maxdepth. elr_stats reports what was built and what each part cost.
 */
#ifndef EL_RENDER_H
#define EL_RENDER_H
#include <stddef.h>
#include <stdint.h>
#ifdef __cplusplus
extern "C" {
#endif

typedef struct elr_scene elr_scene;

/* Parse a pbrt-v3 scene file and build everything it needs except the things that are built lazily
 * (the environment's sampling distribution, MIP levels). Returns 0, or -1 with "file:line: message"
 * in err. Warnings (unsupported directives or parameters) go to stderr as "file:line: warning: ..."
 * unless quiet, and are counted in elr_scene_warnings(). */
int elr_scene_load(const char *path, elr_scene **out, int quiet, char *err, size_t errlen);
/* The same from a string (file names in it are relative to base_dir; name is used in messages). */
int elr_scene_load_string(const char *text, const char *name, const char *base_dir, elr_scene **out,
                          int quiet, char *err, size_t errlen);
void elr_scene_free(elr_scene *s);
int elr_scene_warnings(const elr_scene *s);
const char *elr_scene_last_warning(const elr_scene *s); /* "" when none */
const char *elr_scene_film_filename(const elr_scene *s);
void elr_scene_resolution(const elr_scene *s, int *width, int *height); /* after cropwindow */
int elr_scene_spp(const elr_scene *s);

/* Light sampling strategies (the integrator's "string lightsampling" parameter, a test/bench hook). */
enum { ELR_LS_MIS = 0, ELR_LS_LIGHT = 1, ELR_LS_BSDF = 2 };
/* Samplers: pbrt-v3's random, stratified, halton, sobol, 02sequence (also "lowdiscrepancy"); pbrt-v4's
 * zsobol and paddedsobol. */
enum { ELR_SAMPLER_DEFAULT = 0, ELR_SAMPLER_RANDOM = 1, ELR_SAMPLER_STRATIFIED = 2, ELR_SAMPLER_HALTON = 3, ELR_SAMPLER_SOBOL = 4,
       ELR_SAMPLER_ZEROTWO = 5, ELR_SAMPLER_ZSOBOL = 6, ELR_SAMPLER_PADDEDSOBOL = 7, ELR_SAMPLER_COUNT = 8 };
/* the scene-file name of a sampler kind ("02sequence" for ELR_SAMPLER_ZEROTWO), or "default"; and back
 * (-1 for an unknown name) */
const char *elr_sampler_kind_name(int kind);
int elr_sampler_kind_from_name(const char *name);
/* the sampler of a scene without a Sampler directive (a scene's named sampler is always used) */
/* pbrt-v3's default is halton; 02sequence has 0.38-0.74x its relative variance across seeds on the light
 * sampling of bench_city and bench_studio at 16, 64 and 256 spp for the same CPU time (render README,
 * "Samplers") */
#define ELR_DEFAULT_SAMPLER ELR_SAMPLER_ZEROTWO
#define ELR_DEFAULT_SPP 16

/* the per-tile loops: one sample at a time (the reference), waves of samples (render_wave.c, the fast
 * one). 1 was the batched loop (a pixel's light samples drawn together), folded into the wave loop. */
enum { ELR_LOOP_ONE = 0, ELR_LOOP_WAVE = 2 };
enum { ELR_SPLIT_OFF = 0, ELR_SPLIT_AUTO = 1 };
typedef struct elr_render_options {
  int spp;            /* 0: the scene's */
  int nthreads;       /* 0: all cores */
  uint64_t seed;
  int quiet;          /* no progress bar */
  int light_sampling; /* -1: the scene's, else ELR_LS_* */
  int compensated;    /* -1: the scene's, else 0/1 (envlight's compensated distribution) */
  int importance;     /* -1: the scene's, else 0 cell average (envlight's default), 1 pbrt-v3 (2x res), 2 texel */
  int sampler;        /* ELR_SAMPLER_DEFAULT: the scene's */
  int randomization;  /* -1: the sampler's (the scene's "randomization", or pbrt's default); else sobol, zsobol and
                         paddedsobol scramble with 0 none, 1 permutedigits, 2 fastowen, 3 owen */
  int env_sampling;   /* -1: the infinite lights' "sampling"; 1 product sampling (map x cosine), 0 the map alone */
  int tile_size;      /* 0: 16 */
  int no_batch;       /* 0: the wave loop where it applies (its environment light samples drawn together),
                         1: the reference loop (one at a time inside each sample's shading); the same image
                         except for the path tracer with a pixel sampler (render.c) */
  int loop;           /* -1: the default loop for the scene; else ELR_LOOP_* (the wave loop only where
                         render.c can use them: the environment the only light that emits, and sampled) */
  int split;          /* -1: the scene's ("splitting", default auto); ELR_SPLIT_OFF: each light's "samples";
                         ELR_SPLIT_AUTO: chosen by a pilot (render.c); N >= 2: N light and BSDF sample pairs per
                         camera sample (direct lighting, strategy "all", where the scene leaves "samples" at 1) */
  int wave_api;       /* -1: the wave loop's default; else how it traces (ELR_WAVE_API_* of elr_internal.h:
                         0 rtcIntersect1, 1 packets of 16, 2 rtcIntersect1M streams, 3 rtcIntersectNp) */
  float env_lobe_alpha; /* < 0: ELR_ENV_LOBE_ALPHA; else with product sampling, vertices whose glossy lobe has a
                           Trowbridge-Reitz alpha below it and no diffuse lobe sample the environment's map alone
                           under a sun map, the product around the mirror direction otherwise (0: never; issue 20) */
  float env_light_alpha; /* < 0: ELR_ENV_LIGHT_ALPHA; else with product sampling, directlighting vertices whose lobes
                            are diffuse or of alpha >= it take the light sample alone (no BSDF sample; inf: never) */
  int env_sun;          /* issue 22 (sun.c): 1 on for a product-sampled sun map (elr__sun_share) with hot spots: a pilot learns where they are
                           hidden and the light samples there go to the rest of the map x cosine (1.3-1.9x less variance
                           in the sun's shadow at equal samples, but 1.3-1.8x the render's CPU time on the bench scenes:
                           bench/bench_sun_render.c); 2 split: at every vertex with a product normal one light sample
                           of the hot spots and one of the rest x cosine, MIS with the BSDF sample over the three
                           (either loop: the same image); 0 and -1 (the default, until its per-sample cost is down) off */
  int env_sun_diffuse;  /* -1: ELR_ENV_SUN_DIFFUSE; else with product sampling under a sun map (elr__sun_share), how
                           vertices with only diffuse lobes sample it: ELR_ENVSD_MAP the map alone with MIS, ELR_ENVSD_PRODUCT
                           the product with MIS, ELR_ENVSD_ALONE the product light sample alone, ELR_ENVSD_SUNCOS the map
                           alone where the sun is within acos(env_sun_cos) of the normal, the product with MIS elsewhere
                           (issue 20's sun rule, the default until the wave loop batched product samples; now
                           ELR_ENVSD_PRODUCT: elr_internal.h); ELR_ENVSD_TWO and ELR_ENVSD_TWO_PIXEL: directlighting's
                           BSDF sample spent on a second product light sample (everywhere, or in the pixels whose
                           centre sees the sun), the reference loop only (issue 22's lit pixels) */
  float env_sun_cos;    /* < -2: ELR_ENV_SUN_COS; else that threshold */
} elr_render_options;
void elr_render_options_default(elr_render_options *o);

/* What was built for one light (elr_stats.light) */
#define ELR_STATS_LIGHTS 16
typedef struct elr_light_stats {
  int kind;             /* 0 infinite, 1 point, 2 distant, 3 area */
  int shape_kind, shape, ntri; /* an area light's shape: 0 triangle mesh (ntri triangles), 1 sphere, 2 disk; its index */
  int twosided, nsamples, emits;
  double area, power;   /* area: world area; power: pbrt-v3's Power().y() (computed for the "power" strategy) */
  float pick;           /* the probability that next-event estimation chooses it (1: every light is sampled) */
  int tables_built;     /* environment: its sampling tables; area light on a mesh: its area CDF */
  size_t bytes;         /* those tables */
  double seconds;       /* and their build time */
  int env_product;      /* environment: reflecting vertices sampled the map x cosine (el_envlight_sample_li_cos) */
  float env_lobe_alpha; /* environment, product sampling: vertices with a glossy lobe of alpha below it (no diffuse
                           lobe) took the map under a sun, the product around the mirror direction otherwise */
  float env_light_alpha; /* and directlighting vertices with no lobe narrower than it, the light sample alone */
  float env_sun_share;   /* the share of the map's power above 100x its mean radiance (> 0.5: diffuse lobes take the map) */
  int env_map_built;    /* environment: the map's own tables (el_envlight_sample_li) were built */
  int env_importance;   /* environment: the map's importance mode (EL_ENVLIGHT_IMPORTANCE_*) */
  int env_importance_auto; /* 1: BILINEAR because the scene gave none and the map has a sun (issue 22) */
  int env_portals;      /* environment: pbrt-v4's portals (issue 23), 0 without */
  size_t env_portal_bytes;
  float env_portal_share; /* "float portalmapshare": the map's share where a portal is seen */
  uint64_t env_portal_used, env_portal_fallback; /* light samples through the portals, and by the map behind them */
  int env_portal_compensated; /* the portals' density is MIS-compensated (max(lum - mean, 0)) */
} elr_light_stats;

typedef struct elr_stats {
  double t_parse, t_images, t_embree, t_distribution, t_render, t_total;
  double t_render_cpu; /* CPU seconds of the render loop (all threads) */
  size_t bytes_embree, bytes_textures, bytes_film, bytes_distribution, bytes_splats, bytes_mip;
  uint64_t camera_rays, bounce_rays, shadow_rays, bsdf_light_rays, samples;
  uint64_t env_product_samples, env_map_samples; /* environment light samples by product sampling, by the map alone */
  uint64_t env_light_only_samples;               /* of the product ones: taken alone, without a BSDF sample */
  int mip_levels_built, mip_textures, distribution_built, light_sampling_used, splats_allocated;
  int light_samples_batched; /* the wave loop drew the environment's light samples together (el_envlight_sample_li_n) */
  int loop, wave_api;        /* the per-tile loop that ran (ELR_LOOP_*) and the wave loop's Embree calls */
  double t_embree_loop;      /* the wave loop: seconds inside Embree, summed over the threads (0 for the other loops) */
  int split, split_auto;     /* light and BSDF sample pairs per camera sample given by splitting (1: none); chosen by the pilot */
  double t_split_pilot;      /* the pilot's wall time (in t_total, not in t_render) */
  double split_var[2], split_cpu[2], split_gain; /* the pilot's relative variance and CPU seconds at n = 1 and 4; the
                                                    predicted error x time of n = 1 over that of the n chosen */
  int nthreads, spp, width, height, maxdepth, integrator_path, sampler;
  int sampler_randomization; /* sobol, zsobol, paddedsobol: 0 none, 1 permutedigits, 2 fastowen, 3 owen */
  uint64_t rejected_samples;
  /* the lights: which emit, how next-event estimation chooses among them, what was built for each */
  int nothing_emits;            /* no light emits: nothing was traced, the image is black */
  int lights, lights_emitting, lights_area;
  char light_strategy[32];      /* "all" (every light at every vertex), "uniform", "power", "power (for spatial)" */
  int light_distribution_built; /* more than one light to choose from */
  size_t bytes_light_distribution;
  double t_light_distribution, t_area_lights;
  int nlight_stats;             /* the first ELR_STATS_LIGHTS lights */
  elr_light_stats light[ELR_STATS_LIGHTS];
  /* issue 22: the sun cache (sun.c); sun_used 0: none was built */
  int sun_used, sun_spots;
  float sun_spot_axis[8][3], sun_spot_half_angle[8], sun_spot_share[8]; /* the hot spots (radians; sample_li's share) */
  float sun_cell, sun_floor;  /* the cells' edge (world units); the spots' share of the samples where none is seen */
  int64_t sun_pilot_points, sun_pilot_rays, sun_cells, sun_cells_lowered, sun_cells_dark;
  int64_t sun_cells_horizon;  /* lowered cells whose spots all lay below the pilot's horizons (product kept) */
  double t_sun, t_sun_cpu;    /* the pilot's wall and CPU time (in t_total, not in t_render) */
  uint64_t sun_looked, sun_lowered, sun_dark, sun_to_spot; /* the sun light's samples; at lowered cells; at cells where
                                                              no spot was seen; landing in a spot's cone */
  /* --sun split (env_sun 2, sun.c): built (its tables' CPU time in t_sun_cpu); the vertices whose environment light
   * sample was split (one spot and one sky sample), and of them those with every spot below the horizon (the sky alone) */
  int sunsplit_used, sunsplit_spot; /* sunsplit_spot: how the spot sample was drawn (sun.c's ELR_SUNSPLIT_SPOT: 0 the spots'
                                       bins, 1 product sampling, 2 the map's own density inside the spots' cones, 3 el_envlight_sample_li_spot) */
  uint64_t sunsplit_vertices, sunsplit_sky_only;
} elr_stats;

typedef struct elr_image { int width, height; float *rgb; } elr_image; /* linear RGB, top row first */
void elr_image_free(elr_image *img);
/* Format by extension: .png (sRGB 8-bit), .exr, .pfm, .hdr (linear float). */
int elr_image_write(const elr_image *img, const char *path, char *err, size_t errlen);

int elr_render(elr_scene *s, const elr_render_options *o, elr_image *out, elr_stats *st, char *err,
               size_t errlen);
void elr_stats_print(const elr_stats *st, void *file /* FILE* */);

double elr_now(void); /* seconds, monotonic */
double elr_cpu_now(void); /* CPU seconds of the process */

#ifdef __cplusplus
}
#endif
#endif
