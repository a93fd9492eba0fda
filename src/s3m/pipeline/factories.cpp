#include "s3m/pipeline/factories.hpp"

#include <algorithm>
#include <cstdlib>
#include <filesystem>

#include "s3m/core/error.hpp"
#include "s3m/core/yaml_util.hpp"
#include "s3m/semantics/onnx_segmenter.hpp"
#include "s3m/semantics/oracle_segmenter.hpp"

namespace s3m::pipeline {
namespace fs = std::filesystem;

std::unique_ptr<PoseSource> make_pose_source(const std::string& kind, const FrameSource& source,
                                             const PinholeCamera& camera, const PipelineConfig& config) {
  if (kind == "slam") return make_slam_poses(camera, config);
  if (kind == "gt") {
    if (source.groundtruth().empty())
      throw Error("--poses gt: " + source.name() + " has no ground truth (expected groundtruth.txt with TUM "
                  "'t tx ty tz qx qy qz qw' lines, or a bag's ground-truth topic)");
    GroundTruthPosesConfig g;
    g.max_dt_s = config.eval.gt_max_dt_s;
    return make_ground_truth_poses(source.groundtruth(), g);
  }
  throw Error("--poses: unknown value '" + kind + "' (expected slam | gt)");
}

std::string repo_path(const std::string& relative) {
  const char* env = std::getenv("S3M_SOURCE_DIR");
  return (fs::path(env && *env ? env : S3M_SOURCE_DIR) / relative).string();
}

ResolvedCard resolve_model_card(const std::string& path) {
  if (fs::is_regular_file(path)) return {path, ""};
  if (fs::is_regular_file(path + ".yaml")) return {path + ".yaml", ""};  // "models/s3m_pspnet_small"
  if (!fs::is_directory(path))
    throw Error("segmenter: model '" + path + "' is neither a model card (.yaml) nor a folder");
  std::vector<std::string> cards;
  for (const auto& e : fs::directory_iterator(path)) {
    if (e.path().extension() != ".yaml" || !e.is_regular_file()) continue;  // a FIFO would block LoadFile
    try {
      if (YAML::LoadFile(e.path().string())["model"]) cards.push_back(e.path().string());
    } catch (const YAML::Exception&) {  // not a card; ignore
    }
  }
  std::sort(cards.begin(), cards.end());
  if (cards.size() == 1) return {cards[0], ""};
  if (cards.size() > 1) throw Error("segmenter: " + path + " holds several model cards; pass one: onnx:" + cards[0]);
  const fs::path name = fs::path(path).lexically_normal().filename().empty()
                            ? fs::path(path).lexically_normal().parent_path().filename()
                            : fs::path(path).lexically_normal().filename();
  const fs::path repo_card = repo_path("models/external/" + name.string() + ".yaml");
  if (fs::exists(repo_card)) return {repo_card.string(), path};
  throw Error("segmenter: no model card for " + path + " (expected a .yaml card in that folder or " +
              repo_card.string() + "); pass onnx:CARD.yaml with --model-dir " + path);
}

std::unique_ptr<semantics::Segmenter> make_segmenter(const SegmenterSpec& spec, const PipelineConfig& config,
                                                     bool dataset_has_labels) {
  const SegmenterConfig& sc = config.segmenter;
  std::string type = sc.type, model = sc.model, model_dir = sc.model_dir;
  switch (spec.kind) {
    case SegmenterSpec::Kind::kFromConfig: break;
    case SegmenterSpec::Kind::kNone: type = "none"; break;
    case SegmenterSpec::Kind::kOracle: type = "oracle"; break;
    case SegmenterSpec::Kind::kOnnx: type = "onnx", model = spec.model, model_dir = spec.model_dir; break;
  }
  if (type == "none") return nullptr;
  if (type == "oracle") {
    if (!dataset_has_labels)
      throw Error("segmenter oracle: the dataset has no ground-truth label images (labels.txt, as the "
                  "simulator writes); use --segmenter onnx:MODEL or --segmenter none");
    return std::make_unique<semantics::OracleSegmenter>(sc.oracle, sc.top_k);
  }
  ResolvedCard card = resolve_model_card(model);
  if (!model_dir.empty()) card.model_dir = model_dir;
  return semantics::OnnxSegmenter::from_card(card.card, card.model_dir);
}

}  // namespace s3m::pipeline
