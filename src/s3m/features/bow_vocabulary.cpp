#include "s3m/features/bow_vocabulary.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <random>
#include <set>

#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

#include "s3m/core/error.hpp"
#include "s3m/core/shipped_files.hpp"

namespace s3m::features {

void VocabularyConfig::validate() const {
  require(branching >= 2, "VocabularyConfig.branching must be >= 2");
  require(levels >= 1, "VocabularyConfig.levels must be >= 1");
  require(std::pow(double(branching), double(levels)) <= 1e8,
          "VocabularyConfig: branching^levels must be <= 1e8 words");
  require(max_iterations >= 1, "VocabularyConfig.max_iterations must be >= 1");
}

// Hierarchical k-medians (DBoW2's HKmeansStep, breadth first): each node's descriptors are split
// into k clusters seeded with k-means++; cluster centres are per-bit majorities, the binary
// analogue of a mean that minimises the summed Hamming distance bit by bit.
class VocabularyBuilder {
 public:
  VocabularyBuilder(const VocabularyConfig& config, const std::vector<Descriptor256>& descriptors,
                    const Vocabulary::Progress& progress)
      : config_(config), descriptors_(descriptors), progress_(progress), rng_(config.seed) {}

  void build_tree(Vocabulary& vocab) {
    vocab.branching_ = config_.branching;
    vocab.levels_ = config_.levels;
    vocab.nodes_.assign(1, Vocabulary::Node{});
    struct Pending {
      NodeId node;
      int depth;
      std::vector<uint32_t> members;
    };
    std::deque<Pending> queue;
    std::vector<uint32_t> all(descriptors_.size());
    for (uint32_t i = 0; i < all.size(); ++i) all[i] = i;
    queue.push_back({0, 0, std::move(all)});
    size_t done = 0;
    while (!queue.empty()) {
      Pending p = std::move(queue.front());
      queue.pop_front();
      // A node with few descriptors stays a leaf: splitting it further would give words seen once.
      if (p.depth == config_.levels || p.members.size() <= size_t(config_.branching)) {
        done += p.members.size();
        if (progress_) progress_(done, descriptors_.size());
        continue;
      }
      for (Cluster& c : k_medians(p.members)) {
        const auto child = NodeId(vocab.nodes_.size());
        Vocabulary::Node node;
        node.parent = p.node;
        node.descriptor = c.centre;
        vocab.nodes_.push_back(node);
        vocab.nodes_[p.node].children.push_back(child);
        queue.push_back({child, p.depth + 1, std::move(c.members)});
      }
    }
    vocab.index_words();
  }

 private:
  struct Cluster {
    Descriptor256 centre;
    std::vector<uint32_t> members;
  };

  std::vector<Descriptor256> seed_centres(const std::vector<uint32_t>& members) {
    std::vector<Descriptor256> centres;
    std::uniform_int_distribution<size_t> pick(0, members.size() - 1);
    centres.push_back(descriptors_[members[pick(rng_)]]);
    std::vector<double> d2(members.size(), std::numeric_limits<double>::max());
    while (centres.size() < size_t(config_.branching)) {
      double total = 0.0;
      for (size_t i = 0; i < members.size(); ++i) {
        const double d = hamming(descriptors_[members[i]], centres.back());
        d2[i] = std::min(d2[i], d * d);
        total += d2[i];
      }
      if (total <= 0.0) break;  // every remaining descriptor duplicates a centre
      double r = std::uniform_real_distribution<double>(0.0, total)(rng_);
      size_t chosen = members.size() - 1;
      for (size_t i = 0; i < members.size(); ++i) {
        r -= d2[i];
        if (r <= 0.0 && d2[i] > 0.0) {
          chosen = i;
          break;
        }
      }
      centres.push_back(descriptors_[members[chosen]]);
    }
    return centres;
  }

  Descriptor256 majority(const std::vector<uint32_t>& members) const {
    std::array<uint32_t, 256> ones{};
    for (uint32_t m : members) {
      const Descriptor256& d = descriptors_[m];
      for (int w = 0; w < 4; ++w) {
        uint64_t bits = d[w];
        while (bits) {
          ones[w * 64 + __builtin_ctzll(bits)]++;
          bits &= bits - 1;
        }
      }
    }
    Descriptor256 c{};
    for (int b = 0; b < 256; ++b) {
      if (2 * ones[b] > members.size()) c[b / 64] |= uint64_t{1} << (b % 64);
    }
    return c;
  }

  std::vector<Cluster> k_medians(const std::vector<uint32_t>& members) {
    std::vector<Descriptor256> centres = seed_centres(members);
    std::vector<int> assignment(members.size(), -1);
    for (int it = 0; it < config_.max_iterations; ++it) {
      bool changed = false;
      for (size_t i = 0; i < members.size(); ++i) {
        int best = 0;
        int best_d = 257;
        for (size_t c = 0; c < centres.size(); ++c) {
          const int d = hamming(descriptors_[members[i]], centres[c]);
          if (d < best_d) best_d = d, best = int(c);
        }
        if (assignment[i] != best) assignment[i] = best, changed = true;
      }
      if (!changed) break;
      std::vector<std::vector<uint32_t>> groups(centres.size());
      for (size_t i = 0; i < members.size(); ++i) groups[assignment[i]].push_back(members[i]);
      for (size_t c = 0; c < centres.size(); ++c) {
        if (!groups[c].empty()) centres[c] = majority(groups[c]);
      }
    }
    std::vector<Cluster> clusters(centres.size());
    for (size_t c = 0; c < centres.size(); ++c) clusters[c].centre = centres[c];
    for (size_t i = 0; i < members.size(); ++i) clusters[assignment[i]].members.push_back(members[i]);
    std::erase_if(clusters, [](const Cluster& c) { return c.members.empty(); });
    return clusters;
  }

  const VocabularyConfig& config_;
  const std::vector<Descriptor256>& descriptors_;
  const Vocabulary::Progress& progress_;
  std::mt19937_64 rng_;
};

Vocabulary Vocabulary::train(const std::vector<cv::Mat>& descriptors_per_image, const VocabularyConfig& config,
                             const Progress& progress) {
  config.validate();
  std::vector<Descriptor256> all;
  for (const cv::Mat& d : descriptors_per_image) {
    require_orb_descriptors(d, "Vocabulary::train");
    for (int r = 0; r < d.rows; ++r) all.push_back(descriptor_from_row(d, r));
  }
  if (all.empty()) throw Error("Vocabulary::train: no descriptors in " + std::to_string(descriptors_per_image.size()) +
                               " training images");
  Vocabulary vocab;
  VocabularyBuilder(config, all, progress).build_tree(vocab);

  // IDF: a word seen in every training image carries no information (weight 0); unseen words
  // (possible when greedy descent disagrees with the clustering) get the maximum weight.
  std::vector<uint32_t> images_with_word(vocab.num_words(), 0);
  uint32_t images = 0;
  for (const cv::Mat& d : descriptors_per_image) {
    if (d.rows == 0) continue;
    ++images;
    std::set<WordId> seen;
    for (int r = 0; r < d.rows; ++r) seen.insert(vocab.word_of(descriptor_from_row(d, r)));
    for (WordId w : seen) images_with_word[w]++;
  }
  vocab.training_images_ = images;
  for (WordId w = 0; w < vocab.num_words(); ++w) {
    const double n = std::max<uint32_t>(images_with_word[w], 1);
    vocab.nodes_[vocab.words_[w]].weight = float(std::log(double(images) / n));
  }
  return vocab;
}

void Vocabulary::index_words() {
  words_.clear();
  word_of_node_.assign(nodes_.size(), 0);
  for (NodeId n = 0; n < nodes_.size(); ++n) {
    if (nodes_[n].is_leaf()) {
      word_of_node_[n] = WordId(words_.size());
      words_.push_back(n);
    }
  }
}

WordId Vocabulary::word_of(const Descriptor256& d, NodeId* node_at_level, int level) const {
  require(!empty(), "Vocabulary::word_of: the vocabulary is empty");
  NodeId n = 0;
  int depth = 0;
  if (node_at_level) *node_at_level = 0;
  while (!nodes_[n].is_leaf()) {
    int best_d = 257;
    NodeId best = nodes_[n].children.front();
    for (NodeId c : nodes_[n].children) {
      const int dist = hamming(d, nodes_[c].descriptor);
      if (dist < best_d) best_d = dist, best = c;
    }
    n = best;
    ++depth;
    if (node_at_level && depth <= level) *node_at_level = n;
  }
  return word_of_node_[n];
}

BowVector Vocabulary::transform(const cv::Mat& descriptors, FeatureVector* fv, int direct_level) const {
  require_orb_descriptors(descriptors, "Vocabulary::transform");
  BowVector bow;
  if (fv) fv->clear();
  for (int r = 0; r < descriptors.rows; ++r) {
    NodeId node = 0;
    const WordId w = word_of(descriptor_from_row(descriptors, r), &node, direct_level);
    const double weight = nodes_[words_[w]].weight;
    if (weight > 0.0) bow[w] += weight;
    if (fv) (*fv)[node].push_back(r);
  }
  normalize_l1(bow);
  return bow;
}

std::string default_vocabulary_path() { return shipped_file("vocab/orb_k10_l5.bin"); }

cv::Mat extract_orb_descriptors(const cv::Mat& image, int num_features) {
  require(!image.empty(), "extract_orb_descriptors: empty image");
  require(num_features > 0, "extract_orb_descriptors: num_features must be > 0");
  cv::Mat grey = image;
  if (image.channels() == 3) cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
  auto orb = cv::ORB::create(num_features, 1.2F, 8);
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;
  orb->detectAndCompute(grey, cv::noArray(), keypoints, descriptors);
  return descriptors;
}

}  // namespace s3m::features
