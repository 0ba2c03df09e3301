// Texture images: PNG and JPEG through stb_image (Debian's libstb-dev), EXR through OpenEXR,
// decoded to linear RGBA floats (host/scene/texture_desc.h).
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfIO.h>
#include <ImfInputFile.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>

// stb_image's implementation is compiled in host/scene/stb_image_impl.cpp, with the same
// configuration (PNG and JPEG only, no stdio: files are read here, so every error path is ours).
#define STBI_ONLY_PNG
#define STBI_ONLY_JPEG
#define STBI_NO_STDIO
#include <stb/stb_image.h>

#include "host/film/image_io.h"
#include "host/scene/texture_desc.h"

namespace aw {
namespace {

// The IEC 61966-2-1 (sRGB) decoding curve, exact in double.
double srgb_to_linear(double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }

// An EXR held in memory, for OpenEXR's reader (EXRs embedded in a .glb come this way too).
class MemoryIStream : public Imf::IStream {
 public:
  MemoryIStream(const unsigned char* data, size_t size) : Imf::IStream("memory"), data_(data), size_(size) {}
  bool read(char c[], int n) override {
    // (Not pos_ + n > size_: a corrupt offset table seeks anywhere, even to 2^64 - 1, where
    // that sum wraps around and lets the read through; fuzz_image found it.)
    if (n < 0 || pos_ > size_ || uint64_t(n) > size_ - pos_) throw std::runtime_error("the EXR data is truncated");
    std::memcpy(c, data_ + pos_, size_t(n));
    pos_ += uint64_t(n);
    return pos_ < size_;
  }
  uint64_t tellg() override { return pos_; }
  void seekg(uint64_t pos) override { pos_ = pos; }

 private:
  const unsigned char* data_;
  uint64_t size_;
  uint64_t pos_ = 0;
};

// Decoded images larger than this are refused before they are decoded: 16k x 16k texels at
// 4 floats each is 4 GiB of host memory already (the device's copy, packed, is smaller;
// host/render/texture_pack.h).
constexpr uint64_t kMaxTexels = uint64_t(16384) * 16384;
// More than any EXR compression method achieves on real images (see decode_exr).
constexpr uint64_t kMaxExrCompression = 2048;

bool check_size(int w, int h, std::string* error) {
  if (w <= 0 || h <= 0) {
    *error = "the image has no texels (" + std::to_string(w) + " x " + std::to_string(h) + ")";
    return false;
  }
  if (uint64_t(w) * uint64_t(h) > kMaxTexels) {
    *error = "the image is " + std::to_string(w) + " x " + std::to_string(h) +
             " texels, more than the 16384 x 16384 a texture may have";
    return false;
  }
  return true;
}

bool decode_exr(const unsigned char* bytes, size_t size, TextureDesc* t, std::string* error) {
  std::string why;
  if (!exr_header_sizes_fit(bytes, size, size, &why)) {
    *error = why;
    return false;
  }
  try {
    MemoryIStream stream(bytes, size);
    Imf::InputFile in(stream, 1);
    const Imath::Box2i dw = in.header().dataWindow();
    const int w = dw.max.x - dw.min.x + 1, h = dw.max.y - dw.min.y + 1;
    if (!check_size(w, h, error)) return false;
    const Imf::ChannelList& ch = in.header().channels();
    // The texels are allocated before any is read, so a damaged header that claims a large
    // window in a small file would cost gigabytes (fuzz_image, 2026-12-07: 2.4 GB for a
    // 752-byte file). The file's pixel data, compressed, must still hold that window: no EXR
    // compression reaches kMaxExrCompression (deflate's own limit is about 1032:1, RLE's 64:1),
    // so a window whose uncompressed channels exceed the file's size times that is refused.
    uint64_t texel_bytes = 0;
    for (Imf::ChannelList::ConstIterator c = ch.begin(); c != ch.end(); ++c)
      texel_bytes += c.channel().type == Imf::HALF ? 2u : 4u;
    const uint64_t pixel_bytes = uint64_t(w) * uint64_t(h) * texel_bytes;
    if (pixel_bytes > uint64_t(size) * kMaxExrCompression) {
      *error = "the EXR's data window (" + std::to_string(w) + " x " + std::to_string(h) + " texels) needs " +
               std::to_string(pixel_bytes) + " bytes of pixels, more than its " + std::to_string(size) +
               " bytes can hold at any EXR compression (a damaged header)";
      return false;
    }
    const bool has_rgb = ch.findChannel("R") && ch.findChannel("G") && ch.findChannel("B");
    const bool has_y = ch.findChannel("Y") != nullptr;
    const bool has_a = ch.findChannel("A") != nullptr;
    if (!has_rgb && !has_y) {
      *error = "the EXR has neither R, G, B nor Y channels";
      return false;
    }
    t->width = w;
    t->height = h;
    t->channels = (has_rgb ? 3 : 1) + (has_a ? 1 : 0);
    t->eight_bit = false;
    t->texels.assign(size_t(w) * size_t(h) * 4, 1.0f);
    Imf::FrameBuffer fb;
    // OpenEXR addresses texel (x, y) as base + x * xs + y * ys in data-window coordinates, so
    // base lies before the buffer by the window's origin. That offset is taken on integers
    // (wrapping, defined): as pointer arithmetic it overflows for a window far from the origin,
    // which is undefined (UBSan, fuzz_image, 2026-12-05).
    const uintptr_t origin = uintptr_t(int64_t(dw.min.y) * w + dw.min.x) * 4u * sizeof(float);
    float* base = reinterpret_cast<float*>(reinterpret_cast<uintptr_t>(t->texels.data()) - origin);
    const size_t xs = 4 * sizeof(float), ys = size_t(w) * 4 * sizeof(float);
    if (has_rgb) {
      fb.insert("R", Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(base + 0), xs, ys, 1, 1, 0.0));
      fb.insert("G", Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(base + 1), xs, ys, 1, 1, 0.0));
      fb.insert("B", Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(base + 2), xs, ys, 1, 1, 0.0));
    } else {
      fb.insert("Y", Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(base + 0), xs, ys, 1, 1, 0.0));
    }
    if (has_a) fb.insert("A", Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(base + 3), xs, ys, 1, 1, 1.0));
    in.setFrameBuffer(fb);
    in.readPixels(dw.min.y, dw.max.y);
    for (size_t i = 0; i < size_t(w) * size_t(h); ++i) {
      float* p = &t->texels[i * 4];
      if (!has_rgb) p[1] = p[2] = p[0];
      for (int c = 0; c < 4; ++c) {
        if (!std::isfinite(p[c])) {
          *error = "texel (" + std::to_string(i % size_t(w)) + ", " + std::to_string(i / size_t(w)) +
                   ") is not a finite number";
          return false;
        }
      }
    }
    // EXR holds linear values; an sRGB colour space on an EXR is honoured all the same.
    if (t->colorspace == TextureDesc::ColorSpace::Srgb) {
      for (size_t i = 0; i < t->texels.size(); ++i)
        if (i % 4 != 3) t->texels[i] = float(srgb_to_linear(t->texels[i]));
    }
    return true;
  } catch (const std::exception& e) {
    *error = std::string("not a readable EXR: ") + e.what();
    return false;
  }
}

// stb_image 2.27 (Debian 12) trusts a JPEG Huffman table's sixteen code-length counts: their
// sum may reach 16 x 255 = 4,080 where a table holds 256 symbols (ITU-T T.81 §B.2.4.2: 8-bit
// symbols, so at most 256 codes), and stbi__build_huffman and the symbol copy then write past
// the table (found by tests/fuzz, fuzz_image under UBSan, 2026-12-02). Every DHT segment is
// checked here before stb_image sees the file: the markers are walked by their lengths, and the
// entropy-coded data after a scan header is skipped to the next marker (a 0xFF not followed by
// a stuffed 0x00 or a restart marker). Anything else malformed is left to stb_image to refuse.
bool jpeg_huffman_tables_fit(const unsigned char* b, size_t n, std::string* why) {
  // stb_image takes any run of 0xFF fill bytes before a marker, the first one included.
  size_t i = 0;
  while (i < n && b[i] == 0xFF) ++i;
  if (i == 0 || i >= n || b[i] != 0xD8) return true;  // not a JPEG
  ++i;
  while (i + 1 < n) {
    if (b[i] != 0xFF) {  // entropy-coded data
      ++i;
      continue;
    }
    const unsigned m = b[i + 1];
    if (m == 0xFF) {  // a fill byte before a marker
      ++i;
      continue;
    }
    if (m == 0x00 || m == 0x01 || (m >= 0xD0 && m <= 0xD8)) {  // stuffed 0xFF, TEM, RSTn, SOI: no length
      i += 2;
      continue;
    }
    if (m == 0xD9 || i + 3 >= n) return true;  // EOI, or the file ends
    const size_t len = (size_t(b[i + 2]) << 8) | size_t(b[i + 3]);
    if (m == 0xC4) {
      // As stb_image reads the segment: tables while the declared length lasts, even when the
      // last one runs past the segment's end (bytes past the file's end read as 0).
      auto at = [&](size_t p) -> size_t { return p < n ? b[p] : 0; };
      int64_t left = int64_t(len) - 2;
      for (size_t p = i + 4; left > 0;) {
        size_t codes = 0;
        for (size_t k = 1; k <= 16; ++k) codes += at(p + k);
        if (codes > 256) {
          *why = "a corrupt JPEG: a Huffman table declares " + std::to_string(codes) + " codes, at most 256 exist";
          return false;
        }
        p += 17 + codes;
        left -= int64_t(17 + codes);
      }
    }
    i += 2 + std::max<size_t>(len, 2);
  }
  return true;
}

// stb_image decodes a JPEG's whole declared size even when its data ends early (it reads
// zeros past the end): a 639-byte file declaring 64264 x 2296 texels took over 10 s under the
// sanitizers (found by tests/fuzz, fuzz_image, 2026-12-05). Every 8 x 8 block of a JPEG's
// full-resolution component costs at least one bit of entropy-coded data, its DC code in a
// Huffman-coded baseline or progressive scan (ITU-T T.81 F.1.2.1, G.1.2.1; stb_image decodes
// no other kind), so a file smaller than one bit per block cannot hold the image it declares
// and is refused before decoding; real files are far larger than this bound.
bool jpeg_data_suffices(const unsigned char* b, size_t n, int w, int h, std::string* why) {
  size_t i = 0;
  while (i < n && b[i] == 0xFF) ++i;
  if (i == 0 || i >= n || b[i] != 0xD8) return true;  // not a JPEG
  const uint64_t blocks = (uint64_t(w) + 7) / 8 * ((uint64_t(h) + 7) / 8);
  const uint64_t least = (blocks + 7) / 8;
  if (uint64_t(n) >= least) return true;
  *why = "a corrupt JPEG: " + std::to_string(w) + " x " + std::to_string(h) + " texels need at least " +
         std::to_string(least) + " bytes of image data (a bit per 8 x 8 block), the file has " + std::to_string(n);
  return false;
}

// stb_image 2.27 (Debian 12) grows its buffer for a PNG's image data (IDAT chunks) to the
// length a chunk declares, doubling, before it reads the chunk's bytes: a 246-byte PNG whose
// last IDAT declared 1,187,646,681 bytes made it allocate 2 GiB
// (found by tests/fuzz, fuzz_image, 2026-12-03). The chunks are walked here by their lengths
// (PNG specification, ISO/IEC 15948 §5.3: length, type, data, CRC) as stb_image walks them, and
// an IDAT chunk that declares more bytes than the file has left is refused before stb_image
// sees the file. Other chunks it skips without allocating; anything else malformed is left to
// stb_image to refuse.
bool png_chunks_fit(const unsigned char* b, size_t n, std::string* why) {
  static const unsigned char kPngMagic[8] = {0x89, 'P', 'N', 'G', 0x0D, 0x0A, 0x1A, 0x0A};
  if (n < 8 || std::memcmp(b, kPngMagic, 8) != 0) return true;  // not a PNG
  size_t i = 8;
  while (i + 8 <= n) {
    const uint64_t len = (uint64_t(b[i]) << 24) | (uint64_t(b[i + 1]) << 16) | (uint64_t(b[i + 2]) << 8) | b[i + 3];
    const bool idat = std::memcmp(b + i + 4, "IDAT", 4) == 0;
    if (idat && len > n - (i + 8)) {
      *why = "a corrupt PNG: the IDAT chunk at byte " + std::to_string(i) + " declares " + std::to_string(len) +
             " bytes, the file has " + std::to_string(n - (i + 8)) + " left";
      return false;
    }
    if (std::memcmp(b + i + 4, "IEND", 4) == 0) break;
    i += 12 + size_t(len);  // len < 2^32: no overflow in size_t
  }
  return true;
}

}  // namespace

bool decode_texture_image(const unsigned char* bytes, size_t size, TextureDesc* t, std::string* error) {
  static const unsigned char kExrMagic[4] = {0x76, 0x2f, 0x31, 0x01};
  if (size >= 4 && std::memcmp(bytes, kExrMagic, 4) == 0) return decode_exr(bytes, size, t, error);
  if (size > size_t(std::numeric_limits<int>::max())) {
    *error = "the image file is larger than 2 GiB";
    return false;
  }
  std::string why;
  if (!jpeg_huffman_tables_fit(bytes, size, &why) || !png_chunks_fit(bytes, size, &why)) {
    *error = "cannot decode the image (" + why + ")";
    return false;
  }
  int w = 0, h = 0, n = 0;
  if (!stbi_info_from_memory(bytes, int(size), &w, &h, &n)) {
    *error = std::string("not a PNG, JPEG or EXR image (") + stbi_failure_reason() + ")";
    return false;
  }
  if (!check_size(w, h, error)) return false;
  if (!jpeg_data_suffices(bytes, size, w, h, &why)) {
    *error = "cannot decode the image (" + why + ")";
    return false;
  }
  const bool sixteen = stbi_is_16_bit_from_memory(bytes, int(size)) != 0;
  void* data = sixteen ? static_cast<void*>(stbi_load_16_from_memory(bytes, int(size), &w, &h, &n, 0))
                       : static_cast<void*>(stbi_load_from_memory(bytes, int(size), &w, &h, &n, 0));
  if (!data) {
    *error = std::string("cannot decode the image (") + stbi_failure_reason() + ")";
    return false;
  }
  t->width = w;
  t->height = h;
  t->channels = n;
  t->eight_bit = !sixteen;
  t->texels.assign(size_t(w) * size_t(h) * 4, 1.0f);
  const bool srgb = t->colorspace == TextureDesc::ColorSpace::Srgb;
  // 8-bit sRGB through a table of the 256 values (exact curve, rounded once to float).
  float lut8[256];
  for (int i = 0; i < 256; ++i) lut8[i] = float(srgb ? srgb_to_linear(i / 255.0) : i / 255.0);
  const int colour_channels = (n == 1 || n == 2) ? 1 : 3;
  for (size_t i = 0; i < size_t(w) * size_t(h); ++i) {
    float v[4] = {0.0f, 0.0f, 0.0f, 1.0f};
    for (int c = 0; c < n; ++c) {
      const bool is_alpha = (n == 2 && c == 1) || (n == 4 && c == 3);
      if (sixteen) {
        const double x = static_cast<const uint16_t*>(data)[i * size_t(n) + size_t(c)] / 65535.0;
        v[c] = float(srgb && !is_alpha ? srgb_to_linear(x) : x);
      } else {
        const unsigned char x = static_cast<const unsigned char*>(data)[i * size_t(n) + size_t(c)];
        v[c] = is_alpha ? x / 255.0f : lut8[x];  // alpha is always linear
      }
    }
    float* p = &t->texels[i * 4];
    if (colour_channels == 1) {
      p[0] = p[1] = p[2] = v[0];
      if (n == 2) p[3] = v[1];
    } else {
      p[0] = v[0];
      p[1] = v[1];
      p[2] = v[2];
      if (n == 4) p[3] = v[3];
    }
  }
  stbi_image_free(data);
  return true;
}

bool load_texture_file(const std::string& path, TextureDesc* t, std::string* error) {
  std::ifstream f(path, std::ios::binary);
  if (!f) {
    *error = "cannot open the file (" + std::string(std::strerror(errno)) + ")";
    return false;
  }
  std::ostringstream ss;
  ss << f.rdbuf();
  if (f.bad()) {
    *error = "cannot read the file";
    return false;
  }
  const std::string bytes = ss.str();
  if (bytes.empty()) {
    *error = "the file is empty";
    return false;
  }
  return decode_texture_image(reinterpret_cast<const unsigned char*>(bytes.data()), bytes.size(), t, error);
}

}  // namespace aw
