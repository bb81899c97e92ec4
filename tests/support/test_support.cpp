#include "support/test_support.h"

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace sinew::test {

std::filesystem::path sharedData() {
  if (const char* env = std::getenv("SINEW_SHARED_DATA"); env != nullptr && *env != '\0') {
    return env;
  }
  return SINEW_SHARED_DATA;
}

bool haveSharedData() {
  std::error_code ec;
  return std::filesystem::is_directory(sharedData() / "bvh", ec);
}

std::vector<std::filesystem::path> sharedFiles(const std::string& subfolder,
                                               const std::string& extension) {
  std::vector<std::filesystem::path> files;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(sharedData() / subfolder, ec)) {
    if (entry.path().extension() == extension) files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

std::filesystem::path sourceDir() { return SINEW_SOURCE_DIR; }

TempDir::TempDir() {
  static std::atomic<int> counter{0};
  path_ = std::filesystem::temp_directory_path() /
          ("sinew-test-" + std::to_string(::getpid()) + "-" + std::to_string(counter++));
  std::filesystem::remove_all(path_);
  std::filesystem::create_directories(path_);
}

TempDir::~TempDir() {
  std::error_code ec;
  std::filesystem::remove_all(path_, ec);
}

std::string readText(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

void writeText(const std::filesystem::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
}

std::string quote(const std::filesystem::path& path) {
  std::string quoted = "'";
  for (char c : path.string()) quoted += (c == '\'') ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

CommandResult runCommand(const std::string& command_line) {
  TempDir dir;
  const std::filesystem::path out = dir / "out.txt";
  const std::filesystem::path err = dir / "err.txt";
  const std::string full = command_line + " >" + quote(out) + " 2>" + quote(err) + " </dev/null";
  const int status = std::system(full.c_str());
  CommandResult result;
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  result.out = readText(out);
  result.err = readText(err);
  return result;
}

CommandResult runSinew(const std::string& arguments) {
  return runCommand(quote(SINEW_BINARY) + " " + arguments);
}

}  // namespace sinew::test
