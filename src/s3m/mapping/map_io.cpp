#include "s3m/mapping/map_io.hpp"

#include <algorithm>
#include <cstring>
#include <fstream>
#include <sstream>

#include "s3m/core/byte_io.hpp"
#include "s3m/core/error.hpp"
#include "s3m/core/input_file.hpp"
#include "s3m/io/atomic_file.hpp"

namespace s3m::mapping {
namespace {

constexpr char kMagic[8] = {'S', '3', 'M', 'S', 'E', 'M', '0', '1'};
constexpr char kEndMagic[8] = {'S', '3', 'M', 'E', 'N', 'D', '0', '1'};

template <typename T>
void put(std::ostream& s, const T& v) {
  s.write(reinterpret_cast<const char*>(&v), sizeof(T));
}

template <typename T>
T get(std::istream& s, const char* what) {
  T v{};
  s.read(reinterpret_cast<char*>(&v), sizeof(T));
  if (!s) throw Error(std::string("truncated while reading ") + what);
  return v;
}

void put_header(std::ostream& s, const FusionConfig& f, const OccupancyParams& o, const ClassList& cl) {
  s.write(kMagic, 8);
  put<std::uint8_t>(s, std::uint8_t(f.policy));
  put<std::int32_t>(s, f.k);
  put(s, f.alpha), put(s, f.min_other), put(s, f.max_decay);
  put<std::int32_t>(s, f.num_classes);
  put(s, o.prob_hit), put(s, o.prob_miss), put(s, o.clamp_min), put(s, o.clamp_max), put(s, o.occupancy_thres);
  put<std::uint32_t>(s, std::uint32_t(cl.size()));
  for (const auto& c : cl.all()) {
    put<std::uint16_t>(s, c.id);
    put(s, c.r), put(s, c.g), put(s, c.b);
    put<std::uint32_t>(s, std::uint32_t(c.name.size()));
    s.write(c.name.data(), std::streamsize(c.name.size()));
  }
}

ClassList get_class_list(std::istream& s) {
  const auto count = get<std::uint32_t>(s, "class count");
  if (count > 65536) throw Error("corrupt class list (count " + std::to_string(count) + ")");
  std::vector<ClassInfo> classes;
  for (std::uint32_t i = 0; i < count; ++i) {
    ClassInfo c;
    c.id = get<std::uint16_t>(s, "class id");
    c.r = get<std::uint8_t>(s, "class colour"), c.g = get<std::uint8_t>(s, "class colour");
    c.b = get<std::uint8_t>(s, "class colour");
    const auto len = get<std::uint32_t>(s, "class name length");
    if (len > 256) throw Error("corrupt class name length " + std::to_string(len));
    c.name.resize(len);
    s.read(c.name.data(), len);
    if (!s) throw Error("truncated while reading class name");
    classes.push_back(std::move(c));
  }
  return ClassList(std::move(classes));  // validates the id order
}

}  // namespace

std::ostream& SemanticOcTree::writeData(std::ostream& s) const {
  put_header(s, fusion_, occupancyParams(), classes_);
  std::ostringstream nodes;
  OccupancyOcTreeBase<SemanticOcTreeNode>::writeData(nodes);
  const std::string blob = nodes.str();
  put<std::uint64_t>(s, blob.size());
  s.write(blob.data(), std::streamsize(blob.size()));
  put<std::uint64_t>(s, fnv1a(blob));
  s.write(kEndMagic, 8);
  return s;
}

std::istream& SemanticOcTree::readData(std::istream& s) {
  char magic[8];
  s.read(magic, 8);
  if (!s || std::memcmp(magic, kMagic, 8) != 0) throw Error("missing semantic header (not an s3m semantic map)");
  FusionConfig f;
  const auto policy = get<std::uint8_t>(s, "fusion policy");
  if (policy > 2) throw Error("corrupt fusion policy " + std::to_string(policy));
  f.policy = FusionPolicy(policy);
  f.k = get<std::int32_t>(s, "fusion k");
  f.alpha = get<double>(s, "fusion alpha"), f.min_other = get<double>(s, "fusion min_other");
  f.max_decay = get<double>(s, "fusion max_decay");
  f.num_classes = get<std::int32_t>(s, "fusion num_classes");
  OccupancyParams o;
  o.prob_hit = get<double>(s, "prob_hit"), o.prob_miss = get<double>(s, "prob_miss");
  o.clamp_min = get<double>(s, "clamp_min"), o.clamp_max = get<double>(s, "clamp_max");
  o.occupancy_thres = get<double>(s, "occupancy threshold");
  classes_ = get_class_list(s);
  setFusionConfig(f);  // validates: a corrupt header fails here with the field name
  setOccupancyParams(o);
  const auto len = get<std::uint64_t>(s, "node data length");
  if (len > (std::uint64_t(1) << 40)) throw Error("corrupt node data length");
  // Read in chunks: memory follows the bytes actually present, not the length field (a corrupt
  // length used to allocate it up front, e.g. 124 GB; found by fuzzing).
  std::string blob;
  char chunk[1 << 16];
  for (std::uint64_t left = len; left > 0;) {
    const auto n = static_cast<std::streamsize>(std::min<std::uint64_t>(left, sizeof chunk));
    s.read(chunk, n);
    if (s.gcount() != n) throw Error("truncated node data (expected " + std::to_string(len) + " bytes)");
    blob.append(chunk, static_cast<std::size_t>(n));
    left -= static_cast<std::uint64_t>(n);
  }
  const auto sum = get<std::uint64_t>(s, "checksum");
  if (sum != fnv1a(blob)) throw Error("checksum mismatch: node data is corrupt");
  s.read(magic, 8);
  if (!s || std::memcmp(magic, kEndMagic, 8) != 0) throw Error("truncated file: missing end marker");
  clear();
  if (len > 0) {
    std::istringstream nodes(blob);
    OccupancyOcTreeBase<SemanticOcTreeNode>::readData(nodes);
    if (nodes.peek() != std::char_traits<char>::eof()) throw Error("trailing bytes after the node data");
  }
  return s;
}

void save_semantic_map(const SemanticOcTree& tree, const std::string& path) {
  io::write_file_atomic(path, [&](std::ostream& out) {
    if (!tree.write(out)) throw Error("serialising the semantic map failed");
  });
}

namespace {
// Parses OctoMap's text header ("# Octomap OcTree file", id, size, res, data).
void read_ot_header(std::istream& s, std::string& id, std::size_t& size, double& res) {
  std::string line;
  if (!std::getline(s, line) || line.rfind("# Octomap OcTree file", 0) != 0)
    throw Error("not an OctoMap .ot file (first line is not '# Octomap OcTree file')");
  bool have_res = false;
  while (std::getline(s, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ls(line);
    std::string token;
    ls >> token;
    if (token == "data") {
      if (id.empty() || !have_res) throw Error("header lacks 'id' or 'res' before 'data'");
      return;
    }
    if (token == "id") ls >> id;
    else if (token == "size") ls >> size;
    else if (token == "res") have_res = static_cast<bool>(ls >> res);
    else if (s.eof()) throw Error("truncated header: the file ends in '" + line + "' before the 'data' line");
    else throw Error("unknown header line '" + line + "' (expected id, size, res or data)");
  }
  throw Error("truncated header (no 'data' line)");
}
}  // namespace

std::unique_ptr<SemanticOcTree> load_semantic_map(const std::string& path) {
  std::ifstream in = open_input_file(path, "an s3m semantic map (.ot)", std::ios::binary);
  try {
    std::string id;
    std::size_t size = 0;
    double res = 0.0;
    read_ot_header(in, id, size, res);
    if (id != "SemanticOcTree") throw Error("tree type is '" + id + "', expected 'SemanticOcTree'");
    if (!(res > 0.0 && res < 100.0)) throw Error("bad resolution " + std::to_string(res));
    auto tree = std::make_unique<SemanticOcTree>(res);
    tree->readData(in);
    if (tree->size() != size)
      throw Error("node count " + std::to_string(tree->size()) + " differs from header size " + std::to_string(size));
    return tree;
  } catch (const Error& e) {
    throw Error("semantic map '" + path + "': " + e.what());
  }
}

}  // namespace s3m::mapping
