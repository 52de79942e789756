/* sun.c: where the sun is hidden (issue 22; render --sun on, off by default; --sun split, SPLITTING below). The
 * environment's hot spots (envlight.h's el_envlight_hotspots: a sun, a lamp) are sampled less where a pilot found them hidden,
 * and the sky that lights those places gets their samples. No pbrt counterpart (pbrt-v3 and -v4 sample
 * the map whole; Cycles cone-samples only its procedural sky's sun, with a fixed MIS weight).
 *
 * THE CACHE. Before the render, one pilot camera ray through the centre of every pixel (on the render's
 * threads); at its first hit ELR_SUN_RAYS shadow rays towards each spot (directions drawn from the spot
 * alone, fixed numbers: the cache does not depend on the seed or the thread count). A spot counts as
 * seen along a ray that is not occluded and leaves on the camera's side of the geometric normal. The
 * hits go into a hashed grid of world-space cells (edge ELR_SUN_CELL times the median pixel footprint
 * of the hits), split by the normal's main axis and sign (a wall and the ground at its foot are apart);
 * per cell and spot the fraction v_k of its rays that saw the spot, then the largest v_k of the cell and
 * its 26 neighbours of the same normal class (so a cell at the shadow's edge whose neighbour is lit is
 * treated as lit). A spot is DARK in a cell when that is 0 (ELR_SUN_DARK_ONLY; partly lit cells keep the
 * light's density: measured, scaling the weights by v_k cost the lit side of a sphere 2-4x).
 *
 * THE DENSITY at a vertex whose cell has a dark spot (elsewhere, and at vertices the pilot never saw, the
 * renderer's density unchanged, bit for bit; where every pilot ray of the cell towards its dark spots lay
 * below the horizon, the renderer's product sampling at vertices that have a product normal, COST below):
 * the spot's weight P_k e, the other parts their shares P
 * (e makes the dark spots' total ELR_SUN_FLOOR of the samples), as
 *   the rest x cosine (el_envlight_sample_li_mix_cos) where the vertex reflects only (elr_sun_cos_normal:
 *     also the diffuse vertices that a sun map otherwise sends to the map alone), for the CELL's normal
 *     (the mean of its pilot normals, rounded to ~5 degrees: one table per cell, see elr__sun_tables);
 *     with several spots, some lit, the one-sample mixture a p_cos + (1 - a) p_mixcos,
 *     a = the lit spots' share (p_cos: sample_li_cos's density);
 *   el_envlight_sample_li_mix with those weights elsewhere (a peaked lobe, rough transmission).
 * The light sample keeps its BSDF sample as MIS partner (elr_env_light_only is left out there: the
 * cosine BSDF sample finds a smooth sky well; alone, the rest x cosine had 2.3x more variance than the
 * map with MIS at a ground point behind a wall: bench_sun_render --shadow-point). The pdf queries (the
 * BSDF sample's MIS weight, the path tracer's escaped ray: elr_path_state.prev_sun) find the same cell
 * from the same vertex, so both agree on one density. Every part keeps a positive weight, so a sun the
 * pilot missed is still found (at the floor's rate).
 *
 * COST (issue 22's second step): the rest x cosine tables (el_envlight_mix_cos_prepare, 512 cell bounds)
 * are made once per lowered cell after the pilot and shared read-only (a per-thread memo of 8 was 1.8x);
 * the hash keeps only lowered cells; the light's hot spots are found once per light (elr_light.sun_hs).
 * Callgrind, 16 spp, the render loop and the pilot against --sun off: 1.15x (sun_shadow_object), 1.24x
 * (sun_porch), 1.09x (bench_city), from 1.38x, 1.42x, 1.28x. The CPU time was then 1.3-1.45x: memory (a light
 * sample in a dark cell read a cell's el_distribution2d, the pdf table twice, the direction table and the
 * texels at random places; perf: el_distribution2d_sample_bins 9% of sun_porch's CPU, waiting on its row,
 * el_envlight__sample_table 6.5% on the pdf table, elr_sun_lookup 7% on this hash's 112-byte slots).
 * Loading ahead did not pay (measured 2026-12-02, perf at 64 spp and bench_sun_render interleaved): a wave's
 * dark-cell samples in passes moved the wait into the passes, __builtin_prefetch of the same lines did
 * nothing, loading the pdf and direction tables ahead cost as much as it saved. What paid is reading less
 * (issue 22's cost round, envlight.h NOTES ON HOT SPOTS 4): the cell tables as uint16 CDFs with the product
 * sampler's 8-bucket guides (half the bytes; one row line per sample), the pdf from those entries (no pdf
 * table), the direction without sample_table's pdf (and, under a general rotation, without its second
 * pdf), the radiance at the sample's (u, v) under a signed-permutation matrix (as sample_li), a branch-free
 * search of the cells' sums; here the lookup probes an array of 8-byte keys (elr_sun.keys) and the path
 * loop takes a vertex's cell and normal from its light sample instead of a second lookup. Per sample
 * (bench/callgrind_product.sh, city.hdr, 3% spots): 1060 -> 845 instructions with the radiance, pdf 287 ->
 * 265; callgrind, the render loop alone 1.035x, 1.029x, 1.064x the instructions of --sun off (object,
 * porch, city), with the pilot at 16 spp 1.065x, 1.047x, 1.106x. The render loop's CPU against --sun off
 * (16 spp, 1 thread, best of 5 interleaved process runs, three runs on a loaded machine): 1.23-1.26x ->
 * 1.06-1.14x (object), 1.31-1.43x -> 1.07-1.17x (porch), 1.21-1.26x -> 1.02-1.04x (city;
 * bench_sun_render's renders in one process: 1.09x, 1.17x, 1.09x), plus the pilot (0.011, 0.011, 0.035 s
 * against loops of 0.20, 0.34, 0.46 s). Since issue 20's batched product sampling reached the wave loop
 * (el_envlight_sample_li_cos_n: the default's loop 0.21 -> 0.16, 0.35 -> 0.28, 0.53 -> 0.42 s) while a
 * dark cell's samples stay single calls: 1.19x, 1.28x, 1.19x (best of 5 interleaved, after the merge);
 * batching the mixture's samples the same way is the next step. Measured (perf, sun_porch, 32 spp, 1 thread): the
 * largest single calls were not the mixture's but product samples, el_envlight_sample_li_cos, 10% of the process's
 * cycles: a horizon cell's density is the product's itself; those samples and their pdfs now go through the wave's
 * batched calls (elr_sun_cell_product; the images bit for bit the same): the loop 1.21x -> 1.15x, 1.33x -> 1.23x,
 * 1.17x -> 1.11x the CPU of --sun off (16 spp, 1 thread, best of 5 interleaved); bench_sun_render (16 spp, 8 seeds):
 * the whole image 0.86x, 0.84x, 0.82x at equal time (shadowed 1.21x, 0.85x, 0.78x). What the dark cells' mixture
 * still costs there: its samples 5.3% of the cycles, their pdfs (el_envlight__hot_pdf_cos, the BSDF samples' and
 * escaped rays' weights) 6.0%, the texels 3.1%; per sample no more than a batched product sample costs (3.6% of the
 * cycles for 48% of the samples against 5.5% for 52% on sun_shadow_object); a batched form as much faster as the
 * product's (2.8x) would save at most 9% of porch's cycles, and the earlier prefetching one saved nothing: not
 * built this round. Not in those: finding the hot spots and their cell tables,
 * once per light (city.hdr, 2048x1024 bins: 0.28 G instructions, plus the light's own sampling tables where
 * the render would not build them, plus the cells' dilation 0.09 G: a fresh render --sun on pays them).
 * THE HORIZON (this round): a cell whose pilot rays towards its lowered spots all lay below their points'
 * horizons (elr_sun_cell.horizon: the sphere's far side, a wall facing away) keeps the renderer's product
 * sampling where the vertex has a product normal: it draws no spot there already and bounds the cosine
 * more tightly than the rest's 32 x 16 cells; the map-alone vertices there (a peaked glossy lobe) keep the
 * mixture. Counting those rays as seeing the spot instead (the whole cell back to the default) gave
 * bench_city's shadow 0.98x but cost sun_shadow_object's glossy sphere: 1.40x -> 1.16x.
 * bench/bench_sun_render.c (16 spp, 16 seeds, CPU from 5 interleaved renders), against today's default:
 * in the shadow 1.45x less variance at equal samples on sun_shadow_object (1.26x at equal time; 1.13x
 * after the batched default), 1.03x on sun_porch (0.86x; 0.68x), 0.98x on bench_city (0.84x; 0.76x; 0.92x
 * before the horizon rule); the whole image 1.05x, 1.02x, 1.00x at equal samples, 0.91x, 0.85x, 0.86x at
 * equal time (0.82x, 0.68x, 0.77x after the batched default): off by default (the whole image has
 * at most 5% to gain at equal samples, less than the pilot and the lookups cost). At 64 spp (8 seeds):
 * shadowed 1.45x, 1.01x, 0.75x (median pixel 1.40x, 1.04x, 0.95x; SUN_DUMP/SUN_RATIO at 32 spp: on
 * bench_city the sphere's dark side is now even, and the sphere's cast shadow on the ground, where the
 * default samples the map alone with MIS, is mixed, slightly worse with the cache, a few pixels much
 * worse), the whole image 1.05x, 1.01x, 0.96x at equal samples and 0.96x, 0.88x, 0.88x at equal time. The porch's path
 * tracing: the cache is applied at every vertex whose cell the pilot saw (all depths); at the camera
 * vertices alone the shadow's variance is 1.006x less, at all 1.009x (before the horizon rule; its direct
 * light alone, maxdepth 1: 1.10x less), for 8% more CPU: 73% of the shadow's variance there is indirect
 * light from the sunlit ground, which no light-sample density changes.
 *
 * SPLITTING BY COMPONENT (render --sun split, issue 22's "one sun and one sky sample"; no pilot, no cache). At a
 * vertex with a product normal n (elr_bsdf_cos_normal: diffuse and broad lobes) under a sun map, instead of the one
 * product light sample: a SPOT sample and a SKY sample (the rest x cosine, el_envlight_sample_li_mix_cos_table with
 * the spots' weight 0, one table per normal of an octahedral grid of 33 x 33, made once: 2 ms), plus the BSDF sample,
 * one each, weighted by the power heuristic over the three techniques: a light sample of density p in direction w
 * gets p^2 / (p^2 + p_o(w)^2 + p_b(w)^2) (p_o the other light sample's density there, p_b the BSDF's), the BSDF sample
 * p_b^2 / (p_b^2 + p_s^2 + p_r^2) (elr_sunsplit_pdf); so the weights of the techniques that reach w sum to 1 and the
 * estimate is unbiased (test_render_sun: |z| < 4 against the default, 8 seeds per class). The spot sample is
 * el_envlight_sample_li_spot on the render's own density (l->env_sample: le()'s patches under a sun) and ITS hot spots
 * (P->hsb; a spot by its share): le()'s patches renormalised to a rectangle of patches around the spot's cone, so every
 * draw lands there and its pdf is pdf_li / P(rectangle) (ELR_SUNSPLIT_SPOT 3). Where every spot lies below n's horizon,
 * the renderer's product sample (no split). Both samples use the same two numbers (a third draw from the sampler:
 * shadow 1.47x against 1.54x). Both loops: render_wave.c draws the two samples at the vertex (elr_sunsplit_sample, one
 * call each), traces their shadow rays with the wave's (so a directlighting wave holds half the camera samples: three
 * shadow rays a pair; no structure-of-arrays lanes) and sums them with elr_light_term, the reference's order: the
 * same image bit for bit (test_render_wave 7., directlighting and path).
 * Measured (bench_sun_render --split, 16 spp, 8 seeds, 2 threads; object / porch / city), against the default:
 * shadowed 1.93x / 1.33x / 1.02x less variance at equal spp, lit 10.7x / 3.86x / 1.53x, the whole image 6.15x / 1.52x /
 * 1.41x; at equal time against the default's wave loop 2.32x / 0.71x / 0.51x (the CPU 2.64x, 2.14x, 2.75x), against the
 * default in the same one-sample loop (--loop-one) 4.76x / 1.20x / 1.08x (CPU 1.29x, 1.27x, 1.31x). At 64 spp (4 seeds):
 * shadowed 2.17x / 1.46x / 0.83x, lit 11.5x / 3.81x / 1.19x, whole 6.61x / 1.66x / 1.12x at equal spp, 2.58x / 0.74x /
 * 0.39x at equal time against the wave default (pdf_li_spot answers 0 at once far from the rectangle: on bench_city the
 * spot pdfs of the sky and BSDF samples were 7.3% of the cycles before, under 2% after). The city's shadow loses at
 * 64 spp (0.83x): there the spot sample is wasted and the default's BSDF sample already finds the sky (A3.14). So the split wins every scene's image at equal spp, and at equal time
 * the porch and the city lost mainly to the one-sample loop. IN THE WAVE LOOP (the same images, so the same variances):
 * loop CPU against the default (render --stats, 64 spp, 2 threads, mean of 3 interleaved rounds) 1.86x / 1.58x / 1.94x
 * (from 2.64x / 2.14x / 2.75x), so at equal time the whole image 3.31x / 0.96x / 0.73x less variance at 16 spp (bench_sun_render
 * --split's own CPU columns: 3.21x / 0.96x / 0.73x), 3.55x / 1.05x / 0.58x at 64 spp; the porch as directlighting (Integrator
 * changed, 16 spp, 8 seeds): 2.00x at equal spp (shadow 1.24x, lit 8.90x), CPU 1.70x, 1.18x at equal time. What is left is the
 * library's sampling (perf, bench_city: el_envlight__hot_pdf_cos 15%, sample_li_spot 13%, sample_li_mix_cos_table 13%, the
 * bilinear lookup 8%; the wave itself 7%, Embree small). Off by default: the city still loses at equal time.
 * Before el_envlight_sample_li_spot (the same bench): the map's density (sample_li) kept only inside the spots' cones
 * widened 10% where the spots held half the power (sunrise.hdr: 0.75 of its draws reached the cone), else the spots'
 * piecewise-constant bins (sample_li_mix, the rest's weight 0; city.hdr): shadowed 1.45x / 0.97x / 1.02x, lit 0.78x /
 * 0.77x / 1.33x, whole 0.85x / 0.93x / 1.27x at equal spp (ELR_SUNSPLIT_SPOT 2 and 0 still build those).
 * bench_sun_render --lit-point (the library alone, a lit ground point of sunrise.hdr, variance per camera sample, sun's
 * cone | rest): the default 0.164 | 0.0083; the cone-clipped density 0.193 | 0.0022 (the bins: 0.376); the patches
 * renormalised to the cone by rejection (a diagnostic) 0.00015 | 0.0022; sample_li_spot 0.00041 | 0.0022 (the rectangle
 * holds a little sky beyond the cone): 54x less than the default in all. On city.hdr (--lit-point city; its sun 0.247
 * of the patches' mass): the default 1.128 | 0.587, sample_li_spot 0.0052 | 0.226, 3.1x less in all: what is left
 * there is the sky (the rest x cosine), which is why bench_city gains least. The sky by product sampling over the
 * patches instead (sample_li_cos, with sample_li_spot: the last --lit-point row): 0.502 on city, 0.0198 on sunrise,
 * 2.3x and 7.6x more than with the rest x cosine.
 * Variants (on sun_shadow_object, before sample_li_spot; the first with the spots' bins on sunrise.hdr: shadow 1.48x, lit
 * 0.54x, whole 0.61x: its one-texel sun's bins have a constant density under a bilinear le(); the next as changes of
 * that): product sampling as the first sample (sample_li_cos, MIS with the sky sample where both reach): shadow 1.59x
 * (city 1.29x), lit 0.91x (0.73x), whole 0.97x (0.79x); the sky by the map's rest without the cosine: shadow 1.37x;
 * the two light samples without the BSDF sample at diffuse-only vertices: shadow 1.14x (1.24x with product sampling
 * first); a third sampler draw for the sky sample: 1.47x against 1.54x; the sky sample alone where the spots are below
 * the horizon (the same variance as drawing both there: the spot sample's f is 0): shadow 1.54x against 1.48x.
 * With the independent sampler (--random, 16 spp, 8 seeds) the whole image 7.85x / 1.69x / 2.21x less variance at equal
 * spp (lit 18.5x / 9.6x / 2.58x), 3.07x / 0.72x / 0.75x at equal time against the wave default (before sample_li_spot,
 * the cone-clipped patches: lit 0.73x on sun_shadow_object, city's whole image 2.01x).
 *
 * Cited and compared (tutorials/05-appendix-fast-paths.md, A3.14): Kondapaneni et al. 2019 (optimal MIS
 * weights) and Grittmann et al. 2019 (variance-aware MIS) tune the COMBINATION of fixed techniques; here
 * the technique itself changes (its mixture weights), from visibility, as in the light-selection caches
 * of path guiding (Vevoda et al. 2018, Bayesian online regression for adaptive direct illumination). */
#include "elr_internal.h"
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#define ELR_SUN_FLOOR 0.03f /* the spots' share of the light samples where the pilot saw none of them */
#define ELR_SUN_RAYS 2      /* pilot shadow rays per spot and pixel */
#define ELR_SUN_DIRS 64     /* the directions of a spot they choose from (drawn once per cache: the sampler's
                             * cost per pilot ray was a quarter of the pilot's) */
#define ELR_SUN_CELL 3.f    /* a cell's edge in median pixel footprints */
/* 1: a spot's weight is lowered only in cells where no pilot ray of the cell and its 26 neighbours saw it
 * (partly lit cells keep the light's density: a lit point there lost more, 1/p in its sun term, than a
 * shadowed one gained; measured on sun_shadow_object: the lit side of the sphere had 2-4x more variance
 * with v-scaled weights). 0: spot k's weight P_k max(v_k, e) with v_k the seen fraction. */
#ifndef ELR_SUN_DARK_ONLY
#define ELR_SUN_DARK_ONLY 1
#endif

struct elr_sun_cell {
  uint64_t key; /* 0: empty */
  int rays;
  float seen[EL_ENVLIGHT_HOTSPOT_MAX]; /* the pilot's rays that saw spot k; then v_k, then after dilation */
  float alpha;                         /* sum P_k v_k / sum P_k */
  int lowered;                         /* some v_k < 1 */
  int horizon;                         /* every lowered spot lay below all the cell's pilot points' horizons */
  int tested[EL_ENVLIGHT_HOTSPOT_MAX]; /* the pilot's rays towards spot k above their point's horizon */
  el_envlight_mix_weights w;
  float nsum[3];                       /* the sum of the pilot's normals in the cell */
  const el_envlight_mix_cos_table *tab; /* the rest x cosine table of a lowered cell (shared, read-only) */
};

struct elr_sun {
  const elr_light *l;
  const el_envlight_hotspots *hs; /* the light's (elr_light.sun_hs) */
  float cell;     /* the cells' edge (world units) */
  float inv_cell;
  elr_sun_cell *tab;
  size_t mask, used;
  uint64_t *keys; /* after the pilot: tab[i].key for every slot, probed alone (8 bytes a slot, not the cell's
                   * 112: the lookup every vertex makes was 7% of sun_porch's CPU, waiting on the table) */
  float eps;      /* e above */
  float cos_half[EL_ENVLIGHT_HOTSPOT_MAX];
  elr_v3 dirs[EL_ENVLIGHT_HOTSPOT_MAX][ELR_SUN_DIRS]; /* the pilot's directions towards each spot (0: none) */
  el_envlight_mix_cos_table *tabs; /* the lowered cells' tables, one per (weights, rounded normal) */
  size_t ntabs;
  elr_sun_info info;
};

static uint64_t elr__sun_key(const elr_sun *S, elr_v3 p, elr_v3 n) {
  /* (in float, the floor by hand: the libm call and the doubles were most of a lookup; clamped before the
   * conversion: a far or non-finite point shares the border cells) */
  const float lim = (float)((1 << 19) - 1), inv = S->inv_cell;
  float fx = p.x * inv, fy = p.y * inv, fz = p.z * inv, ax = fabsf(n.x), ay = fabsf(n.y), az = fabsf(n.z);
  uint32_t bin = ax >= ay && ax >= az ? (n.x < 0) : ay >= az ? 2u + (n.y < 0) : 4u + (n.z < 0);
  int32_t ix, iy, iz;
  fx = fx >= -lim ? (fx <= lim ? fx : lim) : -lim; fy = fy >= -lim ? (fy <= lim ? fy : lim) : -lim; fz = fz >= -lim ? (fz <= lim ? fz : lim) : -lim;
  ix = (int32_t)fx; iy = (int32_t)fy; iz = (int32_t)fz;
  ix -= (float)ix > fx; iy -= (float)iy > fy; iz -= (float)iz > fz;
  return 1u + (bin | ((uint64_t)(uint32_t)(ix + (1 << 19) - 1) << 3) | ((uint64_t)(uint32_t)(iy + (1 << 19) - 1) << 23) |
               ((uint64_t)(uint32_t)(iz + (1 << 19) - 1) << 43));
}
static uint64_t elr__sun_key_offset(uint64_t key, int dx, int dy, int dz) { /* the same class, a neighbour cell */
  uint64_t k = key - 1u;
  int64_t ix = (int64_t)((k >> 3) & 0xFFFFF) + dx, iy = (int64_t)((k >> 23) & 0xFFFFF) + dy, iz = (int64_t)((k >> 43) & 0xFFFFF) + dz;
  if (ix < 0 || iy < 0 || iz < 0 || ix > 0xFFFFF || iy > 0xFFFFF || iz > 0xFFFFF) return 0;
  return 1u + ((k & 7u) | ((uint64_t)ix << 3) | ((uint64_t)iy << 23) | ((uint64_t)iz << 43));
}
static size_t elr__sun_hash(uint64_t k) {
  k ^= k >> 33; k *= 0xff51afd7ed558ccdULL; k ^= k >> 33; k *= 0xc4ceb9fe1a85ec53ULL; k ^= k >> 33;
  return (size_t)k;
}
static elr_sun_cell *elr__sun_find(const elr_sun *S, uint64_t key) {
  size_t i = elr__sun_hash(key) & S->mask;
  for (;;) {
    elr_sun_cell *c = &S->tab[i];
    if (c->key == key) return c;
    if (c->key == 0) return NULL;
    i = (i + 1) & S->mask;
  }
}
static elr_sun_cell *elr__sun_insert(elr_sun *S, uint64_t key) {
  size_t i = elr__sun_hash(key) & S->mask;
  for (;;) {
    elr_sun_cell *c = &S->tab[i];
    if (c->key == key) return c;
    if (c->key == 0) { c->key = key; S->used++; return c; }
    i = (i + 1) & S->mask;
  }
}

/* the normal class of a vertex: the geometric normal on wo's side */
static elr_v3 elr__sun_side(const elr_hit *h, elr_v3 wo) { return elr_dot(h->ng, wo) >= 0.f ? h->ng : elr_mul(h->ng, -1.f); }

const elr_sun_cell *elr_sun_lookup(const elr_sun *S, const elr_hit *h, elr_v3 wo) {
  uint64_t key;
  size_t i;
  if (!S || !S->keys) return NULL; /* (no cell: the pilot saw no surface) */
  key = elr__sun_key(S, h->p, elr__sun_side(h, wo));
  for (i = elr__sun_hash(key) & S->mask;; i = (i + 1) & S->mask) { /* (elr__sun_find on the keys alone) */
    uint64_t k = S->keys[i];
    if (k == key) return &S->tab[i]; /* (the table holds only lowered cells) */
    if (k == 0) return NULL;
  }
}

typedef struct { elr_v3 p, n; float fp; int hit; int seen[EL_ENVLIGHT_HOTSPOT_MAX], tested[EL_ENVLIGHT_HOTSPOT_MAX]; } elr__sun_pt;
static int elr__cmp_float(const void *a, const void *b) {
  float x = *(const float *)a, y = *(const float *)b;
  return x < y ? -1 : x > y ? 1 : 0;
}

/* the pilot at pixel (x, y): its centre's first hit and the ELR_SUN_RAYS shadow rays towards each spot
 * (fixed numbers from the pixel's position: the same for any thread count) */
static void elr__sun_pilot_pixel(const elr_ctx *C, const elr_sun *S, int x, int y, elr__sun_pt *q) {
  const elr_scene *s = C->s;
  elr_ray ray, ray1;
  elr_hit h;
  elr_v3 wo;
  int k, r;
  uint32_t hs = (uint32_t)x * 0x9E3779B1u ^ (uint32_t)y * 0x85EBCA77u;
  q->hit = 0;
  elr_camera_ray(&C->cam, (float)x + 0.5f, (float)y + 0.5f, &ray);
  if (!elr_intersect(s, ray.o, ray.d, INFINITY, &h)) return;
  elr_camera_ray(&C->cam, (float)x + 1.5f, (float)y + 0.5f, &ray1); /* the pixel's footprint at the hit */
  q->fp = elr_len(elr_sub(elr_add(ray1.o, elr_mul(ray1.d, h.t)), elr_add(ray.o, elr_mul(ray.d, h.t))));
  wo = elr_mul(ray.d, -1.f);
  q->p = h.p; q->n = elr__sun_side(&h, wo); q->hit = 1;
  for (k = 0; k < S->hs->count; k++) {
    q->seen[k] = q->tested[k] = 0;
    for (r = 0; r < ELR_SUN_RAYS; r++) { /* (a direction of the spot's ELR_SUN_DIRS, stratum r of them) */
      elr_v3 d;
      hs = hs * 747796405u + 2891336453u;
      d = S->dirs[k][r * (ELR_SUN_DIRS / ELR_SUN_RAYS) + (int)((hs >> 16) % (ELR_SUN_DIRS / ELR_SUN_RAYS))];
      if (!(elr_dot(d, d) > 0.f) || elr_dot(d, q->n) <= 0.f) continue;
      q->tested[k]++;
      if (!elr_occluded(s, elr_spawn_origin(&h, d), d, INFINITY)) q->seen[k]++;
    }
  }
}
typedef struct {
  const elr_ctx *C;
  const elr_sun *S;
  const int *fb;
  elr__sun_pt *pt;
  int nthreads, t;
} elr__sun_job;
static void *elr__sun_pilot_rows(void *arg) { /* rows t, t + nthreads, ... */
  const elr__sun_job *J = (const elr__sun_job *)arg;
  int x, y, w = J->fb[2] - J->fb[0];
  for (y = J->fb[1] + J->t; y < J->fb[3]; y += J->nthreads)
    for (x = J->fb[0]; x < J->fb[2]; x++) elr__sun_pilot_pixel(J->C, J->S, x, y, &J->pt[(size_t)(y - J->fb[1]) * (size_t)w + (size_t)(x - J->fb[0])]);
  return NULL;
}

/* the normal the rest x cosine part is made for: n rounded to a grid of 1/ELR_SUN_NQ per component and
 * renormalised (about 5 degrees), so that cells of a plane or of nearby normals share tables */
#define ELR_SUN_NQ 12.f
static void elr__sun_qn(const float n[3], float q[3]) {
  float l2;
  q[0] = roundf(n[0] * ELR_SUN_NQ); q[1] = roundf(n[1] * ELR_SUN_NQ); q[2] = roundf(n[2] * ELR_SUN_NQ);
  l2 = q[0] * q[0] + q[1] * q[1] + q[2] * q[2];
  if (!(l2 > 0.f)) { q[0] = n[0]; q[1] = n[1]; q[2] = n[2]; return; }
  l2 = 1.f / sqrtf(l2);
  q[0] *= l2; q[1] *= l2; q[2] *= l2;
}

/* After the pilot: the hash keeps only the lowered cells (a lookup elsewhere ends at an empty slot), and
 * each lowered cell gets a pointer to the rest x cosine table (el_envlight_mix_cos_prepare) of its weights
 * and of its pilot normals' mean, rounded (elr__sun_qn); cells with the same (weights, rounded normal)
 * share one table. Built once, in the cells' order (the same for any thread count), read-only during the
 * render: a lookup is a hash and a pointer. The density at a vertex is then that of its cell's normal, not
 * of its own: still positive wherever the map is (the cosine bounds' floor), and its light sample and its
 * BSDF sample's pdf agree because both come from the cell. */
static int elr__sun_tables(elr_sun *S) {
  enum { KL = 3 + EL_ENVLIGHT_HOTSPOT_MAX + 1 }; /* a table's key: the rounded normal, the weights */
  size_t i, j, nlow = 0, want, omask = S->mask, hmask = 0, *slot = NULL;
  elr_sun_cell *old = S->tab, *nt;
  int k, nk = S->hs->count, prod = S->l->product != 0;
  float *keys = NULL;
  for (i = 0; i <= omask; i++) if (old[i].key && old[i].lowered) nlow++;
  for (want = 16; want < 2 * nlow + 1; want <<= 1) {}
  nt = (elr_sun_cell *)calloc(want, sizeof *nt);
  if (!nt) return -1;
  if (nlow && prod) {
    hmask = want - 1;
    S->tabs = (el_envlight_mix_cos_table *)malloc(nlow * sizeof *S->tabs);
    keys = (float *)malloc(nlow * KL * sizeof *keys);
    slot = (size_t *)calloc(want, sizeof *slot);
    if (!S->tabs || !keys || !slot) { free(nt); free(keys); free(slot); return -1; }
  }
  S->tab = nt; S->mask = want - 1; S->used = 0; S->ntabs = 0;
  for (i = 0; i <= omask; i++) {
    elr_sun_cell *c;
    float key[KL], l2, nn[3];
    uint64_t hk = 1469598103934665603ULL;
    const unsigned char *kb = (const unsigned char *)key;
    if (!old[i].key || !old[i].lowered) continue;
    c = elr__sun_insert(S, old[i].key);
    *c = old[i];
    c->tab = NULL;
    if (!prod) continue;
    memset(key, 0, sizeof key);
    l2 = c->nsum[0] * c->nsum[0] + c->nsum[1] * c->nsum[1] + c->nsum[2] * c->nsum[2];
    l2 = l2 > 0.f ? 1.f / sqrtf(l2) : 0.f;
    nn[0] = c->nsum[0] * l2; nn[1] = c->nsum[1] * l2; nn[2] = c->nsum[2] * l2;
    elr__sun_qn(nn, key);
    for (k = 0; k < nk; k++) key[3 + k] = c->w.spot[k];
    key[KL - 1] = c->w.rest;
    for (j = 0; j < sizeof key; j++) { hk ^= kb[j]; hk *= 1099511628211ULL; }
    for (j = (size_t)hk & hmask; slot[j] && memcmp(&keys[(slot[j] - 1) * KL], key, sizeof key); j = (j + 1) & hmask) {}
    if (!slot[j]) { /* a new table */
      memcpy(&keys[S->ntabs * KL], key, sizeof key);
      el_envlight_mix_cos_prepare(S->l->env_sample, S->hs, &c->w, key, &S->tabs[S->ntabs]);
      slot[j] = ++S->ntabs;
    }
    c->tab = &S->tabs[slot[j] - 1];
  }
  free(old); free(keys); free(slot);
  S->keys = (uint64_t *)malloc((S->mask + 1) * sizeof *S->keys);
  if (!S->keys) return -1;
  for (i = 0; i <= S->mask; i++) S->keys[i] = S->tab[i].key;
  return 0;
}

/* the light's hot spots: found once per light and density, kept in the light (the scene's lights are never
 * const objects; renders of one scene do not run concurrently); NULL: out of memory */
static const el_envlight_hotspots *elr__sun_spots(const elr_light *l, const el_envlight *e) {
  elr_light *lm = (elr_light *)l;
  if (lm->sun_hs && lm->sun_hs_of != e) { el_envlight_hotspots_free(lm->sun_hs); free(lm->sun_hs); lm->sun_hs = NULL; }
  if (!lm->sun_hs) {
    lm->sun_hs = (el_envlight_hotspots *)calloc(1, sizeof *lm->sun_hs);
    if (!lm->sun_hs) return NULL;
    if (el_envlight_hotspots_init(lm->sun_hs, e, NULL) != EL_SUCCESS) memset(lm->sun_hs, 0, sizeof *lm->sun_hs);
    lm->sun_hs_of = e;
  }
  return lm->sun_hs;
}

int elr_sun_build(const elr_ctx *C, const elr_light *l, const int fb[4], int nthreads, elr_sun **out) {
  const elr_scene *s = C->s;
  elr_sun *S;
  elr__sun_pt *pt = NULL;
  float *fps = NULL;
  size_t npt = 0, cap, i, want;
  int k, nk, t;
  double t0 = elr_now(), c0 = elr_cpu_now(), Ps = 0.0;
  *out = NULL;
  S = (elr_sun *)calloc(1, sizeof *S);
  if (!S) return -1;
  S->l = l;
  if (!(S->hs = elr__sun_spots(l, l->env_sample))) { free(S); return -1; }
  if (S->hs->count == 0) { free(S); return 0; } /* nothing to learn */
  nk = S->hs->count;
  for (k = 0; k < nk; k++) { Ps += S->hs->spot[k].share; S->cos_half[k] = cosf(S->hs->spot[k].half_angle); }
  for (k = 0; k < nk; k++) { /* the pilot's directions: the spot's own density, stratified in u[0], fixed numbers */
    el_envlight_mix_weights w;
    uint32_t hs = 0x2545F491u + (uint32_t)k;
    int r;
    memset(&w, 0, sizeof w);
    w.spot[k] = 1.f;
    for (r = 0; r < ELR_SUN_DIRS; r++) {
      float u[2], wi[3], pdf;
      hs = hs * 747796405u + 2891336453u;
      u[0] = ((float)r + (float)(hs >> 8) * (1.f / 16777216.f)) / (float)ELR_SUN_DIRS;
      hs = hs * 747796405u + 2891336453u;
      u[1] = (float)(hs >> 8) * (1.f / 16777216.f);
      el_envlight_sample_li_mix(l->env_sample, S->hs, &w, u, wi, NULL, &pdf);
      S->dirs[k][r] = pdf > 0.f ? elr_from3(wi) : elr_v(0, 0, 0);
    }
  }
  S->eps = (float)(ELR_SUN_FLOOR * (1.0 - Ps) / ((1.0 - ELR_SUN_FLOOR) * (Ps > 0.0 ? Ps : 1.0)));
  if (!(S->eps > 1e-6f)) S->eps = 1e-6f;
  cap = (size_t)(fb[2] - fb[0]) * (size_t)(fb[3] - fb[1]);
  pt = (elr__sun_pt *)malloc(cap * sizeof *pt);
  fps = (float *)malloc(cap * sizeof *fps);
  if (!pt || !fps) goto fail;
  { /* the pilot, on the render's threads (each pixel's result in its own place) */
    pthread_t th[64];
    elr__sun_job jobs[64];
    int started = 0;
    if (nthreads < 1) nthreads = 1;
    if (nthreads > 64) nthreads = 64;
    for (t = 0; t < nthreads; t++) {
      jobs[t].C = C; jobs[t].S = S; jobs[t].fb = fb; jobs[t].pt = pt; jobs[t].nthreads = nthreads; jobs[t].t = t;
    }
    for (t = 1; t < nthreads; t++) if (pthread_create(&th[t], NULL, elr__sun_pilot_rows, &jobs[t]) == 0) started = t; else break;
    if (started < nthreads - 1) { /* (fewer threads started: the rest on this one, in the same places) */
      for (t = started + 1; t < nthreads; t++) elr__sun_pilot_rows(&jobs[t]);
    }
    elr__sun_pilot_rows(&jobs[0]);
    for (t = 1; t <= started; t++) pthread_join(th[t], NULL);
  }
  for (i = 0; i < cap; i++) /* compacted in pixel order */
    if (pt[i].hit) { pt[npt] = pt[i]; fps[npt] = pt[npt].fp; npt++; }
  S->info.pilot_points = (int64_t)npt;
  S->info.pilot_rays = (int64_t)npt * (int64_t)(1 + nk * ELR_SUN_RAYS);
  if (npt == 0) goto none;
  qsort(fps, npt, sizeof *fps, elr__cmp_float);
  S->cell = ELR_SUN_CELL * fps[npt / 2];
  if (!(S->cell > 0.f) || !isfinite(S->cell)) S->cell = 1e-3f * (s->world_radius > 0.f ? s->world_radius : 1.f);
  S->inv_cell = 1.f / S->cell;
  for (want = 1024; want < 2 * npt; want <<= 1) {}
  S->tab = (elr_sun_cell *)calloc(want, sizeof *S->tab);
  if (!S->tab) goto fail;
  S->mask = want - 1;
  for (i = 0; i < npt; i++) { /* in pixel order: the same table for any thread count */
    elr_sun_cell *c = elr__sun_insert(S, elr__sun_key(S, pt[i].p, pt[i].n));
    c->rays += ELR_SUN_RAYS;
    c->nsum[0] += pt[i].n.x; c->nsum[1] += pt[i].n.y; c->nsum[2] += pt[i].n.z;
    for (k = 0; k < nk; k++) { c->seen[k] += (float)pt[i].seen[k]; c->tested[k] += pt[i].tested[k]; }
  }
  for (i = 0; i <= S->mask; i++) { /* v_k */
    elr_sun_cell *c = &S->tab[i];
    if (c->key) for (k = 0; k < nk; k++) c->seen[k] /= (float)c->rays;
  }
  { /* the dilation, into w.spot (a scratch place), then the weights */
    for (i = 0; i <= S->mask; i++) {
      elr_sun_cell *c = &S->tab[i];
      int dx, dy, dz;
      if (!c->key) continue;
      for (k = 0; k < nk; k++) c->w.spot[k] = c->seen[k];
      for (dz = -1; dz <= 1; dz++)
        for (dy = -1; dy <= 1; dy++)
          for (dx = -1; dx <= 1; dx++) {
            uint64_t nkey = elr__sun_key_offset(c->key, dx, dy, dz);
            const elr_sun_cell *o = nkey ? elr__sun_find(S, nkey) : NULL;
            if (o) for (k = 0; k < nk; k++) if (o->seen[k] > c->w.spot[k]) c->w.spot[k] = o->seen[k];
          }
    }
    for (i = 0; i <= S->mask; i++) {
      elr_sun_cell *c = &S->tab[i];
      double a = 0.0;
      if (!c->key) continue;
      c->lowered = 0;
      for (k = 0; k < nk; k++) { /* (only a spot no ray of the 27 cells saw is lowered: ELR_SUN_DARK_ONLY) */
        float v = c->w.spot[k];
        if (ELR_SUN_DARK_ONLY && v > 0.f) v = 1.f;
        c->seen[k] = v;
        if (v < 1.f) c->lowered = 1;
        a += S->hs->spot[k].share * v;
        c->w.spot[k] = S->hs->spot[k].share * (v > S->eps ? v : S->eps);
      }
      c->w.rest = S->hs->rest_share;
      c->horizon = c->lowered;
      for (k = 0; k < nk; k++) if (c->seen[k] < 1.f && c->tested[k] > 0) c->horizon = 0;
      S->info.cells_horizon += c->horizon;
      c->alpha = (float)(a / Ps);
      S->info.cells++;
      if (c->lowered) S->info.cells_lowered++;
      if (c->alpha == 0.f) S->info.cells_dark++;
    }
  }
  if (elr__sun_tables(S) != 0) goto fail;
none:
  S->info.cell = S->cell;
  S->info.spots = nk;
  for (k = 0; k < nk && k < ELR_SUN_INFO_SPOTS; k++) S->info.spot[k] = S->hs->spot[k];
  S->info.floor = ELR_SUN_FLOOR;
  S->info.seconds = elr_now() - t0;
  S->info.cpu_seconds = elr_cpu_now() - c0;
  free(pt); free(fps);
  *out = S;
  return 0;
fail:
  free(pt); free(fps);
  elr_sun_free(S);
  return -1;
}

void elr_sun_free(elr_sun *S) {
  if (!S) return;
  free(S->tabs); /* (S->hs: the light's) */
  free(S->tab); free(S->keys);
  free(S);
}

const elr_sun_info *elr_sun_get_info(const elr_sun *S) { return S ? &S->info : NULL; }
const elr_light *elr_sun_light(const elr_sun *S) { return S ? S->l : NULL; }

/* whether wi lies in a spot's cone (--stats) */
int elr_sun_in_spot(const elr_sun *S, const float wi[3]) {
  int k;
  if (!S) return 0;
  for (k = 0; k < S->hs->count; k++)
    if (wi[0] * S->hs->spot[k].axis[0] + wi[1] * S->hs->spot[k].axis[1] + wi[2] * S->hs->spot[k].axis[2] >= S->cos_half[k]) return 1;
  return 0;
}

void elr_sun_sample(const elr_sun *S, const elr_sun_cell *c, const elr_v3 *n, const float u[2], float wi[3], float L[3], float *pdf) {
  const el_envlight *e = S->l->env_sample;
  if (n && c->horizon) { /* the spots below the horizon: product sampling at n draws none of them already */
    float nn[3];
    elr_to3(*n, nn);
    el_envlight_sample_li_cos(e, nn, u, wi, L, pdf);
    return;
  }
  if (n && c->tab) {
    float nn[3], uu[2], a = c->alpha, pc, pm;
    uu[1] = u[1];
    if (a > 0.f && u[0] < a) { /* sample_li_cos */
      elr_to3(*n, nn);
      uu[0] = fminf(u[0] / a, 0x1.fffffep-1f);
      el_envlight_sample_li_cos(e, nn, uu, wi, L, &pc);
      pm = pc > 0.f ? el_envlight_pdf_li_mix_cos_table(e, S->hs, c->tab, wi) : 0.f;
    } else {
      uu[0] = a > 0.f ? fminf((u[0] - a) / (1.f - a), 0x1.fffffep-1f) : u[0];
      el_envlight_sample_li_mix_cos_table(e, S->hs, c->tab, uu, wi, L, &pm);
      if (!(pm > 0.f)) { *pdf = 0.f; return; }
      if (!(a > 0.f)) { *pdf = pm; return; }
      elr_to3(*n, nn);
      pc = el_envlight_pdf_li_cos(e, nn, wi);
    }
    *pdf = a * pc + (1.f - a) * pm;
    return;
  }
  el_envlight_sample_li_mix(e, S->hs, &c->w, u, wi, L, pdf);
}

float elr_sun_pdf(const elr_sun *S, const elr_sun_cell *c, const elr_v3 *n, const float wi[3]) {
  const el_envlight *e = S->l->env_sample;
  if (n && c->horizon) { float nn[3]; elr_to3(*n, nn); return el_envlight_pdf_li_cos(e, nn, wi); }
  if (n && c->tab) {
    float nn[3], a = c->alpha, pm = el_envlight_pdf_li_mix_cos_table(e, S->hs, c->tab, wi);
    if (!(a > 0.f)) return pm;
    elr_to3(*n, nn);
    return a * el_envlight_pdf_li_cos(e, nn, wi) + (1.f - a) * pm;
  }
  return el_envlight_pdf_li_mix(e, S->hs, &c->w, wi);
}

float elr_sun_cell_alpha(const elr_sun_cell *c) { return c ? c->alpha : 1.f; }
/* whether elr_sun_sample / elr_sun_pdf at a vertex of cell c (with a product normal: has_n) are the renderer's product
 * sampling itself (a horizon cell): render_wave.c then draws them with the default's batched calls, the same bits */
int elr_sun_cell_product(const elr_sun_cell *c, int has_n) { return c && has_n && c->horizon; }

/* --stats: a light sample of the sun's light in direction wi (pdf 0: none), at a vertex of cell c (NULL: the
 * light's own density) */
void elr_sun_count(const elr_sun *S, const elr_sun_cell *c, const float wi[3], float pdf, elr_tstats *ts) {
  ts->sun_looked++;
  if (c) { ts->sun_lowered++; if (c->alpha == 0.f) ts->sun_dark++; }
  if (pdf > 0.f && elr_sun_in_spot(S, wi)) ts->sun_to_spot++;
}

/* elr_light_sample_li's environment sample at a vertex of cell c, with the counts */
void elr_sun_light_sample(const elr_sun *S, const elr_sun_cell *c, const elr_v3 *n, const float u[2], elr_light_sample *ls, elr_tstats *ts) {
  float wi[3], L[3];
  ls->at_point = 0; ls->dist = INFINITY; ls->portal = -1;
  elr_sun_sample(S, c, n, u, wi, L, &ls->pdf);
  ls->wi = elr_from3(wi); ls->L = elr_from3(L);
  elr_sun_count(S, c, wi, ls->pdf, ts);
}

/* The normal of the product density at a vertex of cell c (NULL: elr_bsdf_cos_normal's answer): where
 * elr_bsdf_cos_normal says "the map alone" only because the scene's map has a sun (issue 20's choice for
 * diffuse lobes, elr_bsdf.env_map without a peaked glossy lobe), the same geometric normal on wo's side:
 * in the sun's shadow the rest x cosine (el_envlight_sample_li_mix_cos) pays. The light sample keeps its
 * BSDF-sampled MIS partner there (the callers leave elr_env_light_only out at a lowered cell): measured,
 * the light sample alone had 2.3x MORE variance than the map with MIS on shadowed ground near a wall. */
int elr_sun_cos_normal(const elr_scene *s, const elr_sun_cell *c, const elr_bsdf *b, elr_v3 wo, elr_v3 *n) {
  int i;
  if (!c || !(b->env_map || b->env_sun_test)) return elr_bsdf_cos_normal(b, wo, n); /* (env_sun_test: the sun rule by the normal, ELR_ENVSD_SUNCOS) */
  if (c->horizon) return elr_bsdf_cos_normal(b, wo, n); /* (the renderer's choice; with a normal, elr_sun_sample's product) */
  if (elr_bsdf_lobe_alpha(b) < s->env_lobe_alpha) return 0; /* a peaked glossy lobe: the map alone, with MIS */
  for (i = 0; i < b->nlobes; i++)
    if ((b->lobe[i].flags & ELR_BSDF_TRANSMISSION) && !(b->lobe[i].flags & ELR_BSDF_SPECULAR)) return 0;
  *n = elr_dot(wo, b->ng) < 0.f ? elr_mul(b->ng, -1.f) : b->ng;
  return 1;
}

/* >> --sun split: one sample of the hot spots and one of the rest x cosine (issue 22's "draw one sun and one
 * sky sample"; see the comment at the top). The multi-sample MIS weights over the three techniques (spot p_s,
 * sky p_r, BSDF p_b; one sample each), with the power heuristic: p_s^2 / (p_s^2 + p_r^2 + p_b^2) for the spot
 * sample, p_r^2 / (p_s^2 + p_r^2 + p_b^2) for the sky sample (the other light density: elr_sunsplit_sample's
 * *other), p_b^2 / (p_b^2 + p_s^2 + p_r^2) for the BSDF sample (elr_sunsplit_pdf gives sqrt(p_s^2 + p_r^2)); at
 * every direction the weights of the techniques that can draw it sum to 1. With the spots' bins the supports
 * are disjoint (a bin is in a spot or in the rest: *other is 0); the map's density kept inside the cones
 * overlaps the sky's rest bins there. */
#ifndef ELR_SUNSPLIT_HORIZON
#define ELR_SUNSPLIT_HORIZON 1 /* where every spot lies below the normal's horizon (f is 0 there): 1 the renderer's product
                                * sample (no split), 2 the sky sample alone, 0 both samples anyway */
#endif
#ifndef ELR_SUNSPLIT_SKY_COS
#define ELR_SUNSPLIT_SKY_COS 1 /* 1: the sky by the rest x cosine (el_envlight_sample_li_mix_cos); 0: the map's rest */
#endif
#ifndef ELR_SUNSPLIT_SPOT
#define ELR_SUNSPLIT_SPOT -1 /* the first sample: 0 the spots' bins (sample_li_mix, the spots alone), 1 product sampling
                              * (sample_li_cos: the sun and the sky), 2 the render's own density of the map (sample_li:
                              * le()'s patches under a sun), kept only inside the spots' cones; 3 that density renormalised
                              * to a rectangle of patches around each spot (el_envlight_sample_li_spot on the render's
                              * density's own hot spots); -1: 3 where the render's density has hot spots, else 2 where the
                              * spots hold at least ELR_SUNSPLIT_SPOT_SHARE of the map's power, else 0 */
#endif
#define ELR_SUNSPLIT_SPOT_SHARE 0.5f
#define ELR_SUNSPLIT_NO 33 /* the normals of the sky's tables: an octahedral grid of 33 x 33 points, the axes among
                            * them, the rest within about 4 degrees */
struct elr_sunsplit {
  const elr_light *l;
  const el_envlight *e; /* the density whose hot spots and mixtures are sampled (l->env) */
  const el_envlight_hotspots *hs;
  el_envlight_mix_weights wspot, wsky; /* the spots at their shares and the rest 0; the rest alone */
  float cos_half[EL_ENVLIGHT_HOTSPOT_MAX], sin_half[EL_ENVLIGHT_HOTSPOT_MAX];
  float cos_wide[EL_ENVLIGHT_HOTSPOT_MAX]; /* twice as wide: where the spots' bins are looked for (their pdf, 0 outside) */
  el_envlight_mix_cos_table *tabs;     /* the rest x cosine for each grid normal (ELR_SUNSPLIT_NO^2) */
  int spot;                            /* how the first sample is drawn (ELR_SUNSPLIT_SPOT) */
  el_envlight_hotspots hsb;            /* spot 3: the hot spots of the render's own density (l->env_sample) */
  float ak[EL_ENVLIGHT_HOTSPOT_MAX];   /* spot 3: the probability of drawing spot k (their shares, normalised) */
  double cpu;
};

/* the grid point of the octahedral map (y the pole: Y-up scenes' ground is a point) nearest to unit n */
static int elr__sunsplit_qi(elr_v3 n) {
  float a = fabsf(n.x) + fabsf(n.y) + fabsf(n.z), x, z, h = 0.5f * (float)(ELR_SUNSPLIT_NO - 1);
  int i, j;
  if (!(a > 0.f)) return 0;
  x = n.x / a; z = n.z / a;
  if (n.y < 0.f) {
    float tx = (1.f - fabsf(z)) * (x >= 0.f ? 1.f : -1.f), tz = (1.f - fabsf(x)) * (z >= 0.f ? 1.f : -1.f);
    x = tx; z = tz;
  }
  i = (int)lrintf((x + 1.f) * h); j = (int)lrintf((z + 1.f) * h);
  i = i < 0 ? 0 : i >= ELR_SUNSPLIT_NO ? ELR_SUNSPLIT_NO - 1 : i;
  j = j < 0 ? 0 : j >= ELR_SUNSPLIT_NO ? ELR_SUNSPLIT_NO - 1 : j;
  return j * ELR_SUNSPLIT_NO + i;
}
static void elr__sunsplit_qn(int q, float n[3]) {
  float x = 2.f * (float)(q % ELR_SUNSPLIT_NO) / (float)(ELR_SUNSPLIT_NO - 1) - 1.f;
  float z = 2.f * (float)(q / ELR_SUNSPLIT_NO) / (float)(ELR_SUNSPLIT_NO - 1) - 1.f, y = 1.f - fabsf(x) - fabsf(z), l2;
  if (y < 0.f) {
    float tx = (1.f - fabsf(z)) * (x >= 0.f ? 1.f : -1.f), tz = (1.f - fabsf(x)) * (z >= 0.f ? 1.f : -1.f);
    x = tx; z = tz;
  }
  l2 = 1.f / sqrtf(x * x + y * y + z * z);
  n[0] = x * l2; n[1] = y * l2; n[2] = z * l2;
}

int elr_sunsplit_build(const elr_light *l, elr_sunsplit **out) {
  elr_sunsplit *P;
  double c0;
  int k, q;
  float ps = 0.f;
  *out = NULL;
  P = (elr_sunsplit *)calloc(1, sizeof *P);
  if (!P) return -1;
  P->l = l;
  /* (the sky's rest x cosine from the light's own density, not its env_sample: under a sun the render samples the
   * map by le()'s patches, EL_ENVLIGHT_IMPORTANCE_BILINEAR, whose hot spots give the spot sample (P->hsb) but which
   * has no mixture tables) */
  P->e = l->env;
  if (!(P->hs = elr__sun_spots(l, P->e))) { free(P); return -1; }
  if (P->hs->count == 0) { free(P); return 0; } /* nothing to split */
  c0 = elr_cpu_now(); /* (the tables' time: the hot spots are the light's, found once) */
  for (k = 0; k < P->hs->count; k++) {
    float a = 1.1f * P->hs->spot[k].half_angle + 1e-3f; /* (a margin: the cone bounds its bins' corners and edge midpoints) */
    P->wspot.spot[k] = P->hs->spot[k].share;
    P->cos_half[k] = cosf(a); P->sin_half[k] = sinf(a); P->cos_wide[k] = cosf(2.f * a);
  }
  P->wsky.rest = 1.f;
  for (k = 0; k < P->hs->count; k++) ps += P->hs->spot[k].share;
  P->spot = ELR_SUNSPLIT_SPOT >= 0 ? ELR_SUNSPLIT_SPOT : 3;
  if (P->spot == 3) { /* (no spot in the render's density: the next rule) */
    float as = 0.f;
    if (el_envlight_hotspots_init(&P->hsb, l->env_sample, NULL) != EL_SUCCESS) { free(P); return -1; }
    for (k = 0; k < P->hsb.count; k++) as += P->hsb.spot[k].share;
    for (k = 0; k < P->hsb.count; k++) P->ak[k] = P->hsb.spot[k].share / as;
    if (P->hsb.count == 0) P->spot = ELR_SUNSPLIT_SPOT >= 0 ? 0 : -1;
  }
  if (P->spot < 0) P->spot = ps >= ELR_SUNSPLIT_SPOT_SHARE ? 2 : 0;
  if (P->spot == 2 && el_envlight_prepare_sampling(l->env_sample) != EL_SUCCESS) { el_envlight_hotspots_free(&P->hsb); free(P); return -1; }
  if (ELR_SUNSPLIT_SKY_COS) {
    P->tabs = (el_envlight_mix_cos_table *)malloc((size_t)ELR_SUNSPLIT_NO * ELR_SUNSPLIT_NO * sizeof *P->tabs);
    if (!P->tabs) { el_envlight_hotspots_free(&P->hsb); free(P); return -1; }
    for (q = 0; q < ELR_SUNSPLIT_NO * ELR_SUNSPLIT_NO; q++) {
      float n[3];
      elr__sunsplit_qn(q, n);
      el_envlight_mix_cos_prepare(P->e, P->hs, &P->wsky, n, &P->tabs[q]);
    }
  }
  P->cpu = elr_cpu_now() - c0;
  *out = P;
  return 0;
}
void elr_sunsplit_free(elr_sunsplit *P) {
  if (!P) return;
  free(P->tabs);
  el_envlight_hotspots_free(&P->hsb);
  free(P);
}
double elr_sunsplit_cpu(const elr_sunsplit *P) { return P ? P->cpu : 0.0; }
const elr_light *elr_sunsplit_light(const elr_sunsplit *P) { return P ? P->l : NULL; }
int elr_sunsplit_spot(const elr_sunsplit *P) { return P ? P->spot : -1; }

int elr_sunsplit_at(const elr_sunsplit *P, const elr_light *l, const elr_bsdf *b, const elr_v3 *n) {
  int k;
  if (!P || l != P->l || !n || b->env_mirror) return 0; /* (env_mirror: n is a lobe's proxy, not the normal) */
  if (!ELR_SUNSPLIT_HORIZON) return 2;
  for (k = 0; k < P->hs->count; k++) /* some of spot k's cone above n's horizon: angle(n, axis) < 90 deg + half-angle */
    if (elr_dot(*n, elr_v(P->hs->spot[k].axis[0], P->hs->spot[k].axis[1], P->hs->spot[k].axis[2])) > -P->sin_half[k]) return 2;
  return ELR_SUNSPLIT_HORIZON == 2 ? 1 : 0;
}

/* the sky part's density at d (world, unit) for normal n */
static float elr__sunsplit_sky_pdf(const elr_sunsplit *P, elr_v3 n, const float d[3]) {
  const el_envlight *e = P->e;
  return ELR_SUNSPLIT_SKY_COS ? el_envlight_pdf_li_mix_cos_table(e, P->hs, &P->tabs[elr__sunsplit_qi(n)], d) : el_envlight_pdf_li_mix(e, P->hs, &P->wsky, d);
}
/* whether d lies in a spot's cone (cos_half, or cos_wide) */
static int elr__sunsplit_in_cone(const elr_sunsplit *P, const float d[3], const float *cosk) {
  int k;
  for (k = 0; k < P->hs->count; k++)
    if (d[0] * P->hs->spot[k].axis[0] + d[1] * P->hs->spot[k].axis[1] + d[2] * P->hs->spot[k].axis[2] >= cosk[k]) return 1;
  return 0;
}
/* the first part's density at d (ELR_SUNSPLIT_SPOT) */
static float elr__sunsplit_spot_pdf(const elr_sunsplit *P, elr_v3 n, const float d[3]) {
  if (P->spot == 3) { /* the mixture of the spots' rectangles */
    float p = 0.f;
    int k;
    for (k = 0; k < P->hsb.count; k++) p += P->ak[k] * el_envlight_pdf_li_spot(P->l->env_sample, &P->hsb, k, d);
    return p;
  }
  if (P->spot == 1) { float nn[3]; elr_to3(n, nn); return el_envlight_pdf_li_cos(P->l->env_sample, nn, d); }
  if (!elr__sunsplit_in_cone(P, d, P->spot == 2 ? P->cos_half : P->cos_wide)) return 0.f; /* (the bins: a shortcut only) */
  return P->spot == 2 ? el_envlight_pdf_li(P->l->env_sample, d) : el_envlight_pdf_li_mix(P->e, P->hs, &P->wspot, d);
}

void elr_sunsplit_sample(const elr_sunsplit *P, int k, int parts, elr_v3 n, const float u[2], elr_light_sample *ls, float *other, elr_tstats *ts) {
  const el_envlight *e = P->e;
  float wi[3], L[3];
  ls->at_point = 0; ls->dist = INFINITY; ls->portal = -1;
  if (k == 0 && P->spot == 3) { /* a spot by its share (u[0] reused), then le()'s patches of its rectangle */
    float uu[2], c = 0.f;
    int j = 0;
    while (j + 1 < P->hsb.count && u[0] >= c + P->ak[j]) c += P->ak[j++];
    uu[0] = fminf((u[0] - c) / P->ak[j], 0x1.fffffep-1f); uu[0] = uu[0] > 0.f ? uu[0] : 0.f; uu[1] = u[1];
    el_envlight_sample_li_spot(P->l->env_sample, &P->hsb, j, uu, wi, L, &ls->pdf);
    if (P->hsb.count > 1 && ls->pdf > 0.f) ls->pdf = elr__sunsplit_spot_pdf(P, n, wi); /* (one spot: already it) */
  } else if (k == 0 && P->spot == 1) { float nn[3]; elr_to3(n, nn); el_envlight_sample_li_cos(P->l->env_sample, nn, u, wi, L, &ls->pdf); }
  else if (k == 0 && P->spot == 2) { /* (a sample outside the cones is dropped: the part's density is 0 there) */
    el_envlight_sample_li(P->l->env_sample, u, wi, L, &ls->pdf);
    if (!elr__sunsplit_in_cone(P, wi, P->cos_half)) ls->pdf = 0.f;
  } else if (k == 0) el_envlight_sample_li_mix(e, P->hs, &P->wspot, u, wi, L, &ls->pdf);
  else if (ELR_SUNSPLIT_SKY_COS) el_envlight_sample_li_mix_cos_table(e, P->hs, &P->tabs[elr__sunsplit_qi(n)], u, wi, L, &ls->pdf);
  else el_envlight_sample_li_mix(e, P->hs, &P->wsky, u, wi, L, &ls->pdf);
  ls->wi = elr_from3(wi); ls->L = elr_from3(L);
  /* (the other part's density there: with the spots' bins (ELR_SUNSPLIT_SPOT 0) none, the supports are disjoint) */
  *other = !(ls->pdf > 0.f) || P->spot == 0 || parts != 2 ? 0.f : k == 0 ? elr__sunsplit_sky_pdf(P, n, wi) : elr__sunsplit_spot_pdf(P, n, wi);
  ts->env_product++;
}

float elr_sunsplit_pdf(const elr_sunsplit *P, int parts, elr_v3 n, elr_v3 wi) {
  float d[3], p, q;
  elr_to3(wi, d);
  p = elr__sunsplit_sky_pdf(P, n, d);
  if (parts != 2) return p;
  q = elr__sunsplit_spot_pdf(P, n, d);
  return q > 0.f ? sqrtf(p * p + q * q) : p;
}
