// Which segmenter a run gets without --segmenter (pipeline::choose_segmenter): the shipped real-image
// model for real cameras, the oracle for simulator sequences, the preset's choice when it has one.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include <unistd.h>

#include "s3m/core/error.hpp"
#include "s3m/pipeline/factories.hpp"
#include "s3m/pipeline/pipeline_config.hpp"

using namespace s3m;
using namespace s3m::pipeline;
namespace fs = std::filesystem;

namespace {
const fs::path kRepo = S3M_TEST_DATA_DIR "/../..";
}

TEST(SegmenterChoice, RealCameraPresetsUseTheShippedRealImageModel) {
  for (const char* preset : {"tum_fr1.yaml", "tum_fr2.yaml", "tum_fr3.yaml", "kitchen_7scenes.yaml", "realsense_d455.yaml"}) {
    SCOPED_TRACE(preset);
    const PipelineConfig config = load_pipeline_config((kRepo / "config" / preset).string());
    for (const char* sign : {"", "sim.yaml"}) {  // a preset's own section wins over the data's kind
      const SegmenterChoice c = choose_segmenter({}, config, sign);
      EXPECT_EQ(c.type, "onnx");
      EXPECT_TRUE(fs::equivalent(c.model, kRepo / kRealImageModelCard)) << c.model;
      EXPECT_EQ(c.reason, std::string("segmenter section of ") + preset);
    }
  }
  const SegmenterChoice sim = choose_segmenter({}, load_pipeline_config((kRepo / "config/sim.yaml").string()), "sim.yaml");
  EXPECT_EQ(sim.type, "oracle");
  EXPECT_EQ(sim.reason, "segmenter section of sim.yaml");
}

TEST(SegmenterChoice, AutoGivesTheOracleOnSimulatorDataAndTheRealImageModelElsewhere) {
  const PipelineConfig defaults;
  EXPECT_EQ(defaults.segmenter.type, "auto");
  const SegmenterChoice real = choose_segmenter({}, defaults, "");
  EXPECT_EQ(real.type, "onnx");
  EXPECT_TRUE(fs::equivalent(real.model, kRepo / "models/deeplabv3plus_mnv2_ade20k_fast.yaml")) << real.model;
  EXPECT_EQ(real.reason, "dataset has no sim.yaml or label images: real-camera default");
  const SegmenterChoice sim = choose_segmenter({}, defaults, "sim.yaml");
  EXPECT_EQ(sim.type, "oracle");
  EXPECT_EQ(sim.reason, "simulator sequence (sim.yaml): its ground-truth labels through the noisy oracle");
  // The command line wins, and says so.
  const SegmenterChoice none = choose_segmenter(parse_segmenter_spec("none"), defaults, "");
  EXPECT_EQ(none.type, "none");
  EXPECT_EQ(none.reason, "--segmenter none");
  const SegmenterChoice onnx = choose_segmenter(parse_segmenter_spec("onnx:my/card.yaml"), defaults, "sim.yaml");
  EXPECT_EQ(onnx.type, "onnx");
  EXPECT_EQ(onnx.model, "my/card.yaml");
  EXPECT_EQ(onnx.reason, "--segmenter onnx:my/card.yaml");
  SegmenterSpec dir_only;  // --model-dir alone: the preset's card with the files elsewhere
  dir_only.model_dir = "/models/mine";
  EXPECT_EQ(choose_segmenter(dir_only, defaults, "").model_dir, "/models/mine");
}

TEST(SegmenterChoice, SimulatorSignComesFromSimYamlOrLabelImages) {
  const fs::path dir = fs::temp_directory_path() / "s3m_simulator_sign_test";
  fs::remove_all(dir);
  fs::create_directories(dir);
  EXPECT_EQ(simulator_sign(dir.string(), false), "");
  EXPECT_EQ(simulator_sign(dir.string(), true), "ground-truth label images");
  EXPECT_EQ(simulator_sign("", false), "");  // a bag or a live stream without label images
  EXPECT_EQ(simulator_sign("", true), "ground-truth label images");
  std::ofstream(dir / "sim.yaml") << "# s3m simulated sequence\n";
  EXPECT_EQ(simulator_sign(dir.string(), false), "sim.yaml");
  fs::remove_all(dir);
}

// `s3m run SIMDIR` without --config takes the camera mount from the sequence's sim.yaml.
TEST(SimulatorCalibration, TcrIsReadFromSimYamlAndABadOneIsNamed) {
  const fs::path dir = fs::temp_directory_path() / ("s3m_sim_tcr_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  EXPECT_FALSE(simulator_T_c_r(dir.string()).has_value());  // no sim.yaml: a real camera
  {
    std::ofstream f(dir / "sim.yaml");
    // A quarter turn about x (q = [sin 45, 0, 0, cos 45]) and 10 cm along z.
    f << "scene: office\nT_c_r:\n  t_m: [0, 0, 0.1]\n  q_xyzw: [0.70710678, 0, 0, 0.70710678]\n";
  }
  const auto T = simulator_T_c_r(dir.string());
  ASSERT_TRUE(T.has_value());
  EXPECT_NEAR((T->translation() - Vec3(0, 0, 0.1)).norm(), 0, 1e-12);
  EXPECT_NEAR((*T * Vec3(0, 1, 0) - Vec3(0, 0, 1.1)).norm(), 0, 1e-7);  // y -> z, then + 0.1 z
  {
    std::ofstream f(dir / "sim.yaml");
    f << "scene: office\nT_c_r: {t_m: [0, 0]}\n";
  }
  try {
    simulator_T_c_r(dir.string());
    ADD_FAILURE() << "a sim.yaml without a readable T_c_r must be refused";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find((dir / "sim.yaml").string() + ": T_c_r"), std::string::npos) << e.what();
  }
  fs::remove_all(dir);
}
