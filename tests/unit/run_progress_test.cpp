// The live progress line of long runs.
#include <gtest/gtest.h>

#include "s3m/run/progress.hpp"

namespace s3m::run {
namespace {

TEST(ProgressLine, FormatShowsRateStateAndEta) {
  EXPECT_EQ(ProgressLine::format(50, 200, 5.0, "OK"), "frames 50/200 (25%)  10.0 fps  OK  ETA 15 s");
  EXPECT_EQ(ProgressLine::format(0, 10, 0.0, "NOT_INITIALIZED"),
            "frames 0/10 (0%)  0.0 fps  NOT_INITIALIZED  ETA --");
}

}  // namespace
}  // namespace s3m::run
