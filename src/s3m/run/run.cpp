#include "s3m/run/run.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>
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

// Everything run_dataset writes into out_dir, by name: an earlier run's copy of one this run does not
// make would be read as this run's. The session a stopped run continued in stays (keep_loaded).
std::vector<std::string> owned_names(const RunOptions& o, bool keep_loaded) {
  std::vector<std::string> n = {"trajectory_camera.txt",
                                "trajectory_robot.txt",
                                "keyframes.txt",
                                "frames.txt",
                                "metrics.json",
                                "config_effective.yaml",
                                "map.ot",
                                "map.ply",
                                "report"};
  if (!keep_loaded) n.insert(n.end(), {pipeline::kSlamMapFile, pipeline::kKeptCloudsFile});
  n.insert(n.end(), o.more_names.begin(), o.more_names.end());
  return n;
}

bool same_recording(const std::string& a, const std::string& b) {
  std::error_code ec;
  return a == b || fs::equivalent(a, b, ec);
}

// What out_dir holds that is not this recording's earlier run: "" when nothing.
std::string foreign_contents(const RunOptions& o) {
  std::error_code ec;
  const fs::path out(o.out_dir);
  if (!fs::is_directory(out, ec)) return "";
  if (!o.dataset_dir.empty() && fs::equivalent(out, o.dataset_dir, ec)) return "the recording this run reads";
  for (const char* f : {"rgb.txt", "depth.txt", "associations.txt", "metadata.yaml"})
    if (fs::exists(out / f, ec)) return std::string("a recording (") + f + ")";
  if (!fs::exists(out / "metrics.json", ec)) return "";
  std::ifstream in(out / "metrics.json");
  const nlohmann::json m = nlohmann::json::parse(in, nullptr, false);
  const std::string earlier =
      m.is_object() && m.contains("inputs") ? m["inputs"].value("dataset", std::string()) : std::string();
  if (earlier.empty()) return "a metrics.json s3m cannot read as a run's";
  return same_recording(earlier, o.dataset_dir) ? "" : "the outputs of a run of " + earlier;
}

// An --out folder holding a recording, or another recording's run, is the user's data: writing into
// it needs --force, and the message says what would be replaced. Continuing a session (--map in
// the same folder) is what the user asked for.
void refuse_foreign_out(const RunOptions& o) {
  if (o.force || same_folder(o.map_dir, o.out_dir)) return;
  const std::string holds = foreign_contents(o);
  if (holds.empty()) return;
  std::string replaced;
  std::error_code ec;
  for (const std::string& name : owned_names(o, false))
    if (fs::exists(fs::path(o.out_dir) / name, ec)) replaced += (replaced.empty() ? "" : ", ") + name;
  throw Error(
      fmt::format("run: --out '{}' holds {}; this run would write its outputs there{}. Give another "
                  "folder, or --force to write into it",
                  o.out_dir, holds, replaced.empty() ? "" : " (replacing " + replaced + ")"));
}

// Output paths as they will be once the staging folder is moved in (metrics.json lists them).
pipeline::OutputPaths moved(pipeline::OutputPaths p, const std::string& from, const std::string& to) {
  for (std::string* s : {&p.out_dir, &p.trajectory_camera, &p.trajectory_robot, &p.keyframes, &p.frames,
                         &p.map_ot, &p.map_ply, &p.slam_map, &p.kept_clouds, &p.metrics, &p.config_effective})
    if (s->rfind(from, 0) == 0) *s = to + s->substr(from.size());
  return p;
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

// Outputs first (trajectory and map are what a user keeps), then the evaluation of them, all into
// the staging folder; moved into out_dir only once everything was written. Returns the names the run
// owns in out_dir (StagedFolder::commit).
std::vector<std::string> write_staged(const RunOptions& o, Components& c, io::StagedFolder& out,
                                      const CameraViewSampler& camera_views, RunResult& r) {
  const bool keep_loaded = r.interrupted && same_folder(o.map_dir, o.out_dir);
  if (keep_loaded) spdlog::warn("run: interrupted: the session loaded from {} is not overwritten", o.out_dir);
  pipeline::OutputPaths paths = pipeline::write_outputs(*c.pipeline, c.config, out.path(), !keep_loaded);
  paths.config_effective = write_effective_config(
      out.path(), c.config,
      {"depth: " + c.info.depth_registration,
       "segmenter: " + c.info.segmenter +
           (c.info.segmenter_reason.empty() ? "" : " (" + c.info.segmenter_reason + ")")});
  r.metrics = compute_metrics(*c.pipeline, *c.source, c.config, c.info, paths);
  r.metrics["outputs"] = outputs_json(moved(paths, out.path(), o.out_dir));
  write_metrics(r.metrics, paths);
  if (o.report && c.config.eval.plots) {
    const std::string views =
        write_report_views(*c.pipeline, *c.source, c.config, paths, camera_views.chosen());
    if (!views.empty()) spdlog::warn("run: report pictures missing: {}", views);
    const ReportResult rep = make_report(out.path());
    if (!rep.html.empty())
      r.report_html = (fs::path(o.out_dir) / "report" / fs::path(rep.html).filename()).string();
    r.report_error = rep.error;
    if (!rep.error.empty()) spdlog::warn("run: report not made: {}", rep.error);
  } else {  // the evaluation's plot data alone is no report (and an earlier one would describe that run)
    std::error_code ec;
    fs::remove_all(fs::path(out.path()) / "report", ec);
  }
  if (o.write_more) o.write_more(out.path());
  return owned_names(o, keep_loaded);
}

}  // namespace

RunResult run_dataset(const RunOptions& o) {
  require(!o.out_dir.empty(), "run: an output directory is required (--out)");
  o.config.validate();
  io::require_folder_path(o.out_dir, "--out");  // before any work: a bad --out costs nothing
  refuse_foreign_out(o);
  Components c = build(o);
  if (!o.slam_only) pipeline::check_cost(c.config, c.source->camera(), o.force);  // before the first frame
  io::StagedFolder out(o.out_dir, "--out");

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

  if (r.frames_done == 0) {  // `out` removes its staging folder, and out_dir if it made it
    spdlog::warn("run: no frame was processed; {} is left as it was", o.out_dir);
    if (!c.info.stopped_by.empty())
      throw Error(
          fmt::format("run: stopped at frame {} of {}: {}; nothing was processed, {} is left as it was",
                      submitted, r.frames_total, c.info.stopped_by, o.out_dir));
    return r;
  }
  std::vector<std::string> owned;
  try {
    owned = write_staged(o, c, out, camera_views, r);
  } catch (const Error& e) {  // name the files where the user will look for them
    std::string what = e.what();
    for (std::size_t k; (k = what.find(out.path())) != std::string::npos;)
      what.replace(k, out.path().size(), o.out_dir);
    throw Error(what + "; nothing was changed in " + o.out_dir);
  }
  for (const std::string& gone : out.commit(owned))
    spdlog::info("run: removed {} of an earlier run (not made by this one)", gone);
  r.written = true;
  if (!c.info.stopped_by.empty())
    throw Error(
        fmt::format("run: stopped at frame {} of {}: {}; the outputs of the {} frames before it are in {}",
                    submitted, r.frames_total, c.info.stopped_by, r.frames_done, o.out_dir));
  return r;
}

}  // namespace s3m::run
