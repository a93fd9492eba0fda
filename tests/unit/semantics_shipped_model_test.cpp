// The shipped models (models/s3m_pspnet_small.*, models/deeplabv3plus_mnv2_ade20k_fast.*) load from
// their cards and produce well-formed LabelMaps at camera resolution: what `s3m demo` and `s3m run` on
// a real camera rely on, on a fresh machine.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <set>

#include "s3m/core/error.hpp"
#include "s3m/semantics/onnx_segmenter.hpp"

using namespace s3m;
using namespace s3m::semantics;

TEST(SemanticsShippedModel, LoadsAndProducesWellFormedTopK) {
  auto seg = OnnxSegmenter::from_card(S3M_TEST_DATA_DIR "/../../models/s3m_pspnet_small.yaml");
  EXPECT_EQ(seg->model_classes().size(), std::size_t(cls::kCount));
  EXPECT_EQ(seg->output_size(), cv::Size(20, 16));  // stride 8 of 160x128
  cv::Mat img(480, 640, CV_8UC3);
  cv::randu(img, 0, 255);
  img(cv::Rect(0, 300, 640, 180)).setTo(cv::Scalar(90, 110, 140));
  const LabelMap m = seg->segment(img);
  ASSERT_EQ(m.rows(), 480);
  ASSERT_EQ(m.cols(), 640);
  ASSERT_EQ(m.k(), 3);
  for (int r = 0; r < 480; r += 13)
    for (int c = 0; c < 640; c += 17) {
      const float p0 = m.prob(r, c, 0), p1 = m.prob(r, c, 1), p2 = m.prob(r, c, 2);
      EXPECT_GE(p0, p1);
      EXPECT_GE(p1, p2);
      EXPECT_GT(p2, 0.f);
      EXPECT_LE(p0 + p1 + p2, 1.0f + 1e-5f);
      for (int j = 0; j < 3; ++j) {
        EXPECT_GE(m.id(r, c, j), 1);  // "unknown" is ignored by the card, never predicted
        EXPECT_LE(m.id(r, c, j), cls::kOther);
      }
      EXPECT_NE(m.id(r, c, 0), m.id(r, c, 1));
    }
  // deterministic
  const LabelMap again = seg->segment(img);
  EXPECT_EQ(cv::countNonZero(again.argmax != m.argmax), 0);
}

// The shipped real-image model (models/deeplabv3plus_mnv2_ade20k_fast.*), from the repository alone.
namespace {
const std::string kAdeCard = S3M_TEST_DATA_DIR "/../../models/deeplabv3plus_mnv2_ade20k_fast.yaml";

int model_class(const OnnxSegmenter& seg, const std::string& name) {
  const auto& names = seg.model_classes();
  const auto it = std::find(names.begin(), names.end(), name);
  return it == names.end() ? -1 : int(it - names.begin());
}
}  // namespace

TEST(SemanticsShippedModel, RealImageModelCardLoadsWithItsClassMap) {
  auto seg = OnnxSegmenter::from_card(kAdeCard);
  EXPECT_EQ(seg->name(), "deeplabv3plus_mnv2_ade20k_fast");
  ASSERT_EQ(seg->model_classes().size(), std::size_t(151));  // 'other' + ADE20K's 150
  EXPECT_EQ(seg->model_classes()[0], "other");
  EXPECT_EQ(seg->output_size(), cv::Size(81, 61));  // stride 4 of the 321x241 input, corners aligned
  EXPECT_EQ(seg->top_k(), 3);
  // The kitchen's ADE20K classes land on the project classes (config/classmaps/ade20k.yaml).
  const std::pair<const char*, ClassId> expected[] = {
      {"wall", cls::kWall},       {"floor", cls::kFloor},     {"ceiling", cls::kCeiling},
      {"table", cls::kTable},     {"desk", cls::kTable},      {"kitchen island", cls::kTable},
      {"chair", cls::kChair},     {"armchair", cls::kChair},  {"cabinet", cls::kCabinet},
      {"counter", cls::kCabinet}, {"countertop", cls::kCabinet}, {"windowpane", cls::kWindow},
      {"sky", cls::kOther}};
  for (const auto& [name, id] : expected) {
    const int c = model_class(*seg, name);
    ASSERT_GE(c, 0) << name;
    EXPECT_EQ(seg->class_map()[c], id) << name;
  }
}

TEST(SemanticsShippedModel, RealImageModelGivesCameraSizedTopKOfMappedClasses) {
  auto seg = OnnxSegmenter::from_card(kAdeCard);
  std::set<ClassId> mapped;  // every project class some trained ADE20K class maps to
  for (std::size_t c = 1; c < seg->model_classes().size(); ++c) mapped.insert(seg->class_map()[c]);
  // A uniform colour image: the network sees the same input everywhere, so one label dominates.
  const cv::Mat img(480, 640, CV_8UC3, cv::Scalar(150, 160, 170));
  const LabelMap m = seg->segment(img);
  ASSERT_EQ(m.rows(), 480);
  ASSERT_EQ(m.cols(), 640);
  ASSERT_EQ(m.k(), 3);
  ASSERT_EQ(m.argmax.type(), CV_16UC1);
  std::map<ClassId, int> count;
  for (int r = 0; r < 480; ++r)
    for (int c = 0; c < 640; ++c) {
      ASSERT_EQ(m.argmax.at<ClassId>(r, c), m.id(r, c, 0));
      for (int j = 0; j < 3; ++j) ASSERT_TRUE(mapped.count(m.id(r, c, j))) << m.id(r, c, j) << " at " << r << "," << c;
      ASSERT_GE(m.prob(r, c, 0), m.prob(r, c, 1));
      ASSERT_GE(m.prob(r, c, 1), m.prob(r, c, 2));
      ASSERT_LE(m.prob(r, c, 0) + m.prob(r, c, 1) + m.prob(r, c, 2), 1.0f + 1e-5f);
      ++count[m.id(r, c, 0)];
    }
  EXPECT_FALSE(mapped.count(cls::kUnknown));  // 'other' (index 0) is ignored, never predicted
  int dominant = 0;
  for (const auto& [id, n] : count) dominant = std::max(dominant, n);
  EXPECT_GT(dominant, 480 * 640 / 2) << dominant;
  const LabelMap again = seg->segment(img);
  EXPECT_EQ(cv::countNonZero(again.argmax != m.argmax), 0);
}

TEST(SemanticsShippedModel, TruncatedOrMismatchedRealImageModelIsAClearErrorNamingTheFile) {
  const std::string truncated = (std::filesystem::temp_directory_path() / "s3m_truncated_deeplab.onnx").string();
  ModelCard card = load_model_card(kAdeCard);
  {
    std::ifstream in(card.model_path, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    ASSERT_GT(bytes.size(), std::size_t(9'000'000));
    std::ofstream(truncated, std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  }
  auto error_of = [](const ModelCard& c) -> std::string {
    try {
      OnnxSegmenter seg(c);
    } catch (const Error& e) {
      return e.what();
    }
    return "no error";
  };
  ModelCard cut = card;
  cut.model_path = truncated;
  const std::string e1 = error_of(cut);
  EXPECT_NE(e1.find(truncated + ": not a valid ONNX model (protobuf data is truncated or corrupt)"), std::string::npos) << e1;
  ModelCard narrow = card;  // a card whose input size is not the model's
  narrow.input_width = 320;
  const std::string e2 = error_of(narrow);
  EXPECT_NE(e2.find("input size 241x320 (HxW) does not match the model's input 'input' of shape [1,3,241,321] in " +
                    card.model_path),
            std::string::npos)
      << e2;
  std::filesystem::remove(truncated);
}
