#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "s3m/core/classes.hpp"
#include "s3m/core/error.hpp"

using namespace s3m;

TEST(Classes, IndoorListHasTheIssueClasses) {
  const auto& c = indoor_classes();
  EXPECT_EQ(c.size(), static_cast<std::size_t>(cls::kCount));
  EXPECT_EQ(c.find("chair"), cls::kChair);
  EXPECT_EQ(c.find("tv_monitor"), cls::kTvMonitor);
  EXPECT_EQ(c.at(cls::kFloor).name, "floor");
  EXPECT_EQ(c.find("spaceship"), -1);
  EXPECT_THROW(c.at(99), Error);
}

TEST(Classes, FileRoundTrip) {
  const auto path = (std::filesystem::temp_directory_path() / "s3m_classes_rt.txt").string();
  write_class_list(path, indoor_classes());
  const ClassList back = read_class_list(path);
  ASSERT_EQ(back.size(), indoor_classes().size());
  for (std::size_t i = 0; i < back.size(); ++i) {
    EXPECT_EQ(back.all()[i].name, indoor_classes().all()[i].name);
    EXPECT_EQ(back.all()[i].g, indoor_classes().all()[i].g);
  }
}

TEST(Classes, BadFileNamesLine) {
  const auto path = (std::filesystem::temp_directory_path() / "s3m_classes_bad.txt").string();
  std::ofstream(path) << "0 unknown 0 0 0\n1 wall 300 0 0\n";
  try {
    read_class_list(path);
    FAIL();
  } catch (const ParseError& e) {
    EXPECT_EQ(e.line(), 2);
    EXPECT_NE(std::string(e.what()).find("0..255"), std::string::npos);
  }
}
