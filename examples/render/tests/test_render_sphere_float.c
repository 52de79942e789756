/* test_render_sphere_float: the sphere callbacks' float intersection (shapes.c's elr_sphere_hit_rays,
 * sphere_simd.h) and the hit record made from it (elr_sphere_hit), against this test's own quadratic
 * in long double, on 210000 random rays at seven spheres: a unit sphere, an ellipsoid (rotated,
 * non-uniformly scaled), a small sphere 200 units from the origin, a sphere of radius 999 (seen from
 * near its surface), a mirrored one, and two whose object-space radius is far from their world radius
 * (1e20 scaled by 1e-19, 1e-18 scaled by 1e18: the parser takes both, float's r^2 does not).
 *   1. Every vector width this CPU runs (plain C, SSE2, AVX) and a ray alone (N = 1, as rtcIntersect1
 *      calls it) give the same hits and bit for bit the same t as packets of 16 (the one-ray loop and
 *      the wave loop make the same image).
 *   2. Hit or miss as the reference says, except where the reference's own discriminant is within
 *      1e-9 of 0 (a tie no precision decides): a fifth of the rays graze, a tenth start within 1e-4
 *      radii of the surface (another shape touching it: the sign of |o|^2 - r^2 decides).
 *   3. t within 32 float ulps of the inputs' scale along the ray (the largest coordinate of the origin
 *      or of the sphere's box: the inputs are floats, and a float solve adds a few roundings of that
 *      size, up to 10 times more near grazing), printed per sphere as measured.
 *   4. The hit record's point (in world and in object space) within 1e-5 radii of the exact one and its
 *      normal within 1e-4 radians, each plus those 32 ulps (world points are floats).
 *   5. No acne: rays leaving the surface outwards from the renderer's offset origin (p + eps n, eps as
 *      scene.c's 2e-5 (1 + max |p|)), at angles down to 1e-4 of grazing, hit nothing; the same inwards
 *      hit the far side. */
#include "render_test_util.h"
#include "../../../tests/test_rng.h"
#include <float.h>

typedef struct { float o[3], d[3]; } ray_t;

/* the reference: the ray in the sphere's object space (o2w.inv, long double), its two roots; 0 when it misses.
 * *rdisc: the discriminant over a r^2 (how far from grazing) */
static int ref_roots(const elr_sphere *sp, const ray_t *r, long double *t0, long double *t1, long double *rdisc) {
  long double o[3], d[3], a = 0, b = 0, c = 0, disc, q, rr = (long double)sp->radius * sp->radius;
  int i;
  for (i = 0; i < 3; i++) {
    o[i] = (long double)sp->o2w.inv[i][0] * r->o[0] + (long double)sp->o2w.inv[i][1] * r->o[1] + (long double)sp->o2w.inv[i][2] * r->o[2] + sp->o2w.inv[i][3];
    d[i] = (long double)sp->o2w.inv[i][0] * r->d[0] + (long double)sp->o2w.inv[i][1] * r->d[1] + (long double)sp->o2w.inv[i][2] * r->d[2];
    a += d[i] * d[i]; b += o[i] * d[i]; c += o[i] * o[i];
  }
  c -= rr;
  disc = b * b - a * c;
  *rdisc = disc / (a * rr);
  if (disc < 0) return 0;
  q = -(b + (b < 0 ? -sqrtl(disc) : sqrtl(disc)));
  *t0 = q / a; *t1 = c / q;
  if (*t0 > *t1) { long double t = *t0; *t0 = *t1; *t1 = t; }
  return 1;
}
/* the nearest root in (0, inf), or -1 */
static long double ref_hit(const elr_sphere *sp, const ray_t *r, long double *rdisc) {
  long double t0, t1;
  if (!ref_roots(sp, r, &t0, &t1, rdisc)) return -1;
  return t0 > 0 ? t0 : t1 > 0 ? t1 : -1;
}
/* world point of object point p (o2w.m, long double) and the outward world normal there (inverse transpose) */
static void obj_to_world(const elr_sphere *sp, const long double p[3], long double pw[3], long double nw[3]) {
  int i;
  long double l = 0;
  for (i = 0; i < 3; i++) {
    pw[i] = (long double)sp->o2w.m[i][0] * p[0] + (long double)sp->o2w.m[i][1] * p[1] + (long double)sp->o2w.m[i][2] * p[2] + sp->o2w.m[i][3];
    nw[i] = (long double)sp->o2w.inv[0][i] * p[0] + (long double)sp->o2w.inv[1][i] * p[1] + (long double)sp->o2w.inv[2][i] * p[2];
    l += nw[i] * nw[i];
  }
  l = sqrtl(l);
  for (i = 0; i < 3; i++) nw[i] /= l;
}
static void unit(rng *g, long double v[3]) { /* uniform on the unit sphere */
  long double z = 1 - 2 * (long double)rng_f(g), phi = 6.283185307179586L * rng_f(g), s = sqrtl(1 - z * z);
  v[0] = s * cosl(phi); v[1] = s * sinl(phi); v[2] = z;
}
static void set_ray(ray_t *r, const long double o[3], const long double d[3]) {
  int i;
  for (i = 0; i < 3; i++) { r->o[i] = (float)o[i]; r->d[i] = (float)d[i]; }
}

/* rays i0 .. i0 + n - 1 of rays[] into Embree's RTCRayN layout of N = n lanes (tnear 0, tfar inf) */
static void pack(const ray_t *rays, int n, float *buf) {
  int i, k;
  for (i = 0; i < n; i++) {
    for (k = 0; k < 3; k++) { buf[k * n + i] = rays[i].o[k]; buf[(4 + k) * n + i] = rays[i].d[k]; }
    buf[3 * n + i] = 0.f; buf[7 * n + i] = 0.f; buf[8 * n + i] = INFINITY;
  }
}

int main(void) {
  static const char *scene =
      "WorldBegin\n"
      "AttributeBegin\n  Shape \"sphere\" \"float radius\" 1\nAttributeEnd\n"
      "AttributeBegin\n  Translate 3 -1 2\n  Rotate 30 1 1 0\n  Scale 1 0.6 1.5\n  Shape \"sphere\" \"float radius\" 0.8\nAttributeEnd\n"
      "AttributeBegin\n  Translate 200 80 -50\n  Shape \"sphere\" \"float radius\" 0.05\nAttributeEnd\n"
      "AttributeBegin\n  Translate 0 -1000 0\n  Shape \"sphere\" \"float radius\" 999\nAttributeEnd\n"
      "AttributeBegin\n  Translate -3 1 0\n  Rotate 70 0 0 1\n  Scale -2 2 2\n  Shape \"sphere\" \"float radius\" 0.5\nAttributeEnd\n"
      "AttributeBegin\n  Translate 5 5 5\n  Scale 1e-19 1e-19 1e-19\n  Shape \"sphere\" \"float radius\" 1e20\nAttributeEnd\n"
      "AttributeBegin\n  Translate -5 5 5\n  Scale 1e18 1e18 1e18\n  Shape \"sphere\" \"float radius\" 1e-18\nAttributeEnd\n"
      "WorldEnd\n";
  enum { NRAYS = 210000, NSPH = 7 };
  char err[1024];
  elr_scene *s;
  rng g = rng_make(21);
  int simd, w, i, k, si;
  long mism_width = 0, mism_ref = 0, ties = 0, hits = 0, acne = 0, out_rays = 0, in_rays = 0, in_missed = 0, redo_band = 0;
  double sdt[NSPH] = {0}, sdr[NSPH] = {0}, sdp[NSPH] = {0}, sdn[NSPH] = {0}, scale;
  long bad_t = 0, bad_p = 0;
  ray_t *rays = (ray_t *)malloc(sizeof(ray_t) * NRAYS);
  int *kind = (int *)malloc(sizeof(int) * NRAYS);
  rt_mkdir("test_render_sphere_float");
  s = rt_load("spheres.pbrt", scene, err, sizeof err);
  if (!s || s->nsph != NSPH || !rays || !kind) { printf("FAIL: loading the scene: %s\n", s ? "not 7 spheres" : err); return 1; }
  simd = elr_sphere_simd();
  printf("vector widths tested: plain C%s%s\n", simd >= 1 ? ", SSE2" : "", simd >= 2 ? ", AVX" : "");
  for (si = 0; si < NSPH; si++) {
    const elr_sphere *sp = &s->sph[si];
    int n0 = si * (NRAYS / NSPH), n = NRAYS / NSPH;
    /* the world radius (largest axis) and how far the centre is from the world's origin */
    double R = 0, cmax = fmax(fabs(sp->o2w.m[0][3]), fmax(fabs(sp->o2w.m[1][3]), fabs(sp->o2w.m[2][3])));
    for (k = 0; k < 3; k++) R = fmax(R, sp->radius * sqrt(sp->o2w.m[0][k] * sp->o2w.m[0][k] + sp->o2w.m[1][k] * sp->o2w.m[1][k] + sp->o2w.m[2][k] * sp->o2w.m[2][k]));
    /* the rays: 50% from 1.05 to 50 radii (object space) towards a point within 1.2 radii of the centre,
     * 20% grazing (aimed within 1e-3 radii of the silhouette), 10% from within 1e-4 radii of the surface
     * in any direction, 20% leaving the surface (half inwards) */
    for (i = n0; i < n0 + n; i++) {
      long double o[3], d[3], u[3], v[3], dist, len = 0, r = sp->radius, pw[3], nw[3], p[3], tw[3], pmax = 0;
      int c = i % 10;
      if (c < 7) { /* from outside, in object space, then to world */
        unit(&g, u);
        dist = r * expl(logl(1.05L) + (logl(50.0L) - logl(1.05L)) * rng_f(&g));
        if (si == 3) dist = r * (1.0005L + 0.02L * rng_f(&g)); /* the big sphere: seen from just above it */
        for (k = 0; k < 3; k++) o[k] = u[k] * dist;
        unit(&g, v);
        if (c < 5) { /* a point within 1.2 radii of the centre */
          long double s3 = 1.2L * r * cbrtl((long double)rng_f(&g));
          for (k = 0; k < 3; k++) tw[k] = v[k] * s3;
        } else { /* the silhouette seen from o: v made perpendicular to o, at the tangent distance +- 1e-3 r */
          long double dot = v[0] * u[0] + v[1] * u[1] + v[2] * u[2], vl = 0, h = r * r / dist, rad = sqrtl(r * r - h * h) * (1 + 2e-3L * ((long double)rng_f(&g) - 0.5L));
          for (k = 0; k < 3; k++) { v[k] -= dot * u[k]; vl += v[k] * v[k]; }
          for (k = 0; k < 3; k++) tw[k] = u[k] * h + v[k] / sqrtl(vl) * rad;
        }
        obj_to_world(sp, o, pw, nw);
        obj_to_world(sp, tw, p, nw);
        for (k = 0; k < 3; k++) { d[k] = p[k] - pw[k]; len += d[k] * d[k]; }
        for (k = 0; k < 3; k++) d[k] /= sqrtl(len);
        set_ray(&rays[i], pw, d);
        kind[i] = 0;
      } else if (c == 8) { /* from within 1e-8 .. 1e-4 radii of the surface (inside or out: another shape touching it), any direction */
        long double h = r * expl(logl(1e-8L) + (logl(1e-4L) - logl(1e-8L)) * rng_f(&g)) * (rng_f(&g) < 0.5f ? -1 : 1);
        unit(&g, u);
        for (k = 0; k < 3; k++) p[k] = u[k] * (r + h);
        obj_to_world(sp, p, pw, nw);
        unit(&g, d);
        set_ray(&rays[i], pw, d);
        kind[i] = 0;
      } else { /* from the surface, offset as elr_spawn_origin does, outwards or inwards */
        long double cs, t1[3], t2[3], sn, phi, eps;
        int in = c == 9;
        unit(&g, u);
        for (k = 0; k < 3; k++) p[k] = u[k] * r;
        obj_to_world(sp, p, pw, nw);
        for (k = 0; k < 3; k++) pmax = fmaxl(pmax, fabsl(pw[k]));
        eps = 2e-5L * (1 + pmax);
        /* a direction at cos cs from the normal (1e-4 .. 1, log-uniform) */
        cs = expl(logl(1e-4L) * rng_f(&g)); sn = sqrtl(1 - cs * cs); phi = 6.283185307179586L * rng_f(&g);
        unit(&g, v);
        { long double dot = v[0] * nw[0] + v[1] * nw[1] + v[2] * nw[2], l2 = 0;
          for (k = 0; k < 3; k++) { t1[k] = v[k] - dot * nw[k]; l2 += t1[k] * t1[k]; }
          for (k = 0; k < 3; k++) t1[k] /= sqrtl(l2);
          t2[0] = nw[1] * t1[2] - nw[2] * t1[1]; t2[1] = nw[2] * t1[0] - nw[0] * t1[2]; t2[2] = nw[0] * t1[1] - nw[1] * t1[0]; }
        for (k = 0; k < 3; k++) {
          d[k] = (in ? -cs : cs) * nw[k] + sn * (cosl(phi) * t1[k] + sinl(phi) * t2[k]);
          o[k] = pw[k] + (in ? -eps : eps) * nw[k];
        }
        set_ray(&rays[i], o, d);
        kind[i] = in ? 2 : 1;
      }
    }
    /* 1. the widths, and a ray alone, against packets of 16 with the widest */
    for (i = n0; i < n0 + n; i += 16) {
      int m = n0 + n - i < 16 ? n0 + n - i : 16, valid[16];
      float buf[9 * 16], t_ref[16], t_w[16], one[9];
      unsigned bits_ref, bits_w;
      for (k = 0; k < 16; k++) valid[k] = k < m ? -1 : 0;
      pack(rays + i, m, buf);
      bits_ref = elr_sphere_hit_rays(sp, simd, buf, (unsigned)m, 0, valid, t_ref);
      for (w = 0; w <= simd + 1; w++) { /* widths 0 .. simd, then each ray alone (N = 1) */
        if (w <= simd) bits_w = elr_sphere_hit_rays(sp, w, buf, (unsigned)m, 0, valid, t_w);
        else {
          bits_w = 0;
          for (k = 0; k < m; k++) {
            pack(rays + i + k, 1, one);
            if (elr_sphere_hit_rays(sp, simd, one, 1, 0, valid, t_w + k) & 1) bits_w |= 1u << k;
          }
        }
        if (bits_w != bits_ref) mism_width++;
        for (k = 0; k < m; k++)
          if ((bits_ref >> k & 1) && memcmp(&t_ref[k], &t_w[k], sizeof(float)) != 0) mism_width++;
      }
      /* 2.-5. against the reference */
      for (k = 0; k < m; k++) {
        const ray_t *r = &rays[i + k];
        long double rdisc, tr = ref_hit(sp, r, &rdisc);
        int hit = (int)(bits_ref >> k & 1);
        if (fabsl(rdisc) < 0.01L) redo_band++;
        if (kind[i + k] == 1) { out_rays++; acne += hit; continue; }
        if (kind[i + k] == 2) { in_rays++; if (!hit) { in_missed++; continue; } }
        if (fabsl(rdisc) < 1e-9L) { ties++; continue; }
        if (hit != (tr > 0)) { mism_ref++; continue; }
        if (!hit) continue;
        hits++;
        /* the float inputs' scale: the largest coordinate of the origin or of the sphere's box */
        scale = fmax(fmax(fabs(r->o[0]), fmax(fabs(r->o[1]), fabs(r->o[2]))), cmax + R);
        { /* t's error relative to t, and in ulps of that scale along the ray */
          long double dl = 0, dt;
          for (w = 0; w < 3; w++) { long double dw = r->d[w]; dl += dw * dw; }
          dt = fabsl(t_ref[k] - tr) * sqrtl(dl);
          sdt[si] = fmax(sdt[si], (double)(fabsl(t_ref[k] - tr) / tr));
          sdr[si] = fmax(sdr[si], (double)dt / (FLT_EPSILON * scale));
          bad_t += dt > 32 * FLT_EPSILON * scale;
        }
        { /* the hit record from the float t against the exact point and normal */
          elr_hit h;
          long double pe[3], po[3], pw[3], nw[3], dp = 0, dn = 0, l = 0;
          memset(&h, 0, sizeof h);
          h.t = t_ref[k];
          elr_sphere_hit(s, si, elr_v(r->o[0], r->o[1], r->o[2]), elr_v(r->d[0], r->d[1], r->d[2]), &h);
          for (w = 0; w < 3; w++) pe[w] = r->o[w] + tr * r->d[w];
          for (w = 0; w < 3; w++) { /* to object space, onto the sphere exactly (it is on it up to rounding), back */
            po[w] = (long double)sp->o2w.inv[w][0] * pe[0] + (long double)sp->o2w.inv[w][1] * pe[1] + (long double)sp->o2w.inv[w][2] * pe[2] + sp->o2w.inv[w][3];
            l += po[w] * po[w];
          }
          for (w = 0; w < 3; w++) po[w] *= sp->radius / sqrtl(l);
          obj_to_world(sp, po, pw, nw);
          if (sp->flip) for (w = 0; w < 3; w++) nw[w] = -nw[w];
          dp = sqrtl((h.p.x - pw[0]) * (h.p.x - pw[0]) + (h.p.y - pw[1]) * (h.p.y - pw[1]) + (h.p.z - pw[2]) * (h.p.z - pw[2]));
          dn = sqrtl((h.ng.x - nw[0]) * (h.ng.x - nw[0]) + (h.ng.y - nw[1]) * (h.ng.y - nw[1]) + (h.ng.z - nw[2]) * (h.ng.z - nw[2]));
          { /* the object-space point (elr_hit_uv's (u, v) come from it) */
            long double dx = h.pobj.x - po[0], dy = h.pobj.y - po[1], dz = h.pobj.z - po[2];
            dp = fmaxl(dp, sqrtl(dx * dx + dy * dy + dz * dz) * R / sp->radius);
          }
          sdp[si] = fmax(sdp[si], (double)(dp / R));
          sdn[si] = fmax(sdn[si], (double)dn);
          bad_p += dp > 1e-5 * R + 32 * FLT_EPSILON * scale || dn > 1e-4 + 32 * FLT_EPSILON * scale / R;
        }
      }
    }
    printf("  sphere %d (radius %g at %g from the origin): t error up to %.2g relative, %.1f float ulps of the scale; point %.2g radii, "
           "normal %.2g\n", si, R, cmax, sdt[si], sdr[si], sdp[si], sdn[si]);
  }
  { /* 6. rays from the centre (a camera or a light inside a sphere): every one hits, t as the reference's, every width */
    long centre_bad = 0, centre_n = 0;
    for (si = 0; si < NSPH; si++) {
      const elr_sphere *sp = &s->sph[si];
      long double zero[3] = {0, 0, 0}, pw[3], nw[3];
      obj_to_world(sp, zero, pw, nw);
      for (i = 0; i < 64; i += 16) {
        ray_t rr[16];
        float buf[9 * 16], t[16];
        int valid[16];
        unsigned bits;
        for (k = 0; k < 16; k++) { long double d[3]; unit(&g, d); set_ray(&rr[k], pw, d); valid[k] = -1; }
        pack(rr, 16, buf);
        for (w = 0; w <= simd; w++) {
          bits = elr_sphere_hit_rays(sp, w, buf, 16, 0, valid, t);
          for (k = 0; k < 16; k++) {
            long double rdisc, tr = ref_hit(sp, &rr[k], &rdisc);
            centre_n++;
            centre_bad += !(bits >> k & 1) || !(tr > 0) || fabsl(t[k] - tr) > 1e-5L * tr;
          }
        }
      }
    }
    rt_check(centre_bad == 0 && centre_n > 0, "rays from each sphere's centre hit it at the reference's t (within 1e-5): %ld of %ld not", centre_bad, centre_n);
  }
  rt_check(mism_width == 0, "every width (and a ray alone) gives the same hits and the same t bit for bit: %ld differences", mism_width);
  rt_check(mism_ref == 0 && hits > NRAYS / 4,
           "hit or miss as the long double reference: %ld disagreements in %d rays (%ld hits; %ld ties within 1e-9 of grazing left out; "
           "%ld rays within 1%% of grazing, solved in double)", mism_ref, NRAYS, hits, ties, redo_band);
  rt_check(bad_t == 0, "t within 32 float ulps of the inputs' scale (the largest coordinate of the origin or the sphere's box) along "
                       "the ray: %ld rays beyond (the double path: within 1 ulp)", bad_t);
  rt_check(bad_p == 0, "hit records: the point within 1e-5 radii of the exact one, the normal within 1e-4, each plus 32 ulps of the "
                       "scale: %ld rays beyond", bad_p);
  rt_check(acne == 0 && out_rays >= NRAYS / 10, "no acne: %ld of %ld rays leaving the surface outwards (down to 1e-4 of grazing) hit it", acne, out_rays);
  rt_check(in_missed == 0 && in_rays >= NRAYS / 10, "rays leaving the surface inwards find the far side: %ld of %ld missed", in_missed, in_rays);
  elr_scene_free(s);
  free(rays); free(kind);
  return rt_finish("test_render_sphere_float");
}
