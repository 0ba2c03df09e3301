// Image output: the linear float EXR the renderer produces, its 8-bit PNG preview, and the
// image comparison the renderer's tests are built on.
#pragma once

#include <cstdint>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace aw {

// A channel besides R, G, B: a layer's channel as compositors name them ("albedo.R"), or the
// film state of docs/production.md ("archwave_film.N"). One of f / u holds width * height values.
struct ImageChannel {
  std::string name;
  std::vector<float> f;     // written as FLOAT when u is empty
  std::vector<uint32_t> u;  // written as UINT
};

// A linear RGB image as the renderer hands it over.
struct Image {
  int width = 0, height = 0;
  std::vector<float> rgb;  // 3 floats per pixel, row-major, top row first
  // Where the pixels lie in the frame (EXR's data window inside its display window): a crop
  // of a frame_width x frame_height frame at (x0, y0). 0 x 0 = the frame is the image.
  int x0 = 0, y0 = 0, frame_width = 0, frame_height = 0;
  std::vector<ImageChannel> channels;  // written after R, G, B; read back by read_exr
  // Written as EXR header attributes under exactly these names (e.g. "spp", "seed",
  // "archwave:device"). A name must not clash with a standard EXR attribute of another
  // type ("compression", "dataWindow", ...) nor appear in both maps; such a write fails.
  std::map<std::string, std::string> string_attrs;
  std::map<std::string, int> int_attrs;
};

// Any failure to write or read an image file. what() names the file and the reason.
class OutputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// 32-bit float R,G,B, ZIP compression, plus every int/string attribute of img.
// The data goes to "<path>.tmp" first and is renamed over path only once complete and
// flushed, so a failed or interrupted write never leaves a truncated file at path
// (an existing file there stays untouched on failure, and the .tmp is removed).
// Throws OutputError (also for an empty image or rgb.size() != width*height*3).
void write_exr(const std::string& path, const Image& img);

// Reads R,G,B as float (the file must have all three channels), every other channel (FLOAT
// or HALF as f, UINT as u) and every int and string attribute of the header. The data window
// gives width, height, x0 and y0; the display window frame_width and frame_height.
// Throws OutputError naming path (missing file, not an EXR, truncated, missing channel).
Image read_exr(const std::string& path);

// OpenEXR (3.1, Debian 12) allocates an attribute's value by the size its header declares
// before reading it: a 600-byte file declaring a 2 GB string made it allocate 2 GB (found by
// tests/fuzz, fuzz_image, 2026-12-02). Walks the header(s) at the start of an EXR file
// (`head`, `head_size` bytes of it; `file_size` the whole file's) and returns false with the
// reason when an attribute declares more bytes than the file has left, or the header is
// malformed within `head`. A header longer than `head` is accepted as far as it was read.
bool exr_header_sizes_fit(const unsigned char* head, size_t head_size, uint64_t file_size, std::string* why);

// 8-bit sRGB PNG: v * exposure_scale, clamped to [0,1], then the exact IEC 61966-2-1
// piecewise curve, rounded to nearest. A pixel with any NaN/Inf channel is written black.
// Same tmp+rename and OutputError behaviour as write_exr; a NaN, infinite or negative
// exposure_scale is an OutputError as well.
void write_png_preview(const std::string& path, const Image& img, float exposure_scale);

// `text` written with the same tmp+rename (and fsync) as write_exr; throws OutputError naming
// `kind` and path.
void write_text_file(const char* kind, const std::string& path, const std::string& text);

// "out.exr" -> "out.png"; the ".exr" suffix is matched case-insensitively ("a.EXR" ->
// "a.png"); any other path gets ".png" appended ("out" -> "out.png").
std::string png_path_for(const std::string& exr_path);

struct ImageDiff {
  double mean_a, mean_b;       // mean over all channels of all pixels
  double rel_mean_diff;        // |mean_a - mean_b| / max(|mean_a|, |mean_b|, DBL_MIN)
  double frac_pixels_within;   // pixels whose 3 channels all have rel. diff <= rel_tol
  double max_abs_diff;         // largest per-channel |a - b|
};

// Per channel, rel = |a-b| / max(|a|, |b|, abs_floor); equal values (including equal
// infinities) count as rel 0. Any NaN makes that pixel "not within" and max_abs_diff NaN,
// so a test comparing against a tolerance fails rather than passes. A 0x0 image yields
// means 0 and frac_pixels_within 1. Throws std::invalid_argument when the sizes differ,
// an rgb vector does not hold width*height*3 floats, or rel_tol/abs_floor is negative/NaN.
ImageDiff compare_images(const Image& a, const Image& b, double rel_tol, double abs_floor);

}  // namespace aw
