// Fuzz target for pipeline presets (config/*.yaml): the top-level sections and everything they
// delegate to (slam:, map:, segmenter: with the oracle noise model, ...). Accepted presets must be
// valid: validate() on the result may not throw.
#include <optional>
#include <stdexcept>

#include "fuzz/targets.hpp"
#include "fuzz/targets_list.hpp"
#include "s3m/pipeline/pipeline_config.hpp"

namespace s3m::fuzz {
namespace {

void fuzz_pipeline_config(const std::uint8_t* data, std::size_t size) {
  const std::string path = write_scratch("preset/preset.yaml", data, size);
  std::optional<pipeline::PipelineConfig> config;
  expect_clean([&] { config = pipeline::load_pipeline_config(path); });
  if (!config) return;
  try {
    config->validate();
  } catch (const Error& e) {
    throw std::logic_error(std::string("fuzz invariant violated: an accepted preset fails validate(): ") + e.what());
  }
}

}  // namespace

void append_pipeline_targets(std::vector<Target>& out) { out.push_back({"pipeline_config", fuzz_pipeline_config}); }

}  // namespace s3m::fuzz
