#pragma once
// The one gate every reader passes before it opens a file. A path that is not a regular file is
// refused with its name and what it is, without opening it: opening a FIFO for reading blocks until
// a writer appears (forever, for a forgotten `mkfifo`), a device such as /dev/zero never ends, and
// a directory "opens" on some platforms and then reads as garbage.
#include <fstream>
#include <string>

namespace s3m {

// What makes `path` unusable as an input file ("file not found", "is a FIFO (named pipe), not a
// regular file", ...), or "" for an existing regular file (symbolic links are followed). Only
// stat()s the path.
std::string input_file_problem(const std::string& path);

// Throws ParseError(path, 0, input_file_problem(path), what) unless path is a regular file. For
// readers that hand the path to a library (cv::imread, readNetFromONNX, yaml-cpp).
void require_input_file(const std::string& path, const std::string& what);

// require_input_file(), then opens the file; ParseError "cannot open file for reading" otherwise.
std::ifstream open_input_file(const std::string& path, const std::string& what,
                              std::ios::openmode mode = std::ios::in);

}  // namespace s3m
