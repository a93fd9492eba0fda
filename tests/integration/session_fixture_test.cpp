// The ctest fixture of the session tests (tests/CMakeLists.txt: FIXTURES_SETUP session_runs): makes
// the flights and runs of session_runs.hpp once, before any SessionMap or MergeSession test starts.
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "session_runs.hpp"

namespace s3m::it {
namespace {

TEST(SessionFixture, FlightsAndRunsAreMadeOnce) {
  for (const std::string& flight : {flight_a_dir(), flight_b_dir(), flight_c_dir()})
    EXPECT_TRUE(std::filesystem::exists(flight + "/gt_voxels.txt")) << flight;
  EXPECT_TRUE(std::filesystem::exists(run_a_dir() + "/slam_map.bin"));
  for (const std::string& run : {run_a(), run_c(), run_c_in_a()})
    EXPECT_TRUE(std::filesystem::exists(run + "/metrics.json")) << run;
}

}  // namespace
}  // namespace s3m::it
