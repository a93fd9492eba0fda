// The map viewer in a real browser: a short `s3m demo` writes its report, headless Chromium opens
// report.html from file:// with the "#selftest" hash (tools/viewer/viewer.js drives its own UI with
// DOM events and writes the result into the page), and a screenshot shows the WebGL canvas.
// Checked against the map itself (map.ot, metrics.json): voxels drawn, hiding a class, a click.
// Skipped (never passed) when chromium or three.js (libjs-three) is not installed.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <unordered_set>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "s3m/mapping/export.hpp"
#include "s3m/mapping/map_io.hpp"
#include "s3m/mapping/queries.hpp"
#include "s3m/viewer/headless_browser.hpp"
#include "s3m/viewer/map_viewer.hpp"

namespace s3m {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;

const fs::path kOut = S3M_BROWSER_TEST_OUT;  // kept after the test: report, DOM, screenshot

// Faces of the voxels not of class `hidden` that have no such voxel beside them: the area the
// viewer's quads must cover, counted here from the map, independently of the page.
std::size_t exposed_faces(const mapping::SemanticOcTree& map, const std::vector<mapping::OccupiedVoxel>& voxels,
                          int hidden) {
  const auto pack = [](int x, int y, int z) {
    return static_cast<std::uint64_t>(x) | static_cast<std::uint64_t>(y) << 16 | static_cast<std::uint64_t>(z) << 32;
  };
  std::vector<octomap::OcTreeKey> keys;
  std::unordered_set<std::uint64_t> shown;
  for (const auto& v : voxels) {
    if (v.label == hidden) continue;
    keys.push_back(map.coordToKey(octomap::point3d(v.centre_w.x(), v.centre_w.y(), v.centre_w.z())));
    shown.insert(pack(keys.back()[0], keys.back()[1], keys.back()[2]));
  }
  std::size_t faces = 0;
  for (const auto& k : keys)
    for (int a = 0; a < 3; ++a)
      for (int s : {-1, 1}) {
        int n[3] = {k[0], k[1], k[2]};
        n[a] += s;
        faces += !shown.count(pack(n[0], n[1], n[2]));
      }
  return faces;
}

std::string read_text(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::ostringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

std::string unescape_html(std::string s) {
  for (const auto& [from, to] : std::map<std::string, std::string>{{"&lt;", "<"}, {"&gt;", ">"}, {"&quot;", "\""}, {"&amp;", "&"}})
    for (std::size_t i = 0; (i = s.find(from, i)) != std::string::npos; i += to.size()) s.replace(i, from.size(), to);
  return s;
}

class ViewerInBrowser : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    chromium_ = viewer::find_chromium();
    if (chromium_.empty() || viewer::find_three_dir().empty()) return;
    // 40 frames of the demo: the real user path (simulator, SLAM, shipped network, map, report).
    fs::remove_all(kOut);
    fs::create_directories(kOut);
    const std::string cmd = std::string(S3M_BINARY) + " demo --frames 40 --out '" + (kOut / "demo").string() + "' > '" +
                            (kOut / "demo.log").string() + "' 2>&1";
    demo_status_ = std::system(cmd.c_str());
  }
  void SetUp() override {
    if (chromium_.empty()) GTEST_SKIP() << "chromium not installed (apt-get install chromium)";
    if (viewer::find_three_dir().empty()) GTEST_SKIP() << "three.js not installed (apt-get install libjs-three)";
    ASSERT_EQ(demo_status_, 0) << read_text(kOut / "demo.log");
  }
  static fs::path run_dir() { return kOut / "demo" / "run"; }
  static viewer::BrowserOptions options() {
    viewer::BrowserOptions o;
    o.width = 1300, o.height = 1400;  // the 3-D view is in the first screen of the report
    o.virtual_time_budget_ms = 15000;
    o.profile_dir = (kOut / "chromium_profile").string();
    return o;
  }
  // The self-test's JSON from the report's DOM.
  static json self_test() {
    const auto run = viewer::dump_dom(chromium_, viewer::file_url((run_dir() / "report/report.html").string(), "selftest"), options());
    std::ofstream(kOut / "report_dom.html") << run.out;
    std::smatch m;
    const std::regex re("<pre id=\"s3m-selftest\">([^<]*)</pre>");
    if (!std::regex_search(run.out, m, re)) return json();
    return json::parse(unescape_html(m[1]));
  }

  static inline std::string chromium_;
  static inline int demo_status_ = -1;
};

TEST_F(ViewerInBrowser, DrawsEveryVoxelHidesAClassExactlyAndPicksTheClickedVoxel) {
  const json metrics = json::parse(read_text(run_dir() / "metrics.json"));
  const std::size_t voxels = metrics["map"]["voxels"].get<std::size_t>();
  const auto map = mapping::load_semantic_map((run_dir() / "map.ot").string());
  std::map<int, std::size_t> per_class;
  const auto occupied = mapping::occupied_voxels(*map);
  for (const auto& v : occupied) ++per_class[v.label];

  const json r = self_test();
  ASSERT_TRUE(r.is_object()) << "the page wrote no self-test result (see " << (kOut / "report_dom.html") << ")";
  ASSERT_TRUE(r.value("loaded", false));
  EXPECT_EQ(r["voxels"].get<std::size_t>(), voxels);
  EXPECT_EQ(r["drawn"].get<std::size_t>(), voxels);
  // The quads cover exactly the exposed voxel faces (runs of one colour merged into one quad, so
  // fewer quads than faces), and WebGL drew exactly the quads the viewer put into its buffers.
  EXPECT_EQ(r["faces_exposed"].get<std::size_t>(), exposed_faces(*map, occupied, -1));
  EXPECT_LT(r["faces_in_buffers"].get<std::size_t>(), r["faces_exposed"].get<std::size_t>() / 2);
  EXPECT_EQ(r["faces_drawn"], r["faces_in_buffers"]);

  // Hiding the largest class through its legend entry removes exactly its voxels.
  const json& hide = r["hide"];
  const int hidden = hide["class_id"].get<int>();
  EXPECT_EQ(hide["class_voxels"].get<std::size_t>(), per_class[hidden]);
  EXPECT_EQ(hide["drawn_after_hide"].get<std::size_t>(), voxels - per_class[hidden]);
  EXPECT_EQ(hide["faces_drawn"], hide["faces_in_buffers"]);
  EXPECT_EQ(hide["faces_exposed"].get<std::size_t>(), exposed_faces(*map, occupied, hidden));
  EXPECT_EQ(hide["drawn_after_show"].get<std::size_t>(), voxels);

  // A click at the projected centre of the voxel nearest to the camera reports that voxel, and its
  // class is the map's class there.
  const json& click = r["click"];
  ASSERT_FALSE(click["reported_class_id"].is_null()) << click.dump();
  EXPECT_EQ(click["reported_key"], click["expected_key"]) << click.dump();
  EXPECT_EQ(click["reported_class_id"], click["expected_class_id"]);
  int key[3];
  ASSERT_EQ(std::sscanf(click["expected_key"].get<std::string>().c_str(), "%d,%d,%d", &key[0], &key[1], &key[2]), 3);
  const octomap::point3d c = map->keyToCoord(octomap::OcTreeKey(key[0], key[1], key[2]));
  const auto truth = mapping::class_at(*map, {c.x(), c.y(), c.z()});
  ASSERT_TRUE(truth.has_value());
  EXPECT_EQ(click["reported_class_id"].get<int>(), truth->label);

  // The WebGL canvas is not blank: the screenshot's canvas area varies.
  const fs::path png = kOut / "report_screenshot.png";
  const auto shot = viewer::screenshot(chromium_, viewer::file_url((run_dir() / "report/report.html").string()), png.string(), options());
  ASSERT_TRUE(fs::exists(png)) << "chromium exit code " << shot.exit_code;
  const cv::Mat img = cv::imread(png.string(), cv::IMREAD_GRAYSCALE);
  ASSERT_FALSE(img.empty());
  const json& cr = r["canvas"];
  const cv::Rect rect = cv::Rect(cr["x"].get<int>(), cr["y"].get<int>(), cr["width"].get<int>(), cr["height"].get<int>()) &
                        cv::Rect(0, 0, img.cols, img.rows);
  ASSERT_GT(rect.area(), 100 * 100) << "the canvas is not in the screenshot";
  cv::Scalar mean, stddev;
  cv::meanStdDev(img(rect), mean, stddev);
  EXPECT_GT(stddev[0], 10.0) << "canvas looks blank (mean grey " << mean[0] << ")";
  // ... and the voxels are drawn in the class colours: far from the background grey in many pixels.
  const cv::Mat colour = cv::imread(png.string(), cv::IMREAD_COLOR)(rect);
  cv::Mat diff;
  cv::absdiff(colour, cv::Scalar(0xf4, 0xf4, 0xf4), diff);
  cv::Mat grey_diff;
  cv::cvtColor(diff, grey_diff, cv::COLOR_BGR2GRAY);
  EXPECT_GT(cv::countNonZero(grey_diff > 30), rect.area() / 50);
}

}  // namespace
}  // namespace s3m
