#pragma once
// A batch manifest (`s3m batch MANIFEST`): the recordings of one building to run and merge.
//
//   defaults:                  # optional; every recording's settings unless it sets its own
//     config: config/sim.yaml  # s3m run --config (paths relative to the manifest's folder)
//     segmenter: oracle        # s3m run --segmenter
//     deterministic: true      # s3m run --deterministic (identical outputs run to run)
//     max_frames: 300          # s3m run --max-frames
//   recordings:
//     - path: flights/monday   # a dataset folder or a recording (ROS 2 .mcap/.db3/folder, ROS1 .bag)
//       name: monday           # optional: the run's folder name (default: the path's last part)
//     - path: flights/tuesday.bag
//       config: config/realsense_d455.yaml
//   merge:                     # optional
//     config: config/sim.yaml  # s3m merge --config (default: the defaults' config)
//
// Every key is checked: a misspelt one is refused with the file, the line and the keys allowed.
#include <string>
#include <vector>

namespace s3m::batch {

// What `s3m run` is told about one recording; unset fields take the manifest's defaults.
struct RunSettings {
  std::string config;     // preset file, absolute ("" = built-in defaults)
  std::string segmenter;  // "" = the preset's
  bool deterministic = false;
  long max_frames = -1;  // < 0: all frames
};

struct Recording {
  std::string name;  // the folder name of its run under DIR/runs/ (unique, [A-Za-z0-9._-])
  std::string path;  // absolute
  RunSettings run;
};

struct Manifest {
  std::string file;  // absolute path of the manifest
  std::vector<Recording> recordings;
  std::string merge_config;  // absolute, "" = built-in defaults
};

// Throws ParseError (file, line, key, what was expected) for bad YAML, unknown keys, a recording
// without a path, or two recordings of the same name. Paths are resolved against the manifest's
// folder; whether they exist is each run's business (a missing one fails that run only).
Manifest load_manifest(const std::string& path);

}  // namespace s3m::batch
