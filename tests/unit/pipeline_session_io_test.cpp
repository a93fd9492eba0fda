// kept_clouds.bin (issue 23): the clouds a run's semantic map is built from come back exactly —
// anchors, relative poses, points, colours, top-k labels — and bad files name the file.
#include <filesystem>
#include <fstream>
#include <iterator>

#include <gtest/gtest.h>
#include <unistd.h>

#include "s3m/core/error.hpp"
#include "s3m/pipeline/session_io.hpp"

namespace s3m::pipeline {
namespace {

namespace fs = std::filesystem;

mapping::LabeledCloud cloud(int n, int k, bool colour) {
  mapping::LabeledCloud c;
  c.origin = Eigen::Vector3f(0.5f, -1, 2);
  c.k = k;
  std::vector<ClassId> labels(static_cast<std::size_t>(k));
  std::vector<float> probs(static_cast<std::size_t>(k));
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < k; ++j) labels[std::size_t(j)] = ClassId(i + j), probs[std::size_t(j)] = 0.5f / float(j + 1);
    c.push_back(Eigen::Vector3f(float(i), 0.25f * float(i), -float(i)), std::uint8_t(i), 7, 200, labels.data(),
                probs.data());
  }
  if (!colour) c.rgb.clear();
  return c;
}

TEST(SessionIo, KeptCloudsRoundTripExactly) {
  KeyframeStore s;
  s.note_keyframe(0, make_se3(Vec3(0, 0, 0), Quat::Identity()));
  s.note_keyframe(3, make_se3(Vec3(1, 2, 0.5), Quat(Eigen::AngleAxisd(0.3, Vec3::UnitZ()))));
  s.add(0, s.keyframes().at(0), 0, cloud(5, 3, true));
  s.add(3, s.keyframes().at(3) * make_se3(Vec3(0.1, 0, 0), Quat::Identity()), 7, cloud(4, 0, false));
  const fs::path p = fs::temp_directory_path() / ("s3m_session_io_" + std::to_string(::getpid()) + ".bin");
  save_kept_clouds(p.string(), s);
  KeyframeStore back;
  load_kept_clouds(p.string(), back);
  ASSERT_EQ(back.size(), 2u);
  EXPECT_EQ(back.keyframes().size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    const KeptCloud &a = s.clouds()[i], &b = back.clouds()[i];
    EXPECT_EQ(a.anchor.keyframe, b.anchor.keyframe);
    EXPECT_TRUE(a.anchor.T_kf_c.isApprox(b.anchor.T_kf_c, 0.0));
    EXPECT_EQ(a.frame_index, b.frame_index);
    EXPECT_EQ(a.cloud.points, b.cloud.points);
    EXPECT_EQ(a.cloud.origin, b.cloud.origin);
    EXPECT_EQ(a.cloud.rgb, b.cloud.rgb);
    EXPECT_EQ(a.cloud.k, b.cloud.k);
    EXPECT_EQ(a.cloud.labels, b.cloud.labels);
    EXPECT_EQ(a.cloud.probs, b.cloud.probs);
    EXPECT_TRUE(s.T_w_c(a).isApprox(back.T_w_c(b), 0.0));
  }
  // Keyframes outside the world (a SLAM sub-map that never merged) and their clouds are not saved.
  s.note_keyframe(9, SE3::Identity(), /*detached=*/true);
  s.add(9, SE3::Identity(), 9, cloud(2, 1, true));
  save_kept_clouds(p.string(), s);
  KeyframeStore world;
  load_kept_clouds(p.string(), world);
  EXPECT_EQ(world.size(), 2u);
  EXPECT_EQ(world.keyframes().count(9), 0u);
  save_kept_clouds(p.string(), back);
  // Truncated and foreign files name the file.
  std::string bytes;
  {
    std::ifstream in(p, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  std::ofstream(p, std::ios::binary) << bytes.substr(0, bytes.size() - 20);
  KeyframeStore bad;
  try {
    load_kept_clouds(p.string(), bad);
    ADD_FAILURE() << "a truncated file must not load";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.file(), p.string());
    EXPECT_NE(std::string(e.what()).find("truncated"), std::string::npos) << e.what();
  }
  std::ofstream(p, std::ios::binary) << "S3MSLAM\0 something else";
  KeyframeStore bad2;
  EXPECT_THROW(load_kept_clouds(p.string(), bad2), ParseError);
  fs::remove(p);
}

}  // namespace
}  // namespace s3m::pipeline
