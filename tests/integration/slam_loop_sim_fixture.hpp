#pragma once
// The loop-closing end-to-end tests' sequence: the simulator's `loop` flight (office, seed 3,
// 640x480, 30 Hz) that passes over its start again, written once in TUM layout as `s3m sim` does
// (cached in the temp folder across test processes), and an outage variant: frames
// kBlankFirst..+9 arrive blank and the next kSkipped frames never arrive, so when images come back
// the camera is 1 s (about 40 deg of the circuit) further on, over ground mapped on the first lap.
// At 30 Hz ten blank frames alone are bridged by the tracker's own reference-keyframe search;
// the gap makes relocalisation necessary.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <opencv2/imgcodecs.hpp>
#include <unistd.h>

#include "s3m/io/tum_dataset.hpp"
#include "s3m/sim/simulate.hpp"

#include "cached_folder.hpp"

namespace s3m::it {

inline constexpr int kLoopFrames = 300;  // the whole shape: 1.15 turns (fewer frames cut it short)
inline constexpr int kBlankFirst = 250;  // frames 250..259 blank: the camera is back over the start
inline constexpr int kSkipped = 20;      // frames 260..279 are never delivered
inline constexpr int kResumeSource = kBlankFirst + 10 + kSkipped;  // first frame after the outage
inline constexpr double kMaxAteWithOutage_m = 0.08;

inline sim::SimConfig loop_config() {
  sim::SimConfig c;
  c.scene = "office";
  c.seed = 3;
  c.trajectory.type = "loop";
  c.trajectory.frames = kLoopFrames;
  return c;
}

inline const sim::Simulation& loop_simulation() {
  static const sim::Simulation sim(loop_config());
  return sim;
}

// Source frame indices of the outage variant, in delivery order.
inline bool delivered_in_outage(int source) { return source < kBlankFirst + 10 || source >= kResumeSource; }

enum class Variant {
  kClean,
  kOutage,  // frames kBlankFirst..+9 with a black colour image (depth kept, so mapping them with a
            // stale pose would show in the map), then kSkipped frames missing
  kGap,     // the same frames missing altogether: what the map must equal when LOST frames are skipped
};

inline std::string loop_sequence_dir(Variant variant) {
  namespace fs = std::filesystem;
  const fs::path clean = fs::temp_directory_path() / "s3m_it_loop_office_seed3";
  const fs::path d = variant == Variant::kClean ? clean
                     : fs::path(clean.string() + (variant == Variant::kGap ? "_gap" : "_outage") +
                                std::to_string(kBlankFirst));
  return cached_folder(d, "gt_voxels.txt", [variant](const fs::path& tmp) {
    if (variant == Variant::kClean) {
      sim::simulate_sequence(loop_config(), tmp.string());
      return;
    }
    fs::copy(loop_sequence_dir(Variant::kClean), tmp, fs::copy_options::recursive);
    // associations.txt: "t_rgb rgb/x.png t_depth depth/x.png", one line per frame in order; the
    // dataset reader follows it, so dropping a line drops the frame.
    std::ifstream in(tmp / "associations.txt");
    std::string kept, line;
    for (int i = 0; std::getline(in, line);) {
      if (line.empty() || line[0] == '#') {
        kept += line + "\n";
        continue;
      }
      char rgb[256];
      const bool blank = i >= kBlankFirst && i < kBlankFirst + 10;
      if (variant == Variant::kOutage && blank && std::sscanf(line.c_str(), "%*f %255s", rgb) == 1) {
        const cv::Mat img = cv::imread((tmp / rgb).string(), cv::IMREAD_UNCHANGED);
        cv::imwrite((tmp / rgb).string(), cv::Mat::zeros(img.size(), img.type()));
      }
      if (delivered_in_outage(i) && !(variant == Variant::kGap && blank)) kept += line + "\n";
      ++i;
    }
    in.close();
    std::ofstream(tmp / "associations.txt") << kept;
  });
}

// The clean flight as read back from its files (cheaper than rendering it again for every run).
inline const io::TumDataset& loop_dataset() {
  static const io::TumDataset data = io::TumDataset::open(loop_sequence_dir(Variant::kClean));
  return data;
}

}  // namespace s3m::it
