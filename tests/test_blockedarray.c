/* test_blockedarray.c: blockedarray.h against hand-computed layouts.
 *
 * Expected values: the row-major input itself (round trips), block/offset arithmetic written out by
 * hand for a few texels (pbrt's BlockedArray layout: blocks of 2^k x 2^k texels, blocks in row-major
 * order, texels row-major inside a block), and the overflow arithmetic of the byte count.
 */
#define EL_BLOCKEDARRAY_IMPLEMENTATION
#include "blockedarray.h"

#include <limits.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int g_pass, g_fail;
static void check(int ok, const char *what) {
  if (ok) g_pass++;
  else g_fail++;
  printf("%s: %s\n", ok ? "PASS" : "FAIL", what);
}

/* Round trip for one size: every texel readable at its (u, v), get_rowmajor gives the input back,
 * every texel has its own address, padding is zero, data is 64-byte aligned. */
static void round_trip(int w, int h, int C, int lb) {
  char what[160];
  size_t n = (size_t)w * (size_t)h * (size_t)C, i;
  float *in = (float *)malloc(n * sizeof(float)), *out = (float *)malloc(n * sizeof(float));
  el_blockedarray a;
  int u, v, c, ok_at = 1, ok_distinct = 1, bs, texels, nonzero = 0;
  unsigned char *seen;
  for (i = 0; i < n; ++i) in[i] = (float)i + 0.25f;
  snprintf(what, sizeof what, "init %dx%d C=%d log_block=%d", w, h, C, lb);
  check(el_blockedarray_init(&a, w, h, C, lb, in) == EL_SUCCESS, what);
  bs = 1 << a.log_block;
  for (v = 0; v < h; ++v)
    for (u = 0; u < w; ++u)
      for (c = 0; c < C; ++c)
        if (el_blockedarray_at(&a, u, v)[c] != in[((size_t)v * w + u) * C + c]) ok_at = 0;
  snprintf(what, sizeof what, "  at(u,v) reads the row-major input (%dx%d C=%d, %dx%d blocks)", w, h, C, bs, bs);
  check(ok_at, what);
  memset(out, 0, n * sizeof(float));
  el_blockedarray_get_rowmajor(&a, out);
  check(memcmp(in, out, n * sizeof(float)) == 0, "  get_rowmajor gives the input back");
  /* distinct addresses, all inside the rounded-up allocation */
  texels = a.ublocks * bs * a.vblocks * bs;
  seen = (unsigned char *)calloc((size_t)texels, 1);
  for (v = 0; v < h; ++v)
    for (u = 0; u < w; ++u) {
      size_t k = el_blockedarray_index(&a, u, v);
      if (k % (size_t)C != 0 || k / (size_t)C >= (size_t)texels || seen[k / (size_t)C]) ok_distinct = 0;
      else seen[k / (size_t)C] = 1;
    }
  check(ok_distinct, "  every texel has its own slot inside the allocation");
  for (i = 0; i < (size_t)texels; ++i)
    if (!seen[i])
      for (c = 0; c < C; ++c) nonzero += a.data[i * (size_t)C + (size_t)c] != 0.0f;
  check(nonzero == 0, "  padding texels of partial blocks are zero");
  check(((uintptr_t)a.data & 63u) == 0, "  data is 64-byte aligned");
  check(el_blockedarray_bytes(&a) >= (size_t)texels * (size_t)C * sizeof(float), "  bytes cover the rounded-up blocks");
  /* set_rowmajor overwrites everything */
  for (i = 0; i < n; ++i) in[i] = -(float)i;
  el_blockedarray_set_rowmajor(&a, in);
  el_blockedarray_get_rowmajor(&a, out);
  check(memcmp(in, out, n * sizeof(float)) == 0, "  set_rowmajor then get_rowmajor round trip");
  el_blockedarray_free(&a);
  check(a.data == NULL && el_blockedarray_bytes(&a) == 0, "  free zeroes the struct");
  free(seen);
  free(in);
  free(out);
}

int main(void) {
  static const int sizes[][2] = {{1, 1}, {3, 5}, {4, 4}, {5, 7}, {17, 9}, {64, 3}, {1, 33}, {33, 1}};
  int s, C, lb;
  el_blockedarray a;
  for (s = 0; s < (int)(sizeof sizes / sizeof sizes[0]); ++s)
    for (C = 1; C <= 4; ++C)
      for (lb = 0; lb <= 3; lb += 3) round_trip(sizes[s][0], sizes[s][1], C, lb);
  round_trip(10, 6, 3, 1);

  /* Hand-computed layout, 4x4 blocks (log_block 0 -> 2), width 10 -> 3 blocks per row, 3 channels.
   * texel (5, 6): block (1, 1) = block number 1*3 + 1 = 4, offset in block (6 & 3) * 4 + (5 & 3) = 9,
   * so texel slot 4 * 16 + 9 = 73, float index 219. texel (3, 3): block 0, slot 15, index 45.
   * texel (4, 0): block 1, slot 16, index 48 (the first texel of the second block). */
  check(el_blockedarray_init(&a, 10, 7, 3, 0, NULL) == EL_SUCCESS, "init 10x7 RGB, NULL data");
  check(a.log_block == 2 && a.ublocks == 3 && a.vblocks == 2, "log_block 0 means 4x4 blocks; 3x2 blocks");
  check(el_blockedarray_index(&a, 5, 6) == 219, "texel (5,6) at float 219 (block 4, slot 9)");
  check(el_blockedarray_index(&a, 3, 3) == 45, "texel (3,3) at float 45 (last of block 0)");
  check(el_blockedarray_index(&a, 4, 0) == 48, "texel (4,0) at float 48 (first of block 1)");
  check(el_blockedarray_index(&a, 9, 4) == 3 * (16 * 5 + 1), "texel (9,4): block 5, slot 1");
  check(el_blockedarray_at(&a, 9, 6)[2] == 0.0f, "NULL data gives zeros");
  el_blockedarray_free(&a);
  el_blockedarray_free(&a); /* twice: harmless */
  el_blockedarray_free(NULL);

  /* Invalid arguments and sizes whose byte count overflows size_t (rejected before any allocation) */
  check(el_blockedarray_init(NULL, 4, 4, 1, 0, NULL) == EL_ERROR_INVALID_ARGUMENT, "NULL array rejected");
  check(el_blockedarray_init(&a, 0, 4, 1, 0, NULL) == EL_ERROR_INVALID_ARGUMENT, "width 0 rejected");
  check(el_blockedarray_init(&a, 4, -3, 1, 0, NULL) == EL_ERROR_INVALID_ARGUMENT, "negative height rejected");
  check(el_blockedarray_init(&a, 4, 4, 5, 0, NULL) == EL_ERROR_INVALID_ARGUMENT, "5 channels rejected");
  check(el_blockedarray_init(&a, 4, 4, 0, 0, NULL) == EL_ERROR_INVALID_ARGUMENT, "0 channels rejected");
  check(el_blockedarray_init(&a, 4, 4, 1, 9, NULL) == EL_ERROR_INVALID_ARGUMENT, "log_block 9 rejected");
  check(a.data == NULL && a.width == 0, "a failed init leaves a zeroed struct");
  if (sizeof(size_t) == 8) {
    /* INT_MAX x INT_MAX x 4 floats rounded up to 256x256 blocks: 2^62 * 16 bytes > SIZE_MAX */
    check(el_blockedarray_init(&a, INT_MAX, INT_MAX, 4, 8, NULL) == EL_ERROR_SIZE_OVERFLOW,
          "INT_MAX x INT_MAX x 4 channels: size overflow reported");
    check(el_blockedarray_init(&a, INT_MAX, INT_MAX, 1, 0, NULL) == EL_ERROR_SIZE_OVERFLOW,
          "INT_MAX x INT_MAX x 1 channel: size overflow reported");
  } else {
    check(el_blockedarray_init(&a, 70000, 70000, 1, 0, NULL) == EL_ERROR_SIZE_OVERFLOW,
          "70000 x 70000 floats: size overflow reported (32-bit size_t)");
  }
  check(a.data == NULL, "no allocation after an overflow");
  printf("test_blockedarray: %d passed, %d failed\n", g_pass, g_fail);
  return g_fail != 0;
}
