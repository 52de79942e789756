/* picture.h: small drawing helpers the chapter examples share (not part of the library).
 *
 *   el_test_image(rgb, 400, 235);        the tutorial's test image: a checkerboard whose frequency rises
 *                                        from 4 to 64 checks across, over a colour ramp (linear RGB)
 *   el_draw_text(img8, w, h, x, y, 2, "EWA", 255, 255, 255);   5x7 bitmap text into an RGB8 image
 *   el_draw_label(img8, w, h, x, y, "WIDTH 0.15");             the same on a darkened band
 *
 * The font has upper case (lower case is drawn as upper case), digits and . : ( ) / + - = ,
 * Other characters leave a blank. Drawing is clipped to the image. */
#ifndef EL_PICTURE_H
#define EL_PICTURE_H
#ifdef __cplusplus
extern "C" {
#endif

void el_test_image(float *rgb, int width, int height);
void el_draw_text(unsigned char *img, int w, int h, int x, int y, int scale, const char *s,
                  unsigned char r, unsigned char g, unsigned char b);
void el_draw_label(unsigned char *img, int w, int h, int x, int y, const char *s);

#ifdef __cplusplus
}
#endif
#endif
