/* sphere_simd.h: the sphere callbacks' intersection (shapes.c) for one vector width: included by
 * shapes.c once per width (scalar, SSE2, AVX), after defining
 *   ELR__SPH_NAME          the function's name          ELR__SPH_W   its lanes (1, 4, 8)
 *   ELR__SPH_TARGET        its __attribute__((target)) or nothing
 *   V, M                   the vector type and the type of a comparison's mask
 *   LOAD(p) SET1(x) ADD SUB MUL DIV SQRT MIN MAX   the operations (MIN, MAX: _mm_min_ps's, the
 *                          second operand where either is NaN)
 *   LT GT GE (V, V -> M)  AND OR (M, M -> M)  SEL(m, a, b) (a where m, else b)  BITS(m) (lane i -> bit i)
 *   VALID(p)               the bits of the lanes whose Embree valid[] is -1
 * Every width does the same IEEE operations in the same order, so every width gives the same t (the
 * one-ray loop and the wave loop's packets make the same image; test_render_sphere_float checks it).
 *
 * pbrt-v4's Sphere::BasicIntersect in float without its intervals: the ray in object space, the
 * discriminant as a r^2 - |o x d|^2 (a |l|^2 = |o x d|^2 for l the point of the line nearest the
 * centre: Ray Tracing Gems ch. 7's r^2 - |l|^2 times a, which keeps its digits where b^2 - a c
 * cancels, a small sphere far away, and needs no division), the roots q / a and c / q with
 * q = -(b + sign(b) sqrt(disc)).
 * ray points to the first of the W lanes in Embree's RTCRayN layout of N rays (component k of lane j
 * at ray[k N + j]: org_x 0 .. dir_z 6, tnear 3, tfar 8), valid to their Embree valid[]. Returns the bits of the valid lanes that hit, t[lane] their nearest root in (tnear,
 * tfar); *redo gets the bits of the valid lanes float cannot answer (shapes.c solves them in double):
 * the discriminant within ELR__SPH_REDO a r^2 of 0, the origin farther than sqrt(ELR__SPH_FAR) radii,
 * or |o|^2 - r^2 within ELR__SPH_NEAR |o|^2 of 0 (the origin that near the surface: c's sign). */
ELR__SPH_TARGET static int ELR__SPH_NAME(const elr_sphere *sp, const float *ray, size_t N, const int *valid, float *t, int *redo) {
  const float *m = sp->w2o;
  V ox = SUB(LOAD(ray), SET1(sp->wc[0])), oy = SUB(LOAD(ray + N), SET1(sp->wc[1])), oz = SUB(LOAD(ray + 2 * N), SET1(sp->wc[2]));
  V dx = LOAD(ray + 4 * N), dy = LOAD(ray + 5 * N), dz = LOAD(ray + 6 * N);
  V tnear = LOAD(ray + 3 * N), tfar = LOAD(ray + 8 * N), r2 = SET1(sp->r2), zero = SET1(0.f);
  V o[3], d[3], a, b, ox2, c, l, l2, ar2, disc, q, t0, t1, lo, hi;
  M in_lo, in_hi;
  int k, v = VALID(valid);
  for (k = 0; k < 3; k++) { /* object space: o - wc by o2w.inv's 3x3, plus wc's place there (w2o) */
    const float *row = m + 4 * k;
    d[k] = ADD(ADD(MUL(SET1(row[0]), dx), MUL(SET1(row[1]), dy)), MUL(SET1(row[2]), dz));
    o[k] = ADD(ADD(ADD(MUL(SET1(row[0]), ox), MUL(SET1(row[1]), oy)), MUL(SET1(row[2]), oz)), SET1(row[3]));
  }
  /* a t^2 + 2 b t + c = 0 */
  a = ADD(ADD(MUL(d[0], d[0]), MUL(d[1], d[1])), MUL(d[2], d[2]));
  b = ADD(ADD(MUL(o[0], d[0]), MUL(o[1], d[1])), MUL(o[2], d[2]));
  ox2 = ADD(ADD(MUL(o[0], o[0]), MUL(o[1], o[1])), MUL(o[2], o[2]));
  c = SUB(ox2, r2);
  /* disc = b^2 - a c = a r^2 - |o x d|^2 (Lagrange's identity: no b^2 - a c to cancel, no division) */
  l = SUB(MUL(o[1], d[2]), MUL(o[2], d[1])); l2 = MUL(l, l);
  l = SUB(MUL(o[2], d[0]), MUL(o[0], d[2])); l2 = ADD(l2, MUL(l, l));
  l = SUB(MUL(o[0], d[1]), MUL(o[1], d[0])); l2 = ADD(l2, MUL(l, l));
  ar2 = MUL(a, r2);
  disc = SUB(ar2, l2);
  /* q = -(b + sign(b) sqrt(disc)); the roots q / a and c / q */
  q = SQRT(MAX(disc, zero));
  q = SEL(LT(b, zero), SUB(q, b), SUB(SUB(zero, b), q));
  t0 = DIV(q, a); t1 = DIV(c, q);
  lo = MIN(t0, t1); hi = MAX(t0, t1); /* (NaN where q = 0: disc = 0, a lane redone in double) */
  in_lo = AND(GT(lo, tnear), LT(lo, tfar));
  in_hi = AND(GT(hi, tnear), LT(hi, tfar));
  lo = SEL(in_lo, lo, hi);
  memcpy(t, &lo, sizeof lo);
  *redo = v & BITS(OR(AND(LT(disc, MUL(ar2, SET1(ELR__SPH_REDO))), GT(disc, MUL(ar2, SET1(-ELR__SPH_REDO)))),
                      OR(GT(c, MUL(r2, SET1(ELR__SPH_FAR))), AND(LT(c, MUL(ox2, SET1(ELR__SPH_NEAR))), GT(c, MUL(ox2, SET1(-ELR__SPH_NEAR)))))));
  return v & BITS(AND(GE(disc, zero), OR(in_lo, in_hi)));
}
#undef ELR__SPH_NAME
#undef ELR__SPH_W
#undef ELR__SPH_TARGET
#undef V
#undef M
#undef LOAD
#undef SET1
#undef ADD
#undef SUB
#undef MUL
#undef DIV
#undef SQRT
#undef MIN
#undef MAX
#undef LT
#undef GT
#undef GE
#undef AND
#undef OR
#undef SEL
#undef BITS
#undef VALID
