// A temporary folder per test (no MRPT: any test may include it).
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <system_error>

namespace dlo::test {

/// A temporary folder, removed with this object. Set DLO_KEEP_TEST_OUTPUT=1 to keep it for
/// inspection (its path is printed).
class TempDir {
 public:
  /// Named after the running test.
  TempDir() {
    const auto* info = testing::UnitTest::GetInstance()->current_test_info();
    create(std::filesystem::path(testing::TempDir()) /
           ("dlo_" + std::string(info->test_suite_name()) + "_" + info->name()));
  }
  /// Named `name` (and the process id): for a folder made outside a test, e.g. a suite's set-up.
  explicit TempDir(const std::string& name) {
    create(std::filesystem::path(testing::TempDir()) /
           ("dlo_" + name + "_" + std::to_string(::getpid())));
  }
  ~TempDir() {
    if (std::getenv("DLO_KEEP_TEST_OUTPUT")) {
      std::printf("kept %s\n", dir_.c_str());
      return;
    }
    // A test may have made the folder read-only.
    std::error_code ec;
    std::filesystem::permissions(dir_, std::filesystem::perms::owner_all,
                                 std::filesystem::perm_options::add, ec);
    std::filesystem::remove_all(dir_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  const std::filesystem::path& dir() const { return dir_; }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }

 private:
  void create(const std::filesystem::path& dir) {
    dir_ = dir;
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }

  std::filesystem::path dir_;
};

}  // namespace dlo::test
