#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "s3m/core/error.hpp"
#include "s3m/semantics/class_map.hpp"

using namespace s3m;
using namespace s3m::semantics;
namespace fs = std::filesystem;

namespace {
std::string write_tmp(const std::string& name, const std::string& text) {
  const auto path = (fs::temp_directory_path() / ("s3m_semantics_" + name)).string();
  std::ofstream(path) << text;
  return path;
}
const std::vector<std::string> kSource = {"other", "wall", "desk", "table", "armchair", "chair", "spaceship"};
}  // namespace

TEST(SemanticsClassMap, ManyToOneWithDefaultOther) {
  const auto yaml = write_tmp("map_ok.yaml",
                              "default: other\nmap:\n  wall: wall\n  table: [desk, table]\n  chair: [armchair, chair]\n"
                              "  unknown: [other]\npalette:\n  wall: [1, 2, 3]\n");
  const ClassMap m = ClassMap::load(yaml, kSource);
  ASSERT_EQ(m.source_size(), kSource.size());
  EXPECT_EQ(m[0], cls::kUnknown);
  EXPECT_EQ(m[1], cls::kWall);
  EXPECT_EQ(m[2], cls::kTable);
  EXPECT_EQ(m[3], cls::kTable);
  EXPECT_EQ(m[4], cls::kChair);
  EXPECT_EQ(m[6], cls::kOther);  // not listed -> default
  EXPECT_EQ(m.sources_of(cls::kTable), (std::vector<int>{2, 3}));
  EXPECT_EQ(m.target().at(cls::kWall).r, 1);
  EXPECT_EQ(m.target().at(cls::kWall).b, 3);
  // apply(): 8-bit source image, ids beyond the list -> unknown
  const cv::Mat src = (cv::Mat_<std::uint8_t>(1, 3) << 2, 4, 200);
  const cv::Mat out = m.apply(src);
  EXPECT_EQ(out.at<ClassId>(0, 0), cls::kTable);
  EXPECT_EQ(out.at<ClassId>(0, 1), cls::kChair);
  EXPECT_EQ(out.at<ClassId>(0, 2), cls::kUnknown);
}

TEST(SemanticsClassMap, ErrorsNameFileLineAndProblem) {
  auto expect_error = [](const std::string& yaml, const std::string& needle) {
    const auto path = write_tmp("map_bad.yaml", yaml);
    try {
      ClassMap::load(path, kSource);
      FAIL() << "no error for: " << yaml;
    } catch (const ParseError& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
  };
  expect_error("map:\n  wall: [wall]\n  starship: [spaceship]\n", "unknown project class 'starship'");
  expect_error("map:\n  wall: [walll]\n", "source class 'walll' is not in the source class list");
  expect_error("map:\n  wall: [wall]\n  table: [wall]\n", "mapped twice");
  expect_error("maps:\n  wall: [wall]\n", "unknown key 'maps'");
  expect_error("palette:\n  wall: [1, 2]\nmap:\n  wall: wall\n", "bad palette colour");
  expect_error("default: other\n", "missing 'map'");
  expect_error("map:\n  [wall, floor]: wall\n", "bad class map entry");  // wrong shapes -> ParseError, not YAML's
  expect_error("map:\n  wall: [[wall]]\n", "bad class map entry");
}

TEST(SemanticsClassMap, ByNameAndNameFileFormats) {
  const ClassMap m = ClassMap::by_name({"wall", "chair", "spaceship"});
  EXPECT_EQ(m[0], cls::kWall);
  EXPECT_EQ(m[1], cls::kChair);
  EXPECT_EQ(m[2], cls::kOther);
  // plain names (with spaces) and id<TAB>name (with gaps and a header line)
  const auto plain = read_class_names(write_tmp("names.txt", "# comment\nwall\nchest of drawers\n"));
  EXPECT_EQ(plain, (std::vector<std::string>{"wall", "chest of drawers"}));
  const auto tsv = read_class_names(write_tmp("names.tsv", "id\tname\n0\twall\n3\tfloor mat\n"));
  ASSERT_EQ(tsv.size(), 4u);
  EXPECT_EQ(tsv[3], "floor mat");
  EXPECT_EQ(tsv[1], "");
  EXPECT_THROW(read_class_names("/nonexistent/names.txt"), ParseError);
  EXPECT_THROW(read_class_names(write_tmp("huge.tsv", "99999999999999999999999\twall\n")), ParseError);
}

TEST(SemanticsClassMap, ShippedAde20kAndSunMapsLoad) {
  const std::string root = S3M_TEST_DATA_DIR "/../../config/classmaps/";
  const auto ade = read_class_names(root + "ade20k151.names.txt");
  ASSERT_EQ(ade.size(), 151u);  // index 0 "other" + 150 ADE20K classes
  const ClassMap m = ClassMap::load(root + "ade20k.yaml", ade);
  auto idx = [&](const std::string& n) { return std::find(ade.begin(), ade.end(), n) - ade.begin(); };
  EXPECT_EQ(m[idx("desk")], cls::kTable);
  EXPECT_EQ(m[idx("armchair")], cls::kChair);
  EXPECT_EQ(m[idx("windowpane")], cls::kWindow);
  EXPECT_EQ(m[idx("bookcase")], cls::kShelf);
  EXPECT_EQ(m[idx("sky")], cls::kOther);
  // every project class except unknown/other receives at least one ADE class
  for (ClassId c = 1; c < cls::kOther; ++c) EXPECT_FALSE(m.sources_of(c).empty()) << indoor_classes().at(c).name;

  std::vector<std::string> sun = {"wall", "floor", "cabinet", "bed", "chair", "sofa", "table", "door", "window",
                                  "bookshelf", "picture", "counter", "blinds", "desk", "shelves", "curtain",
                                  "dresser", "pillow", "mirror", "floor mat", "clothes", "ceiling", "books",
                                  "refridgerator", "television", "paper", "towel", "shower curtain", "box",
                                  "whiteboard", "person", "night stand", "toilet", "sink", "lamp", "bathtub", "bag"};
  sun.resize(256);
  sun[255] = "unlabeled";
  const ClassMap s = ClassMap::load(root + "sunrgbd37.yaml", sun);
  EXPECT_EQ(s[255], cls::kUnknown);
  EXPECT_EQ(s[13], cls::kTable);  // desk
  EXPECT_EQ(s[10], cls::kOther);  // picture
}
