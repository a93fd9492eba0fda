#include "s3m/pipeline/frame_source.hpp"

#include "s3m/io/tum_dataset.hpp"

namespace s3m::pipeline {
namespace {

class TumFrameSource final : public FrameSource {
 public:
  explicit TumFrameSource(io::TumDataset dataset) : dataset_(std::move(dataset)) {}

  std::optional<RgbdFrame> next() override {
    if (next_ >= dataset_.size()) return std::nullopt;
    return dataset_.load(next_++);
  }
  std::size_t size_hint() const override { return dataset_.size(); }
  const PinholeCamera& camera() const override { return dataset_.camera(); }
  const io::Trajectory& groundtruth() const override { return dataset_.groundtruth(); }
  bool has_labels() const override { return dataset_.has_labels(); }
  std::string name() const override { return dataset_.dir(); }
  std::string eval_dir() const override { return dataset_.dir(); }

 private:
  io::TumDataset dataset_;
  std::size_t next_ = 0;
};

}  // namespace

std::unique_ptr<FrameSource> open_tum_source(const std::string& dir, const DatasetConfig& config) {
  io::TumDatasetOptions options;
  options.max_dt_s = config.max_dt_s;
  options.camera = config.camera;
  return std::make_unique<TumFrameSource>(io::TumDataset::open(dir, options));
}

}  // namespace s3m::pipeline
