/* test_tutorial_excerpts.c: the tutorials (every .md file in tutorials/ and tutorials/zh/) quote only what is
 * true: their code excerpts still stand in the files they name, the numbers they quote are still what
 * the programs print, and the pictures and files they link to exist.
 *
 * THE CONVENTION (write tutorials this way; this test enforces it)
 *  - An excerpt: the line `<!-- excerpt: PATH -->` (PATH relative to the repository root), then a
 *    fenced code block (blank lines may come between). Each line of the block, with the white space at
 *    both ends removed, must occur in PATH as a run of consecutive lines, blank lines ignored on both
 *    sides. A line that is only `...` (or `// ...`, or `...` inside a C block comment) in the block
 *    elides any number of lines of PATH: the parts around it must occur in that order.
 *  - Output: the line `<!-- output: PROGRAM ARGS -->`, then a fenced block. PROGRAM is run from the
 *    build's bin directory (build/bin/PROGRAM ARGS; the working directory is the build directory), and
 *    the block must be what it prints on stdout, exactly, indentation included (only white space at
 *    the ends of lines, blank lines, and the fence's own indentation inside a list item are ignored).
 *    A quote that leaves lines out says so: a line that is only `...` stands for one or more lines the
 *    program prints there (at the start: lines before the first one quoted; at the end: lines after
 *    the last). So the parts between `...` lines are runs of consecutive output lines, in order, and a
 *    block that does not start (end) with `...` starts (ends) where the output does. The same command
 *    is run once however many blocks quote it. Keep such
 *    commands to a few seconds: they run in every build of the suite, the sanitizer build included.
 *    A program that the build did not make (a benchmark in a build without benchmarks) is reported and
 *    skipped only when EL_HAVE_BENCH is 0 and its name starts with bench_; otherwise it is a failure.
 *  - Lab output: `<!-- lab output: PROGRAM -->` is an output block of a lab test program run on the
 *    repository's untouched lab file (lab_NN_untouched): the same check, but the program must exit
 *    with 1 (the lab fails with its diagnosis), not 0.
 *  - Labs: chapters 01 to 04 (both editions) each link to their lab, tutorials/labs/NN-*.
 *  - Links: every `![alt](path)` picture and every `[text](path)` link to a local file (no scheme, no
 *    leading #) must name a file that exists, relative to the tutorial's own directory.
 *
 * The test checks itself first (a wrong excerpt, a wrong output line and a missing picture must each
 * be caught), then every tutorial, and prints one line per failure with file:line.
 *   test_tutorial_excerpts [-v]     -v: also print every check that passed */
#define _POSIX_C_SOURCE 200809L
#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>

#ifndef EL_SOURCE_DIR
#define EL_SOURCE_DIR "."
#endif
#ifndef EL_BIN_DIR
#define EL_BIN_DIR "bin"
#endif
#ifndef EL_HAVE_BENCH
#define EL_HAVE_BENCH 1
#endif

static int g_fail, g_pass, g_verbose, g_silent;
static void report(int ok, const char *file, int line, const char *what, const char *detail) {
  if (ok) g_pass++;
  else g_fail++;
  if (g_silent) return;
  if (!ok || g_verbose) printf("%s: %s:%d: %s%s%s\n", ok ? "PASS" : "FAIL", file, line, what, detail ? ": " : "", detail ? detail : "");
}

/* ---- text as an array of lines ---------------------------------------------------------------- */
typedef struct lines { char **v; int n, cap; char *buf; } lines;

static void lines_free(lines *L) { free(L->v); free(L->buf); memset(L, 0, sizeof *L); }
static int lines_push(lines *L, char *s) {
  if (L->n == L->cap) {
    int cap = L->cap ? 2 * L->cap : 256;
    char **v = (char **)realloc(L->v, sizeof(char *) * (size_t)cap);
    if (!v) return -1;
    L->v = v; L->cap = cap;
  }
  L->v[L->n++] = s;
  return 0;
}
/* Splits text (taken over) into lines. */
static int lines_from(lines *L, char *text) {
  char *p = text;
  memset(L, 0, sizeof *L);
  L->buf = text;
  while (*p) {
    char *e = strchr(p, '\n');
    if (e) *e = 0;
    if (e && e > p && e[-1] == '\r') e[-1] = 0;
    if (lines_push(L, p)) return -1;
    if (!e) break;
    p = e + 1;
  }
  return 0;
}
#include "test_files.h" /* read_file */
/* Trimmed copy of s into out (at most n - 1 characters). */
static void trim(const char *s, char *out, size_t n) {
  const char *e;
  size_t k;
  while (*s == ' ' || *s == '\t') s++;
  e = s + strlen(s);
  while (e > s && (e[-1] == ' ' || e[-1] == '\t' || e[-1] == '\r')) e--;
  k = (size_t)(e - s) < n - 1 ? (size_t)(e - s) : n - 1;
  memmove(out, s, k); /* out may be s itself */
  out[k] = 0;
}
static int is_elision(const char *t) {
  return !strcmp(t, "...") || !strcmp(t, "// ...") || !strcmp(t, "/* ... */");
}

/* ---- excerpts --------------------------------------------------------------------------------- */
/* The trimmed non-blank lines of src (for matching). */
typedef struct tlines { char **v; int n; } tlines;
static void tlines_free(tlines *T) { int i; for (i = 0; i < T->n; i++) free(T->v[i]); free(T->v); T->v = NULL; T->n = 0; }
static int tlines_of(const lines *L, int from, int to, tlines *T) {
  int i;
  char t[4096];
  T->n = 0;
  T->v = (char **)malloc(sizeof(char *) * (size_t)(to - from + 1));
  if (!T->v) return -1;
  for (i = from; i < to; i++) {
    trim(L->v[i], t, sizeof t);
    if (!t[0]) continue;
    T->v[T->n] = strdup(t);
    if (!T->v[T->n]) return -1;
    T->n++;
  }
  return 0;
}
/* Does the excerpt (trimmed non-blank lines, with elisions) occur in src? On failure *bad is the index
 * of the first excerpt line of the segment that was not found. */
static int excerpt_found(const tlines *ex, const tlines *src, int *bad) {
  int i = 0, pos = 0;
  while (i < ex->n) {
    int j, len, start, found = -1;
    if (is_elision(ex->v[i])) { i++; continue; }
    for (j = i; j < ex->n && !is_elision(ex->v[j]); j++) {}
    len = j - i;
    for (start = pos; start + len <= src->n && found < 0; start++) {
      int k;
      for (k = 0; k < len && !strcmp(ex->v[i + k], src->v[start + k]); k++) {}
      if (k == len) found = start;
    }
    if (found < 0) { *bad = i; return 0; }
    pos = found + len;
    i = j;
  }
  return 1;
}

/* ---- program output, cached per command ------------------------------------------------------ */
typedef struct outcache { char *cmd[64]; char *out[64]; int ran[64]; int n; } outcache;
static outcache g_out;

/* Runs the command (once) and returns its stdout, or NULL (*missing = 1 when the program is absent). */
static const char *run_output(const char *cmdline, int *missing, int *status) {
  int i;
  char prog[512], path[1024], full[4096];
  const char *sp;
  FILE *p;
  size_t n = 0, cap = 0;
  char *out = NULL;
  *missing = 0; *status = 0;
  for (i = 0; i < g_out.n; i++)
    if (!strcmp(g_out.cmd[i], cmdline)) { *status = g_out.ran[i]; return g_out.out[i]; }
  sp = strchr(cmdline, ' ');
  snprintf(prog, sizeof prog, "%.*s", sp ? (int)(sp - cmdline) : (int)strlen(cmdline), cmdline);
  snprintf(path, sizeof path, "%s/%s", EL_BIN_DIR, prog);
  {
    struct stat st;
    if (stat(path, &st) != 0) { *missing = 1; return NULL; }
  }
  snprintf(full, sizeof full, "'%s'%s", path, sp ? sp : "");
  p = popen(full, "r");
  if (p) {
    char chunk[4096];
    size_t got;
    while ((got = fread(chunk, 1, sizeof chunk, p)) > 0) {
      if (n + got + 1 > cap) {
        char *o;
        cap = (n + got + 1) * 2;
        o = (char *)realloc(out, cap);
        if (!o) break;
        out = o;
      }
      memcpy(out + n, chunk, got);
      n += got;
    }
    *status = pclose(p);
  }
  if (!out) out = strdup("");
  else out[n] = 0;
  if (g_out.n < 64) {
    g_out.cmd[g_out.n] = strdup(cmdline);
    g_out.out[g_out.n] = out;
    g_out.ran[g_out.n] = *status;
    g_out.n++;
  }
  return out;
}
static int output_has_line(const char *out, const char *want) {
  const char *p = out;
  char t[4096];
  while (p && *p) {
    const char *e = strchr(p, '\n');
    size_t len = e ? (size_t)(e - p) : strlen(p);
    char line[4096];
    if (len >= sizeof line) len = sizeof line - 1;
    memcpy(line, p, len);
    line[len] = 0;
    trim(line, t, sizeof t);
    if (!strcmp(t, want)) return 1;
    p = e ? e + 1 : NULL;
  }
  return 0;
}

/* Copy of s without white space at its end (indentation kept) into out (at most n - 1 characters). */
static void rtrim(const char *s, char *out, size_t n) {
  const char *e = s + strlen(s);
  size_t k;
  while (e > s && (e[-1] == ' ' || e[-1] == '\t' || e[-1] == '\r')) e--;
  k = (size_t)(e - s) < n - 1 ? (size_t)(e - s) : n - 1;
  memmove(out, s, k);
  out[k] = 0;
}
/* The non-blank lines of text, right-trimmed, each with `strip` leading spaces removed where present. */
static int rlines_of(char *const *v, int count, int strip, tlines *T) {
  int i;
  char t[4096];
  T->n = 0;
  T->v = (char **)malloc(sizeof(char *) * (size_t)(count + 1));
  if (!T->v) return -1;
  for (i = 0; i < count; i++) {
    const char *s = v[i];
    int k;
    for (k = 0; k < strip && s[0] == ' '; k++) s++;
    rtrim(s, t, sizeof t);
    if (!t[0]) continue;
    T->v[T->n] = strdup(t);
    if (!T->v[T->n]) return -1;
    T->n++;
  }
  return 0;
}
/* Is the quoted block (q, right-trimmed, with `...` cut lines) what the program printed (o)? Each part
 * between cut lines is a run of consecutive output lines, in order; without a cut at the start (end)
 * the block starts (ends) with the output. Runs are placed as early as they fit (the last one against
 * the end when nothing may follow it). On failure *bad is the index of the first quoted line of the part
 * that was not found, and *why says what went wrong. */
static int output_block_found(const tlines *q, const tlines *o, int *bad, const char **why) {
  int i = 0, pos = 0, first = 1;
  *bad = 0; *why = "";
  while (i < q->n) {
    int j, len, start, found = -1, cut_before, cut_after;
    char t[4096];
    trim(q->v[i], t, sizeof t);
    if (is_elision(t)) { i++; first = 0; continue; }
    for (j = i; j < q->n; j++) { trim(q->v[j], t, sizeof t); if (is_elision(t)) break; }
    len = j - i;
    cut_before = !first;
    cut_after = j < q->n;
    if (!cut_before) { /* must start at the first output line (pos is 0) */
      int k;
      for (k = 0; k < len && pos + k < o->n && !strcmp(q->v[i + k], o->v[pos + k]); k++) {}
      if (k == len) found = pos;
    } else if (!cut_after) { /* the last part: must end at the last output line */
      start = o->n - len;
      if (start >= pos + 1) {
        int k;
        for (k = 0; k < len && !strcmp(q->v[i + k], o->v[start + k]); k++) {}
        if (k == len) found = start;
      }
    } else {
      for (start = pos + 1; start + len <= o->n && found < 0; start++) {
        int k;
        for (k = 0; k < len && !strcmp(q->v[i + k], o->v[start + k]); k++) {}
        if (k == len) found = start;
      }
    }
    if (found < 0) {
      *bad = i;
      *why = !cut_before ? "is not how the output starts (mark a cut with a `...` line)"
             : !cut_after ? "is not how the output ends (mark a cut with a `...` line)"
                          : "is not a run of consecutive output lines after the previous part (exact, indentation included)";
      return 0;
    }
    pos = found + len;
    first = 0;
    i = j;
    if (!cut_after && pos != o->n) { *bad = i - len; *why = "is followed by more output (mark a cut with a `...` line)"; return 0; }
  }
  /* a block that ends with `...` needs at least one line there */
  if (q->n > 0) {
    char t[4096];
    trim(q->v[q->n - 1], t, sizeof t);
    if (is_elision(t) && pos >= o->n) { *bad = q->n - 1; *why = "the cut at the end stands for no line"; return 0; }
  }
  return 1;
}

/* ---- one tutorial ---------------------------------------------------------------------------- */
static int file_exists(const char *path) { struct stat st; return stat(path, &st) == 0; }

/* The fenced block starting at or after line i (blank lines skipped): [*b0, *b1) are its content lines;
 * returns the index after the closing fence, or -1. */
static int fenced_block(const lines *L, int i, int *b0, int *b1) {
  char t[4096];
  while (i < L->n) { trim(L->v[i], t, sizeof t); if (t[0]) break; i++; }
  if (i >= L->n) return -1;
  trim(L->v[i], t, sizeof t);
  if (strncmp(t, "```", 3) != 0) return -1;
  *b0 = ++i;
  for (; i < L->n; i++) { trim(L->v[i], t, sizeof t); if (!strncmp(t, "```", 3)) { *b1 = i; return i + 1; } }
  return -1;
}

static void check_links(const char *file, const char *dir, int lineno, const char *s) {
  const char *p = s;
  while ((p = strstr(p, "](")) != NULL) {
    const char *q = p + 2, *e = strchr(q, ')');
    char target[1024], path[2048];
    size_t len;
    p = q;
    if (!e) break;
    len = (size_t)(e - q);
    if (len == 0 || len >= sizeof target) continue;
    memcpy(target, q, len);
    target[len] = 0;
    if (strstr(target, "://") || target[0] == '#' || !strncmp(target, "mailto:", 7)) continue;
    { char *h = strchr(target, '#'); if (h) *h = 0; }
    { char *sp = strchr(target, ' '); if (sp) *sp = 0; } /* [x](path "title") */
    if (!target[0]) continue;
    snprintf(path, sizeof path, "%s/%s", dir, target);
    report(file_exists(path), file, lineno, "link target exists", target);
  }
}

/* Checks one markdown text; `file` for messages, `dir` its directory (links). Returns failures. */
static int check_text(const char *file, const char *dir, char *text) {
  lines L;
  int i, before = g_fail, in_fence = 0;
  char t[4096];
  if (lines_from(&L, text)) { report(0, file, 0, "out of memory", NULL); return 1; }
  for (i = 0; i < L.n; i++) {
    trim(L.v[i], t, sizeof t);
    if (!strncmp(t, "```", 3)) in_fence = !in_fence;
    if (!in_fence) check_links(file, dir, i + 1, L.v[i]);
    if (in_fence) continue;
    if (!strncmp(t, "<!-- excerpt:", 13) || !strncmp(t, "<!-- output:", 12) || !strncmp(t, "<!-- lab output:", 16)) {
      int excerpt = t[5] == 'e', lab = t[5] == 'l', b0 = 0, b1 = 0, next;
      char arg[2048], *end;
      snprintf(arg, sizeof arg, "%s", t + (excerpt ? 13 : lab ? 16 : 12));
      end = strstr(arg, "-->");
      if (!end) { report(0, file, i + 1, "marker without -->", t); continue; }
      *end = 0;
      trim(arg, arg, sizeof arg);
      next = fenced_block(&L, i + 1, &b0, &b1);
      if (next < 0) { report(0, file, i + 1, "marker not followed by a fenced block", t); continue; }
      if (excerpt) {
        char path[2048], *src;
        snprintf(path, sizeof path, "%s/%s", EL_SOURCE_DIR, arg);
        src = read_file(path);
        if (!src) report(0, file, i + 1, "excerpt's file cannot be read", arg);
        else {
          lines S;
          tlines ts, te;
          int bad = 0, ok;
          lines_from(&S, src);
          tlines_of(&S, 0, S.n, &ts);
          tlines_of(&L, b0, b1, &te);
          ok = te.n > 0 && excerpt_found(&te, &ts, &bad);
          if (!ok && te.n > 0) {
            char msg[2048];
            snprintf(msg, sizeof msg, "%s: no longer has \"%s\"", arg, te.v[bad]);
            report(0, file, i + 1, "excerpt", msg);
          } else report(ok, file, i + 1, "excerpt", arg);
          tlines_free(&ts); tlines_free(&te);
          lines_free(&S);
        }
      } else {
        int missing = 0, status = 0, k;
        const char *out = run_output(arg, &missing, &status);
        if (missing) {
          if (!EL_HAVE_BENCH && !strncmp(arg, "bench_", 6)) printf("SKIP: %s:%d: %s (benchmarks not built)\n", file, i + 1, arg);
          else report(0, file, i + 1, "output: program not built", arg);
        } else {
          if (lab)
            report(WIFEXITED(status) && WEXITSTATUS(status) == 1, file, i + 1, "lab output: program exits with 1", arg);
          else
            report(status == 0, file, i + 1, "output: program exits with 0", arg);
          {
            /* the fence's own indentation (a block inside a list item) is not part of the quote */
            int strip = 0, bad = 0, ok;
            const char *why = "";
            char *copy = strdup(out), msg[2048 + 4096 + 256];
            lines O;
            tlines tq, to;
            while (L.v[b0 - 1][strip] == ' ') strip++;
            (void)k;
            if (!copy || lines_from(&O, copy)) { report(0, file, i + 1, "out of memory", NULL); }
            else {
              rlines_of(L.v + b0, b1 - b0, strip, &tq);
              rlines_of(O.v, O.n, 0, &to);
              ok = tq.n > 0 && output_block_found(&tq, &to, &bad, &why);
              if (!ok && tq.n > 0) {
                int at = b0, seen = -1; /* the markdown line of quoted line `bad` */
                for (at = b0; at < b1; at++) { char w[4096]; rtrim(L.v[at], w, sizeof w); if (w[0] && ++seen == bad) break; }
                snprintf(msg, sizeof msg, "%s: \"%s\" %s", arg, tq.v[bad], why);
                report(0, file, at + 1, "output", msg);
              } else report(ok, file, i + 1, "output", arg);
              tlines_free(&tq); tlines_free(&to);
              lines_free(&O);
            }
          }
        }
      }
      i = next - 1;
    }
  }
  lines_free(&L);
  return g_fail - before;
}

/* ---- the test checks itself ------------------------------------------------------------------- */
static void self_test(void) {
  const char *md =
      "<!-- excerpt: tests/test_tutorial_excerpts.c -->\n```c\nstatic int is_elision(const char *t) {\n...\n}\n```\n"
      "<!-- excerpt: tests/test_tutorial_excerpts.c -->\n```c\nint this_line_is_not_in_the_file(void);\n```\n"
      "![missing](no_such_picture_here.png)\n";
  char *text = strdup(md);
  int before_fail = g_fail, before_pass = g_pass, failed;
  g_silent = 1;
  failed = check_text("(self-test)", EL_SOURCE_DIR, text); /* takes text over */
  g_silent = 0;
  g_fail = before_fail; g_pass = before_pass;
  /* one good excerpt, one bad excerpt, one missing picture: exactly two failures */
  report(failed == 2, "(self-test)", 0, "a wrong excerpt and a missing picture are caught, a right excerpt passes", NULL);
  {
    /* quoted output: exact lines, indentation kept, cuts marked with `...` */
    static char o0[] = "head", o1[] = "  loop time 0.38 s  ", o2[] = "  level 1", o3[] = "tail";
    static char *ov[] = {o0, o1, o2, o3};
    static char q_all0[] = "head", q_all1[] = "  loop time 0.38 s", q_all2[] = "  level 1", q_all3[] = "tail";
    static char *q_all[] = {q_all0, q_all1, q_all2, q_all3};
    static char c0[] = "...", c1[] = "  loop time 0.38 s", c2[] = "...";
    static char *q_mid[] = {c0, c1, c2};
    static char n1[] = "loop time 0.38 s"; /* indentation lost */
    static char *q_noindent[] = {c0, n1, c2};
    static char *q_uncut[] = {c1, o2}; /* the head line left out without a `...` */
    static char *q_gap[] = {o0, o2, o3}; /* a line left out in the middle without a `...` */
    static char *q_end[] = {o0, c1, q_all2}; /* the tail line left out without a `...` */
    static char *q_mid2[] = {c0, q_all2, c2}; /* "  level 1": a middle line, cut on both sides */
    static char w2[] = "  loop time 0.39 s";
    static char *q_number[] = {c0, w2, c2};
    tlines o, q;
    int bad, all_ok;
    const char *why;
    rlines_of(ov, 4, 0, &o);
    rlines_of(q_all, 4, 0, &q); all_ok = output_block_found(&q, &o, &bad, &why); tlines_free(&q);
    rlines_of(q_mid, 3, 0, &q); all_ok = all_ok && output_block_found(&q, &o, &bad, &why); tlines_free(&q);
    rlines_of(q_mid2, 3, 0, &q); all_ok = all_ok && output_block_found(&q, &o, &bad, &why); tlines_free(&q);
    report(all_ok, "(self-test)", 0, "a whole output and a part cut with `...` at both ends are found", NULL);
    rlines_of(q_noindent, 3, 0, &q); all_ok = !output_block_found(&q, &o, &bad, &why); tlines_free(&q);
    rlines_of(q_uncut, 2, 0, &q); all_ok = all_ok && !output_block_found(&q, &o, &bad, &why); tlines_free(&q);
    rlines_of(q_gap, 3, 0, &q); all_ok = all_ok && !output_block_found(&q, &o, &bad, &why); tlines_free(&q);
    rlines_of(q_end, 3, 0, &q); all_ok = all_ok && !output_block_found(&q, &o, &bad, &why); tlines_free(&q);
    rlines_of(q_number, 3, 0, &q); all_ok = all_ok && !output_block_found(&q, &o, &bad, &why); tlines_free(&q);
    report(all_ok, "(self-test)", 0, "lost indentation, an unmarked cut at the start, in the middle or at the end, and a wrong number are caught", NULL);
    tlines_free(&o);
    (void)output_has_line;
  }
}

int main(int argc, char **argv) {
  const char *dirs[2] = {"tutorials", "tutorials/zh"};
  int d, files = 0;
  if (argc > 1 && !strcmp(argv[1], "-v")) g_verbose = 1;
  self_test();
  for (d = 0; d < 2; d++) {
    char dir[2048];
    DIR *D;
    struct dirent *e;
    char *names[256];
    /* names are at most 255 bytes (d_name) */
    int n = 0, i;
    snprintf(dir, sizeof dir, "%s/%s", EL_SOURCE_DIR, dirs[d]);
    D = opendir(dir);
    if (!D) { if (d == 0) report(0, dirs[d], 0, "directory exists", NULL); continue; }
    while ((e = readdir(D)) != NULL && n < 256) {
      size_t len = strlen(e->d_name);
      if (len > 3 && !strcmp(e->d_name + len - 3, ".md")) names[n++] = strdup(e->d_name);
    }
    closedir(D);
    for (i = 0; i < n; i++) {
      char path[4096 + 256], shown[256 + 64], *text;
      snprintf(path, sizeof path, "%s/%s", dir, names[i]);
      snprintf(shown, sizeof shown, "%s/%s", dirs[d], names[i]);
      text = read_file(path);
      if (text && names[i][0] == '0' && names[i][1] >= '1' && names[i][1] <= '4' && names[i][2] == '-') {
        char want[32];
        snprintf(want, sizeof want, "labs/0%c-", names[i][1]);
        report(strstr(text, want) != NULL, shown, 0, "the chapter links to its lab", want);
      }
      if (!text) report(0, shown, 0, "readable", NULL);
      else { check_text(shown, dir, text); files++; }
      free(names[i]);
    }
  }
  printf("%d tutorial files, %d checks passed, %d failed\n", files, g_pass, g_fail);
  return g_fail ? 1 : 0;
}
