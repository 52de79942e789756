/* test_tutorial_help.c: every chapter program of the course (and 00_path_tracer) answers --help with its usage on stdout and
 * exit status 0, and writes nothing (before this test, `01_mipmap_pyramid --help` created a folder
 * named "--help"). Each program runs in a fresh empty directory, which must still be empty afterwards.
 *   test_tutorial_help      (run by ctest from the build directory; the programs are in build/bin)
 * Without the examples (EL_BUILD_EXAMPLES off) it reports SKIP and exits 77. */
#define _POSIX_C_SOURCE 200809L /* mkdtemp, popen */
#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#ifndef EL_BIN_DIR
#define EL_BIN_DIR "bin"
#endif
#ifndef EL_HAVE_EXAMPLES
#define EL_HAVE_EXAMPLES 1
#endif

static int g_fail;
static void check(int ok, const char *prog, const char *what) {
  printf("%s: %s --help: %s\n", ok ? "PASS" : "FAIL", prog, what);
  if (!ok) g_fail++;
}

/* Number of entries in dir other than . and .. (-1 if it cannot be read). */
static int entries(const char *dir) {
  DIR *d = opendir(dir);
  struct dirent *e;
  int n = 0;
  if (!d) return -1;
  while ((e = readdir(d)) != NULL)
    if (strcmp(e->d_name, ".") && strcmp(e->d_name, "..")) n++;
  closedir(d);
  return n;
}

/* Removes dir and, one level deep, what a failing program left in it (a "--help" folder or files). */
static void remove_scratch(const char *dir) {
  DIR *d = opendir(dir);
  struct dirent *e;
  char path[4096];
  if (d) {
    while ((e = readdir(d)) != NULL) {
      if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, "..")) continue;
      snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
      if (remove(path) != 0) { /* a non-empty folder: empty it first */
        DIR *s = opendir(path);
        struct dirent *f;
        char inner[8192];
        if (s) {
          while ((f = readdir(s)) != NULL) {
            if (!strcmp(f->d_name, ".") || !strcmp(f->d_name, "..")) continue;
            snprintf(inner, sizeof inner, "%s/%s", path, f->d_name);
            remove(inner);
          }
          closedir(s);
        }
        remove(path);
      }
    }
    closedir(d);
  }
  rmdir(dir);
}

int main(void) {
  static const char *progs[] = {"00_path_tracer", "01_mipmap_pyramid", "02_mipmap_empty_constructor", "02_mipmap_lookup",
                                "03_infinite_light", "04_tone_mapping"};
  char bin[4096], cwd[4096];
  size_t i;
  if (!EL_HAVE_EXAMPLES) {
    printf("SKIP: the examples are not built (EL_BUILD_EXAMPLES is off)\n");
    return 77;
  }
  if (!getcwd(cwd, sizeof cwd)) { printf("FAIL: getcwd\n"); return 1; }
  if (EL_BIN_DIR[0] == '/') snprintf(bin, sizeof bin, "%s", EL_BIN_DIR);
  else snprintf(bin, sizeof bin, "%s/%s", cwd, EL_BIN_DIR);
  for (i = 0; i < sizeof progs / sizeof progs[0]; i++) {
    char scratch[] = "el_help_XXXXXX", cmd[3 * 4096 + 64], out[8192];
    size_t n = 0, got;
    int status, left;
    FILE *p;
    if (!mkdtemp(scratch)) { check(0, progs[i], "a scratch directory can be made"); continue; }
    /* run from inside the scratch directory, so anything the program creates lands there */
    snprintf(cmd, sizeof cmd, "cd '%s/%s' && '%s/%s' --help 2>&1", cwd, scratch, bin, progs[i]);
    p = popen(cmd, "r");
    if (!p) { check(0, progs[i], "runs"); remove_scratch(scratch); continue; }
    while (n + 1 < sizeof out && (got = fread(out + n, 1, sizeof out - 1 - n, p)) > 0) n += got;
    out[n] = 0;
    status = pclose(p);
    check(status != -1 && WIFEXITED(status) && WEXITSTATUS(status) == 0, progs[i], "exits with 0");
    check(strstr(out, "usage:") != NULL && strstr(out, progs[i]) != NULL, progs[i], "prints \"usage:\" and its name");
    left = entries(scratch);
    check(left == 0, progs[i], "creates nothing in the working directory");
    if (left != 0) printf("      it left %d entries in %s/%s\n", left, cwd, scratch);
    remove_scratch(scratch);
  }
  printf("%s\n", g_fail ? "FAILED" : "all chapter programs answer --help");
  return g_fail ? 1 : 0;
}
