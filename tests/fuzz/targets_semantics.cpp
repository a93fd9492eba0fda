// Fuzz target for ONNX model cards and the class files they reference (semantics module).
// Input: up to three files separated by "\n--\n": the card (YAML), its class names file, and a
// class map (YAML). The ONNX model itself is not opened (OpenCV DNN's parser is not ours).
#include "fuzz/targets.hpp"
#include "fuzz/targets_list.hpp"
#include "s3m/semantics/class_map.hpp"
#include "s3m/semantics/model_card.hpp"

namespace s3m::fuzz {
namespace {

void fuzz_model_card(const std::uint8_t* data, std::size_t size) {
  const auto parts = split_parts(data, size, 3);
  const std::string card = write_scratch("card/model.yaml", parts[0]);
  const std::string classes = write_scratch("card/model.classes.txt", parts.size() > 1 ? parts[1] : "");
  const std::string map = write_scratch("card/map.yaml", parts.size() > 2 ? parts[2] : "");
  expect_clean([&] { (void)semantics::load_model_card(card); });
  std::vector<std::string> names = {"wall", "floor", "chair", "table", "spaceship"};
  expect_clean([&] { names = semantics::read_class_names(classes); });
  expect_clean([&] {
    const auto cm = semantics::ClassMap::load(map, names);
    if (cm.source_size() != names.size()) throw std::logic_error("fuzz invariant violated: class map size");
    for (std::size_t i = 0; i < cm.source_size(); ++i)
      if (cm[i] >= cm.target().size()) throw std::logic_error("fuzz invariant violated: class map target id");
  });
  expect_clean([&] { (void)semantics::ClassMap::by_name(names); });
}

}  // namespace

void append_semantics_targets(std::vector<Target>& out) { out.push_back({"model_card", fuzz_model_card}); }

}  // namespace s3m::fuzz
