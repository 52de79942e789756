/* shapes.c: pbrt-v3's Sphere (shapes/sphere.cpp) and Triangle (shapes/triangle.cpp) as the renderer
 * intersects them through Embree (scene.c).
 *
 * A sphere is pbrt-v3's Sphere in its object space (any affine object-to-world transform, so a
 * non-uniformly scaled sphere is an exact ellipsoid), intersected in double precision, never
 * tessellated: Embree's user geometry calls the bounds, intersect and occluded functions below. Triangle
 * meshes are Embree triangle geometries in world space (pbrt-v3 also transforms mesh vertices to world
 * space when it creates them). After Embree's hit, the hit record (elr_sphere_hit, elr_triangle_hit)
 * and, only for textured materials and ray differentials, the parameterisation (elr_hit_uv). Sampling
 * a point on a shape (pbrt-v3's Shape::Sample and Pdf, for area lights) and Shape "disk" would join
 * here; Loop subdivision (shapes/loopsubdiv.cpp) makes triangle meshes and would have a file of its own. */
#include "elr_internal.h"
#include <embree3/rtcore.h>
#include <float.h>

/* >> sphere */
/* Embree's user-geometry callbacks (scene.c attaches them, the scene as the user pointer; primID
 * indexes sph_user): the bounds of the transformed sphere, padded by a relative 1e-6 */
void elr_sphere_bounds(const struct RTCBoundsFunctionArguments *a) {
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

/* pbrt-v3's Sphere::Intersect: the ray taken to object space, the quadratic solved in double precision
 * (pbrt-v3 uses its EFloat error bounds); returns the nearest t in (tnear, tfar) or -1 */
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

/* one ray at a time (the renderer calls rtcIntersect1 / rtcOccluded1) */
void elr_sphere_intersect(const struct RTCIntersectFunctionNArguments *a) {
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
  rh->hit.Ng_x = 0; rh->hit.Ng_y = 0; rh->hit.Ng_z = 1; /* computed in elr_sphere_hit */
  rh->hit.primID = a->primID;
  rh->hit.geomID = a->geomID;
  rh->hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
}
void elr_sphere_occluded(const struct RTCOccludedFunctionNArguments *a) {
  const elr_scene *s = (const elr_scene *)a->geometryUserPtr;
  struct RTCRay *ray = (struct RTCRay *)a->ray;
  const elr_sphere *sp = &s->sph[s->sph_user[a->primID]];
  if (!a->valid[0]) return;
  if (elr__sph_hit(sp, ray->org_x, ray->org_y, ray->org_z, ray->dir_x, ray->dir_y, ray->dir_z, ray->tnear, ray->tfar) >= 0)
    ray->tfar = -INFINITY;
}

/* The hit record of a ray o + t d (t in h->t) on sphere si: <<Refine sphere intersection point>>
 * (projected onto the sphere in object space, as pbrt-v3 does), the normal. */
void elr_sphere_hit(const elr_scene *s, int si, elr_v3 o, elr_v3 d, elr_hit *h) {
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
}

/* >> triangle */
/* The hit record of triangle tri of mesh `mesh` at barycentrics (b1, b2) (pbrt-v3 Triangle::Intersect:
 * the interpolated point, the geometric normal, the shading normal interpolated from the mesh's
 * normals, with the geometric normal turned to its side). */
void elr_triangle_hit(const elr_scene *s, int mesh, unsigned tri, float b1, float b2, elr_hit *h) {
  const elr_mesh *m = &s->mesh[mesh];
  unsigned i0 = m->idx[3 * tri], i1 = m->idx[3 * tri + 1], i2 = m->idx[3 * tri + 2];
  float b0 = 1.f - b1 - b2;
  elr_v3 p0 = elr_v(m->p[3 * i0], m->p[3 * i0 + 1], m->p[3 * i0 + 2]);
  elr_v3 p1 = elr_v(m->p[3 * i1], m->p[3 * i1 + 1], m->p[3 * i1 + 2]);
  elr_v3 p2 = elr_v(m->p[3 * i2], m->p[3 * i2 + 1], m->p[3 * i2 + 2]);
  h->kind = 0;
  h->prim = tri;
  h->mesh = mesh;
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

/* >> parameterisations */
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
