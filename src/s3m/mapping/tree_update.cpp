// SemanticOcTree::applyFrameUpdate: the fast path of map insertion.
// Stock OctoMap descends from the root once per updated key (about a million free keys per frame
// at 2 cm). Here the Morton-sorted bricks are applied in one top-down pass: each touched node is
// visited once, a pruned free region whose whole subtree only receives misses is skipped without
// expanding it (the update could not change it: it is clamped), and disjoint subtrees run as
// parallel TBB tasks. Every node is written by exactly one task, so the result does not depend on
// the number of threads. Per-leaf arithmetic is OctoMap's (add log-odds, clamp), inner nodes are
// pruned or aggregated exactly like updateNode(..., lazy_eval = false) does.
#include <algorithm>
#include <atomic>

#include <tbb/task_group.h>

#include "s3m/mapping/frame_update.hpp"
#include "s3m/mapping/semantic_octree.hpp"

namespace s3m::mapping {

using Node = SemanticOcTreeNode;

struct TreeUpdater {
  SemanticOcTree& tree;
  const FrameUpdate& update;
  std::atomic<long> size_delta{0};
  static constexpr std::ptrdiff_t kParallelBricks = 24;  // below this a subtree runs serially

  static Node* childAt(const Node* n, unsigned i) { return static_cast<Node*>(n->children[i]); }

  bool hasChildren(const Node* n) const {
    if (n->children == nullptr) return false;
    for (int i = 0; i < 8; ++i)
      if (n->children[i] != nullptr) return true;
    return false;
  }

  // Child i of node, creating it (fresh) or expanding a pruned node (children copy its payload).
  Node* child(Node* node, unsigned i, bool node_created, bool& child_created) {
    child_created = false;
    if (node->children != nullptr && node->children[i] != nullptr) return childAt(node, i);
    if (!node_created && !hasChildren(node)) {  // pruned leaf above max depth: expand
      if (node->children == nullptr) tree.allocNodeChildren(node);
      for (unsigned c = 0; c < 8; ++c) {
        Node* n = new Node();
        n->copyData(*node);
        node->children[c] = n;
      }
      size_delta += 8;
      return childAt(node, i);
    }
    if (node->children == nullptr) tree.allocNodeChildren(node);
    Node* n = new Node();
    node->children[i] = n;
    ++size_delta;
    child_created = true;
    return n;
  }

  // Pruning as OcTreeBaseImpl::pruneNode (identical leaf children collapse), else aggregation.
  void finishInner(Node* node) {
    bool collapsible = node->children != nullptr;
    for (unsigned i = 0; collapsible && i < 8; ++i) {
      const Node* c = static_cast<const Node*>(node->children[i]);
      collapsible = c != nullptr && !hasChildren(c) && *c == *static_cast<const Node*>(node->children[0]);
    }
    if (!collapsible) {
      node->updateOccupancyChildren();
      return;
    }
    node->copyData(*static_cast<const Node*>(node->children[0]));
    for (unsigned i = 0; i < 8; ++i) tree.deleteNodeRecurs(childAt(node, i)), node->children[i] = nullptr;
    delete[] node->children;
    node->children = nullptr;
    size_delta -= 8;
  }

  bool clampedFree(const Node* n) const { return n->getLogOdds() <= tree.clamping_thres_min; }

  void updateLeaf(Node* leaf, bool occupied, const VoxelObservation* obs) {
    float v = leaf->getLogOdds() + (occupied ? tree.prob_hit_log : tree.prob_miss_log);
    v = std::clamp(v, tree.clamping_thres_min, tree.clamping_thres_max);
    leaf->setLogOdds(v);
    if (!occupied) return;
    tree.fuse_(leaf->labels_, obs->labels, tree.fusion_);
    if (obs->has_color) leaf->integrateColor(obs->color);
  }

  // ---- inside a brick: bit range [base, base + span) of the brick's masks --------------------
  static bool anyBits(const std::array<std::uint64_t, 8>& m, unsigned base, unsigned span) {
    if (span >= 64) {
      for (unsigned w = base / 64; w < (base + span) / 64; ++w)
        if (m[w]) return true;
      return false;
    }
    const std::uint64_t mask = (span == 64 ? ~0ull : ((1ull << span) - 1)) << (base % 64);
    return (m[base / 64] & mask) != 0;
  }
  static bool bit(const std::array<std::uint64_t, 8>& m, unsigned b) { return (m[b / 64] >> (b % 64)) & 1u; }

  void updateInBrick(Node* node, unsigned depth, const BrickUpdate& b, unsigned base, unsigned span,
                     std::uint32_t& obs, bool created) {
    if (!created && !hasChildren(node) && clampedFree(node) && !anyBits(b.occupied, base, span)) return;
    const unsigned sub = span / 8;
    for (unsigned i = 0; i < 8; ++i) {
      const unsigned cb = base + i * sub;
      const bool occ = anyBits(b.occupied, cb, sub), fre = anyBits(b.free, cb, sub);
      if (!occ && !fre) continue;
      bool child_created = false;
      Node* c = child(node, i, created, child_created);
      if (sub == 1) {
        updateLeaf(c, occ, occ ? &update.observations[obs] : nullptr);
        obs += occ;
      } else {
        updateInBrick(c, depth + 1, b, cb, sub, obs, child_created);
      }
    }
    finishInner(node);
  }

  // ---- above the bricks: a Morton-sorted range of bricks below node ---------------------------
  void updateAbove(Node* node, unsigned depth, const BrickUpdate* begin, const BrickUpdate* end, bool created) {
    if (depth == kBrickDepth) {
      std::uint32_t obs = begin->first_obs;
      updateInBrick(node, depth, *begin, 0, 512, obs, created);
      return;
    }
    if (!created && !hasChildren(node) && clampedFree(node) &&
        std::none_of(begin, end, [](const BrickUpdate& b) { return anyBits(b.occupied, 0, 512); }))
      return;
    const BrickUpdate* split[9];
    split[0] = begin;
    for (unsigned i = 0; i < 8; ++i)
      split[i + 1] = std::partition_point(split[i], end, [&](const BrickUpdate& b) {
        return brick_child_at(b.morton, depth) <= i;
      });
    Node* kids[8] = {};
    bool kid_created[8] = {};
    int nonempty = 0;
    for (unsigned i = 0; i < 8; ++i)
      if (split[i] != split[i + 1]) kids[i] = child(node, i, created, kid_created[i]), ++nonempty;
    if (nonempty > 1 && end - begin >= kParallelBricks) {
      tbb::task_group tasks;
      for (unsigned i = 0; i < 8; ++i)
        if (kids[i]) tasks.run([=, this] { updateAbove(kids[i], depth + 1, split[i], split[i + 1], kid_created[i]); });
      tasks.wait();
    } else {
      for (unsigned i = 0; i < 8; ++i)
        if (kids[i]) updateAbove(kids[i], depth + 1, split[i], split[i + 1], kid_created[i]);
    }
    finishInner(node);
  }
};

void SemanticOcTree::applyFrameUpdate(const FrameUpdate& update) {
  if (update.bricks.empty()) return;
  bool created = false;
  if (root == nullptr) {
    root = new SemanticOcTreeNode();
    ++tree_size;
    created = true;
  }
  TreeUpdater updater{*this, update};
  updater.updateAbove(root, 0, update.bricks.data(), update.bricks.data() + update.bricks.size(), created);
  tree_size = std::size_t(long(tree_size) + updater.size_delta.load());
  size_changed = true;
}

}  // namespace s3m::mapping
