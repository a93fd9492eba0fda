#include "s3m/run/run.hpp"

#include <algorithm>
#include <filesystem>
#include <optional>

#include <fmt/format.h>

#include <spdlog/spdlog.h>

#include "s3m/core/error.hpp"
#include "s3m/core/timing.hpp"
#include "s3m/io/output_folder.hpp"
#include "s3m/pipeline/cost_estimate.hpp"
#include "s3m/pipeline/depth_scale.hpp"
#include "s3m/pipeline/factories.hpp"
#include "s3m/pipeline/outputs.hpp"
#include "s3m/pipeline/pipeline.hpp"
#include "s3m/pipeline/session_io.hpp"
#include "s3m/pipeline/unregistered_depth.hpp"
#include "s3m/run/camera_views.hpp"
#include "s3m/run/effective_config.hpp"
#include "s3m/run/metrics.hpp"
#include "s3m/run/progress.hpp"
#include "s3m/run/report.hpp"
#include "s3m/run/report_views.hpp"

namespace s3m::run {
namespace fs = std::filesystem;

namespace {

// --map: the session folder's files (a path to slam_map.bin itself is accepted too).
struct SessionFiles {
  std::string slam_map, kept_clouds;  // empty without --map
};
SessionFiles session_files(const RunOptions& o) {
  if (o.map_dir.empty()) {
    require(!o.localize_only, "run: --localize-only needs --map RUN_FOLDER (the map to localise in)");
    return {};
  }
  const fs::path given(o.map_dir);
  const fs::path dir = fs::is_regular_file(given) ? given.parent_path() : given;
  const fs::path slam = fs::is_regular_file(given) ? given : dir / pipeline::kSlamMapFile;
  return {slam.string(), (dir / pipeline::kKeptCloudsFile).string()};
}

// The loaded session lives in --out itself: overwritten only by a run that finished.
bool same_folder(const std::string& a, const std::string& b) {
  std::error_code ec;
  const fs::path da = fs::is_regular_file(a) ? fs::path(a).parent_path() : fs::path(a);
  return !a.empty() && fs::equivalent(da, b, ec);
}

// Components the run is made of, built from the options (each factory names what is wrong).
struct Components {
  pipeline::PipelineConfig config;  // o.config with the settings resolved from the data (depth registration)
  std::unique_ptr<pipeline::FrameSource> source;
  std::unique_ptr<pipeline::Pipeline> pipeline;
  RunInfo info;
};

// flow.segment auto: segmenting a frame that never reaches the map is only worth its cost when
// labels are there to score it.
void resolve_segment_mode(pipeline::FlowConfig& flow, bool has_labels) {
  if (flow.segment != pipeline::SegmentMode::kAuto) return;
  flow.segment = has_labels ? pipeline::SegmentMode::kAllFrames : pipeline::SegmentMode::kIntegrated;
  spdlog::info(
      "run: flow.segment auto: {}",
      has_labels ? "every frame (all_frames: the dataset's label images score each one)"
                 : "only the frames that go into the map (integrated: no label images to score the others)");
}

Components build(const RunOptions& o) {
  Components c{
      o.config,
      o.open_source ? o.open_source(o.config) : pipeline::open_tum_source(o.dataset_dir, o.config.dataset),
      nullptr,
      {}};
  c.info.dataset_dir = c.source->name();
  c.info.config_file = o.config.source;
  // Frames 0, 20, ... tell whether depth is registered to colour and whether its scale is plausible.
  std::vector<RgbdFrame> sample = sample_frames(*c.source);
  c.info.depth_registration = pipeline::resolve_depth_registration(
      c.config, sample, c.source->camera(), c.source->depth_registered_by(), !o.open_source);
  spdlog::info("run: depth {}", c.info.depth_registration);
  for (const std::string& name : c.config.overlays)  // those the decision added, for metrics.json
    if (std::find(o.config.overlays.begin(), o.config.overlays.end(), name) == o.config.overlays.end())
      c.info.overlays.push_back(name);
  if (c.config.dataset.camera != o.config.dataset.camera) {  // 7-Scenes' Kinect, opened as its two cameras
    c.source = pipeline::open_tum_source(o.dataset_dir, c.config.dataset);
    sample = sample_frames(*c.source);
  }
  const PinholeCamera& cam = c.source->camera();
  const pipeline::DepthScaleCheck scale = pipeline::check_depth_scale(sample, cam.depth_factor);
  c.info.depth_median_m = scale.median_m;
  c.info.depth_scale_warning = scale.warning;
  if (!scale.warning.empty()) spdlog::warn("run: {}", scale.warning);
  auto poses = pipeline::make_pose_source(o.poses, *c.source, cam, c.config);
  const SessionFiles session = session_files(o);
  if (!session.slam_map.empty()) pipeline::load_session_map(*poses, session.slam_map, o.localize_only);
  c.info.poses = poses->name();
  c.info.loaded_map = o.map_dir;
  c.info.localize_only = o.localize_only;
  std::unique_ptr<semantics::Segmenter> segmenter;
  std::unique_ptr<pipeline::MapIntegrator> map;
  if (!o.slam_only) {
    pipeline::SegmenterSpec spec = pipeline::parse_segmenter_spec(o.segmenter);
    spec.model_dir = o.model_dir;
    const std::string sim_sign =
        pipeline::simulator_sign(o.open_source ? "" : o.dataset_dir, c.source->has_labels());
    const pipeline::SegmenterChoice choice = pipeline::choose_segmenter(spec, c.config, sim_sign);
    segmenter = pipeline::make_segmenter(choice, c.config, c.source->has_labels());
    pipeline::record_segmenter_choice(c.config, choice);
    c.info.segmenter_reason = choice.reason;
    map = std::make_unique<pipeline::MapIntegrator>(c.config.map, c.config.dynamic.map_exclusions());
    resolve_segment_mode(c.config.flow, c.source->has_labels());
  }
  c.info.segmenter = segmenter ? segmenter->name() : (o.slam_only ? "none (--slam-only)" : "none");
  const bool has_map = map != nullptr;
  c.pipeline = std::make_unique<pipeline::Pipeline>(c.config, cam, std::move(poses), std::move(segmenter),
                                                    std::move(map));
  if (has_map && !session.kept_clouds.empty()) {
    if (fs::exists(session.kept_clouds))
      c.pipeline->load_session_clouds(session.kept_clouds);
    else
      spdlog::warn("run: {} has no {} (a --slam-only run?): the semantic map starts empty", o.map_dir,
                   pipeline::kKeptCloudsFile);
  }
  return c;
}

// Reads the frames in order. A frame whose files cannot be read (ParseError: truncated, corrupt,
// wrong size) is skipped once an earlier frame was read: a long run must not end with nothing
// because of one bad file, and SLAM bridges a missing frame as it bridges a dropped one. Before
// that the error stands: a problem with the first frame is most often every frame's (a wrong
// camera size, 8-bit depth) and stopping there costs nothing.
struct FrameReader {
  const pipeline::FrameSource& source;
  RunInfo& info;
  int in_a_row = 0;  // unreadable frames since the last readable one
  bool read_any = false;

  std::optional<RgbdFrame> read(std::size_t i) {
    try {
      RgbdFrame f = source.load(i);
      in_a_row = 0;
      read_any = true;
      return f;
    } catch (const ParseError& e) {
      if (!read_any) throw;
      info.skipped.push_back({i, e.what()});
      ++in_a_row;
      spdlog::warn("run: frame {} skipped: {}", i, e.what());
      return std::nullopt;
    }
  }
};

bool stop_requested(const RunOptions& o, std::size_t done) {
  if (o.stop && o.stop->load()) return true;
  return o.stop_after_frames >= 0 && static_cast<long>(done) >= o.stop_after_frames;
}

// The progress line's state: the latest tracked frame's, nothing before the first.
std::string state_text(const std::optional<FrameState>& state) { return state ? to_string(*state) : ""; }

// Feeds frames 0, 1, ... to the pipeline until the last, a stop request or more unreadable frames in
// a row than the config allows (c.info.stopped_by says why). Returns the index it stopped at.
std::size_t process_frames(const RunOptions& o, Components& c, RunResult& r, ProgressLine& progress) {
  const int max_in_a_row = c.config.dataset.max_unreadable_in_a_row;
  FrameReader reader{*c.source, c.info};
  std::size_t i = 0;
  for (; i < r.frames_total; ++i) {
    if (stop_requested(o, i)) {
      r.interrupted = true;
      break;
    }
    if (std::optional<RgbdFrame> frame = reader.read(i)) {
      c.pipeline->process(std::move(*frame));
    } else if (reader.in_a_row > max_in_a_row) {
      c.info.stopped_by = fmt::format(
          "{} unreadable frame{} in a row, the last frame {} (dataset.max_unreadable_in_a_row "
          "is {}): {}",
          reader.in_a_row, reader.in_a_row == 1 ? "" : "s", i, max_in_a_row, c.info.skipped.back().error);
      r.interrupted = true;
      break;
    }
    progress.update(c.pipeline->frames_done(), state_text(c.pipeline->last_state()));
  }
  return i;
}

}  // namespace

RunResult run_dataset(const RunOptions& o) {
  require(!o.out_dir.empty(), "run: an output directory is required (--out)");
  o.config.validate();
  Components c = build(o);
  if (!o.slam_only) pipeline::check_cost(c.config, c.source->camera(), o.force);  // before the first frame
  const bool out_existed = fs::exists(o.out_dir);
  io::create_output_folder(o.out_dir, "--out");  // before any frame: a bad --out costs nothing

  RunResult r;
  r.frames_total = c.source->size();
  if (o.max_frames >= 0) r.frames_total = std::min<std::size_t>(r.frames_total, o.max_frames);
  require(r.frames_total > 0, "run: dataset " + c.info.dataset_dir + " has no frames");
  spdlog::info("run: {} frames from {} (poses: {})", r.frames_total, c.info.dataset_dir, c.info.poses);
  spdlog::info("run: segmenter: {}{}", c.info.segmenter,
               c.info.segmenter_reason.empty() ? "" : " (" + c.info.segmenter_reason + ")");

  // The report's camera views: segmentations of a few integrated frames, kept as the run goes.
  CameraViewSampler camera_views;
  const bool views = o.report && c.config.eval.plots;
  if (views || o.on_frame)
    c.pipeline->set_frame_listener([&camera_views, views, &o](const pipeline::FrameOutcome& f,
                                                              const RgbdFrame& frame,
                                                              const semantics::LabelMap& l) {
      if (views) camera_views.offer(f, l);
      if (o.on_frame) o.on_frame(f, frame, l);
    });
  ProgressLine progress(r.frames_total, o.progress);
  Stopwatch wall;
  const std::size_t submitted = process_frames(o, c, r, progress);
  c.pipeline->finish();
  c.info.wall_time_s = wall.elapsed_ms() / 1000.0;
  c.info.interrupted = r.interrupted;
  c.info.frames_total = r.frames_total;
  r.frames_done = c.pipeline->frames_done();
  r.frames_skipped = c.info.skipped.size();
  progress.finish(r.frames_done, r.interrupted ? "interrupted" : state_text(c.pipeline->last_state()));
  if (!c.info.skipped.empty())
    spdlog::warn("run: {} unreadable frame(s) skipped (listed in metrics.json, skipped_frames)",
                 c.info.skipped.size());
  if (r.interrupted)
    spdlog::warn("run: stopped after {} of {} frames; writing what was processed", r.frames_done,
                 r.frames_total);

  if (r.frames_done == 0) {
    std::error_code ec;
    if (!out_existed) fs::remove(o.out_dir, ec);  // the folder this run made, still empty
    spdlog::warn("run: no frame was processed; {} is left as it was", o.out_dir);
    if (!c.info.stopped_by.empty())
      throw Error(
          fmt::format("run: stopped at frame {} of {}: {}; nothing was processed, {} is left as it was",
                      submitted, r.frames_total, c.info.stopped_by, o.out_dir));
    return r;
  }
  r.written = true;
  // Outputs first (trajectory and map are what a user keeps), then the evaluation of them.
  const bool keep_loaded = r.interrupted && same_folder(o.map_dir, o.out_dir);
  if (keep_loaded) spdlog::warn("run: interrupted: the session loaded from {} is not overwritten", o.out_dir);
  pipeline::OutputPaths paths = pipeline::write_outputs(*c.pipeline, c.config, o.out_dir, !keep_loaded);
  paths.config_effective = write_effective_config(
      o.out_dir, c.config,
      {"depth: " + c.info.depth_registration,
       "segmenter: " + c.info.segmenter +
           (c.info.segmenter_reason.empty() ? "" : " (" + c.info.segmenter_reason + ")")});
  r.metrics = compute_metrics(*c.pipeline, *c.source, c.config, c.info, paths);
  write_metrics(r.metrics, paths);
  if (o.report && c.config.eval.plots) {
    const std::string views =
        write_report_views(*c.pipeline, *c.source, c.config, paths, camera_views.chosen());
    if (!views.empty()) spdlog::warn("run: report pictures missing: {}", views);
    const ReportResult rep = make_report(o.out_dir);
    r.report_html = rep.html;
    r.report_error = rep.error;
    if (!rep.error.empty()) spdlog::warn("run: report not made: {}", rep.error);
  } else {
    std::error_code ec;  // an earlier run's report would describe that run
    if (fs::remove_all(fs::path(o.out_dir) / "report", ec) > 0)
      spdlog::info("run: removed the report of an earlier run from {} (--no-report)", o.out_dir);
  }
  if (!c.info.stopped_by.empty())
    throw Error(
        fmt::format("run: stopped at frame {} of {}: {}; the outputs of the {} frames before it are in {}",
                    submitted, r.frames_total, c.info.stopped_by, r.frames_done, o.out_dir));
  return r;
}

}  // namespace s3m::run
