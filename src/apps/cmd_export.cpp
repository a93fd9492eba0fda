// `s3m export map.ot --ply map.ply [--color-ot map_color.ot] [--bt map.bt] [--costmap out.yaml
// [--min-z Z --max-z Z] [--class-costs costs.yaml]]`: converts a semantic map for other tools
// (MeshLab/CloudCompare, octovis, octomap_server, a ground robot's map_server).
#include <cstdio>
#include <filesystem>
#include <set>

#include "commands.hpp"
#include "s3m/core/error.hpp"
#include "s3m/mapping/export.hpp"
#include "s3m/mapping/map_io.hpp"
#include "s3m/navigation/costmap.hpp"

namespace s3m::apps {

namespace {

struct ExportOptions {
  std::string map, ply, color_ot, bt, costmap, class_costs;
  navigation::CostmapConfig costmap_cfg;
  std::string ply_color = "rgb";
};

// An export written over the map it reads (or over another export of the same call) would destroy
// it; paths, symlinks and hard links to the same file are all caught.
void refuse_overwrites(const ExportOptions& o) {
  namespace fs = std::filesystem;
  std::set<std::string> outputs;
  for (const auto& [option, out] :
       {std::pair{"--ply", o.ply}, {"--color-ot", o.color_ot}, {"--bt", o.bt}, {"--costmap", o.costmap}}) {
    if (out.empty()) continue;
    std::error_code ec;
    if (fs::exists(out, ec) && fs::equivalent(out, o.map, ec))
      throw Error(std::string("export: ") + option + " '" + out + "' is the map being exported ('" + o.map +
                  "'); write the export to another file");
    require(outputs.insert(fs::weakly_canonical(out, ec).string()).second,
            std::string("export: ") + option + " '" + out + "' is also the path of another export");
  }
}

void run_export(const ExportOptions& o) {
  require(!o.ply.empty() || !o.color_ot.empty() || !o.bt.empty() || !o.costmap.empty(),
          "nothing to do: give --ply, --color-ot, --bt and/or --costmap");
  require(o.class_costs.empty() || !o.costmap.empty(), "--class-costs goes with --costmap");
  refuse_overwrites(o);
  require(o.ply_color == "rgb" || o.ply_color == "class", "--ply-color must be 'rgb' or 'class'");
  // 1. Load (refuses truncated/corrupt files with the reason).
  const auto tree = mapping::load_semantic_map(o.map);
  std::fprintf(stderr, "export: %s: %zu nodes at %.3f m\n", o.map.c_str(), tree->size(),
               tree->getResolution());
  // 2. Each requested format, written atomically.
  if (!o.ply.empty()) {
    const auto n = mapping::export_ply(
        *tree, o.ply, o.ply_color == "class" ? mapping::PlyColor::kClass : mapping::PlyColor::kObserved);
    std::printf("export: wrote %s (%zu occupied voxels with class and confidence)\n", o.ply.c_str(), n);
  }
  if (!o.color_ot.empty()) {
    mapping::export_color_octree(*tree, o.color_ot);
    std::printf("export: wrote %s (ColorOcTree coloured by class, open with octovis)\n", o.color_ot.c_str());
  }
  if (!o.bt.empty()) {
    mapping::export_binary_octree(*tree, o.bt);
    std::printf("export: wrote %s (binary occupancy OcTree)\n", o.bt.c_str());
  }
  if (!o.costmap.empty()) {
    auto cfg = o.costmap_cfg;
    if (!o.class_costs.empty())
      cfg.class_costs = navigation::load_class_costs(o.class_costs, tree->classes());
    const auto grid = navigation::make_costmap(*tree, cfg);
    navigation::write_costmap(grid, o.costmap);
    std::printf("export: wrote %s (map_server costmap, %d x %d cells at %.3f m, z %.2f..%.2f m)\n",
                o.costmap.c_str(), grid.width, grid.height, grid.resolution_m, cfg.min_z_m, cfg.max_z_m);
  }
}

}  // namespace

void register_export(CLI::App& app) {
  auto opts = std::make_shared<ExportOptions>();
  auto* cmd =
      app.add_subcommand("export", "Export a semantic map to PLY, a class-coloured ColorOcTree and/or .bt");
  cmd->add_option("map", opts->map, "semantic map (.ot written by s3m run); or the run's --out folder")
      ->required()
      ->transform(map_or_run_folder())
      ->check(CLI::ExistingFile);
  cmd->add_option("--ply", opts->ply, "PLY points: voxel centres with colour, class id and confidence");
  cmd->add_option("--ply-color", opts->ply_color, "PLY colour: rgb (observed) or class (palette)")
      ->capture_default_str();
  cmd->add_option("--color-ot", opts->color_ot, "ColorOcTree .ot coloured by semantic class");
  cmd->add_option("--bt", opts->bt, "binary occupancy OcTree .bt");
  cmd->add_option("--costmap", opts->costmap,
                  "2-D costmap for a ground robot: map_server YAML (the PGM image is written beside it)");
  cmd->add_option("--min-z", opts->costmap_cfg.min_z_m, "costmap: lowest height projected [m]")
      ->capture_default_str();
  cmd->add_option("--max-z", opts->costmap_cfg.max_z_m, "costmap: highest height projected [m]")
      ->capture_default_str();
  cmd->add_option("--class-costs", opts->class_costs,
                  "costmap: YAML of class: lethal | free | 0..100 | {inflated: RADIUS_M} (unlisted: lethal)")
      ->check(CLI::ExistingFile);
  cmd->callback([opts] { run_export(*opts); });
}

}  // namespace s3m::apps
