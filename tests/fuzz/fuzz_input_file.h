// Helpers shared by the fuzz targets: the input as a file for readers that only take a path, and
// the check that an input error names what was read.
#pragma once

#include <sys/mman.h>
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace dlo::fuzz {

/// The fuzzer's input as a file that path-based readers (MRPT's gzip stream, libpcap) can open:
/// an anonymous in-memory file (memfd), rewritten for each input and opened through
/// /proc/self/fd, so nothing touches the disk and fuzzers running side by side do not collide.
class FuzzInputFile {
 public:
  FuzzInputFile() : fd_(memfd_create("dlo_fuzz_input", 0)) {
    if (fd_ < 0) {
      std::perror("memfd_create");
      std::abort();
    }
    path_ = "/proc/self/fd/" + std::to_string(fd_);
  }
  FuzzInputFile(const FuzzInputFile&) = delete;
  FuzzInputFile& operator=(const FuzzInputFile&) = delete;
  ~FuzzInputFile() { close(fd_); }

  /// Replaces the file's contents with `data`. \return the path to open.
  const std::string& write(const uint8_t* data, size_t size) {
    if (ftruncate(fd_, 0) != 0) std::abort();
    size_t done = 0;
    while (done < size) {
      const ssize_t n = pwrite(fd_, data + done, size - done, static_cast<off_t>(done));
      if (n <= 0) std::abort();
      done += static_cast<size_t>(n);
    }
    return path_;
  }

 private:
  int fd_;
  std::string path_;
};

/// The error contract (dlo/files/error.h): a message about a bad input is one line that names the
/// file. Aborts, so that libFuzzer reports the input, when `message` is not.
inline void requireNames(const std::string& message, const std::string& name) {
  const char* problem = message.find(name) == std::string::npos   ? "does not name the file"
                        : message.find('\n') != std::string::npos ? "is not one line"
                                                                  : nullptr;
  if (problem) {
    std::fprintf(stderr, "input error that %s '%s': %s\n", problem, name.c_str(), message.c_str());
    std::abort();
  }
}

}  // namespace dlo::fuzz
