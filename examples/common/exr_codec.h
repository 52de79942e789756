/* exr_codec.h: the pixel coding of OpenEXR files for image_io.c, through OpenEXR's C++ library
 * (exr_codec.cc). Private to examples/common: call el_image_load / el_image_write_exr instead, which
 * check the file's header and chunk table with OpenEXRCore before anything is decoded. */
#ifndef EL_EXR_CODEC_H
#define EL_EXR_CODEC_H
#include <stddef.h>
#ifdef __cplusplus
extern "C" {
#endif

/* Decodes part 0 of the OpenEXR file at path into rgb (width * height pixels of 3 floats, row 0 at
 * the top of the data window): channel names[c] goes to component c; names[1] and names[2] may be
 * NULL (those components are left alone). The data window must be the one given (image_io.c read it
 * with OpenEXRCore). Any pixel type is converted to float. Returns 0, or -1 with OpenEXR's message
 * in msg. */
int el_exr_decode(const char *path, const char *const names[3], int min_x, int min_y, int width, int height,
                  float *rgb, char *msg, size_t msglen);

/* Writes width x height pixels of `channels` floats (1: Y, 3: RGB, 4: RGBA) as a scanline float32
 * file with ZIP compression (lossless). Returns 0, or -1 with OpenEXR's message in msg. */
int el_exr_encode(const char *path, const float *pixels, int width, int height, int channels, char *msg,
                  size_t msglen);

#ifdef __cplusplus
}
#endif
#endif
