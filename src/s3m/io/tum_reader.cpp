// TUM RGB-D sequences: rgb/, depth/, rgb.txt, depth.txt ('t path'), optional associations.txt
// ('t_rgb rgb_path t_depth depth_path'), optional groundtruth.txt (TUM trajectory, T_w_c) and the
// s3m extensions camera.yaml (intrinsics + depth_factor, and a depth_camera section for depth not
// registered to colour: camera_yaml.hpp) and labels.txt ('t labels/x.png', class-id PNGs).
// ETH3D's RGB-D sequences are this layout with associated.txt for associations.txt and a
// calibration.txt ('fx fy cx cy', depth factor 5000, image size from the first image) for camera.yaml.
#include <filesystem>
#include <utility>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "s3m/core/error.hpp"
#include "s3m/core/input_file.hpp"
#include "s3m/io/association.hpp"
#include "s3m/io/dataset_reader.hpp"
#include "s3m/io/image_io.hpp"
#include "s3m/io/text_lines.hpp"

namespace s3m::io {
namespace fs = std::filesystem;
namespace {

struct ListEntry {
  double t_s;
  std::string path;
  int line;
};

bool exists_in(const std::string& dir, const char* name) { return fs::exists(fs::path(dir) / name); }

void check_image_exists(const std::string& dir, const std::string& rel, const LineReader& reader) {
  const fs::path p = fs::path(dir) / rel;
  if (!fs::exists(p)) reader.fail("image file '" + rel + "' not found", "an existing file under " + dir);
  if (const std::string problem = input_file_problem(p.string()); !problem.empty())
    reader.fail("image file '" + rel + "' " + problem, "a PNG or JPEG image file");
}

// 'timestamp path' lines with strictly increasing timestamps.
std::vector<ListEntry> read_list(const std::string& dir, const std::string& name, bool check_files) {
  LineReader reader((fs::path(dir) / name).string(), "a TUM list file 'timestamp path'");
  std::vector<ListEntry> list;
  std::vector<std::string_view> tok;
  while (reader.next(tok)) {
    reader.expect_tokens(tok, 2, "timestamp path");
    const double t = reader.number(tok, 0, "timestamp");
    if (!list.empty() && !(t > list.back().t_s))
      reader.fail(fmt::format("timestamp {:.6f} is not after the previous one ({:.6f})", t, list.back().t_s),
                  "strictly increasing timestamps");
    if (check_files) check_image_exists(dir, std::string(tok[1]), reader);
    list.push_back({t, std::string(tok[1]), reader.line()});
  }
  if (list.empty()) throw ParseError(reader.path(), 0, "no entries", "lines 'timestamp path'");
  return list;
}

std::vector<Dataset::Entry> read_associations(const std::string& dir, const std::string& name,
                                              bool check_files) {
  LineReader reader((fs::path(dir) / name).string(), "associations 't_rgb rgb_path t_depth depth_path'");
  std::vector<Dataset::Entry> out;
  std::vector<std::string_view> tok;
  while (reader.next(tok)) {
    reader.expect_tokens(tok, 4, "t_rgb rgb_path t_depth depth_path");
    Dataset::Entry e{reader.number(tok, 0, "rgb timestamp"), reader.number(tok, 2, "depth timestamp"),
                     std::string(tok[1]), std::string(tok[3]), ""};
    // associate.py depth.txt rgb.txt gives depth first; accept it rather than load depth as colour.
    if (e.rgb.rfind("depth", 0) == 0 && e.depth.rfind("rgb", 0) == 0) {
      std::swap(e.rgb, e.depth);
      std::swap(e.t_rgb_s, e.t_depth_s);
    }
    if (!out.empty() && !(e.t_rgb_s > out.back().t_rgb_s))
      reader.fail(fmt::format("rgb timestamp {:.6f} is not after the previous one ({:.6f})", e.t_rgb_s,
                              out.back().t_rgb_s),
                  "strictly increasing timestamps");
    if (check_files) {
      check_image_exists(dir, e.rgb, reader);
      check_image_exists(dir, e.depth, reader);
    }
    out.push_back(std::move(e));
  }
  if (out.empty())
    throw ParseError(reader.path(), 0, "no entries", "lines 't_rgb rgb_path t_depth depth_path'");
  return out;
}

std::vector<double> times_of(const std::vector<ListEntry>& list) {
  std::vector<double> ts;
  for (const auto& e : list) ts.push_back(e.t_s);
  return ts;
}

std::vector<Dataset::Entry> associate_lists(const std::string& dir, const DatasetOptions& opt) {
  const auto rgb = read_list(dir, "rgb.txt", opt.check_files);
  const auto depth = read_list(dir, "depth.txt", opt.check_files);
  std::vector<Dataset::Entry> out;
  for (const auto& m : associate(times_of(rgb), times_of(depth), opt.max_dt_s))
    out.push_back({rgb[m.a].t_s, depth[m.b].t_s, rgb[m.a].path, depth[m.b].path, ""});
  if (out.empty())
    throw ParseError((fs::path(dir) / "depth.txt").string(), 0,
                     fmt::format("no depth timestamp within {} s of any rgb timestamp", opt.max_dt_s),
                     "overlapping rgb.txt and depth.txt timestamps (or a larger max_dt_s)");
  if (out.size() < rgb.size())
    spdlog::warn("{}: {} of {} rgb frames have no depth within {} s and are not used", dir,
                 rgb.size() - out.size(), rgb.size(), opt.max_dt_s);
  return out;
}

// labels.txt (s3m extension), associated to the rgb timestamps.
void add_labels(Dataset::Parts& p, const DatasetOptions& opt) {
  const auto labels = read_list(p.dir, "labels.txt", opt.check_files);
  std::vector<double> rgb_t;
  for (const auto& f : p.frames) rgb_t.push_back(f.t_rgb_s);
  const auto matches = associate(rgb_t, times_of(labels), opt.max_dt_s);
  for (const auto& m : matches) p.frames[m.a].labels = labels[m.b].path;
  p.has_labels = true;
  if (matches.size() < p.frames.size())
    spdlog::warn("{}: {} of {} frames have no label image", p.dir, p.frames.size() - matches.size(),
                 p.frames.size());
}

// associations: "associations.txt", "associated.txt" (ETH3D) or "" for rgb.txt and depth.txt.
Dataset read_tum_layout(const std::string& dir, const DatasetOptions& options,
                        const std::string& associations, std::string layout) {
  Dataset::Parts p;
  p.dir = dir;
  p.layout = std::move(layout);
  // 1. Camera first: without intrinsics and depth factor no frame can be used.
  const auto [camera_file, camera_source] = dataset_camera(dir, options);
  p.camera = camera_file.camera;
  p.camera_source = camera_source;
  // 2. Frames: the given associations, else TUM-style nearest-timestamp association.
  p.frames = !associations.empty() ? read_associations(dir, associations, options.check_files)
                                   : associate_lists(dir, options);
  if (p.camera.width == 0) {  // calibration.txt has no image size: the first colour image's
    const cv::Mat first = read_rgb((fs::path(dir) / p.frames.front().rgb).string());
    p.camera.width = first.cols;
    p.camera.height = first.rows;
    p.camera.validate();
  }
  if (camera_file.depth) use_depth_camera(p, *camera_file.depth);
  // 3. Optional labels, 4. optional ground truth.
  if (exists_in(dir, "labels.txt")) add_labels(p, options);
  if (exists_in(dir, "groundtruth.txt"))
    p.groundtruth = read_tum_trajectory((fs::path(dir) / "groundtruth.txt").string());
  return Dataset(std::move(p));
}

class TumReader final : public DatasetReader {
 public:
  std::string name() const override { return "TUM"; }
  std::string detect(const std::string& dir) const override {
    if (exists_in(dir, "associations.txt")) return "associations.txt";
    if (exists_in(dir, "associated.txt")) return "";  // ETH3D's
    return exists_in(dir, "rgb.txt") ? "rgb.txt" : "";
  }
  std::string expected() const override {
    return "a TUM RGB-D sequence (rgb.txt, depth.txt, optional associations.txt)";
  }
  Dataset read(const std::string& dir, const DatasetOptions& options) const override {
    return read_tum_layout(dir, options, exists_in(dir, "associations.txt") ? "associations.txt" : "",
                           "TUM layout");
  }
};

// ETH3D: the TUM layout with associated.txt (and calibration.txt, see dataset_camera()).
class Eth3dReader final : public DatasetReader {
 public:
  std::string name() const override { return "ETH3D"; }
  std::string detect(const std::string& dir) const override {
    return !exists_in(dir, "associations.txt") && exists_in(dir, "associated.txt") ? "associated.txt" : "";
  }
  std::string expected() const override { return ""; }  // TUM's text covers it
  Dataset read(const std::string& dir, const DatasetOptions& options) const override {
    return read_tum_layout(dir, options, "associated.txt", "TUM layout (ETH3D's associated.txt)");
  }
};

}  // namespace

std::unique_ptr<const DatasetReader> make_tum_reader() { return std::make_unique<TumReader>(); }
std::unique_ptr<const DatasetReader> make_eth3d_reader() { return std::make_unique<Eth3dReader>(); }

}  // namespace s3m::io
