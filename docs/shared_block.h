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
