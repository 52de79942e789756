/* paramset.c: a directive's parameter list, "type name" [values] (pbrt-v3 core/paramset.cpp: ParamSet and
 * TextureParams): reading it (elr__read_params), typed lookups with defaults (elr__pfloat, elr__pint,
 * elr__pbool, elr__pstring, elr__ppoint, elr__prgb with pbrt-v3's spectral forms: rgb, xyz, blackbody,
 * spectrum), texture parameters (elr__ptex: a named texture or a constant one), the parameters nobody
 * read (ReportUnused: a warning), and the range checks of values and world coordinates. */
#include "parser.h"

/* >> parameter lists */
static const char *elr__canon_type(const char *t) {
  if (!strcmp(t, "point")) return "point3";
  if (!strcmp(t, "normal")) return "normal3";
  if (!strcmp(t, "normal3")) return "normal3";
  if (!strcmp(t, "vector")) return "vector3";
  if (!strcmp(t, "color")) return "rgb";
  return t;
}
void elr__read_params(elr__parser *P) {
  P->nparams = 0;
  for (;;) {
    elr__tok t = elr__peek(P), v;
    elr__param *pp;
    char ty[64], nm[128];
    int nv = 0, cap = 8, isstr = -1;
    double *nums; char **strs;
    if (t.kind != T_STRING) break;
    elr__next(P);
    if (P->nparams >= ELR_MAX_PARAMS) elr__fail(P, t.line, "too many parameters (more than %d)", ELR_MAX_PARAMS);
    if (sscanf(t.s, "%63s %127s", ty, nm) != 2)
      elr__fail(P, t.line, "parameter declaration \"%s\" is not \"type name\"", t.s);
    {
      const char *ct = elr__canon_type(ty);
      static const char *known[] = {"integer", "float", "point2", "vector2", "point3", "vector3", "normal3",
                                    "rgb", "spectrum", "xyz", "blackbody", "bool", "string", "texture", "point4"};
      int k, ok = 0;
      for (k = 0; k < (int)(sizeof known / sizeof known[0]); k++) if (!strcmp(ct, known[k])) ok = 1;
      if (!ok) elr__fail(P, t.line, "unknown parameter type \"%s\" in \"%s\"", ty, t.s);
      pp = &P->params[P->nparams++];
      memset(pp, 0, sizeof *pp);
      snprintf(pp->type, sizeof pp->type, "%s", ct);
      snprintf(pp->name, sizeof pp->name, "%s", nm);
      pp->line = t.line; pp->file = elr__curfile(P);
    }
    nums = (double *)elr__grow(P, 0, sizeof(double) * (size_t)cap);
    strs = (char **)elr__grow(P, 1, sizeof(char *) * (size_t)cap);
    v = elr__next(P);
    if (v.kind == T_LBR) {
      for (;;) {
        v = elr__next(P);
        if (v.kind == T_RBR) break;
        if (v.kind == T_EOF) elr__fail(P, t.line, "parameter \"%s\": file ends inside [ ]", t.s);
        if (v.kind == T_LBR) elr__fail(P, v.line, "parameter \"%s\": nested '['", t.s);
        if (nv == cap) { /* the list's kind is known by now (cap >= 8): only its array grows */
          if (cap > (1 << 27)) elr__fail(P, v.line, "parameter \"%s\": too many values", t.s);
          cap *= 2;
          if (isstr == 1) strs = (char **)elr__grow(P, 1, sizeof(char *) * (size_t)cap);
          else nums = (double *)elr__grow(P, 0, sizeof(double) * (size_t)cap);
        }
        if (v.kind == T_NUM) {
          if (isstr == 1) elr__fail(P, v.line, "parameter \"%s\": numbers mixed with strings", t.s);
          isstr = 0; nums[nv++] = v.num;
        } else if (v.kind == T_STRING || elr__wordis(&v, "true") || elr__wordis(&v, "false")) {
          if (isstr == 0) elr__fail(P, v.line, "parameter \"%s\": strings mixed with numbers", t.s);
          isstr = 1; strs[nv++] = v.kind == T_STRING ? (char *)v.s : elr__strdup(P, v.s, v.len);
        } else {
          if (v.kind == T_WORD && v.len <= 8 && (!strncmp(v.s, "inf", 3) || !strncmp(v.s, "nan", 3) || !strncmp(v.s, "Inf", 3) || !strncmp(v.s, "NaN", 3)))
            elr__fail(P, v.line, "parameter \"%s\": \"%.*s\" is not a finite number", t.s, (int)v.len, v.s);
          elr__fail(P, v.line, "parameter \"%s\": unexpected token in value list (missing ']'?)", t.s);
        }
      }
    } else if (v.kind == T_NUM) {
      isstr = 0; nums[nv++] = v.num;
    } else if (v.kind == T_STRING || elr__wordis(&v, "true") || elr__wordis(&v, "false")) {
      isstr = 1; strs[nv++] = v.kind == T_STRING ? (char *)v.s : elr__strdup(P, v.s, v.len);
    } else {
      elr__fail(P, v.kind == T_EOF ? t.line : v.line, "parameter \"%s\" has no value%s", t.s,
                v.kind == T_EOF ? " (file ends early)" : "");
    }
    /* the arrays at their final size, then in the arena */
    if (nv > 8) {
      if (isstr == 1) strs = (char **)elr__grow(P, 1, sizeof(char *) * (size_t)nv);
      else nums = (double *)elr__grow(P, 0, sizeof(double) * (size_t)nv);
    }
    elr__grow_keep(P, 0);
    elr__grow_keep(P, 1);
    pp->num = nums; pp->str = strs; pp->n = nv; pp->isstr = isstr == 1;
    {
      int wants_str = !strcmp(pp->type, "string") || !strcmp(pp->type, "texture") || !strcmp(pp->type, "bool");
      if (nv > 0 && wants_str != pp->isstr && strcmp(pp->type, "spectrum") != 0)
        elr__failf(P, pp->file, t.line, "parameter \"%s %s\": %s values expected", pp->type, pp->name,
                  wants_str ? "string" : "numeric");
      if (!strcmp(pp->type, "bool")) {
        int i;
        for (i = 0; i < nv; i++)
          if (strcmp(strs[i], "true") && strcmp(strs[i], "false"))
            elr__failf(P, pp->file, t.line, "parameter \"bool %s\": value \"%s\" is neither true nor false", pp->name, strs[i]);
      }
      if (!strcmp(pp->type, "integer")) {
        int i;
        for (i = 0; i < nv; i++)
          if (nums[i] != floor(nums[i]))
            elr__failf(P, pp->file, t.line, "parameter \"integer %s\": %g is not an integer", pp->name, nums[i]);
          else if (fabs(nums[i]) > 2147483647.0)
            elr__failf(P, pp->file, t.line, "parameter \"integer %s\": %.0f is outside the 32-bit integer range", pp->name, nums[i]);
      }
    }
  }
}

elr__param *elr__find(elr__parser *P, const char *name) {
  int i;
  for (i = 0; i < P->nparams; i++) if (!strcmp(P->params[i].name, name)) return &P->params[i];
  return NULL;
}
elr__param *elr__findt(elr__parser *P, const char *name, const char *type, int count) {
  elr__param *p = elr__find(P, name);
  if (!p) return NULL;
  if (strcmp(p->type, type) != 0)
    elr__failf(P, p->file, p->line, "%s: parameter \"%s\" has type \"%s\", expected \"%s\"", P->dir_name, name, p->type, type);
  if (count > 0 && p->n != count)
    elr__failf(P, p->file, p->line, "%s: parameter \"%s %s\" takes %d value%s, got %d", P->dir_name, type, name, count,
              count == 1 ? "" : "s", p->n);
  if (count < 0 && p->n % (-count) != 0)
    elr__failf(P, p->file, p->line, "%s: parameter \"%s %s\" needs a multiple of %d values, got %d", P->dir_name, type, name,
              -count, p->n);
  p->used = 1;
  return p;
}
double elr__pfloat(elr__parser *P, const char *name, double def) {
  elr__param *p = elr__find(P, name);
  if (p && !strcmp(p->type, "integer")) { /* pbrt-v3 would ignore it; we accept an integer for a float */
    if (p->n != 1) elr__findt(P, name, "integer", 1);
    p->used = 1; return p->num[0];
  }
  p = elr__findt(P, name, "float", 1);
  return p ? p->num[0] : def;
}
int elr__pint(elr__parser *P, const char *name, int def) {
  elr__param *p = elr__findt(P, name, "integer", 1);
  return p ? (int)p->num[0] : def;
}
int elr__pbool(elr__parser *P, const char *name, int def) {
  elr__param *p = elr__findt(P, name, "bool", 1);
  return p ? !strcmp(p->str[0], "true") : def;
}
const char *elr__pstring(elr__parser *P, const char *name, const char *def) {
  elr__param *p = elr__findt(P, name, "string", 1);
  return p ? p->str[0] : def;
}
/* A "spectrum", "blackbody" or "xyz" value as RGB, converted as pbrt-v3 does (spectrum.c). For a light
 * (P->light_param) a negative value given (a spectrum sample, a blackbody scale, an X, Y or Z) is an
 * error, and the negative RGB components that a spectrum outside the sRGB gamut converts to (a
 * normalised 1500 K blackbody is R 0.0111, G 0.00148, B -0.00022) are clamped to 0: pbrt-v3 keeps them, and here the film would reject the
 * negative radiance they make. */
static elr_v3 elr__pspectral(elr__parser *P, elr__param *p) {
  double rgb[3];
  int negative = 0, i;
  p->used = 1;
  if (!strcmp(p->type, "xyz")) { /* Spectrum::FromXYZ */
    double xyz[3];
    if (p->n != 3) elr__failf(P, p->file, p->line, "%s: parameter \"xyz %s\" takes 3 values (X Y Z), got %d", P->dir_name, p->name, p->n);
    xyz[0] = p->num[0]; xyz[1] = p->num[1]; xyz[2] = p->num[2];
    negative = xyz[0] < 0 || xyz[1] < 0 || xyz[2] < 0;
    elr_xyz_to_rgb(xyz, rgb);
  } else if (!strcmp(p->type, "blackbody")) { /* ParamSet::AddBlackbodySpectrum: a (temperature, scale) pair */
    double T;
    if (p->n != 2)
      elr__failf(P, p->file, p->line, "%s: parameter \"blackbody %s\" takes 2 values (temperature in kelvin, scale), pbrt-v3's format; got %d%s",
                 P->dir_name, p->name, p->n, p->n == 1 ? " (pbrt-v4 scenes give the temperature alone)" : "");
    T = p->num[0];
    if (!(T > 0.0))
      elr__failf(P, p->file, p->line, "%s: parameter \"blackbody %s\": the temperature %g K must be positive", P->dir_name, p->name, T);
    elr_blackbody_rgb(T, rgb);
    rgb[0] *= p->num[1]; rgb[1] *= p->num[1]; rgb[2] *= p->num[1];
    negative = p->num[1] < 0;
  } else { /* "spectrum": (wavelength, value) pairs, inline or in a .spd file (AddSampledSpectrum, ...Files) */
    const double *v = p->num;
    double *lam, *val, *file_vals = NULL;
    int n = p->n, i, bad = 0;
    const char *what = "the list";
    char *path = NULL;
    if (p->isstr) {
      size_t len;
      char *txt;
      if (p->n != 1) elr__failf(P, p->file, p->line, "%s: parameter \"spectrum %s\" takes 1 file name, got %d", P->dir_name, p->name, p->n);
      path = elr__resolve(P, p->str[0]);
      txt = elr__read_file(P, path, &len, p->line);
      n = elr_float_file_parse(txt, len, NULL, 0, &bad);
      if (n < 0) elr__failf(P, p->file, p->line, "%s: spectrum file \"%s\": line %d is not a list of numbers", P->dir_name, path, bad);
      file_vals = (double *)elr__alloc(P, sizeof(double) * ((size_t)n + 1));
      elr_float_file_parse(txt, len, file_vals, n, &bad);
      v = file_vals;
      what = "the file";
    }
    if (n < 2 || n % 2 != 0) {
      if (path) elr__failf(P, p->file, p->line, "%s: spectrum file \"%s\" holds %d numbers: (wavelength, value) pairs expected", P->dir_name, path, n);
      elr__failf(P, p->file, p->line, "%s: parameter \"spectrum %s\" takes (wavelength, value) pairs: got %d numbers", P->dir_name, p->name, n);
    }
    n /= 2;
    lam = (double *)elr__alloc(P, sizeof(double) * (size_t)n);
    val = (double *)elr__alloc(P, sizeof(double) * (size_t)n);
    for (i = 0; i < n; i++) {
      lam[i] = v[2 * i]; val[i] = v[2 * i + 1];
      if (val[i] < 0) negative = 1;
      if (i > 0 && !(lam[i] > lam[i - 1]))
        elr__failf(P, p->file, p->line, "%s: parameter \"spectrum %s\": the wavelengths of %s%s%s are not increasing (%g after %g)", P->dir_name,
                   p->name, what, path ? " " : "", path ? path : "", lam[i], lam[i - 1]);
    }
    elr_spectrum_from_sampled(lam, val, n, rgb);
  }
  if (P->light_param) {
    if (negative) elr__failf(P, p->file, p->line, "%s: parameter \"%s %s\" must not be negative", P->dir_name, p->type, p->name);
    for (i = 0; i < 3; i++) if (rgb[i] < 0) rgb[i] = 0;
  }
  if (!isfinite(rgb[0]) || !isfinite(rgb[1]) || !isfinite(rgb[2]) || fabs(rgb[0]) > FLT_MAX || fabs(rgb[1]) > FLT_MAX || fabs(rgb[2]) > FLT_MAX)
    elr__failf(P, p->file, p->line, "%s: parameter \"%s %s\": the colour overflows (%g %g %g)", P->dir_name, p->type, p->name, rgb[0], rgb[1], rgb[2]);
  return elr_v((float)rgb[0], (float)rgb[1], (float)rgb[2]);
}

elr_v3 elr__prgb(elr__parser *P, const char *name, elr_v3 def) {
  elr__param *p = elr__find(P, name);
  if (p && (!strcmp(p->type, "spectrum") || !strcmp(p->type, "blackbody") || !strcmp(p->type, "xyz"))) return elr__pspectral(P, p);
  if (p && !strcmp(p->type, "float") && p->n == 1) { p->used = 1; return elr_v((float)p->num[0], (float)p->num[0], (float)p->num[0]); }
  p = elr__findt(P, name, "rgb", 3);
  return p ? elr_v((float)p->num[0], (float)p->num[1], (float)p->num[2]) : def;
}
elr_v3 elr__ppoint(elr__parser *P, const char *name, const char *type, elr_v3 def) {
  elr__param *p = elr__findt(P, name, type, 3);
  return p ? elr_v((float)p->num[0], (float)p->num[1], (float)p->num[2]) : def;
}
void elr__report_unused(elr__parser *P) {
  int i;
  for (i = 0; i < P->nparams; i++)
    if (!P->params[i].used) {
      char key[300];
      snprintf(key, sizeof key, "parameter %s %s %s", P->dir_name, P->params[i].type, P->params[i].name);
      elr__warn_once(P, P->params[i].file, P->params[i].line, key, "%s: parameter \"%s %s\" is not supported and is ignored",
                     P->dir_name, P->params[i].type, P->params[i].name);
    }
}
void elr__check_range(elr__parser *P, const char *name, double v, double lo, double hi) {
  elr__param *p = elr__find(P, name);
  /* a relative float epsilon of slack: many values arrive here as floats, and 0.01f < 0.01 */
  if (!(v >= lo - fabs(lo) * 1e-6 && v <= hi + fabs(hi) * 1e-6))
    elr__failf(P, p ? p->file : P->dir_file, p ? p->line : P->dir_line, "%s: \"%s\" = %g is out of range [%g, %g]", P->dir_name, name, v, lo, hi);
}
int elr__coord_ok(elr_v3 p) {
  return fabsf(p.x) <= (float)ELR_MAX_COORD && fabsf(p.y) <= (float)ELR_MAX_COORD && fabsf(p.z) <= (float)ELR_MAX_COORD;
}
void elr__check_point(elr__parser *P, int line, elr_v3 p, const char *what) {
  if (!elr__coord_ok(p))
    elr__failf(P, P->dir_file, line, "%s: %s (%g, %g, %g) is not finite or outside |x| <= %g", P->dir_name, what, p.x, p.y, p.z, ELR_MAX_COORD);
}

int elr__const_tex(elr__parser *P, elr_v3 v) {
  elr_scene *s = P->s;
  elr_texture *t;
  ELR_PUSH(P, s->tex, s->ntex, s->captex, elr_texture);
  t = &s->tex[s->ntex - 1];
  t->kind = ELR_TEX_CONST; t->value = v; t->su = t->sv = 1.f;
  return s->ntex - 1;
}
/* A texture-valued parameter ("rgb Kd", "float roughness" or "texture Kd" naming a texture). */
int elr__ptex(elr__parser *P, const char *name, elr_v3 def, int is_float) {
  elr__param *p = elr__find(P, name);
  if (p && !strcmp(p->type, "texture")) {
    int k;
    elr__findt(P, name, "texture", 1);
    k = elr__name_find(&P->htex, P->texnames, P->gs.ntex_scope, p->str[0]);
    if (k < 0) {
      elr_warn(P->s, p->file, p->line, "%s: texture \"%s\" is not defined; using the default %s", P->dir_name, p->str[0], name);
      return elr__const_tex(P, def);
    }
    if (P->texnames[k].is_float != is_float)
      elr_warn(P->s, p->file, p->line, "%s: texture \"%s\" is a %s texture used for %s parameter \"%s\"", P->dir_name, p->str[0],
               P->texnames[k].is_float ? "float" : "spectrum", is_float ? "a float" : "a spectrum", name);
    return P->texnames[k].index;
  }
  if (is_float) {
    double v = elr__pfloat(P, name, def.x);
    return elr__const_tex(P, elr_v((float)v, (float)v, (float)v));
  }
  return elr__const_tex(P, elr__prgb(P, name, def));
}
