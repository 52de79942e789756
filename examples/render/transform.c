/* transform.c: pbrt-v3's Transform (core/transform.cpp): a 4x4 matrix and its inverse, row-major,
 * applied to column vectors; points, vectors and normals (normals by the inverse transpose). The
 * parser keeps the current transformation matrix as one (pbrt-v3's CTM). */
#include "elr_internal.h"
#include <string.h>

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
elr_v3 elr_xpoint_inv(const elr_xform *t, elr_v3 p) {
  elr_xform inv;
  elr_xform_invert(&inv, t);
  return elr_xpoint(&inv, p);
}
