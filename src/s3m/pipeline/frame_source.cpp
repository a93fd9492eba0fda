#include "s3m/pipeline/frame_source.hpp"

#include "s3m/io/dataset_reader.hpp"

namespace s3m::pipeline {
namespace {

class DatasetFrameSource final : public FrameSource {
 public:
  explicit DatasetFrameSource(io::Dataset dataset) : dataset_(std::move(dataset)) {}

  std::size_t size() const override { return dataset_.size(); }
  RgbdFrame load(std::size_t index) const override { return dataset_.load(index); }
  const PinholeCamera& camera() const override { return dataset_.camera(); }
  const io::Trajectory& groundtruth() const override { return dataset_.groundtruth(); }
  bool has_labels() const override { return dataset_.has_labels(); }
  std::string name() const override { return dataset_.dir(); }
  std::string eval_dir() const override { return dataset_.dir(); }
  double timestamp(std::size_t index) const override { return dataset_.timestamp(index); }
  std::string layout() const override { return dataset_.layout(); }
  std::string camera_source() const override { return dataset_.camera_source(); }
  std::string depth_registered_by() const override { return dataset_.depth_registered_by(); }
  std::string depth_camera() const override { return dataset_.depth_camera(); }

 private:
  io::Dataset dataset_;
};

}  // namespace

std::unique_ptr<FrameSource> open_tum_source(const std::string& dir, const DatasetConfig& config) {
  io::DatasetOptions options;
  options.max_dt_s = config.max_dt_s;
  options.camera = config.camera;
  return tum_source(io::open_dataset(dir, options));
}

std::unique_ptr<FrameSource> tum_source(io::Dataset dataset) {
  return std::make_unique<DatasetFrameSource>(std::move(dataset));
}

}  // namespace s3m::pipeline
