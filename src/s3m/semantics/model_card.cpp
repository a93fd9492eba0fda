#include "s3m/semantics/model_card.hpp"
#include <cmath>

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

// A read of an enum-like string into out: its index in the allowed spellings.
template <class E>
YamlMap::Read choice(E& out, std::vector<std::string> allowed, const std::string& ctx) {
  return [&out, allowed = std::move(allowed), &ctx](const YAML::Node& v, const std::string& key) {
    const std::string s = v.as<std::string>();
    for (std::size_t i = 0; i < allowed.size(); ++i)
      if (allowed[i] == s) {
        out = static_cast<E>(i);
        return;
      }
    std::string list;
    for (const auto& a : allowed) list += (list.empty() ? "" : " | ") + a;
    throw ParseError(ctx, line_of(v), "bad value '" + s + "' for '" + key + "'", list);
  };
}

// A read of a number or a list of 3 numbers (one per channel) into out.
YamlMap::Read triple(std::array<double, 3>& out, const std::string& ctx) {
  return [&out, &ctx](const YAML::Node& v, const std::string& key) {
    if (v.IsScalar()) {
      const double x = v.as<double>();
      out = {x, x, x};
      return;
    }
    std::vector<double> xs;
    try {
      xs = v.as<std::vector<double>>();
    } catch (const YAML::Exception&) {
    }
    if (xs.size() != 3)
      throw ParseError(ctx, line_of(v), "bad value for '" + key + "'", "a number or a list of 3 numbers");
    out = {xs[0], xs[1], xs[2]};
  };
}

}  // namespace

ModelCard parse_model_card(const YAML::Node& root, const std::string& card_path,
                           const std::string& model_dir);

void ModelCard::validate() const {
  auto fail = [&](const std::string& what, const std::string& expected) {
    throw ParseError(card_path, 0, what, expected);
  };
  if (model_path.empty()) fail("no 'model' given", "model: <file.onnx>");
  if (classes_path.empty()) fail("no 'classes' given", "classes: <class names file>");
  if (input_width <= 0 || input_height <= 0 || input_width > 8192 || input_height > 8192)
    fail("input size missing or out of range", "input: {width: W, height: H}, 1..8192 pixels");
  if (!(scale > 0) || !std::isfinite(scale))
    fail("input.scale must be positive and finite", "0 < scale < inf");
  for (double m : mean)
    if (!std::isfinite(m)) fail("input.mean entries must be finite", "a number (not .nan or .inf)");
  for (double s : std)
    if (!(s > 0) || !std::isfinite(s)) fail("input.std entries must be positive and finite", "0 < std < inf");
  if (top_k < 1 || top_k > kMaxTopK)
    fail("top_k = " + std::to_string(top_k) + " out of range",
         "1.." + std::to_string(kMaxTopK) + " (labels a map voxel keeps, s3m::kMaxTopK)");
  if (label_stride < 1 || label_stride > 16)
    fail("label_stride = " + std::to_string(label_stride) + " out of range", "1..16");
  if (!thread_count_ok(threads))
    fail("threads = " + std::to_string(threads) + " out of range", thread_count_range("OpenCV's default"));
}

ModelCard load_model_card(const std::string& card_path, const std::string& model_dir) {
  const YAML::Node root = load_yaml_file(card_path);
  try {
    return parse_model_card(root, card_path, model_dir);
  } catch (const YAML::Exception& e) {  // a value of the wrong shape (a map where a name belongs, ...)
    throw ParseError(card_path, e.mark.line + 1, "bad model card entry: " + e.msg,
                     "the layout in model_card.hpp");
  }
}

ModelCard parse_model_card(const YAML::Node& root, const std::string& card_path,
                           const std::string& model_dir) {
  const std::string& ctx = card_path;
  const std::string card_dir = fs::path(card_path).parent_path().string();
  const std::string data_dir = model_dir.empty() ? card_dir : model_dir;
  ModelCard c;
  c.card_path = card_path;
  std::string model, classes, class_map;
  YamlMap m(root, ctx);
  m.get("name", c.name).get("model", model).get("classes", classes).get("class_map", class_map);
  m.get("ignore_classes", c.ignore_classes);
  m.always("input", [&](const YAML::Node& in, const std::string& key) {
    if (!in || !in.IsMap())
      throw ParseError(ctx, 0, "missing '" + key + "' section", "input: {width, height, ...}");
    int rgb = 0;
    YamlMap i(in, ctx);
    i.get("width", c.input_width).get("height", c.input_height);
    i.on("channel_order", choice(rgb, {"rgb", "bgr"}, ctx));
    i.get("scale", c.scale).on("mean", triple(c.mean, ctx)).on("std", triple(c.std, ctx));
    i.on("resize", choice(c.resize, {"stretch", "letterbox"}, ctx));
    i.read();
    c.rgb = rgb == 0;
  });
  m.on("output", [&](const YAML::Node& out, const std::string&) {
    int layout = 0;  // one layout, NCHW; the key says so
    YamlMap o(out, ctx);
    o.on("layout", choice(layout, {"nchw"}, ctx));
    o.on("type", choice(c.output, {"logits", "probabilities"}, ctx));
    o.on("grid", choice(c.grid, {"half_pixel", "align_corners"}, ctx));
    o.read();
  });
  m.on("upsample", choice(c.upsample, {"linear", "nearest"}, ctx));
  m.get("label_stride", c.label_stride).get("top_k", c.top_k).get("threads", c.threads);
  m.ignore("notes").ignore("training").ignore("metrics");  // for people
  m.read();
  c.model_path = resolve(data_dir, model);
  c.classes_path = resolve(data_dir, classes);
  c.class_map_path = resolve(card_dir, class_map);
  c.validate();
  return c;
}

}  // namespace s3m::semantics
