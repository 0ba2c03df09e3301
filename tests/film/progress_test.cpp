#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <string>

#include "host/film/progress.h"

namespace aw {
namespace {

TEST(FormatDuration, ClockStyle) {
  EXPECT_EQ(format_duration(0.0), "0:00");
  EXPECT_EQ(format_duration(3.0), "0:03");
  EXPECT_EQ(format_duration(3.99), "0:03");  // truncated like a stopwatch
  EXPECT_EQ(format_duration(62.0), "1:02");
  EXPECT_EQ(format_duration(3599.0), "59:59");
  EXPECT_EQ(format_duration(3723.0), "1:02:03");
  EXPECT_EQ(format_duration(27 * 3600.0), "27:00:00");
}

TEST(FormatDuration, SubsecondOnlyWhenAsked) {
  EXPECT_EQ(format_duration(0.35), "0:00");
  EXPECT_EQ(format_duration(0.35, true), "0.35 s");
  EXPECT_EQ(format_duration(0.0032, true), "3.20 ms");
  EXPECT_EQ(format_duration(5.0, true), "0:05");
}

TEST(FormatDuration, OddInputs) {
  EXPECT_EQ(format_duration(-2.0), "0:00");
  EXPECT_EQ(format_duration(std::numeric_limits<double>::quiet_NaN()), "--:--");
  EXPECT_EQ(format_duration(std::numeric_limits<double>::infinity()), "--:--");
}

TEST(ProgressLine, FormatLine) {
  ProgressLine p("rendering", 10'000'000, false);
  EXPECT_EQ(p.format_line(4'200'000, 3.0), "rendering  42.0%  elapsed 0:03  ETA 0:04  1.40 Msamples/s");
  EXPECT_EQ(p.format_line(0, 0.0), "rendering  0.0%  elapsed 0:00  ETA --:--  -- samples/s");
  EXPECT_EQ(p.format_line(20'000'000, 10.0),
            "rendering  100.0%  elapsed 0:10  ETA 0:00  1.00 Msamples/s");
  ProgressLine slow("bake", 1000, false);
  EXPECT_EQ(slow.format_line(500, 2.0), "bake  50.0%  elapsed 0:02  ETA 0:02  250 samples/s");
  ProgressLine empty("nothing", 0, false);
  EXPECT_EQ(empty.format_line(0, 1.0), "nothing  100.0%  elapsed 0:01  ETA 0:00  0 samples/s");
}

TEST(ProgressLine, DisabledIsSilent) {
  testing::internal::CaptureStderr();
  {
    ProgressLine p("rendering", 100, false);
    for (uint64_t i = 0; i <= 100; ++i) p.update(i);
    p.finish();
  }
  {
    ProgressLine p("rendering", 100, false);
    p.update(5);  // destroyed without finish()
  }
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
}

TEST(ProgressLine, EnabledDrawsThrottledAndEndsWithNewline) {
  testing::internal::CaptureStderr();
  {
    ProgressLine p("rendering", 1000, true);
    for (uint64_t i = 0; i <= 1000; ++i) p.update(i);
    p.finish();
    p.finish();  // second call adds nothing
  }
  const std::string out = testing::internal::GetCapturedStderr();
  ASSERT_FALSE(out.empty());
  EXPECT_EQ(out.front(), '\r');
  EXPECT_EQ(out.back(), '\n');
  EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 1);
  // 1001 updates take far less than the 200 ms redraw interval: the first update and
  // finish() draw, with slack for one redraw if the process gets descheduled.
  EXPECT_LE(std::count(out.begin(), out.end(), '\r'), 3);
  EXPECT_NE(out.find("rendering  100.0%"), std::string::npos) << out;
}

TEST(ProgressLine, DestructorEndsTheLine) {
  testing::internal::CaptureStderr();
  {
    ProgressLine p("rendering", 10, true);
    p.update(3);
  }
  const std::string out = testing::internal::GetCapturedStderr();
  EXPECT_NE(out.find("30.0%"), std::string::npos) << out;
  EXPECT_EQ(out.back(), '\n');
}

}  // namespace
}  // namespace aw
