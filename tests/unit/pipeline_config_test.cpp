// PipelineConfig: defaults validate, YAML presets load, bad values are refused naming file and key.
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "s3m/core/error.hpp"
#include "s3m/pipeline/pipeline_config.hpp"

namespace s3m::pipeline {
namespace {

std::string write_tmp(const std::string& name, const std::string& text) {
  const auto dir = std::filesystem::temp_directory_path() / "s3m_pipeline_config_test";
  std::filesystem::create_directories(dir);
  const auto path = (dir / name).string();
  std::ofstream(path) << text;
  return path;
}

std::string error_of(const std::string& yaml) {
  try {
    load_pipeline_config(write_tmp("bad.yaml", yaml));
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(PipelineConfig, DefaultsValidate) { EXPECT_NO_THROW(PipelineConfig{}.validate()); }

TEST(PipelineConfig, LoadsValuesAndKeepsDefaultsForAbsentKeys) {
  const auto c = load_pipeline_config(write_tmp("ok.yaml", R"(
cloud:
  max_depth_m: 3.5
  pixel_stride: 4
slam:
  T_c_r: {t: [0.1, 0.0, -0.05], q: [0.0, 0.0, 0.7071067811865476, 0.7071067811865476]}
threads: {deterministic: true, queue_capacity: 8}
flow: {integrate: all_frames, segment: integrated}
dataset: {depth_registration: unregistered}
map: {keep_session_surfaces: false}
)"));
  EXPECT_FALSE(c.map.keep_session_surfaces);
  EXPECT_TRUE(PipelineConfig{}.map.keep_session_surfaces);
  EXPECT_DOUBLE_EQ(c.cloud.max_depth_m, 3.5);
  EXPECT_EQ(c.dataset.depth_registration, "unregistered");
  EXPECT_EQ(PipelineConfig{}.dataset.depth_registration, "auto");
  EXPECT_EQ(c.cloud.pixel_stride, 4);
  EXPECT_DOUBLE_EQ(c.cloud.min_depth_m, CloudConfig{}.min_depth_m);
  EXPECT_TRUE(c.threads.deterministic);
  EXPECT_EQ(c.threads.queue_capacity, 8);
  EXPECT_EQ(c.flow.integrate, IntegrateMode::kAllFrames);
  EXPECT_EQ(c.flow.segment, SegmentMode::kIntegrated);
  // 90 deg about z: the robot's x axis is the camera's y axis.
  const SE3 T = c.slam.T_c_r;
  EXPECT_NEAR((T.linear() * Vec3::UnitX() - Vec3::UnitY()).norm(), 0.0, 1e-12);
  EXPECT_NEAR((T.translation() - Vec3(0.1, 0.0, -0.05)).norm(), 0.0, 1e-12);
}

TEST(PipelineConfig, ErrorsNameFileLineAndExpectation) {
  std::string e = error_of("cloud:\n  max_depth_m: far\n");
  EXPECT_NE(e.find("bad.yaml:2"), std::string::npos) << e;
  EXPECT_NE(e.find("max_depth_m"), std::string::npos) << e;

  e = error_of("cloud:\n  max_dept_m: 3\n");  // typo
  EXPECT_NE(e.find("unknown key 'max_dept_m'"), std::string::npos) << e;
  EXPECT_NE(e.find("max_depth_m"), std::string::npos) << e;  // the list of valid keys

  e = error_of("cloud:\n  min_depth_m: 5\n  max_depth_m: 4\n");
  EXPECT_NE(e.find("bad.yaml"), std::string::npos) << e;
  EXPECT_NE(e.find("cloud.max_depth_m"), std::string::npos) << e;

  e = error_of("flow:\n  integrate: sometimes\n");
  EXPECT_NE(e.find("keyframes | all_frames"), std::string::npos) << e;

  e = error_of("map:\n  fusion:\n    policy: vote\n");
  EXPECT_NE(e.find("vote"), std::string::npos) << e;

  e = error_of("segmenter:\n  type: magic\n");
  EXPECT_NE(e.find("segmenter.type must be auto | onnx | oracle | none"), std::string::npos) << e;

  e = error_of("dataset:\n  depth_registration: maybe\n");
  EXPECT_NE(e.find("dataset.depth_registration must be auto | registered | unregistered (got 'maybe')"),
            std::string::npos)
      << e;

  e = error_of("dynamic:\n  classes: [person, ghost]\n");
  EXPECT_NE(e.find("dynamic.classes: 'ghost' is not a class"), std::string::npos) << e;
  EXPECT_NE(e.find("bad.yaml"), std::string::npos) << e;

  e = error_of("threads: 4\n");
  EXPECT_NE(e.find("section 'threads' is not a map"), std::string::npos) << e;

  e = error_of("cloud: [1\n");
  EXPECT_NE(e.find("YAML syntax error"), std::string::npos) << e;
}

TEST(PipelineConfig, DynamicClassesAreOffUnlessEnabled) {
  DynamicConfig d;
  EXPECT_TRUE(d.map_exclusions().empty());
  EXPECT_FALSE(d.masks_tracking());
  d.enabled = true;
  EXPECT_EQ(d.map_exclusions(), std::vector<ClassId>{cls::kPerson});
  EXPECT_TRUE(d.masks_tracking());
  d.keep_in_map = true;
  EXPECT_TRUE(d.map_exclusions().empty());
  d.classes = {"person", "chair"};
  EXPECT_EQ(d.class_ids(), (std::vector<ClassId>{cls::kPerson, cls::kChair}));
}

TEST(PipelineConfig, MissingFileIsAClearError) {
  try {
    load_pipeline_config("/nonexistent/preset.yaml");
    FAIL();
  } catch (const ParseError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/preset.yaml"), std::string::npos);
  }
}

TEST(PipelineConfig, EveryShippedPresetLoads) {
  // config/ also holds other modules' files (simulator, mapping, SLAM settings): test the presets.
  const auto dir = std::filesystem::path(S3M_TEST_DATA_DIR) / ".." / ".." / "config";
  for (const char* name : {"sim", "tum_fr1", "tum_fr2", "tum_fr3", "realsense_d455", "kitchen_7scenes"}) {
    SCOPED_TRACE(name);
    const PipelineConfig c = load_pipeline_config((dir / (std::string(name) + ".yaml")).string());
    EXPECT_NO_THROW(c.validate());
  }
  // The preset's camera file is resolved next to the preset.
  const auto d455 = load_pipeline_config((dir / "realsense_d455.yaml").string());
  EXPECT_TRUE(std::filesystem::exists(d455.dataset.camera)) << d455.dataset.camera;
}

TEST(PipelineConfig, ACopiedPresetStillFindsTheShippedFilesItNames) {
  // The usual way to make one's own preset: copy a shipped one elsewhere and edit it. Its relative
  // "../models/..." and "cameras/..." then point at nothing beside the copy: the shipped files are
  // meant, and used. A file beside the copy wins.
  namespace fs = std::filesystem;
  const fs::path config = fs::path(S3M_TEST_DATA_DIR) / ".." / ".." / "config";
  const fs::path dir = fs::temp_directory_path() / "s3m_pipeline_config_copy";
  fs::remove_all(dir);
  fs::create_directories(dir);
  for (const char* name : {"kitchen_7scenes.yaml", "realsense_d455.yaml"})
    fs::copy(config / name, dir / name);
  const PipelineConfig kitchen = load_pipeline_config((dir / "kitchen_7scenes.yaml").string());
  EXPECT_TRUE(fs::equivalent(kitchen.segmenter.model,
                             config / ".." / "models" / "deeplabv3plus_mnv2_ade20k_fast.yaml"))
      << kitchen.segmenter.model;
  const PipelineConfig d455 = load_pipeline_config((dir / "realsense_d455.yaml").string());
  EXPECT_TRUE(fs::equivalent(d455.dataset.camera, config / "cameras" / "realsense_d455_640x480.yaml"))
      << d455.dataset.camera;
  fs::create_directories(dir / "cameras");
  fs::copy(config / "cameras" / "realsense_d455_640x480.yaml",
           dir / "cameras" / "realsense_d455_640x480.yaml");
  EXPECT_EQ(load_pipeline_config((dir / "realsense_d455.yaml").string()).dataset.camera,
            (dir / "cameras" / "realsense_d455_640x480.yaml").string());
  // A file that is neither beside it nor shipped stays where the preset says, for the error to name.
  std::ofstream(dir / "own.yaml") << "segmenter: {type: onnx, model: ../nowhere/m.yaml}\n";
  EXPECT_EQ(load_pipeline_config((dir / "own.yaml").string()).segmenter.model,
            (dir.parent_path() / "nowhere" / "m.yaml").string());
  fs::remove_all(dir);
}

}  // namespace
}  // namespace s3m::pipeline

namespace s3m::pipeline {
namespace {

// Found by fuzzing (tests/fuzz/regress/pipeline_config/section_given_as_scalar.yaml): a nested
// section given as a value escaped as yaml-cpp's "operator[] call on a scalar".
TEST(PipelineConfig, NestedSectionGivenAsAValueIsAParseError) {
  const std::string a = error_of("map:\n  resolution_m: 0.05\n  insert: nan\n");
  EXPECT_NE(a.find("bad.yaml:3: a value ('nan') where a section is expected"), std::string::npos) << a;
  EXPECT_NE(a.find("min_range_m"), std::string::npos) << a;  // lists the keys the section takes
  const std::string b = error_of("slam:\n  tracker: [1, 2]\n");
  EXPECT_NE(b.find("bad.yaml:2: a list where a section is expected"), std::string::npos) << b;
  const std::string c = error_of("segmenter:\n  oracle: true\n");
  EXPECT_NE(c.find("a value ('true') where a section is expected"), std::string::npos) << c;
}

}  // namespace
}  // namespace s3m::pipeline
