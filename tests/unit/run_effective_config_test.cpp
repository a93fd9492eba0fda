// The effective config: every key written out reads back as the same config, the keys a preset
// wrote are known, and config/README.md lists every key there is (and none that is not).
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include <gtest/gtest.h>

#include "s3m/core/config_table.hpp"
#include "s3m/core/error.hpp"
#include "s3m/pipeline/config_overlays.hpp"
#include "s3m/run/effective_config.hpp"

namespace s3m::run {
namespace {

namespace fs = std::filesystem;

fs::path scratch() {
  const fs::path dir = fs::temp_directory_path() / "s3m_effective_config_test";
  fs::create_directories(dir);
  return dir;
}

std::string write_tmp(const std::string& name, const std::string& text) {
  const fs::path path = scratch() / name;
  std::ofstream(path) << text;
  return path.string();
}

// Reads effective_config_text(c) back through --config's reader.
pipeline::PipelineConfig reread(const pipeline::PipelineConfig& c, const std::string& name) {
  return pipeline::load_pipeline_config(
      write_tmp(name, effective_config_text(c, {"a note", "on two\nlines"})));
}

TEST(EffectiveConfig, ReadsBackAsTheSameConfig) {
  const std::string preset = write_tmp("preset.yaml", R"(
dataset: {camera: tum_fr2, max_dt_s: 0.03}
slam:
  T_c_r: {t: [0.1, 0.0, -0.05], q: [0.3, -0.2, 0.6, 0.7141428428542850]}
  features: {depth_window_px: 4, orb: {scale_factor: 1.3}}
  tracker: {odometry_downsample: 1, pose_rounds: 3}
  mapper: {dense_links: {max_median_m: 0.0123456789}}
loop_closing: {min_keyframes: 7, reloc: {pnp: {confidence: 0.995}}, merge: {world: first}, ransac: {seed: 42}}
flow: {integrate: all_frames, segment: integrated}
map: {fusion: {policy: bayes, alpha: 0.3}, occupancy: {prob_hit: 0.71}, insert: {max_range_m: 4.5}}
segmenter: {type: oracle, oracle: {enabled: true, similar: {chair: [sofa]}}}
threads: {deterministic: true}
overlays: [unregistered_depth]
)");
  const pipeline::PipelineConfig c = pipeline::load_pipeline_config(preset);
  const pipeline::PipelineConfig again = reread(c, "effective.yaml");
  EXPECT_EQ(config::values(again), config::values(c));
  EXPECT_EQ(again.slam.T_c_r.matrix(), c.slam.T_c_r.matrix());  // bit for bit
  EXPECT_EQ(again.map.fusion.policy, mapping::FusionPolicy::kBayesian);
  EXPECT_EQ(again.overlays, std::vector<std::string>{"unregistered_depth"});
  EXPECT_EQ(again.slam.loop_closing.loop.ransac.seed, 42u);
  // Every key is written, so every key counts as the user's: no automatic decision changes any.
  EXPECT_EQ(again.written.size(), config::values(again).size());
  // And the text is a fixed point (but for the comment naming the file read).
  pipeline::PipelineConfig renamed = again;
  renamed.source = c.source;
  EXPECT_EQ(effective_config_text(renamed), effective_config_text(c));
}

TEST(EffectiveConfig, TheDefaultsReadBackAsTheDefaults) {
  const pipeline::PipelineConfig d;
  EXPECT_EQ(config::values(reread(d, "defaults.yaml")), config::values(d));
  const std::string text = effective_config_text(d);
  EXPECT_NE(text.find("# config: built-in defaults"), std::string::npos) << text;
  EXPECT_NE(text.find("depth_discontinuity_ratio: 0.05"), std::string::npos) << text;
  EXPECT_NE(text.find("camera: \"\""), std::string::npos) << text;  // an empty string, not null
}

TEST(EffectiveConfig, PosesReadBackBitForBit) {
  // Quat(w, x, y, z): the shipped presets' (sim.yaml, realsense_d455.yaml), non-unit ones (read
  // normalised), and one with every digit of a double.
  for (const auto& q :
       {Quat(0.44499671605, 0.549525179318, -0.549525179318, 0.44499671605), Quat(0.5, 0.5, -0.5, 0.5),
        Quat(0.9, 0.1, -0.3, 0.2), Quat(0.1, 0.7, 0.2, -0.6),
        Quat(0.0, 0.0, 0.7071067811865476, 0.7071067811865476),
        Quat(0.12345678901234567, -0.6543210987654321, 0.2718281828459045, 0.6953088303787282)}) {
    pipeline::PipelineConfig c;
    c.slam.T_c_r = make_se3(Vec3(0.12, -0.034, 1.5), q);
    EXPECT_EQ(reread(c, "pose.yaml").slam.T_c_r.matrix(), c.slam.T_c_r.matrix()) << q.coeffs().transpose();
  }
}

TEST(EffectiveConfig, RelativePathsBecomeAbsolute) {
  // Read from another folder, a relative path would mean another file.
  pipeline::PipelineConfig c;
  c.dataset.camera = "cameras/cam.yaml";
  c.segmenter.model = "../models/m.yaml";
  const std::string text = effective_config_text(c);
  EXPECT_NE(text.find("camera: " + (fs::current_path() / "cameras/cam.yaml").string()), std::string::npos)
      << text;
  EXPECT_NE(text.find("model: " + (fs::current_path().parent_path() / "models/m.yaml").string()),
            std::string::npos)
      << text;
  c.dataset.camera = "7scenes_kinect_v1";  // a preset name, not a file
  EXPECT_NE(effective_config_text(c).find("camera: 7scenes_kinect_v1"), std::string::npos);
}

TEST(EffectiveConfig, TheSevenScenesRigsCameraIsInTheEffectiveConfig) {
  // The rig's camera comes with its overlay (as `s3m run` applies it to a 7-Scenes folder), so the
  // file that reruns the run names both, and the summary marks the camera automatic.
  pipeline::PipelineConfig c;
  pipeline::apply_overlay(c, "7scenes_rig", "test");
  const std::string text = effective_config_text(c);
  EXPECT_NE(text.find("camera: 7scenes_kinect_v1"), std::string::npos) << text;
  EXPECT_NE(text.find("overlays: [7scenes_rig]"), std::string::npos) << text;
  EXPECT_EQ(reread(c, "rig.yaml").dataset.camera, "7scenes_kinect_v1");
  EXPECT_NE(settings_summary(c).find("\n  dataset.camera: 7scenes_kinect_v1 (automatic)"), std::string::npos)
      << settings_summary(c);
}

TEST(EffectiveConfig, WrittenKeysAreThoseThePresetSets) {
  const pipeline::PipelineConfig c = pipeline::load_pipeline_config(
      write_tmp("written.yaml",
                "slam: {features: {depth_discontinuity_ratio: 0.05}, T_c_r: {t: [0, 0, 1]}}\n"
                "map: {fusion: {policy: paper}}\n"));
  EXPECT_EQ(c.written, (std::set<std::string>{"slam.features.depth_discontinuity_ratio", "slam.T_c_r",
                                              "map.fusion.policy"}));
}

TEST(EffectiveConfig, TheSummarySaysWhatDiffersAndWhy) {
  pipeline::PipelineConfig c =
      pipeline::pipeline_config_from_yaml(YAML::Load("cloud: {max_depth_m: 3.5}\n"), "p.yaml");
  pipeline::apply_overlay(c, "unregistered_depth", "test");
  const std::string s = settings_summary(c);
  EXPECT_NE(s.find("overlays unregistered_depth"), std::string::npos) << s;
  EXPECT_NE(s.find("\n  cloud.max_depth_m: 3.5 (written)"), std::string::npos) << s;
  EXPECT_NE(s.find("\n  slam.features.depth_discontinuity_ratio: 0.02 (automatic)"), std::string::npos) << s;
  EXPECT_EQ(s.find("max_dt_s"), std::string::npos) << s;  // at its default
  EXPECT_NE(settings_summary(pipeline::PipelineConfig{}).find("none"), std::string::npos);
}

// The first column of config/README.md's key table: "`a.b.c`, `d`" (d is a sibling of c) or
// "`a.b.*`" (every key under a.b).
std::vector<std::string> readme_keys() {
  std::ifstream in(fs::path(S3M_TEST_DATA_DIR) / ".." / ".." / "config" / "README.md");
  std::vector<std::string> keys;
  bool in_table = false;
  const std::regex name("`([^`]+)`");
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("| key |", 0) == 0) in_table = true;
    if (in_table && line.rfind("|", 0) != 0) break;  // the table's end
    if (!in_table || line.rfind("| `", 0) != 0) continue;
    const std::string cell = line.substr(2, line.find('|', 2) - 2);
    std::string parent;
    for (std::sregex_iterator m(cell.begin(), cell.end(), name), end; m != end; ++m) {
      const std::string key = (*m)[1];
      keys.push_back(parent.empty() ? key : parent + key);
      if (parent.empty()) parent = key.substr(0, key.rfind('.') + 1);
    }
  }
  return keys;
}

TEST(EffectiveConfig, TheReadmeListsEveryKeyAndNoOther) {
  const auto listed = readme_keys();
  ASSERT_GT(listed.size(), 50u);
  std::vector<std::string> keys;
  for (const auto& kv : config::values(pipeline::PipelineConfig{})) keys.push_back(kv.first);
  const auto covers = [](const std::string& row, const std::string& key) {
    if (row.size() > 2 && row.compare(row.size() - 2, 2, ".*") == 0)
      return key.rfind(row.substr(0, row.size() - 1), 0) == 0;
    return row == key;
  };
  for (const auto& row : listed)
    EXPECT_TRUE(std::any_of(keys.begin(), keys.end(), [&](const auto& k) { return covers(row, k); }))
        << "config/README.md lists '" << row << "', which is not a key";
  for (const auto& key : keys)
    EXPECT_TRUE(std::any_of(listed.begin(), listed.end(), [&](const auto& r) { return covers(r, key); }))
        << "config/README.md does not list '" << key << "'";
}

}  // namespace
}  // namespace s3m::run
