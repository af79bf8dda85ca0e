#include "dlo/slam/process_memory.h"

#include <sys/resource.h>

#include <fstream>
#include <sstream>
#include <string>

namespace dlo {

namespace {

/// The value of a "Key:   1234 kB" line of /proc/self/status, megabytes; -1 if absent.
double statusFieldMb(const std::string& key) {
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind(key + ":", 0) != 0) continue;
    std::istringstream fields(line.substr(key.size() + 1));
    double kib = 0.0;
    if (fields >> kib) return kib / 1024.0;
  }
  return -1.0;
}

}  // namespace

double residentMemoryMb() {
  const double mb = statusFieldMb("VmRSS");
  return mb < 0.0 ? 0.0 : mb;
}

double peakResidentMemoryMb() {
  const double mb = statusFieldMb("VmHWM");
  if (mb >= 0.0) return mb;
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;  // KiB on Linux
}

bool resetPeakMemory() {
  std::ofstream out("/proc/self/clear_refs");
  out << "5";
  out.flush();
  return static_cast<bool>(out);
}

}  // namespace dlo
