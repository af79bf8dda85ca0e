/// \file export_folder.h
/// \brief A fresh temporary folder, removed when it goes out of scope.
#pragma once

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

namespace dlo::test {

/// Set DLO_KEEP_TEST_OUTPUT=1 to keep the folders for inspection (their path is printed).
class ExportFolder {
 public:
  explicit ExportFolder(const std::string& name)
      : path_(std::filesystem::temp_directory_path() /
              ("dlo_export_" + name + "_" + std::to_string(::getpid()))) {
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~ExportFolder() {
    std::error_code ec;
    if (std::getenv("DLO_KEEP_TEST_OUTPUT")) {
      std::printf("kept %s\n", path_.c_str());
      return;
    }
    std::filesystem::permissions(path_, std::filesystem::perms::owner_all,
                                 std::filesystem::perm_options::add, ec);
    std::filesystem::remove_all(path_, ec);
  }
  ExportFolder(const ExportFolder&) = delete;
  ExportFolder& operator=(const ExportFolder&) = delete;

  const std::filesystem::path& path() const { return path_; }
  std::string file(const std::string& name) const { return (path_ / name).string(); }

 private:
  std::filesystem::path path_;
};

}  // namespace dlo::test
