/* test_render_loopsubdiv: Shape "loopsubdiv" (loopsubdiv.c, pbrt-v3's shapes/loopsubdiv.cpp) against
 * what Loop subdivision must give, each answer derived here:
 *   - sizes: a closed mesh has F * 4^L triangles after L levels and, by Euler's formula (V - E + F = 2,
 *     E = 3F / 2), 2 + F / 2 vertices: the tetrahedron 4, 10, 34, 130, 514; a single triangle (a disc
 *     with a boundary) (n + 1)(n + 2) / 2 vertices with n = 2^L;
 *   - a closed control mesh stays closed: every edge of the result has exactly two triangles, which run
 *     along it in opposite directions; rays from inside the subdivided tetrahedron and cube all hit it;
 *   - limit positions: a vertex's limit is the eigen-mask of its subdivision rule, so an original
 *     vertex's limit position does not move with levels. For the regular tetrahedron (valence 3, beta
 *     3/16, gamma 1/5) it is 0.4 p + 0.2 (sum of the three others) = p / 5 for vertices around the
 *     origin; for a hexagonal fan (valence 6, regular: beta 1/16, gamma 1/12) with the centre raised by
 *     h it is h / 2; a corner of a single triangle follows pbrt-v3's boundary limit rule (1/5: 0.6 p +
 *     0.2 (neighbours));
 *   - planar control meshes give planar limit surfaces whose normals are the plane's;
 *   - normals: the tetrahedron's vertex normals point along -p (pbrt-v3's Cross(S, T) for triangles
 *     counter-clockwise from outside points inwards);
 *   - bad control meshes (an edge of three triangles, inconsistent orientation, too many levels) are
 *     errors naming the file and line, a triangle repeating a vertex is left out with a warning. */
#include "render_test_util.h"

static const char *tet_idx = "0 2 1  0 1 3  0 3 2  1 2 3"; /* counter-clockwise seen from outside */
static const char *tet_p = "1 1 1  -1 -1 1  -1 1 -1  1 -1 -1";

static elr_scene *load_shape(const char *shape, char *err, size_t errlen) {
  char buf[8192];
  snprintf(buf, sizeof buf, "WorldBegin\nLightSource \"point\"\n%s\nWorldEnd\n", shape);
  return rt_load("ls.pbrt", buf, err, errlen);
}

/* every edge of mesh m has exactly two triangles, running along it in opposite directions */
static int closed_and_oriented(const elr_mesh *m) {
  int t, k, bad = 0;
  for (t = 0; t < m->ntri && !bad; t++)
    for (k = 0; k < 3; k++) {
      unsigned a = m->idx[3 * t + k], b = m->idx[3 * t + (k + 1) % 3];
      int u, j, same = 0, opp = 0;
      for (u = 0; u < m->ntri; u++)
        for (j = 0; j < 3; j++) {
          unsigned c = m->idx[3 * u + j], d = m->idx[3 * u + (j + 1) % 3];
          if (c == a && d == b) same++;
          if (c == b && d == a) opp++;
        }
      if (same != 1 || opp != 1) bad = 1;
    }
  return !bad;
}

static void sizes_and_closure(void) {
  int L;
  static const int tet_v[5] = {4, 10, 34, 130, 514};
  for (L = 0; L <= 4; L++) {
    char buf[1024], err[512];
    elr_scene *s;
    snprintf(buf, sizeof buf, "Shape \"loopsubdiv\" \"integer levels\" %d \"integer indices\" [ %s ] \"point P\" [ %s ]", L, tet_idx, tet_p);
    s = load_shape(buf, err, sizeof err);
    if (!s) { rt_check(0, "tetrahedron, %d levels: %s", L, err); continue; }
    rt_check(s->nmesh == 1 && s->mesh[0].ntri == 4 << (2 * L) && s->mesh[0].nvert == tet_v[L] && s->mesh[0].nvert == 2 + s->mesh[0].ntri / 2,
             "tetrahedron, %d levels: %d triangles = 4 * 4^%d, %d vertices = 2 + F/2", L, s->mesh[0].ntri, L, s->mesh[0].nvert);
    if (L <= 3) rt_check(closed_and_oriented(&s->mesh[0]), "  closed: every edge has two triangles running along it in opposite directions");
    elr_scene_free(s);
  }
  for (L = 0; L <= 3; L++) {
    char buf[1024], err[512];
    elr_scene *s;
    int n = 1 << L;
    snprintf(buf, sizeof buf, "Shape \"loopsubdiv\" \"integer levels\" %d \"integer indices\" [ 0 1 2 ] \"point P\" [ 0 0 0  1 0 0  0 1 0 ]", L);
    s = load_shape(buf, err, sizeof err);
    if (!s) { rt_check(0, "triangle: %s", err); continue; }
    rt_check(s->mesh[0].ntri == n * n && s->mesh[0].nvert == (n + 1) * (n + 2) / 2, "single triangle, %d levels: %d triangles, %d vertices = (n+1)(n+2)/2",
             L, s->mesh[0].ntri, s->mesh[0].nvert);
    elr_scene_free(s);
  }
}

/* rays from an inside point c in 20000 directions: all must hit the surface */
static int watertight(const elr_scene *s, elr_v3 c, int *misses) {
  int i, n = 0;
  uint64_t r = 12345;
  *misses = 0;
  for (i = 0; i < 20000; i++) {
    double u1, u2, z, ph;
    elr_hit h;
    r = r * 6364136223846793005ULL + 1442695040888963407ULL; u1 = (double)(r >> 11) * 0x1p-53;
    r = r * 6364136223846793005ULL + 1442695040888963407ULL; u2 = (double)(r >> 11) * 0x1p-53;
    z = 1 - 2 * u1; ph = 2 * 3.14159265358979 * u2;
    if (!elr_intersect(s, c, elr_v((float)(sqrt(1 - z * z) * cos(ph)), (float)(sqrt(1 - z * z) * sin(ph)), (float)z), INFINITY, &h)) (*misses)++;
    n++;
  }
  return n;
}
static void rays_inside(void) {
  char buf[2048], err[512];
  elr_scene *s;
  int misses, n;
  snprintf(buf, sizeof buf, "Shape \"loopsubdiv\" \"integer levels\" 4 \"integer indices\" [ %s ] \"point P\" [ %s ]", tet_idx, tet_p);
  s = load_shape(buf, err, sizeof err);
  if (s) {
    n = watertight(s, elr_v(0.01f, 0.02f, 0.03f), &misses);
    rt_check(misses == 0, "subdivided tetrahedron (4 levels) is watertight: %d of %d rays from inside escape", misses, n);
    elr_scene_free(s);
  } else rt_check(0, "tetrahedron: %s", err);
  /* a cube of 12 triangles (valences 4 and 5), counter-clockwise from outside */
  s = load_shape("Shape \"loopsubdiv\" \"integer levels\" 3 \"integer indices\" [ 0 2 1 0 3 2  4 5 6 4 6 7  0 1 5 0 5 4  1 2 6 1 6 5  2 3 7 2 7 6  3 0 4 3 4 7 ]\n"
                 "  \"point P\" [ -1 -1 -1  1 -1 -1  1 1 -1  -1 1 -1  -1 -1 1  1 -1 1  1 1 1  -1 1 1 ]", err, sizeof err);
  if (s) {
    rt_check(s->mesh[0].ntri == 12 * 64 && s->mesh[0].nvert == 2 + 12 * 64 / 2 && closed_and_oriented(&s->mesh[0]),
             "cube, 3 levels: %d triangles, %d vertices, closed and consistently oriented", s->mesh[0].ntri, s->mesh[0].nvert);
    n = watertight(s, elr_v(0.1f, -0.05f, 0.2f), &misses);
    rt_check(misses == 0, "subdivided cube is watertight: %d of %d rays from inside escape", misses, n);
    elr_scene_free(s);
  } else rt_check(0, "cube: %s", err);
}

static void limits(void) {
  int L;
  double worst = 0, worstn = 0, worst_hex = 0, worst_tri = 0;
  for (L = 0; L <= 4; L++) {
    char buf[1024], err[512];
    elr_scene *s;
    int v, c;
    static const float P[4][3] = {{1, 1, 1}, {-1, -1, 1}, {-1, 1, -1}, {1, -1, -1}};
    snprintf(buf, sizeof buf, "Shape \"loopsubdiv\" \"integer levels\" %d \"integer indices\" [ %s ] \"point P\" [ %s ]", L, tet_idx, tet_p);
    s = load_shape(buf, err, sizeof err);
    if (!s) { rt_check(0, "tetrahedron: %s", err); continue; }
    for (v = 0; v < 4; v++) { /* the original vertices keep their indices (pbrt-v3 puts even vertices first) */
      elr_v3 n = elr_v(s->mesh[0].n[3 * v], s->mesh[0].n[3 * v + 1], s->mesh[0].n[3 * v + 2]), pn = elr_norm(elr_v(P[v][0], P[v][1], P[v][2]));
      for (c = 0; c < 3; c++) worst = fmax(worst, fabs(s->mesh[0].p[3 * v + c] - P[v][c] / 5.0));
      worstn = fmax(worstn, elr_len(elr_add(n, pn))); /* n = -p / |p| */
    }
    elr_scene_free(s);
  }
  rt_check(worst < 1e-6, "tetrahedron: the original vertices' limit positions are p / 5 at 0 to 4 levels (max dev %.2g)", worst);
  rt_check(worstn < 1e-5, "  their limit normals are -p / |p| (pbrt-v3's orientation: inwards for counter-clockwise triangles; max dev %.2g)", worstn);
  for (L = 0; L <= 3; L++) {
    char buf[1024], err[512];
    elr_scene *s;
    int k;
    /* a hexagonal fan: centre 0 raised by h = 0.6, ring 1..6 in the plane z = 0 */
    char pts[400];
    int o = snprintf(pts, sizeof pts, "0 0 0.6");
    for (k = 0; k < 6; k++) o += snprintf(pts + o, sizeof pts - (size_t)o, "  %.9f %.9f 0", cos(k * 3.14159265358979 / 3), sin(k * 3.14159265358979 / 3));
    snprintf(buf, sizeof buf, "Shape \"loopsubdiv\" \"integer levels\" %d \"integer indices\" [ 0 1 2 0 2 3 0 3 4 0 4 5 0 5 6 0 6 1 ] \"point P\" [ %s ]", L, pts);
    s = load_shape(buf, err, sizeof err);
    if (!s) { rt_check(0, "fan: %s", err); continue; }
    worst_hex = fmax(worst_hex, fabs(s->mesh[0].p[2] - 0.3) + fabs(s->mesh[0].p[0]) + fabs(s->mesh[0].p[1]));
    elr_scene_free(s);
    snprintf(buf, sizeof buf, "Shape \"loopsubdiv\" \"integer levels\" %d \"integer indices\" [ 0 1 2 ] \"point P\" [ 0 0 0  1 0 0  0 1 0 ]", L);
    s = load_shape(buf, err, sizeof err);
    if (!s) { rt_check(0, "triangle: %s", err); continue; }
    if (L == 0) /* corner 0 = 0.6 (0,0,0) + 0.2 (1,0,0) + 0.2 (0,1,0) */
      worst_tri = fabs(s->mesh[0].p[0] - 0.2) + fabs(s->mesh[0].p[1] - 0.2) + fabs(s->mesh[0].p[2]);
    elr_scene_free(s);
  }
  rt_check(worst_hex < 1e-6, "regular interior vertex (valence 6, weights 1/2 and 1/12): the raised centre's limit is h / 2 = 0.3 at 0 to 3 levels (dev %.2g)", worst_hex);
  rt_check(worst_tri < 1e-7, "boundary corner: pbrt-v3's limit rule 0.6 p + 0.2 (neighbours) = (0.2, 0.2, 0) (dev %.2g)", worst_tri);
  { /* a planar mesh stays planar: a tilted square of 8 triangles around an interior vertex, z = 0.3 x - 0.2 y + 1 */
    char err[512];
    elr_scene *s = load_shape("Shape \"loopsubdiv\" \"integer levels\" 3 \"integer indices\" [ 0 1 2  0 2 3  0 3 4  0 4 5  0 5 6  0 6 7  0 7 8  0 8 1 ]\n"
                              "  \"point P\" [ 0 0 1   1 0 1.3   1 1 1.1   0 1 0.8   -1 1 0.5   -1 0 0.7   -1 -1 0.9   0 -1 1.2   1 -1 1.5 ]", err, sizeof err);
    if (s) {
      double wp = 0, wn = 0;
      int v;
      elr_v3 pn = elr_norm(elr_v(-0.3f, 0.2f, 1.f));
      for (v = 0; v < s->mesh[0].nvert; v++) {
        const float *p = &s->mesh[0].p[3 * v], *n = &s->mesh[0].n[3 * v];
        wp = fmax(wp, fabs(p[2] - (0.3 * p[0] - 0.2 * p[1] + 1)));
        wn = fmax(wn, fmin(elr_len(elr_sub(elr_v(n[0], n[1], n[2]), pn)), elr_len(elr_add(elr_v(n[0], n[1], n[2]), pn))));
      }
      rt_check(wp < 1e-5 && wn < 1e-4, "planar control mesh: %d limit points on the plane (max dev %.2g), normals the plane's (%.2g)", s->mesh[0].nvert, wp, wn);
      elr_scene_free(s);
    } else rt_check(0, "planar: %s", err);
  }
}

static void bad_meshes(void) {
  char err[512];
  elr_scene *s;
  s = load_shape("Shape \"loopsubdiv\" \"integer indices\" [ 0 1 2  1 0 3  0 1 4 ] \"point P\" [ 0 0 0  1 0 0  0 1 0  0 -1 0  0 0 1 ]", err, sizeof err);
  rt_check(!s && strstr(err, "ls.pbrt:3:") && strstr(err, "more than two triangles"), "an edge of three triangles: \"%s\"", s ? "(loaded)" : err);
  elr_scene_free(s);
  s = load_shape("Shape \"loopsubdiv\" \"integer indices\" [ 0 1 2  0 1 3 ] \"point P\" [ 0 0 0  1 0 0  0 1 0  0 -1 0 ]", err, sizeof err);
  rt_check(!s && strstr(err, "ls.pbrt:3:") && strstr(err, "same direction"), "inconsistently oriented triangles: \"%s\"", s ? "(loaded)" : err);
  elr_scene_free(s);
  s = load_shape("Shape \"loopsubdiv\" \"integer levels\" 12 \"integer indices\" [ 0 1 2 0 2 3 ] \"point P\" [ 0 0 0  1 0 0  1 1 0  0 1 0 ]", err, sizeof err);
  rt_check(!s && strstr(err, "ls.pbrt:3:") && strstr(err, "at most 16777216"), "12 levels of 2 triangles (33554432): \"%s\"", s ? "(loaded)" : err);
  elr_scene_free(s);
  s = load_shape("Shape \"loopsubdiv\" \"integer levels\" -1 \"integer indices\" [ 0 1 2 ] \"point P\" [ 0 0 0  1 0 0  1 1 0 ]", err, sizeof err);
  rt_check(!s && strstr(err, "out of range"), "levels -1: \"%s\"", s ? "(loaded)" : err);
  elr_scene_free(s);
  s = load_shape("Shape \"loopsubdiv\" \"integer indices\" [ 0 1 7 ] \"point P\" [ 0 0 0  1 0 0  1 1 0 ]", err, sizeof err);
  rt_check(!s && strstr(err, "out of range"), "an index past P: \"%s\"", s ? "(loaded)" : err);
  elr_scene_free(s);
  s = load_shape("Shape \"loopsubdiv\" \"point P\" [ 0 0 0  1 0 0  1 1 0 ]", err, sizeof err);
  rt_check(!s && strstr(err, "\"integer indices\" is required"), "no indices: \"%s\"", s ? "(loaded)" : err);
  elr_scene_free(s);
  s = load_shape("Shape \"loopsubdiv\" \"integer levels\" 1 \"integer indices\" [ 0 1 2  0 0 1  0 2 3 ] \"point P\" [ 0 0 0  1 0 0  1 1 0  0 1 0  5 5 5 ]", err, sizeof err);
  rt_check(s && s->mesh[0].ntri == 8 && s->mesh[0].nvert == 9 && strstr(elr_scene_last_warning(s), "1 triangle with a repeated vertex left out"),
           "a triangle repeating a vertex left out with a warning, an unused vertex dropped (%d triangles, %d vertices: \"%s\")", s ? s->mesh[0].ntri : -1,
           s ? s->mesh[0].nvert : -1, s ? elr_scene_last_warning(s) : err);
  elr_scene_free(s);
}

int main(void) {
  rt_mkdir("test_render_loopsubdiv");
  sizes_and_closure();
  rays_inside();
  limits();
  bad_meshes();
  return rt_finish("test_render_loopsubdiv");
}
