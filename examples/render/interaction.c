/* interaction.c: what a ray's hit needs before shading (pbrt-v3 core/interaction.cpp).
 *
 * The hit record itself (elr_hit: point, normals, the shape's parameterisation) is made by
 * elr_intersect and elr_hit_uv (scene.c); here the screen-space footprint of the hit that the textures
 * filter over (ray differentials from the camera, and from specular reflection in directlighting),
 * and the radiance a hit on an area light emits (pbrt-v3's SurfaceInteraction::Le). */
#include "elr_internal.h"

/* pbrt-v3's SurfaceInteraction::Le(w): the hit shape's area light, DiffuseAreaLight::L(*this, w): its
 * radiance towards w on the side its normal points to, or on both sides when twosided */
elr_v3 elr_hit_le(const elr_scene *s, const elr_hit *h, elr_v3 w) {
  if (h->light < 0) return elr_v(0, 0, 0);
  return elr_area_light_L(&s->light[h->light], h->ng, w);
}

/* pbrt-v3's SurfaceInteraction::ComputeDifferentials: where the ray's two differential rays meet the
 * hit's tangent plane, dp/dx and dp/dy, and from them the texture footprint du/dx, dv/dx, du/dy, dv/dy
 * (all zero without differentials). Also the hit's (u, v), which only textures read: when no material
 * is textured, none of it is computed. */
void elr_compute_differentials(const elr_scene *s, const elr_ray *r, elr_hit *h, elr_tex_ctx *c, elr_v3 *dpdx, elr_v3 *dpdy) {
  c->u = c->v = 0.f;
  c->dudx = c->dudy = c->dvdx = c->dvdy = 0.f;
  *dpdx = *dpdy = elr_v(0, 0, 0);
  if (!s->any_textured) return; /* nothing reads uv or footprints: skip the parameterisation */
  elr_hit_uv(s, h);
  c->u = h->u; c->v = h->v;
  if (r->has_diff) {
    elr_v3 n = h->ng, px, py;
    float d = elr_dot(n, h->p), tx, ty, dnx = elr_dot(n, r->rxd), dny = elr_dot(n, r->ryd);
    float A[2][2], Bx[2], By[2], det;
    float pa[3], pxa[3], pya[3], dpu[3], dpv[3];
    int dim0, dim1;
    if (dnx == 0.f || dny == 0.f) return;
    tx = -(elr_dot(n, r->rxo) - d) / dnx; ty = -(elr_dot(n, r->ryo) - d) / dny;
    if (!isfinite(tx) || !isfinite(ty)) return;
    px = elr_add(r->rxo, elr_mul(r->rxd, tx)); py = elr_add(r->ryo, elr_mul(r->ryd, ty));
    *dpdx = elr_sub(px, h->p); *dpdy = elr_sub(py, h->p);
    if (fabsf(n.x) > fabsf(n.y) && fabsf(n.x) > fabsf(n.z)) { dim0 = 1; dim1 = 2; }
    else if (fabsf(n.y) > fabsf(n.z)) { dim0 = 0; dim1 = 2; }
    else { dim0 = 0; dim1 = 1; }
    pa[0] = h->p.x; pa[1] = h->p.y; pa[2] = h->p.z;
    pxa[0] = px.x; pxa[1] = px.y; pxa[2] = px.z; pya[0] = py.x; pya[1] = py.y; pya[2] = py.z;
    dpu[0] = h->dpdu.x; dpu[1] = h->dpdu.y; dpu[2] = h->dpdu.z; dpv[0] = h->dpdv.x; dpv[1] = h->dpdv.y; dpv[2] = h->dpdv.z;
    A[0][0] = dpu[dim0]; A[0][1] = dpv[dim0]; A[1][0] = dpu[dim1]; A[1][1] = dpv[dim1];
    Bx[0] = pxa[dim0] - pa[dim0]; Bx[1] = pxa[dim1] - pa[dim1];
    By[0] = pya[dim0] - pa[dim0]; By[1] = pya[dim1] - pa[dim1];
    det = A[0][0] * A[1][1] - A[0][1] * A[1][0];
    if (fabsf(det) < 1e-10f) return;
    c->dudx = (A[1][1] * Bx[0] - A[0][1] * Bx[1]) / det; c->dvdx = (A[0][0] * Bx[1] - A[1][0] * Bx[0]) / det;
    c->dudy = (A[1][1] * By[0] - A[0][1] * By[1]) / det; c->dvdy = (A[0][0] * By[1] - A[1][0] * By[0]) / det;
    if (!isfinite(c->dudx) || !isfinite(c->dvdx)) c->dudx = c->dvdx = 0.f;
    if (!isfinite(c->dudy) || !isfinite(c->dvdy)) c->dudy = c->dvdy = 0.f;
  }
}
