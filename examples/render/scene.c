/* scene.c: transforms, the PLY reader, and the Embree scene (triangle meshes and exact spheres).
 *
 * Spheres are an Embree user geometry: each sphere is pbrt-v3's Sphere in its object space (any affine
 * object-to-world transform, so a non-uniformly scaled sphere is an exact ellipsoid), intersected in
 * double precision; never a tessellation. Triangle meshes are Embree triangle geometries in world space
 * (pbrt-v3 also transforms mesh vertices to world space when it creates them). */
#define _POSIX_C_SOURCE 200809L
#include "elr_internal.h"
#include "image_io.h"
#include <embree3/rtcore.h>
#include <float.h>
#include <stdlib.h>
#include <string.h>

/* >> transforms */
void elr_xform_identity(elr_xform *t) {
  int i, j;
  for (i = 0; i < 4; i++) for (j = 0; j < 4; j++) t->m[i][j] = t->inv[i][j] = i == j ? 1.0 : 0.0;
}
static int elr__inverse(double m[4][4], double out[4][4]) {
  /* Gauss-Jordan with full pivoting, as pbrt-v3's Inverse() */
  int indxc[4], indxr[4], ipiv[4] = {0, 0, 0, 0};
  double minv[4][4];
  int i, j, k;
  memcpy(minv, m, sizeof minv);
  for (i = 0; i < 4; i++) {
    int irow = 0, icol = 0;
    double big = 0.0, pivinv;
    for (j = 0; j < 4; j++) {
      if (ipiv[j] != 1) {
        for (k = 0; k < 4; k++) {
          if (ipiv[k] == 0) {
            if (fabs(minv[j][k]) >= big) { big = fabs(minv[j][k]); irow = j; icol = k; }
          } else if (ipiv[k] > 1) return -1;
        }
      }
    }
    ++ipiv[icol];
    if (irow != icol) for (k = 0; k < 4; ++k) { double tmp = minv[irow][k]; minv[irow][k] = minv[icol][k]; minv[icol][k] = tmp; }
    indxr[i] = irow; indxc[i] = icol;
    if (minv[icol][icol] == 0.0 || !isfinite(minv[icol][icol])) return -1;
    pivinv = 1.0 / minv[icol][icol];
    minv[icol][icol] = 1.0;
    for (j = 0; j < 4; j++) minv[icol][j] *= pivinv;
    for (j = 0; j < 4; j++) {
      if (j != icol) {
        double save = minv[j][icol];
        minv[j][icol] = 0;
        for (k = 0; k < 4; k++) minv[j][k] -= minv[icol][k] * save;
      }
    }
  }
  for (j = 3; j >= 0; j--) {
    if (indxr[j] != indxc[j]) {
      for (k = 0; k < 4; k++) { double tmp = minv[k][indxr[j]]; minv[k][indxr[j]] = minv[k][indxc[j]]; minv[k][indxc[j]] = tmp; }
    }
  }
  memcpy(out, minv, sizeof minv);
  return 0;
}
int elr_xform_from_matrix(elr_xform *t, double m[4][4]) {
  memcpy(t->m, m, sizeof t->m);
  if (elr__inverse(m, t->inv) != 0) { elr_xform_identity(t); memcpy(t->m, m, sizeof t->m); return -1; }
  return 0;
}
void elr_xform_mul(elr_xform *out, const elr_xform *a, const elr_xform *b) {
  elr_xform r;
  int i, j, k;
  for (i = 0; i < 4; i++)
    for (j = 0; j < 4; j++) {
      double s = 0, si = 0;
      for (k = 0; k < 4; k++) { s += a->m[i][k] * b->m[k][j]; si += b->inv[i][k] * a->inv[k][j]; }
      r.m[i][j] = s; r.inv[i][j] = si;
    }
  *out = r;
}
void elr_xform_invert(elr_xform *out, const elr_xform *a) {
  elr_xform r;
  memcpy(r.m, a->inv, sizeof r.m); memcpy(r.inv, a->m, sizeof r.inv);
  *out = r;
}
elr_v3 elr_xpoint(const elr_xform *t, elr_v3 p) {
  const double(*m)[4] = t->m;
  double x = m[0][0] * p.x + m[0][1] * p.y + m[0][2] * p.z + m[0][3];
  double y = m[1][0] * p.x + m[1][1] * p.y + m[1][2] * p.z + m[1][3];
  double z = m[2][0] * p.x + m[2][1] * p.y + m[2][2] * p.z + m[2][3];
  double w = m[3][0] * p.x + m[3][1] * p.y + m[3][2] * p.z + m[3][3];
  if (w != 1.0 && w != 0.0) { x /= w; y /= w; z /= w; }
  return elr_v((float)x, (float)y, (float)z);
}
elr_v3 elr_xvector(const elr_xform *t, elr_v3 v) {
  const double(*m)[4] = t->m;
  return elr_v((float)(m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z), (float)(m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z),
               (float)(m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z));
}
elr_v3 elr_xnormal(const elr_xform *t, elr_v3 n) {
  const double(*mi)[4] = t->inv;
  return elr_v((float)(mi[0][0] * n.x + mi[1][0] * n.y + mi[2][0] * n.z), (float)(mi[0][1] * n.x + mi[1][1] * n.y + mi[2][1] * n.z),
               (float)(mi[0][2] * n.x + mi[1][2] * n.y + mi[2][2] * n.z));
}
elr_v3 elr_xvector_inv(const elr_xform *t, elr_v3 v) {
  const double(*m)[4] = t->inv;
  return elr_v((float)(m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z), (float)(m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z),
               (float)(m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z));
}

/* >> PLY */
enum { PLY_I8, PLY_U8, PLY_I16, PLY_U16, PLY_I32, PLY_U32, PLY_F32, PLY_F64, PLY_BAD };
static int elr__ply_type(const char *s) {
  if (!strcmp(s, "char") || !strcmp(s, "int8")) return PLY_I8;
  if (!strcmp(s, "uchar") || !strcmp(s, "uint8")) return PLY_U8;
  if (!strcmp(s, "short") || !strcmp(s, "int16")) return PLY_I16;
  if (!strcmp(s, "ushort") || !strcmp(s, "uint16")) return PLY_U16;
  if (!strcmp(s, "int") || !strcmp(s, "int32")) return PLY_I32;
  if (!strcmp(s, "uint") || !strcmp(s, "uint32")) return PLY_U32;
  if (!strcmp(s, "float") || !strcmp(s, "float32")) return PLY_F32;
  if (!strcmp(s, "double") || !strcmp(s, "float64")) return PLY_F64;
  return PLY_BAD;
}
static const int elr__ply_size[] = {1, 1, 2, 2, 4, 4, 4, 8};

typedef struct { char name[64]; int type, list, count_type; } elr__ply_prop;
typedef struct { char name[64]; long count; elr__ply_prop prop[32]; int nprop; } elr__ply_elem;

typedef struct {
  const unsigned char *p, *end;
  int format; /* 0 ascii, 1 little, 2 big */
  int bad;
} elr__ply_rd;

static double elr__ply_read(elr__ply_rd *r, int type) {
  if (r->format == 0) {
    char *e;
    double v;
    char buf[64]; int n = 0;
    while (r->p < r->end && (*r->p == ' ' || *r->p == '\t' || *r->p == '\r' || *r->p == '\n')) r->p++;
    while (r->p < r->end && n < 63 && !(*r->p == ' ' || *r->p == '\t' || *r->p == '\r' || *r->p == '\n')) buf[n++] = (char)*r->p++;
    buf[n] = 0;
    if (n == 0) { r->bad = 1; return 0; }
    v = strtod(buf, &e);
    if (*e) r->bad = 1;
    return v;
  } else {
    unsigned char b[8];
    int n = elr__ply_size[type], i;
    if (r->end - r->p < n) { r->bad = 1; return 0; }
    for (i = 0; i < n; i++) b[i] = r->p[r->format == 1 ? i : n - 1 - i];
    r->p += n;
    switch (type) {
    case PLY_I8: return (double)(signed char)b[0];
    case PLY_U8: return (double)b[0];
    case PLY_I16: { int16_t v; memcpy(&v, b, 2); return v; }
    case PLY_U16: { uint16_t v; memcpy(&v, b, 2); return v; }
    case PLY_I32: { int32_t v; memcpy(&v, b, 4); return v; }
    case PLY_U32: { uint32_t v; memcpy(&v, b, 4); return v; }
    case PLY_F32: { float v; memcpy(&v, b, 4); return v; }
    default: { double v; memcpy(&v, b, 8); return v; }
    }
  }
}

int elr_ply_load(const char *path, elr_mesh *m, char *err, size_t errlen) {
  char why[128] = "";
  FILE *f = el_file_is_regular(path, why, sizeof why) == 0 ? fopen(path, "rb") : NULL;
  long n;
  unsigned char *buf = NULL;
  elr__ply_elem el[8];
  int nel = 0, e, ok = 0;
  elr__ply_rd rd;
  char line[256];
  const unsigned char *p;
  size_t ntri = 0, captri = 0;
  unsigned *idx = NULL;
  memset(m, 0, sizeof *m);
  memset(&rd, 0, sizeof rd);
  if (!f) { snprintf(err, errlen, "cannot open \"%s\"%s%s", path, why[0] ? ": " : "", why); return -1; }
  if (fseek(f, 0, SEEK_END) != 0 || (n = ftell(f)) < 0 || fseek(f, 0, SEEK_SET) != 0 || n > (1L << 31)) {
    fclose(f); snprintf(err, errlen, "cannot read \"%s\"", path); return -1;
  }
  buf = (unsigned char *)malloc((size_t)n + 1);
  if (!buf || (n > 0 && fread(buf, 1, (size_t)n, f) != (size_t)n)) { fclose(f); free(buf); snprintf(err, errlen, "cannot read \"%s\"", path); return -1; }
  fclose(f);
  buf[n] = 0;
  p = buf;
#define PLY_FAIL(...) do { snprintf(err, errlen, __VA_ARGS__); goto done; } while (0)
  /* header */
  {
    int first = 1;
    rd.format = -1;
    for (;;) {
      size_t k = 0;
      char w0[64] = "", w1[64] = "", w2[64] = "", w3[64] = "", w4[64] = "";
      int nw, cut = 0;
      if (p >= buf + n) PLY_FAIL("\"%s\": PLY header has no end_header", path);
      while (p < buf + n && *p != '\n' && k < sizeof line - 1) line[k++] = (char)*p++;
      /* a line longer than the buffer: its rest is skipped (only a comment may be that long, below) */
      while (p < buf + n && *p != '\n') { p++; cut = 1; }
      if (p < buf + n && *p == '\n') p++;
      line[k] = 0;
      if (k && line[k - 1] == '\r') line[k - 1] = 0;
      nw = sscanf(line, "%63s %63s %63s %63s %63s", w0, w1, w2, w3, w4);
      if (first) { if (strcmp(w0, "ply") != 0) PLY_FAIL("\"%s\" is not a PLY file", path); first = 0; continue; }
      if (nw <= 0) continue;
      if (cut && strcmp(w0, "comment") != 0 && strcmp(w0, "obj_info") != 0)
        PLY_FAIL("\"%s\": PLY header line \"%.40s...\" is longer than %d characters", path, line, (int)sizeof line - 1);
      if (!strcmp(w0, "format")) {
        if (!strcmp(w1, "ascii")) rd.format = 0;
        else if (!strcmp(w1, "binary_little_endian")) rd.format = 1;
        else if (!strcmp(w1, "binary_big_endian")) rd.format = 2;
        else PLY_FAIL("\"%s\": unknown PLY format \"%s\"", path, w1);
      } else if (!strcmp(w0, "element")) {
        char *e2;
        if (nel == 8) PLY_FAIL("\"%s\": too many PLY elements", path);
        memset(&el[nel], 0, sizeof el[nel]);
        snprintf(el[nel].name, sizeof el[nel].name, "%s", w1);
        el[nel].count = strtol(w2, &e2, 10);
        if (*e2 || el[nel].count < 0 || el[nel].count > (1L << 28)) PLY_FAIL("\"%s\": bad element count \"%s\"", path, w2);
        nel++;
      } else if (!strcmp(w0, "property")) {
        elr__ply_prop *pr;
        if (nel == 0 || el[nel - 1].nprop == 32) PLY_FAIL("\"%s\": property outside an element or too many", path);
        pr = &el[nel - 1].prop[el[nel - 1].nprop++];
        if (!strcmp(w1, "list")) {
          pr->list = 1; pr->count_type = elr__ply_type(w2); pr->type = elr__ply_type(w3);
          snprintf(pr->name, sizeof pr->name, "%s", w4);
          if (pr->count_type == PLY_BAD || pr->type == PLY_BAD) PLY_FAIL("\"%s\": unknown PLY type in \"%s\"", path, line);
        } else {
          pr->type = elr__ply_type(w1);
          snprintf(pr->name, sizeof pr->name, "%s", w2);
          if (pr->type == PLY_BAD) PLY_FAIL("\"%s\": unknown PLY type in \"%s\"", path, line);
        }
      } else if (!strcmp(w0, "end_header")) break;
    }
    if (rd.format < 0) PLY_FAIL("\"%s\": PLY header has no format line", path);
    for (e = 0; e < nel; e++) { /* faces whose index list has another name would be read and dropped */
      int j, lists = 0;
      if (strcmp(el[e].name, "face") != 0 || el[e].count == 0) continue;
      for (j = 0; j < el[e].nprop; j++)
        if (el[e].prop[j].list && (!strcmp(el[e].prop[j].name, "vertex_indices") || !strcmp(el[e].prop[j].name, "vertex_index"))) lists++;
      if (!lists) PLY_FAIL("\"%s\": the face element has no \"vertex_indices\" (or \"vertex_index\") list", path);
    }
  }
  rd.p = p; rd.end = buf + n;
  for (e = 0; e < nel; e++) {
    elr__ply_elem *E = &el[e];
    int isv = !strcmp(E->name, "vertex"), isf = !strcmp(E->name, "face");
    int px = -1, py = -1, pz = -1, nx = -1, ny = -1, nz = -1, pu = -1, pv = -1, j;
    long i;
    double vals[32];
    {
      /* every element takes at least one byte per property (binary) or two characters (ASCII): a count
       * the rest of the file cannot hold is a truncated or corrupt file, not an allocation to attempt */
      double need = (double)E->count * (double)(E->nprop > 0 ? E->nprop : 1) * (rd.format == 0 ? 2.0 : 1.0);
      if (need > (double)(rd.end - rd.p) + 1.0) PLY_FAIL("\"%s\": file is truncated (%ld %s elements announced)", path, E->count, E->name);
    }
    if (isv) {
      if (m->p) PLY_FAIL("\"%s\": two vertex elements", path);
      for (j = 0; j < E->nprop; j++) {
        const char *nm = E->prop[j].name;
        if (!strcmp(nm, "x")) px = j; else if (!strcmp(nm, "y")) py = j; else if (!strcmp(nm, "z")) pz = j;
        else if (!strcmp(nm, "nx")) nx = j; else if (!strcmp(nm, "ny")) ny = j; else if (!strcmp(nm, "nz")) nz = j;
        else if (!strcmp(nm, "u") || !strcmp(nm, "s") || !strcmp(nm, "texture_u") || !strcmp(nm, "texture_s")) pu = j;
        else if (!strcmp(nm, "v") || !strcmp(nm, "t") || !strcmp(nm, "texture_v") || !strcmp(nm, "texture_t")) pv = j;
      }
      if (px < 0 || py < 0 || pz < 0) PLY_FAIL("\"%s\": vertices have no x, y, z", path);
      { /* a list-valued coordinate would leave its value unread (uninitialised) */
        int want[8], w;
        want[0] = px; want[1] = py; want[2] = pz; want[3] = nx; want[4] = ny; want[5] = nz; want[6] = pu; want[7] = pv;
        for (w = 0; w < 8; w++)
          if (want[w] >= 0 && E->prop[want[w]].list)
            PLY_FAIL("\"%s\": vertex property \"%s\" is a list, not a number", path, E->prop[want[w]].name);
      }
      m->nvert = (int)E->count;
      m->p = (float *)malloc(sizeof(float) * 3 * (size_t)(E->count ? E->count : 1));
      if (nx >= 0 && ny >= 0 && nz >= 0) m->n = (float *)malloc(sizeof(float) * 3 * (size_t)(E->count ? E->count : 1));
      if (pu >= 0 && pv >= 0) m->uv = (float *)malloc(sizeof(float) * 2 * (size_t)(E->count ? E->count : 1));
      if (!m->p || (nx >= 0 && ny >= 0 && nz >= 0 && !m->n) || (pu >= 0 && pv >= 0 && !m->uv)) PLY_FAIL("out of memory");
    }
    for (i = 0; i < E->count; i++) {
      for (j = 0; j < E->nprop; j++) {
        elr__ply_prop *pr = &E->prop[j];
        if (pr->list) {
          double cnt = elr__ply_read(&rd, pr->count_type);
          long c, k;
          unsigned first = 0, prev = 0;
          if (rd.bad) PLY_FAIL("\"%s\": file is truncated or malformed (element \"%s\" %ld)", path, E->name, i);
          if (!(cnt >= 0 && cnt <= 1000) || cnt != floor(cnt)) /* NaN too: (long)NaN is undefined */
            PLY_FAIL("\"%s\": element \"%s\" %ld: list of %g entries (0 to 1000 expected)", path, E->name, i, cnt);
          c = (long)cnt;
          for (k = 0; k < c; k++) {
            double v = elr__ply_read(&rd, pr->type);
            if (rd.bad) PLY_FAIL("\"%s\": file is truncated or malformed (element \"%s\" %ld)", path, E->name, i);
            if (isf && (!strcmp(pr->name, "vertex_indices") || !strcmp(pr->name, "vertex_index"))) {
              unsigned u;
              if (!(v >= 0 && v < (double)m->nvert) || v != floor(v) || !m->p) /* NaN too: (unsigned)NaN is undefined */
                PLY_FAIL("\"%s\": face %ld has vertex index %g out of range", path, i, v);
              u = (unsigned)v; /* after the check: a negative or huge double is undefined as unsigned */
              if (k == 0) first = u;
              else if (k >= 2) { /* fan triangulation (quads become two triangles, as pbrt-v3) */
                if (ntri == captri) {
                  size_t nc = captri ? captri * 2 : 1024;
                  unsigned *ni = (unsigned *)realloc(idx, nc * 3 * sizeof(unsigned));
                  if (!ni) PLY_FAIL("out of memory");
                  idx = ni; captri = nc;
                }
                idx[ntri * 3] = first; idx[ntri * 3 + 1] = prev; idx[ntri * 3 + 2] = u; ntri++;
              }
              prev = u;
            }
          }
        } else {
          double v = elr__ply_read(&rd, pr->type);
          if (rd.bad) PLY_FAIL("\"%s\": file is truncated or malformed (element \"%s\" %ld)", path, E->name, i);
          vals[j] = v;
        }
      }
      if (isv) {
        m->p[3 * i] = (float)vals[px]; m->p[3 * i + 1] = (float)vals[py]; m->p[3 * i + 2] = (float)vals[pz];
        if (m->n) { m->n[3 * i] = (float)vals[nx]; m->n[3 * i + 1] = (float)vals[ny]; m->n[3 * i + 2] = (float)vals[nz]; }
        if (m->uv) { m->uv[2 * i] = (float)vals[pu]; m->uv[2 * i + 1] = (float)vals[pv]; }
      }
    }
  }
  if (!m->p) PLY_FAIL("\"%s\": no vertex element", path);
  if (ntri == 0) PLY_FAIL("\"%s\": no triangles", path);
  if (ntri > (size_t)1 << 30) PLY_FAIL("\"%s\": too many triangles", path);
  m->idx = idx; m->ntri = (int)ntri; idx = NULL;
  ok = 1;
done:
#undef PLY_FAIL
  free(buf);
  free(idx);
  if (!ok) { free(m->p); free(m->n); free(m->uv); memset(m, 0, sizeof *m); return -1; }
  return 0;
}

/* >> Embree */
static size_t elr__embree_bytes; /* device memory monitor (one render at a time per process) */
static bool elr__memmon(void *ptr, ssize_t bytes, bool post) {
  (void)ptr; (void)post;
  if (bytes > 0) elr__embree_bytes += (size_t)bytes; else elr__embree_bytes -= (size_t)(-bytes);
  return true;
}

typedef struct elr__sph_rt { double w2o[3][4]; double r2; } elr__sph_rt;

static void elr__sph_bounds(const struct RTCBoundsFunctionArguments *a) {
  const elr_scene *s = (const elr_scene *)a->geometryUserPtr;
  const elr_sphere *sp = &s->sph[s->sph_user[a->primID]];
  float r = sp->radius;
  int i;
  struct RTCBounds *b = a->bounds_o;
  b->lower_x = b->lower_y = b->lower_z = FLT_MAX;
  b->upper_x = b->upper_y = b->upper_z = -FLT_MAX;
  for (i = 0; i < 8; i++) {
    elr_v3 c = elr_xpoint(&sp->o2w, elr_v(i & 1 ? r : -r, i & 2 ? r : -r, i & 4 ? r : -r));
    b->lower_x = fminf(b->lower_x, c.x); b->upper_x = fmaxf(b->upper_x, c.x);
    b->lower_y = fminf(b->lower_y, c.y); b->upper_y = fmaxf(b->upper_y, c.y);
    b->lower_z = fminf(b->lower_z, c.z); b->upper_z = fmaxf(b->upper_z, c.z);
  }
  {
    float pad = 1e-6f * (fabsf(b->upper_x) + fabsf(b->upper_y) + fabsf(b->upper_z) + fabsf(b->lower_x) + fabsf(b->lower_y) + fabsf(b->lower_z) + r);
    b->lower_x -= pad; b->lower_y -= pad; b->lower_z -= pad; b->upper_x += pad; b->upper_y += pad; b->upper_z += pad;
  }
}

/* object-space quadratic in double precision; returns the nearest t in (tnear, tfar) or -1 */
static double elr__sph_hit(const elr_sphere *sp, float ox, float oy, float oz, float dx, float dy, float dz, float tnear, float tfar) {
  const double(*m)[4] = sp->o2w.inv;
  double o0 = m[0][0] * ox + m[0][1] * oy + m[0][2] * oz + m[0][3];
  double o1 = m[1][0] * ox + m[1][1] * oy + m[1][2] * oz + m[1][3];
  double o2 = m[2][0] * ox + m[2][1] * oy + m[2][2] * oz + m[2][3];
  double d0 = m[0][0] * dx + m[0][1] * dy + m[0][2] * dz;
  double d1 = m[1][0] * dx + m[1][1] * dy + m[1][2] * dz;
  double d2 = m[2][0] * dx + m[2][1] * dy + m[2][2] * dz;
  double r = sp->radius;
  double A = d0 * d0 + d1 * d1 + d2 * d2, B = 2 * (d0 * o0 + d1 * o1 + d2 * o2), C = o0 * o0 + o1 * o1 + o2 * o2 - r * r;
  double disc = B * B - 4 * A * C, q, t0, t1;
  if (disc < 0 || A == 0) return -1;
  disc = sqrt(disc);
  q = B < 0 ? -0.5 * (B - disc) : -0.5 * (B + disc);
  t0 = q / A; t1 = q != 0 ? C / q : t0;
  if (t0 > t1) { double t = t0; t0 = t1; t1 = t; }
  if (t0 > tnear && t0 < tfar) return t0;
  if (t1 > tnear && t1 < tfar) return t1;
  return -1;
}

static void elr__sph_intersect(const struct RTCIntersectFunctionNArguments *a) {
  const elr_scene *s = (const elr_scene *)a->geometryUserPtr;
  struct RTCRayHit *rh = (struct RTCRayHit *)a->rayhit;
  const elr_sphere *sp = &s->sph[s->sph_user[a->primID]];
  double t;
  if (!a->valid[0]) return;
  t = elr__sph_hit(sp, rh->ray.org_x, rh->ray.org_y, rh->ray.org_z, rh->ray.dir_x, rh->ray.dir_y, rh->ray.dir_z,
                   rh->ray.tnear, rh->ray.tfar);
  if (t < 0) return;
  rh->ray.tfar = (float)t;
  rh->hit.u = rh->hit.v = 0.f;
  rh->hit.Ng_x = 0; rh->hit.Ng_y = 0; rh->hit.Ng_z = 1; /* computed in elr_intersect */
  rh->hit.primID = a->primID;
  rh->hit.geomID = a->geomID;
  rh->hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
}
static void elr__sph_occluded(const struct RTCOccludedFunctionNArguments *a) {
  const elr_scene *s = (const elr_scene *)a->geometryUserPtr;
  struct RTCRay *ray = (struct RTCRay *)a->ray;
  const elr_sphere *sp = &s->sph[s->sph_user[a->primID]];
  if (!a->valid[0]) return;
  if (elr__sph_hit(sp, ray->org_x, ray->org_y, ray->org_z, ray->dir_x, ray->dir_y, ray->dir_z, ray->tnear, ray->tfar) >= 0)
    ray->tfar = -INFINITY;
}

int elr_scene_build(elr_scene *s, char *err, size_t errlen) {
  RTCDevice dev;
  RTCScene sc;
  int i;
  double t0 = elr_now();
  elr__embree_bytes = 0;
  dev = rtcNewDevice("verbose=0");
  if (!dev) { snprintf(err, errlen, "Embree: cannot create a device (error %d)", (int)rtcGetDeviceError(NULL)); return -1; }
  rtcSetDeviceMemoryMonitorFunction(dev, elr__memmon, NULL);
  s->device = dev;
  sc = rtcNewScene(dev);
  s->rtscene = sc;
  rtcSetSceneBuildQuality(sc, RTC_BUILD_QUALITY_HIGH);
  s->ngeom = (unsigned)s->nmesh + (s->nsph ? 2u : 0u);
  s->geom_kind = (unsigned *)calloc(s->ngeom + 1, sizeof(unsigned));
  s->geom_index = (int *)calloc(s->ngeom + 1, sizeof(int));
  if (!s->geom_kind || !s->geom_index) { snprintf(err, errlen, "out of memory"); return -1; }
  s->sphere_geom = ~0u;
  for (i = 0; i < s->nmesh; i++) {
    elr_mesh *m = &s->mesh[i];
    RTCGeometry g = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
    float *vb = (float *)rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), (size_t)m->nvert);
    unsigned *ib = (unsigned *)rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), (size_t)m->ntri);
    unsigned id;
    if (!vb || !ib) { rtcReleaseGeometry(g); snprintf(err, errlen, "Embree: out of memory for mesh %d", i); return -1; }
    memcpy(vb, m->p, sizeof(float) * 3 * (size_t)m->nvert);
    memcpy(ib, m->idx, sizeof(unsigned) * 3 * (size_t)m->ntri);
    rtcCommitGeometry(g);
    id = rtcAttachGeometry(sc, g);
    rtcReleaseGeometry(g);
    s->geom_kind[id] = 0; s->geom_index[id] = i;
  }
  /* Spheres are the user geometry above (pbrt-v3's Sphere in object space, in double precision: any
   * affine transform, so a non-uniform Scale gives an exact ellipsoid). With the environment variable
   * ELR_EMBREE_SPHERES set, spheres whose object-to-world transform is a similarity (rotation, uniform
   * scale, translation) use Embree's RTC_GEOMETRY_TYPE_SPHERE_POINT instead; on the benchmark scene that
   * was not faster (830 vs 734 instructions per rtcIntersect1 under callgrind, and lower measured rates),
   * so it is not the default. Both are refined the same way in elr_intersect. */
  s->sph_builtin = (int *)calloc((size_t)s->nsph + 1, sizeof(int));
  if (!s->sph_builtin) { snprintf(err, errlen, "out of memory"); return -1; }
  s->builtin_geom = ~0u;
  {
    int nb = 0;
    for (i = 0; i < s->nsph; i++) {
      const double(*m)[4] = (const double(*)[4])s->sph[i].o2w.m;
      double g[3][3], sc;
      int a, b, k, sim = 1;
      for (a = 0; a < 3; a++)
        for (b = 0; b < 3; b++) { g[a][b] = 0; for (k = 0; k < 3; k++) g[a][b] += m[k][a] * m[k][b]; }
      sc = g[0][0];
      for (a = 0; a < 3; a++)
        for (b = 0; b < 3; b++) if (fabs(g[a][b] - (a == b ? sc : 0.0)) > 1e-9 * sc) sim = 0;
      if (m[3][0] != 0 || m[3][1] != 0 || m[3][2] != 0 || m[3][3] != 1) sim = 0;
      if (sim && getenv("ELR_EMBREE_SPHERES")) s->sph_builtin[nb++] = i;
    }
    if (nb > 0) {
      RTCGeometry g = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_SPHERE_POINT);
      float *vb = (float *)rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, 4 * sizeof(float), (size_t)nb);
      unsigned id;
      if (!vb) { rtcReleaseGeometry(g); snprintf(err, errlen, "Embree: out of memory for spheres"); return -1; }
      for (i = 0; i < nb; i++) {
        const elr_sphere *sp = &s->sph[s->sph_builtin[i]];
        elr_v3 c = elr_xpoint(&sp->o2w, elr_v(0, 0, 0));
        double sc = sqrt(sp->o2w.m[0][0] * sp->o2w.m[0][0] + sp->o2w.m[1][0] * sp->o2w.m[1][0] + sp->o2w.m[2][0] * sp->o2w.m[2][0]);
        vb[4 * i] = c.x; vb[4 * i + 1] = c.y; vb[4 * i + 2] = c.z; vb[4 * i + 3] = (float)(sp->radius * sc);
      }
      rtcCommitGeometry(g);
      id = rtcAttachGeometry(sc, g);
      rtcReleaseGeometry(g);
      s->builtin_geom = id;
      s->nbuiltin = nb;
    }
    s->nuser = 0;
    s->sph_user = (int *)calloc((size_t)s->nsph + 1, sizeof(int));
    if (!s->sph_user) { snprintf(err, errlen, "out of memory"); return -1; }
    for (i = 0; i < s->nsph; i++) {
      int k, b = 0;
      for (k = 0; k < nb; k++) if (s->sph_builtin[k] == i) b = 1;
      if (!b) s->sph_user[s->nuser++] = i;
    }
  }
  if (s->nuser) {
    RTCGeometry g = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_USER);
    unsigned id;
    rtcSetGeometryUserPrimitiveCount(g, (unsigned)s->nuser);
    rtcSetGeometryUserData(g, s);
    rtcSetGeometryBoundsFunction(g, elr__sph_bounds, NULL);
    rtcSetGeometryIntersectFunction(g, elr__sph_intersect);
    rtcSetGeometryOccludedFunction(g, elr__sph_occluded);
    rtcCommitGeometry(g);
    id = rtcAttachGeometry(sc, g);
    rtcReleaseGeometry(g);
    s->geom_kind[id] = 1; s->geom_index[id] = 0;
    s->sphere_geom = id;
  }
  rtcCommitScene(sc);
  if (rtcGetDeviceError(dev) != RTC_ERROR_NONE) { snprintf(err, errlen, "Embree: building the scene failed"); return -1; }
  {
    struct RTCBounds b;
    rtcGetSceneBounds(sc, &b);
    if (s->nmesh + s->nsph > 0 && b.lower_x <= b.upper_x) {
      s->world_center = elr_v(0.5f * (b.lower_x + b.upper_x), 0.5f * (b.lower_y + b.upper_y), 0.5f * (b.lower_z + b.upper_z));
      s->world_radius = 0.5f * elr_len(elr_v(b.upper_x - b.lower_x, b.upper_y - b.lower_y, b.upper_z - b.lower_z));
    } else {
      s->world_center = elr_v(0, 0, 0); s->world_radius = 1.f;
    }
  }
  s->t_embree = elr_now() - t0;
  s->bytes_embree = elr__embree_bytes;
  return 0;
}

void elr_scene_release(elr_scene *s) {
  if (s->rtscene) rtcReleaseScene((RTCScene)s->rtscene);
  if (s->device) rtcReleaseDevice((RTCDevice)s->device);
  s->rtscene = s->device = NULL;
  free(s->geom_kind); free(s->geom_index); free(s->sph_builtin); free(s->sph_user);
  s->geom_kind = NULL; s->geom_index = NULL; s->sph_builtin = s->sph_user = NULL;
}

static void elr__rayhit_init(struct RTCRayHit *rh, elr_v3 o, elr_v3 d, float tmax) {
  rh->ray.org_x = o.x; rh->ray.org_y = o.y; rh->ray.org_z = o.z; rh->ray.tnear = 0.f;
  rh->ray.dir_x = d.x; rh->ray.dir_y = d.y; rh->ray.dir_z = d.z; rh->ray.time = 0.f;
  rh->ray.tfar = tmax; rh->ray.mask = ~0u; rh->ray.id = 0; rh->ray.flags = 0;
  rh->hit.geomID = RTC_INVALID_GEOMETRY_ID; rh->hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
}

void elr_raw_intersect(const elr_scene *s, elr_v3 o, elr_v3 d, float *t, unsigned *geom) {
  struct RTCRayHit rh;
  elr__rayhit_init(&rh, o, d, INFINITY);
#if RTC_VERSION_MAJOR >= 4
  rtcIntersect1((RTCScene)s->rtscene, &rh, NULL);
#else
  {
    struct RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    rtcIntersect1((RTCScene)s->rtscene, &ctx, &rh);
  }
#endif
  *t = rh.ray.tfar; *geom = rh.hit.geomID;
}

int elr_occluded(const elr_scene *s, elr_v3 o, elr_v3 d, float tmax) {
  struct RTCRay r;
  r.org_x = o.x; r.org_y = o.y; r.org_z = o.z; r.tnear = 0.f;
  r.dir_x = d.x; r.dir_y = d.y; r.dir_z = d.z; r.time = 0.f;
  r.tfar = tmax; r.mask = ~0u; r.id = 0; r.flags = 0;
#if RTC_VERSION_MAJOR >= 4
  rtcOccluded1((RTCScene)s->rtscene, &r, NULL);
#else
  {
    struct RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    rtcOccluded1((RTCScene)s->rtscene, &ctx, &r);
  }
#endif
  return r.tfar < 0.f;
}

int elr_intersect(const elr_scene *s, elr_v3 o, elr_v3 d, float tmax, elr_hit *h) {
  struct RTCRayHit rh;
  float pmax;
  elr__rayhit_init(&rh, o, d, tmax);
#if RTC_VERSION_MAJOR >= 4
  rtcIntersect1((RTCScene)s->rtscene, &rh, NULL);
#else
  {
    struct RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    rtcIntersect1((RTCScene)s->rtscene, &ctx, &rh);
  }
#endif
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return 0;
  h->t = rh.ray.tfar;
  h->prim = rh.hit.primID;
  h->has_uv = 0;
  if (rh.hit.geomID == s->sphere_geom || rh.hit.geomID == s->builtin_geom) {
    /* <<Refine sphere intersection point>>: project onto the sphere in object space */
    int si = rh.hit.geomID == s->sphere_geom ? s->sph_user[rh.hit.primID] : s->sph_builtin[rh.hit.primID];
    const elr_sphere *sp = &s->sph[si];
    elr_v3 pw = elr_add(o, elr_mul(d, h->t));
    const double(*mi)[4] = sp->o2w.inv;
    double x = mi[0][0] * pw.x + mi[0][1] * pw.y + mi[0][2] * pw.z + mi[0][3];
    double y = mi[1][0] * pw.x + mi[1][1] * pw.y + mi[1][2] * pw.z + mi[1][3];
    double z = mi[2][0] * pw.x + mi[2][1] * pw.y + mi[2][2] * pw.z + mi[2][3];
    double r = sp->radius, l = sqrt(x * x + y * y + z * z);
    elr_v3 pob;
    if (l > 0) { x *= r / l; y *= r / l; z *= r / l; }
    pob = elr_v((float)x, (float)y, (float)z);
    h->kind = 1;
    h->prim = (unsigned)si;
    h->pobj = pob;
    h->p = elr_xpoint(&sp->o2w, pob);
    h->ng = elr_norm(elr_xnormal(&sp->o2w, pob));
    h->ns = h->ng;
    h->material = sp->material;
  } else {
    const elr_mesh *m = &s->mesh[s->geom_index[rh.hit.geomID]];
    unsigned tri = rh.hit.primID;
    unsigned i0 = m->idx[3 * tri], i1 = m->idx[3 * tri + 1], i2 = m->idx[3 * tri + 2];
    float b1 = rh.hit.u, b2 = rh.hit.v, b0 = 1.f - b1 - b2;
    elr_v3 p0 = elr_v(m->p[3 * i0], m->p[3 * i0 + 1], m->p[3 * i0 + 2]);
    elr_v3 p1 = elr_v(m->p[3 * i1], m->p[3 * i1 + 1], m->p[3 * i1 + 2]);
    elr_v3 p2 = elr_v(m->p[3 * i2], m->p[3 * i2 + 1], m->p[3 * i2 + 2]);
    h->kind = 0;
    h->mesh = s->geom_index[rh.hit.geomID];
    h->b1 = b1; h->b2 = b2;
    h->p = elr_add(elr_add(elr_mul(p0, b0), elr_mul(p1, b1)), elr_mul(p2, b2));
    h->ng = elr_norm(elr_cross(elr_sub(p0, p2), elr_sub(p1, p2)));
    if (m->n) {
      elr_v3 n0 = elr_v(m->n[3 * i0], m->n[3 * i0 + 1], m->n[3 * i0 + 2]);
      elr_v3 n1 = elr_v(m->n[3 * i1], m->n[3 * i1 + 1], m->n[3 * i1 + 2]);
      elr_v3 n2 = elr_v(m->n[3 * i2], m->n[3 * i2 + 1], m->n[3 * i2 + 2]);
      elr_v3 ns = elr_add(elr_add(elr_mul(n0, b0), elr_mul(n1, b1)), elr_mul(n2, b2));
      ns = elr_len(ns) > 0 ? elr_norm(ns) : h->ng;
      if (elr_dot(ns, h->ng) < 0) h->ng = elr_mul(h->ng, -1.f); /* pbrt: ng on the side of ns */
      h->ns = ns;
    } else {
      h->ns = h->ng;
    }
    h->material = m->material;
  }
  pmax = fabsf(h->p.x); if (fabsf(h->p.y) > pmax) pmax = fabsf(h->p.y); if (fabsf(h->p.z) > pmax) pmax = fabsf(h->p.z);
  h->eps = 2e-5f * (1.f + pmax);
  return 1;
}

/* Texture coordinates and the partial derivatives of p and n, only for textured materials and ray
 * differentials: pbrt-v3's Sphere::Intersect and Triangle::Intersect parameterisations. */
void elr_hit_uv(const elr_scene *s, elr_hit *h) {
  if (h->has_uv) return;
  h->has_uv = 1;
  if (h->kind == 1) {
    const elr_sphere *sp = &s->sph[h->prim];
    double x = h->pobj.x, y = h->pobj.y, z = h->pobj.z, r = sp->radius, phi, theta, zr, cphi, sphi;
    const double PI = 3.14159265358979323846;
    elr_v3 dpdu, dpdv;
    if (x == 0 && y == 0) x = 1e-5 * r;
    phi = atan2(y, x); if (phi < 0) phi += 2 * PI;
    theta = acos(z / r < -1 ? -1 : (z / r > 1 ? 1 : z / r));
    h->u = (float)(phi / (2 * PI));
    h->v = (float)(1.0 - theta / PI); /* (theta - thetaZMin) / (thetaZMax - thetaZMin), thetaZMin = pi */
    zr = sqrt(x * x + y * y);
    cphi = x / zr; sphi = y / zr;
    dpdu = elr_v((float)(-2 * PI * y), (float)(2 * PI * x), 0.f);
    dpdv = elr_mul(elr_v((float)(z * cphi), (float)(z * sphi), (float)(-r * sin(theta))), (float)(-PI));
    h->dpdu = elr_xvector(&sp->o2w, dpdu);
    h->dpdv = elr_xvector(&sp->o2w, dpdv);
    /* Weingarten: for a sphere n = p / r, so dn/du = (dp/du) / r in object space */
    h->dndu = elr_xnormal(&sp->o2w, elr_mul(dpdu, (float)(1.0 / r)));
    h->dndv = elr_xnormal(&sp->o2w, elr_mul(dpdv, (float)(1.0 / r)));
  } else {
    const elr_mesh *m = &s->mesh[h->mesh];
    unsigned tri = h->prim;
    unsigned i0 = m->idx[3 * tri], i1 = m->idx[3 * tri + 1], i2 = m->idx[3 * tri + 2];
    float b1 = h->b1, b2 = h->b2, b0 = 1.f - b1 - b2;
    elr_v3 p0 = elr_v(m->p[3 * i0], m->p[3 * i0 + 1], m->p[3 * i0 + 2]);
    elr_v3 p1 = elr_v(m->p[3 * i1], m->p[3 * i1 + 1], m->p[3 * i1 + 2]);
    elr_v3 p2 = elr_v(m->p[3 * i2], m->p[3 * i2 + 1], m->p[3 * i2 + 2]);
    float uv0[2] = {0, 0}, uv1[2] = {1, 0}, uv2[2] = {1, 1}; /* pbrt-v3's default uv */
    elr_v3 dp02, dp12;
    float du02, dv02, du12, dv12, det;
    if (m->uv) {
      uv0[0] = m->uv[2 * i0]; uv0[1] = m->uv[2 * i0 + 1];
      uv1[0] = m->uv[2 * i1]; uv1[1] = m->uv[2 * i1 + 1];
      uv2[0] = m->uv[2 * i2]; uv2[1] = m->uv[2 * i2 + 1];
    }
    h->u = b0 * uv0[0] + b1 * uv1[0] + b2 * uv2[0];
    h->v = b0 * uv0[1] + b1 * uv1[1] + b2 * uv2[1];
    /* <<Compute triangle partial derivatives>> */
    dp02 = elr_sub(p0, p2); dp12 = elr_sub(p1, p2);
    du02 = uv0[0] - uv2[0]; dv02 = uv0[1] - uv2[1]; du12 = uv1[0] - uv2[0]; dv12 = uv1[1] - uv2[1];
    det = du02 * dv12 - dv02 * du12;
    if (fabsf(det) < 1e-12f) {
      elr_onb(h->ng, &h->dpdu, &h->dpdv);
    } else {
      float inv = 1.f / det;
      h->dpdu = elr_mul(elr_sub(elr_mul(dp02, dv12), elr_mul(dp12, dv02)), inv);
      h->dpdv = elr_mul(elr_sub(elr_mul(dp12, du02), elr_mul(dp02, du12)), inv);
    }
    h->dndu = h->dndv = elr_v(0, 0, 0);
    if (m->n && fabsf(det) >= 1e-12f) {
      elr_v3 n0 = elr_v(m->n[3 * i0], m->n[3 * i0 + 1], m->n[3 * i0 + 2]);
      elr_v3 n1 = elr_v(m->n[3 * i1], m->n[3 * i1 + 1], m->n[3 * i1 + 2]);
      elr_v3 n2 = elr_v(m->n[3 * i2], m->n[3 * i2 + 1], m->n[3 * i2 + 2]);
      elr_v3 dn1 = elr_sub(n0, n2), dn2 = elr_sub(n1, n2);
      float inv = 1.f / det;
      h->dndu = elr_mul(elr_sub(elr_mul(dn1, dv12), elr_mul(dn2, dv02)), inv);
      h->dndv = elr_mul(elr_sub(elr_mul(dn2, du02), elr_mul(dn1, du12)), inv);
    }
  }
}

/* >> loading and freeing a scene (pbrt-v3 core/api.cpp: pbrtParseFile, then the scene made at WorldEnd) */
static void elr__dirname(const char *path, char *dir, size_t n) {
  const char *sl = strrchr(path, '/');
  if (!sl) snprintf(dir, n, ".");
  else if (sl == path) snprintf(dir, n, "/");
  else snprintf(dir, n, "%.*s", (int)(sl - path), path);
}
int elr_scene_load_string(const char *text, const char *name, const char *base_dir, elr_scene **out, int quiet, char *err,
                          size_t errlen) {
  elr_scene *s = (elr_scene *)calloc(1, sizeof *s);
  double t0 = elr_now();
  *out = NULL;
  if (!s) { snprintf(err, errlen, "out of memory"); return -1; }
  s->quiet = quiet;
  if (elr_parse(s, text, strlen(text), name, base_dir, err, errlen) != 0) { elr_scene_free(s); return -1; }
  s->t_parse = elr_now() - t0;
  if (elr_scene_build(s, err, errlen) != 0) { elr_scene_free(s); return -1; }
  *out = s;
  return 0;
}
int elr_scene_load(const char *path, elr_scene **out, int quiet, char *err, size_t errlen) {
  FILE *f;
  long n;
  char *buf, dir[4096], why[128];
  int r;
  *out = NULL;
  if (el_file_is_regular(path, why, sizeof why) != 0) { snprintf(err, errlen, "%s: cannot read the scene file: %s", path, why); return -1; }
  f = fopen(path, "rb");
  if (!f) { snprintf(err, errlen, "%s: cannot open the scene file", path); return -1; }
  if (fseek(f, 0, SEEK_END) != 0 || (n = ftell(f)) < 0 || fseek(f, 0, SEEK_SET) != 0 || n > (1L << 30)) {
    fclose(f); snprintf(err, errlen, "%s: cannot read the scene file", path); return -1;
  }
  buf = (char *)malloc((size_t)n + 1);
  if (!buf || (n > 0 && fread(buf, 1, (size_t)n, f) != (size_t)n)) { fclose(f); free(buf); snprintf(err, errlen, "%s: cannot read the scene file", path); return -1; }
  fclose(f);
  buf[n] = 0;
  if (strlen(buf) != (size_t)n) { free(buf); snprintf(err, errlen, "%s:1: error: the file contains a NUL byte (not a pbrt-v3 text file)", path); return -1; }
  elr__dirname(path, dir, sizeof dir);
  r = elr_scene_load_string(buf, path, dir, out, quiet, err, errlen);
  free(buf);
  return r;
}
void elr_scene_free(elr_scene *s) {
  int i;
  if (!s) return;
  elr_scene_release(s);
  for (i = 0; i < s->ntex; i++) if (s->tex[i].mip) { el_mipmap_free(s->tex[i].mip); free(s->tex[i].mip); }
  for (i = 0; i < s->nmesh; i++) { free(s->mesh[i].idx); free(s->mesh[i].p); free(s->mesh[i].n); free(s->mesh[i].uv); }
  for (i = 0; i < s->nlight; i++) elr_light_free(&s->light[i]);
  free(s->tex); free(s->mat); free(s->mesh); free(s->sph); free(s->light); free(s->mat_textured);
  free(s);
}
int elr_scene_warnings(const elr_scene *s) { return s->warnings; }
const char *elr_scene_last_warning(const elr_scene *s) { return s->last_warning; }
const char *elr_scene_film_filename(const elr_scene *s) { return s->d.filename; }
void elr_scene_resolution(const elr_scene *s, int *w, int *h) {
  int b[4];
  elr_film_bounds(&s->d, b);
  *w = b[2] - b[0]; *h = b[3] - b[1];
}
int elr_scene_spp(const elr_scene *s) { return s->d.spp; }
