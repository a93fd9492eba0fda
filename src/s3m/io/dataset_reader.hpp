#pragma once
// One reader per dataset folder layout, behind one interface. open_dataset() asks them in order
// which layout a folder is, and the first that recognises it reads it into an io::Dataset.
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "s3m/io/camera_yaml.hpp"
#include "s3m/io/dataset.hpp"

namespace s3m::io {

class DatasetReader {
 public:
  virtual ~DatasetReader() = default;
  virtual std::string name() const = 0;  // "TUM", "ETH3D", "7-Scenes", "ScanNet", "Replica"
  // Why dir is of this layout ("rgb.txt", "color/ and depth/", ...); "" when it is not.
  virtual std::string detect(const std::string& dir) const = 0;
  // What a folder of this layout holds, for the error when no reader recognises a folder; "" for a
  // variant that another reader's text covers.
  virtual std::string expected() const = 0;
  // Reads a folder detect() recognised. Throws ParseError naming the file (and line) on a problem.
  virtual Dataset read(const std::string& dir, const DatasetOptions& options) const = 0;
};

// The readers in the order open_dataset() asks them (TUM, ETH3D, 7-Scenes, ScanNet, Replica).
const std::vector<std::unique_ptr<const DatasetReader>>& dataset_readers();

struct DetectedLayout {
  const DatasetReader* reader = nullptr;  // nullptr: no reader recognises the folder
  std::string reason;                     // what it recognised the folder by
};
DetectedLayout detect_layout(const std::string& dir);

// The reader of dir's layout reads it. Throws ParseError when dir is no directory, or when no
// reader recognises it (saying what each layout would hold).
Dataset open_dataset(const std::string& dir, const DatasetOptions& options = {});

// The TUM and ETH3D readers (tum_reader.cpp); the numbered-folder layouts' reader is
// make_folder_reader() (frame_folders.hpp).
std::unique_ptr<const DatasetReader> make_tum_reader();
std::unique_ptr<const DatasetReader> make_eth3d_reader();

// What the readers share.
// The camera file of options.camera, else <dir>/camera.yaml, else ETH3D's calibration.txt, else a
// TUM preset from 'freiburg1/2/3' in the folder name, else ParseError; with where it came from (for
// Dataset::camera_source()).
std::pair<CameraFile, std::string> dataset_camera(const std::string& dir, const DatasetOptions& options);
// After parts.frames and parts.camera are known: checks the first depth image has the depth
// camera's size and sets parts.to_colour and parts.registered_by.
void use_depth_camera(Dataset::Parts& parts, const DepthCamera& depth);

}  // namespace s3m::io
