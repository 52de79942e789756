/* scene.c: the scene: loading it (parse, then build) and freeing it, and the Embree scene that the
 * integrators trace rays in (pbrt-v3 core/scene.cpp and api.cpp's MakeScene; Embree replaces its
 * accelerators/). One Embree triangle geometry per mesh; the spheres as one user geometry of exact
 * object-space spheres (shapes.c), or Embree's own sphere primitive for similarity transforms with
 * ELR_EMBREE_SPHERES=1; the disks as another user geometry. ObjectInstance: each instanced prototype is
 * an Embree scene of its own, built once, and each instance an RTC_GEOMETRY_TYPE_INSTANCE of it with the
 * instance's transform. elr_intersect makes the hit record through shapes.c (in world space, also for
 * instances), elr_occluded answers shadow rays. The image textures and the infinite lights are made here
 * too, of the descriptions the parser leaves (elr_scene_make_textures, elr_scene_make_lights: their
 * images, MIP maps and envlight's tables). */
#define _POSIX_C_SOURCE 200809L
#include "elr_internal.h"
#include "image_io.h"
#include <embree3/rtcore.h>
#include <stdlib.h>
#include <string.h>

/* >> the Embree scene */
static size_t elr__embree_bytes; /* device memory monitor (one render at a time per process) */
static bool elr__memmon(void *ptr, ssize_t bytes, bool post) {
  (void)ptr; (void)post;
  if (bytes > 0) elr__embree_bytes += (size_t)bytes; else elr__embree_bytes -= (size_t)(-bytes);
  return true;
}

/* One Embree triangle geometry of mesh i in scene sc; its geometry id, or RTC_INVALID_GEOMETRY_ID */
static unsigned elr__attach_mesh(const elr_scene *s, RTCDevice dev, RTCScene sc, int i, char *err, size_t errlen) {
  const elr_mesh *m = &s->mesh[i];
  RTCGeometry g = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
  float *vb = (float *)rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), (size_t)m->nvert);
  unsigned *ib = (unsigned *)rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), (size_t)m->ntri);
  unsigned id;
  if (!vb || !ib) { rtcReleaseGeometry(g); snprintf(err, errlen, "Embree: out of memory for mesh %d", i); return RTC_INVALID_GEOMETRY_ID; }
  memcpy(vb, m->p, sizeof(float) * 3 * (size_t)m->nvert);
  memcpy(ib, m->idx, sizeof(unsigned) * 3 * (size_t)m->ntri);
  rtcCommitGeometry(g);
  id = rtcAttachGeometry(sc, g);
  rtcReleaseGeometry(g);
  return id;
}
/* The user geometry of the spheres set->idx[0 .. n) (shapes.c's callbacks, set as their data) */
static unsigned elr__attach_spheres(RTCDevice dev, RTCScene sc, elr_sphere_set *set, int n) {
  RTCGeometry g = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_USER);
  unsigned id;
  rtcSetGeometryUserPrimitiveCount(g, (unsigned)n);
  set->simd = elr_sphere_simd();
  rtcSetGeometryUserData(g, set);
  rtcSetGeometryBoundsFunction(g, elr_sphere_bounds, NULL);
  rtcSetGeometryIntersectFunction(g, elr_sphere_intersect);
  rtcSetGeometryOccludedFunction(g, elr_sphere_occluded);
  rtcCommitGeometry(g);
  id = rtcAttachGeometry(sc, g);
  rtcReleaseGeometry(g);
  return id;
}

/* An instanced prototype's Embree scene: its meshes and its spheres, in its own space (built once,
 * however many instances place it) */
static int elr__build_object(elr_scene *s, RTCDevice dev, int oi, char *err, size_t errlen) {
  elr_object *o = &s->obj[oi];
  RTCScene sc = rtcNewScene(dev);
  int i, n = 0;
  o->rtscene = sc;
  rtcSetSceneBuildQuality(sc, RTC_BUILD_QUALITY_HIGH);
  o->geom_mesh = (int *)calloc((size_t)o->nmesh + 2, sizeof(int));
  o->sph_user = (int *)calloc((size_t)o->nsph + 1, sizeof(int));
  if (!o->geom_mesh || !o->sph_user) { snprintf(err, errlen, "out of memory"); return -1; }
  o->sphere_geom = RTC_INVALID_GEOMETRY_ID;
  for (i = 0; i < s->nmesh; i++)
    if (s->mesh[i].object == oi) {
      unsigned id = elr__attach_mesh(s, dev, sc, i, err, errlen);
      if (id == RTC_INVALID_GEOMETRY_ID) return -1;
      o->geom_mesh[id] = i;
    }
  for (i = 0; i < s->nsph; i++) if (s->sph[i].object == oi) o->sph_user[n++] = i;
  if (n) {
    o->spheres.sph = s->sph; o->spheres.idx = o->sph_user;
    o->sphere_geom = elr__attach_spheres(dev, sc, &o->spheres, n);
    o->geom_mesh[o->sphere_geom] = -1;
  }
  rtcCommitScene(sc);
  return 0;
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
  s->ngeom = (unsigned)s->nmesh + 3u + (unsigned)s->ninst;
  s->geom_kind = (unsigned *)calloc(s->ngeom + 1, sizeof(unsigned));
  s->geom_index = (int *)calloc(s->ngeom + 1, sizeof(int));
  if (!s->geom_kind || !s->geom_index) { snprintf(err, errlen, "out of memory"); return -1; }
  s->sphere_geom = ~0u;
  s->disk_geom = ~0u;
  for (i = 0; i < s->nsph; i++) elr_sphere_prepare(&s->sph[i]); /* the callbacks' float copies */
  /* the world's meshes, one geometry each (a prototype's belong to its own scene, below) */
  for (i = 0; i < s->nmesh; i++) {
    unsigned id;
    if (s->mesh[i].object >= 0) continue;
    id = elr__attach_mesh(s, dev, sc, i, err, errlen);
    if (id == RTC_INVALID_GEOMETRY_ID) return -1;
    s->geom_kind[id] = 0; s->geom_index[id] = i;
  }
  /* Spheres are the user geometry above (pbrt-v3's Sphere in object space, in float several rays at a
   * time and in double where float is not enough, shapes.c: any affine transform, so a non-uniform
   * Scale gives an exact ellipsoid). With the environment variable
   * ELR_EMBREE_SPHERES set, spheres whose object-to-world transform is a similarity (rotation, uniform
   * scale, translation) use Embree's RTC_GEOMETRY_TYPE_SPHERE_POINT instead; on the benchmark scene that
   * was not faster (830 vs 734 instructions per rtcIntersect1 under callgrind, and lower measured rates),
   * so it is not the default. Both are refined the same way in elr_intersect. Measured again with the
   * wave loop's packets of 16 (issue 21; bench/callgrind_parts.py, bench_city, 16 spp, zsobol): Embree
   * and the sphere code take 1529 instructions per camera sample with Embree's spheres against 1087
   * with the callbacks, loop CPU 0.94-1.11x (median 1.03x) of the callbacks' in 5 interleaved runs;
   * the image differs in the sphere's pixels by at most 4.6e-5 relative (Embree's float t before the
   * projection onto the sphere); on 200000 random rays at the bench sphere the hit distances differ by
   * at most 1.4e-6 relative, the normals by 4.4e-6, and no ray hits one and misses the other. Exact
   * enough, but not faster: still not the default. Since the callbacks test 4 or 8 rays at once in
   * float (issue 21), Embree and intersection take 764 instructions per camera sample on bench_city
   * (direct, callgrind_parts.sh) against 1396 with ELR_EMBREE_SPHERES=1 on the same build. The scene's
   * build quality (LOW instead of HIGH) and RTC_SCENE_FLAG_DYNAMIC change nothing there (764: a sphere
   * and two triangles), RTC_SCENE_FLAG_COMPACT costs more (796): HIGH, no flags stay. */
  s->sph_builtin = (int *)calloc((size_t)s->nsph + 1, sizeof(int));
  if (!s->sph_builtin) { snprintf(err, errlen, "out of memory"); return -1; }
  s->builtin_geom = ~0u;
  {
    int nb = 0;
    for (i = 0; i < s->nsph; i++) {
      const double(*m)[4] = (const double(*)[4])s->sph[i].o2w.m;
      double g[3][3], sc;
      int a, b, k, sim = 1;
      if (s->sph[i].object >= 0) continue;
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
      if (s->sph[i].object >= 0) continue;
      for (k = 0; k < nb; k++) if (s->sph_builtin[k] == i) b = 1;
      if (!b) s->sph_user[s->nuser++] = i;
    }
  }
  if (s->nuser) {
    unsigned id;
    s->world_spheres.sph = s->sph; s->world_spheres.idx = s->sph_user;
    id = elr__attach_spheres(dev, sc, &s->world_spheres, s->nuser);
    s->geom_kind[id] = 1; s->geom_index[id] = 0;
    s->sphere_geom = id;
  }
  /* ObjectInstance: each prototype that is placed somewhere gets its scene once, each placement an
   * Embree instance of it with the instance-to-world transform */
  for (i = 0; i < s->nobj; i++)
    if (s->obj[i].ninstances > 0 && elr__build_object(s, dev, i, err, errlen) != 0) return -1;
  for (i = 0; i < s->ninst; i++) {
    const elr_instance *in = &s->inst[i];
    RTCGeometry g = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_INSTANCE);
    float xf[12];
    int r, c;
    unsigned id;
    for (r = 0; r < 3; r++) for (c = 0; c < 4; c++) xf[4 * r + c] = (float)in->xf.m[r][c];
    rtcSetGeometryInstancedScene(g, (RTCScene)s->obj[in->object].rtscene);
    rtcSetGeometryTransform(g, 0, RTC_FORMAT_FLOAT3X4_ROW_MAJOR, xf);
    rtcCommitGeometry(g);
    id = rtcAttachGeometry(sc, g);
    rtcReleaseGeometry(g);
    s->geom_kind[id] = 2; s->geom_index[id] = i;
  }
  if (s->ndisk) { /* pbrt-v3's disks, exact: shapes.c */
    RTCGeometry g = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_USER);
    unsigned id;
    rtcSetGeometryUserPrimitiveCount(g, (unsigned)s->ndisk);
    rtcSetGeometryUserData(g, s);
    rtcSetGeometryBoundsFunction(g, elr_disk_bounds, NULL);
    rtcSetGeometryIntersectFunction(g, elr_disk_intersect);
    rtcSetGeometryOccludedFunction(g, elr_disk_occluded);
    rtcCommitGeometry(g);
    id = rtcAttachGeometry(sc, g);
    rtcReleaseGeometry(g);
    s->geom_kind[id] = 3; s->geom_index[id] = 0;
    s->disk_geom = id;
  }
  rtcCommitScene(sc);
  if (rtcGetDeviceError(dev) != RTC_ERROR_NONE) { snprintf(err, errlen, "Embree: building the scene failed"); return -1; }
  {
    struct RTCBounds b;
    rtcGetSceneBounds(sc, &b);
    if (s->nmesh + s->nsph + s->ndisk > 0 && b.lower_x <= b.upper_x) {
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
  int i;
  if (s->rtscene) rtcReleaseScene((RTCScene)s->rtscene);
  for (i = 0; i < s->nobj; i++) {
    elr_object *o = &s->obj[i];
    if (o->rtscene) rtcReleaseScene((RTCScene)o->rtscene);
    free(o->geom_mesh); free(o->sph_user);
    o->rtscene = NULL; o->geom_mesh = NULL; o->sph_user = NULL;
  }
  if (s->device) rtcReleaseDevice((RTCDevice)s->device);
  s->rtscene = s->device = NULL;
  free(s->geom_kind); free(s->geom_index); free(s->sph_builtin); free(s->sph_user);
  s->geom_kind = NULL; s->geom_index = NULL; s->sph_builtin = s->sph_user = NULL;
}

static void elr__ray_init(struct RTCRay *r, elr_v3 o, elr_v3 d, float tmax) {
  r->org_x = o.x; r->org_y = o.y; r->org_z = o.z; r->tnear = 0.f;
  r->dir_x = d.x; r->dir_y = d.y; r->dir_z = d.z; r->time = 0.f;
  r->tfar = tmax; r->mask = ~0u; r->id = 0; r->flags = 0;
}
static void elr__rayhit_init(struct RTCRayHit *rh, elr_v3 o, elr_v3 d, float tmax) {
  elr__ray_init(&rh->ray, o, d, tmax);
  rh->hit.geomID = RTC_INVALID_GEOMETRY_ID; rh->hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
}
/* one ray through the scene's top level (rtcIntersect1 / rtcOccluded1), Embree 3's context or Embree 4's none */
static void elr__intersect1(const elr_scene *s, struct RTCRayHit *rh) {
#if RTC_VERSION_MAJOR >= 4
  rtcIntersect1((RTCScene)s->rtscene, rh, NULL);
#else
  struct RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  rtcIntersect1((RTCScene)s->rtscene, &ctx, rh);
#endif
}
static void elr__occluded1(const elr_scene *s, struct RTCRay *r) {
#if RTC_VERSION_MAJOR >= 4
  rtcOccluded1((RTCScene)s->rtscene, r, NULL);
#else
  struct RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  rtcOccluded1((RTCScene)s->rtscene, &ctx, r);
#endif
}

void elr_raw_intersect(const elr_scene *s, elr_v3 o, elr_v3 d, float *t, unsigned *geom) {
  struct RTCRayHit rh;
  elr__rayhit_init(&rh, o, d, INFINITY);
  elr__intersect1(s, &rh);
  *t = rh.ray.tfar; *geom = rh.hit.geomID;
}

int elr_occluded(const elr_scene *s, elr_v3 o, elr_v3 d, float tmax) {
  struct RTCRay r;
  elr__ray_init(&r, o, d, tmax);
  elr__occluded1(s, &r);
  return r.tfar < 0.f;
}

/* A hit on the prototype of instance ii (geometry geom of its scene): the hit record made in the
 * prototype's space (the ray taken there by the inverse transform; t is the same in both spaces), then
 * taken to world space (pbrt-v3's TransformedPrimitive::Intersect: the point, the normals by the inverse
 * transpose, the shading normal turned to the geometric normal's side) */
static ELR_NOINLINE void elr__instance_hit(const elr_scene *s, int ii, unsigned geom, unsigned prim, float b1, float b2, elr_v3 o, elr_v3 d, elr_hit *h) {
  const elr_instance *in = &s->inst[ii];
  const elr_object *ob = &s->obj[in->object];
  if (geom == ob->sphere_geom) {
    elr_sphere_hit(s, ob->sph_user[prim], elr_xpoint_inv(&in->xf, o), elr_xvector_inv(&in->xf, d), h);
  } else {
    elr_triangle_hit(s, ob->geom_mesh[geom], prim, b1, b2, h);
  }
  h->inst = ii;
  h->p = elr_xpoint(&in->xf, h->p);
  h->ng = elr_norm(elr_xnormal(&in->xf, h->ng));
  h->ns = elr_norm(elr_xnormal(&in->xf, h->ns));
  if (elr_dot(h->ns, h->ng) < 0.f) h->ns = elr_mul(h->ns, -1.f);
}

/* The hit record of ray o + t d from Embree's answer (geometry, instance, primitive, barycentrics, t):
 * each shape's hit record (shapes.c), in world space also for an instance's shape. */
static void elr__hit_record(const elr_scene *s, elr_v3 o, elr_v3 d, unsigned geom, unsigned inst, unsigned prim, float u, float v, float t,
                            elr_hit *h) {
  float pmax;
  h->t = t;
  h->prim = prim;
  h->has_uv = 0;
  h->inst = -1;
  if (inst != RTC_INVALID_GEOMETRY_ID)
    elr__instance_hit(s, s->geom_index[inst], geom, prim, u, v, o, d, h);
  else if (geom == s->sphere_geom || geom == s->builtin_geom)
    elr_sphere_hit(s, geom == s->sphere_geom ? s->sph_user[prim] : s->sph_builtin[prim], o, d, h);
  else if (geom == s->disk_geom)
    elr_disk_hit(s, (int)prim, o, d, h);
  else
    elr_triangle_hit(s, s->geom_index[geom], prim, u, v, h);
  pmax = fabsf(h->p.x); if (fabsf(h->p.y) > pmax) pmax = fabsf(h->p.y); if (fabsf(h->p.z) > pmax) pmax = fabsf(h->p.z);
  h->eps = 2e-5f * (1.f + pmax);
}

int elr_intersect(const elr_scene *s, elr_v3 o, elr_v3 d, float tmax, elr_hit *h) {
  struct RTCRayHit rh;
  elr__rayhit_init(&rh, o, d, tmax);
  elr__intersect1(s, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return 0;
  elr__hit_record(s, o, d, rh.hit.geomID, rh.hit.instID[0], rh.hit.primID, rh.hit.u, rh.hit.v, rh.ray.tfar, h);
  return 1;
}

/* >> a wave of rays (render_wave.c): one Embree call for many rays. ELR_WAVE_API_SINGLE traces them one
 * by one (rtcIntersect1, rtcOccluded1), PACKET16 in packets of 16 (rtcIntersect16, rtcOccluded16; the
 * last one masked), STREAM as one stream of rays (rtcIntersect1M, rtcOccluded1M), SOA as one stream in
 * the wave's own arrays (rtcIntersectNp, rtcOccludedNp). coherent: the rays start near each other and
 * point alike (camera rays), which lets Embree's streams trace them as packets. */
#if RTC_VERSION_MAJOR < 4
static void elr__wave_context(struct RTCIntersectContext *ctx, int coherent) {
  rtcInitIntersectContext(ctx);
  ctx->flags = coherent ? RTC_INTERSECT_CONTEXT_FLAG_COHERENT : RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
}
static void elr__wave_np(elr_wave_rays *w, struct RTCRayHitNp *np) {
  np->ray.org_x = w->ox; np->ray.org_y = w->oy; np->ray.org_z = w->oz; np->ray.tnear = w->tnear;
  np->ray.dir_x = w->dx; np->ray.dir_y = w->dy; np->ray.dir_z = w->dz; np->ray.time = w->time;
  np->ray.tfar = w->tfar; np->ray.mask = w->mask; np->ray.id = w->id; np->ray.flags = w->flags;
  np->hit.Ng_x = w->ngx; np->hit.Ng_y = w->ngy; np->hit.Ng_z = w->ngz; np->hit.u = w->u; np->hit.v = w->v;
  np->hit.primID = w->prim; np->hit.geomID = w->geom; np->hit.instID[0] = w->inst;
}
#endif

/* the packet of rays i .. i + 15 of the wave, and its mask: the last packet's unused lanes hold a copy
 * of its first ray, masked off (Embree wants the packet and its mask 64-byte aligned) */
static void elr__wave_ray16(const elr_wave_rays *w, int i, struct RTCRay16 *r, int valid[16]) {
  int k;
  if (i + 16 <= w->n) { /* a full packet: each component a copy of 16 (elr_wave_rays_init wrote tnear, time 0, mask ~0, flags 0) */
    static const unsigned lane[16] = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15};
    for (k = 0; k < 16; k++) valid[k] = -1;
    memcpy(r->org_x, w->ox + i, sizeof r->org_x); memcpy(r->org_y, w->oy + i, sizeof r->org_y); memcpy(r->org_z, w->oz + i, sizeof r->org_z);
    memcpy(r->tnear, w->tnear + i, sizeof r->tnear); memcpy(r->dir_x, w->dx + i, sizeof r->dir_x); memcpy(r->dir_y, w->dy + i, sizeof r->dir_y);
    memcpy(r->dir_z, w->dz + i, sizeof r->dir_z); memcpy(r->time, w->time + i, sizeof r->time); memcpy(r->tfar, w->tfar + i, sizeof r->tfar);
    memcpy(r->mask, w->mask + i, sizeof r->mask); memcpy(r->id, lane, sizeof r->id); memcpy(r->flags, w->flags + i, sizeof r->flags);
    return;
  }
  for (k = 0; k < 16; k++) {
    int j = i + k < w->n ? i + k : i;
    valid[k] = i + k < w->n ? -1 : 0;
    r->org_x[k] = w->ox[j]; r->org_y[k] = w->oy[j]; r->org_z[k] = w->oz[j]; r->tnear[k] = 0.f;
    r->dir_x[k] = w->dx[j]; r->dir_y[k] = w->dy[j]; r->dir_z[k] = w->dz[j]; r->time[k] = 0.f;
    r->tfar[k] = w->tfar[j]; r->mask[k] = ~0u; r->id[k] = (unsigned)k; r->flags[k] = 0;
  }
}

typedef char elr__wave_add_miss_id[RTC_INVALID_GEOMETRY_ID == ~0u ? 1 : -1]; /* (elr_wave_add's ~0u is Embree's miss) */
void elr_wave_rays_init(elr_wave_rays *w) {
  int i;
  for (i = 0; i < ELR_WAVE_RAYS; i++) { w->tnear[i] = 0.f; w->time[i] = 0.f; w->mask[i] = ~0u; w->id[i] = (unsigned)i; w->flags[i] = 0; }
}

void elr_wave_intersect(const elr_scene *s, elr_wave_rays *w, int api, int coherent) {
  RTCScene sc = (RTCScene)s->rtscene;
  int i, k;
#if RTC_VERSION_MAJOR < 4
  struct RTCIntersectContext ctx;
  elr__wave_context(&ctx, coherent);
#endif
  if (api == ELR_WAVE_API_SOA) {
#if RTC_VERSION_MAJOR < 4
    struct RTCRayHitNp np;
    elr__wave_np(w, &np);
    rtcIntersectNp(sc, &ctx, &np, (unsigned)w->n);
    return;
#else
    api = ELR_WAVE_API_STREAM;
#endif
  }
  if (api == ELR_WAVE_API_PACKET16) {
    for (i = 0; i < w->n; i += 16) {
      RTC_ALIGN(64) struct RTCRayHit16 rh;
      RTC_ALIGN(64) int valid[16];
      elr__wave_ray16(w, i, &rh.ray, valid);
      for (k = 0; k < 16; k++) { rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID; rh.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID; }
#if RTC_VERSION_MAJOR >= 4
      rtcIntersect16(valid, sc, &rh, NULL);
#else
      rtcIntersect16(valid, sc, &ctx, &rh);
#endif
      if (i + 16 <= w->n) {
        memcpy(w->tfar + i, rh.ray.tfar, sizeof rh.ray.tfar); memcpy(w->geom + i, rh.hit.geomID, sizeof rh.hit.geomID);
        memcpy(w->inst + i, rh.hit.instID[0], sizeof rh.hit.instID[0]); memcpy(w->prim + i, rh.hit.primID, sizeof rh.hit.primID);
        memcpy(w->u + i, rh.hit.u, sizeof rh.hit.u); memcpy(w->v + i, rh.hit.v, sizeof rh.hit.v);
      } else
        for (k = 0; k < 16 && i + k < w->n; k++) {
          w->tfar[i + k] = rh.ray.tfar[k]; w->geom[i + k] = rh.hit.geomID[k]; w->inst[i + k] = rh.hit.instID[0][k];
          w->prim[i + k] = rh.hit.primID[k]; w->u[i + k] = rh.hit.u[k]; w->v[i + k] = rh.hit.v[k];
        }
    }
    return;
  }
  for (i = 0; i < w->n; i += ELR_WAVE_CHUNK) { /* one by one, or streams of up to ELR_WAVE_CHUNK rays */
    struct RTCRayHit rh[ELR_WAVE_CHUNK];
    int m = w->n - i < ELR_WAVE_CHUNK ? w->n - i : ELR_WAVE_CHUNK;
    for (k = 0; k < m; k++) elr__rayhit_init(&rh[k], elr_v(w->ox[i + k], w->oy[i + k], w->oz[i + k]), elr_v(w->dx[i + k], w->dy[i + k], w->dz[i + k]), w->tfar[i + k]);
#if RTC_VERSION_MAJOR >= 4
    for (k = 0; k < m; k++) rtcIntersect1(sc, &rh[k], NULL);
#else
    if (api == ELR_WAVE_API_STREAM) rtcIntersect1M(sc, &ctx, rh, (unsigned)m, sizeof(struct RTCRayHit));
    else for (k = 0; k < m; k++) rtcIntersect1(sc, &ctx, &rh[k]);
#endif
    for (k = 0; k < m; k++) {
      w->tfar[i + k] = rh[k].ray.tfar; w->geom[i + k] = rh[k].hit.geomID; w->inst[i + k] = rh[k].hit.instID[0];
      w->prim[i + k] = rh[k].hit.primID; w->u[i + k] = rh[k].hit.u; w->v[i + k] = rh[k].hit.v;
    }
  }
}

void elr_wave_occluded(const elr_scene *s, elr_wave_rays *w, int api, int coherent) {
  RTCScene sc = (RTCScene)s->rtscene;
  int i, k;
#if RTC_VERSION_MAJOR < 4
  struct RTCIntersectContext ctx;
  elr__wave_context(&ctx, coherent);
#endif
  if (api == ELR_WAVE_API_SOA) {
#if RTC_VERSION_MAJOR < 4
    struct RTCRayHitNp np;
    elr__wave_np(w, &np);
    rtcOccludedNp(sc, &ctx, &np.ray, (unsigned)w->n);
    return;
#else
    api = ELR_WAVE_API_STREAM;
#endif
  }
  if (api == ELR_WAVE_API_PACKET16) {
    for (i = 0; i < w->n; i += 16) {
      RTC_ALIGN(64) struct RTCRay16 r;
      RTC_ALIGN(64) int valid[16];
      elr__wave_ray16(w, i, &r, valid);
#if RTC_VERSION_MAJOR >= 4
      rtcOccluded16(valid, sc, &r, NULL);
#else
      rtcOccluded16(valid, sc, &ctx, &r);
#endif
      if (i + 16 <= w->n) memcpy(w->tfar + i, r.tfar, sizeof r.tfar);
      else for (k = 0; k < 16 && i + k < w->n; k++) w->tfar[i + k] = r.tfar[k];
    }
    return;
  }
  for (i = 0; i < w->n; i += ELR_WAVE_CHUNK) {
    struct RTCRay r[ELR_WAVE_CHUNK];
    int m = w->n - i < ELR_WAVE_CHUNK ? w->n - i : ELR_WAVE_CHUNK;
    for (k = 0; k < m; k++) elr__ray_init(&r[k], elr_v(w->ox[i + k], w->oy[i + k], w->oz[i + k]), elr_v(w->dx[i + k], w->dy[i + k], w->dz[i + k]), w->tfar[i + k]);
#if RTC_VERSION_MAJOR >= 4
    for (k = 0; k < m; k++) rtcOccluded1(sc, &r[k], NULL);
#else
    if (api == ELR_WAVE_API_STREAM) rtcOccluded1M(sc, &ctx, r, (unsigned)m, sizeof(struct RTCRay));
    else for (k = 0; k < m; k++) rtcOccluded1(sc, &ctx, &r[k]);
#endif
    for (k = 0; k < m; k++) w->tfar[i + k] = r[k].tfar;
  }
}

int elr_wave_hit(const elr_scene *s, const elr_wave_rays *w, int i, elr_hit *h) {
  if (w->geom[i] == RTC_INVALID_GEOMETRY_ID) return 0;
  elr__hit_record(s, elr_v(w->ox[i], w->oy[i], w->oz[i]), elr_v(w->dx[i], w->dy[i], w->dz[i]), w->geom[i], w->inst[i], w->prim[i], w->u[i],
                  w->v[i], w->tfar[i], h);
  return 1;
}

/* >> the image textures and lights the parser described (pbrt-v3's ImageTexture constructor, MakeLight and
 * CreateInfiniteLight, called here after the parse as pbrt-v4's scene.cpp creates its textures and lights
 * from the parser's entities: api_materials.c and api_lights.c describe, this builds, and lights.c calls
 * neither) */
/* the scene's images, read for what the parser described: what ("LightSource", "Texture") and the
 * directive's file:line name an error (pbrt-v3's ReadImage; imageio.c) */
static int elr__read_image(elr_scene *s, const char *what, const char *path, const char *file, int line, el_image *img, char *err,
                           size_t errlen) {
  char why[700];
  double t0 = elr_now();
  int r = elr_image_read(path, img, why, sizeof why);
  s->t_images += elr_now() - t0;
  if (r != 0) elr_error(err, errlen, file, line, "%s: %s", what, why);
  return r;
}
/* the image as linear RGB; a NaN or infinite texel (or one that overflows when scaled) is an error naming
 * the file and the texel (img is freed then) */
static float *elr__image_rgb(const char *what, el_image *img, int gamma, float scale, const char *path, const char *file, int line,
                             char *err, size_t errlen) {
  int64_t bad;
  float v = 0.f;
  float *rgb = elr_image_rgb(img, gamma, scale, &bad, &v);
  int w = img->width;
  if (rgb) return rgb;
  el_image_free(img);
  if (bad < 0) snprintf(err, errlen, "out of memory");
  else if (!isfinite(v))
    elr_error(err, errlen, file, line, "%s: image \"%s\": texel (%d, %d) is %s", what, path, (int)(bad % w), (int)(bad / w),
              v != v ? "NaN" : "infinite");
  else
    elr_error(err, errlen, file, line, "%s: image \"%s\": texel (%d, %d) times scale %g overflows", what, path, (int)(bad % w),
              (int)(bad / w), scale);
  return NULL;
}

static int elr__make_infinite(elr_scene *s, const elr_infinite_desc *D, char *err, size_t errlen) {
  elr_light *l = &s->light[D->light];
  const char *path = D->path;
  float *rgb = NULL;
  int w = 1, h = 1, r;
  char e[700];
  double t0;
  if (path) {
    el_image img;
    if (elr__read_image(s, "LightSource", path, D->file, D->line, &img, err, errlen) != 0) return -1;
    if (l->bad_texels != EL_ENVLIGHT_BAD_TEXELS_ZERO) { /* NaN / infinite: an error naming the file and texel */
      if (!(rgb = elr__image_rgb("LightSource", &img, 0, 1.f, path, D->file, D->line, err, errlen))) return -1;
    } else { /* "zero": every value as the file holds it, for envlight to count and replace */
      size_t n = (size_t)img.width * (size_t)img.height, k;
      rgb = (float *)malloc(n * 3 * sizeof(float));
      if (!rgb) { el_image_free(&img); snprintf(err, errlen, "out of memory"); return -1; }
      for (k = 0; k < 3 * n; k++) rgb[k] = img.pixels[(k / 3) * (size_t)img.channels + (img.channels >= 3 ? k % 3 : 0)];
    }
    w = img.width; h = img.height;
    el_image_free(&img);
    l->has_map = 1;
    /* pbrt-v4 reads "filename" as a square equal-area octahedral map (ImageInfiniteLight) and refuses any
     * other shape; here a non-square "filename" is read as pbrt-v3's lat-long map, with a warning */
    if (D->v4_filename && w == h) l->mapping = EL_ENVLIGHT_MAPPING_EQUAL_AREA;
    else if (D->v4_filename)
      elr_warn(s, D->filename_file, D->filename_line,
               "LightSource \"infinite\": \"%s\" is %dx%d, not square: pbrt-v4 wants a square equal-area map; read as a lat-long "
               "map (pbrt-v3's \"mapname\")", path, w, h);
  }
  t0 = elr_now();
  r = elr_infinite_init(l, rgb, w, h, D->scale, D->l2w, e, sizeof e);
  if (r == 0 && rgb && l->env && l->env->borrowed) l->env_pixels = rgb; /* read in place: freed with the light */
  else free(rgb);
  if (r != 0) {
    if (path) elr_error(err, errlen, D->file, D->line, "LightSource \"infinite\": image \"%s\": %s", path, e);
    else elr_error(err, errlen, D->file, D->line, "LightSource \"infinite\": %s", e);
    return -1;
  }
  s->t_images += elr_now() - t0;
  /* one warning per kind of texel replaced (the light's "badtexels" policy) */
  if (l->env->negative_texels > 0) {
    int mi = l->env->most_negative_index;
    elr_warn(s, D->file, D->line,
             "LightSource \"infinite\": image \"%s\": %zu negative texels clamped to 0 (the most negative %.3g at texel (%d, %d);"
             " lossy EXR compression such as DWAB rings below 0; \"string badtexels\" \"error\" refuses them)",
             path ? path : "(constant L)", l->env->negative_texels, (double)l->env->most_negative, mi % w, mi / w);
  }
  if (l->env->nonfinite_texels > 0)
    elr_warn(s, D->file, D->line, "LightSource \"infinite\": image \"%s\": %zu NaN or infinite texels set to 0 (\"string badtexels\" \"zero\")",
             path ? path : "(constant L)", l->env->nonfinite_texels);
  if (D->nportal > 0) {
    t0 = elr_now();
    if (elr_infinite_set_portals(l, D->portal, D->nportal, e, sizeof e) != 0) {
      elr_error(err, errlen, D->portal_file, D->portal_line, "LightSource \"infinite\": %s", e);
      return -1;
    }
    s->t_images += elr_now() - t0;
  }
  return 0;
}
/* an image texture the parser described (pbrt-v3's ImageTexture constructor): its image as linear RGB
 * (a float texture's as luminance), flipped in y, in a MIP map (mipmap.h; the texture owns it) */
static int elr__make_imagemap(elr_scene *s, const elr_imagemap_desc *D, char *err, size_t errlen) {
  elr_texture *t = &s->tex[D->tex];
  el_image img;
  float *rgb;
  if (elr__read_image(s, "Texture", D->path, D->file, D->line, &img, err, errlen) != 0) return -1;
  if (!(rgb = elr__image_rgb("Texture", &img, D->gamma, D->scale, D->path, D->file, D->line, err, errlen))) return -1;
  if (D->is_float) { /* pbrt-v3 converts to float by luminance */
    size_t i, n = (size_t)img.width * (size_t)img.height;
    for (i = 0; i < n; i++) {
      float y = 0.212671f * rgb[3 * i] + 0.715160f * rgb[3 * i + 1] + 0.072169f * rgb[3 * i + 2];
      rgb[3 * i] = rgb[3 * i + 1] = rgb[3 * i + 2] = y;
    }
  }
  { /* <<Flip image in y; texture coordinate space has (0,0) at the lower left corner>> (pbrt-v3) */
    int y, W = img.width, H = img.height;
    size_t row = (size_t)W * 3, k;
    for (y = 0; y < H / 2; y++)
      for (k = 0; k < row; k++) {
        float tmp = rgb[(size_t)y * row + k];
        rgb[(size_t)y * row + k] = rgb[(size_t)(H - 1 - y) * row + k];
        rgb[(size_t)(H - 1 - y) * row + k] = tmp;
      }
  }
  {
    double t0 = elr_now();
    el_result r = EL_ERROR_OUT_OF_MEMORY;
    el_mipmap_options mo;
    memset(&mo, 0, sizeof mo);
    mo.wrap_u = mo.wrap_v = (el_mipmap_wrap)D->wrap;
    mo.filter = (el_mipmap_filter)D->filter;
    mo.max_anisotropy = D->maxaniso;
    t->mip = (el_mipmap *)calloc(1, sizeof *t->mip);
    if (t->mip) r = el_mipmap_init(t->mip, rgb, img.width, img.height, 3, &mo);
    if (r != EL_SUCCESS) { free(t->mip); t->mip = NULL; }
    free(rgb);
    s->t_images += elr_now() - t0;
    s->bytes_textures += (size_t)img.width * (size_t)img.height * 3 * sizeof(float);
    el_image_free(&img);
    if (r != EL_SUCCESS) { elr_error(err, errlen, D->file, D->line, "Texture \"%s\": MIP map: %s", D->name, el_result_string(r)); return -1; }
  }
  return 0;
}
int elr_scene_make_textures(elr_scene *s, char *err, size_t errlen) {
  int i;
  for (i = 0; i < s->ntexdesc; i++)
    if (elr__make_imagemap(s, &s->texdesc[i], err, errlen) != 0) return -1;
  return 0;
}
int elr_scene_make_lights(elr_scene *s, char *err, size_t errlen) {
  int i;
  for (i = 0; i < s->nenvdesc; i++)
    if (elr__make_infinite(s, &s->envdesc[i], err, errlen) != 0) return -1;
  return 0;
}
static void elr__free_descs(elr_scene *s) {
  int i;
  for (i = 0; i < s->nenvdesc; i++) {
    elr_infinite_desc *D = &s->envdesc[i];
    free(D->path); free(D->portal); free(D->file); free(D->filename_file); free(D->portal_file);
  }
  free(s->envdesc);
  s->envdesc = NULL; s->nenvdesc = s->capenvdesc = 0;
  for (i = 0; i < s->ntexdesc; i++) {
    elr_imagemap_desc *D = &s->texdesc[i];
    free(D->path); free(D->name); free(D->file);
  }
  free(s->texdesc);
  s->texdesc = NULL; s->ntexdesc = s->captexdesc = 0;
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
  if (elr_parse(s, text, strlen(text), name, base_dir, err, errlen) != 0 || elr_scene_make_textures(s, err, errlen) != 0 ||
      elr_scene_make_lights(s, err, errlen) != 0) {
    elr_scene_free(s);
    return -1;
  }
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
  elr__free_descs(s);
  free(s->tex); free(s->mat); free(s->mesh); free(s->sph); free(s->disk); free(s->light); free(s->mat_textured); free(s->obj); free(s->inst);
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
