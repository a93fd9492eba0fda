#include "s3m/semantics/oracle_segmenter.hpp"

#include <algorithm>
#include <random>

#include <opencv2/imgproc.hpp>

#include "s3m/core/config_table.hpp"
#include "s3m/core/error.hpp"
#include "s3m/core/yaml_util.hpp"

namespace s3m::semantics {
namespace {

using Rng = std::mt19937_64;

double beta_sample(Rng& rng, double mean, double concentration) {
  if (mean >= 1.0) return 1.0;
  std::gamma_distribution<double> ga(mean * concentration, 1.0), gb((1.0 - mean) * concentration, 1.0);
  const double a = ga(rng), b = gb(rng);
  return a + b > 0 ? a / (a + b) : mean;
}

// Most common labelled class on a thin ring around a region (what the region is drawn over).
ClassId surrounding_class(const cv::Mat& gt, const cv::Mat& region_mask, const cv::Rect& box, ClassId self) {
  const cv::Rect roi = (box + cv::Size(8, 8) - cv::Point(4, 4)) & cv::Rect(0, 0, gt.cols, gt.rows);
  cv::Mat grown;
  cv::dilate(region_mask(roi), grown, cv::getStructuringElement(cv::MORPH_RECT, {7, 7}));
  std::vector<int> count(65536, 0);
  for (int r = 0; r < roi.height; ++r) {
    const auto* g = grown.ptr<std::uint8_t>(r);
    const auto* m = region_mask(roi).ptr<std::uint8_t>(r);
    const auto* l = gt(roi).ptr<ClassId>(r);
    for (int c = 0; c < roi.width; ++c)
      if (g[c] && !m[c] && l[c] != cls::kUnknown && l[c] != self) ++count[l[c]];
  }
  const auto best = std::max_element(count.begin(), count.end());
  return *best > 0 ? static_cast<ClassId>(best - count.begin()) : cls::kOther;
}

}  // namespace

std::map<ClassId, std::vector<ClassId>> default_similar() {
  using namespace cls;
  return {{kWall, {kDoor, kWindow, kCeiling}},
          {kFloor, {kOther, kTable}},
          {kCeiling, {kWall}},
          {kDoor, {kWall, kCabinet}},
          {kWindow, {kWall, kTvMonitor}},
          {kTable, {kCabinet, kShelf}},
          {kChair, {kSofa, kTable}},
          {kSofa, {kChair, kBed}},
          {kBed, {kSofa, kTable}},
          {kCabinet, {kShelf, kTable, kDoor}},
          {kShelf, {kCabinet, kTable}},
          {kTvMonitor, {kWindow, kOther}},
          {kPlant, {kOther}},
          {kPerson, {kOther, kChair}},
          {kOther, {kCabinet, kTable}}};
}

void OracleNoiseConfig::validate() const {
  require(confusion_rate >= 0 && drop_rate >= 0 && confusion_rate + drop_rate <= 0.6,
          "oracle: confusion_rate and drop_rate must be >= 0 with sum <= 0.6");
  require(boundary_width_px >= 0 && boundary_width_px <= 50, "oracle: boundary_width_px must be in 0..50");
  require(boundary_flip_prob >= 0 && boundary_flip_prob <= 0.5,
          "oracle: boundary_flip_prob must be in [0, 0.5]");
  require(concentration > 0, "oracle: concentration must be > 0");
  require(min_confidence >= 0.375 && min_confidence <= 1,
          "oracle: min_confidence must be in [0.375, 1] (rank 1 >= rank 2)");
}

namespace {

// `similar: {wall: [door, window], ...}`: entries replace those of default_similar().
void read_similar(const YAML::Node& node, std::map<ClassId, std::vector<ClassId>>& similar,
                  const std::string& ctx) {
  const auto& classes = indoor_classes();
  auto id_of = [&](const YAML::Node& n) {
    const int id = classes.find(n.as<std::string>());
    if (id < 0)
      throw ParseError(ctx, n.Mark().line + 1, "unknown class '" + n.as<std::string>() + "'",
                       "a project class name");
    return static_cast<ClassId>(id);
  };
  if (similar.empty()) similar = default_similar();
  try {
    for (const auto& kv : node) {
      std::vector<ClassId> to;
      for (const auto& v : kv.second) to.push_back(id_of(v));
      similar[id_of(kv.first)] = to;
    }
  } catch (const YAML::Exception& e) {
    throw ParseError(ctx, e.mark.line + 1, "bad oracle entry: " + e.msg, "similar: {class: [classes]}");
  }
}

YAML::Node similar_node(const std::map<ClassId, std::vector<ClassId>>& similar) {
  YAML::Node n(YAML::NodeType::Map);
  for (const auto& [from, to] : similar.empty() ? default_similar() : similar) {  // empty: the defaults apply
    YAML::Node list(YAML::NodeType::Sequence);
    for (const ClassId c : to) list.push_back(indoor_classes().at(c).name);
    list.SetStyle(YAML::EmitterStyle::Flow);
    n[indoor_classes().at(from).name] = list;
  }
  return n;
}

}  // namespace

void fields(config::FieldVisitor& v, OracleNoiseConfig& c) {
  v("enabled", c.enabled);
  v("confusion_rate", c.confusion_rate);
  v("drop_rate", c.drop_rate);
  v("boundary_width_px", c.boundary_width_px);
  v("boundary_flip_prob", c.boundary_flip_prob);
  v("concentration", c.concentration);
  v("min_confidence", c.min_confidence);
  v("seed", c.seed);
  v("similar", config::Custom{[&c](const YAML::Node& n, const std::string&, const std::string& ctx) {
                                read_similar(n, c.similar, ctx);
                              },
                              [&c] { return similar_node(c.similar); }});
}

OracleNoiseConfig load_oracle_config(const YAML::Node& node, const std::string& ctx) {
  OracleNoiseConfig c;
  c.similar = default_similar();
  if (!node) return c;
  config::read(node, config::table_of(c), ctx);
  c.validate();
  return c;
}

OracleSegmenter::OracleSegmenter(OracleNoiseConfig config, int k) : config_(std::move(config)), k_(k) {
  config_.validate();
  require(k >= 1 && k <= 32, "OracleSegmenter: k must be in 1..32");
  if (config_.similar.empty()) config_.similar = default_similar();
}

LabelMap OracleSegmenter::segment(const cv::Mat&) {
  throw Error("OracleSegmenter needs ground-truth labels: call segment(frame) with frame.labels set");
}

LabelMap OracleSegmenter::segment(const RgbdFrame& frame) {
  require(!frame.labels.empty(), "OracleSegmenter: frame " + std::to_string(frame.index) +
                                     " has no ground-truth labels (the oracle only works on simulated data)");
  return segment_labels(frame.labels, frame.index);
}

LabelMap OracleSegmenter::segment_labels(const cv::Mat& gt, int frame_index) const {
  require(gt.type() == CV_16UC1 && !gt.empty(),
          "OracleSegmenter: ground truth must be a CV_16UC1 class-id image");
  const OracleNoiseConfig& cfg = config_;
  // Seed per frame so the noise does not depend on the order frames are processed in.
  Rng rng(cfg.seed * 0x9E3779B97F4A7C15ull + static_cast<std::uint64_t>(frame_index) * 0xBF58476D1CE4E5B9ull +
          1);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  cv::Mat noisy = gt.clone();
  cv::Mat conf(gt.size(), CV_32FC1, cv::Scalar(1.0f));

  if (cfg.enabled) {
    // 1. region-level errors: confusions and drops, with a calibrated confidence per region
    const double err = cfg.confusion_rate + cfg.drop_rate;
    double min_v, max_v;
    cv::minMaxLoc(gt, &min_v, &max_v);
    for (int cid = 1; cid <= int(max_v); ++cid) {
      const cv::Mat mask = gt == cid;
      cv::Mat comp, stats, centroids;
      const int n = cv::connectedComponentsWithStats(mask, comp, stats, centroids, 8, CV_32S);
      for (int r = 1; r < n; ++r) {
        const double c = std::max(cfg.min_confidence, beta_sample(rng, 1.0 - err, cfg.concentration));
        const bool wrong = uni(rng) >= c;
        const bool drop = uni(rng) < (err > 0 ? cfg.drop_rate / err : 0.0);
        const cv::Rect box(stats.at<int>(r, cv::CC_STAT_LEFT), stats.at<int>(r, cv::CC_STAT_TOP),
                           stats.at<int>(r, cv::CC_STAT_WIDTH), stats.at<int>(r, cv::CC_STAT_HEIGHT));
        const cv::Mat region = comp(box) == r;
        conf(box).setTo(static_cast<float>(c), region);
        if (!wrong) continue;
        ClassId to;
        if (drop) {
          to = surrounding_class(gt, comp == r, box, static_cast<ClassId>(cid));
        } else {
          const auto it = cfg.similar.find(static_cast<ClassId>(cid));
          const std::vector<ClassId> cand =
              it != cfg.similar.end() && !it->second.empty() ? it->second : std::vector<ClassId>{cls::kOther};
          to = cand[std::uniform_int_distribution<std::size_t>(0, cand.size() - 1)(rng)];
        }
        noisy(box).setTo(to, region);
      }
    }
    // 2. boundary band: pixels near another labelled class take it with boundary_flip_prob
    if (cfg.boundary_width_px > 0 && cfg.boundary_flip_prob > 0) {
      const int w = 2 * cfg.boundary_width_px + 1;
      const cv::Mat kernel = cv::getStructuringElement(cv::MORPH_RECT, {w, w});
      cv::Mat hi, lo;
      cv::dilate(gt, hi, kernel);
      cv::erode(gt, lo, kernel);
      const float keep = static_cast<float>(1.0 - cfg.boundary_flip_prob);
      for (int r = 0; r < gt.rows; ++r) {
        const ClassId *g = gt.ptr<ClassId>(r), *h = hi.ptr<ClassId>(r), *l = lo.ptr<ClassId>(r);
        ClassId* o = noisy.ptr<ClassId>(r);
        float* cf = conf.ptr<float>(r);
        for (int c = 0; c < gt.cols; ++c) {
          if (g[c] == cls::kUnknown) continue;
          const ClassId other = h[c] != g[c] ? h[c] : l[c];
          if (other == g[c] || other == cls::kUnknown) continue;
          cf[c] *= keep;
          if (uni(rng) < cfg.boundary_flip_prob) o[c] = other;
        }
      }
    }
  }

  // 3. top-k lists: rank 1 the (noisy) label, the rest share 1 - p1 (true class first if rank 1 is wrong)
  LabelMap out = make_label_map(gt.rows, gt.cols, k_);
  std::vector<ClassId> ranks;
  for (int r = 0; r < gt.rows; ++r) {
    const ClassId *g = gt.ptr<ClassId>(r), *o = noisy.ptr<ClassId>(r);
    const float* cf = conf.ptr<float>(r);
    ClassId* ids = out.ids.ptr<ClassId>(r);
    float* probs = out.probs.ptr<float>(r);
    ClassId* am = out.argmax.ptr<ClassId>(r);
    for (int c = 0; c < gt.cols; ++c) {
      if (g[c] == cls::kUnknown) continue;
      ranks.assign(1, o[c]);
      if (o[c] != g[c]) ranks.push_back(g[c]);
      if (const auto it = config_.similar.find(g[c]); it != config_.similar.end())
        for (ClassId s : it->second)
          if (std::find(ranks.begin(), ranks.end(), s) == ranks.end()) ranks.push_back(s);
      const float rest = 1.0f - cf[c];
      float share = 0.6f;
      for (int j = 0; j < k_; ++j) {
        if (j >= int(ranks.size()) || (j > 0 && rest <= 0.f)) break;
        ids[c * k_ + j] = ranks[j];
        // capped so ranks stay ordered when p1 is low (boundary bands of low-confidence regions)
        probs[c * k_ + j] = j == 0 ? cf[c] : std::min(rest * share, probs[c * k_ + j - 1]);
        if (j > 0) share *= 0.4f;
      }
      am[c] = ranks[0];
    }
  }
  return out;
}

}  // namespace s3m::semantics
