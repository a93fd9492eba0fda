// Writes the semantic-map seeds of tests/fuzz/corpus/semantic_map/ (tiny .ot files; a few voxels
// keep the fuzzer fast). Built with the fuzz targets; run once by hand:
//   build/tests/fuzz/fuzz_make_map_seeds tests/fuzz/corpus/semantic_map
#include <iostream>

#include "s3m/mapping/map_io.hpp"
#include "s3m/mapping/semantic_octree.hpp"

using namespace s3m::mapping;

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: fuzz_make_map_seeds <output dir>\n";
    return 2;
  }
  const std::string dir = argv[1];
  SemanticOcTree empty(0.1);
  save_semantic_map(empty, dir + "/empty.ot");

  SemanticOcTree tree(0.05);
  LabelSet a, b;
  a.push(1, 0.7f), a.push(2, 0.2f);
  b.push(7, 0.9f);
  tree.updateNode(tree.coordToKey(0.05, 0.05, 0.05), 0.85f, true);
  tree.updateNode(tree.coordToKey(0.15, 0.05, 0.05), -0.4f, true);
  tree.updateNode(tree.coordToKey(-0.5, 0.3, 1.0), 0.85f, true);
  tree.integrateObservation(tree.coordToKey(0.05, 0.05, 0.05), a, Rgb{200, 10, 10});
  tree.integrateObservation(tree.coordToKey(-0.5, 0.3, 1.0), b, Rgb{0, 0, 255});
  tree.updateInnerOccupancy();
  save_semantic_map(tree, dir + "/three_voxels.ot");
  std::cout << "wrote " << dir << "/empty.ot and three_voxels.ot\n";
  return 0;
}
