#include "host/film/image_io.h"

#include <Iex.h>
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfIO.h>
#include <ImfInputFile.h>
#include <ImfIntAttribute.h>
#include <ImfOutputFile.h>
#include <ImfStringAttribute.h>
#include <png.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <system_error>

namespace aw {
namespace {

namespace fs = std::filesystem;

std::string in_quotes(const std::string& s) { return "\"" + s + "\""; }

std::string errno_text(int err) { return std::error_code(err, std::generic_category()).message(); }

[[noreturn]] void fail_write(const char* kind, const std::string& path, const std::string& reason) {
  throw OutputError(std::string("cannot write ") + kind + " " + in_quotes(path) + ": " + reason);
}

[[noreturn]] void fail_read(const char* kind, const std::string& path, const std::string& reason) {
  throw OutputError(std::string("cannot read ") + kind + " " + in_quotes(path) + ": " + reason);
}

void check_image_for_write(const char* kind, const std::string& path, const Image& img) {
  if (img.width <= 0 || img.height <= 0)
    fail_write(kind, path,
               "image is empty (" + std::to_string(img.width) + "x" + std::to_string(img.height) + ")");
  const size_t expected = size_t(img.width) * size_t(img.height) * 3;
  if (img.rgb.size() != expected)
    fail_write(kind, path,
               "image holds " + std::to_string(img.rgb.size()) + " floats, " +
                   std::to_string(img.width) + "x" + std::to_string(img.height) + " RGB needs " +
                   std::to_string(expected));
  if (img.x0 < 0 || img.y0 < 0 ||
      (img.frame_width > 0 && (img.frame_height <= 0 || int64_t(img.x0) + img.width > img.frame_width ||
                               int64_t(img.y0) + img.height > img.frame_height)))
    fail_write(kind, path, "the image's window lies outside its frame");
}

// "<path>.tmp", opened for writing, that becomes path only through commit(). Destroying it
// uncommitted (any failure, any exception) removes the temporary, so path is either the
// previous file or the complete new one, never a partial write.
class TmpFile {
 public:
  TmpFile(const char* kind, std::string path) : kind_(kind), path_(std::move(path)), tmp_(path_ + ".tmp") {
    // Otherwise this would only surface at the final rename, after all the encoding work.
    std::error_code ec;
    if (fs::is_directory(path_, ec)) fail_write(kind_, path_, "is a directory");
    file_ = std::fopen(tmp_.c_str(), "wb");
    if (!file_) {
      const int err = errno;
      if (err == ENOENT) {
        fs::path dir = fs::path(path_).parent_path();
        std::error_code ec;
        if (!dir.empty() && !fs::exists(dir, ec))
          fail_write(kind_, path_, "directory " + in_quotes(dir.string()) + " does not exist");
      }
      fail_write(kind_, path_, "cannot create " + in_quotes(tmp_) + ": " + errno_text(err));
    }
  }
  TmpFile(const TmpFile&) = delete;
  TmpFile& operator=(const TmpFile&) = delete;

  ~TmpFile() {
    if (file_) std::fclose(file_);
    if (!committed_) std::remove(tmp_.c_str());
  }

  FILE* file() const { return file_; }
  const std::string& tmp_path() const { return tmp_; }

  // fsync before rename: otherwise a crash shortly after could leave path renamed but
  // pointing at data that never reached the disk.
  void commit() {
    FILE* f = file_;
    file_ = nullptr;
    if (std::fflush(f) != 0) {
      const int err = errno;
      std::fclose(f);
      fail_write(kind_, path_, "writing " + in_quotes(tmp_) + " failed: " + errno_text(err));
    }
    if (::fsync(fileno(f)) != 0 && errno != EINVAL && errno != EROFS) {
      const int err = errno;
      std::fclose(f);
      fail_write(kind_, path_, "syncing " + in_quotes(tmp_) + " failed: " + errno_text(err));
    }
    if (std::fclose(f) != 0)
      fail_write(kind_, path_, "closing " + in_quotes(tmp_) + " failed: " + errno_text(errno));
    if (std::rename(tmp_.c_str(), path_.c_str()) != 0)
      fail_write(kind_, path_, "renaming " + in_quotes(tmp_) + " over it failed: " + errno_text(errno));
    committed_ = true;
  }

 private:
  const char* kind_;
  std::string path_, tmp_;
  FILE* file_ = nullptr;
  bool committed_ = false;
};

// OpenEXR's own file streams report I/O errors without errno detail, and errors while
// ~OutputFile writes the line-offset table are swallowed; this stream remembers the first
// errno so write_exr can still report "No space left on device" and refuse to commit.
class StdioOStream : public Imf::OStream {
 public:
  StdioOStream(FILE* f, const std::string& name) : Imf::OStream(name.c_str()), f_(f) {}

  void write(const char c[], int n) override {
    if (n > 0 && std::fwrite(c, 1, size_t(n), f_) != size_t(n)) fail("write");
  }
  uint64_t tellp() override {
    // Must not throw: ~OutputFile calls it outside its try block.
    const off_t pos = ftello(f_);
    if (pos < 0) {
      remember(errno);
      return 0;
    }
    return uint64_t(pos);
  }
  void seekp(uint64_t pos) override {
    if (pos > uint64_t(std::numeric_limits<off_t>::max()) || fseeko(f_, off_t(pos), SEEK_SET) != 0)
      fail("seek");
  }

  int error() const { return err_; }

 private:
  void remember(int err) {
    if (!err_) err_ = err ? err : EIO;
  }
  [[noreturn]] void fail(const char* what) {
    remember(errno);
    // An Iex exception, because that is what OpenEXR code paths expect to catch.
    throw IEX_NAMESPACE::IoExc(std::string(what) + " failed: " + errno_text(err_));
  }

  FILE* f_;
  int err_ = 0;
};

// IEC 61966-2-1 encoding of an already scaled linear value, in double so that the curve
// itself adds no error before the final rounding to 8 bits.
uint8_t encode_srgb8(double linear) {
  if (!(linear > 0.0)) return 0;  // also catches NaN
  if (linear >= 1.0) return 255;
  const double encoded =
      linear <= 0.0031308 ? 12.92 * linear : 1.055 * std::pow(linear, 1.0 / 2.4) - 0.055;
  return uint8_t(std::lround(encoded * 255.0));
}

}  // namespace

void write_text_file(const char* kind, const std::string& path, const std::string& text) {
  TmpFile out(kind, path);
  if (std::fwrite(text.data(), 1, text.size(), out.file()) != text.size())
    fail_write(kind, path, "writing " + in_quotes(out.tmp_path()) + " failed: " + errno_text(errno));
  out.commit();
}

void write_exr(const std::string& path, const Image& img) {
  static const char* kind = "EXR";
  check_image_for_write(kind, path, img);

  const int fw = img.frame_width > 0 ? img.frame_width : img.width;
  const int fh = img.frame_height > 0 ? img.frame_height : img.height;
  const Imath::Box2i display(Imath::V2i(0, 0), Imath::V2i(fw - 1, fh - 1));
  const Imath::Box2i data(Imath::V2i(img.x0, img.y0), Imath::V2i(img.x0 + img.width - 1, img.y0 + img.height - 1));
  Imf::Header header(display, data);
  header.compression() = Imf::ZIP_COMPRESSION;
  header.channels().insert("R", Imf::Channel(Imf::FLOAT));
  header.channels().insert("G", Imf::Channel(Imf::FLOAT));
  header.channels().insert("B", Imf::Channel(Imf::FLOAT));
  const size_t npix = size_t(img.width) * size_t(img.height);
  for (const ImageChannel& c : img.channels) {
    if (c.name.empty() || c.name == "R" || c.name == "G" || c.name == "B" || header.channels().findChannel(c.name))
      fail_write(kind, path, "channel " + in_quotes(c.name) + " is empty or given twice");
    if ((c.u.empty() ? c.f.size() : c.u.size()) != npix || (!c.u.empty() && !c.f.empty()))
      fail_write(kind, path, "channel " + in_quotes(c.name) + " does not hold one value per pixel");
    header.channels().insert(c.name, Imf::Channel(c.u.empty() ? Imf::FLOAT : Imf::UINT));
  }
  for (const auto& [name, value] : img.string_attrs) {
    if (img.int_attrs.count(name))
      fail_write(kind, path, "attribute " + in_quotes(name) + " given both as int and as string");
  }
  try {
    for (const auto& [name, value] : img.int_attrs) header.insert(name, Imf::IntAttribute(value));
    for (const auto& [name, value] : img.string_attrs) header.insert(name, Imf::StringAttribute(value));
  } catch (const std::exception& e) {
    fail_write(kind, path, std::string("bad attribute: ") + e.what());
  }

  // OpenEXR only reads through the frame buffer when writing; the const_cast is for its API.
  char* base = reinterpret_cast<char*>(const_cast<float*>(img.rgb.data()));
  const size_t xs = 3 * sizeof(float);
  const size_t ys = xs * size_t(img.width);
  Imf::FrameBuffer fb;
  fb.insert("R", Imf::Slice::Make(Imf::FLOAT, base + 0 * sizeof(float), data, xs, ys));
  fb.insert("G", Imf::Slice::Make(Imf::FLOAT, base + 1 * sizeof(float), data, xs, ys));
  fb.insert("B", Imf::Slice::Make(Imf::FLOAT, base + 2 * sizeof(float), data, xs, ys));
  for (const ImageChannel& c : img.channels) {
    const bool u = !c.u.empty();
    const void* p = u ? static_cast<const void*>(c.u.data()) : static_cast<const void*>(c.f.data());
    fb.insert(c.name, Imf::Slice::Make(u ? Imf::UINT : Imf::FLOAT, const_cast<void*>(p), data, 4, 4 * size_t(img.width)));
  }

  TmpFile tmp(kind, path);
  StdioOStream stream(tmp.file(), tmp.tmp_path());
  try {
    // Scoped: the line-offset table is only written by ~OutputFile, before commit.
    Imf::OutputFile out(stream, header, 1);
    out.setFrameBuffer(fb);
    out.writePixels(img.height);
  } catch (const std::exception& e) {
    fail_write(kind, path, e.what());
  }
  if (stream.error()) fail_write(kind, path, "writing " + in_quotes(tmp.tmp_path()) + " failed: " + errno_text(stream.error()));
  tmp.commit();
}

bool exr_header_sizes_fit(const unsigned char* b, size_t n, uint64_t file_size, std::string* why) {
  // Layout (OpenEXR file layout, "Header"): magic (4), version (4; bit 12 = multi-part), then
  // attributes: name\0 type\0 size (int32, little-endian) value; an empty name ends a header,
  // and a multi-part file's list of headers ends with one more empty name.
  if (n < 8) return true;
  const bool multipart = (b[5] & 0x10) != 0;
  size_t i = 8;
  auto cstring = [&](size_t* at) {  // skips a NUL-terminated string; false if it runs past `head`
    while (*at < n && b[*at] != 0) ++*at;
    if (*at >= n) return false;
    ++*at;
    return true;
  };
  for (;;) {
    if (i >= n) return true;
    if (b[i] == 0) {  // the end of a header
      ++i;
      if (!multipart || i >= n || b[i] == 0) return true;
      continue;
    }
    const size_t name = i;
    if (!cstring(&i) || !cstring(&i) || i + 4 > n) return true;  // read further than `head`: OpenEXR checks the rest
    const uint32_t size = uint32_t(b[i]) | (uint32_t(b[i + 1]) << 8) | (uint32_t(b[i + 2]) << 16) | (uint32_t(b[i + 3]) << 24);
    i += 4;
    if (uint64_t(size) > file_size - std::min<uint64_t>(file_size, i)) {
      *why = "corrupt EXR header: attribute \"" + std::string(reinterpret_cast<const char*>(b + name)) + "\" declares " +
             std::to_string(int32_t(size)) + " bytes, the file has " + std::to_string(file_size - std::min<uint64_t>(file_size, i)) +
             " left";
      return false;
    }
    i += size;
  }
}

Image read_exr(const std::string& path) {
  static const char* kind = "EXR";
  {
    std::error_code ec;
    const fs::file_status st = fs::status(path, ec);
    if (st.type() == fs::file_type::not_found) fail_read(kind, path, "file does not exist");
    if (st.type() == fs::file_type::directory) fail_read(kind, path, "is a directory");
  }
  {
    std::ifstream f(path, std::ios::binary);
    std::vector<unsigned char> head(1 << 20);
    f.read(reinterpret_cast<char*>(head.data()), std::streamsize(head.size()));
    std::error_code ec;
    const uint64_t file_size = fs::file_size(path, ec);
    std::string why;
    if (!ec && !exr_header_sizes_fit(head.data(), size_t(f.gcount()), file_size, &why)) fail_read(kind, path, why);
  }
  try {
    Imf::InputFile in(path.c_str(), 1);
    const Imf::Header& header = in.header();
    const Imath::Box2i dw = header.dataWindow();
    const int64_t w = int64_t(dw.max.x) - dw.min.x + 1;
    const int64_t h = int64_t(dw.max.y) - dw.min.y + 1;
    if (w <= 0 || h <= 0 || w > std::numeric_limits<int>::max() || h > std::numeric_limits<int>::max())
      fail_read(kind, path, "invalid data window");
    for (const char* c : {"R", "G", "B"}) {
      const Imf::Channel* ch = header.channels().findChannel(c);
      if (!ch) fail_read(kind, path, std::string("no ") + c + " channel");
      if (ch->xSampling != 1 || ch->ySampling != 1)
        fail_read(kind, path, std::string("channel ") + c + " is subsampled, which is not supported");
    }
    // readPixels would fill missing scanlines with zeros instead of failing.
    if (!in.isComplete()) fail_read(kind, path, "file is incomplete (truncated?)");

    Image img;
    img.width = int(w);
    img.height = int(h);
    img.x0 = dw.min.x;
    img.y0 = dw.min.y;
    const Imath::Box2i disp = header.displayWindow();
    img.frame_width = disp.max.x - disp.min.x + 1;
    img.frame_height = disp.max.y - disp.min.y + 1;
    img.rgb.assign(size_t(w) * size_t(h) * 3, 0.0f);

    char* base = reinterpret_cast<char*>(img.rgb.data());
    const size_t xs = 3 * sizeof(float);
    const size_t ys = xs * size_t(w);
    Imf::FrameBuffer fb;
    fb.insert("R", Imf::Slice::Make(Imf::FLOAT, base + 0 * sizeof(float), dw, xs, ys));
    fb.insert("G", Imf::Slice::Make(Imf::FLOAT, base + 1 * sizeof(float), dw, xs, ys));
    fb.insert("B", Imf::Slice::Make(Imf::FLOAT, base + 2 * sizeof(float), dw, xs, ys));
    for (auto it = header.channels().begin(); it != header.channels().end(); ++it) {
      const std::string name = it.name();
      if (name == "R" || name == "G" || name == "B") continue;
      if (it.channel().xSampling != 1 || it.channel().ySampling != 1)
        fail_read(kind, path, "channel " + name + " is subsampled, which is not supported");
      ImageChannel c;
      c.name = name;
      if (it.channel().type == Imf::UINT) c.u.assign(size_t(w) * size_t(h), 0u);
      else c.f.assign(size_t(w) * size_t(h), 0.0f);
      img.channels.push_back(std::move(c));
    }
    for (ImageChannel& c : img.channels) {
      const bool u = !c.u.empty();
      void* p = u ? static_cast<void*>(c.u.data()) : static_cast<void*>(c.f.data());
      fb.insert(c.name, Imf::Slice::Make(u ? Imf::UINT : Imf::FLOAT, p, dw, 4, 4 * size_t(w)));
    }
    in.setFrameBuffer(fb);
    in.readPixels(dw.min.y, dw.max.y);

    for (auto it = header.begin(); it != header.end(); ++it) {
      if (auto* ia = dynamic_cast<const Imf::IntAttribute*>(&it.attribute()))
        img.int_attrs[it.name()] = ia->value();
      else if (auto* sa = dynamic_cast<const Imf::StringAttribute*>(&it.attribute()))
        img.string_attrs[it.name()] = sa->value();
    }
    return img;
  } catch (const OutputError&) {
    throw;
  } catch (const std::exception& e) {
    fail_read(kind, path, e.what());
  }
}

void write_png_preview(const std::string& path, const Image& img, float exposure_scale) {
  static const char* kind = "PNG";
  check_image_for_write(kind, path, img);
  if (!std::isfinite(exposure_scale) || exposure_scale < 0.0f)
    fail_write(kind, path, "invalid exposure scale " + std::to_string(exposure_scale));
  if (size_t(img.width) * 3 > size_t(std::numeric_limits<png_int_32>::max()))
    fail_write(kind, path, "image too wide for PNG");

  const size_t n_pixels = size_t(img.width) * size_t(img.height);
  std::vector<uint8_t> bytes(n_pixels * 3);
  const double scale = exposure_scale;
  for (size_t i = 0; i < n_pixels; ++i) {
    const float* p = &img.rgb[3 * i];
    // A NaN/Inf sample is a bug upstream; black keeps it visible without inventing colour.
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) continue;
    for (int c = 0; c < 3; ++c) bytes[3 * i + c] = encode_srgb8(double(p[c]) * scale);
  }

  TmpFile tmp(kind, path);
  // libpng's simplified API reports errors through png_image::message instead of longjmp,
  // which would skip C++ destructors; it also tags the file as sRGB.
  png_image pi;
  std::memset(&pi, 0, sizeof pi);
  pi.version = PNG_IMAGE_VERSION;
  pi.width = png_uint_32(img.width);
  pi.height = png_uint_32(img.height);
  pi.format = PNG_FORMAT_RGB;
  const int ok = png_image_write_to_stdio(&pi, tmp.file(), 0, bytes.data(), 0, nullptr);
  const std::string message = pi.message;
  png_image_free(&pi);
  if (!ok) fail_write(kind, path, "libpng: " + message);
  tmp.commit();
}

std::string png_path_for(const std::string& exr_path) {
  static const char ext[] = ".exr";
  const size_t n = sizeof ext - 1;
  if (exr_path.size() >= n &&
      std::equal(exr_path.end() - n, exr_path.end(), ext,
                 [](char a, char b) { return std::tolower(static_cast<unsigned char>(a)) == b; }))
    return exr_path.substr(0, exr_path.size() - n) + ".png";
  return exr_path + ".png";
}

ImageDiff compare_images(const Image& a, const Image& b, double rel_tol, double abs_floor) {
  if (a.width != b.width || a.height != b.height)
    throw std::invalid_argument("compare_images: size mismatch " + std::to_string(a.width) + "x" +
                                std::to_string(a.height) + " vs " + std::to_string(b.width) + "x" +
                                std::to_string(b.height));
  if (a.width < 0 || a.height < 0) throw std::invalid_argument("compare_images: negative size");
  const size_t n_pixels = size_t(a.width) * size_t(a.height);
  if (a.rgb.size() != n_pixels * 3 || b.rgb.size() != n_pixels * 3)
    throw std::invalid_argument("compare_images: rgb data does not match width*height*3");
  if (!(rel_tol >= 0.0) || !(abs_floor >= 0.0))
    throw std::invalid_argument("compare_images: rel_tol and abs_floor must be >= 0");

  ImageDiff d{};
  if (n_pixels == 0) {
    d.frac_pixels_within = 1.0;
    return d;
  }
  double sum_a = 0.0, sum_b = 0.0, max_abs = 0.0;
  bool saw_nan = false;
  size_t within = 0;
  for (size_t i = 0; i < n_pixels; ++i) {
    bool pixel_within = true;
    for (int c = 0; c < 3; ++c) {
      const double va = a.rgb[3 * i + c], vb = b.rgb[3 * i + c];
      sum_a += va;
      sum_b += vb;
      if (va == vb) continue;  // also equal infinities, where |a-b| would be NaN
      const double abs_diff = std::fabs(va - vb);
      if (std::isnan(abs_diff)) {
        saw_nan = true;
        pixel_within = false;
        continue;
      }
      max_abs = std::max(max_abs, abs_diff);
      const double denom = std::max({std::fabs(va), std::fabs(vb), abs_floor});
      // denom == 0 only if both are 0, which the equality test above already took.
      if (!(abs_diff / denom <= rel_tol)) pixel_within = false;
    }
    if (pixel_within) ++within;
  }
  const double count = double(n_pixels) * 3.0;
  d.mean_a = sum_a / count;
  d.mean_b = sum_b / count;
  d.rel_mean_diff = std::fabs(d.mean_a - d.mean_b) /
                    std::max({std::fabs(d.mean_a), std::fabs(d.mean_b), DBL_MIN});
  d.frac_pixels_within = double(within) / double(n_pixels);
  d.max_abs_diff = saw_nan ? std::numeric_limits<double>::quiet_NaN() : max_abs;
  return d;
}

}  // namespace aw
