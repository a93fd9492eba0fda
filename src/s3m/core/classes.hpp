#pragma once
// The project's indoor class list: the ids that label images, segmenters (after mapping) and the
// semantic map all share. Id 0 is "unknown" (no label / not evaluated); the simulator, the oracle
// segmenter and the ADE20K mapping all produce ids from this list.
#include <cstdint>
#include <string>
#include <vector>

namespace s3m {

using ClassId = std::uint16_t;

struct ClassInfo {
  ClassId id = 0;
  std::string name;
  std::uint8_t r = 0, g = 0, b = 0;  // palette colour (sRGB)
};

class ClassList {
 public:
  ClassList() = default;
  explicit ClassList(std::vector<ClassInfo> classes);  // ids must be 0..n-1 in order

  std::size_t size() const { return classes_.size(); }
  const ClassInfo& at(ClassId id) const;  // throws s3m::Error for an unknown id
  const std::vector<ClassInfo>& all() const { return classes_; }
  // Id of a class by name, or -1 when absent.
  int find(const std::string& name) const;

 private:
  std::vector<ClassInfo> classes_;
};

// unknown, wall, floor, ceiling, door, window, table, chair, sofa, bed, cabinet, shelf, tv_monitor,
// plant, person, other (ids 0..15).
const ClassList& indoor_classes();

namespace cls {
inline constexpr ClassId kUnknown = 0, kWall = 1, kFloor = 2, kCeiling = 3, kDoor = 4, kWindow = 5,
                         kTable = 6, kChair = 7, kSofa = 8, kBed = 9, kCabinet = 10, kShelf = 11,
                         kTvMonitor = 12, kPlant = 13, kPerson = 14, kOther = 15;
inline constexpr int kCount = 16;
}  // namespace cls

// The one top-k limit: labels per pixel a segmenter may emit (model cards, the oracle) and labels a
// map voxel keeps (mapping::kMaxLabels, fusion.k). Checked where each is configured or loaded.
inline constexpr int kMaxTopK = 5;

// classes.txt format, one class per line: "<id> <name> <r> <g> <b>"; '#' starts a comment.
void write_class_list(const std::string& path, const ClassList& classes);
ClassList read_class_list(const std::string& path);  // ParseError with file/line on bad input

}  // namespace s3m
