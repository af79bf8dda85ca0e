#include "dlo/mrpt/tum_file.h"

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "dlo/mrpt/input_error.h"

namespace dlo {

void writeTumTrajectory(const std::string& path, const std::vector<double>& times,
                        const std::vector<Eigen::Isometry3d>& poses) {
  const std::string temp = path + ".tmp";
  {
    std::ofstream out(temp);
    if (!out) throw InputError("cannot create '" + temp + "' (is the folder writable?).");
    char line[256];
    for (size_t i = 0; i < poses.size() && i < times.size(); ++i) {
      const Eigen::Vector3d t = poses[i].translation();
      const Eigen::Quaterniond q(poses[i].rotation());
      // %.9f keeps nanoseconds of epoch times and sub-millimetre positions.
      std::snprintf(line, sizeof(line), "%.9f %.9f %.9f %.9f %.9f %.9f %.9f %.9f\n", times[i],
                    t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w());
      out << line;
    }
    if (!out) throw InputError("cannot write '" + temp + "' (disk full?).");
  }
  std::error_code ec;
  std::filesystem::rename(temp, path, ec);
  if (ec) throw InputError("cannot rename '" + temp + "' to '" + path + "': " + ec.message() + ".");
}

}  // namespace dlo
