/* test_render_instancing: ObjectBegin / ObjectEnd / ObjectInstance as Embree instances (api.c,
 * api_shapes.c, scene.c) against the same scene written with explicit copies of the shapes, each copy under the
 * transform pbrt-v3 gives an instance (the CTM at ObjectInstance times the shape's CTM inside the
 * object).
 *   1. Hit records: 40000 rays through both scenes hit the same shapes; points, geometric normals,
 *      (u, v) and dp/du agree within float rounding (bounds below), interpolated shading normals within
 *      5e-3 (under a non-uniform scale an instance interpolates before transforming, a copy after). The instance's hit maths is
 *      not the copies' (Embree intersects the instance in its own space, in float; the copies' vertices
 *      were transformed in double), so the images are compared within a stated bound, not bit for bit.
 *   2. Images: textured matte, glass and plastic, spheres and meshes (with normals), rotations, a
 *      non-uniform scale and a mirroring instance transform, path tracer: mean |difference| below 3e-4
 *      of the mean and 99.5% of the pixel channels within 1e-3 (a ray that grazes a silhouette may hit
 *      in one scene and miss in the other, and a path through glass may take another branch: each such
 *      sample adds about 5e-5; over seeds 1 to 12 the mean |difference| was 3.4e-5 to 2.0e-4, with the
 *      double-precision sphere callbacks as with the float ones, issue 21).
 *   3. One copy of the geometry: 100 instances of a 2048-triangle prototype keep one mesh and add less
 *      than 1 KiB of Embree memory per instance, where 100 copies add the whole mesh each time; a
 *      prototype that is never instanced is not built.
 *   4. Errors and warnings: ObjectInstance of an unknown name warns; ObjectEnd without ObjectBegin,
 *      nested ObjectBegin and ObjectInstance inside a definition are errors naming file:line. */
#include "render_test_util.h"

/* the object's shapes: written once inside ObjectBegin, or under each instance's transform */
static const char *shapes =
    "  Texture \"ck\" \"spectrum\" \"checkerboard\" \"float uscale\" 6 \"float vscale\" 3 \"rgb tex1\" [ 0.8 0.2 0.1 ] \"rgb tex2\" [ 0.1 0.3 0.7 ]\n"
    "  AttributeBegin\n    Material \"matte\" \"texture Kd\" \"ck\"\n    Translate 0 0.5 0\n    Shape \"sphere\" \"float radius\" 0.4\n  AttributeEnd\n"
    "  AttributeBegin\n    Material \"glass\"\n    Translate 0.55 0.25 0.1\n    Scale 1 0.6 1\n    Shape \"sphere\" \"float radius\" 0.25\n  AttributeEnd\n"
    "  Material \"plastic\" \"rgb Kd\" [ 0.2 0.5 0.2 ] \"float roughness\" 0.05\n"
    "  Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point P\" [ -0.5 0 -0.5  0.5 0 -0.5  0.5 0 0.5  -0.5 0 0.5 ]\n"
    "    \"normal N\" [ 0 1 0.2  0 1 -0.2  0.2 1 0  -0.2 1 0 ] \"float uv\" [ 0 0 1 0 1 1 0 1 ]\n";
static const char *places[6] = {"Translate -2 0 0", "Translate -0.7 0 0.3\n  Rotate 35 0 1 0", "Translate 0.6 0 -0.2\n  Rotate 20 1 0 1\n  Scale 1 1.4 0.8",
                                "Translate 1.9 0 0\n  Scale -1 1 1", "Translate -1.4 0 1.6\n  Rotate -60 0 1 0\n  Scale 0.7 0.7 0.7", "Translate 0.9 0.1 1.5\n  Rotate 90 0 0 1"};

static void make_scenes(char *inst, char *copy, size_t n) {
  static const char *head =
      "LookAt 0 3 -5  0 0.3 0.5  0 1 0\nCamera \"perspective\" \"float fov\" [ 45 ]\n"
      "Film \"image\" \"integer xresolution\" [ 64 ] \"integer yresolution\" [ 48 ]\nSampler \"halton\" \"integer pixelsamples\" [ 8 ]\n"
      "Integrator \"path\" \"integer maxdepth\" [ 6 ]\nWorldBegin\nLightSource \"infinite\" \"rgb L\" [ 0.8 0.9 1 ]\n"
      "LightSource \"distant\" \"point from\" [ 1 3 -2 ] \"point to\" [ 0 0 0 ] \"rgb L\" [ 2 2 2 ]\n"
      "Translate 0 -0.1 0\n"; /* a world transform before the object: part of its shapes' CTM */
  int i;
  size_t a = 0, b = 0;
  a += (size_t)snprintf(inst + a, n - a, "%sObjectBegin \"thing\"\n  Rotate 10 0 1 0\n%sObjectEnd\n", head, shapes);
  b += (size_t)snprintf(copy + b, n - b, "%s", head);
  for (i = 0; i < 6; i++) {
    a += (size_t)snprintf(inst + a, n - a, "AttributeBegin\n  %s\n  ObjectInstance \"thing\"\nAttributeEnd\n", places[i]);
    /* the copy: the instance's transform, then the CTM of the definition (Translate 0 -0.1 0, Rotate 10).
     * pbrt-v3 turns a shape's normal when its own transform mirrors (Scale -1 1 1), not when an instance's
     * does: the mirrored copy needs ReverseOrientation to keep the instance's inside and outside (glass) */
    b += (size_t)snprintf(copy + b, n - b, "AttributeBegin\n  %s\n  Translate 0 -0.1 0\n  Rotate 10 0 1 0\n%s%sAttributeEnd\n", places[i],
                          i == 3 ? "  ReverseOrientation\n" : "", shapes);
  }
  snprintf(inst + a, n - a, "WorldEnd\n");
  snprintf(copy + b, n - b, "WorldEnd\n");
}

static void hits_and_images(void) {
  static char inst[16384], copy[16384];
  char err[512];
  elr_scene *si, *sc;
  make_scenes(inst, copy, sizeof inst);
  si = rt_load("inst.pbrt", inst, err, sizeof err);
  if (!si) { rt_check(0, "instanced scene: %s", err); return; }
  sc = rt_load("copy.pbrt", copy, err, sizeof err);
  if (!sc) { rt_check(0, "copied scene: %s", err); elr_scene_free(si); return; }
  rt_check(si->nobj == 1 && si->ninst == 6 && si->nmesh == 1 && si->nsph == 2 && sc->nmesh == 6 && sc->nsph == 12,
           "6 instances of one object: 1 mesh and 2 spheres stored (copies: %d meshes, %d spheres)", sc->nmesh, sc->nsph);
  { /* 1. hit records along the same rays */
    int i, j, both = 0, one = 0, kind_mismatch = 0;
    double dp = 0, dng = 0, dns = 0, duv = 0, ddp = 0;
    for (i = 0; i < 200; i++)
      for (j = 0; j < 200; j++) {
        elr_v3 o = elr_v(0, 3, -5), d = elr_norm(elr_v(-0.9f + 1.8f * (float)i / 199.f, -0.8f + 0.6f * (float)j / 199.f, 1.f));
        elr_hit a, b;
        int ha = elr_intersect(si, o, d, INFINITY, &a), hb = elr_intersect(sc, o, d, INFINITY, &b);
        if (ha != hb) { one++; continue; }
        if (!ha) continue;
        both++;
        if (a.kind != b.kind || si->mat[a.material].kind != sc->mat[b.material].kind || a.flip != b.flip) { kind_mismatch++; continue; }
        elr_hit_uv(si, &a); elr_hit_uv(sc, &b);
        dp = fmax(dp, elr_len(elr_sub(a.p, b.p)));
        dng = fmax(dng, elr_len(elr_sub(a.ng, b.ng)));
        dns = fmax(dns, elr_len(elr_sub(a.ns, b.ns)));
        duv = fmax(duv, fmax(fabs(a.u - b.u), fabs(a.v - b.v)));
        ddp = fmax(ddp, elr_len(elr_sub(a.dpdu, b.dpdu)) / fmax(1e-6, elr_len(b.dpdu)));
      }
    rt_check(both > 5000 && one <= both / 1000 && kind_mismatch <= both / 1000,
             "40000 rays: %d hit in both scenes, %d in one only (silhouettes), %d on different shapes", both, one, kind_mismatch);
    /* the shading normal of a mesh with normals under a non-uniform scale: an instance interpolates them in
     * its space and transforms the result, a copy interpolates transformed normals (pbrt-v3 does both):
     * they differ by up to a few 1e-3 there; everything else is float rounding */
    rt_check(dp < 2e-5 && dng < 2e-4 && dns < 5e-3 && duv < 2e-4 && ddp < 1e-3,
             "  same hit records: |dp| %.2g, |dng| %.2g, |dns| %.2g, |duv| %.2g, |d dpdu| / |dpdu| %.2g", dp, dng, dns, duv, ddp);
  }
  { /* 2. images */
    elr_image a, b;
    elr_stats st;
    if (rt_render(si, 0, -1, -1, 2, 9, &a, &st) == 0 && rt_render(sc, 0, -1, -1, 2, 9, &b, &st) == 0) {
      int k, n = a.width * a.height * 3, close = 0;
      double mean = 0, diff = 0;
      for (k = 0; k < n; k++) {
        double d = fabs(a.rgb[k] - b.rgb[k]);
        mean += b.rgb[k]; diff += d;
        close += d <= 1e-3 * fmax(1.0, b.rgb[k]);
      }
      rt_check(diff < 3e-4 * mean && close >= n * 995 / 1000,
               "path-traced images: mean |difference| %.3g of the mean, %d of %d pixel channels within 1e-3", diff / mean, close, n);
      elr_image_free(&a); elr_image_free(&b);
    }
  }
  elr_scene_free(si);
  elr_scene_free(sc);
}

/* a 2048-triangle grid, instanced or copied k times */
#define MEMBUF (8 << 20)
static size_t embree_bytes(int k, int instanced, int *nmesh) {
  static char buf[MEMBUF];
  char err[512];
  size_t o = 0;
  int i, j;
  elr_scene *s;
  size_t bytes;
  o += (size_t)snprintf(buf + o, MEMBUF - o, "WorldBegin\n%s", instanced ? "ObjectBegin \"grid\"\n" : "");
  for (j = 0; j < (instanced ? 1 : k); j++) {
    if (!instanced) o += (size_t)snprintf(buf + o, MEMBUF - o, "AttributeBegin\nTranslate %d 0 0\n", 3 * j);
    o += (size_t)snprintf(buf + o, MEMBUF - o, "Shape \"trianglemesh\" \"integer indices\" [");
    for (i = 0; i < 32 * 32; i++) {
      int x = i % 32, y = i / 32, v = y * 33 + x;
      o += (size_t)snprintf(buf + o, MEMBUF - o, " %d %d %d %d %d %d", v, v + 1, v + 34, v, v + 34, v + 33);
    }
    o += (size_t)snprintf(buf + o, MEMBUF - o, " ] \"point P\" [");
    for (i = 0; i < 33 * 33; i++) o += (size_t)snprintf(buf + o, MEMBUF - o, " %g %g 0", (i % 33) / 16.0, (i / 33) / 16.0);
    o += (size_t)snprintf(buf + o, MEMBUF - o, " ]\n%s", instanced ? "" : "AttributeEnd\n");
  }
  if (instanced) {
    o += (size_t)snprintf(buf + o, MEMBUF - o, "ObjectEnd\nObjectBegin \"unused\"\nShape \"sphere\"\nObjectEnd\n");
    for (j = 0; j < k; j++) o += (size_t)snprintf(buf + o, MEMBUF - o, "AttributeBegin\nTranslate %d 0 0\nObjectInstance \"grid\"\nAttributeEnd\n", 3 * j);
  }
  snprintf(buf + o, MEMBUF - o, "WorldEnd\n");
  s = rt_load("mem.pbrt", buf, err, sizeof err);
  if (!s) { rt_check(0, "memory scene: %s", err); return 0; }
  bytes = s->bytes_embree;
  *nmesh = s->nmesh;
  if (instanced) rt_check(s->obj[1].rtscene == NULL && s->obj[0].rtscene != NULL, "  the prototype never instanced is not built");
  elr_scene_free(s);
  return bytes;
}
static void one_copy(void) {
  int m1, m100, c1, c100;
  size_t i1 = embree_bytes(1, 1, &m1), i100 = embree_bytes(100, 1, &m100), k1 = embree_bytes(1, 0, &c1), k100 = embree_bytes(100, 0, &c100);
  double per_inst = ((double)i100 - (double)i1) / 99.0, per_copy = ((double)k100 - (double)k1) / 99.0;
  rt_check(m1 == 1 && m100 == 1 && c100 == 100, "100 instances keep 1 mesh (copies: %d)", c100);
  rt_check(per_inst < 1024 && per_copy > 50 * per_inst && per_copy > 2048 * 12,
           "Embree memory per instance %.0f bytes, per copy %.0f bytes (a 2048-triangle mesh)", per_inst, per_copy);
}

static void errors(void) {
  char err[512];
  elr_scene *s;
  s = rt_load("e1.pbrt", "WorldBegin\nLightSource \"point\"\nObjectInstance \"nothing\"\nWorldEnd\n", err, sizeof err);
  rt_check(s && strstr(elr_scene_last_warning(s), "e1.pbrt:3:") && strstr(elr_scene_last_warning(s), "\"nothing\" is not defined"),
           "ObjectInstance of an unknown object warns: \"%s\"", s ? elr_scene_last_warning(s) : err);
  elr_scene_free(s);
  s = rt_load("e2.pbrt", "WorldBegin\nLightSource \"point\"\nObjectEnd\nWorldEnd\n", err, sizeof err);
  rt_check(!s && strstr(err, "e2.pbrt:3:") && strstr(err, "ObjectEnd without ObjectBegin"), "\"%s\"", s ? "(loaded)" : err);
  elr_scene_free(s);
  s = rt_load("e3.pbrt", "WorldBegin\nLightSource \"point\"\nObjectBegin \"a\"\nObjectBegin \"b\"\nObjectEnd\nObjectEnd\nWorldEnd\n", err, sizeof err);
  rt_check(!s && strstr(err, "e3.pbrt:4:") && strstr(err, "inside the definition"), "\"%s\"", s ? "(loaded)" : err);
  elr_scene_free(s);
  s = rt_load("e4.pbrt", "WorldBegin\nLightSource \"point\"\nObjectBegin \"a\"\nShape \"sphere\"\nObjectInstance \"a\"\nObjectEnd\nWorldEnd\n", err, sizeof err);
  rt_check(!s && strstr(err, "e4.pbrt:5:") && strstr(err, "inside an object definition"), "\"%s\"", s ? "(loaded)" : err);
  elr_scene_free(s);
  s = rt_load("e5.pbrt", "WorldBegin\nLightSource \"point\"\nObjectBegin \"a\"\nShape \"sphere\"\nObjectEnd\nTranslate 2e15 0 0\nObjectInstance \"a\"\nWorldEnd\n", err, sizeof err);
  rt_check(!s && strstr(err, "e5.pbrt:7:") && strstr(err, "outside |x| <="), "an instance placed beyond the traceable range: \"%s\"", s ? "(loaded)" : err);
  elr_scene_free(s);
  s = rt_load("e6.pbrt", "WorldBegin\nLightSource \"point\"\nObjectBegin \"a\"\nObjectEnd\nObjectInstance \"a\"\nWorldEnd\n", err, sizeof err);
  rt_check(s && s->ninst == 0 && elr_scene_warnings(s) == 0, "an empty object adds nothing, silently (pbrt-v3)");
  elr_scene_free(s);
}

int main(void) {
  rt_mkdir("test_render_instancing");
  hits_and_images();
  one_copy();
  errors();
  return rt_finish("test_render_instancing");
}
