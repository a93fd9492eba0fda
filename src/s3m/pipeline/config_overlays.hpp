#pragma once
// Named overlays: pipeline keys with values (config/overlays/NAME.yaml, built into the library)
// that an automatic decision (unregistered_depth.hpp) or a preset's `overlays:` list applies to the
// keys the config does not write. A value the user wrote, even the default, is never overridden;
// what an overlay set and what it left is logged, and its name goes into the config's `overlays`,
// so config_effective.yaml says which were applied.
#include <string>
#include <vector>

#include "s3m/pipeline/pipeline_config.hpp"

namespace s3m::pipeline {

struct OverlayResult {
  std::string name;
  std::vector<std::string> set;   // dotted keys the overlay set
  std::vector<std::string> kept;  // dotted keys it left, because the config writes them
};

// The shipped overlays' names, sorted.
std::vector<std::string> overlay_names();

// The overlay's file as shipped, comments included. Throws Error listing the names.
const std::string& overlay_text(const std::string& name);

// Applies overlay `name` to the keys of c not in c.written, appends the name to c.overlays (once)
// and logs what it set and what it left; `why` says what chose it, for the log.
OverlayResult apply_overlay(PipelineConfig& c, const std::string& name, const std::string& why);

// "overlay NAME set k = v, ...; left as the config writes them: k, ..." (c: the config it was
// applied to, for the values).
std::string describe(const OverlayResult& r, const PipelineConfig& c);

}  // namespace s3m::pipeline
