#pragma once
// What an image file's first bytes say, checked before any decoder sees it (used by image_io).
#include <string>

namespace s3m::io {

// Throws ParseError(path, 0, ..., what) unless the file is a PNG or a JPEG whose header states a
// size with both sides in 1..16384 px, and, for a JPEG, unless its end-of-image marker follows the
// scan (a truncated JPEG decodes without an error, its missing rows grey). Why only these two: cv::imread picks its decoder from the
// file's bytes, not its name, and several decoders in Debian's OpenCV abort the process on
// malformed input (GDCM's DICOM reader fails an assert()) or allocate what the header claims
// before reading a pixel (BMP, TIFF, PNM: a 51-byte "BM" file asked for 2.2 GB). Both were found
// by fuzz_label_png. Every RGB-D dataset this project reads (TUM, 7-Scenes, SUN RGB-D, ADE20K,
// the simulator) stores PNG and JPEG.
void check_image_header(const std::string& path, const std::string& what);

}  // namespace s3m::io
