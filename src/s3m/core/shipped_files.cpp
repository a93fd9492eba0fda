#include "s3m/core/shipped_files.hpp"

#include <cstdlib>
#include <filesystem>

namespace s3m {
namespace fs = std::filesystem;

std::string shipped_file(const std::string& relative) {
  if (const char* env = std::getenv("S3M_DATA_DIR"); env && *env) return (fs::path(env) / relative).string();
  const fs::path in_source = fs::path(S3M_SOURCE_DIR) / relative;
  if (fs::exists(in_source)) return in_source.string();
  const fs::path installed = fs::path(S3M_INSTALL_DATA_DIR) / relative;
  if (fs::exists(installed)) return installed.string();
  return in_source.string();
}

}  // namespace s3m
