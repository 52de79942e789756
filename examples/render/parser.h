/* parser.h: what the parser's files share (parser.c, paramset.c, api.c, api_options.c, api_lights.c,
 * api_shapes.c, api_materials.c; parser.c's opening comment says which holds what): the parser's state
 * (pbrt-v3's graphics state, render options and named tables in one struct), its tokens and parameter
 * lists, and their functions. Only those files include it. The elr__ names are the parser's own: they
 * are not static only because its files call each other. */
#ifndef ELR_PARSER_H
#define ELR_PARSER_H
#include "elr_internal.h"
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

/* World-space coordinates the renderer can trace: Embree refuses (asserts on) a ray whose origin has a
 * component beyond 1.8e18, and squared distances in float overflow near 1e19. Camera positions, light
 * positions and geometry must stay within |x| <= ELR_MAX_COORD; a transformation whose matrix or inverse
 * is not finite (Scale 1e-200 twice, Translate 1e300) is refused at the directive that made it. */
#define ELR_MAX_COORD 1e15

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

/* parser.c: the arena, errors and warnings, the tokenizer, files, named tables */
void *elr__alloc(elr__parser *P, size_t n);
void *elr__grow(elr__parser *P, int slot, size_t n);
void elr__grow_keep(elr__parser *P, int slot);
char *elr__strdup(elr__parser *P, const char *s, size_t n);
char *elr__heap_strdup(elr__parser *P, const char *str);
#if defined(__GNUC__) || defined(__clang__)
void elr__failf(elr__parser *P, const char *file, int line, const char *fmt, ...) __attribute__((noreturn));
#else
void elr__failf(elr__parser *P, const char *file, int line, const char *fmt, ...);
#endif
void elr__fail(elr__parser *P, int line, const char *fmt, ...);
void elr__warn_once(elr__parser *P, const char *file, int line, const char *key, const char *fmt, ...);
elr__tok elr__next(elr__parser *P);
elr__tok elr__peek(elr__parser *P);
int elr__wordis(const elr__tok *t, const char *w);
const char *elr__curfile(elr__parser *P);
double elr__num(elr__parser *P, const char *what);
const char *elr__str(elr__parser *P, const char *what);
void elr__nums16(elr__parser *P, double *m, const char *what);
int elr__name_find(const elr__hmap *h, const elr__named *arr, int n, const char *name);
void elr__name_add(elr__parser *P, elr__hmap *h, elr__named *arr, int k);
void elr__name_drop(elr__hmap *h, elr__named *arr, int from, int to);
char *elr__resolve(elr__parser *P, const char *name);
void elr__parse_file(elr__parser *P, const char *text, size_t len, const char *name);
char *elr__read_file(elr__parser *P, const char *path, size_t *len, int line);
void elr__skip_args(elr__parser *P);
void elr__directive_block(elr__parser *P, int need_world, const char *what);

/* paramset.c: parameter lists */
void elr__read_params(elr__parser *P);
elr__param *elr__find(elr__parser *P, const char *name);
elr__param *elr__findt(elr__parser *P, const char *name, const char *type, int count);
double elr__pfloat(elr__parser *P, const char *name, double def);
int elr__pint(elr__parser *P, const char *name, int def);
int elr__pbool(elr__parser *P, const char *name, int def);
const char *elr__pstring(elr__parser *P, const char *name, const char *def);
elr_v3 elr__prgb(elr__parser *P, const char *name, elr_v3 def);
elr_v3 elr__ppoint(elr__parser *P, const char *name, const char *type, elr_v3 def);
void elr__report_unused(elr__parser *P);
void elr__check_range(elr__parser *P, const char *name, double v, double lo, double hi);
int elr__coord_ok(elr_v3 p);
void elr__check_point(elr__parser *P, int line, elr_v3 p, const char *what);
int elr__const_tex(elr__parser *P, elr_v3 v);
int elr__ptex(elr__parser *P, const char *name, elr_v3 def, int is_float);

/* api_options.c: camera, film, filter, sampler, integrator */
void elr__camera(elr__parser *P, const char *type);
void elr__film(elr__parser *P, const char *type);
void elr__filter(elr__parser *P, const char *type);
void elr__sampler(elr__parser *P, const char *type);
void elr__integrator(elr__parser *P, const char *type);

/* api_lights.c: lights */
void elr__light(elr__parser *P, const char *type);
void elr__area_light_source(elr__parser *P, const char *type);
void elr__attach_area(elr__parser *P, int kind, int index);

/* api_shapes.c: shapes */
void elr__shape(elr__parser *P, const char *type);

/* api_materials.c: materials and textures */
int elr__make_material(elr__parser *P, const char *type);
void elr__texture(elr__parser *P, const char *name, const char *vtype, const char *cls);

#endif
