#pragma once
// `s3m run` as a library call: a TUM-layout dataset (or any FrameSource) in, every output file in OUT
// (trajectories, keyframes, semantic map, metrics, report). Used by the CLI, `s3m demo` and the integration
// tests.
#include <atomic>
#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "s3m/pipeline/frame_source.hpp"
#include "s3m/pipeline/pipeline.hpp"
#include "s3m/pipeline/pipeline_config.hpp"

namespace s3m::run {

struct RunOptions {
  std::string dataset_dir;
  // When set, frames come from this source (e.g. a rosbag, src/ros) instead of dataset_dir. It is
  // called once with the validated config (camera override, association window).
  std::function<std::unique_ptr<pipeline::FrameSource>(const pipeline::PipelineConfig&)> open_source;
  std::string out_dir;
  pipeline::PipelineConfig config;
  // Segmenter: "" = the config's segmenter section; "onnx:MODEL_DIR_OR_CARD", "oracle", "none".
  std::string segmenter;
  std::string model_dir;       // with onnx: the folder holding the model files
  std::string poses = "slam";  // slam | gt (ground-truth poses: evaluates semantics/mapping alone)
  bool slam_only = false;      // trajectories only: no segmentation, no map
  long max_frames = -1;        // < 0: all frames
  // Set by the caller (e.g. a SIGINT handler) to stop early; outputs so far are still written.
  const std::atomic<bool>* stop = nullptr;
  bool progress = false;  // live progress line on stderr
  bool report = true;     // plots + report.html via tools/plot_report.py
  // Run even when the cost estimate is over its limit (cost_estimate.hpp), and write into an out_dir
  // that holds a recording or a run of another recording (its outputs are replaced).
  bool force = false;
  // A map that lasts: continue in the session a previous run wrote into this folder
  // (slam_map.bin, and kept_clouds.bin for the semantic map); "" = start from nothing. With
  // localize_only the SLAM map is not changed (the semantic map still fuses this run's frames).
  std::string map_dir;
  bool localize_only = false;
  // Stop after this many frames as if `stop` had been set (tests of the interrupted path); < 0: off.
  long stop_after_frames = -1;
  // Called after every frame with its outcome and labels (pipeline::FrameListener: from the thread
  // that ran the frame; keep it short), besides the report's own use; unset: not called.
  pipeline::FrameListener on_frame;
  // More outputs of the caller's (the CLI's session.mcap), written into the staging folder DIR after
  // run_dataset's own and moved in with them; a throw leaves out_dir as it was. Unset: none.
  std::function<void(const std::string& dir)> write_more;
  std::vector<std::string> more_names;  // the names write_more writes (removed when it did not)
};

struct RunResult {
  std::size_t frames_total = 0;    // frames in the dataset (after max_frames)
  std::size_t frames_done = 0;     // frames that went through the pipeline
  std::size_t frames_skipped = 0;  // frames whose files could not be read (metrics.json: skipped_frames)
  bool interrupted = false;
  bool written = false;      // false: no frame was processed, so out_dir was left as it was
  std::string report_html;   // empty when no report was made
  std::string report_error;  // why the report is missing, if it is
  nlohmann::json metrics;    // what metrics.json holds
};

// Throws s3m::Error / ParseError for bad input (dataset, config, model), with file and line. An
// unreadable frame is skipped (RunResult::frames_skipped); more than
// config.dataset.max_unreadable_in_a_row in a row throw, after the outputs so far are written.
// Outputs are staged inside out_dir and moved in at the end (io::StagedFolder): a run that
// processed no frame (stopped before the first) or failed leaves out_dir exactly as it was; one
// that finished or was stopped replaces an earlier run's outputs whole, the files it did not make
// this time included. An out_dir holding a recording, or a run of another recording, is refused
// before any work unless force (or it is the map_dir being continued).
RunResult run_dataset(const RunOptions& options);

}  // namespace s3m::run
