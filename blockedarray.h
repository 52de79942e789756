/* blockedarray.h - tiled 2D float storage (pbrt's BlockedArray) - envlight v0.1.0 - MIT or public domain
 *
 * DO THIS in exactly one C or C++ file (the first line alone is enough):
 *     #define EL_IMPLEMENTATION   // implements every envlight header included after it
 *     #include "blockedarray.h"
 * Every other file includes it without the macro. EL_BLOCKEDARRAY_IMPLEMENTATION instead implements
 * blockedarray.h alone: a module's own macro never implements another module's header.
 *
 * USAGE (valid C and C++; tests/test_snippets.c compiles it)
 * >> usage
 *     // given: const float *rgb; float *out;    (400 * 235 * 3 floats each, row 0 first)
 *     el_blockedarray a;
 *     if (el_blockedarray_init(&a, 400, 235, 3, 0, rgb) != EL_SUCCESS) return 1;  // 0: 4x4 blocks
 *     float *p = el_blockedarray_at(&a, 17, 42);  // the 3 floats of texel (17, 42): u along a row
 *     p[0] = 1.0f;
 *     el_blockedarray_get_rowmajor(&a, out);      // back to row-major order
 *     el_blockedarray_free(&a);
 * << usage
 *
 * OPTIONS (define before including): EL_MALLOC / EL_REALLOC / EL_FREE (all or none), EL_ASSERT,
 * EL_STATIC (private functions in this translation unit), EL_DEF.
 *
 * PORTS pbrt-v3's BlockedArray<T, logBlockSize> (src/core/memory.h): the 2D array is stored as square
 * blocks of 2^log_block x 2^log_block texels so that texels close in 2D are close in memory; pbrt's
 * operator()(u, v) is el_blockedarray_at, GetLinearArray el_blockedarray_get_rowmajor. NOTES after
 * the declarations: where it departs from pbrt.
 */
#ifndef EL_BLOCKEDARRAY_H
#define EL_BLOCKEDARRAY_H

/* >> shared declarations (identical in every envlight header; guarded so any set of headers can be
 * included together, in any order). Change it in every header at once, or not at all. */
#ifndef EL_SHARED_DECLARATIONS
#define EL_SHARED_DECLARATIONS
#include <stddef.h>
#ifndef EL_DEF
#ifdef EL_STATIC
#define EL_DEF static
#else
#define EL_DEF extern
#endif
#endif
#ifndef EL_ASSERT
#include <assert.h>
#define EL_ASSERT(x) assert(x)
#endif
#if defined(EL_MALLOC) && defined(EL_FREE) && defined(EL_REALLOC)
/* the user supplied all three */
#elif !defined(EL_MALLOC) && !defined(EL_FREE) && !defined(EL_REALLOC)
#include <stdlib.h>
#define EL_MALLOC(sz) malloc(sz)
#define EL_REALLOC(p, newsz) realloc(p, newsz)
#define EL_FREE(p) free(p)
#else
#error "envlight: define all of EL_MALLOC, EL_REALLOC and EL_FREE, or none of them"
#endif
#ifdef __cplusplus
extern "C" {
#endif
/* What a constructor, loader or parser returns. el_result_string() explains a value. */
typedef enum el_result {
  EL_SUCCESS = 0,
  EL_ERROR_INVALID_ARGUMENT = 1, /* a NULL pointer, a size <= 0, channels outside 1..4, an unknown enum */
  EL_ERROR_OUT_OF_MEMORY = 2,    /* EL_MALLOC returned NULL */
  EL_ERROR_SIZE_OVERFLOW = 3,    /* a byte count would overflow size_t (or exceeds an int index) */
  EL_ERROR_NAN = 4,              /* an input value is NaN */
  EL_ERROR_INFINITE = 5,         /* an input value is infinite */
  EL_ERROR_NEGATIVE = 6,         /* an input value is negative where only >= 0 is allowed */
  EL_ERROR_NOT_ORTHONORMAL = 7,  /* a matrix that must be a rotation or reflection is not */
  EL_ERROR_EMPTY = 8             /* an input has no elements (n = 0, a 0-sized image) */
} el_result;
static inline const char *el_result_string(el_result r) {
  switch (r) {
  case EL_SUCCESS: return "success";
  case EL_ERROR_INVALID_ARGUMENT: return "invalid argument (NULL pointer, non-positive size, or value out of range)";
  case EL_ERROR_OUT_OF_MEMORY: return "out of memory";
  case EL_ERROR_SIZE_OVERFLOW: return "size overflow: the requested size is too large";
  case EL_ERROR_NAN: return "input contains a NaN value";
  case EL_ERROR_INFINITE: return "input contains an infinite value";
  case EL_ERROR_NEGATIVE: return "input contains a negative value";
  case EL_ERROR_NOT_ORTHONORMAL: return "matrix is not orthonormal (not a rotation or reflection)";
  case EL_ERROR_EMPTY: return "input is empty (zero elements)";
  }
  return "unknown el_result value";
}
#ifdef __cplusplus
}
#endif
#endif /* EL_SHARED_DECLARATIONS */
/* << shared declarations */

#ifdef __cplusplus
extern "C" {
#endif

/* >> blockedarray declarations */

/* A width x height array of `channels` floats per texel, stored in 2^log_block square blocks.
 * Fields are readable; change them only through the functions. */
typedef struct el_blockedarray {
  int width, height;  /* texels, >= 1 */
  int channels;       /* floats per texel, 1..4 */
  int log_block;      /* blocks are (1 << log_block) texels square, 1..8 (0 at init means 2) */
  int ublocks;        /* blocks per row: ceil(width / block) */
  int vblocks;        /* block rows: ceil(height / block) */
  float *data;        /* 64-byte aligned, ublocks*vblocks*block*block*channels floats */
  void *allocation;   /* what EL_MALLOC returned (data is aligned inside it) */
  size_t allocated;   /* bytes of `allocation` */
} el_blockedarray;

/* Allocates a width x height array with channels 1..4 floats per texel and blocks of 2^log_block
 * texels (log_block 0 means 2, i.e. 4x4 blocks as in pbrt; 1..8 are accepted). The padding texels of
 * partial blocks are zero. rowmajor: width*height*channels floats, row 0 first, copied in; NULL
 * gives zeros. Returns EL_ERROR_INVALID_ARGUMENT (a NULL array, a size < 1, channels outside 1..4,
 * log_block outside 0..8), EL_ERROR_SIZE_OVERFLOW, EL_ERROR_OUT_OF_MEMORY; on failure *a is zeroed. */
EL_DEF el_result el_blockedarray_init(el_blockedarray *a, int width, int height, int channels,
                                      int log_block, const float *rowmajor);
/* Releases the storage and zeroes *a. Safe on a zeroed struct and on NULL. */
EL_DEF void el_blockedarray_free(el_blockedarray *a);
/* Copies the array out / in as row-major floats (width*height*channels, row 0 first). */
EL_DEF void el_blockedarray_get_rowmajor(const el_blockedarray *a, float *out);
EL_DEF void el_blockedarray_set_rowmajor(el_blockedarray *a, const float *in);
/* Bytes allocated on the heap (0 for a zeroed struct). */
EL_DEF size_t el_blockedarray_bytes(const el_blockedarray *a);

/* Index in floats of texel (u, v) inside a->data. u in [0, width), v in [0, height): no checks
 * beyond EL_ASSERT (pbrt's operator() does not check either). */
static inline size_t el_blockedarray_index(const el_blockedarray *a, int u, int v) {
  int lb = a->log_block, mask = (1 << lb) - 1;
  size_t block = (size_t)(v >> lb) * (size_t)a->ublocks + (size_t)(u >> lb);
  size_t inblock = ((size_t)(v & mask) << lb) + (size_t)(u & mask);
  EL_ASSERT(u >= 0 && u < a->width && v >= 0 && v < a->height);
  return ((block << (2 * lb)) + inblock) * (size_t)a->channels;
}
/* Pointer to the `channels` floats of texel (u, v); same preconditions as el_blockedarray_index. */
static inline float *el_blockedarray_at(const el_blockedarray *a, int u, int v) {
  return a->data + el_blockedarray_index(a, u, v);
}
/* << blockedarray declarations */

#ifdef __cplusplus
}
#endif
#endif /* EL_BLOCKEDARRAY_H */

/* ====================================================================================================
 * NOTES (the reasons behind the API; a user of the functions above needs none of this)
 *
 * Where it departs from pbrt-v3's BlockedArray: elements are 1..4 interleaved floats (not a template
 * T); the allocation is rounded up to whole blocks and aligned to 64 bytes with EL_MALLOC (pbrt:
 * AllocAligned); sizes whose byte count would overflow size_t, or whose rounded-up texel count would
 * overflow int indexing, are rejected with EL_ERROR_SIZE_OVERFLOW instead of wrapping around; free on a
 * zeroed struct is harmless.
 * ==================================================================================================== */

/* ---------------------------------------------------------------------------------------------
 * Implementation below; stop reading here if you only need the API.
 * --------------------------------------------------------------------------------------------- */
#if defined(EL_IMPLEMENTATION) || defined(EL_BLOCKEDARRAY_IMPLEMENTATION)
#ifndef EL_BLOCKEDARRAY_IMPLEMENTATION_DONE
#define EL_BLOCKEDARRAY_IMPLEMENTATION_DONE
#include <string.h>
#include <limits.h>
#include <stdint.h>

/* >> blockedarray implementation */
EL_DEF el_result el_blockedarray_init(el_blockedarray *a, int width, int height, int channels,
                                      int log_block, const float *rowmajor) {
  size_t bs, ub, vb, texels, floats, bytes;
  unsigned char *raw;
  uintptr_t addr;
  if (!a) return EL_ERROR_INVALID_ARGUMENT;
  memset(a, 0, sizeof *a);
  if (width < 1 || height < 1 || channels < 1 || channels > 4 || log_block < 0 || log_block > 8)
    return EL_ERROR_INVALID_ARGUMENT;
  if (log_block == 0) log_block = 2;
  bs = (size_t)1 << log_block;
  /* <<Round up width and height to whole blocks>>: no int arithmetic, so no overflow here */
  ub = ((size_t)width + bs - 1) >> log_block;
  vb = ((size_t)height + bs - 1) >> log_block;
  /* every index el_blockedarray_index can form must fit in size_t, and the byte count too */
  if (ub > (SIZE_MAX / bs) / bs / vb) return EL_ERROR_SIZE_OVERFLOW;
  texels = ub * vb * bs * bs;
  if (texels > SIZE_MAX / (size_t)channels) return EL_ERROR_SIZE_OVERFLOW;
  floats = texels * (size_t)channels;
  if (floats > (SIZE_MAX - 64) / sizeof(float)) return EL_ERROR_SIZE_OVERFLOW;
  bytes = floats * sizeof(float) + 64;
  raw = (unsigned char *)EL_MALLOC(bytes);
  if (!raw) return EL_ERROR_OUT_OF_MEMORY;
  addr = (uintptr_t)raw;
  addr = (addr + 63u) & ~(uintptr_t)63u;
  a->allocation = raw;
  a->allocated = bytes;
  a->data = (float *)(void *)(raw + (addr - (uintptr_t)raw));
  a->width = width;
  a->height = height;
  a->channels = channels;
  a->log_block = log_block;
  a->ublocks = (int)ub;
  a->vblocks = (int)vb;
  memset(a->data, 0, floats * sizeof(float));
  if (rowmajor) el_blockedarray_set_rowmajor(a, rowmajor);
  return EL_SUCCESS;
}

EL_DEF void el_blockedarray_free(el_blockedarray *a) {
  if (!a) return;
  if (a->allocation) EL_FREE(a->allocation);
  memset(a, 0, sizeof *a);
}

/* One row of a block at a time: a block row holds (1 << log_block) * channels consecutive floats. */
EL_DEF void el_blockedarray_get_rowmajor(const el_blockedarray *a, float *out) {
  int v, u0, bs, C;
  if (!a || !a->data || !out) return;
  bs = 1 << a->log_block;
  C = a->channels;
  for (v = 0; v < a->height; ++v)
    for (u0 = 0; u0 < a->width; u0 += bs) {
      int n = a->width - u0 < bs ? a->width - u0 : bs;
      memcpy(out + ((size_t)v * (size_t)a->width + (size_t)u0) * (size_t)C, el_blockedarray_at(a, u0, v),
             (size_t)n * (size_t)C * sizeof(float));
    }
}

EL_DEF void el_blockedarray_set_rowmajor(el_blockedarray *a, const float *in) {
  int v, u0, bs, C;
  if (!a || !a->data || !in) return;
  bs = 1 << a->log_block;
  C = a->channels;
  for (v = 0; v < a->height; ++v)
    for (u0 = 0; u0 < a->width; u0 += bs) {
      int n = a->width - u0 < bs ? a->width - u0 : bs;
      memcpy(el_blockedarray_at(a, u0, v), in + ((size_t)v * (size_t)a->width + (size_t)u0) * (size_t)C,
             (size_t)n * (size_t)C * sizeof(float));
    }
}

EL_DEF size_t el_blockedarray_bytes(const el_blockedarray *a) { return a ? a->allocated : 0; }
/* << blockedarray implementation */

#endif /* EL_BLOCKEDARRAY_IMPLEMENTATION_DONE */
#endif /* implementation */

/* Version history
 *   0.1.0  first release: init/free, (u, v) access, row-major copies, overflow checks.
 *
 * Licence: MIT or public domain (choose one), like stb.
 *   MIT: Copyright (c) 2026 the envlight authors. Permission is hereby granted, free of charge, to any
 *   person obtaining a copy of this software, to deal in it without restriction, including the rights
 *   to use, copy, modify, merge, publish, distribute, sublicense and/or sell copies, subject to
 *   including this notice. THE SOFTWARE IS PROVIDED "AS IS", WITHOUT WARRANTY OF ANY KIND.
 *   Public domain: anyone may use this file for any purpose, without any conditions.
 */
