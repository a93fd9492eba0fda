#include "s3m/semantics/onnx_inspect.hpp"

#include <fstream>
#include <iterator>
#include <set>
#include <string_view>

#include "s3m/core/error.hpp"
#include "s3m/core/input_file.hpp"

namespace s3m::semantics {
namespace {

// Minimal protobuf wire-format cursor over one message's bytes.
struct Cursor {
  const unsigned char* p;
  const unsigned char* end;
  std::string file;

  [[noreturn]] void corrupt() const { throw Error(file + ": not a valid ONNX model (protobuf data is truncated or corrupt)"); }
  std::uint64_t varint() {
    std::uint64_t v = 0;
    for (int shift = 0; shift < 64; shift += 7) {
      if (p >= end) corrupt();
      const unsigned char b = *p++;
      v |= std::uint64_t(b & 0x7f) << shift;
      if (!(b & 0x80)) return v;
    }
    corrupt();
  }
  // Reads the next field; for length-delimited fields returns the sub-range in `sub`.
  bool next(int& field, int& wire, std::uint64_t& value, Cursor& sub) {
    if (p >= end) return false;
    const std::uint64_t key = varint();
    field = static_cast<int>(key >> 3);
    wire = static_cast<int>(key & 7);
    switch (wire) {
      case 0: value = varint(); break;
      case 1: if (end - p < 8) corrupt(); p += 8; break;
      case 5: if (end - p < 4) corrupt(); p += 4; break;
      case 2: {
        const std::uint64_t len = varint();
        if (len > static_cast<std::uint64_t>(end - p)) corrupt();
        sub = Cursor{p, p + len, file};
        p += len;
        break;
      }
      default: corrupt();
    }
    return true;
  }
};

std::string string_field(Cursor msg, int wanted) {
  int f, w;
  std::uint64_t v;
  Cursor sub{nullptr, nullptr, msg.file};
  while (msg.next(f, w, v, sub))
    if (f == wanted && w == 2) return std::string(reinterpret_cast<const char*>(sub.p), sub.end - sub.p);
  return "";
}

// ValueInfoProto{1 name, 2 TypeProto{1 Tensor{2 TensorShapeProto{1 Dimension{1 dim_value, 2 dim_param}}}}}
OnnxInputInfo parse_value_info(Cursor vi) {
  OnnxInputInfo info;
  int f, w;
  std::uint64_t v;
  Cursor type{nullptr, nullptr, vi.file}, tensor = type, shape = type, dim = type;
  while (vi.next(f, w, v, type)) {
    if (f == 1 && w == 2) info.name.assign(reinterpret_cast<const char*>(type.p), type.end - type.p);
    if (f != 2 || w != 2) continue;
    while (type.next(f, w, v, tensor)) {
      if (f != 1 || w != 2) continue;
      while (tensor.next(f, w, v, shape)) {
        if (f != 2 || w != 2) continue;
        while (shape.next(f, w, v, dim)) {
          if (f != 1 || w != 2) continue;
          std::int64_t d = -1;
          Cursor x{nullptr, nullptr, vi.file};
          while (dim.next(f, w, v, x))
            if (f == 1 && w == 0) d = static_cast<std::int64_t>(v);
          info.dims.push_back(d);
        }
      }
    }
  }
  return info;
}

}  // namespace

OnnxInputInfo read_onnx_input(const std::string& onnx_path) {
  std::ifstream in = open_input_file(onnx_path, "an ONNX model file", std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (bytes.empty()) throw Error(onnx_path + ": ONNX model file is empty");
  Cursor model{reinterpret_cast<const unsigned char*>(bytes.data()),
               reinterpret_cast<const unsigned char*>(bytes.data()) + bytes.size(), onnx_path};
  int f, w;
  std::uint64_t v;
  Cursor graph{nullptr, nullptr, onnx_path};
  bool have_graph = false;
  while (model.next(f, w, v, graph))
    if (f == 7 && w == 2) {
      have_graph = true;
      break;
    }
  if (!have_graph) throw Error(onnx_path + ": not a valid ONNX model (no graph found)");
  // Older exporters list weights as graph inputs too; the real input is the first non-initializer.
  std::set<std::string> initializers;
  std::vector<Cursor> inputs;
  Cursor item{nullptr, nullptr, onnx_path};
  while (graph.next(f, w, v, item)) {
    if (f == 5 && w == 2) initializers.insert(string_field(item, 8));
    if (f == 11 && w == 2) inputs.push_back(item);
  }
  for (const Cursor& c : inputs) {
    OnnxInputInfo info = parse_value_info(c);
    if (!initializers.count(info.name)) return info;
  }
  throw Error(onnx_path + ": ONNX graph declares no input");
}

}  // namespace s3m::semantics
