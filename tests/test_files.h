/* test_files.h: reading a whole file into a NUL-terminated buffer, for the tests that read the
 * repository's own text (headers, README, tutorials, logs). */
#ifndef TEST_FILES_H
#define TEST_FILES_H
#include <stdio.h>
#include <stdlib.h>

/* the file's bytes and a final 0 (free it), or NULL when it cannot be read */
static char *read_file(const char *path) {
  FILE *f = fopen(path, "rb");
  char *b;
  long n;
  if (!f) return NULL;
  if (fseek(f, 0, SEEK_END) || (n = ftell(f)) < 0 || fseek(f, 0, SEEK_SET)) { fclose(f); return NULL; }
  b = (char *)malloc((size_t)n + 1);
  if (b && fread(b, 1, (size_t)n, f) != (size_t)n) { free(b); b = NULL; }
  if (b) b[n] = 0;
  fclose(f);
  return b;
}

#ifdef EL_SOURCE_DIR
/* the same for a path relative to the repository's root */
static inline char *read_source(const char *rel) {
  char path[1024];
  snprintf(path, sizeof path, "%s/%s", EL_SOURCE_DIR, rel);
  return read_file(path);
}
#endif
#endif
