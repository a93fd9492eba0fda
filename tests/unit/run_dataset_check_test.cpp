// format_dataset_check(): the lines `s3m check` prints, from a hand-made check (exact text).
#include <gtest/gtest.h>

#include "s3m/run/dataset_check.hpp"

namespace s3m::run {
namespace {

DatasetCheck kitchen_like() {
  DatasetCheck c;
  c.dir = "seq";
  c.layout = "TUM layout";
  c.camera = *camera_preset("7scenes");
  c.camera_source = "seq/camera.yaml";
  c.frames = 100;
  c.t_first_s = 0;
  c.t_last_s = 4.3;
  c.median_step_s = 0.04;
  c.largest_gap_s = 0.5;
  c.largest_gap_after = 41;
  c.gt_poses = 90;
  c.frames_with_gt = 88;
  c.gt_path_m = 2.345;
  c.sampled = 5;
  c.unreadable = {"frame 20: rgb/x.png: cannot read"};
  c.depth_registration = "registered (dataset.depth_registration: registered)";
  c.depth_scale.median_m = 1.5;
  c.depth_scale.frames = 4;
  c.segmenter = "none (segmenter section of p.yaml)";
  return c;
}

TEST(DatasetCheck, LinesForPeople) {
  EXPECT_EQ(format_dataset_check(kitchen_like()),
            "dataset: seq (TUM layout)\n"
            "frames: 100, t 0.000 .. 4.300 s (4.3 s), median step 40.0 ms (25.0 Hz), longest 500.0 ms after "
            "frame 41\n"
            "warning: a gap of 0.50 s after frame 41: tracking may be lost there (dropped frames?)\n"
            "camera: 640x480, fx 585 fy 585 cx 320 cy 240, no distortion, depth factor 1000 (from "
            "seq/camera.yaml)\n"
            "ground truth: 90 poses, camera path 2.35 m; 88 of 100 frames have a pose\n"
            "labels: none\n"
            "sample: frames 0, 20, ... (5 read)\n"
            "warning: unreadable frame 20: rgb/x.png: cannot read\n"
            "depth: registered (dataset.depth_registration: registered)\n"
            "depth scale: median 1.50 m over 4 frame(s), plausible\n"
            "segmenter: none (segmenter section of p.yaml)\n"
            "settings: built-in defaults; differing from the defaults: none\n");
}

TEST(DatasetCheck, NoGroundTruthAndADepthScaleWarning) {
  DatasetCheck c = kitchen_like();
  c.gt_poses = c.frames_with_gt = 0;
  c.largest_gap_s = 0.05;  // within 5 median steps: no gap warning
  c.depth_scale.warning = "depth scale check: median depth 0.30 m ...";
  const std::string text = format_dataset_check(c);
  EXPECT_NE(text.find("ground truth: none (no ATE; s3m eval can score the trajectory later)\n"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("\nwarning: depth scale check: median depth 0.30 m ...\n"), std::string::npos) << text;
  EXPECT_EQ(text.find("gap"), std::string::npos) << text;
  EXPECT_EQ(text.find("plausible"), std::string::npos) << text;
}

}  // namespace
}  // namespace s3m::run
