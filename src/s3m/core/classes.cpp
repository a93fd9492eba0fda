#include "s3m/core/classes.hpp"

#include <fstream>
#include <sstream>

#include "s3m/core/atomic_file.hpp"
#include "s3m/core/error.hpp"
#include "s3m/core/input_file.hpp"

namespace s3m {

ClassList::ClassList(std::vector<ClassInfo> classes) : classes_(std::move(classes)) {
  for (std::size_t i = 0; i < classes_.size(); ++i)
    require(classes_[i].id == i, "class list: ids must run 0..n-1 in order (class '" + classes_[i].name +
                                     "' has id " + std::to_string(classes_[i].id) + " at position " +
                                     std::to_string(i) + ")");
}

const ClassInfo& ClassList::at(ClassId id) const {
  require(id < classes_.size(), "class id " + std::to_string(id) + " is outside the class list (size " +
                                    std::to_string(classes_.size()) + ")");
  return classes_[id];
}

int ClassList::find(const std::string& name) const {
  for (const auto& c : classes_)
    if (c.name == name) return c.id;
  return -1;
}

const ClassList& indoor_classes() {
  // Colours loosely follow the ADE20K/SUN RGB-D palettes so maps look familiar, except where those
  // are near-identical (table/shelf, bed/cabinet, wall/ceiling): every pair differs by >= 60 in RGB.
  static const ClassList list({{0, "unknown", 0, 0, 0},
                               {1, "wall", 120, 120, 120},
                               {2, "floor", 80, 50, 50},
                               {3, "ceiling", 180, 180, 120},
                               {4, "door", 8, 255, 51},
                               {5, "window", 230, 230, 230},
                               {6, "table", 255, 6, 82},
                               {7, "chair", 204, 70, 3},
                               {8, "sofa", 11, 102, 255},
                               {9, "bed", 204, 5, 255},
                               {10, "cabinet", 0, 120, 120},
                               {11, "shelf", 140, 90, 220},
                               {12, "tv_monitor", 0, 255, 194},
                               {13, "plant", 4, 200, 3},
                               {14, "person", 150, 5, 61},
                               {15, "other", 255, 184, 6}});
  return list;
}

void write_class_list(const std::string& path, const ClassList& classes) {
  write_file_atomic(path, [&](std::ostream& out) {
    out << "# s3m class list: id name r g b\n";
    for (const auto& c : classes.all())
      out << c.id << ' ' << c.name << ' ' << int(c.r) << ' ' << int(c.g) << ' ' << int(c.b) << '\n';
  });
}

ClassList read_class_list(const std::string& path) {
  std::ifstream in = open_input_file(path, "a readable classes.txt");
  std::vector<ClassInfo> classes;
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    const auto hash = line.find('#');
    if (hash != std::string::npos) line.resize(hash);
    std::istringstream ss(line);
    long id;
    std::string name;
    int r, g, b;
    if (!(ss >> id)) continue;  // blank line
    if (!(ss >> name >> r >> g >> b) || r < 0 || r > 255 || g < 0 || g > 255 || b < 0 || b > 255)
      throw ParseError(path, line_no, "malformed class line", "'<id> <name> <r> <g> <b>' with colours 0..255");
    if (id != static_cast<long>(classes.size()))
      throw ParseError(path, line_no, "class id " + std::to_string(id) + " out of order",
                       "id " + std::to_string(classes.size()));
    classes.push_back({static_cast<ClassId>(id), name, static_cast<std::uint8_t>(r),
                       static_cast<std::uint8_t>(g), static_cast<std::uint8_t>(b)});
  }
  if (classes.empty()) throw ParseError(path, 0, "class list is empty", "at least one class");
  return ClassList(std::move(classes));
}

}  // namespace s3m
