/* test_render_format: the parts of the pbrt-v3 format that issue 16 adds to the parser (api.c,
 * api_options.c, api_materials.c, textures.c), each against an answer worked out by hand:
 *   - Texture "scale" (tex1 * tex2) and "mix" ((1 - amount) tex1 + amount tex2), float and spectrum:
 *     of constants they are constants of the hand-computed value; of checkerboards, looked up at a (u, v)
 *     in each check, the product and the blend of that check's colours;
 *   - integrators the renderer does not have fall back to "path" with a warning naming them and keep
 *     their maxdepth (pbrt-v3's default 5 when not given); Accelerator lines are accepted silently;
 *   - unsupported features say so once per directive or type (5 media lines, 3 curves and 4 cylinders:
 *     3 warnings), and `render` still writes the picture (exit code 0);
 *   - ActiveTransform EndTime: the transformations that follow move only the end time, which is not
 *     rendered (a sphere stays where the start time has it);
 *   - MakeNamedMaterial / NamedMaterial with the new materials, and pbrt-v3's scoping of named
 *     materials by AttributeBegin / AttributeEnd;
 *   - ReverseOrientation and mirroring transforms turn the side glass calls outside (pbrt-v3:
 *     reverseOrientation xor transformSwapsHandedness, also for meshes with normals, as pbrt-v3's
 *     SetShadingGeometry; the hit record's normals and glass's frame follow);
 *   - a glass index outside (0, 1000] is an error naming file:line. */
#include "render_test_util.h"

static elr_scene *world(const char *name, const char *body, char *err, size_t errlen) {
  char buf[8192];
  /* a point light first (the line numbers below count it), so that no "nothing emits" warning is added */
  snprintf(buf, sizeof buf, "WorldBegin\n%s\n%s\nWorldEnd\n", strstr(body, "LightSource") ? "" : "LightSource \"point\"", body);
  return rt_load(name, buf, err, errlen);
}

static void textures(void) {
  char err[512];
  elr_scene *s = world("tex.pbrt",
                       "Texture \"a\" \"spectrum\" \"constant\" \"rgb value\" [ 0.5 0.25 2 ]\n"
                       "Texture \"b\" \"spectrum\" \"scale\" \"texture tex1\" \"a\" \"rgb tex2\" [ 0.4 2 0.1 ]\n"
                       "Texture \"m\" \"spectrum\" \"mix\" \"texture tex1\" \"a\" \"rgb tex2\" [ 1 0 0 ] \"float amount\" 0.25\n"
                       "Texture \"f\" \"float\" \"scale\" \"float tex1\" 0.5 \"float tex2\" 0.3\n"
                       "Texture \"g\" \"float\" \"mix\" \"float amount\" 0.75\n"
                       "Material \"plastic\" \"texture Kd\" \"b\" \"texture Ks\" \"m\" \"texture roughness\" \"f\"\n"
                       "Material \"matte\" \"texture Kd\" \"g\"\n",
                       err, sizeof err);
  if (!s) { rt_check(0, "texture scene: %s", err); return; }
  {
    const elr_material *p = &s->mat[s->nmat - 2], *q = &s->mat[s->nmat - 1];
    const elr_texture *b = &s->tex[p->kd], *m = &s->tex[p->ks], *f = &s->tex[p->rough], *g = &s->tex[q->kd];
    rt_check(b->kind == ELR_TEX_CONST && fabsf(b->value.x - 0.2f) < 1e-7f && fabsf(b->value.y - 0.5f) < 1e-7f && fabsf(b->value.z - 0.2f) < 1e-7f,
             "scale of constants (0.5 0.25 2) * (0.4 2 0.1) = (0.2 0.5 0.2): a constant (%g %g %g)", b->value.x, b->value.y, b->value.z);
    rt_check(m->kind == ELR_TEX_CONST && fabsf(m->value.x - 0.625f) < 1e-7f && fabsf(m->value.y - 0.1875f) < 1e-7f && fabsf(m->value.z - 1.5f) < 1e-7f,
             "mix 0.25 of (0.5 0.25 2) and (1 0 0) = (0.625 0.1875 1.5) (%g %g %g)", m->value.x, m->value.y, m->value.z);
    rt_check(f->kind == ELR_TEX_CONST && fabsf(f->value.x - 0.15f) < 1e-7f, "float scale 0.5 * 0.3 = 0.15 (%g)", f->value.x);
    rt_check(g->kind == ELR_TEX_CONST && fabsf(g->value.x - 0.75f) < 1e-7f, "float mix of pbrt-v3's defaults (0 and 1) by 0.75 = 0.75 (%g)", g->value.x);
  }
  elr_scene_free(s);
  /* of checkerboards: checks of 0.5 x 0.5 in (u, v), (0.2 0.4 0.6) / (1 1 1) and, as amount, 0.1 / 0.9 */
  s = world("tex2.pbrt",
            "Texture \"c\" \"spectrum\" \"checkerboard\" \"float uscale\" 2 \"float vscale\" 2 \"rgb tex1\" [ 0.2 0.4 0.6 ] \"rgb tex2\" [ 1 1 1 ]\n"
            "Texture \"k\" \"float\" \"checkerboard\" \"float uscale\" 2 \"float vscale\" 2 \"float tex1\" 0.1 \"float tex2\" 0.9\n"
            "Texture \"s\" \"spectrum\" \"scale\" \"texture tex1\" \"c\" \"rgb tex2\" [ 2 3 4 ]\n"
            "Texture \"x\" \"spectrum\" \"mix\" \"rgb tex1\" [ 0 0 1 ] \"texture tex2\" \"c\" \"texture amount\" \"k\"\n"
            "Material \"plastic\" \"texture Kd\" \"s\" \"texture Ks\" \"x\"\n",
            err, sizeof err);
  if (!s) { rt_check(0, "texture scene 2: %s", err); return; }
  {
    const elr_material *p = &s->mat[s->nmat - 1];
    elr_tex_ctx c;
    elr_v3 v00, v10, x00, x10;
    memset(&c, 0, sizeof c);
    c.u = 0.25f; c.v = 0.25f; /* check (0, 0): tex1, amount 0.1 */
    v00 = elr_tex_eval(s, p->kd, &c); x00 = elr_tex_eval(s, p->ks, &c);
    c.u = 0.75f; /* check (1, 0): tex2, amount 0.9 */
    v10 = elr_tex_eval(s, p->kd, &c); x10 = elr_tex_eval(s, p->ks, &c);
    rt_check(s->tex[p->kd].kind == ELR_TEX_SCALE && fabsf(v00.x - 0.4f) < 1e-6f && fabsf(v00.y - 1.2f) < 1e-6f && fabsf(v00.z - 2.4f) < 1e-6f &&
             fabsf(v10.x - 2.f) < 1e-6f && fabsf(v10.y - 3.f) < 1e-6f && fabsf(v10.z - 4.f) < 1e-6f,
             "scale of a checkerboard by (2 3 4): (0.4 1.2 2.4) in the first check, (2 3 4) in the second (%g %g %g / %g %g %g)", v00.x, v00.y, v00.z,
             v10.x, v10.y, v10.z);
    rt_check(s->tex[p->ks].kind == ELR_TEX_MIX && fabsf(x00.x - 0.02f) < 1e-6f && fabsf(x00.y - 0.04f) < 1e-6f && fabsf(x00.z - 0.96f) < 1e-6f &&
             fabsf(x10.x - 0.9f) < 1e-6f && fabsf(x10.y - 0.9f) < 1e-6f && fabsf(x10.z - 1.f) < 1e-6f,
             "mix by a float checkerboard: 0.9 (0 0 1) + 0.1 (0.2 0.4 0.6) = (0.02 0.04 0.96), 0.1 (0 0 1) + 0.9 (1 1 1) = (0.9 0.9 1) "
             "(%g %g %g / %g %g %g)", x00.x, x00.y, x00.z, x10.x, x10.y, x10.z);
  }
  elr_scene_free(s);
}

static void integrators(void) {
  static const char *names[6] = {"bdpt", "mlt", "sppm", "volpath", "ambientocclusion", "whitted"};
  int i;
  for (i = 0; i < 6; i++) {
    char buf[512], err[512];
    elr_scene *s;
    snprintf(buf, sizeof buf, "Integrator \"%s\" %s \"integer maxdepth\" %d\nWorldBegin\nLightSource \"point\"\nWorldEnd\n", names[i], i == 0 ? "\"string lightsamplestrategy\" \"power\"" : "",
             3 + i);
    s = rt_load("integ.pbrt", buf, err, sizeof err);
    rt_check(s && s->d.integrator_path && s->d.maxdepth == 3 + i && elr_scene_warnings(s) == 1 && strstr(elr_scene_last_warning(s), names[i]),
             "Integrator \"%s\": path, maxdepth %d, one warning naming it (%d: \"%s\")", names[i], 3 + i, s ? elr_scene_warnings(s) : -1,
             s ? elr_scene_last_warning(s) : err);
    elr_scene_free(s);
  }
  {
    char err[512];
    elr_scene *s = rt_load("integ2.pbrt", "Integrator \"sppm\" \"float radius\" 0.1\nWorldBegin\nLightSource \"point\"\nWorldEnd\n", err, sizeof err);
    rt_check(s && s->d.maxdepth == 5 && elr_scene_warnings(s) == 1, "without maxdepth: pbrt-v3's 5, one warning (its own parameters not reported)");
    elr_scene_free(s);
    s = rt_load("accel.pbrt", "Accelerator \"kdtree\" \"integer maxprims\" 2\nAccelerator \"bvh\" \"string splitmethod\" \"sah\"\nWorldBegin\nLightSource \"point\"\nWorldEnd\n", err,
                sizeof err);
    rt_check(s && elr_scene_warnings(s) == 0, "Accelerator lines accepted silently (%d warnings)", s ? elr_scene_warnings(s) : -1);
    elr_scene_free(s);
  }
}

static void unsupported_once(void) {
  char err[512], cmd[1024];
  int k;
  static char body[4096];
  size_t o = 0;
  elr_scene *s;
  for (k = 0; k < 5; k++) o += (size_t)snprintf(body + o, sizeof body - o, "MakeNamedMedium \"m%d\" \"string type\" \"homogeneous\"\nMediumInterface \"m%d\" \"\"\n", k, k);
  for (k = 0; k < 3; k++) o += (size_t)snprintf(body + o, sizeof body - o, "Shape \"curve\" \"point P\" [ 0 0 0 1 0 0 1 1 0 0 1 0 ]\n");
  for (k = 0; k < 4; k++) o += (size_t)snprintf(body + o, sizeof body - o, "Shape \"cylinder\" \"float radius\" 1\n");
  for (k = 0; k < 3; k++) o += (size_t)snprintf(body + o, sizeof body - o, "Shape \"sphere\" \"float foo\" 1\n");
  snprintf(body + o, sizeof body - o, "LightSource \"infinite\"\nShape \"sphere\"\n");
  s = world("once.pbrt", body, err, sizeof err);
  rt_check(s && elr_scene_warnings(s) == 4, "10 media lines, 3 curves, 4 cylinders, 3 unknown sphere parameters: 4 warnings, once each (%d)",
           s ? elr_scene_warnings(s) : -1);
  elr_scene_free(s);
  /* the program still writes the picture */
  {
    char buf[8192];
    FILE *f;
    snprintf(buf, sizeof buf, "Film \"image\" \"integer xresolution\" 8 \"integer yresolution\" 8 \"string filename\" \"%s\"\n"
             "ActiveTransform EndTime\nTranslate 1 0 0\nActiveTransform All\nTransformTimes 0 1\nWorldBegin\nLightSource \"point\"\n%sWorldEnd\n", rt_path("once.pfm"), body);
    rt_write("once2.pbrt", buf);
    snprintf(cmd, sizeof cmd, "'%s' '%s' --quiet --spp 1 2> '%s'", EL_RENDER_BIN, rt_path("once2.pbrt"), rt_path("once.log"));
    k = system(cmd);
    f = fopen(rt_path("once.pfm"), "rb");
    rt_check(k == 0 && f != NULL, "render exits 0 and writes the picture of a scene with unsupported features (exit %d)", k);
    if (f) fclose(f);
  }
  /* ActiveTransform EndTime: its transformations do not move what the start time renders */
  s = world("active.pbrt", "ActiveTransform EndTime\nTranslate 5 0 0\nActiveTransform StartTime\nTranslate 0 1 0\nActiveTransform All\nShape \"sphere\"\n", err, sizeof err);
  if (s) {
    elr_v3 c = elr_xpoint(&s->sph[0].o2w, elr_v(0, 0, 0));
    rt_check(c.x == 0.f && c.y == 1.f && c.z == 0.f && elr_scene_warnings(s) == 1,
             "ActiveTransform EndTime: Translate 5 0 0 moves only the end time; the sphere is at (0 1 0) (%g %g %g), one warning", c.x, c.y, c.z);
    elr_scene_free(s);
  } else rt_check(0, "active: %s", err);
}

static void named_materials(void) {
  char err[512];
  elr_scene *s = world("named.pbrt",
                       "MakeNamedMaterial \"g\" \"string type\" \"glass\" \"float index\" 1.33\n"
                       "AttributeBegin\n  MakeNamedMaterial \"inner\" \"string type\" \"metal\"\n  NamedMaterial \"inner\"\n  Shape \"sphere\"\nAttributeEnd\n"
                       "NamedMaterial \"g\"\nShape \"sphere\"\n"
                       "MakeNamedMaterial \"u\" \"string type\" \"uber\" \"rgb opacity\" [ 0.5 0.5 0.5 ]\nNamedMaterial \"u\"\nShape \"sphere\"\n"
                       "MakeNamedMaterial \"s\" \"string type\" \"substrate\"\nNamedMaterial \"s\"\nShape \"sphere\"\n"
                       "NamedMaterial \"inner\"\nShape \"sphere\"\n",
                       err, sizeof err);
  if (!s) { rt_check(0, "named: %s", err); return; }
  rt_check(s->nsph == 5 && s->mat[s->sph[0].material].kind == ELR_MAT_METAL && s->mat[s->sph[1].material].kind == ELR_MAT_GLASS &&
           fabsf(s->tex[s->mat[s->sph[1].material].index].value.x - 1.33f) < 1e-7f && s->mat[s->sph[2].material].kind == ELR_MAT_UBER &&
           s->mat[s->sph[3].material].kind == ELR_MAT_SUBSTRATE,
           "MakeNamedMaterial / NamedMaterial with metal, glass (index 1.33), uber, substrate");
  rt_check(s->sph[4].material == s->sph[3].material && strstr(elr_scene_last_warning(s), "\"inner\" is not defined"),
           "a named material made inside AttributeBegin/End is gone after it (pbrt-v3's graphics state): \"%s\"", elr_scene_last_warning(s));
  elr_scene_free(s);
}

static void orientation(void) {
  char err[512];
  elr_scene *s = world("orient.pbrt",
                       "Material \"glass\"\nShape \"sphere\"\n"
                       "AttributeBegin\n  ReverseOrientation\n  Shape \"sphere\"\nAttributeEnd\n"
                       "AttributeBegin\n  Scale -1 1 1\n  Shape \"sphere\"\n  ReverseOrientation\n  Shape \"sphere\"\nAttributeEnd\n"
                       "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 ] \"point P\" [ 0 0 0 1 0 0 0 1 0 ]\n"
                       "ReverseOrientation\nShape \"trianglemesh\" \"integer indices\" [ 0 1 2 ] \"point P\" [ 0 0 0 1 0 0 0 1 0 ]\n"
                       "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 ] \"point P\" [ 0 0 0 1 0 0 0 1 0 ] \"normal N\" [ 0 0 1 0 0 1 0 0 1 ]\n",
                       err, sizeof err);
  if (!s) { rt_check(0, "orientation: %s", err); return; }
  rt_check(s->sph[0].flip == 0 && s->sph[1].flip == 1 && s->sph[2].flip == 1 && s->sph[3].flip == 0 && s->mesh[0].flip == 0 && s->mesh[1].flip == 1 &&
           s->mesh[2].flip == 1,
           "normals turned by ReverseOrientation xor a mirroring transform (spheres %d %d %d %d, meshes %d %d), also for meshes with normals "
           "(pbrt-v3's SetShadingGeometry: %d)",
           s->sph[0].flip, s->sph[1].flip, s->sph[2].flip, s->sph[3].flip, s->mesh[0].flip, s->mesh[1].flip, s->mesh[2].flip);
  elr_scene_free(s);
  { /* what glass makes of it: seen from outside, a turned sphere's frame points inside (the BSDF's eta side swaps) */
    int turned;
    for (turned = 0; turned < 2; turned++) {
      elr_hit h;
      elr_bsdf b;
      elr_tex_ctx tc;
      memset(&tc, 0, sizeof tc);
      s = world("orient_glass.pbrt", turned ? "Material \"glass\"\nReverseOrientation\nShape \"sphere\"\n" : "Material \"glass\"\nShape \"sphere\"\n", err,
                sizeof err);
      if (!s) { rt_check(0, "orientation (glass): %s", err); return; }
      rt_check(elr_intersect(s, elr_v(0, 0, -5), elr_v(0, 0, 1), INFINITY, &h), "the glass sphere is hit");
      elr_bsdf_init(s, &h, &tc, &b);
      rt_check(turned ? elr_dot(b.ns, elr_v(0, 0, -1)) < -0.99f && elr_dot(h.ng, elr_v(0, 0, -1)) < -0.99f
                      : elr_dot(b.ns, elr_v(0, 0, -1)) > 0.99f && elr_dot(h.ng, elr_v(0, 0, -1)) > 0.99f,
               "glass frame and hit normal point %s", turned ? "inside (ReverseOrientation)" : "outside (towards the camera)");
      elr_scene_free(s);
    }
  }
  s = world("badidx.pbrt", "\nMaterial \"glass\" \"float index\" 0\n", err, sizeof err);
  rt_check(!s && strstr(err, "badidx.pbrt:4:") && strstr(err, "out of range"), "glass of index 0: \"%s\"", s ? "(loaded)" : err);
  elr_scene_free(s);
}

int main(void) {
  rt_mkdir("test_render_format");
  textures();
  integrators();
  unsupported_once();
  named_materials();
  orientation();
  return rt_finish("test_render_format");
}
