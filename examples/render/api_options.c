/* api_options.c: the render options' directives (pbrt-v3 core/api.cpp's RenderOptions, MakeCamera,
 * MakeFilm, MakeFilter, MakeSampler, MakeIntegrator): Camera "perspective", Film "image", PixelFilter,
 * Sampler (pbrt-v3's and pbrt-v4's) and Integrator, with pbrt-v3's defaults, into elr_scene_desc. */
#include "parser.h"

/* >> directives */
void elr__camera(elr__parser *P, const char *type) {
  elr_scene_desc *d = &P->s->d;
  elr__param *sw;
  if (strcmp(type, "perspective") != 0) {
    elr_warn(P->s, P->dir_file, P->dir_line, "Camera \"%s\" is not supported; using \"perspective\"", type);
  }
  double fov = elr__pfloat(P, "fov", 90.0), fa;
  if (elr__find(P, "halffov")) { /* pbrt-v3: halffov > 0 overrides fov */
    double hf = elr__pfloat(P, "halffov", -1.0);
    if (hf > 0) fov = 2.0 * hf;
  }
  /* the ranges are checked on the values as written (as floats, 179.99 is above 179.99) */
  elr__check_range(P, "fov", fov, 1e-4, 179.99);
  d->fov = (float)fov;
  if (elr__find(P, "frameaspectratio")) {
    fa = elr__pfloat(P, "frameaspectratio", 1.0);
    elr__check_range(P, "frameaspectratio", fa, 1e-6, 1e6);
    d->frameaspect = (float)fa;
    d->has_frameaspect = 1;
  }
  sw = elr__findt(P, "screenwindow", "float", 4);
  if (sw) {
    int i;
    for (i = 0; i < 4; i++) d->screen[i] = (float)sw->num[i];
    if (!(d->screen[1] > d->screen[0]) || !(d->screen[3] > d->screen[2]))
      elr__failf(P, sw->file, sw->line, "Camera: screenwindow must be [xmin xmax ymin ymax] with xmin < xmax and ymin < ymax");
    d->has_screen = 1;
  }
  if (elr__find(P, "lensradius")) {
    double lr = elr__pfloat(P, "lensradius", 0.0);
    if (lr != 0.0) elr_warn(P->s, P->dir_file, P->dir_line, "Camera: \"lensradius\" %g ignored (pinhole camera only)", lr);
  }
  if (elr__find(P, "focaldistance")) elr__pfloat(P, "focaldistance", 1e6);
  elr_xform_invert(&d->cam2world, &P->ctm);
  elr__check_point(P, P->dir_line, elr_xpoint(&d->cam2world, elr_v(0, 0, 0)), "the camera position");
  P->seen_camera = 1;
  /* named coordinate system "camera" */
  {
    int k = elr__name_find(&P->hctx, P->ctx, P->nctx, "camera");
    if (k < 0) {
      ELR_PUSH(P, P->ctx, P->nctx, P->capctx, elr__named);
      P->cs_xf = (elr_xform *)realloc(P->cs_xf, sizeof(elr_xform) * (size_t)P->capctx);
      if (!P->cs_xf) { snprintf(P->err, P->errlen, "out of memory"); longjmp(P->jb, 1); }
      k = P->nctx - 1;
      P->ctx[k].name = elr__strdup(P, "camera", 6);
      elr__name_add(P, &P->hctx, P->ctx, k);
    }
    P->cs_xf[k] = d->cam2world;
  }
}

void elr__film(elr__parser *P, const char *type) {
  elr_scene_desc *d = &P->s->d;
  elr__param *cw;
  const char *fn;
  if (strcmp(type, "image") != 0) elr_warn(P->s, P->dir_file, P->dir_line, "Film \"%s\" is not supported; using \"image\"", type);
  d->xres = elr__pint(P, "xresolution", 1280);
  d->yres = elr__pint(P, "yresolution", 720);
  elr__check_range(P, "xresolution", d->xres, 1, 32768);
  elr__check_range(P, "yresolution", d->yres, 1, 32768);
  if ((double)d->xres * (double)d->yres > 1e8)
    elr__failf(P, P->dir_file, P->dir_line, "Film: %d x %d is more than 1e8 pixels", d->xres, d->yres);
  fn = elr__pstring(P, "filename", "pbrt.exr");
  if (strlen(fn) >= sizeof d->filename) elr__failf(P, P->dir_file, P->dir_line, "Film: filename too long");
  snprintf(d->filename, sizeof d->filename, "%s", fn);
  cw = elr__findt(P, "cropwindow", "float", 4);
  if (cw) {
    int i;
    for (i = 0; i < 4; i++) {
      d->crop[i] = (float)cw->num[i];
      if (!(d->crop[i] >= 0.f && d->crop[i] <= 1.f))
        elr__failf(P, cw->file, cw->line, "Film: cropwindow values must lie in [0, 1]");
    }
    { /* pbrt-v3 sorts each pair */
      float t;
      if (d->crop[0] > d->crop[1]) { t = d->crop[0]; d->crop[0] = d->crop[1]; d->crop[1] = t; }
      if (d->crop[2] > d->crop[3]) { t = d->crop[2]; d->crop[2] = d->crop[3]; d->crop[3] = t; }
    }
    /* the pixel bounds as elr_render computes them (pbrt-v3: ceil of crop times resolution) */
    if (ceil(d->xres * (double)d->crop[1]) <= ceil(d->xres * (double)d->crop[0]) ||
        ceil(d->yres * (double)d->crop[3]) <= ceil(d->yres * (double)d->crop[2]))
      elr__failf(P, cw->file, cw->line, "Film: cropwindow [ %g %g %g %g ] covers no pixel of the %d x %d film", d->crop[0], d->crop[1], d->crop[2],
                d->crop[3], d->xres, d->yres);
  }
  if (elr__find(P, "scale")) {
    double sc = elr__pfloat(P, "scale", 1.0);
    if (sc != 1.0) elr_warn(P->s, P->dir_file, P->dir_line, "Film: \"scale\" %g ignored", sc);
  }
  if (elr__find(P, "diagonal")) elr__pfloat(P, "diagonal", 35.0);
}

void elr__filter(elr__parser *P, const char *type) {
  elr_filter_desc *f = &P->s->d.filter;
  float defw = 2.f;
  memset(f, 0, sizeof *f);
  if (!strcmp(type, "box")) { f->type = ELR_PF_BOX; defw = 0.5f; }
  else if (!strcmp(type, "triangle")) f->type = ELR_PF_TRIANGLE;
  else if (!strcmp(type, "gaussian")) { f->type = ELR_PF_GAUSSIAN; f->alpha = (float)elr__pfloat(P, "alpha", 2.0); }
  else if (!strcmp(type, "mitchell")) {
    f->type = ELR_PF_MITCHELL;
    f->b = (float)elr__pfloat(P, "B", 1.0 / 3.0); f->c = (float)elr__pfloat(P, "C", 1.0 / 3.0);
  } else if (!strcmp(type, "sinc")) { f->type = ELR_PF_SINC; defw = 4.f; f->tau = (float)elr__pfloat(P, "tau", 3.0); }
  else {
    elr_warn(P->s, P->dir_file, P->dir_line, "PixelFilter \"%s\" is not supported; using \"box\"", type);
    f->type = ELR_PF_BOX; defw = 0.5f;
  }
  /* parameters whose absurd values make every filter weight 0 or overflow (a silently black image) */
  if (f->type == ELR_PF_GAUSSIAN) elr__check_range(P, "alpha", f->alpha, 1e-4, 1e3);
  if (f->type == ELR_PF_MITCHELL) { elr__check_range(P, "B", f->b, -100, 100); elr__check_range(P, "C", f->c, -100, 100); }
  if (f->type == ELR_PF_SINC) elr__check_range(P, "tau", f->tau, 1e-2, 1e3);
  f->xw = (float)elr__pfloat(P, "xwidth", defw);
  f->yw = (float)elr__pfloat(P, "ywidth", defw);
  /* envlight's extension: negative filter weights (mitchell's and sinc's lobes) count as 0, so that few
   * samples per pixel cannot overshoot (film.h's el_film_options.nonnegative_filter) */
  f->nonneg = elr__pbool(P, "nonnegative", 0);
  elr__check_range(P, "xwidth", f->xw, 1e-3, 16);
  elr__check_range(P, "ywidth", f->yw, 1e-3, 16);
}

/* pbrt-v4's "string randomization" (sobol, zsobol, paddedsobol) */
static int elr__randomization(elr__parser *P, const char *type, const char *def) {
  static const char *const names[4] = {"none", "permutedigits", "fastowen", "owen"}; /* ELR_RANDOMIZE_* */
  const char *r = elr__pstring(P, "randomization", def);
  elr__param *p = elr__find(P, "randomization");
  int k;
  for (k = 0; k < 4; k++) if (!strcmp(r, names[k])) return k;
  elr__failf(P, p ? p->file : P->dir_file, p ? p->line : P->dir_line,
             "Sampler \"%s\": unknown randomization \"%s\" (none, permutedigits, fastowen, owen)", type, r);
  return ELR_RANDOMIZE_NONE;
}

/* pbrt-v3's MakeSampler (api.cpp) and each sampler's Create: the parameters, with pbrt's defaults */
void elr__sampler(elr__parser *P, const char *type) {
  elr_scene_desc *d = &P->s->d;
  int kind = elr_sampler_kind_from_name(type);
  d->randomize = ELR_RANDOMIZE_NONE; d->has_seed = 0; d->sseed = 0; d->dims = 4; d->jitter = 1;
  if (kind < 0) {
    /* pbrt-v3's "maxmindist", pbrt-v4's "pmj02bn" and "independent" */
    if (!strcmp(type, "independent")) kind = ELR_SAMPLER_RANDOM;
    else if (!strcmp(type, "pmj02bn")) kind = ELR_SAMPLER_ZSOBOL;
    else kind = ELR_SAMPLER_HALTON;
    elr_warn(P->s, P->dir_file, P->dir_line, "Sampler \"%s\" is not supported; using \"%s\"", type, elr_sampler_kind_name(kind));
    if (kind == ELR_SAMPLER_ZSOBOL) d->randomize = ELR_RANDOMIZE_FAST_OWEN;
  }
  d->sampler = kind;
  switch (kind) {
  case ELR_SAMPLER_RANDOM:
    d->spp = elr__pint(P, "pixelsamples", 4);
    break;
  case ELR_SAMPLER_STRATIFIED:
    d->jitter = elr__pbool(P, "jitter", 1);
    d->xs = elr__pint(P, "xsamples", 4);
    d->ys = elr__pint(P, "ysamples", 4);
    d->dims = elr__pint(P, "dimensions", 4);
    elr__check_range(P, "xsamples", d->xs, 1, 4096);
    elr__check_range(P, "ysamples", d->ys, 1, 4096);
    elr__check_range(P, "dimensions", d->dims, 0, 64);
    d->spp = d->xs * d->ys;
    /* every render thread holds xsamples * ysamples * (dimensions + 1) 1D and 2D samples (12 bytes) */
    if ((double)d->spp * (double)(d->dims + 1) > (double)(1 << 24))
      elr__failf(P, P->dir_file, P->dir_line, "Sampler \"stratified\": %d x %d samples in %d dimensions need %.0f MiB per thread (at most 16777216 "
                "samples times dimensions + 1)", d->xs, d->ys, d->dims, (double)d->spp * (d->dims + 1) * 12.0 / 1048576.0);
    break;
  case ELR_SAMPLER_ZEROTWO:
    d->spp = elr__pint(P, "pixelsamples", 16);
    d->dims = elr__pint(P, "dimensions", 4);
    elr__check_range(P, "dimensions", d->dims, 0, 64);
    break;
  case ELR_SAMPLER_SOBOL: case ELR_SAMPLER_ZSOBOL: case ELR_SAMPLER_PADDEDSOBOL:
    d->spp = elr__pint(P, "pixelsamples", 16);
    /* pbrt-v4's parameters; pbrt-v3's sobol has none and is not randomized */
    d->randomize = elr__randomization(P, type, kind == ELR_SAMPLER_SOBOL ? "none" : "fastowen");
    if (elr__find(P, "seed")) { d->has_seed = 1; d->sseed = elr__pint(P, "seed", 0); }
    break;
  default: /* halton */
    d->spp = elr__pint(P, "pixelsamples", 16);
    if (elr__find(P, "samplepixelcenter") && elr__pbool(P, "samplepixelcenter", 0))
      elr_warn(P->s, P->dir_file, P->dir_line, "Sampler: \"samplepixelcenter\" ignored");
    break;
  }
  elr__check_range(P, "pixelsamples", d->spp, 1, 1 << 24);
  if (kind == ELR_SAMPLER_SOBOL || kind == ELR_SAMPLER_ZEROTWO || kind == ELR_SAMPLER_ZSOBOL) {
    int p2 = 1;
    while (p2 < d->spp) p2 <<= 1;
    if (p2 > (1 << 24))
      elr__failf(P, P->dir_file, P->dir_line, "Sampler \"%s\": %d pixel samples, rounded up to a power of two, exceed 16777216", type, d->spp);
    if (p2 != d->spp) {
      elr_warn(P->s, P->dir_file, P->dir_line, "Sampler \"%s\": %d pixel samples rounded up to %d (a power of two)", type, d->spp, p2);
      d->spp = p2;
    }
  }
  if (kind == ELR_SAMPLER_ZEROTWO && (double)d->spp * (double)(d->dims + 1) > (double)(1 << 24))
    elr__failf(P, P->dir_file, P->dir_line, "Sampler \"%s\": %d samples in %d dimensions need %.0f MiB per thread (at most 16777216 "
              "samples times dimensions + 1)", type, d->spp, d->dims, (double)d->spp * (d->dims + 1) * 12.0 / 1048576.0);
}

void elr__integrator(elr__parser *P, const char *type) {
  elr_scene_desc *d = &P->s->d;
  const char *ls;
  P->integ_file = P->dir_file; P->integ_line = P->dir_line;
  if (!strcmp(type, "directlighting")) {
    /* pbrt-v3's strategy: "all" (UniformSampleAllLights, each light's samples) or "one" (UniformSampleOneLight,
     * one light chosen uniformly) */
    const char *st = elr__pstring(P, "strategy", "all");
    d->integrator_path = 0;
    if (!strcmp(st, "all")) d->direct_one = 0;
    else if (!strcmp(st, "one")) d->direct_one = 1;
    else elr__failf(P, elr__find(P, "strategy")->file, elr__find(P, "strategy")->line, "Integrator \"directlighting\": strategy must be \"all\" or \"one\"");
    /* envlight's extension (default "off": bench_render --split measured no gain on its scenes): "auto" chooses the light and BSDF samples per camera sample from a pilot's
     * measured variance and cost (render.c), "off" keeps each light's "samples" */
    st = elr__pstring(P, "splitting", "off");
    if (!strcmp(st, "auto")) d->split_auto = 1;
    else if (!strcmp(st, "off")) d->split_auto = 0;
    else elr__failf(P, elr__find(P, "splitting")->file, elr__find(P, "splitting")->line, "Integrator \"directlighting\": splitting must be \"auto\" or \"off\"");
  } else {
    const char *st;
    if (strcmp(type, "path") != 0) {
      /* pbrt-v3's other integrators (whitted, volpath, bdpt, mlt, sppm, ambientocclusion) and anything
       * else: the path tracer, with the scene's maxdepth; the other parameters belong to the integrator
       * that is not there */
      int i, keep = 0;
      for (i = 0; i < P->nparams; i++)
        if (strcmp(P->params[i].name, "maxdepth") != 0) P->params[i].used = 1;
        else keep = 1;
      elr_warn(P->s, P->dir_file, P->dir_line, "Integrator \"%s\" is not supported; using \"path\"%s, its other parameters ignored", type,
               keep ? " with its maxdepth" : " (maxdepth 5)");
      d->integrator_path = 1; d->rrthreshold = 1.f;
      d->light_strategy = ELR_LSTRAT_SPATIAL;
      d->maxdepth = elr__pint(P, "maxdepth", 5);
      elr__check_range(P, "maxdepth", d->maxdepth, 0, 100000);
      d->light_sampling = ELR_LS_MIS;
      return;
    }
    d->integrator_path = 1;
    d->rrthreshold = (float)elr__pfloat(P, "rrthreshold", 1.0);
    /* pbrt-v3's lightsamplestrategy (default "spatial", which is "power" here: lightdistrib.c) */
    st = elr__pstring(P, "lightsamplestrategy", "spatial");
    if (!strcmp(st, "uniform")) d->light_strategy = ELR_LSTRAT_UNIFORM;
    else if (!strcmp(st, "power")) d->light_strategy = ELR_LSTRAT_POWER;
    else if (!strcmp(st, "spatial")) d->light_strategy = ELR_LSTRAT_SPATIAL;
    else elr__failf(P, elr__find(P, "lightsamplestrategy")->file, elr__find(P, "lightsamplestrategy")->line,
                    "Integrator \"path\": lightsamplestrategy must be \"uniform\", \"power\" or \"spatial\"");
  }
  d->maxdepth = elr__pint(P, "maxdepth", 5);
  elr__check_range(P, "maxdepth", d->maxdepth, 0, 100000);
  /* envlight's extension: which strategies estimate direct light (a test and benchmark hook) */
  ls = elr__pstring(P, "lightsampling", "mis");
  if (!strcmp(ls, "mis")) d->light_sampling = ELR_LS_MIS;
  else if (!strcmp(ls, "light")) d->light_sampling = ELR_LS_LIGHT;
  else if (!strcmp(ls, "bsdf")) d->light_sampling = ELR_LS_BSDF;
  else elr__failf(P, elr__find(P, "lightsampling")->file, elr__find(P, "lightsampling")->line, "Integrator: lightsampling must be \"mis\", \"light\" or \"bsdf\"");
  if (elr__find(P, "pixelbounds")) elr_warn(P->s, P->dir_file, P->dir_line, "Integrator: \"pixelbounds\" ignored");
  if (elr__find(P, "pixelbounds")) elr__find(P, "pixelbounds")->used = 1;
}
