#include "sinew/core/file_io.h"

#include <sys/stat.h>

#include <gtest/gtest.h>

#include "support/test_support.h"

namespace sinew {
namespace {

TEST(FileIoTest, RefusesMissingFilesAndDirectoriesByName) {
  test::TempDir dir;
  Result<std::string> missing = readFile(dir / "nope.bvh");
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.message().find("nope.bvh: no such file"), std::string::npos);
  Result<std::string> folder = readFile(dir.path());
  ASSERT_FALSE(folder.ok());
  EXPECT_NE(folder.message().find("is a directory"), std::string::npos);
}

TEST(FileIoTest, WritesAndReplacesAtomically) {
  test::TempDir dir;
  const auto path = dir / "clip.bvh";
  ASSERT_TRUE(writeFileAtomically(path, "first").ok());
  ASSERT_TRUE(writeFileAtomically(path, "second").ok());
  EXPECT_EQ(readFile(path).value(), "second");
  // No temporary files left behind.
  int files = 0;
  for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator(dir.path())) ++files;
  EXPECT_EQ(files, 1);
}

TEST(FileIoTest, FailedSaveKeepsThePreviousFile) {
  test::TempDir dir;
  const auto locked = dir / "locked";
  std::filesystem::create_directory(locked);
  const auto path = locked / "clip.bvh";
  ASSERT_TRUE(writeFileAtomically(path, "precious").ok());
  // A read-only folder: the temporary cannot be created, so the save fails...
  ::chmod(locked.c_str(), 0555);
  const bool root = ::geteuid() == 0;  // root ignores permissions; the failure path differs
  Status status = writeFileAtomically(path, "replacement");
  ::chmod(locked.c_str(), 0755);
  if (!root) {
    ASSERT_FALSE(status.ok());
    EXPECT_NE(status.message().find("unchanged"), std::string::npos);
    EXPECT_EQ(readFile(path).value(), "precious");
  }
  // ...and a target that is a directory cannot be replaced, whoever we are.
  const auto folder_target = dir / "folder";
  std::filesystem::create_directories(folder_target / "inside");
  Status into_folder = writeFileAtomically(folder_target, "bytes");
  ASSERT_FALSE(into_folder.ok());
  EXPECT_TRUE(std::filesystem::is_directory(folder_target / "inside"));
}

}  // namespace
}  // namespace sinew
