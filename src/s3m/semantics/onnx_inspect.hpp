#pragma once
// Just enough ONNX protobuf reading to check a model against its card before running it: the
// declared shape of the graph's first real input. OpenCV DNN 4.6 has no API for this, and an input
// of the wrong size otherwise surfaces as an obscure error (or silently wrong output) at run time.
#include <cstdint>
#include <string>
#include <vector>

namespace s3m::semantics {

struct OnnxInputInfo {
  std::string name;
  // One entry per dimension; -1 where the model leaves it symbolic/unknown (e.g. a batch "N").
  std::vector<std::int64_t> dims;
};

// Throws s3m::Error naming the file when it is missing or not a readable ONNX model.
OnnxInputInfo read_onnx_input(const std::string& onnx_path);

}  // namespace s3m::semantics
