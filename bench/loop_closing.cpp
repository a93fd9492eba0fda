// Loop closing and relocalisation on a TUM-layout sequence: runs RGB-D SLAM twice, without and
// with loop closing (relocalisation on in both), and prints ATE RMSE (SE3 alignment), loops
// closed, relocalisations, lost frames and the loop closer's cost per keyframe.
//   bench_loop_closing DATASET_DIR [--vocab FILE] [--blank FIRST] [--threaded]
// --blank FIRST blanks frames FIRST..FIRST+9 (black image, no depth) to exercise relocalisation.
#include <cstdio>
#include <cstdlib>
#include <string>

#include "s3m/core/timing.hpp"
#include "s3m/eval/trajectory_eval.hpp"
#include "s3m/features/bow_vocabulary.hpp"
#include "s3m/io/tum_dataset.hpp"
#include "s3m/slam/system.hpp"

using namespace s3m;

namespace {

struct Outcome {
  double ate_m = 0, wall_s = 0;
  int loops = 0, relocalisations = 0, lost = 0, keyframes = 0;
};

Outcome run(const io::TumDataset& data, std::shared_ptr<const features::Vocabulary> vocab, bool loop_closing,
            int blank_first, bool threaded) {
  slam::SlamConfig cfg;
  cfg.threaded = threaded;
  cfg.loop_closing.enabled = loop_closing;
  slam::System system(data.camera(), cfg, std::move(vocab));
  Outcome o;
  Stopwatch wall;
  for (std::size_t i = 0; i < data.size(); ++i) {
    RgbdFrame f = data.load(i);
    if (blank_first >= 0 && int(i) >= blank_first && int(i) < blank_first + 10) {
      f.rgb.setTo(0);
      f.depth_m.setTo(0);
    }
    const auto r = system.track(f);
    o.lost += r.state == FrameState::kLost;
    if (i % 100 == 0) std::fprintf(stderr, "  frame %zu/%zu %s\n", i, data.size(), to_string(r.state));
  }
  system.finish();
  o.wall_s = wall.elapsed_ms() / 1000.0;
  eval::MatchedPoses m;
  for (const auto& p : system.camera_trajectory()) {
    if (p.state == FrameState::kLost) continue;
    if (const auto gt = data.groundtruth_at(p.t_s)) {
      m.t_s.push_back(p.t_s);
      m.T_w_gt.push_back(*gt);
      m.T_w_est.push_back(p.T_w_x);
    }
  }
  o.ate_m = eval::compute_ate(m, eval::AlignMode::kSe3).stats_m.rmse;
  o.loops = system.n_loops();
  o.relocalisations = system.n_relocalised_frames();
  o.keyframes = system.map().n_keyframes();
  return o;
}

}  // namespace

int main(int argc, char** argv) {
  std::string dir, vocab_path = features::default_vocabulary_path();
  int blank_first = -1;
  bool threaded = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--vocab" && i + 1 < argc)
      vocab_path = argv[++i];
    else if (a == "--blank" && i + 1 < argc)
      blank_first = std::atoi(argv[++i]);
    else if (a == "--threaded")
      threaded = true;
    else
      dir = a;
  }
  if (dir.empty()) {
    std::fprintf(stderr,
                 "usage: bench_loop_closing DATASET_DIR [--vocab FILE] [--blank FIRST] [--threaded]\n");
    return 2;
  }
  try {
    const auto data = io::TumDataset::open(dir);
    const auto vocab = std::make_shared<const features::Vocabulary>(features::Vocabulary::load(vocab_path));
    for (bool loop_closing : {false, true}) {
      std::fprintf(stderr, "%s loop closing:\n", loop_closing ? "with" : "without");
      const Outcome o = run(data, vocab, loop_closing, blank_first, threaded);
      std::printf(
          "%-8s loop closing: ATE_rmse_m %.4f loops %d relocalisations %d lost %d keyframes %d wall %.1f s\n",
          loop_closing ? "with" : "without", o.ate_m, o.loops, o.relocalisations, o.lost, o.keyframes,
          o.wall_s);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_loop_closing: %s\n", e.what());
    return 1;
  }
  return 0;
}
