// Ghost voxels of a run on a simulated sequence with people (run/ghost_voxels.hpp): occupied
// voxels of the final map near a person's path that the static ground-truth map does not explain.
//
//   ./build/bench/bench_dynamic_ghosts SEQ RUN [PEOPLE_SEQ]
//
// SEQ: the sequence (gt_voxels.txt; people.txt unless PEOPLE_SEQ names the sequence whose paths
// to use, e.g. the same flight with people when RUN mapped the people-free one). RUN: an `s3m run`
// folder (map.ot; its metrics.json alignment maps a SLAM world into the ground truth's; a run with
// --poses gt has none and needs none). Prints one JSON line.
#include <cstdio>
#include <fstream>

#include <nlohmann/json.hpp>

#include "s3m/mapping/map_io.hpp"
#include "s3m/run/ghost_voxels.hpp"

using namespace s3m;

namespace {

SE3 alignment(const std::string& run) {
  std::ifstream in(run + "/metrics.json");
  const nlohmann::json m = nlohmann::json::parse(in);
  SE3 T = SE3::Identity();
  if (!m.contains("trajectory") || m["trajectory"].is_null()) return T;  // --poses gt: the GT world
  const auto& a = m["trajectory"]["details"]["alignment"];
  const auto q = a["q_xyzw"], t = a["t_xyz_m"];
  T.linear() =
      Eigen::Quaterniond(q[3].get<double>(), q[0].get<double>(), q[1].get<double>(), q[2].get<double>())
          .toRotationMatrix();
  T.translation() = Eigen::Vector3d(t[0].get<double>(), t[1].get<double>(), t[2].get<double>());
  return T;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s SEQ RUN [PEOPLE_SEQ]\n", argv[0]);
    return 2;
  }
  const std::string seq = argv[1], run = argv[2], people_seq = argc > 3 ? argv[3] : argv[1];
  const auto tree = mapping::load_semantic_map(run + "/map.ot");
  const run::GhostCount g =
      run::count_ghost_voxels(*tree, alignment(run), io::read_gt_voxels(seq + "/gt_voxels.txt"),
                              run::read_people_positions(people_seq + "/people.txt"));
  std::printf("{\"run\": \"%s\", \"occupied\": %zu, \"near_paths\": %zu, \"ghost_voxels\": %zu}\n",
              run.c_str(), g.occupied, g.near_paths, g.ghosts);
  return 0;
}
