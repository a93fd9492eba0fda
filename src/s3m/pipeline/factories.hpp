#pragma once
// Building the pipeline's components from a preset and the command line, with messages that say
// what is missing and what to pass instead.
#include <memory>
#include <optional>
#include <string>

#include "s3m/core/se3.hpp"
#include "s3m/pipeline/frame_source.hpp"
#include "s3m/pipeline/map_integrator.hpp"
#include "s3m/pipeline/pipeline_config.hpp"
#include "s3m/pipeline/pose_source.hpp"
#include "s3m/semantics/segmenter.hpp"

namespace s3m::features {
class Vocabulary;
}

namespace s3m::pipeline {

// Parses "onnx:PATH" / "oracle" / "none" (throws Error listing the accepted forms).
struct SegmenterSpec {
  enum class Kind { kFromConfig, kOnnx, kOracle, kNone } kind = Kind::kFromConfig;
  std::string model;      // onnx: model card file or directory holding one
  std::string model_dir;  // onnx: folder with the model files (when the card lives elsewhere)
};
SegmenterSpec parse_segmenter_spec(const std::string& spec);

// "slam" (the SLAM system of s3m::slam) or "gt" (the dataset's ground truth).
std::unique_ptr<PoseSource> make_pose_source(const std::string& kind, const FrameSource& source,
                                             const PinholeCamera& camera, const PipelineConfig& config);

// The SLAM system as a PoseSource (slam_pose_source.cpp), with loop closing and relocalisation as
// config.slam.loop_closing asks (then the vocabulary is loaded first). threads.deterministic takes
// precedence over slam.threaded (logged when it overrides it).
std::unique_ptr<PoseSource> make_slam_poses(const PinholeCamera& camera, const PipelineConfig& config);

// The vocabulary config.vocabulary names (or the shipped one); throws s3m::Error naming the file
// when it is missing or not a valid vocabulary.
std::shared_ptr<const features::Vocabulary> load_vocabulary(const slam::LoopClosingConfig& config);

// The shipped real-image model (repository-relative): the segmenter of real-camera presets and of
// segmenter type `auto` on anything that is not a simulator sequence.
inline constexpr const char* kRealImageModelCard = "models/deeplabv3plus_mnv2_ade20k_fast.yaml";

// Which segmenter a run uses and why, in words for the log, metrics.json and the report.
struct SegmenterChoice {
  std::string type;       // onnx | oracle | none (never auto)
  std::string model;      // onnx: model card or folder holding one
  std::string model_dir;  // onnx: folder with the model files ("" = the card's)
  std::string reason;     // e.g. "segmenter section of kitchen_7scenes.yaml"
};
// What marks a source as simulator output: "sim.yaml" (dataset_dir holds the file `s3m sim` writes),
// "ground-truth label images" (has_labels: a TUM labels.txt, a bag's or the node's label topic), or
// "" for a real camera. dataset_dir is "" for a bag or a live stream.
std::string simulator_sign(const std::string& dataset_dir, bool has_labels);

// The robot-to-camera calibration T_c_r (`T_c_r: {t_m, q_xyzw}`) of the sim.yaml `s3m sim` writes
// into dataset_dir, or nothing when there is no such file. Throws with the file's name when it is
// there but has no readable T_c_r.
std::optional<SE3> simulator_T_c_r(const std::string& dataset_dir);

// `spec` (the command line) wins over the config's segmenter section. Type `auto` (the built-in
// default) becomes the oracle on a simulator sequence and the shipped real-image model on everything
// else. sim_sign: simulator_sign() of the source ("" = a real camera).
SegmenterChoice choose_segmenter(const SegmenterSpec& spec, const PipelineConfig& config,
                                 const std::string& sim_sign);

// Writes the choice into c.segmenter (type, model, model_dir), so the effective config says which
// segmenter ran and a rerun with it makes the same choice.
void record_segmenter_choice(PipelineConfig& c, const SegmenterChoice& choice);

// nullptr for "none". The oracle needs the dataset's label images (simulator output).
std::unique_ptr<semantics::Segmenter> make_segmenter(const SegmenterChoice& choice,
                                                     const PipelineConfig& config, bool dataset_has_labels);

// Finds the model card for `onnx:PATH`: PATH itself when it is a .yaml file (or PATH.yaml), or the single
// card (*.yaml with a `model:` key) inside the folder PATH.
std::string resolve_model_card(const std::string& path);

}  // namespace s3m::pipeline
