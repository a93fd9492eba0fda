// slam_map.bin (issue 23): a map built by SLAM on a rendered room flight saves, loads and saves
// again to the same bytes; the loaded map relocalises every keyframe image; bad files (missing,
// truncated, foreign, other version, corrupt, inconsistent, other camera, other vocabulary) stop
// with a ParseError naming the file and the problem. A second session over the same room
// (System::load_map) starts relocalised, reports poses in the first session's world, and with
// localize_only adds nothing (the map saves to the bytes it was loaded from).
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>

#include <gtest/gtest.h>
#include <unistd.h>

#include "s3m/core/byte_io.hpp"
#include "s3m/core/error.hpp"
#include "s3m/features/bow_vocabulary.hpp"
#include "s3m/slam/io/map_io.hpp"
#include "s3m/slam/system.hpp"
#include "s3m/slam/tracking/reloc.hpp"
#include "slam_synthetic_room.hpp"

namespace fs = std::filesystem;

namespace s3m::slam {
namespace {

constexpr int kFrames = 60;

using test::room_camera;

RgbdFrame room_frame(int i) {
  return test::render_room(test::Room{}, room_camera(), test::uav_pose(i, 4 * kFrames), i, i / 30.0, 0.002);
}

std::shared_ptr<const features::Vocabulary> vocabulary() {
  static const auto v = std::make_shared<const features::Vocabulary>(
      features::Vocabulary::load(features::default_vocabulary_path()));
  return v;
}

// The map SLAM builds on a quarter of the room circuit, its BoW index and one loop edge (the
// file stores loop edges; this short flight closes none).
struct Built {
  Map map;
  KeyFrameBowIndex index{vocabulary()};
  LoopEdges loops;
};

const Built& built() {
  static const Built b = [] {
    System slam(room_camera(), SlamConfig{});
    for (int i = 0; i < kFrames; ++i) slam.track(room_frame(i));
    slam.finish();
    Built out{slam.map(), KeyFrameBowIndex(vocabulary()), {}};
    out.index.sync(out.map);
    out.loops = {{out.map.keyframes().rbegin()->first, out.map.keyframes().begin()->first}};
    return out;
  }();
  return b;
}

fs::path temp_file(const std::string& name) {
  return fs::temp_directory_path() / ("s3m_map_io_" + name + "_" + std::to_string(::getpid()) + ".bin");
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

void write(const fs::path& p, const std::string& bytes) { std::ofstream(p, std::ios::binary) << bytes; }

// The message of the ParseError load_slam_map throws for path ("" when it loads).
std::string load_error(const fs::path& path, const PinholeCamera& camera = room_camera(),
                       std::shared_ptr<const features::Vocabulary> vocab = vocabulary()) {
  try {
    load_slam_map(path.string(), camera, std::move(vocab));
  } catch (const ParseError& e) {
    EXPECT_EQ(e.file(), path.string());
    return e.what();
  }
  return "";
}

TEST(SlamMapIo, SaveLoadSaveGivesIdenticalBytes) {
  const Built& b = built();
  ASSERT_GE(b.map.n_keyframes(), 5);
  ASSERT_GE(b.map.n_points(), 500);
  const fs::path a = temp_file("a"), c = temp_file("c");
  save_slam_map(a.string(), b.map, b.index, b.loops, room_camera());
  const LoadedSlamMap m = load_slam_map(a.string(), room_camera(), vocabulary());
  save_slam_map(c.string(), m.map, m.index, m.loop_edges, m.camera);
  const std::string bytes = slurp(a);
  EXPECT_EQ(bytes, slurp(c));
  EXPECT_EQ(bytes, serialise_slam_map(b.map, b.index, b.loops, room_camera()));
  // What the bytes stand for came back too: ids, poses, observations, graph, BoW index.
  EXPECT_EQ(m.map.n_keyframes(), b.map.n_keyframes());
  EXPECT_EQ(m.map.n_points(), b.map.n_points());
  EXPECT_EQ(m.map.last_keyframe_id(), b.map.last_keyframe_id());
  EXPECT_EQ(m.loop_edges, b.loops);
  EXPECT_EQ(m.index.size(), b.index.size());
  for (const auto& [id, kf] : b.map.keyframes()) {
    const KeyFrame& k = m.map.keyframe(id);
    EXPECT_TRUE(k.T_w_c.isApprox(kf.T_w_c, 0.0));
    EXPECT_EQ(k.points, kf.points);
    EXPECT_EQ(k.covisibility, kf.covisibility);
    EXPECT_EQ(k.parent, kf.parent);
    EXPECT_EQ(cv::norm(k.features->descriptors, kf.features->descriptors, cv::NORM_INF), 0.0);
    EXPECT_EQ(k.features->in_area(320, 240, 40), kf.features->in_area(320, 240, 40)) << "grid rebuilt";
    EXPECT_EQ(m.index.find(id)->bow, b.index.find(id)->bow);
    EXPECT_EQ(m.index.find(id)->direct, b.index.find(id)->direct);
  }
  for (const auto& [pid, p] : b.map.points()) {
    EXPECT_EQ(m.map.point(pid).observations, p.observations);
    EXPECT_EQ(m.map.point(pid).descriptor, p.descriptor);
  }
  // A session matching at another direct-index level recomputes the index: same BoW vectors.
  const LoadedSlamMap other_level = load_slam_map(a.string(), room_camera(), vocabulary(), 3);
  for (const auto& [id, kf] : b.map.keyframes())
    EXPECT_EQ(other_level.index.find(id)->bow, b.index.find(id)->bow);
  fs::remove(a);
  fs::remove(c);
}

TEST(SlamMapIo, LoadedMapRelocalisesEveryKeyframeImage) {
  const fs::path a = temp_file("reloc");
  save_slam_map(a.string(), built().map, built().index, built().loops, room_camera());
  const LoadedSlamMap m = load_slam_map(a.string(), room_camera(), vocabulary());
  const SlamConfig cfg;
  const features::OrbExtractor orb(cfg.features.orb);
  int n = 0;
  for (const auto& [id, kf] : m.map.keyframes()) {
    const RgbdFrame f = room_frame(kf.frame_index);
    const auto feats = features::compute_frame_features(f.rgb, f.depth_m, room_camera(), orb, cfg.features);
    const RelocResult r = relocalise(feats, m.map, m.index, room_camera());
    ASSERT_TRUE(r.success) << "keyframe " << id;
    const SE3 d = kf.T_w_c.inverse() * r.T_w_c;
    EXPECT_LT(d.translation().norm(), 0.01) << "keyframe " << id;
    EXPECT_LT(rotation_angle_rad(d.linear()) * 180 / M_PI, 0.5) << "keyframe " << id;
    ++n;
  }
  EXPECT_EQ(n, built().map.n_keyframes());
  fs::remove(a);
}

// Version 2 files (before features.orb.level_sigma_exponent) had no exponent after each keyframe's
// pyramid (f64 scale factor, u32 levels). Removing it from a version 3 file and framing the payload
// as version 2 gives exactly what the old writer wrote; it loads with ORB-SLAM's exponent 1 (the
// weights those keyframes were made with) and everything else as saved.
TEST(SlamMapIo, Version2MapsLoadWithOrbSlamLevelSigmas) {
  const Built& b = built();
  const double exponent = SlamConfig{}.features.orb.level_sigma_exponent;
  ASSERT_NE(exponent, 1.0) << "the test tells version 2's exponent 1 from the default";
  const std::string v3 = serialise_slam_map(b.map, b.index, b.loops, room_camera());
  constexpr std::size_t kHead = 8 + 4 + 8, kTail = 8 + 8;  // magic, version, length | checksum, end marker
  std::string payload = v3.substr(kHead, v3.size() - kHead - kTail);
  ByteWriter pattern;
  pattern.put(1.2), pattern.put<std::uint32_t>(8), pattern.put(exponent);
  const std::string& pat = pattern.bytes();
  int removed = 0;
  for (std::size_t at = payload.find(pat); at != std::string::npos;
       at = payload.find(pat, at + pat.size() - 8)) {
    payload.erase(at + pat.size() - 8, 8);
    ++removed;
  }
  ASSERT_EQ(removed, b.map.n_keyframes());
  const BinaryFormat v2{"S3MSLAM\0", "S3MSLEND", 2, "SLAM map", ""};
  const fs::path old = temp_file("v2");
  write(old, frame_payload(v2, payload));
  const LoadedSlamMap m = load_slam_map(old.string(), room_camera(), vocabulary());
  ASSERT_EQ(m.map.n_keyframes(), b.map.n_keyframes());
  ASSERT_EQ(m.map.n_points(), b.map.n_points());
  for (const auto& [id, kf] : b.map.keyframes()) {
    const auto& pyr = m.map.keyframe(id).features->pyramid;
    EXPECT_EQ(pyr.sigma_exponent, 1.0) << "keyframe " << id;
    EXPECT_DOUBLE_EQ(pyr.sigma2[7], std::pow(1.2, 14)) << "keyframe " << id;
    EXPECT_TRUE(m.map.keyframe(id).T_w_c.isApprox(kf.T_w_c, 0.0));
    EXPECT_EQ(m.map.keyframe(id).points, kf.points);
  }
  // Saved again it is a version 3 file holding the exponent 1 it was loaded with.
  const std::string again = serialise_slam_map(m.map, m.index, m.loop_edges, m.camera);
  EXPECT_EQ(again[8], 3);
  ByteWriter one;
  one.put(1.2), one.put<std::uint32_t>(8), one.put(1.0);
  EXPECT_NE(again.find(one.bytes()), std::string::npos);
  EXPECT_EQ(again.size(), v3.size());
  fs::remove(old);
}

TEST(SlamMapIo, BadFilesNameTheFileAndTheProblem) {
  const fs::path good = temp_file("good"), bad = temp_file("bad");
  const std::string bytes = serialise_slam_map(built().map, built().index, built().loops, room_camera());
  write(good, bytes);
  ASSERT_EQ(load_error(good), "");

  EXPECT_NE(load_error(temp_file("missing")).find("no such SLAM map file"), std::string::npos);
  write(bad, bytes.substr(0, bytes.size() / 2));
  EXPECT_NE(load_error(bad).find("truncated"), std::string::npos) << load_error(bad);
  write(bad, bytes.substr(0, 10));
  EXPECT_NE(load_error(bad).find("truncated"), std::string::npos) << load_error(bad);
  write(bad, slurp(features::default_vocabulary_path()));
  EXPECT_NE(load_error(bad).find("not an s3m SLAM map"), std::string::npos);
  std::string v1 = bytes;
  v1[8] = 1;  // u32 version after the 8 magic bytes: version 1 had no keypoint depth sigmas
  write(bad, v1);
  EXPECT_NE(load_error(bad).find("version 1 is not supported (expected version 2 to 3)"), std::string::npos)
      << load_error(bad);
  std::string flipped = bytes;
  flipped[bytes.size() / 2] ^= 0x10;
  write(bad, flipped);
  EXPECT_NE(load_error(bad).find("checksum mismatch"), std::string::npos);

  PinholeCamera other = room_camera();
  other.fx = 500;
  EXPECT_NE(load_error(good, other).find("made with another camera: fx = 525 (this run: 500)"),
            std::string::npos)
      << load_error(good, other);
  other = room_camera();
  other.width = 320;
  EXPECT_NE(load_error(good, other).find("image size 640x480 (this run: 320x480)"), std::string::npos);

  // A vocabulary trained on a few room images: other words, other checksum.
  std::vector<cv::Mat> descs;
  for (int i : {0, 20, 40}) descs.push_back(features::extract_orb_descriptors(room_frame(i).rgb, 300));
  features::VocabularyConfig vc;
  vc.branching = 4;
  vc.levels = 2;
  const auto tiny = std::make_shared<const features::Vocabulary>(features::Vocabulary::train(descs, vc));
  EXPECT_NE(load_error(good, room_camera(), tiny).find("made with another vocabulary"), std::string::npos)
      << load_error(good, room_camera(), tiny);
  fs::remove(good);
  fs::remove(bad);
}

// A file whose framing and checksum are right but whose map contradicts itself.
TEST(SlamMapIo, InconsistentMapIsRejected) {
  std::string bytes = serialise_slam_map(built().map, built().index, built().loops, room_camera());
  // Payload = camera (96 B), vocabulary checksum and size, direct level (20 B), then the map's
  // next keyframe id and next point id: claim no point was ever created.
  const std::size_t payload = 8 + 4 + 8, next_point = payload + 96 + 20 + 8;
  const std::int64_t zero = 0;
  std::memcpy(bytes.data() + next_point, &zero, 8);
  const std::uint64_t sum = fnv1a(std::string_view(bytes).substr(payload, bytes.size() - payload - 16));
  std::memcpy(bytes.data() + bytes.size() - 16, &sum, 8);
  const fs::path p = temp_file("inconsistent");
  write(p, bytes);
  const std::string e = load_error(p);
  EXPECT_NE(e.find("inconsistent map: point id "), std::string::npos) << e;
  EXPECT_NE(e.find(" outside [0, 0)"), std::string::npos) << e;
  fs::remove(p);
}

// Session B of the room: the poses between session A's frames (half a frame on) with other depth
// noise, so no image repeats one the map was built from.
RgbdFrame session_b_frame(int i) {
  return test::render_room(test::Room{}, room_camera(), test::uav_pose(2 * i + 1, 8 * kFrames), i, i / 30.0,
                           0.002, 2);
}
SE3 session_b_T_w_c(int i) {  // ground truth in session A's world (its first camera)
  return test::uav_pose(0, 4 * kFrames).inverse() * test::uav_pose(2 * i + 1, 8 * kFrames);
}

// Session A through System::save_map (single-thread, place recognition on); removed at exit.
const std::string& session_a_file() {
  struct File {
    std::string path = temp_file("session_a").string();
    File() {
      System slam(room_camera(), SlamConfig{}, vocabulary());
      for (int i = 0; i < kFrames; ++i) slam.track(room_frame(i));
      slam.finish();
      slam.save_map(path);
    }
    ~File() { fs::remove(path); }
  };
  static const File file;
  return file.path;
}

struct SessionB {
  std::vector<TrackResult> results;
  std::vector<FramePose> traj;
  int keyframes_before = 0, keyframes_after = 0, keyframes_made = 0;
};

SessionB run_session_b(bool localize_only, bool threaded, const std::string& save_to = "") {
  SlamConfig cfg;
  cfg.threaded = threaded;
  System slam(room_camera(), cfg, vocabulary());
  slam.load_map(session_a_file(), localize_only);
  SessionB b;
  b.keyframes_before = slam.map().n_keyframes();
  for (int i = 0; i < kFrames; ++i) {
    b.results.push_back(slam.track(session_b_frame(i)));
    b.keyframes_made += b.results.back().keyframe;
  }
  slam.finish();
  b.traj = slam.camera_trajectory();
  b.keyframes_after = slam.map().n_keyframes();
  if (!save_to.empty()) slam.save_map(save_to);
  return b;
}

// Worst camera position error of session B against ground truth in session A's world: no
// alignment, the loaded map's frame is the frame.
double worst_error_m(const SessionB& b) {
  double worst = 0;
  for (const auto& p : b.traj)
    worst = std::max(worst, (p.T_w_x.translation() - session_b_T_w_c(p.frame_index).translation()).norm());
  return worst;
}

TEST(SlamSession, LocalizeOnlyTracksInTheLoadedWorldAndLeavesTheMapAsItWas) {
  const fs::path again = temp_file("localized");
  const SessionB b = run_session_b(true, false, again.string());
  EXPECT_EQ(b.results.front().state, FrameState::kRelocalised) << "the first frame relocalises in the map";
  for (const auto& r : b.results) EXPECT_NE(r.state, FrameState::kLost) << "frame " << r.frame_index;
  EXPECT_EQ(b.keyframes_made, 0);
  EXPECT_EQ(b.keyframes_after, b.keyframes_before);
  EXPECT_EQ(slurp(again), slurp(session_a_file())) << "the frozen map saves to the bytes it was loaded from";
  ASSERT_EQ(b.traj.size(), std::size_t(kFrames));
  const double worst = worst_error_m(b);
  std::printf("localize-only session B: worst position error %.4f m in session A's world\n", worst);
  EXPECT_LT(worst, 0.03);
  fs::remove(again);
}

TEST(SlamSession, ThreadedLocalizeOnlyAlsoAddsNothing) {
  const SessionB b = run_session_b(true, true);
  EXPECT_EQ(b.results.front().state, FrameState::kRelocalised);
  EXPECT_EQ(b.keyframes_made, 0);
  EXPECT_EQ(b.keyframes_after, b.keyframes_before);
  EXPECT_LT(worst_error_m(b), 0.03);
}

TEST(SlamSession, ExtendingContinuesTheLoadedMapInItsWorld) {
  const SessionB b = run_session_b(false, false);
  EXPECT_EQ(b.results.front().state, FrameState::kRelocalised);
  for (const auto& r : b.results) EXPECT_NE(r.state, FrameState::kLost) << "frame " << r.frame_index;
  ASSERT_EQ(b.traj.size(), std::size_t(kFrames));
  // New keyframes continue the loaded ids.
  for (const auto& r : b.results)
    if (r.keyframe) {
      EXPECT_GE(r.anchor.keyframe, b.keyframes_before) << "frame " << r.frame_index;
    }
  const double worst = worst_error_m(b);
  std::printf("extending session B: %d keyframes added, worst position error %.4f m\n", b.keyframes_made,
              worst);
  EXPECT_LT(worst, 0.03);
}

TEST(SlamSession, LoadingNeedsRelocalisationAndAFreshSystem) {
  System no_vocab(room_camera(), SlamConfig{});
  EXPECT_THROW(no_vocab.load_map(session_a_file()), Error);
  System used(room_camera(), SlamConfig{}, vocabulary());
  used.track(room_frame(0));
  EXPECT_THROW(used.load_map(session_a_file()), Error);
  System other_camera(room_camera().scaled(0.5), SlamConfig{}, vocabulary());
  EXPECT_THROW(other_camera.load_map(session_a_file()), ParseError);
}

}  // namespace
}  // namespace s3m::slam
