// The stages written on lanes (kernels/integrator/kernels_lanes.cl: 16 paths per work-item on a
// CPU device) render the film of the one-path kernels bit for bit (docs/performance.md, "Paths
// in explicit lanes"; docs/testing.md). Each scene renders twice with lanes, since a race
// between the work-groups PoCL runs on its threads would show as two different films.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "host/render/render.h"
#include "host/scene/scene.h"
#include "tests/render/render_test_util.h"

namespace {

// scenes/materials.json without what keeps classification one path per work-item (the glass's
// fog, the bronze's anisotropy): every Fresnel mode of the reflection lobes' sampled split.
const std::vector<std::string> kMaterialsClassifiedOnLanes = {"materials.glass.refraction.fog.enable=false",
                                                              "materials.bronze.anisotropy.amount=0"};

size_t differing_words(const aw::RenderResult& a, const aw::RenderResult& b) {
  if (a.acc.size() != b.acc.size()) return a.acc.size() + b.acc.size();
  size_t n = 0;
  for (size_t i = 0; i < a.acc.size(); ++i) n += a.acc[i] != b.acc[i];
  return n;
}

// Scenes whose ray stages (forced: --lane-traversal on, so that both devices' compilers build
// and run the lane traversal whatever the measured default), classification and diffuse stage
// run on lanes: the Cornell box (quad and point
// light, Lambert; also with paths ended at max_depth 2), the race's small sphere light (an
// analytic sphere beside triangles), rough diffuse (EON) under a quad light; and lobes on lanes
// beside lobes that are not (glass, GGX, lobe splitting: race_spheres; and every material of
// materials.json but fog and anisotropy, which keep classification one path per work-item:
// GGX over rough diffuse, a curve-Fresnel plastic with a second reflection lobe, a mirror,
// glass, a conductor with metal, a thin-walled translucent leaf, an incandescent lamp, so that
// classification's sampled split on lanes meets every Fresnel mode); every launch of those
// stages dense (the lane kernels' only form) and the default mix of dense and queue launches;
// with GI and without.
//
// Each case runs with the ray stages and classification at 16 lanes (the lane program's one
// width) and, where `narrow` is set, at 8 too (a second program, kernels_lanes.cl at
// -DAW_LANES=8: what Intel's runtime uses where a register holds 8 floats; wavefront.cpp,
// narrow_lane_width), so that both widths are checked on every device whatever its own choice.
TEST(Lanes, SameFilmWithAndWithoutLanes) {
  struct Case {
    const char* file;
    std::vector<std::string> defs;
    double dense_fraction;
    const char* lanes;  // the stats' account of the stages on lanes, at 16
    const char* narrow;  // the same with the narrow stages at 8; null: not run at 8
  };
  const char* all = "16 paths per work-item: regenerate intersect_closest classify_hit shade_diffuse intersect_shadow accumulate";
  const char* all8 = "16 paths per work-item: regenerate shade_diffuse accumulate; 8: intersect_closest classify_hit intersect_shadow";
  // Scenes of at least 16 primitives sort the closest hit's rays (wavefront.cpp, kSortMinPrimitives).
  const char* sorted = "16 paths per work-item: regenerate intersect_closest(sorted) classify_hit shade_diffuse intersect_shadow accumulate";
  const char* sorted8 =
      "16 paths per work-item: regenerate shade_diffuse accumulate; 8: intersect_closest(sorted) classify_hit intersect_shadow";
  const std::vector<std::string> small = {"render.width=96", "render.height=64", "render.spp=8"};
  std::vector<std::string> every_fresnel = kMaterialsClassifiedOnLanes;
  every_fresnel.push_back("materials.plastic.reflection2={\"weight\": 0.5, \"glossiness\": 0.4}");
  const Case cases[] = {{"scenes/cornell.json", {}, 0.0, sorted, sorted8},
                        {"scenes/cornell.json", {}, -1.0, sorted, sorted8},
                        {"scenes/cornell.json", {"render.gi=false"}, 0.0, sorted, nullptr},
                        {"scenes/cornell.json", {"render.max_depth=2"}, 0.0, sorted, nullptr},
                        {"scenes/bench/race_small_light.json", {}, 0.0, sorted, sorted8},
                        {"scenes/docs/diffuse_roughness_1.json", {}, 0.0, all, nullptr},
                        {"scenes/bench/race_spheres.json", {}, 0.0, all, all8},
                        {"scenes/materials.json", every_fresnel, 0.0, all, all8}};
  for (const Case& c : cases) for (int narrow : {16, 8}) {
    if (narrow == 8 && !c.narrow) continue;
    std::vector<std::string> defs = small;
    defs.insert(defs.end(), c.defs.begin(), c.defs.end());
    aw::Scene scene = aw::load_scene(aw_test::source_path(c.file), defs);
    aw::RenderOptions on = aw_test::quiet_options(), off = on;
    on.dense_fraction = off.dense_fraction = c.dense_fraction;
    on.lane_traversal = 1;
    on.narrow_lanes = narrow;
    off.lanes = false;
    aw::RenderResult a = aw::render_wavefront(scene, on), a2 = aw::render_wavefront(scene, on);
    aw::RenderResult b = aw::render_wavefront(scene, off);
    const std::string what = std::string(c.file) + " (dense fraction " + std::to_string(c.dense_fraction) +
                             ", narrow stages at " + std::to_string(narrow) + " lanes)";
    EXPECT_EQ(a.stats.lanes, narrow == 8 ? c.narrow : c.lanes) << what;
    EXPECT_EQ(b.stats.lanes, "off (--no-lanes)") << what;
    EXPECT_EQ(differing_words(a, b), 0u) << what << ": lanes against one path per work-item";
    EXPECT_EQ(differing_words(a, a2), 0u) << what << ": two renders with lanes";
    EXPECT_EQ(a.stats.bad_samples, 0u) << what;
  }
}

// regenerate on lanes hands its jobs out by an atomic per work-item (kernels_lanes.cl): a part of
// a frame (a 13 x 7 window off the origin, samples 3 to 9), so that job -> (pixel, sample) wraps
// at a window that is no multiple of 16 and starts off the origin, in batches of 37 jobs, which
// end inside a work-item's lanes and leave most of the pool (one group, 256 slots) free: its
// film is the one-path kernels'.
TEST(Lanes, RegenerateOnLanesKeepsEveryJobOnce) {
  aw::Scene scene = aw::load_scene(aw_test::source_path("scenes/cornell.json"),
                                   {"render.width=40", "render.height=24", "render.spp=9"});
  aw::RenderOptions on = aw_test::quiet_options();
  on.window = aw::PixelBounds{5, 18, 9, 16};
  on.sample_start = 3;
  on.pool_size = 256;
  on.max_batch = 37;
  on.dense_fraction = 0.0;  // every launch of every stage on lanes
  aw::RenderOptions off = on;
  off.lanes = false;
  aw::RenderResult a = aw::render_wavefront(scene, on), b = aw::render_wavefront(scene, off);
  EXPECT_NE(a.stats.lanes.find("regenerate"), std::string::npos) << a.stats.lanes;
  EXPECT_EQ(a.stats.samples, 13u * 7u * 6u);
  EXPECT_EQ(b.stats.samples, 13u * 7u * 6u);
  EXPECT_EQ(differing_words(a, b), 0u);
}

// accumulate on lanes (kernels_lanes.cl, kernel_accumulate_lanes) discards, clamps and counts as
// the one-path kernel does: a quad light of intensity 3e38 makes samples overflow to Inf (each
// discarded and counted), and render.clamp scales the others; every launch of every stage on
// lanes, the film word for word and the discarded samples' count the one-path kernels', and
// the same again at a pool of 256 slots in batches of 37 jobs (the finished jobs counted per half
// of the batch ring, which end inside a work-item's lanes). A per-lobe split keeps accumulate one
// path per call (accumulate_path sends the next split to its lobe's queue).
TEST(Lanes, AccumulateOnLanesDiscardsClampsAndCountsAsOnePathPerCall) {
  const std::string hot =
      "lights=[{\"type\": \"quad\", \"corner\": [-0.25, 1.995, -0.25], \"edge_u\": [0.5, 0, 0], "
      "\"edge_v\": [0, 0, 0.5], \"color\": [1, 1, 1], \"intensity\": 3e38}, {\"type\": \"point\", "
      "\"position\": [0.55, 1.55, 0.6], \"color\": [0.6, 0.7, 1.0], \"intensity\": 0.6}]";
  for (const std::string& def : {hot, std::string("render.clamp=0.5")})
    for (const auto& [pool, batch] : std::vector<std::pair<uint32_t, uint32_t>>{{0u, 0u}, {256u, 37u}}) {
      aw::Scene scene = aw::load_scene(aw_test::source_path("scenes/cornell.json"),
                                       {"render.width=40", "render.height=24", "render.spp=4", def});
      aw::RenderOptions on = aw_test::quiet_options();
      if (pool) on.pool_size = pool;
      if (batch) on.max_batch = batch;
      on.dense_fraction = 0.0;
      aw::RenderOptions off = on;
      off.lanes = false;
      aw::RenderResult a = aw::render_wavefront(scene, on), b = aw::render_wavefront(scene, off);
      const std::string what = def.substr(0, 20) + ", pool " + std::to_string(pool) + ", batch " + std::to_string(batch);
      EXPECT_NE(a.stats.lanes.find(" accumulate"), std::string::npos) << a.stats.lanes;
      if (def == hot) {
        EXPECT_GT(b.stats.bad_samples, 0u) << what;
      }
      EXPECT_EQ(a.stats.bad_samples, b.stats.bad_samples) << what;
      EXPECT_EQ(a.stats.samples, 40u * 24u * 4u) << what;
      EXPECT_EQ(differing_words(a, b), 0u) << what;
    }
  aw::Scene split = aw::load_scene(aw_test::source_path("scenes/materials.json"),
                                   {"render.width=16", "render.height=16", "render.spp=1",
                                    "materials.plastic.reflection.samples=4"});
  aw::RenderResult s = aw::render_wavefront(split, aw_test::quiet_options());
  EXPECT_EQ(s.stats.lanes.find(" accumulate "), std::string::npos) << s.stats.lanes;
  EXPECT_NE(s.stats.lanes.find("(accumulate one path per work-item: the scene needs split)"), std::string::npos)
      << s.stats.lanes;
}

// The sorted closest hit (kernels_lanes.cl, kernel_intersect_closest_sorted) takes 4,096 slots
// per work-item: a pool of 4,352 leaves the second work-item 256 (its span cut at the pool's
// end), and the film is still the one-path kernels' word for word, with every path traced
// once (no sample lost or doubled: the counts match).
TEST(Lanes, SortedClosestHitCoversAPoolNotAWholeNumberOfSpans) {
  aw::Scene scene = aw::load_scene(aw_test::source_path("scenes/cornell.json"),
                                   {"render.width=72", "render.height=40", "render.spp=6"});
  aw::RenderOptions on = aw_test::quiet_options();
  on.pool_size = 4352;
  on.dense_fraction = 0.0;
  on.lane_traversal = 1;
  aw::RenderOptions off = on;
  off.lanes = false;
  aw::RenderResult a = aw::render_wavefront(scene, on), b = aw::render_wavefront(scene, off);
  EXPECT_NE(a.stats.lanes.find(" intersect_closest(sorted)"), std::string::npos) << a.stats.lanes;
  EXPECT_EQ(a.stats.samples, 72u * 40u * 6u);
  EXPECT_EQ(a.stats.closest_rays, b.stats.closest_rays);
  EXPECT_EQ(differing_words(a, b), 0u);
}

// The ray stages on lanes by default only where the lane traversal was measured to pay: not for
// 24578 triangles on any device (wavefront.cpp, lane_traversal_limit), nor when turned off;
// the film is the same either way.
TEST(Lanes, RayStagesOnLanesOnlyWhereTheyPay) {
  aw::Scene knot = aw::load_scene(aw_test::source_path("scenes/knot.json"),
                                  {"render.width=48", "render.height=32", "render.spp=2"});
  aw::RenderOptions opts = aw_test::quiet_options();
  opts.narrow_lanes = 16;  // the stats' strings below name one width whatever the device's own choice
  aw::RenderResult a = aw::render_wavefront(knot, opts);
  EXPECT_EQ(a.stats.lanes.find(" intersect_closest"), std::string::npos) << a.stats.lanes;
  EXPECT_NE(a.stats.lanes.find("one path per work-item: 24578 primitives, above the"),
            std::string::npos)
      << a.stats.lanes;
  opts.lane_traversal = 1;
  aw::RenderResult b = aw::render_wavefront(knot, opts);
  EXPECT_EQ(b.stats.lanes, "16 paths per work-item: regenerate intersect_closest(sorted) classify_hit shade_diffuse intersect_shadow accumulate");
  EXPECT_EQ(differing_words(a, b), 0u);
  aw::Scene cornell = aw::load_scene(aw_test::source_path("scenes/cornell.json"),
                                     {"render.width=16", "render.height=16", "render.spp=1"});
  opts.lane_traversal = 0;
  aw::RenderResult c = aw::render_wavefront(cornell, opts);
  EXPECT_EQ(c.stats.lanes,
            "16 paths per work-item: regenerate classify_hit shade_diffuse accumulate (the ray stages one path per work-item: "
            "--lane-traversal off)");
}

// The narrow stages' width (wavefront.cpp, narrow_lane_width): 8 only on Intel's CPU runtime where
// a SIMD register holds 8 floats (AVX2), where the ray stages and classification were measured
// faster at 8; 16 on PoCL (level or slower at 8) and with AVX-512; what the option forces, else
// a clear error.
TEST(Lanes, NarrowStagesAtEightOnlyWhereMeasuredToPay) {
  aw::DeviceInfo intel, pocl;
  intel.platform = "Intel(R) OpenCL";
  pocl.platform = "Portable Computing Language";
  intel.native_float_width = pocl.native_float_width = 8;
  EXPECT_EQ(aw::narrow_lane_width(intel, 0), 8u);
  EXPECT_EQ(aw::narrow_lane_width(pocl, 0), 16u);
  EXPECT_EQ(aw::narrow_lane_width(intel, 16), 16u);
  EXPECT_EQ(aw::narrow_lane_width(pocl, 8), 8u);
  intel.native_float_width = pocl.native_float_width = 16;
  EXPECT_EQ(aw::narrow_lane_width(intel, 0), 16u);
  EXPECT_EQ(aw::narrow_lane_width(pocl, 0), 16u);
  for (int bad : {1, 4, 32, -1}) {
    try {
      aw::narrow_lane_width(intel, bad);
      ADD_FAILURE() << bad << " was taken";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("expected 8 or 16"), std::string::npos) << e.what();
    }
  }
}

TEST(Lanes, SmallerWorkGroupsOnlyOnIntelsRuntime) {
  aw::DeviceInfo intel, pocl;
  intel.platform = "Intel(R) OpenCL";
  pocl.platform = "Portable Computing Language";
  EXPECT_EQ(aw::lane_work_group(intel), 8u);  // 2,048 paths a group
  EXPECT_EQ(aw::lane_work_group(pocl), 64u);  // 16,384
}

// What the lane program leaves out keeps the scene on the one-path kernels, and the stats say why.
TEST(Lanes, OffForWhatIsStillOnePathPerCall) {
  aw::Scene zsobol = aw::load_scene(aw_test::source_path("scenes/cornell.json"),
                                    {"render.width=16", "render.height=16", "render.spp=1", "render.sampler=zsobol"});
  aw::RenderResult r = aw::render_wavefront(zsobol, aw_test::quiet_options());
  EXPECT_EQ(r.stats.lanes, "off (the scene needs sampler_zsobol, one path per work-item still)");
  aw::Scene textured = aw::load_scene(aw_test::source_path("scenes/docs/floor_bump.json"),
                                      {"render.width=16", "render.height=16", "render.spp=1"});
  aw::RenderResult t = aw::render_wavefront(textured, aw_test::quiet_options());
  EXPECT_EQ(t.stats.lanes, "off (the scene needs texture, bump, one path per work-item still)");
  // Classification alone: its sampled split on lanes has isotropic GGX and mirrors only
  // (kernels/material/architectural.h, material_sampled_fresnel), and no fog.
  const std::string classify_off =
      "16 paths per work-item: regenerate intersect_closest shade_diffuse intersect_shadow (classify_hit one path per "
      "work-item: the scene needs ";
  // (materials.json's lobes have per-lobe samples, 8 by default: at 1 spp they split, which keeps
  // accumulate one path per call.)
  const std::string split_off = " (accumulate one path per work-item: the scene needs split)";
  aw::RenderOptions opts = aw_test::quiet_options();
  opts.lane_traversal = 1;
  opts.narrow_lanes = 16;
  for (const auto& [def, why] : std::vector<std::pair<std::string, std::string>>{
           {"", "fog, anisotropy"},
           {"materials.plastic.reflection.brdf=beckmann", "brdf_beckmann"},
           {"materials.floor.reflection.brdf=ashikhmin_shirley", "brdf_as"}}) {
    std::vector<std::string> d = {"render.width=16", "render.height=16", "render.spp=1"};
    if (!def.empty()) {  // the others without fog and anisotropy, so that only `def` keeps it off
      d.insert(d.end(), kMaterialsClassifiedOnLanes.begin(), kMaterialsClassifiedOnLanes.end());
      d.push_back(def);
    }
    aw::Scene sc = aw::load_scene(aw_test::source_path("scenes/materials.json"), d);
    EXPECT_EQ(aw::render_wavefront(sc, opts).stats.lanes, classify_off + why + ")" + split_off);
  }
}

}  // namespace
