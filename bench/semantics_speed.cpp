// Segmentation speed: OnnxSegmenter::segment() per model card (whole call: resize, normalise,
// forward, softmax, class mapping, upsampling to the camera image, top-k), plus the post-processing
// steps alone.
//
//   S3M_SEG_CARDS="models/s3m_pspnet_small.yaml;models/deeplabv3plus_mnv2_ade20k_fast.yaml"
//   S3M_SEG_IMAGE=/work/shared/data/7scenes_redkitchen_0000-0499/rgb/<frame>.png
//   build/bench/bench_semantics_speed --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
// Cards are ';'-separated, each optionally "@model_dir". Without S3M_SEG_IMAGE a 640x480 noise image
// is used. S3M_SEG_THREADS sets cv::setNumThreads (default: OpenCV's, i.e. all cores).
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <random>
#include <sstream>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "s3m/semantics/onnx_segmenter.hpp"
#include "s3m/semantics/resample.hpp"

using namespace s3m;
using namespace s3m::semantics;

namespace {

cv::Mat bench_image() {
  if (const char* p = std::getenv("S3M_SEG_IMAGE")) {
    cv::Mat img = cv::imread(p, cv::IMREAD_COLOR);
    if (!img.empty()) return img;
  }
  cv::Mat img(480, 640, CV_8UC3);
  cv::randu(img, 0, 255);
  return img;
}

void BM_Segment(benchmark::State& state, std::string card, std::string model_dir) {
  std::unique_ptr<OnnxSegmenter> seg;
  try {
    seg = OnnxSegmenter::from_card(card, model_dir);
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
    return;
  }
  const cv::Mat img = bench_image();
  seg->segment(img);  // warm-up
  for (auto _ : state) benchmark::DoNotOptimize(seg->segment(img));
  state.SetLabel(std::to_string(seg->card().input_width) + "x" + std::to_string(seg->card().input_height) + " -> " +
                 std::to_string(img.cols) + "x" + std::to_string(img.rows));
}

// The network forward pass alone (OpenCV DNN, the card's model and input size, a blank blob): what
// segment() costs beyond it is pre- and post-processing.
void BM_Forward(benchmark::State& state, std::string card_path, std::string model_dir) {
  ModelCard card;
  cv::dnn::Net net;
  try {
    card = load_model_card(card_path, model_dir);
    net = cv::dnn::readNetFromONNX(card.model_path);
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
    return;
  }
  const int shape[] = {1, 3, card.input_height, card.input_width};
  const cv::Mat blob(4, shape, CV_32F, cv::Scalar(0));
  net.setInput(blob);
  net.forward();  // warm-up
  for (auto _ : state) {
    net.setInput(blob);
    benchmark::DoNotOptimize(net.forward());
  }
}

std::vector<cv::Mat> random_planes(int n, cv::Size size) {
  std::vector<cv::Mat> planes(n);
  for (auto& p : planes) {
    p.create(size, CV_32FC1);
    cv::randu(p, 0.f, 1.f);
  }
  return planes;
}

void BM_TopK3_16Classes_640x480(benchmark::State& state) {
  const auto planes = random_planes(15, {640, 480});
  std::vector<ClassId> ids(15);
  for (int i = 0; i < 15; ++i) ids[i] = ClassId(i + 1);
  for (auto _ : state) benchmark::DoNotOptimize(topk_from_planes(planes, ids, 3));
}
BENCHMARK(BM_TopK3_16Classes_640x480)->Unit(benchmark::kMillisecond);

void BM_Softmax_151Classes_81x61(benchmark::State& state) {
  const auto planes = random_planes(151, {81, 61});
  for (auto _ : state) {
    auto p = planes;  // shallow: softmax works in place on shared data, values stay bounded
    softmax_planes(p);
  }
}
BENCHMARK(BM_Softmax_151Classes_81x61)->Unit(benchmark::kMillisecond);

}  // namespace

int main(int argc, char** argv) {
  if (const char* t = std::getenv("S3M_SEG_THREADS")) cv::setNumThreads(std::atoi(t));
  std::string cards = "models/s3m_pspnet_small.yaml";
  if (const char* c = std::getenv("S3M_SEG_CARDS")) cards = c;
  std::stringstream ss(cards);
  std::string item;
  while (std::getline(ss, item, ';')) {
    if (item.empty()) continue;
    const auto at = item.find('@');
    const std::string card = item.substr(0, at), dir = at == std::string::npos ? "" : item.substr(at + 1);
    benchmark::RegisterBenchmark(("BM_Segment/" + card).c_str(), BM_Segment, card, dir)->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("BM_Forward/" + card).c_str(), BM_Forward, card, dir)->Unit(benchmark::kMillisecond);
  }
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}

namespace {
void BM_Upsample15_WarpAffine(benchmark::State& state) {
  const auto planes = random_planes(15, {32, 24});
  const cv::Mat M = (cv::Mat_<double>(2, 3) << 0.05, 0, -0.475, 0, 0.05, -0.475);
  cv::Mat out;
  for (auto _ : state)
    for (const auto& p : planes) cv::warpAffine(p, out, M, {640, 480}, cv::INTER_LINEAR | cv::WARP_INVERSE_MAP, cv::BORDER_REPLICATE);
}
BENCHMARK(BM_Upsample15_WarpAffine)->Unit(benchmark::kMillisecond);
void BM_Upsample15_Resize(benchmark::State& state) {
  const auto planes = random_planes(15, {32, 24});
  cv::Mat out;
  for (auto _ : state)
    for (const auto& p : planes) cv::resize(p, out, {640, 480}, 0, 0, cv::INTER_LINEAR);
}
BENCHMARK(BM_Upsample15_Resize)->Unit(benchmark::kMillisecond);
}  // namespace

namespace {
void BM_ResampleTopK3_15Classes_32x24_to_640x480(benchmark::State& state) {
  // Smooth class blobs like a network's output, so most pixels are in label interiors.
  std::vector<cv::Mat> planes = random_planes(15, {32, 24});
  for (int i = 0; i < 15; ++i)
    for (int y = 0; y < 24; ++y)
      for (int x = 0; x < 32; ++x) planes[i].at<float>(y, x) = 0.2f * planes[i].at<float>(y, x) + ((x / 6 + 3 * (y / 6)) % 15 == i);
  std::vector<ClassId> ids(15);
  for (int i = 0; i < 15; ++i) ids[i] = ClassId(i + 1);
  for (auto _ : state)
    benchmark::DoNotOptimize(resample_topk(planes, ids, 3, {640, 480}, AxisMap{0.05, -0.475, 0.05, -0.475}));
}
BENCHMARK(BM_ResampleTopK3_15Classes_32x24_to_640x480)->Unit(benchmark::kMillisecond);
}  // namespace
