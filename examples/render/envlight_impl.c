/* envlight_impl.c: the one translation unit that compiles envlight's headers (film.h, envlight.h,
 * mipmap.h, distribution2d.h, blockedarray.h), as every user of a header-only library has one
 * (stb's "#define STB_IMAGE_IMPLEMENTATION" file). The rest of the renderer includes the headers for
 * their declarations only and calls el_film_*, el_envlight_*, el_mipmap_* where it uses them.
 *
 * Why it is more than the five #defines: the headers allocate through EL_MALLOC (their documented
 * hook), and the renderer gives large tables transparent huge pages. Tables of 2 MiB and more (the
 * environment's texels, its sampling tables, MIP levels) are 2 MiB aligned and marked MADV_HUGEPAGE.
 * The renderer reads them at random directions: with 4 KiB pages nearly every such read also missed
 * the TLB (the 6 MB map and the 8 MB pdf and CDF tables of pbrt-v3's importance map span thousands of
 * pages). Smaller blocks and reallocations are plain malloc / realloc; free() takes both. */
#if defined(__linux__) && !defined(_DEFAULT_SOURCE)
#define _DEFAULT_SOURCE /* madvise */
#endif
#include <stdlib.h>
#if defined(__linux__)
#include <sys/mman.h>
#endif

static void *elr__malloc(size_t n) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  const size_t huge = (size_t)2 << 20;
  if (n >= huge) {
    void *p = NULL;
    if (posix_memalign(&p, huge, n) != 0) return NULL;
    (void)madvise(p, n & ~(huge - 1), MADV_HUGEPAGE); /* a hint: without it the pages are just small */
    return p;
  }
#endif
  return malloc(n);
}
#define EL_MALLOC(sz) elr__malloc(sz)
#define EL_REALLOC(p, newsz) realloc(p, newsz)
#define EL_FREE(p) free(p)

#define EL_FILM_IMPLEMENTATION
#define EL_ENVLIGHT_IMPLEMENTATION
#define EL_DISTRIBUTION2D_IMPLEMENTATION
#define EL_MIPMAP_IMPLEMENTATION
#define EL_BLOCKEDARRAY_IMPLEMENTATION
#include "film.h"
#include "envlight.h"
#include "mipmap.h"
