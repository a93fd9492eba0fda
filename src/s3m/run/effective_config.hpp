#pragma once
// The settings in effect, for people and for reruns: `s3m run` writes every key of the pipeline
// config after its automatic decisions into OUT/config_effective.yaml, which `--config` reads back
// as the same config; `s3m check` prints what differs from the built-in defaults.
#include <string>
#include <vector>

#include "s3m/pipeline/pipeline_config.hpp"

namespace s3m::run {

inline constexpr const char* kEffectiveConfigFile = "config_effective.yaml";

// Every key of c as YAML, preceded by comment lines: what the file is, c.source and `notes` (the
// run's decisions, one per line). Relative file paths (camera file, model, vocabulary) are made
// absolute, so the file means the same from any folder.
std::string effective_config_text(const pipeline::PipelineConfig& c,
                                  const std::vector<std::string>& notes = {});

// Writes effective_config_text() to out_dir/config_effective.yaml atomically; returns the path.
std::string write_effective_config(const std::string& out_dir, const pipeline::PipelineConfig& c,
                                   const std::vector<std::string>& notes = {});

// The overlays applied and one line per key whose value differs from the built-in default:
// "  key: value (written)" for keys the config or the command line wrote, "(automatic)" otherwise.
std::string settings_summary(const pipeline::PipelineConfig& c);

}  // namespace s3m::run
