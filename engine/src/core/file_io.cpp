#include "sinew/core/file_io.h"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <system_error>

namespace sinew {

Result<std::string> readFile(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) {
    return Status::error(path.string() + ": no such file");
  }
  if (std::filesystem::is_directory(path, ec)) {
    return Status::error(path.string() + ": is a directory, expected a file");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) return Status::error(path.string() + ": cannot open: " + std::strerror(errno));
  std::ostringstream buffer;
  buffer << in.rdbuf();
  if (in.bad()) return Status::error(path.string() + ": read failed");
  return std::move(buffer).str();
}

Status writeFileAtomically(const std::filesystem::path& path, std::string_view bytes) {
  const std::filesystem::path temp =
      path.string() + ".tmp-" + std::to_string(static_cast<long>(::getpid()));
  std::FILE* file = std::fopen(temp.c_str(), "wb");
  if (file == nullptr) {
    return Status::error(path.string() + ": cannot write: " + std::strerror(errno));
  }
  const bool written = std::fwrite(bytes.data(), 1, bytes.size(), file) == bytes.size();
  const bool flushed = std::fflush(file) == 0 && ::fsync(::fileno(file)) == 0;
  const int write_errno = errno;
  const bool closed = std::fclose(file) == 0;
  if (!written || !flushed || !closed) {
    std::remove(temp.c_str());
    return Status::error(path.string() + ": write failed: " + std::strerror(write_errno) +
                         "; the previous file, if any, is unchanged");
  }
  std::error_code ec;
  std::filesystem::rename(temp, path, ec);
  if (ec) {
    std::remove(temp.c_str());
    return Status::error(path.string() + ": cannot replace: " + ec.message() +
                         "; the previous file, if any, is unchanged");
  }
  return {};
}

}  // namespace sinew
