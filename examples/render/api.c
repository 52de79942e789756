/* api.c: the directives and elr_parse (pbrt-v3 core/api.cpp: pbrtTranslate ... pbrtWorldEnd, with the
 * loop of parser.cpp's parse that calls them, and pbrtParseFile): the current transformation matrix
 * (CTM) with its stack, named coordinate systems, the graphics state of AttributeBegin/End (material,
 * named materials and textures, ReverseOrientation, the area light), ObjectBegin/End/ObjectInstance,
 * Include, WorldBegin/End. What a directive describes is made by the file of its kind (api_options.c,
 * api_lights.c, api_shapes.c, api_materials.c); parser.c's opening comment maps the parser's files. */
#include "parser.h"

static void elr__check_ctm(elr__parser *P, int line) {
  int i, j;
  for (i = 0; i < 4; i++)
    for (j = 0; j < 4; j++)
      if (!isfinite(P->ctm.m[i][j]) || !isfinite(P->ctm.inv[i][j]) || fabs(P->ctm.m[i][j]) > 1e30 || fabs(P->ctm.inv[i][j]) > 1e30)
        elr__failf(P, P->dir_file, line, "%s: the transformation overflows (a matrix entry or an entry of its inverse is %g, beyond 1e30)",
                  P->dir_name, isfinite(P->ctm.m[i][j]) && fabs(P->ctm.m[i][j]) > 1e30 ? P->ctm.m[i][j] : P->ctm.inv[i][j]);
}

static void elr__run(elr__parser *P) {
  static const char *unsupported[] = {"ColorSpace", "Option", "Attribute", "AttributeSet", "SurfaceIntegrator",
                                      "VolumeIntegrator", "Renderer", "Volume"};
  for (;;) {
    elr__tok t = elr__next(P);
    char nm[64];
    int is_xform;
    elr_xform saved_ctm;
    if (t.kind == T_EOF) break;
    P->dir_line = t.line; P->dir_file = elr__curfile(P); /* the token was read from the current file */
    if (t.kind != T_WORD) {
      if (t.kind == T_STRING) elr__failf(P, P->dir_file, t.line, "expected a directive, got the string \"%s\" (a parameter without a directive?)", t.s);
      elr__failf(P, P->dir_file, t.line, "expected a directive, got %s", t.kind == T_NUM ? "a number" : (t.kind == T_LBR ? "'['" : "']'"));
    }
    if (t.len >= sizeof nm) elr__failf(P, P->dir_file, t.line, "unknown directive \"%.*s\"", 40, t.s);
    memcpy(nm, t.s, t.len); nm[t.len] = 0;
    snprintf(P->dir_name, sizeof P->dir_name, "%s", nm);
    P->dir_line = t.line; P->dir_file = elr__curfile(P);
    if (P->world_ended) elr__failf(P, P->dir_file, t.line, "directive \"%s\" after WorldEnd", nm);
    is_xform = !strcmp(nm, "Translate") || !strcmp(nm, "Scale") || !strcmp(nm, "Rotate") || !strcmp(nm, "LookAt") ||
               !strcmp(nm, "Transform") || !strcmp(nm, "ConcatTransform") || !strcmp(nm, "Identity") || !strcmp(nm, "CoordSysTransform");
    saved_ctm = P->ctm;

    if (!strcmp(nm, "Translate")) {
      double x = elr__num(P, nm), y = elr__num(P, nm), z = elr__num(P, nm);
      double m[4][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}};
      elr_xform a, r;
      m[0][3] = x; m[1][3] = y; m[2][3] = z;
      elr_xform_from_matrix(&a, m); elr_xform_mul(&r, &P->ctm, &a); P->ctm = r;
      elr__check_ctm(P, t.line);
    } else if (!strcmp(nm, "Scale")) {
      double x = elr__num(P, nm), y = elr__num(P, nm), z = elr__num(P, nm);
      double m[4][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}};
      elr_xform a, r;
      m[0][0] = x; m[1][1] = y; m[2][2] = z;
      if (x == 0 || y == 0 || z == 0) elr__failf(P, P->dir_file, t.line, "Scale %g %g %g is singular", x, y, z);
      elr_xform_from_matrix(&a, m); elr_xform_mul(&r, &P->ctm, &a); P->ctm = r;
      elr__check_ctm(P, t.line);
    } else if (!strcmp(nm, "Rotate")) {
      double ang = elr__num(P, nm), x = elr__num(P, nm), y = elr__num(P, nm), z = elr__num(P, nm);
      double l = sqrt(x * x + y * y + z * z), s, c, m[4][4];
      elr_xform a, r;
      if (!(l > 0)) elr__failf(P, P->dir_file, t.line, "Rotate: the axis is zero");
      x /= l; y /= l; z /= l;
      s = sin(ang * 3.14159265358979323846 / 180.0); c = cos(ang * 3.14159265358979323846 / 180.0);
      /* pbrt-v3's Rotate(theta, axis) */
      m[0][0] = x * x + (1 - x * x) * c; m[0][1] = x * y * (1 - c) - z * s; m[0][2] = x * z * (1 - c) + y * s; m[0][3] = 0;
      m[1][0] = x * y * (1 - c) + z * s; m[1][1] = y * y + (1 - y * y) * c; m[1][2] = y * z * (1 - c) - x * s; m[1][3] = 0;
      m[2][0] = x * z * (1 - c) - y * s; m[2][1] = y * z * (1 - c) + x * s; m[2][2] = z * z + (1 - z * z) * c; m[2][3] = 0;
      m[3][0] = m[3][1] = m[3][2] = 0; m[3][3] = 1;
      elr_xform_from_matrix(&a, m); elr_xform_mul(&r, &P->ctm, &a); P->ctm = r;
      elr__check_ctm(P, t.line);
    } else if (!strcmp(nm, "LookAt")) {
      double v[9];
      int i;
      elr_v3 pos, look, up, dir, right, nup;
      double m[4][4];
      elr_xform c2w, w2c, r;
      for (i = 0; i < 9; i++) v[i] = elr__num(P, nm);
      for (i = 0; i < 9; i++)
        if (fabs(v[i]) > ELR_MAX_COORD) elr__failf(P, P->dir_file, t.line, "LookAt: %g is outside |x| <= %g", v[i], ELR_MAX_COORD);
      pos = elr_v((float)v[0], (float)v[1], (float)v[2]);
      look = elr_v((float)v[3], (float)v[4], (float)v[5]);
      up = elr_v((float)v[6], (float)v[7], (float)v[8]);
      dir = elr_sub(look, pos);
      if (elr_len(dir) == 0.f) elr__failf(P, P->dir_file, t.line, "LookAt: eye and look-at point coincide");
      dir = elr_norm(dir);
      if (elr_len(up) == 0.f || elr_len(elr_cross(elr_norm(up), dir)) == 0.f)
        elr__failf(P, P->dir_file, t.line, "LookAt: the up vector is zero or parallel to the viewing direction");
      right = elr_norm(elr_cross(elr_norm(up), dir));
      nup = elr_cross(dir, right);
      m[0][0] = right.x; m[1][0] = right.y; m[2][0] = right.z; m[3][0] = 0;
      m[0][1] = nup.x; m[1][1] = nup.y; m[2][1] = nup.z; m[3][1] = 0;
      m[0][2] = dir.x; m[1][2] = dir.y; m[2][2] = dir.z; m[3][2] = 0;
      m[0][3] = v[0]; m[1][3] = v[1]; m[2][3] = v[2]; m[3][3] = 1;
      if (elr_xform_from_matrix(&c2w, m) != 0) elr__failf(P, P->dir_file, t.line, "LookAt: the camera frame is singular");
      elr_xform_invert(&w2c, &c2w);
      elr_xform_mul(&r, &P->ctm, &w2c); P->ctm = r;
      elr__check_ctm(P, t.line);
    } else if (!strcmp(nm, "Transform") || !strcmp(nm, "ConcatTransform")) {
      double v[16], m[4][4];
      int i, j;
      elr_xform a, r;
      elr__nums16(P, v, nm);
      for (i = 0; i < 4; i++) for (j = 0; j < 4; j++) m[i][j] = v[j * 4 + i]; /* pbrt: Transpose */
      if (elr_xform_from_matrix(&a, m) != 0) elr__failf(P, P->dir_file, t.line, "%s: the matrix is singular", nm);
      if (nm[0] == 'T') P->ctm = a;
      else { elr_xform_mul(&r, &P->ctm, &a); P->ctm = r; }
      elr__check_ctm(P, t.line);
    } else if (!strcmp(nm, "Identity")) {
      elr_xform_identity(&P->ctm);
    } else if (!strcmp(nm, "ReverseOrientation")) { /* graphics state: the normals of the shapes after it */
      P->gs.reverse = !P->gs.reverse;
    } else if (!strcmp(nm, "CoordinateSystem")) {
      const char *n = elr__str(P, nm);
      int k = elr__name_find(&P->hctx, P->ctx, P->nctx, n);
      if (k < 0) {
        ELR_PUSH(P, P->ctx, P->nctx, P->capctx, elr__named);
        P->cs_xf = (elr_xform *)realloc(P->cs_xf, sizeof(elr_xform) * (size_t)P->capctx);
        if (!P->cs_xf) elr__failf(P, P->dir_file, t.line, "out of memory");
        k = P->nctx - 1;
        P->ctx[k].name = elr__strdup(P, n, strlen(n));
        elr__name_add(P, &P->hctx, P->ctx, k);
      }
      P->cs_xf[k] = P->ctm;
    } else if (!strcmp(nm, "CoordSysTransform")) {
      const char *n = elr__str(P, nm);
      int k = elr__name_find(&P->hctx, P->ctx, P->nctx, n);
      if (k < 0) elr_warn(P->s, P->dir_file, t.line, "CoordSysTransform: coordinate system \"%s\" unknown; ignored", n);
      else P->ctm = P->cs_xf[k];
    } else if (!strcmp(nm, "AttributeBegin") || !strcmp(nm, "TransformBegin")) {
      if (P->depth >= ELR_MAX_STACK) elr__failf(P, P->dir_file, t.line, "%s nested more than %d deep", nm, ELR_MAX_STACK);
      P->xstack[P->depth] = P->ctm;
      P->gstack[P->depth] = P->gs;
      P->stack_kind[P->depth] = nm[0] == 'A' ? 'a' : 't';
      P->depth++;
    } else if (!strcmp(nm, "AttributeEnd") || !strcmp(nm, "TransformEnd")) {
      char want = nm[0] == 'A' ? 'a' : 't';
      if (P->depth == 0) { elr_warn(P->s, P->dir_file, t.line, "unmatched %s ignored", nm); continue; }
      if (P->stack_kind[P->depth - 1] != want)
        elr_warn(P->s, P->dir_file, t.line, "%s closes a%s block", nm,
                 P->stack_kind[P->depth - 1] == 'o' ? "n ObjectBegin" : (want == 'a' ? " TransformBegin" : "n AttributeBegin"));
      P->depth--;
      P->ctm = P->xstack[P->depth];
      if (want == 'a') P->gs = P->gstack[P->depth];
      else P->gs.end_only = P->gstack[P->depth].end_only; /* pbrt-v3 pushes the active transform bits with both */
    } else if (!strcmp(nm, "WorldBegin")) {
      if (P->in_world) elr__failf(P, P->dir_file, t.line, "WorldBegin inside the world block");
      P->in_world = 1;
      elr_xform_identity(&P->ctm);
      {
        int k = elr__name_find(&P->hctx, P->ctx, P->nctx, "world");
        if (k < 0) {
          ELR_PUSH(P, P->ctx, P->nctx, P->capctx, elr__named);
          P->cs_xf = (elr_xform *)realloc(P->cs_xf, sizeof(elr_xform) * (size_t)P->capctx);
          if (!P->cs_xf) elr__failf(P, P->dir_file, t.line, "out of memory");
          k = P->nctx - 1; P->ctx[k].name = elr__strdup(P, "world", 5);
          elr__name_add(P, &P->hctx, P->ctx, k);
        }
        P->cs_xf[k] = P->ctm;
      }
    } else if (!strcmp(nm, "WorldEnd")) {
      if (!P->in_world) elr__failf(P, P->dir_file, t.line, "WorldEnd without WorldBegin");
      if (P->depth != 0) elr_warn(P->s, P->dir_file, t.line, "%d unclosed AttributeBegin/TransformBegin at WorldEnd", P->depth);
      P->world_ended = 1;
      {
        int i, nemit = 0;
        for (i = 0; i < P->s->nlight; i++) nemit += elr_light_emits(&P->s->light[i]);
        if (nemit == 0) /* elr_render then traces nothing */
          elr_warn(P->s, P->dir_file, t.line, "nothing in the scene emits light (no light source or area light with L > 0): the image is black");
        if (nemit > 1 && P->s->d.integrator_path && P->s->d.light_strategy == ELR_LSTRAT_SPATIAL)
          elr_warn(P->s, P->integ_file ? P->integ_file : P->dir_file, P->integ_file ? P->integ_line : t.line,
                   "Integrator \"path\": lightsamplestrategy \"spatial\" (pbrt-v3's default) is not implemented; the %d lights are chosen by "
                   "\"power\"", nemit);
      }
    } else if (!strcmp(nm, "Include") || !strcmp(nm, "Import")) {
      const char *fn = elr__str(P, nm);
      char *path = elr__resolve(P, fn);
      size_t len;
      char *txt = elr__read_file(P, path, &len, t.line);
      elr__parse_file(P, txt, len, path);
    } else if (!strcmp(nm, "Camera") || !strcmp(nm, "Film") || !strcmp(nm, "PixelFilter") ||
               !strcmp(nm, "Sampler") || !strcmp(nm, "Integrator")) {
      const char *type = elr__str(P, nm);
      elr__read_params(P);
      if (P->in_world) { elr__directive_block(P, 0, nm); continue; }
      if (nm[0] == 'C') elr__camera(P, type);
      else if (nm[0] == 'F') elr__film(P, type);
      else if (nm[0] == 'P') elr__filter(P, type);
      else if (nm[0] == 'S') elr__sampler(P, type);
      else elr__integrator(P, type);
      elr__report_unused(P);
    } else if (!strcmp(nm, "LightSource") || !strcmp(nm, "Shape") || !strcmp(nm, "Material") ||
               !strcmp(nm, "NamedMaterial") || !strcmp(nm, "AreaLightSource")) {
      const char *type = elr__str(P, nm);
      elr__read_params(P);
      if (!P->in_world) { elr__directive_block(P, 1, nm); continue; }
      if (nm[0] == 'A') elr__area_light_source(P, type);
      else if (nm[0] == 'L') elr__light(P, type);
      else if (nm[0] == 'S') elr__shape(P, type);
      else if (nm[0] == 'M') P->gs.material = elr__make_material(P, type);
      else {
        int k = elr__name_find(&P->hmat, P->matnames, P->gs.nnamed_mat, type);
        if (k < 0) elr_warn(P->s, P->dir_file, t.line, "NamedMaterial \"%s\" is not defined; ignored", type);
        else P->gs.material = P->matnames[k].index;
      }
      elr__report_unused(P);
    } else if (!strcmp(nm, "MakeNamedMaterial")) {
      const char *name = elr__str(P, nm);
      const char *type;
      int idx;
      elr__read_params(P);
      if (!P->in_world) { elr__directive_block(P, 1, nm); continue; }
      type = elr__pstring(P, "type", "");
      if (!type[0]) elr__failf(P, P->dir_file, t.line, "MakeNamedMaterial \"%s\": \"string type\" is required", name);
      idx = elr__make_material(P, type);
      /* pbrt-v3 keeps named materials in the graphics state: a name made inside AttributeBegin/End is
       * forgotten at its AttributeEnd, as named textures are */
      if (P->gs.nnamed_mat < P->nmatn) {
        elr__name_drop(&P->hmat, P->matnames, P->nmatn, P->gs.nnamed_mat);
        P->nmatn = P->gs.nnamed_mat;
      }
      if (elr__name_find(&P->hmat, P->matnames, P->nmatn, name) >= 0)
        elr_warn(P->s, P->dir_file, t.line, "MakeNamedMaterial: named material \"%s\" redefined", name);
      ELR_PUSH(P, P->matnames, P->nmatn, P->capmatn, elr__named);
      P->matnames[P->nmatn - 1].name = elr__strdup(P, name, strlen(name));
      elr__name_add(P, &P->hmat, P->matnames, P->nmatn - 1);
      P->matnames[P->nmatn - 1].index = idx;
      P->gs.nnamed_mat = P->nmatn;
      elr__report_unused(P);
    } else if (!strcmp(nm, "ObjectBegin")) {
      /* pbrt-v3's pbrtObjectBegin: an AttributeBegin, then the shapes that follow make the prototype */
      const char *name = elr__str(P, nm);
      elr_object *o;
      if (!P->in_world) { elr__directive_block(P, 1, nm); continue; }
      if (P->cur_object >= 0) elr__failf(P, P->dir_file, t.line, "ObjectBegin \"%s\" inside the definition of another object", name);
      if (P->depth >= ELR_MAX_STACK) elr__failf(P, P->dir_file, t.line, "%s nested more than %d deep", nm, ELR_MAX_STACK);
      P->xstack[P->depth] = P->ctm; P->gstack[P->depth] = P->gs; P->stack_kind[P->depth] = 'o'; P->depth++;
      ELR_PUSH(P, P->s->obj, P->s->nobj, P->s->capobj, elr_object);
      o = &P->s->obj[P->s->nobj - 1];
      o->lo[0] = o->lo[1] = o->lo[2] = INFINITY; o->hi[0] = o->hi[1] = o->hi[2] = -INFINITY;
      P->cur_object = P->s->nobj - 1;
      ELR_PUSH(P, P->objnames, P->nobjn, P->capobjn, elr__named); /* a later ObjectBegin of the name replaces it */
      P->objnames[P->nobjn - 1].name = elr__strdup(P, name, strlen(name));
      elr__name_add(P, &P->hobj, P->objnames, P->nobjn - 1);
      P->objnames[P->nobjn - 1].index = P->cur_object;
    } else if (!strcmp(nm, "ObjectEnd")) {
      if (!P->in_world) { elr__directive_block(P, 1, nm); continue; }
      if (P->cur_object < 0) elr__failf(P, P->dir_file, t.line, "ObjectEnd without ObjectBegin");
      P->cur_object = -1;
      /* pbrt-v3's pbrtObjectEnd ends with an AttributeEnd */
      if (P->depth == 0) { elr_warn(P->s, P->dir_file, t.line, "unmatched ObjectEnd ignored"); continue; }
      if (P->stack_kind[P->depth - 1] != 'o') elr_warn(P->s, P->dir_file, t.line, "ObjectEnd closes a %s block",
                                                       P->stack_kind[P->depth - 1] == 'a' ? "AttributeBegin" : "TransformBegin");
      P->depth--;
      P->ctm = P->xstack[P->depth];
      P->gs = P->gstack[P->depth];
    } else if (!strcmp(nm, "ObjectInstance")) {
      /* pbrt-v3's pbrtObjectInstance: the prototype placed by the CTM (instance to world); its shapes'
       * own transformations come first */
      const char *name = elr__str(P, nm);
      int k;
      if (!P->in_world) { elr__directive_block(P, 1, nm); continue; }
      if (P->cur_object >= 0) elr__failf(P, P->dir_file, t.line, "ObjectInstance \"%s\" inside an object definition", name);
      k = elr__name_find(&P->hobj, P->objnames, P->nobjn, name);
      if (k < 0) { elr_warn(P->s, P->dir_file, t.line, "ObjectInstance: object \"%s\" is not defined; ignored", name); continue; }
      k = P->objnames[k].index;
      if (P->s->obj[k].nmesh + P->s->obj[k].nsph == 0) continue; /* pbrt-v3: an empty object adds nothing */
      {
        const elr_object *o = &P->s->obj[k];
        int c;
        for (c = 0; c < 8; c++) /* the instance's world bounds must be traceable */
          elr__check_point(P, t.line, elr_xpoint(&P->ctm, elr_v((float)(c & 1 ? o->hi[0] : o->lo[0]), (float)(c & 2 ? o->hi[1] : o->lo[1]),
                                                              (float)(c & 4 ? o->hi[2] : o->lo[2]))),
                           "a corner of the instance's bounds");
      }
      ELR_PUSH(P, P->s->inst, P->s->ninst, P->s->capinst, elr_instance);
      P->s->inst[P->s->ninst - 1].object = k;
      P->s->inst[P->s->ninst - 1].xf = P->ctm;
      P->s->obj[k].ninstances++;
    } else if (!strcmp(nm, "ReverseOrientation")) {
      /* pbrt-v3's graphicsState.reverseOrientation: it flips the normals of the shapes that follow (only
       * transmissive materials see the difference: every other material here is two-sided) */
      P->gs.reverse = !P->gs.reverse;
    } else if (!strcmp(nm, "Accelerator")) {
      elr__str(P, nm); /* pbrt-v3's bvh or kdtree: Embree builds ours, so the line is accepted and ignored */
      elr__read_params(P);
      if (P->in_world) elr__directive_block(P, 0, nm);
    } else if (!strcmp(nm, "ActiveTransform")) {
      /* pbrt-v3's animated transformations (motion blur): the render is of the start time, so
       * transformations made while only EndTime is active are dropped */
      elr__tok w = elr__next(P);
      if (elr__wordis(&w, "StartTime") || elr__wordis(&w, "All")) P->gs.end_only = 0;
      else if (elr__wordis(&w, "EndTime")) P->gs.end_only = 1;
      else elr__failf(P, P->dir_file, t.line, "ActiveTransform: expected StartTime, EndTime or All");
      elr__warn_once(P, P->dir_file, t.line, "animated transforms", "animated transformations (ActiveTransform, TransformTimes) are not supported: "
                     "the scene is rendered at its start time");
    } else if (!strcmp(nm, "TransformTimes")) {
      elr__num(P, nm); elr__num(P, nm);
      elr__warn_once(P, P->dir_file, t.line, "animated transforms", "animated transformations (ActiveTransform, TransformTimes) are not supported: "
                     "the scene is rendered at its start time");
    } else if (!strcmp(nm, "MakeNamedMedium") || !strcmp(nm, "MediumInterface")) {
      /* participating media: not simulated; surfaces render as if every medium were vacuum */
      elr__str(P, nm);
      if (nm[0] == 'M' && nm[1] == 'a') elr__read_params(P);
      else if (elr__peek(P).kind == T_STRING) elr__str(P, nm); /* MediumInterface "inside" "outside" (or one name) */
      elr__warn_once(P, P->dir_file, t.line, "media", "participating media (%s) are not supported: surfaces render as in vacuum", nm);
    } else if (!strcmp(nm, "Texture")) {
      const char *name = elr__str(P, nm);
      const char *vtype = elr__str(P, nm);
      const char *cls = elr__str(P, nm);
      elr__read_params(P);
      if (!P->in_world) { elr__directive_block(P, 1, nm); continue; }
      elr__texture(P, name, vtype, cls);
      elr__report_unused(P);
    } else {
      int i, known = 0;
      for (i = 0; i < (int)(sizeof unsupported / sizeof unsupported[0]); i++) if (!strcmp(nm, unsupported[i])) known = 1;
      if (!known) elr__failf(P, P->dir_file, t.line, "unknown directive \"%s\"", nm);
      {
        char key[80];
        snprintf(key, sizeof key, "directive %s", nm);
        elr__warn_once(P, P->dir_file, t.line, key, "directive \"%s\" is not supported and is ignored", nm);
      }
      elr__skip_args(P);
    }
    /* a transformation while ActiveTransform EndTime holds moves the end time only: the render is of the start time */
    if (is_xform && P->gs.end_only) P->ctm = saved_ctm;
  }
  if (!P->in_world) elr__fail(P, P->lex[0].line, "the file ends before WorldBegin (truncated?)");
  if (!P->world_ended) elr__fail(P, P->lex[0].line, "the file ends before WorldEnd (truncated?)");
}

int elr_parse(elr_scene *s, const char *text, size_t len, const char *name, const char *base_dir, char *err,
              size_t errlen) {
  elr__parser *P = (elr__parser *)calloc(1, sizeof(elr__parser));
  int rc = 0;
  char dummy[8];
  if (!P) { snprintf(err, errlen, "out of memory"); return -1; }
  if (!err || errlen == 0) { err = dummy; errlen = sizeof dummy; }
  P->s = s; P->err = err; P->errlen = errlen; P->base_dir = base_dir;
  P->cur_object = -1;
  elr_xform_identity(&P->ctm);
  /* pbrt-v3's defaults */
  elr_xform_identity(&s->d.cam2world);
  s->d.fov = 90.f; s->d.xres = 1280; s->d.yres = 720;
  s->d.crop[0] = 0; s->d.crop[1] = 1; s->d.crop[2] = 0; s->d.crop[3] = 1;
  snprintf(s->d.filename, sizeof s->d.filename, "pbrt.exr");
  s->d.filter.type = ELR_PF_BOX; s->d.filter.xw = s->d.filter.yw = 0.5f;
  /* the sampler of a scene without a Sampler directive (el_render.h; pbrt-v3's is halton, 16 spp) */
  /* a scene without a Sampler: 02sequence with 16 dimensions (pbrt-v3's 4 cover the camera and one light
   * and BSDF pair; past them its draws are random: 16 gave directlighting with 2 pairs 1.3x and path 1.09x
   * less variance at 16 spp on bench_city) */
  s->d.sampler = ELR_DEFAULT_SAMPLER; s->d.spp = ELR_DEFAULT_SPP; s->d.dims = ELR_DEFAULT_SAMPLER == ELR_SAMPLER_ZEROTWO ? 16 : 4; s->d.jitter = 1;
  s->d.randomize = ELR_DEFAULT_SAMPLER == ELR_SAMPLER_ZSOBOL || ELR_DEFAULT_SAMPLER == ELR_SAMPLER_PADDEDSOBOL ? ELR_RANDOMIZE_FAST_OWEN : ELR_RANDOMIZE_NONE;
  s->d.integrator_path = 1; s->d.maxdepth = 5; s->d.rrthreshold = 1.f;
  s->d.light_sampling = ELR_LS_MIS;
  s->d.light_strategy = ELR_LSTRAT_SPATIAL; /* pbrt-v3's default lightsamplestrategy */
  if (setjmp(P->jb) == 0) {
    /* the default material: matte, Kd 0.5 */
    ELR_PUSH(P, s->mat, s->nmat, s->capmat, elr_material);
    s->mat[0].kind = ELR_MAT_MATTE;
    s->mat[0].kd = elr__const_tex(P, elr_v(.5f, .5f, .5f));
    s->mat[0].ks = s->mat[0].kr = s->mat[0].rough = -1;
    s->mat[0].kt = s->mat[0].urough = s->mat[0].vrough = s->mat[0].index = s->mat[0].eta = s->mat[0].k = s->mat[0].opacity = -1;
    P->gs.material = 0;
    elr__parse_file(P, text, len, name);
    elr__run(P);
  } else {
    rc = -1;
  }
  while (P->arena) { elr__block *b = P->arena; P->arena = b->next; free(b); }
  free(P->growing[0]); free(P->growing[1]); /* a parse stopped while a value list grew */
  free(P->ctx); free(P->cs_xf); free(P->texnames); free(P->matnames); free(P->warned); free(P->areas);
  free(P->hctx.s); free(P->htex.s); free(P->hmat.s); free(P->hobj.s); free(P->objnames);
  free(P);
  return rc;
}
