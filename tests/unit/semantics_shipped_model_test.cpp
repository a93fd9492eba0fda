// The shipped model (models/s3m_pspnet_small.*) loads from its card and produces a well-formed
// LabelMap at camera resolution: what `s3m demo` relies on, on a fresh machine.
#include <gtest/gtest.h>

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
