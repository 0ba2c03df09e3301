// A render's film as a file: the EXR that --checkpoint, --time-limit, an interrupt,
// --sample-range and --pixel-bounds write holds, beside the image, everything that resuming
// and merging need (docs/production.md):
//   - channels archwave_film.R0..R3, .G0..G3, .B0..B3 (UINT): each pixel's exact channel sums
//     (kernels/integrator/film.h), 128 bits as four 32-bit words, lowest first;
//   - channel archwave_film.N (UINT): the pixel's sample count;
//   - attributes archwave:film (the state's format, "1"), archwave:samples ("START END"),
//     archwave:scene_hash (16 hex digits), archwave:exposure (ExposureMap), plus the image's
//     usual seed, spp_requested, max_depth, archwave:version, renderer and device;
//   - the EXR data window: the film's pixels in the frame (the display window).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "host/film/image_io.h"
#include "host/render/render.h"
#include "host/scene/scene.h"

namespace aw {

struct FilmState {
  int width = 0, height = 0, x0 = 0, y0 = 0, frame_width = 0, frame_height = 0;
  uint32_t sample_start = 0, sample_end = 0;
  uint64_t scene_hash = 0;
  std::vector<uint64_t> acc;    // AW_FILM_WORDS per pixel
  std::vector<uint32_t> count;  // samples per pixel
  uint32_t aov_mask = 0;          // AOVs (kernels/integrator/aov.h)
  std::vector<uint64_t> aov_acc;  // per pixel aov_film_channels(aov_mask) exact signed sums, 2 words each
  ExposureMap exposure;
  uint32_t spp_requested = 0, seed = 0;
  int max_depth = 0;
  std::string version, renderer, device, scene_path;
  bool interrupted = false, time_limited = false;
  uint32_t min_spp() const;
};

// A channel's exact sum (two words of a pixel's acc, low first) as a number: exact up to
// 2^53 on the film's grid, rounded to nearest double beyond. The signed form reads the two
// words as two's complement (the AOVs' sums: normals and positions are signed).
double film_word_value(const uint64_t* w);
double film_word_value_signed(const uint64_t* w);

// The EXR channel names of the AOVs in `mask`, in film order ("albedo.R", "depth.Z",
// "material_id.id", "diffuse.B", ...), and for each the AOV it belongs to.
std::vector<std::pair<std::string, uint32_t>> aov_channel_names(uint32_t mask);
// "albedo,normal": the names of the AOVs in mask.
std::string aov_mask_names(uint32_t mask);

// The film of a render of `scene`.
FilmState film_state(const RenderResult& r, const Scene& scene);

// The exposed image (each pixel's sum / count, 0 where count is 0; ExposureMap), with the
// header attributes of every archwave image and, with_state, the film state above.
Image film_image(const FilmState& f, bool with_state);

// The film state of an EXR archwave wrote. Throws OutputError naming the file and what is
// missing or malformed (no film state at all: written without one, or by another program).
FilmState read_film_state(const std::string& path);

// The film as the renderers take it back (RenderOptions::resume).
RenderResult film_to_result(const FilmState& f);

// Merges parts of one render: parts over the same pixels add their sums and counts (their
// sample ranges must not overlap), parts over other pixels are stitched into the bounding
// box of all. Because the sums are exact integers, parts that together cover a render's
// samples and pixels merge into exactly that render's film, bit for bit. Throws SceneError
// for parts of different scenes, seeds, frames, versions or renderers, or parts whose pixels
// and sample ranges overlap, naming the files (`names`). Appends what it did to *report and
// notes (pixels no part covers, gaps) to *warnings. *resumable is false when some pixel's
// samples are not one run from the first sample (an interrupted part): the film then cannot
// be resumed or merged further, only viewed.
FilmState merge_films(const std::vector<FilmState>& parts, const std::vector<std::string>& names, std::string* report,
                      std::vector<std::string>* warnings, bool* resumable);

}  // namespace aw
