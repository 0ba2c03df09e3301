#include "host/render/film_state.h"

#include <algorithm>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "kernels/integrator/aov.h"
#include "kernels/integrator/film.h"

namespace aw {

namespace {

const char* const kFilmLayer = "archwave_film.";
const char* const kChannelNames = "RGB";

std::string hex64(uint64_t v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%016" PRIx64, v);
  return buf;
}

std::string bounds_text(const FilmState& f) {
  return "pixels " + std::to_string(f.x0) + "," + std::to_string(f.x0 + f.width) + "," + std::to_string(f.y0) + "," +
         std::to_string(f.y0 + f.height) + " of " + std::to_string(f.frame_width) + "x" + std::to_string(f.frame_height) +
         ", samples " + std::to_string(f.sample_start) + ":" + std::to_string(f.sample_end);
}

[[noreturn]] void bad_state(const std::string& path, const std::string& why) {
  throw OutputError("cannot read the film state of \"" + path + "\": " + why);
}

// The film's place in the frame, from one holder of it (Image, FilmState, RenderResult) to another.
template <class From, class To>
void copy_window(const From& a, To& b) {
  b.width = a.width;
  b.height = a.height;
  b.x0 = a.x0;
  b.y0 = a.y0;
  b.frame_width = a.frame_width;
  b.frame_height = a.frame_height;
}

// The film itself (its samples range, scene, sums and counts), between FilmState and RenderResult.
template <class From, class To>
void copy_film(const From& a, To& b) {
  copy_window(a, b);
  b.sample_start = a.sample_start;
  b.sample_end = a.sample_end;
  b.scene_hash = a.scene_hash;
  b.acc = a.acc;
  b.count = a.count;
  b.aov_mask = a.aov_mask;
  b.aov_acc = a.aov_acc;
}

}  // namespace

uint32_t FilmState::min_spp() const {
  if (count.empty()) return 0;
  return *std::min_element(count.begin(), count.end());
}

double film_word_value(const uint64_t* w) {
  return (double(w[1]) * 18446744073709551616.0 + double(w[0])) * std::ldexp(1.0, -AW_FILM_FRAC_BITS);
}

double film_word_value_signed(const uint64_t* w) {
  if (!(w[1] >> 63)) return film_word_value(w);
  const uint64_t neg[2] = {~w[0] + 1u, ~w[1] + (w[0] == 0 ? 1u : 0u)};
  return -film_word_value(neg);
}

std::vector<std::pair<std::string, uint32_t>> aov_channel_names(uint32_t mask) {
  std::vector<std::pair<std::string, uint32_t>> v;
  for (uint32_t a = 0; a < AW_AOV_COUNT; ++a) {
    if (!(mask & (1u << a))) continue;
    const std::string layer = aov_name(a);
    const char* const* ch;
    static const char* const rgb[] = {"R", "G", "B"};
    static const char* const xyz[] = {"X", "Y", "Z"};
    static const char* const z[] = {"Z"};
    static const char* const id[] = {"id"};
    if (a == AW_AOV_NORMAL || a == AW_AOV_POSITION) ch = xyz;
    else if (a == AW_AOV_DEPTH) ch = z;
    else if (a == AW_AOV_MATERIAL_ID) ch = id;
    else ch = rgb;
    for (uint32_t c = 0; c < aov_channels(a); ++c) v.emplace_back(layer + "." + ch[c], a);
  }
  return v;
}

std::string aov_mask_names(uint32_t mask) {
  std::string s;
  for (uint32_t a = 0; a < AW_AOV_COUNT; ++a)
    if (mask & (1u << a)) s += std::string(s.empty() ? "" : ",") + aov_name(a);
  return s;
}

Image film_image(const FilmState& f, bool with_state) {
  Image img;
  copy_window(f, img);
  const size_t npix = size_t(f.width) * size_t(f.height);
  img.rgb.assign(npix * 3, 0.0f);
  for (size_t p = 0; p < npix; ++p) {
    if (f.count[p] == 0) continue;
    for (int c = 0; c < 3; ++c)
      img.rgb[p * 3 + c] = float(film_word_value(&f.acc[p * AW_FILM_WORDS + 2 * c]) / double(f.count[p]));
  }
  // Exposure is applied here so the EXR holds exposed radiance (docs/scene-format.md,
  // camera.exposure): x k, and in photographic mode white balance and vignetting.
  f.exposure.apply(f.frame_width, f.frame_height, f.x0, f.y0, f.width, f.height, img.rgb.data());
  // AOVs: each pixel's mean; the light groups exposed like the beauty, so they sum to it.
  const auto aov_names = aov_channel_names(f.aov_mask);
  const size_t nch = aov_names.size();
  if (nch) {
    std::vector<float> group(npix * 3);
    for (size_t k = 0; k < nch; ++k) {
      ImageChannel ch;
      ch.name = aov_names[k].first;
      ch.f.assign(npix, 0.0f);
      for (size_t p = 0; p < npix; ++p)
        if (f.count[p]) ch.f[p] = float(film_word_value_signed(&f.aov_acc[(p * nch + k) * 2]) / double(f.count[p]));
      img.channels.push_back(std::move(ch));
    }
    // Expose the light groups, three channels at a time (they are RGB).
    for (size_t k = 0; k < nch; ++k) {
      if (!aov_is_light_group(aov_names[k].second) || aov_names[k].first.back() != 'R') continue;
      // (img.channels holds only the AOVs' channels so far, in film order.)
      float* c[3] = {img.channels[k].f.data(), img.channels[k + 1].f.data(), img.channels[k + 2].f.data()};
      for (size_t p = 0; p < npix; ++p)
        for (int i = 0; i < 3; ++i) group[p * 3 + i] = c[i][p];
      f.exposure.apply(f.frame_width, f.frame_height, f.x0, f.y0, f.width, f.height, group.data());
      for (size_t p = 0; p < npix; ++p)
        for (int i = 0; i < 3; ++i) c[i][p] = group[p * 3 + i];
    }
  }
  img.int_attrs["spp"] = int(f.min_spp());
  img.int_attrs["spp_requested"] = int(f.spp_requested);
  img.int_attrs["seed"] = int(f.seed);
  img.int_attrs["max_depth"] = f.max_depth;
  img.string_attrs["archwave:version"] = f.version;
  img.string_attrs["archwave:renderer"] = f.renderer;
  img.string_attrs["archwave:device"] = f.device;
  img.string_attrs["archwave:scene"] = f.scene_path;
  if (f.interrupted) img.string_attrs["archwave:interrupted"] = "yes";
  if (f.time_limited) img.string_attrs["archwave:time_limited"] = "yes";
  if (!with_state) return img;
  img.string_attrs["archwave:film"] = "1";
  img.string_attrs["archwave:samples"] = std::to_string(f.sample_start) + " " + std::to_string(f.sample_end);
  img.string_attrs["archwave:scene_hash"] = hex64(f.scene_hash);
  img.string_attrs["archwave:exposure"] = f.exposure.to_string();
  for (int c = 0; c < 3; ++c) {
    for (int k = 0; k < 4; ++k) {
      ImageChannel ch;
      ch.name = std::string(kFilmLayer) + kChannelNames[c] + char('0' + k);
      ch.u.resize(npix);
      for (size_t p = 0; p < npix; ++p) {
        const uint64_t word = f.acc[p * AW_FILM_WORDS + 2 * c + k / 2];
        ch.u[p] = uint32_t(k % 2 == 0 ? word : word >> 32);
      }
      img.channels.push_back(std::move(ch));
    }
  }
  ImageChannel n;
  n.name = std::string(kFilmLayer) + "N";
  n.u = f.count;
  img.channels.push_back(std::move(n));
  img.string_attrs["archwave:aovs"] = aov_mask_names(f.aov_mask);
  for (size_t k = 0; k < nch; ++k)
    for (int w = 0; w < 4; ++w) {
      ImageChannel ch;
      ch.name = std::string(kFilmLayer) + aov_names[k].first + "." + char('0' + w);
      ch.u.resize(npix);
      for (size_t p = 0; p < npix; ++p) {
        const uint64_t word = f.aov_acc[(p * nch + k) * 2 + w / 2];
        ch.u[p] = uint32_t(w % 2 == 0 ? word : word >> 32);
      }
      img.channels.push_back(std::move(ch));
    }
  return img;
}

FilmState read_film_state(const std::string& path) {
  const Image img = read_exr(path);
  auto str = [&](const char* key) -> const std::string& {
    auto it = img.string_attrs.find(key);
    if (it == img.string_attrs.end()) {
      if (std::string(key) == "archwave:film")
        bad_state(path, "it holds no archwave film state (archwave writes one with --save-state, --checkpoint, "
                        "--time-limit, --sample-range, --pixel-bounds or on an interrupt)");
      bad_state(path, std::string("attribute ") + key + " is missing");
    }
    return it->second;
  };
  auto integer = [&](const char* key) {
    auto it = img.int_attrs.find(key);
    if (it == img.int_attrs.end()) bad_state(path, std::string("attribute ") + key + " is missing");
    return it->second;
  };
  if (str("archwave:film") != "1")
    bad_state(path, "its film state has format \"" + str("archwave:film") + "\", this archwave reads format 1");
  FilmState f;
  copy_window(img, f);
  if (f.x0 < 0 || f.y0 < 0 || f.x0 + f.width > f.frame_width || f.y0 + f.height > f.frame_height)
    bad_state(path, "its data window is not inside its display window");
  {
    unsigned a = 0, b = 0;
    char tail = 0;
    if (std::sscanf(str("archwave:samples").c_str(), "%u %u %c", &a, &b, &tail) != 2 || !(a < b))
      bad_state(path, "attribute archwave:samples is \"" + str("archwave:samples") + "\", not \"START END\" with START < END");
    f.sample_start = a;
    f.sample_end = b;
  }
  {
    const std::string& h = str("archwave:scene_hash");
    char* end = nullptr;
    f.scene_hash = std::strtoull(h.c_str(), &end, 16);
    if (h.size() != 16 || *end != '\0') bad_state(path, "attribute archwave:scene_hash is \"" + h + "\", not 16 hex digits");
  }
  if (!ExposureMap::parse(str("archwave:exposure"), &f.exposure))
    bad_state(path, "attribute archwave:exposure is \"" + str("archwave:exposure") + "\", not six non-negative numbers");
  f.spp_requested = uint32_t(integer("spp_requested"));
  f.seed = uint32_t(integer("seed"));
  f.max_depth = integer("max_depth");
  f.version = str("archwave:version");
  f.renderer = str("archwave:renderer");
  f.device = str("archwave:device");
  auto it = img.string_attrs.find("archwave:scene");
  if (it != img.string_attrs.end()) f.scene_path = it->second;
  f.interrupted = img.string_attrs.count("archwave:interrupted") > 0;
  f.time_limited = img.string_attrs.count("archwave:time_limited") > 0;
  const size_t npix = size_t(f.width) * size_t(f.height);
  auto channel = [&](const std::string& name) -> const std::vector<uint32_t>& {
    for (const ImageChannel& c : img.channels)
      if (c.name == name) {
        if (c.u.size() != npix) bad_state(path, "channel " + name + " is not of type UINT");
        return c.u;
      }
    bad_state(path, "channel " + name + " is missing");
  };
  f.count = channel(std::string(kFilmLayer) + "N");
  f.acc.assign(npix * AW_FILM_WORDS, 0ull);
  for (int c = 0; c < 3; ++c)
    for (int k = 0; k < 4; ++k) {
      const std::vector<uint32_t>& words = channel(std::string(kFilmLayer) + kChannelNames[c] + char('0' + k));
      for (size_t p = 0; p < npix; ++p)
        f.acc[p * AW_FILM_WORDS + 2 * c + k / 2] |= uint64_t(words[p]) << (32 * (k % 2));
    }
  {
    auto it = img.string_attrs.find("archwave:aovs");
    if (it != img.string_attrs.end() && !it->second.empty()) {
      std::stringstream ss(it->second);
      std::string name;
      while (std::getline(ss, name, ',')) {
        const uint32_t bits = aov_bits_for_name(name);
        if (!bits) bad_state(path, "attribute archwave:aovs names \"" + name + "\", which is not an AOV");
        f.aov_mask |= bits;
      }
    }
    const auto names = aov_channel_names(f.aov_mask);
    f.aov_acc.assign(npix * names.size() * 2, 0ull);
    for (size_t k = 0; k < names.size(); ++k)
      for (int w = 0; w < 4; ++w) {
        const std::vector<uint32_t>& words = channel(std::string(kFilmLayer) + names[k].first + "." + char('0' + w));
        for (size_t p = 0; p < npix; ++p) f.aov_acc[(p * names.size() + k) * 2 + w / 2] |= uint64_t(words[p]) << (32 * (w % 2));
      }
  }
  for (size_t p = 0; p < npix; ++p)
    if (f.count[p] > f.sample_end - f.sample_start)
      bad_state(path, "a pixel holds " + std::to_string(f.count[p]) + " samples, more than its range " +
                          std::to_string(f.sample_start) + ":" + std::to_string(f.sample_end) + " has");
  return f;
}

FilmState film_state(const RenderResult& r, const Scene& scene) {
  FilmState f;
  copy_film(r, f);
  if (f.frame_width <= 0) f.frame_width = r.width;  // a result made by hand: the film is the frame
  if (f.frame_height <= 0) f.frame_height = r.height;
  f.exposure = exposure_map(scene.camera);
  f.spp_requested = uint32_t(scene.render.spp);
  f.seed = scene.render.seed;
  f.max_depth = scene.render.max_depth;
  f.version = ARCHWAVE_VERSION;
  f.renderer = r.stats.renderer;
  f.device = r.stats.device;
  f.scene_path = scene.path;
  f.interrupted = r.stats.interrupted;
  f.time_limited = r.stats.time_limited;
  return f;
}

RenderResult film_to_result(const FilmState& f) {
  RenderResult r;
  copy_film(f, r);
  r.stats.renderer = f.renderer;
  r.stats.device = f.device;
  r.update_sums();
  return r;
}

FilmState merge_films(const std::vector<FilmState>& parts, const std::vector<std::string>& names, std::string* report,
                      std::vector<std::string>* warnings, bool* resumable) {
  if (parts.empty()) throw SceneError("nothing to merge");
  const FilmState& a = parts[0];
  auto refuse = [&](size_t i, const std::string& what) {
    throw SceneError("cannot merge \"" + names[i] + "\" with \"" + names[0] + "\": " + what);
  };
  for (size_t i = 1; i < parts.size(); ++i) {
    const FilmState& b = parts[i];
    if (b.seed != a.seed) refuse(i, "seeds differ (" + std::to_string(b.seed) + " and " + std::to_string(a.seed) + ")");
    if (b.frame_width != a.frame_width || b.frame_height != a.frame_height)
      refuse(i, "frame sizes differ (" + std::to_string(b.frame_width) + "x" + std::to_string(b.frame_height) + " and " +
                    std::to_string(a.frame_width) + "x" + std::to_string(a.frame_height) + ")");
    if (b.scene_hash != a.scene_hash)
      refuse(i, "they are renders of different scenes (scene hashes " + hex64(b.scene_hash) + " and " + hex64(a.scene_hash) + ")");
    if (b.spp_requested != a.spp_requested)
      refuse(i, "they are parts of renders of different spp (" + std::to_string(b.spp_requested) + " and " +
                    std::to_string(a.spp_requested) + ")");
    if (b.version != a.version)
      refuse(i, "archwave versions differ (" + b.version + " and " + a.version + "): sample values may differ");
    if (b.renderer != a.renderer)
      refuse(i, "renderers differ (" + b.renderer + " and " + a.renderer + "): their samples agree to float precision, not bit for bit");
    if (b.exposure.to_string() != a.exposure.to_string()) refuse(i, "their exposures differ");
    if (b.aov_mask != a.aov_mask)
      refuse(i, "their AOVs differ (\"" + aov_mask_names(b.aov_mask) + "\" and \"" + aov_mask_names(a.aov_mask) + "\")");
    if (b.device != a.device)
      warnings->push_back("\"" + names[i] + "\" was rendered on " + b.device + ", \"" + names[0] + "\" on " + a.device +
                          ": the parts agree to float precision; a single render on one device is reproduced bit for bit");
  }
  // Pixels and samples must not be counted twice.
  for (size_t i = 0; i < parts.size(); ++i)
    for (size_t j = i + 1; j < parts.size(); ++j) {
      const FilmState &p = parts[i], &q = parts[j];
      const bool pixels = p.x0 < q.x0 + q.width && q.x0 < p.x0 + p.width && p.y0 < q.y0 + q.height && q.y0 < p.y0 + p.height;
      const bool samples = p.sample_start < q.sample_end && q.sample_start < p.sample_end;
      if (pixels && samples)
        throw SceneError("cannot merge \"" + names[i] + "\" (" + bounds_text(p) + ") with \"" + names[j] + "\" (" +
                         bounds_text(q) + "): they overlap in pixels and in samples, which would count samples twice");
    }
  FilmState m = a;
  int x1 = a.x0 + a.width, y1 = a.y0 + a.height;
  for (const FilmState& p : parts) {
    m.x0 = std::min(m.x0, p.x0);
    m.y0 = std::min(m.y0, p.y0);
    x1 = std::max(x1, p.x0 + p.width);
    y1 = std::max(y1, p.y0 + p.height);
    m.sample_start = std::min(m.sample_start, p.sample_start);
    m.sample_end = std::max(m.sample_end, p.sample_end);
  }
  m.width = x1 - m.x0;
  m.height = y1 - m.y0;
  const size_t npix = size_t(m.width) * size_t(m.height);
  m.acc.assign(npix * AW_FILM_WORDS, 0ull);
  m.count.assign(npix, 0u);
  const size_t nch = aov_channel_names(m.aov_mask).size();
  m.aov_acc.assign(npix * nch * 2, 0ull);
  auto add128 = [](uint64_t* w, const uint64_t* v) {  // two's complement: signed sums too
    const uint64_t lo = w[0] + v[0];
    w[1] = w[1] + v[1] + (lo < v[0] ? 1u : 0u);
    w[0] = lo;
  };
  m.interrupted = m.time_limited = false;
  // Per pixel: which parts cover it, to check that its samples are one run from sample_start.
  std::vector<uint8_t> covered(npix, 0);
  for (const FilmState& p : parts) {
    m.interrupted = m.interrupted || p.interrupted;
    m.time_limited = m.time_limited || p.time_limited;
    for (int y = 0; y < p.height; ++y)
      for (int x = 0; x < p.width; ++x) {
        const size_t src = size_t(y) * size_t(p.width) + size_t(x);
        const size_t dst = size_t(p.y0 + y - m.y0) * size_t(m.width) + size_t(p.x0 + x - m.x0);
        covered[dst] = 1;
        for (int c = 0; c < 3; ++c) add128(&m.acc[dst * AW_FILM_WORDS + 2 * c], &p.acc[src * AW_FILM_WORDS + 2 * c]);
        for (size_t k = 0; k < nch; ++k) add128(&m.aov_acc[(dst * nch + k) * 2], &p.aov_acc[(src * nch + k) * 2]);
        m.count[dst] += p.count[src];
      }
  }
  // Resumable only if every pixel holds the samples [sample_start, sample_start + count):
  // the parts over it, sorted by their first sample, must each be complete up to the last.
  *resumable = true;
  size_t uncovered = 0, gaps = 0;
  for (int y = 0; y < m.height; ++y)
    for (int x = 0; x < m.width; ++x) {
      const size_t dst = size_t(y) * size_t(m.width) + size_t(x);
      if (!covered[dst]) {
        ++uncovered;
        continue;
      }
      std::vector<std::pair<uint32_t, uint32_t>> runs;  // (first sample, count) of each part here
      for (const FilmState& p : parts) {
        const int px = m.x0 + x, py = m.y0 + y;
        if (px < p.x0 || py < p.y0 || px >= p.x0 + p.width || py >= p.y0 + p.height) continue;
        runs.emplace_back(p.sample_start, p.count[size_t(py - p.y0) * size_t(p.width) + size_t(px - p.x0)]);
      }
      std::sort(runs.begin(), runs.end());
      uint32_t next = m.sample_start;
      bool ok = true;
      for (const auto& r : runs) {
        if (r.second == 0) continue;
        if (r.first != next) ok = false;
        next = r.first + r.second;
      }
      if (!ok) ++gaps;
    }
  if (uncovered) {
    *resumable = false;
    warnings->push_back(std::to_string(uncovered) + " pixels of the merged window " + std::to_string(m.width) + "x" +
                        std::to_string(m.height) + " are in no part: they are black");
  }
  if (gaps) {
    *resumable = false;
    warnings->push_back(std::to_string(gaps) + " pixels hold samples with a gap between parts (an interrupted or time-limited "
                        "part): the image is right for the samples it holds, but the film cannot be resumed or merged further; "
                        "resume that part first");
  }
  std::ostringstream r;
  r << "merged " << parts.size() << " parts into " << bounds_text(m) << ", " << m.min_spp() << " spp at least";
  *report = r.str();
  return m;
}

}  // namespace aw
