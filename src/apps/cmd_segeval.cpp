// `s3m segeval`: segmentation evaluation (per-class IoU, mIoU, pixel accuracy, confusion matrix PNG),
// optionally running a segmenter (ONNX model card) over a folder of images first.
//
//   s3m segeval --pred-dir P --gt-dir G [--classes classes.txt] [--out DIR]
//   s3m segeval --card models/x.yaml [--model-dir D] --images IMGS [--gt-dir G] --out DIR
// Label images are PNGs of project class ids (8 or 16 bit), matched by file stem; --gt-map/--gt-names
// translate another dataset's ids (e.g. SUN RGB-D 37) into project ids first.
#include <filesystem>
#include <fstream>
#include <iostream>

#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>

#include "commands.hpp"
#include "s3m/core/error.hpp"
#include "s3m/core/timing.hpp"
#include "s3m/io/image_io.hpp"
#include "s3m/semantics/class_map.hpp"
#include "s3m/semantics/onnx_segmenter.hpp"
#include "s3m/semantics/seg_metrics.hpp"

namespace s3m::apps {
namespace fs = std::filesystem;
using namespace s3m::semantics;

namespace {

struct SegevalOptions {
  std::string pred_dir, gt_dir, classes_path, gt_map, gt_names, out_dir, card, model_dir, images;
  std::vector<std::string> exclude;
  int every = 1;
  long max_images = 0;
};

// A single image file, or every .png/.jpg/.jpeg in a folder, sorted by name (numerically for timestamps).
std::vector<fs::path> list_images(const std::string& path, int every, long max_images) {
  if (!fs::exists(path)) throw Error("'" + path + "' does not exist");
  std::vector<fs::path> all;
  if (fs::is_regular_file(path)) {
    all.push_back(path);
  } else {
    for (const auto& e : fs::directory_iterator(path)) {
      const auto ext = e.path().extension().string();
      if (e.is_regular_file() && (ext == ".png" || ext == ".jpg" || ext == ".jpeg")) all.push_back(e.path());
    }
    // TUM-style names are timestamps: order numerically when every stem is a number.
    auto number = [](const fs::path& p) {
      char* end = nullptr;
      const std::string s = p.stem().string();
      const double v = std::strtod(s.c_str(), &end);
      return std::make_pair(!s.empty() && *end == '\0', v);
    };
    const bool numeric =
        std::all_of(all.begin(), all.end(), [&](const fs::path& p) { return number(p).first; });
    std::sort(all.begin(), all.end(), [&](const fs::path& a, const fs::path& b) {
      return numeric ? number(a).second < number(b).second : a < b;
    });
  }
  std::vector<fs::path> out;
  for (std::size_t i = 0; i < all.size(); i += std::max(every, 1)) {
    out.push_back(all[i]);
    if (max_images > 0 && static_cast<long>(out.size()) >= max_images) break;
  }
  if (out.empty()) throw Error("no images (.png/.jpg) in '" + path + "'");
  return out;
}

// Runs the card's model on every image; writes <stem>.png (16-bit ids), color/<stem>.png, overlay/<stem>.png.
std::string run_segmenter(const SegevalOptions& o, const ClassList& classes) {
  auto seg = OnnxSegmenter::from_card(o.card, o.model_dir);
  const fs::path out = fs::path(o.out_dir) / "pred";
  fs::create_directories(out / "color");
  fs::create_directories(out / "overlay");
  const auto images = list_images(o.images, o.every, o.max_images);
  std::cout << fmt::format("segmenting {} images with '{}' ({}x{} input, {} output grid)\n", images.size(),
                           seg->name(), seg->card().input_width, seg->card().input_height,
                           fmt::format("{}x{}", seg->output_size().width, seg->output_size().height));
  std::vector<double> ms;
  for (std::size_t i = 0; i < images.size(); ++i) {
    const cv::Mat bgr = io::read_rgb(images[i].string());
    Stopwatch sw;
    const LabelMap m = seg->segment(bgr);
    ms.push_back(sw.elapsed_ms());
    const std::string stem = images[i].stem().string();
    cv::imwrite((out / (stem + ".png")).string(), m.argmax);
    cv::imwrite((out / "color" / (stem + ".png")).string(), colorize(m.argmax, seg->class_map().target()));
    cv::imwrite((out / "overlay" / (stem + ".png")).string(),
                overlay(bgr, m.argmax, seg->class_map().target()));
    if ((i + 1) % 20 == 0 || i + 1 == images.size())
      std::cout << fmt::format("  [{}/{}] {} ({:.1f} ms)\n", i + 1, images.size(), stem, ms.back());
  }
  const TimingStats t = timing_stats(ms);
  std::cout << fmt::format(
      "segment(): mean {:.1f} ms, median {:.1f} ms, p95 {:.1f} ms per image (incl. pre/post-processing)\n",
      t.mean_ms, t.p50_ms, t.p95_ms);
  (void)classes;
  return out.string();
}

// Pairs prediction and ground-truth files by stem (or the two files when both are single files).
std::vector<std::pair<fs::path, fs::path>> pair_files(const std::string& pred, const std::string& gt) {
  std::vector<std::pair<fs::path, fs::path>> pairs;
  const auto preds = list_images(pred, 1, 0);
  if (fs::is_regular_file(gt)) {
    if (preds.size() != 1)
      throw Error("--gt-dir is one file but there are " + std::to_string(preds.size()) + " predictions");
    pairs.emplace_back(preds[0], gt);
    return pairs;
  }
  for (const auto& p : preds) {
    const fs::path g = fs::path(gt) / (p.stem().string() + ".png");
    if (!fs::exists(g))
      throw Error("no ground truth '" + g.string() + "' for prediction '" + p.string() + "'");
    pairs.emplace_back(p, g);
  }
  return pairs;
}

void write_report(const std::string& out_dir, const SegMetrics& m, const ConfusionMatrix& cm,
                  const ClassList& classes) {
  fs::create_directories(out_dir);
  cv::imwrite((fs::path(out_dir) / "confusion.png").string(), cm.render(classes));
  std::ofstream csv(fs::path(out_dir) / "per_class_iou.csv");
  csv << "class_id,class,iou,gt_pixels\n";
  for (std::size_t c = 1; c < m.iou.size(); ++c)
    if (m.gt_px[c] > 0 || !std::isnan(m.iou[c]))
      csv << c << ',' << classes.at(ClassId(c)).name << ',' << (std::isnan(m.iou[c]) ? 0.0 : m.iou[c]) << ','
          << m.gt_px[c] << '\n';
  std::ofstream json(fs::path(out_dir) / "metrics.json");
  json << fmt::format(
      "{{\n  \"miou\": {:.6f},\n  \"pixel_accuracy\": {:.6f},\n  \"evaluated_pixels\": {},\n  \"classes\": "
      "{{",
      m.miou, m.pixel_accuracy, m.evaluated_px);
  bool first = true;
  for (ClassId c : m.evaluated) {
    json << fmt::format("{}\n    \"{}\": {:.6f}", first ? "" : ",", classes.at(c).name, m.iou[c]);
    first = false;
  }
  json << "\n  }\n}\n";
  if (!json.good() || !csv.good()) throw Error("cannot write the report into '" + out_dir + "'");
  std::cout << "wrote " << out_dir << "/{metrics.json, per_class_iou.csv, confusion.png}\n";
}

void run_segeval(const SegevalOptions& o) {
  const ClassList classes = o.classes_path.empty() ? indoor_classes() : read_class_list(o.classes_path);
  if (o.card.empty() == o.pred_dir.empty())
    throw Error("give either --pred-dir (evaluate) or --card with --images (segment, then evaluate)");
  std::string pred_dir = o.pred_dir;
  if (!o.card.empty()) {
    if (o.images.empty() || o.out_dir.empty()) throw Error("--card needs --images and --out");
    pred_dir = run_segmenter(o, classes);
  }
  if (o.gt_dir.empty()) return;  // segmentation only
  ClassMap gt_map;
  if (!o.gt_map.empty()) {
    if (o.gt_names.empty()) throw Error("--gt-map needs --gt-names (the ground truth's class names)");
    gt_map = ClassMap::load(o.gt_map, read_class_names(o.gt_names), classes);
  }
  std::vector<ClassId> exclude;
  for (const auto& name : o.exclude) {
    const int id = classes.find(name);
    if (id < 0) throw Error("--exclude: unknown class '" + name + "'");
    exclude.push_back(ClassId(id));
  }
  ConfusionMatrix cm(int(classes.size()));
  const auto pairs = pair_files(pred_dir, o.gt_dir);
  for (const auto& [p, g] : pairs) {
    cv::Mat gt = io::read_label_png(g.string());
    if (!o.gt_map.empty()) {
      gt = gt_map.apply(gt);
      if (!o.out_dir.empty()) {  // keep the translated ground truth for inspection and figures
        fs::create_directories(fs::path(o.out_dir) / "gt_mapped");
        cv::imwrite((fs::path(o.out_dir) / "gt_mapped" / (p.stem().string() + ".png")).string(), gt);
      }
    }
    cm.add(gt, io::read_label_png(p.string()));
  }
  const SegMetrics m = cm.metrics(exclude);
  std::cout << fmt::format("evaluated {} image pairs\n", pairs.size()) << format_metrics(m, classes);
  if (!o.out_dir.empty()) write_report(o.out_dir, m, cm, classes);
}

}  // namespace

void register_segeval(CLI::App& app) {
  auto opts = std::make_shared<SegevalOptions>();
  auto* cmd = app.add_subcommand(
      "segeval", "Segmentation evaluation: per-class IoU, mIoU, pixel accuracy, confusion matrix");
  cmd->add_option("--pred-dir", opts->pred_dir, "Predicted label PNGs (project class ids), or one file");
  cmd->add_option("--gt-dir", opts->gt_dir, "Ground-truth label PNGs matched by file stem, or one file");
  cmd->add_option("--classes", opts->classes_path,
                  "Project class list (classes.txt); default: built-in indoor list");
  cmd->add_option("--gt-map", opts->gt_map,
                  "Class map YAML translating ground-truth ids (e.g. config/classmaps/sunrgbd37.yaml)");
  cmd->add_option("--gt-names", opts->gt_names, "Ground truth's class names (names.txt or id<TAB>name .tsv)");
  cmd->add_option("--exclude", opts->exclude, "Classes left out of the mIoU (e.g. other)");
  cmd->add_option("--out", opts->out_dir,
                  "Output folder: metrics.json, per_class_iou.csv, confusion.png (+ pred/)");
  cmd->add_option("--card", opts->card, "Segment --images first with this ONNX model card");
  cmd->add_option("--model-dir", opts->model_dir,
                  "Folder holding the card's model and class list (default: the card's)");
  cmd->add_option("--images", opts->images, "Image folder or file to segment (with --card)");
  cmd->add_option("--every", opts->every, "Use every N-th image")->check(CLI::PositiveNumber);
  cmd->add_option("--max-images", opts->max_images, "Stop after this many images (0 = all)")
      ->check(count_option());
  cmd->callback([opts] { run_segeval(*opts); });
}

}  // namespace s3m::apps
