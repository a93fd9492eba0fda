#pragma once
// Files s3m ships besides its code: presets (config/), the segmentation models (models/), the
// bag-of-words vocabulary (vocab/) and the plot and viewer scripts (tools/). One lookup for all of
// them, so that a build used from its source tree, an installed copy (`cmake --install`, which puts
// these folders under <prefix>/share/s3m) and a moved copy find the same files.
#include <string>

namespace s3m {

// The file `relative` (e.g. "vocab/orb_k10_l5.bin") from the first of:
//   1. $S3M_DATA_DIR, when set and not empty: a folder holding copies of the folders above; used
//      as given, whether or not it has the file (an explicit choice is never second-guessed);
//   2. the source tree this library was built from, when the file is there;
//   3. <install prefix>/share/s3m, when the file is there (an installed library whose source tree
//      is gone).
// When neither 2 nor 3 has it, the source tree's path, so that a "not found" names where it was
// expected.
std::string shipped_file(const std::string& relative);

}  // namespace s3m
