#include "s3m/features/bow_training.hpp"

#include <algorithm>
#include <filesystem>
#include <string>

#include "s3m/core/error.hpp"
#include "s3m/features/bow_vocabulary.hpp"

namespace s3m::features {

namespace fs = std::filesystem;

std::vector<std::string> list_training_images(const std::vector<std::string>& paths, int stride) {
  require(stride >= 1, "list_training_images: stride must be >= 1");
  std::vector<std::string> out;
  for (const std::string& p : paths) {
    std::vector<std::string> files;
    if (fs::is_directory(p)) {
      for (const auto& e : fs::directory_iterator(p)) {
        std::string ext = e.path().extension().string();
        std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
        if (e.is_regular_file() && (ext == ".png" || ext == ".jpg" || ext == ".jpeg")) files.push_back(e.path().string());
      }
      std::sort(files.begin(), files.end());
      if (files.empty()) throw Error("vocabulary training: folder '" + p + "' holds no .png/.jpg images");
    } else if (fs::is_regular_file(p)) {
      files.push_back(p);
    } else {
      throw Error("vocabulary training: '" + p + "' is neither an image file nor a folder");
    }
    for (size_t i = 0; i < files.size(); i += size_t(stride)) out.push_back(files[i]);
  }
  return out;
}

std::vector<cv::Mat> descriptors_from_image_files(const std::vector<std::string>& files, int features_per_image,
                                                  const ImageLoader& load,
                                                  const std::function<void(size_t, size_t)>& progress) {
  std::vector<cv::Mat> out;
  out.reserve(files.size());
  for (size_t i = 0; i < files.size(); ++i) {
    const cv::Mat bgr = load(files[i]);
    require(bgr.type() == CV_8UC3, "vocabulary training: the loader gave '" + files[i] + "' as " +
                                       std::to_string(bgr.channels()) + " channels of depth " +
                                       std::to_string(bgr.depth()) + ", expected 8-bit BGR");
    out.push_back(extract_orb_descriptors(bgr, features_per_image));
    if (progress) progress(i + 1, files.size());
  }
  return out;
}

}  // namespace s3m::features
