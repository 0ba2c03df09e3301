// Production renders (issue 15, docs/production.md): the film's exact sums, parts of a render
// (sample ranges, pixel bounds) that merge into the single render bit for bit, a resumed
// render equal to the uninterrupted one bit for bit, time limits that stop at a whole sample
// pass, checkpoints, and the refusals of parts and films that do not belong together.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <memory>
#include <random>
#include <string>
#include <thread>

#include "host/render/film_state.h"
#include "host/render/render.h"
#include "host/scene/scene.h"
#include "kernels/integrator/film.h"
#include "tests/render/render_test_util.h"

namespace {

// Small enough to render many times; odd sizes so that windows and passes do not divide evenly.
const std::vector<std::string> kSmall = {"render.width=37", "render.height=23", "render.spp=7", "render.max_depth=4"};

aw::Scene cornell(std::vector<std::string> extra = {}) {
  std::vector<std::string> o = kSmall;
  o.insert(o.end(), extra.begin(), extra.end());
  return aw::load_scene(aw_test::source_path("scenes/cornell.json"), o);
}

aw::RenderResult render(const aw::Scene& s, const aw::RenderOptions& o, bool scalar = false) {
  return scalar ? aw::render_scalar(s, o) : aw::render_wavefront(s, o);
}

aw::RenderOptions part(int x0, int x1, int y0, int y1, uint32_t s0, uint32_t s1) {
  aw::RenderOptions o = aw_test::quiet_options();
  o.window = aw::PixelBounds{x0, x1, y0, y1};
  o.sample_start = s0;
  o.sample_end = s1;
  return o;
}

// Bit for bit: the exact sums, the counts, and the image's floats.
void expect_same_film(const aw::FilmState& a, const aw::FilmState& b) {
  ASSERT_EQ(a.width, b.width);
  ASSERT_EQ(a.height, b.height);
  EXPECT_EQ(a.x0, b.x0);
  EXPECT_EQ(a.y0, b.y0);
  EXPECT_EQ(a.count, b.count);
  EXPECT_TRUE(a.acc == b.acc) << "the exact sums differ";
  const aw::Image ia = aw::film_image(a, false), ib = aw::film_image(b, false);
  ASSERT_EQ(ia.rgb.size(), ib.rgb.size());
  EXPECT_EQ(0, std::memcmp(ia.rgb.data(), ib.rgb.data(), ia.rgb.size() * sizeof(float))) << "the images differ";
}

aw::FilmState merge(const std::vector<aw::FilmState>& parts, bool* resumable = nullptr) {
  std::vector<std::string> names;
  for (size_t i = 0; i < parts.size(); ++i) names.push_back("part" + std::to_string(i));
  std::string report;
  std::vector<std::string> warnings;
  bool r = true;
  aw::FilmState m = aw::merge_films(parts, names, &report, &warnings, &r);
  if (resumable) *resumable = r;
  std::printf("%s\n", report.c_str());
  return m;
}

// The film's grid: a float converts exactly when its last mantissa bit is at or above 2^-40,
// and to the nearest multiple of 2^-40 below; sums carry across the two words.
TEST(Film, FixedPointConversionIsExactAndCarries) {
  uint64_t w[2] = {0, 0};
  film_add_channel(w, 1.0f);
  EXPECT_EQ(w[0], uint64_t(1) << 40);
  EXPECT_EQ(w[1], 0u);
  w[0] = w[1] = 0;
  film_add_channel(w, std::ldexp(1.0f, 30));  // 2^70 on the grid: the high word
  EXPECT_EQ(w[0], 0u);
  EXPECT_EQ(w[1], uint64_t(1) << 6);
  w[0] = w[1] = 0;
  film_add_channel(w, 0x1.000002p40f);  // 2^80 + 2^57: both words
  EXPECT_EQ(w[1], uint64_t(1) << 16);
  EXPECT_EQ(w[0], uint64_t(1) << 57);
  w[0] = ~uint64_t(0) - 5;
  w[1] = 3;
  film_add_channel(w, std::ldexp(1.0f, -34));  // 64 units: carries into the high word
  EXPECT_EQ(w[0], uint64_t(58));
  EXPECT_EQ(w[1], 4u);
  w[0] = w[1] = 0;
  film_add_channel(w, std::ldexp(1.5f, -41));  // 0.75 units: rounds to 1
  EXPECT_EQ(w[0], 1u);
  film_add_channel(w, std::ldexp(1.0f, -42));  // 0.25 units: rounds to 0
  EXPECT_EQ(w[0], 1u);
  film_add_channel(w, std::ldexp(1.0f, -41));  // 0.5 units: ties round up
  EXPECT_EQ(w[0], 2u);
  film_add_channel(w, 1e-40f);                 // subnormal: 0
  EXPECT_EQ(w[0], 2u);
  film_add_channel(w, 0.0f);
  EXPECT_EQ(w[0], 2u);
  EXPECT_EQ(w[1], 0u);
  // Values converted exactly come back exactly.
  w[0] = w[1] = 0;
  film_add_channel(w, 3.25f);
  film_add_channel(w, 1024.5f);
  EXPECT_EQ(aw::film_word_value(w), 1027.75);
}

// Sums do not depend on the order of the samples: shuffled orders give the same bits, which
// a float running sum does not (the reason for the grid).
TEST(Film, SumsAreOrderIndependent) {
  std::mt19937 rng(15);
  std::lognormal_distribution<float> value(0.0f, 3.0f);  // fireflies and dark samples alike
  std::vector<float> v(5000);
  for (float& x : v) x = value(rng);
  uint64_t ref[2] = {0, 0};
  for (float x : v) film_add_channel(ref, x);
  bool float_sums_differ = false;
  float fref = 0.0f;
  for (float x : v) fref += x;
  for (int trial = 0; trial < 20; ++trial) {
    std::shuffle(v.begin(), v.end(), rng);
    uint64_t w[2] = {0, 0};
    float f = 0.0f;
    for (float x : v) {
      film_add_channel(w, x);
      f += x;
    }
    EXPECT_EQ(w[0], ref[0]);
    EXPECT_EQ(w[1], ref[1]);
    float_sums_differ = float_sums_differ || f != fref;
  }
  EXPECT_TRUE(float_sums_differ) << "the test's data should show why a float sum is not enough";
}

// Sample-range parts, split evenly, unevenly and one sample at a time, merge into the single
// render bit for bit: sums, counts and the image.
TEST(Parts, SampleRangesMergeIntoTheSingleRenderBitForBit) {
  const aw::Scene s = cornell();
  const aw::FilmState whole = aw::film_state(render(s, aw_test::quiet_options()), s);
  const std::vector<std::vector<uint32_t>> splits = {{0, 3, 7}, {0, 1, 6, 7}, {0, 1, 2, 3, 4, 5, 6, 7}};
  for (const auto& cuts : splits) {
    std::vector<aw::FilmState> parts;
    for (size_t i = 0; i + 1 < cuts.size(); ++i)
      parts.push_back(aw::film_state(render(s, part(0, 0, 0, 0, cuts[i], cuts[i + 1])), s));
    std::reverse(parts.begin(), parts.end());  // the order of the files does not matter
    bool resumable = false;
    expect_same_film(merge(parts, &resumable), whole);
    EXPECT_TRUE(resumable);
  }
}

// Pixel-bound parts (uneven tiles, a crop window's) and a mix of tiles and sample ranges.
TEST(Parts, PixelBoundsStitchIntoTheSingleRenderBitForBit) {
  const aw::Scene s = cornell();
  const aw::FilmState whole = aw::film_state(render(s, aw_test::quiet_options()), s);
  std::vector<aw::FilmState> tiles;
  for (auto [x0, x1, y0, y1] : std::vector<std::array<int, 4>>{{0, 17, 0, 9}, {17, 37, 0, 9}, {0, 5, 9, 23}, {5, 37, 9, 23}})
    tiles.push_back(aw::film_state(render(s, part(x0, x1, y0, y1, 0, 0)), s));
  EXPECT_EQ(tiles[1].x0, 17);
  EXPECT_EQ(tiles[1].width, 20);
  expect_same_film(merge(tiles), whole);
  // A tile in two sample ranges beside whole tiles.
  std::vector<aw::FilmState> mixed = {tiles[0], tiles[1], tiles[2]};
  mixed.push_back(aw::film_state(render(s, part(5, 37, 9, 23, 0, 4)), s));
  mixed.push_back(aw::film_state(render(s, part(5, 37, 9, 23, 4, 7)), s));
  expect_same_film(merge(mixed), whole);
}

// The scalar path's parts merge into the scalar render the same way (its thread split and
// pass order change nothing either).
TEST(Parts, ScalarPartsMergeBitForBit) {
  const aw::Scene s = cornell({"render.width=19", "render.height=11"});
  aw::RenderOptions o = aw_test::quiet_options();
  o.threads = 2;
  const aw::FilmState whole = aw::film_state(render(s, o, true), s);
  aw::RenderOptions a = part(0, 19, 0, 4, 0, 7), b = part(0, 19, 4, 11, 0, 2), c = part(0, 19, 4, 11, 2, 7);
  c.threads = 1;
  expect_same_film(merge({aw::film_state(render(s, a, true), s), aw::film_state(render(s, b, true), s),
                          aw::film_state(render(s, c, true), s)}),
                   whole);
}

// A window renders the frame's own pixels: its pixels equal the whole render's there.
TEST(Parts, AWindowRendersTheFramesPixels) {
  const aw::Scene s = cornell();
  const aw::RenderResult whole = render(s, aw_test::quiet_options());
  const aw::RenderResult w = render(s, part(11, 30, 6, 20, 0, 0));
  ASSERT_EQ(w.width, 19);
  ASSERT_EQ(w.height, 14);
  for (int y = 0; y < w.height; ++y)
    for (int x = 0; x < w.width; ++x)
      for (int k = 0; k < AW_FILM_WORDS; ++k)
        ASSERT_EQ(w.acc[(size_t(y) * w.width + x) * AW_FILM_WORDS + k],
                  whole.acc[(size_t(y + 6) * whole.width + x + 11) * AW_FILM_WORDS + k]);
}

// A film through its EXR (film state channels and attributes) and back.
aw::RenderResult through_exr(const aw::RenderResult& r, const aw::Scene& s, const std::string& name) {
  const std::string path = testing::TempDir() + "/parts_" + name + "_" + std::to_string(getpid()) + ".exr";
  aw::write_exr(path, r.image(s, true));
  return aw::film_to_result(aw::read_film_state(path));
}

// Interrupted at a batch's end, then resumed through the EXR: the uninterrupted render bit for
// bit, on the wavefront (a job prefix: some pixels one sample ahead) and on the scalar path
// (whole rows done).
TEST(Resume, InterruptedThenResumedIsTheUninterruptedRender) {
  const aw::Scene s = cornell();
  for (bool scalar : {false, true}) {
    SCOPED_TRACE(scalar ? "scalar" : "wavefront");
    const aw::FilmState whole = aw::film_state(render(s, aw_test::quiet_options(), scalar), s);
    std::atomic<bool> cancel{false};
    aw::RenderOptions o = aw_test::quiet_options();
    o.cancel = &cancel;
    o.max_batch = 1000;  // not a multiple of the 851 pixels: the interrupt leaves a ragged film
    o.pool_size = 512;
    o.checkpoint_seconds = 1e-9;
    int calls = 0;
    o.checkpoint = [&](const aw::RenderResult&) {
      if (++calls == 3) cancel = true;
    };
    aw::RenderResult partial = render(s, o, scalar);
    ASSERT_TRUE(partial.stats.interrupted);
    ASSERT_LT(partial.min_spp(), 7u);
    const aw::RenderResult back = through_exr(partial, s, scalar ? "scalar" : "wavefront");
    EXPECT_EQ(back.acc, partial.acc);
    aw::RenderOptions r = aw_test::quiet_options();
    r.resume = &back;
    const aw::RenderResult resumed = render(s, r, scalar);
    EXPECT_FALSE(resumed.stats.interrupted);
    EXPECT_EQ(resumed.stats.resumed_samples + resumed.stats.samples, uint64_t(37 * 23 * 7));
    expect_same_film(aw::film_state(resumed, s), whole);
  }
}

// Interrupted at an arbitrary moment by another thread, as a signal would: the same.
TEST(Resume, InterruptedAnywhereThenResumedIsTheUninterruptedRender) {
  const aw::Scene s = cornell({"render.width=64", "render.height=48", "render.spp=16"});
  const aw::FilmState whole = aw::film_state(render(s, aw_test::quiet_options()), s);
  std::atomic<bool> cancel{false};
  aw::RenderOptions o = aw_test::quiet_options();
  o.cancel = &cancel;
  o.pool_size = 1024;
  o.max_batch = 4096;
  std::thread stopper([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    cancel = true;
  });
  aw::RenderResult partial = render(s, o);
  stopper.join();
  aw::RenderOptions r = aw_test::quiet_options();
  r.resume = &partial;
  expect_same_film(aw::film_state(render(s, r), s), whole);
}

// A time limit stops at the end of a sample pass (every pixel the same count, below spp),
// marks the image, and resuming completes it bit for bit. Resuming a complete film to more
// samples equals rendering those samples at once.
TEST(Resume, TimeLimitStopsAtAWholeSampleAndResumes) {
  const aw::Scene s = cornell();
  for (bool scalar : {false, true}) {
    SCOPED_TRACE(scalar ? "scalar" : "wavefront");
    const aw::FilmState whole = aw::film_state(render(s, aw_test::quiet_options(), scalar), s);
    aw::RenderOptions o = aw_test::quiet_options();
    o.time_limit = 1e-6;  // passed at the first check
    o.max_batch = 1000;
    o.pool_size = 512;
    aw::RenderResult limited = render(s, o, scalar);
    ASSERT_TRUE(limited.stats.time_limited);
    EXPECT_FALSE(limited.stats.interrupted);
    const uint32_t n = limited.count[0];
    EXPECT_GE(n, 1u);
    EXPECT_LT(n, 7u);
    for (uint32_t c : limited.count) ASSERT_EQ(c, n) << "not a whole sample pass";
    EXPECT_EQ(limited.image(s, true).string_attrs.at("archwave:time_limited"), "yes");
    aw::RenderOptions r = aw_test::quiet_options();
    r.resume = &limited;
    expect_same_film(aw::film_state(render(s, r, scalar), s), whole);
  }
  // More samples later: 7 then 7 more of a 14-spp render (the Sobol' sampler does not depend
  // on spp) equal the 14-spp render.
  const aw::Scene s14 = cornell({"render.spp=14"});
  const aw::RenderResult seven = render(s, aw_test::quiet_options());
  aw::RenderOptions more = aw_test::quiet_options();
  more.resume = &seven;
  expect_same_film(aw::film_state(render(s14, more), s14), aw::film_state(render(s14, aw_test::quiet_options()), s14));
}

// A complete film resumes to itself: no job is left, nothing changes, on both renderers.
TEST(Resume, ACompleteFilmResumesToItself) {
  const aw::Scene s = cornell();
  for (bool scalar : {false, true}) {
    const aw::RenderResult whole = render(s, aw_test::quiet_options(), scalar);
    aw::RenderOptions r = aw_test::quiet_options();
    r.resume = &whole;
    const aw::RenderResult again = render(s, r, scalar);
    EXPECT_EQ(again.stats.samples, 0u);
    EXPECT_FALSE(again.stats.interrupted);
    expect_same_film(aw::film_state(again, s), aw::film_state(whole, s));
  }
}

// Checkpoints hand over the film at batch ends with what it holds so far, growing.
TEST(Resume, CheckpointsHandOverTheFilmSoFar) {
  const aw::Scene s = cornell();
  aw::RenderOptions o = aw_test::quiet_options();
  o.max_batch = 2000;
  o.pool_size = 512;
  o.checkpoint_seconds = 1e-9;
  std::vector<uint64_t> held;
  o.checkpoint = [&](const aw::RenderResult& r) {
    uint64_t n = 0;
    for (uint32_t c : r.count) n += c;
    held.push_back(n);
    EXPECT_EQ(r.acc.size(), r.count.size() * AW_FILM_WORDS);
  };
  aw::RenderResult r = render(s, o);
  ASSERT_GE(held.size(), 2u);
  for (size_t i = 0; i < held.size(); ++i) EXPECT_EQ(held[i], uint64_t(2000) * (i + 1));
  EXPECT_EQ(r.stats.checkpoints, held.size());
}

// A device lost mid-render (ARCHWAVE_FAULT, docs/production.md#a-device-lost-mid-render):
// with a snapshot after every batch, the film kept is the last whole batch's, and resuming it
// gives the uninterrupted render bit for bit. An error that leaves the device answering reads
// the film back after it: the same film, with or without snapshots. Lost with no snapshot
// taken, nothing is kept.
TEST(Resume, ADeviceLostMidRenderKeepsItsFilmAndResumes) {
  const aw::Scene s = cornell();
  const aw::FilmState whole = aw::film_state(render(s, aw_test::quiet_options()), s);
  auto failing = [&](const char* fault, double snapshot_seconds) -> std::shared_ptr<aw::RenderResult> {
    aw::RenderOptions o = aw_test::quiet_options();
    o.max_batch = 1000;
    o.pool_size = 512;
    o.snapshot_seconds = snapshot_seconds;
    setenv("ARCHWAVE_FAULT", fault, 1);
    std::shared_ptr<aw::RenderResult> kept;
    try {
      render(s, o);
      ADD_FAILURE() << fault << ": the render did not fail";
    } catch (const aw::RenderDeviceError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("clEnqueue"), std::string::npos) << what;
      EXPECT_NE(what.find("CL_OUT_OF_RESOURCES"), std::string::npos) << what;
      kept = e.partial;
      std::printf("%s, snapshots every %g s: %s\n", fault, snapshot_seconds, what.c_str());
    }
    unsetenv("ARCHWAVE_FAULT");
    return kept;
  };
  auto held = [](const aw::RenderResult& r) {
    uint64_t n = 0;
    for (uint32_t c : r.count) n += c;
    return n;
  };
  // Launch 200 falls in the fifth of the six batches (measured: the film keeps 4000 samples).
  std::shared_ptr<aw::RenderResult> lost = failing("lost:200", 0.0);
  ASSERT_TRUE(lost);
  EXPECT_TRUE(lost->stats.interrupted);
  EXPECT_NE(lost->stats.device_error.find("CL_OUT_OF_RESOURCES"), std::string::npos);
  EXPECT_GE(lost->stats.film_snapshots, 1u);
  const uint64_t n = held(*lost);
  EXPECT_GT(n, 0u);
  EXPECT_LT(n, uint64_t(37 * 23 * 7));
  EXPECT_EQ(n % 1000, 0u) << "a snapshot holds whole batches";
  const aw::RenderResult back = through_exr(*lost, s, "device_lost");
  aw::RenderOptions r = aw_test::quiet_options();
  r.resume = &back;
  expect_same_film(aw::film_state(render(s, r), s), whole);
  // The device still answers: the film read back after the error is the same, snapshots or not.
  for (double snap : {0.0, -1.0}) {
    std::shared_ptr<aw::RenderResult> read = failing("launch:200", snap);
    ASSERT_TRUE(read);
    EXPECT_EQ(read->acc, lost->acc);
    EXPECT_EQ(read->count, lost->count);
  }
  // Lost with snapshots off: nothing to keep.
  EXPECT_FALSE(failing("lost:200", -1.0));
  // A bad value of the testing aid is refused, naming it.
  setenv("ARCHWAVE_FAULT", "lost:x", 1);
  try {
    render(s, aw_test::quiet_options());
    ADD_FAILURE() << "ARCHWAVE_FAULT=lost:x accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("ARCHWAVE_FAULT=lost:x"), std::string::npos) << e.what();
  }
  unsetenv("ARCHWAVE_FAULT");
}

// What does not belong together is refused, naming the reason.
TEST(Resume, RefusesAFilmOfAnotherSceneOrPart) {
  const aw::Scene s = cornell();
  const aw::RenderResult film = render(s, part(0, 10, 0, 10, 0, 3));
  auto refused = [&](const aw::Scene& scene, aw::RenderOptions o, const std::string& why) {
    o.resume = &film;
    try {
      render(scene, o);
      ADD_FAILURE() << "resumed, expected: " << why;
    } catch (const aw::SceneError& e) {
      EXPECT_NE(std::string(e.what()).find(why), std::string::npos) << e.what();
    }
  };
  refused(cornell({"materials.white.diffuse.color=[0.5,0.5,0.5]"}), part(0, 10, 0, 10, 0, 7), "another scene");
  refused(cornell({"render.seed=99"}), part(0, 10, 0, 10, 0, 7), "another scene");
  refused(s, part(0, 10, 0, 11, 0, 7), "covers pixels");
  refused(s, part(0, 10, 0, 10, 1, 7), "starts at sample 0");
  // And the same film resumes with its own part.
  aw::RenderOptions ok = part(0, 10, 0, 10, 0, 7);
  ok.resume = &film;
  EXPECT_EQ(render(s, ok).min_spp(), 7u);
}

TEST(Parts, RefusesBadWindowsAndRanges) {
  const aw::Scene s = cornell();
  EXPECT_THROW(render(s, part(0, 38, 0, 23, 0, 0)), aw::SceneError);
  EXPECT_THROW(render(s, part(-1, 10, 0, 23, 0, 0)), aw::SceneError);
  EXPECT_THROW(render(s, part(5, 5, 0, 0, 0, 0)), aw::SceneError);  // empty but not the default
  EXPECT_THROW(render(s, part(0, 0, 0, 0, 3, 3)), aw::SceneError);
  EXPECT_THROW(render(s, part(0, 0, 0, 0, 0, 8)), aw::SceneError);
}

TEST(Merge, RefusesPartsThatDoNotBelongTogether) {
  const aw::Scene s = cornell();
  const aw::FilmState a = aw::film_state(render(s, part(0, 0, 0, 0, 0, 3)), s);
  auto refused = [&](const aw::FilmState& b, const std::string& why) {
    try {
      merge({a, b});
      ADD_FAILURE() << "merged, expected: " << why;
    } catch (const aw::SceneError& e) {
      EXPECT_NE(std::string(e.what()).find(why), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("part1"), std::string::npos) << "names the file: " << e.what();
    }
  };
  const aw::Scene seeded = cornell({"render.seed=4"});
  refused(aw::film_state(render(seeded, part(0, 0, 0, 0, 3, 7)), seeded), "seeds differ");
  const aw::Scene other = cornell({"materials.white.diffuse.color=[0.5,0.5,0.5]"});
  refused(aw::film_state(render(other, part(0, 0, 0, 0, 3, 7)), other), "different scenes");
  const aw::Scene wider = cornell({"render.width=40"});
  refused(aw::film_state(render(wider, part(0, 0, 0, 0, 3, 7)), wider), "frame sizes differ");
  refused(aw::film_state(render(s, part(0, 0, 0, 0, 2, 7)), s), "overlap in pixels and in samples");
  refused(aw::film_state(render(s, part(0, 0, 0, 0, 3, 7), true), s), "renderers differ");
}

// A merge with a gap (one part interrupted) keeps the image right for what it holds but says
// it cannot be resumed; pixels no part covers are black and reported.
TEST(Merge, GapsAndHolesAreReported) {
  const aw::Scene s = cornell();
  std::atomic<bool> cancel{true};  // interrupted before the first batch: nothing rendered
  aw::RenderOptions o = part(0, 0, 0, 0, 0, 3);
  o.cancel = &cancel;
  const aw::FilmState empty_first = aw::film_state(render(s, o), s);
  const aw::FilmState rest = aw::film_state(render(s, part(0, 0, 0, 0, 3, 7)), s);
  bool resumable = true;
  aw::FilmState m = merge({empty_first, rest}, &resumable);
  EXPECT_FALSE(resumable);
  EXPECT_EQ(m.min_spp(), 4u);
  const aw::FilmState tile = aw::film_state(render(s, part(0, 10, 0, 10, 0, 7)), s);
  const aw::FilmState far = aw::film_state(render(s, part(20, 30, 10, 20, 0, 7)), s);
  m = merge({tile, far}, &resumable);
  EXPECT_FALSE(resumable);
  EXPECT_EQ(m.width, 30);
  EXPECT_EQ(m.height, 20);
  EXPECT_EQ(m.min_spp(), 0u);
}

// The scene hash is a function of the scene alone: the same scene loaded twice hashes the same,
// and the window or sample range do not enter it.
TEST(Parts, SceneHashIsStable) {
  const aw::RenderResult a = render(cornell(), part(0, 5, 0, 5, 0, 1));
  const aw::RenderResult b = render(cornell(), part(3, 9, 2, 4, 2, 5));
  EXPECT_EQ(a.scene_hash, b.scene_hash);
  EXPECT_NE(a.scene_hash, render(cornell({"render.max_depth=5"}), part(0, 5, 0, 5, 0, 1)).scene_hash);
}

}  // namespace
