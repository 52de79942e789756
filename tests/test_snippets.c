/* test_snippets.c: every C snippet of README.md and of the five headers' front comments compiles as
 * C99 and as C++11 and C++17, with the compilers CMake found, warnings as errors (C: -std=c99 -Wall
 * -Wextra -pedantic -Werror; C++: -std=c++11 / -std=c++17 -Wall -Wextra -Werror), so that the
 * documentation cannot drift from the API. Snippets that carry a recipe (each header's, README's first)
 * are also linked, as C99, and README's recipe as C++11 too: that proves the recipe's first line alone
 * implements what the usage calls. The other compiles stop after the checks (-fsyntax-only, which still
 * reports every warning of -Wall -Wextra but those that need the optimiser), to keep the test fast.
 *
 * WHERE SNIPPETS ARE FOUND
 *  - README.md: every fenced block that opens with ```c (and ends with ```).
 *  - A header: the lines between ` * >> usage` and ` * << usage` in its front comment, each written
 *    ` *     code` (the first 7 characters are dropped), so the code may hold only // comments.
 *    The header's recipe is the front comment's lines written ` *     #...` (the #define and #include
 *    under "DO THIS"): the usage is compiled after the recipe alone, so a recipe whose first line does
 *    not implement everything the usage calls fails to link.
 *
 * HOW A SNIPPET BECOMES A PROGRAM
 *  - Its lines that start with # (preprocessor lines) go first. A README snippet without an #include is
 *    preceded by `#define EL_IMPLEMENTATION` and the five headers instead.
 *  - A line `// given: T a, *b; U c[3];  (any remark)` (or the same in a block comment) declares what
 *    the snippet takes from its surroundings: up to the last ';', its declarations become the parameters
 *    of the function the snippet is wrapped in, `int el_snippet_N(T a, T *b, U c[3])`, whose body is
 *    the snippet (in its own block) followed by `return 0;`. An unused given is an error (-Wextra), so
 *    the given line stays exact. A snippet may `return 1;` on failure.
 *  - C and C++ spell a zeroed struct differently. A snippet writes the C spelling `= {0}` and, on the
 *    same line, the remark `C++: = {}`; the C++ compiles replace `= {0}` by `= {}`. A `= {0}` without
 *    the remark is an error of the snippet (this test fails), so both spellings are always documented.
 *  - main() is empty: the program is compiled (and linked, see above), never run.
 *
 * A README snippet that is a header's usage block character for character (with the same given line)
 * is the same program: it is compiled once, and reported for both.
 *
 * The test checks itself first: a snippet with an undeclared name and the mipmap usage compiled as C++
 * without the `= {}` spelling must both fail to compile, or the harness is not testing anything.
 * Sources and compiler output are kept in test_snippets.d/ of the working directory (the build dir).
 *
 *   EL_SNIPPETS_VERBOSE=1 test_snippets   prints every generated source. */
#define _POSIX_C_SOURCE 200809L
#include <ctype.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#ifndef EL_SOURCE_DIR
#define EL_SOURCE_DIR "."
#endif
#ifndef EL_C_COMPILER
#define EL_C_COMPILER "cc"
#endif
#ifndef EL_CXX_COMPILER
#define EL_CXX_COMPILER "c++"
#endif

static int g_pass, g_fail;
static void check(int ok, const char *what) {
  if (ok) g_pass++;
  else g_fail++;
  printf("%s: %s\n", ok ? "PASS" : "FAIL", what);
}

#include "test_files.h" /* read_file */

/* A growing string. */
typedef struct str {
  char *p;
  size_t n, cap;
} str;
static void put(str *s, const char *t, size_t len) {
  if (s->n + len + 1 > s->cap) {
    size_t c = s->cap ? s->cap : 256;
    while (c < s->n + len + 1) c *= 2;
    s->p = (char *)realloc(s->p, c);
    s->cap = c;
  }
  memcpy(s->p + s->n, t, len);
  s->n += len;
  s->p[s->n] = 0;
}
static void puts_(str *s, const char *t) { put(s, t, strlen(t)); }

typedef struct snippet {
  char name[128];
  str pre;    /* preprocessor lines (the recipe), each ending in \n */
  str code;   /* the body, each line ending in \n */
  str params; /* from the given line */
  int has_include;
} snippet;

static void trim_end(char *s) {
  size_t n = strlen(s);
  while (n && (s[n - 1] == ' ' || s[n - 1] == '\t' || s[n - 1] == '\r')) s[--n] = 0;
}

/* `T a, *b; U c[3]` -> "T a, T *b, U c[3]": in each declaration the base type is what precedes the
 * first declarator (its first '*', or else its name, the last identifier before any '['). Returns 0 on a
 * malformed declaration. */
static int given_to_params(const char *decls, str *out) {
  char buf[1024], *d, *save = NULL;
  const char *end = strrchr(decls, ';');
  size_t n;
  if (!end) return 0;
  n = (size_t)(end - decls);
  if (n >= sizeof buf) return 0;
  memcpy(buf, decls, n);
  buf[n] = 0;
  for (d = strtok_r(buf, ";", &save); d; d = strtok_r(NULL, ";", &save)) {
    char base[256], *p, *save2 = NULL, *first_end, *name_end, *name, *star, *start;
    while (*d == ' ') ++d;
    if (!*d) continue;
    first_end = strchr(d, ',');
    if (!first_end) first_end = d + strlen(d);
    name_end = memchr(d, '[', (size_t)(first_end - d));
    if (!name_end) name_end = first_end;
    while (name_end > d && name_end[-1] == ' ') --name_end;
    name = name_end;
    while (name > d && (isalnum((unsigned char)name[-1]) || name[-1] == '_')) --name;
    if (name == name_end || name == d) return 0; /* no name, or no type before it */
    star = memchr(d, '*', (size_t)(name - d));
    start = star ? star : name;
    n = (size_t)(start - d);
    if (n >= sizeof base) return 0;
    memcpy(base, d, n);
    base[n] = 0;
    trim_end(base);
    if (!*base) return 0;
    for (p = strtok_r(start, ",", &save2); p; p = strtok_r(NULL, ",", &save2)) {
      while (*p == ' ') ++p;
      trim_end(p);
      if (!*p) return 0;
      if (out->n) puts_(out, ", ");
      puts_(out, base);
      puts_(out, " ");
      puts_(out, p);
    }
  }
  return 1;
}

/* Adds one code line to a snippet: preprocessor lines to pre, a given line to params. */
static int add_line(snippet *sn, const char *line) {
  const char *t = line, *g;
  while (*t == ' ') ++t;
  if (*t == '#') {
    puts_(&sn->pre, t);
    puts_(&sn->pre, "\n");
    if (!strncmp(t, "#include", 8)) sn->has_include = 1;
    return 1;
  }
  g = strstr(line, "given:");
  if (g && (!strncmp(t, "//", 2) || !strncmp(t, "/*", 2))) return given_to_params(g + 6, &sn->params);
  puts_(&sn->code, line);
  puts_(&sn->code, "\n");
  return 1;
}

#define MAX_SNIPPETS 32
static snippet g_sn[MAX_SNIPPETS];
static int g_nsn;

static void readme_snippets(const char *text) {
  const char *p = text;
  int k = 0;
  while ((p = strstr(p, "```c\n")) && g_nsn < MAX_SNIPPETS) {
    const char *b = p + 5, *e = strstr(b, "```");
    snippet *sn = &g_sn[g_nsn++];
    char line[1024];
    memset(sn, 0, sizeof *sn);
    snprintf(sn->name, sizeof sn->name, "README.md snippet %d", ++k);
    if (!e) break;
    while (b < e) {
      const char *nl = memchr(b, '\n', (size_t)(e - b));
      size_t n = nl ? (size_t)(nl - b) : (size_t)(e - b);
      if (n >= sizeof line) n = sizeof line - 1;
      memcpy(line, b, n);
      line[n] = 0;
      if (!add_line(sn, line)) {
        printf("FAIL: %s: a malformed given line: %s\n", sn->name, line);
        g_fail++;
      }
      b += n + 1;
    }
    p = e + 3;
  }
}

static void header_snippet(const char *file, const char *text) {
  const char *front_end = strstr(text, "*/"), *a = strstr(text, " * >> usage\n"), *b = strstr(text, " * << usage\n"), *p;
  snippet *sn = &g_sn[g_nsn++];
  char line[1024];
  memset(sn, 0, sizeof *sn);
  snprintf(sn->name, sizeof sn->name, "%s usage", file);
  if (!front_end || !a || !b || a > b || b > front_end) {
    printf("FAIL: %s: no ` * >> usage` ... ` * << usage` block in the front comment\n", file);
    g_fail++;
    --g_nsn;
    return;
  }
  /* the recipe: front-comment lines ` *     #...` */
  for (p = text; p < front_end;) {
    const char *nl = strchr(p, '\n');
    size_t n = nl ? (size_t)(nl - p) : strlen(p);
    if (n > 7 && !strncmp(p, " *     #", 8)) {
      if (n - 7 >= sizeof line) n = sizeof line + 6;
      memcpy(line, p + 7, n - 7);
      line[n - 7] = 0;
      add_line(sn, line);
    }
    p += n + 1;
  }
  for (p = a + strlen(" * >> usage\n"); p < b;) {
    const char *nl = strchr(p, '\n');
    size_t n = (size_t)(nl - p);
    if (n < 7 || strncmp(p, " *     ", 7)) {
      printf("FAIL: %s: a usage line not written ` *     code`: %.*s\n", file, (int)n, p);
      g_fail++;
    } else {
      if (n - 7 >= sizeof line) n = sizeof line + 6;
      memcpy(line, p + 7, n - 7);
      line[n - 7] = 0;
      if (!add_line(sn, line)) {
        printf("FAIL: %s: a malformed given line: %s\n", sn->name, line);
        g_fail++;
      }
    }
    p = nl + 1;
  }
}

/* The code for C++: `= {0}` -> `= {}` on lines that document it; 0 if a `= {0}` is undocumented. */
static int cxx_code(const snippet *sn, str *out, char *why, size_t whylen) {
  const char *p = sn->code.p ? sn->code.p : "";
  while (*p) {
    const char *nl = strchr(p, '\n');
    size_t n = nl ? (size_t)(nl - p) + 1 : strlen(p);
    char line[1024], *z;
    if (n >= sizeof line) n = sizeof line - 1;
    memcpy(line, p, n);
    line[n] = 0;
    z = strstr(line, "= {0}");
    if (z) {
      if (!strstr(line, "C++: = {}")) {
        snprintf(why, whylen, "`= {0}` without its C++ spelling (the remark `C++: = {}`): %s", line);
        return 0;
      }
      memmove(z + 3, z + 4, strlen(z + 4) + 1); /* "= {0}" -> "= {}" */
    }
    puts_(out, line);
    p += n;
  }
  return 1;
}

static int verbose(void) { return getenv("EL_SNIPPETS_VERBOSE") != NULL; }

/* Writes the program for snippet sn (code: the body to use) and compiles it in language lang (0: C99,
 * 1: C++11, 2: C++17), linking it when link is set. Returns 1 when the compiler succeeded. */
static int build(const snippet *sn, const char *code, int lang, int index, const char *tag, int link) {
  static const char *ext[3] = {"c", "cc", "cc"};
  char src[512], exe[512], log[512], cmd[4096];
  FILE *f;
  int r;
  snprintf(src, sizeof src, "test_snippets.d/%s%d_%d.%s", tag, index, lang, ext[lang]);
  snprintf(exe, sizeof exe, "test_snippets.d/%s%d_%d.exe", tag, index, lang);
  snprintf(log, sizeof log, "test_snippets.d/%s%d_%d.log", tag, index, lang);
  f = fopen(src, "w");
  if (!f) return 0;
  fprintf(f, "/* %s, generated by tests/test_snippets.c */\n", sn->name);
  if (sn->has_include) fputs(sn->pre.p, f);
  else {
    fputs("#define EL_IMPLEMENTATION\n#include \"blockedarray.h\"\n#include \"mipmap.h\"\n"
          "#include \"distribution2d.h\"\n#include \"envlight.h\"\n#include \"film.h\"\n", f);
    if (sn->pre.p) fputs(sn->pre.p, f);
  }
  fprintf(f, "int el_snippet_%d(%s);\nint el_snippet_%d(%s) {\n  {\n", index, sn->params.n ? sn->params.p : "void", index,
          sn->params.n ? sn->params.p : "void");
  {
    const char *p = code;
    while (*p) {
      const char *nl = strchr(p, '\n');
      size_t n = nl ? (size_t)(nl - p) + 1 : strlen(p);
      fputs("    ", f);
      fwrite(p, 1, n, f);
      p += n;
    }
  }
  fputs("  }\n  return 0;\n}\nint main(void) { return 0; }\n", f);
  fclose(f);
  if (verbose()) {
    char *t = read_file(src);
    printf("---- %s ----\n%s", src, t ? t : "");
    free(t);
  }
  if (link)
    snprintf(cmd, sizeof cmd, "'%s' %s -Wall -Wextra %s-Werror -I'%s' '%s' -o '%s' -lm > '%s' 2>&1",
             lang ? EL_CXX_COMPILER : EL_C_COMPILER, lang == 0 ? "-std=c99" : lang == 1 ? "-std=c++11" : "-std=c++17",
             lang == 0 ? "-pedantic " : "", EL_SOURCE_DIR, src, exe, log);
  else
    snprintf(cmd, sizeof cmd, "'%s' %s -Wall -Wextra %s-Werror -fsyntax-only -I'%s' '%s' > '%s' 2>&1",
             lang ? EL_CXX_COMPILER : EL_C_COMPILER, lang == 0 ? "-std=c99" : lang == 1 ? "-std=c++11" : "-std=c++17",
             lang == 0 ? "-pedantic " : "", EL_SOURCE_DIR, src, log);
  r = system(cmd);
  if (r != 0 && strcmp(tag, "selfcheck") != 0) {
    char *t = read_file(log);
    printf("  %s\n  %s\n%s\n", cmd, src, t ? t : "");
    free(t);
  }
  remove(exe);
  return r == 0;
}

int main(void) {
  static const char *headers[5] = {"blockedarray.h", "mipmap.h", "distribution2d.h", "envlight.h", "film.h"};
  static const char *lang_name[3] = {"C99", "C++11", "C++17"};
  char path[1024], msg[8192];
  int i, lang, readme_count;
  char *t;
  mkdir("test_snippets.d", 0777);
  snprintf(path, sizeof path, "%s/README.md", EL_SOURCE_DIR);
  t = read_file(path);
  check(t != NULL, "read README.md");
  if (t) readme_snippets(t);
  free(t);
  readme_count = g_nsn;
  snprintf(msg, sizeof msg, "README.md: %d ```c snippets found (at least 6: the recipe and one per header)", readme_count);
  check(readme_count >= 6, msg);
  for (i = 0; i < 5; ++i) {
    snprintf(path, sizeof path, "%s/%s", EL_SOURCE_DIR, headers[i]);
    t = read_file(path);
    if (!t) {
      snprintf(msg, sizeof msg, "read %s", path);
      check(0, msg);
      continue;
    }
    header_snippet(headers[i], t);
    free(t);
  }
  snprintf(msg, sizeof msg, "5 header usage blocks found (%d)", g_nsn - readme_count);
  check(g_nsn - readme_count == 5, msg);

  /* the harness must be able to fail */
  {
    snippet bad;
    str cxx = {0, 0, 0};
    char why[2048];
    int k, mip = -1;
    memset(&bad, 0, sizeof bad);
    snprintf(bad.name, sizeof bad.name, "self-check: an undeclared name");
    puts_(&bad.code, "el_mipmap m;\nel_mipmap_init(&m, no_such_image, 4, 4, 3, NULL);\n");
    check(!build(&bad, bad.code.p, 0, 0, "selfcheck", 0), "self-check: a snippet using an undeclared name fails to compile as C99");
    for (k = readme_count; k < g_nsn; ++k)
      if (strstr(g_sn[k].name, "mipmap.h")) mip = k;
    if (mip >= 0) {
      check(!build(&g_sn[mip], g_sn[mip].code.p, 1, 1, "selfcheck", 0),
            "self-check: mipmap.h's usage compiled as C++11 with the C spelling `= {0}` fails (the C++ spelling is needed)");
      check(cxx_code(&g_sn[mip], &cxx, why, sizeof why), "self-check: mipmap.h's usage documents its C++ spelling");
    }
    free(cxx.p);
    free(bad.code.p);
  }

  for (i = 0; i < g_nsn; ++i) {
    int same = -1, k;
    for (k = readme_count; k < g_nsn && i < readme_count; ++k)
      if (!g_sn[i].has_include && g_sn[i].code.p && g_sn[k].code.p && !strcmp(g_sn[i].code.p, g_sn[k].code.p) &&
          !strcmp(g_sn[i].params.p ? g_sn[i].params.p : "", g_sn[k].params.p ? g_sn[k].params.p : ""))
        same = k;
    if (same >= 0) {
      snprintf(msg, sizeof msg, "%s is %s, character for character (compiled below)", g_sn[i].name, g_sn[same].name);
      check(1, msg);
      continue;
    }
    for (lang = 0; lang < 3; ++lang) {
      str cxx = {0, 0, 0};
      char why[2048] = "";
      int ok, link;
      const char *code = g_sn[i].code.p ? g_sn[i].code.p : "";
      if (lang > 0) {
        if (!cxx_code(&g_sn[i], &cxx, why, sizeof why)) {
          snprintf(msg, sizeof msg, "%s as %s: %s", g_sn[i].name, lang_name[lang], why);
          check(0, msg);
          free(cxx.p);
          continue;
        }
        code = cxx.p ? cxx.p : "";
      }
      link = g_sn[i].has_include && (lang == 0 || (lang == 1 && i < readme_count));
      ok = build(&g_sn[i], code, lang, i + 1, "snippet", link);
      snprintf(msg, sizeof msg, "%s %s as %s%s", g_sn[i].name, link ? "compiles and links" : "compiles", lang_name[lang],
               g_sn[i].has_include ? " after its own recipe alone" : "");
      check(ok, msg);
      free(cxx.p);
    }
  }
  for (i = 0; i < g_nsn; ++i) {
    free(g_sn[i].pre.p);
    free(g_sn[i].code.p);
    free(g_sn[i].params.p);
  }
  printf("test_snippets: %d passed, %d failed\n", g_pass, g_fail);
  return g_fail != 0;
}
