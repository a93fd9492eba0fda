// The distance field against a brute-force Euclidean distance transform on small maps built by
// ray casting (OctoMap's insertPointCloud) from random scans, fixed seeds; both unknown-space
// policies, before and after incremental updates.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "s3m/core/error.hpp"
#include "s3m/navigation/distance_field.hpp"

using namespace s3m;
using namespace s3m::navigation;

namespace {
constexpr double kRes = 0.1;

// Points on the faces of a few random boxes in a 2.4 x 2.4 x 1.2 m room, seen from random origins.
void insert_scans(mapping::SemanticOcTree& tree, std::mt19937& rng, int scans) {
  std::uniform_real_distribution<double> ux(0.1, 2.3), uz(0.1, 1.1), u01(0.0, 1.0);
  for (int s = 0; s < scans; ++s) {
    const Eigen::Vector3d lo(ux(rng), ux(rng), uz(rng));
    const Eigen::Vector3d hi =
        (lo + Eigen::Vector3d(0.2 + 0.4 * u01(rng), 0.2 + 0.4 * u01(rng), 0.3)).cwiseMin(2.35);
    octomap::Pointcloud cloud;
    for (int i = 0; i < 400; ++i) {
      Eigen::Vector3d p = lo + (hi - lo).cwiseProduct(Eigen::Vector3d(u01(rng), u01(rng), u01(rng)));
      const int axis = int(3 * u01(rng)) % 3;
      p[axis] = u01(rng) < 0.5 ? lo[axis] : hi[axis];  // on a face
      cloud.push_back(float(p.x()), float(p.y()), float(p.z()));
    }
    const octomap::point3d origin(float(ux(rng)), float(ux(rng)), float(uz(rng)));
    tree.insertPointCloud(cloud, origin);
  }
}

bool is_obstacle(const mapping::SemanticOcTree& tree, const octomap::point3d& c, UnknownSpace unknown) {
  const auto* n = tree.search(c);
  return n == nullptr ? unknown == UnknownSpace::kOccupied : tree.isNodeOccupied(n);
}

// Largest |field - brute force| over every voxel centre of the field's box [m].
double worst_error(const mapping::SemanticOcTree& tree, const DistanceField& field) {
  std::vector<Eigen::Vector3d> centres, obstacles;
  const Eigen::Vector3i n = ((field.max_w() - field.min_w()) / kRes).array().round().cast<int>() + 1;
  for (int x = 0; x < n.x(); ++x)
    for (int y = 0; y < n.y(); ++y)
      for (int z = 0; z < n.z(); ++z) {
        const Eigen::Vector3d c = field.min_w() + kRes * Eigen::Vector3d(x, y, z);
        centres.push_back(c);
        if (is_obstacle(tree, octomap::point3d(float(c.x()), float(c.y()), float(c.z())),
                        field.config().unknown))
          obstacles.push_back(c);
      }
  double worst = 0.0;
  for (const auto& c : centres) {
    double bf = field.config().max_distance_m;
    for (const auto& o : obstacles) bf = std::min(bf, (c - o).norm());
    worst = std::max(worst, std::abs(field.clearance(c) - bf));
  }
  return worst;
}

}  // namespace

class DistanceFieldProperty : public ::testing::TestWithParam<std::tuple<unsigned, UnknownSpace>> {};

TEST_P(DistanceFieldProperty, WithinOneVoxelOfBruteForceBeforeAndAfterUpdates) {
  const auto [seed, unknown] = GetParam();
  std::mt19937 rng(seed);
  mapping::SemanticOcTree tree(kRes);
  insert_scans(tree, rng, 6);
  DistanceFieldConfig cfg;
  cfg.unknown = unknown;
  cfg.max_distance_m = 0.8;
  DistanceField field(tree, cfg);
  EXPECT_LE(worst_error(tree, field), kRes);
  // Later scans inside the same extent, folded in incrementally.
  insert_scans(tree, rng, 4);
  field.update();
  EXPECT_LE(worst_error(tree, field), kRes);
}

INSTANTIATE_TEST_SUITE_P(Seeds, DistanceFieldProperty,
                         ::testing::Combine(::testing::Values(1u, 2u, 3u),
                                            ::testing::Values(UnknownSpace::kOccupied, UnknownSpace::kFree)));

TEST(DistanceField, KnownDistancesAndPolicies) {
  // A free 1.1 m cube of voxels with one occupied voxel at its centre.
  mapping::SemanticOcTree tree(kRes);
  for (int x = 0; x < 11; ++x)
    for (int y = 0; y < 11; ++y)
      for (int z = 0; z < 11; ++z)
        tree.updateNode(tree.coordToKey((x + 0.5) * kRes, (y + 0.5) * kRes, (z + 0.5) * kRes),
                        x == 5 && y == 5 && z == 5 ? 2.0f : -2.0f);
  DistanceFieldConfig free_cfg;
  free_cfg.unknown = UnknownSpace::kFree;
  {
    const DistanceField f(tree, free_cfg);
    EXPECT_NEAR(f.clearance({0.55, 0.55, 0.55}), 0.0, 1e-6);
    EXPECT_NEAR(f.clearance({0.85, 0.55, 0.55}), 0.3, 1e-5);
    EXPECT_NEAR(f.clearance({0.85, 0.85, 0.55}), std::sqrt(0.18), 1e-5);
    EXPECT_NEAR(f.clearance({5.0, 5.0, 5.0}), free_cfg.max_distance_m, 1e-9);  // outside: free
  }
  const DistanceField f(tree, {});  // unknown = occupied: the space round the cube is an obstacle
  EXPECT_NEAR(f.clearance({0.05, 0.55, 0.55}), 0.1, 1e-5);  // next to the unknown shell
  EXPECT_NEAR(f.clearance({0.25, 0.55, 0.55}), 0.3, 1e-5);  // nearer the shell than the centre voxel
  EXPECT_EQ(f.clearance({5.0, 5.0, 5.0}), 0.0);
  EXPECT_THROW(unknown_space_from_string("maybe"), Error);
  DistanceFieldConfig bad;
  bad.max_distance_m = 0.0;
  EXPECT_THROW(bad.validate(), Error);
}
