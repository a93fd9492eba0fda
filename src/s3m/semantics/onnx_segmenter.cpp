#include "s3m/semantics/onnx_segmenter.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <new>

#include <opencv2/imgproc.hpp>

#include "s3m/core/error.hpp"
#include "s3m/semantics/onnx_inspect.hpp"
#include "s3m/semantics/resample.hpp"

#include <unistd.h>

namespace s3m::semantics {

namespace {

// One forward pass needs memory in proportion to the input's pixels: the shipped DeepLabV3+
// MobileNetV2 took ~500 bytes per input pixel (peak RSS of a kitchen run with and without it, input
// 321x241). A card whose input would need more than half the machine's memory is refused before
// the pass instead of failing in an allocation after gigabytes.
void check_input_cost(const ModelCard& card) {
  constexpr double kBytesPerPixel = 500;
  const double need_gb = double(card.input_width) * card.input_height * kBytesPerPixel / 1e9;
  const double ram_gb = double(sysconf(_SC_PHYS_PAGES)) * double(sysconf(_SC_PAGE_SIZE)) / 1e9;
  if (ram_gb <= 0 || need_gb <= 0.5 * ram_gb) return;
  char msg[160];
  std::snprintf(msg, sizeof msg,
                "one forward pass needs ~%.1f GB (~500 bytes per input pixel), over half of this "
                "machine's %.1f GB",
                need_gb, ram_gb);
  throw ParseError(
      card.card_path, 0,
      "input " + std::to_string(card.input_width) + "x" + std::to_string(card.input_height) + ": " + msg,
      "an input size the machine can run (the shipped model uses 321x241)");
}

}  // namespace

OnnxSegmenter::OnnxSegmenter(ModelCard card) : card_(std::move(card)) {
  card_.validate();
  const std::string& ctx = card_.card_path;
  if (!std::filesystem::exists(card_.model_path))
    throw Error(ctx + ": model file '" + card_.model_path + "' not found");
  model_classes_ = read_class_names(card_.classes_path);
  map_ = card_.class_map_path.empty() ? ClassMap::by_name(model_classes_)
                                      : ClassMap::load(card_.class_map_path, model_classes_);

  ignored_.assign(model_classes_.size(), false);
  for (const auto& n : card_.ignore_classes) {
    const auto it = std::find(model_classes_.begin(), model_classes_.end(), n);
    if (it == model_classes_.end())
      throw ParseError(ctx, 0, "ignore_classes names '" + n + "', which is not in " + card_.classes_path,
                       "model class names");
    ignored_[it - model_classes_.begin()] = true;
  }
  for (ClassId id = 0; id < map_.target().size(); ++id)
    for (int s : map_.sources_of(id))
      if (!ignored_[s] && id != cls::kUnknown) {
        active_.push_back(id);
        break;
      }
  require(!active_.empty(), ctx + ": every model class is ignored or mapped to 'unknown'");

  check_input_cost(card_);
  const OnnxInputInfo input = read_onnx_input(card_.model_path);  // clear message for corrupt files
  try {
    net_ = cv::dnn::readNetFromONNX(card_.model_path);
  } catch (const cv::Exception& e) {
    throw Error(card_.model_path + ": OpenCV DNN cannot load this ONNX model: " + e.err);
  }
  net_.setPreferableBackend(cv::dnn::DNN_BACKEND_OPENCV);
  net_.setPreferableTarget(cv::dnn::DNN_TARGET_CPU);
  if (card_.threads > 0) cv::setNumThreads(card_.threads);
  check_model(input);
}

std::unique_ptr<OnnxSegmenter> OnnxSegmenter::from_card(const std::string& card_path,
                                                        const std::string& model_dir) {
  return std::make_unique<OnnxSegmenter>(load_model_card(card_path, model_dir));
}

// Load-time checks: declared input shape vs card, then one forward pass on a blank image to learn
// the output grid and compare its channel count with the class list.
void OnnxSegmenter::check_model(const OnnxInputInfo& in) {
  const std::string want = std::to_string(card_.input_height) + "x" + std::to_string(card_.input_width);
  if (in.dims.size() != 4)
    throw Error(card_.model_path + ": input '" + in.name + "' has " + std::to_string(in.dims.size()) +
                " dimensions (expected NCHW, 4)");
  if ((in.dims[1] > 0 && in.dims[1] != 3) || (in.dims[2] > 0 && in.dims[2] != card_.input_height) ||
      (in.dims[3] > 0 && in.dims[3] != card_.input_width))
    throw Error(card_.card_path + ": input size " + want + " (HxW) does not match the model's input '" +
                in.name + "' of shape [" + std::to_string(in.dims[0]) + "," + std::to_string(in.dims[1]) +
                "," + std::to_string(in.dims[2]) + "," + std::to_string(in.dims[3]) + "] in " +
                card_.model_path);
  const cv::Mat blank(card_.input_height, card_.input_width, CV_8UC3, cv::Scalar::all(0));
  Geometry geo;
  const cv::Mat out = forward(preprocess(blank, geo));
  if (out.dims != 4 || out.size[0] != 1)
    throw Error(card_.model_path + ": output must be NCHW [1, C, H, W], got " + std::to_string(out.dims) +
                " dimensions");
  if (out.size[1] != static_cast<int>(model_classes_.size()))
    throw Error(card_.card_path + ": class list " + card_.classes_path + " has " +
                std::to_string(model_classes_.size()) + " classes but the model outputs " +
                std::to_string(out.size[1]) + " channels");
  output_size_ = cv::Size(out.size[3], out.size[2]);
}

cv::Mat OnnxSegmenter::preprocess(const cv::Mat& bgr, Geometry& geo) const {
  const int W = card_.input_width, H = card_.input_height;
  cv::Size fit(W, H);
  if (card_.resize == ModelCard::Resize::kLetterbox) {
    const double s = std::min(double(W) / bgr.cols, double(H) / bgr.rows);
    fit = cv::Size(std::clamp(int(std::lround(bgr.cols * s)), 1, W),
                   std::clamp(int(std::lround(bgr.rows * s)), 1, H));
  }
  geo.scale_x = double(fit.width) / bgr.cols;
  geo.scale_y = double(fit.height) / bgr.rows;
  geo.offset_x = (W - fit.width) / 2;
  geo.offset_y = (H - fit.height) / 2;

  cv::Mat resized, f;
  if (fit == bgr.size())
    resized = bgr;
  else
    cv::resize(bgr, resized, fit, 0, 0, cv::INTER_LINEAR);  // what blobFromImage does
  if (card_.rgb) cv::cvtColor(resized, resized, cv::COLOR_BGR2RGB);
  resized.convertTo(f, CV_32FC3, card_.scale);
  f -= cv::Scalar(card_.mean[0], card_.mean[1], card_.mean[2]);
  cv::multiply(f, cv::Scalar(1.0 / card_.std[0], 1.0 / card_.std[1], 1.0 / card_.std[2]), f);
  if (fit != cv::Size(W, H))  // letterbox: pad with 0 = the mean colour after normalisation
    cv::copyMakeBorder(f, f, int(geo.offset_y), H - fit.height - int(geo.offset_y), int(geo.offset_x),
                       W - fit.width - int(geo.offset_x), cv::BORDER_CONSTANT, cv::Scalar::all(0));
  return cv::dnn::blobFromImage(f);  // HWC -> NCHW, no further scaling or swapping
}

cv::Mat OnnxSegmenter::forward(const cv::Mat& blob) {
  cv::Mat out;
  try {
    net_.setInput(blob);
    out = net_.forward();
  } catch (const cv::Exception& e) {
    throw Error(card_.model_path + ": forward pass failed for input " + std::to_string(card_.input_height) +
                "x" + std::to_string(card_.input_width) + " (HxW from " + card_.card_path + "): " + e.err);
  } catch (const std::bad_alloc&) {
    throw Error(card_.model_path + ": out of memory in a forward pass for input " +
                std::to_string(card_.input_height) + "x" + std::to_string(card_.input_width) + " (HxW from " +
                card_.card_path + "): a smaller input in the card");
  }
  require_finite(out);
  return out;
}

// NaN or infinity in the output would become labels without a class and a map without a label,
// silently: a broken model (or input normalisation) is an error instead.
void OnnxSegmenter::require_finite(const cv::Mat& out) const {
  if (cv::checkRange(out, true)) return;  // an N-d array: no position from OpenCV
  std::string where;
  cv::Point at;
  if (out.dims == 4 && out.isContinuous() && !cv::checkRange(out.reshape(1, 1), true, &at)) {
    const int plane = out.size[2] * out.size[3], i = at.x;
    where = " at channel " + std::to_string(i / plane) + ", row " + std::to_string(i % plane / out.size[3]) +
            ", column " + std::to_string(i % out.size[3]);
  }
  throw Error(card_.model_path + ": the model's output holds NaN or infinity" + where +
              " (check the model, and the input normalisation scale / mean / std in " + card_.card_path +
              ")");
}

std::vector<cv::Mat> OnnxSegmenter::project_probabilities(const cv::Mat& out) const {
  const int C = out.size[1], Ho = out.size[2], Wo = out.size[3];
  auto* data = const_cast<float*>(out.ptr<float>());
  // 1. model-class planes (views into the output blob, modified in place), ignored ones left out
  std::vector<cv::Mat> planes;
  std::vector<int> plane_class;
  for (int c = 0; c < C; ++c)
    if (!ignored_[c]) {
      planes.emplace_back(Ho, Wo, CV_32FC1, data + std::size_t(c) * Ho * Wo);
      plane_class.push_back(c);
    }
  // 2. probabilities over the kept classes
  if (card_.output == ModelCard::Output::kLogits) {
    softmax_planes(planes);
  } else {
    cv::Mat sum(Ho, Wo, CV_32FC1, cv::Scalar(0));
    for (const auto& p : planes) sum += p;
    cv::max(sum, 1e-12, sum);
    for (auto& p : planes) cv::divide(p, sum, p);
  }
  // 3. many-to-one: sum the probabilities of model classes that map to the same project class
  std::vector<cv::Mat> proj(active_.size());
  for (std::size_t a = 0; a < active_.size(); ++a) proj[a] = cv::Mat(Ho, Wo, CV_32FC1, cv::Scalar(0));
  for (std::size_t i = 0; i < planes.size(); ++i) {
    const auto it = std::find(active_.begin(), active_.end(), map_[plane_class[i]]);
    if (it != active_.end()) proj[it - active_.begin()] += planes[i];
  }
  return proj;
}

cv::Mat OnnxSegmenter::camera_to_output(const Geometry& geo) const {
  // camera u -> input x = (u + 0.5) sx - 0.5 + ox -> output grid (half-pixel or align-corners).
  const double Wi = card_.input_width, Hi = card_.input_height, Wo = output_size_.width,
               Ho = output_size_.height;
  double ax, bx, ay, by;
  if (card_.grid == ModelCard::Grid::kAlignCorners) {
    const double kx = Wi > 1 ? (Wo - 1) / (Wi - 1) : 0, ky = Hi > 1 ? (Ho - 1) / (Hi - 1) : 0;
    ax = geo.scale_x * kx, bx = (0.5 * geo.scale_x - 0.5 + geo.offset_x) * kx;
    ay = geo.scale_y * ky, by = (0.5 * geo.scale_y - 0.5 + geo.offset_y) * ky;
  } else {
    const double kx = Wo / Wi, ky = Ho / Hi;
    ax = geo.scale_x * kx, bx = (0.5 * geo.scale_x + geo.offset_x) * kx - 0.5;
    ay = geo.scale_y * ky, by = (0.5 * geo.scale_y + geo.offset_y) * ky - 0.5;
  }
  return (cv::Mat_<double>(2, 3) << ax, 0, bx, 0, ay, by);
}

LabelMap OnnxSegmenter::segment(const cv::Mat& bgr) {
  require(!bgr.empty() && bgr.type() == CV_8UC3,
          "OnnxSegmenter::segment: expected a non-empty CV_8UC3 BGR image");
  // 1. resize / letterbox and normalise into an NCHW blob
  Geometry geo;
  const cv::Mat blob = preprocess(bgr, geo);
  // 2. network forward pass -> [1, C, Ho, Wo]
  const cv::Mat out = forward(blob);
  // 3. softmax over model classes, summed into project classes
  std::vector<cv::Mat> proj = project_probabilities(out);
  // 4. back to the camera image and top-k
  const cv::Mat M = camera_to_output(geo);
  const int k = card_.top_k;
  if (card_.upsample == ModelCard::Upsample::kLinear) {
    const int s = card_.label_stride;
    const double ax = M.at<double>(0, 0), bx = M.at<double>(0, 2), ay = M.at<double>(1, 1),
                 by = M.at<double>(1, 2);
    if (s == 1) return resample_topk(proj, active_, k, bgr.size(), AxisMap{ax, bx, ay, by});
    // coarse pixel u' stands for the centre of camera block [s u', s u' + s): u = s u' + (s - 1) / 2
    const cv::Size coarse((bgr.cols + s - 1) / s, (bgr.rows + s - 1) / s);
    const double c = 0.5 * (s - 1);
    const LabelMap m =
        resample_topk(proj, active_, k, coarse, AxisMap{ax * s, ax * c + bx, ay * s, ay * c + by});
    return upsample_blocks(m, s, bgr.size());
  }
  const LabelMap small = topk_from_planes(proj, active_, k);
  LabelMap full = make_label_map(bgr.rows, bgr.cols, k);
  std::vector<int> xs(bgr.cols);
  for (int u = 0; u < bgr.cols; ++u)
    xs[u] = std::clamp(int(std::lround(M.at<double>(0, 0) * u + M.at<double>(0, 2))), 0, small.cols() - 1);
  for (int v = 0; v < bgr.rows; ++v) {
    const int y =
        std::clamp(int(std::lround(M.at<double>(1, 1) * v + M.at<double>(1, 2))), 0, small.rows() - 1);
    const ClassId* si = small.ids.ptr<ClassId>(y);
    const float* sp = small.probs.ptr<float>(y);
    ClassId* di = full.ids.ptr<ClassId>(v);
    float* dp = full.probs.ptr<float>(v);
    ClassId* da = full.argmax.ptr<ClassId>(v);
    for (int u = 0; u < bgr.cols; ++u) {
      std::copy_n(si + xs[u] * k, k, di + u * k);
      std::copy_n(sp + xs[u] * k, k, dp + u * k);
      da[u] = di[u * k];
    }
  }
  return full;
}

}  // namespace s3m::semantics
