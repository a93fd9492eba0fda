// `s3m view MAP.ot [--trajectory T.txt] [--keyframes K.txt] [--out DIR]`: writes the interactive
// 3-D viewer (src/s3m/viewer) for a saved semantic map and prints the page to open.
#include <filesystem>
#include <iostream>

#include "commands.hpp"
#include "s3m/viewer/map_viewer.hpp"

namespace s3m::apps {
namespace fs = std::filesystem;

namespace {

// A run's folder holds its trajectories next to map.ot: use them unless told otherwise.
std::string sibling(const std::string& map, const char* name) {
  const fs::path p = fs::path(map).parent_path() / name;
  return fs::exists(p) ? p.string() : std::string();
}

void run_view(viewer::ViewInputs in, bool no_trajectory) {
  if (in.out_dir.empty()) in.out_dir = (fs::path(in.map).parent_path() / (fs::path(in.map).stem().string() + "_viewer")).string();
  if (!no_trajectory) {
    if (in.trajectory.empty()) in.trajectory = sibling(in.map, "trajectory_camera.txt");
    if (in.keyframes.empty()) in.keyframes = sibling(in.map, "keyframes.txt");
  }
  const viewer::ViewerFolder f = viewer::view_map_file(in);
  if (!in.trajectory.empty()) std::cout << "trajectory: " << in.trajectory << "\n";
  if (!in.keyframes.empty()) std::cout << "keyframes:  " << in.keyframes << "\n";
  if (!f.note.empty()) std::cout << "note: " << f.note << "\n";
  std::cout << "viewer: " << fs::absolute(f.index_html).string() << "\n";
}

}  // namespace

void register_view(CLI::App& app) {
  auto in = std::make_shared<viewer::ViewInputs>();
  auto no_trajectory = std::make_shared<bool>(false);
  auto* cmd = app.add_subcommand("view", "Write an interactive 3-D viewer (HTML, opens from file://) for a semantic map");
  cmd->add_option("map", in->map, "semantic map (.ot written by s3m run or the ROS node); or the run's --out folder")
      ->required()
      ->transform(map_or_run_folder())
      ->check(CLI::ExistingFile);
  cmd->add_option("--trajectory,-t", in->trajectory,
                  "camera trajectory to draw (TUM or KITTI; default: trajectory_camera.txt next to the map)");
  cmd->add_option("--keyframes", in->keyframes, "keyframe poses to draw as frusta (TUM; default: keyframes.txt next to the map)");
  cmd->add_flag("--no-trajectory", *no_trajectory, "do not look for trajectories next to the map");
  cmd->add_option("--out,-o", in->out_dir, "output folder (default: <map>_viewer next to the map)");
  cmd->callback([in, no_trajectory] { run_view(*in, *no_trajectory); });
}

}  // namespace s3m::apps
