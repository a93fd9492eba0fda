// `s3m query map.ot --class chair [--json]`: object instances of a class in a semantic map;
// `--at x y z` asks for the class at a point; `--clearance x,y,z` for the distance to the nearest
// obstacle (distance field, unknown space counted as occupied unless --unknown free); without any,
// a per-class summary.
#include <cstdio>
#include <iostream>

#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "s3m/core/error.hpp"
#include "s3m/mapping/map_io.hpp"
#include "s3m/mapping/queries.hpp"
#include "s3m/navigation/distance_field.hpp"

namespace s3m::apps {

namespace {

struct QueryOptions {
  std::string map;
  std::string cls;
  std::vector<double> at, clearance;
  std::string unknown = "occupied";
  double max_distance_m = 2.0;
  std::size_t min_voxels = 10;  // the viewer's instance_min_voxels: specks are not objects
  bool json = false;
};

nlohmann::json to_json(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

nlohmann::json instances_json(const mapping::SemanticOcTree& tree, ClassId id, std::size_t min_voxels) {
  nlohmann::json list = nlohmann::json::array();
  for (const auto& o : mapping::object_instances(tree, id, min_voxels))
    list.push_back({{"class", tree.classes().at(o.label).name},
                    {"class_id", o.label},
                    {"voxels", o.voxels},
                    {"centroid_m", to_json(o.centroid_w)},
                    {"bbox_min_m", to_json(o.bbox_min_w)},
                    {"bbox_max_m", to_json(o.bbox_max_w)},
                    {"volume_m3", o.volume_m3},
                    {"mean_confidence", o.mean_confidence}});
  return list;
}

ClassId class_by_name(const mapping::SemanticOcTree& tree, const std::string& name) {
  const int id = tree.classes().find(name);
  if (id >= 0) return ClassId(id);
  std::string known;
  for (const auto& c : tree.classes().all()) known += (known.empty() ? "" : ", ") + c.name;
  throw Error("unknown class '" + name + "' (the map's classes: " + known + ")");
}

void print_text(const nlohmann::json& result) {
  if (result.contains("at")) {
    const auto& a = result["at"];
    if (a.is_null())
      std::printf("no occupied, labelled voxel there\n");
    else
      std::printf("%s (p=%.3f, occupancy %.3f, voxel %.3f m at %.3f %.3f %.3f)\n",
                  a["class"].get<std::string>().c_str(), a["confidence"].get<double>(),
                  a["occupancy"].get<double>(), a["size_m"].get<double>(), a["center_m"][0].get<double>(),
                  a["center_m"][1].get<double>(), a["center_m"][2].get<double>());
  }
  if (result.contains("clearance")) {
    const auto& c = result["clearance"];
    std::printf("clearance %.3f m at (%.3f, %.3f, %.3f) (unknown space %s, saturates at %.2f m)\n",
                c["clearance_m"].get<double>(), c["point_m"][0].get<double>(), c["point_m"][1].get<double>(),
                c["point_m"][2].get<double>(), c["unknown_space"].get<std::string>().c_str(),
                c["max_distance_m"].get<double>());
  }
  if (result.contains("instances")) {
    std::printf("%zu instance(s)\n", result["instances"].size());
    for (const auto& o : result["instances"])
      std::printf("  %-12s %6zu voxels  %.4f m3  centroid (%.3f, %.3f, %.3f)  p=%.3f\n",
                  o["class"].get<std::string>().c_str(), o["voxels"].get<std::size_t>(),
                  o["volume_m3"].get<double>(), o["centroid_m"][0].get<double>(),
                  o["centroid_m"][1].get<double>(), o["centroid_m"][2].get<double>(),
                  o["mean_confidence"].get<double>());
  }
  if (result.contains("classes"))
    for (const auto& [name, n] : result["classes"].items())
      std::printf("  %-12s %zu voxels\n", name.c_str(), n.get<std::size_t>());
}

void run_query(const QueryOptions& o) {
  // 1. Load (refuses truncated/corrupt files with the reason).
  const auto tree = mapping::load_semantic_map(o.map);
  nlohmann::json result = {{"map", o.map}, {"resolution_m", tree->getResolution()}};
  // 2. Class at a point.
  if (!o.at.empty()) {
    require(o.at.size() == 3, "--at needs three coordinates x y z [m]");
    const auto v = mapping::class_at(*tree, {o.at[0], o.at[1], o.at[2]});
    result["at"] = v ? nlohmann::json{{"class", tree->classes().at(v->label).name},
                                      {"class_id", v->label},
                                      {"confidence", v->confidence},
                                      {"occupancy", v->occupancy},
                                      {"size_m", v->size_m},
                                      {"center_m", to_json(v->center_w)}}
                     : nlohmann::json(nullptr);
  }
  // 3. Clearance at a point (distance field over the whole map).
  if (!o.clearance.empty()) {
    require(o.clearance.size() == 3, "--clearance needs three coordinates x,y,z [m]");
    navigation::DistanceFieldConfig fc;
    fc.unknown = navigation::unknown_space_from_string(o.unknown);
    fc.max_distance_m = o.max_distance_m;
    const navigation::DistanceField field(*tree, fc);
    const Eigen::Vector3d p(o.clearance[0], o.clearance[1], o.clearance[2]);
    result["clearance"] = {{"point_m", to_json(p)},
                           {"clearance_m", field.clearance(p)},
                           {"inside_map", field.contains(p)},
                           {"unknown_space", o.unknown},
                           {"max_distance_m", o.max_distance_m}};
  }
  // 4. Instances of a class, or a per-class voxel count.
  if (!o.cls.empty()) result["instances"] = instances_json(*tree, class_by_name(*tree, o.cls), o.min_voxels);
  if (o.cls.empty() && o.at.empty() && o.clearance.empty()) {
    result["classes"] = nlohmann::json::object();
    for (const auto& c : tree->classes().all()) {
      const auto n = mapping::voxels_of_class(*tree, c.id).size();
      if (n > 0) result["classes"][c.name] = n;
    }
  }
  if (o.json)
    std::cout << result.dump(2) << "\n";
  else
    print_text(result);
}

}  // namespace

void register_query(CLI::App& app) {
  auto opts = std::make_shared<QueryOptions>();
  auto* cmd =
      app.add_subcommand("query", "Query a semantic map: object instances of a class, class at a point");
  cmd->add_option("map", opts->map, "semantic map (.ot written by s3m run); or the run's --out folder")
      ->required()
      ->transform(map_or_run_folder())
      ->check(CLI::ExistingFile);
  cmd->add_option("--class,-c", opts->cls, "class name: list its object instances (connected components)");
  cmd->add_option("--at", opts->at, "x y z [m]: class of the voxel at this world point")->expected(3);
  cmd->add_option("--clearance", opts->clearance,
                  "x,y,z [m]: distance to the nearest obstacle from this point")
      ->expected(3)
      ->delimiter(',');
  cmd->add_option("--unknown", opts->unknown, "for --clearance, unknown space counts as: occupied or free")
      ->check(CLI::IsMember({"occupied", "free"}))
      ->capture_default_str();
  cmd->add_option("--max-distance", opts->max_distance_m, "for --clearance, distances saturate here [m]")
      ->capture_default_str();
  cmd->add_option("--min-voxels", opts->min_voxels, "ignore instances smaller than this")
      ->capture_default_str();
  cmd->add_flag("--json", opts->json, "print JSON instead of text");
  cmd->callback([opts] { run_query(*opts); });
}

}  // namespace s3m::apps
