// Shared helpers for the tests: the real data in ../shared/data, temporary folders, running the
// sinew binary.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace sinew::test {

// ../shared/data beside the checkout (set at configure time; SINEW_SHARED_DATA env overrides).
std::filesystem::path sharedData();
bool haveSharedData();
std::vector<std::filesystem::path> sharedFiles(const std::string& subfolder,
                                               const std::string& extension);
std::filesystem::path sourceDir();  // the project's source tree (assets/, tools/)

// Skips the current test with a message naming where the data was looked for.
#define SINEW_REQUIRE_SHARED_DATA()                                                        \
  do {                                                                                     \
    if (!::sinew::test::haveSharedData())                                                  \
      GTEST_SKIP() << "real test data not found at " << ::sinew::test::sharedData()        \
                   << " (the ../shared folder beside the checkout); skipping";            \
  } while (false)

// A fresh folder under the system temp directory, removed with its contents on destruction.
class TempDir {
 public:
  TempDir();
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

 private:
  std::filesystem::path path_;
};

struct CommandResult {
  int exit_code = -1;
  std::string out;  // standard output
  std::string err;  // standard error
};

// Runs a shell command line, capturing both streams.
CommandResult runCommand(const std::string& command_line);
// Runs the built sinew binary with the given (already quoted) arguments.
CommandResult runSinew(const std::string& arguments);
std::string quote(const std::filesystem::path& path);

std::string readText(const std::filesystem::path& path);
void writeText(const std::filesystem::path& path, const std::string& text);

}  // namespace sinew::test
