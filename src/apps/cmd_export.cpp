// `s3m export map.ot --ply map.ply [--color-ot map_color.ot] [--bt map.bt]`: converts a semantic
// map for other tools (MeshLab/CloudCompare, octovis, octomap_server).
#include <cstdio>
#include <filesystem>
#include <set>

#include "commands.hpp"
#include "s3m/core/error.hpp"
#include "s3m/mapping/export.hpp"
#include "s3m/mapping/map_io.hpp"

namespace s3m::apps {

namespace {

struct ExportOptions {
  std::string map, ply, color_ot, bt;
  std::string ply_color = "rgb";
};

// An export written over the map it reads (or over another export of the same call) would destroy
// it; paths, symlinks and hard links to the same file are all caught.
void refuse_overwrites(const ExportOptions& o) {
  namespace fs = std::filesystem;
  std::set<std::string> outputs;
  for (const auto& [option, out] : {std::pair{"--ply", o.ply}, {"--color-ot", o.color_ot}, {"--bt", o.bt}}) {
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
  require(!o.ply.empty() || !o.color_ot.empty() || !o.bt.empty(),
          "nothing to do: give --ply, --color-ot and/or --bt");
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
  cmd->callback([opts] { run_export(*opts); });
}

}  // namespace s3m::apps
