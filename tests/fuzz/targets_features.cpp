// Fuzz target for the ORB vocabulary file (features module).
#include <cstring>
#include <string>

#include "fuzz/targets.hpp"
#include "fuzz/targets_list.hpp"
#include "s3m/features/bow_vocabulary.hpp"

namespace s3m::fuzz {
namespace {

std::uint64_t fnv1a(std::string_view bytes) {
  std::uint64_t h = 1469598103934665603ULL;
  for (unsigned char c : bytes) h = (h ^ c) * 1099511628211ULL;
  return h;
}

// The file ends in a checksum that random mutations almost never match, so the input is tried
// twice: as given (checksum path) and with the checksum repaired (structural checks behind it).
void fuzz_vocabulary(const std::uint8_t* data, std::size_t size) {
  std::string bytes(reinterpret_cast<const char*>(data), size);
  const std::string path = write_scratch("vocab.bin", bytes);
  expect_clean([&] { (void)features::Vocabulary::load(path); });
  if (bytes.size() < 16) return;
  const std::uint64_t sum = fnv1a(std::string_view(bytes).substr(0, bytes.size() - 8));
  std::memcpy(bytes.data() + bytes.size() - 8, &sum, 8);
  const std::string fixed = write_scratch("vocab_fixed.bin", bytes);
  expect_clean([&] { (void)features::Vocabulary::load(fixed); });
}

}  // namespace

void append_features_targets(std::vector<Target>& out) { out.push_back({"vocabulary", fuzz_vocabulary}); }

}  // namespace s3m::fuzz
