#pragma once
// Output folders named on the command line, checked before any work: a bad --out must cost nothing.
#include <string>

namespace s3m::io {

// Refused (s3m::Error naming option and path) when path is an existing file: creating the folder
// would fail halfway through the work otherwise. Creates nothing.
void require_folder_path(const std::string& path, const std::string& option);
// The same check, then the folder and its parents are created; a folder that cannot be created is
// refused naming option, path and the reason.
void create_output_folder(const std::string& path, const std::string& option);

}  // namespace s3m::io
