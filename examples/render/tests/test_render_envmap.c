/* test_render_envmap: the environment seen by the camera, against pbrt-v3's mathematics computed here
 * independently of the renderer.
 *
 * A 64 x 32 latitude-longitude map made of 8 x 8-texel blocks, each block a different colour
 * (R = (bx + 1) / 8, G = (by + 1) / 4): asymmetric in both axes, so a left-right mirror, an upside-down
 * map, a transposition or a swapped channel all fail. The light is rotated (Rotate -90 1 0 0, then
 * Rotate 30 0 0 1) and scaled ("rgb L" and "rgb scale"); the camera looks along an oblique direction.
 * For each pixel centre (the stratified sampler without jitter samples exactly the centre) the test
 * computes pbrt-v3's camera ray (LookAt frame, fov on the shorter axis, raster y down), the light-space
 * direction (the inverse rotation), phi = atan2(y, x), theta = acos(z), (s, t) = (phi / 2pi, theta / pi)
 * with row 0 at theta = 0, and the block it falls in. Pixels whose point lies within 1 texel of a block
 * edge (where bilinear reconstruction mixes blocks) are skipped; every other pixel must reproduce its
 * block's texel value exactly. */
#include "render_test_util.h"

#define MW 64
#define MH 32
#define XR 48
#define YR 32

static void block_value(int bx, int by, float *rgb) { rgb[0] = (bx + 1) / 8.0f; rgb[1] = (by + 1) / 4.0f; rgb[2] = 0.25f; }

typedef struct { double x, y, z; } v3d;
static v3d vd(double x, double y, double z) { v3d r; r.x = x; r.y = y; r.z = z; return r; }
static v3d vnorm(v3d a) { double l = sqrt(a.x * a.x + a.y * a.y + a.z * a.z); return vd(a.x / l, a.y / l, a.z / l); }
static v3d vcross(v3d a, v3d b) { return vd(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x); }

/* rotation by deg about a unit axis, pbrt-v3's Rotate (Rodrigues), applied to v */
static v3d rot(double deg, v3d k, v3d v) {
  double a = deg * 3.14159265358979323846 / 180.0, c = cos(a), s = sin(a), d = k.x * v.x + k.y * v.y + k.z * v.z;
  v3d kx = vcross(k, v);
  return vd(v.x * c + kx.x * s + k.x * d * (1 - c), v.y * c + kx.y * s + k.y * d * (1 - c), v.z * c + kx.z * s + k.z * d * (1 - c));
}

static void run(int scene_variant) {
  float *map = (float *)malloc(sizeof(float) * 3 * MW * MH);
  char err[512], scene[2048];
  int x, y, tested = 0, bad = 0, worst_x = -1, worst_y = -1;
  double worst = 0;
  elr_scene *s;
  elr_image img;
  elr_stats st;
  const float Lc[3] = {2.0f, 1.0f, 0.5f}, sc[3] = {1.5f, 2.0f, 4.0f};
  v3d eye = vd(0.5, 0.2, -0.3), look = vd(1.5, 0.5, 0.4), up = vd(0, 1, 0), dir, right, nup;
  for (y = 0; y < MH; y++)
    for (x = 0; x < MW; x++) block_value(x / 8, y / 8, map + 3 * (y * MW + x));
  if (el_image_write_pfm(rt_path("blocks.pfm"), map, MW, MH, 3, err, sizeof err) != 0) { rt_check(0, "write map: %s", err); free(map); return; }
  snprintf(scene, sizeof scene,
           "LookAt %g %g %g  %g %g %g  %g %g %g\n"
           "Camera \"perspective\" \"float fov\" [ 70 ]\n"
           "Film \"image\" \"integer xresolution\" [ %d ] \"integer yresolution\" [ %d ]\n"
           "Sampler \"stratified\" \"integer xsamples\" 1 \"integer ysamples\" 1 \"bool jitter\" \"false\"\n"
           "Integrator \"%s\"\n"
           "WorldBegin\n"
           "AttributeBegin\n"
           "  Rotate -90 1 0 0\n"
           "  Rotate 30 0 0 1\n"
           "  LightSource \"infinite\" \"string mapname\" \"blocks.pfm\" \"rgb L\" [ %g %g %g ] \"rgb scale\" [ %g %g %g ]\n"
           "AttributeEnd\n"
           "WorldEnd\n",
           eye.x, eye.y, eye.z, look.x, look.y, look.z, up.x, up.y, up.z, XR, YR, scene_variant ? "path" : "directlighting",
           Lc[0], Lc[1], Lc[2], sc[0], sc[1], sc[2]);
  s = rt_load("env.pbrt", scene, err, sizeof err);
  free(map);
  if (!s) { rt_check(0, "load: %s", err); return; }
  if (rt_render(s, 0, -1, -1, 2, 1, &img, &st) != 0) { rt_check(0, "render"); elr_scene_free(s); return; }
  rt_check(img.width == XR && img.height == YR, "image is %d x %d", img.width, img.height);
  rt_check(st.distribution_built == 0 && st.light_sampling_used == 0 && st.shadow_rays == 0,
           "environment seen only in the background: no distribution, no light sampling, no shadow rays");
  /* the camera frame, pbrt-v3's LookAt: right = up x dir (left-handed), newUp = dir x right */
  dir = vnorm(vd(look.x - eye.x, look.y - eye.y, look.z - eye.z));
  right = vnorm(vcross(vnorm(up), dir));
  nup = vcross(dir, right);
  for (y = 0; y < YR; y++)
    for (x = 0; x < XR; x++) {
      double aspect = (double)XR / YR, th = tan(35.0 * 3.14159265358979323846 / 180.0);
      double sx = -aspect + (x + 0.5) / XR * 2 * aspect, sy = 1 - (y + 0.5) / YR * 2; /* fov on the shorter axis (y) */
      v3d dc = vd(sx * th, sy * th, 1), w, l;
      double phi, theta, u, v, tu, tv;
      int bx, by, c;
      float expect[3];
      w = vnorm(vd(right.x * dc.x + nup.x * dc.y + dir.x * dc.z, right.y * dc.x + nup.y * dc.y + dir.y * dc.z,
                   right.z * dc.x + nup.z * dc.y + dir.z * dc.z));
      /* world = Rx(-90) Rz(30) light, so light = Rz(-30) Rx(90) world */
      l = rot(90, vd(1, 0, 0), w);
      l = rot(-30, vd(0, 0, 1), l);
      phi = atan2(l.y, l.x); if (phi < 0) phi += 2 * 3.14159265358979323846;
      theta = acos(l.z > 1 ? 1 : (l.z < -1 ? -1 : l.z));
      u = phi / (2 * 3.14159265358979323846); v = theta / 3.14159265358979323846;
      tu = u * MW; tv = v * MH;
      if (fabs(tu / 8 - floor(tu / 8 + 0.5)) * 8 < 1.0 || fabs(tv / 8 - floor(tv / 8 + 0.5)) * 8 < 1.0) continue;
      if (tv < 1 || tv > MH - 1) continue;
      bx = (int)floor(tu / 8) % 8; by = (int)floor(tv / 8);
      block_value(bx, by, expect);
      tested++;
      for (c = 0; c < 3; c++) {
        double e = expect[c] * Lc[c] * sc[c], got = img.rgb[3 * (y * XR + x) + c], d = fabs(got - e) / e;
        if (d > worst) { worst = d; worst_x = x; worst_y = y; }
        if (d > 1e-4) bad++;
      }
    }
  rt_check(tested > XR * YR / 3, "%s: %d of %d pixels lie well inside a block", scene_variant ? "path" : "directlighting", tested, XR * YR);
  rt_check(bad == 0, "%s: every tested pixel shows its block's texel x L x scale (worst relative error %.2g at %d,%d)",
           scene_variant ? "path" : "directlighting", worst, worst_x, worst_y);
  elr_image_free(&img);
  elr_scene_free(s);
}

/* The mapping must also be the right way round in an unrotated light: straight up (+z in light space,
 * the light's identity transform) is the top row, and phi = 90 degrees (+y) is a quarter along a row. */
static void axes(void) {
  float map[3 * 8 * 4];
  char err[512];
  int x, y;
  elr_scene *s;
  elr_image img;
  elr_stats st;
  for (y = 0; y < 4; y++)
    for (x = 0; x < 8; x++) { map[3 * (y * 8 + x)] = (float)(x + 1); map[3 * (y * 8 + x) + 1] = (float)(y + 1); map[3 * (y * 8 + x) + 2] = 1; }
  el_image_write_pfm(rt_path("axes.pfm"), map, 8, 4, 3, err, sizeof err);
  /* camera at the origin looking along +y (light space = world space): phi = 90 deg, theta = 90 deg ->
   * u = 0.25 (column 2 of 8), v = 0.5 (between rows 1 and 2: look slightly up, theta = 67.5 deg -> row 1) */
  s = rt_load("axes.pbrt",
              "LookAt 0 0 0  0 1 0.41421356  0 0 1\n"
              "Camera \"perspective\" \"float fov\" [ 1 ]\n"
              "Film \"image\" \"integer xresolution\" 1 \"integer yresolution\" 1\n"
              "Sampler \"stratified\" \"integer xsamples\" 1 \"integer ysamples\" 1 \"bool jitter\" \"false\"\n"
              "WorldBegin\nLightSource \"infinite\" \"string mapname\" \"axes.pfm\"\nWorldEnd\n", err, sizeof err);
  if (!s) { rt_check(0, "load axes scene: %s", err); return; }
  if (rt_render(s, 0, -1, -1, 1, 1, &img, &st) == 0) {
    /* direction (0, 1, 0.414): theta = 67.5 deg -> v = 0.375 -> row 1.5 - 0.5 = texel 1 exactly (bilinear
     * at row centre); phi = 90 deg -> u = 0.25 -> column 2.0 - 0.5 = 1.5: halfway between columns 1 and 2 */
    rt_check(fabsf(img.rgb[0] - 2.5f) < 1e-3f && fabsf(img.rgb[1] - 2.0f) < 1e-3f,
             "light +y with +z up: u = 0.25 (R %.4f, expect 2.5), theta 67.5 deg -> row 1 (G %.4f, expect 2)", img.rgb[0], img.rgb[1]);
    elr_image_free(&img);
  }
  elr_scene_free(s);
}

int main(void) {
  rt_mkdir("test_render_envmap");
  run(0);
  run(1);
  axes();
  return rt_finish("test_render_envmap");
}
