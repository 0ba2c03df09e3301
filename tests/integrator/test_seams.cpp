// The seams between the stages, the lobes and the features (docs/architecture.md, "Where each
// stage lives", "How to add a lobe", "How to add a feature"): everything that enumerates
// lobes or features is generated from one list, the host binds stage arguments by name, and
// the shared code's invariant checks are live on the host.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>

#include "host/render/features.h"
#include "kernels/integrator/queues.h"
#include "kernels/integrator/stage_args.h"
#include "kernels/material/lobes.h"

namespace {

TEST(LobeList, QueuesFollowTheList) {
  EXPECT_EQ(int(AW_Q_COUNT), int(AW_Q_LOBE) + int(AW_LID_COUNT));
  // The ids the energy split and the scene packing index by.
  EXPECT_EQ(int(AW_LID_DIFFUSE), 0);
  EXPECT_EQ(int(AW_LID_REFRACTION), int(AW_LID_COUNT) - 1);
}

TEST(LobeList, FeatureAndTraitsOfEachLobe) {
  EXPECT_EQ(lobe_feature_bit(AW_LID_DIFFUSE), 0u);  // every build has diffuse
  EXPECT_EQ(lobe_feature_bit(AW_LID_TRANSLUCENCY), uint(AW_FEATBIT_TRANSLUCENCY));
  EXPECT_EQ(lobe_feature_bit(AW_LID_REFLECTION), uint(AW_FEATBIT_REFLECTION));
  EXPECT_EQ(lobe_feature_bit(AW_LID_REFLECTION2), uint(AW_FEATBIT_REFLECTION));
  EXPECT_EQ(lobe_feature_bit(AW_LID_REFRACTION), uint(AW_FEATBIT_REFRACTION));
  EXPECT_TRUE(lobe_traits(AW_LID_REFLECTION2) & AW_LT_REFLECTION);
  EXPECT_TRUE(lobe_traits(AW_LID_TRANSLUCENCY) & AW_LT_TRANSMIT);
  EXPECT_TRUE(lobe_traits(AW_LID_REFRACTION) & AW_LT_REFRACTION);
  EXPECT_EQ(lobe_traits(AW_LID_DIFFUSE), 0u);
  for (uint32_t lid = 0; lid < AW_LID_COUNT; ++lid) EXPECT_TRUE(lobe_compiled(lid)) << lid;  // host: generic
}

TEST(LobeList, HostFeatureSetAgreesWithTheKernelsLobeCheck) {
  aw::FeatureSet none;
  EXPECT_TRUE(none.lobe(AW_LID_DIFFUSE));
  for (uint32_t lid = 1; lid < AW_LID_COUNT; ++lid) EXPECT_FALSE(none.lobe(lid)) << lid;
  aw::FeatureSet refl;
  refl.on[aw::FeatureSet::REFLECTION] = true;
  EXPECT_TRUE(refl.lobe(AW_LID_REFLECTION));
  EXPECT_TRUE(refl.lobe(AW_LID_REFLECTION2));
  EXPECT_FALSE(refl.lobe(AW_LID_REFRACTION));
  EXPECT_TRUE(aw::FeatureSet::all().lobe(AW_LID_REFRACTION));
}

TEST(FeatureList, OneMaskDefineAndGeneratedSwitches) {
  aw::FeatureSet f;
  f.on[aw::FeatureSet::REFLECTION] = true;
  f.on[aw::FeatureSet::SPLIT] = true;
  EXPECT_EQ(f.mask(), uint32_t(AW_FEATBIT_REFLECTION | AW_FEATBIT_SPLIT));
  char want[40];
  std::snprintf(want, sizeof want, "-DAW_FEATURES=0x%08xu", unsigned(AW_FEATBIT_REFLECTION | AW_FEATBIT_SPLIT));
  EXPECT_EQ(f.defines(), want);
  EXPECT_EQ(f.describe(), "reflection split");
  EXPECT_STREQ(aw::FeatureSet::name(aw::FeatureSet::THIN_WALLED), "THIN_WALLED");
  // The host build of the kernel headers is the generic build.
  EXPECT_EQ(int(AW_FEAT_CUTOUT), 1);
  EXPECT_EQ(AW_FEAT_COMPILED_MATERIAL_MASK, (1u << AW_FEAT_MATERIAL_COUNT) - 1u);
  EXPECT_EQ(int(AW_FEAT_MATERIAL_COUNT), int(AW_FID_BUMP) + 1);  // material features first
}

TEST(StageArgs, RenderParamsFirstThenTheList) {
  EXPECT_EQ(int(AW_ARG_rp), 0);
  EXPECT_EQ(int(AW_ARG_count), 1);
  EXPECT_GT(int(AW_ARG_lights), int(AW_ARG_sf));
  EXPECT_EQ(int(AW_ARG_COUNT), int(AW_ARG_mat_resolved) + 1);
}

// The host binds stage arguments by the generated AW_ARG_* indices only (stage_args.h): a
// literal position in the render driver would silently bind the wrong buffer after a
// reordering of the list.
TEST(StageArgs, NoPositionalKernelArgumentsInTheRenderDriver) {
  namespace fs = std::filesystem;
  const std::regex literal(R"(setArg\s*\(\s*[0-9])");
  int files = 0;
  for (const auto& e : fs::directory_iterator(fs::path(ARCHWAVE_SOURCE_DIR) / "host" / "render")) {
    std::ifstream in(e.path());
    std::stringstream text;
    text << in.rdbuf();
    ++files;
    EXPECT_FALSE(std::regex_search(text.str(), literal)) << e.path() << " binds a kernel argument by position";
  }
  EXPECT_GT(files, 0);
}

// AW_KERNEL_ASSERT compiles to nothing on the device and is checked on the host, in every
// build type (kernels/common/compat.h).
TEST(KernelAssertDeathTest, AbortsNamingTheInvariantAndLine) {
  volatile int q = AW_Q_COUNT;
  EXPECT_DEATH(AW_KERNEL_ASSERT(q < AW_Q_COUNT), "kernel invariant failed: q < AW_Q_COUNT \\(.*test_seams.cpp:[0-9]+\\)");
  AW_KERNEL_ASSERT(q == AW_Q_COUNT);  // a true invariant costs nothing and does nothing
}

}  // namespace
