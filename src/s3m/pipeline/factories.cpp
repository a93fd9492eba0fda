#include "s3m/pipeline/factories.hpp"

#include <algorithm>
#include <filesystem>

#include "s3m/core/error.hpp"
#include "s3m/core/shipped_files.hpp"
#include "s3m/core/yaml_util.hpp"
#include "s3m/semantics/onnx_segmenter.hpp"
#include "s3m/semantics/oracle_segmenter.hpp"

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
    throw Error("--segmenter: unknown value '" + spec +
                "' (expected onnx:MODEL_DIR_OR_CARD | oracle | none)");
  }
  return s;
}

std::unique_ptr<PoseSource> make_pose_source(const std::string& kind, const FrameSource& source,
                                             const PinholeCamera& camera, const PipelineConfig& config) {
  if (kind == "slam") return make_slam_poses(camera, config);
  if (kind == "gt") {
    if (source.groundtruth().empty())
      throw Error("--poses gt: " + source.name() +
                  " has no ground truth (expected groundtruth.txt with TUM "
                  "'t tx ty tz qx qy qz qw' lines, or a bag's ground-truth topic)");
    GroundTruthPosesConfig g;
    g.max_dt_s = config.eval.gt_max_dt_s;
    return make_ground_truth_poses(source.groundtruth(), g);
  }
  throw Error("--poses: unknown value '" + kind + "' (expected slam | gt)");
}

std::string resolve_model_card(const std::string& path) {
  if (fs::is_regular_file(path)) return path;
  if (fs::is_regular_file(path + ".yaml")) return path + ".yaml";  // "models/s3m_pspnet_small"
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
  if (cards.size() == 1) return cards[0];
  if (cards.size() > 1)
    throw Error("segmenter: " + path + " holds several model cards; pass one: onnx:" + cards[0]);
  throw Error("segmenter: no model card in " + path + " (expected a .yaml card with a 'model:' key, see " +
              shipped_file("models/s3m_pspnet_small.yaml") + "); or pass onnx:CARD.yaml with --model-dir " +
              path);
}

std::optional<SE3> simulator_T_c_r(const std::string& dataset_dir) {
  const fs::path file = fs::path(dataset_dir) / "sim.yaml";
  if (dataset_dir.empty() || !fs::is_regular_file(file)) return std::nullopt;
  const YAML::Node n = load_yaml_file(file.string())["T_c_r"];
  const std::string ctx = file.string() + ": T_c_r";
  if (!n || !n["t_m"] || !n["q_xyzw"] || n["t_m"].size() != 3 || n["q_xyzw"].size() != 4)
    throw Error(ctx + ": expected {t_m: [x, y, z], q_xyzw: [qx, qy, qz, qw]} (as s3m sim writes it)");
  try {
    const auto t = n["t_m"].as<std::vector<double>>();
    const auto q = n["q_xyzw"].as<std::vector<double>>();
    return make_se3(Vec3(t[0], t[1], t[2]), Quat(q[3], q[0], q[1], q[2]).normalized());
  } catch (const YAML::Exception& e) {
    throw Error(ctx + ": " + e.what());
  }
}

std::string simulator_sign(const std::string& dataset_dir, bool has_labels) {
  if (!dataset_dir.empty() && fs::exists(fs::path(dataset_dir) / "sim.yaml")) return "sim.yaml";
  return has_labels ? "ground-truth label images" : "";
}

SegmenterChoice choose_segmenter(const SegmenterSpec& spec, const PipelineConfig& config,
                                 const std::string& sim_sign) {
  const SegmenterConfig& sc = config.segmenter;
  SegmenterChoice c{sc.type, sc.model, sc.model_dir, ""};
  switch (spec.kind) {
    case SegmenterSpec::Kind::kFromConfig:
      c.reason =
          "segmenter section of " +
          (config.source.empty() ? "the built-in defaults" : fs::path(config.source).filename().string());
      break;
    case SegmenterSpec::Kind::kNone: return {"none", "", "", "--segmenter none"};
    case SegmenterSpec::Kind::kOracle: return {"oracle", "", "", "--segmenter oracle"};
    case SegmenterSpec::Kind::kOnnx:
      return {"onnx", spec.model, spec.model_dir, "--segmenter onnx:" + spec.model};
  }
  if (!spec.model_dir.empty()) c.model_dir = spec.model_dir;
  if (c.type != "auto") return c;
  if (!sim_sign.empty()) {
    c.type = "oracle";
    c.reason = "simulator sequence (" + sim_sign + "): its ground-truth labels through the noisy oracle";
  } else {
    c.type = "onnx";
    c.model = shipped_file(kRealImageModelCard);
    c.reason = "dataset has no sim.yaml or label images: real-camera default";
  }
  return c;
}

void record_segmenter_choice(PipelineConfig& c, const SegmenterChoice& choice) {
  c.segmenter.type = choice.type;
  c.segmenter.model = choice.model;
  c.segmenter.model_dir = choice.model_dir;
}

std::unique_ptr<semantics::Segmenter> make_segmenter(const SegmenterChoice& choice,
                                                     const PipelineConfig& config, bool dataset_has_labels) {
  const SegmenterConfig& sc = config.segmenter;
  if (choice.type == "none") return nullptr;
  if (choice.type == "oracle") {
    if (!dataset_has_labels)
      throw Error(
          "segmenter oracle: the dataset has no ground-truth label images (labels.txt, as the "
          "simulator writes); use --segmenter onnx:MODEL or --segmenter none");
    return std::make_unique<semantics::OracleSegmenter>(sc.oracle, sc.top_k);
  }
  require(choice.type == "onnx", "segmenter: unknown type '" + choice.type + "'");
  return semantics::OnnxSegmenter::from_card(resolve_model_card(choice.model), choice.model_dir);
}

}  // namespace s3m::pipeline
