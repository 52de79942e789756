/* ply.c: the PLY reader of Shape "plymesh" (pbrt-v3 shapes/plymesh.cpp, which reads with rply):
 * ASCII and binary (little and big endian) files; vertex positions, normals and (u, v); faces as
 * triangles, polygons as fans. Malformed files (counts, indices, types, header lines) are errors
 * naming the file. */
#include "elr_internal.h"
#include "image_io.h"
#include <stdlib.h>
#include <string.h>

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
