/* api_lights.c: LightSource and AreaLightSource (pbrt-v3 core/api.cpp's MakeLight and MakeAreaLight, with
 * the parameters of lights/point.cpp, distant.cpp, infinite.cpp, diffuse.cpp). Point and distant lights
 * are complete here; an infinite light is described (elr_infinite_desc: its map, scale, rotation and
 * portals) and scene.c's elr_scene_make_lights reads its image and builds it; an area light is attached
 * to each shape after it in its attribute block. Nothing here calls lights.c. */
#include "parser.h"

/* a point or distant light's radiance, its parameter times "scale": an overflow or a negative channel is an
 * error naming the light and the parameter (the infinite light's rule: negative light would render black, unsaid) */
static elr_v3 elr__light_radiance(elr__parser *P, const char *type, const char *param, elr_v3 v, elr_v3 sc) {
  elr_v3 L = elr_vmul(v, sc);
  if (!isfinite(L.x + L.y + L.z) || !isfinite(L.x) || !isfinite(L.y) || !isfinite(L.z))
    elr__failf(P, P->dir_file, P->dir_line, "LightSource \"%s\": %s times scale overflows (%g %g %g)", type, param, L.x, L.y, L.z);
  if (L.x < 0.f || L.y < 0.f || L.z < 0.f)
    elr__failf(P, P->dir_file, P->dir_line, "LightSource \"%s\": %s times scale (%g %g %g) must not be negative", type, param, L.x, L.y, L.z);
  return L;
}

void elr__light(elr__parser *P, const char *type) {
  elr_scene *s = P->s;
  elr_light *l;
  elr_v3 sc;
  P->light_param = 1;
  sc = elr__prgb(P, "scale", elr_v(1, 1, 1));
  ELR_PUSH(P, s->light, s->nlight, s->caplight, elr_light);
  l = &s->light[s->nlight - 1];
  if (!strcmp(type, "infinite")) {
    /* pbrt-v3 names the map "mapname" (lat-long); pbrt-v4 "filename" (a square equal-area map) */
    const char *map = elr__pstring(P, "mapname", ""), *fn4 = elr__pstring(P, "filename", "");
    float m3[9];
    int i, j;
    elr_v3 L = elr__prgb(P, "L", elr_v(1, 1, 1));
    float scale3[3];
    elr_infinite_desc *D;
    l->kind = ELR_LIGHT_INFINITE;
    l->nsamples = elr__pint(P, "samples", 1);
    elr__check_range(P, "samples", l->nsamples, 1, 1 << 16);
    l->compensated = elr__pbool(P, "compensated", 0);
    {
      /* envlight's extension: the importance map. Default "pbrt-v3" (pbrt-v3's own: twice the image
       * resolution from point lookups of le); "cellaverage" is envlight's default (exact bin averages of
       * the bilinear le, a quarter of the bins). Measured on city.hdr (a 3e4 sun), the relative variance
       * of lum(le) / pdf per light sample is 0.024 for pbrt-v3's map and 0.098 for cell averages: the
       * piecewise-constant density cannot follow the bilinear ramp around the sun at image resolution. */
      const char *im = elr__pstring(P, "importance", "pbrt-v3");
      /* none given: under a sun map (render.c: elr__sun_share) and with a low-discrepancy sampler the
       * render takes "bilinear", le()'s patch density (issue 22: 1.1x the whole image's, 1.2-1.3x the lit
       * pixels' time to unit variance on bench_city with zsobol; README) */
      l->importance_auto = elr__find(P, "importance") == NULL;
      if (!strcmp(im, "cellaverage")) l->importance = EL_ENVLIGHT_IMPORTANCE_CELL_AVERAGE;
      else if (!strcmp(im, "pbrt-v3")) l->importance = EL_ENVLIGHT_IMPORTANCE_PBRT_V3;
      else if (!strcmp(im, "texel")) l->importance = EL_ENVLIGHT_IMPORTANCE_TEXEL;
      else if (!strcmp(im, "bilinear")) l->importance = EL_ENVLIGHT_IMPORTANCE_BILINEAR;
      else elr__failf(P, elr__find(P, "importance")->file, elr__find(P, "importance")->line, "LightSource \"infinite\": importance must be \"cellaverage\", \"pbrt-v3\", \"texel\" or \"bilinear\"");
    }
    {
      /* envlight's extension: how a surface that only reflects samples the light. "product" (the
       * default): the map times the clamped cosine of the surface's normal (el_envlight_sample_li_cos),
       * no sample below the horizon; "map": the map alone (pbrt-v3's, with the importance map above) */
      const char *ls = elr__pstring(P, "sampling", "product");
      if (!strcmp(ls, "product")) l->sampling = ELR_ENVLS_PRODUCT;
      else if (!strcmp(ls, "map")) l->sampling = ELR_ENVLS_MAP;
      else elr__failf(P, elr__find(P, "sampling")->file, elr__find(P, "sampling")->line, "LightSource \"infinite\": sampling must be \"product\" or \"map\"");
    }
    {
      /* envlight's extension: what becomes of texels envlight cannot use. "clampnegative" (the default):
       * finite negative texels become 0, with one warning that counts them and names the most negative
       * value (lossy EXR compression, DWAA/DWAB, rings slightly below 0: the HDRIs Blender ships hold 3 to
       * 8980 such texels, down to -0.0039), NaN and infinite texels are errors naming the file and the
       * texel; "zero": NaN and infinite texels become 0 too (one warning); "error": negatives are errors
       * as well. The image reader keeps every value as the file holds it: the policy is the light's. */
      const char *bt = elr__pstring(P, "badtexels", "clampnegative");
      if (!strcmp(bt, "clampnegative")) l->bad_texels = EL_ENVLIGHT_BAD_TEXELS_CLAMP_NEGATIVE;
      else if (!strcmp(bt, "zero")) l->bad_texels = EL_ENVLIGHT_BAD_TEXELS_ZERO;
      else if (!strcmp(bt, "error")) l->bad_texels = EL_ENVLIGHT_BAD_TEXELS_ERROR;
      else elr__failf(P, elr__find(P, "badtexels")->file, elr__find(P, "badtexels")->line, "LightSource \"infinite\": badtexels must be \"clampnegative\", \"zero\" or \"error\"");
    }
    l->L = elr_vmul(L, sc);
    scale3[0] = l->L.x; scale3[1] = l->L.y; scale3[2] = l->L.z;
    for (i = 0; i < 3; i++) /* else envlight reports "texel (0, 0) is NaN, infinite or negative" */
      if (!(scale3[i] >= 0.f && scale3[i] <= FLT_MAX))
        elr__failf(P, P->dir_file, P->dir_line, "LightSource \"infinite\": L times scale (%g %g %g) must be finite and not negative", scale3[0],
                  scale3[1], scale3[2]);
    /* the light-to-world rotation: the CTM's upper 3x3 (pbrt-v3 allows only rotations here) */
    /* pbrt-v3 normalises WorldToLight(d): a uniform scale in the CTM does not change the mapping, so
     * divide it out (envlight takes a rotation or a reflection) */
    double colscale = sqrt(P->ctm.m[0][0] * P->ctm.m[0][0] + P->ctm.m[1][0] * P->ctm.m[1][0] + P->ctm.m[2][0] * P->ctm.m[2][0]);
    if (!(colscale > 0)) colscale = 1;
    for (i = 0; i < 3; i++)
      for (j = 0; j < 3; j++) {
        double v = P->ctm.m[i][j] / colscale;
        /* Rotate by multiples of 90 degrees leaves cos = 6e-17 instead of 0: snap, so that envlight sees
         * the exact signed permutation (its exact and faster path) that the scene meant */
        if (fabs(v) < 1e-9) v = 0.0;
        else if (fabs(v - 1.0) < 1e-9) v = 1.0;
        else if (fabs(v + 1.0) < 1e-9) v = -1.0;
        m3[i * 3 + j] = (float)v;
      }
    if (map[0] && fn4[0])
      elr__failf(P, elr__find(P, "filename")->file, elr__find(P, "filename")->line,
                 "LightSource \"infinite\": both \"mapname\" (pbrt-v3, lat-long) and \"filename\" (pbrt-v4, equal-area) are given");
    /* the description scene.c's elr_scene_make_lights builds the light of (the image is read there) */
    ELR_PUSH(P, s->envdesc, s->nenvdesc, s->capenvdesc, elr_infinite_desc);
    D = &s->envdesc[s->nenvdesc - 1];
    D->light = s->nlight - 1;
    memcpy(D->scale, scale3, sizeof D->scale);
    memcpy(D->l2w, m3, sizeof D->l2w);
    D->file = elr__heap_strdup(P, P->dir_file ? P->dir_file : "?");
    D->line = P->dir_line;
    if (map[0] || fn4[0]) D->path = elr__heap_strdup(P, elr__resolve(P, map[0] ? map : fn4));
    if (fn4[0]) {
      D->v4_filename = 1;
      D->filename_file = elr__heap_strdup(P, elr__find(P, "filename")->file);
      D->filename_line = elr__find(P, "filename")->line;
    }
    {
      /* pbrt-v4's "point3 portal" [p0 p1 p2 p3]: a window the light shines through (world space, not
       * the light's CTM, as pbrt-v4's cameraTransform.RenderFromWorld(p)); envlight also takes several
       * rectangles, 4 points each */
      elr__param *pp = elr__find(P, "portal");
      /* envlight's extension: the share of light samples drawn from the map where a portal is seen from
       * behind another portal's plane (a defensive mixture for points outside the room; 0: pbrt-v4's) */
      l->portal_share = (float)elr__pfloat(P, "portalmapshare", ELR_PORTAL_MAP_SHARE);
      elr__check_range(P, "portalmapshare", l->portal_share, 0, 1);
      if (pp) {
        int np, k;
        pp = elr__findt(P, "portal", "point3", -12);
        np = pp->n / 12;
        if (np < 1 || np > EL_ENVLIGHT_PORTAL_MAX)
          elr__failf(P, pp->file, pp->line, "LightSource \"infinite\": \"point3 portal\" takes 4 points per portal, 1 to %d portals; got %d values",
                     EL_ENVLIGHT_PORTAL_MAX, pp->n);
        D->portal = (float *)malloc(sizeof(float) * 12 * (size_t)np);
        if (!D->portal) { snprintf(P->err, P->errlen, "out of memory"); longjmp(P->jb, 1); }
        for (k = 0; k < 12 * np; k++) D->portal[k] = (float)pp->num[k];
        D->nportal = np;
        D->portal_file = elr__heap_strdup(P, pp->file);
        D->portal_line = pp->line;
      }
    }
  } else if (!strcmp(type, "point")) {
    elr_v3 I = elr__prgb(P, "I", elr_v(1, 1, 1));
    elr_v3 from = elr__ppoint(P, "from", "point3", elr_v(0, 0, 0));
    l->kind = ELR_LIGHT_POINT;
    l->L = elr__light_radiance(P, "point", "I", I, sc);
    l->pos = elr_xpoint(&P->ctm, from);
    elr__check_point(P, P->dir_line, l->pos, "the light's position");
    l->nsamples = 1;
  } else if (!strcmp(type, "distant")) {
    elr_v3 L = elr__prgb(P, "L", elr_v(1, 1, 1));
    elr_v3 from = elr__ppoint(P, "from", "point3", elr_v(0, 0, 0));
    elr_v3 to = elr__ppoint(P, "to", "point3", elr_v(0, 0, 1));
    l->kind = ELR_LIGHT_DISTANT;
    l->L = elr__light_radiance(P, "distant", "L", L, sc);
    l->dir = elr_norm(elr_xvector(&P->ctm, elr_sub(from, to)));
    l->nsamples = 1;
  } else {
    elr_warn(P->s, P->dir_file, P->dir_line, "LightSource \"%s\" is not supported and is ignored", type);
    s->nlight--;
    { int i; for (i = 0; i < P->nparams; i++) P->params[i].used = 1; }
  }
  P->light_param = 0;
}

/* AreaLightSource (pbrt-v3's pbrtAreaLightSource and CreateDiffuseAreaLight): "diffuse", or its alias
 * "area", with L (default 1), scale, twosided (default false) and nsamples ("samples" first, as pbrt-v3
 * reads it; default 1). Every shape after it in the attribute block emits that (elr__attach_area). */
void elr__area_light_source(elr__parser *P, const char *type) {
  elr__area *a;
  elr_v3 L, sc;
  if (strcmp(type, "diffuse") != 0 && strcmp(type, "area") != 0) {
    int i;
    elr_warn(P->s, P->dir_file, P->dir_line, "AreaLightSource \"%s\" is not supported; the shapes after it do not emit", type);
    for (i = 0; i < P->nparams; i++) P->params[i].used = 1;
    P->gs.area = 0;
    return;
  }
  ELR_PUSH(P, P->areas, P->nareas, P->capareas, elr__area);
  a = &P->areas[P->nareas - 1];
  P->light_param = 1;
  L = elr__prgb(P, "L", elr_v(1, 1, 1));
  sc = elr__prgb(P, "scale", elr_v(1, 1, 1));
  P->light_param = 0;
  a->L = elr_vmul(L, sc);
  if (!isfinite(a->L.x) || !isfinite(a->L.y) || !isfinite(a->L.z))
    elr__failf(P, P->dir_file, P->dir_line, "AreaLightSource \"%s\": L times scale overflows (%g %g %g)", type, a->L.x, a->L.y, a->L.z);
  if (a->L.x < 0.f || a->L.y < 0.f || a->L.z < 0.f)
    elr__failf(P, P->dir_file, P->dir_line, "AreaLightSource \"%s\": L times scale (%g %g %g) must not be negative", type, a->L.x, a->L.y, a->L.z);
  a->twosided = elr__pbool(P, "twosided", 0);
  a->nsamples = elr__pint(P, "nsamples", 1);
  a->nsamples = elr__pint(P, "samples", a->nsamples);
  elr__check_range(P, elr__find(P, "samples") ? "samples" : "nsamples", a->nsamples, 1, 1 << 16);
  P->gs.area = P->nareas;
}
/* The area light of the graphics state on the shape just made (pbrt-v3's pbrtShape: MakeAreaLight for
 * each shape; one light per triangle mesh here, see lights.c). A black L makes no light. */
void elr__attach_area(elr__parser *P, int kind, int index) {
  elr_scene *s = P->s;
  const elr__area *a;
  elr_light *l;
  if (!P->gs.area) return;
  if (P->cur_object >= 0) { /* pbrt-v3: "Area lights not supported with object instancing" */
    elr__warn_once(P, P->dir_file, P->dir_line, "area in object", "AreaLightSource: the shapes of an ObjectBegin block do not emit (area lights are not supported with object instancing, as in pbrt-v3)");
    return;
  }
  a = &P->areas[P->gs.area - 1];
  if (!(elr_maxc(a->L) > 0.f)) return;
  ELR_PUSH(P, s->light, s->nlight, s->caplight, elr_light);
  l = &s->light[s->nlight - 1];
  l->kind = ELR_LIGHT_AREA;
  l->L = a->L; l->twosided = a->twosided; l->nsamples = a->nsamples;
  l->shape_kind = kind; l->shape = index;
  if (kind == ELR_SHAPE_MESH) s->mesh[index].light = s->nlight - 1;
  else if (kind == ELR_SHAPE_SPHERE) s->sph[index].light = s->nlight - 1;
  else s->disk[index].light = s->nlight - 1;
}
