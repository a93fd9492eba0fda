#include "s3m/core/atomic_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>

#include <fmt/format.h>

#include "s3m/core/error.hpp"

namespace s3m {
namespace {

std::string temp_name_for(const std::filesystem::path& target) {
  static std::atomic<unsigned> counter{0};
  // fmt rather than string +: GCC 12 emits a false -Wrestrict on "." + std::string.
  return (target.parent_path() / fmt::format(".{}.tmp{}_{}", target.filename().string(), ::getpid(), counter++))
      .string();
}

// fsync so that a power cut after rename cannot leave an empty file behind.
void fsync_file(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDONLY);
  if (fd < 0) return;
  ::fsync(fd);
  ::close(fd);
}

}  // namespace

void write_file_atomic(const std::string& path, const std::function<void(std::ostream&)>& writer) {
  namespace fs = std::filesystem;
  const fs::path target(path);
  const fs::path dir = target.parent_path().empty() ? fs::path(".") : target.parent_path();
  if (!fs::is_directory(dir)) throw Error("cannot write '" + path + "': directory '" + dir.string() + "' does not exist");
  const std::string tmp = temp_name_for(target.parent_path().empty() ? fs::path(".") / target : target);
  try {
    {
      std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
      if (!out) throw Error("cannot write '" + path + "': " + std::strerror(errno));
      writer(out);
      out.flush();
      if (!out) throw Error("cannot write '" + path + "': write failed (disk full?)");
    }
    fsync_file(tmp);
    std::error_code ec;
    fs::rename(tmp, target, ec);
    if (ec) throw Error("cannot write '" + path + "': rename failed: " + ec.message());
  } catch (const Error&) {
    std::error_code ignore;
    fs::remove(tmp, ignore);
    throw;
  } catch (const std::exception& e) {
    std::error_code ignore;
    fs::remove(tmp, ignore);
    throw Error("cannot write '" + path + "': " + e.what());
  }
}

void write_text_atomic(const std::string& path, const std::string& content) {
  write_file_atomic(path, [&](std::ostream& os) { os << content; });
}

void write_bytes_atomic(const std::string& path, const std::vector<unsigned char>& bytes) {
  write_file_atomic(path, [&](std::ostream& os) {
    os.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  });
}

}  // namespace s3m
