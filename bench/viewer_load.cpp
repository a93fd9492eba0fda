// Load time of the browser map viewer (src/s3m/viewer, tools/viewer/) in headless Chromium.
// Builds a synthetic room map with --voxels occupied voxels (walls, floor, ceiling, furniture
// boxes, top-3 labels, varying colours), writes the viewer for it and opens it --runs times.
// "load" is the page's own clock (performance.now() at the end of the first drawn frame, after a
// pixel read-back, counted from navigation start: parsing three.js and the map data included);
// "browser" is the wall-clock time of the whole chromium process (start-up and exit included).
//   build/bench/bench_viewer_load [--voxels 200000] [--runs 3] [--out /tmp/s3m_viewer_bench]
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <regex>
#include <string>

#include "s3m/core/timing.hpp"
#include "s3m/mapping/label_set.hpp"
#include "s3m/mapping/semantic_octree.hpp"
#include "s3m/viewer/headless_browser.hpp"
#include "s3m/viewer/map_viewer.hpp"

namespace {

using s3m::mapping::SemanticOcTree;

// Adds occupied voxels of axis-aligned box surfaces (cells [lo, hi) of res) until the map has n.
struct RoomBuilder {
  SemanticOcTree& tree;
  std::size_t target, added = 0;
  void voxel(int x, int y, int z, s3m::ClassId cls) {
    if (added >= target) return;
    const octomap::OcTreeKey key = tree.coordToKey(octomap::point3d(x * 0.05f + 0.025f, y * 0.05f + 0.025f, z * 0.05f + 0.025f));
    if (tree.search(key) != nullptr) return;
    tree.updateNode(key, 2.0f, /*lazy_eval=*/true);
    s3m::mapping::LabelSet obs;
    const float p = 0.5f + 0.45f * float((x * 7 + y * 13 + z * 3) % 10) / 10.0f;
    obs.push(cls, p);
    obs.push(s3m::cls::kOther, (1 - p) * 0.7f);
    obs.push(s3m::cls::kWall == cls ? s3m::cls::kDoor : s3m::cls::kWall, (1 - p) * 0.3f);
    tree.integrateObservation(key, obs, {std::uint8_t(100 + x % 100), std::uint8_t(120 + y % 80), std::uint8_t(90 + z % 60)});
    ++added;
  }
  // Surface of the box [x0,x1) x [y0,y1) x [z0,z1) in cells.
  void box(int x0, int x1, int y0, int y1, int z0, int z1, s3m::ClassId cls) {
    for (int x = x0; x < x1; ++x)
      for (int y = y0; y < y1; ++y)
        for (int z = z0; z < z1; ++z)
          if (x == x0 || x == x1 - 1 || y == y0 || y == y1 - 1 || z == z0 || z == z1 - 1) voxel(x, y, z, cls);
  }
};

}  // namespace

int main(int argc, char** argv) {
  std::size_t voxels = 200000;
  int runs = 3;
  std::string out = "/tmp/s3m_viewer_bench";
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i];
    if (a == "--voxels") voxels = std::stoul(argv[i + 1]);
    else if (a == "--runs") runs = std::stoi(argv[i + 1]);
    else if (a == "--out") out = argv[i + 1];
    else return std::fprintf(stderr, "unknown option %s\n", a.c_str()), 2;
  }
  // 1. The map: furniture first, then a room whose size grows until the count is reached.
  SemanticOcTree tree(0.05);
  RoomBuilder b{tree, voxels};
  const s3m::ClassId furniture[] = {s3m::cls::kTable, s3m::cls::kCabinet, s3m::cls::kChair, s3m::cls::kSofa, s3m::cls::kShelf};
  const int side = 60 + static_cast<int>(std::sqrt(double(voxels)) * 0.45);
  for (int i = 0; i < 40; ++i) {
    const int x = 10 + (i * 37) % (side - 40), y = 10 + (i * 53) % (side - 40);
    b.box(x, x + 12 + i % 9, y, y + 8 + i % 7, 1, 10 + i % 8, furniture[i % 5]);
  }
  b.box(0, side, 0, side, 0, 1, s3m::cls::kFloor);
  for (int z = 1; z < 60; ++z)
    for (int t = 0; t < side; ++t) b.voxel(t, 0, z, s3m::cls::kWall), b.voxel(t, side - 1, z, s3m::cls::kWall),
                                   b.voxel(0, t, z, s3m::cls::kWall), b.voxel(side - 1, t, z, s3m::cls::kWall);
  b.box(0, side, 0, side, 60, 61, s3m::cls::kCeiling);
  for (int z = 61; b.added < voxels; ++z) b.box(0, side, 0, side, z, z + 1, s3m::cls::kOther);
  tree.updateInnerOccupancy();
  // 2. The viewer folder.
  s3m::Stopwatch write;
  const s3m::viewer::ViewerFolder f = s3m::viewer::write_viewer(tree, {}, out + "/viewer");
  std::printf("map: %zu voxels; viewer written in %.0f ms (%s)\n", b.added, write.elapsed_ms(), f.dir.c_str());
  if (!f.have_three) return std::fprintf(stderr, "%s\n", f.note.c_str()), 1;
  // 3. Open it.
  const std::string chromium = s3m::viewer::find_chromium();
  if (chromium.empty()) return std::fprintf(stderr, "chromium not found (apt-get install chromium)\n"), 1;
  const std::regex load_re("data-load-ms=\"([0-9.]+)\""), drawn_re("data-drawn=\"([0-9]+)\"");
  for (int r = 0; r < runs; ++r) {
    s3m::viewer::BrowserOptions o;
    o.profile_dir = out + "/profile";
    const auto run = s3m::viewer::dump_dom(chromium, s3m::viewer::file_url(f.index_html), o);
    std::smatch load, drawn;
    if (!std::regex_search(run.out, load, load_re) || !std::regex_search(run.out, drawn, drawn_re))
      return std::fprintf(stderr, "run %d: the page did not report a load (exit %d)\n", r, run.exit_code), 1;
    std::printf("run %d: load %.0f ms (page clock), %s voxels drawn, browser process %.2f s\n", r,
                std::stod(load[1]), drawn[1].str().c_str(), run.wall_s);
  }
  return 0;
}
