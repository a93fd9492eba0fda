#include "s3m/mapping/semantic_octree.hpp"

#include "s3m/core/error.hpp"

namespace s3m::mapping {

namespace {
std::uint8_t blend(std::uint8_t old_v, std::uint8_t new_v, int weight_old) {
  // Integer rounding keeps the result deterministic and exactly reproducible after a save/load.
  return std::uint8_t((old_v * weight_old + new_v + (weight_old + 1) / 2) / (weight_old + 1));
}
}  // namespace

// ---- node -----------------------------------------------------------------------------------

void SemanticOcTreeNode::integrateColor(Rgb c) {
  if (color_count_ == 0) {
    color_ = c;
    color_count_ = 1;
    return;
  }
  const int w = color_count_;
  color_ = {blend(color_.r, c.r, w), blend(color_.g, c.g, w), blend(color_.b, c.b, w)};
  if (color_count_ < kColorWindow) ++color_count_;
}

void SemanticOcTreeNode::updateOccupancyChildren() {
  setLogOdds(getMaxChildLogOdds());
  const SemanticOcTreeNode* best = nullptr;
  bool best_occupied = false;
  if (children != nullptr) {
    for (int i = 0; i < 8; ++i) {
      const auto* c = static_cast<const SemanticOcTreeNode*>(children[i]);
      if (c == nullptr || (c->labels_.empty() && c->color_count_ == 0)) continue;
      const bool occupied = c->getLogOdds() > 0.0f;
      const bool better = best == nullptr || (occupied && !best_occupied) ||
                          (occupied == best_occupied && c->labels_.top_prob() > best->labels_.top_prob());
      if (better) best = c, best_occupied = occupied;
    }
  }
  if (best != nullptr) {
    labels_ = best->labels_;
    color_ = best->color_;
    color_count_ = best->color_count_;
  } else {
    labels_ = LabelSet{};
    color_count_ = 0;
    color_ = Rgb{};
  }
}

std::ostream& SemanticOcTreeNode::writeData(std::ostream& s) const {
  s.write(reinterpret_cast<const char*>(&value), sizeof(value));
  s.write(reinterpret_cast<const char*>(&color_count_), 1);
  s.write(reinterpret_cast<const char*>(&color_), 3);
  s.write(reinterpret_cast<const char*>(&labels_.n), 1);
  s.write(reinterpret_cast<const char*>(labels_.ids.data()), sizeof(ClassId) * labels_.n);
  s.write(reinterpret_cast<const char*>(labels_.probs.data()), sizeof(float) * labels_.n);
  return s;
}

std::istream& SemanticOcTreeNode::readData(std::istream& s) {
  s.read(reinterpret_cast<char*>(&value), sizeof(value));
  s.read(reinterpret_cast<char*>(&color_count_), 1);
  s.read(reinterpret_cast<char*>(&color_), 3);
  std::uint8_t n = 0;
  s.read(reinterpret_cast<char*>(&n), 1);
  if (!s || n > kMaxLabels)
    throw Error("semantic map node: " + std::string(!s ? "truncated node record" : "label count " +
                                                                                     std::to_string(n) + " > " +
                                                                                     std::to_string(kMaxLabels)));
  labels_ = LabelSet{};
  labels_.n = n;
  s.read(reinterpret_cast<char*>(labels_.ids.data()), sizeof(ClassId) * n);
  s.read(reinterpret_cast<char*>(labels_.probs.data()), sizeof(float) * n);
  if (!s) throw Error("semantic map node: truncated label record");
  return s;
}

// ---- tree -----------------------------------------------------------------------------------

SemanticOcTree::StaticMemberInitializer SemanticOcTree::semantic_octree_member_init_;

SemanticOcTree::StaticMemberInitializer::StaticMemberInitializer() {
  auto* tree = new SemanticOcTree(0.1);  // owned by OctoMap's factory for the process lifetime
  tree->clearKeyRays();
  octomap::AbstractOcTree::registerTreeType(tree);
}

SemanticOcTree::SemanticOcTree(double resolution_m) : OccupancyOcTreeBase<SemanticOcTreeNode>(resolution_m) {
  semantic_octree_member_init_.ensureLinking();
}

void SemanticOcTree::setFusionConfig(const FusionConfig& cfg) {
  cfg.validate();
  fusion_ = cfg;
  fuse_ = fusion_function(cfg.policy);
}

void OccupancyParams::validate() const {
  // OctoMap keeps these as float log-odds and hands them back as probabilities, so the ranges are
  // checked on the value as stored: a probability that rounds to exactly 0 or 1 there would be
  // written into a saved map and refused when the map is loaded again (fuzz_semantic_map: an
  // occupancy threshold of 4.8e-312 was accepted, saved as 0 and refused on reload). Storing is
  // idempotent (a stored value stores as itself), so what passes here passes again after loading.
  const auto stored = [](double p) { return octomap::probability(octomap::logodds(p)); };
  const double hit = stored(prob_hit), miss = stored(prob_miss), lo = stored(clamp_min), hi = stored(clamp_max);
  const double thres = stored(occupancy_thres);
  require(hit > 0.5 && hit < 1.0, "occupancy.prob_hit must be in (0.5, 1) as a float log-odds");
  require(miss > 0.0 && miss < 0.5, "occupancy.prob_miss must be in (0, 0.5) as a float log-odds");
  require(lo > 0.0 && lo < hi && hi < 1.0,
          "occupancy clamping must satisfy 0 < clamp_min < clamp_max < 1 as float log-odds");
  require(thres > 0.0 && thres < 1.0, "occupancy.occupancy_thres must be in (0, 1) as a float log-odds");
}

OccupancyParams SemanticOcTree::occupancyParams() const {
  OccupancyParams p;
  p.prob_hit = getProbHit();
  p.prob_miss = getProbMiss();
  p.clamp_min = getClampingThresMin();
  p.clamp_max = getClampingThresMax();
  p.occupancy_thres = getOccupancyThres();
  return p;
}

void SemanticOcTree::setOccupancyParams(const OccupancyParams& p) {
  p.validate();
  setProbHit(p.prob_hit);
  setProbMiss(p.prob_miss);
  setClampingThresMin(p.clamp_min);
  setClampingThresMax(p.clamp_max);
  setOccupancyThres(p.occupancy_thres);
}

SemanticOcTreeNode* SemanticOcTree::integrateObservation(const octomap::OcTreeKey& key, const LabelSet& obs,
                                                         Rgb color) {
  SemanticOcTreeNode* node = search(key);
  if (node == nullptr) node = updateNode(key, 0.0f, /*lazy_eval=*/true);
  fuse_(node->labels_, obs, fusion_);
  node->integrateColor(color);
  return node;
}

void SemanticOcTree::updateInnerOccupancy() {
  if (root != nullptr) updateInnerRecurs(root, 0);
}

void SemanticOcTree::updateInnerRecurs(SemanticOcTreeNode* node, unsigned depth) {
  if (!nodeHasChildren(node)) return;
  if (depth < tree_depth) {
    for (unsigned i = 0; i < 8; ++i)
      if (nodeChildExists(node, i)) updateInnerRecurs(getNodeChild(node, i), depth + 1);
  }
  node->updateOccupancyChildren();
}

std::size_t restore_occupied(SemanticOcTree& from, SemanticOcTree& into) {
  require(from.getResolution() == into.getResolution(), "restore_occupied: the maps have different resolutions");
  from.expand();
  std::size_t n = 0;
  for (auto it = from.begin_leafs(), end = from.end_leafs(); it != end; ++it) {
    if (!from.isNodeOccupied(*it)) continue;
    const octomap::OcTreeKey key = it.getKey();
    if (const SemanticOcTreeNode* there = into.search(key); there != nullptr && into.isNodeOccupied(*there)) continue;
    SemanticOcTreeNode* node = into.setNodeValue(key, it->getLogOdds(), /*lazy_eval=*/true);
    node->copyData(*it);
    ++n;
  }
  if (n > 0) into.updateInnerOccupancy();
  return n;
}

}  // namespace s3m::mapping
