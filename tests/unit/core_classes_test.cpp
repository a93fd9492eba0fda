#include <gtest/gtest.h>

#include <filesystem>
#include <cmath>
#include <fstream>

#include <unistd.h>

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

// Map and label pictures colour voxels by class: two classes must never look alike.
TEST(Classes, EveryClassColourIsDistinct) {
  const auto& all = indoor_classes().all();
  double min_dist = 1e9;
  std::string closest;
  for (std::size_t a = 0; a < all.size(); ++a)
    for (std::size_t b = a + 1; b < all.size(); ++b) {
      const double dr = all[a].r - all[b].r, dg = all[a].g - all[b].g, db = all[a].b - all[b].b;
      const double d = std::sqrt(dr * dr + dg * dg + db * db);
      if (d < min_dist) min_dist = d, closest = all[a].name + " / " + all[b].name;
    }
  EXPECT_GE(min_dist, 60.0) << "closest colours: " << closest;
}

TEST(Classes, WriteIsAtomicAndFailsCleanly) {
  const auto dir = std::filesystem::temp_directory_path() / ("s3m_classes_atomic_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const auto path = (dir / "classes.txt").string();
  write_class_list(path, indoor_classes());
  write_class_list(path, indoor_classes());  // replacing an existing file
  EXPECT_EQ(read_class_list(path).size(), indoor_classes().size());
  std::size_t files = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir)) files += (void(e), 1);
  EXPECT_EQ(files, 1u);  // no temporary file left next to it
  try {
    write_class_list((dir / "missing" / "classes.txt").string(), indoor_classes());
    FAIL() << "writing into a missing folder must fail";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("does not exist"), std::string::npos) << e.what();
  }
  std::filesystem::remove_all(dir);
}
