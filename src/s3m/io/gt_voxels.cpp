#include "s3m/io/gt_voxels.hpp"

#include <cmath>
#include <fstream>
#include <limits>

#include <fmt/format.h>

#include "s3m/core/error.hpp"
#include "s3m/core/input_file.hpp"
#include "s3m/io/atomic_file.hpp"
#include "s3m/io/text_lines.hpp"

namespace s3m::io {
namespace {
constexpr const char* kHeader = "# s3m ground-truth voxel map v1";
}

void write_gt_voxels(const std::string& path, const GtVoxelMap& map) {
  require(map.centres_w.size() == map.labels.size(), "write_gt_voxels: centres_w and labels differ in length");
  require(std::isfinite(map.resolution_m) && map.resolution_m > 0, "write_gt_voxels: resolution_m must be > 0");
  write_file_atomic(path, [&](std::ostream& os) {
    os << kHeader << "\n" << fmt::format("resolution {:.9g}\n", map.resolution_m);
    for (std::size_t i = 0; i < map.labels.size(); ++i) {
      const auto& c = map.centres_w[i];
      os << fmt::format("{:.9g} {:.9g} {:.9g} {}\n", c.x(), c.y(), c.z(), map.labels[i]);
    }
  });
}

GtVoxelMap read_gt_voxels(const std::string& path) {
  {  // The header is a comment, so LineReader would skip it: check it first.
    std::ifstream in = open_input_file(path, "an s3m ground-truth voxel map");
    std::string first;
    if (in && std::getline(in, first) && first.rfind(kHeader, 0) != 0)
      throw ParseError(path, 1, "missing header", std::string("'") + kHeader + "'");
  }
  LineReader reader(path, "an s3m ground-truth voxel map");
  GtVoxelMap map;
  std::vector<std::string_view> tok;
  if (!reader.next(tok) || tok.size() != 2 || tok[0] != "resolution")
    reader.fail("missing resolution line", "'resolution <metres>' after the header");
  map.resolution_m = reader.number(tok, 1, "resolution");
  if (map.resolution_m <= 0) reader.fail("resolution must be > 0", "a positive voxel size in metres");
  while (reader.next(tok)) {
    reader.expect_tokens(tok, 4, "x y z class_id");
    const Eigen::Vector3d c(reader.coordinate_m(tok, 0, "x"), reader.coordinate_m(tok, 1, "y"),
                            reader.coordinate_m(tok, 2, "z"));
    const double id = reader.number(tok, 3, "class_id");
    if (id < 0 || id > std::numeric_limits<ClassId>::max() || id != std::floor(id))
      reader.fail(fmt::format("class_id {} is not a valid id", id), "an integer in 0..65535");
    map.centres_w.push_back(c.cast<float>());
    map.labels.push_back(static_cast<ClassId>(id));
  }
  return map;
}

}  // namespace s3m::io
