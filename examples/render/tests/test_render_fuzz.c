/* test_render_fuzz: a small deterministic mutation fuzzer for the renderer's inputs: pbrt-v3 scene
 * text (parser.c and the api*.c files, Include, PLY meshes) and the image files image_io.c reads (HDR, EXR, PFM, PNG).
 *
 * Every case starts from a valid input (the scenes in scenes/, a scene built here that uses every
 * directive, small images, PLY and .spd spectrum files written here) and applies a few seeded mutations: byte flips,
 * token deletion and duplication, numbers replaced by extremes (1e38, -1, 0, nan, 4294967296...),
 * truncation, bracket removal, strings and numbers swapped, directives and parameter names spliced in.
 * The project rule for bad input is checked on each: the loader returns an error with a non-empty
 * message naming the file (scene errors name file:line), or a valid result; never a crash, a hang or
 * undefined behaviour (the sanitizer build runs this too), and a rendered image (8 x 8 or smaller at 1
 * spp, 1 thread) has only finite pixels.
 *
 *   test_render_fuzz                       the ctest run: fixed seed and case counts
 *   test_render_fuzz --seed S --scenes N --images M [--dump DIR] [--only K] [--alarm] [--render-all] [--verbose]
 *
 * A longer campaign runs with other seeds; --dump DIR writes each case's input to DIR before it runs
 * (what a crash leaves behind), --only K runs case K alone (every case has its own generator seeded by
 * (seed, K), so a case reproduces on its own). */
#include "render_test_util.h"
#include <signal.h>
#include <sys/wait.h>

/* >> random numbers (splitmix64: each case seeds its own) */
static uint64_t fz_state;
static uint64_t fz_u64(void) {
  uint64_t z = (fz_state += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}
static size_t fz_below(size_t n) { return n ? (size_t)(fz_u64() % n) : 0; }
static void fz_seed(uint64_t seed, uint64_t kase) { fz_state = seed * 0x2545f4914f6cdd1dULL ^ (kase + 1) * 0x9e3779b97f4a7c15ULL; fz_u64(); }

/* >> a growable byte buffer */
typedef struct fz_buf { unsigned char *p; size_t n, cap; } fz_buf;
static void fz_reserve(fz_buf *b, size_t n) {
  if (n + 1 > b->cap) {
    size_t c = b->cap ? b->cap : 256;
    while (c < n + 1) c *= 2;
    b->p = (unsigned char *)realloc(b->p, c);
    if (!b->p) { printf("out of memory\n"); exit(1); }
    b->cap = c;
  }
}
static void fz_set(fz_buf *b, const void *data, size_t n) { fz_reserve(b, n); memcpy(b->p, data, n); b->n = n; b->p[n] = 0; }
/* replace [at, at+len) by data[0..n) */
static void fz_splice(fz_buf *b, size_t at, size_t len, const void *data, size_t n) {
  if (at > b->n) at = b->n;
  if (at + len > b->n) len = b->n - at;
  fz_reserve(b, b->n - len + n);
  memmove(b->p + at + n, b->p + at + len, b->n - at - len);
  if (n) memcpy(b->p + at, data, n);
  b->n = b->n - len + n;
  b->p[b->n] = 0;
}
static int fz_read_file(const char *path, fz_buf *b) {
  FILE *f = fopen(path, "rb");
  long n;
  if (!f) return -1;
  fseek(f, 0, SEEK_END); n = ftell(f); fseek(f, 0, SEEK_SET);
  fz_reserve(b, (size_t)n);
  b->n = fread(b->p, 1, (size_t)n, f);
  b->p[b->n] = 0;
  fclose(f);
  return 0;
}
static void fz_write_file(const char *path, const unsigned char *p, size_t n) {
  FILE *f = fopen(path, "wb");
  if (!f) { perror(path); exit(1); }
  if (n) fwrite(p, 1, n, f);
  fclose(f);
}

/* >> what mutations splice in */
static const char *fz_numbers[] = {"1e38", "-1e38", "-1", "0", "nan", "inf", "-inf", "4294967296", "-4294967296",
                                   "2147483647", "2147483648", "-2147483648", "1e-38", "1e-45", "3.4e38", "1e300",
                                   "0.5", "-0", "1099511627776", "65536", "16777217", "100000", "1e9", "1e-300",
                                   "3", "1", "2", "8", "255", "-1e-30", "0x10", "1.", ".5", "1e", "--1", "+"};
static const char *fz_words[] = {
    "WorldBegin", "WorldEnd", "AttributeBegin", "AttributeEnd", "TransformBegin", "TransformEnd", "Translate 1 2 3",
    "Scale 2 2 2", "Scale 1e38 1e38 1e38", "Scale 1e-38 1e-38 1e-38", "Rotate 90 0 0 1", "Rotate 1e38 1 1 1",
    "LookAt 0 0 0 0 0 1 0 1 0", "Transform [ 1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1 ]", "ConcatTransform [ 2 0 0 0 0 2 0 0 0 0 2 0 1 1 1 1 ]",
    "Transform [ 1e38 0 0 0 0 1e38 0 0 0 0 1e38 0 0 0 0 1 ]", "Transform [ 1e-30 0 0 0 0 1e-30 0 0 0 0 1e-30 0 0 0 0 1 ]",
    "ConcatTransform [ 1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 0 ]", "Identity", "CoordinateSystem \"c\"",
    "CoordSysTransform \"c\"", "CoordSysTransform \"camera\"", "ReverseOrientation", "Include \"inc.pbrt\"",
    "Include \"missing.pbrt\"", "Include \"\"", "Include \".\"", "Include \"tiny.hdr\"", "Import \"inc.pbrt\"",
    "Shape \"sphere\"", "Shape \"sphere\" \"float radius\" -1", "Shape \"sphere\" \"float radius\" 1e38",
    "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 ] \"point P\" [ 0 0 0 1 0 0 0 1 0 ]",
    "Shape \"trianglemesh\" \"integer indices\" [ 0 1 4294967295 ] \"point P\" [ 0 0 0 1 0 0 0 1 0 ]",
    "Shape \"trianglemesh\" \"point P\" [ 0 0 0 1 0 0 0 1 0 ] \"float uv\" [ 0 0 1 0 ]",
    "Shape \"plymesh\" \"string filename\" \"a.ply\"", "Shape \"plymesh\" \"string filename\" \"b.ply\"",
    "Shape \"plymesh\" \"string filename\" \"tiny.png\"", "Shape \"disk\"",
    "LightSource \"infinite\" \"string mapname\" \"tiny.hdr\"", "LightSource \"infinite\" \"string mapname\" \"tiny.exr\"",
    "LightSource \"infinite\" \"string mapname\" \"tiny.pfm\"", "LightSource \"infinite\" \"string mapname\" \"tiny.png\"",
    "LightSource \"infinite\" \"rgb L\" [ 1e38 1e38 1e38 ]", "LightSource \"infinite\" \"rgb L\" [ -1 -1 -1 ]",
    "LightSource \"point\" \"point from\" [ 0 1 0 ] \"rgb I\" [ 1e38 1 1 ]", "LightSource \"distant\" \"point from\" [ 0 0 0 ] \"point to\" [ 0 0 0 ]",
    "LightSource \"spot\"", "AreaLightSource \"diffuse\"", "AreaLightSource \"area\" \"rgb L\" [ 4 4 4 ] \"bool twosided\" \"true\"",
    "AreaLightSource \"diffuse\" \"blackbody L\" [ 6500 2 ] \"integer nsamples\" 3", "AreaLightSource \"diffuse\" \"rgb L\" [ -1 1 1 ]",
    "AreaLightSource \"diffuse\" \"spectrum L\" \"s.spd\"", "AreaLightSource \"diffuse\" \"spectrum L\" [ 400 1 700 1e38 ]",
    "AreaLightSource \"diffuse\" \"xyz L\" [ 1 1 1 ] \"integer samples\" 0", "AreaLightSource \"goniometric\"",
    "Shape \"disk\" \"float radius\" 0.5 \"float innerradius\" 0.2 \"float phimax\" 90 \"float height\" 1",
    "Shape \"disk\" \"float innerradius\" 2", "Shape \"disk\" \"float phimax\" 0", "Shape \"disk\" \"float radius\" 1e38",
    "LightSource \"point\" \"blackbody I\" [ 0 1 ]", "LightSource \"point\" \"blackbody I\" [ 1e-30 1 ]",
    "Integrator \"directlighting\" \"string strategy\" \"one\"", "Integrator \"path\" \"string lightsamplestrategy\" \"uniform\"",
    "Integrator \"path\" \"string lightsamplestrategy\" \"power\"", "Integrator \"path\" \"string lightsamplestrategy\" \"spatial\"",
    "Material \"matte\" \"spectrum Kd\" \"s.spd\"", "Material \"matte\" \"spectrum Kd\" [ 500 0.5 400 0.5 ]",
    "Material \"matte\" \"xyz Kd\" [ 0.2 0.3 0.4 ]", "Material \"matte\" \"blackbody Kd\" [ 3000 0.5 ]", "Material \"matte\"",
    "Material \"mirror\"",
    "Material \"plastic\" \"float roughness\" 0", "Material \"plastic\" \"float roughness\" -1e38 \"bool remaproughness\" \"false\"",
    "Material \"glass\"", "Material \"\"", "MakeNamedMaterial \"m\" \"string type\" \"plastic\"", "NamedMaterial \"m\"",
    "Texture \"t\" \"spectrum\" \"imagemap\" \"string filename\" \"tiny.png\"",
    "Texture \"t\" \"float\" \"imagemap\" \"string filename\" \"tiny.pfm\" \"string wrap\" \"black\"",
    "Texture \"t\" \"spectrum\" \"imagemap\" \"string filename\" \"tiny.exr\" \"float maxanisotropy\" 1e6",
    "Texture \"t\" \"spectrum\" \"checkerboard\" \"float uscale\" 1e38", "Texture \"t\" \"spectrum\" \"checkerboard\" \"texture tex1\" \"t\"",
    "Material \"matte\" \"texture Kd\" \"t\"", "Camera \"perspective\" \"float fov\" 179", "Camera \"orthographic\"",
    "Film \"image\" \"integer xresolution\" 1 \"integer yresolution\" 1", "Film \"image\" \"float cropwindow\" [ 0.5 0.5 0 1 ]",
    "PixelFilter \"gaussian\" \"float alpha\" 1e38", "PixelFilter \"sinc\" \"float tau\" 0", "PixelFilter \"mitchell\" \"float B\" nan",
    "PixelFilter \"gaussian\" \"float alpha\" -1e38", "PixelFilter \"triangle\" \"float xwidth\" 1e-3",
    "Sampler \"stratified\" \"integer xsamples\" 4096 \"integer ysamples\" 4096", "Sampler \"random\" \"integer pixelsamples\" 1",
    "Sampler \"halton\" \"integer pixelsamples\" 16777216", "Sampler \"sobol\"",
    "Sampler \"zsobol\" \"string randomization\" \"owen\"", "Sampler \"02sequence\" \"integer dimensions\" 0",
    "Sampler \"paddedsobol\" \"integer pixelsamples\" 3 \"integer seed\" -7", "Sampler \"sobol\" \"string randomization\" \"x\"",
    "Sampler \"lowdiscrepancy\" \"integer pixelsamples\" 16777215", "Sampler \"pmj02bn\"",
    "Integrator \"path\" \"integer maxdepth\" 100000", "Integrator \"directlighting\" \"integer maxdepth\" 100000",
    "Integrator \"path\" \"float rrthreshold\" -1e38", "Integrator \"path\" \"float rrthreshold\" 1e38", "Integrator \"bdpt\"",
    "ObjectBegin \"o\"", "ObjectEnd", "ObjectInstance \"o\"", "ObjectInstance \"obj\"", "ObjectBegin \"obj\"",
    "Option \"bool x\" \"true\"", "Attribute \"shape\" \"float radius\" 2",
    "Shape \"loopsubdiv\" \"integer levels\" 2 \"integer indices\" [ 0 2 1 0 1 3 0 3 2 1 2 3 ] \"point P\" [ 1 1 1 -1 -1 1 -1 1 -1 1 -1 -1 ]",
    "Shape \"loopsubdiv\" \"integer levels\" 12 \"integer indices\" [ 0 1 2 0 2 3 ] \"point P\" [ 0 0 0 1 0 0 1 1 0 0 1 0 ]",
    "Shape \"loopsubdiv\" \"integer indices\" [ 0 1 2 0 1 2 ] \"point P\" [ 0 0 0 1 0 0 0 1 0 ]",
    "Shape \"loopsubdiv\" \"integer indices\" [ 0 1 2 1 0 3 0 1 3 ] \"point P\" [ 0 0 0 1 0 0 0 1 0 0 0 1 ]",
    "Material \"glass\" \"float index\" 1e-30", "Material \"glass\" \"float uroughness\" 0.3 \"float vroughness\" 0", "Material \"metal\" \"rgb eta\" [ 0 0 0 ] \"rgb k\" [ 0 0 0 ]",
    "Material \"metal\" \"float roughness\" -1e38", "Material \"uber\" \"rgb opacity\" [ 0.5 -1 2 ]", "Material \"uber\" \"rgb Kt\" [ 1 1 1 ] \"float index\" 1",
    "Material \"substrate\" \"float uroughness\" 0 \"bool remaproughness\" \"false\"", "MakeNamedMaterial \"g\" \"string type\" \"glass\"", "NamedMaterial \"g\"",
    "Texture \"s\" \"spectrum\" \"scale\" \"texture tex1\" \"t\" \"texture tex2\" \"s\"", "Texture \"x\" \"float\" \"mix\" \"texture amount\" \"x\"",
    "Texture \"t\" \"spectrum\" \"mix\" \"texture tex1\" \"t\" \"texture tex2\" \"t\" \"texture amount\" \"t\"",
    "Accelerator \"bvh\"", "Integrator \"mlt\" \"integer maxdepth\" 3", "Integrator \"sppm\"", "ActiveTransform EndTime", "ActiveTransform Foo",
    "MediumInterface \"a\" \"b\"", "Shape \"curve\"", "Shape \"cylinder\"",
    "MakeNamedMedium \"m\" \"string type\" \"homogeneous\"", "MediumInterface \"\" \"m\"", "ActiveTransform All", "TransformTimes 0 1",
    "Foo", "[", "]", "\"", "#", "\"float", "1", "-", "\\",
    /* PLY header lines (the ASCII PLY seed goes through this mutator too) */
    "property list uchar float x", "property list uint uint vertex_indices", "property list float int vertex_indices",
    "element vertex 4294967296", "element face -1", "element face 1000000", "format binary_big_endian 1.0",
    "property double nx", "property uchar u", "end_header", "element normal 2", "comment end_header"};
static const char *fz_strings[] = {"\"float radius\"", "\"integer indices\"", "\"point P\"", "\"point3 P\"", "\"normal N\"",
                                   "\"float uv\"", "\"point2 uv\"", "\"float st\"", "\"rgb Kd\"", "\"spectrum Kd\"",
                                   "\"blackbody L\"", "\"texture Kd\"", "\"string filename\"", "\"string mapname\"",
                                   "\"spectrum L\"", "\"xyz Kd\"", "\"blackbody I\"", "\"bool twosided\"", "\"integer nsamples\"",
                                   "\"float innerradius\"", "\"float phimax\"", "\"float height\"", "\"string strategy\"",
                                   "\"string lightsamplestrategy\"", "\"s.spd\"", "\"one\"", "\"power\"", "\"uniform\"", "\"spatial\"",
                                   "\"diffuse\"", "\"area\"", "\"disk\"",
                                   "\"bool jitter\"", "\"integer pixelsamples\"", "\"integer maxdepth\"", "\"float fov\"",
                                   "\"float screenwindow\"", "\"float cropwindow\"", "\"integer xresolution\"",
                                   "\"float scale\"", "\"rgb scale\"", "\"integer samples\"", "\"string importance\"",
                                   "\"bool compensated\"", "\"float maxanisotropy\"", "\"string wrap\"", "\"string filter\"",
                                   "\"bool gamma\"", "\"integer dimension\"", "\"string aamode\"", "\"float zmin\"",
                                   "\"float halffov\"", "\"float frameaspectratio\"", "\"float lensradius\"", "\"float xwidth\"",
                                   "\"float alpha\"", "\"float tau\"", "\"float B\"", "\"float roughness\"", "\"bool remaproughness\"",
                                   "\"vector3 N\"", "\"point4 P\"", "\"xyz L\"", "\"float\"", "\"\"", "\"unknown name\"",
                                   "\"integer indices indices\"", "\"tiny.hdr\"", "\"tiny.exr\"", "\"tiny.pfm\"", "\"tiny.png\"",
                                   "\"a.ply\"", "\"b.ply\"", "\"inc.pbrt\"", "\"missing.hdr\"", "\"/\"", "\".\"", "\"true\"",
                                   "\"false\"", "\"perspective\"", "\"infinite\"", "\"imagemap\"", "\"checkerboard\"",
                                   "\"stratified\"", "\"halton\"", "\"zsobol\"", "\"02sequence\"", "\"string randomization\"", "\"integer seed\"",
                                   "\"texel\"", "\"cellaverage\"", "\"clamp\"", "\"ewa\"",
                                   "\"t\"", "\"m\"", "\"c\"", "\"world\"", "\"camera\"", "\"a\\\"b\"", "\"\\\\\"",
                                   "\"integer levels\"", "\"float index\"", "\"float eta\"", "\"rgb eta\"", "\"rgb k\"", "\"float uroughness\"",
                                   "\"float vroughness\"", "\"rgb Kt\"", "\"rgb opacity\"", "\"texture tex1\"", "\"texture amount\"", "\"float amount\"",
                                   "\"glass\"", "\"metal\"", "\"uber\"", "\"substrate\"", "\"scale\"", "\"mix\"", "\"loopsubdiv\"", "\"obj\""};

/* >> token positions of a scene text (whitespace-separated; a quoted string is one token) */
typedef struct fz_tok { size_t at, len; } fz_tok;
static int fz_tokens(const fz_buf *b, fz_tok *t, int max) {
  size_t i = 0;
  int n = 0;
  while (i < b->n && n < max) {
    size_t s;
    while (i < b->n && (b->p[i] == ' ' || b->p[i] == '\n' || b->p[i] == '\t' || b->p[i] == '\r')) i++;
    if (i >= b->n) break;
    s = i;
    if (b->p[i] == '"') { i++; while (i < b->n && b->p[i] != '"' && b->p[i] != '\n') i++; if (i < b->n && b->p[i] == '"') i++; }
    else if (b->p[i] == '#') { while (i < b->n && b->p[i] != '\n') i++; }
    else while (i < b->n && b->p[i] != ' ' && b->p[i] != '\n' && b->p[i] != '\t' && b->p[i] != '\r') i++;
    t[n].at = s; t[n].len = i - s; n++;
  }
  return n;
}
static int fz_isnum(const fz_buf *b, const fz_tok *t) {
  unsigned char c = b->p[t->at];
  return (c >= '0' && c <= '9') || c == '-' || c == '+' || c == '.';
}

#define FZ_NSEEDS 8
static fz_buf fz_scene_seed[FZ_NSEEDS];
static int fz_nscene_seeds;
#define FZ_MAXTOK 8192
static fz_tok fz_tok_buf[FZ_MAXTOK];

/* One mutation of a scene text. */
static void fz_mutate_scene(fz_buf *b) {
  int nt = fz_tokens(b, fz_tok_buf, FZ_MAXTOK), k, tries;
  fz_tok *t = fz_tok_buf;
  int op = (int)fz_below(19);
  if (b->n == 0) { const char *w = fz_words[fz_below(sizeof fz_words / sizeof fz_words[0])]; fz_splice(b, 0, 0, w, strlen(w)); return; }
  switch (op) {
  case 0: { /* byte flips */
    int i, n = 1 + (int)fz_below(3);
    for (i = 0; i < n; i++) {
      size_t at = fz_below(b->n);
      unsigned char v = fz_below(4) == 0 ? (unsigned char)fz_below(256) : (unsigned char)(32 + fz_below(95));
      b->p[at] = v;
    }
    break;
  }
  case 1: /* delete a token */
    if (nt) { k = (int)fz_below((size_t)nt); fz_splice(b, t[k].at, t[k].len, "", 0); }
    break;
  case 2: /* duplicate a token */
    if (nt) {
      char tmp[4096];
      k = (int)fz_below((size_t)nt);
      if (t[k].len < sizeof tmp - 1) { memcpy(tmp, b->p + t[k].at, t[k].len); tmp[t[k].len] = ' '; fz_splice(b, t[k].at, 0, tmp, t[k].len + 1); }
    }
    break;
  case 3: case 4: case 14: case 15: /* a number replaced by an extreme */
    for (tries = 0; tries < 20 && nt; tries++) {
      k = (int)fz_below((size_t)nt);
      if (fz_isnum(b, &t[k])) {
        const char *v = fz_numbers[fz_below(sizeof fz_numbers / sizeof fz_numbers[0])];
        fz_splice(b, t[k].at, t[k].len, v, strlen(v));
        break;
      }
    }
    break;
  case 5: /* truncation */
    b->n = fz_below(b->n + 1); b->p[b->n] = 0;
    break;
  case 6: /* remove a bracket */
    for (tries = 0; tries < 20 && nt; tries++) {
      k = (int)fz_below((size_t)nt);
      if (b->p[t[k].at] == '[' || b->p[t[k].at] == ']') { fz_splice(b, t[k].at, 1, "", 0); break; }
    }
    break;
  case 7: /* string <-> number */
    for (tries = 0; tries < 20 && nt; tries++) {
      k = (int)fz_below((size_t)nt);
      if (b->p[t[k].at] == '"') { const char *v = fz_numbers[fz_below(sizeof fz_numbers / sizeof fz_numbers[0])]; fz_splice(b, t[k].at, t[k].len, v, strlen(v)); break; }
      if (fz_isnum(b, &t[k])) { const char *v = fz_strings[fz_below(sizeof fz_strings / sizeof fz_strings[0])]; fz_splice(b, t[k].at, t[k].len, v, strlen(v)); break; }
    }
    break;
  case 8: case 9: { /* a directive spliced in at a token boundary */
    const char *w = fz_words[fz_below(sizeof fz_words / sizeof fz_words[0])];
    size_t at = nt ? t[fz_below((size_t)nt)].at : 0;
    char tmp[512];
    if (op == 8) /* mostly at the start of a line: between directives */
      for (tries = 0; tries < 20 && nt; tries++) {
        at = t[fz_below((size_t)nt)].at;
        if (at == 0 || b->p[at - 1] == '\n') break;
      }
    snprintf(tmp, sizeof tmp, "%s\n", w);
    fz_splice(b, at, 0, tmp, strlen(tmp));
    break;
  }
  case 10: case 11: /* a quoted string replaced (parameter declarations, class names, file names) */
    for (tries = 0; tries < 20 && nt; tries++) {
      k = (int)fz_below((size_t)nt);
      if (b->p[t[k].at] == '"') { const char *v = fz_strings[fz_below(sizeof fz_strings / sizeof fz_strings[0])]; fz_splice(b, t[k].at, t[k].len, v, strlen(v)); break; }
    }
    break;
  case 12: /* a token moved elsewhere */
    if (nt > 1) {
      char tmp[4096];
      int a = (int)fz_below((size_t)nt), c = (int)fz_below((size_t)nt);
      size_t len = t[a].len;
      if (len < sizeof tmp - 1) {
        memcpy(tmp, b->p + t[a].at, len); tmp[len] = ' ';
        if (t[c].at > t[a].at) { fz_splice(b, t[c].at, 0, tmp, len + 1); fz_splice(b, t[a].at, len, "", 0); }
        else { fz_splice(b, t[a].at, len, "", 0); fz_splice(b, t[c].at, 0, tmp, len + 1); }
      }
    }
    break;
  case 16: /* a parameter's type changed ("float radius" -> "integer radius", "rgb Kd" -> "float Kd") */
    for (tries = 0; tries < 20 && nt; tries++) {
      static const char *types[] = {"float", "integer", "rgb", "string", "bool", "texture", "point3", "normal", "point2",
                                    "spectrum", "blackbody", "vector3", "color", "point"};
      size_t sp;
      k = (int)fz_below((size_t)nt);
      if (b->p[t[k].at] != '"' || t[k].len < 4) continue;
      for (sp = 1; sp < t[k].len && b->p[t[k].at + sp] != ' '; sp++) {}
      if (sp >= t[k].len - 1) continue;
      {
        const char *ty = types[fz_below(sizeof types / sizeof types[0])];
        fz_splice(b, t[k].at + 1, sp - 1, ty, strlen(ty));
      }
      break;
    }
    break;
  case 17: /* one value dropped from inside a bracketed list */
    for (tries = 0; tries < 20 && nt > 1; tries++) {
      k = 1 + (int)fz_below((size_t)nt - 1);
      if (b->p[t[k - 1].at] == '[' || fz_isnum(b, &t[k - 1])) {
        if (fz_isnum(b, &t[k]) || b->p[t[k].at] == '"') { fz_splice(b, t[k].at, t[k].len, "", 0); break; }
      }
    }
    break;
  case 18: { /* a line of another seed spliced in at a line start (crossover) */
    const fz_buf *o = &fz_scene_seed[fz_below((size_t)fz_nscene_seeds)];
    size_t a = fz_below(o->n), e2, at = 0;
    while (a > 0 && o->p[a - 1] != '\n') a--;
    e2 = a;
    while (e2 < o->n && o->p[e2] != '\n') e2++;
    if (e2 < o->n) e2++;
    for (tries = 0; tries < 20 && nt; tries++) {
      at = t[fz_below((size_t)nt)].at;
      if (at == 0 || b->p[at - 1] == '\n') break;
    }
    if (e2 > a) {
      unsigned char *tmp = (unsigned char *)malloc(e2 - a + 1);
      memcpy(tmp, o->p + a, e2 - a);
      fz_splice(b, at, 0, tmp, e2 - a);
      free(tmp);
    }
    break;
  }
  default: { /* a number token multiplied into a long list (huge parameter arrays) */
    for (tries = 0; tries < 20 && nt; tries++) {
      k = (int)fz_below((size_t)nt);
      if (fz_isnum(b, &t[k])) {
        char tmp[64];
        size_t reps = 1 + fz_below(300), i;
        fz_buf r; memset(&r, 0, sizeof r);
        snprintf(tmp, sizeof tmp, "%.*s ", (int)(t[k].len < 40 ? t[k].len : 40), (const char *)b->p + t[k].at);
        for (i = 0; i < reps; i++) fz_splice(&r, r.n, 0, tmp, strlen(tmp));
        fz_splice(b, t[k].at, 0, r.p, r.n);
        free(r.p);
        break;
      }
    }
    break;
  }
  }
}

/* One mutation of a binary file (images, PLY). */
static void fz_mutate_bytes(fz_buf *b) {
  int op = (int)fz_below(10);
  if (b->n == 0) { fz_splice(b, 0, 0, "\x76\x2f\x31\x01", 4); return; }
  switch (op) {
  case 0: case 1: { /* random bytes, mostly in the header */
    int i, n = 1 + (int)fz_below(4);
    for (i = 0; i < n; i++) {
      size_t at = fz_below(3) ? fz_below(b->n < 128 ? b->n : 128) : fz_below(b->n);
      b->p[at] = (unsigned char)fz_below(256);
    }
    break;
  }
  case 2: { /* a bit flip */
    size_t at = fz_below(b->n);
    b->p[at] ^= (unsigned char)(1u << fz_below(8));
    break;
  }
  case 3: /* truncation */
    b->n = fz_below(b->n); b->p[b->n] = 0;
    break;
  case 4: { /* 4 bytes set to an extreme (sizes, offsets, float bits) */
    static const unsigned char ext[7][4] = {{0xff, 0xff, 0xff, 0xff}, {0, 0, 0, 0}, {0xff, 0xff, 0xff, 0x7f}, {0, 0, 0, 0x80},
                                            {0, 0, 0xc0, 0x7f}, {0, 0, 0x80, 0x7f}, {1, 0, 0, 0}};
    size_t at = fz_below(3) ? fz_below(b->n < 400 ? b->n : 400) : fz_below(b->n);
    size_t n = b->n - at < 4 ? b->n - at : 4;
    memcpy(b->p + at, ext[fz_below(7)], n);
    break;
  }
  case 5: { /* bytes inserted or deleted */
    size_t at = fz_below(b->n), n = 1 + fz_below(8);
    if (fz_below(2)) fz_splice(b, at, n, "", 0);
    else { unsigned char tmp[8]; size_t i; for (i = 0; i < n; i++) tmp[i] = (unsigned char)fz_below(256); fz_splice(b, at, 0, tmp, n); }
    break;
  }
  case 6: case 7: { /* a decimal number in a text header replaced by an extreme */
    size_t lim = b->n < 200 ? b->n : 200, at = fz_below(lim), e;
    int tries;
    for (tries = 0; tries < 50; tries++, at = fz_below(lim)) {
      if (b->p[at] >= '0' && b->p[at] <= '9') {
        const char *v = fz_numbers[fz_below(sizeof fz_numbers / sizeof fz_numbers[0])];
        while (at > 0 && ((b->p[at - 1] >= '0' && b->p[at - 1] <= '9') || b->p[at - 1] == '.' || b->p[at - 1] == '-')) at--;
        e = at;
        while (e < b->n && ((b->p[e] >= '0' && b->p[e] <= '9') || b->p[e] == '.' || b->p[e] == '-' || b->p[e] == 'e')) e++;
        fz_splice(b, at, e - at, v, strlen(v));
        break;
      }
    }
    break;
  }
  case 8: { /* a 32-bit little-endian field somewhere in the first 400 bytes multiplied */
    size_t at = fz_below(b->n < 400 ? b->n : 400);
    if (at + 4 <= b->n) {
      uint32_t v;
      memcpy(&v, b->p + at, 4);
      v = fz_below(2) ? v * 0x10001u + 1u : v + (uint32_t)fz_below(5) - 2u;
      memcpy(b->p + at, &v, 4);
    }
    break;
  }
  default: { /* a block duplicated */
    size_t at = fz_below(b->n), n = 1 + fz_below(64);
    if (at + n > b->n) n = b->n - at;
    {
      unsigned char *tmp = (unsigned char *)malloc(n + 1);
      memcpy(tmp, b->p + at, n);
      fz_splice(b, at, 0, tmp, n);
      free(tmp);
    }
    break;
  }
  }
}

/* >> the seed inputs */
/* (the code below names tiny.pfm and tiny.exr by position, and the last three by their distance from the end) */
static const char *fz_img_names[] = {"tiny.hdr", "flat.hdr", "tiny.exr", "tiny.pfm", "grey.pfm", "tiny.png", "grey.png", "s.spd",
                                     "a.ply", "b.ply", "inc.pbrt"};
#define FZ_NIMG ((int)(sizeof fz_img_names / sizeof fz_img_names[0]))
static fz_buf fz_img_seed[FZ_NIMG];

static const char *fz_every_directive =
    "# every directive the parser knows\n"
    "LookAt 0 1 -4  0 0.5 0  0 1 0\n"
    "Camera \"perspective\" \"float fov\" [ 45 ] \"float frameaspectratio\" 1 \"float screenwindow\" [ -1 1 -1 1 ]\n"
    "Film \"image\" \"integer xresolution\" [ 8 ] \"integer yresolution\" 8 \"string filename\" \"out.pfm\"\n"
    "  \"float cropwindow\" [ 0 1 0 1 ]\n"
    "PixelFilter \"mitchell\" \"float xwidth\" 2 \"float ywidth\" 2 \"float B\" 0.3 \"float C\" 0.3\n"
    "Sampler \"stratified\" \"integer xsamples\" 1 \"integer ysamples\" 1 \"bool jitter\" \"true\" \"integer dimensions\" 4\n"
    "Integrator \"path\" \"integer maxdepth\" 4 \"float rrthreshold\" 0.5 \"string lightsampling\" \"mis\"\n"
    "WorldBegin\n"
    "AttributeBegin\n  Rotate -90 1 0 0\n"
    "  LightSource \"infinite\" \"string mapname\" \"tiny.hdr\" \"rgb scale\" [ 1 1 1 ] \"integer samples\" 2 \"string importance\" \"texel\"\n"
    "AttributeEnd\n"
    "LightSource \"point\" \"point from\" [ 0 3 0 ] \"rgb I\" [ 2 2 2 ]\n"
    "LightSource \"distant\" \"point from\" [ 0 1 0 ] \"point to\" [ 0 0 0 ] \"rgb L\" [ 0.5 0.5 0.5 ]\n"
    "TransformBegin\n  Translate 0 1 0\n  Scale 1 2 1\n  CoordinateSystem \"a\"\nTransformEnd\n"
    "CoordSysTransform \"a\"\nIdentity\n"
    "Texture \"c\" \"spectrum\" \"checkerboard\" \"rgb tex1\" [ 1 0 0 ] \"rgb tex2\" [ 0 0 1 ] \"float uscale\" 4 \"float vscale\" 4\n"
    "Texture \"img\" \"spectrum\" \"imagemap\" \"string filename\" \"tiny.png\" \"string wrap\" \"clamp\" \"string filter\" \"ewa\"\n"
    "Texture \"f\" \"float\" \"imagemap\" \"string filename\" \"tiny.pfm\" \"float scale\" 0.5\n"
    "Texture \"e\" \"spectrum\" \"imagemap\" \"string filename\" \"tiny.exr\" \"bool trilinear\" \"true\"\n"
    "Texture \"k\" \"float\" \"constant\" \"float value\" 0.2\n"
    "MakeNamedMaterial \"shiny\" \"string type\" \"plastic\" \"texture Kd\" \"img\" \"rgb Ks\" [ 0.3 0.3 0.3 ] \"texture roughness\" \"f\"\n"
    "AttributeBegin\n  Material \"plastic\" \"texture Kd\" \"c\" \"texture roughness\" \"k\" \"bool remaproughness\" \"false\"\n"
    "  Translate -1 0.5 0\n  Shape \"sphere\" \"float radius\" 0.5\nAttributeEnd\n"
    "AttributeBegin\n  NamedMaterial \"shiny\"\n  Translate 1 0.5 0\n  Shape \"sphere\" \"float radius\" 0.4\nAttributeEnd\n"
    "AttributeBegin\n  Material \"mirror\" \"rgb Kr\" [ 0.9 0.9 0.9 ]\n"
    "  ConcatTransform [ 1 0 0 0 0 1 0 0 0 0 1 0 0 0 2 1 ]\n  Shape \"plymesh\" \"string filename\" \"a.ply\"\nAttributeEnd\n"
    "Material \"matte\" \"texture Kd\" \"e\" \"float sigma\" 0\n"
    "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point P\" [ -4 0 -4 4 0 -4 4 0 4 -4 0 4 ]\n"
    "  \"normal N\" [ 0 1 0 0 1 0 0 1 0 0 1 0 ] \"float uv\" [ 0 0 1 0 1 1 0 1 ]\n"
    "Shape \"plymesh\" \"string filename\" \"b.ply\"\n"
    "Include \"inc.pbrt\"\n"
    /* issue 16's format: instances, Loop subdivision, glass, metal, uber, substrate, scale and mix */
    "Texture \"sc\" \"spectrum\" \"scale\" \"texture tex1\" \"c\" \"rgb tex2\" [ 0.5 0.5 0.5 ]\n"
    "Texture \"mx\" \"float\" \"mix\" \"float tex1\" 0.1 \"texture tex2\" \"k\" \"float amount\" 0.3\n"
    "MakeNamedMaterial \"rough\" \"string type\" \"glass\" \"float uroughness\" 0.2 \"texture vroughness\" \"mx\" \"float index\" 1.4\n"
    "ObjectBegin \"obj\"\n  Material \"metal\" \"float roughness\" 0.1\n  Shape \"sphere\" \"float radius\" 0.2\n"
    "  Material \"uber\" \"texture Kd\" \"sc\" \"rgb Kr\" [ 0.2 0.2 0.2 ] \"rgb opacity\" [ 0.7 0.7 0.7 ]\n"
    "  Shape \"loopsubdiv\" \"integer levels\" 1 \"integer indices\" [ 0 2 1 0 1 3 0 3 2 1 2 3 ] \"point P\" [ 0.3 0.3 0.3 -0.3 -0.3 0.3 -0.3 0.3 -0.3 0.3 -0.3 -0.3 ]\n"
    "ObjectEnd\n"
    "AttributeBegin\n  Translate 0 1.5 0\n  ObjectInstance \"obj\"\n  Translate 0.6 0 0\n  Scale -1 1 1\n  ObjectInstance \"obj\"\nAttributeEnd\n"
    "AttributeBegin\n  Material \"glass\" \"float index\" 1.5\n  Translate 0 0.4 -1.5\n  ReverseOrientation\n  Shape \"sphere\" \"float radius\" 0.2\nAttributeEnd\n"
    "AttributeBegin\n  NamedMaterial \"rough\"\n  Material \"substrate\" \"float uroughness\" 0.05\n  Translate -1 0.2 -1.5\n  Shape \"sphere\" \"float radius\" 0.2\nAttributeEnd\n"
    /* area lights on every shape, their orientation, spectral values */
    "AttributeBegin\n  AreaLightSource \"diffuse\" \"blackbody L\" [ 5500 2 ] \"bool twosided\" \"true\" \"integer nsamples\" 2\n"
    "  Translate 0 2 0\n  ReverseOrientation\n"
    "  Shape \"disk\" \"float radius\" 0.3 \"float innerradius\" 0.1 \"float phimax\" 270 \"float height\" 0.1\nAttributeEnd\n"
    "AttributeBegin\n  AreaLightSource \"area\" \"spectrum L\" \"s.spd\" \"rgb scale\" [ 1 1 1 ]\n  Translate 0 2.5 1\n"
    "  Shape \"sphere\" \"float radius\" 0.2\nAttributeEnd\n"
    "AttributeBegin\n  AreaLightSource \"diffuse\" \"xyz L\" [ 0.5 0.5 0.5 ] \"spectrum scale\" [ 400 1 700 2 ]\n"
    "  Material \"matte\" \"spectrum Kd\" [ 400 0.2 550 0.8 700 0.4 ]\n"
    "  Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 ] \"point P\" [ -1 3 0 1 3 0 0 3 1 ]\nAttributeEnd\n"
    "WorldEnd\n";

static void fz_write_le32(FILE *f, uint32_t v) { unsigned char b[4]; b[0] = (unsigned char)v; b[1] = (unsigned char)(v >> 8); b[2] = (unsigned char)(v >> 16); b[3] = (unsigned char)(v >> 24); fwrite(b, 1, 4, f); }
static void fz_write_lef(FILE *f, float x) { uint32_t v; memcpy(&v, &x, 4); fz_write_le32(f, v); }

static void fz_make_seeds(void) {
  float px[8 * 4 * 3];
  unsigned char p8[6 * 5 * 3];
  char e[512];
  int i;
  /* an asymmetric 8 x 4 map (RLE in .hdr: width >= 8), a 4 x 2 one (flat .hdr) */
  for (i = 0; i < 8 * 4 * 3; i++) px[i] = 0.05f + (float)((i * 37) % 11) * 0.3f;
  px[5 * 3] = 40.f; /* a bright texel */
  if (el_image_write_hdr(rt_path("tiny.hdr"), px, 8, 4, 3, e, sizeof e) || el_image_write_hdr(rt_path("flat.hdr"), px, 4, 2, 3, e, sizeof e) ||
      el_image_write_exr(rt_path("tiny.exr"), px, 8, 4, 3, e, sizeof e) || el_image_write_pfm(rt_path("tiny.pfm"), px, 8, 4, 3, e, sizeof e) ||
      el_image_write_pfm(rt_path("grey.pfm"), px, 4, 3, 1, e, sizeof e)) {
    printf("cannot write the seed images: %s\n", e);
    exit(1);
  }
  for (i = 0; i < 6 * 5 * 3; i++) p8[i] = (unsigned char)((i * 53) % 256);
  if (el_image_write_png(rt_path("tiny.png"), p8, 6, 5, 3, e, sizeof e) || el_image_write_png(rt_path("grey.png"), p8, 5, 3, 1, e, sizeof e)) {
    printf("cannot write the seed PNGs: %s\n", e);
    exit(1);
  }
  rt_write("a.ply", "ply\nformat ascii 1.0\ncomment a quad\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
                    "property float nx\nproperty float ny\nproperty float nz\nproperty float u\nproperty float v\n"
                    "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
                    "-1 0 0 0 0 -1 0 0\n1 0 0 0 0 -1 1 0\n1 1 0 0 0 -1 1 1\n-1 1 0 0 0 -1 0 1\n4 0 1 2 3\n");
  {
    FILE *f = fopen(rt_path("b.ply"), "wb");
    static const float v[12] = {-1, 0, 2, 1, 0, 2, 1, 1, 2, -1, 1, 2};
    if (!f) { perror("b.ply"); exit(1); }
    fputs("ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
          "element face 2\nproperty list uchar uint vertex_indices\nend_header\n", f);
    for (i = 0; i < 12; i++) fz_write_lef(f, v[i]);
    fputc(3, f); fz_write_le32(f, 0); fz_write_le32(f, 1); fz_write_le32(f, 2);
    fputc(3, f); fz_write_le32(f, 0); fz_write_le32(f, 2); fz_write_le32(f, 3);
    fclose(f);
  }
  rt_write("inc.pbrt", "# included\nAttributeBegin\n  Translate 0 0.3 -1\n  Material \"matte\" \"rgb Kd\" [ 0.2 0.7 0.2 ]\n"
                       "  Shape \"sphere\" \"float radius\" 0.3\nAttributeEnd\n");
  rt_write("s.spd", "# a spectrum: wavelength (nm), value\n380 0.5\n450 1.5\n550 1.0 # a comment\n650 2.0\n780 0.7\n");
  for (i = 0; i < FZ_NIMG; i++)
    if (fz_read_file(rt_path(fz_img_names[i]), &fz_img_seed[i])) { printf("cannot read %s\n", fz_img_names[i]); exit(1); }

  /* scene seeds: the directive tour, the repository's scenes (their map replaced by the tiny one, their
   * film shrunk to 8 x 8), small scenes */
  fz_set(&fz_scene_seed[fz_nscene_seeds++], fz_every_directive, strlen(fz_every_directive));
  {
    static const char *files[4] = {"envlight_demo.pbrt", "bench_city.pbrt", "glass_metal.pbrt", "loopsubdiv.pbrt"};
    int k;
    for (k = 0; k < 4; k++) {
      char path[1024];
      fz_buf *b = &fz_scene_seed[fz_nscene_seeds];
      char *q;
      snprintf(path, sizeof path, "%s/scenes/%s", EL_SOURCE_DIR, files[k]);
      if (fz_read_file(path, b)) { printf("(no %s: skipped as a seed)\n", path); continue; }
      while ((q = strstr((char *)b->p, "../data/envmaps/")) != NULL) fz_splice(b, (size_t)(q - (char *)b->p), strlen("../data/envmaps/city.hdr"), "tiny.hdr", 8);
      while ((q = strstr((char *)b->p, "[ 640 ]")) != NULL) fz_splice(b, (size_t)(q - (char *)b->p), 7, "[ 8 ]", 5);
      while ((q = strstr((char *)b->p, "[ 400 ]")) != NULL) fz_splice(b, (size_t)(q - (char *)b->p), 7, "[ 8 ]", 5);
      while ((q = strstr((char *)b->p, "[ 320 ]")) != NULL) fz_splice(b, (size_t)(q - (char *)b->p), 7, "[ 8 ]", 5);
      while ((q = strstr((char *)b->p, "[ 240 ]")) != NULL) fz_splice(b, (size_t)(q - (char *)b->p), 7, "[ 8 ]", 5);
      while ((q = strstr((char *)b->p, "[ 192 ]")) != NULL) fz_splice(b, (size_t)(q - (char *)b->p), 7, "[ 8 ]", 5);
      while ((q = strstr((char *)b->p, "[ 180 ]")) != NULL) fz_splice(b, (size_t)(q - (char *)b->p), 7, "[ 8 ]", 5);
      fz_nscene_seeds++;
    }
  }
  {
    static const char *small[] = {
        "Film \"image\" \"integer xresolution\" 4 \"integer yresolution\" 4\nWorldBegin\nLightSource \"infinite\"\nShape \"sphere\"\nWorldEnd\n",
        "Film \"image\" \"integer xresolution\" 4 \"integer yresolution\" 3\nSampler \"random\" \"integer pixelsamples\" 1\n"
        "Integrator \"directlighting\"\nWorldBegin\nLightSource \"infinite\" \"string mapname\" \"tiny.exr\"\n"
        "Texture \"t\" \"spectrum\" \"imagemap\" \"string filename\" \"tiny.hdr\"\nMaterial \"matte\" \"texture Kd\" \"t\"\n"
        "Shape \"plymesh\" \"string filename\" \"a.ply\"\nWorldEnd\n",
        "Film \"image\" \"integer xresolution\" 5 \"integer yresolution\" 5\nWorldBegin\nLightSource \"infinite\" \"string mapname\" \"tiny.pfm\"\n"
        "Shape \"trianglemesh\" \"point P\" [ 0 0 1 1 0 1 0 1 1 ]\nTexture \"g\" \"float\" \"imagemap\" \"string filename\" \"grey.png\"\n"
        "Material \"plastic\" \"texture roughness\" \"g\"\nShape \"sphere\" \"float radius\" 0.5\nWorldEnd\n",
        /* area lights: a quad light over a box (directlighting, one light at a time), a sphere light beside the environment */
        "Film \"image\" \"integer xresolution\" 4 \"integer yresolution\" 4\nLookAt 0 1 -3 0 1 0 0 1 0\n"
        "Integrator \"directlighting\" \"string strategy\" \"one\"\nWorldBegin\nAttributeBegin\n"
        "AreaLightSource \"diffuse\" \"rgb L\" [ 8 8 8 ]\nShape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ]\n"
        "  \"point P\" [ -0.3 1.9 -0.3 0.3 1.9 -0.3 0.3 1.9 0.3 -0.3 1.9 0.3 ]\nAttributeEnd\n"
        "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ] \"point P\" [ -1 0 -1 1 0 -1 1 0 1 -1 0 1 ]\n"
        "LightSource \"point\" \"point from\" [ 0 1 0 ] \"blackbody I\" [ 4000 1 ]\nWorldEnd\n",
        "Film \"image\" \"integer xresolution\" 4 \"integer yresolution\" 4\nIntegrator \"path\" \"string lightsamplestrategy\" \"power\"\n"
        "WorldBegin\nLightSource \"infinite\" \"string mapname\" \"tiny.hdr\"\nAttributeBegin\nTranslate 0 0 3\nScale 1 2 1\n"
        "AreaLightSource \"area\" \"xyz L\" [ 1 1 1 ]\nShape \"sphere\" \"float radius\" 0.5\nAttributeEnd\n"
        "Shape \"disk\" \"float height\" -1 \"float radius\" 4\nWorldEnd\n"};
    int k;
    for (k = 0; k < 5 && fz_nscene_seeds < FZ_NSEEDS; k++) fz_set(&fz_scene_seed[fz_nscene_seeds++], small[k], strlen(small[k]));
  }
}

/* >> running one case */
static int fz_verbose, fz_render_all;
static const char *fz_dump_dir;
static long fz_scene_ok, fz_scene_err, fz_rendered, fz_image_ok, fz_image_err, fz_bad;

static void fz_bad_case(const char *what, long kase, const char *detail, const unsigned char *input, size_t n) {
  fz_bad++;
  if (fz_bad <= 10) {
    printf("FAIL case %ld (%s): %s\n", kase, what, detail);
    if (input) printf("---- input (%zu bytes) ----\n%.*s\n----\n", n, (int)(n < 2000 ? n : 2000), (const char *)input);
  }
}

/* "name.ext:123: " at the start of the message: a scene error names its file and line (a file name
 * with an extension: "?:1:" once stood for an unknown file) */
static int fz_has_file_line(const char *err) {
  const char *p = err, *dot = NULL;
  while (*p && *p != ':' && *p != ' ') { if (*p == '.') dot = p; p++; }
  if (*p != ':' || !dot || dot == err) return 0;
  p++;
  if (!(*p >= '0' && *p <= '9')) return 0;
  while (*p >= '0' && *p <= '9') p++;
  return p[0] == ':' && p[1] == ' ';
}

static void fz_dump(const char *name, const unsigned char *p, size_t n) {
  char path[1024];
  if (!fz_dump_dir) return;
  snprintf(path, sizeof path, "%s/%s", fz_dump_dir, name);
  fz_write_file(path, p, n);
}

/* Render at most 8 x 8 (or the crop of it) at 1 spp on 1 thread; every pixel must be finite. */
static void fz_render_check(elr_scene *s, long kase, const fz_buf *in) {
  int w, h;
  elr_image img;
  elr_stats st;
  elr_render_options o;
  char err[512];
  elr_scene_resolution(s, &w, &h);
  if (w <= 0 || h <= 0 || w > 8 || h > 8 || s->d.xres > 64 || s->d.yres > 64) return;
  elr_render_options_default(&o);
  o.spp = 1; o.nthreads = 1; o.quiet = 1; o.seed = (uint64_t)kase;
  if (kase >= 0) { /* the render options' overrides too, varied by case (deterministically) */
    uint64_t h = (uint64_t)kase * 0x9e3779b97f4a7c15ULL;
    o.light_sampling = (int)((h >> 20) % 4) - 1;  /* -1 (the scene's), mis, light, bsdf */
    o.sampler = (int)((h >> 24) % ELR_SAMPLER_COUNT); /* the scene's, or one of the 7 samplers */
    o.importance = (int)((h >> 28) % 4) - 1;
    o.compensated = (int)((h >> 32) % 3) - 1;
    if ((h >> 36) % 4 == 0) o.spp = 2 + (int)((h >> 40) % 3);
    if ((h >> 44) % 4 == 0) o.tile_size = 1 + (int)((h >> 48) % 5);
    if ((h >> 52) % 8 == 0) o.nthreads = 2 + (int)((h >> 56) % 2); /* tiles on threads too */
  }
  err[0] = 0;
  if (elr_render(s, &o, &img, &st, err, sizeof err) != 0) {
    if (!err[0]) fz_bad_case("render", kase, "elr_render failed with an empty message", in->p, in->n);
    else if (fz_verbose) printf("  render -> %s\n", err);
    return;
  }
  fz_rendered++;
  {
    size_t i, n = (size_t)img.width * (size_t)img.height * 3;
    for (i = 0; i < n; i++)
      if (!isfinite(img.rgb[i]) || img.rgb[i] < 0.f) {
        char d[200];
        snprintf(d, sizeof d, "pixel value %g at %zu of the %d x %d image", img.rgb[i], i / 3, img.width, img.height);
        fz_bad_case("render", kase, d, in->p, in->n);
        break;
      }
  }
  elr_image_free(&img);
}

/* The render program on a scene that failed to load: exit code 1 and a message on stderr naming
 * file:line, no image written. */
static long fz_cli_runs;
static void fz_cli_check(long kase, const fz_buf *b) {
  char cmd[2048], log[1024] = "";
  FILE *f;
  int r;
  size_t n;
  fz_write_file(rt_path("cli.pbrt"), b->p, b->n);
  remove(rt_path("cli_out.pfm"));
  snprintf(cmd, sizeof cmd, "cd '%s' && '%s' cli.pbrt --outfile cli_out.pfm --quiet --nthreads 1 --spp 1 2>cli.log", rt_dir, EL_RENDER_BIN);
  r = system(cmd);
  f = fopen(rt_path("cli.log"), "rb");
  n = f ? fread(log, 1, sizeof log - 1, f) : 0;
  log[n] = 0;
  if (f) fclose(f);
  fz_cli_runs++;
  if (r == -1 || !WIFEXITED(r) || WEXITSTATUS(r) != 1 || !fz_has_file_line(log)) { /* cli.pbrt or a file it includes */
    char d[1300];
    snprintf(d, sizeof d, "render exited with status %d (signal %d), stderr \"%s\"", WIFEXITED(r) ? WEXITSTATUS(r) : -1,
             WIFSIGNALED(r) ? WTERMSIG(r) : 0, log);
    fz_bad_case("render program", kase, d, b->p, b->n);
  }
  f = fopen(rt_path("cli_out.pfm"), "rb");
  if (f) { fclose(f); fz_bad_case("render program", kase, "an image was written for a scene that does not load", b->p, b->n); }
}

static void fz_scene_case(uint64_t seed, long kase, fz_buf *b) {
  int nm, i;
  char err[512];
  elr_scene *s = NULL;
  fz_seed(seed, (uint64_t)kase);
  {
    const fz_buf *src = &fz_scene_seed[fz_below((size_t)fz_nscene_seeds)];
    fz_set(b, src->p, src->n);
  }
  nm = fz_below(3) ? 1 : 2 + (int)fz_below(4);
  for (i = 0; i < nm; i++) fz_mutate_scene(b);
  /* the loaders stop at a NUL (elr_scene_load refuses one): keep the text a C string */
  b->n = strlen((const char *)b->p);
  fz_dump("case.pbrt", b->p, b->n);
  if (fz_verbose) printf("case %ld: %zu bytes\n", kase, b->n);
  err[0] = 0;
  if (elr_scene_load_string((const char *)b->p, "fuzz.pbrt", rt_dir, &s, 1, err, sizeof err) == 0) {
    fz_scene_ok++;
    if (!s) { fz_bad_case("scene", kase, "success without a scene", b->p, b->n); return; }
    if (fz_render_all || kase % 3 == 0) fz_render_check(s, kase, b);
    elr_scene_free(s);
  } else {
    fz_scene_err++;
    if (s) fz_bad_case("scene", kase, "an error with a scene", b->p, b->n);
    if (kase % 200 == 7) fz_cli_check(kase, b); /* a sample through the program too */
    if (!err[0]) fz_bad_case("scene", kase, "an error with an empty message", b->p, b->n);
    else if (!fz_has_file_line(err)) {
      /* parse errors name file:line; Embree build errors cannot, but name the scene part */
      char d[700];
      snprintf(d, sizeof d, "the message does not name file:line: \"%s\"", err);
      fz_bad_case("scene", kase, d, b->p, b->n);
    } else if (fz_verbose) printf("  -> %s\n", err);
  }
}

/* Image (and PLY, included scene) files: mutate one, write it under its own extension, load it with
 * el_image_load (or through a scene that uses it), check. */
static void fz_image_case(uint64_t seed, long kase, fz_buf *b) {
  int which, nm, i;
  char name[64], err[512];
  const char *ext;
  fz_seed(seed ^ 0x5ca1ab1eULL, (uint64_t)kase);
  which = (int)fz_below((size_t)FZ_NIMG);
  fz_set(b, fz_img_seed[which].p, fz_img_seed[which].n);
  nm = 1 + (int)fz_below(3);
  for (i = 0; i < nm; i++) {
    /* text formats (the included scene, the ASCII PLY, PFM headers) also get token mutations */
    if (which == FZ_NIMG - 1 || which == FZ_NIMG - 4 || (which == FZ_NIMG - 3 && fz_below(2)) || (which == 3 && fz_below(4) == 0)) fz_mutate_scene(b);
    else fz_mutate_bytes(b);
  }
  if (which == FZ_NIMG - 1 || which == FZ_NIMG - 4) b->n = strlen((const char *)b->p);
  ext = strrchr(fz_img_names[which], '.');
  snprintf(name, sizeof name, "m%s", ext);
  fz_write_file(rt_path(name), b->p, b->n);
  fz_dump(name, b->p, b->n);
  if (fz_verbose) printf("image case %ld: %s %zu bytes\n", kase, name, b->n);
  if (!strcmp(ext, ".hdr") || !strcmp(ext, ".exr") || !strcmp(ext, ".pfm") || !strcmp(ext, ".png")) {
    el_image img;
    err[0] = 0;
    if (el_image_load(rt_path(name), &img, err, sizeof err) == 0) {
      size_t n, k;
      double sum = 0;
      fz_image_ok++;
      if (img.width <= 0 || img.height <= 0 || img.channels < 1 || img.channels > 4 || !img.pixels) {
        char d[200];
        snprintf(d, sizeof d, "success with %d x %d x %d, pixels %p", img.width, img.height, img.channels, (void *)img.pixels);
        fz_bad_case("image", kase, d, NULL, 0);
      } else {
        n = (size_t)img.width * (size_t)img.height * (size_t)img.channels;
        for (k = 0; k < n; k++) sum += img.pixels[k]; /* reads every pixel: ASan checks the buffer's size */
        (void)sum;
      }
      el_image_free(&img);
    } else {
      fz_image_err++;
      if (!err[0] || !strstr(err, name)) {
        char d[700];
        snprintf(d, sizeof d, "the message does not name the file: \"%s\"", err);
        fz_bad_case("image", kase, d, NULL, 0);
      } else if (fz_verbose) printf("  -> %s\n", err);
    }
  }
  if (kase % 4 == 0 || !strcmp(ext, ".ply") || !strcmp(ext, ".pbrt") || !strcmp(ext, ".spd")) {
    /* through the scene: an environment map and a texture (or the mesh, or the include) */
    char scene[1024];
    elr_scene *s = NULL;
    fz_buf in; memset(&in, 0, sizeof in);
    if (!strcmp(ext, ".ply"))
      snprintf(scene, sizeof scene, "Film \"image\" \"integer xresolution\" 4 \"integer yresolution\" 4\nWorldBegin\n"
                                    "LightSource \"infinite\"\nShape \"plymesh\" \"string filename\" \"%s\"\nWorldEnd\n", name);
    else if (!strcmp(ext, ".spd")) /* a spectrum file: an area light's L and a material's Kd */
      snprintf(scene, sizeof scene, "Film \"image\" \"integer xresolution\" 4 \"integer yresolution\" 4\nWorldBegin\n"
                                    "AreaLightSource \"diffuse\" \"spectrum L\" \"%s\"\nShape \"disk\"\nAttributeBegin\n"
                                    "Material \"matte\" \"spectrum Kd\" \"%s\"\nShape \"sphere\" \"float radius\" 0.5\nAttributeEnd\nWorldEnd\n", name, name);
    else if (!strcmp(ext, ".pbrt"))
      snprintf(scene, sizeof scene, "Film \"image\" \"integer xresolution\" 4 \"integer yresolution\" 4\nWorldBegin\n"
                                    "LightSource \"infinite\"\nInclude \"%s\"\nWorldEnd\n", name);
    else
      snprintf(scene, sizeof scene, "Film \"image\" \"integer xresolution\" 4 \"integer yresolution\" 4\nWorldBegin\n"
                                    "LightSource \"infinite\" \"string mapname\" \"%s\"\n"
                                    "Texture \"t\" \"spectrum\" \"imagemap\" \"string filename\" \"%s\"\n"
                                    "Material \"plastic\" \"texture Kd\" \"t\"\nShape \"sphere\"\nWorldEnd\n", name, name);
    fz_set(&in, scene, strlen(scene));
    err[0] = 0;
    if (elr_scene_load_string(scene, "img.pbrt", rt_dir, &s, 1, err, sizeof err) == 0) {
      fz_render_check(s, kase, &in);
      elr_scene_free(s);
    } else if (!err[0] || (!fz_has_file_line(err) && !strstr(err, name))) {
      char d[700];
      snprintf(d, sizeof d, "the message does not name the file: \"%s\"", err);
      fz_bad_case("image scene", kase, d, b->p, !strcmp(ext, ".pbrt") || !strcmp(ext, ".ply") || !strcmp(ext, ".spd") ? b->n : 0);
    } else if (fz_verbose) printf("  scene -> %s\n", err);
    free(in.p);
  }
}

/* The length of an EXR seed's header (magic, version, attributes): where its chunk offset table starts.
 * The table's first entry points just past the table, so it is the first position k whose 8-byte
 * value is k + 8 * (number of chunks). */
static size_t fz_exr_header_length(const fz_buf *e) {
  size_t k;
  uint64_t c;
  for (k = 8; k + 8 <= e->n; k++) {
    uint64_t v = 0;
    int i;
    for (i = 7; i >= 0; i--) v = (v << 8) | e->p[k + (size_t)i];
    for (c = 1; c <= 64; c++)
      if (v == k + 8 * c) return k;
  }
  printf("the EXR seed has no chunk offset table\n");
  exit(1);
}

/* >> bugs the fuzzer found, each as a fixed input */
static void fz_regressions(void) {
  char err[512];
  el_image img;
  { /* an EXR whose first pixel chunk is corrupt (4 bytes inserted into its data): an earlier EXR reader
     * failed and leaked its channel buffers (LeakSanitizer in the sanitizer build) */
    fz_buf b;
    uint64_t off = 0;
    size_t hl = fz_exr_header_length(&fz_img_seed[2]);
    int i, r;
    memset(&b, 0, sizeof b);
    fz_set(&b, fz_img_seed[2].p, fz_img_seed[2].n); /* tiny.exr: 8 x 4, ZIP, one scanline chunk */
    for (i = 7; i >= 0; i--) off = (off << 8) | b.p[hl + (size_t)i]; /* the first chunk's offset */
    fz_splice(&b, (size_t)off + 8 + 6, 0, "\xff\x00\x7f\x80", 4);
    fz_write_file(rt_path("corrupt_chunk.exr"), b.p, b.n);
    r = el_image_load(rt_path("corrupt_chunk.exr"), &img, err, sizeof err);
    rt_check(r != 0 && strstr(err, "corrupt_chunk.exr") != NULL, "an EXR with a corrupt pixel chunk: an error naming the file, nothing leaked (\"%s\")", r ? err : "loaded");
    if (r == 0) el_image_free(&img);
    /* the same with the version field's "tiled" bit set (the header is still a scanline one): this took
     * another path through that reader, which leaked the same way */
    b.p[5] |= 0x02;
    fz_write_file(rt_path("corrupt_tiled.exr"), b.p, b.n);
    r = el_image_load(rt_path("corrupt_tiled.exr"), &img, err, sizeof err);
    rt_check(r != 0 && strstr(err, "corrupt_tiled.exr") != NULL, "the same EXR flagged as tiled: an error naming the file, nothing leaked (\"%s\")", r ? err : "loaded");
    if (r == 0) el_image_free(&img);
    free(b.p);
  }
  { /* a 2 x 1 grey PNG whose zlib stream uses distance code 30 (invalid): Debian's stb_image indexed
     * past its distance table and "loaded" it, with pixels from wherever that pointed (uninitialised
     * memory for a fuzzed file: a different image in every run) */
    static const unsigned char png[68] = {
        0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x48, 0x44, 0x52, 0x00,
        0x00, 0x00, 0x02, 0x00, 0x00, 0x00, 0x01, 0x08, 0x00, 0x00, 0x00, 0x00, 0xd1, 0x49, 0x20, 0x56, 0x00,
        0x00, 0x00, 0x0b, 0x49, 0x44, 0x41, 0x54, 0x78, 0x01, 0x63, 0x60, 0x07, 0x3e, 0x00, 0x00, 0x00, 0x00,
        0x01, 0xfe, 0xdf, 0x93, 0xd5, 0x00, 0x00, 0x00, 0x00, 0x49, 0x45, 0x4e, 0x44, 0xae, 0x42, 0x60, 0x82};
    int r;
    fz_write_file(rt_path("dist30.png"), png, sizeof png);
    r = el_image_load(rt_path("dist30.png"), &img, err, sizeof err);
    rt_check(r != 0 && strstr(err, "dist30.png") && strstr(err, "invalid distance code"),
             "a PNG with an invalid zlib distance code: an error naming the file and the problem (\"%s\")", r ? err : "loaded");
    if (r == 0) el_image_free(&img);
  }
  { /* an 8 x 4 Radiance HDR whose first two scanlines are run-length encoded and the last two flat:
     * stb_image restarts flat decoding at row 0 there, so it loaded with wrong pixels (and read past the
     * end of the file as zeros) */
    fz_buf b;
    int y, c, r;
    static const char hdr[] = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 4 +X 8\n";
    memset(&b, 0, sizeof b);
    fz_set(&b, hdr, strlen(hdr));
    for (y = 0; y < 2; y++) {
      unsigned char line[12];
      line[0] = 2; line[1] = 2; line[2] = 0; line[3] = 8;
      for (c = 0; c < 4; c++) { line[4 + 2 * c] = 128 + 8; line[5 + 2 * c] = (unsigned char)(c < 3 ? 100 + 10 * y : 129); }
      fz_splice(&b, b.n, 0, line, sizeof line);
    }
    for (y = 0; y < 16; y++) fz_splice(&b, b.n, 0, "\x78\x78\x78\x81", 4);
    fz_write_file(rt_path("mixed.hdr"), b.p, b.n);
    r = el_image_load(rt_path("mixed.hdr"), &img, err, sizeof err);
    rt_check(r != 0 && strstr(err, "mixed.hdr") && strstr(err, "scanline 3 of 4 is flat"),
             "an HDR mixing run-length encoded and flat scanlines: an error naming the file and scanline (\"%s\")", r ? err : "loaded");
    if (r == 0) el_image_free(&img);
    free(b.p);
  }
  { /* error messages quote bytes of corrupt files: they must stay printable (a PFM scale token of binary
     * bytes was copied into the message as it was) */
    int r, k, printable = 1;
    fz_write_file(rt_path("binscale.pfm"), (const unsigned char *)"PF\n2 1\n\x01\x1b[2J\xff\xfe\n", 16);
    r = el_image_load(rt_path("binscale.pfm"), &img, err, sizeof err);
    for (k = 0; err[k]; k++) if ((unsigned char)err[k] < 32 || (unsigned char)err[k] >= 127) printable = 0;
    rt_check(r != 0 && printable && strstr(err, "bad PFM scale"), "a PFM with a binary scale token: a printable message (\"%s\")", err);
    if (r == 0) el_image_free(&img);
    {
      elr_scene *sc = NULL;
      r = elr_scene_load_string("WorldBegin\nTexture \"t\" \"\x1b[2J\x07\" \"constant\"\nWorldEnd\n", "ctl.pbrt", rt_dir, &sc, 1, err, sizeof err);
      for (printable = 1, k = 0; err[k]; k++) if ((unsigned char)err[k] < 32 || (unsigned char)err[k] == 127) printable = 0;
      rt_check(r != 0 && printable && strstr(err, "ctl.pbrt:2:"), "a scene error quoting control characters: a printable message (\"%s\")", err);
      if (r == 0) elr_scene_free(sc);
    }
  }
  { /* sizes that would decode to more than 2^28 pixels are refused from the header: run-length encoded
     * HDR and deflated PNG data expand up to 1000 times (a 38 MB HDR of 30000 x 20000 asked for 7 GB) */
    int r;
    static const unsigned char png[33] = {0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x48, 0x44, 0x52, 0x00,
                                          0x00, 0x40, 0x01, 0x00, 0x00, 0x40, 0x01, 0x08, 0x02, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00};
    rt_write("big.hdr", "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 16385 +X 16385\n");
    r = el_image_load(rt_path("big.hdr"), &img, err, sizeof err);
    rt_check(r != 0 && strstr(err, "big.hdr") && strstr(err, "too large (16385 x 16385"), "an HDR header of 16385 x 16385: too large (\"%s\")", err);
    if (r == 0) el_image_free(&img);
    fz_write_file(rt_path("big.png"), png, sizeof png);
    r = el_image_load(rt_path("big.png"), &img, err, sizeof err);
    rt_check(r != 0 && strstr(err, "big.png") && strstr(err, "too large (16385 x 16385"), "a PNG header of 16385 x 16385: too large (\"%s\")", err);
    if (r == 0) el_image_free(&img);
  }
  { /* an EXR whose data window is 2^23 x 33 pixels, with a complete offset table of empty chunks:
     * an earlier EXR reader allocated 3 x 1.1 GB for its channels before decoding anything; refused
     * from the header, before OpenEXR reads a chunk */
    fz_buf b;
    size_t hl = fz_exr_header_length(&fz_img_seed[2]);
    int y, r;
    static const char *wins[2] = {"dataWindow", "displayWindow"};
    memset(&b, 0, sizeof b);
    fz_set(&b, fz_img_seed[2].p, hl); /* the header */
    for (y = 0; y < 2; y++) {
      size_t at;
      for (at = 0; at + strlen(wins[y]) < b.n; at++)
        if (!memcmp(b.p + at, wins[y], strlen(wins[y]) + 1)) {
          int32_t box[4] = {0, 0, (1 << 23) - 1, 32};
          memcpy(b.p + at + strlen(wins[y]) + 1 + 6 + 4, box, 16); /* name NUL "box2i" NUL size, then 4 int32 */
          break;
        }
    }
    for (y = 0; y < 33; y++) {
      uint64_t off = hl + 33 * 8 + 8 * (uint64_t)y;
      unsigned char le[8];
      int i;
      for (i = 0; i < 8; i++) le[i] = (unsigned char)(off >> (8 * i));
      fz_splice(&b, b.n, 0, le, 8);
    }
    for (y = 0; y < 33; y++) {
      unsigned char c[8] = {0, 0, 0, 0, 0, 0, 0, 0};
      c[0] = (unsigned char)y;
      fz_splice(&b, b.n, 0, c, 8);
    }
    fz_write_file(rt_path("bomb.exr"), b.p, b.n);
    r = el_image_load(rt_path("bomb.exr"), &img, err, sizeof err);
    rt_check(r != 0 && strstr(err, "bomb.exr") && strstr(err, "8388608 x 33 pixels is empty or too large"),
             "an EXR of 8388608 x 33 pixels: too large before OpenEXR allocates (\"%s\")", err);
    if (r == 0) el_image_free(&img);
    free(b.p);
  }
  { /* a checkerboard's box filter with a huge differential: (int)floorf(5e29) in textures.c (undefined;
     * UBSan's float-cast-overflow, on in the sanitizer build) */
    elr_scene sc;
    elr_texture t[3];
    elr_tex_ctx c;
    elr_v3 v;
    memset(&sc, 0, sizeof sc); memset(t, 0, sizeof t); memset(&c, 0, sizeof c);
    t[0].kind = ELR_TEX_CONST; t[0].value = elr_v(1, 1, 1);
    t[1].kind = ELR_TEX_CONST;
    t[2].kind = ELR_TEX_CHECKER; t[2].tex1 = 0; t[2].tex2 = 1; t[2].aa_closedform = 1; t[2].su = t[2].sv = 1;
    sc.tex = t; sc.ntex = 3;
    c.u = 0.5f; c.v = 0.5f; c.dudx = 1e30f; c.dvdx = 1e30f;
    v = elr_tex_eval(&sc, 2, &c);
    rt_check(v.x == 0.5f, "checkerboard with a differential of 1e30: the box filter's average 0.5 (got %g)", v.x);
    c.dudx = 1e9f; c.dvdx = 0.25f; c.u = 1e8f;
    v = elr_tex_eval(&sc, 2, &c);
    rt_check(v.x == 0.5f, "checkerboard with u 1e8 and a differential of 1e9: 0.5 (got %g)", v.x);
  }
}

/* Every prefix of every seed image (and of the PLY files through a scene): an error naming the file, or
 * (only for the whole file) the image. */
static void fz_truncations(void) {
  int which, bad = 0, tried = 0;
  char err[512];
  for (which = 0; which < FZ_NIMG - 1; which++) {
    const char *ext = strrchr(fz_img_names[which], '.');
    size_t k, n = fz_img_seed[which].n;
    char name[64];
    snprintf(name, sizeof name, "t%s", ext);
    for (k = 0; k < n; k++) {
      size_t j = k;
      while (j < n && (fz_img_seed[which].p[j] == '\n' || fz_img_seed[which].p[j] == ' ')) j++;
      if (j == n) break; /* only trailing white space is missing (an ASCII PLY's last newline) */
      fz_write_file(rt_path(name), fz_img_seed[which].p, k);
      tried++;
      if (!strcmp(ext, ".ply")) {
        char scene[512];
        elr_scene *sc = NULL;
        snprintf(scene, sizeof scene, "WorldBegin\nShape \"plymesh\" \"string filename\" \"%s\"\nWorldEnd\n", name);
        if (elr_scene_load_string(scene, "trunc.pbrt", rt_dir, &sc, 1, err, sizeof err) == 0) {
          elr_scene_free(sc);
          if (++bad <= 3) printf("  %s cut to %zu of %zu bytes loads\n", fz_img_names[which], k, n);
        } else if (!strstr(err, "trunc.pbrt:2:")) {
          if (++bad <= 3) printf("  %s cut to %zu bytes: \"%s\"\n", fz_img_names[which], k, err);
        }
      } else {
        el_image img;
        if (el_image_load(rt_path(name), &img, err, sizeof err) == 0) {
          el_image_free(&img);
          if (++bad <= 3) printf("  %s cut to %zu of %zu bytes loads\n", fz_img_names[which], k, n);
        } else if (!strstr(err, name)) {
          if (++bad <= 3) printf("  %s cut to %zu bytes: \"%s\"\n", fz_img_names[which], k, err);
        }
      }
    }
  }
  rt_check(bad == 0, "every proper prefix of the %d seed images and PLY files (%d files) fails with a message naming the file (%d do not)",
           FZ_NIMG - 1, tried, bad);
}

static void fz_alarm(int sig) {
  static const char msg[] = "test_render_fuzz: a case ran longer than the time limit (a hang?)\n";
  (void)sig;
  if (write(2, msg, sizeof msg - 1) < 0) _exit(3);
  _exit(3);
}

int main(int argc, char **argv) {
  uint64_t seed = 20261201;
  long nscenes = 12000, nimages = 12000, only = -1, k;
  int i, per_case_alarm = 0;
  fz_buf b;
  double t0 = elr_now();
  for (i = 1; i < argc; i++) {
    if (!strcmp(argv[i], "--seed") && i + 1 < argc) seed = strtoull(argv[++i], NULL, 10);
    else if (!strcmp(argv[i], "--scenes") && i + 1 < argc) nscenes = strtol(argv[++i], NULL, 10);
    else if (!strcmp(argv[i], "--images") && i + 1 < argc) nimages = strtol(argv[++i], NULL, 10);
    else if (!strcmp(argv[i], "--only") && i + 1 < argc) only = strtol(argv[++i], NULL, 10);
    else if (!strcmp(argv[i], "--dump") && i + 1 < argc) fz_dump_dir = argv[++i];
    else if (!strcmp(argv[i], "--alarm")) per_case_alarm = 1;
    else if (!strcmp(argv[i], "--verbose")) fz_verbose = 1;
    else if (!strcmp(argv[i], "--render-all")) fz_render_all = 1;
    else { printf("usage: test_render_fuzz [--seed S] [--scenes N] [--images M] [--only K] [--dump DIR] [--alarm] [--render-all] [--verbose]\n"); return 2; }
  }
  if (per_case_alarm) signal(SIGALRM, fz_alarm);
  rt_mkdir("test_render_fuzz");
  fz_make_seeds();
  memset(&b, 0, sizeof b);
  if (only < 0) fz_regressions();
  if (only < 0) fz_truncations();
  if (only < 0) { /* the seeds themselves load and render */
    int good = 0;
    for (i = 0; i < fz_nscene_seeds; i++) {
      elr_scene *s = NULL;
      char err[512];
      if (elr_scene_load_string((const char *)fz_scene_seed[i].p, "seed.pbrt", rt_dir, &s, 1, err, sizeof err) == 0) {
        long bad = fz_bad;
        fz_render_check(s, -1 - i, &fz_scene_seed[i]);
        if (fz_bad == bad) good++;
        elr_scene_free(s);
      } else printf("seed scene %d: %s\n", i, err);
    }
    rt_check(good == fz_nscene_seeds, "the %d seed scenes load and render (%d do)", fz_nscene_seeds, good);
  }
  for (k = 0; k < nscenes; k++) {
    if (only >= 0 && k != only) continue;
    if (per_case_alarm) alarm(20);
    fz_scene_case(seed, k, &b);
  }
  for (k = 0; k < nimages; k++) {
    if (only >= 0 && k != only) continue;
    if (per_case_alarm) alarm(20);
    fz_image_case(seed, k, &b);
  }
  if (per_case_alarm) alarm(0);
  free(b.p);
  for (i = 0; i < FZ_NSEEDS; i++) free(fz_scene_seed[i].p);
  for (i = 0; i < FZ_NIMG; i++) free(fz_img_seed[i].p);
  printf("seed %llu: %ld scene cases (%ld loaded, %ld errors, %ld rendered, %ld through the render program), %ld image cases "
         "(%ld loaded, %ld errors) in %.1f s\n", (unsigned long long)seed, only >= 0 ? 1L : nscenes, fz_scene_ok, fz_scene_err,
         fz_rendered, fz_cli_runs, only >= 0 ? 1L : nimages, fz_image_ok, fz_image_err, elr_now() - t0);
  rt_check(fz_bad == 0, "every mutated input loads or fails with a message naming the file; rendered pixels are finite (%ld bad)", fz_bad);
  return rt_finish("test_render_fuzz");
}
