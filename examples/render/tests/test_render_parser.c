/* test_render_parser: the pbrt-v3 subset the renderer reads, directive by directive, and the errors
 * bad files give (each names file:line and the problem; the `render` program then exits 1 and writes
 * nothing).
 *
 * Expected values are pbrt-v3's semantics worked by hand: LookAt's camera-to-world frame, the CTM
 * composition order (Translate then Scale applies the scale first), Rotate's right-hand rule in a
 * left-handed space, Transform's column-major (transposed) matrix, named coordinate systems, attribute
 * and transform scopes, the defaults of every directive. */
#include "render_test_util.h"
#include <sys/stat.h>

static int near3(elr_v3 a, float x, float y, float z, float tol) {
  return fabsf(a.x - x) < tol && fabsf(a.y - y) < tol && fabsf(a.z - z) < tol;
}

static const char *W(const char *body) { /* a minimal valid file around a world body */
  static char buf[8192];
  snprintf(buf, sizeof buf, "Film \"image\" \"integer xresolution\" 8 \"integer yresolution\" 8\nWorldBegin\n%sWorldEnd\n", body);
  return buf;
}

static void defaults(void) {
  char err[512];
  elr_scene *s = rt_load("empty.pbrt", "WorldBegin\nWorldEnd\n", err, sizeof err);
  if (!s) { rt_check(0, "empty scene: %s", err); return; }
  rt_check(s->d.xres == 1280 && s->d.yres == 720, "defaults: Film 1280 x 720 (pbrt-v3)");
  rt_check(!strcmp(s->d.filename, "pbrt.exr"), "defaults: filename pbrt.exr");
  rt_check(s->d.fov == 90.f, "defaults: fov 90");
  rt_check(s->d.sampler == ELR_SAMPLER_ZEROTWO && s->d.spp == 16 && s->d.dims == 16,
           "defaults: 02sequence (the best measured; pbrt-v3's is halton), 16 pixel samples, 16 dimensions (%d, %d, %d)", s->d.sampler,
           s->d.spp, s->d.dims);
  rt_check(s->d.integrator_path == 1 && s->d.maxdepth == 5, "defaults: path, maxdepth 5");
  rt_check(s->d.filter.type == ELR_PF_BOX && s->d.filter.xw == 0.5f, "defaults: box filter, radius 0.5");
  rt_check(s->nmat == 1 && s->mat[0].kind == ELR_MAT_MATTE && s->tex[s->mat[0].kd].value.x == 0.5f, "defaults: matte Kd 0.5");
  elr_scene_free(s);
}

static void options(void) {
  char err[512];
  elr_scene *s;
  elr_v3 o, f;
  s = rt_load("opts.pbrt",
              "LookAt 1 2 3  1 2 4  0 1 0\n"
              "Camera \"perspective\" \"float fov\" 30 \"float frameaspectratio\" 2 \"float screenwindow\" [ -2 2 -1 1 ]\n"
              "Film \"image\" \"integer xresolution\" [ 40 ] \"integer yresolution\" [ 20 ] \"string filename\" \"x.pfm\"\n"
              "  \"float cropwindow\" [ 0.25 0.75 0 0.5 ]\n"
              "PixelFilter \"mitchell\" \"float xwidth\" 1.5 \"float ywidth\" 2.5 \"float B\" 0.2 \"float C\" 0.4\n"
              "Sampler \"stratified\" \"integer xsamples\" 3 \"integer ysamples\" 2 \"bool jitter\" \"false\"\n"
              "Integrator \"directlighting\" \"integer maxdepth\" [ 7 ]\n"
              "WorldBegin\nWorldEnd\n", err, sizeof err);
  if (!s) { rt_check(0, "options scene: %s", err); return; }
  o = elr_xpoint(&s->d.cam2world, elr_v(0, 0, 0));
  f = elr_xvector(&s->d.cam2world, elr_v(0, 0, 1));
  rt_check(near3(o, 1, 2, 3, 1e-6f) && near3(f, 0, 0, 1, 1e-6f), "LookAt: camera at (1,2,3) looking along +z");
  f = elr_xvector(&s->d.cam2world, elr_v(1, 0, 0));
  rt_check(near3(f, 1, 0, 0, 1e-6f), "LookAt: camera +x is world +x (left-handed: up x dir)");
  rt_check(s->d.fov == 30.f && s->d.has_frameaspect && s->d.frameaspect == 2.f && s->d.has_screen && s->d.screen[0] == -2.f,
           "Camera: fov, frameaspectratio, screenwindow");
  rt_check(s->d.xres == 40 && s->d.yres == 20 && !strcmp(s->d.filename, "x.pfm"), "Film: resolution, filename");
  {
    int w, h;
    elr_scene_resolution(s, &w, &h);
    rt_check(w == 20 && h == 10, "Film: cropwindow [0.25 0.75 0 0.5] of 40 x 20 gives 20 x 10 (got %d x %d)", w, h);
  }
  rt_check(s->d.filter.type == ELR_PF_MITCHELL && s->d.filter.xw == 1.5f && s->d.filter.yw == 2.5f && s->d.filter.b == 0.2f &&
               s->d.filter.c == 0.4f, "PixelFilter mitchell with widths and B, C");
  rt_check(s->d.sampler == ELR_SAMPLER_STRATIFIED && s->d.spp == 6 && s->d.jitter == 0, "Sampler stratified 3 x 2, no jitter");
  rt_check(!s->d.integrator_path && s->d.maxdepth == 7, "Integrator directlighting maxdepth 7");
  elr_scene_free(s);
  {
    const char *filters[5] = {"box", "triangle", "gaussian", "mitchell", "sinc"};
    float defw[5] = {0.5f, 2.f, 2.f, 2.f, 4.f};
    int k;
    for (k = 0; k < 5; k++) {
      char buf[512];
      snprintf(buf, sizeof buf, "PixelFilter \"%s\"\nSampler \"random\" \"integer pixelsamples\" 3\nIntegrator \"path\"\nWorldBegin\nWorldEnd\n", filters[k]);
      s = rt_load("f.pbrt", buf, err, sizeof err);
      rt_check(s && s->d.filter.type == k && s->d.filter.xw == defw[k] && s->d.sampler == ELR_SAMPLER_RANDOM && s->d.spp == 3,
               "PixelFilter \"%s\": default radius %g; Sampler random", filters[k], defw[k]);
      elr_scene_free(s);
    }
  }
}

static void transforms_and_shapes(void) {
  char err[512];
  elr_scene *s;
  {
    char cmd[600];
    snprintf(cmd, sizeof cmd, "mkdir -p '%s/inc'", rt_dir);
    if (system(cmd) != 0) printf("mkdir failed\n");
  }
  rt_write("inc/part.pbrt", "# included\nShape \"sphere\" \"float radius\" 0.25\n");
  rt_write("quad.ply",
           "ply\nformat ascii 1.0\ncomment a unit quad\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
           "property float u\nproperty float v\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
           "0 0 0 0 0\n1 0 0 1 0\n1 1 0 1 1\n0 1 0 0 1\n4 0 1 2 3\n");
  {
    /* binary little endian: one triangle with normals */
    FILE *f = fopen(rt_path("tri.ply"), "wb");
    float v[3][6] = {{0, 0, 0, 0, 0, 1}, {2, 0, 0, 0, 0, 1}, {0, 2, 0, 0, 0, 1}};
    unsigned char n = 3;
    int idx[3] = {0, 1, 2};
    fputs("ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
          "property float nx\nproperty float ny\nproperty float nz\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n", f);
    fwrite(v, sizeof v, 1, f);
    fwrite(&n, 1, 1, f);
    fwrite(idx, sizeof idx, 1, f);
    fclose(f);
  }
  s = rt_load("xf.pbrt", W(
      "AttributeBegin\n"
      "  Translate 1 0 0\n  Scale 2 2 2\n"
      "  Shape \"sphere\" \"float radius\" 0.5\n"                 /* sphere 0: centre (1,0,0), world radius 1 */
      "  CoordinateSystem \"mine\"\n"
      "AttributeEnd\n"
      "TransformBegin\n  Rotate 90 0 0 1\n"
      "  Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 ] \"point P\" [ 1 0 0  0 1 0  0 0 1 ]\n" /* mesh 0 */
      "TransformEnd\n"
      "Transform [ 1 0 0 0  0 1 0 0  0 0 1 0  5 6 7 1 ]\n"
      "Shape \"sphere\"\n"                                          /* sphere 1: centre (5,6,7) */
      "ConcatTransform [ 2 0 0 0  0 2 0 0  0 0 2 0  0 0 0 1 ]\n"
      "Shape \"sphere\"\n"                                          /* sphere 2: centre (5,6,7), scale 2 */
      "Identity\nCoordSysTransform \"mine\"\n"
      "Include \"inc/part.pbrt\"\n"                                 /* sphere 3 in \"mine\" */
      "Identity\n"
      "Shape \"plymesh\" \"string filename\" \"quad.ply\"\n"          /* mesh 1: 2 triangles */
      "Translate 0 0 3\n"
      "Shape \"plymesh\" \"string filename\" \"tri.ply\"\n"           /* mesh 2 */
      "LightSource \"point\" \"point from\" [ 0 1 0 ] \"rgb I\" [ 3 3 3 ]\n"
      "LightSource \"distant\" \"point from\" [ 0 0 0 ] \"point to\" [ 0 0 1 ] \"rgb L\" [ 2 2 2 ]\n"
      "ReverseOrientation\n"), err, sizeof err);
  if (!s) { rt_check(0, "transforms scene: %s", err); return; }
  rt_check(s->nsph == 4 && s->nmesh == 3 && s->nlight == 2, "4 spheres, 3 meshes, 2 lights (got %d, %d, %d)", s->nsph, s->nmesh, s->nlight);
  if (s->nsph == 4 && s->nmesh == 3 && s->nlight == 2) {
    elr_v3 c0 = elr_xpoint(&s->sph[0].o2w, elr_v(0, 0, 0)), e0 = elr_xpoint(&s->sph[0].o2w, elr_v(0.5f, 0, 0));
    rt_check(near3(c0, 1, 0, 0, 1e-6f) && near3(e0, 2, 0, 0, 1e-6f), "Translate then Scale: sphere centre (1,0,0), surface point (2,0,0)");
    rt_check(near3(elr_v(s->mesh[0].p[0], s->mesh[0].p[1], s->mesh[0].p[2]), 0, 1, 0, 1e-6f) &&
                 near3(elr_v(s->mesh[0].p[3], s->mesh[0].p[4], s->mesh[0].p[5]), -1, 0, 0, 1e-6f),
             "Rotate 90 about z: (1,0,0) -> (0,1,0), (0,1,0) -> (-1,0,0)");
    rt_check(near3(elr_xpoint(&s->sph[1].o2w, elr_v(0, 0, 0)), 5, 6, 7, 1e-6f), "Transform: column-major matrix, translation (5,6,7)");
    rt_check(near3(elr_xpoint(&s->sph[2].o2w, elr_v(1, 0, 0)), 7, 6, 7, 1e-6f), "ConcatTransform: scale 2 after the translation");
    rt_check(near3(elr_xpoint(&s->sph[3].o2w, elr_v(0.25f, 0, 0)), 1.5f, 0, 0, 1e-6f) && s->sph[3].radius == 0.25f,
             "CoordinateSystem / CoordSysTransform + Include: the included sphere in the saved frame");
    rt_check(s->mesh[1].ntri == 2 && s->mesh[1].uv && s->mesh[1].uv[4] == 1.f, "plymesh ASCII: a quad becomes 2 triangles, uv read");
    rt_check(s->mesh[2].ntri == 1 && s->mesh[2].n && s->mesh[2].p[5] == 3.f && s->mesh[2].p[3] == 2.f,
             "plymesh binary: 1 triangle with normals, moved by Translate 0 0 3");
    rt_check(s->light[0].kind == ELR_LIGHT_POINT && near3(s->light[0].pos, 0, 1, 3, 1e-6f) && s->light[0].L.x == 3.f, "point light: from (0,1,0) moved by the CTM to (0,1,3), I");
    rt_check(s->light[1].kind == ELR_LIGHT_DISTANT && near3(s->light[1].dir, 0, 0, -1, 1e-6f) && s->light[1].L.x == 2.f,
             "distant light: direction towards the light = from - to");
  }
  /* the one warning: two lights under the default path integrator, whose default lightsamplestrategy
   * "spatial" is "power" here */
  rt_check(elr_scene_warnings(s) == 1 && strstr(elr_scene_last_warning(s), "\"spatial\"") && strstr(elr_scene_last_warning(s), "\"power\""),
           "no warnings for supported directives but pbrt-v3's default lightsamplestrategy \"spatial\" (%d: %s)", elr_scene_warnings(s),
           elr_scene_last_warning(s));
  elr_scene_free(s);
}

/* Exact spheres: Embree's sphere primitive for a similarity transform, the object-space user geometry
 * for an ellipsoid; hits from outside and from inside, at the analytic distances. */
static void sphere_hits(int embree_spheres) {
  char err[512];
  elr_scene *s;
  if (embree_spheres) setenv("ELR_EMBREE_SPHERES", "1", 1); else unsetenv("ELR_EMBREE_SPHERES");
  s = rt_load("hits.pbrt", W("AttributeBegin\n  Translate 0 0 10\n  Scale 2 1 1\n  Shape \"sphere\" \"float radius\" 1\nAttributeEnd\n"
                                          "AttributeBegin\n  Translate 0 0 -10\n  Rotate 30 1 1 0\n  Scale 3 3 3\n  Shape \"sphere\" \"float radius\" 0.5\nAttributeEnd\n"),
                         err, sizeof err);
  elr_hit h;
  if (!s) { rt_check(0, "hits scene: %s", err); return; }
  if (embree_spheres)
    rt_check(s->nbuiltin == 1 && s->nuser == 1, "ELR_EMBREE_SPHERES: the similarity sphere on Embree's primitive, the ellipsoid on the user geometry");
  else
    rt_check(s->nbuiltin == 0 && s->nuser == 2, "default: both spheres on the object-space user geometry");
  {
    int k;
    k = elr_intersect(s, elr_v(-5, 0, 10), elr_v(1, 0, 0), INFINITY, &h);
    rt_check(k && fabsf(h.t - 3.f) < 1e-5f && near3(h.ng, -1, 0, 0, 1e-5f), "ellipsoid (Scale 2 1 1): hit at x = -2 (t %.6f), normal -x", h.t);
    k = elr_intersect(s, elr_v(0, 0, 10), elr_v(0, 1, 0), INFINITY, &h);
    rt_check(k && fabsf(h.t - 1.f) < 1e-5f, "ellipsoid from inside: hit at y = 1 (t %.6f)", h.t);
    k = elr_intersect(s, elr_v(0, 5, -10), elr_v(0, -1, 0), INFINITY, &h);
    rt_check(k && fabsf(h.t - 3.5f) < 1e-5f && near3(h.ng, 0, 1, 0, 1e-5f), "rotated, scaled sphere (radius 0.5 x 3): hit at t = 3.5 (%.6f)", h.t);
    k = elr_intersect(s, elr_v(0.3f, 0.2f, -14), elr_v(0, 0, 1), INFINITY, &h);
    rt_check(k && fabsf(h.t - (4.f - sqrtf(1.5f * 1.5f - 0.13f))) < 1e-5f, "sphere: off-centre hit at t = 4 - sqrt(2.25 - 0.13) (%.6f)", h.t);
    k = elr_intersect(s, elr_v(0, 0, -10), elr_v(0, 0, 1), INFINITY, &h);
    rt_check(k && fabsf(h.t - 1.5f) < 1e-5f, "sphere from inside: t = 1.5 (%.6f)", h.t);
  }
  rt_check(!elr_intersect(s, elr_v(0, 1.6f, -10), elr_v(0, 0, 1), INFINITY, &h) && !elr_occluded(s, elr_v(0, 1.6f, -10), elr_v(0, 0, 1), 15.f),
           "a ray passing 0.1 above the sphere misses, and is not occluded before the ellipsoid");
  rt_check(elr_occluded(s, elr_v(-5, 0, 10), elr_v(1, 0, 0), INFINITY) && !elr_occluded(s, elr_v(-5, 0, 10), elr_v(1, 0, 0), 2.9f),
           "occlusion respects tmax (ellipsoid at t = 3)");
  elr_scene_free(s);
}

static void materials_textures(void) {
  char err[512];
  elr_scene *s;
  unsigned char png[4 * 2 * 3] = {255, 0, 0, 0, 255, 0, 0, 0, 255, 255, 255, 255, 128, 128, 128, 0, 0, 0, 10, 20, 30, 40, 50, 60};
  float hdr[3 * 2 * 2] = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12};
  el_image_write_png(rt_path("tex.png"), png, 4, 2, 3, err, sizeof err);
  el_image_write_hdr(rt_path("env.hdr"), hdr, 2, 2, 3, err, sizeof err);
  el_image_write_exr(rt_path("env.exr"), hdr, 2, 2, 3, err, sizeof err);
  s = rt_load("mat.pbrt", W(
      "Texture \"c\" \"spectrum\" \"checkerboard\" \"float uscale\" 4 \"float vscale\" 2 \"rgb tex1\" [ 1 0 0 ] \"rgb tex2\" [ 0 0 1 ]\n"
      "Texture \"k\" \"spectrum\" \"constant\" \"rgb value\" [ 0.1 0.2 0.3 ]\n"
      "Texture \"img\" \"spectrum\" \"imagemap\" \"string filename\" \"tex.png\" \"string filter\" \"trilinear\" \"string wrap\" \"clamp\"\n"
      "   \"float maxanisotropy\" 4 \"float scale\" 2 \"bool gamma\" \"false\"\n"
      "Texture \"r\" \"float\" \"constant\" \"float value\" 0.3\n"
      "Material \"matte\" \"texture Kd\" \"c\" \"float sigma\" 0\n"
      "Material \"mirror\" \"rgb Kr\" [ 0.5 0.6 0.7 ]\n"
      "Material \"plastic\" \"texture Kd\" \"img\" \"texture Ks\" \"k\" \"texture roughness\" \"r\" \"bool remaproughness\" \"false\"\n"
      "MakeNamedMaterial \"gold\" \"string type\" \"plastic\" \"rgb Kd\" [ 0.9 0.7 0.1 ]\n"
      "NamedMaterial \"gold\"\n"
      "Shape \"sphere\"\n"
      "LightSource \"infinite\" \"string mapname\" \"env.hdr\" \"integer samples\" 4\n"
      "LightSource \"infinite\" \"string mapname\" \"env.exr\" \"bool compensated\" \"true\"\n"), err, sizeof err);
  if (!s) { rt_check(0, "materials scene: %s", err); return; }
  {
    int n = s->nmat;
    elr_tex_ctx c;
    elr_v3 v;
    memset(&c, 0, sizeof c);
    rt_check(n == 5 && s->mat[1].kind == ELR_MAT_MATTE && s->mat[2].kind == ELR_MAT_MIRROR && s->mat[3].kind == ELR_MAT_PLASTIC &&
                 s->mat[4].kind == ELR_MAT_PLASTIC, "materials matte, mirror, plastic, named plastic");
    rt_check(s->sph[0].material == 4, "NamedMaterial binds the named material to the next shape");
    c.u = 0.1f; c.v = 0.1f; /* st = (0.4, 0.2): cell (0,0) even -> tex1 */
    v = elr_tex_eval(s, s->mat[1].kd, &c);
    c.u = 0.3f; /* st = (1.2, 0.2): cell (1,0) odd -> tex2 */
    rt_check(near3(v, 1, 0, 0, 1e-6f) && near3(elr_tex_eval(s, s->mat[1].kd, &c), 0, 0, 1, 1e-6f), "checkerboard with uscale/vscale");
    rt_check(near3(elr_tex_eval(s, s->mat[2].kr, &c), 0.5f, 0.6f, 0.7f, 1e-6f), "mirror Kr");
    rt_check(near3(elr_tex_eval(s, s->mat[3].ks, &c), 0.1f, 0.2f, 0.3f, 1e-6f) && elr_tex_eval(s, s->mat[3].rough, &c).x == 0.3f &&
                 s->mat[3].remap == 0, "plastic: constant textures for Ks and roughness, remaproughness false");
    /* imagemap: row 0 of the file is the TOP, pbrt-v3 flips so t = 0 is the bottom row; texel centres */
    c.u = 0.125f; c.v = 0.75f; /* texel (0, top row) = red, x scale 2, no gamma */
    v = elr_tex_eval(s, s->mat[3].kd, &c);
    rt_check(near3(v, 2, 0, 0, 1e-5f), "imagemap: top-left texel at (u,v) = (0.125, 0.75), scaled by 2 (got %g %g %g)", v.x, v.y, v.z);
    c.u = 0.875f; c.v = 0.25f; /* bottom right texel (40,50,60)/255 * 2 */
    v = elr_tex_eval(s, s->mat[3].kd, &c);
    rt_check(near3(v, 80 / 255.f, 100 / 255.f, 120 / 255.f, 1e-5f), "imagemap: bottom-right texel at (0.875, 0.25)");
    rt_check(s->nlight == 2 && s->light[0].nsamples == 4 && s->light[0].has_map && s->light[1].compensated == 1,
             "infinite lights from .hdr (samples 4) and .exr (compensated)");
  }
  elr_scene_free(s);
  /* gamma: an 8-bit PNG is sRGB-decoded by default (pbrt-v3) */
  s = rt_load("gam.pbrt", W("Texture \"img\" \"spectrum\" \"imagemap\" \"string filename\" \"tex.png\"\nMaterial \"matte\" \"texture Kd\" \"img\"\n"), err, sizeof err);
  if (s) {
    elr_tex_ctx c;
    elr_v3 v;
    memset(&c, 0, sizeof c);
    c.u = 0.125f; c.v = 0.25f; /* the bottom row's first texel, (128, 128, 128) */
    v = elr_tex_eval(s, s->mat[1].kd, &c);
    {
      double e = pow((128 / 255.0 + 0.055) / 1.055, 2.4);
      rt_check(fabs(v.x - e) < 1e-4, "imagemap PNG: sRGB decoded by default (%.5f, expect %.5f)", v.x, e);
    }
    elr_scene_free(s);
  } else rt_check(0, "gamma scene: %s", err);
}

/* binary big endian PLY: bytes written in reverse order by hand */
static void ply_big_endian(void) {
  char err[512];
  elr_scene *s;
  FILE *f = fopen(rt_path("be.ply"), "wb");
  float v[9] = {0, 0, 0, 3, 0, 0, 0, 0, 5};
  int idx[3] = {0, 1, 2}, i, k;
  unsigned char n = 3;
  fputs("ply\nformat binary_big_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
        "element face 1\nproperty list uchar int vertex_indices\nend_header\n", f);
  for (i = 0; i < 9; i++) { unsigned char b[4], r[4]; memcpy(b, &v[i], 4); for (k = 0; k < 4; k++) r[k] = b[3 - k]; fwrite(r, 1, 4, f); }
  fwrite(&n, 1, 1, f);
  for (i = 0; i < 3; i++) { unsigned char b[4], r[4]; memcpy(b, &idx[i], 4); for (k = 0; k < 4; k++) r[k] = b[3 - k]; fwrite(r, 1, 4, f); }
  fclose(f);
  s = rt_load("be.pbrt", W("Shape \"plymesh\" \"string filename\" \"be.ply\"\n"), err, sizeof err);
  rt_check(s && s->nmesh == 1 && s->mesh[0].ntri == 1 && s->mesh[0].p[3] == 3.f && s->mesh[0].p[8] == 5.f && s->mesh[0].idx[2] == 2,
           "plymesh binary big endian: vertices and indices byte-swapped correctly%s%s", s ? "" : ": ", s ? "" : err);
  elr_scene_free(s);
}

static void expect_error(const char *name, const char *text, const char *where, const char *what);
/* PLY headers: a comment longer than the line buffer loads (its rest was read as another header line);
 * another keyword's line that long, and a face list of another name, are errors that say so */
static void ply_headers(void) {
  char err[512], longc[400], hdr[1024];
  elr_scene *s;
  memset(longc, 'c', sizeof longc - 1);
  longc[sizeof longc - 1] = 0;
  memcpy(longc + 247, "element face 9 ", 15); /* where a 255-character buffer would cut the line: read as a header line */
  snprintf(hdr, sizeof hdr, "ply\nformat ascii 1.0\ncomment %s\nelement vertex 3\nproperty float x\nproperty float y\n"
           "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", longc);
  rt_write("longc.ply", hdr);
  s = rt_load("longc.pbrt", W("Shape \"plymesh\" \"string filename\" \"longc.ply\"\n"), err, sizeof err);
  rt_check(s && s->nmesh == 1 && s->mesh[0].ntri == 1, "PLY with a 400-character comment loads%s%s", s ? "" : ": ", s ? "" : err);
  elr_scene_free(s);
  snprintf(hdr, sizeof hdr, "ply\nformat ascii 1.0\nelement vertex 3 %s\nproperty float x\nend_header\n", longc);
  rt_write("longe.ply", hdr);
  expect_error("longe.pbrt", W("Shape \"plymesh\" \"string filename\" \"longe.ply\"\n"), "longe.ply", "longer than 255 characters");
  rt_write("faces.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                        "element face 1\nproperty list uchar int indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  expect_error("faces.pbrt", W("Shape \"plymesh\" \"string filename\" \"faces.ply\"\n"), "faces.ply", "no \"vertex_indices\"");
}

static void warnings(void) {
  char err[512];
  elr_scene *s = rt_load("warn.pbrt", W("MakeNamedMedium \"fog\" \"string type\" \"homogeneous\"\nShape \"sphere\" \"float radius\" 1 \"float foo\" 3\n"
                                        "Material \"hair\"\nLightSource \"point\"\n"),
                         err, sizeof err);
  if (!s) { rt_check(0, "warnings scene: %s", err); return; }
  rt_check(elr_scene_warnings(s) == 3, "3 warnings: unsupported directive, unknown parameter, unsupported material (%d)", elr_scene_warnings(s));
  rt_check(strstr(elr_scene_last_warning(s), "warn.pbrt:5:") && strstr(elr_scene_last_warning(s), "hair"),
           "warning names file:line and what is ignored: \"%s\"", elr_scene_last_warning(s));
  elr_scene_free(s);
}

static void expect_error(const char *name, const char *text, const char *where, const char *what) {
  char err[512];
  elr_scene *s = rt_load(name, text, err, sizeof err);
  if (s) { rt_check(0, "%s: expected an error", name); elr_scene_free(s); return; }
  rt_check(strstr(err, where) != NULL && strstr(err, what) != NULL, "%s: error \"%s\" names %s and %s", name, err, where, what);
}

/* A FIFO given as the scene, an Include, an image or a PLY file: opening it for reading would wait for
 * a writer forever. Each must fail at once, naming the file (an alarm turns a hang into a failure). */
static void fifos(void) {
  const char *names[3] = {"fifo.hdr", "fifo_inc.pbrt", "fifo.ply"};
  char err[512];
  elr_scene *s = NULL;
  int k, made = 1;
  for (k = 0; k < 3; k++) {
    unlink(rt_path(names[k]));
    if (mkfifo(rt_path(names[k]), 0600) != 0) made = 0;
  }
  if (!made) { rt_check(0, "mkfifo in %s", rt_dir); return; }
  alarm(60);
  expect_error("fifo1.pbrt", "WorldBegin\nLightSource \"infinite\" \"string mapname\" \"fifo.hdr\"\nWorldEnd\n", "fifo1.pbrt:2:",
               "not a regular file");
  expect_error("fifo2.pbrt", "Include \"fifo_inc.pbrt\"\nWorldBegin\nWorldEnd\n", "fifo2.pbrt:1:", "not a regular file");
  expect_error("fifo3.pbrt", "WorldBegin\nShape \"plymesh\" \"string filename\" \"fifo.ply\"\nWorldEnd\n", "fifo3.pbrt:2:",
               "not a regular file");
  rt_check(elr_scene_load(rt_path("fifo_inc.pbrt"), &s, 1, err, sizeof err) != 0 && strstr(err, "fifo_inc.pbrt") &&
               strstr(err, "not a regular file"),
           "a FIFO as the scene file: \"%s\"", err);
  elr_scene_free(s);
  alarm(0);
}

static void errors(void) {
  expect_error("trunc1.pbrt", "Film \"image\" \"integer xresolution\" [ 8 ", "trunc1.pbrt:1:", "file ends");
  expect_error("trunc2.pbrt", "WorldBegin\nShape \"sphere\"\n", "trunc2.pbrt:", "before WorldEnd");
  expect_error("trunc3.pbrt", "Film \"image\" \"string filename\" \"abc", "trunc3.pbrt:1:", "unterminated string");
  expect_error("unknown.pbrt", "WorldBegin\nFoo 1 2 3\nWorldEnd\n", "unknown.pbrt:2:", "unknown directive \"Foo\"");
  expect_error("type.pbrt", "Camera \"perspective\"\n \"string fov\" \"wide\"\nWorldBegin\nWorldEnd\n", "type.pbrt:2:", "expected \"float\"");
  expect_error("count.pbrt", "Camera \"perspective\" \"float fov\" [ 30 40 ]\nWorldBegin\nWorldEnd\n", "count.pbrt:1:", "takes 1 value");
  expect_error("int.pbrt", "Film \"image\" \"integer xresolution\" 10.5\nWorldBegin\nWorldEnd\n", "int.pbrt:1:", "not an integer");
  expect_error("include.pbrt", "WorldBegin\n\nInclude \"nothere.pbrt\"\nWorldEnd\n", "include.pbrt:3:", "nothere.pbrt");
  expect_error("image.pbrt", "WorldBegin\nLightSource \"infinite\" \"string mapname\" \"missing.hdr\"\nWorldEnd\n", "image.pbrt:2:", "missing.hdr");
  /* the environment's and the image textures' images are read after the parse (scene.c builds what the
   * parser described): their errors still name the included file and line of the directive */
  rt_write("light_inc.pbrt", "# the light\nLightSource \"infinite\" \"string mapname\" \"missing2.hdr\"\n");
  expect_error("incimage.pbrt", "WorldBegin\nInclude \"light_inc.pbrt\"\nShape \"sphere\"\nWorldEnd\n", "light_inc.pbrt:2:", "missing2.hdr");
  rt_write("tex_inc.pbrt", "\n\nTexture \"t\" \"spectrum\" \"imagemap\" \"string filename\" \"missing3.png\"\n");
  expect_error("inctex.pbrt", "WorldBegin\nInclude \"tex_inc.pbrt\"\nWorldEnd\n", "tex_inc.pbrt:3:", "missing3.png");
  expect_error("res.pbrt", "Film \"image\" \"integer xresolution\" 1000000000\nWorldBegin\nWorldEnd\n", "res.pbrt:1:", "out of range");
  expect_error("spp.pbrt", "Sampler \"halton\" \"integer pixelsamples\" -4\nWorldBegin\nWorldEnd\n", "spp.pbrt:1:", "out of range");
  expect_error("nan.pbrt", "WorldBegin\nTranslate 1 nan 2\nWorldEnd\n", "nan.pbrt:2:", "expected a number");
  expect_error("inf.pbrt", "WorldBegin\nTranslate 1 1e999 2\nWorldEnd\n", "inf.pbrt:2:", "not finite");
  expect_error("idx.pbrt", "WorldBegin\nShape \"trianglemesh\" \"integer indices\" [ 0 1 5 ] \"point P\" [ 0 0 0 1 0 0 0 1 0 ]\nWorldEnd\n",
               "idx.pbrt:2:", "out of range");
  expect_error("pts.pbrt", "WorldBegin\nShape \"trianglemesh\" \"integer indices\" [ 0 1 2 ] \"point P\" [ 0 0 0 1 0 0 0 1 ]\nWorldEnd\n",
               "pts.pbrt:2:", "multiple of 3");
  rt_write("bad.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                      "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n");
  expect_error("ply.pbrt", "WorldBegin\nShape \"plymesh\" \"string filename\" \"bad.ply\"\nWorldEnd\n", "ply.pbrt:2:", "truncated");
  rt_write("huge.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 200000000\nproperty float x\nproperty float y\n"
                       "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n");
  expect_error("hugeply.pbrt", "WorldBegin\nShape \"plymesh\" \"string filename\" \"huge.ply\"\nWorldEnd\n", "hugeply.pbrt:2:", "truncated");
  rt_write("loop.pbrt", "Include \"loop.pbrt\"\n");
  expect_error("rec.pbrt", "Include \"loop.pbrt\"\nWorldBegin\nWorldEnd\n", ":1:", "nested");
  expect_error("scale.pbrt", "WorldBegin\nScale 1 0 1\nWorldEnd\n", "scale.pbrt:2:", "singular");
  expect_error("after.pbrt", "WorldBegin\nWorldEnd\nShape \"sphere\"\n", "after.pbrt:3:", "after WorldEnd");
  expect_error("lightscale.pbrt", "WorldBegin\nScale 1 2 1\nLightSource \"infinite\"\nWorldEnd\n", "lightscale.pbrt:3:", "rotation");
  {
    char err[512];
    elr_scene *s = rt_load("lightuni.pbrt", "WorldBegin\nScale 3 3 3\nRotate 90 1 0 0\nLightSource \"infinite\"\nWorldEnd\n", err, sizeof err);
    rt_check(s != NULL, "a uniform Scale before LightSource \"infinite\" is divided out (pbrt-v3 normalises the direction)%s%s", s ? "" : ": ", s ? "" : err);
    elr_scene_free(s);
  }
  expect_error("str.pbrt", "WorldBegin\n\"float radius\" 1\nWorldEnd\n", "str.pbrt:2:", "expected a directive");
  /* fuzzing: world coordinates Embree cannot trace (it asserts on a ray origin beyond 1.8e18: LookAt
   * 0 1e300 0 crashed the render) and transformations that overflow are refused where they are made */
  expect_error("lookat.pbrt", "LookAt 0 1e300 -4.5  0 0.7 0  0 1 0\nWorldBegin\nWorldEnd\n", "lookat.pbrt:1:", "outside");
  expect_error("campos.pbrt", "Translate 0 0 1e20\nCamera \"perspective\"\nWorldBegin\nWorldEnd\n", "campos.pbrt:2:", "camera position");
  expect_error("tiny.pbrt", "WorldBegin\nScale 1e-200 1e-200 1e-200\nScale 1e-200 1e-200 1e-200\nWorldEnd\n", "tiny.pbrt:2:", "overflows");
  expect_error("farsph.pbrt", "WorldBegin\nTranslate 1e20 0 0\nShape \"sphere\"\nWorldEnd\n", "farsph.pbrt:3:", "centre");
  expect_error("bigsph.pbrt", "WorldBegin\nShape \"sphere\" \"float radius\" 1e19\nWorldEnd\n", "bigsph.pbrt:2:", "radius");
  expect_error("farpt.pbrt", "WorldBegin\nLightSource \"point\" \"point from\" [ 0 1e30 0 ]\nWorldEnd\n", "farpt.pbrt:2:", "position");
  /* fuzzing: unclear errors and silently black images */
  expect_error("incdir.pbrt", "WorldBegin\nInclude \".\"\nWorldEnd\n", "incdir.pbrt:2:", "Is a directory");
  expect_error("incempty.pbrt", "WorldBegin\nInclude \"\"\nWorldEnd\n", "incempty.pbrt:2:", "Is a directory");
  expect_error("bsnl.pbrt", "Film \"image\" \"string filename\" \"a\\\nb.png\"\nWorldBegin\nWorldEnd\n", "bsnl.pbrt:1:", "newline inside quotes");
  expect_error("pthuge.pbrt", "WorldBegin\nLightSource \"point\" \"rgb I\" [ 3e38 1 1 ] \"rgb scale\" [ 10 1 1 ]\nWorldEnd\n", "pthuge.pbrt:2:", "overflows");
  expect_error("dsthuge.pbrt", "WorldBegin\nLightSource \"distant\" \"rgb L\" [ 1 3e38 1 ] \"rgb scale\" [ 1 10 1 ]\nWorldEnd\n", "dsthuge.pbrt:2:", "overflows");
  expect_error("gauss.pbrt", "PixelFilter \"gaussian\" \"float alpha\" 1e38\nWorldBegin\nWorldEnd\n", "gauss.pbrt:1:", "\"alpha\" = 1e+38 is out of range");
  expect_error("mitch.pbrt", "PixelFilter \"mitchell\" \"float C\" -1e38\nWorldBegin\nWorldEnd\n", "mitch.pbrt:1:", "\"C\" = -1e+38 is out of range");
  expect_error("sinc.pbrt", "PixelFilter \"sinc\" \"float tau\" 1e-38\nWorldBegin\nWorldEnd\n", "sinc.pbrt:1:", "\"tau\" = 1e-38 is out of range");
  { /* range limits are inclusive also for values stored as floats (0.01f < 0.01, 179.99f > 179.99) */
    char err[512];
    elr_scene *s = rt_load("edges.pbrt", "Camera \"perspective\" \"float fov\" 179.99 \"float frameaspectratio\" 1e-6\n"
                                         "PixelFilter \"sinc\" \"float tau\" 0.01\nWorldBegin\nShape \"sphere\" \"float radius\" 1e-20\nWorldEnd\n",
                           err, sizeof err);
    rt_check(s != NULL, "fov 179.99, frameaspectratio 1e-6, tau 0.01, radius 1e-20 (the range limits) load%s%s", s ? "" : ": ", s ? "" : err);
    elr_scene_free(s);
  }
  expect_error("strat.pbrt", "Sampler \"stratified\" \"integer xsamples\" 4096 \"integer ysamples\" 4096 \"integer dimensions\" 64\n"
               "WorldBegin\nWorldEnd\n", "strat.pbrt:1:", "MiB per thread");
  { /* the same limit for a sample count given to the render (render --spp): an error, not 12.5 GiB per thread */
    char err[512];
    elr_scene *s = rt_load("strat_spp.pbrt", "Sampler \"stratified\" \"integer xsamples\" 2 \"integer ysamples\" 2 \"integer dimensions\" 64\n"
                                             "WorldBegin\nWorldEnd\n", err, sizeof err);
    elr_render_options o;
    elr_image img;
    int rc = -1;
    err[0] = 0;
    elr_render_options_default(&o);
    o.spp = 16777216; o.quiet = 1; o.nthreads = 1;
    if (s) rc = elr_render(s, &o, &img, NULL, err, sizeof err);
    rt_check(s && rc != 0 && strstr(err, "MiB per thread") != NULL,
             "stratified, 64 dimensions, render spp 16777216: refused before allocating (%s)", err);
    if (s && rc == 0) elr_image_free(&img);
    elr_scene_free(s);
  }
  expect_error("negpoint.pbrt", "WorldBegin\nLightSource \"point\" \"rgb I\" [ -1 -1 -1 ]\nWorldEnd\n", "negpoint.pbrt:2:", "must not be negative");
  expect_error("negdist.pbrt", "WorldBegin\nLightSource \"distant\" \"rgb L\" [ 1 1 1 ] \"float scale\" -2\nWorldEnd\n", "negdist.pbrt:2:",
               "must not be negative");
  expect_error("bigidx.pbrt", "WorldBegin\nShape \"trianglemesh\" \"integer indices\" [ 0 1 4294967296 ] \"point P\" [ 0 0 0 1 0 0 0 1 0 ]\nWorldEnd\n",
               "bigidx.pbrt:2:", "4294967296 is outside the 32-bit integer range");
  /* maxanisotropy above mipmap.h's 1024 failed with the library's generic 'invalid argument (NULL pointer,
   * non-positive size, or value out of range)' */
  {
    float one[3] = {1, 1, 1};
    char e[256];
    if (el_image_write_pfm(rt_path("one.pfm"), one, 1, 1, 3, e, sizeof e) != 0) printf("cannot write one.pfm: %s\n", e);
  }
  expect_error("aniso.pbrt", W("Texture \"t\" \"spectrum\" \"imagemap\" \"string filename\" \"one.pfm\" \"float maxanisotropy\" 1e6\n"),
               "aniso.pbrt:3:", "\"maxanisotropy\" = 1e+06 is out of range [1, 1024]");
  expect_error("envsampling.pbrt", W("LightSource \"infinite\" \"string sampling\" \"cosine\"\n"), "envsampling.pbrt:3:",
               "sampling must be \"product\" or \"map\"");
  { /* the infinite light's "sampling": product by default, "map" for pbrt-v3's (the map alone) */
    char err[512];
    elr_scene *a = rt_load("envs1.pbrt", W("LightSource \"infinite\"\n"), err, sizeof err);
    elr_scene *b = rt_load("envs2.pbrt", W("LightSource \"infinite\" \"string sampling\" \"map\"\n"), err, sizeof err);
    rt_check(a && b && a->nlight == 1 && b->nlight == 1 && a->light[0].sampling == ELR_ENVLS_PRODUCT && b->light[0].sampling == ELR_ENVLS_MAP,
             "LightSource \"infinite\": \"string sampling\" product by default, \"map\" read");
    elr_scene_free(a);
    elr_scene_free(b);
  }
  expect_error("envneg.pbrt", W("LightSource \"infinite\" \"rgb L\" [ 1 -1 1 ]\n"), "envneg.pbrt:3:", "L times scale (1 -1 1) must be finite and not negative");
  expect_error("envinf.pbrt", W("LightSource \"infinite\" \"rgb L\" [ 1e38 1 1 ] \"rgb scale\" [ 10 1 1 ]\n"), "envinf.pbrt:3:", "must be finite");
  expect_error("crop.pbrt", "Film \"image\" \"integer xresolution\" 8 \"float cropwindow\" [ 0.51 0.55 0 1 ]\nWorldBegin\nWorldEnd\n",
               "crop.pbrt:1:", "covers no pixel of the 8 x 720 film");
  { /* checkerboards of checkerboards: each level doubles the lookups (26 levels took 36 s for 8x8
     * pixels) and recurses on the render thread's stack (200000 levels crashed it) */
    char buf[8192];
    size_t n = 0;
    int i;
    n += (size_t)snprintf(buf + n, sizeof buf - n, "WorldBegin\nTexture \"t0\" \"spectrum\" \"checkerboard\"\n");
    for (i = 1; i < 8; i++)
      n += (size_t)snprintf(buf + n, sizeof buf - n, "Texture \"t%d\" \"spectrum\" \"checkerboard\" \"texture tex1\" \"t%d\" \"texture tex2\" \"t%d\"\n",
                            i, i - 1, i - 1);
    snprintf(buf + n, sizeof buf - n, "WorldEnd\n");
    expect_error("chain.pbrt", buf, "chain.pbrt:8:", "nested too deeply (128 texture lookups per evaluation, at most 64)");
    n = 0;
    n += (size_t)snprintf(buf + n, sizeof buf - n, "WorldBegin\nTexture \"t0\" \"spectrum\" \"checkerboard\"\n");
    for (i = 1; i < 100; i++)
      n += (size_t)snprintf(buf + n, sizeof buf - n, "Texture \"t%d\" \"spectrum\" \"checkerboard\" \"texture tex1\" \"t%d\"\n", i, i - 1);
    snprintf(buf + n, sizeof buf - n, "WorldEnd\n");
    expect_error("deepchain.pbrt", buf, "deepchain.pbrt:", "nested too deeply");
  }
  { /* named textures, materials and coordinate systems through the hash index: shadowing, scopes, and
     * many names (100000 named textures took 25 s to parse with linear lookups) */
    char err[512];
    elr_scene *s = rt_load("names.pbrt",
                           "WorldBegin\nTexture \"a\" \"spectrum\" \"constant\" \"rgb value\" [ 1 0 0 ]\n"
                           "AttributeBegin\n Texture \"a\" \"spectrum\" \"constant\" \"rgb value\" [ 0 1 0 ]\n"
                           " Material \"matte\" \"texture Kd\" \"a\"\nAttributeEnd\n"  /* mat 1: green */
                           "Material \"matte\" \"texture Kd\" \"a\"\n"                     /* mat 2: red */
                           "AttributeBegin\n Texture \"b\" \"spectrum\" \"constant\" \"rgb value\" [ 0 0 1 ]\nAttributeEnd\n"
                           "Material \"matte\" \"texture Kd\" \"a\"\n"                     /* mat 3: red */
                           "Texture \"a\" \"spectrum\" \"constant\" \"rgb value\" [ 1 1 0 ]\n"
                           "Material \"matte\" \"texture Kd\" \"a\"\n"                     /* mat 4: yellow */
                           "Material \"matte\" \"texture Kd\" \"b\"\n"                     /* mat 5: b out of scope */
                           "MakeNamedMaterial \"m\" \"string type\" \"mirror\"\nMakeNamedMaterial \"m\" \"string type\" \"plastic\"\n"
                           "NamedMaterial \"m\"\nShape \"sphere\"\n"
                           "Translate 1 0 0\nCoordinateSystem \"c\"\nTranslate 1 0 0\nCoordinateSystem \"c\"\nIdentity\nCoordSysTransform \"c\"\n"
                           "LightSource \"point\"\nWorldEnd\n",
                           err, sizeof err);
    if (!s) rt_check(0, "names scene: %s", err);
    else {
      rt_check(s->nmat >= 8 && near3(s->tex[s->mat[1].kd].value, 0, 1, 0, 1e-6f) && near3(s->tex[s->mat[2].kd].value, 1, 0, 0, 1e-6f) &&
                   near3(s->tex[s->mat[3].kd].value, 1, 0, 0, 1e-6f) && near3(s->tex[s->mat[4].kd].value, 1, 1, 0, 1e-6f) &&
                   near3(s->tex[s->mat[5].kd].value, .5f, .5f, .5f, 1e-6f),
               "named textures: an inner scope shadows, a closed scope's names are gone, a redefinition wins");
      rt_check(s->nsph == 1 && s->mat[s->sph[0].material].kind == ELR_MAT_PLASTIC, "MakeNamedMaterial redefined: the latest wins");
      rt_check(s->nlight == 1 && near3(s->light[0].pos, 2, 0, 0, 1e-6f), "CoordinateSystem redefined: the latest wins");
      elr_scene_free(s);
    }
  }
  {
    char *buf = (char *)malloc(4 << 20), err[512];
    size_t n = 0;
    int i;
    elr_scene *s = NULL;
    double t0 = elr_now();
    n += (size_t)snprintf(buf + n, (4u << 20) - n, "WorldBegin\nTexture \"t0\" \"spectrum\" \"constant\"\n");
    for (i = 1; i < 50000; i++)
      n += (size_t)snprintf(buf + n, (4u << 20) - n, "Texture \"t%d\" \"spectrum\" \"checkerboard\" \"texture tex1\" \"t0\"\n", i);
    snprintf(buf + n, (4u << 20) - n, "WorldEnd\n");
    i = elr_scene_load_string(buf, "many.pbrt", rt_dir, &s, 1, err, sizeof err);
    rt_check(i == 0 && elr_now() - t0 < 5.0, "50000 named textures parse in %.2f s (under 5 s)", elr_now() - t0);
    elr_scene_free(s);
    free(buf);
  }
  { /* a NaN or infinite texel became 0 silently (the project rule asks for an error) */
    float px[6] = {1, 1, 1, 1, 1, 1};
    char e[256];
    px[4] = NAN;
    if (el_image_write_pfm(rt_path("nan.pfm"), px, 2, 1, 3, e, sizeof e) != 0) printf("cannot write nan.pfm: %s\n", e);
    px[4] = INFINITY;
    if (el_image_write_pfm(rt_path("inf.pfm"), px, 2, 1, 3, e, sizeof e) != 0) printf("cannot write inf.pfm: %s\n", e);
    px[4] = 3e38f;
    if (el_image_write_pfm(rt_path("big.pfm"), px, 2, 1, 3, e, sizeof e) != 0) printf("cannot write big.pfm: %s\n", e);
    expect_error("nantex.pbrt", W("Texture \"t\" \"spectrum\" \"imagemap\" \"string filename\" \"nan.pfm\"\n"), "nantex.pbrt:3:",
                 "nan.pfm\": texel (1, 0) is NaN");
    expect_error("nanenv.pbrt", W("LightSource \"infinite\" \"string mapname\" \"nan.pfm\"\n"), "nanenv.pbrt:3:", "texel (1, 0) is NaN");
    expect_error("infenv.pbrt", W("LightSource \"infinite\" \"string mapname\" \"inf.pfm\"\n"), "infenv.pbrt:3:", "texel (1, 0) is infinite");
    expect_error("bigtex.pbrt", W("Texture \"t\" \"float\" \"imagemap\" \"string filename\" \"big.pfm\" \"float scale\" 10\n"), "bigtex.pbrt:3:",
                 "texel (1, 0) times scale 10 overflows");
  }
  /* an error or warning in the last directive of an included file named the includer (with the included
   * file's line): the lexer had already left the included file when it peeked for more parameters */
  rt_write("inc_last.pbrt", "# included\n\n\nShape \"trianglemesh\" \"point P\" [ 0 0 0 1 0 0 ]\n");
  expect_error("incl.pbrt", "WorldBegin\nInclude \"inc_last.pbrt\"\nWorldEnd\n", "inc_last.pbrt:4:", "\"integer indices\" is required");
  rt_write("inc_last2.pbrt", "# included\nLightSource \"point\" \"rgb I\" [ 1 1 ]\n");
  expect_error("incl2.pbrt", "WorldBegin\nInclude \"inc_last2.pbrt\"\nWorldEnd\n", "inc_last2.pbrt:2:", "takes 3 values, got 2");
  rt_write("inc_last3.pbrt", "# included\nTexture \"t\" \"color\" \"imagemap\" \"string filename\" \"nothere.png\"\n");
  expect_error("incl3.pbrt", "WorldBegin\nInclude \"inc_last3.pbrt\"\nWorldEnd\n", "inc_last3.pbrt:2:", "nothere.png");
  {
    char err[512];
    elr_scene *s;
    rt_write("inc_last4.pbrt", "# included\n\nMaterial \"hair\"\n");
    s = rt_load("incl4.pbrt", "WorldBegin\nLightSource \"point\"\nInclude \"inc_last4.pbrt\"\nWorldEnd\n", err, sizeof err); /* (a light: no \"nothing emits\" warning) */
    rt_check(s && strstr(elr_scene_last_warning(s), "inc_last4.pbrt:3: warning") != NULL,
             "a warning in an included file's last directive names that file: \"%s\"", s ? elr_scene_last_warning(s) : err);
    elr_scene_free(s);
  }
  /* fuzzing: PLY values the range checks did not see (NaN compares false): a NaN vertex index was
   * converted to unsigned (undefined), a NaN list count gave "no triangles", a list-valued x was never
   * read (an uninitialised coordinate) */
  {
    const char *hdr = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                      "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 1\n1 0 1\n0 1 1\n";
    char buf[512];
    snprintf(buf, sizeof buf, "%s3 0 1 nan\n", hdr); rt_write("nanidx.ply", buf);
    snprintf(buf, sizeof buf, "%s3 0 1 1.5\n", hdr); rt_write("fracidx.ply", buf);
    snprintf(buf, sizeof buf, "%snan 0 1 2\n", hdr); rt_write("nancnt.ply", buf);
    rt_write("listx.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty list uchar float x\nproperty float y\nproperty float z\n"
                          "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 1\n0 0 1\n0 1 1\n3 0 1 2\n");
    expect_error("nanidx.pbrt", W("Shape \"plymesh\" \"string filename\" \"nanidx.ply\"\n"), "nanidx.pbrt:3:", "vertex index nan");
    expect_error("fracidx.pbrt", W("Shape \"plymesh\" \"string filename\" \"fracidx.ply\"\n"), "fracidx.pbrt:3:", "vertex index 1.5");
    expect_error("nancnt.pbrt", W("Shape \"plymesh\" \"string filename\" \"nancnt.ply\"\n"), "nancnt.pbrt:3:", "list of nan entries");
    expect_error("listx.pbrt", W("Shape \"plymesh\" \"string filename\" \"listx.ply\"\n"), "listx.pbrt:3:", "\"x\" is a list");
  }
  expect_error("farmesh.pbrt", "WorldBegin\nShape \"trianglemesh\" \"point P\" [ 0 0 0 1e20 0 0 0 1 0 ]\nWorldEnd\n", "farmesh.pbrt:2:", "outside");
}

/* Every prefix of a file that uses most directives (truncated at every byte) must load or fail with a
 * "file:line: error" message; never crash (the suite also runs under AddressSanitizer). Only the whole
 * file, and prefixes that end after WorldEnd, load. */
static void truncations(void) {
  const char *full =
      "# every directive\nLookAt 0 1 -4  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [ 45 ]\n"
      "Film \"image\" \"integer xresolution\" [ 8 ] \"integer yresolution\" 8 \"string filename\" \"t.png\"\n"
      "PixelFilter \"gaussian\" \"float alpha\" 2\nSampler \"halton\" \"integer pixelsamples\" 4\n"
      "Integrator \"path\" \"integer maxdepth\" 3\nWorldBegin\nAttributeBegin\n  Rotate -90 1 0 0\n"
      "  LightSource \"infinite\" \"rgb L\" [ 1 1 1 ]\nAttributeEnd\nTransformBegin\n  Translate 0 1 0\n  Scale 1 1 1\n"
      "  CoordinateSystem \"a\"\nTransformEnd\nCoordSysTransform \"a\"\n"
      "Texture \"c\" \"spectrum\" \"checkerboard\" \"rgb tex1\" [ 1 0 0 ]\nMaterial \"plastic\" \"texture Kd\" \"c\"\n"
      "Shape \"sphere\" \"float radius\" 0.5\nIdentity\nConcatTransform [ 1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1 ]\n"
      "Material \"matte\"\nShape \"trianglemesh\" \"integer indices\" [ 0 1 2 ] \"point P\" [ 0 0 0 1 0 0 0 0 1 ]\n"
      "WorldEnd\n";
  size_t n = strlen(full), k;
  int loaded = 0, errors = 0, bad = 0;
  char err[512];
  for (k = 0; k <= n; k++) {
    char *pre = (char *)malloc(k + 1);
    elr_scene *s = NULL;
    memcpy(pre, full, k); pre[k] = 0;
    if (elr_scene_load_string(pre, "trunc.pbrt", rt_dir, &s, 1, err, sizeof err) == 0) { loaded++; elr_scene_free(s); }
    else if (strstr(err, "trunc.pbrt:") && strstr(err, "error")) errors++;
    else { bad++; if (bad < 3) printf("      prefix %zu: unexpected message \"%s\"\n", k, err); }
    free(pre);
  }
  rt_check(bad == 0 && loaded >= 1 && loaded <= 2 && loaded + errors == (int)n + 1,
           "all %zu prefixes of a %zu-byte file: %d load (the whole file), %d fail with file:line errors", n + 1, n, loaded, errors);
}

/* the start of a file of the test directory as a string ("" when it cannot be read) */
static void read_text(const char *file, char *buf, size_t cap) {
  FILE *f = fopen(rt_path(file), "rb");
  size_t n = f ? fread(buf, 1, cap - 1, f) : 0;
  buf[n] = 0;
  if (f) fclose(f);
}

/* The program: exit codes, no output on error, the Film's filename by default, the output formats. */
static void cli(void) {
  char cmd[1024];
  const char *bin = EL_RENDER_BIN;
  int r;
  FILE *f;
  rt_write("ok.pbrt", "Film \"image\" \"integer xresolution\" 8 \"integer yresolution\" 6 \"string filename\" \"film_default.pfm\"\n"
                      "Sampler \"random\" \"integer pixelsamples\" 2\nWorldBegin\nLightSource \"infinite\"\nShape \"sphere\"\nWorldEnd\n");
  snprintf(cmd, sizeof cmd, "cd '%s' && '%s' ok.pbrt --quiet 2>/dev/null", rt_dir, bin);
  r = system(cmd);
  f = fopen(rt_path("film_default.pfm"), "rb");
  rt_check(r == 0 && f != NULL, "render ok.pbrt: exit 0, writes the Film's filename (film_default.pfm)");
  if (f) fclose(f);
  {
    const char *exts[4] = {"png", "exr", "pfm", "hdr"};
    int k;
    for (k = 0; k < 4; k++) {
      el_image img;
      char e[256], out[64];
      snprintf(out, sizeof out, "o.%s", exts[k]);
      snprintf(cmd, sizeof cmd, "'%s' '%s' --outfile '%s' --spp 1 --nthreads 1 --seed 5 --quiet 2>/dev/null", bin, rt_path("ok.pbrt"), rt_path(out));
      r = system(cmd);
      rt_check(r == 0 && el_image_load(rt_path(out), &img, e, sizeof e) == 0 && img.width == 8 && img.height == 6,
               "--outfile %s: exit 0 and an 8 x 6 image", out);
      if (r == 0) el_image_free(&img);
    }
  }
  snprintf(cmd, sizeof cmd, "'%s' '%s' --outfile '%s' --quiet 2>/dev/null", bin, rt_path("unknown.pbrt"), rt_path("never.png"));
  r = system(cmd);
  f = fopen(rt_path("never.png"), "rb");
  rt_check(r != 0 && WEXITSTATUS(r) == 1 && f == NULL, "render on a bad file: exit 1, no image written");
  if (f) fclose(f);
  snprintf(cmd, sizeof cmd, "'%s' '%s' --spp -3 --quiet 2>/dev/null", bin, rt_path("ok.pbrt"));
  r = system(cmd);
  rt_check(WEXITSTATUS(r) == 1, "render --spp -3: exit 1");
  snprintf(cmd, sizeof cmd, "'%s' '%s' --outfile '%s' --quiet 2>/dev/null", bin, rt_path("ok.pbrt"), rt_path("x.bmp"));
  r = system(cmd);
  rt_check(WEXITSTATUS(r) == 1, "render --outfile x.bmp (unknown format): exit 1");
  /* the batched loop was folded into the wave loop: its option is refused with a message naming the two loops */
  snprintf(cmd, sizeof cmd, "'%s' '%s' --outfile '%s' --loop batched --quiet 2>'%s'", bin, rt_path("ok.pbrt"), rt_path("batched.pfm"),
           rt_path("batched.txt"));
  r = system(cmd);
  {
    char log[1024];
    read_text("batched.txt", log, sizeof log);
    f = fopen(rt_path("batched.pfm"), "rb");
    rt_check(WEXITSTATUS(r) == 1 && f == NULL && strstr(log, "--loop wave") && strstr(log, "--loop one"),
             "render --loop batched: exit 1, no image, the message names --loop wave and --loop one (%s)", log);
    if (f) fclose(f);
  }
  snprintf(cmd, sizeof cmd, "'%s' '%s' --outfile '%s' --spp 1 --stats 2>'%s'", bin, rt_path("ok.pbrt"), rt_path("s.png"), rt_path("log.txt"));
  r = system(cmd);
  {
    char log[8192];
    read_text("log.txt", log, sizeof log);
    rt_check(r == 0 && strstr(log, "elapsed") && strstr(log, "remaining") && strstr(log, "samples/s") && strstr(log, "rays/s") &&
                 strstr(log, "env distribution") && !strstr(log, "warning"),
             "progress bar (elapsed, remaining), --stats, closing line with samples/s and rays/s; no warning");
  }
  /* samples the film rejects (here light-sampled radiance overflowing a float: 3e38 x 4 cos, from the
   * map alone's uniform sphere; product sampling's cosine sampling would give 3e38 exactly) are said,
   * even with --quiet: the image lacks them */
  rt_write("hot.pbrt", "LookAt 0 0 -5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 30\n"
                       "Film \"image\" \"integer xresolution\" 8 \"integer yresolution\" 6\nSampler \"random\" \"integer pixelsamples\" 2\n"
                       "Integrator \"directlighting\"\nWorldBegin\nLightSource \"infinite\" \"rgb L\" [ 3e38 3e38 3e38 ]\n"
                       "Material \"matte\" \"rgb Kd\" [ 1 1 1 ]\nShape \"sphere\"\nWorldEnd\n");
  snprintf(cmd, sizeof cmd, "'%s' '%s' --outfile '%s' --light-sampling light --env-sampling map --quiet 2>'%s'", bin, rt_path("hot.pbrt"), rt_path("hot.pfm"),
           rt_path("hot.txt"));
  r = system(cmd);
  {
    char log[4096];
    read_text("hot.txt", log, sizeof log);
    rt_check(r == 0 && strstr(log, "warning:") && strstr(log, "samples rejected"), "rejected samples: render warns (%s)", log);
  }
}

int main(void) {
  rt_mkdir("test_render_parser");
  defaults();
  options();
  transforms_and_shapes();
  sphere_hits(0);
  sphere_hits(1);
  unsetenv("ELR_EMBREE_SPHERES");
  materials_textures();
  ply_big_endian();
  ply_headers();
  warnings();
  errors();
  truncations();
  fifos();
  cli();
  return rt_finish("test_render_parser");
}
