// `s3m vocab IMAGES... --out vocab.bin`: trains the bag-of-words vocabulary used by loop closing
// and relocalisation from ORB descriptors of the given images (files or folders).
#include <cstdio>

#include "commands.hpp"
#include "s3m/core/error.hpp"
#include "s3m/core/timing.hpp"
#include "s3m/features/bow_training.hpp"
#include "s3m/features/bow_vocabulary.hpp"
#include "s3m/io/image_io.hpp"

namespace s3m::apps {

namespace {

struct VocabOptions {
  std::vector<std::string> images;
  std::string out;
  int features = 1000;
  int stride = 1;
  bool force = false;
  features::VocabularyConfig config;
};

// Work no one means is refused before the first image is read, with the estimate: ORB finds at
// most a few ten thousand corners in a camera image, and every descriptor kept costs 32 bytes.
void check_cost(const VocabOptions& o, std::size_t n_images) {
  constexpr int kMaxFeatures = 100000;
  constexpr double kMaxGb = 4.0;
  if (o.force) return;
  require(o.features <= kMaxFeatures, "--features " + std::to_string(o.features) +
                                          " per image is over the limit of " + std::to_string(kMaxFeatures) +
                                          " (ORB finds far fewer in a camera image); --force to go on");
  const double gb = double(n_images) * double(o.features) * 32.0 / 1e9;
  if (gb > kMaxGb) {
    char msg[200];
    std::snprintf(msg, sizeof msg,
                  "--features %d on %zu images would keep up to %.1f GB of descriptors (limit %.0f GB): use "
                  "--stride or fewer features, or --force to go on",
                  o.features, n_images, gb, kMaxGb);
    throw Error(msg);
  }
}

void run_vocab(const VocabOptions& o) {
  o.config.validate();
  require(o.features > 0, "--features must be > 0");
  // 1. Collect the training images.
  const auto files = features::list_training_images(o.images, o.stride);
  check_cost(o, files.size());
  std::fprintf(stderr, "vocab: %zu training images, %d ORB features each\n", files.size(), o.features);
  // 2. ORB descriptors per image.
  const auto load = [](const std::string& path) { return io::read_rgb(path); };
  const auto descriptors =
      features::descriptors_from_image_files(files, o.features, load, [](size_t i, size_t n) {
        if (i % 25 == 0 || i == n) std::fprintf(stderr, "\rvocab: extracted %zu/%zu images", i, n);
      });
  size_t total = 0;
  for (const auto& d : descriptors) total += size_t(d.rows);
  std::fprintf(stderr, "\nvocab: clustering %zu descriptors (k=%d, L=%d)\n", total, o.config.branching,
               o.config.levels);
  // 3. Hierarchical k-medians + IDF.
  int last_percent = -1;
  const auto vocab = features::Vocabulary::train(descriptors, o.config, [&](size_t done, size_t n) {
    const int percent = int(100 * done / std::max<size_t>(n, 1));
    if (percent / 10 != last_percent / 10)
      std::fprintf(stderr, "\rvocab: %3d %%", percent), last_percent = percent;
  });
  // 4. Atomic write.
  vocab.save(o.out);
  std::printf("\nvocab: wrote %s: %zu words, %zu nodes, trained on %u images\n", o.out.c_str(),
              vocab.num_words(), vocab.num_nodes(), vocab.training_images());
}

}  // namespace

void register_vocab(CLI::App& app) {
  auto opts = std::make_shared<VocabOptions>();
  auto* cmd =
      app.add_subcommand("vocab", "Train a bag-of-words ORB vocabulary from images (files or folders)");
  cmd->add_option("images", opts->images, "training images or folders of .png/.jpg images")->required();
  cmd->add_option("--out,-o", opts->out, "output vocabulary file")->required();
  cmd->add_option("--k", opts->config.branching, "branching factor")->capture_default_str();
  cmd->add_option("--levels", opts->config.levels, "tree depth (at most k^levels words)")
      ->capture_default_str();
  cmd->add_option("--features", opts->features, "ORB features extracted per image")->capture_default_str();
  cmd->add_flag("--force", opts->force, "train even when the descriptors would take more than 4 GB");
  cmd->add_option("--stride", opts->stride, "use every n-th image of each folder")->capture_default_str();
  cmd->add_option("--seed", opts->config.seed, "k-means++ seed")->capture_default_str();
  cmd->add_option("--iterations", opts->config.max_iterations, "k-medians iterations per node")
      ->capture_default_str();
  cmd->callback([opts] { run_vocab(*opts); });
}

}  // namespace s3m::apps
