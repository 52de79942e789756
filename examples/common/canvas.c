/* canvas.c: see canvas.h. */
#include "canvas.h"

#include <stdlib.h>

static void put(unsigned char *page, int w, int h, int x, int y, unsigned char r, unsigned char g, unsigned char b) {
  unsigned char *p;
  if (x < 0 || y < 0 || x >= w || y >= h) return;
  p = page + 3 * ((size_t)y * (size_t)w + (size_t)x);
  p[0] = r;
  p[1] = g;
  p[2] = b;
}

void el_canvas_blit(unsigned char *page, int w, int h, const unsigned char *panel, int pw, int ph, int x0, int y0,
                    int mag) {
  int x, y;
  for (y = 0; y < ph * mag; y++)
    for (x = 0; x < pw * mag; x++) {
      const unsigned char *s = panel + 3 * ((size_t)(y / mag) * (size_t)pw + (size_t)(x / mag));
      put(page, w, h, x0 + x, y0 + y, s[0], s[1], s[2]);
    }
}

void el_canvas_fill(unsigned char *page, int w, int h, int x0, int y0, int x1, int y1, unsigned char r,
                    unsigned char g, unsigned char b) {
  int x, y;
  for (y = y0; y < y1; y++)
    for (x = x0; x < x1; x++) put(page, w, h, x, y, r, g, b);
}

/* Bresenham's line */
void el_canvas_line(unsigned char *page, int w, int h, int x0, int y0, int x1, int y1, unsigned char r,
                    unsigned char g, unsigned char b) {
  int dx = abs(x1 - x0), sx = x0 < x1 ? 1 : -1, dy = -abs(y1 - y0), sy = y0 < y1 ? 1 : -1, e = dx + dy;
  for (;;) {
    int e2 = 2 * e;
    put(page, w, h, x0, y0, r, g, b);
    if (x0 == x1 && y0 == y1) break;
    if (e2 >= dy) { e += dy; x0 += sx; }
    if (e2 <= dx) { e += dx; y0 += sy; }
  }
}

void el_canvas_dot(unsigned char *page, int w, int h, int x, int y, int radius, unsigned char r, unsigned char g,
                   unsigned char b) {
  el_canvas_fill(page, w, h, x - radius, y - radius, x + radius + 1, y + radius + 1, r, g, b);
}
