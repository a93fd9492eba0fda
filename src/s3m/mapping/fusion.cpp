#include "s3m/mapping/fusion.hpp"

#include <algorithm>
#include <cmath>

#include "s3m/core/config_table.hpp"
#include "s3m/core/error.hpp"
#include "s3m/core/yaml_util.hpp"

namespace s3m::mapping {
namespace {

// Working list in double precision: the union of two lists has at most 2*kMaxLabels entries.
struct Work {
  int n = 0;
  std::array<ClassId, 2 * kMaxLabels> ids{};
  std::array<double, 2 * kMaxLabels> p{};

  explicit Work(const LabelSet& s) {
    for (int i = 0; i < s.n; ++i) push(s.ids[i], std::max(0.0, double(s.probs[i])));
  }
  int find(ClassId id) const {
    for (int i = 0; i < n; ++i)
      if (ids[i] == id) return i;
    return -1;
  }
  void push(ClassId id, double v) {
    ids[n] = id;
    p[n] = v;
    ++n;
  }
  double sum() const {
    double s = 0;
    for (int i = 0; i < n; ++i) s += p[i];
    return s;
  }
};

// Sorts by (p desc, id asc) and writes the first k entries with p > 0 into out.
void write_top_k(const Work& w, int k, LabelSet& out) {
  std::array<int, 2 * kMaxLabels> order{};
  for (int i = 0; i < w.n; ++i) order[i] = i;
  std::sort(order.begin(), order.begin() + w.n,
            [&](int a, int b) { return w.p[a] != w.p[b] ? w.p[a] > w.p[b] : w.ids[a] < w.ids[b]; });
  out = LabelSet{};
  for (int i = 0; i < w.n && out.n < k; ++i)
    if (w.p[order[i]] > 0.0) out.push(w.ids[order[i]], float(w.p[order[i]]));
}

bool same_ordered_labels(const LabelSet& a, const LabelSet& b) {
  if (a.n != b.n) return false;
  for (int i = 0; i < a.n; ++i)
    if (a.ids[i] != b.ids[i]) return false;
  return true;
}

double unexplained(const Work& w, double floor) { return std::max(1.0 - w.sum(), floor); }

// Algorithm 1 lines 4-8 (and 9-13 mirrored): push each label of `from` missing in `to`
// with alpha * p-bar(to), recomputing p-bar after every push.
void synchronise(const Work& from, Work& to, const FusionConfig& cfg) {
  double pbar = unexplained(to, cfg.min_other);
  for (int i = 0; i < from.n; ++i) {
    if (to.find(from.ids[i]) >= 0) continue;
    to.push(from.ids[i], cfg.alpha * pbar);
    pbar = unexplained(to, cfg.min_other);
  }
}

}  // namespace

void FusionConfig::validate() const {
  require(k >= 1 && k <= kMaxLabels,
          "fusion.k must be in [1, " + std::to_string(kMaxLabels) + "], got " + std::to_string(k));
  require(alpha > 0.0 && alpha <= 1.0, "fusion.alpha must be in (0, 1], got " + std::to_string(alpha));
  require(min_other > 0.0 && min_other < 1.0, "fusion.min_other must be in (0, 1)");
  require(max_decay > 0.0 && max_decay <= 1.0, "fusion.max_decay must be in (0, 1]");
  require(num_classes >= 2, "fusion.num_classes must be >= 2");
}

std::string to_string(FusionPolicy policy) {
  switch (policy) {
    case FusionPolicy::kPaper: return "paper";
    case FusionPolicy::kMaxConfidence: return "max_confidence";
    case FusionPolicy::kBayesian: return "bayesian";
  }
  return "unknown";
}

FusionPolicy parse_fusion_policy(const std::string& name) {
  if (name == "paper") return FusionPolicy::kPaper;
  if (name == "max_confidence" || name == "max") return FusionPolicy::kMaxConfidence;
  if (name == "bayesian" || name == "bayes") return FusionPolicy::kBayesian;
  throw Error("unknown fusion policy '" + name + "' (expected paper, max_confidence or bayesian)");
}

void fields(config::FieldVisitor& v, FusionConfig& c) {
  // Read through parse_fusion_policy, which also takes the short spellings (max, bayes).
  config::Custom policy{[&c](const YAML::Node& n, const std::string& key, const std::string& ctx) {
                          try {
                            c.policy = parse_fusion_policy(yaml_as<std::string>(n, key, ctx));
                          } catch (const ParseError&) {
                            throw;
                          } catch (const Error& e) {
                            throw ParseError(ctx, n.Mark().line + 1, e.what());
                          }
                        },
                        [&c] { return YAML::Node(to_string(c.policy)); }};
  v("policy", policy);
  v("k", c.k);
  v("alpha", c.alpha);
  v("min_other", c.min_other);
  v("max_decay", c.max_decay);
  v("num_classes", c.num_classes);
}

FusionConfig fusion_config_from_yaml(const YAML::Node& node, const std::string& ctx) {
  FusionConfig c;
  if (!node) return c;
  config::read(node, config::table_of(c), ctx);
  c.validate();
  return c;
}

FusionFn fusion_function(FusionPolicy policy) {
  switch (policy) {
    case FusionPolicy::kPaper: return &fuse_paper;
    case FusionPolicy::kMaxConfidence: return &fuse_max_confidence;
    case FusionPolicy::kBayesian: return &fuse_bayesian;
  }
  throw Error("invalid fusion policy value " + std::to_string(int(policy)));
}

// Algorithm 1. Departures, all for cases the paper does not define:
// - "Q1.s = Q2.s" is read literally: same labels in the same order -> keep Q1 unchanged.
// - An empty side carries no information: empty map takes the observation, empty obs is a no-op.
// - p-bar is floored at min_other so a full list (sum p = 1) does not zero the other view's labels.
// - The product is aligned by label (the paper's lists are index-aligned only implicitly).
// - If every product is 0 (zero-probability inputs) the map is left unchanged.
// - The fused union (up to 2k labels) is truncated back to the top k; the dropped mass becomes
//   p-bar for the next fusion. Ties rank by class id.
void fuse_paper(LabelSet& map, const LabelSet& obs, const FusionConfig& cfg) {
  if (obs.empty()) return;
  if (map.empty()) {
    map = obs;
    map.normalise(cfg.k);
    return;
  }
  if (same_ordered_labels(map, obs)) return;  // Algorithm 1 line 2
  Work q1(map), q2(obs);
  synchronise(q1, q2, cfg);  // labels of Q1 into Q2
  synchronise(q2, q1, cfg);  // labels of Q2 into Q1
  double total = 0.0;
  for (int i = 0; i < q1.n; ++i) {
    q1.p[i] *= q2.p[q2.find(q1.ids[i])];
    total += q1.p[i];
  }
  if (!(total > 0.0)) return;
  for (int i = 0; i < q1.n; ++i) q1.p[i] /= total;
  write_top_k(q1, cfg.k, map);
}

// Max-confidence (semantic_slam's max fusion, extended to k labels): the voxel keeps the list of
// its most confident view. A weaker view that agrees on the top label changes nothing; a weaker
// disagreeing view decays the stored list by max_decay, so persistent contrary evidence
// eventually wins; a more confident view replaces the list.
void fuse_max_confidence(LabelSet& map, const LabelSet& obs_in, const FusionConfig& cfg) {
  LabelSet obs = obs_in;
  obs.normalise(cfg.k);
  if (obs.empty()) return;
  if (map.empty() || obs.top_prob() > map.top_prob()) {
    map = obs;
    return;
  }
  if (obs.top() == map.top()) return;
  Work w(map);
  for (int i = 0; i < w.n; ++i) w.p[i] *= cfg.max_decay;
  write_top_k(w, cfg.k, map);
}

// Recursive Bayes with the unlisted classes sharing the "other" mass uniformly:
// P(c) = p(c) if c is listed, else max(1 - sum p, min_other) / (C - n). The posterior over the
// union of listed classes and the remaining "other" bin is normalised; its top k are stored.
void fuse_bayesian(LabelSet& map, const LabelSet& obs, const FusionConfig& cfg) {
  if (obs.empty()) return;
  if (map.empty()) {
    map = obs;
    map.normalise(cfg.k);
    return;
  }
  Work q1(map), q2(obs);
  const double C = cfg.num_classes;
  const double u1 = unexplained(q1, cfg.min_other) / std::max(1.0, C - q1.n);
  const double u2 = unexplained(q2, cfg.min_other) / std::max(1.0, C - q2.n);
  Work fused(LabelSet{});
  for (int i = 0; i < q1.n; ++i) fused.push(q1.ids[i], 0.0);
  for (int i = 0; i < q2.n; ++i)
    if (fused.find(q2.ids[i]) < 0) fused.push(q2.ids[i], 0.0);
  double total = std::max(0.0, C - fused.n) * u1 * u2;  // classes in neither list
  for (int i = 0; i < fused.n; ++i) {
    const int a = q1.find(fused.ids[i]), b = q2.find(fused.ids[i]);
    fused.p[i] = (a >= 0 ? q1.p[a] : u1) * (b >= 0 ? q2.p[b] : u2);
    total += fused.p[i];
  }
  if (!(total > 0.0)) return;
  for (int i = 0; i < fused.n; ++i) fused.p[i] /= total;
  write_top_k(fused, cfg.k, map);
}

}  // namespace s3m::mapping
