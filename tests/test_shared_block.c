/* test_shared_block.c: every root header that carries the shared declarations (el_result, EL_MALLOC,
 * EL_ASSERT, EL_DEF; see DEVELOPERS.md) carries them verbatim, byte for byte equal to
 * docs/shared_block.h. The block is guarded by EL_SHARED_DECLARATIONS, so whichever header a user
 * includes first defines it: a header whose copy drifted would give different declarations depending on
 * the include order. mipmap.h gets the block through blockedarray.h and must not carry a second copy. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifndef EL_SOURCE_DIR
#error "EL_SOURCE_DIR must name the repository root"
#endif

static int passes = 0, failures = 0;
static void check(int ok, const char *what, const char *name) {
  if (ok) { passes++; printf("PASS %s: %s\n", name, what); }
  else { failures++; printf("FAIL %s: %s\n", name, what); }
}

#include "test_files.h" /* read_source */

int main(void) {
  static const char *const with_block[] = {"blockedarray.h", "distribution2d.h", "envlight.h", "film.h"};
  const char *begin = "/* >> shared declarations", *end_marker = "/* << shared declarations */\n";
  char *ref = read_source("docs/shared_block.h"), *mip;
  size_t i;
  if (!ref) { printf("FAIL cannot read docs/shared_block.h\n"); return 1; }
  for (i = 0; i < sizeof with_block / sizeof with_block[0]; i++) {
    char *h = read_source(with_block[i]), *a, *b;
    if (!h) { check(0, "readable", with_block[i]); continue; }
    a = strstr(h, begin);
    b = a ? strstr(a, end_marker) : NULL;
    check(a && b, "has the shared block markers", with_block[i]);
    if (a && b) {
      size_t len = (size_t)(b - a) + strlen(end_marker);
      check(len == strlen(ref) && memcmp(a, ref, len) == 0, "shared block equals docs/shared_block.h", with_block[i]);
      check(strstr(b + 1, begin) == NULL, "carries the block once", with_block[i]);
    }
    free(h);
  }
  mip = read_source("mipmap.h");
  check(mip && !strstr(mip, begin) && strstr(mip, "#include \"blockedarray.h\""),
        "takes the block from blockedarray.h, no copy of its own", "mipmap.h");
  free(mip);
  free(ref);
  printf("test_shared_block: %d passed, %d failed\n", passes, failures);
  return failures != 0;
}
