#pragma once
// Hierarchical k-medians vocabulary of 256-bit ORB descriptors (the DBoW2 design): a tree with
// branching factor k and depth L whose leaves are the visual words, TF-IDF word weights, and a
// versioned binary file format. Trained by `s3m vocab`; loaded by loop closing and relocalisation.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "s3m/features/bow_vector.hpp"

namespace s3m::features {

struct VocabularyConfig {
  int branching = 10;        // k: children per node
  int levels = 5;            // L: tree depth below the root (at most k^L words)
  int max_iterations = 10;   // k-medians iterations per node (stops earlier when assignments settle)
  uint64_t seed = 20261123;  // k-means++ seeding; fixed so training is reproducible

  // Throws s3m::Error naming the bad field.
  void validate() const;
};

class Vocabulary {
 public:
  // Called with (descriptors clustered so far, total descriptors) during training.
  using Progress = std::function<void(size_t done, size_t total)>;

  Vocabulary() = default;

  // Trains on one descriptor matrix (CV_8UC1, N x 32) per training image. IDF weights are
  // log(images / images containing the word). Throws s3m::Error when there are no descriptors.
  static Vocabulary train(const std::vector<cv::Mat>& descriptors_per_image, const VocabularyConfig& config,
                          const Progress& progress = {});

  // Atomic binary write (temporary file + rename). Throws s3m::Error when the file can't be written.
  void save(const std::string& path) const;
  // Throws s3m::ParseError naming the file and the problem (missing, bad magic, unsupported
  // version, truncated, checksum mismatch, inconsistent tree).
  static Vocabulary load(const std::string& path);

  // FNV-1a of the vocabulary's file bytes: two vocabularies with one checksum give the same words,
  // weights and BoW vectors (a saved SLAM map records it).
  uint64_t checksum() const;

  bool empty() const { return words_.empty(); }
  int branching() const { return branching_; }
  int levels() const { return levels_; }
  size_t num_words() const { return words_.size(); }
  size_t num_nodes() const { return nodes_.size(); }
  // Number of images the vocabulary was trained on (N in the IDF).
  uint32_t training_images() const { return training_images_; }

  // Word of a descriptor (greedy descent by Hamming distance). When node_at_level is given it
  // receives the ancestor node `level` steps below the root (or the leaf, if shallower).
  WordId word_of(const Descriptor256& d, NodeId* node_at_level = nullptr, int level = 0) const;
  double word_weight(WordId w) const { return nodes_.at(words_.at(w)).weight; }

  // BoW vector of one image's descriptors (TF-IDF, L1-normalised). When fv is given it receives
  // the direct index at `direct_level` levels below the root (ORB-SLAM uses L - 4).
  BowVector transform(const cv::Mat& descriptors, FeatureVector* fv = nullptr, int direct_level = 2) const;

 private:
  friend class VocabularyBuilder;
  friend class VocabularyIo;
  struct Node {
    NodeId parent = 0;
    Descriptor256 descriptor{};
    float weight = 0.0F;  // IDF, leaves only
    std::vector<NodeId> children;
    bool is_leaf() const { return children.empty(); }
  };
  void index_words();  // rebuilds words_ and the word id of each leaf from the tree

  int branching_ = 0;
  int levels_ = 0;
  uint32_t training_images_ = 0;
  std::vector<Node> nodes_;         // nodes_[0] is the root; parents precede children
  std::vector<NodeId> words_;       // word id -> leaf node
  std::vector<WordId> word_of_node_;  // node -> word id (leaves only)
};

// The vocabulary shipped in the repository (vocab/orb_k10_l5.bin, see vocab/PROVENANCE.md), found
// as every shipped file is (s3m/core/shipped_files.hpp).
std::string default_vocabulary_path();

// ORB descriptors of one image for vocabulary training and tests: OpenCV ORB with a fixed number
// of features, 8 pyramid levels, scale 1.2 (ORB-SLAM's settings). Grey or BGR input.
cv::Mat extract_orb_descriptors(const cv::Mat& image, int num_features);

}  // namespace s3m::features
