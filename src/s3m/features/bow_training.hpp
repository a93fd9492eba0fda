#pragma once
// Training input for `s3m vocab`: image paths (files or folders) -> ORB descriptors per image.
#include <functional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace s3m::features {

// Expands folders to their .png/.jpg/.jpeg files (sorted by name) and keeps every `stride`-th
// image of each argument. Throws s3m::Error for a path that doesn't exist or a folder with no images.
std::vector<std::string> list_training_images(const std::vector<std::string>& paths, int stride = 1);

// Reads each image with `load` and extracts `features_per_image` ORB descriptors. `load` is the
// caller's checked reader returning 8-bit BGR (io::read_rgb: it throws naming the file for a
// missing, undecodable or 16-bit image; this module does not depend on io); anything else it
// returns is an s3m::Error. progress(i, n) after each image.
using ImageLoader = std::function<cv::Mat(const std::string& path)>;
std::vector<cv::Mat> descriptors_from_image_files(const std::vector<std::string>& files, int features_per_image,
                                                  const ImageLoader& load,
                                                  const std::function<void(size_t, size_t)>& progress = {});

}  // namespace s3m::features
