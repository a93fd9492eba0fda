// Bad inputs from docs/ROBUSTNESS.md that the per-reader tests do not cover yet, and crash-safe
// output: a write that fails half-way (disk full, simulated with RLIMIT_FSIZE) leaves the previous
// file intact and loadable, and no temporary file behind.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/resource.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>

#include "io_test_util.hpp"
#include "s3m/io/atomic_file.hpp"
#include "s3m/io/camera_yaml.hpp"
#include "s3m/io/gt_voxels.hpp"
#include "s3m/io/image_io.hpp"
#include "s3m/io/ply.hpp"
#include "s3m/io/trajectory.hpp"

using namespace s3m;
using namespace s3m::io;
using s3m::testing::expect_error;
using s3m::testing::fresh_temp_dir;
using s3m::testing::write_file;
namespace fs = std::filesystem;

namespace {

// Lowers the process's file-size limit for the lifetime of the object. Writes beyond it fail with
// EFBIG (SIGXFSZ is ignored meanwhile), which is what a full disk looks like to the writer.
class FileSizeLimit {
 public:
  explicit FileSizeLimit(rlim_t bytes) {
    getrlimit(RLIMIT_FSIZE, &old_);
    old_handler_ = signal(SIGXFSZ, SIG_IGN);
    rlimit lim = old_;
    lim.rlim_cur = bytes;
    ok_ = setrlimit(RLIMIT_FSIZE, &lim) == 0;
  }
  ~FileSizeLimit() {
    setrlimit(RLIMIT_FSIZE, &old_);
    signal(SIGXFSZ, old_handler_);
  }
  bool ok() const { return ok_; }

 private:
  rlimit old_{};
  sighandler_t old_handler_ = SIG_DFL;
  bool ok_ = false;
};

std::size_t count_files(const fs::path& dir) {
  return static_cast<std::size_t>(std::distance(fs::directory_iterator(dir), fs::directory_iterator{}));
}

Trajectory line_trajectory(int n) {
  Trajectory t;
  for (int i = 0; i < n; ++i) t.push_back({0.1 * i, make_se3(Vec3(0.01 * i, 0, 1), Quat::Identity())});
  return t;
}

}  // namespace

TEST(IoRobustness, DiskFullDuringWriteKeepsPreviousTrajectoryLoadable) {
  const auto dir = fresh_temp_dir();
  const std::string path = (dir / "traj.txt").string();
  write_tum_trajectory(path, line_trajectory(10));
  const auto before = fs::file_size(path);
  {
    FileSizeLimit limit(4096);  // the 10-pose file is ~600 bytes, the 1000-pose one ~60 kB
    ASSERT_TRUE(limit.ok());
    expect_error([&] { write_tum_trajectory(path, line_trajectory(1000)); }, {"traj.txt", "cannot write"});
  }
  EXPECT_EQ(fs::file_size(path), before);
  const auto back = read_tum_trajectory(path);
  ASSERT_EQ(back.size(), 10u);
  EXPECT_NEAR(back[9].T_w_x.translation().x(), 0.09, 1e-9);
  EXPECT_EQ(count_files(dir), 1u) << "the temporary file must be removed";
}

TEST(IoRobustness, DiskFullDuringPlyWriteKeepsPreviousCloud) {
  const auto dir = fresh_temp_dir();
  const std::string path = (dir / "map.ply").string();
  write_ply(path, std::vector<PlyPoint>(3, PlyPoint{1, 2, 3, 4, 5, 6, 7, 0.5f}), true);
  {
    FileSizeLimit limit(8192);
    ASSERT_TRUE(limit.ok());
    expect_error([&] { write_ply(path, std::vector<PlyPoint>(10000), true); }, {"map.ply"});
  }
  const auto back = read_ply(path);
  ASSERT_EQ(back.size(), 3u);
  EXPECT_EQ(back[2].label, 7);
  EXPECT_EQ(count_files(dir), 1u);
}

TEST(IoRobustness, FailingStreamIsReportedNotIgnored) {
  const auto dir = fresh_temp_dir();
  const std::string path = (dir / "x.txt").string();
  write_text_atomic(path, "old\n");
  expect_error([&] { write_file_atomic(path, [](std::ostream& os) { os.setstate(std::ios::badbit); }); },
               {"x.txt", "write failed"});
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "old");
}

TEST(IoRobustness, PlyWithCorruptVertexCountIsAnErrorNotAnAllocation) {
  const auto dir = fresh_temp_dir();
  const std::string head =
      "ply\nformat binary_little_endian 1.0\nelement vertex {}\nproperty float x\nproperty float y\n"
      "property float z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n";
  auto with_count = [&](const std::string& n) {
    std::string h = head;
    h.replace(h.find("{}"), 2, n);
    return h;
  };
  const auto huge = write_file(dir / "huge.ply", with_count("18446744073709551615") + std::string(15, '\0'));
  expect_error([&] { read_ply(huge); }, {"huge.ply", "file ends before 18446744073709551615 vertices"});
  const auto garbage = write_file(dir / "garbage.ply", with_count("12x"));
  expect_error([&] { read_ply(garbage); }, {"garbage.ply:3", "bad vertex count '12x'"});
  const auto overflow = write_file(dir / "overflow.ply", with_count("99999999999999999999999"));
  expect_error([&] { read_ply(overflow); }, {"overflow.ply:3", "bad vertex count"});
}

TEST(IoRobustness, CameraYamlHugeOrFractionalSizesAndNonScalarValues) {
  const auto dir = fresh_temp_dir();
  const std::string base = "fx: 500\nfy: 500\ncx: 320\ncy: 240\ndepth_factor: 1000\n";
  const auto huge = write_file(dir / "huge.yaml", base + "width: 1e300\nheight: 480\n");
  expect_error([&] { read_camera_yaml(huge); }, {"huge.yaml:6", "bad image size width", "1..16384"});
  const auto frac = write_file(dir / "frac.yaml", base + "width: 640\nheight: 479.5\n");
  expect_error([&] { read_camera_yaml(frac); }, {"frac.yaml:7", "height = 479.5"});
  const auto negative = write_file(dir / "neg.yaml", base + "width: -640\nheight: 480\n");
  expect_error([&] { read_camera_yaml(negative); }, {"neg.yaml:6", "width = -640"});
  const auto model = write_file(dir / "model.yaml", base + "width: 640\nheight: 480\ncamera_model: [pinhole]\n");
  expect_error([&] { read_camera_yaml(model); }, {"model.yaml:8", "bad value for 'camera_model'"});
  const auto key = write_file(dir / "key.yaml", base + "width: 640\nheight: 480\n? [a, b]\n: 1\n");
  expect_error([&] { read_camera_yaml(key); }, {"key.yaml:8", "not a plain name"});
  const auto zero_f = write_file(dir / "zero.yaml", "fx: 0\nfy: -1\ncx: 320\ncy: 240\ndepth_factor: 1000\nwidth: 640\nheight: 480\n");
  expect_error([&] { read_camera_yaml(zero_f); }, {"zero.yaml", "fx, fy must be finite and > 0"});
  const auto orb = write_file(dir / "orb.yaml", "%YAML:1.0\nCamera.fx: 500\nCamera.fy: 500\nCamera.cx: 1\nCamera.cy: 1\n"
                                               "Camera.width: 4e9\nDepthMapFactor: 1000\n");
  expect_error([&] { read_orbslam_settings(orb); }, {"orb.yaml:6", "bad image size Camera.width"});
}

TEST(IoRobustness, KittiEntriesThatOverflowAreNotARotation) {
  const auto dir = fresh_temp_dir();
  const auto path = write_file(dir / "k.txt", "1e308 0 0 0 0 1e308 0 0 0 0 1e308 0\n");
  expect_error([&] { read_kitti_trajectory(path); }, {"k.txt:1", "not a rotation"});
}

TEST(IoRobustness, PngClaimingHugeSizeIsRejectedBeforeDecoding) {
  const auto dir = fresh_temp_dir();
  // Signature + IHDR chunk start: length 13, "IHDR", width 30000, height 30000 (big-endian).
  const std::string header = std::string("\x89PNG\r\n\x1a\n", 8) + std::string("\0\0\0\x0dIHDR", 8) +
                             std::string("\0\0\x75\x30\0\0\x75\x30", 8) + std::string("\x10\0\0\0\0", 5);
  const auto path = write_file(dir / "bomb.png", header);
  expect_error([&] { read_depth_png(path, 1000.0); }, {"bomb.png", "PNG header says 30000x30000 pixels", "1..16384"});
  expect_error([&] { read_label_png(path); }, {"bomb.png", "30000x30000"});
}

TEST(IoRobustness, OnlyPngAndJpegReachTheDecoder) {
  // Found by fuzz_label_png. (1) 135 bytes starting like a PNG but without its full signature,
  // with "DICM" at offset 128: cv::imread handed them to GDCM's DICOM reader, which failed an
  // assert() and aborted the process. (2) 51 bytes starting "BM": the BMP decoder allocated the
  // 2.2 GB its header claimed. Both, and TIFF / PNM / BMP files in general, are refused with their
  // first bytes named before any decoder runs.
  const auto dir = fresh_temp_dir();
  std::string dicm(128, '\xff');
  dicm.replace(0, 8, std::string("\x89PNG\0\0\x04\0", 8));
  dicm += "DICM\xbe\xe7\x0d";
  const auto label = write_file(dir / "labels.png", dicm);
  expect_error([&] { read_label_png(label); },
               {"labels.png", "not a PNG or JPEG file (it starts with bytes 89 50 4e 47 00 00 04 00)", "label PNG"});
  const auto bmp = write_file(dir / "bomb.png", std::string("BMNG\x0d\0z\0\xfc\x0a\x1a\x0a\0\0\x06\x0d", 16));
  expect_error([&] { read_label_png(bmp); }, {"bomb.png", "starts with bytes 42 4d 4e 47"});
  const cv::Mat bgr(3, 5, CV_8UC3, cv::Scalar(10, 20, 30));
  for (const char* ext : {".tiff", ".bmp", ".ppm"}) {
    const auto path = (dir / (std::string("c") + ext)).string();
    ASSERT_TRUE(cv::imwrite(path, bgr)) << ext;
    expect_error([&] { read_rgb(path); }, {std::string("c") + ext, "not a PNG or JPEG file"});
  }
  // PNG and JPEG decode whatever the file is called.
  for (const char* ext : {".png", ".jpg"}) {
    const auto path = (dir / (std::string("c") + ext)).string();
    ASSERT_TRUE(cv::imwrite(path, bgr)) << ext;
    const auto renamed = (dir / (std::string("c") + ext + ".img")).string();
    std::filesystem::rename(path, renamed);
    EXPECT_LE(cv::norm(read_rgb(renamed, {5, 3}), bgr, cv::NORM_INF), 2.0) << ext;  // JPEG is lossy
  }
}

TEST(IoRobustness, JpegClaimingHugeSizeIsRejectedBeforeDecoding) {
  // SOI, an APP0 segment to walk past, then SOF0 claiming 40000 (high) x 30000 (wide) pixels.
  const auto dir = fresh_temp_dir();
  const std::string app0 = std::string("\xff\xe0\0\x10JFIF\0\x01\x01\0\0\x01\0\x01\0\0", 18);
  const std::string sof0 = std::string("\xff\xc0\0\x11\x08\x9c\x40\x75\x30\x03", 10) + std::string(9, '\x01');
  const auto path = write_file(dir / "bomb.jpg", std::string("\xff\xd8", 2) + app0 + sof0);
  expect_error([&] { read_rgb(path); }, {"bomb.jpg", "JPEG header says 30000x40000 pixels", "1..16384"});
  // A real JPEG's header is read right: its own size passes and it decodes.
  const cv::Mat bgr(48, 64, CV_8UC3, cv::Scalar(90, 120, 150));
  const auto ok = (dir / "ok.jpg").string();
  ASSERT_TRUE(cv::imwrite(ok, bgr));
  EXPECT_EQ(read_rgb(ok, {64, 48}).size(), cv::Size(64, 48));
}

TEST(IoRobustness, TruncatedJpegIsRefusedNotDecodedGrey) {
  // libjpeg decodes a JPEG cut short without an error (the missing rows grey, a message on stderr
  // naming no file); a recording's frame cut short must be named and refused instead.
  const auto dir = fresh_temp_dir();
  cv::Mat bgr(240, 320, CV_8UC3);
  cv::randu(bgr, 0, 255);  // noise: a large file, so a cut lands in the scan data
  std::vector<unsigned char> jpeg;
  ASSERT_TRUE(cv::imencode(".jpg", bgr, jpeg));
  ASSERT_GT(jpeg.size(), 20000u);
  const std::string bytes(jpeg.begin(), jpeg.end());
  const auto whole = write_file(dir / "whole.jpg", bytes);
  EXPECT_EQ(read_rgb(whole, {320, 240}).size(), cv::Size(320, 240));
  for (const std::size_t keep : {bytes.size() / 2, bytes.size() - 1}) {  // half; only the last byte lost
    const auto cut = write_file(dir / "cut.jpg", bytes.substr(0, keep));
    expect_error([&] { read_rgb(cut); },
                 {"cut.jpg", "JPEG ends without its end-of-image marker after " + std::to_string(keep) + " bytes",
                  "a complete JPEG file"});
  }
  // A marker before the scan (an EXIF thumbnail's own end, in APP1) does not make a cut file whole.
  const std::string app1 = std::string("\xff\xe1\x00\x0a" "Exif\0\0\xff\xd9", 12);
  const std::string with_thumb = bytes.substr(0, 2) + app1 + bytes.substr(2);
  EXPECT_EQ(read_rgb(write_file(dir / "thumb.jpg", with_thumb), {320, 240}).size(), cv::Size(320, 240));
  // Cut 200 bytes into the scan: the file's last 4 KiB reach back over the thumbnail's marker.
  const std::size_t scan = with_thumb.find("\xff\xda");
  ASSERT_NE(scan, std::string::npos);
  ASSERT_LT(scan + 200, 4096u);
  const auto cut_thumb = write_file(dir / "cut_thumb.jpg", with_thumb.substr(0, scan + 200));
  expect_error([&] { read_rgb(cut_thumb); }, {"cut_thumb.jpg", "end-of-image marker"});
  // Padding after the marker (some writers round files up) is not a truncation.
  const auto padded = write_file(dir / "padded.jpg", bytes + std::string(1000, '\0'));
  EXPECT_EQ(read_rgb(padded, {320, 240}).size(), cv::Size(320, 240));
}

TEST(IoRobustness, ImplausiblyLargeCoordinatesAreRejected) {
  const auto dir = fresh_temp_dir();
  // 1e300 m is finite but squares to inf: ATE would print 'inf' instead of failing.
  const auto tum = write_file(dir / "t.txt", "0 0 0 0 0 0 0 1\n1 1e300 0 0 0 0 0 1\n");
  expect_error([&] { read_tum_trajectory(tum); }, {"t.txt:2", "coordinate tx = 1e300 m is implausibly large"});
  const auto kitti = write_file(dir / "k.txt", "1 0 0 0 0 1 0 -2e9 0 0 1 0\n");
  expect_error([&] { read_kitti_trajectory(kitti); }, {"k.txt:1", "coordinate ty = -2e9 m"});
  const auto ok = write_file(dir / "ok.txt", "0 1e9 -1e9 0 0 0 0 1\n");
  EXPECT_EQ(read_tum_trajectory(ok)[0].T_w_x.translation().x(), 1e9);
  const auto vox = write_file(dir / "v.txt", "# s3m ground-truth voxel map v1\nresolution 0.05\n0 0 1e39 3\n");
  expect_error([&] { read_gt_voxels(vox); }, {"v.txt:3", "coordinate z = 1e39 m"});
}
