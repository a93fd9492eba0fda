#include "s3m/mapping/export.hpp"

#include <octomap/ColorOcTree.h>
#include <octomap/OcTree.h>

#include "s3m/core/error.hpp"
#include "s3m/io/atomic_file.hpp"
#include "s3m/io/ply.hpp"

namespace s3m::mapping {
namespace {

Rgb display_color(const SemanticOcTree& tree, const SemanticOcTreeNode& n) {
  const ClassId id = n.labels().top();
  if (!n.labels().empty() && id < tree.classes().size()) {
    const ClassInfo& c = tree.classes().at(id);
    return {c.r, c.g, c.b};
  }
  return n.hasColor() ? n.color() : Rgb{200, 200, 200};
}

// Copies the tree shape node by node into an OctoMap tree of another node type. Deriving gives
// access to the protected root; createNodeChild() keeps the destination's node count right.
template <typename Base>
class ShapeCopy : public Base {
 public:
  explicit ShapeCopy(double res) : Base(res) {}
  template <typename SetPayload>
  void copyFrom(const SemanticOcTree& src, SetPayload&& set) {
    if (src.getRoot() == nullptr) return;
    this->root = new typename Base::NodeType();
    ++this->tree_size;
    copyRecurs(src, src.getRoot(), this->root, set);
  }

 private:
  template <typename SetPayload>
  void copyRecurs(const SemanticOcTree& src, const SemanticOcTreeNode* s, typename Base::NodeType* d, SetPayload& set) {
    set(*s, *d);
    if (!src.nodeHasChildren(s)) return;
    for (unsigned i = 0; i < 8; ++i)
      if (src.nodeChildExists(s, i)) copyRecurs(src, src.getNodeChild(s, i), this->createNodeChild(d, i), set);
  }
};

template <typename Tree>
void copy_params(const SemanticOcTree& src, Tree& dst) {
  const OccupancyParams p = src.occupancyParams();
  dst.setProbHit(p.prob_hit);
  dst.setProbMiss(p.prob_miss);
  dst.setClampingThresMin(p.clamp_min);
  dst.setClampingThresMax(p.clamp_max);
  dst.setOccupancyThres(p.occupancy_thres);
}

}  // namespace

void export_color_octree(const SemanticOcTree& tree, const std::string& path) {
  ShapeCopy<octomap::ColorOcTree> out(tree.getResolution());
  copy_params(tree, out);
  out.copyFrom(tree, [&](const SemanticOcTreeNode& s, octomap::ColorOcTreeNode& d) {
    d.setLogOdds(s.getLogOdds());
    const Rgb c = display_color(tree, s);
    d.setColor(c.r, c.g, c.b);
  });
  io::write_file_atomic(path, [&](std::ostream& s) {
    if (!out.write(s)) throw Error("serialising the ColorOcTree failed");
  });
}

void export_binary_octree(const SemanticOcTree& tree, const std::string& path) {
  ShapeCopy<octomap::OcTree> out(tree.getResolution());
  copy_params(tree, out);
  out.copyFrom(tree, [](const SemanticOcTreeNode& s, octomap::OcTreeNode& d) { d.setLogOdds(s.getLogOdds()); });
  out.toMaxLikelihood();
  out.prune();
  io::write_file_atomic(path, [&](std::ostream& s) {
    if (!out.writeBinaryConst(s)) throw Error("serialising the binary OcTree failed");
  });
}

std::vector<OccupiedVoxel> occupied_voxels(const SemanticOcTree& tree, PlyColor color) {
  std::vector<OccupiedVoxel> out;
  const double res = tree.getResolution();
  for (auto it = tree.begin_leafs(); it != tree.end_leafs(); ++it) {
    if (!tree.isNodeOccupied(*it)) continue;
    const Rgb c = color == PlyColor::kClass || !it->hasColor() ? display_color(tree, *it) : it->color();
    const int span = 1 << (tree.getTreeDepth() - it.getDepth());
    const octomap::point3d centre = it.getCoordinate();
    for (int x = 0; x < span; ++x)
      for (int y = 0; y < span; ++y)
        for (int z = 0; z < span; ++z) {  // pruned occupied nodes: one point per finest voxel
          OccupiedVoxel v;
          v.centre_w = {float(centre.x() + (x - (span - 1) / 2.0) * res), float(centre.y() + (y - (span - 1) / 2.0) * res),
                        float(centre.z() + (z - (span - 1) / 2.0) * res)};
          v.color = c;
          v.label = it->labels().top();
          v.confidence = it->labels().top_prob();
          out.push_back(v);
        }
  }
  return out;
}

std::size_t export_ply(const SemanticOcTree& tree, const std::string& path, PlyColor color) {
  std::vector<io::PlyPoint> points;
  for (const OccupiedVoxel& v : occupied_voxels(tree, color)) {
    io::PlyPoint p;
    p.x = v.centre_w.x(), p.y = v.centre_w.y(), p.z = v.centre_w.z();
    p.r = v.color.r, p.g = v.color.g, p.b = v.color.b;
    p.label = v.label;
    p.confidence = v.confidence;
    points.push_back(p);
  }
  io::write_ply(path, points, /*with_semantics=*/true);
  return points.size();
}

}  // namespace s3m::mapping
