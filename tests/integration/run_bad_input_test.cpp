// Bad input through `s3m run` (run::run_dataset): each case gets an s3m::Error naming the file,
// the line where there is one, and what was expected — never a crash or a foreign exception — and a
// failing run leaves the outputs of an earlier run in OUT intact and loadable.
#include <sys/resource.h>

#include <csignal>
#include <regex>

#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>

#include "pipeline_fixture.hpp"
#include "s3m/core/error.hpp"
#include "s3m/io/trajectory.hpp"
#include "s3m/mapping/map_io.hpp"
#include "unit/fifo_test_util.hpp"

namespace s3m::it {
namespace {

const auto* const kCleanup = ::testing::AddGlobalTestEnvironment(new ScratchCleanup);

constexpr int kShort = 8;  // frames of the bad-input sequences (errors need no long runs)

// Keeps comment lines and the first n data lines of a TUM list.
void truncate_list(const fs::path& file, int n) {
  std::istringstream in(read_bytes(file.string()));
  std::string out, line;
  int data = 0;
  while (std::getline(in, line))
    if (line.empty() || line[0] == '#' || data++ < n) out += line + "\n";
  std::ofstream(file) << out;
}

// The first kShort frames of the shared simulated sequence, copied into a fresh folder per case.
fs::path short_sequence(const std::string& name) {
  static const fs::path master = [] {
    const fs::path d = scratch_dir() / "short_master";
    fs::remove_all(d);
    fs::create_directories(d);
    for (const auto& e : fs::directory_iterator(sequence_dir()))
      if (e.is_regular_file()) fs::copy(e.path(), d / e.path().filename());
    for (const char* list : {"rgb.txt", "depth.txt", "labels.txt", "associations.txt"})
      truncate_list(d / list, kShort);
    // Copy just the images the shortened lists name.
    for (const char* sub : {"rgb", "depth", "labels"}) {
      fs::create_directories(d / sub);
      std::istringstream in(read_bytes((d / (std::string(sub) + ".txt")).string()));
      std::string line, t, path;
      while (std::getline(in, line)) {
        if (line.empty() || line[0] == '#') continue;
        std::istringstream(line) >> t >> path;
        fs::copy(fs::path(sequence_dir()) / path, d / path);
      }
    }
    return d;
  }();
  const fs::path d = scratch_dir() / ("bad_" + name);
  fs::remove_all(d);
  fs::copy(master, d, fs::copy_options::recursive);
  return d;
}

// The n-th data line's second field (the image path) of a TUM list.
std::string list_entry(const fs::path& list, int n) {
  std::istringstream in(read_bytes(list.string()));
  std::string line, t, path;
  for (int data = 0; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    if (data++ == n) {
      std::istringstream(line) >> t >> path;
      return path;
    }
  }
  throw Error("no entry " + std::to_string(n) + " in " + list.string());
}

// Replaces the first match of `pattern` (multi-line) in a text file.
void edit(const fs::path& file, const std::string& pattern, const std::string& replacement) {
  const std::string before = read_bytes(file.string());
  const std::string after = std::regex_replace(before, std::regex(pattern, std::regex::multiline),
                                               replacement, std::regex_constants::format_first_only);
  ASSERT_NE(before, after) << pattern << " not found in " << file;
  std::ofstream(file) << after;
}

run::RunOptions options_for(const fs::path& seq, const std::string& out_name) {
  run::RunOptions o = options(out_name, /*deterministic=*/true);
  o.dataset_dir = seq.string();
  return o;
}

// run_dataset must throw s3m::Error containing every fragment; returns the message.
std::string run_error(const run::RunOptions& o, std::initializer_list<std::string> fragments) {
  try {
    run::run_dataset(o);
  } catch (const Error& e) {
    const std::string msg = e.what();
    for (const auto& f : fragments)
      EXPECT_NE(msg.find(f), std::string::npos) << "message: " << msg << "\nmissing: " << f;
    ::testing::Test::RecordProperty("message", msg);
    return msg;
  }
  ADD_FAILURE() << "expected an s3m::Error";
  return {};
}

std::string run_error(const fs::path& seq, std::initializer_list<std::string> fragments) {
  return run_error(options_for(seq, "out_" + seq.filename().string()), fragments);
}

// A frame after the first that cannot be read is skipped: the run completes without it and
// names it (metrics.json skipped_frames). With dataset.max_unreadable_in_a_row 0 the same frame
// stops the run with that message, after writing the frames before it.
void expect_skipped(const fs::path& seq, int frame, std::initializer_list<std::string> fragments) {
  run::RunOptions o = options_for(seq, "out_" + seq.filename().string());
  const run::RunResult r = run::run_dataset(o);
  EXPECT_FALSE(r.interrupted);
  EXPECT_EQ(r.frames_done, static_cast<std::size_t>(kShort - 1));
  ASSERT_EQ(r.metrics["skipped_frames"].size(), 1u);
  EXPECT_EQ(r.metrics["skipped_frames"][0]["index"].get<int>(), frame);
  const std::string why = r.metrics["skipped_frames"][0]["error"];
  for (const auto& f : fragments)
    EXPECT_NE(why.find(f), std::string::npos) << "skipped: " << why << "\nmissing: " << f;
  o.config.dataset.max_unreadable_in_a_row = 0;
  const std::string msg = run_error(o, fragments);
  EXPECT_NE(msg.find(fmt::format("stopped at frame {} of {}", frame, kShort)), std::string::npos) << msg;
  EXPECT_EQ(io::read_tum_trajectory(o.out_dir + "/trajectory_camera.txt").size(),
            static_cast<std::size_t>(frame));
}

TEST(RunBadInput, TheShortSequenceItselfRuns) {  // so every failure below is the edit's doing
  const auto r = run::run_dataset(options_for(short_sequence("good"), "good"));
  EXPECT_EQ(r.frames_done, static_cast<std::size_t>(kShort));
}

TEST(RunBadInput, MissingDatasetOrList) {
  const fs::path seq = short_sequence("missing");
  run_error(seq / "nope", {"nope", "directory not found", "expected a TUM RGB-D sequence directory"});
  fs::remove(seq / "rgb.txt");
  fs::remove(seq / "associations.txt");
  run_error(seq, {"rgb.txt", "not found"});
}

TEST(RunBadInput, MissingImageFile) {
  const fs::path seq = short_sequence("missing_png");
  fs::remove(seq / list_entry(seq / "rgb.txt", 3));
  run_error(seq, {list_entry(seq / "rgb.txt", 3), "not found"});
}

TEST(RunBadInput, CorruptAndTruncatedPngs) {
  const fs::path seq = short_sequence("corrupt_png");
  std::ofstream(seq / list_entry(seq / "rgb.txt", 2), std::ios::binary) << "this is not a PNG at all";
  // Text is refused before any decoder sees it, with its first bytes ("this is ").
  expect_skipped(seq, 2,
                 {list_entry(seq / "rgb.txt", 2), "not a PNG or JPEG file", "74 68 69 73 20 69 73 20"});
  const fs::path seq2 = short_sequence("truncated_png");
  const fs::path depth = seq2 / list_entry(seq2 / "depth.txt", 4);
  const std::string bytes = read_bytes(depth.string());
  std::ofstream(depth, std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  expect_skipped(seq2, 4,
                 {list_entry(seq2 / "depth.txt", 4), "cannot read or decode"});  // a PNG: libpng reports it
}

// A run that fails on its first frame writes nothing: the earlier run's outputs in the same OUT stay.
TEST(RunBadInput, AFailedRunLeavesTheEarlierRunsOutputsIntact) {
  const fs::path seq = short_sequence("rerun");
  const run::RunOptions o = options_for(seq, "rerun");
  run::run_dataset(o);
  const std::string map_before = read_bytes(o.out_dir + "/map.ot");
  const std::string metrics_before = read_bytes(o.out_dir + "/metrics.json");
  std::ofstream(seq / list_entry(seq / "rgb.txt", 0), std::ios::binary) << "garbage";
  run_error(o, {list_entry(seq / "rgb.txt", 0), "not a PNG"});
  EXPECT_TRUE(read_bytes(o.out_dir + "/map.ot") == map_before);
  EXPECT_EQ(read_bytes(o.out_dir + "/metrics.json"), metrics_before);
  EXPECT_NE(mapping::load_semantic_map(o.out_dir + "/map.ot"), nullptr);
}

TEST(RunBadInput, EightBitDepthAndWrongImageSize) {
  const fs::path seq = short_sequence("depth8");
  const fs::path depth = seq / list_entry(seq / "depth.txt", 1);
  cv::imwrite(depth.string(), cv::Mat(480, 640, CV_8UC1, cv::Scalar(100)));
  expect_skipped(seq, 1, {depth.filename().string(), "8-bit", "expected a 16-bit single-channel depth PNG"});
  const fs::path seq2 = short_sequence("small_rgb");
  const fs::path rgb = seq2 / list_entry(seq2 / "rgb.txt", 5);
  cv::imwrite(rgb.string(), cv::Mat(240, 320, CV_8UC3, cv::Scalar(1, 2, 3)));
  expect_skipped(seq2, 5, {rgb.filename().string(), "image is 320x240", "expected 640x480"});
  // On the first frame the same error stops the run: there it is most often every frame's.
  const fs::path seq3 = short_sequence("small_first");
  cv::imwrite((seq3 / list_entry(seq3 / "rgb.txt", 0)).string(),
              cv::Mat(240, 320, CV_8UC3, cv::Scalar(1, 2, 3)));
  const std::string msg = run_error(seq3, {list_entry(seq3 / "rgb.txt", 0), "image is 320x240"});
  EXPECT_EQ(msg.find("stopped at frame"), std::string::npos) << msg;
}

TEST(RunBadInput, TimestampsThatDoNotMatch) {
  const fs::path seq = short_sequence("shifted");
  fs::remove(seq / "associations.txt");
  // Depth stamps 5 s later than colour: nothing pairs within max_dt_s.
  std::istringstream in(read_bytes((seq / "depth.txt").string()));
  std::string out, line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ss(line);
    double t;
    std::string path;
    ss >> t >> path;
    out += std::to_string(t + 5.0) + " " + path + "\n";
  }
  std::ofstream(seq / "depth.txt") << out;
  run_error(seq, {"depth.txt", "no depth timestamp within 0.02 s"});
}

TEST(RunBadInput, EmptySequence) {
  const fs::path seq = short_sequence("empty");
  fs::remove(seq / "associations.txt");
  std::ofstream(seq / "rgb.txt") << "# color images\n# timestamp filename\n";
  run_error(seq, {"rgb.txt", "no entries", "expected lines 'timestamp path'"});
}

TEST(RunBadInput, NanAndHugePosesInGroundTruth) {
  const fs::path seq = short_sequence("nan_gt");
  edit(seq / "groundtruth.txt", R"(^([0-9.]+) [-0-9.e]+ )", "$1 nan ");
  run_error(seq,
            {"groundtruth.txt:", "non-finite value 'nan' as tx", "expected a finite number in column 2"});
  const fs::path seq2 = short_sequence("huge_gt");
  edit(seq2 / "groundtruth.txt", R"(^([0-9.]+) [-0-9.e]+ )", "$1 1e300 ");
  run_error(seq2, {"groundtruth.txt:", "implausibly large"});
}

TEST(RunBadInput, ZeroNegativeAndHugeIntrinsics) {
  const fs::path seq = short_sequence("fx0");
  edit(seq / "camera.yaml", "^fx: .*$", "fx: 0");
  run_error(seq, {"camera.yaml", "fx", "> 0"});
  const fs::path seq2 = short_sequence("fy_neg");
  edit(seq2 / "camera.yaml", "^fy: .*$", "fy: -525");
  run_error(seq2, {"camera.yaml", "fy", "> 0"});
  const fs::path seq3 = short_sequence("width_huge");
  edit(seq3 / "camera.yaml", "^width: .*$", "width: 1e300");
  run_error(seq3, {"camera.yaml", "width", "1..16384"});
  const fs::path seq4 = short_sequence("depth_factor0");
  edit(seq4 / "camera.yaml", "^depth_factor: .*$", "depth_factor: 0");
  run_error(seq4, {"camera.yaml", "depth_factor"});
  // Normalised intrinsics ran to an ATE in metres.
  const fs::path seq5 = short_sequence("fx_normalised");
  edit(seq5 / "camera.yaml", "^fx: .*$", "fx: 0.9");
  run_error(seq5, {"camera.yaml", "fx=0.9", "deg field of view over 640 px", "normalised intrinsics"});
}

TEST(RunBadInput, ModelCardWhoseClassCountDoesNotMatchTheModel) {
  // The test model has 4 output channels; its card names a class file with 3.
  const fs::path dir = scratch_dir() / "model_card_4_classes";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path data = fs::path(S3M_TEST_DATA_DIR) / "semantics";
  fs::copy(data / "tiny_rgb.onnx", dir / "tiny_rgb.onnx");
  fs::copy(data / "tiny_rgb.yaml", dir / "tiny_rgb.yaml");
  std::ofstream(dir / "tiny_rgb.classes.txt") << "wall\nfloor\nchair\n";
  run::RunOptions o = options_for(short_sequence("card"), "card");
  o.segmenter = "onnx:" + (dir / "tiny_rgb.yaml").string();
  run_error(o, {"tiny_rgb.yaml", "has 3 classes but the model outputs 4 channels"});
}

TEST(RunBadInput, OutputDirectoryThatCannotBeCreated) {
  run::RunOptions o = options_for(short_sequence("outdir"), "blocker");
  std::ofstream(o.out_dir) << "a file where the output folder should be";
  run_error(o, {"--out '" + o.out_dir + "' is a file, not a folder"});
}

// Lowers the file-size limit while alive: writes beyond it fail with EFBIG (SIGXFSZ ignored), as
// writes on a full disk fail with ENOSPC.
class FileSizeLimit {
 public:
  explicit FileSizeLimit(rlim_t bytes) {
    getrlimit(RLIMIT_FSIZE, &old_);
    old_handler_ = std::signal(SIGXFSZ, SIG_IGN);
    rlimit lim = old_;
    lim.rlim_cur = bytes;
    ok_ = setrlimit(RLIMIT_FSIZE, &lim) == 0;
  }
  ~FileSizeLimit() {
    setrlimit(RLIMIT_FSIZE, &old_);
    std::signal(SIGXFSZ, old_handler_);
  }
  bool ok() const { return ok_; }

 private:
  rlimit old_{};
  void (*old_handler_)(int) = SIG_DFL;
  bool ok_ = false;
};

TEST(RunBadInput, DiskFullWhileWritingOutputsKeepsThePreviousRunLoadable) {
  const run::RunOptions o = options_for(short_sequence("disk_full"), "disk_full");
  run::run_dataset(o);
  const std::string map_before = read_bytes(o.out_dir + "/map.ot");
  const std::string traj_before = read_bytes(o.out_dir + "/trajectory_camera.txt");
  const std::string metrics_before = read_bytes(o.out_dir + "/metrics.json");
  ASSERT_GT(map_before.size(), 64u * 1024u);  // so the limit below stops the map, not the small files
  {
    const FileSizeLimit limit(64 * 1024);
    ASSERT_TRUE(limit.ok());
    run_error(o, {o.out_dir + "/map.ot", "disk full?"});
  }
  // The earlier run's files are whole, unchanged and load; no temporary file or staging folder is left.
  EXPECT_TRUE(read_bytes(o.out_dir + "/map.ot") == map_before);
  EXPECT_NE(mapping::load_semantic_map(o.out_dir + "/map.ot"), nullptr);
  EXPECT_EQ(read_bytes(o.out_dir + "/trajectory_camera.txt"), traj_before);
  EXPECT_EQ(read_bytes(o.out_dir + "/metrics.json"),
            metrics_before);  // not a new trajectory beside old metrics
  EXPECT_EQ(io::read_tum_trajectory(o.out_dir + "/trajectory_camera.txt").size(),
            static_cast<std::size_t>(kShort));
  for (const auto& e : fs::directory_iterator(o.out_dir))
    EXPECT_TRUE(e.path().filename().string().find(".tmp") == std::string::npos &&
                e.path().filename().string().find(".s3m-staging") == std::string::npos)
        << e.path();
}

// A FIFO where a list or an image belongs: refused with its path instead of blocking the run
// forever (issue 24); the read has a timeout, so a reader that opens the FIFO fails, not hangs.
TEST(RunBadInput, FifoInsteadOfAListOrAnImage) {
  const fs::path seq = short_sequence("fifo_list");
  testing::make_fifo(seq / "associations.txt");
  testing::error_without_blocking(seq / "associations.txt", [&] {
    run_error(seq, {"associations.txt", "is a FIFO (named pipe), not a regular file"});
  });
  const fs::path seq2 = short_sequence("fifo_png");
  const std::string png = list_entry(seq2 / "rgb.txt", 3);
  testing::make_fifo(seq2 / png);
  testing::error_without_blocking(seq2 / png, [&] {
    run_error(seq2,
              {"associations.txt:", "image file '" + png + "' is a FIFO (named pipe), not a regular file"});
  });
}

// `s3m run` as a user types it, limited to 4 GB of address space and 120 s so that a regression
// (a crash, or a run until the machine is exhausted) fails instead of taking the machine down.
int s3m_run(const std::string& args, const fs::path& log_path, std::string* log) {
  const std::string cmd = "ulimit -v 4000000; timeout 120 " + std::string(S3M_BINARY) + " run " + args +
                          " > '" + log_path.string() + "' 2>&1";
  const int status = std::system(cmd.c_str());
  *log = read_bytes(log_path.string());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

fs::path edited_preset(const std::string& name, const std::string& pattern, const std::string& replacement) {
  const fs::path preset = scratch_dir() / (name + ".yaml");
  fs::copy_file(fs::path(S3M_TEST_DATA_DIR) / ".." / ".." / "config" / "sim.yaml", preset,
                fs::copy_options::overwrite_existing);
  edit(preset, pattern, replacement);
  return preset;
}

// 2f6b067: exit 139 (segmentation fault inside TBB) for map.insert.num_threads 65537.
TEST(RunBadInput, HugeThreadCountInAPresetIsRefusedByTheCli) {
  const fs::path preset = edited_preset("threads_65537", "radius_min_neighbors: 1\\}",
                                        "radius_min_neighbors: 1, num_threads: 65537}");
  const fs::path seq = short_sequence("cli_threads");
  std::string log;
  EXPECT_EQ(s3m_run("--config '" + preset.string() + "' --deterministic --no-report '" + seq.string() +
                        "' --out '" + (scratch_dir() / "out_cli_threads").string() + "'",
                    scratch_dir() / "cli_threads.log", &log),
            1)
      << log;
  EXPECT_NE(log.find("s3m: error: " + preset.string() + ":"), std::string::npos) << log;
  EXPECT_NE(log.find("insert.num_threads = 65537 must be 0 (all cores) or 1.."), std::string::npos) << log;
}

// 2f6b067: a segmentation fault in cv::setNumThreads(65537).
TEST(RunBadInput, HugeThreadCountInAModelCardIsRefused) {
  const fs::path dir = scratch_dir() / "model_card_threads";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path data = fs::path(S3M_TEST_DATA_DIR) / "semantics";
  for (const char* f : {"tiny_rgb.onnx", "tiny_rgb.yaml", "tiny_rgb.classes.txt"})
    fs::copy(data / f, dir / f);
  std::ofstream(dir / "tiny_rgb.yaml", std::ios::app) << "threads: 65537\n";
  run::RunOptions o = options_for(short_sequence("card_threads"), "card_threads");
  o.segmenter = "onnx:" + (dir / "tiny_rgb.yaml").string();
  run_error(o, {"tiny_rgb.yaml", "threads = 65537 out of range", "expected 0 (OpenCV's default) or 1.."});
}

// 2f6b067: ran until killed (5.9 GB after one frame). Refused before the first frame and before
// anything is written; --force runs it (not tested: it is what exhausts the machine).
TEST(RunBadInput, SettingsThatWouldExhaustTheMachineAreRefusedBeforeTheFirstFrame) {
  run::RunOptions o = options_for(short_sequence("cost"), "cost");
  o.config.cloud.pixel_stride = 1;
  o.config.map.resolution_m = 0.005;
  o.config.cloud.max_depth_m = 100;
  run_error(o, {"cloud.pixel_stride 1 x 640x480 px with map.resolution_m 0.005 and cloud.max_depth_m 100",
                "voxel updates per integrated frame", "exceeds the limit of 1e+08", "--force"});
  EXPECT_FALSE(fs::exists(o.out_dir));
  // The same through the CLI, from a preset.
  const fs::path preset = edited_preset("cost", "pixel_stride: 2 ", "pixel_stride: 1 ");
  edit(preset, "resolution_m: 0.05 ", "resolution_m: 0.005 ");
  edit(preset, "max_depth_m: 4.0 ", "max_depth_m: 100 ");
  std::string log;
  EXPECT_EQ(s3m_run("--config '" + preset.string() + "' --deterministic --no-report '" + o.dataset_dir +
                        "' --out '" + o.out_dir + "'",
                    scratch_dir() / "cli_cost.log", &log),
            1)
      << log;
  EXPECT_NE(log.find("about 3.1e+08 voxel updates per integrated frame"), std::string::npos) << log;
  EXPECT_NE(log.find("or pass --force to run anyway"), std::string::npos) << log;
}

}  // namespace
}  // namespace s3m::it
