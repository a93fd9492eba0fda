#include "s3m/pipeline/run.hpp"

#include <filesystem>

#include <spdlog/spdlog.h>

#include "s3m/core/error.hpp"
#include "s3m/core/timing.hpp"
#include "s3m/pipeline/camera_views.hpp"
#include "s3m/pipeline/cost_estimate.hpp"
#include "s3m/pipeline/factories.hpp"
#include "s3m/pipeline/metrics.hpp"
#include "s3m/pipeline/outputs.hpp"
#include "s3m/pipeline/pipeline.hpp"
#include "s3m/pipeline/progress.hpp"
#include "s3m/pipeline/report.hpp"
#include "s3m/pipeline/report_views.hpp"
#include "s3m/pipeline/session_io.hpp"
#include "s3m/pipeline/unregistered_depth.hpp"

namespace s3m::pipeline {
namespace fs = std::filesystem;

SegmenterSpec parse_segmenter_spec(const std::string& spec) {
  SegmenterSpec s;
  if (spec.empty()) return s;
  if (spec == "oracle") {
    s.kind = SegmenterSpec::Kind::kOracle;
  } else if (spec == "none") {
    s.kind = SegmenterSpec::Kind::kNone;
  } else if (spec.rfind("onnx:", 0) == 0 && spec.size() > 5) {
    s.kind = SegmenterSpec::Kind::kOnnx;
    s.model = spec.substr(5);
  } else {
    throw Error("--segmenter: unknown value '" + spec + "' (expected onnx:MODEL_DIR_OR_CARD | oracle | none)");
  }
  return s;
}

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
  const fs::path slam = fs::is_regular_file(given) ? given : dir / kSlamMapFile;
  return {slam.string(), (dir / kKeptCloudsFile).string()};
}

// The loaded session lives in --out itself: overwritten only by a run that finished.
bool same_folder(const std::string& a, const std::string& b) {
  std::error_code ec;
  const fs::path da = fs::is_regular_file(a) ? fs::path(a).parent_path() : fs::path(a);
  return !a.empty() && fs::equivalent(da, b, ec);
}

// Components the run is made of, built from the options (each factory names what is wrong).
struct Components {
  PipelineConfig config;  // o.config with the settings resolved from the data (depth registration)
  std::unique_ptr<FrameSource> source;
  std::unique_ptr<Pipeline> pipeline;
  RunInfo info;
};

Components build(const RunOptions& o) {
  Components c{o.config, o.open_source ? o.open_source(o.config) : open_tum_source(o.dataset_dir, o.config.dataset),
               nullptr, {}};
  const PinholeCamera& cam = c.source->camera();
  c.info.dataset_dir = c.source->name();
  c.info.config_file = o.config.source;
  c.info.depth_registration = resolve_depth_registration(c.config, *c.source);
  spdlog::info("run: depth {}", c.info.depth_registration);
  auto poses = make_pose_source(o.poses, *c.source, cam, c.config);
  const SessionFiles session = session_files(o);
  if (!session.slam_map.empty()) poses->load_map(session.slam_map, o.localize_only);
  c.info.poses = poses->name();
  c.info.loaded_map = o.map_dir;
  c.info.localize_only = o.localize_only;
  std::unique_ptr<semantics::Segmenter> segmenter;
  std::unique_ptr<MapIntegrator> map;
  if (!o.slam_only) {
    SegmenterSpec spec = parse_segmenter_spec(o.segmenter);
    spec.model_dir = o.model_dir;
    const std::string sim_sign = simulator_sign(o.open_source ? "" : o.dataset_dir, c.source->has_labels());
    const SegmenterChoice choice = choose_segmenter(spec, c.config, sim_sign);
    segmenter = make_segmenter(choice, c.config, c.source->has_labels());
    c.info.segmenter_reason = choice.reason;
    map = std::make_unique<MapIntegrator>(c.config.map);
  }
  c.info.segmenter = segmenter ? segmenter->name() : (o.slam_only ? "none (--slam-only)" : "none");
  const bool has_map = map != nullptr;
  c.pipeline = std::make_unique<Pipeline>(c.config, cam, std::move(poses), std::move(segmenter), std::move(map));
  if (has_map && !session.kept_clouds.empty()) {
    if (fs::exists(session.kept_clouds))
      c.pipeline->load_session_clouds(session.kept_clouds);
    else
      spdlog::warn("run: {} has no {} (a --slam-only run?): the semantic map starts empty", o.map_dir, kKeptCloudsFile);
  }
  return c;
}

// Before any frame is processed, so a bad --out costs nothing (filesystem_error is no s3m::Error).
void create_output_dir(const std::string& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir))
    throw Error("run: cannot create the output directory '" + dir + "': " +
                (ec ? ec.message() : "a file of that name exists") + " (expected a writable folder for --out)");
}

bool stop_requested(const RunOptions& o, std::size_t done) {
  if (o.stop && o.stop->load()) return true;
  return o.stop_after_frames >= 0 && static_cast<long>(done) >= o.stop_after_frames;
}

}  // namespace

RunResult run_dataset(const RunOptions& o) {
  require(!o.out_dir.empty(), "run: an output directory is required (--out)");
  o.config.validate();
  Components c = build(o);
  if (!o.slam_only) check_cost(c.config, c.source->camera(), o.force);  // before the first frame
  create_output_dir(o.out_dir);

  RunResult r;
  r.frames_total = c.source->size();
  if (o.max_frames >= 0) r.frames_total = std::min<std::size_t>(r.frames_total, o.max_frames);
  require(r.frames_total > 0, "run: dataset " + c.info.dataset_dir + " has no frames");
  spdlog::info("run: {} frames from {} (poses: {})", r.frames_total, c.info.dataset_dir, c.info.poses);
  spdlog::info("run: segmenter: {}{}", c.info.segmenter,
               c.info.segmenter_reason.empty() ? "" : " (" + c.info.segmenter_reason + ")");

  // The report's camera views: segmentations of a few integrated frames, kept as the run goes.
  CameraViewSampler camera_views;
  if (o.report && c.config.eval.plots)
    c.pipeline->set_frame_listener([&camera_views](const FrameOutcome& f, const RgbdFrame&, const semantics::LabelMap& l) {
      camera_views.offer(f, l);
    });
  ProgressLine progress(r.frames_total, o.progress);
  Stopwatch wall;
  std::size_t submitted = 0;
  for (; submitted < r.frames_total; ++submitted) {
    if (stop_requested(o, submitted)) {
      r.interrupted = true;
      break;
    }
    c.pipeline->process(c.source->load(submitted));
    progress.update(c.pipeline->frames_done(), c.pipeline->last_state());
  }
  c.pipeline->finish();
  c.info.wall_time_s = wall.elapsed_ms() / 1000.0;
  c.info.interrupted = r.interrupted;
  c.info.frames_total = r.frames_total;
  r.frames_done = c.pipeline->frames_done();
  progress.finish(r.frames_done, r.interrupted ? "interrupted" : c.pipeline->last_state());
  if (r.interrupted) spdlog::warn("run: stopped after {} of {} frames; writing what was processed", r.frames_done, r.frames_total);

  // Outputs first (trajectory and map are what a user keeps), then the evaluation of them.
  const bool keep_loaded = r.interrupted && same_folder(o.map_dir, o.out_dir);
  if (keep_loaded) spdlog::warn("run: interrupted: the session loaded from {} is not overwritten", o.out_dir);
  const OutputPaths paths = write_outputs(*c.pipeline, c.config, o.out_dir, !keep_loaded);
  r.metrics = compute_metrics(*c.pipeline, *c.source, c.config, c.info, paths);
  write_metrics(r.metrics, paths);
  if (o.report && c.config.eval.plots) {
    const std::string views = write_report_views(*c.pipeline, *c.source, c.config, paths, camera_views.chosen());
    if (!views.empty()) spdlog::warn("run: report pictures missing: {}", views);
    const ReportResult rep = make_report(o.out_dir);
    r.report_html = rep.html;
    r.report_error = rep.error;
    if (!rep.error.empty()) spdlog::warn("run: report not made: {}", rep.error);
  }
  return r;
}

}  // namespace s3m::pipeline
