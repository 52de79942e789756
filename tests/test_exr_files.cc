// test_exr_files.cc: el_image_load (examples/common/image_io.c) on OpenEXR files of every kind, written
// here by the reference OpenEXR library itself with explicit settings.
//
//   test_exr_files                  the ctest run
//   test_exr_files --mutations N    N mutated copies of each generated file instead of 8 (a campaign)
// The files go to the working directory and are removed at the end (kept if EL_TEST_KEEP_FILES is set).
//
// 1. Every compression (NONE, RLE, ZIPS, ZIP, PIZ, PXR24, B44, B44A, DWAA, DWAB), scanline and tiled
//    (16 x 8 tiles, partial at the edges of the 37 x 23 image), half, float and uint channels, RGB,
//    RGBA and Y (grey), written by OpenEXR's C++ library, the encoder applications use. (OpenEXRCore
//    3.1.5's encoders were tried first: they have no DWA, store a ZIP chunk whose compressed size
//    equals its raw size without marking it raw -- internal_zip.c tests `>` for `>=` -- so one tile of
//    this image came back as noise, and their B44 files with float channels decode as noise.)
//    The loaded pixels must equal what was written exactly where the compression is lossless; the
//    bounds for the lossy ones:
//      PXR24 on float channels: |error| <= 2^-16 |value| (it keeps 24 of a float's 32 bits: 15 mantissa
//        bits, rounded). Half and uint channels are lossless. Measured: 0.96 of the bound.
//      B44 / B44A on half channels: in half steps (half bit patterns ordered by value), |error| <= 1/32
//        of the 4 x 4 block's range + 1 (B44 stores 6-bit differences from the block's maximum, shifted
//        to fit). Float and uint channels are stored raw. Measured: 0.65 of the bound.
//      DWAA / DWAB (quality 45, OpenEXR's default) on half and float: |error| <= 3% of max(|value|, 1)
//        (DWA quantises in a perceptual space: roughly a constant fraction of the value above 1, of
//        a constant below). uint channels are lossless. Measured: 0.65 of the bound (1.95%).
//    The B44 and DWA bounds are margins over what OpenEXR 3.1.5 gives on this content (printed as
//    fractions of the bound), not guarantees of the formats.
// 2. Layouts: layered channels ("diffuse.R" ...), the default layer preferred to another, a Y-only file
//    with an A, a multi-part file (part 0 read), a MIP-mapped tiled file (level 0), a data window not
//    at the origin; unsupported ones (only Z, luminance/chroma Y RY BY, subsampled, deep) must say
//    "unsupported".
// 3. Broken files: cut at several points, chunk data overwritten, a chunk offset pointing past the
//    end, a bad compression code: each load fails with a message naming the file.
// 4. Hostile headers, checked from the header before OpenEXR allocates: a data window of 2^40 pixels,
//    chunks that would unpack to gigabytes (a 2^24-wide image, 2000 channels, a 65536 x 65536 tile),
//    an offset table longer than the file. In the normal build these run in a child process limited to
//    1 GiB of address space, so an allocation of the announced size would fail and change the message.
// 5. Mutations: each generated file, bytes flipped / replaced / cut / duplicated (seeded), must load
//    or fail with a message naming the file, never crash (the sanitizer build runs this too).
#include "image_io.h"

#include <openexr.h>

#include <ImfChannelList.h>
#include <ImfDeepFrameBuffer.h>
#include <ImfDeepScanLineOutputFile.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfMultiPartOutputFile.h>
#include <ImfOutputFile.h>
#include <ImfOutputPart.h>
#include <ImfPartType.h>
#include <ImfTiledOutputFile.h>
#include <half.h>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <algorithm>
#include <cstring>
#include <string>
#include <vector>

#if defined(__SANITIZE_ADDRESS__)
#define EL_TEST_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define EL_TEST_ASAN 1
#endif
#endif

namespace {

int g_pass = 0, g_fail = 0;
void check(bool ok, const std::string &what) {
  std::printf("%s %s\n", ok ? "PASS" : "FAIL", what.c_str());
  (ok ? g_pass : g_fail)++;
}

const int W = 37, H = 23, TW = 16, TH = 8;
const exr_compression_t kComp[10] = {EXR_COMPRESSION_NONE, EXR_COMPRESSION_RLE,   EXR_COMPRESSION_ZIPS, EXR_COMPRESSION_ZIP,
                                     EXR_COMPRESSION_PIZ,  EXR_COMPRESSION_PXR24, EXR_COMPRESSION_B44,  EXR_COMPRESSION_B44A,
                                     EXR_COMPRESSION_DWAA, EXR_COMPRESSION_DWAB};
const char *const kCompName[10] = {"NONE", "RLE", "ZIPS", "ZIP", "PIZ", "PXR24", "B44", "B44A", "DWAA", "DWAB"};
const char *const kTypeName[3] = {"uint", "half", "float"}; // exr_pixel_type_t order

// The test image: smooth, positive, different in each channel and asymmetric (R grows to the right,
// G downwards, B is a bump off the centre), plus a small ripple so the lossless coders see detail.
// uint channels store round(100 * value).
double value(int c, int x, int y) {
  const double u = (x + 0.5) / W, v = (y + 0.5) / H;
  const double ripple = 0.02 * (((x * 7 + y * 13) % 5) - 2);
  switch (c) {
  case 0: return 0.05 + 3.0 * u * u + ripple;            // R
  case 1: return 0.10 + 1.5 * v + ripple;                // G
  case 2: return 0.20 + 4.0 * std::exp(-8.0 * ((u - 0.3) * (u - 0.3) + (v - 0.6) * (v - 0.6))); // B
  case 3: return 0.25 + 0.5 * u;                         // A
  default: return 0.3 + 2.0 * u * v + ripple;            // Y
  }
}

// One channel's samples in the type it is stored as, row-major W x H.
struct Plane {
  std::string name;
  exr_pixel_type_t type;
  int c; // which value()
  std::vector<uint32_t> u;
  std::vector<half> h;
  std::vector<float> f;
  Plane(const std::string &n, exr_pixel_type_t t, int comp) : name(n), type(t), c(comp) {
    for (int y = 0; y < H; y++)
      for (int x = 0; x < W; x++) {
        const double v = value(c, x, y);
        u.push_back((uint32_t)std::lround(100 * v));
        h.push_back(half((float)v));
        f.push_back((float)v);
      }
  }
  const void *data() const { return type == EXR_PIXEL_UINT ? (const void *)u.data() : type == EXR_PIXEL_HALF ? (const void *)h.data() : (const void *)f.data(); }
  int bytes() const { return type == EXR_PIXEL_HALF ? 2 : 4; }
  double stored(int i) const { return type == EXR_PIXEL_UINT ? (double)u[i] : type == EXR_PIXEL_HALF ? (double)(float)h[i] : (double)f[i]; }
};

std::vector<Plane> planes(const char *layout, exr_pixel_type_t t, const std::string &prefix = "") {
  std::vector<Plane> p;
  if (!std::strcmp(layout, "Y")) p.push_back(Plane(prefix + "Y", t, 4));
  else {
    p.push_back(Plane(prefix + "R", t, 0));
    p.push_back(Plane(prefix + "G", t, 1));
    p.push_back(Plane(prefix + "B", t, 2));
    if (!std::strcmp(layout, "RGBA")) p.push_back(Plane(prefix + "A", t, 3));
  }
  return p;
}

// ---- writing, through OpenEXR's C++ library
Imf::PixelType imf_type(exr_pixel_type_t t) { return t == EXR_PIXEL_UINT ? Imf::UINT : t == EXR_PIXEL_HALF ? Imf::HALF : Imf::FLOAT; }
Imf::Compression imf_comp(exr_compression_t c) { return (Imf::Compression)(int)c; } // the same numbering (the file format's)

Imf::FrameBuffer frame_buffer(Imf::Header &hdr, const std::vector<Plane> &ps, bool add_channels = true) {
  Imf::FrameBuffer fb;
  for (size_t c = 0; c < ps.size(); c++) {
    if (add_channels) hdr.channels().insert(ps[c].name, Imf::Channel(imf_type(ps[c].type)));
    fb.insert(ps[c].name, Imf::Slice(imf_type(ps[c].type), (char *)ps[c].data(), (size_t)ps[c].bytes(), (size_t)ps[c].bytes() * W));
  }
  return fb;
}

bool imf_write(const char *path, const std::vector<Plane> &ps, exr_compression_t comp, bool tiled,
               Imf::LevelMode levels = Imf::ONE_LEVEL) {
  try {
    Imf::Header hdr(W, H);
    hdr.compression() = imf_comp(comp);
    Imf::FrameBuffer fb = frame_buffer(hdr, ps);
    if (tiled) {
      hdr.setTileDescription(Imf::TileDescription(TW, TH, levels));
      Imf::TiledOutputFile out(path, hdr);
      out.setFrameBuffer(fb);
      out.writeTiles(0, out.numXTiles(0) - 1, 0, out.numYTiles(0) - 1, 0); // level 0; others stay empty
      if (levels != Imf::ONE_LEVEL) // the other levels: whatever, the loader reads level 0
        for (int l = 1; l < out.numLevels(); l++) // smaller: the same slices, read partly
          out.writeTiles(0, out.numXTiles(l) - 1, 0, out.numYTiles(l) - 1, l);
    } else {
      Imf::OutputFile out(path, hdr);
      out.setFrameBuffer(fb);
      out.writePixels(H);
    }
    return true;
  } catch (const std::exception &e) {
    std::printf("  OpenEXR: %s\n", e.what());
    return false;
  }
}

// ---- reading back
struct Loaded {
  int r;
  el_image img;
  char err[512];
  explicit Loaded(const char *path) {
    err[0] = 0;
    r = el_image_load(path, &img, err, sizeof err);
  }
  ~Loaded() {
    if (r == 0) el_image_free(&img);
  }
};

// A half's bits as an integer that grows with the value (B44 works on these).
int ordered(float v) {
  const unsigned short b = half(v).bits();
  return (b & 0x8000) ? 0x7fff - (b & 0x7fff) : 0x8000 + b;
}

// The largest error divided by its bound (<= 1 passes). kind: 0 exact; 1 PXR24: 2^-16 |value| on float
// channels; 2 B44: on half channels, 1/32 of the 4 x 4 block's range in half steps (ordered() units)
// plus one step; 3 DWA: 3% of max(|value|, 1) on half and float channels. Other cases exact.
double worst_error(const el_image &img, const std::vector<Plane> &ps, int kind, int x0 = 0, int y0 = 0) {
  double worst = 0;
  const bool grey = ps[0].name[ps[0].name.size() - 1] == 'Y';
  for (int c = 0; c < 3; c++) {
    const Plane &p = ps[grey ? 0 : c];
    for (int y = 0; y < H; y++)
      for (int x = 0; x < W; x++) {
        const int i = y * W + x;
        const double want = p.stored(i), got = img.pixels[3 * ((size_t)(y + y0) * img.width + (x + x0)) + c];
        double e = std::fabs(got - want), bound = 0;
        if (kind == 1 && p.type == EXR_PIXEL_FLOAT) bound = std::ldexp(std::fabs(want), -16);
        if (kind == 2 && p.type == EXR_PIXEL_HALF) {
          int lo = 1 << 30, hi = -1;
          for (int by = y / 4 * 4; by < y / 4 * 4 + 4 && by < H; by++)
            for (int bx = x / 4 * 4; bx < x / 4 * 4 + 4 && bx < W; bx++) {
              lo = std::min(lo, ordered((float)p.stored(by * W + bx)));
              hi = std::max(hi, ordered((float)p.stored(by * W + bx)));
            }
          e = std::abs(ordered((float)got) - ordered((float)want));
          bound = (hi - lo) / 32.0 + 1;
        }
        if (kind == 3 && p.type != EXR_PIXEL_UINT) bound = 0.03 * std::fmax(std::fabs(want), 1.0);
        if (got != got) return 1e30;
        worst = std::fmax(worst, bound > 0 ? e / bound : e > 0 ? 1e30 : 0);
      }
  }
  return worst;
}
double rel_error(const el_image &img, const std::vector<Plane> &ps) { // the largest |error| / |value|
  double worst = 0;
  const bool grey = ps.size() == 1;
  for (int c = 0; c < 3; c++)
    for (int i = 0; i < W * H; i++) {
      const double want = ps[grey ? 0 : c].stored(i);
      worst = std::fmax(worst, std::fabs(img.pixels[3 * (size_t)i + c] - want) / std::fabs(want));
    }
  return worst;
}

// the message names the file and has kw after the name
bool says(const Loaded &in, const std::string &path, const char *kw) {
  const char *named = std::strstr(in.err, path.c_str());
  return in.r != 0 && named && std::strstr(named + path.size(), kw);
}

int kind_of(int comp) { return comp == 5 ? 1 : comp == 6 || comp == 7 ? 2 : comp >= 8 ? 3 : 0; }

std::vector<std::string> g_written; // every file this test wrote, removed at the end
std::string tmp(const std::string &name) {
  const std::string p = "test_exr_files_" + name + ".exr";
  if (std::find(g_written.begin(), g_written.end(), p) == g_written.end()) g_written.push_back(p);
  return p;
}
std::vector<std::string> g_files; // the generated valid files, for the mutations

// 1. every compression x storage x pixel type x layout
void test_compressions() {
  static const char *const layouts[3] = {"RGB", "RGBA", "Y"};
  double lossy_max[10] = {0};
  for (int comp = 0; comp < 10; comp++)
    for (int tiled = 0; tiled < 2; tiled++)
      for (int t = 0; t < 3; t++)
        for (int l = 0; l < 3; l++) {
          if (t == EXR_PIXEL_UINT && l != 0) continue; // uint: RGB only
          const std::vector<Plane> ps = planes(layouts[l], (exr_pixel_type_t)t);
          const std::string what = std::string(kCompName[comp]) + (tiled ? " tiled " : " scanline ") + kTypeName[t] + " " + layouts[l];
          const std::string path = tmp(std::string(kCompName[comp]) + (tiled ? "_tiled_" : "_scan_") + kTypeName[t] + "_" + layouts[l]);
          if (!imf_write(path.c_str(), ps, kComp[comp], tiled != 0)) {
            check(false, what + ": written by OpenEXR");
            continue;
          }
          g_files.push_back(path);
          Loaded in(path.c_str());
          if (in.r != 0 || in.img.width != W || in.img.height != H || in.img.channels != 3) {
            check(false, what + " loads as 37 x 23 RGB (" + (in.r ? in.err : "wrong size") + ")");
            continue;
          }
          const int kind = kind_of(comp);
          const double e = worst_error(in.img, ps, kind);
          if (kind && t != EXR_PIXEL_UINT) lossy_max[comp] = std::fmax(lossy_max[comp], rel_error(in.img, ps));
          char buf[64];
          std::snprintf(buf, sizeof buf, " (%.2f of the bound)", e);
          check(e <= 1, what + (kind == 0 || e == 0 ? " loads exactly" : " loads within the bound") + (kind && e > 0 ? buf : ""));
        }
  for (int comp = 5; comp < 10; comp++)
    std::printf("  %s, largest relative error on half/float channels: %.3g\n", kCompName[comp], lossy_max[comp]);
}

// 2. layouts
void test_layouts() {
  { // layered: the default layer is preferred; without one, the first layer (alphabetically) with R, G, B
    std::vector<Plane> ps = planes("RGB", EXR_PIXEL_HALF, "diffuse.");
    std::vector<Plane> other = planes("RGB", EXR_PIXEL_HALF, "spec.");
    for (size_t i = 0; i < other.size(); i++) { other[i].c = (other[i].c + 1) % 3; other[i] = Plane(other[i].name, EXR_PIXEL_HALF, other[i].c); }
    std::vector<Plane> both = ps;
    both.insert(both.end(), other.begin(), other.end());
    const std::string path = tmp("layered");
    check(imf_write(path.c_str(), both, EXR_COMPRESSION_ZIP, false), "layered file (diffuse.R/G/B, spec.R/G/B) written");
    Loaded in(path.c_str());
    check(in.r == 0 && worst_error(in.img, ps, 0) == 0, std::string("layered channels: diffuse.R, G, B are read (") + (in.r ? in.err : "ok") + ")");
    std::vector<Plane> with_default = planes("RGB", EXR_PIXEL_FLOAT);
    with_default.insert(with_default.end(), other.begin(), other.end());
    const std::string p2 = tmp("layered_default");
    imf_write(p2.c_str(), with_default, EXR_COMPRESSION_PIZ, true);
    Loaded in2(p2.c_str());
    std::vector<Plane> def(with_default.begin(), with_default.begin() + 3);
    check(in2.r == 0 && worst_error(in2.img, def, 0) == 0, "R, G, B and spec.R, G, B: the default layer's R, G, B are read");
    g_files.push_back(path);
  }
  { // Y with an alpha channel: grey
    std::vector<Plane> ps = planes("Y", EXR_PIXEL_FLOAT);
    ps.push_back(Plane("A", EXR_PIXEL_HALF, 3));
    const std::string path = tmp("YA");
    imf_write(path.c_str(), ps, EXR_COMPRESSION_RLE, false);
    Loaded in(path.c_str());
    std::vector<Plane> y(ps.begin(), ps.begin() + 1);
    check(in.r == 0 && worst_error(in.img, y, 0) == 0, std::string("Y and A: grey from Y in all three channels (") + (in.r ? in.err : "ok") + ")");
  }
  { // a data window that does not start at the origin (the display window is larger)
    const std::string path = tmp("window");
    const std::vector<Plane> ps = planes("RGB", EXR_PIXEL_FLOAT);
    try {
      Imath::Box2i display(Imath::V2i(0, 0), Imath::V2i(99, 99)), data(Imath::V2i(-5, 40), Imath::V2i(-5 + W - 1, 40 + H - 1));
      Imf::Header hdr(display, data);
      hdr.compression() = Imf::ZIP_COMPRESSION;
      Imf::FrameBuffer fb;
      for (size_t c = 0; c < ps.size(); c++) {
        hdr.channels().insert(ps[c].name, Imf::Channel(Imf::FLOAT));
        fb.insert(ps[c].name, Imf::Slice::Make(Imf::FLOAT, ps[c].data(), data, 4, 4 * W));
      }
      Imf::OutputFile out(path.c_str(), hdr);
      out.setFrameBuffer(fb);
      out.writePixels(H);
    } catch (const std::exception &e) { std::printf("  %s\n", e.what()); }
    Loaded in(path.c_str());
    check(in.r == 0 && in.img.width == W && in.img.height == H && worst_error(in.img, ps, 0) == 0,
          "data window (-5, 40) - (31, 62): its pixels, row 0 at its top");
  }
  { // multi-part: part 0 is read
    const std::string path = tmp("multipart");
    const std::vector<Plane> p0 = planes("RGB", EXR_PIXEL_HALF), p1 = planes("Y", EXR_PIXEL_FLOAT);
    try {
      std::vector<Imf::Header> hs(2, Imf::Header(W, H));
      hs[0].setName("beauty"); hs[0].setType(Imf::SCANLINEIMAGE); hs[0].compression() = Imf::PIZ_COMPRESSION;
      hs[1].setName("depth"); hs[1].setType(Imf::SCANLINEIMAGE); hs[1].compression() = Imf::ZIP_COMPRESSION;
      Imf::FrameBuffer f0 = frame_buffer(hs[0], p0), f1 = frame_buffer(hs[1], p1);
      Imf::MultiPartOutputFile out(path.c_str(), hs.data(), 2);
      Imf::OutputPart a(out, 0), b(out, 1);
      a.setFrameBuffer(f0); a.writePixels(H);
      b.setFrameBuffer(f1); b.writePixels(H);
    } catch (const std::exception &e) { std::printf("  %s\n", e.what()); }
    Loaded in(path.c_str());
    check(in.r == 0 && worst_error(in.img, p0, 0) == 0, std::string("multi-part file: part 0 (RGB) is read (") + (in.r ? in.err : "ok") + ")");
    g_files.push_back(path);
  }
  { // MIP-mapped tiles: level 0
    const std::string path = tmp("mipmap");
    const std::vector<Plane> ps = planes("RGB", EXR_PIXEL_HALF);
    imf_write(path.c_str(), ps, EXR_COMPRESSION_ZIP, true, Imf::MIPMAP_LEVELS);
    Loaded in(path.c_str());
    check(in.r == 0 && worst_error(in.img, ps, 0) == 0, std::string("MIP-mapped tiled file: level 0 is read (") + (in.r ? in.err : "ok") + ")");
    g_files.push_back(path);
  }
  // unsupported layouts
  struct { const char *name, *chans; } bad[3] = {{"Z", "Z"}, {"YC", "Y RY BY"}, {"ZA", "A Z"}};
  for (int k = 0; k < 3; k++) {
    std::vector<Plane> ps;
    char names[16];
    std::snprintf(names, sizeof names, "%s", bad[k].chans);
    for (char *t = std::strtok(names, " "); t; t = std::strtok(NULL, " ")) ps.push_back(Plane(t, EXR_PIXEL_HALF, 4));
    const std::string path = tmp(std::string("unsupported_") + bad[k].name);
    imf_write(path.c_str(), ps, EXR_COMPRESSION_ZIP, false);
    Loaded in(path.c_str());
    check(says(in, path, "unsupported"),
          std::string("channels ") + bad[k].chans + ": \"unsupported\", naming the file (" + in.err + ")");
  }
  { // subsampled chroma-style channel
    const std::string path = tmp("subsampled");
    try {
      Imf::Header hdr(W + 1, H + 1); // even sizes for 2 x 2 sampling
      hdr.channels().insert("R", Imf::Channel(Imf::HALF, 2, 2));
      hdr.channels().insert("G", Imf::Channel(Imf::HALF));
      hdr.channels().insert("B", Imf::Channel(Imf::HALF));
      Imf::OutputFile out(path.c_str(), hdr); // no pixels: the loader refuses from the header
    } catch (const std::exception &e) { std::printf("  %s\n", e.what()); }
    Loaded in(path.c_str());
    check(says(in, path, "unsupported") && says(in, path, "subsampled"),
          std::string("a 2 x 2 subsampled R: \"unsupported\" (") + in.err + ")");
  }
  { // deep, with R, G, B channels
    const std::string path = tmp("deep");
    try {
      Imf::Header hdr(4, 2);
      hdr.channels().insert("R", Imf::Channel(Imf::FLOAT));
      hdr.channels().insert("G", Imf::Channel(Imf::FLOAT));
      hdr.channels().insert("B", Imf::Channel(Imf::FLOAT));
      hdr.setType(Imf::DEEPSCANLINE);
      hdr.compression() = Imf::ZIPS_COMPRESSION;
      Imf::DeepScanLineOutputFile out(path.c_str(), hdr);
      std::vector<unsigned int> counts(8, 1);
      std::vector<float> z(8, 1.0f);
      std::vector<float *> zp(8);
      for (int i = 0; i < 8; i++) zp[i] = &z[i];
      Imf::DeepFrameBuffer fb;
      fb.insertSampleCountSlice(Imf::Slice(Imf::UINT, (char *)counts.data(), sizeof(unsigned), 4 * sizeof(unsigned)));
      for (const char *n : {"R", "G", "B"})
        fb.insert(n, Imf::DeepSlice(Imf::FLOAT, (char *)zp.data(), sizeof(float *), 4 * sizeof(float *), sizeof(float)));
      out.setFrameBuffer(fb);
      out.writePixels(2);
    } catch (const std::exception &e) { std::printf("  %s\n", e.what()); }
    Loaded in(path.c_str());
    check(says(in, path, "unsupported") && says(in, path, "deep image"),
          std::string("a deep scanline file with R, G, B: \"unsupported\" (") + in.err + ")");
  }
}

// ---- byte surgery
std::vector<unsigned char> read_all(const std::string &path) {
  std::vector<unsigned char> b;
  FILE *f = std::fopen(path.c_str(), "rb");
  if (!f) return b;
  int ch;
  while ((ch = std::fgetc(f)) != EOF) b.push_back((unsigned char)ch);
  std::fclose(f);
  return b;
}
void write_all(const std::string &path, const std::vector<unsigned char> &b) {
  FILE *f = std::fopen(path.c_str(), "wb");
  if (!f) return;
  if (!b.empty()) std::fwrite(b.data(), 1, b.size(), f);
  std::fclose(f);
}
// the position of attribute `name`'s value (after name NUL type NUL int32 size), or 0
size_t attr_value(const std::vector<unsigned char> &b, const char *name) {
  const size_t n = std::strlen(name);
  for (size_t at = 8; at + n + 1 < b.size(); at++)
    if (!std::memcmp(&b[at], name, n + 1)) {
      size_t t = at + n + 1;
      while (t < b.size() && b[t]) t++;
      return t + 1 + 4;
    }
  return 0;
}
size_t header_end(const std::vector<unsigned char> &b, int chunks) { // the offset table's position
  for (size_t k = 8; k + 8 <= b.size(); k++) {
    uint64_t v = 0;
    for (int i = 7; i >= 0; i--) v = (v << 8) | b[k + (size_t)i];
    if (v == k + 8 * (uint64_t)chunks) return k;
  }
  return 0;
}
void put32(std::vector<unsigned char> &b, size_t at, int32_t v) {
  for (int i = 0; i < 4; i++) b[at + (size_t)i] = (unsigned char)((uint32_t)v >> (8 * i));
}

// the load fails with a message that names the file and has kw after the name
void expect_error(const std::string &path, const char *kw, const std::string &what) {
  Loaded in(path.c_str());
  const char *named = std::strstr(in.err, path.c_str());
  check(in.r != 0 && named && (!kw || std::strstr(named + path.size(), kw)) && in.img.pixels == NULL,
        what + ": an error naming the file" + (kw ? std::string(" and '") + kw + "'" : std::string()) + " (" + (in.r ? in.err : "loaded") + ")");
}

// 3. broken files
void test_broken() {
  const std::vector<Plane> ps = planes("RGB", EXR_PIXEL_HALF);
  const char *const srcs[3] = {"ZIP_scan", "PIZ_tiled", "DWAB_scan"};
  for (int s = 0; s < 3; s++) {
    const std::string src = tmp(std::string(srcs[s]) + "_half_RGB");
    const std::vector<unsigned char> b = read_all(src);
    if (b.size() < 100) { check(false, src + " exists"); continue; }
    const size_t cuts[4] = {20, b.size() / 2, b.size() - 1, (size_t)attr_value(b, "channels")};
    for (int k = 0; k < 4; k++) {
      const std::string cut = tmp(std::string("cut_") + srcs[s]);
      write_all(cut, std::vector<unsigned char>(b.begin(), b.begin() + (long)cuts[k]));
      char what[160];
      std::snprintf(what, sizeof what, "%s cut to %zu of %zu bytes", srcs[s], cuts[k], b.size());
      expect_error(cut, k == 1 || k == 2 ? "truncated" : "EXR", what);
    }
  }
  { // ZIP scanline: the zlib data of the first chunk overwritten
    std::vector<unsigned char> b = read_all(tmp("ZIP_scan_half_RGB"));
    const size_t table = header_end(b, (H + 15) / 16);
    if (table) {
      uint64_t off = 0;
      for (int i = 7; i >= 0; i--) off = (off << 8) | b[table + (size_t)i];
      for (size_t i = (size_t)off + 8; i < (size_t)off + 8 + 16 && i < b.size(); i++) b[i] = 0xA5;
      write_all(tmp("corrupt_zip"), b);
      expect_error(tmp("corrupt_zip"), NULL, "a ZIP chunk's data overwritten");
      // the second chunk's offset pointing past the end of the file
      const uint64_t past = b.size() + 1000;
      for (int i = 0; i < 8; i++) b[table + 8 + (size_t)i] = (unsigned char)(past >> (8 * i));
      write_all(tmp("corrupt_offset"), b);
      expect_error(tmp("corrupt_offset"), "chunk 2 of 2", "a chunk offset past the end of the file");
    } else check(false, "the ZIP file's offset table found");
  }
  { // a compression code OpenEXR does not know
    std::vector<unsigned char> b = read_all(tmp("ZIP_scan_half_RGB"));
    const size_t at = attr_value(b, "compression");
    if (at) b[at] = 42;
    write_all(tmp("corrupt_compression"), b);
    expect_error(tmp("corrupt_compression"), "unsupported", "compression code 42");
  }
  { // not an EXR, and empty
    write_all(tmp("not_exr"), std::vector<unsigned char>(64, 'x'));
    expect_error(tmp("not_exr"), "not an OpenEXR", "64 bytes of 'x'");
  }
}

// 4. hostile headers: refused from the header. Runs in a child process with 1 GiB of address space
// (not under AddressSanitizer, which reserves terabytes of shadow memory).
void hostile_one(const std::string &path, const char *kw, const std::string &what) {
#ifndef EL_TEST_ASAN
  std::fflush(stdout);
  const pid_t pid = fork();
  if (pid == 0) {
    struct rlimit lim;
    lim.rlim_cur = lim.rlim_max = (rlim_t)1 << 30;
    setrlimit(RLIMIT_AS, &lim);
    g_pass = g_fail = 0;
    expect_error(path, kw, what + " (1 GiB address space)");
    std::fflush(stdout);
    _exit(g_fail ? 1 : 0);
  }
  int st = 0;
  waitpid(pid, &st, 0);
  check(WIFEXITED(st) && WEXITSTATUS(st) == 0, what + ": the child process passed");
#else
  expect_error(path, kw, what);
#endif
}

void test_hostile() {
  const std::vector<Plane> ps = planes("RGB", EXR_PIXEL_FLOAT);
  std::vector<unsigned char> b = read_all(tmp("ZIP_scan_float_RGB"));
  const size_t dw = attr_value(b, "dataWindow"), disp = attr_value(b, "displayWindow");
  if (!dw || !disp) { check(false, "the dataWindow attribute found"); return; }
  { // 2^20 x 2^20 pixels
    std::vector<unsigned char> c = b;
    put32(c, dw + 8, (1 << 20) - 1); put32(c, dw + 12, (1 << 20) - 1);
    write_all(tmp("hostile_window"), c);
    hostile_one(tmp("hostile_window"), "too large", "a data window of 2^20 x 2^20 pixels");
  }
  { // 2^24 x 16 pixels (2^28, allowed): a ZIP chunk of 16 lines would unpack to 3 GiB
    std::vector<unsigned char> c = b;
    put32(c, dw + 8, (1 << 24) - 1); put32(c, dw + 12, 15);
    write_all(tmp("hostile_chunk"), c);
    hostile_one(tmp("hostile_chunk"), "too large", "2^24 x 16 pixels, 12-byte pixels, 16 lines a chunk");
  }
  { // 1 x 2^28 pixels, uncompressed: 2^28 chunks, an offset table of 2 GiB in a small file
    std::vector<unsigned char> c = read_all(tmp("NONE_scan_float_RGB"));
    const size_t d = attr_value(c, "dataWindow");
    put32(c, d + 8, 0); put32(c, d + 12, (1 << 28) - 1);
    write_all(tmp("hostile_table"), c);
    hostile_one(tmp("hostile_table"), "truncated", "1 x 2^28 pixels, one line a chunk: a 2 GiB offset table");
  }
  { // 2000 channels on a 2^20-wide window: 2000 x 4 bytes x 2^20 x 16 lines a chunk
    std::vector<Plane> many;
    for (int k = 0; k < 2000; k++) {
      char n[16];
      std::snprintf(n, sizeof n, "c%04d", k);
      many.push_back(Plane(n, EXR_PIXEL_FLOAT, 0));
    }
    many.push_back(Plane("R", EXR_PIXEL_FLOAT, 0)); many.push_back(Plane("G", EXR_PIXEL_FLOAT, 1)); many.push_back(Plane("B", EXR_PIXEL_FLOAT, 2));
    const std::string src = tmp("many_channels");
    if (imf_write(src.c_str(), many, EXR_COMPRESSION_ZIP, false)) {
      Loaded ok(src.c_str());
      check(ok.r == 0 && worst_error(ok.img, std::vector<Plane>(many.end() - 3, many.end()), 0) == 0, "2003 channels, 37 x 23: R, G, B load");
      std::vector<unsigned char> c = read_all(src);
      const size_t d = attr_value(c, "dataWindow");
      put32(c, d + 8, (1 << 20) - 1); put32(c, d + 12, 15);
      write_all(tmp("hostile_channels"), c);
      hostile_one(tmp("hostile_channels"), "too large", "2003 float channels on a 2^20 x 16 window");
    } else check(false, "2003 channels written");
  }
  { // a 65536 x 65536 tile
    std::vector<unsigned char> c = read_all(tmp("ZIP_tiled_float_RGB"));
    const size_t t = attr_value(c, "tiles");
    if (t) { put32(c, t, 65536); put32(c, t + 4, 65536); }
    write_all(tmp("hostile_tile"), c);
    hostile_one(tmp("hostile_tile"), t ? "too large" : "x", "65536 x 65536 tiles of 12-byte pixels");
  }
}

// 5. mutations
uint64_t g_rng = 0;
uint64_t rnd() { // splitmix64
  uint64_t z = (g_rng += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}
void test_mutations(int per_file) {
  long loaded = 0, failed = 0, bad = 0;
  for (size_t f = 0; f < g_files.size(); f++) {
    const std::vector<unsigned char> src = read_all(g_files[f]);
    for (int m = 0; m < per_file; m++) {
      g_rng = 0x5eed0000ULL + f * 1000003ULL + (uint64_t)m;
      std::vector<unsigned char> b = src;
      const int edits = 1 + (int)(rnd() % 4);
      for (int e = 0; e < edits && !b.empty(); e++) {
        const size_t at = (size_t)(rnd() % b.size());
        switch (rnd() % 6) {
        case 0: b[at] ^= (unsigned char)(1u << (rnd() % 8)); break;
        case 1: b[at] = (unsigned char)rnd(); break;
        case 2: { static const unsigned char v[6] = {0, 0xff, 0x7f, 0x80, 0x01, 0xfe}; b[at] = v[rnd() % 6]; break; }
        case 3: b.resize(at + 1); break;
        case 4: { const size_t n = 1 + (size_t)(rnd() % 16); if (at + n <= b.size()) b.insert(b.begin() + (long)at, b.begin() + (long)at, b.begin() + (long)(at + n)); break; }
        default: if (at + 4 <= b.size()) put32(b, at, (int32_t)(rnd() % 3 == 0 ? 0x7fffffff : (int32_t)rnd())); break;
        }
      }
      const std::string path = tmp("mutated");
      write_all(path, b);
      Loaded in(path.c_str());
      if (in.r == 0) {
        loaded++;
        if (in.img.width < 1 || in.img.height < 1 || in.img.channels != 3 || !in.img.pixels) bad++;
      } else {
        failed++;
        if (!std::strstr(in.err, path.c_str())) {
          bad++;
          std::printf("  mutation %d of %s: the message does not name the file: %s\n", m, g_files[f].c_str(), in.err);
        }
      }
    }
  }
  char buf[200];
  std::snprintf(buf, sizeof buf, "%ld mutated copies of %zu files: %ld load, %ld fail with a message naming the file, %ld bad",
                loaded + failed, g_files.size(), loaded, failed, bad);
  check(bad == 0, buf);
}

} // namespace

int main(int argc, char **argv) {
  int per_file = 8;
  for (int i = 1; i < argc; i++) {
    if (!std::strcmp(argv[i], "--mutations") && i + 1 < argc) per_file = std::atoi(argv[++i]);
    else { std::printf("usage: test_exr_files [--mutations N]\n"); return 2; }
  }
  test_compressions();
  test_layouts();
  test_broken();
  test_hostile();
  test_mutations(per_file);
  if (!std::getenv("EL_TEST_KEEP_FILES")) for (size_t i = 0; i < g_written.size(); i++) std::remove(g_written[i].c_str());
  std::printf("test_exr_files: %d passed, %d failed\n", g_pass, g_fail);
  return g_fail ? 1 : 0;
}
