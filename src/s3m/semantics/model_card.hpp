#pragma once
// The YAML model card that describes an ONNX segmentation model to OnnxSegmenter. It lives next to
// the model; relative paths are resolved against the card's folder (or an explicit model folder).
//
//   name: s3m_pspnet_small
//   model: s3m_pspnet_small.onnx        # ONNX file
//   classes: s3m_pspnet_small.classes.txt   # model class names, index = output channel
//   class_map: ../config/classmaps/ade20k.yaml   # optional; absent = map classes by name
//   ignore_classes: [unknown]           # output channels left out of the softmax (untrained)
//   input:
//     width: 160                        # network input size [px]
//     height: 128
//     channel_order: rgb                # rgb | bgr: order the network expects
//     scale: 0.00392156862745098        # x = (pixel * scale - mean[c]) / std[c], c in network order
//     mean: [0.485, 0.456, 0.406]
//     std: [0.229, 0.224, 0.225]
//     resize: stretch                   # stretch (plain resize) | letterbox (keep aspect, pad 0)
//   output:
//     layout: nchw                      # only NCHW [1, C, H, W] is supported
//     type: logits                      # logits | probabilities
//     grid: half_pixel                  # how a smaller output grid sits on the input:
//                                       # half_pixel (like cv::resize) | align_corners
//   upsample: linear                    # linear: class probabilities bilinearly resampled, then top-k;
//                                       # nearest: top-k at network resolution, then nearest (faster)
//   label_stride: 1                     # linear only: interpolate + rank at every s-th pixel, then copy
//                                       # each result into its s x s block (s = 2: ~4x cheaper; the
//                                       # network's own grid is 8-32 camera pixels, so no visible loss)
//   top_k: 3
//   threads: 0                          # cv::setNumThreads (process-wide!); 0 = leave as is, else
//                                       # 1..4 x the hardware threads (core/thread_count.hpp)
#include <array>
#include <string>
#include <vector>

namespace s3m::semantics {

struct ModelCard {
  enum class Resize { kStretch, kLetterbox };
  enum class Output { kLogits, kProbabilities };
  enum class Grid { kHalfPixel, kAlignCorners };
  enum class Upsample { kLinear, kNearest };

  std::string card_path;       // where the card came from (for messages)
  std::string name;
  std::string model_path;      // resolved
  std::string classes_path;    // resolved
  std::string class_map_path;  // resolved; empty = map by name
  std::vector<std::string> ignore_classes;
  int input_width = 0, input_height = 0;  // [px]
  bool rgb = true;
  double scale = 1.0 / 255.0;
  std::array<double, 3> mean{0, 0, 0}, std{1, 1, 1};
  Resize resize = Resize::kStretch;
  Output output = Output::kLogits;
  Grid grid = Grid::kHalfPixel;
  Upsample upsample = Upsample::kLinear;
  int label_stride = 1;  // [px]
  int top_k = 3;
  int threads = 0;

  void validate() const;  // throws ParseError naming the card
};

// Reads and validates a card. model_dir, when non-empty, replaces the card's folder as the base of
// the relative `model` and `classes` paths (for cards kept in the repo describing downloaded models).
ModelCard load_model_card(const std::string& card_path, const std::string& model_dir = "");

}  // namespace s3m::semantics
