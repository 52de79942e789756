/* test_names.c: the naming rule of DEVELOPERS.md, checked on the five headers' declarations.
 *
 * Every public name a header defines before its implementation section starts with that header's
 * module prefix: functions and types el_<module>..., macros and enumerators EL_<MODULE>_... (the
 * shared block's EL_SUCCESS / EL_ERROR_*, EL_DEF, EL_MALLOC... are the one exception, and are skipped
 * with the block). And every enum has its own enumerator prefix: no enumerator of one enum starts with
 * another enum's common prefix, in the same header or another (pbrt's MIP filters and pixel filters
 * once both began with EL_FILTER_, so `fo.filter.type = EL_FILTER_BILINEAR` compiled in C and chose a
 * Gaussian pixel filter).
 *
 * What counts as "defined here" (comments stripped first): `#define NAME`, `typedef struct|enum NAME`,
 * `} NAME;`, the enumerators between an enum's braces, and the function name of a line that starts with
 * EL_DEF or `static inline`. Names a header only uses (envlight.h's el_distribution2d) are not checked
 * against it. */
#include <ctype.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifndef EL_SOURCE_DIR
#define EL_SOURCE_DIR "."
#endif

static int g_pass, g_fail;
static void check(int ok, const char *what) {
  if (ok) g_pass++;
  else {
    g_fail++;
    printf("FAIL: %s\n", what);
  }
}

typedef struct header {
  const char *file;
  const char *prefixes[6]; /* allowed prefixes of defined names (NULL-terminated) */
} header;

static const header headers[] = {
    {"blockedarray.h", {"el_blockedarray", "EL_BLOCKEDARRAY_", NULL}},
    {"mipmap.h", {"el_mipmap", "EL_MIPMAP_", NULL}},
    /* the distributions module: 1D and 2D, one options struct and one constant prefix for both */
    {"distribution2d.h", {"el_distribution1d", "el_distribution2d", "el_distribution_", "EL_DISTRIBUTION_",
                          "EL_DISTRIBUTION2D_", NULL}},
    {"envlight.h", {"el_envlight", "EL_ENVLIGHT_", NULL}},
    {"film.h", {"el_film", "EL_FILM_", NULL}},
};
#define NHEADERS ((int)(sizeof headers / sizeof headers[0]))

#include "test_files.h" /* read_source */

/* Comments and string literals become spaces (newlines kept). */
static void strip(char *s) {
  char *p = s;
  while (*p) {
    if (p[0] == '/' && p[1] == '*') {
      char *e = strstr(p + 2, "*/");
      char *end = e ? e + 2 : p + strlen(p);
      for (; p < end; ++p)
        if (*p != '\n') *p = ' ';
    } else if (p[0] == '/' && p[1] == '/') {
      for (; *p && *p != '\n'; ++p) *p = ' ';
    } else if (*p == '"') {
      *p++ = ' ';
      for (; *p && *p != '"'; ++p) {
        if (*p == '\\' && p[1]) *p++ = ' ';
        *p = ' ';
      }
      if (*p) *p++ = ' ';
    } else {
      ++p;
    }
  }
}

/* Blanks out [from, to) of s, where from is the first occurrence of `a` and to the end of the first
 * occurrence of `b` after it. */
static void blank_between(char *s, const char *a, const char *b) {
  char *p = strstr(s, a), *e;
  if (!p) return;
  e = strstr(p, b);
  e = e ? e + strlen(b) : p + strlen(p);
  for (; p < e; ++p)
    if (*p != '\n') *p = ' ';
}

static int is_id(int c) { return isalnum(c) || c == '_'; }

static int starts(const char *s, const char *p) { return strncmp(s, p, strlen(p)) == 0; }

typedef struct names {
  char name[1024][64];
  int enum_id[1024]; /* -1: not an enumerator; else which enum (counted over all headers) */
  int header[1024];
  int n;
} names;

static void add(names *ns, const char *p, int len, int hdr, int enum_id) {
  if (ns->n >= 1024 || len >= 64) return;
  memcpy(ns->name[ns->n], p, (size_t)len);
  ns->name[ns->n][len] = 0;
  ns->header[ns->n] = hdr;
  ns->enum_id[ns->n] = enum_id;
  ns->n++;
}

/* The identifier at p (an el_/EL_ name) and its length. */
static int id_len(const char *p) {
  int n = 0;
  while (is_id((unsigned char)p[n])) ++n;
  return n;
}
static const char *skip_space(const char *p) {
  while (*p == ' ' || *p == '\t' || *p == '\n' || *p == '\r') ++p;
  return p;
}

static const char *skip_blank(const char *p) { /* spaces and tabs, within a line */
  while (*p == ' ' || *p == '\t') ++p;
  return p;
}

static int g_enums = 0;

static void collect(const char *s, int hdr, names *ns) {
  const char *p = s;
  while (*p) {
    const char *line = p, *q;
    while (*p && *p != '\n') ++p;
    q = skip_blank(line);
    if (starts(q, "#define")) {
      q = skip_space(q + 7);
      if (starts(q, "el_") || starts(q, "EL_")) add(ns, q, id_len(q), hdr, -1);
    } else if (starts(q, "typedef enum") || starts(q, "typedef struct")) {
      const char *t = skip_space(q + (q[8] == 'e' ? 12 : 14));
      if (starts(t, "el_")) add(ns, t, id_len(t), hdr, -1);
      if (q[8] == 'e') { /* the enumerators: first identifier of each comma-separated item */
        const char *b = strchr(t, '{'), *e = b ? strchr(b, '}') : NULL;
        int id = g_enums++;
        if (b && e) {
          const char *r = b + 1;
          while (r < e) {
            r = skip_space(r);
            if (r < e && (starts(r, "EL_") || starts(r, "el_"))) add(ns, r, id_len(r), hdr, id);
            while (r < e && *r != ',') ++r;
            if (r < e) ++r;
          }
        }
      }
    } else if (q[0] == '}') {
      const char *t = skip_space(q + 1);
      if (starts(t, "el_")) add(ns, t, id_len(t), hdr, -1);
    } else if (starts(q, "EL_DEF ") || starts(q, "static inline ")) {
      /* the function's name: the first el_ identifier followed by '(' */
      const char *r = q;
      while (r < p) {
        if ((starts(r, "el_") || starts(r, "EL_")) && (r == s || !is_id((unsigned char)r[-1]))) {
          int n = id_len(r);
          if (*skip_space(r + n) == '(') {
            add(ns, r, n, hdr, -1);
            break;
          }
          r += n;
        } else {
          ++r;
        }
      }
    }
    if (*p) ++p;
  }
}

int main(void) {
  names ns;
  int h, i, j;
  char msg[512];
  memset(&ns, 0, sizeof ns);
  for (h = 0; h < NHEADERS; ++h) {
    char *s = read_source(headers[h].file), *impl;
    if (!s) {
      snprintf(msg, sizeof msg, "read %s/%s", EL_SOURCE_DIR, headers[h].file);
      check(0, msg);
      continue;
    }
    blank_between(s, "#ifndef EL_SHARED_DECLARATIONS", "#endif /* EL_SHARED_DECLARATIONS */");
    strip(s);
    /* the implementation section: private names, not checked */
    impl = strstr(s, "#if defined(EL_IMPLEMENTATION)");
    if (impl) *impl = 0;
    collect(s, h, &ns);
    free(s);
  }
  if (getenv("TEST_NAMES_LIST")) /* TEST_NAMES_LIST=1 test_names: every name found, with its enum */
    for (i = 0; i < ns.n; ++i) printf("%s %s %d\n", headers[ns.header[i]].file, ns.name[i], ns.enum_id[i]);
  check(ns.n > 100, "the headers' declarations were found (more than 100 defined names)");
  /* 1. module prefixes */
  for (i = 0; i < ns.n; ++i) {
    const header *hd = &headers[ns.header[i]];
    const char *first = hd->prefixes[0] ? hd->prefixes[0] : "";
    int ok = 0, k;
    for (k = 0; hd->prefixes[k]; ++k) ok |= starts(ns.name[i], hd->prefixes[k]);
    snprintf(msg, sizeof msg, "%s: %s starts with the module's prefix (%s...)", hd->file, ns.name[i], first);
    check(ok, msg);
  }
  /* 2. one enumerator prefix per enum: the common prefix (to its last '_') of an enum's enumerators
   * begins no enumerator of another enum */
  for (i = 0; i < ns.n; ++i) {
    char common[64];
    int len = -1, cut, count = 0, first = 1;
    if (ns.enum_id[i] < 0) continue;
    for (j = 0; j < i; ++j) first &= ns.enum_id[j] != ns.enum_id[i];
    if (!first) continue; /* each enum once */
    for (j = 0; j < ns.n; ++j) {
      int k = 0;
      if (ns.enum_id[j] != ns.enum_id[i]) continue;
      ++count;
      if (len < 0) {
        strcpy(common, ns.name[j]);
        len = (int)strlen(common);
        continue;
      }
      while (k < len && common[k] == ns.name[j][k]) ++k;
      len = k;
    }
    for (cut = len; cut > 0 && common[cut - 1] != '_'; --cut) {}
    common[cut] = 0;
    if (cut == 0 || count < 2) continue;
    for (j = 0; j < ns.n; ++j) {
      if (ns.enum_id[j] < 0 || ns.enum_id[j] == ns.enum_id[i]) continue;
      if (starts(ns.name[j], common)) {
        snprintf(msg, sizeof msg, "%s (%s) does not start with %s, the prefix of another enum (%s, %s)", ns.name[j],
                 headers[ns.header[j]].file, common, ns.name[i], headers[ns.header[i]].file);
        check(0, msg);
      }
    }
  }
  printf("test_names: %d passed, %d failed (%d names)\n", g_pass, g_fail, ns.n);
  return g_fail != 0;
}
