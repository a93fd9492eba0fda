// Runs the tiny committed test models (tools/seg_make_test_model.py) through OnnxSegmenter.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include <unistd.h>

#include "s3m/core/error.hpp"
#include "s3m/semantics/onnx_inspect.hpp"
#include "s3m/semantics/onnx_segmenter.hpp"

using namespace s3m;
using namespace s3m::semantics;
namespace fs = std::filesystem;

namespace {
const std::string kData = S3M_TEST_DATA_DIR "/semantics/";

// Card text for the tiny model with absolute paths, so it can live in a temp folder.
std::string card_text(const std::string& model = kData + "tiny_rgb.onnx", int w = 16, int h = 16,
                      const std::string& extra = "") {
  return "name: t\nmodel: " + model + "\nclasses: " + kData + "tiny_rgb.classes.txt\n" +
         "input: {width: " + std::to_string(w) + ", height: " + std::to_string(h) +
         ", channel_order: rgb, scale: 0.00392156862745098}\n" + extra;
}
std::string write_card(const std::string& name, const std::string& text) {
  const auto path = (fs::temp_directory_path() / ("s3m_card_" + name + ".yaml")).string();
  std::ofstream(path) << text;
  return path;
}
// 32x24 BGR image: left half red, right half blue, bottom-left 8x8 corner black.
cv::Mat test_image() {
  cv::Mat img(24, 32, CV_8UC3, cv::Scalar(0, 0, 255));
  img(cv::Rect(16, 0, 16, 24)).setTo(cv::Scalar(255, 0, 0));
  img(cv::Rect(0, 16, 8, 8)).setTo(cv::Scalar(0, 0, 0));
  return img;
}
double softmax0(double a, double b, double c, double d) {
  return std::exp(a) / (std::exp(a) + std::exp(b) + std::exp(c) + std::exp(d));
}
}  // namespace

TEST(SemanticsOnnx, CommittedCardRunsAndGivesExactProbabilities) {
  auto seg = OnnxSegmenter::from_card(kData + "tiny_rgb.yaml");
  EXPECT_EQ(seg->output_size(), cv::Size(16, 16));
  // A uniform image avoids resampling effects: pure red -> logits (10, 0, 0, 2).
  const LabelMap m = seg->segment(cv::Mat(16, 16, CV_8UC3, cv::Scalar(0, 0, 255)));
  ASSERT_EQ(m.k(), 3);
  EXPECT_EQ(m.id(5, 5, 0), cls::kWall);
  EXPECT_EQ(m.id(5, 5, 1), cls::kOther);  // "spaceship" (logit 2) is not a project class -> other
  EXPECT_NEAR(m.prob(5, 5, 0), softmax0(10, 0, 0, 2), 1e-5);
  EXPECT_NEAR(m.prob(5, 5, 1), softmax0(2, 10, 0, 0), 1e-5);
  EXPECT_NEAR(m.prob(5, 5, 2), softmax0(0, 10, 0, 2), 1e-5);
}

TEST(SemanticsOnnx, ArgmaxOnSyntheticImageAtCameraSize) {
  for (const char* model : {"tiny_rgb.onnx", "tiny_rgb_s2.onnx"})
    for (const char* up : {"nearest", "linear", "linear\nlabel_stride: 2"}) {
      SCOPED_TRACE(std::string(model) + " " + up);
      // 32x24 camera image stretched to the 16x16 input; the strided model outputs 8x8.
      OnnxSegmenter seg(load_model_card(
          write_card("argmax", card_text(kData + model, 16, 16, std::string("upsample: ") + up + "\n"))));
      const LabelMap m = seg.segment(test_image());
      ASSERT_EQ(m.rows(), 24);
      ASSERT_EQ(m.cols(), 32);
      EXPECT_EQ(m.argmax.at<ClassId>(4, 4), cls::kWall);    // red
      EXPECT_EQ(m.argmax.at<ClassId>(4, 28), cls::kChair);  // blue
      EXPECT_EQ(m.argmax.at<ClassId>(22, 2), cls::kOther);  // black -> spaceship -> other
      EXPECT_EQ(m.argmax.at<ClassId>(20, 26), cls::kChair);
      // all pixels far from the colour edges are right
      int wrong = 0;
      for (int r = 0; r < 12; ++r)
        for (int c = 0; c < 32; ++c)
          if (std::abs(c - 16) > 4)
            wrong += m.argmax.at<ClassId>(r, c) != (c < 16 ? cls::kWall : cls::kChair);
      EXPECT_EQ(wrong, 0);
    }
}

TEST(SemanticsOnnx, LetterboxKeepsGeometry) {
  // 32x16 image letterboxed into 16x16: occupies input rows 4..11; labels must come back in place.
  const std::string card = "name: t\nmodel: " + kData + "tiny_rgb.onnx\nclasses: " + kData +
                           "tiny_rgb.classes.txt\ninput: {width: 16, height: 16, scale: 0.00392156862745098, "
                           "resize: letterbox}\nupsample: nearest\n";
  OnnxSegmenter seg(load_model_card(write_card("letterbox", card)));
  cv::Mat img(16, 32, CV_8UC3, cv::Scalar(0, 255, 0));      // green = floor
  img(cv::Rect(0, 0, 32, 4)).setTo(cv::Scalar(0, 0, 255));  // top band red = wall
  const LabelMap m = seg.segment(img);
  EXPECT_EQ(m.argmax.at<ClassId>(0, 10), cls::kWall);
  EXPECT_EQ(m.argmax.at<ClassId>(2, 20), cls::kWall);
  EXPECT_EQ(m.argmax.at<ClassId>(10, 10), cls::kFloor);
  EXPECT_EQ(m.argmax.at<ClassId>(15, 31), cls::kFloor);
}

TEST(SemanticsOnnx, ReadsDeclaredInputShape) {
  const OnnxInputInfo in = read_onnx_input(kData + "tiny_rgb_s2.onnx");
  EXPECT_EQ(in.name, "input");
  EXPECT_EQ(in.dims, (std::vector<std::int64_t>{1, 3, 16, 16}));
}

TEST(SemanticsOnnx, BadCardsAndModelsFailAtLoadWithClearMessages) {
  auto expect_error = [](const std::string& card, const std::string& needle) {
    try {
      OnnxSegmenter seg(load_model_card(write_card("bad", card)));
      FAIL() << "no error for card:\n" << card;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  expect_error(card_text("/nonexistent/model.onnx"), "model file '/nonexistent/model.onnx' not found");
  const auto corrupt = (fs::temp_directory_path() / "s3m_corrupt.onnx").string();
  std::ofstream(corrupt) << "this is not a protobuf \xff\xff\xff\xff\xff\xff\xff\xff\xff\xff\xff";
  expect_error(card_text(corrupt), "not a valid ONNX model");
  expect_error(card_text(kData + "tiny_rgb.onnx", 20, 16),
               "input size 16x20 (HxW) does not match the model's input 'input' of shape [1,3,16,16]");
  // an output that is not NCHW (tiny_flat.onnx: [1,4,256])
  expect_error(card_text(kData + "tiny_flat.onnx"),
               kData + "tiny_flat.onnx: output must be NCHW [1, C, H, W], got 3 dimensions");
  // class list with 3 names for a 4-channel model
  const auto names3 = (fs::temp_directory_path() / "s3m_names3.txt").string();
  std::ofstream(names3) << "wall\nfloor\nchair\n";
  expect_error("model: " + kData + "tiny_rgb.onnx\nclasses: " + names3 + "\ninput: {width: 16, height: 16}\n",
               "has 3 classes but the model outputs 4 channels");
  expect_error(card_text() + "top_k: 0\n", "top_k = 0 out of range");
  expect_error(card_text() + "output: {type: softmax}\n", "bad value 'softmax' for 'type'");
  expect_error(card_text() + "ignore_classes: [sky]\n", "ignore_classes names 'sky'");
  expect_error(card_text() + "modle: x.onnx\n", "unknown key 'modle'");
  expect_error(card_text() + "output: {type: {a: 1}}\n", "bad model card entry");
  expect_error(card_text(kData + "tiny_rgb.onnx", 100000, 16), "input size missing or out of range");
  expect_error("classes: x.txt\ninput: {width: 16, height: 16}\n", "no 'model' given");
}

TEST(SemanticsOnnx, AnInputTooLargeForTheMachineIsRefusedBeforeTheForwardPass) {
  // 8192x8192 at ~500 bytes per input pixel: ~33.6 GB for one pass.
  const double ram_gb = double(sysconf(_SC_PHYS_PAGES)) * double(sysconf(_SC_PAGE_SIZE)) / 1e9;
  if (ram_gb >= 2 * 33.6)
    GTEST_SKIP() << "this machine has " << ram_gb << " GB: 8192x8192 fits in half of it";
  try {
    OnnxSegmenter seg(load_model_card(write_card("huge", card_text(kData + "tiny_rgb.onnx", 8192, 8192))));
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("input 8192x8192: one forward pass needs ~33.6 GB (~500 bytes per "
                                         "input pixel), over half of this machine's"),
              std::string::npos)
        << e.what();
  }
}

TEST(SemanticsOnnx, NonFiniteCardValuesAreRefusedAtLoad) {
  auto card = [](const std::string& input_extra) {
    return "name: t\nmodel: " + kData + "tiny_rgb.onnx\nclasses: " + kData +
           "tiny_rgb.classes.txt\ninput: {width: 16, height: 16, " + input_extra + "}\n";
  };
  auto expect_refused = [&](const std::string& extra, const std::string& needle) {
    try {
      load_model_card(write_card("nonfinite", card(extra)));
      FAIL() << "a card with " << extra << " loaded";
    } catch (const ParseError& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  expect_refused("scale: .inf", "input.scale must be positive and finite");
  expect_refused("scale: .nan", "input.scale must be positive and finite");
  expect_refused("mean: .nan", "input.mean entries must be finite");
  expect_refused("mean: [0, -.inf, 0]", "input.mean entries must be finite");
  expect_refused("std: [1, 1, .inf]", "input.std entries must be positive and finite");
  EXPECT_NO_THROW(load_model_card(write_card("finite", card("scale: 0.5, mean: [0.1, 0.2, 0.3], std: 2"))));
}

TEST(SemanticsOnnx, OutputThatIsNotFiniteIsAnErrorNamingTheModel) {
  // A std of 1e-300 is a valid number, but it blows every non-black pixel up to infinity in
  // float: the blank load-time image still passes, the first real image must not.
  OnnxSegmenter seg(load_model_card(write_card("finite_std", card_text())));
  const cv::Mat red(16, 16, CV_8UC3, cv::Scalar(0, 0, 255));
  EXPECT_NO_THROW(seg.segment(red));
  const std::string text = "name: t\nmodel: " + kData + "tiny_rgb.onnx\nclasses: " + kData +
                           "tiny_rgb.classes.txt\ninput: {width: 16, height: 16, std: 1e-300}\n";
  OnnxSegmenter broken(load_model_card(write_card("tinystd", text)));
  try {
    broken.segment(red);
    FAIL() << "an output of infinities was turned into labels";
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(kData + "tiny_rgb.onnx: the model's output holds NaN or infinity at channel "),
              std::string::npos)
        << what;
    EXPECT_NE(what.find("s3m_card_tinystd.yaml"), std::string::npos) << what;
  }
}

TEST(SemanticsOnnx, CardTopKAboveWhatAVoxelKeepsIsRefusedAtLoad) {
  // One limit (kMaxTopK = 5): a card asking for 8 labels per pixel used to load and then fail at
  // the first map insert.
  try {
    load_model_card(write_card("topk8", card_text() + "top_k: 8\n"));
    FAIL() << "a card with top_k 8 loaded";
  } catch (const ParseError& e) {
    EXPECT_NE(std::string(e.what()).find("top_k = 8 out of range"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("1..5"), std::string::npos) << e.what();
  }
  EXPECT_EQ(load_model_card(write_card("topk5", card_text() + "top_k: 5\n")).top_k, kMaxTopK);
}
