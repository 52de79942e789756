/* stats.c: what a render built and what each part cost, as `render --stats` prints it (pbrt-v3's
 * core/stats.cpp keeps counters and timers and prints them at the end of a render; here elr_render
 * fills an elr_stats: render.c), and the clock the timings use. */
#define _POSIX_C_SOURCE 200809L
#include "elr_internal.h"
#include <time.h>

double elr_now(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* CPU seconds of the whole process (every thread) */
double elr_cpu_now(void) {
  struct timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

void elr_stats_print(const elr_stats *st, void *fp) {
  FILE *f = (FILE *)fp;
  uint64_t rays = st->camera_rays + st->bounce_rays + st->shadow_rays + st->bsdf_light_rays;
  fprintf(f, "render statistics\n");
  static const char *rz[4] = {", no randomization", ", random digit permutation", ", fast Owen scrambling", ", Owen scrambling"};
  int scrambled = st->sampler == ELR_SAMPLER_SOBOL || st->sampler == ELR_SAMPLER_ZSOBOL || st->sampler == ELR_SAMPLER_PADDEDSOBOL;
  const char *r = scrambled ? rz[st->sampler_randomization & 3] : "";
  fprintf(f, "  image              %d x %d, %d spp (sampler %s%s), %d thread%s, %s, maxdepth %d\n", st->width, st->height, st->spp,
          elr_sampler_kind_name(st->sampler), r,
          st->nthreads, st->nthreads == 1 ? "" : "s", st->integrator_path ? "path" : "directlighting", st->maxdepth);
  fprintf(f, "  parse              %8.3f s (images and meshes read: %.3f s)\n", st->t_parse, st->t_images);
  fprintf(f, "  embree build       %8.3f s  %10.1f KiB\n", st->t_embree, (double)st->bytes_embree / 1024.0);
  fprintf(f, "  textures (level 0) %10.1f KiB  (environment map image included)\n", (double)st->bytes_textures / 1024.0);
  fprintf(f, "  MIP maps           %d image texture%s, %d level%s built, %.1f KiB\n", st->mip_textures,
          st->mip_textures == 1 ? "" : "s", st->mip_levels_built, st->mip_levels_built == 1 ? "" : "s", (double)st->bytes_mip / 1024.0);
  if (st->nothing_emits) fprintf(f, "  light sampling     no: nothing emits (the image is black; no ray traced)\n");
  else
    fprintf(f, "  light sampling     %s%s\n", st->light_sampling_used ? "yes" : "no (no surface has a non-specular lobe)",
            st->light_samples_batched ? "; a wave's environment samples drawn together" : "");
  if (!st->nothing_emits) {
    static const char *loops[3] = {"one sample at a time (the reference)", "?" /* (the batched loop, gone) */,
                                   "waves of up to 256 camera samples (render_wave.c)"};
    static const char *apis[4] = {"rtcIntersect1 / rtcOccluded1", "packets of 16", "rtcIntersect1M streams", "rtcIntersectNp streams"};
    fprintf(f, "  loop               %s", st->loop >= 0 && st->loop < 3 ? loops[st->loop] : "?");
    if (st->loop == 2) {
      fprintf(f, ", Embree %s", st->wave_api >= 0 && st->wave_api < 4 ? apis[st->wave_api] : "?");
      if (st->t_render > 0 && st->nthreads > 0)
        fprintf(f, "; %.0f%% of the loop's time inside Embree", 100.0 * st->t_embree_loop / (st->t_render * st->nthreads));
    }
    fprintf(f, "\n");
    if (st->split_auto)
      fprintf(f, "  splitting          %d light and BSDF sample pair%s per camera sample, chosen by a pilot (%.3f s): relative "
              "variance %.3g / %.3g and CPU %.3f / %.3f s at 1 / 4 pairs; predicted error x time %.2fx better than 1 pair\n",
              st->split, st->split == 1 ? "" : "s", st->t_split_pilot, st->split_var[0], st->split_var[1], st->split_cpu[0], st->split_cpu[1],
              st->split_gain);
    else if (st->split > 1) fprintf(f, "  splitting          %d light and BSDF sample pairs per camera sample (given)\n", st->split);
  }
  fprintf(f, "  env distribution   %s  %8.3f s  %10.1f KiB\n", st->distribution_built ? "built" : "not built", st->t_distribution,
          (double)st->bytes_distribution / 1024.0);
  fprintf(f, "  lights             %d, %d emitting (%d area); next-event estimation: %s; light distribution %s", st->lights,
          st->lights_emitting, st->lights_area, st->light_strategy, st->light_distribution_built ? "built" : "not built");
  if (st->light_distribution_built) fprintf(f, " (%.1f KiB, %.3f s)", (double)st->bytes_light_distribution / 1024.0, st->t_light_distribution);
  fprintf(f, "\n");
  {
    static const char *kinds[4] = {"infinite", "point", "distant", "area"}, *shapes[3] = {"trianglemesh", "sphere", "disk"};
    int i;
    for (i = 0; i < st->nlight_stats; i++) {
      const elr_light_stats *l = &st->light[i];
      fprintf(f, "    light %-3d        %s", i, kinds[l->kind & 3]);
      if (l->kind == 3) {
        fprintf(f, " on %s %d", shapes[l->shape_kind % 3], l->shape);
        if (l->shape_kind == 0) fprintf(f, " (%d triangle%s)", l->ntri, l->ntri == 1 ? "" : "s");
        fprintf(f, "%s, area %.4g", l->twosided ? ", two-sided" : "", l->area);
      }
      if (!l->emits) { fprintf(f, ": emits nothing\n"); continue; }
      if (l->pick > 0.f) fprintf(f, "; chosen with p = %.4g", l->pick);
      if (l->power > 0.0) fprintf(f, ", power %.4g", l->power);
      if (l->kind == 0 && l->tables_built) {
        static const char *im[4] = {"cellaverage", "pbrt-v3", "texel", "bilinear"};
        if (l->env_portals) {
          /* below */
        } else if (l->env_product)
          fprintf(f, "; sampled by product sampling (map x cosine: el_envlight_sample_li_cos)%s%s%s",
                  l->env_map_built ? ", the map alone where a rough lobe transmits or a glossy lobe is peaked" : "",
                  l->env_map_built ? ", importance " : "", l->env_map_built ? im[l->env_importance & 3] : "");
        else fprintf(f, "; sampled by the map alone (el_envlight_sample_li, importance %s)", im[l->env_importance & 3]);
        if (l->env_importance_auto) fprintf(f, " (le()'s patch density: the default under a sun map, issue 22)");
      }
      if (l->kind == 0 && l->env_portals) {
        double n = (double)(l->env_portal_used + l->env_portal_fallback);
        fprintf(f, "; portal strategy: %d portal%s (el_envlight_portal_sample_li, %.1f KiB, map share %.2f behind a portal's plane%s), used for %.1f%% of %llu light samples, the map alone (el_envlight_sample_li) for the rest (points behind every portal)",
                l->env_portals, l->env_portals == 1 ? "" : "s", (double)l->env_portal_bytes / 1024.0, l->env_portal_share,
                l->env_portal_compensated ? ", compensated" : "", n > 0 ? 100.0 * (double)l->env_portal_used / n : 0.0, (unsigned long long)(l->env_portal_used + l->env_portal_fallback));
      }
      if (l->kind == 0) fprintf(f, "; sampling tables %s", l->tables_built ? "built" : "not built");
      if (l->kind == 3 && l->shape_kind == 0) fprintf(f, "; area CDF %s", l->tables_built ? "built" : "not built");
      if (l->tables_built) fprintf(f, " (%.1f KiB)", (double)l->bytes / 1024.0);
      fprintf(f, "\n");
    }
    if (st->lights > st->nlight_stats) fprintf(f, "    (%d more lights)\n", st->lights - st->nlight_stats);
  }
  if (st->env_product_samples + st->env_map_samples > 0) {
    float a = 0.f, b = INFINITY, sun = 0.f;
    int i;
    for (i = 0; i < st->nlight_stats; i++)
      if (st->light[i].env_product) { a = st->light[i].env_lobe_alpha; b = st->light[i].env_light_alpha; sun = st->light[i].env_sun_share; }
    fprintf(f, "  env strategies     %llu light samples by product sampling (%llu of them alone, without a BSDF sample: lobes "
               "diffuse or of alpha >= %g; around the mirror direction for metal of alpha < %g without a sun), %llu by the map "
               "alone (metal of alpha < %g under a sun, rough transmission%s); "
               "the map's sun share %.3f\n",
            (unsigned long long)st->env_product_samples, (unsigned long long)st->env_light_only_samples, (double)b, (double)a,
            (unsigned long long)st->env_map_samples, (double)a, sun > ELR_ENV_SUN_SHARE ? ", diffuse lobes under a sun by --env-sun-diffuse map or suncos" : "", (double)sun);
  }
  if (st->sun_used) { /* issue 22 (sun.c) */
    double n = (double)st->sun_looked;
    int k;
    fprintf(f, "  sun cache          %d hot spot%s:", st->sun_spots, st->sun_spots == 1 ? "" : "s");
    for (k = 0; k < st->sun_spots && k < 8; k++)
      fprintf(f, " (axis %.3f %.3f %.3f, half-angle %.2f deg, share %.3f)", (double)st->sun_spot_axis[k][0], (double)st->sun_spot_axis[k][1],
              (double)st->sun_spot_axis[k][2], (double)st->sun_spot_half_angle[k] * 57.29577951308232, (double)st->sun_spot_share[k]);
    fprintf(f, "; pilot %lld points, %lld rays, %.3f s; %lld cells of %.4g, %lld lowered (%lld where no spot was seen; "
               "%lld with the spots below the horizon: product sampling kept where the lobe takes it), floor %.2f\n",
            (long long)st->sun_pilot_points, (long long)st->sun_pilot_rays, st->t_sun, (long long)st->sun_cells, (double)st->sun_cell,
            (long long)st->sun_cells_lowered, (long long)st->sun_cells_dark, (long long)st->sun_cells_horizon, (double)st->sun_floor);
    fprintf(f, "  sun sharing        %llu light samples of the sun's light: %.1f%% at vertices where the cache lowered the spots "
               "(%.1f%% where it saw none: shadowed), %.1f%% elsewhere; %.1f%% of all landed in a spot's cone (sun), %.1f%% in the rest (sky)\n",
            (unsigned long long)st->sun_looked, n > 0 ? 100.0 * (double)st->sun_lowered / n : 0.0, n > 0 ? 100.0 * (double)st->sun_dark / n : 0.0,
            n > 0 ? 100.0 * (1.0 - (double)st->sun_lowered / n) : 0.0, n > 0 ? 100.0 * (double)st->sun_to_spot / n : 0.0,
            n > 0 ? 100.0 * (1.0 - (double)st->sun_to_spot / n) : 0.0);
  }
  if (st->sunsplit_used) /* issue 22 (sun.c): --sun split */
    fprintf(f, "  sun split          %llu vertices drew a light sample of the hot spots (%s) and one of the rest x cosine, %llu the "
               "rest alone (every spot below the horizon); tables %.3f s CPU\n",
            (unsigned long long)(st->sunsplit_vertices - st->sunsplit_sky_only),
            st->sunsplit_spot == 3 ? "le()'s patches around their cones" : st->sunsplit_spot == 2 ? "the map's density inside their cones" : st->sunsplit_spot == 1 ? "product sampling" : "their bins",
            (unsigned long long)st->sunsplit_sky_only, st->t_sun_cpu);
  fprintf(f, "  film               %10.1f KiB; splat buffer %s\n", (double)st->bytes_film / 1024.0,
          st->splats_allocated ? "allocated" : "not allocated (nothing splats)");
  fprintf(f, "  render             %8.3f s  (CPU %.3f s)\n", st->t_render, st->t_render_cpu);
  fprintf(f, "  rays               %llu camera, %llu bounce, %llu shadow (light samples), %llu BSDF-sampled light; %llu total\n",
          (unsigned long long)st->camera_rays, (unsigned long long)st->bounce_rays, (unsigned long long)st->shadow_rays,
          (unsigned long long)st->bsdf_light_rays, (unsigned long long)rays);
  fprintf(f, "  rejected samples   %llu (NaN, infinite or negative radiance)\n", (unsigned long long)st->rejected_samples);
}
