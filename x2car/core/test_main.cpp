// The test binaries' main: GoogleTest's, with a temp folder of each test's own.
//
// ctest runs the tests of a binary in parallel, one process each, and ::testing::TempDir() (the
// build folder's test_tmp/, TEST_TMPDIR) was one folder for all of them: two tests that wrote a
// file of the same name there raced, and one read the other's half-written file (a radar CSV test
// failed so, now and then, under `make test`). Here each test's TempDir() is
// <TEST_TMPDIR>/<suite>.<test>/, emptied when the test starts. It stays after the test: a failed
// test's files are there for a look, and a drive one test simulates once for the tests after it
// (run in one process, as the binary alone runs them) is still there for them.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <utility>

namespace {

class TempFolderPerTest : public ::testing::EmptyTestEventListener {
 public:
  explicit TempFolderPerTest(std::filesystem::path shared) : shared_(std::move(shared)) {}

  void OnTestStart(const ::testing::TestInfo& test) override {
    // Parameterised tests' names hold slashes ("Beams/OdometryDrift", "Urban/128").
    std::string name = std::string(test.test_suite_name()) + "." + test.name();
    std::replace(name.begin(), name.end(), '/', '_');
    const std::filesystem::path folder = shared_ / name;
    std::filesystem::remove_all(folder);
    std::filesystem::create_directories(folder);
    set_temp_dir(folder);
  }

  void OnTestEnd(const ::testing::TestInfo& /*test*/) override { set_temp_dir(shared_); }

 private:
  static void set_temp_dir(const std::filesystem::path& folder) {
    // TempDir() reads TEST_TMPDIR on each call; its trailing slash is what callers append to.
    ::setenv("TEST_TMPDIR", (folder.string() + "/").c_str(), 1);
  }

  std::filesystem::path shared_;
};

}  // namespace

int main(int argc, char** argv) {
  ::testing::InitGoogleMock(&argc, argv);
  ::testing::UnitTest::GetInstance()->listeners().Append(
      new TempFolderPerTest(::testing::TempDir()));  // GoogleTest owns its listeners
  return RUN_ALL_TESTS();
}
