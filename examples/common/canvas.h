/* canvas.h: composing the chapter pictures on an RGB8 page (not part of the library).
 *
 *   el_canvas_blit(page, w, h, panel, pw, ph, x0, y0, 2);   a panel, magnified 2x (nearest)
 *   el_canvas_fill(page, w, h, x0, y0, x1, y1, r, g, b);    a rectangle [x0, x1) x [y0, y1)
 *   el_canvas_line(page, w, h, x0, y0, x1, y1, r, g, b);    a line, both ends included
 *   el_canvas_dot(page, w, h, x, y, 1, r, g, b);            a (2 * 1 + 1)-pixel square dot
 *
 * A page is w * h * 3 bytes, row 0 at the top. Everything is clipped to the page. Text and labels
 * are picture.h's (el_draw_text, el_draw_label). */
#ifndef EL_CANVAS_H
#define EL_CANVAS_H
#ifdef __cplusplus
extern "C" {
#endif

void el_canvas_blit(unsigned char *page, int w, int h, const unsigned char *panel, int pw, int ph, int x0, int y0,
                    int mag);
void el_canvas_fill(unsigned char *page, int w, int h, int x0, int y0, int x1, int y1, unsigned char r,
                    unsigned char g, unsigned char b);
void el_canvas_line(unsigned char *page, int w, int h, int x0, int y0, int x1, int y1, unsigned char r,
                    unsigned char g, unsigned char b);
void el_canvas_dot(unsigned char *page, int w, int h, int x, int y, int radius, unsigned char r, unsigned char g,
                   unsigned char b);

#ifdef __cplusplus
}
#endif
#endif
