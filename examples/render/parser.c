/* parser.c: the pbrt-v3 scene-file subset (see el_render.h and the issue's list).
 *
 * pbrt-v3's api.cpp in miniature: a tokenizer, parameter lists ("type name" value...), the current
 * transformation matrix (CTM) with its stack, named coordinate systems, the graphics state (material,
 * named textures) and the render options (camera, film, filter, sampler, integrator). Shapes, lights,
 * textures and materials are added to the scene as they are read.
 *
 * Errors abort the parse with "file:line: message" (longjmp to elr_parse; every allocation of the parse
 * lives in an arena freed there, scene pieces belong to the scene). Unsupported directives and
 * parameters are warnings naming file:line and what is ignored. */
#include "elr_internal.h"
#include "image_io.h"
#include <ctype.h>
#include <errno.h>
#include <float.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

/* >> arena */
typedef struct elr__block { struct elr__block *next; } elr__block;

/* >> tokens */
enum { T_EOF = 0, T_WORD, T_STRING, T_NUM, T_LBR, T_RBR };
typedef struct elr__tok { int kind, line; const char *s; size_t len; double num; } elr__tok;

typedef struct elr__lexer {
  const char *text, *p, *end;
  const char *file; /* name used in messages */
  int line;
} elr__lexer;

typedef struct elr__param {
  char type[64], name[128];
  double *num; char **str; int n, isstr, used, line;
  const char *file;
} elr__param;

#define ELR_MAX_PARAMS 64
#define ELR_MAX_INCLUDE 32
#define ELR_MAX_STACK 1024

typedef struct elr__gstate {
  int material;
  int *ftex_names; /* unused: named textures are stored globally with their scope below */
  int ntex_scope;  /* number of named textures visible */
  int nnamed_mat;  /* number of named materials visible */
  int reverse;     /* ReverseOrientation */
  int end_only;    /* ActiveTransform EndTime: transformations go to the end time, which is not rendered */
  int area;        /* AreaLightSource: 1 + its index in elr__parser.areas, 0 for none */
} elr__gstate;

/* an AreaLightSource "diffuse" directive: what each shape after it in its attribute block emits */
typedef struct elr__area { elr_v3 L; int twosided, nsamples; } elr__area;

typedef struct elr__named { char *name; int index; int is_float; int prev; /* the entry it shadows, or -1 */ } elr__named;
/* A hash index over a list of names (open addressing; a slot holds the latest entry of its name, -1
 * empty, -2 removed): a list of 100000 named textures, materials or coordinate systems took 25-75 s to
 * parse with linear lookups. */
typedef struct elr__hmap { int *s; int cap, used; } elr__hmap;

typedef struct elr__parser {
  elr_scene *s;
  jmp_buf jb;
  char *err; size_t errlen;
  elr__block *arena;
  elr__block *growing[2]; /* a parameter's value arrays while they grow (elr__grow), not yet in the arena */
  elr__lexer lex[ELR_MAX_INCLUDE];
  int nlex;
  elr__tok peeked; int has_peek;
  const char *base_dir;
  /* state */
  elr_xform ctm;
  elr_xform xstack[ELR_MAX_STACK];
  elr__gstate gs, gstack[ELR_MAX_STACK];
  char stack_kind[ELR_MAX_STACK]; /* 'a' attribute, 't' transform */
  int depth;
  elr__named *ctx; int nctx, capctx; /* named coordinate systems (index into cs_xf) */
  elr_xform *cs_xf;
  elr__named *texnames; int ntexn, captexn;
  elr__named *matnames; int nmatn, capmatn;
  elr__hmap hctx, htex, hmat, hobj;
  elr__named *objnames; int nobjn, capobjn; /* ObjectBegin names -> elr_object */
  int in_world, world_ended, seen_camera;
  elr__area *areas; int nareas, capareas;
  int light_param; /* reading a light's L, I or scale: spectral values must not be negative (elr__pspectral) */
  const char *integ_file; int integ_line; /* the Integrator directive, for a warning at WorldEnd */
  elr_xform camera_ctm;
  elr__param params[ELR_MAX_PARAMS]; int nparams;
  const char *dir_file; int dir_line; /* current directive, for messages */
  char dir_name[64];
  /* what was said once already (elr__warn_once): unsupported directives, types and parameters are
   * reported at their first occurrence only, so that a scene of 10^5 shapes gives one line, not 10^5 */
  char **warned; int nwarned, capwarned;
  int cur_object; /* the ObjectBegin block being read (its elr_object), or -1 */
} elr__parser;

static void *elr__alloc(elr__parser *P, size_t n) {
  elr__block *b = (elr__block *)malloc(sizeof(elr__block) + n + 16);
  if (!b) { snprintf(P->err, P->errlen, "out of memory"); longjmp(P->jb, 1); }
  b->next = P->arena; P->arena = b;
  return (void *)((char *)b + sizeof(elr__block) + (16 - sizeof(elr__block) % 16) % 16);
}
/* An arena block that can still grow: slot's block reallocated to hold n bytes (the contents kept, the
 * data at the same offset as elr__alloc's), then handed to the arena by elr__grow_keep. A parameter of
 * 1e8 values then costs its final array, not every array of the doublings that led to it. */
static void *elr__grow(elr__parser *P, int slot, size_t n) {
  elr__block *b = (elr__block *)realloc(P->growing[slot], sizeof(elr__block) + n + 16);
  if (!b) { snprintf(P->err, P->errlen, "out of memory"); longjmp(P->jb, 1); }
  P->growing[slot] = b;
  return (void *)((char *)b + sizeof(elr__block) + (16 - sizeof(elr__block) % 16) % 16);
}
static void elr__grow_keep(elr__parser *P, int slot) {
  elr__block *b = P->growing[slot];
  P->growing[slot] = NULL;
  b->next = P->arena; P->arena = b;
}
static char *elr__strdup(elr__parser *P, const char *s, size_t n) {
  char *r = (char *)elr__alloc(P, n + 1);
  memcpy(r, s, n); r[n] = 0; return r;
}

/* An error at file:line. The file is given explicitly wherever the line is a directive's or a
 * parameter's: the lexer leaves an included file as soon as it peeks past its last token, so the
 * current file may already be the includer (errors in an included file's last directive named the
 * includer with the included file's line). */
/* It never returns (it longjmps to elr_parse): saying so lets the compiler see that a value checked by a
 * failing branch is set on every path that goes on (clang's -Wsometimes-uninitialized). */
#if defined(__GNUC__) || defined(__clang__)
static void elr__failv(elr__parser *P, const char *file, int line, const char *fmt, va_list ap) __attribute__((noreturn));
static void elr__failf(elr__parser *P, const char *file, int line, const char *fmt, ...) __attribute__((noreturn));
#endif
static void elr__failv(elr__parser *P, const char *file, int line, const char *fmt, va_list ap) {
  char msg[400];
  vsnprintf(msg, sizeof msg, fmt, ap);
  { /* a quoted string of the scene may hold control characters: keep them off the terminal */
    char *c;
    for (c = msg; *c; c++) if ((unsigned char)*c < 32 || *c == 127) *c = *c == '\n' || *c == '\t' ? ' ' : '?';
  }
  snprintf(P->err, P->errlen, "%s:%d: error: %s", file ? file : "?", line, msg);
  longjmp(P->jb, 1);
}
static void elr__failf(elr__parser *P, const char *file, int line, const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  elr__failv(P, file, line, fmt, ap);
  va_end(ap);
}
/* an error at a line of the file being read now (the lexer's errors) */
static void elr__fail(elr__parser *P, int line, const char *fmt, ...) {
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
static void elr__warn_once(elr__parser *P, const char *file, int line, const char *key, const char *fmt, ...) {
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
static elr__tok elr__next(elr__parser *P) {
  if (P->has_peek) { P->has_peek = 0; return P->peeked; }
  return elr__lex(P);
}
static elr__tok elr__peek(elr__parser *P) {
  if (!P->has_peek) { P->peeked = elr__lex(P); P->has_peek = 1; }
  return P->peeked;
}
static int elr__wordis(const elr__tok *t, const char *w) {
  return t->kind == T_WORD && strlen(w) == t->len && memcmp(t->s, w, t->len) == 0;
}
static const char *elr__curfile(elr__parser *P) { return P->lex[P->nlex - 1].file; }

static double elr__num(elr__parser *P, const char *what) {
  elr__tok t = elr__next(P);
  if (t.kind != T_NUM) elr__failf(P, t.kind == T_EOF ? P->dir_file : elr__curfile(P), t.kind == T_EOF ? P->dir_line : t.line, "%s: expected a number%s", what,
                                 t.kind == T_EOF ? " (file ends early)" : "");
  return t.num;
}
static const char *elr__str(elr__parser *P, const char *what) {
  elr__tok t = elr__next(P);
  if (t.kind != T_STRING) elr__failf(P, t.kind == T_EOF ? P->dir_file : elr__curfile(P), t.kind == T_EOF ? P->dir_line : t.line, "%s: expected a quoted string%s",
                                    what, t.kind == T_EOF ? " (file ends early)" : "");
  return t.s;
}
/* Transform / ConcatTransform: 16 numbers, in brackets or not. */
static void elr__nums16(elr__parser *P, double *m, const char *what) {
  int i, br = 0;
  if (elr__peek(P).kind == T_LBR) { elr__next(P); br = 1; }
  for (i = 0; i < 16; i++) m[i] = elr__num(P, what);
  if (br) {
    elr__tok t = elr__next(P);
    if (t.kind != T_RBR) elr__fail(P, t.line, "%s: expected ']' after 16 numbers", what);
  }
}

/* >> parameter lists */
static const char *elr__canon_type(const char *t) {
  if (!strcmp(t, "point")) return "point3";
  if (!strcmp(t, "normal")) return "normal3";
  if (!strcmp(t, "normal3")) return "normal3";
  if (!strcmp(t, "vector")) return "vector3";
  if (!strcmp(t, "color")) return "rgb";
  return t;
}
static void elr__read_params(elr__parser *P) {
  P->nparams = 0;
  for (;;) {
    elr__tok t = elr__peek(P), v;
    elr__param *pp;
    char ty[64], nm[128];
    int nv = 0, cap = 8, isstr = -1;
    double *nums; char **strs;
    if (t.kind != T_STRING) break;
    elr__next(P);
    if (P->nparams >= ELR_MAX_PARAMS) elr__fail(P, t.line, "too many parameters (more than %d)", ELR_MAX_PARAMS);
    if (sscanf(t.s, "%63s %127s", ty, nm) != 2)
      elr__fail(P, t.line, "parameter declaration \"%s\" is not \"type name\"", t.s);
    {
      const char *ct = elr__canon_type(ty);
      static const char *known[] = {"integer", "float", "point2", "vector2", "point3", "vector3", "normal3",
                                    "rgb", "spectrum", "xyz", "blackbody", "bool", "string", "texture", "point4"};
      int k, ok = 0;
      for (k = 0; k < (int)(sizeof known / sizeof known[0]); k++) if (!strcmp(ct, known[k])) ok = 1;
      if (!ok) elr__fail(P, t.line, "unknown parameter type \"%s\" in \"%s\"", ty, t.s);
      pp = &P->params[P->nparams++];
      memset(pp, 0, sizeof *pp);
      snprintf(pp->type, sizeof pp->type, "%s", ct);
      snprintf(pp->name, sizeof pp->name, "%s", nm);
      pp->line = t.line; pp->file = elr__curfile(P);
    }
    nums = (double *)elr__grow(P, 0, sizeof(double) * (size_t)cap);
    strs = (char **)elr__grow(P, 1, sizeof(char *) * (size_t)cap);
    v = elr__next(P);
    if (v.kind == T_LBR) {
      for (;;) {
        v = elr__next(P);
        if (v.kind == T_RBR) break;
        if (v.kind == T_EOF) elr__fail(P, t.line, "parameter \"%s\": file ends inside [ ]", t.s);
        if (v.kind == T_LBR) elr__fail(P, v.line, "parameter \"%s\": nested '['", t.s);
        if (nv == cap) { /* the list's kind is known by now (cap >= 8): only its array grows */
          if (cap > (1 << 27)) elr__fail(P, v.line, "parameter \"%s\": too many values", t.s);
          cap *= 2;
          if (isstr == 1) strs = (char **)elr__grow(P, 1, sizeof(char *) * (size_t)cap);
          else nums = (double *)elr__grow(P, 0, sizeof(double) * (size_t)cap);
        }
        if (v.kind == T_NUM) {
          if (isstr == 1) elr__fail(P, v.line, "parameter \"%s\": numbers mixed with strings", t.s);
          isstr = 0; nums[nv++] = v.num;
        } else if (v.kind == T_STRING || elr__wordis(&v, "true") || elr__wordis(&v, "false")) {
          if (isstr == 0) elr__fail(P, v.line, "parameter \"%s\": strings mixed with numbers", t.s);
          isstr = 1; strs[nv++] = v.kind == T_STRING ? (char *)v.s : elr__strdup(P, v.s, v.len);
        } else {
          if (v.kind == T_WORD && v.len <= 8 && (!strncmp(v.s, "inf", 3) || !strncmp(v.s, "nan", 3) || !strncmp(v.s, "Inf", 3) || !strncmp(v.s, "NaN", 3)))
            elr__fail(P, v.line, "parameter \"%s\": \"%.*s\" is not a finite number", t.s, (int)v.len, v.s);
          elr__fail(P, v.line, "parameter \"%s\": unexpected token in value list (missing ']'?)", t.s);
        }
      }
    } else if (v.kind == T_NUM) {
      isstr = 0; nums[nv++] = v.num;
    } else if (v.kind == T_STRING || elr__wordis(&v, "true") || elr__wordis(&v, "false")) {
      isstr = 1; strs[nv++] = v.kind == T_STRING ? (char *)v.s : elr__strdup(P, v.s, v.len);
    } else {
      elr__fail(P, v.kind == T_EOF ? t.line : v.line, "parameter \"%s\" has no value%s", t.s,
                v.kind == T_EOF ? " (file ends early)" : "");
    }
    /* the arrays at their final size, then in the arena */
    if (nv > 8) {
      if (isstr == 1) strs = (char **)elr__grow(P, 1, sizeof(char *) * (size_t)nv);
      else nums = (double *)elr__grow(P, 0, sizeof(double) * (size_t)nv);
    }
    elr__grow_keep(P, 0);
    elr__grow_keep(P, 1);
    pp->num = nums; pp->str = strs; pp->n = nv; pp->isstr = isstr == 1;
    {
      int wants_str = !strcmp(pp->type, "string") || !strcmp(pp->type, "texture") || !strcmp(pp->type, "bool");
      if (nv > 0 && wants_str != pp->isstr && strcmp(pp->type, "spectrum") != 0)
        elr__failf(P, pp->file, t.line, "parameter \"%s %s\": %s values expected", pp->type, pp->name,
                  wants_str ? "string" : "numeric");
      if (!strcmp(pp->type, "bool")) {
        int i;
        for (i = 0; i < nv; i++)
          if (strcmp(strs[i], "true") && strcmp(strs[i], "false"))
            elr__failf(P, pp->file, t.line, "parameter \"bool %s\": value \"%s\" is neither true nor false", pp->name, strs[i]);
      }
      if (!strcmp(pp->type, "integer")) {
        int i;
        for (i = 0; i < nv; i++)
          if (nums[i] != floor(nums[i]))
            elr__failf(P, pp->file, t.line, "parameter \"integer %s\": %g is not an integer", pp->name, nums[i]);
          else if (fabs(nums[i]) > 2147483647.0)
            elr__failf(P, pp->file, t.line, "parameter \"integer %s\": %.0f is outside the 32-bit integer range", pp->name, nums[i]);
      }
    }
  }
}

static elr__param *elr__find(elr__parser *P, const char *name) {
  int i;
  for (i = 0; i < P->nparams; i++) if (!strcmp(P->params[i].name, name)) return &P->params[i];
  return NULL;
}
static elr__param *elr__findt(elr__parser *P, const char *name, const char *type, int count) {
  elr__param *p = elr__find(P, name);
  if (!p) return NULL;
  if (strcmp(p->type, type) != 0)
    elr__failf(P, p->file, p->line, "%s: parameter \"%s\" has type \"%s\", expected \"%s\"", P->dir_name, name, p->type, type);
  if (count > 0 && p->n != count)
    elr__failf(P, p->file, p->line, "%s: parameter \"%s %s\" takes %d value%s, got %d", P->dir_name, type, name, count,
              count == 1 ? "" : "s", p->n);
  if (count < 0 && p->n % (-count) != 0)
    elr__failf(P, p->file, p->line, "%s: parameter \"%s %s\" needs a multiple of %d values, got %d", P->dir_name, type, name,
              -count, p->n);
  p->used = 1;
  return p;
}
static double elr__pfloat(elr__parser *P, const char *name, double def) {
  elr__param *p = elr__find(P, name);
  if (p && !strcmp(p->type, "integer")) { /* pbrt-v3 would ignore it; we accept an integer for a float */
    if (p->n != 1) elr__findt(P, name, "integer", 1);
    p->used = 1; return p->num[0];
  }
  p = elr__findt(P, name, "float", 1);
  return p ? p->num[0] : def;
}
static int elr__pint(elr__parser *P, const char *name, int def) {
  elr__param *p = elr__findt(P, name, "integer", 1);
  return p ? (int)p->num[0] : def;
}
static int elr__pbool(elr__parser *P, const char *name, int def) {
  elr__param *p = elr__findt(P, name, "bool", 1);
  return p ? !strcmp(p->str[0], "true") : def;
}
static const char *elr__pstring(elr__parser *P, const char *name, const char *def) {
  elr__param *p = elr__findt(P, name, "string", 1);
  return p ? p->str[0] : def;
}
static char *elr__read_file(elr__parser *P, const char *path, size_t *len, int line);
static char *elr__resolve(elr__parser *P, const char *name);
/* A "spectrum", "blackbody" or "xyz" value as RGB, converted as pbrt-v3 does (spectrum.c). For a light
 * (P->light_param) a negative value given (a spectrum sample, a blackbody scale, an X, Y or Z) is an
 * error, and the negative RGB components that a spectrum outside the sRGB gamut converts to (a
 * normalised 1500 K blackbody is R 0.0111, G 0.00148, B -0.00022) are clamped to 0: pbrt-v3 keeps them, and here the film would reject the
 * negative radiance they make. */
static elr_v3 elr__pspectral(elr__parser *P, elr__param *p) {
  double rgb[3];
  int negative = 0, i;
  p->used = 1;
  if (!strcmp(p->type, "xyz")) { /* Spectrum::FromXYZ */
    double xyz[3];
    if (p->n != 3) elr__failf(P, p->file, p->line, "%s: parameter \"xyz %s\" takes 3 values (X Y Z), got %d", P->dir_name, p->name, p->n);
    xyz[0] = p->num[0]; xyz[1] = p->num[1]; xyz[2] = p->num[2];
    negative = xyz[0] < 0 || xyz[1] < 0 || xyz[2] < 0;
    elr_xyz_to_rgb(xyz, rgb);
  } else if (!strcmp(p->type, "blackbody")) { /* ParamSet::AddBlackbodySpectrum: a (temperature, scale) pair */
    double T;
    if (p->n != 2)
      elr__failf(P, p->file, p->line, "%s: parameter \"blackbody %s\" takes 2 values (temperature in kelvin, scale), pbrt-v3's format; got %d%s",
                 P->dir_name, p->name, p->n, p->n == 1 ? " (pbrt-v4 scenes give the temperature alone)" : "");
    T = p->num[0];
    if (!(T > 0.0))
      elr__failf(P, p->file, p->line, "%s: parameter \"blackbody %s\": the temperature %g K must be positive", P->dir_name, p->name, T);
    elr_blackbody_rgb(T, rgb);
    rgb[0] *= p->num[1]; rgb[1] *= p->num[1]; rgb[2] *= p->num[1];
    negative = p->num[1] < 0;
  } else { /* "spectrum": (wavelength, value) pairs, inline or in a .spd file (AddSampledSpectrum, ...Files) */
    const double *v = p->num;
    double *lam, *val, *file_vals = NULL;
    int n = p->n, i, bad = 0;
    const char *what = "the list";
    char *path = NULL;
    if (p->isstr) {
      size_t len;
      char *txt;
      if (p->n != 1) elr__failf(P, p->file, p->line, "%s: parameter \"spectrum %s\" takes 1 file name, got %d", P->dir_name, p->name, p->n);
      path = elr__resolve(P, p->str[0]);
      txt = elr__read_file(P, path, &len, p->line);
      n = elr_float_file_parse(txt, len, NULL, 0, &bad);
      if (n < 0) elr__failf(P, p->file, p->line, "%s: spectrum file \"%s\": line %d is not a list of numbers", P->dir_name, path, bad);
      file_vals = (double *)elr__alloc(P, sizeof(double) * ((size_t)n + 1));
      elr_float_file_parse(txt, len, file_vals, n, &bad);
      v = file_vals;
      what = "the file";
    }
    if (n < 2 || n % 2 != 0) {
      if (path) elr__failf(P, p->file, p->line, "%s: spectrum file \"%s\" holds %d numbers: (wavelength, value) pairs expected", P->dir_name, path, n);
      elr__failf(P, p->file, p->line, "%s: parameter \"spectrum %s\" takes (wavelength, value) pairs: got %d numbers", P->dir_name, p->name, n);
    }
    n /= 2;
    lam = (double *)elr__alloc(P, sizeof(double) * (size_t)n);
    val = (double *)elr__alloc(P, sizeof(double) * (size_t)n);
    for (i = 0; i < n; i++) {
      lam[i] = v[2 * i]; val[i] = v[2 * i + 1];
      if (val[i] < 0) negative = 1;
      if (i > 0 && !(lam[i] > lam[i - 1]))
        elr__failf(P, p->file, p->line, "%s: parameter \"spectrum %s\": the wavelengths of %s%s%s are not increasing (%g after %g)", P->dir_name,
                   p->name, what, path ? " " : "", path ? path : "", lam[i], lam[i - 1]);
    }
    elr_spectrum_from_sampled(lam, val, n, rgb);
  }
  if (P->light_param) {
    if (negative) elr__failf(P, p->file, p->line, "%s: parameter \"%s %s\" must not be negative", P->dir_name, p->type, p->name);
    for (i = 0; i < 3; i++) if (rgb[i] < 0) rgb[i] = 0;
  }
  if (!isfinite(rgb[0]) || !isfinite(rgb[1]) || !isfinite(rgb[2]) || fabs(rgb[0]) > FLT_MAX || fabs(rgb[1]) > FLT_MAX || fabs(rgb[2]) > FLT_MAX)
    elr__failf(P, p->file, p->line, "%s: parameter \"%s %s\": the colour overflows (%g %g %g)", P->dir_name, p->type, p->name, rgb[0], rgb[1], rgb[2]);
  return elr_v((float)rgb[0], (float)rgb[1], (float)rgb[2]);
}

static elr_v3 elr__prgb(elr__parser *P, const char *name, elr_v3 def) {
  elr__param *p = elr__find(P, name);
  if (p && (!strcmp(p->type, "spectrum") || !strcmp(p->type, "blackbody") || !strcmp(p->type, "xyz"))) return elr__pspectral(P, p);
  if (p && !strcmp(p->type, "float") && p->n == 1) { p->used = 1; return elr_v((float)p->num[0], (float)p->num[0], (float)p->num[0]); }
  p = elr__findt(P, name, "rgb", 3);
  return p ? elr_v((float)p->num[0], (float)p->num[1], (float)p->num[2]) : def;
}
static elr_v3 elr__ppoint(elr__parser *P, const char *name, const char *type, elr_v3 def) {
  elr__param *p = elr__findt(P, name, type, 3);
  return p ? elr_v((float)p->num[0], (float)p->num[1], (float)p->num[2]) : def;
}
static void elr__report_unused(elr__parser *P) {
  int i;
  for (i = 0; i < P->nparams; i++)
    if (!P->params[i].used) {
      char key[300];
      snprintf(key, sizeof key, "parameter %s %s %s", P->dir_name, P->params[i].type, P->params[i].name);
      elr__warn_once(P, P->params[i].file, P->params[i].line, key, "%s: parameter \"%s %s\" is not supported and is ignored",
                     P->dir_name, P->params[i].type, P->params[i].name);
    }
}
static void elr__check_range(elr__parser *P, const char *name, double v, double lo, double hi) {
  elr__param *p = elr__find(P, name);
  /* a relative float epsilon of slack: many values arrive here as floats, and 0.01f < 0.01 */
  if (!(v >= lo - fabs(lo) * 1e-6 && v <= hi + fabs(hi) * 1e-6))
    elr__failf(P, p ? p->file : P->dir_file, p ? p->line : P->dir_line, "%s: \"%s\" = %g is out of range [%g, %g]", P->dir_name, name, v, lo, hi);
}

/* World-space coordinates the renderer can trace: Embree refuses (asserts on) a ray whose origin has a
 * component beyond 1.8e18, and squared distances in float overflow near 1e19. Camera positions, light
 * positions and geometry must stay within |x| <= ELR_MAX_COORD; a transformation whose matrix or inverse
 * is not finite (Scale 1e-200 twice, Translate 1e300) is refused at the directive that made it. */
#define ELR_MAX_COORD 1e15
static int elr__coord_ok(elr_v3 p) {
  return fabsf(p.x) <= (float)ELR_MAX_COORD && fabsf(p.y) <= (float)ELR_MAX_COORD && fabsf(p.z) <= (float)ELR_MAX_COORD;
}
static void elr__check_point(elr__parser *P, int line, elr_v3 p, const char *what) {
  if (!elr__coord_ok(p))
    elr__failf(P, P->dir_file, line, "%s: %s (%g, %g, %g) is not finite or outside |x| <= %g", P->dir_name, what, p.x, p.y, p.z, ELR_MAX_COORD);
}
static void elr__check_ctm(elr__parser *P, int line) {
  int i, j;
  for (i = 0; i < 4; i++)
    for (j = 0; j < 4; j++)
      if (!isfinite(P->ctm.m[i][j]) || !isfinite(P->ctm.inv[i][j]) || fabs(P->ctm.m[i][j]) > 1e30 || fabs(P->ctm.inv[i][j]) > 1e30)
        elr__failf(P, P->dir_file, line, "%s: the transformation overflows (a matrix entry or an entry of its inverse is %g, beyond 1e30)",
                  P->dir_name, isfinite(P->ctm.m[i][j]) && fabs(P->ctm.m[i][j]) > 1e30 ? P->ctm.m[i][j] : P->ctm.inv[i][j]);
}

/* >> scene growth */
#define ELR_PUSH(P, arr, n, cap, T)                                                              \
  do {                                                                                           \
    if ((n) == (cap)) {                                                                          \
      int nc = (cap) ? (cap) * 2 : 8;                                                           \
      T *na = (T *)realloc((arr), sizeof(T) * (size_t)nc);                                       \
      if (!na) { snprintf((P)->err, (P)->errlen, "out of memory"); longjmp((P)->jb, 1); }        \
      (arr) = na; (cap) = nc;                                                                    \
    }                                                                                            \
    memset(&(arr)[(n)], 0, sizeof(T));                                                           \
    (n)++;                                                                                       \
  } while (0)

static int elr__const_tex(elr__parser *P, elr_v3 v) {
  elr_scene *s = P->s;
  elr_texture *t;
  ELR_PUSH(P, s->tex, s->ntex, s->captex, elr_texture);
  t = &s->tex[s->ntex - 1];
  t->kind = ELR_TEX_CONST; t->value = v; t->su = t->sv = 1.f;
  return s->ntex - 1;
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
static int elr__name_find(const elr__hmap *h, const elr__named *arr, int n, const char *name) {
  int found, k;
  if (h->cap == 0) return -1;
  k = h->s[elr__hslot(h, arr, name, &found)];
  if (!found) return -1;
  while (k >= n) k = arr[k].prev;
  return k;
}
/* Index entry k (its name set; the latest entry of the list). */
static void elr__name_add(elr__parser *P, elr__hmap *h, elr__named *arr, int k) {
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
static void elr__name_drop(elr__hmap *h, elr__named *arr, int from, int to) {
  int k, found, slot;
  for (k = from - 1; k >= to; k--) {
    slot = elr__hslot(h, arr, arr[k].name, &found);
    if (found && h->s[slot] == k) h->s[slot] = arr[k].prev >= 0 ? arr[k].prev : -2;
  }
}
/* A texture-valued parameter ("rgb Kd", "float roughness" or "texture Kd" naming a texture). */
static int elr__ptex(elr__parser *P, const char *name, elr_v3 def, int is_float) {
  elr__param *p = elr__find(P, name);
  if (p && !strcmp(p->type, "texture")) {
    int k;
    elr__findt(P, name, "texture", 1);
    k = elr__name_find(&P->htex, P->texnames, P->gs.ntex_scope, p->str[0]);
    if (k < 0) {
      elr_warn(P->s, p->file, p->line, "%s: texture \"%s\" is not defined; using the default %s", P->dir_name, p->str[0], name);
      return elr__const_tex(P, def);
    }
    if (P->texnames[k].is_float != is_float)
      elr_warn(P->s, p->file, p->line, "%s: texture \"%s\" is a %s texture used for %s parameter \"%s\"", P->dir_name, p->str[0],
               P->texnames[k].is_float ? "float" : "spectrum", is_float ? "a float" : "a spectrum", name);
    return P->texnames[k].index;
  }
  if (is_float) {
    double v = elr__pfloat(P, name, def.x);
    return elr__const_tex(P, elr_v((float)v, (float)v, (float)v));
  }
  return elr__const_tex(P, elr__prgb(P, name, def));
}

static char *elr__resolve(elr__parser *P, const char *name) {
  size_t n;
  char *r;
  if (name[0] == '/' || !P->base_dir || !P->base_dir[0]) return elr__strdup(P, name, strlen(name));
  n = strlen(P->base_dir) + strlen(name) + 2;
  r = (char *)elr__alloc(P, n);
  snprintf(r, n, "%s/%s", P->base_dir, name);
  return r;
}

static void elr__load_image(elr__parser *P, const char *file, int line, el_image *img) {
  char e[512];
  double t0 = elr_now();
  if (el_image_load(file, img, e, sizeof e) != 0) elr__failf(P, P->dir_file, line, "%s: cannot read image: %s", P->dir_name, e);
  P->s->t_images += elr_now() - t0;
  if (img->width <= 0 || img->height <= 0 || img->width > 65536 || img->height > 65536) {
    int w = img->width, h = img->height;
    el_image_free(img);
    elr__failf(P, P->dir_file, line, "%s: image \"%s\" has an absurd size (%d x %d; 1 to 65536 per side)", P->dir_name, file, w, h);
  }
}
/* channels -> linear RGB (3 floats per texel); 8-bit input with gamma: sRGB to linear. A NaN or
 * infinite texel (or one that overflows when scaled) is an error naming the file and the texel: it used
 * to become 0 silently. */
static float *elr__to_rgb(elr__parser *P, el_image *img, int gamma, float scale, const char *file) {
  size_t n = (size_t)img->width * (size_t)img->height, i;
  float *rgb = (float *)malloc(n * 3 * sizeof(float));
  if (!rgb) { el_image_free(img); snprintf(P->err, P->errlen, "out of memory"); longjmp(P->jb, 1); }
  for (i = 0; i < n; i++) {
    int c;
    for (c = 0; c < 3; c++) {
      int src = img->channels >= 3 ? c : 0;
      float v = img->pixels[i * (size_t)img->channels + (size_t)src];
      if (img->is_8bit && gamma)
        v = v <= 0.04045f ? v / 12.92f : powf((v + 0.055f) / 1.055f, 2.4f);
      if (!isfinite(v) || !isfinite(v * scale)) {
        int x = (int)(i % (size_t)img->width), y = (int)(i / (size_t)img->width);
        float bad = v;
        free(rgb);
        el_image_free(img);
        if (!isfinite(bad))
          elr__failf(P, P->dir_file, P->dir_line, "%s: image \"%s\": texel (%d, %d) is %s", P->dir_name, file, x, y, bad != bad ? "NaN" : "infinite");
        elr__failf(P, P->dir_file, P->dir_line, "%s: image \"%s\": texel (%d, %d) times scale %g overflows", P->dir_name, file, x, y, scale);
      }
      rgb[i * 3 + (size_t)c] = v * scale;
    }
  }
  return rgb;
}

/* >> directives */
static void elr__camera(elr__parser *P, const char *type) {
  elr_scene_desc *d = &P->s->d;
  elr__param *sw;
  if (strcmp(type, "perspective") != 0) {
    elr_warn(P->s, P->dir_file, P->dir_line, "Camera \"%s\" is not supported; using \"perspective\"", type);
  }
  double fov = elr__pfloat(P, "fov", 90.0), fa;
  if (elr__find(P, "halffov")) { /* pbrt-v3: halffov > 0 overrides fov */
    double hf = elr__pfloat(P, "halffov", -1.0);
    if (hf > 0) fov = 2.0 * hf;
  }
  /* the ranges are checked on the values as written (as floats, 179.99 is above 179.99) */
  elr__check_range(P, "fov", fov, 1e-4, 179.99);
  d->fov = (float)fov;
  if (elr__find(P, "frameaspectratio")) {
    fa = elr__pfloat(P, "frameaspectratio", 1.0);
    elr__check_range(P, "frameaspectratio", fa, 1e-6, 1e6);
    d->frameaspect = (float)fa;
    d->has_frameaspect = 1;
  }
  sw = elr__findt(P, "screenwindow", "float", 4);
  if (sw) {
    int i;
    for (i = 0; i < 4; i++) d->screen[i] = (float)sw->num[i];
    if (!(d->screen[1] > d->screen[0]) || !(d->screen[3] > d->screen[2]))
      elr__failf(P, sw->file, sw->line, "Camera: screenwindow must be [xmin xmax ymin ymax] with xmin < xmax and ymin < ymax");
    d->has_screen = 1;
  }
  if (elr__find(P, "lensradius")) {
    double lr = elr__pfloat(P, "lensradius", 0.0);
    if (lr != 0.0) elr_warn(P->s, P->dir_file, P->dir_line, "Camera: \"lensradius\" %g ignored (pinhole camera only)", lr);
  }
  if (elr__find(P, "focaldistance")) elr__pfloat(P, "focaldistance", 1e6);
  elr_xform_invert(&d->cam2world, &P->ctm);
  elr__check_point(P, P->dir_line, elr_xpoint(&d->cam2world, elr_v(0, 0, 0)), "the camera position");
  P->seen_camera = 1;
  /* named coordinate system "camera" */
  {
    int k = elr__name_find(&P->hctx, P->ctx, P->nctx, "camera");
    if (k < 0) {
      ELR_PUSH(P, P->ctx, P->nctx, P->capctx, elr__named);
      P->cs_xf = (elr_xform *)realloc(P->cs_xf, sizeof(elr_xform) * (size_t)P->capctx);
      if (!P->cs_xf) { snprintf(P->err, P->errlen, "out of memory"); longjmp(P->jb, 1); }
      k = P->nctx - 1;
      P->ctx[k].name = elr__strdup(P, "camera", 6);
      elr__name_add(P, &P->hctx, P->ctx, k);
    }
    P->cs_xf[k] = d->cam2world;
  }
}

static void elr__film(elr__parser *P, const char *type) {
  elr_scene_desc *d = &P->s->d;
  elr__param *cw;
  const char *fn;
  if (strcmp(type, "image") != 0) elr_warn(P->s, P->dir_file, P->dir_line, "Film \"%s\" is not supported; using \"image\"", type);
  d->xres = elr__pint(P, "xresolution", 1280);
  d->yres = elr__pint(P, "yresolution", 720);
  elr__check_range(P, "xresolution", d->xres, 1, 32768);
  elr__check_range(P, "yresolution", d->yres, 1, 32768);
  if ((double)d->xres * (double)d->yres > 1e8)
    elr__failf(P, P->dir_file, P->dir_line, "Film: %d x %d is more than 1e8 pixels", d->xres, d->yres);
  fn = elr__pstring(P, "filename", "pbrt.exr");
  if (strlen(fn) >= sizeof d->filename) elr__failf(P, P->dir_file, P->dir_line, "Film: filename too long");
  snprintf(d->filename, sizeof d->filename, "%s", fn);
  cw = elr__findt(P, "cropwindow", "float", 4);
  if (cw) {
    int i;
    for (i = 0; i < 4; i++) {
      d->crop[i] = (float)cw->num[i];
      if (!(d->crop[i] >= 0.f && d->crop[i] <= 1.f))
        elr__failf(P, cw->file, cw->line, "Film: cropwindow values must lie in [0, 1]");
    }
    { /* pbrt-v3 sorts each pair */
      float t;
      if (d->crop[0] > d->crop[1]) { t = d->crop[0]; d->crop[0] = d->crop[1]; d->crop[1] = t; }
      if (d->crop[2] > d->crop[3]) { t = d->crop[2]; d->crop[2] = d->crop[3]; d->crop[3] = t; }
    }
    /* the pixel bounds as elr_render computes them (pbrt-v3: ceil of crop times resolution) */
    if (ceil(d->xres * (double)d->crop[1]) <= ceil(d->xres * (double)d->crop[0]) ||
        ceil(d->yres * (double)d->crop[3]) <= ceil(d->yres * (double)d->crop[2]))
      elr__failf(P, cw->file, cw->line, "Film: cropwindow [ %g %g %g %g ] covers no pixel of the %d x %d film", d->crop[0], d->crop[1], d->crop[2],
                d->crop[3], d->xres, d->yres);
  }
  if (elr__find(P, "scale")) {
    double sc = elr__pfloat(P, "scale", 1.0);
    if (sc != 1.0) elr_warn(P->s, P->dir_file, P->dir_line, "Film: \"scale\" %g ignored", sc);
  }
  if (elr__find(P, "diagonal")) elr__pfloat(P, "diagonal", 35.0);
}

static void elr__filter(elr__parser *P, const char *type) {
  elr_filter_desc *f = &P->s->d.filter;
  float defw = 2.f;
  memset(f, 0, sizeof *f);
  if (!strcmp(type, "box")) { f->type = ELR_PF_BOX; defw = 0.5f; }
  else if (!strcmp(type, "triangle")) f->type = ELR_PF_TRIANGLE;
  else if (!strcmp(type, "gaussian")) { f->type = ELR_PF_GAUSSIAN; f->alpha = (float)elr__pfloat(P, "alpha", 2.0); }
  else if (!strcmp(type, "mitchell")) {
    f->type = ELR_PF_MITCHELL;
    f->b = (float)elr__pfloat(P, "B", 1.0 / 3.0); f->c = (float)elr__pfloat(P, "C", 1.0 / 3.0);
  } else if (!strcmp(type, "sinc")) { f->type = ELR_PF_SINC; defw = 4.f; f->tau = (float)elr__pfloat(P, "tau", 3.0); }
  else {
    elr_warn(P->s, P->dir_file, P->dir_line, "PixelFilter \"%s\" is not supported; using \"box\"", type);
    f->type = ELR_PF_BOX; defw = 0.5f;
  }
  /* parameters whose absurd values make every filter weight 0 or overflow (a silently black image) */
  if (f->type == ELR_PF_GAUSSIAN) elr__check_range(P, "alpha", f->alpha, 1e-4, 1e3);
  if (f->type == ELR_PF_MITCHELL) { elr__check_range(P, "B", f->b, -100, 100); elr__check_range(P, "C", f->c, -100, 100); }
  if (f->type == ELR_PF_SINC) elr__check_range(P, "tau", f->tau, 1e-2, 1e3);
  f->xw = (float)elr__pfloat(P, "xwidth", defw);
  f->yw = (float)elr__pfloat(P, "ywidth", defw);
  /* envlight's extension: negative filter weights (mitchell's and sinc's lobes) count as 0, so that few
   * samples per pixel cannot overshoot (film.h's el_film_options.nonnegative_filter) */
  f->nonneg = elr__pbool(P, "nonnegative", 0);
  elr__check_range(P, "xwidth", f->xw, 1e-3, 16);
  elr__check_range(P, "ywidth", f->yw, 1e-3, 16);
}

/* pbrt-v4's "string randomization" (sobol, zsobol, paddedsobol) */
static int elr__randomization(elr__parser *P, const char *type, const char *def) {
  static const char *const names[4] = {"none", "permutedigits", "fastowen", "owen"}; /* ELR_RANDOMIZE_* */
  const char *r = elr__pstring(P, "randomization", def);
  elr__param *p = elr__find(P, "randomization");
  int k;
  for (k = 0; k < 4; k++) if (!strcmp(r, names[k])) return k;
  elr__failf(P, p ? p->file : P->dir_file, p ? p->line : P->dir_line,
             "Sampler \"%s\": unknown randomization \"%s\" (none, permutedigits, fastowen, owen)", type, r);
  return ELR_RANDOMIZE_NONE;
}

/* pbrt-v3's MakeSampler (api.cpp) and each sampler's Create: the parameters, with pbrt's defaults */
static void elr__sampler(elr__parser *P, const char *type) {
  elr_scene_desc *d = &P->s->d;
  int kind = elr_sampler_kind_from_name(type);
  d->randomize = ELR_RANDOMIZE_NONE; d->has_seed = 0; d->sseed = 0; d->dims = 4; d->jitter = 1;
  if (kind < 0) {
    /* pbrt-v3's "maxmindist", pbrt-v4's "pmj02bn" and "independent" */
    if (!strcmp(type, "independent")) kind = ELR_SAMPLER_RANDOM;
    else if (!strcmp(type, "pmj02bn")) kind = ELR_SAMPLER_ZSOBOL;
    else kind = ELR_SAMPLER_HALTON;
    elr_warn(P->s, P->dir_file, P->dir_line, "Sampler \"%s\" is not supported; using \"%s\"", type, elr_sampler_kind_name(kind));
    if (kind == ELR_SAMPLER_ZSOBOL) d->randomize = ELR_RANDOMIZE_FAST_OWEN;
  }
  d->sampler = kind;
  switch (kind) {
  case ELR_SAMPLER_RANDOM:
    d->spp = elr__pint(P, "pixelsamples", 4);
    break;
  case ELR_SAMPLER_STRATIFIED:
    d->jitter = elr__pbool(P, "jitter", 1);
    d->xs = elr__pint(P, "xsamples", 4);
    d->ys = elr__pint(P, "ysamples", 4);
    d->dims = elr__pint(P, "dimensions", 4);
    elr__check_range(P, "xsamples", d->xs, 1, 4096);
    elr__check_range(P, "ysamples", d->ys, 1, 4096);
    elr__check_range(P, "dimensions", d->dims, 0, 64);
    d->spp = d->xs * d->ys;
    /* every render thread holds xsamples * ysamples * (dimensions + 1) 1D and 2D samples (12 bytes) */
    if ((double)d->spp * (double)(d->dims + 1) > (double)(1 << 24))
      elr__failf(P, P->dir_file, P->dir_line, "Sampler \"stratified\": %d x %d samples in %d dimensions need %.0f MiB per thread (at most 16777216 "
                "samples times dimensions + 1)", d->xs, d->ys, d->dims, (double)d->spp * (d->dims + 1) * 12.0 / 1048576.0);
    break;
  case ELR_SAMPLER_ZEROTWO:
    d->spp = elr__pint(P, "pixelsamples", 16);
    d->dims = elr__pint(P, "dimensions", 4);
    elr__check_range(P, "dimensions", d->dims, 0, 64);
    break;
  case ELR_SAMPLER_SOBOL: case ELR_SAMPLER_ZSOBOL: case ELR_SAMPLER_PADDEDSOBOL:
    d->spp = elr__pint(P, "pixelsamples", 16);
    /* pbrt-v4's parameters; pbrt-v3's sobol has none and is not randomized */
    d->randomize = elr__randomization(P, type, kind == ELR_SAMPLER_SOBOL ? "none" : "fastowen");
    if (elr__find(P, "seed")) { d->has_seed = 1; d->sseed = elr__pint(P, "seed", 0); }
    break;
  default: /* halton */
    d->spp = elr__pint(P, "pixelsamples", 16);
    if (elr__find(P, "samplepixelcenter") && elr__pbool(P, "samplepixelcenter", 0))
      elr_warn(P->s, P->dir_file, P->dir_line, "Sampler: \"samplepixelcenter\" ignored");
    break;
  }
  elr__check_range(P, "pixelsamples", d->spp, 1, 1 << 24);
  if (kind == ELR_SAMPLER_SOBOL || kind == ELR_SAMPLER_ZEROTWO || kind == ELR_SAMPLER_ZSOBOL) {
    int p2 = 1;
    while (p2 < d->spp) p2 <<= 1;
    if (p2 > (1 << 24))
      elr__failf(P, P->dir_file, P->dir_line, "Sampler \"%s\": %d pixel samples, rounded up to a power of two, exceed 16777216", type, d->spp);
    if (p2 != d->spp) {
      elr_warn(P->s, P->dir_file, P->dir_line, "Sampler \"%s\": %d pixel samples rounded up to %d (a power of two)", type, d->spp, p2);
      d->spp = p2;
    }
  }
  if (kind == ELR_SAMPLER_ZEROTWO && (double)d->spp * (double)(d->dims + 1) > (double)(1 << 24))
    elr__failf(P, P->dir_file, P->dir_line, "Sampler \"%s\": %d samples in %d dimensions need %.0f MiB per thread (at most 16777216 "
              "samples times dimensions + 1)", type, d->spp, d->dims, (double)d->spp * (d->dims + 1) * 12.0 / 1048576.0);
}

static void elr__integrator(elr__parser *P, const char *type) {
  elr_scene_desc *d = &P->s->d;
  const char *ls;
  P->integ_file = P->dir_file; P->integ_line = P->dir_line;
  if (!strcmp(type, "directlighting")) {
    /* pbrt-v3's strategy: "all" (UniformSampleAllLights, each light's samples) or "one" (UniformSampleOneLight,
     * one light chosen uniformly) */
    const char *st = elr__pstring(P, "strategy", "all");
    d->integrator_path = 0;
    if (!strcmp(st, "all")) d->direct_one = 0;
    else if (!strcmp(st, "one")) d->direct_one = 1;
    else elr__failf(P, elr__find(P, "strategy")->file, elr__find(P, "strategy")->line, "Integrator \"directlighting\": strategy must be \"all\" or \"one\"");
    /* envlight's extension (default "off": bench_render --split measured no gain on its scenes): "auto" chooses the light and BSDF samples per camera sample from a pilot's
     * measured variance and cost (render.c), "off" keeps each light's "samples" */
    st = elr__pstring(P, "splitting", "off");
    if (!strcmp(st, "auto")) d->split_auto = 1;
    else if (!strcmp(st, "off")) d->split_auto = 0;
    else elr__failf(P, elr__find(P, "splitting")->file, elr__find(P, "splitting")->line, "Integrator \"directlighting\": splitting must be \"auto\" or \"off\"");
  } else {
    const char *st;
    if (strcmp(type, "path") != 0) {
      /* pbrt-v3's other integrators (whitted, volpath, bdpt, mlt, sppm, ambientocclusion) and anything
       * else: the path tracer, with the scene's maxdepth; the other parameters belong to the integrator
       * that is not there */
      int i, keep = 0;
      for (i = 0; i < P->nparams; i++)
        if (strcmp(P->params[i].name, "maxdepth") != 0) P->params[i].used = 1;
        else keep = 1;
      elr_warn(P->s, P->dir_file, P->dir_line, "Integrator \"%s\" is not supported; using \"path\"%s, its other parameters ignored", type,
               keep ? " with its maxdepth" : " (maxdepth 5)");
      d->integrator_path = 1; d->rrthreshold = 1.f;
      d->light_strategy = ELR_LSTRAT_SPATIAL;
      d->maxdepth = elr__pint(P, "maxdepth", 5);
      elr__check_range(P, "maxdepth", d->maxdepth, 0, 100000);
      d->light_sampling = ELR_LS_MIS;
      return;
    }
    d->integrator_path = 1;
    d->rrthreshold = (float)elr__pfloat(P, "rrthreshold", 1.0);
    /* pbrt-v3's lightsamplestrategy (default "spatial", which is "power" here: lightdistrib.c) */
    st = elr__pstring(P, "lightsamplestrategy", "spatial");
    if (!strcmp(st, "uniform")) d->light_strategy = ELR_LSTRAT_UNIFORM;
    else if (!strcmp(st, "power")) d->light_strategy = ELR_LSTRAT_POWER;
    else if (!strcmp(st, "spatial")) d->light_strategy = ELR_LSTRAT_SPATIAL;
    else elr__failf(P, elr__find(P, "lightsamplestrategy")->file, elr__find(P, "lightsamplestrategy")->line,
                    "Integrator \"path\": lightsamplestrategy must be \"uniform\", \"power\" or \"spatial\"");
  }
  d->maxdepth = elr__pint(P, "maxdepth", 5);
  elr__check_range(P, "maxdepth", d->maxdepth, 0, 100000);
  /* envlight's extension: which strategies estimate direct light (a test and benchmark hook) */
  ls = elr__pstring(P, "lightsampling", "mis");
  if (!strcmp(ls, "mis")) d->light_sampling = ELR_LS_MIS;
  else if (!strcmp(ls, "light")) d->light_sampling = ELR_LS_LIGHT;
  else if (!strcmp(ls, "bsdf")) d->light_sampling = ELR_LS_BSDF;
  else elr__failf(P, elr__find(P, "lightsampling")->file, elr__find(P, "lightsampling")->line, "Integrator: lightsampling must be \"mis\", \"light\" or \"bsdf\"");
  if (elr__find(P, "pixelbounds")) elr_warn(P->s, P->dir_file, P->dir_line, "Integrator: \"pixelbounds\" ignored");
  if (elr__find(P, "pixelbounds")) elr__find(P, "pixelbounds")->used = 1;
}

static void elr__light(elr__parser *P, const char *type) {
  elr_scene *s = P->s;
  elr_light *l;
  elr_v3 sc;
  P->light_param = 1;
  sc = elr__prgb(P, "scale", elr_v(1, 1, 1));
  ELR_PUSH(P, s->light, s->nlight, s->caplight, elr_light);
  l = &s->light[s->nlight - 1];
  if (!strcmp(type, "infinite")) {
    /* pbrt-v3 names the map "mapname" (lat-long); pbrt-v4 "filename" (a square equal-area map) */
    const char *map = elr__pstring(P, "mapname", ""), *fn4 = elr__pstring(P, "filename", "");
    float m3[9];
    int i, j;
    elr_v3 L = elr__prgb(P, "L", elr_v(1, 1, 1));
    char e[512];
    float scale3[3];
    float *rgb = NULL;
    char *path = NULL;
    int w = 1, h = 1;
    l->kind = ELR_LIGHT_INFINITE;
    l->nsamples = elr__pint(P, "samples", 1);
    elr__check_range(P, "samples", l->nsamples, 1, 1 << 16);
    l->compensated = elr__pbool(P, "compensated", 0);
    {
      /* envlight's extension: the importance map. Default "pbrt-v3" (pbrt-v3's own: twice the image
       * resolution from point lookups of le); "cellaverage" is envlight's default (exact bin averages of
       * the bilinear le, a quarter of the bins). Measured on city.hdr (a 3e4 sun), the relative variance
       * of lum(le) / pdf per light sample is 0.024 for pbrt-v3's map and 0.098 for cell averages: the
       * piecewise-constant density cannot follow the bilinear ramp around the sun at image resolution. */
      const char *im = elr__pstring(P, "importance", "pbrt-v3");
      if (!strcmp(im, "cellaverage")) l->importance = EL_ENVLIGHT_IMPORTANCE_CELL_AVERAGE;
      else if (!strcmp(im, "pbrt-v3")) l->importance = EL_ENVLIGHT_IMPORTANCE_PBRT_V3;
      else if (!strcmp(im, "texel")) l->importance = EL_ENVLIGHT_IMPORTANCE_TEXEL;
      else if (!strcmp(im, "bilinear")) l->importance = EL_ENVLIGHT_IMPORTANCE_BILINEAR;
      else elr__failf(P, elr__find(P, "importance")->file, elr__find(P, "importance")->line, "LightSource \"infinite\": importance must be \"cellaverage\", \"pbrt-v3\", \"texel\" or \"bilinear\"");
    }
    {
      /* envlight's extension: how a surface that only reflects samples the light. "product" (the
       * default): the map times the clamped cosine of the surface's normal (el_envlight_sample_li_cos),
       * no sample below the horizon; "map": the map alone (pbrt-v3's, with the importance map above) */
      const char *ls = elr__pstring(P, "sampling", "product");
      if (!strcmp(ls, "product")) l->sampling = ELR_ENVLS_PRODUCT;
      else if (!strcmp(ls, "map")) l->sampling = ELR_ENVLS_MAP;
      else elr__failf(P, elr__find(P, "sampling")->file, elr__find(P, "sampling")->line, "LightSource \"infinite\": sampling must be \"product\" or \"map\"");
    }
    {
      /* envlight's extension: what becomes of texels envlight cannot use. "clampnegative" (the default):
       * finite negative texels become 0, with one warning that counts them and names the most negative
       * value (lossy EXR compression, DWAA/DWAB, rings slightly below 0: the HDRIs Blender ships hold 3 to
       * 8980 such texels, down to -0.0039), NaN and infinite texels are errors naming the file and the
       * texel; "zero": NaN and infinite texels become 0 too (one warning); "error": negatives are errors
       * as well. The image reader keeps every value as the file holds it: the policy is the light's. */
      const char *bt = elr__pstring(P, "badtexels", "clampnegative");
      if (!strcmp(bt, "clampnegative")) l->bad_texels = EL_ENVLIGHT_BAD_TEXELS_CLAMP_NEGATIVE;
      else if (!strcmp(bt, "zero")) l->bad_texels = EL_ENVLIGHT_BAD_TEXELS_ZERO;
      else if (!strcmp(bt, "error")) l->bad_texels = EL_ENVLIGHT_BAD_TEXELS_ERROR;
      else elr__failf(P, elr__find(P, "badtexels")->file, elr__find(P, "badtexels")->line, "LightSource \"infinite\": badtexels must be \"clampnegative\", \"zero\" or \"error\"");
    }
    l->L = elr_vmul(L, sc);
    scale3[0] = l->L.x; scale3[1] = l->L.y; scale3[2] = l->L.z;
    for (i = 0; i < 3; i++) /* else envlight reports "texel (0, 0) is NaN, infinite or negative" */
      if (!(scale3[i] >= 0.f && scale3[i] <= FLT_MAX))
        elr__failf(P, P->dir_file, P->dir_line, "LightSource \"infinite\": L times scale (%g %g %g) must be finite and not negative", scale3[0],
                  scale3[1], scale3[2]);
    /* the light-to-world rotation: the CTM's upper 3x3 (pbrt-v3 allows only rotations here) */
    /* pbrt-v3 normalises WorldToLight(d): a uniform scale in the CTM does not change the mapping, so
     * divide it out (envlight takes a rotation or a reflection) */
    double colscale = sqrt(P->ctm.m[0][0] * P->ctm.m[0][0] + P->ctm.m[1][0] * P->ctm.m[1][0] + P->ctm.m[2][0] * P->ctm.m[2][0]);
    if (!(colscale > 0)) colscale = 1;
    for (i = 0; i < 3; i++)
      for (j = 0; j < 3; j++) {
        double v = P->ctm.m[i][j] / colscale;
        /* Rotate by multiples of 90 degrees leaves cos = 6e-17 instead of 0: snap, so that envlight sees
         * the exact signed permutation (its exact and faster path) that the scene meant */
        if (fabs(v) < 1e-9) v = 0.0;
        else if (fabs(v - 1.0) < 1e-9) v = 1.0;
        else if (fabs(v + 1.0) < 1e-9) v = -1.0;
        m3[i * 3 + j] = (float)v;
      }
    if (map[0] && fn4[0])
      elr__failf(P, elr__find(P, "filename")->file, elr__find(P, "filename")->line,
                 "LightSource \"infinite\": both \"mapname\" (pbrt-v3, lat-long) and \"filename\" (pbrt-v4, equal-area) are given");
    if (map[0] || fn4[0]) {
      el_image img;
      path = elr__resolve(P, map[0] ? map : fn4);
      elr__load_image(P, path, P->dir_line, &img);
      if (l->bad_texels != EL_ENVLIGHT_BAD_TEXELS_ZERO) {
        rgb = elr__to_rgb(P, &img, 0, 1.f, path); /* NaN / infinite: an error naming the file and texel */
      } else { /* "zero": every value as the file holds it, for envlight to count and replace */
        size_t n = (size_t)img.width * (size_t)img.height, k;
        rgb = (float *)malloc(n * 3 * sizeof(float));
        if (!rgb) { el_image_free(&img); snprintf(P->err, P->errlen, "out of memory"); longjmp(P->jb, 1); }
        for (k = 0; k < 3 * n; k++) rgb[k] = img.pixels[(k / 3) * (size_t)img.channels + (img.channels >= 3 ? k % 3 : 0)];
      }
      w = img.width; h = img.height;
      el_image_free(&img);
      l->has_map = 1;
      /* pbrt-v4 reads "filename" as a square equal-area octahedral map (ImageInfiniteLight) and refuses any
       * other shape; here a non-square "filename" is read as pbrt-v3's lat-long map, with a warning */
      if (fn4[0] && w == h) l->mapping = EL_ENVLIGHT_MAPPING_EQUAL_AREA;
      else if (fn4[0])
        elr_warn(s, elr__find(P, "filename")->file, elr__find(P, "filename")->line,
                 "LightSource \"infinite\": \"%s\" is %dx%d, not square: pbrt-v4 wants a square equal-area map; read as a lat-long "
                 "map (pbrt-v3's \"mapname\")", path, w, h);
    } else {
      rgb = NULL; /* a constant light */
    }
    {
      double t0 = elr_now();
      int r = elr_infinite_init(l, rgb, w, h, scale3, m3, e, sizeof e);
      if (r == 0 && rgb && l->env && l->env->borrowed) l->env_pixels = rgb; /* read in place: freed with the light */
      else free(rgb);
      if (r != 0) {
        if (path) elr__failf(P, P->dir_file, P->dir_line, "LightSource \"infinite\": image \"%s\": %s", path, e);
        elr__failf(P, P->dir_file, P->dir_line, "LightSource \"infinite\": %s", e);
      }
      s->t_images += elr_now() - t0;
      /* one warning per kind of texel replaced (the light's policy above) */
      if (l->env->negative_texels > 0) {
        int mi = l->env->most_negative_index;
        elr_warn(P->s, P->dir_file, P->dir_line,
                 "LightSource \"infinite\": image \"%s\": %zu negative texels clamped to 0 (the most negative %.3g at texel (%d, %d);"
                 " lossy EXR compression such as DWAB rings below 0; \"string badtexels\" \"error\" refuses them)",
                 path ? path : "(constant L)", l->env->negative_texels, (double)l->env->most_negative, mi % w, mi / w);
      }
      if (l->env->nonfinite_texels > 0)
        elr_warn(P->s, P->dir_file, P->dir_line, "LightSource \"infinite\": image \"%s\": %zu NaN or infinite texels set to 0 (\"string badtexels\" \"zero\")",
                 path ? path : "(constant L)", l->env->nonfinite_texels);
    }
    {
      /* pbrt-v4's "point3 portal" [p0 p1 p2 p3]: a window the light shines through (world space, not
       * the light's CTM, as pbrt-v4's cameraTransform.RenderFromWorld(p)); envlight also takes several
       * rectangles, 4 points each */
      elr__param *pp = elr__find(P, "portal");
      /* envlight's extension: the share of light samples drawn from the map where a portal is seen from
       * behind another portal's plane (a defensive mixture for points outside the room; 0: pbrt-v4's) */
      l->portal_share = (float)elr__pfloat(P, "portalmapshare", ELR_PORTAL_MAP_SHARE);
      elr__check_range(P, "portalmapshare", l->portal_share, 0, 1);
      if (pp) {
        float pts[12 * EL_ENVLIGHT_PORTAL_MAX];
        int np, k;
        double t0 = elr_now();
        pp = elr__findt(P, "portal", "point3", -12);
        np = pp->n / 12;
        if (np < 1 || np > EL_ENVLIGHT_PORTAL_MAX)
          elr__failf(P, pp->file, pp->line, "LightSource \"infinite\": \"point3 portal\" takes 4 points per portal, 1 to %d portals; got %d values",
                     EL_ENVLIGHT_PORTAL_MAX, pp->n);
        for (k = 0; k < 12 * np; k++) pts[k] = (float)pp->num[k];
        if (elr_infinite_set_portals(l, pts, np, e, sizeof e) != 0) elr__failf(P, pp->file, pp->line, "LightSource \"infinite\": %s", e);
        s->t_images += elr_now() - t0;
      }
    }
  } else if (!strcmp(type, "point")) {
    elr_v3 I = elr__prgb(P, "I", elr_v(1, 1, 1));
    elr_v3 from = elr__ppoint(P, "from", "point3", elr_v(0, 0, 0));
    l->kind = ELR_LIGHT_POINT;
    l->L = elr_vmul(I, sc);
    if (!isfinite(l->L.x + l->L.y + l->L.z) || !isfinite(l->L.x) || !isfinite(l->L.y) || !isfinite(l->L.z))
      elr__failf(P, P->dir_file, P->dir_line, "LightSource \"point\": I times scale overflows (%g %g %g)", l->L.x, l->L.y, l->L.z);
    if (l->L.x < 0.f || l->L.y < 0.f || l->L.z < 0.f) /* the infinite light's rule: negative light would render black, unsaid */
      elr__failf(P, P->dir_file, P->dir_line, "LightSource \"point\": I times scale (%g %g %g) must not be negative", l->L.x, l->L.y, l->L.z);
    l->pos = elr_xpoint(&P->ctm, from);
    elr__check_point(P, P->dir_line, l->pos, "the light's position");
    l->nsamples = 1;
  } else if (!strcmp(type, "distant")) {
    elr_v3 L = elr__prgb(P, "L", elr_v(1, 1, 1));
    elr_v3 from = elr__ppoint(P, "from", "point3", elr_v(0, 0, 0));
    elr_v3 to = elr__ppoint(P, "to", "point3", elr_v(0, 0, 1));
    l->kind = ELR_LIGHT_DISTANT;
    l->L = elr_vmul(L, sc);
    if (!isfinite(l->L.x + l->L.y + l->L.z) || !isfinite(l->L.x) || !isfinite(l->L.y) || !isfinite(l->L.z))
      elr__failf(P, P->dir_file, P->dir_line, "LightSource \"distant\": L times scale overflows (%g %g %g)", l->L.x, l->L.y, l->L.z);
    if (l->L.x < 0.f || l->L.y < 0.f || l->L.z < 0.f) /* the infinite light's rule: negative light would render black, unsaid */
      elr__failf(P, P->dir_file, P->dir_line, "LightSource \"distant\": L times scale (%g %g %g) must not be negative", l->L.x, l->L.y, l->L.z);
    l->dir = elr_norm(elr_xvector(&P->ctm, elr_sub(from, to)));
    l->nsamples = 1;
  } else {
    elr_warn(P->s, P->dir_file, P->dir_line, "LightSource \"%s\" is not supported and is ignored", type);
    s->nlight--;
    { int i; for (i = 0; i < P->nparams; i++) P->params[i].used = 1; }
  }
  P->light_param = 0;
}

/* AreaLightSource (pbrt-v3's pbrtAreaLightSource and CreateDiffuseAreaLight): "diffuse", or its alias
 * "area", with L (default 1), scale, twosided (default false) and nsamples ("samples" first, as pbrt-v3
 * reads it; default 1). Every shape after it in the attribute block emits that (elr__attach_area). */
static void elr__area_light_source(elr__parser *P, const char *type) {
  elr__area *a;
  elr_v3 L, sc;
  if (strcmp(type, "diffuse") != 0 && strcmp(type, "area") != 0) {
    int i;
    elr_warn(P->s, P->dir_file, P->dir_line, "AreaLightSource \"%s\" is not supported; the shapes after it do not emit", type);
    for (i = 0; i < P->nparams; i++) P->params[i].used = 1;
    P->gs.area = 0;
    return;
  }
  ELR_PUSH(P, P->areas, P->nareas, P->capareas, elr__area);
  a = &P->areas[P->nareas - 1];
  P->light_param = 1;
  L = elr__prgb(P, "L", elr_v(1, 1, 1));
  sc = elr__prgb(P, "scale", elr_v(1, 1, 1));
  P->light_param = 0;
  a->L = elr_vmul(L, sc);
  if (!isfinite(a->L.x) || !isfinite(a->L.y) || !isfinite(a->L.z))
    elr__failf(P, P->dir_file, P->dir_line, "AreaLightSource \"%s\": L times scale overflows (%g %g %g)", type, a->L.x, a->L.y, a->L.z);
  if (a->L.x < 0.f || a->L.y < 0.f || a->L.z < 0.f)
    elr__failf(P, P->dir_file, P->dir_line, "AreaLightSource \"%s\": L times scale (%g %g %g) must not be negative", type, a->L.x, a->L.y, a->L.z);
  a->twosided = elr__pbool(P, "twosided", 0);
  a->nsamples = elr__pint(P, "nsamples", 1);
  a->nsamples = elr__pint(P, "samples", a->nsamples);
  elr__check_range(P, elr__find(P, "samples") ? "samples" : "nsamples", a->nsamples, 1, 1 << 16);
  P->gs.area = P->nareas;
}
/* The area light of the graphics state on the shape just made (pbrt-v3's pbrtShape: MakeAreaLight for
 * each shape; one light per triangle mesh here, see lights.c). A black L makes no light. */
static void elr__attach_area(elr__parser *P, int kind, int index) {
  elr_scene *s = P->s;
  const elr__area *a;
  elr_light *l;
  if (!P->gs.area) return;
  if (P->cur_object >= 0) { /* pbrt-v3: "Area lights not supported with object instancing" */
    elr__warn_once(P, P->dir_file, P->dir_line, "area in object", "AreaLightSource: the shapes of an ObjectBegin block do not emit (area lights are not supported with object instancing, as in pbrt-v3)");
    return;
  }
  a = &P->areas[P->gs.area - 1];
  if (!(elr_maxc(a->L) > 0.f)) return;
  ELR_PUSH(P, s->light, s->nlight, s->caplight, elr_light);
  l = &s->light[s->nlight - 1];
  l->kind = ELR_LIGHT_AREA;
  l->L = a->L; l->twosided = a->twosided; l->nsamples = a->nsamples;
  l->shape_kind = kind; l->shape = index;
  if (kind == ELR_SHAPE_MESH) s->mesh[index].light = s->nlight - 1;
  else if (kind == ELR_SHAPE_SPHERE) s->sph[index].light = s->nlight - 1;
  else s->disk[index].light = s->nlight - 1;
}

static void elr__object_grow(elr_object *o, double x, double y, double z) {
  o->lo[0] = fmin(o->lo[0], x); o->lo[1] = fmin(o->lo[1], y); o->lo[2] = fmin(o->lo[2], z);
  o->hi[0] = fmax(o->hi[0], x); o->hi[1] = fmax(o->hi[1], y); o->hi[2] = fmax(o->hi[2], z);
}
/* pbrt-v3's Transform::SwapsHandedness: the upper 3x3 has a negative determinant */
static int elr__swaps_handedness(const elr_xform *t) {
  const double(*m)[4] = (const double(*)[4])t->m;
  double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
               m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
  return det < 0;
}
static void elr__add_mesh(elr__parser *P, elr_mesh *m) {
  elr_scene *s = P->s;
  int i;
  m->object = P->cur_object;
  for (i = 0; i < m->nvert; i++) {
    elr_v3 p = elr_xpoint(&P->ctm, elr_v(m->p[3 * i], m->p[3 * i + 1], m->p[3 * i + 2]));
    m->p[3 * i] = p.x; m->p[3 * i + 1] = p.y; m->p[3 * i + 2] = p.z;
    if (!elr__coord_ok(p)) {
      free(m->idx); free(m->p); free(m->n); free(m->uv);
      elr__failf(P, P->dir_file, P->dir_line, "Shape: vertex %d (%g, %g, %g) is not finite or outside |x| <= %g after the transformation", i,
                p.x, p.y, p.z, ELR_MAX_COORD);
    }
    if (m->n) {
      elr_v3 n = elr_norm(elr_xnormal(&P->ctm, elr_v(m->n[3 * i], m->n[3 * i + 1], m->n[3 * i + 2])));
      m->n[3 * i] = n.x; m->n[3 * i + 1] = n.y; m->n[3 * i + 2] = n.z;
    }
  }
  m->material = P->gs.material;
  m->light = -1;
  /* pbrt-v3's triangle orientation (Triangle::Intersect and SetShadingGeometry): ReverseOrientation xor a
   * mirroring CTM turns the normals, with or without the mesh's own normals */
  m->flip = P->gs.reverse ^ elr__swaps_handedness(&P->ctm);
  if (m->object >= 0) { /* a prototype's shape: its bounds grow (ObjectInstance checks them in world space) */
    elr_object *o = &s->obj[m->object];
    for (i = 0; i < m->nvert; i++) elr__object_grow(o, m->p[3 * i], m->p[3 * i + 1], m->p[3 * i + 2]);
    o->nmesh++;
  }
  ELR_PUSH(P, s->mesh, s->nmesh, s->capmesh, elr_mesh);
  s->mesh[s->nmesh - 1] = *m;
  elr__attach_area(P, ELR_SHAPE_MESH, s->nmesh - 1);
}

static void elr__shape(elr__parser *P, const char *type) {
  elr_scene *s = P->s;
  if (!strcmp(type, "sphere")) {
    elr_sphere *sp;
    float r = (float)elr__pfloat(P, "radius", 1.0);
    elr__check_range(P, "radius", r, 1e-20, 1e20);
    if (elr__find(P, "zmin") || elr__find(P, "zmax") || elr__find(P, "phimax")) {
      double zmin = elr__pfloat(P, "zmin", -r), zmax = elr__pfloat(P, "zmax", r), pm = elr__pfloat(P, "phimax", 360.);
      if (zmin > -r || zmax < r || pm < 360.)
        elr_warn(P->s, P->dir_file, P->dir_line, "Shape \"sphere\": zmin/zmax/phimax ignored (only full spheres)");
    }
    { /* the sphere's world-space bounds must be traceable */
      elr_v3 c = elr_xpoint(&P->ctm, elr_v(0, 0, 0));
      double sc = 0;
      int i, j;
      for (j = 0; j < 3; j++) {
        double col = 0;
        for (i = 0; i < 3; i++) col += P->ctm.m[i][j] * P->ctm.m[i][j];
        if (sqrt(col) > sc) sc = sqrt(col);
      }
      elr__check_point(P, P->dir_line, c, "the sphere's centre");
      if (!(r * sc <= ELR_MAX_COORD))
        elr__failf(P, P->dir_file, P->dir_line, "Shape \"sphere\": the radius in world space (%g) is outside |x| <= %g", r * sc, ELR_MAX_COORD);
    }
    ELR_PUSH(P, s->sph, s->nsph, s->capsph, elr_sphere);
    sp = &s->sph[s->nsph - 1];
    sp->o2w = P->ctm; sp->radius = r; sp->material = P->gs.material;
    sp->light = -1;
    sp->flip = P->gs.reverse ^ elr__swaps_handedness(&P->ctm);
    sp->object = P->cur_object;
    if (sp->object >= 0) {
      elr_object *o = &s->obj[sp->object];
      int i;
      for (i = 0; i < 8; i++) {
        elr_v3 c = elr_xpoint(&sp->o2w, elr_v(i & 1 ? r : -r, i & 2 ? r : -r, i & 4 ? r : -r));
        elr__object_grow(o, c.x, c.y, c.z);
      }
      o->nsph++;
    }
    elr__attach_area(P, ELR_SHAPE_SPHERE, s->nsph - 1);
  } else if (!strcmp(type, "disk")) { /* pbrt-v3's CreateDiskShape: height 0, radius 1, innerradius 0, phimax 360 */
    elr_disk *dk;
    double h = elr__pfloat(P, "height", 0.0), r = elr__pfloat(P, "radius", 1.0), ri = elr__pfloat(P, "innerradius", 0.0);
    double pm = elr__pfloat(P, "phimax", 360.0), sc = 0;
    int i, j;
    elr__check_range(P, "radius", r, 1e-20, 1e20);
    elr__check_range(P, "innerradius", ri, 0.0, r);
    if (!(ri < r)) elr__failf(P, P->dir_file, P->dir_line, "Shape \"disk\": innerradius %g must be smaller than radius %g", ri, r);
    if (!(pm > 0.0)) elr__failf(P, P->dir_file, P->dir_line, "Shape \"disk\": phimax %g must be positive", pm);
    if (pm > 360.0) pm = 360.0; /* pbrt-v3 clamps it to [0, 360] */
    elr__check_range(P, "height", h, -ELR_MAX_COORD, ELR_MAX_COORD);
    if (P->cur_object >= 0) {
      elr__warn_once(P, P->dir_file, P->dir_line, "disk in object", "Shape \"disk\" inside ObjectBegin is not supported and is left out");
      return;
    }
    for (j = 0; j < 3; j++) { /* the disk's world-space bounds must be traceable */
      double col = 0;
      for (i = 0; i < 3; i++) col += P->ctm.m[i][j] * P->ctm.m[i][j];
      if (sqrt(col) > sc) sc = sqrt(col);
    }
    elr__check_point(P, P->dir_line, elr_xpoint(&P->ctm, elr_v(0, 0, (float)h)), "the disk's centre");
    if (!(r * sc <= ELR_MAX_COORD))
      elr__failf(P, P->dir_file, P->dir_line, "Shape \"disk\": the radius in world space (%g) is outside |x| <= %g", r * sc, ELR_MAX_COORD);
    ELR_PUSH(P, s->disk, s->ndisk, s->capdisk, elr_disk);
    dk = &s->disk[s->ndisk - 1];
    dk->o2w = P->ctm; dk->height = (float)h; dk->radius = (float)r; dk->inner = (float)ri;
    dk->phimax = (float)(pm * 3.14159265358979323846 / 180.0);
    dk->material = P->gs.material; dk->light = -1; dk->flip = P->gs.reverse ^ elr__swaps_handedness(&P->ctm);
    elr__attach_area(P, ELR_SHAPE_DISK, s->ndisk - 1);
  } else if (!strcmp(type, "trianglemesh")) {
    elr_mesh m;
    elr__param *pi = elr__findt(P, "indices", "integer", -3);
    elr__param *pp = elr__findt(P, "P", "point3", -3);
    elr__param *pn = elr__find(P, "N") ? elr__findt(P, "N", "normal3", -3) : NULL;
    elr__param *puv = NULL;
    int i;
    const char *uvn = elr__find(P, "uv") ? "uv" : (elr__find(P, "st") ? "st" : NULL);
    if (uvn) {
      elr__param *q = elr__find(P, uvn);
      puv = elr__findt(P, uvn, !strcmp(q->type, "point2") ? "point2" : "float", -2);
    }
    if (elr__find(P, "S")) elr_warn(P->s, P->dir_file, P->dir_line, "Shape \"trianglemesh\": \"S\" (tangents) ignored"), elr__find(P, "S")->used = 1;
    if (!pp) elr__failf(P, P->dir_file, P->dir_line, "Shape \"trianglemesh\": \"point3 P\" is required");
    if (!pi) {
      if (pp->n != 9) elr__failf(P, P->dir_file, P->dir_line, "Shape \"trianglemesh\": \"integer indices\" is required");
    }
    memset(&m, 0, sizeof m);
    m.nvert = pp->n / 3;
    m.ntri = pi ? pi->n / 3 : 1;
    if (m.ntri == 0) elr__failf(P, P->dir_file, P->dir_line, "Shape \"trianglemesh\": no triangles");
    if (pn && pn->n != pp->n) elr__failf(P, pn->file, pn->line, "Shape \"trianglemesh\": \"N\" must have as many values as \"P\"");
    if (puv && puv->n / 2 != m.nvert) elr__failf(P, puv->file, puv->line, "Shape \"trianglemesh\": \"%s\" must have 2 values per vertex", uvn);
    for (i = 0; pi && i < pi->n; i++)
      if (pi->num[i] < 0 || pi->num[i] >= m.nvert)
        elr__failf(P, pi->file, pi->line, "Shape \"trianglemesh\": index %g out of range [0, %d)", pi->num[i], m.nvert);
    m.idx = (unsigned *)malloc(sizeof(unsigned) * 3 * (size_t)m.ntri);
    m.p = (float *)malloc(sizeof(float) * 3 * (size_t)m.nvert);
    m.n = pn ? (float *)malloc(sizeof(float) * 3 * (size_t)m.nvert) : NULL;
    m.uv = puv ? (float *)malloc(sizeof(float) * 2 * (size_t)m.nvert) : NULL;
    if (!m.idx || !m.p || (pn && !m.n) || (puv && !m.uv)) {
      free(m.idx); free(m.p); free(m.n); free(m.uv);
      elr__failf(P, P->dir_file, P->dir_line, "out of memory");
    }
    for (i = 0; i < 3 * m.ntri; i++) m.idx[i] = pi ? (unsigned)pi->num[i] : (unsigned)i;
    for (i = 0; i < 3 * m.nvert; i++) m.p[i] = (float)pp->num[i];
    for (i = 0; pn && i < 3 * m.nvert; i++) m.n[i] = (float)pn->num[i];
    for (i = 0; puv && i < 2 * m.nvert; i++) m.uv[i] = (float)puv->num[i];
    elr__add_mesh(P, &m);
  } else if (!strcmp(type, "loopsubdiv")) { /* pbrt-v3's CreateLoopSubdiv */
    elr_mesh m;
    char e[300];
    elr__param *pi = elr__findt(P, "indices", "integer", -3), *pp = elr__findt(P, "P", "point3", -3);
    int levels = elr__find(P, "levels") ? elr__pint(P, "levels", 3) : elr__pint(P, "nlevels", 3), *idx, i, dropped;
    if (elr__find(P, "scheme")) elr__pstring(P, "scheme", "loop"); /* pbrt-v3: "don't actually use this for now" */
    if (!pi) elr__failf(P, P->dir_file, P->dir_line, "Shape \"loopsubdiv\": \"integer indices\" is required");
    if (!pp) elr__failf(P, P->dir_file, P->dir_line, "Shape \"loopsubdiv\": \"point3 P\" is required");
    elr__check_range(P, elr__find(P, "levels") ? "levels" : "nlevels", levels, 0, 12);
    if (pi->n == 0) elr__failf(P, P->dir_file, P->dir_line, "Shape \"loopsubdiv\": no triangles");
    for (i = 0; i < pi->n; i++)
      if (pi->num[i] < 0 || pi->num[i] >= pp->n / 3)
        elr__failf(P, pi->file, pi->line, "Shape \"loopsubdiv\": index %g out of range [0, %d)", pi->num[i], pp->n / 3);
    idx = (int *)elr__alloc(P, sizeof(int) * (size_t)pi->n);
    for (i = 0; i < pi->n; i++) idx[i] = (int)pi->num[i];
    {
      double t0 = elr_now();
      if (elr_loop_subdivide(levels, idx, pi->n, pp->num, pp->n / 3, &m, &dropped, e, sizeof e) != 0)
        elr__failf(P, P->dir_file, P->dir_line, "Shape \"loopsubdiv\": %s", e);
      P->s->t_images += elr_now() - t0; /* (the time of files and of built geometry, as PLY meshes) */
    }
    if (dropped) elr_warn(P->s, P->dir_file, P->dir_line, "Shape \"loopsubdiv\": %d triangle%s with a repeated vertex left out", dropped,
                          dropped == 1 ? "" : "s");
    elr__add_mesh(P, &m);
  } else if (!strcmp(type, "plymesh")) {
    elr_mesh m;
    char e[600];
    const char *fn = elr__pstring(P, "filename", "");
    char *path;
    double t0 = elr_now();
    if (!fn[0]) elr__failf(P, P->dir_file, P->dir_line, "Shape \"plymesh\": \"string filename\" is required");
    path = elr__resolve(P, fn);
    memset(&m, 0, sizeof m);
    if (elr_ply_load(path, &m, e, sizeof e) != 0) elr__failf(P, P->dir_file, P->dir_line, "Shape \"plymesh\": %s", e);
    P->s->t_images += elr_now() - t0;
    elr__add_mesh(P, &m);
  } else {
    char key[200];
    snprintf(key, sizeof key, "Shape %.180s", type);
    elr__warn_once(P, P->dir_file, P->dir_line, key, "Shape \"%s\" is not supported and is ignored", type);
    { int i; for (i = 0; i < P->nparams; i++) P->params[i].used = 1; }
  }
  if (elr__find(P, "alpha")) { elr_warn(P->s, P->dir_file, P->dir_line, "Shape: \"alpha\" ignored"); elr__find(P, "alpha")->used = 1; }
}

/* glass's and uber's index of refraction: pbrt-v3's "eta", else "index" (1.5); a number must be one
 * the Fresnel and refraction maths can use (textures are kept in [1e-3, 1e3] where evaluated) */
static int elr__pindex(elr__parser *P) {
  const char *nm = elr__find(P, "eta") ? "eta" : "index";
  elr__param *p = elr__find(P, nm);
  if (p && strcmp(p->type, "texture") != 0) elr__check_range(P, nm, elr__pfloat(P, nm, 1.5), 1e-3, 1e3);
  return elr__ptex(P, nm, elr_v(1.5f, 1.5f, 1.5f), 1);
}
static int elr__make_material(elr__parser *P, const char *type) {
  elr_scene *s = P->s;
  elr_material *m;
  int kind;
  if (!strcmp(type, "matte")) kind = ELR_MAT_MATTE;
  else if (!strcmp(type, "mirror")) kind = ELR_MAT_MIRROR;
  else if (!strcmp(type, "plastic")) kind = ELR_MAT_PLASTIC;
  else if (!strcmp(type, "glass")) kind = ELR_MAT_GLASS;
  else if (!strcmp(type, "metal")) kind = ELR_MAT_METAL;
  else if (!strcmp(type, "uber")) kind = ELR_MAT_UBER;
  else if (!strcmp(type, "substrate")) kind = ELR_MAT_SUBSTRATE;
  else {
    char key[200];
    snprintf(key, sizeof key, "Material %.180s", type);
    if (!strcmp(type, "") || !strcmp(type, "none") || !strcmp(type, "interface")) {
      elr__warn_once(P, P->dir_file, P->dir_line, key, "Material \"%s\" (no surface) is not supported; using \"matte\"", type);
    } else {
      elr__warn_once(P, P->dir_file, P->dir_line, key, "Material \"%s\" is not supported; using \"matte\" with its defaults", type);
    }
    { int i; for (i = 0; i < P->nparams; i++) P->params[i].used = 1; }
    kind = -1;
  }
  ELR_PUSH(P, s->mat, s->nmat, s->capmat, elr_material);
  m = &s->mat[s->nmat - 1];
  m->kind = kind < 0 ? ELR_MAT_MATTE : kind;
  m->kd = m->ks = m->kr = m->rough = -1;
  m->kt = m->urough = m->vrough = m->index = m->eta = m->k = m->opacity = -1;
  if (kind < 0) { m->kd = elr__const_tex(P, elr_v(.5f, .5f, .5f)); return s->nmat - 1; }
  if (kind == ELR_MAT_MATTE) {
    m->kd = elr__ptex(P, "Kd", elr_v(.5f, .5f, .5f), 0);
    /* sigma (degrees): pbrt-v3's OrenNayar where it is not 0; its texture in the "rough" slot, only
     * when given, so a matte without it keeps the fixed Lambertian lobe */
    if (elr__find(P, "sigma")) m->rough = elr__ptex(P, "sigma", elr_v(0, 0, 0), 1);
  } else if (kind == ELR_MAT_MIRROR) {
    m->kr = elr__ptex(P, "Kr", elr_v(.9f, .9f, .9f), 0);
  } else if (kind == ELR_MAT_PLASTIC) {
    m->kd = elr__ptex(P, "Kd", elr_v(.25f, .25f, .25f), 0);
    m->ks = elr__ptex(P, "Ks", elr_v(.25f, .25f, .25f), 0);
    m->rough = elr__ptex(P, "roughness", elr_v(.1f, .1f, .1f), 1);
    m->remap = elr__pbool(P, "remaproughness", 1);
  } else if (kind == ELR_MAT_GLASS) { /* CreateGlassMaterial */
    m->kr = elr__ptex(P, "Kr", elr_v(1, 1, 1), 0);
    m->kt = elr__ptex(P, "Kt", elr_v(1, 1, 1), 0);
    m->index = elr__pindex(P);
    m->urough = elr__ptex(P, "uroughness", elr_v(0, 0, 0), 1);
    m->vrough = elr__ptex(P, "vroughness", elr_v(0, 0, 0), 1);
    m->remap = elr__pbool(P, "remaproughness", 1);
  } else if (kind == ELR_MAT_METAL) { /* CreateMetalMaterial: copper by default */
    /* pbrt-v3's CopperN and CopperK spectra (materials/metal.cpp, 56 samples from 298.8 to 885.6 nm)
     * as RGBSpectrum::FromSampled makes them: the CIE 1931 matching functions of core/spectrum.cpp at
     * 1 nm, normalised by CIE_Y_integral, then XYZToRGB; computed in float with pbrt-v3's own tables
     * and order of operations (Mitsuba 3's Cu preset, from other measurements: 0.2004 0.9240 1.1022
     * and 3.9129 2.4528 2.1422) */
    m->eta = elr__ptex(P, "eta", elr_v(0.19999069f, 0.92208463f, 1.09987593f), 0);
    m->k = elr__ptex(P, "k", elr_v(3.90463543f, 2.44763327f, 2.13765264f), 0);
    m->rough = elr__ptex(P, "roughness", elr_v(.01f, .01f, .01f), 1);
    if (elr__find(P, "uroughness")) m->urough = elr__ptex(P, "uroughness", elr_v(0, 0, 0), 1);
    if (elr__find(P, "vroughness")) m->vrough = elr__ptex(P, "vroughness", elr_v(0, 0, 0), 1);
    m->remap = elr__pbool(P, "remaproughness", 1);
  } else if (kind == ELR_MAT_UBER) { /* CreateUberMaterial */
    m->kd = elr__ptex(P, "Kd", elr_v(.25f, .25f, .25f), 0);
    m->ks = elr__ptex(P, "Ks", elr_v(.25f, .25f, .25f), 0);
    m->kr = elr__ptex(P, "Kr", elr_v(0, 0, 0), 0);
    m->kt = elr__ptex(P, "Kt", elr_v(0, 0, 0), 0);
    m->rough = elr__ptex(P, "roughness", elr_v(.1f, .1f, .1f), 1);
    if (elr__find(P, "uroughness")) m->urough = elr__ptex(P, "uroughness", elr_v(0, 0, 0), 1);
    if (elr__find(P, "vroughness")) m->vrough = elr__ptex(P, "vroughness", elr_v(0, 0, 0), 1);
    m->index = elr__pindex(P);
    m->opacity = elr__ptex(P, "opacity", elr_v(1, 1, 1), 0);
    m->remap = elr__pbool(P, "remaproughness", 1);
  } else { /* CreateSubstrateMaterial */
    m->kd = elr__ptex(P, "Kd", elr_v(.5f, .5f, .5f), 0);
    m->ks = elr__ptex(P, "Ks", elr_v(.5f, .5f, .5f), 0);
    m->urough = elr__ptex(P, "uroughness", elr_v(.1f, .1f, .1f), 1);
    m->vrough = elr__ptex(P, "vroughness", elr_v(.1f, .1f, .1f), 1);
    m->remap = elr__pbool(P, "remaproughness", 1);
  }
  if (elr__find(P, "bumpmap")) { elr_warn(P->s, P->dir_file, P->dir_line, "Material: \"bumpmap\" ignored"); elr__find(P, "bumpmap")->used = 1; }
  return s->nmat - 1;
}

/* How many textures one evaluation of texture ti may look up: a checkerboard evaluates both of its
 * sub-textures where its filter straddles an edge, a scale both, a mix all three (textures.c recurses). Every texture already made has a
 * cost of at most ELR_MAX_TEX_COST, so this recursion visits at most that many leaves. */
#define ELR_MAX_TEX_COST 64
static int elr__tex_cost(const elr_scene *s, int ti) {
  const elr_texture *t;
  if (ti < 0 || ti >= s->ntex) return 1;
  t = &s->tex[ti];
  if (t->kind == ELR_TEX_MIX) return elr__tex_cost(s, t->tex1) + elr__tex_cost(s, t->tex2) + elr__tex_cost(s, t->amount);
  if (t->kind != ELR_TEX_CHECKER && t->kind != ELR_TEX_SCALE) return 1;
  return elr__tex_cost(s, t->tex1) + elr__tex_cost(s, t->tex2);
}

static void elr__texture(elr__parser *P, const char *name, const char *vtype, const char *cls) {
  elr_scene *s = P->s;
  elr_texture t;
  int is_float = !strcmp(vtype, "float");
  const char *mapping;
  if (!is_float && strcmp(vtype, "spectrum") && strcmp(vtype, "color") && strcmp(vtype, "rgb"))
    elr__failf(P, P->dir_file, P->dir_line, "Texture \"%s\": type \"%s\" must be \"float\" or \"spectrum\"", name, vtype);
  memset(&t, 0, sizeof t);
  t.is_float = is_float;
  mapping = elr__pstring(P, "mapping", "uv");
  if (strcmp(mapping, "uv") != 0) elr_warn(P->s, P->dir_file, P->dir_line, "Texture \"%s\": mapping \"%s\" not supported; using \"uv\"", name, mapping);
  t.su = (float)elr__pfloat(P, "uscale", 1.0); t.sv = (float)elr__pfloat(P, "vscale", 1.0);
  t.du = (float)elr__pfloat(P, "udelta", 0.0); t.dv = (float)elr__pfloat(P, "vdelta", 0.0);
  if (!strcmp(cls, "constant")) {
    t.kind = ELR_TEX_CONST;
    if (is_float) { float v = (float)elr__pfloat(P, "value", 1.0); t.value = elr_v(v, v, v); }
    else t.value = elr__prgb(P, "value", elr_v(1, 1, 1));
  } else if (!strcmp(cls, "checkerboard")) {
    int dim = elr__pint(P, "dimension", 2);
    const char *aa = elr__pstring(P, "aamode", "closedform");
    if (dim != 2) elr__failf(P, P->dir_file, P->dir_line, "Texture \"%s\": checkerboard dimension %d not supported (only 2)", name, dim);
    t.kind = ELR_TEX_CHECKER;
    t.tex1 = elr__ptex(P, "tex1", elr_v(1, 1, 1), is_float);
    t.tex2 = elr__ptex(P, "tex2", elr_v(0, 0, 0), is_float);
    { /* chained checkerboards double the work per level (2^40 lookups from a 40-line file) and recurse
       * once per level on a render thread's stack (200000 levels overflowed it) */
      int cost = elr__tex_cost(s, t.tex1) + elr__tex_cost(s, t.tex2);
      if (cost > ELR_MAX_TEX_COST)
        elr__failf(P, P->dir_file, P->dir_line, "Texture \"%s\": checkerboards nested too deeply (%d texture lookups per evaluation, at most %d)",
                  name, cost, ELR_MAX_TEX_COST);
    }
    if (!strcmp(aa, "closedform")) t.aa_closedform = 1;
    else if (!strcmp(aa, "none")) t.aa_closedform = 0;
    else elr__failf(P, P->dir_file, P->dir_line, "Texture \"%s\": aamode must be \"closedform\" or \"none\"", name);
  } else if (!strcmp(cls, "scale") || !strcmp(cls, "mix")) {
    /* pbrt-v3's ScaleTexture (tex1 * tex2, both 1 by default) and MixTexture ((1 - amount) tex1 +
     * amount tex2; tex1 0, tex2 1, amount 0.5) */
    int mix = cls[0] == 'm';
    float d1 = mix ? 0.f : 1.f;
    const elr_texture *a, *b, *m = NULL;
    t.kind = mix ? ELR_TEX_MIX : ELR_TEX_SCALE;
    t.tex1 = elr__ptex(P, "tex1", elr_v(d1, d1, d1), is_float);
    t.tex2 = elr__ptex(P, "tex2", elr_v(1, 1, 1), is_float);
    t.amount = mix ? elr__ptex(P, "amount", elr_v(.5f, .5f, .5f), 1) : -1;
    {
      int cost = elr__tex_cost(s, t.tex1) + elr__tex_cost(s, t.tex2) + (mix ? elr__tex_cost(s, t.amount) : 0);
      if (cost > ELR_MAX_TEX_COST)
        elr__failf(P, P->dir_file, P->dir_line, "Texture \"%s\": textures nested too deeply (%d texture lookups per evaluation, at most %d)",
                  name, cost, ELR_MAX_TEX_COST);
    }
    /* of constants, a constant (the same sums textures.c would make at every shading point) */
    a = &s->tex[t.tex1]; b = &s->tex[t.tex2];
    if (mix) m = &s->tex[t.amount];
    if (a->kind == ELR_TEX_CONST && b->kind == ELR_TEX_CONST && (!mix || m->kind == ELR_TEX_CONST)) {
      if (mix) t.value = elr_add(elr_mul(a->value, 1.f - m->value.x), elr_mul(b->value, m->value.x));
      else t.value = elr_vmul(a->value, b->value);
      t.kind = ELR_TEX_CONST;
    }
  } else if (!strcmp(cls, "imagemap")) {
    const char *fn = elr__pstring(P, "filename", "");
    const char *wrap = elr__pstring(P, "wrap", "repeat");
    float scale = (float)elr__pfloat(P, "scale", 1.0);
    float maxan = (float)elr__pfloat(P, "maxanisotropy", 8.0);
    el_mipmap_options mo;
    el_mipmap_filter filter = EL_MIPMAP_FILTER_EWA;
    el_mipmap_wrap wr;
    int gamma;
    size_t fl = strlen(fn);
    el_image img;
    float *rgb;
    char *path;
    if (elr__find(P, "filter")) {
      const char *f = elr__pstring(P, "filter", "bilinear");
      if (!strcmp(f, "ewa") || !strcmp(f, "EWA")) filter = EL_MIPMAP_FILTER_EWA;
      else if (!strcmp(f, "trilinear")) filter = EL_MIPMAP_FILTER_TRILINEAR;
      else if (!strcmp(f, "bilinear")) filter = EL_MIPMAP_FILTER_BILINEAR;
      else elr__failf(P, elr__find(P, "filter")->file, elr__find(P, "filter")->line, "Texture \"%s\": filter must be \"bilinear\", \"trilinear\" or \"ewa\"", name);
    } else if (elr__find(P, "trilinear")) { /* pbrt-v3's spelling */
      filter = elr__pbool(P, "trilinear", 0) ? EL_MIPMAP_FILTER_TRILINEAR : EL_MIPMAP_FILTER_EWA;
    }
    if (!strcmp(wrap, "repeat")) wr = EL_MIPMAP_WRAP_REPEAT;
    else if (!strcmp(wrap, "black")) wr = EL_MIPMAP_WRAP_BLACK;
    else if (!strcmp(wrap, "clamp")) wr = EL_MIPMAP_WRAP_CLAMP;
    else elr__failf(P, elr__find(P, "wrap")->file, elr__find(P, "wrap")->line, "Texture \"%s\": wrap must be \"repeat\", \"black\" or \"clamp\"", name);
    elr__check_range(P, "maxanisotropy", maxan, 1.0, 1024.0); /* mipmap.h's limit */
    if (!fn[0]) elr__failf(P, P->dir_file, P->dir_line, "Texture \"%s\": imagemap needs \"string filename\"", name);
    gamma = elr__pbool(P, "gamma", (fl > 4 && (!strcmp(fn + fl - 4, ".png") || !strcmp(fn + fl - 4, ".tga"))));
    path = elr__resolve(P, fn);
    elr__load_image(P, path, P->dir_line, &img);
    rgb = elr__to_rgb(P, &img, gamma, scale, path);
    if (is_float) { /* pbrt-v3 converts to float by luminance */
      size_t i, n = (size_t)img.width * (size_t)img.height;
      for (i = 0; i < n; i++) {
        float y = 0.212671f * rgb[3 * i] + 0.715160f * rgb[3 * i + 1] + 0.072169f * rgb[3 * i + 2];
        rgb[3 * i] = rgb[3 * i + 1] = rgb[3 * i + 2] = y;
      }
    }
    { /* <<Flip image in y; texture coordinate space has (0,0) at the lower left corner>> (pbrt-v3) */
      int y, W = img.width, H = img.height;
      size_t row = (size_t)W * 3, k;
      for (y = 0; y < H / 2; y++)
        for (k = 0; k < row; k++) {
          float tmp = rgb[(size_t)y * row + k];
          rgb[(size_t)y * row + k] = rgb[(size_t)(H - 1 - y) * row + k];
          rgb[(size_t)(H - 1 - y) * row + k] = tmp;
        }
    }
    t.kind = ELR_TEX_IMAGE;
    {
      double t0 = elr_now();
      el_result r = EL_ERROR_OUT_OF_MEMORY;
      /* pbrt-v3's ImageTexture: a MIPMap of the image (mipmap.h; the texture owns it) */
      memset(&mo, 0, sizeof mo);
      mo.wrap_u = mo.wrap_v = wr;
      mo.filter = filter;
      mo.max_anisotropy = maxan;
      t.mip = (el_mipmap *)calloc(1, sizeof *t.mip);
      if (t.mip) r = el_mipmap_init(t.mip, rgb, img.width, img.height, 3, &mo);
      if (r != EL_SUCCESS) { free(t.mip); t.mip = NULL; }
      free(rgb);
      s->t_images += elr_now() - t0;
      s->bytes_textures += (size_t)img.width * (size_t)img.height * 3 * sizeof(float);
      el_image_free(&img);
      if (r != EL_SUCCESS) elr__failf(P, P->dir_file, P->dir_line, "Texture \"%s\": MIP map: %s", name, el_result_string(r));
    }
  } else {
    char key[200];
    snprintf(key, sizeof key, "Texture %.180s", cls);
    elr__warn_once(P, P->dir_file, P->dir_line, key, "Texture class \"%s\" is not supported; \"%s\" is a constant %s", cls, name,
                   is_float ? "1" : "(1,1,1)");
    { int i; for (i = 0; i < P->nparams; i++) P->params[i].used = 1; }
    t.kind = ELR_TEX_CONST; t.value = elr_v(1, 1, 1);
  }
  ELR_PUSH(P, s->tex, s->ntex, s->captex, elr_texture);
  s->tex[s->ntex - 1] = t;
  /* name it in the current scope */
  if (P->gs.ntex_scope < P->ntexn) { /* drop names of closed scopes */
    elr__name_drop(&P->htex, P->texnames, P->ntexn, P->gs.ntex_scope);
    P->ntexn = P->gs.ntex_scope;
  }
  ELR_PUSH(P, P->texnames, P->ntexn, P->captexn, elr__named);
  P->texnames[P->ntexn - 1].name = elr__strdup(P, name, strlen(name));
  elr__name_add(P, &P->htex, P->texnames, P->ntexn - 1);
  P->texnames[P->ntexn - 1].index = s->ntex - 1;
  P->texnames[P->ntexn - 1].is_float = is_float;
  P->gs.ntex_scope = P->ntexn;
}

static void elr__parse_file(elr__parser *P, const char *text, size_t len, const char *name) {
  elr__lexer *L;
  if (P->nlex >= ELR_MAX_INCLUDE) elr__failf(P, P->dir_file, P->dir_line, "Include nested more than %d deep (recursive include?)", ELR_MAX_INCLUDE);
  L = &P->lex[P->nlex++];
  L->text = L->p = text; L->end = text + len; L->file = name; L->line = 1;
}

static char *elr__read_file(elr__parser *P, const char *path, size_t *len, int line) {
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

static void elr__skip_args(elr__parser *P) {
  for (;;) {
    elr__tok t = elr__peek(P);
    if (t.kind == T_EOF) return;
    if (t.kind == T_WORD && !elr__wordis(&t, "true") && !elr__wordis(&t, "false")) return;
    elr__next(P);
  }
}

static void elr__directive_block(elr__parser *P, int need_world, const char *what) {
  if (need_world && !P->in_world) {
    elr_warn(P->s, P->dir_file, P->dir_line, "%s before WorldBegin is not allowed; ignoring it", what);
  }
  if (!need_world && P->in_world) {
    elr_warn(P->s, P->dir_file, P->dir_line, "%s inside the world block is not allowed; ignoring it", what);
  }
}

static void elr__run(elr__parser *P) {
  static const char *unsupported[] = {"ColorSpace", "Option", "Attribute", "AttributeSet", "SurfaceIntegrator",
                                      "VolumeIntegrator", "Renderer", "Volume"};
  for (;;) {
    elr__tok t = elr__next(P);
    char nm[64];
    int is_xform;
    elr_xform saved_ctm;
    if (t.kind == T_EOF) break;
    P->dir_line = t.line; P->dir_file = elr__curfile(P); /* the token was read from the current file */
    if (t.kind != T_WORD) {
      if (t.kind == T_STRING) elr__failf(P, P->dir_file, t.line, "expected a directive, got the string \"%s\" (a parameter without a directive?)", t.s);
      elr__failf(P, P->dir_file, t.line, "expected a directive, got %s", t.kind == T_NUM ? "a number" : (t.kind == T_LBR ? "'['" : "']'"));
    }
    if (t.len >= sizeof nm) elr__failf(P, P->dir_file, t.line, "unknown directive \"%.*s\"", 40, t.s);
    memcpy(nm, t.s, t.len); nm[t.len] = 0;
    snprintf(P->dir_name, sizeof P->dir_name, "%s", nm);
    P->dir_line = t.line; P->dir_file = elr__curfile(P);
    if (P->world_ended) elr__failf(P, P->dir_file, t.line, "directive \"%s\" after WorldEnd", nm);
    is_xform = !strcmp(nm, "Translate") || !strcmp(nm, "Scale") || !strcmp(nm, "Rotate") || !strcmp(nm, "LookAt") ||
               !strcmp(nm, "Transform") || !strcmp(nm, "ConcatTransform") || !strcmp(nm, "Identity") || !strcmp(nm, "CoordSysTransform");
    saved_ctm = P->ctm;

    if (!strcmp(nm, "Translate")) {
      double x = elr__num(P, nm), y = elr__num(P, nm), z = elr__num(P, nm);
      double m[4][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}};
      elr_xform a, r;
      m[0][3] = x; m[1][3] = y; m[2][3] = z;
      elr_xform_from_matrix(&a, m); elr_xform_mul(&r, &P->ctm, &a); P->ctm = r;
      elr__check_ctm(P, t.line);
    } else if (!strcmp(nm, "Scale")) {
      double x = elr__num(P, nm), y = elr__num(P, nm), z = elr__num(P, nm);
      double m[4][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}};
      elr_xform a, r;
      m[0][0] = x; m[1][1] = y; m[2][2] = z;
      if (x == 0 || y == 0 || z == 0) elr__failf(P, P->dir_file, t.line, "Scale %g %g %g is singular", x, y, z);
      elr_xform_from_matrix(&a, m); elr_xform_mul(&r, &P->ctm, &a); P->ctm = r;
      elr__check_ctm(P, t.line);
    } else if (!strcmp(nm, "Rotate")) {
      double ang = elr__num(P, nm), x = elr__num(P, nm), y = elr__num(P, nm), z = elr__num(P, nm);
      double l = sqrt(x * x + y * y + z * z), s, c, m[4][4];
      elr_xform a, r;
      if (!(l > 0)) elr__failf(P, P->dir_file, t.line, "Rotate: the axis is zero");
      x /= l; y /= l; z /= l;
      s = sin(ang * 3.14159265358979323846 / 180.0); c = cos(ang * 3.14159265358979323846 / 180.0);
      /* pbrt-v3's Rotate(theta, axis) */
      m[0][0] = x * x + (1 - x * x) * c; m[0][1] = x * y * (1 - c) - z * s; m[0][2] = x * z * (1 - c) + y * s; m[0][3] = 0;
      m[1][0] = x * y * (1 - c) + z * s; m[1][1] = y * y + (1 - y * y) * c; m[1][2] = y * z * (1 - c) - x * s; m[1][3] = 0;
      m[2][0] = x * z * (1 - c) - y * s; m[2][1] = y * z * (1 - c) + x * s; m[2][2] = z * z + (1 - z * z) * c; m[2][3] = 0;
      m[3][0] = m[3][1] = m[3][2] = 0; m[3][3] = 1;
      elr_xform_from_matrix(&a, m); elr_xform_mul(&r, &P->ctm, &a); P->ctm = r;
      elr__check_ctm(P, t.line);
    } else if (!strcmp(nm, "LookAt")) {
      double v[9];
      int i;
      elr_v3 pos, look, up, dir, right, nup;
      double m[4][4];
      elr_xform c2w, w2c, r;
      for (i = 0; i < 9; i++) v[i] = elr__num(P, nm);
      for (i = 0; i < 9; i++)
        if (fabs(v[i]) > ELR_MAX_COORD) elr__failf(P, P->dir_file, t.line, "LookAt: %g is outside |x| <= %g", v[i], ELR_MAX_COORD);
      pos = elr_v((float)v[0], (float)v[1], (float)v[2]);
      look = elr_v((float)v[3], (float)v[4], (float)v[5]);
      up = elr_v((float)v[6], (float)v[7], (float)v[8]);
      dir = elr_sub(look, pos);
      if (elr_len(dir) == 0.f) elr__failf(P, P->dir_file, t.line, "LookAt: eye and look-at point coincide");
      dir = elr_norm(dir);
      if (elr_len(up) == 0.f || elr_len(elr_cross(elr_norm(up), dir)) == 0.f)
        elr__failf(P, P->dir_file, t.line, "LookAt: the up vector is zero or parallel to the viewing direction");
      right = elr_norm(elr_cross(elr_norm(up), dir));
      nup = elr_cross(dir, right);
      m[0][0] = right.x; m[1][0] = right.y; m[2][0] = right.z; m[3][0] = 0;
      m[0][1] = nup.x; m[1][1] = nup.y; m[2][1] = nup.z; m[3][1] = 0;
      m[0][2] = dir.x; m[1][2] = dir.y; m[2][2] = dir.z; m[3][2] = 0;
      m[0][3] = v[0]; m[1][3] = v[1]; m[2][3] = v[2]; m[3][3] = 1;
      if (elr_xform_from_matrix(&c2w, m) != 0) elr__failf(P, P->dir_file, t.line, "LookAt: the camera frame is singular");
      elr_xform_invert(&w2c, &c2w);
      elr_xform_mul(&r, &P->ctm, &w2c); P->ctm = r;
      elr__check_ctm(P, t.line);
    } else if (!strcmp(nm, "Transform") || !strcmp(nm, "ConcatTransform")) {
      double v[16], m[4][4];
      int i, j;
      elr_xform a, r;
      elr__nums16(P, v, nm);
      for (i = 0; i < 4; i++) for (j = 0; j < 4; j++) m[i][j] = v[j * 4 + i]; /* pbrt: Transpose */
      if (elr_xform_from_matrix(&a, m) != 0) elr__failf(P, P->dir_file, t.line, "%s: the matrix is singular", nm);
      if (nm[0] == 'T') P->ctm = a;
      else { elr_xform_mul(&r, &P->ctm, &a); P->ctm = r; }
      elr__check_ctm(P, t.line);
    } else if (!strcmp(nm, "Identity")) {
      elr_xform_identity(&P->ctm);
    } else if (!strcmp(nm, "ReverseOrientation")) { /* graphics state: the normals of the shapes after it */
      P->gs.reverse = !P->gs.reverse;
    } else if (!strcmp(nm, "CoordinateSystem")) {
      const char *n = elr__str(P, nm);
      int k = elr__name_find(&P->hctx, P->ctx, P->nctx, n);
      if (k < 0) {
        ELR_PUSH(P, P->ctx, P->nctx, P->capctx, elr__named);
        P->cs_xf = (elr_xform *)realloc(P->cs_xf, sizeof(elr_xform) * (size_t)P->capctx);
        if (!P->cs_xf) elr__failf(P, P->dir_file, t.line, "out of memory");
        k = P->nctx - 1;
        P->ctx[k].name = elr__strdup(P, n, strlen(n));
        elr__name_add(P, &P->hctx, P->ctx, k);
      }
      P->cs_xf[k] = P->ctm;
    } else if (!strcmp(nm, "CoordSysTransform")) {
      const char *n = elr__str(P, nm);
      int k = elr__name_find(&P->hctx, P->ctx, P->nctx, n);
      if (k < 0) elr_warn(P->s, P->dir_file, t.line, "CoordSysTransform: coordinate system \"%s\" unknown; ignored", n);
      else P->ctm = P->cs_xf[k];
    } else if (!strcmp(nm, "AttributeBegin") || !strcmp(nm, "TransformBegin")) {
      if (P->depth >= ELR_MAX_STACK) elr__failf(P, P->dir_file, t.line, "%s nested more than %d deep", nm, ELR_MAX_STACK);
      P->xstack[P->depth] = P->ctm;
      P->gstack[P->depth] = P->gs;
      P->stack_kind[P->depth] = nm[0] == 'A' ? 'a' : 't';
      P->depth++;
    } else if (!strcmp(nm, "AttributeEnd") || !strcmp(nm, "TransformEnd")) {
      char want = nm[0] == 'A' ? 'a' : 't';
      if (P->depth == 0) { elr_warn(P->s, P->dir_file, t.line, "unmatched %s ignored", nm); continue; }
      if (P->stack_kind[P->depth - 1] != want)
        elr_warn(P->s, P->dir_file, t.line, "%s closes a%s block", nm,
                 P->stack_kind[P->depth - 1] == 'o' ? "n ObjectBegin" : (want == 'a' ? " TransformBegin" : "n AttributeBegin"));
      P->depth--;
      P->ctm = P->xstack[P->depth];
      if (want == 'a') P->gs = P->gstack[P->depth];
      else P->gs.end_only = P->gstack[P->depth].end_only; /* pbrt-v3 pushes the active transform bits with both */
    } else if (!strcmp(nm, "WorldBegin")) {
      if (P->in_world) elr__failf(P, P->dir_file, t.line, "WorldBegin inside the world block");
      P->in_world = 1;
      elr_xform_identity(&P->ctm);
      {
        int k = elr__name_find(&P->hctx, P->ctx, P->nctx, "world");
        if (k < 0) {
          ELR_PUSH(P, P->ctx, P->nctx, P->capctx, elr__named);
          P->cs_xf = (elr_xform *)realloc(P->cs_xf, sizeof(elr_xform) * (size_t)P->capctx);
          if (!P->cs_xf) elr__failf(P, P->dir_file, t.line, "out of memory");
          k = P->nctx - 1; P->ctx[k].name = elr__strdup(P, "world", 5);
          elr__name_add(P, &P->hctx, P->ctx, k);
        }
        P->cs_xf[k] = P->ctm;
      }
    } else if (!strcmp(nm, "WorldEnd")) {
      if (!P->in_world) elr__failf(P, P->dir_file, t.line, "WorldEnd without WorldBegin");
      if (P->depth != 0) elr_warn(P->s, P->dir_file, t.line, "%d unclosed AttributeBegin/TransformBegin at WorldEnd", P->depth);
      P->world_ended = 1;
      {
        int i, nemit = 0;
        for (i = 0; i < P->s->nlight; i++) nemit += elr_light_emits(&P->s->light[i]);
        if (nemit == 0) /* elr_render then traces nothing */
          elr_warn(P->s, P->dir_file, t.line, "nothing in the scene emits light (no light source or area light with L > 0): the image is black");
        if (nemit > 1 && P->s->d.integrator_path && P->s->d.light_strategy == ELR_LSTRAT_SPATIAL)
          elr_warn(P->s, P->integ_file ? P->integ_file : P->dir_file, P->integ_file ? P->integ_line : t.line,
                   "Integrator \"path\": lightsamplestrategy \"spatial\" (pbrt-v3's default) is not implemented; the %d lights are chosen by "
                   "\"power\"", nemit);
      }
    } else if (!strcmp(nm, "Include") || !strcmp(nm, "Import")) {
      const char *fn = elr__str(P, nm);
      char *path = elr__resolve(P, fn);
      size_t len;
      char *txt = elr__read_file(P, path, &len, t.line);
      elr__parse_file(P, txt, len, path);
    } else if (!strcmp(nm, "Camera") || !strcmp(nm, "Film") || !strcmp(nm, "PixelFilter") ||
               !strcmp(nm, "Sampler") || !strcmp(nm, "Integrator")) {
      const char *type = elr__str(P, nm);
      elr__read_params(P);
      if (P->in_world) { elr__directive_block(P, 0, nm); continue; }
      if (nm[0] == 'C') elr__camera(P, type);
      else if (nm[0] == 'F') elr__film(P, type);
      else if (nm[0] == 'P') elr__filter(P, type);
      else if (nm[0] == 'S') elr__sampler(P, type);
      else elr__integrator(P, type);
      elr__report_unused(P);
    } else if (!strcmp(nm, "LightSource") || !strcmp(nm, "Shape") || !strcmp(nm, "Material") ||
               !strcmp(nm, "NamedMaterial") || !strcmp(nm, "AreaLightSource")) {
      const char *type = elr__str(P, nm);
      elr__read_params(P);
      if (!P->in_world) { elr__directive_block(P, 1, nm); continue; }
      if (nm[0] == 'A') elr__area_light_source(P, type);
      else if (nm[0] == 'L') elr__light(P, type);
      else if (nm[0] == 'S') elr__shape(P, type);
      else if (nm[0] == 'M') P->gs.material = elr__make_material(P, type);
      else {
        int k = elr__name_find(&P->hmat, P->matnames, P->gs.nnamed_mat, type);
        if (k < 0) elr_warn(P->s, P->dir_file, t.line, "NamedMaterial \"%s\" is not defined; ignored", type);
        else P->gs.material = P->matnames[k].index;
      }
      elr__report_unused(P);
    } else if (!strcmp(nm, "MakeNamedMaterial")) {
      const char *name = elr__str(P, nm);
      const char *type;
      int idx;
      elr__read_params(P);
      if (!P->in_world) { elr__directive_block(P, 1, nm); continue; }
      type = elr__pstring(P, "type", "");
      if (!type[0]) elr__failf(P, P->dir_file, t.line, "MakeNamedMaterial \"%s\": \"string type\" is required", name);
      idx = elr__make_material(P, type);
      /* pbrt-v3 keeps named materials in the graphics state: a name made inside AttributeBegin/End is
       * forgotten at its AttributeEnd, as named textures are */
      if (P->gs.nnamed_mat < P->nmatn) {
        elr__name_drop(&P->hmat, P->matnames, P->nmatn, P->gs.nnamed_mat);
        P->nmatn = P->gs.nnamed_mat;
      }
      if (elr__name_find(&P->hmat, P->matnames, P->nmatn, name) >= 0)
        elr_warn(P->s, P->dir_file, t.line, "MakeNamedMaterial: named material \"%s\" redefined", name);
      ELR_PUSH(P, P->matnames, P->nmatn, P->capmatn, elr__named);
      P->matnames[P->nmatn - 1].name = elr__strdup(P, name, strlen(name));
      elr__name_add(P, &P->hmat, P->matnames, P->nmatn - 1);
      P->matnames[P->nmatn - 1].index = idx;
      P->gs.nnamed_mat = P->nmatn;
      elr__report_unused(P);
    } else if (!strcmp(nm, "ObjectBegin")) {
      /* pbrt-v3's pbrtObjectBegin: an AttributeBegin, then the shapes that follow make the prototype */
      const char *name = elr__str(P, nm);
      elr_object *o;
      if (!P->in_world) { elr__directive_block(P, 1, nm); continue; }
      if (P->cur_object >= 0) elr__failf(P, P->dir_file, t.line, "ObjectBegin \"%s\" inside the definition of another object", name);
      if (P->depth >= ELR_MAX_STACK) elr__failf(P, P->dir_file, t.line, "%s nested more than %d deep", nm, ELR_MAX_STACK);
      P->xstack[P->depth] = P->ctm; P->gstack[P->depth] = P->gs; P->stack_kind[P->depth] = 'o'; P->depth++;
      ELR_PUSH(P, P->s->obj, P->s->nobj, P->s->capobj, elr_object);
      o = &P->s->obj[P->s->nobj - 1];
      o->lo[0] = o->lo[1] = o->lo[2] = INFINITY; o->hi[0] = o->hi[1] = o->hi[2] = -INFINITY;
      P->cur_object = P->s->nobj - 1;
      ELR_PUSH(P, P->objnames, P->nobjn, P->capobjn, elr__named); /* a later ObjectBegin of the name replaces it */
      P->objnames[P->nobjn - 1].name = elr__strdup(P, name, strlen(name));
      elr__name_add(P, &P->hobj, P->objnames, P->nobjn - 1);
      P->objnames[P->nobjn - 1].index = P->cur_object;
    } else if (!strcmp(nm, "ObjectEnd")) {
      if (!P->in_world) { elr__directive_block(P, 1, nm); continue; }
      if (P->cur_object < 0) elr__failf(P, P->dir_file, t.line, "ObjectEnd without ObjectBegin");
      P->cur_object = -1;
      /* pbrt-v3's pbrtObjectEnd ends with an AttributeEnd */
      if (P->depth == 0) { elr_warn(P->s, P->dir_file, t.line, "unmatched ObjectEnd ignored"); continue; }
      if (P->stack_kind[P->depth - 1] != 'o') elr_warn(P->s, P->dir_file, t.line, "ObjectEnd closes a %s block",
                                                       P->stack_kind[P->depth - 1] == 'a' ? "AttributeBegin" : "TransformBegin");
      P->depth--;
      P->ctm = P->xstack[P->depth];
      P->gs = P->gstack[P->depth];
    } else if (!strcmp(nm, "ObjectInstance")) {
      /* pbrt-v3's pbrtObjectInstance: the prototype placed by the CTM (instance to world); its shapes'
       * own transformations come first */
      const char *name = elr__str(P, nm);
      int k;
      if (!P->in_world) { elr__directive_block(P, 1, nm); continue; }
      if (P->cur_object >= 0) elr__failf(P, P->dir_file, t.line, "ObjectInstance \"%s\" inside an object definition", name);
      k = elr__name_find(&P->hobj, P->objnames, P->nobjn, name);
      if (k < 0) { elr_warn(P->s, P->dir_file, t.line, "ObjectInstance: object \"%s\" is not defined; ignored", name); continue; }
      k = P->objnames[k].index;
      if (P->s->obj[k].nmesh + P->s->obj[k].nsph == 0) continue; /* pbrt-v3: an empty object adds nothing */
      {
        const elr_object *o = &P->s->obj[k];
        int c;
        for (c = 0; c < 8; c++) /* the instance's world bounds must be traceable */
          elr__check_point(P, t.line, elr_xpoint(&P->ctm, elr_v((float)(c & 1 ? o->hi[0] : o->lo[0]), (float)(c & 2 ? o->hi[1] : o->lo[1]),
                                                              (float)(c & 4 ? o->hi[2] : o->lo[2]))),
                           "a corner of the instance's bounds");
      }
      ELR_PUSH(P, P->s->inst, P->s->ninst, P->s->capinst, elr_instance);
      P->s->inst[P->s->ninst - 1].object = k;
      P->s->inst[P->s->ninst - 1].xf = P->ctm;
      P->s->obj[k].ninstances++;
    } else if (!strcmp(nm, "ReverseOrientation")) {
      /* pbrt-v3's graphicsState.reverseOrientation: it flips the normals of the shapes that follow (only
       * transmissive materials see the difference: every other material here is two-sided) */
      P->gs.reverse = !P->gs.reverse;
    } else if (!strcmp(nm, "Accelerator")) {
      elr__str(P, nm); /* pbrt-v3's bvh or kdtree: Embree builds ours, so the line is accepted and ignored */
      elr__read_params(P);
      if (P->in_world) elr__directive_block(P, 0, nm);
    } else if (!strcmp(nm, "ActiveTransform")) {
      /* pbrt-v3's animated transformations (motion blur): the render is of the start time, so
       * transformations made while only EndTime is active are dropped */
      elr__tok w = elr__next(P);
      if (elr__wordis(&w, "StartTime") || elr__wordis(&w, "All")) P->gs.end_only = 0;
      else if (elr__wordis(&w, "EndTime")) P->gs.end_only = 1;
      else elr__failf(P, P->dir_file, t.line, "ActiveTransform: expected StartTime, EndTime or All");
      elr__warn_once(P, P->dir_file, t.line, "animated transforms", "animated transformations (ActiveTransform, TransformTimes) are not supported: "
                     "the scene is rendered at its start time");
    } else if (!strcmp(nm, "TransformTimes")) {
      elr__num(P, nm); elr__num(P, nm);
      elr__warn_once(P, P->dir_file, t.line, "animated transforms", "animated transformations (ActiveTransform, TransformTimes) are not supported: "
                     "the scene is rendered at its start time");
    } else if (!strcmp(nm, "MakeNamedMedium") || !strcmp(nm, "MediumInterface")) {
      /* participating media: not simulated; surfaces render as if every medium were vacuum */
      elr__str(P, nm);
      if (nm[0] == 'M' && nm[1] == 'a') elr__read_params(P);
      else if (elr__peek(P).kind == T_STRING) elr__str(P, nm); /* MediumInterface "inside" "outside" (or one name) */
      elr__warn_once(P, P->dir_file, t.line, "media", "participating media (%s) are not supported: surfaces render as in vacuum", nm);
    } else if (!strcmp(nm, "Texture")) {
      const char *name = elr__str(P, nm);
      const char *vtype = elr__str(P, nm);
      const char *cls = elr__str(P, nm);
      elr__read_params(P);
      if (!P->in_world) { elr__directive_block(P, 1, nm); continue; }
      elr__texture(P, name, vtype, cls);
      elr__report_unused(P);
    } else {
      int i, known = 0;
      for (i = 0; i < (int)(sizeof unsupported / sizeof unsupported[0]); i++) if (!strcmp(nm, unsupported[i])) known = 1;
      if (!known) elr__failf(P, P->dir_file, t.line, "unknown directive \"%s\"", nm);
      {
        char key[80];
        snprintf(key, sizeof key, "directive %s", nm);
        elr__warn_once(P, P->dir_file, t.line, key, "directive \"%s\" is not supported and is ignored", nm);
      }
      elr__skip_args(P);
    }
    /* a transformation while ActiveTransform EndTime holds moves the end time only: the render is of the start time */
    if (is_xform && P->gs.end_only) P->ctm = saved_ctm;
  }
  if (!P->in_world) elr__fail(P, P->lex[0].line, "the file ends before WorldBegin (truncated?)");
  if (!P->world_ended) elr__fail(P, P->lex[0].line, "the file ends before WorldEnd (truncated?)");
}

int elr_parse(elr_scene *s, const char *text, size_t len, const char *name, const char *base_dir, char *err,
              size_t errlen) {
  elr__parser *P = (elr__parser *)calloc(1, sizeof(elr__parser));
  int rc = 0;
  char dummy[8];
  if (!P) { snprintf(err, errlen, "out of memory"); return -1; }
  if (!err || errlen == 0) { err = dummy; errlen = sizeof dummy; }
  P->s = s; P->err = err; P->errlen = errlen; P->base_dir = base_dir;
  P->cur_object = -1;
  elr_xform_identity(&P->ctm);
  /* pbrt-v3's defaults */
  elr_xform_identity(&s->d.cam2world);
  s->d.fov = 90.f; s->d.xres = 1280; s->d.yres = 720;
  s->d.crop[0] = 0; s->d.crop[1] = 1; s->d.crop[2] = 0; s->d.crop[3] = 1;
  snprintf(s->d.filename, sizeof s->d.filename, "pbrt.exr");
  s->d.filter.type = ELR_PF_BOX; s->d.filter.xw = s->d.filter.yw = 0.5f;
  /* the sampler of a scene without a Sampler directive (el_render.h; pbrt-v3's is halton, 16 spp) */
  /* a scene without a Sampler: 02sequence with 16 dimensions (pbrt-v3's 4 cover the camera and one light
   * and BSDF pair; past them its draws are random: 16 gave directlighting with 2 pairs 1.3x and path 1.09x
   * less variance at 16 spp on bench_city) */
  s->d.sampler = ELR_DEFAULT_SAMPLER; s->d.spp = ELR_DEFAULT_SPP; s->d.dims = ELR_DEFAULT_SAMPLER == ELR_SAMPLER_ZEROTWO ? 16 : 4; s->d.jitter = 1;
  s->d.randomize = ELR_DEFAULT_SAMPLER == ELR_SAMPLER_ZSOBOL || ELR_DEFAULT_SAMPLER == ELR_SAMPLER_PADDEDSOBOL ? ELR_RANDOMIZE_FAST_OWEN : ELR_RANDOMIZE_NONE;
  s->d.integrator_path = 1; s->d.maxdepth = 5; s->d.rrthreshold = 1.f;
  s->d.light_sampling = ELR_LS_MIS;
  s->d.light_strategy = ELR_LSTRAT_SPATIAL; /* pbrt-v3's default lightsamplestrategy */
  if (setjmp(P->jb) == 0) {
    /* the default material: matte, Kd 0.5 */
    ELR_PUSH(P, s->mat, s->nmat, s->capmat, elr_material);
    s->mat[0].kind = ELR_MAT_MATTE;
    s->mat[0].kd = elr__const_tex(P, elr_v(.5f, .5f, .5f));
    s->mat[0].ks = s->mat[0].kr = s->mat[0].rough = -1;
    s->mat[0].kt = s->mat[0].urough = s->mat[0].vrough = s->mat[0].index = s->mat[0].eta = s->mat[0].k = s->mat[0].opacity = -1;
    P->gs.material = 0;
    elr__parse_file(P, text, len, name);
    elr__run(P);
  } else {
    rc = -1;
  }
  while (P->arena) { elr__block *b = P->arena; P->arena = b->next; free(b); }
  free(P->growing[0]); free(P->growing[1]); /* a parse stopped while a value list grew */
  free(P->ctx); free(P->cs_xf); free(P->texnames); free(P->matnames); free(P->warned); free(P->areas);
  free(P->hctx.s); free(P->htex.s); free(P->hmat.s); free(P->hobj.s); free(P->objnames);
  free(P);
  return rc;
}
