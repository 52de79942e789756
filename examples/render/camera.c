/* camera.c: pbrt-v3's PerspectiveCamera (cameras/perspective.cpp), a pinhole: no lens, no motion.
 *
 * The screen window spans [-frame, frame] x [-1, 1] (or [-1, 1] x [-1/frame, 1/frame]) so that fov
 * applies to the shorter image axis; raster y grows downwards; the camera looks down +z of camera space
 * (left-handed, as pbrt). Rays carry differentials towards the next pixel in x and in y, scaled by
 * 1/sqrt(spp) (pbrt-v3's ScaleDifferentials), when some texture will filter over them. */
#include "elr_internal.h"

/* The camera of the scene description for a render of spp samples per pixel; differentials: whether
 * its rays carry them (some material is textured). */
void elr_camera_init(elr_camera *C, const elr_scene_desc *d, int spp, int differentials) {
  double frame;
  C->xres = d->xres; C->yres = d->yres;
  C->diff_scale = 1.f / sqrtf((float)spp);
  C->differentials = differentials;
  /* the camera's origin and the images of its axes in world space */
  C->o = elr_xpoint(&d->cam2world, elr_v(0, 0, 0));
  C->x = elr_xvector(&d->cam2world, elr_v(1, 0, 0));
  C->y = elr_xvector(&d->cam2world, elr_v(0, 1, 0));
  C->z = elr_xvector(&d->cam2world, elr_v(0, 0, 1));
  /* <<Compute screen window>> */
  frame = d->has_frameaspect ? d->frameaspect : (double)d->xres / (double)d->yres;
  if (d->has_screen) { C->sx0 = d->screen[0]; C->sx1 = d->screen[1]; C->sy0 = d->screen[2]; C->sy1 = d->screen[3]; }
  else if (frame > 1.0) { C->sx0 = (float)-frame; C->sx1 = (float)frame; C->sy0 = -1.f; C->sy1 = 1.f; }
  else { C->sx0 = -1.f; C->sx1 = 1.f; C->sy0 = (float)(-1.0 / frame); C->sy1 = (float)(1.0 / frame); }
  C->tanhalf = tanf(d->fov * ELR_PI / 360.f);
}

/* pbrt-v3's PerspectiveCamera::GenerateRayDifferential (pinhole) at raster position (fx, fy) */
void elr_camera_ray(const elr_camera *C, float fx, float fy, elr_ray *r) {
  float sx, sy;
  elr_v3 dc;
  /* <<Compute raster and camera sample positions>> */
  sx = C->sx0 + fx / (float)C->xres * (C->sx1 - C->sx0);
  sy = C->sy1 - fy / (float)C->yres * (C->sy1 - C->sy0);
  dc = elr_v(sx * C->tanhalf, sy * C->tanhalf, 1.f);
  r->o = C->o;
  r->d = elr_norm(elr_add(elr_add(elr_mul(C->x, dc.x), elr_mul(C->y, dc.y)), elr_mul(C->z, dc.z)));
  r->has_diff = 0;
  if (C->differentials) {
    float dxs = (C->sx1 - C->sx0) / (float)C->xres * C->tanhalf, dys = -(C->sy1 - C->sy0) / (float)C->yres * C->tanhalf;
    elr_v3 dx = elr_norm(elr_add(dc, elr_v(dxs, 0, 0))), dy = elr_norm(elr_add(dc, elr_v(0, dys, 0)));
    elr_v3 dcn = elr_norm(dc);
    /* ScaleDifferentials(1 / sqrt(spp)) */
    dx = elr_add(dcn, elr_mul(elr_sub(dx, dcn), C->diff_scale));
    dy = elr_add(dcn, elr_mul(elr_sub(dy, dcn), C->diff_scale));
    r->has_diff = 1;
    r->rxo = r->ryo = r->o;
    r->rxd = elr_norm(elr_add(elr_add(elr_mul(C->x, dx.x), elr_mul(C->y, dx.y)), elr_mul(C->z, dx.z)));
    r->ryd = elr_norm(elr_add(elr_add(elr_mul(C->x, dy.x), elr_mul(C->y, dy.y)), elr_mul(C->z, dy.z)));
  }
}
