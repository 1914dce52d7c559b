// The tests' main (test_main.cpp): each test writes into a temp folder of its own.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace {

using ::testing::EndsWith;

// Two tests that write the same file name: with one shared folder, running them at once raced.
void expect_own_empty_folder(const std::string& test_name) {
  const std::filesystem::path folder = ::testing::TempDir();
  EXPECT_THAT(::testing::TempDir(), EndsWith("/TestMain." + test_name + "/"));
  ASSERT_TRUE(std::filesystem::is_directory(folder));
  EXPECT_TRUE(std::filesystem::is_empty(folder));
  std::ofstream(folder / "same_name.txt") << test_name;
}

TEST(TestMain, EachTestHasATempFolderOfItsOwn) {
  expect_own_empty_folder("EachTestHasATempFolderOfItsOwn");
}

TEST(TestMain, AnotherTestHasAnotherFolder) {
  expect_own_empty_folder("AnotherTestHasAnotherFolder");
}

}  // namespace
