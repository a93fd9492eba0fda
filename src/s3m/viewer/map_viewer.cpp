#include "s3m/viewer/map_viewer.hpp"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "s3m/core/error.hpp"
#include "s3m/eval/report.hpp"
#include "s3m/io/atomic_file.hpp"
#include "s3m/io/trajectory.hpp"
#include "s3m/mapping/map_io.hpp"

namespace s3m::viewer {
namespace fs = std::filesystem;

namespace {

// The viewer's own files in tools/viewer/ (index.html loads them by these names).
constexpr const char* kOwnFiles[] = {"index.html", "viewer_voxels.js", "viewer.js", "viewer_pick.js", "viewer.css"};
// three.js files inside libjs-three's folder, and their names in the viewer folder.
constexpr const char* kThreeFiles[][2] = {{"three.min.js", "three.min.js"},
                                          {"examples/js/controls/OrbitControls.js", "OrbitControls.js"}};

std::string read_file(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  if (!f) throw Error("viewer: cannot read " + p.string());
  std::ostringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

}  // namespace

std::string find_three_dir() {
  const char* env = std::getenv("S3M_THREE_DIR");
  const fs::path dir = env && *env ? fs::path(env) : fs::path("/usr/share/javascript/three");
  return fs::exists(dir / "three.min.js") ? dir.string() : std::string();
}

std::string find_viewer_assets() {
  const std::string tools = eval::find_tools_dir();
  const fs::path dir = fs::path(tools) / "viewer";
  if (tools.empty() || !fs::exists(dir / "viewer.js"))
    throw Error("viewer: tools/viewer/viewer.js not found (set S3M_TOOLS_DIR to the repository's tools/ folder)");
  return dir.string();
}

ViewerFolder write_viewer(const mapping::SemanticOcTree& map, const SceneExtras& extras, const std::string& dir) {
  ViewerFolder out;
  out.dir = dir;
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw Error("viewer: cannot create '" + dir + "': " + ec.message());
  const fs::path assets = find_viewer_assets();
  for (const char* name : kOwnFiles) io::write_text_atomic(dir + "/" + name, read_file(assets / name));
  io::write_file_atomic(dir + "/map_data.js", [&](std::ostream& s) {
    s << "// s3m semantic map for tools/viewer/viewer.js (format: src/s3m/viewer/viewer_data.hpp)\n"
      << "window.S3M_VIEWER_DATA = " << scene_json(map, extras).dump() << ";\n";
  });
  const std::string three = find_three_dir();
  out.have_three = !three.empty();
  if (out.have_three) {
    for (const auto& [from, to] : kThreeFiles) io::write_text_atomic(dir + "/" + to, read_file(fs::path(three) / from));
    // three.js is MIT-licensed: its notice travels with the copy (Debian's copyright file).
    const fs::path notice = "/usr/share/doc/libjs-three/copyright";
    if (fs::exists(notice)) io::write_text_atomic(dir + "/three.js-LICENSE.txt", read_file(notice));
  } else {
    out.note = "three.js not found (apt-get install libjs-three, or set S3M_THREE_DIR): the 3-D view needs it";
  }
  out.index_html = dir + "/index.html";
  return out;
}

ViewerFolder view_map_file(const ViewInputs& in) {
  const auto map = mapping::load_semantic_map(in.map);
  SceneExtras extras;
  if (!in.trajectory.empty()) extras.trajectory = io::read_trajectory_auto(in.trajectory);
  if (!in.keyframes.empty()) extras.keyframes = io::read_tum_trajectory(in.keyframes);
  extras.camera = in.camera;
  extras.title = "s3m map " + fs::path(in.map).filename().string();
  return write_viewer(*map, extras, in.out_dir);
}

}  // namespace s3m::viewer
