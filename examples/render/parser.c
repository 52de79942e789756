/* parser.c: the pbrt-v3 scene file's syntax (pbrt-v3 core/parser.cpp): the tokenizer, the files that
 * Include reads, errors and warnings with file:line, the parse's arena and its named tables (textures,
 * materials, coordinate systems, objects: hashed). elr_parse (api.c) runs the directives over the tokens.
 *
 * The parser's files (parser.h holds what they share), each calling only the ones before it:
 *   parser.c          the syntax, the arena, the named tables             core/parser.cpp
 *   paramset.c        parameter lists ("type name" value...)              core/paramset.cpp
 *   api_options.c     Camera, Film, PixelFilter, Sampler, Integrator      core/api.cpp's MakeCamera ...
 *   api_lights.c      LightSource, AreaLightSource                        core/api.cpp's MakeLight ...
 *   api_shapes.c      Shape                                               core/api.cpp's MakeShapes
 *   api_materials.c   Material, MakeNamedMaterial, Texture                core/api.cpp's MakeMaterial ...
 *   api.c             the directives, the CTM, the graphics state;        core/api.cpp's pbrtTranslate ...
 *                     elr_parse                                           pbrtParseFile
 * The parser describes: shapes, materials and textures are added to the scene as they are read; an
 * image texture is an elr_imagemap_desc and an infinite light an elr_infinite_desc that scene.c builds
 * after the parse (reading their images), so that no parser file calls the library or lights.c.
 *
 * Errors abort the parse with "file:line: message" (longjmp to elr_parse; every allocation of the parse
 * lives in an arena freed there, scene pieces belong to the scene). Unsupported directives and
 * parameters are warnings naming file:line and what is ignored. */
#include "parser.h"
#include "image_io.h"

void *elr__alloc(elr__parser *P, size_t n) {
  elr__block *b = (elr__block *)malloc(sizeof(elr__block) + n + 16);
  if (!b) { snprintf(P->err, P->errlen, "out of memory"); longjmp(P->jb, 1); }
  b->next = P->arena; P->arena = b;
  return (void *)((char *)b + sizeof(elr__block) + (16 - sizeof(elr__block) % 16) % 16);
}
/* An arena block that can still grow: slot's block reallocated to hold n bytes (the contents kept, the
 * data at the same offset as elr__alloc's), then handed to the arena by elr__grow_keep. A parameter of
 * 1e8 values then costs its final array, not every array of the doublings that led to it. */
void *elr__grow(elr__parser *P, int slot, size_t n) {
  elr__block *b = (elr__block *)realloc(P->growing[slot], sizeof(elr__block) + n + 16);
  if (!b) { snprintf(P->err, P->errlen, "out of memory"); longjmp(P->jb, 1); }
  P->growing[slot] = b;
  return (void *)((char *)b + sizeof(elr__block) + (16 - sizeof(elr__block) % 16) % 16);
}
void elr__grow_keep(elr__parser *P, int slot) {
  elr__block *b = P->growing[slot];
  P->growing[slot] = NULL;
  b->next = P->arena; P->arena = b;
}
char *elr__strdup(elr__parser *P, const char *s, size_t n) {
  char *r = (char *)elr__alloc(P, n + 1);
  memcpy(r, s, n); r[n] = 0; return r;
}
/* a copy that outlives the parse (the scene's descriptions own it) */
char *elr__heap_strdup(elr__parser *P, const char *str) {
  size_t n = strlen(str) + 1;
  char *r = (char *)malloc(n);
  if (!r) { snprintf(P->err, P->errlen, "out of memory"); longjmp(P->jb, 1); }
  memcpy(r, str, n);
  return r;
}
/* An error at file:line. The file is given explicitly wherever the line is a directive's or a
 * parameter's: the lexer leaves an included file as soon as it peeks past its last token, so the
 * current file may already be the includer (errors in an included file's last directive named the
 * includer with the included file's line). elr__failf and elr__failv never return (they longjmp to
 * elr_parse). */
#if defined(__GNUC__) || defined(__clang__)
static void elr__failv(elr__parser *P, const char *file, int line, const char *fmt, va_list ap) __attribute__((noreturn));
#endif
static void elr__verror(char *err, size_t errlen, const char *file, int line, const char *fmt, va_list ap) {
  char msg[400];
  vsnprintf(msg, sizeof msg, fmt, ap);
  { /* a quoted string of the scene may hold control characters: keep them off the terminal */
    char *c;
    for (c = msg; *c; c++) if ((unsigned char)*c < 32 || *c == 127) *c = *c == '\n' || *c == '\t' ? ' ' : '?';
  }
  snprintf(err, errlen, "%s:%d: error: %s", file ? file : "?", line, msg);
}
/* the same message for what is built of the scene's descriptions after the parse (scene.c) */
void elr_error(char *err, size_t errlen, const char *file, int line, const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  elr__verror(err, errlen, file, line, fmt, ap);
  va_end(ap);
}
static void elr__failv(elr__parser *P, const char *file, int line, const char *fmt, va_list ap) {
  elr__verror(P->err, P->errlen, file, line, fmt, ap);
  longjmp(P->jb, 1);
}
void elr__failf(elr__parser *P, const char *file, int line, const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  elr__failv(P, file, line, fmt, ap);
  va_end(ap);
}
/* an error at a line of the file being read now (the lexer's errors) */
void elr__fail(elr__parser *P, int line, const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  elr__failv(P, P->nlex ? P->lex[P->nlex - 1].file : "?", line, fmt, ap);
  va_end(ap);
}

void elr_warn(elr_scene *s, const char *file, int line, const char *fmt, ...) {
  char msg[400];
  va_list ap; va_start(ap, fmt); vsnprintf(msg, sizeof msg, fmt, ap); va_end(ap);
  {
    char *c;
    for (c = msg; *c; c++) if ((unsigned char)*c < 32 || *c == 127) *c = *c == '\n' || *c == '\t' ? ' ' : '?';
  }
  snprintf(s->last_warning, sizeof s->last_warning, "%s:%d: warning: %s", file, line, msg);
  s->warnings++;
  if (!s->quiet) fprintf(stderr, "%s\n", s->last_warning);
}

/* A warning that is given once per key (the first occurrence's file:line); returns 1 when it was given.
 * At most ELR_MAX_WARNED keys are remembered (keys come from the scene's own names); past that, one last
 * line says that further unsupported features are not reported. */
#define ELR_MAX_WARNED 512
void elr__warn_once(elr__parser *P, const char *file, int line, const char *key, const char *fmt, ...) {
  char msg[400];
  va_list ap;
  int i;
  for (i = 0; i < P->nwarned; i++) if (!strcmp(P->warned[i], key)) return;
  if (P->nwarned >= ELR_MAX_WARNED) {
    if (P->nwarned == ELR_MAX_WARNED) {
      elr_warn(P->s, file, line, "more than %d different unsupported features: the rest are not reported", ELR_MAX_WARNED);
      P->nwarned++;
    }
    return;
  }
  if (P->nwarned == P->capwarned) {
    int nc = P->capwarned ? 2 * P->capwarned : 16;
    char **nw = (char **)realloc(P->warned, sizeof(char *) * (size_t)nc);
    if (!nw) { snprintf(P->err, P->errlen, "out of memory"); longjmp(P->jb, 1); }
    P->warned = nw; P->capwarned = nc;
  }
  P->warned[P->nwarned] = (char *)elr__alloc(P, strlen(key) + 1);
  memcpy(P->warned[P->nwarned], key, strlen(key) + 1);
  P->nwarned++;
  va_start(ap, fmt); vsnprintf(msg, sizeof msg, fmt, ap); va_end(ap);
  elr_warn(P->s, file, line, "%s (reported once)", msg);
}

/* >> tokenizer */
static elr__tok elr__lex(elr__parser *P) {
  elr__tok t; memset(&t, 0, sizeof t);
  for (;;) {
    elr__lexer *L;
    if (P->nlex == 0) { t.kind = T_EOF; return t; }
    L = &P->lex[P->nlex - 1];
    while (L->p < L->end) {
      char c = *L->p;
      if (c == '\n') { L->line++; L->p++; }
      else if (c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v') L->p++;
      else if (c == '#') { while (L->p < L->end && *L->p != '\n') L->p++; }
      else break;
    }
    if (L->p >= L->end) {
      if (P->nlex == 1) { t.kind = T_EOF; t.line = L->line; return t; }
      P->nlex--; /* end of an included file: continue with the includer */
      continue;
    }
    t.line = L->line;
    {
      char c = *L->p;
      if (c == '[') { t.kind = T_LBR; L->p++; return t; }
      if (c == ']') { t.kind = T_RBR; L->p++; return t; }
      if (c == '"') {
        const char *q = ++L->p;
        char *buf; size_t n = 0;
        while (L->p < L->end && *L->p != '"') {
          if (*L->p == '\n') elr__fail(P, t.line, "unterminated string (a newline inside quotes)");
          if (*L->p == '\\' && L->p + 1 < L->end) { /* an escape: the next character is taken as it is */
            L->p++;
            if (*L->p == '\n') elr__fail(P, t.line, "unterminated string (a newline inside quotes)");
          }
          L->p++;
        }
        if (L->p >= L->end) elr__fail(P, t.line, "unterminated string at end of file");
        buf = (char *)elr__alloc(P, (size_t)(L->p - q) + 1);
        while (q < L->p) {
          char ch = *q++;
          if (ch == '\\' && q < L->p) {
            ch = *q++;
            if (ch == 'n') ch = '\n'; else if (ch == 't') ch = '\t';
          }
          buf[n++] = ch;
        }
        buf[n] = 0; L->p++;
        t.kind = T_STRING; t.s = buf; t.len = n; return t;
      }
      if (isdigit((unsigned char)c) || c == '-' || c == '+' || c == '.') {
        char tmp[80]; size_t n = 0; char *endp;
        const char *q = L->p;
        while (q < L->end && (isalnum((unsigned char)*q) || *q == '-' || *q == '+' || *q == '.')) q++;
        n = (size_t)(q - L->p);
        if (n >= sizeof tmp) elr__fail(P, t.line, "number too long");
        memcpy(tmp, L->p, n); tmp[n] = 0;
        errno = 0;
        t.num = strtod(tmp, &endp);
        if (*endp != 0 || endp == tmp) elr__fail(P, t.line, "malformed number \"%s\"", tmp);
        if (!isfinite(t.num)) elr__fail(P, t.line, "number \"%s\" is not finite", tmp);
        L->p = q; t.kind = T_NUM; t.s = NULL; return t;
      }
      if (isalpha((unsigned char)c) || c == '_') {
        const char *q = L->p;
        while (q < L->end && (isalnum((unsigned char)*q) || *q == '_')) q++;
        t.kind = T_WORD; t.s = L->p; t.len = (size_t)(q - L->p); L->p = q; return t;
      }
      if ((unsigned char)c < 32 || (unsigned char)c >= 127)
        elr__fail(P, t.line, "unexpected byte 0x%02x (is this a pbrt-v3 text file?)", (unsigned char)c);
      elr__fail(P, t.line, "unexpected character '%c'", c);
    }
  }
}
elr__tok elr__next(elr__parser *P) {
  if (P->has_peek) { P->has_peek = 0; return P->peeked; }
  return elr__lex(P);
}
elr__tok elr__peek(elr__parser *P) {
  if (!P->has_peek) { P->peeked = elr__lex(P); P->has_peek = 1; }
  return P->peeked;
}
int elr__wordis(const elr__tok *t, const char *w) {
  return t->kind == T_WORD && strlen(w) == t->len && memcmp(t->s, w, t->len) == 0;
}
const char *elr__curfile(elr__parser *P) { return P->lex[P->nlex - 1].file; }

double elr__num(elr__parser *P, const char *what) {
  elr__tok t = elr__next(P);
  if (t.kind != T_NUM) elr__failf(P, t.kind == T_EOF ? P->dir_file : elr__curfile(P), t.kind == T_EOF ? P->dir_line : t.line, "%s: expected a number%s", what,
                                 t.kind == T_EOF ? " (file ends early)" : "");
  return t.num;
}
const char *elr__str(elr__parser *P, const char *what) {
  elr__tok t = elr__next(P);
  if (t.kind != T_STRING) elr__failf(P, t.kind == T_EOF ? P->dir_file : elr__curfile(P), t.kind == T_EOF ? P->dir_line : t.line, "%s: expected a quoted string%s",
                                    what, t.kind == T_EOF ? " (file ends early)" : "");
  return t.s;
}
/* Transform / ConcatTransform: 16 numbers, in brackets or not. */
void elr__nums16(elr__parser *P, double *m, const char *what) {
  int i, br = 0;
  if (elr__peek(P).kind == T_LBR) { elr__next(P); br = 1; }
  for (i = 0; i < 16; i++) m[i] = elr__num(P, what);
  if (br) {
    elr__tok t = elr__next(P);
    if (t.kind != T_RBR) elr__fail(P, t.line, "%s: expected ']' after 16 numbers", what);
  }
}
static unsigned elr__hash(const char *s) {
  unsigned h = 2166136261u;
  while (*s) { h ^= (unsigned char)*s++; h *= 16777619u; }
  return h;
}
/* the slot of name (*found) or the slot to put it in */
static int elr__hslot(const elr__hmap *h, const elr__named *arr, const char *name, int *found) {
  int i = (int)(elr__hash(name) & (unsigned)(h->cap - 1)), free_slot = -1;
  *found = 0;
  for (;;) {
    int v = h->s[i];
    if (v == -1) return free_slot >= 0 ? free_slot : i;
    if (v == -2) { if (free_slot < 0) free_slot = i; }
    else if (!strcmp(arr[v].name, name)) { *found = 1; return i; }
    i = (i + 1) & (h->cap - 1);
  }
}
/* The entry of name among the first n (the latest one), or -1. */
int elr__name_find(const elr__hmap *h, const elr__named *arr, int n, const char *name) {
  int found, k;
  if (h->cap == 0) return -1;
  k = h->s[elr__hslot(h, arr, name, &found)];
  if (!found) return -1;
  while (k >= n) k = arr[k].prev;
  return k;
}
/* Index entry k (its name set; the latest entry of the list). */
void elr__name_add(elr__parser *P, elr__hmap *h, elr__named *arr, int k) {
  int found, slot;
  if ((h->used + 1) * 2 > h->cap) { /* grow (and drop removed slots) */
    elr__hmap g;
    int i;
    g.cap = h->cap ? h->cap * 2 : 64;
    g.used = 0;
    g.s = (int *)malloc(sizeof(int) * (size_t)g.cap);
    if (!g.s) { snprintf(P->err, P->errlen, "out of memory"); longjmp(P->jb, 1); }
    for (i = 0; i < g.cap; i++) g.s[i] = -1;
    for (i = 0; i < h->cap; i++)
      if (h->s[i] >= 0) { g.s[elr__hslot(&g, arr, arr[h->s[i]].name, &found)] = h->s[i]; g.used++; }
    free(h->s);
    *h = g;
  }
  slot = elr__hslot(h, arr, arr[k].name, &found);
  arr[k].prev = found ? h->s[slot] : -1;
  if (!found && h->s[slot] == -1) h->used++;
  h->s[slot] = k;
}
/* Forget entries [to, from) (names of closed scopes), the latest first. */
void elr__name_drop(elr__hmap *h, elr__named *arr, int from, int to) {
  int k, found, slot;
  for (k = from - 1; k >= to; k--) {
    slot = elr__hslot(h, arr, arr[k].name, &found);
    if (found && h->s[slot] == k) h->s[slot] = arr[k].prev >= 0 ? arr[k].prev : -2;
  }
}

char *elr__resolve(elr__parser *P, const char *name) {
  size_t n;
  char *r;
  if (name[0] == '/' || !P->base_dir || !P->base_dir[0]) return elr__strdup(P, name, strlen(name));
  n = strlen(P->base_dir) + strlen(name) + 2;
  r = (char *)elr__alloc(P, n);
  snprintf(r, n, "%s/%s", P->base_dir, name);
  return r;
}

void elr__parse_file(elr__parser *P, const char *text, size_t len, const char *name) {
  elr__lexer *L;
  if (P->nlex >= ELR_MAX_INCLUDE) elr__failf(P, P->dir_file, P->dir_line, "Include nested more than %d deep (recursive include?)", ELR_MAX_INCLUDE);
  L = &P->lex[P->nlex++];
  L->text = L->p = text; L->end = text + len; L->file = name; L->line = 1;
}

char *elr__read_file(elr__parser *P, const char *path, size_t *len, int line) {
  FILE *f;
  long n;
  char *buf, why[128];
  if (el_file_is_regular(path, why, sizeof why) != 0) elr__failf(P, P->dir_file, line, "cannot read \"%s\": %s", path, why);
  f = fopen(path, "rb");
  if (!f) elr__failf(P, P->dir_file, line, "cannot open \"%s\": %s", path, strerror(errno));
  errno = 0;
  if (getc(f) == EOF && ferror(f)) { /* a directory opens, but reading it fails (and its size is nonsense) */
    int e = errno;
    fclose(f);
    elr__failf(P, P->dir_file, line, "cannot read \"%s\": %s", path, e ? strerror(e) : "read error");
  }
  if (fseek(f, 0, SEEK_END) != 0 || (n = ftell(f)) < 0 || fseek(f, 0, SEEK_SET) != 0) {
    fclose(f); elr__failf(P, P->dir_file, line, "cannot read \"%s\"", path);
  }
  if (n > (1L << 30)) { fclose(f); elr__failf(P, P->dir_file, line, "\"%s\" is larger than 1 GiB", path); }
  buf = (char *)elr__alloc(P, (size_t)n + 1);
  if (n > 0 && fread(buf, 1, (size_t)n, f) != (size_t)n) { fclose(f); elr__failf(P, P->dir_file, line, "cannot read \"%s\"", path); }
  fclose(f);
  buf[n] = 0; *len = (size_t)n;
  return buf;
}

void elr__skip_args(elr__parser *P) {
  for (;;) {
    elr__tok t = elr__peek(P);
    if (t.kind == T_EOF) return;
    if (t.kind == T_WORD && !elr__wordis(&t, "true") && !elr__wordis(&t, "false")) return;
    elr__next(P);
  }
}

void elr__directive_block(elr__parser *P, int need_world, const char *what) {
  if (need_world && !P->in_world) {
    elr_warn(P->s, P->dir_file, P->dir_line, "%s before WorldBegin is not allowed; ignoring it", what);
  }
  if (!need_world && P->in_world) {
    elr_warn(P->s, P->dir_file, P->dir_line, "%s inside the world block is not allowed; ignoring it", what);
  }
}
