#include "s3m/semantics/model_card.hpp"

#include <filesystem>

#include "s3m/core/classes.hpp"  // kMaxTopK
#include "s3m/core/error.hpp"
#include "s3m/core/thread_count.hpp"
#include "s3m/core/yaml_util.hpp"

namespace s3m::semantics {
namespace fs = std::filesystem;
namespace {

std::string resolve(const std::string& base, const std::string& p) {
  if (p.empty() || fs::path(p).is_absolute()) return p;
  return (fs::path(base) / p).lexically_normal().string();
}

int line_of(const YAML::Node& n) { return n ? n.Mark().line + 1 : 0; }

// Reads an enum-like string key, checking it against the allowed spellings.
int choice(const YAML::Node& node, const std::string& key, const std::vector<std::string>& allowed, int def,
           const std::string& ctx) {
  if (!node || !node[key]) return def;
  const std::string v = node[key].as<std::string>();
  for (std::size_t i = 0; i < allowed.size(); ++i)
    if (allowed[i] == v) return static_cast<int>(i);
  std::string list;
  for (const auto& a : allowed) list += (list.empty() ? "" : " | ") + a;
  throw ParseError(ctx, line_of(node[key]), "bad value '" + v + "' for '" + key + "'", list);
}

std::array<double, 3> triple(const YAML::Node& node, const std::string& key, std::array<double, 3> def,
                             const std::string& ctx) {
  if (!node || !node[key]) return def;
  const YAML::Node v = node[key];
  if (v.IsScalar()) {
    const double x = v.as<double>();
    return {x, x, x};
  }
  std::vector<double> xs;
  try {
    xs = v.as<std::vector<double>>();
  } catch (const YAML::Exception&) {
  }
  if (xs.size() != 3) throw ParseError(ctx, line_of(v), "bad value for '" + key + "'", "a number or a list of 3 numbers");
  return {xs[0], xs[1], xs[2]};
}

}  // namespace

ModelCard parse_model_card(const YAML::Node& root, const std::string& card_path, const std::string& model_dir);

void ModelCard::validate() const {
  auto fail = [&](const std::string& what, const std::string& expected) {
    throw ParseError(card_path, 0, what, expected);
  };
  if (model_path.empty()) fail("no 'model' given", "model: <file.onnx>");
  if (classes_path.empty()) fail("no 'classes' given", "classes: <class names file>");
  if (input_width <= 0 || input_height <= 0 || input_width > 8192 || input_height > 8192)
    fail("input size missing or out of range", "input: {width: W, height: H}, 1..8192 pixels");
  if (!(scale > 0)) fail("input.scale must be positive", "scale > 0");
  for (double s : std)
    if (!(s > 0)) fail("input.std entries must be positive", "std > 0");
  if (top_k < 1 || top_k > kMaxTopK)
    fail("top_k = " + std::to_string(top_k) + " out of range",
         "1.." + std::to_string(kMaxTopK) + " (labels a map voxel keeps, s3m::kMaxTopK)");
  if (label_stride < 1 || label_stride > 16) fail("label_stride = " + std::to_string(label_stride) + " out of range", "1..16");
  if (!thread_count_ok(threads))
    fail("threads = " + std::to_string(threads) + " out of range", thread_count_range("OpenCV's default"));
}

ModelCard load_model_card(const std::string& card_path, const std::string& model_dir) {
  const YAML::Node root = load_yaml_file(card_path);
  try {
    return parse_model_card(root, card_path, model_dir);
  } catch (const YAML::Exception& e) {  // a value of the wrong shape (a map where a name belongs, ...)
    throw ParseError(card_path, e.mark.line + 1, "bad model card entry: " + e.msg, "the layout in model_card.hpp");
  }
}

ModelCard parse_model_card(const YAML::Node& root, const std::string& card_path, const std::string& model_dir) {
  const std::string& ctx = card_path;
  check_known_keys(root, {"name", "model", "classes", "class_map", "ignore_classes", "input", "output", "upsample", "label_stride",
                          "top_k", "threads", "notes", "training", "metrics"},
                   ctx);
  const std::string card_dir = fs::path(card_path).parent_path().string();
  const std::string data_dir = model_dir.empty() ? card_dir : model_dir;
  ModelCard c;
  c.card_path = card_path;
  std::string model, classes, class_map;
  yaml_get(root, "name", c.name, ctx);
  yaml_get(root, "model", model, ctx);
  yaml_get(root, "classes", classes, ctx);
  yaml_get(root, "class_map", class_map, ctx);
  yaml_get(root, "ignore_classes", c.ignore_classes, ctx);
  yaml_get(root, "top_k", c.top_k, ctx);
  yaml_get(root, "threads", c.threads, ctx);
  yaml_get(root, "label_stride", c.label_stride, ctx);
  c.model_path = resolve(data_dir, model);
  c.classes_path = resolve(data_dir, classes);
  c.class_map_path = resolve(card_dir, class_map);
  c.upsample = static_cast<ModelCard::Upsample>(choice(root, "upsample", {"linear", "nearest"}, 0, ctx));

  const YAML::Node in = root["input"];
  if (!in || !in.IsMap()) throw ParseError(ctx, 0, "missing 'input' section", "input: {width, height, ...}");
  check_known_keys(in, {"width", "height", "channel_order", "scale", "mean", "std", "resize"}, ctx);
  yaml_get(in, "width", c.input_width, ctx);
  yaml_get(in, "height", c.input_height, ctx);
  yaml_get(in, "scale", c.scale, ctx);
  c.rgb = choice(in, "channel_order", {"rgb", "bgr"}, 0, ctx) == 0;
  c.mean = triple(in, "mean", c.mean, ctx);
  c.std = triple(in, "std", c.std, ctx);
  c.resize = static_cast<ModelCard::Resize>(choice(in, "resize", {"stretch", "letterbox"}, 0, ctx));

  const YAML::Node out = root["output"];
  if (out) {
    check_known_keys(out, {"layout", "type", "grid"}, ctx);
    choice(out, "layout", {"nchw"}, 0, ctx);
    c.output = static_cast<ModelCard::Output>(choice(out, "type", {"logits", "probabilities"}, 0, ctx));
    c.grid = static_cast<ModelCard::Grid>(choice(out, "grid", {"half_pixel", "align_corners"}, 0, ctx));
  }
  c.validate();
  return c;
}

}  // namespace s3m::semantics
