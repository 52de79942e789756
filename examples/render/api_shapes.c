/* api_shapes.c: Shape (pbrt-v3 core/api.cpp's MakeShapes and the creators of shapes/sphere.cpp, disk.cpp,
 * triangle.cpp, plymesh.cpp, loopsubdiv.cpp): meshes in world space (or an object's space inside
 * ObjectBegin), spheres and disks with their transforms, their orientation (ReverseOrientation xor a
 * transform that swaps handedness), material and area light. */
#include "parser.h"

static void elr__object_grow(elr_object *o, double x, double y, double z) {
  o->lo[0] = fmin(o->lo[0], x); o->lo[1] = fmin(o->lo[1], y); o->lo[2] = fmin(o->lo[2], z);
  o->hi[0] = fmax(o->hi[0], x); o->hi[1] = fmax(o->hi[1], y); o->hi[2] = fmax(o->hi[2], z);
}
/* pbrt-v3's Transform::SwapsHandedness: the upper 3x3 has a negative determinant */
static int elr__swaps_handedness(const elr_xform *t) {
  const double(*m)[4] = (const double(*)[4])t->m;
  double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
               m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
  return det < 0;
}
static void elr__add_mesh(elr__parser *P, elr_mesh *m) {
  elr_scene *s = P->s;
  int i;
  m->object = P->cur_object;
  for (i = 0; i < m->nvert; i++) {
    elr_v3 p = elr_xpoint(&P->ctm, elr_v(m->p[3 * i], m->p[3 * i + 1], m->p[3 * i + 2]));
    m->p[3 * i] = p.x; m->p[3 * i + 1] = p.y; m->p[3 * i + 2] = p.z;
    if (!elr__coord_ok(p)) {
      free(m->idx); free(m->p); free(m->n); free(m->uv);
      elr__failf(P, P->dir_file, P->dir_line, "Shape: vertex %d (%g, %g, %g) is not finite or outside |x| <= %g after the transformation", i,
                p.x, p.y, p.z, ELR_MAX_COORD);
    }
    if (m->n) {
      elr_v3 n = elr_norm(elr_xnormal(&P->ctm, elr_v(m->n[3 * i], m->n[3 * i + 1], m->n[3 * i + 2])));
      m->n[3 * i] = n.x; m->n[3 * i + 1] = n.y; m->n[3 * i + 2] = n.z;
    }
  }
  m->material = P->gs.material;
  m->light = -1;
  /* pbrt-v3's triangle orientation (Triangle::Intersect and SetShadingGeometry): ReverseOrientation xor a
   * mirroring CTM turns the normals, with or without the mesh's own normals */
  m->flip = P->gs.reverse ^ elr__swaps_handedness(&P->ctm);
  if (m->object >= 0) { /* a prototype's shape: its bounds grow (ObjectInstance checks them in world space) */
    elr_object *o = &s->obj[m->object];
    for (i = 0; i < m->nvert; i++) elr__object_grow(o, m->p[3 * i], m->p[3 * i + 1], m->p[3 * i + 2]);
    o->nmesh++;
  }
  ELR_PUSH(P, s->mesh, s->nmesh, s->capmesh, elr_mesh);
  s->mesh[s->nmesh - 1] = *m;
  elr__attach_area(P, ELR_SHAPE_MESH, s->nmesh - 1);
}

void elr__shape(elr__parser *P, const char *type) {
  elr_scene *s = P->s;
  if (!strcmp(type, "sphere")) {
    elr_sphere *sp;
    float r = (float)elr__pfloat(P, "radius", 1.0);
    elr__check_range(P, "radius", r, 1e-20, 1e20);
    if (elr__find(P, "zmin") || elr__find(P, "zmax") || elr__find(P, "phimax")) {
      double zmin = elr__pfloat(P, "zmin", -r), zmax = elr__pfloat(P, "zmax", r), pm = elr__pfloat(P, "phimax", 360.);
      if (zmin > -r || zmax < r || pm < 360.)
        elr_warn(P->s, P->dir_file, P->dir_line, "Shape \"sphere\": zmin/zmax/phimax ignored (only full spheres)");
    }
    { /* the sphere's world-space bounds must be traceable */
      elr_v3 c = elr_xpoint(&P->ctm, elr_v(0, 0, 0));
      double sc = 0;
      int i, j;
      for (j = 0; j < 3; j++) {
        double col = 0;
        for (i = 0; i < 3; i++) col += P->ctm.m[i][j] * P->ctm.m[i][j];
        if (sqrt(col) > sc) sc = sqrt(col);
      }
      elr__check_point(P, P->dir_line, c, "the sphere's centre");
      if (!(r * sc <= ELR_MAX_COORD))
        elr__failf(P, P->dir_file, P->dir_line, "Shape \"sphere\": the radius in world space (%g) is outside |x| <= %g", r * sc, ELR_MAX_COORD);
    }
    ELR_PUSH(P, s->sph, s->nsph, s->capsph, elr_sphere);
    sp = &s->sph[s->nsph - 1];
    sp->o2w = P->ctm; sp->radius = r; sp->material = P->gs.material;
    sp->light = -1;
    sp->flip = P->gs.reverse ^ elr__swaps_handedness(&P->ctm);
    sp->object = P->cur_object;
    if (sp->object >= 0) {
      elr_object *o = &s->obj[sp->object];
      int i;
      for (i = 0; i < 8; i++) {
        elr_v3 c = elr_xpoint(&sp->o2w, elr_v(i & 1 ? r : -r, i & 2 ? r : -r, i & 4 ? r : -r));
        elr__object_grow(o, c.x, c.y, c.z);
      }
      o->nsph++;
    }
    elr__attach_area(P, ELR_SHAPE_SPHERE, s->nsph - 1);
  } else if (!strcmp(type, "disk")) { /* pbrt-v3's CreateDiskShape: height 0, radius 1, innerradius 0, phimax 360 */
    elr_disk *dk;
    double h = elr__pfloat(P, "height", 0.0), r = elr__pfloat(P, "radius", 1.0), ri = elr__pfloat(P, "innerradius", 0.0);
    double pm = elr__pfloat(P, "phimax", 360.0), sc = 0;
    int i, j;
    elr__check_range(P, "radius", r, 1e-20, 1e20);
    elr__check_range(P, "innerradius", ri, 0.0, r);
    if (!(ri < r)) elr__failf(P, P->dir_file, P->dir_line, "Shape \"disk\": innerradius %g must be smaller than radius %g", ri, r);
    if (!(pm > 0.0)) elr__failf(P, P->dir_file, P->dir_line, "Shape \"disk\": phimax %g must be positive", pm);
    if (pm > 360.0) pm = 360.0; /* pbrt-v3 clamps it to [0, 360] */
    elr__check_range(P, "height", h, -ELR_MAX_COORD, ELR_MAX_COORD);
    if (P->cur_object >= 0) {
      elr__warn_once(P, P->dir_file, P->dir_line, "disk in object", "Shape \"disk\" inside ObjectBegin is not supported and is left out");
      return;
    }
    for (j = 0; j < 3; j++) { /* the disk's world-space bounds must be traceable */
      double col = 0;
      for (i = 0; i < 3; i++) col += P->ctm.m[i][j] * P->ctm.m[i][j];
      if (sqrt(col) > sc) sc = sqrt(col);
    }
    elr__check_point(P, P->dir_line, elr_xpoint(&P->ctm, elr_v(0, 0, (float)h)), "the disk's centre");
    if (!(r * sc <= ELR_MAX_COORD))
      elr__failf(P, P->dir_file, P->dir_line, "Shape \"disk\": the radius in world space (%g) is outside |x| <= %g", r * sc, ELR_MAX_COORD);
    ELR_PUSH(P, s->disk, s->ndisk, s->capdisk, elr_disk);
    dk = &s->disk[s->ndisk - 1];
    dk->o2w = P->ctm; dk->height = (float)h; dk->radius = (float)r; dk->inner = (float)ri;
    dk->phimax = (float)(pm * 3.14159265358979323846 / 180.0);
    dk->material = P->gs.material; dk->light = -1; dk->flip = P->gs.reverse ^ elr__swaps_handedness(&P->ctm);
    elr__attach_area(P, ELR_SHAPE_DISK, s->ndisk - 1);
  } else if (!strcmp(type, "trianglemesh")) {
    elr_mesh m;
    elr__param *pi = elr__findt(P, "indices", "integer", -3);
    elr__param *pp = elr__findt(P, "P", "point3", -3);
    elr__param *pn = elr__find(P, "N") ? elr__findt(P, "N", "normal3", -3) : NULL;
    elr__param *puv = NULL;
    int i;
    const char *uvn = elr__find(P, "uv") ? "uv" : (elr__find(P, "st") ? "st" : NULL);
    if (uvn) {
      elr__param *q = elr__find(P, uvn);
      puv = elr__findt(P, uvn, !strcmp(q->type, "point2") ? "point2" : "float", -2);
    }
    if (elr__find(P, "S")) elr_warn(P->s, P->dir_file, P->dir_line, "Shape \"trianglemesh\": \"S\" (tangents) ignored"), elr__find(P, "S")->used = 1;
    if (!pp) elr__failf(P, P->dir_file, P->dir_line, "Shape \"trianglemesh\": \"point3 P\" is required");
    if (!pi) {
      if (pp->n != 9) elr__failf(P, P->dir_file, P->dir_line, "Shape \"trianglemesh\": \"integer indices\" is required");
    }
    memset(&m, 0, sizeof m);
    m.nvert = pp->n / 3;
    m.ntri = pi ? pi->n / 3 : 1;
    if (m.ntri == 0) elr__failf(P, P->dir_file, P->dir_line, "Shape \"trianglemesh\": no triangles");
    if (pn && pn->n != pp->n) elr__failf(P, pn->file, pn->line, "Shape \"trianglemesh\": \"N\" must have as many values as \"P\"");
    if (puv && puv->n / 2 != m.nvert) elr__failf(P, puv->file, puv->line, "Shape \"trianglemesh\": \"%s\" must have 2 values per vertex", uvn);
    for (i = 0; pi && i < pi->n; i++)
      if (pi->num[i] < 0 || pi->num[i] >= m.nvert)
        elr__failf(P, pi->file, pi->line, "Shape \"trianglemesh\": index %g out of range [0, %d)", pi->num[i], m.nvert);
    m.idx = (unsigned *)malloc(sizeof(unsigned) * 3 * (size_t)m.ntri);
    m.p = (float *)malloc(sizeof(float) * 3 * (size_t)m.nvert);
    m.n = pn ? (float *)malloc(sizeof(float) * 3 * (size_t)m.nvert) : NULL;
    m.uv = puv ? (float *)malloc(sizeof(float) * 2 * (size_t)m.nvert) : NULL;
    if (!m.idx || !m.p || (pn && !m.n) || (puv && !m.uv)) {
      free(m.idx); free(m.p); free(m.n); free(m.uv);
      elr__failf(P, P->dir_file, P->dir_line, "out of memory");
    }
    for (i = 0; i < 3 * m.ntri; i++) m.idx[i] = pi ? (unsigned)pi->num[i] : (unsigned)i;
    for (i = 0; i < 3 * m.nvert; i++) m.p[i] = (float)pp->num[i];
    for (i = 0; pn && i < 3 * m.nvert; i++) m.n[i] = (float)pn->num[i];
    for (i = 0; puv && i < 2 * m.nvert; i++) m.uv[i] = (float)puv->num[i];
    elr__add_mesh(P, &m);
  } else if (!strcmp(type, "loopsubdiv")) { /* pbrt-v3's CreateLoopSubdiv */
    elr_mesh m;
    char e[300];
    elr__param *pi = elr__findt(P, "indices", "integer", -3), *pp = elr__findt(P, "P", "point3", -3);
    int levels = elr__find(P, "levels") ? elr__pint(P, "levels", 3) : elr__pint(P, "nlevels", 3), *idx, i, dropped;
    if (elr__find(P, "scheme")) elr__pstring(P, "scheme", "loop"); /* pbrt-v3: "don't actually use this for now" */
    if (!pi) elr__failf(P, P->dir_file, P->dir_line, "Shape \"loopsubdiv\": \"integer indices\" is required");
    if (!pp) elr__failf(P, P->dir_file, P->dir_line, "Shape \"loopsubdiv\": \"point3 P\" is required");
    elr__check_range(P, elr__find(P, "levels") ? "levels" : "nlevels", levels, 0, 12);
    if (pi->n == 0) elr__failf(P, P->dir_file, P->dir_line, "Shape \"loopsubdiv\": no triangles");
    for (i = 0; i < pi->n; i++)
      if (pi->num[i] < 0 || pi->num[i] >= pp->n / 3)
        elr__failf(P, pi->file, pi->line, "Shape \"loopsubdiv\": index %g out of range [0, %d)", pi->num[i], pp->n / 3);
    idx = (int *)elr__alloc(P, sizeof(int) * (size_t)pi->n);
    for (i = 0; i < pi->n; i++) idx[i] = (int)pi->num[i];
    {
      double t0 = elr_now();
      if (elr_loop_subdivide(levels, idx, pi->n, pp->num, pp->n / 3, &m, &dropped, e, sizeof e) != 0)
        elr__failf(P, P->dir_file, P->dir_line, "Shape \"loopsubdiv\": %s", e);
      P->s->t_images += elr_now() - t0; /* (the time of files and of built geometry, as PLY meshes) */
    }
    if (dropped) elr_warn(P->s, P->dir_file, P->dir_line, "Shape \"loopsubdiv\": %d triangle%s with a repeated vertex left out", dropped,
                          dropped == 1 ? "" : "s");
    elr__add_mesh(P, &m);
  } else if (!strcmp(type, "plymesh")) {
    elr_mesh m;
    char e[600];
    const char *fn = elr__pstring(P, "filename", "");
    char *path;
    double t0 = elr_now();
    if (!fn[0]) elr__failf(P, P->dir_file, P->dir_line, "Shape \"plymesh\": \"string filename\" is required");
    path = elr__resolve(P, fn);
    memset(&m, 0, sizeof m);
    if (elr_ply_load(path, &m, e, sizeof e) != 0) elr__failf(P, P->dir_file, P->dir_line, "Shape \"plymesh\": %s", e);
    P->s->t_images += elr_now() - t0;
    elr__add_mesh(P, &m);
  } else {
    char key[200];
    snprintf(key, sizeof key, "Shape %.180s", type);
    elr__warn_once(P, P->dir_file, P->dir_line, key, "Shape \"%s\" is not supported and is ignored", type);
    { int i; for (i = 0; i < P->nparams; i++) P->params[i].used = 1; }
  }
  if (elr__find(P, "alpha")) { elr_warn(P->s, P->dir_file, P->dir_line, "Shape: \"alpha\" ignored"); elr__find(P, "alpha")->used = 1; }
}
