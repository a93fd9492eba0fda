// Vocabulary file format (little-endian), version 1:
//   "S3MVOCAB" | u32 version | u32 branching | u32 levels | u32 training_images | u32 nodes |
//   nodes x { u32 parent, f32 idf weight, 32 B descriptor } | u64 FNV-1a of all preceding bytes
// Nodes are stored parents first, so the tree is rebuilt in one pass; the checksum catches
// truncation and bit rot that the structural checks would miss.
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "s3m/core/atomic_file.hpp"
#include "s3m/core/byte_io.hpp"
#include "s3m/core/error.hpp"
#include "s3m/core/input_file.hpp"
#include "s3m/features/bow_vocabulary.hpp"

namespace s3m::features {

namespace {

constexpr char kMagic[8] = {'S', '3', 'M', 'V', 'O', 'C', 'A', 'B'};
constexpr uint32_t kVersion = 1;

template <typename T>
void put(std::string& out, const T& v) {
  out.append(reinterpret_cast<const char*>(&v), sizeof(T));
}

class Reader {
 public:
  Reader(const std::string& path, const std::string& bytes) : path_(path), bytes_(bytes) {}
  template <typename T>
  T get(const char* what) {
    if (pos_ + sizeof(T) > bytes_.size()) {
      throw ParseError(path_, 0, "file truncated while reading " + std::string(what) + " at byte " + std::to_string(pos_),
                       "a complete s3m vocabulary file");
    }
    T v;
    std::memcpy(&v, bytes_.data() + pos_, sizeof(T));
    pos_ += sizeof(T);
    return v;
  }
  size_t pos() const { return pos_; }

 private:
  const std::string& path_;
  const std::string& bytes_;
  size_t pos_ = 0;
};

}  // namespace

class VocabularyIo {
 public:
  static std::string serialise(const Vocabulary& v) {
    std::string out(kMagic, sizeof(kMagic));
    put(out, kVersion);
    put(out, uint32_t(v.branching_));
    put(out, uint32_t(v.levels_));
    put(out, v.training_images_);
    put(out, uint32_t(v.nodes_.size()));
    for (const auto& n : v.nodes_) {
      put(out, n.parent);
      put(out, n.weight);
      put(out, n.descriptor);
    }
    put(out, fnv1a(out));
    return out;
  }

  static Vocabulary parse(const std::string& path, const std::string& bytes) {
    const std::string expected = "an s3m vocabulary file written by 's3m vocab'";
    if (bytes.size() < sizeof(kMagic) || std::memcmp(bytes.data(), kMagic, sizeof(kMagic)) != 0) {
      throw ParseError(path, 0, "not a vocabulary file (bad magic bytes)", expected);
    }
    Reader r(path, bytes);
    for (size_t i = 0; i < sizeof(kMagic); ++i) r.get<char>("magic");
    const auto version = r.get<uint32_t>("version");
    if (version != kVersion) {
      throw ParseError(path, 0, "unsupported vocabulary version " + std::to_string(version), "version 1");
    }
    Vocabulary v;
    v.branching_ = int(r.get<uint32_t>("branching"));
    v.levels_ = int(r.get<uint32_t>("levels"));
    v.training_images_ = r.get<uint32_t>("training image count");
    const auto num_nodes = r.get<uint32_t>("node count");
    const size_t node_bytes = 4 + 4 + 32;
    if (num_nodes == 0 || bytes.size() != r.pos() + size_t(num_nodes) * node_bytes + 8) {
      throw ParseError(path, 0,
                       "file size " + std::to_string(bytes.size()) + " does not match its " + std::to_string(num_nodes) +
                           " nodes (truncated or corrupt)",
                       expected);
    }
    v.nodes_.resize(num_nodes);
    for (uint32_t i = 0; i < num_nodes; ++i) {
      auto& n = v.nodes_[i];
      n.parent = r.get<uint32_t>("node parent");
      n.weight = r.get<float>("node weight");
      n.descriptor = r.get<Descriptor256>("node descriptor");
      if (i > 0 && n.parent >= i) {
        throw ParseError(path, 0, "node " + std::to_string(i) + " has parent " + std::to_string(n.parent),
                         "parents stored before their children");
      }
      if (i > 0) v.nodes_[n.parent].children.push_back(i);
    }
    const size_t payload = r.pos();
    if (r.get<uint64_t>("checksum") != fnv1a(bytes.substr(0, payload))) {
      throw ParseError(path, 0, "checksum mismatch (file corrupt)", expected);
    }
    if (v.branching_ < 2 || v.levels_ < 1) {
      throw ParseError(path, 0, "invalid branching " + std::to_string(v.branching_) + " / levels " +
                                    std::to_string(v.levels_), "branching >= 2 and levels >= 1");
    }
    v.index_words();
    return v;
  }
};

void Vocabulary::save(const std::string& path) const {
  require(!empty(), "Vocabulary::save: the vocabulary is empty");
  const std::string bytes = VocabularyIo::serialise(*this);
  // Temporary file with a unique name in the same folder, fsync, rename: concurrent saves and a
  // crash mid-write never leave a torn vocabulary (the old file stays until the rename).
  write_text_atomic(path, bytes);
}

uint64_t Vocabulary::checksum() const { return fnv1a(VocabularyIo::serialise(*this)); }

Vocabulary Vocabulary::load(const std::string& path) {
  std::ifstream in = open_input_file(path, "an s3m ORB vocabulary file", std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return VocabularyIo::parse(path, ss.str());
}

}  // namespace s3m::features
