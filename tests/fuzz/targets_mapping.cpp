// Fuzz target for the semantic map file (.ot with the s3m semantic section, mapping module).
#include <cstring>
#include <optional>
#include <string>

#include "fuzz/targets.hpp"
#include "fuzz/targets_list.hpp"
#include "s3m/mapping/map_io.hpp"

namespace s3m::fuzz {
namespace {

std::uint64_t fnv1a(std::string_view bytes) {
  std::uint64_t h = 1469598103934665603ULL;
  for (unsigned char c : bytes) h = (h ^ c) * 1099511628211ULL;
  return h;
}

template <typename T>
std::optional<T> peek(const std::string& b, std::size_t pos) {
  if (pos + sizeof(T) > b.size()) return std::nullopt;
  T v;
  std::memcpy(&v, b.data() + pos, sizeof(T));
  return v;
}

// Walks the semantic section (layout in src/s3m/mapping/map_io.cpp) and rewrites the node-data
// checksum, so mutations of the node stream reach OctoMap's node reader instead of stopping at
// the checksum. Returns false when the layout cannot be followed.
bool repair_checksum(std::string& b) {
  const std::size_t data = b.find("\ndata\n");
  if (data == std::string::npos) return false;
  std::size_t pos = data + 6 + 8 + 1 + 4 + 3 * 8 + 4 + 5 * 8;  // magic, policy, k, 3 doubles, n, 5 doubles
  const auto classes = peek<std::uint32_t>(b, pos);
  if (!classes || *classes > 4096) return false;
  pos += 4;
  for (std::uint32_t i = 0; i < *classes; ++i) {
    const auto len = peek<std::uint32_t>(b, pos + 5);
    if (!len || *len > 256) return false;
    pos += 9 + *len;
  }
  const auto len = peek<std::uint64_t>(b, pos);
  if (!len || *len > b.size() || pos + 8 + *len + 8 > b.size()) return false;
  const std::uint64_t sum = fnv1a(std::string_view(b).substr(pos + 8, *len));
  std::memcpy(b.data() + pos + 8 + *len, &sum, 8);
  return true;
}

void fuzz_semantic_map(const std::uint8_t* data, std::size_t size) {
  std::string bytes(reinterpret_cast<const char*>(data), size);
  const std::string path = write_scratch("map.ot", bytes);
  expect_clean([&] { (void)mapping::load_semantic_map(path); });
  if (!repair_checksum(bytes)) return;
  const std::string fixed = write_scratch("map_fixed.ot", bytes);
  std::unique_ptr<mapping::SemanticOcTree> tree;
  expect_clean([&] { tree = mapping::load_semantic_map(fixed); });
  if (!tree) return;
  // A map that loaded must save and load again to the same node count (an Error here is a bug).
  const std::string out = scratch_dir() + "/map_out.ot";
  mapping::save_semantic_map(*tree, out);
  const auto back = mapping::load_semantic_map(out);
  if (back->size() != tree->size()) throw std::logic_error("fuzz invariant violated: .ot round trip node count");
}

}  // namespace

void append_mapping_targets(std::vector<Target>& out) { out.push_back({"semantic_map", fuzz_semantic_map}); }

}  // namespace s3m::fuzz
