#include "s3m/io/output_folder.hpp"

#include <filesystem>
#include <system_error>

#include "s3m/core/error.hpp"

namespace fs = std::filesystem;

namespace s3m::io {

void require_folder_path(const std::string& path, const std::string& option) {
  std::error_code ec;
  if (fs::exists(path, ec) && !fs::is_directory(path, ec))
    throw Error(option + " '" + path + "' is a file, not a folder: give a folder to write into");
}

void create_output_folder(const std::string& path, const std::string& option) {
  require_folder_path(path, option);
  std::error_code ec;
  fs::create_directories(path, ec);  // filesystem_error is no s3m::Error: report it as one
  if (ec || !fs::is_directory(path))
    throw Error(option + ": cannot create the output directory '" + path +
                "': " + (ec ? ec.message() : "it is not a folder") + " (expected a writable folder)");
}

}  // namespace s3m::io
