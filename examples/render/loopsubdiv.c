/* loopsubdiv.c: pbrt-v3's Loop subdivision surface (shapes/loopsubdiv.cpp; the book's section 3.8,
 * Subdivision Surfaces), which Shape "loopsubdiv" turns into a triangle mesh (api_shapes.c).
 *
 * The control mesh (a triangle mesh of "indices" and "P") is refined "levels" times (pbrt-v3's default
 * 3): each triangle into four, the old ("even") vertices moved by Loop's one-ring rule (beta = 3/16 for
 * valence 3, 3 / (8 valence) otherwise, 1/16 for regular interior vertices) or the boundary rule (1/8
 * of each boundary neighbour), the new ("odd") vertices on the edges at 3/8, 3/8, 1/8, 1/8 (1/2, 1/2 on
 * a boundary). Then every vertex is pushed to its limit position (gamma = 1 / (valence + 3 / (8 beta))
 * interior, 1/5 on a boundary) and gets the limit surface's normal from two tangents of its one-ring
 * (the cos / sin weighted sums; pbrt-v3's boundary tangents for valences 2, 3, 4 and more). Vertices and
 * triangles come out in pbrt-v3's order. Positions are computed in double precision (pbrt-v3: float).
 *
 * pbrt-v3 keeps its mesh as pointers (SDVertex, SDFace); here they are arrays and indices. A face's
 * neighbour f[i] lies across its edge v[i] -> v[i + 1]. pbrt-v3 assumes a manifold, consistently
 * oriented control mesh and walks around vertices by these neighbours; a mesh where an edge has more
 * than two triangles, or two triangles run along an edge in the same direction, would make those walks
 * wrong or endless, so it is refused with a message. Triangles that repeat a vertex are left out (the
 * caller warns), and vertices that no triangle uses are dropped.
 *
 * Orientation: as in pbrt-v3, the normal Cross(S, T) of a mesh whose triangles run counter-clockwise
 * seen from outside points inwards (the one-ring is walked clockwise); the triangles' geometric normals
 * follow the shading normals (pbrt-v3's FaceForward), so glass sees the same inside as pbrt-v3. */
#include "elr_internal.h"
#include <stdlib.h>
#include <string.h>

#define NEXT(i) (((i) + 1) % 3)
#define PREV(i) (((i) + 2) % 3)

typedef struct sd_vertex { double p[3]; int start_face, child; unsigned char regular, boundary; } sd_vertex;
typedef struct sd_face { int v[3], f[3], children[4]; } sd_face;
typedef struct sd_mesh { sd_vertex *v; sd_face *f; int nv, nf; } sd_mesh;

/* >> an edge table: (smaller vertex, larger vertex) -> a value, open addressing */
typedef struct sd_edges { uint64_t *key; int *val; size_t cap; } sd_edges;
static int sd_edges_init(sd_edges *e, size_t n) {
  size_t i;
  e->cap = 16;
  while (e->cap < 2 * n) e->cap *= 2;
  e->key = (uint64_t *)malloc(e->cap * sizeof(uint64_t));
  e->val = (int *)malloc(e->cap * sizeof(int));
  if (!e->key || !e->val) { free(e->key); free(e->val); e->key = NULL; e->val = NULL; return -1; }
  for (i = 0; i < e->cap; i++) e->key[i] = ~(uint64_t)0;
  return 0;
}
static void sd_edges_free(sd_edges *e) { free(e->key); free(e->val); e->key = NULL; e->val = NULL; }
static uint64_t sd_edge_key(int a, int b) {
  unsigned lo = (unsigned)(a < b ? a : b), hi = (unsigned)(a < b ? b : a);
  return ((uint64_t)lo << 32) | hi;
}
/* the slot of key (found or empty) */
static size_t sd_edges_slot(const sd_edges *e, uint64_t key) {
  size_t i = (size_t)(elr_mix64(key) & (e->cap - 1));
  while (e->key[i] != key && e->key[i] != ~(uint64_t)0) i = (i + 1) & (e->cap - 1);
  return i;
}

/* >> SDFace and SDVertex methods (by index; -1 is pbrt-v3's nullptr) */
static int sd_vnum(const sd_face *f, int v) { return f->v[0] == v ? 0 : (f->v[1] == v ? 1 : 2); }
static int sd_next_face(const sd_mesh *m, int f, int v) { return m->f[f].f[sd_vnum(&m->f[f], v)]; }
static int sd_prev_face(const sd_mesh *m, int f, int v) { return m->f[f].f[PREV(sd_vnum(&m->f[f], v))]; }
static int sd_next_vert(const sd_mesh *m, int f, int v) { return m->f[f].v[NEXT(sd_vnum(&m->f[f], v))]; }
static int sd_prev_vert(const sd_mesh *m, int f, int v) { return m->f[f].v[PREV(sd_vnum(&m->f[f], v))]; }
static int sd_other_vert(const sd_mesh *m, int f, int v0, int v1) {
  const sd_face *F = &m->f[f];
  return F->v[0] != v0 && F->v[0] != v1 ? F->v[0] : (F->v[1] != v0 && F->v[1] != v1 ? F->v[1] : F->v[2]);
}
/* SDVertex::valence (a walk of at most nf faces: the checks above make every walk end) */
static int sd_valence(const sd_mesh *m, int v) {
  int f = m->v[v].start_face, nf = 1, guard = m->nf + 2;
  if (!m->v[v].boundary) {
    while ((f = sd_next_face(m, f, v)) != m->v[v].start_face && f >= 0 && --guard > 0) ++nf;
    return nf;
  }
  while ((f = sd_next_face(m, f, v)) >= 0 && --guard > 0) ++nf;
  f = m->v[v].start_face;
  while ((f = sd_prev_face(m, f, v)) >= 0 && --guard > 0) ++nf;
  return nf + 1;
}
/* SDVertex::oneRing: the neighbours' positions (ring holds at least valence entries) */
static void sd_one_ring(const sd_mesh *m, int v, double (*ring)[3], int n) {
  int f = m->v[v].start_face, k = 0, f2, guard = m->nf + 2;
#define SD_PUT(vi) do { if (k < n) memcpy(ring[k], m->v[(vi)].p, sizeof ring[k]); k++; } while (0)
  if (!m->v[v].boundary) {
    /* <<Get one-ring vertices for interior vertex>> */
    do {
      SD_PUT(sd_next_vert(m, f, v));
      f = sd_next_face(m, f, v);
    } while (f != m->v[v].start_face && f >= 0 && --guard > 0);
  } else {
    /* <<Get one-ring vertices for boundary vertex>> */
    while ((f2 = sd_next_face(m, f, v)) >= 0 && --guard > 0) f = f2;
    SD_PUT(sd_next_vert(m, f, v));
    do {
      SD_PUT(sd_prev_vert(m, f, v));
      f = sd_prev_face(m, f, v);
    } while (f >= 0 && --guard > 0);
  }
#undef SD_PUT
}
static double sd_beta(int valence) { return valence == 3 ? 3.0 / 16.0 : 3.0 / (8.0 * valence); }
static double sd_gamma(int valence) { return 1.0 / (valence + 3.0 / (8.0 * sd_beta(valence))); }

/* weightOneRing and weightBoundary: the vertex's new position from its one-ring (ring: scratch of cap entries) */
static int sd_weight(const sd_mesh *m, int v, double beta, int boundary_rule, double (**ring)[3], int *cap, double out[3]) {
  int n = sd_valence(m, v), i, c;
  if (n > *cap) {
    double(*r)[3] = (double(*)[3])realloc(*ring, sizeof(double[3]) * (size_t)n);
    if (!r) return -1;
    *ring = r; *cap = n;
  }
  sd_one_ring(m, v, *ring, n);
  for (c = 0; c < 3; c++) {
    if (!boundary_rule) {
      double p = (1 - n * beta) * m->v[v].p[c];
      for (i = 0; i < n; i++) p += beta * (*ring)[i][c];
      out[c] = p;
    } else {
      out[c] = (1 - 2 * beta) * m->v[v].p[c] + beta * (*ring)[0][c] + beta * (*ring)[n - 1][c];
    }
  }
  return 0;
}

int elr_loop_subdivide(int levels, const int *indices, int nindices, const double *P, int npoints, elr_mesh *out, int *dropped,
                       char *err, size_t errlen) {
  sd_mesh m, nm;
  sd_edges e;
  int *remap = NULL, i, k, lev, ringcap = 16, rc = -1;
  double(*ring)[3] = NULL, (*plimit)[3] = NULL;
  memset(&m, 0, sizeof m); memset(&nm, 0, sizeof nm); memset(&e, 0, sizeof e);
  memset(out, 0, sizeof *out);
  *dropped = 0;
  ring = (double(*)[3])malloc(sizeof(double[3]) * (size_t)ringcap);
  remap = (int *)malloc(sizeof(int) * (size_t)(npoints + 1));
  m.f = (sd_face *)malloc(sizeof(sd_face) * (size_t)(nindices / 3 + 1));
  m.v = (sd_vertex *)malloc(sizeof(sd_vertex) * (size_t)(npoints + 1));
  if (!ring || !remap || !m.f || !m.v) goto oom;
  /* <<Allocate LoopSubdiv vertices and faces>>: triangles that repeat a vertex left out, unused vertices dropped */
  for (i = 0; i < npoints; i++) remap[i] = -1;
  for (i = 0; i + 2 < nindices; i += 3) { /* the vertices used, kept in their order (pbrt-v3's when all are) */
    const int *t = indices + i;
    if (!(t[0] == t[1] || t[1] == t[2] || t[0] == t[2])) remap[t[0]] = remap[t[1]] = remap[t[2]] = 0;
  }
  for (i = 0; i < npoints; i++)
    if (remap[i] == 0) {
      sd_vertex *v = &m.v[m.nv];
      memcpy(v->p, P + 3 * (size_t)i, sizeof v->p);
      v->start_face = -1; v->child = -1; v->regular = v->boundary = 0;
      remap[i] = m.nv++;
    }
  for (i = 0; i + 2 < nindices; i += 3) {
    const int *t = indices + i;
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) { (*dropped)++; continue; }
    for (k = 0; k < 3; k++) {
      /* <<Set face to vertex pointers>> */
      m.f[m.nf].v[k] = remap[t[k]];
      m.f[m.nf].f[k] = -1;
      m.v[remap[t[k]]].start_face = m.nf;
    }
    m.nf++;
  }
  if (m.nf == 0) { snprintf(err, errlen, "no triangles (every one repeats a vertex)"); goto done; }
  { /* the size after `levels` refinements: faces times 4^levels (vertices about half as many) */
    double nfaces = (double)m.nf;
    for (lev = 0; lev < levels; lev++) nfaces *= 4;
    if (nfaces > (double)(1 << 24)) {
      snprintf(err, errlen, "%d levels of %d triangles would make %.0f triangles (at most 16777216)", levels, m.nf, nfaces);
      goto done;
    }
  }
  /* <<Set neighbor pointers in faces>>, refusing what would break the walks around vertices: an edge's
   * first triangle waits in the table (val = 3 face + edge) until its second; a third is an error */
  if (sd_edges_init(&e, (size_t)m.nf * 3) != 0) goto oom;
  for (i = 0; i < m.nf; i++)
    for (k = 0; k < 3; k++) {
      int a = m.f[i].v[k], b = m.f[i].v[NEXT(k)];
      size_t sl = sd_edges_slot(&e, sd_edge_key(a, b));
      if (e.key[sl] == ~(uint64_t)0) { e.key[sl] = sd_edge_key(a, b); e.val[sl] = 3 * i + k; continue; }
      if (e.val[sl] < 0) {
        snprintf(err, errlen, "the edge of control points %d and %d has more than two triangles (not a manifold mesh)", a, b);
        goto done;
      } else {
        int f0 = e.val[sl] / 3, e0 = e.val[sl] % 3;
        if (m.f[f0].v[e0] == a) {
          snprintf(err, errlen, "triangles %d and %d run along their shared edge in the same direction (not consistently oriented)", f0, i);
          goto done;
        }
        m.f[f0].f[e0] = i;
        m.f[i].f[k] = f0;
        e.val[sl] = -1;
      }
    }
  sd_edges_free(&e);
  /* <<Finish vertex initialization>> */
  for (i = 0; i < m.nv; i++) {
    sd_vertex *v = &m.v[i];
    int f = v->start_face, guard = m.nf + 2, val;
    do { f = sd_next_face(&m, f, i); } while (f >= 0 && f != v->start_face && --guard > 0);
    v->boundary = f < 0;
    val = sd_valence(&m, i);
    v->regular = (!v->boundary && val == 6) || (v->boundary && val == 4);
  }

  /* <<Refine LoopSubdiv into triangles>> */
  for (lev = 0; lev < levels; lev++) {
    int nodd = 0;
    /* <<Allocate next level of children in mesh tree>>: even children first, in order; then the odd
     * vertices (at most one per edge: 3 per face) */
    nm.v = (sd_vertex *)malloc(sizeof(sd_vertex) * ((size_t)m.nv + 3 * (size_t)m.nf));
    nm.f = (sd_face *)malloc(sizeof(sd_face) * 4 * (size_t)m.nf);
    if (!nm.v || !nm.f) goto oom;
    nm.nv = m.nv; nm.nf = 4 * m.nf;
    for (i = 0; i < m.nv; i++) {
      m.v[i].child = i;
      nm.v[i].regular = m.v[i].regular; nm.v[i].boundary = m.v[i].boundary;
      nm.v[i].start_face = -1; nm.v[i].child = -1;
    }
    for (i = 0; i < m.nf; i++) for (k = 0; k < 4; k++) m.f[i].children[k] = 4 * i + k;
    /* <<Update vertex positions for even vertices>> */
    for (i = 0; i < m.nv; i++) {
      int r;
      if (!m.v[i].boundary) {
        /* <<Apply one-ring rule for even vertex>> */
        r = sd_weight(&m, i, m.v[i].regular ? 1.0 / 16.0 : sd_beta(sd_valence(&m, i)), 0, &ring, &ringcap, nm.v[i].p);
      } else {
        /* <<Apply boundary rule for even vertex>> */
        r = sd_weight(&m, i, 1.0 / 8.0, 1, &ring, &ringcap, nm.v[i].p);
      }
      if (r != 0) goto oom;
    }
    /* <<Compute new odd edge vertices>> */
    if (sd_edges_init(&e, (size_t)m.nf * 3) != 0) goto oom;
    for (i = 0; i < m.nf; i++)
      for (k = 0; k < 3; k++) {
        int a = m.f[i].v[k], b = m.f[i].v[NEXT(k)], v0 = a < b ? a : b, v1 = a < b ? b : a, c;
        size_t sl = sd_edges_slot(&e, sd_edge_key(a, b));
        sd_vertex *vert;
        if (e.key[sl] != ~(uint64_t)0) continue;
        /* <<Create and initialize new odd vertex>> */
        e.key[sl] = sd_edge_key(a, b); e.val[sl] = nm.nv;
        vert = &nm.v[nm.nv++];
        nodd++;
        vert->regular = 1; vert->child = -1;
        vert->boundary = m.f[i].f[k] < 0;
        vert->start_face = m.f[i].children[3];
        /* <<Apply edge rules to compute new vertex position>> */
        for (c = 0; c < 3; c++) {
          if (vert->boundary) {
            vert->p[c] = 0.5 * m.v[v0].p[c] + 0.5 * m.v[v1].p[c];
          } else {
            vert->p[c] = 3.0 / 8.0 * m.v[v0].p[c] + 3.0 / 8.0 * m.v[v1].p[c] + 1.0 / 8.0 * m.v[sd_other_vert(&m, i, v0, v1)].p[c] +
                         1.0 / 8.0 * m.v[sd_other_vert(&m, m.f[i].f[k], v0, v1)].p[c];
          }
        }
      }
    (void)nodd;
    /* <<Update even vertex face pointers>> */
    for (i = 0; i < m.nv; i++) {
      int sf = m.v[i].start_face;
      nm.v[m.v[i].child].start_face = m.f[sf].children[sd_vnum(&m.f[sf], i)];
    }
    /* <<Update face neighbor pointers>> */
    for (i = 0; i < m.nf; i++) {
      const sd_face *F = &m.f[i];
      int j;
      for (j = 0; j < 3; j++) {
        int f2;
        /* <<Update children f pointers for siblings>> */
        nm.f[F->children[3]].f[j] = F->children[NEXT(j)];
        nm.f[F->children[j]].f[NEXT(j)] = F->children[3];
        /* <<Update children f pointers for neighbor children>> */
        f2 = F->f[j];
        nm.f[F->children[j]].f[j] = f2 >= 0 ? m.f[f2].children[sd_vnum(&m.f[f2], F->v[j])] : -1;
        f2 = F->f[PREV(j)];
        nm.f[F->children[j]].f[PREV(j)] = f2 >= 0 ? m.f[f2].children[sd_vnum(&m.f[f2], F->v[j])] : -1;
      }
    }
    /* <<Update face vertex pointers>> */
    for (i = 0; i < m.nf; i++) {
      const sd_face *F = &m.f[i];
      int j;
      for (j = 0; j < 3; j++) {
        int vert = e.val[sd_edges_slot(&e, sd_edge_key(F->v[j], F->v[NEXT(j)]))];
        /* <<Update child vertex pointer to new even vertex>> */
        nm.f[F->children[j]].v[j] = m.v[F->v[j]].child;
        /* <<Update child vertex pointer to new odd vertex>> */
        nm.f[F->children[j]].v[NEXT(j)] = vert;
        nm.f[F->children[NEXT(j)]].v[j] = vert;
        nm.f[F->children[3]].v[j] = vert;
      }
    }
    sd_edges_free(&e);
    /* <<Prepare for next level of subdivision>> */
    free(m.v); free(m.f);
    m = nm;
    memset(&nm, 0, sizeof nm);
  }

  /* <<Push vertices to limit surface>> */
  plimit = (double(*)[3])malloc(sizeof(double[3]) * (size_t)m.nv);
  if (!plimit) goto oom;
  for (i = 0; i < m.nv; i++) {
    int r = m.v[i].boundary ? sd_weight(&m, i, 1.0 / 5.0, 1, &ring, &ringcap, plimit[i])
                            : sd_weight(&m, i, sd_gamma(sd_valence(&m, i)), 0, &ring, &ringcap, plimit[i]);
    if (r != 0) goto oom;
  }
  for (i = 0; i < m.nv; i++) memcpy(m.v[i].p, plimit[i], sizeof m.v[i].p);

  out->nvert = m.nv; out->ntri = m.nf;
  out->p = (float *)malloc(sizeof(float) * 3 * (size_t)m.nv);
  out->n = (float *)malloc(sizeof(float) * 3 * (size_t)m.nv);
  out->idx = (unsigned *)malloc(sizeof(unsigned) * 3 * (size_t)m.nf);
  if (!out->p || !out->n || !out->idx) goto oom;
  /* <<Compute vertex tangents on limit surface>> */
  for (i = 0; i < m.nv; i++) {
    double S[3] = {0, 0, 0}, T[3] = {0, 0, 0}, N[3];
    const double *vp = m.v[i].p;
    int val = sd_valence(&m, i), j, c;
    if (val > ringcap) {
      double(*r)[3] = (double(*)[3])realloc(ring, sizeof(double[3]) * (size_t)val);
      if (!r) goto oom;
      ring = r; ringcap = val;
    }
    sd_one_ring(&m, i, ring, val);
    if (!m.v[i].boundary) {
      /* <<Compute tangents of interior face>> */
      for (j = 0; j < val; j++) {
        double cs = cos(2 * 3.14159265358979323846 * j / val), sn = sin(2 * 3.14159265358979323846 * j / val);
        for (c = 0; c < 3; c++) { S[c] += cs * ring[j][c]; T[c] += sn * ring[j][c]; }
      }
    } else {
      /* <<Compute tangents of boundary face>> */
      for (c = 0; c < 3; c++) S[c] = ring[val - 1][c] - ring[0][c];
      if (val == 2) for (c = 0; c < 3; c++) T[c] = ring[0][c] + ring[1][c] - 2 * vp[c];
      else if (val == 3) for (c = 0; c < 3; c++) T[c] = ring[1][c] - vp[c];
      else if (val == 4) /* regular */
        for (c = 0; c < 3; c++) T[c] = -1 * ring[0][c] + 2 * ring[1][c] + 2 * ring[2][c] + -1 * ring[3][c] + -2 * vp[c];
      else {
        double theta = 3.14159265358979323846 / (double)(val - 1);
        for (c = 0; c < 3; c++) T[c] = sin(theta) * (ring[0][c] + ring[val - 1][c]);
        for (j = 1; j < val - 1; j++) {
          double wt = (2 * cos(theta) - 2) * sin(j * theta);
          for (c = 0; c < 3; c++) T[c] += wt * ring[j][c];
        }
        for (c = 0; c < 3; c++) T[c] = -T[c];
      }
    }
    N[0] = S[1] * T[2] - S[2] * T[1]; N[1] = S[2] * T[0] - S[0] * T[2]; N[2] = S[0] * T[1] - S[1] * T[0];
    for (c = 0; c < 3; c++) { out->p[3 * i + c] = (float)vp[c]; out->n[3 * i + c] = (float)N[c]; }
  }
  { /* where the two tangents are parallel (coincident control points), the normal of the triangles
     * around the vertex instead (turned as Cross(S, T) turns: against their counter-clockwise normal) */
    double *acc = NULL;
    for (i = 0; i < m.nv; i++) {
      const float *n = out->n + 3 * i;
      if (n[0] != 0.f || n[1] != 0.f || n[2] != 0.f) continue;
      if (!acc) {
        acc = (double *)calloc(3 * (size_t)m.nv, sizeof(double));
        if (!acc) goto oom;
        for (k = 0; k < m.nf; k++) {
          const double *a = m.v[m.f[k].v[0]].p, *b = m.v[m.f[k].v[1]].p, *c = m.v[m.f[k].v[2]].p;
          double u[3], w[3], fn[3];
          int j, q;
          for (q = 0; q < 3; q++) { u[q] = b[q] - a[q]; w[q] = c[q] - a[q]; }
          fn[0] = u[1] * w[2] - u[2] * w[1]; fn[1] = u[2] * w[0] - u[0] * w[2]; fn[2] = u[0] * w[1] - u[1] * w[0];
          for (j = 0; j < 3; j++) for (q = 0; q < 3; q++) acc[3 * (size_t)m.f[k].v[j] + (size_t)q] -= fn[q];
        }
      }
      out->n[3 * i] = (float)acc[3 * i]; out->n[3 * i + 1] = (float)acc[3 * i + 1]; out->n[3 * i + 2] = (float)acc[3 * i + 2];
    }
    free(acc);
  }
  /* <<Create triangle mesh from subdivision mesh>> */
  for (i = 0; i < m.nf; i++)
    for (k = 0; k < 3; k++) out->idx[3 * i + k] = (unsigned)m.f[i].v[k];
  rc = 0;
  goto done;
oom:
  snprintf(err, errlen, "out of memory");
done:
  if (rc != 0) { free(out->p); free(out->n); free(out->idx); memset(out, 0, sizeof *out); }
  sd_edges_free(&e);
  free(m.v); free(m.f); free(nm.v); free(nm.f); free(ring); free(remap); free(plimit);
  return rc;
}
