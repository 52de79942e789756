/* 02_mipmap_empty_constructor.c: the seed's first checkpoint of the MIPMap port, in C. The class
 * definitions are ported, the constructor's body is still empty, and the seed's one-line test
 * compiles and runs (chapter 2 of the course, tutorials/02-porting-the-mipmap.md, step 2).
 *
 * WHAT IT DEMONSTRATES
 *   The seed ports MIPMap in small steps and compiles after each one. It ports the class definition
 *   and BlockedArray first (2.1: AllocAligned becomes new[], a forward declaration of BlockedArray goes
 *   into the global header). Then it empties the constructor's body (2.2) and checks that
 *       float * mpdata = nullptr;
 *       MIPMap<float > mp(Point2i(100,100), mpdata, true);
 *   compiles: "可以编译则说明类定义移植正确" (if it compiles, the class definition is ported
 *   correctly). Here the class definitions come from examples/pbrtv3/mipmap.h with
 *   PBRT_MIPMAP_CLASS_ONLY defined (the header stops after them), and this file supplies the empty
 *   constructor. C has no templates, so the port's texel type is RGBSpectrum and mpdata points to
 *   RGBSpectrum, not float.
 *
 * WHICH PART OF PBRT IT MIRRORS
 *   pbrt-v3 src/core/mipmap.h (<<MIPMap Helper Declarations>>, <<MIPMap Declarations>>, the
 *   constructor's member initialisers) and src/core/memory.h (BlockedArray).
 *
 * HOW TO RUN IT
 *   build/bin/02_mipmap_empty_constructor          (no arguments; --help prints the usage)
 *
 * WHAT IT WRITES
 *   Nothing but two lines on stdout: what the constructor stored.
 */
#define PBRT_MIPMAP_CLASS_ONLY /* only the class definitions: the seed's step 2.1 */
#include "pbrtv3/mipmap.h"

#include <stdio.h>
#include <string.h>

/* MIPMap(resolution, img, doTrilinear, maxAnisotropy, wrapMode) with its body cleared: only the
 * member initialisers stay, ": doTrilinear(doTrilinear), maxAnisotropy(maxAnisotropy),
 * wrapMode(wrapMode), resolution(res)". */
static void pbrt_MIPMap_init(pbrt_MIPMap *mip, pbrt_Point2i res, const pbrt_RGBSpectrum *img, int doTrilinear,
                             float maxAnisotropy, pbrt_ImageWrap wrapMode) {
  (void)img; /* the body that reads it comes in the next step */
  mip->doTrilinear = doTrilinear;
  mip->maxAnisotropy = maxAnisotropy;
  mip->wrapMode = wrapMode;
  mip->resolution = res;
  mip->pyramid = NULL; /* std::vector's constructor: no levels yet */
  mip->nLevels = 0;
}

int main(int argc, char **argv) {
  if (argc > 1) { /* it takes no arguments: --help (or -h) prints this, anything else is an error */
    int help = !strcmp(argv[1], "--help") || !strcmp(argv[1], "-h");
    fprintf(help ? stdout : stderr, "usage: 02_mipmap_empty_constructor   (no arguments; prints two lines)\n");
    return help ? 0 : 1;
  }
  /* the seed's test: float * mpdata = nullptr; MIPMap<float > mp(Point2i(100,100), mpdata, true);
   * C has no default arguments: maxAnisotropy 8 and Repeat are pbrt's defaults, written out */
  const pbrt_RGBSpectrum *mpdata = NULL;
  pbrt_MIPMap mp;
  pbrt_MIPMap_init(&mp, pbrt_Point2i_make(100, 100), mpdata, 1, 8.f, pbrt_ImageWrap_Repeat);
  printf("MIPMap mp(Point2i(100,100), mpdata, true) compiles and runs\n");
  printf("resolution %d x %d, doTrilinear %d, %d levels (the body is empty)\n", mp.resolution.x, mp.resolution.y,
         mp.doTrilinear, mp.nLevels);
  return 0;
}
