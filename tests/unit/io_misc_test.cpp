#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "io_test_util.hpp"
#include "s3m/io/atomic_file.hpp"
#include "s3m/io/gt_voxels.hpp"
#include "s3m/io/output_folder.hpp"
#include "s3m/io/ply.hpp"

using namespace s3m;
using namespace s3m::io;
using s3m::testing::expect_error;
using s3m::testing::fresh_temp_dir;
using s3m::testing::write_file;
namespace fs = std::filesystem;

TEST(IoAtomicFile, WritesAndLeavesOldContentOnFailure) {
  const auto dir = fresh_temp_dir();
  const auto path = (dir / "a.txt").string();
  write_text_atomic(path, "first\n");
  expect_error(
      [&] {
        write_file_atomic(path, [](std::ostream& os) {
          os << "partial";
          throw std::runtime_error("boom");
        });
      },
      {"a.txt", "boom"});
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  EXPECT_EQ(ss.str(), "first\n");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator{}), 1);  // no temp file left
  expect_error([&] { write_text_atomic((dir / "no_dir" / "x.txt").string(), "x"); },
               {"no_dir", "does not exist"});
}

TEST(IoOutputFolder, AFileIsRefusedAndAFolderIsMadeWithItsParents) {
  const auto dir = fresh_temp_dir();
  const std::string file = write_file(dir / "a_file", "not a folder");
  expect_error([&] { require_folder_path(file, "--out"); }, {"--out '" + file + "' is a file, not a folder"});
  expect_error([&] { create_output_folder(file, "--out"); },
               {"--out '" + file + "' is a file, not a folder"});
  expect_error([&] { create_output_folder((dir / "a_file" / "sub").string(), "--out"); },
               {"--out: cannot create the output directory", "a_file"});
  const fs::path nested = dir / "x" / "y";
  require_folder_path(nested.string(), "--out");  // checks only
  EXPECT_FALSE(fs::exists(dir / "x"));
  create_output_folder(nested.string(), "--out");
  EXPECT_TRUE(fs::is_directory(nested));
  create_output_folder(nested.string(), "--out");  // already there: fine
}

namespace {
std::string file_text(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}
std::size_t entries(const fs::path& dir) {
  return std::distance(fs::directory_iterator(dir), fs::directory_iterator{});
}
}  // namespace

TEST(IoStagedFolder, CommitReplacesFilesAndFoldersAndRemovesOwnedLeftovers) {
  const auto dir = fresh_temp_dir();
  const fs::path dest = dir / "out";
  fs::create_directories(dest / "report");
  write_file(dest / "a.txt", "old a");
  write_file(dest / "map.ot", "old map");
  write_file(dest / "report" / "old.html", "old report");
  write_file(dest / "notes.txt", "the user's");
  fs::create_directories(dest / ".s3m-staging-1");  // a killed command's
  {
    StagedFolder out(dest.string(), "--out");
    EXPECT_FALSE(out.created_dest());
    EXPECT_FALSE(fs::exists(dest / ".s3m-staging-1"));
    write_file(fs::path(out.path()) / "a.txt", "new a");
    fs::create_directories(fs::path(out.path()) / "report");
    write_file(fs::path(out.path()) / "report" / "new.html", "new report");
    EXPECT_EQ(file_text(dest / "a.txt"), "old a");  // nothing moves before commit
    const auto removed = out.commit({"a.txt", "map.ot", "report", "never_made.bin"});
    ASSERT_EQ(removed.size(), 1u);
    EXPECT_EQ(removed[0], (dest / "map.ot").string());
  }
  EXPECT_EQ(file_text(dest / "a.txt"), "new a");
  EXPECT_EQ(file_text(dest / "report" / "new.html"), "new report");
  EXPECT_FALSE(fs::exists(dest / "report" / "old.html"));  // a folder is replaced whole
  EXPECT_FALSE(fs::exists(dest / "map.ot"));
  EXPECT_EQ(file_text(dest / "notes.txt"), "the user's");
  EXPECT_EQ(entries(dest), 3u);  // a.txt, report, notes.txt: no staging folder left
}

TEST(IoStagedFolder, WithoutCommitTheDestinationIsLeftAsItWas) {
  const auto dir = fresh_temp_dir();
  const fs::path dest = dir / "out";
  fs::create_directories(dest);
  write_file(dest / "a.txt", "old a");
  {
    StagedFolder out(dest.string(), "--out");
    write_file(fs::path(out.path()) / "a.txt", "new a");
  }  // e.g. an exception while writing
  EXPECT_EQ(file_text(dest / "a.txt"), "old a");
  EXPECT_EQ(entries(dest), 1u);
  const fs::path fresh = dir / "x" / "fresh";
  {
    StagedFolder out(fresh.string(), "--out");
    EXPECT_TRUE(out.created_dest());
    EXPECT_TRUE(fs::is_directory(out.path()));
  }
  EXPECT_FALSE(fs::exists(fresh));  // the folder it made, still empty, goes
  const std::string file = write_file(dir / "a_file", "x");
  expect_error([&] { StagedFolder bad(file, "--out"); }, {"--out '" + file + "' is a file, not a folder"});
}

TEST(IoGtVoxels, RoundTripAndErrors) {
  const auto dir = fresh_temp_dir();
  GtVoxelMap map;
  map.resolution_m = 0.05;
  map.centres_w = {{0.025f, -1.275f, 2.5f}, {1.0f, 2.0f, 3.0f}};
  map.labels = {2, 15};
  write_gt_voxels((dir / "v.txt").string(), map);
  const auto back = read_gt_voxels((dir / "v.txt").string());
  EXPECT_DOUBLE_EQ(back.resolution_m, 0.05);
  ASSERT_EQ(back.labels, map.labels);
  EXPECT_EQ(back.centres_w[0], map.centres_w[0]);
  const auto noheader = write_file(dir / "n.txt", "resolution 0.05\n0 0 0 1\n");
  expect_error([&] { read_gt_voxels(noheader); }, {"n.txt:1", "missing header"});
  const auto badid =
      write_file(dir / "b.txt", "# s3m ground-truth voxel map v1\nresolution 0.05\n0 0 0 1\n0 0 0 1.5\n");
  expect_error([&] { read_gt_voxels(badid); }, {"b.txt:4", "class_id 1.5", "integer"});
  const auto nores = write_file(dir / "r.txt", "# s3m ground-truth voxel map v1\n0 0 0 1\n");
  expect_error([&] { read_gt_voxels(nores); }, {"r.txt:2", "missing resolution"});
  map.labels.pop_back();
  EXPECT_THROW(write_gt_voxels((dir / "x.txt").string(), map), Error);
}

TEST(IoPly, BinaryRoundTripWithAndWithoutSemantics) {
  const auto dir = fresh_temp_dir();
  std::vector<PlyPoint> pts(2);
  pts[0] = {1.5f, -2.0f, 3.25f, 255, 0, 7, 12, 0.75f};
  pts[1] = {0, 0, 0, 1, 2, 3, 0, 0};
  write_ply((dir / "s.ply").string(), pts, true);
  auto back = read_ply((dir / "s.ply").string());
  ASSERT_EQ(back.size(), 2u);
  EXPECT_EQ(back[0].z, 3.25f);
  EXPECT_EQ(back[0].b, 7);
  EXPECT_EQ(back[0].label, 12);
  EXPECT_EQ(back[0].confidence, 0.75f);
  write_ply((dir / "p.ply").string(), pts, false);
  // Header + 15 bytes per vertex (3 floats + 3 uchar).
  const auto header_end = [&] {
    std::ifstream in(dir / "p.ply", std::ios::binary);
    std::string all((std::istreambuf_iterator<char>(in)), {});
    return all.find("end_header\n") + 11;
  }();
  EXPECT_EQ(fs::file_size(dir / "p.ply"), header_end + 2 * 15);
  back = read_ply((dir / "p.ply").string());
  EXPECT_EQ(back[1].g, 2);
  EXPECT_EQ(back[0].label, 0);
  const auto ascii = write_file(dir / "a.ply", "ply\nformat ascii 1.0\nelement vertex 0\nend_header\n");
  expect_error([&] { read_ply(ascii); }, {"a.ply", "unsupported PLY layout"});
}
