// dataset.depth_registration: what a run changes for depth that is not registered to colour, and
// that a preset's own values and a registered sequence are left alone.
#include <fstream>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "s3m/core/error.hpp"
#include "s3m/pipeline/config_overlays.hpp"
#include "s3m/pipeline/unregistered_depth.hpp"
#include "s3m/slam/slam_config.hpp"

namespace s3m::pipeline {
namespace {

// Frames with boxes before a wall; the depth drawn through "c + s (colour - c) + shift".
class BoxesSource : public FrameSource {
 public:
  BoxesSource(double s, double dx, std::string registered_by = "", PinholeCamera cam = boxes_camera())
      : s_(s), dx_(dx), registered_by_(std::move(registered_by)), cam_(cam) {}
  static PinholeCamera boxes_camera() {
    PinholeCamera c;
    c.cx = 320, c.cy = 240;
    return c;
  }
  std::size_t size() const override { return 200; }
  RgbdFrame load(std::size_t index) const override {
    ++loads;
    RgbdFrame f;
    f.index = static_cast<int>(index);
    f.rgb = cv::Mat(480, 640, CV_8UC3, cv::Scalar(90, 100, 110));
    f.depth_m = cv::Mat(480, 640, CV_32F, cv::Scalar(3.0f));
    for (int b = 0; b < 4; ++b) {
      const int u0 = 60 + 130 * b, v0 = 80 + 40 * b + static_cast<int>(index % 7) * 5, w = 90, h = 120;
      cv::rectangle(f.rgb, cv::Rect(u0, v0, w, h), cv::Scalar(200, 60 + 40 * b, 220), cv::FILLED);
      auto d = [&](double u, double v) {
        return cv::Point(static_cast<int>(std::lround(320 + s_ * (u - 320) + dx_)),
                         static_cast<int>(std::lround(240 + s_ * (v - 240))));
      };
      cv::rectangle(f.depth_m, cv::Rect(d(u0, v0), d(u0 + w, v0 + h)), cv::Scalar(1.0 + 0.2 * b), cv::FILLED);
    }
    return f;
  }
  const PinholeCamera& camera() const override { return cam_; }
  const io::Trajectory& groundtruth() const override { return gt_; }
  bool has_labels() const override { return false; }
  std::string name() const override { return "boxes"; }
  std::string eval_dir() const override { return ""; }
  std::string depth_registered_by() const override { return registered_by_; }
  mutable int loads = 0;

 private:
  double s_, dx_;
  std::string registered_by_;
  PinholeCamera cam_;
  io::Trajectory gt_;
};

void expect_unregistered_settings(const slam::SlamConfig& s) {
  EXPECT_DOUBLE_EQ(s.features.depth_discontinuity_ratio, 0.02);
  EXPECT_EQ(s.features.depth_window_px, 3);
  EXPECT_EQ(s.features.depth_noise.model, "virtual_right");
  EXPECT_FALSE(s.mapper.dense_links.enabled);
}

void expect_defaults(const slam::SlamConfig& s) {
  const slam::SlamConfig d;
  EXPECT_DOUBLE_EQ(s.features.depth_discontinuity_ratio, d.features.depth_discontinuity_ratio);
  EXPECT_EQ(s.features.depth_window_px, d.features.depth_window_px);
  EXPECT_EQ(s.features.depth_noise.model, d.features.depth_noise.model);
  EXPECT_EQ(s.mapper.dense_links.enabled, d.mapper.dense_links.enabled);
}

TEST(UnregisteredDepth, AutoDetectsUnregisteredDepthAndSwitchesTheSlamSettings) {
  PipelineConfig c;
  BoxesSource src(1.10, 8);
  const std::string why = resolve_depth_registration(c, src);
  EXPECT_EQ(why.rfind("not registered", 0), 0u) << why;
  expect_unregistered_settings(c.slam);
  EXPECT_EQ(src.loads, 6);  // frames 0, 20, ..., 100
}

TEST(UnregisteredDepth, AutoLeavesRegisteredDepthAlone) {
  PipelineConfig c;
  BoxesSource src(1.0, 0);
  const std::string why = resolve_depth_registration(c, src);
  EXPECT_EQ(why.rfind("registered", 0), 0u) << why;
  expect_defaults(c.slam);
}

TEST(UnregisteredDepth, ASetModeIsObeyedWithoutReadingFrames) {
  PipelineConfig c;
  BoxesSource unreg(1.10, 8);
  c.dataset.depth_registration = "registered";
  resolve_depth_registration(c, unreg);
  expect_defaults(c.slam);
  EXPECT_EQ(unreg.loads, 0);
  BoxesSource reg(1.0, 0);
  c.dataset.depth_registration = "unregistered";
  EXPECT_EQ(resolve_depth_registration(c, reg).rfind(
                "not registered (dataset.depth_registration: unregistered)", 0),
            0u);
  expect_unregistered_settings(c.slam);
  EXPECT_EQ(reg.loads, 0);
}

TEST(UnregisteredDepth, ASourceThatAlignedItsDepthIsBelievedWithoutReadingFrames) {
  // A bag reader that drew a raw depth stream into the colour camera knows the answer; the edge
  // check would only measure its resampling.
  PipelineConfig c;
  BoxesSource aligned(1.10, 8, "s3m, with the recording's depth camera and extrinsics");
  EXPECT_EQ(resolve_depth_registration(c, aligned),
            "registered (aligned to colour by s3m, with the recording's depth camera and extrinsics)");
  expect_defaults(c.slam);
  EXPECT_EQ(aligned.loads, 0);
  c.dataset.depth_registration = "unregistered";  // a set mode still wins
  EXPECT_EQ(resolve_depth_registration(c, aligned)
                .rfind("not registered (dataset.depth_registration: unregistered)", 0),
            0u);
}

TEST(UnregisteredDepth, APresetsOwnValuesStay) {
  PipelineConfig c = pipeline_config_from_yaml(
      YAML::Load("slam: {features: {depth_window_px: 4, depth_discontinuity_ratio: 0.03}}"), "preset.yaml");
  const OverlayResult r = apply_overlay(c, kUnregisteredDepthOverlay, "test");
  const slam::SlamConfig& s = c.slam;
  EXPECT_EQ(s.features.depth_window_px, 4);
  EXPECT_DOUBLE_EQ(s.features.depth_discontinuity_ratio, 0.03);
  EXPECT_EQ(s.features.depth_noise.model, "virtual_right");  // not written: changed
  EXPECT_FALSE(s.mapper.dense_links.enabled);
  EXPECT_EQ(r.kept, (std::vector<std::string>{"slam.features.depth_discontinuity_ratio",
                                              "slam.features.depth_window_px"}));
  EXPECT_EQ(r.set,
            (std::vector<std::string>{"slam.features.depth_noise.model", "slam.mapper.dense_links.enabled"}));
  EXPECT_EQ(c.overlays, std::vector<std::string>{kUnregisteredDepthOverlay});
}

TEST(UnregisteredDepth, ADefaultValueWrittenOnPurposeIsNotOverridden) {
  // A preset that writes the default 0.05 keeps it on unregistered depth; without the key the
  // overlay's 0.02 applies. Comparing with a default-built struct could not tell the two apart.
  const auto resolved = [](const std::string& yaml) {
    PipelineConfig c = pipeline_config_from_yaml(YAML::Load(yaml), "preset.yaml");
    BoxesSource unregistered(1.10, 8);
    const std::string why = resolve_depth_registration(c, unregistered);
    EXPECT_EQ(why.rfind("not registered", 0), 0u) << why;
    return std::pair(c, why);
  };
  const auto [explicit_default, why] =
      resolved("slam: {features: {depth_discontinuity_ratio: 0.05}}\ncloud: {max_depth_m: 3.5}\n");
  EXPECT_DOUBLE_EQ(explicit_default.slam.features.depth_discontinuity_ratio, 0.05);
  EXPECT_EQ(explicit_default.slam.features.depth_window_px, 3);  // not written: the overlay's
  EXPECT_NE(why.find("left as the config writes them: slam.features.depth_discontinuity_ratio"),
            std::string::npos)
      << why;
  const auto [without, why2] = resolved("cloud: {max_depth_m: 3.5}\n");
  EXPECT_DOUBLE_EQ(without.slam.features.depth_discontinuity_ratio, 0.02);
  EXPECT_NE(why2.find("overlay unregistered_depth set slam.features.depth_discontinuity_ratio = 0.02"),
            std::string::npos)
      << why2;
  EXPECT_EQ(without.overlays, std::vector<std::string>{kUnregisteredDepthOverlay});
}

TEST(UnregisteredDepth, ACommandLineSettingCountsAsWritten) {
  PipelineConfig c;
  c.slam.mapper.dense_links.enabled = true;
  mark_written(c, "slam.mapper.dense_links.enabled");
  apply_overlay(c, kUnregisteredDepthOverlay, "test");
  EXPECT_TRUE(c.slam.mapper.dense_links.enabled);
  EXPECT_THROW(mark_written(c, "slam.mapper.dense_link.enabled"), Error);  // not a key
}

TEST(UnregisteredDepth, SevenScenesIntrinsicsAreRecognisedExactly) {
  PinholeCamera c = *camera_preset("7scenes");
  EXPECT_TRUE(is_seven_scenes_depth_camera(c));
  for (auto change : std::vector<void (*)(PinholeCamera&)>{
           [](PinholeCamera& k) { k.fx = 584; }, [](PinholeCamera& k) { k.fy = 525; },
           [](PinholeCamera& k) { k.cx = 319.5; }, [](PinholeCamera& k) { k.cy = 239.5; },
           [](PinholeCamera& k) { k.width = 1280; }, [](PinholeCamera& k) { k.depth_factor = 5000; },
           [](PinholeCamera& k) { k.dist[0] = 0.1; }}) {
    PinholeCamera other = c;
    change(other);
    EXPECT_FALSE(is_seven_scenes_depth_camera(other));
  }
}

TEST(UnregisteredDepth, SevenScenesDepthFoundUnregisteredIsDrawnInWithItsKinectRig) {
  const PinholeCamera nominal = *camera_preset("7scenes");
  // 1. A folder (the caller can open it again): the two cameras, the rig's settings.
  PipelineConfig c;
  BoxesSource kinect(1.106, 8, "", nominal);
  const std::string why = resolve_depth_registration(c, kinect, true);
  EXPECT_EQ(why.rfind("not registered", 0), 0u) << why;
  EXPECT_NE(why.find("camera preset 7scenes_kinect_v1"), std::string::npos) << why;
  EXPECT_EQ(c.dataset.camera, "7scenes_kinect_v1");
  const slam::SlamConfig d;
  EXPECT_DOUBLE_EQ(c.slam.features.depth_discontinuity_ratio, 0.02);
  EXPECT_EQ(c.slam.features.depth_window_px, 3);
  EXPECT_EQ(c.slam.features.depth_noise.model, d.features.depth_noise.model);  // registered depth's
  EXPECT_EQ(c.slam.mapper.dense_links.enabled, d.mapper.dense_links.enabled);
  EXPECT_EQ(c.slam.mapper.dense_links.downsample, 2);
  // 2. A source that cannot be opened again (a bag, the live node): one camera, as before.
  PipelineConfig bag;
  EXPECT_EQ(resolve_depth_registration(bag, kinect).find("7scenes_kinect_v1"), std::string::npos);
  EXPECT_EQ(bag.dataset.camera, "");
  expect_unregistered_settings(bag.slam);
  // 3. "unregistered" set by the user: one camera, no check.
  PipelineConfig set;
  set.dataset.depth_registration = "unregistered";
  resolve_depth_registration(set, kinect, true);
  EXPECT_EQ(set.dataset.camera, "");
  expect_unregistered_settings(set.slam);
  // 4. Other intrinsics: whose camera they are is unknown, so one camera.
  PipelineConfig other;
  BoxesSource not_7scenes(1.106, 8);
  resolve_depth_registration(other, not_7scenes, true);
  EXPECT_EQ(other.dataset.camera, "");
  expect_unregistered_settings(other.slam);
  // 5. 7-Scenes' intrinsics with registered depth: nothing changes.
  PipelineConfig registered;
  BoxesSource aligned(1.0, 0, "", nominal);
  EXPECT_EQ(resolve_depth_registration(registered, aligned, true).rfind("registered", 0), 0u);
  EXPECT_EQ(registered.dataset.camera, "");
  expect_defaults(registered.slam);
}

TEST(UnregisteredDepth, TheRigsCameraIsItsOverlaysAndACameraTheConfigWritesStays) {
  BoxesSource kinect(1.106, 8, "", *camera_preset("7scenes"));
  // The switch to the two cameras is the overlay's: said with what it set, listed in overlays.
  PipelineConfig c;
  const std::string why = resolve_depth_registration(c, kinect, true);
  EXPECT_NE(why.find("overlay 7scenes_rig set dataset.camera = 7scenes_kinect_v1, slam.features."),
            std::string::npos)
      << why;
  EXPECT_EQ(c.overlays, std::vector<std::string>{kSevenScenesRigOverlay});
  // A camera the config writes, even the one-camera preset these intrinsics are, stays; its depth
  // is then read as one camera's.
  PipelineConfig written =
      pipeline_config_from_yaml(YAML::Load("dataset: {camera: 7scenes}\n"), "preset.yaml");
  const std::string why2 = resolve_depth_registration(written, kinect, true);
  EXPECT_EQ(written.dataset.camera, "7scenes") << why2;
  EXPECT_EQ(written.overlays, std::vector<std::string>{kUnregisteredDepthOverlay}) << why2;
  expect_unregistered_settings(written.slam);
  // Listed by a preset, the overlay leaves the preset's camera too.
  PipelineConfig listed =
      pipeline_config_from_yaml(YAML::Load("dataset: {camera: tum_fr1}\n"), "preset.yaml");
  const OverlayResult r = apply_overlay(listed, kSevenScenesRigOverlay, "test");
  EXPECT_EQ(listed.dataset.camera, "tum_fr1");
  EXPECT_EQ(r.kept, std::vector<std::string>{"dataset.camera"});
  EXPECT_NE(describe(r, listed).find("left as the config writes them: dataset.camera"), std::string::npos);
}

TEST(UnregisteredDepth, TheRigSettingsAreThoseOfTheKitchenPreset) {
  // `s3m run DIR` without a preset must track a 7-Scenes folder as config/kitchen_7scenes.yaml does.
  const PipelineConfig kitchen =
      load_pipeline_config(std::string(S3M_TEST_DATA_DIR) + "/../../config/kitchen_7scenes.yaml");
  EXPECT_EQ(kitchen.dataset.camera, "7scenes_kinect_v1");
  PipelineConfig applied;
  apply_overlay(applied, kSevenScenesRigOverlay, "test");
  EXPECT_EQ(applied.dataset.camera, kitchen.dataset.camera);
  const slam::SlamConfig& k = kitchen.slam;
  EXPECT_DOUBLE_EQ(applied.slam.features.depth_discontinuity_ratio, k.features.depth_discontinuity_ratio);
  EXPECT_EQ(applied.slam.features.depth_window_px, k.features.depth_window_px);
  EXPECT_EQ(applied.slam.features.depth_noise.model, k.features.depth_noise.model);
  EXPECT_EQ(applied.slam.mapper.dense_links.enabled, k.mapper.dense_links.enabled);
  EXPECT_EQ(applied.slam.mapper.dense_links.downsample, k.mapper.dense_links.downsample);
}

TEST(UnregisteredDepth, TheOverlaysAreTheShippedFiles) {
  // The library carries config/overlays/ built in; a stale build would silently use old values.
  EXPECT_EQ(overlay_names(), (std::vector<std::string>{"7scenes_rig", "unregistered_depth"}));
  for (const std::string& name : overlay_names()) {
    SCOPED_TRACE(name);
    const std::string path = std::string(S3M_TEST_DATA_DIR) + "/../../config/overlays/" + name + ".yaml";
    std::ifstream in(path);
    EXPECT_EQ(overlay_text(name), std::string(std::istreambuf_iterator<char>(in), {}));
    // Each is also a preset of its own, and a SLAM config (bench_slam_kitchen --config).
    EXPECT_NO_THROW(load_pipeline_config(path).validate());
    EXPECT_NO_THROW(slam::load_slam_config(path));
  }
  PipelineConfig c;
  EXPECT_THROW(apply_overlay(c, "registered_depth", "test"), Error);
}

TEST(UnregisteredDepth, APresetMayListAnOverlay) {
  const PipelineConfig c = pipeline_config_from_yaml(
      YAML::Load("overlays: [unregistered_depth]\nslam: {features: {depth_window_px: 4}}\n"), "preset.yaml");
  EXPECT_EQ(c.slam.features.depth_window_px, 4);
  EXPECT_DOUBLE_EQ(c.slam.features.depth_discontinuity_ratio, 0.02);
  EXPECT_TRUE(c.written.count("slam.features.depth_discontinuity_ratio"));  // chosen by the preset
  EXPECT_THROW(pipeline_config_from_yaml(YAML::Load("overlays: [sometimes]\n"), "preset.yaml"), ParseError);
}

TEST(UnregisteredDepth, ModeIsValidated) {
  PipelineConfig c;
  EXPECT_EQ(c.dataset.depth_registration, "auto");
  c.dataset.depth_registration = "sometimes";
  EXPECT_THROW(c.validate(), Error);
}

}  // namespace
}  // namespace s3m::pipeline
