// exr_codec.cc: see exr_codec.h. OpenEXR's C++ library (libOpenEXR, Debian's libopenexr-dev) decodes
// every compression OpenEXR has (NONE, RLE, ZIPS, ZIP, PIZ, PXR24, B44, B44A, DWAA, DWAB), scanline
// and tiled; its C core (OpenEXRCore), which image_io.c uses for the header, has no DWA decoder
// before OpenEXR 3.2. Exceptions never leave this file: each becomes a message.
#include "exr_codec.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>

#include <cstdio>
#include <exception>
#include <mutex>

namespace {
// The largest image and tile either reader accepts: image_io.c refuses more than 2^28 pixels, and
// checks the chunk sizes, before calling us; this keeps the C++ library's own header check in line
// with it should it read a header differently.
const int kMaxSide = 1 << 28, kMaxTile = 1 << 16;

std::once_flag limits_once;
void set_limits() { // process-wide settings of the C++ library: set once, before the first file
  Imf::Header::setMaxImageSize(kMaxSide, kMaxSide);
  Imf::Header::setMaxTileSize(kMaxTile, kMaxTile);
}

int fail(char *msg, size_t msglen, const char *what) {
  if (msg && msglen) std::snprintf(msg, msglen, "%s", what);
  return -1;
}
} // namespace

extern "C" int el_exr_decode(const char *path, const char *const names[3], int min_x, int min_y, int width,
                             int height, float *rgb, char *msg, size_t msglen) {
  try {
    std::call_once(limits_once, set_limits);
    Imf::InputFile in(path); // a multi-part file: its part 0
    const Imath::Box2i dw = in.header().dataWindow();
    if (dw.min.x != min_x || dw.min.y != min_y || (long long)dw.max.x - dw.min.x + 1 != width ||
        (long long)dw.max.y - dw.min.y + 1 != height)
      return fail(msg, msglen, "the data window reads differently in OpenEXR's C++ library (corrupt header)");
    Imf::FrameBuffer fb;
    for (int c = 0; c < 3; c++) {
      if (!names[c]) continue;
      if (!in.header().channels().findChannel(names[c]))
        return fail(msg, msglen, "a channel is missing in OpenEXR's C++ library's view of the header (corrupt header)");
      // rgb holds the data window: pixel (x, y) of the file is rgb[3 * ((y - min.y) * width + x - min.x)]
      fb.insert(names[c], Imf::Slice::Make(Imf::FLOAT, rgb + c, dw, 3 * sizeof(float), 3 * sizeof(float) * (size_t)width));
    }
    in.setFrameBuffer(fb);
    in.readPixels(dw.min.y, dw.max.y);
    return 0;
  } catch (const std::exception &e) {
    return fail(msg, msglen, e.what());
  } catch (...) {
    return fail(msg, msglen, "unknown OpenEXR error");
  }
}

extern "C" int el_exr_encode(const char *path, const float *pixels, int width, int height, int channels, char *msg,
                             size_t msglen) {
  static const char *const grey[1] = {"Y"}, *const rgba[4] = {"R", "G", "B", "A"};
  const char *const *names = channels == 1 ? grey : rgba;
  if (channels != 1 && channels != 3 && channels != 4) return fail(msg, msglen, "the EXR writer takes 1, 3 or 4 channels");
  try {
    Imf::Header hdr(width, height); // display and data window (0, 0) - (width - 1, height - 1)
    hdr.compression() = Imf::ZIP_COMPRESSION;
    Imf::FrameBuffer fb;
    const size_t xs = sizeof(float) * (size_t)channels;
    for (int c = 0; c < channels; c++) {
      hdr.channels().insert(names[c], Imf::Channel(Imf::FLOAT));
      // Slice takes a char *: the writer only reads through it
      fb.insert(names[c], Imf::Slice(Imf::FLOAT, (char *)(pixels + c), xs, xs * (size_t)width));
    }
    Imf::OutputFile out(path, hdr);
    out.setFrameBuffer(fb);
    out.writePixels(height);
    return 0;
  } catch (const std::exception &e) {
    return fail(msg, msglen, e.what());
  } catch (...) {
    return fail(msg, msglen, "unknown OpenEXR error");
  }
}
