// Absurd settings are refused before they crash or exhaust the machine (issue 24): thread counts in
// presets and model cards, and the map's cost estimate (exact values computed by hand).
#include <filesystem>
#include <fstream>

#include <unistd.h>

#include <gtest/gtest.h>

#include "s3m/core/error.hpp"
#include "s3m/core/thread_count.hpp"
#include "s3m/io/camera_yaml.hpp"
#include "s3m/pipeline/cost_estimate.hpp"
#include "s3m/pipeline/pipeline_config.hpp"
#include "s3m/semantics/model_card.hpp"

namespace s3m::pipeline {
namespace {

namespace fs = std::filesystem;

const fs::path kConfigDir = fs::path(S3M_TEST_DATA_DIR) / ".." / ".." / "config";

std::string write_tmp(const std::string& name, const std::string& text) {
  const auto dir = fs::temp_directory_path() / ("s3m_pipeline_limits_test_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const auto path = (dir / name).string();
  std::ofstream(path) << text;
  return path;
}

template <typename F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

void expect_contains(const std::string& msg, std::initializer_list<std::string> fragments) {
  for (const auto& f : fragments) EXPECT_NE(msg.find(f), std::string::npos) << msg << "\nmissing: " << f;
}

TEST(PipelineLimits, PresetWithAHugeInsertThreadCountIsRefused) {
  // 65537 segfaulted inside TBB on 2f6b067 (TBB printed that it limits workers, then crashed).
  const std::string path = write_tmp("threads.yaml", "map:\n  insert: {num_threads: 65537}\n");
  const std::string e = error_of([&] { load_pipeline_config(path); });
  expect_contains(e, {path + ":", "insert.num_threads = 65537", "must be 0 (all cores) or 1..",
                      std::to_string(max_thread_count())});
  EXPECT_NE(error_of([&] { load_pipeline_config(write_tmp("neg.yaml", "map: {insert: {num_threads: -1}}\n")); })
                .find("insert.num_threads = -1"),
            std::string::npos);
  const std::string max = std::to_string(max_thread_count());
  EXPECT_EQ(load_pipeline_config(write_tmp("max.yaml", "map: {insert: {num_threads: " + max + "}}\n")).map.insert.num_threads,
            max_thread_count());
  // Set in code (no file): validate() still names the key and the range.
  PipelineConfig c;
  c.map.insert.num_threads = 100000;
  EXPECT_NE(error_of([&] { c.validate(); }).find("insert.num_threads = 100000 must be 0 (all cores) or 1.."),
            std::string::npos);
}

TEST(PipelineLimits, ModelCardWithAHugeThreadCountIsRefused) {
  const std::string card = "model: m.onnx\nclasses: c.txt\ninput: {width: 16, height: 16}\nthreads: ";
  const std::string path = write_tmp("card.yaml", card + "65537\n");
  const std::string e = error_of([&] { semantics::load_model_card(path); });
  expect_contains(e, {path + ":", "threads = 65537 out of range", "expected 0 (OpenCV's default) or 1..",
                      std::to_string(max_thread_count())});
  EXPECT_EQ(semantics::load_model_card(write_tmp("card2.yaml", card + "2\n")).threads, 2);
}

PinholeCamera camera_640x480_f500() {
  PinholeCamera cam;
  cam.width = 640, cam.height = 480, cam.fx = cam.fy = 500, cam.cx = 319.5, cam.cy = 239.5;
  return cam;
}

TEST(PipelineLimits, CostEstimateOfTheDefaultsByHand) {
  // Stride 2: 320 x 240 = 76800 rays; min(max_depth 4, max_range 4) = 4 m / 0.05 = 80 voxels each;
  // view pyramid (4 / 0.05)^3 * (640/500) * (480/500) / 3 = 512000 * 0.4096 = 209715.2 voxels.
  const CostEstimate e = estimate_cost(PipelineConfig{}, camera_640x480_f500());
  EXPECT_DOUBLE_EQ(e.rays, 76800);
  EXPECT_DOUBLE_EQ(e.ray_length_m, 4.0);
  EXPECT_DOUBLE_EQ(e.voxels_per_ray, 80);
  EXPECT_NEAR(e.frustum_voxels, 209715.2, 1e-6);
  EXPECT_NEAR(e.voxel_updates, 209715.2, 1e-6);  // the pyramid, not 76800 * 80 = 6144000
  EXPECT_NEAR(e.map_bytes, 209715.2 * 74, 1e-3);
  EXPECT_DOUBLE_EQ(e.cloud_bytes, 76800.0 * (12 + 3 + 3 * (2 + 4)));  // xyz, rgb, top-3 (id, p)
  EXPECT_NEAR(e.kept_clouds, 256e6 / 2534400.0, 1e-9);
  EXPECT_DOUBLE_EQ(e.map_extent_m, 3276.8);
  EXPECT_NO_THROW(check_cost(PipelineConfig{}, camera_640x480_f500(), false));
}

PipelineConfig issue_24_settings() {  // config/sim.yaml with the issue's three keys
  PipelineConfig c = load_pipeline_config((kConfigDir / "sim.yaml").string());
  c.cloud.pixel_stride = 1;
  c.map.resolution_m = 0.005;
  c.cloud.max_depth_m = 100;
  return c;
}

TEST(PipelineLimits, TheIssuesSettingsAreRefusedUnlessForced) {
  const PipelineConfig c = issue_24_settings();
  const CostEstimate e = estimate_cost(c, camera_640x480_f500());
  // 640 x 480 rays; rays end at map.insert.max_range_m 5 (sim.yaml): 5 / 0.005 = 1000 voxels each;
  // the pyramid holds 1000^3 * 0.4096 = 4.096e8, so the rays bound it: 3.072e8.
  EXPECT_DOUBLE_EQ(e.rays, 307200);
  EXPECT_DOUBLE_EQ(e.ray_length_m, 5.0);
  EXPECT_NEAR(e.voxels_per_ray, 1000, 1e-9);
  EXPECT_NEAR(e.frustum_voxels, 4.096e8, 1e-3);
  EXPECT_NEAR(e.voxel_updates, 3.072e8, 1e-3);
  EXPECT_GT(e.voxel_updates, kMaxVoxelUpdates);
  const std::string msg = error_of([&] { check_cost(c, camera_640x480_f500(), false); });
  expect_contains(msg, {"cloud.pixel_stride 1 x 640x480 px", "map.resolution_m 0.005", "cloud.max_depth_m 100",
                        "map.insert.max_range_m 5", "about 3.1e+08 voxel updates per integrated frame",
                        "limit of 1e+08", "--force"});
  EXPECT_NO_THROW(check_cost(c, camera_640x480_f500(), true));
}

TEST(PipelineLimits, StrideRoundsUpAndNoFreeSpaceMeansOneVoxelPerRay) {
  PipelineConfig c;
  c.cloud.pixel_stride = 3;  // u = 0, 3, ..., 639: 214 columns; v: 160 rows
  c.map.insert.clear_free_space = false;
  const CostEstimate e = estimate_cost(c, camera_640x480_f500());
  EXPECT_DOUBLE_EQ(e.rays, 214.0 * 160.0);
  EXPECT_DOUBLE_EQ(e.voxels_per_ray, 1);
  EXPECT_DOUBLE_EQ(e.voxel_updates, 34240);
  c.cloud.kept_clouds_budget_mb = 0;  // unlimited
  EXPECT_DOUBLE_EQ(estimate_cost(c, camera_640x480_f500()).kept_clouds, 0);
}

TEST(PipelineLimits, EveryShippedPresetIsFarBelowTheWarningLevel) {
  for (const char* name : {"sim", "tum_fr1", "tum_fr2", "tum_fr3", "realsense_d455", "kitchen_7scenes"}) {
    SCOPED_TRACE(name);
    const PipelineConfig c = load_pipeline_config((kConfigDir / (std::string(name) + ".yaml")).string());
    // "" = the sequence's camera: the simulator's 640x480, fx = 525 (the kitchen's 585 is narrower).
    const PinholeCamera cam = c.dataset.camera.empty() ? PinholeCamera{} : io::load_camera(c.dataset.camera);
    const CostEstimate e = estimate_cost(c, cam);
    EXPECT_LT(e.voxel_updates, kWarnVoxelUpdates / 10) << e.voxel_updates;
    EXPECT_GT(e.kept_clouds, 50);
    EXPECT_NO_THROW(check_cost(c, cam, false));
  }
}

}  // namespace
}  // namespace s3m::pipeline
